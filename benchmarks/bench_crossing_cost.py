"""The README's 8-car full-interaction crossing per car and step, against the vehicle on linear rail springs.

Case: the README's ``bridge-crossing --span-m 20 --bridge-mass-kg-per-m 15000 --bridge-frequency-hz 5
--damping-ratio 0.01 --modes 3 --train vehicles/trains/crh6_intercity_8car.toml --model vehicles --speed-kmh 250``
(8 cars, 32 wheelsets, one contact, RK44 at the command's step, recording every step), built as the command builds
it and run through the runner as the command runs it: ``watched`` (the run's checks and the recorder's columns in
the compiled force call, :mod:`exudyn_wheelrail.simulation.watch`) and, for comparison, ``pre_step`` (every state
checked and recorded by the runner's Python pre-step function, ``watch=False``).  The baseline: the vehicle on
linear rail springs of ``bench_step_overhead.py`` (RTRI 20 m, RK44 1 ms, no user function), the baseline of every
ratio to "springs".  Every configuration a fresh model, interleaved, ``--repeats`` rounds; time = the thread's CPU time inside
``mbs.SolveDynamic`` (less disturbed than the wall time on a shared machine; the wall time is stored too), the
median over the rounds.  Cost per car and step = solve time / steps / cars.  The load average is printed beside
every run.

Run:  python benchmarks/bench_crossing_cost.py [--repeats 3] [--configs watched pre_step springs]
Writes benchmarks/results/crossing_cost.json.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
from pathlib import Path

import bench_step_overhead as springs_bench
from exudyn_wheelrail.scenarios.bridge_crossing import BridgeCrossing
from exudyn_wheelrail.scenarios.build import build_crossing
from exudyn_wheelrail.simulation.runner import run

RESULTS = Path(__file__).resolve().parent / "results" / "crossing_cost.json"
TRAIN = Path(__file__).resolve().parents[1] / "vehicles" / "trains" / "crh6_intercity_8car.toml"
CARS = 8
CONFIGS = ("watched", "pre_step", "springs")


def crossing_case() -> BridgeCrossing:
    """The README's crossing (its command's options)."""
    return BridgeCrossing(span_m=20.0, mass_kg_m=15000.0, f1_Hz=5.0, damping_ratio=0.01, n_modes=3, axles=None,
                          speed_m_s=250.0 / 3.6, model="vehicles", train_file=str(TRAIN))


def solve_crossing(watch: bool) -> dict:
    """One fresh crossing through the runner: CPU and wall time inside ``SolveDynamic``, steps, watched states."""
    h = build_crossing(crossing_case())
    h.contact.warm_up(h.mbs, jacobian=False)
    with springs_bench.SolveClock() as clock:
        out = run(h.mbs, h.run, h.contact, speed_m_s=h.speed_m_s, recorder=h.recorder,
                  exu_settings=(h.settings, h.solver_type), watch=watch)
    if out.status.kind != "ok":
        print(f"crossing: {out.status}", file=sys.stderr)
    wall, cpu = clock.spans[-1]
    return {"cpu_s": cpu, "wall_s": wall, "steps": h.run.steps, "watched_states": out.watched_states,
            "status": out.status.kind}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--configs", nargs="+", choices=CONFIGS, default=list(CONFIGS))
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args(argv)
    runs = {c: [] for c in args.configs}
    solve_crossing(True)                                 # compiled code loaded outside the measurements
    springs_bench.solve_once("springs")
    springs_steps = springs_bench.build(record=False, wheel_rail="springs").run.steps
    for r in range(args.repeats):
        for c in args.configs:
            load = os.getloadavg()
            if c == "springs":
                wall, cpu = springs_bench.solve_once("springs")
                rec = {"cpu_s": cpu, "wall_s": wall, "steps": springs_steps,
                       "us_per_step_cpu": cpu / springs_steps * 1e6}
            else:
                rec = solve_crossing(c == "watched")
                rec["us_per_car_step_cpu"] = rec["cpu_s"] / rec["steps"] / CARS * 1e6
            rec["load"] = [round(x, 2) for x in load]
            runs[c].append(rec)
            per = rec.get("us_per_car_step_cpu", rec.get("us_per_step_cpu"))
            print(f"round {r + 1} {c:8s} load {load[0]:.2f}: {rec['cpu_s']:.3f} s CPU ({rec['wall_s']:.3f} s wall), "
                  f"{per:.1f} µs per {'car and step' if c != 'springs' else 'step'}", flush=True)
    result = {"benchmark": "README 8-car crossing per car and step against the springs vehicle "
                           "(benchmarks/bench_crossing_cost.py)", "cars": CARS, "runs": runs}
    med = {}
    for c in args.configs:
        key = "us_per_step_cpu" if c == "springs" else "us_per_car_step_cpu"
        med[c] = statistics.median(x[key] for x in runs[c])
    result["median_us"] = med
    if "springs" in med:
        for c in ("watched", "pre_step"):
            if c in med:
                result[f"{c}_over_springs"] = med[c] / med["springs"]
    result["load_end"] = [round(x, 2) for x in os.getloadavg()]
    print("\n| configuration | µs (CPU, median) | ÷ springs |\n|---|---:|---:|")
    for c in args.configs:
        ratio = result.get(f"{c}_over_springs")
        print(f"| {c} | {med[c]:.1f} | {'' if ratio is None else f'{ratio:.2f}'} |")
    Path(args.out).write_text(json.dumps(result, indent=1))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
