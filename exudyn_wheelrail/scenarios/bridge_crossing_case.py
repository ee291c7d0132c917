"""The bridge crossing's case: its inputs and their checks (:class:`BridgeCrossing`), the plausibility ranges of the
deck's inputs and the default time step (:func:`default_dt_s`).  The crossing is described in
:mod:`exudyn_wheelrail.scenarios.bridge_crossing`, its public import path."""
from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..conventions import speed_km_h
from ..simulation.solvers import RESOLUTION_LIMIT, SOLVERS
from ..structures.load_models import AxleTrain
from ..structures.modes_file import half_waves, mode_kinds, read_modes_file
from ..validation import Quantity
from .deck import TRACK_FORMS, bending_stiffness_Nm2
from .defaults import (DEFAULT_SOLVER, LATERAL_EI_RATIO, LOAD_MODELS, MAX_MODES, MODEL_NAMES, SPRUNG_DAMPING_RATIO,
                       SPRUNG_FREQUENCY_HZ, STEPS_PER_PERIOD)

__all__ = ["BridgeCrossing", "default_dt_s", "step_rounded_down", "positive_number", "SPAN_M", "MASS_KG_M", "F1_HZ",
           "FREE_VIBRATION_S", "MAX_DEFAULT_DT_S", "MIN_ELEMENTS", "ELEMENTS_PER_MODE", "MAX_SPANS", "CLAMPED_BAND",
           "file_sha256"]

#: plausibility of the deck's inputs (a value outside is an error, outside ``typical`` a warning)
SPAN_M = Quantity("span length", "m", 1.0, 500.0, typical=(5.0, 150.0))
MASS_KG_M = Quantity("deck mass per length", "kg/m", 100.0, 1.0e6, typical=(2.0e3, 1.0e5))
F1_HZ = Quantity("first bending frequency", "Hz", 0.05, 200.0, typical=(1.0, 40.0))
FREE_VIBRATION_S = Quantity("free-vibration time", "s", 0.0, 600.0)
#: largest default time step [s]
MAX_DEFAULT_DT_S = 0.01
#: beam elements of the span: max(MIN_ELEMENTS, ELEMENTS_PER_MODE * N)
MIN_ELEMENTS = 20
ELEMENTS_PER_MODE = 8
#: most spans of a chain
MAX_SPANS = 50
#: a clamped–clamped beam's N-th frequency is at most ``(N + CLAMPED_BAND)²`` times the simply supported first
#: (β_N L = 4.730, 7.853, 10.996, … ≈ (N + 1/2) π; 1.5056² = 2.267 ≤ 1.51²)
CLAMPED_BAND = 0.51


def file_sha256(path) -> str:
    """The SHA-256 of a file's bytes (a crossing's fingerprint holds its modes file's), read once per file version
    (its path, modification time and size)."""
    p = Path(path)
    st = p.stat()
    return _sha256(str(p.resolve()), st.st_mtime_ns, st.st_size)


@lru_cache(maxsize=16)
def _sha256(resolved: str, mtime_ns: int, size: int) -> str:
    return hashlib.sha256(Path(resolved).read_bytes()).hexdigest()


# ================================================================================================= the case
def positive_number(name, value, *, allow_zero=False) -> float:
    """``value`` as a finite float > 0 (``allow_zero``: >= 0); ``ValueError`` ``"<name>: <problem>"``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected a number, got {value!r}") from None
    if not math.isfinite(x) or (x < 0.0 if allow_zero else x <= 0.0):
        raise ValueError(f"{name}: {value!r} must be a finite number {'>= 0' if allow_zero else '> 0'}")
    return x


@dataclass(frozen=True)
class BridgeCrossing:
    """A crossing (module docstring).  Errors: ``ValueError`` ``"<field>: <problem>"``.

    span_m, mass_kg_m, f1_Hz : span length [m], deck mass per length [kg/m], first bending frequency [Hz] of the
        first span as a simply supported span (it sets the section's ``EI``).  With a modes file: ``mass_kg_m``
        only reported (None allowed), ``f1_Hz`` None (the file's first vertical frequency is taken).
    damping_ratio : modal damping ratio ζ of every mode, 0 ≤ ζ < 1; with a modes file None takes the file's.
    n_modes : vertical bending modes kept per span (1 … :data:`MAX_MODES`); a continuous deck keeps its
        ``n_modes × spans`` lowest; a modes file its ``n_modes`` lowest modes (of any kind).
    axles : the train as axle loads (:class:`~exudyn_wheelrail.structures.load_models.AxleTrain`); None only
        for a load model that builds the train itself (``train_file``).
    speed_m_s : running speed [m/s].
    model : a name of :data:`LOAD_MODELS`.
    free_vibration_s : time simulated after the last axle has left the span [s].
    dt_s : time step [s]; None: :func:`default_dt_s`.
    solver : integrator (:data:`~exudyn_wheelrail.simulation.settings.SOLVERS`).
    track_form : the EN 1990 limit applied (:data:`~exudyn_wheelrail.scenarios.deck.TRACK_FORMS`).
    train_file : a consist file for the load models that read one.
    deck_start_m : track distance of the first support [m].
    spans_m : a chain of simply supported spans, in running order [m] (module docstring, *A chain of spans*); the
        first is ``span_m``.  None: the single span ``span_m``.
    lateral_modes : lateral bending modes kept per span (0 … :data:`MAX_MODES`; default 0: none).
    lateral_f1_Hz : first lateral bending frequency of the first span [Hz] (it sets ``EI_z``); None: ``EI_z =``
        :data:`LATERAL_EI_RATIO` ``EI_y``.
    sprung_frequency_Hz, sprung_damping_ratio : the suspension of the ``sprung-masses`` model (its module
        docstring).
    continuous : the spans form one deck continuous over the intermediate supports (the built-in beam; at least
        two spans).
    modes_file : a modes file from an FE program (:mod:`~exudyn_wheelrail.structures.modes_file`) instead of the
        built-in beam; the spans then give its supports.
    mass_scale : with a modes file, the deck mass over the mass its modes were computed with (a mass bound).
    """

    span_m: float
    mass_kg_m: float
    f1_Hz: float
    damping_ratio: float
    n_modes: int
    axles: AxleTrain | None
    speed_m_s: float
    model: str = MODEL_NAMES[0]
    free_vibration_s: float = 0.0
    dt_s: float | None = None
    solver: str = DEFAULT_SOLVER
    track_form: str = TRACK_FORMS[0]
    train_file: str | None = None
    deck_start_m: float = 0.0
    spans_m: tuple | None = None
    lateral_modes: int = 0
    lateral_f1_Hz: float | None = None
    sprung_frequency_Hz: float = SPRUNG_FREQUENCY_HZ
    sprung_damping_ratio: float = SPRUNG_DAMPING_RATIO
    continuous: bool = False
    modes_file: str | None = None
    mass_scale: float = 1.0

    def __post_init__(self):
        if self.modes_file is not None:
            self._check_modes_file()
        for name in ("span_m", "mass_kg_m", "f1_Hz", "speed_m_s"):
            if name == "mass_kg_m" and self.modes_file is not None and self.mass_kg_m is None:
                continue
            object.__setattr__(self, name, positive_number(name, getattr(self, name)))
        if self.damping_ratio is None and self.modes_file is not None:
            if self.file_modes.damping_ratio is None:
                raise ValueError(f"damping_ratio: missing: the modes file {self.modes_file} gives none")
        else:
            z = positive_number("damping_ratio", self.damping_ratio, allow_zero=True)
            if not z < 1.0:
                raise ValueError(f"damping_ratio: {z:g} must be < 1 (a ratio, not a percentage: 2 % is 0.02)")
            object.__setattr__(self, "damping_ratio", z)
        n = self.n_modes
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= MAX_MODES:
            raise ValueError(f"n_modes: {n!r} must be an integer from 1 to {MAX_MODES}")
        if self.modes_file is not None and n > self.file_modes.n_modes:
            raise ValueError(f"n_modes: {n} modes asked, the modes file {self.modes_file} has "
                             f"{self.file_modes.n_modes}")
        if self.modes_file is not None and "vertical" not in mode_kinds(self.file_modes.lowest(n)):
            raise ValueError(f"n_modes: the {n} lowest modes of the modes file {self.modes_file} have no vertical "
                             "mode (keep more)")
        object.__setattr__(self, "n_modes", int(n))
        if self.axles is not None and not isinstance(self.axles, AxleTrain):
            raise ValueError(f"axles: expected an AxleTrain, got {type(self.axles).__name__}")
        if self.model not in LOAD_MODELS:
            raise ValueError(f"model: {self.model!r}: expected one of {', '.join(MODEL_NAMES)}")
        object.__setattr__(self, "free_vibration_s", positive_number("free_vibration_s", self.free_vibration_s,
                                                               allow_zero=True))
        if self.spans_m is not None:
            spans = self.spans_m
            if isinstance(spans, (str, bytes)) or not hasattr(spans, "__len__") or len(spans) < 1:
                raise ValueError(f"spans_m: {spans!r}: expected a sequence of span lengths [m]")
            if len(spans) > MAX_SPANS:
                raise ValueError(f"spans_m: {len(spans)} spans, more than {MAX_SPANS}")
            spans = tuple(positive_number(f"spans_m[{k}]", x) for k, x in enumerate(spans))
            if spans[0] != self.span_m:
                raise ValueError(f"spans_m: the first span {spans[0]:g} m is not span_m = {self.span_m:g} m (span_m is "
                                 "the first span of the chain)")
            object.__setattr__(self, "spans_m", spans)
        n = self.lateral_modes
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 0 <= n <= MAX_MODES:
            raise ValueError(f"lateral_modes: {n!r} must be an integer from 0 to {MAX_MODES}")
        object.__setattr__(self, "lateral_modes", int(n))
        if self.lateral_f1_Hz is not None:
            object.__setattr__(self, "lateral_f1_Hz", positive_number("lateral_f1_Hz", self.lateral_f1_Hz))
        object.__setattr__(self, "sprung_frequency_Hz",
                           positive_number("sprung_frequency_Hz", self.sprung_frequency_Hz))
        zv = positive_number("sprung_damping_ratio", self.sprung_damping_ratio, allow_zero=True)
        if not zv < 1.0:
            raise ValueError(f"sprung_damping_ratio: {zv:g} must be < 1 (a ratio, not a percentage)")
        object.__setattr__(self, "sprung_damping_ratio", zv)
        if self.dt_s is not None:
            dt = positive_number("dt_s", self.dt_s)
            wh = 2.0 * math.pi * self.f_N_Hz * dt
            if wh > RESOLUTION_LIMIT:
                raise ValueError(f"dt_s: {dt:g} s does not integrate mode {self.n_modes} ({self.f_N_Hz:g} Hz): omega "
                                 f"dt = {wh:.3g} > 2 sqrt 2 (RK44's stability limit, the trapezoidal rule's "
                                 f"resolution bound); use dt <= {RESOLUTION_LIMIT / (2.0 * math.pi * self.f_N_Hz):.3g} "
                                 "s or fewer modes")
            object.__setattr__(self, "dt_s", dt)
        if self.solver not in SOLVERS:
            raise ValueError(f"solver: {self.solver!r}: expected one of {', '.join(SOLVERS)}")
        if self.track_form not in TRACK_FORMS:
            raise ValueError(f"track_form: {self.track_form!r}: expected one of {', '.join(TRACK_FORMS)}")
        start = float(self.deck_start_m)
        if not math.isfinite(start):
            raise ValueError(f"deck_start_m: {self.deck_start_m!r} is not a finite number")
        object.__setattr__(self, "deck_start_m", start)
        if not isinstance(self.continuous, (bool, np.bool_)):
            raise ValueError(f"continuous: {self.continuous!r}: expected true or false")
        if self.continuous and self.n_spans < 2:
            raise ValueError("continuous: a deck continuous over intermediate supports needs at least two spans "
                             "(spans_m)")
        if self.continuous and self.modes_file is not None:
            raise ValueError("continuous: give either the built-in continuous deck or a modes file, not both")

    def _check_modes_file(self):
        """A modes file's case: the file read and checked (its errors name the file and key), ``f1_Hz`` its first
        vertical frequency at the mass scale, no lateral modes asked (the file's modes are taken as given)."""
        r = positive_number("mass_scale", self.mass_scale)
        object.__setattr__(self, "mass_scale", r)
        object.__setattr__(self, "modes_file", str(self.modes_file))
        try:
            data = read_modes_file(self.modes_file)
        except ValueError as exc:
            raise ValueError(f"modes_file: {exc}") from None
        if self.lateral_modes or self.lateral_f1_Hz is not None:
            raise ValueError("lateral_modes: a modes file's modes are taken as given (its lateral rows, if any)")
        vertical = [f for f, kind in zip(data.frequency_hz, mode_kinds(data)) if kind == "vertical"]
        if not vertical:
            raise ValueError(f"modes_file: {self.modes_file}: no vertical mode")
        f1 = min(vertical) / math.sqrt(r)
        if self.f1_Hz is not None and abs(float(self.f1_Hz) / f1 - 1.0) > 1e-9:
            raise ValueError(f"f1_Hz: {self.f1_Hz!r} Hz is not the modes file's first vertical frequency {f1:.6g} Hz "
                             "(leave it out: the file gives it)")
        object.__setattr__(self, "f1_Hz", f1)

    @property
    def file_modes(self):
        """The modes file's contents (:class:`~exudyn_wheelrail.structures.modes_file.ModesFileData`; read once per
        file version), None for the built-in beam."""
        return None if self.modes_file is None else read_modes_file(self.modes_file)

    @property
    def global_modes(self) -> bool:
        """Whether the deck's modes span the whole deck (a continuous deck, a modes file) rather than one span each
        (a chain of simply supported spans)."""
        return bool(self.continuous) or self.modes_file is not None

    @property
    def EI_Nm2(self) -> float | None:
        """Vertical bending stiffness of the built-in beam (None with a modes file)."""
        if self.modes_file is not None:
            return None
        return bending_stiffness_Nm2(self.span_m, self.mass_kg_m, self.f1_Hz)[0]

    @property
    def EI_z_Nm2(self) -> float | None:
        """Lateral bending stiffness: from ``lateral_f1_Hz`` on the first span, else :data:`LATERAL_EI_RATIO`
        ``EI_y`` (:func:`~.deck.bending_stiffness_Nm2`); None with a modes file."""
        if self.modes_file is not None:
            return None
        return bending_stiffness_Nm2(self.span_m, self.mass_kg_m, self.f1_Hz, self.lateral_f1_Hz)[1]

    @property
    def chain_m(self) -> tuple:
        """The spans in running order [m] (``(span_m,)`` for a single span)."""
        return (self.span_m,) if self.spans_m is None else self.spans_m

    @property
    def n_spans(self) -> int:
        return len(self.chain_m)

    @property
    def length_m(self) -> float:
        """Deck length, the sum of the spans [m]."""
        return self.span_m if self.spans_m is None else float(sum(self.spans_m))

    def span_start_m(self, k: int) -> float:
        """Track distance of the first support of span ``k`` (0-based) [m]."""
        return self.deck_start_m + float(sum(self.chain_m[:k]))

    def span_f1_Hz(self, k: int) -> float:
        """First vertical bending frequency of span ``k`` (0-based), the section of the first: ``f1 (L1/Lk)²``."""
        return self.f1_Hz if k == 0 else self.f1_Hz * (self.span_m / self.chain_m[k]) ** 2

    def span_lateral_f1_Hz(self, k: int) -> float:
        """First lateral bending frequency of span ``k`` (0-based) [Hz]: ``√(EI_z/EI_y) f1_k``."""
        if self.lateral_f1_Hz is not None:
            return self.lateral_f1_Hz * (self.span_m / self.chain_m[k]) ** 2
        return math.sqrt(LATERAL_EI_RATIO) * self.span_f1_Hz(k)

    @property
    def f_N_Hz(self) -> float:
        """The Euler–Bernoulli frequency of the highest mode kept: ``N² f1`` of a single span without lateral modes;
        the largest ``N² f1_k`` and ``N_L² f_L,k`` over the spans otherwise.  A continuous deck: the bound
        ``(N + CLAMPED_BAND) ² f1_k`` (the N-th frequency of the stiffest span clamped at both ends: clamping every
        support adds constraints, which raise every eigenvalue, so it bounds the deck's ``N K``-th mode).  A modes
        file: its highest kept frequency at the mass scale."""
        if self.modes_file is not None:
            return float(np.sort(self.file_modes.frequency_hz)[self.n_modes - 1]) / math.sqrt(self.mass_scale)
        band = CLAMPED_BAND if self.continuous else 0.0
        if self.spans_m is None and self.lateral_modes == 0:
            return self.n_modes ** 2 * self.f1_Hz
        f = max((self.n_modes + band) ** 2 * self.span_f1_Hz(k) for k in range(self.n_spans))
        if self.lateral_modes:
            f = max(f, max((self.lateral_modes + band) ** 2 * self.span_lateral_f1_Hz(k)
                           for k in range(self.n_spans)))
        return f

    @property
    def half_waves(self) -> int:
        """The most half-waves of a kept shape along a span (the moving loads' spatial resolution): ``N`` (and
        ``N_L``) of the built-in beam, counted from a modes file's shapes."""
        if self.modes_file is not None:
            supports = np.concatenate([[0.0], np.cumsum(self.chain_m)])
            return half_waves(self.file_modes.lowest(self.n_modes), supports)
        return max(self.n_modes, self.lateral_modes)

    def as_dict(self) -> dict:
        return {"span_m": self.span_m, "mass_kg_m": self.mass_kg_m, "f1_Hz": self.f1_Hz,
                "damping_ratio": self.damping_ratio, "n_modes": self.n_modes, "speed_m_s": self.speed_m_s,
                "speed_km_h": speed_km_h(self.speed_m_s), "model": self.model, "free_vibration_s": self.free_vibration_s,
                "dt_s": self.dt_s, "solver": self.solver, "track_form": self.track_form,
                "train_file": self.train_file, "deck_start_m": self.deck_start_m, "spans_m": list(self.chain_m),
                "lateral_modes": self.lateral_modes, "lateral_f1_Hz": self.lateral_f1_Hz,
                "sprung_frequency_Hz": self.sprung_frequency_Hz, "sprung_damping_ratio": self.sprung_damping_ratio,
                "continuous": bool(self.continuous), "modes_file": self.modes_file,
                "modes_file_sha256": None if self.modes_file is None else file_sha256(self.modes_file),
                "mass_scale": self.mass_scale,
                "axles": None if self.axles is None else self.axles.as_dict()}


def default_dt_s(case: BridgeCrossing) -> float:
    """``min(1/(40 f_N), 2L/(40 N V), 10 ms)`` rounded down to 3 significant digits (module docstring; a chain: the
    shortest span, the highest mode of all spans, N the larger of the vertical and lateral mode counts)."""
    return step_rounded_down(min(
        1.0 / (STEPS_PER_PERIOD * case.f_N_Hz),
        2.0 * min(case.chain_m) / (STEPS_PER_PERIOD * case.half_waves * case.speed_m_s),
        MAX_DEFAULT_DT_S))


def step_rounded_down(dt: float) -> float:
    """A time step rounded down to 3 significant digits [s]."""
    scale = 10.0 ** (math.floor(math.log10(dt)) - 2)
    return math.floor(dt / scale + 1e-9) * scale

