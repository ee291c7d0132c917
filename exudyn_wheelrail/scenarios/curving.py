r"""Steady curving run: a vehicle from straight track through an entry transition (clothoid, linear cant ramp) into
a circular curve, run until it is steady, and the steady-state quantities of :mod:`exudyn_wheelrail.analysis.
curving`.

>>> case = CurvingCase("manchester_vehicle1", radius_m=600.0, cant_m=0.15, speed_km_h=100.0)   # doctest: +SKIP
>>> result = run_curving(case, out_dir="out/curving")                                          # doctest: +SKIP
>>> result.summary["sum_Y_N"], result.summary["status"]                                        # doctest: +SKIP

The ``curving`` command is a front end of the scenario pipeline (:mod:`exudyn_wheelrail.scenarios.scenario`):
:func:`curving_scenario` fills a scenario spec from the :class:`CurvingCase` — ``[vehicle]`` (leading wheelset at
s = 0), ``[layout]`` (the curve, its transition starting :data:`LEAD_IN_M` ahead), ``[contact]`` and ``[run]`` from
the case's preset (:data:`~exudyn_wheelrail.simulation.presets.PRESETS`: integrator, contact geometry, creep law;
the preset's step, shortened where the creep damping of a slowly rolling wheelset needs it,
:func:`creep_step_limit_s`; the duration of :func:`curving_distances`) and the friction, ``[outputs]`` (no car-body
points, no criteria, no plots) — and :func:`build_curving` builds it with :func:`~.build.build_scenario` (the model
of a scenario's ``[layout]``: the wheel–rail connector on the rails of the layout, the track-following frames
updated before every step, started in static equilibrium on the straight); :func:`run_curving` runs it through the
scenario pipeline's solve wrapper (:func:`~.run.run_model`), evaluates it with :func:`curving_summary` (this
command's own evaluation: steady state and force balance, :mod:`exudyn_wheelrail.analysis.curving`) and writes it
with the scenarios' writer (:func:`~.outputs.write_json`, :func:`~.outputs.write_csv`).  What the spec's plain
values cannot hold goes to :func:`~.build.build_scenario` as its Python-only inputs: a vehicle given as
:class:`~exudyn_wheelrail.rolling_stock.vehicle_data.VehicleData`, ``CurvingCase.wheel_rail_pair`` and
``CurvingCase.irregularity``.

Outputs: ``summary.json`` (:func:`curving_summary`; non-finite numbers as ``null``, as every summary the
scenarios' writer writes) and ``timeseries.csv`` — every column the run records, in the recorder's order (time,
leading wheelset's distance, Y, Q, Y/Q, flange contact, contact angle, wheelset lateral displacement, the track
under the wheelsets, then the curve's columns: yaw relative to the track and curvature per wheelset), 10
significant digits.

Run length (:func:`curving_distances`): the leading wheelset starts :data:`LEAD_IN_M` before the transition; the
run lasts until the trailing wheelset has run the settling distance ``max(SETTLE_M, SETTLE_S · V)`` into the
circular curve and then the steady part ``max(WINDOW_M, WINDOW_S · V)``.  The mean over a whole number of periods
of the slowest oscillation left in it (:func:`~exudyn_wheelrail.analysis.curving.averaging_window`) is the steady
value; the run is called steady when the means of ΣY over the two halves of the steady part differ, summed over
the wheelsets, by less than :data:`~exudyn_wheelrail.analysis.curving.STEADY_TOLERANCE` of ``m max(|a_nc|, 0.3 m/s²)``
(:func:`~exudyn_wheelrail.analysis.curving.steady_state`).

Track irregularities (``CurvingCase.irregularity``, or ``irregularity_spectrum`` and ``seed``): any
:class:`~exudyn_wheelrail.track.rigid.Irregularity`
(per-rail channels, :mod:`exudyn_wheelrail.track.irregularities`) displaces the rails of the layout, relative to
the local track frame at each wheelset's s.  The vehicle starts in equilibrium on the undisplaced straight, so the
irregularity must vanish, with its slopes, under every wheelset at t = 0 (checked before any work).
:func:`spectral_irregularity` generates one from a standard spectrum (:mod:`exudyn_wheelrail.track.spectra`) over
the run's distance and fades it in (:class:`~exudyn_wheelrail.track.irregularities.FadedIn`, a raised cosine)
from the leading wheelset's start to the start of the circular curve, so the steady part runs over the full
standard irregularity.  The steady values are then the means over the averaging window of the response to it.  A
spectrum and seed of the case (the command line's ``--irregularity-spectrum``, ``--seed``) are written into the
scenario as its ``spectrum`` track component with that fade-in (:func:`spectrum_component`); an irregularity
object reaches the build as :func:`~.build.build_scenario`'s Python-only ``irregularity``.
"""
from __future__ import annotations

import math
import operator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import contact_defaults
from ..conventions import CURVE_DIRECTION_SIGN
from ..analysis.curving import steady_state
from ..rolling_stock.vehicle_data import VehicleData, load_vehicle
from ..simulation import status as S
from ..simulation.presets import PRESETS
from ..simulation.settings import RunSettings
from ..track.irregularities import FadedIn
from ..track.layout import MAX_RADIUS_M, MAX_TRANSITION_M, curve_quantities
from ..track.spectra import DEFAULT_BAND_M, SPECTRA
from .build import ScenarioModel, build_scenario
from .curve_setup import (CREEP_STEP_FACTOR, CURVE_READ_M, LAYOUT_MARGIN_M, START_TOLERANCE_M, CurvingInputError,
                          check_curve, check_start_undisplaced, creep_limited_step_s, creep_step_limit_s)
from .defaults import DEFAULT_RAMP, LEAD_IN_M, default_transition_m
from .outputs import write_csv, write_json
from .run import run_events, run_model
from .spec import spectrum_table

__all__ = ["CurvingCase", "CurvingResult", "CurvingInputError", "check_curving_case", "curving_distances",
           "curving_scenario", "build_curving", "run_curving", "CURVING_TIMESERIES", "LEAD_IN_M", "SETTLE_M",
           "SETTLE_S", "WINDOW_M", "WINDOW_S",
           "MAX_TRANSITION_M", "MAX_SPEED_KM_H", "MIN_SPEED_KM_H", "MAX_RADIUS_M", "DEFAULT_RAMP", "CREEP_STEP_FACTOR",
           "creep_step_limit_s", "curving_summary", "write_outputs", "FadedIn", "spectral_irregularity",
           "spectrum_component",
           "irregularity_fade_m", "MIN_FADE_M", "START_TOLERANCE_M"]

# LEAD_IN_M (straight track ahead of the leading wheelset at t = 0) and the default transition (the cant ramp
# 1 : DEFAULT_RAMP, at least DEFAULT_MIN_TRANSITION_M) are declared in .defaults (the command line shows them); the
# plausible radius, cant and transition in track.layout (MAX_RADIUS_M, MAX_CANT_M, MAX_TRANSITION_M); their check
# (check_curve), the creep step (CREEP_STEP_FACTOR), the layout's margin (LAYOUT_MARGIN_M), the undisplaced start
# (START_TOLERANCE_M) and CurvingInputError in .curve_setup, which a scenario's [layout] shares.

#: settling distance after the trailing wheelset enters the circular curve: at least this [m] and this [s] of run
SETTLE_M = 60.0
SETTLE_S = 3.0
#: averaging window of the steady state: at least this [m] and this [s] of run
WINDOW_M = 40.0
WINDOW_S = 2.5
#: plausible speeds (values outside name the unit they were evidently given in)
MAX_SPEED_KM_H = 500.0
MIN_SPEED_KM_H = 10.0
#: shortest fade-in of a generated irregularity [m] (its slope is at most π/2 · amplitude / fade length)
MIN_FADE_M = 20.0

@dataclass(frozen=True)
class CurvingCase:
    """What a curving run simulates.  ``transition_m`` None: the default ramp (:data:`DEFAULT_RAMP`)."""

    vehicle: object                       #: a shipped vehicle name, a vehicle file or a VehicleData
    radius_m: float
    cant_m: float
    speed_km_h: float
    transition_m: float | None = None
    direction: str = "right"
    friction: float = contact_defaults.FRICTION
    preset: str = "fast"
    #: a :class:`~exudyn_wheelrail.contact.WheelRailPair` in place of the vehicle's profiles (None: the vehicle's)
    wheel_rail_pair: object = None
    #: an :class:`~exudyn_wheelrail.track.rigid.Irregularity` of the rails (None: a perfect track); zero under
    #: the wheelsets at t = 0 (module docstring; :func:`spectral_irregularity`)
    irregularity: object = None
    #: or the name of a standard spectrum (:data:`~exudyn_wheelrail.track.spectra.SPECTRA`) and its ``seed``: the
    #: irregularity of :func:`spectral_irregularity`, written into the scenario as its ``spectrum`` track component
    irregularity_spectrum: str | None = None
    seed: int | None = None

    @property
    def speed_m_s(self) -> float:
        return self.speed_km_h / 3.6

    @property
    def transition_length_m(self) -> float:
        if self.transition_m is not None:
            return float(self.transition_m)
        return default_transition_m(self.cant_m)


@dataclass
class CurvingResult:
    summary: dict
    timeseries: dict = field(repr=False)
    outcome: object = field(default=None, repr=False)


def _vehicle(case: CurvingCase):
    return case.vehicle if isinstance(case.vehicle, VehicleData) else load_vehicle(case.vehicle)


def check_curving_case(case: CurvingCase, vehicle=None):
    """Check the inputs before any work; raises :class:`CurvingInputError` naming the argument.  Returns the
    vehicle data."""
    def num(name, v):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise CurvingInputError(name, f"{v!r}: expected a finite number")
        return float(v)

    R = num("radius_m", case.radius_m)
    h = num("cant_m", case.cant_m)
    v = num("speed_km_h", case.speed_km_h)
    lt = None
    if case.transition_m is not None:
        lt = num("transition_m", case.transition_m)
        if lt < 0.0:
            raise CurvingInputError("transition_m", f"{lt:g} m: a transition cannot be shorter than 0 m")
    if h < 0.0:
        raise CurvingInputError("cant_m", f"{h:g} m: expected a cant >= 0 (it raises the outer rail; the direction "
                                          "of the curve is given separately)")
    if not v >= MIN_SPEED_KM_H:
        raise CurvingInputError("speed_km_h", f"{v:g} km/h: expected a running speed >= {MIN_SPEED_KM_H:g} km/h "
                                              "(the steady-curving run covers a fixed distance; below this its "
                                              "duration and the creep damping's time step make it impractical)")
    if v > MAX_SPEED_KM_H:
        raise CurvingInputError("speed_km_h", f"{v:g} km/h is above {MAX_SPEED_KM_H:g} km/h")
    if case.direction not in CURVE_DIRECTION_SIGN:
        raise CurvingInputError("direction", f"{case.direction!r}: expected one of "
                                             f"{', '.join(map(repr, CURVE_DIRECTION_SIGN))}")
    if not R > 0.0:
        raise CurvingInputError("radius_m", f"{R:g} m: expected a radius > 0")
    if vehicle is None:
        try:
            vehicle = _vehicle(case)
        except (ValueError, FileNotFoundError) as exc:
            raise CurvingInputError("vehicle", str(exc).splitlines()[0] if str(exc) else repr(exc)) from None
    check_curve(R, h, lt, vehicle)
    if case.irregularity is not None:
        if case.irregularity_spectrum is not None:
            raise CurvingInputError("irregularity", "give an irregularity or a spectrum with its seed, not both")
        check_start_undisplaced(case.irregularity, vehicle)
    if case.irregularity_spectrum is None and case.seed is not None:
        raise CurvingInputError("seed", f"{case.seed!r}: given without a spectrum (it seeds the generated "
                                        "irregularity)")
    if case.irregularity_spectrum is not None:
        if case.irregularity_spectrum not in SPECTRA:
            raise CurvingInputError("irregularity_spectrum", f"{case.irregularity_spectrum!r}: expected one of "
                                                             f"{', '.join(SPECTRA)}")
        if case.seed is None:
            raise CurvingInputError("seed", f"missing (required with the spectrum {case.irregularity_spectrum})")
        try:
            seed = None if isinstance(case.seed, bool) else operator.index(case.seed)
        except TypeError:
            seed = None
        if seed is None or seed < 0:
            raise CurvingInputError("seed", f"{case.seed!r}: expected a non-negative integer")
    return vehicle


def irregularity_fade_m(case: CurvingCase) -> tuple[float, float]:
    """Where a generated irregularity is faded in: from the leading wheelset's start (s = 0) to the start of the
    circular curve, at least :data:`MIN_FADE_M`."""
    return 0.0, max(LEAD_IN_M + case.transition_length_m, MIN_FADE_M)


def spectrum_component(case: CurvingCase, spectrum, seed: int, vehicle=None, **options) -> dict:
    """The scenario's ``spectrum`` track component (:mod:`.spec`) of :func:`spectral_irregularity`: generated from
    s = 0 over the run's distance (at least the band's longest wavelength) and faded in
    (:func:`irregularity_fade_m`); the seed as a Python integer (the spec's, whatever integer type it was given
    as)."""
    if vehicle is None:
        vehicle = _vehicle(case)
    dist = curving_distances(case, vehicle)
    band = options.get("band_m", DEFAULT_BAND_M)
    length = max(dist["total_m"] + LAYOUT_MARGIN_M, float(max(band)))
    s_from, s_to = irregularity_fade_m(case)
    return {"type": "spectrum", "spectrum": spectrum, "seed": operator.index(seed), "length_m": length,
            "start_m": s_from, "fade_in_m": s_to - s_from, **options}


def spectral_irregularity(case: CurvingCase, spectrum, seed: int, vehicle=None, **options) -> FadedIn:
    """An irregularity of ``spectrum`` (a name of :data:`~exudyn_wheelrail.track.spectra.SPECTRA`) and ``seed``
    for ``case``: generated from s = 0 over the run's distance (at least the band's longest wavelength; ``options``
    as :class:`~exudyn_wheelrail.track.spectra.SpectralIrregularity`: ``band_m``, ``step_m``, ``channels``,
    ``scale``; their defaults are the spectra module's) and faded in (:func:`irregularity_fade_m`).  Raises
    ``ValueError`` for a bad spectrum, seed or option."""
    return spectrum_table(spectrum_component(case, spectrum, seed, vehicle, **options))


def curving_distances(case: CurvingCase, vehicle) -> dict:
    """The run's distances [m] and duration [s] (module docstring)."""
    V = case.speed_m_s
    x = vehicle.wheelset_x_m()
    extent = float(max(x) - min(x))
    lt = case.transition_length_m
    settle = max(SETTLE_M, SETTLE_S * V)
    window = max(WINDOW_M, WINDOW_S * V)
    total = LEAD_IN_M + lt + extent + settle + window
    return dict(lead_in_m=LEAD_IN_M, transition_m=lt, vehicle_extent_m=extent, settle_m=settle, window_m=window,
                total_m=total, duration_s=total / V, window_start_s=(total - window) / V)


#: the column groups of the curving run's time series (the recorder's, then the curve's), all written
CURVING_TIMESERIES = ["Y", "Q", "YQ", "flange", "contact_angle", "wheelset_lateral", "track", "curving"]


def _vehicle_entry(case: CurvingCase, vehicle) -> dict:
    """The spec's vehicle reference: the case's name or file; for VehicleData (the build's Python-only ``vehicle``,
    which the spec's checks judge) a label: the file it was read from, else its name."""
    if isinstance(case.vehicle, VehicleData):
        return {"file": str(vehicle.path)} if vehicle.path is not None else {"name": vehicle.name}
    return {"file" if Path(str(case.vehicle)).suffix else "name": str(case.vehicle)}


def curving_scenario(case: CurvingCase, vehicle=None) -> dict:
    """The scenario spec (plain values, :func:`~.spec.validate_scenario`'s input) of a curving case: the module
    docstring says what it fills.  ``vehicle``: the case's vehicle data (read if None)."""
    vehicle = _vehicle(case) if vehicle is None else vehicle
    dist = curving_distances(case, vehicle)
    preset = PRESETS[case.preset]
    layout = {"radius_m": float(case.radius_m), "cant_m": float(case.cant_m), "direction": case.direction,
              "start_m": LEAD_IN_M}
    if case.transition_m is not None:
        layout["transition_m"] = float(case.transition_m)
    track = {} if case.irregularity_spectrum is None else {
        "track": [spectrum_component(case, case.irregularity_spectrum, case.seed, vehicle)]}
    return {"schema_version": 2,
            "scenario": {"name": "curving", "description": f"steady curving: {vehicle.name}, R = {case.radius_m:g} m "
                                                           f"{case.direction}, cant {case.cant_m:g} m, "
                                                           f"{case.speed_km_h:g} km/h"},
            "vehicle": {**_vehicle_entry(case, vehicle), "speed_km_h": float(case.speed_km_h), "start_s_m": 0.0},
            "layout": layout, **track,
            "contact": {**preset.contact, "friction": float(case.friction)},
            "run": {**preset.run, "dt_s": creep_limited_step_s(vehicle, case.speed_m_s, RunSettings(**preset.run).dt_s),
                    "duration_s": dist["duration_s"]},
            "outputs": {"timeseries": list(CURVING_TIMESERIES), "carbody_points": [], "criteria": False,
                        "plots": False, "formats": ["csv"]}}


def build_curving(case: CurvingCase, vehicle=None) -> ScenarioModel:
    """The assembled model of a curving run (checked first, :func:`check_curving_case`): the
    :class:`~.build.ScenarioModel` of :func:`curving_scenario`, with the case's Python-only inputs."""
    vehicle = check_curving_case(case, vehicle)
    return build_scenario(curving_scenario(case, vehicle),
                          vehicle=vehicle if isinstance(case.vehicle, VehicleData) else None,
                          pair=case.wheel_rail_pair, irregularity=case.irregularity)


def run_curving(case: CurvingCase, out_dir=None, progress=None) -> CurvingResult:
    """Build, run and reduce a curving case; with ``out_dir`` write ``summary.json`` and ``timeseries.csv``.
    ``progress``: None or False — none; True or a stream — the bar of :func:`~.run.run_model`."""
    h = build_curving(case)
    outcome = run_model(h, progress=progress or False, label="curving: ")
    ts = h.recorder.table()
    result = CurvingResult(summary=curving_summary(case, h, ts, outcome), timeseries=ts, outcome=outcome)
    if out_dir is not None:
        write_outputs(result, out_dir)
    return result


def curving_summary(case: CurvingCase, h: ScenarioModel, ts: dict, outcome) -> dict:
    """The curving run's ``summary.json``: the case, the curve's quantities, the run's status, and for a run that
    reached its end the steady state and the force balance (:func:`~exudyn_wheelrail.analysis.curving.
    steady_state`) over the steady part."""
    vehicle, model, layout = h.vehicle, h.model, h.layout
    dist = curving_distances(case, vehicle)
    status = outcome.status
    g = model.gravity_m_s2
    V = case.speed_m_s
    s_curve = LEAD_IN_M + dist["transition_m"] + CURVE_READ_M
    curve = curve_quantities(layout, case.radius_m, case.cant_m, s_curve, V, g)
    a_nc = curve["unbalanced_lateral_acceleration_m_s2"]
    mass = float(vehicle.total_mass_kg)
    summary = {"status": status.kind, "status_detail": status.as_dict(), "exit_code": status.exit_code,
               "status_text": str(status), "events": run_events(outcome), "n_events": len(outcome.events or []),
               "vehicle": vehicle.name, "vehicle_mass_kg": mass, "n_wheelsets": len(model.wheelsets),
               "radius_m": case.radius_m, "cant_m": case.cant_m, "direction": case.direction,
               "speed_km_h": case.speed_km_h, "transition_m": dist["transition_m"],
               "cant_angle_rad": curve["cant_angle_rad"],
               "unbalanced_lateral_acceleration_m_s2": a_nc,
               "balance_speed_km_h": curve["balance_speed_km_h"],
               "distances_m": dist, "solver": h.run.solver, "dt_s": h.run.dt_s,
               "solve_seconds": outcome.solve_seconds, "t_end_s": outcome.t_end_s}
    irregular = case.irregularity is not None or case.irregularity_spectrum is not None
    if irregular:
        irr = h.track.irregularity          # the case's, or its spectrum's as built from the scenario
        summary["irregularity"] = {"description": repr(irr), "seed": getattr(irr, "seed", None)}
        if isinstance(irr, FadedIn):
            summary["irregularity"]["faded_in_m"] = [irr.s_from_m, irr.s_to_m]
    ok = status.kind == S.OK and outcome.t_end_s >= dist["duration_s"] - 2 * h.run.dt_s
    if ok:
        st = steady_state(ts, model, layout, t_from_s=dist["window_start_s"], speed_m_s=V, gravity_m_s2=g,
                          a_nc_m_s2=a_nc)
        summary.update(st)
        total = float(np.sum(st["sum_Y_N"]))
        guidance = st.get("guidance_lateral_N", 0.0)
        summary["force_balance"] = {
            "sum_sum_Y_N": total, "m_a_nc_N": mass * a_nc, "guidance_lateral_N": guidance,
            "relative_error": (total + guidance - mass * a_nc) / (mass * a_nc) if abs(a_nc) > 0 else None,
            "reads": "sum_sum_Y_N + guidance_lateral_N = m_a_nc (guidance: the elements to the moving frame of the "
                     "bogie and wheelset layouts, zero for a car)"}
        if not st["steady"]:
            summary["notes"] = [f"not steady: the means of sum Y over the two halves of the steady part differ by "
                                f"{sum(st['steady_drift_N']):.4g} N summed over the wheelsets (tolerance "
                                f"{st['steady_tolerance_N']:.4g} N): the values are means of a drifting run; run a "
                                "longer curve or check the vehicle's damping"]
            if irregular:
                summary["notes"].append("over track irregularities the halves differ also by the response to them "
                                        "(the drift tolerance is set for a perfect track)")
    else:
        summary["sum_Y_N"] = None
        summary["steady"] = False
    summary["assumptions"] = [
        "track-following frames per body (exudyn_wheelrail.rolling_stock.track_following): frame inertia and gravity in "
        "the canted track plane on every body, gyroscopic moment of the wheelsets, suspension offsets from the "
        "chord geometry between bodies at different track distances",
        "creepage terms of the turning frame in the contact connector (longitudinal -+ b kappa, spin)",
        "neglected (module docstring of track_following): element forces are not turned by the relative yaw of "
        "the bodies' frames, the rate of the suspension offsets in the dampers (transition only), the Coriolis "
        "term of the bodies' relative velocities",
    ]
    if model.vehicle.layout in ("wheelset", "bogie"):
        summary["assumptions"].append(
            "dead-load layout: the carried mass is held by the moving frame (its weight is the dead load, its "
            "lateral inertia is not on the wheelsets); vehicle_mass_kg is the mass of the modelled bodies, and the "
            "guidance elements to the frame carry guidance_lateral_N")
    return summary


def write_outputs(result: CurvingResult, out_dir) -> None:
    """``summary.json`` and ``timeseries.csv`` (every recorded column) into ``out_dir``, by the scenarios' writer."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_json(out / "summary.json", result.summary)
    write_csv(out / "timeseries.csv", result.timeseries)
