r"""The scenario spec: the schema's constants, the loader and the validation (overrides: :mod:`.overrides`).

The schema itself (every table and key, its default and range) is written in the docstring of
:mod:`exudyn_wheelrail.scenarios.scenario`, the public import path of the scenario functions.  :func:`load_scenario`
reads a TOML file, :func:`validate_scenario` checks a scenario (as read, or in its normal form: idempotent) and
returns the **normal form** — a plain dict of plain values (picklable, JSON- and TOML-representable) with every
default filled in and file paths absolute (:func:`~.overrides.apply_overrides` applies dotted keys to a normal
form and validates again).  Errors are :class:`ScenarioError` naming the source and the dotted key.
"""
from __future__ import annotations

import copy
import math
import re
from pathlib import Path

from ..analysis.curving import CURVING_GROUP
from ..simulation.recorder import GROUPS
from ..simulation.settings import DURATION_AUTO, ContactSettings, RunSettings, SettingsError, settings_from_mapping
from ..simulation.solvers import METHODS
from ..structures.bridge_exudyn import FORMULATIONS
from ..track.irregularities import CHANNELS, DEFECT_SHAPES, RAILS, FadedIn
from ..track.measured import read_irregularity_csv
from ..track.rigid import SampledIrregularity
from ..track.spectra import DEFAULT_BAND_M, DEFAULT_STEP_M, SPECTRA, SpectralIrregularity
from ..validation import Quantity, read_toml
from .bridge_crossing_case import F1_HZ, MASS_KG_M
from .deck import DECK_GROUPS, PLATEAU_AUTO, TRACK_FORMS, support_motion_default
from .flexible_track import FLEXIBLE_TRACK_GROUP, default_step_s, normalise_flexible_track
from .spec_crossing import is_crossing, normalise_crossing
from .spec_layout import layout_combination_error, layout_run_settings, normalise_layout

__all__ = ["SCHEMA_VERSION", "V1_MOVED", "TRACK_TYPES", "DIRECTIONS", "UNLOADING_GROUP", "STRUCTURE_GROUPS",
           "TIMESERIES_GROUPS", "FORMATS", "NAMED_X", "CRITERIA_VEHICLES", "DEFAULT_FLOOR_HEIGHT_M", "QUANTITIES",
           "ScenarioError", "load_scenario", "validate_scenario", "features_end_m", "as_scenario", "spectrum_table",
           "SPECTRUM_OPTIONS"]

SCHEMA_VERSION = 2
#: keys of ``schema_version = 1`` files (and overrides) -> their place in version 2
V1_MOVED = {"run.speed_km_h": "vehicle.speed_km_h", "run.start_s_m": "vehicle.start_s_m",
            "run.creep_law": "contact.creep_law", "run.friction": "contact.friction",
            "run.fastsim_grid": "contact.fastsim_grid"}
TRACK_TYPES = ("span_deflection", "harmonic", "sampled", "measured", "spectrum", "defect")
#: irregularity channels of span deflections and harmonics: lateral (alignment), vertical (level), cross level, gauge
DIRECTIONS = ("lateral", "vertical", "cross_level", "gauge")
#: the wheel unloading ``dQQ_w<j>_<side>`` = (Q₀ − Q)/Q₀ per wheel (Q₀ the static wheel load of the vehicle's load
#: path), derived from the recorded Q after the run (:mod:`.run`)
UNLOADING_GROUP = "unloading"
#: the groups that need a ``[structure]``: the recorder's mid-span group and the deck's own (:mod:`.deck`)
STRUCTURE_GROUPS = ("deck",) + DECK_GROUPS
#: column groups of the time series, in the order they are written: the recorder's
#: (:mod:`exudyn_wheelrail.simulation.recorder`), the wheel unloading, the deck's, the flexible track's, the curve's
#: (with a ``[layout]``: :func:`~exudyn_wheelrail.analysis.curving.curving_columns`)
TIMESERIES_GROUPS = GROUPS + (UNLOADING_GROUP,) + DECK_GROUPS + (FLEXIBLE_TRACK_GROUP, CURVING_GROUP)
FORMATS = ("csv", "npz")
NAMED_X = ("front_bogie", "rear_bogie", "centre")
CRITERIA_VEHICLES = ("passenger", "locomotive", "freight")
#: ASSUMPTION: height of a car-body floor above the top of rail [m] — typical of a standard-gauge passenger coach
#: (~1.2 m); the Manchester data give none.  The default car-body points and the RTRI accelerometer sit there.
DEFAULT_FLOOR_HEIGHT_M = 1.20
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
#: Plausibility of the scenario's lengths and ground motion beyond their type and sign, by key (``track.*`` for
#: every track component): a value outside is an error, a length evidently given in millimetres is named so.  (The
#: time step and the run-out are judged by :mod:`exudyn_wheelrail.simulation.settings`.)
QUANTITIES = {
    "track.*.amplitude_m": Quantity("track irregularity amplitude", "m", 0.0, 0.1, magnitude=True),
    "track.*.span_length_m": Quantity("span length of a span deflection", "m", 1.0, 1000.0),
    "track.*.transition_length_m": Quantity("transition length", "m", 0.0, 200.0),
    "track.*.wavelength_m": Quantity("irregularity wavelength", "m", 0.01, 1000.0),
    "track.*.depth_m": Quantity("isolated defect depth", "m", 0.0, 0.05, magnitude=True),
    "track.*.length_m": Quantity("length of an isolated defect or a generated irregularity", "m", 0.01, 100000.0),
    "structure.spans_m": Quantity("bridge span length", "m", 1.0, 1000.0),
    "structure.rail_height_m": Quantity("height of the rail top above the deck's beam axis", "m", 0.0, 10.0),
    "structure.mass_kg_m": MASS_KG_M,
    "structure.f1_Hz": F1_HZ,
    "structure.lateral_f1_Hz": F1_HZ,
    "structure.support_motion.peak_acceleration_m_s2": Quantity("peak ground acceleration", "m/s²", 0.0, 10.0),
    "structure.support_motion.frequency_Hz": Quantity("ground-motion frequency", "Hz", 0.1, 20.0),
    "structure.support_motion.ramp_cycles": Quantity("ramp length of the ground-motion burst in periods", "", 0.0,
                                                     100.0),
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

    def plausible(self, x: float, key: str, quantity) -> float:
        """``x`` judged by ``quantity`` (a :class:`~exudyn_wheelrail.validation.Quantity`, or its key of
        :data:`QUANTITIES`): an error naming the key if implausible, a warning if unusual."""
        quantity = QUANTITIES[quantity] if isinstance(quantity, str) else quantity
        return quantity.check(f"{self.source}: {key}", x, error=ScenarioError)

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


def load_scenario(path, vehicle=None) -> dict:
    """Read and validate a scenario file; returns the normalised scenario (module docstring).  ``vehicle`` as
    :func:`validate_scenario`."""
    path = Path(path)
    if not path.is_file():
        raise ScenarioError(f"{path}: scenario file not found")
    data = read_toml(path, ScenarioError)
    return validate_scenario(data, source=str(path), base_dir=path.resolve().parent, default_name=path.stem,
                             vehicle=vehicle)


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


def validate_scenario(data: dict, source: str = "<dict>", base_dir=None, default_name: str = "scenario",
                      vehicle=None) -> dict:
    """Validate a scenario (as read from TOML, or a normalised scenario) and return its normal form: defaults
    filled in, file paths absolute (relative ones against ``base_dir``), plain Python values only.  ``vehicle``: the
    VehicleData a Python caller builds in place of the named vehicle (:func:`~.build.build_scenario`'s Python-only
    input): the checks judge it and ``vehicle.name`` / ``vehicle.file`` is not read (a label of it)."""
    c = _Check(source, Path(base_dir) if base_dir is not None else None)
    c.table(data, "", required=("schema_version", "vehicle"),
            optional=("scenario", "track", "layout", "structure", "flexible_track", "contact", "run", "outputs"))
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
    if is_crossing(data):                         # a bridge crossing: a load model on the deck's modes
        if vehicle is not None:
            raise c.error("vehicle.load_model", "a bridge crossing takes no vehicle data (vehicle=)")
        return normalise_crossing(c, data, out)
    # ----------------------------------------------------------------------------------------- [vehicle]
    out["vehicle"], vehicle = _vehicle(c, data["vehicle"], vehicle)
    # ------------------------------------------------------------------------------------------- [track]
    track = c.array(data.get("track", []), "track")
    out["track"] = [_track_component(c, comp, f"track.{i}") for i, comp in enumerate(track)]
    # ------------------------------------------------------------------------------------------ [layout]
    if "layout" in data:                          # a curve: straight, transition, circular curve (spec_layout)
        wrong = layout_combination_error(c, data)
        if wrong is not None:
            raise wrong
        out["layout"] = normalise_layout(c, data["layout"], out["vehicle"]["start_s_m"], vehicle)
    # --------------------------------------------------------------------------------------- [structure]
    if "structure" in data:
        out["structure"] = _structure(c, data["structure"])
    if "flexible_track" in data:                  # rails on pads, sleepers and ballast (scenarios/flexible_track.py)
        if "structure" in data:
            raise c.error("flexible_track", "cannot be combined with a [structure] in a scenario (the track on a deck "
                                            "is the Python model track/flexible_deck.py): remove one of the two "
                                            "tables")
        out["flexible_track"] = normalise_flexible_track(data["flexible_track"], c.error, c.base_dir)
    # --------------------------------------------------------------------------------- [contact], [run]
    contact = c.settings(ContactSettings, data.get("contact", {}), "contact")
    run = c.settings(RunSettings, data.get("run", {}), "run")
    if "flexible_track" in out and "dt_s" not in data.get("run", {}):
        # an explicit solver on the flexible track: the step its stability needs at this speed (flexible_track)
        if METHODS[run.solver].imaginary_axis_limit:
            run = c.settings(RunSettings, {**data.get("run", {}), "dt_s": default_step_s(
                out["vehicle"]["speed_km_h"] / 3.6, out["flexible_track"]["modes_up_to_Hz"])}, "run")
    if "layout" in out:
        # an explicit solver on a curve: the curving run's step for the creep damping at this speed (spec_layout)
        run = layout_run_settings(c, data.get("run", {}), run, vehicle, out["vehicle"]["speed_km_h"] / 3.6)
    out["contact"] = contact.as_dict()
    out["run"] = run.as_dict()
    if out.get("structure", {}).get("formulation") == "ffrf" and run.solver != "newmark":
        raise c.error("structure.formulation", "'ffrf' holds its reference frame by constraints and needs "
                                               "run.solver = 'newmark'")
    if run.duration_s == DURATION_AUTO and features_end_m(out) is None:
        raise c.error("run.duration_s", "'auto' needs a track feature with an end (a span deflection, a sampled "
                                        "table, a structure or a curve's transition); harmonic components run along "
                                        "the whole track: give a time in s")
    if contact.wheel_rail == "springs" and run.record:
        raise c.error("contact.wheel_rail", "'springs' (the cost baseline) records nothing: set run.record = false")
    # ----------------------------------------------------------------------------------------- [outputs]
    out["outputs"] = _outputs(c, data.get("outputs", {}), vehicle, "structure" in out, "flexible_track" in out,
                              "layout" in out)
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


def _vehicle(c: _Check, vt, given=None) -> tuple[dict, object]:
    """``[vehicle]``: one vehicle (``name`` or ``file``) or a train (``consist``: a shipped consist name of
    ``vehicles/trains/`` or a consist file, :mod:`exudyn_wheelrail.rolling_stock.train`; ``start_s_m`` is then the track
    distance of the train's leading wheelset; no ``overrides``).  Returns the normal form and the vehicle data the
    output checks judge (for a train: its first car without a car body, else its first car; ``given``: the Python
    caller's vehicle data, the reference not read)."""
    c.table(vt, "vehicle", required=("speed_km_h",), optional=("name", "file", "consist", "start_s_m", "overrides"))
    if sum(k in vt for k in ("name", "file", "consist")) != 1:
        raise c.error("vehicle", "give exactly one of vehicle.name (a shipped vehicle), vehicle.file (a vehicle "
                                 "data file) or vehicle.consist (a train: a shipped consist or a consist file)")
    if "consist" in vt and given is not None:
        raise c.error("vehicle.consist", "a vehicle's data given in place of a train: give vehicle.name or file")
    if "consist" in vt:
        from ..rolling_stock.train import ConsistError, load_consist
        ref = c.string(vt["consist"], "vehicle.consist")
        if Path(ref).suffix:
            ref = c.path(ref, "vehicle.consist")
        if vt.get("overrides"):
            raise c.error("vehicle.overrides", "not available for a train (vehicle.consist): change the vehicle files")
        try:
            consist = load_consist(ref)
        except ConsistError as exc:
            raise c.error("vehicle.consist", str(exc)) from None
        cars = [car.vehicle for car in consist.cars]
        out = {"consist": ref,
               "speed_km_h": c.number(vt["speed_km_h"], "vehicle.speed_km_h", lo=0.0, hi=600.0),
               "start_s_m": c.number(vt.get("start_s_m", 0.0), "vehicle.start_s_m"), "overrides": {}}
        return out, next((v for v in cars if v.car_body is None), cars[0])
    from ..rolling_stock.vehicle_data import load_vehicle_with_overrides
    if "name" in vt:
        key, ref = "vehicle.name", c.string(vt["name"], "vehicle.name")
        out = {"name": ref}
    else:
        key = "vehicle.file"
        ref = c.path(vt["file"], key) if given is None else c.string(vt["file"], key)
        out = {"file": ref}
    overrides = vt.get("overrides", {})
    if not isinstance(overrides, dict):
        raise c.error("vehicle.overrides", f"expected a table {{\"table.key\" = value}}, got {overrides!r}")
    overrides = _flat_overrides(overrides)
    if overrides and given is not None:
        raise c.error("vehicle.overrides", "not applied to a vehicle given to the build as data (vehicle=): change "
                                           "that VehicleData instead")
    try:
        vehicle = given if given is not None else load_vehicle_with_overrides(ref, overrides or None)
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
    if kind == "spectrum":
        return _spectrum_component(c, comp, key)
    if kind == "defect":
        c.table(comp, key, required=("type", "shape", "position_m", "length_m", "depth_m"),
                optional=("rail", "direction"))
        return {"type": kind, "shape": c.string(comp["shape"], f"{key}.shape", tuple(DEFECT_SHAPES)),
                "position_m": c.number(comp["position_m"], f"{key}.position_m"),
                "length_m": c.plausible(c.number(comp["length_m"], f"{key}.length_m", lo=0.0), f"{key}.length_m",
                                        "track.*.length_m"),
                "depth_m": c.plausible(c.number(comp["depth_m"], f"{key}.depth_m"), f"{key}.depth_m",
                                       "track.*.depth_m"),
                "rail": c.string(comp.get("rail", "both"), f"{key}.rail", tuple(RAILS)),
                "direction": c.string(comp.get("direction", "vertical"), f"{key}.direction", DIRECTIONS[:2])}
    c.table(comp, key, required=("type", "file"))
    path = c.path(comp["file"], f"{key}.file")
    try:
        _track_table(kind, path)
    except (ValueError, OSError) as exc:
        raise c.error(f"{key}.file", str(exc)) from None
    return {"type": kind, "file": path}


def _track_table(kind: str, path):
    """The table of a ``sampled`` (columns s_m, y_m, z_m) or ``measured`` (the four channels or the rails,
    :mod:`exudyn_wheelrail.track.measured`) track component."""
    if kind == "sampled":
        return SampledIrregularity.from_csv(path)
    return read_irregularity_csv(path)


#: the options of a ``spectrum`` track component handed to the generator (the spectra module's defaults where absent)
SPECTRUM_OPTIONS = ("band_m", "step_m", "start_m", "channels", "scale")


def spectrum_table(comp: dict):
    """The irregularity of a ``spectrum`` track component (normalised, or as :func:`~.curving.spectrum_component`
    writes it): the generated table (:class:`~exudyn_wheelrail.track.spectra.SpectralIrregularity`, the options of
    :data:`SPECTRUM_OPTIONS` given), faded in from zero at its start over ``fade_in_m`` when that is > 0
    (:class:`~exudyn_wheelrail.track.irregularities.FadedIn`; e.g. under a vehicle that starts on the undisplaced
    track of a curve).  Raises ``ValueError`` for a bad spectrum, seed or option."""
    table = SpectralIrregularity(comp["spectrum"], comp["length_m"], comp["seed"],
                                 **{k: comp[k] for k in SPECTRUM_OPTIONS if k in comp})
    fade = comp.get("fade_in_m")
    if not fade:
        return table
    start = table.s_m[0]
    return FadedIn(table, start, start + fade)


def _spectrum_component(c: _Check, comp, key: str) -> dict:
    """A ``spectrum`` track component: irregularities generated from a standard PSD
    (:class:`~exudyn_wheelrail.track.spectra.SpectralIrregularity`)."""
    c.table(comp, key, required=("type", "spectrum", "seed", "length_m"),
            optional=("band_m", "step_m", "start_m", "channels", "scale", "fade_in_m"))
    band = c.array(comp.get("band_m", list(DEFAULT_BAND_M)), f"{key}.band_m")
    if len(band) != 2:
        raise c.error(f"{key}.band_m", f"expected [lambda_min_m, lambda_max_m], got {band!r}")
    channels = c.array(comp.get("channels", list(CHANNELS)), f"{key}.channels")
    out = {"type": "spectrum", "spectrum": c.string(comp["spectrum"], f"{key}.spectrum", tuple(SPECTRA)),
           "seed": c.integer(comp["seed"], f"{key}.seed", lo=0),
           "length_m": c.plausible(c.number(comp["length_m"], f"{key}.length_m", lo=0.0), f"{key}.length_m",
                                   "track.*.length_m"),
           "band_m": [c.number(v, f"{key}.band_m", lo=0.0) for v in band],
           "step_m": c.number(comp.get("step_m", DEFAULT_STEP_M), f"{key}.step_m", lo=0.0),
           "start_m": c.number(comp.get("start_m", 0.0), f"{key}.start_m"),
           "channels": [c.string(v, f"{key}.channels", tuple(CHANNELS)) for v in channels],
           "scale": c.number(comp.get("scale", 1.0), f"{key}.scale", lo=0.0, lo_open=False)}
    if "fade_in_m" in comp:
        out["fade_in_m"] = c.number(comp["fade_in_m"], f"{key}.fade_in_m", lo=0.0, lo_open=False)
        if out["fade_in_m"] > out["length_m"]:
            raise c.error(f"{key}.fade_in_m", f"{out['fade_in_m']:g} m is longer than the generated length_m = "
                                              f"{out['length_m']:g} m (it would never reach its full amplitude)")
    try:
        spectrum_table(out)
    except ValueError as exc:
        raise c.error(key, str(exc)) from None
    return out


_SECTION_KEYS = ("m_kg_m", "EI_y_Nm2", "EI_z_Nm2", "GJ_Nm2", "EA_N", "Ip_kgm2_m")


def _frequency_form(c: _Check, st) -> dict:
    """A deck given by its mass and bending frequencies instead of a section: ``mass_kg_m`` and ``f1_Hz`` (the
    simply supported first vertical frequency of the first span, ``spans_m[0]``: the one section of every span has
    the ``EI_y`` that gives it there), optional ``lateral_f1_Hz`` (else ``EI_z =``
    :data:`~.defaults.LATERAL_EI_RATIO` ``EI_y``); the section is :func:`~.deck.structure_section`'s."""
    out = {"mass_kg_m": c.plausible(c.number(st["mass_kg_m"], "structure.mass_kg_m", lo=0.0), "structure.mass_kg_m",
                                    "structure.mass_kg_m"),
           "f1_Hz": c.plausible(c.number(st["f1_Hz"], "structure.f1_Hz", lo=0.0), "structure.f1_Hz",
                                "structure.f1_Hz")}
    if "lateral_f1_Hz" in st:
        out["lateral_f1_Hz"] = c.plausible(c.number(st["lateral_f1_Hz"], "structure.lateral_f1_Hz", lo=0.0),
                                           "structure.lateral_f1_Hz", "structure.lateral_f1_Hz")
    return out


def _structure(c: _Check, st) -> dict:
    c.table(st, "structure", required=("spans_m", "start_m", "damping_ratio", "rail_height_m"),
            optional=("section", "mass_kg_m", "f1_Hz", "lateral_f1_Hz", "continuous", "elements_per_span",
                      "formulation", "modes_cutoff_Hz", "track_form", "support_motion"))
    spans = st["spans_m"]
    if isinstance(spans, (int, float)) and not isinstance(spans, bool):
        spans = [spans]
    spans = c.array(spans, "structure.spans_m", min_length=1)
    by_frequency = [k for k in ("mass_kg_m", "f1_Hz", "lateral_f1_Hz") if k in st]
    if "section" in st and by_frequency:
        raise c.error("structure", f"give the section or the deck's mass and frequencies ({', '.join(by_frequency)}),"
                                   " not both")
    if "section" not in st and not by_frequency:
        raise c.error("structure.section", "missing (or give the deck's mass_kg_m and f1_Hz)")
    for k in ("mass_kg_m", "f1_Hz"):
        if by_frequency and k not in st:
            raise c.error(f"structure.{k}", "missing (a deck given by its mass and frequency needs mass_kg_m and "
                                            "f1_Hz)")
    cut = st.get("modes_cutoff_Hz", "en1990")
    if isinstance(cut, str):
        cut = c.string(cut, "structure.modes_cutoff_Hz", ("en1990",))
    else:
        cut = c.number(cut, "structure.modes_cutoff_Hz", lo=0.0)
    out = {"spans_m": [c.plausible(c.number(L, f"structure.spans_m.{i}", lo=0.0), f"structure.spans_m.{i}",
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
           "track_form": c.string(st.get("track_form", TRACK_FORMS[0]), "structure.track_form", TRACK_FORMS)}
    if "section" in st:
        sec = c.table(st["section"], "structure.section", required=_SECTION_KEYS)
        out["section"] = {k: c.number(sec[k], f"structure.section.{k}", lo=0.0) for k in _SECTION_KEYS}
    else:
        out.update(_frequency_form(c, st))
    if "support_motion" in st:
        out["support_motion"] = _support_motion(c, st["support_motion"])
    return out


def _support_motion(c: _Check, sm) -> dict:
    """``[structure.support_motion]`` (the burst of :func:`.deck.support_motion`).  ``ramp_cycles`` must be > 0: a
    sudden start would make the rails under the vehicle jump in velocity."""
    key = "structure.support_motion"
    c.table(sm, key, required=("peak_acceleration_m_s2", "frequency_Hz"),
            optional=("ramp_cycles", "plateau_cycles", "start_s"))

    def plausible(name, value, **limits):
        return c.plausible(c.number(value, f"{key}.{name}", **limits), f"{key}.{name}", f"{key}.{name}")

    plateau = sm.get("plateau_cycles", PLATEAU_AUTO)
    if isinstance(plateau, str):
        plateau = c.string(plateau, f"{key}.plateau_cycles", (PLATEAU_AUTO,))
    else:
        plateau = c.number(plateau, f"{key}.plateau_cycles", lo=0.0, lo_open=False)
    return {"peak_acceleration_m_s2": plausible("peak_acceleration_m_s2", sm["peak_acceleration_m_s2"], lo=0.0),
            "frequency_Hz": plausible("frequency_Hz", sm["frequency_Hz"], lo=0.0),
            "ramp_cycles": plausible("ramp_cycles", sm.get("ramp_cycles", support_motion_default("ramp_cycles")),
                                     lo=0.0),
            "plateau_cycles": plateau,
            "start_s": c.number(sm.get("start_s", support_motion_default("start_s")), f"{key}.start_s", lo=0.0,
                                lo_open=False)}


def _outputs(c: _Check, o, vehicle, has_structure: bool, has_flexible_track: bool = False,
             has_layout: bool = False) -> dict:
    c.table(o, "outputs", optional=("timeseries", "carbody_points", "formats", "plots", "criteria"))
    has_car = vehicle.car_body is not None
    available = [g for g in TIMESERIES_GROUPS
                 if (g != "carbody" or has_car) and (g not in STRUCTURE_GROUPS or has_structure)
                 and (g != FLEXIBLE_TRACK_GROUP or has_flexible_track) and (g != CURVING_GROUP or has_layout)]
    if "timeseries" in o:
        groups = c.array(o["timeseries"], "outputs.timeseries")
        for i, g in enumerate(groups):
            c.string(g, f"outputs.timeseries.{i}", TIMESERIES_GROUPS)
            if g == "carbody" and not has_car:
                raise c.error(f"outputs.timeseries.{i}", f"'carbody': the vehicle {vehicle.name!r} (layout "
                                                         f"{vehicle.layout!r}) has no car body")
            if g in STRUCTURE_GROUPS and not has_structure:
                raise c.error(f"outputs.timeseries.{i}", f"{g!r} needs a [structure]")
            if g == FLEXIBLE_TRACK_GROUP and not has_flexible_track:
                raise c.error(f"outputs.timeseries.{i}", f"{g!r} needs a [flexible_track]")
            if g == CURVING_GROUP and not has_layout:
                raise c.error(f"outputs.timeseries.{i}", f"{g!r} needs a [layout]")
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


def features_end_m(scn: dict) -> float | None:
    """Track distance where the last track feature with an end ends (None if there is none); a curve's
    (``[layout]``) is the end of its transition, where the circular curve starts (it has no end)."""
    ends = []
    for comp in scn.get("track", []):
        if comp["type"] == "span_deflection":
            ends.append(comp["start_m"] + comp["span_length_m"] + 0.5 * comp["transition_length_m"])
        elif comp["type"] in ("sampled", "measured"):
            ends.append(float(_track_table(comp["type"], comp["file"]).s_m[-1]))
        elif comp["type"] == "spectrum":
            ends.append(comp["start_m"] + comp["length_m"])
        elif comp["type"] == "defect":
            ends.append(comp["position_m"] + (comp["length_m"] if comp["shape"] == "bump" else 0.5 * comp["length_m"]))
    if "structure" in scn:
        st = scn["structure"]
        ends.append(st["start_m"] + sum(st["spans_m"]))
    if "layout" in scn:
        ends.append(scn["layout"]["start_m"] + scn["layout"]["transition_m"])
    return max(ends) if ends else None


def as_scenario(scenario, vehicle=None) -> tuple[dict, str | None]:
    """The normal form of a scenario file path or dict, and the resolved file path (None for a dict); ``vehicle``
    as :func:`validate_scenario`."""
    if isinstance(scenario, (str, Path)):
        return load_scenario(scenario, vehicle), str(Path(scenario).resolve())
    if isinstance(scenario, dict):
        return validate_scenario(scenario, vehicle=vehicle), None
    raise TypeError(f"scenario: expected a file path or a scenario dict, got {type(scenario).__name__}")
