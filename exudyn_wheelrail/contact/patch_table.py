"""The non-Hertzian patch tabulated: its correction of Hertz over the wheel's pose relative to the rail and the
penetration, so that a dynamics call pays an interpolation instead of a patch.

With rigid profiles the patch of a contact (:mod:`.patch_pass`) depends on the wheel's pose relative to its rail
only — lateral offset ``c_y``, roll ``ρ`` and height ``c_z`` (side frame) — and for a given ``(c_y, ρ)`` the height
acts through the penetration: lowering the wheel by Δ moves it rigidly, every strip's interpenetration along the
contact plane's normal grows by the same ``Δ cos γ``.  The table stores, over a grid of ``(c_y, ρ)`` and for each
node at the heights where the deepest contact has the penetrations ``deltas_m``, per kernel slot:

* its code (:data:`CODE_NONE` no loaded contact, :data:`CODE_PATCH` a contact — the pass's resultant, which is
  Hertz's own row where the pass keeps Hertz — or :data:`CODE_MERGED` the zone of another slot, no force) and the
  slot's own penetration;
* the pass's output for it: the normal force (its logarithm), the contact angle of the resultant, the resultant's
  point as arc lengths on the rail and the wheel profile, the equivalent ellipse's semi-axes.

These are the patch's own quantities, not corrections of Hertz: the patch changes smoothly with the pose where Hertz
jumps (between the humps of a conformal overlap), so its own values interpolate well.  **Evaluation**
(:func:`patch_tabulated`): after the kernel (or the geometry table) each loaded slot of a wheel reads its four
surrounding ``(c_y, ρ)`` nodes, each interpolated between the two tabulated heights whose penetrations of the slot
bracket its penetration (a zone that appears between them: the upper height's values, the force along Hertz's
δ^1.5 below it), linearly in ln δ (the force's logarithm too, so that it follows the power law of δ; beyond
the tabulated range the force is extrapolated along it, the rest held), and combines them bilinearly; the row gets
the force, dN/dδ (the power law's slope), the angle and normal, the points (from the arc lengths), the rolling
radius and the semi-axes.  A slot that has no force of its own at any of its four nodes and bracketing heights —
the tail of another slot's zone at one of them at least, no contact at the others — is that zone's tail here too
(merged, no force: the zone's carrying slot reads the whole zone's resultant, at every node its own).  The kernel
finds such a second maximum of the conformal tread wherever it appears inside the first one's zone, so this is the
common case of a zone merging.  A wheel outside the grid, one with a slot that carries its own contact at some of
its nodes and not at others (a second zone merging into the first between two nodes), or one whose tails have no
loaded slot read as carrying a contact, gets the patch solved online (:func:`~.patch_pass.patch_wheels`) for that
evaluation.

The build solves the pass at every node and height (global kernel search, the pass's own strips): about
``nodes × len(deltas_m)`` patches, roll columns in parallel; cached on disk per profile pair, kernel parameters,
pass parameters and grid (the geometry table's cache folder).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import prange

from ..jit import compiled
from . import kernel as K
from .geometry_table import (GeometryTableGrid, cache_dir, cache_key, column_arrays, height_at_penetration,
                             load_cached, nominal_height, save_cached)
from .patch_pass import HERTZ_EXPONENT, PP_N_STRIPS, PP_SWITCH_HI, PP_SWITCH_LO, pass_work, patch_params, patch_wheels
from ..profiles.curve import curve_point
from .strips import curve_of

__all__ = ["PatchTableGrid", "PatchTable", "patch_table", "patch_tabulated", "patch_contacts", "patch_argument",
           "CODE_NONE", "CODE_PATCH",
           "CODE_MERGED", "PT_CODE", "PT_DELTA", "PT_LOG_N", "PT_GAMMA", "PT_S_RAIL", "PT_S_WHEEL", "PT_A", "PT_B",
           "PT_LOG_DELTA", "PT_PATCHED", "N_PT", "PATCH_TABLE_VERSION", "no_table"]

CODE_NONE = -1.0
CODE_PATCH = 1.0
CODE_MERGED = 2.0

# the fields per node, height and slot: data[i_y, i_roll, i_delta, slot, PT_*]
PT_CODE = 0
PT_DELTA = 1        # the slot's penetration [m]
PT_LOG_N = 2        # ln of the normal force [N]
PT_GAMMA = 3        # contact angle of the resultant [rad]
PT_S_RAIL = 4       # the resultant's point: rail and wheel arc lengths [m]
PT_S_WHEEL = 5
PT_A = 6            # the equivalent ellipse's semi-axes [m]
PT_B = 7
PT_LOG_DELTA = 8    # ln of the slot's penetration (where positive)
PT_PATCHED = 9      # 1 where the pass patched the contact (flag FLAG_PATCH), 0 where it kept Hertz
N_PT = 10

# the grid's parameters: par[TP_*]
TP_Y0 = 0
TP_DY = 1
TP_NY = 2
TP_R0 = 3
TP_DR = 4
TP_NR = 5
N_TP = 6

PATCH_TABLE_VERSION = 3


@dataclass(frozen=True)
class PatchTableGrid:
    """Grid of the table (SI) and the penetrations of the deepest contact at which each node is solved.  The range
    covers the tread and the flange root of S1002/UIC60 (|c_y| <= 8 mm; beyond, on the flange, Hertz holds and the
    pass keeps it at the cost of two strips) and wheel rolls of ±4 mrad relative to the rail; the roll step is
    fine because the conformal tread's patch changes by percent per 0.5 mrad (measured: 1 mrad steps, 4 % RMS error
    of the force midway; 0.1 mm steps in c_y, 1.8 % at most).  Where the tread's second zone joins the first, the
    force at a given penetration rises along a ridge ~0.1 mm wide that moves with the roll, which a cell of these
    steps flattens (the table against the patch solved online over the RTRI run: docs/performance.md)."""

    y_min_m: float = -0.008
    y_max_m: float = 0.008
    dy_m: float = 0.05e-3
    roll_min_rad: float = -0.004
    roll_max_rad: float = 0.004
    droll_rad: float = 0.25e-3
    deltas_m: tuple = field(default=(4e-6, 8e-6, 15e-6, 25e-6, 35e-6, 50e-6, 70e-6, 100e-6, 140e-6, 200e-6))

    def axes(self):
        """(c_y nodes, roll nodes, penetrations): the nodes by the geometry table's rule."""
        ys, rolls = GeometryTableGrid.axes(self)
        if len(self.deltas_m) < 2 or list(self.deltas_m) != sorted(self.deltas_m) or self.deltas_m[0] <= 0.0:
            raise ValueError(f"patch table grid {self}: needs two or more increasing positive deltas_m")
        return ys, rolls, np.asarray(self.deltas_m, dtype=float)


def no_table() -> tuple:
    """The table arguments of a contact without a patch table (every patch solved online)."""
    return np.zeros(N_TP), np.zeros((0, 0, 0, K.N_SLOTS, N_PT)), np.zeros((K.N_SLOTS, N_PT + 1))


def patch_argument(table: "PatchTable | None" = None, pp=None) -> tuple:
    """The patch's argument of a contact evaluation (:func:`patch_contacts`): the pass's work arrays
    (:func:`~.patch_pass.patch_params`; ``pp`` its parameters, default the defaults) and the table's arrays, or none
    (every patch solved online)."""
    work = patch_params() if pp is None else patch_params(int(pp[PP_N_STRIPS]), float(pp[PP_SWITCH_LO]),
                                                          float(pp[PP_SWITCH_HI]))
    return work, (table.arrays() if table is not None else no_table())


@compiled
def _build_column(nodes, meta, mono, curve_row, params, pp, ys, rolls, deltas, j, cz_start, data):
    """One roll column of :func:`build_patch_table_core`; returns its number of failed nodes."""
    patch = pass_work(pp.copy())
    cids, pose, warm, out, out2 = column_arrays(curve_row)
    failed = 0
    cz = cz_start
    for i in range(ys.shape[0]):
        pose[0, 0] = ys[i]
        pose[0, 2] = rolls[j]
        for m in range(deltas.shape[0]):
            cz, ok = height_at_penetration(nodes, meta, mono, cids, pose, warm, params, out, deltas[m], cz)
            if not ok:
                failed += 1
                data[i, j, m, :, :] = np.nan
                cz = cz_start
                continue
            out2[:, :, :] = out
            patch_wheels(nodes, meta, cids, pose, params, out2, patch)
            for s in range(K.N_SLOTS):
                h = out[0, s]
                p = out2[0, s]
                row = data[i, j, m, s]
                row[PT_DELTA] = h[K.F_PENETRATION]
                if not (h[K.F_STATUS] > 0 and h[K.F_NORMAL_FORCE] > 0.0):
                    row[PT_CODE] = CODE_NONE
                elif p[K.F_STATUS] == K.STATUS_MERGED:
                    row[PT_CODE] = CODE_MERGED
                elif int(p[K.F_FLAGS]) & K.FLAG_PATCH_FAILED:
                    row[:] = np.nan                   # not tabulated: solved online (and failing there, flagged)
                else:
                    row[PT_CODE] = CODE_PATCH
                    row[PT_LOG_N] = math.log(p[K.F_NORMAL_FORCE])
                    row[PT_GAMMA] = p[K.F_CONTACT_ANGLE]
                    row[PT_S_RAIL] = p[K.F_S_RAIL]
                    row[PT_S_WHEEL] = p[K.F_S_WHEEL]
                    row[PT_A] = p[K.F_SEMI_A]
                    row[PT_B] = p[K.F_SEMI_B]
                    row[PT_LOG_DELTA] = math.log(h[K.F_PENETRATION])
                    row[PT_PATCHED] = 1.0 if int(p[K.F_FLAGS]) & K.FLAG_PATCH else 0.0
        # the next node starts from this one's deepest height
        pose[0, 1] = cz
    return failed


@compiled(parallel=True)
def build_patch_table_core(nodes, meta, mono, curve_row, params, pp, ys, rolls, deltas, cz_start, data):
    """Fill ``data`` (ny, nr, nδ, N_SLOTS, N_PT); ``params`` global-mode kernel parameters.  Returns the number of
    (node, height) pairs whose height did not converge (their data NaN, read as "solve online")."""
    failed = np.zeros(rolls.shape[0], dtype=np.int64)
    for j in prange(rolls.shape[0]):
        failed[j] = _build_column(nodes, meta, mono, curve_row, params, pp, ys, rolls, deltas, j, cz_start, data)
    return failed.sum()


class PatchTable:
    """The tabulated patch of one wheel/rail curve set (build with :func:`patch_table`)."""

    def __init__(self, grid: PatchTableGrid, data: np.ndarray, failed: int, key: str):
        self.grid = grid
        self.data = data
        self.failed = int(failed)
        self.key = key
        ys, rolls, _ = grid.axes()
        self.par = np.zeros(N_TP)
        self.par[TP_Y0], self.par[TP_DY], self.par[TP_NY] = ys[0], grid.dy_m, len(ys)
        self.par[TP_R0], self.par[TP_DR], self.par[TP_NR] = rolls[0], grid.droll_rad, len(rolls)

    def arrays(self):
        """``(par, data, scratch)``: the grid, the data and the evaluation's work array (per slot: its code and
        interpolated values)."""
        return self.par, self.data, np.zeros((K.N_SLOTS, N_PT + 1))


_MEMORY: dict = {}


def patch_table(nodes, meta, mono, curve_row, params, pp=None, grid: PatchTableGrid | None = None,
                cache: bool = True) -> PatchTable:
    """The table for the curves ``curve_row`` with the kernel parameters ``params`` (made global here) and the pass's
    parameters ``pp`` (:func:`~.patch_pass.patch_params`' first element; default its defaults).  Cached in memory and
    on disk (module docstring)."""
    grid = grid or PatchTableGrid()
    pp = patch_params()[0] if pp is None else np.asarray(pp, dtype=float)
    pg = np.array(params, dtype=float)
    pg[K.P_GLOBAL] = 1.0
    key = cache_key(nodes, meta, curve_row, (pg, pp), (grid, PATCH_TABLE_VERSION))
    if key in _MEMORY:
        return _MEMORY[key]
    ys, rolls, deltas = grid.axes()
    shape = (len(ys), len(rolls), len(deltas), K.N_SLOTS, N_PT)
    path = cache_dir() / f"patch_table_{key}.npz"
    z = load_cached(path, shape, ("data", "failed")) if cache else None
    if z is not None:
        t = PatchTable(grid, z["data"], int(z["failed"]), key)
        _MEMORY[key] = t
        return t
    data = np.zeros(shape)
    failed = build_patch_table_core(nodes, meta, mono, np.asarray(curve_row, dtype=np.int64), pg, pp, ys, rolls,
                                    deltas, nominal_height(nodes, meta, curve_row), data)
    t = PatchTable(grid, data, failed, key)
    _MEMORY[key] = t
    if cache:
        save_cached(path, data=data, failed=failed)
    return t


# ------------------------------------------------------------------------------------------------- evaluation
@compiled(refcount=False)
def _corner(data, i, j, s, delta, log_delta, acc, weight):
    """Add ``weight`` × the values of node (i, j) for slot s at penetration ``delta`` into ``acc`` (module
    docstring); returns the code of the two bracketing heights: CODE_PATCH (its contact at both, or appearing
    between them), CODE_MERGED (no force of its own at either, the tail of a zone at one at least), CODE_NONE (no
    contact at either), NaN otherwise (not tabulated)."""
    nd = data.shape[2]
    m = 0
    while m < nd - 2 and data[i, j, m + 1, s, PT_DELTA] < delta:
        m += 1
    code = data[i, j, m, s, PT_CODE]
    if code == CODE_NONE and data[i, j, m + 1, s, PT_CODE] == CODE_PATCH:
        # the slot's zone appears between the two heights: a new zone is small, Hertz's N ∝ δ^1.5 down from the
        # upper height's values
        l1 = data[i, j, m + 1, s, PT_LOG_DELTA]
        acc[PT_LOG_N] += weight * (data[i, j, m + 1, s, PT_LOG_N] + HERTZ_EXPONENT * (log_delta - l1))
        for f in range(PT_GAMMA, PT_LOG_DELTA):
            acc[f] += weight * data[i, j, m + 1, s, f]
        acc[PT_PATCHED] += weight * data[i, j, m + 1, s, PT_PATCHED]
        return CODE_PATCH
    upper = data[i, j, m + 1, s, PT_CODE]
    if code != CODE_PATCH and upper != CODE_PATCH and code == code and upper == upper:
        # no force of its own at either height: none, or the tail of another slot's zone (which carries it)
        return CODE_MERGED if (code == CODE_MERGED or upper == CODE_MERGED) else CODE_NONE
    if upper != code:
        return np.nan
    l0 = data[i, j, m, s, PT_LOG_DELTA]
    l1 = data[i, j, m + 1, s, PT_LOG_DELTA]
    if not l1 > l0:
        return np.nan
    u = (log_delta - l0) / (l1 - l0)
    slope = (data[i, j, m + 1, s, PT_LOG_N] - data[i, j, m, s, PT_LOG_N]) / (l1 - l0)
    acc[PT_LOG_N] += weight * (data[i, j, m, s, PT_LOG_N] + u * slope * (l1 - l0))
    u = min(max(u, 0.0), 1.0)
    for f in range(PT_GAMMA, PT_LOG_DELTA):
        acc[f] += weight * ((1.0 - u) * data[i, j, m, s, f] + u * data[i, j, m + 1, s, f])
    acc[PT_PATCHED] += weight * max(data[i, j, m, s, PT_PATCHED], data[i, j, m + 1, s, PT_PATCHED])
    return code


@compiled(refcount=False)
def patch_tabulated(par, data, slots, nodes, meta, curve_ids, poses, params, out, patch):
    """The pass (:func:`~.patch_pass.patch_wheels`) from the table ``(par, data)`` (module docstring); a wheel the
    table cannot answer is solved online.  ``slots`` the work array (:meth:`PatchTable.arrays`), ``patch`` the
    pass's work arrays (for the fallback)."""
    for w in range(poses.shape[0]):
        c_y, roll = poses[w, 0], poses[w, 2]
        x = (c_y - par[TP_Y0]) / par[TP_DY]
        y = (roll - par[TP_R0]) / par[TP_DR]
        online = not (0.0 <= x <= par[TP_NY] - 1.0 and 0.0 <= y <= par[TP_NR] - 1.0)
        if not online:
            i = min(int(x), int(par[TP_NY]) - 2)
            j = min(int(y), int(par[TP_NR]) - 2)
            fx = x - i
            fy = y - j
            carried = False
            tails = False
            for s in range(K.N_SLOTS):
                row = out[w, s]
                acc = slots[s]
                for f in range(N_PT + 1):
                    acc[f] = 0.0
                if not (row[K.F_STATUS] > 0 and row[K.F_NORMAL_FORCE] > 0.0):
                    continue
                n_patch = 0
                n_merged = 0
                log_delta = math.log(row[K.F_PENETRATION])
                for a in range(2):
                    for b in range(2):
                        c = _corner(data, i + a, j + b, s, row[K.F_PENETRATION], log_delta, acc,
                                    (fx if a else 1.0 - fx) * (fy if b else 1.0 - fy))
                        if c == CODE_PATCH:
                            n_patch += 1
                        elif c == CODE_MERGED:
                            n_merged += 1
                        elif c != CODE_NONE:
                            online = True
                # every corner the slot's own contact, or none of them (the tail of a zone another slot carries at
                # one corner at least, nothing at the others): else it is solved online
                if n_patch == 4:
                    acc[PT_CODE] = CODE_PATCH
                    carried = True
                elif n_patch == 0 and n_merged > 0:
                    acc[PT_CODE] = CODE_MERGED
                    tails = True
                else:
                    online = True
            # a zone's tail needs a loaded slot that carries a zone here: never a wheel left without its force
            if tails and not carried:
                online = True
        if online:
            patch_wheels(nodes, meta, curve_ids[w:w + 1], poses[w:w + 1], params, out[w:w + 1], patch)
            continue
        for s in range(K.N_SLOTS):
            row = out[w, s]
            acc = slots[s]
            if not (row[K.F_STATUS] > 0 and row[K.F_NORMAL_FORCE] > 0.0):
                continue
            if acc[PT_CODE] == CODE_MERGED:
                K.merge_row(row)
                continue
            delta = row[K.F_PENETRATION]
            force = math.exp(acc[PT_LOG_N])
            gamma = acc[PT_GAMMA]
            rny = -math.sin(gamma)
            rnz = -math.cos(gamma)
            s_r = acc[PT_S_RAIL]
            s_w = acc[PT_S_WHEEL]
            ry, rz, _, _ = curve_point(nodes, meta, curve_ids[w, 0], s_r)
            _, qz, _, _ = curve_point(nodes, meta, curve_of(nodes, meta, curve_ids[w, 1], curve_ids[w, 2], s_w), s_w)
            row[K.F_NORMAL_FORCE] = force
            row[K.F_DN_DDELTA] = HERTZ_EXPONENT * force / delta      # as the pass writes it
            row[K.F_SEMI_A] = acc[PT_A]
            row[K.F_SEMI_B] = acc[PT_B]
            row[K.F_CONTACT_ANGLE] = gamma
            row[K.F_NR_Y] = rny
            row[K.F_NR_Z] = rnz
            row[K.F_S_RAIL] = s_r
            row[K.F_S_WHEEL] = s_w
            row[K.F_PR_Y] = ry
            row[K.F_PR_Z] = rz
            row[K.F_PW_Y] = ry - delta * rny
            row[K.F_PW_Z] = rz - delta * rnz
            row[K.F_ROLLING_RADIUS] = qz
            if acc[PT_PATCHED] > 0.0:
                row[K.F_FLAGS] = int(row[K.F_FLAGS]) | K.FLAG_PATCH


@compiled(refcount=False)
def patch_contacts(nodes, meta, curve_ids, poses, params, out, patch):
    """The non-Hertzian patch over the kernel's output ``out``: from the table where the argument
    (:func:`patch_argument`) has one, else solved online (:func:`~.patch_pass.patch_wheels`)."""
    work, table = patch
    if table[1].shape[0] == 0:
        patch_wheels(nodes, meta, curve_ids, poses, params, out, work)
    else:
        patch_tabulated(table[0], table[1], table[2], nodes, meta, curve_ids, poses, params, out, work)
