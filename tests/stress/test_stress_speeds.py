"""Stress (a): one wheelset and one bogie of Manchester vehicle 1 at 0 (standstill), 50, 200 and 400 km/h on a
straight track with a small irregularity (1 mm lateral, λ 20 m; 0.5 mm vertical, λ 7 m; faded in ahead of the
vehicle), RK44 at 0.5 ms, wheelset started 1 mm off centre.

Checked at every step (the monitor's evaluation of the state): finite results; every loaded contact's creep force
within Coulomb's bound |F_t| <= μ N (the creep laws saturate at μ N; 1 % tolerance: the interpolated table of
Kalker's theory overshoots by up to ~0.2 %); at standstill the creepage guard is active
(``CREEP_STANDSTILL``) and everything stays finite; the run completes with the lateral displacement relative to the
rails bounded below the flangeway clearance — or the monitor reports hunting (the bogie at 400 km/h, above this
model's critical speed)."""
from __future__ import annotations

import numpy as np
import pytest
from stress_models import build, finite_history, settings
from exudyn_wheelrail.contact.creepage import CREEP_STANDSTILL
from exudyn_wheelrail.multibody import SampledIrregularity
from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.simulation.runner import run_monitored

DT = 5e-4
T_END = 1.5
#: lateral displacement relative to the rails that a non-hunting run stays below [m] (S1002/UIC60 1:40 flange
#: contact begins at about 6.5-7 mm)
BOUND_M = 5e-3
#: relative tolerance of Coulomb's bound: the interpolated creep table overshoots mu N by up to ~0.2 % (reported)
COULOMB_TOL = 1e-2


def small_irregularity():
    s = np.arange(-10.0, 700.0, 0.05)
    u = np.clip((s - 3.0) / 5.0, 0.0, 1.0)
    fade = u * u * (3.0 - 2.0 * u)             # zero under the vehicle at t = 0, full from 8 m on
    return SampledIrregularity(s, 1e-3 * fade * np.sin(2 * np.pi * s / 20.0),
                               0.5e-3 * fade * np.sin(2 * np.pi * s / 7.0))


IRREGULARITY = small_irregularity()


@pytest.mark.parametrize("vehicle", ["single_wheelset", "single_bogie"])
@pytest.mark.parametrize("speed_km_h", [0.0, 50.0, 200.0, 400.0])
def test_speeds_give_finite_bounded_results_or_hunting(vehicle, speed_km_h):
    m = build(speed_km_h / 3.6, vehicle=vehicle, irregularity=IRREGULARITY, y0_m=1e-3)
    mu = float(m.contact.cp[C.CP_MU])
    violations = []
    standstill = []

    def after_check(mbs, t):
        r = m.contact.results
        loaded = (r[:, :, C.RES_STATUS] > 0) & (r[:, :, C.RES_N] > 0.0)
        rows = r[loaded]
        if not np.all(np.isfinite(rows)):
            violations.append((t, "non-finite results"))
        ft = np.hypot(rows[:, C.RES_FX], rows[:, C.RES_FY])
        if np.any(ft > mu * rows[:, C.RES_N] * (1 + COULOMB_TOL) + 1e-6):
            violations.append((t, "creep force above mu N", float(np.max(ft / rows[:, C.RES_N]))))
        standstill.append(bool(np.all(rows[:, C.RES_CREEP_STATUS].astype(int) & CREEP_STANDSTILL)))
        return True

    m.monitor.attach(m.mbs, user_function=after_check, rk44_dt_s=DT)
    status, t_end = run_monitored(m.mbs, settings(T_END, DT), "rk44", m.monitor)
    assert status.kind in ("completed", "hunting"), str(status)
    assert t_end == pytest.approx(T_END)
    assert not violations, violations[:5]
    assert finite_history(m.monitor)
    h = m.monitor.history()
    y = h["lateral_m"][:, 0::2]                 # right wheels: the wheelsets' lateral displacement rel. to the rails
    if speed_km_h == 0.0:
        assert all(standstill)                  # no rolling: every contact normalised by the guard speed
        assert np.max(np.abs(y)) <= 1e-3 + 1e-6   # nothing drives it at standstill
    if status.kind == "completed":
        assert np.max(np.abs(y)) < BOUND_M
    else:
        k = status.wheelset
        assert m.monitor.hunting[k] is not None and 0.0 < status.time_s < T_END
        assert "Hz" in status.detail
    assert not m.monitor.events_of("derailment") and not m.monitor.events_of("invalid_state")
