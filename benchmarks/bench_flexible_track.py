"""The flexible track: error of the modal reduction against the full finite-element model, and the cost of a
crossing against the rigid track.

    /tmp/venv_dev/bin/python benchmarks/bench_flexible_track.py [--skip-runs] [--duration 0.4]

1. Reduction error (default 60E1 ballasted track, a 30 m segment): per cut-off ``modes_up_to_Hz`` the kept modes
   (per metre), the static deflection under one wheelset (2 x 80 kN) at a sleeper and mid-bay — vertical, and a
   10 kN lateral force — relative to the full model, and the vertical receptance at the full-track and
   rail-on-pad peaks (frequency and magnitude) relative to the full model.
2. Cost of a crossing: the RTRI car (Manchester vehicle 1) at 250 km/h from s = 8 m into the RTRI lateral span
   deflection, ``--duration`` s, through the scenario pipeline (build, then solve with the monitor; recording on):
   rigid track with RK44 at 1, 0.5 and 0.25 ms, flexible track (auto segment) with RK44 at 0.25 ms (modes to
   800 Hz, the default; the wheel on the rail's modal mass needs <= 0.35 ms) and at 0.4 ms with modes to 400 Hz
   (21 % too stiff statically).  One run each (the
   machine is shared), load printed beside every timing.
"""
from __future__ import annotations

import argparse
import os
import time

import numpy as np

from exudyn_wheelrail.track.flexible import FlexibleTrackModel, TrackParameters


def load() -> str:
    return "load %.2f %.2f %.2f" % os.getloadavg()


def reduction_error(cutoffs=(400.0, 800.0, 1200.0)):
    p = TrackParameters.from_file()
    model = FlexibleTrackModel(p, 0.0, 30.0)
    f_grid = {"full-track": np.arange(40.0, 120.0, 0.5), "rail-on-pad": np.arange(300.0, 600.0, 1.0)}
    s_sl, s_mid = 15.0, 15.3
    full_rec = {k: model.receptance("vertical", s_sl, f) for k, f in f_grid.items()}
    print(f"reduction error, 30 m segment, {model.n_sleepers} sleepers ({load()})")
    print("  cut-off  modes  /m   static z sleeper  mid-bay   static y sleeper  mid-bay   "
          "receptance peaks (f, |a|) full-track  rail-on-pad")
    for fc in cutoffs:
        t0 = time.perf_counter()
        modes = model.modes(f_max_Hz=fc)
        t_modes = time.perf_counter() - t0
        errs = []
        for kind, row, F in (("vertical", 1, 160e3), ("lateral", 0, 10e3)):
            for s in (s_sl, s_mid):
                u = model.static(kind, [(s, F)])
                w_full = float(model.rail_field(kind, u, s)[0][0])
                Fv = [0.0, 0.0, 0.0]
                Fv[row] = F
                w_red = float(modes.shape_at(s)[row] @ modes.static_coordinates([s], [Fv]))
                errs.append(w_red / w_full - 1.0)
        rec = []
        for k, f in f_grid.items():
            a_full, a_red = np.abs(full_rec[k]), np.abs(modes.receptance("vertical", s_sl, f))
            rec.append((f[np.argmax(a_red)] / f[np.argmax(a_full)] - 1.0, a_red.max() / a_full.max() - 1.0))
        print(f"  {fc:6.0f}  {modes.n_modes:5d} {modes.n_modes / model.length_m:4.1f}   "
              f"{errs[0]:+8.2%} {errs[1]:+8.2%}      {errs[2]:+8.2%} {errs[3]:+8.2%}     "
              f"({rec[0][0]:+.2%}, {rec[0][1]:+.2%})  ({rec[1][0]:+.2%}, {rec[1][1]:+.2%})   "
              f"[modes {t_modes:.2f} s]")


def crossing(duration_s: float):
    from exudyn_wheelrail.scenarios.build import build_scenario
    from exudyn_wheelrail.scenarios.run import run_model
    from exudyn_wheelrail.scenarios.spec import validate_scenario

    def run(dt, flex=None):
        d = {"schema_version": 2, "vehicle": {"name": "manchester_vehicle1", "speed_km_h": 250.0, "start_s_m": 8.0},
             "track": [{"type": "span_deflection", "span_length_m": 20.0, "amplitude_m": 0.010, "start_m": 11.5,
                        "transition_length_m": 3.0, "direction": "lateral"}],
             "run": {"duration_s": duration_s, "solver": "rk44", "dt_s": dt},
             "outputs": {"plots": False, "criteria": False, "timeseries": ["Y", "Q"]}}
        if flex is not None:
            d["flexible_track"] = flex
        t0 = time.perf_counter()
        h = build_scenario(validate_scenario(d))
        t1 = time.perf_counter()
        out = run_model(h, progress=False)
        t2 = time.perf_counter()
        ts = h.recorder.table()
        y = max(np.nanmax(np.abs(ts[c])) for c in ts if c.startswith("Y_w"))
        q = max(np.nanmax(np.abs(ts[c])) for c in ts if c.startswith("Q_w"))
        m = h.flexible_track.modes if h.flexible_track is not None else None
        return t1 - t0, t2 - t1, out.status.kind, y, q, m

    print(f"\ncrossing: RTRI car 250 km/h, {duration_s} s ({duration_s * 250 / 3.6:.0f} m), RK44")
    res = {}
    for label, dt, flex in (("rigid, 1 ms", 1e-3, None), ("rigid, 0.5 ms", 5e-4, None),
                            ("rigid, 0.25 ms", 2.5e-4, None), ("flexible 800 Hz, 0.25 ms", 2.5e-4, {}),
                            ("flexible 400 Hz, 0.4 ms", 4e-4, {"modes_up_to_Hz": 400.0})):
        lb = load()
        tb, ts, st, y, q, m = run(dt, flex)
        res[label] = ts
        print(f"  {label:26s} build {tb:6.2f} s  solve {ts:7.2f} s  {st:8s} max|Y| {y / 1e3:6.2f} kN  "
              f"max Q {q / 1e3:6.2f} kN  {m if m is not None else ''}  ({lb})")
    base = res["rigid, 1 ms"]
    for k, v in res.items():
        print(f"  solve / rigid 1 ms: {k:26s} {v / base:6.2f}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skip-runs", action="store_true", help="only the reduction error")
    ap.add_argument("--duration", type=float, default=0.4, help="crossing duration [s]")
    a = ap.parse_args()
    reduction_error()
    if not a.skip_runs:
        crossing(a.duration)
