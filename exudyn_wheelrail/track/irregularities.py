r"""Irregularities of each rail: the four channels alignment, vertical level, cross level and gauge deviation.

The channels, their signs and the rail-centre distance that turns cross level into a roll are those of
:mod:`exudyn_wheelrail.conventions` ("Track irregularities (per rail)"); per rail

.. math::  y_{right} = y + g/2,\quad y_{left} = y - g/2,\quad z_{right} = z + c/2,\quad z_{left} = z - c/2

(y lateral + right, z vertical + down, c cross level, g gauge deviation).  Every class here is an
:class:`~exudyn_wheelrail.track.rigid.Irregularity`: it packs into the same arrays as the whole-track classes
(:class:`~exudyn_wheelrail.track.rigid.SpanDeflection`, :class:`~exudyn_wheelrail.track.rigid.Harmonic`
— which take ``direction="cross_level"`` or ``"gauge"`` too — and
:class:`~exudyn_wheelrail.track.rigid.SampledIrregularity`), sums with them by ``+`` and is evaluated, all
components in one call, by the compiled :func:`~exudyn_wheelrail.track.rigid.irregularity_channels_at` that the
contact calls per wheelset.  A component of one rail is packed as its mean channel (half its amplitude) and its
difference channel (± its amplitude).

* :class:`ChannelTable` — sampled channels (measured or generated), cubic splines with zero end slopes, held
  constant outside the table; :meth:`ChannelTable.from_rails` from left/right rail values;
* :class:`FadedIn` — a table's channels faded in from zero (with their slopes) by a raised cosine, e.g. for a
  vehicle that starts on the undisplaced track;
* :class:`IsolatedDefect` — one local defect of one rail (or both), vertical or lateral:

  - ``"bump"``: ``d (1 - cos(2π u/L))/2`` on ``u = s - s0 ∈ [0, L]`` (C1; a positive depth is a dip, z down),
  - ``"cusp"``: ``d (1 - |x|)²`` with ``x = 2 (s - s_c)/L ∈ [-1, 1]`` (ends tangent to the rail, a slope jump
    ``8 d/L`` at the centre),
  - ``"dipped_joint"``: ``d (1 - |x|)`` (straight rail ends meeting at the joint: slope jump ``4 d/L`` at the joint
    — the joint's total dip angle — and ``2 d/L`` at each end of the dip);

  ``s0`` is ``position_m`` for the bump (its start) and the centre ``s_c`` for the cusp and the dipped joint.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import CubicSpline

from .rigid import (
    EMPTY_COEFS,
    EMPTY_KNOTS,
    KIND_COSINE_BUMP,
    KIND_CUSP,
    KIND_TABLE,
    KIND_V,
    CROSS_LEVEL,
    GAUGE,
    LATERAL,
    N_CHANNEL_VALUES,
    VERTICAL,
    Irregularity,
    irregularity_channels_many,
)
from ..validation import finite

__all__ = ["CHANNELS", "RAILS", "DEFECT_SHAPES", "ChannelValues", "ChannelTable", "FadedIn", "IsolatedDefect",
           "channel_values", "rail_values"]

#: the four channels by name, in the order of :func:`~exudyn_wheelrail.track.rigid.irregularity_channels_at`
CHANNELS = {"alignment": LATERAL, "level": VERTICAL, "cross_level": CROSS_LEVEL, "gauge": GAUGE}

#: rails a defect can be on, with the sign of its difference channel per direction (cross level = z_right - z_left,
#: gauge = y_right - y_left)
RAILS = {"right": 1.0, "left": -1.0, "both": 0.0}

#: isolated defect shapes (their kind in the packed rows)
DEFECT_SHAPES = {"bump": KIND_COSINE_BUMP, "cusp": KIND_CUSP, "dipped_joint": KIND_V}


class ChannelValues:
    """The four channels and their first and second derivatives with respect to s at the points asked for:
    attributes ``alignment_m``, ``level_m``, ``cross_level_m``, ``gauge_m`` and ``d_<name>``, ``dd_<name>``
    (arrays of the shape of s)."""

    def __init__(self, out: np.ndarray, shape):
        for name, code in CHANNELS.items():
            for j, prefix in enumerate(("", "d_", "dd_")):
                setattr(self, f"{prefix}{name}_m" if not prefix else f"{prefix}{name}",
                        out[:, 3 * code + j].reshape(shape))


def channel_values(irregularity: Irregularity, s_m) -> ChannelValues:
    """All four channels of ``irregularity`` (any :class:`~exudyn_wheelrail.track.rigid.Irregularity`) at the
    track distance(s) ``s_m``, by the compiled evaluation the contact uses."""
    s = np.asarray(s_m, dtype=float)
    p = irregularity.packed()
    out = irregularity_channels_many(p.rows, p.knots, p.coefs, np.ascontiguousarray(s.reshape(-1)))
    assert out.shape[1] == N_CHANNEL_VALUES
    return ChannelValues(out, s.shape)


def rail_values(irregularity: Irregularity, s_m) -> dict[str, np.ndarray]:
    """Lateral and vertical position of each rail (``y_right_m``, ``y_left_m``, ``z_right_m``, ``z_left_m``) at the
    track distance(s) ``s_m`` (conventions.py: per rail)."""
    v = channel_values(irregularity, s_m)
    return {"y_right_m": v.alignment_m + 0.5 * v.gauge_m, "y_left_m": v.alignment_m - 0.5 * v.gauge_m,
            "z_right_m": v.level_m + 0.5 * v.cross_level_m, "z_left_m": v.level_m - 0.5 * v.cross_level_m}


def _finite(name: str, value, positive=False) -> float:
    """:func:`~exudyn_wheelrail.validation.finite`, and > 0 with ``positive``."""
    value = finite(name, value)
    if positive and not value > 0.0:
        raise ValueError(f"{name}: {value:g} must be positive")
    return value


class ChannelTable(Irregularity):
    """Sampled channels: each given channel interpolated by a cubic spline with zero end slopes (C2 inside the
    table, C1 at its ends) and held constant outside the table; channels not given are zero.

    Parameters: ``s_m`` strictly increasing track distances (at least 2); ``channels`` a dict ``{name: values}``
    with names of :data:`CHANNELS` (m); ``name`` names the source in messages."""

    def __init__(self, s_m, channels: dict, name: str = "table"):
        s = np.asarray(s_m, dtype=float).reshape(-1)
        self.name = name
        if len(s) < 2:
            raise ValueError(f"{name}: at least two samples are needed, got {len(s)}")
        if not np.all(np.isfinite(s)):
            raise ValueError(f"{name}: non-finite distance at sample {int(np.argmin(np.isfinite(s))) + 1}")
        if np.any(np.diff(s) <= 0.0):
            i = int(np.argmax(np.diff(s) <= 0.0))
            raise ValueError(f"{name}: s must increase strictly (sample {i + 2}: {s[i]} -> {s[i + 1]})")
        self.s_m = s
        self.channels = {}
        for key, values in channels.items():
            if key not in CHANNELS:
                raise ValueError(f"{name}: unknown channel {key!r} (expected {', '.join(CHANNELS)})")
            v = np.asarray(values, dtype=float).reshape(-1)
            if len(v) != len(s):
                raise ValueError(f"{name}: channel {key!r} has {len(v)} values for {len(s)} distances")
            if not np.all(np.isfinite(v)):
                raise ValueError(f"{name}: channel {key!r}: non-finite value at sample "
                                 f"{int(np.argmin(np.isfinite(v))) + 1}")
            self.channels[key] = v
        self._coefs = {key: CubicSpline(s, v, bc_type="clamped").c.T.copy() for key, v in self.channels.items()}

    @classmethod
    def from_rails(cls, s_m, *, y_right_m=None, y_left_m=None, z_right_m=None, z_left_m=None,
                   name: str = "table") -> "ChannelTable":
        """The channels of sampled rail positions (a rail not given is at its nominal place; lateral given for
        both rails or neither, likewise vertical)."""
        s = np.asarray(s_m, dtype=float).reshape(-1)
        channels = {}
        for a, b, mean, diff, what in ((y_right_m, y_left_m, "alignment", "gauge", "y"),
                                       (z_right_m, z_left_m, "level", "cross_level", "z")):
            if a is None and b is None:
                continue
            if a is None or b is None:
                raise ValueError(f"{name}: give {what}_right_m and {what}_left_m together")
            a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
            channels[mean] = 0.5 * (a + b)
            channels[diff] = a - b
        return cls(s, channels, name=name)

    def _parts(self):
        n = len(self.s_m)
        return [([KIND_TABLE, CHANNELS[key], 0, n, 0, 0.0, 0.0, 0.0], self.s_m, c) for key, c in self._coefs.items()]

    def __repr__(self):
        return (f"ChannelTable({self.name!r}, {', '.join(self.channels)}, {len(self.s_m)} samples, "
                f"s {self.s_m[0]}..{self.s_m[-1]} m)")


class IsolatedDefect(Irregularity):
    """One isolated defect (module docstring: shapes ``bump``, ``cusp``, ``dipped_joint``) of ``length_m`` and
    ``depth_m`` on the ``rail`` ``"right"``, ``"left"`` or ``"both"``, in the ``direction`` ``"vertical"`` (a
    positive depth lowers the rail: z down) or ``"lateral"`` (a positive depth moves the rail to the right)."""

    def __init__(self, shape: str, position_m: float, length_m: float, depth_m: float, rail: str = "both",
                 direction: str = "vertical"):
        if shape not in DEFECT_SHAPES:
            raise ValueError(f"defect shape {shape!r}: expected one of {', '.join(DEFECT_SHAPES)}")
        if rail not in RAILS:
            raise ValueError(f"defect rail {rail!r}: expected one of {', '.join(RAILS)}")
        if direction not in ("vertical", "lateral"):
            raise ValueError(f"defect direction {direction!r}: expected 'vertical' or 'lateral'")
        self.shape, self.rail, self.direction = shape, rail, direction
        self.position_m = _finite("defect position_m", position_m)
        self.length_m = _finite("defect length_m", length_m, positive=True)
        self.depth_m = _finite("defect depth_m", depth_m)

    def _parts(self):
        kind = DEFECT_SHAPES[self.shape]
        mean, diff = (VERTICAL, CROSS_LEVEL) if self.direction == "vertical" else (LATERAL, GAUGE)
        sign = RAILS[self.rail]
        # one rail: half the depth in the mean channel, ± the depth in the difference channel; both rails: the mean
        parts = [(mean, self.depth_m if sign == 0.0 else 0.5 * self.depth_m)]
        if sign != 0.0:
            parts.append((diff, sign * self.depth_m))
        return [([kind, channel, self.position_m, self.length_m, depth, 0.0, 0.0, 0.0], EMPTY_KNOTS, EMPTY_COEFS)
                for channel, depth in parts]

    def __repr__(self):
        return (f"IsolatedDefect({self.shape!r}, position_m={self.position_m}, length_m={self.length_m}, "
                f"depth_m={self.depth_m}, rail={self.rail!r}, direction={self.direction!r})")


class FadedIn(ChannelTable):
    """The channels of ``table`` (a :class:`ChannelTable`, e.g. a
    :class:`~exudyn_wheelrail.track.spectra.SpectralIrregularity`) times the raised cosine
    ``w(s) = (1 - cos(π u))/2``, ``u = (s - s_from)/(s_to - s_from)`` clipped to [0, 1]: zero (with its slope) up to
    ``s_from_m``, the table's own from ``s_to_m`` on; re-interpolated at the table's samples.  The table must start
    at or before ``s_from_m``.  ``seed`` is the table's (None if it has none)."""

    def __init__(self, table, s_from_m: float, s_to_m: float):
        if not isinstance(table, ChannelTable):
            raise ValueError(f"FadedIn: {table!r}: expected a ChannelTable (sampled channels)")
        if not (math.isfinite(s_from_m) and math.isfinite(s_to_m) and s_to_m > s_from_m):
            raise ValueError(f"FadedIn: s_from_m = {s_from_m!r}, s_to_m = {s_to_m!r}: expected finite s_from_m < "
                             "s_to_m")
        if table.s_m[0] > s_from_m:
            raise ValueError(f"FadedIn: {table!r} starts at s = {table.s_m[0]:g} m, after s_from_m = {s_from_m:g} m "
                             "(it is held constant before its start, not zero)")
        u = np.clip((table.s_m - s_from_m) / (s_to_m - s_from_m), 0.0, 1.0)
        w = 0.5 * (1.0 - np.cos(math.pi * u))
        self.source = table
        self.seed = getattr(table, "seed", None)
        self.s_from_m, self.s_to_m = float(s_from_m), float(s_to_m)
        super().__init__(table.s_m, {k: w * v for k, v in table.channels.items()}, name=f"{table.name} faded in")

    def __repr__(self):
        return f"FadedIn({self.source!r}, s_from_m={self.s_from_m:g}, s_to_m={self.s_to_m:g})"
