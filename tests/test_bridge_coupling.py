"""Wheel–rail connector on a flexible bridge (``add_wheel_rail_contact(..., structure=...)``).

References (independent of the coupling code):
* static mid-span deflection of a simply supported Euler–Bernoulli span under a central point force
  ``P L³/(48 EI)``, with P the weight of wheelset + dead load (and equilibrium of the modal equations
  ``ω² q = Q``);
* Frýba's moving-force solution (``fryba_moving_force``: the closed-form modal series of the simply supported beam,
  Frýba 1999 Ch. 1) for a light wheelset crossing the span;
* action = reaction: the modal forces are the projection ``Σ Φ(s)^T (Fy, Fz, Mx)`` of minus the contact forces on
  the wheels (rebuilt from the recorded forces and contact points by the bridge module's own Python projection);
* invariance: moving deck and wheelset together rigidly (translation and roll about the rails' centre line, with
  velocities) leaves the contact forces unchanged up to that rotation;
* column-by-column finite differences of the force function for the structured Jacobian.

Creep law: FASTSIM (the packaged creep table is not needed here).
"""
from __future__ import annotations

import math
import tomllib
from pathlib import Path

import exudyn as exu
import numpy as np
import pytest

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.multibody import build_vehicle, vehicle_from_dict
from exudyn_wheelrail.simulation.exudyn_settings import simulation_settings
from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.track.rigid import Harmonic, RigidStraightTrack
from exudyn_wheelrail.structures import BridgeModel, DeckSection, add_bridge, fryba_moving_force
from exudyn_wheelrail.validation import InputWarning

VEHICLES = Path(__file__).resolve().parents[1] / "vehicles"
G_M_S2 = 9.81
# the 20 m deck of tests/test_bridge.py: f1 (vertical) 4.53 Hz, lateral 10.1 Hz, torsion 7.91 Hz
SEC = DeckSection(m_kg_m=15e3, EI_y_Nm2=2.0e10, EI_z_Nm2=1.0e11, GJ_Nm2=6e9, EA_N=2e11, Ip_kgm2_m=6e4)
L = 20.0
DEAD_LOAD_PER_SIDE_N = 45653.29          # vehicles/single_wheelset.toml
CREEP = dict(creep_law="fastsim", fastsim_grid=(16, 8))


def _pair():
    return WheelRailPair("S1002", "UIC60", inclination="1/40")


def _wheelset_data(mass_kg=None):
    """The single wheelset under its dead load; ``mass_kg`` scales mass and inertia (a lighter wheelset)."""
    d = tomllib.loads((VEHICLES / "single_wheelset.toml").read_text())
    if mass_kg is not None:
        f = mass_kg / d["wheelset"]["mass_kg"]
        for k in ("mass_kg", "Ixx_kg_m2", "Iyy_kg_m2", "Izz_kg_m2"):
            d["wheelset"][k] *= f
    return vehicle_from_dict(d)


def _modes(damping_ratio, f_max_Hz=150.0, start_m=0.0, spans=(L,)):
    return BridgeModel(spans, SEC, damping_ratio=damping_ratio, rail_height_m=1.0,
                       start_m=start_m).modes(f_max_Hz=f_max_Hz)


def _wheelset_on_bridge(modes, *, speed, s_start, mass_kg=None, track=None):
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, _wheelset_data(mass_kg), speed_m_s=speed, s_start_m=s_start)
    pair = _pair()
    C.place_on_rails(mbs, model, pair)
    bridge = add_bridge(mbs, modes) if modes is not None else None
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=speed, s_start_m=s_start,
                                       structure=bridge, track=track, **CREEP)
    sensor = bridge.add_sensor(mbs) if bridge is not None else None
    return SC, mbs, model, bridge, contact, sensor


def _solve(mbs, contact, T, h, spectral_radius=1.0):
    mbs.Assemble()
    contact.warm_up(mbs)
    ss = simulation_settings(T, h, spectral_radius=spectral_radius)
    ss.timeIntegration.newton.useModifiedNewton = True
    assert mbs.SolveDynamic(ss)


# ---------------------------------------------------------------------------------------------- (a) static
def test_wheelset_standing_at_mid_span_deflects_the_deck_by_PL3_over_48EI():
    """A wheelset creeping at 0.1 m/s over mid-span of a heavily damped deck (ζ = 0.7, settled after 1 s): the
    mid-span deflection is P L³/(48 EI) (P = dead load + wheelset weight), the wheel loads are those of the rigid
    track (P/2 each), the deck is in modal equilibrium ω² q = Q and the recorded deck displacement under the wheel
    is the deck's deflection there."""
    modes = _modes(damping_ratio=0.7)
    V, T = 0.1, 1.0
    SC, mbs, model, bridge, contact, sensor = _wheelset_on_bridge(modes, speed=V, s_start=L / 2 - 0.5 * V * T)
    _solve(mbs, contact, T, 1e-3, spectral_radius=0.8)
    res = contact.evaluate(mbs, T)
    q, _ = bridge.coordinates(mbs)
    P = 2 * DEAD_LOAD_PER_SIDE_N + model.wheelsets[0].mass_kg * G_M_S2
    w_mid = float(modes.shape_at(L / 2)[1] @ q)
    assert w_mid == pytest.approx(P * L ** 3 / (48 * SEC.EI_y_Nm2), rel=0.01)
    # the wheel loads are unchanged by the flexible deck
    Q = np.array([-contact.wheel_force_N(0, s)[2] for s in ("right", "left")])
    np.testing.assert_allclose(Q, P / 2, rtol=1e-3)
    # equilibrium of the modal equations: elastic forces = generalized contact forces
    Qm = contact.modal_forces_N()
    np.testing.assert_allclose(modes.omega_rad_s ** 2 * q, Qm, atol=1e-3 * np.abs(Qm).max())
    s_w = res[0, 0, C.RES_S_TRACK]
    assert abs(s_w - L / 2) < 0.06 and res[0, 0, C.RES_ON_DECK] == 1.0  # a 0/1 flag: exact
    assert res[0, 0, C.RES_DECK_Z] == pytest.approx(float(modes.shape_at(s_w)[1] @ q), rel=1e-12)
    assert abs(res[0, 0, C.RES_DECK_Y]) < 1e-9 and abs(res[0, 0, C.RES_DECK_ROLL]) < 1e-9   # symmetric load


# --------------------------------------------------------------------------------------- (b) moving force
def _crossing(mass_kg, speed=40.0, zeta=0.01, h=1e-3):
    modes = _modes(damping_ratio=zeta)
    s0 = -1.0                                   # the wheelset starts 1 m before the deck
    T = (L - s0) / speed + 0.3                  # across the span and 0.3 s of free vibration
    SC, mbs, model, bridge, contact, sensor = _wheelset_on_bridge(modes, speed=speed, s_start=s0, mass_kg=mass_kg)
    _solve(mbs, contact, T, h)
    d = mbs.GetSensorStoredData(sensor)
    t = d[:, 0]
    w = d[:, 1:] @ modes.shape_at(L / 2)[1]
    P = 2 * DEAD_LOAD_PER_SIDE_N + model.wheelsets[0].mass_kg * G_M_S2
    ref = fryba_moving_force(L / 2, t + s0 / speed, force_N=P, speed_m_s=speed, span_m=L, EI_Nm2=SEC.EI_y_Nm2,
                             m_kg_m=SEC.m_kg_m, damping_ratio=zeta, n_terms=60)
    return np.max(np.abs(w - ref)) / np.max(np.abs(ref)), t, w, ref


def test_light_wheelset_crossing_approaches_the_moving_force_solution():
    """A wheelset under a dead load crossing the 20 m span at 40 m/s (α = v/(2 f1 L) = 0.22, ζ = 1 %): the mid-span
    deflection history (on the span and 0.3 s of free vibration after it) against Frýba's moving force of the same
    weight.  A 200 kg wheelset is within 0.3 % of the peak (measured 0.14 %: 0.07 % of it is the modal truncation at
    150 Hz, the rest the wheelset's inertia); the real 1813 kg wheelset within 1.5 % (measured 0.8 %).  The
    residual is the wheelset's inertia: a mass m_w on the span lowers the loaded first frequency by about
    m_w φ1(x)²/2 = m_w/(m L) (0.6 % at mid-span for 1813 kg) and so shifts the phase of the free vibration the
    crossing excites; it grows in proportion to m_w (9x the mass, 5–13x the residual beyond the truncation).
    The contact stiffness does not show (its static compression is constant; the Hertz bounce is far above f1)."""
    with pytest.warns(InputWarning, match="unusual wheelset mass"):   # deliberately light: the warning says so
        err_light, t, w, ref = _crossing(200.0)
    err_heavy, *_ = _crossing(1813.0)
    truncation = 7e-4                           # modal model vs Frýba (tests/test_bridge.py, 150 Hz)
    assert err_light < 3e-3
    assert err_heavy < 1.5e-2
    assert 5.0 < (err_heavy - truncation) / max(err_light - truncation, 1e-12) < 13.0
    # the crossing is dynamic: the peak exceeds the static central deflection and the span vibrates afterwards
    P = 2 * DEAD_LOAD_PER_SIDE_N + 200.0 * G_M_S2
    assert np.max(w) > 1.05 * P * L ** 3 / (48 * SEC.EI_y_Nm2)
    assert np.min(w[t > 21.0 / 40.0]) < -0.2 * np.max(w)


# ----------------------------------------------------------------------------------------- (c) bookkeeping
def _vehicle_on_deck(deck_start_m, s_start_m=0.0, speed=30.0, track=None, with_bridge=True, zeta=0.02, spans=(L,)):
    """Manchester vehicle 1 (wheelsets at x = ±9.5 ± 1.28 m) with its frame origin at s_start_m and a deck of 20 m
    spans from deck_start_m; returns (mbs, contact, modes, q, v) with a deflected, moving deck (lateral, vertical and
    torsion modes) and a pose per wheelset."""
    modes = _modes(damping_ratio=zeta, f_max_Hz=60.0, start_m=deck_start_m, spans=spans)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=speed, s_start_m=s_start_m)
    bridge = add_bridge(mbs, modes) if with_bridge else None
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, _pair(), speed_m_s=speed, s_start_m=s_start_m,
                                       structure=bridge, track=track, **CREEP)
    n_m = modes.n_modes
    rng = np.random.default_rng(5)
    q = np.zeros(24 + n_m)
    v = np.zeros(24 + n_m)
    for k in range(4):
        q[6 * k + 1], q[6 * k + 2], q[6 * k + 5] = 1e-3 * (k - 1.5), 2.5e-4, 1e-3 * (1 - 0.5 * k)
        v[6 * k + 1], v[6 * k + 2], v[6 * k + 4] = 0.01, -0.002, -speed / 0.46 * (1 + 1e-4 * k)
    # mass-normalised shapes ~2.6e-3 (bending) / 1.3e-3 (torsion): deck offsets ~0.3 mm, roll ~1e-4 rad
    q[24:] = rng.normal(scale=0.1, size=n_m) / (1.0 + np.arange(n_m))
    v[24:] = rng.normal(scale=0.5, size=n_m) / (1.0 + np.arange(n_m))
    if not with_bridge:
        q, v = q[:24], v[:24]
    return mbs, contact, modes, q, v


def test_modal_forces_are_the_projection_of_minus_the_contact_forces():
    """Action = reaction: the connector's generalized modal forces equal Σ Φ(s)^T (Fy, Fz, Mx) of the forces on the
    rails, rebuilt here from the recorded wheel forces (minus), contact points and deck offsets with the bridge
    module's own projection (BridgeModes.project); the rail forces sum to minus the wheelset forces."""
    # two simply supported 20 m spans from s = -20 m: all four wheelsets on the deck, two on each span
    mbs, contact, modes, q, v = _vehicle_on_deck(deck_start_m=-L, spans=(L, L))
    f = contact.forces(q, v, 0.0).copy()
    r = contact.results
    on = r[:, :, C.RES_STATUS] > 0
    assert on.sum() >= 8 and np.all(r[:, :, C.RES_ON_DECK] == 1.0)  # 0/1 flags: exact
    F = r[..., C.RES_F_TRACK_X:C.RES_F_TRACK_Z + 1][on]                   # on the wheels
    P = r[..., C.RES_P_X:C.RES_P_Z + 1][on]
    yb, zb = r[..., C.RES_DECK_Y][on], r[..., C.RES_DECK_Z][on]
    Fr = -F
    Mx = (P[:, 1] - yb) * Fr[:, 2] - (P[:, 2] - zb) * Fr[:, 1]
    # spin moments act about the contact normal, which has no x component on a straight track: no Mx from them
    s = r[..., C.RES_S_TRACK][on]
    Q_ref = modes.project(s, np.column_stack([Fr[:, 1], Fr[:, 2], Mx]))
    np.testing.assert_allclose(f[24:], Q_ref, rtol=1e-9, atol=1e-9 * np.abs(Q_ref).max())
    assert np.abs(Q_ref).max() > 10.0
    rail = contact.rail_forces_N()
    for k in range(4):
        np.testing.assert_allclose(rail[k, :2], -f[6 * k + 1:6 * k + 3], rtol=1e-12)
    # the deck offsets used are Φ(s) q at the wheelset's s
    for w in range(8):
        u = modes.shape_at(r[w, 0, C.RES_S_TRACK]) @ q[24:]
        np.testing.assert_allclose(r[w, 0, [C.RES_DECK_Y, C.RES_DECK_Z, C.RES_DECK_ROLL]], u, rtol=1e-12,
                                   atol=1e-18)


def test_moving_deck_and_wheelsets_together_changes_nothing():
    """Invariance: the wheelset poses, translated with the deck's rail offsets (y, z) and rolled by the deck's θ about
    the rails' centre line at rail top — with the matching velocities (deck velocity plus θ̇ about that line) —
    give the contact forces of the undisplaced system rotated by R_x(θ) (torques in the body frame unchanged), and
    the forces on the rails (Fy, Fz) rotated likewise with the same moment about the deflected centre line."""
    speed = 30.0
    mbs, contact, modes, q, v = _vehicle_on_deck(deck_start_m=-L, speed=speed, spans=(L, L))
    n_m = modes.n_modes
    # reference: the vehicle on the undeflected, resting deck (yaw set to zero: the kernel's roll is the axle's)
    q0, v0 = q.copy(), v.copy()
    q0[24:] = 0.0
    v0[24:] = 0.0
    for k in range(4):
        q0[6 * k + 5] = 0.0
    f0 = contact.forces(q0, v0, 0.0).copy()
    rail0 = contact.rail_forces_N()
    st0 = contact.save_warm_start()
    # a deck state: the same rigid offset (y, z, θ) and rates under every wheelset — one mode set per wheelset
    # cannot do that, so each wheelset is checked on its own deck state (modal coordinates by least squares)
    u, du = np.array([4e-4, 6e-4, 2e-4]), np.array([0.01, -0.02, 0.05])
    s_w = np.array([contact.results[2 * k, 0, C.RES_S_TRACK] for k in range(4)])
    R = np.empty((3, 3))
    for k in range(4):
        phi = modes.shape_at(s_w[k])
        qm = np.linalg.lstsq(phi, u, rcond=None)[0]
        vm = np.linalg.lstsq(phi, du, rcond=None)[0]
        np.testing.assert_allclose(phi @ qm, u, rtol=1e-10)
        q1, v1 = q0.copy(), v0.copy()
        q1[24:], v1[24:] = qm, vm
        th, dth = u[2], du[2]
        Rx = np.array([[1, 0, 0], [0, math.cos(th), -math.sin(th)], [0, math.sin(th), math.cos(th)]])
        o = 6 * k
        p = contact.p_ref[k] + q0[o:o + 3]
        p1 = Rx @ p + np.array([0.0, u[0], u[1]])
        q1[o:o + 3] = p1 - contact.p_ref[k]
        C.rotation_from_vector(*q0[o + 3:o + 6], R)
        C._rotation_vector_from_matrix(Rx @ R, q1, o + 3)
        v1[o:o + 3] = Rx @ v0[o:o + 3] + np.array([0.0, du[0], du[1]]) + np.cross([dth, 0, 0], p1 - [0, u[0], u[1]])
        v1[o + 3:o + 6] = v0[o + 3:o + 6] + R.T @ np.array([dth, 0.0, 0.0])
        contact.restore_warm_start(st0)
        f1 = contact.forces(q1, v1, 0.0).copy()
        np.testing.assert_allclose(f1[o:o + 3], Rx @ f0[o:o + 3], rtol=1e-7, atol=1e-6 * np.abs(f0[o:o + 3]).max())
        np.testing.assert_allclose(f1[o + 3:o + 6], f0[o + 3:o + 6], rtol=1e-7,
                                   atol=1e-6 * np.abs(f0[o + 3:o + 6]).max())
        rail1 = contact.rail_forces_N()[k]
        np.testing.assert_allclose(rail1[:2], Rx[1:, 1:] @ rail0[k, :2], rtol=1e-7, atol=1e-6 * abs(rail0[k]).max())
        assert rail1[2] == pytest.approx(rail0[k, 2], rel=1e-6, abs=1e-6 * abs(rail0[k]).max())
        assert n_m > 3 and abs(rail0[k, 1]) > 1e4


# --------------------------------------------------------------------------------------------- (d) off deck
def test_wheels_off_the_deck_see_the_rigid_track():
    """With a lateral irregularity on the whole track: wheelsets off the deck get exactly the forces of the model
    without a bridge (whatever the deck does), wheelsets on it differ; a deck far ahead changes nothing in a
    dynamic run and stays at rest."""
    track = RigidStraightTrack(Harmonic(amplitude_m=1e-3, wavelength_m=25.0))
    # deck under the front bogie only (front wheelsets at s = 18.8, 16.2; rear ones at -0.2, -2.8)
    mbs, contact, modes, q, v = _vehicle_on_deck(deck_start_m=0.0, s_start_m=8.0, track=track)
    f = contact.forces(q, v, 0.0).copy()
    on = contact.results[::2, 0, C.RES_ON_DECK]
    np.testing.assert_array_equal(on, [1.0, 1.0, 0.0, 0.0])  # 0/1 flags: exact
    mbs0, contact0, _, q0, v0 = _vehicle_on_deck(deck_start_m=0.0, s_start_m=8.0, track=track, with_bridge=False)
    f0 = contact0.forces(q0, v0, 0.0).copy()
    # exact by construction: off the deck the bridge path adds exact zero offsets and rotates by the identity, and
    # each wheel is evaluated on its own by the same compiled code
    np.testing.assert_array_equal(f[12:24], f0[12:24])
    np.testing.assert_array_equal(contact.results[4:, :, :C.RES_DECK_Y], contact0.results[4:, :, :C.RES_DECK_Y])
    assert np.all(contact.results[4:, :, C.RES_DECK_Y:] == 0.0)  # off the deck: zero shapes, exact zeros
    assert np.abs(f[:12] - f0[:12]).max() > 100.0                 # the deck does act on the front wheelsets
    # dynamics: a wheelset running towards a deck 100 m ahead, with and without the bridge
    out = []
    for with_bridge in (True, False):
        modes = _modes(damping_ratio=0.02, start_m=100.0) if with_bridge else None
        SC, mbs, model, bridge, contact, sensor = _wheelset_on_bridge(modes, speed=30.0, s_start=0.0, track=track)
        node = model.wheelsets[0].node
        mbs.Assemble()
        contact.warm_up(mbs)
        ss = simulation_settings(0.2, 1e-3)
        ss.timeIntegration.newton.useModifiedNewton = True
        mbs.SolveDynamic(ss)
        out.append(np.array(mbs.GetNodeOutput(node, exu.OutputVariableType.Coordinates)))
        if with_bridge:
            qb, vb = bridge.coordinates(mbs)
            assert np.all(qb == 0.0) and np.all(vb == 0.0)        # exact: unloaded, uncoupled, from rest
    # two different systems (the bridge adds decoupled coordinates, so the linear solves may round differently and
    # Newton may stop one iteration apart): equal to the Newton tolerance, relative to the wheelset's motion
    # (bit-identical on the CPU this was written on)
    tol = simulation_settings(1.0, 1.0).timeIntegration.newton.relativeTolerance
    np.testing.assert_allclose(out[0], out[1], rtol=tol, atol=tol * np.abs(out[1][:3]).max())
    assert abs(out[0][1]) > 1e-5                                  # the irregularity moved the wheelset


# ----------------------------------------------------------------------------------------------- Jacobian
def test_structured_jacobian_with_bridge_equals_column_by_column_differences():
    """The Jacobian user function with a bridge (wheelset columns perturbed for all wheelsets at once; modal columns
    by the chain rule through the deck state under each wheelset) against one-coordinate-at-a-time differences of
    the force function: wheelset columns with the same forward steps; modal columns by central differences with a
    step that moves the rail by ~1e-7 m — the structured Jacobian's forward differences differ from them by their
    truncation error, 1.8e-3 of the column at the connector's steps and 1.9e-5 at 100 times smaller steps (first
    order: the chain rule itself is exact)."""
    mbs, contact, modes, q, v = _vehicle_on_deck(deck_start_m=0.0, s_start_m=8.0)    # two wheelsets on the deck
    n = q.size
    a, b = 1.0, 0.5
    contact.forces(q, v, 0.0)                               # a warm start for the state
    state = contact.save_warm_start()
    contact.jacobian_method = "forward_difference"         # the structured differences (not the default)
    J = contact._jacobian_uf(mbs, 0.0, 0, q, v, a, b).copy()

    def f(qq, vv):                                          # every evaluation from the Jacobian's warm start
        contact.restore_warm_start(state)
        return contact.forces(qq, vv, 0.0).copy()

    f0 = f(q, v)

    for j in (0, 1, 2, 7, 13, 19, 20):                    # wheelset coordinates (x moves s: Φ(s) changes)
        qp, vp = q.copy(), v.copy()
        qp[j] += 1e-7
        vp[j] += 1e-5
        ref = -(a * (f(qp, v) - f0) / 1e-7 + b * (f(q, vp) - f0) / 1e-5)
        np.testing.assert_allclose(J[:, j], ref, atol=1e-6 * np.abs(ref).max())
        assert np.abs(ref[24:]).max() > 0.0 or j >= 12     # front wheelsets (on the deck) load the deck
    s_w = contact.results[::2, 0, C.RES_S_TRACK]
    phi = modes.shape_at(s_w)                               # (4, 3, n_m)
    # the same Jacobian with 100 times smaller steps (1e-9 m / rad, 1e-7 m/s): the chain rule is exact in the limit,
    # the difference to the exact derivative is the forward-difference truncation, proportional to the step
    J_fine = np.zeros((n, n))
    contact.restore_warm_start(state)
    C.contact_jacobian_core(*contact._args(q, v, 0.0), np.zeros(n), contact.results, a, b, J_fine, 1e-9, 1e-9, 1e-7)
    checked = 0
    for j in range(24, n):
        amp = np.abs(phi[:, :, j - 24]).max()
        if amp < 1e-9:                                      # axial modes: (almost) no rail offset
            assert np.abs(J[:, j]).max() < 1e-12 * np.abs(J).max()
            continue
        hq = 1e-7 / amp                                     # central differences, rail moved by ~1e-7 m
        hv = 1e-5 / amp
        e = np.zeros(n)
        e[j] = 1.0
        dq = (f(q + hq * e, v) - f(q - hq * e, v)) / (2 * hq)
        dv = (f(q, v + hv * e) - f(q, v - hv * e)) / (2 * hv)
        ref = -(a * dq + b * dv)
        scale = np.abs(ref).max()
        np.testing.assert_allclose(J[:, j], ref, atol=5e-3 * scale)          # measured ≤ 1.8e-3
        np.testing.assert_allclose(J_fine[:, j], ref, atol=1e-4 * scale)     # measured ≤ 1.9e-5
        checked += 1
    assert checked >= 6
    # no coupling to the wheelsets off the deck (rear: rows/columns 12..23): structural zeros, exact
    np.testing.assert_array_equal(J[12:24, 24:], 0.0)
    np.testing.assert_array_equal(J[24:, 12:24], 0.0)


# --------------------------------------------------------------------------------------------- bad input
def test_bad_bridge_input_raises():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=30.0)
    with pytest.raises(TypeError, match="ExudynBridge"):
        C.add_wheel_rail_contact(mbs, model.wheelset_nodes, _pair(), speed_m_s=30.0, structure=_modes(0.02), **CREEP)
    bridge = add_bridge(mbs, _modes(0.02, f_max_Hz=30.0))
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, _pair(), speed_m_s=30.0, structure=bridge, **CREEP)
    n = 6 + bridge.modes.n_modes
    with pytest.raises(ValueError, match=f"expected \\({n},\\)"):
        contact.forces(np.zeros(6), np.zeros(6), 0.0)
    q = np.zeros(n)
    q[-1] = np.nan
    with pytest.raises(C.ContactStateError, match="modal coordinates"):
        contact.forces(q, np.zeros(n), 0.0)


# ------------------------------------------------------------------------------------------------ example
def test_bridge_crossing_example_agrees_with_the_moving_axle_loads(tmp_path):
    """examples/bridge_crossing.py (Manchester vehicle, 40 m span, 200 km/h): the coupled mid-span deflection is
    within 2 % of the deck under the vehicle's static axle loads moving at V (the vehicle–bridge interaction of a
    stiff, heavy deck is small), above the quasi-static influence-line maximum, and the outputs are complete."""
    import csv
    import importlib.util
    import json

    path = Path(__file__).resolve().parents[1] / "examples" / "bridge_crossing.py"
    spec = importlib.util.spec_from_file_location("bridge_crossing", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.main(["--span", "40", "--speed-kmh", "200", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    sp = s["deck"]["spans"][0]
    assert sp["coupled_over_moving_force"] == pytest.approx(1.0, abs=0.02)
    assert sp["dynamic_amplification_mid_span"] > 1.0
    en = s["deck"]["EN1990_A2_deck_acceleration"]
    assert en["ballasted_ok"] == (en["peak_m_s2"] <= 3.5) and en["direct_fastening_ok"] == (en["peak_m_s2"] <= 5.0)
    assert s["model"]["bridge"]["f_cut_Hz"] == pytest.approx(max(30.0, 1.5 * 3.5, 9 * 3.5))
    with open(tmp_path / "timeseries.csv") as fh:
        header = next(csv.reader(fh))
    for c in ("time_s", "deck_mid_deflection_s1_m", "deck_mid_acceleration_s1_m_s2", "Q_w1_right_N", "YQ_w4_left",
              "dQQ_w2_right"):
        assert c in header
    # the static wheel loads of the load path sum to the vehicle's weight
    from exudyn_wheelrail.multibody import load_vehicle
    Q0 = s["model"]["static_wheel_loads_N"]
    assert sum(Q0.values()) == pytest.approx(load_vehicle("manchester_vehicle1").total_mass_kg * G_M_S2, rel=1e-9)
