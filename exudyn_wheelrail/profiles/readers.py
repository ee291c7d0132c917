"""Readers for wheel and rail profile point files, and the smooth fit that turns points into a :class:`DenseProfile`.

Sources
-------
* SIMPACK profile files, ``.prw`` (wheel) and ``.prr`` (rail): :func:`read_simpack_profile`.
* Plain two-column y-z tables as exported by profile gauges (comma, semicolon, tab or whitespace separated,
  optional header line, ``#`` comments): :func:`read_yz_table`.
* :func:`dense_from_points` fits a C2 parametric cubic spline to ordered points (interpolating, or smoothing
  measurement noise) and resamples it densely with exact derivatives; :func:`load_profile` does read + fit.

Frame and units of everything returned
--------------------------------------
The *profile frame* of :mod:`exudyn_wheelrail.conventions`, in **metres**:

* ``y`` lateral, positive towards the field side;
* ``z`` for a wheel the radius increase over the tape circle (positive towards the rail), for a rail the depth below
  the top of the rail (positive downwards);
* points ordered from the gauge (flange) side to the field side, so that ``y[0] < y[-1]``.

The SIMPACK profile coordinates already use these directions (a wheel flange lies at negative y with positive z, a
rail crown has its smallest z at the top), so a SIMPACK file is returned exactly as its header transforms it; only
the point order is normalised.  No repositioning is done: a canted rail file stays canted, a non-standard reference
point stays where it is; the caller places the profile.

Validation
----------
Every reader checks the points and raises :class:`ProfileError` (a ``ValueError``) with a message that names the
file, the offending line where there is one, and the problem:

* fewer than :data:`MIN_POINTS` points; NaN/inf or text that is not a number;
* two consecutive points closer than :data:`DUPLICATE_TOL_M` (a duplicated point);
* **progression**: wherever a segment is inclined less than 45 degrees to the lateral axis (tread, crown, flange
  top) the lateral coordinate must increase from the gauge side to the field side.  Steep parts (flange back, flange
  flank, gauge face) may overhang slightly, but the point sequence may not turn back on itself by more than
  :data:`FOLD_BACK_DEG` degrees between consecutive segments (a spike or zig-zag);
* the polyline through the points may not intersect itself;
* units: the bounding-box diagonal of a wheel or rail profile is 0.05-0.2 m; anything between
  :data:`PLAUSIBLE_EXTENT_M` is accepted.  Values that are evidently millimetres where metres were declared (or the
  reverse) are reported as such; ``units='auto'`` infers the unit from the extent and records the choice;
* SIMPACK files: missing ``point.begin``/``point.end``, a header ``type`` that contradicts the extension or the
  requested kind.
"""
from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

import numpy as np
from scipy.interpolate import BSpline, make_interp_spline, make_smoothing_spline, splprep
from scipy.optimize import brentq

from .dense import DenseProfile

__all__ = [
    "ProfileError",
    "read_simpack_profile",
    "read_yz_table",
    "dense_from_points",
    "load_profile",
    "validate_profile_points",
    "MIN_POINTS",
    "DUPLICATE_TOL_M",
    "PLAUSIBLE_EXTENT_M",
    "DEFAULT_GAUGE_NOISE_M",
    "DEFAULT_SPACING_M",
]

#: Fewest points accepted in a profile file.
MIN_POINTS = 10
#: Two consecutive points closer than this [m] count as a duplicated point.
DUPLICATE_TOL_M = 1.0e-9
#: Largest turn [deg] between consecutive polyline segments before the sequence is said to fold back.
FOLD_BACK_DEG = 150.0
#: Accepted range of the bounding-box diagonal of a profile [m]: a full wheel or rail profile spans 0.05-0.2 m,
#: a partial measurement (gauge corner only) may be smaller.  The ranges in m and mm do not overlap.
PLAUSIBLE_EXTENT_M = (0.01, 0.5)
#: Standard deviation of the measurement noise [m] assumed when ``smoothing=None``: 0.01 mm, typical of contact and
#: laser profile gauges.
DEFAULT_GAUGE_NOISE_M = 1.0e-5
#: Spacing [m] along the curve of the dense samples returned by :func:`dense_from_points`.
DEFAULT_SPACING_M = 2.0e-5
#: When interpolating (``smoothing=0``), points closer than this [m] to the previous kept point are dropped: they only
#: carry the rounding noise of the file (8 significant digits = 1 nm) and would turn it into huge curvature spikes.
#: The interpolant still passes within nanometres of the dropped points.
INTERPOLATION_MIN_SPACING_M = 1.0e-5
#: Residual sums tried for the final smoothing fit, as ``n + band * sqrt(2 n)`` times sigma^2: the mean of the
#: residual sum of n normal noise components plus 2, 3, 4 of its standard deviations.  All are consistent with the
#: noise; the fit with the fewest knots is kept (FITPACK occasionally adds superfluous knots that put wiggles into
#: the curvature when the target sits just below a noise realisation).
FITPACK_RESIDUAL_BANDS = (2.0, 3.0, 4.0)

_KINDS = ("wheel", "rail")
_EXTENSION_KIND = {".prw": "wheel", ".prr": "rail"}
_SIMPACK_TYPE_KIND = {0: "rail", 1: "wheel"}
_LENGTH_UNIT_FACTORS = {"m": 1.0, "mm": 1000.0, "cm": 100.0, "dm": 10.0, "um": 1.0e6, "in": 1.0 / 0.0254}


class ProfileError(ValueError):
    """A profile file or point set that cannot be used; the message names the source and the problem."""


# ================================================================================================= validation
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


def _extent(y, z) -> float:
    return float(np.hypot(np.ptp(y), np.ptp(z)))


def _in_plausible(extent_m: float) -> bool:
    return PLAUSIBLE_EXTENT_M[0] <= extent_m <= PLAUSIBLE_EXTENT_M[1]


def _plausible_range_text() -> str:
    lo, hi = PLAUSIBLE_EXTENT_M
    return f"{lo:g}-{hi:g} m"


# ================================================================================================= SIMPACK files
def _strip_comment(line: str, marker: str) -> str:
    """Text of ``line`` before the first comment marker outside single or double quotes."""
    quote = None
    for k, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == marker:
            return line[:k]
    return line


def _parse_value(text: str):
    text = text.strip()
    if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
        return text[1:-1]
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text.replace("D", "E").replace("d", "e"))
    except ValueError:
        return text


def _read_text(path: Path) -> list[str]:
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ProfileError(f"{path}: cannot read the file ({exc.strerror or exc})") from exc
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    return text.splitlines()


def _check_kind(kind, source) -> str | None:
    if kind is None:
        return None
    kind = str(kind).lower()
    if kind not in _KINDS:
        raise ProfileError(f"{source}: kind must be 'wheel' or 'rail', got {kind!r}")
    return kind


def read_simpack_profile(path, kind: str | None = None) -> tuple[np.ndarray, np.ndarray, dict]:
    """Read a SIMPACK wheel (``.prw``) or rail (``.prr``) profile file.

    Returns ``(y, z, metadata)``: y and z in metres in the profile frame (module docstring), ordered from the gauge
    (flange) side to the field side, and a dict with the header data (``'header'``, ``'spline'`` sections as
    read), ``'kind'``, ``'length_factor'`` (``units.len.f``), ``'units'``, ``'steps'`` (the transformations applied),
    ``'reversed'`` (whether the processed SIMPACK order was reversed to gauge -> field), ``'weights'`` (third
    point column or None), ``'approx_smooth'``, ``'comment'`` and the point counts.

    File layout: ``header.begin ... header.end`` with ``type`` (0 = rail, 1 = wheel), then ``spline.begin ...
    spline.end`` with processing keys and the points (``y z [weight]`` per line, in the file's length unit) between
    ``point.begin`` and ``point.end``.  ``!`` starts a comment (outside quotes), so a commented-out point is ignored.

    ``kind`` ('wheel' / 'rail'), when given, must agree with the header ``type``; so must the extension (``.prw`` =
    wheel, ``.prr`` = rail).  Without a ``type`` the extension or ``kind`` decides.

    Header semantics (assumptions)
    ------------------------------
    SIMPACK's own manual was not available; the processing steps are applied in the order of the step numbers that
    SIMPACK writes next to the keys ("1: point.dist.min ... 7: units"), the order also used by the independent
    reader in Vtech CMCC's CONTACT:

    1. ``point.dist.min`` (> 0): a point closer than this to the previously kept point is dropped.
    2. ``shift.y``, ``shift.z``: added to the coordinates (file length unit).
    3. ``rotate`` (angle unit, divided by ``units.ang.f`` to give radians): rotation about the profile x axis in
       the right-handed sense that turns +y towards +z, about the origin after the shift:
       ``y' = y cos a - z sin a``, ``z' = y sin a + z cos a``.  (Sign assumed; CONTACT does not implement it.)
    4. ``bound.y.min/max``: if min < max, points with y outside [min, max] are removed; ``bound.z.min/max``: if
       min < max, z is clipped to [min, max] (as in CONTACT).  min >= max (the default 1 / 0) means no bound.
    5. ``mirror.y`` / ``mirror.z`` = 1: y -> -y / z -> -z.
    6. ``inversion`` = 1: the point order is reversed.  (In SIMPACK's processed order wheel points run towards
       decreasing y and rail points towards increasing y; we always return gauge side first, see ``'reversed'``.)
    7. ``units.len.f`` = file length unit per metre (1000 for mm): coordinates are divided by it.  If it is absent,
       ``units.len`` ('mm', 'm', ...) is used, else metres.  The result is checked for a plausible size, so a
       millimetre file declared in metres (or the reverse) is reported, not silently scaled.

    ``approx.smooth`` is recorded, not applied (see :func:`load_profile`).  Unknown keys and sections are kept in
    the metadata, not interpreted.
    """
    path = Path(path)
    source = str(path)
    kind = _check_kind(kind, source)
    lines = _read_text(path)

    header: dict = {}
    spline: dict = {}
    other_sections: dict = {}      # sections other than header / spline: kept, not interpreted
    section = None                 # None, 'header', 'spline' or another section name
    point_begin_line = None
    point_end_line = None
    pts, wts, line_numbers = [], [], []
    has_weights = False
    for lineno, raw in enumerate(lines, start=1):
        text = _strip_comment(raw, "!").strip()
        if not text:
            continue
        word = text.lower()
        if point_begin_line is not None and point_end_line is None:
            if word == "point.end":
                point_end_line = lineno
                continue
            if "=" in text or word.endswith((".begin", ".end")):
                raise ProfileError(f"{source}: line {lineno}: '{text}' inside the point block opened on line "
                                   f"{point_begin_line}; 'point.end' is missing")
            fields = [f for f in re.split(r"[\s,;]+", text) if f]
            if len(fields) not in (2, 3):
                raise ProfileError(f"{source}: line {lineno}: a point needs 2 or 3 numbers (y z [weight]), found "
                                   f"{len(fields)} in '{text}'")
            try:
                values = [float(f.replace("D", "E").replace("d", "e")) for f in fields]
            except ValueError:
                raise ProfileError(f"{source}: line {lineno}: cannot read the point '{text}' as numbers") from None
            if not all(math.isfinite(v) for v in values):
                raise ProfileError(f"{source}: line {lineno}: point '{text}' is not finite (NaN or inf)")
            pts.append(values[:2])
            wts.append(values[2] if len(values) == 3 else 1.0)
            has_weights = has_weights or len(values) == 3
            line_numbers.append(lineno)
            continue
        if word == "point.begin":
            if point_begin_line is not None:
                raise ProfileError(f"{source}: line {lineno}: a second 'point.begin' (the first is on line "
                                   f"{point_begin_line}); only one point block is supported")
            point_begin_line = lineno
            continue
        if word == "point.end":
            raise ProfileError(f"{source}: line {lineno}: 'point.end' without a preceding 'point.begin'")
        marker = re.fullmatch(r"([a-z0-9_.]+)\.(begin|end)", word)
        if marker:
            section = marker.group(1) if marker.group(2) == "begin" else None
            if section not in (None, "header", "spline"):
                other_sections.setdefault(section, {})
            continue
        if "=" in text:
            key, value = text.split("=", 1)
            if section == "header":
                target = header
            elif section in (None, "spline"):
                target = spline
            else:
                target = other_sections[section]
            target[key.strip().lower()] = _parse_value(value)
            continue
        try:
            [float(f) for f in re.split(r"[\s,;]+", text) if f]
            looks_like_point = True
        except ValueError:
            looks_like_point = False
        if looks_like_point:
            where = "after 'point.end'" if point_end_line is not None else "before any 'point.begin'"
            raise ProfileError(f"{source}: line {lineno}: point data '{text}' {where}: points must lie between "
                               f"'point.begin' and 'point.end'" + ("" if point_end_line else
                                                                   " ('point.begin' is missing)"))
        raise ProfileError(f"{source}: line {lineno}: cannot interpret '{text}' (expected 'key = value', a section "
                           f"keyword or, between 'point.begin' and 'point.end', a point)")

    if point_begin_line is None:
        raise ProfileError(f"{source}: no 'point.begin' found: the file holds no point block "
                           f"('point.begin' ... 'point.end' inside 'spline.begin' ... 'spline.end')")
    if point_end_line is None:
        raise ProfileError(f"{source}: the point block opened on line {point_begin_line} is not closed: "
                           f"'point.end' is missing")

    # wheel or rail: header type vs extension vs requested kind
    ext_kind = _EXTENSION_KIND.get(path.suffix.lower())
    file_type = header.get("type")
    if file_type is not None:
        if file_type not in _SIMPACK_TYPE_KIND:
            raise ProfileError(f"{source}: header 'type = {file_type}' is neither 0 (rail) nor 1 (wheel)")
        type_kind = _SIMPACK_TYPE_KIND[file_type]
        if ext_kind is not None and ext_kind != type_kind:
            raise ProfileError(f"{source}: header 'type = {file_type}' ({type_kind} profile) contradicts the "
                               f"extension '{path.suffix}' ({ext_kind} profile)")
        if kind is not None and kind != type_kind:
            raise ProfileError(f"{source}: a {kind} profile was requested but the header says 'type = {file_type}' "
                               f"({type_kind} profile)")
        file_kind = type_kind
    else:
        if ext_kind is not None and kind is not None and ext_kind != kind:
            raise ProfileError(f"{source}: a {kind} profile was requested but the extension '{path.suffix}' denotes "
                               f"a {ext_kind} profile")
        file_kind = kind or ext_kind
        if file_kind is None:
            raise ProfileError(f"{source}: the header has no 'type' (0 = rail, 1 = wheel), the extension is neither "
                               f".prw nor .prr and no kind was given: cannot tell a wheel from a rail profile")

    n_file = len(pts)
    if n_file < MIN_POINTS:
        raise ProfileError(f"{source}: only {n_file} point(s) between 'point.begin' (line {point_begin_line}) and "
                           f"'point.end'; at least {MIN_POINTS} are needed for a profile")
    p = np.array(pts, dtype=float)
    w = np.array(wts, dtype=float)
    lines_arr = np.array(line_numbers)
    steps = []

    def number(key, default):
        value = spline.get(key, default)
        if isinstance(value, str):
            raise ProfileError(f"{source}: '{key} = {value}' is not a number")
        return float(value)

    # 1: minimum point distance (file units)
    dist_min = number("point.dist.min", 0.0)
    if dist_min > 0:
        keep = [0]
        for k in range(1, len(p)):
            if np.hypot(*(p[k] - p[keep[-1]])) >= dist_min:
                keep.append(k)
        if len(keep) < len(p):
            steps.append(f"point.dist.min: dropped {len(p) - len(keep)} point(s)")
        p, w, lines_arr = p[keep], w[keep], lines_arr[keep]
    # 2: shift (file units)
    shift_y, shift_z = number("shift.y", 0.0), number("shift.z", 0.0)
    if shift_y or shift_z:
        p = p + [shift_y, shift_z]
        steps.append(f"shift by ({shift_y:g}, {shift_z:g})")
    # 3: rotation about x (angle units / units.ang.f = rad)
    angle_factor = number("units.ang.f", 1.0)
    if angle_factor <= 0:
        raise ProfileError(f"{source}: 'units.ang.f = {angle_factor:g}' must be positive")
    angle = number("rotate", 0.0) / angle_factor
    if angle:
        c, s = math.cos(angle), math.sin(angle)
        p = np.column_stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]])
        steps.append(f"rotate by {angle:g} rad (+y towards +z)")
    # 4: bounds
    y_min, y_max = number("bound.y.min", 1.0), number("bound.y.max", 0.0)
    if y_min < y_max:
        inside = (p[:, 0] >= y_min) & (p[:, 0] <= y_max)
        p, w, lines_arr = p[inside], w[inside], lines_arr[inside]
        steps.append(f"bound.y: kept {int(inside.sum())} point(s) in [{y_min:g}, {y_max:g}]")
    z_min, z_max = number("bound.z.min", 1.0), number("bound.z.max", 0.0)
    if z_min < z_max:
        p = p.copy()
        p[:, 1] = np.clip(p[:, 1], z_min, z_max)
        steps.append(f"bound.z: clipped z to [{z_min:g}, {z_max:g}]")
    # 5: mirroring
    if int(number("mirror.y", 0)) == 1:
        p = p * [-1.0, 1.0]
        steps.append("mirror y")
    if int(number("mirror.z", 0)) == 1:
        p = p * [1.0, -1.0]
        steps.append("mirror z")
    # 6: inversion of the point order
    if int(number("inversion", 0)) == 1:
        p, w, lines_arr = p[::-1], w[::-1], lines_arr[::-1]
        steps.append("inversion (order reversed)")
    # 7: length unit
    if "units.len.f" in spline:
        length_factor = number("units.len.f", 1.0)
        unit_source = "units.len.f"
    elif "units.len" in spline:
        name = str(spline["units.len"]).strip().lower()
        if name not in _LENGTH_UNIT_FACTORS:
            raise ProfileError(f"{source}: unknown length unit 'units.len = {spline['units.len']}'")
        length_factor = _LENGTH_UNIT_FACTORS[name]
        unit_source = "units.len"
    else:
        length_factor = 1.0
        unit_source = "default (metres)"
    if length_factor <= 0:
        raise ProfileError(f"{source}: 'units.len.f = {length_factor:g}' must be positive")
    p = p / length_factor
    steps.append(f"divide by units.len.f = {length_factor:g} (to metres)")
    unit_name = next((u for u, f in _LENGTH_UNIT_FACTORS.items() if math.isclose(f, length_factor)), None)

    extent = _extent(p[:, 0], p[:, 1])
    if not _in_plausible(extent):
        if _in_plausible(extent * 1e-3):
            hint = ("the data are evidently in millimetres, the length factor should be 1000"
                    if math.isclose(length_factor, 1.0) else "the data look 1000 times too large for this unit")
        elif _in_plausible(extent * 1e3):
            hint = ("the data are evidently in metres, the length factor should be 1"
                    if math.isclose(length_factor, 1000.0) else "the data look 1000 times too small for this unit")
        else:
            hint = "that is not the size of a wheel or rail profile"
        raise ProfileError(f"{source}: with the length factor {length_factor:g} ({unit_source}) the points span "
                           f"{extent:.4g} m (bounding-box diagonal; expected {_plausible_range_text()}): {hint}")

    # gauge side first
    reversed_ = bool(p[0, 0] > p[-1, 0])
    if reversed_:
        p, w, lines_arr = p[::-1], w[::-1], lines_arr[::-1]
    labels = [f"line {ln}" for ln in lines_arr]
    validate_profile_points(p[:, 0], p[:, 1], source, labels)

    approx_smooth = spline.get("approx.smooth", 0.0)
    metadata = {
        "format": "simpack",
        "path": source,
        "kind": file_kind,
        "header": header,
        "spline": spline,
        "other_sections": other_sections,
        "length_factor": length_factor,
        "length_factor_source": unit_source,
        "units": unit_name,
        "angle_factor": angle_factor,
        "steps": steps,
        "reversed": reversed_,
        "weights": w.copy() if has_weights else None,
        "approx_smooth": None if isinstance(approx_smooth, str) else float(approx_smooth),
        "comment": spline.get("comment"),
        "n_points_file": n_file,
        "n_points": len(p),
        "lines": lines_arr.copy(),
    }
    return p[:, 0].copy(), p[:, 1].copy(), metadata


# ================================================================================================= y-z tables
_UNIT_HINT = re.compile(r"[\[(]\s*(mm|m)\s*[\])]", re.IGNORECASE)


def _split_fields(text: str) -> tuple[list[str], str]:
    """Fields of one table line and the delimiter name; a semicolon or tab table may use decimal commas."""
    if ";" in text:
        fields, delim = text.split(";"), "semicolon"
    elif "\t" in text:
        fields, delim = text.split("\t"), "tab"
    elif "," in text:
        fields, delim = text.split(","), "comma"
    else:
        return text.split(), "whitespace"
    fields = [f.strip() for f in fields]
    while fields and fields[-1] == "":
        fields.pop()
    if delim != "comma":
        fields = [f.replace(",", ".") if ("," in f and "." not in f) else f for f in fields]
    return fields, delim


def read_yz_table(path, units="auto", kind: str | None = None, *, columns=(0, 1), mirror_y: bool = False,
                  mirror_z: bool = False, check_geometry: bool = True) -> tuple[np.ndarray, np.ndarray, dict]:
    """Read a plain y-z point table (profile gauge export) and return ``(y, z, metadata)`` in metres.

    Format: one point per line, the columns separated by commas, semicolons (then a decimal comma is accepted),
    tabs or whitespace; ``#`` starts a comment; one header line (text that is not numbers) may precede the data.
    ``columns`` selects the y and z columns (0-based); all data lines must have the same number of columns.

    The table must already be in the profile frame of the module docstring (y to the field side; wheel z = radius
    increase, rail z = depth below the top), apart from the unit and the point order: points given field side first
    are reversed (``metadata['reversed']``).  ``mirror_y`` / ``mirror_z`` flip a coordinate first, for gauges
    with other sign conventions.

    ``units``: ``'m'``, ``'mm'``, a positive number (metres per file unit) or ``'auto'``.  With ``'auto'`` a unit
    hint in the header line (``[mm]``, ``(m)``) is used if present, else the unit follows from the extent
    (bounding-box diagonal): within :data:`PLAUSIBLE_EXTENT_M` in m -> metres, within the same range in mm ->
    millimetres.  A declared unit that makes the profile evidently 1000 times too large or small raises
    :class:`ProfileError`.  The choice is recorded in ``metadata['units']`` / ``metadata['units_source']``.
    ``kind`` ('wheel' / 'rail' / None) is recorded only.

    ``check_geometry=False`` skips the shape checks of :func:`validate_profile_points` (self-intersection,
    progression, fold-back): for scans sampled more densely than their noise, whose raw polyline zig-zags.  The fit
    of :func:`dense_from_points` copes with such data (it re-orders points by their foot on a smoothed curve).
    """
    path = Path(path)
    source = str(path)
    kind = _check_kind(kind, source)
    if len(columns) != 2 or min(columns) < 0 or columns[0] == columns[1]:
        raise ProfileError(f"{source}: columns must be two different non-negative column indices, got {columns!r}")
    lines = _read_text(path)

    rows, line_numbers = [], []
    header_line = None
    n_fields = None
    delimiter = None
    for lineno, raw in enumerate(lines, start=1):
        text = raw.split("#", 1)[0].strip()
        if not text:
            continue
        fields, delim = _split_fields(text)
        try:
            values = [float(f) for f in fields]
        except ValueError:
            if not rows and header_line is None:
                header_line = text
                continue
            raise ProfileError(f"{source}: line {lineno}: cannot read '{text}' as numbers") from None
        if n_fields is None:
            n_fields, delimiter = len(values), delim
            if n_fields <= max(columns):
                raise ProfileError(f"{source}: line {lineno}: {n_fields} column(s), but columns {columns} are "
                                   f"needed for y and z")
        elif len(values) != n_fields:
            raise ProfileError(f"{source}: line {lineno}: {len(values)} column(s) where the first data line has "
                               f"{n_fields}")
        y_val, z_val = values[columns[0]], values[columns[1]]
        if not (math.isfinite(y_val) and math.isfinite(z_val)):
            raise ProfileError(f"{source}: line {lineno}: '{text}' is not finite (NaN or inf)")
        rows.append((y_val, z_val))
        line_numbers.append(lineno)
    if len(rows) < MIN_POINTS:
        raise ProfileError(f"{source}: only {len(rows)} data line(s); at least {MIN_POINTS} points are needed "
                           f"for a profile")
    p = np.array(rows, dtype=float)
    lines_arr = np.array(line_numbers)
    raw_extent = _extent(p[:, 0], p[:, 1])

    # units
    def fits(scale):
        return _in_plausible(raw_extent * scale)

    if isinstance(units, str):
        unit = units.strip().lower()
        if unit == "auto":
            hint = _UNIT_HINT.search(header_line or "")
            if hint:
                unit_name = hint.group(1).lower()
                scale = 1e-3 if unit_name == "mm" else 1.0
                if not fits(scale):
                    raise ProfileError(
                        f"{source}: the header '{header_line}' says {unit_name}, but the points span {raw_extent:.4g} "
                        f"{unit_name} (bounding-box diagonal), not a wheel or rail profile in {unit_name}")
                units_source = f"header line '{header_line}'"
            elif fits(1.0):
                unit_name, scale = "m", 1.0
                units_source = f"auto: extent {raw_extent:.4g} fits metres"
            elif fits(1e-3):
                unit_name, scale = "mm", 1e-3
                units_source = f"auto: extent {raw_extent:.4g} fits millimetres"
            else:
                raise ProfileError(
                    f"{source}: cannot infer the length unit: the points span {raw_extent:.4g} file units "
                    f"(bounding-box diagonal), which is a wheel or rail profile neither in metres "
                    f"({_plausible_range_text()}) nor in millimetres; pass units=")
        elif unit in ("m", "mm"):
            unit_name, scale = unit, (1.0 if unit == "m" else 1e-3)
            units_source = "argument"
            if not fits(scale):
                if unit == "m" and fits(1e-3):
                    problem = "the values are evidently millimetres (use units='mm' or 'auto')"
                elif unit == "mm" and fits(1.0):
                    problem = "the values are evidently metres (use units='m' or 'auto')"
                else:
                    problem = "that is not the size of a wheel or rail profile"
                raise ProfileError(f"{source}: units='{unit}' but the points span {raw_extent:.4g} {unit} "
                                   f"(bounding-box diagonal; a profile spans {_plausible_range_text()}): {problem}")
        else:
            raise ProfileError(f"{source}: units must be 'auto', 'm', 'mm' or a number (metres per file unit), "
                               f"got {units!r}")
    else:
        scale = float(units)
        if not scale > 0:
            raise ProfileError(f"{source}: units factor must be positive, got {units!r}")
        unit_name, units_source = None, "argument (metres per file unit)"
        if not fits(scale):
            raise ProfileError(f"{source}: with {scale:g} m per file unit the points span {raw_extent * scale:.4g} m "
                               f"(expected {_plausible_range_text()})")
    p = p * scale
    if mirror_y:
        p[:, 0] = -p[:, 0]
    if mirror_z:
        p[:, 1] = -p[:, 1]
    reversed_ = bool(p[0, 0] > p[-1, 0])
    if reversed_:
        p, lines_arr = p[::-1], lines_arr[::-1]
    labels = [f"line {ln}" for ln in lines_arr]
    validate_profile_points(p[:, 0], p[:, 1], source, labels, geometry=check_geometry)
    metadata = {
        "format": "table",
        "path": source,
        "kind": kind,
        "units": unit_name,
        "scale_to_m": scale,
        "units_source": units_source,
        "delimiter": delimiter,
        "header_line": header_line,
        "columns": tuple(columns),
        "mirror_y": bool(mirror_y),
        "mirror_z": bool(mirror_z),
        "geometry_checked": bool(check_geometry),
        "reversed": reversed_,
        "n_points": len(p),
        "lines": lines_arr.copy(),
    }
    return p[:, 0].copy(), p[:, 1].copy(), metadata


# ================================================================================================= spline fit
def _chord_parameter(p: np.ndarray) -> np.ndarray:
    return np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])


def _normal_rms(spline: BSpline, t: np.ndarray, p: np.ndarray) -> float:
    """RMS of the residual components normal to the fitted curve at the data parameters."""
    r = p - spline(t)
    d = spline.derivative()(t)
    d = d / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-300)[:, None]
    return float(np.sqrt(np.mean((d[:, 0] * r[:, 1] - d[:, 1] * r[:, 0]) ** 2)))


def _penalised_fit(t: np.ndarray, p: np.ndarray, sigma: float) -> BSpline:
    """Cubic smoothing spline (knots at all data, penalty on the second derivative) of both coordinates with one
    common penalty, chosen so that the RMS normal residual equals ``sigma`` (discrepancy principle)."""
    t0, length = t[0], t[-1] - t[0]
    u = (t - t0) / length

    def build(log_lam: float) -> BSpline:
        lam = 10.0 ** log_lam
        sy = make_smoothing_spline(u, p[:, 0], lam=lam)
        sz = make_smoothing_spline(u, p[:, 1], lam=lam)
        m = min(len(sy.c), len(sz.c))
        return BSpline(sy.t * length + t0, np.column_stack([sy.c[:m], sz.c[:m]]), 3)

    def misfit(log_lam: float) -> float:
        return math.log(max(_normal_rms(build(log_lam), t, p), 1e-300) / sigma)

    lo, hi = -24.0, 8.0
    if misfit(hi) <= 0.0:            # even the straightest fit is within the noise
        return build(hi)
    if misfit(lo) >= 0.0:
        return build(lo)
    return build(brentq(misfit, lo, hi, xtol=0.02))


def _reparametrise(spline: BSpline, t: np.ndarray, p: np.ndarray):
    """Arc length along ``spline`` of the foot points of ``p`` (a few Newton steps from ``t``), in sorted order.

    Feet may lie slightly beyond the ends of the data range (the spline is continued polynomially there, at most
    2 % of the length), so end points do not pile up on one parameter value.  Points whose foot coincides (within 0.1 nm) with the previous
    one are dropped: they add nothing and would make the spline basis singular.
    """
    d1s, d2s = spline.derivative(1), spline.derivative(2)
    margin = 0.02 * (t[-1] - t[0])
    tau = t.copy()
    for _ in range(5):
        r = spline(tau) - p
        d1, d2 = d1s(tau), d2s(tau)
        g = np.sum(r * d1, axis=1)
        speed2 = np.sum(d1 * d1, axis=1)
        h = speed2 + np.sum(r * d2, axis=1)
        h = np.where(h > 0.1 * speed2, h, speed2)
        tau = np.clip(tau - g / h, t[0] - margin, t[-1] + margin)
    lo, hi = float(tau.min()), float(tau.max())
    fine = np.linspace(lo, hi, max(20 * len(t), 2001))
    speed = np.hypot(*d1s(fine).T)
    arc = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(fine))])
    s = np.interp(tau, fine, arc)
    order = np.argsort(s, kind="stable")
    s, p = s[order], p[order]
    keep = np.concatenate([[True], np.diff(s) > 1e-10])
    return s[keep] - s[keep][0], p[keep]


def _thin(p: np.ndarray, min_spacing: float) -> np.ndarray:
    """Indices of points kept so that consecutive kept points are at least ``min_spacing`` apart (ends kept)."""
    keep = [0]
    for k in range(1, len(p)):
        if np.hypot(*(p[k] - p[keep[-1]])) >= min_spacing:
            keep.append(k)
    last = len(p) - 1
    if keep[-1] != last:
        if len(keep) > 1 and np.hypot(*(p[last] - p[keep[-1]])) < min_spacing:
            keep[-1] = last
        else:
            keep.append(last)
    return np.array(keep)


def _fit_spline(p: np.ndarray, sigma: float) -> tuple[BSpline, np.ndarray]:
    """The fitted C2 cubic spline c(tau) and the data parameters."""
    t = _chord_parameter(p)
    if sigma == 0.0:
        return make_interp_spline(t, p, k=3), t
    preliminary = _penalised_fit(t, p, sigma)
    s, p_sorted = _reparametrise(preliminary, t, p)
    n = len(s)
    best = None
    for band in FITPACK_RESIDUAL_BANDS:
        target = (n + band * math.sqrt(2.0 * n)) * sigma ** 2
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                (tck, _), fp, ier, _ = splprep([p_sorted[:, 0], p_sorted[:, 1]], u=s, k=3, s=target,
                                               full_output=1, quiet=1)
            except ValueError:
                continue
        # ier 2 / 3: FITPACK met s only approximately (or stopped iterating on it): usable if fp is close
        if ier not in (-2, -1, 0, 2, 3) or not fp <= 1.5 * target:
            continue
        if best is None or len(tck[0]) < len(best[0]):
            best = tck
    if best is None:   # FITPACK failed: the penalised spline refitted on the new parameter
        return _penalised_fit(s, p_sorted, sigma), s
    knots, coeffs, degree = best
    m = len(knots) - degree - 1
    return BSpline(knots, np.column_stack([coeffs[0][:m], coeffs[1][:m]]), degree), s


def dense_from_points(y, z, smoothing: float | None = None, name: str = "profile", *,
                      spacing: float = DEFAULT_SPACING_M, validate: bool = True) -> DenseProfile:
    """Smooth C2 parametric fit of ordered profile points, densely resampled with exact derivatives.

    ``y``, ``z``: points in metres in the profile frame, ordered from the gauge side to the field side.
    The curve c(tau) = (y(tau), z(tau)) is a cubic B-spline (C2) in a parameter tau close to arc length:

    * ``smoothing=0``: interpolation.  tau = cumulative chord length; the not-a-knot cubic spline passes through
      every point (points closer than :data:`INTERPOLATION_MIN_SPACING_M` to their predecessor are dropped first, so
      that file rounding does not produce curvature spikes).  For exact point files (analytic standards exported
      as points, e.g. the Manchester benchmark files).
    * ``smoothing=sigma > 0``: ``sigma`` is the standard deviation [m] of the measurement noise normal to the
      profile.  (1) A cubic smoothing spline with knots at every point (``scipy.interpolate.make_smoothing_spline``,
      one penalty for both coordinates, so the fit does not depend on the orientation) is fitted on the chord
      length with the penalty chosen so that the RMS normal residual is ``sigma``.  (2) Each point is projected onto
      it and tau is set to the arc length of its foot point: this removes the jitter that noise puts into chord
      lengths (with dense noisy samples the chords are mostly noise).  (3) The final spline is FITPACK's smoothing
      spline (``scipy.interpolate.splprep``) on that parameter with a residual sum ``(n + b sqrt(2 n)) sigma^2``,
      b = 2, 3, 4 (:data:`FITPACK_RESIDUAL_BANDS`; FITPACK recommends n +- sqrt(2 n) for weights 1), keeping the
      fit with the fewest knots: FITPACK places knots only where the data need them, which keeps the curvature of
      smooth parts free of noise.  Should FITPACK fail, the spline of step (1) refitted on the new parameter is
      used.
    * ``smoothing=None``: ``sigma = DEFAULT_GAUGE_NOISE_M`` (0.01 mm, typical gauge noise).

    Returns a :class:`DenseProfile` sampled uniformly in tau with spacing about ``spacing`` along the curve, with the
    spline's exact first and second derivatives with respect to tau.  ``validate`` runs
    :func:`validate_profile_points` on the input first (the readers have already done so).
    """
    y = np.asarray(y, dtype=float).ravel()
    z = np.asarray(z, dtype=float).ravel()
    if validate:
        validate_profile_points(y, z, name)
        extent = _extent(y, z)
        if _in_plausible(extent * 1e-3):
            raise ProfileError(f"{name}: the points span {extent:.4g} m (bounding-box diagonal): they are evidently "
                               f"millimetres, but dense_from_points expects metres")
    elif len(y) != len(z) or len(y) < 4:
        raise ProfileError(f"{name}: need equally long y and z with at least 4 points")
    sigma = DEFAULT_GAUGE_NOISE_M if smoothing is None else float(smoothing)
    if not (sigma >= 0.0 and math.isfinite(sigma)):
        raise ProfileError(f"{name}: smoothing must be None, 0 or a positive noise level in metres, got {smoothing!r}")
    if not spacing > 0:
        raise ProfileError(f"{name}: spacing must be positive, got {spacing!r}")
    p = np.column_stack([y, z])
    if sigma == 0.0:
        p = p[_thin(p, INTERPOLATION_MIN_SPACING_M)]
        if len(p) < 4:
            raise ProfileError(f"{name}: fewer than 4 points are at least {INTERPOLATION_MIN_SPACING_M:g} m apart")
    spline, tau_data = _fit_spline(p, sigma)
    tau0, tau1 = float(tau_data[0]), float(tau_data[-1])
    count = max(int(math.ceil((tau1 - tau0) / spacing)) + 1, 4)
    tau = np.linspace(tau0, tau1, count)
    c0, c1, c2 = spline(tau), spline.derivative(1)(tau), spline.derivative(2)(tau)
    return DenseProfile(c0[:, 0].copy(), c0[:, 1].copy(), c1[:, 0].copy(), c1[:, 1].copy(), c2[:, 0].copy(),
                        c2[:, 1].copy(), name=name)


def load_profile(path, kind: str | None = None, *, smoothing: float | None = None, name: str | None = None,
                 spacing: float = DEFAULT_SPACING_M, **reader_kw) -> DenseProfile:
    """Read a profile file and fit it: ``.prw``/``.prr`` -> :func:`read_simpack_profile`, anything else ->
    :func:`read_yz_table` (``reader_kw``: ``units``, ``columns``, ``mirror_y``, ``mirror_z``, ``check_geometry``).

    ``smoothing=None`` uses the file's nature: a SIMPACK file with ``approx.smooth = 0`` holds exact points and is
    interpolated (``smoothing=0``); a SIMPACK file with ``approx.smooth > 0`` and a table are treated as
    measurements with the default gauge noise (:data:`DEFAULT_GAUGE_NOISE_M`).  SIMPACK's ``approx.smooth`` value
    itself is not translated (its scale is SIMPACK's own).  ``name`` defaults to the file stem.
    """
    path = Path(path)
    if path.suffix.lower() in _EXTENSION_KIND:
        if reader_kw:
            raise TypeError(f"read_simpack_profile takes no options {sorted(reader_kw)}")
        y, z, meta = read_simpack_profile(path, kind=kind)
        if smoothing is None:
            smoothing = 0.0 if not meta.get("approx_smooth") else DEFAULT_GAUGE_NOISE_M
    else:
        y, z, meta = read_yz_table(path, kind=kind, **reader_kw)
    return dense_from_points(y, z, smoothing=smoothing, name=name or path.stem, spacing=spacing, validate=False)
