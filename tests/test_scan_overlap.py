"""The coarse vertical-overlap scan that seeds the contact search (``search.overlap_peaks``) against brute force.

Reference (independent of the kernel's Newton and segment walk): every scan sample's wheel point from the curve's
NumPy evaluation (``brute_force.wheel_points``), the rail point under it by a bracketed root search on the rail
curve's lateral coordinate (``scipy.optimize.brentq`` to 1e-15 m), its overlap ``z_w - z_r``; the local maxima of
those overlaps, deepest first.

Tolerance: the scan takes the rail height from the tangent at its last Newton point once the step is below
``SCAN_NEWTON_TOL_M`` (1e-7 m); the error is about kappa_r ds^2 / t_y <= 77 1/m x (1e-7 m)^2 / 0.15 ~ 5e-12 m on the
projectable stretch (t_y >= 0.15, UIC60's R13 gauge corner the largest curvature).  The reference's own error is
~1e-15 m (root tolerance times the slope).  ``OVERLAP_TOL_M`` = 1e-11 m covers both with a factor of two; peak
rankings are compared only where the reference depths differ by more than that.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from brute_force import wheel_points
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact.pair import WheelRailPair
from exudyn_wheelrail.contact.search import _scan_overlap, overlap_peaks
from exudyn_wheelrail.contact.wheelset import WheelsetContact

OVERLAP_TOL_M = 1e-11
N_SCAN = 200
K_MAX = 3


@pytest.fixture(scope="module")
def setup():
    pair = WheelRailPair()
    return pair, WheelsetContact(pair, global_search=True)


def _reference_overlaps(pair, c, reg, pose):
    """(s_w samples, overlaps or -inf, rail arc lengths) of the scan grid of region ``reg`` by brute force."""
    curve = (pair.tread_side, pair.flange_side)[reg]
    rail = pair.rail_side
    lo, hi = int(c.mono[0, 0]), int(c.mono[0, 1])
    s_r_lo, s_r_hi = c.nodes[lo, 0], c.nodes[hi, 0]
    y_lo, y_hi = c.nodes[lo, 1], c.nodes[hi, 1]
    s = np.linspace(curve.s_min, curve.s_max, N_SCAN)
    pw = wheel_points(curve, s, pose)
    ov = np.full(N_SCAN, -np.inf)
    sr = np.full(N_SCAN, np.nan)
    for k, (y, z) in enumerate(pw[:, :2]):
        if not y_lo <= y <= y_hi:
            continue
        x = brentq(lambda q: rail.position([q])[0, 0] - y, s_r_lo, s_r_hi, xtol=1e-15, rtol=1e-15)
        sr[k] = x
        ov[k] = z - rail.position([x])[0, 1]
    return s, ov, sr


def _poses():
    """Poses over the range of the contact search tests (lateral -8..10 mm, roll +-4 mrad), each at the height where
    the tread's deepest scan sample overlaps by 50 µm (the overlap is linear in the height: set exactly)."""
    rng = np.random.default_rng(20261202)
    return [(rng.uniform(-8e-3, 10e-3), rng.uniform(-4e-3, 4e-3)) for _ in range(6)] + [(0.0, 0.0), (7.5e-3, 2e-3)]


@pytest.mark.parametrize("y, roll", _poses())
def test_scan_matches_brute_force(setup, y, roll):
    pair, c = setup
    z0 = -0.46
    _, ov0, _ = _reference_overlaps(pair, c, 0, (y, z0, roll))
    z = z0 + 50e-6 - np.max(ov0)
    pose = (y, z, roll)
    cos_r, sin_r = np.cos(roll), np.sin(roll)
    for reg in (0, 1):
        cid = int(c.curve_ids[0, 1 + reg])
        s, ov, sr = _reference_overlaps(pair, c, reg, pose)
        # every sample's overlap (and whether it lies over the rail's projectable stretch)
        pw = wheel_points((pair.tread_side, pair.flange_side)[reg], s, pose)
        row = int(c.mono[0, 0])
        for k in range(N_SCAN):
            ok, d, row = _scan_overlap(c.nodes, c.meta, 0, int(c.mono[0, 0]), int(c.mono[0, 1]), pw[k, 0], pw[k, 1],
                                       row)
            assert ok == np.isfinite(ov[k]), (reg, k)
            if ok:
                assert abs(d - ov[k]) <= OVERLAP_TOL_M, (reg, k, d, ov[k])
        # the peaks: local maxima of the reference overlaps, deepest first, their rail points exact
        out_sw = np.full(K.MAX_STARTS, np.nan)
        out_sr = np.full(K.MAX_STARTS, np.nan)
        n = overlap_peaks(c.nodes, c.meta, c.mono, 0, cid, y, z, cos_r, sin_r, s[0], s[-1], N_SCAN, K_MAX, out_sw,
                          out_sr)
        left = np.concatenate([[-np.inf], ov[:-1]])
        right = np.concatenate([ov[1:], [-np.inf]])
        ref_peaks = [k for k in range(N_SCAN) if np.isfinite(ov[k]) and ov[k] >= left[k] - OVERLAP_TOL_M
                     and ov[k] >= right[k] - OVERLAP_TOL_M]
        strict = [k for k in ref_peaks if ov[k] > left[k] + OVERLAP_TOL_M and ov[k] > right[k] + OVERLAP_TOL_M]
        assert n == min(K_MAX, len(ref_peaks)) or len(ref_peaks) != len(strict), (reg, n, ref_peaks)
        got = [int(round((out_sw[j] - s[0]) / (s[1] - s[0]))) for j in range(n)]
        for j, k in enumerate(got):
            assert k in ref_peaks, (reg, got, ref_peaks)
            assert out_sw[j] == pytest.approx(s[k], abs=1e-12)
            assert out_sr[j] == pytest.approx(sr[k], abs=1e-12)
            if j:
                assert ov[k] <= ov[got[j - 1]] + OVERLAP_TOL_M, (reg, got)
        # nothing deeper was left out
        if n:
            floor = ov[got[-1]]
            missed = [k for k in strict if k not in got and ov[k] > floor + OVERLAP_TOL_M]
            assert not missed, (reg, got, missed)
        if reg == 0:
            assert n >= 1          # the tread overlaps by 50 µm: at least one peak


@pytest.mark.parametrize("y, roll", _poses())
def test_cached_scan_points_change_nothing(setup, y, roll):
    """The kernel's cached scan points (``WheelsetContact.scan``, ``kernel.scan_array``) are the wheel curve's own
    evaluations at the scan's arc lengths: the peaks and the whole kernel output are bitwise those of the scan that
    evaluates the curve (whose peaks are checked against brute force above)."""
    pair, c = setup
    _, ov0, _ = _reference_overlaps(pair, c, 0, (y, -0.46, roll))
    pose = (y, -0.46 + 3e-4 - np.max(ov0), roll)      # the tread's deepest sample 300 µm into the rail
    assert c.scan.shape == (c.meta.shape[0], N_SCAN, 2)
    cos_r, sin_r = np.cos(roll), np.sin(roll)
    for reg in (0, 1):
        cid = int(c.curve_ids[0, 1 + reg])
        lo = c.nodes[int(c.meta[cid, 0]), 0]
        hi = c.nodes[int(c.meta[cid, 0] + c.meta[cid, 1]) - 1, 0]
        peaks = []
        for points in (K.NO_SCAN[0], c.scan[cid]):
            out_sw = np.full(K.MAX_STARTS, np.nan)
            out_sr = np.full(K.MAX_STARTS, np.nan)
            n = overlap_peaks(c.nodes, c.meta, c.mono, 0, cid, y, pose[1], cos_r, sin_r, lo, hi, N_SCAN, K_MAX,
                              out_sw, out_sr, points)
            peaks.append((n, out_sw[:n].tobytes(), out_sr[:n].tobytes()))
        assert peaks[0] == peaks[1], reg
        assert peaks[0][0] >= 1 or reg == 1
    outs = []
    for scan in (K.NO_SCAN, c.scan):
        warm = np.full_like(c.warm, np.nan)
        out = np.zeros_like(c.out)
        K.evaluate_wheels(c.nodes, c.meta, c.mono, c.curve_ids[:1], np.array([pose]), warm[:1], c.params, out[:1],
                          scan)
        outs.append(out[:1].tobytes())
    assert outs[0] == outs[1]
