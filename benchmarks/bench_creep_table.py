"""Creep table (exudyn_wheelrail.creep.table): lookup time and table-vs-generator accuracy.

Measures
--------
1. Lookup time of the compiled core ``table_core`` called from a numba loop (warm, after compilation), cubic and
   linear interpolation, including the evaluation of C11, C22 (``kalker_coefficients_core``) per call; and, for
   information, the Python wrapper ``table_forces``.
2. Table-vs-reference error on random **off-grid** points (default 4000, seed 1): a/b log-uniform 0.05–20, the
   length of the normalised creepage vector log-uniform 0.01–20 (linear range to deep saturation), random
   direction; every other point without spin (φ = 0).  Each point gets its own physical scale
   (c 3–8 mm, N 5–100 kN, μ 0.15–0.5, G 81 GPa), so the dimensional-analysis claim is tested too.  Errors: |ΔF|/(μN)
   with ΔF the (Fx, Fy) vector difference, and |ΔMz|/(μNc); max, RMS, 99 % and 99.9 % quantiles.
3. Beyond the table: the reference at r = 2·r_max … 100·r_max against the table (scaled back onto r_max).
4. ν: a table built at ν = 0.28 looked up at ν = 0.25 … 0.31 (``table_forces`` accepts ±0.02; measured here
   through the compiled core, also outside the band) vs the generator at that ν,
   against the baseline of a table built at that ν (the difference is the extra error of the approximation).
   Three-flexibility FASTSIM is ν-invariant under the table's normalisation except through C23 in spin (its
   flexibilities are ∝ 1/C11, 1/C22, 1/C23), which would hide the effect; the main measurement uses FASTSIM's
   *weighted* flexibility, whose full-slip force opposes the creepage as in the exact theory (a proxy).

``--reference fastsim`` (default): the FASTSIM-built tables are built here (``build_table``, grid ``--grid``) in
a temporary directory, or read with ``--table``.  ``--reference exact``: the table given by ``--table`` (default
the package table) against ``kalker_exact`` (imported only then; ~10–50 ms a point: use ``--points``).

Run:  python benchmarks/bench_creep_table.py [--reference fastsim|exact] [--table PATH] [--points N]
Writes benchmarks/results/creep_table.json.
"""
from __future__ import annotations

import argparse
import json
import math
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from numba import njit

from exudyn_wheelrail.creep.build_table import build_table, case_count
from exudyn_wheelrail.creep.fastsim import fastsim_core
from exudyn_wheelrail.creep.linear import _COEF, _T_NODES, kalker_coefficients, kalker_coefficients_core
from exudyn_wheelrail.creep.table import (TABLE_PATH, load_table, normalisation_coefficients, physical_creepages,
                                          table_core, table_forces)

RESULTS = Path(__file__).resolve().parent / "results" / "creep_table.json"


@njit(cache=False)
def _lookup_loop(a, b, xi, eta, phi, N, mu, G, nu, t_nodes, t_breaks, r_pad, th_pad, ps_pad, values_pad, order):
    acc = 0.0
    for i in range(a.size):
        ab = a[i] / b[i]
        ab = min(max(ab, 0.1), 10.0)
        c11, c22, c23 = kalker_coefficients_core(math.log(ab), nu, _T_NODES, _COEF, 0)
        Fx, Fy, Mz = table_core(a[i], b[i], xi[i], eta[i], phi[i], N, mu, G, c11, c22, t_nodes, t_breaks, r_pad,
                                th_pad, ps_pad, values_pad, order)
        acc += Fx + Fy + Mz
    return acc


def time_lookup(table, n=20000, repeats=7):
    rng = np.random.default_rng(3)
    ab = np.exp(rng.uniform(math.log(0.05), math.log(20.0), n))
    c = 6e-3
    a, b = c * np.sqrt(ab), c / np.sqrt(ab)
    xi = rng.uniform(-3e-3, 3e-3, n)
    eta = rng.uniform(-3e-3, 3e-3, n)
    phi = rng.uniform(-2.0, 2.0, n)
    out = {}
    for name, order in (("cubic", 3), ("linear", 1)):
        _lookup_loop(a[:2], b[:2], xi[:2], eta[:2], phi[:2], 1e4, 0.3, 8.1e10, 0.28, *table.core_arrays(), order)
        ts = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            _lookup_loop(a, b, xi, eta, phi, 1e4, 0.3, 8.1e10, 0.28, *table.core_arrays(), order)
            ts.append((time.perf_counter() - t0) / n * 1e6)
        out[f"core_{name}_us"] = dict(median=float(np.median(ts)), min=float(min(ts)), max=float(max(ts)))
    table_forces(a[0], b[0], xi[0], eta[0], phi[0], 1e4, 0.3, 8.1e10, 0.28, table=table)
    ts = []
    for _ in range(3):
        t0 = time.perf_counter()
        for i in range(2000):
            table_forces(a[i], b[i], xi[i], eta[i], phi[i], 1e4, 0.3, 8.1e10, 0.28, table=table)
        ts.append((time.perf_counter() - t0) / 2000 * 1e6)
    out["python_wrapper_cubic_us"] = dict(median=float(np.median(ts)), min=float(min(ts)), max=float(max(ts)))
    return out


# ------------------------------------------------------------------------------------------------------------
# references
# ------------------------------------------------------------------------------------------------------------
def make_reference(kind, options=None):
    """A function ``(a, b, xi, eta, phi, N, mu, G, nu) -> (Fx, Fy, Mz)``: the generator the table is compared to."""
    options = dict(options or {})
    if kind == "fastsim":
        n_x = int(options.get("n_x", 48))
        n_y = int(options.get("n_y", 16))
        weighted = 1 if options.get("flexibility", "three") == "weighted" else 0

        def ref(a, b, xi, eta, phi, N, mu, G, nu):
            ab = min(max(a / b, 0.1), 10.0)          # the stand-in's clamped coefficients (build_table)
            c11, c22, c23 = kalker_coefficients(ab, nu)
            return fastsim_core(a, b, xi, eta, phi, N, mu, G, c11, c22, c23, n_x, n_y, weighted)
        return ref
    if kind == "exact":
        from exudyn_wheelrail.creep.kalker_exact import kalker_exact    # lazily: only for this reference

        def ref(a, b, xi, eta, phi, N, mu, G, nu):
            return kalker_exact(a, b, xi, eta, phi, N, mu, G, nu, **options)
        return ref
    raise ValueError(f"unknown reference {kind!r}")


def random_points(n, seed=1, ratio_range=(0.05, 20.0), r_range=(0.01, 20.0)):
    """Random off-grid cases: dict of arrays (a, b, xi, eta, phi, N, mu, G, spin mask, r)."""
    rng = np.random.default_rng(seed)
    ab = np.exp(rng.uniform(math.log(ratio_range[0]), math.log(ratio_range[1]), n))
    r = np.exp(rng.uniform(math.log(r_range[0]), math.log(r_range[1]), n))
    d = rng.normal(size=(n, 3))
    spin = np.arange(n) % 2 == 1            # alternate, so that every prefix has both kinds
    d[~spin, 2] = 0.0
    d /= np.linalg.norm(d, axis=1)[:, None]
    v = d * r[:, None]
    c = rng.uniform(3e-3, 8e-3, n)
    N = np.exp(rng.uniform(math.log(5e3), math.log(1e5), n))
    mu = rng.uniform(0.15, 0.5, n)
    G = np.full(n, 8.1e10)
    a, b = c * np.sqrt(ab), c / np.sqrt(ab)
    return dict(a=a, b=b, vhat=v, N=N, mu=mu, G=G, spin=spin, r=r, ab=ab)


def errors(table, ref, pts, nu=0.28, interpolation="cubic", scale_r=None, any_nu=False):
    """Normalised errors |ΔF|/(μN), |ΔMz|/(μNc) of the table against ``ref`` at the points (``table_forces``;
    ``any_nu``: the compiled core directly, to measure also outside the accepted ν band)."""
    n = pts["a"].size
    dF = np.empty(n)
    dM = np.empty(n)
    for i in range(n):
        a, b, N, mu, G = pts["a"][i], pts["b"][i], pts["N"][i], pts["mu"][i], pts["G"][i]
        C11, C22 = normalisation_coefficients(a / b, nu)
        xh, eh, ph = pts["vhat"][i] * (1.0 if scale_r is None else scale_r[i])
        xi, eta, phi = physical_creepages(a, b, xh, eh, ph, N, mu, G, C11, C22)
        if any_nu:
            T = table_core(a, b, xi, eta, phi, N, mu, G, C11, C22, *table.core_arrays(),
                           3 if interpolation == "cubic" else 1)
        else:
            T = table_forces(a, b, xi, eta, phi, N, mu, G, nu, table=table, interpolation=interpolation)
        R = ref(a, b, xi, eta, phi, N, mu, G, nu)
        dF[i] = math.hypot(T[0] - R[0], T[1] - R[1]) / (mu * N)
        dM[i] = abs(T[2] - R[2]) / (mu * N * math.sqrt(a * b))
    return dF, dM


def summary(dF, dM, spin=None):
    def s(x):
        return dict(max=float(x.max()), rms=float(np.sqrt(np.mean(x ** 2))), q99=float(np.quantile(x, 0.99)),
                    q999=float(np.quantile(x, 0.999)), n=int(x.size))
    out = dict(all=dict(F=s(dF), Mz=s(dM)))
    if spin is not None:
        out["no_spin"] = dict(F=s(dF[~spin]), Mz=s(dM[~spin]))
        out["spin"] = dict(F=s(dF[spin]), Mz=s(dM[spin]))
    return out


def _row(label, res, key="all"):
    F, M = res[key]["F"], res[key]["Mz"]
    return (f"| {label} | {key} | {100 * F['max']:.2f} | {100 * F['rms']:.3f} | {100 * F['q999']:.2f} | "
            f"{100 * M['max']:.2f} | {100 * M['rms']:.3f} | {100 * M['q999']:.2f} |")


HEADER = ("| table | points | ΔF max [% μN] | ΔF RMS [% μN] | ΔF 99.9 % [% μN] | ΔMz max [% μNc] | "
          "ΔMz RMS [% μNc] | ΔMz 99.9 % [% μNc] |\n|---|---|---:|---:|---:|---:|---:|---:|")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--reference", default="fastsim", choices=("fastsim", "exact"))
    p.add_argument("--table", default=None, help="table file (default: build FASTSIM tables here / the package "
                                                 "table for --reference exact)")
    p.add_argument("--grid", default="default", choices=("default", "coarse"))
    p.add_argument("--points", type=int, default=4000)
    p.add_argument("--workers", type=int, default=None)
    p.add_argument("--no-nu", action="store_true", help="skip the Poisson-ratio measurement (4 extra builds)")
    p.add_argument("--out", default=str(RESULTS))
    args = p.parse_args(argv)
    t_start = time.perf_counter()
    res = dict(reference=args.reference, points=args.points, grid=args.grid, case_count=case_count(args.grid),
               python=sys.version.split()[0], platform=platform.platform(), processor=platform.processor())
    pts = random_points(args.points)
    tmp = tempfile.TemporaryDirectory(prefix="creep_table_bench_")

    def fastsim_table(nu=0.28, **options):
        tag = "_".join(f"{k}{v}" for k, v in sorted(options.items())) or "default"
        path = Path(tmp.name) / f"fastsim_{args.grid}_nu{nu}_{tag}.npz"
        t0 = time.perf_counter()
        build_table(path, generator="fastsim", grid=args.grid, workers=args.workers, poisson=nu, options=options,
                    progress=None)
        res.setdefault("builds", []).append(dict(nu=nu, options=options, seconds=time.perf_counter() - t0))
        return load_table(path)

    print("## Creep table benchmark\n")
    if args.reference == "fastsim":
        main_table = load_table(args.table) if args.table else fastsim_table()
        ref_opts = dict(main_table.metadata.get("generator_options", {}))
    else:
        main_table = load_table(args.table or TABLE_PATH)
        ref_opts = {k: v for k, v in main_table.metadata.get("generator_options", {}).items() if k != "warm_start"}
    res["table_metadata"] = main_table.metadata
    print(f"table: generator {main_table.generator} {main_table.metadata.get('generator_options')}, grid "
          f"{main_table.metadata.get('grid')}, {main_table.metadata.get('case_count')} cases; reference "
          f"{args.reference} {ref_opts}; {args.points} random off-grid points\n")

    # 1. lookup time
    res["timing"] = time_lookup(main_table)
    tm = res["timing"]
    print("| call | median µs | min–max µs |\n|---|---:|---:|")
    for k in ("core_cubic_us", "core_linear_us", "python_wrapper_cubic_us"):
        print(f"| {k[:-3]} | {tm[k]['median']:.3f} | {tm[k]['min']:.3f}–{tm[k]['max']:.3f} |")
    print("(core: numba loop, warm, including C11, C22 from kalker_coefficients_core per call)\n")

    # 2. off-grid errors
    ref = make_reference(args.reference, ref_opts)
    res["errors"] = {}
    print(HEADER)
    for interp in ("cubic", "linear"):
        dF, dM = errors(main_table, ref, pts, interpolation=interp)
        res["errors"][interp] = summary(dF, dM, pts["spin"])
        for key in ("all", "no_spin", "spin"):
            print(_row(f"{main_table.generator} {interp}", res["errors"][interp], key))
    if args.reference == "fastsim" and not args.table:
        # FASTSIM's own discretisation roughness (n_y = 16 strips) vs the table's interpolation error
        opts = dict(n_x=64, n_y=48)
        fine = fastsim_table(**opts)
        dF, dM = errors(fine, make_reference("fastsim", opts), pts)
        res["errors"]["cubic_fastsim_64x48"] = summary(dF, dM, pts["spin"])
        for key in ("all", "spin"):
            print(_row("fastsim n_x=64 n_y=48 cubic", res["errors"]["cubic_fastsim_64x48"], key))
    print()

    # 3. beyond the table's edge
    n_edge = min(1000, args.points)
    sub = {k: (v[:n_edge] if isinstance(v, np.ndarray) else v) for k, v in pts.items()}
    rng = np.random.default_rng(7)
    factor = main_table.r_max * np.exp(rng.uniform(math.log(2.0), math.log(100.0), n_edge)) / sub["r"]
    dF, dM = errors(main_table, ref, sub, scale_r=factor)
    res["beyond_edge"] = summary(dF, dM)
    res["beyond_edge"]["r_over_rmax"] = [2.0, 100.0]
    print(f"beyond the edge (r = 2–100 r_max = {main_table.r_max:g}, {n_edge} points, scaled back onto r_max): "
          f"ΔF max {100 * res['beyond_edge']['all']['F']['max']:.2f} % μN, RMS "
          f"{100 * res['beyond_edge']['all']['F']['rms']:.3f} %; ΔMz max "
          f"{100 * res['beyond_edge']['all']['Mz']['max']:.2f} % μNc, RMS "
          f"{100 * res['beyond_edge']['all']['Mz']['rms']:.3f} %\n")

    # 4. Poisson ratio
    if args.reference == "fastsim" and not args.no_nu:
        res["poisson"] = {}
        n_nu = min(2000, args.points)
        sub = {k: (v[:n_nu] if isinstance(v, np.ndarray) else v) for k, v in pts.items()}
        print("Poisson ratio: table at ν_table looked up at ν (normalisation with C11, C22 at ν) vs the generator "
              "at ν; baseline = table built at ν\n")
        print("| generator | ν | table ν | ΔF max | ΔF RMS | ΔMz max | ΔMz RMS |\n|---|---:|---:|---:|---:|---:|---:|")
        for flex, nus in (("weighted", (0.25, 0.27, 0.30, 0.31)), ("three", (0.25, 0.31))):
            t28 = main_table if flex == "three" and not args.table else fastsim_table(0.28, flexibility=flex)
            for nu in nus:
                tnu = fastsim_table(nu, flexibility=flex)
                refnu = make_reference("fastsim", dict(flexibility=flex))
                for label, tab in (("0.28", t28), (f"{nu}", tnu)):
                    dF, dM = errors(tab, refnu, sub, nu=nu, any_nu=True)
                    s = summary(dF, dM)["all"]
                    res["poisson"][f"{flex}_nu{nu}_table{label}"] = s
                    print(f"| FASTSIM {flex} | {nu} | {label} | {100 * s['F']['max']:.2f} | "
                          f"{100 * s['F']['rms']:.3f} | {100 * s['Mz']['max']:.2f} | {100 * s['Mz']['rms']:.3f} |")
        print()
    res["runtime_s"] = time.perf_counter() - t_start
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(res, indent=1, default=lambda o: o.tolist() if isinstance(o, np.ndarray) else str(o)))
    print(f"(written {out}; runtime {res['runtime_s']:.0f} s)")
    tmp.cleanup()


if __name__ == "__main__":
    main()
