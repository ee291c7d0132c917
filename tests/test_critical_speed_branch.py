"""The unstable branch's bookkeeping in the default suite (exudyn_wheelrail/scenarios/critical_speed_branch.py and its
wiring into the critical-speed command), without runs: which speeds are tried, where each wheelset's windows start,
what the summary notes say, the bifurcation table's rows and figure, the command's option.  The branch itself against
the full model is in test_critical_speed_model.py (validation)."""
import csv
import math

import numpy as np
import pytest

from exudyn_wheelrail.cli import main
from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle
from exudyn_wheelrail.scenarios import critical_speed as cs
from exudyn_wheelrail.scenarios.critical_speed_branch import branch_speeds
from exudyn_wheelrail.scenarios.critical_speed_defaults import (BRANCH_POINTS, BUMP_LENGTH_M, BUMP_POSITION_M)
from exudyn_wheelrail.scenarios.critical_speed_nonlinear import disturbance_passed_m


def test_branch_speeds():
    """BRANCH_POINTS speeds strictly between the two critical speeds, evenly spaced; the range's end caps a linear
    critical speed above it (or missing); none without a nonlinear one below the top; no duplicates when the
    interval is narrow."""
    v = branch_speeds(170.0, 330.0, 400.0)
    assert len(v) == BRANCH_POINTS and 170.0 < v[0] and v[-1] < 330.0
    assert np.allclose(np.diff(v), (330.0 - 170.0) / (BRANCH_POINTS + 1), atol=0.1)
    assert max(branch_speeds(170.0, 450.0, 400.0)) < 400.0
    assert max(branch_speeds(170.0, None, 400.0)) < 400.0
    assert branch_speeds(None, 330.0, 400.0) == []
    assert branch_speeds(340.0, 330.0, 400.0) == []
    narrow = branch_speeds(200.0, 200.3, 400.0)
    assert len(narrow) == len(set(narrow)) and all(200.0 < x < 200.3 for x in narrow)


def test_windows_start_where_each_wheelset_has_passed_the_disturbance():
    """Front wheelset first: the bump's end; every other one later by its distance behind the front one."""
    x = load_vehicle("manchester_vehicle1").wheelset_x_m()
    start = disturbance_passed_m(x)
    end = BUMP_POSITION_M + BUMP_LENGTH_M
    assert start[0] == pytest.approx(end)
    assert start == pytest.approx([end + (x[0] - xj) for xj in x])
    assert all(b > a for a, b in zip(start, start[1:]))


def _case(**kw):
    return cs.CriticalSpeedCase("manchester_vehicle1", (100.0, 400.0), 1, **kw)


def test_branch_summary_notes():
    found = {250.0: {"speed_kmh": 250.0, "found": True, "amplitude_m": [1e-4, 2e-4], "stable_amplitude_m": [2e-3, 1e-3],
                     "depth_bracket_m": [1e-4, 1.07e-4], "window_m": [[22.0, 42.0], None], "note": None}}
    missing = {250.0: {"speed_kmh": 250.0, "found": False, "amplitude_m": [], "note": "a run ended step_rejected"}}
    rows, note = cs._branch_summary(_case(), {"critical_kmh": 170.0}, found)
    assert note is None and rows[0]["amplitude_m"] == [1e-4, 2e-4]
    assert "not found" in cs._branch_summary(_case(), {"critical_kmh": 170.0}, missing)[1]
    assert "not computed" in cs._branch_summary(_case(unstable_branch=False), {"critical_kmh": 170.0}, {})[1]
    assert "no nonlinear critical speed" in cs._branch_summary(_case(), {"critical_kmh": None}, {})[1]


def _bif_inputs():
    lam = np.array([-1.0 + 10j, -1.0 - 10j])
    point = {"eigenvalues": lam, "shapes": np.eye(2, dtype=complex), "labels": ["b y", "b yaw"],
             "lateral_share": np.ones(2), "candidate": np.array([True, False]), "residual_acceleration": 0.0}
    lin = {"points": {150.0: point, 250.0: point}}
    run = {"status": "ok", "amplitude_m": [1e-3, float("nan")], "persists": [True, True],
           "frequency_hz": [4.0, float("nan")]}
    nl = {"runs": {200.0: run}}
    return lin, nl


@pytest.mark.parametrize("branch", [{}, {210.0: {"found": True, "amplitude_m": [2e-4, float("nan")]}},
                                    {210.0: {"found": False, "amplitude_m": []}}])
def test_bifurcation_table_and_figure(tmp_path, branch):
    """The stable rows from the runs, the unstable rows from the found cycles (NaN amplitudes kept as NaN), the
    figure drawn with any of them."""
    lin, nl = _bif_inputs()
    summary = {"linear_critical_speed_kmh": 330.0, "nonlinear_critical_speed_kmh": 170.0}
    paths = cs._write(tmp_path, lin, nl, branch, summary)
    with open(paths["bifurcation"]) as fh:
        rows = list(csv.DictReader(fh))
    assert [r["branch"] for r in rows].count("stable") == 2
    unstable = [r for r in rows if r["branch"] == "unstable"]
    expected = branch.get(210.0, {})
    assert len(unstable) == (len(expected["amplitude_m"]) if expected.get("found") else 0)
    if unstable:
        assert float(unstable[0]["amplitude_m"]) == pytest.approx(2e-4) and math.isnan(float(unstable[1]["amplitude_m"]))
    assert (tmp_path / "bifurcation.png").stat().st_size > 0


def test_option_no_unstable_branch(monkeypatch, tmp_path):
    """--no-unstable-branch reaches the case; the default computes the branch."""
    seen = []

    def fake(case, out, progress=None):
        seen.append(case.unstable_branch)
        raise SystemExit(0)
    monkeypatch.setattr(cs, "run_critical_speed", fake)
    for extra, expected in (([], True), (["--no-unstable-branch"], False)):
        with pytest.raises(SystemExit):
            main(["critical-speed", "--vehicle", "manchester_vehicle1", "--out", str(tmp_path / "o"), *extra])
        assert seen[-1] is expected
