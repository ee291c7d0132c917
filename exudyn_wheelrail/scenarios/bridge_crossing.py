r"""A train crossing a simply supported span (or a chain of them): the deck in Exudyn, the train by a load model,
one run through the project's runner, the deck's outputs (``python -m exudyn_wheelrail bridge-crossing``).

>>> case = BridgeCrossing(span_m=20.0, mass_kg_m=15e3, f1_Hz=5.0, damping_ratio=0.01, n_modes=3,
...                       axles=hslm_a("A1"), speed_m_s=300 / 3.6)                     # doctest: +SKIP
>>> result = run_bridge_crossing(case, out_dir="out/crossing")                          # doctest: +SKIP
>>> result.summary["max_abs_deck_midspan_acceleration_m_s2"]                            # doctest: +SKIP

The deck
--------
A simply supported Euler–Bernoulli span of length ``L`` and mass ``m`` per length whose bending stiffness follows
from the first frequency: ``f1 = π/(2L²) √(EI/m)`` ⇒ ``EI = m (2L² f1/π)²``
(:func:`~exudyn_wheelrail.structures.load_models.flexural_rigidity_Nm2`).  It is the deck of
:mod:`exudyn_wheelrail.structures.bridge` — the 3-D beam meshed with ``max(20, 8 N)`` elements
(:data:`MIN_ELEMENTS`, :data:`ELEMENTS_PER_MODE`; the N-th bending frequency then lies within 3e-5 of
``N² f1``), reduced to its **N lowest vertical bending modes** (mass-normalised) with the modal damping ratio ζ in
every mode, entered into Exudyn by :func:`~exudyn_wheelrail.structures.bridge.add_bridge` (``"modal"``: one
``NodeGenericODE2`` with ``I``, ``diag(ω²)``, ``diag(2ζω)``) — the same bridge object a vehicle model couples
its wheel–rail contact to.  The lateral, torsional and axial stiffnesses of the section (:func:`deck_section`) do
not act on the vertical modes (the beam axis is the shear centre and the centre of mass, the rails at its height);
the torsional and axial modes are not kept, the lateral ones on request (*Lateral modes*).  The deck starts at
track distance ``deck_start_m`` (default 0); the first axle is there at ``t = 0``.

A chain of spans
----------------
``spans_m = (L1, L2, …)`` (``--spans-m``, or ``--n-spans K`` equal spans): simply supported spans end to end in
running order, each an independent deck (:class:`~exudyn_wheelrail.structures.bridge.BridgeModel` with
``continuous=False``: doubled nodes at the joints, nothing couples the spans).  ``span_m`` (``--span-m``) is the
**first** span, the one ``f1`` is given for; every span has the same section (``m``, ``EI`` of the first), so span
k's first frequency is ``f1 (L1/Lk)²``.  ``N`` vertical (and ``N_L`` lateral) modes **per span**, each span's
computed alone (:func:`deck_modes`; the modes of equal spans are never mixed, as the eigenvectors of a repeated
eigenvalue of the whole chain would be).  ``t = 0`` when the first axle enters the first span; the run ends when
the last axle leaves the last span.  The contract's columns and keys (``deck_midspan_*``,
``max_abs_deck_midspan_*``, ``EN1990_A2_deck_acceleration``, the support rotations, the check points, the
quasi-static deflection and the dynamic amplification) are the **first span's**; per span
``deck_span<k>_midspan_displacement_m``, ``deck_span<k>_midspan_acceleration_m_s2``,
``deck_span<k>_en1990_max_abs_acceleration_m_s2`` (:data:`SPAN_COLUMNS`, k = 1 … K, the first span included) and
in ``summary.json`` ``spans`` (per span: place, ``f1``, frequencies, resonance speeds ``f1_k d/i``, peaks, the EN
1990 A2 check with its own cut-off) and ``EN1990_A2_all_spans_passed``.  A single span (``spans_m`` None or one
length) gives the single-span run, bit for bit.

Lateral modes
-------------
``lateral_modes = N_L`` (``--lateral-modes``, default 0): the N_L lowest lateral bending modes of every span
(modal damping ζ), their stiffness ``EI_z`` from the first lateral frequency of the first span
(``lateral_f1_Hz``, ``--lateral-frequency-hz``: ``EI_z = m (2 L1² f_L/π)²``), else ``EI_z =``
:data:`LATERAL_EI_RATIO` ``EI_y`` (``f_L = √10 f1``).  The section decouples them exactly from the vertical ones; a
lateral mode keeps its lateral DOFs only (the eigen-solver's rounding removed).  **Moving vertical loads leave them
at rest — exactly zero** (the moving-load model has no lateral force); with ``vehicles`` the wheel–rail lateral
forces drive them through the same modal projection (on the crossing's perfect straight track these are only the
small left/right differences of the creep forces of a centred vehicle).  Outputs: ``deck_lateral_midspan_
displacement_m`` and ``deck_lateral_midspan_acceleration_m_s2`` (:data:`LATERAL_COLUMNS`, the first span; along
the track's y axis, the lateral modes' share), per span of a chain ``deck_span<k>_lateral_midspan_*``;
``summary.json``: ``max_abs_deck_lateral_midspan_displacement_m``, ``max_abs_deck_lateral_midspan_acceleration_
m_s2`` and ``lateral`` (N_L, ``EI_z``, the rule, the frequencies).  The time step then resolves the highest mode of
all (:func:`default_dt_s`).

Load models (:data:`LOAD_MODELS`)
---------------------------------
``model`` names an entry ``"module:attribute"`` resolved when the case is checked; the attribute is a
:class:`LoadModel`: ``check(case)`` (bad input: ``ValueError`` naming the option, before any work) and ``build(mbs,
case, bridge)`` returning a :class:`LoadModelHandle` (the contact the run monitor watches or None, the axle places
and static loads, the generalized modal forces at the recorded state, extra recorder probes and summary entries).
``"moving-loads"``: the axle loads as constant vertical forces moving at V
(:class:`~exudyn_wheelrail.structures.bridge.MovingForces`: ``Q = Σ Φ(s_k(t))ᵀ F_k`` in one compiled call).
``"vehicles"``: the full vehicle–bridge interaction, provided by
``exudyn_wheelrail.scenarios.bridge_crossing_vehicles`` (module attribute ``VEHICLES``); when that module is not
part of the installation the command stops before any work with ``error: --model: ...`` (exit code 2).
``"sprung-masses"``: every axle a mass on a spring and a damper riding on the deck
(``exudyn_wheelrail.scenarios.bridge_crossing_sprung``, its docstring: the equations and the assumed default
suspension :data:`SPRUNG_FREQUENCY_HZ`, :data:`SPRUNG_DAMPING_RATIO`). A consist file (``train_file``) gives the
axle-load models (:data:`AXLE_LOAD_MODELS`) their axles through :data:`TRAIN_AXLES` (``train_axles(path)`` of the
vehicles module; without it: ``error: --train: ...``).

The run
-------
``t = 0`` when the first axle enters the span; the run ends when the last axle leaves it (the last span of a
chain, deck length ``L`` = the sum of the spans), plus ``free_vibration_s``: ``duration = (x_last + L)/V +
free_vibration_s``.  Integrator (:data:`DEFAULT_SOLVER`):
Exudyn's RK44 (classical 4th-order Runge–Kutta) at the time step :func:`default_dt_s`

    ``dt = min(1/(40 f_N), 2L/(40 N V), 10 ms)``

— 40 steps per period of the highest mode and 40 per period ``2L/(NV)`` of the N-th harmonic of a load's passage
(:data:`STEPS_PER_PERIOD`).  RK44's phase error per step is about ``(ωh)⁵/120``: at ``ω_N h = 2π/40`` 7.9e-7 rad,
its amplitude error ``(ωh)⁶/144`` 1.0e-7 per step, so a response kept for thousands of steps is integrated to well
below 0.1 % (measured against the closed form: 1e-5 of the peak deflection, 7e-5 of the peak acceleration,
tests/test_bridge_crossing.py); the stability limit ``ωh ≤ 2√2`` is 18 times away.  The trapezoidal rule
(``solver="newmark"``) at the same step has a period error ``(ωh)²/12 = 2.1e-3`` that accumulates over the free
vibration (1e-3 of the peak deflection measured).  The run goes through :func:`~exudyn_wheelrail.simulation.runner.
run` (the one pre-step hook, the recorder, the run status of :mod:`~exudyn_wheelrail.simulation.status`).

Outputs (``timeseries.csv``, ``summary.json``)
----------------------------------------------
Time series, one row per step (:data:`DECK_COLUMNS`; **vertical values positive downward**, rotations
``dw/dx``): ``time_s``, ``x_first_axle_m`` (deck coordinate of the first axle, ``V t``),
``deck_midspan_static_displacement_m`` (the quasi-static mid-span deflection under the static axle loads,
:func:`~exudyn_wheelrail.structures.load_models.quasi_static_midspan_deflection_m`),
``deck_midspan_displacement_m``, ``deck_midspan_velocity_m_s``, ``deck_midspan_acceleration_m_s2``,
``deck_support_rotation_start_rad``, ``deck_support_rotation_end_rad``, ``deck_acceleration_p<k>_m_s2`` at
``x = kL/10`` (k = 1 … 9) and ``deck_en1990_max_abs_acceleration_m_s2`` (the largest ``|a|`` of the nine points
with the modes up to the EN 1990 cut-off).  The accelerations are the **modal accelerations** of the state,
``q̈ = Q(t) − diag(2ζω) q̇ − diag(ω²) q`` (exact for the integrated state; never a difference quotient).

``summary.json``: ``status`` and ``status_detail``, ``max_abs_deck_midspan_displacement_m``,
``max_abs_deck_midspan_acceleration_m_s2``, ``solve_seconds``, ``simulated_seconds``, ``real_time_factor``, the
inputs, ``EI_Nm2``, the frequencies (``frequencies_Hz`` of the FE modes used, ``frequencies_euler_bernoulli_Hz``
``= j² f1``), the train (axle count, length, characteristic spacing d), the resonance speeds ``v_i = f1 d/i``
(i = 1 … 4; :func:`~exudyn_wheelrail.structures.load_models.resonance_speeds_m_s`), the EN 1990 A2
deck-acceleration check (EN 1990:2002/A1:2005 A2.4.4.2.1(4)P: peak over L/10 … 9L/10 with the modes up to
max(30 Hz, 1.5 f1, f3); limits 3.5 m/s² ballasted, 5 m/s² direct fastening, from
:data:`~exudyn_wheelrail.scenarios.deck.EN1990_DECK_ACCELERATION_LIMITS_M_S2`; whether the N modes reach the
cut-off), ``quasi_static`` (the peak quasi-static mid-span deflection and the dynamic amplification, the peak
dynamic over it), the run settings and notes.  Peaks of a run that did not end ``ok`` are not evaluated (``None``).

Speed sweeps (:func:`speed_sweep`, ``python -m exudyn_wheelrail bridge-crossing-sweep``)
---------------------------------------------------------------------------------------
The same crossing at many speeds, one task per speed through the executors of the scenario sweeps
(:mod:`.sweep`: a local pool of spawned processes, any ``concurrent.futures.Executor``, a Dask client): one row
per speed (:data:`SWEEP_COLUMNS`) in ``sweep.csv`` / ``sweep.json`` and ``sweep_plot.png`` — the peak mid-span
displacement and acceleration against the speed with the resonance speeds ``v_i = f1 d/i`` marked and the EN 1990
limit drawn.
"""
from __future__ import annotations

import importlib
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from ..structures.load_models import (AxleTrain, characteristic_spacing_m, flexural_rigidity_Nm2,
                                      quasi_static_midspan_deflection_m, resonance_speeds_m_s,
                                      simply_supported_frequencies_Hz)
from ..validation import Quantity
from .deck import CHECK_POINTS_X_OVER_L, EN1990_DECK_ACCELERATION_LIMITS_M_S2, TRACK_FORMS
from .defaults import (AXLE_LOAD_MODELS, DEFAULT_SOLVER, LATERAL_EI_RATIO, LOAD_MODELS, MAX_MODES, MODEL_NAMES,
                       SPRUNG_DAMPING_RATIO, SPRUNG_FREQUENCY_HZ, STEPS_PER_PERIOD)

__all__ = ["BridgeCrossing", "LoadModel", "LoadModelHandle", "BridgeCrossingResult", "LOAD_MODELS", "MODEL_NAMES",
           "DEFAULT_SOLVER", "STEPS_PER_PERIOD", "MAX_DEFAULT_DT_S", "MIN_ELEMENTS", "ELEMENTS_PER_MODE",
           "MAX_MODES", "DECK_COLUMNS", "SUMMARY_KEYS", "deck_section", "vertical_modes", "default_dt_s",
           "resolve_load_model", "resolve_train_axles", "en1990_cutoff_Hz", "TRAIN_AXLES", "SPAN_M", "MASS_KG_M",
           "F1_HZ", "FREE_VIBRATION_S", "run_bridge_crossing", "write_bridge_crossing_outputs",
           "MOVING_LOADS", "SWEEP_COLUMNS", "SpeedSweepResult", "sweep_case", "speed_sweep", "plot_speed_sweep",
           "DeckModes", "deck_modes", "deck_columns", "LATERAL_COLUMNS", "SPAN_COLUMNS", "SPAN_LATERAL_COLUMNS",
           "MAX_SPANS", "LATERAL_EI_RATIO", "AXLE_LOAD_MODELS", "SPRUNG_FREQUENCY_HZ", "SPRUNG_DAMPING_RATIO"]

# The load models (LOAD_MODELS, MODEL_NAMES, AXLE_LOAD_MODELS), the sprung masses' suspension, the integrator
# (DEFAULT_SOLVER), STEPS_PER_PERIOD, MAX_MODES and LATERAL_EI_RATIO are declared in .defaults (the command line
# shows them before any work).

#: ``"module:attribute"`` of ``train_axles(path) -> AxleTrain``: the static axle loads of a consist file (the
#: moving-load model with ``train_file``)
TRAIN_AXLES = "exudyn_wheelrail.scenarios.bridge_crossing_vehicles:train_axles"
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
#: the recorded columns after ``time_s`` and ``x_first_axle_m`` (module docstring)
DECK_COLUMNS = (("deck_midspan_displacement_m", "deck_midspan_velocity_m_s", "deck_midspan_acceleration_m_s2",
                 "deck_support_rotation_start_rad", "deck_support_rotation_end_rad")
                + tuple(f"deck_acceleration_p{k + 1}_m_s2" for k in range(len(CHECK_POINTS_X_OVER_L)))
                + ("deck_en1990_max_abs_acceleration_m_s2",))
#: the first span's lateral columns, recorded with lateral modes (module docstring)
LATERAL_COLUMNS = ("deck_lateral_midspan_displacement_m", "deck_lateral_midspan_acceleration_m_s2")
#: the columns of every span of a chain (``{k}`` = 1, 2, ...; the lateral ones with lateral modes)
SPAN_COLUMNS = ("deck_span{k}_midspan_displacement_m", "deck_span{k}_midspan_acceleration_m_s2",
                "deck_span{k}_en1990_max_abs_acceleration_m_s2")
SPAN_LATERAL_COLUMNS = ("deck_span{k}_lateral_midspan_displacement_m",
                        "deck_span{k}_lateral_midspan_acceleration_m_s2")


def deck_columns(case) -> tuple:
    """The deck's recorded columns of ``case`` after ``time_s`` and the axle columns: :data:`DECK_COLUMNS` (the
    first span), :data:`LATERAL_COLUMNS` with lateral modes, and per span of a chain :data:`SPAN_COLUMNS` (and
    :data:`SPAN_LATERAL_COLUMNS`)."""
    cols = DECK_COLUMNS + (LATERAL_COLUMNS if case.lateral_modes else ())
    if case.n_spans > 1:
        per = SPAN_COLUMNS + (SPAN_LATERAL_COLUMNS if case.lateral_modes else ())
        cols += tuple(c.format(k=k + 1) for k in range(case.n_spans) for c in per)
    return cols


#: keys every summary.json has (the command-line contract)
SUMMARY_KEYS = ("status", "max_abs_deck_midspan_displacement_m", "max_abs_deck_midspan_acceleration_m_s2",
                "solve_seconds", "simulated_seconds")


# ================================================================================================= the case
def _positive(name, value, *, allow_zero=False) -> float:
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

    span_m, mass_kg_m, f1_Hz : span length [m], deck mass per length [kg/m], first bending frequency [Hz].
    damping_ratio : modal damping ratio ζ of every mode, 0 ≤ ζ < 1.
    n_modes : vertical bending modes kept (1 … :data:`MAX_MODES`).
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

    def __post_init__(self):
        from ..simulation.solvers import SOLVERS
        for name in ("span_m", "mass_kg_m", "f1_Hz", "speed_m_s"):
            object.__setattr__(self, name, _positive(name, getattr(self, name)))
        z = _positive("damping_ratio", self.damping_ratio, allow_zero=True)
        if not z < 1.0:
            raise ValueError(f"damping_ratio: {z:g} must be < 1 (a ratio, not a percentage: 2 % is 0.02)")
        object.__setattr__(self, "damping_ratio", z)
        n = self.n_modes
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= MAX_MODES:
            raise ValueError(f"n_modes: {n!r} must be an integer from 1 to {MAX_MODES}")
        object.__setattr__(self, "n_modes", int(n))
        if self.axles is not None and not isinstance(self.axles, AxleTrain):
            raise ValueError(f"axles: expected an AxleTrain, got {type(self.axles).__name__}")
        if self.model not in LOAD_MODELS:
            raise ValueError(f"model: {self.model!r}: expected one of {', '.join(MODEL_NAMES)}")
        object.__setattr__(self, "free_vibration_s", _positive("free_vibration_s", self.free_vibration_s,
                                                               allow_zero=True))
        if self.spans_m is not None:
            spans = self.spans_m
            if isinstance(spans, (str, bytes)) or not hasattr(spans, "__len__") or len(spans) < 1:
                raise ValueError(f"spans_m: {spans!r}: expected a sequence of span lengths [m]")
            if len(spans) > MAX_SPANS:
                raise ValueError(f"spans_m: {len(spans)} spans, more than {MAX_SPANS}")
            spans = tuple(_positive(f"spans_m[{k}]", x) for k, x in enumerate(spans))
            if spans[0] != self.span_m:
                raise ValueError(f"spans_m: the first span {spans[0]:g} m is not span_m = {self.span_m:g} m (span_m is "
                                 "the first span of the chain)")
            object.__setattr__(self, "spans_m", spans)
        n = self.lateral_modes
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 0 <= n <= MAX_MODES:
            raise ValueError(f"lateral_modes: {n!r} must be an integer from 0 to {MAX_MODES}")
        object.__setattr__(self, "lateral_modes", int(n))
        if self.lateral_f1_Hz is not None:
            object.__setattr__(self, "lateral_f1_Hz", _positive("lateral_f1_Hz", self.lateral_f1_Hz))
        object.__setattr__(self, "sprung_frequency_Hz", _positive("sprung_frequency_Hz", self.sprung_frequency_Hz))
        zv = _positive("sprung_damping_ratio", self.sprung_damping_ratio, allow_zero=True)
        if not zv < 1.0:
            raise ValueError(f"sprung_damping_ratio: {zv:g} must be < 1 (a ratio, not a percentage)")
        object.__setattr__(self, "sprung_damping_ratio", zv)
        if self.dt_s is not None:
            dt = _positive("dt_s", self.dt_s)
            from ..simulation.runner import RESOLUTION_LIMIT
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

    @property
    def EI_Nm2(self) -> float:
        return flexural_rigidity_Nm2(self.span_m, self.mass_kg_m, self.f1_Hz)

    @property
    def EI_z_Nm2(self) -> float:
        """Lateral bending stiffness: from ``lateral_f1_Hz`` on the first span, else :data:`LATERAL_EI_RATIO`
        ``EI_y``."""
        if self.lateral_f1_Hz is None:
            return LATERAL_EI_RATIO * self.EI_Nm2
        return flexural_rigidity_Nm2(self.span_m, self.mass_kg_m, self.lateral_f1_Hz)

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
        the largest ``N² f1_k`` and ``N_L² f_L,k`` over the spans otherwise."""
        if self.spans_m is None and self.lateral_modes == 0:
            return self.n_modes ** 2 * self.f1_Hz
        f = max(self.n_modes ** 2 * self.span_f1_Hz(k) for k in range(self.n_spans))
        if self.lateral_modes:
            f = max(f, max(self.lateral_modes ** 2 * self.span_lateral_f1_Hz(k) for k in range(self.n_spans)))
        return f

    def as_dict(self) -> dict:
        return {"span_m": self.span_m, "mass_kg_m": self.mass_kg_m, "f1_Hz": self.f1_Hz,
                "damping_ratio": self.damping_ratio, "n_modes": self.n_modes, "speed_m_s": self.speed_m_s,
                "speed_km_h": self.speed_m_s * 3.6, "model": self.model, "free_vibration_s": self.free_vibration_s,
                "dt_s": self.dt_s, "solver": self.solver, "track_form": self.track_form,
                "train_file": self.train_file, "deck_start_m": self.deck_start_m, "spans_m": list(self.chain_m),
                "lateral_modes": self.lateral_modes, "lateral_f1_Hz": self.lateral_f1_Hz,
                "sprung_frequency_Hz": self.sprung_frequency_Hz, "sprung_damping_ratio": self.sprung_damping_ratio,
                "axles": None if self.axles is None else self.axles.as_dict()}


def default_dt_s(case: BridgeCrossing) -> float:
    """``min(1/(40 f_N), 2L/(40 N V), 10 ms)`` rounded down to 3 significant digits (module docstring; a chain: the
    shortest span, the highest mode of all spans, N the larger of the vertical and lateral mode counts)."""
    dt = min(1.0 / (STEPS_PER_PERIOD * case.f_N_Hz),
             2.0 * min(case.chain_m) / (STEPS_PER_PERIOD * max(case.n_modes, case.lateral_modes) * case.speed_m_s),
             MAX_DEFAULT_DT_S)
    scale = 10.0 ** (math.floor(math.log10(dt)) - 2)
    return math.floor(dt / scale + 1e-9) * scale


def deck_section(case: BridgeCrossing):
    """The :class:`~exudyn_wheelrail.structures.bridge.DeckSection` of every span: ``m``, ``EI_y`` from ``f1`` of
    the first span, ``EI_z`` (:attr:`BridgeCrossing.EI_z_Nm2`: from the lateral frequency, else
    :data:`LATERAL_EI_RATIO` ``EI_y``); the torsional (``GJ = EI_y``, ``I_p = m (2 m)²``) and axial
    (``EA = 1e3 EI_y / m²``) values are placeholders of the right order that do not act on the bending modes (beam
    axis = shear centre = centre of mass, rail height 0)."""
    from ..structures.bridge import DeckSection
    EI = case.EI_Nm2
    return DeckSection(m_kg_m=case.mass_kg_m, EI_y_Nm2=EI, EI_z_Nm2=case.EI_z_Nm2, GJ_Nm2=EI, EA_N=1e3 * EI,
                       Ip_kgm2_m=case.mass_kg_m * 4.0)


def _elements_per_span(case: BridgeCrossing) -> int:
    return max(MIN_ELEMENTS, ELEMENTS_PER_MODE * max(case.n_modes, case.lateral_modes))


def _span_modes(case: BridgeCrossing, k: int):
    """Span ``k`` alone (a simply supported :class:`~exudyn_wheelrail.structures.bridge.BridgeModel`): its
    ``N`` lowest vertical and ``N_L`` lowest lateral bending modes — ``(model, omega (N + N_L,), shapes)``, the
    vertical first.  A lateral mode keeps its lateral DOFs (v, θz) only: the section decouples them exactly from
    the others, so this removes the eigen-solver's rounding and vertical loads leave it exactly at rest."""
    from ..structures.bridge import N_DOF_NODE, BridgeModel
    n, n_l = case.n_modes, case.lateral_modes
    model = BridgeModel((case.chain_m[k],), deck_section(case), continuous=False, damping_ratio=case.damping_ratio,
                        rail_height_m=0.0, start_m=case.span_start_m(k), elements_per_span=_elements_per_span(case))
    f_top = n ** 2 * case.span_f1_Hz(k)
    if n_l:
        f_top = max(f_top, n_l ** 2 * case.span_lateral_f1_Hz(k))
    every = model.modes(f_max_Hz=1.05 * f_top)
    idx = every.of_kind("vertical")[:n]
    if idx.size < n:
        raise RuntimeError(f"the deck model has {idx.size} vertical modes below {1.05 * f_top:g} Hz, expected {n}")
    omega, shapes = every.omega_rad_s[idx], every.shapes[:, idx]
    if n_l:
        lat = every.of_kind("lateral")[:n_l]
        if lat.size < n_l:
            raise RuntimeError(f"the deck model has {lat.size} lateral modes below {1.05 * f_top:g} Hz, expected "
                               f"{n_l}")
        keep = np.zeros(model.n_dof, dtype=bool)
        keep[1::N_DOF_NODE] = keep[5::N_DOF_NODE] = True
        omega = np.concatenate([omega, every.omega_rad_s[lat]])
        shapes = np.concatenate([shapes, np.where(keep[:, None], every.shapes[:, lat], 0.0)], axis=1)
    return model, omega, shapes


@dataclass(frozen=True)
class DeckModes:
    """The modes of the deck (:func:`deck_modes`): ``modes`` (:class:`~exudyn_wheelrail.structures.bridge.
    BridgeModes` of the whole chain), ``vertical`` and ``lateral`` (per span, the indices of its modes in
    ``modes``)."""

    modes: object
    vertical: tuple
    lateral: tuple


def deck_modes(case: BridgeCrossing) -> DeckModes:
    """Every span's ``N`` vertical and ``N_L`` lateral bending modes, each span computed alone (the spans are
    independent simply supported decks: the modes of equal spans stay separate, never mixed as the eigenvectors
    of a repeated eigenvalue would be), as modes of the chain (:class:`~exudyn_wheelrail.structures.bridge.
    BridgeModel` with ``continuous=False``: doubled nodes at the joints); span after span, vertical first."""
    from ..structures.bridge import N_DOF_NODE, BridgeModel, BridgeModes
    n, n_l = case.n_modes, case.lateral_modes
    parts = [_span_modes(case, k) for k in range(case.n_spans)]
    if case.n_spans == 1:
        model, omega, shapes = parts[0]
    else:
        model = BridgeModel(case.chain_m, deck_section(case), continuous=False, damping_ratio=case.damping_ratio,
                            rail_height_m=0.0, start_m=case.deck_start_m, elements_per_span=_elements_per_span(case))
        per_span = N_DOF_NODE * (_elements_per_span(case) + 1)           # the nodes of a span, its own at joints
        shapes = np.zeros((model.n_dof, case.n_spans * (n + n_l)))
        for k, (_, _, sk) in enumerate(parts):
            shapes[k * per_span:(k + 1) * per_span, k * (n + n_l):(k + 1) * (n + n_l)] = sk
        omega = np.concatenate([p[1] for p in parts])
    first = [k * (n + n_l) for k in range(case.n_spans)]
    return DeckModes(BridgeModes(model, omega, shapes),
                     vertical=tuple(np.arange(i, i + n) for i in first),
                     lateral=tuple(np.arange(i + n, i + n + n_l) for i in first))


def vertical_modes(case: BridgeCrossing):
    """The N lowest vertical bending modes of the (first) span (:class:`~exudyn_wheelrail.structures.bridge.
    BridgeModes`)."""
    from dataclasses import replace

    from ..structures.bridge import BridgeModes
    model, omega, shapes = _span_modes(replace(case, spans_m=None, lateral_modes=0), 0)
    return BridgeModes(model, omega, shapes)


def en1990_cutoff_Hz(case: BridgeCrossing, span: int = 0) -> float:
    """EN 1990 A2.4.4.2.1(4)P: modes up to max(30 Hz, 1.5 f1, f3) (``f3 = 9 f1``) of span ``span`` (0-based)."""
    from .deck import en1990_cutoff_Hz as cutoff
    sec = deck_section(case)
    return cutoff((case.chain_m[span],), {f: getattr(sec, f) for f in ("m_kg_m", "EI_y_Nm2", "EI_z_Nm2", "GJ_Nm2",
                                                                          "EA_N", "Ip_kgm2_m")})


# ============================================================================================ load models
@dataclass
class LoadModelHandle:
    """What a load model hands back (:data:`LOAD_MODELS`).

    contact : the wheel–rail contact the run monitor watches (``None``: nothing to watch, e.g. moving loads).
    axle_x_m : the axles' distances behind the first axle (running order; the first 0) [m].
    axle_load_N : their static (downward) loads [N].
    modal_forces : ``modal_forces(mbs, t) -> Q`` — the generalized forces on the bridge's modal node at the state
        being recorded (n_modes,), for the modal accelerations.
    probes : extra recorder probes (:class:`~exudyn_wheelrail.simulation.recorder.Recorder`), recorded after the
        deck's columns.
    summary : ``summary(table) -> dict`` merged into ``summary.json`` under ``"load_model"`` (optional).
    description : one line for the summary and the console.
    max_dt_s : the largest time step the load model integrates correctly (e.g. the wheel–rail contact's
        resolution bound); the default step is not larger (``None``: no bound).  A given ``dt_s`` is used as given.
    """

    contact: object | None
    axle_x_m: np.ndarray
    axle_load_N: np.ndarray
    modal_forces: Callable
    probes: list = field(default_factory=list)
    summary: Callable | None = None
    description: str = ""
    max_dt_s: float | None = None


@dataclass(frozen=True)
class LoadModel:
    """A load model: ``check(case)`` (``ValueError`` naming the option; no work) and ``build(mbs, case, bridge)
    -> LoadModelHandle`` (``bridge`` the :class:`~exudyn_wheelrail.structures.bridge.ExudynBridge` of the deck, not
    assembled)."""

    check: Callable
    build: Callable


def _resolve(target: str, what: str, option: str):
    module, attr = target.split(":")
    try:
        mod = importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name is not None and module.startswith(exc.name):
            raise ValueError(f"{option}: {what} is not available in this installation (module {module} not "
                             "found)") from None
        raise
    entry = getattr(mod, attr, None)
    if entry is None:
        raise ValueError(f"{option}: {what} is not available in this installation ({module} has no {attr})")
    return entry


def resolve_load_model(name: str) -> LoadModel:
    """The :class:`LoadModel` of ``name`` (:data:`LOAD_MODELS`); ``ValueError`` ``"--model: ..."`` when it is not
    part of this installation."""
    if name not in LOAD_MODELS:
        raise ValueError(f"--model: {name!r}: expected one of {', '.join(MODEL_NAMES)}")
    return _resolve(LOAD_MODELS[name], f"the load model {name!r}", "--model")


def resolve_train_axles(path) -> AxleTrain:
    """The static axle loads of the consist file ``path`` (:data:`TRAIN_AXLES`); ``ValueError`` ``"--train: ..."``
    when consist files cannot be read by this installation."""
    reader = _resolve(TRAIN_AXLES, "reading the static axle loads of a consist file", "--train")
    return reader(path)


def _moving_loads_check(case: BridgeCrossing) -> None:
    if case.axles is None:
        raise ValueError("--axles/--hslm: the moving-load model needs the axle loads (give --axles FILE.csv or "
                         "--hslm A1..A10)")


def _moving_loads_build(mbs, case: BridgeCrossing, bridge) -> LoadModelHandle:
    ax = case.axles
    forces = np.zeros((ax.n_axles, 3))
    forces[:, 1] = ax.load_N                                      # Fz, z down: a weight is positive
    mf = bridge.add_moving_forces(mbs, -ax.x_m, forces, case.speed_m_s, s_start_m=case.deck_start_m,
                                  name="axle_loads")

    def modal_forces(mbs_, t):
        return mf.forces(t).copy()

    return LoadModelHandle(contact=None, axle_x_m=ax.x_m.copy(), axle_load_N=ax.load_N.copy(),
                           modal_forces=modal_forces,
                           description=f"{ax.n_axles} constant axle loads ({ax.name}) moving at "
                                       f"{case.speed_m_s * 3.6:.4g} km/h")


#: the constant moving axle loads
MOVING_LOADS = LoadModel(check=_moving_loads_check, build=_moving_loads_build)


# ================================================================================================ recording
class _FirstAxle:
    """``x_first_axle_m``: deck coordinate of the first axle, ``V t``; ``deck_midspan_static_displacement_m``: the
    quasi-static mid-span deflection under the static axle loads at their places (functions of the time)."""

    def __init__(self, case, axle_x_m, axle_load_N):
        self.V = float(case.speed_m_s)
        self.axles = AxleTrain(np.asarray(axle_x_m, dtype=float), np.asarray(axle_load_N, dtype=float),
                               name="static axle loads")
        self.L, self.EI = case.span_m, case.EI_Nm2
        self.columns = [("axle", "x_first_axle_m"), ("axle", "deck_midspan_static_displacement_m")]

    def fill_rows(self, t, rows):
        rows[:, 0] = self.V * t
        rows[:, 1] = quasi_static_midspan_deflection_m(t, self.axles, speed_m_s=self.V, span_m=self.L,
                                                       EI_Nm2=self.EI)


class _DeckProbe:
    """The deck's columns (:func:`deck_columns`) from the modal state and the modal accelerations."""

    def __init__(self, case, bridge, deck, modal_forces, cutoffs_Hz):
        modes = deck.modes
        cutoff_Hz = cutoffs_Hz[0]
        self.bridge, self.modal_forces = bridge, modal_forces
        L, x0 = case.span_m, case.deck_start_m
        phi, dphi = modes.shape_and_slope_at(np.array([x0 + 0.5 * L, x0, x0 + L]))
        self.phi_mid = phi[0, 1].copy()
        self.slopes = dphi[1:, 1].copy()                              # (2, n): dw/dx at the supports
        if case.n_spans > 1:       # x0 + L is also the start of span 2: the end node of span 1, dw/dx = -θy
            from ..structures.bridge import N_DOF_NODE
            self.slopes[1] = -modes.shapes[N_DOF_NODE * _elements_per_span(case) + 4]
        s_pts = x0 + L * np.asarray(CHECK_POINTS_X_OVER_L)
        self.phi_pts = modes.shape_at(s_pts)[:, 1, :].copy()
        keep = modes.frequencies_Hz <= 1.01 * cutoff_Hz          # FE frequencies lie slightly above the exact ones
        self.phi_pts_cut = np.where(keep[None, :], self.phi_pts, 0.0)
        self.w2 = np.diag(modes.modal_stiffness()).copy()
        self.d = np.diag(modes.modal_damping()).copy()
        self.columns = [("deck", c) for c in deck_columns(case)]
        self.lateral = bool(case.lateral_modes)
        # the lateral columns: the lateral modes' y rows (a vertical mode's lateral DOFs are the eigen-solver's
        # rounding, about 1e-13 of its vertical ones)
        lat = np.zeros(modes.n_modes, dtype=bool)
        for idx in deck.lateral:
            lat[idx] = True
        self.phi_lat_mid = np.where(lat, modes.shape_at(x0 + 0.5 * L)[0], 0.0) if self.lateral else None
        self.spans = []
        if case.n_spans > 1:
            for k in range(case.n_spans):
                xk, Lk = case.span_start_m(k), case.chain_m[k]
                mid = modes.shape_at(xk + 0.5 * Lk)
                mine = np.zeros(modes.n_modes, dtype=bool)
                mine[deck.vertical[k]] = True
                keep = mine & (modes.frequencies_Hz <= 1.01 * cutoffs_Hz[k])
                pts = modes.shape_at(xk + Lk * np.asarray(CHECK_POINTS_X_OVER_L))[:, 1, :]
                self.spans.append((mid[1].copy(), np.where(keep[None, :], pts, 0.0), np.where(lat, mid[0], 0.0)))

    def fill(self, mbs, t, out):
        q, q_t = (np.atleast_1d(v) for v in self.bridge.coordinates(mbs))      # a scalar for one mode
        q_tt = self.modal_forces(mbs, t) - self.w2 * q - self.d * q_t          # modal equations, M = I
        out[0] = self.phi_mid @ q
        out[1] = self.phi_mid @ q_t
        out[2] = self.phi_mid @ q_tt
        out[3:5] = self.slopes @ q
        k = 5 + self.phi_pts.shape[0]
        out[5:k] = self.phi_pts @ q_tt
        out[k] = np.max(np.abs(self.phi_pts_cut @ q_tt))
        k += 1
        if self.lateral:
            out[k] = self.phi_lat_mid @ q
            out[k + 1] = self.phi_lat_mid @ q_tt
            k += 2
        for phi_mid, phi_cut, phi_lat in self.spans:
            out[k] = phi_mid @ q
            out[k + 1] = phi_mid @ q_tt
            out[k + 2] = np.max(np.abs(phi_cut @ q_tt))
            k += 3
            if self.lateral:
                out[k] = phi_lat @ q
                out[k + 1] = phi_lat @ q_tt
                k += 2


# ==================================================================================================== run
@dataclass
class BridgeCrossingResult:
    """``timeseries`` (column -> array), ``summary`` (the contents of summary.json), the runner's ``outcome``,
    the written ``paths``."""

    timeseries: dict
    summary: dict
    outcome: object = None
    paths: dict = field(default_factory=dict)


def _max_abs(v):
    v = np.asarray(v, dtype=float)
    return float(np.max(np.abs(v))) if v.size and np.all(np.isfinite(v)) else None


def run_bridge_crossing(case: BridgeCrossing, out_dir=None, progress=False) -> BridgeCrossingResult:
    """Build the deck and the load model in Exudyn, run the crossing through the project's runner and evaluate
    it (module docstring); write ``timeseries.csv`` and ``summary.json`` into ``out_dir`` (None: nothing written).
    ``progress``: a progress bar — ``True`` on stderr, or a stream to draw it on; ``False``: none."""
    import exudyn as exu

    from ..simulation.recorder import PROGRESS_MIN_STEPS, ProgressBar, Recorder
    from ..simulation.runner import run
    from ..simulation.settings import RunSettings
    from ..structures.bridge import add_bridge

    load_model = resolve_load_model(case.model)
    load_model.check(case)
    t_build = time.perf_counter()
    deck = deck_modes(case)
    modes = deck.modes
    cutoffs = [en1990_cutoff_Hz(case, k) for k in range(case.n_spans)]
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    bridge = add_bridge(mbs, modes, "modal", name="deck")
    handle = load_model.build(mbs, case, bridge)
    axle_x = np.asarray(handle.axle_x_m, dtype=float)
    duration = (float(axle_x[-1]) + case.length_m) / case.speed_m_s + case.free_vibration_s
    dt = case.dt_s
    if dt is None:
        dt = default_dt_s(case) if handle.max_dt_s is None else min(default_dt_s(case), float(handle.max_dt_s))
    settings = RunSettings(solver=case.solver, dt_s=dt, duration_s=duration, progress=bool(progress))
    probes = [_FirstAxle(case, axle_x, handle.axle_load_N),
              _DeckProbe(case, bridge, deck, handle.modal_forces, cutoffs)]
    probes += list(handle.probes)
    recorder = Recorder(probes, n_rows_hint=settings.steps + 2)
    mbs.Assemble()
    if handle.contact is not None:
        handle.contact.warm_up(mbs, jacobian=settings.implicit)       # compiled code loaded before the timed solve
    build_seconds = time.perf_counter() - t_build
    bar = None
    if progress and settings.steps >= PROGRESS_MIN_STEPS:
        bar = ProgressBar(settings.end_time_s, stream=progress, label="bridge-crossing: ")
    outcome = run(mbs, settings, handle.contact, speed_m_s=case.speed_m_s, recorder=recorder, progress=bar)
    if bar is not None:
        bar.close(outcome.status.kind)
    ts = recorder.table()
    status = _deck_status(outcome.status, ts, _deflection_bound_m(modes, case, handle, settings.end_time_s),
                          deck_columns(case), _midspan_displacement_columns(case))
    summary = _summary(case, deck, cutoffs, handle, settings, outcome, ts, build_seconds, status)
    result = BridgeCrossingResult(timeseries=ts, summary=summary, outcome=outcome)
    if out_dir is not None:
        result.paths = write_bridge_crossing_outputs(result, out_dir)
    return result


#: margin of the deflection bound of :func:`_deflection_bound_m` (the loads of a vehicle model vary about their
#: static values)
DEFLECTION_BOUND_MARGIN = 10.0


def _deflection_bound_m(modes, case, handle, t_end_s) -> float:
    """An upper bound of the mid-span deflection of the integrated deck: from Duhamel's integral, a mode driven by
    ``|Q_j| ≤ Q̄_j`` from rest has ``|q_j(t)| ≤ Q̄_j t/ω_dj``; ``Q̄_j = Σ_k |P_k| max_x |φ_j(x)|`` (static axle
    loads); times :data:`DEFLECTION_BOUND_MARGIN`."""
    x0, L = case.deck_start_m, case.length_m
    phi = np.abs(modes.shape_at(x0 + L * np.linspace(0.0, 1.0, 200 * case.n_spans + 1))[:, 1, :])    # (201 K, n)
    q_bar = np.sum(np.abs(handle.axle_load_N)) * phi.max(axis=0)
    wd = modes.omega_rad_s * np.sqrt(1.0 - modes.damping_ratio ** 2)
    phi_mid = np.max([np.abs(modes.shape_at(case.span_start_m(k) + 0.5 * case.chain_m[k])[1])
                      for k in range(case.n_spans)], axis=0)
    return DEFLECTION_BOUND_MARGIN * float(np.sum(phi_mid * q_bar * t_end_s / wd))


def _midspan_displacement_columns(case) -> tuple:
    return ("deck_midspan_displacement_m",) + tuple(SPAN_COLUMNS[0].format(k=k + 1) for k in range(case.n_spans)
                                                    if case.n_spans > 1)


def _deck_status(status, ts, bound_m, columns=DECK_COLUMNS, midspan_columns=("deck_midspan_displacement_m",)):
    """The run's status, ``diverged`` when a deck value is not finite or a mid-span deflection exceeds the bound
    no stable integration can reach (:func:`_deflection_bound_m`): an unstable integration of the deck's modes (the
    runner watches wheel–rail contacts, not the deck)."""
    from ..simulation import status as S
    if status.kind != S.OK or not ts:
        return status
    bad = np.zeros(len(ts["time_s"]), dtype=bool)
    for c in midspan_columns:
        bad |= np.abs(ts[c]) > bound_m
    for c in columns:
        bad |= ~np.isfinite(ts[c])
    if not bad.any():
        return status
    t_bad = float(ts["time_s"][int(np.argmax(bad))])
    return S.RunStatus(S.DIVERGED, time_s=t_bad,
                       detail=f"the deck state is not finite or the mid-span deflection exceeds {bound_m:.3g} m, more "
                              "than the loads can cause: the integration of the deck's modes is unstable",
                       hint="reduce --dt or keep fewer modes (--modes)")


def _en1990(case, f_Hz, cutoff, reach, peak) -> dict:
    """The EN 1990 A2 deck-acceleration check of one span: ``f_Hz`` its vertical frequencies, ``peak`` the largest
    ``|a|`` over its check points with the modes up to ``cutoff``."""
    limit = EN1990_DECK_ACCELERATION_LIMITS_M_S2[case.track_form]
    limits = ", ".join(f"{v:g} m/s2 {k.replace('_', ' ')}" for k, v in EN1990_DECK_ACCELERATION_LIMITS_M_S2.items())
    judged = peak is not None and reach
    return {"rule": "EN 1990:2002/A1:2005 A2.4.4.2.1(4)P: peak vertical deck acceleration over x = L/10 ... 9L/10, "
                    f"modes up to max(30 Hz, 1.5 f1, f3); limits {limits}; the peak is that of the modal "
                    "accelerations of the modes kept up to the cut-off, unfiltered (with the vehicles model it "
                    "includes the wheel-rail forces' content above the cut-off: on the safe side)",
            "cutoff_Hz": cutoff, "modes_used": int(np.sum(f_Hz <= 1.01 * cutoff)), "modes_reach_cutoff": reach,
            "peak_acceleration_m_s2": peak, "track_form": case.track_form, "limit_m_s2": limit,
            "limits_m_s2": dict(EN1990_DECK_ACCELERATION_LIMITS_M_S2),
            "passed": bool(peak <= limit) if judged else None,
            "not_evaluated": (None if judged else "the modes kept do not reach the cut-off frequency" if
                              peak is not None else "no peak (the run did not complete)"),
            "utilisation": None if peak is None else peak / limit}


def _spans_summary(case, deck, cutoffs, ts, ok, spacing) -> list:
    """One entry per span of a chain: its place, frequencies, resonance speeds ``f1_k d/i``, peaks and EN 1990
    check."""
    out = []
    for k in range(case.n_spans):
        f = deck.modes.frequencies_Hz[deck.vertical[k]]
        col = [c.format(k=k + 1) for c in SPAN_COLUMNS]
        reach = bool(f[-1] >= cutoffs[k] or case.n_modes ** 2 * case.span_f1_Hz(k) >= cutoffs[k])
        entry = {"span": k + 1, "span_m": case.chain_m[k], "start_m": case.span_start_m(k),
                 "f1_Hz": case.span_f1_Hz(k), "frequencies_Hz": [float(x) for x in f],
                 "resonance_speeds_km_h": ([] if spacing is None else
                                           [3.6 * v for v in resonance_speeds_m_s(case.span_f1_Hz(k), spacing)]),
                 "max_abs_midspan_displacement_m": _max_abs(ts[col[0]]) if ok else None,
                 "max_abs_midspan_acceleration_m_s2": _max_abs(ts[col[1]]) if ok else None,
                 "EN1990_A2_deck_acceleration": _en1990(case, f, cutoffs[k], reach, _max_abs(ts[col[2]]))
                 if ok else None}
        if case.lateral_modes:
            lat = [c.format(k=k + 1) for c in SPAN_LATERAL_COLUMNS]
            entry.update({"lateral_frequencies_Hz": [float(x) for x in deck.modes.frequencies_Hz[deck.lateral[k]]],
                          "max_abs_lateral_midspan_displacement_m": _max_abs(ts[lat[0]]) if ok else None,
                          "max_abs_lateral_midspan_acceleration_m_s2": _max_abs(ts[lat[1]]) if ok else None})
        out.append(entry)
    return out


def _summary(case, deck, cutoffs, handle, settings, outcome, ts, build_seconds, status) -> dict:
    from ..simulation import status as S
    ok = status.kind == S.OK and len(ts.get("time_s", ())) > 0
    sim = float(outcome.t_end_s)
    axle_x = np.asarray(handle.axle_x_m, dtype=float)
    spacing = characteristic_spacing_m(axle_x) if case.axles is None else case.axles.spacing_m
    cutoff = cutoffs[0]
    f_first = deck.modes.frequencies_Hz[deck.vertical[0]]                 # the first span's vertical modes
    f1_fe = float(f_first[0])
    res = []
    if spacing is not None:
        for i, v in enumerate(resonance_speeds_m_s(case.f1_Hz, spacing), 1):
            res.append({"i": i, "speed_m_s": v, "speed_km_h": v * 3.6})
    notes = []
    en = None
    reach = bool(f_first[-1] >= cutoff or case.n_modes ** 2 * case.f1_Hz >= cutoff)
    if not reach:
        notes.append(f"the {case.n_modes} modes kept end at {f_first[-1]:.4g} Hz, below the EN 1990 "
                     f"cut-off {cutoff:.4g} Hz: keep more modes (--modes) for the deck-acceleration check")
    if ok:
        en = _en1990(case, f_first, cutoff, reach, _max_abs(ts["deck_en1990_max_abs_acceleration_m_s2"]))
    else:
        notes.append(f"the run {status.kind}: peaks and the EN 1990 check are not evaluated")
    if res:
        near = min(res, key=lambda r: abs(r["speed_m_s"] - case.speed_m_s))
        if abs(near["speed_m_s"] / case.speed_m_s - 1.0) < 0.02:
            notes.append(f"the speed is within 2 % of the resonance speed v_{near['i']} = f1 d/{near['i']} = "
                         f"{near['speed_km_h']:.4g} km/h")
    notes += list(outcome.warnings)
    frac_cycle = (case.f_N_Hz * float(settings.dt_s))
    if case.dt_s is not None and frac_cycle > 1.0 / 10.0:
        notes.append(f"dt = {settings.dt_s:g} s has {1.0 / frac_cycle:.3g} steps per period of mode {case.n_modes} "
                     f"({case.f_N_Hz:g} Hz): its acceleration is not resolved (default dt {default_dt_s(case):.3g} s)")
    peaks = {}
    quasi_static = None
    if ok:
        for c in deck_columns(case):
            peaks[f"max_abs_{c}"] = _max_abs(ts[c])
        w_st = _max_abs(ts["deck_midspan_static_displacement_m"])
        quasi_static = {"rule": "mid-span influence line of the static axle loads, P a (3L^2 - 4a^2)/(48 EI)",
                        "max_midspan_displacement_m": w_st,
                        "dynamic_amplification": (peaks["max_abs_deck_midspan_displacement_m"] / w_st
                                                  if w_st else None)}
    extra = None
    if handle.summary is not None:
        extra = handle.summary(ts) if ok else {"error": f"not evaluated: the run {status.kind}"}
    out = {
        "status": status.kind,
        "status_detail": status.as_dict(),
        "max_abs_deck_midspan_displacement_m": peaks.get("max_abs_deck_midspan_displacement_m"),
        "max_abs_deck_midspan_acceleration_m_s2": peaks.get("max_abs_deck_midspan_acceleration_m_s2"),
        "solve_seconds": outcome.solve_seconds,
        "simulated_seconds": sim,
        "real_time_factor": sim / outcome.solve_seconds if outcome.solve_seconds > 0 else None,
        "build_seconds": build_seconds,
        "steps": settings.steps,
        "dt_s": float(settings.dt_s),
        "dt_rule": (f"min(1/({STEPS_PER_PERIOD} f_N), 2L/({STEPS_PER_PERIOD} N V), {MAX_DEFAULT_DT_S:g} s"
                    + (f", the load model's {handle.max_dt_s:g} s" if handle.max_dt_s is not None else "") + ")"
                    if case.dt_s is None else "given"),
        "duration_s": settings.end_time_s,
        "t_last_axle_leaves_s": (float(axle_x[-1]) + case.length_m) / case.speed_m_s,
        "rejected_steps": outcome.rejected_steps,
        "solver": {"name": settings.solver, "exudyn": settings.describe_solver()},
        "inputs": case.as_dict(),
        "load_model": {"name": case.model, "description": handle.description, "n_axles": int(axle_x.size),
                       "axle_x_m": axle_x, "axle_load_N": np.asarray(handle.axle_load_N, dtype=float),
                       **({"details": extra} if extra is not None else {})},
        "EI_Nm2": case.EI_Nm2,
        "frequencies_Hz": [float(f) for f in f_first],
        "frequencies_euler_bernoulli_Hz": simply_supported_frequencies_Hz(case.f1_Hz, case.n_modes).tolist(),
        "f1_fe_relative_error": f1_fe / case.f1_Hz - 1.0,
        "characteristic_spacing_m": spacing,
        "resonance_speeds": res,
        "EN1990_A2_deck_acceleration": en,
        "quasi_static": quasi_static,
        "peaks": peaks,
        "sign_conventions": {"deck": "vertical displacement, velocity and acceleration positive downward (z down); "
                                     "support rotations dw/dx (x along the span from the first support)",
                             "x_first_axle_m": "deck coordinate of the first axle, V t"},
        "notes": notes,
    }
    if case.lateral_modes:
        f_lat = deck.modes.frequencies_Hz[deck.lateral[0]]
        for c in LATERAL_COLUMNS:
            out[f"max_abs_{c}"] = peaks.get(f"max_abs_{c}")
        out["lateral"] = {"n_modes": case.lateral_modes, "EI_z_Nm2": case.EI_z_Nm2,
                          "lateral_f1_Hz": case.span_lateral_f1_Hz(0),
                          "EI_z_rule": ("from --lateral-frequency-hz on the first span"
                                        if case.lateral_f1_Hz is not None else f"EI_z = {LATERAL_EI_RATIO:g} EI_y"),
                          "frequencies_Hz": [float(f) for f in f_lat],
                          "sign": "lateral displacement and acceleration along the track's y axis"}
    if case.n_spans > 1:
        out["spans"] = _spans_summary(case, deck, cutoffs, ts, ok, spacing)
        checks = [sp["EN1990_A2_deck_acceleration"] for sp in out["spans"]]
        out["EN1990_A2_all_spans_passed"] = (None if not ok or any(c is None or c["passed"] is None for c in checks)
                                             else all(c["passed"] for c in checks))
    return out


def write_bridge_crossing_outputs(result: BridgeCrossingResult, out_dir) -> dict:
    """``timeseries.csv`` (every recorded column) and ``summary.json`` into ``out_dir`` (created); returns the
    paths."""
    from .outputs import write_csv, write_json
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"timeseries_csv": out / "timeseries.csv", "summary": out / "summary.json"}
    write_csv(paths["timeseries_csv"], result.timeseries)
    write_json(paths["summary"], result.summary)
    return {k: str(v) for k, v in paths.items()}


# ============================================================================================= speed sweep
#: the columns of a speed sweep's table (sweep.csv), in order
SWEEP_COLUMNS = ("case", "speed_km_h", "status", "max_abs_deck_midspan_displacement_m",
                 "max_abs_deck_midspan_acceleration_m_s2", "en1990_peak_acceleration_m_s2", "en1990_passed",
                 "solve_seconds", "simulated_seconds", "steps", "case_dir")


@dataclass
class SpeedSweepResult:
    """``table`` (column -> list, one entry per speed, :data:`SWEEP_COLUMNS`), the base ``case``, the
    ``resonance_speeds`` of the train on the span, the written ``paths``, the sweep's ``wall_seconds``."""

    table: dict
    case: BridgeCrossing
    resonance_speeds: list
    wall_seconds: float = 0.0
    paths: dict = field(default_factory=dict)


def sweep_case(case: BridgeCrossing, case_dir=None) -> dict:
    """One speed of a sweep (runs in the worker): the row of :data:`SWEEP_COLUMNS`; an exception becomes
    ``status = "error: ..."`` (one case does not stop the others)."""
    row = {"speed_km_h": case.speed_m_s * 3.6, "case_dir": None if case_dir is None else str(case_dir)}
    try:
        s = run_bridge_crossing(case, out_dir=case_dir).summary
    except Exception as exc:
        return {**row, "status": f"error: {type(exc).__name__}: {exc}".splitlines()[0]}
    en = s["EN1990_A2_deck_acceleration"] or {}
    return {**row, "status": s["status"],
            "max_abs_deck_midspan_displacement_m": s["max_abs_deck_midspan_displacement_m"],
            "max_abs_deck_midspan_acceleration_m_s2": s["max_abs_deck_midspan_acceleration_m_s2"],
            "en1990_peak_acceleration_m_s2": en.get("peak_acceleration_m_s2"), "en1990_passed": en.get("passed"),
            "solve_seconds": s["solve_seconds"], "simulated_seconds": s["simulated_seconds"], "steps": s["steps"]}


def speed_sweep(case: BridgeCrossing, speeds_m_s, executor=None, out_dir=None, *, workers: int | None = None,
                write_cases: bool = False, progress=print) -> SpeedSweepResult:
    """``case`` at every speed of ``speeds_m_s``, one task per speed through ``executor`` — the executors of the
    scenario sweeps (:mod:`.sweep`: ``None`` a local process pool of ``workers`` spawned processes, any
    ``concurrent.futures.Executor``, a Dask client, :class:`~.sweep.SerialExecutor`); with ``out_dir``:
    ``sweep.csv``, ``sweep.json`` and ``sweep_plot.png`` (peak mid-span displacement and acceleration against the
    speed, the resonance speeds ``v_i = f1 d/i`` marked, the EN 1990 limit drawn), and each speed's own outputs
    under ``cases/`` with ``write_cases``."""
    from concurrent.futures import as_completed
    from dataclasses import replace

    from .sweep import _executor
    speeds = [_positive("speeds_m_s", v) for v in speeds_m_s]
    if not speeds:
        raise ValueError("speeds_m_s: no speed given")
    resolve_load_model(case.model).check(case)
    out = Path(out_dir) if out_dir is not None else None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    dirs = [str(out / "cases" / f"v{v * 3.6:07.2f}_kmh") if (out is not None and write_cases) else None
            for v in speeds]
    cases = [replace(case, speed_m_s=v) for v in speeds]
    rows = [None] * len(cases)
    t0 = time.perf_counter()
    pool, own = _executor(executor, workers, len(cases))
    try:
        futures = {pool.submit(sweep_case, c, d): i for i, (c, d) in enumerate(zip(cases, dirs))}
        for f in as_completed(futures):
            i = futures[f]
            try:
                rows[i] = f.result()
            except Exception as exc:              # the executor itself failed
                rows[i] = {"speed_km_h": speeds[i] * 3.6, "case_dir": dirs[i],
                           "status": f"error: executor: {type(exc).__name__}: {exc}".splitlines()[0]}
            if progress:
                r = rows[i]
                a = r.get("max_abs_deck_midspan_acceleration_m_s2")
                progress(f"  {r['speed_km_h']:.5g} km/h: {r['status']}" + (f"; max |a| {a:.4g} m/s^2" if a else ""))
    finally:
        if own:
            pool.shutdown()
    wall = time.perf_counter() - t0
    table = {c: [] for c in SWEEP_COLUMNS}
    for i, r in enumerate(rows):
        for c in SWEEP_COLUMNS:
            table[c].append(i if c == "case" else r.get(c))
    spacing = case.axles.spacing_m if case.axles is not None else None
    res = [] if spacing is None else [{"i": i, "speed_m_s": v, "speed_km_h": v * 3.6}
                                      for i, v in enumerate(resonance_speeds_m_s(case.f1_Hz, spacing), 1)]
    result = SpeedSweepResult(table=table, case=case, resonance_speeds=res, wall_seconds=wall)
    if out is not None:
        result.paths = _write_sweep(result, out)
    return result


def _write_sweep(result: SpeedSweepResult, out: Path) -> dict:
    import csv
    import json

    from .outputs import jsonable
    t = result.table
    paths = {"csv": out / "sweep.csv", "json": out / "sweep.json", "plot": out / "sweep_plot.png"}
    with open(paths["csv"], "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(list(t))
        for i in range(len(t["case"])):
            w.writerow(["" if t[c][i] is None else (repr(t[c][i]) if isinstance(t[c][i], float) else t[c][i])
                        for c in t])
    with open(paths["json"], "w") as fh:
        json.dump({"case": result.case.as_dict(), "resonance_speeds": result.resonance_speeds,
                   "wall_seconds": result.wall_seconds, "table": t}, fh, indent=1, allow_nan=True, default=jsonable)
    plot_speed_sweep(result, paths["plot"])
    return {k: str(v) for k, v in paths.items()}


def plot_speed_sweep(result: SpeedSweepResult, path) -> None:
    """Peak mid-span displacement and acceleration against the speed (``ok`` cases), the resonance speeds
    ``v_i = f1 d/i`` inside the swept range as dashed vertical lines, the EN 1990 limit as a horizontal line."""
    from .plots import pyplot
    plt = pyplot()
    t = result.table
    ok = [i for i in range(len(t["case"])) if t["status"][i] == "ok"]
    v = np.array([t["speed_km_h"][i] for i in ok])
    order = np.argsort(v)
    fig, axes = plt.subplots(2, 1, figsize=(7.5, 6.0), sharex=True)
    for ax, col, scale, label in ((axes[0], "max_abs_deck_midspan_displacement_m", 1e3, "max |w| mid-span [mm]"),
                                  (axes[1], "max_abs_deck_midspan_acceleration_m_s2", 1.0,
                                   "max |a| mid-span [m/s²]")):
        y = np.array([t[col][i] for i in ok], dtype=float) * scale
        ax.plot(v[order], y[order], "o-", ms=3)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    c = result.case
    limit = EN1990_DECK_ACCELERATION_LIMITS_M_S2[c.track_form]
    axes[1].axhline(limit, color="C3", lw=1, label=f"EN 1990 A2 limit ({c.track_form.replace('_', ' ')}) {limit:g} "
                                                   "m/s²")
    if v.size:
        lo, hi = float(v.min()), float(v.max())
        for r in result.resonance_speeds:
            if lo <= r["speed_km_h"] <= hi:
                for ax in axes:
                    ax.axvline(r["speed_km_h"], color="0.4", ls="--", lw=0.8)
                axes[0].annotate(f"f1 d/{r['i']}", (r["speed_km_h"], 1.0), xycoords=("data", "axes fraction"),
                                 ha="center", va="bottom", fontsize=7)
    axes[1].legend(fontsize=7)
    axes[1].set_xlabel("speed [km/h]")
    name = c.axles.name if c.axles is not None else c.train_file
    fig.suptitle(f"{name} over L = {c.span_m:g} m, f1 = {c.f1_Hz:g} Hz, ζ = {c.damping_ratio:g}, {c.n_modes} modes, "
                 f"{c.model}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
