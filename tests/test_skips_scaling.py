"""The connector's skips stay exact as the number of wheelsets grows.

The contact of a wheel depends on its own wheelset's state, the track (and the deck) under it and its own warm start
only; so in one connector spanning 8 vehicles (32 wheelsets) the forces on vehicle k must be those of vehicle k alone
in its own connector, at the same nodes' positions (the same track distances) and the same states, call after
call — bit for bit, whatever each wheel skipped: flange regions reported apart by the separation bound, treads of
lifted wheels, the online search replaced by the geometry table, the deck coupling of wheelsets off the deck.  And
what the large connector skipped (``skipped()``, ``geometry_statistics()``) is the sum of what the vehicles alone
skipped.  The modal forces on a bridge are sums over the wheelsets, so they agree to the rounding of a sum of 32
terms (bound: 2 n ε Σ|Φ(s_k)ᵀ F_rail,k| over the wheelsets, the two summation orders' error bounds).

The states: a sequence of 40 calls, 1 ms apart, at 250 km/h on a rigid straight track with a lateral harmonic
irregularity (17 m wavelength, not a divisor of the 26 m vehicle spacing: each vehicle sees another part of it) —
each wheelset oscillates laterally about its own offset relative to the rails (seeded: from the centre to beyond the
S1002/UIC60 flank at 6.25 mm, both sides) at the height and roll of the rigid two-wheel contact plus a Hertz
approach, one in six lifted 0.3 mm off the rails.
"""
from __future__ import annotations

import exudyn as exu
import numpy as np
import pytest
from exudyn.utilities import RigidBodyInertia
from scipy.spatial.transform import Rotation

from exudyn_wheelrail.analysis.geometry_functions import solve_rigid_contact
from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
from exudyn_wheelrail.contact.layout import RES_S_TRACK
from exudyn_wheelrail.multibody import add_wheel_rail_contact, load_vehicle
from exudyn_wheelrail.track.rigid import Harmonic, RigidStraightTrack
from exudyn_wheelrail.structures import BridgeModel, DeckSection, add_bridge

N_VEHICLES = 8
SPACING_M = 26.0
V_M_S = 250 / 3.6
DT_S = 1e-3
N_CALLS = 40
SKIP_KINDS = ("flange_search_far_from_flange", "tread_search_lifted_off", "contact_search_by_geometry_table",
              "bridge_coupling")
VEHICLE = load_vehicle("manchester_vehicle1")
R0_M = VEHICLE.geometry.r0_m
PAIR = WheelRailPair("S1002", "UIC60", inclination="1/40", r0_m=R0_M)
TRACK = RigidStraightTrack(Harmonic(amplitude_m=2e-3, wavelength_m=17.0, direction="lateral"))
# the 20 m deck of tests/test_bridge_coupling.py under the rear bogie of vehicle 3 and the front bogie of vehicle 4
# (wheelsets 11, 12, 13, 14 on it, the other 28 off it)
SEC = DeckSection(m_kg_m=15e3, EI_y_Nm2=2.0e10, EI_z_Nm2=1.0e11, GJ_Nm2=6e9, EA_N=2e11, Ip_kgm2_m=6e4)
DECK_START_M = -72.0


def _x_nodes() -> np.ndarray:
    """Reference x of every wheelset node, vehicle-major: vehicle k centred at -k * spacing."""
    x = np.asarray(VEHICLE.wheelset_x_m(), dtype=float)
    return np.concatenate([x - k * SPACING_M for k in range(N_VEHICLES)])


def _states() -> list[tuple[np.ndarray, np.ndarray, float]]:
    """``(q, q_t, t)`` of all 32 wheelsets for each call (module docstring)."""
    x = _x_nodes()
    n = len(x)
    rng = np.random.default_rng(7)
    offset = rng.uniform(-7.5e-3, 7.5e-3, n)
    amplitude = rng.uniform(0.0, 1.2e-3, n)
    phase = rng.uniform(0.0, 2 * np.pi, n)
    approach = np.where(np.arange(n) % 6 == 5, -3e-4, 6e-5)       # Hertz approach [m]; < 0: lifted
    # rigid two-wheel contact (height, roll) against the lateral shift relative to the rails
    wc = WheelsetContact(PAIR, 1, global_search=True)
    y_grid = np.linspace(-9e-3, 9e-3, 73)
    rigid = [solve_rigid_contact(wc, y) for y in y_grid]
    z_grid = np.array([r.z_m for r in rigid])
    roll_grid = np.array([r.roll_rad for r in rigid])
    omega = 2 * np.pi * 3.0
    out = []
    for i in range(N_CALLS):
        t = i * DT_S
        s = V_M_S * t + x
        irr = TRACK.rail_offset(s)
        y_rel = offset + amplitude * np.sin(omega * t + phase)
        y_rel_t = amplitude * omega * np.cos(omega * t + phase)
        q = np.zeros(6 * n)
        v = np.zeros(6 * n)
        for j in range(n):
            z = np.interp(y_rel[j], y_grid, z_grid) + approach[j]
            roll = np.interp(y_rel[j], y_grid, roll_grid)
            yaw = np.arctan(irr.dy_ds[j])
            R = (Rotation.from_euler("z", yaw) * Rotation.from_euler("x", roll)
                 * Rotation.from_euler("y", -V_M_S / R0_M * t))
            q[6 * j:6 * j + 3] = (0.0, irr.y_m[j] + y_rel[j], z + R0_M)     # displacement from (x, 0, -r0)
            q[6 * j + 3:6 * j + 6] = R.as_rotvec()
            v[6 * j:6 * j + 3] = (0.0, V_M_S * irr.dy_ds[j] + y_rel_t[j], 0.0)
            v[6 * j + 3:6 * j + 6] = (0.0, -V_M_S / R0_M, 0.0)              # body-frame angular velocity
        out.append((q, v, t))
    return out


def _connector(x_nodes, geometry, modes):
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    nodes = [mbs.CreateRigidBody(inertia=RigidBodyInertia(VEHICLE.wheelset.mass_kg, VEHICLE.wheelset.inertia_kg_m2),
                                 referencePosition=[float(xj), 0.0, -R0_M], returnDict=True,
                                 nodeType=exu.NodeType.RotationRotationVector)["nodeNumber"] for xj in x_nodes]
    bridge = add_bridge(mbs, modes) if modes is not None else None
    c = add_wheel_rail_contact(mbs, nodes, PAIR, speed_m_s=V_M_S, track=TRACK, geometry=geometry,
                               **({"structure": bridge} if bridge is not None else {}))
    return sc, c


@pytest.fixture(scope="module")
def states():
    return _states()


@pytest.fixture(scope="module")
def modes():
    return BridgeModel((20.0,), SEC, damping_ratio=0.01, rail_height_m=1.0,
                       start_m=DECK_START_M).modes(f_max_Hz=60.0)


@pytest.mark.parametrize("case", ["online", "table", "bridge"])
def test_vehicle_in_a_train_gets_the_forces_of_the_vehicle_alone(case, states, modes):
    geometry = "table" if case == "table" else "online"
    modes = modes if case == "bridge" else None
    n_m = modes.n_modes if modes is not None else 0
    x = _x_nodes()
    keep = []
    sc, train = _connector(x, geometry, modes)
    keep.append(sc)
    alone = []
    for k in range(N_VEHICLES):
        sc, c = _connector(x[4 * k:4 * k + 4], geometry, modes)
        keep.append(sc)
        alone.append(c)
    rng = np.random.default_rng(3)
    qm = rng.normal(0.0, 2e-4, n_m)          # a deck state: modal coordinates [m] and rates [m/s]
    vm = rng.normal(0.0, 2e-3, n_m)
    flange_contacts = 0
    for q, v, t in states:
        f = train.forces(np.concatenate([q, qm]), np.concatenate([v, vm]), t).copy()
        res = train.results.copy()
        q_modal = np.zeros(n_m)
        bound = np.zeros(n_m)
        for k, c in enumerate(alone):
            sl = slice(24 * k, 24 * k + 24)
            fk = c.forces(np.concatenate([q[sl], qm]), np.concatenate([v[sl], vm]), t)
            # per wheel the same compiled code on the same inputs (module docstring): bit-equality
            np.testing.assert_array_equal(f[sl], fk[:24], err_msg=f"vehicle {k + 1} at t = {t:g} s")
            np.testing.assert_array_equal(res[8 * k:8 * k + 8], c.results, err_msg=f"vehicle {k + 1} at t = {t:g} s")
            if n_m:
                q_modal += fk[24:]
                s_k = c.results[0::2, 0, RES_S_TRACK]
                for j in range(4):
                    phi = modes.shape_at(np.array([s_k[j]]))[0]                  # (3, n_m): rows y, z, θ
                    bound += np.abs(phi).T @ np.abs(c.rail_forces_N()[j])
            flange_contacts += sum(c.flange_contact(w, side) for w in range(4) for side in ("right", "left"))
        if n_m:
            n = len(x)
            err = np.abs(f[24 * N_VEHICLES:] - q_modal)
            np.testing.assert_array_less(err, 2 * n * np.finfo(float).eps * bound + np.finfo(float).tiny)
    assert flange_contacts > 0                              # the scene has flange contacts ...
    sk_train = train.skipped()
    sk_alone = [c.skipped() for c in alone]
    for kind in SKIP_KINDS:
        total = sk_train[kind]["skipped"]
        if total is None:                                  # bridge coupling without a bridge
            continue
        assert total == sum(s[kind]["skipped"] for s in sk_alone), kind
    assert sk_train["concave_search"]["run"] == sum(s["concave_search"]["run"] for s in sk_alone)
    g = train.geometry_statistics()
    for key in ("wheel_evaluations_table", "wheel_evaluations_online"):
        assert g[key] == sum(c.geometry_statistics()[key] for c in alone), key
    # ... and every skip of this case is exercised
    if geometry == "online":
        assert sk_train["flange_search_far_from_flange"]["skipped"] > 0
        assert sk_train["tread_search_lifted_off"]["skipped"] > 0
    else:
        assert g["wheel_evaluations_table"] == 2 * len(x) * len(states) and g["wheel_evaluations_online"] == 0
    if modes is not None:
        b = sk_train["bridge_coupling"]
        assert 0 < b["skipped"] < b["of_wheelset_evaluations"]   # wheelsets on and off the deck

