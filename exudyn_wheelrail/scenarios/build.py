r"""The builder: a scenario's normal form (:mod:`.spec`) -> the assembled Exudyn model (:class:`ScenarioModel`).

:func:`build_scenario` creates the vehicle of a data file (:func:`~exudyn_wheelrail.multibody.build_vehicle`, frame
moving with the running speed V), the wheel–rail connector (:func:`~exudyn_wheelrail.multibody.
add_wheel_rail_contact`) on a rigid straight track (:func:`build_track`) displaced by the listed irregularities,
optionally a modally reduced bridge deck (:func:`build_bridge_modes`, coupled through the connector's
``structure=``) with its support motion (:func:`.deck.support_motion`, for the resolved duration), puts the vehicle in
static equilibrium on the rails at t = 0 and on the displaced track (:func:`~exudyn_wheelrail.rolling_stock.placement.start_on_track`; the starting state of
:mod:`exudyn_wheelrail.scenarios.scenario`), and the recorder (the recorder's probes and the deck's,
:func:`.deck.deck_probes`); it returns handles, not strings.  A train (``vehicle.consist``) is built by
:func:`~exudyn_wheelrail.rolling_stock.train.build_train` (every car at its place in the model frame, the couplers), its
wheelsets in the one connector, every car put on the rails and the track, the recorder's wheel columns numbering
the train's wheelsets car after car and every car's car-body points suffixed ``_c<k>`` (:func:`.probes.train_probes`).
A bridge crossing (``vehicle.load_model``, :mod:`.spec_crossing`) is built by :func:`build_crossing`: its deck of N
modes per span and its load model, the same :class:`ScenarioModel` for the same runner.

Python-only inputs: the normal form holds plain values only, so what a Python caller has as an object goes to
:func:`build_scenario` as a keyword argument — ``vehicle`` (a :class:`~exudyn_wheelrail.rolling_stock.vehicle_data.
VehicleData` built in Python, e.g. with changed values, in place of the one the spec names, which is then a label
only: :func:`~.spec.validate_scenario`), ``pair`` (a
:class:`~exudyn_wheelrail.contact.WheelRailPair` in place of the vehicle's profiles) and ``irregularity`` (an
:class:`~exudyn_wheelrail.track.rigid.Irregularity` of any kind, added to the spec's ``track`` components).  The
``curving`` command's front end (:mod:`.curving`) passes them from its ``CurvingCase``.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import exudyn as exu
import numpy as np

from ..analysis.curving import curving_columns
from ..contact.pair import WheelRailPair
from ..multibody.connector import add_wheel_rail_contact, place_on_rails
from ..rolling_stock.placement import start_on_track
from ..rolling_stock.track_following import TrackFollowingFrame
from ..rolling_stock.train import build_train, load_consist, place_train_on_track
from ..rolling_stock.vehicle_builder import build_vehicle
from ..rolling_stock.vehicle_data import load_vehicle_with_overrides
from ..simulation.exudyn_settings import run_solver_settings
from ..simulation.recorder import Recorder, vehicle_probes
from ..simulation.settings import DURATION_AUTO, MAX_STEPS, ContactSettings, RunSettings, SettingsError
from ..structures.bridge import BridgeModel
from ..structures.bridge_exudyn import add_bridge
from ..track.flexible import add_flexible_track
from ..track.irregularities import IsolatedDefect
from ..track.measured import read_irregularity_csv
from ..track.rigid import Harmonic, IrregularitySum, RigidStraightTrack, SampledIrregularity, SpanDeflection
from .bridge_crossing_case import BridgeCrossing, default_dt_s
from .bridge_crossing_deck import deck_modes
from .bridge_crossing_loads import resolve_load_model
from .bridge_crossing_probes import DeckProbe, FirstAxleProbe
from .curve_setup import LAYOUT_MARGIN_M, CurvingInputError, check_start_undisplaced, entry_layout
from .deck import deck_probes, en1990_cutoff_Hz, structure_section, support_motion
from .flexible_track import (flexible_track_modes, flexible_track_probes, flexible_track_window,
                             start_on_flexible_track)
from .probes import carbody_x, train_probes
from .spec import ScenarioError, as_scenario, features_end_m, spectrum_table
from .spec_crossing import crossing_case, is_crossing
from .spec_layout import warn_creep_step

__all__ = ["ScenarioModel", "CrossingModel", "build_track", "build_bridge_modes", "build_layout", "vehicle_data",
           "scenario_run_settings", "build_scenario", "build_crossing", "MODES_CUTOFF_MARGIN"]

#: modes up to this factor times the EN 1990 cut-off are kept (the FE frequencies lie slightly above the
#: Euler–Bernoulli values the cut-off is computed from)
MODES_CUTOFF_MARGIN = 1.01


def build_track(scn: dict, irregularity=None):
    """The :class:`~..track.rigid.RigidStraightTrack` of the scenario's ``track`` components and, last, the
    Python-only ``irregularity`` (an :class:`~..track.rigid.Irregularity`; None: none)."""
    parts = []
    for comp in scn["track"]:
        if comp["type"] == "span_deflection":
            parts.append(SpanDeflection(span_length_m=comp["span_length_m"], amplitude_m=comp["amplitude_m"],
                                        start_m=comp["start_m"], transition_length_m=comp["transition_length_m"],
                                        direction=comp["direction"]))
        elif comp["type"] == "harmonic":
            parts.append(Harmonic(amplitude_m=comp["amplitude_m"], wavelength_m=comp["wavelength_m"],
                                  phase_rad=comp["phase_rad"], direction=comp["direction"]))
        elif comp["type"] == "measured":
            parts.append(read_irregularity_csv(comp["file"]))
        elif comp["type"] == "spectrum":
            parts.append(spectrum_table(comp))
        elif comp["type"] == "defect":
            parts.append(IsolatedDefect(comp["shape"], comp["position_m"], comp["length_m"], comp["depth_m"],
                                        rail=comp["rail"], direction=comp["direction"]))
        else:
            parts.append(SampledIrregularity.from_csv(comp["file"]))
    if irregularity is not None:
        parts.append(irregularity)
    if not parts:
        return RigidStraightTrack()
    return RigidStraightTrack(parts[0] if len(parts) == 1 else IrregularitySum(parts))


def build_bridge_modes(structure: dict):
    """``(BridgeModel, BridgeModes, f_cut_Hz)`` of a normalised ``[structure]`` table."""
    sec = structure_section(structure)
    model = BridgeModel(tuple(structure["spans_m"]), sec, continuous=structure["continuous"],
                        damping_ratio=structure["damping_ratio"], rail_height_m=structure["rail_height_m"],
                        start_m=structure["start_m"], elements_per_span=structure["elements_per_span"])
    cut = structure["modes_cutoff_Hz"]
    if cut == "en1990":
        cut = en1990_cutoff_Hz(structure["spans_m"], sec)
        f_max = MODES_CUTOFF_MARGIN * cut
    else:
        f_max = float(cut)
    return model, model.modes(f_max_Hz=f_max), float(cut)


def build_layout(scn: dict, run: RunSettings):
    """The :class:`~..track.layout.TrackLayout` of the scenario's ``[layout]`` (None without one): straight track up
    to ``layout.start_m``, the transition, the circular curve to ``LAYOUT_MARGIN_M`` beyond the leading wheelset's
    track distance at the end of the run (the construction of the ``curving`` command,
    :func:`~.curve_setup.entry_layout`)."""
    lay = scn.get("layout")
    if lay is None:
        return None
    V = scn["vehicle"]["speed_km_h"] / 3.6
    curve_start = lay["start_m"] + lay["transition_m"]
    reach = scn["vehicle"]["start_s_m"] + V * run.end_time_s
    return entry_layout(lay["radius_m"], lay["cant_m"], lay["transition_m"], lay["direction"], lay["start_m"],
                        max(reach - curve_start, 0.0) + LAYOUT_MARGIN_M)


def vehicle_data(scn: dict):
    """The scenario's :class:`~..rolling_stock.vehicle_data.VehicleData`, or its :class:`~..rolling_stock.train.Consist` for
    a train (``vehicle.consist``; both have ``name`` and ``wheelset_x_m()``, the leading wheelset's x the largest)."""
    v = scn["vehicle"]
    if "consist" in v:
        return load_consist(v["consist"])
    return load_vehicle_with_overrides(v.get("name") or v["file"], v.get("overrides") or None)


def scenario_run_settings(scn: dict, vehicle) -> tuple[RunSettings, dict]:
    """The run settings with the duration resolved, and what the run covers: ``t_passage_s`` is the time for the
    trailing wheelset to be ``run_out_m`` past the end of the last track feature (None without an ending
    feature)."""
    run = RunSettings(**scn["run"])
    V = scn["vehicle"]["speed_km_h"] / 3.6
    x = vehicle.wheelset_x_m()
    extent = float(max(x) - min(x))
    end = features_end_m(scn)
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
    recorder (None without recording) and the Exudyn solver settings (``settings``, ``solver_type``).  A bridge
    crossing's (:func:`build_crossing`) has ``crossing`` set and no ``vehicle``, ``model``, ``pair``, ``track`` or
    ``contact_settings`` (None; its load model holds them), and no ``scenario`` when its case was built in Python."""

    scenario: dict | None
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
    contact_settings: ContactSettings | None     #: None for a crossing (its load model's own)
    coverage: dict
    recorder: Recorder | None = None
    settings: object = None
    solver_type: object = None
    start_shift: float | None = None        #: largest track displacement under a wheelset at t = 0 (None: none)
    support_motion: object = None           #: the ground motion of the supports and the track (None: none)
    flexible_track: object = None           #: the flexible track's handle (track.flexible; None: rigid track)
    flexible_window: object = None          #: its moving window (track.flexible_window; None: a fixed segment)
    layout: object = None                   #: the curve's TrackLayout (track.layout; None: straight track)
    frame: object = None                    #: its TrackFollowingFrame (rolling_stock.track_following), updated
    #: before every step
    crossing: object = None                 #: a bridge crossing's parts (CrossingModel; None: not a crossing)

    @property
    def user_function(self):
        """What the runner calls before every step (None: nothing): the curve's track-following frames or the
        flexible track's moving window (a scenario has at most one of the two)."""
        return self.frame.update if self.frame is not None else self.flexible_window

    @property
    def speed_m_s(self) -> float:
        if self.crossing is not None:                  # the case's own speed (a Python case has no scenario)
            return self.crossing.case.speed_m_s
        return self.scenario["vehicle"]["speed_km_h"] / 3.6

    @property
    def steps(self) -> int:
        return self.run.steps


def build_scenario(scenario, *, vehicle=None, pair=None, irregularity=None) -> ScenarioModel:
    """Build and assemble the Exudyn model of a scenario (path or dict): vehicle, track, bridge, contact,
    recorder; not solved.  The Python-only inputs (module docstring): ``vehicle`` — a VehicleData built in place of
    the spec's vehicle (not with a train); ``pair`` — a WheelRailPair in place of the vehicle's profiles;
    ``irregularity`` — an Irregularity added to the spec's track components."""
    scn, _ = as_scenario(scenario, vehicle)
    if is_crossing(scn):
        given = [k for k, v in (("pair", pair), ("irregularity", irregularity)) if v is not None]
        if given:                                 # (vehicle=: as_scenario has refused it)
            raise ScenarioError(f"{given[0]}: not with a bridge crossing (vehicle.load_model)")
        return build_crossing(crossing_case(scn), scn)
    vehicle = vehicle_data(scn) if vehicle is None else vehicle
    run, coverage = scenario_run_settings(scn, vehicle)
    cs = ContactSettings(**{**scn["contact"], "fastsim_grid": tuple(scn["contact"]["fastsim_grid"])})
    V = scn["vehicle"]["speed_km_h"] / 3.6
    s_lead0 = scn["vehicle"]["start_s_m"]
    s_start = s_lead0 - max(vehicle.wheelset_x_m())              # frame origin; leading wheelset at start_s_m
    modes = f_cut = None
    if "structure" in scn:
        _, modes, f_cut = build_bridge_modes(scn["structure"])
    train = "consist" in scn["vehicle"]
    geo = (vehicle.cars[0].vehicle if train else vehicle).geometry
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    springs = cs.wheel_rail == "springs"
    if train:
        model = build_train(mbs, vehicle, speed_m_s=V, s_start_m=s_start, wheel_rail="springs" if springs else "none")
    else:
        model = build_vehicle(mbs, vehicle, speed_m_s=V, s_start_m=s_start,
                              wheel_rail="springs" if springs else "none")
    if pair is None:
        pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                             inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    track = build_track(scn, irregularity)
    layout = build_layout(scn, run)
    if layout is not None:
        warn_creep_step(run, vehicle, V)
    if layout is not None and (scn["track"] or irregularity is not None):   # starts on the undisplaced straight
        try:
            check_start_undisplaced(track.irregularity, vehicle, s_lead0)
        except CurvingInputError as exc:
            raise ScenarioError(f"track: {exc.problem}") from None
    bridge = contact = shift = motion = frame = None
    if modes is not None:
        bridge = add_bridge(mbs, modes, formulation=scn["structure"]["formulation"])
        if "support_motion" in scn["structure"]:
            motion = support_motion(scn["structure"]["support_motion"], run.end_time_s)
            bridge.add_support_motion(mbs, motion)
    flex = window = None
    if "flexible_track" in scn and not springs:       # rails on pads, sleepers and ballast: the contact's deck slot
        flex = add_flexible_track(mbs, flexible_track_modes(
            scn["flexible_track"], s_start_m=s_start, wheelset_x_m=vehicle.wheelset_x_m(), speed_m_s=V,
            end_time_s=run.end_time_s, solver=run.solver, dt_s=run.dt_s, moving_window=True))
    if not springs:
        try:
            contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V, track=track,
                                             s_start_m=s_start, creep_law=cs.creep_law, mu=cs.friction,
                                             fastsim_grid=cs.fastsim_grid, geometry=cs.geometry,
                                             contact_patch=cs.contact_patch,
                                             **({"layout": layout} if layout is not None else {}),
                                             **({"structure": bridge} if bridge is not None else {}),
                                             **({"structure": flex} if flex is not None else {}))
        except FileNotFoundError as exc:      # e.g. the creep table of creep_law="table" has not been built
            raise RuntimeError(f"contact.creep_law = {cs.creep_law!r}: {exc}") from None
        if train:
            model.contact = contact
            shift = place_train_on_track(mbs, model, pair, track)
        elif layout is not None:                      # the curving command's start (curve_setup: no track shift)
            place_on_rails(mbs, model, pair)
            frame = TrackFollowingFrame(mbs, model, layout)
        else:
            place_on_rails(mbs, model, pair)
            shift = start_on_track(mbs, model, track)
        if flex is not None:
            start_on_flexible_track(mbs, model, flex, contact=contact)
            window = flexible_track_window(scn["flexible_track"], contact=contact, handle=flex)
    h = ScenarioModel(scenario=scn, system_container=sc, mbs=mbs, vehicle=vehicle, model=model, pair=pair,
                      track=track, contact=contact, bridge=bridge, modes=modes, f_cut_Hz=f_cut, run=run,
                      contact_settings=cs, coverage=coverage, start_shift=shift, support_motion=motion)
    h.flexible_track = flex
    h.flexible_window = window
    h.layout, h.frame = layout, frame
    if run.record and contact is not None:
        st = scn.get("structure", {})
        if train:
            probes = train_probes(model, contact, track, V, s_lead0, scn["outputs"]["carbody_points"], bridge, modes,
                                  st, mbs=mbs)
        else:
            points = [(p["name"], [carbody_x(p["x_m"], vehicle), p["y_m"], -p["height_m"]])
                      for p in scn["outputs"]["carbody_points"]]
            probes = vehicle_probes(model=model, contact=contact, track=track, speed_m_s=V, s_leading0_m=s_lead0,
                                    carbody_points=points, bridge=bridge, modes=modes,
                                    deck_spans_m=st.get("spans_m"), deck_start_m=st.get("start_m"), mbs=mbs)
        if bridge is not None:
            probes += deck_probes(contact=contact, bridge=bridge, modes=modes, spans_m=st["spans_m"],
                                  start_m=st["start_m"], n_wheelsets=len(model.wheelsets))
        if flex is not None:
            probes += flexible_track_probes(contact=contact, handle=flex, model=model, window=window)
        if frame is not None:
            probes += curving_columns(model, layout)
        h.recorder = Recorder(probes, n_rows_hint=run.steps // run.record_every + 2)
    mbs.Assemble()
    if frame is not None:                          # the curve's terms at t = 0, after Assemble (as the curving run)
        frame.update(mbs, 0.0)
    h.settings, h.solver_type = run_solver_settings(run)
    if flex is not None:        # hundreds of modal coordinates: Exudyn's sparse solver (measured: the dense one 3-30x slower)
        h.settings.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    return h


@dataclass(frozen=True)
class CrossingModel:
    """What a bridge crossing's evaluation reads beside the model (:func:`build_crossing`): the ``case``
    (:class:`~.bridge_crossing_case.BridgeCrossing`), the deck's modes per span (``deck``,
    :class:`~.bridge_crossing_deck.DeckModes`), every span's EN 1990 cut-off (``cutoffs``), the load model's
    :class:`~.bridge_crossing_loads.LoadModelHandle` (``load``) and the build's wall time (``build_seconds``)."""

    case: BridgeCrossing
    deck: object
    cutoffs: list
    load: object
    build_seconds: float


def build_crossing(case: BridgeCrossing, scenario: dict | None = None) -> ScenarioModel:
    """Build and assemble a bridge crossing (:mod:`.bridge_crossing`): the deck of N modes per span
    (:func:`~.bridge_crossing_deck.deck_modes`) in Exudyn, the load model on it (its check first, before any work),
    the run settings (duration: the last axle off the deck plus the free vibration; the step: the case's, else
    :func:`~.bridge_crossing_case.default_dt_s`, not above the load model's bound), the recorder (the first axle's
    place and the quasi-static deflection, the deck, the load model's probes).  ``scenario``: its normal form when the
    case came from one (kept in the model; a case built in Python has none)."""
    load_model = resolve_load_model(case.model)
    load_model.check(case)
    t_build = time.perf_counter()
    deck = deck_modes(case)
    cutoffs = list(deck.cutoffs_Hz)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    bridge = add_bridge(mbs, deck.modes, "modal", name="deck")
    handle = load_model.build(mbs, case, bridge)
    axle_x = np.asarray(handle.axle_x_m, dtype=float)
    duration = (float(axle_x[-1]) + case.length_m) / case.speed_m_s + case.free_vibration_s
    dt = case.dt_s
    if dt is None:
        dt = default_dt_s(case) if handle.max_dt_s is None else min(default_dt_s(case), float(handle.max_dt_s))
    run = RunSettings(solver=case.solver, dt_s=dt, duration_s=duration)
    probes = [FirstAxleProbe(case, axle_x, handle.axle_load_N, deck),
              DeckProbe(case, bridge, deck, handle.modal_forces, cutoffs, contact=handle.contact)] + list(handle.probes)
    recorder = Recorder(probes, n_rows_hint=run.steps + 2)
    mbs.Assemble()
    h = ScenarioModel(scenario=scenario, system_container=sc, mbs=mbs, vehicle=None, model=None, pair=None,
                      track=None, contact=handle.contact, bridge=bridge, modes=deck.modes, f_cut_Hz=cutoffs[0],
                      run=run, contact_settings=None, coverage={}, recorder=recorder)
    h.settings, h.solver_type = run_solver_settings(run)
    h.crossing = CrossingModel(case, deck, cutoffs, handle, time.perf_counter() - t_build)
    return h
