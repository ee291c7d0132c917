"""Kalker's exact solver: accuracy of the creep coefficients against Kalker's Table E.3 and cost per case.

Run: ``python benchmarks/bench_kalker_exact.py [--quick]``; writes ``benchmarks/results/kalker_exact.json``.

* Small-creepage slopes C11, C22, C23 at the default grid and Richardson-extrapolated (n_x, 2 n_x), for
  a/b = 0.2 … 5, against Table E.3 interpolated to ν = 0.28 (:func:`exudyn_wheelrail.creep.kalker_coefficients`)
  and at ν = 0.25 (a table column: no interpolation in ν).
* Wall time per case (operator cached, i.e. repeated calls at one a/b, as the table build does) for linear,
  partial-slip, saturated and spin cases, cold and warm-started.
"""
from __future__ import annotations

import argparse
import json
import math
import platform
import time
from pathlib import Path

from exudyn_wheelrail.creep import kalker_coefficients, kalker_exact, kalker_exact_extrapolated, kalker_exact_solution

G = 82e9
N = 10e3
C_M = 6e-3          # √(ab) [m]
EPS = 1e-7          # small creepage: no slip anywhere


def slopes(a_over_b, nu, extrapolated=False):
    a = C_M * math.sqrt(a_over_b)
    b = C_M / math.sqrt(a_over_b)
    f = kalker_exact_extrapolated if extrapolated else kalker_exact
    fx = f(a, b, EPS, 0.0, 0.0, N, 0.3, G, nu)[0]
    fy = f(a, b, 0.0, EPS, 0.0, N, 0.3, G, nu)[1]
    fs = f(a, b, 0.0, 0.0, EPS / C_M, N, 0.3, G, nu)[1]
    k = G * C_M * C_M * EPS
    return -fx / k, -fy / k, -fs / k


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="fewer a/b values, no extrapolation")
    args = ap.parse_args()
    ratios = [0.2, 1.0, 5.0] if args.quick else [0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0, 5.0]
    rows = []
    for nu in (0.28, 0.25):
        for ab in ratios:
            ref = kalker_coefficients(ab, nu)
            t = time.perf_counter()
            d = slopes(ab, nu)
            t_default = time.perf_counter() - t
            row = {"nu": nu, "a_over_b": ab, "table": ref, "default": d,
                   "default_rel_err": [d[i] / ref[i] - 1 for i in range(3)], "seconds_default_3_cases": t_default}
            if not args.quick:
                e = slopes(ab, nu, extrapolated=True)
                row["extrapolated"] = e
                row["extrapolated_rel_err"] = [e[i] / ref[i] - 1 for i in range(3)]
            rows.append(row)
            print(f"nu={nu} a/b={ab:4.1f}  default err C11 {row['default_rel_err'][0]:+.4f} C22 "
                  f"{row['default_rel_err'][1]:+.4f} C23 {row['default_rel_err'][2]:+.4f}"
                  + ("" if args.quick else "  extrapolated " + " ".join(f"{v:+.4f}" for v in
                                                                      row["extrapolated_rel_err"])), flush=True)
    # timing per case at one a/b (operator cached after the first call)
    a, b = 6e-3, 4e-3
    kalker_exact(a, b, 1e-4, 0, 0, N, 0.3, G, 0.28)
    cases = {"linear xi": (1e-6, 0, 0), "partial slip xi": (2e-4, 0, 0), "partial slip xi+eta+spin": (3e-4, 2e-4, 0.3),
             "saturated": (5e-3, 2e-3, 0), "large spin": (0, 0, 5.0)}
    timing = {}
    for name, (xi, eta, phi) in cases.items():
        reps = 3
        t = time.perf_counter()
        for _ in range(reps):
            s = kalker_exact_solution(a, b, xi, eta, phi, N, 0.3, G, 0.28)
        cold = (time.perf_counter() - t) / reps
        t = time.perf_counter()
        s2 = kalker_exact_solution(a, b, xi * 1.02, eta * 1.02, phi * 1.02, N, 0.3, G, 0.28, initial=s)
        warm = time.perf_counter() - t
        timing[name] = {"cold_s": cold, "sweeps": s.sweeps, "warm_start_s": warm, "warm_sweeps": s2.sweeps}
        print(f"{name:28s} {cold * 1e3:7.1f} ms ({s.sweeps} sweeps); warm-started neighbour {warm * 1e3:6.1f} ms "
              f"({s2.sweeps} sweeps)")
    t = time.perf_counter()
    kalker_exact(a * 1.1, b, 1e-4, 0, 0, N, 0.3, G, 0.28)
    build = time.perf_counter() - t
    print(f"new a/b (operator build + solve): {build:.2f} s")
    out = {"machine": platform.processor() or platform.machine(), "grid": "80 x 20 (default)", "slopes": rows,
           "timing": timing, "new_a_over_b_seconds": build}
    path = Path(__file__).parent / "results" / "kalker_exact.json"
    path.write_text(json.dumps(out, indent=1))
    print("wrote", path)


if __name__ == "__main__":
    main()
