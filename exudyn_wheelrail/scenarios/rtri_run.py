r"""The RTRI run and its summary: :func:`run_rtri` builds the case's spec (:class:`~.rtri_case.RtriCase`), runs it
and summarises it (coverage, whole-run and passage peaks, what is left after the passage, notes, the assumptions
table); :func:`write_rtri_outputs` writes ``timeseries.csv``, ``summary.json`` and the Fig. 5/6 plots
(:mod:`.rtri_figures`).  The public import path of the case is :mod:`exudyn_wheelrail.scenarios.rtri`.

How it runs
-----------
:class:`~.rtri_case.RtriCase` is a **spec**: :meth:`~.rtri_case.RtriCase.scenario` writes it as a normalised
scenario (vehicle, one span deflection, contact and run settings, the recorded groups; :mod:`.scenario`),
:func:`run_rtri` builds it with :func:`~.scenario.build_scenario` and runs it through the one solve wrapper
(:func:`exudyn_wheelrail.simulation.runner.run`: watched by the run monitor; the summary's ``status`` is one of
:mod:`exudyn_wheelrail.simulation.status`).  The time series below are the scenario recorder's columns
(:mod:`exudyn_wheelrail.simulation.recorder`) under the case's names (:data:`RTRI_COLUMNS`).


Outputs (one row per time step, the state at ``time_s``)
---------------------------------------------------------
The recorder reads the contact as the run monitor evaluated it at the state's own time (Exudyn's pre-step function
receives the end time of the coming step; the runner passes the state's time — evaluating at the passed time would
shift the rails by V h, up to 69 mm at 250 km/h).  A run of n steps has n + 1 rows.

* ``carbody_lateral_acceleration_rear_m_s2`` — track-frame (y right) acceleration of the car-body point above the
  rear bogie centre at floor level (``floor_height_m`` above the rail top, an assumption), from Exudyn's
  rigid-body output ``OutputVariableType.Acceleration`` at that local position (a ``SensorBody`` on that point,
  stored in memory: the node's translational acceleration plus the angular-acceleration and centripetal terms,
  the same numbers as ``GetObjectOutputBody``).  Kinematic acceleration, without gravity.  ``carbody_lateral_accelerometer_rear_m_s2``
  is what an accelerometer fixed to the floor reads: the specific force (a − g) in the car body's own y axis,
  which includes g times the car-body roll.
* ``lateral_contact_force_w1_right_N`` — y component (track frame, y to the right) of the total contact force
  (normal + creep, tread + flange region) that the **rail exerts on the right wheel of the leading wheelset**
  (``WheelRailContact.wheel_force_N``).  A flange contact of the right wheel gives a **negative** value (the rail
  pushes the wheel to the left).  The straight track's y axis is used: the deviated rail is turned by at most
  πδ/L = 1.6 mrad, which changes the value by at most 0.0016 |Fx|.  The paper's Fig. 6 most likely shows the
  opposite sign (the force of the wheel on the rail, positive during a flange impact, as Y is usually plotted);
  ``derailment_quotient_w1_right`` uses that sign: Y/Q = −Fy/Q (positive when the right flange presses against
  its rail), NaN when the wheel is lifted (Q = 0).
* ``vertical_contact_force_w1_right_N`` — wheel load Q = −Fz (z down), positive.
* ``flange_contact_w1_right`` — 1 when the wheel's *flange region* (the profile beyond the tread/flange split in
  the throat, :class:`~..profiles.profiles.WheelProfile`) carries a contact (``WheelRailContact.flange_contact``),
  else 0.  A contact high on the flange root can still belong to the tread region (contact angles up to ~0.55
  rad); ``contact_angle_w1_right_rad`` shows it (the angle of the most loaded region).
* with a flexible car body (``RtriCase(car_body="flexible")``) the accelerations are those of the deformed body at
  the point (the frame's and the modes' motion), and the points above the front bogie and mid-car are recorded too
  (``carbody_<lateral|vertical>_<acceleration|accelerometer>_<front|centre|rear>_m_s2``); ``summary["comfort"]``
  gives Sperling's Wz and the EN 14363 quantities of every recorded point, ``summary["car_body"]`` the modes.
* extras: the track deviation under the leading wheelset and the wheelset's lateral displacement relative to its
  rails (the contact search's pose), ``Y_w<j>_<side>_N`` / ``Q_w<j>_<side>_N`` of every wheel (j = 1 leading … 4),
  the flange flags of both leading wheels, the car body's lateral displacement above the rear bogie.

Peaks
-----
``summary["peaks"]`` covers the whole run (not evaluated for a ``diverged`` run), ``summary["peaks_passage"]``
the response to the deviation (until the whole car has left the span and run the run-out),
``summary["after_passage"]`` what is left afterwards (a lateral oscillation that does not decay is self-excited and
is flagged in the notes).  Besides the raw peak of the lateral force, the peak of its 10 ms moving average
(:data:`AVERAGE_WINDOW_S`) is given: the raw force carries spikes of the wheelset's almost undamped ~200 Hz
vertical bounce on the Hertz spring (:mod:`.rtri_sweep`, what the model gives), whose heights are not converged in
dt; the averaged peak is (``tests/test_rtri.py``).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..analysis.comfort import carbody_acceleration_en14363, sperling_index
from ..rolling_stock.flexible_body import highest_mode_rad_s
from ..simulation import status as S
from ..simulation.settings import RunSettings
from ..simulation.solvers import METHODS, undamped_step_problem
from .drawing import FigureProcess
from .rtri_case import RtriCase, case_assumptions_table, vehicle_extent_m
from .rtri_figures import plot_fig5, plot_fig6
from .rtri_result import AVERAGE_WINDOW_S, RtriResult
from .scenario import build_scenario, peaks, run_model, write_csv, write_json

__all__ = [
    "AVERAGE_WINDOW_S",
    "RTRI_COLUMNS",
    "TIMESERIES_REQUIRED",
    "RtriResult",
    "rtri_columns",
    "run_rtri",
    "write_rtri_outputs",
]

#: the case's time-series columns and the scenario recorder's column each one is (:mod:`~exudyn_wheelrail.
#: simulation.recorder`); then ``Y_w<j>_<side>_N``, ``Q_w<j>_<side>_N`` of every wheel (:func:`rtri_columns`)
RTRI_COLUMNS = {
    "time_s": "time_s",
    "carbody_lateral_acceleration_rear_m_s2": "carbody_lateral_acceleration_rear_m_s2",
    "lateral_contact_force_w1_right_N": "Y_w1_right_N",
    "vertical_contact_force_w1_right_N": "Q_w1_right_N",
    "flange_contact_w1_right": "flange_w1_right",
    "track_deviation_w1_m": "track_lateral_w1_m",
    "wheelset1_lateral_rel_track_m": "y_rel_w1_m",
    "derailment_quotient_w1_right": "YQ_w1_right",
    "contact_angle_w1_right_rad": "contact_angle_w1_right_rad",
    "flange_contact_w1_left": "flange_w1_left",
    "carbody_lateral_accelerometer_rear_m_s2": "carbody_lateral_accelerometer_rear_m_s2",
    "carbody_lateral_displacement_rear_m": "carbody_lateral_displacement_rear_m",
}
#: the contract columns of ``timeseries.csv`` (further columns follow them)
TIMESERIES_REQUIRED = tuple(RTRI_COLUMNS)[:5]


def rtri_columns(n_wheelsets: int, carbody_points=("rear",)) -> dict:
    """:data:`RTRI_COLUMNS` followed by every wheel's ``Y`` and ``Q`` (wheelset by wheelset, right then left) and,
    for every car-body point, its lateral and vertical acceleration and accelerometer reading (the rear point's
    lateral ones are in :data:`RTRI_COLUMNS`)."""
    cols = dict(RTRI_COLUMNS)
    for p in carbody_points:
        for q in ("acceleration", "accelerometer"):
            for d in ("lateral", "vertical"):
                name = f"carbody_{d}_{q}_{p}_m_s2"
                cols.setdefault(name, name)
    for j in range(1, n_wheelsets + 1):
        for side in ("right", "left"):
            cols[f"Y_w{j}_{side}_N"] = f"Y_w{j}_{side}_N"
            cols[f"Q_w{j}_{side}_N"] = f"Q_w{j}_{side}_N"
    return cols


# ======================================================================================== what the run covers
def _coverage(case: RtriCase, vehicle, run: RunSettings) -> tuple[dict, list[str]]:
    """What the run covers (track distances of the leading wheelset, times) and notes."""
    a = case.assumptions
    V = case.speed_m_s
    L, lt = float(case.span_m), case.transition_m
    e = vehicle_extent_m(vehicle)
    x = vehicle.wheelset_x_m()
    x_rear_bogie_lead = sorted(x)[1]          # the rear bogie's leading wheelset
    sd = case.span_deflection()
    s_enter = sd.start_m - 0.5 * lt           # deviation begins
    s_leave = sd.end_m + 0.5 * lt             # deviation ends
    d_rear = max(x) - x_rear_bogie_lead
    t_end = run.end_time_s
    cov = {
        "vehicle_extent_m": e,
        "deviation_begins_at_track_distance_m": s_enter,
        "deviation_ends_at_track_distance_m": s_leave,
        "t_leading_wheelset_enters_span_s": s_enter / V,
        "t_leading_wheelset_leaves_span_s": s_leave / V,
        "t_rear_bogie_enters_span_s": (s_enter + d_rear) / V,
        "t_whole_car_left_span_s": (s_leave + e) / V,
        "t_needed_with_run_out_s": (a.lead_in_m + L + lt + e + a.run_out_m) / V,
        "t_end_s": t_end,
    }
    cov["steps_needed"] = int(math.ceil(cov["t_needed_with_run_out_s"] / run.dt_s - 1e-9))
    cov["leading_wheelset_crosses_span"] = t_end >= cov["t_leading_wheelset_leaves_span_s"]
    cov["whole_car_passes_span"] = t_end >= cov["t_whole_car_left_span_s"]
    notes = []
    if not cov["leading_wheelset_crosses_span"]:
        notes.append(f"the run ends at {t_end:.3f} s, before the leading wheelset has left the span "
                     f"({cov['t_leading_wheelset_leaves_span_s']:.3f} s); peak values may be missed")
    elif not cov["whole_car_passes_span"]:
        notes.append(f"the run ends at {t_end:.3f} s: the leading wheelset crosses the whole span (leaves at "
                     f"{cov['t_leading_wheelset_leaves_span_s']:.3f} s) but the trailing wheelset leaves it only at "
                     f"{cov['t_whole_car_left_span_s']:.3f} s ({cov['steps_needed']} steps needed with the run-out); "
                     "the rear-bogie car-body acceleration may not have peaked")
    elif t_end < cov["t_needed_with_run_out_s"]:
        notes.append(f"the whole car has left the span at {cov['t_whole_car_left_span_s']:.3f} s; the run-out of "
                     f"{a.run_out_m} m would need {cov['steps_needed']} steps")
    if case.speed_km_h > a.plant_max_speed_km_h:
        notes.append(f"speed {case.speed_km_h} km/h exceeds the plant's limit {a.plant_max_speed_km_h} km/h")
    return cov, notes


# ================================================================================================ running
def _case_peaks(ts: dict, dt: float, t_max: float | None = None) -> dict:
    """The case's peak values of the recorded rows with ``time_s <= t_max`` (all rows for ``None``): the per-column
    peaks of :func:`~.scenario.peaks` under the case's names, the flange-contact durations and the 10 ms
    moving-average peak of the lateral force."""
    if t_max is not None:
        keep = ts["time_s"] <= t_max + 1e-9
        ts = {k: v[keep] for k, v in ts.items()}
    t = ts["time_s"]
    if len(t) == 0:
        return {}
    p = peaks(ts)
    Y = p["lateral_contact_force_w1_right_N"]
    acc = p["carbody_lateral_acceleration_rear_m_s2"]
    Q = p["vertical_contact_force_w1_right_N"]
    fl = ts["flange_contact_w1_right"] > 0.5
    out = {
        "max_abs_lateral_contact_force_w1_right_N": Y["max_abs"],
        "lateral_contact_force_w1_right_at_peak_N": Y["value_at_max_abs"],
        "time_of_max_abs_lateral_force_s": Y["time_of_max_abs_s"],
        "max_abs_carbody_lateral_acceleration_rear_m_s2": acc["max_abs"],
        "time_of_max_carbody_acceleration_s": acc["time_of_max_abs_s"],
        "max_abs_carbody_lateral_accelerometer_rear_m_s2": p["carbody_lateral_accelerometer_rear_m_s2"]["max_abs"],
        "flange_contact_w1_right": bool(fl.any()),
        "flange_contact_w1_right_duration_s": float(fl.sum() * dt),
        "flange_contact_w1_right_first_time_s": float(t[fl][0]) if fl.any() else None,
        "flange_contact_w1_left": bool((ts["flange_contact_w1_left"] > 0.5).any()),
        "max_derailment_quotient_w1_right": p["derailment_quotient_w1_right"]["max"],
        "min_wheel_load_w1_right_N": Q["min"],
        "max_wheel_load_w1_right_N": Q["max"],
        "wheel_lift_w1_right_duration_s": float((ts["vertical_contact_force_w1_right_N"] <= 0.0).sum() * dt),
        "max_abs_wheelset1_lateral_rel_track_m": p["wheelset1_lateral_rel_track_m"]["max_abs"],
        "max_contact_angle_w1_right_rad": p["contact_angle_w1_right_rad"]["max"],
    }
    n = max(1, int(round(AVERAGE_WINDOW_S / dt)))
    y_raw = ts["lateral_contact_force_w1_right_N"]
    if len(y_raw) >= n:
        y_avg = np.convolve(y_raw, np.ones(n) / n, mode="valid")
        i = int(np.nanargmax(np.abs(y_avg)))
        out["max_abs_lateral_contact_force_w1_right_10ms_avg_N"] = float(abs(y_avg[i]))
        out["time_of_max_abs_lateral_force_10ms_avg_s"] = float(0.5 * (t[i] + t[i + n - 1]))
    out["max_abs_Y_any_wheel_N"] = max(v["max_abs"] for k, v in p.items() if k.startswith("Y_w"))
    out["min_Q_any_wheel_N"] = min(v["min"] for k, v in p.items() if k.startswith("Q_w"))
    return out


def _after_passage(ts: dict, t_passage_end: float) -> dict:
    """Motion left after the passage (the whole car off the span plus the run-out): a lateral oscillation of the
    leading wheelset that does not decay there is self-excited (hunting), not the response to the deviation."""
    t = ts["time_s"]
    keep = t > t_passage_end + 1e-9
    if not keep.any():
        return {"recorded": False}
    return {"recorded": True, "from_s": float(t_passage_end), "to_s": float(t[keep][-1]),
            "max_abs_wheelset1_lateral_rel_track_m":
                float(np.nanmax(np.abs(ts["wheelset1_lateral_rel_track_m"][keep]))),
            "max_abs_carbody_lateral_acceleration_rear_m_s2":
                float(np.nanmax(np.abs(ts["carbody_lateral_acceleration_rear_m_s2"][keep]))),
            "max_abs_lateral_contact_force_w1_right_N":
                float(np.nanmax(np.abs(ts["lateral_contact_force_w1_right_N"][keep]))),
            "min_wheel_load_w1_right_N": float(np.nanmin(ts["vertical_contact_force_w1_right_N"][keep]))}


def run_rtri(case: RtriCase, progress=None, view=None, progress_bar=False) -> RtriResult:
    """Build the case's spec (:meth:`RtriCase.scenario`, :func:`~.scenario.build_scenario`), warm up, run it
    through the one solve wrapper (timed: ``mbs.SolveDynamic`` only) and collect the outputs.  ``summary["status"]``
    is one of :data:`~exudyn_wheelrail.simulation.status.STATUSES` (``status_detail``: time, wheelset, side, the
    monitor's detail, a hint); the time series keep the rows up to the last valid state.  ``progress``: a callable
    for one line before the run (e.g. ``print``).  ``view``: an object with ``attach(model)`` (called with the built
    :class:`~.scenario.ScenarioModel` before the solve) and ``close()`` (after it), e.g.
    :class:`~exudyn_wheelrail.interactive.view3d.RtriView` (Exudyn's renderer).  ``progress_bar``: the run's
    progress bar, ``True`` on stderr or a stream to draw it on (:func:`~.scenario.run_model`); ``False``: none."""
    vehicle = case.vehicle()
    if vehicle.layout != "car" or vehicle.car_body is None:
        raise ValueError(f"vehicle {case.assumptions.vehicle!r}: the RTRI case needs a car (layout 'car')")
    # the car body's modes are damped: a solver without a stable interval on the imaginary axis (explicit midpoint,
    # RK67: growth per step ~ (ω h)⁴/8 resp. ~6e-4 (ω h)⁸, solvers.py) stays far below the modal damping's decay
    # 2 ζ ω h at the steps the car body allows, so only a finite limit is checked
    w = highest_mode_rad_s(vehicle)
    problem = (undamped_step_problem(case.run.solver, case.run.dt_s, w,
                                     f"the flexible car body's highest kept mode ({w / (2 * math.pi):.4g} Hz)",
                                     "take a smaller step, fewer modes or an implicit solver")
               if METHODS[case.run.solver].imaginary_axis_limit else None)
    if problem:                                           # before any work: the run would diverge
        raise ValueError(f"dt_s (--dt) with car_body={case.car_body!r}: {problem}")
    h = build_scenario(case.scenario())
    run = h.run
    if progress:
        progress(f"RTRI: span {case.span_m:g} m, {case.speed_km_h:g} km/h, {run.solver}, dt {run.dt_s:g} s, "
                 f"{run.duration_s:g} s ({run.steps} steps), {case.contact.wheel_rail}"
                 + (f", creep law {case.contact.creep_law}" if h.contact else ""))
    outcome = run_model(h, progress=progress_bar, view=view)
    status = outcome.status
    rec = h.recorder.table() if h.recorder is not None else {}
    ts = ({name: rec[col] for name, col in rtri_columns(len(h.model.wheelsets), case.carbody_points).items()}
          if rec else {})
    cov, notes = _coverage(case, vehicle, run)
    evaluate = bool(ts) and len(ts["time_s"]) > 0 and status.kind != S.DIVERGED
    after = _after_passage(ts, cov["t_needed_with_run_out_s"]) if evaluate else {}
    passage = _case_peaks(ts, run.dt_s, cov["t_needed_with_run_out_s"]) if evaluate else {}
    if after.get("recorded") and passage and (after["max_abs_wheelset1_lateral_rel_track_m"] >
                                              0.5 * passage["max_abs_wheelset1_lateral_rel_track_m"]):
        notes.append(f"after the passage (t > {after['from_s']:.3f} s) the leading wheelset still oscillates laterally "
                     f"by up to {after['max_abs_wheelset1_lateral_rel_track_m'] * 1e3:.2f} mm (passage peak "
                     f"{passage['max_abs_wheelset1_lateral_rel_track_m'] * 1e3:.2f} mm): a self-excited oscillation "
                     "(hunting / limit cycle), not the response to the deviation; whole-run peaks include it")
    if case.contact.wheel_rail == "springs":
        notes.append("wheel_rail = springs: cost baseline only (the deviation does not act on linear springs)")
    notes += outcome.warnings
    if status.kind != S.OK:
        notes.append(f"the run ended {status.kind} (status_detail): the time series hold the rows up to the last "
                     "valid state"
                     + ("; peaks not evaluated" if status.kind == S.DIVERGED else ""))
    table = case_assumptions_table(case)
    solve_seconds = outcome.solve_seconds
    sim_time = outcome.t_end_s
    summary = {
        "case": "RTRI rigid-rail validation case (Montenegro et al., Comput. Struct. 152 (2015) 200-214), "
                "SUBSTITUTE INPUTS: see 'assumptions'",
        "status": status.kind,
        "status_detail": status.as_dict(),
        "events": [{"kind": e.kind, "time_s": e.time_s, "wheelset": e.wheelset, "side": e.side, "detail": e.detail}
                   for e in outcome.events[:200]],
        "n_events": len(outcome.events),
        "solve_seconds": solve_seconds,
        "steps": run.steps,
        "dt_s": run.dt_s,
        "duration_s": run.end_time_s,
        "simulated_time_s": sim_time,
        "real_time_factor": sim_time / solve_seconds if solve_seconds > 0 else None,
        "rows_recorded": int(len(ts.get("time_s", []))),
        "rows_dropped_after_divergence": outcome.rows_dropped,
        "rejected_steps": outcome.rejected_steps,
        "contact_omega_rad_s": outcome.contact_omega_rad_s,
        "speed_km_h": float(case.speed_km_h),
        "speed_m_s": case.speed_m_s,
        "span_m": float(case.span_m),
        "deviation_amplitude_m": case.delta_m,
        "transition_length_m": case.transition_m,
        "deviation_start_m": case.span_deflection().start_m,
        "run_settings": run.as_dict(),
        "contact_settings": case.contact.as_dict(),
        "solver": {"name": run.solver, "exudyn": run.describe_solver()},
        "wheel_rail": case.contact.wheel_rail,
        "creep_law": case.contact.creep_law if case.contact.wheel_rail == "contact" else None,
        "geometry": h.contact.geometry_statistics() if h.contact is not None else None,
        "skipped": h.contact.skipped() if h.contact is not None else None,
        "fastsim_grid": list(case.contact.fastsim_grid),
        "contact_calls": int(h.contact.n_calls) if h.contact is not None else 0,
        "vehicle": vehicle.name,
        "car_body": _car_body_summary(case, h.model),
        "comfort": _comfort(ts, run.dt_s, case) if evaluate else {},
        "wheel_rail_pair": repr(h.pair),
        "coverage": cov,
        "notes": notes,
        "peak_windows": {"peaks": "the whole run",
                         "peaks_passage": "t <= coverage.t_needed_with_run_out_s (the whole car has left the span "
                                          "and run the run-out): the response to the deviation",
                         "after_passage": "t > coverage.t_needed_with_run_out_s (what is left: a self-excited "
                                          "oscillation if it does not decay)"},
        "peaks": _case_peaks(ts, run.dt_s) if evaluate else {},
        "peaks_passage": passage,
        "after_passage": after,
        "sign_conventions": {
            "lateral_contact_force_w1_right_N": "force of the rail ON the wheel, track y (+ = towards the right); "
                                                "a right-flange contact is negative. The paper's Fig. 6 likely "
                                                "plots the opposite sign (force on the rail)",
            "derailment_quotient_w1_right": "-Fy/Q: positive when the right flange presses on its rail",
            "carbody_lateral_acceleration_rear_m_s2": "track-frame y acceleration (no gravity) of the car-body "
                                                      "point above the rear bogie centre at floor level "
                                                      "(Exudyn rigid-body Acceleration output at that point)",
            "flange_contact_w1_right": "the wheel's flange region (beyond the throat split) carries a contact",
        },
        "assumptions": table,
    }
    return RtriResult(timeseries=ts, summary=summary, case=case, outcome=outcome)


def _car_body_summary(case: RtriCase, model) -> dict:
    """The car-body model of the run: rigid, or the flexible body's modes."""
    fb = getattr(model.car_body, "flexible", None)
    if fb is None:
        return {"model": "rigid"}
    m = fb.modes
    return {"model": case.car_body, "vehicle_file": case.vehicle_name,
            "modes": [{"kind": k, "frequency_Hz": float(f), "damping_ratio": float(z)}
                      for k, f, z in zip(m.kinds, m.frequencies_Hz, m.damping_ratio)]}


def _comfort(ts: dict, dt_s: float, case: RtriCase) -> dict:
    """Sperling's ride index Wz and the EN 14363 car-body quantities (0.4–10 Hz band-passed maximum and RMS) of every
    recorded car-body point over the whole run (:mod:`exudyn_wheelrail.analysis.comfort`): lateral from the
    accelerometer reading (what a floor sensor measures, g times the roll included), vertical from the kinematic
    acceleration (the accelerometer's constant -g removed) — the scenarios' convention."""
    out = {}
    for p in case.carbody_points:
        cols = {"lateral": f"carbody_lateral_accelerometer_{p}_m_s2",
                "vertical": f"carbody_vertical_acceleration_{p}_m_s2"}
        res = {}
        for d, c in cols.items():
            a = np.asarray(ts.get(c, []), dtype=float)
            if a.size < 2 or not np.all(np.isfinite(a)):
                continue
            try:
                en = carbody_acceleration_en14363(a, dt_s)
                res[d] = {"column": c, "sperling_Wz": float(sperling_index(a, dt_s, d)["Wz"]),
                          "en14363_peak_m_s2": en["peak_m_s2"], "en14363_rms_m_s2": en["rms_m_s2"],
                          "en14363_peak_near_record_edge": en["peak_near_record_edge"]}
            except ValueError as exc:                   # a record too short for the filters
                res[d] = {"column": c, "not_evaluated": str(exc)}
        out[p] = res
    return out


# ================================================================================================ outputs
def write_rtri_outputs(result: RtriResult, out_dir, plots: bool = True, figures: FigureProcess | None = None) -> dict:
    """Write ``timeseries.csv``, ``summary.json`` and (``plots``) the Fig. 5/6 PNGs into ``out_dir``; returns the
    paths.  ``figures``: a :class:`~.drawing.FigureProcess` of :mod:`.rtri_figures` started before the run (it
    draws the figures while the tables are written); ``None``: drawn here."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"timeseries": out / "timeseries.csv", "summary": out / "summary.json"}
    jobs = []
    if plots and result.timeseries and len(result.timeseries["time_s"]) > 1:
        paths["fig5"] = out / "fig5_carbody_acceleration.png"
        paths["fig6"] = out / "fig6_lateral_force.png"
        drawn = RtriResult(result.timeseries, result.summary)        # what the figures read
        jobs = [(plot_fig5, (drawn, paths["fig5"])), (plot_fig6, (drawn, paths["fig6"]))]
    figures = figures if figures is not None else FigureProcess.here()
    figures.draw(jobs)
    write_csv(paths["timeseries"], result.timeseries)
    write_json(paths["summary"], result.summary)
    figures.wait()
    return paths
