"""Cost of the curve: the contact call with and without a track layout, and a steady-curving run.

Run:  python benchmarks/bench_curving.py [--repeats 15] [--no-run]

1. ``WheelRailContact.forces()`` of the Manchester vehicle (4 wheelsets, creep table) at rest on its rails: process
   CPU time per call (best and median of ``--repeats`` blocks of 2000 calls), straight track and the same connector
   with a curved layout (R = 600 m, 150 mm cant, every wheelset in the circular curve).  CPU time, not wall time:
   the machine is shared.
2. ``curving`` run (Manchester vehicle, R = 600 m, 150 mm cant, 120 km/h): solve time and the real-time factor.

Writes ``benchmarks/results/curving.json`` with the load average (``os.getloadavg``) beside every figure.
"""
from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import exudyn as exu
import numpy as np

from exudyn_wheelrail.contact.pair import WheelRailPair
from exudyn_wheelrail.multibody.connector import add_wheel_rail_contact, place_on_rails
from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
from exudyn_wheelrail.track.layout import TrackLayout

OUT = Path(__file__).resolve().parent / "results" / "curving.json"
SPEED_M_S = 30.0


def call_cost(layout, repeats: int) -> dict:
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=SPEED_M_S)
    pair = WheelRailPair("S1002", "UIC60", gauge_m=1.435, inclination="1/40", back_to_back_m=1.36, r0_m=0.46)
    c = add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=SPEED_M_S, layout=layout)
    place_on_rails(mbs, model, pair)                 # the static wheel loads on the rails
    q = np.concatenate([mbs.GetNodeParameter(w.node, "initialCoordinates") for w in model.wheelsets])
    v = np.zeros(24)
    v[4::6] = -SPEED_M_S / 0.46
    f = c.forces(q, v, 0.0)
    assert -f[2] > 1e5, "the wheels must carry their loads"
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        for i in range(2000):
            c.forces(q, v, 1e-4 * i)
        times.append((time.process_time() - t0) / 2000 * 1e6)
    return {"best_us": min(times), "median_us": float(np.median(times)), "load": os.getloadavg()}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--repeats", type=int, default=15)
    p.add_argument("--no-run", action="store_true", help="only the contact call")
    args = p.parse_args(argv)
    curve = TrackLayout.curve_entry(600.0, 0.15, 60.0, start_m=-200.0)
    res = {"forces_straight": call_cost(None, args.repeats), "forces_curved": call_cost(curve, args.repeats)}
    print("| contact call (CPU time per call) | best µs | median µs | load |\n|---|---|---|---|")
    for k in ("forces_straight", "forces_curved"):
        r = res[k]
        print(f"| {k} | {r['best_us']:.1f} | {r['median_us']:.1f} | {r['load'][0]:.1f} |")
    if not args.no_run:
        from exudyn_wheelrail.scenarios.curving import CurvingCase, run_curving
        load = os.getloadavg()
        t0 = time.perf_counter()
        r = run_curving(CurvingCase("manchester_vehicle1", radius_m=600.0, cant_m=0.15, speed_km_h=120.0))
        wall = time.perf_counter() - t0
        s = r.summary
        res["run"] = {"wall_s": wall, "solve_s": s["solve_seconds"], "simulated_s": s["t_end_s"],
                      "real_time_factor": s["t_end_s"] / s["solve_seconds"], "load": load,
                      "status": s["status"], "force_balance": s.get("force_balance")}
        print(f"curving run: {s['t_end_s']:.2f} s simulated in {s['solve_seconds']:.1f} s solve ({wall:.1f} s wall), "
              f"load {load[0]:.1f}")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(res, indent=2))
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
