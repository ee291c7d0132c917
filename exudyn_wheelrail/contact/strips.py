r"""The strips of a contact zone: the interpenetration of the undeformed wheel and rail profiles, strip by strip
across the rolling direction, in the contact plane of a kernel contact point (the geometry of :mod:`.patch`).

The **contact plane** is the tangent plane of the rail at the kernel's contact point ``o``: normal
``n_rail_in_side`` (outward, towards the wheel), lateral tangent ``t = (-n_z, n_y)`` (side frame).  A strip is a
lateral coordinate η along ``t``; at each η the rail and the wheel profile are cut by the line ``o + η t + ζ n``
(Newton on each curve's arc length, the wheel's tread and flange curves sharing the profile's arc length) and

* ``g(η) = ζ_rail - ζ_wheel`` is the interpenetration of the undeformed profiles along ``n`` (positive: overlap);
* ``A(η) = (κ_w,roll(η) + κ_r,roll)/2`` the relative curvature in the rolling direction (the wheel's by Meusnier,
  ``n_z/r`` of its own normal, as in the kernel): the interpenetration at ``(x, η)`` is ``g(η) - A(η) x²``
  (rigid rail, wheel of revolution, yaw neglected — as for Hertz in :mod:`.normal`);
* ``γ(η)`` the contact angle of the rail normal at the strip (positive towards the track centre, as the kernel's).

The zone is the interval around ``o`` where ``g`` exceeds a level (0: the overlap; stepping out, then bisecting),
so a conformal zone with two maxima of ``g`` is one zone.
"""
from __future__ import annotations

import math

from ..jit import compiled
from ..profiles.curve import curve_eval, curve_point
from .search import place_point

__all__ = ["S_G", "S_A", "S_GAMMA", "S_RADIUS", "S_RAIL_Y", "S_RAIL_Z", "S_S_RAIL", "S_S_WHEEL", "S_OK", "S_ETA",
           "S_WIDTH", "N_STRIP_FIELDS", "curve_of", "strip_at", "zone_edges", "fill_strips"]

# one strip's fields (a row of the strips' array)
S_G = 0          # interpenetration g of the undeformed profiles along the plane's normal [m]
S_A = 1          # relative curvature in the rolling direction [1/m]
S_GAMMA = 2      # contact angle of the rail normal at the strip [rad]
S_RADIUS = 3     # wheel's rolling radius at the strip [m]
S_RAIL_Y = 4     # rail point of the strip, side frame [m]
S_RAIL_Z = 5
S_S_RAIL = 6     # rail arc length [m]
S_S_WHEEL = 7    # wheel arc length [m]
S_OK = 8         # 1 when both Newton solves converged
S_ETA = 9        # the strip's lateral coordinate in the contact plane [m]
S_WIDTH = 10     # the strip's width [m]
N_STRIP_FIELDS = 11

_NEWTON_TOL_M = 1e-10
_NEWTON_MAX = 12
_BISECTIONS = 20      # an edge to 1e-6 of the step
_MAX_HALF_WIDTH_M = 0.06


@compiled(refcount=False)
def curve_of(nodes, meta, first, second, s):
    """The curve holding arc length ``s`` of a profile split in two curves sharing its arc length: ``second`` (the
    wheel's flange, or -1 for an unsplit profile) before ``first``'s first node, else ``first``."""
    if second >= 0 and s < nodes[int(meta[first, 0]), 0]:
        return second
    return first


@compiled(refcount=False)
def _point_at(nodes, meta, first, second, s0, c_y, c_z, cos_r, sin_r, o_y, o_z, t_y, t_z, eta):
    """Arc length of the profile point (placed by the pose; the rail: the identity) with lateral coordinate η on
    the plane, Newton from ``s0``: (s, ok)."""
    s = s0
    for _ in range(_NEWTON_MAX):
        py, pz, ty, tz = curve_point(nodes, meta, curve_of(nodes, meta, first, second, s), s)
        wy, wz = place_point(py, pz, c_y, c_z, cos_r, sin_r)
        f = (wy - o_y) * t_y + (wz - o_z) * t_z - eta
        df = (cos_r * ty - sin_r * tz) * t_y + (sin_r * ty + cos_r * tz) * t_z
        if abs(df) < 1e-6:
            return s, False
        ds = f / df
        s -= ds
        if abs(ds) < _NEWTON_TOL_M:
            return s, True
    return s, False


@compiled(refcount=False)
def strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, s_r0, s_w0, k_rail_roll,
             eta, row):
    """Fill ``row`` (fields S_*) with the strip at lateral coordinate ``eta`` of the plane (``o``, ``n``); the
    Newton solves start from ``s_r0``, ``s_w0``.  Returns the interpenetration g."""
    t_y = -n_z
    t_z = n_y
    s_r, ok_r = _point_at(nodes, meta, rail, -1, s_r0, 0.0, 0.0, 1.0, 0.0, o_y, o_z, t_y, t_z, eta)
    s_w, ok_w = _point_at(nodes, meta, tread, flange, s_w0, c_y, c_z, cos_r, sin_r, o_y, o_z, t_y, t_z, eta)
    ry, rz, _, _, rny, rnz, _ = curve_eval(nodes, meta, rail, s_r)
    qy, qz, _, _, _, qnz, _ = curve_eval(nodes, meta, curve_of(nodes, meta, tread, flange, s_w), s_w)
    wy, wz = place_point(qy, qz, c_y, c_z, cos_r, sin_r)
    g = (ry - wy) * n_y + (rz - wz) * n_z
    row[S_G] = g
    row[S_A] = 0.5 * (qnz / qz + k_rail_roll)
    row[S_GAMMA] = math.atan2(-rny, -rnz)
    row[S_RADIUS] = qz
    row[S_RAIL_Y] = ry
    row[S_RAIL_Z] = rz
    row[S_S_RAIL] = s_r
    row[S_S_WHEEL] = s_w
    row[S_OK] = 1.0 if (ok_r and ok_w) else 0.0
    row[S_ETA] = eta
    return g


@compiled(refcount=False)
def zone_edges(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, s_r0, s_w0,
               k_rail_roll, level, step, row):
    """The interval (η_lo, η_hi) around η = 0 where the interpenetration exceeds ``level`` (stepping out by
    ``step`` — Hertz's lateral semi-axis is the natural one — then bisecting); ``g(0) > level`` is assumed."""
    out_lo = 0.0
    out_hi = 0.0
    for side in range(2):
        sgn = -1.0 if side == 0 else 1.0
        inside = 0.0
        outside = sgn * step
        sr, sw = s_r0, s_w0
        while abs(outside) < _MAX_HALF_WIDTH_M:
            if strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, sr, sw,
                        k_rail_roll, outside, row) <= level:
                break
            sr, sw = row[S_S_RAIL], row[S_S_WHEEL]
            inside = outside
            outside += sgn * step
        for _ in range(_BISECTIONS):
            mid = 0.5 * (inside + outside)
            if strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, sr, sw,
                        k_rail_roll, mid, row) > level:
                inside = mid
            else:
                outside = mid
        if side == 0:
            out_lo = inside
        else:
            out_hi = inside
    return out_lo, out_hi


@compiled(refcount=False)
def fill_strips(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, s_r0, s_w0,
                k_rail_roll, eta_lo, eta_hi, strips):
    """The strips of equal width over [η_lo, η_hi] (their centres), each row of ``strips`` filled (S_*)."""
    n = strips.shape[0]
    w = (eta_hi - eta_lo) / n
    # from the contact point outwards, so that each Newton solve starts next to its answer
    j0 = min(max(int((0.0 - eta_lo) / w), 0), n - 1)
    sr, sw = s_r0, s_w0
    for j in range(j0, n):
        strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, sr, sw, k_rail_roll,
                 eta_lo + (j + 0.5) * w, strips[j])
        strips[j, S_WIDTH] = w
        sr, sw = strips[j, S_S_RAIL], strips[j, S_S_WHEEL]
    sr, sw = s_r0, s_w0
    for j in range(j0 - 1, -1, -1):
        strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, sr, sw, k_rail_roll,
                 eta_lo + (j + 0.5) * w, strips[j])
        strips[j, S_WIDTH] = w
        sr, sw = strips[j, S_S_RAIL], strips[j, S_S_WHEEL]
