"""The connector's two call paths (:mod:`exudyn_wheelrail.multibody.direct_call`).

* Which path ran: on the compiled path Exudyn calls the native function directly — the function counts its calls
  and, separately, the calls that came through Python (pybind11's dispatcher); a run on the compiled path has calls
  and none through Python.  The native module is built at install wherever a C++ compiler is (CI has one), so its
  absence there is a failure, not a skip.
* Both paths run the same compiled evaluation (``forces_step``) on the same numbers Exudyn hands over, so a run gives
  the same results bit for bit on either (the same code path in the sense of the arithmetic: one machine code).
* A bad state met on the compiled path (no Python to raise in) ends the solve, and the run's status names the
  wheelset and the time as on the Python path.
* Slots: released with their connector, so any number of models can be built one after the other; when all are
  taken, or numba's native convention is not the assumed one, the slot function (or the connector) falls back to
  the Python path with the same numbers.
"""
from __future__ import annotations

import gc
import shutil

import numpy as np
import pytest

from exudyn_wheelrail.multibody import direct_call as D
from exudyn_wheelrail.multibody.connector import ContactStateError
from exudyn_wheelrail.scenarios.rtri import RtriCase
from exudyn_wheelrail.scenarios.scenario import build_scenario
from exudyn_wheelrail.simulation import runner as R
from exudyn_wheelrail.simulation.exudyn_settings import simulation_settings
from exudyn_wheelrail.simulation.monitor_records import contact_state_error
from exudyn_wheelrail.simulation.presets import apply_preset

DURATION_S = 0.2


def _build(duration_s=DURATION_S, record=True):
    base = RtriCase(span_m=20.0)
    run, contact, _ = apply_preset("default", base.run, base.contact)
    return build_scenario(RtriCase(span_m=20.0, run=run, contact=contact, duration_s=duration_s,
                                   record=record).scenario())


def _run(h):
    out = R.run(h.mbs, h.run, h.contact, speed_m_s=h.speed_m_s, recorder=h.recorder,
                exu_settings=(h.settings, h.solver_type))
    return out, (h.recorder.table() if h.recorder is not None else None)


@pytest.fixture(scope="module")
def python_run():
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv(D.CALL_PATH_ENV, "python")
        h = _build()
    assert h.contact.call_path == "python"
    out, arrays = _run(h)
    assert out.stop.kind == "completed", str(out.stop)
    return h, arrays


def test_the_native_module_is_built_where_a_compiler_is():
    if shutil.which("c++") is None and shutil.which("g++") is None:
        pytest.skip("no C++ compiler on this machine: the install leaves the native module out (Python path)")
    assert D.native_available(), "a C++ compiler is here, yet exudyn_wheelrail.native.direct_force was not built"


@pytest.mark.skipif(not D.native_available(), reason="the native module is not built (no C++ compiler at install)")
def test_the_compiled_path_runs_without_python_and_gives_the_same_numbers(python_run):
    h_py, ref = python_run
    h = _build()
    c = h.contact
    assert c.call_path == "compiled"
    out, arrays = _run(h)
    assert out.stop.kind == "completed", str(out.stop)
    calls, through_python = c.compiled_path_counts()
    steps = h.run.steps
    assert calls >= 4 * steps and through_python == 0          # RK44: 4 stages a step, all called directly
    assert h_py.contact.compiled_path_counts() == (0, 0)
    # same compiled evaluation, same inputs: bit-equality of every recorded column and of the evaluations' count;
    # on the compiled path the states after the first are checked in the force call (simulation/watch.py) on the
    # first stage's own evaluation, on the Python path the pre-step function's evaluation is kept for that stage
    assert out.watched_states == steps - 1
    assert c.n_calls == h_py.contact.n_calls
    assert (c.n_reused, h_py.contact.n_reused) == (1, steps)
    assert set(arrays) == set(ref)
    for name in ref:
        np.testing.assert_array_equal(arrays[name], ref[name], err_msg=name)


@pytest.mark.skipif(not D.native_available(), reason="the native module is not built (no C++ compiler at install)")
def test_a_bad_state_on_the_compiled_path_ends_with_the_contact_state_error():
    h = _build(duration_s=0.01, record=False)
    c, mbs = h.contact, h.mbs
    assert c.call_path == "compiled"
    node = c.nodes_exu[1]
    q0 = np.array(mbs.GetNodeParameter(node, "initialCoordinates"))
    q0[2] = np.nan
    mbs.SetNodeParameter(node, "initialCoordinates", q0.tolist())
    mbs.Assemble()
    with pytest.raises(Exception) as info:              # unwatched: Exudyn meets it in its first force call
        mbs.SolveDynamic(h.settings, solverType=h.solver_type)
    assert D.NATIVE_STATE_ERROR_MARK in str(info.value)
    err = contact_state_error(info.value)
    assert isinstance(err, ContactStateError)
    assert err.wheelset == 1 and err.time_s == 0.0
    assert f"(node {node})" in str(err)
    assert contact_state_error(info.value) is None     # the record is taken once


@pytest.mark.skipif(not D.native_available(), reason="the native module is not built (no C++ compiler at install)")
def test_slots_are_released_with_their_connector_and_the_python_path_takes_over_when_none_is_free():
    h = _build(duration_s=0.01, record=False)
    c = h.contact
    n = c.n_coordinates

    def direct():
        return D.DirectCall(c._call, n, c._f, c._compiled_forces_step, c.forces, c._state_error)
    for _ in range(2 * D.SLOTS):                 # made and dropped one after the other: never run out
        d = direct()
        assert d.available
        del d
    held = []
    try:
        while True:                                      # every free slot taken
            d = direct()
            if not d.available:
                break
            held.append(d)
        assert len(held) < D.SLOTS
        with pytest.warns(UserWarning, match="every compiled call slot is taken"):
            h2 = _build(duration_s=0.01, record=False)
        assert h2.contact.call_path == "python"          # none free: the connector's Python path
        out, _ = _run(h2)
        assert out.stop.kind == "completed", str(out.stop)
    finally:
        del held
        gc.collect()
    assert direct().available


@pytest.mark.skipif(not D.native_available(), reason="the native module is not built (no C++ compiler at install)")
def test_an_unknown_native_convention_leaves_the_slot_on_the_python_path(python_run, monkeypatch):
    _, ref = python_run
    monkeypatch.setattr(D, "NATIVE_STEP_TYPE", D.NATIVE_STEP_TYPE.replace("double, i8*)", "float, i8*)"))
    h = _build()
    c = h.contact
    assert c.call_path == "python"
    out, arrays = _run(h)
    assert out.stop.kind == "completed", str(out.stop)
    calls, through_python = c.compiled_path_counts()
    assert calls > 0 and through_python == calls         # the slot's function called the Python path every time
    for name in ref:
        np.testing.assert_array_equal(arrays[name], ref[name], err_msg=name)


@pytest.mark.skipif(not D.native_available(), reason="the native module is not built (no C++ compiler at install)")
def test_the_model_keeps_its_connector_and_its_slot_while_the_caller_drops_them():
    """The slot holds no reference to its connector: the model does (``mbs.variables``).  Without it, a connector
    built without a Jacobian user function (nothing else of Exudyn's holds it) would be collected, its slot given
    to the next connector, and the first model would run on the second one's data."""
    import exudyn as exu
    import weakref

    from exudyn_wheelrail.contact.pair import WheelRailPair
    from exudyn_wheelrail.multibody import build_vehicle
    from exudyn_wheelrail.multibody.connector import add_wheel_rail_contact, place_on_rails

    def one_model():
        sc = exu.SystemContainer()
        mbs = sc.AddSystem()
        pair = WheelRailPair()
        model = build_vehicle(mbs, "single_wheelset", speed_m_s=30.0)
        place_on_rails(mbs, model, pair)
        contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=30.0, jacobian=None)
        mbs.Assemble()
        return sc, mbs, weakref.ref(contact), contact._direct.slot
    sc1, mbs1, ref1, slot1 = one_model()
    gc.collect()
    assert ref1() is not None                            # alive: the model holds it
    sc2, mbs2, ref2, slot2 = one_model()
    assert slot2 != slot1
    mbs1.SolveDynamic(simulation_settings(0.01, 1e-3), solverType=exu.DynamicSolverType.RK44)
    assert ref1().n_calls >= 40 and ref2().n_calls == 0  # the first model ran on its own connector

