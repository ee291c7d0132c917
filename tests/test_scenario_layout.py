"""A curve in a scenario: the ``[layout]`` table (scenarios/spec_layout.py), its build (scenarios/build.py) and its
summary block (scenarios/run.py).

References, independent of the scenario path:

* the hand-written scenario of a curve (examples/scenarios/curve_r1000.toml): the ``curving`` command's front end
  (scenarios/curving.py ``curving_scenario``) fills the same vehicle, start, curve, contact settings and step for
  the same case, so the command is that scenario run longer;
* the quasi-static balance of steady curving, ΣΣY = m a_nc (analysis/curving.py ``steady_state``, the curving
  command's check), with a_nc from the closed form V²/R cos φ − g sin φ;
* the default transition, the plausible ranges and the creep step of the curving command (scenarios/defaults.py,
  track/layout.py, scenarios/curve_setup.py): the same functions and constants, not copies.
"""
import dataclasses
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.analysis.curving import STEADY_A_MIN_M_S2, STEADY_TOLERANCE, steady_state
from exudyn_wheelrail.contact.pair import WheelRailPair
from exudyn_wheelrail.conventions import RAIL_CENTRE_DISTANCE_M
from exudyn_wheelrail.profiles.profiles import WheelProfile
from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle, load_vehicle_with_overrides
from exudyn_wheelrail.scenarios.curve_setup import creep_step_limit_s
from exudyn_wheelrail.scenarios.curving import CurvingCase, build_curving, curving_distances, curving_scenario
from exudyn_wheelrail.scenarios.defaults import LEAD_IN_M
from exudyn_wheelrail.scenarios.scenario import (ScenarioError, apply_overrides, build_scenario, load_scenario,
                                                 run_model, scenario_summary, validate_scenario)
from exudyn_wheelrail.simulation.presets import PRESETS
from exudyn_wheelrail.track.rigid import Harmonic, IrregularitySum
from exudyn_wheelrail.validation import InputWarning

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "scenarios"
VEHICLE = "manchester_vehicle1"


def _scn(layout=None, **tables):
    scn = {"schema_version": 2, "vehicle": {"name": VEHICLE, "speed_km_h": 100.0},
           "layout": {"radius_m": 1000.0, "cant_m": 0.1} if layout is None else layout,
           "run": {"duration_s": 0.1}}
    scn.update(tables)
    return scn


# ---------------------------------------------------------------------------------------------- (a) the spec
def test_defaults_are_the_curving_commands():
    out = validate_scenario(_scn())
    case = CurvingCase(VEHICLE, radius_m=1000.0, cant_m=0.1, speed_km_h=100.0)
    assert out["layout"] == {"radius_m": 1000.0, "cant_m": 0.1, "transition_m": case.transition_length_m,
                             "direction": "right", "start_m": LEAD_IN_M}
    assert out["layout"]["transition_m"] == 40.0                       # the ramp 1:400 of 0.1 m
    assert validate_scenario(_scn({"radius_m": 2000.0, "cant_m": 0.0}))["layout"]["transition_m"] == 20.0
    assert validate_scenario(out) == out                               # the normal form is idempotent
    assert "curving" in out["outputs"]["timeseries"]
    assert "curving" not in validate_scenario({k: v for k, v in _scn().items() if k != "layout"})["outputs"][
        "timeseries"]


LAYOUT_ERRORS = [
    ({"cant_m": 0.1}, "layout.radius_m", "missing"),
    ({"radius_m": -5.0, "cant_m": 0.1}, "layout.radius_m", "must be >"),
    ({"radius_m": 2.0e5, "cant_m": 0.1}, "layout.radius_m", "mm"),
    ({"radius_m": 1.0, "cant_m": 0.1}, "layout.radius_m", "smallest radius"),
    ({"radius_m": 1000.0}, "layout.cant_m", "missing"),
    ({"radius_m": 1000.0, "cant_m": -0.1}, "layout.cant_m", "must be >="),
    ({"radius_m": 1000.0, "cant_m": 150.0}, "layout.cant_m", "given in mm"),
    ({"radius_m": 1000.0, "cant_m": 0.1, "transition_m": 5000.0}, "layout.transition_m", "given in mm"),
    ({"radius_m": 1000.0, "cant_m": 0.1, "transition_m": 0.0}, "layout.transition_m", "cant ramp"),
    ({"radius_m": 1000.0, "cant_m": 0.1, "transition_m": "long"}, "layout.transition_m", "expected a number"),
    ({"radius_m": 1000.0, "cant_m": 0.1, "direction": "up"}, "layout.direction", "'right'"),
    ({"radius_m": 1000.0, "cant_m": 0.1, "start_m": -1.0}, "layout.start_m", "behind the leading wheelset"),
    ({"radius_m": 1000.0, "cant_m": 0.1, "length_m": 3.0}, "layout.length_m", "unknown key"),
    ("curve", "layout", "expected a table"),
]


@pytest.mark.parametrize("layout, key, words", LAYOUT_ERRORS, ids=[f"{e[1]}:{e[2]}" for e in LAYOUT_ERRORS])
def test_each_layout_key_is_checked_and_named(layout, key, words):
    with pytest.raises(ScenarioError, match=rf"<dict>: {key}: .*{words}"):
        validate_scenario(_scn(layout))


def test_combinations_refused_with_one_line_naming_both():
    with pytest.raises(ScenarioError, match=r"layout: .*not a train \(vehicle\.consist\)") as e:
        validate_scenario(_scn(vehicle={"consist": "manchester_x8", "speed_km_h": 100.0}))
    assert "\n" not in str(e.value)
    with pytest.raises(ScenarioError, match=r"layout: a \[layout\] cannot be combined with a \[flexible_track\]") as e:
        validate_scenario(_scn(flexible_track={}))
    assert "\n" not in str(e.value)
    with pytest.raises(ScenarioError, match=r"contact\.wheel_rail: 'springs'.*\[layout\]"):
        validate_scenario(_scn(contact={"wheel_rail": "springs"}, run={"duration_s": 0.1, "record": False}))
    with pytest.raises(ScenarioError, match=r"outputs\.timeseries\.0: 'curving' needs a \[layout\]"):
        validate_scenario({"schema_version": 2, "vehicle": {"name": VEHICLE, "speed_km_h": 100.0},
                           "run": {"duration_s": 0.1}, "outputs": {"timeseries": ["curving"]}})


def test_auto_duration_runs_the_whole_vehicle_through_the_transition():
    """``run.duration_s = "auto"`` with a curve and no other track feature: the curve's end is the end of its
    transition (the circular curve has none), so the run lasts until the trailing wheelset is ``run_out_m`` past it:
    ``(start_m + transition_m - vehicle.start_s_m + extent + run_out_m) / V``."""
    from exudyn_wheelrail.scenarios.build import scenario_run_settings
    from exudyn_wheelrail.scenarios.spec import features_end_m
    scn = validate_scenario(_scn(run={"duration_s": "auto", "run_out_m": 12.0}))
    assert features_end_m(scn) == LEAD_IN_M + 40.0
    vehicle = load_vehicle(VEHICLE)
    x = vehicle.wheelset_x_m()
    run, coverage = scenario_run_settings(scn, vehicle)
    want = (LEAD_IN_M + 40.0 - scn["vehicle"]["start_s_m"] + float(max(x) - min(x)) + 12.0) / (100.0 / 3.6)
    assert coverage["t_passage_s"] == pytest.approx(want, rel=1e-12)
    assert run.duration_s == pytest.approx(want, rel=1e-12)


def test_explicit_step_is_the_curving_commands():
    """Without run.dt_s an explicit solver gets the curving command's step (1 ms, or its largest whole fraction
    within the creep limit); a longer given step is a warning; an implicit solver keeps its step."""
    vehicle = load_vehicle(VEHICLE)
    for v_kmh in (100.0, 12.0):
        out = validate_scenario(_scn(vehicle={"name": VEHICLE, "speed_km_h": v_kmh},
                                     run={"duration_s": 0.1, "solver": "rk44"}))
        limit = creep_step_limit_s(vehicle, v_kmh / 3.6)
        dt = out["run"]["dt_s"]
        assert dt <= limit and dt == 1e-3 / math.ceil(1e-3 / min(1e-3, limit))
    assert out["run"]["dt_s"] < 1e-3                                   # 12 km/h: the creep damping shortens it
    slow = _scn(vehicle={"name": VEHICLE, "speed_km_h": 12.0}, run={"duration_s": 0.01, "solver": "rk44",
                                                                     "dt_s": 1e-3})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert validate_scenario(slow)["run"]["dt_s"] == 1e-3             # a given step is kept
        assert validate_scenario(_scn(vehicle={"name": VEHICLE, "speed_km_h": 12.0}))["run"]["dt_s"] == 1e-3
    with pytest.warns(InputWarning, match=r"^run\.dt_s: 0\.001 s is longer than .* at 12 km/h") as record:
        build_scenario(slow)                                           # judged once, when the model is built
    assert len([w for w in record if issubclass(w.category, InputWarning)]) == 1


def test_irregularity_under_the_vehicle_at_the_start_is_refused():
    scn = _scn(track=[{"type": "harmonic", "amplitude_m": 0.002, "wavelength_m": 25.0}])
    with pytest.raises(ScenarioError, match=r"track: .*under a wheelset at t = 0.*s <= 0 m"):
        build_scenario(scn)


# ------------------------------------------------------------------------------ (b) the curving command's spec
def _tables(scn, *names):
    return {k: scn[k] for k in names}


def test_curving_front_end_fills_the_hand_written_curve():
    """The spec the curving command fills for R = 1000 m, 100 mm, 100 km/h (validated) has the vehicle, start,
    track, curve and contact of curve_r1000.toml, written by hand for that case, and its step; the run is longer
    (until the whole vehicle is steady: curving_distances) and records no car-body points."""
    case = CurvingCase(VEHICLE, radius_m=1000.0, cant_m=0.1, speed_km_h=100.0)
    ref = load_scenario(EXAMPLES / "curve_r1000.toml")
    out = validate_scenario(curving_scenario(case))
    assert _tables(out, "vehicle", "track", "layout", "contact") == _tables(ref, "vehicle", "track", "layout",
                                                                             "contact")
    assert {k: v for k, v in out["run"].items() if k != "duration_s"} == {
        k: v for k, v in ref["run"].items() if k != "duration_s"}
    dist = curving_distances(case, load_vehicle(VEHICLE))
    assert out["run"]["duration_s"] == dist["duration_s"] > ref["run"]["duration_s"]
    assert out["outputs"]["carbody_points"] == [] and not out["outputs"]["criteria"]["enabled"]
    assert validate_scenario(out) == out


@pytest.mark.parametrize("v_kmh, preset", [(12.0, "fast"), (100.0, "accurate")])
def test_curving_front_end_step_is_the_preset_step_within_the_creep_limit(v_kmh, preset):
    """The step the front end fills is the preset's, shortened to its largest whole fraction within the creep
    limit: at 12 km/h the 1 ms of 'fast' the spec's own rule gives a curve without run.dt_s; 'accurate' keeps its
    0.25 ms.  Contact settings and friction are the preset's and the case's."""
    case = CurvingCase(VEHICLE, radius_m=1000.0, cant_m=0.1, speed_km_h=v_kmh, preset=preset, friction=0.3)
    out = validate_scenario(curving_scenario(case))
    dt = PRESETS[preset].run["dt_s"]
    limit = creep_step_limit_s(load_vehicle(VEHICLE), v_kmh / 3.6)
    assert out["run"]["dt_s"] == dt / math.ceil(dt / min(dt, limit)) <= limit
    assert out["run"]["solver"] == PRESETS[preset].run["solver"]
    assert {k: out["contact"][k] for k in PRESETS[preset].contact} == PRESETS[preset].contact
    assert out["contact"]["friction"] == 0.3
    if preset == "fast":
        assert out["run"]["dt_s"] < dt
        own = validate_scenario(_scn(vehicle={"name": VEHICLE, "speed_km_h": v_kmh},
                                     run={"duration_s": 0.1, "solver": "rk44"}))
        assert out["run"]["dt_s"] == own["run"]["dt_s"]


def test_python_only_inputs_of_the_build():
    """What the spec cannot hold goes to build_scenario by keyword: a pair object is the model's pair, an
    irregularity is added after the spec's track components and is checked against the undisplaced start, a vehicle
    object is built in place of the named one (its changed value in the model)."""
    case = CurvingCase(VEHICLE, radius_m=1000.0, cant_m=0.1, speed_km_h=100.0)
    scn = _scn(run={"duration_s": 0.01}, outputs={"carbody_points": [], "criteria": False, "plots": False})
    pair = WheelRailPair(WheelProfile.cone(0.05), "UIC60", inclination="1/40")
    late = Harmonic(amplitude_m=0.0, wavelength_m=25.0)               # zero everywhere: allowed at the start
    h = build_scenario(scn, pair=pair, irregularity=late)
    assert h.pair is pair and h.track.irregularity is late
    two = build_scenario(_scn(track=[{"type": "harmonic", "amplitude_m": 0.0, "wavelength_m": 30.0}],
                              run={"duration_s": 0.01}), irregularity=late)
    assert isinstance(two.track.irregularity, IrregularitySum) and two.track.irregularity.components[-1] is late
    with pytest.raises(ScenarioError, match=r"track: .*under a wheelset at t = 0"):
        build_scenario(scn, irregularity=Harmonic(amplitude_m=0.002, wavelength_m=25.0))
    heavy = load_vehicle_with_overrides(VEHICLE, {"car_body.mass_kg": 40000.0})
    assert build_scenario(scn, vehicle=heavy).model.car_body.mass_kg == 40000.0
    assert build_curving(dataclasses.replace(case, vehicle=heavy)).model.car_body.mass_kg == 40000.0
    # the spec's overrides are not applied to a vehicle given as data: refused, naming the key
    with pytest.raises(ScenarioError, match=r"vehicle\.overrides: not applied to a vehicle given"):
        build_scenario({**scn, "vehicle": {**scn["vehicle"], "overrides": {"car_body.mass_kg": 30000.0}}},
                       vehicle=heavy)


# ------------------------------------------------------------------------------------- (c) a steady curve
def test_steady_curve_balances_the_unbalanced_lateral_acceleration():
    """curve_r1000.toml run as long as the curving command runs that curve: ΣΣY over the steady window balances
    the vehicle's mass times a_nc (from the closed form) within twice STEADY_TOLERANCE of the force balance's scale
    (the curving module's 2 % target), and the run is steady by its drift criterion."""
    case = CurvingCase(VEHICLE, radius_m=1000.0, cant_m=0.1, speed_km_h=100.0)
    dist = curving_distances(case, load_vehicle(VEHICLE))
    scn = apply_overrides(load_scenario(EXAMPLES / "curve_r1000.toml"),
                          {"run.duration_s": dist["duration_s"], "outputs.plots": False})
    h = build_scenario(scn)
    outcome = run_model(h)
    result = scenario_summary(h, outcome)
    assert result.summary["status"] == "ok"
    lay = result.summary["layout"]
    g, V = h.model.gravity_m_s2, h.speed_m_s
    phi = math.asin(0.1 / RAIL_CENTRE_DISTANCE_M)
    a_nc = V * V / 1000.0 * math.cos(phi) - g * math.sin(phi)
    assert lay["unbalanced_lateral_acceleration_m_s2"] == pytest.approx(a_nc, rel=1e-12)
    assert lay["cant_angle_rad"] == phi
    assert lay["balance_speed_km_h"] == pytest.approx(math.sqrt(g * math.tan(phi) * 1000.0) * 3.6, rel=1e-12)
    m = load_vehicle(VEHICLE).total_mass_kg                         # the vehicle file's bodies (a car)
    assert lay["vehicle_mass_kg"] == m
    assert lay["m_a_nc_N"] == pytest.approx(m * a_nc, rel=1e-12)
    st = steady_state(result.timeseries, h.model, h.layout, t_from_s=dist["window_start_s"], speed_m_s=V,
                      gravity_m_s2=g, a_nc_m_s2=a_nc)
    assert st["steady"], st["steady_drift_N"]
    total = sum(st["sum_Y_N"]) + st.get("guidance_lateral_N", 0.0)
    scale = m * max(abs(a_nc), STEADY_A_MIN_M_S2)
    assert abs(total - m * a_nc) <= 2.0 * STEADY_TOLERANCE * scale, (total, m * a_nc)


# ----------------------------------------------------------------------------------- (d) a curve over a deck
def test_curve_over_a_bridge_runs_with_its_deck_columns():
    """curve_over_bridge.toml with the deck moved into the transition (s = 12 ... 32 m) so that the vehicle is on
    it within 400 steps."""
    scn = apply_overrides(load_scenario(EXAMPLES / "curve_over_bridge.toml"),
                          {"run.duration_s": 0.4, "structure.start_m": 12.0, "outputs.plots": False})
    h = build_scenario(scn)
    assert h.layout is not None and h.bridge is not None and h.contact.layout is h.layout
    outcome = run_model(h)
    result = scenario_summary(h, outcome)
    s = result.summary
    assert s["status"] == "ok" and s["steps"] == 400
    for group in ("deck", "deck_acceleration", "deck_wheelsets", "deck_lateral", "curving"):
        assert s["columns"].get(group), group
    ts = result.timeseries
    assert abs(ts["deck_deflection_w1_m"][-1]) > 1e-5                   # the leading wheelset loads the deck
    assert np.max(np.abs(ts["curvature_w1_1_m"])) > 0.0
    assert s["layout"]["curve_start_m"] == 65.0 and s["deck"] is not None
