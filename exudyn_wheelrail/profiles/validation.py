"""Validation of profile points and of their length unit, shared by the profile readers and the spline fit.

:func:`validate_profile_points` checks ordered points given in the *profile frame* of
:mod:`exudyn_wheelrail.conventions`, in **metres** (``y`` lateral, positive towards the field side; ``z`` for a wheel
the radius increase over the tape circle, for a rail the depth below the top of the rail; gauge side first), and
raises :class:`ProfileError` (a ``ValueError``) with a message that names the source, the offending point or line
where there is one, and the problem:

* fewer than :data:`MIN_POINTS` points; NaN/inf;
* two consecutive points closer than :data:`DUPLICATE_TOL_M` (a duplicated point);
* **progression**: wherever a segment is inclined less than 45 degrees to the lateral axis (tread, crown, flange
  top) the lateral coordinate must increase from the gauge side to the field side.  Steep parts (flange back, flange
  flank, gauge face) may overhang slightly, but the point sequence may not turn back on itself by more than
  :data:`FOLD_BACK_DEG` degrees between consecutive segments (a spike or zig-zag);
* the polyline through the points may not intersect itself.

:func:`profile_shape` tells a wheel from a rail profile by its shape (a rail head is a cap whose two ends lie well
below its top; a wheel has a flange summit on the gauge side and its lowest point at the field side), and
:func:`check_profile_kind` raises :class:`ProfileError` when a profile given as one kind looks like the other.

Unit checks: the bounding-box diagonal of a wheel or rail profile is 0.05-0.2 m; anything within
:data:`PLAUSIBLE_EXTENT_M` is accepted (the ranges in m and mm do not overlap, so values that are evidently
millimetres where metres were declared, or the reverse, can be recognised).  The private helpers ``profile_extent``,
``in_plausible_extent`` and ``plausible_extent_text`` serve the readers for that; ``read_profile_text`` and ``check_kind`` are
the file and ``kind`` argument checks common to all readers.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

#: Fewest points accepted in a profile file.
MIN_POINTS = 10
#: Two consecutive points closer than this [m] count as a duplicated point.
DUPLICATE_TOL_M = 1.0e-9
#: Largest turn [deg] between consecutive polyline segments before the sequence is said to fold back.
FOLD_BACK_DEG = 150.0
#: Accepted range of the bounding-box diagonal of a profile [m]: a full wheel or rail profile spans 0.05-0.2 m,
#: a partial measurement (gauge corner only) may be smaller.  The ranges in m and mm do not overlap.
PLAUSIBLE_EXTENT_M = (0.01, 0.5)

_KINDS = ("wheel", "rail")

#: A wheel profile's flange in the profile frame: 15-45 mm high over the tape circle, its tip at y < -20 mm.
FLANGE_HEIGHT_RANGE_M = (0.015, 0.045)
FLANGE_TIP_MAX_Y_M = -0.020
#: A rail head is a cap: both ends of a rail profile lie at least this far below its top [m].  A wheel's field-side
#: end is its lowest point or, on a hollow-worn tread, a few millimetres above it — never this much.
RAIL_HEAD_MIN_END_DEPTH_M = 0.010
#: Depth below the top at which the width of a rail head is reported [m] (the gauge measuring depth, EN 13848-1).
RAIL_HEAD_WIDTH_DEPTH_M = 0.014
#: A flange tip is a summit: the points on its gauge side (flange back) lie at least this much lower [m].  A rail
#: head, a convex cap, has no summit between its ends.
FLANGE_BACK_MIN_DROP_M = 0.002


class ProfileError(ValueError):
    """A profile file or point set that cannot be used; the message names the source and the problem."""


def _label(labels, k: int) -> str:
    return labels[k] if labels is not None else f"point {k + 1}"


def _mm(v: float) -> str:
    return f"{v * 1e3:.4g} mm"


def _segment_crossings(p: np.ndarray, max_pairs: int = 2_000_000):
    """First pair (i, j), j >= i + 2, of polyline segments [p_i, p_i+1], [p_j, p_j+1] that touch or cross, or None.

    Candidate pairs come from a sweep over the lateral extent of the segments (a profile is mostly monotone in y,
    so there are O(n) candidates), processed in chunks of at most ``max_pairs``; each candidate is decided by the
    signs of the four orientation determinants.
    """
    a, b = p[:-1], p[1:]
    m = len(a)
    if m < 3:
        return None
    ylo, yhi = np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 0], b[:, 0])
    zlo, zhi = np.minimum(a[:, 1], b[:, 1]), np.maximum(a[:, 1], b[:, 1])
    order = np.argsort(ylo, kind="stable")
    stop = np.searchsorted(ylo[order], yhi[order], side="right")   # sorted positions k+1 .. stop-1 overlap in y
    counts = np.maximum(stop - np.arange(m) - 1, 0)
    ends = np.cumsum(counts)

    def orient(p0, p1, q):
        return (p1[:, 0] - p0[:, 0]) * (q[:, 1] - p0[:, 1]) - (p1[:, 1] - p0[:, 1]) * (q[:, 0] - p0[:, 0])

    found = None
    k0 = 0
    while k0 < m:
        k1 = max(int(np.searchsorted(ends, (ends[k0 - 1] if k0 else 0) + max_pairs, side="right")), k0 + 1)
        cnt = counts[k0:k1]
        total = int(cnt.sum())
        if total:
            first = np.repeat(np.arange(k0, k1), cnt)
            offsets = np.arange(total) - np.repeat(np.cumsum(cnt) - cnt, cnt)
            i, j = order[first], order[first + 1 + offsets]
            i, j = np.minimum(i, j), np.maximum(i, j)
            keep = (j - i >= 2) & (zlo[i] <= zhi[j]) & (zlo[j] <= zhi[i])
            i, j = i[keep], j[keep]
            if len(i):
                o1, o2 = orient(a[i], b[i], a[j]), orient(a[i], b[i], b[j])
                o3, o4 = orient(a[j], b[j], a[i]), orient(a[j], b[j], b[i])
                collinear = (o1 == 0) & (o2 == 0) & (o3 == 0) & (o4 == 0)
                hit = (o1 * o2 <= 0) & (o3 * o4 <= 0) & ~collinear
                if np.any(collinear):   # collinear pieces: overlap of their projections on the common line
                    d = b[i] - a[i]
                    ta = np.sum((a[j] - a[i]) * d, axis=1)
                    tb = np.sum((b[j] - a[i]) * d, axis=1)
                    hit |= collinear & (np.maximum(np.minimum(ta, tb), 0) <= np.minimum(np.maximum(ta, tb),
                                                                                         np.sum(d * d, axis=1)))
                if np.any(hit):
                    h = np.flatnonzero(hit)
                    h = h[np.lexsort((j[h], i[h]))][0]
                    candidate = (int(i[h]), int(j[h]))
                    found = candidate if found is None or candidate < found else found
        k0 = k1
    return found


def validate_profile_points(y, z, source: str, labels=None, *, min_points: int = MIN_POINTS,
                            geometry: bool = True) -> None:
    """Check ordered profile points (metres, profile frame, gauge side first); raise :class:`ProfileError` if unusable.

    ``source`` names the file or point set in messages, ``labels[k]`` the k-th point (e.g. ``'line 57'``).
    The requirements are listed in the module docstring; ``geometry=False`` skips the shape checks (self-intersection,
    progression, fold-back) and keeps the count, finiteness, duplicate and overall-direction checks.
    """
    y = np.asarray(y, dtype=float)
    z = np.asarray(z, dtype=float)
    n = len(y)
    if len(z) != n:
        raise ProfileError(f"{source}: y has {n} values but z has {len(z)}")
    if n < min_points:
        raise ProfileError(f"{source}: only {n} profile point(s); at least {min_points} are needed for a profile")
    bad = np.flatnonzero(~(np.isfinite(y) & np.isfinite(z)))
    if len(bad):
        k = int(bad[0])
        raise ProfileError(f"{source}: {_label(labels, k)} is not a finite number (y = {y[k]!r}, z = {z[k]!r}); "
                           f"{len(bad)} such point(s)")
    p = np.column_stack([y, z])
    d = np.diff(p, axis=0)
    length = np.hypot(d[:, 0], d[:, 1])
    dup = np.flatnonzero(length < DUPLICATE_TOL_M)
    if len(dup):
        k = int(dup[0])
        raise ProfileError(
            f"{source}: {_label(labels, k)} and {_label(labels, k + 1)} coincide (y = {_mm(y[k])}, z = {_mm(z[k])}, "
            f"distance {length[k]:.2g} m): duplicated consecutive points are not allowed, remove one of them")
    if y[-1] <= y[0]:
        raise ProfileError(
            f"{source}: the points must run from the gauge side to the field side (increasing y), but the first "
            f"point has y = {_mm(y[0])} and the last y = {_mm(y[-1])}")
    if not geometry:
        return
    crossing = _segment_crossings(p)
    if crossing is not None:
        i, j = crossing
        raise ProfileError(
            f"{source}: the profile line intersects itself: the segment {_label(labels, i)} - {_label(labels, i + 1)} "
            f"(y = {_mm(y[i])}, z = {_mm(z[i])}) crosses the segment {_label(labels, j)} - {_label(labels, j + 1)} "
            f"(y = {_mm(y[j])}, z = {_mm(z[j])})")
    flat_back = np.flatnonzero((np.abs(d[:, 1]) < np.abs(d[:, 0])) & (d[:, 0] < 0))
    if len(flat_back):
        k = int(flat_back[0])
        raise ProfileError(
            f"{source}: the lateral coordinate y must increase from the gauge side to the field side wherever the "
            f"profile is inclined less than 45 degrees (tread, crown, flange top), but it decreases from "
            f"{_label(labels, k)} to {_label(labels, k + 1)} (y = {_mm(y[k])} -> {_mm(y[k + 1])}, z = {_mm(z[k])}): "
            f"the points are not monotonic along the profile")
    u = d / length[:, None]
    cos_turn = np.sum(u[:-1] * u[1:], axis=1)
    fold = np.flatnonzero(cos_turn < math.cos(math.radians(FOLD_BACK_DEG)))
    if len(fold):
        k = int(fold[0]) + 1
        turn = math.degrees(math.acos(max(-1.0, min(1.0, cos_turn[k - 1]))))
        raise ProfileError(
            f"{source}: the point sequence folds back on itself at {_label(labels, k)} (y = {_mm(y[k])}, "
            f"z = {_mm(z[k])}): the direction turns by {turn:.0f} degrees (more than {FOLD_BACK_DEG:.0f}); an outlier "
            f"or a zig-zag, the points must progress along the profile")


def profile_extent(y, z) -> float:
    """The diagonal of the points' bounding box (in their own unit): how large a profile is."""
    return float(np.hypot(np.ptp(y), np.ptp(z)))


def in_plausible_extent(extent_m: float) -> bool:
    """A profile of this extent [m] is plausible (:data:`PLAUSIBLE_EXTENT_M`)."""
    return PLAUSIBLE_EXTENT_M[0] <= extent_m <= PLAUSIBLE_EXTENT_M[1]


def plausible_extent_text() -> str:
    """The plausible extent range as text, for error messages."""
    lo, hi = PLAUSIBLE_EXTENT_M
    return f"{lo:g}-{hi:g} m"


def read_profile_text(path: Path) -> list[str]:
    """The lines of a profile file (UTF-8, else Latin-1); :class:`ProfileError` naming the file when unreadable."""
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ProfileError(f"{path}: cannot read the file ({exc.strerror or exc})") from exc
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    return text.splitlines()


def check_kind(kind, source) -> str | None:
    """``kind`` ('wheel' / 'rail', any case, or None) in lower case; :class:`ProfileError` naming ``source``
    otherwise."""
    if kind is None:
        return None
    kind = str(kind).lower()
    if kind not in _KINDS:
        raise ProfileError(f"{source}: kind must be 'wheel' or 'rail', got {kind!r}")
    return kind


def profile_shape(y, z) -> tuple[str | None, str]:
    """``('rail' | 'wheel' | 'wheel mirrored' | None, description)``: what ordered profile-frame points (metres,
    gauge side first) look like.  ``'rail'``: a cap — the lowest z (the top of the head) lies between the ends and both ends are at least
    :data:`RAIL_HEAD_MIN_END_DEPTH_M` deeper.  ``'wheel'``: a flange — a summit of z on the gauge side of the lowest
    point, at least ``FLANGE_HEIGHT_RANGE_M[0]`` above the field-side end and :data:`FLANGE_BACK_MIN_DROP_M` above the
    gauge-side end, with the field-side end no deeper than a rail's; ``'wheel mirrored'``: the same with the sides
    exchanged (a flange on the field side: y runs the wrong way).  ``None`` when neither is clear (a partial
    measurement, a cone, a crown): nothing is concluded then."""
    y = np.asarray(y, dtype=float)
    z = np.asarray(z, dtype=float)
    i_low = int(np.argmin(z))
    top = z[i_low]
    d_gauge, d_field = z[0] - top, z[-1] - top
    if d_gauge >= RAIL_HEAD_MIN_END_DEPTH_M and d_field >= RAIL_HEAD_MIN_END_DEPTH_M:
        d = min(d_gauge, d_field, RAIL_HEAD_WIDTH_DEPTH_M)
        left = int(np.flatnonzero(z[:i_low] - top >= d)[-1])
        right = i_low + int(np.flatnonzero(z[i_low:] - top >= d)[0])
        return "rail", (f"a cap {(y[right] - y[left]) * 1e3:.0f} mm wide {d * 1e3:.0f} mm below its top, its ends "
                        f"{d_gauge * 1e3:.0f} and {d_field * 1e3:.0f} mm below the top")
    i_tip = int(np.argmax(z))
    for near, far, depth_far, kind, side in ((0, -1, d_field, "wheel", "gauge"),
                                              (-1, 0, d_gauge, "wheel mirrored", "field")):
        height = z[i_tip] - z[far]
        summit_side = 0 < i_tip < i_low if side == "gauge" else i_low < i_tip < len(z) - 1
        if (summit_side and height >= FLANGE_HEIGHT_RANGE_M[0] and z[i_tip] - z[near] >= FLANGE_BACK_MIN_DROP_M
                and depth_far < RAIL_HEAD_MIN_END_DEPTH_M):
            return kind, (f"a flange summit at y = {y[i_tip] * 1e3:.0f} mm, {height * 1e3:.0f} mm above the tread's "
                          f"end, on the {side} side of the tread")
    return None, ""


def check_profile_kind(y, z, kind: str | None, source: str) -> None:
    """Raise :class:`ProfileError` if points given as a ``kind`` ('wheel' / 'rail') profile look like the other
    kind (:func:`profile_shape`); nothing when ``kind`` is None or the shape is not conclusive."""
    if kind is None:
        return
    seen, description = profile_shape(y, z)
    if seen is None or seen == kind:
        return
    if seen == "wheel mirrored":
        if kind == "wheel":
            raise ProfileError(f"{source}: the wheel profile is mirrored: {description}; the profile frame has y towards "
                               "the field side and the flange at negative y (mirror the y coordinate: mirror_y=True "
                               "for a table, mirror.y = 1 in a SIMPACK file)")
        seen = "wheel"
    if kind == "wheel":
        raise ProfileError(f"{source}: given as a wheel profile but it looks like a rail head: {description} (a wheel "
                           "profile has a flange on the gauge side and its lowest point at the field side); is it the "
                           "rail profile?")
    raise ProfileError(f"{source}: given as a rail profile but it looks like a wheel profile: {description} (a rail "
                       "head is a cap whose two ends lie well below its top); is it the wheel profile?")
