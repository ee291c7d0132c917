"""Stress (e) large lateral irregularity and (f) forced flange climb to derailment (RK44, 0.25 ms), with the run
monitor's derailment definition (``exudyn_wheelrail/simulation/monitor.py``) and a time limit on every run.

(e) A 20 mm lateral sine of 3 m wavelength (faded in over one wavelength) at 100 km/h, one wheelset and one bogie:
    either the run completes (possibly flagged as hunting: the forced lateral oscillation exceeds 3 mm) or it ends
    with a derailment status naming time, wheelset and wheel — preceded by flange impacts — never with NaN or an
    invalid state.
(f) A wheelset without lateral guidance pushed by a lateral force at rail level (ramped to 150 kN in 0.1 s, Y/Q
    = 2.75, twice Nadal's limit 1.34 of S1002's 70° flank with μ = 0.3): the right wheel climbs its flange — the
    contact passes the flank's steepest part (flange-climb event ``beyond_flank``), the wheelset rises and rolls —
    until the flange tip has lifted above the rail top: ``derailment`` of wheelset 0, right wheel, with its time;
    and an extreme lateral track step (100 mm over 0.5 m at 100 km/h) that throws the wheelset off: a
    ``derailment`` status too."""
from __future__ import annotations

import math

import numpy as np
import pytest
from stress_models import build, finite_history, run, vehicle_data

from exudyn_wheelrail.multibody import SampledIrregularity

TIME_LIMIT_S = 60.0          # the monitor's wall-clock limit; run() adds a hard limit of 120 s


def _lateral(s, y):
    return SampledIrregularity(s, y, 0.0 * s)


def large_sine(amplitude_m=0.02, wavelength_m=3.0, s0_m=2.0):
    s = np.arange(-5.0, 150.0, 0.02)
    u = np.clip((s - s0_m) / wavelength_m, 0.0, 1.0)
    return _lateral(s, amplitude_m * u * u * (3 - 2 * u) * np.sin(2 * np.pi * (s - s0_m) / wavelength_m))


def lateral_step(step_m, s0_m, length_m):
    s = np.arange(-5.0, 60.0, 0.02)
    u = np.clip((s - s0_m) / length_m, 0.0, 1.0)
    return _lateral(s, step_m * u * u * (3 - 2 * u))


@pytest.mark.parametrize("vehicle", ["single_wheelset", "single_bogie"])
def test_large_lateral_irregularity_runs_or_reports(vehicle):
    m = build(100 / 3.6, vehicle=vehicle, irregularity=large_sine(), monitor_options=dict(time_limit_s=TIME_LIMIT_S))
    status, t_end = run(m, 1.0, 2.5e-4)
    assert status.kind in ("completed", "hunting", "derailment"), str(status)
    assert finite_history(m.monitor)
    assert not m.monitor.events_of("invalid_state")
    assert max(w.max_contact_angle_rad for w in m.monitor.wheels) > 1.0          # flange impacts happened
    if status.kind == "derailment":
        assert status.wheelset is not None and status.side in ("right", "left")
        assert 0.0 < status.time_s <= t_end < 1.0
        assert any(e.time_s <= status.time_s for e in m.monitor.events_of("flange_climb"))
    else:
        assert t_end == pytest.approx(1.0)
        h = m.monitor.history()
        assert np.max(np.abs(h["lateral_m"])) < m.monitor.derail_lateral_m


def test_forced_flange_climb_ends_in_derailment_of_the_climbing_wheel():
    F = 150e3
    free = vehicle_data("single_wheelset", primary={"ky_N_per_m": 0.0, "cy_N_s_per_m": 0.0})
    m = build(50 / 3.6, vehicle=free, lateral_force=lambda t: F * min(max((t - 0.01) / 0.1, 0.0), 1.0),
              force_height_m=0.46, monitor_options=dict(time_limit_s=TIME_LIMIT_S))
    assert F / 54.5e3 > 2 * m.monitor.nadal_limit
    status, t_end = run(m, 1.0, 2.5e-4)
    assert status.kind == "derailment", str(status)
    assert (status.wheelset, status.side) == (0, "right")
    assert 0.1 < status.time_s < 0.5 and t_end == pytest.approx(status.time_s + 2.5e-4)
    assert "flange" in status.detail
    assert finite_history(m.monitor)
    right = m.monitor.wheels[0]
    climbs = [c for c in right.flange_climbs if c.start_s < status.time_s]
    assert any("beyond_flank" in c.reasons for c in climbs)
    h = m.monitor.history()
    # at the end the wheel has climbed: lifted by about the flange height, moved towards the field side
    assert h["vertical_m"][-1, 0] < h["vertical_m"][0, 0] - 0.010
    assert h["lateral_m"][-1, 0] > 0.015
    assert not m.monitor.events_of("invalid_state")


def test_extreme_lateral_track_step_derails():
    m = build(100 / 3.6, irregularity=lateral_step(0.1, 3.0, 0.5), monitor_options=dict(time_limit_s=TIME_LIMIT_S))
    status, t_end = run(m, 1.0, 2.5e-4)
    assert status.kind == "derailment", str(status)
    assert status.wheelset == 0 and status.side in ("right", "left")
    assert 3.0 / (100 / 3.6) < status.time_s < 0.5                    # after the step reaches the wheelset
    assert finite_history(m.monitor)
    assert math.isfinite(max(w.max_normal_force_N for w in m.monitor.wheels))
