"""Watching a run costs no extra contact evaluation and changes no number.

The run monitor evaluates the contact at the state an explicit step starts from (the pre-step function); the first
stage of that step evaluates the contact at exactly that state again.  The connector keeps the monitor's evaluation
for that call (``WheelRailContact.evaluate_state``).  References, independent of the code under test:

* counting: RK44 evaluates the right-hand side 4 times per step (Kutta's classical scheme), and the monitor once
  per state it checks; with the reuse the contact is *computed* 4 times per step, once more at the start (the
  runner's stability estimate at t0 and the final state's check are outside the steps: counted by hand below);
* identity: the same model solved by Exudyn without any pre-step function (no monitor, no recorder) — the
  watched run must give the same wheelset coordinates bit for bit, since the kept evaluation is the one the
  first stage would compute from the same warm start.
"""
import numpy as np
import pytest

from exudyn_wheelrail.scenarios.rtri import RtriCase
from exudyn_wheelrail.scenarios.scenario import build_scenario
from exudyn_wheelrail.simulation import runner as R
from exudyn_wheelrail.simulation.presets import apply_preset

DURATION_S = 0.1        # 100 RK44 steps of 1 ms: past the start, wheels rolling on the irregular track


def _built():
    base = RtriCase(span_m=20.0)
    run, contact, _ = apply_preset("default", base.run, base.contact)        # RK44, 1 ms
    h = build_scenario(RtriCase(span_m=20.0, run=run, contact=contact, duration_s=DURATION_S,
                                record=True).scenario())
    h.contact.warm_up(h.mbs, jacobian=False)
    return h


def _wheelset_coordinates(h):
    q, v = h.contact.coordinates(h.mbs)
    return np.concatenate([q, v])


@pytest.mark.parametrize("in_call", [False, True])
def test_watched_run_reuses_the_monitor_evaluation_and_equals_the_unwatched_solve(in_call):
    watched = _built()
    c = watched.contact
    out = R.run(watched.mbs, watched.run, c, speed_m_s=watched.speed_m_s, recorder=watched.recorder,
                exu_settings=(watched.settings, watched.solver_type), watch=in_call)
    assert out.status.kind == "ok"
    steps = round(DURATION_S / watched.run.dt_s)
    if in_call and c.call_path == "compiled":
        # the states after the first are checked in the force call on the first stage's own evaluation
        # (simulation/watch.py): only the first state's evaluation is kept for its stage
        assert out.watched_states == steps - 1
        assert c.n_reused == 1
        # computed: 4 stages per step minus the reused one, the first and the final state's checks, and the
        # runner's contact-frequency estimate at t0
        assert c.n_calls == (4 * steps - 1) + 2 + 1
    else:
        assert out.watched_states == 0
        # every step's first stage took the monitor's evaluation of its start state
        assert c.n_reused == steps
        # computed: 4 stages per step minus the reused one, one monitor check per step plus the final state's
        # check, and the runner's contact-frequency estimate at t0
        assert c.n_calls == 3 * steps + (steps + 1) + 1

    unwatched = _built()
    unwatched.mbs.SolveDynamic(unwatched.settings, solverType=unwatched.solver_type)
    assert unwatched.contact.n_reused == 0
    # the reused evaluation is the plain computation bit for bit, the solver the same: bit-equality
    np.testing.assert_array_equal(_wheelset_coordinates(watched), _wheelset_coordinates(unwatched))


def test_a_kept_evaluation_is_discarded_by_any_other_call():
    h = _built()
    c = h.contact
    q, v = c.coordinates(h.mbs)
    c.evaluate_state(q, v, 0.0)
    f_kept = c.forces(q, v, 0.0).copy()
    assert c.n_reused == 1
    f_kept = c.evaluate_state(q, v, 0.0).copy()    # from the warm start the first evaluation left
    q2 = q.copy()
    q2[1] += 1e-4                                   # another lateral position of wheelset 0
    warm = c.save_warm_start()
    f_other = c.forces(q2, v, 0.0).copy()
    # another state: forces differ by far more than rounding
    assert c.n_reused == 1 and not np.array_equal(f_other, f_kept)
    c.restore_warm_start(warm)                      # the search starts where the kept evaluation started
    calls = c.n_calls
    f_again = c.forces(q, v, 0.0)                   # computed again, not taken from the discarded evaluation
    assert c.n_calls == calls + 1
    assert c.n_reused == 1
    np.testing.assert_array_equal(f_again, f_kept)  # same warm start, same state, same code: bit-equality
