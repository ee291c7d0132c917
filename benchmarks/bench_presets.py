"""Presets (simulation.presets): real-time factor of each preset on the RTRI 20 m case at 250 km/h, 2.5 s simulated.

solve_seconds = wall time inside ``mbs.SolveDynamic`` (model building, table loading, numba warm-up outside);
minimum of ``--repeats`` fresh runs, interleaved (the machine may be shared); ``record=False`` (the pure simulation)
and ``record=True`` (the CLI's configuration: the outputs of every step, read from the run monitor's contact
evaluation and Exudyn's stored sensors).  The peak
lateral-force error of each preset is taken from ``benchmarks/results/work_precision.csv`` (same configuration,
against the RK44 0.05 ms reference); the preset targets: ``simulation.presets.TARGETS``.

Run:  python benchmarks/bench_presets.py [--repeats 3]   Writes benchmarks/results/presets.json.
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import time
from pathlib import Path

from exudyn_wheelrail.scenarios.rtri import RtriCase, run_rtri
from exudyn_wheelrail.simulation.presets import PRESETS, TARGETS, apply_preset

RESULTS = Path(__file__).resolve().parent / "results"


def _wp_error(p):
    path = RESULTS / "work_precision.csv"
    if not path.exists():
        return None
    for row in csv.DictReader(open(path)):
        if (row["integrator"] == p.run["solver"] and row["creep_law"] == p.contact["creep_law"]
                and row["geometry"] == p.contact["geometry"] and abs(float(row["dt_ms"]) - p.run["dt_s"] * 1e3) < 1e-9
                and row["status"] == "ok"):
            return float(row["peak_Y_rel_err"])
    return None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    cases = {}
    base = RtriCase()                                   # the paper's 2.5 s
    for name in PRESETS:
        run, contact, _ = apply_preset(name, base.run, base.contact)
        for record in (False, True):
            cases[(name, record)] = RtriCase(run=run, contact=contact, record=record)
        run_rtri(RtriCase(run=run, contact=contact, duration_s=5 * run.dt_s))   # warm-up
    times = {k: [] for k in cases}
    for rep in range(args.repeats):
        for k, case in cases.items():
            r = run_rtri(case)
            assert r.summary["status"] == "ok", r.summary["status"]
            times[k].append(r.summary["solve_seconds"])
            print(f"repeat {rep + 1}: {k[0]:8s} record={k[1]!s:5s} {times[k][-1]:.3f} s", flush=True)
    rows = []
    for name, p in PRESETS.items():
        sim = cases[(name, False)].run.end_time_s
        t0 = min(times[(name, False)])
        t1 = min(times[(name, True)])
        err = _wp_error(p)
        tgt = TARGETS.get(name)
        rows.append(dict(preset=name, **p.run, **p.contact, simulated_s=sim, solve_s=t0, solve_s_recording=t1,
                         real_time_factor=sim / t0, real_time_factor_recording=sim / t1,
                         peak_lateral_force_error=err,
                         target_real_time_factor=tgt[0] if tgt else None, target_error=tgt[1] if tgt else None,
                         meets_speed=(sim / t0 >= tgt[0]) if tgt else None,
                         meets_accuracy=(err is not None and err <= tgt[1]) if tgt else None,
                         all_times=dict(pure=times[(name, False)], recording=times[(name, True)])))
    out = dict(rows=rows, repeats=args.repeats, load_average=list(os.getloadavg()), cpu_count=os.cpu_count(),
               date=time.strftime("%Y-%m-%dT%H:%M:%S%z"))
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "presets.json").write_text(json.dumps(out, indent=2))
    print("\n| preset | solver | dt [ms] | geometry | solve [s] | real-time factor (recording) | peak Y error | "
          "target |")
    print("|---|---|---:|---|---:|---:|---:|---|")
    for r in rows:
        e = "n/a" if r["peak_lateral_force_error"] is None else f"{100 * r['peak_lateral_force_error']:.2f} %"
        t = (f">= {r['target_real_time_factor']:g}x, <= {100 * r['target_error']:g} %"
             if r["target_error"] is not None else "-")
        print(f"| {r['preset']} | {r['solver']} | {r['dt_s'] * 1e3:g} | {r['geometry']} | {r['solve_s']:.3f} | "
              f"{r['real_time_factor']:.1f} ({r['real_time_factor_recording']:.1f}) | {e} | {t} |")


if __name__ == "__main__":
    main()
