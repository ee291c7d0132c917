"""Contact-point search between one wheel region (tread or flange function) and a rail, compiled with numba.

Method: Montenegro, Neves, Calçada, Tanabe & Sogabe, "Wheel–rail contact formulation for analyzing the lateral
train–structure dynamic interaction", Computers & Structures 152 (2015) 200–214, Sec. 2.

All geometry is in the side frame of :mod:`exudyn_wheelrail.conventions` (y to the field side, z down) with the
rail fixed; the wheel curve is given in the wheelset frame and placed by its pose ``(c_y, c_z, roll)``.

* :func:`convex_newton` — Newton on the two contact conditions (paper Eqs. 5–6)
  ``f1 = t_r · (p_w - p_r) = 0`` and ``f2 = n_r · t_w = 0`` in the surface parameters (s_r, s_w), with the
  analytic Jacobian from ``dt/ds = -kappa n`` and ``dn/ds = kappa t``.
* :func:`vertical_overlap_search` — the *concave search* (paper Eqs. 8–13): both surfaces discretised, each point
  projected vertically onto the other surface, the pair of maximum vertical overlap taken; optionally refined to
  the continuous maximum (where the two tangents are parallel).  The same routine with penetration allowed to be
  negative is the *global scan* that starts Newton from the best basin (contact jumps).
"""
from __future__ import annotations

import numpy as np

from ..jit import compiled
from ..profiles.curve import curve_eval, curve_point

NEWTON_MAX_STEP_M = 3e-3


@compiled(inline="always")
def place_point(p_y, p_z, c_y, c_z, cos_r, sin_r):
    """A point of the wheelset frame placed by the pose (c_y, c_z, roll): its side-frame (y, z)."""
    return c_y + cos_r * p_y - sin_r * p_z, c_z + sin_r * p_y + cos_r * p_z


@compiled(inline="always")
def place_wheel_point(py, pz, ty, tz, ny, nz, k, c_y, c_z, cos_r, sin_r):
    """A wheel curve's ``curve_eval`` output placed by the pose: (p_y, p_z, t_y, t_z, n_y, n_z, kappa), side frame."""
    wy, wz = place_point(py, pz, c_y, c_z, cos_r, sin_r)
    return (wy, wz, cos_r * ty - sin_r * tz, sin_r * ty + cos_r * tz,
            cos_r * ny - sin_r * nz, sin_r * ny + cos_r * nz, k)


@compiled(inline="always")
def wheel_position(nodes, meta, curve, s, c_y, c_z, cos_r, sin_r):
    """The position of :func:`wheel_point` alone (the same numbers): (p_y, p_z) in the side frame."""
    py, pz, ty, tz = curve_point(nodes, meta, curve, s)
    return place_point(py, pz, c_y, c_z, cos_r, sin_r)


@compiled(inline="always")
def rail_point(nodes, meta, rail, s):
    """The rail's point and outward normal at ``s`` (those of :func:`curve_eval`, the same numbers):
    (p_y, p_z, n_y, n_z)."""
    py, pz, ty, tz = curve_point(nodes, meta, rail, s)
    sign = meta[rail, 2]
    return py, pz, -sign * tz, sign * ty


@compiled(inline="always")
def wheel_point(nodes, meta, curve, s, c_y, c_z, cos_r, sin_r):
    """Wheel curve point at ``s`` placed by the pose: (p_y, p_z, t_y, t_z, n_y, n_z, kappa) in the side frame."""
    py, pz, ty, tz, ny, nz, k = curve_eval(nodes, meta, curve, s)
    return place_wheel_point(py, pz, ty, tz, ny, nz, k, c_y, c_z, cos_r, sin_r)


@compiled(refcount=False)
def convex_newton(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, s_r, s_w, max_iter, tol_m):
    """Newton iteration on the contact conditions from (s_r, s_w).

    Returns ``(converged, s_r, s_w, iterations)``; steps are limited to 3 mm.
    """
    return newton_from(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, s_r, s_w, max_iter, tol_m,
                       curve_eval(nodes, meta, rail, s_r), curve_eval(nodes, meta, wheel, s_w))


@compiled(refcount=False)
def newton_from(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, s_r, s_w, max_iter, tol_m, rail_curve,
                wheel_curve):
    """:func:`convex_newton` with the curves at the start already evaluated: ``rail_curve`` and ``wheel_curve``
    :func:`curve_eval` of the rail at ``s_r`` and of the wheel at ``s_w`` (the wheelset frame, before the pose)."""
    r = rail_curve
    q = wheel_curve
    for it in range(max_iter):
        if it > 0:
            r = curve_eval(nodes, meta, rail, s_r)
            q = curve_eval(nodes, meta, wheel, s_w)
        ry, rz, rty, rtz, rny, rnz, rk = r
        wy, wz, wty, wtz, wny, wnz, wk = place_wheel_point(q[0], q[1], q[2], q[3], q[4], q[5], q[6], c_y, c_z,
                                                           cos_r, sin_r)
        dy = wy - ry
        dz = wz - rz
        f1 = rty * dy + rtz * dz
        f2 = rny * wty + rnz * wtz
        nd = rny * dy + rnz * dz
        tt = rty * wty + rtz * wtz
        j11 = -rk * nd - 1.0
        j12 = tt
        j21 = rk * tt
        j22 = -wk * (rny * wny + rnz * wnz)
        det = j11 * j22 - j12 * j21
        if abs(det) < 1e-12:
            return False, s_r, s_w, it + 1
        d_r = -(f1 * j22 - j12 * f2) / det
        d_w = -(j11 * f2 - j21 * f1) / det
        step = max(abs(d_r), abs(d_w))
        if step > NEWTON_MAX_STEP_M:
            d_r *= NEWTON_MAX_STEP_M / step
            d_w *= NEWTON_MAX_STEP_M / step
        s_r += d_r
        s_w += d_w
        if step < tol_m:
            return True, s_r, s_w, it + 1
    return False, s_r, s_w, max_iter


@compiled(refcount=False)
def project_vertical(nodes, meta, curve, row_lo, row_hi, y_target, c_y, c_z, cos_r, sin_r):
    """Arc length of the point of ``curve`` (placed by the pose) with side-frame lateral coordinate ``y_target``.

    Only the stretch of rows [row_lo, row_hi] is searched, on which y must increase with s (the part of the
    profile that a vertical line meets once).  Returns ``(found, s)``.
    """
    y_lo = c_y + cos_r * nodes[row_lo, 1] - sin_r * nodes[row_lo, 2]
    y_hi = c_y + cos_r * nodes[row_hi, 1] - sin_r * nodes[row_hi, 2]
    if not (y_lo <= y_target <= y_hi):
        return False, 0.0
    a = row_lo
    b = row_hi
    while b - a > 1:
        m = (a + b) // 2
        ym = c_y + cos_r * nodes[m, 1] - sin_r * nodes[m, 2]
        if ym <= y_target:
            a = m
        else:
            b = m
    ya = c_y + cos_r * nodes[a, 1] - sin_r * nodes[a, 2]
    yb = c_y + cos_r * nodes[b, 1] - sin_r * nodes[b, 2]
    s = nodes[a, 0] + (y_target - ya) / (yb - ya) * (nodes[b, 0] - nodes[a, 0])
    for _ in range(6):
        py, pz, ty, tz = curve_point(nodes, meta, curve, s)
        dyds = cos_r * ty - sin_r * tz
        ds = (y_target - (c_y + cos_r * py - sin_r * pz)) / dyds
        s += ds
        if abs(ds) < 1e-13:
            break
    return True, s


@compiled(inline="always")
def overlap_at_wheel(nodes, meta, mono, rail, wheel, s_w, c_y, c_z, cos_r, sin_r):
    """Vertical overlap (z_w - z_r, positive = penetration) of the wheel point at s_w; (found, overlap, s_r)."""
    wy, wz = wheel_position(nodes, meta, wheel, s_w, c_y, c_z, cos_r, sin_r)
    ok, s_r = project_vertical(nodes, meta, rail, mono[rail, 0], mono[rail, 1], wy, 0.0, 0.0, 1.0, 0.0)
    if not ok:
        return False, -1.0, 0.0
    ry, rz, rty, rtz = curve_point(nodes, meta, rail, s_r)
    return True, wz - rz, s_r


@compiled(inline="always")
def _slope_mismatch(nodes, meta, rail, wheel, s_w, s_r, c_y, c_z, cos_r, sin_r):
    """Derivative sign of the vertical overlap along the wheel: cross(t_w, t_r) (zero at the maximum)."""
    wy, wz, wty, wtz, wny, wnz, wk = wheel_point(nodes, meta, wheel, s_w, c_y, c_z, cos_r, sin_r)
    ry, rz, rty, rtz, rny, rnz, rk = curve_eval(nodes, meta, rail, s_r)
    # d(z_w - z_r)/ds_w = t_wz - (t_rz / t_ry) t_wy  ->  sign of (t_wz t_ry - t_rz t_wy) for t_ry > 0
    return wtz * rty - rtz * wty


@compiled(refcount=False)
def vertical_overlap_search(nodes, meta, mono, rail, wheel, c_y, c_z, cos_r, sin_r, s_w_lo, s_w_hi,
                            n_wheel, n_rail, refine):
    """Maximum vertical overlap between a wheel region [s_w_lo, s_w_hi] and the rail (paper Eqs. 8–13).

    ``n_wheel`` wheel points are projected vertically onto the rail and ``n_rail`` rail points (within the wheel
    region's lateral window) onto the wheel; the pair of largest overlap ``z_w - z_r`` wins.  With ``refine`` the
    maximum is then located on the continuous curves (bracketed root of the slope mismatch, Illinois method).
    Returns ``(found, s_w, s_r, overlap_m)``; the overlap is negative when the surfaces are apart (then it is the
    smallest vertical gap, with sign flipped) — callers decide contact on its sign.
    """
    best = -1e30
    best_sw = 0.5 * (s_w_lo + s_w_hi)
    best_sr = 0.0
    found = False
    h_w = (s_w_hi - s_w_lo) / (n_wheel - 1)
    y_min = 1e30
    y_max = -1e30
    for k in range(n_wheel):
        s_w = s_w_lo + h_w * k
        wy, wz = wheel_position(nodes, meta, wheel, s_w, c_y, c_z, cos_r, sin_r)
        y_min = min(y_min, wy)
        y_max = max(y_max, wy)
        ok, dv, s_r = overlap_at_wheel(nodes, meta, mono, rail, wheel, s_w, c_y, c_z, cos_r, sin_r)
        if ok and dv > best:
            best = dv
            best_sw = s_w
            best_sr = s_r
            found = True
    # rail points projected onto the wheel region (its monotone stretch)
    if n_rail > 1 and mono[wheel, 1] > mono[wheel, 0]:
        r_lo = nodes[mono[rail, 0], 0]
        r_hi = nodes[mono[rail, 1], 0]
        h_r = (r_hi - r_lo) / (n_rail - 1)
        for k in range(n_rail):
            s_r = r_lo + h_r * k
            ry, rz, rty, rtz = curve_point(nodes, meta, rail, s_r)
            if ry < y_min or ry > y_max:
                continue
            ok, s_w = project_vertical(nodes, meta, wheel, mono[wheel, 0], mono[wheel, 1], ry,
                                       c_y, c_z, cos_r, sin_r)
            if not ok or s_w < s_w_lo or s_w > s_w_hi:
                continue
            wy, wz = wheel_position(nodes, meta, wheel, s_w, c_y, c_z, cos_r, sin_r)
            if wz - rz > best:
                best = wz - rz
                best_sw = s_w
                best_sr = s_r
                found = True
    if not found or not refine:
        return found, best_sw, best_sr, best
    # refine: bracket [s - h, s + h] around the best sample, root of the slope mismatch
    a = max(s_w_lo, best_sw - h_w)
    b = min(s_w_hi, best_sw + h_w)
    ok_a, dv_a, sr_a = overlap_at_wheel(nodes, meta, mono, rail, wheel, a, c_y, c_z, cos_r, sin_r)
    ok_b, dv_b, sr_b = overlap_at_wheel(nodes, meta, mono, rail, wheel, b, c_y, c_z, cos_r, sin_r)
    if not (ok_a and ok_b):
        return found, best_sw, best_sr, best
    ga = _slope_mismatch(nodes, meta, rail, wheel, a, sr_a, c_y, c_z, cos_r, sin_r)
    gb = _slope_mismatch(nodes, meta, rail, wheel, b, sr_b, c_y, c_z, cos_r, sin_r)
    if ga * gb > 0.0:
        return found, best_sw, best_sr, best     # maximum at the region's end: keep the sample
    side = 0
    for _ in range(60):
        c = (a * gb - b * ga) / (gb - ga)
        ok_c, dv_c, sr_c = overlap_at_wheel(nodes, meta, mono, rail, wheel, c, c_y, c_z, cos_r, sin_r)
        if not ok_c:
            break
        gc = _slope_mismatch(nodes, meta, rail, wheel, c, sr_c, c_y, c_z, cos_r, sin_r)
        if dv_c > best:
            best = dv_c
            best_sw = c
            best_sr = sr_c
        if abs(b - a) < 1e-11 or gc == 0.0:
            break
        if gc * gb > 0.0:
            b = c
            gb = gc
            if side == -1:
                ga *= 0.5
            side = -1
        else:
            a = c
            ga = gc
            if side == 1:
                gb *= 0.5
            side = 1
    return found, best_sw, best_sr, best


@compiled(refcount=False)
def normal_foot(nodes, meta, rail, p_y, p_z, s_r):
    """Arc length of the rail point whose normal passes through (p_y, p_z), by Newton from ``s_r``.

    Solves ``t_r(s) · (p - r(s)) = 0``; returns ``(converged, s_r)``.
    """
    for _ in range(20):
        ry, rz, rty, rtz, rny, rnz, rk = curve_eval(nodes, meta, rail, s_r)
        dy = p_y - ry
        dz = p_z - rz
        g = rty * dy + rtz * dz
        dg = -rk * (rny * dy + rnz * dz) - 1.0
        if dg == 0.0:
            return False, s_r
        step = -g / dg
        if abs(step) > NEWTON_MAX_STEP_M:
            step = NEWTON_MAX_STEP_M if step > 0 else -NEWTON_MAX_STEP_M
        s_r += step
        if abs(step) < 1e-13:
            return True, s_r
    return False, s_r


@compiled(refcount=False)
def nearest_start(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, s_w_lo, s_w_hi, n_wheel, n_rail, rail_y, rail_z):
    """Newton start when nothing overlaps vertically: the nearest pair among ``n_wheel`` wheel-region samples and
    ``n_rail`` samples of the whole rail curve (gauge face included), the rail's kept in ``rail_y``, ``rail_z``
    (at least ``n_rail`` long).  Returns ``(s_w, s_r)``."""
    first = int(meta[rail, 0])
    r_lo = nodes[first, 0]
    r_hi = nodes[first + int(meta[rail, 1]) - 1, 0]
    for j in range(n_rail):
        ry, rz, rty, rtz = curve_point(nodes, meta, rail, r_lo + (r_hi - r_lo) * j / (n_rail - 1))
        rail_y[j] = ry
        rail_z[j] = rz
    best = 1e30
    best_sw = s_w_lo
    best_j = 0
    for k in range(n_wheel):
        s_w = s_w_lo + (s_w_hi - s_w_lo) * k / (n_wheel - 1)
        wy, wz = wheel_position(nodes, meta, wheel, s_w, c_y, c_z, cos_r, sin_r)
        for j in range(n_rail):
            d = (wy - rail_y[j]) ** 2 + (wz - rail_z[j]) ** 2
            if d < best:
                best = d
                best_sw = s_w
                best_j = j
    return best_sw, r_lo + (r_hi - r_lo) * best_j / (n_rail - 1)


@compiled(refcount=False)
def nearest_by_normal_distance(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, s_w_lo, s_w_hi, n_wheel, s_r0):
    """Wheel point of the region with the smallest signed normal distance to the rail (global over the region).

    ``n_wheel`` samples, each with its normal foot on the rail (Newton warm-started along the samples), then a
    golden-section refinement between the neighbours of the best sample.  Returns
    ``(found, all_samples_ok, s_w, s_r, distance)``; ``all_samples_ok`` is False when the normal foot of some
    sample could not be found (the minimum is then not guaranteed to the sampling resolution).
    """
    best = 1e30
    best_sw = s_w_lo
    best_sr = s_r0
    s_r = s_r0
    found = False
    all_ok = True
    h = (s_w_hi - s_w_lo) / (n_wheel - 1)
    for k in range(n_wheel):
        s_w = s_w_lo + h * k
        wy, wz = wheel_position(nodes, meta, wheel, s_w, c_y, c_z, cos_r, sin_r)
        ok, s_f = normal_foot(nodes, meta, rail, wy, wz, s_r)
        if not ok:
            all_ok = False
            continue
        s_r = s_f
        ry, rz, rny, rnz = rail_point(nodes, meta, rail, s_f)
        d = (wy - ry) * rny + (wz - rz) * rnz
        if d < best:
            best = d
            best_sw = s_w
            best_sr = s_f
            found = True
    if not found:
        return False, False, best_sw, best_sr, best
    a = max(s_w_lo, best_sw - h)
    b = min(s_w_hi, best_sw + h)
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    s_r = best_sr
    for _ in range(40):
        c = b - g * (b - a)
        d_ = a + g * (b - a)
        wy, wz = wheel_position(nodes, meta, wheel, c, c_y, c_z, cos_r, sin_r)
        ok_c, sc = normal_foot(nodes, meta, rail, wy, wz, s_r)
        ry, rz, rny, rnz = rail_point(nodes, meta, rail, sc)
        fc = (wy - ry) * rny + (wz - rz) * rnz
        wy, wz = wheel_position(nodes, meta, wheel, d_, c_y, c_z, cos_r, sin_r)
        ok_d, sd = normal_foot(nodes, meta, rail, wy, wz, s_r)
        ry, rz, rny, rnz = rail_point(nodes, meta, rail, sd)
        fd = (wy - ry) * rny + (wz - rz) * rnz
        if ok_c and fc < best:
            best, best_sw, best_sr = fc, c, sc
        if ok_d and fd < best:
            best, best_sw, best_sr = fd, d_, sd
        if fc < fd:
            b = d_
        else:
            a = c
        if b - a < 1e-10:
            break
    return True, all_ok, best_sw, best_sr, best


@compiled(inline="always")
def _normal_distance_slope(nodes, meta, rail, wheel, s_w, s_r, c_y, c_z, cos_r, sin_r):
    """Signed normal distance of the wheel point at ``s_w`` to the rail and its derivative along the wheel.

    The derivative is ``n_r · t_w`` at the normal foot (the foot's own motion drops out: ``t_r`` is orthogonal to
    ``p_w - r`` there).  Returns ``(ok, s_foot, distance, slope)``; ``ok`` is False when the foot is not found.
    """
    wy, wz, wty, wtz, wny, wnz, wk = wheel_point(nodes, meta, wheel, s_w, c_y, c_z, cos_r, sin_r)
    ok, s_f = normal_foot(nodes, meta, rail, wy, wz, s_r)
    ry, rz, rty, rtz, rny, rnz, rk = curve_eval(nodes, meta, rail, s_f)
    return ok, s_f, (wy - ry) * rny + (wz - rz) * rnz, wty * rny + wtz * rnz


@compiled(refcount=False)
def normal_penetration_ascent(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, s_w, s_r, s_w_lo, s_w_hi, step):
    """Follow the normal penetration uphill along the wheel region [s_w_lo, s_w_hi] from the point ``s_w``.

    The signed normal distance is walked in steps of ``step`` in the direction in which it falls until its slope
    changes sign (a local maximum of the penetration, then located as the root of the slope by the Illinois method
    to 1e-11 m), or until the region's end, where the penetration is then still rising: the zone's deepest point
    lies beyond that end.  ``s_r`` is the start of the normal-foot Newton.  Returns
    ``(ok, s_w, s_r, distance, at_end)``; ``ok`` is False when a normal foot is not found.
    """
    ok, s_r, d, g = _normal_distance_slope(nodes, meta, rail, wheel, s_w, s_r, c_y, c_z, cos_r, sin_r)
    if not ok or g == 0.0:
        return ok, s_w, s_r, d, False
    direction = 1.0 if g < 0.0 else -1.0      # the distance falls along -g
    a, sr_a, d_a, g_a = s_w, s_r, d, g
    b, sr_b, d_b, g_b = s_w, s_r, d, g
    n_steps = int((s_w_hi - s_w_lo) / step) + 2
    bracketed = False
    for _ in range(n_steps):
        b = a + direction * step
        at_end = False
        if b >= s_w_hi:
            b = s_w_hi
            at_end = True
        elif b <= s_w_lo:
            b = s_w_lo
            at_end = True
        ok, sr_b, d_b, g_b = _normal_distance_slope(nodes, meta, rail, wheel, b, sr_a, c_y, c_z, cos_r, sin_r)
        if not ok:
            return False, a, sr_a, d_a, False
        if g_b * g_a <= 0.0:
            bracketed = True
            break
        if at_end:
            return True, b, sr_b, d_b, True
        a, sr_a, d_a, g_a = b, sr_b, d_b, g_b
    if not bracketed:
        return False, a, sr_a, d_a, False
    # root of the slope in [a, b] (Illinois); keep the smallest distance met
    best_sw, best_sr, best = a, sr_a, d_a
    if d_b < best:
        best_sw, best_sr, best = b, sr_b, d_b
    side = 0
    for _ in range(60):
        if abs(b - a) < 1e-11 or g_b == g_a:
            break
        c = (a * g_b - b * g_a) / (g_b - g_a)
        ok, sr_c, d_c, g_c = _normal_distance_slope(nodes, meta, rail, wheel, c, best_sr, c_y, c_z, cos_r, sin_r)
        if not ok:
            break
        if d_c < best:
            best_sw, best_sr, best = c, sr_c, d_c
        if g_c == 0.0:
            break
        if g_c * g_b > 0.0:
            b, g_b = c, g_c
            if side == -1:
                g_a *= 0.5
            side = -1
        else:
            a, g_a = c, g_c
            if side == 1:
                g_b *= 0.5
            side = 1
    return True, best_sw, best_sr, best, False


#: Newton step on the rail below which the scan's overlap is taken from the tangent at the last evaluated point
#: (:func:`_scan_overlap`).  Its error is at most about kappa_r ds^2 / t_y: with kappa_r <= 77 1/m (the 13 mm gauge
#: corner of UIC60) and t_y >= 0.15 (the vertically projectable stretch, :func:`monotone_rows`) below 5e-12 m.
SCAN_NEWTON_TOL_M = 1e-7


@compiled(inline="always")
def _scan_overlap(nodes, meta, rail, row_lo, row_hi, wy, wz, a):
    """Vertical overlap ``wz - z_r(wy)`` of a side-frame point over the rail (fixed in the side frame) for the scan
    of :func:`overlap_peaks`; ``(found, overlap, row)``.

    The rail's segment is walked from ``row`` (the previous sample's: the samples move along the rail) to the same
    segment the bisection of :func:`project_vertical` finds; Newton starts from the cubic Hermite inverse of the
    segment (usually one curve evaluation suffices) and stops once the step is below ``SCAN_NEWTON_TOL_M``: the
    height at the foot then comes from the tangent at the last evaluated point instead of one more evaluation.
    Accurate to ~5e-12 m (see ``SCAN_NEWTON_TOL_M``), far below the overlap differences between neighbouring scan
    samples that decide the peaks (kappa h^2 / 2 ~ 1e-8 to 1e-6 m for h ~ 0.35 mm); the peaks' rail points are then
    projected exactly.
    """
    if not (nodes[row_lo, 1] <= wy <= nodes[row_hi, 1]):
        return False, -1.0, a
    if a < row_lo:
        a = row_lo
    elif a > row_hi - 1:
        a = row_hi - 1
    while a > row_lo and nodes[a, 1] > wy:
        a -= 1
    while a < row_hi - 1 and nodes[a + 1, 1] <= wy:
        a += 1
    # start: the inverse s(y) on the segment as a cubic Hermite through its nodes (ds/dy = 1 / t_y there)
    dy = nodes[a + 1, 1] - nodes[a, 1]
    t = (wy - nodes[a, 1]) / dy
    t2 = t * t
    t3 = t2 * t
    s = ((2.0 * t3 - 3.0 * t2 + 1.0) * nodes[a, 0] + (t3 - 2.0 * t2 + t) * dy / nodes[a, 3]
         + (3.0 * t2 - 2.0 * t3) * nodes[a + 1, 0] + (t3 - t2) * dy / nodes[a + 1, 3])
    z_foot = 0.0
    for _ in range(6):
        py, pz, ty, tz = curve_point(nodes, meta, rail, s)
        ds = (wy - py) / ty
        z_foot = pz + tz * ds
        if abs(ds) < SCAN_NEWTON_TOL_M:
            break
        s += ds
    return True, wz - z_foot, a


#: no cached scan points (:func:`overlap_peaks` evaluates the wheel curve at every sample)
NO_SCAN_POINTS = np.zeros((0, 2))
#: the same for every curve: the ``scan`` argument of :func:`~.kernel.evaluate_wheels` without cached points
NO_SCAN = NO_SCAN_POINTS[np.newaxis]


@compiled
def scan_points(nodes, meta, curve, n_wheel):
    """The wheel points ``(p_y, p_z)`` (wheel frame, before the pose) of :func:`overlap_peaks`'s ``n_wheel`` samples
    over the whole of ``curve``, as an (n_wheel, 2) array: the same numbers the scan evaluates (same arc lengths,
    same arithmetic), so a scan given them returns exactly what it returns without."""
    first = int(meta[curve, 0])
    s_w_lo = nodes[first, 0]
    s_w_hi = nodes[first + int(meta[curve, 1]) - 1, 0]
    h = (s_w_hi - s_w_lo) / (n_wheel - 1)
    pts = np.empty((n_wheel, 2))
    for k in range(n_wheel):
        py, pz, ty, tz = curve_point(nodes, meta, curve, s_w_lo + h * k)
        pts[k, 0] = py
        pts[k, 1] = pz
    return pts


@compiled(refcount=False)
def overlap_peaks(nodes, meta, mono, rail, wheel, c_y, c_z, cos_r, sin_r, s_w_lo, s_w_hi, n_wheel, k_max, out_sw,
                  out_sr, points=NO_SCAN_POINTS):
    """Up to ``k_max`` local maxima of the sampled vertical overlap along the wheel region, deepest first.

    Writes their (s_w, s_r) into ``out_sw``/``out_sr`` and returns how many were found.  Starting Newton from
    several basins (not only the deepest sample) finds a narrow deeper zone that falls between two samples of a
    broad one.  A sample is a local maximum when its overlap is at least both neighbours' (a sample without overlap
    counts as -inf); among equal depths the first sample ranks first.  The samples are evaluated by
    :func:`_scan_overlap` in one pass keeping the ``k_max`` deepest maxima (no array allocated; ``out_sr`` holds
    their depths meanwhile), then the rail point of each kept maximum is projected as :func:`overlap_at_wheel` does.
    ``points``: the samples' wheel points of :func:`scan_points` when ``[s_w_lo, s_w_hi]`` is the whole curve (used
    when it has ``n_wheel`` rows; the wheel curve is then not evaluated), else :data:`NO_SCAN_POINTS`.
    """
    cached = points.shape[0] == n_wheel
    row_lo = mono[rail, 0]
    row_hi = mono[rail, 1]
    h = (s_w_hi - s_w_lo) / (n_wheel - 1)
    count = 0
    row = row_lo
    left = -np.inf          # overlap of samples k - 1 (left) and k (mid)
    mid = -np.inf
    for k in range(n_wheel + 1):
        right = -np.inf
        if k < n_wheel:
            if cached:          # wheel_point's placement of the same curve point
                wy, wz = place_point(points[k, 0], points[k, 1], c_y, c_z, cos_r, sin_r)
            else:
                wy, wz = wheel_position(nodes, meta, wheel, s_w_lo + h * k, c_y, c_z, cos_r, sin_r)
            ok, d, row = _scan_overlap(nodes, meta, rail, row_lo, row_hi, wy, wz, row)
            if ok:
                right = d
        # sample k - 1 decided: a local maximum joins the sorted list (after equal depths: first sample first)
        if k >= 1 and mid > -np.inf and mid >= left and mid >= right:
            pos = count
            while pos > 0 and out_sr[pos - 1] < mid:
                pos -= 1
            if pos < k_max:
                last = min(count, k_max - 1)
                for j in range(last, pos, -1):
                    out_sw[j] = out_sw[j - 1]
                    out_sr[j] = out_sr[j - 1]
                out_sw[pos] = s_w_lo + h * (k - 1)
                out_sr[pos] = mid
                count = min(count + 1, k_max)
        left = mid
        mid = right
    for j in range(count):
        ok, d, s_r = overlap_at_wheel(nodes, meta, mono, rail, wheel, out_sw[j], c_y, c_z, cos_r, sin_r)
        out_sr[j] = s_r
    return count


def monotone_rows(curve_nodes: np.ndarray, first_row: int, min_ty: float = 0.15) -> tuple[int, int]:
    """Longest run of nodes on which the lateral coordinate increases (|slope| below acos(min_ty))."""
    ok = curve_nodes[:, 3] > min_ty
    best = (0, 0)
    start = None
    for i, flag in enumerate(np.append(ok, False)):
        if flag and start is None:
            start = i
        elif not flag and start is not None:
            if i - 1 - start > best[1] - best[0]:
                best = (start, i - 1)
            start = None
    return first_row + best[0], first_row + best[1]
