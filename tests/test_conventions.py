"""The sign conventions written in exudyn_wheelrail/conventions.py, checked one by one on real geometry."""
import numpy as np
import pytest

from exudyn_wheelrail.analysis.geometry_functions import contact_geometry_sweep
from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
from exudyn_wheelrail.contact.pair import gauge_point
from exudyn_wheelrail.conventions import GAUGE_MEASURING_DEPTH_M, parse_inclination


@pytest.fixture(scope="module")
def pair():
    return WheelRailPair("S1002", "UIC60", gauge_m=1.435, inclination="1/40", back_to_back_m=1.360, r0_m=0.46)


def _at_y(curve, y):
    s = np.linspace(curve.s_min, curve.s_max, 20001)
    e = curve.evaluate(s)
    return e[np.argmin(np.abs(e[:, 0] - y) + 1e3 * (np.abs(np.arctan2(e[:, 3], e[:, 2])) > 1.2))]


def test_outward_normals_and_convex_positive_curvature(pair):
    # rail crown: outward normal points up (-z), UIC60 crown radius 300 mm -> kappa = +1/0.3
    top = _at_y(pair.rail.curve, 0.0)
    assert top[5] < -0.99
    assert top[6] == pytest.approx(1 / 0.300, rel=1e-6)
    # wheel tread at the tape circle: outward normal points down (+z, towards the rail)
    tape = _at_y(pair.wheel.curve, 0.0)
    assert tape[5] > 0.99
    # S1002 throat (section D, R13 concave) has negative curvature, the flange tip (R12) positive
    throat = _at_y(pair.wheel.curve, -0.0365)
    assert throat[6] == pytest.approx(-1 / 0.013, rel=1e-6)
    tip = _at_y(pair.wheel.curve, -0.055)
    assert tip[6] == pytest.approx(1 / 0.012, rel=1e-6)


def test_gauge_point_and_rail_top(pair):
    z_top, y_gauge = gauge_point(pair.rail_side)
    assert z_top == pytest.approx(0.0, abs=1e-12)
    assert y_gauge == pytest.approx(0.5 * 1.435, abs=1e-9)
    # the gauge point is 14 mm below the top and is the most inward point of the head at that depth
    s = np.linspace(pair.rail_side.s_min, pair.rail_side.s_max, 200001)
    p = pair.rail_side.position(s)
    band = np.abs(p[:, 1] - GAUGE_MEASURING_DEPTH_M) < 2e-6
    assert np.min(p[band, 0]) == pytest.approx(0.7175, abs=2e-6)


def test_rail_inclination_tilts_head_towards_track_centre(pair):
    # at the crown centre (vertical rail: normal straight up) the 1:40 rail's normal leans towards the track centre
    # (-y in the side frame) by exactly atan(1/40): n = (-sin a, -cos a)
    vertical = WheelRailPair(pair.wheel, pair.rail, inclination="none")
    s = np.linspace(vertical.rail_side.s_min, vertical.rail_side.s_max, 200001)
    e_v = vertical.rail_side.evaluate(s)
    s_crown = s[np.argmin(np.abs(e_v[:, 4]))]
    n_inclined = pair.rail_side.normal([s_crown])[0]
    alpha = np.arctan(1 / 40)
    assert n_inclined == pytest.approx([-np.sin(alpha), -np.cos(alpha)], abs=1e-9)


def test_positive_roll_lowers_right_wheel_and_positive_y_moves_right(pair):
    c = WheelsetContact(pair, global_search=True)
    base = c.evaluate(np.array([[0.0, -0.46, 0.0]])).copy()
    rolled = c.evaluate(np.array([[0.0, -0.46, 1e-3]])).copy()
    # right wheel (index 0) penetrates more, left (index 1) less
    assert rolled[0, 0, 9] > base[0, 0, 9] + 1e-4
    assert rolled[1, 0, 9] < base[1, 0, 9] - 1e-4
    shifted = c.evaluate(np.array([[0.004, -0.46, 0.0]])).copy()
    # moving right: the right flange gets closer to its rail, the left one further away
    assert shifted[0, 1, 9] > base[0, 1, 9]
    assert shifted[1, 1, 9] < base[1, 1, 9]


def test_contact_angle_positive_on_the_flange_side_of_both_wheels(pair):
    sweep = contact_geometry_sweep(pair, [-0.008, 0.008])
    flange = [r for r in sweep.rows if r["region"] == "flange"]
    assert {r["side"] for r in flange} == {"left", "right"}
    assert all(r["contact_angle_rad"] > 0.5 for r in flange)
    assert [r["side"] for r in flange if r["y_m"] > 0] == ["right"]


def test_parse_inclination():
    assert parse_inclination("1/40") == pytest.approx(0.025)
    assert parse_inclination("1:20") == pytest.approx(0.05)
    assert parse_inclination("none") == 0.0
    assert parse_inclination(0.03) == 0.03


def test_cross_level_and_gauge_per_rail(pair):
    """Track irregularities (per rail): the rail-centre distance that turns cross level into a roll is that of the
    placed rail heads; cross level = z_right - z_left (+ right rail lower) is a positive roll; gauge = y_right -
    y_left (+ wider)."""
    from exudyn_wheelrail.conventions import RAIL_CENTRE_DISTANCE_M
    from exudyn_wheelrail.track.rigid import Harmonic
    from exudyn_wheelrail.track.irregularities import IsolatedDefect, channel_values, rail_values
    # the head's centre at the gauge depth: midway between its gauge face (at gauge/2) and its field face; UIC60's
    # 72 mm head on a 1435 mm gauge puts the centres 1.507 m apart: 1.5 m within 1 %
    s = np.linspace(pair.rail_side.s_min, pair.rail_side.s_max, 200001)
    p = pair.rail_side.position(s)
    band = np.abs(p[:, 1] - GAUGE_MEASURING_DEPTH_M) < 2e-6
    centre = 0.5 * (np.min(p[band, 0]) + np.max(p[band, 0]))
    assert 2 * centre == pytest.approx(RAIL_CENTRE_DISTANCE_M, rel=0.01)
    # a dip of the right rail only is a positive cross level; rolling the rail pair by asin(c/b) lowers the right
    # rail centre (y = b/2) by b/2 sin θ = c/2 and lifts the left one by as much
    d = 3e-3
    dip = IsolatedDefect("bump", 0.0, 2.0, d, rail="right")
    r = rail_values(dip, [1.0])
    c = channel_values(dip, [1.0]).cross_level_m[0]
    assert (r["z_right_m"][0], r["z_left_m"][0], c) == pytest.approx((d, 0.0, d), abs=1e-15)
    theta = np.arcsin(c / RAIL_CENTRE_DISTANCE_M)
    assert theta > 0 and 0.5 * RAIL_CENTRE_DISTANCE_M * np.sin(theta) == pytest.approx(c / 2, rel=1e-12)
    # a positive gauge deviation moves the right rail right and the left rail left by half of it each
    wide = rail_values(Harmonic(2e-3, 40.0, phase_rad=np.pi / 2, direction="gauge"), [0.0])
    assert (wide["y_right_m"][0], wide["y_left_m"][0]) == pytest.approx((1e-3, -1e-3), abs=1e-15)


def test_curve_sign_right_hand_curve_positive_outer_rail_raised():
    """conventions.py, "Curves, cant and gradient": kappa > 0 turns right (the centre on +y), the cant raises the
    outer (left) rail, outwards is -sign(kappa) y, a_nc = V^2 |kappa| cos(phi) - g sin|phi|."""
    from exudyn_wheelrail.conventions import RAIL_CENTRE_DISTANCE_M, CURVE_DIRECTION_SIGN, outward_sign
    from exudyn_wheelrail.track.layout import Curve, TrackLayout

    R, h = 500.0, 0.12
    lay = TrackLayout([Curve(200.0, R, h, "right")])
    s = 100.0
    kappa, _, phi, _ = lay.evaluate([s])[0]
    assert kappa == pytest.approx(1 / R) and CURVE_DIRECTION_SIGN["right"] == 1.0
    assert phi == pytest.approx(np.arcsin(h / RAIL_CENTRE_DISTANCE_M))
    p = lay.position([s])[0]
    centre = np.array([0.0, R, 0.0])                       # right-hand curve from the origin along +x
    assert np.linalg.norm(p - centre) == pytest.approx(R, rel=1e-9)
    Rot = lay.rotation([s])[0]
    left_rail, right_rail = Rot @ [0.0, -0.75, 0.0], Rot @ [0.0, 0.75, 0.0]
    assert left_rail[2] - right_rail[2] == pytest.approx(-2 * 0.75 * h / RAIL_CENTRE_DISTANCE_M, rel=1e-12)   # left higher
    assert outward_sign(kappa) == -1.0 and outward_sign(-kappa) == 1.0
    V, g = 25.0, 9.81
    assert lay.unbalanced_lateral_acceleration([s], V, g)[0] == pytest.approx(
        V ** 2 / R * np.cos(phi) - g * np.sin(phi), rel=1e-14)
