"""The per-step shortcuts of a watched run change no number.

* The evaluation the run monitor keeps for an explicit step's first stage (``WheelRailContact.evaluate_state``) stays
  in place instead of being copied: the reference is the plain computation from the same warm start — forces,
  results and the warm start it leaves must be those bit for bit, and while the evaluation is kept the warm start
  the connector reports is the one it started from.
* The wheelset poses the monitor and the recorder read from the connector's arrays (``rail_pose_arrays``, no copy)
  against the connector's own ``wheelset_rail_pose`` (the right wheels' rows plus the half gauge).
* The car-body points a scenario records through Exudyn's sensors stored in memory (filled once, after the solve)
  against the same probe reading the body's outputs at every recorded state in the same run.
"""
import numpy as np
import pytest

from exudyn_wheelrail.simulation import monitor_core as MC
from exudyn_wheelrail.multibody.connector import ContactStateError
from exudyn_wheelrail.scenarios.rtri import RtriCase
from exudyn_wheelrail.scenarios.scenario import build_scenario
from exudyn_wheelrail.simulation.presets import apply_preset


@pytest.fixture(scope="module")
def built():
    base = RtriCase(span_m=20.0)
    run, contact, _ = apply_preset("default", base.run, base.contact)
    h = build_scenario(RtriCase(span_m=20.0, run=run, contact=contact, duration_s=0.01, record=True).scenario())
    h.contact.warm_up(h.mbs, jacobian=False)
    return h


def _moved_state(h):
    """A state off the initial one (wheelset 0 shifted and yawed, wheelset 2 rolled), so that the search moves."""
    q, v = h.contact.coordinates(h.mbs)
    q = q.copy()
    q[1] += 1.5e-3
    q[5] += 2e-4
    q[6 * 2 + 3] += 1e-4
    v = v.copy()
    v[1] += 0.01
    return q, v


def test_a_kept_evaluation_is_the_plain_computation(built):
    c = built.contact
    q, v = _moved_state(built)
    t = 0.0123
    warm0 = c.save_warm_start()
    # reference: the plain computation from warm0
    f_ref = c.forces(q, v, t).copy()
    res_ref = c.results.copy()
    warm_ref = c.save_warm_start()
    c.restore_warm_start(warm0)
    calls, reused = c.n_calls, c.n_reused
    c.evaluate_state(q, v, t)
    np.testing.assert_array_equal(c.save_warm_start(), warm0)      # kept: the warm start it started from (a copy)
    f = c.forces(q.copy(), v.copy(), t)                              # equal bytes, other arrays: taken
    assert (c.n_calls, c.n_reused) == (calls + 1, reused + 1)
    # same code path (the same compiled evaluation from the same warm start and state): bit-equality
    np.testing.assert_array_equal(f, f_ref)
    np.testing.assert_array_equal(c.results, res_ref)
    np.testing.assert_array_equal(c.save_warm_start(), warm_ref)
    # not taken by a call at another time: computed from warm0 again
    c.restore_warm_start(warm0)
    c.evaluate_state(q, v, t)
    f_later = c.forces(q, v, t + 1e-3).copy()
    c.restore_warm_start(warm0)
    np.testing.assert_array_equal(f_later, c.forces(q, v, t + 1e-3))   # same code path, same inputs: bit-equality
    c.restore_warm_start(warm0)


def test_a_failed_evaluation_keeps_nothing_and_leaves_the_warm_start(built):
    c = built.contact
    q, v = _moved_state(built)
    warm0 = c.save_warm_start()
    bad = q.copy()
    bad[6] = np.nan                                                    # wheelset 1
    with pytest.raises(ContactStateError):
        c.evaluate_state(bad, v, 0.0)
    np.testing.assert_array_equal(c.save_warm_start(), warm0)          # left untouched: bit-equality
    calls = c.n_calls
    c.forces(q, v, 0.0)
    assert c.n_calls == calls + 1                                      # computed: nothing was kept
    c.restore_warm_start(warm0)


def test_pose_readers_equal_the_connector_pose(built):
    c = built.contact
    q, v = _moved_state(built)
    warm0 = c.save_warm_start()
    c.forces(q, v, 0.0)
    pose = c.wheelset_rail_pose()
    out = np.full_like(pose, np.nan)
    MC.rail_poses(*c.rail_pose_arrays(), out)                          # the monitor's
    # copies and one IEEE addition c_y + half gauge of the same two doubles (correctly rounded on any CPU): bit-equality
    np.testing.assert_array_equal(out, pose)
    lateral = next(p for p in built.recorder.probes if type(p).__name__ == "_WheelsetLateral")
    row = np.full(len(lateral.columns), np.nan)
    lateral.fill(built.mbs, 0.0, row)                                  # the recorder's
    np.testing.assert_array_equal(row, pose[:, 0])                     # the same addition: bit-equality
    assert abs(pose[0, 0] - pose[1, 0]) > 1e-4                         # the state moved wheelset 0 only
    c.restore_warm_start(warm0)


def test_car_body_points_from_sensors_are_the_per_state_outputs():
    import exudyn as exu

    from exudyn_wheelrail.simulation.recorder import Recorder, _CarBodyPoints
    from exudyn_wheelrail.scenarios.run import run_model
    base = RtriCase(span_m=20.0)
    run, contact, _ = apply_preset("default", base.run, base.contact)
    h = build_scenario(RtriCase(span_m=20.0, run=run, contact=contact, duration_s=0.06, record=True).scenario())
    stored = [p for p in h.recorder.probes if isinstance(p, _CarBodyPoints)]
    assert len(stored) == 1 and stored[0].sensors is not None
    stored = stored[0]
    cb = h.model.car_body
    points = [(f"p{i}", np.asarray(loc) + cb.p_cg_in_frame) for i, loc in enumerate(stored.local)]
    reference = _CarBodyPoints(h.model, points)           # no mbs: reads the outputs at every recorded state
    assert reference.sensors is None
    h.recorder = rec = Recorder(h.recorder.probes + [reference], n_rows_hint=8)
    # the car body rolling and yawing from the start, so that its rotation matrix is far from symmetric (a
    # transposed rotation would otherwise go unnoticed in the accelerometer columns)
    sd = h.mbs.systemData
    initial = exu.ConfigurationType.Initial
    v0 = np.array(sd.GetODE2Coordinates_t(configuration=initial))
    i0 = h.mbs.GetNodeODE2Index(cb.node)
    v0[i0 + 3] += 0.05                                      # roll rate [rad/s]
    v0[i0 + 5] += 0.02                                      # yaw rate
    sd.SetODE2Coordinates_t(v0, configuration=initial)
    outcome = run_model(h, progress=False)
    assert outcome.status.kind == "ok"
    data = rec.data[:rec.n]
    assert rec.n == h.run.steps + 1
    sl_stored, sl_ref = rec._slices[-2], rec._slices[-1]
    assert sl_stored.stop - sl_stored.start == 6 * len(points)
    assert np.isfinite(data[:, sl_ref]).all()
    stored_cols, ref_cols = data[:, sl_stored].reshape(rec.n, -1, 6), data[:, sl_ref].reshape(rec.n, -1, 6)
    # accelerations and displacements: the same Exudyn outputs, stored by the sensors or read per state (bit-equality)
    np.testing.assert_array_equal(stored_cols[:, :, [0, 1, 4, 5]], ref_cols[:, :, [0, 1, 4, 5]])
    # accelerometer f_j = sum_i R_ij (a - g)_i: written out term by term, or NumPy's R.T @ (a - g) (SIMD/BLAS order,
    # maybe fused): two orders of a 3-term dot product, |difference| <= 3 eps sum_i |R_ij (a - g)_i|
    rot = h.mbs.GetSensorStoredData(stored.sensors[1])
    idx = np.searchsorted(rot[:, 0], data[:, 0] - 1e-9)
    np.testing.assert_allclose(rot[idx, 0], data[:, 0], rtol=0, atol=1e-9)       # the states the columns are of
    R = rot[idx, 1:10].reshape(-1, 3, 3)
    eps = np.finfo(float).eps
    for i, (s_acc, _) in enumerate(stored.sensors[0]):
        v = h.mbs.GetSensorStoredData(s_acc)[idx, 1:4] - stored.gravity
        bound = 3 * eps * np.einsum("mij,mi->mj", np.abs(R), np.abs(v))[:, 1:]       # (m, 2): lateral, vertical
        # (a bound per element: assert_allclose takes only a scalar atol on NumPy 2)
        diff = np.abs(stored_cols[:, i, 2:4] - ref_cols[:, i, 2:4])
        assert np.all(diff <= bound), (i, diff.max(), diff[diff > bound], bound[diff > bound])   # per element
    assert np.ptp(data[:, sl_ref][:, 0]) > 0.0              # the run moves the car body: the columns are not constant
    R = h.mbs.GetSensorStoredData(stored.sensors[1])[-1, 1:10].reshape(3, 3)
    assert abs(R[1, 2] - R[2, 1]) > 1e-3 and abs(R[0, 1] - R[1, 0]) > 1e-4     # rolled and yawed: R != R^T
    # a state the sensors did not store (off the step grid) is an error naming the setting, not a NaN
    with pytest.raises(RuntimeError, match="sensorsWritePeriod"):
        stored.fill_rows(np.array([0.5 * float(h.run.dt_s)]), np.zeros((1, 6 * len(points))))
