"""The flexible track's static correction (the dropped modes' flexibility in series with the contact:
``FlexibleTrackModes.residual_table``, ``structures.deck_kinematics.series_contacts`` and the connector's two-pass
stage ``multibody.connector_core.series_compliance``) against independent references: the closed form of one
Hertz contact on a spring, a brute-force root of the coupled contacts of a wheelset, the full finite-element
model's static flexibility, and a vehicle at rest on the track against the full model's static deflection."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import scipy.optimize

from exudyn_wheelrail.structures.deck_kinematics import (N_SC, SC_AT, SC_AY, SC_AZ, SC_DELTA_G, SC_DN_G, SC_N,
                                                         SC_N_G, SC_RATIO, series_contacts)
from exudyn_wheelrail.track.flexible import FlexibleTrackModel
from exudyn_wheelrail.track.flexible_parameters import TrackParameters
from exudyn_wheelrail.validation import InputWarning


def _contact(a, N_g, delta_g):
    c = np.zeros(N_SC)
    c[SC_AY], c[SC_AZ], c[SC_AT] = a
    c[SC_N_G], c[SC_DELTA_G], c[SC_DN_G] = N_g, delta_g, 1.5 * N_g / delta_g
    return c


def _g6(G):
    return np.array([G[0, 0], G[1, 1], G[2, 2], G[0, 1], G[0, 2], G[1, 2]])


def test_one_contact_on_a_spring_closed_form():
    """One Hertz contact (N = K δ^1.5) in series with a spring of compliance c along its normal: N = K (δ_g − c N)^1.5,
    solved here by bracketing (brentq to 1e-15 relative); the Newton of series_contacts must agree to round-off
    (1e-12) over residual-to-Hertz ratios from 0.01 to 100 — the range of a track's pads (c K δ^0.5 ~ 3)."""
    K = 1.1e11                                                         # N/m^1.5, an 80 kN wheel at 0.08 mm
    delta_g = 2.4e-4
    N_g = K * delta_g ** 1.5
    for ratio in (0.01, 0.3, 3.0, 100.0):
        c = ratio * delta_g / N_g
        a = np.array([-0.03, -0.9995, 0.75])                           # a tread contact on the right rail
        G = np.diag([0.0, c, 0.0])                                     # compliance along a: a_z² c
        contacts = np.array([_contact(a, N_g, delta_g)])
        series_contacts(_g6(G), contacts, 1, np.zeros(3), np.zeros((7, 3)))
        c_n = a[1] ** 2 * c
        N_ref = scipy.optimize.brentq(lambda N: N - K * max(delta_g - c_n * N, 0.0) ** 1.5, 0.0, N_g, xtol=1e-15 * N_g,
                                      rtol=1e-15)
        assert contacts[0, SC_N] == pytest.approx(N_ref, rel=1e-12)
        assert contacts[0, SC_RATIO] == pytest.approx(1.0 - c_n * N_ref / delta_g, rel=1e-12)


def test_coupled_contacts_of_a_wheelset_brute_force():
    """Three contacts of a wheelset (two regions on one wheel, one on the other) on rails with a full 3 x 3 residual
    flexibility: the rails' displacement u = −G Σ N_r a_r with N_r = K_r (δ_g,r + a_r·u)₊^1.5, found by a general
    root finder from another start (scipy's hybr, to 1e-14 m) — Newton in series_contacts must agree to 1e-9 of the
    forces (the root is unique: the gradient of a convex potential); started from a residual displacement u0 the
    rails already had (the connector's second pass), the solution is the same physical state."""
    rng = np.random.default_rng(3)
    A = rng.normal(size=(3, 3)) * 1e-5
    G = A @ A.T + np.diag([2e-10, 1e-9, 2e-9])                         # SPD, m/N and rad/(N m)
    a = np.array([[-0.03, -0.9995, 0.7505], [-0.35, -0.937, 0.705], [0.03, -0.9995, -0.7505]])
    K = np.array([1.1e11, 0.6e11, 1.0e11])
    delta_g = np.array([2.4e-4, 0.3e-4, 2.2e-4])

    def resid(u):
        d = np.maximum(delta_g + a @ u, 0.0)
        return u + G @ (a.T @ (K * d ** 1.5))

    u_ref = scipy.optimize.root(resid, -np.array([0.0, 1e-4, 0.0]), method="hybr", tol=1e-16).x
    N_ref = K * np.maximum(delta_g + a @ u_ref, 0.0) ** 1.5
    assert np.max(np.abs(resid(u_ref))) < 1e-14
    contacts = np.array([_contact(a[r], K[r] * delta_g[r] ** 1.5, delta_g[r]) for r in range(3)])
    work = np.zeros((7, 3))
    its = series_contacts(_g6(G), contacts, 3, np.zeros(3), work)
    assert its < 30
    np.testing.assert_allclose(contacts[:, SC_N], N_ref, rtol=1e-9, atol=1e-9 * N_ref.max())
    np.testing.assert_allclose(work[0], u_ref, rtol=0, atol=1e-14)
    # the second pass: penetrations found on rails already displaced by u0 (δ_g' = δ_g + a·u0)
    # (a contact without penetration there is not passed: it carries nothing at the solution either)
    assert N_ref[1] == 0.0 and N_ref[0] > 0.0 and N_ref[2] > 0.0
    u0 = 0.9 * u_ref
    d0 = delta_g + a @ u0
    keep = d0 > 0.0
    again = np.array([_contact(a[r], K[r] * d0[r] ** 1.5, d0[r]) for r in np.flatnonzero(keep)])
    series_contacts(_g6(G), again, len(again), u0, work)
    np.testing.assert_allclose(again[:, SC_N], N_ref[keep], rtol=1e-9, atol=1e-9 * N_ref.max())


@pytest.fixture(scope="module")
def track_400():
    model = FlexibleTrackModel(TrackParameters.from_file(), 0.0, 18.0)
    return model, model.modes(f_max_Hz=400.0)


def test_kept_modes_plus_residual_equal_the_full_static_flexibility(track_400):
    """At points between the shape table's points (where the residual is interpolated linearly), the kept modes'
    static flexibility Σ φ²/ω² plus the residual equals the full finite-element model's point flexibility (a sparse
    solve under a unit load at the point, a computation separate from the table's).  The residual is 4 % (lateral)
    to 22 % (vertical, roll) of the whole at 400 Hz and varies along the bay, with kinks at the rail seats;
    linear interpolation between points h apart errs by at most ~h² |G''|/8, bounded here by the table's largest
    second difference nearby / 8 (twice that is the tolerance: up to 0.4 % of the flexibility; measured 0.17 %).
    At a table point the two agree to round-off (the only check of the roll row, whose kept shapes are themselves
    interpolated linearly between the points).  Without the correction the reduced model misses the residual, which
    is asserted to be far above the tolerance."""
    model, modes = track_400
    s = np.array([8.0375, 8.2125, 9.1])                                # within the table's elements
    s_pt = 8.4                                                         # a table point
    for kind, row in (("lateral", 0), ("vertical", 1), ("roll", 2)):
        phi = modes.shape_at(np.append(s, s_pt))[:, row, :]
        kept = np.sum(phi ** 2 / modes.omega_rad_s ** 2, axis=1)
        res = modes.residual_at(np.append(s, s_pt))[:, row, row]
        full = np.array([float(model.rail_field(kind, model.static(kind, [(x, 1.0)]), x)[0][0])
                         for x in np.append(s, s_pt)])
        tb = modes.table
        near = np.abs(tb.start_m + np.append(tb.elem_x0, tb.elem_x0[-1] + tb.elem_len[-1]) - 8.6) < 1.2
        d2 = np.max(np.abs(np.diff(modes.residual_table[near, row], 2)))   # around the points checked
        if kind != "roll":          # the table's roll row is linear between its points in the kept modes too
            np.testing.assert_allclose(kept[:-1] + res[:-1], full[:-1], rtol=1e-9, atol=2.0 * d2 / 8.0)
        assert kept[-1] + res[-1] == pytest.approx(full[-1], rel=1e-9)
        assert np.all(res > 0.03 * full)                               # the correction is not negligible here
        assert 2.0 * d2 / 8.0 < 1e-2 * full.min()                      # and the tolerance is a fraction of it


def _vehicle_at_rest(f_max_Hz: float, correction: bool):
    from exudyn_wheelrail.scenarios.build import build_scenario
    from exudyn_wheelrail.scenarios.spec import validate_scenario
    import exudyn_wheelrail.track.flexible as F

    d = {"schema_version": 2, "vehicle": {"name": "manchester_vehicle1", "speed_km_h": 100.0, "start_s_m": 8.0},
         "run": {"duration_s": 0.01, "solver": "rk44", "dt_s": 2.5e-4},
         "outputs": {"plots": False, "criteria": False, "timeseries": ["Q"]},
         "flexible_track": {"modes_up_to_Hz": f_max_Hz}}
    modes_of = F.FlexibleTrackModel.modes
    try:
        F.FlexibleTrackModel.modes = (lambda self, f_max_Hz=None, damping="full", kinds=F.KINDS,
                                      static_correction=True:
                                      modes_of(self, f_max_Hz, damping, kinds, correction))
        h = build_scenario(validate_scenario(d))
    finally:
        F.FlexibleTrackModel.modes = modes_of
    h.mbs.Assemble()
    q, v = h.contact.coordinates(h.mbs)
    h.contact.evaluate_state(q, v, 0.0)
    return h


@pytest.mark.parametrize("correction", [True, False])
def test_vehicle_at_rest_deflects_the_rails_as_the_full_model(correction):
    """The RTRI car standing on the track with modes to 400 Hz: its start (the rails deflected by the kept modes'
    statics plus the residual, the car lowered with them) is the static equilibrium of the connector's two-pass
    series solve — every wheel carries its static load (to 0.1 %: the contact geometry's round-off and the
    neglected coupling between the two rails through the residual, ~0.1 % of it) — and the rails' deflection under
    each wheelset equals the full finite-element model's under the four wheelset loads, to the residual's neglected
    coupling between wheelsets (computed here from the full model: 0.2 % within a bogie, 2.5 m apart) plus 0.2 %
    for the interpolation.  Without
    the correction the reduced model is 21 % too stiff at this cut-off."""
    from exudyn_wheelrail.contact.layout import RES_F_TRACK_Z

    h = _vehicle_at_rest(400.0, correction)
    model = h.flexible_track.modes.model
    Q = np.asarray(h.model.load_path.wheel, dtype=float)                # (n_ws, 2) static wheel loads
    Fz = -h.contact.results[:, :, RES_F_TRACK_Z].sum(axis=1)           # per wheel: the force on the wheel, up
    x = np.array([ws.p_cg_in_frame[0] for ws in h.model.wheelsets])
    s = h.model.track_distance_m(x, 0.0)
    u = model.static("vertical", [(sk, float(Q[k].sum())) for k, sk in enumerate(s)])
    z_full = np.array([float(model.rail_field("vertical", u, sk)[0][0]) for sk in s])
    z = h.contact.deck_state()[:, 1]
    if correction:
        np.testing.assert_allclose(Fz.reshape(-1, 2), Q, rtol=1e-3)
        # the neglected residual coupling between wheelsets: the full model's cross flexibility G(s_k, s_j) less
        # the kept modes' Σ φ(s_k) φ(s_j)/ω², times the other wheelsets' loads (0.2 % of z within a bogie)
        modes = h.flexible_track.modes
        phi = modes.shape_at(s)[:, 1, :] / modes.omega_rad_s
        cross = np.zeros(len(s))
        for j, sj in enumerate(s):
            g_full = np.array([float(model.rail_field("vertical", model.static("vertical", [(sj, 1.0)]), sk)[0][0])
                               for sk in s])
            g_res = g_full - phi @ phi[j]
            cross += np.where(np.arange(len(s)) != j, np.abs(g_res) * Q[j].sum(), 0.0)
        assert np.all(np.abs(z - z_full) <= cross + 2e-3 * z_full)
        assert np.all(cross < 0.01 * z_full)
    else:
        assert np.all(z < 0.85 * z_full)
        assert math.isfinite(float(np.sum(Fz)))


def test_train_on_the_moving_window_starts_in_equilibrium():
    """A two-coach train on the ballasted track (a scenario with ``vehicle.consist`` and a moving window, modes to
    400 Hz with the correction): at t = 0 every wheel carries its static load (0.1 %, as the single car above: the
    train's start on the flexible track is the same static solve), the window moves with the train (at 200 km/h it
    passes a 0.6 m bay every 11 ms) and the run ends ok; the wheel loads stay within ±10 % on the level track.  The
    step, 0.5 ms, is within RK44's limits of the contact stiffness and, by 20 %, of the creep damping on the rails
    at this speed (the monitor's estimate 0.62 ms, within a few % of the measured boundary): no warning."""
    from exudyn_wheelrail.scenarios.build import build_scenario
    from exudyn_wheelrail.scenarios.run import run_model
    from exudyn_wheelrail.scenarios.spec import validate_scenario

    d = {"schema_version": 2, "vehicle": {"consist": "manchester_x2", "speed_km_h": 200.0, "start_s_m": 10.0},
         "run": {"duration_s": 0.06, "solver": "rk44", "dt_s": 0.0005},
         "outputs": {"plots": False, "criteria": False, "timeseries": ["Q", "flexible_track"]},
         "flexible_track": {"modes_up_to_Hz": 400.0, "length_m": "window"}}
    h = build_scenario(validate_scenario(d))
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        out = run_model(h, progress=False)
    assert out.status.kind == "ok", out.status
    ts = h.recorder.table()
    Q = np.array([ts[c] for c in ts if c.startswith("Q_w")])
    Q_static = np.asarray(h.model.load_path.wheel, dtype=float)       # (n_ws, 2)
    np.testing.assert_allclose(np.sort(Q[:, 0]), np.sort(Q_static.ravel()), rtol=1e-3)
    assert np.all(np.abs(Q / Q[:, :1] - 1.0) < 0.1)
    assert h.flexible_window.summary()["shifts"] >= 4


def test_track_on_deck_residual_completes_the_coupled_statics():
    """Over a bridge deck (track and deck coupled through the ballast, modes to 200 Hz): at the shape table's points
    the kept coupled modes' Σ φ φᵀ/ω² plus the residual equals the coupled model's static flexibility — a dense
    solve of the assembled coupled stiffness under unit loads on each rail field, separate from the residual's
    sparse one — to round-off (1e-6 of the diagonal), cross terms included; the residual is a sizeable part there."""
    from exudyn_wheelrail.structures import BridgeModel, DeckSection
    from exudyn_wheelrail.structures.beam import hermite
    from exudyn_wheelrail.track.flexible_deck import TrackOnDeckModel

    sec = DeckSection(m_kg_m=15e3, EI_y_Nm2=3.501660107e10, EI_z_Nm2=2.801328085e11, GJ_Nm2=3.501660107e10,
                      EA_N=1.44e11, Ip_kgm2_m=40262.5)
    deck = BridgeModel(spans_m=(20.0,), section=sec, damping_ratio=0.01, rail_height_m=1.45, start_m=6.0,
                       elements_per_span=20)
    model = TrackOnDeckModel(TrackParameters.from_file(), 0.0, 32.4, deck, ballast_height_m=0.8)
    modes = model.modes(f_max_Hz=200.0)
    _, K, _, off = model.assemble_coupled()
    for s0 in (3.0, 16.2):                                             # embankment, on the deck (table points)
        e, xi = model._locate(np.array([s0]))
        N, _, _ = hermite(xi, model.h_m)
        Psi = np.zeros((K.shape[0], 3))
        for row, kind in enumerate(("lateral", "vertical", "roll")):
            Psi[off[kind] + 2 * e[0] + np.arange(4), row] = N[0]
        G_full = Psi.T @ np.linalg.solve(K, Psi)
        phi = modes.shape_at(s0) / modes.omega_rad_s
        G = phi @ phi.T + modes.residual_at(s0)
        np.testing.assert_allclose(G, G_full, rtol=0, atol=1e-6 * np.max(np.diag(G_full)))
        assert np.all(np.diag(modes.residual_at(s0)) > 0.02 * np.diag(G_full))


def test_runner_refuses_an_explicit_step_the_rail_cannot_carry():
    """The Python API path (no scenario build): a train on a flexible track with modes to 600 Hz run through the
    runner with RK44 at 0.75 ms — measured in the crossing benchmark to diverge while the run monitor reports ok —
    is refused before the solve with an error naming run.dt_s and the largest stable step (0.51 ms); 0.4 ms runs."""
    import exudyn as exu

    from exudyn_wheelrail.rolling_stock.train import load_consist
    from exudyn_wheelrail.scenarios.bridge_crossing_vehicles import build_train_on_straight_track
    from exudyn_wheelrail.simulation.runner import run
    from exudyn_wheelrail.simulation.settings import RunSettings
    from exudyn_wheelrail.track.flexible import add_flexible_track
    from exudyn_wheelrail.track.flexible_parameters import TrackFileError
    from exudyn_wheelrail.scenarios.flexible_track import start_on_flexible_track

    modes = FlexibleTrackModel(TrackParameters.from_file(), -70.0, 100.0).modes(f_max_Hz=600.0)
    for dt, refused in ((7.5e-4, True), (4e-4, False)):
        mbs = exu.SystemContainer().AddSystem()
        handle = add_flexible_track(mbs, modes)
        train, _ = build_train_on_straight_track(mbs, load_consist("manchester_x2"), speed_m_s=50.0,
                                                 s_start_m=-10.0, structure=handle)
        start_on_flexible_track(mbs, train, handle, contact=train.contact)
        mbs.Assemble()
        settings = RunSettings(solver="rk44", dt_s=dt, duration_s=0.004)
        if refused:
            with pytest.raises(TrackFileError, match=r"run\.dt_s = 0\.00075 s: .* use run\.dt_s <= 0\.0005"):
                run(mbs, settings, train.contact, speed_m_s=50.0)
        else:
            assert run(mbs, settings, train.contact, speed_m_s=50.0).status.kind == "ok"


def test_monitor_estimate_sees_the_rail_modal_mass():
    """The run monitor's stability estimate on a structure adds the rails' inverse modal mass at the wheel,
    ``B += g_iᵀ Φ Φᵀ g_j`` (monitor_core.rail_mobility, checked against numpy), so that the wheel on a light rail is
    seen: the train on the track with modes to 600 Hz has ω h above RK44's 2√2 at 0.75 ms — the step measured to
    diverge there — while on rigid rails the same train is far below it."""
    import exudyn as exu

    import exudyn_wheelrail.simulation.monitor_core as MC
    from exudyn_wheelrail.rolling_stock.train import load_consist
    from exudyn_wheelrail.scenarios.bridge_crossing_vehicles import build_train_on_straight_track
    from exudyn_wheelrail.simulation.runner import contact_omega_rad_s
    from exudyn_wheelrail.track.flexible import add_flexible_track
    from exudyn_wheelrail.scenarios.flexible_track import start_on_flexible_track

    rng = np.random.default_rng(5)
    G = rng.normal(size=(2, 4, MC.N_G))
    phi = rng.normal(size=(2, 3, 7)) * 0.05
    B = rng.normal(size=(4, 4))
    B = B @ B.T
    expect = B[:3, :3] + G[1, :3, 6:] @ phi[1] @ phi[1].T @ G[1, :3, 6:].T
    MC.rail_mobility(1, 3, G, phi, B, np.zeros((3, 3)))
    np.testing.assert_allclose(B[:3, :3], expect, rtol=1e-12)

    omega = {}
    for flexible in (True, False):
        mbs = exu.SystemContainer().AddSystem()
        handle = None
        if flexible:
            modes = FlexibleTrackModel(TrackParameters.from_file(), -70.0, 100.0).modes(f_max_Hz=600.0)
            handle = add_flexible_track(mbs, modes)
        train, _ = build_train_on_straight_track(mbs, load_consist("manchester_x2"), speed_m_s=50.0,
                                                 s_start_m=-10.0, structure=handle)
        if flexible:
            start_on_flexible_track(mbs, train, handle, contact=train.contact)
        mbs.Assemble()
        omega[flexible] = max(contact_omega_rad_s(mbs, train.contact))
    assert omega[False] > 1000.0                                       # the wheels are in contact
    assert omega[True] * 7.5e-4 > 2.0 * math.sqrt(2.0) > 1.3 * omega[False] * 7.5e-4
