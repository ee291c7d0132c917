"""Checks of a run's time step before the solve, against the stability limits of the solver table
(:data:`~.solvers.METHODS`): the explicit step on a flexible track (:func:`check_explicit_step`)."""
from __future__ import annotations

import math

from ..track.flexible_parameters import TrackFileError
from ..track.flexible_contact import CONTACT_STIFFNESS_N_M, contact_mode_Hz
from .solvers import METHODS, stable_step_s

__all__ = ["flexible_track_limit", "check_explicit_step"]


def flexible_track_limit(solver: str) -> float | None:
    """The largest ω h at which ``solver`` carries the nearly undamped oscillations of a flexible track (the
    imaginary-axis limit of :data:`~.solvers.METHODS`; None for an implicit solver); a
    :class:`~exudyn_wheelrail.track.flexible_parameters.TrackFileError` naming ``run.solver`` for a solver that
    amplifies them at any step."""
    limit = METHODS[solver].imaginary_axis_limit
    if limit == 0.0:
        raise TrackFileError(f"run.solver = {solver!r}: amplifies the undamped track modes at any step; use 'rk44' "
                             "(or 'newmark') with a flexible track")
    return limit


def check_explicit_step(modes, solver: str, dt_s: float, s_from_m: float | None = None,
                        s_to_m: float | None = None) -> None:
    """Raise :class:`~exudyn_wheelrail.track.flexible_parameters.TrackFileError` (naming ``run.dt_s`` and the largest
    stable step) if the explicit ``solver`` at ``dt_s`` cannot carry the wheel on the rail's kept modal mass over
    ``[s_from_m, s_to_m]`` (:func:`~exudyn_wheelrail.track.flexible_contact.contact_mode_Hz`; the limits of the solver
    table :data:`~.solvers.METHODS`); nothing for an implicit solver.  The scenario build and the runner call it before
    the solve, over the track the wheelsets will cross; the run monitor checks the same stiffness on the rail's modal
    mass where the wheelsets are during the run."""
    limit = flexible_track_limit(solver)
    if limit is None:
        return
    f_c = contact_mode_Hz(modes, s_from_m, s_to_m)
    f_lim = limit / (2.0 * math.pi * dt_s)
    if f_c >= f_lim:
        raise TrackFileError(f"run.dt_s = {dt_s:g} s: the wheel on the flexible rail (contact stiffness "
                             f"{CONTACT_STIFFNESS_N_M:.0e} N/m, in series with the residual flexibility, on the "
                             f"rail's kept modal mass) vibrates at up to {f_c:.4g} Hz, beyond explicit {solver}'s "
                             f"stability ({f_lim:.4g} Hz at this step): use run.dt_s <= "
                             f"{stable_step_s(solver, 2.0 * math.pi * f_c):.3g} s")
