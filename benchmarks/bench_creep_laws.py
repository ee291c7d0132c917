"""Cheap creep laws (Shen–Hedrick–Elkins, Polach) and FASTSIM: cost per call and error against Kalker's exact theory.

1. Timing: microseconds per call of the compiled cores ``she_core``, ``polach_core`` and ``fastsim_core`` (default
   grid) called from a numba loop (warm, after compilation: the cost inside a contact kernel), over creepages from
   the linear range to full slip, with spin; for information also the Python wrappers (input checks + Table E.3
   interpolation + numba dispatch).  ``time.perf_counter``, median and min–max of repeats.
2. Accuracy: on random cases — a/b log-uniform in [0.2, 5], ν = 0.28; Kalker's normalised creepages
   ``ν_x = G c² C11 ξ/(3μN)``, ``ν_y = G c² C22 η/(3μN)`` with ``|(ν_x, ν_y)|`` log-uniform in [0.01, 3] (linear to
   fully saturated; the SHE cubic saturates at 1) in a uniformly random direction; half of the cases without
   spin, half with ``ν_φ = G c³ C23 φ/(3μN)``, ``|ν_φ|`` log-uniform in [0.01, 3], random sign — the errors of
   FASTSIM (default grid, three flexibilities), SHE and Polach against Kalker's exact theory
   (``exudyn_wheelrail.creep.kalker_exact``, its default discretisation unless ``--exact-n``), as max and RMS of
   ``|ΔF|/(μN)`` (the force vector (Fx, Fy)) and of ``|ΔMz|/(μN c)``.  The exact solver is imported lazily; if it
   is not available (or fails on every case) only the timing part is run and the error part is reported as
   skipped.  Cases on which the exact solver raises are counted and left out.

Writes ``benchmarks/results/creep_laws.json``.

Run:  python benchmarks/bench_creep_laws.py [--cases 120] [--seed 7] [--exact-n 40] [--exact-budget 600]
"""
from __future__ import annotations

import argparse
import importlib
import json
import math
import os
import platform
import subprocess
import time
from pathlib import Path

import numba
import numpy as np
from numba import njit

from exudyn_wheelrail.creep import DEFAULT_NX, DEFAULT_NY, fastsim, fastsim_core, kalker_coefficients
from exudyn_wheelrail.creep.laws import polach, polach_core, she_core, shen_hedrick_elkins
from exudyn_wheelrail.creep.linear import fastsim_spin_moment_coefficient

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"

G, NU, N, MU = 82e9, 0.28, 1.0e4, 0.3
B = 5e-3
AB_RANGE = (0.2, 5.0)
NORM_RANGE = (0.01, 3.0)


# ---------------------------------------------------------------------------------------------------- machine
def git_state() -> str:
    """Commit of the library under test (read-only git queries) and whether its files differ from it."""
    try:
        root = HERE.parent
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True,
                              timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "exudyn_wheelrail"], cwd=root,
                               capture_output=True, text=True, timeout=10).stdout.strip()
        return head + (" (+ uncommitted changes in exudyn_wheelrail)" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        return "?"


def machine_info() -> dict:
    cpu = ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        load = [round(x, 2) for x in os.getloadavg()]
    except OSError:
        load = []
    return {"cpu_model": cpu, "cpu_count": os.cpu_count(), "python": platform.python_version(),
            "numba": numba.__version__, "numpy": np.__version__, "loadavg_1_5_15": load, "git": git_state()}


# ---------------------------------------------------------------------------------------------------- drivers
@njit(cache=False)
def _loop_she(a, b, xi, eta, phi, C11, C22, C23, C33):
    acc = 0.0
    for i in range(xi.size):
        Fx, Fy, Mz = she_core(a[i], b, xi[i], eta[i], phi[i], N, MU, G, C11[i], C22[i], C23[i], C33[i])
        acc += Fx + Fy + Mz
    return acc


@njit(cache=False)
def _loop_polach(a, b, xi, eta, phi, C11, C22, C23, C33):
    acc = 0.0
    for i in range(xi.size):
        Fx, Fy, Mz = polach_core(a[i], b, xi[i], eta[i], phi[i], N, MU, G, C11[i], C22[i], C23[i], C33[i], 1.0,
                                 1.0)
        acc += Fx + Fy + Mz
    return acc


@njit(cache=False)
def _loop_fastsim(a, b, xi, eta, phi, C11, C22, C23, n_x, n_y):
    acc = 0.0
    for i in range(xi.size):
        Fx, Fy, Mz = fastsim_core(a[i], b, xi[i], eta[i], phi[i], N, MU, G, C11[i], C22[i], C23[i], n_x, n_y, 0)
        acc += Fx + Fy + Mz
    return acc


# ---------------------------------------------------------------------------------------------------- cases
def make_cases(n, seed):
    """Random cases (see the module docstring): list of dicts with a/b, a, b, xi, eta, phi, spin flag and the
    normalised creepages."""
    rng = np.random.default_rng(seed)
    cases = []
    for k in range(n):
        ab = math.exp(rng.uniform(math.log(AB_RANGE[0]), math.log(AB_RANGE[1])))
        a = ab * B
        c = math.sqrt(a * B)
        C11, C22, C23 = kalker_coefficients(ab, NU)
        m = math.exp(rng.uniform(math.log(NORM_RANGE[0]), math.log(NORM_RANGE[1])))
        th = rng.uniform(0.0, 2.0 * math.pi)
        nx, ny = m * math.cos(th), m * math.sin(th)
        spin = k % 2 == 1
        nphi = 0.0
        if spin:
            nphi = math.exp(rng.uniform(math.log(NORM_RANGE[0]), math.log(NORM_RANGE[1]))) * rng.choice([-1.0, 1.0])
        scale = 3.0 * MU * N / (G * c * c)
        cases.append(dict(a_over_b=ab, a=a, b=B, c=c, xi=scale * nx / C11, eta=scale * ny / C22,
                          phi=scale * nphi / (c * C23), nu_x=nx, nu_y=ny, nu_phi=nphi, spin=spin))
    return cases


def _arrays(cases):
    a = np.array([cs["a"] for cs in cases])
    xi = np.array([cs["xi"] for cs in cases])
    eta = np.array([cs["eta"] for cs in cases])
    phi = np.array([cs["phi"] for cs in cases])
    coef = np.array([kalker_coefficients(cs["a_over_b"], NU) for cs in cases])
    c33 = np.array([fastsim_spin_moment_coefficient(cs["a_over_b"], NU) for cs in cases])
    return a, xi, eta, phi, coef[:, 0].copy(), coef[:, 1].copy(), coef[:, 2].copy(), c33


def _time(fn, n_calls, repeats):
    t = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        t.append((time.perf_counter() - t0) / n_calls * 1e6)
    return {"median_us": float(np.median(t)), "min_us": float(min(t)), "max_us": float(max(t)),
            "calls_per_repeat": n_calls, "repeats": repeats}


def timing(seed):
    cases = make_cases(4000, seed + 1000)
    a, xi, eta, phi, C11, C22, C23, C33 = _arrays(cases)
    k = 400   # FASTSIM subset
    # warm-up (compilation)
    _loop_she(a[:2], B, xi[:2], eta[:2], phi[:2], C11[:2], C22[:2], C23[:2], C33[:2])
    _loop_polach(a[:2], B, xi[:2], eta[:2], phi[:2], C11[:2], C22[:2], C23[:2], C33[:2])
    _loop_fastsim(a[:2], B, xi[:2], eta[:2], phi[:2], C11[:2], C22[:2], C23[:2], DEFAULT_NX, DEFAULT_NY)
    rows = {}
    reps = 25   # the cheap laws: 25 x 4000 calls, repeated passes over the case set
    rows["SHE (she_core), numba loop"] = _time(
        lambda: [_loop_she(a, B, xi, eta, phi, C11, C22, C23, C33) for _ in range(reps)], reps * a.size, 9)
    rows["Polach (polach_core), numba loop"] = _time(
        lambda: [_loop_polach(a, B, xi, eta, phi, C11, C22, C23, C33) for _ in range(reps)], reps * a.size, 9)
    rows[f"FASTSIM (fastsim_core {DEFAULT_NX}x{DEFAULT_NY}), numba loop"] = _time(
        lambda: _loop_fastsim(a[:k], B, xi[:k], eta[:k], phi[:k], C11[:k], C22[:k], C23[:k], DEFAULT_NX,
                              DEFAULT_NY), k, 7)
    # Python wrappers (input checks + Table E.3 interpolation + dispatch)
    m = 300
    sub = cases[:m]
    shen_hedrick_elkins(sub[0]["a"], B, 1e-3, 0, 0, N, MU, G, NU)
    polach(sub[0]["a"], B, 1e-3, 0, 0, N, MU, G, NU)
    fastsim(sub[0]["a"], B, 1e-3, 0, 0, N, MU, G, NU)
    for name, fn in [("SHE shen_hedrick_elkins(), Python call", shen_hedrick_elkins),
                     ("Polach polach(), Python call", polach), ("FASTSIM fastsim(), Python call", fastsim)]:
        rows[name] = _time(lambda fn=fn: [fn(cs["a"], B, cs["xi"], cs["eta"], cs["phi"], N, MU, G, NU)
                                          for cs in sub], m, 5)
    return rows


# ---------------------------------------------------------------------------------------------------- accuracy
def load_exact():
    """Kalker's exact solver ``exudyn_wheelrail.creep.kalker_exact`` (function, or module holding the function),
    imported lazily: ``(callable, None)`` or ``(None, reason)``."""
    try:
        creep = importlib.import_module("exudyn_wheelrail.creep")
        obj = getattr(creep, "kalker_exact", None)
        if obj is None:
            obj = importlib.import_module("exudyn_wheelrail.creep.kalker_exact")
        if not callable(obj):
            obj = getattr(obj, "kalker_exact", None)
        if not callable(obj):
            return None, "exudyn_wheelrail.creep.kalker_exact has no callable kalker_exact"
        return obj, None
    except Exception as exc:   # noqa: BLE001 - any import problem means: not available
        return None, f"import failed: {type(exc).__name__}: {exc}"


def _stats(values):
    v = np.asarray(values, dtype=float)
    if v.size == 0:
        return {"max": None, "rms": None, "n": 0}
    return {"max": float(v.max()), "rms": float(math.sqrt(np.mean(v * v))), "n": int(v.size)}


def accuracy(exact, cases, exact_options, budget_s):
    laws = {
        "FASTSIM": lambda cs: fastsim(cs["a"], cs["b"], cs["xi"], cs["eta"], cs["phi"], N, MU, G, NU),
        "SHE": lambda cs: shen_hedrick_elkins(cs["a"], cs["b"], cs["xi"], cs["eta"], cs["phi"], N, MU, G, NU),
        "Polach": lambda cs: polach(cs["a"], cs["b"], cs["xi"], cs["eta"], cs["phi"], N, MU, G, NU),
    }
    rows, failures = [], []
    t0 = time.perf_counter()
    t_exact = 0.0
    for i, cs in enumerate(cases):
        if time.perf_counter() - t0 > budget_s:
            break
        t1 = time.perf_counter()
        try:
            ref = np.array(exact(cs["a"], cs["b"], cs["xi"], cs["eta"], cs["phi"], N, MU, G, NU, **exact_options),
                           dtype=float)
        except Exception as exc:   # noqa: BLE001 - record and go on
            failures.append({"case": i, "error": f"{type(exc).__name__}: {exc}"[:300]})
            t_exact += time.perf_counter() - t1
            continue
        t_exact += time.perf_counter() - t1
        row = {k: cs[k] for k in ("a_over_b", "xi", "eta", "phi", "nu_x", "nu_y", "nu_phi", "spin")}
        row["exact"] = ref.tolist()
        for name, fn in laws.items():
            F = np.array(fn(cs))
            row[name] = F.tolist()
            row[f"{name}_dF"] = float(math.hypot(*(F[:2] - ref[:2])) / (MU * N))
            row[f"{name}_dMz"] = float(abs(F[2] - ref[2]) / (MU * N * cs["c"]))
        rows.append(row)
    summary = {}
    for name in laws:
        summary[name] = {}
        for subset, sel in [("all", lambda r: True), ("no_spin", lambda r: not r["spin"]),
                            ("with_spin", lambda r: r["spin"])]:
            rs = [r for r in rows if sel(r)]
            summary[name][subset] = {"dF_over_muN": _stats([r[f"{name}_dF"] for r in rs]),
                                     "dMz_over_muNc": _stats([r[f"{name}_dMz"] for r in rs])}
        if rows:
            worst = max(rows, key=lambda r: r[f"{name}_dF"])
            summary[name]["worst_force_case"] = {k: worst[k] for k in ("a_over_b", "nu_x", "nu_y", "nu_phi")}
    n_tried = len(rows) + len(failures)
    return {"cases_requested": len(cases), "cases_tried": n_tried, "cases_ok": len(rows),
            "exact_failures": failures, "exact_seconds_per_case": t_exact / max(n_tried, 1),
            "budget_exhausted": n_tried < len(cases), "summary": summary, "cases": rows}


# ---------------------------------------------------------------------------------------------------- main
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, default=120, help="number of random cases for the error part")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--exact-n", type=int, default=None, help="n_x = n_y of the exact solver (default: its own)")
    ap.add_argument("--exact-budget", type=float, default=600.0, help="seconds allowed for the exact solver")
    args = ap.parse_args(argv)
    t_start = time.perf_counter()
    info = machine_info()
    print(f"CPU: {info['cpu_model']} ({info['cpu_count']} logical CPUs), Python {info['python']}, numba "
          f"{info['numba']}; library at git {info['git']}")

    rows = timing(args.seed)
    print("\n| call | µs per call (median) | min–max |\n|---|---:|---:|")
    for name, r in rows.items():
        print(f"| {name} | {r['median_us']:.3f} | {r['min_us']:.3f}–{r['max_us']:.3f} |")

    out = {"machine": info, "settings": {"G": G, "poisson": NU, "normal_force": N, "mu": MU, "b": B,
                                         "a_over_b_range": AB_RANGE, "normalised_creepage_range": NORM_RANGE,
                                         "fastsim_grid": [DEFAULT_NX, DEFAULT_NY], "seed": args.seed},
           "timing_us": rows}

    exact, reason = load_exact()
    if exact is None:
        print(f"\nError part SKIPPED: Kalker's exact solver is not available ({reason}).")
        out["accuracy"] = {"skipped": True, "reason": reason}
    else:
        exact_options = {} if args.exact_n is None else {"n_x": args.exact_n, "n_y": args.exact_n}
        cases = make_cases(args.cases, args.seed)
        acc = accuracy(exact, cases, exact_options, args.exact_budget)
        acc["exact_options"] = exact_options
        if acc["cases_ok"] == 0:
            msg = (f"the exact solver failed on all {acc['cases_tried']} cases tried"
                   + (f" (first: {acc['exact_failures'][0]['error']})" if acc["exact_failures"] else ""))
            print(f"\nError part SKIPPED: {msg}.")
            out["accuracy"] = {"skipped": True, "reason": msg, "exact_failures": acc["exact_failures"]}
        else:
            out["accuracy"] = acc
            print(f"\nErrors against Kalker's exact theory (kalker_exact {exact_options or 'defaults'}): "
                  f"{acc['cases_ok']} cases ({acc['cases_tried']} tried, {len(acc['exact_failures'])} exact-solver "
                  f"failures{', time budget exhausted' if acc['budget_exhausted'] else ''}; "
                  f"{acc['exact_seconds_per_case']:.2f} s per exact case)")
            print("\n| law | subset | n | max abs(dF)/(muN) | RMS abs(dF)/(muN) | max abs(dMz)/(muN c) | "
                  "RMS abs(dMz)/(muN c) |\n|---|---|---:|---:|---:|---:|---:|")
            for name, s in acc["summary"].items():
                for subset in ("all", "no_spin", "with_spin"):
                    f, m = s[subset]["dF_over_muN"], s[subset]["dMz_over_muNc"]
                    if f["n"] == 0:
                        continue
                    print(f"| {name} | {subset} | {f['n']} | {f['max']:.4f} | {f['rms']:.4f} | {m['max']:.4f} | "
                          f"{m['rms']:.4f} |")
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / "creep_laws.json"
    out["runtime_s"] = time.perf_counter() - t_start
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(out, fh, indent=1)
    print(f"\n(written {path}; runtime {out['runtime_s']:.0f} s)")


if __name__ == "__main__":
    main()
