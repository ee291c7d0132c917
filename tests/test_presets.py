"""Presets (simulation.presets, ``rtri --preset``): what each sets, explicit options override, the summary says so."""
import json

import pytest

from exudyn_wheelrail.cli import main
from exudyn_wheelrail.simulation.presets import PRESETS, TARGETS, apply_preset
from exudyn_wheelrail.simulation.settings import ContactSettings, RunSettings

BASE_RUN = RunSettings(solver="newmark", dt_s=1e-3, duration_s=2.5)
BASE_CONTACT = ContactSettings()


def test_presets_set_run_and_contact_settings_and_options_override():
    run, contact, rec = apply_preset("fast", BASE_RUN, BASE_CONTACT)
    assert contact.geometry == "table" and run.solver == PRESETS["fast"].run["solver"]
    assert run.duration_s == 2.5                      # a preset does not touch the duration: steps follow dt
    assert run.steps == round(2.5 / run.dt_s)
    assert rec["set"] == {"run": PRESETS["fast"].run, "contact": PRESETS["fast"].contact}
    assert rec["targets"] == {"min_real_time_factor": TARGETS["fast"][0],
                              "max_peak_lateral_force_error": TARGETS["fast"][1]}
    run, contact, rec = apply_preset("accurate", BASE_RUN, BASE_CONTACT, run_options={"dt_s": 0.5e-3,
                                                                                     "duration_s": 0.01})
    assert run.dt_s == 0.5e-3 and run.steps == 20
    assert rec["overridden_by_options"] == {"dt_s": 0.5e-3}
    # no preset: the front end's settings, explicit options on top
    run, contact, rec = apply_preset(None, BASE_RUN, BASE_CONTACT, run_options={"solver": "rk44", "dt_s": None})
    assert rec is None and run.solver == "rk44" and run.dt_s == 1e-3 and contact == BASE_CONTACT
    with pytest.raises(ValueError, match="preset"):
        apply_preset("fastest", BASE_RUN, BASE_CONTACT)
    # the accurate preset resolves time finer than the default, the fast one skips the search
    assert PRESETS["accurate"].run["dt_s"] < PRESETS["default"].run["dt_s"]
    assert PRESETS["fast"].contact["geometry"] == "table" and PRESETS["default"].contact["geometry"] == "online"


def test_rtri_cli_preset_recorded_in_summary(tmp_path):
    rc = main(["rtri", "--preset", "fast", "--duration", "0.04", "--no-plots", "--out", str(tmp_path)])
    assert rc == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["preset"]["name"] == "fast" and s["preset"]["set"]["contact"]["geometry"] == "table"
    assert s["solver"]["name"] == PRESETS["fast"].run["solver"] and s["dt_s"] == PRESETS["fast"].run["dt_s"]
    assert s["steps"] == 40
    assert s["skipped"]["contact_search_by_geometry_table"]["skipped"] > 0
