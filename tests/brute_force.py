"""Brute-force reference for contact points: dense sampling + nearest neighbours, no Newton, no scan.

The deepest point of a wheel region is the wheel point with the most negative signed distance to the rail.  The
signed distance of a point to the rail is found from the nearest of ~1 µm-spaced rail samples (KD-tree) and
projected on that sample's normal (error O(h^2 kappa) ~ 1e-10 m); the wheel region is sampled every ~2 µm and the
best sample refined by a bounded scalar minimisation of the same distance.  Only the curve evaluation (whose
accuracy is tested separately against the analytic profiles and point files) is shared with the code under test.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.spatial import cKDTree


class RailDistance:
    def __init__(self, rail_curve, spacing_m=1e-6):
        s = np.linspace(rail_curve.s_min, rail_curve.s_max, int(rail_curve.length / spacing_m) + 1)
        e = rail_curve.evaluate(s)
        self.p = e[:, 0:2]
        self.n = e[:, 4:6]
        self.tree = cKDTree(self.p)

    def signed_distance(self, pts):
        """Signed distance of points (N, 2) to the rail (negative inside the rail) and nearest rail index."""
        _, idx = self.tree.query(pts)
        d = np.sum((pts - self.p[idx]) * self.n[idx], axis=1)
        return d, idx


def wheel_points(wheel_curve, s, pose):
    c_y, c_z, roll = pose
    e = wheel_curve.evaluate(np.atleast_1d(s))
    co, si = np.cos(roll), np.sin(roll)
    y = c_y + co * e[:, 0] - si * e[:, 1]
    z = c_z + si * e[:, 0] + co * e[:, 1]
    return np.column_stack([y, z])


def deepest_point(wheel_curve, rail: RailDistance, pose, spacing_m=2e-6):
    """(s_w, penetration, wheel point (y, z), rail point (y, z)) of a wheel region at a side-frame pose."""
    s = np.linspace(wheel_curve.s_min, wheel_curve.s_max, int(wheel_curve.length / spacing_m) + 1)
    pts = wheel_points(wheel_curve, s, pose)
    d, _ = rail.signed_distance(pts)
    k = int(np.argmin(d))
    h = s[1] - s[0]
    lo, hi = s[max(k - 2, 0)], s[min(k + 2, len(s) - 1)]

    def f(x):
        return rail.signed_distance(wheel_points(wheel_curve, x, pose))[0][0]

    res = minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-10})
    s_best = res.x if res.fun < d[k] else s[k]
    p = wheel_points(wheel_curve, s_best, pose)
    dist, idx = rail.signed_distance(p)
    return float(s_best), float(-dist[0]), p[0], rail.p[idx[0]], h


class FastRailDistance(RailDistance):
    """:class:`RailDistance` with the same ~1 µm rail samples and (up to ties) the same nearest sample, faster.

    The KD-tree holds every ``stride``-th sample only; the exact nearest fine sample is then taken from a window of
    +-2 coarse spacings around the coarse nearest one (the nearest point of a smooth curve moves by less than one
    coarse spacing between the two sample sets wherever the foot of the normal is unique).
    """

    def __init__(self, rail_curve, spacing_m=1e-6, stride=8):
        s = np.linspace(rail_curve.s_min, rail_curve.s_max, int(rail_curve.length / spacing_m) + 1)
        e = rail_curve.evaluate(s)
        self.s = s
        self.p = e[:, 0:2]
        self.n = e[:, 4:6]
        self.stride = int(stride)
        self.coarse = np.arange(0, len(s), self.stride)
        self.tree = cKDTree(self.p[self.coarse], compact_nodes=False, balanced_tree=False)
        self._window = np.arange(-2 * self.stride, 2 * self.stride + 1)
        self._py, self._pz = np.ascontiguousarray(self.p[:, 0]), np.ascontiguousarray(self.p[:, 1])

    def signed_distance(self, pts, chunk=20000):
        pts = np.atleast_2d(np.asarray(pts, dtype=float))
        d = np.empty(len(pts))
        j = np.empty(len(pts), dtype=np.int64)
        for a in range(0, len(pts), chunk):
            q = pts[a:a + chunk]
            _, ic = self.tree.query(q)
            idx = self.coarse[ic][:, None] + self._window
            np.clip(idx, 0, len(self.p) - 1, out=idx)
            # squared distances to the window's samples, dy² + dz² (the same sum of two squares as summing the
            # squared components along an axis, without the (n, window, 2) temporary)
            dy = q[:, 0:1] - self._py[idx]
            dz = q[:, 1:2] - self._pz[idx]
            d2 = dy * dy + dz * dz
            jj = idx[np.arange(len(q)), np.argmin(d2, axis=1)]
            d[a:a + chunk] = np.sum((q - self.p[jj]) * self.n[jj], axis=1)
            j[a:a + chunk] = jj
        return d, j


_FROM_ABOVE = {}


def _rail_seen_from_above(rail_curve, spacing_m):
    """(y, z, s) samples of the longest stretch of the rail on which y increases with s (cached per curve)."""
    key = (id(rail_curve), spacing_m)
    if key not in _FROM_ABOVE:
        s_r = np.linspace(rail_curve.s_min, rail_curve.s_max, int(rail_curve.length / spacing_m) + 1)
        pr = rail_curve.position(s_r)
        inc = np.concatenate([[False], np.diff(pr[:, 0]) > 0, [False]]).astype(np.int8)
        starts = np.flatnonzero(np.diff(inc) == 1)        # first increasing step of each run
        ends = np.flatnonzero(np.diff(inc) == -1)         # one past its last step
        k = int(np.argmax(ends - starts))
        lo, hi = starts[k], ends[k]                        # samples lo..hi are strictly increasing in y
        _FROM_ABOVE[key] = (rail_curve, pr[lo:hi + 1, 0], pr[lo:hi + 1, 1], s_r[lo:hi + 1])
    return _FROM_ABOVE[key][1:]


def max_vertical_overlap(wheel_curve, rail_curve, pose, spacing_m=2e-6, rail_spacing_m=1e-6, refine=True):
    """The concave search's own criterion by brute force: the wheel point of largest vertical overlap.

    Overlap of a wheel point = z_w - z_r(y_w), with z_r(y) the rail surface seen vertically (the stretch of the
    rail on which y increases with s, i.e. the part a vertical line meets once, from the gauge point over the head).
    Wheel points every ``spacing_m``; the best sample is refined by a bounded scalar maximisation in which the rail
    point under the wheel point is found by a root search on the rail curve (no interpolation error).
    Returns ``(s_w, overlap, wheel point (y, z), rail point (y, z))``; overlap < 0 means a vertical gap; ``None``
    when no wheel point lies above the rail.  ``refine=False`` returns the best sample (rail point interpolated).
    """
    from scipy.optimize import brentq
    ry, rz, rs = _rail_seen_from_above(rail_curve, rail_spacing_m)
    s = np.linspace(wheel_curve.s_min, wheel_curve.s_max, int(wheel_curve.length / spacing_m) + 1)
    pw = wheel_points(wheel_curve, s, pose)
    inside = (pw[:, 0] >= ry[0]) & (pw[:, 0] <= ry[-1])
    if not inside.any():
        return None
    ov = np.full(len(s), -np.inf)
    ov[inside] = pw[inside, 1] - np.interp(pw[inside, 0], ry, rz)
    k = int(np.argmax(ov))
    if not refine:
        return float(s[k]), float(ov[k]), pw[k], np.array([pw[k, 0], pw[k, 1] - ov[k]])

    def rail_under(y):
        i = int(np.clip(np.searchsorted(ry, y), 1, len(ry) - 1))
        a, b = rs[max(i - 2, 0)], rs[min(i + 1, len(rs) - 1)]
        sr = brentq(lambda x: rail_curve.position([x])[0, 0] - y, a, b, xtol=1e-15, rtol=1e-15)
        return rail_curve.position([sr])[0]

    def neg_overlap(x):
        p = wheel_points(wheel_curve, x, pose)[0]
        if not (ry[0] <= p[0] <= ry[-1]):
            return np.inf
        return -(p[1] - rail_under(p[0])[1])

    a, b = s[max(k - 2, 0)], s[min(k + 2, len(s) - 1)]
    f_k = neg_overlap(s[k])
    res = minimize_scalar(neg_overlap, bounds=(a, b), method="bounded", options={"xatol": 1e-11})
    s_best = res.x if res.fun < f_k else s[k]
    p = wheel_points(wheel_curve, s_best, pose)[0]
    return float(s_best), float(-neg_overlap(s_best)), p, rail_under(p[0])
