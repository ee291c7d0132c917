"""The run's per-state work in the compiled force call (:mod:`exudyn_wheelrail.simulation.watch`).

The reference is the pre-step function's path (``solve(..., watch=False)``): the same compiled checks on the same
contact evaluation, so every result must be equal bit for bit — the recorded table, the monitor's history, its
events and status, the flange-climb window's maxima, the number of checked states, the end time — also when a
state raises events, when the monitor stops the run and when the flange-climb window does (the stopping state is
then not recorded and the window's maxima are those before it, as on the pre-step path; the solve ends one step
later).  Which path ran is
proved by ``RunOutcome.watched_states`` (every state after the first) and by the connector's counts.
"""
from __future__ import annotations

import numpy as np
import pytest

import subprocess
import sys
from pathlib import Path

from exudyn_wheelrail.multibody import direct_call as D
from exudyn_wheelrail.scenarios.bridge_crossing import BridgeCrossing
from exudyn_wheelrail.scenarios.build import build_crossing
from exudyn_wheelrail.scenarios.rtri import RtriCase
from exudyn_wheelrail.scenarios.scenario import build_scenario
from exudyn_wheelrail.simulation import runner as R
from exudyn_wheelrail.simulation import watch as W
from exudyn_wheelrail.simulation.guidance import FlangeClimbCheck
from exudyn_wheelrail.simulation.monitor import RunMonitor
from exudyn_wheelrail.simulation.presets import apply_preset

TRAINS = Path(__file__).resolve().parents[1] / "vehicles" / "trains"

pytestmark = pytest.mark.skipif(not D.native_available(),
                                reason="the native module is not built (no C++ compiler at install)")


def _build(duration_s, record=True):
    base = RtriCase(span_m=20.0)
    run, contact, _ = apply_preset("default", base.run, base.contact)
    return build_scenario(RtriCase(span_m=20.0, run=run, contact=contact, duration_s=duration_s,
                                   record=record).scenario())


def _solve(duration_s, watch, monitor_kw=None, nadal=None, record=True):
    h = _build(duration_s, record)
    assert h.contact.call_path == "compiled"
    monitor = RunMonitor(h.contact, **(monitor_kw or {}))
    guidance = FlangeClimbCheck(len(h.contact.nodes_exu), h.speed_m_s,
                                monitor.nadal_limit if nadal is None else nadal)
    out = R.solve(h.mbs, h.settings, h.solver_type, monitor, dt_s=h.run.dt_s, solver=h.run.solver, guidance=guidance,
                  recorder=h.recorder, grid_check=True, watch=watch)
    return h, out


def _same_run(duration_s, **kw):
    """Both paths; asserts bit-equality of everything the run reports; returns the watched run's outcome."""
    runs = [_solve(duration_s, watch, **kw) for watch in (True, False)]
    (h, out), (h_ref, ref) = runs
    assert str(out.stop) == str(ref.stop)
    # a stop is found by the pre-step function after the step that checked the state: one step later
    stopped = ref.t_end_s < ref.t_goal_s - 0.5 * ref.dt_s
    assert out.t_end_s == pytest.approx(ref.t_end_s + (ref.dt_s if stopped else 0.0), abs=1e-9 * ref.dt_s)
    assert [str(e) for e in out.monitor.events] == [str(e) for e in ref.monitor.events]
    assert out.monitor.n_checks == ref.monitor.n_checks
    assert out.monitor.t_last == ref.monitor.t_last
    hist, hist_ref = out.monitor.history(), ref.monitor.history()
    assert hist.keys() == hist_ref.keys()
    for k in hist_ref:
        np.testing.assert_array_equal(hist[k], hist_ref[k], err_msg=k)
    np.testing.assert_array_equal(out.guidance.max_quotient, ref.guidance.max_quotient)
    if h.recorder is not None:
        table, table_ref = h.recorder.table(), h_ref.recorder.table()
        assert table.keys() == table_ref.keys()
        for k in table_ref:
            np.testing.assert_array_equal(table[k], table_ref[k], err_msg=k)
    assert ref.watched_states == 0
    assert out.monitor.wheels[0].max_normal_force_N == ref.monitor.wheels[0].max_normal_force_N
    return out, ref


def test_the_watch_gives_the_pre_step_functions_numbers_and_checks_every_state_after_the_first():
    out, ref = _same_run(0.3)
    steps = int(round(0.3 / 1e-3))
    assert out.stop.kind == "completed"
    assert out.watched_states == steps - 1          # the first state and the final one: the Python path
    assert out.monitor.n_checks == steps + 1


def test_events_on_the_way_are_those_of_the_pre_step_function():
    # hunting at 1 mm over 1 cycle: reported early, does not stop; the lift-off and flange intervals as they come
    out, _ = _same_run(0.6, monitor_kw=dict(hunting_amplitude_m=1e-3, hunting_cycles=1))
    assert out.stop.kind == "hunting"
    assert out.watched_states > 0


def test_a_stop_by_the_monitor_in_the_watch_ends_as_on_the_pre_step_path():
    out, ref = _same_run(0.6, monitor_kw=dict(stop_on=("derailment", "invalid_state", "hunting"),
                                              hunting_amplitude_m=1e-3, hunting_cycles=1))
    assert out.stop.kind == "hunting" and out.t_end_s < 0.6
    assert out.t_end_s == pytest.approx(out.stop.time_s + 2e-3, abs=1e-9)   # Exudyn completes the step after


def test_a_stop_by_the_flange_climb_window_in_the_watch_ends_as_on_the_pre_step_path():
    # Nadal's limit set below any quotient: the window stops the run once 2 m are run (0.0288 s at 250 km/h)
    out, _ = _same_run(0.1, nadal=1e-6)
    assert out.stop.kind == "derailment" and "flange climb" in out.stop.detail
    assert 0.028 < out.stop.time_s < 0.032


@pytest.mark.parametrize("deck", [{}, dict(spans_m=(20.0, 20.0), lateral_modes=2, lateral_f1_Hz=7.0)],
                         ids=["one-span", "two-spans-lateral"])
def test_a_bridge_crossing_is_watched_with_its_deck_columns_and_gives_the_pre_step_numbers(deck):
    """A structure under the rails (the deck's modes, their coordinates the connector's last) and the deck's
    columns filled from the modal state and the connector's modal forces — one span; a chain of two with lateral
    modes (every span's and the lateral columns) —: the same table, history and status as the pre-step function's,
    bit for bit."""
    case = BridgeCrossing(span_m=20.0, mass_kg_m=15e3, f1_Hz=5.0, damping_ratio=0.01, n_modes=3, axles=None,
                          speed_m_s=300 / 3.6, model="vehicles", train_file=str(TRAINS / "manchester_x2.toml"),
                          **deck)
    runs = []
    for watch in (True, False):
        h = build_crossing(case)
        h.contact.warm_up(h.mbs, jacobian=False)
        runs.append((h, R.run(h.mbs, h.run, h.contact, speed_m_s=h.speed_m_s, recorder=h.recorder,
                              exu_settings=(h.settings, h.solver_type), watch=watch)))
    (h, out), (h_ref, ref) = runs
    assert out.stop.kind == ref.stop.kind == "completed"
    assert out.watched_states == h.run.steps - 1 and ref.watched_states == 0
    assert out.monitor.n_checks == ref.monitor.n_checks
    hist, hist_ref = out.monitor.history(), ref.monitor.history()
    for k in hist_ref:
        np.testing.assert_array_equal(hist[k], hist_ref[k], err_msg=k)
    table, table_ref = h.recorder.table(), h_ref.recorder.table()
    assert table.keys() == table_ref.keys()
    for k in table_ref:
        np.testing.assert_array_equal(table[k], table_ref[k], err_msg=k)
    columns = [k for k in table if k.startswith("deck_")]
    assert len(columns) >= (8 if not deck else 8 + 2 + 2 * 5)
    assert np.max(np.abs(table["deck_midspan_displacement_m"])) > 1e-4
    if deck:
        assert np.max(np.abs(table["deck_span2_midspan_displacement_m"])) > 1e-4


def test_runs_the_watch_cannot_take_are_checked_by_the_pre_step_function():
    h = _build(0.02, record=False)
    c = h.contact
    m = RunMonitor(c)
    assert W.unwatchable(contact=c, monitor=m, solver_explicit=True) is None
    assert "implicit" in W.unwatchable(contact=c, monitor=m, solver_explicit=False)
    assert "user function" in W.unwatchable(contact=c, monitor=m, solver_explicit=True, user_function=print)
    assert "wall-clock" in W.unwatchable(contact=c, monitor=RunMonitor(c, time_limit_s=10.0), solver_explicit=True)
    seen = []
    out = R.run(h.mbs, h.run, c, speed_m_s=h.speed_m_s, exu_settings=(h.settings, h.solver_type),
                user_function=lambda mbs, t: seen.append(t) or True)
    assert out.stop.kind == "completed"
    assert out.watched_states == 0 and len(seen) == 20


def test_the_grid_index_takes_the_step_grid_within_its_tolerance():
    st = np.zeros(W.N_W)
    st[W.W_T0], st[W.W_DT] = 0.5, 1e-3
    assert W._grid_index(st, 0.5) == 0
    assert W._grid_index(st, 0.5 + 7 * 1e-3) == 7
    assert W._grid_index(st, 0.5 + 7.5e-3) == -1                    # an RK stage between grid points
    assert W._grid_index(st, 0.5 + (7 + 0.5 * W.GRID_TOLERANCE) * 1e-3) == 7
    assert W._grid_index(st, 0.5 + (7 + 2.0 * W.GRID_TOLERANCE) * 1e-3) == -1


_ONE_CHECK = """
import sys
sys.path.insert(0, {tests!r})
import test_watch as T
from exudyn_wheelrail.simulation import monitor_core as MC
out = T._solve(0.02, True)[1]
print(out.watched_states, len(MC.monitor_state.overloads))
"""


def test_the_watch_and_the_pre_step_path_share_one_compiled_check():
    """The monitor's check is compiled for the argument types both paths pass (the deck shapes as the contact's
    read-only view): in a fresh process, a watched run (the monitor's own first call, then the watch's calls) has
    one specialization of it (each costs seconds of a first run's compilation)."""
    code = _ONE_CHECK.format(tests=str(Path(__file__).resolve().parent))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    watched, specializations = map(int, done.stdout.split()[-2:])
    assert watched > 0 and specializations == 1
