"""Arc-length parameterised C2 profile curves, evaluated by a compiled kernel.

A :class:`ProfileCurve` stores nodes along the curve at arc length ``s_i`` with the exact position ``p_i``, unit
tangent ``t_i = dp/ds`` and second derivative ``a_i = d2p/ds2 = -kappa_i n_i``, taken from a dense exact
description (:class:`~exudyn_wheelrail.profiles.dense.DenseProfile`).  Between nodes, position is the quintic
Hermite interpolant of (p, t, a) — C2, exact for the node data, error O(h^6) on smooth sections; a curvature jump
(a section joint of a standard profile) inside a segment costs O(h^2 * jump / 100).  The fit error against the
dense source is measured on construction and stored in ``fit_error_m``.

Frames and signs are those of :mod:`exudyn_wheelrail.conventions`: the outward normal is
``n = normal_sign * (-t_z, t_y)`` and the curvature obeys ``dt/ds = -kappa n`` (convex positive).

The compiled functions work on a *packed* curve set: ``nodes`` (N, 7) = [s, p_y, p_z, t_y, t_z, a_y, a_z] for all
curves one after the other, and ``meta`` (n_curves, 5) = [first row, row count, normal_sign, mean spacing, end flags]
(end flags: 1 = the start is an end of the real profile, 2 = the stop is; a tread/flange split is not).
"""
from __future__ import annotations

import numpy as np

from ..jit import compiled
from .dense import DenseProfile

NODE_COLUMNS = 7
META_COLUMNS = 5


@compiled(inline="always")
def _segment(nodes, first, count, h_mean, s):
    """Index (row) of the segment [s_i, s_i+1] holding s; ends are clipped to the first/last segment; ``h_mean``
    the curve's mean node spacing (its ``meta`` row), the first guess."""
    last_seg = first + count - 2
    i = first + int((s - nodes[first, 0]) / h_mean)
    if i < first:
        i = first
    if i > last_seg:
        i = last_seg
    while i > first and s < nodes[i, 0]:
        i -= 1
    while i < last_seg and s > nodes[i + 1, 0]:
        i += 1
    return i


@compiled(inline="always")
def _basis(u):
    """The quintic Hermite basis at ``u`` in [0, 1] and its first derivatives with respect to u (d3 = -d0)."""
    u2 = u * u
    u3 = u2 * u
    u4 = u3 * u
    u5 = u4 * u
    h0 = 1.0 - 10.0 * u3 + 15.0 * u4 - 6.0 * u5
    h1 = u - 6.0 * u3 + 8.0 * u4 - 3.0 * u5
    h2 = 0.5 * (u2 - 3.0 * u3 + 3.0 * u4 - u5)
    h3 = 10.0 * u3 - 15.0 * u4 + 6.0 * u5
    h4 = -4.0 * u3 + 7.0 * u4 - 3.0 * u5
    h5 = 0.5 * (u3 - 2.0 * u4 + u5)
    d0 = -30.0 * u2 + 60.0 * u3 - 30.0 * u4
    d1 = 1.0 - 18.0 * u2 + 32.0 * u3 - 15.0 * u4
    d2 = 0.5 * (2.0 * u - 9.0 * u2 + 12.0 * u3 - 5.0 * u4)
    d4 = -12.0 * u2 + 28.0 * u3 - 15.0 * u4
    d5 = 0.5 * (3.0 * u2 - 8.0 * u3 + 5.0 * u4)
    return h0, h1, h2, h3, h4, h5, d0, d1, d2, d4, d5


@compiled(inline="always")
def _hermite(nodes, i, col, h, hh, b):
    """Position and first derivative (per arc length) of coordinate ``col`` (1: y, 2: z) on segment ``i`` from the
    basis ``b`` of :func:`_basis`; also the node data scaled to the segment, for the second derivative
    (:func:`curve_eval`)."""
    p0 = nodes[i, col]; t0 = nodes[i, col + 2] * h; a0 = nodes[i, col + 4] * hh
    p1 = nodes[i + 1, col]; t1 = nodes[i + 1, col + 2] * h; a1 = nodes[i + 1, col + 4] * hh
    p = b[0] * p0 + b[1] * t0 + b[2] * a0 + b[3] * p1 + b[4] * t1 + b[5] * a1
    dp = (b[6] * (p0 - p1) + b[7] * t0 + b[8] * a0 + b[9] * t1 + b[10] * a1) / h
    return p, dp, p0 - p1, t0, a0, t1, a1


@compiled(inline="always")
def _segment_at(nodes, meta, curve, s):
    """``(inside, row, h, u)``: inside ``[s_min, s_max]`` the segment row holding ``s``, its length and the local
    coordinate; outside the end row."""
    first = int(meta[curve, 0])
    count = int(meta[curve, 1])
    s_lo = nodes[first, 0]
    s_hi = nodes[first + count - 1, 0]
    if s < s_lo or s > s_hi:
        return False, (first if s < s_lo else first + count - 1), 0.0, 0.0
    i = _segment(nodes, first, count, meta[curve, 3], s)
    h = nodes[i + 1, 0] - nodes[i, 0]
    return True, i, h, (s - nodes[i, 0]) / h


@compiled(refcount=False, error_model="numpy")
def curve_eval(nodes, meta, curve, s):
    """Evaluate packed curve ``curve`` at arc length ``s``.

    Returns ``(p_y, p_z, t_y, t_z, n_y, n_z, kappa)`` in the curve's frame.  Outside ``[s_min, s_max]`` the curve
    continues along its end tangent (straight, kappa = 0), so Newton iterations stay well defined; callers check
    the range.  Its divisions (by a segment's length and the tangent's length, never zero on a packed curve) are
    not checked for zero (numba's ``error_model="numpy"``): the hottest function of the contact search.
    """
    sign = meta[curve, 2]
    inside, i, h, u = _segment_at(nodes, meta, curve, s)
    if not inside:
        ds = s - nodes[i, 0]
        ty = nodes[i, 3]
        tz = nodes[i, 4]
        return (nodes[i, 1] + ds * ty, nodes[i, 2] + ds * tz, ty, tz, -sign * tz, sign * ty, 0.0)
    hh = h * h
    b = _basis(u)
    u2 = u * u
    u3 = u2 * u
    # second derivatives of the basis with respect to u (e3 = -e0)
    e0 = -60.0 * u + 180.0 * u2 - 120.0 * u3
    e1 = -36.0 * u + 96.0 * u2 - 60.0 * u3
    e2 = 0.5 * (2.0 - 18.0 * u + 36.0 * u2 - 20.0 * u3)
    e4 = -24.0 * u + 84.0 * u2 - 60.0 * u3
    e5 = 0.5 * (6.0 * u - 24.0 * u2 + 20.0 * u3)
    py, dy, dp, t0, a0, t1, a1 = _hermite(nodes, i, 1, h, hh, b)
    ddy = (e0 * dp + e1 * t0 + e2 * a0 + e4 * t1 + e5 * a1) / hh
    pz, dz, dp, t0, a0, t1, a1 = _hermite(nodes, i, 2, h, hh, b)
    ddz = (e0 * dp + e1 * t0 + e2 * a0 + e4 * t1 + e5 * a1) / hh
    speed = np.sqrt(dy * dy + dz * dz)
    ty = dy / speed
    tz = dz / speed
    # signed curvature about J t = (-t_z, t_y); kappa (convex positive) = -normal_sign * k_J
    k_j = (dy * ddz - dz * ddy) / (speed * speed * speed)
    return (py, pz, ty, tz, -sign * tz, sign * ty, -sign * k_j)


@compiled(refcount=False, error_model="numpy")
def curve_point(nodes, meta, curve, s):
    """``(p_y, p_z, t_y, t_z)`` of :func:`curve_eval` (the same numbers) without the second derivatives: for the
    searches that need the point and its tangent only."""
    inside, i, h, u = _segment_at(nodes, meta, curve, s)
    if not inside:
        ds = s - nodes[i, 0]
        ty = nodes[i, 3]
        tz = nodes[i, 4]
        return nodes[i, 1] + ds * ty, nodes[i, 2] + ds * tz, ty, tz
    b = _basis(u)
    py, dy, _, _, _, _, _ = _hermite(nodes, i, 1, h, h * h, b)
    pz, dz, _, _, _, _, _ = _hermite(nodes, i, 2, h, h * h, b)
    speed = np.sqrt(dy * dy + dz * dz)
    return py, pz, dy / speed, dz / speed


@compiled
def curve_eval_many(nodes, meta, curve, s_values):
    """Vectorised :func:`curve_eval`: returns an array (len(s), 7)."""
    out = np.empty((s_values.shape[0], 7))
    for j in range(s_values.shape[0]):
        r = curve_eval(nodes, meta, curve, s_values[j])
        for k in range(7):
            out[j, k] = r[k]
    return out


class ProfileCurve:
    """A plane profile curve parameterised by arc length ``s`` [m] (see module docstring).

    Build it with :meth:`from_dense`; evaluate with :meth:`evaluate` (or the properties-style helpers
    :meth:`position`, :meth:`tangent`, :meth:`normal`, :meth:`curvature`).
    """

    def __init__(self, nodes: np.ndarray, normal_sign: float, name: str = "curve", fit_error_m: float = 0.0):
        nodes = np.ascontiguousarray(nodes, dtype=float)
        if nodes.ndim != 2 or nodes.shape[1] != NODE_COLUMNS or nodes.shape[0] < 2:
            raise ValueError(f"{name}: nodes must be an (N>=2, {NODE_COLUMNS}) array")
        if np.any(np.diff(nodes[:, 0]) <= 0):
            raise ValueError(f"{name}: node arc lengths must increase strictly")
        if normal_sign not in (1.0, -1.0, 1, -1):
            raise ValueError(f"{name}: normal_sign must be +1 or -1")
        self.nodes = nodes
        self.normal_sign = float(normal_sign)
        self.name = name
        self.fit_error_m = float(fit_error_m)
        #: which ends are ends of the real profile (1 start, 2 stop); set by the owner of a sub-curve
        self.end_flags = 3
        self.meta = np.array([[0.0, nodes.shape[0], self.normal_sign, 0.0, 3.0]])
        self.meta[0, 3] = (nodes[-1, 0] - nodes[0, 0]) / (nodes.shape[0] - 1)

    # ----------------------------------------------------------------------------------------------- building
    @classmethod
    def from_dense(cls, dense: DenseProfile, outward: str, node_spacing_m: float = 2.5e-4,
                   name: str | None = None) -> "ProfileCurve":
        """Arc-length curve through a dense exact description (points ordered along the curve; the derivative
        parameter may run either way).

        ``outward`` is the side of the material's outward normal in the profile frame: ``'+z'`` for a wheel
        (towards the rail, z = radius increase) and ``'-z'`` for a rail (upwards).  Nodes are a subset of the
        dense samples about ``node_spacing_m`` apart; the fit is checked against every dense sample.
        """
        name = name or dense.name
        p = np.column_stack([dense.y, dense.z])
        dp = np.column_stack([dense.dy, dense.dz])
        ddp = np.column_stack([dense.ddy, dense.ddz])
        speed = np.hypot(dp[:, 0], dp[:, 1])
        if np.any(speed <= 0):
            raise ValueError(f"{name}: zero parametric speed (repeated points or a cusp)")
        t = dp / speed[:, None]
        # the parameter may run against the point order: orient the tangent along the order (d2p/dtau2 is even)
        chord_dir = np.diff(p, axis=0)
        if np.median(np.sum(t[:-1] * chord_dir, axis=1)) < 0:
            t = -t
        a = (ddp - np.sum(ddp * t, axis=1)[:, None] * t) / (speed ** 2)[:, None]
        chord = np.hypot(*np.diff(p, axis=0).T)
        if np.any(chord <= 0):
            raise ValueError(f"{name}: repeated consecutive points")
        # arc = chord * (1 + chord^2 kappa^2 / 24) for a locally circular piece
        kappa_mid = 0.5 * (np.hypot(*a[:-1].T) + np.hypot(*a[1:].T))
        s = np.concatenate([[0.0], np.cumsum(chord * (1.0 + chord ** 2 * kappa_mid ** 2 / 24.0))])
        # orientation of the outward normal: J t = (-t_z, t_y); check against the requested side at the middle
        j_t = np.column_stack([-t[:, 1], t[:, 0]])
        if outward == "+z":
            sign = 1.0 if np.median(j_t[:, 1]) > 0 else -1.0
        elif outward == "-z":
            sign = 1.0 if np.median(j_t[:, 1]) < 0 else -1.0
        else:
            raise ValueError("outward must be '+z' (wheel) or '-z' (rail)")
        # choose nodes: every k-th sample, ends included
        step = max(1, int(round(node_spacing_m / max(np.median(chord), 1e-12))))
        idx = np.unique(np.concatenate([np.arange(0, len(s), step), [len(s) - 1]]))
        if len(idx) >= 3 and s[idx[-1]] - s[idx[-2]] < 0.25 * node_spacing_m:
            idx = np.delete(idx, -2)
        nodes = np.column_stack([s[idx], p[idx], t[idx], a[idx]])
        curve = cls(nodes, sign, name)
        fit = curve_eval_many(curve.nodes, curve.meta, 0, s)
        curve.fit_error_m = float(np.max(np.hypot(fit[:, 0] - p[:, 0], fit[:, 1] - p[:, 1])))
        return curve

    def transformed(self, angle_rad: float = 0.0, offset=(0.0, 0.0), name: str | None = None) -> "ProfileCurve":
        """The curve rotated by ``angle_rad`` (positive turns +y towards +z) and then shifted by ``offset``."""
        c, sn = np.cos(angle_rad), np.sin(angle_rad)
        rot = np.array([[c, -sn], [sn, c]])
        n = self.nodes.copy()
        for col in (1, 3, 5):
            n[:, col:col + 2] = n[:, col:col + 2] @ rot.T
        n[:, 1] += offset[0]
        n[:, 2] += offset[1]
        moved = ProfileCurve(n, self.normal_sign, name or self.name, self.fit_error_m)
        moved.end_flags = self.end_flags
        return moved

    def sub(self, s_start: float, s_end: float, name: str | None = None) -> "ProfileCurve":
        """The piece between arc lengths ``s_start`` and ``s_end`` (same parameter values, exact end nodes)."""
        if not (self.s_min <= s_start < s_end <= self.s_max):
            raise ValueError(f"{self.name}: sub-range [{s_start}, {s_end}] outside [{self.s_min}, {self.s_max}]")
        inner = self.nodes[(self.nodes[:, 0] > s_start + 1e-9) & (self.nodes[:, 0] < s_end - 1e-9)]
        ends = []
        for s_end_k in (s_start, s_end):
            r = curve_eval(self.nodes, self.meta, 0, s_end_k)
            kappa = r[6]
            ends.append([s_end_k, r[0], r[1], r[2], r[3], -kappa * r[4], -kappa * r[5]])
        nodes = np.vstack([ends[0], inner, ends[1]])
        return ProfileCurve(nodes, self.normal_sign, name or self.name, self.fit_error_m)

    # ----------------------------------------------------------------------------------------------- queries
    @property
    def s_min(self) -> float:
        return float(self.nodes[0, 0])

    @property
    def s_max(self) -> float:
        return float(self.nodes[-1, 0])

    @property
    def length(self) -> float:
        return self.s_max - self.s_min

    def evaluate(self, s) -> np.ndarray:
        """Array (len(s), 7): p_y, p_z, t_y, t_z, n_y, n_z, kappa at arc lengths ``s``."""
        return curve_eval_many(self.nodes, self.meta, 0, np.atleast_1d(np.asarray(s, dtype=float)))

    def position(self, s) -> np.ndarray:
        return self.evaluate(s)[:, 0:2]

    def tangent(self, s) -> np.ndarray:
        return self.evaluate(s)[:, 2:4]

    def normal(self, s) -> np.ndarray:
        return self.evaluate(s)[:, 4:6]

    def curvature(self, s) -> np.ndarray:
        return self.evaluate(s)[:, 6]

    def sample(self, spacing_m: float = 1e-4) -> np.ndarray:
        """Points (N, 2) every ``spacing_m`` of arc length (for plots and brute-force checks)."""
        s = np.linspace(self.s_min, self.s_max, max(2, int(np.ceil(self.length / spacing_m)) + 1))
        return self.position(s)

    def __repr__(self) -> str:
        return (f"ProfileCurve({self.name!r}, s=[{self.s_min:.4f}, {self.s_max:.4f}] m, "
                f"{self.nodes.shape[0]} nodes, fit error {self.fit_error_m * 1e6:.2f} um)")


def pack_curves(curves: list[ProfileCurve]) -> tuple[np.ndarray, np.ndarray]:
    """Pack curves into the (nodes, meta) arrays the compiled kernels take."""
    nodes = np.vstack([c.nodes for c in curves])
    meta = np.zeros((len(curves), META_COLUMNS))
    row = 0
    for k, c in enumerate(curves):
        meta[k] = [row, c.nodes.shape[0], c.normal_sign, c.meta[0, 3], c.end_flags]
        row += c.nodes.shape[0]
    return np.ascontiguousarray(nodes), meta
