"""The compiled all-wheels contact evaluation: geometry (convex/concave search) + Hertz, one call for a vehicle.

:func:`evaluate_wheels` takes plain arrays and fills ``out[wheel, region, field]`` (region 0 = tread, 1 = flange;
fields below).  It is the inner loop of the Exudyn connector; :class:`ContactKernel` wraps it for Python users.

Per wheel and region the search is (Montenegro et al. 2015, Sec. 2):

1. **separation bound** (warm mode): once a region's smallest gap g is known (computed over the whole region) at a
   reference pose, the region is reported separated without any search while the wheel has moved less than g
   since (translation + |roll change| x P_WHEEL_LEVER): the signed distance is 1-Lipschitz in the point position,
   so this skips no contact.  The reported penetration is then minus that guaranteed lower bound;
2. **convex search**: Newton on the two contact conditions from the last solution (warm mode) or from the best
   basins (P_N_STARTS deepest local maxima) of a coarse vertical-overlap scan of the region (global mode, or when the warm start fails, lands on a
   concave/conformal point, or has lifted off — the region is then checked as a whole).  Accepted when it
   converges inside the region with opposing normals, penetration, and a locally convex pair:
   kappa_w + kappa_r >= P_CONVEX_MIN_CURVATURE (relative lateral curvature; the two conditions then mark a strict
   local minimum of the distance).  The paper checks the wheel's convexity alone (kappa_w >= 0); S1002's tread is
   mildly concave everywhere (kappa_w about -3 to -5 1/m against UIC60's +3.3 crown), so the relative curvature
   is what separates a well-posed convex contact from a conformal one that needs the concave search;
3. otherwise the **concave search** (maximum vertical overlap, :func:`~.search.vertical_overlap_search`).  Its
   point is polished by Newton when the pair is convex there (then it is a convex contact); else it moves to the
   deepest point by *normal* distance within P_CONCAVE_NORMAL_WINDOW, when that is a true local maximum inside
   the window (in a conformal throat the vertical and the normal maximum lie up to ~4 mm and ~8 µm apart); else
   (the normal penetration still rises at the window's edge) it follows the normal penetration uphill
   (:func:`~.search.normal_penetration_ascent`) to the local maximum of its zone, or to the region's end if the
   penetration rises all the way there.  The rail point is the normal foot: the penetration is always the normal
   distance of the reported wheel point;
4. **apart**: the region's gap is its smallest normal distance over the whole region
   (:func:`~.search.nearest_by_normal_distance`); for step 1 it is remembered less the largest dip a distance
   function can make between two scan samples, h^2/8 x P_CURVATURE_BOUND (h = sample spacing);
5. **Hertz** for every contact: N = Kh delta^1.5, dN/ddelta, a, b.

Both regions of a wheel may carry a contact (two-point contact).  One overlap zone that straddles the tread/flange
split is reported once: a region whose point sits at its split end (the normal penetration rises all the way to
the split: no maximum of its own) is the tail of the neighbour's zone and is dropped, and so is the shallower of two
points closer than P_DEDUP_DISTANCE.  Two separate local maxima of the
penetration (e.g. flange flank and tread, even with the throat between them in overlap) stay two contacts.

Several zones on one region (S1002/UIC60 has two tread zones ~10 mm apart near the centred position):

* **tracking**: a region remembers its other local optimum of the last scan (``W_ALT_*``) and in warm mode runs
  Newton from it too, so a deeper zone is never missed (warm mode = global mode); a region in contact is rescanned
  after ``P_RESCAN_DISTANCE`` of lateral motion to discover zones that appear.  The curves at the warm start and
  at the other zone's point are kept as the search last evaluated them (``W_CURVES``, ``W_ALT_CURVES``): the
  next Newton search from there, and a region separated by its bound, take them;
* **two patches** (the surfaces separate between the two points): the second zone is reported in the extra output
  slot ``SLOT_TREAD_2`` — a two-point contact on the tread;
* **one zone with two maxima** (the surfaces overlap all the way between them — a conformal zone): Hertz at either
  maximum gives very different forces (S1002/UIC60: 37 vs 67 kN at the same pose), so picking the deeper one makes
  the normal force jump by a factor of two when the depths cross, which excites a wheelset bounce.  Where the two
  depths differ by less than ``P_BLEND_DEPTH`` × the deeper one, both are reported (slots tread and tread-2) with
  their normal forces weighted by a smoothstep of the depth difference (½–½ at equal depth), flag
  ``FLAG_BLENDED``: the total force is continuous.  This is a regularisation of the one-Hertz-point model, not a
  conformal-contact theory (a semi-Hertzian model would be the remedy).
"""
from __future__ import annotations

import numpy as np

from ..jit import compiled
from ..profiles.curve import curve_eval
from .layout import (  # noqa: F401  (the kernel's fields, slots, warm start, parameters; re-exported)
    F_A_REL, F_B_REL, F_CONTACT_ANGLE, F_DN_DDELTA, F_FLAGS, F_HERTZ_STATUS, F_ITERATIONS, F_KR_LAT, F_KR_ROLL,
    F_KW_LAT, F_KW_ROLL, F_NORMAL_FORCE, F_NR_Y, F_NR_Z, F_PENETRATION, F_PR_Y, F_PR_Z, F_PW_Y, F_PW_Z,
    F_ROLLING_RADIUS, F_S_RAIL, F_S_WHEEL, F_SEMI_A, F_SEMI_B, F_STATUS, N_FIELDS, N_PARAMS, N_SLOTS, N_WARM,
    P_BLEND_DEPTH, P_CONCAVE_NORMAL_WINDOW, P_CONVEX_MIN_CURVATURE, P_CURVATURE_BOUND, P_DEDUP_DISTANCE, P_E_STAR,
    P_GLOBAL, P_MAX_PENETRATION, P_MIN_CURVATURE, P_N_CONCAVE_RAIL, P_N_CONCAVE_WHEEL, P_N_SCAN, P_N_STARTS,
    P_NEWTON_MAX_ITER, P_NEWTON_TOL, P_RAIL_ROLL_CURVATURE, P_REFINE, P_RESCAN_DISTANCE, P_WHEEL_LEVER,
    KEPT_BLOCK, KEPT_RAIL, KEPT_S_RAIL, KEPT_S_WHEEL, KEPT_WHEEL, SLOT_FLANGE, SLOT_TREAD, SLOT_TREAD_2,
    W_ALT_CURVES, W_ALT_S_RAIL, W_ALT_S_WHEEL, W_CURVES, W_GAP, W_POSE_ROLL, W_POSE_Y, W_POSE_Z, W_S_RAIL, W_S_WHEEL,
    W_SCAN_Y)
from .normal import hertz_from_penetration
from .search import (NO_SCAN, overlap_at_wheel, nearest_by_normal_distance, nearest_start, newton_from,
                     normal_foot, normal_penetration_ascent, overlap_peaks, place_point, place_wheel_point,
                     scan_points, vertical_overlap_search, wheel_point)

# ---- flags (F_FLAGS bits) and status (F_STATUS) ------------------------------------------------------------------
FLAG_PROFILE_END = 1        # the wheel or rail point is at an end of its profile: the contact may lie beyond the data
FLAG_DEEP_PENETRATION = 2   # penetration above P_MAX_PENETRATION: far outside elastic contact (climbing, bad pose)
FLAG_HERTZ_CLAMPED = 4      # relative curvature clamped (conformal contact): Hertz is an approximation there
FLAG_BLENDED = 8            # one of two blended penetration maxima of one overlap zone (normal force weighted)
FLAG_PATCH = 16             # the non-Hertzian patch's resultant (contact.patch_pass), partly where the switch blends
FLAG_PATCH_FAILED = 32      # the non-Hertzian patch could not be solved: Hertz kept (contact.patch_pass)

STATUS_SEPARATED = 0  # a solution was found, no penetration
STATUS_CONVEX = 1     # contact from the convex search
STATUS_CONCAVE = 2    # contact from the concave search
STATUS_NO_OVERLAP = -1  # the region does not face the rail (no vertical overlap at all)
STATUS_MERGED = -2      # penetrating, but the tail of the other region's contact zone (reported there, no force)
STATUS_INVALID_POSE = -3  # the pose contains NaN or infinity: every other output field is NaN


def default_params(E_star: float, global_search: bool = False, n_scan: int = 200, n_concave_wheel: int = 100,
                   n_concave_rail: int = 100, refine: bool = True, newton_tol_m: float = 1e-11,
                   newton_max_iter: int = 30, min_curvature: float = 0.1, dedup_distance_m: float = 1e-3,
                   convex_min_curvature: float = 0.5, max_penetration_m: float = 2e-3, wheel_lever_m: float = 2.0,
                   curvature_bound: float = 200.0, n_starts: int = 3, concave_normal_window_m: float = 5e-3,
                   rescan_distance_m: float = 0.2e-3, blend_depth: float = 0.1):
    """Parameter vector for :func:`evaluate_wheels` (see the P_* indices)."""
    p = np.zeros(N_PARAMS)
    p[P_E_STAR] = E_star
    p[P_NEWTON_TOL] = newton_tol_m
    p[P_NEWTON_MAX_ITER] = newton_max_iter
    p[P_N_SCAN] = n_scan
    p[P_N_CONCAVE_WHEEL] = n_concave_wheel
    p[P_N_CONCAVE_RAIL] = n_concave_rail
    p[P_REFINE] = 1.0 if refine else 0.0
    p[P_GLOBAL] = 1.0 if global_search else 0.0
    p[P_RAIL_ROLL_CURVATURE] = 0.0
    p[P_MIN_CURVATURE] = min_curvature
    p[P_DEDUP_DISTANCE] = dedup_distance_m
    p[P_CONVEX_MIN_CURVATURE] = convex_min_curvature
    p[P_MAX_PENETRATION] = max_penetration_m
    p[P_WHEEL_LEVER] = wheel_lever_m
    p[P_CURVATURE_BOUND] = curvature_bound
    p[P_N_STARTS] = n_starts
    p[P_CONCAVE_NORMAL_WINDOW] = concave_normal_window_m
    p[P_RESCAN_DISTANCE] = rescan_distance_m
    p[P_BLEND_DEPTH] = blend_depth
    return p


@compiled(refcount=False)
def _fill(out, w, reg, status, s_w, s_r, nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, iters, params):
    """Evaluate geometry at (s_w, s_r) and Hertz; write one output row."""
    qy, qz, qty, qtz, qny, qnz, kw = curve_eval(nodes, meta, wheel, s_w)   # wheelset frame
    ry, rz, rty, rtz, rny, rnz, kr = curve_eval(nodes, meta, rail, s_r)
    _fill_at(out, w, reg, status, s_w, s_r, qy, qz, qnz, kw, ry, rz, rny, rnz, kr, nodes, meta, rail, wheel, c_y, c_z,
             cos_r, sin_r, iters, params)


@compiled(refcount=False)
def _fill_at(out, w, reg, status, s_w, s_r, qy, qz, qnz, kw, ry, rz, rny, rnz, kr, nodes, meta, rail, wheel, c_y, c_z,
             cos_r, sin_r, iters, params):
    """:func:`_fill` with the curves already evaluated at (s_w, s_r): the wheel's point, normal z and curvature in
    the wheelset frame (``qy, qz, qnz, kw``), the rail's point, normal and curvature (``ry ... kr``)."""
    wy, wz = place_point(qy, qz, c_y, c_z, cos_r, sin_r)
    delta = -((wy - ry) * rny + (wz - rz) * rnz)
    r_roll = qz
    k_w_roll = qnz / r_roll        # Meusnier: normal curvature of the parallel circle, cos(psi)/r
    k_r_roll = params[P_RAIL_ROLL_CURVATURE]
    o = out[w, reg]
    o[F_S_WHEEL] = s_w
    o[F_S_RAIL] = s_r
    o[F_PW_Y] = wy
    o[F_PW_Z] = wz
    o[F_PR_Y] = ry
    o[F_PR_Z] = rz
    o[F_NR_Y] = rny
    o[F_NR_Z] = rnz
    o[F_PENETRATION] = delta
    o[F_CONTACT_ANGLE] = np.arctan2(-rny, -rnz)
    o[F_ROLLING_RADIUS] = r_roll
    o[F_KW_LAT] = kw
    o[F_KW_ROLL] = k_w_roll
    o[F_KR_LAT] = kr
    o[F_KR_ROLL] = k_r_roll
    A = 0.5 * (k_w_roll + k_r_roll)
    B = 0.5 * (kw + kr)
    o[F_A_REL] = A
    o[F_B_REL] = B
    o[F_ITERATIONS] = iters
    flags = 0
    w_first = int(meta[wheel, 0])
    r_first = int(meta[rail, 0])
    w_ends = int(meta[wheel, 4])
    if ((w_ends & 1) and s_w <= nodes[w_first, 0] + 1e-9) or \
            ((w_ends & 2) and s_w >= nodes[w_first + int(meta[wheel, 1]) - 1, 0] - 1e-9) or \
            s_r <= nodes[r_first, 0] + 1e-9 or s_r >= nodes[r_first + int(meta[rail, 1]) - 1, 0] - 1e-9:
        flags |= FLAG_PROFILE_END
    if delta > params[P_MAX_PENETRATION]:
        flags |= FLAG_DEEP_PENETRATION
    o[F_FLAGS] = flags
    if delta > 0.0 and status > 0:
        n, dn, a, b, hs = hertz_from_penetration(A, B, params[P_E_STAR], delta, params[P_MIN_CURVATURE])
        o[F_STATUS] = status
        o[F_NORMAL_FORCE] = n
        o[F_DN_DDELTA] = dn
        o[F_SEMI_A] = a
        o[F_SEMI_B] = b
        o[F_HERTZ_STATUS] = hs
        if hs & 3:
            o[F_FLAGS] = flags | FLAG_HERTZ_CLAMPED
    else:
        o[F_STATUS] = STATUS_SEPARATED if status >= 0 else status
        o[F_NORMAL_FORCE] = 0.0
        o[F_DN_DDELTA] = 0.0
        o[F_SEMI_A] = 0.0
        o[F_SEMI_B] = 0.0
        o[F_HERTZ_STATUS] = 0.0


@compiled(refcount=False)
def _keep_curves(kept, block, s_w, s_r, q, r):
    """Keep the curves evaluated at (s_w, s_r) in the block of kept curves at ``kept[block:]`` (``KEPT_*``; a warm
    row's :data:`W_CURVES` or :data:`W_ALT_CURVES`, or a candidate's scratch row): ``q`` the wheel's, ``r`` the
    rail's :func:`curve_eval`."""
    kept[block + KEPT_S_WHEEL] = s_w
    kept[block + KEPT_S_RAIL] = s_r
    for j in range(7):
        kept[block + KEPT_WHEEL + j] = q[j]
        kept[block + KEPT_RAIL + j] = r[j]


@compiled(inline="always")
def _block_curves(kept, block):
    """The wheel's and the rail's curves kept in the block at ``kept[block:]``."""
    c = block + KEPT_WHEEL
    d = block + KEPT_RAIL
    return ((kept[c], kept[c + 1], kept[c + 2], kept[c + 3], kept[c + 4], kept[c + 5], kept[c + 6]),
            (kept[d], kept[d + 1], kept[d + 2], kept[d + 3], kept[d + 4], kept[d + 5], kept[d + 6]))


@compiled(inline="always")
def _kept_at(kept, block, s_w, s_r):
    """Whether the block at ``kept[block:]`` holds the curves at (s_w, s_r)."""
    return kept[block + KEPT_S_WHEEL] == s_w and kept[block + KEPT_S_RAIL] == s_r


@compiled(inline="always")
def _kept_curves(kept, nodes, meta, rail, wheel, s_w, s_r):
    """The wheel's and the rail's :func:`curve_eval` at (s_w, s_r): those kept in the warm row ``kept`` (the warm
    start's or the other zone's block) when they were evaluated there, else evaluated now."""
    for block in (W_CURVES, W_ALT_CURVES):
        if _kept_at(kept, block, s_w, s_r):
            return _block_curves(kept, block)
    return curve_eval(nodes, meta, wheel, s_w), curve_eval(nodes, meta, rail, s_r)


@compiled(refcount=False)
def _fill_curves(out, w, reg, status, s_w, s_r, q, r, nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, iters,
                 params):
    """:func:`_fill_at` from the curves' :func:`curve_eval` at the point: ``q`` the wheel's (wheelset frame),
    ``r`` the rail's."""
    _fill_at(out, w, reg, status, s_w, s_r, q[0], q[1], q[5], q[6], r[0], r[1], r[4], r[5], r[6], nodes, meta, rail,
             wheel, c_y, c_z, cos_r, sin_r, iters, params)


@compiled(refcount=False)
def _fill_warm(out, w, reg, warm, s_w, s_r, nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, params):
    """:func:`_fill` of a separated region at its warm start (s_w, s_r) = ``warm[w, reg, W_S_*]``, from the curves
    kept there (evaluated and kept when they are not)."""
    kept = warm[w, reg]
    if not _kept_at(kept, W_CURVES, s_w, s_r):
        _keep_curves(kept, W_CURVES, s_w, s_r, curve_eval(nodes, meta, wheel, s_w), curve_eval(nodes, meta, rail, s_r))
    q, r = _block_curves(kept, W_CURVES)
    _fill_curves(out, w, reg, STATUS_SEPARATED, s_w, s_r, q, r, nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, 0,
                 params)


@compiled(refcount=False)
def _no_overlap(out, w, reg):
    out[w, reg, :] = 0.0
    out[w, reg, F_STATUS] = STATUS_NO_OVERLAP
    out[w, reg, F_PENETRATION] = -np.inf


#: the curves' placeholder (:func:`curve_eval`'s seven values) where a search found no point
NO_CURVE = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

#: rows of the scratch array of :func:`_solve_region` (N_SCRATCH_ROWS, SCRATCH_WIDTH): Newton starts and candidates
#: (MAX_STARTS), the rail samples of the nearest-pair start (NEAREST_RAIL_SAMPLES)
_SC_START_SW = 0
_SC_START_SR = 1
_SC_CAND_SW = 2
_SC_CAND_SR = 3
_SC_CAND_DELTA = 4
_SC_CAND_CONVEX = 5     # 1.0: the candidate is a convex optimum
_SC_RAIL_Y = 6
_SC_RAIL_Z = 7
_SC_CAND_CURVES = 8     # MAX_STARTS rows: each candidate's curves at its point (a block of kept curves, KEPT_*)
MAX_STARTS = 8          # Newton starts and tracked candidates per region
N_SCRATCH_ROWS = _SC_CAND_CURVES + MAX_STARTS
#: rail samples of the nearest-pair Newton start (:func:`~.search.nearest_start`): 2-3 mm apart on a rail head
NEAREST_RAIL_SAMPLES = 50
SCRATCH_WIDTH = max(MAX_STARTS, NEAREST_RAIL_SAMPLES, KEPT_BLOCK)


def scan_array(nodes, meta, n_scan: int) -> np.ndarray:
    """The coarse scan's wheel points of every packed curve, (n_curves, n_scan, 2) (:func:`~.search.scan_points`),
    for the ``scan`` argument of :func:`evaluate_wheels`: a scan then places stored points instead of evaluating the
    wheel curve, with the same result.  Used while ``params[P_N_SCAN]`` equals ``n_scan``."""
    n_scan = int(n_scan)
    if n_scan < 2:
        return NO_SCAN
    return np.ascontiguousarray([scan_points(nodes, meta, c, n_scan) for c in range(meta.shape[0])])


@compiled(refcount=False)
def _scan_starts(nodes, meta, mono, rail, wheel, c_y, c_z, cos_r, sin_r, s_lo, s_hi, n_scan, k_max, out_sw, out_sr,
                 points, scratch):
    """Newton starts: the deepest local maxima of a coarse vertical-overlap scan, or the nearest sample pair;
    ``points`` the scan's cached wheel points of the whole region (or none, :func:`scan_array`)."""
    n = overlap_peaks(nodes, meta, mono, rail, wheel, c_y, c_z, cos_r, sin_r, s_lo, s_hi, n_scan,
                      min(k_max, MAX_STARTS), out_sw, out_sr, points)
    if n == 0:
        # a Newton start only: a few rail samples are plenty
        out_sw[0], out_sr[0] = nearest_start(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, s_lo, s_hi, n_scan,
                                             min(n_scan, NEAREST_RAIL_SAMPLES), scratch[_SC_RAIL_Y],
                                             scratch[_SC_RAIL_Z])
        n = 1
    return n


@compiled(refcount=False)
def _newton_candidate(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, s_r, s_w, s_lo, s_hi, r_lo, r_hi, params,
                      kept):
    """Convex search from (s_r, s_w), from the curves kept in the warm row ``kept`` when they were evaluated there.
    Returns (valid, convex, s_r, s_w, penetration, iterations, wheel curve, rail curve): valid = converged inside
    both ranges with opposing normals; convex = valid and kappa_w + kappa_r >= P_CONVEX_MIN_CURVATURE; the curves'
    :func:`curve_eval` at the point (the wheel's in the wheelset frame; valid only)."""
    q0, r0 = _kept_curves(kept, nodes, meta, rail, wheel, s_w, s_r)
    conv, s_r, s_w, it = newton_from(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, s_r, s_w,
                                     int(params[P_NEWTON_MAX_ITER]), params[P_NEWTON_TOL], r0, q0)
    if not (conv and s_lo <= s_w <= s_hi and r_lo <= s_r <= r_hi):
        return False, False, s_r, s_w, 0.0, it, NO_CURVE, NO_CURVE
    q = curve_eval(nodes, meta, wheel, s_w)   # wheel_point, unplaced values kept
    wy, wz, wty, wtz, wny, wnz, kw = place_wheel_point(q[0], q[1], q[2], q[3], q[4], q[5], q[6], c_y, c_z, cos_r,
                                                       sin_r)
    r = curve_eval(nodes, meta, rail, s_r)
    ry, rz, rty, rtz, rny, rnz, kr = r
    if wny * rny + wnz * rnz >= 0.0:
        return False, False, s_r, s_w, 0.0, it, q, r
    delta = -((wy - ry) * rny + (wz - rz) * rnz)
    return True, kw + kr >= params[P_CONVEX_MIN_CURVATURE], s_r, s_w, delta, it, q, r


@compiled
def solve_region(nodes, meta, mono, rail, wheel, c_y, c_z, roll, warm, params, out, w, reg, slot2=-1):
    """Contact of one wheel region with the rail (steps in the module docstring); updates ``warm[w, reg]``.
    ``slot2`` >= 0: the output slot for the region's second, separate contact zone (filled when a distinct convex
    optimum also penetrates and the surfaces separate between the two points), else left untouched."""
    _solve_region(nodes, meta, mono, rail, wheel, c_y, c_z, roll, np.cos(roll), np.sin(roll), warm, params, out, w,
                  reg, slot2, np.empty((N_SCRATCH_ROWS, SCRATCH_WIDTH)), NO_SCAN)


@compiled(refcount=False)
def _solve_region(nodes, meta, mono, rail, wheel, c_y, c_z, roll, cos_r, sin_r, warm, params, out, w, reg, slot2,
                  scratch, scan):
    """:func:`solve_region` with the cosine and sine of the roll given, a scratch array (``N_SCRATCH_ROWS``,
    ``SCRATCH_WIDTH``) for the Newton starts and candidates (no allocation per call) and the cached scan points
    (:func:`scan_array` or :data:`NO_SCAN`)."""
    if wheel < 0:                                   # the profile has no such region (e.g. a flangeless cone)
        _no_overlap(out, w, reg)
        return
    first = int(meta[wheel, 0])
    s_lo = nodes[first, 0]
    s_hi = nodes[first + int(meta[wheel, 1]) - 1, 0]
    r_first = int(meta[rail, 0])
    r_lo = nodes[r_first, 0]
    r_hi = nodes[r_first + int(meta[rail, 1]) - 1, 0]
    n_scan = int(params[P_N_SCAN])
    points = scan[wheel] if wheel < scan.shape[0] else scan[0]    # used by the scan when it has n_scan rows
    warm_mode = params[P_GLOBAL] == 0.0
    s_r = warm[w, reg, W_S_RAIL]
    s_w = warm[w, reg, W_S_WHEEL]
    scanned = not (warm_mode and np.isfinite(s_r) and np.isfinite(s_w))
    if not scanned and warm[w, reg, W_GAP] > 0.0:
        # separation bound: the signed distance to the rail is 1-Lipschitz in the wheel point's position, and no
        # wheel point has moved further than `motion` since the region's smallest gap was computed globally
        motion = (abs(c_y - warm[w, reg, W_POSE_Y]) + abs(c_z - warm[w, reg, W_POSE_Z])
                  + abs(roll - warm[w, reg, W_POSE_ROLL]) * params[P_WHEEL_LEVER])
        if warm[w, reg, W_GAP] - motion > 0.0:
            _fill_warm(out, w, reg, warm, s_w, s_r, nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, params)
            out[w, reg, F_PENETRATION] = -(warm[w, reg, W_GAP] - motion)    # a guaranteed lower bound of the gap
            return
    warm[w, reg, W_GAP] = -1.0
    if not scanned and not abs(c_y - warm[w, reg, W_SCAN_Y]) <= params[P_RESCAN_DISTANCE]:
        scanned = True          # moved far since the last scan (or never scanned): look for other zones again
    starts_sw = scratch[_SC_START_SW]
    starts_sr = scratch[_SC_START_SR]
    n_starts = 1
    if scanned:
        n_starts = _scan_starts(nodes, meta, mono, rail, wheel, c_y, c_z, cos_r, sin_r, s_lo, s_hi, n_scan,
                                int(params[P_N_STARTS]), starts_sw, starts_sr, points, scratch)
        warm[w, reg, W_SCAN_Y] = c_y
    else:
        starts_sw[0] = s_w
        starts_sr[0] = s_r
        # the region's other penetration zone (tracked from the last scan): a deeper zone is never missed
        a_sw = warm[w, reg, W_ALT_S_WHEEL]
        a_sr = warm[w, reg, W_ALT_S_RAIL]
        if np.isfinite(a_sw) and np.isfinite(a_sr):
            starts_sw[1] = a_sw
            starts_sr[1] = a_sr
            n_starts = 2
    dedup = params[P_DEDUP_DISTANCE]
    alt_ok = False          # the best other converged convex optimum (distinct from the reported point)
    alt_sw = 0.0
    alt_sr = 0.0
    alt_delta = -np.inf
    cand_sw = scratch[_SC_CAND_SW]
    cand_sr = scratch[_SC_CAND_SR]
    cand_delta = scratch[_SC_CAND_DELTA]
    cand_convex = scratch[_SC_CAND_CONVEX]
    n_cand = 0
    iters = 0
    sep_ok = False          # a convex, separated Newton solution from the global start (exact gap candidate)
    sep_sw = 0.0
    sep_sr = 0.0
    sep_gap = np.inf
    best_delta = 0.0        # deepest convex contact among the starts
    best_sw = 0.0
    best_sr = 0.0
    best_q = NO_CURVE       # the curves there (curve_eval of the wheel and the rail)
    best_r = NO_CURVE
    # 1. convex search: warm start first; a failure, a concave point or (warm) a lifted-off point -> global starts
    for attempt in range(2):
        for k in range(n_starts):
            valid, convex, s_r, s_w, delta, it, q, r = _newton_candidate(
                nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, starts_sr[k], starts_sw[k], s_lo, s_hi, r_lo, r_hi,
                params, warm[w, reg])
            iters += it
            if valid and n_cand < MAX_STARTS:       # any converged optimum marks a zone worth tracking
                cand_sw[n_cand] = s_w
                cand_sr[n_cand] = s_r
                cand_delta[n_cand] = delta
                cand_convex[n_cand] = 1.0 if convex else 0.0
                _keep_curves(scratch[_SC_CAND_CURVES + n_cand], 0, s_w, s_r, q, r)
                n_cand += 1
            if valid and convex and delta > best_delta:
                best_delta = delta
                best_sw = s_w
                best_sr = s_r
                best_q = q
                best_r = r
            elif valid and convex and scanned and -delta < sep_gap:
                sep_ok = True
                sep_sw = s_w
                sep_sr = s_r
                sep_gap = -delta
        if best_delta > 0.0:
            warm[w, reg, W_S_RAIL] = best_sr
            warm[w, reg, W_S_WHEEL] = best_sw
            _keep_curves(warm[w, reg], W_CURVES, best_sw, best_sr, best_q, best_r)
            # remember the deepest other optimum, distinct from the reported one, as the alternative zone
            for k in range(n_cand):
                if abs(cand_sw[k] - best_sw) > dedup and cand_delta[k] > alt_delta:
                    alt_ok = True
                    alt_delta = cand_delta[k]
                    alt_sw = cand_sw[k]
                    alt_sr = cand_sr[k]
            fill2 = False
            blend = 1.0
            if alt_ok:
                warm[w, reg, W_ALT_S_WHEEL] = alt_sw
                warm[w, reg, W_ALT_S_RAIL] = alt_sr
                k2 = -1
                for k in range(n_cand):
                    if cand_sw[k] == alt_sw and cand_sr[k] == alt_sr:
                        k2 = k
                if k2 >= 0:             # the other zone's curves, for its next search and a second contact
                    q, r = _block_curves(scratch[_SC_CAND_CURVES + k2], 0)
                    _keep_curves(warm[w, reg], W_ALT_CURVES, alt_sw, alt_sr, q, r)
                if slot2 >= 0 and alt_delta > 0.0 and k2 >= 0:
                    mid_ok, mid_dv, mid_sr = overlap_at_wheel(nodes, meta, mono, rail, wheel,
                                                               0.5 * (alt_sw + best_sw), c_y, c_z, cos_r, sin_r)
                    if mid_ok and mid_dv < 0.0:
                        fill2 = cand_convex[k2] != 0.0  # two separate patches: a two-point tread contact
                    else:
                        # one overlap zone with two penetration maxima (a conformal zone, e.g. S1002/UIC60 near
                        # the centre): Hertz at either maximum jumps when their depths cross, so the two are
                        # blended over a depth difference of P_BLEND_DEPTH x the deeper penetration
                        width = params[P_BLEND_DEPTH] * best_delta
                        u = 1.0 - (best_delta - alt_delta) / width if width > 0.0 else 0.0
                        if u > 0.0:
                            u = min(u, 1.0)
                            fill2 = True
                            blend = 0.5 * u * u * (3.0 - 2.0 * u)     # weight of the shallower maximum, <= 1/2
            elif scanned or abs(warm[w, reg, W_ALT_S_WHEEL] - best_sw) <= dedup:
                warm[w, reg, W_ALT_S_WHEEL] = np.nan       # no other zone (or it merged into this one)
                warm[w, reg, W_ALT_S_RAIL] = np.nan
            # the curves at the point, as the search evaluated them: not evaluated again
            _fill_curves(out, w, reg, STATUS_CONVEX, best_sw, best_sr, best_q, best_r, nodes, meta, rail, wheel, c_y,
                         c_z, cos_r, sin_r, iters, params)
            if fill2:               # k2 >= 0: the curves kept just now
                q, r = _block_curves(warm[w, reg], W_ALT_CURVES)
                _fill_curves(out, w, slot2, STATUS_CONVEX, alt_sw, alt_sr, q, r, nodes, meta, rail, wheel, c_y, c_z,
                             cos_r, sin_r, 0, params)
                if blend < 1.0:
                    out[w, slot2, F_NORMAL_FORCE] *= blend
                    out[w, slot2, F_DN_DDELTA] *= blend
                    out[w, reg, F_NORMAL_FORCE] *= 1.0 - blend
                    out[w, reg, F_DN_DDELTA] *= 1.0 - blend
                    out[w, slot2, F_FLAGS] = int(out[w, slot2, F_FLAGS]) | FLAG_BLENDED
                    out[w, reg, F_FLAGS] = int(out[w, reg, F_FLAGS]) | FLAG_BLENDED
            return
        if scanned:
            break
        n_starts = _scan_starts(nodes, meta, mono, rail, wheel, c_y, c_z, cos_r, sin_r, s_lo, s_hi, n_scan,
                                int(params[P_N_STARTS]), starts_sw, starts_sr, points, scratch)
        scanned = True
    # 2. concave search (maximum vertical overlap); its point is polished by Newton where the pair is convex there
    found, c_sw, c_sr, dv = vertical_overlap_search(nodes, meta, mono, rail, wheel, c_y, c_z, cos_r, sin_r, s_lo, s_hi,
                                                    int(params[P_N_CONCAVE_WHEEL]), int(params[P_N_CONCAVE_RAIL]),
                                                    params[P_REFINE] > 0.0)
    if found and dv > 0.0:
        p_valid, p_convex, p_sr, p_sw, p_delta, it, q, r = _newton_candidate(
            nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, c_sr, c_sw, s_lo, s_hi, r_lo, r_hi, params, warm[w, reg])
        iters += it
        if p_valid and p_convex and p_delta > 0.0 and abs(p_sw - c_sw) < 1e-3:
            warm[w, reg, W_S_RAIL] = p_sr
            warm[w, reg, W_S_WHEEL] = p_sw
            _keep_curves(warm[w, reg], W_CURVES, p_sw, p_sr, q, r)
            _fill_curves(out, w, reg, STATUS_CONVEX, p_sw, p_sr, q, r, nodes, meta, rail, wheel, c_y, c_z, cos_r,
                         sin_r, iters, params)
            return
        # the penetration is a normal distance: take the deepest wheel point (by its normal distance to the rail)
        # within P_CONCAVE_NORMAL_WINDOW of the vertical-overlap maximum; its rail point is the normal foot
        wy, wz, wty, wtz, wny, wnz, kw = wheel_point(nodes, meta, wheel, c_sw, c_y, c_z, cos_r, sin_r)
        ok, s_foot = normal_foot(nodes, meta, rail, wy, wz, c_sr)
        if ok and r_lo <= s_foot <= r_hi:
            c_sr = s_foot
        half = params[P_CONCAVE_NORMAL_WINDOW]
        moved = False
        if half > 0.0:
            win_lo = max(s_lo, c_sw - half)
            win_hi = min(s_hi, c_sw + half)
            ok, all_ok, n_sw, n_sr, d_min = nearest_by_normal_distance(
                nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, win_lo, win_hi, 21, c_sr)
            ry, rz, rty, rtz, rny, rnz, rk = curve_eval(nodes, meta, rail, c_sr)
            interior = win_lo + 1e-7 < n_sw < win_hi - 1e-7      # a true local maximum, not the window's edge
            if ok and interior and r_lo <= n_sr <= r_hi and d_min < (wy - ry) * rny + (wz - rz) * rnz:
                c_sw = n_sw
                c_sr = n_sr
                moved = True
        if not moved:
            # the penetration still rises at the window's edge: on a steep flank the vertical overlap (about the
            # normal penetration over cos(contact angle)) can peak where the normal penetration does not.  Follow
            # the normal penetration uphill to the local maximum of the zone, or to the region's end where it is
            # still rising (the zone's deepest point then lies beyond: at the split evaluate_wheels merges it)
            h_w = (s_hi - s_lo) / (int(params[P_N_CONCAVE_WHEEL]) - 1)
            ok, a_sw, a_sr, _, _ = normal_penetration_ascent(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, c_sw,
                                                             c_sr, s_lo, s_hi, h_w)
            if ok and r_lo <= a_sr <= r_hi:
                c_sw = a_sw
                c_sr = a_sr
        warm[w, reg, W_S_RAIL] = c_sr
        warm[w, reg, W_S_WHEEL] = c_sw
        _fill(out, w, reg, STATUS_CONCAVE, c_sw, c_sr, nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, iters,
              params)
        return
    # 3. apart: the region's smallest normal distance over the whole region is its gap; remember it as a bound
    ok, all_ok, g_sw, g_sr, gap = nearest_by_normal_distance(nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r,
                                                             s_lo, s_hi, n_scan, s_r if np.isfinite(s_r) else r_lo)
    if sep_ok and (not ok or sep_gap <= gap + 1e-9):
        # the Newton point is the region's nearest point (to the scan's resolution): exact, keep it
        ok = True
        g_sw = sep_sw
        g_sr = sep_sr
        gap = min(sep_gap, gap)
    if not (ok and r_lo <= g_sr <= r_hi):
        _no_overlap(out, w, reg)
        return
    warm[w, reg, W_S_RAIL] = g_sr
    warm[w, reg, W_S_WHEEL] = g_sw
    # for step 1: the sampled minimum can exceed the true one by at most h^2/8 x (curvature bound) between samples
    h_scan = (s_hi - s_lo) / (n_scan - 1)
    gap_bound = gap - 0.125 * h_scan * h_scan * params[P_CURVATURE_BOUND]
    if gap_bound > 0.0 and all_ok:
        warm[w, reg, W_GAP] = gap_bound
        warm[w, reg, W_POSE_Y] = c_y
        warm[w, reg, W_POSE_Z] = c_z
        warm[w, reg, W_POSE_ROLL] = roll
    # a negative gap is a penetration where no vertical line meets the rail (the steep gauge face): a contact
    status = STATUS_SEPARATED if gap > 0.0 else STATUS_CONCAVE
    _fill(out, w, reg, status, g_sw, g_sr, nodes, meta, rail, wheel, c_y, c_z, cos_r, sin_r, iters, params)


@compiled
def evaluate_wheels(nodes, meta, mono, curve_ids, poses, warm, params, out, scan=NO_SCAN):
    """Contact geometry and Hertz for every wheel (:func:`solve_wheels` with its scratch made here).

    Parameters (arrays)
    -------------------
    nodes, meta : packed curves (:func:`~exudyn_wheelrail.profiles.curve.pack_curves`), side frame.
    mono : (n_curves, 2) int rows of each curve's vertically projectable stretch.
    curve_ids : (n_wheels, 3) int — rail, tread and flange curve of each wheel.
    poses : (n_wheels, 3) — wheel (wheelset) pose relative to its rail in the side frame: c_y, c_z [m], roll [rad].
    warm : (n_wheels, 2, N_WARM) — warm-start state (W_* fields; s NaN for none); updated in place.
    params : :func:`default_params`.
    out : (n_wheels, N_SLOTS, N_FIELDS) — filled: slots tread, flange and the tread's second zone.
    scan : the coarse scan's wheel points (:func:`scan_array`); optional, the results are the same without.
    """
    solve_wheels(nodes, meta, mono, curve_ids, poses, warm, params, out, scan,
                 np.empty((N_SCRATCH_ROWS, SCRATCH_WIDTH)))


@compiled(refcount=False)
def merge_row(row):
    """Make a contact's output row the tail of another contact's zone: STATUS_MERGED, no force, no ellipse."""
    row[F_STATUS] = STATUS_MERGED
    row[F_NORMAL_FORCE] = 0.0
    row[F_DN_DDELTA] = 0.0
    row[F_SEMI_A] = 0.0
    row[F_SEMI_B] = 0.0


@compiled(refcount=False)
def solve_wheels(nodes, meta, mono, curve_ids, poses, warm, params, out, scan, scratch):
    """:func:`evaluate_wheels` with its scratch given (nothing allocated): ``scratch`` a work array of at least
    (N_SCRATCH_ROWS, SCRATCH_WIDTH), overwritten."""
    n_wheels = poses.shape[0]
    for w in range(n_wheels):
        rail = curve_ids[w, 0]
        if not (np.isfinite(poses[w, 0]) and np.isfinite(poses[w, 1]) and np.isfinite(poses[w, 2])):
            out[w, :, :] = np.nan
            out[w, :, F_STATUS] = STATUS_INVALID_POSE
            continue
        _no_overlap(out, w, SLOT_TREAD_2)
        roll = poses[w, 2]
        cos_r = np.cos(roll)
        sin_r = np.sin(roll)
        for reg in range(2):
            _solve_region(nodes, meta, mono, rail, curve_ids[w, 1 + reg], poses[w, 0], poses[w, 1], roll, cos_r, sin_r,
                          warm, params, out, w, reg, SLOT_TREAD_2 if reg == 0 else -1, scratch, scan)
        t2 = out[w, SLOT_TREAD_2]
        if t2[F_STATUS] > 0 and out[w, 1, F_STATUS] > 0 and np.hypot(
                t2[F_PW_Y] - out[w, 1, F_PW_Y], t2[F_PW_Z] - out[w, 1, F_PW_Z]) < params[P_DEDUP_DISTANCE]:
            _no_overlap(out, w, SLOT_TREAD_2)        # the flange's contact, seen from the tread: one contact
        t = out[w, 0]
        f = out[w, 1]
        if t[F_STATUS] > 0 and f[F_STATUS] > 0:
            # one overlap zone across the split: the region whose point sits at its split end (its penetration
            # rises into the neighbour) is the tail of the neighbour's zone; otherwise two points closer than
            # P_DEDUP_DISTANCE are one contact
            t_first = int(meta[curve_ids[w, 1], 0])
            f_first = int(meta[curve_ids[w, 2], 0])
            t_at_split = t[F_S_WHEEL] <= nodes[t_first, 0] + 1e-9
            f_at_split = f[F_S_WHEEL] >= nodes[f_first + int(meta[curve_ids[w, 2], 1]) - 1, 0] - 1e-9
            drop_reg = -1
            if t_at_split and not f_at_split:
                drop_reg = 0
            elif f_at_split and not t_at_split:
                drop_reg = 1
            elif np.hypot(t[F_PW_Y] - f[F_PW_Y], t[F_PW_Z] - f[F_PW_Z]) < params[P_DEDUP_DISTANCE]:
                drop_reg = 1 if t[F_PENETRATION] >= f[F_PENETRATION] else 0
            if drop_reg >= 0:
                merge_row(out[w, drop_reg])


def compile_shares(nodes, meta, mono, curve_ids, poses, warm, params, out, scan=NO_SCAN):
    """The callees of :func:`evaluate_wheels` (through :func:`_solve_region`) as the two shares of
    :func:`~exudyn_wheelrail.jit.compile_ahead`, for the types of the call ``evaluate_wheels(nodes, meta, mono,
    curve_ids, poses, warm, params, out, scan)``: this process's — the scan's starts, Newton, the output — and the
    other's — the concave search (vertical overlap, normal-penetration ascent).  The arguments stand in for those
    the kernel hands each callee: the same types (a curve or row index an integer, a coordinate a float, the
    scratch rows arrays of one dimension), not their values."""
    i, x = 0, 0.0
    row = np.empty(SCRATCH_WIDTH)
    scratch = np.empty((N_SCRATCH_ROWS, SCRATCH_WIDTH))
    points = scan[0]
    here = [(_scan_starts, (nodes, meta, mono, i, i, x, x, x, x, x, x, i, i, row, row, points, scratch)),
            (_newton_candidate, (nodes, meta, i, i, x, x, x, x, x, x, x, x, x, x, params, warm[0, 0])),
            (_fill_curves, (out, i, i, i, x, x, NO_CURVE, NO_CURVE, nodes, meta, i, i, x, x, x, x, i, params)),
            (_fill_warm, (out, i, i, warm, x, x, nodes, meta, i, i, x, x, x, x, params)),
            (_fill, (out, i, i, i, x, x, nodes, meta, i, i, x, x, x, x, i, params)),
            (nearest_by_normal_distance, (nodes, meta, i, i, x, x, x, x, x, x, i, x)),
            (normal_foot, (nodes, meta, i, x, x, x))]
    aside = [(vertical_overlap_search, (nodes, meta, mono, i, i, x, x, x, x, x, x, i, i, True)),
             (normal_penetration_ascent, (nodes, meta, i, i, x, x, x, x, x, x, x, x, x))]
    return here, aside
