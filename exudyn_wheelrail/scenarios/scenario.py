r"""Scenario files: a whole simulation (vehicle, track, optional flexible bridge, contact and run settings, outputs)
in one TOML file, run by :func:`run_scenario` or ``python -m exudyn_wheelrail run SCENARIO.toml --out DIR``.

>>> scenario = load_scenario("examples/scenarios/rtri_20m.toml")        # doctest: +SKIP
>>> result = run_scenario(scenario, "out/rtri_20m")                      # doctest: +SKIP
>>> result.summary["status"], result.summary["criteria"]["safety_passed"]  # doctest: +SKIP

The normalised scenario is the **spec** of the simulation pipeline (:mod:`exudyn_wheelrail.simulation`):
:func:`build_scenario` turns it into the Exudyn model — the vehicle of a data file
(:func:`~exudyn_wheelrail.multibody.build_vehicle`, frame moving with the running speed V), the wheel–rail connector
(:func:`~exudyn_wheelrail.multibody.add_wheel_rail_contact`) on a rigid straight track
(:class:`~exudyn_wheelrail.multibody.RigidStraightTrack`) displaced by the listed irregularities, optionally laid
out as a curve (a ``[layout]``: the connector's ``layout=`` and the track-following frames of
:mod:`exudyn_wheelrail.rolling_stock.track_following`), optionally a modally reduced bridge deck (:mod:`exudyn_wheelrail.structures.bridge`, coupled through the connector's ``structure=``)
with an optional lateral support motion, the vehicle in static equilibrium on the rails at t = 0
(:func:`~exudyn_wheelrail.multibody.place_on_rails`) — and the recorder; :func:`run_scenario` runs it through the
one solve wrapper (:func:`exudyn_wheelrail.simulation.runner.run`: watched by the run monitor, a status of
:mod:`exudyn_wheelrail.simulation.status`) and evaluates it.  The RTRI case (:mod:`.rtri`) is such a spec, and so
is the ``curving`` command's run (:mod:`.curving`: a spec with a ``[layout]`` filled from its case, built by
:func:`build_scenario`, run by :func:`run_model`, written by :func:`write_json` / :func:`write_csv`; its own part is
the steady-state evaluation).  What a Python caller holds as an object — a vehicle's data, a wheel–rail pair, an
irregularity of any kind — goes to :func:`build_scenario` as a keyword argument (its Python-only inputs,
:mod:`.build`), not into the spec.

The modules, one job each (this module is the public import path: it re-exports their public names):
:mod:`.spec` — the schema's constants, the loader and the validation (``[layout]``: :mod:`.spec_layout`; a bridge
crossing: :mod:`.spec_crossing`);
:mod:`.overrides` — the dotted-key overrides; :mod:`.build` — spec → Exudyn model; :mod:`.deck` — the flexible deck's support motion, recorded
columns and summary; :mod:`.run` — the run and its summary (peaks, scalars, criteria, notes); :mod:`.result` —
the result of a run (:class:`ScenarioResult`); :mod:`.outputs` and :mod:`.plots` — the files (the package's one
writer of time series and summaries: CSV with 10 significant digits, JSON with non-finite numbers as ``null``) and
the figures.

Schema (``schema_version = 2``)
===============================
SI units, the unit in every key name; track frame of :mod:`exudyn_wheelrail.conventions` (x forward, y right,
z down); ``s`` is the track distance.  Tables and keys not listed are errors, as are missing required keys and
values of the wrong type or range: :class:`ScenarioError` (a ``ValueError``) names the file and the key
(``track.0.amplitude_m``, the dotted form the sweep overrides use); lengths and times outside their plausible
range (:data:`QUANTITIES`, :mod:`exudyn_wheelrail.simulation.settings`; e.g. an amplitude in millimetres) are
errors too.  File paths are relative to the scenario file.  A file of ``schema_version = 1`` (speed, start, creep
law, friction and FASTSIM grid in ``[run]``) is read with those keys moved to their tables (:data:`V1_MOVED`);
dotted overrides with the old keys are moved the same way.

``schema_version = 2``  (required)

``[scenario]`` (optional)
    ``name`` (default: the file name without ``.toml``), ``description`` (default "").

``[vehicle]`` (required) — exactly one of ``name`` (a shipped vehicle, ``vehicles/<name>.toml``, e.g.
    ``"manchester_vehicle1"``), ``file`` (a vehicle data file, schema: ``vehicles/README.md``) or ``consist`` (a
    train: a shipped consist of ``vehicles/trains/`` or a consist file, :mod:`exudyn_wheelrail.rolling_stock.train`),
    and ``speed_km_h`` (required, 0 < V ≤ 600), ``start_s_m`` (track distance of the **leading** wheelset — of
    the train's first car for a consist — at t = 0, default 0), ``overrides`` (optional table, not for a
    consist: numeric values of the vehicle file replaced for this run, by ``"table.key"``, e.g.
    ``"primary.ky_N_per_m" = 7.8e6``; :func:`~..rolling_stock.vehicle_data.load_vehicle_with_overrides`).  The wheel
    and rail profiles, gauge, inclination and back-to-back distance come from the vehicle file (the first car's
    for a train).  A train's wheel columns number its wheelsets front to back over the whole train (``w1`` …),
    its car-body points are named ``<point>_c<k>`` (car k from the front), and the criteria are given for the
    train and per car (``criteria.cars``).

``[[track]]`` (optional, any number; none = a perfect straight track) — irregularity components, summed, on the
    four channels of :mod:`exudyn_wheelrail.conventions` (alignment, level, cross level, gauge; ``direction``
    "lateral" = alignment, "vertical" = level):
    ``type = "span_deflection"``: ``span_length_m``, ``amplitude_m``, ``start_m`` (s of the span start),
    optional ``transition_length_m`` (0; C2 end transitions centred on the span ends), ``direction``
    ("lateral" | "vertical" | "cross_level" | "gauge", default "lateral") —
    :class:`~..track.rigid.SpanDeflection`.
    ``type = "harmonic"``: ``amplitude_m``, ``wavelength_m``, optional ``phase_rad`` (0), ``direction``
    ("lateral") — ``amplitude sin(2π s/wavelength + phase)`` along the whole track.
    ``type = "sampled"``: ``file`` — a CSV file with the columns ``s_m, y_m, z_m`` (``#`` comments allowed),
    cubic-spline interpolated, held constant outside the table
    (:meth:`~..track.rigid.SampledIrregularity.from_csv`).
    ``type = "measured"``: ``file`` — a CSV file of ``s_m`` and the four channels or the rails' ``y_right``,
    ``y_left``, ``z_right``, ``z_left``, each with its unit ``_m`` or ``_mm`` (:mod:`exudyn_wheelrail.track.measured`).
    ``type = "spectrum"``: generated from a standard PSD (:mod:`exudyn_wheelrail.track.spectra`: ``spectrum`` =
    "fra_class_1" … "fra_class_6", "german_low", "german_high"), ``seed`` (required), ``length_m``, optional
    ``band_m`` ([3, 150]), ``step_m``, ``start_m``, ``channels`` (all four), ``scale`` (1), ``fade_in_m`` (0: none;
    a raised-cosine fade from zero at ``start_m`` over that length, :class:`~..track.irregularities.FadedIn`).
    ``type = "defect"``: an isolated defect of one rail or both (:class:`~..track.irregularities.IsolatedDefect`):
    ``shape`` ("bump" | "cusp" | "dipped_joint"), ``position_m``, ``length_m``, ``depth_m``, optional ``rail``
    ("right" | "left" | "both"), ``direction`` ("vertical" | "lateral").  Full example:
    ``examples/scenarios/README.md``.

``[layout]`` (optional; none = straight track) — the track's horizontal alignment and cant: straight track up to
    ``start_m``, a clothoid transition of ``transition_m`` with a linear cant ramp, then a circular curve of
    ``radius_m`` and ``cant_m`` to the end of the run (:meth:`~..track.layout.TrackLayout.curve_entry`, the curve
    of the ``curving`` command, :mod:`.curving`).  ``radius_m`` (required; at most
    :data:`~..track.layout.MAX_RADIUS_M` and not below the smallest radius the vehicle can follow,
    :func:`~..analysis.curving.minimum_radius_m`), ``cant_m`` (required, 0 ≤ h ≤
    :data:`~..track.layout.MAX_CANT_M`, raises the outer rail), ``transition_m`` (default: the cant ramp
    1 : :data:`~.defaults.DEFAULT_RAMP`, at least :data:`~.defaults.DEFAULT_MIN_TRANSITION_M`; at most
    :data:`~..track.layout.MAX_TRANSITION_M`; 0 only without cant), ``direction`` ("right" (default) | "left"),
    ``start_m`` (s where the transition starts, default :data:`~.defaults.LEAD_IN_M`; not behind the leading
    wheelset: the vehicle starts in equilibrium on the straight).  Every body then moves in its own track-following
    frame (:class:`~..rolling_stock.track_following.TrackFollowingFrame`, updated before every step) and the
    contact sees the rails of the layout at each wheelset's s; the ``[[track]]`` irregularities displace them
    relative to the local track frame and must vanish, with their slopes, under every wheelset at t = 0 (the build
    refuses others, naming ``track``).  An explicit ``run.solver`` without ``run.dt_s`` takes the ``curving``
    command's step: 1 ms, or the largest whole fraction of it within the creep damping's limit at this speed
    (:func:`~.curve_setup.creep_step_limit_s`; a given ``run.dt_s`` above that limit is a warning).  With a
    ``[structure]`` the curve runs over the deck (the deck's modes along s, under the local track frame: its lateral
    modes take the wheels' force in the canted track plane, about m a_nc, not the horizontal m V²/R a level deck
    carries, and its vertical modes the load normal to that plane, 1/cos φ of the weight; read the deck's lateral
    response of a curve with that in mind); not with
    a ``[flexible_track]`` or a train (``vehicle.consist``: the track-following frames follow one vehicle's
    bodies), nor with ``contact.wheel_rail = "springs"``.  Output group ``"curving"``; ``summary.json`` gains a
    ``layout`` block (:func:`layout_summary`: radius, cant, cant angle, balance speed, the unbalanced lateral
    acceleration a_nc at the run's speed and m a_nc, the steady ΣY balance of :mod:`exudyn_wheelrail.analysis.
    curving`).

``[structure]`` (optional) — a flexible bridge deck under the track (:class:`~..structures.bridge.BridgeModel`,
entered with :func:`~..structures.bridge_exudyn.add_bridge`):
    ``spans_m`` (list of span lengths, running order), ``start_m`` (s of the first abutment),
    ``damping_ratio`` (modal ζ of every mode, 0 ≤ ζ < 1), ``rail_height_m`` (top of rail above the beam axis),
    optional ``continuous`` (false: independent simply supported spans), ``elements_per_span`` (20),
    ``formulation`` ("modal" | "ffrf", default "modal"; "ffrf" needs ``run.solver = "newmark"``),
    ``modes_cutoff_Hz`` (a frequency, or ``"en1990"`` (default): max over the spans of max(30 Hz, 1.5 f1, f3)
    with the simply supported Euler–Bernoulli bending frequencies f_n = n²π/(2L²)√(EI_y/m) — EN 1990
    A2.4.4.2.1(4)P; modes up to 1.01 times the cut-off are kept, because the FE frequencies lie slightly above
    those values), and the table ``[structure.section]``: ``m_kg_m``, ``EI_y_Nm2`` (vertical bending),
    ``EI_z_Nm2`` (lateral), ``GJ_Nm2``, ``EA_N``, ``Ip_kgm2_m`` (all required, > 0; one section for all spans) —
    or, in its place, the deck by its mass and frequencies as the ``bridge-crossing`` command gives it:
    ``mass_kg_m``, ``f1_Hz`` (the first span's simply supported first vertical frequency; one section for all
    spans), optional ``lateral_f1_Hz`` (:func:`~.deck.structure_section`; torsion and axial stiffness are then
    placeholders whose torsion modes below the cut-off move the rails too).
    ``track_form`` ("ballasted" (default) | "direct_fastening"): the EN 1990 A2.4.4.2.1(4)P deck-acceleration
    limit the check's verdict applies (3.5 / 5 m/s²; :mod:`.deck`).
    The deck carries the vehicle only: its dead load is not modelled (the record is relative to the loaded
    state).  Start the vehicle off the deck: it starts in equilibrium on the rigid track.
    ``[structure.support_motion]`` (optional) — a lateral ground motion of all supports and of the track off the
    deck (synchronous; relative-motion formulation, :mod:`exudyn_wheelrail.structures.support_motion`): the sine
    burst of :class:`~exudyn_wheelrail.structures.support_motion.SmoothHarmonicSupportMotion` with
    ``peak_acceleration_m_s2`` (required: max |ÿ_g| over the burst, ramps included; 0 < a ≤ 10),
    ``frequency_Hz`` (required, 0.1–20), ``ramp_cycles`` (C² ramp length in periods, 0 < n ≤ 100, default 1: a
    sudden start would make the rails under the vehicle jump in velocity), ``plateau_cycles`` (periods at full
    amplitude ≥ 0, or ``"auto"`` (default): to the end of the run), ``start_s`` (≥ 0, default 0: the time the
    ramp starts).  Start the vehicle so that it reaches the deck after the ramp (``start_m`` − ``start_s_m`` ≥
    V × ramp_cycles / frequency_Hz) to see the deck's own response to the ground first.

``[flexible_track]`` (optional, not with ``[structure]``) — rails on pads, sleepers and ballast instead of rigid
    rails (:mod:`exudyn_wheelrail.track.flexible`, coupled like a deck, :mod:`exudyn_wheelrail.scenarios.
    flexible_track`): ``file`` (a track file, default ``exudyn_wheelrail/data/track_60E1_ballasted.toml``),
    ``start_m`` and ``length_m`` of the modelled segment (both numbers or both ``"auto"`` (default): the segment the
    run needs; ``length_m = "window"``: a window travelling with the vehicle, whose cost does not grow with the
    run, ``shift_bays`` the sleeper bays per move, default 1), ``modes_up_to_Hz`` (the modal reduction's cut-off;
    the static flexibility of the modes above it acts in series with the contacts).  An explicit solver needs a
    step the wheel on the rail's modal mass allows (the build refuses a larger one, naming ``run.dt_s``;
    ``docs/track.md``) and one the creep damping on the rails allows (it grows as 1/V; the run monitor warns):
    without ``run.dt_s`` an explicit run takes :func:`~exudyn_wheelrail.scenarios.flexible_track.default_step_s` of
    its speed (0.052 ms at 50 km/h, 0.21 ms at 200 km/h, at most 0.4 ms).  Output
    group ``"flexible_track"``: rail displacements under each wheelset, the nearest sleeper's displacement, pad and
    ballast forces.

``[contact]`` (optional) — the fields of :class:`~exudyn_wheelrail.simulation.settings.ContactSettings`, validated
    by it: ``creep_law`` ("table" (default: Kalker's exact theory, tabulated), "table_linear" (the same table
    interpolated multilinearly), "fastsim", "shen_hedrick_elkins", "polach", "linear", "none"), ``friction`` (μ,
    0.3), ``fastsim_grid`` ([24, 8]), ``geometry`` ("online" search
    (default) or "table": precomputed for the rigid rail profile), ``wheel_rail`` ("contact" (default) or
    "springs": linear springs at the nominal rail position, a cost baseline without irregularities, contact and
    recording — needs ``run.record = false``).

``[run]`` (optional) — the fields of :class:`~exudyn_wheelrail.simulation.settings.RunSettings`, validated by it:
    ``solver`` ("newmark" (default): trapezoidal rule β = 1/4, γ = 1/2, index-2, modified Newton with the
    connector's Jacobian — the RTRI paper's scheme; "rk44": explicit RK44 with Lie-group integration;
    "generalized_alpha", "explicit_midpoint", "rk33", "rk67"), ``dt_s`` (1e-3), ``duration_s`` (a time > 0, or
    ``"auto"`` (default): until the trailing wheelset is ``run_out_m`` past the end of the last track feature — the
    end of the last span deflection (with its transition), sampled table, generated spectrum, isolated defect, deck
    or a curve's transition (the circular curve has no end, nor have harmonic components), ``run_out_m`` (10), ``newton_tolerance`` (1e-4, implicit solvers), ``record`` (true), ``record_every``
    (1: every step), ``progress`` (false: the command line's ``--no-progress`` decides there).  A run of n =
    ceil(duration/dt) steps has n/record_every + 1 rows (the states at t = 0, record_every dt, …).

``[outputs]`` (optional)
    ``timeseries`` — the column groups written (default: every group the model has;
    :mod:`exudyn_wheelrail.simulation.recorder` defines them): ``"Y"``, ``"Q"``, ``"YQ"``, ``"flange"``,
    ``"contact_angle"``, ``"wheelset_lateral"``, ``"track"``, ``"carbody"`` (a vehicle with a car body),
    ``"deck"`` (with a structure); ``"curving"`` (with a ``[layout]``: ``yaw_w<j>_rad`` the wheelset's yaw relative
    to its local track frame, ``curvature_w<j>_1_m`` the curvature under it, ``guidance_lateral_N`` for the bogie
    and wheelset layouts; :func:`~exudyn_wheelrail.analysis.curving.curving_columns`); ``"unloading"`` — the wheel unloading ``dQQ_w<j>_<side>`` = (Q₀ − Q)/Q₀ (Q₀
    the static wheel load of the vehicle's load path); with a structure (:mod:`.deck`) ``"deck_acceleration"``
    (vertical deck acceleration at L/10 … 9L/10 of every span: the EN 1990 check points), ``"deck_wheelsets"``
    (deck deflection under each wheelset), ``"deck_lateral"`` (lateral mid-span displacement relative to the
    supports, absolute lateral acceleration, the ground motion).  ``time_s`` and ``s_leading_m`` are always
    written.
    ``carbody_points`` — array of tables ``{name, x_m, y_m, height_m}``: ``x_m`` a number (vehicle frame: from the
        vehicle centre, + forward) or ``"front_bogie"`` | ``"rear_bogie"`` | ``"centre"``; ``y_m`` (+ right,
        default 0); ``height_m`` above the top of rail.  Default (a vehicle with a car body): ``rear`` and
        ``front``, above the bogie centres at :data:`DEFAULT_FLOOR_HEIGHT_M`.
    ``formats`` — ``["csv"]`` (default) and/or ``"npz"`` (``timeseries.csv`` / ``timeseries.npz``).
    ``plots`` — true (default): one PNG per written group that has a figure (``plot_<group>.png``).
    ``criteria`` — true (default) / false, or a table ``{enabled, vehicle ("passenger" | "locomotive" |
        "freight"), yq_limit (0.8), unloading_limit (0.6), carbody_point (default: the first point)}``:
        :func:`~..analysis.safety.running_criteria_summary` on the recorded run (per-wheel Y, Q — static wheel
        loads from the vehicle's lever-rule load path — and the car-body point's lateral accelerometer and
        vertical acceleration), stored in ``summary.json``.  A record too short for its filters and windows gives
        ``criteria = {"error": ...}`` and a note, not a failure.

A bridge crossing
-----------------
A ``[vehicle]`` with a ``load_model`` makes the scenario a bridge crossing (:mod:`.spec_crossing`; what the
``bridge-crossing`` command fills and runs): a train given as axle loads — ``hslm`` (a universal train of EN
1991-2, ``"A1"`` … ``"A10"``), ``axles`` (an axle file) or ``consist`` (a shipped consist or a consist file) —
crosses a chain of simply supported spans given by their mass and first frequency and kept to N modes per span.
``load_model``: ``"moving-loads"`` (constant forces), ``"sprung-masses"`` (each axle a mass on a spring and damper:
``sprung_frequency_Hz``, ``sprung_damping_ratio``) or ``"vehicles"`` (the vehicles of a ``consist``, in wheel–rail
contact with the deck); ``speed_km_h`` (required).  ``[structure]`` (required): ``spans_m`` (a list in running
order), ``mass_kg_m``, ``f1_Hz`` (of the first span), ``damping_ratio``, ``modes`` (vertical, per span, at most
:data:`~.defaults.MAX_MODES`), ``lateral_modes`` (default 0), ``lateral_f1_Hz`` (default: ``EI_z =``
:data:`~.defaults.LATERAL_EI_RATIO` ``EI_y``), ``track_form``.  ``[run]``: ``solver`` (default ``"rk44"``),
``dt_s`` (default: the crossing's rule, ``docs/cli.md``), ``free_vibration_s`` (default 0).  No other table or
key: the crossing's deck (N modes per span, not the modes up to a cut-off of the ``[structure]`` above), run (until
the last axle has left the last span) and files (its columns and summary, ``docs/cli.md``, *bridge-crossing*; no
figures) are its own; ``sweep`` sweeps any of its keys (its table: the summary's ``scalars``,
:func:`~.bridge_crossing_summary.crossing_scalars`; ``bridge-crossing-sweep`` sweeps the speed with its plot).
``examples/scenarios/crossing_hslm_a1_20m.toml``.

Starting state
--------------
The vehicle starts in static equilibrium on the centred, undisplaced rails (:func:`~..multibody.place_on_rails`).
Where the track is displaced under the wheelsets at t = 0 (a harmonic, a sampled table), the bodies start on it
(:func:`~exudyn_wheelrail.rolling_stock.placement.start_on_track`): each wheelset moved by the track under it and yawed along it, with the velocities and
yaw rate at which the track moves and turns under it in the moving frame; each bogie frame and the car body on the
straight line through their supports (displaced, yawed, pitched, with the rates) — otherwise a millimetre of
vertical irregularity is a millimetre of Hertz penetration (MN contact forces) and a slope dy/ds a lateral
creepage dy/ds.  What the track's curvature leaves over loads the suspensions: the run may start with a small
transient (the summary notes the start).  A rigid translation of the whole track, or a lateral inclination of it,
leaves the contact forces unchanged (tested).

What :func:`run_scenario` writes into ``out_dir``
-------------------------------------------------
The folder is checked (writable, not a file) before the model is built.  ``timeseries.csv`` and/or
``timeseries.npz`` (the written groups), ``summary.json`` (the normalised scenario, the ``status`` — one of
:data:`~exudyn_wheelrail.simulation.status.STATUSES` — with its detail, hint and the monitor's events, steps,
timings, the model — vehicle, static wheel loads, bridge modes —, ``peaks`` of every recorded column (not for a
diverged run), ``scalars`` — the flat dict of scalar results a sweep tabulates —, ``criteria``, ``deck`` (with a
structure, :func:`~.deck.deck_summary`: per span the mid-span deflection against the quasi-static influence line
and the deck alone under the moving static axle loads, the accelerations, the lateral response and its reference
with a support motion; the EN 1990 deck-acceleration check; the deflection under each wheelset), ``layout`` (with
a ``[layout]``, :func:`layout_summary`), ``notes``, sign conventions) and the plots.

Loader and normal form
----------------------
:func:`load_scenario` reads and validates a file and returns the **normalised scenario**: a plain dict of plain
values (picklable, JSON- and TOML-representable) with every default filled in and file paths absolute.
:func:`validate_scenario` accepts its own output (idempotent), so overrides with dotted keys
(:func:`apply_overrides`: ``vehicle.speed_km_h``, ``track.0.amplitude_m``, ``structure.section.m_kg_m``) are
applied to the normal form and validated again — what :mod:`.sweep` does.
"""
from __future__ import annotations

from .build import (
    MODES_CUTOFF_MARGIN,
    ScenarioModel,
    build_bridge_modes,
    build_layout,
    build_scenario,
    build_track,
    scenario_run_settings,
    vehicle_data,
)
from ..rolling_stock.placement import start_on_track
from .outputs import jsonable, write_csv, write_json, write_scenario_outputs
from .overrides import apply_overrides, parse_value, set_dotted
from .plots import group_figure
from .result import ScenarioResult
from .run import layout_summary, peaks, run_model, run_scenario, scenario_summary, static_wheel_loads
from .spec import (
    CRITERIA_VEHICLES,
    DEFAULT_FLOOR_HEIGHT_M,
    DIRECTIONS,
    FORMATS,
    NAMED_X,
    QUANTITIES,
    SCHEMA_VERSION,
    TIMESERIES_GROUPS,
    TRACK_TYPES,
    V1_MOVED,
    ScenarioError,
    as_scenario,
    features_end_m,
    load_scenario,
    validate_scenario,
)

__all__ = [
    "SCHEMA_VERSION",
    "V1_MOVED",
    "TRACK_TYPES",
    "DIRECTIONS",
    "TIMESERIES_GROUPS",
    "FORMATS",
    "NAMED_X",
    "CRITERIA_VEHICLES",
    "DEFAULT_FLOOR_HEIGHT_M",
    "MODES_CUTOFF_MARGIN",
    "QUANTITIES",
    "ScenarioError",
    "ScenarioModel",
    "ScenarioResult",
    "load_scenario",
    "validate_scenario",
    "as_scenario",
    "features_end_m",
    "apply_overrides",
    "set_dotted",
    "parse_value",
    "build_track",
    "build_bridge_modes",
    "build_layout",
    "vehicle_data",
    "scenario_run_settings",
    "build_scenario",
    "start_on_track",
    "run_model",
    "run_scenario",
    "scenario_summary",
    "layout_summary",
    "static_wheel_loads",
    "write_scenario_outputs",
    "write_csv",
    "write_json",
    "group_figure",
    "peaks",
    "jsonable",
]
