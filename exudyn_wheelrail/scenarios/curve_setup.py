r"""What the steady-curving run (:mod:`.curving`) and a scenario with a ``[layout]`` (:mod:`.build`) share, written
once: the curve entry's layout covering a run (:func:`entry_layout`), the explicit step the creep damping of a
slowly rolling wheelset allows (:func:`creep_step_limit_s`, :func:`creep_limited_step_s`), the plausibility of a
curve for a vehicle (:func:`check_curve`), and the starting rule for
track irregularities on a curve (:func:`check_start_undisplaced`): the vehicle starts in static equilibrium on the
undisplaced straight ahead of the transition, so an irregularity must vanish, with its slopes, under every wheelset
at t = 0.
"""
from __future__ import annotations

import math

import numpy as np

from ..analysis.curving import minimum_radius_m
from ..rolling_stock.vehicle_builder import RailSprings, static_load_path
from ..track.irregularities import CHANNELS, channel_values
from ..track.layout import MAX_CANT_M, MAX_RADIUS_M, MAX_TRANSITION_M, TrackLayout
from ..track.rigid import Irregularity
from .defaults import DEFAULT_RAMP

__all__ = ["CurvingInputError", "CREEP_STEP_FACTOR", "LAYOUT_MARGIN_M", "START_TOLERANCE_M", "CURVE_READ_M",
           "creep_step_limit_s", "creep_limited_step_s", "check_curve", "wheelset_start_s_m", "check_start_undisplaced",
           "entry_layout"]

#: RK44 step = this / the fastest creep decay rate (RK44's real-axis stability limit is 2.785)
CREEP_STEP_FACTOR = 2.0
#: the layout's circular curve (and a generated irregularity) reaches this far beyond the run's distance [m]
LAYOUT_MARGIN_M = 10.0
#: the track under the wheelsets at t = 0 counts as undisplaced when every channel is within this [m] (and every
#: slope within this per metre)
START_TOLERANCE_M = 1e-12
#: the curve's quantities at the run's speed (cant angle, a_nc, balance speed) are read this far into the circular
#: curve [m], past the end of the transition
CURVE_READ_M = 1.0


class CurvingInputError(ValueError):
    """Bad curving input: ``option`` names the argument (``radius_m``…), ``str()`` is ``"<option>: <problem>"``."""

    def __init__(self, option: str, problem: str):
        super().__init__(f"{option}: {problem}")
        self.option = option
        self.problem = problem


def creep_step_limit_s(vehicle, speed_m_s: float, gravity_m_s2: float = 9.81) -> float:
    """The largest RK44 step [s] for the creep damping of a wheelset, :data:`CREEP_STEP_FACTOR` / λ_max: at low
    speed the creep forces act on a rolling wheelset like dampers ``f11/V``, ``f22/V`` (Kalker's coefficients at the
    static wheel load, :meth:`~exudyn_wheelrail.rolling_stock.vehicle_builder.RailSprings.from_hertz`), whose decay rates
    ``2 f11 r0²/(V I_yy)`` (spin), ``2 f22/(V m)`` (lateral) and ``2 f11 b²/(V I_zz)`` (yaw) grow as 1/V; an explicit
    step beyond RK44's real-axis limit h λ = 2.785 integrates a limit cycle instead of rolling (e.g. 36 km/h,
    single wheelset: λ ≈ 4500 1/s, unstable at 1 ms).  The run monitor's step check watches the vertical contact
    frequency only."""
    q = float(np.max(static_load_path(vehicle, gravity_m_s2).wheel))
    rs = RailSprings.from_hertz(wheel_load_N=q, speed_m_s=speed_m_s, r0_m=vehicle.geometry.r0_m)
    ws = vehicle.wheelset
    b = vehicle.tape_circle_semi_spacing_m()
    lam = max(2.0 * rs.c_longitudinal_N_s_per_m * vehicle.geometry.r0_m ** 2 / ws.Iyy_kg_m2,
              2.0 * rs.c_lateral_N_s_per_m / ws.mass_kg,
              2.0 * rs.c_longitudinal_N_s_per_m * b ** 2 / ws.Izz_kg_m2)
    return CREEP_STEP_FACTOR / lam


def creep_limited_step_s(vehicle, speed_m_s: float, dt_s: float) -> float:
    """``dt_s`` if it is within :func:`creep_step_limit_s`, else the largest whole fraction ``dt_s / n`` that is."""
    dt = min(float(dt_s), creep_step_limit_s(vehicle, speed_m_s))
    if dt < float(dt_s):
        dt = float(dt_s) / math.ceil(float(dt_s) / dt)
    return dt


def check_curve(radius_m: float, cant_m: float, transition_m, vehicle) -> None:
    """Raise :class:`CurvingInputError` (option ``radius_m``, ``cant_m`` or ``transition_m``) for a curve that
    ``vehicle`` cannot run or that was evidently given in another unit: a radius above :data:`~..track.layout.
    MAX_RADIUS_M` or below the smallest the vehicle can follow (:func:`~..analysis.curving.minimum_radius_m`), a cant
    above :data:`~..track.layout.MAX_CANT_M`, a transition longer than :data:`~..track.layout.MAX_TRANSITION_M` or of
    0 m with a cant.  The values are numbers already, the radius > 0, the cant and the transition >= 0
    (``transition_m`` None: the default ramp); the callers check that and name their own inputs."""
    if radius_m > MAX_RADIUS_M:
        raise CurvingInputError("radius_m", f"{radius_m:g} m is above {MAX_RADIUS_M:g} m (was it given in mm?)")
    r_min, why = minimum_radius_m(vehicle)
    if radius_m < r_min:
        hint = f"; was it given in km ({radius_m * 1000:g} m)?" if radius_m < 10.0 else ""
        raise CurvingInputError("radius_m", f"{radius_m:g} m is below the smallest radius this vehicle can follow, "
                                            f"{r_min:.0f} m ({why}){hint}")
    if cant_m > MAX_CANT_M:
        hint = f"; was it given in mm ({cant_m / 1000:g} m)?" if cant_m >= 1.0 else ""
        raise CurvingInputError("cant_m", f"{cant_m:g} m is above the largest cant, {MAX_CANT_M:g} m (EN 13803){hint}")
    if transition_m is None:
        return
    if transition_m > MAX_TRANSITION_M:
        raise CurvingInputError("transition_m", f"{transition_m:g} m is longer than {MAX_TRANSITION_M:g} m; was it "
                                                f"given in mm ({transition_m / 1000:g} m)?")
    if transition_m == 0.0 and cant_m > 0.0:
        raise CurvingInputError("transition_m", f"0 m with a cant: the cant would step from 0 to {cant_m:g} m at one "
                                                "section (the rails twist instantly under a wheelset); give a "
                                                f"transition for the cant ramp (e.g. 1:{DEFAULT_RAMP:g}) or leave the "
                                                "transition out (the default ramp)")


def wheelset_start_s_m(vehicle, s_leading_m: float = 0.0) -> np.ndarray:
    """Track distances of the wheelsets at t = 0, the leading one at ``s_leading_m``."""
    x = np.asarray(vehicle.wheelset_x_m(), dtype=float)
    return x - np.max(x) + s_leading_m


def check_start_undisplaced(irregularity, vehicle, s_leading_m: float = 0.0) -> None:
    """Raise :class:`CurvingInputError` (option ``irregularity``) unless ``irregularity`` (an
    :class:`~exudyn_wheelrail.track.rigid.Irregularity`) and its slopes are within :data:`START_TOLERANCE_M` on every
    channel under every wheelset at t = 0 (the leading one at ``s_leading_m``)."""
    if not isinstance(irregularity, Irregularity):
        raise CurvingInputError("irregularity", f"{irregularity!r}: expected an Irregularity "
                                                "(exudyn_wheelrail.track.rigid, track.irregularities, "
                                                "track.spectra) or None")
    s0 = wheelset_start_s_m(vehicle, s_leading_m)
    v = channel_values(irregularity, s0)
    for name in CHANNELS:
        for prefix, unit in (("", "m"), ("d_", "m/m")):
            key = f"{prefix}{name}" if prefix else f"{name}_m"
            vals = np.asarray(getattr(v, key))
            if np.any(np.abs(vals) > START_TOLERANCE_M):
                j = int(np.argmax(np.abs(vals)))
                what = "slope of the " if prefix else ""
                raise CurvingInputError(
                    "irregularity", f"{irregularity!r}: the {what}{name} is {vals[j]:.3g} {unit} under a wheelset "
                                    f"at t = 0 (s = {s0[j]:g} m); the vehicle starts on the undisplaced straight "
                                    f"(s <= {s_leading_m:g} m): start the irregularity ahead of the leading wheelset "
                                    "or fade it in (a spectrum track entry's fade_in_m; in Python FadedIn or "
                                    "spectral_irregularity)")


def entry_layout(radius_m: float, cant_m: float, transition_m: float, direction: str, transition_start_m: float,
                 curve_m: float) -> TrackLayout:
    """Straight track up to ``transition_start_m``, the transition (clothoid, linear cant ramp) of
    ``transition_m``, then the circular curve of ``radius_m``, ``cant_m``, ``direction`` for ``curve_m`` (and
    continued after): :meth:`~exudyn_wheelrail.track.layout.TrackLayout.curve_entry` with the straight from s = 0
    (a transition starting before s = 0: the layout starts there)."""
    return TrackLayout.curve_entry(radius_m, cant_m, transition_m, direction=direction,
                                   lead_in_m=max(transition_start_m, 0.0), curve_m=curve_m,
                                   start_m=min(transition_start_m, 0.0))
