"""The compiled per-state work of watching a run, against independent references (no solve, synthetic arrays):

* the stability estimate's largest eigenvalue (Jacobi) against LAPACK (``numpy.linalg.eigvalsh``): the eigenvalue
  of a symmetric matrix moves by at most ||E||_2 for a perturbation E, so both agree to a few ε ||B||;
* the per-wheel quantities of a state (normal force, Y, Q, penetration, contact angle, gap, the derailment
  geometry) against a NumPy evaluation of their definitions (the monitor's docstring), on random result arrays
  with lifted wheels, flange contacts and NaNs: selections and copies give the same numbers, the three-slot sums
  agree to 2 ε times the sum of the magnitudes (the two summation orders);
* the hunting detection on a sampled sine of known frequency: detected at the sixth sign change (3 cycles) with the
  sine's frequency (crossing times on the sample grid: error below one step over five half-periods), never for an
  amplitude below the limit;
* the 2 m Y/Q window of the flange-climb check (O(1) running sums in a ring) against the quotient of sums over the
  states of the last 2 m recomputed for every state, with lifted wheels, a ring that wraps around and then has to
  grow (the step falls from 1.6 to 0.2 ms);
* the recorder's wheel columns against the connector's own per-wheel methods (``wheel_force_N``,
  ``flange_contact``): a three-term sum agrees to 2 ε times the sum of the magnitudes.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact import layout as L
from exudyn_wheelrail.simulation import monitor_core as MC
from exudyn_wheelrail.multibody.connector import WheelRailContact
from exudyn_wheelrail.simulation.guidance import FlangeClimbCheck
from exudyn_wheelrail.simulation.recorder import wheel_columns

EPS = np.finfo(float).eps


# ------------------------------------------------------------------------------------------------- eigenvalue
def test_largest_eigenvalue_agrees_with_lapack():
    rng = np.random.default_rng(7)
    work = np.zeros((6, 6))
    for trial in range(400):
        n = 1 + trial % 6
        rows = rng.integers(1, 7)
        G = rng.standard_normal((n, rows)) * 10.0 ** rng.uniform(-3, 3, (n, 1))   # rank <= rows, scaled rows
        B = G @ G.T
        lam = MC.largest_eigenvalue_psd(B, n, work)
        ref = np.linalg.eigvalsh(B)[-1]
        assert abs(lam - ref) <= 20 * n * EPS * np.linalg.norm(B, 2)
    assert MC.largest_eigenvalue_psd(np.zeros((3, 3)), 3, work) == 0.0  # zero matrix: exactly 0


def test_the_stability_bound_skips_only_states_below_the_running_maximum():
    # _omega_h skips the Jacobi iteration (returns -1) when Gershgorin's bound of A A^T puts omega h at or below
    # `below` (the running maximum): it may skip only a state whose exact value is no larger, and must return the
    # exact value (the same numbers as without a limit) otherwise
    rng = np.random.default_rng(11)
    n_ws, h = 1, 1e-3
    ws_par = np.zeros((n_ws, MC.N_WSP))
    work = np.zeros((MC.N_MW, 2 * L.N_SLOTS, 2 * L.N_SLOTS))
    phi_ws = np.zeros((n_ws, 3, 0))
    skipped = 0
    for trial in range(300):
        n_rows = 1 + trial % 4
        G = np.zeros((n_ws, 2 * L.N_SLOTS, MC.N_G))
        G[0, :n_rows, :6] = rng.standard_normal((n_rows, 6)) * 10.0 ** rng.uniform(3, 4.5)
        q = np.zeros(6)
        q[3:6] = rng.uniform(-0.05, 0.05, 3)
        root = rng.standard_normal((3, 3))
        ws_par[0, MC.WSP_INV_SQRT_MASS] = 1.0 / math.sqrt(rng.uniform(800.0, 2000.0))
        ws_par[0, MC.WSP_I_INV_SQRT:MC.WSP_I_INV_SQRT + 9] = (root @ root.T + np.eye(3)).ravel() * 0.1
        exact = MC._omega_h(0, n_rows, q, ws_par, G, phi_ws, h, work, -1.0)
        assert exact >= 0.0
        for below in exact * np.array([0.5, 0.999, 1.0, 1.001, 1.5, 4.0]):
            wh = MC._omega_h(0, n_rows, q, ws_par, G, phi_ws, h, work, below)
            if wh < 0.0:
                skipped += 1
                assert exact <= below
            else:
                assert wh == exact
    assert skipped > 300          # the bound is tight enough to skip (exact for one row, Gershgorin otherwise)


# ------------------------------------------------------------------------------------------ per-wheel quantities
def _par():
    """A flanged wheel on a rail with its crown 40 mm to the field side of the flange tip (side frame, metres)."""
    par = np.zeros(MC.N_PAR)
    par[MC.PAR_LIFT_FORCE] = 0.0
    par[MC.PAR_LARGE_LATERAL] = math.nan
    par[MC.PAR_PRUDHOMME_C0], par[MC.PAR_PRUDHOMME_C1], par[MC.PAR_PRUDHOMME_NONE] = 10e3, 1.0 / 3.0, 10e3
    par[MC.PAR_INVALID_PEN] = 5e-3
    par[MC.PAR_MAX_SPEED], par[MC.PAR_MAX_RATE] = 10.0, 20.0
    par[MC.PAR_Y_CROWN], par[MC.PAR_Z_CROWN] = 0.04, -0.001
    par[MC.PAR_TIP_Y], par[MC.PAR_TIP_Z] = 0.0, 0.028
    par[MC.PAR_FIELD_Y], par[MC.PAR_FIELD_Z] = 0.10, -0.005
    par[MC.PAR_FLANGED] = 1.0
    par[MC.PAR_S_FLANK] = 0.02
    par[MC.PAR_PROFILE_END_LAT] = 0.05
    par[MC.PAR_HUNT_AMP], par[MC.PAR_HUNT_NEED] = 3e-3, 6
    return par


def _random_state(rng, n_ws):
    n_w = 2 * n_ws
    res = rng.standard_normal((n_w, L.N_SLOTS, L.N_RES)) * 1e4
    res[:, :, L.RES_STATUS] = rng.integers(0, 3, (n_w, L.N_SLOTS))
    res[:, :, L.RES_N] = rng.uniform(-1e3, 8e4, (n_w, L.N_SLOTS))
    res[:, :, L.RES_DELTA] = rng.uniform(0.0, 6e-3, (n_w, L.N_SLOTS))
    res[:, :, L.RES_GAMMA] = rng.uniform(-0.1, 1.3, (n_w, L.N_SLOTS))
    res[:, :, L.RES_FLAGS] = rng.integers(0, 16, (n_w, L.N_SLOTS))
    lifted = rng.random(n_w) < 0.25
    res[lifted, :, L.RES_STATUS] = 0
    nan = rng.random((n_w, L.N_SLOTS, L.N_RES)) < 0.01
    res[nan] = np.nan
    out = rng.standard_normal((n_w, L.N_SLOTS, L.N_FIELDS)) * 1e-3
    out[:, :, L.F_S_WHEEL] = rng.uniform(0.0, 0.04, (n_w, L.N_SLOTS))
    out[rng.random((n_w, L.N_SLOTS)) < 0.1, L.F_PENETRATION] = np.nan
    poses = np.column_stack([rng.uniform(-0.02, 0.06, n_ws), rng.uniform(-0.04, 0.01, n_ws),
                             rng.uniform(-0.05, 0.05, n_ws)])
    return res, out, poses


def _numpy_quantities(res, out, poses):
    """The monitor's documented per-wheel quantities, by NumPy."""
    loaded = (res[:, :, L.RES_STATUS] > 0) & (res[:, :, L.RES_N] > 0.0)
    any_loaded = loaded.any(axis=1)
    wheel_poses = np.empty((2 * len(poses), 3))
    wheel_poses[0::2] = poses
    wheel_poses[1::2] = poses * np.array([-1.0, 1.0, -1.0])
    pen = np.where(np.isfinite(out[:, :, L.F_PENETRATION]), out[:, :, L.F_PENETRATION], -np.inf)
    return {
        MC.WQ_N: np.where(loaded, res[:, :, L.RES_N], 0.0).sum(axis=1),
        MC.WQ_Y: res[:, :, L.RES_F_TRACK_Y].sum(axis=1),
        MC.WQ_Q: -res[:, :, L.RES_F_TRACK_Z].sum(axis=1),
        MC.WQ_Y_FLANGE: np.where(loaded[:, L.SLOT_FLANGE], res[:, L.SLOT_FLANGE, L.RES_F_TRACK_Y], 0.0),
        MC.WQ_DEPTH: np.where(loaded, res[:, :, L.RES_DELTA], 0.0).max(axis=1),
        MC.WQ_GAMMA: np.where(any_loaded, np.where(loaded, res[:, :, L.RES_GAMMA], -np.inf).max(axis=1), np.nan),
        MC.WQ_GAP: -pen.max(axis=1),
        MC.WQ_CY: wheel_poses[:, 0], MC.WQ_CZ: wheel_poses[:, 1], MC.WQ_ROLL: wheel_poses[:, 2],
    }, loaded, wheel_poses


def test_per_wheel_quantities_and_flags_match_numpy():
    rng = np.random.default_rng(11)
    n_ws = 3
    par = _par()
    ws_par = np.zeros((n_ws, MC.N_WSP))
    q, v = np.zeros(6 * n_ws), np.zeros(6 * n_ws)
    ext, iv, wq, wflag, wss, rings, G, work = MC.empty_arrays(n_ws, 6)
    hist = np.zeros((1, 1 + 7 * 2 * n_ws))
    for _ in range(300):
        res, out, poses = _random_state(rng, n_ws)
        MC.monitor_state(0.1, res, out, poses, q, v, par, ws_par, ext, iv, wq, wflag, wss, rings, G, work,
                         np.zeros((n_ws, 3, 0)), hist, 0)
        ref, loaded, wp = _numpy_quantities(res, out, poses)
        # the three-slot sums N, Y, Q: the monitor adds slot by slot, NumPy's sum(axis=1) in the order its reduction
        # loop picks (version dependent): two orders of a 3-term sum, |difference| <= 2 eps sum_j |term_j| per wheel
        terms = {MC.WQ_N: np.where(loaded, res[:, :, L.RES_N], 0.0), MC.WQ_Y: res[:, :, L.RES_F_TRACK_Y],
                 MC.WQ_Q: res[:, :, L.RES_F_TRACK_Z]}
        for field, values in ref.items():
            if field in terms:
                bound = 2 * EPS * np.abs(terms[field]).sum(axis=1)                  # NaN where a term is NaN
                both_nan = np.isnan(wq[:, field]) & np.isnan(values)
                assert np.all((np.abs(wq[:, field] - values) <= bound) | both_nan), (field, wq[:, field], values)
            else:
                # copies, sign changes, maxima (selections): no rounding, bit-equality
                np.testing.assert_array_equal(wq[:, field], values)
        # the derailment geometry: the flange tip and the field end placed by the pose
        cr, sr = np.cos(wp[:, 2]), np.sin(wp[:, 2])
        y_tip = wp[:, 0] + cr * par[MC.PAR_TIP_Y] - sr * par[MC.PAR_TIP_Z]
        z_tip = wp[:, 1] + sr * par[MC.PAR_TIP_Y] + cr * par[MC.PAR_TIP_Z]
        y_field = wp[:, 0] + cr * par[MC.PAR_FIELD_Y] - sr * par[MC.PAR_FIELD_Z]
        d1 = y_tip >= par[MC.PAR_Y_CROWN]
        d2 = ~d1 & (z_tip < par[MC.PAR_Z_CROWN])
        d1_field = ~d1 & ~d2 & (y_field <= par[MC.PAR_Y_CROWN])
        # boolean flags (exact): the seeded states keep the tip and field points >= 5e-6 m from the crown (the
        # lateral limit likewise), so a one-ulp difference of cos/sin between NumPy and the compiled code flips none
        np.testing.assert_array_equal((wflag & MC.WF_D1_TIP) != 0, d1)
        np.testing.assert_array_equal((wflag & MC.WF_D2_LIFTED) != 0, d2)
        np.testing.assert_array_equal((wflag & MC.WF_D1_FIELD) != 0, d1_field)
        # thresholds on input values and their maxima (no arithmetic), isfinite: exact booleans
        np.testing.assert_array_equal((wflag & MC.WF_PENETRATION) != 0, ref[MC.WQ_DEPTH] > par[MC.PAR_INVALID_PEN])
        cols = [L.RES_N, L.RES_F_TRACK_X, L.RES_F_TRACK_Y, L.RES_F_TRACK_Z, L.RES_GAMMA, L.RES_DELTA, L.RES_P_Y,
                L.RES_P_Z]
        finite = np.all(np.isfinite(np.where(loaded[:, :, None], res[:, :, cols], 0.0)), axis=(1, 2))
        np.testing.assert_array_equal((wflag & MC.WF_NON_FINITE) != 0, ~finite)
        flange = loaded[:, L.SLOT_FLANGE]
        beyond = flange & (out[:, L.SLOT_FLANGE, L.F_S_WHEEL] < par[MC.PAR_S_FLANK])
        prof = flange & ((np.nan_to_num(res[:, L.SLOT_FLANGE, L.RES_FLAGS]).astype(np.int64) & K.FLAG_PROFILE_END)
                         != 0)
        reasons = wflag >> MC.WF_REASONS_SHIFT
        np.testing.assert_array_equal((reasons & MC.REASON_BEYOND_FLANK) != 0, beyond)
        np.testing.assert_array_equal((reasons & MC.REASON_PROFILE_END) != 0, prof)
        np.testing.assert_array_equal((wflag & MC.WF_D3) != 0, prof & (wp[:, 0] >= par[MC.PAR_PROFILE_END_LAT]))
        # the history row is the state's quantities
        row = hist[0, 1:].reshape(2 * n_ws, 7)
        np.testing.assert_array_equal(row[:, 3], wq[:, MC.WQ_N])                  # a copy: bit-equality
        np.testing.assert_array_equal(row[:, 6], ref[MC.WQ_DEPTH])                # a maximum (selection): exact


def test_intervals_start_and_end_with_the_condition():
    """Lift-off of one wheel over states 3..5: one start flag, one end flag, the interval's times and largest gap."""
    n_ws = 1
    par = _par()
    ws_par = np.zeros((n_ws, MC.N_WSP))
    q, v = np.zeros(6), np.zeros(6)
    arrays = MC.empty_arrays(n_ws, 6)
    ext, iv, wq, wflag = arrays[:4]
    res = np.zeros((2, L.N_SLOTS, L.N_RES))
    res[:, 0, L.RES_STATUS] = 1
    out = np.zeros((2, L.N_SLOTS, L.N_FIELDS))
    poses = np.array([[0.0, -0.0005, 0.0]])
    gaps = {3: 1e-4, 4: 3e-4, 5: 2e-4}
    flags = []
    for i in range(8):
        res[:, 0, L.RES_N] = 5e4
        out[:, :, L.F_PENETRATION] = -1e-3
        if i in gaps:
            res[0, 0, L.RES_N] = 0.0
            out[0, :, L.F_PENETRATION] = -gaps[i]
        MC.monitor_state(0.01 * i, res, out, poses, q, v, par, ws_par, *arrays, np.zeros((1, 3, 0)), np.zeros((0, 15)),
                         -1)
        flags.append(int(wflag[0]))
    starts = [i for i, f in enumerate(flags) if f & MC.WF_LIFT_START]
    ends = [i for i, f in enumerate(flags) if f & MC.WF_LIFT_END]
    assert starts == [3] and ends == [6]
    # the times and the gap the monitor stores are the values passed in (0.01 * i, -penetration): exact
    assert iv[0, MC.IV_LIFT, MC.IVF_START] == 0.01 * 3 and iv[0, MC.IV_LIFT, MC.IVF_LAST] == 0.01 * 6
    assert iv[0, MC.IV_LIFT, MC.IVF_PEAK] == 3e-4 and ext[0, MC.EXT_MAX_GAP] == 3e-4
    assert iv[0, MC.IV_LIFT, MC.IVF_OPEN] == 0.0 and not any(f & MC.WF_LIFT_START for f in flags[:3])


# --------------------------------------------------------------------------------------------------- hunting
@pytest.mark.parametrize("amplitude_m, detected", [(4e-3, True), (2.9e-3, False)])
def test_hunting_is_detected_after_three_cycles_with_the_frequency(amplitude_m, detected):
    f_hz, dt, n_ws = 4.0, 1e-3, 1
    par = _par()
    ws_par = np.zeros((n_ws, MC.N_WSP))
    q, v = np.zeros(6), np.zeros(6)
    arrays = MC.empty_arrays(n_ws, 6)
    wss, rings = arrays[4], arrays[5]
    res = np.zeros((2, L.N_SLOTS, L.N_RES))
    out = np.zeros((2, L.N_SLOTS, L.N_FIELDS))
    t_found = None
    for i in range(1, 2001):
        t = i * dt
        poses = np.array([[amplitude_m * math.sin(2 * math.pi * f_hz * t), 0.0, 0.0]])
        MC.monitor_state(t, res, out, poses, q, v, par, ws_par, *arrays, np.zeros((1, 3, 0)), np.zeros((0, 15)), -1)
        if int(wss[0, MC.WS_FLAGS]) & MC.WSF_HUNTING:
            t_found = t
            break
    if not detected:
        assert t_found is None
        return
    # the sixth sign change (every half-cycle from the first has its peak above the limit): t = 3 / f, registered at
    # the first sample of the new sign
    assert 3.0 / f_hz - 1e-12 <= t_found <= 3.0 / f_hz + dt + 1e-12
    ts, peaks = MC.hunting_rings_ordered(rings[0], int(wss[0, MC.WS_HUNT_COUNT]), int(wss[0, MC.WS_HUNT_CROSSINGS]),
                                         6)
    f_est = 0.5 / float(np.mean(np.diff(ts)))
    assert f_est == pytest.approx(f_hz, rel=dt * f_hz * 2 / 5 + 1e-12)
    assert amplitude_m * math.cos(math.pi * f_hz * dt) <= peaks.min() <= amplitude_m


# ------------------------------------------------------------------------------------------------ the 2 m window
def test_window_quotient_is_the_quotient_of_the_window_sums():
    rng = np.random.default_rng(3)
    n_ws, V = 2, 25.0
    nadal = 1.34
    check = FlangeClimbCheck(n_ws, V, nadal)
    contact = SimpleNamespace(results=np.zeros((2 * n_ws, L.N_SLOTS, L.N_RES)))
    # 2 m = 0.08 s: 50 states of 1.6 ms (the ring of 64 wraps around), then 400 of 0.2 ms (it grows, wrapped)
    n_states = 1500
    ts = np.concatenate([np.arange(200) * 1.6e-3, 200 * 1.6e-3 + np.arange(1, n_states - 199) * 2e-4])
    ys = np.zeros((n_states, 2 * n_ws))                 # Y towards the field side and Q of every state
    qs = np.zeros((n_states, 2 * n_ws))
    found = None
    for i, t in enumerate(ts):
        r = contact.results
        r[:, :, L.RES_F_TRACK_Z] = -rng.uniform(0.0, 3e4, (2 * n_ws, L.N_SLOTS))
        r[:, :, L.RES_F_TRACK_Y] = rng.uniform(-2e4, 2e4, (2 * n_ws, L.N_SLOTS))
        if i % 97 < 5:
            r[1, :, L.RES_F_TRACK_Z] = 0.0                                       # wheel 1 lifted
        ramp = max(0.0, (i - 1000) / 300.0)                                     # wheel 2 pushed out, then climbs
        r[2, :, L.RES_F_TRACK_Y] = -ramp * 2.0 * (-r[2, :, L.RES_F_TRACK_Z])
        fy = r[:, :, L.RES_F_TRACK_Y].sum(axis=1)
        ys[i] = np.where(np.arange(2 * n_ws) % 2 == 0, -fy, fy)
        qs[i] = np.maximum(-r[:, :, L.RES_F_TRACK_Z].sum(axis=1), 0.0)
        st = check(contact, float(t))
        inside = t - ts[:i + 1] <= check.window_s
        y = ys[:i + 1][inside].sum(axis=0)
        q = qs[:i + 1][inside].sum(axis=0)
        quotient = np.where(q > 0.0, y / np.where(q > 0.0, q, 1.0), 0.0)
        if t < check.window_s * (1 - 1e-9):
            assert st is None
            continue
        # running sums of 400 states of ~1e5 N: rounding far below 1e-9 of the quotient's scale
        sy, sq = check._sums
        np.testing.assert_allclose(np.where(sq > 0.0, sy / np.where(sq > 0.0, sq, 1.0), 0.0), quotient, rtol=1e-9,
                                   atol=1e-12)
        if quotient.max() > nadal:
            found = t
            assert st is not None and st.kind == "derailment" and (st.wheelset, st.side) == (1, "right")
            assert st.time_s == t  # a copy: exact
            break
        assert st is None
    assert found is not None
    assert check.max_quotient[2] > nadal


# ------------------------------------------------------------------------------------------------- the recorder
def test_recorder_wheel_columns_match_the_connector_methods():
    rng = np.random.default_rng(5)
    n_ws = 4
    n_w = 2 * n_ws
    for _ in range(200):
        res, _, _ = _random_state(rng, n_ws)
        res[rng.random((n_w, L.N_SLOTS)) < 0.2, L.RES_N] = 0.0
        fake = SimpleNamespace(results=res)
        row = np.full(5 * n_w, -1.0)
        wheel_columns(res, row)
        for w in range(n_w):
            k, side = w // 2, ("right", "left")[w % 2]
            F = WheelRailContact.wheel_force_N(fake, k, side)
            tol = 2 * EPS * np.abs(res[w, :, L.RES_F_TRACK_X:L.RES_F_TRACK_Z + 1]).sum(axis=0)
            assert abs(row[w] - F[1]) <= tol[1] or (math.isnan(row[w]) and math.isnan(F[1]))
            Q = -F[2]
            assert abs(row[n_w + w] - Q) <= tol[2] or (math.isnan(row[n_w + w]) and math.isnan(Q))
            y_out = -F[1] if side == "right" else F[1]
            if Q > 0.0:              # quotient of two sums known to tol: relative error their relative errors
                rel = tol[1] / abs(F[1]) + tol[2] / Q + 2 * EPS if F[1] != 0.0 else 2 * EPS
                assert row[2 * n_w + w] == pytest.approx(y_out / Q, rel=rel, abs=1e-300, nan_ok=True)
            elif not math.isnan(Q):
                assert math.isnan(row[2 * n_w + w])
            assert row[3 * n_w + w] == (1.0 if WheelRailContact.flange_contact(fake, k, side) else 0.0)
            loads = res[w, :, L.RES_N]
            j = int(np.argmax(loads))
            expected = res[w, j, L.RES_GAMMA] if loads[j] > 0.0 else math.nan
            # the flag and the contact angle of the most loaded slot (a selection): exact
            assert row[4 * n_w + w] == expected or (math.isnan(row[4 * n_w + w]) and math.isnan(expected))
