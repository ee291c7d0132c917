"""bridge-crossing, moving-load model: real-time factor of one crossing over a 20 m and a 40 m span, and the wall
time of a 30-speed sweep on 2 worker processes.

Case: HSLM-A1 (EN 1991-2, 50 axles of 170 kN, 397.5 m) at 300 km/h; deck m = 15 t/m, ζ = 1 %, 3 vertical modes;
20 m span with f1 = 5 Hz, 40 m span with f1 = 3 Hz (EI from f1); RK44 at the default step (40 steps per period of
the third mode), recording every step (the command's configuration).  ``solve_seconds`` = wall time of the
runner's solve (model building and the eigen solution outside), best of ``--repeats`` runs; the sweep: 30 speeds
140 … 430 km/h over the 20 m span through :func:`~exudyn_wheelrail.scenarios.bridge_crossing.speed_sweep` with
2 spawned worker processes (whole wall time, process start and each case's build included).  The machine load
(``os.getloadavg``) is printed beside every figure: the machine is shared.

Run:  python benchmarks/bench_bridge_crossing.py [--repeats 3] [--no-sweep]
Writes benchmarks/results/bridge_crossing.json.
"""
from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np

from exudyn_wheelrail.scenarios.bridge_crossing import BridgeCrossing, run_bridge_crossing, speed_sweep
from exudyn_wheelrail.structures.load_models import hslm_a

RESULTS = Path(__file__).resolve().parent / "results"
SPANS = ((20.0, 5.0), (40.0, 3.0))           # (span [m], f1 [Hz])


def _load() -> str:
    return "load %.2f %.2f %.2f" % os.getloadavg()


def _case(span, f1, V):
    return BridgeCrossing(span_m=span, mass_kg_m=15e3, f1_Hz=f1, damping_ratio=0.01, n_modes=3, axles=hslm_a("A1"),
                          speed_m_s=V)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--no-sweep", action="store_true")
    args = ap.parse_args(argv)
    out = {"case": "HSLM-A1 at 300 km/h, m = 15 t/m, zeta = 1 %, 3 modes, RK44 default dt", "crossings": []}
    V = 300 / 3.6
    run_bridge_crossing(_case(20.0, 5.0, V))                      # warm-up: numba caches, Exudyn import
    for span, f1 in SPANS:
        best = None
        for _ in range(args.repeats):
            before = _load()
            s = run_bridge_crossing(_case(span, f1, V)).summary
            assert s["status"] == "ok", s["status"]
            if best is None or s["solve_seconds"] < best["solve_seconds"]:
                best = {**{k: s[k] for k in ("solve_seconds", "simulated_seconds", "steps", "dt_s", "build_seconds",
                                              "real_time_factor")}, "load_before": before, "load_after": _load()}
        best.update(span_m=span, f1_Hz=f1, us_per_step=1e6 * best["solve_seconds"] / best["steps"],
                    us_per_step_and_axle=1e6 * best["solve_seconds"] / best["steps"] / 50)
        out["crossings"].append(best)
        print(f"L = {span:g} m, f1 = {f1:g} Hz: {best['steps']} steps of {best['dt_s'] * 1e3:.3g} ms, solve "
              f"{best['solve_seconds']:.2f} s for {best['simulated_seconds']:.3g} s simulated: real-time factor "
              f"{best['real_time_factor']:.2f} ({best['us_per_step']:.0f} us/step; build {best['build_seconds']:.2f} s)"
              f"  [{best['load_before']} -> {best['load_after']}]", flush=True)
    if not args.no_sweep:
        speeds = np.arange(140.0, 431.0, 10.0)
        assert speeds.size == 30
        before = _load()
        t0 = time.perf_counter()
        r = speed_sweep(_case(20.0, 5.0, V), speeds / 3.6, workers=2, progress=None)
        wall = time.perf_counter() - t0
        assert all(st == "ok" for st in r.table["status"]), r.table["status"]
        out["sweep"] = {"speeds": 30, "workers": 2, "wall_seconds": wall, "sum_solve_seconds":
                        float(np.sum(r.table["solve_seconds"])), "load_before": before, "load_after": _load()}
        print(f"30-speed sweep (140 ... 430 km/h, 20 m) on 2 workers: {wall:.1f} s wall, "
              f"{out['sweep']['sum_solve_seconds']:.1f} s of solves  [{before} -> {_load()}]")
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "bridge_crossing.json").write_text(json.dumps(out, indent=1))
    print(f"wrote {RESULTS / 'bridge_crossing.json'}")


if __name__ == "__main__":
    main()
