"""The run monitor's per-state checks on set poses (no solve): lift-off with its gap, the derailment definition
against S1002's nominal flange height (28 mm, EN 13715) and the lateral position of the UIC60 1:40 crown, the wall
clock limit and the option checks."""
from __future__ import annotations

import numpy as np
import pytest
from stress_models import build

from exudyn_wheelrail.simulation.monitor import RunMonitor
from exudyn_wheelrail.simulation.monitor_records import Status

FLANGE_HEIGHT_M = 0.028          # S1002, EN 13715


def _posed(dy=0.0, lift=0.0):
    m = build(100 / 3.6)
    node = m.model.wheelsets[0].node
    q0 = np.array(m.mbs.GetNodeParameter(node, "initialCoordinates"))
    q0[1] += dy
    q0[2] -= lift                  # z down: lift = up
    m.mbs.SetNodeParameter(node, "initialCoordinates", q0.tolist())
    m.mbs.Assemble()
    return m


def test_centred_wheelset_gives_no_event():
    m = _posed()
    assert m.monitor.check(m.mbs, 0.0) is None
    assert m.monitor.events == []
    assert all(w.max_normal_force_N > 50e3 for w in m.monitor.wheels)


def test_lifted_wheelset_is_lifted_off_with_its_gap():
    m = _posed(lift=0.010)
    assert m.monitor.check(m.mbs, 0.0) is None
    assert {(e.kind, e.side) for e in m.monitor.events} == {("lift_off", "right"), ("lift_off", "left")}
    h = m.monitor.history()
    for i, w in enumerate(m.monitor.wheels):
        assert len(w.lift_offs) == 1 and w.lift_offs[0].end_s is None
        # the gap is the smallest wheel-rail distance: brute force over the placed profile curves
        c_y, c_z, roll = h["lateral_m"][0, i], h["vertical_m"][0, i], h["roll_rad"][0, i]
        assert w.max_gap_m == pytest.approx(_smallest_distance(m.contact.pair, c_y, c_z, roll), abs=2e-5)
        assert 0.005 < w.max_gap_m < 0.010          # the flange's diagonal clearance to the gauge corner


def _smallest_distance(pair, c_y, c_z, roll):
    from scipy.spatial import cKDTree
    rail = pair.rail_side.position(np.linspace(pair.rail_side.s_min, pair.rail_side.s_max, 20001))
    tree = cKDTree(rail)
    best = np.inf
    for curve in (pair.tread_side, pair.flange_side):
        p = curve.position(np.linspace(curve.s_min, curve.s_max, 20001))
        c, s = np.cos(roll), np.sin(roll)
        placed = np.column_stack([c_y + c * p[:, 0] - s * p[:, 1], c_z + s * p[:, 0] + c * p[:, 1]])
        best = min(best, float(tree.query(placed)[0].min()))
    return best


@pytest.mark.parametrize("lift, derailed", [(FLANGE_HEIGHT_M - 1e-3, False), (FLANGE_HEIGHT_M + 1e-3, True)])
def test_derailment_when_the_flange_tip_is_lifted_above_the_rail_top(lift, derailed):
    m = _posed(lift=lift)
    st = m.monitor.check(m.mbs, 0.25)
    if derailed:
        assert st is not None and st.kind == "derailment" and st.time_s == 0.25 and st.wheelset == 0
        assert "above the rail top" in st.detail
    else:
        assert st is None


def test_derailment_when_the_flange_tip_has_passed_the_rail_crown():
    m = _posed(dy=0.070, lift=0.035)
    assert m.monitor.derail_lateral_m == pytest.approx(0.0655, abs=1e-3)   # crown 43 mm outside the gauge point
    st = m.monitor.check(m.mbs, 0.0)
    assert st.kind == "derailment" and (st.wheelset, st.side) == (0, "right")
    assert "beyond the rail crown" in st.detail


def test_time_limit_and_options():
    m = _posed()
    mon = RunMonitor(m.contact, time_limit_s=1e-9)
    mon.attach(m.mbs)
    st = mon.check(m.mbs, 0.0)
    assert st.kind == "time_limit" and not st.completed
    for bad in (dict(stop_on=("magic",)), dict(invalid_penetration_m=-1.0), dict(hunting_cycles=0),
                dict(large_lateral_force_N=0.0), dict(time_limit_s=0.0), dict(max_speed_m_s=float("nan"))):
        with pytest.raises(ValueError):
            RunMonitor(m.contact, **bad)
    assert "derailment wheelset 1 left at t = 0.5 s: x" == str(Status("derailment", 0.5, 1, "left", "x"))
