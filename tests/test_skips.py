"""Each thing the contact evaluation skips changes the results by less than a stated tolerance.

Runs the RTRI 20 m case at 250 km/h for 450 steps of 1 ms with RK44 (the leading bogie enters the span, the
lateral force builds up) with and without each skip, and compares the lateral contact force of wheelset 1's right
wheel (peak and RMS difference over the run, relative to the peak) and the car-body lateral acceleration.

* separation bound (flange regions not searched while far from the rail): against ``global_search=True``, which
  scans every region at every evaluation — the bound is a proof that no contact is skipped; the two runs differ
  only by Newton solutions reached from different starts (converged to 1e-11 m), which the dynamics carry along
  (stated: 1e-4 of the peak; measured 2e-5);
* precomputed geometry table instead of the online search: stated tolerance 3 % of the peak lateral force (peak
  and RMS difference) and 1 % of the peak car-body acceleration (measured over the full 2.5 s run: +1.2 % peak,
  1.7 % RMS; the table is an interpolation, see contact/geometry_table.py);
* bridge coupling only for wheelsets on the deck: tests/test_bridge_coupling.py checks that wheels off the deck
  see the rigid track bit for bit.
"""
import numpy as np
import pytest

from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.scenarios import build as scenario_build
from exudyn_wheelrail.scenarios.rtri import RtriCase, run_rtri

STEPS = 450


def _run(monkeypatch=None, **kw):
    r = run_rtri(RtriCase(solver="rk44", duration_s=STEPS * 1e-3, **kw))
    assert r.summary["status"] == "ok"
    return r


def _compare(a, b):
    Ya = a.timeseries["lateral_contact_force_w1_right_N"]
    Yb = b.timeseries["lateral_contact_force_w1_right_N"]
    Aa = a.timeseries["carbody_lateral_acceleration_rear_m_s2"]
    Ab = b.timeseries["carbody_lateral_acceleration_rear_m_s2"]
    peak = np.max(np.abs(Ya))
    return (abs(np.max(np.abs(Yb)) - peak) / peak, np.sqrt(np.mean((Ya - Yb) ** 2)) / peak,
            abs(np.max(np.abs(Ab)) - np.max(np.abs(Aa))) / np.max(np.abs(Aa)), peak)


@pytest.fixture(scope="module")
def online():
    return _run()


def test_separation_bound_skips_no_contact(online, monkeypatch):
    original = C.add_wheel_rail_contact

    def scanning(*args, **kw):
        kw["global_search"] = True
        return original(*args, **kw)

    monkeypatch.setattr(scenario_build, "add_wheel_rail_contact", scanning)      # where the scenario build calls it
    full = _run()
    sk = online.summary["skipped"]["flange_search_far_from_flange"]
    assert sk["fraction"] > 0.9                     # the skip is real in this scene ...
    assert full.summary["skipped"]["flange_search_far_from_flange"]["skipped"] == 0
    d_peak, d_rms, d_acc, peak = _compare(online, full)
    assert peak > 1e3
    assert d_peak < 1e-4 and d_rms < 1e-4 and d_acc < 1e-4     # ... and changes nothing (measured 2e-5)


def test_geometry_table_against_online_search(online):
    tab = _run(geometry="table")
    st = tab.summary["skipped"]["contact_search_by_geometry_table"]
    assert st["skipped"] == st["of_wheel_evaluations"] > 0
    d_peak, d_rms, d_acc, peak = _compare(online, tab)
    assert d_peak < 0.03
    assert d_rms < 0.03
    assert d_acc < 0.01
