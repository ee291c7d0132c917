"""Small Exudyn models for the stress tests: one wheelset (or one bogie) of Manchester vehicle 1 with the project's
wheel–rail contact, the run monitor, optional lateral/vertical loads on the wheelset, run under a wall-clock limit."""
from __future__ import annotations

import signal
import tomllib
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import exudyn as exu
import numpy as np
from exudyn.itemInterface import LoadForceVector, LoadTorqueVector, MarkerNodeRigid

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.multibody import RigidStraightTrack, build_vehicle, vehicle_from_dict
from exudyn_wheelrail.simulation.exudyn_settings import simulation_settings
from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.simulation.monitor import RunMonitor
from exudyn_wheelrail.simulation.runner import run_monitored

VEHICLES = Path(__file__).resolve().parents[2] / "vehicles"
PAIR = WheelRailPair("S1002", "UIC60", inclination="1/40")
#: static wheel load of the single-wheelset model (vehicles/single_wheelset.toml) [N]
WHEEL_LOAD_N = 45653.29 + 1813.0 * 9.81 / 2


def vehicle_data(name: str, **changes):
    """A shipped vehicle file with some sections updated: ``primary={"ky_N_per_m": 0.0}``."""
    d = tomllib.loads((VEHICLES / f"{name}.toml").read_text())
    for section, values in changes.items():
        d[section].update(values)
    return vehicle_from_dict(d)


@dataclass
class Model:
    sc: object
    mbs: object
    model: object
    contact: object
    monitor: RunMonitor
    dz: float


def build(speed_m_s: float, *, vehicle="single_wheelset", irregularity=None, lateral_force=None, creep_law="table",
          y0_m: float = 0.0, monitor_options=None, bump_stop="none", force_height_m: float = 0.0) -> Model:
    """Model on a rigid straight track (``irregularity``), in static equilibrium, leading wheelset displaced by
    ``y0_m``; ``lateral_force(t) -> N`` (track y) applied to the first wheelset, its line of action
    ``force_height_m`` below the axle centre (r0: at rail level — a force at the axle plus the moment about x)."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    data = vehicle if not isinstance(vehicle, str) else None
    model = build_vehicle(mbs, data or vehicle, speed_m_s=speed_m_s, bump_stop=bump_stop)
    dz = C.place_on_rails(mbs, model, PAIR)
    ws = model.wheelsets[0]
    if y0_m:
        q0 = np.array(mbs.GetNodeParameter(ws.node, "initialCoordinates"))
        q0[1] += y0_m
        mbs.SetNodeParameter(ws.node, "initialCoordinates", q0.tolist())
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, PAIR, speed_m_s=speed_m_s,
                                       track=RigidStraightTrack(irregularity), creep_law=creep_law)
    if lateral_force is not None:
        marker = mbs.AddMarker(MarkerNodeRigid(nodeNumber=ws.node))
        mbs.AddLoad(LoadForceVector(markerNumber=marker, loadVector=[0.0, 0.0, 0.0],
                                    loadVectorUserFunction=lambda mbs, t, v: [0.0, float(lateral_force(t)), 0.0]))
        if force_height_m:
            # moment of the force about the centre, (0, 0, h) x (0, F, 0) = (-h F, 0, 0), global frame
            mbs.AddLoad(LoadTorqueVector(markerNumber=marker, loadVector=[0.0, 0.0, 0.0], bodyFixed=False,
                                         loadVectorUserFunction=lambda mbs, t, v: [
                                             -force_height_m * float(lateral_force(t)), 0.0, 0.0]))
    monitor = RunMonitor(contact, **(monitor_options or {}))
    mbs.Assemble()
    contact.warm_up(mbs, jacobian=False)
    return Model(sc, mbs, model, contact, monitor, dz)


def settings(end_time_s: float, dt_s: float):
    s = simulation_settings(end_time_s, dt_s)
    s.timeIntegration.explicit.computeEndOfStepAccelerations = False
    return s


class HardTimeLimit(Exception):
    pass


@contextmanager
def hard_time_limit(seconds: float):
    """Raise :class:`HardTimeLimit` in the main thread after ``seconds`` (SIGALRM; reaches Python code at the next
    user-function call) — a hang guard around a solve, besides the monitor's own wall-clock limit."""
    def handler(signum, frame):
        raise HardTimeLimit(f"hard time limit of {seconds} s exceeded")
    old = signal.signal(signal.SIGALRM, handler)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old)


def run(m: Model, end_time_s: float, dt_s: float, solver="rk44", hard_limit_s: float = 120.0):
    with hard_time_limit(hard_limit_s):
        return run_monitored(m.mbs, settings(end_time_s, dt_s), solver, m.monitor)


def finite_history(monitor: RunMonitor) -> bool:
    h = monitor.history()
    keys = ("lateral_m", "vertical_m", "roll_rad", "normal_force_N", "lateral_force_N", "penetration_m")
    return all(np.all(np.isfinite(h[k])) for k in keys)
