r"""A bridge crossing as a scenario: a train given by its load model (``vehicle.load_model``: constant axle loads,
sprung masses or the vehicles themselves) crosses a deck of simply supported spans given by its mass and
frequencies and N modes per span (:mod:`.bridge_crossing`).  The scenario form of the ``bridge-crossing`` command:
the command fills it, ``run`` runs it, both through :func:`~.run.run_scenario`.

:func:`normalise_crossing` checks such a scenario (called by :func:`~.spec.validate_scenario` when ``[vehicle]`` names
a ``load_model``) and returns its normal form; :func:`crossing_case` makes the
:class:`~.bridge_crossing_case.BridgeCrossing` of a normal form, :func:`crossing_scenario` the normal form of a
case.  The tables and keys::

    [vehicle]       load_model (moving-loads | sprung-masses | vehicles), speed_km_h, one of hslm (A1 … A10),
                    axles (an axle file, CSV) or consist (a shipped consist or a consist file);
                    sprung_frequency_Hz, sprung_damping_ratio (used by sprung-masses)
    [structure]     spans_m (a list: one span or a chain in running order), mass_kg_m, f1_Hz (of the first span),
                    damping_ratio, modes (vertical modes per span), lateral_modes (default 0), lateral_f1_Hz
                    (optional), track_form, continuous (default false: one deck over the intermediate
                    supports); or, instead of mass_kg_m and f1_Hz, modes_file (an FE program's modes, NPZ or
                    CSV: :mod:`~exudyn_wheelrail.structures.modes_file`; modes = how many of its lowest are kept;
                    damping_ratio optional when the file gives it)
    [run]           solver (default rk44), dt_s (optional: the crossing's own rule), free_vibration_s (default 0)

No ``[track]``, ``[layout]``, ``[flexible_track]``, ``[contact]`` or ``[outputs]``: the crossing writes its own
columns and summary (``docs/cli.md``, *bridge-crossing*).
"""
from __future__ import annotations

from pathlib import Path

from ..simulation.settings import DT_S, SPEED_KM_H
from ..simulation.solvers import SOLVERS
from ..standards import TRACK_FORMS
from ..structures.load_models import hslm_a, hslm_name, read_axle_file
from .bridge_crossing_case import F1_HZ, FREE_VIBRATION_S, MASS_KG_M, MAX_SPANS, SPAN_M, BridgeCrossing
from .bridge_crossing_loads import consist_axles, resolve_load_model
from .defaults import (AXLE_LOAD_MODELS, DEFAULT_SOLVER, MAX_MODES, MODEL_NAMES, SPRUNG_DAMPING_RATIO,
                       SPRUNG_FREQUENCY_HZ)

__all__ = ["CROSSING_TABLES", "TRAIN_SOURCES", "CASE_KEYS", "is_crossing", "normalise_crossing", "crossing_case",
           "crossing_scenario", "train_axles"]

#: the tables of a crossing scenario
CROSSING_TABLES = ("schema_version", "scenario", "vehicle", "structure", "run")
#: the keys of ``[vehicle]`` that give the train (exactly one)
TRAIN_SOURCES = ("hslm", "axles", "consist")
#: the dotted key of each field of :class:`~.bridge_crossing_case.BridgeCrossing` and of each option the load models'
#: checks name (their errors then name the key)
CASE_KEYS = {"span_m": "structure.spans_m", "mass_kg_m": "structure.mass_kg_m", "f1_Hz": "structure.f1_Hz",
             "damping_ratio": "structure.damping_ratio", "n_modes": "structure.modes",
             "modes_file": "structure.modes_file", "continuous": "structure.continuous",
             "speed_m_s": "vehicle.speed_km_h", "model": "vehicle.load_model",
             "free_vibration_s": "run.free_vibration_s", "dt_s": "run.dt_s", "solver": "run.solver",
             "track_form": "structure.track_form", "spans_m": "structure.spans_m",
             "lateral_modes": "structure.lateral_modes", "lateral_f1_Hz": "structure.lateral_f1_Hz",
             "sprung_frequency_Hz": "vehicle.sprung_frequency_Hz",
             "sprung_damping_ratio": "vehicle.sprung_damping_ratio", "axles": "vehicle", "train_file": "vehicle",
             # the load models' checks name the command's options
             "--model": "vehicle.load_model", "--train": "vehicle.consist", "--axles/--hslm": "vehicle"}


def is_crossing(scn: dict) -> bool:
    """Whether a scenario (as read or normalised) is a bridge crossing: its ``[vehicle]`` names a load model."""
    return isinstance(scn.get("vehicle"), dict) and "load_model" in scn["vehicle"]


def normalise_crossing(c, data: dict, out: dict) -> dict:
    """The normal form of a crossing scenario ``data`` (``out``: the normal form's ``schema_version`` and
    ``[scenario]``, filled by the caller); ``c``: the spec's checker (errors name the source and the dotted key).
    Every check of the crossing's case is made here (the axle file read, the load model resolved), before any
    work."""
    wrong = [k for k in data if k not in CROSSING_TABLES]
    if wrong:
        raise c.error(wrong[0], "not with vehicle.load_model (a bridge crossing: its load model on the deck's modes "
                                "writes its own columns and summary)")
    # ------------------------------------------------------------------------------------------- [vehicle]
    vt = c.table(data["vehicle"], "vehicle", required=("load_model", "speed_km_h"),
                 optional=TRAIN_SOURCES + ("sprung_frequency_Hz", "sprung_damping_ratio"))
    model = c.string(vt["load_model"], "vehicle.load_model", choices=MODEL_NAMES)
    given = [k for k in TRAIN_SOURCES if k in vt]
    if len(given) != 1:
        raise c.error("vehicle", "give exactly one of vehicle.hslm (a universal train A1 … A10), vehicle.axles (an "
                                 "axle file) or vehicle.consist (a consist file)")
    source = given[0]
    key = f"vehicle.{source}"
    if model not in AXLE_LOAD_MODELS and source != "consist":
        raise c.error("vehicle.load_model", f"{model!r} runs the vehicles of a consist: give vehicle.consist")
    if source == "hslm":
        text = c.string(vt["hslm"], key)
        try:
            train = hslm_name(text)
        except ValueError as exc:
            raise c.error(key, str(exc)) from None
    elif source == "axles":
        train = c.path(vt["axles"], key)
    else:                                         # a shipped consist's name or a consist file (as a [vehicle]'s)
        train = c.string(vt["consist"], key)
        if Path(train).suffix:
            train = c.path(train, key)
    vehicle = {"load_model": model, source: train,
               "speed_km_h": _plausible(c, SPEED_KM_H, "vehicle.speed_km_h", vt["speed_km_h"]),
               # used by the sprung-masses model only; kept with every model (a summary's inputs show them)
               "sprung_frequency_Hz": c.number(vt.get("sprung_frequency_Hz", SPRUNG_FREQUENCY_HZ),
                                               "vehicle.sprung_frequency_Hz", lo=0.0),
               "sprung_damping_ratio": c.number(vt.get("sprung_damping_ratio", SPRUNG_DAMPING_RATIO),
                                                "vehicle.sprung_damping_ratio", lo=0.0, lo_open=False)}
    # ----------------------------------------------------------------------------------------- [structure]
    if "structure" not in data:
        raise c.error("structure", "missing: a crossing needs its deck (spans_m, mass_kg_m, f1_Hz, damping_ratio, "
                                   "modes)")
    by_file = isinstance(data["structure"], dict) and "modes_file" in data["structure"]
    st = c.table(data["structure"], "structure",
                 required=("spans_m", "modes") + (("modes_file",) if by_file else ("mass_kg_m", "f1_Hz",
                                                                                   "damping_ratio")),
                 optional=("lateral_modes", "lateral_f1_Hz", "track_form", "continuous")
                 + (("mass_kg_m", "damping_ratio") if by_file else ()))
    spans = c.array(st["spans_m"], "structure.spans_m", min_length=1)
    if len(spans) > MAX_SPANS:
        raise c.error("structure.spans_m", f"{len(spans)} spans, more than {MAX_SPANS}")
    structure = {
        "spans_m": [_plausible(c, SPAN_M, f"structure.spans_m.{k}", x) for k, x in enumerate(spans)],
        "modes": c.integer(st["modes"], "structure.modes", lo=1, hi=MAX_MODES),
        "lateral_modes": c.integer(st.get("lateral_modes", 0), "structure.lateral_modes", lo=0, hi=MAX_MODES),
        "track_form": c.string(st.get("track_form", TRACK_FORMS[0]), "structure.track_form", choices=TRACK_FORMS)}
    if "mass_kg_m" in st:
        structure["mass_kg_m"] = _plausible(c, MASS_KG_M, "structure.mass_kg_m", st["mass_kg_m"])
    if "f1_Hz" in st:
        structure["f1_Hz"] = _plausible(c, F1_HZ, "structure.f1_Hz", st["f1_Hz"])
    if "damping_ratio" in st:
        structure["damping_ratio"] = _damping_ratio(c, st["damping_ratio"])
    if by_file:
        structure["modes_file"] = c.path(st["modes_file"], "structure.modes_file")
    if "continuous" in st:
        structure["continuous"] = c.boolean(st["continuous"], "structure.continuous")
    if "lateral_f1_Hz" in st:
        structure["lateral_f1_Hz"] = _plausible(c, F1_HZ, "structure.lateral_f1_Hz", st["lateral_f1_Hz"])
    # ----------------------------------------------------------------------------------------------- [run]
    rt = c.table(data.get("run", {}), "run", optional=("solver", "dt_s", "free_vibration_s"))
    run = {"solver": c.string(rt.get("solver", DEFAULT_SOLVER), "run.solver", choices=SOLVERS),
           "free_vibration_s": _plausible(c, FREE_VIBRATION_S, "run.free_vibration_s", rt.get("free_vibration_s", 0.0))}
    if "dt_s" in rt:
        run["dt_s"] = _plausible(c, DT_S, "run.dt_s", rt["dt_s"])
    scn = dict(out, vehicle=vehicle, structure=structure, run=run)
    try:                                          # the train's file read now: its errors name the key, file, line
        axles = train_axles(vehicle)
    except ValueError as exc:
        raise c.error(key, str(exc).removeprefix("--train: ")) from None
    try:
        case = _case(scn, axles)
        resolve_load_model(case.model).check(case)
    except ValueError as exc:
        name, _, problem = str(exc).partition(": ")
        raise c.error(CASE_KEYS.get(name, "vehicle"), problem or str(exc)) from None
    return scn


def _plausible(c, quantity, key: str, value) -> float:
    """``value`` as a float judged by ``quantity`` (an error and a warning for an unusual value name the source
    and the key)."""
    return c.plausible(c.number(value, key), key, quantity)


def _damping_ratio(c, value) -> float:
    z = c.number(value, "structure.damping_ratio")
    if not 0.0 <= z < 1.0:
        raise c.error("structure.damping_ratio", f"{z:g} must be in [0, 1) (a ratio, not a percentage: 2 % is 0.02)")
    return z


def train_axles(vehicle: dict):
    """The axle loads of a crossing's normalised ``[vehicle]`` (the axle file read, the universal train made, the
    consist's static loads; None for the vehicles model, which runs the consist's vehicles)."""
    if "hslm" in vehicle:
        return hslm_a(vehicle["hslm"])
    if "axles" in vehicle:
        return read_axle_file(vehicle["axles"])
    return consist_axles(vehicle["consist"]) if vehicle["load_model"] in AXLE_LOAD_MODELS else None


def crossing_case(scn: dict) -> BridgeCrossing:
    """The :class:`~.bridge_crossing_case.BridgeCrossing` of a crossing scenario's normal form
    (:func:`train_axles`)."""
    return _case(scn, train_axles(scn["vehicle"]))


def _case(scn: dict, axles) -> BridgeCrossing:
    v, st, r = scn["vehicle"], scn["structure"], scn["run"]
    spans = tuple(float(x) for x in st["spans_m"])
    return BridgeCrossing(span_m=spans[0], mass_kg_m=st.get("mass_kg_m"), f1_Hz=st.get("f1_Hz"),
                          damping_ratio=st.get("damping_ratio"), n_modes=st["modes"], axles=axles,
                          speed_m_s=v["speed_km_h"] / 3.6, model=v["load_model"],
                          free_vibration_s=r["free_vibration_s"], dt_s=r.get("dt_s"), solver=r["solver"],
                          track_form=st["track_form"], train_file=v.get("consist"),
                          spans_m=spans if len(spans) > 1 else None, lateral_modes=st["lateral_modes"],
                          lateral_f1_Hz=st.get("lateral_f1_Hz"),
                          sprung_frequency_Hz=v["sprung_frequency_Hz"], sprung_damping_ratio=v["sprung_damping_ratio"],
                          continuous=st.get("continuous", False), modes_file=st.get("modes_file"))


def crossing_scenario(case: BridgeCrossing, train: dict, name: str = "bridge_crossing",
                      speed_km_h: float | None = None) -> dict:
    """The scenario (as read: :func:`~.spec.validate_scenario` gives its normal form) of a crossing ``case`` whose
    train came from ``train``: ``{"hslm": "A1"}``, ``{"axles": FILE}`` or ``{"consist": FILE}`` (the case keeps the
    axle loads, not where they came from).  ``speed_km_h``: the speed as given (the case keeps it in m/s, and
    ``speed_m_s * 3.6 / 3.6`` is not always ``speed_m_s`` in the last bit: the command line passes the option's
    value).  A case whose deck does not start at the first support (``deck_start_m``) has no scenario form."""
    if case.deck_start_m != 0.0:
        raise ValueError(f"deck_start_m: {case.deck_start_m:g} m: a crossing's scenario starts at the first support")
    vehicle = {"load_model": case.model, **{k: str(v) for k, v in train.items()},
               "speed_km_h": speed_km_h if speed_km_h is not None else case.speed_m_s * 3.6,
               "sprung_frequency_Hz": case.sprung_frequency_Hz, "sprung_damping_ratio": case.sprung_damping_ratio}
    if case.modes_file is not None and case.mass_scale != 1.0:
        raise ValueError(f"mass_scale: {case.mass_scale:g}: a crossing's scenario takes a modes file as it is")
    structure = {"spans_m": list(case.chain_m), "modes": case.n_modes, "lateral_modes": case.lateral_modes,
                 "track_form": case.track_form}
    if case.modes_file is not None:
        structure["modes_file"] = case.modes_file
        if case.mass_kg_m is not None:
            structure["mass_kg_m"] = case.mass_kg_m
    else:
        structure.update(mass_kg_m=case.mass_kg_m, f1_Hz=case.f1_Hz)
    if case.damping_ratio is not None:
        structure["damping_ratio"] = case.damping_ratio
    if case.continuous:
        structure["continuous"] = True
    if case.lateral_f1_Hz is not None:
        structure["lateral_f1_Hz"] = case.lateral_f1_Hz
    run = {"solver": case.solver, "free_vibration_s": case.free_vibration_s}
    if case.dt_s is not None:
        run["dt_s"] = case.dt_s
    return {"schema_version": 2, "scenario": {"name": name}, "vehicle": vehicle, "structure": structure, "run": run}
