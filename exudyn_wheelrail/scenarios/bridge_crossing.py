r"""A train crossing a simply supported span (a chain of them, a continuous deck, a deck from a modes file): the deck
in Exudyn, the train by a load model, one run through the project's runner, the deck's outputs (``python -m
exudyn_wheelrail bridge-crossing``).

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
every mode, entered into Exudyn by :func:`~exudyn_wheelrail.structures.bridge_exudyn.add_bridge` (``"modal"``: one
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

A continuous deck, a modes file
-------------------------------
``continuous=True`` (``--continuous``): the spans form **one deck continuous over its intermediate supports** (the
built-in beam, :func:`~.bridge_crossing_deck.continuous_modes`): its ``N K`` lowest vertical (and ``N_L K``
lateral) modes, the section of the first span (``EI`` from ``f1`` as for a simply supported first span); the time
step's highest frequency is bounded by the N-th clamped–clamped frequency of the stiffest span
(:data:`~.bridge_crossing_case.CLAMPED_BAND`).  ``modes_file`` (``--modes-file``): the deck of an FE program's modes
(:mod:`~exudyn_wheelrail.structures.modes_file`: mass-normalised with the given modal masses, splines between the
positions broken at the spans' supports; :func:`~.bridge_crossing_deck.file_modes`), its ``N`` lowest modes, its
damping ratios unless one is given, a mass bound by ``mass_scale``.  For both, a span's modes are those that move
it, its ``f1`` (resonance speeds) and EN 1990 cut-off ``max(30 Hz, 1.5 f1, f3)`` from its first and third vertical
modes, and the quasi-static deflection is the static response of the modes kept
(:class:`~.bridge_crossing_probes.FirstAxleProbe`); ``summary.json``'s ``deck`` says which deck ran.

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
(:class:`~exudyn_wheelrail.structures.bridge_exudyn.MovingForces`: ``Q = Σ Φ(s_k(t))ᵀ F_k`` in one compiled call).
``"vehicles"``: the full vehicle–bridge interaction, provided by
``exudyn_wheelrail.scenarios.bridge_crossing_vehicles`` (module attribute ``VEHICLES``); when that module is not
part of the installation the command stops before any work with ``error: --model: ...`` (exit code 2).
``"sprung-masses"``: every axle a mass on a spring and a damper riding on the deck
(``exudyn_wheelrail.scenarios.bridge_crossing_sprung``, its docstring: the equations and the assumed default
suspension :data:`SPRUNG_FREQUENCY_HZ`, :data:`SPRUNG_DAMPING_RATIO`). A consist file (``train_file``) gives the
axle-load models (:data:`AXLE_LOAD_MODELS`) its static axle loads (:func:`~.bridge_crossing_loads.consist_axles`; a
file that cannot be read: ``error: --train: ...``).

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
dynamic over it), the run settings, notes and ``scalars`` (the flat results a scenario sweep tabulates,
:func:`~.bridge_crossing_summary.crossing_scalars`).  Peaks of a run that did not end ``ok`` are not evaluated
(``None``; no scalars).

Speed sweeps (:func:`speed_sweep`, ``python -m exudyn_wheelrail bridge-crossing-sweep``)
---------------------------------------------------------------------------------------
The same crossing at many speeds, one task per speed through the executors of the scenario sweeps
(:mod:`.sweep`: a local pool of spawned processes, any ``concurrent.futures.Executor``, a Dask client): one row
per speed (:data:`SWEEP_COLUMNS`) in ``sweep.csv`` / ``sweep.json`` and ``sweep_plot.png`` — the peak mid-span
displacement and acceleration against the speed with the resonance speeds ``v_i = f1 d/i`` marked and the EN 1990
limit drawn.

The modules
-----------
This module is the public import path of the crossing: it re-exports the public names of the modules that do the
work, one job each — :mod:`.bridge_crossing_case` (the case, its checks, its default step),
:mod:`.bridge_crossing_deck` (the deck's section and modes), :mod:`.bridge_crossing_loads` (the load models),
:mod:`.bridge_crossing_probes` (the recorded columns), :mod:`.bridge_crossing_summary` (the status, the EN 1990
check, ``summary.json``, the result of a run), :mod:`.bridge_crossing_run` (a case built in Python through the
scenario's stages: :func:`~.build.build_crossing`, the runner, the evaluation, the writer) and
:mod:`.bridge_crossing_sweep` (the speed sweeps).
"""
from __future__ import annotations

from .bridge_crossing_case import (ELEMENTS_PER_MODE, F1_HZ, FREE_VIBRATION_S, MASS_KG_M, MAX_DEFAULT_DT_S, MAX_SPANS,
                                   MIN_ELEMENTS, SPAN_M, BridgeCrossing, default_dt_s)
from .bridge_crossing_deck import DeckModes, deck_modes, deck_section, en1990_cutoff_Hz, vertical_modes
from .bridge_crossing_loads import MOVING_LOADS, LoadModel, LoadModelHandle, consist_axles, resolve_load_model
from .bridge_crossing_probes import DECK_COLUMNS, LATERAL_COLUMNS, SPAN_COLUMNS, SPAN_LATERAL_COLUMNS, deck_columns
from .bridge_crossing_run import run_bridge_crossing
from .bridge_crossing_summary import SUMMARY_KEYS
from .bridge_crossing_sweep import SWEEP_COLUMNS, SpeedSweepResult, plot_speed_sweep, speed_sweep, sweep_case
from .defaults import (AXLE_LOAD_MODELS, DEFAULT_SOLVER, LATERAL_EI_RATIO, LOAD_MODELS, MAX_MODES, MODEL_NAMES,
                       SPRUNG_DAMPING_RATIO, SPRUNG_FREQUENCY_HZ, STEPS_PER_PERIOD)

__all__ = ["BridgeCrossing", "LoadModel", "LoadModelHandle", "LOAD_MODELS", "MODEL_NAMES",
           "DEFAULT_SOLVER", "STEPS_PER_PERIOD", "MAX_DEFAULT_DT_S", "MIN_ELEMENTS", "ELEMENTS_PER_MODE",
           "MAX_MODES", "DECK_COLUMNS", "SUMMARY_KEYS", "deck_section", "vertical_modes", "default_dt_s",
           "resolve_load_model", "consist_axles", "en1990_cutoff_Hz", "SPAN_M", "MASS_KG_M",
           "F1_HZ", "FREE_VIBRATION_S", "run_bridge_crossing",
           "MOVING_LOADS", "SWEEP_COLUMNS", "SpeedSweepResult", "sweep_case", "speed_sweep", "plot_speed_sweep",
           "DeckModes", "deck_modes", "deck_columns", "LATERAL_COLUMNS", "SPAN_COLUMNS", "SPAN_LATERAL_COLUMNS",
           "MAX_SPANS", "LATERAL_EI_RATIO", "AXLE_LOAD_MODELS", "SPRUNG_FREQUENCY_HZ", "SPRUNG_DAMPING_RATIO"]

# The load models (LOAD_MODELS, MODEL_NAMES, AXLE_LOAD_MODELS), the sprung masses' suspension, the integrator
# (DEFAULT_SOLVER), STEPS_PER_PERIOD, MAX_MODES and LATERAL_EI_RATIO are declared in .defaults (the command line
# shows them before any work).
