"""Measured track irregularities from CSV files: the four channels or the rails' positions along the track.

File format
-----------
Comma-separated text; blank lines and lines starting with ``#`` are ignored.  The first other line is the header:
it names every column with its unit suffix, ``_m`` or ``_mm`` (millimetres are converted to metres on reading):

* ``s_m`` (required) — track distance, strictly increasing;
* channels (:mod:`exudyn_wheelrail.conventions`): ``alignment``, ``level``, ``cross_level``, ``gauge`` — e.g.
  ``s_m, alignment_mm, level_mm, cross_level_mm, gauge_mm``;
* or rails: ``y_right``, ``y_left`` (lateral, + right) and ``z_right``, ``z_left`` (vertical, + down), in pairs —
  a rail pair and the channels it makes (alignment and gauge from y, level and cross level from z) cannot both be
  given.

Channels not given are zero.  Every error — an unknown or repeated column, a missing unit, a non-numeric or NaN
value, a distance that does not increase, a value too large for an irregularity in metres (:data:`MAX_PLAUSIBLE_M`,
as when millimetres are labelled ``_m``) or a millimetre column whose values all lie below
:data:`MIN_PLAUSIBLE_PEAK_M` (metres labelled ``_mm``) — raises ``ValueError`` naming the file and the line.  The samples are interpolated by
:class:`~.irregularities.ChannelTable` (cubic splines with zero end slopes, held constant outside the file).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .irregularities import CHANNELS, ChannelTable

__all__ = ["read_irregularity_csv", "MAX_PLAUSIBLE_M", "MIN_PLAUSIBLE_PEAK_M", "RAIL_COLUMNS", "UNITS"]

#: largest |value| accepted for an irregularity column in metres [m]
MAX_PLAUSIBLE_M = 0.2
#: smallest largest |value| accepted for a millimetre column [m] (0.05 mm): below it the file holds metres
MIN_PLAUSIBLE_PEAK_M = 5e-5
#: unit suffixes and their factor to metres
UNITS = {"m": 1.0, "mm": 1e-3}
#: rail columns: name -> (the channel pair they make, the partner column)
RAIL_COLUMNS = {"y_right": ("lateral", "y_left"), "y_left": ("lateral", "y_right"),
                "z_right": ("vertical", "z_left"), "z_left": ("vertical", "z_right")}
_PAIR_CHANNELS = {"lateral": ("alignment", "gauge"), "vertical": ("level", "cross_level")}


def _split_unit(path, line_no, column):
    base, sep, unit = column.rpartition("_")
    if not sep or unit not in UNITS:
        raise ValueError(f"{path}:{line_no}: column {column!r} has no unit suffix (_m or _mm)")
    return base, unit


def read_irregularity_csv(path) -> ChannelTable:
    """The :class:`~.irregularities.ChannelTable` of the CSV file ``path`` (module docstring)."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as e:
        raise ValueError(f"{path}: cannot read the irregularity file ({e.strerror or e})") from None
    rows = [(i, line) for i, line in enumerate(text.splitlines(), start=1)
            if line.strip() and not line.lstrip().startswith("#")]
    if not rows:
        raise ValueError(f"{path}: no header line (expected e.g. 's_m, alignment_mm, level_mm, cross_level_mm, "
                         "gauge_mm')")
    header_no, header = rows[0]
    columns = [c.strip() for c in header.split(",")]
    known = set(CHANNELS) | set(RAIL_COLUMNS) | {"s"}
    bases, factors = [], []
    for c in columns:
        base, unit = _split_unit(path, header_no, c)
        if base not in known:
            raise ValueError(f"{path}:{header_no}: unknown column {c!r} (expected s_m and channels "
                             f"{', '.join(CHANNELS)} or rails {', '.join(RAIL_COLUMNS)}, each with _m or _mm)")
        if base in bases:
            raise ValueError(f"{path}:{header_no}: column {base!r} given twice")
        if base == "s" and unit != "m":
            raise ValueError(f"{path}:{header_no}: the distance column must be s_m")
        bases.append(base)
        factors.append(UNITS[unit])
    if "s" not in bases:
        raise ValueError(f"{path}:{header_no}: missing the distance column s_m")
    for base in bases:
        if base in RAIL_COLUMNS:
            pair, partner = RAIL_COLUMNS[base]
            if partner not in bases:
                raise ValueError(f"{path}:{header_no}: rail column {base!r} needs {partner!r} too")
            for ch in _PAIR_CHANNELS[pair]:
                if ch in bases:
                    raise ValueError(f"{path}:{header_no}: {ch!r} and the rail columns {base!r}/{partner!r} "
                                     "describe the same thing: give one of them")
    if len(rows) < 3:
        raise ValueError(f"{path}: at least two data lines are needed, found {len(rows) - 1}")
    data = np.empty((len(rows) - 1, len(columns)))
    lines = np.array([i for i, _ in rows[1:]])
    for r, (line_no, line) in enumerate(rows[1:]):
        fields = [f.strip() for f in line.split(",")]
        if len(fields) != len(columns):
            raise ValueError(f"{path}:{line_no}: {len(fields)} values for {len(columns)} columns")
        for j, (f, c) in enumerate(zip(fields, columns)):
            try:
                v = float(f)
            except ValueError:
                raise ValueError(f"{path}:{line_no}: column {c!r}: not a number: {f!r}") from None
            if not math.isfinite(v):
                raise ValueError(f"{path}:{line_no}: column {c!r}: {f!r} is not a finite number")
            if j and factors[j] == 1.0 and abs(v) > MAX_PLAUSIBLE_M:
                raise ValueError(f"{path}:{line_no}: column {c!r}: {v:g} m is implausible for an irregularity "
                                 f"(|value| > {MAX_PLAUSIBLE_M} m): are these millimetres? name the column "
                                 f"{c[:-2]}_mm")
            data[r, j] = v * factors[j]
    s = data[:, bases.index("s")]
    ds = np.diff(s)
    if np.any(ds <= 0.0):
        i = int(np.argmax(ds <= 0.0))
        what = "repeats" if ds[i] == 0.0 else "decreases"
        raise ValueError(f"{path}:{lines[i + 1]}: the distance s_m {what} ({s[i]:g} -> {s[i + 1]:g} m): it must "
                         "increase strictly")
    for j, (c, f) in enumerate(zip(columns, factors)):
        if f != 1.0 and 0.0 < np.max(np.abs(data[:, j])) < MIN_PLAUSIBLE_PEAK_M:
            raise ValueError(f"{path}:{header_no}: column {c!r}: every value is below {MIN_PLAUSIBLE_PEAK_M * 1e3:g} "
                             f"mm: are these metres? name the column {c[:-3]}_m")
    col = {b: data[:, j] for j, b in enumerate(bases)}
    channels = {b: col[b] for b in bases if b in CHANNELS}
    if "y_right" in col:
        channels["alignment"] = 0.5 * (col["y_right"] + col["y_left"])
        channels["gauge"] = col["y_right"] - col["y_left"]
    if "z_right" in col:
        channels["level"] = 0.5 * (col["z_right"] + col["z_left"])
        channels["cross_level"] = col["z_right"] - col["z_left"]
    return ChannelTable(s, channels, name=str(path))
