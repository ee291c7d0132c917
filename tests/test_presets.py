"""Presets (scenarios.presets, ``rtri --preset``): what each sets, explicit options override, the summary says so."""
import json

import pytest

from exudyn_wheelrail.cli import main
from exudyn_wheelrail.scenarios.presets import PRESET_DURATION_S, PRESETS, TARGETS, resolve


def test_presets_resolve_and_override():
    st, rec = resolve("fast")
    assert st["geometry"] == "table" and st["solver"] == PRESETS["fast"].solver
    assert st["steps"] == round(PRESET_DURATION_S / st["dt_s"])
    assert rec["targets"] == {"min_real_time_factor": TARGETS["fast"][0],
                              "max_peak_lateral_force_error": TARGETS["fast"][1]}
    st, rec = resolve("accurate", dt_s=0.5e-3, steps=10)
    assert st["dt_s"] == 0.5e-3 and st["steps"] == 10
    assert rec["overridden_by_options"] == {"dt_s": 0.5e-3}
    # no preset: the paper's settings, explicit options on top
    st, rec = resolve(None, solver="rk44", paper_defaults=dict(solver="newmark", dt_s=1e-3, geometry="online",
                                                               creep_law="table"))
    assert rec is None and st["solver"] == "rk44" and st["dt_s"] == 1e-3
    with pytest.raises(ValueError, match="preset"):
        resolve("fastest")
    # the accurate preset resolves time finer than the default, the fast one skips the search
    assert PRESETS["accurate"].dt_s < PRESETS["default"].dt_s
    assert PRESETS["fast"].geometry == "table" and PRESETS["default"].geometry == "online"


def test_rtri_cli_preset_recorded_in_summary(tmp_path):
    rc = main(["rtri", "--preset", "fast", "--steps", "40", "--no-plots", "--out", str(tmp_path)])
    assert rc == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["preset"]["name"] == "fast" and s["preset"]["set"]["geometry"] == "table"
    assert s["solver"]["name"] == PRESETS["fast"].solver and s["dt_s"] == PRESETS["fast"].dt_s
    assert s["skipped"]["contact_search_by_geometry_table"]["skipped"] > 0
