"""Add the wheel–rail contact to your own Exudyn model (no builders of this package).

A single wheelset (a rigid body with a Lie-group node), loaded by dead weights on its axle boxes and held by
lateral/longitudinal springs to a frame that moves with the running speed, starts 3 mm off centre and runs on
S1002/UIC60 1:40 rails.  The contact is one call: ``add_wheel_rail_contact(mbs, [node], pair, speed_m_s=V)``.

Run:  python examples/own_exudyn_model.py [--speed-kmh 100] [--time 2.0] [--creep-law fastsim] [--plot out.png]
Prints the lateral displacement every 0.1 s and the wheel loads at the end (the wheelset has no vertical suspension
in this sketch, so it keeps bouncing on the contact stiffness: the loads oscillate about the weight).
"""
from __future__ import annotations

import argparse

import exudyn as exu
import numpy as np
from exudyn.itemInterface import LoadForceVector, MarkerBodyPosition, ObjectConnectorCartesianSpringDamper
from exudyn.utilities import RigidBodyInertia

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.multibody import add_wheel_rail_contact, static_axle_offset_m
from exudyn_wheelrail.multibody.connector import RES_F_TRACK_Z


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--speed-kmh", type=float, default=100.0)
    ap.add_argument("--time", type=float, default=2.0, help="simulated time [s]")
    ap.add_argument("--dt", type=float, default=5e-4)
    ap.add_argument("--creep-law", default="fastsim")
    ap.add_argument("--plot", default=None, help="PNG of the lateral displacement")
    args = ap.parse_args(argv)

    V = args.speed_kmh / 3.6
    r0, mass, load_per_box = 0.46, 1813.0, 45e3            # wheelset mass [kg], dead load per axle box [N]
    pair = WheelRailPair("S1002", "UIC60", inclination="1/40", r0_m=r0)
    wheel_load = load_per_box + mass * 9.81 / 2
    dz = static_axle_offset_m(pair, wheel_load, r0)       # axle height at which each wheel carries its load

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    ground = mbs.CreateGround()
    # the track frame: x forward, y right, z down (gravity +z); the model frame moves with V (rails at -V)
    ws = mbs.CreateRigidBody(inertia=RigidBodyInertia(mass, np.diag([1120.0, 112.0, 1120.0])),
                             referencePosition=[0.0, 0.0, -r0], initialDisplacement=[0.0, 0.003, dz],
                             initialAngularVelocity=[0.0, -V / r0, 0.0], gravity=[0.0, 0.0, 9.81],
                             nodeType=exu.NodeType.RotationRotationVector, returnDict=True)
    for side in (-1.0, 1.0):
        box = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ws["bodyNumber"], localPosition=[0.0, side, 0.0]))
        fixed = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[0.0, side, -r0]))
        mbs.AddLoad(LoadForceVector(markerNumber=box, loadVector=[0.0, 0.0, load_per_box]))
        mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[fixed, box],
                                                           stiffness=[31.4e6, 3.9e6, 0.0],
                                                           damping=[15e3, 2e3, 0.0]))
    contact = add_wheel_rail_contact(mbs, [ws["nodeNumber"]], pair, speed_m_s=V, creep_law=args.creep_law)

    history = []

    def record(mbs, t):
        r = contact.evaluate(mbs, t)
        history.append((t, mbs.GetNodeOutput(ws["nodeNumber"], exu.OutputVariableType.Position)[1],
                        -r[:, :, RES_F_TRACK_Z].sum()))
        return True

    mbs.SetPreStepUserFunction(record)
    mbs.Assemble()
    sim = exu.SimulationSettings()
    sim.solution.file.write = False
    sim.timeIntegration.verboseMode = 0
    sim.timeIntegration.endTime = args.time
    sim.timeIntegration.numberOfSteps = int(round(args.time / args.dt))
    sim.timeIntegration.explicit.useLieGroupIntegration = True
    sim.timeIntegration.explicit.computeEndOfStepAccelerations = False
    mbs.SolveDynamic(sim, solverType=exu.DynamicSolverType.RK44)

    t, y, q_sum = np.array(history).T
    for tk in np.arange(0.0, args.time + 1e-9, 0.1):
        i = min(int(np.searchsorted(t, tk)), len(t) - 1)
        print(f"t = {t[i]:5.2f} s   lateral displacement {y[i] * 1e3:+7.3f} mm")
    contact.evaluate(mbs, args.time)
    for side in ("right", "left"):
        F = contact.wheel_force_N(0, side)
        print(f"{side:5s} wheel: Q = {-F[2] / 1e3:7.2f} kN, Y = {F[1] / 1e3:+6.2f} kN "
              f"(expected Q = {wheel_load / 1e3:.2f} kN when centred)")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 3))
        ax.plot(t, y * 1e3)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("lateral displacement [mm]")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
    return t, y, q_sum, contact


if __name__ == "__main__":
    main()
