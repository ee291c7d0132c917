"""Cost per time step against the number of wheelsets (1, 4, 16, 32): planning trains (8 cars = 32 wheelsets).

Models (public API only):

* 1 wheelset: ``vehicles/single_wheelset.toml`` (the Manchester wheelset under its static axle load);
* 4, 16, 32 wheelsets: a train of 1, 4, 8 Manchester vehicles (``vehicles/manchester_vehicle1.toml``): the first
  n cars of the consist ``vehicles/trains/manchester_x8.toml`` (car length :data:`SPACING_M`, end to end, its
  couplers), built by :func:`~exudyn_wheelrail.rolling_stock.train.build_train` — every car at its own place in the
  model frame (car k's centre at ``x = -(k - 1) SPACING_M``), one frame ``s_start_m = S_START_M`` for all.

Track: straight, rigid, a lateral harmonic (:data:`LATERAL_AMPLITUDE_M`, wavelength = the spacing) plus a vertical
one (:data:`VERTICAL_AMPLITUDE_M`, half the spacing), so every wheel's contact moves (creepages, lateral creep
forces, varying loads) and every vehicle of the train sees the same track; speed 250 km/h, the vehicles start in
equilibrium on the displaced track (``place_on_rails``, ``rolling_stock.placement.start_on_track``).

Wheel–rail coupling, three ways:

* ``contact`` — **one** wheel–rail connector for all wheelsets of the train (``build_train``'s default; what the
  pipeline supports: :func:`~exudyn_wheelrail.simulation.runner.run` watches one connector, so every wheelset is
  watched by the run monitor and recorded).  Recording (``RunSettings.record``): the train's probes
  (:func:`exudyn_wheelrail.scenarios.probes.train_probes`): all wheels, the irregularity under every wheelset and
  two car-body points (above the bogies, floor height) of every car;
* ``per_vehicle`` — one connector per car (``build_train(..., wheel_rail="none")`` and a connector for each car's
  wheelsets); the runner watches the first car's connector only, the others run unwatched (their results are not
  evaluated at the recorded states, so this variant is measured without recording); 16 and 32 wheelsets (at 4 it
  is the same model as ``contact``);
* ``springs`` — ``build_train(..., wheel_rail="springs")``: linear springs instead of the contact, nothing
  watched or recorded (``run(..., contact=None)``): the cost of the multibody model itself.

Integrators RK44 and Newmark (trapezoidal rule, modified Newton, the connector's forward-difference Jacobian), both
at 1 ms, :data:`STEPS` steps.  Time = ``RunOutcome.solve_seconds`` (``mbs.SolveDynamic`` only: model building,
numba compilation — one untimed run of each solver first — and the connector's ``warm_up`` are outside).  Every
configuration runs :data:`REPEATS` times, alternating (each repeat runs all configurations once, in turn), fresh
model each time; the **median** is reported with min–max and the load average (``os.getloadavg``, 1 min) before
each run.

Per configuration: µs per step, µs per wheelset and step, real-time factor (simulated / wall time), ratio to the
springs model (same count and solver), contact calls per step (``WheelRailContact.n_calls`` summed over the
connectors: the integrator's right-hand sides, the monitor's one evaluation per state, one evaluation before the
solve; Newmark's Jacobian calls come on top, each 13 evaluations inside one compiled call).

The split (configuration ``split``, in the same alternating loop): the ``contact`` model without recording, with a
wrapper on the instance's ``forces`` (the connector's force user function calls ``self.forces``) that saves every
call's arguments and warm-start state, and one on the module's compiled Jacobian that times it in place; right after
the run ``contact.forces`` is timed **alone** on the saved states, replayed one by one from each saved warm start.
Solve time = ``solve_seconds`` minus the wrappers' own time; contact = replayed ``forces`` + Jacobian; rest = solve
minus contact: Exudyn (bodies, suspension, integrator, calling the Python user functions), the run monitor's checks
beyond its contact evaluation, the runner's hook.  The ``forces`` time measured inside the run is reported beside
the replay.

Target: 32 wheelsets at >= 1.5 x real time (RK44, 1 ms, recording on).

Run:  python benchmarks/bench_scaling.py [--repeats 3] [--steps 400] [--counts 1 4 16 32]
Writes benchmarks/results/scaling.json.
"""
from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from exudyn_wheelrail.multibody.direct_call import python_call_path
from exudyn_wheelrail.simulation.settings import ContactSettings

RESULTS = Path(__file__).resolve().parent / "results" / "scaling.json"
ROOT = Path(__file__).resolve().parents[1]

SPEED_KM_H = 250.0
SPACING_M = 26.0                 #: distance between the cars' centres [m]: the car length of manchester_x8.toml
S_START_M = 0.0                  #: track distance of car 1's centre at t = 0
LATERAL_AMPLITUDE_M = 2e-3
VERTICAL_AMPLITUDE_M = 1e-3
DT_S = 1e-3
STEPS = 400
REPEATS = 3
COUNTS = (1, 4, 16, 32)
SOLVERS = ("rk44", "newmark")
TARGET = dict(wheelsets=32, solver="rk44", record=True, real_time_factor_min=1.5)


def track():
    from exudyn_wheelrail.track.rigid import Harmonic, IrregularitySum, RigidStraightTrack
    return RigidStraightTrack(IrregularitySum([
        Harmonic(amplitude_m=LATERAL_AMPLITUDE_M, wavelength_m=SPACING_M, direction="lateral"),
        Harmonic(amplitude_m=VERTICAL_AMPLITUDE_M, wavelength_m=SPACING_M / 2, direction="vertical")]))


def build(n_wheelsets: int, coupling: str, record: bool):
    """Assembled model: ``(mbs, system container, contacts, recorder, train)`` (module docstring)."""
    import exudyn as exu

    from exudyn_wheelrail.contact import WheelRailPair
    from exudyn_wheelrail.multibody import (add_train_contact, add_wheel_rail_contact, build_vehicle, load_vehicle,
                                           place_on_rails)
    from exudyn_wheelrail.rolling_stock.train import build_train, load_consist, place_train_on_track
    from exudyn_wheelrail.rolling_stock.placement import start_on_track
    from exudyn_wheelrail.scenarios.probes import train_probes
    from exudyn_wheelrail.scenarios.spec import DEFAULT_FLOOR_HEIGHT_M
    from exudyn_wheelrail.simulation.recorder import Recorder, vehicle_probes

    V = SPEED_KM_H / 3.6
    trk = track()
    cs = ContactSettings()
    contact_options = dict(creep_law=cs.creep_law, mu=cs.friction, fastsim_grid=cs.fastsim_grid,
                           geometry=cs.geometry)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    if n_wheelsets == 1:                                     # the single wheelset: no train
        data = load_vehicle("single_wheelset")
        geo = data.geometry
        pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                             inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
        springs = coupling == "springs"
        model = build_vehicle(mbs, data, speed_m_s=V, s_start_m=S_START_M, wheel_rail="springs" if springs else "none")
        contacts, recorder = [], None
        if not springs:
            contacts = [add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V, track=trk,
                                               s_start_m=S_START_M, **contact_options)]
            place_on_rails(mbs, model, pair)
            start_on_track(mbs, model, trk)
            if record:
                recorder = Recorder(vehicle_probes(model=model, contact=contacts[0], track=trk, speed_m_s=V,
                                                   s_leading0_m=S_START_M, mbs=mbs), n_rows_hint=STEPS + 2)
        mbs.Assemble()
        for c in contacts:
            c.warm_up(mbs)
        return mbs, sc, contacts, recorder, model
    consist = load_consist("manchester_x8")
    n_cars = n_wheelsets // consist.cars[0].vehicle.n_wheelsets
    if n_cars * consist.cars[0].vehicle.n_wheelsets != n_wheelsets or not 1 <= n_cars <= consist.n_cars:
        raise ValueError(f"{n_wheelsets} wheelsets: expected 1 or 4, 8, ... {4 * consist.n_cars}")
    consist = dataclasses.replace(consist, cars=consist.cars[:n_cars])
    geo = consist.cars[0].vehicle.geometry
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    train = build_train(mbs, consist, speed_m_s=V, s_start_m=S_START_M,
                        wheel_rail="springs" if coupling == "springs" else "none")
    contacts = []
    if coupling == "contact":
        contacts = [add_train_contact(mbs, train, pair, track=trk, **contact_options)]
    if coupling == "per_vehicle":
        contacts = [add_wheel_rail_contact(mbs, car.wheelset_nodes, pair, speed_m_s=V, track=trk, s_start_m=S_START_M,
                                           name=f"wheel_rail_contact_c{k + 1}", **contact_options)
                    for k, car in enumerate(train.cars)]
        place_train_on_track(mbs, train, pair, trk)
    recorder = None
    if record:
        if coupling != "contact":
            raise ValueError("recording is measured with one connector for all wheelsets only")
        lead = max(consist.cars[0].vehicle.wheelset_x_m())
        points = [{"name": name, "x_m": x, "y_m": 0.0, "height_m": DEFAULT_FLOOR_HEIGHT_M}
                  for name, x in (("rear", "rear_bogie"), ("front", "front_bogie"))]
        recorder = Recorder(train_probes(train, contacts[0], trk, V, S_START_M + lead, points, mbs=mbs),
                            n_rows_hint=STEPS + 2)
    mbs.Assemble()
    for c in contacts:
        c.warm_up(mbs)
    return mbs, sc, contacts, recorder, train


def run_once(n_wheelsets: int, coupling: str, solver: str, record: bool, steps: int) -> dict:
    """One run of a fresh model; returns its figures.  ``coupling="split"``: the ``contact`` model with every
    ``contact.forces`` call saved (arguments and warm start) and replayed alone after the run, and the Jacobian calls
    timed in place (module docstring)."""
    from exudyn_wheelrail.multibody import connector as C
    from exudyn_wheelrail.simulation.runner import run
    from exudyn_wheelrail.simulation.settings import RunSettings

    split = coupling == "split"
    with python_call_path() if split else contextlib.nullcontext():     # split: every call through c.forces
        mbs, _sc, contacts, recorder, _models = build(n_wheelsets, "contact" if split else coupling, record)
    settings = RunSettings(solver=solver, dt_s=DT_S, duration_s=steps * DT_S, record=record)
    calls0 = [c.n_calls for c in contacts]
    saved = []
    acc = dict(in_situ=0.0, wrapper=0.0, jacobian=0.0, jacobian_calls=0)
    original_jacobian = C.contact_jacobian_core
    if split:
        c = contacts[0]
        forces = c.forces
        clock = time.perf_counter

        def saving(q, q_t, t):
            t0 = clock()
            saved.append((np.array(q, dtype=float), np.array(q_t, dtype=float), float(t), c.save_warm_start()))
            t1 = clock()
            f = forces(q, q_t, t)
            t2 = clock()
            acc["in_situ"] += t2 - t1
            acc["wrapper"] += t1 - t0 + clock() - t2
            return f

        def timed_jacobian(*args):
            t0 = clock()
            out = original_jacobian(*args)
            acc["jacobian"] += clock() - t0
            acc["jacobian_calls"] += 1
            return out

        c.forces = saving                      # the connector's force user function calls self.forces
        C.contact_jacobian_core = timed_jacobian
    load = os.getloadavg()[0]
    try:
        out = run(mbs, settings, contacts[0] if contacts else None, speed_m_s=SPEED_KM_H / 3.6, recorder=recorder)
    finally:
        C.contact_jacobian_core = original_jacobian
    r = dict(solve_seconds=out.solve_seconds, status=out.status.kind, load_1min=load,
             contact_calls=sum(c.n_calls for c in contacts) - sum(calls0), t_end_s=out.t_end_s,
             rows=(recorder.n if recorder is not None else 0))
    if split:
        r.update(forces_calls=len(saved), forces_replay_seconds=replay_forces(contacts[0], saved),
                 forces_in_situ_seconds=acc["in_situ"], wrapper_seconds=acc["wrapper"],
                 jacobian_seconds=acc["jacobian"], jacobian_calls=acc["jacobian_calls"])
    return r


def replay_forces(contact, saved) -> float:
    """Seconds of ``contact.forces`` over the saved calls, each from its saved warm start, one by one."""
    forces = type(contact).forces
    total = 0.0
    for q, v, t, warm in saved:
        contact.restore_warm_start(warm)
        t0 = time.perf_counter()
        forces(contact, q, v, t)
        total += time.perf_counter() - t0
    return total


def machine() -> dict:
    info = dict(python=platform.python_version(), platform=platform.platform(), cpu_count=os.cpu_count())
    try:
        with open("/proc/cpuinfo") as fh:
            info["cpu"] = next((ln.split(":", 1)[1].strip() for ln in fh if ln.startswith("model name")), "")
    except OSError:
        info["cpu"] = platform.processor()
    import exudyn
    import numba
    info.update(exudyn=exudyn.__version__, numba=numba.__version__, numpy=np.__version__)
    try:
        def git(*a):
            return subprocess.run(["git", *a], cwd=ROOT, capture_output=True, text=True, check=False).stdout.strip()
        info["git_head"] = git("rev-parse", "--short", "HEAD")
        info["git_modified_files"] = len([ln for ln in git("status", "--porcelain").splitlines() if ln.strip()])
    except OSError:
        pass
    return info


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True, check=False).stdout.strip()
    except OSError:
        return "load average: {:.2f}, {:.2f}, {:.2f}".format(*os.getloadavg())


def _median(values):
    return statistics.median(values)


def main(argv=None):
    global STEPS
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=REPEATS)
    ap.add_argument("--steps", type=int, default=STEPS)
    ap.add_argument("--counts", type=int, nargs="+", default=list(COUNTS))
    ap.add_argument("--solvers", nargs="+", default=list(SOLVERS))
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args(argv)
    STEPS = args.steps
    t_wall = time.perf_counter()
    uptime_start = uptime()

    configs = []                           # (wheelsets, coupling, solver, record)
    for n in args.counts:
        for solver in args.solvers:
            configs += [(n, "contact", solver, False), (n, "contact", solver, True), (n, "springs", solver, False),
                        (n, "split", solver, False)]
            if n > 4:
                configs.append((n, "per_vehicle", solver, False))
    # untimed warm-up: numba caches, Exudyn, every coupling and solver once
    for solver in args.solvers:
        for coupling, record in (("contact", True), ("per_vehicle", False), ("springs", False), ("split", False)):
            run_once(8 if coupling == "per_vehicle" else 4, coupling, solver, record, 5)
    runs = {cfg: [] for cfg in configs}
    for rep in range(args.repeats):
        for cfg in configs:
            n, coupling, solver, record = cfg
            r = run_once(n, coupling, solver, record, args.steps)
            runs[cfg].append(r)
            print(f"repeat {rep + 1}: {n:2d} ws {coupling:11s} {solver:7s} record={record!s:5s} "
                  f"{r['solve_seconds'] * 1e6 / args.steps:8.0f} us/step  {r['status']}  load {r['load_1min']:.2f}",
                  flush=True)

    sim_time = args.steps * DT_S
    per_step = 1e6 / args.steps
    rows, splits = [], []
    for cfg in configs:
        n, coupling, solver, record = cfg
        rs = runs[cfg]
        loads = [r["load_1min"] for r in rs]
        if coupling == "split":
            net = [r["solve_seconds"] - r["wrapper_seconds"] for r in rs]
            contact = [r["forces_replay_seconds"] + r["jacobian_seconds"] for r in rs]
            spr = _median(r["solve_seconds"] for r in runs[(n, "springs", solver, False)])
            splits.append(dict(
                wheelsets=n, solver=solver, steps=args.steps, solve_us_per_step=_median(net) * per_step,
                forces_calls_per_step=rs[0]["forces_calls"] / args.steps,
                jacobian_calls_per_step=rs[0]["jacobian_calls"] / args.steps,
                forces_us_per_call_replay=_median(r["forces_replay_seconds"] / r["forces_calls"] for r in rs) * 1e6,
                forces_us_per_call_in_situ=_median(r["forces_in_situ_seconds"] / r["forces_calls"] for r in rs) * 1e6,
                forces_us_per_wheelset_call=_median(r["forces_replay_seconds"] / r["forces_calls"] for r in rs)
                * 1e6 / n,
                jacobian_us_per_step=_median(r["jacobian_seconds"] for r in rs) * per_step,
                contact_us_per_step=_median(contact) * per_step,
                rest_us_per_step=_median(a - b for a, b in zip(net, contact)) * per_step,
                contact_share=_median(b / a for a, b in zip(net, contact)),
                springs_us_per_step=spr * per_step,
                status=sorted({r["status"] for r in rs}), load_1min_range=[min(loads), max(loads)]))
            continue
        t = [r["solve_seconds"] for r in rs]
        med = _median(t)
        row = dict(wheelsets=n, coupling=coupling, solver=solver, record=record, steps=args.steps,
                   solve_seconds_median=med, solve_seconds_all=t, us_per_step=med * per_step,
                   us_per_step_min_max=[min(t) * per_step, max(t) * per_step],
                   us_per_wheelset_step=med * per_step / n, real_time_factor=sim_time / med,
                   status=sorted({r["status"] for r in rs}), load_1min_range=[min(loads), max(loads)],
                   contact_calls_per_step=rs[0]["contact_calls"] / args.steps, rows_recorded=rs[0]["rows"])
        if coupling != "springs":
            row["ratio_to_springs"] = med / _median(r["solve_seconds"] for r in runs[(n, "springs", solver, False)])
        rows.append(row)
    by = {(r["wheelsets"], r["coupling"], r["solver"], r["record"]): r for r in rows}
    tgt = by.get((TARGET["wheelsets"], "contact", TARGET["solver"], TARGET["record"]))
    result = dict(
        what="cost per time step vs number of wheelsets (bench_scaling.py docstring)",
        model=dict(speed_km_h=SPEED_KM_H, spacing_m=SPACING_M, lateral_amplitude_m=LATERAL_AMPLITUDE_M,
                   lateral_wavelength_m=SPACING_M, vertical_amplitude_m=VERTICAL_AMPLITUDE_M,
                   vertical_wavelength_m=SPACING_M / 2, dt_s=DT_S, steps=args.steps, simulated_time_s=sim_time,
                   vehicles={"1": "single_wheelset",
                             "4, 16, 32": "the first n/4 cars of vehicles/trains/manchester_x8.toml (build_train)"},
                   contact=dict(creep_law=ContactSettings().creep_law, geometry=ContactSettings().geometry)),
        repeats=args.repeats, statistic="median of repeats, configurations alternating", rows=rows, split=splits,
        target=dict(**TARGET, measured_real_time_factor=tgt["real_time_factor"] if tgt else None,
                    met=(tgt["real_time_factor"] >= TARGET["real_time_factor_min"]) if tgt else None),
        machine=machine(), uptime_start=uptime_start, uptime_end=uptime(),
        runtime_s=time.perf_counter() - t_wall, date=time.strftime("%Y-%m-%dT%H:%M:%S%z"))
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(result, fh, indent=2)

    print(f"\n{result['machine'].get('cpu')}; {uptime_start} ... {result['uptime_end']}\n")
    print("| wheelsets | solver | coupling | recording | µs/step (min–max) | µs/(wheelset·step) | real-time factor "
          "| ÷ springs | contact calls/step | load (1 min) |")
    print("|---:|---|---|---|---:|---:|---:|---:|---:|---|")
    for r in rows:
        ratio = f"{r['ratio_to_springs']:.1f}" if "ratio_to_springs" in r else "—"
        calls = f"{r['contact_calls_per_step']:.2f}" if r["coupling"] != "springs" else "—"
        print(f"| {r['wheelsets']} | {r['solver']} | {r['coupling']} | {'yes' if r['record'] else 'no'} | "
              f"{r['us_per_step']:.0f} ({r['us_per_step_min_max'][0]:.0f}–{r['us_per_step_min_max'][1]:.0f}) | "
              f"{r['us_per_wheelset_step']:.0f} | {r['real_time_factor']:.2f} | {ratio} | {calls} | "
              f"{r['load_1min_range'][0]:.1f}–{r['load_1min_range'][1]:.1f} |")
    print("\n| wheelsets | solver | µs/step | forces calls/step | forces µs/call alone (in the run) "
          "| µs per wheelset-call | contact µs/step | rest µs/step | contact share | springs µs/step | load (1 min) |")
    print("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    for r in splits:
        calls = f"{r['forces_calls_per_step']:.2f}"
        if r["jacobian_calls_per_step"]:
            calls += f" (+ {r['jacobian_calls_per_step']:.3f} Jacobian)"
        print(f"| {r['wheelsets']} | {r['solver']} | {r['solve_us_per_step']:.0f} | {calls} | "
              f"{r['forces_us_per_call_replay']:.1f} ({r['forces_us_per_call_in_situ']:.1f}) | "
              f"{r['forces_us_per_wheelset_call']:.1f} | {r['contact_us_per_step']:.0f} | "
              f"{r['rest_us_per_step']:.0f} | {r['contact_share']:.2f} | {r['springs_us_per_step']:.0f} | "
              f"{r['load_1min_range'][0]:.1f}–{r['load_1min_range'][1]:.1f} |")
    if tgt:
        print(f"\ntarget: {TARGET['wheelsets']} wheelsets, {TARGET['solver']} 1 ms, recording: real-time factor "
              f"{tgt['real_time_factor']:.2f} (>= {TARGET['real_time_factor_min']}): "
              f"{'MET' if result['target']['met'] else 'NOT MET'}")
    print(f"wrote {args.out} ({result['runtime_s']:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
