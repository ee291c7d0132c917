"""Precomputed contact geometry for a rigid rail profile and constant wheel profiles (``geometry="table"``).

The online kernel (:mod:`.kernel`) searches the contact of every wheel at every evaluation.  With a rigid rail
profile and an unworn wheel the search result depends on the wheel's pose relative to its rail only, in the side
frame (:mod:`exudyn_wheelrail.conventions`): lateral offset ``c_y``, height ``c_z`` (z down) and roll ``ρ``.  The
rail may still move as a whole (irregularities, a bridge deck): the pose is taken relative to it.  This module
tabulates the kernel once and replaces the search by an interpolation.

**What is stored** (grid over ``c_y`` × ``ρ``; every node is one global-mode kernel evaluation): for each node the
height ``c_z_ref(c_y, ρ)`` at which the deepest contact of the wheel has the penetration ``δ_ref`` (a typical
static penetration, default 0.1 mm), and for each output slot (tread, flange, second tread zone) the kernel's
result there: status, surface parameters, wheel point in the wheelset frame, rail point and outward normal,
penetration ``δ_ref,k``, curvatures, flags — plus the second-order term ``c2_k`` of the penetration against the
height, measured by a second kernel evaluation ``Δh`` deeper (zero when the contact point moved to another zone).

**Evaluation** at a pose (c_y, c_z, ρ): at each of the four surrounding nodes the penetration of slot k follows
from the node's contact point moved rigidly with the wheel,

    δ_k = δ_ref,k + g_k Δ + c2_k Δ²,   Δ = c_z − c_z_ref,   g_k = −n_z (the rail normal's z component),

(first order: the wheel point moves by Δ along z; the quadratic term is the change of the contact points, exact for
two circles: −½ sin²γ Δ² / (R_w + R_r)), and the four values are combined bilinearly.  The other fields are
interpolated bilinearly where the four nodes carry the same contact (same status class, wheel points within
``SAME_ZONE_DISTANCE_M``); across a jump of the contact point (zone change, flange contact appearing) the nearest
node's point is used.  Hertz (:func:`~.normal.hertz_from_penetration`) and the kernel's blending of two maxima of one
zone (``P_BLEND_DEPTH``) are applied to the interpolated values as the kernel does.  The quadratic term is used
within ``|Δ| <= QUADRATIC_RANGE_M`` and continued linearly beyond.

**Outside the table** (|c_y| or |ρ| beyond the grid, a non-finite pose) the wheel falls back to the online kernel
for that evaluation (counted: :data:`STAT_FALLBACK`); a wheel evaluated from the table has its warm-start state reset
so a later fallback starts with a global scan.

Accuracy is tested against the online kernel (tests/test_geometry_table.py) and measured in the work–precision
benchmark.  The table is built in about ten seconds and cached on disk per profile pair and grid
(``$EXUDYN_WHEELRAIL_CACHE`` or ``~/.cache/exudyn_wheelrail``).

Reference for the approach (tabulated contact geometry against lateral displacement and roll for rigid profiles,
elastic penetration evaluated online): Shabana, Zaazaa & Sugiyama, *Railroad Vehicle Dynamics: A Computational
Approach*, CRC 2008, ch. 5 ("lookup tables"); Pombo, Ambrósio & Silva, Vehicle System Dynamics 45 (2007) 165–189.
"""
from __future__ import annotations

import hashlib
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import prange

from ..jit import compiled
from ..profiles.curve import curve_point
from . import kernel as K
from .layout import (  # noqa: F401  (the table's node fields, grid, counters; re-exported)
    G_C2, G_DELTA, G_FLAGS, G_KR_LAT, G_KR_ROLL, G_KW_LAT, G_KW_ROLL, G_NR_Y, G_NR_Z, G_PR_Y, G_PR_Z, G_PW_Y, G_PW_Z,
    G_QY, G_QZ, G_S_RAIL, G_S_WHEEL, G_STATUS, N_G, N_STATS, N_T, STAT_CONCAVE, STAT_FALLBACK, STAT_FLANGE_SKIPPED,
    STAT_OFF_DECK, STAT_ON_DECK, STAT_TABLE, STAT_TREAD_SKIPPED, T_DR, T_DY, T_NR, T_NY, T_R0, T_Y0)
from .normal import hertz_from_penetration
from .search import overlap_at_wheel, place_point

#: fields interpolated between the nodes (the penetration is combined from each node's own prediction instead)
_INTERPOLATED = (G_S_WHEEL, G_S_RAIL, G_QY, G_QZ, G_PR_Y, G_PR_Z, G_NR_Y, G_NR_Z, G_KW_LAT, G_KW_ROLL, G_KR_LAT,
                 G_KR_ROLL)

#: rows of the lookup's scratch after the online kernel's own (kernel.N_SCRATCH_ROWS; :func:`scratch_array`)
_TS_ACC = K.N_SCRATCH_ROWS    # the tread zones' weighted sums of the fields (2 rows)
_TS_MISC = _TS_ACC + 2        # per zone: prototype y, z, weight sum, penetration sum, flags (2 each)
_TS_ROW = _TS_ACC + 3         # interpolated fields of one slot or zone
N_SCRATCH_ROWS = _TS_ACC + 4
SCRATCH_WIDTH = max(K.SCRATCH_WIDTH, N_G, K.N_FIELDS, 10)


def scratch_array() -> np.ndarray:
    """The work array of the geometry stage (the online kernel's rows, then the lookup's): allocated once per
    connector, overwritten by every evaluation."""
    return np.empty((N_SCRATCH_ROWS, SCRATCH_WIDTH))


SAME_ZONE_DISTANCE_M = 1.0e-3
ZONE_MATCH_DISTANCE_M = 5.0e-3
ALT_DEPTH_M = 0.3e-3
QUADRATIC_RANGE_M = 1.0e-3
TABLE_VERSION = 5


@dataclass(frozen=True)
class GeometryTableGrid:
    """Grid of the table (SI).  Defaults cover flange contact and the start of a climb on S1002/UIC60 (c_y up to
    ±25 mm) and wheel rolls of ±15 mrad relative to the rail; the roll step is fine because a conformal tread contact
    (S1002/UIC60 near the centre) moves by millimetres per milliradian."""

    y_min_m: float = -0.025
    y_max_m: float = 0.025
    dy_m: float = 0.1e-3
    roll_min_rad: float = -0.015
    roll_max_rad: float = 0.015
    droll_rad: float = 0.5e-3
    delta_ref_m: float = 0.1e-3
    dh_m: float = 0.2e-3

    def axes(self):
        ny = int(round((self.y_max_m - self.y_min_m) / self.dy_m)) + 1
        nr = int(round((self.roll_max_rad - self.roll_min_rad) / self.droll_rad)) + 1
        if ny < 2 or nr < 2:
            raise ValueError(f"geometry table grid {self}: needs at least two nodes along c_y and roll")
        return (self.y_min_m + self.dy_m * np.arange(ny), self.roll_min_rad + self.droll_rad * np.arange(nr))


@compiled
def _deepest(out):
    best = -np.inf
    k_best = -1
    for k in range(out.shape[1]):
        st = out[0, k, K.F_STATUS]
        if st >= 0 and out[0, k, K.F_PENETRATION] > best:
            best = out[0, k, K.F_PENETRATION]
            k_best = k
    return k_best, best


@compiled
def _store(out, data, i, j, c2):
    for k in range(out.shape[1]):
        o = out[0, k]
        d = data[i, j, k]
        d[G_STATUS] = o[K.F_STATUS]
        d[G_S_WHEEL] = o[K.F_S_WHEEL]
        d[G_S_RAIL] = o[K.F_S_RAIL]
        d[G_PR_Y] = o[K.F_PR_Y]
        d[G_PR_Z] = o[K.F_PR_Z]
        d[G_NR_Y] = o[K.F_NR_Y]
        d[G_NR_Z] = o[K.F_NR_Z]
        d[G_DELTA] = o[K.F_PENETRATION]
        d[G_C2] = c2[k]
        d[G_KW_LAT] = o[K.F_KW_LAT]
        d[G_KW_ROLL] = o[K.F_KW_ROLL]
        d[G_KR_LAT] = o[K.F_KR_LAT]
        d[G_KR_ROLL] = o[K.F_KR_ROLL]
        d[G_FLAGS] = o[K.F_FLAGS]
        d[G_PW_Y] = o[K.F_PW_Y]
        d[G_PW_Z] = o[K.F_PW_Z]


@compiled(parallel=True)
def build_table_core(nodes, meta, mono, curve_row, params_global, ys, rolls, cz_start, delta_ref, dh, data, cz_ref):
    """Fill ``data`` (ny, nr, N_SLOTS, N_G) and ``cz_ref`` (ny, nr); ``params_global`` must be global-mode kernel
    parameters.  Returns the number of nodes whose reference height did not converge (their data are NaN).
    The roll columns are built in parallel."""
    failed = np.zeros(rolls.shape[0], dtype=np.int64)
    for j in prange(rolls.shape[0]):
        failed[j] = _build_column(nodes, meta, mono, curve_row, params_global, ys, rolls, j, cz_start, delta_ref, dh,
                                  data, cz_ref)
    return failed.sum()


@compiled
def height_at_penetration(nodes, meta, mono, cids, pose, warm, params_global, out, target, cz):
    """The height ``c_z`` from ``cz`` (Newton, steps ≤ 2 mm) at which the deepest contact of the wheel at ``pose``'s
    lateral offset and roll has the penetration ``target``: ``(c_z, converged)``; ``out`` holds the kernel's output
    there (``pose[0, 1]`` is set)."""
    for it in range(40):
        pose[0, 1] = cz
        K.evaluate_wheels(nodes, meta, mono, cids, pose, warm, params_global, out)
        k, d = _deepest(out)
        if k < 0:
            cz += 1e-3          # nothing faces the rail at all: move down
            continue
        g = -out[0, k, K.F_NR_Z]
        if g < 0.05:
            g = 0.05
        step = (target - d) / g
        if step > 2e-3:
            step = 2e-3
        elif step < -2e-3:
            step = -2e-3
        if abs(step) < 1e-10:
            return cz, True
        cz += step
    return cz, False


@compiled
def column_arrays(curve_row):
    """The arrays of one wheel's kernel evaluations while a table's column is built: its curve ids (1, 3), pose
    (1, 3), warm start and two outputs."""
    cids = np.empty((1, 3), dtype=np.int64)
    for i in range(3):
        cids[0, i] = curve_row[i]
    return (cids, np.zeros((1, 3)), np.full((1, 2, K.N_WARM), np.nan), np.zeros((1, K.N_SLOTS, K.N_FIELDS)),
            np.zeros((1, K.N_SLOTS, K.N_FIELDS)))


def save_cached(path: Path, **arrays) -> None:
    """Write a table's arrays to the cache file ``path`` (through a file of this process's own: test workers may
    race); a folder that cannot be written leaves the table uncached."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".{os.getpid()}.tmp.npz")
        np.savez_compressed(tmp, **arrays)
        os.replace(tmp, path)
    except OSError:
        pass


@compiled
def _build_column(nodes, meta, mono, curve_row, params_global, ys, rolls, j, cz_start, delta_ref, dh, data, cz_ref):
    """One roll column of :func:`build_table_core`; returns its number of failed nodes."""
    cids, pose, warm, out, out2 = column_arrays(curve_row)
    c2 = np.zeros(K.N_SLOTS)
    failed = 0
    cz = cz_start
    for i in range(ys.shape[0]):
        pose[0, 0] = ys[i]
        pose[0, 2] = rolls[j]
        cz, ok = height_at_penetration(nodes, meta, mono, cids, pose, warm, params_global, out, delta_ref, cz)
        if not ok:
            failed += 1
            data[i, j, :, :] = np.nan
            cz_ref[i, j] = np.nan
            cz = cz_start
            continue
        cz_ref[i, j] = cz
        pose[0, 1] = cz + dh
        K.evaluate_wheels(nodes, meta, mono, cids, pose, warm, params_global, out2)
        for k in range(K.N_SLOTS):
            c2[k] = 0.0
            a = out[0, k]
            b = out2[0, k]
            if a[K.F_STATUS] >= 0 and b[K.F_STATUS] >= 0 and \
                    math.hypot(a[K.F_PW_Y] - b[K.F_PW_Y], a[K.F_PW_Z] - b[K.F_PW_Z]) < 0.5 * SAME_ZONE_DISTANCE_M:
                c2[k] = (b[K.F_PENETRATION] - a[K.F_PENETRATION] + a[K.F_NR_Z] * dh) / (dh * dh)
        if out[0, K.SLOT_TREAD_2, K.F_STATUS] < 0 and out[0, K.SLOT_TREAD, K.F_STATUS] >= 0:
            # the tread's other zone, not penetrating here: taken from a deeper evaluation (ALT_DEPTH_M), where
            # it penetrates, and kept with its gap, so that the evaluation finds it when it does
            pose[0, 1] = cz + ALT_DEPTH_M
            K.evaluate_wheels(nodes, meta, mono, cids, pose, warm, params_global, out2)
            a_sw = np.nan
            far = params_global[K.P_DEDUP_DISTANCE]
            for k in (K.SLOT_TREAD, K.SLOT_TREAD_2):
                if out2[0, k, K.F_STATUS] >= 0:
                    dist = abs(out2[0, k, K.F_S_WHEEL] - out[0, K.SLOT_TREAD, K.F_S_WHEEL])
                    if dist > far:
                        far = dist
                        a_sw = out2[0, k, K.F_S_WHEEL]
                        a_sr = out2[0, k, K.F_S_RAIL]
            if np.isfinite(a_sw):
                K._fill(out, 0, K.SLOT_TREAD_2, K.STATUS_SEPARATED, a_sw, a_sr, nodes, meta, cids[0, 0],
                        cids[0, 1], ys[i], cz, math.cos(rolls[j]), math.sin(rolls[j]), 0, params_global)
                out[0, K.SLOT_TREAD_2, K.F_NORMAL_FORCE] = 0.0
            pose[0, 1] = cz
        _store(out, data, i, j, c2)
        # the wheel point in the wheelset frame
        for k in range(K.N_SLOTS):
            if out[0, k, K.F_STATUS] >= 0:
                from_curve = curve_row[1] if k != K.SLOT_FLANGE else curve_row[2]
                s = out[0, k, K.F_S_WHEEL]
                qy, qz, _, _ = curve_point(nodes, meta, from_curve, s)
                data[i, j, k, G_QY] = qy
                data[i, j, k, G_QZ] = qz
            else:
                data[i, j, k, G_QY] = np.nan
                data[i, j, k, G_QZ] = np.nan
    return failed


@compiled(refcount=False)
def _node_delta(d, c_y, c_z, cos_r, sin_r):
    """Penetration of one slot at the pose from a node's contact point moved rigidly with the wheel (module doc):
    first order -n·Δp_w (the distance is stationary in the point positions), plus the measured vertical
    second-order term."""
    qy = d[G_QY]
    qz = d[G_QZ]
    wy, wz = place_point(qy, qz, c_y, c_z, cos_r, sin_r)
    dy = wy - d[G_PW_Y]
    dz = wz - d[G_PW_Z]
    lin = d[G_DELTA] - (d[G_NR_Y] * dy + d[G_NR_Z] * dz)
    c2 = d[G_C2]
    if dz > QUADRATIC_RANGE_M:
        return lin + c2 * QUADRATIC_RANGE_M * (2.0 * dz - QUADRATIC_RANGE_M)
    if dz < -QUADRATIC_RANGE_M:
        return lin + c2 * QUADRATIC_RANGE_M * (-2.0 * dz - QUADRATIC_RANGE_M)
    return lin + c2 * dz * dz


@compiled
def _status_class(st):
    if st >= 0:
        return 0            # a point pair exists (contact or separated)
    return int(st)          # no overlap / merged


@compiled(refcount=False)
def _fill_from_table(data, cz_ref, i, j, fy, fr, slot, c_y, c_z, cos_r, sin_r, params, o, v):
    """Interpolate one slot at (c_y, c_z, roll) into the kernel output row ``o`` (``v``: a scratch row, N_G);
    returns whether a point pair was interpolated."""
    w00 = (1.0 - fy) * (1.0 - fr)
    w10 = fy * (1.0 - fr)
    w01 = (1.0 - fy) * fr
    w11 = fy * fr
    ii = (i, i + 1, i, i + 1)
    jj = (j, j, j + 1, j + 1)
    ww = (w00, w10, w01, w11)
    # the node that dominates
    m = 0
    for c in range(1, 4):
        if ww[c] > ww[m]:
            m = c
    dm = data[ii[m], jj[m], slot]
    cls = _status_class(dm[G_STATUS])
    same = True         # the same contact point at every corner: interpolate every field
    same_class = True   # a point pair at every corner: interpolate the penetration
    for c in range(4):
        if ww[c] <= 0.0:
            continue
        dc = data[ii[c], jj[c], slot]
        if _status_class(dc[G_STATUS]) != cls or not np.isfinite(dc[G_DELTA]):
            same = False
            same_class = False
        elif cls == 0 and (abs(dc[G_QY] - dm[G_QY]) + abs(dc[G_QZ] - dm[G_QZ]) > SAME_ZONE_DISTANCE_M
                           or int(dc[G_FLAGS]) & K.FLAG_BLENDED != int(dm[G_FLAGS]) & K.FLAG_BLENDED):
            same = False
    o[:] = 0.0
    if cls != 0:
        o[K.F_STATUS] = dm[G_STATUS]
        return False
    fields = _INTERPOLATED
    v[:N_G] = 0.0
    delta = 0.0
    if same:
        for c in range(4):
            if ww[c] <= 0.0:
                continue
            dc = data[ii[c], jj[c], slot]
            for f in fields:
                v[f] += ww[c] * dc[f]
    else:
        for f in fields:
            v[f] = dm[f]
    if same_class:
        for c in range(4):
            if ww[c] > 0.0:
                delta += ww[c] * _node_delta(data[ii[c], jj[c], slot], c_y, c_z, cos_r, sin_r)
    else:
        delta = _node_delta(dm, c_y, c_z, cos_r, sin_r)
    _row(o, v, delta, dm[G_STATUS], int(dm[G_FLAGS]) & (K.FLAG_PROFILE_END | K.FLAG_BLENDED), c_y, c_z, cos_r, sin_r,
         params)
    return True


@compiled(refcount=False)
def _tread_zones(data, i, j, fy, fr, c_y, c_z, cos_r, sin_r, params, o1, o2, scratch):
    """The tread's (up to) two zones at the pose: each corner node offers the points of slots tread and tread-2;
    they are matched to the dominant corner's zones by their wheel point (within ZONE_MATCH_DISTANCE_M), and each
    zone's penetration and fields are the weighted mean over the corners that carry it.  Fills ``o1``/``o2``
    with the zones (tread slot rows, unblended); returns the number of zones.  ``scratch``: the rows ``_TS_*``
    of the kernel's scratch (:func:`scratch_array`)."""
    ww = ((1.0 - fy) * (1.0 - fr), fy * (1.0 - fr), (1.0 - fy) * fr, fy * fr)
    ii = (i, i + 1, i, i + 1)
    jj = (j, j, j + 1, j + 1)
    m = 0
    for c in range(1, 4):
        if ww[c] > ww[m]:
            m = c
    misc = scratch[_TS_MISC]
    proto_y = misc[0:2]
    proto_z = misc[2:4]
    wsum = misc[4:6]
    dsum = misc[6:8]
    flags = misc[8:10]                # integer flags, held exactly as floats
    misc[:10] = 0.0
    acc = scratch[_TS_ACC:_TS_ACC + 2]
    acc[:, :N_G] = 0.0
    n_z = 0
    for slot in (K.SLOT_TREAD, K.SLOT_TREAD_2):
        d = data[ii[m], jj[m], slot]
        if d[G_STATUS] >= 0 and np.isfinite(d[G_DELTA]):
            proto_y[n_z] = d[G_QY]
            proto_z[n_z] = d[G_QZ]
            n_z += 1
    fields = _INTERPOLATED
    for c in range(4):
        if ww[c] <= 0.0 and c != m:
            continue
        for slot in (K.SLOT_TREAD, K.SLOT_TREAD_2):
            d = data[ii[c], jj[c], slot]
            if not (d[G_STATUS] >= 0 and np.isfinite(d[G_DELTA])):
                continue
            z = -1
            best = ZONE_MATCH_DISTANCE_M
            for k in range(n_z):
                dist = abs(d[G_QY] - proto_y[k]) + abs(d[G_QZ] - proto_z[k])
                if dist < best:
                    best = dist
                    z = k
            if z < 0:
                continue
            wc = max(ww[c], 1e-12)
            for f in fields:
                acc[z, f] += wc * d[f]
            dsum[z] += wc * _node_delta(d, c_y, c_z, cos_r, sin_r)
            wsum[z] += wc
            if c == m:
                flags[z] = int(d[G_FLAGS]) & K.FLAG_PROFILE_END
    v = scratch[_TS_ROW]
    for z in range(n_z):
        o = o1 if z == 0 else o2
        for f in range(N_G):
            v[f] = acc[z, f] / wsum[z]
        _row(o, v, dsum[z] / wsum[z], K.STATUS_CONVEX, int(flags[z]), c_y, c_z, cos_r, sin_r, params)
    return n_z


@compiled(refcount=False)
def _row(o, v, delta, status, flags, c_y, c_z, cos_r, sin_r, params):
    """One kernel output row from interpolated fields ``v`` (G_*) and the penetration (Hertz where positive)."""
    o[:] = 0.0
    qy = v[G_QY]
    qz = v[G_QZ]
    ny = v[G_NR_Y]
    nz = v[G_NR_Z]
    nn = math.hypot(ny, nz)
    ny /= nn
    nz /= nn
    o[K.F_S_WHEEL] = v[G_S_WHEEL]
    o[K.F_S_RAIL] = v[G_S_RAIL]
    o[K.F_PW_Y], o[K.F_PW_Z] = place_point(qy, qz, c_y, c_z, cos_r, sin_r)
    o[K.F_PR_Y] = v[G_PR_Y]
    o[K.F_PR_Z] = v[G_PR_Z]
    o[K.F_NR_Y] = ny
    o[K.F_NR_Z] = nz
    o[K.F_PENETRATION] = delta
    o[K.F_CONTACT_ANGLE] = math.atan2(-ny, -nz)
    o[K.F_ROLLING_RADIUS] = qz
    o[K.F_KW_LAT] = v[G_KW_LAT]
    o[K.F_KW_ROLL] = v[G_KW_ROLL]
    o[K.F_KR_LAT] = v[G_KR_LAT]
    o[K.F_KR_ROLL] = v[G_KR_ROLL]
    A = 0.5 * (v[G_KW_ROLL] + v[G_KR_ROLL])
    B = 0.5 * (v[G_KW_LAT] + v[G_KR_LAT])
    o[K.F_A_REL] = A
    o[K.F_B_REL] = B
    if delta > params[K.P_MAX_PENETRATION]:
        flags |= K.FLAG_DEEP_PENETRATION
    if delta > 0.0:
        n, dn, a, b, hs = hertz_from_penetration(A, B, params[K.P_E_STAR], delta, params[K.P_MIN_CURVATURE])
        o[K.F_STATUS] = status if status > 0 else K.STATUS_CONVEX
        o[K.F_NORMAL_FORCE] = n
        o[K.F_DN_DDELTA] = dn
        o[K.F_SEMI_A] = a
        o[K.F_SEMI_B] = b
        o[K.F_HERTZ_STATUS] = hs
        if hs & 3:
            flags |= K.FLAG_HERTZ_CLAMPED
    else:
        o[K.F_STATUS] = K.STATUS_SEPARATED
    o[K.F_FLAGS] = flags


@compiled(refcount=False)
def _table_wheel(par, cz_ref, data, nodes, meta, mono, rail, tread, w, c_y, c_z, roll, params, out, scratch):
    """All slots of wheel ``w`` from the table (pose inside the grid; ``scratch``: :func:`scratch_array`)."""
    u = (c_y - par[T_Y0]) / par[T_DY]
    r = (roll - par[T_R0]) / par[T_DR]
    i = min(int(u), int(par[T_NY]) - 2)
    j = min(int(r), int(par[T_NR]) - 2)
    fy = u - i
    fr = r - j
    cos_r = math.cos(roll)
    sin_r = math.sin(roll)
    _fill_from_table(data, cz_ref, i, j, fy, fr, K.SLOT_FLANGE, c_y, c_z, cos_r, sin_r, params, out[w, K.SLOT_FLANGE],
                     scratch[_TS_ROW])
    t = out[w, K.SLOT_TREAD]
    t2 = out[w, K.SLOT_TREAD_2]
    n_z = _tread_zones(data, i, j, fy, fr, c_y, c_z, cos_r, sin_r, params, t, t2, scratch)
    if n_z == 0:
        t[:] = 0.0
        t[K.F_STATUS] = K.STATUS_NO_OVERLAP
    if n_z < 2:
        t2[:] = 0.0
        t2[K.F_STATUS] = K.STATUS_NO_OVERLAP
        return
    if t2[K.F_PENETRATION] > t[K.F_PENETRATION]:       # the deeper zone goes to the tread slot
        for f in range(t.shape[0]):
            t[f], t2[f] = t2[f], t[f]
    if not (t2[K.F_PENETRATION] > 0.0):
        t2[:] = 0.0                                      # the other zone does not touch: not reported
        t2[K.F_STATUS] = K.STATUS_NO_OVERLAP
        return
    # both zones penetrate: separate patches (a gap between them) or one zone with two maxima (blended as the
    # kernel does, P_BLEND_DEPTH)
    mid_ok, mid_dv, mid_sr = overlap_at_wheel(nodes, meta, mono, rail, tread,
                                               0.5 * (t[K.F_S_WHEEL] + t2[K.F_S_WHEEL]), c_y, c_z, cos_r, sin_r)
    if mid_ok and mid_dv < 0.0:
        return
    width = params[K.P_BLEND_DEPTH] * t[K.F_PENETRATION]
    uu = 1.0 - (t[K.F_PENETRATION] - t2[K.F_PENETRATION]) / width if width > 0.0 else 0.0
    if uu <= 0.0:
        t2[:] = 0.0
        t2[K.F_STATUS] = K.STATUS_NO_OVERLAP
        return
    uu = min(uu, 1.0)
    blend = 0.5 * uu * uu * (3.0 - 2.0 * uu)
    t2[K.F_NORMAL_FORCE] *= blend
    t2[K.F_DN_DDELTA] *= blend
    t[K.F_NORMAL_FORCE] *= 1.0 - blend
    t[K.F_DN_DDELTA] *= 1.0 - blend
    t[K.F_FLAGS] = int(t[K.F_FLAGS]) | K.FLAG_BLENDED
    t2[K.F_FLAGS] = int(t2[K.F_FLAGS]) | K.FLAG_BLENDED


@compiled(refcount=False)
def _count_online(out, w0, w1, stats):
    for w in range(w0, w1):
        for reg in range(2):
            o = out[w, reg]
            if o[K.F_STATUS] == K.STATUS_SEPARATED and o[K.F_ITERATIONS] == 0:
                stats[STAT_FLANGE_SKIPPED if reg == 1 else STAT_TREAD_SKIPPED] += 1
            elif o[K.F_STATUS] == K.STATUS_CONCAVE:
                stats[STAT_CONCAVE] += 1


@compiled(refcount=False)
def count_fallback(out, stats):
    """Count every wheel of the kernel's output ``out`` as evaluated by the online kernel in ``stats`` (STAT_*):
    the table's fallback, its skipped regions and concave contacts."""
    stats[STAT_FALLBACK] += out.shape[0]
    _count_online(out, 0, out.shape[0], stats)


@compiled
def evaluate_wheels_tabulated(par, cz_ref, data, nodes, meta, mono, curve_ids, poses, warm, params, out, stats,
                              scan=K.NO_SCAN):
    """:func:`~.kernel.evaluate_wheels` with the table ``(par, cz_ref, data)`` (:meth:`GeometryTable.arrays`)
    where the pose is inside it; the online kernel elsewhere (``scan`` its cached scan points,
    :func:`~.kernel.scan_array`).  ``stats`` counts (STAT_*).  Without a table the caller runs the online kernel
    for every wheel and counts it with :func:`count_fallback`.  (:func:`tabulated_wheels` with its scratch made
    here.)"""
    tabulated_wheels(par, cz_ref, data, nodes, meta, mono, curve_ids, poses, warm, params, out, stats, scan,
                     np.empty((N_SCRATCH_ROWS, SCRATCH_WIDTH)))


@compiled(refcount=False)
def tabulated_wheels(par, cz_ref, data, nodes, meta, mono, curve_ids, poses, warm, params, out, stats, scan,
                     scratch):
    """:func:`evaluate_wheels_tabulated` with its scratch given (nothing allocated)."""
    y_hi = par[T_Y0] + par[T_DY] * (par[T_NY] - 1.0)
    r_hi = par[T_R0] + par[T_DR] * (par[T_NR] - 1.0)
    for w in range(poses.shape[0]):
        c_y = poses[w, 0]
        c_z = poses[w, 1]
        roll = poses[w, 2]
        inside = c_y >= par[T_Y0] and c_y <= y_hi and roll >= par[T_R0] and roll <= r_hi and math.isfinite(c_z)
        if inside:
            # every surrounding node must exist (a node whose reference height did not converge is NaN)
            i = min(int((c_y - par[T_Y0]) / par[T_DY]), int(par[T_NY]) - 2)
            j = min(int((roll - par[T_R0]) / par[T_DR]), int(par[T_NR]) - 2)
            inside = (math.isfinite(cz_ref[i, j]) and math.isfinite(cz_ref[i + 1, j])
                      and math.isfinite(cz_ref[i, j + 1]) and math.isfinite(cz_ref[i + 1, j + 1]))
        if inside:
            _table_wheel(par, cz_ref, data, nodes, meta, mono, curve_ids[w, 0], curve_ids[w, 1], w, c_y, c_z, roll,
                         params, out, scratch)
            for reg in range(2):
                warm[w, reg, K.W_S_RAIL] = np.nan
                warm[w, reg, K.W_S_WHEEL] = np.nan
                warm[w, reg, K.W_GAP] = -1.0
                warm[w, reg, K.W_ALT_S_RAIL] = np.nan
                warm[w, reg, K.W_ALT_S_WHEEL] = np.nan
            stats[STAT_TABLE] += 1
        else:
            K.solve_wheels(nodes, meta, mono, curve_ids[w:w + 1], poses[w:w + 1], warm[w:w + 1], params,
                           out[w:w + 1], scan, scratch)
            stats[STAT_FALLBACK] += 1
            _count_online(out, w, w + 1, stats)


class GeometryTable:
    """The tabulated contact geometry of one wheel/rail curve set (build with :func:`geometry_table`)."""

    def __init__(self, grid: GeometryTableGrid, cz_ref: np.ndarray, data: np.ndarray, failed: int, key: str):
        self.grid = grid
        self.cz_ref = cz_ref
        self.data = data
        self.failed = int(failed)
        self.key = key
        ys, rolls = grid.axes()
        self.par = np.zeros(N_T)
        self.par[T_Y0], self.par[T_DY], self.par[T_NY] = ys[0], grid.dy_m, len(ys)
        self.par[T_R0], self.par[T_DR], self.par[T_NR] = rolls[0], grid.droll_rad, len(rolls)

    def arrays(self):
        return self.par, self.cz_ref, self.data

    def describe(self) -> dict:
        g = self.grid
        return {"c_y_range_m": [g.y_min_m, g.y_max_m], "dy_m": g.dy_m, "roll_range_rad": [g.roll_min_rad, g.roll_max_rad],
                "droll_rad": g.droll_rad, "delta_ref_m": g.delta_ref_m, "nodes": int(self.cz_ref.size),
                "nodes_failed": self.failed, "key": self.key}


_MEMORY: dict = {}


def cache_dir() -> Path:
    """The folder of the cached tables (``$EXUDYN_WHEELRAIL_CACHE`` or ``~/.cache/exudyn_wheelrail``)."""
    d = os.environ.get("EXUDYN_WHEELRAIL_CACHE")
    return Path(d) if d else Path.home() / ".cache" / "exudyn_wheelrail"


def cache_key(nodes, meta, curve_row, arrays, tag) -> str:
    """The cache key of a table of the curves ``curve_row`` in ``nodes``/``meta``: a digest of them, of the float
    ``arrays`` (its parameters) and of ``repr(tag)`` (its grid and format version)."""
    h = hashlib.sha256()
    for a in (np.ascontiguousarray(nodes, dtype=float), np.ascontiguousarray(meta, dtype=float),
              np.asarray(curve_row, dtype=np.int64), *(np.ascontiguousarray(x, dtype=float) for x in arrays)):
        h.update(a.tobytes())
    h.update(repr(tag).encode())
    return h.hexdigest()[:20]


def load_cached(path: Path, data_shape, names) -> dict | None:
    """The arrays ``names`` of the cached table file ``path``, or None where there is none, where it is corrupt,
    lacks one of them or its ``data`` is not of ``data_shape`` (the table is then built again)."""
    if not path.exists():
        return None
    try:
        with np.load(path) as z:
            if z["data"].shape != tuple(data_shape):
                return None
            return {name: z[name] for name in names}
    except Exception:   # a corrupt cache file is rebuilt
        return None


def geometry_table(nodes, meta, mono, curve_row, params, grid: GeometryTableGrid | None = None,
                   cache: bool = True) -> GeometryTable:
    """The table for the curves ``curve_row`` (rail, tread, flange ids in the packed ``nodes``/``meta``) with the
    kernel parameters ``params`` (the search settings of the online kernel; made global here).  Cached in memory
    and on disk (module doc)."""
    grid = grid or GeometryTableGrid()
    pg = np.array(params, dtype=float)
    pg[K.P_GLOBAL] = 1.0
    pg[K.P_BLEND_DEPTH] = 1e9           # report the second maximum of a zone whenever it penetrates (flagged)
    key = cache_key(nodes, meta, curve_row, (pg,), (grid, TABLE_VERSION))
    if key in _MEMORY:
        return _MEMORY[key]
    path = cache_dir() / f"geometry_table_{key}.npz"
    ys, rolls = grid.axes()
    z = load_cached(path, (len(ys), len(rolls), K.N_SLOTS, N_G), ("cz_ref", "data", "failed")) if cache else None
    if z is not None:
        t = GeometryTable(grid, z["cz_ref"], z["data"], int(z["failed"]), key)
        _MEMORY[key] = t
        return t
    data = np.zeros((len(ys), len(rolls), K.N_SLOTS, N_G))
    cz_ref = np.zeros((len(ys), len(rolls)))
    r0 = nominal_height(nodes, meta, curve_row)
    failed = build_table_core(nodes, meta, mono, np.asarray(curve_row, dtype=np.int64), pg, ys, rolls, r0,
                              grid.delta_ref_m, grid.dh_m, data, cz_ref)
    t = GeometryTable(grid, cz_ref, data, failed, key)
    _MEMORY[key] = t
    if cache:
        save_cached(path, cz_ref=cz_ref, data=data, failed=failed)
    return t


def nominal_height(nodes, meta, curve_row) -> float:
    """A start height for the reference search: minus the wheel tread curve's largest z (its radius)."""
    first = int(meta[curve_row[1], 0])
    n = int(meta[curve_row[1], 1])
    return -float(np.max(nodes[first:first + n, 2])) if nodes.shape[1] > 2 else -0.46
