"""Flexible bridge (exudyn_wheelrail.structures.bridge): cost per step of the coupled vehicle–bridge simulation
against the rigid track, and of the modal against the FFRF formulation.

1. **Vehicle on the bridge vs rigid track.**  Manchester vehicle 1 (``vehicles/manchester_vehicle1.toml``, four
   wheelsets, S1002 / UIC60 1:40, FASTSIM 24 × 8) at 200 km/h, 1 s (1000 steps of 1 ms), straight track without
   irregularities, leading wheelset 5 m before the deck at t = 0 (all four wheelsets cross the deck within the
   second).  Configurations, each with RK44 (explicit, Lie group) and Newmark (trapezoidal rule β = 1/4, γ = 1/2,
   modified Newton with the connector's Jacobian):

   * ``rigid``: the contact connector on the rigid track (no bridge);
   * ``bridge``: the same with the 20 m simply supported deck of ``examples/scenarios/bridge_20m.toml`` (section
     assumptions of that scenario; modal formulation, 7 modes up to 54 Hz = the EN 1990 A2 cut-off), coupled in the
     connector (``bridge=``);
   * ``bridge+support``: the same plus a lateral support motion (sine burst 1.5 m/s², 1.5 Hz,
     :mod:`exudyn_wheelrail.structures.support_motion`): the cost of the effective modal load's user function and
     of the ground state in the connector — and of the lateral dynamics it excites (more Newton iterations);
   * ``rigid+lat_irr``: the rigid track with a lateral harmonic irregularity of 2 mm at wavelength V/1.5 Hz
     (37 m: 1.5 Hz at the wheels) — a reference for the cost of laterally excited running without any bridge.

   ``solve_seconds`` = wall time inside ``mbs.SolveDynamic`` only (model building, numba cache loading and a
   warm-up contact call outside); no output recording.  Every configuration is repeated (default 3 times, fresh
   model each time, interleaved) and the **minimum** is reported (the machine is shared), with all repeats.

2. **Modal vs FFRF formulation** of the deck alone: :func:`~exudyn_wheelrail.scenarios.moving_forces.benchmark_formulations`
   (simply supported 20 m span, all 25 modes up to 150 Hz, one 200 kN force at 40 m/s, generalized-α ρ∞ = 1,
   Δt = 0.5 ms, 1500 steps, best of ``--repeats``), with the mid-span error against Frýba's solution.

Run:  python benchmarks/bench_bridge.py [--repeats 3] [--steps 1000]
Writes benchmarks/results/bridge.json and prints Markdown tables.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import exudyn as exu

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.multibody import build_vehicle
from exudyn_wheelrail.simulation.exudyn_settings import simulation_settings
from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle
from exudyn_wheelrail.scenarios.scenario import build_bridge_modes, load_scenario
from exudyn_wheelrail.scenarios.moving_forces import benchmark_formulations
from exudyn_wheelrail.structures import add_bridge
from exudyn_wheelrail.structures.support_motion import SmoothHarmonicSupportMotion

ROOT = Path(__file__).resolve().parents[1]
RESULTS = Path(__file__).resolve().parent / "results" / "bridge.json"
SPAN_M = 20.0
SPEED_KM_H = 200.0
DT_S = 1e-3
LEAD_IN_M = 5.0
CREEP = dict(creep_law="fastsim", fastsim_grid=(24, 8))
TRACKS = ("rigid", "bridge", "bridge+support", "rigid+lat_irr")
SOLVERS = ("rk44", "newmark")


def deck_modes():
    """The modes of the 20 m deck of examples/scenarios/bridge_20m.toml (EN 1990 cut-off)."""
    scn = load_scenario(ROOT / "examples" / "scenarios" / "bridge_20m.toml")
    return build_bridge_modes(scn["structure"])[1]


def run_once(track: str, solver: str, steps: int, modes) -> dict:
    V = SPEED_KM_H / 3.6
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    vehicle = load_vehicle("manchester_vehicle1")
    x_ws = vehicle.wheelset_x_m()
    s_start = -LEAD_IN_M - max(x_ws)
    model = build_vehicle(mbs, vehicle, speed_m_s=V, s_start_m=s_start)
    geo = vehicle.geometry
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    C.place_on_rails(mbs, model, pair)
    bridge = None
    irregular = None
    if track == "rigid+lat_irr":
        from exudyn_wheelrail.track.rigid import Harmonic, RigidStraightTrack
        irregular = RigidStraightTrack(Harmonic(amplitude_m=2e-3, wavelength_m=V / 1.5))
    elif track != "rigid":
        bridge = add_bridge(mbs, modes)
        if track == "bridge+support":
            bridge.add_support_motion(mbs, SmoothHarmonicSupportMotion(1.5, 1.5, ramp_cycles=1.0,
                                                                       plateau_cycles=10.0))
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V, s_start_m=s_start,
                                       structure=bridge, track=irregular, **CREEP)
    mbs.Assemble()
    contact.warm_up(mbs)
    ss = simulation_settings(steps * DT_S, DT_S)
    ss.timeIntegration.numberOfSteps = int(steps)
    if solver == "rk44":
        ss.timeIntegration.explicit.computeEndOfStepAccelerations = False
        stype = exu.DynamicSolverType.RK44
    else:
        ga = ss.timeIntegration.generalizedAlpha
        ga.useNewmark = True
        ga.newmarkBeta = 0.25
        ga.newmarkGamma = 0.5
        ga.useIndex2Constraints = True
        ss.timeIntegration.newton.useModifiedNewton = True
        stype = exu.DynamicSolverType.GeneralizedAlpha
    t0 = time.perf_counter()
    ok = mbs.SolveDynamic(ss, solverType=stype)
    solve_s = time.perf_counter() - t0
    T = float(mbs.systemData.GetTime())
    # sanity of the end state: the wheel loads carry the vehicle's weight
    res = contact.evaluate(mbs, T)
    Q = -res[:, :, C.RES_F_TRACK_Z].sum()
    W = vehicle.total_mass_kg * 9.81
    out = dict(ok=bool(ok), solve_seconds=solve_s, contact_calls=int(contact.n_calls), end_time_s=T,
               wheel_loads_over_weight=float(Q / W))
    if bridge is not None:
        q, _ = bridge.coordinates(mbs)
        out["n_modes"] = modes.n_modes
        out["deck_mid_deflection_end_m"] = float(modes.shape_at(SPAN_M / 2)[1] @ q)
    return out


def _git():
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True,
                              timeout=10).stdout.strip() or None
    except Exception:  # pragma: no cover
        return None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args(argv)
    if args.repeats < 1 or args.steps < 1:
        ap.error("--repeats and --steps must be >= 1")

    modes = deck_modes()
    for solver in SOLVERS:                          # warm-up: numba caches, Exudyn
        for track in TRACKS:
            run_once(track, solver, 5, modes)
    configs = [(s, tr) for s in SOLVERS for tr in TRACKS]
    times = {c: [] for c in configs}
    info = {}
    for rep in range(args.repeats):
        for cfg in configs:                          # interleaved: a load change on the machine hits all alike
            r = run_once(cfg[1], cfg[0], args.steps, modes)
            if not r["ok"]:
                print(f"{cfg}: SolveDynamic reported failure", file=sys.stderr)
            times[cfg].append(r["solve_seconds"])
            info[cfg] = r
            print(f"repeat {rep + 1}: {cfg[0]:7s} {cfg[1]:15s} {r['solve_seconds']:.3f} s  "
                  f"(Q/W at end {r['wheel_loads_over_weight']:.4f})", flush=True)
    sim_time = args.steps * DT_S
    rows = []
    for cfg in configs:
        t = min(times[cfg])
        r = info[cfg]
        rows.append(dict(solver=cfg[0], track=cfg[1], solve_seconds_min=t, solve_seconds_all=times[cfg],
                         us_per_step=t / args.steps * 1e6, real_time_factor=sim_time / t,
                         contact_calls_per_step=r["contact_calls"] / args.steps, ok=r["ok"],
                         wheel_loads_over_weight_at_end=r["wheel_loads_over_weight"],
                         **({"n_modes": r["n_modes"], "deck_mid_deflection_end_m": r["deck_mid_deflection_end_m"]}
                            if "n_modes" in r else {})))
    by = {(r["solver"], r["track"]): r for r in rows}
    ratios = {s: {"bridge_over_rigid": by[(s, "bridge")]["solve_seconds_min"] / by[(s, "rigid")]["solve_seconds_min"],
                  "bridge_support_over_rigid": by[(s, "bridge+support")]["solve_seconds_min"]
                  / by[(s, "rigid")]["solve_seconds_min"],
                  "lateral_irregularity_over_rigid": by[(s, "rigid+lat_irr")]["solve_seconds_min"]
                  / by[(s, "rigid")]["solve_seconds_min"],
                  "extra_us_per_step_bridge": by[(s, "bridge")]["us_per_step"] - by[(s, "rigid")]["us_per_step"]}
              for s in SOLVERS}
    print("modal vs FFRF formulation (benchmark_formulations) ...", flush=True)
    bf = benchmark_formulations(n_repeat=args.repeats)
    form = {"n_modes": bf["n_modes"],
            "case": "simply supported 20 m span (m = 15 t/m, f1 = 4.53 Hz, zeta = 0), all modes up to 150 Hz, one "
                    "200 kN force at 40 m/s, 0.75 s, generalized-alpha rho = 1, dt = 0.5 ms (1500 steps), best of "
                    f"{args.repeats}"}
    for k in ("modal", "ffrf"):
        form[k] = {"error_rel_peak_vs_fryba": bf[k]["error_rel_peak"], "us_per_step": bf[k]["s_per_step"] * 1e6}
    form["ffrf_over_modal"] = bf["ffrf"]["s_per_step"] / bf["modal"]["s_per_step"]

    result = dict(
        case=f"Manchester vehicle 1, {SPEED_KM_H:g} km/h, {args.steps} steps of {DT_S * 1e3:g} ms, straight track "
             f"without irregularities; bridge: {SPAN_M:g} m simply supported deck of "
             f"examples/scenarios/bridge_20m.toml (modal, {modes.n_modes} modes up to {modes.frequencies_Hz[-1]:.1f} Hz), leading wheelset "
             f"{LEAD_IN_M:g} m before it at t = 0",
        creep_law=CREEP["creep_law"], fastsim_grid=list(CREEP["fastsim_grid"]), repeats=args.repeats,
        simulated_time_s=sim_time, timing="wall time inside mbs.SolveDynamic, minimum over the repeats",
        newmark="beta 1/4, gamma 1/2 (trapezoidal), modified Newton, connector Jacobian",
        rk44="explicit RK44, Lie-group integration, no end-of-step accelerations",
        support_motion="sine burst 1.5 m/s2 at 1.5 Hz (SmoothHarmonicSupportMotion, one-period ramp)",
        rows=rows, ratios=ratios, formulations=form,
        python=platform.python_version(), platform=platform.platform(), cpu_count=os.cpu_count(),
        load_average=list(os.getloadavg()), date=time.strftime("%Y-%m-%dT%H:%M:%S%z"), git=_git())
    try:
        import numba
        result["exudyn"], result["numba"] = exu.__version__, numba.__version__
    except Exception:  # pragma: no cover
        pass
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(result, fh, indent=2)

    print(f"\n### Vehicle on the flexible bridge vs rigid track ({SPAN_M:g} m span, {SPEED_KM_H:g} km/h, "
          f"{args.steps} steps of {DT_S * 1e3:g} ms, min of {args.repeats})\n")
    print("| solver | track | solve [s] | µs/step | real-time factor | contact calls/step | vs rigid |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for r in rows:
        rel = r["solve_seconds_min"] / by[(r["solver"], "rigid")]["solve_seconds_min"]
        print(f"| {r['solver']} | {r['track']} | {r['solve_seconds_min']:.3f} | {r['us_per_step']:.0f} | "
              f"{r['real_time_factor']:.2f} | {r['contact_calls_per_step']:.1f} | {rel:.2f} |")
    print(f"\n### Bridge formulations (deck alone, {form['n_modes']} modes, best of {args.repeats})\n")
    print("| formulation | µs/step | mid-span error vs Frýba (of peak) |")
    print("|---|---:|---:|")
    for k in ("modal", "ffrf"):
        print(f"| {k} | {form[k]['us_per_step']:.1f} | {form[k]['error_rel_peak_vs_fryba'] * 100:.3f} % |")
    print(f"\nFFRF / modal = {form['ffrf_over_modal']:.1f}")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
