"""Validation report: re-runs the project's validations by calling the library directly (not pytest) and writes
``report.md`` with PNG plots into an output directory (``python -m exudyn_wheelrail validation-report``).

Sections (every row states its reference and the tolerance of the corresponding test):

(a) Kalker's exact solver against Table E.3 (C11, C22, C23; ν = 0.28)       tests/test_kalker_exact.py
(b) the shipped creep table against the exact solver at random off-grid points tests/test_creep_table.py
(c) Klingel's wavelength of a free coned wheelset                             tests/test_connector.py
(d) Frýba's moving force on a simply supported span                           tests/test_bridge.py
(e) the RTRI 20 m vs 40 m findings at 250 km/h                                tests/test_rtri.py

``quick=True`` (about 15 s) runs (a)–(c) in full, (d) with Δt = 1 ms instead of 0.5 ms and skips (e) (two RTRI
runs); the full report takes about 15 s more (numba compilation included).
"""
from __future__ import annotations

import math
import time
import tomllib
from pathlib import Path

import numpy as np

#: section headings (the test checks them)
HEADINGS = {
    "a": "## (a) Kalker's exact solver vs Table E.3",
    "b": "## (b) Creep table vs exact solver (off-grid)",
    "c": "## (c) Klingel wavelength of a free coned wheelset",
    "d": "## (d) Frýba moving force on a simply supported span",
    "e": "## (e) RTRI 20 m vs 40 m at 250 km/h",
}

# (a): the problem of tests/test_kalker_exact.py
A_RATIOS = (0.2, 0.5, 1.0, 2.0, 5.0)
NU_A, G_A, N_A, MU_A, C_A, EPS_A = 0.28, 82e9, 10e3, 0.3, 6e-3, 1e-7
TOL_A = 0.015
# (b): tests/test_creep_table.py::test_shipped_exact_table...
G_B, N_B, MU_B, C_B = 8.1e10, 2.5e4, 0.4, 5e-3
TOL_B = 0.02
TOL_C = 0.02
TOL_D = 0.01
MUCH_LARGER = 2.0


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


# ------------------------------------------------------------------------------------------------------- (a)
def kalker_slopes(a_over_b, nu=NU_A, **options):
    """(C11, C22, C23) of the exact solver from a small creepage: slope = −F/(G c² ε)."""
    from ..creep import kalker_exact
    a, b = C_A * math.sqrt(a_over_b), C_A / math.sqrt(a_over_b)
    k = G_A * C_A * C_A * EPS_A
    c11 = -kalker_exact(a, b, EPS_A, 0.0, 0.0, N_A, MU_A, G_A, nu, **options)[0] / k
    c22 = -kalker_exact(a, b, 0.0, EPS_A, 0.0, N_A, MU_A, G_A, nu, **options)[1] / k
    c23 = -kalker_exact(a, b, 0.0, 0.0, EPS_A / C_A, N_A, MU_A, G_A, nu, **options)[1] / k
    return np.array([c11, c22, c23])


def section_a(out: Path):
    from ..creep import kalker_coefficients
    rows = []
    for ab in A_RATIOS:
        ref = np.array(kalker_coefficients(ab, NU_A))
        got = kalker_slopes(ab)
        rows.append((ab, got, ref, got / ref - 1.0))
    worst = max(float(np.max(np.abs(r[3]))) for r in rows)
    lines = [HEADINGS["a"], "",
             f"Reference: Kalker's Table E.3 (`kalker_coefficients`, ν = {NU_A}); solver: `kalker_exact` (default "
             f"grid), creepage {EPS_A:g}, μ = {MU_A}, N = {N_A / 1e3:g} kN, G = {G_A / 1e9:g} GPa, c = √(ab) = "
             f"{C_A * 1e3:g} mm, slope = −F/(G c² ε). Tolerance: |rel. error| < {TOL_A * 100:g} % "
             "(tests/test_kalker_exact.py).", "",
             "| a/b | C11 solver | C11 Table E.3 | err C11 [%] | C22 solver | C22 Table E.3 | err C22 [%] | "
             "C23 solver | C23 Table E.3 | err C23 [%] | reference | tolerance | pass |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for ab, got, ref, err in rows:
        cells = " | ".join(f"{got[i]:.4f} | {ref[i]:.4f} | {err[i] * 100:+.3f}" for i in range(3))
        ok = bool(np.all(np.abs(err) < TOL_A))
        lines.append(f"| {ab:g} | {cells} | Table E.3 | {TOL_A * 100:g} % | {'yes' if ok else 'NO'} |")
    lines += ["", f"Worst relative error: {worst * 100:.3f} %.", "", "![Kalker coefficients](kalker_e3.png)", ""]
    plt = _plt()
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    abs_ = np.array([r[0] for r in rows])
    for i, name in enumerate(("C11", "C22", "C23")):
        ax[0].plot(abs_, [r[2][i] for r in rows], "o-", color=f"C{i}", label=f"{name} Table E.3")
        ax[0].plot(abs_, [r[1][i] for r in rows], "x", ms=9, color=f"C{i}", label=f"{name} exact solver")
        ax[1].plot(abs_, [r[3][i] * 100 for r in rows], "o-", color=f"C{i}", label=name)
    ax[1].axhspan(-TOL_A * 100, TOL_A * 100, color="0.9", label="tolerance")
    ax[0].set(xscale="log", xlabel="a/b", ylabel="coefficient", title=f"Kalker coefficients, ν = {NU_A}")
    ax[1].set(xscale="log", xlabel="a/b", ylabel="relative error [%]", title="solver vs Table E.3")
    ax[0].legend(fontsize=7)
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "kalker_e3.png", dpi=110)
    plt.close(fig)
    return lines, {"rows": [(r[0], r[1].tolist(), r[2].tolist()) for r in rows], "worst": worst}


# ------------------------------------------------------------------------------------------------------- (b)
def section_b(out: Path, n_points: int = 20, seed: int = 2026):
    from ..creep import kalker_exact, load_table, table_forces
    t = load_table()
    nu = t.poisson
    opts = {k: v for k, v in t.metadata["generator_options"].items() if k in ("n_x", "n_y", "tol")}
    rng = np.random.default_rng(seed)
    ef, em = [], []
    for _ in range(n_points):
        ab = float(np.exp(rng.uniform(np.log(0.2), np.log(5.0))))
        a, b = C_B * math.sqrt(ab), C_B / math.sqrt(ab)
        xi, eta = rng.normal(scale=4e-4, size=2)
        phi = rng.normal(scale=1.0) if rng.uniform() < 0.5 else 0.0
        F_ref = np.array(kalker_exact(a, b, xi, eta, phi, N_B, MU_B, G_B, nu, **opts))
        F_tab = np.array(table_forces(a, b, xi, eta, phi, N_B, MU_B, G_B, nu, table=t))
        ef.append(np.hypot(*(F_tab[:2] - F_ref[:2])) / (MU_B * N_B))
        em.append(abs(F_tab[2] - F_ref[2]) / (MU_B * N_B * math.sqrt(a * b)))
    ef, em = np.array(ef), np.array(em)
    res = {"max_F": float(ef.max()), "rms_F": float(np.sqrt(np.mean(ef ** 2))), "max_M": float(em.max()),
           "rms_M": float(np.sqrt(np.mean(em ** 2))), "n": n_points}
    ok = res["max_F"] < TOL_B and res["max_M"] < TOL_B
    lines = [HEADINGS["b"], "",
             f"Reference: `kalker_exact` with the table's generator options {opts} at {n_points} random points "
             f"(a/b log-uniform in [0.2, 5], ξ, η ~ N(0, 4e-4), φ ~ N(0, 1 rad/m) in half of them; c = "
             f"{C_B * 1e3:g} mm, N = {N_B / 1e3:g} kN, μ = {MU_B}, G = {G_B / 1e9:g} GPa, ν = {nu:g}, seed {seed}). "
             f"Tolerance: max error < {TOL_B * 100:g} % of μN (forces) and of μNc (spin moment) "
             "(tests/test_creep_table.py).", "",
             "| quantity | max error | RMS error | reference | tolerance | pass |", "|---|---|---|---|---|---|",
             f"| Fx, Fy / μN | {res['max_F'] * 100:.3f} % | {res['rms_F'] * 100:.3f} % | exact solver | "
             f"{TOL_B * 100:g} % | {'yes' if res['max_F'] < TOL_B else 'NO'} |",
             f"| Mz / μNc | {res['max_M'] * 100:.3f} % | {res['rms_M'] * 100:.3f} % | exact solver | "
             f"{TOL_B * 100:g} % | {'yes' if res['max_M'] < TOL_B else 'NO'} |", ""]
    res["ok"] = ok
    return lines, res


# ------------------------------------------------------------------------------------------------------- (c)
def zero_crossing_wavelengths(t, y, speed):
    """Wavelengths [m] of an oscillation y(t) travelled at ``speed``: twice the distance between consecutive zero
    crossings (linearly interpolated)."""
    zc = [t[i - 1] - y[i - 1] * (t[i] - t[i - 1]) / (y[i] - y[i - 1]) for i in range(1, len(y))
          if (y[i - 1] > 0 >= y[i]) or (y[i - 1] < 0 <= y[i])]
    return speed * 2 * np.diff(zc)


def klingel_run(conicity=0.05, speed=5.0, end_time_s=8.0, step_s=1e-3):
    """The free coned wheelset (no primary springs) released with 1 mm lateral offset: wavelengths from the
    zero crossings of the lateral displacement, and Klingel's λ = 2π √(r0 e / γ) of the centred pair."""
    import exudyn as exu

    from ..contact import WheelRailPair, WheelsetContact
    from ..multibody import build_vehicle, simulation_settings, vehicle_from_dict
    from ..multibody import connector as C
    from ..multibody.vehicle_data import VEHICLES_DIR
    from ..profiles import WheelProfile

    d = tomllib.loads((VEHICLES_DIR / "single_wheelset.toml").read_text())
    d["primary"] = {"kx_N_per_m": 0.0, "ky_N_per_m": 0.0, "cx_N_s_per_m": 0.0, "cy_N_s_per_m": 0.0}
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, vehicle_from_dict(d), speed_m_s=speed)
    pair = WheelRailPair(WheelProfile.cone(conicity), "UIC60", inclination="1/40")
    dz = C.place_on_rails(mbs, model, pair)
    ws = model.wheelsets[0]
    q0 = np.array(mbs.GetNodeParameter(ws.node, "initialCoordinates"))
    q0[1] = 1e-3
    mbs.SetNodeParameter(ws.node, "initialCoordinates", q0.tolist())
    C.add_wheel_rail_contact(mbs, [ws.node], pair, speed_m_s=speed)
    rec = []
    mbs.SetPreStepUserFunction(lambda mbs, t: rec.append(
        (t, mbs.GetNodeOutput(ws.node, exu.OutputVariableType.Position)[1])) or True)
    mbs.Assemble()
    sim = simulation_settings(end_time_s, step_s)
    sim.timeIntegration.newton.useModifiedNewton = True
    mbs.SolveDynamic(sim, solverType=exu.DynamicSolverType.GeneralizedAlpha)
    t, y = np.array(rec).T
    lam = zero_crossing_wavelengths(t, y, speed)
    pts = WheelsetContact(pair, 1).contact_points(0.0, -0.46 + dz, 0.0)
    r0 = float(np.mean([p.rolling_radius_m for p in pts]))
    e = 0.5 * abs(pts[0].p_wheel_in_track[0] - pts[1].p_wheel_in_track[0])
    return t, y, lam, 2 * math.pi * math.sqrt(r0 * e / conicity), r0, e


def section_c(out: Path, quick: bool):
    T = 8.0
    conicity, speed = 0.05, 5.0
    t, y, lam, ref, r0, e = klingel_run(conicity, speed, T)
    err = lam / ref - 1.0 if lam.size else np.array([np.nan])
    ok = lam.size >= 3 and bool(np.all(np.abs(err) < TOL_C))
    lines = [HEADINGS["c"], "",
             f"Cone γ = {conicity} on UIC60 1:40, single free wheelset (no primary springs), {speed} m/s, 1 mm initial "
             f"offset, {T:g} s (generalized-α, 1 ms). Reference: Klingel λ = 2π √(r0 e/γ), r0 = {r0 * 1e3:.1f} mm, "
             f"e = {e * 1e3:.1f} mm. Tolerance: {TOL_C * 100:g} % per measured wavelength "
             "(tests/test_connector.py).", "",
             "| quantity | measured | Klingel | error | reference | tolerance | pass |", "|---|---|---|---|---|---|---|",
             f"| wavelength (mean of {lam.size}) [m] | {np.mean(lam) if lam.size else float('nan'):.3f} | {ref:.3f} | "
             f"{np.max(np.abs(err)) * 100:.3f} % (worst) | Klingel | {TOL_C * 100:g} % | {'yes' if ok else 'NO'} |",
             "", "![Klingel](klingel.png)", ""]
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.plot(t * speed, y * 1e3, label="simulated lateral displacement")
    ax.plot(t * speed, 1e3 * np.cos(2 * np.pi * t * speed / ref), "--", label="Klingel (1 mm, λ)")
    ax.set(xlabel="distance [m]", ylabel="y [mm]", title=f"free coned wheelset, λ_Klingel = {ref:.2f} m")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "klingel.png", dpi=110)
    plt.close(fig)
    return lines, {"lambda_mean": float(np.mean(lam)) if lam.size else None, "lambda_ref": ref, "ok": ok,
                   "worst": float(np.max(np.abs(err)))}


# ------------------------------------------------------------------------------------------------------- (d)
def section_d(out: Path, quick: bool):
    from ..structures import BridgeModel, DeckSection, fryba_moving_force
    from ..structures.bridge import simulate_moving_forces
    sec = DeckSection(m_kg_m=15e3, EI_y_Nm2=2.0e10, EI_z_Nm2=1.0e11, GJ_Nm2=6e9, EA_N=2e11, Ip_kgm2_m=6e4)
    L, P, v = 20.0, 2e5, 40.0
    step = 1e-3 if quick else 5e-4
    modes = BridgeModel((L,), sec).modes(f_max_Hz=150.0)
    t, q, _ = simulate_moving_forces(modes, x_m=[0.0], forces_N=[[0.0, P, 0.0]], speed_m_s=v, s_start_m=0.0,
                                     end_time_s=L / v + 0.25, step_s=step)
    w = q @ modes.shape_at(L / 2)[1]
    ref = fryba_moving_force(L / 2, t, force_N=P, speed_m_s=v, span_m=L, EI_Nm2=sec.EI_y_Nm2, m_kg_m=sec.m_kg_m,
                             n_terms=60)
    peak = float(np.max(np.abs(ref)))
    err = float(np.max(np.abs(w - ref))) / peak
    static = P * L ** 3 / (48 * sec.EI_y_Nm2)
    ok = err < TOL_D
    lines = [HEADINGS["d"], "",
             f"20 m span (m = 15 t/m, EI = 2e10 N m², f1 = {sec.vertical_frequency_Hz(L):.2f} Hz), P = 200 kN at "
             f"{v:g} m/s, modal model with {len(modes.frequencies_Hz)} modes up to 150 Hz, generalized-α (ρ∞ = 1), "
             f"Δt = {step * 1e3:g} ms, passage + 0.25 s. Reference: Frýba's series (60 terms, `fryba_moving_force`). "
             f"Tolerance: max |w − w_Frýba| < {TOL_D * 100:g} % of the peak (tests/test_bridge.py).", "",
             "| quantity | Exudyn | Frýba | error | reference | tolerance | pass |", "|---|---|---|---|---|---|---|",
             f"| peak mid-span deflection [mm] | {np.max(np.abs(w)) * 1e3:.4f} | {peak * 1e3:.4f} | "
             f"{err * 100:.3f} % of peak (max over history) | Frýba (1999) | {TOL_D * 100:g} % | "
             f"{'yes' if ok else 'NO'} |",
             f"| dynamic amplification | {np.max(np.abs(w)) / static:.3f} | {peak / static:.3f} | | PL³/(48EI) = "
             f"{static * 1e3:.3f} mm | | |", "", "![Fryba](fryba.png)", ""]
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.plot(t, w * 1e3, label="Exudyn (modal)")
    ax.plot(t, ref * 1e3, "--", label="Frýba series")
    ax.axvline(L / v, color="0.6", lw=0.8)
    ax.set(xlabel="t [s]", ylabel="mid-span deflection (down) [mm]", title="moving force on a 20 m span")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "fryba.png", dpi=110)
    plt.close(fig)
    return lines, {"peak_mm": peak * 1e3, "err": err, "ok": ok}


# ------------------------------------------------------------------------------------------------------- (e)
def section_e(out: Path, quick: bool):
    if quick:
        return [HEADINGS["e"], "", "Skipped in `--quick` (two RTRI runs; run without `--quick`). Reference: "
                "Montenegro et al. (2015): the 20 m span gives a much higher lateral contact force than the 40 m "
                f"span (read as ≥ {MUCH_LARGER:g}×) and no flange contact at 40 m (tests/test_rtri.py).", ""], {}
    from .rtri import RTRI, RTRI_CASE, RtriCase, run_rtri
    v = RTRI_CASE.representative_speed_km_h
    runs = {}
    for L in (20.0, 40.0):
        distance = RTRI.lead_in_m + L + RTRI.transition_length_m + RTRI.run_out_m
        steps = int(math.ceil(distance / (v / 3.6) / RTRI.time_step_s))
        runs[L] = run_rtri(RtriCase(span_m=L, speed_km_h=v, solver="newmark", steps=steps))
    keys = [("max_abs_lateral_contact_force_w1_right_N", "max abs(Y) w1 right [kN]", 1e-3),
            ("max_abs_lateral_contact_force_w1_right_10ms_avg_N", "max abs(Y) 10 ms avg [kN]", 1e-3),
            ("max_abs_carbody_lateral_acceleration_rear_m_s2", "max car-body lat. acc. [m/s²]", 1.0),
            ("max_abs_wheelset1_lateral_rel_track_m", "max wheelset 1 y rel. track [mm]", 1e3),
            ("max_derailment_quotient_w1_right", "max Y/Q w1 right [-]", 1.0),
            ("flange_contact_w1_right", "flange contact w1 right", None)]
    p = {L: r.summary["peaks"] for L, r in runs.items()}
    lines = [HEADINGS["e"], "",
             f"Rigid-rail RTRI case, Newmark, Δt = {RTRI.time_step_s * 1e3:g} ms, {v:g} km/h, the leading wheelset "
             "through lead-in, span, transition and run-out (status: "
             f"{', '.join(r.summary['status'] for r in runs.values())}). Reference: Montenegro et al. (2015). "
             f"Tolerance: |Y|(20 m) ≥ {MUCH_LARGER:g} × |Y|(40 m) and no flange contact at 40 m (tests/test_rtri.py).",
             "", "| peak | 20 m | 40 m | ratio 20/40 | reference | tolerance | pass |", "|---|---|---|---|---|---|---|"]
    res = {}
    for key, label, scale in keys:
        a, b = p[20.0].get(key), p[40.0].get(key)
        if scale is None:
            ok = not b
            lines.append(f"| {label} | {a} | {b} | | paper: flange contact at 20 m only | none at 40 m | "
                         f"{'yes' if ok else 'NO'} (40 m) |")
            res[key] = (a, b)
            continue
        ratio = a / b if (a is not None and b) else float("nan")
        crit = key.startswith("max_abs_lateral_contact_force")
        ok = ratio >= MUCH_LARGER if crit else None
        lines.append(f"| {label} | {a * scale:.3f} | {b * scale:.3f} | {ratio:.2f} | "
                     f"{'paper: much higher at 20 m' if crit else 'information'} | "
                     f"{f'≥ {MUCH_LARGER:g}' if crit else '—'} | {'' if ok is None else ('yes' if ok else 'NO')} |")
        res[key] = (a, b)
    lines += ["", "Known deviation: the paper's flange contact at 20 m is not reproduced with the stated assumptions "
              "(xfail in tests/test_rtri.py).", "", "![RTRI](rtri.png)", ""]
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 3.5))
    for L, r in runs.items():
        ts = r.timeseries
        ax.plot(ts["time_s"], ts["lateral_contact_force_w1_right_N"] / 1e3, label=f"{L:g} m span")
    ax.set(xlabel="t [s]", ylabel="Y w1 right [kN]", title=f"RTRI, {v:g} km/h")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "rtri.png", dpi=110)
    plt.close(fig)
    return lines, res


# ------------------------------------------------------------------------------------------------------ report
def write_report(out_dir, quick: bool = False, progress=print) -> dict:
    """Run the sections and write ``out_dir/report.md`` (and the PNGs); returns the results per section."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    body, results, timing = [], {}, {}
    sections = (("a", lambda: section_a(out)), ("b", lambda: section_b(out, 20)),
                ("c", lambda: section_c(out, quick)), ("d", lambda: section_d(out, quick)),
                ("e", lambda: section_e(out, quick)))
    for key, fn in sections:
        if progress:
            progress(f"validation report: section ({key}) ...")
        t0 = time.perf_counter()
        try:
            lines, res = fn()
        except Exception as exc:   # one failing section must not hide the others
            lines, res = [HEADINGS[key], "", f"**ERROR**: {type(exc).__name__}: {exc}", ""], {"error": str(exc)}
        timing[key] = time.perf_counter() - t0
        body += lines + [f"_Section runtime: {timing[key]:.1f} s._", ""]
        results[key] = res
    total = time.perf_counter() - t_start
    from .. import __version__ as version
    head = ["# exudyn_wheelrail validation report", "",
            f"Package version {version}; mode: {'quick' if quick else 'full'}; generated "
            f"{time.strftime('%Y-%m-%d %H:%M:%S')}; total runtime {total:.1f} s. Regenerate with "
            f"`python -m exudyn_wheelrail validation-report --out DIR{' --quick' if quick else ''}`.", ""]
    (out / "report.md").write_text("\n".join(head + body), encoding="utf-8")
    results["runtime_s"] = total
    return results
