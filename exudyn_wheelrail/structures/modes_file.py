r"""A bridge from any finite-element program: its modes read from a file (:func:`read_modes_file`) and entered as
the deck's modal basis (:class:`SampledModes`, a :class:`~.modal_basis.ModalBasis`).

The file
--------
Per mode ``j`` (n modes) and track position ``x_i`` (k positions, deck coordinate: the distance along the track from
the first abutment [m]):

==================  ======  ===============================================================================
key                 shape   meaning
==================  ======  ===============================================================================
``frequency_hz``    (n,)    natural frequency [Hz], > 0
``modal_mass_kg``   (n,)    modal mass ``φ_jᵀ M φ_j`` of the shape **as given** [kg], > 0
``x_m``             (k,)    positions along the track axis [m], increasing (a position given twice is a joint
                            between two separate decks: the first value ends the deck before, the second starts
                            the next)
``vertical``        (n, k)  vertical displacement of the track axis [m], **positive downward**
``lateral``         (n, k)  optional: lateral displacement of the track axis [m], positive to the right
``torsion``         (n, k)  optional: rotation of the deck about the track axis [rad] (right-hand about the
                            running direction: the right rail goes down)
``damping_ratio``   (n,)    optional: modal damping ratio (0 ≤ ζ < 1)
==================  ======  ===============================================================================

**NPZ** (``numpy.savez``) with these keys, or **CSV** for an exported table: a header line and one row per mode and
position with the columns ``mode, frequency_hz, modal_mass_kg, x_m, vertical`` (and optionally ``lateral``,
``torsion``, ``damping_ratio``); ``mode`` numbers the modes (any integers, in the order of the file), every mode
has the same positions, its ``frequency_hz``, ``modal_mass_kg`` and ``damping_ratio`` are the same on all its rows;
lines starting with ``#`` are comments.  Any other key or column is an error (a misspelt optional key would be lost
silently).  A problem is one line ``ValueError`` ``"<file>: <key>: <problem>"``; a plausible slip (a mode whose
shape is zero, positions that do not cover the deck) an :class:`~exudyn_wheelrail.validation.InputWarning`.

The deck it gives
-----------------
The frames are the bridge's (:mod:`.bridge`: x along the track, y right, z down).  The shapes are mass-normalised
with the given modal masses, ``φ̂_j = φ_j/√(m_j)``, so the modal equations are those of every deck
(:mod:`.modal_basis`).  Between the positions the vertical and lateral shapes are **cubic splines** (their values and
spline slopes at the positions are the nodes of the :class:`~.modal_shapes.ShapeTable`, whose cubic Hermite
interpolation then reproduces the spline), one spline per stretch between supports ("not-a-knot" ends: a bending
shape has a kink in its curvature over a support of a continuous deck, and a kink in its slope at a joint); the
torsion is linear between positions.  The rails are at the track axis (rail height 0: the file gives the track
axis's motion).  Off the positions the shapes are zero.

**Mass bounds** (EN 1991-2 §6.4.6.3.2): the deck mass scaled by ``r`` (``mass_scale``) with the same stiffness and
shapes has ``ω_j/√r`` and modal masses ``r m_j`` — exact when the whole mass scales (the usual bounds of a deck's
density and its ballast), stated where used.

**Kinds**: a mode is ``vertical``, ``lateral`` or ``torsion`` by the largest root-mean-square of its vertical and
lateral displacement and of its torsion times half the rail-centre distance (the rails' vertical motion by it,
:data:`~exudyn_wheelrail.conventions.RAIL_CENTRE_DISTANCE_M`).
"""
from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline

from ..conventions import RAIL_CENTRE_DISTANCE_M
from ..validation import InputWarning, csv_rows
from .modal_basis import ModalBasis
from .modal_shapes import NS_DV, NS_DW, NS_TH, NS_V, NS_W, ShapeTable

__all__ = ["MODES_FILE_REQUIRED", "MODES_FILE_OPTIONAL", "MODES_FILE_SUFFIXES", "ModesFileData", "read_modes_file",
           "SampledModes", "half_waves", "mode_kinds", "write_modes_npz", "SUPPORT_MATCH_M"]

#: the keys (NPZ) and columns (CSV) of a modes file
MODES_FILE_REQUIRED = ("frequency_hz", "modal_mass_kg", "x_m", "vertical")
MODES_FILE_OPTIONAL = ("lateral", "torsion", "damping_ratio")
MODES_FILE_SUFFIXES = (".npz", ".csv")
#: a value of a mode's shape below this fraction of its largest is a zero (sign changes, :func:`half_waves`)
_ZERO_FRACTION = 1e-6
#: a support matches a position within this fraction of its distance (at least 1 m): the rounding of the spans' sum
SUPPORT_MATCH_M = 1e-9


@dataclass(frozen=True, eq=False)
class ModesFileData:
    """The checked contents of a modes file (module docstring); ``lateral``, ``torsion`` and ``damping_ratio``
    None when not given."""

    source: str
    frequency_hz: np.ndarray
    modal_mass_kg: np.ndarray
    x_m: np.ndarray
    vertical: np.ndarray
    lateral: np.ndarray | None
    torsion: np.ndarray | None
    damping_ratio: np.ndarray | None

    @property
    def n_modes(self) -> int:
        return self.frequency_hz.shape[0]

    def lowest(self, n: int) -> "ModesFileData":
        """The ``n`` modes of lowest frequency (their order in the file kept among equal frequencies)."""
        keep = np.sort(np.argsort(self.frequency_hz, kind="stable")[:int(n)])
        pick = (lambda a: None if a is None else a[keep])
        return ModesFileData(self.source, self.frequency_hz[keep], self.modal_mass_kg[keep], self.x_m,
                             self.vertical[keep], pick(self.lateral), pick(self.torsion), pick(self.damping_ratio))


def read_modes_file(path) -> ModesFileData:
    """The modes of ``path`` (NPZ or CSV, module docstring), checked; read once per file version (the file's path,
    modification time and size)."""
    p = Path(path)
    try:
        st = os.stat(p)
    except OSError as exc:
        raise ValueError(f"{p}: cannot read the modes file ({exc.strerror or exc})") from None
    return _read_cached(str(p.resolve()), st.st_mtime_ns, st.st_size, str(path))


@lru_cache(maxsize=16)
def _read_cached(resolved: str, mtime_ns: int, size: int, shown: str) -> ModesFileData:
    suffix = Path(resolved).suffix.lower()
    if suffix == ".npz":
        raw = _read_npz(resolved, shown)
    elif suffix == ".csv":
        raw = _read_csv(resolved, shown)
    else:
        raise ValueError(f"{shown}: a modes file is {' or '.join(MODES_FILE_SUFFIXES)}, not "
                         f"{suffix or 'without a suffix'}")
    return _checked(raw, shown)


def _read_npz(path, shown) -> dict:
    try:
        with np.load(path, allow_pickle=False) as z:
            raw = {k: np.asarray(z[k]) for k in z.files}
    except (OSError, ValueError) as exc:
        raise ValueError(f"{shown}: not a readable NPZ file ({exc})") from None
    return raw


def _read_csv(path, shown) -> dict:
    allowed = ("mode",) + MODES_FILE_REQUIRED + MODES_FILE_OPTIONAL
    header, rows = None, []
    for lineno, cells in csv_rows(path):
        if header is None:
            header = cells
            if "" in header:
                raise ValueError(f"{shown}:{lineno}: an empty column name (a trailing comma?)")
            for c in header:
                if c not in allowed:
                    raise ValueError(f"{shown}:{lineno}: {c}: unknown column (expected {', '.join(allowed)})")
            for c in ("mode",) + MODES_FILE_REQUIRED:
                if c not in header:
                    raise ValueError(f"{shown}:{lineno}: {c}: missing column (expected {', '.join(allowed)})")
            continue
        if len(cells) != len(header):
            raise ValueError(f"{shown}:{lineno}: {len(cells)} cells, the header has {len(header)}")
        vals = []
        for c, text in zip(header, cells):
            try:
                vals.append(float(text))
            except ValueError:
                raise ValueError(f"{shown}:{lineno}: {c}: {text!r} is not a number") from None
        rows.append((lineno, vals))
    if header is None or not rows:
        raise ValueError(f"{shown}: no modes (expected a header line with {', '.join(('mode',) + MODES_FILE_REQUIRED)} "
                         "and one line per mode and position)")
    col = {c: i for i, c in enumerate(header)}
    order, by_mode = [], {}
    for lineno, vals in rows:
        m = vals[col["mode"]]
        if m not in by_mode:
            order.append(m)
            by_mode[m] = []
        by_mode[m].append((lineno, vals))
    x0 = [v[col["x_m"]] for _, v in by_mode[order[0]]]
    raw = {"x_m": np.array(x0)}
    for m in order:
        xs = [v[col["x_m"]] for _, v in by_mode[m]]
        if xs != x0:
            raise ValueError(f"{shown}:{by_mode[m][0][0]}: x_m: mode {m:g} has other positions than mode "
                             f"{order[0]:g} (every mode needs the same positions, in the same order)")
    for c in ("frequency_hz", "modal_mass_kg", "damping_ratio"):
        if c not in col:
            continue
        per_mode = []
        for m in order:
            v = {vals[col[c]] for _, vals in by_mode[m]}
            if len(v) != 1:
                raise ValueError(f"{shown}:{by_mode[m][0][0]}: {c}: mode {m:g} has {len(v)} different values (one per "
                                 "mode)")
            per_mode.append(v.pop())
        raw[c] = np.array(per_mode)
    for c in ("vertical", "lateral", "torsion"):
        if c in col:
            raw[c] = np.array([[vals[col[c]] for _, vals in by_mode[m]] for m in order])
    return raw


def _checked(raw: dict, shown: str) -> ModesFileData:
    def bad(key, problem):
        return ValueError(f"{shown}: {key}: {problem}")
    unknown = sorted(set(raw) - set(MODES_FILE_REQUIRED) - set(MODES_FILE_OPTIONAL))
    if unknown:
        raise bad(unknown[0], f"unknown key (expected {', '.join(MODES_FILE_REQUIRED + MODES_FILE_OPTIONAL)})")
    for key in MODES_FILE_REQUIRED:
        if key not in raw:
            raise bad(key, "missing")
    out = {}
    for key in MODES_FILE_REQUIRED + MODES_FILE_OPTIONAL:
        if key not in raw:
            continue
        try:
            a = np.array(raw[key], dtype=float)
        except (TypeError, ValueError):
            raise bad(key, "not numbers") from None
        if not np.all(np.isfinite(a)):
            raise bad(key, "holds a value that is not a finite number")
        out[key] = a
    f, x = out["frequency_hz"], out["x_m"]
    if f.ndim != 1 or f.size < 1:
        raise bad("frequency_hz", f"shape {f.shape}: expected one frequency per mode (n,)")
    n = f.size
    if np.any(f <= 0.0):
        raise bad("frequency_hz", f"{f[f <= 0.0][0]:g}: a natural frequency must be > 0 Hz")
    if x.ndim != 1 or x.size < 2:
        raise bad("x_m", f"shape {x.shape}: expected at least two positions along the track (k,)")
    dx = np.diff(x)
    if np.any(dx < 0.0):
        raise bad("x_m", f"{x[1:][dx < 0.0][0]:g} after {x[:-1][dx < 0.0][0]:g}: the positions must increase")
    if np.any((dx[1:] == 0.0) & (dx[:-1] == 0.0)):
        raise bad("x_m", "a position given three times (at most twice: a joint between two decks)")
    if dx[0] == 0.0 or dx[-1] == 0.0:
        raise bad("x_m", f"{x[0] if dx[0] == 0.0 else x[-1]:g} given twice at an end (a position given twice is a "
                         "joint between two decks: it needs positions on both sides)")
    for key in ("modal_mass_kg", "damping_ratio"):
        if key in out and out[key].shape != (n,):
            raise bad(key, f"shape {out[key].shape}: expected one value per mode ({n},), as frequency_hz")
    m = out["modal_mass_kg"]
    if np.any(m <= 0.0):
        raise bad("modal_mass_kg", f"{m[m <= 0.0][0]:g}: a modal mass must be > 0 kg")
    z = out.get("damping_ratio")
    if z is not None and np.any((z < 0.0) | (z >= 1.0)):
        raise bad("damping_ratio", f"{z[(z < 0.0) | (z >= 1.0)][0]:g}: expected 0 <= ζ < 1 (a ratio: 2 % is 0.02)")
    for key in ("vertical", "lateral", "torsion"):
        if key in out and out[key].shape != (n, x.size):
            raise bad(key, f"shape {out[key].shape} disagrees with {n} modes (frequency_hz) x {x.size} positions "
                           f"(x_m): expected ({n}, {x.size})")
    shapes = sum(np.abs(out[k]) for k in ("vertical", "lateral", "torsion") if k in out)
    zero = np.flatnonzero(np.max(shapes, axis=1) == 0.0)
    if zero.size:
        warnings.warn(f"{shown}: mode {zero[0] + 1} ({f[zero[0]]:g} Hz) has a zero shape: it carries no load",
                      InputWarning, stacklevel=3)
    for a in out.values():
        a.setflags(write=False)                          # shared by every caller of the cached reading
    return ModesFileData(shown, f, m, x, out["vertical"], out.get("lateral"), out.get("torsion"), z)


def write_modes_npz(path, *, frequency_hz, modal_mass_kg, x_m, vertical, lateral=None, torsion=None,
                    damping_ratio=None) -> Path:
    """Write a modes file (NPZ, module docstring) — for exporting a deck's modes and for tests."""
    data = {"frequency_hz": frequency_hz, "modal_mass_kg": modal_mass_kg, "x_m": x_m, "vertical": vertical}
    for k, v in (("lateral", lateral), ("torsion", torsion), ("damping_ratio", damping_ratio)):
        if v is not None:
            data[k] = v
    p = Path(path)
    with p.open("wb") as fh:
        np.savez(fh, **{k: np.asarray(v, dtype=float) for k, v in data.items()})
    return p


def half_waves(data: ModesFileData, supports_x_m=()) -> int:
    """The largest number of half-waves of a vertical or lateral shape along one stretch between supports (sign
    changes + 1): the spatial resolution a moving load needs on a span."""
    most = 1
    segs = _segments(data.x_m, supports_x_m, data.source, warn=False)
    for key in ("vertical", "lateral"):
        a = getattr(data, key)
        if a is None:
            continue
        for row in a:
            big = np.max(np.abs(row))
            if big == 0.0:
                continue
            for lo, hi in segs:
                part = row[lo:hi]
                s = np.sign(part[np.abs(part) > _ZERO_FRACTION * big])
                most = max(most, int(np.count_nonzero(s[1:] != s[:-1])) + 1)
    return most


def mode_kinds(data: ModesFileData) -> tuple:
    """The kind of every mode (module docstring, *Kinds*): ``vertical``, ``lateral`` or ``torsion``."""
    rms = np.zeros((3, data.n_modes))
    for i, (key, arm) in enumerate((("vertical", 1.0), ("lateral", 1.0), ("torsion", 0.5 * RAIL_CENTRE_DISTANCE_M))):
        a = getattr(data, key)
        if a is not None:
            rms[i] = arm * np.sqrt(np.mean(a * a, axis=1))
    return tuple(("vertical", "lateral", "torsion")[i] for i in np.argmax(rms, axis=0))


def _segments(x, supports_x_m, source="", warn=True) -> list:
    """Index ranges ``[a, b)`` of the positions between consecutive supports and joints (a position given twice):
    each one spline."""
    x = np.asarray(x)
    cuts = {0, x.size}
    for i in np.flatnonzero(np.diff(x) == 0.0):
        cuts.add(int(i) + 1)                             # a joint: the second of the two starts the next stretch
    segs = []
    bounds = sorted(cuts)
    for a, b in zip(bounds[:-1], bounds[1:]):
        inner = [float(s) for s in supports_x_m if x[a] < s < x[b - 1]]
        start = a
        for s in inner:                                  # a support inside a stretch: split there (shared position)
            j = a + int(np.argmin(np.abs(x[a:b] - s)))
            if abs(x[j] - s) <= SUPPORT_MATCH_M * max(1.0, abs(s)):
                segs.append((start, j + 1))
                start = j
            elif warn:
                warnings.warn(f"{source}: x_m: the support at {s:g} m is not one of the positions: the spline of the "
                              "shapes runs across it (give the shapes at the supports)", InputWarning, stacklevel=4)
        segs.append((start, b))
    return segs


def _spline_slopes(x, values):
    """Values (n, k) and their cubic-spline slopes at ``x`` (k,): not-a-knot, linear for two points."""
    if x.size == 2:
        slope = (values[:, 1] - values[:, 0]) / (x[1] - x[0])
        return np.repeat(slope[:, None], 2, axis=1)
    return CubicSpline(x, values, axis=1, bc_type="not-a-knot")(x, 1)


class SampledModes(ModalBasis):
    """The modes of a :class:`ModesFileData` as a deck (module docstring).

    start_m : track distance of the first abutment (deck coordinate x = s - start_m).
    supports_x_m : deck coordinates of the supports, where the splines break (the ends and joints need not be given).
    mass_scale : the deck mass over the mass the file's modes were computed with (mass bounds).
    damping_ratio : one ratio for every mode; None: the file's ``damping_ratio`` (an error if it has none).
    """

    def __init__(self, data: ModesFileData, *, start_m: float = 0.0, supports_x_m=(), mass_scale: float = 1.0,
                 damping_ratio: float | None = None):
        r = float(mass_scale)
        if not (math.isfinite(r) and r > 0.0):
            raise ValueError(f"mass_scale={mass_scale!r}: expected a number > 0")
        if damping_ratio is None:
            if data.damping_ratio is None:
                raise ValueError(f"{data.source}: damping_ratio: the file has none: give the deck's damping ratio")
            zeta = data.damping_ratio
        else:
            zeta = float(damping_ratio)
        self.data = data
        self.mass_scale = r
        x = data.x_m
        scale = 1.0 / np.sqrt(r * data.modal_mass_kg)                     # mass normalisation
        n, k = data.n_modes, x.size
        rows = {NS_W: (data.vertical, NS_DW), NS_V: (data.lateral, NS_DV)}
        segs = _segments(x, supports_x_m, data.source)
        n_nodes = sum(b - a for a, b in segs)
        node_shapes = np.zeros((n_nodes, 5, n))
        elem_x0, elem_len, elem_nodes = [], [], []
        node = 0
        for a, b in segs:
            xs = x[a:b]
            for row, (vals, drow) in rows.items():
                if vals is None:
                    continue
                v = vals[:, a:b] * scale[:, None]
                node_shapes[node:node + b - a, row] = v.T
                node_shapes[node:node + b - a, drow] = _spline_slopes(xs, v).T
            if data.torsion is not None:
                node_shapes[node:node + b - a, NS_TH] = (data.torsion[:, a:b] * scale[:, None]).T
            for i in range(b - a - 1):
                if xs[i + 1] > xs[i]:
                    elem_x0.append(xs[i])
                    elem_len.append(xs[i + 1] - xs[i])
                    elem_nodes.append((node + i, node + i + 1))
            node += b - a
        table = ShapeTable(float(start_m), 0.0, np.array(elem_x0), np.array(elem_len),
                           np.array(elem_nodes, dtype=np.int64).reshape(-1, 2), np.ascontiguousarray(node_shapes))
        kinds = mode_kinds(data)
        omega = 2.0 * math.pi * data.frequency_hz / math.sqrt(r)
        super().__init__(omega, zeta, kinds, table)
        if k and (x[0] > 0.0 or (len(supports_x_m) and x[-1] < max(supports_x_m))):
            hi = max(supports_x_m) if len(supports_x_m) else x[-1]
            warnings.warn(f"{data.source}: x_m: the positions cover {x[0]:g} ... {x[-1]:g} m of the deck 0 ... "
                          f"{hi:g} m: the shapes are zero outside them", InputWarning, stacklevel=2)
