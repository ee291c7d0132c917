"""Checks of user input shared by the whole package: one function per kind of value, one message style.

Every check raises ``ValueError`` with a one-line message ``<name>: <problem>``, ``name`` being the argument, key or
command-line option the value came from, so that the command line can print it as ``error: <name>: <problem>``
(:mod:`exudyn_wheelrail.cli`).  A value that is plausible but unusual is not an error: :meth:`Quantity.check` then
issues an :class:`InputWarning` (printed by the command line as one line ``warning: ...``) and returns the value.

* :func:`finite` — a finite number;
* :func:`poisson_ratio`, :func:`youngs_modulus` — elastic constants (every module that takes them calls these);
* :class:`Quantity` — a physical quantity with its plausibility range, declared once beside the parameter it belongs
  to (e.g. the track gauge in :mod:`exudyn_wheelrail.contact.pair`); a value that fits the range only in another
  unit (millimetres for metres, ...) is reported with that hint;
* :func:`output_dir`, :func:`output_file` — a location the results can be written to, checked before any work;
* :func:`read_toml` — an input file in TOML (scenario, vehicle, consist, track file), its syntax errors reported as
  ``<path>: not valid TOML: ...`` in the caller's error class.
"""
from __future__ import annotations

import csv
import math
import os
import tomllib
import warnings
from dataclasses import dataclass
from pathlib import Path

__all__ = ["InputWarning", "finite", "poisson_ratio", "youngs_modulus", "POISSON_RATIO_RANGE", "Quantity",
           "output_dir", "output_file", "read_toml", "csv_rows"]


class InputWarning(UserWarning):
    """A plausible but unusual input: the computation goes on (the command line prints ``warning: <message>``)."""


def finite(name: str, value) -> float:
    """``float(value)``; ``ValueError`` naming ``name`` when it is not a number or not finite."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name}: {x!r} is not a finite number")
    return x


#: Poisson's ratio of an isotropic linear-elastic material: -1 < nu <= 0.5 (positive definite strain energy; 0.5
#: is the incompressible limit, which Kalker's tables include).
POISSON_RATIO_RANGE = (-1.0, 0.5)


def poisson_ratio(name: str, value) -> float:
    """A Poisson's ratio, ``-1 < nu <= 0.5`` (:data:`POISSON_RATIO_RANGE`); ``ValueError`` naming ``name`` else."""
    nu = finite(name, value)
    lo, hi = POISSON_RATIO_RANGE
    if not lo < nu <= hi:
        raise ValueError(f"{name}: {nu:g} is not a Poisson's ratio (an isotropic elastic material has "
                         f"{lo:g} < nu <= {hi:g}; steel 0.28)")
    return nu


def youngs_modulus(name: str, value) -> float:
    """A Young's modulus in Pa, finite and > 0; ``ValueError`` naming ``name`` else."""
    E = finite(name, value)
    if not E > 0.0:
        raise ValueError(f"{name}: {E:g} Pa is not a Young's modulus (must be > 0; steel 2.1e11 Pa)")
    return E


#: other units a value may evidently have been given in: (name, factor to the expected unit)
_OTHER_UNITS = {
    "m": (("millimetres", 1e-3),),
    "mm": (("metres", 1e3),),
    "s": (("milliseconds", 1e-3),),
    "N": (("kilonewtons", 1e3),),
    "kg": (("tonnes", 1e3),),
}
_UNIT_NAMES = {"m": "metres", "mm": "millimetres", "s": "seconds", "N": "newtons", "kg": "kilograms",
               "km/h": "km/h", "Pa": "pascals"}


@dataclass(frozen=True)
class Quantity:
    """A physical input with its plausibility range (SI unit ``unit``; ``""`` for a number without unit).

    ``lo``/``hi`` (``None``: unbounded) bound what is accepted: a value outside is an error, reported with the other
    unit it evidently was given in when it fits the range there (``1435`` for a gauge in metres: millimetres).
    ``typical`` = ``(lo, hi)`` is the usual range: a value outside it (but accepted) gives an :class:`InputWarning`.
    ``magnitude``: the ranges bound ``|value|`` (a signed quantity such as an irregularity amplitude).
    """

    what: str
    unit: str
    lo: float | None = None
    hi: float | None = None
    typical: tuple[float, float] | None = None
    magnitude: bool = False

    def _inside(self, x: float, lo, hi) -> bool:
        v = abs(x) if self.magnitude else x
        return (lo is None or v >= lo) and (hi is None or v <= hi)

    def _range_text(self, lo, hi) -> str:
        unit = f" {self.unit}" if self.unit else ""
        if self.magnitude:
            return f"|value| up to {hi:g}{unit}" if not lo else f"|value| {lo:g} to {hi:g}{unit}"
        if lo is not None and hi is not None:
            a, b = f"{lo:g}", f"{hi:g}"
            return f"{a}{'-' if lo >= 0 and 'e' not in a + b else ' to '}{b}{unit}"
        return f"up to {hi:g}{unit}" if hi is not None else f"at least {lo:g}{unit}"

    def _in_unit(self) -> str:
        name = _UNIT_NAMES.get(self.unit, self.unit)
        return f" in {name}" if name else ""

    def problem(self, value) -> str | None:
        """Why the finite number ``value`` is not accepted (one line, without the name), or None."""
        x = float(value)
        if self._inside(x, self.lo, self.hi):
            return None
        hint = ""
        for other, factor in _OTHER_UNITS.get(self.unit, ()):
            if self._inside(x * factor, self.lo, self.hi):
                hint = f"; {other} given? check the units"
                break
        return (f"{x:g} is not a plausible {self.what}{self._in_unit()} (expected about "
                f"{self._range_text(self.lo, self.hi)}{hint})")

    def unusual(self, value) -> str | None:
        """Why the accepted ``value`` is unusual (outside ``typical``), or None."""
        x = float(value)
        if self.typical is None or self._inside(x, *self.typical):
            return None
        hint = next((f"; {other} given?" for other, factor in _OTHER_UNITS.get(self.unit, ())
                     if self._inside(x * factor, *self.typical)), "")
        return (f"{x:g}{' ' + self.unit if self.unit else ''} is an unusual {self.what} (typical "
                f"{self._range_text(*self.typical)}{hint}); going on with it")

    def check(self, name: str, value, error: type[ValueError] = ValueError) -> float:
        """The value as a float: ``error('<name>: <problem>')`` if it is not finite or not plausible, an
        :class:`InputWarning` ``'<name>: ...'`` if it is unusual.  ``name`` may carry the source too
        (``'file.toml: track.0.amplitude_m'``); ``error`` is ``ValueError`` or a subclass."""
        try:
            x = finite(name, value)
        except ValueError as exc:
            raise error(str(exc)) from None
        problem = self.problem(x)
        if problem:
            raise error(f"{name}: {problem}")
        note = self.unusual(x)
        if note:
            warnings.warn(f"{name}: {note}", InputWarning, stacklevel=2)
        return x


def _existing_ancestor(p: Path) -> Path:
    a = p.parent
    while not a.exists() and a != a.parent:
        a = a.parent
    return a


def output_dir(name: str, path) -> Path:
    """A directory results can be written into (it exists, or can be created): ``ValueError`` naming ``name``
    otherwise.  Creates nothing."""
    p = Path(path).absolute()
    if p.exists():
        if not p.is_dir():
            raise ValueError(f"{name}: {path} is an existing file, not a directory")
        if not os.access(p, os.W_OK | os.X_OK):
            raise ValueError(f"{name}: cannot write into the directory {path} (permission denied)")
        return Path(path)
    a = _existing_ancestor(p)
    if not a.is_dir():
        raise ValueError(f"{name}: cannot create the directory {path}: {a} is a file, not a directory")
    if not os.access(a, os.W_OK | os.X_OK):
        raise ValueError(f"{name}: cannot create the directory {path}: {a} is not writable")
    return Path(path)


def output_file(name: str, path, suffixes: tuple[str, ...] | None = None, what: str = "file") -> Path:
    """A file that can be written: not a directory, its directory exists and is writable, its suffix one of
    ``suffixes`` (lower case, with the dot) when given.  ``ValueError`` naming ``name`` otherwise; creates nothing."""
    p = Path(path).absolute()
    if p.is_dir():
        raise ValueError(f"{name}: {path} is a directory; expected the {what} to write")
    if suffixes and p.suffix.lower() not in suffixes:
        raise ValueError(f"{name}: {path}: expected a {what} ending in {', '.join(suffixes)}")
    parent = p.parent
    if not parent.exists():
        a = _existing_ancestor(p)
        if not a.is_dir():
            raise ValueError(f"{name}: cannot write {path}: {a} is a file, not a directory")
        raise ValueError(f"{name}: cannot write {path}: the directory {parent} does not exist")
    if not parent.is_dir():
        raise ValueError(f"{name}: cannot write {path}: {parent} is a file, not a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ValueError(f"{name}: cannot write {path}: the directory {parent} is not writable")
    if p.exists() and not os.access(p, os.W_OK):
        raise ValueError(f"{name}: cannot write {path}: the file is read-only")
    return Path(path)


def read_toml(path, error=ValueError) -> dict:
    """The parsed TOML file ``path``; a syntax error raises ``error("<path>: not valid TOML: <detail>")``."""
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML: {exc}") from None


def csv_rows(path):
    """``(line number, cells)`` of every row of the CSV file ``path`` that holds something: cells stripped, blank rows
    and rows whose first cell starts with ``#`` (comments) left out, a spreadsheet's byte-order mark not part of the
    first name."""
    with open(path, newline="", encoding="utf-8-sig") as fh:
        for lineno, row in enumerate(csv.reader(fh), 1):
            cells = [c.strip() for c in row]
            if cells and any(cells) and not cells[0].startswith("#"):
                yield lineno, cells
