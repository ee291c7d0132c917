r"""The scenario's ``[layout]`` table: the track's horizontal alignment and cant — straight track, a clothoid
transition with a linear cant ramp, a circular curve (:meth:`~exudyn_wheelrail.track.layout.TrackLayout.curve_entry`,
the curve of the ``curving`` command, :mod:`.curving`) — and what it asks of the run settings.  The schema is
documented in :mod:`exudyn_wheelrail.scenarios.scenario`; :mod:`.spec` calls these functions with its checker (the
helpers that raise :class:`~.spec.ScenarioError` naming the source and the dotted key).
"""
from __future__ import annotations

import warnings

from ..conventions import CURVE_DIRECTION_SIGN
from ..simulation.settings import RunSettings
from ..simulation.solvers import METHODS
from ..validation import InputWarning
from .curve_setup import CurvingInputError, check_curve, creep_limited_step_s, creep_step_limit_s
from .defaults import LEAD_IN_M, default_transition_m

__all__ = ["LAYOUT_KEYS", "CURVE_DIRECTIONS", "normalise_layout", "layout_combination_error", "layout_run_settings",
           "warn_creep_step"]

#: the keys of ``[layout]``: required, optional
LAYOUT_KEYS = (("radius_m", "cant_m"), ("transition_m", "direction", "start_m"))
#: the directions of a curve, as the layout names them
CURVE_DIRECTIONS = tuple(CURVE_DIRECTION_SIGN)


def normalise_layout(c, table, vehicle_start_m: float, vehicle) -> dict:
    """The normal form of ``[layout]`` (``c``: the spec's checker; ``vehicle_start_m``: ``vehicle.start_s_m``;
    ``vehicle``: its data, for the smallest radius it can follow; the curve's plausibility:
    :func:`~.curve_setup.check_curve`)."""
    required, optional = LAYOUT_KEYS
    c.table(table, "layout", required=required, optional=optional)
    R = c.number(table["radius_m"], "layout.radius_m", lo=0.0)
    h = c.number(table["cant_m"], "layout.cant_m", lo=0.0, lo_open=False)
    lt = (c.number(table["transition_m"], "layout.transition_m", lo=0.0, lo_open=False) if "transition_m" in table
          else None)
    try:
        check_curve(R, h, lt, vehicle)
    except CurvingInputError as exc:
        raise c.error(f"layout.{exc.option}", exc.problem) from None
    if lt is None:
        lt = float(default_transition_m(h))
    start = c.number(table.get("start_m", LEAD_IN_M), "layout.start_m")
    if start < vehicle_start_m:
        raise c.error("layout.start_m", f"{start:g} m: the transition starts behind the leading wheelset "
                                        f"(vehicle.start_s_m = {vehicle_start_m:g} m); the vehicle starts in "
                                        "equilibrium on the straight ahead of it")
    return {"radius_m": R, "cant_m": h, "transition_m": lt,
            "direction": c.string(table.get("direction", CURVE_DIRECTIONS[0]), "layout.direction", CURVE_DIRECTIONS),
            "start_m": start}


def layout_combination_error(c, data: dict):
    """The error (a :class:`~.spec.ScenarioError` to raise) for a ``[layout]`` with what it cannot be combined
    with, or None: a train (the track-following frames follow one vehicle's bodies, not a train's cars and
    couplers), a ``[flexible_track]`` (the build gives the run one update before every step: the flexible track's
    moving window or the curve's track-following frames), ``contact.wheel_rail = "springs"`` (no wheel–rail
    connector: no curve in the contact)."""
    vt = data.get("vehicle", {})
    if isinstance(vt, dict) and "consist" in vt:
        return c.error("layout", "a curved track is run with one vehicle (vehicle.name or vehicle.file), not a train "
                                 "(vehicle.consist): the track-following frames follow one vehicle's bodies")
    if "flexible_track" in data:
        return c.error("layout", "a [layout] cannot be combined with a [flexible_track] (the run's update before "
                                 "every step is either the flexible track's moving window or the curve's "
                                 "track-following frames): remove one of the two tables")
    contact = data.get("contact", {})
    if isinstance(contact, dict) and contact.get("wheel_rail") == "springs":
        return c.error("contact.wheel_rail", "'springs' has no wheel-rail connector: a [layout] needs 'contact'")
    return None


def layout_run_settings(c, run_table: dict, run: RunSettings, vehicle, speed_m_s: float) -> RunSettings:
    """The run settings on a curve: an explicit solver without ``run.dt_s`` takes the curving run's step (the
    default step, or the largest whole fraction of it within the creep damping's limit,
    :func:`~.curve_setup.creep_limited_step_s`); a given ``run.dt_s`` is kept (:func:`warn_creep_step` judges it
    when the model is built)."""
    if METHODS[run.solver].implicit or "dt_s" in run_table:
        return run
    return c.settings(RunSettings, {**run_table, "dt_s": creep_limited_step_s(vehicle, speed_m_s, run.dt_s)}, "run")


def warn_creep_step(run: RunSettings, vehicle, speed_m_s: float) -> None:
    """An :class:`~exudyn_wheelrail.validation.InputWarning` (``warning: run.dt_s: ...`` on the command line) when an
    explicit solver's step on a curve is longer than :func:`~.curve_setup.creep_step_limit_s` at this speed: the run
    goes on with it.  Issued once per build (the spec is validated again at every step of the pipeline)."""
    if METHODS[run.solver].implicit:
        return
    limit = creep_step_limit_s(vehicle, speed_m_s)
    if float(run.dt_s) > limit:
        warnings.warn(InputWarning(
            f"run.dt_s: {float(run.dt_s):g} s is longer than {limit:.3g} s, the largest explicit step for the creep "
            f"damping of a wheelset at {speed_m_s * 3.6:g} km/h (scenarios.curve_setup.creep_step_limit_s): the "
            "wheelsets may integrate a limit cycle instead of rolling; leave run.dt_s out for the curving run's "
            "step"), stacklevel=3)
