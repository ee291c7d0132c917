"""Start a vehicle in static equilibrium on its rails: the axle height at which each wheel carries its static load.

The vertical offset comes from the quasi-static contact of the centred wheelset (rigid touching height plus the
Hertz approach, :func:`~exudyn_wheelrail.analysis.quasi_static.solve_quasi_static` without creep); all bodies of
the vehicle move together, so the suspension preloads of the builder's static load path are unchanged.
Frames: the track/model frame of :mod:`exudyn_wheelrail.conventions` (z down); SI units.
"""
from __future__ import annotations

import math

import numpy as np

from ..analysis.quasi_static import solve_quasi_static
from ..contact.pair import WheelRailPair
from ..contact.wheelset import WheelsetContact
from ..conventions import RAIL_CENTRE_DISTANCE_M
from ..track.irregularities import channel_values

__all__ = ["static_axle_offset_m", "place_on_rails", "start_on_track"]


def static_axle_offset_m(pair: WheelRailPair, wheel_load_N: float, r0_m: float, E_Pa: float = 2.1e11,
                         nu: float = 0.28) -> float:
    """Vertical offset (z down) of the centred wheelset's axle from its nominal height ``-r0`` at which each wheel
    carries ``wheel_load_N`` by its normal force (quasi-static, no creep): the rigid touching height plus the Hertz
    approach.  Used to start a simulation in equilibrium."""
    contact = WheelsetContact(pair, 1, E_Pa, nu, E_Pa, nu, global_search=True)
    res = solve_quasi_static(contact, 0.0, 0.0, wheel_load_N, 1.0, shear_modulus_Pa=E_Pa / (2 * (1 + nu)),
                             poisson=nu, creep_law=lambda *a: (0.0, 0.0, 0.0), pitch_rate_rad_s=-1.0 / r0_m,
                             semi_axis_ratio_range=None)
    if not res.converged:
        raise RuntimeError(f"static wheelset position not found: {res.message}")
    return res.z_m - (-r0_m)


def place_on_rails(mbs, model, pair: WheelRailPair, E_Pa: float = 2.1e11, nu: float = 0.28) -> float:
    """Shift every body of a :class:`~.vehicle_builder.VehicleModel` vertically so the centred wheelsets start in
    static equilibrium on the rails (the suspension preloads are unchanged: all bodies move together).  Call before
    ``mbs.Assemble()``.  Returns the shift [m] (z down)."""
    loads = model.load_path.wheel if model.load_path is not None else None
    if loads is None:
        raise ValueError("the vehicle model has no static load path (build it with preload=True)")
    dz = static_axle_offset_m(pair, float(np.mean(loads)), model.wheelsets[0].r0_m, E_Pa, nu)
    for body in model.bodies:
        q0 = np.array(mbs.GetNodeParameter(body.node, "initialCoordinates"), dtype=float)
        q0[2] += dz
        mbs.SetNodeParameter(body.node, "initialCoordinates", q0.tolist())
    return dz


def start_on_track(mbs, model, track) -> float | None:
    """Put the bodies' initial state on the track under the wheelsets at t = 0 (call after
    :func:`place_on_rails`, which puts the centred vehicle on the *undisplaced* rails).

    Each wheelset moves by the track's lateral and vertical displacement ``(y, z)`` at its track distance and is
    yawed along the track, ``ψ = atan(dy/ds)``; its velocity gets ``(V dy/ds, V dz/ds)`` and its yaw rate
    ``V y''/(1 + y'²)`` — the rates at which the track moves and turns under it in the frame moving with V —, so
    it starts without lateral creepage and without penetration.  Each bogie frame (and the car body) follows the
    straight line through its supports (its wheelsets; the bogie centres): displacement at its centre of mass,
    yaw ``atan(Δy/Δx)`` and pitch ``-atan(Δz/Δx)`` (z down: the nose goes up for θ > 0), with the matching rates
    (rotation vector ``(0, θ, ψ)``, the small-angle composition).  Without it a millimetre of vertical
    irregularity is a millimetre of Hertz penetration at t = 0 (MN contact forces) and a slope dy/ds a lateral
    creepage dy/ds.  A cross level c rolls each wheelset with its rails, ``θ = asin(c/b)`` (b the rail-centre
    distance, :mod:`exudyn_wheelrail.conventions`), at the rate ``V dθ/ds``; the bogie frames and the car body stay
    level (the suspension takes the small roll difference).  Returns the largest displacement [m], or None when the
    track under every wheelset is undisplaced and parallel to the frame (nothing is changed)."""
    x = np.array([ws.p_cg_in_frame[0] for ws in model.wheelsets])
    s0 = model.track_distance_m(x, 0.0)
    v = track.rail_offset(s0)
    cl = channel_values(track.irregularity, s0)
    roll = np.arcsin(cl.cross_level_m / RAIL_CENTRE_DISTANCE_M)
    roll_rate = model.speed_m_s * cl.d_cross_level / (RAIL_CENTRE_DISTANCE_M * np.cos(roll))
    if not (np.any(v.y_m) or np.any(v.z_m) or np.any(v.dy_ds) or np.any(v.dz_ds) or np.any(roll)
            or np.any(roll_rate)):
        return None
    V = model.speed_m_s
    # per body: x, (y, z, pitch θ, yaw ψ) and their rates
    ws = [(x[j], np.array([v.y_m[j], v.z_m[j], 0.0, math.atan(v.dy_ds[j])]),
           V * np.array([v.dy_ds[j], v.dz_ds[j], 0.0, v.d2y_ds2[j] / (1.0 + v.dy_ds[j] ** 2)]))
          for j in range(len(x))]

    def on_line(supports, x_cg):
        """State of a body resting on the line through its supports (front and rear: largest and smallest x)."""
        f = max(supports, key=lambda b: b[0])
        r = min(supports, key=lambda b: b[0])
        dx = f[0] - r[0]
        lam = (x_cg - r[0]) / dx
        pos = r[1] + lam * (f[1] - r[1])
        rate = r[2] + lam * (f[2] - r[2])
        dy, dz = f[1][0] - r[1][0], f[1][1] - r[1][1]
        pos[2] = -math.atan(dz / dx)
        pos[3] = math.atan(dy / dx)
        rate[2] = -(f[2][1] - r[2][1]) / dx / (1.0 + (dz / dx) ** 2)
        rate[3] = (f[2][0] - r[2][0]) / dx / (1.0 + (dy / dx) ** 2)
        return x_cg, pos, rate

    def shift(node, state):
        _, pos, rate = state
        q0 = np.array(mbs.GetNodeParameter(node, "initialCoordinates"), dtype=float)
        v0 = np.array(mbs.GetNodeParameter(node, "initialVelocities"), dtype=float)
        q0[1:3] += pos[:2]
        q0[4:6] += pos[2:]              # rotation vector (0, θ, ψ); the reference rotation is zero
        v0[1:3] += rate[:2]
        v0[4:6] += rate[2:]             # body-frame angular velocity (= track frame for these small rotations)
        mbs.SetNodeParameter(node, "initialCoordinates", q0.tolist())
        mbs.SetNodeParameter(node, "initialVelocities", v0.tolist())

    for j, w in enumerate(model.wheelsets):
        shift(w.node, ws[j])
        if roll[j] != 0.0 or roll_rate[j] != 0.0:
            # rolled with the rails about their centre line: the axle centre at R_x(θ) of its height d above it
            q0 = np.array(mbs.GetNodeParameter(w.node, "initialCoordinates"), dtype=float)
            v0 = np.array(mbs.GetNodeParameter(w.node, "initialVelocities"), dtype=float)
            d = w.p_cg_in_frame[2] + q0[2] - v.z_m[j]
            sn, cs = math.sin(roll[j]), math.cos(roll[j])
            q0[1] -= d * sn
            q0[2] += d * (cs - 1.0)
            q0[3] += roll[j]
            v0[1] -= d * cs * roll_rate[j]
            v0[2] -= d * sn * roll_rate[j]
            v0[3] += roll_rate[j]
            mbs.SetNodeParameter(w.node, "initialCoordinates", q0.tolist())
            mbs.SetNodeParameter(w.node, "initialVelocities", v0.tolist())
    bogies = []
    for i, b in enumerate(model.bogies):
        bogies.append(on_line([ws[j] for j, w in enumerate(model.wheelsets) if w.bogie == i], b.p_cg_in_frame[0]))
        shift(b.node, bogies[-1])
    if model.car_body is not None:
        shift(model.car_body.node, on_line(bogies, model.car_body.p_cg_in_frame[0]))
    return float(max(np.max(np.abs(v.y_m)), np.max(np.abs(v.z_m))))
