"""A bridge crossing as a scenario (``vehicle.load_model``, :mod:`exudyn_wheelrail.scenarios.spec_crossing`):

* ``run`` of the shipped crossing scenario writes the time series the ``bridge-crossing`` command writes for the
  same case, byte for byte, and the same summary (but its timings): the command fills the scenario and both run it
  through ``run_scenario`` (one code path; bit-equality between its runs);
* the normal form is idempotent and gives back the case it was made from (train from an HSLM name, an axle file or
  a consist; a chain of spans, lateral modes, sprung masses, an explicit step);
* bad input names the dotted key before any work.
"""
from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.cli import main as cli_main
from exudyn_wheelrail.scenarios.bridge_crossing_case import BridgeCrossing
from exudyn_wheelrail.scenarios.scenario import ScenarioError, load_scenario, validate_scenario
from exudyn_wheelrail.scenarios.spec_crossing import crossing_case, crossing_scenario, is_crossing
from exudyn_wheelrail.structures.load_models import hslm_a, read_axle_file

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "scenarios" / "crossing_hslm_a1_20m.toml"
CONSIST = ROOT / "vehicles" / "trains" / "manchester_x2.toml"
#: the summary's timings (wall-clock values, not results)
TIMINGS = ("solve_seconds", "build_seconds", "real_time_factor")


def _summary(path: Path) -> dict:
    s = json.loads(path.read_text())
    for k in TIMINGS:
        s.pop(k, None)
    return s


def test_run_of_the_scenario_writes_what_the_command_writes(tmp_path):
    command = ["bridge-crossing", "--span-m", "20", "--bridge-mass-kg-per-m", "15000", "--bridge-frequency-hz", "5",
               "--damping-ratio", "0.01", "--modes", "3", "--hslm", "A1", "--speed-kmh", "300", "--no-progress",
               "--out", str(tmp_path / "command")]
    assert cli_main(command) == 0
    assert cli_main(["run", str(EXAMPLE), "--no-progress", "--out", str(tmp_path / "scenario")]) == 0
    a, b = tmp_path / "command", tmp_path / "scenario"
    assert (a / "timeseries.csv").read_bytes() == (b / "timeseries.csv").read_bytes()
    assert _summary(a / "summary.json") == _summary(b / "summary.json")
    assert sorted(p.name for p in b.iterdir()) == ["summary.json", "timeseries.csv"]


def _axle_file(tmp_path) -> Path:
    path = tmp_path / "axles.csv"
    path.write_text("x_m,load_N\n0.0,170000\n2.5,170000\n17.5,170000\n20.0,170000\n")
    return path


def _cases(tmp_path):
    axles = _axle_file(tmp_path)
    deck = dict(span_m=20.0, mass_kg_m=15000.0, f1_Hz=5.0, damping_ratio=0.01, n_modes=3)
    yield BridgeCrossing(**deck, axles=hslm_a("A1"), speed_m_s=300 / 3.6), {"hslm": "a1"}
    yield (BridgeCrossing(**deck, axles=read_axle_file(axles), speed_m_s=50.0, spans_m=(20.0, 25.0, 20.0),
                          lateral_modes=2, lateral_f1_Hz=7.0, track_form="direct_fastening", free_vibration_s=0.5),
           {"axles": str(axles)})
    yield (BridgeCrossing(**deck, axles=hslm_a("A4"), speed_m_s=60.0 / 7.0, model="sprung-masses", sprung_frequency_Hz=1.2,
                          sprung_damping_ratio=0.3, dt_s=2e-4, solver="newmark"), {"hslm": "A4"})
    yield (BridgeCrossing(**deck, axles=None, speed_m_s=40.0, model="vehicles", train_file=str(CONSIST)),
           {"consist": str(CONSIST)})


def test_the_normal_form_gives_back_its_case_and_is_idempotent(tmp_path):
    for case, train in _cases(tmp_path):
        speed_km_h = case.speed_m_s * 3.6
        scn = validate_scenario(crossing_scenario(case, train, speed_km_h=speed_km_h))
        assert is_crossing(scn)
        assert validate_scenario(scn) == scn
        back = crossing_case(scn)
        speeds = ("speed_m_s", "speed_km_h")
        assert {k: v for k, v in back.as_dict().items() if k not in speeds} == \
            {k: v for k, v in case.as_dict().items() if k not in speeds}
        assert back.speed_m_s == speed_km_h / 3.6                    # the speed as the scenario gives it, in km/h
        assert json.loads(json.dumps(scn)) == scn                   # plain values


def _scenario(**changes) -> dict:
    scn = load_scenario(EXAMPLE)
    for dotted, value in changes.items():
        table, key = dotted.split("__")
        if value is None:
            scn[table].pop(key, None)
        else:
            scn.setdefault(table, {})[key] = value
    return scn


@pytest.mark.parametrize("changes, key", [
    ({"structure__modes": None}, "structure.modes: missing"),
    ({"structure__modes": 0}, "structure.modes"),
    ({"structure__damping_ratio": 2.0}, "structure.damping_ratio"),
    ({"structure__spans_m": [20.0, 0.5]}, "structure.spans_m.1"),
    ({"structure__elements_per_span": 40}, "structure.elements_per_span"),
    ({"vehicle__hslm": "B3"}, "vehicle.hslm"),
    ({"vehicle__hslm": None, "vehicle__axles": "no_such_file.csv"}, "vehicle.axles: file not found"),
    ({"vehicle__hslm": 1}, "vehicle.hslm: expected a string"),
    ({"vehicle__speed_km_h": 0.05}, "vehicle.speed_km_h"),
    ({"structure__damping_ratio": 2.0}, "a ratio, not a percentage"),
    ({"vehicle__load_model": "vehicles"}, "vehicle.load_model"),
    ({"vehicle__load_model": "rigid-loads"}, "vehicle.load_model"),
    ({"vehicle__sprung_frequency_Hz": -1.0}, "vehicle.sprung_frequency_Hz"),
    ({"run__dt_s": 1.0}, "run.dt_s"),
    ({"run__duration_s": 2.0}, "run.duration_s"),
    ({"outputs__plots": False}, "outputs"),
])
def test_bad_input_names_the_key(changes, key):
    with pytest.raises(ScenarioError, match=re.escape(key)) as err:
        validate_scenario(_scenario(**changes))
    assert str(err.value).count("<dict>") == 1                       # the source named once


def test_an_axle_file_error_names_the_key_the_file_and_the_line(tmp_path):
    bad = tmp_path / "axles.csv"
    bad.write_text("x_m,load_N\n0.0,170000\n-2.5,170000\n")
    with pytest.raises(ScenarioError, match=r"vehicle\.axles: .*axles\.csv:3: "):
        validate_scenario(_scenario(vehicle__hslm=None, vehicle__axles=str(bad)))


def _max_abs(ts, column):
    return float(np.max(np.abs(ts[column])))


def test_a_sweep_of_a_crossing_tabulates_the_crossings_results(tmp_path):
    """A scenario sweep over a crossing's damping at the first resonance speed (f1 d = 5 Hz x 18 m = 324 km/h): the
    resonant peak falls as the damping rises as the first mode's build-up does — after N load cycles (N = the
    train's length over its coach length d: 397.525 / 18 = 22.1 for HSLM-A1) a resonant mode's amplitude is
    proportional to (1 - exp(-2 pi zeta N)) / zeta, so the peaks' ratios at zeta = 0.005, 0.01, 0.02 are 1.334 and
    1.600; within 5 %, what the two non-resonant modes (their share does not grow with 1/zeta) and the axle groups'
    departure from one harmonic can move them.  A row's scalars are those of the same case run alone, and each is
    its time series' value (the peak of the recorded column; the EN 1990 peak over the check points with the modes
    to the cut-off against the limit)."""
    from exudyn_wheelrail.scenarios.bridge_crossing import run_bridge_crossing
    from exudyn_wheelrail.scenarios.sweep import CROSSING_PLOT_RESULT, SerialExecutor, sweep
    base = load_scenario(EXAMPLE)
    base["vehicle"]["speed_km_h"] = 324.0
    result = sweep(base, {"structure.damping_ratio": [0.005, 0.01, 0.02]}, executor=SerialExecutor(),
                   out_dir=tmp_path, write_cases=False, progress=None)
    t = result.table
    assert t["status"] == ["ok"] * 3
    peaks = t[CROSSING_PLOT_RESULT]
    assert peaks[0] > peaks[1] > peaks[2] > 0.0
    axles = hslm_a("A1")
    cycles = axles.x_m[-1] / axles.spacing_m

    def build_up(zeta):
        return (1.0 - np.exp(-2.0 * np.pi * zeta * cycles)) / zeta

    for k, (z1, z2) in enumerate(((0.005, 0.01), (0.01, 0.02))):
        assert peaks[k] / peaks[k + 1] == pytest.approx(build_up(z1) / build_up(z2), rel=0.05)
    alone = run_bridge_crossing(crossing_case(validate_scenario(result.scenarios[1])))
    row = {k: t[k][1] for k in alone.summary["scalars"]}
    assert row == alone.summary["scalars"]                   # one code path: equal
    ts = alone.timeseries
    assert row["max_abs_deck_midspan_acceleration_m_s2"] == _max_abs(ts, "deck_midspan_acceleration_m_s2")
    en1990 = _max_abs(ts, "deck_en1990_max_abs_acceleration_m_s2")
    assert row["deck.en1990_peak_acceleration_m_s2"] == en1990
    assert row["deck.en1990_passed"] is (en1990 <= 3.5)      # ballasted; 3 modes reach the 45 Hz cut-off
    w = _max_abs(ts, "deck_midspan_displacement_m")
    assert row["deck.max_mid_span_deflection_m"] == w
    assert row["deck.dynamic_amplification_mid_span"] == pytest.approx(
        w / _max_abs(ts, "deck_midspan_static_displacement_m"), rel=1e-12)
    assert (tmp_path / "sweep_plot.png").is_file()


def test_a_chains_scalars_are_the_largest_over_its_spans_and_a_failed_run_has_none():
    """Two spans (20 m then 30 m: the second f1 (2/3)², the more flexible): the deflection and the EN 1990 peak of the table are the largest
    over the spans' recorded columns (the first span's alone would understate a chain), no amplification (the
    quasi-static deflection is the first span's); a run that diverges (RK33 beyond its stability limit) has no
    scalars."""
    from exudyn_wheelrail.scenarios.bridge_crossing import run_bridge_crossing
    deck = dict(span_m=20.0, mass_kg_m=15000.0, f1_Hz=5.0, damping_ratio=0.01, n_modes=3, axles=hslm_a("A1"),
                speed_m_s=250 / 3.6, free_vibration_s=0.0)
    r = run_bridge_crossing(BridgeCrossing(**deck, spans_m=(20.0, 30.0)))
    sc, ts = r.summary["scalars"], r.timeseries
    w = [_max_abs(ts, f"deck_span{k}_midspan_displacement_m") for k in (1, 2)]
    a = [_max_abs(ts, f"deck_span{k}_en1990_max_abs_acceleration_m_s2") for k in (1, 2)]
    assert w[1] > 2 * w[0]                                    # the second span's governs
    assert sc["deck.max_mid_span_deflection_m"] == max(w) and sc["deck.en1990_peak_acceleration_m_s2"] == max(a)
    assert sc["deck.en1990_passed"] is r.summary["EN1990_A2_all_spans_passed"]
    assert "deck.dynamic_amplification_mid_span" not in sc
    bad = run_bridge_crossing(BridgeCrossing(**deck, solver="rk33", dt_s=0.009))
    assert bad.summary["status"] == "diverged" and bad.summary["scalars"] == {}


def test_the_command_checks_its_scenario_before_any_work_a_shipped_consist_too(tmp_path):
    """The command builds and validates the scenario it will run in its checks: for the vehicles of a shipped
    consist (a name, not a file) the scenario names the consist as the command got it."""
    from exudyn_wheelrail.cli import build_parser
    args = build_parser().parse_args(
        ["bridge-crossing", "--span-m", "20", "--bridge-mass-kg-per-m", "15000", "--bridge-frequency-hz", "5",
         "--damping-ratio", "0.01", "--modes", "3", "--model", "vehicles", "--train", "manchester_x2",
         "--speed-kmh", "120", "--out", str(tmp_path / "o")])
    args.check(args)
    assert args.scenario_spec["vehicle"]["consist"] == "manchester_x2"
    assert crossing_case(args.scenario_spec).as_dict() == args.crossing.as_dict()


def test_an_unusual_value_is_named_once(tmp_path, capsys):
    """A 3 m span (unusual, allowed): named once by the command (by its option) and once by run (by its key)."""
    assert cli_main(["bridge-crossing", "--span-m", "3", "--bridge-mass-kg-per-m", "15000", "--bridge-frequency-hz",
                     "20", "--damping-ratio", "0.01", "--modes", "1", "--hslm", "A1", "--speed-kmh", "100",
                     "--no-progress", "--out", str(tmp_path / "command")]) == 0
    err = capsys.readouterr().err
    assert err.count("unusual span length") == 1 and "--span-m" in err
    short = tmp_path / "short.toml"
    short.write_text(EXAMPLE.read_text().replace("spans_m = [20.0]", "spans_m = [3.0]").replace("f1_Hz = 5.0",
                                                                                                  "f1_Hz = 20.0"))
    assert cli_main(["run", str(short), "--no-progress", "--out", str(tmp_path / "scenario")]) == 0
    err = capsys.readouterr().err
    assert err.count("unusual span length") == 1 and "structure.spans_m.0" in err


def test_the_command_line_names_the_file_and_key(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(EXAMPLE.read_text().replace("modes = 3", "modes = 0"))
    assert cli_main(["run", str(bad), "--no-progress", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: ") and "bad.toml: structure.modes" in err[0]
