r"""The non-Hertzian patch in the contact's output: each contact the kernel found, where Hertz does not hold, gets the
resultant of its patch (:mod:`.patch`) in place of Hertz's point.

The switch (per contact, continuous)
------------------------------------
Hertz assumes the interpenetration of the undeformed profiles quadratic over its ellipse, ``g(η) = δ - B η²``.  The
pass reads ``g`` at the lateral edges of Hertz's own ellipse, ``η = ±b`` (two strips of :mod:`.strips`), and its
miss ``D = max |g(±b) - (δ - B b²)| / δ``:

* ``D ≤ D_lo`` (:data:`SWITCH_LO`): Hertz, untouched (the patch would give Hertz's ellipse within its own error);
* ``D ≥ D_hi`` (:data:`SWITCH_HI`): the patch;
* between, the two blended with the smoothstep weight ``w`` of ``(D - D_lo)/(D_hi - D_lo)``: normal force, contact
  angle, lateral position of the point and the semi-axes each ``(1 - w) Hertz + w patch`` — so the contact force
  is continuous in the pose across the switch.

Contacts of one overlap zone (the kernel's two maxima of one zone, or a tread and a flange contact across the
split: a shallower contact whose point lies inside the deepest one's zone) are decided together, before any row is
changed: the weight is that of the group's most non-Hertzian contact, "Hertz" is the group's Hertz contacts
together (their forces summed, their angle and lateral position force-weighted), the deepest row gets the blend
and the others become ``STATUS_MERGED`` with no force — at ``w → 0`` the group's Hertz force, so a second maximum
does not lose its share when the switch turns on.

On S1002/UIC60 (``docs/validation.md``) D is 0.25 at the centred position (one overlap zone 18 mm wide with two
humps), 0.06–0.2 on the conformal tread within ±3 mm of it, ≤ 0.03 on the tread at 2–5 mm and 0 on the flange.

What the pass writes (a contact's row of :mod:`.layout`)
--------------------------------------------------------
``F_NORMAL_FORCE`` the blended force; ``F_CONTACT_ANGLE`` and ``F_NR_*`` the blended resultant's direction (the
strips' normals weighted by their loads); ``F_PR_*`` the rail point at the blended lateral position of the resultant
and ``F_PW_*`` the wheel point δ inside it along that normal (``F_PENETRATION`` stays the kernel's δ);
``F_ROLLING_RADIUS`` the wheel's radius there, ``F_S_RAIL``/``F_S_WHEEL`` the profiles' arc lengths there;
``F_SEMI_A/B`` the equivalent ellipse (the patch's lateral half-width b, the semi-axis a of the same area) for the
tangential problem — the creep laws and the creep table take the patch
as that ellipse, with the creepages at the resultant's point; ``F_DN_DDELTA`` :data:`HERTZ_EXPONENT` ``N/δ`` (the
force's exponent taken as Hertz's: an estimate, read by the series compliance of a structure's residual
flexibility and the run's stability estimate; the implicit solvers difference a patched contact numerically);
``F_FLAGS`` gains the kernel's ``FLAG_PATCH``.  A patch that cannot be solved leaves Hertz and sets
``FLAG_PATCH_FAILED``.
"""
from __future__ import annotations

import math

import numpy as np

from ..jit import compiled
from . import kernel as K
from .layout import (F_B_REL, F_CONTACT_ANGLE, F_DN_DDELTA, F_FLAGS, F_NORMAL_FORCE, F_NR_Y, F_NR_Z,
                     F_PENETRATION, F_PR_Y, F_PR_Z, F_PW_Y, F_PW_Z, F_ROLLING_RADIUS, F_S_RAIL, F_S_WHEEL, F_SEMI_A,
                     F_SEMI_B, F_STATUS, N_SLOTS, P_E_STAR, P_RAIL_ROLL_CURVATURE)
from .patch import (N_RESULTANTS, N_STRIPS, R_AREA, R_COS, R_ETA, R_FORCE, R_HALF_WIDTH, R_SIN, resultants,
                    row_zone_edges, scratch, solve_core)
from .strips import (N_STRIP_FIELDS, S_A, S_ETA, S_G, S_GAMMA, S_OK, S_RADIUS, S_RAIL_Y, S_RAIL_Z, S_S_RAIL,
                     S_S_WHEEL, fill_strips, strip_at)

__all__ = ["SWITCH_LO", "SWITCH_HI", "HERTZ_EXPONENT", "PP_N_STRIPS", "PP_SWITCH_LO", "PP_SWITCH_HI", "N_PP",
           "patch_params",
           "hertz_miss", "patch_wheels"]

#: Hertz's miss of the interpenetration at its ellipse's edges below which Hertz is kept, above which the patch
#: replaces it (relative to δ; module docstring)
SWITCH_LO = 0.02
SWITCH_HI = 0.05

# a zone's Hertz resultant (the pass's scratch, zones[group, 1:]): hertz[_H_*]
_H_FORCE = 0
_H_ETA = 1
_H_GAMMA = 2
_H_A = 3
_H_B = 4
N_H = 5
# a contact's row of the pass's zones scratch: its group (the leader's index), the Hertz resultant, the zone's edges
_Z_GROUP = 0
_Z_HERTZ = 1
_Z_LO = _Z_HERTZ + N_H
_Z_HI = _Z_LO + 1
_Z_WIDTH = _Z_HI + 1
#: the exponent of the force against the penetration taken for dN/dδ (Hertz's; the patch's own is close to it)
HERTZ_EXPONENT = 1.5

# the pass's parameters: pp[PP_*]
PP_N_STRIPS = 0
PP_SWITCH_LO = 1
PP_SWITCH_HI = 2
N_PP = 3


def patch_params(n_strips: int = N_STRIPS, switch_lo: float = SWITCH_LO, switch_hi: float = SWITCH_HI) -> tuple:
    """The pass's argument ``patch``: its parameters ``pp[PP_*]`` and its work arrays (nothing is allocated per
    call): ``(pp, strips (n, N_STRIP_FIELDS), zones (N_SLOTS, _Z_WIDTH): per contact its group, the group's Hertz
    resultant and its zone's edges, vecs (5, max(n, N_RESULTANTS)): g, A, q, x_l (their first n entries) and the
    patch's resultants (patch.resultants), *patch.scratch(n), order (N_SLOTS,) int)``."""
    if not (isinstance(n_strips, int) and n_strips >= 5):
        raise ValueError(f"n_strips: expected an integer >= 5, got {n_strips!r}")
    if not 0.0 <= switch_lo < switch_hi:
        raise ValueError(f"switch: expected 0 <= switch_lo < switch_hi, got {switch_lo!r}, {switch_hi!r}")
    pp = np.zeros(N_PP)
    pp[PP_N_STRIPS] = n_strips
    pp[PP_SWITCH_LO] = switch_lo
    pp[PP_SWITCH_HI] = switch_hi
    return pass_work(pp)


@compiled
def pass_work(pp):
    """The pass's argument for the parameters ``pp`` (:func:`patch_params`, whose docstring lists the arrays)."""
    n = int(pp[PP_N_STRIPS])
    C, aug, vectors, idx = scratch(n)
    return (pp, np.zeros((n, N_STRIP_FIELDS)), np.zeros((N_SLOTS, _Z_WIDTH)), np.zeros((5, max(n, N_RESULTANTS))), C,
            aug, vectors, idx, np.zeros(N_SLOTS, dtype=np.int64))


@compiled(refcount=False)
def hertz_miss(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, row, k_rail_roll, scratch):
    """D = max |g(±b) - (δ - B b²)| / δ of a contact's row (module docstring)."""
    delta = row[F_PENETRATION]
    b = row[F_SEMI_B]
    quad = delta - row[F_B_REL] * b * b
    miss = 0.0
    for side in (-1.0, 1.0):
        g = strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, row[F_PR_Y], row[F_PR_Z], row[F_NR_Y],
                     row[F_NR_Z], row[F_S_RAIL], row[F_S_WHEEL], k_rail_roll, side * b, scratch)
        miss = max(miss, abs(g - quad))
    return miss / delta


@compiled(refcount=False)
def _patch_row(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, row, k_rail_roll, e_star, n, weight,
               hertz, lo, hi, strips, vecs, C, aug, vectors, idx):
    """Solve the patch of ``row``'s zone and write its blend with Hertz's resultant ``hertz`` (_H_*: force,
    lateral position in the plane, angle, semi-axes — the zone's Hertz contacts together) into ``row``; ``lo``,
    ``hi`` the zone's edges (:func:`~.patch.row_zone_edges`).  False (row untouched) if the patch could not be
    solved."""
    o_y, o_z, n_y, n_z = row[F_PR_Y], row[F_PR_Z], row[F_NR_Y], row[F_NR_Z]
    s_r, s_w = row[F_S_RAIL], row[F_S_WHEEL]
    if not hi - lo > 0.0:
        return False
    fill_strips(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, s_r, s_w, k_rail_roll,
                lo, hi, strips)
    g = vecs[0]
    A = vecs[1]
    q = vecs[2]
    xl = vecs[3]
    for j in range(n):
        if strips[j, S_OK] == 0.0:
            return False
        g[j] = strips[j, S_G]
        A[j] = strips[j, S_A]
        if not A[j] > 0.0:
            return False
    width = (hi - lo) / n
    it, _ = solve_core(g, A, n, width, e_star, q, xl, C, aug, vectors, idx)
    if it < 0:
        return False
    res = vecs[4]
    resultants(q, xl, width, strips[:, S_GAMMA], strips[:, S_ETA], n, res)
    force = res[R_FORCE]
    if not force > 0.0:
        return False
    delta = row[F_PENETRATION]
    w = weight
    eta = (1.0 - w) * hertz[_H_ETA] + w * res[R_ETA] / force
    gamma = (1.0 - w) * hertz[_H_GAMMA] + w * math.atan2(res[R_SIN], res[R_COS])
    b_patch = res[R_HALF_WIDTH]
    a_patch = res[R_AREA] / (math.pi * b_patch)
    # the rail point and the wheel's radius at the resultant's lateral position (a strip of its own)
    strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, s_r, s_w, k_rail_roll,
             eta, strips[0])
    if strips[0, S_OK] == 0.0:
        return False
    rny = -math.sin(gamma)
    rnz = -math.cos(gamma)
    force = (1.0 - w) * hertz[_H_FORCE] + w * force
    row[F_NORMAL_FORCE] = force
    row[F_DN_DDELTA] = HERTZ_EXPONENT * force / delta
    row[F_SEMI_A] = (1.0 - w) * hertz[_H_A] + w * a_patch
    row[F_SEMI_B] = (1.0 - w) * hertz[_H_B] + w * b_patch
    row[F_CONTACT_ANGLE] = gamma
    row[F_NR_Y] = rny
    row[F_NR_Z] = rnz
    row[F_PR_Y] = strips[0, S_RAIL_Y]
    row[F_PR_Z] = strips[0, S_RAIL_Z]
    row[F_PW_Y] = strips[0, S_RAIL_Y] - delta * rny
    row[F_PW_Z] = strips[0, S_RAIL_Z] - delta * rnz
    row[F_ROLLING_RADIUS] = strips[0, S_RADIUS]
    row[F_S_RAIL] = strips[0, S_S_RAIL]
    row[F_S_WHEEL] = strips[0, S_S_WHEEL]
    return True


@compiled(refcount=False)
def patch_wheels(nodes, meta, curve_ids, poses, params, out, patch):
    """The pass over the kernel's output ``out`` (n_wheels, N_SLOTS, N_FIELDS) at the side-frame ``poses``
    (module docstring), ``patch`` of :func:`patch_params`; rows rewritten in place."""
    pp, strips, zones, vecs, C, aug, vectors, idx, order = patch
    n = int(pp[PP_N_STRIPS])
    lo_sw = pp[PP_SWITCH_LO]
    hi_sw = pp[PP_SWITCH_HI]
    e_star = params[P_E_STAR]
    k_rr = params[P_RAIL_ROLL_CURVATURE]
    for w in range(poses.shape[0]):
        rail, tread, flange = curve_ids[w, 0], curve_ids[w, 1], curve_ids[w, 2]
        c_y, c_z = poses[w, 0], poses[w, 1]
        cos_r = math.cos(poses[w, 2])
        sin_r = math.sin(poses[w, 2])
        # the contacts by depth; a shallower contact inside a deeper one's overlap zone is that zone seen twice:
        # one group, its patch the deepest's (found before any is decided, so that a group is decided as one)
        m = 0
        for slot in range(N_SLOTS):
            if out[w, slot, F_STATUS] > 0 and out[w, slot, F_NORMAL_FORCE] > 0.0:
                order[m] = slot
                m += 1
        for a in range(1, m):
            b = a
            while b > 0 and out[w, order[b], F_PENETRATION] > out[w, order[b - 1], F_PENETRATION]:
                order[b], order[b - 1] = order[b - 1], order[b]
                b -= 1
        for a in range(m):
            zones[a, _Z_GROUP] = -1.0                 # the group's leader (an index into order), -1: none yet
            zones[a, _Z_LO] = np.nan                  # the zone's edges: found when needed, once
        for a in range(m):
            if zones[a, _Z_GROUP] >= 0.0:
                continue
            zones[a, _Z_GROUP] = a
            if a == m - 1:
                break
            lead = out[w, order[a]]
            t_y, t_z = -lead[F_NR_Z], lead[F_NR_Y]
            lo, hi = row_zone_edges(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, lead, k_rr, strips[0])
            zones[a, _Z_LO] = lo
            zones[a, _Z_HI] = hi
            for b in range(a + 1, m):
                other = out[w, order[b]]
                e = (other[F_PR_Y] - lead[F_PR_Y]) * t_y + (other[F_PR_Z] - lead[F_PR_Z]) * t_z
                if zones[b, _Z_GROUP] < 0.0 and lo <= e <= hi:
                    zones[b, _Z_GROUP] = a
        for a in range(m):
            if zones[a, _Z_GROUP] != a:
                continue
            lead = out[w, order[a]]
            # the group's switch weight (its most non-Hertzian contact's) and its Hertz resultant
            weight = 0.0
            hertz = zones[a, _Z_HERTZ:_Z_HERTZ + N_H]
            for f in range(N_H):
                hertz[f] = 0.0
            sy = 0.0
            sz = 0.0
            for b in range(a, m):
                if zones[b, _Z_GROUP] != a:
                    continue
                row = out[w, order[b]]
                miss = hertz_miss(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, row, k_rr, strips[0])
                x = (miss - lo_sw) / (hi_sw - lo_sw)
                if x > 0.0:
                    weight = max(weight, 1.0 if x >= 1.0 else x * x * (3.0 - 2.0 * x))
                f_n = row[F_NORMAL_FORCE]
                hertz[_H_FORCE] += f_n
                sy += f_n * math.sin(row[F_CONTACT_ANGLE])
                sz += f_n * math.cos(row[F_CONTACT_ANGLE])
                hertz[_H_ETA] += f_n * ((row[F_PR_Y] - lead[F_PR_Y]) * -lead[F_NR_Z]
                                        + (row[F_PR_Z] - lead[F_PR_Z]) * lead[F_NR_Y])
            if weight == 0.0:
                continue                              # Hertz holds: the rows stay the kernel's
            hertz[_H_ETA] /= hertz[_H_FORCE]
            hertz[_H_GAMMA] = math.atan2(sy, sz)
            hertz[_H_A] = lead[F_SEMI_A]
            hertz[_H_B] = lead[F_SEMI_B]
            if np.isnan(zones[a, _Z_LO]):
                zones[a, _Z_LO], zones[a, _Z_HI] = row_zone_edges(nodes, meta, rail, tread, flange, c_y, c_z, cos_r,
                                                              sin_r, lead, k_rr, strips[0])
            if _patch_row(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, lead, k_rr, e_star, n, weight,
                          hertz, zones[a, _Z_LO], zones[a, _Z_HI], strips, vecs, C, aug, vectors, idx):
                lead[F_FLAGS] = int(lead[F_FLAGS]) | K.FLAG_PATCH
                for b in range(a + 1, m):
                    if zones[b, _Z_GROUP] == a:
                        K.merge_row(out[w, order[b]])
            else:
                lead[F_FLAGS] = int(lead[F_FLAGS]) | K.FLAG_PATCH_FAILED
