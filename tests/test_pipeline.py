"""The simulation pipeline (exudyn_wheelrail.simulation): run settings, statuses and exit codes, the one solve
wrapper, and how runs that go wrong end.

References, independent of the code under test:

* the steps of a run: ceil(duration / dt), by hand;
* Nadal's limit of S1002's 70° flank with μ = 0.3 by its formula, (tan γ − μ)/(1 + μ tan γ) = 1.343;
* RK44's stable step on the wheel–rail contact: ω h <= 2√2 (the stability region on the imaginary axis) with ω the
  stiffest mode of a wheelset on its two linearised Hertz contacts, k = dN/dδ = 1.5 N0/δ0 (N ∝ δ^1.5; N0, δ0 from
  the contact kernel at the static wheel load of the published Manchester masses), ω² = max(2 k cos²γ / m,
  2 k e² / I_xx) — computed here, not by the monitor;
* physics of the held-out runs: a 100 mm lateral span deflection over 20 m at 250 km/h pushes the leading wheelset
  with a lateral force far beyond what friction lets a flange carry: the run must end ``derailed`` (never ``ok``);
  a time step past RK44's limit must end ``diverged`` with that limit as the hint and no peak; the paper's
  Newmark scheme at 10 ms (ω h ≈ 13) resolves nothing of the contact: never ``ok``.
"""
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.analysis.safety import nadal_limit
from exudyn_wheelrail.scenarios.rtri import RTRI, RtriCase, run_rtri
from exudyn_wheelrail.scenarios.scenario import (
    ScenarioError,
    apply_overrides,
    load_scenario,
    run_scenario,
    validate_scenario,
)
from exudyn_wheelrail.simulation import status as S
from exudyn_wheelrail.simulation.settings import ContactSettings, RunSettings, SettingsError, settings_from_mapping
from exudyn_wheelrail.simulation.solvers import SOLVERS

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "scenarios"
V_RTRI = 250.0 / 3.6


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "exudyn_wheelrail", *map(str, args)], capture_output=True, text=True,
                          timeout=600)


# ----------------------------------------------------------------------------------------------- run settings
def test_steps_follow_from_the_duration_never_the_other_way():
    assert RunSettings(dt_s=1e-3, duration_s=2.5).steps == 2500
    assert RunSettings(dt_s=1e-2, duration_s=2.5).steps == 250              # a coarser step: the same 2.5 s
    assert RunSettings(dt_s=3e-3, duration_s=0.01).steps == 4               # ceil(3.33)
    assert RunSettings(dt_s=3e-3, duration_s=0.01).end_time_s == pytest.approx(0.012)
    with pytest.raises(ValueError, match="not resolved"):
        RunSettings().steps                                                 # "auto" needs the spec
    assert RunSettings().with_duration(1.0).steps == 1000


@pytest.mark.parametrize("kwargs, field, words", [
    (dict(solver="euler"), "solver", "newmark"),
    (dict(dt_s=1.0), "dt_s", "milliseconds"),
    (dict(dt_s=float("nan")), "dt_s", "finite"),
    (dict(duration_s=-1.0), "duration_s", "> 0"),
    (dict(duration_s="forever"), "duration_s", "auto"),
    (dict(dt_s=1e-6, duration_s=100.0), "duration_s", "steps"),
    (dict(newton_tolerance=0.0), "newton_tolerance", "> 0"),
    (dict(record="yes"), "record", "true or false"),
    (dict(record_every=0), "record_every", ">= 1"),
])
def test_bad_run_settings_name_the_field(kwargs, field, words):
    with pytest.raises(SettingsError) as err:
        RunSettings(**kwargs)
    assert err.value.field == field and str(err.value).startswith(f"{field}: ") and words in str(err.value)


def test_contact_settings_and_the_tables_map_one_to_one():
    assert ContactSettings().fastsim_grid == (24, 8)
    with pytest.raises(SettingsError, match="creep_law: 'bogus': expected one of .*fastsim"):
        ContactSettings(creep_law="bogus")
    with pytest.raises(SettingsError, match="run.dt_ms: unknown key .*duration_s"):
        settings_from_mapping(RunSettings, {"dt_ms": 1.0}, "run")
    # the scenario's [run] and [contact] tables are the settings' fields, defaults included
    scn = validate_scenario({"schema_version": 2, "vehicle": {"name": "manchester_vehicle1", "speed_km_h": 100.0},
                             "run": {"duration_s": 0.1}})
    assert scn["run"] == RunSettings(duration_s=0.1).as_dict()
    assert scn["contact"] == ContactSettings().as_dict()
    assert set(SOLVERS) >= {"newmark", "rk44"} and len(set(SOLVERS)) == len(SOLVERS)


def test_the_rtri_case_takes_run_and_contact_settings():
    case = RtriCase(span_m=40.0, solver="rk44", duration_s=1.0, creep_law="fastsim")
    assert case.run == RunSettings(solver="rk44", dt_s=RTRI.time_step_s, duration_s=1.0)
    assert case.contact.creep_law == "fastsim"
    same = RtriCase(span_m=40.0, run=case.run, contact=case.contact)
    assert same == case and case.replace(dt_s=0.5e-3).run.steps == 2000
    with pytest.raises(TypeError, match="steps"):
        RtriCase(steps=10)                        # the duration is the setting; steps are derived


# ------------------------------------------------------------------------------------------ statuses and exits
def test_statuses_and_exit_codes():
    assert S.STATUSES == ("ok", "derailed", "diverged", "step_rejected")
    assert [S.EXIT_CODES[k] for k in S.STATUSES] == [0, 3, 4, 5]
    assert S.EXIT_BAD_INPUT == 2 and S.EXIT_ERROR == 1
    assert S.exit_code(["ok", "ok"]) == 0 and S.exit_code(["ok", "derailed", "diverged"]) == 4
    assert S.exit_code(["step_rejected", "error: boom"]) == 1
    assert set(S.MONITOR_KINDS.values()) <= set(S.STATUSES)
    with pytest.raises(ValueError, match="kind"):
        S.RunStatus("completed")


def test_the_output_folder_is_checked_before_the_model_is_built(tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    scn = apply_overrides(load_scenario(EXAMPLES / "harmonic_track.toml"), {"run.duration_s": 0.01})
    with pytest.raises(ValueError, match="out_dir: .*existing file, not a directory"):
        run_scenario(scn, blocker, progress=False)


# ------------------------------------------------------------------------------------- held-out: 100 mm deviation
@pytest.fixture(scope="module")
def deviation_100mm():
    scn = apply_overrides(load_scenario(EXAMPLES / "rtri_20m.toml"),
                          {"track.0.amplitude_m": 0.1, "run.duration_s": 0.4, "outputs.plots": False,
                           "outputs.criteria": False})
    return scn, run_scenario(scn, None, progress=False)


def test_a_100mm_lateral_deviation_derails(deviation_100mm):
    """The rails move 100 mm sideways within half a span: the leading wheelset's flange is pushed with a
    derailment quotient that friction cannot hold (above Nadal's limit over 2 m of running) — derailed, with the
    time, the wheelset and the wheel, and the monitor's events before it."""
    scn, r = deviation_100mm
    s = r.summary
    st = s["status_detail"]
    assert s["status"] == "derailed" and st["exit_code"] == 3, st
    assert st["wheelset"] == 0 and st["side"] in ("right", "left")
    track = scn["track"][0]
    t_enter = (track["start_m"] - 0.5 * track["transition_length_m"]) / V_RTRI
    assert t_enter < st["time_s"] < 0.4
    assert "flange climb" in st["detail"] and "Nadal" in st["detail"]
    nadal = nadal_limit(math.radians(70.0), 0.3)
    assert nadal == pytest.approx((math.tan(math.radians(70.0)) - 0.3) / (1 + 0.3 * math.tan(math.radians(70.0))))
    # the monitor takes the flank angle from the S1002 data (70° to 0.1°: Nadal's limit to 5e-3)
    assert r.outcome.guidance.nadal_limit == pytest.approx(nadal, rel=5e-3)
    assert r.outcome.guidance.max_quotient.max() > nadal
    assert any(e["kind"] in ("flange_climb", "lift_off") and e["time_s"] <= st["time_s"] for e in s["events"])
    # the run stopped promptly: rows only up to the derailment state, no row after it
    assert r.timeseries["time_s"][-1] < st["time_s"] and s["simulated_time_s"] < st["time_s"] + 2.5e-3


def test_the_stated_rtri_deviation_stays_guided():
    """The same check on the stated 10 mm deviation (the flange root, no flange contact): ok."""
    r = run_rtri(RtriCase(duration_s=0.6))
    assert r.summary["status"] == "ok", r.summary["status_detail"]
    assert r.outcome.guidance.max_quotient.max() < 0.5 * r.outcome.guidance.nadal_limit


# --------------------------------------------------------------------------------- held-out: RK44 past its limit
@pytest.fixture(scope="module")
def rk44_stable_step_s():
    """The independent estimate of RK44's largest stable step on the vehicle's wheelsets (module docstring)."""
    from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
    from exudyn_wheelrail.contact import kernel as K
    from exudyn_wheelrail.multibody.connector import static_axle_offset_m
    pair = WheelRailPair("S1002", "UIC60", gauge_m=1.435, inclination="1/40", back_to_back_m=1.360, r0_m=0.46)
    q0 = (32000.0 / 4 + 2615.0 / 2 + 1813.0) * 9.81 / 2
    dz = static_axle_offset_m(pair, q0, 0.46)
    out = WheelsetContact(pair, 1, global_search=True).evaluate(np.array([[0.0, -0.46 + dz, 0.0]]))[0, 0]
    k = 1.5 * out[K.F_NORMAL_FORCE] / out[K.F_PENETRATION]
    gamma, e = out[K.F_CONTACT_ANGLE], abs(out[K.F_PW_Y])
    omega = math.sqrt(max(2 * k * math.cos(gamma) ** 2 / 1813.0, 2 * k * e * e / 1120.0))
    return 2.0 * math.sqrt(2.0) / omega


def test_rk44_past_its_stability_limit_ends_diverged_with_the_stable_step(tmp_path, rk44_stable_step_s):
    assert 1.5e-3 < rk44_stable_step_s < 3e-3
    dt = 1.2 * rk44_stable_step_s
    out = tmp_path / "rk44"
    r = run_cli("rtri", "--solver", "rk44", "--dt", f"{dt:.6g}", "--duration", "0.5", "--no-plots", "--out", out)
    assert r.returncode == 4, (r.stdout, r.stderr)
    s = json.loads((out / "summary.json").read_text())
    st = s["status_detail"]
    assert s["status"] == "diverged" and "stability limit" in st["detail"]
    h_hint = float(st["hint"].split("about ")[1].split(" s")[0])
    assert h_hint == pytest.approx(rk44_stable_step_s, rel=0.15)        # the hint is the limit, not the step taken
    assert "Error in Python USER FUNCTION" not in r.stdout + r.stderr
    assert "passage peaks" not in r.stdout and s["peaks"] == {} and s["peaks_passage"] == {}
    ts = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    assert np.all(np.abs(np.atleast_1d(ts["carbody_lateral_acceleration_rear_m_s2"])) < 10.0)
    assert s["simulated_time_s"] < 0.5                                    # stopped promptly


def test_rk44_below_its_stability_limit_runs_ok(rk44_stable_step_s):
    dt = 0.9 * rk44_stable_step_s
    r = run_rtri(RtriCase(solver="rk44", dt_s=dt, duration_s=0.3))
    assert r.summary["status"] == "ok", r.summary["status_detail"]
    assert r.summary["steps"] == math.ceil(0.3 / dt - 1e-9)


def test_rk44_past_the_creep_damping_limit_at_low_speed_is_flagged():
    """At small creepage a contact acts as a damper G a b C11 / V along x (Kalker's linear theory): on the spin of
    a wheelset (lever r_z: the contact point below the axle) the decay rate is at least the Rayleigh quotient
    Σ c11 r_z² / I_yy, ∝ 1/V.  Hand reference: that quotient from the patches of the initial state and Kalker's C11
    (Table E.3).  The monitor's rate (the largest eigenvalue of the wheelset's 6x6 creep damping) must be at least
    it, and RK44 at 1 ms must be flagged where σ h > 2.785 (36 km/h) and not at 250 km/h."""
    from exudyn_wheelrail.contact import layout as L
    from exudyn_wheelrail.creep.linear import kalker_coefficients
    from exudyn_wheelrail.simulation.solvers import RK44
    from exudyn_wheelrail.scenarios.scenario import build_scenario
    from exudyn_wheelrail.simulation import runner as R

    rates = {}
    for v_kmh in (36.0, 250.0):
        h = build_scenario(RtriCase(speed_km_h=v_kmh, solver="rk44", dt_s=1e-3, duration_s=0.02).scenario())
        c = h.contact
        q0, v0 = c.coordinates(h.mbs)
        c.forces(q0, v0, 0.0)                                    # the initial state's patches
        G, nu = float(c.cp[L.CP_G]), float(c.cp[L.CP_NU])
        body = [h.mbs.GetObject(i) for i in range(h.mbs.systemData.NumberOfObjects())
                if h.mbs.GetObject(i).get("objectType") == "RigidBody"
                and int(h.mbs.GetObject(i)["nodeNumber"]) == int(c.nodes_exu[0])][0]
        i_yy = float(body["inertia"][1])
        bound = 0.0
        for w in (0, 1):
            for r in c.results[w]:
                if r[L.RES_N] > 0:
                    c11 = kalker_coefficients(r[L.RES_A] / r[L.RES_B], nu)[0]
                    r_z = r[L.RES_P_Z] - (c.p_ref[0][2] + q0[2])
                    bound += G * r[L.RES_A] * r[L.RES_B] * c11 / abs(r[L.RES_V]) * r_z ** 2 / i_yy
        out = R.run(h.mbs, h.run, c, speed_m_s=h.speed_m_s, recorder=None, exu_settings=(h.settings, h.solver_type))
        sigma = out.creep_rate_1_s
        assert len(sigma) == 4 and bound > 0.0
        assert bound * (1 - 1e-9) <= sigma[0] < 10 * bound
        rates[v_kmh] = (sigma[0], out)
    (slow, out_slow), (fast, out_fast) = rates[36.0], rates[250.0]
    assert slow * 1e-3 > RK44.real_axis_limit > fast * 1e-3
    assert slow / fast == pytest.approx(250.0 / 36.0, rel=0.05)      # ∝ 1/V (the same patches at rest)
    warn = " ".join(out_slow.warnings)
    assert "creep damping" in warn and "stability limit" in warn
    assert not any("creep damping" in w for w in out_fast.warnings)


# --------------------------------------------------------------------------------------- held-out: Newmark 10 ms
def test_rtri_dt_10ms_simulates_2_5_s_and_is_never_ok(tmp_path):
    out = tmp_path / "dt10"
    r = run_cli("rtri", "--dt", "0.01", "--no-plots", "--out", out)
    s = json.loads((out / "summary.json").read_text())
    assert s["steps"] == 250 and s["duration_s"] == pytest.approx(2.5)
    assert s["status"] in ("diverged", "step_rejected"), s["status_detail"]
    assert r.returncode == S.EXIT_CODES[s["status"]]
    assert s["status_detail"]["hint"] and "dt" in s["status_detail"]["hint"]
    assert s["rows_recorded"] == 0 or s["rows_recorded"] == len(np.atleast_1d(
        np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)["time_s"]))


# ---------------------------------------------------------------------------------------------- the CLI's codes
def test_cli_run_exits_with_the_status_code(tmp_path):
    r = run_cli("run", EXAMPLES / "rtri_20m.toml", "--no-progress", "--set", "track.0.amplitude_m=0.1",
                "--set", "run.duration_s=0.3", "--set", "outputs.plots=false", "--out", tmp_path / "run")
    assert r.returncode == 3, (r.stdout, r.stderr)
    assert "status: derailed wheelset 0" in r.stdout
    with pytest.raises(ScenarioError, match="run.steps: unknown key"):
        apply_overrides(load_scenario(EXAMPLES / "rtri_20m.toml"), {"run.steps": 10})


def test_recorder_refuses_a_contact_with_another_number_of_wheelsets():
    """The wheel columns are filled by compiled code without bounds checks: a contact coupling more wheelsets than
    the recorded model must be refused before the run (it would write past the end of the row)."""
    from exudyn_wheelrail.contact.layout import N_RES
    from exudyn_wheelrail.simulation.recorder import _Wheels

    class FourWheelsets:                      # results of 4 wheelsets: (wheels, slots, fields)
        results = np.zeros((8, 3, N_RES))

    with pytest.raises(ValueError, match="expects 2 wheelsets but the contact couples 4"):
        _Wheels(FourWheelsets(), 2)


@pytest.mark.parametrize("argv, dt_s, steps", [
    (["--steps", "500"], 1e-3, 500),                       # the paper's dt: 500 steps = 0.5 s
    (["--steps", "300", "--dt", "0.002"], 2e-3, 300),       # steps of the given dt: 0.6 s
    (["--preset", "fast", "--steps", "100"], 1e-3, 100),    # the preset's dt
    (["--dt", "0.01"], 1e-2, 250),                          # without --steps the duration stays the paper's 2.5 s
])
def test_cli_steps_is_a_duration_in_steps_of_the_runs_dt(tmp_path, argv, dt_s, steps):
    """``--steps N`` (the older way of giving the length of an RTRI run) sets duration = N dt of the resolved time
    step; ``--dt`` alone never changes the duration."""
    from exudyn_wheelrail.cli import build_parser
    args = build_parser().parse_args(["rtri", "--out", str(tmp_path), *argv])
    args.check(args)
    run = args.settings[0]
    assert run.dt_s == pytest.approx(dt_s, rel=1e-15) and run.steps == steps
    assert run.duration_s == pytest.approx(steps * dt_s, rel=1e-15)


def test_cli_steps_and_duration_exclude_each_other(tmp_path):
    from exudyn_wheelrail.cli import main
    with pytest.raises(SystemExit) as e:
        main(["rtri", "--out", str(tmp_path), "--steps", "5", "--duration", "1"])
    assert e.value.code == 2
