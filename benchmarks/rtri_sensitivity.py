"""RTRI case: how robust is the 20 m flange-contact finding to the ASSUMED deviation amplitude δ and transition l_t?

The paper's headline finding (Montenegro et al. 2015, rigid rail): the 20 m span gives a flange impact and a much
higher lateral contact force than the 40 m span, which has no flange contact.  Our case uses unpublished,
assumed values δ = 10 mm and l_t = 3 m (``scenarios/rtri_assumptions.py``).  This script sweeps them.

Per case (span 20 m and 40 m, 250 km/h, the *short* run of ``tests/test_rtri.py``: lead-in, span with its
transitions, run-out of the leading wheelset, no more):

* ``max_y_rel_mm``: the largest |lateral displacement of wheelset 1 relative to the deviated track|
  (``summary["peaks"]["max_abs_wheelset1_lateral_rel_track_m"]``);
* ``margin_mm = max_y_rel_mm - y_jump_mm``: how far beyond (> 0) or short of (< 0) the quasi-static contact jump to
  the flange flank the wheelset went.  ``y_jump_mm`` is computed here with the package's rigid contact-geometry
  sweep (:func:`exudyn_wheelrail.analysis.geometry_functions.contact_geometry_sweep`) of the vehicle's pair
  (S1002 / UIC60 1:40, gauge 1.435, back-to-back 1.360): the smallest shift at which the deepest point of the
  right wheel lies in the flange region, bracketed by bisection to ``JUMP_TOL_M``;
* flange contact of w1 right (``flange_contact_w1_right``: the flange region carries load) and its duration, the
  largest contact angle of w1 right, the raw and the 10 ms-averaged peak |Y| of w1 right, and per (δ, l_t,
  scheme) the 20 m / 40 m ratio of both.

Schemes: ``newmark_1ms`` (the paper's: Newmark β 1/4, γ 1/2, 1 ms) on the whole grid; ``rk44_1ms`` (the
``default`` preset: RK44, 1 ms, online geometry, exact-theory creep table) and ``newmark_0.5ms`` on the
``--check-deltas`` x ``--check-lts`` sub-grid (default: the whole grid), to see whether the yes/no
answer is converged in the integrator and the step.

Steps of a short run: ``ceil((lead_in + L + l_t + run_out) / V / 1 ms) * (1 ms / dt)`` — the tests' ``short_steps``
with the case's own l_t (the same as the tests for l_t = 3 m; for l_t = 6 m the run-out after the deviation stays
10 m), times two at 0.5 ms as the tests' ``fine_run``.

The "finding holds" criteria evaluated per (δ, l_t) and scheme (``--margin-mm``, default 0.1 mm):
flange contact of w1 right at 20 m AND margin_20 >= +margin; no flange contact of w1 (right or left) at 40 m AND
margin_40 <= -margin; raw and 10 ms-averaged |Y| ratio 20 m / 40 m >= 2.  "Robust" = holds for all three schemes.
``holds_flange_yes`` / ``robust_flange_yes``: the same without the displacement margin at 20 m — once the flange
flank (contact angle ~1.22 rad) is hit it stops the wheelset within ~0.15 mm of the jump whatever δ, so
margin_20 measures the flank's stiffness more than the distance from the threshold; the yes/no agreement of the
three schemes and the δ distance to the no-contact cells are the better robustness measures there.

The short run ends ~10 m after the leading wheelset has left the deviation: a later excursion (the rebound towards
the left flange at 40 m peaks near the end of that window) is outside it, as in the tests.

Also: wall time of one short run pair (20 m + 40 m, Newmark 1 ms, the tests' ``short_runs`` fixture), measured in
this process before the parallel sweep starts (first pair: with imports and numba cache loading; second: warm).

Run:  python benchmarks/rtri_sensitivity.py [--workers 2] [--check-deltas 9 10 11 12 --check-lts 2 3 4]
(~8 min on 2 cores with the default full check grid, 288 short runs; ~2 min with the sub-grid shown)
Writes benchmarks/results/rtri_sensitivity.csv, .json and .png.  SUBSTITUTE inputs throughout (Manchester vehicle 1,
S1002/UIC60 1:40; δ, l_t assumed): see rtri_assumptions.py.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import platform
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from multiprocessing import get_context
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).resolve().parent / "results"
SPEED_KM_H = 250.0
SPANS_M = (20.0, 40.0)
DELTAS_MM = (8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 16.0)
LTS_M = (1.0, 1.5, 2.0, 3.0, 4.0, 6.0)
#: the sub-grid also run with RK44 1 ms and Newmark 0.5 ms: by default the whole grid (~8 min on 2 cores; the
#: neighbourhood of the defaults alone: ``--check-deltas 9 10 11 12 --check-lts 2 3 4``, ~2 min)
CHECK_DELTAS_MM = DELTAS_MM
CHECK_LTS_M = LTS_M
#: end-rotation range πδ/L called physically defensible in rtri_assumptions.py's docstring (deck-end rotation
#: limits, 1.5-3.5 mrad), applied to the 20 m span
END_ROTATION_RANGE_RAD = (1.5e-3, 3.5e-3)
JUMP_TOL_M = 1e-8
MAX_WORKERS = 2

CSV_COLUMNS = ("scheme", "solver", "dt_ms", "span_m", "delta_mm", "lt_m", "end_rotation_mrad", "steps", "status",
               "max_y_rel_mm", "max_y_rel_signed_mm", "time_of_max_y_rel_s", "y_jump_mm", "margin_mm",
               "max_y_rel_right_mm", "margin_right_mm", "max_y_rel_left_mm", "margin_left_mm",
               "t_leading_wheelset_leaves_deviation_s", "t_end_s",
               "flange_contact", "flange_duration_s", "flange_first_time_s", "y_rel_at_first_flange_mm",
               "flange_contact_w1_left", "max_contact_angle_rad", "max_abs_Y_N", "max_abs_Y_10ms_avg_N",
               "max_derailment_quotient", "min_wheel_load_N", "ratio_raw_20_40", "ratio_avg_20_40",
               "solve_seconds", "run_seconds", "load_1min_start", "load_1min_end")


# ------------------------------------------------------------------------------------------------ schemes
def schemes():
    """name -> (solver, dt_s, geometry, creep_law)."""
    from exudyn_wheelrail.scenarios.rtri import RTRI, RTRI_CASE
    from exudyn_wheelrail.simulation.presets import PRESETS
    d = {**PRESETS["default"].run, **PRESETS["default"].contact}
    return {
        "newmark_1ms": ("newmark", RTRI.time_step_s, "online", RTRI_CASE.creep_law),
        "rk44_1ms": (d["solver"], d["dt_s"], d["geometry"], d["creep_law"]),
        "newmark_0.5ms": ("newmark", 0.5 * RTRI.time_step_s, "online", RTRI_CASE.creep_law),
    }


def short_steps(span_m: float, lt_m: float, dt_s: float) -> int:
    """The tests' short run (leading wheelset: lead-in, span + transitions, run-out) with this case's l_t."""
    from exudyn_wheelrail.scenarios.rtri import RTRI
    distance = RTRI.lead_in_m + span_m + lt_m + RTRI.run_out_m
    n_1ms = int(math.ceil(distance / (SPEED_KM_H / 3.6) / RTRI.time_step_s))
    return n_1ms * int(round(RTRI.time_step_s / dt_s))


def make_case(span_m, delta_mm, lt_m, scheme):
    from exudyn_wheelrail.scenarios.rtri import RtriCase
    solver, dt, geometry, creep_law = schemes()[scheme]
    return RtriCase(span_m=span_m, speed_km_h=SPEED_KM_H, solver=solver, dt_s=dt, geometry=geometry,
                    creep_law=creep_law, duration_s=short_steps(span_m, lt_m, dt) * dt,
                    deviation_amplitude_m=delta_mm * 1e-3, transition_length_m=lt_m)


# --------------------------------------------------------------------------------------- the contact jump
def flank_jump(pair=None) -> dict:
    """Lateral shift of the quasi-static jump of the right wheel's contact to its flange region (rigid
    contact-geometry sweep, global search): coarse sweep 0..10 mm by 0.05 mm, then bisection."""
    from exudyn_wheelrail.analysis.geometry_functions import contact_geometry_sweep
    from exudyn_wheelrail.contact.pair import WheelRailPair
    from exudyn_wheelrail.contact.wheelset import WheelsetContact
    from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle

    g = load_vehicle("manchester_vehicle1").geometry
    if pair is None:
        pair = WheelRailPair(g.wheel_profile, g.rail_profile, gauge_m=g.gauge_m, inclination=g.rail_inclination_tan,
                             back_to_back_m=g.back_to_back_m, r0_m=g.r0_m)
    contact = WheelsetContact(pair, global_search=True)

    def main_right(y):
        rows = [r for r in contact_geometry_sweep(pair, [y], contact=contact).rows if r["side"] == "right"]
        return min(rows, key=lambda r: r["gap_m"])          # the touching (deepest) point of the right wheel

    ys = np.round(np.arange(0, 201) * 0.05e-3, 12)
    sweep = contact_geometry_sweep(pair, ys, contact=contact)
    first = None
    for y in ys:
        rows = [r for r in sweep.rows if r["side"] == "right" and r["y_m"] == y]
        if min(rows, key=lambda r: r["gap_m"])["region"] == "flange":
            first = float(y)
            break
    if first is None:
        raise RuntimeError("no flange-region contact of the right wheel up to 10 mm")
    lo, hi = first - 0.05e-3, first
    while hi - lo > JUMP_TOL_M:
        mid = 0.5 * (lo + hi)
        if main_right(mid)["region"] == "flange":
            hi = mid
        else:
            lo = mid
    a, b = main_right(lo), main_right(hi)
    # where the flange region first comes within the sweep's two-point tolerance (1 µm gap) of the rail
    two_point = None
    for y in ys:
        if any(r["side"] == "right" and r["region"] == "flange" for r in sweep.rows if r["y_m"] == y):
            two_point = float(y)
            break
    return {"y_jump_m": 0.5 * (lo + hi), "bracket_m": [lo, hi],
            "contact_angle_before_rad": a["contact_angle_rad"], "contact_angle_after_rad": b["contact_angle_rad"],
            "y_wheel_before_m": a["y_wheel_m"], "y_wheel_after_m": b["y_wheel_m"],
            "first_shift_with_flange_within_1um_on_0.05mm_grid_m": two_point,
            "pair": repr(pair), "gauge_m": g.gauge_m, "back_to_back_m": g.back_to_back_m,
            "rail_inclination_tan": g.rail_inclination_tan,
            "method": "exudyn_wheelrail.analysis.geometry_functions.contact_geometry_sweep (rigid, global search): "
                      "smallest shift with the right wheel's deepest point in the flange region; 0.05 mm grid, "
                      f"then bisection to {JUMP_TOL_M:g} m"}


# ------------------------------------------------------------------------------------------------ one run
def run_one(span_m, delta_mm, lt_m, scheme, y_jump_m):
    """One short run; returns a flat row (no time series)."""
    from exudyn_wheelrail.scenarios.rtri import run_rtri
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    case = make_case(span_m, delta_mm, lt_m, scheme)
    row = {"scheme": scheme, "solver": case.run.solver, "dt_ms": case.run.dt_s * 1e3, "span_m": span_m,
           "delta_mm": delta_mm, "lt_m": lt_m, "end_rotation_mrad": math.pi * delta_mm / span_m,
           "steps": case.run.steps, "y_jump_mm": y_jump_m * 1e3}
    try:
        r = run_rtri(case)
    except Exception as exc:                 # one failing case must not stop the sweep
        row.update(status=f"error: {type(exc).__name__}: {exc}", run_seconds=time.perf_counter() - t0,
                   load_1min_start=load0, load_1min_end=os.getloadavg()[0])
        return row
    s, ts = r.summary, r.timeseries
    p = s.get("peaks", {})
    row["status"] = s["status"]
    row["solve_seconds"] = s["solve_seconds"]
    if p:
        rel = ts["wheelset1_lateral_rel_track_m"]
        i = int(np.nanargmax(np.abs(rel)))
        fl = ts["flange_contact_w1_right"] > 0.5
        row.update(
            max_y_rel_mm=p["max_abs_wheelset1_lateral_rel_track_m"] * 1e3,
            max_y_rel_signed_mm=float(rel[i]) * 1e3,
            time_of_max_y_rel_s=float(ts["time_s"][i]),
            margin_mm=(p["max_abs_wheelset1_lateral_rel_track_m"] - y_jump_m) * 1e3,
            max_y_rel_right_mm=float(np.nanmax(rel)) * 1e3,
            margin_right_mm=(float(np.nanmax(rel)) - y_jump_m) * 1e3,
            max_y_rel_left_mm=float(-np.nanmin(rel)) * 1e3,
            margin_left_mm=(float(-np.nanmin(rel)) - y_jump_m) * 1e3,
            t_leading_wheelset_leaves_deviation_s=s["coverage"]["t_leading_wheelset_leaves_span_s"],
            t_end_s=float(ts["time_s"][-1]),
            flange_contact=p["flange_contact_w1_right"],
            flange_duration_s=p["flange_contact_w1_right_duration_s"],
            flange_first_time_s=p["flange_contact_w1_right_first_time_s"],
            y_rel_at_first_flange_mm=float(rel[fl][0]) * 1e3 if fl.any() else None,
            flange_contact_w1_left=p["flange_contact_w1_left"],
            max_contact_angle_rad=p["max_contact_angle_w1_right_rad"],
            max_abs_Y_N=p["max_abs_lateral_contact_force_w1_right_N"],
            max_abs_Y_10ms_avg_N=p["max_abs_lateral_contact_force_w1_right_10ms_avg_N"],
            max_derailment_quotient=p["max_derailment_quotient_w1_right"],
            min_wheel_load_N=p["min_wheel_load_w1_right_N"])
    row["run_seconds"] = time.perf_counter() - t0
    row["load_1min_start"] = load0
    row["load_1min_end"] = os.getloadavg()[0]
    return row


def time_pair() -> dict:
    """Wall time of the tests' short_runs fixture (20 m + 40 m, Newmark 1 ms, stated assumptions), twice."""
    from exudyn_wheelrail.scenarios.rtri import RTRI, RtriCase, run_rtri
    out = []
    for rep in range(2):
        one = {}
        for L in SPANS_M:
            t0 = time.perf_counter()
            r = run_rtri(RtriCase(span_m=L, speed_km_h=SPEED_KM_H, solver="newmark",
                                  duration_s=short_steps(L, RTRI.transition_length_m, RTRI.time_step_s)
                                  * RTRI.time_step_s))
            one[f"{L:g}m"] = {"wall_s": time.perf_counter() - t0, "solve_s": r.summary["solve_seconds"],
                              "steps": r.summary["steps"], "status": r.summary["status"]}
        one["pair_wall_s"] = sum(v["wall_s"] for v in one.values())
        one["load_1min"] = os.getloadavg()[0]
        out.append(one)
    return {"first_pair_with_imports_and_numba_cache": out[0], "second_pair_warm": out[1]}


# -------------------------------------------------------------------------------------------- evaluation
def add_ratios(rows):
    by = {(r["scheme"], r["delta_mm"], r["lt_m"], r["span_m"]): r for r in rows}
    for r in rows:
        a, b = by.get((r["scheme"], r["delta_mm"], r["lt_m"], 20.0)), by.get((r["scheme"], r["delta_mm"], r["lt_m"], 40.0))
        ok = a and b and a.get("status") == "ok" and b.get("status") == "ok"
        r["ratio_raw_20_40"] = a["max_abs_Y_N"] / b["max_abs_Y_N"] if ok else None
        r["ratio_avg_20_40"] = a["max_abs_Y_10ms_avg_N"] / b["max_abs_Y_10ms_avg_N"] if ok else None


def evaluate(rows, margin_mm: float) -> list[dict]:
    """Per (δ, l_t): the criteria per scheme and the robust verdict."""
    by = {(r["scheme"], r["delta_mm"], r["lt_m"], r["span_m"]): r for r in rows}
    cells = sorted({(r["delta_mm"], r["lt_m"]) for r in rows})
    out = []
    for d, lt in cells:
        cell = {"delta_mm": d, "lt_m": lt, "end_rotation_20m_mrad": math.pi * d / 20.0,
                "end_rotation_40m_mrad": math.pi * d / 40.0,
                "in_defensible_end_rotation_range_20m": END_ROTATION_RANGE_RAD[0] <= math.pi * d * 1e-3 / 20.0
                <= END_ROTATION_RANGE_RAD[1], "schemes": {}}
        for sch in ("newmark_1ms", "rk44_1ms", "newmark_0.5ms"):
            a, b = by.get((sch, d, lt, 20.0)), by.get((sch, d, lt, 40.0))
            if not (a and b):
                continue
            if a.get("status") != "ok" or b.get("status") != "ok":
                cell["schemes"][sch] = {"status": f"20 m: {a.get('status')}; 40 m: {b.get('status')}", "holds": False}
                continue
            c = {"flange_20": bool(a["flange_contact"]), "margin_20_mm": a["margin_mm"],
                 "flange_20_duration_s": a["flange_duration_s"],
                 "flange_40": bool(b["flange_contact"]) or bool(b["flange_contact_w1_left"]),
                 "margin_40_mm": b["margin_mm"], "margin_40_right_mm": b["margin_right_mm"],
                 "ratio_raw": a["ratio_raw_20_40"], "ratio_avg": a["ratio_avg_20_40"]}
            c["flange_20_ok"] = c["flange_20"] and c["margin_20_mm"] >= margin_mm
            c["no_flange_40_ok"] = (not c["flange_40"]) and c["margin_40_mm"] <= -margin_mm
            c["ratio_ok"] = c["ratio_raw"] >= 2.0 and c["ratio_avg"] >= 2.0
            c["holds"] = c["flange_20_ok"] and c["no_flange_40_ok"] and c["ratio_ok"]
            # the same without the 0.1 mm displacement margin at 20 m (see the module docstring: once the flank is
            # hit the wheelset stops within ~0.15 mm of the jump, so that margin measures the flank, not robustness)
            c["holds_flange_yes"] = c["flange_20"] and c["no_flange_40_ok"] and c["ratio_ok"]
            cell["schemes"][sch] = c
        ran = list(cell["schemes"])
        cell["schemes_run"] = ran
        cell["holds_newmark_1ms"] = cell["schemes"].get("newmark_1ms", {}).get("holds", False)
        cell["flange_20_same_in_all_schemes"] = len({cell["schemes"][s].get("flange_20") for s in ran}) == 1
        cell["robust"] = len(ran) == 3 and all(cell["schemes"][s]["holds"] for s in ran)
        cell["robust_flange_yes"] = len(ran) == 3 and all(cell["schemes"][s].get("holds_flange_yes") for s in ran)
        out.append(cell)
    return out


# -------------------------------------------------------------------------------------------------- plot
def plot(rows, y_jump_mm, margin_mm, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    lts = sorted({r["lt_m"] for r in rows})
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), sharey=False)
    marks = {"rk44_1ms": ("x", "RK44 1 ms (default preset)"), "newmark_0.5ms": ("+", "Newmark 0.5 ms")}
    for ax, L in zip(axes, SPANS_M):
        for i, lt in enumerate(lts):
            sel = sorted((r for r in rows if r["scheme"] == "newmark_1ms" and r["span_m"] == L and r["lt_m"] == lt
                          and r.get("status") == "ok"), key=lambda r: r["delta_mm"])
            if not sel:
                continue
            d = [r["delta_mm"] for r in sel]
            m = [r["margin_mm"] for r in sel]
            ax.plot(d, m, "-", color=f"C{i}", lw=1.2, label=f"l_t = {lt:g} m (Newmark 1 ms)")
            for r in sel:
                ax.plot(r["delta_mm"], r["margin_mm"], "o", color=f"C{i}", ms=6,
                        mfc=f"C{i}" if r["flange_contact"] else "white")
            for sch, (mk, _) in marks.items():
                other = [r for r in rows if r["scheme"] == sch and r["span_m"] == L and r["lt_m"] == lt
                         and r.get("status") == "ok"]
                for r in other:
                    ax.plot(r["delta_mm"], r["margin_mm"], mk, color=f"C{i}", ms=8)
        ax.axhline(0.0, color="k", lw=1.0)
        for s in (-1, 1):
            ax.axhline(s * margin_mm, color="0.5", lw=0.8, ls=":")
        lo = END_ROTATION_RANGE_RAD[0] * 20.0 / math.pi * 1e3     # the range is defined on the 20 m span
        ax.axvspan(lo, max(r["delta_mm"] for r in rows) + 0.5, color="0.85", alpha=0.4, zorder=0)
        ax.set(xlabel="deviation amplitude δ [mm]",
               ylabel=f"max |y_w1 - y_track| - y_jump [mm]  (y_jump = {y_jump_mm:.3f} mm)",
               title=f"span {L:g} m, 250 km/h, short run; filled: flange contact w1 right")
        ax.title.set_fontsize(9)
        ax.grid(True, alpha=0.3)
    for sch, (mk, lab) in marks.items():
        axes[0].plot([], [], mk, color="k", label=lab)
    axes[0].plot([], [], "s", color="0.85", label="π δ / (20 m) in 1.5-3.5 mrad")
    axes[0].legend(fontsize=7, loc="lower right")
    fig.suptitle("RTRI sensitivity to the ASSUMED δ and l_t — SUBSTITUTE inputs (Manchester vehicle 1, "
                 "S1002/UIC60 1:40)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# -------------------------------------------------------------------------------------------------- main
def _git():
    here = Path(__file__).resolve().parent
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=here, capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain"], cwd=here, capture_output=True, text=True).stdout
        return {"head": head, "uncommitted_changes": bool(dirty.strip())}
    except OSError:
        return None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--workers", type=int, default=MAX_WORKERS, help=f"parallel processes (at most {MAX_WORKERS})")
    ap.add_argument("--deltas", type=float, nargs="+", default=list(DELTAS_MM), help="δ values [mm]")
    ap.add_argument("--lts", type=float, nargs="+", default=list(LTS_M), help="l_t values [m]")
    ap.add_argument("--check-deltas", type=float, nargs="*", default=list(CHECK_DELTAS_MM),
                    help="δ [mm] also run with RK44 1 ms and Newmark 0.5 ms")
    ap.add_argument("--check-lts", type=float, nargs="*", default=list(CHECK_LTS_M),
                    help="l_t [m] also run with RK44 1 ms and Newmark 0.5 ms")
    ap.add_argument("--margin-mm", type=float, default=0.1, help="required distance from the flank jump [mm]")
    ap.add_argument("--no-timing", action="store_true", help="skip the timing of one short run pair")
    ap.add_argument("--out", default=str(RESULTS / "rtri_sensitivity"), help="output path without extension")
    args = ap.parse_args(argv)
    workers = max(1, min(MAX_WORKERS, args.workers))
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    load_start = list(os.getloadavg())
    t_start = time.perf_counter()

    jump = flank_jump()
    y_jump = jump["y_jump_m"]
    print(f"flange-flank jump of the right wheel: {y_jump * 1e3:.4f} mm (contact angle "
          f"{jump['contact_angle_before_rad']:.3f} -> {jump['contact_angle_after_rad']:.3f} rad)", flush=True)

    timing = None if args.no_timing else time_pair()
    if timing:
        print(f"short run pair (Newmark 1 ms): first {timing['first_pair_with_imports_and_numba_cache']['pair_wall_s']:.1f} s, "
              f"warm {timing['second_pair_warm']['pair_wall_s']:.1f} s", flush=True)

    tasks = [(L, d, lt, "newmark_1ms") for d in args.deltas for lt in args.lts for L in SPANS_M]
    tasks += [(L, d, lt, sch) for sch in ("newmark_0.5ms", "rk44_1ms") for d in args.check_deltas
              for lt in args.check_lts for L in SPANS_M]
    for L, d, lt, sch in tasks:                       # validate every case before starting
        make_case(L, d, lt, sch)
    # longest first (0.5 ms, 40 m) for a balanced pool
    tasks.sort(key=lambda t: -(short_steps(t[0], t[2], schemes()[t[3]][1])))
    rows = []
    t_pool = time.perf_counter()
    with ProcessPoolExecutor(max_workers=workers, mp_context=get_context("spawn")) as pool:
        futs = [pool.submit(run_one, L, d, lt, sch, y_jump) for (L, d, lt, sch) in tasks]
        for k, f in enumerate(as_completed(futs), 1):
            r = f.result()
            rows.append(r)
            print(f"[{k}/{len(tasks)}] {r['scheme']:13s} L {r['span_m']:g} δ {r['delta_mm']:g} l_t {r['lt_m']:g}: "
                  f"{r['status']}; y {r.get('max_y_rel_mm', float('nan')):.3f} mm, margin "
                  f"{r.get('margin_mm', float('nan')):+.3f} mm, flange {r.get('flange_contact')}, |Y| "
                  f"{r.get('max_abs_Y_N', float('nan')) / 1e3:.1f} / {r.get('max_abs_Y_10ms_avg_N', float('nan')) / 1e3:.1f} kN "
                  f"({r.get('run_seconds', float('nan')):.1f} s)", flush=True)
    pool_seconds = time.perf_counter() - t_pool
    order = {"newmark_1ms": 0, "rk44_1ms": 1, "newmark_0.5ms": 2}
    rows.sort(key=lambda r: (order[r["scheme"]], r["delta_mm"], r["lt_m"], r["span_m"]))
    add_ratios(rows)
    cells = evaluate(rows, args.margin_mm)

    with open(out.with_suffix(".csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(CSV_COLUMNS), extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    meta = {
        "what": "RTRI rigid-rail case, sensitivity of the 20 m flange-contact finding to the ASSUMED deviation "
                "amplitude and transition length; SUBSTITUTE inputs (Manchester vehicle 1, S1002/UIC60 1:40)",
        "speed_km_h": SPEED_KM_H, "spans_m": list(SPANS_M), "deltas_mm": args.deltas, "lts_m": args.lts,
        "check_deltas_mm": args.check_deltas, "check_lts_m": args.check_lts,
        "schemes": {k: dict(zip(("solver", "dt_s", "geometry", "creep_law"), v)) for k, v in schemes().items()},
        "steps_rule": "ceil((lead_in + L + l_t + run_out) / V / 1 ms) * (1 ms / dt)",
        "peaks_window": "summary['peaks'] (the whole short run), as tests/test_rtri.py",
        "margin_definition": "max |y_w1 rel track| - y_jump (> 0: beyond the flank jump; either flange); "
                             "margin_right/left: the same with the largest excursion to that side",
        "flange_40_definition": "flange region of w1 right OR left in contact",
        "criteria": {"margin_mm": args.margin_mm, "force_ratio_min": 2.0,
                     "holds": "flange_20 and margin_20 >= m; not flange_40 and margin_40 <= -m; raw and 10 ms-avg "
                              "|Y| ratio 20/40 >= 2",
                     "robust": "holds with newmark_1ms, rk44_1ms and newmark_0.5ms",
                     "holds_flange_yes": "as holds, without the margin_20 >= m condition",
                     "robust_flange_yes": "holds_flange_yes with all three schemes"},
        "end_rotation_range_rad": list(END_ROTATION_RANGE_RAD),
        "flank_jump": jump,
        "timing_short_run_pair": timing,
        "pool": {"workers": workers, "cases": len(tasks), "wall_seconds": pool_seconds},
        "total_wall_seconds": time.perf_counter() - t_start,
        "machine": {"load_average_start": load_start, "load_average_end": list(os.getloadavg()),
                    "cpu_count": os.cpu_count(), "python": platform.python_version(),
                    "platform": platform.platform()},
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "git": _git(),
        "cells": cells, "rows": rows,
    }
    with open(out.with_suffix(".json"), "w") as fh:
        json.dump(meta, fh, indent=1, default=float)
    plot(rows, y_jump * 1e3, args.margin_mm, out.with_suffix(".png"))

    print("\n δ mm  l_t m  rot20 mrad  | margin20 fl20 | margin40 fl40 | ratio raw/avg | holds NM1 | robust | "
          "robust_flange_yes")
    for c in cells:
        n = c["schemes"].get("newmark_1ms", {})
        if "margin_20_mm" not in n:
            continue
        print(f" {c['delta_mm']:5g} {c['lt_m']:5g} {c['end_rotation_20m_mrad']:8.2f}    | {n['margin_20_mm']:+7.3f} "
              f"{'Y' if n['flange_20'] else 'n'}    | {n['margin_40_mm']:+7.3f} {'Y' if n['flange_40'] else 'n'}    | "
              f"{n['ratio_raw']:5.2f} / {n['ratio_avg']:5.2f} | {n['holds']!s:5} | "
              f"{c['robust'] if len(c['schemes_run']) == 3 else '(only ' + ','.join(c['schemes_run']) + ')'} | "
              f"{c['robust_flange_yes']}")
    print(f"wrote {out.with_suffix('.csv')}, .json, .png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
