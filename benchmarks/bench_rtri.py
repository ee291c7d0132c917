"""RTRI case (exudyn_wheelrail.scenarios.rtri): cost of the wheel–rail contact in a full vehicle simulation.

Measures, for the RTRI 20 m case at the representative speed (250 km/h), 2500 steps of 1 ms (the paper's run),
with RK44 and with Newmark (trapezoidal rule, modified Newton):

* ``contact``: the vehicle with the project's wheel–rail connector (FASTSIM 24 x 8), without output recording
  (``record=False``: the simulation watched by the run monitor, which evaluates the contact once more per step)
  and with it (the CLI's configuration: the recorder reads the monitor's evaluation and the body outputs);
* ``springs``: the same vehicle with each wheel–rail contact replaced by linear springs
  (``build_vehicle(..., wheel_rail="springs")``; the deviation does not act on them — a cost baseline);

``solve_seconds`` = wall time inside ``mbs.SolveDynamic`` only (model building, numba cache loading and a warm-up
contact call are outside).  Every configuration is repeated (default 3 times, fresh model each time) and the
**minimum** is reported (the machine is shared), with all repeats listed.  Ratio = contact / springs (same solver,
no recording); real-time factor = simulated time / solve time (> 1: faster than real time).  Targets (those of the
``default`` preset, :mod:`exudyn_wheelrail.simulation.presets`): ratio <= ``SPRINGS_RATIO_MAX`` and real-time factor
>= ``TARGETS["default"][0]`` on one core.

Also: the Python-level cost of one contact evaluation (``WheelRailContact.forces`` for 4 wheelsets, at the initial
state, mean of 2000 calls) to relate the solve time to the number of contact calls.

Run:  python benchmarks/bench_rtri.py [--repeats 3] [--duration 2.5] [--speed-kmh 250] [--span 20]
Writes benchmarks/results/rtri.json.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

from exudyn_wheelrail.scenarios.rtri import RTRI_CASE, RtriCase, run_rtri
from exudyn_wheelrail.scenarios.scenario import build_scenario
from exudyn_wheelrail.simulation.presets import SPRINGS_RATIO_MAX, TARGETS

RESULTS = Path(__file__).resolve().parent / "results" / "rtri.json"


def contact_call_us(span_m: float, speed_km_h: float, n: int = 2000) -> float:
    h = build_scenario(RtriCase(span_m=span_m, speed_km_h=speed_km_h, duration_s=1e-3, record=False).scenario())
    c = h.contact
    q, v = c.coordinates(h.mbs)
    warm = c.save_warm_start()
    c.forces(q, v, 0.0)
    t0 = time.perf_counter()
    for _ in range(n):
        c.forces(q, v, 0.0)
    dt = (time.perf_counter() - t0) / n
    c.restore_warm_start(warm)
    return dt * 1e6


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--duration", type=float, default=2.5, help="simulated time [s] (steps of 1 ms)")
    ap.add_argument("--speed-kmh", type=float, default=RTRI_CASE.representative_speed_km_h)
    ap.add_argument("--span", type=float, default=20.0)
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args(argv)
    args.steps = RtriCase(duration_s=args.duration).run.steps

    configs = []
    for solver in ("rk44", "newmark"):
        configs += [(solver, "contact", False), (solver, "contact", True), (solver, "springs", False)]
    # warm-up (numba caches, Exudyn) outside all measurements
    run_rtri(RtriCase(span_m=args.span, speed_km_h=args.speed_kmh, solver="newmark", duration_s=0.005))
    run_rtri(RtriCase(span_m=args.span, speed_km_h=args.speed_kmh, solver="rk44", duration_s=0.005))
    times = {c: [] for c in configs}
    info = {}
    for rep in range(args.repeats):
        for cfg in configs:                       # interleaved, so a load change on the machine hits all alike
            solver, wr, record = cfg
            case = RtriCase(span_m=args.span, speed_km_h=args.speed_kmh, solver=solver, duration_s=args.duration,
                            wheel_rail=wr, record=record)
            r = run_rtri(case)
            if r.summary["status"] != "ok":
                print(f"{cfg}: {r.summary['status']}", file=sys.stderr)
            times[cfg].append(r.summary["solve_seconds"])
            info[cfg] = dict(status=r.summary["status"], contact_calls=r.summary["contact_calls"])
            print(f"repeat {rep + 1}: {solver:7s} {wr:7s} record={record!s:5s} {r.summary['solve_seconds']:.3f} s "
                  f"({r.summary['status']})", flush=True)
    sim_time = args.steps * RtriCase().run.dt_s
    rows = []
    for cfg in configs:
        solver, wr, record = cfg
        t = min(times[cfg])
        rows.append(dict(solver=solver, wheel_rail=wr, record=record, solve_seconds_min=t,
                         solve_seconds_all=times[cfg], real_time_factor=sim_time / t,
                         us_per_step=t / args.steps * 1e6, status=info[cfg]["status"],
                         contact_calls_per_step=info[cfg]["contact_calls"] / args.steps))
    by = {(r["solver"], r["wheel_rail"], r["record"]): r for r in rows}
    ratios = {}
    for solver in ("rk44", "newmark"):
        spr = by[(solver, "springs", False)]["solve_seconds_min"]
        ratios[solver] = dict(contact_over_springs=by[(solver, "contact", False)]["solve_seconds_min"] / spr,
                              contact_recording_over_springs=by[(solver, "contact", True)]["solve_seconds_min"] / spr)
    call_us = contact_call_us(args.span, args.speed_kmh)
    result = dict(
        case=f"RTRI {args.span:g} m span, {args.speed_kmh:g} km/h, {args.steps} steps of 1 ms (substitute inputs)",
        creep_law=RTRI_CASE.creep_law, fastsim_grid=list(RTRI_CASE.fastsim_grid), repeats=args.repeats,
        simulated_time_s=sim_time, rows=rows, ratios=ratios, contact_call_us_python=call_us,
        targets=dict(ratio_max=SPRINGS_RATIO_MAX, real_time_factor_min=TARGETS["default"][0]),
        targets_met={solver: dict(ratio=ratios[solver]["contact_over_springs"] <= SPRINGS_RATIO_MAX,
                                  real_time=by[(solver, "contact", False)]["real_time_factor"]
                                  >= TARGETS["default"][0])
                     for solver in ("rk44", "newmark")},
        python=platform.python_version(), platform=platform.platform(), cpu_count=os.cpu_count(),
        load_average=list(os.getloadavg()), date=time.strftime("%Y-%m-%dT%H:%M:%S%z"))
    try:
        import exudyn
        import numba
        result["exudyn"], result["numba"] = exudyn.__version__, numba.__version__
    except Exception:  # pragma: no cover
        pass
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(result, fh, indent=2)

    print(f"\n### RTRI {args.span:g} m, {args.speed_kmh:g} km/h, {args.steps} steps (min of {args.repeats})\n")
    print("| solver | wheel-rail | recording | solve [s] | µs/step | real-time factor | contact calls/step |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['solver']} | {r['wheel_rail']} | {'yes' if r['record'] else 'no'} | "
              f"{r['solve_seconds_min']:.3f} | {r['us_per_step']:.0f} | {r['real_time_factor']:.2f} | "
              f"{r['contact_calls_per_step']:.1f} |")
    print()
    for solver, v in ratios.items():
        print(f"{solver}: contact / springs = {v['contact_over_springs']:.2f} (with recording "
              f"{v['contact_recording_over_springs']:.2f}); target <= {SPRINGS_RATIO_MAX:g}")
    print(f"one contact evaluation (4 wheelsets, Python call): {call_us:.1f} µs")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
