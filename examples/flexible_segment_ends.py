"""What a wheel meets at the ends of a flexible track segment: one Manchester coach at constant speed over rigid
track, onto a segment of the ballasted 60E1 track on the ground (exudyn_wheelrail/track/flexible.py) and off it.

Off the segment the track is rigid (its modes vanish there), and the segment's rails end free on its first and last
sleeper.  Running onto the segment, the wheel meets the unloaded free rail end, which deflects more under it than
the continuous track (up to four times for a continuously supported rail end, Hetényi's semi-infinite beam); leaving
it, the wheel steps from the deflected rail end up onto the rigid rail — a step of the end's deflection, an impact.
Neither is a property of a track: a run on a flexible segment must keep every wheel away from the segment's ends
(:func:`exudyn_wheelrail.track.flexible_segment.segment_for_run`, the scenario check of ``[flexible_track]``,
examples/train_on_ballasted_bridge.py).  This example measures both transients; its run goes through the runner
like any other and prints the status it reports.

Run:  python examples/flexible_segment_ends.py [--speed-kmh 200] [--segment-m 20]
"""
from __future__ import annotations

import argparse
import math
from exudyn_wheelrail.simulation.exudyn_settings import run_solver_settings


#: the leading wheelset starts this far before the segment [m] and the run ends this far after the car left it
RUN_IN_M = 3.0
DT_S = 2.5e-4
#: one car of vehicles/trains/manchester_x2.toml (its sources and assumptions)
CAR = {"schema_version": 1,
       "train": {"name": "1 x Manchester benchmark vehicle 1",
                 "source": "vehicle: Iwnicki, Veh. Syst. Dyn. 30 (1998) 295-313; car length: assumed"},
       "car": [{"vehicle": "manchester_vehicle1", "length_m": 26.0}]}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed-kmh", type=float, default=200.0, help="running speed [km/h] (default 200)")
    ap.add_argument("--segment-m", type=float, default=20.0, help="length of the flexible segment [m] (default 20)")
    a = ap.parse_args(argv)
    if not (math.isfinite(a.speed_kmh) and 0.0 < a.speed_kmh <= 500.0):
        ap.error(f"--speed-kmh: {a.speed_kmh!r}: expected a speed in (0, 500] km/h")
    if not (math.isfinite(a.segment_m) and a.segment_m >= 4.0):
        ap.error(f"--segment-m: {a.segment_m!r}: expected at least 4 m")

    import exudyn as exu

    from exudyn_wheelrail.rolling_stock.train import consist_from_dict
    from exudyn_wheelrail.scenarios.bridge_crossing_vehicles import build_train_on_straight_track
    from exudyn_wheelrail.scenarios.probes import train_probes
    from exudyn_wheelrail.simulation.recorder import Recorder
    from exudyn_wheelrail.simulation.runner import run
    from exudyn_wheelrail.simulation.settings import RunSettings
    from exudyn_wheelrail.track.flexible import FlexibleTrackModel, add_flexible_track
    from exudyn_wheelrail.track.flexible_parameters import TrackParameters
    from exudyn_wheelrail.track.flexible_outputs import track_under_wheels

    consist = consist_from_dict(CAR, "<one car>")
    V = a.speed_kmh / 3.6
    x = consist.wheelset_x_m()
    s_start = -RUN_IN_M - float(x[0])
    params = TrackParameters.from_file()
    modes = FlexibleTrackModel(params, 0.0, a.segment_m).modes()
    mbs = exu.SystemContainer().AddSystem()
    handle = add_flexible_track(mbs, modes)
    train, track = build_train_on_straight_track(mbs, consist, speed_m_s=V, s_start_m=s_start, structure=handle)
    x1 = float(x[0])

    class Rail:
        columns = [("track", "rail_z_w1_right_m")]

        def fill(self, mbs_, t, out):
            q, q_t = handle.coordinates(mbs_)
            out[0] = track_under_wheels(modes, [train.track_distance_m(x1, t)], q, q_t)["rail_z_right_m"][0]

    probes = [Rail()] + train_probes(train, train.contact, track, V, s_start + x1, [])
    settings = RunSettings(solver="rk44", dt_s=DT_S,
                           duration_s=(2.0 * RUN_IN_M + a.segment_m + float(x[0] - x[-1])) / V)
    rec = Recorder(probes, n_rows_hint=settings.steps + 2)
    mbs.Assemble()
    sim, solver_type = run_solver_settings(settings)
    sim.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    outcome = run(mbs, settings, train.contact, speed_m_s=V, recorder=rec, exu_settings=(sim, solver_type))
    ts = rec.table()
    s1, Q, z = ts["s_leading_m"], ts["Q_w1_right_N"], ts["rail_z_w1_right_m"]
    k = params.support_stiffness_per_rail_N_m2()
    beta = (k / (4.0 * params.rail_E_Pa * params.rail_I_vertical_m4)) ** 0.25
    L = a.segment_m
    zones = {"entering (first 3 m)": (0.0, 3.0), "inside": (3.0, L - 3.0), "last 3 m": (L - 3.0, L),
             "leaving (3 m after)": (L, L + 3.0)}
    out = {"status": outcome.status.kind, "static_Q_N": float(Q[0]),
           "zimmermann_deflection_m": float(Q[0] * beta / (2.0 * k)), "zones": {}}
    print(f"one coach, {a.speed_kmh:g} km/h, {L:g} m segment on the ground ({modes.n_modes} modes), RK44 "
          f"{DT_S * 1e3:g} ms: status {outcome.status.kind} ({outcome.status.detail})")
    print(f"  leading wheel, right: static Q {Q[0] * 1e-3:.1f} kN, Zimmermann deflection "
          f"{out['zimmermann_deflection_m'] * 1e3:.3f} mm")
    for name, (lo, hi) in zones.items():
        m = (s1 >= lo) & (s1 < hi)
        r = {"Q_min_N": float(Q[m].min()), "Q_max_N": float(Q[m].max()), "rail_z_max_m": float(z[m].max())}
        out["zones"][name] = r
        print(f"  {name:22s} Q {r['Q_min_N'] * 1e-3:7.1f} .. {r['Q_max_N'] * 1e-3:7.1f} kN, rail under it up to "
              f"{r['rail_z_max_m'] * 1e3:.3f} mm")
    on = s1 <= L
    out["rail_end_deflection_m"] = float(z[on][-1])
    print(f"  the rail end's deflection under the wheel as it leaves: {z[on][-1] * 1e3:.3f} mm (the step onto the "
          "rigid rail)")
    return out


if __name__ == "__main__":
    main()
