r"""Running a built scenario and evaluating it: :func:`run_model` (the one solve wrapper, watched by the run
monitor), :func:`run_scenario` (build, run, evaluate, write) and :func:`scenario_summary` (status, the wheel
unloading columns derived from Q, peaks, scalars, criteria, the deck's block (:func:`.deck.deck_summary`), notes:
the ``summary.json`` of :mod:`exudyn_wheelrail.scenarios.scenario`).
"""
from __future__ import annotations

import numpy as np

from ..simulation import status as S
from ..simulation.recorder import PROGRESS_MIN_STEPS, SIDES, ProgressBar
from ..simulation.runner import run
from ..track.layout import curve_quantities
from ..validation import output_dir
from .bridge_crossing_summary import crossing_result
from .build import ScenarioModel, build_scenario
from .criteria import running_criteria, train_criteria
from .curve_setup import CURVE_READ_M
from .deck import deck_scalars, deck_summary
from .flexible_track import flexible_track_summary
from .outputs import write_scenario_outputs
from .result import ScenarioResult
from .spec import TIMESERIES_GROUPS, UNLOADING_GROUP, as_scenario

__all__ = ["ScenarioResult", "peaks", "static_wheel_loads", "run_model", "run_scenario", "scenario_summary",
           "run_events", "layout_summary"]

# ScenarioResult is declared in .result (below the writer and the figures, which read it).

def peaks(ts: dict) -> dict:
    """Per recorded column (``time_s`` and ``s_leading_m`` aside): ``max_abs`` (with its signed value and its
    time), ``min``, ``max`` (NaN rows ignored)."""
    out = {}
    if not ts:
        return out
    t = ts["time_s"]
    for name, v in ts.items():
        if name in ("time_s", "s_leading_m") or len(v) == 0:
            continue
        if not np.isfinite(v).any():
            out[name] = {"max_abs": None, "value_at_max_abs": None, "time_of_max_abs_s": None, "min": None,
                         "max": None}
            continue
        i = int(np.nanargmax(np.abs(v)))
        out[name] = {"max_abs": float(abs(v[i])), "value_at_max_abs": float(v[i]), "time_of_max_abs_s": float(t[i]),
                     "min": float(np.nanmin(v)), "max": float(np.nanmax(v))}
    return out


def _scalars(ts: dict, groups: dict, pk: dict, criteria, dt: float, deck: dict | None) -> dict:
    """The flat dict of scalar results (what a sweep tabulates)."""
    out = {}
    if pk and ts and len(ts["time_s"]):
        def agg(fn, cols):
            vals = [fn(ts[c]) for c in cols if np.isfinite(ts[c]).any()]
            return float(max(vals)) if vals else None
        out["max_abs_Y_any_wheel_N"] = agg(lambda v: np.nanmax(np.abs(v)), groups["Y"])
        out["max_Q_any_wheel_N"] = agg(np.nanmax, groups["Q"])
        q_min = [float(np.nanmin(ts[c])) for c in groups["Q"]]
        out["min_Q_any_wheel_N"] = min(q_min) if q_min else None
        out["max_YQ_any_wheel"] = agg(np.nanmax, groups["YQ"])
        if groups.get(UNLOADING_GROUP):
            out["max_dQQ_any_wheel"] = agg(np.nanmax, groups[UNLOADING_GROUP])
        fl = np.array([ts[c] for c in groups["flange"]]) > 0.5
        out["flange_contact_any_wheel"] = bool(fl.any())
        out["flange_contact_duration_max_s"] = float(fl.sum(axis=1).max() * dt) if fl.size else 0.0
        out["max_abs_y_rel_any_wheelset_m"] = agg(lambda v: np.nanmax(np.abs(v)), groups["wheelset_lateral"])
        for name, p in pk.items():
            if not name.startswith("flange_"):
                out[f"max_abs_{name}"] = p["max_abs"]
    if isinstance(criteria, dict) and "verdicts" in criteria:
        out["criteria.safety_passed"] = criteria["safety_passed"]
        out["criteria.passed"] = criteria["passed"]
        for k, v in criteria["verdicts"].items():
            out[f"criteria.{k}.passed"] = v.get("passed")
            if "worst_value" in v:
                out[f"criteria.{k}.worst"] = v.get("worst")
                out[f"criteria.{k}.worst_value"] = v.get("worst_value")
                out[f"criteria.{k}.worst_utilisation"] = v.get("worst_utilisation")
        for k, v in criteria["criteria"].items():
            if k.startswith("carbody_"):
                out[f"criteria.{k}.peak_m_s2"] = v.get("peak_m_s2")
                out[f"criteria.{k}.rms_m_s2"] = v.get("rms_m_s2")
            elif k.startswith("sperling_"):
                out[f"criteria.{k}.Wz"] = v.get("Wz")
        after = [v["value_after_lowpass"] for v in criteria["criteria"]["wheel_unloading"].values()
                 if v.get("value_after_lowpass") is not None]
        if after:
            out["criteria.wheel_unloading.max_value_after_lowpass"] = max(after)
        for car in criteria.get("cars", []):                      # a train: every car's verdicts
            out[f"criteria.car{car['car']}.safety_passed"] = car["safety_passed"]
            out[f"criteria.car{car['car']}.passed"] = car["passed"]
    if deck is not None:
        out.update(deck_scalars(deck))
    return out


def _add_unloading(h: ScenarioModel, ts: dict, groups: dict) -> None:
    """The ``unloading`` group: ``dQQ_w<j>_<side>`` = (Q₀ − Q)/Q₀ of every recorded wheel load (the wheel
    unloading of :func:`~exudyn_wheelrail.analysis.safety.wheel_unloading`; Q₀ the static wheel load of the
    vehicle's load path)."""
    static = static_wheel_loads(h)
    cols = []
    for c in groups["Q"]:
        wheel = c[len("Q_"):-len("_N")]
        name = f"dQQ_{wheel}"
        ts[name] = (static[wheel] - ts[c]) / static[wheel]
        cols.append(name)
    groups[UNLOADING_GROUP] = cols


def _criteria(h: ScenarioModel, ts: dict, groups: dict) -> dict:
    """The running-safety and comfort criteria (:func:`~exudyn_wheelrail.analysis.safety.running_criteria_summary`)
    of the vehicle, or of a train (:func:`train_criteria`)."""
    o = h.scenario["outputs"]["criteria"]
    options = dict(vehicle=o["vehicle"], yq_limit=o["yq_limit"], unloading_limit=o["unloading_limit"])
    if _is_train(h):
        return train_criteria(h.model, ts, h.speed_m_s, static_wheel_loads(h), groups["Y"] + groups["Q"],
                              carbody_point=o["carbody_point"], **options)
    return running_criteria(ts, h.speed_m_s, groups["Y"] + groups["Q"], static_wheel_loads(h), o["carbody_point"],
                            **options)


def _is_train(h) -> bool:
    return "consist" in h.scenario["vehicle"]


def static_wheel_loads(h: ScenarioModel) -> dict:
    """``{"w<j>_<side>": Q0}``: the static wheel loads of the lever rule (a train: every car's, train order)."""
    wheel = h.model.static_wheel_loads_N() if _is_train(h) else h.model.load_path.wheel   # (n_ws, 2) (left, right)
    return {f"w{j + 1}_{side}": float(wheel[j, 0 if side == "left" else 1])
            for j in range(len(h.model.wheelsets)) for side in SIDES}


def run_model(h, *, progress=None, view=None, label: str = ""):
    """Warm up and run a built model (:class:`ScenarioModel`) through the one solve wrapper
    (:func:`exudyn_wheelrail.simulation.runner.run`); returns the :class:`~exudyn_wheelrail.simulation.runner.
    RunOutcome`.  ``progress``: ``None`` — the run settings' ``progress``; ``True``/``False``; or a stream for the
    bar (runs of at least :data:`~exudyn_wheelrail.simulation.recorder.PROGRESS_MIN_STEPS` steps).  ``view``: an
    object with ``attach(model)`` (before the solve) and ``close()`` (after it), e.g.
    :class:`~exudyn_wheelrail.interactive.view3d.RtriView` (not for a bridge crossing)."""
    if view is not None and h.crossing is not None:
        raise ValueError("view: a bridge crossing has no 3-D view")
    if view is not None:
        view.attach(h)
    if h.contact is not None:
        h.contact.warm_up(h.mbs, jacobian=h.run.implicit)
    show = h.run.progress if progress is None else progress
    bar = None
    if show and h.run.steps >= PROGRESS_MIN_STEPS:
        bar = ProgressBar(h.run.end_time_s, stream=show, label=label)
    try:
        outcome = run(h.mbs, h.run, h.contact, speed_m_s=h.speed_m_s, recorder=h.recorder, progress=bar,
                      exu_settings=(h.settings, h.solver_type), user_function=h.user_function)
    finally:
        if view is not None:
            view.close()
    if bar is not None:
        bar.close(outcome.status.kind)
    return outcome


def run_scenario(scenario, out_dir=None, progress=None, view=None, figures=None) -> ScenarioResult:
    """Build, solve and evaluate a scenario (a file path or a scenario dict); write the outputs into ``out_dir``
    (``None``: write nothing; checked before anything is built).  ``progress``, ``view``: :func:`run_model`.
    ``figures``: where the plots are drawn (:func:`~.outputs.write_scenario_outputs`).  The summary's ``status``
    is one of :data:`~exudyn_wheelrail.simulation.status.STATUSES`.  A bridge crossing (``vehicle.load_model``,
    :mod:`.spec_crossing`) goes the same way: built by :func:`~.build.build_crossing` (its deck of N modes per
    span, its load model), evaluated by :func:`~.bridge_crossing_summary.crossing_result` (its columns and summary),
    written without figures."""
    scn, source = as_scenario(scenario)
    if out_dir is not None:
        output_dir("out_dir", out_dir)
    h = build_scenario(scn)
    outcome = run_model(h, progress=progress, view=view, label=f"{scn['scenario']['name']}: ")
    result = scenario_summary(h, outcome, source)
    if out_dir is not None:
        result.paths = write_scenario_outputs(result, out_dir, figures=figures)
    return result


def run_events(outcome, limit: int = 200, car_of_wheelset=None) -> list:
    """The monitor's events (the first ``limit``) as plain dicts; for a train also the ``car`` (1 = leading) of the
    event's wheelset (``car_of_wheelset``: 0-based car per 0-based wheelset; the monitor numbers the train's
    wheelsets from 0)."""
    out = []
    for e in outcome.events[:limit]:
        d = {"kind": e.kind, "time_s": e.time_s, "wheelset": e.wheelset, "side": e.side, "detail": e.detail}
        if car_of_wheelset is not None:
            d["car"] = car_of_wheelset[e.wheelset] + 1 if e.wheelset is not None else None
        out.append(d)
    return out


def _flexible_track_summary(h: ScenarioModel):
    if h.flexible_track is None:
        return None
    return flexible_track_summary(h.flexible_track.modes, h.flexible_window)


def scenario_summary(h: ScenarioModel, outcome, source: str | None = None) -> ScenarioResult:
    """The :class:`ScenarioResult` of a run: the recorded time series and the summary (module docstring; a bridge
    crossing's: :func:`~.bridge_crossing_summary.crossing_result`)."""
    if h.crossing is not None:
        return crossing_result(h, outcome)
    scn = h.scenario
    run = h.run
    status = outcome.status
    rec = h.recorder
    ts = rec.table() if rec is not None else {}
    groups = {g: cols for g, cols in (rec.groups.items() if rec is not None else []) if g in TIMESERIES_GROUPS}
    if groups.get("Q"):
        _add_unloading(h, ts, groups)
    notes = _notes(h, outcome)
    evaluate = status.kind != S.DIVERGED and bool(ts) and len(ts["time_s"]) > 0
    deck = None
    if evaluate and groups.get("deck_acceleration"):
        deck, deck_notes = deck_summary(h, ts)
        notes += deck_notes
    criteria = None
    if scn["outputs"]["criteria"]["enabled"] and rec is not None:
        if not evaluate:
            criteria = {"error": f"not evaluated: the run {status.kind}"}
        else:
            try:
                criteria = _criteria(h, ts, groups)
            except ValueError as exc:
                criteria = {"error": str(exc)}
                notes.append(f"criteria not evaluated: {exc}")
    pk = peaks(ts) if evaluate else {}
    dt = float(run.dt_s)
    t_end = run.end_time_s
    sim_time = outcome.t_end_s
    summary = {
        "scenario_name": scn["scenario"]["name"],
        "scenario_file": source,
        "status": status.kind,
        "status_detail": status.as_dict(),
        "events": run_events(outcome, car_of_wheelset=h.model.car_of_wheelset if _is_train(h) else None),
        "n_events": len(outcome.events),
        "steps": run.steps,
        "dt_s": dt,
        "duration_s": t_end,
        "simulated_time_s": sim_time,
        "solve_seconds": outcome.solve_seconds,
        "real_time_factor": sim_time / outcome.solve_seconds if outcome.solve_seconds > 0 else None,
        "rows_recorded": int(len(ts["time_s"])) if ts else 0,
        "rows_dropped_after_divergence": outcome.rows_dropped,
        "rejected_steps": outcome.rejected_steps,
        "contact_omega_rad_s": outcome.contact_omega_rad_s,
        "speed_m_s": h.speed_m_s,
        "run_settings": run.as_dict(),
        "solver": {"name": run.solver, "exudyn": run.describe_solver()},
        "contact_calls": int(h.contact.n_calls) if h.contact is not None else 0,
        "geometry": h.contact.geometry_statistics() if h.contact is not None else None,
        "skipped": h.contact.skipped() if h.contact is not None else None,
        "coverage": {**h.coverage, "t_end_s": t_end,
                     "passage_covered": None if h.coverage["t_passage_s"] is None
                     else bool(t_end >= h.coverage["t_passage_s"] - 1e-9)},
        "model": _model_info(h),
        "columns": {g: list(cols) for g, cols in groups.items() if cols},
        "written_groups": list(scn["outputs"]["timeseries"]),
        "peaks": pk,
        "scalars": _scalars(ts, groups, pk, criteria, dt, deck),
        "criteria": criteria,
        "deck": deck,
        "flexible_track": _flexible_track_summary(h),
        "notes": notes,
        "sign_conventions": {
            "Y": "Y_w<j>_<side>_N: track-frame y component (+ right) of the contact force of the rail on the wheel",
            "Q": "Q_w<j>_<side>_N: wheel load, -F_z of the force on the wheel (z down): positive pressing",
            "YQ": "YQ_w<j>_<side>: Y positive towards the wheel's field side (-F_y right, +F_y left) over Q; NaN "
                  "when lifted",
            "wheelset_lateral": "y_rel_w<j>_m: axle centre relative to the rails' centre line at rail top, + right",
            "track": "track_<lateral|vertical>_w<j>_m: track irregularity under wheelset j (y right, z down)",
            "carbody": "acceleration: track frame (y right, z down), no gravity; accelerometer: a - g in the car "
                       "body's axes; displacement: track frame",
            "deck": "vertical, + down, mid-span on the track centre line at rail-top level",
            "unloading": "dQQ_w<j>_<side>: (Q0 - Q)/Q0, Q0 the static wheel load: positive when the wheel is unloaded",
            "deck_acceleration": "deck_acceleration_s<i>_p<k>_m_s2: vertical (+ down) at x = k L/10 of span i, on the "
                                 "track centre line",
            "deck_wheelsets": "deck_deflection_w<j>_m: vertical deflection (+ down) of the deck under wheelset j, 0 "
                              "off the deck",
            "deck_lateral": "deck_mid_lateral_rel_s<i>_m: lateral (+ right) at mid-span relative to the supports; "
                            "deck_mid_lateral_acceleration_s<i>_m_s2: absolute lateral acceleration; ground_lateral_*: "
                            "the ground (support) motion",
        },
        "scenario": scn,
    }
    if h.layout is not None:
        summary["layout"] = layout_summary(h)
        summary["sign_conventions"]["curving"] = (
            "yaw_w<j>_rad: yaw of wheelset j relative to its local track frame (z down: + turns it to the right); "
            "curvature_w<j>_1_m: the layout's curvature under wheelset j (+ right-hand curve); guidance_lateral_N "
            "(bogie and wheelset layouts): track-frame y force of the guidance elements on the bodies")
    return ScenarioResult(timeseries=ts, summary=summary, outcome=outcome)


def layout_summary(h: ScenarioModel) -> dict:
    """The curve of a scenario with a ``[layout]``: its input (normal form), where the circular curve starts, and at
    the run's speed its cant angle, balance speed and unbalanced lateral acceleration a_nc (track plane, positive
    outwards; :func:`~exudyn_wheelrail.track.layout.curve_quantities`, read :data:`~.curve_setup.CURVE_READ_M` into
    the circular curve as the ``curving`` command does) with the mass of the modelled bodies times a_nc — the
    steady-curving balance of the wheelsets' ΣY and the guidance elements' force (the ``curving`` command's
    ``force_balance``, :mod:`exudyn_wheelrail.analysis.curving`: for the bogie and wheelset layouts the carried dead
    load's lateral inertia is held by the moving frame, not by the wheels)."""
    lay = h.scenario["layout"]
    curve_start = lay["start_m"] + lay["transition_m"]
    g = h.model.gravity_m_s2
    q = curve_quantities(h.layout, lay["radius_m"], lay["cant_m"], curve_start + CURVE_READ_M, h.speed_m_s, g)
    mass = float(h.vehicle.total_mass_kg)
    return {**lay, "curve_start_m": curve_start, "speed_km_h": h.scenario["vehicle"]["speed_km_h"], **q,
            "vehicle_mass_kg": mass, "m_a_nc_N": mass * q["unbalanced_lateral_acceleration_m_s2"],
            "balance": "in the steady curve the wheelsets' sum of Y plus guidance_lateral_N (the guidance elements "
                       "of the bogie and wheelset layouts; none for a car) is m_a_nc_N"}


def _model_info(h: ScenarioModel) -> dict:
    train = _is_train(h)
    info = {"vehicle": h.vehicle.name, "layout": "train" if train else h.vehicle.layout,
            "n_wheelsets": len(h.model.wheelsets), "wheelset_x_m": [float(x) for x in h.vehicle.wheelset_x_m()],
            "frame_s_start_m": float(h.model.s_start_m), "wheel_rail_pair": repr(h.pair),
            "static_wheel_loads_N": static_wheel_loads(h), "bridge": None}
    if train:
        info["cars"] = [{"car": k + 1, "vehicle": car.vehicle.name, "x_m": float(x),
                         "length_m": h.vehicle.cars[k].length_m,
                         "wheelsets": [j + 1 for j in h.model.wheelset_range(k)]}
                        for k, (car, x) in enumerate(zip(h.model.cars, h.model.car_x_m))]
        info["consist"] = {"name": h.vehicle.name, "file": h.vehicle.file, "source": h.vehicle.source,
                           "gap_m": h.vehicle.gap_m, "coupling": dict(h.vehicle.coupling.__dict__),
                           "total_mass_kg": h.vehicle.total_mass_kg, "length_m": h.vehicle.length_m}
    if h.modes is not None:
        info["bridge"] = {"n_modes": int(h.modes.n_modes), "f_cut_Hz": h.f_cut_Hz,
                          "frequencies_Hz": [float(f) for f in h.modes.frequencies_Hz], "kinds": list(h.modes.kinds),
                          "formulation": h.scenario["structure"]["formulation"]}
    return info


def _notes(h: ScenarioModel, outcome) -> list:
    notes = []
    cov = h.coverage
    t_end = h.run.end_time_s
    if cov["t_passage_s"] is not None and not cov["duration_auto"] and t_end < cov["t_passage_s"] - 1e-9:
        notes.append(f"the run ends at {t_end:.3f} s, before the trailing wheelset is run_out_m past the last track "
                     f"feature ({cov['t_passage_s']:.3f} s; duration_s = 'auto' runs that long)")
    x0 = np.asarray(h.model.track_distance_m(np.array([ws.p_cg_in_frame[0] for ws in h.model.wheelsets]), 0.0))
    if "structure" in h.scenario:
        st = h.scenario["structure"]
        end = st["start_m"] + sum(st["spans_m"])
        if np.any((x0 > st["start_m"]) & (x0 < end)):
            notes.append("a wheelset stands on the deck at t = 0: the unloaded deck starts with the vehicle's "
                         "weight on it (free vibration transient); start the vehicle off the deck")
    if h.start_shift is not None:
        notes.append(f"the track is displaced by up to {h.start_shift * 1e3:.3g} mm under the wheelsets at t = 0: the "
                     "bodies start on it (wheelsets moved and yawed with the track under them, bogie frames and car "
                     "body along the line through their supports, with the matching rates); the suspensions carry "
                     "what the track's curvature leaves over, so the run may start with a small transient")
    if h.contact_settings.wheel_rail == "springs":
        notes.append("contact.wheel_rail = springs: cost baseline only (the irregularities do not act on linear "
                     "springs; nothing is recorded or watched)")
    notes += outcome.warnings
    status = outcome.status
    if status.kind != S.OK:
        notes.append(f"the run ended {status.kind} (status_detail): the time series hold the rows recorded up to the "
                     "last valid state"
                     + (f" ({outcome.rows_dropped} rows after the first step beyond the stability limit dropped)"
                        if outcome.rows_dropped else "")
                     + ("; peaks not evaluated" if status.kind == S.DIVERGED else ""))
    return notes

