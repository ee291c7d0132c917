"""The contact's semi-analytic stiffness and damping (exudyn_wheelrail.multibody.contact_jacobian) at states of a
recorded RTRI run (20 m, 250 km/h, 12 mm deviation: tread, two-zone tread and flange contact; a lifted wheel made
from a recorded state) and of a vehicle on a bridge deck:

* the exact parts against central differences of the same compiled call: the penetration's gradient (the
  envelope theorem the Hertz block rests on), the Hertz block's assembly in Exudyn's coordinates, the creep
  damping with the linear creep law;
* the approximate parts against what they promise: the creep law's tangent is Kalker's linear theory at small
  creepage; a state is differenced exactly where a normal turns fast; the omitted terms (turn of the normal,
  contact-point migration, creepages' pose dependence) keep Newton's linear contraction small at h = 1 ms, with
  and without the bridge coupling;
* implicit runs with the new and the old (forward-difference) Jacobian converge to the same solution, and the new
  one costs fewer contact calls (counts, not times).
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact import layout as L
from exudyn_wheelrail.creep import linear as creep_linear
from exudyn_wheelrail.creep.registry import CREEP_LAWS
from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.multibody import contact_jacobian as CJ
from exudyn_wheelrail.multibody.core_data import W_WHEELSET, WS_COS_TH, WS_SIN_TH
from exudyn_wheelrail.scenarios.rtri import RtriCase
from exudyn_wheelrail.scenarios.scenario import build_scenario

#: the RTRI case with a flange impact (the 12 mm deviation), Newmark 1 ms; 0.40 s holds the first flange contacts
CASE = dict(span_m=20.0, speed_km_h=250.0, deviation_amplitude_m=12e-3, solver="newmark", dt_s=1e-3, record=False)
T_RECORD_S = 0.40
#: central-difference steps: displacement [m], body rotation [rad], velocity [m/s], angular velocity [rad/s]
H_POS = 1e-6
H_VEL = 1e-5
#: Newmark β, γ and the step of Newton's iteration matrix M + β h² K + γ h C (the connector's factors)
BETA, GAMMA, H_STEP = 0.25, 0.5, 1e-3


def _build(creep_law="table", duration_s=T_RECORD_S, **run):
    case = RtriCase(**{**CASE, **run}, duration_s=duration_s, creep_law=creep_law)
    h = build_scenario(case.scenario())
    h.contact.warm_up(h.mbs)
    return h


def _record(h):
    """(t, q, v) of every state of a Newmark solve of the built case (the state's own time)."""
    c = h.contact
    states = []
    t_state = [0.0]

    def pre_step(mbs, t):
        q, v = c.coordinates(mbs)
        states.append((t_state[0], q, v))
        t_state[0] = float(t)
        return True

    h.mbs.SetPreStepUserFunction(pre_step)
    assert h.mbs.SolveDynamic(h.settings, solverType=h.solver_type)
    return states


def _kind(res, out):
    on = (res[..., C.RES_STATUS] > 0) & (res[..., C.RES_N] > 0.0)
    if on[:, 1].any():
        return "flange"
    if on[:, 2].any():
        return "two_zone"
    if (~on.any(axis=1)).any():
        return "lifted"
    return "tread"


@pytest.fixture(scope="module")
def rtri_states():
    """Model (table creep law) and one recorded state per kind: ``{kind: (t, q, v, warm)}``; a lifted wheel made
    from the tread state (wheelset 1 raised 0.1 mm and rolled by 0.5 mrad: its left wheel leaves the rail)."""
    h = _build()
    states = _record(h)
    c = h.contact
    picked = {}
    for t, q, v in states[50:]:
        c.forces(q, v, t)
        kind = _kind(c.results, c.kernel_output())
        if kind not in picked:
            picked[kind] = (t, q.copy(), v.copy(), c.save_warm_start())
    assert {"tread", "two_zone", "flange"} <= set(picked), sorted(picked)
    t, q, v, warm = picked["tread"]
    q = q.copy()
    q[2] -= 1e-4
    R = Rotation.from_rotvec(q[3:6]).as_matrix()
    q[3:6] = Rotation.from_matrix(Rotation.from_rotvec([5e-4, 0.0, 0.0]).as_matrix() @ R).as_rotvec()
    c.restore_warm_start(warm)
    c.forces(q, v, t)
    on = (c.results[..., C.RES_STATUS] > 0) & (c.results[..., C.RES_N] > 0.0)
    assert not on[1].any() and on[0].any()                 # the lifted wheel and its loaded partner
    picked["lifted"] = (t, q, v, warm)
    return h, picked


@pytest.fixture(scope="module")
def deck_state():
    """A vehicle on a bridge deck (two wheelsets on a deflected, moving deck: tests/test_bridge_coupling.py)."""
    from test_bridge_coupling import _vehicle_on_deck
    mbs, contact, modes, q, v = _vehicle_on_deck(deck_start_m=0.0, s_start_m=8.0)
    contact.forces(q, v, 0.0)
    assert contact.results[::2, 0, C.RES_ON_DECK].tolist() == [1.0, 1.0, 0.0, 0.0]  # 0/1 flags: exact
    contact.modes = modes                                  # for the coupled test below
    return mbs, contact, (0.0, q, v, contact.save_warm_start())


def _rotated(q, k, i, h):
    """q with wheelset k turned by the body-frame increment h e_i (R' = R exp(h e_i), the Lie-group update)."""
    qp = q.copy()
    R = Rotation.from_rotvec(q[6 * k + 3:6 * k + 6]).as_matrix()
    qp[6 * k + 3:6 * k + 6] = Rotation.from_matrix(R @ Rotation.from_rotvec(h * np.eye(3)[i]).as_matrix()).as_rotvec()
    return qp


def _perturbed(q, k, j, h):
    if j < 3:
        qp = q.copy()
        qp[6 * k + j] += h
        return qp
    return _rotated(q, k, j - 3, h)


def _central(contact, state, what, k, j, velocity=False):
    """Central difference of ``what(contact)`` in wheelset k's coordinate j (position or velocity), every evaluation
    from the state's warm start."""
    t, q, v, warm = state
    vals = []
    for s in (1.0, -1.0):
        contact.restore_warm_start(warm)
        if velocity:
            vp = v.copy()
            vp[6 * k + j] += s * H_VEL
            contact.forces(q, vp, t)
        else:
            contact.forces(_perturbed(q, k, j, s * H_POS), v, t)
        vals.append(np.array(what(contact), dtype=float))
    return (vals[0] - vals[1]) / (2.0 * (H_VEL if velocity else H_POS))


def _semi_analytic(contact, state, f_odeq, f_odev):
    """The module's semi-analytic Jacobian at the state (one contact call from the state's warm start), whatever
    its contacts (the connector itself falls back on differences for a fast-turning normal)."""
    t, q, v, warm = state
    contact.restore_warm_start(warm)
    contact.forces(q, v, t)
    n = q.size
    J = np.zeros((n, n))
    shape = (len(contact.nodes_exu), CJ.N_BLOCK, CJ.N_BLOCK)
    CJ.semi_analytic_jacobian(q, v, contact._data, contact._f, contact.results, f_odeq, f_odev, J, np.zeros(shape),
                              np.zeros(shape))
    return J


def _all_states(rtri_states, deck_state):
    h, picked = rtri_states
    out = [(name, h.mbs, h.contact, st) for name, st in picked.items()]
    mbs, contact, st = deck_state
    out.append(("deck", mbs, contact, st))
    return out


# ---------------------------------------------------------------------------------------------- exact parts
def test_penetration_gradient_is_the_envelope_theorem(rtri_states, deck_state):
    """dδ = -n·du - (r × n)·dθ for every convex contact (the contact point is a stationary point of the
    penetration): against central differences of the kernel's penetration.  Tolerance: the difference's truncation
    h²/6 δ''' with δ''' ~ κ² ≤ (1/10 mm)² gives 2e-10 at h = 1e-6 m; the penetration is located by Newton to
    ~1e-15 m, 5e-10 over 2h: 1e-7 (per unit displacement, per radian times the ~0.8 m lever) leaves a wide margin
    and still catches a wrong lever arm or sign (terms of 0.01 … 0.8)."""
    checked = 0
    for name, _, contact, state in _all_states(rtri_states, deck_state):
        t, q, v, warm = state
        contact.restore_warm_start(warm)
        contact.forces(q, v, t)
        res = contact.results.copy()
        out = contact.kernel_output().copy()
        wsd = contact._work[W_WHEELSET]
        for w in range(res.shape[0]):
            k, side = divmod(w, 2)
            R = Rotation.from_rotvec(q[6 * k + 3:6 * k + 6]).as_matrix()
            p_c = contact.p_ref[k] + q[6 * k:6 * k + 3]
            for reg in range(res.shape[1]):
                if res[w, reg, C.RES_STATUS] != K.STATUS_CONVEX or not res[w, reg, C.RES_N] > 0.0:
                    continue
                mirror = 1.0 if side == 0 else -1.0
                c_th, s_th = wsd[k, WS_COS_TH], wsd[k, WS_SIN_TH]       # the rail pair's roll
                ny_l, nz_l = mirror * out[w, reg, L.F_NR_Y], out[w, reg, L.F_NR_Z]
                n = np.array([0.0, c_th * ny_l - s_th * nz_l, s_th * ny_l + c_th * nz_l])
                r = res[w, reg, C.RES_P_X:C.RES_P_Z + 1] - p_c
                expected = np.concatenate([-n, -R.T @ np.cross(r, n)])     # body-frame rotation columns
                for j in range(6):
                    d = _central(contact, state, lambda c: c.results[w, reg, C.RES_DELTA], k, j)
                    # x also moves the wheel along the track: the rails' slope there (the deviation's, at most
                    # π δ/L = 1.9 mrad; the deck's deflection, ~1e-4 here) turns into penetration through the
                    # normal; not differentiated (module docstring)
                    slope = 2e-3 if j == 0 else 0.0
                    # the kernel's penetration is that of the wheelset's cross-section, the point then led by the
                    # yaw: its rotation gradients are those of the point at x = 0, the 3-D lever differs by r_x
                    lead = 2.0 * abs(r[0]) if j >= 3 else 0.0
                    assert d == pytest.approx(expected[j], abs=1e-7 + slope + lead), (name, w, reg, j)
                checked += 1
    assert checked >= 8


def _normal_only_model(rtri_states):
    """The same recorded states in a model with creep law "none" (normal forces only)."""
    h = _build(creep_law="none", duration_s=1e-3)
    return h


def test_hertz_block_assembly_against_the_penetration_differences(rtri_states):
    """With normal forces only (creep law "none"), the Jacobian's position block is, per contact, ``dN/dδ`` times
    the penetration's change, applied as force along the normal and its moment, torque in the body frame (plus the
    body frame's own turn ``[τ_b]×``), and for two blended maxima of one zone the kernel's weights' change: built
    here from central differences of each slot's penetration and the kernel's ``dN/dδ``, Hertz's 1.5 N/δ (exact:
    the curvatures are those at the point), independently of the module's code.  Tolerance: per entry the
    penetration gradient's tolerance of the test above times dN/dδ and the row's lever."""
    h_none = _normal_only_model(rtri_states)
    c = h_none.contact
    _, picked = rtri_states
    checked = 0
    for name in ("tread", "flange", "lifted"):
        t, q, v, _ = picked[name]
        c.forces(q, v, t)
        for _ in range(3):                                 # the search's own warm start for this state
            c.forces(q, v, t)
        warm = c.save_warm_start()
        state = (t, q, v, warm)
        J = _semi_analytic(c, state, 1.0, 0.0)
        f0 = c._f.copy()
        res = c.results.copy()
        out = c.kernel_output().copy()
        n_ws = len(c.nodes_exu)
        for k in range(n_ws):
            R = Rotation.from_rotvec(q[6 * k + 3:6 * k + 6]).as_matrix()
            p_c = c.p_ref[k] + q[6 * k:6 * k + 3]
            slots = [(w, s) for w in (2 * k, 2 * k + 1) for s in range(3) if res[w, s, C.RES_STATUS] > 0]
            if any(int(out[w, s, L.F_FLAGS]) & K.FLAG_BLENDED for w, s in slots):
                continue                                   # blended pairs: their own test below
            if any(res[w, s, C.RES_STATUS] != K.STATUS_CONVEX for w, s in slots):
                continue                                   # a concave-search point: not located to 1e-7 (above)
            expected = np.zeros((6, 6))
            tol = np.zeros((6, 6))
            for w in (2 * k, 2 * k + 1):
                for reg in range(res.shape[1]):
                    if res[w, reg, C.RES_STATUS] <= 0 or not res[w, reg, C.RES_N] > 0.0:
                        continue
                    N, delta = res[w, reg, C.RES_N], res[w, reg, C.RES_DELTA]
                    dN = out[w, reg, L.F_DN_DDELTA]
                    assert dN == pytest.approx(1.5 * N / delta, rel=1e-9)      # Hertz: N = K δ^1.5
                    F = np.array([res[w, reg, C.RES_F_TRACK_X], res[w, reg, C.RES_F_TRACK_Y],
                                  res[w, reg, C.RES_F_TRACK_Z]])
                    n = F / N                                                 # normal forces only: F = N n
                    r = res[w, reg, C.RES_P_X:C.RES_P_Z + 1] - p_c
                    grad = np.array([_central(c, state, lambda cc: cc.results[w, reg, C.RES_DELTA], k, j)
                                     for j in range(6)])
                    row = np.concatenate([n, R.T @ np.cross(r, n)])
                    expected += dN * np.outer(row, grad)
                    # the gradient's tolerance of the test above: differences, the rails' slope in x, the yaw lead
                    tol += dN * np.outer(np.abs(row), [1e-7 + 2e-3] + [1e-7] * 2 + [1e-7 + 2 * abs(r[0])] * 3)
            tb = f0[6 * k + 3:6 * k + 6]
            expected[3:, 3:] += np.array([[0, -tb[2], tb[1]], [tb[2], 0, -tb[0]], [-tb[1], tb[0], 0]])
            got = -J[6 * k:6 * k + 6, 6 * k:6 * k + 6]
            assert np.all(np.abs(got - expected) <= tol + 1e-9 * np.abs(expected).max()), (name, k, got - expected)
            checked += 1
    assert checked >= 6


def test_blended_maxima_normal_forces_follow_the_weights(rtri_states):
    """Two blended penetration maxima of one zone (kernel FLAG_BLENDED: N_1 = (1 - b) H_1(δ_1), N_2 = b H_2(δ_2)
    with the weight b a smoothstep of the depth difference): the module couples the two slots through b's change.
    Checked on the vertical column (creep law "none") against central differences of the wheelset's forces: a
    vertical motion moves the contact points along the profiles by about γ dz (γ ≤ 0.07 rad on the tread), so the
    curvature's change, not differentiated, stays below 1e-3 of the column (measured 2e-4); without the weights'
    change the vertical stiffness of the pair is off by the blend's derivative, N/(P δ) ~ 10 N/δ against Hertz's
    1.5 N/δ."""
    h_none = _normal_only_model(rtri_states)
    c = h_none.contact
    _, picked = rtri_states
    t, q, v, _ = picked["two_zone"]
    for _ in range(4):
        c.forces(q, v, t)
    out = c.kernel_output()
    blended = [w for w in range(out.shape[0]) if int(out[w, 2, L.F_FLAGS]) & K.FLAG_BLENDED]
    assert blended, "no blended pair at the recorded two-zone state"
    warm = c.save_warm_start()
    state = (t, q, v, warm)
    J = _semi_analytic(c, state, 1.0, 0.0)
    for w in blended:
        k = w // 2
        cd = -_central(c, state, lambda cc: cc._f[6 * k:6 * k + 6].copy(), k, 2)
        got = J[6 * k:6 * k + 6, 6 * k + 2]
        np.testing.assert_allclose(got, cd, rtol=0, atol=1e-3 * np.abs(cd).max())


def test_creep_damping_with_the_linear_law_against_differences(rtri_states):
    """The velocity block (creep damping, exact for a linear creep law up to the rolling speed's own change, which
    moves a creepage by -ξ dV/V): against central differences of the forces in every velocity coordinate, with the
    linear law.  Tolerance per entry: Σ_c (|F_x|+|F_y|)(1+|r|)/V + |M_z|/V (the omitted ∂V terms, |∂V/∂v| ≤ 1,
    |∂V/∂ω| ≤ |r|) plus the differences' rounding, 1e-9 of the block."""
    h_lin = _build(creep_law="linear", duration_s=1e-3)
    c = h_lin.contact
    _, picked = rtri_states
    for name in ("tread", "flange", "two_zone"):
        t, q, v, _ = picked[name]
        for _ in range(4):
            c.forces(q, v, t)
        warm = c.save_warm_start()
        state = (t, q, v, warm)
        J = _semi_analytic(c, state, 0.0, 1.0)
        res = c.results.copy()
        for k in range(len(c.nodes_exu)):
            p_c = c.p_ref[k] + q[6 * k:6 * k + 3]
            bound = 0.0
            for w in (2 * k, 2 * k + 1):
                for reg in range(res.shape[1]):
                    if res[w, reg, C.RES_STATUS] > 0 and res[w, reg, C.RES_N] > 0.0:
                        r = np.linalg.norm(res[w, reg, C.RES_P_X:C.RES_P_Z + 1] - p_c)
                        V = max(res[w, reg, C.RES_V], 1e-3)
                        bound += ((abs(res[w, reg, C.RES_FX]) + abs(res[w, reg, C.RES_FY])) * (1 + r)
                                  + abs(res[w, reg, C.RES_MZ])) / V
            cd = np.column_stack([-_central(c, state, lambda cc: cc._f[6 * k:6 * k + 6].copy(), k, j, velocity=True)
                                  for j in range(6)])
            got = J[6 * k:6 * k + 6, 6 * k:6 * k + 6]
            np.testing.assert_allclose(got, cd, rtol=0, atol=bound + 1e-9 * np.abs(cd).max(),
                                       err_msg=f"{name}, wheelset {k}")
            assert np.abs(cd).max() > 10 * bound               # the check has teeth: damping >> omitted terms


# ---------------------------------------------------------------------------------------------- approximate parts
def test_creep_tangent_is_kalkers_linear_theory_at_small_creepage():
    """The creep law's tangent (forward differences of the law, module docstring) at small creepage: for the
    linear law exactly Kalker's ``-G c² C11``, ``-G c² C22``, ``-G c³ C23``, ``G c³ C23`` (Table E.3; to the
    difference's rounding, 1e-6); for the table of the exact theory and FASTSIM their longitudinal and lateral
    slopes are C11, C22 to their documented small-creepage accuracy (5e-3: tests/test_creep_table.py; FASTSIM's
    flexibilities are calibrated on them), and every entry is the law's own slope: a central difference of the
    law with 10x the step, within 1e-3 of the block (truncation of a smooth law at creepage ~1e-6)."""
    from exudyn_wheelrail.creep.table import load_table
    cp = np.zeros(C.N_CP)
    G, nu, mu = 8.1e10, 0.28, 0.3
    cp[[C.CP_MU, C.CP_G, C.CP_NU, C.CP_NX, C.CP_NY, C.CP_AB_MIN, C.CP_AB_MAX, C.CP_V_MIN]] = \
        [mu, G, nu, 48, 16, 0.05, 20, 1e-3]
    tab = tuple(np.ascontiguousarray(x) for x in load_table().core_arrays())
    a, b, N = 6.5e-3, 4.0e-3, 5e4
    c11, c22, c23 = creep_linear.kalker_coefficients(a / b, nu)
    c = np.sqrt(a * b)
    kalker = {(0, 0): -G * c * c * c11, (1, 1): -G * c * c * c22, (1, 2): -G * c ** 3 * c23,
              (2, 1): G * c ** 3 * c23}
    point = np.array([1e-6, 1e-6, 1e-5])

    def law_forces(code, x):
        return np.array(C._creep(code, a, b, x[0], x[1], x[2], N, cp, creep_linear._T_NODES, creep_linear._COEF,
                                 tab)[:3])

    for law in ("linear", "table", "fastsim"):
        code = CREEP_LAWS[law]
        F = law_forces(code, point)
        D = np.zeros((3, 3))
        dFN = np.zeros(3)
        CJ.creep_tangent(code, a, b, *point, N, *F, cp, creep_linear._T_NODES, creep_linear._COEF, tab, D, dFN)
        checked = kalker if law == "linear" else {ij: kalker[ij] for ij in ((0, 0), (1, 1))}
        for (i, j), value in checked.items():
            assert D[i, j] == pytest.approx(value, rel=1e-6 if law == "linear" else 5e-3), (law, i, j)
        for j, h in enumerate((1e-6, 1e-6, 1e-4)):
            e = np.zeros(3)
            e[j] = h
            slope = (law_forces(code, point + e) - law_forces(code, point - e)) / (2 * h)
            np.testing.assert_allclose(D[:, j], slope, rtol=0, atol=1e-3 * np.abs(D).max(), err_msg=law)


def test_fast_turning_normals_fall_back_on_differences(rtri_states):
    """What the fallback promises (contact_jacobian.needs_differences): a state is differenced exactly where a
    contact's normal turns fast enough for the left-out stiffness N dγ/dy to matter against Hertz's dN/dδ —
    measured by central differences of the contact angle in the wheelset's lateral coordinate: above 1 % of
    dN/dδ at the flange state (the flange root: ~1e4 rad/m), below it at the tread and two-zone states."""
    h, picked = rtri_states
    c = h.contact
    for name in ("tread", "two_zone", "flange"):
        state = picked[name]
        t, q, v, warm = state
        c.restore_warm_start(warm)
        c.forces(q, v, t)
        res = c.results.copy()
        out = c.kernel_output().copy()
        ratio = 0.0
        for w in range(res.shape[0]):
            for reg in range(res.shape[1]):
                if res[w, reg, C.RES_STATUS] <= 0 or not res[w, reg, C.RES_N] > 0.0:
                    continue
                dgamma = _central(c, state, lambda cc: cc.results[w, reg, C.RES_GAMMA], w // 2, 1)
                ratio = max(ratio, res[w, reg, C.RES_N] * abs(dgamma) / out[w, reg, L.F_DN_DDELTA])
        assert CJ.needs_differences(res, out) == (name == "flange"), (name, ratio)
        assert (ratio > 0.01) == (name == "flange"), (name, ratio)


def test_newton_contraction_with_the_semi_analytic_jacobian(rtri_states, deck_state):
    """What the omitted terms promise: per wheelset, Newton's linear contraction with the semi-analytic Jacobian
    instead of the differenced one, ρ = max |eig((M + β h² K + γ h C)⁻¹ (β h² ΔK + γ h ΔC))| at h = 1 ms
    (M the wheelset's mass and inertias, K, C central differences), stays below 0.1: the first iteration reaches
    ~1e-3 of the initial residual (measured, benchmarks/bench_implicit.py), so ρ < 0.1 lets the second meet the
    tolerance 1e-4 as with the exact Jacobian."""
    h, _ = rtri_states
    ws = h.vehicle.wheelset
    M = np.diag([ws.mass_kg] * 3 + [ws.Ixx_kg_m2, ws.Iyy_kg_m2, ws.Izz_kg_m2])
    worst = 0.0
    for name, mbs, contact, state in _all_states(rtri_states, deck_state):
        t, q, v, warm = state
        contact.restore_warm_start(warm)
        Jq = contact._jacobian_uf(mbs, t, 0, q, v, 1.0, 0.0).copy()          # -∂f/∂q: the stiffness
        contact.restore_warm_start(warm)
        Jv = contact._jacobian_uf(mbs, t, 0, q, v, 0.0, 1.0).copy()          # -∂f/∂q̇: the damping
        for k in range(len(contact.nodes_exu)):
            s = slice(6 * k, 6 * k + 6)
            Kcd = np.column_stack([-_central(contact, state, lambda c: c._f[s].copy(), k, j) for j in range(6)])
            Ccd = np.column_stack([-_central(contact, state, lambda c: c._f[s].copy(), k, j, velocity=True)
                                   for j in range(6)])
            A = M + BETA * H_STEP ** 2 * Kcd + GAMMA * H_STEP * Ccd
            E = BETA * H_STEP ** 2 * (Kcd - Jq[s, s]) + GAMMA * H_STEP * (Ccd - Jv[s, s])
            rho = np.abs(np.linalg.eigvals(np.linalg.solve(A, E))).max()
            worst = max(worst, rho)
            assert rho < 0.1, (name, k, rho)
    print(f"largest contraction {worst:.3g}")
    assert worst > 0.0


def test_newton_contraction_with_the_bridge_coupling(rtri_states, deck_state):
    """The same promise for the coupled wheelset–deck system (two wheelsets on the deck, all modes): Newton's
    linear contraction with the semi-analytic Jacobian (wheelset blocks, the modal rows and columns through
    Φ(s), the modal block Σ Φᵀ ∂F_rail/∂u Φ) instead of column-by-column central differences, on the iteration
    matrix M + β h² (K_deck + K) + γ h (C_deck + C) with the wheelsets' mass and inertias and the mass-normalised
    modes (modal stiffness ω², damping 2 ζ ω), stays below 0.1 (as above)."""
    h, _ = rtri_states
    ws = h.vehicle.wheelset
    mbs, contact, state = deck_state
    modes = contact.modes
    t, q, v, warm = state
    n = q.size
    contact.restore_warm_start(warm)
    Jq = contact._jacobian_uf(mbs, t, 0, q, v, 1.0, 0.0).copy()
    contact.restore_warm_start(warm)
    Jv = contact._jacobian_uf(mbs, t, 0, q, v, 0.0, 1.0).copy()
    Kcd = np.zeros((n, n))
    Ccd = np.zeros((n, n))

    def f(qq, vv):
        contact.restore_warm_start(warm)
        return contact.forces(qq, vv, t).copy()

    for j in range(n):
        if j < 24:
            k, i = divmod(j, 6)
            Kcd[:, j] = -(f(_perturbed(q, k, i, H_POS), v) - f(_perturbed(q, k, i, -H_POS), v)) / (2 * H_POS)
        else:
            e = np.zeros(n)
            e[j] = 1e-4                                     # mass-normalised coordinate: rails move ~1e-7 m
            Kcd[:, j] = -(f(q + e, v) - f(q - e, v)) / 2e-4
        e = np.zeros(n)
        e[j] = H_VEL if j < 24 else 1e-2
        Ccd[:, j] = -(f(q, v + e) - f(q, v - e)) / (2 * e[j])
    M = np.diag([ws.mass_kg] * 3 + [ws.Ixx_kg_m2, ws.Iyy_kg_m2, ws.Izz_kg_m2])
    mass = np.zeros((n, n))
    k_s = np.zeros((n, n))
    c_s = np.zeros((n, n))
    for k in range(4):
        mass[6 * k:6 * k + 6, 6 * k:6 * k + 6] = M
    mass[24:, 24:] = modes.modal_mass()
    k_s[24:, 24:] = modes.modal_stiffness()
    c_s[24:, 24:] = modes.modal_damping()
    A = mass + BETA * H_STEP ** 2 * (k_s + Kcd) + GAMMA * H_STEP * (c_s + Ccd)
    E = BETA * H_STEP ** 2 * (Kcd - Jq) + GAMMA * H_STEP * (Ccd - Jv)
    rho = np.abs(np.linalg.eigvals(np.linalg.solve(A, E))).max()
    print(f"coupled contraction {rho:.3g}")
    assert rho < 0.1, rho
    assert np.abs(Jq[24:, 24:]).max() > 0.0 and np.abs(Jq[:24, 24:]).max() > 0.0     # the coupling is there


# ---------------------------------------------------------------------------------------------- runs
#: the largest initial Newton residual of a step in these runs [N] (Exudyn's verbose output: 0.5 … 1.3e5 N)
R0_MAX_N = 1.5e5


def _run(method, tol, per_step, duration_s=0.35):
    """Newmark over the first ``duration_s`` of the case: the lateral force of wheelset 1's right wheel per state,
    and per step the Newton iterations and the contact calls of the Jacobian."""
    h = _build(duration_s=duration_s, newton_tolerance=tol)
    h.settings.timeIntegration.newton.modifiedNewtonJacUpdatePerStep = per_step
    c = h.contact
    c.jacobian_method = method
    c.n_jacobian_calls = c.n_jacobian_contact_calls = c.n_jacobian_differenced = 0
    states = _record(h)
    it = h.mbs.sys["dynamicSolver"].it
    steps = len(states)
    y = []
    for t, q, v in states[1:]:
        c.forces(q, v, t)
        y.append(c.wheel_force_N(0, "right")[1])
    return dict(y=np.array(y), steps=steps, newton=it.newtonStepsCount / steps, jac=c.n_jacobian_calls / steps,
                jac_calls=c.n_jacobian_contact_calls / steps, differenced=c.n_jacobian_differenced)


def test_implicit_run_converges_to_the_same_solution_and_costs_fewer_calls():
    """Newmark over the first 0.35 s of the case (the deviation and the first flange contact) with the pipeline's
    Newton (solver_settings: modified Newton, the Jacobian kept across steps) and the connector's semi-analytic
    Jacobian, against the same with the old forward-difference Jacobian, and the semi-analytic one updated every
    step.  Every run stops when the residual is below the tolerance times the step's initial residual
    (≤ R0_MAX_N): each step's state is then off the exact discrete solution by at most that residual over the
    iteration matrix, which moves the contact force by at most the residual itself; over n steps two runs differ
    by at most 2 n tol R0_MAX_N (at 1e-6: 105 N, 1.3e-3 of the 82 kN peak; measured 1e-5 of it).  At the
    production tolerance (1e-4) the peak of each is within 1e-3 of the 1e-6 solution's (the tolerance's measured
    effect on the RTRI peaks is 1e-6 … 1e-4, simulation/settings.py).  Counts (deterministic, not times): one
    contact call per semi-analytic Jacobian, 15 where the flange contact's fast-turning normal sends it to the
    differences; fewer Jacobian contact calls than the differences; updated every step, the semi-analytic
    Jacobian needs at most 2.5 iterations per step (the first reaches ~1e-3 of the initial residual, the second
    ~1e-7 where the Jacobian is exact)."""
    runs = {(m, tol): _run(m, tol, False) for tol in (1e-6, 1e-4) for m in ("semi_analytic", "forward_difference")}
    runs[("per_step", 1e-4)] = _run("semi_analytic", 1e-4, True)
    new, old = runs[("semi_analytic", 1e-6)], runs[("forward_difference", 1e-6)]
    assert new["steps"] == old["steps"] == 350                       # no step rejected
    peak = np.abs(old["y"]).max()
    assert peak > 1e3
    np.testing.assert_allclose(new["y"], old["y"], rtol=0, atol=2 * new["steps"] * 1e-6 * R0_MAX_N)
    for key, r in runs.items():
        assert abs(np.abs(r["y"]).max() - peak) <= 1e-3 * peak, key
    for key in (("semi_analytic", 1e-6), ("semi_analytic", 1e-4), ("per_step", 1e-4)):
        r = runs[key]
        assert r["jac_calls"] * r["steps"] == pytest.approx(r["jac"] * r["steps"] + 14 * r["differenced"]), key
    new, old = runs[("semi_analytic", 1e-4)], runs[("forward_difference", 1e-4)]
    assert new["jac"] > 0 and new["jac_calls"] < old["jac_calls"]
    per_step = runs[("per_step", 1e-4)]
    assert per_step["jac"] == pytest.approx(1.0, abs=0.01) and 0 < per_step["differenced"] < 0.2 * per_step["steps"]
    assert per_step["newton"] <= 2.5
