"""The EN 1991-2 dynamic check (``en1991-dynamic``, ``scenarios/en1991_dynamic.py``).

* The published rules, against numbers worked out by hand from the standard: Table 6.6's damping (ζ = ζ_20 +
  s (20 - L) below 20 m), Eq. (6.13)'s additional damping, EN 1990's modal cut-off max(30 Hz, 1.5 f1, f3) with
  f_n = n² f1, the speed grid of 6.4.6.2 (144 km/h to 1.2 V, steps ≤ 10 km/h, exact decimals, refined around the
  resonance speeds).
* The procedure against its parts: every row of the envelope is the single crossing of ``bridge-crossing``'s runner
  for that train, mass and speed (the same computation: bit-equality); the verdict, the governing case and the
  largest acceleration follow from the envelope and the limit.
* Faults: a run started again on the same folder computes only the crossings missing there (one deleted, one cut
  short), with the same envelope; bad bridge files end before any work with one line naming the file and key.
* The report: one self-contained HTML page with the verdict, the governing case and the figure embedded (a PNG).
"""
from __future__ import annotations

import base64
import csv
import json
import math
import re
from pathlib import Path

import pytest

from bridge_file_check import check_bridge_file

from exudyn_wheelrail.cli import main
from exudyn_wheelrail.scenarios import en1991_dynamic as E
from exudyn_wheelrail.scenarios.bridge_crossing_run import run_bridge_crossing
from exudyn_wheelrail.scenarios.sweep import SerialExecutor

BRIDGE = """
[bridge]
spans_m = [15.0]
EI_Nm2 = 1.0e10
mass_kg_per_m = {mass}
structure = "steel_composite"
track_form = "ballasted"
"""


@pytest.mark.parametrize("structure, L, percent", [
    ("steel_composite", 10.0, 1.75), ("steel_composite", 25.0, 0.5), ("prestressed_concrete", 20.0, 1.0),
    ("prestressed_concrete", 10.0, 1.7), ("reinforced_concrete", 5.0, 2.55), ("filler_beam", 40.0, 1.5)])
def test_damping_of_table_6_6(structure, L, percent):
    assert E.damping_ratio_table_6_6(structure, L) == pytest.approx(percent / 100, rel=1e-12)


def test_additional_damping_of_eq_6_13():
    # L = 10 m: (0.187 - 0.064) / (1 - 0.147 + 0.00931) = 0.123 / 0.86231 = 0.142640 %
    assert E.additional_damping_ratio(10.0) == pytest.approx(0.123 / 0.86231 / 100, rel=1e-9)
    assert E.additional_damping_ratio(30.0) == 0.0 and E.additional_damping_ratio(45.0) == 0.0


def _EI(L, m, f1):
    """EI of a simply supported span L [m] of m [kg/m] whose first frequency is f1: m (2 L² f1 / π)²."""
    return m * (2.0 * L * L * f1 / math.pi) ** 2


@pytest.mark.parametrize("f1, n", [(5.0, 3), (2.0, 4), (1.0, 6), (1.2, 5), (10.0, 3)])
def test_modes_up_to_the_first_at_or_above_the_en1990_cutoff(f1, n):
    # f_n = n² f1 up to the first >= max(30, 1.5 f1, 9 f1): f1 = 2 Hz -> 30 Hz -> n = 4 (32 Hz); f1 = 1.2 -> 5 (30)
    assert E.n_modes_to_cutoff([20.0], _EI(20.0, 1e4, f1), 1e4) == n


def test_a_chains_modes_reach_the_cutoff_on_every_span():
    # spans of 20 and 40 m of one section: f1 = 5 and 1.25 Hz, cut-off max(45, 30) = 45 Hz; the 40 m span needs
    # n² 1.25 >= 45: n = 6
    assert E.n_modes_to_cutoff([20.0, 40.0], _EI(20.0, 1e4, 5.0), 1e4) == 6


def test_the_speed_grid_of_6_4_6_2():
    grid = E.speed_grid_kmh(300.0, resonances_kmh=[250.0, 110.0])
    assert grid[0] == 144.0 and grid[-1] == 360.0                       # 40 m/s to 1.2 V
    plain = E.speed_grid_kmh(300.0)
    assert plain == [144.0] + [150.0 + 10.0 * k for k in range(22)]      # 144, 150, 160, ... 350, 360
    assert max(b - a for a, b in zip(plain, plain[1:])) <= 10.0
    assert all(round(v * 10) == v * 10 for v in grid)                    # exact decimals of 0.1 km/h
    assert {245.0, 247.5, 250.0, 252.5, 255.0} <= set(grid)             # refined around the resonance inside
    assert 110.0 not in grid                                             # below 144 km/h: not run
    with pytest.raises(ValueError, match="below 144"):
        E.speed_grid_kmh(100.0)


@pytest.fixture(scope="module")
def small_check(tmp_path_factory):
    d = tmp_path_factory.mktemp("en1991")
    f = d / "bridge.toml"
    f.write_text(BRIDGE.format(mass="[12000.0, 15000.0]"))
    check = E.DynamicCheck(bridge=E.read_bridge_file(f), max_line_speed_kmh=200.0, trains=("A1", "A3"),
                           speeds_kmh=(160.0, 200.0, 240.0))
    out = d / "out"
    summary = E.run_dynamic_check(check, out, executor=SerialExecutor(), progress=None)
    return check, out, summary


def test_every_row_is_the_single_crossing_and_the_verdict_follows(small_check):
    check, out, summary = small_check
    with open(out / "envelope.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 2 * 2 * 3 == summary["crossings"]
    for r in rows[::5]:
        case = check.crossing(r["train"], r["mass_bound"], float(r["speed_kmh"]))
        sc = run_bridge_crossing(case).summary["scalars"]
        assert float(r["max_deck_acceleration_m_s2"]) == sc["deck.en1990_peak_acceleration_m_s2"]
        assert float(r["max_deck_displacement_m"]) == sc["deck.max_mid_span_deflection_m"]
    # the check's own inputs: Table 6.6 at 15 m, f1 and modes of each bound
    assert summary["damping_ratio_used"] == pytest.approx(0.01 * (0.5 + 0.125 * 5.0), rel=1e-12)
    assert set(summary["modes"]) == {"lower", "upper"}
    acc = [float(r["max_deck_acceleration_m_s2"]) for r in rows]
    worst = rows[max(range(len(rows)), key=acc.__getitem__)]
    assert summary["max_deck_acceleration_m_s2"] == max(acc)
    assert summary["governing"] == {"train": worst["train"], "speed_kmh": float(worst["speed_kmh"]),
                                    "mass_bound": worst["mass_bound"]}
    assert summary["verdict"] == ("pass" if max(acc) <= 3.5 else "fail")
    assert json.loads((out / "summary.json").read_text())["verdict"] == summary["verdict"]


def _without_timing(path):
    with open(path, newline="") as fh:
        return [{k: v for k, v in r.items() if k != "solve_seconds"} for r in csv.DictReader(fh)]


def test_a_run_started_again_computes_only_what_is_missing(small_check):
    check, out, summary = small_check
    runs = sorted((out / "runs").glob("*.json"))
    assert len(runs) == summary["crossings"]
    envelope = _without_timing(out / "envelope.csv")
    runs[0].unlink()                                  # lost
    runs[1].write_text('{"train": "A1", "mass_')       # cut short by a kill
    lines = []
    again = E.run_dynamic_check(check, out, executor=SerialExecutor(), progress=lines.append)
    computed = [ln for ln in lines if re.match(r"\s+\[\d+/\d+\]", ln)]
    assert len(computed) == 2
    assert _without_timing(out / "envelope.csv") == envelope     # the same computations: the same numbers
    assert again["verdict"] == summary["verdict"]


def test_the_report_is_one_page_with_the_verdict_and_the_figure(small_check):
    _, out, summary = small_check
    page = (out / "report.html").read_text(encoding="utf-8")
    assert f"Verdict: {summary['verdict'].upper()}" in page
    assert summary["governing"]["train"] in page
    m = re.search(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', page)
    assert m and base64.b64decode(m.group(1))[:8] == b"\x89PNG\r\n\x1a\n"
    assert "EN 1991-2 6.4.6.2(1)" in page and "Table 6.6" in page
    assert not re.search(r'(src|href)="(?!data:)', page)          # nothing outside the page


def test_on_a_dask_client_the_check_equals_the_serial_one(small_check, tmp_path):
    distributed = pytest.importorskip("distributed")
    check, out, _ = small_check
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=2, dashboard_address=None) as client:
        E.run_dynamic_check(check, tmp_path / "dask", executor=client, progress=None)
    # each crossing is the same deterministic computation wherever it runs: bit-equality (timings left out)
    assert _without_timing(tmp_path / "dask" / "envelope.csv") == _without_timing(out / "envelope.csv")


def test_a_consist_file_runs_as_its_static_axle_loads(tmp_path):
    from exudyn_wheelrail.scenarios.bridge_crossing_loads import consist_axles
    consist = str(Path(__file__).resolve().parents[1] / "vehicles" / "trains" / "manchester_x2.toml")
    f = tmp_path / "bridge.toml"
    f.write_text(BRIDGE.format(mass="12000.0"))
    check = E.DynamicCheck(bridge=E.read_bridge_file(f), max_line_speed_kmh=200.0, trains=(consist,),
                           speeds_kmh=(180.0,))
    s = E.run_dynamic_check(check, tmp_path / "out", executor=SerialExecutor(), progress=None)
    case = check.crossing(consist, "nominal", 180.0)
    assert case.axles.as_dict() == consist_axles(consist).as_dict()
    expected = run_bridge_crossing(case).summary["scalars"]["deck.en1990_peak_acceleration_m_s2"]
    assert s["max_deck_acceleration_m_s2"] == expected and s["governing"]["train"] == consist


def test_a_changed_bridge_is_computed_again_not_taken_from_the_folder(small_check, tmp_path):
    check, out, summary = small_check
    stiffer = E.BridgeSpec(**{**check.bridge.__dict__, "EI_Nm2": 1.5 * check.bridge.EI_Nm2})
    other = E.DynamicCheck(bridge=stiffer, max_line_speed_kmh=200.0, trains=("A1",), speeds_kmh=(200.0,))
    lines = []
    again = E.run_dynamic_check(other, out, executor=SerialExecutor(), progress=lines.append)
    assert len([ln for ln in lines if re.match(r"\s+\[\d+/\d+\]", ln)]) == 2        # both bounds computed anew
    old = {(r["train"], r["mass_bound"]): r for r in csv.DictReader(open(out / "envelope.csv", newline=""))}
    assert again["modes"]["lower"]["f1_Hz"] != summary["modes"]["lower"]["f1_Hz"]
    assert len(old) == 2


def test_a_crossing_that_did_not_complete_fails_the_check_and_is_listed(small_check):
    check, _, _ = small_check
    env = [{"train": "A1", "mass_bound": "lower", "speed_kmh": 160.0, "status": "ok",
            "max_deck_acceleration_m_s2": 1.0},
           {"train": "A1", "mass_bound": "lower", "speed_kmh": 200.0, "status": "error: executor: its worker died"},
           {"train": "A1", "mass_bound": "upper", "speed_kmh": 200.0, "status": "ok",
            "max_deck_acceleration_m_s2": None}]
    s = E.check_summary(check, env)
    assert s["verdict"] == "fail" and "2 crossing(s) did not complete" in s["verdict_reason"]
    assert [r["speed_kmh"] for r in s["not_completed"]] == [200.0, 200.0]
    assert s["max_deck_acceleration_m_s2"] == 1.0          # below the limit, yet not a pass


def test_the_command_exits_with_the_crossings_status(tmp_path, capsys):
    f = tmp_path / "b.toml"
    f.write_text(BRIDGE.format(mass="12000.0"))
    code = main(["en1991-dynamic", "--bridge", str(f), "--max-line-speed-kmh", "200", "--trains", "A1",
                 "--speeds-kmh", "200", "--workers", "1", "--out", str(tmp_path / "o")])
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert code == 0 and s["crossings"] == 1 and not s["not_completed"]
    assert f"verdict: {s['verdict'].upper()}" in capsys.readouterr().out


@pytest.mark.parametrize("body, expected", [
    ("spans_m = [15.0]\nEI_Nm2 = 1e10\nmass_kg_per_m = 12000.0\n", "bridge.structure: missing"),
    ("spans_m = [15.0]\nEI_Nm2 = 1e10\nmass_kg_per_m = [15000.0, 12000.0]\nstructure = 'filler_beam'\n",
     "bridge.mass_kg_per_m"),
    ("spans_m = [15.0]\nEI_Nm2 = 1e10\nmass_kg_per_m = 12000.0\nstructure = 'timber'\n", "bridge.structure: 'timber'"),
    ("spans_m = [15.0]\nEI = 1e10\nmass_kg_per_m = 12000.0\nstructure = 'filler_beam'\n", "bridge.EI: unknown key"),
])
def test_a_bad_bridge_file_is_one_line_before_any_work(tmp_path, capsys, body, expected):
    code, err, f, out = check_bridge_file(tmp_path, capsys, body)
    assert code == 2 and err.count("\n") == 0 and expected in err and str(f) in err, err
    assert not (out / "runs").exists()


def test_on_a_terminal_the_crossings_are_a_bar_redrawn_in_place():
    import io

    from exudyn_wheelrail.cli.common import CountBar
    out = io.StringIO()
    bar = CountBar(out)
    bar("  2 of 6 crossings taken from DIR/runs")
    for k in range(3, 7):
        bar(f"  [{k}/6] A1 lower {140 + 10 * k:g} km/h: ok")
    text = out.getvalue()
    lines = text.split("\n")
    # the kept line as it is, then one line redrawn by carriage returns, ended at 6/6
    assert lines[0] == "  2 of 6 crossings taken from DIR/runs" and lines[-1] == ""
    redraws = lines[1].split("\r")[1:]
    assert len(redraws) == 4
    assert redraws[0].startswith("[" + "#" * 15 + "." * 15 + "] 3/6")
    assert redraws[-1].startswith("[" + "#" * 30 + "] 6/6") and "A1 lower 2" in redraws[-1]
