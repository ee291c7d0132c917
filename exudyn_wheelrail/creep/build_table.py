"""Build a USETAB-style creep table (:mod:`exudyn_wheelrail.creep.table`) with a rolling-contact solver.

Command line (one reproducible command)::

    python -m exudyn_wheelrail creep-table --out PATH [--generator exact|fastsim] [--workers N]
                                           [--grid coarse|default] [--nu 0.28] [--option KEY=VALUE ...]

Generators
----------
* ``exact`` (default): Kalker's exact theory, :func:`exudyn_wheelrail.creep.kalker_exact.kalker_exact` at its
  default discretisation unless ``--option`` says otherwise (imported only when used).
* ``fastsim``: FASTSIM (:func:`exudyn_wheelrail.creep.fastsim.fastsim_core`), ~10 µs a case — a stand-in to
  develop and validate the machinery.  Outside Table E.3's range (a/b < 0.1 or > 10) FASTSIM's flexibilities use
  C11, C22, C23 at the clamped ratio (``fastsim()`` itself refuses such ratios): a stand-in, not a model there.

Every case is one *canonical* dimensional problem (``CANONICAL``: c = 5 mm, N = 10 kN, μ = 0.3, G = 80 GPa; the
normalised results do not depend on this choice — dimensional analysis, module :mod:`~exudyn_wheelrail.creep.table`)
with ``a = c √(a/b)``, ``b = c / √(a/b)`` and the physical creepages of the node's normalised ones.

Cases, order, chunks, resume
----------------------------
The grid's nodes are (a/b, r, θ, ψ) (see :mod:`~exudyn_wheelrail.creep.table`).  r = 0 gives zero force and is not
solved; at a pole ψ = ±π/2 every θ is the same creepage, solved once.  One *chunk* = all cases of one (a/b, θ)
pair, solved in the order ψ ascending and along r back and forth (r up for one ψ, down for the next), so that
consecutive cases are neighbouring creepages: a generator that accepts a warm start (``initial_guess`` in
:func:`solve_chunk`; the exact solver's ``initial_traction`` with ``--option warm_start=1``) gets the previous
case's solution.  Each chunk starts cold, so the result of a chunk does not depend on the workers or the order in
which chunks run: the output is deterministic (bit-identical arrays for the same generator, options, grid and
machine arithmetic).

Chunks run in a ``concurrent.futures.ProcessPoolExecutor`` (``--workers``, default: the machine's cores) and each
finished chunk is written at once to ``PATH.parts/chunk_NNNNN.npz``, stamped with a fingerprint of the build
(generator, options, ν, grid, normalisation, format).  Re-running the same command resumes: chunks already on disk
with the same fingerprint are not solved again.  After the last chunk the table is assembled, written atomically,
and the parts directory removed (``--keep-parts`` keeps it).

Budget: the build must finish within 60 min on 2 cores.  The default grid has 114 426 cases (:func:`case_count`,
:func:`grid_summary`): 10 / 29 / 48 min at 10 / 30 / 50 ms per exact case on 2 cores; the coarse grid 15 408 cases
(1 / 4 / 6 min).  (Measured while this module was written, on the shared 2-core machine under load: the exact
solver at its then defaults n_x = 80, n_y = 20 took 80–200 ms per table case, i.e. the default grid would need
1.3–3 h — use a faster solver setting via ``--option``, a warm start, or the coarse grid until then.)
"""
from __future__ import annotations

import concurrent.futures as cf
import datetime as _dt
import hashlib
import importlib
import inspect
import json
import math
import os
import platform
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from .. import __version__
from .fastsim import DEFAULT_NX, DEFAULT_NY, fastsim_core
from .linear import A_OVER_B_MAX, A_OVER_B_MIN, kalker_coefficients, table_poisson
from .table import (FASTSIM_TABLE_PATH, FORMAT, FORMAT_VERSION, NORMALISATION, NU_TABLE, TABLE_PATH,
                    normalisation_coefficients, physical_creepages, save_table)

__all__ = ["CANONICAL", "GENERATORS", "make_grid", "case_count", "grid_summary", "chunk_cases",
           "solve_chunk", "evaluate_case", "build_table", "generator_function"]

#: The canonical dimensional problem every case is solved on.
CANONICAL = dict(c=5e-3, normal_force=1.0e4, mu=0.3, shear_modulus=8.0e10)

GENERATORS = ("exact", "fastsim")


def _ratio_nodes(n_inner, n_outer):
    """a/b nodes: log-spaced 0.1 … 10 (n_inner nodes, both ends included, breaks of the normalisation) and n_outer
    log-spaced nodes on each side out to 0.05 and 20."""
    inner = np.geomspace(A_OVER_B_MIN, A_OVER_B_MAX, n_inner)
    lo = np.geomspace(0.05, A_OVER_B_MIN, n_outer + 1)[:-1]
    hi = np.geomspace(A_OVER_B_MAX, 20.0, n_outer + 1)[1:]
    nodes = np.concatenate((lo, inner, hi))
    breaks = np.isclose(nodes, A_OVER_B_MIN, rtol=1e-12) | np.isclose(nodes, A_OVER_B_MAX, rtol=1e-12)
    return nodes, breaks


def _sym_psi(n_half):
    """ψ nodes from -π/2 to π/2, symmetric, with 0; ``n_half`` intervals on each side."""
    half = np.linspace(0.0, math.pi / 2, n_half + 1)
    return np.concatenate((-half[:0:-1], half))


def make_grid(name: str = "default") -> dict:
    """Node lists of a named grid: ``ratio_nodes``, ``ratio_breaks``, ``r_nodes``, ``theta_nodes``, ``psi_nodes``.

    default: r with two nodes close to 0 (0.001, 0.01: the cubic's slope at r = 0 comes from the odd continuation,
    i.e. the secant F(r1)/r1, so a tiny first node keeps the small-creepage slopes — Kalker's linear coefficients
    — to ~0.1 %), dense where adhesion turns into sliding (0.05 … 3), geometric to r_max = 1000 (full sliding);
    θ every π/22, ψ every π/28, a/b ratio 1.78 inside 0.1 … 10 and 1.41 outside.  See the benchmark for the
    measured accuracy.  coarse: about a seventh of the cases (quick builds, tests of the machinery)."""
    if name == "default":
        ratio, breaks = _ratio_nodes(9, 2)
        r = np.concatenate(([0.0, 0.001, 0.01, 0.05, 0.1, 0.15, 0.2, 0.27, 0.35, 0.45, 0.55, 0.7, 0.85, 1.0, 1.2,
                             1.45, 1.75, 2.1, 2.6], np.geomspace(3.3, 1000.0, 9)))
        theta = np.linspace(0.0, math.pi / 2, 12)
        psi = _sym_psi(14)
    elif name == "coarse":
        ratio, breaks = _ratio_nodes(7, 1)
        r = np.concatenate(([0.0, 0.002, 0.03, 0.1, 0.25, 0.45, 0.7, 1.0, 1.4, 2.0], np.geomspace(3.0, 1000.0, 7)))
        theta = np.linspace(0.0, math.pi / 2, 7)
        psi = _sym_psi(8)
    else:
        raise ValueError(f"unknown grid {name!r}; choose 'default' or 'coarse'")
    return dict(name=name, ratio_nodes=ratio, ratio_breaks=breaks, r_nodes=r, theta_nodes=theta, psi_nodes=psi)


def _grid_of(grid):
    if isinstance(grid, str):
        return make_grid(grid)
    g = dict(grid)
    g.setdefault("name", "custom")
    for k in ("ratio_nodes", "r_nodes", "theta_nodes", "psi_nodes"):
        g[k] = np.asarray(g[k], float)
    if "ratio_breaks" not in g:
        g["ratio_breaks"] = (np.isclose(g["ratio_nodes"], A_OVER_B_MIN, rtol=1e-12)
                             | np.isclose(g["ratio_nodes"], A_OVER_B_MAX, rtol=1e-12))
    g["ratio_breaks"] = np.asarray(g["ratio_breaks"], bool)
    return g


def _is_pole(psi):
    return abs(abs(psi) - math.pi / 2) < 1e-12


def chunk_cases(grid) -> list:
    """The chunks of a grid: a list of ``(i_ratio, i_theta, cases)``, ``cases`` = list of ``(i_r, i_psi)`` in
    solving order (ψ ascending, r back and forth; r = 0 and the repeated pole cases left out — they are filled when
    the table is assembled).  The pole cases belong to the chunk θ = 0."""
    g = _grid_of(grid)
    nr, nth, nps = g["r_nodes"].size, g["theta_nodes"].size, g["psi_nodes"].size
    chunks = []
    for it in range(g["ratio_nodes"].size):
        for ith in range(nth):
            cases = []
            up = True
            for ips in range(nps):
                if _is_pole(g["psi_nodes"][ips]) and ith != 0:
                    continue
                rs = range(1, nr) if up else range(nr - 1, 0, -1)
                cases.extend((ir, ips) for ir in rs)
                up = not up
            chunks.append((it, ith, cases))
    return chunks


def case_count(grid="default") -> int:
    """Number of generator calls of a build."""
    return sum(len(c[2]) for c in chunk_cases(grid))


def grid_summary(grid="default") -> str:
    g = _grid_of(grid)
    n = case_count(g)
    lines = [f"grid {g['name']}: {g['ratio_nodes'].size} a/b x {g['r_nodes'].size} r x {g['theta_nodes'].size} "
             f"theta x {g['psi_nodes'].size} psi nodes; {n} generator calls"]
    for ms in (10, 30, 50):
        lines.append(f"  exact solver at {ms} ms/case on 2 cores: {n * ms / 1000 / 2 / 60:.0f} min")
    return "\n".join(lines)


# ----------------------------------------------------------------------------------------------------------------
# generators
# ----------------------------------------------------------------------------------------------------------------
def generator_function(generator: str):
    """The solver behind a generator name (the exact solver imported lazily)."""
    if generator == "exact":
        try:
            mod = importlib.import_module("exudyn_wheelrail.creep.kalker_exact")
        except ImportError as exc:
            raise RuntimeError("generator 'exact' needs exudyn_wheelrail.creep.kalker_exact, which is not "
                               f"available ({exc})") from exc
        return mod.kalker_exact
    if generator == "fastsim":
        return fastsim_core
    raise ValueError(f"unknown generator {generator!r}; choose one of {GENERATORS}")


def _fastsim_options(options):
    opts = dict(n_x=DEFAULT_NX, n_y=DEFAULT_NY, flexibility="three")
    unknown = set(options) - set(opts)
    if unknown:
        raise ValueError(f"unknown FASTSIM option(s) {sorted(unknown)}; known: {sorted(opts)}")
    opts.update(options)
    if opts["flexibility"] not in ("three", "weighted"):
        raise ValueError(f"flexibility must be 'three' or 'weighted', got {opts['flexibility']!r}")
    opts["n_x"] = int(opts["n_x"])
    opts["n_y"] = int(opts["n_y"])
    return opts


#: The exact solver's settings for the shipped table: a 64 x 16 grid (about 0.3 % of the force from the 80 x 20
#: default in the linear range, 2.4x cheaper per sweep), traction tolerance 1e-6 of μ max p_n, and a warm start
#: from the neighbouring case — so the build fits the 60-minute budget on 2 cores
#: (``benchmarks/bench_creep_table.py --reference exact`` measures the table against the default grid).
EXACT_TABLE_OPTIONS = {"n_x": 64, "n_y": 16, "tol": 1e-6, "warm_start": True}


def _exact_options(options):
    opts = dict(EXACT_TABLE_OPTIONS)
    opts.update(options)
    opts["warm_start"] = bool(int(opts.get("warm_start", 0)))
    for key in ("n_x", "n_y"):
        opts[key] = int(opts[key])
    opts["tol"] = float(opts["tol"])
    return opts


def resolved_options(generator: str, options: dict | None) -> dict:
    """Generator options with defaults filled in (what the metadata records)."""
    options = dict(options or {})
    if generator == "fastsim":
        return _fastsim_options(options)
    if generator == "exact":
        return _exact_options(options)
    raise ValueError(f"unknown generator {generator!r}; choose one of {GENERATORS}")


class _Case:
    """Per-(a/b) constants of the canonical problem, shared by all cases of a chunk."""

    def __init__(self, generator, options, a_over_b, poisson):
        c, N, mu, G = CANONICAL["c"], CANONICAL["normal_force"], CANONICAL["mu"], CANONICAL["shear_modulus"]
        self.generator, self.options, self.poisson = generator, options, float(poisson)
        sq = math.sqrt(a_over_b)
        self.a, self.b, self.c, self.N, self.mu, self.G = c * sq, c / sq, c, N, mu, G
        self.C11, self.C22 = normalisation_coefficients(a_over_b, poisson)
        self.fn = generator_function(generator)
        if generator == "fastsim":
            ab = min(max(a_over_b, A_OVER_B_MIN), A_OVER_B_MAX)
            self.fastsim_coefficients = kalker_coefficients(ab, poisson)
            self.weighted = 1 if options["flexibility"] == "weighted" else 0
        else:
            self.solver_options = {k: v for k, v in options.items() if k != "warm_start"}
            self.warm = bool(options.get("warm_start"))
            if self.warm:
                mod = importlib.import_module("exudyn_wheelrail.creep.kalker_exact")
                fn = getattr(mod, "kalker_exact_solution", None)
                if fn is None or "initial_traction" not in inspect.signature(fn).parameters:
                    raise ValueError("warm_start=1: kalker_exact_solution(..., initial_traction=...) is not available "
                                     "in exudyn_wheelrail.creep.kalker_exact; build without warm_start")
                self.solution_fn = fn

    def __call__(self, xi_hat, eta_hat, phi_hat, initial_guess=None):
        a, b, N, mu, G = self.a, self.b, self.N, self.mu, self.G
        xi, eta, phi = physical_creepages(a, b, xi_hat, eta_hat, phi_hat, N, mu, G, self.C11, self.C22)
        state = None
        if self.generator == "fastsim":
            c11, c22, c23 = self.fastsim_coefficients
            Fx, Fy, Mz = self.fn(a, b, xi, eta, phi, N, mu, G, c11, c22, c23, self.options["n_x"],
                                 self.options["n_y"], self.weighted)
        elif self.warm:
            sol = self.solution_fn(a, b, xi, eta, phi, N, mu, G, self.poisson, initial_traction=initial_guess,
                                   **self.solver_options)
            Fx, Fy, Mz = sol.Fx_N, sol.Fy_N, sol.Mz_Nm
            state = (sol.px_Pa, sol.py_Pa)
        else:
            Fx, Fy, Mz = self.fn(a, b, xi, eta, phi, N, mu, G, self.poisson, **self.solver_options)
        return (Fx / (mu * N), Fy / (mu * N), Mz / (mu * N * self.c)), state


def evaluate_case(generator: str, options: dict, a_over_b, xi_hat, eta_hat, phi_hat, poisson, initial_guess=None):
    """Solve one normalised case on the canonical problem: returns ``((fx, fy, mz), state)`` with
    ``fx = Fx/(μN)``, ``fy = Fy/(μN)``, ``mz = Mz/(μNc)``; ``state`` is what the next, neighbouring case may use
    as ``initial_guess`` (the exact solver's traction field when ``warm_start`` is on, else None).  ``options``
    as returned by :func:`resolved_options`."""
    return _Case(generator, options, a_over_b, poisson)(xi_hat, eta_hat, phi_hat, initial_guess)


def solve_chunk(job):
    """Worker: solve the cases of one chunk in order.  ``job`` = dict(generator, options, poisson, a_over_b,
    r_nodes, theta, psi_nodes, cases, index).  Returns ``(index, values (n_cases, 3), seconds, failures)``; a case
    the generator fails on is NaN and listed in ``failures`` as ``(i_r, i_psi, message)``."""
    case = _Case(job["generator"], job["options"], job["a_over_b"], job["poisson"])
    r_nodes, psi_nodes, th = job["r_nodes"], job["psi_nodes"], job["theta"]
    cos_th, sin_th = math.cos(th), math.sin(th)
    out = np.full((len(job["cases"]), 3), np.nan)
    failures = []
    state = None          # initial_guess hook: the previous (neighbouring) case's solution
    t0 = time.perf_counter()
    for k, (ir, ips) in enumerate(job["cases"]):
        r, ps = r_nodes[ir], psi_nodes[ips]
        rc = r * math.cos(ps)
        try:
            out[k], state = case(rc * cos_th, rc * sin_th, r * math.sin(ps), initial_guess=state)
        except (RuntimeError, ValueError, ArithmeticError) as exc:
            failures.append((int(ir), int(ips), f"{type(exc).__name__}: {exc}"))
            state = None
    return job["index"], out, time.perf_counter() - t0, failures


# ----------------------------------------------------------------------------------------------------------------
# build
# ----------------------------------------------------------------------------------------------------------------
def _fingerprint(generator, options, poisson, g) -> str:
    h = hashlib.sha256()
    h.update(json.dumps(dict(generator=generator, options=options, poisson=poisson, normalisation=NORMALISATION,
                             format=FORMAT, version=FORMAT_VERSION, canonical=CANONICAL), sort_keys=True).encode())
    for k in ("ratio_nodes", "ratio_breaks", "r_nodes", "theta_nodes", "psi_nodes"):
        h.update(np.ascontiguousarray(g[k], dtype=float).tobytes())
    return h.hexdigest()[:16]


def _assemble(g, chunks, results):
    nt, nr, nth, nps = (g[k].size for k in ("ratio_nodes", "r_nodes", "theta_nodes", "psi_nodes"))
    values = np.full((nt, nr, nth, nps, 3), np.nan)
    values[:, 0] = 0.0
    for idx, (it, ith, cases) in enumerate(chunks):
        vals = results[idx]
        for (ir, ips), v in zip(cases, vals):
            values[it, ir, ith, ips] = v
    for ips in range(nps):
        if _is_pole(g["psi_nodes"][ips]):
            values[:, :, 1:, ips] = values[:, :, :1, ips]
    return values


def _package_version():
    return __version__


def _git_commit():
    try:
        import subprocess
        root = Path(__file__).resolve().parents[2]
        out = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"], capture_output=True,
                             text=True, timeout=5)
        return out.stdout.strip() or None
    except (OSError, ValueError, subprocess.SubprocessError):
        return None


def build_table(out, generator: str = "exact", grid="default", workers: int | None = None,
                poisson: float = NU_TABLE, options: dict | None = None, keep_parts: bool = False,
                progress=print, parts_dir=None) -> Path:
    """Build a creep table and write it to ``out`` (npz).  See the module docstring (chunks, resume, order).

    ``grid``: 'default', 'coarse' or a dict of node lists (``make_grid`` keys).  ``workers``: processes (default
    ``os.cpu_count()``; 1 solves in this process).  ``options``: generator options (FASTSIM: n_x, n_y,
    flexibility; exact: the solver's keyword options plus ``warm_start``).  ``progress``: a print-like callable or
    None.  Raises ``RuntimeError`` if cases failed (the finished chunks stay in the parts directory)."""
    if generator not in GENERATORS:
        raise ValueError(f"unknown generator {generator!r}; choose one of {GENERATORS}")
    poisson = table_poisson(poisson)
    out = Path(out)
    if out.suffix != ".npz":
        raise ValueError(f"--out must be an .npz file, got {out}")
    if generator != "exact" and out.resolve() == TABLE_PATH.resolve():
        raise ValueError(f"{TABLE_PATH.name} is reserved for the exact-solver table; write a {generator} table to "
                         f"another file (e.g. {FASTSIM_TABLE_PATH.name})")
    g = _grid_of(grid)
    opts = resolved_options(generator, options)
    _Case(generator, opts, 1.0, poisson)     # fail early: solver missing, bad options
    workers = (os.cpu_count() or 1) if workers is None else int(workers)
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    say = progress or (lambda *a, **k: None)
    chunks = chunk_cases(g)
    n_cases = sum(len(c[2]) for c in chunks)
    fp = _fingerprint(generator, opts, poisson, g)
    parts = Path(parts_dir) if parts_dir is not None else out.with_name(out.name + ".parts")
    parts.mkdir(parents=True, exist_ok=True)
    results = {}
    for idx in range(len(chunks)):
        f = parts / f"chunk_{idx:05d}.npz"
        if f.is_file():
            try:
                with np.load(f, allow_pickle=False) as z:
                    if str(z["fingerprint"]) == fp and z["values"].shape == (len(chunks[idx][2]), 3):
                        results[idx] = np.array(z["values"])
            except (OSError, ValueError, KeyError):
                pass
    done_cases = sum(len(chunks[i][2]) for i in results)
    say(f"creep table: generator {generator} {opts}, nu {poisson}, grid {g['name']}: {len(chunks)} chunks, "
        f"{n_cases} cases, {workers} worker(s); parts in {parts}")
    if results:
        say(f"  resuming: {len(results)} chunks ({done_cases} cases) already done")
    jobs = [dict(generator=generator, options=opts, poisson=poisson, a_over_b=float(g["ratio_nodes"][it]),
                 r_nodes=g["r_nodes"], theta=float(g["theta_nodes"][ith]), psi_nodes=g["psi_nodes"], cases=cases,
                 index=idx)
            for idx, (it, ith, cases) in enumerate(chunks) if idx not in results]
    failures_all = []
    t_start = time.perf_counter()
    solved = 0
    last_report = 0.0

    def _store(idx, vals, secs, failures):
        nonlocal solved, last_report
        solved += len(vals)
        if failures:
            failures_all.extend((idx, *f) for f in failures)
        else:
            tmp = parts / f"chunk_{idx:05d}.tmp.npz"
            np.savez(tmp, values=vals, fingerprint=np.array(fp))
            tmp.replace(parts / f"chunk_{idx:05d}.npz")
            results[idx] = vals
        el = time.perf_counter() - t_start
        if el - last_report >= 30.0 or len(results) + len({f[0] for f in failures_all}) == len(chunks):
            last_report = el
            left = n_cases - done_cases - solved
            eta = el / solved * left if solved else float("nan")
            say(f"  {done_cases + solved}/{n_cases} cases ({100 * (done_cases + solved) / n_cases:.1f} %), "
                f"{el:.0f} s elapsed, ~{eta:.0f} s left, {1e3 * el * workers / max(solved, 1):.2f} ms/case/worker")

    if workers == 1 or len(jobs) <= 1:
        for job in jobs:
            _store(*solve_chunk(job))
    else:
        with cf.ProcessPoolExecutor(max_workers=workers) as pool:
            futs = [pool.submit(solve_chunk, job) for job in jobs]
            for fut in cf.as_completed(futs):
                _store(*fut.result())
    if failures_all:
        head = "\n".join(f"  chunk {c}, r[{ir}], psi[{ips}]: {msg}" for c, ir, ips, msg in failures_all[:10])
        raise RuntimeError(f"{len(failures_all)} case(s) failed (their chunks were not stored; the finished chunks "
                           f"are kept in {parts} and a re-run resumes):\n{head}")
    values = _assemble(g, chunks, [results[i] for i in range(len(chunks))])
    wall = time.perf_counter() - t_start
    import numba
    meta = dict(format=FORMAT, format_version=FORMAT_VERSION, generator=generator, generator_options=opts,
                poisson=poisson, grid=g["name"], normalisation=NORMALISATION, canonical_problem=CANONICAL,
                case_count=n_cases, build_date=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                package_version=_package_version(), git_commit=_git_commit(), build_seconds=round(wall, 1),
                workers=workers, resumed_chunks=len(chunks) - len(jobs), python=sys.version.split()[0],
                numpy=np.__version__, numba=numba.__version__, platform=platform.platform(),
                fingerprint=fp)
    save_table(out, g["ratio_nodes"], g["ratio_breaks"], g["r_nodes"], g["theta_nodes"], g["psi_nodes"], values,
               meta)
    say(f"wrote {out} ({out.stat().st_size / 1e6:.2f} MB, {n_cases} cases, {wall:.0f} s this run)")
    if not keep_parts:
        shutil.rmtree(parts, ignore_errors=True)
    return out
