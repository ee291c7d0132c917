r"""The time integrators: one table (:data:`METHODS`) from a solver's name to Exudyn's fixed-step solver, whether it
is implicit, and its stability limits; every check of a time step against a stability limit reads them here.

>>> METHODS["rk44"].exudyn_type, METHODS["rk44"].implicit
('RK44', False)
>>> round(METHODS["rk44"].imaginary_axis_limit, 4)           # 2 sqrt(2): an undamped mode needs omega h <= this
2.8284

The solvers (their Exudyn settings: :func:`exudyn_wheelrail.simulation.exudyn_settings.solver_settings`):

* ``"newmark"`` — the trapezoidal rule as Newmark β = 1/4, γ = 1/2 (:data:`NEWMARK_BETA`, :data:`NEWMARK_GAMMA`,
  the scheme of Montenegro et al. 2015), index-2 constraints, modified Newton;
* ``"generalized_alpha"`` — Chung–Hulbert generalized-α, ρ∞ :data:`GENERALIZED_ALPHA_SPECTRAL_RADIUS`, modified
  Newton;
* ``"explicit_midpoint"``, ``"rk33"``, ``"rk44"``, ``"rk67"`` — Exudyn's explicit Runge–Kutta solvers (2, 3, 4 and
  7 stages), Lie-group integration.

Stability limits of the explicit solvers, for ``y' = λ y`` with one step ``h``:

* ``imaginary_axis_limit`` — the largest ``ω h`` at which an undamped oscillation (λ = iω) does not grow: the
  classical RK4 2√2, RK3 √3 (the boundary of their stability polynomials on the imaginary axis, e.g. Hairer &
  Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., Springer 1996, Sect. IV.2); the explicit midpoint
  rule amplifies every undamped oscillation, ``|1 + iy - y²/2|² = 1 + y⁴/4 > 1``: 0.  Exudyn's RK67 was measured
  (Exudyn 1.13.6, one undamped oscillator, 1000 steps): it grows by 2.3e-6, 5.3e-4 and 7.7e-2 per step at
  ω h = 0.5, 1 and 2 — it amplifies every undamped oscillation too: 0;
* ``real_axis_limit`` — the largest ``σ h`` at which a decay (λ = -σ, e.g. the creep forces' damping of a wheelset)
  stays stable: ``|R(-x)| = 1`` of the stability polynomial ``R``: 2 (explicit midpoint), 2.5127 (RK3), 2.7853
  (RK4; ``R(-x) = 1 - x + x²/2 - x³/6 + x⁴/24 = 1`` there); Exudyn's RK67 measured the same way: 2.8656.
  ``tests/test_solvers.py`` measures every value on Exudyn's solvers.

The implicit solvers are A-stable (no limit): their step is chosen by accuracy (the run monitor's resolution bound,
:mod:`~exudyn_wheelrail.simulation.runner`).

Step sizes: :data:`DEFAULT_STEP_S` (the paper's 1 ms) is the one default of every run that names no step.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Method", "METHODS", "SOLVERS", "IMPLICIT_SOLVERS", "NEWMARK_BETA", "NEWMARK_GAMMA",
           "GENERALIZED_ALPHA_SPECTRAL_RADIUS", "DEFAULT_STEP_S", "RESOLUTION_LIMIT", "RK44", "solver_description", "stable_step_s",
           "undamped_step_problem"]


@dataclass(frozen=True)
class Method:
    """One time integrator: its name here, the name of its ``exudyn.DynamicSolverType``, implicit or explicit, and
    its stability limits (module docstring; ``None`` for an implicit solver: no limit)."""

    name: str
    exudyn_type: str
    implicit: bool
    imaginary_axis_limit: float | None
    real_axis_limit: float | None


#: solver name -> :class:`Method` (all fixed step size), in the order they are listed
METHODS = {m.name: m for m in (
    Method("newmark", "GeneralizedAlpha", True, None, None),
    Method("generalized_alpha", "GeneralizedAlpha", True, None, None),
    Method("explicit_midpoint", "ExplicitMidpoint", False, 0.0, 2.0),
    Method("rk33", "RK33", False, math.sqrt(3.0), 2.512745326618329),
    Method("rk44", "RK44", False, 2.0 * math.sqrt(2.0), 2.785293563405282),
    Method("rk67", "RK67", False, 0.0, 2.8656),
)}
#: the solver names, in the order they are listed
SOLVERS = tuple(METHODS)
#: the implicit ones (Newton iterations: the contact's Jacobian user function is used)
IMPLICIT_SOLVERS = tuple(k for k, m in METHODS.items() if m.implicit)
#: the classical RK4, the explicit solver of the presets
RK44 = METHODS["rk44"]
#: the trapezoidal rule as Newmark (published for the RTRI case: no numerical dissipation)
NEWMARK_BETA = 0.25
NEWMARK_GAMMA = 0.5
#: ρ∞ of ``"generalized_alpha"`` (numerical damping of the highest frequencies; 1 = none)
GENERALIZED_ALPHA_SPECTRAL_RADIUS = 0.8
#: the time step of a run that names none [s]: the paper's 1 ms
DEFAULT_STEP_S = 1e-3
#: the **resolution bound**: the largest ω h (ω the stiffest wheel–rail contact frequency) at which a step of any
#: solver integrates a lift-off or a flange impact as the contact's dynamics — RK44's imaginary-axis limit, at which
#: the trapezoidal rule has about 3.3 steps per period (its discrete frequency ``2 atan(ω h/2)/h`` 32 % low)
RESOLUTION_LIMIT = RK44.imaginary_axis_limit


def _method(solver: str) -> Method:
    if solver not in METHODS:
        raise ValueError(f"solver={solver!r}: expected one of {', '.join(repr(k) for k in METHODS)}")
    return METHODS[solver]


def solver_description(solver: str, newton_tolerance: float = 1e-6, newmark_beta: float = NEWMARK_BETA,
                       newmark_gamma: float = NEWMARK_GAMMA,
                       spectral_radius: float = GENERALIZED_ALPHA_SPECTRAL_RADIUS) -> str:
    """One line describing the Exudyn integrator that
    :func:`~exudyn_wheelrail.simulation.exudyn_settings.solver_settings` sets up for ``solver``."""
    m = _method(solver)
    if solver == "newmark":
        return ("GeneralizedAlpha, useNewmark, beta %.3g, gamma %.3g, index-2, modified Newton, tolerance %.1e"
                % (newmark_beta, newmark_gamma, newton_tolerance))
    if solver == "generalized_alpha":
        return ("GeneralizedAlpha, spectral radius %.3g, index-3, modified Newton, tolerance %.1e"
                % (spectral_radius, newton_tolerance))
    return f"{m.exudyn_type} (explicit, Lie group), no end-of-step accelerations"


def stable_step_s(solver: str, omega_rad_s: float) -> float:
    """The largest step [s] at which ``solver`` keeps an undamped oscillation of ``omega_rad_s`` from growing:
    ``imaginary_axis_limit / ω`` (``inf`` for an implicit solver or ω = 0; 0 for a solver that amplifies every
    undamped oscillation)."""
    limit = _method(solver).imaginary_axis_limit
    if limit is None or omega_rad_s <= 0.0:
        return math.inf
    return limit / omega_rad_s


def undamped_step_problem(solver: str, dt_s: float, omega_rad_s: float, what: str,
                          remedy: str = "take a smaller step or an implicit solver") -> str | None:
    """Why the explicit ``solver`` at ``dt_s`` cannot carry an undamped oscillation of ``omega_rad_s`` (``what``
    names it, e.g. "the flexible car body's highest kept mode (61.2 Hz)"; ``remedy`` ends the message of a step too
    large), or ``None`` (implicit solver, or the step within the limit)."""
    m = _method(solver)
    if m.imaginary_axis_limit is None or omega_rad_s <= 0.0:
        return None
    if m.imaginary_axis_limit == 0.0:
        return (f"{solver} amplifies every undamped oscillation at any step ({what}); use 'rk44', 'rk33' or an "
                "implicit solver")
    if omega_rad_s * dt_s <= m.imaginary_axis_limit:
        return None
    return (f"{dt_s:g} s is beyond the stability limit of {solver} for {what}: dt must be <= "
            f"{stable_step_s(solver, omega_rad_s):.3g} s (ω dt <= {m.imaginary_axis_limit:.3g}); {remedy}")
