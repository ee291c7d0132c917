"""Exact force and torque balance of the wheel–rail connector about the wheelset centre, spin moments included.

The connector's generalized forces of a wheelset are the resultant force (track frame) and the resultant torque
about the wheelset centre c (body frame).  Rebuilt here from the per-contact results (``RES_*`` of
``multibody.connector``: the total contact force F on the wheel and the contact point p in the track frame, the spin
moment Mz about the contact normal) and the contact normal itself, reconstructed from the contact angle γ by the
convention of ``exudyn_wheelrail.conventions`` (outward rail normal ``n_r = (-sin γ, -cos γ)`` in the side frame
(y, z); the contact frame's ``z_c = -n_r`` from the wheel into the rail, i.e. ``n = (0, ±sin γ, cos γ)`` in the track
frame, + on the right wheel, - on the left), every contact of the wheelset summed::

    F_total = Σ F,        τ = Σ [(p - c) × F + Mz n]      (track frame),  f[3:6] = Rᵀ τ  (body frame).

Both sides are the same sum of the same numbers, so they agree to round-off; the spin-moment term is made orders
of magnitude larger than that round-off in every pose (spin creepage from the contact angle, the yaw rate and the
roll rate), largest on the flange (contact angle ~70°).  The rotation R of the node's rotation vector comes from
``scipy.spatial.transform.Rotation`` (independent of the connector's Rodrigues formula).
"""
import math

import exudyn as exu
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.multibody import build_vehicle
from exudyn_wheelrail.multibody import connector as C

V = 30.0                        # running speed [m/s] (moving frame: rail material velocity (-V, 0, 0))
R0 = 0.46                       # nominal rolling radius of the single_wheelset model [m]
WHEEL_LOAD_N = 60e3             # vertical load of each wheel in every pose (height and roll found by bisection)
HALF_BASE = 0.75                # lever of the roll angle at the wheels [m] (only for the load search)
EPS = np.finfo(float).eps

# poses: lateral shift y [m] and yaw [rad] (height and roll follow from the wheel loads); velocity coordinates:
# lateral velocity [m/s], body-frame roll and yaw rates [rad/s] on top of rolling (ω_y = -V/R0)
POSES = {
    "centred_yaw_rate": dict(y=0.0, yaw=2e-3, vy=0.05, roll_rate=0.0, yaw_rate=0.4),
    "shift_yaw_roll_rate": dict(y=3e-3, yaw=-3e-3, vy=-0.1, roll_rate=0.05, yaw_rate=-0.3),
    "left_shift": dict(y=-4e-3, yaw=4e-3, vy=0.02, roll_rate=-0.03, yaw_rate=0.2),
    # the right flange in contact (the flange touches at y ≈ 6.3 mm; contact angle 70°)
    "flange_right": dict(y=6.5e-3, yaw=5e-3, vy=0.05, roll_rate=0.0, yaw_rate=0.1),
}


@pytest.fixture(scope="module", params=["table", "fastsim"])
def contact(request):
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=V)
    pair = WheelRailPair("S1002", "UIC60", inclination="1/40")
    return C.add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V, creep_law=request.param,
                                    global_search=True)


def _coordinates(pose, z_right, z_left):
    """Node coordinates and velocities of the pose with the wheels at heights z_right, z_left (down) [m]: centre
    height their mean, roll (+x, lowers the right wheel) their difference over 2 HALF_BASE; the rotation vector of
    R = R_z(yaw) R_x(roll) R_y(0.7) (0.7 rad of spin angle: a general orientation)."""
    z = 0.5 * (z_right + z_left)
    roll = (z_right - z_left) / (2 * HALF_BASE)
    rotvec = Rotation.from_euler("ZXY", [pose["yaw"], roll, 0.7]).as_rotvec()
    q = np.array([0.0, pose["y"], z, *rotvec])
    v = np.array([0.02, pose["vy"], 0.0, pose["roll_rate"], -V / R0, pose["yaw_rate"]])
    return q, v


def _wheel_loads(contact, q, v):
    contact.forces(q, v, 0.0)
    return -contact.results[:, :, C.RES_F_TRACK_Z].sum(axis=1)          # (right, left) [N]


def _pose(contact, name):
    """(q, v) of the pose with each wheel carrying WHEEL_LOAD_N: alternating bisections on the heights of the
    right and the left wheel (each wheel's load grows with its own height; the coupling through the roll is weak)."""
    pose = POSES[name]
    z = [0.0, 0.0]
    for _ in range(4):
        for side in (0, 1):
            lo, hi = -6e-3, 6e-3
            for _ in range(45):
                z[side] = 0.5 * (lo + hi)
                if _wheel_loads(contact, *_coordinates(pose, *z))[side] > WHEEL_LOAD_N:
                    hi = z[side]
                else:
                    lo = z[side]
            z[side] = hi
    q, v = _coordinates(pose, *z)
    np.testing.assert_allclose(_wheel_loads(contact, q, v), WHEEL_LOAD_N, rtol=1e-2)      # the pose is found
    return q, v


def _balance(contact, q, v):
    """Generalized forces of the connector and the independent sums over the contacts (track frame)."""
    f = contact.forces(q, v, 0.0).copy()
    res = contact.results
    c = contact.p_ref[0] + q[:3]
    F_sum = np.zeros(3)
    tau_forces = np.zeros(3)
    tau_spin = np.zeros(3)
    scale = 0.0                      # Σ |p - c| |F| + |Mz|: the size of the terms summed (round-off scale)
    n_contacts = 0
    for w in range(res.shape[0]):
        side = 1.0 if w % 2 == 0 else -1.0            # wheels 2k right, 2k+1 left
        for slot in range(res.shape[1]):
            r = res[w, slot]
            if r[C.RES_STATUS] <= 0:
                continue
            n_contacts += 1
            F = r[C.RES_F_TRACK_X:C.RES_F_TRACK_Z + 1]
            p = r[C.RES_P_X:C.RES_P_Z + 1]
            g = r[C.RES_GAMMA]
            n = np.array([0.0, side * math.sin(g), math.cos(g)])
            # the reconstructed normal is the contact frame's: F = N n_r + tangential, so F·n = -N exactly
            assert abs(F @ n + r[C.RES_N]) <= 1e-12 * np.linalg.norm(F), (w, slot)
            F_sum += F
            tau_forces += np.cross(p - c, F)
            tau_spin += r[C.RES_MZ] * n
            scale += np.linalg.norm(p - c) * np.linalg.norm(F) + abs(r[C.RES_MZ])
    R = Rotation.from_rotvec(q[3:6]).as_matrix()
    return f, R, F_sum, tau_forces, tau_spin, scale, n_contacts


# round-off: each term is a product of two numbers; the sums, the cross products and the two rotations (Rᵀ in the
# connector, R here) add a few ε of the largest term each: 64 ε of Σ|terms| bounds it with a wide margin
ROUND_OFF = 64 * EPS


@pytest.mark.parametrize("name", list(POSES))
def test_torque_about_centre_is_moment_of_contact_forces_plus_spin_moments(contact, name):
    q, v = _pose(contact, name)
    f, R, F_sum, tau_forces, tau_spin, scale, n_contacts = _balance(contact, q, v)
    assert n_contacts >= 1
    res = contact.results
    active = res[:, :, C.RES_STATUS] > 0
    assert np.all(np.abs(res[:, :, C.RES_PHI][active]) > 1e-3)          # spin creepage in every contact [1/m]
    tol = ROUND_OFF * scale
    np.testing.assert_allclose(f[:3], F_sum, rtol=0, atol=tol)
    tau = R @ f[3:6]                                                       # body frame -> track frame
    err = np.linalg.norm(tau - (tau_forces + tau_spin))
    assert err <= tol, (name, err, tol)
    # the spin moments are resolved: their resultant is far above the round-off of the balance
    assert np.linalg.norm(tau_spin) > 1e4 * tol, (name, np.linalg.norm(tau_spin), tol)


def test_flange_contact_spin_moment_is_large(contact):
    """Flange contact (contact angle > 1 rad): large spin creepage φ = ω·n/V ≈ -Ω sin γ / V and a spin moment whose
    share of the torque exceeds the round-off by many orders of magnitude."""
    q, v = _pose(contact, "flange_right")
    f, R, F_sum, tau_forces, tau_spin, scale, _ = _balance(contact, q, v)
    res = contact.results
    right = res[0]
    flange = (right[:, C.RES_STATUS] > 0) & (right[:, C.RES_GAMMA] > 1.0)
    assert flange.any(), right[:, C.RES_GAMMA]
    # spin creepage of a rolling coned contact: |φ| ≈ sin γ / R0 (> 1.8 1/m at γ > 1 rad)
    assert np.all(np.abs(right[flange, C.RES_PHI]) > 0.8 * math.sin(1.0) / R0)
    tol = ROUND_OFF * scale
    assert np.linalg.norm(tau_spin) > 1e6 * tol
    assert np.linalg.norm(R @ f[3:6] - (tau_forces + tau_spin)) <= tol
