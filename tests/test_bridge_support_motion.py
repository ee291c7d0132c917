"""Lateral support (ground) motion of a bridge (exudyn_wheelrail.structures.support_motion) and its transmission to
the vehicle through the wheel–rail contact.

References (independent of the code under test):
* participation factors of a simply supported Euler–Bernoulli span, mass-normalised modes
  ``√(2/(mL)) sin(nπx/L)``: ``Γ_n = ∫ m φ_n dx = 2√(2mL)/(nπ)`` (odd n), 0 for even n; no participation of
  vertical, torsion and axial modes in a lateral translation;
* the quasi-static relative deflection of a simply supported beam under the uniform inertia load ``-m ÿ_g``:
  ``-5 m ÿ_g L⁴/(384 EI_z)`` at mid-span;
* the single-DOF modal equation ``q̈ + 2ζωq̇ + ω²q = -Γ ÿ_g(t)`` integrated by scipy (DOP853, rtol 1e-11), and its
  steady state ``|q| = Γ a/ω² · 1/√((1-r²)² + (2ζr)²)``, r = Ω/ω; the continuous beam's steady-state mid-span
  amplitude ``Σ_n φ_n(L/2) Γ_n a H_n/ω_n²`` with the analytic ``φ_n, Γ_n, ω_n``;
* invariance: translating the ground and every wheelset together (with velocities) changes no contact force;
* creep lock of a laterally free wheelset at low speed V: the lateral creep force ``-2 f22 ẏ_rel/V`` (Kalker's
  linear theory, ``f22 = G a b C22`` per wheel from Kalker's Table E.3) carries the wheelset with the rails, so the
  relative displacement follows ``y_rel(t) ≈ -(m V/(2 f22)) ẏ_rail(t)`` (micrometres), far from flange contact.
"""
from __future__ import annotations

import math
import tomllib
from pathlib import Path

import exudyn as exu
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.creep.linear import kalker_coefficients
from exudyn_wheelrail.multibody import build_vehicle, vehicle_from_dict
from exudyn_wheelrail.simulation.exudyn_settings import simulation_settings
from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.multibody.direct_call import native_available
from exudyn_wheelrail.structures import BridgeModel, DeckSection, add_bridge
from exudyn_wheelrail.scenarios.moving_forces import simulate_moving_forces
from exudyn_wheelrail.structures.support_motion import (
    SmoothHarmonicSupportMotion,
    SupportMotion,
    smoothstep5,
)

VEHICLES = Path(__file__).resolve().parents[1] / "vehicles"
# the 20 m deck of tests/test_bridge.py: f1 (vertical) 4.53 Hz, lateral 10.1 Hz, torsion 7.91 Hz
SEC = DeckSection(m_kg_m=15e3, EI_y_Nm2=2.0e10, EI_z_Nm2=1.0e11, GJ_Nm2=6e9, EA_N=2e11, Ip_kgm2_m=6e4)
L = 20.0
CREEP = dict(creep_law="fastsim", fastsim_grid=(16, 8))


def _pair():
    return WheelRailPair("S1002", "UIC60", inclination="1/40")


def _phi_ss(n, x):
    """Mass-normalised sine mode of the simply supported span."""
    return math.sqrt(2.0 / (SEC.m_kg_m * L)) * math.sin(n * math.pi * x / L)


def _gamma_ss(n):
    return 2.0 * math.sqrt(2.0 * SEC.m_kg_m * L) / (n * math.pi) if n % 2 else 0.0


# ------------------------------------------------------------------------------------------ the formulation
def test_participation_factors_and_quasi_static_deflection_against_the_beam():
    """Γ of the lateral modes against 2√(2mL)/(nπ) (signs follow the modes' sign rule), zero for all other modes;
    the static modal sum Σ φ_n(L/2) (-Γ_n a/ω_n²) equals the beam under the uniform inertia load -m a."""
    modes = BridgeModel((L,), SEC, rail_height_m=1.0).modes(f_max_Hz=1000.0)
    G = modes.participation_factors("lateral")
    lat = modes.of_kind("lateral")
    assert len(lat) >= 6
    for n, j in enumerate(lat[:6], start=1):
        sign = np.sign(modes.shape_at(L / (2 * n))[0, j])             # the sine's first crest
        assert sign * G[j] == pytest.approx(_gamma_ss(n), abs=2e-5 * _gamma_ss(1)), n
    others = np.setdiff1d(np.arange(modes.n_modes), lat)
    assert np.abs(G[others]).max() < 1e-9 * _gamma_ss(1)
    assert G[lat[0]] ** 2 == pytest.approx(8.0 / math.pi ** 2 * SEC.m_kg_m * L, rel=1e-6)   # effective mass
    # a vertical translation loads only the vertical modes
    Gv = modes.participation_factors("vertical")
    assert np.abs(Gv[lat]).max() < 1e-9 * _gamma_ss(1) and np.abs(Gv).max() > 0.9 * _gamma_ss(1)
    a = 1.5
    phi = modes.shape_at(L / 2)[0]                                     # y_rail row (torsion: Γ = 0)
    w_rel = float(phi @ (-G * a / modes.omega_rad_s ** 2))
    assert w_rel == pytest.approx(-5.0 * SEC.m_kg_m * a * L ** 4 / (384.0 * SEC.EI_z_Nm2), rel=1e-5)
    with pytest.raises(ValueError, match="direction"):
        modes.participation_factors("longitudinal")


def test_sine_burst_is_c2_starts_and_ends_at_rest_and_has_the_stated_peak():
    m = SmoothHarmonicSupportMotion(1.5, 1.5, ramp_cycles=1.0, plateau_cycles=2.0, start_s=0.2)
    t = np.linspace(0.0, m.end_s + 0.3, 400001)
    y, v, a = m.displacement_m(t), m.velocity_m_s(t), m.acceleration_m_s2(t)
    # derivatives consistent (central differences), continuous acceleration (C2: no jumps)
    np.testing.assert_allclose(np.gradient(y, t)[1:-1], v[1:-1], atol=1e-6 * np.abs(v).max())
    np.testing.assert_allclose(np.gradient(v, t)[1:-1], a[1:-1], atol=1e-5 * np.abs(a).max())
    assert np.abs(np.diff(a)).max() < 1e-3 * np.abs(a).max()
    for k in (y, v, a):
        assert k[0] == 0.0 and k[-1] == 0.0  # before the start and after the end: exact zeros
    assert np.abs(a).max() == pytest.approx(1.5, rel=1e-5)                    # the stated peak acceleration
    plateau = (t > 0.2 + m.ramp_s) & (t < 0.2 + m.ramp_s + m.plateau_s)
    assert np.abs(a[plateau]).max() == pytest.approx(m.plateau_acceleration_m_s2, rel=1e-6)
    assert m.amplitude_m == pytest.approx(m.plateau_acceleration_m_s2 / (2 * math.pi * 1.5) ** 2)
    assert smoothstep5(0.5) == (0.5, 1.875, 0.0)  # dyadic values: exact in any order
    # a steady sine without ramps: ÿ_g = -a sin Ωt exactly
    s = SmoothHarmonicSupportMotion(2.0, 3.0, ramp_cycles=0.0, plateau_cycles=math.inf)
    np.testing.assert_allclose(s.acceleration_m_s2(t[1:]), -2.0 * np.sin(6 * math.pi * t[1:]), atol=1e-12)
    for kwargs, exc in (({"peak_acceleration_m_s2": -1.0, "frequency_Hz": 1.0}, ValueError),
                        ({"peak_acceleration_m_s2": 1.0, "frequency_Hz": 0.0}, ValueError),
                        ({"peak_acceleration_m_s2": "x", "frequency_Hz": 1.0}, TypeError),
                        ({"peak_acceleration_m_s2": 1.0, "frequency_Hz": 1.0, "ramp_cycles": math.nan}, ValueError)):
        with pytest.raises(exc):
            SmoothHarmonicSupportMotion(**kwargs)


# --------------------------------------------------------------------------------- (a) deck, no vehicle
def test_deck_under_harmonic_support_motion_against_sdof_and_steady_state():
    """The deck alone (ζ = 5 %) under ÿ_g = -a sin Ωt from rest, Ω = 0.8 ω1 (first lateral mode), a = 1.5 m/s²,
    3 s, trapezoidal rule at 0.5 ms: the first lateral modal coordinate against the SDOF equation integrated by
    scipy (whole history), its steady-state amplitude against Γ a/ω² · 1/√((1-r²)²+(2ζr)²) (last 0.5 s: the
    transient has decayed to e^{-ζω·2.5 s} = 3e-4), the mid-span relative amplitude against the continuous beam's
    modal sum, and the modes that a lateral translation does not excite stay at rest."""
    zeta, a, r = 0.05, 1.5, 0.8
    modes = BridgeModel((L,), SEC, damping_ratio=zeta, rail_height_m=1.0).modes(f_max_Hz=300.0)
    j1 = int(modes.of_kind("lateral")[0])
    w1 = float(modes.omega_rad_s[j1])
    Om = r * w1
    motion = SmoothHarmonicSupportMotion(a, Om / (2 * math.pi), ramp_cycles=0.0, plateau_cycles=math.inf)
    T, h = 3.0, 5e-4
    t, q, _ = simulate_moving_forces(modes, x_m=[0.0], forces_N=[[0.0, 0.0, 0.0]], speed_m_s=1.0, s_start_m=-1e3,
                                     end_time_s=T, dt_s=h, support_motion=motion)
    G = modes.participation_factors()[j1]
    ref = solve_ivp(lambda tt, x: [x[1], -2 * zeta * w1 * x[1] - w1 ** 2 * x[0] - G * motion.state(tt)[2]],
                    (0.0, T), [0.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-14, t_eval=t, max_step=1e-3).y[0]
    peak = np.abs(ref).max()
    assert np.abs(q[:, j1] - ref).max() < 1e-3 * peak                          # measured 5.2e-4
    late = t > T - 0.5
    amp_ss = abs(G) * a / w1 ** 2 / math.sqrt((1 - r * r) ** 2 + (2 * zeta * r) ** 2)
    assert np.abs(q[late, j1]).max() == pytest.approx(amp_ss, rel=1e-3)       # measured 2.8e-4
    assert amp_ss / (abs(G) * a / w1 ** 2) == pytest.approx(2.711, abs=1e-3)        # the resonance amplification
    # mid-span relative amplitude: continuous beam, lateral modes n = 1, 3 (both kept: 10.1 and 91 Hz)
    y_mid = q @ modes.shape_at(L / 2)[0]
    H = 0.0
    for n in (1, 3):
        wn = (n * math.pi / L) ** 2 * math.sqrt(SEC.EI_z_Nm2 / SEC.m_kg_m)
        rn = Om / wn
        Hn = _phi_ss(n, L / 2) * _gamma_ss(n) * a / wn ** 2 / complex(1 - rn * rn, 2 * zeta * rn)
        H += Hn
    assert np.abs(y_mid[late]).max() == pytest.approx(abs(H), rel=1e-3)       # measured 3.9e-4 (1.274 mm)
    # modes without lateral participation are not excited
    quiet = np.setdiff1d(np.arange(modes.n_modes), modes.of_kind("lateral"))
    assert np.abs(q[:, quiet]).max() < 1e-8 * np.abs(q[:, j1]).max()


def test_ffrf_formulation_takes_the_same_support_motion():
    modes = BridgeModel((L,), SEC, damping_ratio=0.02, rail_height_m=1.0).modes(f_max_Hz=60.0)
    motion = SmoothHarmonicSupportMotion(1.5, 8.0, ramp_cycles=1.0, plateau_cycles=2.0)
    out = {}
    for form in ("modal", "ffrf"):
        t, q, _ = simulate_moving_forces(modes, x_m=[0.0], forces_N=[[0.0, 0.0, 0.0]], speed_m_s=1.0,
                                         s_start_m=-1e3, end_time_s=0.5, dt_s=1e-3, formulation=form,
                                         support_motion=motion)
        out[form] = q
    assert np.abs(out["modal"]).max() > 1e-5
    # the same equations by two code paths: the FFRF run's Newton stops at a relative residual tolerance, so the two
    # agree to that tolerance times the total variation of the response (see tests/test_bridge.py; measured ~1e-10
    # of the peak on one CPU, the exact agreement depends on the rounding)
    tol = simulation_settings(1.0, 1.0).timeIntegration.newton.relativeTolerance
    np.testing.assert_allclose(out["ffrf"], out["modal"], rtol=0,
                               atol=tol * np.abs(np.diff(out["modal"], axis=0)).sum(axis=0).max())


# ----------------------------------------------------------------------- the connector sees the ground
class _FixedGround(SupportMotion):
    """A ground state frozen in time (for the kinematic checks)."""

    def __init__(self, y, v, a=0.0):
        self.y, self.v, self.a = y, v, a

    def state(self, t_s):
        return self.y, self.v, self.a


def test_ground_and_wheelsets_moved_together_change_no_contact_force():
    """Manchester vehicle 1, two wheelsets on a deflected, moving deck and two off it: moving the ground by y_g with
    velocity ẏ_g and every wheelset by the same (position and velocity) leaves all contact forces, the modal forces
    and the rail forces unchanged — on the deck and off it (synchronous ground motion: the track off the deck moves
    too); the Jacobian is unchanged as well, the ground state is reported, and the pose relative to the rails is the
    same."""
    speed = 30.0
    modes = BridgeModel((L,), SEC, damping_ratio=0.02, rail_height_m=1.0).modes(f_max_Hz=60.0)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=speed, s_start_m=8.0)
    bridge = add_bridge(mbs, modes)
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, _pair(), speed_m_s=speed, s_start_m=8.0,
                                       structure=bridge, **CREEP)
    n_m = modes.n_modes
    rng = np.random.default_rng(3)
    q = np.zeros(24 + n_m)
    v = np.zeros(24 + n_m)
    for k in range(4):
        q[6 * k + 1], q[6 * k + 2], q[6 * k + 5] = 1e-3 * (k - 1.5), 2.5e-4, 1e-3 * (1 - 0.5 * k)
        v[6 * k + 1], v[6 * k + 2], v[6 * k + 4] = 0.01, -0.002, -speed / 0.46 * (1 + 1e-4 * k)
    q[24:] = rng.normal(scale=0.1, size=n_m) / (1.0 + np.arange(n_m))
    v[24:] = rng.normal(scale=0.5, size=n_m) / (1.0 + np.arange(n_m))
    f0 = contact.forces(q, v, 0.0).copy()
    res0 = contact.results.copy()
    rail0 = contact.rail_forces_N()
    pose0 = contact.wheelset_rail_pose()
    np.testing.assert_array_equal(contact.results[::2, 0, C.RES_ON_DECK], [1.0, 1.0, 0.0, 0.0])  # 0/1 flags: exact
    st0 = contact.save_warm_start()
    J0 = contact._jacobian_uf(mbs, 0.0, 0, q, v, 1.0, 0.5).copy()
    Y, VY = 0.012, -0.15
    # the compiled call path does not evaluate a ground motion: a support motion added later switches it to Python
    assert contact.call_path == ("compiled" if native_available() else "python")
    bridge.add_support_motion(mbs, _FixedGround(Y, VY, 0.7))
    assert contact.call_path == "python"
    with pytest.raises(ValueError, match="already has a support motion"):
        bridge.add_support_motion(mbs, _FixedGround(0.0, 0.0))
    q1, v1 = q.copy(), v.copy()
    for k in range(4):
        q1[6 * k + 1] += Y
        v1[6 * k + 1] += VY
    contact.restore_warm_start(st0)
    f1 = contact.forces(q1, v1, 0.0).copy()
    assert np.abs(f0[:24]).max() > 1e4 and np.abs(f0[24:]).max() > 10.0
    np.testing.assert_allclose(f1, f0, rtol=1e-7, atol=1e-7 * np.abs(f0).max())
    np.testing.assert_allclose(contact.rail_forces_N(), rail0, rtol=1e-7, atol=1e-7 * np.abs(rail0).max())
    np.testing.assert_allclose(contact.wheelset_rail_pose(), pose0, rtol=0, atol=1e-12)
    # the ground state stored as given: exact
    assert np.all(contact.results[:, :, C.RES_GROUND_Y] == Y) and np.all(contact.results[:, :, C.RES_GROUND_VY] == VY)
    # everything else reported is the same; contact points shift by Y
    for i in range(C.N_RES):
        if i not in (C.RES_P_Y, C.RES_GROUND_Y, C.RES_GROUND_VY):
            np.testing.assert_allclose(contact.results[..., i], res0[..., i], rtol=1e-6,
                                       atol=1e-6 * np.abs(res0[..., i]).max() + 1e-15, err_msg=f"field {i}")
    on = res0[..., C.RES_STATUS] > 0
    # the relative pose is the same to rounding (1e-18 m) and every contact here is a convex one, located by Newton
    # (to ~1e-15 m): 1e-9 m.  (A point from the concave search would be located only to sqrt(2e-15 m / kappa_rel),
    # ~5e-8 m on a flat tread: see test_geometry_sweep.py.)
    assert np.all(res0[..., C.RES_STATUS][on] == K.STATUS_CONVEX)  # a status code: exact
    np.testing.assert_allclose(contact.results[..., C.RES_P_Y][on], res0[..., C.RES_P_Y][on] + Y, atol=1e-9)
    contact.restore_warm_start(st0)
    J1 = contact._jacobian_uf(mbs, 0.0, 0, q1, v1, 1.0, 0.5).copy()
    np.testing.assert_allclose(J1, J0, rtol=1e-5, atol=1e-5 * np.abs(J0).max())
    assert contact.ground_state(0.0) == (Y, VY)  # stored as given: exact
    # without moving the wheelsets, the ground offset does act (a lateral shift of 12 mm: flange contact)
    contact.restore_warm_start(st0)
    f2 = contact.forces(q, v, 0.0)
    assert np.abs(f2[:24] - f0[:24]).max() > 1e3


# ------------------------------------------------------------------ (b) vehicle standing on the deck
def test_slow_support_motion_carries_a_standing_wheelset_with_the_rails():
    """A laterally free wheelset (Manchester vehicle 1 wheelset under its dead axle load, primary lateral elements
    removed; yaw held by the longitudinal ones) rolls at V = 0.5 m/s over mid-span of the 20 m deck while the ground
    makes a 1.5 Hz, 1.5 m/s² sine burst (one-period ramps, one period of plateau; 15 mm amplitude).  The deck
    follows the ground quasi-statically (f_lat = 10.1 Hz: relative mid-span deflection ≈ 5 m ÿ_g L⁴/(384 EI_z)), and
    the rails carry the wheelset through the lateral creep force: at low speed it acts like a damper
    ``2 f22/V`` (4e7 N s/m) on the relative velocity, so the relative displacement follows
    ``y_rel ≈ -(m V/(2 f22)) ẏ_rail`` — a few micrometres — with f22 = G a b C22 (Kalker's linear theory, C22 from
    Table E.3, semi-axes from the run).  Checked: the wheelset's lateral displacement (Exudyn node) against the
    rails' (y_g + deck under it) within 0.1 % of the ground amplitude, the relative history against the creep-lock
    estimate (within 15 % of its peak) and its peak between 0.8 and 1.3 times the estimate, no flange contact
    (6.5 mm flange clearance)."""
    d = tomllib.loads((VEHICLES / "single_wheelset.toml").read_text())
    d["primary"]["ky_N_per_m"] = 0.0
    d["primary"]["cy_N_s_per_m"] = 0.0
    vehicle = vehicle_from_dict(d)
    modes = BridgeModel((L,), SEC, damping_ratio=0.02, rail_height_m=1.0).modes(f_max_Hz=60.0)
    for j in modes.of_kind("vertical"):
        modes.damping_ratio[j] = 0.7            # the deck settles vertically under the wheelset before the burst
    t_settle, f_g, a_g, V = 0.3, 1.5, 1.5, 0.5
    motion = SmoothHarmonicSupportMotion(a_g, f_g, ramp_cycles=1.0, plateau_cycles=1.0, start_s=t_settle)
    T, h = motion.end_s + 0.2, 1e-3
    s0 = L / 2 - 0.5 * V * T
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, vehicle, speed_m_s=V, s_start_m=s0)
    pair = _pair()
    C.place_on_rails(mbs, model, pair)
    bridge = add_bridge(mbs, modes)
    bridge.add_support_motion(mbs, motion)
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V, s_start_m=s0, structure=bridge,
                                       **CREEP)
    from exudyn.itemInterface import SensorNode
    s_ws = mbs.AddSensor(SensorNode(nodeNumber=model.wheelsets[0].node, storeInternal=True,
                                    outputVariableType=exu.OutputVariableType.Coordinates))
    s_br = bridge.add_sensor(mbs)
    flange = []
    mbs.SetPreStepUserFunction(lambda mbs_, t: flange.append(contact.results[:, 1, C.RES_N].max()) or True)
    mbs.Assemble()
    contact.warm_up(mbs)
    ss = simulation_settings(T, h)
    ss.timeIntegration.newton.useModifiedNewton = True
    assert mbs.SolveDynamic(ss)
    dw = mbs.GetSensorStoredData(s_ws)
    db = mbs.GetSensorStoredData(s_br)
    t = dw[:, 0]
    np.testing.assert_allclose(db[:, 0], t)
    assert t.size == int(round(T / h)) + 1 and np.all(np.diff(t) > 0)        # no step reductions
    s_t = s0 + V * t + dw[:, 1]                             # the axle centre's track distance (x: creep, µm)
    y_deck, z_deck, th_deck = np.einsum("ikj,ij->ki", modes.shape_at(s_t), db[:, 1:])   # rows y, z, θ
    y_g = motion.displacement_m(t)
    y_rail = y_g + y_deck
    y_ws = dw[:, 2]                                                             # node coordinate y
    z_ws = contact.p_ref[0, 2] + dw[:, 3]
    assert np.abs(y_g).max() == pytest.approx(motion.amplitude_m, rel=1e-3)
    # the deck follows the ground quasi-statically: relative deflection ≈ the beam under -m ÿ_g at mid-span
    y_qs = -5 * SEC.m_kg_m * motion.acceleration_m_s2(t) * L ** 4 / (384 * SEC.EI_z_Nm2)
    assert np.abs(y_deck - y_qs).max() < 0.1 * np.abs(y_qs).max()             # measured 0.073 (r = 0.15)
    # lateral wheelset–rail displacement in the frame of the rail pair (rolled with the deck by θ: the axle centre
    # is r0 above rail top, so the deck's roll under the wheel's lateral force, ~2e-6 rad, shifts it by ~1 µm)
    y_rel = (y_ws - y_rail) * np.cos(th_deck) + (z_ws - z_deck) * np.sin(th_deck)
    dy = y_rel - y_rel[t <= t_settle][-1]
    assert np.abs(y_rel).max() < 1e-3 * motion.amplitude_m                     # carried with the rails
    # the creep-lock estimate from Kalker's linear theory
    res = contact.evaluate(mbs, T)
    G_shear = 2.1e11 / (2 * (1 + 0.28))
    f22 = 0.0
    for w in (0, 1):
        a_, b_ = res[w, 0, C.RES_A], res[w, 0, C.RES_B]
        f22 += 0.5 * G_shear * a_ * b_ * kalker_coefficients(a_ / b_, 0.28)[1]
    assert 5e6 < f22 < 2e7
    m = vehicle.wheelset.mass_kg
    v_rail = np.gradient(y_rail, t)
    est = -(m * V / (2 * f22)) * v_rail
    peak_est = np.abs(est).max()
    assert 2e-6 < peak_est < 2e-5
    assert 0.9 < np.abs(dy).max() / peak_est < 1.2                             # measured 1.055
    assert np.abs(dy - est).max() < 0.12 * peak_est                             # measured 0.066
    # far from the flange: no flange contact, relative displacement ≪ 6.5 mm
    assert max(flange) == 0.0 and np.abs(dy).max() < 1e-2 * 6.5e-3
    # the connector's own view of the pose relative to the rails agrees with the sensors at the end
    assert contact.wheelset_rail_pose()[0, 0] == pytest.approx(y_rel[-1], abs=2e-8)


# ------------------------------------------------------------------------------------------------ example
def _example():
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "examples" / "bridge_crossing.py"
    spec = importlib.util.spec_from_file_location("bridge_crossing", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_bridge_crossing_example_with_support_motion(tmp_path):
    """examples/bridge_crossing.py --support-motion 1.5,1.5 (Manchester vehicle, 20 m span, 200 km/h): the outputs
    are complete, the ground record is the stated one, the deck follows the ground quasi-statically (relative
    mid-span motion within 10 % of 5 m a L⁴/(384 EI_z)), the wheelsets stay on the treads (no flange contact,
    |y_rel| below the 6.5 mm flange clearance) and the lateral forces are those of a shaken vehicle (Y/Q ≫ 0.005
    of the run without ground motion) but far below the flange-climbing limit; the vertical deck response is
    that of the run without ground motion."""
    import csv
    import json

    mod = _example()
    assert mod.main(["--span", "20", "--speed-kmh", "200", "--out", str(tmp_path),
                     "--support-motion", "1.5,1.5"]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    sm, sp = s["deck"]["support_motion"], s["deck"]["spans"][0]
    sc, verdicts = s["scalars"], s["criteria"]["verdicts"]
    assert sm["peak_acceleration_m_s2"] == 1.5 and sm["frequency_Hz"] == 1.5
    assert sm["max_abs_ground_acceleration_m_s2"] == pytest.approx(1.5, rel=1e-3)
    assert sp["max_abs_mid_lateral_rel_m"] == pytest.approx(sp["support_motion_quasi_static_mid_lateral_m"], rel=0.1)
    bridge = s["model"]["bridge"]
    assert bridge["frequencies_Hz"][bridge["kinds"].index("lateral")] == pytest.approx(
        sp["first_lateral_frequency_euler_bernoulli_Hz"], rel=1e-5)
    assert not sc["flange_contact_any_wheel"]
    assert 1e-4 < sc["max_abs_y_rel_any_wheelset_m"] < 6.5e-3
    assert 0.05 < sc["max_YQ_any_wheel"] < 0.8
    assert verdicts["derailment_quotient_en14363"]["worst_value"] < 0.8
    # Newton's law for the whole vehicle: each wheelset carries about a quarter of M ÿ_g (measured 1.005 of it
    # with the plateau acceleration; the suspension's own dynamics may add to it)
    from exudyn_wheelrail.multibody import load_vehicle
    M = load_vehicle("manchester_vehicle1").total_mass_kg
    ratio = verdicts["track_shift_force_prudhomme"]["worst_value"] / (M * sm["plateau_acceleration_m_s2"] / 4)
    assert 0.8 < ratio < 1.5
    # the lead-in is extended by the ramp: the leading wheelset reaches the deck when the ramp ends
    assert sp["start_m"] - s["scenario"]["vehicle"]["start_s_m"] == pytest.approx(5.0 + 200 / 3.6 / 1.5)
    # vertical: as without ground motion (docstring of the example: 1.370 mm)
    assert sp["max_mid_span_deflection_m"] == pytest.approx(1.370e-3, rel=5e-3)
    with open(tmp_path / "timeseries.csv") as fh:
        header = next(csv.reader(fh))
    for c in ("ground_lateral_m", "ground_lateral_acceleration_m_s2", "deck_mid_lateral_rel_s1_m",
              "deck_mid_lateral_acceleration_s1_m_s2", "y_rel_w1_m", "y_rel_w4_m", "YQ_w1_right"):
        assert c in header


@pytest.mark.parametrize("value", ["1.5", "a,b", "-1,1.5", "1.5,0", "1.5,50"])
def test_bridge_crossing_example_rejects_bad_support_motion(value, tmp_path):
    with pytest.raises(SystemExit):
        _example().main(["--span", "20", "--speed-kmh", "200", "--out", str(tmp_path), "--support-motion", value])
