"""Regression of the RTRI case against the stored reference ``tests/data/rtri_reference/`` (a short run: 20 m span,
250 km/h, Newmark, 1 ms, 500 steps, δ = 12 mm so that it covers a flange-region contact).  Regenerate it with
``python tests/data/regenerate_rtri_reference.py`` (the exact command is in that script) only after a change of
the results has been understood.

Tolerances (fail on drift):

* the peak |lateral contact force| of the leading right wheel, the peak car-body lateral acceleration and the peak
  lateral excursion of the leading wheelset within 1 %;
* RMS of the difference of each of these time series within 2 % of the reference peak;
* the flange-contact flag of the leading right wheel: the first step in contact within ±1 step, the number of steps
  in contact within ±2 per contact episode (each episode's start and end are threshold crossings; rounding or a
  different Newton stop may move either by one step).
"""
import csv
import json
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.scenarios.rtri import RtriCase, run_rtri

REFERENCE = Path(__file__).resolve().parent / "data" / "rtri_reference"
SERIES = ("lateral_contact_force_w1_right_N", "carbody_lateral_acceleration_rear_m_s2",
          "wheelset1_lateral_rel_track_m")


def read_reference():
    with open(REFERENCE / "timeseries.csv") as fh:
        rows = list(csv.reader(fh))
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, i] for i, name in enumerate(rows[0])}, json.loads((REFERENCE / "summary.json").read_text())


@pytest.fixture(scope="module")
def fresh_and_reference():
    ref_ts, ref = read_reference()
    assert ref["status"] == "ok"
    case = RtriCase(span_m=ref["span_m"], speed_km_h=ref["speed_km_h"], solver=ref["solver"]["name"],
                    dt_s=ref["dt_s"], duration_s=ref["steps"] * ref["dt_s"], creep_law=ref["creep_law"],
                    fastsim_grid=tuple(ref["fastsim_grid"]), deviation_amplitude_m=ref["deviation_amplitude_m"],
                    transition_length_m=ref["transition_length_m"])
    return run_rtri(case), ref_ts, ref


def test_reference_configuration_is_the_documented_one(fresh_and_reference):
    _, _, ref = fresh_and_reference
    assert (ref["span_m"], ref["speed_km_h"], ref["solver"]["name"], ref["dt_s"], ref["steps"]) == \
        (20.0, 250.0, "newmark", 0.001, 500)
    assert ref["deviation_amplitude_m"] == pytest.approx(0.012)
    assert ref["peaks"]["flange_contact_w1_right"]   # the reference covers a flange-region contact


def test_same_columns_and_times(fresh_and_reference):
    fresh, ref_ts, _ = fresh_and_reference
    assert fresh.summary["status"] == "ok"
    # every column of the reference, in its order (columns added since, e.g. the car body's vertical acceleration,
    # are new outputs, not changes)
    assert [c for c in fresh.timeseries if c in ref_ts] == list(ref_ts)
    np.testing.assert_allclose(fresh.timeseries["time_s"], ref_ts["time_s"], rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", SERIES)
def test_time_series_within_tolerance(fresh_and_reference, name):
    fresh, ref_ts, _ = fresh_and_reference
    new, old = fresh.timeseries[name], ref_ts[name]
    peak_old = np.max(np.abs(old))
    assert np.max(np.abs(new)) == pytest.approx(peak_old, rel=0.01), "peak drifted"
    rms = np.sqrt(np.mean((new - old) ** 2))
    assert rms <= 0.02 * peak_old, f"RMS difference {rms:.4g} > 2 % of the peak {peak_old:.4g}"


def test_flange_contact_unchanged(fresh_and_reference):
    fresh, ref_ts, _ = fresh_and_reference
    new = fresh.timeseries["flange_contact_w1_right"] > 0.5
    old = ref_ts["flange_contact_w1_right"] > 0.5
    episodes = int(np.count_nonzero(np.diff(old.astype(int)) == 1) + old[0])
    assert abs(int(new.sum()) - int(old.sum())) <= 2 * episodes
    assert new.any() and abs(int(np.argmax(new)) - int(np.argmax(old))) <= 1
