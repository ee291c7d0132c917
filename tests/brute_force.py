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
