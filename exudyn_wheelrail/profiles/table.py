"""Reader for plain two-column y-z point tables as exported by profile gauges: :func:`read_yz_table`.

Comma, semicolon (with decimal commas), tab or whitespace separated columns, an optional header line, ``#``
comments.  The table must already be in the *profile frame* of :mod:`exudyn_wheelrail.conventions` (``y`` lateral,
positive towards the field side; ``z`` for a wheel the radius increase over the tape circle, for a rail the depth
below the top of the rail), apart from the length unit and the point order: what is returned is in **metres**,
ordered from the gauge side to the field side.  The unit is declared or inferred from the extent
(:data:`~exudyn_wheelrail.profiles.validation.PLAUSIBLE_EXTENT_M`); the points are checked by
:func:`~exudyn_wheelrail.profiles.validation.validate_profile_points`.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from .validation import (MIN_POINTS, ProfileError, check_kind, in_plausible_extent, plausible_extent_text,
                         profile_extent, read_profile_text, validate_profile_points)

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
    kind = check_kind(kind, source)
    if len(columns) != 2 or min(columns) < 0 or columns[0] == columns[1]:
        raise ProfileError(f"{source}: columns must be two different non-negative column indices, got {columns!r}")
    lines = read_profile_text(path)

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
    raw_extent = profile_extent(p[:, 0], p[:, 1])

    # units
    def fits(scale):
        return in_plausible_extent(raw_extent * scale)

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
                    f"({plausible_extent_text()}) nor in millimetres; pass units=")
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
                                   f"(bounding-box diagonal; a profile spans {plausible_extent_text()}): {problem}")
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
                               f"(expected {plausible_extent_text()})")
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
