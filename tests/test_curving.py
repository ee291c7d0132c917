"""Steady curving (scenarios/curving.py, rolling_stock/track_following.py, the connector's curve terms) against
independent references: the lateral force balance of the whole vehicle ΣΣY = m (V²/R cos φ − g sin φ) at cant
deficiency and excess and ΣΣY ≈ 0 at the balance speed (Manchester vehicle, R = 600 m, 150 mm cant); a free
coned wheelset settles at the pure-rolling shift y = r0 b/(R λ); left curves mirror right ones; the chord geometry
between bodies is the circle's; bad input is refused before any work."""
import dataclasses
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from exudyn_wheelrail.analysis.curving import flange_play_m, minimum_radius_m
from exudyn_wheelrail.analysis.geometry_functions import contact_geometry_sweep
from exudyn_wheelrail.contact.pair import WheelRailPair
from exudyn_wheelrail.conventions import RAIL_CENTRE_DISTANCE_M
from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle, load_vehicle_with_overrides
from exudyn_wheelrail.profiles.profiles import WheelProfile
from exudyn_wheelrail.scenarios.curving import CurvingCase, CurvingResult, build_curving, run_curving, write_outputs

R, H, G = 600.0, 0.150, 9.81
PHI = math.asin(H / RAIL_CENTRE_DISTANCE_M)
V_BALANCE_KMH = math.sqrt(G * R * math.tan(PHI)) * 3.6          # V^2/R cos(phi) = g sin(phi)


def _a_nc(v_kmh):
    v = v_kmh / 3.6
    return v * v / R * math.cos(PHI) - G * math.sin(PHI)


@pytest.fixture(scope="module")
def deficiency_left():
    return run_curving(CurvingCase("manchester_vehicle1", radius_m=R, cant_m=H, speed_km_h=120.0,
                                   direction="left")).summary


@pytest.fixture(scope="module")
def excess_right():
    # a_nc = -0.52 m/s^2
    return run_curving(CurvingCase("manchester_vehicle1", radius_m=R, cant_m=H, speed_km_h=60.0)).summary


def _check_balance(s, v_kmh):
    assert s["status"] == "ok" and s["steady"], s
    m = load_vehicle("manchester_vehicle1").total_mass_kg
    assert s["vehicle_mass_kg"] == pytest.approx(m)
    a = _a_nc(v_kmh)
    assert s["unbalanced_lateral_acceleration_m_s2"] == pytest.approx(a, rel=1e-12)
    assert abs(a) >= 0.3
    # the contract's target: within 2 % of m a_nc (the steady mean of a lightly damped car-body mode, averaged over
    # whole periods; every lateral load of the frame passes through the wheelsets)
    assert sum(s["sum_Y_N"]) == pytest.approx(m * a, rel=0.02)
    assert len(s["sum_Y_N"]) == 4


def test_force_balance_at_cant_deficiency_left_curve(deficiency_left):
    _check_balance(deficiency_left, 120.0)
    s = deficiency_left
    assert s["unbalanced_lateral_acceleration_m_s2"] > 0.8
    # the leading wheelset of each bogie runs with a positive angle of attack (turned outwards), the trailing one
    # smaller, and the leading wheelsets' outer wheels carry the larger Y/Q
    aoa = s["angle_of_attack_rad"]
    assert aoa[0] > aoa[1] and aoa[2] > aoa[3]
    assert aoa[0] == pytest.approx(1.28 / R, rel=0.6)          # the bogie chord: a/R, plus the wheelset's lag
    assert s["YQ"][0]["outer"] > s["YQ"][1]["outer"]


def test_force_balance_at_cant_excess(excess_right):
    _check_balance(excess_right, 60.0)
    assert excess_right["unbalanced_lateral_acceleration_m_s2"] < -0.5


def test_balance_speed_sum_of_lateral_forces_vanishes():
    s = run_curving(CurvingCase("manchester_vehicle1", radius_m=R, cant_m=H, speed_km_h=V_BALANCE_KMH)).summary
    assert s["status"] == "ok" and s["steady"]
    assert s["unbalanced_lateral_acceleration_m_s2"] == pytest.approx(0.0, abs=1e-12)
    m = s["vehicle_mass_kg"]
    # 2 % of m a_nc at the smallest a_nc the balance is stated for (0.3 m/s^2): 0.06 % of m g
    assert abs(sum(s["sum_Y_N"])) < 0.02 * m * 0.3


def _cone_case(direction):
    # a free wheelset (no yaw or lateral stiffness; dampers only, which carry nothing in the steady state) with
    # coned wheels (no flange) at the balance speed of a shallow curve
    veh = load_vehicle_with_overrides("single_wheelset", {"primary.kx_N_per_m": 0.0, "primary.ky_N_per_m": 0.0,
                                                         "primary.cx_N_s_per_m": 15e3, "primary.cy_N_s_per_m": 20e3})
    pair = WheelRailPair(WheelProfile.cone(0.05), "UIC60", inclination="1/40")
    radius, cant = 3000.0, 0.020
    v_kmh = math.sqrt(G * radius * math.tan(math.asin(cant / RAIL_CENTRE_DISTANCE_M))) * 3.6
    return CurvingCase(veh, radius_m=radius, cant_m=cant, speed_km_h=v_kmh, direction=direction,
                       wheel_rail_pair=pair, preset="default"), pair


@pytest.fixture(scope="module")
def cone_runs():
    out = {}
    for d in ("right", "left"):
        case, pair = _cone_case(d)
        out[d] = run_curving(case)
    return out, pair


def test_coned_wheelset_settles_at_the_pure_rolling_shift(cone_runs):
    runs, pair = cone_runs
    s = runs["right"].summary
    # ("steady" judges sum Y against the force balance's scale; a free wheelset's sum Y is ~0 with a slow residual
    # oscillation of ~0.1 % of its axle load: the shift below is the quantity this test converges)
    assert s["status"] == "ok"
    # lambda: the rolling-radius difference gradient of the pair over +-3 mm (least squares), b and r0 from the
    # centred contact points -- the geometry sweep, independent of the dynamic run
    y = np.linspace(-0.003, 0.003, 61)
    sw = contact_geometry_sweep(pair, y)
    lam = np.polyfit(y, sw.delta_r_m, 1)[0] / 2.0
    centred = [r for r in sw.rows if r["y_m"] == 0.0 and r["side"] == "right"][0]
    r0 = centred["rolling_radius_m"]
    b = 0.5 * 1.360 + 0.070 + centred["y_wheel_m"]          # tape circle at b2b/2 - flange back (S1002 placement)
    y_ref = r0 * b / (s["radius_m"] * lam)
    # the linear fit's residual over the +-3 mm range is 2e-3 of Delta r; creep coupling (spin, f23) moves the
    # shift by less than 1 %: tolerance 2 %
    assert s["lateral_shift_m"][0] == pytest.approx(y_ref, rel=0.02)
    assert abs(s["angle_of_attack_rad"][0]) < 1e-4


def test_left_curve_mirrors_right(cone_runs):
    runs, _ = cone_runs
    r, l = runs["right"], runs["left"]
    # the time series mirror (to the round-off of the contact search, far below these bounds): lateral shift and
    # yaw change sign, the wheel loads swap sides
    np.testing.assert_allclose(l.timeseries["y_rel_w1_m"], -r.timeseries["y_rel_w1_m"], atol=1e-9)
    np.testing.assert_allclose(l.timeseries["yaw_w1_rad"], -r.timeseries["yaw_w1_rad"], atol=1e-9)
    np.testing.assert_allclose(l.timeseries["Q_w1_left_N"], r.timeseries["Q_w1_right_N"], rtol=1e-6)
    np.testing.assert_allclose(l.timeseries["Y_w1_left_N"], -r.timeseries["Y_w1_right_N"], atol=1e-2)
    # and so do the steady values, which are outwards-signed
    for key in ("sum_Y_N", "lateral_shift_m", "angle_of_attack_rad"):
        np.testing.assert_allclose(l.summary[key], r.summary[key], rtol=1e-6, atol=1e-6)
    assert l.summary["Q_N"][0]["outer"] == pytest.approx(r.summary["Q_N"][0]["outer"], rel=1e-6)


def test_chord_geometry_between_bodies_in_a_circular_curve():
    """In the circular curve a bogie 9.5 m ahead of the car-body centre sits, in the car body's frame, on the
    versine l^2/(2R) towards the centre and turned by l/R (the circle, to second order in l/R); a wheelset 1.28 m
    ahead of its bogie likewise."""
    case = CurvingCase("manchester_vehicle1", radius_m=R, cant_m=H, speed_km_h=100.0, transition_m=20.0)
    h = build_curving(case)
    frame = h.frame
    t = 60.0 / (100 / 3.6)                   # every body in the circular curve
    delta, theta = frame.offsets(t)
    phi = PHI
    for k, (_, kind, kA, kB, _, v, _) in enumerate(frame.elements):
        l = frame._x[kB] - frame._x[kA]
        if abs(l) < 1e-9:
            continue
        # rotation about the global vertical, in the canted frame A
        np.testing.assert_allclose(theta[k], [0.0, l / R * math.sin(phi), l / R * math.cos(phi)], atol=1e-12)
        # B's frame origin on the circle: y_h = l^2/(2R) (exact integral of the heading), plus theta x v
        y_h = l * l / (2 * R)
        ref = np.array([0.0, y_h * math.cos(phi), -y_h * math.sin(phi)]) + np.cross(theta[k], v)
        np.testing.assert_allclose(delta[k], ref, atol=1e-12)
    assert any(abs(frame._x[e[3]] - frame._x[e[2]]) == pytest.approx(9.5) for e in frame.elements)
    # the body loads: the lateral one is m (g sin(phi) - V^2/R cos(phi)) on every body (conventions: right curve)
    # m (g sin(phi) - a cos(phi)), a the horizontal centripetal acceleration of the centre of mass, whose height h
    # above the canted rail plane puts it at the radius R - h sin(phi): a = (V/R)^2 (R - h sin(phi))
    F, T = frame.body_terms(t)
    V = 100 / 3.6
    m = np.array([b.mass_kg for b in frame.bodies])
    h_cg = np.array([-b.p_cg_in_frame[2] for b in frame.bodies])
    a = (V / R) ** 2 * (R - h_cg * math.sin(phi))
    np.testing.assert_allclose(F[:, 1], m * (G * math.sin(phi) - a * math.cos(phi)), rtol=1e-9)
    # a wheelset precessing steadily with the frame: its angular momentum H = I (omega_s e_y + Omega) turns with
    # Omega = V/R (0, sin(phi), cos(phi)), dH/dt = Omega x H, which the rails must supply (-dH/dt is the load)
    ws = h.model.wheelsets[0]
    k = frame.bodies.index(ws)
    wd = h.vehicle.wheelset
    inertia = np.diag([wd.Ixx_kg_m2, wd.Iyy_kg_m2, wd.Izz_kg_m2])
    omega = V / R * np.array([0.0, math.sin(phi), math.cos(phi)])
    H_ws = inertia @ (np.array([0.0, -V / ws.r0_m, 0.0]) + omega)
    np.testing.assert_allclose(T[k], -np.cross(omega, H_ws), rtol=1e-9, atol=1e-9)
    assert T[k, 0] < 0.0                     # a negative roll moment: it loads the outer (left) wheel


def test_minimum_radius_from_the_wheelbase():
    v = load_vehicle("manchester_vehicle1")
    play = flange_play_m(v)
    assert play == pytest.approx(1.435 - 1.360 - 2 * 0.0325, abs=2e-4)    # S1002 flange thickness 32.5 mm
    r_min, why = minimum_radius_m(v)
    assert r_min >= (2 * 1.28) ** 2 / (8 * play) and "wheelbase" in why


@pytest.mark.parametrize("args, option", [
    (["--radius-m", "60", "--cant-m", "0.1"], "--radius-m"),
    (["--radius-m", "600", "--cant-m", "0.25"], "--cant-m"),
    (["--radius-m", "600", "--cant-m", "150"], "--cant-m"),
    (["--radius-m", "600", "--cant-m", "0.1", "--transition-m", "-10"], "--transition-m"),
    (["--radius-m", "600", "--cant-m", "0.1", "--vehicle", "no_such_vehicle"], "--vehicle"),
])
def test_cli_bad_input_one_line_exit_2(tmp_path, capsys, args, option):
    from exudyn_wheelrail.cli import main
    code = main(["curving", "--vehicle", "manchester_vehicle1", "--speed-kmh", "100", "--out", str(tmp_path / "o")]
                + args)
    assert code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {option}:"), lines
    assert not (tmp_path / "o" / "summary.json").exists()


def test_outputs_by_the_scenarios_writer(tmp_path):
    """write_outputs: summary.json is strict JSON (a non-finite number is null, also in arrays and NumPy scalars);
    timeseries.csv holds every column in the result's order, 10 significant digits, NaN as nan."""
    ts = {"time_s": np.array([0.0, 1e-3]), "s_leading_m": np.array([0.0, 1.0 / 36.0]),
          "Y_w1_right_N": np.array([np.nan, 1234.56789012345])}
    summary = {"sum_Y_N": [1.0, float("nan")], "a": np.float64(np.inf), "b": np.array([1.5, -np.inf]), "n": 3}
    write_outputs(CurvingResult(summary=summary, timeseries=ts), tmp_path)

    def refuse(constant):
        raise AssertionError(f"{constant} in summary.json")

    s = json.loads((tmp_path / "summary.json").read_text(), parse_constant=refuse)
    assert s == {"sum_Y_N": [1.0, None], "a": None, "b": [1.5, None], "n": 3}
    rows = (tmp_path / "timeseries.csv").read_text().splitlines()
    assert rows == ["time_s,s_leading_m,Y_w1_right_N", "0,0,nan", "0.001,0.02777777778,1234.56789"]


def test_cli_contract_subprocess(tmp_path):
    # the exact command line of the contract, refused before any work (one process: the import cost)
    p = subprocess.run([sys.executable, "-m", "exudyn_wheelrail", "curving", "--vehicle", "manchester_vehicle1",
                        "--radius-m", "600", "--cant-m", "0.15", "--speed-kmh", "100", "--transition-m", "-1",
                        "--out", str(tmp_path / "o")], capture_output=True, text=True)
    assert p.returncode == 2 and p.stderr.strip().startswith("error: --transition-m:"), p.stderr


def test_body_torques_in_the_transition_follow_the_turning_frame():
    """In the transition the frame's angular velocity changes: the load on each body is -(I dOmega/dt + Omega x I
    Omega) (plus the wheelsets' gyroscopic part), with dOmega/dt taken here by central differences in time of the
    layout's Omega (itself checked against differences of the frame's rotation in test_track_layout.py)."""
    case = CurvingCase("manchester_vehicle1", radius_m=R, cant_m=H, speed_km_h=100.0, transition_m=60.0)
    h = build_curving(case)
    frame, layout, model = h.frame, h.layout, h.model
    V = 100 / 3.6
    car = model.car_body
    k = frame.bodies.index(car)
    t = (5.0 + 30.0 + model.wheelsets[0].p_cg_in_frame[0]) / V       # the car body's centre mid-transition
    s = model.track_distance_m(car.p_cg_in_frame[0], t)
    assert 5.0 < s < 65.0
    dt = 1e-4
    om = layout.frame_angular_velocity([s], V)[0]
    dom = (layout.frame_angular_velocity([s + V * dt], V)[0] - layout.frame_angular_velocity([s - V * dt], V)[0]) / (
        2 * dt)
    cb = h.vehicle.car_body
    inertia = np.diag([cb.Ixx_kg_m2, cb.Iyy_kg_m2, cb.Izz_kg_m2])
    _, T = frame.body_terms(t)
    np.testing.assert_allclose(T[k], -(inertia @ dom + np.cross(om, inertia @ om)), rtol=1e-6, atol=1e-6)
    # the yaw part is the car body's yaw inertia times V^2 dkappa/ds (cos(phi) of the canted frame)
    assert T[k, 2] == pytest.approx(-cb.Izz_kg_m2 * V * V / (R * 60.0), rel=0.02)


def test_irregularity_identically_zero_gives_the_perfect_track_run(deficiency_left):
    """A generated irregularity scaled by 0 (all channels exactly zero: the whole irregularity path, the faded
    table and the contact's channel evaluation, with nothing to add) leaves every result bit-identical."""
    from exudyn_wheelrail.scenarios.curving import spectral_irregularity
    case = CurvingCase("manchester_vehicle1", radius_m=R, cant_m=H, speed_km_h=120.0, direction="left")
    s = run_curving(dataclasses.replace(case, irregularity=spectral_irregularity(case, "german_low", 1,
                                                                                 scale=0.0))).summary
    assert s["irregularity"]["seed"] == 1 and "german_low" in s["irregularity"]["description"]
    skip = {"irregularity", "solve_seconds"}
    assert {k: v for k, v in s.items() if k not in skip} == {k: v for k, v in deficiency_left.items() if k not in skip}


def test_force_balance_over_a_generated_irregularity(deficiency_left):
    """Over a zero-mean irregularity the steady means still balance: for the whole vehicle in the track plane
    ΣΣY + guidance − m a_nc = Σ m_i ÿ_i (the bodies' lateral accelerations relative to the track frame), whose mean
    over the averaging window T is Σ m_i Δẏ_i / T.  The bodies move laterally at most as fast as the rails under
    them, V |dy_rail/ds|, with the suspension's lateral modes (~1 Hz) near the shortest excitation frequencies
    (V/λ ≥ 1.3 Hz in the 3–25 m band) allowed a factor 2: |Δẏ_i| ≤ 2 · 2 V max|dy_rail/ds|.  Tolerance: that bound
    over m plus the perfect track's 2 % (the contract's target)."""
    from exudyn_wheelrail.scenarios.curving import curving_distances, spectral_irregularity
    from exudyn_wheelrail.track.irregularities import channel_values
    case = CurvingCase("manchester_vehicle1", radius_m=R, cant_m=H, speed_km_h=120.0, direction="left")
    irr = spectral_irregularity(case, "german_low", 1, band_m=(3.0, 25.0))
    s = run_curving(dataclasses.replace(case, irregularity=irr)).summary
    assert s["status"] == "ok"
    m, V = s["vehicle_mass_kg"], 120.0 / 3.6
    a = _a_nc(120.0)
    run_m = curving_distances(case, load_vehicle("manchester_vehicle1"))["total_m"]
    ch = channel_values(irr, np.arange(0.0, run_m, 0.05))
    slope = max(np.max(np.abs(ch.d_alignment + 0.5 * ch.d_gauge)), np.max(np.abs(ch.d_alignment - 0.5 * ch.d_gauge)))
    assert slope > 1e-4                                  # the irregularity is there (a real test of the balance)
    t0, t1 = s["steady_window_s"]
    tol = 0.02 * abs(m * a) + m * 2.0 * 2.0 * V * slope / (t1 - t0)
    fb = s["force_balance"]
    assert abs(fb["sum_sum_Y_N"] + fb["guidance_lateral_N"] - m * a) < tol
    assert s["sum_Y_N"] != deficiency_left["sum_Y_N"]  # and the run responds to it


@pytest.mark.parametrize("args, option", [
    (["--irregularity-spectrum", "no_such_spectrum", "--seed", "1"], "--irregularity-spectrum"),
    (["--irregularity-spectrum", "german_low"], "--seed"),
    (["--seed", "1"], "--seed"),
    (["--irregularity-spectrum", "german_low", "--seed", "-1"], "--seed"),
])
def test_cli_irregularity_options_bad_input_one_line_exit_2(tmp_path, capsys, args, option):
    from exudyn_wheelrail.cli import main
    try:                        # an option argparse refuses (not a choice) exits from the parser
        code = main(["curving", "--vehicle", "manchester_vehicle1", "--radius-m", "600", "--cant-m", "0.15",
                     "--speed-kmh", "100", "--out", str(tmp_path / "o")] + args)
    except SystemExit as exc:
        code = exc.code
    assert code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {option}:"), lines
    assert not (tmp_path / "o").exists()


# ------------------------------------------------------------------------------------------------- gradient
GRADIENT = 0.08          # rise per length; 8 %: sin(atan(0.08)) and 0.08 differ by 0.32 %, above the tolerance below


def _free_rolling_acceleration(gradient, V=30.0, duration_s=0.3, fit_from_s=0.1):
    """A single wheelset (vehicles/single_wheelset.toml: its axle load a dead vertical force) free to roll along a
    straight layout of the given gradient: no longitudinal guidance spring or damper and no longitudinal restraint,
    so only gravity and the contact act along the track.  Returns (the wheelset's longitudinal acceleration relative
    to the frame moving with V, fitted to its velocity from ``fit_from_s`` on [m/s²], the vehicle data)."""
    import exudyn as exu

    from exudyn_wheelrail.multibody.connector import add_wheel_rail_contact, place_on_rails
    from exudyn_wheelrail.rolling_stock.track_following import TrackFollowingFrame
    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
    from exudyn_wheelrail.scenarios.curving import creep_step_limit_s
    from exudyn_wheelrail.simulation.runner import run
    from exudyn_wheelrail.simulation.settings import RunSettings
    from exudyn_wheelrail.track.layout import Straight, TrackLayout

    veh = load_vehicle_with_overrides("single_wheelset", {"primary.kx_N_per_m": 0.0, "primary.cx_N_s_per_m": 0.0})
    geo = veh.geometry
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    layout = TrackLayout([Straight(1000.0)], gradient=gradient)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    model = build_vehicle(mbs, veh, speed_m_s=V, s_start_m=0.0, longitudinal="none")
    contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=V, s_start_m=0.0, layout=layout)
    place_on_rails(mbs, model, pair)
    frame = TrackFollowingFrame(mbs, model, layout)
    mbs.Assemble()
    frame.update(mbs, 0.0)
    node = model.wheelsets[0].node
    rows = []

    def step(mbs_, t):
        frame.update(mbs_, t)
        rows.append((t, mbs_.GetNodeOutput(node, exu.OutputVariableType.Velocity)[0]))
        return True

    dt = min(1e-3, creep_step_limit_s(veh, V))
    out = run(mbs, RunSettings(solver="rk44", dt_s=dt, duration_s=duration_s), contact, speed_m_s=V,
              user_function=step)
    assert out.status.kind == "ok"
    t, v = np.array(rows).T
    on = t >= fit_from_s
    return float(np.polyfit(t[on], v[on], 1)[0]), veh


@pytest.fixture(scope="module")
def gradient_runs():
    return {g: _free_rolling_acceleration(g) for g in (GRADIENT, 0.0, -GRADIENT)}


def test_a_free_wheelset_rolls_down_a_gradient_with_g_sin_theta_times_its_mass_ratio(gradient_runs):
    """Reference (rigid wheel rolling without slip; the creepage the creep force needs is constant while the
    acceleration is, so it does not change the rate): along the track, gravity -m g sin(theta) (theta = atan of
    the gradient, positive uphill) and the contact force F on the wheelset, m a = -m g sin(theta) + F; about the axle
    the same F at the rolling radius r spins it up, I_yy a / r = r F; hence

        a = -g sin(theta) m / (m + I_yy / r²)      (uphill: backwards; downhill: forwards)

    with the wheelset's mass and spin inertia only: the axle load of this layout is a dead vertical force (no mass).
    On level track the same model decelerates slightly (rolling resistance of the spin creepage of the coned
    contacts, ~6e-4 m/s², the same on the gradient to O(1 - cos theta)): it is taken off by subtracting the level run.
    Tolerance 1e-3 relative: the rolling radius at the centred contact point differs from r0 by well below 0.5 mm,
    which moves the mass ratio by 2 (I/r²)/(m + I/r²) dr/r < 5e-4; the least-squares fit over 200 steps of a
    constant acceleration is exact up to the Hertz vertical oscillation's share (< 1e-5 m/s²)."""
    a_up, veh = gradient_runs[GRADIENT]
    a_level, _ = gradient_runs[0.0]
    a_down, _ = gradient_runs[-GRADIENT]
    m, I, r = veh.wheelset.mass_kg, veh.wheelset.Iyy_kg_m2, veh.geometry.r0_m
    ratio = m / (m + I / r ** 2)                                  # 0.774 for this wheelset
    a_ref = G * math.sin(math.atan(GRADIENT)) * ratio
    assert abs(a_level) < 2e-3 * a_ref                            # level track: (almost) no acceleration
    assert a_up < 0.0 < a_down                                    # uphill it rolls back, downhill it speeds up
    assert a_up - a_level == pytest.approx(-a_ref, rel=1e-3)
    assert a_down - a_level == pytest.approx(a_ref, rel=1e-3)


def test_gradient_loads_every_body_with_its_weight_in_the_pitched_track_frame():
    """Manchester vehicle on a straight 8 % gradient: gravity in the track frame pitched nose-up by theta = atan(0.08)
    is g (-sin(theta), 0, cos(theta)) (x forward, z down); the model integrates with (0, 0, g), so every body (car
    body, bogie frames, wheelsets) gets m g (-sin(theta), 0, cos(theta) - 1) and no torque (no curvature: the frame
    does not turn).  Sums of two or three products of numbers of order 1e5: 1e-12 relative."""
    import exudyn as exu

    from exudyn_wheelrail.rolling_stock.track_following import TrackFollowingFrame
    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
    from exudyn_wheelrail.track.layout import Straight, TrackLayout

    layout = TrackLayout([Straight(500.0)], gradient=GRADIENT)
    theta = math.atan(GRADIENT)
    s = np.array([0.0, 100.0])
    np.testing.assert_allclose(layout.gravity(s, G), [[-G * math.sin(theta), 0.0, G * math.cos(theta)]] * 2,
                               rtol=0, atol=1e-14 * G)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=30.0, s_start_m=50.0, gravity_m_s2=G)
    frame = TrackFollowingFrame(mbs, model, layout)
    F, T = frame.body_terms(1.0)
    m = np.array([b.mass_kg for b in frame.bodies])
    assert len(m) == 7 and m.sum() == pytest.approx(load_vehicle("manchester_vehicle1").total_mass_kg, rel=1e-15)
    ref = np.outer(m, [-G * math.sin(theta), 0.0, G * (math.cos(theta) - 1.0)])
    np.testing.assert_allclose(F, ref, rtol=1e-12, atol=1e-12 * m.max() * G)
    assert np.all(F[:, 0] < 0.0)                 # uphill: the weight pulls every body back
    np.testing.assert_allclose(T, 0.0, atol=1e-9)


# --------------------------------------------------------------------- the turning frame's terms by hand
@pytest.mark.parametrize("where, s_car", [("mid-transition", 20.0 + 30.0), ("circular curve", 20.0 + 60.0 + 40.0)])
def test_frame_loads_on_every_body_from_the_clothoid_closed_forms(where, s_car):
    """Every body of the Manchester vehicle (car body, bogie frames, wheelsets) at V = 100 km/h on a right curve
    R = 600 m, 150 mm cant, entered by a 60 m clothoid after 20 m of straight, all bodies inside the transition
    (car-body centre mid-transition) or inside the curve.  Reference, from the clothoid's closed forms alone (not
    through the layout module): u = (s - 20)/60 m, κ = u/R, dκ/ds = 1/(R L_T), cant h = u H, φ = asin(h/b),
    dφ/ds = (H/L_T)/(b cos φ) (b the rail-centre distance; in the curve u = 1 and the rates vanish).  The track frame
    (x forward, y right, z down) yaws at ψ̇ = V κ about the downward vertical and rolls at V dφ/ds about x, so in
    its own axes Ω = V (dφ/ds, κ sin φ, κ cos φ); Ω̇ by central differences (±1 cm) of that closed form.  The frame
    origin runs along the centre line at constant V: a_O = V² κ horizontally towards the centre, (0, V²κ cos φ,
    -V²κ sin φ) in track axes; gravity (0, g sin φ, g cos φ).  With the model integrating (0, 0, g) and the centre
    of mass at r = (0, y_cg, z_cg) from the frame origin, each body gets

        F = m (g_track - (0, 0, g) - a_O - Ω̇ × r - Ω × (Ω × r)),
        T = -dH/dt = -(I Ω̇ + Ω × I (Ω + ω_s)),

    the torque from the transport of the angular momentum H = I (Ω + ω_s) carried by the frame (ω_s = (0, -V/r0, 0)
    the wheelsets' spin, fixed in the frame; zero for the other bodies; valid for I_xx = I_zz, asserted).
    Tolerance: the differences' truncation (δ/L_T)² ~ 3e-8 of Ω̇, round-off ε V |Ω|/δ ~ 1e-12 of it: 1e-6
    relative, with an absolute floor of 1e-9 of m g (forces) and of |I| V²/(R L_T) (torques)."""
    import exudyn as exu

    from exudyn_wheelrail.rolling_stock.track_following import TrackFollowingFrame
    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
    from exudyn_wheelrail.track.layout import Curve, Straight, TrackLayout, Transition

    lead, lt, V = 20.0, 60.0, 100.0 / 3.6
    b = RAIL_CENTRE_DISTANCE_M
    layout = TrackLayout([Straight(lead), Transition(lt), Curve(400.0, R, H, "right")])
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    t = 1.0
    s0 = s_car - V * t                                 # the frame origin at t = 0 (the car body's centre at x = 0)
    model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=V, s_start_m=s0, gravity_m_s2=G)
    frame = TrackFollowingFrame(mbs, model, layout, gravity_m_s2=G)
    F, T = frame.body_terms(t)
    vehicle = load_vehicle("manchester_vehicle1")

    def omega(s):
        u = min(max((s - lead) / lt, 0.0), 1.0)
        on_ramp = lead < s < lead + lt
        kappa, phi = u / R, math.asin(u * H / b)
        dphi = H / lt / (b * math.cos(phi)) if on_ramp else 0.0
        return V * np.array([dphi, kappa * math.sin(phi), kappa * math.cos(phi)]), kappa, phi

    delta = 1e-2
    s_all = [s0 + V * t + body.p_cg_in_frame[0] for body in frame.bodies]          # each body's own frame
    assert all((lead + 1.0 < s < lead + lt - 1.0) if where == "mid-transition" else (s > lead + lt + 1.0)
               for s in s_all)
    wheelsets = {id(w) for w in model.wheelsets}
    n_checked = 0
    for k, (body, s) in enumerate(zip(frame.bodies, s_all)):
        Om, kappa, phi = omega(s)
        dOm = V * (omega(s + delta)[0] - omega(s - delta)[0]) / (2.0 * delta)
        m = body.mass_kg
        r = np.array([0.0, body.p_cg_in_frame[1], body.p_cg_in_frame[2]])
        g_track = np.array([0.0, G * math.sin(phi), G * math.cos(phi)])
        a_O = V * V * kappa * np.array([0.0, math.cos(phi), -math.sin(phi)])
        F_ref = m * (g_track - np.array([0.0, 0.0, G]) - a_O - np.cross(dOm, r) - np.cross(Om, np.cross(Om, r)))
        if id(body) in wheelsets:
            data, spin = vehicle.wheelset, np.array([0.0, -V / vehicle.geometry.r0_m, 0.0])
            assert data.Ixx_kg_m2 == data.Izz_kg_m2
        elif body is model.car_body:
            data, spin = vehicle.car_body, np.zeros(3)
        else:
            data, spin = vehicle.bogie_frame, np.zeros(3)
        assert m == data.mass_kg
        inertia = np.diag([data.Ixx_kg_m2, data.Iyy_kg_m2, data.Izz_kg_m2])
        T_ref = -(inertia @ dOm + np.cross(Om, inertia @ (Om + spin)))
        np.testing.assert_allclose(F[k], F_ref, rtol=1e-6, atol=1e-9 * m * G, err_msg=f"{where}: body {k} force")
        t_floor = 1e-9 * np.max(inertia) * V * V / (R * lt)
        np.testing.assert_allclose(T[k], T_ref, rtol=1e-6, atol=t_floor, err_msg=f"{where}: body {k} torque")
        n_checked += 1
    assert n_checked == 7
    if where == "mid-transition":
        # the yaw rate V κ cos φ and its rate V² (κ' cos φ - κ sin φ φ') on the car body: nonzero, so T_z is checked
        assert abs(T[frame.bodies.index(model.car_body), 2]) > 1e3


def test_chord_geometry_between_bodies_in_the_transition():
    """Part (c) of the track-following frame inside a clothoid, where the cant twists between bodies (Δφ ≠ 0, which
    the circular curve cannot show) and the heading is quadratic: every suspension element joining two bodies of
    the Manchester vehicle, all of them inside a 60 m transition to R = 600 m with a 150 mm cant ramp, against the
    clothoid's small-angle closed forms (not the layout module): with u = s - 20 m into the transition, ψ = u²/(2 R L_T),
    Ψ = ∫ψ ds = u³/(6 R L_T), φ = asin(u H/(L_T b)).  B's frame origin in A's frame lies at y_h = Ψ(s_B) - Ψ(s_A)
    - ψ(s_A)(s_B - s_A) (the chord's offset), turned by Δψ about the vertical and by Δφ about x: θ = (Δφ, Δψ sin φ_A,
    Δψ cos φ_A), δ = (0, y_h cos φ_A, -y_h sin φ_A) + θ × v.  Values below 0.1 m and rad, a few roundings each:
    1e-12 absolute."""
    import exudyn as exu

    from exudyn_wheelrail.rolling_stock.track_following import TrackFollowingFrame
    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
    from exudyn_wheelrail.track.layout import Curve, Straight, TrackLayout, Transition

    lead, lt, V, t = 20.0, 60.0, 100.0 / 3.6, 1.0
    b = RAIL_CENTRE_DISTANCE_M
    layout = TrackLayout([Straight(lead), Transition(lt), Curve(400.0, R, H, "right")])
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    s0 = lead + 0.5 * lt - V * t                      # the car body's centre mid-transition at t
    model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=V, s_start_m=s0, gravity_m_s2=G)
    frame = TrackFollowingFrame(mbs, model, layout, gravity_m_s2=G)
    delta, theta = frame.offsets(t)

    def psi(s):
        return (s - lead) ** 2 / (2.0 * R * lt)

    def Psi(s):
        return (s - lead) ** 3 / (6.0 * R * lt)

    def phi(s):
        return math.asin((s - lead) / lt * H / b)

    twisted = 0
    assert len(frame.elements) > 0
    for k, (_, kind, kA, kB, _, v, _) in enumerate(frame.elements):
        sA, sB = (s0 + V * t + frame.bodies[i].p_cg_in_frame[0] for i in (kA, kB))
        assert lead < min(sA, sB) and max(sA, sB) < lead + lt           # inside the transition
        y_h = Psi(sB) - Psi(sA) - psi(sA) * (sB - sA)
        d_psi, pA = psi(sB) - psi(sA), phi(sA)
        th = np.array([phi(sB) - pA, d_psi * math.sin(pA), d_psi * math.cos(pA)])
        np.testing.assert_allclose(theta[k], th, rtol=0, atol=1e-12, err_msg=f"element {k} ({kind}): theta")
        ref = np.array([0.0, y_h * math.cos(pA), -y_h * math.sin(pA)]) + np.cross(th, v)
        np.testing.assert_allclose(delta[k], ref, rtol=0, atol=1e-12, err_msg=f"element {k} ({kind}): delta")
        twisted += abs(th[0]) > 1e-3
    assert twisted >= 2                               # the car body to its bogies: a cant twist of a few mrad
