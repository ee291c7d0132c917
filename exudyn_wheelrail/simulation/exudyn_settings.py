"""Exudyn's settings of a solve: :func:`simulation_settings` (quiet, file-free) and :func:`solver_settings` (the
settings and ``exu.DynamicSolverType`` of a solver of the table :data:`~.solvers.METHODS`)."""
from __future__ import annotations

import exudyn as exu

from .solvers import GENERALIZED_ALPHA_SPECTRAL_RADIUS, METHODS, NEWMARK_BETA, NEWMARK_GAMMA

__all__ = ["simulation_settings", "solver_settings", "run_solver_settings"]


def simulation_settings(end_time_s: float, dt_s: float, newton_tolerance: float = 1e-6,
                        spectral_radius: float = 1.0) -> exu.SimulationSettings:
    """Quiet, file-free Exudyn settings for ``mbs.SolveDynamic`` (and ``mbs.SolveStatic``: Newton to a residual
    of ``newton_tolerance`` N, relative 1e-10).

    Implicit (default solver, generalized-α): ``spectral_radius = 1`` is the trapezoidal rule (Newmark
    β = 1/4, γ = 1/2, the paper's scheme); Newton tolerances ``newton_tolerance``.  Explicit
    (``solverType=exu.DynamicSolverType.RK44``): Lie-group integration is on.  No solution file; sensors are
    stored internally (``storeInternal=True``) and not written.

    Step size (measured, Exudyn 1.13.6): an *undamped* wheelset spinning at 151 rad/s (250 km/h) on the
    1e9 N/m rail springs (ω h ≈ 1.2 at h = 1 ms) grows unstable after about 3 s with generalized-α at h = 1 ms for
    ρ∞ = 1 … 0.7 (Lie-group or Euler-parameter nodes alike); h = 0.5 ms, ρ∞ = 0.6 or RK44 at 0.5 ms are stable,
    and so is the damped vehicle (default :class:`RailSprings` damping) at 1 ms."""
    s = exu.SimulationSettings()
    s.solution.file.write = False
    s.solution.sensors.writeHeader = False
    s.solution.sensors.writePeriod = float(dt_s)
    s.timeIntegration.verboseMode = 0
    s.timeIntegration.endTime = float(end_time_s)
    s.timeIntegration.numberOfSteps = max(1, int(round(end_time_s / dt_s)))
    s.timeIntegration.newton.relativeTolerance = newton_tolerance
    s.timeIntegration.newton.absoluteTolerance = newton_tolerance
    s.timeIntegration.generalizedAlpha.spectralRadius = spectral_radius
    s.timeIntegration.explicit.useLieGroupIntegration = True
    s.staticSolver.verboseMode = 0
    s.staticSolver.newton.relativeTolerance = 1e-10
    s.staticSolver.newton.absoluteTolerance = newton_tolerance
    s.show.computationTime = False
    return s


def solver_settings(solver: str, dt_s: float, steps: int, newton_tolerance: float = 1e-6,
                    newmark_beta: float = NEWMARK_BETA, newmark_gamma: float = NEWMARK_GAMMA,
                    spectral_radius: float = GENERALIZED_ALPHA_SPECTRAL_RADIUS):
    """Settings and solver type for ``mbs.SolveDynamic``, fixed step ``dt_s`` [s] for ``steps`` steps:

    * ``"newmark"`` — generalized-α as Newmark (β, γ; the paper's β = 1/4, γ = 1/2 is the trapezoidal rule),
      index-2 constraints, modified Newton (below);
    * ``"generalized_alpha"`` — Exudyn's generalized-α (Chung–Hulbert) with ``spectral_radius`` ρ∞ (default 0.8),
      modified Newton as for ``"newmark"``; index-3 constraints (Exudyn 1.13.6 accepts index 2 only with
      ``useNewmark``; only ``longitudinal="rigid"`` adds a constraint to the vehicle in dynamics);
    * ``"explicit_midpoint"`` (2nd order, 2 stages), ``"rk33"`` (3rd order), ``"rk44"`` (classical 4th order),
      ``"rk67"`` (6th order, 7 stages) — Exudyn's explicit Runge–Kutta solvers, Lie-group integration, without the
      extra end-of-step right-hand side (``computeEndOfStepAccelerations = False``).

    Exudyn's error-controlled explicit solvers (DOPRI5, ODE23) are not offered: they adapt the step even with
    ``automaticStepSize = False`` and stop after the first step with ``adaptiveStep = False`` (Exudyn 1.13.6).

    Newton (implicit solvers): Exudyn's modified Newton, the Jacobian kept across steps and updated only when
    Newton slows down (more than ``maxModifiedNewtonIterations`` = 8 iterations, or a contraction worse than 0.5
    from the third).  The wheel–rail connector's Jacobian costs one contact evaluation
    (:mod:`~exudyn_wheelrail.multibody.contact_jacobian`).  Measured on the RTRI case (20 m, 250 km/h, tolerance
    1e-4, Newmark; ``benchmarks/bench_implicit.py``, docs/performance.md): with the Jacobian kept, 3.0 / 4.8 / 6.9
    iterations per step at 0.5 / 1 / 2 ms; updated every step (``modifiedNewtonJacUpdatePerStep``) 1.9 / 2.0 / 3.3
    — the first iteration reaches ~1e-3 of the initial residual, the second ~1e-7, as with full Newton (1.9
    iterations, one Jacobian each) — but each update also costs Exudyn's Jacobian of the other items and its
    factorization (~0.2 ms, more than the connector's ~0.15 ms): CPU time per run +70–85 % at 0.5 ms, +30–40 % at
    1 ms, −1 … −4 % at 2 ms, so the Jacobian is kept.  Returns ``(settings, exu.DynamicSolverType)``."""
    if solver not in METHODS:
        raise ValueError(f"solver={solver!r}: expected one of {', '.join(repr(k) for k in METHODS)}")
    s = simulation_settings(steps * dt_s, dt_s, newton_tolerance=newton_tolerance)
    s.timeIntegration.numberOfSteps = int(steps)
    solver_type = getattr(exu.DynamicSolverType, METHODS[solver].exudyn_type)
    if not METHODS[solver].implicit:
        s.timeIntegration.explicit.computeEndOfStepAccelerations = False
        # the mass-matrix solve of every stage by Eigen's sparse LU: Exudyn's dense default costs O(n³) in the
        # bodies (measured, 8-car train of 56 bodies on rail springs: 0.28-0.31 s -> 0.16-0.19 s per 300 RK44
        # steps; one vehicle: the same within the scatter; results equal to rounding)
        s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
        return s, solver_type
    ga = s.timeIntegration.generalizedAlpha
    if solver == "newmark":
        ga.useNewmark = True
        ga.newmarkBeta = newmark_beta
        ga.newmarkGamma = newmark_gamma
        ga.useIndex2Constraints = True
    else:
        if not (0.0 <= spectral_radius <= 1.0):
            raise ValueError(f"spectral_radius = {spectral_radius!r}: expected a value in [0, 1]")
        ga.useNewmark = False
        ga.spectralRadius = float(spectral_radius)
        ga.useIndex2Constraints = False
    s.timeIntegration.newton.useModifiedNewton = True
    return s, solver_type


def run_solver_settings(run):
    """``(exu.SimulationSettings, exu.DynamicSolverType)`` of a :class:`~.settings.RunSettings`."""
    return solver_settings(run.solver, float(run.dt_s), run.steps, float(run.newton_tolerance), NEWMARK_BETA,
                           NEWMARK_GAMMA)
