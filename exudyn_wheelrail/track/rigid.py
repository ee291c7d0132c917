r"""Rigid straight track with irregularities as functions of the track distance s: the packed components and the
compiled evaluation of all four irregularity channels.

The channels (:mod:`exudyn_wheelrail.conventions`, "Track irregularities (per rail)") are the alignment ``y(s)``
and vertical level ``z(s)`` of the rails' centre line (track-frame y positive to the right, z positive downwards),
the cross level ``c(s)`` and the gauge deviation ``g(s)``.  For the contact kernel every irregularity is *packed*
into plain arrays (one row per component: its kind, its channel and its parameters) and evaluated by one numba
function, :func:`irregularity_channels_at` (scalar s, returns value, d/ds and d²/ds² of the four channels) —
:func:`irregularity_at` returns the alignment and level alone (``y, y', y'', z, z', z''``), :func:`irregularity_many`
and :func:`irregularity_channels_many` evaluate arrays of s.  The Python classes here (:class:`SpanDeflection`,
:class:`Harmonic`, :class:`SampledIrregularity`, sums with ``+``) and those of :mod:`exudyn_wheelrail.track`
(per-rail tables, measured files, isolated defects, generated spectra) build those arrays; ``direction`` of a span
deflection or a harmonic names its channel (:data:`CHANNEL_NAMES`).

Span deflection with smooth end transitions (RTRI case)
-------------------------------------------------------
The lateral deflection of a simply supported span of length L starting at s0 is
``y(s) = δ sin(π (s - s0)/L)`` on the span and 0 outside.  Its slope jumps by ``k = π δ / L`` at each end
(a kink a continuous rail cannot follow).  Each kink is replaced by a **quintic Hermite transition of length
l_t centred on the span end**, i.e. on ``[s0 - l_t/2, s0 + l_t/2]`` (and mirrored at ``s0 + L``), that matches
value, slope and curvature of the zero line on one side and of the sine on the other — the track is C2
everywhere.  With ``u = s - s0``, ``h = l_t/2``, ``ξ = (u + h)/l_t ∈ [0, 1]`` and the sine's value, slope and
curvature at the inner end of the transition

.. math::  f = δ \sin(π h/L),\quad f' = δ (π/L) \cos(π h/L),\quad f'' = -δ (π/L)^2 \sin(π h/L),

the transition is (the quintic Hermite interpolant with zero data at ξ = 0)

.. math::  y = f\,(10ξ^3 - 15ξ^4 + 6ξ^5) + l_t f'\,(-4ξ^3 + 7ξ^4 - 3ξ^5) + l_t^2 f''\,(ξ^3 - 2ξ^4 + ξ^5)/2 ,

with ``dy/ds = (dy/dξ)/l_t`` and ``d²y/ds² = (d²y/dξ²)/l_t²``.  At the far end the shape is mirrored,
``y(s0 + L - u) = y(s0 + u)``, so the whole shape is symmetric about mid-span, where ``y = δ`` exactly (for
``l_t < L``).  For a short transition (sine ≈ its tangent, f'' → 0, f = k h) this reduces to the quartic
``y = k l_t (ξ³ - ξ⁴/2)``, whose curvature ``(3k/l_t)·2ξ(1-ξ)`` rises from 0 to ``1.5 k/l_t`` mid-transition and
back: the kink is spread into a parabolic curvature bump of length l_t, and the shape stays within 0 … δ (no
overshoot; checked by the tests).  The transition changes the shape only within ``l_t/2`` of each span end (at the
end itself by about ``3 k l_t / 32``, the short-transition value).  ``l_t = 0`` gives the original kinked shape.

Other irregularities
--------------------
* :class:`Harmonic`: ``a sin(2π s/λ + φ)`` along the whole track (any channel).
* :class:`SampledIrregularity`: measured data (CSV columns ``s_m, y_m, z_m``), interpolated by a cubic spline
  with zero end slopes (C2 inside the table, C1 at its ends) and held constant outside it.
* Sums: ``a + b`` (any number of components, evaluated in one call).

Default values of the RTRI deviation (δ, l_t) are assumptions and live in
:class:`exudyn_wheelrail.scenarios.rtri_assumptions.RtriAssumptions`.
"""
from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline

from ..jit import compiled

__all__ = [
    "LATERAL",
    "VERTICAL",
    "CROSS_LEVEL",
    "GAUGE",
    "CHANNEL_NAMES",
    "IrregularityValues",
    "PackedIrregularity",
    "Irregularity",
    "NoIrregularity",
    "SpanDeflection",
    "Harmonic",
    "SampledIrregularity",
    "IrregularitySum",
    "RigidStraightTrack",
    "irregularity_at",
    "irregularity_many",
    "irregularity_channels_at",
    "irregularity_channels_many",
    "span_deflection_at",
]

LATERAL = 0      #: channel code: alignment, track y of the rails' centre line
VERTICAL = 1     #: channel code: vertical level, track z of the rails' centre line
CROSS_LEVEL = 2  #: channel code: cross level (conventions.py)
GAUGE = 3        #: channel code: gauge deviation (conventions.py)
N_CHANNEL_VALUES = 12  # value, d/ds, d2/ds2 of the four channels (irregularity_channels_at)

#: the kinds of a row of the compiled component table (``ROW_COLUMNS`` columns; :mod:`.irregularities` writes them too)
KIND_SPAN = 1
KIND_HARMONIC = 2
KIND_TABLE = 3
KIND_COSINE_BUMP = 4  # p0 start, p1 length, p2 depth
KIND_CUSP = 5         # p0 centre, p1 length, p2 depth
KIND_V = 6            # p0 centre, p1 length, p2 depth
ROW_COLUMNS = 8  # [kind, channel, p0 ... p5]


# ------------------------------------------------------------------------------------------ compiled kernels
@compiled(refcount=False)
def _transition(u, h, span, delta):
    """Left transition of the span shape at u in [-h, h] (u from the span start): value, d/ds, d2/ds2."""
    lt = 2.0 * h
    w = math.pi / span
    sn, cs = math.sin(w * h), math.cos(w * h)
    f, f1, f2 = delta * sn, delta * w * cs, -delta * w * w * sn
    x = (u + h) / lt
    x2 = x * x
    x3 = x2 * x
    # quintic Hermite basis (zero data at x = 0): value, slope and curvature at x = 1
    h5 = 10.0 * x3 - 15.0 * x3 * x + 6.0 * x3 * x2
    h5d = 30.0 * x2 - 60.0 * x3 + 30.0 * x2 * x2
    h5dd = 60.0 * x - 180.0 * x2 + 120.0 * x3
    h4 = -4.0 * x3 + 7.0 * x3 * x - 3.0 * x3 * x2
    h4d = -12.0 * x2 + 28.0 * x3 - 15.0 * x2 * x2
    h4dd = -24.0 * x + 84.0 * x2 - 60.0 * x3
    h3 = 0.5 * (x3 - 2.0 * x3 * x + x3 * x2)
    h3d = 0.5 * (3.0 * x2 - 8.0 * x3 + 5.0 * x2 * x2)
    h3dd = 0.5 * (6.0 * x - 24.0 * x2 + 20.0 * x3)
    value = f * h5 + lt * f1 * h4 + lt * lt * f2 * h3
    slope = (f * h5d + lt * f1 * h4d + lt * lt * f2 * h3d) / lt
    curvature = (f * h5dd + lt * f1 * h4dd + lt * lt * f2 * h3dd) / (lt * lt)
    return value, slope, curvature


@compiled(refcount=False)
def span_deflection_at(s, start, span, delta, transition):
    """Span shape (value, d/ds, d2/ds2) at s: δ sin(π (s - start)/span) with C2 end transitions."""
    u = s - start
    h = 0.5 * transition
    if u <= -h or u >= span + h:
        return 0.0, 0.0, 0.0
    if h > 0.0 and u < h:
        return _transition(u, h, span, delta)
    if h > 0.0 and u > span - h:
        v, d1, d2 = _transition(span - u, h, span, delta)
        return v, -d1, d2
    if u < 0.0 or u > span:  # l_t = 0: outside the span
        return 0.0, 0.0, 0.0
    w = math.pi / span
    return delta * math.sin(w * u), delta * w * math.cos(w * u), -delta * w * w * math.sin(w * u)


@compiled(refcount=False)
def _table_at(knots, coefs, k0, n, c0, s):
    """Piecewise cubic (coefficients c3, c2, c1, c0 per interval, in powers of s - s_i) at s; held outside."""
    if s <= knots[k0]:
        return coefs[c0, 3], 0.0, 0.0
    if s >= knots[k0 + n - 1]:
        i = n - 2
        d = knots[k0 + n - 1] - knots[k0 + i]
        c = coefs[c0 + i]
        return ((c[0] * d + c[1]) * d + c[2]) * d + c[3], 0.0, 0.0
    i = np.searchsorted(knots[k0:k0 + n], s, side="right") - 1
    if i > n - 2:
        i = n - 2
    d = s - knots[k0 + i]
    c = coefs[c0 + i]
    return (((c[0] * d + c[1]) * d + c[2]) * d + c[3], (3.0 * c[0] * d + 2.0 * c[1]) * d + c[2],
            6.0 * c[0] * d + 2.0 * c[1])


@compiled(refcount=False)
def _component_at(rows, r, knots, coefs, s):
    """Value, d/ds and d2/ds2 of the packed component ``rows[r]`` at s."""
    kind = int(rows[r, 0])
    if kind == KIND_SPAN:
        return span_deflection_at(s, rows[r, 2], rows[r, 3], rows[r, 4], rows[r, 5])
    if kind == KIND_HARMONIC:
        w = 2.0 * math.pi / rows[r, 3]
        arg = w * s + rows[r, 4]
        a = rows[r, 2]
        return a * math.sin(arg), a * w * math.cos(arg), -a * w * w * math.sin(arg)
    if kind == KIND_TABLE:
        return _table_at(knots, coefs, int(rows[r, 2]), int(rows[r, 3]), int(rows[r, 4]), s)
    if kind == KIND_COSINE_BUMP:
        # depth (1 - cos(2π u/L))/2 on u = s - start in [0, L]
        u = s - rows[r, 2]
        length = rows[r, 3]
        if u <= 0.0 or u >= length:
            return 0.0, 0.0, 0.0
        w = 2.0 * math.pi / length
        a = 0.5 * rows[r, 4]
        return a * (1.0 - math.cos(w * u)), a * w * math.sin(w * u), a * w * w * math.cos(w * u)
    if kind == KIND_CUSP:
        # depth (1 - |x|)^2, x = 2 (s - centre)/L in [-1, 1]
        length = rows[r, 3]
        x = 2.0 * (s - rows[r, 2]) / length
        ax = abs(x)
        if ax >= 1.0:
            return 0.0, 0.0, 0.0
        d = rows[r, 4]
        sign = 1.0 if x >= 0.0 else -1.0
        k = 2.0 / length
        return d * (1.0 - ax) * (1.0 - ax), -2.0 * d * (1.0 - ax) * sign * k, 2.0 * d * k * k
    if kind == KIND_V:
        # depth (1 - |x|), x = 2 (s - centre)/L in [-1, 1]
        length = rows[r, 3]
        x = 2.0 * (s - rows[r, 2]) / length
        ax = abs(x)
        if ax >= 1.0:
            return 0.0, 0.0, 0.0
        d = rows[r, 4]
        sign = 1.0 if x >= 0.0 else -1.0
        return d * (1.0 - ax), -d * sign * 2.0 / length, 0.0
    return 0.0, 0.0, 0.0


@compiled(refcount=False)
def irregularity_channels_at(rows, knots, coefs, s):
    """The four irregularity channels of the packed components at track distance s, each with d/ds and d2/ds2.

    Returns ``(y, y', y'', z, z', z'', c, c', c'', g, g', g'')``: alignment y and vertical level z of the rails'
    centre line (track frame, m), cross level c and gauge deviation g (m; signs in
    :mod:`exudyn_wheelrail.conventions`).  ``rows`` (n, 8) float: ``[kind, channel, p0..p5]``; ``knots`` (m,) and
    ``coefs`` (m', 4) hold the sampled tables (may be empty).  Allocates nothing (the contact evaluates it per
    wheelset at every call)."""
    y = y1 = y2 = z = z1 = z2 = c = c1 = c2 = g = g1 = g2 = 0.0
    for r in range(rows.shape[0]):
        channel = int(rows[r, 1])
        v, d1, d2 = _component_at(rows, r, knots, coefs, s)
        if channel == LATERAL:
            y += v
            y1 += d1
            y2 += d2
        elif channel == VERTICAL:
            z += v
            z1 += d1
            z2 += d2
        elif channel == CROSS_LEVEL:
            c += v
            c1 += d1
            c2 += d2
        else:
            g += v
            g1 += d1
            g2 += d2
    return y, y1, y2, z, z1, z2, c, c1, c2, g, g1, g2


@compiled(refcount=False)
def irregularity_at(rows, knots, coefs, s):
    """Alignment and vertical level of the packed components at track distance s: ``(y, dy/ds, d2y/ds2, z, dz/ds,
    d2z/ds2)`` (m, -, 1/m), the first six entries of :func:`irregularity_channels_at`."""
    v = irregularity_channels_at(rows, knots, coefs, s)
    return v[0], v[1], v[2], v[3], v[4], v[5]


@compiled
def irregularity_many(rows, knots, coefs, s_values):
    """:func:`irregularity_at` for every entry of ``s_values``: array (n, 6)."""
    out = np.empty((s_values.shape[0], 6))
    for i in range(s_values.shape[0]):
        y, y1, y2, z, z1, z2 = irregularity_at(rows, knots, coefs, s_values[i])
        out[i, 0], out[i, 1], out[i, 2], out[i, 3], out[i, 4], out[i, 5] = y, y1, y2, z, z1, z2
    return out


@compiled
def irregularity_channels_many(rows, knots, coefs, s_values):
    """:func:`irregularity_channels_at` for every entry of ``s_values``: array (n, 12)."""
    out = np.empty((s_values.shape[0], N_CHANNEL_VALUES))
    for i in range(s_values.shape[0]):
        v = irregularity_channels_at(rows, knots, coefs, s_values[i])
        for j in range(N_CHANNEL_VALUES):
            out[i, j] = v[j]
    return out


# --------------------------------------------------------------------------------------------- Python side
@dataclass(frozen=True)
class IrregularityValues:
    """Irregularity and its derivatives with respect to s (arrays of the shape of s)."""

    y_m: np.ndarray
    dy_ds: np.ndarray
    d2y_ds2: np.ndarray
    z_m: np.ndarray
    dz_ds: np.ndarray
    d2z_ds2: np.ndarray


@dataclass(frozen=True)
class PackedIrregularity:
    """Plain arrays for :func:`irregularity_at`: ``rows`` (n, 8), ``knots`` (m,), ``coefs`` (m', 4)."""

    rows: np.ndarray
    knots: np.ndarray
    coefs: np.ndarray


#: channel names accepted for a component's ``direction`` (the code of each), the first of each code its name
CHANNEL_NAMES = {"lateral": LATERAL, "alignment": LATERAL, "y": LATERAL,
                 "vertical": VERTICAL, "level": VERTICAL, "z": VERTICAL,
                 "cross_level": CROSS_LEVEL, "gauge": GAUGE}


def _direction(direction) -> int:
    if isinstance(direction, str) and direction in CHANNEL_NAMES:
        return CHANNEL_NAMES[direction]
    if direction in (LATERAL, VERTICAL, CROSS_LEVEL, GAUGE) and not isinstance(direction, bool):
        return int(direction)
    raise ValueError(f"direction {direction!r}: expected one of {', '.join(repr(k) for k in CHANNEL_NAMES)}")


def _finite(name: str, value, positive=False, non_negative=False) -> float:
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} = {value!r} must be finite")
    if positive and not value > 0.0:
        raise ValueError(f"{name} = {value!r} must be positive")
    if non_negative and value < 0.0:
        raise ValueError(f"{name} = {value!r} must not be negative")
    return value


class Irregularity:
    """Base class: a list of packed components; ``a + b`` sums irregularities."""

    def _parts(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """(row, knots, coefs) per component; row knot/coef offsets relative to the component's own arrays."""
        raise NotImplementedError

    def packed(self) -> PackedIrregularity:
        rows, knots, coefs = [], [], []
        n_knots = n_coefs = 0
        for row, k, c in self._parts():
            row = np.array(row, dtype=float)
            if int(row[0]) == KIND_TABLE:
                row[2] += n_knots
                row[4] += n_coefs
            rows.append(row)
            knots.append(k)
            coefs.append(c)
            n_knots += len(k)
            n_coefs += len(c)
        return PackedIrregularity(
            np.array(rows, dtype=float).reshape(-1, ROW_COLUMNS),
            np.concatenate(knots) if knots else np.zeros(0),
            np.concatenate(coefs).reshape(-1, 4) if coefs else np.zeros((0, 4)))

    def evaluate(self, s_m) -> IrregularityValues:
        """Values and derivatives at the track distance(s) ``s_m``."""
        s = np.asarray(s_m, dtype=float)
        p = self.packed()
        out = irregularity_many(p.rows, p.knots, p.coefs, np.ascontiguousarray(s.reshape(-1)))
        cols = [out[:, i].reshape(s.shape) for i in range(6)]
        return IrregularityValues(*cols)

    def __add__(self, other: "Irregularity") -> "IrregularitySum":
        if not isinstance(other, Irregularity):
            return NotImplemented
        return IrregularitySum([self, other])


class NoIrregularity(Irregularity):
    """A perfect track."""

    def _parts(self):
        return []


class IrregularitySum(Irregularity):
    """Sum of irregularities (nested sums are flattened)."""

    def __init__(self, components):
        flat = []
        for c in components:
            if not isinstance(c, Irregularity):
                raise TypeError(f"{c!r} is not an Irregularity")
            flat.extend(c.components if isinstance(c, IrregularitySum) else [c])
        self.components = flat

    def _parts(self):
        return [part for c in self.components for part in c._parts()]

    def __repr__(self):
        return " + ".join(repr(c) for c in self.components) or "IrregularitySum([])"


#: the knots and coefficients of a component without a sampled table (the compiled evaluation's placeholders)
EMPTY_KNOTS = np.zeros(0)
EMPTY_COEFS = np.zeros((0, 4))


@dataclass(frozen=True, repr=True)
class SpanDeflection(Irregularity):
    """Deflection of one span: ``δ sin(π (s - start)/L)`` on the span, 0 outside, C2 end transitions of
    length ``transition_length_m`` centred on the span ends (see the module docstring)."""

    span_length_m: float
    amplitude_m: float
    start_m: float = 0.0
    transition_length_m: float = 0.0
    direction: str = "lateral"

    def __post_init__(self):
        L = _finite("span_length_m", self.span_length_m, positive=True)
        _finite("amplitude_m", self.amplitude_m)
        _finite("start_m", self.start_m)
        lt = _finite("transition_length_m", self.transition_length_m, non_negative=True)
        if not lt < L:
            raise ValueError(f"transition_length_m = {lt} must be shorter than the span ({L} m)")
        _direction(self.direction)

    def _parts(self):
        row = [KIND_SPAN, _direction(self.direction), self.start_m, self.span_length_m, self.amplitude_m,
               self.transition_length_m, 0.0, 0.0]
        return [(row, EMPTY_KNOTS, EMPTY_COEFS)]

    @property
    def end_m(self) -> float:
        return self.start_m + self.span_length_m

    def joints_m(self) -> tuple[float, ...]:
        """Track distances where the pieces of the shape meet (transition ends, or the span ends if l_t = 0)."""
        h = 0.5 * self.transition_length_m
        if h == 0.0:
            return (self.start_m, self.end_m)
        return (self.start_m - h, self.start_m + h, self.end_m - h, self.end_m + h)


@dataclass(frozen=True)
class Harmonic(Irregularity):
    """``amplitude sin(2π s/wavelength + phase)`` along the whole track."""

    amplitude_m: float
    wavelength_m: float
    phase_rad: float = 0.0
    direction: str = "lateral"

    def __post_init__(self):
        _finite("amplitude_m", self.amplitude_m)
        _finite("wavelength_m", self.wavelength_m, positive=True)
        _finite("phase_rad", self.phase_rad)
        _direction(self.direction)

    def _parts(self):
        row = [KIND_HARMONIC, _direction(self.direction), self.amplitude_m, self.wavelength_m, self.phase_rad,
               0.0, 0.0, 0.0]
        return [(row, EMPTY_KNOTS, EMPTY_COEFS)]


class SampledIrregularity(Irregularity):
    """Sampled (measured) lateral and vertical irregularity, interpolated by cubic splines with zero end slopes
    (C2 inside the table, C1 at its ends), held constant outside the table.

    Parameters: ``s_m`` strictly increasing track distances (at least 2), ``y_m``, ``z_m`` the values."""

    def __init__(self, s_m, y_m, z_m, name: str = "table"):
        s, y, z = (np.asarray(a, dtype=float).reshape(-1) for a in (s_m, y_m, z_m))
        self.name = name
        if not (len(s) == len(y) == len(z)):
            raise ValueError(f"{name}: s, y and z have different lengths ({len(s)}, {len(y)}, {len(z)})")
        if len(s) < 2:
            raise ValueError(f"{name}: at least two samples are needed, got {len(s)}")
        if not (np.all(np.isfinite(s)) and np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
            raise ValueError(f"{name}: non-finite values in the table")
        if np.any(np.diff(s) <= 0.0):
            i = int(np.argmax(np.diff(s) <= 0.0))
            raise ValueError(f"{name}: s must increase strictly (row {i + 2}: {s[i]} -> {s[i + 1]})")
        self.s_m, self.y_m, self.z_m = s, y, z
        self._coefs = [CubicSpline(s, v, bc_type="clamped").c.T.copy() for v in (y, z)]  # (n-1, 4) each

    @classmethod
    def from_csv(cls, path) -> "SampledIrregularity":
        """Read a CSV file with the header columns ``s_m, y_m, z_m`` (further columns are ignored; lines starting
        with '#' are comments)."""
        path = Path(path)
        with open(path, newline="") as fh:
            lines = [line for line in fh if line.strip() and not line.lstrip().startswith("#")]
        reader = csv.DictReader(lines)
        need = ("s_m", "y_m", "z_m")
        header = [h.strip() for h in (reader.fieldnames or [])]
        for key in need:
            if key not in header:
                raise ValueError(f"{path}: missing column {key!r} (header: {header})")
        data = {k: [] for k in need}
        for i, row in enumerate(reader, start=2):
            row = {k.strip(): v for k, v in row.items() if k is not None}
            for key in need:
                try:
                    data[key].append(float(row[key]))
                except (TypeError, ValueError):
                    raise ValueError(f"{path}: data row {i}: column {key!r}: not a number: {row.get(key)!r}") from None
        return cls(data["s_m"], data["y_m"], data["z_m"], name=str(path))

    def _parts(self):
        n = len(self.s_m)
        return [([KIND_TABLE, LATERAL, 0, n, 0, 0.0, 0.0, 0.0], self.s_m, self._coefs[0]),
                ([KIND_TABLE, VERTICAL, 0, n, 0, 0.0, 0.0, 0.0], self.s_m, self._coefs[1])]

    def __repr__(self):
        return f"SampledIrregularity({self.name!r}, {len(self.s_m)} samples, s {self.s_m[0]}..{self.s_m[-1]} m)"


@dataclass
class RigidStraightTrack:
    """A rigid straight track displaced by ``irregularity`` at distance s: its centre line (y right, z down) and, per
    rail, the cross level and gauge deviation (:mod:`exudyn_wheelrail.conventions`).

    ``rail_offset(s)`` gives the centre line's displacement and its derivatives (all four channels:
    :func:`exudyn_wheelrail.track.irregularities.channel_values`); ``packed()`` the arrays for the compiled kernel
    (:func:`irregularity_channels_at`)."""

    irregularity: Irregularity = None

    def __post_init__(self):
        if self.irregularity is None:
            self.irregularity = NoIrregularity()
        self._packed = self.irregularity.packed()

    def packed(self) -> PackedIrregularity:
        return self._packed

    def rail_offset(self, s_m) -> IrregularityValues:
        return self.irregularity.evaluate(s_m)
