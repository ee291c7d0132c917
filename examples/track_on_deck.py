"""The deck's response with and without the track layer: Manchester vehicle 1 over the 20 m simply supported span
of examples/scenarios/bridge_20m.toml at 200 km/h,

* as the scenario runs it: rigid rails carried by the deck modes (the deck's mass includes the track's);
* on the flexible ballasted 60E1 track (exudyn_wheelrail/track/flexible_deck.py): rails on pads, sleepers and
  ballast, the ballast on the deck over the span and on the ground before and after it, one set of coupled modes
  up to 800 Hz; the deck's own mass per metre is then the scenario's minus the track's (rails and sleepers), so the
  two models carry the same mass.

Run:  python examples/track_on_deck.py [--duration 0.8] [--dt 0.00025]
Prints the largest mid-span deflection of the deck of both runs (explicit RK44).
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import exudyn as exu
import numpy as np

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.multibody import add_wheel_rail_contact
from exudyn_wheelrail.rolling_stock.placement import place_on_rails
from exudyn_wheelrail.track.rigid import RigidStraightTrack
from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle_with_overrides
from exudyn_wheelrail.scenarios.run import run_scenario
from exudyn_wheelrail.scenarios.spec import load_scenario
from exudyn_wheelrail.simulation.recorder import Recorder
from exudyn_wheelrail.simulation.runner import run
from exudyn_wheelrail.simulation.settings import RunSettings
from exudyn_wheelrail.structures import BridgeModel, DeckSection
from exudyn_wheelrail.track import TrackParameters, add_flexible_track
from exudyn_wheelrail.track.flexible_segment import segment_for_run
from exudyn_wheelrail.track.flexible_deck import TrackOnDeckModel
from exudyn_wheelrail.scenarios.flexible_track import start_on_flexible_track
from exudyn_wheelrail.simulation.solvers import RK44
from exudyn_wheelrail.track.flexible_contact import CONTACT_STIFFNESS_N_M, contact_mode_Hz
from exudyn_wheelrail.simulation.exudyn_settings import run_solver_settings

SCENARIO = Path(__file__).resolve().parent / "scenarios" / "bridge_20m.toml"
#: ASSUMPTION: the ballast's bottom (the deck slab's top) above the deck's beam axis [m] — the scenario's rail height
#: 1.45 m minus rail, pad, sleeper and ballast under the sleeper (~0.65 m)
BALLAST_HEIGHT_M = 0.80


class _DeckMid:
    """Recorder probe: the deck's mid-span deflection (+ down) from the coupled modal coordinates."""

    columns = [("deck", "deck_mid_m")]

    def __init__(self, handle, s_mid):
        self.h, self.s_mid = handle, s_mid

    def fill(self, mbs, t, out):
        q, _ = self.h.coordinates(mbs)
        out[0] = self.h.modes.deck_displacement(self.s_mid, q)[0, 1]


def flexible_run(scn: dict, duration_s: float, dt_s: float) -> dict:
    st, veh = scn["structure"], scn["vehicle"]
    params = TrackParameters.from_file()
    m_track = 2.0 * params.rail_mass_kg_m + params.sleeper_mass_kg / params.sleeper_spacing_m
    section = dict(st["section"], m_kg_m=st["section"]["m_kg_m"] - m_track)
    deck = BridgeModel(tuple(st["spans_m"]), DeckSection(**section), continuous=st["continuous"],
                       damping_ratio=st["damping_ratio"], rail_height_m=st["rail_height_m"], start_m=st["start_m"],
                       elements_per_span=st["elements_per_span"])
    vehicle = load_vehicle_with_overrides(veh["name"])
    V = veh["speed_km_h"] / 3.6
    x = np.asarray(vehicle.wheelset_x_m())
    s_start = veh["start_s_m"] - x.max()
    seg = segment_for_run(s_start + x.min(), s_start + V * duration_s + x.max(), params)
    t0 = time.perf_counter()
    modes = TrackOnDeckModel(params, *seg, deck, BALLAST_HEIGHT_M).modes()
    f_c = contact_mode_Hz(modes, s_start + x.min(), s_start + V * duration_s + x.max())
    if 2.0 * np.pi * f_c * dt_s >= RK44.imaginary_axis_limit:
        raise SystemExit(f"--dt {dt_s}: RK44 is unstable for the wheel on the rail ({f_c:.0f} Hz at "
                         f"{CONTACT_STIFFNESS_N_M:.0e} N/m); use --dt <= {RK44.imaginary_axis_limit / (2 * np.pi * f_c):.2g}")
    print(f"  {modes}  [{time.perf_counter() - t0:.1f} s]")
    geo = vehicle.geometry
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    model = build_vehicle(mbs, vehicle, speed_m_s=V, s_start_m=s_start, wheel_rail="none")
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m, inclination=geo.rail_inclination_tan,
                         back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    handle = add_flexible_track(mbs, modes)
    contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V, track=RigidStraightTrack(),
                                     s_start_m=s_start, creep_law=scn["contact"]["creep_law"],
                                     mu=scn["contact"]["friction"], fastsim_grid=tuple(scn["contact"]["fastsim_grid"]),
                                     structure=handle)
    place_on_rails(mbs, model, pair)
    start_on_flexible_track(mbs, model, handle, contact=contact)
    s_mid = st["start_m"] + 0.5 * st["spans_m"][0]
    rec = Recorder([_DeckMid(handle, s_mid)], n_rows_hint=int(duration_s / dt_s) + 2)
    mbs.Assemble()
    settings = RunSettings(solver="rk44", dt_s=dt_s, duration_s=duration_s)
    sim, solver_type = run_solver_settings(settings)
    sim.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    t0 = time.perf_counter()
    out = run(mbs, settings, contact, speed_m_s=V, recorder=rec, exu_settings=(sim, solver_type))
    ts = rec.table()
    return {"status": out.status.kind, "solve_s": time.perf_counter() - t0,
            "max_deck_mid_m": float(np.nanmax(ts["deck_mid_m"]))}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=0.8, help="simulated time [s] (0.8 s: the car over the span)")
    ap.add_argument("--dt", type=float, default=2.5e-4, help="RK44 step [s]")
    a = ap.parse_args(argv)
    scn = load_scenario(SCENARIO)
    scn["run"] = dict(scn["run"], duration_s=a.duration, solver="rk44", dt_s=a.dt)
    scn["outputs"] = dict(scn["outputs"], plots=False)
    scn["outputs"]["criteria"] = dict(scn["outputs"]["criteria"], enabled=False)
    print(f"Manchester vehicle 1, 200 km/h, 20 m span, {a.duration} s, RK44 {a.dt * 1e3:g} ms")
    t0 = time.perf_counter()
    rigid = run_scenario(scn)
    w_rigid = max(s["max_mid_span_deflection_m"] for s in rigid.summary["deck"]["spans"])
    print(f"  rigid rails on the deck modes:   max mid-span deflection {w_rigid * 1e3:.3f} mm "
          f"({rigid.summary['status']}, {time.perf_counter() - t0:.1f} s)")
    flex = flexible_run(scn, a.duration, a.dt)
    print(f"  ballasted track on the deck:     max mid-span deflection {flex['max_deck_mid_m'] * 1e3:.3f} mm "
          f"({flex['status']}, solve {flex['solve_s']:.1f} s)")


if __name__ == "__main__":
    main()
