"""The precomputed contact geometry (contact.geometry_table) against the online search it replaces.

References: the online kernel in global mode (brute-force scan + Newton) at the same poses; the table's own
construction (exact at its nodes); the connector with geometry="online" on the same short RTRI run.
Tolerances are stated with each test and come from measurements of the table against the online search (default grid
0.1 mm x 0.5 mrad; conformal tread contact on S1002/UIC60 moves by millimetres per milliradian of roll, which is
where the table differs most).
"""
import math

import numpy as np
import pytest

from exudyn_wheelrail.contact import geometry_table as GT
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact.pair import WheelRailPair
from exudyn_wheelrail.contact.wheelset import WheelsetContact

STATIC_WHEEL_LOAD_N = 54.5e3


@pytest.fixture(scope="module")
def setup():
    pair = WheelRailPair("S1002", "UIC60", inclination="1/40")
    kc = WheelsetContact(pair, 1, global_search=True)
    tab = GT.geometry_table(kc.nodes, kc.meta, kc.mono, kc.curve_ids[0], kc.params)
    return kc, tab


def _both(kc, tab, pose):
    par, czr, data = tab.arrays()
    warm = np.full((1, 2, K.N_WARM), np.nan)
    online = np.zeros((1, K.N_SLOTS, K.N_FIELDS))
    table = np.zeros_like(online)
    stats = np.zeros(GT.N_STATS, dtype=np.int64)
    P = np.array([pose], dtype=float)
    K.evaluate_wheels(kc.nodes, kc.meta, kc.mono, kc.curve_ids[:1], P, warm, kc.params, online)
    GT.evaluate_wheels_tabulated(par, czr, data, kc.nodes, kc.meta, kc.mono, kc.curve_ids[:1], P, warm, kc.params,
                                 table, stats)
    return online[0], table[0], stats


def _resultant(o):
    """Total normal force and its lateral component (rail on wheel, side frame)."""
    N = o[:, K.F_NORMAL_FORCE]
    return float(N.sum()), float(-(N * o[:, K.F_NR_Y]).sum())


def _height(tab, c_y, roll):
    """c_z of the reference penetration at (c_y, roll), bilinear in the table's grid."""
    par, czr, _ = tab.arrays()
    u = (c_y - par[GT.T_Y0]) / par[GT.T_DY]
    r = (roll - par[GT.T_R0]) / par[GT.T_DR]
    i, j = int(u), int(r)
    fy, fr = u - i, r - j
    return ((1 - fy) * (1 - fr) * czr[i, j] + fy * (1 - fr) * czr[i + 1, j] + (1 - fy) * fr * czr[i, j + 1]
            + fy * fr * czr[i + 1, j + 1])


def test_table_is_exact_at_its_nodes(setup):
    kc, tab = setup
    ys, rolls = tab.grid.axes()
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(40):
        i = int(rng.integers(50, len(ys) - 50))
        j = int(rng.integers(2, len(rolls) - 2))
        if not math.isfinite(tab.cz_ref[i, j]):
            continue
        on, tb, st = _both(kc, tab, (ys[i], tab.cz_ref[i, j], rolls[j]))
        assert st[GT.STAT_TABLE] == 1
        # the deepest contact: the reference penetration
        k = int(np.argmax(np.where(tb[:, K.F_STATUS] > 0, tb[:, K.F_PENETRATION], -np.inf)))
        assert tb[k, K.F_PENETRATION] == pytest.approx(tab.grid.delta_ref_m, rel=1e-6)
        assert _resultant(tb)[0] == pytest.approx(_resultant(on)[0], rel=1e-6)
        checked += 1
    assert checked >= 30


def test_normal_force_against_online_search_off_the_nodes(setup):
    """Random poses between the nodes: c_y within ±12 mm (tread to flange contact), roll ±3 mrad, penetration
    from lift-off to about three times the static one.  Measured: 90 % of the poses within 0.5 %
    of max(N, 50 kN), RMS 4 %; the outliers are conformal-tread and tread/flange two-point poses where the online
    kernel's own answer jumps between zones."""
    kc, tab = setup
    rng = np.random.default_rng(11)
    rel_N, rel_Y = [], []
    for _ in range(600):
        c_y = rng.uniform(-0.012, 0.012)
        roll = rng.uniform(-3e-3, 3e-3)
        cz = _height(tab, c_y, roll)
        if not math.isfinite(cz):
            continue
        c_z = cz + rng.uniform(-0.06e-3, 0.1e-3)
        on, tb, st = _both(kc, tab, (c_y, c_z, roll))
        assert st[GT.STAT_TABLE] == 1
        assert np.all(np.isfinite(tb[:, K.F_NORMAL_FORCE]))
        N_on, Y_on = _resultant(on)
        N_tb, Y_tb = _resultant(tb)
        scale = max(N_on, STATIC_WHEEL_LOAD_N)
        rel_N.append(abs(N_tb - N_on) / scale)
        rel_Y.append(abs(Y_tb - Y_on) / scale)
    rel_N, rel_Y = np.array(rel_N), np.array(rel_Y)
    assert len(rel_N) > 550
    assert np.percentile(rel_N, 90) < 0.01
    assert np.percentile(rel_Y, 90) < 0.01
    assert np.sqrt(np.mean(rel_N ** 2)) < 0.08


def test_outside_the_table_falls_back_to_the_online_search(setup):
    kc, tab = setup
    # beyond the roll range and beyond the lateral range: the online kernel answers, bit for bit
    for pose in ((0.0, -0.4597, 0.05), (0.04, -0.47, 0.0)):
        on, tb, st = _both(kc, tab, pose)
        assert st[GT.STAT_FALLBACK] == 1 and st[GT.STAT_TABLE] == 0
        # the same compiled kernel, global search (no memory), same pose: bit-equality
        np.testing.assert_array_equal(np.nan_to_num(on, nan=-7.0), np.nan_to_num(tb, nan=-7.0))
    # a NaN pose: the kernel's invalid-pose status, never a number
    on, tb, st = _both(kc, tab, (float("nan"), -0.46, 0.0))
    assert np.all(tb[:, K.F_STATUS] == K.STATUS_INVALID_POSE)  # a status code: exact


def test_flange_contact_from_the_table(setup):
    """A flange contact (c_y = 8 mm: beyond the jump to the flange at about 6.3 mm) is found with its steep contact
    angle, and its normal force agrees with the online search within 2 % of the static wheel load."""
    kc, tab = setup
    c_y, roll = 8e-3, 0.0
    c_z = _height(tab, c_y, roll)
    on, tb, _ = _both(kc, tab, (c_y, c_z, roll))
    assert tb[K.SLOT_FLANGE, K.F_STATUS] > 0 and on[K.SLOT_FLANGE, K.F_STATUS] > 0
    assert tb[K.SLOT_FLANGE, K.F_CONTACT_ANGLE] == pytest.approx(on[K.SLOT_FLANGE, K.F_CONTACT_ANGLE], abs=0.02)
    assert tb[K.SLOT_FLANGE, K.F_CONTACT_ANGLE] > 0.9
    assert abs(_resultant(tb)[0] - _resultant(on)[0]) < 0.02 * STATIC_WHEEL_LOAD_N


def test_connector_option_and_cache(setup, tmp_path, monkeypatch):
    kc, tab = setup
    # the in-memory cache returns the same object; a bad option is a clear error
    again = GT.geometry_table(kc.nodes, kc.meta, kc.mono, kc.curve_ids[0], kc.params)
    assert again is tab
    from exudyn_wheelrail.scenarios.rtri import RtriCase
    with pytest.raises(ValueError, match="geometry"):
        RtriCase(geometry="lookup")
