"""Stress (b): RK44 time steps up to and beyond the explicit stability limit of the wheel–rail contact.

Reference: RK44 is stable for an undamped oscillator while ω h <= 2√2 (its stability region on the imaginary
axis).  The stiffest mode of a wheelset on its two Hertz contacts is the bounce (or roll) on the linearised normal
stiffness k = dN/dδ = 1.5 N0/δ0 of each wheel (Hertz, N ∝ δ^1.5; N0, δ0 the static load and approach of the
centred wheelset from the kernel):  ω² = max(2 k cos²γ / m, 2 k e² / I_xx), e the lateral distance of the contact
points from the axle centre — computed here, independently of the monitor's 6x6 estimate.

Below the limit the runs complete; well beyond it every run ends with a clear status — the monitor's
``invalid_state`` naming the exceeded limit, with time and wheelset, one step after the detected state (returning
False from Exudyn's pre-step function lets it finish the step it is taking; two steps when the compiled force call
checked the state, ``simulation/watch.py``) — and never with NaN; a monitor that
does not stop still never reports such a run as completed (the first invalid event, or the ContactStateError of
the non-finite state, with its time and wheelset)."""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
import pytest
from stress_models import PAIR, build, finite_history, run, settings

from exudyn_wheelrail.contact import WheelsetContact
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.simulation.solvers import RK44

MASS_KG = 1813.0
I_XX_KG_M2 = 1120.0
SPEED = 200 / 3.6
T_END = 0.5


@pytest.fixture(scope="module")
def h_limit():
    m = build(SPEED)
    kc = WheelsetContact(PAIR, 1, global_search=True)
    out = kc.evaluate(np.array([[0.0, -PAIR.r0_m + m.dz, 0.0]]))
    o = out[0, 0]
    k = 1.5 * o[K.F_NORMAL_FORCE] / o[K.F_PENETRATION]
    gamma = o[K.F_CONTACT_ANGLE]
    e = abs(o[K.F_PW_Y])
    omega = math.sqrt(max(2 * k * math.cos(gamma) ** 2 / MASS_KG, 2 * k * e * e / I_XX_KG_M2))
    h = RK44.imaginary_axis_limit / omega
    assert 1.5e-3 < h < 3e-3          # ~2.3 ms for this wheelset
    return h


@pytest.mark.parametrize("fraction", [0.4, 0.8])
def test_below_the_rk44_limit_the_run_completes(h_limit, fraction):
    m = build(SPEED, y0_m=1e-3)
    status, t_end = run(m, T_END, fraction * h_limit)
    assert status.kind == "completed", str(status)
    assert t_end == pytest.approx(T_END)
    assert finite_history(m.monitor)
    assert max(m.monitor.max_omega_h) < RK44.imaginary_axis_limit * 1.2          # the monitor's own estimate agrees
    assert not m.monitor.events_of("invalid_state")


@pytest.mark.parametrize("factor", [1.3, 2.0, 4.0, 8.0])
def test_beyond_the_rk44_limit_the_run_ends_with_a_clear_status(h_limit, factor):
    dt = factor * h_limit
    m = build(SPEED, y0_m=1e-3)
    status, t_end = run(m, T_END, dt)
    assert status.kind == "invalid_state", str(status)
    assert status.wheelset == 0 and status.time_s is not None and math.isfinite(status.time_s)
    assert "stability limit" in status.detail
    assert t_end < T_END
    n = int(round(T_END / dt))
    # stopped after the step being taken; the compiled call's watch (simulation/watch.py) finds it one step later
    steps_after = 2 if m.monitor.contact.call_path == "compiled" else 1
    assert t_end - status.time_s == pytest.approx(steps_after * T_END / n, rel=1e-6)
    assert finite_history(m.monitor)
    # the monitor's linearised estimate brackets the reference limit
    est = m.monitor.stability_exceeded
    assert est is not None and est.time_s <= status.time_s


@pytest.mark.parametrize("factor", [1.3, 4.0])
def test_a_monitor_that_does_not_stop_still_reports_the_divergence(h_limit, factor):
    dt = factor * h_limit
    m = build(SPEED, y0_m=1e-3, monitor_options=dict(stop_on=()))
    status, t_end = run(m, 2.0, dt)
    assert not status.completed, str(status)
    assert status.kind == "invalid_state" and status.wheelset == 0, str(status)
    assert math.isfinite(status.time_s) and status.time_s <= t_end


def test_a_non_finite_state_ends_with_thecontact_state_error():
    m = build(SPEED)
    node = m.model.wheelsets[0].node
    q0 = np.array(m.mbs.GetNodeParameter(node, "initialCoordinates"))
    q0[1] = np.nan
    m.mbs.SetNodeParameter(node, "initialCoordinates", q0.tolist())
    m.mbs.Assemble()
    status, t_end = run(m, 0.01, 1e-3)
    assert status.kind == "invalid_state" and status.wheelset == 0, str(status)
    assert "ContactStateError" in status.detail and status.time_s == pytest.approx(0.0, abs=1.1e-3)


def test_returning_false_from_the_pre_step_function_stops_exudyn_after_that_step():
    """The property run_monitored relies on (Exudyn 1.13.6): the solve ends one step after the refused state."""
    m = build(SPEED)
    calls = []

    def pre(mbs, t):
        calls.append(t)
        return t < 0.0105

    m.mbs.SetPreStepUserFunction(pre)
    ok = m.mbs.SolveDynamic(settings(0.1, 1e-3), solverType=exu.DynamicSolverType.RK44)
    assert ok
    assert m.mbs.systemData.GetTime() == pytest.approx(0.011)
    assert calls[-1] == pytest.approx(0.011) and len(calls) == 11
