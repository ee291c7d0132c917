"""The moving-window flexible track (exudyn_wheelrail/track/flexible_window.py): the shift of a static field against
the full finite-element solution, Exudyn's continuation from a shifted state against the exact solution, a vehicle
run on the window against a fixed segment that carries the whole run, and bad input."""
from __future__ import annotations

import math

import numpy as np
import pytest

from exudyn_wheelrail.track.flexible import FlexibleTrackModel, add_flexible_track
from exudyn_wheelrail.track.flexible_parameters import TrackFileError, TrackParameters
from exudyn_wheelrail.track.flexible_window import (FlexibleTrackWindow, shift_gather, shift_matrix, shifted_state,
                                                    transfer_modal_state, window_length_m, window_margin_m,
                                                    window_start_m)
from exudyn_wheelrail.simulation.exudyn_settings import run_solver_settings

V_M_S = 250.0 / 3.6


@pytest.fixture(scope="module")
def params():
    return TrackParameters.from_file()


@pytest.fixture(scope="module")
def window(params):
    """A window for one wheelset (x = 0) moving by two bays, and its modes."""
    L = window_length_m(params, [0.0], 2)
    model = FlexibleTrackModel(params, 0.0, L)
    return model, model.modes()


# --------------------------------------------------------------------------------------- (a) the shift's statics
@pytest.mark.parametrize("kind,row,force_N", [("vertical", 1, 160e3), ("lateral", 0, 10e3)])
@pytest.mark.parametrize("in_bay", [0.0, 0.5])                       # at a sleeper, mid-bay
def test_shifted_static_field_against_full_model(params, window, kind, row, force_N, in_bay):
    model, modes = window
    d, k = params.sleeper_spacing_m, 2
    # the load where the window moves (its centre plus k d / 2; a sleeper here) or half a bay further, and where it
    # is after the move
    s0 = 0.5 * (model.length_m + k * d) + in_bay * d
    s1 = s0 - k * d
    F = np.zeros(3)
    F[row] = force_N
    q0 = modes.static_coordinates([s0], [F])
    full0 = model.rail_field(kind, model.static(kind, [(s0, force_N)]), s0)[0][0]
    e_t = abs(float(modes.shape_at(s0)[row] @ q0) / full0 - 1.0)          # the truncation's static error here
    assert 0.005 < e_t < 0.05                                             # 800 Hz: 1-3 % (docs/track.md)
    # the plain shift, T q: the translated field is represented by the kept modes to e_t, and projecting it back
    # on them loses at most its part outside their span, again at most e_t: 2 e_t from the full solution
    q1 = shift_matrix(modes, k) @ q0
    m = window_margin_m(params)
    xs = np.linspace(m, model.length_m - m, 61)
    u_full = model.static(kind, [(s1, force_N)])
    w_full = model.rail_field(kind, u_full, xs)[0]
    w_shift = modes.shape_at(xs)[:, row, :] @ q1
    assert np.max(np.abs(w_shift - w_full)) <= 2.0 * e_t * np.max(np.abs(w_full))
    at_load = float(modes.shape_at(s1)[row] @ q1) / float(model.rail_field(kind, u_full, s1)[0][0]) - 1.0
    assert abs(at_load) <= 2.0 * e_t
    # the window's move with the load's quasi-static part taken out (shifted_state): the state becomes the reduced
    # static solution at s1 for the force that keeps the rail under the load where it was, F f(s0)/f(s1) with the
    # kept modes' point flexibility f = Σ φ²/ω² — exact up to round-off (relative 1e-8: sums of ~100 modes).  The
    # segment is mirror-symmetric: where the window moves (s0 at its centre plus k d / 2, s1 the mirror image)
    # the two flexibilities are equal and the moved state is the static solution at s1 itself
    A0 = modes.shape_at(s0)
    A1 = modes.shape_at(s1)
    q_new, v_new = shifted_state(q0, np.zeros_like(q0), shift_matrix(modes, k), modes.omega_rad_s ** -2.0, 0.0, F,
                                 A0, np.zeros_like(A0), A1, np.zeros_like(A1))
    q_ref = modes.static_coordinates([s1], [F])
    ratio = (np.sum(A0[row] ** 2 / modes.omega_rad_s ** 2) / np.sum(A1[row] ** 2 / modes.omega_rad_s ** 2))
    assert np.linalg.norm(q_new - ratio * q_ref) <= 1e-8 * np.linalg.norm(q_ref)
    assert np.max(np.abs(v_new)) == 0.0  # zero rates in: every term an exact zero
    if abs(s0 + s1 - model.length_m) < 1e-9:
        assert abs(ratio - 1.0) < 1e-9
    else:
        assert abs(ratio - 1.0) < e_t                                   # the truncation ripple


def test_shift_gather_moves_nodes_and_sleepers(params):
    model = FlexibleTrackModel(params, 0.0, 6 * params.sleeper_spacing_m)
    g = shift_gather(model, 2)
    e = params.elements_per_bay
    # rail node i takes node i + 2 e (displacement and slope), sleeper j takes sleeper j + 2, the front bays nothing
    # integer index maps: exact
    assert np.array_equal(g[:4], [4 * e, 4 * e + 1, 4 * e + 2, 4 * e + 3])
    n_keep = model.n_nodes - 2 * e
    assert np.all(g[2 * n_keep:2 * model.n_nodes] == -1)
    assert np.array_equal(g[2 * model.n_nodes:2 * model.n_nodes + 3], 2 * model.n_nodes + 2 + np.arange(3))
    assert np.all(g[2 * model.n_nodes + model.n_sleepers - 2:] == -1)


# ----------------------------------------------------------------------------- (b) Exudyn continues from the shift
def test_exudyn_continues_from_the_shifted_state(params):
    """Undamped vertical track modes (exact solution q cos ωt + q̇/ω sin ωt), RK44 through the runner; the
    runner's user function moves the state by T_2 once: the end state must be the exact continuation from T_2 q,
    T_2 q̇ (and far from the run without the move)."""
    import exudyn as exu

    from exudyn_wheelrail.simulation.runner import solve
    from exudyn_wheelrail.simulation.settings import RunSettings

    p = params.replace(pad_c_vertical_Ns_m=0.0, ballast_c_vertical_Ns_m=0.0)
    modes = FlexibleTrackModel(p, 0.0, 6 * p.sleeper_spacing_m).modes(f_max_Hz=400.0, kinds=("vertical",))
    T = shift_matrix(modes, 2)
    w = modes.omega_rad_s
    rng = np.random.default_rng(1)
    q0 = 1e-4 * rng.normal(size=modes.n_modes)
    v0 = 1e-4 * w * rng.normal(size=modes.n_modes)

    def exact(q, v, t):
        return q * np.cos(w * t) + v / w * np.sin(w * t), -q * w * np.sin(w * t) + v * np.cos(w * t)

    dt, n, n_shift = 2e-5, 1000, 400
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    h = add_flexible_track(mbs, modes)
    mbs.SetNodeParameter(h.modal_node, "initialCoordinates", q0.tolist())
    mbs.SetNodeParameter(h.modal_node, "initialCoordinates_t", v0.tolist())
    mbs.Assemble()
    rs = RunSettings(solver="rk44", dt_s=dt, duration_s=n * dt)
    sim, solver_type = run_solver_settings(rs)
    moved = []

    def user_function(mbs, t):           # t: the end of the coming step; the state is at t - dt
        if round(t / dt) == n_shift + 1:
            transfer_modal_state(mbs, h.modal_node, T)
            moved.append(t)
        return True

    out = solve(mbs, sim, solver_type, None, dt_s=dt, solver="rk44", user_function=user_function)
    assert out.status.kind == "ok" and len(moved) == 1
    q, v = h.coordinates(mbs)
    qs, vs = exact(q0, v0, n_shift * dt)
    q_ref, v_ref = exact(T @ qs, T @ vs, (n - n_shift) * dt)
    # RK44's global error: n local errors (ω dt)^5/120 of the fastest mode; ten times that
    tol = 10.0 * n * (w.max() * dt) ** 5 / 120.0
    assert np.max(np.abs(q - q_ref)) <= tol * np.max(np.abs(q_ref))
    assert np.max(np.abs(v - v_ref)) <= tol * np.max(np.abs(v_ref))
    q_no, _ = exact(q0, v0, n * dt)
    assert np.max(np.abs(q_no - q_ref)) > 0.1 * np.max(np.abs(q_ref))    # the move matters


# ------------------------------------------------------------------------ (c) a run on the window vs a fixed segment
def _wheelset_run(params, length_m, duration_s, dt_s=2.5e-4):
    """The single wheelset of Manchester vehicle 1 at 250 km/h into the RTRI lateral deviation on the flexible
    track: a fixed segment that carries the run (``length_m="auto"``) or the moving window (``"window"``), built
    with the scenario's functions; returns the recorded table and the window (or None)."""
    import exudyn as exu

    from exudyn_wheelrail.contact.pair import WheelRailPair
    from exudyn_wheelrail.multibody.connector import add_wheel_rail_contact, place_on_rails
    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
    from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle_with_overrides
    from exudyn_wheelrail.rolling_stock.placement import start_on_track
    from exudyn_wheelrail.scenarios.build import build_track
    from exudyn_wheelrail.scenarios.spec import validate_scenario
    from exudyn_wheelrail.simulation.recorder import Recorder
    from exudyn_wheelrail.simulation.runner import run
    from exudyn_wheelrail.simulation.settings import RunSettings
    from exudyn_wheelrail.scenarios.flexible_track import (flexible_track_modes, flexible_track_probes,
                                                          flexible_track_window, normalise_flexible_track,
                                                          start_on_flexible_track)

    name = "single_wheelset"
    scn = validate_scenario({
        "schema_version": 2, "vehicle": {"name": name, "speed_km_h": V_M_S * 3.6, "start_s_m": 8.0},
        "track": [{"type": "span_deflection", "span_length_m": 20.0, "amplitude_m": 0.010, "start_m": 8.5,
                   "transition_length_m": 3.0, "direction": "lateral"}],
        "run": {"duration_s": duration_s, "solver": "rk44", "dt_s": dt_s}})
    ft = normalise_flexible_track({"length_m": length_m}, lambda k, m: ValueError(f"{k}: {m}"), None)
    vehicle = load_vehicle_with_overrides(name)
    x = np.asarray(vehicle.wheelset_x_m())
    s_start = 8.0 - x.max()
    modes = flexible_track_modes(ft, s_start_m=s_start, wheelset_x_m=x, speed_m_s=V_M_S, end_time_s=duration_s,
                                 solver="rk44", dt_s=dt_s, moving_window=True)
    track = build_track(scn)
    geo = vehicle.geometry
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    model = build_vehicle(mbs, vehicle, speed_m_s=V_M_S, s_start_m=s_start, wheel_rail="none")
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    handle = add_flexible_track(mbs, modes)
    contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V_M_S, track=track,
                                     s_start_m=s_start, structure=handle)
    place_on_rails(mbs, model, pair)
    start_on_track(mbs, model, track)
    start_on_flexible_track(mbs, model, handle)
    mbs.Assemble()
    win = flexible_track_window(ft, contact=contact, handle=handle)

    class Wheel:
        columns = [("wheel", "Q_N"), ("wheel", "Y_N")]

        def fill(self, mbs, t, out):
            f = contact.wheel_force_N(0, "right")
            out[0], out[1] = -f[2], f[1]

    rec = Recorder([Wheel()] + flexible_track_probes(contact=contact, handle=handle, model=model, window=win),
                   n_rows_hint=int(duration_s / dt_s) + 2)
    settings = RunSettings(solver="rk44", dt_s=dt_s, duration_s=duration_s)
    sim, solver_type = run_solver_settings(settings)
    sim.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    out = run(mbs, settings, contact, speed_m_s=V_M_S, recorder=rec, exu_settings=(sim, solver_type),
              user_function=win)
    assert out.status.kind == "ok", out.status
    return rec.table(), win, modes


def _flexibility_ripple(d, *paths):
    """The truncation ripple of the kept modes' vertical point flexibility f(s) = Σ φ_z(s)²/ω²: at each position
    in the sleeper bay, (max - min)/mean of f over the sleeper bays of every ``(modes, s_from, s_to)`` together
    (the variation within a bay, sleeper against mid-bay, is the track's and is not counted)."""
    r = 0.0
    for xi in np.linspace(0.0, d, 13):
        f = []
        for modes, s_from, s_to in paths:
            s = np.arange(math.ceil(s_from / d), math.floor(s_to / d)) * d + xi
            f.append(np.sum(modes.shape_at(s)[:, 1, :] ** 2 / modes.omega_rad_s ** 2, axis=1))
        f = np.concatenate(f)
        r = max(r, (f.max() - f.min()) / f.mean())
    return r


def test_window_run_against_fixed_segment(params):
    duration = 0.1                                   # 6.9 m: eleven moves of one bay
    fixed, _, m_fixed = _wheelset_run(params, "auto", duration)
    moving, win, m_win = _wheelset_run(params, "window", duration)
    assert win.shifts >= 10 and m_win.n_modes < m_fixed.n_modes
    # the two reduced models differ at the same track distance by the kept modes' truncation ripple (the point
    # flexibility varies along a segment by r, a fraction of the 3 % truncation error; measured ~0.5 %): the rail
    # under the wheel by up to r of its deflection, its response to the wheel (a step of r w on the track spring,
    # overshoot at most 2) by up to 2 r of the forces
    m, d = window_margin_m(params), params.sleeper_spacing_m
    s_path = 8.0 + V_M_S * np.array([0.0, duration])
    w0 = m_win.model.start_m
    r = _flexibility_ripple(d, (m_fixed, *s_path), (m_win, w0 + m, w0 + m_win.model.length_m - m))
    assert r < 0.01

    def err(col):
        a, b = np.asarray(fixed[col]), np.asarray(moving[col])
        return float(np.max(np.abs(a - b)) / np.max(np.abs(a)))

    assert err("rail_z_w1_m") <= 2.0 * r
    for col in ("Q_N", "ballast_left_w1_N", "ballast_right_w1_N", "sleeper_z_w1_m"):
        assert err(col) <= 2.0 * r, col
    # the lateral force: the same bound relative to the larger of its peak and 1 % of the wheel load
    dy = np.max(np.abs(np.asarray(fixed["Y_N"]) - np.asarray(moving["Y_N"])))
    assert dy <= 2.0 * r * max(np.max(np.abs(fixed["Y_N"])), 0.01 * np.max(fixed["Q_N"]))


# ------------------------------------------------------------------------------------------------ (d) bad input
def test_bad_window_input(params):
    from exudyn_wheelrail.scenarios.spec import ScenarioError, validate_scenario
    from exudyn_wheelrail.scenarios.flexible_track import flexible_track_modes, normalise_flexible_track

    def scenario(solver="rk44", **flex):
        return validate_scenario({"schema_version": 2, "vehicle": {"name": "manchester_vehicle1",
                                                                    "speed_km_h": 100.0},
                                  "run": {"duration_s": 0.02, "solver": solver, "dt_s": 2.5e-4, "record": False},
                                  "outputs": {"plots": False, "criteria": False}, "flexible_track": flex})

    with pytest.raises(ScenarioError, match=r"flexible_track\.length_m: 'windows': expected a number in m or 'auto' "
                                            r"or 'window'"):
        scenario(length_m="windows")
    with pytest.raises(ScenarioError, match=r"flexible_track\.start_m: 5\.0: a moving window"):
        scenario(start_m=5.0, length_m="window")
    for bad in (0, 1.5, True, "2"):
        with pytest.raises(ScenarioError, match=r"flexible_track\.shift_bays: .*expected a whole number"):
            scenario(length_m="window", shift_bays=bad)
    with pytest.raises(ScenarioError, match=r"flexible_track\.shift_bays: only with length_m = 'window'"):
        scenario(shift_bays=2)
    ft = scenario(length_m="window")["flexible_track"]
    assert ft["length_m"] == "window" and ft["shift_bays"] >= 1
    kw = dict(s_start_m=0.0, wheelset_x_m=[0.0, -2.5], speed_m_s=30.0, end_time_s=10.0, dt_s=2.5e-4)
    with pytest.raises(TrackFileError, match=r"flexible_track\.length_m = 'window': this build does not move"):
        flexible_track_modes(ft, solver="rk44", **kw)
    with pytest.raises(TrackFileError, match=r"flexible_track\.length_m = 'window': run\.solver = 'newmark'"):
        flexible_track_modes(ft, solver="newmark", moving_window=True, **kw)
    ft2 = normalise_flexible_track({"length_m": "window", "shift_bays": 3}, lambda k, m: ValueError(f"{k}: {m}"),
                                   None)
    assert ft2["shift_bays"] == 3
    with pytest.raises(ValueError, match=r"shift_bays = 0: expected an integer >= 1"):
        window_length_m(params, [0.0], 0)
    with pytest.raises(ValueError, match=r"wheelset_x_m"):
        window_length_m(params, [], 2)
    with pytest.raises(ValueError, match=r"margin_m = 0\.1: expected a length of at least one sleeper bay"):
        window_start_m(params, 10.0, margin_m=0.1)
    with pytest.raises(ValueError, match=r"k = 99: expected a whole number of bays"):
        shift_gather(FlexibleTrackModel(params, 0.0, 3.0), 99)


def test_window_object_checks(params):
    """A window too short to move, a move larger than its room, and a contact on a fixed frame are refused
    before the run."""
    import exudyn as exu

    from exudyn_wheelrail.contact.pair import WheelRailPair
    from exudyn_wheelrail.multibody.connector import add_wheel_rail_contact
    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
    from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle_with_overrides

    vehicle = load_vehicle_with_overrides("single_wheelset")
    geo = vehicle.geometry
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    m = window_margin_m(params)

    def build(length_m, frame="moving"):
        sc = exu.SystemContainer()
        mbs = sc.AddSystem()
        model = build_vehicle(mbs, vehicle, speed_m_s=V_M_S, s_start_m=0.0, wheel_rail="none")
        start = window_start_m(params, 0.0)
        handle = add_flexible_track(mbs, FlexibleTrackModel(params, start, length_m).modes(f_max_Hz=200.0))
        contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V_M_S, s_start_m=0.0,
                                         structure=handle, frame=frame)
        return handle, contact, sc

    handle, contact, _ = build(2.0 * m)
    with pytest.raises(ValueError, match=r"too short to move"):
        FlexibleTrackWindow(handle, contact)
    handle, contact, _ = build(window_length_m(params, [0.0], 2))
    with pytest.raises(ValueError, match=r"shift_bays = 3: the window .* leaves room for 2 bays"):
        FlexibleTrackWindow(handle, contact, shift_bays=3)
    assert FlexibleTrackWindow(handle, contact).shift_bays == 2
    handle, contact, _ = build(window_length_m(params, [0.0], 2), frame="track")
    with pytest.raises(ValueError, match=r"frame='moving'"):
        FlexibleTrackWindow(handle, contact)


def test_shift_moves_the_connector_and_drops_its_kept_evaluation(params):
    """After a move, the connector's next call at the shifted state (which it may take from the evaluation it
    keeps) projects the rail forces on the modes of the window at its new start, and reads the rail there."""
    import exudyn as exu

    from exudyn_wheelrail.contact.pair import WheelRailPair
    from exudyn_wheelrail.multibody.connector import add_wheel_rail_contact, place_on_rails
    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
    from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle_with_overrides
    from exudyn_wheelrail.scenarios.flexible_track import start_on_flexible_track

    vehicle = load_vehicle_with_overrides("single_wheelset")
    geo = vehicle.geometry
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    model = build_vehicle(mbs, vehicle, speed_m_s=V_M_S, s_start_m=0.0, wheel_rail="none")
    modes = FlexibleTrackModel(params, window_start_m(params, 0.0), window_length_m(params, [0.0], 2)).modes()
    handle = add_flexible_track(mbs, modes)
    contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V_M_S, s_start_m=0.0, structure=handle)
    place_on_rails(mbs, model, pair)
    start_on_flexible_track(mbs, model, handle)
    mbs.Assemble()
    win = FlexibleTrackWindow(handle, contact)
    start0 = win.start_m
    q, v = contact.coordinates(mbs)
    contact.evaluate(mbs, 0.0)
    f_before = contact.forces(q, v, 0.0)[6:].copy()
    win.shift(mbs, 2, 0.0)
    # the same sum, stored in both: exact
    assert win.start_m == start0 + 2 * params.sleeper_spacing_m == contact._deck[0][0]
    q, v = contact.coordinates(mbs)
    f = contact.forces(q, v, 0.0)[6:]                # the kept evaluation is that of the shifted state
    s = win.wheelset_s_m(mbs, 0.0)
    phi = win.shape_at(s)[0]                          # (3, n_modes) at the new start
    F = contact.rail_forces_N()[0]
    assert np.allclose(f, phi.T @ F, rtol=0.0, atol=1e-9 * np.max(np.abs(f)))
    assert not np.allclose(f, f_before, rtol=1e-3)
    # the rail under the wheelset: the connector's deck state is the window's field at its new start (plus the
    # static correction's few per cent, if the modes carry one), far from the field read at the old start
    z = contact.deck_state()[0, 1]
    z_new = float(phi[1] @ q[6:])
    z_old = float(win.shape_at(s, start0)[0, 1] @ q[6:])
    assert abs(z - z_new) <= 0.05 * abs(z_new) < abs(z_old - z_new)
