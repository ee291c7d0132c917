"""Cost of the flexible car body (rolling_stock.flexible_body): the RTRI 20 m case at 250 km/h with the rigid and the
flexible car body (``RtriCase(car_body=...)``), RK44 1 ms (the ``default`` preset's integrator) and the paper's
Newmark 1 ms, the contact connector as in every RTRI run; and, to show where the cost goes, the vehicle on rail
springs (no contact) with Exudyn's CPU-time statistics of the solver.

solve_seconds = wall time inside ``mbs.SolveDynamic``; the runs are interleaved (rigid, flexible, rigid, ...) and
the minimum of ``--repeats`` is kept (the machine is shared: the load average is recorded before and after).
``record=False`` is the simulation alone, ``record=True`` the CLI's configuration (the recorder's rows; both car
bodies record the same point, above the rear bogie).  The product's target: the flexible run costs at most 1.5
times the rigid one.

Run:  python benchmarks/bench_flexible_car_body.py [--repeats 3] [--duration 1.0]
Writes benchmarks/results/flexible_car_body.json.
"""
from __future__ import annotations

import argparse
import io
import json
import os
import re
import time
from contextlib import redirect_stdout
from pathlib import Path

from exudyn_wheelrail.scenarios.rtri import RtriCase, run_rtri

RESULTS = Path(__file__).resolve().parent / "results"
TARGET_RATIO = 1.5


def _load() -> list[float]:
    return [round(v, 2) for v in os.getloadavg()]


def _springs_profile(vehicle: str, solver: str, dt_s: float, steps: int) -> dict:
    """Per-step cost and Exudyn's CPU-time shares of the vehicle on rail springs (no contact)."""
    import exudyn as exu

    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
    from exudyn_wheelrail.simulation.exudyn_settings import solver_settings
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    build_vehicle(mbs, vehicle, speed_m_s=250 / 3.6, wheel_rail="springs")
    mbs.Assemble()
    s, st = solver_settings(solver, dt_s, steps)
    s.show.computationTime = True
    s.timeIntegration.verboseMode = 1
    buf = io.StringIO()
    t0 = time.perf_counter()
    with redirect_stdout(buf):
        mbs.SolveDynamic(s, solverType=st)
    wall = time.perf_counter() - t0
    shares = {m.group(1).strip(): float(m.group(2)) for m in re.finditer(r"^\s+(\w[\w/ ]*?)\s*=\s*([\d.]+)%",
                                                                         buf.getvalue(), re.M)}
    return {"us_per_step": wall / steps * 1e6, "cpu_shares_percent": shares, "ode2_size": mbs.systemData.ODE2Size()}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--duration", type=float, default=1.0, help="simulated time per run [s]")
    args = ap.parse_args(argv)
    load_before = _load()
    solvers = ("rk44", "newmark")
    cases = {(solver, record, cb): RtriCase(span_m=20.0, speed_km_h=250.0, solver=solver, dt_s=1e-3,
                                            duration_s=args.duration, car_body=cb, record=record,
                                            carbody_points=("rear",))
             for solver in solvers for record in (False, True) for cb in ("rigid", "flexible")}
    for case in cases.values():                           # warm-up: numba, tables
        run_rtri(case.replace(duration_s=0.005))
    times = {k: [] for k in cases}
    for rep in range(args.repeats):
        for k, case in cases.items():
            r = run_rtri(case)
            assert r.summary["status"] == "ok", (k, r.summary["status"])
            times[k].append(r.summary["solve_seconds"])
            print(f"repeat {rep + 1}: {k[0]:8s} record={k[1]!s:5s} {k[2]:8s} {times[k][-1]:.3f} s  (load "
                  f"{_load()[0]})", flush=True)
    rows = []
    for solver, record in ((s_, r_) for s_ in solvers for r_ in (False, True)):
        t_r, t_f = min(times[(solver, record, "rigid")]), min(times[(solver, record, "flexible")])
        rows.append({"solver": solver, "record": record, "dt_s": 1e-3, "simulated_s": args.duration, "rigid_s": t_r,
                     "flexible_s": t_f, "ratio": t_f / t_r, "target_ratio": TARGET_RATIO,
                     "target_met": t_f / t_r <= TARGET_RATIO,
                     "rigid_us_per_step": t_r / args.duration * 1e-3 * 1e6,
                     "flexible_us_per_step": t_f / args.duration * 1e-3 * 1e6,
                     "all_rigid_s": times[(solver, record, "rigid")],
                     "all_flexible_s": times[(solver, record, "flexible")]})
    profile = {f"{solver} {veh}": _springs_profile(veh, solver, 1e-3, 1000)
               for solver in solvers for veh in ("manchester_vehicle1", "manchester_vehicle1_flexible")}
    load_after = _load()
    print(f"\nRTRI 20 m, 250 km/h, {args.duration:g} s simulated, min of {args.repeats}; load before {load_before}, "
          f"after {load_after}\n")
    print("| solver | record | rigid [s] | flexible [s] | ratio | target |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['solver']} 1 ms | {r['record']} | {r['rigid_s']:.3f} | {r['flexible_s']:.3f} | {r['ratio']:.2f} | "
              f"<= {TARGET_RATIO} {'met' if r['target_met'] else 'NOT met'} |")
    print("\nvehicle on rail springs (no contact), 1000 steps of 1 ms: us/step and Exudyn's CPU shares")
    for k, p in profile.items():
        print(f"  {k}: {p['us_per_step']:.0f} us/step, {p['ode2_size']} ODE2 coordinates, {p['cpu_shares_percent']}")
    RESULTS.mkdir(exist_ok=True)
    out = {"case": "RTRI 20 m, 250 km/h", "load_before": load_before, "load_after": load_after,
           "rows": rows, "springs_profile": profile}
    (RESULTS / "flexible_car_body.json").write_text(json.dumps(out, indent=2))
    print(f"wrote {RESULTS / 'flexible_car_body.json'}")


if __name__ == "__main__":
    main()
