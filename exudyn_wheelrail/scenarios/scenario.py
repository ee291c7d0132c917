r"""Scenario files: a whole simulation (vehicle, track, optional flexible bridge, contact and run settings, outputs)
in one TOML file, run by :func:`run_scenario` or ``python -m exudyn_wheelrail run SCENARIO.toml --out DIR``.

>>> scenario = load_scenario("examples/scenarios/rtri_20m.toml")        # doctest: +SKIP
>>> result = run_scenario(scenario, "out/rtri_20m")                      # doctest: +SKIP
>>> result.summary["status"], result.summary["criteria"]["safety_passed"]  # doctest: +SKIP

The normalised scenario is the **spec** of the simulation pipeline (:mod:`exudyn_wheelrail.simulation`):
:func:`build_scenario` turns it into the Exudyn model — the vehicle of a data file
(:func:`~exudyn_wheelrail.multibody.build_vehicle`, frame moving with the running speed V), the wheel–rail
connector (:func:`~exudyn_wheelrail.multibody.add_wheel_rail_contact`) on a rigid straight track
(:class:`~exudyn_wheelrail.multibody.RigidStraightTrack`) displaced by the listed irregularities, optionally a
modally reduced bridge deck (:mod:`exudyn_wheelrail.structures.bridge`, coupled through the connector's
``bridge=``), the vehicle in static equilibrium on the rails at t = 0 (:func:`~exudyn_wheelrail.multibody.
place_on_rails`) — and the recorder; :func:`run_scenario` runs it through the one solve wrapper
(:func:`exudyn_wheelrail.simulation.runner.run`: watched by the run monitor, a status of
:mod:`exudyn_wheelrail.simulation.status`) and evaluates it.  The RTRI case (:mod:`.rtri`) is such a spec.

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
    ``"manchester_vehicle1"``) or ``file`` (a vehicle data file, schema: ``vehicles/README.md``), and
    ``speed_km_h`` (required, 0 < V ≤ 600), ``start_s_m`` (track distance of the **leading** wheelset at t = 0,
    default 0), ``overrides`` (optional table: numeric values of the vehicle file replaced for this run, by
    ``"table.key"``, e.g. ``"primary.ky_N_per_m" = 7.8e6``;
    :func:`~..multibody.vehicle_data.load_vehicle_with_overrides`).  The wheel and rail profiles, gauge,
    inclination and back-to-back distance come from the vehicle file.

``[[track]]`` (optional, any number; none = a perfect straight track) — irregularity components, summed:
    ``type = "span_deflection"``: ``span_length_m``, ``amplitude_m``, ``start_m`` (s of the span start),
    optional ``transition_length_m`` (0; C2 end transitions centred on the span ends), ``direction``
    ("lateral" | "vertical", default "lateral") — :class:`~..multibody.track.SpanDeflection`.
    ``type = "harmonic"``: ``amplitude_m``, ``wavelength_m``, optional ``phase_rad`` (0), ``direction``
    ("lateral") — ``amplitude sin(2π s/wavelength + phase)`` along the whole track.
    ``type = "sampled"``: ``file`` — a CSV file with the columns ``s_m, y_m, z_m`` (``#`` comments allowed),
    cubic-spline interpolated, held constant outside the table
    (:meth:`~..multibody.track.SampledIrregularity.from_csv`).

``[structure]`` (optional) — a flexible bridge deck under the track (:class:`~..structures.bridge.BridgeModel`,
entered with :func:`~..structures.bridge.add_bridge`):
    ``spans_m`` (list of span lengths, running order), ``start_m`` (s of the first abutment),
    ``damping_ratio`` (modal ζ of every mode, 0 ≤ ζ < 1), ``rail_height_m`` (top of rail above the beam axis),
    optional ``continuous`` (false: independent simply supported spans), ``elements_per_span`` (20),
    ``formulation`` ("modal" | "ffrf", default "modal"; "ffrf" needs ``run.solver = "newmark"``),
    ``modes_cutoff_Hz`` (a frequency, or ``"en1990"`` (default): max over the spans of max(30 Hz, 1.5 f1, f3)
    with the simply supported Euler–Bernoulli bending frequencies f_n = n²π/(2L²)√(EI_y/m) — EN 1990
    A2.4.4.2.1(4)P; modes up to 1.01 times the cut-off are kept, because the FE frequencies lie slightly above
    those values), and the table ``[structure.section]``: ``m_kg_m``, ``EI_y_Nm2`` (vertical bending),
    ``EI_z_Nm2`` (lateral), ``GJ_Nm2``, ``EA_N``, ``Ip_kgm2_m`` (all required, > 0; one section for all spans).
    The deck carries the vehicle only: its dead load is not modelled (the record is relative to the loaded
    state).  Start the vehicle off the deck: it starts in equilibrium on the rigid track.

``[contact]`` (optional) — the fields of :class:`~exudyn_wheelrail.simulation.settings.ContactSettings`, validated
    by it: ``creep_law`` ("table" (default: Kalker's exact theory, tabulated), "fastsim", "shen_hedrick_elkins",
    "polach", "linear", "none"), ``friction`` (μ, 0.3), ``fastsim_grid`` ([24, 8]), ``geometry`` ("online" search
    (default) or "table": precomputed for the rigid rail profile), ``wheel_rail`` ("contact" (default) or
    "springs": linear springs at the nominal rail position, a cost baseline without irregularities, contact and
    recording — needs ``run.record = false``).

``[run]`` (optional) — the fields of :class:`~exudyn_wheelrail.simulation.settings.RunSettings`, validated by it:
    ``solver`` ("newmark" (default): trapezoidal rule β = 1/4, γ = 1/2, index-2, modified Newton with the
    connector's Jacobian — the RTRI paper's scheme; "rk44": explicit RK44 with Lie-group integration;
    "generalized_alpha", "explicit_midpoint", "rk33", "rk67"), ``dt_s`` (1e-3), ``duration_s`` (a time > 0, or
    ``"auto"`` (default): until the trailing wheelset is ``run_out_m`` past the end of the last track feature — the
    end of the last span deflection (with its transition), sampled table or deck; harmonic components have no
    end), ``run_out_m`` (10), ``newton_tolerance`` (1e-4, implicit solvers), ``record`` (true), ``record_every``
    (1: every step), ``progress`` (false: the command line's ``--no-progress`` decides there).  A run of n =
    ceil(duration/dt) steps has n/record_every + 1 rows (the states at t = 0, record_every dt, …).

``[outputs]`` (optional)
    ``timeseries`` — the column groups written (default: every group the model has;
    :mod:`exudyn_wheelrail.simulation.recorder` defines them): ``"Y"``, ``"Q"``, ``"YQ"``, ``"flange"``,
    ``"contact_angle"``, ``"wheelset_lateral"``, ``"track"``, ``"carbody"`` (a vehicle with a car body),
    ``"deck"`` (with a structure).  ``time_s`` and ``s_leading_m`` are always written.
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

Starting state
--------------
The vehicle starts in static equilibrium on the centred, undisplaced rails (:func:`~..multibody.place_on_rails`).
Where the track is displaced under the wheelsets at t = 0 (a harmonic, a sampled table), the bodies start on it
(:func:`_start_on_track`): each wheelset moved by the track under it and yawed along it, with the velocities and
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
diverged run), ``scalars`` — the flat dict of scalar results a sweep tabulates —, ``criteria``, ``notes``, sign
conventions) and the plots.

Loader and normal form
----------------------
:func:`load_scenario` reads and validates a file and returns the **normalised scenario**: a plain dict of plain
values (picklable, JSON- and TOML-representable) with every default filled in and file paths absolute.
:func:`validate_scenario` accepts its own output (idempotent), so overrides with dotted keys
(:func:`apply_overrides`: ``vehicle.speed_km_h``, ``track.0.amplitude_m``, ``structure.section.m_kg_m``) are
applied to the normal form and validated again — what :mod:`.sweep` does.
"""
from __future__ import annotations

import copy
import csv
import json
import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..simulation import status as S
from ..simulation.recorder import GROUPS, PROGRESS_MIN_STEPS, ProgressBar, Recorder, vehicle_probes
from ..simulation.settings import (
    DURATION_AUTO,
    MAX_STEPS,
    ContactSettings,
    RunSettings,
    SettingsError,
    settings_from_mapping,
)
from ..validation import Quantity, output_dir

__all__ = [
    "SCHEMA_VERSION",
    "V1_MOVED",
    "TRACK_TYPES",
    "TIMESERIES_GROUPS",
    "FORMATS",
    "DEFAULT_FLOOR_HEIGHT_M",
    "ScenarioError",
    "ScenarioModel",
    "ScenarioResult",
    "load_scenario",
    "validate_scenario",
    "apply_overrides",
    "set_dotted",
    "parse_value",
    "build_track",
    "build_bridge_modes",
    "scenario_run_settings",
    "build_scenario",
    "run_model",
    "run_scenario",
    "scenario_summary",
    "write_scenario_outputs",
    "peaks",
    "jsonable",
]

SCHEMA_VERSION = 2
#: keys of ``schema_version = 1`` files (and overrides) -> their place in version 2
V1_MOVED = {"run.speed_km_h": "vehicle.speed_km_h", "run.start_s_m": "vehicle.start_s_m",
            "run.creep_law": "contact.creep_law", "run.friction": "contact.friction",
            "run.fastsim_grid": "contact.fastsim_grid"}
TRACK_TYPES = ("span_deflection", "harmonic", "sampled")
DIRECTIONS = ("lateral", "vertical")
#: column groups of the time series, in the order they are written
TIMESERIES_GROUPS = GROUPS
FORMATS = ("csv", "npz")
NAMED_X = ("front_bogie", "rear_bogie", "centre")
CRITERIA_VEHICLES = ("passenger", "locomotive", "freight")
#: ASSUMPTION: height of a car-body floor above the top of rail [m] — typical of a standard-gauge passenger coach
#: (~1.2 m); the Manchester data give none.  The default car-body points and the RTRI accelerometer sit there.
DEFAULT_FLOOR_HEIGHT_M = 1.20
#: modes up to this factor times the EN 1990 cut-off are kept (the FE frequencies lie slightly above the
#: Euler–Bernoulli values the cut-off is computed from; as examples/bridge_crossing.py)
MODES_CUTOFF_MARGIN = 1.01
SIDES_OUT = ("right", "left")
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
#: Plausibility of the scenario's lengths beyond their type and sign, by key (``track.*`` for every track
#: component): a value outside is an error, one evidently given in millimetres is named so.  (The time step and
#: the run-out are judged by :mod:`exudyn_wheelrail.simulation.settings`.)
QUANTITIES = {
    "track.*.amplitude_m": Quantity("track irregularity amplitude", "m", 0.0, 0.1, magnitude=True),
    "track.*.span_length_m": Quantity("span length of a span deflection", "m", 1.0, 1000.0),
    "track.*.transition_length_m": Quantity("transition length", "m", 0.0, 200.0),
    "track.*.wavelength_m": Quantity("irregularity wavelength", "m", 0.01, 1000.0),
    "structure.spans_m": Quantity("bridge span length", "m", 1.0, 1000.0),
    "structure.rail_height_m": Quantity("height of the rail top above the deck's beam axis", "m", 0.0, 10.0),
    "outputs.carbody_points.x_m": Quantity("car-body point position (x from the vehicle centre)", "m", 0.0, 30.0,
                                           magnitude=True),
    "outputs.carbody_points.y_m": Quantity("car-body point position (y from the centre line)", "m", 0.0, 2.5,
                                           magnitude=True),
    "outputs.carbody_points.height_m": Quantity("car-body point height above the rail", "m", -1.0, 6.0),
}


class ScenarioError(ValueError):
    """Invalid scenario: the message names the file (or ``<dict>``) and the key."""


# ================================================================================================ validation
class _Check:
    """Helpers that raise :class:`ScenarioError` naming the source and the dotted key."""

    def __init__(self, source: str, base_dir: Path | None):
        self.source = source
        self.base_dir = base_dir

    def error(self, key: str, message: str) -> ScenarioError:
        return ScenarioError(f"{self.source}: {key}: {message}")

    def table(self, value, key: str, required=(), optional=()) -> dict:
        if not isinstance(value, dict):
            raise self.error(key, f"expected a table, got {type(value).__name__} {value!r}")
        allowed = tuple(required) + tuple(optional)
        for k in value:
            if k not in allowed:
                raise self.error(f"{key}.{k}" if key else k,
                                 f"unknown key (allowed in {'[' + key + ']' if key else 'the top level'}: "
                                 f"{', '.join(allowed)})")
        for k in required:
            if k not in value:
                raise self.error(f"{key}.{k}" if key else k, "missing (required)")
        return value

    def number(self, value, key: str, lo=None, hi=None, lo_open=True, hi_open=False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(key, f"expected a number, got {type(value).__name__} {value!r}")
        x = float(value)
        if not math.isfinite(x):
            raise self.error(key, f"expected a finite number, got {value!r}")
        if lo is not None and (x <= lo if lo_open else x < lo):
            raise self.error(key, f"{value!r}: must be {'>' if lo_open else '>='} {lo}")
        if hi is not None and (x >= hi if hi_open else x > hi):
            raise self.error(key, f"{value!r}: must be {'<' if hi_open else '<='} {hi}")
        return x

    def plausible(self, x: float, key: str, quantity_key: str) -> float:
        """``x`` judged by ``QUANTITIES[quantity_key]`` (error naming the key if implausible, warning if unusual)."""
        return QUANTITIES[quantity_key].check(f"{self.source}: {key}", x, error=ScenarioError)

    def integer(self, value, key: str, lo=None, hi=None) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(key, f"expected an integer, got {type(value).__name__} {value!r}")
        if lo is not None and value < lo:
            raise self.error(key, f"{value!r}: must be >= {lo}")
        if hi is not None and value > hi:
            raise self.error(key, f"{value!r}: must be <= {hi}")
        return int(value)

    def boolean(self, value, key: str) -> bool:
        if not isinstance(value, bool):
            raise self.error(key, f"expected true or false, got {value!r}")
        return value

    def string(self, value, key: str, choices=None) -> str:
        if not isinstance(value, str):
            raise self.error(key, f"expected a string, got {type(value).__name__} {value!r}")
        if choices is not None and value not in choices:
            raise self.error(key, f"{value!r}: expected one of {', '.join(map(repr, choices))}")
        return value

    def array(self, value, key: str, min_length: int = 0) -> list:
        if not isinstance(value, (list, tuple)):
            raise self.error(key, f"expected an array, got {type(value).__name__} {value!r}")
        if len(value) < min_length:
            raise self.error(key, f"expected at least {min_length} entr{'y' if min_length == 1 else 'ies'}")
        return list(value)

    def path(self, value, key: str) -> str:
        self.string(value, key)
        p = Path(value)
        if not p.is_absolute() and self.base_dir is not None:
            p = self.base_dir / p
        if not p.is_file():
            raise self.error(key, f"file not found: {p}")
        return str(p.resolve())

    def settings(self, cls, value, key: str):
        """A :class:`RunSettings` / :class:`ContactSettings` from the table ``key`` (validated by it)."""
        try:
            return settings_from_mapping(cls, value, key)
        except SettingsError as exc:
            raise self.error(exc.field, exc.problem) from None


def load_scenario(path) -> dict:
    """Read and validate a scenario file; returns the normalised scenario (module docstring)."""
    path = Path(path)
    if not path.is_file():
        raise ScenarioError(f"{path}: scenario file not found")
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from None
    return validate_scenario(data, source=str(path), base_dir=path.resolve().parent, default_name=path.stem)


def _from_v1(data: dict) -> dict:
    """A ``schema_version = 1`` scenario with the keys of :data:`V1_MOVED` moved to their version-2 tables."""
    out = copy.deepcopy(data)
    out["schema_version"] = SCHEMA_VERSION
    run = out.get("run")
    if isinstance(run, dict):
        for old, new in V1_MOVED.items():
            key = old.split(".", 1)[1]
            if key in run:
                table, name = new.split(".")
                if not isinstance(out.get(table, {}), dict):
                    continue                          # the table's own check reports it
                out.setdefault(table, {})[name] = run.pop(key)
    return out


def validate_scenario(data: dict, source: str = "<dict>", base_dir=None, default_name: str = "scenario") -> dict:
    """Validate a scenario (as read from TOML, or a normalised scenario) and return its normal form: defaults
    filled in, file paths absolute (relative ones against ``base_dir``), plain Python values only."""
    c = _Check(source, Path(base_dir) if base_dir is not None else None)
    c.table(data, "", required=("schema_version", "vehicle"),
            optional=("scenario", "track", "structure", "contact", "run", "outputs"))
    version = c.integer(data["schema_version"], "schema_version")
    if version == 1:
        data = _from_v1(data)
    elif version != SCHEMA_VERSION:
        raise c.error("schema_version", f"{data['schema_version']!r}: this version reads schema_version = "
                                        f"{SCHEMA_VERSION} (and 1)")
    out = {"schema_version": SCHEMA_VERSION}
    # ---------------------------------------------------------------------------------------- [scenario]
    sc = c.table(data.get("scenario", {}), "scenario", optional=("name", "description"))
    out["scenario"] = {"name": c.string(sc.get("name", default_name), "scenario.name"),
                       "description": c.string(sc.get("description", ""), "scenario.description")}
    # ----------------------------------------------------------------------------------------- [vehicle]
    out["vehicle"], vehicle = _vehicle(c, data["vehicle"])
    # ------------------------------------------------------------------------------------------- [track]
    track = c.array(data.get("track", []), "track")
    out["track"] = [_track_component(c, comp, f"track.{i}") for i, comp in enumerate(track)]
    # --------------------------------------------------------------------------------------- [structure]
    if "structure" in data:
        out["structure"] = _structure(c, data["structure"])
    # --------------------------------------------------------------------------------- [contact], [run]
    contact = c.settings(ContactSettings, data.get("contact", {}), "contact")
    run = c.settings(RunSettings, data.get("run", {}), "run")
    out["contact"] = contact.as_dict()
    out["run"] = run.as_dict()
    if out.get("structure", {}).get("formulation") == "ffrf" and run.solver != "newmark":
        raise c.error("structure.formulation", "'ffrf' holds its reference frame by constraints and needs "
                                               "run.solver = 'newmark'")
    if run.duration_s == DURATION_AUTO and _features_end_m(out) is None:
        raise c.error("run.duration_s", "'auto' needs a track feature with an end (a span deflection, a sampled "
                                        "table or a structure); harmonic components run along the whole track: "
                                        "give a time in s")
    if contact.wheel_rail == "springs" and run.record:
        raise c.error("contact.wheel_rail", "'springs' (the cost baseline) records nothing: set run.record = false")
    # ----------------------------------------------------------------------------------------- [outputs]
    out["outputs"] = _outputs(c, data.get("outputs", {}), vehicle, "structure" in out)
    return out


def _flat_overrides(value, prefix: str = "") -> dict:
    """``{"primary": {"ky_N_per_m": 1}}`` (TOML dotted keys) or ``{"primary.ky_N_per_m": 1}`` -> the flat form."""
    out = {}
    for k, v in value.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_flat_overrides(v, key + "."))
        else:
            out[key] = v
    return out


def _vehicle(c: _Check, vt) -> tuple[dict, object]:
    c.table(vt, "vehicle", required=("speed_km_h",), optional=("name", "file", "start_s_m", "overrides"))
    if ("name" in vt) == ("file" in vt):
        raise c.error("vehicle", "give exactly one of vehicle.name (a shipped vehicle) or vehicle.file (a vehicle "
                                 "data file)")
    from ..multibody.vehicle_data import load_vehicle_with_overrides
    if "name" in vt:
        key, ref = "vehicle.name", c.string(vt["name"], "vehicle.name")
        out = {"name": ref}
    else:
        key, ref = "vehicle.file", c.path(vt["file"], "vehicle.file")
        out = {"file": ref}
    overrides = vt.get("overrides", {})
    if not isinstance(overrides, dict):
        raise c.error("vehicle.overrides", f"expected a table {{\"table.key\" = value}}, got {overrides!r}")
    overrides = _flat_overrides(overrides)
    try:
        vehicle = load_vehicle_with_overrides(ref, overrides or None)
    except ValueError as exc:
        raise c.error("vehicle.overrides" if overrides and "override" in str(exc) else key, str(exc)) from None
    out.update({"speed_km_h": c.number(vt["speed_km_h"], "vehicle.speed_km_h", lo=0.0, hi=600.0),
                "start_s_m": c.number(vt.get("start_s_m", 0.0), "vehicle.start_s_m"),
                "overrides": overrides})
    return out, vehicle


def _track_component(c: _Check, comp, key: str) -> dict:
    if not isinstance(comp, dict):
        raise c.error(key, f"expected a table (a [[track]] entry), got {comp!r}")
    if "type" not in comp:
        raise c.error(f"{key}.type", f"missing (required: one of {', '.join(TRACK_TYPES)})")
    kind = c.string(comp["type"], f"{key}.type", TRACK_TYPES)
    if kind == "span_deflection":
        c.table(comp, key, required=("type", "span_length_m", "amplitude_m", "start_m"),
                optional=("transition_length_m", "direction"))
        L = c.plausible(c.number(comp["span_length_m"], f"{key}.span_length_m", lo=0.0), f"{key}.span_length_m",
                        "track.*.span_length_m")
        lt = c.plausible(c.number(comp.get("transition_length_m", 0.0), f"{key}.transition_length_m", lo=0.0,
                                  lo_open=False), f"{key}.transition_length_m", "track.*.transition_length_m")
        if not lt < L:
            raise c.error(f"{key}.transition_length_m", f"{lt}: must be shorter than the span ({L} m)")
        return {"type": kind, "span_length_m": L,
                "amplitude_m": c.plausible(c.number(comp["amplitude_m"], f"{key}.amplitude_m"), f"{key}.amplitude_m",
                                           "track.*.amplitude_m"),
                "start_m": c.number(comp["start_m"], f"{key}.start_m"), "transition_length_m": lt,
                "direction": c.string(comp.get("direction", "lateral"), f"{key}.direction", DIRECTIONS)}
    if kind == "harmonic":
        c.table(comp, key, required=("type", "amplitude_m", "wavelength_m"), optional=("phase_rad", "direction"))
        return {"type": kind,
                "amplitude_m": c.plausible(c.number(comp["amplitude_m"], f"{key}.amplitude_m"), f"{key}.amplitude_m",
                                           "track.*.amplitude_m"),
                "wavelength_m": c.plausible(c.number(comp["wavelength_m"], f"{key}.wavelength_m", lo=0.0),
                                            f"{key}.wavelength_m", "track.*.wavelength_m"),
                "phase_rad": c.number(comp.get("phase_rad", 0.0), f"{key}.phase_rad"),
                "direction": c.string(comp.get("direction", "lateral"), f"{key}.direction", DIRECTIONS)}
    c.table(comp, key, required=("type", "file"))
    path = c.path(comp["file"], f"{key}.file")
    from ..multibody.track import SampledIrregularity
    try:
        SampledIrregularity.from_csv(path)
    except (ValueError, OSError) as exc:
        raise c.error(f"{key}.file", str(exc)) from None
    return {"type": kind, "file": path}


_SECTION_KEYS = ("m_kg_m", "EI_y_Nm2", "EI_z_Nm2", "GJ_Nm2", "EA_N", "Ip_kgm2_m")


def _structure(c: _Check, st) -> dict:
    from ..structures.bridge import FORMULATIONS
    c.table(st, "structure", required=("spans_m", "start_m", "damping_ratio", "rail_height_m", "section"),
            optional=("continuous", "elements_per_span", "formulation", "modes_cutoff_Hz"))
    spans = st["spans_m"]
    if isinstance(spans, (int, float)) and not isinstance(spans, bool):
        spans = [spans]
    spans = c.array(spans, "structure.spans_m", min_length=1)
    sec = c.table(st["section"], "structure.section", required=_SECTION_KEYS)
    cut = st.get("modes_cutoff_Hz", "en1990")
    if isinstance(cut, str):
        cut = c.string(cut, "structure.modes_cutoff_Hz", ("en1990",))
    else:
        cut = c.number(cut, "structure.modes_cutoff_Hz", lo=0.0)
    return {"spans_m": [c.plausible(c.number(L, f"structure.spans_m.{i}", lo=0.0), f"structure.spans_m.{i}",
                                    "structure.spans_m") for i, L in enumerate(spans)],
            "start_m": c.number(st["start_m"], "structure.start_m"),
            "damping_ratio": c.number(st["damping_ratio"], "structure.damping_ratio", lo=0.0, hi=1.0,
                                      lo_open=False, hi_open=True),
            "rail_height_m": c.plausible(c.number(st["rail_height_m"], "structure.rail_height_m", lo=0.0,
                                                  lo_open=False), "structure.rail_height_m", "structure.rail_height_m"),
            "continuous": c.boolean(st.get("continuous", False), "structure.continuous"),
            "elements_per_span": c.integer(st.get("elements_per_span", 20), "structure.elements_per_span", 2, 1000),
            "formulation": c.string(st.get("formulation", "modal"), "structure.formulation", FORMULATIONS),
            "modes_cutoff_Hz": cut,
            "section": {k: c.number(sec[k], f"structure.section.{k}", lo=0.0) for k in _SECTION_KEYS}}


def _outputs(c: _Check, o, vehicle, has_structure: bool) -> dict:
    c.table(o, "outputs", optional=("timeseries", "carbody_points", "formats", "plots", "criteria"))
    has_car = vehicle.car_body is not None
    available = [g for g in TIMESERIES_GROUPS if (g != "carbody" or has_car) and (g != "deck" or has_structure)]
    if "timeseries" in o:
        groups = c.array(o["timeseries"], "outputs.timeseries")
        for i, g in enumerate(groups):
            c.string(g, f"outputs.timeseries.{i}", TIMESERIES_GROUPS)
            if g == "carbody" and not has_car:
                raise c.error(f"outputs.timeseries.{i}", f"'carbody': the vehicle {vehicle.name!r} (layout "
                                                         f"{vehicle.layout!r}) has no car body")
            if g == "deck" and not has_structure:
                raise c.error(f"outputs.timeseries.{i}", "'deck' needs a [structure]")
        if len(set(groups)) != len(groups):
            raise c.error("outputs.timeseries", f"{groups!r}: a group is listed twice")
        groups = [g for g in TIMESERIES_GROUPS if g in groups]          # canonical order
    else:
        groups = available
    # car-body points
    if "carbody_points" in o:
        pts = c.array(o["carbody_points"], "outputs.carbody_points")
        if pts and not has_car:
            raise c.error("outputs.carbody_points", f"the vehicle {vehicle.name!r} (layout {vehicle.layout!r}) has "
                                                    "no car body")
    else:
        pts = ([{"name": "rear", "x_m": "rear_bogie", "y_m": 0.0, "height_m": DEFAULT_FLOOR_HEIGHT_M},
                {"name": "front", "x_m": "front_bogie", "y_m": 0.0, "height_m": DEFAULT_FLOOR_HEIGHT_M}]
               if has_car else [])
    points, names = [], set()
    for i, p in enumerate(pts):
        key = f"outputs.carbody_points.{i}"
        c.table(p, key, required=("name", "x_m", "height_m"), optional=("y_m",))
        name = c.string(p["name"], f"{key}.name")
        if not _NAME.match(name):
            raise c.error(f"{key}.name", f"{name!r}: letters, digits and _ only, starting with a letter")
        if name in names:
            raise c.error(f"{key}.name", f"{name!r}: used twice")
        names.add(name)
        x = p["x_m"]
        x = (c.string(x, f"{key}.x_m", NAMED_X) if isinstance(x, str) else
             c.plausible(c.number(x, f"{key}.x_m"), f"{key}.x_m", "outputs.carbody_points.x_m"))
        points.append({"name": name, "x_m": x,
                       "y_m": c.plausible(c.number(p.get("y_m", 0.0), f"{key}.y_m"), f"{key}.y_m",
                                          "outputs.carbody_points.y_m"),
                       "height_m": c.plausible(c.number(p["height_m"], f"{key}.height_m"), f"{key}.height_m",
                                               "outputs.carbody_points.height_m")})
    fm = c.array(o.get("formats", ["csv"]), "outputs.formats", min_length=1)
    for i, f in enumerate(fm):
        c.string(f, f"outputs.formats.{i}", FORMATS)
    fm = [f for f in FORMATS if f in fm]
    # criteria
    cr = o.get("criteria", True)
    if isinstance(cr, bool):
        cr = {"enabled": cr}
    c.table(cr, "outputs.criteria", optional=("enabled", "vehicle", "yq_limit", "unloading_limit", "carbody_point"))
    crit = {"enabled": c.boolean(cr.get("enabled", True), "outputs.criteria.enabled"),
            "vehicle": c.string(cr.get("vehicle", "passenger"), "outputs.criteria.vehicle", CRITERIA_VEHICLES),
            "yq_limit": c.number(cr.get("yq_limit", 0.8), "outputs.criteria.yq_limit", lo=0.0),
            "unloading_limit": c.number(cr.get("unloading_limit", 0.6), "outputs.criteria.unloading_limit", lo=0.0),
            "carbody_point": cr.get("carbody_point", points[0]["name"] if points else "")}
    c.string(crit["carbody_point"], "outputs.criteria.carbody_point")
    if crit["carbody_point"] != "":                       # "" = no car-body point: comfort not evaluated
        if crit["carbody_point"] not in names:
            raise c.error("outputs.criteria.carbody_point", f"{crit['carbody_point']!r}: no car-body point of that "
                                                            f"name (points: {', '.join(sorted(names)) or 'none'})")
    return {"timeseries": groups, "carbody_points": points, "formats": fm,
            "plots": c.boolean(o.get("plots", True), "outputs.plots"), "criteria": crit}


def _features_end_m(scn: dict) -> float | None:
    """Track distance where the last track feature with an end ends (None if there is none)."""
    ends = []
    for comp in scn.get("track", []):
        if comp["type"] == "span_deflection":
            ends.append(comp["start_m"] + comp["span_length_m"] + 0.5 * comp["transition_length_m"])
        elif comp["type"] == "sampled":
            from ..multibody.track import SampledIrregularity
            ends.append(float(SampledIrregularity.from_csv(comp["file"]).s_m[-1]))
    if "structure" in scn:
        st = scn["structure"]
        ends.append(st["start_m"] + sum(st["spans_m"]))
    return max(ends) if ends else None


# ================================================================================================= overrides
def parse_value(text: str):
    """A command-line value: a TOML value (``250``, ``1e-3``, ``true``, ``"x"``, ``[20, 40]``) or else the plain
    string (``newmark``, ``auto``)."""
    text = text.strip()
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def set_dotted(scn: dict, key: str, value) -> None:
    """Set ``scn[a][b]...`` for the dotted key ``a.b...`` in place; integers index arrays (``track.0.start_m``).
    The parent must exist (a missing optional table, ``contact`` or ``run``, is created); the key itself may be new
    (validation judges it).  The keys of :data:`V1_MOVED` are moved to their version-2 place."""
    if not isinstance(key, str) or not key or any(not p for p in key.split(".")):
        raise ScenarioError(f"parameter {key!r}: expected a dotted key such as vehicle.speed_km_h or "
                            "track.0.amplitude_m")
    key = V1_MOVED.get(key, key)
    parts = key.split(".")
    if parts[0] in ("contact", "run") and isinstance(scn, dict):
        scn.setdefault(parts[0], {})
    node = scn
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        where = ".".join(parts[:depth]) or "the top level"
        if isinstance(node, list):
            try:
                i = int(part)
            except ValueError:
                raise ScenarioError(f"parameter {key!r}: {where} is an array: expected an index, "
                                    f"got {part!r}") from None
            if not 0 <= i < len(node):
                raise ScenarioError(f"parameter {key!r}: {where} has {len(node)} entr"
                                    f"{'y' if len(node) == 1 else 'ies'} (index {i} out of range)")
            if last:
                node[i] = value
            else:
                node = node[i]
        elif isinstance(node, dict):
            if last:
                node[part] = value
            elif part not in node:
                raise ScenarioError(f"parameter {key!r}: no {'.'.join(parts[:depth + 1])!r} in the scenario")
            else:
                node = node[part]
        else:
            raise ScenarioError(f"parameter {key!r}: {where} is a value ({node!r}), not a table or an array")


def apply_overrides(scenario: dict, overrides: dict, source: str = "<overrides>") -> dict:
    """A validated copy of the normalised ``scenario`` with the dotted-key ``overrides`` applied."""
    scn = copy.deepcopy(scenario)
    for key, value in overrides.items():
        set_dotted(scn, key, value)
    return validate_scenario(scn, source=source, default_name=scenario.get("scenario", {}).get("name", "scenario"))


def _as_scenario(scenario) -> tuple[dict, str | None]:
    if isinstance(scenario, (str, Path)):
        return load_scenario(scenario), str(Path(scenario).resolve())
    if isinstance(scenario, dict):
        return validate_scenario(scenario), None
    raise TypeError(f"scenario: expected a file path or a scenario dict, got {type(scenario).__name__}")


# =================================================================================================== building
def build_track(scn: dict):
    """The :class:`~..multibody.track.RigidStraightTrack` of the scenario's ``track`` components."""
    from ..multibody.track import Harmonic, IrregularitySum, RigidStraightTrack, SampledIrregularity, SpanDeflection
    parts = []
    for comp in scn["track"]:
        if comp["type"] == "span_deflection":
            parts.append(SpanDeflection(span_length_m=comp["span_length_m"], amplitude_m=comp["amplitude_m"],
                                        start_m=comp["start_m"], transition_length_m=comp["transition_length_m"],
                                        direction=comp["direction"]))
        elif comp["type"] == "harmonic":
            parts.append(Harmonic(amplitude_m=comp["amplitude_m"], wavelength_m=comp["wavelength_m"],
                                  phase_rad=comp["phase_rad"], direction=comp["direction"]))
        else:
            parts.append(SampledIrregularity.from_csv(comp["file"]))
    if not parts:
        return RigidStraightTrack()
    return RigidStraightTrack(parts[0] if len(parts) == 1 else IrregularitySum(parts))


def build_bridge_modes(structure: dict):
    """``(BridgeModel, BridgeModes, f_cut_Hz)`` of a normalised ``[structure]`` table."""
    from ..structures.bridge import BridgeModel, DeckSection
    sec = DeckSection(**structure["section"])
    model = BridgeModel(tuple(structure["spans_m"]), sec, continuous=structure["continuous"],
                        damping_ratio=structure["damping_ratio"], rail_height_m=structure["rail_height_m"],
                        start_m=structure["start_m"], elements_per_span=structure["elements_per_span"])
    cut = structure["modes_cutoff_Hz"]
    if cut == "en1990":
        cut = max(max(30.0, 1.5 * sec.vertical_frequency_Hz(L), sec.vertical_frequency_Hz(L, 3))
                  for L in structure["spans_m"])
        f_max = MODES_CUTOFF_MARGIN * cut
    else:
        f_max = float(cut)
    return model, model.modes(f_max_Hz=f_max), float(cut)


def _vehicle_data(scn: dict):
    from ..multibody.vehicle_data import load_vehicle_with_overrides
    v = scn["vehicle"]
    return load_vehicle_with_overrides(v.get("name") or v["file"], v.get("overrides") or None)


def scenario_run_settings(scn: dict, vehicle) -> tuple[RunSettings, dict]:
    """The run settings with the duration resolved, and what the run covers: ``t_passage_s`` is the time for the
    trailing wheelset to be ``run_out_m`` past the end of the last track feature (None without an ending
    feature)."""
    run = RunSettings(**scn["run"])
    V = scn["vehicle"]["speed_km_h"] / 3.6
    x = vehicle.wheelset_x_m()
    extent = float(max(x) - min(x))
    end = _features_end_m(scn)
    t_passage = None if end is None else (end - scn["vehicle"]["start_s_m"] + extent + run.run_out_m) / V
    if run.duration_s == DURATION_AUTO:
        if t_passage is None or t_passage <= 0.0:
            raise ScenarioError(f"run.duration_s = 'auto': the track features end at s = {end} m, behind the "
                                f"vehicle (leading wheelset at s = {scn['vehicle']['start_s_m']} m): give a time in "
                                "s")
        try:
            run = run.with_duration(t_passage)
        except SettingsError as exc:
            raise ScenarioError(f"run.duration_s = 'auto' ({t_passage:.6g} s): {exc.problem}") from None
    if run.steps > MAX_STEPS:
        raise ScenarioError(f"run.duration_s: {run.steps} steps (more than {MAX_STEPS})")
    return run, {"features_end_m": end, "vehicle_extent_m": extent, "t_passage_s": t_passage,
                 "duration_auto": scn["run"]["duration_s"] == DURATION_AUTO}


@dataclass
class ScenarioModel:
    """What :func:`build_scenario` created (assembled, not solved): handles, the resolved run settings, the
    recorder (None without recording) and the Exudyn solver settings (``settings``, ``solver_type``)."""

    scenario: dict
    system_container: object
    mbs: object
    vehicle: object
    model: object
    pair: object
    track: object
    contact: object                          #: the connector; None for ``contact.wheel_rail = "springs"``
    bridge: object
    modes: object
    f_cut_Hz: float | None
    run: RunSettings
    contact_settings: ContactSettings
    coverage: dict
    recorder: Recorder | None = None
    settings: object = None
    solver_type: object = None
    start_shift: float | None = None        #: largest track displacement under a wheelset at t = 0 (None: none)

    @property
    def speed_m_s(self) -> float:
        return self.scenario["vehicle"]["speed_km_h"] / 3.6

    @property
    def steps(self) -> int:
        return self.run.steps


def _carbody_x(x, vehicle) -> float:
    if isinstance(x, str):
        return {"front_bogie": max(vehicle.bogie_x_m()), "rear_bogie": min(vehicle.bogie_x_m()), "centre": 0.0}[x]
    return float(x)


def build_scenario(scenario) -> ScenarioModel:
    """Build and assemble the Exudyn model of a scenario (path or dict): vehicle, track, bridge, contact,
    recorder; not solved."""
    import exudyn as exu

    from ..contact.pair import WheelRailPair
    from ..multibody.connector import add_wheel_rail_contact, place_on_rails
    from ..multibody.vehicle_builder import build_vehicle

    scn, _ = _as_scenario(scenario)
    vehicle = _vehicle_data(scn)
    run, coverage = scenario_run_settings(scn, vehicle)
    cs = ContactSettings(**{**scn["contact"], "fastsim_grid": tuple(scn["contact"]["fastsim_grid"])})
    V = scn["vehicle"]["speed_km_h"] / 3.6
    s_lead0 = scn["vehicle"]["start_s_m"]
    s_start = s_lead0 - max(vehicle.wheelset_x_m())              # frame origin; leading wheelset at start_s_m
    modes = f_cut = None
    if "structure" in scn:
        _, modes, f_cut = build_bridge_modes(scn["structure"])
    geo = vehicle.geometry
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    springs = cs.wheel_rail == "springs"
    model = build_vehicle(mbs, vehicle, speed_m_s=V, s_start_m=s_start, wheel_rail="springs" if springs else "none")
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    track = build_track(scn)
    bridge = contact = shift = None
    if modes is not None:
        from ..structures.bridge import add_bridge
        bridge = add_bridge(mbs, modes, formulation=scn["structure"]["formulation"])
    if not springs:
        try:
            contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V, track=track,
                                             s_start_m=s_start, creep_law=cs.creep_law, mu=cs.friction,
                                             fastsim_grid=cs.fastsim_grid, geometry=cs.geometry,
                                             **({"bridge": bridge} if bridge is not None else {}))
        except FileNotFoundError as exc:      # e.g. the creep table of creep_law="table" has not been built
            raise RuntimeError(f"contact.creep_law = {cs.creep_law!r}: {exc}") from None
        place_on_rails(mbs, model, pair)
        shift = _start_on_track(mbs, model, track)
    h = ScenarioModel(scenario=scn, system_container=sc, mbs=mbs, vehicle=vehicle, model=model, pair=pair,
                      track=track, contact=contact, bridge=bridge, modes=modes, f_cut_Hz=f_cut, run=run,
                      contact_settings=cs, coverage=coverage, start_shift=shift)
    if run.record and contact is not None:
        points = [(p["name"], [_carbody_x(p["x_m"], vehicle), p["y_m"], -p["height_m"]])
                  for p in scn["outputs"]["carbody_points"]]
        st = scn.get("structure", {})
        probes = vehicle_probes(model=model, contact=contact, track=track, speed_m_s=V, s_leading0_m=s_lead0,
                                carbody_points=points, bridge=bridge, modes=modes, deck_spans_m=st.get("spans_m"),
                                deck_start_m=st.get("start_m"))
        h.recorder = Recorder(probes, n_rows_hint=run.steps // run.record_every + 2)
    mbs.Assemble()
    h.settings, h.solver_type = run.exudyn()
    return h


def _start_on_track(mbs, model, track) -> float | None:
    """Put the bodies' initial state on the track under the wheelsets at t = 0 (call after
    :func:`~..multibody.place_on_rails`, which puts the centred vehicle on the *undisplaced* rails).

    Each wheelset moves by the track's lateral and vertical displacement ``(y, z)`` at its track distance and is
    yawed along the track, ``ψ = atan(dy/ds)``; its velocity gets ``(V dy/ds, V dz/ds)`` and its yaw rate
    ``V y''/(1 + y'²)`` — the rates at which the track moves and turns under it in the frame moving with V —, so
    it starts without lateral creepage and without penetration.  Each bogie frame (and the car body) follows the
    straight line through its supports (its wheelsets; the bogie centres): displacement at its centre of mass,
    yaw ``atan(Δy/Δx)`` and pitch ``-atan(Δz/Δx)`` (z down: the nose goes up for θ > 0), with the matching rates
    (rotation vector ``(0, θ, ψ)``, the small-angle composition).  Without it a millimetre of vertical
    irregularity is a millimetre of Hertz penetration at t = 0 (MN contact forces) and a slope dy/ds a lateral
    creepage dy/ds.  Returns the largest displacement [m], or None when the track under every wheelset is
    undisplaced and parallel to the frame (nothing is changed)."""
    x = np.array([ws.p_cg_in_frame[0] for ws in model.wheelsets])
    v = track.rail_offset(model.track_distance_m(x, 0.0))
    if not (np.any(v.y_m) or np.any(v.z_m) or np.any(v.dy_ds) or np.any(v.dz_ds)):
        return None
    V = model.speed_m_s
    # per body: x, (y, z, pitch θ, yaw ψ) and their rates
    ws = [(x[j], np.array([v.y_m[j], v.z_m[j], 0.0, math.atan(v.dy_ds[j])]),
           V * np.array([v.dy_ds[j], v.dz_ds[j], 0.0, v.d2y_ds2[j] / (1.0 + v.dy_ds[j] ** 2)]))
          for j in range(len(x))]

    def on_line(supports, x_cg):
        """State of a body resting on the line through its supports (front and rear: largest and smallest x)."""
        f = max(supports, key=lambda b: b[0])
        r = min(supports, key=lambda b: b[0])
        dx = f[0] - r[0]
        lam = (x_cg - r[0]) / dx
        pos = r[1] + lam * (f[1] - r[1])
        rate = r[2] + lam * (f[2] - r[2])
        dy, dz = f[1][0] - r[1][0], f[1][1] - r[1][1]
        pos[2] = -math.atan(dz / dx)
        pos[3] = math.atan(dy / dx)
        rate[2] = -(f[2][1] - r[2][1]) / dx / (1.0 + (dz / dx) ** 2)
        rate[3] = (f[2][0] - r[2][0]) / dx / (1.0 + (dy / dx) ** 2)
        return x_cg, pos, rate

    def shift(node, state):
        _, pos, rate = state
        q0 = np.array(mbs.GetNodeParameter(node, "initialCoordinates"), dtype=float)
        v0 = np.array(mbs.GetNodeParameter(node, "initialVelocities"), dtype=float)
        q0[1:3] += pos[:2]
        q0[4:6] += pos[2:]              # rotation vector (0, θ, ψ); the reference rotation is zero
        v0[1:3] += rate[:2]
        v0[4:6] += rate[2:]             # body-frame angular velocity (= track frame for these small rotations)
        mbs.SetNodeParameter(node, "initialCoordinates", q0.tolist())
        mbs.SetNodeParameter(node, "initialVelocities", v0.tolist())

    for j, w in enumerate(model.wheelsets):
        shift(w.node, ws[j])
    bogies = []
    for i, b in enumerate(model.bogies):
        bogies.append(on_line([ws[j] for j, w in enumerate(model.wheelsets) if w.bogie == i], b.p_cg_in_frame[0]))
        shift(b.node, bogies[-1])
    if model.car_body is not None:
        shift(model.car_body.node, on_line(bogies, model.car_body.p_cg_in_frame[0]))
    return float(max(np.max(np.abs(v.y_m)), np.max(np.abs(v.z_m))))


# ==================================================================================================== running
@dataclass
class ScenarioResult:
    """Time series (every recorded column -> array), the summary dict, the written files and the run's outcome."""

    timeseries: dict
    summary: dict
    paths: dict = field(default_factory=dict)
    outcome: object = None


def peaks(ts: dict) -> dict:
    """Per recorded column (``time_s`` and ``s_leading_m`` aside): ``max_abs`` (with its signed value and its
    time), ``min``, ``max`` (NaN rows ignored)."""
    out = {}
    if not ts:
        return out
    t = ts["time_s"]
    for name, v in ts.items():
        if name in ("time_s", "s_leading_m") or len(v) == 0:
            continue
        if not np.isfinite(v).any():
            out[name] = {"max_abs": None, "value_at_max_abs": None, "time_of_max_abs_s": None, "min": None,
                         "max": None}
            continue
        i = int(np.nanargmax(np.abs(v)))
        out[name] = {"max_abs": float(abs(v[i])), "value_at_max_abs": float(v[i]), "time_of_max_abs_s": float(t[i]),
                     "min": float(np.nanmin(v)), "max": float(np.nanmax(v))}
    return out


def _scalars(ts: dict, groups: dict, pk: dict, criteria, dt: float) -> dict:
    """The flat dict of scalar results (what a sweep tabulates)."""
    out = {}
    if pk and ts and len(ts["time_s"]):
        def agg(fn, cols):
            vals = [fn(ts[c]) for c in cols if np.isfinite(ts[c]).any()]
            return float(max(vals)) if vals else None
        out["max_abs_Y_any_wheel_N"] = agg(lambda v: np.nanmax(np.abs(v)), groups["Y"])
        out["max_Q_any_wheel_N"] = agg(np.nanmax, groups["Q"])
        q_min = [float(np.nanmin(ts[c])) for c in groups["Q"]]
        out["min_Q_any_wheel_N"] = min(q_min) if q_min else None
        out["max_YQ_any_wheel"] = agg(np.nanmax, groups["YQ"])
        fl = np.array([ts[c] for c in groups["flange"]]) > 0.5
        out["flange_contact_any_wheel"] = bool(fl.any())
        out["flange_contact_duration_max_s"] = float(fl.sum(axis=1).max() * dt) if fl.size else 0.0
        out["max_abs_y_rel_any_wheelset_m"] = agg(lambda v: np.nanmax(np.abs(v)), groups["wheelset_lateral"])
        for name, p in pk.items():
            if not name.startswith("flange_"):
                out[f"max_abs_{name}"] = p["max_abs"]
    if isinstance(criteria, dict) and "verdicts" in criteria:
        out["criteria.safety_passed"] = criteria["safety_passed"]
        out["criteria.passed"] = criteria["passed"]
        for k, v in criteria["verdicts"].items():
            out[f"criteria.{k}.passed"] = v.get("passed")
            if "worst_value" in v:
                out[f"criteria.{k}.worst"] = v.get("worst")
                out[f"criteria.{k}.worst_value"] = v.get("worst_value")
                out[f"criteria.{k}.worst_utilisation"] = v.get("worst_utilisation")
        for k, v in criteria["criteria"].items():
            if k.startswith("carbody_"):
                out[f"criteria.{k}.peak_m_s2"] = v.get("peak_m_s2")
                out[f"criteria.{k}.rms_m_s2"] = v.get("rms_m_s2")
            elif k.startswith("sperling_"):
                out[f"criteria.{k}.Wz"] = v.get("Wz")
    return out


def _criteria(h: ScenarioModel, ts: dict, groups: dict) -> dict:
    from ..analysis.safety import running_criteria_summary
    o = h.scenario["outputs"]["criteria"]
    cols = {}
    p = o["carbody_point"]
    if p:
        cols = {"lateral": f"carbody_lateral_accelerometer_{p}_m_s2",
                "vertical": f"carbody_vertical_acceleration_{p}_m_s2"}
    static = _static_wheel_loads(h)
    sub = {k: ts[k] for k in ["time_s"] + groups["Y"] + groups["Q"] + list(cols.values())}
    return running_criteria_summary(sub, h.speed_m_s, vehicle=o["vehicle"], static_wheel_loads_N=static,
                                    yq_limit=o["yq_limit"], unloading_limit=o["unloading_limit"],
                                    carbody_columns=cols or None)


def _static_wheel_loads(h: ScenarioModel) -> dict:
    wheel = h.model.load_path.wheel                                          # (n_ws, 2) in (left, right)
    return {f"w{j + 1}_{side}": float(wheel[j, 0 if side == "left" else 1])
            for j in range(len(h.model.wheelsets)) for side in SIDES_OUT}


def run_model(h, *, progress=None, view=None, label: str = ""):
    """Warm up and run a built model (:class:`ScenarioModel`) through the one solve wrapper
    (:func:`exudyn_wheelrail.simulation.runner.run`); returns the :class:`~exudyn_wheelrail.simulation.runner.
    RunOutcome`.  ``progress``: ``None`` — the run settings' ``progress``; ``True``/``False``; or a stream for the
    bar (runs of at least :data:`~exudyn_wheelrail.simulation.recorder.PROGRESS_MIN_STEPS` steps).  ``view``: an
    object with ``attach(model)`` (before the solve) and ``close()`` (after it), e.g.
    :class:`~exudyn_wheelrail.interactive.view3d.RtriView`."""
    from ..simulation.runner import run
    if view is not None:
        view.attach(h)
    if h.contact is not None:
        h.contact.warm_up(h.mbs, jacobian=h.run.implicit)
    show = h.run.progress if progress is None else progress
    bar = None
    if show and h.run.steps >= PROGRESS_MIN_STEPS:
        bar = ProgressBar(h.run.end_time_s, stream=None if show is True else show, label=label)
    try:
        outcome = run(h.mbs, h.run, h.contact, speed_m_s=h.speed_m_s, recorder=h.recorder, progress=bar,
                      exu_settings=(h.settings, h.solver_type))
    finally:
        if view is not None:
            view.close()
    if bar is not None:
        bar.close(outcome.status.kind)
    return outcome


def run_scenario(scenario, out_dir=None, progress=None, view=None) -> ScenarioResult:
    """Build, solve and evaluate a scenario (a file path or a scenario dict); write the outputs into ``out_dir``
    (``None``: write nothing; checked before anything is built).  ``progress``, ``view``: :func:`run_model`.  The
    summary's ``status`` is one of :data:`~exudyn_wheelrail.simulation.status.STATUSES`."""
    scn, source = _as_scenario(scenario)
    if out_dir is not None:
        output_dir("out_dir", out_dir)
    h = build_scenario(scn)
    outcome = run_model(h, progress=progress, view=view, label=f"{scn['scenario']['name']}: ")
    result = scenario_summary(h, outcome, source)
    if out_dir is not None:
        result.paths = write_scenario_outputs(result, out_dir)
    return result


def _events(outcome, limit: int = 200) -> list:
    """The monitor's events (the first ``limit``) as plain dicts."""
    return [{"kind": e.kind, "time_s": e.time_s, "wheelset": e.wheelset, "side": e.side, "detail": e.detail}
            for e in outcome.events[:limit]]


def scenario_summary(h: ScenarioModel, outcome, source: str | None = None) -> ScenarioResult:
    """The :class:`ScenarioResult` of a run: the recorded time series and the summary (module docstring)."""
    scn = h.scenario
    run = h.run
    status = outcome.status
    rec = h.recorder
    ts = rec.table() if rec is not None else {}
    groups = {g: cols for g, cols in (rec.groups.items() if rec is not None else []) if g in TIMESERIES_GROUPS}
    notes = _notes(h, outcome)
    evaluate = status.kind != S.DIVERGED and bool(ts) and len(ts["time_s"]) > 0
    criteria = None
    if scn["outputs"]["criteria"]["enabled"] and rec is not None:
        if not evaluate:
            criteria = {"error": f"not evaluated: the run {status.kind}"}
        else:
            try:
                criteria = _criteria(h, ts, groups)
            except ValueError as exc:
                criteria = {"error": str(exc)}
                notes.append(f"criteria not evaluated: {exc}")
    pk = peaks(ts) if evaluate else {}
    dt = float(run.dt_s)
    t_end = run.end_time_s
    sim_time = outcome.t_end_s
    summary = {
        "scenario_name": scn["scenario"]["name"],
        "scenario_file": source,
        "status": status.kind,
        "status_detail": status.as_dict(),
        "events": _events(outcome),
        "n_events": len(outcome.events),
        "steps": run.steps,
        "dt_s": dt,
        "duration_s": t_end,
        "simulated_time_s": sim_time,
        "solve_seconds": outcome.solve_seconds,
        "real_time_factor": sim_time / outcome.solve_seconds if outcome.solve_seconds > 0 else None,
        "rows_recorded": int(len(ts["time_s"])) if ts else 0,
        "rows_dropped_after_divergence": outcome.rows_dropped,
        "rejected_steps": outcome.rejected_steps,
        "contact_omega_rad_s": outcome.contact_omega_rad_s,
        "speed_m_s": h.speed_m_s,
        "run_settings": run.as_dict(),
        "solver": {"name": run.solver, "exudyn": run.describe_solver()},
        "contact_calls": int(h.contact.n_calls) if h.contact is not None else 0,
        "geometry": h.contact.geometry_statistics() if h.contact is not None else None,
        "skipped": h.contact.skipped() if h.contact is not None else None,
        "coverage": {**h.coverage, "t_end_s": t_end,
                     "passage_covered": None if h.coverage["t_passage_s"] is None
                     else bool(t_end >= h.coverage["t_passage_s"] - 1e-9)},
        "model": _model_info(h),
        "columns": {g: list(cols) for g, cols in groups.items() if cols},
        "written_groups": list(scn["outputs"]["timeseries"]),
        "peaks": pk,
        "scalars": _scalars(ts, groups, pk, criteria, dt),
        "criteria": criteria,
        "notes": notes,
        "sign_conventions": {
            "Y": "Y_w<j>_<side>_N: track-frame y component (+ right) of the contact force of the rail on the wheel",
            "Q": "Q_w<j>_<side>_N: wheel load, -F_z of the force on the wheel (z down): positive pressing",
            "YQ": "YQ_w<j>_<side>: Y positive towards the wheel's field side (-F_y right, +F_y left) over Q; NaN "
                  "when lifted",
            "wheelset_lateral": "y_rel_w<j>_m: axle centre relative to the rails' centre line at rail top, + right",
            "track": "track_<lateral|vertical>_w<j>_m: track irregularity under wheelset j (y right, z down)",
            "carbody": "acceleration: track frame (y right, z down), no gravity; accelerometer: a - g in the car "
                       "body's axes; displacement: track frame",
            "deck": "vertical, + down, mid-span on the track centre line at rail-top level",
        },
        "scenario": scn,
    }
    return ScenarioResult(timeseries=ts, summary=summary, outcome=outcome)


def _model_info(h: ScenarioModel) -> dict:
    info = {"vehicle": h.vehicle.name, "layout": h.vehicle.layout, "n_wheelsets": len(h.model.wheelsets),
            "wheelset_x_m": [float(x) for x in h.vehicle.wheelset_x_m()],
            "frame_s_start_m": float(h.model.s_start_m), "wheel_rail_pair": repr(h.pair),
            "static_wheel_loads_N": _static_wheel_loads(h), "bridge": None}
    if h.modes is not None:
        info["bridge"] = {"n_modes": int(h.modes.n_modes), "f_cut_Hz": h.f_cut_Hz,
                          "frequencies_Hz": [float(f) for f in h.modes.frequencies_Hz], "kinds": list(h.modes.kinds),
                          "formulation": h.scenario["structure"]["formulation"]}
    return info


def _notes(h: ScenarioModel, outcome) -> list:
    notes = []
    cov = h.coverage
    t_end = h.run.end_time_s
    if cov["t_passage_s"] is not None and not cov["duration_auto"] and t_end < cov["t_passage_s"] - 1e-9:
        notes.append(f"the run ends at {t_end:.3f} s, before the trailing wheelset is run_out_m past the last track "
                     f"feature ({cov['t_passage_s']:.3f} s; duration_s = 'auto' runs that long)")
    x0 = np.asarray(h.model.track_distance_m(np.array([ws.p_cg_in_frame[0] for ws in h.model.wheelsets]), 0.0))
    if "structure" in h.scenario:
        st = h.scenario["structure"]
        end = st["start_m"] + sum(st["spans_m"])
        if np.any((x0 > st["start_m"]) & (x0 < end)):
            notes.append("a wheelset stands on the deck at t = 0: the unloaded deck starts with the vehicle's "
                         "weight on it (free vibration transient); start the vehicle off the deck")
    if h.start_shift is not None:
        notes.append(f"the track is displaced by up to {h.start_shift * 1e3:.3g} mm under the wheelsets at t = 0: the "
                     "bodies start on it (wheelsets moved and yawed with the track under them, bogie frames and car "
                     "body along the line through their supports, with the matching rates); the suspensions carry "
                     "what the track's curvature leaves over, so the run may start with a small transient")
    if h.contact_settings.wheel_rail == "springs":
        notes.append("contact.wheel_rail = springs: cost baseline only (the irregularities do not act on linear "
                     "springs; nothing is recorded or watched)")
    notes += outcome.warnings
    status = outcome.status
    if status.kind != S.OK:
        notes.append(f"the run ended {status.kind} (status_detail): the time series hold the rows recorded up to the "
                     "last valid state"
                     + (f" ({outcome.rows_dropped} rows after the first step beyond the stability limit dropped)"
                        if outcome.rows_dropped else "")
                     + ("; peaks not evaluated" if status.kind == S.DIVERGED else ""))
    return notes


# ==================================================================================================== outputs
def jsonable(o):
    """``json.dump``'s ``default``: NumPy scalars and arrays as Python values."""
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.bool_):
        return bool(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, tuple):
        return list(o)
    raise TypeError(f"{type(o).__name__} is not JSON serialisable")


def write_scenario_outputs(result: ScenarioResult, out_dir) -> dict:
    """Write ``timeseries.csv`` / ``.npz`` (the written groups), ``summary.json`` and the plots; returns the paths."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    s = result.summary
    o = s["scenario"]["outputs"]
    ts = result.timeseries
    paths = {}
    if ts:
        cols = ["time_s", "s_leading_m"] + [c for g in o["timeseries"] for c in s["columns"].get(g, [])]
        if "csv" in o["formats"]:
            paths["timeseries_csv"] = out / "timeseries.csv"
            write_csv(paths["timeseries_csv"], {c: ts[c] for c in cols})
        if "npz" in o["formats"]:
            paths["timeseries_npz"] = out / "timeseries.npz"
            np.savez_compressed(paths["timeseries_npz"], **{c: ts[c] for c in cols})
    paths["summary"] = out / "summary.json"
    write_json(paths["summary"], s)
    if o["plots"] and ts and len(ts["time_s"]) > 1:
        for g in o["timeseries"]:
            if g in _FIGURES and s["columns"].get(g):
                paths[f"plot_{g}"] = out / f"plot_{g}.png"
                _plot_group(result, g, paths[f"plot_{g}"])
    return {k: str(v) for k, v in paths.items()}


def write_csv(path, ts: dict) -> None:
    """A time series (column -> array) as CSV, 10 significant digits."""
    cols = list(ts)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        if cols and len(ts[cols[0]]):
            for row in np.column_stack([ts[c] for c in cols]):
                w.writerow([f"{v:.10g}" for v in row])


def write_json(path, data: dict) -> None:
    with open(path, "w") as fh:
        json.dump(data, fh, indent=2, allow_nan=True, default=jsonable)


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


# ----------------------------------------------------------------------------------------------------- plots
# What a plot shows (one quantity per axis, its unit in the label) and how the lines are named: wheelset j
# (1 = leading) and the side as the user reads it.  Colours: one per side in the per-wheel plots, one per wheelset
# (or car-body point) where the wheelsets share an axis.
_SIDE_COLOUR = {"right": "C0", "left": "C3"}
_SIDE_NOTE = "right/left: looking in the running direction (track y + right)"
_WHEEL_COLUMN = re.compile(r"_w(\d+)_(right|left)")
#: colour of the criteria's limit lines
_LIMIT_COLOUR = "k"
_FIG_WIDTH_IN = 12.0


def _wheel_of(column: str) -> tuple[int, str]:
    """(wheelset number, side) of a per-wheel column name (``Y_w2_left_N`` -> (2, "left"))."""
    m = _WHEEL_COLUMN.search(column)
    return int(m.group(1)), m.group(2)


def _wheel_label(wheelset: int, side: str) -> str:
    """Legend name of a wheel: ``"wheelset 1, right"`` (wheelsets numbered from 1 = leading)."""
    return f"wheelset {wheelset}, {side}"


def _run_title(s: dict) -> str:
    scn = s["scenario"]
    run = scn["run"]
    return (f"{s['scenario_name']}: {s['model']['vehicle']}, {scn['vehicle']['speed_km_h']:g} km/h, {run['solver']}, "
            f"dt {run['dt_s'] * 1e3:g} ms, creep law {scn['contact']['creep_law']}\nwheelset 1 = leading; "
            f"{_SIDE_NOTE}")


def _criteria_inputs(s: dict) -> dict:
    """Limits and evaluation settings of the run's criteria: those the run applied (``summary["criteria"]``), or,
    where the criteria were not evaluated, those it would have applied (the scenario's settings and the defaults
    of :mod:`~..analysis.safety`)."""
    from ..analysis import safety
    o = s["scenario"]["outputs"]["criteria"]
    ev = s.get("criteria") if isinstance(s.get("criteria"), dict) else {}
    inp = ev.get("inputs", {})
    return {"yq_limit": inp.get("yq_limit_en14363", o["yq_limit"]),
            "unloading_limit": inp.get("unloading_limit", o["unloading_limit"]),
            "window_m": inp.get("window_m_requested", safety.EN14363_WINDOW_M),
            "lowpass_hz": inp.get("force_lowpass_hz", safety.EN14363_FORCE_LOWPASS_HZ),
            "nadal_limit": inp.get("nadal_limit"),
            "alpha": inp.get("prudhomme_alpha", safety.PRUDHOMME_ALPHA[o["vehicle"]]),
            "criteria": ev.get("criteria", {})}


def _sliding_2m(x: np.ndarray, t: np.ndarray, speed_m_s: float, ci: dict, ignore_nan: bool = False):
    """The EN 14363 sliding mean over the criteria's window (2 m) of a series (already low-passed with
    :func:`_lowpassed`), as :mod:`~..analysis.safety` evaluates it: (window centre times, means), or ``None`` when
    the record is shorter than the window."""
    from ..analysis import comfort
    dt = float(t[1] - t[0])
    try:
        n = comfort.window_samples(ci["window_m"], speed_m_s, dt)
        m = comfort.sliding_mean(x, n, ignore_nan=ignore_nan)
    except ValueError:
        return None
    return t[: len(m)] + 0.5 * (n - 1) * dt, m


def _lowpassed(x: np.ndarray, dt: float, ci: dict, name: str):
    """The criteria's force low-pass (EN 14363: 20 Hz) of a series; ``ValueError`` if the record is too short."""
    from ..analysis import comfort
    if ci["lowpass_hz"] is None:
        return x
    return comfort.lowpass(x, dt, ci["lowpass_hz"], name=name)


def _limit_line(ax, value: float, label: str, gid: str, style: str = "--") -> None:
    ax.axhline(value, color=_LIMIT_COLOUR, ls=style, lw=1.3, label=label, gid=gid)


def _wheelsets(cols) -> list[int]:
    return sorted({_wheel_of(c)[0] for c in cols})


def _per_wheelset_axes(plt, n_rows: int, title: str):
    fig, axes = plt.subplots(n_rows, 1, figsize=(_FIG_WIDTH_IN, 1.2 + 2.1 * n_rows), sharex=True, squeeze=False,
                             layout="constrained")
    axes = axes[:, 0]
    fig.suptitle(title, fontsize=8)
    return fig, axes


def _figure_Y(plt, result: ScenarioResult):
    """Y per wheel, one axis per wheelset; below, the track shift force ΣY_2m per wheelset with Prud'homme's
    limit (EN 14363) when the run has both wheels of a wheelset."""
    from ..analysis.safety import prudhomme_limit_N
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    cols = s["columns"]["Y"]
    ci = _criteria_inputs(s)
    ws = _wheelsets(cols)
    both = [j for j in ws if f"Y_w{j}_right_N" in ts and f"Y_w{j}_left_N" in ts]
    fig, axes = _per_wheelset_axes(plt, len(ws) + (1 if both else 0), _run_title(s))
    for ax, j in zip(axes, ws):
        for c in cols:
            if _wheel_of(c)[0] == j:
                side = _wheel_of(c)[1]
                ax.plot(t, ts[c] * 1e-3, color=_SIDE_COLOUR[side], lw=0.7, label=_wheel_label(j, side))
        ax.set_ylabel("Y [kN]")
    axes[0].set_title("Y: lateral force of the rail on the wheel, track y (+ right)", fontsize=8)
    if both:
        ax = axes[len(ws)]
        dt = float(t[1] - t[0])
        v = s["speed_m_s"]
        limits = set()
        for k, j in enumerate(both):
            sum_y = -(ts[f"Y_w{j}_right_N"] + ts[f"Y_w{j}_left_N"])
            try:
                curve = _sliding_2m(_lowpassed(sum_y, dt, ci, "sum_Y_N"), t, v, ci)
            except ValueError:
                curve = None
            if curve is not None:
                ax.plot(curve[0], curve[1] * 1e-3, color=f"C{k}", lw=1.0, label=f"wheelset {j}")
            q0 = 0.5 * (s["model"]["static_wheel_loads_N"][f"w{j}_right"] +
                        s["model"]["static_wheel_loads_N"][f"w{j}_left"])
            limits.add(round(prudhomme_limit_N(q0, ci["alpha"]), 6))
        for lim in sorted(limits):
            label = f"Prud'homme limit α(10 kN + 2Q₀/3) = ±{lim * 1e-3:.1f} kN"
            _limit_line(ax, lim * 1e-3, label, "limit:prudhomme")
            _limit_line(ax, -lim * 1e-3, None, "limit:prudhomme")
        ax.set_ylabel("ΣY₂ₘ [kN]")
        ax.set_title(f"track shift force ΣY₂ₘ = −(F_y,right + F_y,left), {ci['lowpass_hz']:g} Hz low-pass, "
                     f"{ci['window_m']:g} m sliding mean (EN 14363), at the window centre", fontsize=8)
    return fig, axes


def _figure_Q(plt, result: ScenarioResult):
    """Q per wheel, one axis per wheelset, with the static wheel load and the wheel-unloading limit
    ΔQ/Q₀ as the wheel load Q = (1 − limit) Q₀ it allows."""
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    cols = s["columns"]["Q"]
    ci = _criteria_inputs(s)
    q_static = s["model"]["static_wheel_loads_N"]
    ws = _wheelsets(cols)
    fig, axes = _per_wheelset_axes(plt, len(ws), _run_title(s))
    lim = ci["unloading_limit"]
    for ax, j in zip(axes, ws):
        statics = set()
        for c in cols:
            jj, side = _wheel_of(c)
            if jj == j:
                ax.plot(t, ts[c] * 1e-3, color=_SIDE_COLOUR[side], lw=0.6, label=_wheel_label(j, side))
                statics.add(round(q_static[f"w{j}_{side}"], 6))
        for q0 in sorted(statics):
            ax.axhline(q0 * 1e-3, color="0.4", ls=":", lw=1.0, label=f"static wheel load Q₀ = {q0 * 1e-3:.1f} kN",
                       gid="static_wheel_load")
            _limit_line(ax, (1.0 - lim) * q0 * 1e-3,
                        f"wheel-unloading limit ΔQ/Q₀ = {lim:g} (Q = {(1.0 - lim) * q0 * 1e-3:.1f} kN)",
                        "limit:wheel_unloading")
        ax.set_ylabel("Q [kN]")
    axes[0].set_title("Q: wheel load (vertical force of the rail on the wheel, + pressing)", fontsize=8)
    return fig, axes


def _figure_YQ(plt, result: ScenarioResult):
    """Y/Q per wheel, one axis per wheelset: the instantaneous quotient (thin; the JNR criterion's limit, for
    exceedances of at least its reference duration) and the EN 14363 quotient (Y, Q low-passed, 2 m sliding mean;
    bold) with its limit; Nadal's limit when the run evaluated it."""
    from ..analysis import safety
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    dt = float(t[1] - t[0])
    cols = s["columns"]["YQ"]
    ci = _criteria_inputs(s)
    ws = _wheelsets(cols)
    fig, axes = _per_wheelset_axes(plt, len(ws), _run_title(s))
    for ax, j in zip(axes, ws):
        for c in cols:
            jj, side = _wheel_of(c)
            if jj != j:
                continue
            ax.plot(t, ts[c], color=_SIDE_COLOUR[side], lw=0.5, alpha=0.45,
                    label=f"{_wheel_label(j, side)}: Y/Q instantaneous")
            y_col, q_col = f"Y_w{j}_{side}_N", f"Q_w{j}_{side}_N"
            if y_col in ts and q_col in ts:
                try:
                    y = _lowpassed(safety.flange_lateral_force_N(ts[y_col], side), dt, ci, "Y_N")
                    q = _lowpassed(ts[q_col], dt, ci, "Q_N")
                    curve = _sliding_2m(safety.derailment_quotient(y, q), t, s["speed_m_s"], ci, ignore_nan=True)
                except ValueError:
                    curve = None
                if curve is not None:
                    ax.plot(curve[0], curve[1], color=_SIDE_COLOUR[side], lw=1.6,
                            label=f"{_wheel_label(j, side)}: (Y/Q)₂ₘ (EN 14363)", gid=f"yq2m:w{j}_{side}")
        if abs(ci["yq_limit"] - safety.JNR_YQ_LIMIT) < 1e-12:
            _limit_line(ax, ci["yq_limit"], f"limit {ci['yq_limit']:g}: EN 14363 on (Y/Q)₂ₘ; JNR on Y/Q lasting "
                        f"≥ {safety.JNR_DURATION_S * 1e3:g} ms", "limit:yq_en14363")
        else:
            _limit_line(ax, ci["yq_limit"], f"EN 14363 limit on (Y/Q)₂ₘ: {ci['yq_limit']:g}", "limit:yq_en14363")
            _limit_line(ax, safety.JNR_YQ_LIMIT, f"JNR limit on Y/Q lasting ≥ {safety.JNR_DURATION_S * 1e3:g} ms: "
                        f"{safety.JNR_YQ_LIMIT:g}", "limit:yq_jnr", style="-.")
        if ci["nadal_limit"] is not None:
            _limit_line(ax, ci["nadal_limit"], f"Nadal limit {ci['nadal_limit']:.3g}", "limit:nadal", style=":")
        ax.set_ylabel("Y/Q [-]")
    axes[0].set_title(f"Y/Q, Y towards the wheel's field side; (Y/Q)₂ₘ: {ci['lowpass_hz']:g} Hz low-pass, "
                      f"{ci['window_m']:g} m sliding mean, at the window centre", fontsize=8)
    return fig, axes


def _figure_wheelset_lateral(plt, result: ScenarioResult):
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    fig, ax = plt.subplots(figsize=(_FIG_WIDTH_IN, 4.5), layout="constrained")
    for c in s["columns"]["wheelset_lateral"]:
        j = int(re.search(r"_w(\d+)_", c).group(1))
        ax.plot(t, ts[c] * 1e3, color=f"C{(j - 1) % 10}", lw=0.9, label=f"wheelset {j}")
    ax.set(xlabel="time [s]", ylabel="lateral displacement [mm]")
    fig.suptitle(_run_title(s), fontsize=8)
    ax.set_title("axle centre relative to the rails' centre line (+ right, looking in the running direction)",
                 fontsize=8)
    return fig, np.array([ax])


def _point_label(p: dict) -> str:
    x = p["x_m"]
    where = {"front_bogie": "above the front bogie", "rear_bogie": "above the rear bogie",
             "centre": "at the vehicle centre"}.get(x) if isinstance(x, str) else f"x = {x:g} m"
    side = f", y = {p['y_m']:g} m" if p.get("y_m") else ""
    return f"car body '{p['name']}' ({where}{side}, {p['height_m']:g} m above rail)"


def _figure_carbody(plt, result: ScenarioResult):
    """Lateral and vertical car-body acceleration (one axis each) of every car-body point; the criteria's
    point also with the signal the comfort criteria evaluate, and their results (Sperling's Wz, the EN 14363
    band-passed peak and RMS) written on the axis."""
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    ci = _criteria_inputs(s)
    points = s["scenario"]["outputs"]["carbody_points"]
    fig, axes = plt.subplots(2, 1, figsize=(_FIG_WIDTH_IN, 6.5), sharex=True, layout="constrained")
    fig.suptitle(_run_title(s), fontsize=8)
    for ax, direction in zip(axes, ("lateral", "vertical")):
        assessed = ci["criteria"].get(f"carbody_{direction}", {}).get("column")
        for k, p in enumerate(points):
            c = f"carbody_{direction}_acceleration_{p['name']}_m_s2"
            if c in ts:
                ax.plot(t, ts[c], color=f"C{k}", lw=0.9, label=_point_label(p))
            if assessed and assessed != c and assessed.endswith(f"_{p['name']}_m_s2"):
                ax.plot(t, ts[assessed], color=f"C{k}", lw=0.7, ls="--",
                        label=f"car body '{p['name']}', floor accelerometer (body axes, a − g)")
        ax.set_ylabel(f"{direction} acceleration [m/s²]")
        # the comfort criteria are numbers, not time series: their results are legend entries
        sp = ci["criteria"].get(f"sperling_{direction}")
        cb = ci["criteria"].get(f"carbody_{direction}")
        if sp or cb:
            what = "floor accelerometer" if "accelerometer" in assessed else "track frame"
            name = next((p["name"] for p in points if assessed.endswith(f"_{p['name']}_m_s2")), assessed)
            ax.plot([], [], " ", label=f"criteria on car body '{name}', {what}:")
        if sp:
            limit = "no limit set" if sp.get("limit") is None else f"limit {sp['limit']:g}"
            ax.plot([], [], " ", gid=f"criteria:sperling_{direction}",
                    label=f"  Sperling Wz = {sp['Wz']:.2f} ({sp['ride_quality']}; {limit})")
        if cb:
            lim = {k: v.get("limit") for k, v in cb.get("assessment", {}).items()}
            limit = ("no limit set" if not any(v is not None for v in lim.values()) else
                     ", ".join(f"{k} limit {v:g} m/s²" for k, v in lim.items() if v is not None))
            ax.plot([], [], " ", gid=f"criteria:carbody_{direction}",
                    label=f"  EN 14363 band-pass {cb['band_hz'][0]:g}–{cb['band_hz'][1]:g} Hz: peak "
                          f"{cb['peak_m_s2']:.3f} m/s², RMS {cb['rms_m_s2']:.3f} m/s² ({limit})")
    axes[0].set_title("acceleration: track frame (y right, z down), kinematic (no gravity)", fontsize=8)
    return fig, axes


def _figure_deck(plt, result: ScenarioResult):
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    fig, axes = plt.subplots(2, 1, figsize=(_FIG_WIDTH_IN, 6), sharex=True, layout="constrained")
    fig.suptitle(_run_title(s), fontsize=8)
    for c in s["columns"]["deck"]:
        i = int(re.search(r"_s(\d+)_", c).group(1))
        deflection = "deflection" in c
        ax = axes[0] if deflection else axes[1]
        ax.plot(t, ts[c] * (1e3 if deflection else 1.0), color=f"C{(i - 1) % 10}", lw=0.9, label=f"span {i}")
    axes[0].set(ylabel="deflection [mm]")
    axes[0].set_title("deck at mid-span, on the track centre line, vertical (+ down)", fontsize=8)
    axes[1].set(ylabel="acceleration [m/s²]")
    return fig, axes


_FIGURES = {"Y": _figure_Y, "Q": _figure_Q, "YQ": _figure_YQ, "wheelset_lateral": _figure_wheelset_lateral,
            "carbody": _figure_carbody, "deck": _figure_deck}


def group_figure(result: ScenarioResult, group: str):
    """The matplotlib figure of one column group (``plot_<group>.png``), not saved; returns (figure, axes)."""
    plt = _pyplot()
    fig, axes = _FIGURES[group](plt, result)
    for ax in axes:
        ax.grid(True, alpha=0.3)
        handles, labels = ax.get_legend_handles_labels()
        if handles:
            ax.legend(fontsize=6.5, loc="upper left", bbox_to_anchor=(1.005, 1.0), borderaxespad=0.0)
    axes[-1].set_xlabel("time [s]")
    return fig, axes


def _plot_group(result: ScenarioResult, group: str, path) -> None:
    plt = _pyplot()
    fig, _ = group_figure(result, group)
    fig.savefig(path, dpi=100)
    plt.close(fig)
