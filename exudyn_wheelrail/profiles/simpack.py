"""Reader for SIMPACK wheel (``.prw``) and rail (``.prr``) profile files: :func:`read_simpack_profile`.

Frame and units of what is returned: the *profile frame* of :mod:`exudyn_wheelrail.conventions`, in **metres**
(``y`` lateral, positive towards the field side; ``z`` for a wheel the radius increase over the tape circle, for a
rail the depth below the top of the rail; points ordered from the gauge (flange) side to the field side, so that
``y[0] < y[-1]``).

The SIMPACK profile coordinates already use these directions (a wheel flange lies at negative y with positive z, a
rail crown has its smallest z at the top), so a SIMPACK file is returned exactly as its header transforms it; only
the point order is normalised.  No repositioning is done: a canted rail file stays canted, a non-standard reference
point stays where it is; the caller places the profile.

The points are checked by :func:`~exudyn_wheelrail.profiles.validation.validate_profile_points` and for a plausible
size in metres; in addition a missing ``point.begin``/``point.end`` and a header ``type`` that contradicts the
extension or the requested kind raise :class:`~exudyn_wheelrail.profiles.validation.ProfileError`.  The header
semantics assumed (SIMPACK's manual was not available; step order as in Vtech CMCC's CONTACT) are listed in
:func:`read_simpack_profile`.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from .validation import (MIN_POINTS, ProfileError, check_kind, in_plausible_extent, plausible_extent_text,
                         profile_extent, read_profile_text, validate_profile_points)

EXTENSION_KIND = {".prw": "wheel", ".prr": "rail"}
_SIMPACK_TYPE_KIND = {0: "rail", 1: "wheel"}
_LENGTH_UNIT_FACTORS = {"m": 1.0, "mm": 1000.0, "cm": 100.0, "dm": 10.0, "um": 1.0e6, "in": 1.0 / 0.0254}


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
    kind = check_kind(kind, source)
    lines = read_profile_text(path)

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
    ext_kind = EXTENSION_KIND.get(path.suffix.lower())
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

    extent = profile_extent(p[:, 0], p[:, 1])
    if not in_plausible_extent(extent):
        if in_plausible_extent(extent * 1e-3):
            hint = ("the data are evidently in millimetres, the length factor should be 1000"
                    if math.isclose(length_factor, 1.0) else "the data look 1000 times too large for this unit")
        elif in_plausible_extent(extent * 1e3):
            hint = ("the data are evidently in metres, the length factor should be 1"
                    if math.isclose(length_factor, 1000.0) else "the data look 1000 times too small for this unit")
        else:
            hint = "that is not the size of a wheel or rail profile"
        raise ProfileError(f"{source}: with the length factor {length_factor:g} ({unit_source}) the points span "
                           f"{extent:.4g} m (bounding-box diagonal; expected {plausible_extent_text()}): {hint}")

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
