"""The bridge crossing's evaluation: the deck's run status (:func:`deck_status`, with the deflection bound no stable
integration can reach), the EN 1990 A2 deck-acceleration check and the contents of ``summary.json``
(:func:`crossing_summary`, :data:`SUMMARY_KEYS`), the result of a run (:func:`crossing_result`)."""
from __future__ import annotations

import numpy as np

from ..conventions import speed_km_h
from ..simulation import status as S
from ..structures.load_models import (characteristic_spacing_m, resonance_speeds_m_s,
                                      simply_supported_frequencies_Hz)
from .bridge_crossing_case import MAX_DEFAULT_DT_S, default_dt_s
from .bridge_crossing_probes import DECK_COLUMNS, LATERAL_COLUMNS, SPAN_COLUMNS, SPAN_LATERAL_COLUMNS, deck_columns
from .deck import EN1990_DECK_ACCELERATION_LIMITS_M_S2
from .defaults import LATERAL_EI_RATIO, STEPS_PER_PERIOD
from .result import ScenarioResult

__all__ = ["SUMMARY_KEYS", "DEFLECTION_BOUND_MARGIN", "deflection_bound_m", "midspan_displacement_columns",
           "deck_status", "crossing_summary", "deck_description", "crossing_scalars", "crossing_result"]

#: keys every summary.json has (the command-line contract)
SUMMARY_KEYS = ("status", "max_abs_deck_midspan_displacement_m", "max_abs_deck_midspan_acceleration_m_s2",
                "solve_seconds", "simulated_seconds")


def _max_abs(v):
    v = np.asarray(v, dtype=float)
    return float(np.max(np.abs(v))) if v.size and np.all(np.isfinite(v)) else None


#: margin of the deflection bound of :func:`deflection_bound_m` (the loads of a vehicle model vary about their
#: static values)
DEFLECTION_BOUND_MARGIN = 10.0


def deflection_bound_m(modes, case, handle, t_end_s) -> float:
    """An upper bound of the mid-span deflection of the integrated deck: from Duhamel's integral, a mode driven by
    ``|Q_j| ≤ Q̄_j`` from rest has ``|q_j(t)| ≤ Q̄_j t/ω_dj``; ``Q̄_j = Σ_k |P_k| max_x |φ_j(x)|`` (static axle
    loads); times :data:`DEFLECTION_BOUND_MARGIN`."""
    x0, L = case.deck_start_m, case.length_m
    phi = np.abs(modes.shape_at(x0 + L * np.linspace(0.0, 1.0, 200 * case.n_spans + 1))[:, 1, :])    # (201 K, n)
    q_bar = np.sum(np.abs(handle.axle_load_N)) * phi.max(axis=0)
    wd = modes.omega_rad_s * np.sqrt(1.0 - modes.damping_ratio ** 2)
    phi_mid = np.max([np.abs(modes.shape_at(case.span_start_m(k) + 0.5 * case.chain_m[k])[1])
                      for k in range(case.n_spans)], axis=0)
    return DEFLECTION_BOUND_MARGIN * float(np.sum(phi_mid * q_bar * t_end_s / wd))


def midspan_displacement_columns(case) -> tuple:
    """The mid-span displacement columns the deflection bound applies to: the first span's and every span's of a
    chain."""
    return ("deck_midspan_displacement_m",) + tuple(SPAN_COLUMNS[0].format(k=k + 1) for k in range(case.n_spans)
                                                    if case.n_spans > 1)


def deck_status(status, ts, bound_m, columns=DECK_COLUMNS, midspan_columns=("deck_midspan_displacement_m",)):
    """The run's status, ``diverged`` when a deck value is not finite or a mid-span deflection exceeds the bound
    no stable integration can reach (:func:`deflection_bound_m`): an unstable integration of the deck's modes (the
    runner watches wheel–rail contacts, not the deck)."""
    if status.kind != S.OK or not ts:
        return status
    bad = np.zeros(len(ts["time_s"]), dtype=bool)
    for c in midspan_columns:
        bad |= np.abs(ts[c]) > bound_m
    for c in columns:
        bad |= ~np.isfinite(ts[c])
    if not bad.any():
        return status
    t_bad = float(ts["time_s"][int(np.argmax(bad))])
    return S.RunStatus(S.DIVERGED, time_s=t_bad,
                       detail=f"the deck state is not finite or the mid-span deflection exceeds {bound_m:.3g} m, more "
                              "than the loads can cause: the integration of the deck's modes is unstable",
                       hint="reduce --dt or keep fewer modes (--modes)")


def _en1990(case, f_Hz, cutoff, reach, peak) -> dict:
    """The EN 1990 A2 deck-acceleration check of one span: ``f_Hz`` its vertical frequencies, ``peak`` the largest
    ``|a|`` over its check points with the modes up to ``cutoff``."""
    limit = EN1990_DECK_ACCELERATION_LIMITS_M_S2[case.track_form]
    limits = ", ".join(f"{v:g} m/s2 {k.replace('_', ' ')}" for k, v in EN1990_DECK_ACCELERATION_LIMITS_M_S2.items())
    judged = peak is not None and reach
    return {"rule": "EN 1990:2002/A1:2005 A2.4.4.2.1(4)P: peak vertical deck acceleration over x = L/10 ... 9L/10, "
                    f"modes up to max(30 Hz, 1.5 f1, f3); limits {limits}; the peak is that of the modal "
                    "accelerations of the modes kept up to the cut-off, unfiltered (with the vehicles model it "
                    "includes the wheel-rail forces' content above the cut-off: on the safe side)",
            "cutoff_Hz": cutoff, "modes_used": int(np.sum(f_Hz <= 1.01 * cutoff)), "modes_reach_cutoff": reach,
            "peak_acceleration_m_s2": peak, "track_form": case.track_form, "limit_m_s2": limit,
            "limits_m_s2": dict(EN1990_DECK_ACCELERATION_LIMITS_M_S2),
            "passed": bool(peak <= limit) if judged else None,
            "not_evaluated": (None if judged else "the modes kept do not reach the cut-off frequency" if
                              peak is not None else "no peak (the run did not complete)"),
            "utilisation": None if peak is None else peak / limit}


def _spans_summary(case, deck, cutoffs, ts, ok, spacing) -> list:
    """One entry per span of a chain: its place, frequencies, resonance speeds ``f1_k d/i``, peaks and EN 1990
    check."""
    out = []
    for k in range(case.n_spans):
        f = deck.modes.frequencies_Hz[deck.vertical[k]]
        col = [c.format(k=k + 1) for c in SPAN_COLUMNS]
        reach = deck.reaches_cutoff(k)
        entry = {"span": k + 1, "span_m": case.chain_m[k], "start_m": case.span_start_m(k),
                 "f1_Hz": deck.f1_Hz[k], "frequencies_Hz": [float(x) for x in f],
                 "resonance_speeds_km_h": ([] if spacing is None else
                                           [speed_km_h(v) for v in resonance_speeds_m_s(deck.f1_Hz[k], spacing)]),
                 "max_abs_midspan_displacement_m": _max_abs(ts[col[0]]) if ok else None,
                 "max_abs_midspan_acceleration_m_s2": _max_abs(ts[col[1]]) if ok else None,
                 "EN1990_A2_deck_acceleration": _en1990(case, f, cutoffs[k], reach, _max_abs(ts[col[2]]))
                 if ok else None}
        if case.lateral_modes:
            lat = [c.format(k=k + 1) for c in SPAN_LATERAL_COLUMNS]
            entry.update({"lateral_frequencies_Hz": [float(x) for x in deck.modes.frequencies_Hz[deck.lateral[k]]],
                          "max_abs_lateral_midspan_displacement_m": _max_abs(ts[lat[0]]) if ok else None,
                          "max_abs_lateral_midspan_acceleration_m_s2": _max_abs(ts[lat[1]]) if ok else None})
        out.append(entry)
    return out


def crossing_summary(case, deck, cutoffs, handle, settings, outcome, ts, build_seconds, status) -> dict:
    """The contents of ``summary.json`` (:mod:`~exudyn_wheelrail.scenarios.bridge_crossing` docstring, *Outputs*)
    of a run: ``deck`` its modes (:func:`~.bridge_crossing_deck.deck_modes`), ``cutoffs`` the EN 1990 cut-off of
    every span, ``handle`` the load model's, ``ts`` the recorded table, ``status`` the deck's run status."""
    ok = status.kind == S.OK and len(ts.get("time_s", ())) > 0
    sim = float(outcome.t_end_s)
    axle_x = np.asarray(handle.axle_x_m, dtype=float)
    spacing = characteristic_spacing_m(axle_x) if case.axles is None else case.axles.spacing_m
    cutoff = cutoffs[0]
    f_first = deck.modes.frequencies_Hz[deck.vertical[0]]                 # the first span's vertical modes
    f1_fe = float(f_first[0])
    res = []
    if spacing is not None:
        for i, v in enumerate(resonance_speeds_m_s(deck.f1_Hz[0], spacing), 1):
            res.append({"i": i, "speed_m_s": v, "speed_km_h": speed_km_h(v)})
    notes = []
    en = None
    reach = deck.reaches_cutoff(0)
    if not reach:
        notes.append(f"the {case.n_modes} modes kept end at {f_first[-1]:.4g} Hz, below the EN 1990 "
                     f"cut-off {cutoff:.4g} Hz: keep more modes (--modes) for the deck-acceleration check")
    if ok:
        en = _en1990(case, f_first, cutoff, reach, _max_abs(ts["deck_en1990_max_abs_acceleration_m_s2"]))
    else:
        notes.append(f"the run {status.kind}: peaks and the EN 1990 check are not evaluated")
    if res:
        near = min(res, key=lambda r: abs(r["speed_m_s"] - case.speed_m_s))
        if abs(near["speed_m_s"] / case.speed_m_s - 1.0) < 0.02:
            notes.append(f"the speed is within 2 % of the resonance speed v_{near['i']} = f1 d/{near['i']} = "
                         f"{near['speed_km_h']:.4g} km/h")
    notes += list(outcome.warnings)
    frac_cycle = (case.f_N_Hz * float(settings.dt_s))
    if case.dt_s is not None and frac_cycle > 1.0 / 10.0:
        notes.append(f"dt = {settings.dt_s:g} s has {1.0 / frac_cycle:.3g} steps per period of mode {case.n_modes} "
                     f"({case.f_N_Hz:g} Hz): its acceleration is not resolved (default dt {default_dt_s(case):.3g} s)")
    peaks = {}
    quasi_static = None
    if ok:
        for c in deck_columns(case):
            peaks[f"max_abs_{c}"] = _max_abs(ts[c])
        w_st = _max_abs(ts["deck_midspan_static_displacement_m"])
        quasi_static = {"rule": ("the static response of the modes kept at the first span's middle, sum_j phi_j(x_m) "
                                 "sum_k P_k phi_j(s_k) / omega_j^2" if case.global_modes else
                                 "mid-span influence line of the static axle loads, P a (3L^2 - 4a^2)/(48 EI)"),
                        "max_midspan_displacement_m": w_st,
                        "dynamic_amplification": (peaks["max_abs_deck_midspan_displacement_m"] / w_st
                                                  if w_st else None)}
    extra = None
    if handle.summary is not None:
        extra = handle.summary(ts) if ok else {"error": f"not evaluated: the run {status.kind}"}
    out = {
        "status": status.kind,
        "status_detail": status.as_dict(),
        "max_abs_deck_midspan_displacement_m": peaks.get("max_abs_deck_midspan_displacement_m"),
        "max_abs_deck_midspan_acceleration_m_s2": peaks.get("max_abs_deck_midspan_acceleration_m_s2"),
        "solve_seconds": outcome.solve_seconds,
        "simulated_seconds": sim,
        "real_time_factor": sim / outcome.solve_seconds if outcome.solve_seconds > 0 else None,
        "build_seconds": build_seconds,
        "steps": settings.steps,
        "dt_s": float(settings.dt_s),
        "dt_rule": (f"min(1/({STEPS_PER_PERIOD} f_N), 2L/({STEPS_PER_PERIOD} N V), {MAX_DEFAULT_DT_S:g} s"
                    + (f", the load model's {handle.max_dt_s:g} s" if handle.max_dt_s is not None else "") + ")"
                    if case.dt_s is None else "given"),
        "duration_s": settings.end_time_s,
        "t_last_axle_leaves_s": (float(axle_x[-1]) + case.length_m) / case.speed_m_s,
        "rejected_steps": outcome.rejected_steps,
        "solver": {"name": settings.solver, "exudyn": settings.describe_solver()},
        "inputs": case.as_dict(),
        "load_model": {"name": case.model, "description": handle.description, "n_axles": int(axle_x.size),
                       "axle_x_m": axle_x, "axle_load_N": np.asarray(handle.axle_load_N, dtype=float),
                       **({"details": extra} if extra is not None else {})},
        "EI_Nm2": case.EI_Nm2,
        "deck": deck_description(case, deck),
        "frequencies_Hz": [float(f) for f in f_first],
        "frequencies_euler_bernoulli_Hz": (None if case.global_modes else
                                           simply_supported_frequencies_Hz(case.f1_Hz, case.n_modes).tolist()),
        "f1_fe_relative_error": None if case.global_modes else f1_fe / case.f1_Hz - 1.0,
        "characteristic_spacing_m": spacing,
        "resonance_speeds": res,
        "EN1990_A2_deck_acceleration": en,
        "quasi_static": quasi_static,
        "peaks": peaks,
        "sign_conventions": {"deck": "vertical displacement, velocity and acceleration positive downward (z down); "
                                     "support rotations dw/dx (x along the span from the first support)",
                             "x_first_axle_m": "deck coordinate of the first axle, V t"},
        "notes": notes,
    }
    if case.lateral_modes:
        f_lat = deck.modes.frequencies_Hz[deck.lateral[0]]
        for c in LATERAL_COLUMNS:
            out[f"max_abs_{c}"] = peaks.get(f"max_abs_{c}")
        out["lateral"] = {"n_modes": case.lateral_modes, "EI_z_Nm2": case.EI_z_Nm2,
                          "lateral_f1_Hz": case.span_lateral_f1_Hz(0),
                          "EI_z_rule": ("from --lateral-frequency-hz on the first span"
                                        if case.lateral_f1_Hz is not None else f"EI_z = {LATERAL_EI_RATIO:g} EI_y"),
                          "frequencies_Hz": [float(f) for f in f_lat],
                          "sign": "lateral displacement and acceleration along the track's y axis"}
    if case.n_spans > 1:
        out["spans"] = _spans_summary(case, deck, cutoffs, ts, ok, spacing)
        checks = [sp["EN1990_A2_deck_acceleration"] for sp in out["spans"]]
        out["EN1990_A2_all_spans_passed"] = (None if not ok or any(c is None or c["passed"] is None for c in checks)
                                             else all(c["passed"] for c in checks))
    out["scalars"] = crossing_scalars(out)
    return out


def deck_description(case, deck) -> dict:
    """What the deck is (``summary.json``'s ``deck``): its kind, where its modes come from, every mode's frequency
    and kind, the resonances' first frequency and the EN 1990 cut-off."""
    kind = ("modes file" if case.modes_file is not None else "continuous beam" if case.continuous
            else "simply supported spans")
    out = {"kind": kind, "spans_m": list(case.chain_m), "f1_Hz": deck.f1_Hz[0], "en1990_cutoff_Hz": deck.cutoffs_Hz[0],
           "modes": [{"frequency_Hz": float(f), "kind": k, "damping_ratio": float(z)}
                     for f, k, z in zip(deck.modes.frequencies_Hz, deck.modes.kinds, deck.modes.damping_ratio)]}
    if case.modes_file is not None:
        out.update({"modes_file": case.modes_file, "mass_scale": case.mass_scale,
                    "mass_scale_rule": "every mass scaled by r with the stiffness kept: omega_j / sqrt(r), modal "
                                       "masses r m_j, the same shapes",
                    "interpolation": "cubic splines between the file's positions (not-a-knot, broken at the "
                                     "supports), torsion linear"})
    return out


def crossing_scalars(summary: dict) -> dict:
    """The flat dict of a crossing's scalar results (what a scenario sweep tabulates; empty for a run that did not
    end ``ok``): every peak ``max_abs_<column>`` of the deck's columns (``max_abs_deck_midspan_*`` the first span's,
    ``max_abs_deck_span<k>_*`` each span's of a chain) and, named as a scenario's deck scalars
    (:func:`~.deck.deck_scalars`, the largest over the spans), ``deck.en1990_peak_acceleration_m_s2``,
    ``deck.en1990_passed`` (every span; None where the modes kept do not reach the cut-off),
    ``deck.max_mid_span_deflection_m`` and, for a single span (the quasi-static deflection is the first span's),
    ``deck.dynamic_amplification_mid_span``; with the vehicles model its running criteria ``criteria.passed`` and
    ``criteria.safety_passed``."""
    if summary["status"] != S.OK or not summary["peaks"]:
        return {}
    out = dict(summary["peaks"])
    if "spans" in summary:
        spans = summary["spans"]
        out["deck.en1990_peak_acceleration_m_s2"] = max(sp["EN1990_A2_deck_acceleration"]["peak_acceleration_m_s2"]
                                                        for sp in spans)
        out["deck.en1990_passed"] = summary["EN1990_A2_all_spans_passed"]
        out["deck.max_mid_span_deflection_m"] = max(sp["max_abs_midspan_displacement_m"] for sp in spans)
    else:
        en = summary["EN1990_A2_deck_acceleration"]
        out["deck.en1990_peak_acceleration_m_s2"] = en["peak_acceleration_m_s2"]
        out["deck.en1990_passed"] = en["passed"]
        out["deck.max_mid_span_deflection_m"] = summary["max_abs_deck_midspan_displacement_m"]
        out["deck.dynamic_amplification_mid_span"] = summary["quasi_static"]["dynamic_amplification"]
    criteria = summary["load_model"].get("details", {}).get("criteria") or {}
    for k in ("passed", "safety_passed"):
        if k in criteria:
            out[f"criteria.{k}"] = criteria[k]
    return out


def crossing_result(h, outcome) -> ScenarioResult:
    """The :class:`~.result.ScenarioResult` of a crossing's run (``crossing`` set): ``h`` the built model
    (:func:`~.build.build_crossing`, its parts in ``h.crossing``), ``outcome`` the runner's; the recorded table, the
    deck's run status (:func:`deck_status`) and the summary (:func:`crossing_summary`)."""
    c = h.crossing
    ts = h.recorder.table()
    status = deck_status(outcome.status, ts, deflection_bound_m(h.modes, c.case, c.load, h.run.end_time_s),
                         deck_columns(c.case), midspan_displacement_columns(c.case))
    summary = crossing_summary(c.case, c.deck, c.cutoffs, c.load, h.run, outcome, ts, c.build_seconds, status)
    return ScenarioResult(timeseries=ts, summary=summary, outcome=outcome, crossing=True)
