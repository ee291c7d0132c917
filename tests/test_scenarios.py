"""Scenario files and parameter sweeps (exudyn_wheelrail.scenarios.scenario / .sweep; CLI ``run`` / ``sweep``).

References, independent of the code under test:

* the bridge deck alone under the static axle loads moving at V (scenarios.moving_forces.simulate_moving_forces, a separate
  Exudyn model without vehicle) for the deck deflection of the bridge scenario; the EN 1990 cut-off computed by
  hand from the stated section; the trapezoidal rule's identity (w₊ − 2w + w₋)/h² = (a₊ + 2a + a₋)/4 between
  the recorded deck deflection and acceleration; the total static wheel load = vehicle weight; the FE beam's
  static deflection (the sum over all its modes) for the quasi-static reference; the mid-span deflection when a
  wheelset passes mid-span for the deck under that wheelset; the load path's static wheel loads for ΔQ/Q;
* invariance: a rigid lateral/vertical translation of the whole track does not change the contact forces;
* the serial run (in process) for the sweep through a thread pool, a process pool and a Dask cluster;
* a ``schema_version = 1`` file is the same scenario as its version-2 form (the keys moved, nothing else).

All runs are short (tens to a few hundred steps; the bridge crossing ~1400 steps, < 1 s of solving).
"""
import csv
import io
import json
import math
import pickle
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from multiprocessing import get_context
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.cli import main as cli_main
from exudyn_wheelrail.scenarios.scenario import (
    ScenarioError,
    apply_overrides,
    build_bridge_modes,
    load_scenario,
    run_scenario,
    set_dotted,
    validate_scenario,
)
from exudyn_wheelrail.scenarios.sweep import TIMING_COLUMNS, SerialExecutor, sweep
from exudyn_wheelrail.simulation.recorder import PROGRESS_MIN_STEPS
from exudyn_wheelrail.simulation.runner import _Hook

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "scenarios"
SHIPPED = ("rtri_20m", "bridge_20m", "bridge_40m", "bridge_20m_support_motion", "harmonic_track", "curve_r1000",
           "curve_over_bridge")

BASE_TOML = """\
schema_version = 2
[vehicle]
name = "manchester_vehicle1"
speed_km_h = 250.0
[[track]]
type = "span_deflection"
span_length_m = 20.0
amplitude_m = 0.01
start_m = 11.5
transition_length_m = 3.0
[run]
duration_s = 0.02
"""


STRUCTURE = "[structure]\nspans_m = [20.0]\nstart_m = 50.0\ndamping_ratio = 0.01\nrail_height_m = 1.0\n"
SECTION = ("[structure.section]\nm_kg_m = 1e4\nEI_y_Nm2 = 1e10\nEI_z_Nm2 = 1e10\nGJ_Nm2 = 1e10\nEA_N = 1e11\n"
           "Ip_kgm2_m = 1e4\n")


def _motion(*lines):
    """A deck with a [structure.support_motion] table of these lines."""
    return STRUCTURE + SECTION + "[structure.support_motion]\n" + "".join(f"{line}\n" for line in lines)


def read_csv(path):
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return rows[0], {k: np.array([float(r[i]) for r in rows[1:]]) for i, k in enumerate(rows[0])}


# ------------------------------------------------------------------------------------------------------- loader
def _edit(old, new):
    return lambda text: text.replace(old, new) if old in text else pytest.fail(f"{old!r} not in the base")


LOADER_ERRORS = [
    (_edit("schema_version = 2\n", ""), "schema_version", "missing"),
    (_edit("schema_version = 2", "schema_version = 3"), "schema_version", "3"),
    (_edit("duration_s = 0.02", "durationn_s = 0.02"), "run.durationn_s", "unknown key"),
    (_edit("speed_km_h = 250.0\n", ""), "vehicle.speed_km_h", "missing"),
    (_edit("speed_km_h = 250.0", "speed_km_h = true"), "vehicle.speed_km_h", "number"),
    (_edit("speed_km_h = 250.0", "speed_km_h = -5.0"), "vehicle.speed_km_h", "> 0"),
    (_edit("duration_s = 0.02", "duration_s = \"forever\""), "run.duration_s", "auto"),
    (_edit("duration_s = 0.02", "duration_s = 0.02\nsolver = \"euler\""), "run.solver", "newmark"),
    (_edit("duration_s = 0.02", "duration_s = 0.02\ndt_s = \"0.001\""), "run.dt_s", "number"),
    (_edit("duration_s = 0.02", "duration_s = 0.02\ndt_s = 1.0"), "run.dt_s", "milliseconds"),
    (_edit("duration_s = 0.02", "duration_s = 0.02\nrecord_every = 0"), "run.record_every", ">= 1"),
    (_edit("[run]", "[contact]\ncreep_law = \"bogus\"\n[run]"), "contact.creep_law", "fastsim"),
    (_edit("[run]", "[contact]\nfastsim_grid = [24]\n[run]"), "contact.fastsim_grid", "two"),
    (_edit("[run]", "[contact]\nwheel_rail = \"springs\"\n[run]"), "contact.wheel_rail", "run.record = false"),
    (_edit("amplitude_m = 0.01\n", ""), "track.0.amplitude_m", "missing"),
    (_edit("type = \"span_deflection\"", "type = \"spline\""), "track.0.type", "harmonic"),
    (_edit("transition_length_m = 3.0", "transition_length_m = 30.0"), "track.0.transition_length_m", "shorter"),
    (_edit("transition_length_m = 3.0", "transition_length_m = 3.0\ndirection = \"up\""), "track.0.direction",
     "vertical"),
    (_edit("name = \"manchester_vehicle1\"", "name = \"no_such_vehicle\""), "vehicle.name", "not found"),
    (_edit("name = \"manchester_vehicle1\"", "name = \"manchester_vehicle1\"\nfile = \"v.toml\""), "vehicle",
     "exactly one"),
    (_edit("speed_km_h = 250.0", "speed_km_h = 250.0\n[vehicle.overrides]\nprimary.kyy = 1.0"), "vehicle.overrides",
     "kyy"),
    (lambda t: t + "[foo]\nbar = 1\n", "foo", "unknown key"),
    (lambda t: t + "[outputs]\ntimeseries = [\"Y\", \"deck\"]\n", "outputs.timeseries.1", "structure"),
    (lambda t: t + "[outputs]\nformats = [\"hdf5\"]\n", "outputs.formats.0", "csv"),
    (lambda t: t + "[[outputs.carbody_points]]\nname = \"p\"\nx_m = \"middle\"\nheight_m = 1.2\n",
     "outputs.carbody_points.0.x_m", "rear_bogie"),
    (lambda t: t + "[[outputs.carbody_points]]\nname = \"p\"\nx_m = 0.0\n", "outputs.carbody_points.0.height_m",
     "missing"),
    (lambda t: t + "[outputs.criteria]\ncarbody_point = \"roof\"\n", "outputs.criteria.carbody_point", "roof"),
    (lambda t: t + "[structure]\nspans_m = [20.0]\nstart_m = 50.0\ndamping_ratio = 0.01\nrail_height_m = 1.0\n",
     "structure.section", "missing"),
    (lambda t: t + "[structure]\nspans_m = [20.0]\nstart_m = 50.0\ndamping_ratio = 2.0\nrail_height_m = 1.0\n"
                   "[structure.section]\nm_kg_m = 1e4\nEI_y_Nm2 = 1e10\nEI_z_Nm2 = 1e10\nGJ_Nm2 = 1e10\n"
                   "EA_N = 1e11\nIp_kgm2_m = 1e4\n", "structure.damping_ratio", "< 1.0"),
    (lambda t: t.replace("duration_s = 0.02", "duration_s = 0.02\nsolver = \"rk44\"")
     + "[structure]\nspans_m = [20.0]\nstart_m = 50.0\ndamping_ratio = 0.01\nrail_height_m = 1.0\n"
       "formulation = \"ffrf\"\n[structure.section]\nm_kg_m = 1e4\nEI_y_Nm2 = 1e10\nEI_z_Nm2 = 1e10\n"
       "GJ_Nm2 = 1e10\nEA_N = 1e11\nIp_kgm2_m = 1e4\n", "structure.formulation", "newmark"),
    (lambda t: t + STRUCTURE + "track_form = \"slab\"\n" + SECTION, "structure.track_form", "ballasted"),
    (lambda t: t + _motion("frequency_Hz = 1.5"), "structure.support_motion.peak_acceleration_m_s2", "missing"),
    (lambda t: t + _motion("peak_acceleration_m_s2 = 0.0", "frequency_Hz = 1.5"),
     "structure.support_motion.peak_acceleration_m_s2", "> 0.0"),
    (lambda t: t + _motion("peak_acceleration_m_s2 = 15.0", "frequency_Hz = 1.5"),
     "structure.support_motion.peak_acceleration_m_s2", "plausible peak ground"),
    (lambda t: t + _motion("peak_acceleration_m_s2 = 1.5", "frequency_Hz = 50"),
     "structure.support_motion.frequency_Hz", "plausible ground-motion frequency"),
    (lambda t: t + _motion("peak_acceleration_m_s2 = 1.5", "frequency_Hz = 1.5", "ramp_cycles = 0"),
     "structure.support_motion.ramp_cycles", "> 0.0"),
    (lambda t: t + _motion("peak_acceleration_m_s2 = 1.5", "frequency_Hz = 1.5", "plateau_cycles = \"forever\""),
     "structure.support_motion.plateau_cycles", "auto"),
    (lambda t: t + _motion("peak_acceleration_m_s2 = 1.5", "frequency_Hz = 1.5", "amplitude_m = 0.01"),
     "structure.support_motion.amplitude_m", "unknown key"),
    (lambda t: t + "[outputs]\ntimeseries = [\"deck_lateral\"]\n", "outputs.timeseries.0", "needs a [structure]"),
    (lambda t: t.replace("type = \"span_deflection\"\nspan_length_m = 20.0\namplitude_m = 0.01\nstart_m = 11.5\n"
                         "transition_length_m = 3.0", "type = \"harmonic\"\namplitude_m = 0.001\nwavelength_m = 20.0")
     .replace("duration_s = 0.02", "duration_s = \"auto\""), "run.duration_s", "harmonic"),
]


@pytest.mark.parametrize("edit, key, words", LOADER_ERRORS, ids=[e[1] + ":" + e[2] for e in LOADER_ERRORS])
def test_loader_errors_name_the_file_and_the_key(tmp_path, edit, key, words):
    path = tmp_path / "case.toml"
    path.write_text(edit(BASE_TOML))
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    msg = str(err.value)
    assert str(path) in msg and f"{key}:" in msg and words in msg, msg


def test_loader_file_errors(tmp_path):
    with pytest.raises(ScenarioError, match="not found"):
        load_scenario(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("schema_version = 1\n[run\n")
    with pytest.raises(ScenarioError, match=r"bad\.toml: not valid TOML"):
        load_scenario(bad)
    # a sampled table: the path is relative to the scenario file; a bad table names the key
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "irr.csv").write_text("s_m,y_m\n0,0\n1,0\n")
    path = tmp_path / "case.toml"
    path.write_text(BASE_TOML.replace("[run]", "[[track]]\ntype = \"sampled\"\nfile = \"data/irr.csv\"\n[run]"))
    with pytest.raises(ScenarioError, match=r"case\.toml: track\.1\.file: .*z_m"):
        load_scenario(path)
    (tmp_path / "data" / "irr.csv").write_text("s_m,y_m,z_m\n0,0,0\n1,0.001,0\n")
    scn = load_scenario(path)
    assert scn["track"][1]["file"] == str((tmp_path / "data" / "irr.csv").resolve())


@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_scenarios_normal_form(name):
    """The normal form is plain data: validating it again changes nothing; it survives JSON and pickle."""
    scn = load_scenario(EXAMPLES / f"{name}.toml")
    assert validate_scenario(scn) == scn
    assert json.loads(json.dumps(scn)) == scn
    assert pickle.loads(pickle.dumps(scn)) == scn
    assert scn["scenario"]["name"] == name


def test_dotted_overrides():
    scn = load_scenario(EXAMPLES / "rtri_20m.toml")
    new = apply_overrides(scn, {"vehicle.speed_km_h": 100, "track.0.amplitude_m": 0.005})
    assert new["vehicle"]["speed_km_h"] == 100.0 and new["track"][0]["amplitude_m"] == 0.005
    assert scn["vehicle"]["speed_km_h"] == 250.0                 # the base is not changed
    old_keys = apply_overrides(scn, {"run.speed_km_h": 100, "run.creep_law": "fastsim"})    # version-1 keys
    assert old_keys["vehicle"]["speed_km_h"] == 100.0 and old_keys["contact"]["creep_law"] == "fastsim"
    with pytest.raises(ScenarioError, match=r"'track\.3\.amplitude_m': track has 1 entry"):
        set_dotted(dict(scn), "track.3.amplitude_m", 1.0)
    with pytest.raises(ScenarioError, match=r"'vehicle\.speed_km_h\.x'.*is a value"):
        set_dotted(dict(scn), "vehicle.speed_km_h.x", 1.0)
    with pytest.raises(ScenarioError, match=r"no 'nosuch'"):
        set_dotted(dict(scn), "nosuch.key", 1.0)
    with pytest.raises(ScenarioError, match=r"<overrides>: run\.speedd: unknown key"):
        apply_overrides(scn, {"run.speedd": 1.0})
    with pytest.raises(ScenarioError, match=r"<overrides>: run\.dt_s: -1 is not a plausible time step"):
        apply_overrides(scn, {"run.dt_s": -1.0})


def test_version_1_files_are_read_with_the_keys_moved(tmp_path):
    """A version-1 file (speed, start, creep law, friction and FASTSIM grid in [run]) gives the same normal form as
    the version-2 file with those keys in [vehicle] and [contact]."""
    v1 = BASE_TOML.replace("schema_version = 2", "schema_version = 1").replace("speed_km_h = 250.0\n", "") \
        .replace("duration_s = 0.02", "duration_s = 0.02\nspeed_km_h = 250.0\nstart_s_m = 1.0\ncreep_law = "
                                      "\"fastsim\"\nfriction = 0.25\nfastsim_grid = [12, 4]")
    v2 = BASE_TOML.replace("speed_km_h = 250.0", "speed_km_h = 250.0\nstart_s_m = 1.0").replace(
        "[run]", "[contact]\ncreep_law = \"fastsim\"\nfriction = 0.25\nfastsim_grid = [12, 4]\n[run]")
    (tmp_path / "v1.toml").write_text(v1)
    (tmp_path / "v2.toml").write_text(v2)
    a, b = load_scenario(tmp_path / "v1.toml"), load_scenario(tmp_path / "v2.toml")
    a["scenario"]["name"] = b["scenario"]["name"]
    assert a == b and a["schema_version"] == 2 and a["contact"]["fastsim_grid"] == [12, 4]


# ------------------------------------------------------------------------------------------- run and outputs
@pytest.fixture(scope="module")
def rtri_run(tmp_path_factory):
    """rtri_20m.toml over 0.4 s (the leading wheelset runs onto the deviation) with the progress bar on a stream."""
    bar = io.StringIO()
    tmp = tmp_path_factory.mktemp("rtri_scenario")
    scn = apply_overrides(load_scenario(EXAMPLES / "rtri_20m.toml"), {"run.duration_s": 0.4})
    result = run_scenario(scn, tmp / "scenario", progress=bar)
    return result, bar.getvalue(), tmp


def test_run_is_ok_and_watched(rtri_run):
    s = rtri_run[0].summary
    assert s["status"] == "ok" and s["status_detail"]["exit_code"] == 0
    assert s["rows_recorded"] == s["steps"] + 1 == 401
    assert s["contact_calls"] > s["steps"]                  # the monitor evaluated every state
    assert s["scalars"]["max_abs_Y_any_wheel_N"] > 5e3       # the deviation acts in the run


def test_progress_bar_every_percent(rtri_run):
    bar = rtri_run[1]
    assert rtri_run[0].summary["steps"] >= PROGRESS_MIN_STEPS
    pct = [int(x) for x in __import__("re").findall(r"\] +(\d+) %", bar)]
    assert pct == list(range(0, 101))                                    # every whole percent once, in order
    assert bar.endswith("ok\n")


def test_outputs_files_columns_and_criteria(rtri_run):
    result, _, tmp = rtri_run
    out = tmp / "scenario"
    s = json.loads((out / "summary.json").read_text())
    header, ts = read_csv(out / "timeseries.csv")
    groups = s["scenario"]["outputs"]["timeseries"]
    assert groups == ["Y", "Q", "YQ", "flange", "wheelset_lateral", "carbody"]
    assert header == ["time_s", "s_leading_m"] + [c for g in groups for c in s["columns"][g]]
    npz = np.load(out / "timeseries.npz")
    assert sorted(npz.files) == sorted(header)
    np.testing.assert_array_equal(npz["Y_w1_right_N"], result.timeseries["Y_w1_right_N"])    # npz keeps the doubles
    np.testing.assert_allclose(ts["s_leading_m"], 250.0 / 3.6 * ts["time_s"], rtol=1e-9, atol=1e-9)
    # the static wheel loads of the criteria carry the vehicle's weight (published Manchester masses)
    from exudyn_wheelrail.multibody import load_vehicle
    weight = load_vehicle("manchester_vehicle1").total_mass_kg * 9.81
    assert sum(s["criteria"]["inputs"]["static_wheel_loads_N"].values()) == pytest.approx(weight, rel=1e-12)
    assert set(s["criteria"]["verdicts"]) >= {"derailment_quotient_en14363", "wheel_unloading",
                                              "track_shift_force_prudhomme", "carbody_lateral", "sperling_lateral"}
    assert s["criteria"]["criteria"]["carbody_lateral"]["column"] == "carbody_lateral_accelerometer_rear_m_s2"
    assert s["scalars"]["criteria.derailment_quotient_en14363.worst_value"] == \
        s["criteria"]["verdicts"]["derailment_quotient_en14363"]["worst_value"]
    for g in ("Y", "Q", "YQ", "wheelset_lateral", "carbody"):
        assert (out / f"plot_{g}.png").stat().st_size > 0


# -------------------------------------------------------------------------------------------------------- bridge
def test_bridge_scenario_against_the_moving_force_reference(tmp_path):
    """bridge_40m.toml: the deck deflection of the coupled crossing against the deck alone under the static axle
    loads moving at V (the vehicle-bridge interaction of a heavy concrete deck is small: within 1 %)."""
    from exudyn_wheelrail.multibody import load_vehicle
    from exudyn_wheelrail.rolling_stock.vehicle_builder import static_load_path
    from exudyn_wheelrail.scenarios.moving_forces import simulate_moving_forces

    scn = apply_overrides(load_scenario(EXAMPLES / "bridge_40m.toml"), {"outputs.plots": False})
    r = run_scenario(scn, None, progress=False)
    s = r.summary
    assert s["status"] == "ok" and s["coverage"]["passage_covered"]
    # EN 1990 cut-off by hand: f_n = n^2 pi/(2 L^2) sqrt(EI/m); max(30, 1.5 f1, f3) with f1 = 3.5 Hz -> 31.5 Hz
    sec = scn["structure"]["section"]
    f1 = math.pi / (2 * 40.0 ** 2) * math.sqrt(sec["EI_y_Nm2"] / sec["m_kg_m"])
    assert s["model"]["bridge"]["f_cut_Hz"] == pytest.approx(max(30.0, 1.5 * f1, 9 * f1), rel=1e-12)
    assert max(s["model"]["bridge"]["frequencies_Hz"]) <= 1.01 * 9 * f1
    ts = r.timeseries
    w, a = ts["deck_mid_deflection_s1_m"], ts["deck_mid_acceleration_s1_m_s2"]
    before = ts["s_leading_m"] < scn["structure"]["start_m"]
    # deck at rest, no load: exact zeros
    assert before.any() and np.all(w[before] == 0.0) and np.all(a[before] == 0.0)
    vehicle = load_vehicle("manchester_vehicle1")
    P = static_load_path(vehicle).wheel.sum(axis=1)
    x = np.array(vehicle.wheelset_x_m())
    V, dt = scn["vehicle"]["speed_km_h"] / 3.6, scn["run"]["dt_s"]
    _, modes, _ = build_bridge_modes(scn["structure"])
    _, q, _ = simulate_moving_forces(modes, x_m=x, forces_N=[[0.0, p, 0.0] for p in P], speed_m_s=V,
                                     s_start_m=scn["vehicle"]["start_s_m"] - x.max(), end_time_s=s["steps"] * dt,
                                     dt_s=dt)
    w_ref = q @ modes.shape_at(scn["structure"]["start_m"] + 20.0)[1]
    assert np.max(w) == pytest.approx(np.max(w_ref), rel=0.01)
    sp = s["deck"]["spans"][0]
    assert sp["coupled_over_moving_force"] == pytest.approx(np.max(w) / np.max(w_ref), rel=1e-9)
    # the recorded acceleration is the one the trapezoidal rule integrates to the recorded deflection
    lhs = (w[2:] - 2 * w[1:-1] + w[:-2]) / dt ** 2
    rhs = (a[2:] + 2 * a[1:-1] + a[:-2]) / 4
    assert np.max(np.abs(lhs - rhs)) < 1e-4 * np.max(np.abs(a))
    assert s["scalars"]["max_abs_deck_mid_acceleration_s1_m_s2"] == pytest.approx(np.max(np.abs(a)))
    # quasi-static reference against the static deflection of the FE beam under the axle loads at their places: the
    # sum over all its modes of phi(mid) phi(s) P / omega^2 (Hermite elements: exact Euler-Bernoulli nodal statics;
    # the tolerance is the eigensolution's round-off)
    _, all_modes, _ = build_bridge_modes({**scn["structure"], "modes_cutoff_Hz": 1e5})
    t = ts["time_s"]
    s_ax = scn["vehicle"]["start_s_m"] - x.max() + V * t[:, None] + x[None, :]
    phi_ax = all_modes.shape_at(s_ax)[..., 1, :]                                   # (n_t, n_ws, n_modes)
    phi_mid = all_modes.shape_at(scn["structure"]["start_m"] + 20.0)[1]
    w_static = np.einsum("tjn,j,n->t", phi_ax, P, phi_mid / all_modes.omega_rad_s ** 2)
    assert sp["quasi_static_max_mid_span_deflection_m"] == pytest.approx(np.max(w_static), rel=1e-8)
    # EN 1990 A2.4.4.2.1(4)P: the largest of the nine points' accelerations against 3.5 m/s2 (ballasted track)
    pts = np.array([ts[f"deck_acceleration_s1_p{k}_m_s2"] for k in range(1, 10)])
    en = s["deck"]["EN1990_A2_deck_acceleration"]
    # the summary's peak is the maximum of these columns (a selection): exact
    assert en["peak_m_s2"] == np.max(np.abs(pts)) and en["passed"] == (en["peak_m_s2"] <= 3.5)
    np.testing.assert_allclose(pts[4], a, rtol=0.0, atol=1e-12 * np.max(np.abs(a)))            # x = L/2
    # the deck under each wheelset: zero before it reaches the deck; the mid-span deflection when it passes there
    # (both read between rows: linear interpolation in time, error dt^2/8 max|w_tt| ~ (V dt pi/L)^2/8 w = 2e-6 w)
    for j, xj in enumerate(x):
        under = ts[f"deck_deflection_w{j + 1}_m"]
        s_j = scn["vehicle"]["start_s_m"] - x.max() + V * t + xj
        assert np.all(under[s_j < scn["structure"]["start_m"] - 1e-3] == 0.0)  # zero shapes off the deck: exact
        t_mid = (scn["structure"]["start_m"] + 20.0 - (s_j[0] - V * t[0])) / V
        assert np.interp(t_mid, t, under) == pytest.approx(np.interp(t_mid, t, w), abs=1e-5 * np.max(w))
    # the wheel unloading against the static wheel loads of the vehicle's load path
    Q0 = static_load_path(vehicle).wheel                                             # (n_ws, 2): left, right
    np.testing.assert_allclose(ts["dQQ_w2_left"], (Q0[1, 0] - ts["Q_w2_left_N"]) / Q0[1, 0], rtol=1e-12)
    # a maximum (selection): exact
    assert s["scalars"]["max_dQQ_any_wheel"] == max(np.max(ts[c]) for c in s["columns"]["unloading"])


# --------------------------------------------------------------------------------------------- start and recorder
@pytest.mark.parametrize("slope", [0.0, 2e-3], ids=["translated", "translated_and_inclined"])
def test_rigid_motion_of_the_track_changes_no_force(tmp_path, slope):
    """A sampled track y = 5 mm + k s, z = 2 mm (knots every metre over ±300 m: the clamped spline is the straight
    line to round-off in the middle) is the perfect track translated (k = 0) or also turned by atan(k) in its
    plane: the vehicle starts on it (moved, yawed, with the matching velocities) and every contact force and
    wheelset-rail displacement is that of the perfect track — to round-off for the translation, to O(k) for the
    turn: the connector evaluates the rail cross-section at the wheelset's yaw in the frame, not relative to the
    rail direction (small-angle model), so the kernel sees a relative yaw k; bound used: k x 10 kN, k x 5 mm.
    Without the yaw alignment at the start the wheelsets would see a lateral creepage k (f22 k: tens of kN)."""
    s_m = np.arange(-300.0, 301.0, 1.0)
    rows = "\n".join(f"{s:.17g},{0.005 + slope * s:.17g},0.002" for s in s_m)
    (tmp_path / "offset.csv").write_text("s_m,y_m,z_m\n" + rows + "\n")
    text = BASE_TOML.replace("[[track]]\ntype = \"span_deflection\"\nspan_length_m = 20.0\namplitude_m = 0.01\n"
                             "start_m = 11.5\ntransition_length_m = 3.0\n", "")
    text = text.replace("duration_s = 0.02", "duration_s = 0.1").replace("[run]", "[contact]\ncreep_law = "
                                                                                   "\"fastsim\"\n[run]") + \
        "[outputs]\ncriteria = false\nplots = false\n"
    (tmp_path / "flat.toml").write_text(text)
    (tmp_path / "moved.toml").write_text(text.replace("[contact]", "[[track]]\ntype = \"sampled\"\n"
                                                                   "file = \"offset.csv\"\n[contact]"))
    flat = run_scenario(tmp_path / "flat.toml", None, progress=False)
    moved = run_scenario(tmp_path / "moved.toml", None, progress=False)
    assert any("displaced by up to" in n for n in moved.summary["notes"])
    assert not any("displaced" in n for n in flat.summary["notes"])
    rtol, atol_N, atol_m = (1e-7, 1e-3, 1e-10) if slope == 0.0 else (0.0, slope * 1e4, slope * 5e-3)
    for g in ("Y", "Q"):
        for c in flat.summary["columns"][g]:
            np.testing.assert_allclose(moved.timeseries[c], flat.timeseries[c], rtol=rtol, atol=atol_N, err_msg=c)
    for c in flat.summary["columns"]["wheelset_lateral"]:
        np.testing.assert_allclose(moved.timeseries[c], flat.timeseries[c], rtol=0, atol=atol_m, err_msg=c)


class _Rows:
    def __init__(self):
        self.t = []

    def record(self, mbs, t):
        self.t.append(t)


def test_recorder_keeps_accepted_states_on_the_grid():
    """Exudyn calls the pre-step function with the end time of the step it attempts; after a rejected attempt it
    calls again with a smaller end time (the state rolled back).  Rows: one per accepted state on the dt grid; a
    reduced step that lands on the grid again loses no row."""
    rows = _Rows()
    dt = 1e-3
    hook = _Hook(None, None, rows, 1, None, dt, 0.0, True, None)
    for k in (1, 2, 3, 2.5, 2.25, 2.5, 3, 4, 5):      # 2->3 and 2->2.5 rejected, then quarter and half steps
        assert hook(None, k * dt) is True
    assert rows.t == pytest.approx([0.0, dt, 2 * dt, 3 * dt, 4 * dt], abs=1e-15)
    assert hook.rejected == 2 and hook.stop is None


def test_a_state_past_a_missing_grid_row_stops_the_run_as_step_rejected():
    """Reduced steps that pass a point of the dt grid without a state on it: the run stops there (the rows would
    have a gap), with the time of the missing row."""
    rows = _Rows()
    dt = 1e-3
    hook = _Hook(None, None, rows, 1, None, dt, 0.0, True, None)
    results = [hook(None, k * dt) for k in (1, 2, 3, 2.5, 3.5, 4.5)]   # states 0, 1, 2, 2.5, then 3.5 (no 3)
    assert results[:5] == [True] * 5 and results[5] is False
    assert rows.t == pytest.approx([0.0, dt, 2 * dt], abs=1e-15)
    assert hook.stop.kind == "step_rejected" and hook.stop.time_s == pytest.approx(3 * dt)


# --------------------------------------------------------------------------------------------------------- sweep
def _tiny_base():
    """harmonic_track.toml, 30 steps: the vehicle starts on the irregularities, so the cases differ at once."""
    return apply_overrides(load_scenario(EXAMPLES / "harmonic_track.toml"),
                           {"run.duration_s": 0.03, "contact.creep_law": "fastsim", "outputs.criteria": False,
                            "outputs.plots": False})


TINY_PARAMS = {"track.0.amplitude_m": [0.001, 0.003]}


def _comparable(table):
    return {k: v for k, v in table.items() if k not in TIMING_COLUMNS + ("case_dir",)}


@pytest.fixture(scope="module")
def serial_sweep(tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep_serial")
    return sweep(_tiny_base(), TINY_PARAMS, SerialExecutor(), out_dir=out, progress=None), out


def test_sweep_table_one_row_per_case(serial_sweep):
    r, out = serial_sweep
    t = r.table
    assert t["case"] == [0, 1] and t["track.0.amplitude_m"] == [0.001, 0.003] and t["status"] == ["ok", "ok"]
    assert all(len(v) == 2 for v in t.values())
    assert t["max_abs_Y_any_wheel_N"][0] != t["max_abs_Y_any_wheel_N"][1]          # the cases differ
    header, rows = read_csv_text(out / "sweep.csv")
    assert header == list(t) and len(rows) == 2
    for i, row in enumerate(rows):                                                  # repr floats: exact
        assert float(row[header.index("max_abs_Y_any_wheel_N")]) == t["max_abs_Y_any_wheel_N"][i]
    assert json.loads((out / "sweep.json").read_text())["table"]["status"] == ["ok", "ok"]
    assert (out / "sweep_plot.png").stat().st_size > 0
    assert (out / "cases" / "case_001" / "summary.json").is_file()


def read_csv_text(path):
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return rows[0], rows[1:]


@pytest.mark.parametrize("kind", ["thread", "process"])
def test_sweep_through_executors_is_identical_to_serial(serial_sweep, kind):
    make = {"thread": lambda: ThreadPoolExecutor(max_workers=2),
            "process": lambda: ProcessPoolExecutor(max_workers=2, mp_context=get_context("spawn"))}[kind]
    with make() as ex:
        r = sweep(_tiny_base(), TINY_PARAMS, ex, out_dir=None, progress=None)
    # exact by design: each case is the same deterministic computation whichever worker runs it
    assert _comparable(r.table) == _comparable(serial_sweep[0].table)


def test_sweep_on_a_dask_cluster_is_identical_to_serial(serial_sweep):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None) as lc, \
            distributed.Client(lc) as client:
        via_executor = sweep(_tiny_base(), TINY_PARAMS, client.get_executor(), out_dir=None, progress=None)
        via_client = sweep(_tiny_base(), TINY_PARAMS, client, out_dir=None, progress=None)
    ref = _comparable(serial_sweep[0].table)
    # the same deterministic computation in other processes (same machine and libraries): exact
    assert _comparable(via_executor.table) == ref
    assert _comparable(via_client.table) == ref


def test_sweep_validates_every_case_before_running():
    ran = []

    class Recording(SerialExecutor):
        def submit(self, fn, *args, **kwargs):
            ran.append(args)
            return super().submit(fn, *args, **kwargs)

    with pytest.raises(ScenarioError, match=r"sweep case 1 \(vehicle\.speed_km_h=-5\): vehicle\.speed_km_h"):
        sweep(_tiny_base(), {"vehicle.speed_km_h": [100, -5]}, Recording())
    with pytest.raises(ScenarioError, match=r"'track\.2\.amplitude_m'"):
        sweep(_tiny_base(), {"track.2.amplitude_m": [0.001]}, Recording())
    with pytest.raises(ScenarioError, match="plot_parameter"):
        sweep(_tiny_base(), {"vehicle.speed_km_h": [100]}, Recording(), plot_parameter="run.dt_s")
    with pytest.raises(ScenarioError, match="no values"):
        sweep(_tiny_base(), {"vehicle.speed_km_h": []}, Recording())
    assert ran == []


# ----------------------------------------------------------------------------------------------------------- CLI
def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "exudyn_wheelrail", *args], capture_output=True, text=True,
                          timeout=600)


def test_cli_run_with_overrides_and_progress(tmp_path, capsys):
    out = tmp_path / "run"
    # 200 steps: the shortest run that draws a progress bar (PROGRESS_MIN_STEPS); no plots (2.5 s of the 4 s run;
    # what a run plots is checked in test_outputs_files_columns_and_criteria)
    assert PROGRESS_MIN_STEPS == 200
    r = run_cli("run", str(EXAMPLES / "harmonic_track.toml"), "--out", str(out), "--set", "run.duration_s=0.2",
                "--set", "run.creep_law=fastsim", "--set", "outputs.formats=[\"npz\"]", "--set", "outputs.plots=false",
                "--progress")
    assert r.returncode == 0, r.stderr
    assert "100 %" in r.stderr and "\r" not in r.stderr and "status: ok" in r.stdout      # stderr a pipe: lines
    s = json.loads((out / "summary.json").read_text())
    assert s["steps"] == 200 and s["scenario"]["contact"]["creep_law"] == "fastsim"
    assert (out / "timeseries.npz").is_file() and not (out / "timeseries.csv").exists()
    # the rest through the same entry point in this process: main() returns the code ``python -m exudyn_wheelrail``
    # exits with (``__main__``: sys.exit(main())); stderr is captured, not a terminal, as a pipe is
    capsys.readouterr()
    assert cli_main(["run", str(EXAMPLES / "harmonic_track.toml"), "--out", str(out), "--no-progress",
                     "--set", "run.duration_s=0.01", "--set", "outputs.plots=false"]) == 0
    assert "%" not in capsys.readouterr().err
    assert cli_main(["run", str(EXAMPLES / "harmonic_track.toml"), "--out", str(out), "--set",
                     "run.speedd_km_h=1"]) == 2
    err = capsys.readouterr().err
    assert "run.speedd_km_h" in err and "harmonic_track.toml" in err
    assert cli_main(["run", str(EXAMPLES / "harmonic_track.toml"), "--out", str(out), "--set", "run.dt_s=1"]) == 2
    err = capsys.readouterr().err
    assert "run.dt_s" in err and "milliseconds" in err
    assert cli_main(["run", str(tmp_path / "missing.toml"), "--out", str(out)]) == 2
    assert "missing.toml" in capsys.readouterr().err


def test_cli_sweep(tmp_path):
    out = tmp_path / "sweep"
    r = run_cli("sweep", str(EXAMPLES / "rtri_20m.toml"), "--param", "vehicle.speed_km_h=200,250",
                "--param", "track.0.span_length_m=20,40", "--set", "run.duration_s=0.02",
                "--set", "contact.creep_law=fastsim", "--out", str(out), "--workers", "2", "--no-case-outputs",
                "--plot-result", "max_abs_Q_w1_right_N")
    assert r.returncode == 0, r.stderr
    header, rows = read_csv_text(out / "sweep.csv")
    assert len(rows) == 4
    i, j = header.index("vehicle.speed_km_h"), header.index("track.0.span_length_m")
    assert [(float(x[i]), float(x[j])) for x in rows] == [(200, 20), (200, 40), (250, 20), (250, 40)]
    assert all(x[header.index("status")] == "ok" for x in rows)
    assert (out / "sweep_plot.png").stat().st_size > 0 and not (out / "cases").exists()
    with pytest.raises(SystemExit):
        cli_main(["sweep", str(EXAMPLES / "rtri_20m.toml"), "--param", "vehicle.speed_km_h", "--out", str(out)])
