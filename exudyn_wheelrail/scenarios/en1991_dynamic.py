"""The dynamic check of a railway bridge to EN 1991-2 §6.4.6 in one procedure: every train at every speed at the
lower and upper bound of the deck mass, the deck acceleration against EN 1990 A2, the dynamic enhancement.

``python -m exudyn_wheelrail en1991-dynamic --bridge FILE.toml --max-line-speed-kmh V [--trains ...]
[--speeds-kmh ...] [--workers N] --out DIR``.  The bridge file (:func:`read_bridge_file`)::

    [bridge]
    spans_m = [20.0]                  # the spans between supports, in running order
    EI_Nm2 = 1.2e10                   # the built-in beam deck (the spans' common bending stiffness) ...
    continuous = false                #   true: one deck continuous over the intermediate supports
    # modes_file = "deck_modes.npz"   # ... or the modes of an FE program (NPZ or CSV, relative to this file)
    # modes_mass_kg_per_m = 14500     #   the deck mass the file's modes were computed with (for the bounds)
    mass_kg_per_m = [13000, 16000]    # a number, or [lower, upper]: the two bounds of §6.4.6.3.2
    structure = "prestressed_concrete"   # the damping of Table 6.6 for the span (damping_ratio overrides it)
    track_form = "ballasted"          # the EN 1990 A2.4.4.2.1 limit: 3.5 m/s² ballasted, 5 m/s² direct fastening
    additional_damping = false        # true: + Δζ of §6.4.6.3.1(3), Eq. (6.13), for spans below 30 m

The procedure (each choice with its clause):

* **Trains** (§6.4.6.1.1): the ten universal trains HSLM-A1…A10 (Table 6.3), or those named, or consist files
  (their static axle loads, :func:`~.bridge_crossing_loads.consist_axles`); each as moving axle loads
  (§6.4.6.1.1(6): the moving-load model; the crossings are :func:`~.bridge_crossing_run.run_bridge_crossing`'s).
* **Speeds** (§6.4.6.2(1)): from 40 m/s (144 km/h) to 1.2 × the maximum line speed in steps of at most
  :data:`SPEED_STEP_KM_H`, plus, around every resonance speed ``v_i = f1 d / i`` (i = 1…4, d the train's
  characteristic spacing, f1 that of the mass bound) within the range, the speeds ``v_i ± k`` :data:`REFINE_KM_H`
  (k = 0…2): a resonance peak is not missed between two grid speeds.  All speeds exact decimals (0.1 km/h).
* **Mass** (§6.4.6.3.2): a ``[lower, upper]`` pair runs both — the lower bound gives the highest accelerations,
  the upper the lowest resonance speeds; a single value is ``nominal``.
* **Damping** (§6.4.6.3.1, Table 6.6): the lower limit ζ of the structure type for the span, optionally plus Δζ
  (Eq. 6.13, L < 30 m); for a chain the smallest over its spans (one ratio for every mode: on the safe side); an
  explicit ``damping_ratio`` replaces it.
* **Modes** (EN 1990 A2.4.4.2.1(4)P): every span's vertical modes up to the first at or above ``max(30 Hz, 1.5 f1,
  f3)`` (f3 = 9 f1 of a simply supported span; the largest over the spans; :func:`~.deck.en1990_cutoff_Hz`), at
  least 3 — the bridge crossing's own check of the cut-off.  A continuous deck: its ``N K`` lowest vertical modes
  with the smallest ``N ≥ 3`` that reaches its cut-off (f1, f3 its own first and third vertical modes).  A modes
  file (:mod:`~exudyn_wheelrail.structures.modes_file`): its modes up to the first vertical one at or above the
  cut-off (all of them, with a warning, when none is); for the mass bounds its modes are scaled from
  ``modes_mass_kg_per_m`` (every mass scaled, the stiffness kept: ``ω/√r``), and its ``damping_ratio`` column is not
  used: the check's damping is Table 6.6's (or the given ``damping_ratio``).
* **Verdict**: the largest deck acceleration over the deck's points, every run and speed (modes up to the cut-off:
  ``deck.en1990_peak_acceleration_m_s2``), against the limit of the track form; ``fail`` also when any crossing
  did not complete (its status in the envelope, never dropped).  The dynamic enhancement: the largest mid-span
  displacement against the static one under the same train (a single span; the static one of a continuous deck
  or a modes file is that of its modes kept, :class:`~.bridge_crossing_probes.FirstAxleProbe`).

Scale and faults: the crossings run in parallel through the sweeps' executors (:func:`~.sweep.run_tasks`: a dead
worker costs only time); every finished crossing is written at once to ``DIR/runs/`` with its fingerprint (its whole
case and the package's code, :func:`run_fingerprint`), and a run started again on the same ``DIR`` takes those whose
fingerprint matches instead of computing them again (a killed run resumes where it stopped; a changed bridge, train
or code is computed anew; a crossing lost with its worker is tried again).

Outputs: ``DIR/summary.json`` (:func:`check_summary`), ``DIR/envelope.csv`` (:data:`ENVELOPE_COLUMNS`, one row per
crossing), ``DIR/envelope.png`` (the deck acceleration against speed, per mass bound, a line per train, the
resonance speeds marked and the limit drawn), ``DIR/report.html`` (:mod:`.en1991_report`: self-contained, the
figures embedded).
"""
from __future__ import annotations

import hashlib
import json
import math
import tomllib
import warnings
from dataclasses import dataclass, field
from decimal import Decimal
from pathlib import Path

import numpy as np

from ..conventions import speed_km_h
from ..jit import package_source_digest
from ..simulation.status import OK
from ..structures.beam import DeckSection
from ..standards import (EN1990_DECK_ACCELERATION_LIMITS_M_S2, EN1991_ADDITIONAL_DAMPING_MAX_SPAN_M,
                         EN1991_DAMPING_PERCENT, HSLM_NAMES, TRACK_FORMS)
from ..structures.load_models import hslm_a, resonance_speeds_m_s
from ..structures.modes_file import MODES_FILE_SUFFIXES
from ..validation import InputWarning
from .bridge_crossing_case import BridgeCrossing
from .bridge_crossing_deck import deck_modes, file_modes_to_cutoff
from .bridge_crossing_loads import consist_axles
from .bridge_crossing_run import run_bridge_crossing
from .deck import en1990_cutoff_Hz
from .defaults import (CHECK_MIN_SPEED_KM_H, CHECK_REFINE_KM_H, CHECK_RESONANCES, CHECK_SPEED_STEP_KM_H, MAX_MODES,
                       LATERAL_EI_RATIO)
from .en1991_report import write_figures_and_report
from .outputs import write_json, write_table_csv
from .sweep import EXECUTOR_ERROR, run_tasks

__all__ = ["BridgeSpec", "read_bridge_file", "damping_ratio_table_6_6", "additional_damping_ratio", "n_modes_to_cutoff",
           "first_frequency_Hz", "speed_grid_kmh", "DynamicCheck", "run_dynamic_check", "check_summary",
           "run_fingerprint", "section", "N_RESONANCES", "ENVELOPE_COLUMNS", "SPEED_STEP_KM_H", "REFINE_KM_H",
           "MIN_SPEED_KM_H", "STRUCTURES"]

#: §6.4.6.2(1): the lowest speed of the check [km/h] (40 m/s); the largest step of the speed grid [km/h]; the step
#: of the refinement around a resonance speed [km/h]; the resonance speeds f1 d / i refined around (i = 1 ... N)
MIN_SPEED_KM_H = CHECK_MIN_SPEED_KM_H
SPEED_STEP_KM_H = CHECK_SPEED_STEP_KM_H
REFINE_KM_H = CHECK_REFINE_KM_H
N_RESONANCES = CHECK_RESONANCES
#: the structure types of Table 6.6 (the bridge file's ``structure``)
STRUCTURES = tuple(EN1991_DAMPING_PERCENT)
#: the columns of envelope.csv
ENVELOPE_COLUMNS = ("train", "mass_bound", "speed_kmh", "status", "max_deck_acceleration_m_s2",
                    "max_deck_displacement_m", "dynamic_enhancement", "steps", "solve_seconds")
MASS_BOUNDS = ("lower", "upper")


def damping_ratio_table_6_6(structure: str, span_m: float) -> float:
    """EN 1991-2:2003 Table 6.6: the lower limit of the damping ratio (a ratio, not %) of ``structure`` for a span
    of ``span_m``: ``ζ = ζ_20 + s (20 - L)`` below 20 m, ``ζ_20`` from 20 m."""
    if structure not in EN1991_DAMPING_PERCENT:
        raise ValueError(f"structure: {structure!r}: expected one of {', '.join(STRUCTURES)}")
    z20, slope = EN1991_DAMPING_PERCENT[structure]
    return 0.01 * (z20 + slope * max(0.0, 20.0 - float(span_m)))


def additional_damping_ratio(span_m: float) -> float:
    """EN 1991-2:2003 §6.4.6.3.1(3), Eq. (6.13): ``Δζ = (0.0187 L - 0.00064 L²) / (1 - 0.0147 L + 0.0000931 L²)``
    [%] for L < 30 m (zero from 30 m), as a ratio."""
    L = float(span_m)
    if L >= EN1991_ADDITIONAL_DAMPING_MAX_SPAN_M:
        return 0.0
    return 0.01 * (0.0187 * L - 0.00064 * L * L) / (1.0 - 0.0147 * L + 0.0000931 * L * L)


def section(EI_Nm2: float, mass_kg_m: float) -> DeckSection:
    """The beam deck's section (bending only; the lateral stiffness as the crossing's default)."""
    return DeckSection.bending_only(mass_kg_m, EI_Nm2, LATERAL_EI_RATIO * EI_Nm2)


def first_frequency_Hz(span_m: float, EI_Nm2: float, mass_kg_m: float) -> float:
    """First bending frequency of a simply supported span, ``f1 = π/(2 L²) √(EI/m)``."""
    return section(EI_Nm2, mass_kg_m).vertical_frequency_Hz(span_m)


def n_modes_to_cutoff(spans_m, EI_Nm2: float, mass_kg_m: float) -> int:
    """Vertical modes per span up to EN 1990's cut-off (:func:`~.deck.en1990_cutoff_Hz`: max(30 Hz, 1.5 f1, f3),
    the largest over the spans): every span's modes ``n² f1`` up to the first at or above it (the bridge
    crossing's own check of the cut-off), at least 3."""
    sec = section(EI_Nm2, mass_kg_m)
    cutoff = en1990_cutoff_Hz(spans_m, sec)
    return max(3, max(math.ceil(math.sqrt(cutoff / sec.vertical_frequency_Hz(L)) - 1e-9) for L in spans_m))


def speed_grid_kmh(max_line_speed_kmh: float, resonances_kmh=()) -> list[float]:
    """The speeds [km/h] of one train and mass bound (module docstring): 144, the multiples of 10 km/h above it and
    1.2 V (steps of at most 10 km/h), and ``v_i ± k 2.5`` (k = 0…2) around each resonance speed inside; exact
    decimals of 0.1 km/h."""
    hi = Decimal(repr(1.2 * max_line_speed_kmh)).quantize(Decimal("0.1"))
    lo = Decimal(repr(MIN_SPEED_KM_H))
    if hi < lo:
        raise ValueError(f"--max-line-speed-kmh: {max_line_speed_kmh:g}: 1.2 V is below {MIN_SPEED_KM_H:g} km/h, "
                         "the check's lowest speed (EN 1991-2 6.4.6.2)")
    step = Decimal(repr(SPEED_STEP_KM_H))
    speeds = {lo, hi} | {k * step for k in range(int(lo // step) + 1, int(hi // step) + 1) if lo < k * step < hi}
    for v in resonances_kmh:
        v = Decimal(repr(float(v))).quantize(Decimal("0.1"))
        for k in (-2, -1, 0, 1, 2):
            w = v + k * Decimal(repr(REFINE_KM_H))
            if lo <= w <= hi:
                speeds.add(w)
    return [float(v) for v in sorted(speeds)]


@dataclass(frozen=True)
class BridgeSpec:
    """The bridge of a check (:func:`read_bridge_file`): the built-in beam (``EI_Nm2``, ``continuous``) or a modes
    file (``modes_file``, its ``modes_mass_kg_per_m``); ``masses``: mass bound -> mass per length [kg/m]
    (``{"lower", "upper"}`` or ``{"nominal"}``; a modes file's nominal may be None: the file's own)."""

    spans_m: tuple
    EI_Nm2: float | None
    masses: dict
    structure: str | None
    damping_ratio: float | None
    additional_damping: bool
    track_form: str
    source: str = ""
    continuous: bool = False
    modes_file: str | None = None
    modes_mass_kg_per_m: float | None = None

    def mass_scale(self, bound: str) -> float:
        """A modes file's mass scale at ``bound``: the bound's mass over the file's (1 without a mass)."""
        m = self.masses[bound]
        return 1.0 if m is None or self.modes_mass_kg_per_m is None else m / self.modes_mass_kg_per_m

    @property
    def damping_ratio_used(self) -> float:
        """The given damping ratio, else Table 6.6 (+ Eq. 6.13) of the span that allows the least: one ratio for
        every mode of a chain, on the safe side."""
        if self.damping_ratio is not None:
            return self.damping_ratio
        return min(damping_ratio_table_6_6(self.structure, L)
                   + (additional_damping_ratio(L) if self.additional_damping else 0.0) for L in self.spans_m)


_BRIDGE_KEYS = {"spans_m", "EI_Nm2", "continuous", "modes_file", "modes_mass_kg_per_m", "mass_kg_per_m", "structure",
                "damping_ratio", "additional_damping", "track_form"}


def read_bridge_file(path) -> BridgeSpec:
    """The ``[bridge]`` table of a bridge file (module docstring), checked: a problem is a ``ValueError``
    ``"<file>: bridge.<key>: <problem>"``."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except OSError as exc:
        raise ValueError(f"--bridge: {path}: {exc.strerror or exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"--bridge: {path}: not a TOML file ({exc})") from None

    def bad(key, problem):
        return ValueError(f"{path}: bridge.{key}: {problem}")
    b = data.get("bridge")
    if not isinstance(b, dict):
        raise ValueError(f"{path}: no [bridge] table")
    unknown = sorted(set(b) - _BRIDGE_KEYS)
    if unknown:
        raise bad(unknown[0], f"unknown key (expected {', '.join(sorted(_BRIDGE_KEYS))})")
    spans = b.get("spans_m")
    if not isinstance(spans, list) or not spans or not all(_positive(x) for x in spans):
        raise bad("spans_m", f"{spans!r}: expected a list of positive span lengths [m]")
    continuous = b.get("continuous", False)
    if not isinstance(continuous, bool):
        raise bad("continuous", f"{continuous!r}: expected true or false")
    if continuous and len(spans) < 2:
        raise bad("continuous", "a deck continuous over intermediate supports needs at least two spans")
    modes_file, modes_mass, EI = b.get("modes_file"), b.get("modes_mass_kg_per_m"), None
    if modes_file is not None:
        if "EI_Nm2" in b or continuous:
            raise bad("modes_file", "give either the built-in beam (EI_Nm2, continuous) or a modes file, not both")
        if not isinstance(modes_file, str) or Path(modes_file).suffix.lower() not in MODES_FILE_SUFFIXES:
            raise bad("modes_file", f"{modes_file!r}: expected the path of a {' or '.join(MODES_FILE_SUFFIXES)} file")
        modes_file = str((path.parent / modes_file).resolve())
        if not Path(modes_file).is_file():
            raise bad("modes_file", f"{modes_file}: no such file")
        if modes_mass is not None and not _positive(modes_mass):
            raise bad("modes_mass_kg_per_m", f"{modes_mass!r}: expected the positive deck mass per length the "
                                             "modes were computed with [kg/m]")
    else:
        if modes_mass is not None:
            raise bad("modes_mass_kg_per_m", "only with a modes_file")
        EI = b.get("EI_Nm2")
        if not _positive(EI):
            raise bad("EI_Nm2", f"{EI!r}: expected the positive bending stiffness of the spans [N m²] (or give a "
                                "modes_file)")
    m = b.get("mass_kg_per_m")
    if m is None and modes_file is not None:
        masses = {"nominal": None}
    elif _positive(m):
        masses = {"nominal": float(m)}
    elif isinstance(m, list) and len(m) == 2 and all(_positive(x) for x in m) and m[0] <= m[1]:
        masses = {"lower": float(m[0]), "upper": float(m[1])}
    else:
        raise bad("mass_kg_per_m", f"{m!r}: expected a positive number or [lower, upper] with lower <= upper [kg/m]")
    if modes_file is not None and modes_mass is None:
        if "lower" in masses:
            raise bad("modes_mass_kg_per_m", "missing: the deck mass per length the modes file was computed with "
                                             "(the mass bounds scale its modes)")
        modes_mass = masses["nominal"]
    structure = b.get("structure")
    zeta = b.get("damping_ratio")
    if zeta is not None and not (isinstance(zeta, (int, float)) and 0.0 <= zeta < 1.0):
        raise bad("damping_ratio", f"{zeta!r}: expected a ratio in [0, 1) (2 % is 0.02)")
    if structure is None and zeta is None:
        raise bad("structure", f"missing: give the structure type ({', '.join(STRUCTURES)}) for the damping of "
                               "EN 1991-2 Table 6.6, or damping_ratio")
    if structure is not None and structure not in STRUCTURES:
        raise bad("structure", f"{structure!r}: expected one of {', '.join(STRUCTURES)}")
    extra = b.get("additional_damping", False)
    if not isinstance(extra, bool):
        raise bad("additional_damping", f"{extra!r}: expected true or false")
    track = b.get("track_form", TRACK_FORMS[0])
    if track not in TRACK_FORMS:
        raise bad("track_form", f"{track!r}: expected one of {', '.join(TRACK_FORMS)}")
    return BridgeSpec(spans_m=tuple(float(x) for x in spans), EI_Nm2=None if EI is None else float(EI),
                      masses=masses, structure=structure, damping_ratio=None if zeta is None else float(zeta),
                      additional_damping=extra, track_form=track, source=str(path), continuous=continuous,
                      modes_file=modes_file, modes_mass_kg_per_m=None if modes_mass is None else float(modes_mass))


def _positive(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and x > 0


@dataclass(frozen=True)
class DynamicCheck:
    """A whole check: the bridge, the maximum line speed [km/h], the trains (names of HSLM-A or consist files) and,
    optionally, the speeds [km/h] (else :func:`speed_grid_kmh` per train and mass bound)."""

    bridge: BridgeSpec
    max_line_speed_kmh: float
    trains: tuple = HSLM_NAMES
    speeds_kmh: tuple | None = None

    _n: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    _decks: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __getstate__(self):                  # the modes counts go with a task, the modes themselves do not
        return {k: v for k, v in self.__dict__.items() if k != "_decks"}

    def __setstate__(self, state):
        self.__dict__.update(state, _decks={})

    def axles(self, train: str):
        return hslm_a(train) if train in HSLM_NAMES else consist_axles(train)

    def crossing(self, train: str, bound: str, v_kmh: float) -> BridgeCrossing:
        return self._case(bound, self.n_modes(bound), self.axles(train), v_kmh / 3.6)

    def _case(self, bound: str, n_modes: int, axles, speed_m_s: float) -> BridgeCrossing:
        b = self.bridge
        m = b.masses[bound]
        spans = b.spans_m if len(b.spans_m) > 1 else None
        if b.modes_file is not None:
            return BridgeCrossing(span_m=b.spans_m[0], mass_kg_m=m, f1_Hz=None, damping_ratio=b.damping_ratio_used,
                                  n_modes=n_modes, axles=axles, speed_m_s=speed_m_s, track_form=b.track_form,
                                  spans_m=spans, modes_file=b.modes_file, mass_scale=b.mass_scale(bound))
        return BridgeCrossing(span_m=b.spans_m[0], mass_kg_m=m, f1_Hz=first_frequency_Hz(b.spans_m[0], b.EI_Nm2, m),
                              damping_ratio=b.damping_ratio_used, n_modes=n_modes, axles=axles, speed_m_s=speed_m_s,
                              track_form=b.track_form, spans_m=spans, continuous=b.continuous)

    def n_modes(self, bound: str) -> int:
        """The crossings' ``n_modes`` at ``bound`` (module docstring, *Modes*), found once (and sent with the check
        to the workers)."""
        if bound not in self._n:
            self._n[bound] = self._modes_count(bound)
        return self._n[bound]

    def _modes_count(self, bound: str) -> int:
        b = self.bridge
        probe = hslm_a(HSLM_NAMES[0])
        if b.modes_file is None and not b.continuous:
            return n_modes_to_cutoff(b.spans_m, b.EI_Nm2, b.masses[bound])
        if b.continuous:
            for n in range(3, MAX_MODES + 1):
                if all(deck_modes(self._case(bound, n, probe, 1.0)).reaches_cutoff(k) for k in range(len(b.spans_m))):
                    return n
            raise ValueError(f"continuous: {MAX_MODES} modes per span do not reach EN 1990's cut-off")
        one = self._case(bound, 1, probe, 1.0)
        n = file_modes_to_cutoff(one)
        everything = one.file_modes.n_modes
        if n is None:
            warnings.warn(f"{b.modes_file}: the file's vertical modes do not reach EN 1990's cut-off on every span "
                          f"(mass bound {bound}; a span needs its first and third vertical modes and one at or "
                          f"above max(30 Hz, 1.5 f1, f3)): the check uses all the file's modes", InputWarning,
                          stacklevel=3)
            n = everything
        if n > MAX_MODES:
            raise ValueError(f"modes_file: {n} of its modes are needed to reach EN 1990's cut-off, more than "
                             f"{MAX_MODES}")
        return n

    def deck(self, bound: str):
        """``(n_modes, DeckModes)`` of the crossings at ``bound`` (module docstring, *Modes*), computed once."""
        if bound not in self._decks:
            n = self.n_modes(bound)
            self._decks[bound] = (n, deck_modes(self._case(bound, n, hslm_a(HSLM_NAMES[0]), 1.0)))
        return self._decks[bound]

    def resonances_kmh(self, train: str, bound: str) -> list[float]:
        """The resonance speeds ``f1 d / i`` (i = 1…:data:`N_RESONANCES`) of ``train`` on every span of the bridge
        (a chain's own first frequencies, the whole deck's otherwise) at the mass ``bound`` [km/h] (none for a train
        without a characteristic spacing)."""
        spacing = self.axles(train).spacing_m
        if spacing is None:
            return []
        f1s = sorted(set(self.deck(bound)[1].f1_Hz))
        return sorted(speed_km_h(v) for f1 in f1s for v in resonance_speeds_m_s(f1, spacing)[:N_RESONANCES])

    def runs(self) -> list[tuple]:
        """Every crossing ``(train, mass bound, speed [km/h])`` of the check, in the envelope's order."""
        out = []
        for train in self.trains:
            for bound in self.bridge.masses:
                if self.speeds_kmh is not None:
                    speeds = sorted(set(float(v) for v in self.speeds_kmh))
                else:
                    speeds = speed_grid_kmh(self.max_line_speed_kmh, self.resonances_kmh(train, bound))
                out += [(train, bound, v) for v in speeds]
        return out

    def speed_rule(self) -> str:
        """The speeds of the check in words (the report's and the summary's)."""
        if self.speeds_kmh is not None:
            return "as given: " + ", ".join(f"{v:g}" for v in sorted(set(self.speeds_kmh))) + " km/h"
        return (f"from {MIN_SPEED_KM_H:g} km/h (40 m/s) to 1.2 x {self.max_line_speed_kmh:g} km/h in steps of at most "
                f"{SPEED_STEP_KM_H:g} km/h, refined by {REFINE_KM_H:g} km/h around each resonance speed f1 d/i "
                f"(i = 1...{N_RESONANCES})")


def run_fingerprint(check: DynamicCheck, train: str, bound: str, v_kmh: float) -> dict:
    """What a crossing's result depends on: its whole case (the bridge, the train's axles, the speed) and the
    package's code (:func:`~exudyn_wheelrail.jit.package_source_digest`) — a run file is taken on a resumed check
    only when this matches exactly."""
    return {"crossing": json.loads(json.dumps(check.crossing(train, bound, v_kmh).as_dict())),
            "train": train, "mass_bound": bound, "speed_kmh": v_kmh, "code": package_source_digest().hex()}


def _run_name(fingerprint: dict) -> str:
    """A run file's name: readable, and unique by a digest of the whole fingerprint."""
    digest = hashlib.sha256(json.dumps(fingerprint, sort_keys=True).encode()).hexdigest()[:16]
    train = fingerprint["train"]
    stem = train if train in HSLM_NAMES else Path(train).stem
    return f"{stem}__{fingerprint['mass_bound']}__{fingerprint['speed_kmh']!r}kmh__{digest}.json"


def crossing_row(check: DynamicCheck, train: str, bound: str, v_kmh: float) -> dict:
    """One crossing of the check (runs in a worker): its row of :data:`ENVELOPE_COLUMNS`; an exception becomes
    ``status = "error: ..."``."""
    row = {"train": train, "mass_bound": bound, "speed_kmh": v_kmh}
    try:
        s = run_bridge_crossing(check.crossing(train, bound, v_kmh)).summary
    except Exception as exc:
        return {**row, "status": f"error: {type(exc).__name__}: {exc}".splitlines()[0]}
    sc = s.get("scalars") or {}
    return {**row, "status": s["status"], "max_deck_acceleration_m_s2": sc.get("deck.en1990_peak_acceleration_m_s2"),
            "max_deck_displacement_m": sc.get("deck.max_mid_span_deflection_m"),
            "dynamic_enhancement": (sc["deck.dynamic_amplification_mid_span"] - 1.0
                                    if sc.get("deck.dynamic_amplification_mid_span") is not None else None),
            "steps": s.get("steps"), "solve_seconds": s.get("solve_seconds")}


def run_dynamic_check(check: DynamicCheck, out_dir, *, executor=None, workers: int | None = None,
                      progress=print) -> dict:
    """Run every crossing of ``check`` not already in ``out_dir/runs`` (module docstring), write the outputs and
    return the summary (:func:`check_summary`)."""
    out = Path(out_dir)
    (out / "runs").mkdir(parents=True, exist_ok=True)
    runs = check.runs()
    prints = {key: run_fingerprint(check, *key) for key in runs}
    rows = {}
    for key in runs:
        f = out / "runs" / _run_name(prints[key])
        if f.is_file():
            try:
                kept = json.loads(f.read_text())
            except (OSError, ValueError):
                continue                  # a file cut short by a kill: computed again
            if isinstance(kept, dict) and kept.get("fingerprint") == prints[key] and "row" in kept:
                rows[key] = kept["row"]
    missing = [key for key in runs if key not in rows]
    done = [len(rows)]

    def finished(i, row):
        key = missing[i]
        rows[key] = row
        if not str(row.get("status", "")).startswith(EXECUTOR_ERROR):     # a lost worker: tried again next time
            write_json(out / "runs" / _run_name(prints[key]), {"fingerprint": prints[key], "row": row})
        done[0] += 1
        if progress:
            a = row.get("max_deck_acceleration_m_s2")
            progress(f"  [{done[0]}/{len(runs)}] {key[0]} {key[1]} {key[2]:g} km/h: {row['status']}"
                     + (f"; max |a| {a:.4g} m/s^2" if isinstance(a, float) else ""))

    def failed(i, text):
        train, bound, v = missing[i]
        return {"train": train, "mass_bound": bound, "speed_kmh": v, "status": text.splitlines()[0]}
    if progress and len(missing) < len(runs):
        progress(f"  {len(runs) - len(missing)} of {len(runs)} crossings taken from {out / 'runs'}")
    run_tasks(executor, workers, crossing_row, [(check, *key) for key in missing], finished, failed)
    envelope = [rows[key] for key in runs]
    summary = check_summary(check, envelope)
    write_table_csv(out / "envelope.csv", {c: [r.get(c) for r in envelope] for c in ENVELOPE_COLUMNS})
    resonances = {(t, b): check.resonances_kmh(t, b) for t in check.trains for b in check.bridge.masses}
    summary["paths"] = write_figures_and_report(envelope, summary, resonances, out)
    write_json(out / "summary.json", summary)
    return summary


def check_summary(check: DynamicCheck, envelope: list) -> dict:
    """``summary.json`` of a check: ``verdict`` (``pass`` | ``fail``), ``max_deck_acceleration_m_s2``,
    ``acceleration_limit_m_s2``, ``governing`` (train, speed, mass bound), ``damping_ratio_used``, the modes, the
    largest dynamic enhancement, the crossings that did not complete, the inputs and the clauses."""
    b = check.bridge
    limit = EN1990_DECK_ACCELERATION_LIMITS_M_S2[b.track_form]
    ok = [r for r in envelope if r.get("status") == OK and r.get("max_deck_acceleration_m_s2") is not None]
    failed = [{k: r.get(k) for k in ("train", "mass_bound", "speed_kmh", "status")} for r in envelope
              if not (r.get("status") == OK and r.get("max_deck_acceleration_m_s2") is not None)]
    worst = max(ok, key=lambda r: r["max_deck_acceleration_m_s2"]) if ok else None
    enh = [r["dynamic_enhancement"] for r in ok if r.get("dynamic_enhancement") is not None]
    a_max = worst["max_deck_acceleration_m_s2"] if worst else None
    verdict = "pass" if worst is not None and not failed and a_max <= limit else "fail"
    modes = {}
    for bound, m in b.masses.items():
        n, deck = check.deck(bound)
        f = deck.modes.frequencies_Hz
        modes[bound] = {"mass_kg_per_m": m, "f1_Hz": list(deck.f1_Hz), "n_modes": n,
                        "frequencies_Hz": [[float(f[i]) for i in idx] for idx in
                                           (deck.vertical if b.modes_file is None and not b.continuous
                                            else deck.vertical[:1])],
                        "kinds": list(deck.modes.kinds),
                        "cutoff_Hz": max(deck.cutoffs_Hz), "modes_reach_cutoff": all(
                            deck.reaches_cutoff(k) for k in range(len(b.spans_m)))}
        if b.modes_file is not None:
            modes[bound]["mass_scale"] = b.mass_scale(bound)
    return {"verdict": verdict,
            "verdict_reason": (f"{len(failed)} crossing(s) did not complete" if failed else
                               "no crossing completed" if worst is None else
                               f"max deck acceleration {a_max:.4g} m/s^2 "
                               f"{'<=' if a_max <= limit else '>'} {limit:g} m/s^2"),
            "max_deck_acceleration_m_s2": a_max, "acceleration_limit_m_s2": limit,
            "governing": None if worst is None else {"train": worst["train"], "speed_kmh": worst["speed_kmh"],
                                                     "mass_bound": worst["mass_bound"]},
            "damping_ratio_used": b.damping_ratio_used,
            "damping_rule": ("given (bridge.damping_ratio)" if b.damping_ratio is not None else
                             f"EN 1991-2 Table 6.6, {b.structure}, L = {min(b.spans_m):g} m"
                             + (" + Eq. (6.13) additional damping" if b.additional_damping else "")),
            "modes": modes, "speed_rule": check.speed_rule(),
            "max_dynamic_enhancement": max(enh) if enh else None,
            "crossings": len(envelope), "not_completed": failed,
            "deck": ("modes file " + b.modes_file if b.modes_file is not None else
                     "continuous beam" if b.continuous else "simply supported spans"),
            "inputs": {"bridge_file": b.source, "spans_m": list(b.spans_m), "EI_Nm2": b.EI_Nm2,
                       "continuous": b.continuous, "modes_file": b.modes_file,
                       "modes_mass_kg_per_m": b.modes_mass_kg_per_m,
                       "mass_kg_per_m": b.masses, "track_form": b.track_form, "structure": b.structure,
                       "max_line_speed_kmh": check.max_line_speed_kmh, "trains": list(check.trains),
                       "speeds_kmh": None if check.speeds_kmh is None else list(check.speeds_kmh)},
            "clauses": {"trains": "EN 1991-2 6.4.6.1.1, Table 6.3 (HSLM-A)", "speeds": "EN 1991-2 6.4.6.2(1)",
                        "mass": "EN 1991-2 6.4.6.3.2", "damping": "EN 1991-2 6.4.6.3.1, Table 6.6, Eq. (6.13)",
                        "modes": "EN 1990 A2.4.4.2.1(4)P", "limit": "EN 1990 A2.4.4.2.1(4)P"}}

