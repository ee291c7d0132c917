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
3. The moving window (``--window``; track/flexible_window.py): the same car and track, RK44 at 0.25 ms, on a fixed
   segment that carries the run (``length_m = "auto"``), on one five bays longer (how much the run depends on the
   reduced model itself) and on the window (``"window"``, moves of one bay), for ``--window-durations`` (default
   0.4 s and 1.5 s): modes, build and solve time, solve time per simulated second, and the differences from the
   first segment (largest over the run and the wheelsets: Q, Y, the rail's deflection under the wheelsets);
   written to benchmarks/results/flexible_track_window.json.
"""
from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np

from exudyn_wheelrail.track.flexible import FlexibleTrackModel
from exudyn_wheelrail.track.flexible_parameters import TrackParameters
from exudyn_wheelrail.simulation.exudyn_settings import run_solver_settings

RESULTS = Path(__file__).resolve().parent / "results"


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


def _flexible_run(vehicle_name: str, length_m: str, duration_s: float, dt_s: float, extend_bays: int = 0):
    """One RK44 run of ``vehicle_name`` at 250 km/h from s = 8 m into the RTRI lateral span deflection on the
    flexible track, a fixed segment (``"auto"``; ``extend_bays``: that many bays more at its start) or the moving
    window (``"window"``), assembled as the scenario build does, with the scenario's flexible-track functions;
    recording Q and Y of every wheel and the track columns.  Returns a dict of timings, sizes and the table."""
    import exudyn as exu

    from exudyn_wheelrail.contact.pair import WheelRailPair
    from exudyn_wheelrail.multibody.connector import add_wheel_rail_contact, place_on_rails
    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
    from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle_with_overrides
    from exudyn_wheelrail.rolling_stock.placement import start_on_track
    from exudyn_wheelrail.scenarios.build import build_track
    from exudyn_wheelrail.scenarios.spec import validate_scenario
    from exudyn_wheelrail.simulation.recorder import Recorder
    from exudyn_wheelrail.simulation.runner import run
    from exudyn_wheelrail.simulation.settings import RunSettings
    from exudyn_wheelrail.track.flexible import add_flexible_track
    from exudyn_wheelrail.scenarios.flexible_track import (flexible_track_modes, flexible_track_probes,
                                                          flexible_track_window, normalise_flexible_track,
                                                          start_on_flexible_track)

    V = 250.0 / 3.6
    t0 = time.perf_counter()
    scn = validate_scenario({
        "schema_version": 2, "vehicle": {"name": vehicle_name, "speed_km_h": 250.0, "start_s_m": 8.0},
        "track": [{"type": "span_deflection", "span_length_m": 20.0, "amplitude_m": 0.010, "start_m": 11.5,
                   "transition_length_m": 3.0, "direction": "lateral"}],
        "run": {"duration_s": duration_s, "solver": "rk44", "dt_s": dt_s}})
    vehicle = load_vehicle_with_overrides(vehicle_name)
    x = np.asarray(vehicle.wheelset_x_m())
    s_start = 8.0 - x.max()
    table = {"length_m": length_m}
    if extend_bays:
        from exudyn_wheelrail.track.flexible_segment import segment_for_run
        p = TrackParameters.from_file()
        start, length = segment_for_run(s_start + x.min(), s_start + V * duration_s + x.max(), p)
        table = {"start_m": start - extend_bays * p.sleeper_spacing_m,
                 "length_m": length + extend_bays * p.sleeper_spacing_m}
    ft = normalise_flexible_track(table, lambda k, m: ValueError(f"{k}: {m}"), None)
    modes = flexible_track_modes(ft, s_start_m=s_start, wheelset_x_m=x, speed_m_s=V, end_time_s=duration_s,
                                 solver="rk44", dt_s=dt_s, moving_window=True)
    t_modes = time.perf_counter() - t0
    track = build_track(scn)
    geo = vehicle.geometry
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    model = build_vehicle(mbs, vehicle, speed_m_s=V, s_start_m=s_start, wheel_rail="none")
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    handle = add_flexible_track(mbs, modes)
    contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V, track=track, s_start_m=s_start,
                                     structure=handle)
    place_on_rails(mbs, model, pair)
    start_on_track(mbs, model, track)
    start_on_flexible_track(mbs, model, handle)
    mbs.Assemble()
    win = flexible_track_window(ft, contact=contact, handle=handle)
    n_ws = len(x)

    class Wheels:
        columns = [("wheel", f"{c}_w{j + 1}{side[0]}") for j in range(n_ws) for side in ("left", "right")
                   for c in ("Q", "Y")]

        def fill(self, mbs, t, out):
            i = 0
            for j in range(n_ws):
                for side in ("left", "right"):
                    f = contact.wheel_force_N(j, side)
                    out[i], out[i + 1] = -f[2], f[1]
                    i += 2

    rec = Recorder([Wheels()] + flexible_track_probes(contact=contact, handle=handle, model=model, window=win),
                   n_rows_hint=int(duration_s / dt_s) + 2)
    settings = RunSettings(solver="rk44", dt_s=dt_s, duration_s=duration_s)
    sim, solver_type = run_solver_settings(settings)
    sim.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    contact.warm_up(mbs, jacobian=False)
    t_build = time.perf_counter() - t0
    lb = load()
    t1 = time.perf_counter()
    out = run(mbs, settings, contact, speed_m_s=V, recorder=rec, exu_settings=(sim, solver_type), user_function=win)
    t_solve = time.perf_counter() - t1
    q_cols = [c for c in rec.table() if c.startswith("Q_w")]
    y_cols = [c for c in rec.table() if c.startswith("Y_w")]
    tab = rec.table()
    return {"status": out.status.kind, "modes": modes.n_modes, "length_m": modes.model.length_m,
            "max_Q_N": round(float(max(np.nanmax(tab[c]) for c in q_cols)), 1),
            "max_abs_Y_N": round(float(max(np.nanmax(np.abs(tab[c])) for c in y_cols)), 1),
            "modes_s": round(t_modes, 2), "build_s": round(t_build, 2), "solve_s": round(t_solve, 2),
            "solve_per_simulated_s": round(t_solve / duration_s, 2), "load_before_solve": lb, "load_after": load(),
            "window": win.summary() if win is not None else None, "table": rec.table(), "n_wheelsets": n_ws}


def window_runs(durations, dt_s: float = 2.5e-4, vehicle_name: str = "manchester_vehicle1") -> dict:
    print(f"\nmoving window: {vehicle_name}, 250 km/h, RK44 {dt_s * 1e3:g} ms; fixed segment ('auto') vs window")
    out = {"vehicle": vehicle_name, "speed_km_h": 250.0, "solver": "rk44", "dt_s": dt_s, "runs": []}
    for duration in durations:
        res = {"fixed": _flexible_run(vehicle_name, "auto", duration, dt_s),
               "fixed, 5 bays longer": _flexible_run(vehicle_name, "auto", duration, dt_s, extend_bays=5),
               "window": _flexible_run(vehicle_name, "window", duration, dt_s)}
        a = res["fixed"]["table"]
        n = res["fixed"]["n_wheelsets"]
        q = [f"Q_w{j + 1}{s}" for j in range(n) for s in "lr"]
        y = [f"Y_w{j + 1}{s}" for j in range(n) for s in "lr"]
        z = [f"rail_z_w{j + 1}_m" for j in range(n)]
        t = np.asarray(a["time_s"])

        def diff(b, cols):
            A = np.array([np.asarray(a[c]) for c in cols])
            D = np.abs(A - np.array([np.asarray(b[c]) for c in cols]))
            # the largest difference in each tenth of the run: does it grow?
            tenths = [round(float(np.nanmax(D[:, (t >= lo) & (t <= lo + duration / 10)])), 1)
                      for lo in np.linspace(0.0, duration, 11)[:-1]]
            return float(np.nanmax(D)), float(np.nanmax(np.abs(A))), tenths

        errors = {}
        for k in ("fixed, 5 bays longer", "window"):
            b = res[k]["table"]
            (dq, q_max, dq_t), (dy, y_max, _), (dz, z_max, _) = diff(b, q), diff(b, y), diff(b, z)
            errors[k] = {"max_abs_dQ_N": round(dq, 1), "max_Q_N": round(q_max, 1), "dQ_rel": round(dq / q_max, 5),
                         "max_abs_dQ_N_per_tenth_of_run": dq_t, "max_abs_dY_N": round(dy, 1),
                         "max_abs_Y_N": round(y_max, 1), "dY_rel_to_Q": round(dy / q_max, 5),
                         "max_abs_d_rail_z_m": dz, "max_rail_z_m": z_max, "d_rail_z_rel": round(dz / z_max, 5)}
        for k, r in res.items():
            r.pop("table")
            print(f"  {duration:4.2f} s {k:21s} {r['status']:4s} {r['modes']:5d} modes ({r['length_m']:6.1f} m)  "
                  f"modes {r['modes_s']:5.2f} s  build {r['build_s']:5.2f} s  solve {r['solve_s']:7.2f} s = "
                  f"{r['solve_per_simulated_s']:6.2f} s per simulated s  ({r['load_before_solve']} before, "
                  f"{r['load_after']} after)  max Q {r['max_Q_N'] / 1e3:.2f} kN, max |Y| "
                  f"{r['max_abs_Y_N'] / 1e3:.2f} kN  {r['window'] or ''}")
        for k, e in errors.items():
            print(f"         {k} - fixed: max |dQ| {e['max_abs_dQ_N']:7.1f} N ({e['dQ_rel']:.2%} of max Q "
                  f"{e['max_Q_N'] / 1e3:.1f} kN; per tenth of the run {e['max_abs_dQ_N_per_tenth_of_run']}), "
                  f"max |dY| {e['max_abs_dY_N']:6.1f} N, rail z under the wheels "
                  f"{e['max_abs_d_rail_z_m'] * 1e6:.2f} um ({e['d_rail_z_rel']:.2%})")
        out["runs"].append({"duration_s": duration, **res, "difference_from_fixed": errors})
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "flexible_track_window.json").write_text(json.dumps(out, indent=2))
    print(f"wrote {RESULTS / 'flexible_track_window.json'}")
    return out


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skip-runs", action="store_true", help="only the reduction error")
    ap.add_argument("--duration", type=float, default=0.4, help="crossing duration [s]")
    ap.add_argument("--window", action="store_true", help="only the moving window against the fixed segment")
    ap.add_argument("--window-durations", type=float, nargs="+", default=[0.4, 1.5],
                    help="run durations of the window comparison [s]")
    a = ap.parse_args()
    if a.window:
        window_runs(a.window_durations)
    else:
        reduction_error()
        if not a.skip_runs:
            crossing(a.duration)
