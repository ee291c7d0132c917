"""The wheel–rail connector in Exudyn: static loads against the weight split, Klingel's kinematic wavelength of a
free coned wheelset and of a rigid bogie, wheelset spin over > 2000 rad, separation and re-contact, force/moment
bookkeeping, creep-law selection, bad states."""
from __future__ import annotations

import math
import tomllib
from pathlib import Path

import exudyn as exu
import numpy as np
import pytest
from exudyn.itemInterface import LoadTorqueVector, MarkerNodeRigid

from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
from exudyn_wheelrail.multibody import build_vehicle, vehicle_from_dict
from exudyn_wheelrail.simulation.exudyn_settings import simulation_settings
from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.profiles import WheelProfile
from exudyn_wheelrail.scenarios.validation_report import klingel_run, zero_crossing_wavelengths

VEHICLES = Path(__file__).resolve().parents[1] / "vehicles"
G_M_S2 = 9.81


def _pair(wheel="S1002"):
    return WheelRailPair(wheel, "UIC60", inclination="1/40")


def _solve(mbs, T, dt, solver="rk44"):
    sim = simulation_settings(T, dt)
    sim.timeIntegration.explicit.computeEndOfStepAccelerations = False
    sim.timeIntegration.newton.useModifiedNewton = True
    mbs.SolveDynamic(sim, solverType=exu.DynamicSolverType.RK44 if solver == "rk44"
                     else exu.DynamicSolverType.GeneralizedAlpha)


def test_static_wheel_loads_equal_the_weight_split():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=30.0)
    pair = _pair()
    C.place_on_rails(mbs, model, pair)
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=30.0, creep_law="fastsim",
                                       fastsim_grid=(16, 8))
    mbs.Assemble()
    _solve(mbs, 0.3, 1e-3)
    contact.evaluate(mbs, 0.3)
    Q = np.array([[-contact.wheel_force_N(w, s)[2] for s in ("right", "left")] for w in range(4)])
    total_weight = model.vehicle.total_mass_kg * G_M_S2
    assert Q.sum() == pytest.approx(total_weight, rel=2e-3)
    # symmetric vehicle: every wheel carries an eighth (the lever rule of the builder's load path)
    np.testing.assert_allclose(Q, total_weight / 8, rtol=2e-3)


def _klingel(pair, dz, conicity):
    """λ = 2π √(r0 e / γ) with r0 and e (half the lateral distance of the contact points) of the centred pair."""
    pts = WheelsetContact(pair, 1).contact_points(0.0, -0.46 + dz, 0.0)
    r0 = float(np.mean([p.rolling_radius_m for p in pts]))
    e = 0.5 * abs(pts[0].p_wheel_in_track[0] - pts[1].p_wheel_in_track[0])
    return 2 * math.pi * math.sqrt(r0 * e / conicity), e


def test_free_coned_wheelset_runs_at_klingels_wavelength():
    # the simulation of the validation report: free wheelset, cone γ = 0.05, 5 m/s, 1 mm offset, 8 s Newmark
    conicity = 0.05
    t, y, lam, _, r0, e = klingel_run(conicity, 5.0, 8.0, 1e-3)
    ref = 2 * math.pi * math.sqrt(r0 * e / conicity)        # Klingel, with r0 and e of the centred pair
    assert len(lam) >= 3
    np.testing.assert_allclose(lam, ref, rtol=0.02)
    assert np.std(lam) < 1e-3 * ref            # a clean periodic motion


def test_rigid_bogie_runs_at_the_rigid_bogie_wavelength():
    conicity, speed, kp = 0.05, 5.0, 1e9
    d = tomllib.loads((VEHICLES / "single_bogie.toml").read_text())
    d["primary"].update(kx_N_per_m=kp, ky_N_per_m=kp, kz_N_per_m=kp, cx_N_s_per_m=0.0, cy_N_s_per_m=0.0)
    d["secondary"].update(kx_N_per_m=0.0, ky_N_per_m=0.0, cx_N_s_per_m=0.0, cy_N_s_per_m=0.0,
                          yaw_stiffness_N_m_per_rad=0.0)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, vehicle_from_dict(d), speed_m_s=speed, bump_stop="none")
    pair = _pair(WheelProfile.cone(conicity))
    dz = C.place_on_rails(mbs, model, pair)
    for body in model.bodies:
        q0 = np.array(mbs.GetNodeParameter(body.node, "initialCoordinates"))
        q0[1] = 1e-3
        mbs.SetNodeParameter(body.node, "initialCoordinates", q0.tolist())
    C.add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=speed)
    bogie = model.bogies[0]
    rec = []
    mbs.SetPreStepUserFunction(lambda mbs, t: rec.append(
        (t, mbs.GetNodeOutput(bogie.node, exu.OutputVariableType.Position)[1])) or True)
    mbs.Assemble()
    _solve(mbs, 12.0, 1e-3, "newmark")
    t, y = np.array(rec).T
    lam = zero_crossing_wavelengths(t, y, speed)
    lam_w, e = _klingel(pair, dz, conicity)
    a = model.vehicle.geometry.semi_wheelbase_m
    assert len(lam) >= 2
    np.testing.assert_allclose(lam, lam_w * math.sqrt(1 + (a / e) ** 2), rtol=0.02)


def test_spin_over_2000_rad_changes_nothing():
    """A wheelset at 250 km/h held by its primary springs with a constant yaw moment (steady creep forces):
    creepages and forces after more than 2000 rad of spin equal those after 1 s."""
    speed = 250 / 3.6
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=speed)
    pair = _pair()
    C.place_on_rails(mbs, model, pair)
    ws = model.wheelsets[0]
    mbs.AddLoad(LoadTorqueVector(markerNumber=mbs.AddMarker(MarkerNodeRigid(nodeNumber=ws.node)),
                                 loadVector=[0.0, 0.0, 3000.0]))
    contact = C.add_wheel_rail_contact(mbs, [ws.node], pair, speed_m_s=speed, creep_law="fastsim",
                                       fastsim_grid=(16, 8))
    snapshots = {}
    probe = (1.0, 2100 * pair.r0_m / speed)

    def pre(mbs, t):
        for tp in probe:
            if abs(t - tp) < 0.5e-3 and tp not in snapshots:
                snapshots[tp] = (contact.evaluate(mbs, t).copy(),
                                 mbs.GetNodeOutput(ws.node, exu.OutputVariableType.AngularVelocity).copy(),
                                 np.array(mbs.GetNodeOutput(ws.node, exu.OutputVariableType.Coordinates)))
        return True

    mbs.SetPreStepUserFunction(pre)
    mbs.Assemble()
    _solve(mbs, probe[1] + 0.01, 1e-3)
    (r1, w1, q1), (r2, w2, q2) = snapshots[probe[0]], snapshots[probe[1]]
    assert abs(w2[1]) * probe[1] > 2000                      # the spin angle travelled
    assert np.all(np.isfinite(q2)) and np.linalg.norm(q2[3:]) < 2 * math.pi + 1e-9   # bounded rotation vector
    tread = (slice(None), 0)
    for field, tol in ((C.RES_N, 1e-3 * 5e4), (C.RES_FY, 1.0), (C.RES_FX, 1.0)):
        np.testing.assert_allclose(r2[tread][:, field], r1[tread][:, field], atol=tol)
    np.testing.assert_allclose(r2[tread][:, C.RES_ETA], r1[tread][:, C.RES_ETA], atol=1e-7)
    assert np.max(np.abs(r1[tread][:, C.RES_FY])) > 100.0      # the test has steady creep forces to compare


def test_separation_gives_no_force_and_recontact_is_found():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=20.0)
    pair = _pair()
    dz = C.place_on_rails(mbs, model, pair)
    ws = model.wheelsets[0]
    q0 = np.array(mbs.GetNodeParameter(ws.node, "initialCoordinates"))
    q0[2] -= 1e-3                                       # lifted 1 mm above its equilibrium
    mbs.SetNodeParameter(ws.node, "initialCoordinates", q0.tolist())
    contact = C.add_wheel_rail_contact(mbs, [ws.node], pair, speed_m_s=20.0)
    rec = []
    mbs.SetPreStepUserFunction(lambda mbs, t: rec.append(
        (t, contact.evaluate(mbs, t)[:, :, C.RES_N].sum(),
         mbs.GetNodeOutput(ws.node, exu.OutputVariableType.Position)[2])) or True)
    mbs.Assemble()
    _solve(mbs, 0.1, 2e-4)
    t, N, z = np.array(rec).T
    lifted = z < -0.46 + dz - 1.5e-4                    # clearly above the unloaded touching height
    assert lifted[:5].all() and np.all(N[lifted] == 0.0)  # lifted: Hertz assigns 0.0
    assert N.max() > 5e4                                 # it lands


def test_generalized_forces_match_the_contact_forces():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=30.0)
    pair = _pair()
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=30.0)
    q = np.array([0.0, 2e-3, 4e-4, 0.0, 0.7, 0.0])
    v = np.array([0.1, 0.05, 0.0, 0.0, -30 / 0.46, 0.01])
    f = contact.forces(q, v, 0.0).copy()
    r = contact.results
    F = r[:, :, C.RES_F_TRACK_X:C.RES_F_TRACK_Z + 1].reshape(-1, 3)
    P = r[:, :, C.RES_P_X:C.RES_P_Z + 1].reshape(-1, 3)
    np.testing.assert_allclose(f[:3], F.sum(axis=0), rtol=1e-12)
    # torque: Σ (p - c) × F + spin moments; f[3:] is it in the body frame
    Rm = np.empty((3, 3))
    C.rotation_from_vector(*q[3:], Rm)
    c = np.array([0.0, 0.0, -0.46]) + q[:3]
    tau_forces = np.cross(P - c, F).sum(axis=0)
    tau = Rm @ f[3:]
    Mz = r[:, :, C.RES_MZ].reshape(-1)
    assert np.linalg.norm(tau - tau_forces) <= np.abs(Mz).sum() + 1e-9
    assert (r[:, :, C.RES_STATUS] > 0).sum() >= 2


def test_rotation_vector_round_trip():
    rng = np.random.default_rng(3)
    R = np.empty((3, 3))
    v = np.empty(3)
    for _ in range(50):
        w = rng.normal(size=3)
        w *= rng.uniform(0, math.pi - 1e-3) / np.linalg.norm(w)
        C.rotation_from_vector(*w, R)
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
        C._rotation_vector_from_matrix(R, v, 0)
        np.testing.assert_allclose(v, w, atol=1e-9)


def _contact_samples(seed, n=20):
    """Random ellipses and creepages ``(a, b, ξ, η, φ)`` of a loaded wheel (partial slip to saturation)."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        a, b = rng.uniform(2e-3, 8e-3, 2)
        xi, eta = rng.normal(scale=5e-4, size=2)
        yield a, b, xi, eta, rng.normal(scale=0.5)


@pytest.mark.parametrize("law", ["linear", "fastsim", "shen_hedrick_elkins", "polach"])
def test_creep_law_dispatch_matches_the_creep_modules(law):
    from exudyn_wheelrail import creep
    from exudyn_wheelrail.creep import linear

    funcs = {"fastsim": lambda *a: creep.fastsim(*a, n_x=16, n_y=8), "shen_hedrick_elkins": creep.shen_hedrick_elkins,
             "polach": creep.polach,
             "linear": lambda a, b, xi, eta, phi, N, mu, G, nu: creep.linear_creep_forces(a, b, xi, eta, phi, G, nu)}
    cp = np.zeros(C.N_CP)
    cp[[C.CP_MU, C.CP_G, C.CP_NU, C.CP_NX, C.CP_NY, C.CP_AB_MIN, C.CP_AB_MAX]] = [0.3, 8.1e10, 0.28, 16, 8, 0.1, 10]
    tab = (np.zeros(2), np.zeros(2, np.int8), np.zeros(3), np.zeros(3), np.zeros(3), np.zeros((2, 3, 3, 3, 3)))
    for a, b, xi, eta, phi in _contact_samples(11):
        got = C._creep(C.CREEP_LAWS[law], a, b, xi, eta, phi, 4e4, cp, linear._T_NODES, linear._COEF, tab)
        want = funcs[law](a, b, xi, eta, phi, 4e4, 0.3, 8.1e10, 0.28)
        np.testing.assert_allclose(got[:3], want, rtol=1e-9, atol=1e-9)
        assert got[3] == 0
    # outside Table E.3's a/b range: evaluated at the limit with the same area, flagged
    got = C._creep(C.CREEP_LAWS[law], 0.02, 1e-3, 1e-4, 0.0, 0.0, 4e4, cp, linear._T_NODES, linear._COEF, tab)
    c = math.sqrt(0.02 * 1e-3)
    want = funcs[law](c * math.sqrt(10), c / math.sqrt(10), 1e-4, 0.0, 0.0, 4e4, 0.3, 8.1e10, 0.28)
    np.testing.assert_allclose(got[:2], want[:2], rtol=1e-9)
    assert got[3] == C.CREEP_AB_CLAMPED


@pytest.mark.parametrize("law, interpolation", [("table", "cubic"), ("table_linear", "linear")])
def test_table_laws_dispatch_to_the_table_lookup_of_their_interpolation(law, interpolation):
    from exudyn_wheelrail.creep import linear, load_table, table_forces

    cp = np.zeros(C.N_CP)
    cp[[C.CP_MU, C.CP_G, C.CP_NU, C.CP_NX, C.CP_NY, C.CP_AB_MIN, C.CP_AB_MAX]] = [0.3, 8.1e10, 0.28, 16, 8, 0.05, 20]
    t = load_table()
    tab = tuple(np.ascontiguousarray(x) for x in t.core_arrays())
    for a, b, xi, eta, phi in _contact_samples(12):
        got = C._creep(C.CREEP_LAWS[law], a, b, xi, eta, phi, 4e4, cp, linear._T_NODES, linear._COEF, tab)
        want = table_forces(a, b, xi, eta, phi, 4e4, 0.3, 8.1e10, 0.28, table=t, interpolation=interpolation)
        np.testing.assert_allclose(got[:3], want, rtol=1e-9, atol=1e-9 * 0.3 * 4e4)


def test_non_finite_state_raises_a_clear_error():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=30.0)
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, _pair(), speed_m_s=30.0)
    q = np.zeros(6)
    q[1] = np.nan
    with pytest.raises(C.ContactStateError, match="wheelset 0") as info:
        contact.forces(q, np.zeros(6), 1.5)
    assert info.value.wheelset == 0 and info.value.time_s == 1.5


def test_bad_options_raise():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=30.0)
    with pytest.raises(ValueError, match="creep_law"):
        C.add_wheel_rail_contact(mbs, model.wheelset_nodes, _pair(), speed_m_s=30.0, creep_law="magic")
    with pytest.raises(ValueError, match="speed"):
        C.add_wheel_rail_contact(mbs, model.wheelset_nodes, _pair(), speed_m_s=-1.0)


def test_example_with_a_users_own_exudyn_model():
    import importlib.util
    path = Path(__file__).resolve().parents[1] / "examples" / "own_exudyn_model.py"
    spec = importlib.util.spec_from_file_location("own_exudyn_model", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    t, y, q_sum, contact = mod.main(["--time", "0.6"])
    assert abs(y[0] - 0.003) < 1e-9 and abs(y[-1]) < 0.5e-3        # pulled back towards the centre
    # no vertical damping in the sketch: the loads oscillate about the weight; their time average is the weight
    late = t > 0.3
    assert np.mean(q_sum[late]) == pytest.approx(2 * (45e3 + 1813.0 * 9.81 / 2), rel=0.02)


def test_structured_jacobian_equals_column_by_column_differences():
    """The Jacobian user function perturbs the same coordinate of all wheelsets at once (block-diagonal structure):
    its columns equal one-coordinate-at-a-time forward differences of the force function."""
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=30.0)
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, _pair(), speed_m_s=30.0)
    q = np.zeros(24)
    v = np.zeros(24)
    for k in range(4):
        q[6 * k + 1], q[6 * k + 2] = 1e-3 * (k - 1.5), 2.5e-4
        v[6 * k + 1], v[6 * k + 4] = 0.01, -30 / 0.46 * (1 + 1e-4 * k)
    contact.jacobian_method = "forward_difference"         # the structured differences (not the default)
    J = contact._jacobian_uf(mbs, 0.0, 0, q, v, 1.0, 0.5).copy()
    f0 = contact.forces(q, v, 0.0).copy()
    state = contact.save_warm_start()
    for j in (1, 2, 7, 13, 19, 20):
        qp, vp = q.copy(), v.copy()
        qp[j] += 1e-7
        vp[j] += 1e-5
        contact.restore_warm_start(state)
        dq = (contact.forces(qp, v, 0.0) - f0) / 1e-7
        contact.restore_warm_start(state)
        dv = (contact.forces(q, vp, 0.0) - f0) / 1e-5
        contact.restore_warm_start(state)
        ref = -(dq + 0.5 * dv)
        np.testing.assert_allclose(J[:, j], ref, atol=1e-6 * np.abs(ref).max())



def test_connector_creep_forces_never_exceed_coulomb():
    """Found by the stress tests: near full sliding the table's cubic interpolation gave 1.002 μN and FASTSIM
    1.0006 μN; the connector holds every law's resultant on the friction bound."""
    from exudyn_wheelrail.creep import linear, load_table

    cp = np.zeros(C.N_CP)
    cp[[C.CP_MU, C.CP_G, C.CP_NU, C.CP_NX, C.CP_NY, C.CP_AB_MIN, C.CP_AB_MAX]] = [0.3, 8.1e10, 0.28, 16, 8, 0.05, 20]
    t = load_table()
    tab = tuple(np.ascontiguousarray(x) for x in t.core_arrays())
    a, b = 6.554e-3, 2.674e-3
    for law in ("table", "table_linear", "fastsim", "shen_hedrick_elkins", "polach"):
        for xi, eta, phi in [(6.19e-4, 4.17e-3, 0.1445), (5e-3, 5e-3, 0.0), (2e-3, -1e-2, -3.0), (0.05, 0.0, 0.0)]:
            Fx, Fy, Mz, _ = C._creep(C.CREEP_LAWS[law], a, b, xi, eta, phi, 5e4, cp, linear._T_NODES,
                                     linear._COEF, tab)
            assert np.hypot(Fx, Fy) <= 0.3 * 5e4 * (1 + 1e-12), law
