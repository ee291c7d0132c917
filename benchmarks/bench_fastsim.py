"""Timing of FASTSIM (exudyn_wheelrail.creep.fastsim) at the default grid.

Prints microseconds per call of the compiled core ``fastsim_core`` called from a numba loop (warm, after
compilation; the cost inside a contact kernel), and, for information, per call of the Python wrapper ``fastsim``
(input checks + coefficient interpolation + numba dispatch).

Run:  python benchmarks/bench_fastsim.py
"""
from __future__ import annotations

import time

import numpy as np
from numba import njit

from exudyn_wheelrail.creep import DEFAULT_NX, DEFAULT_NY, fastsim, fastsim_core, kalker_coefficients


@njit(cache=False)
def _loop(xi, eta, phi, C11, C22, C23, n_x, n_y):
    acc = 0.0
    for i in range(xi.size):
        Fx, Fy, Mz = fastsim_core(6e-3, 5e-3, xi[i], eta[i], phi[i], 1e4, 0.3, 82e9, C11, C22, C23, n_x, n_y, 0)
        acc += Fx + Fy + Mz
    return acc


def main():
    rng = np.random.default_rng(1)
    n = 2000
    xi = rng.uniform(-3e-3, 3e-3, n)
    eta = rng.uniform(-3e-3, 3e-3, n)
    phi = rng.uniform(-1.0, 1.0, n)
    C11, C22, C23 = kalker_coefficients(6e-3 / 5e-3, 0.28)
    _loop(xi[:2], eta[:2], phi[:2], C11, C22, C23, DEFAULT_NX, DEFAULT_NY)  # compile
    times = []
    for _ in range(7):
        t0 = time.perf_counter()
        _loop(xi, eta, phi, C11, C22, C23, DEFAULT_NX, DEFAULT_NY)
        times.append((time.perf_counter() - t0) / n * 1e6)
    fastsim(6e-3, 5e-3, 1e-3, 0, 0, 1e4, 0.3, 82e9, 0.28)
    tw = []
    for _ in range(3):
        t0 = time.perf_counter()
        for i in range(500):
            fastsim(6e-3, 5e-3, xi[i], eta[i], phi[i], 1e4, 0.3, 82e9, 0.28)
        tw.append((time.perf_counter() - t0) / 500 * 1e6)
    print(f"FASTSIM default grid n_x={DEFAULT_NX}, n_y={DEFAULT_NY} ({DEFAULT_NX * DEFAULT_NY} elements)")
    print("| call | median µs | min–max µs |\n|---|---|---|")
    print(f"| fastsim_core in numba loop (warm) | {np.median(times):.2f} | {min(times):.2f}–{max(times):.2f} |")
    print(f"| fastsim Python wrapper | {np.median(tw):.2f} | {min(tw):.2f}–{max(tw):.2f} |")


if __name__ == "__main__":
    main()
