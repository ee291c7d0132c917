"""Work–precision of the RTRI 20 m case: wall time of the solve against the error of the outputs with respect to a
converged reference, over time step, integrator and contact options.

Case: ``RtriCase`` at the default span (20 m) and representative speed (250 km/h), substitute inputs
(``exudyn_wheelrail.scenarios.rtri``), simulated time 2.5 s for every run (``steps = round(2.5 s / dt)``: the
paper's 2500 steps at 1 ms), outputs recorded (``record=True``: the errors need the time series).

Configurations (one axis varied at a time around the main line, each part selectable):

* ``main``: every time step (``--dt-ms``, default 2, 1, 0.5, 0.25 ms) x every integrator (``--integrators``,
  default all of ``SOLVERS``: newmark, generalized_alpha (ρ∞ 0.8), explicit_midpoint, rk33, rk44, rk67), with
  the creep table of Kalker's exact theory (``creep_law="table"``) and the online contact search
  (``geometry="online"``);
* ``creep``: the other creep laws (``--creep-laws``: ``table_linear`` (the same table, multilinear), ``fastsim``
  (24 x 8), ``shen_hedrick_elkins`` — the cheap law)
  at ``--option-dt-ms`` (default 1, 0.5 ms) with ``--option-integrators`` (default newmark, rk44), online geometry;
* ``geometry``: the precomputed geometry table of the rigid profiles (``geometry="table"``), with the creep table
  interpolated cubically (``table``) and multilinearly (``table_linear``, the ``fast`` preset's), same dt and
  integrators as ``creep``.  ``geometry`` is a field of ``RtriCase`` added separately; while it does not exist
  these rows are skipped with a printed note (and listed under ``skipped`` in the JSON).

Reference: the same case with RK44 at dt = 0.05 ms (50 000 steps), the creep table, the online geometry, and a
fine concave search (``n_concave_wheel = n_concave_rail = 400``, kernel default 100, refinement on).  Its own
convergence is checked with the same error measures as for the runs: against the same settings at 0.1 ms and against
Newmark (β = 1/4, γ = 1/2, the paper's scheme) at 0.05 ms (the cross-check).  RK44 rather than Newmark because it is
the more economical reference (measured, 2 cores shared: 0.1 vs 0.05 ms differ by 0.015 % (peak Y), 0.49 % (RMS Y),
0.1 % (RMS a) with RK44 against 0.03 %, 2.1 %, 0.87 % with Newmark, at 1.2-1.4 x Newmark's solve time);
``--reference-solver newmark`` selects Newmark (the cross-check is then RK44).  The larger of the two differences
per error measure is the reference's resolution (``reference_resolution`` in the JSON, dotted lines in the plot):
smaller errors are not resolved.  The reference time series, its settings and the checks are cached in
``results/work_precision_reference.npz`` and reused when the settings match (``--rebuild-reference`` forces a new
one).

Measured per run:

* wall time = ``summary["solve_seconds"]`` (inside ``mbs.SolveDynamic`` only; model building, compiled-code loading
  and the connector's warm-up call are outside), minimum of ``--repeats`` runs (default 1) after an untimed
  5-step warm-up run of every (integrator, creep law, geometry) combination.  Recording costs one extra contact
  evaluation per step (the recorder's pre-step function evaluates the contact at the state's time) and the Python
  work of filling one row: it is included in the wall time of every run alike (``contact_calls_per_step`` counts
  it).  ``contact_calls_per_step`` counts the force evaluations (``WheelRailContact.n_calls``); an implicit
  solver's Jacobian makes contact calls of its own (one per semi-analytic update, 14 per forward-difference one):
  ``benchmarks/bench_implicit.py`` counts both, per Newton configuration;
* errors against the reference, for the lateral contact force of the right wheel of the leading wheelset
  (``lateral_contact_force_w1_right_N``, the rail on the wheel, track y) and the car-body lateral acceleration above
  the rear bogie (``carbody_lateral_acceleration_rear_m_s2``):
  - peak error: ``|max|x_run| − max|x_ref|| / max|x_ref|`` over the whole run (``summary["peaks"]``);
  - RMS error: ``sqrt(mean((x_run(t_k) − x_ref(t_k))²)) / max|x_ref|`` on the run's time grid t_k (the reference
    linearly interpolated; every dt used is a multiple of 0.05 ms, so it is sampled at its own rows);
  - for information: the same measures restricted to the passage window (``t <= coverage.t_needed_with_run_out_s``,
    the response to the deviation; later the vehicle hunts at 250 km/h, a self-excited oscillation whose phase
    is sensitive to any perturbation) and the relative error of the 10 ms moving-average peak of the force;
* a run whose solve fails (status not "ok"), whose outputs are not finite, or whose peak of either output exceeds
  ``DIVERGED_FACTOR`` (10) times the reference peak is a row with that status and NaN errors.

Outputs: ``results/work_precision.csv`` (one row per run), ``results/work_precision.json`` (machine, date, reference
settings and convergence check, rows, Pareto sets, skipped rows), ``results/work_precision.png`` (log–log wall time
vs peak error and vs RMS error, force and acceleration, markers per integrator and option, Pareto fronts) and a
Markdown table on stdout.

Run:  python benchmarks/work_precision.py [--quick] [--parts main creep geometry] [--repeats 1]
                                          [--rebuild-reference] [--reference-solver rk44]
``--quick``: dt 1 and 0.5 ms, newmark and rk44, online geometry (main and creep parts).  Run it alone on the machine
(one heavy process at a time): the reference takes about a minute of one core, the full design some minutes.
"""
from __future__ import annotations

import argparse
import contextlib
import csv
import dataclasses
import json
import math
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from exudyn_wheelrail.scenarios import rtri_run as rtri
from exudyn_wheelrail.scenarios.rtri import RtriCase, run_rtri
from exudyn_wheelrail.simulation.solvers import SOLVERS

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"

T_END_S = 2.5                    #: simulated time of every run [s] (the paper's 2500 steps of 1 ms)
SPAN_M = 20.0
DT_MS = (2.0, 1.0, 0.5, 0.25)
CREEP_LAWS = ("table", "table_linear", "fastsim", "shen_hedrick_elkins")
#: the creep laws of the geometry rows
GEOMETRY_CREEP_LAWS = ("table", "table_linear")
GEOMETRIES = ("online", "table")
OPTION_DT_MS = (1.0, 0.5)
OPTION_INTEGRATORS = ("newmark", "rk44")
PARTS = ("main", "creep", "geometry")
#: a run whose peak |Y| or |a| exceeds this multiple of the reference peak has diverged
DIVERGED_FACTOR = 10.0
#: the reference: integrator, step, creep law, geometry and concave-search discretisation
REFERENCE = dict(solver="rk44", dt_ms=0.05, check_dt_ms=0.1, creep_law="table", geometry="online",
                 n_concave=400)
Y_COL = "lateral_contact_force_w1_right_N"
A_COL = "carbody_lateral_acceleration_rear_m_s2"
HAS_GEOMETRY = "geometry" in {f.name for f in dataclasses.fields(RtriCase().contact)}

CSV_COLUMNS = ("integrator", "creep_law", "geometry", "dt_ms", "steps", "status", "wall_s", "wall_s_all",
               "us_per_step", "real_time_factor", "contact_calls_per_step",
               "peak_Y_N", "peak_Y_rel_err", "rms_Y_rel_err", "peak_a_m_s2", "peak_a_rel_err", "rms_a_rel_err",
               "peak_Y_10ms_rel_err", "passage_peak_Y_rel_err", "passage_rms_Y_rel_err", "passage_peak_a_rel_err",
               "passage_rms_a_rel_err", "pareto_peak_Y", "pareto_peak_a")


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
        return "unknown"


def machine_info() -> dict:
    info = dict(python=platform.python_version(), platform=platform.platform(), processor=platform.processor(),
                cpu_count=os.cpu_count(), load_average=list(os.getloadavg()), git=git_state(),
                date=time.strftime("%Y-%m-%dT%H:%M:%S%z"))
    try:
        import exudyn
        import numba
        info["exudyn"], info["numba"], info["numpy"] = exudyn.__version__, numba.__version__, np.__version__
    except Exception:  # pragma: no cover
        pass
    return info


# ---------------------------------------------------------------------------------------------------- runs
def make_case(solver: str, dt_s: float, creep_law: str, geometry: str, steps: int | None = None) -> RtriCase:
    """The RTRI 20 m case at 250 km/h over ``T_END_S`` with the given options (``geometry`` only passed when
    ``RtriCase`` has the field)."""
    kw = dict(span_m=SPAN_M, solver=solver, dt_s=dt_s, creep_law=creep_law, record=True,
              duration_s=(steps if steps is not None else round(T_END_S / dt_s)) * dt_s)
    if HAS_GEOMETRY:
        kw["geometry"] = geometry
    elif geometry != "online":
        raise ValueError(f"geometry={geometry!r}: RtriCase has no 'geometry' field yet")
    return RtriCase(**kw)


@contextlib.contextmanager
def concave_discretisation(n: int | None):
    """Run the RTRI case with ``n`` points per wheel region and rail in the contact kernel's concave search
    (``None``: the kernel default).  ``run_rtri`` builds its model through ``rtri.build_scenario``; this wraps it for
    the duration and sets the kernel parameters of the built contact (read at every evaluation)."""
    if n is None:
        yield
        return
    from exudyn_wheelrail.contact import layout as L
    original = rtri.build_scenario

    def build(spec):
        h = original(spec)
        if h.contact is None:
            raise RuntimeError("the RTRI model has no wheel-rail contact: cannot set the concave discretisation of "
                               "the reference")
        params = h.contact.kernel_parameters()
        params[L.P_N_CONCAVE_WHEEL] = n
        params[L.P_N_CONCAVE_RAIL] = n
        return h

    rtri.build_scenario = build
    try:
        yield
    finally:
        rtri.build_scenario = original


def solve(case: RtriCase, n_concave: int | None = None):
    """``run_rtri`` (optionally with a fine concave search); returns the result."""
    with concave_discretisation(n_concave):
        return run_rtri(case)


# ---------------------------------------------------------------------------------------------------- reference
def reference_settings(args) -> dict:
    return dict(case=f"RTRI span {SPAN_M:g} m, {RtriCase().speed_km_h:g} km/h, substitute inputs", span_m=SPAN_M,
                speed_km_h=float(RtriCase().speed_km_h), t_end_s=T_END_S, solver=args.reference_solver,
                dt_s=args.reference_dt_ms * 1e-3, steps=int(round(T_END_S / (args.reference_dt_ms * 1e-3))),
                check_dt_s=args.check_dt_ms * 1e-3, creep_law=REFERENCE["creep_law"],
                geometry=REFERENCE["geometry"], n_concave_wheel=REFERENCE["n_concave"],
                n_concave_rail=REFERENCE["n_concave"], refine=True,
                newton_tolerance=RtriCase().run.newton_tolerance,
                cross_check_solver="newmark" if args.reference_solver == "rk44" else "rk44")


def _series(result) -> dict:
    ts = result.timeseries
    return {"time_s": np.asarray(ts["time_s"]), Y_COL: np.asarray(ts[Y_COL]), A_COL: np.asarray(ts[A_COL])}


def _ref_run(settings: dict, solver: str, dt_s: float, label: str) -> tuple[dict, dict]:
    case = make_case(solver, dt_s, settings["creep_law"], settings["geometry"])
    print(f"reference: {label}: {solver}, dt {dt_s * 1e3:g} ms, {case.run.steps} steps ...", flush=True)
    t0 = time.perf_counter()
    r = solve(case, settings["n_concave_wheel"])
    s = r.summary
    print(f"  {s['status']}, solve {s['solve_seconds']:.1f} s (total {time.perf_counter() - t0:.1f} s)", flush=True)
    if s["status"] != "ok":
        raise RuntimeError(f"reference run {label} failed: {s['status']}")
    info = dict(label=label, solver=solver, dt_s=dt_s, steps=case.run.steps, solve_seconds=s["solve_seconds"],
                contact_calls_per_step=s["contact_calls"] / case.run.steps,
                t_passage_end_s=s["coverage"]["t_needed_with_run_out_s"],
                peak_Y_N=s["peaks"]["max_abs_lateral_contact_force_w1_right_N"],
                peak_Y_10ms_N=s["peaks"].get("max_abs_lateral_contact_force_w1_right_10ms_avg_N"),
                peak_a_m_s2=s["peaks"]["max_abs_carbody_lateral_acceleration_rear_m_s2"])
    return _series(r), info


def load_or_build_reference(args, path: Path) -> dict:
    """The reference series and metadata: from the cache when its settings equal the requested ones, else run
    (reference, the convergence check at ``check_dt``, the cross-check with the other integrator) and store."""
    settings = reference_settings(args)
    if path.exists() and not args.rebuild_reference:
        with np.load(path, allow_pickle=False) as z:
            meta = json.loads(str(z["meta_json"]))
            if meta["settings"] == settings:
                print(f"reference: cached {path.name} (built {meta['built']['date']}, library "
                      f"{meta['built']['git']}; --rebuild-reference to recompute)")
                return dict(series={k: z[k] for k in ("time_s", Y_COL, A_COL)}, meta=meta)
            print(f"reference: cached {path.name} has other settings; rebuilding")
    ref, ref_info = _ref_run(settings, settings["solver"], settings["dt_s"], "reference")
    chk, chk_info = _ref_run(settings, settings["solver"], settings["check_dt_s"], "convergence check")
    conv = {"check": chk_info,
            "errors_of_check_vs_reference": errors(chk, chk_info, ref, ref_info)}
    xs, xs_info = _ref_run(settings, settings["cross_check_solver"], settings["dt_s"], "cross-check")
    conv["cross_check"] = xs_info
    conv["errors_of_cross_check_vs_reference"] = errors(xs, xs_info, ref, ref_info)
    e1, e2 = conv["errors_of_check_vs_reference"], conv["errors_of_cross_check_vs_reference"]
    conv["reference_resolution"] = {k: max(e1[k], e2[k]) for k in e1}
    meta = dict(settings=settings, reference=ref_info, convergence=conv, built=machine_info())
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(path, meta_json=np.array(json.dumps(meta)), **ref)
    print(f"reference: wrote {path} ({path.stat().st_size / 1e6:.2f} MB)")
    return dict(series=ref, meta=meta)


# ---------------------------------------------------------------------------------------------------- errors
def _peak(x):
    return float(np.max(np.abs(x))) if len(x) else math.nan


def errors(run: dict, run_info: dict, ref: dict, ref_info: dict) -> dict:
    """Relative peak and RMS errors of ``run`` against ``ref`` (see module docstring), whole run and passage
    window; the 10 ms-average peak error when both peaks are known."""
    t = run["time_s"]
    t_ref = ref["time_s"]
    out = {}
    for key, col in (("Y", Y_COL), ("a", A_COL)):
        x, xr = run[col], ref[col]
        peak_ref = _peak(xr)
        diff = x - np.interp(t, t_ref, xr)
        out[f"peak_{key}_rel_err"] = abs(_peak(x) - peak_ref) / peak_ref
        out[f"rms_{key}_rel_err"] = float(np.sqrt(np.mean(diff ** 2))) / peak_ref
        t_p = ref_info["t_passage_end_s"]
        w, wr = t <= t_p + 1e-9, t_ref <= t_p + 1e-9
        peak_ref_p = _peak(xr[wr])
        out[f"passage_peak_{key}_rel_err"] = abs(_peak(x[w]) - peak_ref_p) / peak_ref_p
        out[f"passage_rms_{key}_rel_err"] = float(np.sqrt(np.mean(diff[w] ** 2))) / peak_ref_p
    p10, p10_ref = run_info.get("peak_Y_10ms_N"), ref_info.get("peak_Y_10ms_N")
    out["peak_Y_10ms_rel_err"] = abs(p10 - p10_ref) / p10_ref if p10 is not None and p10_ref else math.nan
    return out


# ---------------------------------------------------------------------------------------------------- design
def design(args) -> tuple[list[tuple], list[dict]]:
    """The configurations ``(integrator, creep_law, geometry, dt_ms)`` of the selected parts (no duplicates) and
    the skipped ones."""
    configs, skipped = [], []

    def add(cfg):
        if cfg[2] != "online" and not HAS_GEOMETRY:
            skipped.append(dict(zip(("integrator", "creep_law", "geometry", "dt_ms"), cfg),
                                reason="RtriCase has no 'geometry' field yet (precomputed geometry table not "
                                       "available)"))
        elif cfg not in configs:
            configs.append(cfg)

    if "main" in args.parts:
        for solver in args.integrators:
            for dt in args.dt_ms:
                add((solver, "table", "online", dt))
    for solver in args.option_integrators:
        for dt in args.option_dt_ms:
            if "creep" in args.parts:
                for law in args.creep_laws:
                    add((solver, law, "online", dt))
            if "geometry" in args.parts:
                for geo in args.geometries:
                    for law in GEOMETRY_CREEP_LAWS:
                        add((solver, law, geo, dt))
    return configs, skipped


def run_config(cfg, ref: dict, ref_info: dict, repeats: int) -> dict:
    solver, law, geo, dt_ms = cfg
    dt = dt_ms * 1e-3
    row = dict(integrator=solver, creep_law=law, geometry=geo, dt_ms=dt_ms, steps=int(round(T_END_S / dt)))
    walls, result = [], None
    for _ in range(repeats):
        result = solve(make_case(solver, dt, law, geo))
        walls.append(result.summary["solve_seconds"])
        if result.summary["status"] != "ok":
            break
    s = result.summary
    row.update(status=s["status"], wall_s=min(walls), wall_s_all=walls,
               us_per_step=min(walls) / row["steps"] * 1e6, real_time_factor=T_END_S / min(walls),
               contact_calls_per_step=s["contact_calls"] / row["steps"])
    nan_errors = {k: math.nan for k in CSV_COLUMNS if k.endswith("_rel_err")}
    if s["status"] != "ok" or not s.get("peaks"):
        row.update(nan_errors, peak_Y_N=math.nan, peak_a_m_s2=math.nan)
        return row
    run = _series(result)
    pY = s["peaks"]["max_abs_lateral_contact_force_w1_right_N"]
    pa = s["peaks"]["max_abs_carbody_lateral_acceleration_rear_m_s2"]
    row.update(peak_Y_N=pY, peak_a_m_s2=pa)
    finite = all(np.all(np.isfinite(run[c])) for c in (Y_COL, A_COL))
    if not finite or pY > DIVERGED_FACTOR * ref_info["peak_Y_N"] or pa > DIVERGED_FACTOR * ref_info["peak_a_m_s2"]:
        row["status"] = ("diverged: " + ("non-finite outputs" if not finite else
                                         f"peak |Y| {pY / 1e3:.3g} kN, peak |a| {pa:.3g} m/s² (reference "
                                         f"{ref_info['peak_Y_N'] / 1e3:.3g} kN, {ref_info['peak_a_m_s2']:.3g} m/s²)"))
        row.update(nan_errors)
        return row
    info = dict(t_passage_end_s=s["coverage"]["t_needed_with_run_out_s"],
                peak_Y_10ms_N=s["peaks"].get("max_abs_lateral_contact_force_w1_right_10ms_avg_N"))
    row.update(errors(run, info, ref, ref_info))
    return row


def pareto(rows: list[dict], err_key: str) -> list[int]:
    """Indices of the rows (status ok, finite error) not dominated in (wall_s, err): no other row is at least as
    fast and at least as accurate and better in one of them."""
    ok = [i for i, r in enumerate(rows) if r["status"] == "ok" and math.isfinite(r[err_key])]
    front = []
    for i in ok:
        ti, ei = rows[i]["wall_s"], rows[i][err_key]
        if not any(rows[j]["wall_s"] <= ti and rows[j][err_key] <= ei and
                   (rows[j]["wall_s"] < ti or rows[j][err_key] < ei) for j in ok if j != i):
            front.append(i)
    return sorted(front, key=lambda i: rows[i]["wall_s"])


# ---------------------------------------------------------------------------------------------------- outputs
_MARKERS = {("table", "online"): "o", ("fastsim", "online"): "s", ("shen_hedrick_elkins", "online"): "^",
            ("table", "table"): "D"}
_LABEL_OPTION = {("table", "online"): "creep table, online search", ("fastsim", "online"): "FASTSIM, online",
                 ("shen_hedrick_elkins", "online"): "Shen–Hedrick–Elkins, online",
                 ("table", "table"): "creep table, geometry table"}


def plot(rows: list[dict], fronts: dict, path: Path, ref_meta: dict) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    panels = (("peak_Y_rel_err", "peak |Y| w1 right: relative error"),
              ("peak_a_rel_err", "peak |car-body lateral acc.|: relative error"),
              ("rms_Y_rel_err", "RMS error of Y(t) / reference peak"),
              ("rms_a_rel_err", "RMS error of a(t) / reference peak"))
    solvers = [s for s in SOLVERS if any(r["integrator"] == s for r in rows)]
    colours = {s: f"C{i}" for i, s in enumerate(SOLVERS)}
    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    for ax, (key, title) in zip(axes.ravel(), panels):
        groups = {}
        for r in rows:
            if r["status"] == "ok" and math.isfinite(r[key]):
                groups.setdefault((r["integrator"], r["creep_law"], r["geometry"]), []).append(r)
        for (solver, law, geo), rs in groups.items():
            rs = sorted(rs, key=lambda r: r["dt_ms"])
            x = [r["wall_s"] for r in rs]
            y = [max(r[key], 1e-12) for r in rs]
            ax.plot(x, y, "-", color=colours[solver], lw=0.6, alpha=0.5)
            ax.plot(x, y, _MARKERS.get((law, geo), "x"), color=colours[solver], ms=6,
                    mfc=colours[solver] if (law, geo) == ("table", "online") else "none")
            for r, xi, yi in zip(rs, x, y):
                ax.annotate(f"{r['dt_ms']:g}", (xi, yi), textcoords="offset points", xytext=(3, 3), fontsize=6,
                            color=colours[solver])
        front = fronts.get(key, [])
        if front:
            fx = [rows[i]["wall_s"] for i in front]
            fy = [max(rows[i][key], 1e-12) for i in front]
            ax.step(fx, fy, where="post", color="k", lw=1.2, alpha=0.7, label="Pareto front")
            ax.plot(fx, fy, "o", ms=11, mfc="none", mec="k", alpha=0.7)
        res = ref_meta["convergence"]["reference_resolution"].get(key)
        if res is not None and res > 0:
            ax.axhline(res, color="0.4", ls=":", lw=1.0, label="reference resolution")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set(xlabel="wall time of SolveDynamic [s] (2.5 s simulated)", ylabel="relative error [-]")
        ax.set_title(title, fontsize=9)
        ax.grid(True, which="both", alpha=0.25)
    handles = [Line2D([], [], color=colours[s], marker="o", ls="-", label=s) for s in solvers]
    opts = sorted({(r["creep_law"], r["geometry"]) for r in rows})
    handles += [Line2D([], [], color="0.3", marker=_MARKERS.get(o, "x"), ls="", mfc="none" if o != ("table", "online")
                       else "0.3", label=_LABEL_OPTION.get(o, f"{o[0]}, {o[1]}")) for o in opts]
    handles.append(Line2D([], [], color="k", lw=1.2, label="Pareto front (step line; circled)"))
    handles.append(Line2D([], [], color="0.4", ls=":", lw=1.0, label="reference resolution (errors below: "
                                                                     "not resolved)"))
    fig.legend(handles=handles, loc="lower center", ncol=min(len(handles), 5), fontsize=8)
    s = ref_meta["settings"]
    failed = [f"{r['integrator']} {r['dt_ms']:g} ms ({r['creep_law']}, {r['geometry']})" for r in rows
              if r["status"] != "ok"]
    fig.suptitle(f"RTRI {s['span_m']:g} m, {s['speed_km_h']:g} km/h, {T_END_S:g} s simulated (substitute inputs); "
                 f"reference {s['solver']} {s['dt_s'] * 1e3:g} ms, creep table, online, concave n = "
                 f"{s['n_concave_wheel']}; labels: dt [ms]"
                 + (f"\nnot plotted (failed/diverged): {', '.join(failed)}" if failed else ""), fontsize=9)
    fig.tight_layout(rect=(0, 0.07, 1, 0.95))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _fmt(v, pct=False):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "—"
    return f"{100 * v:.3g}" if pct else f"{v:.3g}"


def markdown(rows: list[dict]) -> str:
    lines = ["| integrator | creep law | geometry | dt [ms] | status | wall [s] | µs/step | contact calls/step | "
             "peak Y err [%] | RMS Y err [%] | peak a err [%] | RMS a err [%] | Pareto (Y / a) |",
             "|---|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        status = r["status"] if len(r["status"]) < 60 else r["status"][:57] + "..."
        lines.append(f"| {r['integrator']} | {r['creep_law']} | {r['geometry']} | {r['dt_ms']:g} | {status} | "
                     f"{r['wall_s']:.2f} | {r['us_per_step']:.0f} | {r['contact_calls_per_step']:.2f} | "
                     f"{_fmt(r['peak_Y_rel_err'], True)} | {_fmt(r['rms_Y_rel_err'], True)} | "
                     f"{_fmt(r['peak_a_rel_err'], True)} | {_fmt(r['rms_a_rel_err'], True)} | "
                     f"{'Y' if r['pareto_peak_Y'] else '-'} / {'a' if r['pareto_peak_a'] else '-'} |")
    return "\n".join(lines)


def write_csv(rows: list[dict], path: Path) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(CSV_COLUMNS))
        w.writeheader()
        for r in rows:
            w.writerow({k: (";".join(f"{x:.4f}" for x in r[k]) if k == "wall_s_all" else
                            f"{r[k]:.6g}" if isinstance(r[k], float) else r[k]) for k in CSV_COLUMNS})


# ---------------------------------------------------------------------------------------------------- main
def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--parts", nargs="+", choices=PARTS, default=list(PARTS),
                    help="main: dt x integrators; creep: creep laws; geometry: geometry table (default all)")
    ap.add_argument("--dt-ms", nargs="+", type=float, default=list(DT_MS))
    ap.add_argument("--integrators", nargs="+", choices=SOLVERS, default=list(SOLVERS))
    ap.add_argument("--creep-laws", nargs="+", choices=CREEP_LAWS, default=list(CREEP_LAWS))
    ap.add_argument("--geometries", nargs="+", choices=GEOMETRIES, default=list(GEOMETRIES))
    ap.add_argument("--option-dt-ms", nargs="+", type=float, default=list(OPTION_DT_MS),
                    help="dt of the creep-law and geometry rows")
    ap.add_argument("--option-integrators", nargs="+", choices=SOLVERS, default=list(OPTION_INTEGRATORS))
    ap.add_argument("--quick", action="store_true",
                    help="dt 1, 0.5 ms; newmark, rk44; online geometry (parts main and creep)")
    ap.add_argument("--repeats", type=int, default=1, help="timed runs per configuration; the minimum is reported")
    ap.add_argument("--reference-solver", choices=("newmark", "rk44"), default=REFERENCE["solver"])
    ap.add_argument("--reference-dt-ms", type=float, default=REFERENCE["dt_ms"])
    ap.add_argument("--check-dt-ms", type=float, default=REFERENCE["check_dt_ms"],
                    help="step of the reference's convergence check")
    ap.add_argument("--rebuild-reference", action="store_true")
    ap.add_argument("--out-dir", default=str(RESULTS))
    ap.add_argument("--no-plot", action="store_true")
    args = ap.parse_args(argv)
    if args.quick:
        args.dt_ms, args.option_dt_ms = [1.0, 0.5], [1.0, 0.5]
        args.integrators = args.option_integrators = ["newmark", "rk44"]
        args.geometries = ["online"]
        args.parts = [p for p in args.parts if p != "geometry"]
    if args.repeats < 1:
        ap.error("--repeats must be >= 1")
    for dt in list(args.dt_ms) + list(args.option_dt_ms):
        n = dt / args.reference_dt_ms
        if dt <= 0 or abs(n - round(n)) > 1e-9:
            ap.error(f"dt {dt:g} ms: must be a positive multiple of the reference step {args.reference_dt_ms:g} ms")
    return args


def main(argv=None):
    args = parse_args(argv)
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    configs, skipped = design(args)
    for s in skipped:
        print(f"note: skipped {s['integrator']} {s['dt_ms']:g} ms {s['creep_law']} geometry={s['geometry']}: "
              f"{s['reason']}")
    ref_all = load_or_build_reference(args, out / "work_precision_reference.npz")
    ref, ref_meta = ref_all["series"], ref_all["meta"]
    ref_info = ref_meta["reference"]
    conv = ref_meta["convergence"]
    print(f"reference: peak |Y| {ref_info['peak_Y_N'] / 1e3:.3f} kN, peak |a| {ref_info['peak_a_m_s2']:.4f} m/s²; "
          "check at {:g} ms vs reference: ".format(conv["check"]["dt_s"] * 1e3)
          + ", ".join(f"{k} {100 * v:.3g} %" for k, v in conv["errors_of_check_vs_reference"].items()))
    # untimed warm-up of every combination (numba caches, Exudyn's first solve)
    for combo in sorted({(c[0], c[1], c[2]) for c in configs}):
        solve(make_case(combo[0], 1e-3, combo[1], combo[2], steps=5))
    rows = []
    for i, cfg in enumerate(configs):
        row = run_config(cfg, ref, ref_info, args.repeats)
        rows.append(row)
        print(f"[{i + 1}/{len(configs)}] {cfg[0]:17s} {cfg[1]:19s} {cfg[2]:6s} dt {cfg[3]:g} ms: {row['status'][:70]}"
              f", wall {row['wall_s']:.2f} s, peak Y err {_fmt(row['peak_Y_rel_err'], True)} %, peak a err "
              f"{_fmt(row['peak_a_rel_err'], True)} %", flush=True)
    fronts = {k: pareto(rows, k) for k in ("peak_Y_rel_err", "peak_a_rel_err", "rms_Y_rel_err", "rms_a_rel_err")}
    for i, r in enumerate(rows):
        r["pareto_peak_Y"] = i in fronts["peak_Y_rel_err"]
        r["pareto_peak_a"] = i in fronts["peak_a_rel_err"]
    write_csv(rows, out / "work_precision.csv")
    result = dict(
        what="RTRI 20 m, 250 km/h, 2.5 s simulated: wall time of SolveDynamic vs error w.r.t. a converged "
             "reference (benchmarks/work_precision.py docstring)",
        machine=machine_info(), repeats=args.repeats, record=True,
        wall_time="summary['solve_seconds'] (SolveDynamic only), minimum of the repeats; recording adds one "
                  "contact evaluation per step to every run",
        error_definitions=dict(
            peak="|max|x_run| - max|x_ref|| / max|x_ref| over the whole run",
            rms="sqrt(mean((x_run - x_ref)^2)) / max|x_ref| on the run's time grid (reference interpolated)",
            passage="the same within t <= coverage.t_needed_with_run_out_s (response to the deviation)",
            diverged=f"status 'diverged' if outputs are not finite or a peak exceeds {DIVERGED_FACTOR:g} x the "
                     "reference peak; errors NaN"),
        args={k: v for k, v in vars(args).items()}, has_geometry_field=HAS_GEOMETRY,
        reference=ref_meta, skipped=skipped, rows=rows,
        pareto={k: [dict(integrator=rows[i]["integrator"], creep_law=rows[i]["creep_law"],
                         geometry=rows[i]["geometry"], dt_ms=rows[i]["dt_ms"], wall_s=rows[i]["wall_s"],
                         error=rows[i][k]) for i in v] for k, v in fronts.items()},
        runtime_s=time.perf_counter() - t_start)
    with open(out / "work_precision.json", "w") as fh:
        json.dump(result, fh, indent=2, allow_nan=True)
    if not args.no_plot:
        plot(rows, fronts, out / "work_precision.png", ref_meta)
    print(f"\n### Work–precision, RTRI {SPAN_M:g} m, 250 km/h, {T_END_S:g} s simulated (min of {args.repeats} "
          f"repeat(s), recording on)\n")
    print(markdown(rows))
    c = conv["errors_of_check_vs_reference"]
    print(f"\nreference {ref_meta['settings']['solver']} {ref_meta['settings']['dt_s'] * 1e3:g} ms "
          f"(solve {ref_info['solve_seconds']:.1f} s): peak |Y| {ref_info['peak_Y_N']:.1f} N, peak |a| "
          f"{ref_info['peak_a_m_s2']:.5f} m/s²; {conv['check']['dt_s'] * 1e3:g} ms vs reference: peak Y "
          f"{100 * c['peak_Y_rel_err']:.3g} %, RMS Y {100 * c['rms_Y_rel_err']:.3g} %, peak a "
          f"{100 * c['peak_a_rel_err']:.3g} %, RMS a {100 * c['rms_a_rel_err']:.3g} %")
    x = conv["errors_of_cross_check_vs_reference"]
    print(f"cross-check {conv['cross_check']['solver']} {conv['cross_check']['dt_s'] * 1e3:g} ms vs reference: "
          f"peak Y {100 * x['peak_Y_rel_err']:.3g} %, RMS Y {100 * x['rms_Y_rel_err']:.3g} %, peak a "
          f"{100 * x['peak_a_rel_err']:.3g} %, RMS a {100 * x['rms_a_rel_err']:.3g} % (the larger of the two = the "
          "reference's resolution)")
    print(f"wrote {out / 'work_precision.csv'}, .json" + ("" if args.no_plot else ", .png")
          + f"; runtime {time.perf_counter() - t_start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
