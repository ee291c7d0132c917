"""Front of the profile readers: :func:`load_profile` (read a point file and fit it) and the public names of the
reader modules, re-exported here so that ``exudyn_wheelrail.profiles.readers`` keeps its interface.

Sources
-------
* SIMPACK profile files, ``.prw`` (wheel) and ``.prr`` (rail): :func:`read_simpack_profile`
  (:mod:`~exudyn_wheelrail.profiles.simpack`).
* Plain two-column y-z tables as exported by profile gauges (comma, semicolon, tab or whitespace separated,
  optional header line, ``#`` comments): :func:`read_yz_table` (:mod:`~exudyn_wheelrail.profiles.table`).
* :func:`dense_from_points` fits a C2 parametric cubic spline to ordered points (interpolating, or smoothing
  measurement noise) and resamples it densely with exact derivatives (:mod:`~exudyn_wheelrail.profiles.fitting`);
  :func:`load_profile` does read + fit.
* :class:`ProfileError`, :func:`validate_profile_points` and the unit/extent checks:
  :mod:`~exudyn_wheelrail.profiles.validation`.

Frame and units of everything returned: the *profile frame* of :mod:`exudyn_wheelrail.conventions`, in **metres**
(``y`` lateral, positive towards the field side; ``z`` for a wheel the radius increase over the tape circle, for a
rail the depth below the top of the rail; points ordered from the gauge side to the field side).
"""
from __future__ import annotations

from pathlib import Path

from .dense import DenseProfile
from .fitting import (DEFAULT_GAUGE_NOISE_M, DEFAULT_SPACING_M, FITPACK_RESIDUAL_BANDS,  # noqa: F401
                      INTERPOLATION_MIN_SPACING_M, dense_from_points)
from .simpack import EXTENSION_KIND, read_simpack_profile
from .table import read_yz_table
from .validation import (DUPLICATE_TOL_M, FOLD_BACK_DEG, MIN_POINTS, PLAUSIBLE_EXTENT_M,  # noqa: F401
                         ProfileError, check_profile_kind, profile_shape, validate_profile_points)

__all__ = [
    "ProfileError",
    "read_simpack_profile",
    "read_yz_table",
    "dense_from_points",
    "load_profile",
    "validate_profile_points",
    "profile_shape",
    "check_profile_kind",
    "MIN_POINTS",
    "DUPLICATE_TOL_M",
    "PLAUSIBLE_EXTENT_M",
    "DEFAULT_GAUGE_NOISE_M",
    "DEFAULT_SPACING_M",
]


def load_profile(path, kind: str | None = None, *, smoothing: float | None = None, name: str | None = None,
                 spacing: float = DEFAULT_SPACING_M, **reader_kw) -> DenseProfile:
    """Read a profile file and fit it: ``.prw``/``.prr`` -> :func:`read_simpack_profile`, anything else ->
    :func:`read_yz_table` (``reader_kw``: ``units``, ``columns``, ``mirror_y``, ``mirror_z``, ``check_geometry``).

    ``smoothing=None`` uses the file's nature: a SIMPACK file with ``approx.smooth = 0`` holds exact points and is
    interpolated (``smoothing=0``); a SIMPACK file with ``approx.smooth > 0`` and a table are treated as
    measurements with the default gauge noise (:data:`DEFAULT_GAUGE_NOISE_M`).  SIMPACK's ``approx.smooth`` value
    itself is not translated (its scale is SIMPACK's own).  ``name`` defaults to the file stem.  A file whose content
    is a SIMPACK profile (a ``point.begin`` line) is read as one whatever its extension.

    A profile requested as ``kind`` (or declared one by its SIMPACK header or extension) that looks like the other
    kind raises :class:`ProfileError` (:func:`~exudyn_wheelrail.profiles.validation.check_profile_kind`).
    """
    path = Path(path)
    if path.suffix.lower() in EXTENSION_KIND or _looks_like_simpack(path):
        if reader_kw:
            raise TypeError(f"read_simpack_profile takes no options {sorted(reader_kw)}")
        y, z, meta = read_simpack_profile(path, kind=kind)
        if smoothing is None:
            smoothing = 0.0 if not meta.get("approx_smooth") else DEFAULT_GAUGE_NOISE_M
    else:
        y, z, meta = read_yz_table(path, kind=kind, **reader_kw)
    check_profile_kind(y, z, kind or meta.get("kind"), str(path))
    return dense_from_points(y, z, smoothing=smoothing, name=name or path.stem, spacing=spacing, validate=False)


def _looks_like_simpack(path: Path) -> bool:
    """A file with another extension whose content is a SIMPACK profile (it has a ``point.begin`` line)."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(1 << 20)
    except OSError:
        return False          # the table reader reports the file
    return any(line.split(b"!", 1)[0].strip().lower() == b"point.begin" for line in head.splitlines())
