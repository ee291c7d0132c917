"""Timing of the Hertz normal-contact kernels (exudyn_wheelrail.contact.normal).

Prints nanoseconds per call of ``hertz_from_penetration`` (and ``hertz_from_force``) called from inside a
numba-compiled loop (the relevant cost in a contact kernel; warm, i.e. after compilation), and, for
information, the cost of one call from the Python interpreter (dominated by numba's dispatcher).

Run:  python benchmarks/bench_hertz.py
"""
from __future__ import annotations

import time

import numpy as np
from numba import njit

from exudyn_wheelrail.contact.normal import (
    effective_modulus,
    hertz_from_force,
    hertz_from_penetration,
)


@njit(cache=False)
def _loop_penetration(A, B, E_star, delta):
    acc = 0.0
    for i in range(A.size):
        N, dN, a, b, status = hertz_from_penetration(A[i], B[i], E_star, delta[i])
        acc += N + dN + a + b + status
    return acc


@njit(cache=False)
def _loop_force(A, B, E_star, N):
    acc = 0.0
    for i in range(A.size):
        d, a, b, status = hertz_from_force(A[i], B[i], E_star, N[i])
        acc += d + a + b + status
    return acc


@njit(cache=False)
def _loop_empty(A, B, E_star, delta):  # loop + memory traffic only, for reference
    acc = 0.0
    for i in range(A.size):
        acc += A[i] + B[i] + E_star + delta[i]
    return acc


def _best_ns(fn, args, n, repeats=7):
    fn(*args)  # compile / warm up
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn(*args)
        best = min(best, time.perf_counter() - t0)
    return best / n * 1e9


def main(n=1_000_000):
    rng = np.random.default_rng(0)
    # wheel-rail-like relative curvatures: A ~ 1 1/m (rolling), B from 0.2 to 50 1/m; a few conformal ones
    A = rng.uniform(0.9, 1.3, n)
    B = np.exp(rng.uniform(np.log(0.2), np.log(50.0), n))
    B[::50] = -0.3  # ~2 % clamped (conformal) inputs
    delta = rng.uniform(-1e-5, 2e-4, n)  # ~5 % out of contact
    N = rng.uniform(0.0, 1.5e5, n)
    Es = effective_modulus(2.1e11, 0.28, 2.1e11, 0.28)

    t_pen = _best_ns(_loop_penetration, (A, B, Es, delta), n)
    t_force = _best_ns(_loop_force, (A, B, Es, N), n)
    t_empty = _best_ns(_loop_empty, (A, B, Es, delta), n)

    hertz_from_penetration(1.0, 2.0, Es, 1e-4)
    m = 100_000
    t0 = time.perf_counter()
    for i in range(m):
        hertz_from_penetration(1.0, 2.0, Es, 1e-4)
    t_py = (time.perf_counter() - t0) / m * 1e9

    print(f"hertz_from_penetration, numba loop (warm): {t_pen:7.1f} ns/call")
    print(f"hertz_from_force,       numba loop (warm): {t_force:7.1f} ns/call")
    print(f"empty loop reference (memory + loop):      {t_empty:7.1f} ns/iter")
    print(f"hertz_from_penetration from Python:        {t_py:7.1f} ns/call (numba dispatcher overhead)")


if __name__ == "__main__":
    main()
