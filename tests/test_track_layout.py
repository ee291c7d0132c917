"""The track layout (exudyn_wheelrail/track/layout.py) against independent references: the clothoid's curvature is
linear in s and its position is given by the Fresnel integrals, the heading is the integral of the curvature, the
cant ramp is linear, left curves mirror right ones, the frame kinematics match finite differences of the frame."""
import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import fresnel

from exudyn_wheelrail.conventions import RAIL_CENTRE_DISTANCE_M
from exudyn_wheelrail.track.layout import MAX_CANT_M, Curve, LayoutError, Straight, TrackLayout, Transition, layout_at

R, LT, H, LEAD = 600.0, 80.0, 0.15, 20.0


@pytest.fixture(scope="module")
def entry():
    return TrackLayout([Straight(LEAD), Transition(LT), Curve(300.0, R, H, "right"), Transition(LT),
                        Straight(50.0)])


def test_clothoid_curvature_linear_and_cant_ramp(entry):
    s = np.linspace(LEAD, LEAD + LT, 41)
    u = (s - LEAD) / LT
    np.testing.assert_allclose(entry.curvature(s), u / R, rtol=0, atol=1e-15)
    np.testing.assert_allclose(entry.curvature_rate(s[:-1]), 1.0 / (R * LT), rtol=1e-12)
    np.testing.assert_allclose(entry.cant_m(s), H * u, rtol=0, atol=1e-15)
    # the rate of the cant angle is the ramp's rate over the base and cos(phi)
    phi = entry.cant_angle(s[:-1])
    np.testing.assert_allclose(entry.cant_angle_rate(s[:-1]), H / LT / (RAIL_CENTRE_DISTANCE_M * np.cos(phi)), rtol=1e-12)
    # the curve, the exit transition back to zero and the straight after it
    assert entry.curvature([LEAD + LT + 100])[0] == pytest.approx(1 / R, rel=1e-15)
    assert entry.cant_angle([LEAD + LT + 100])[0] == pytest.approx(math.asin(H / RAIL_CENTRE_DISTANCE_M), rel=1e-15)
    mid_exit = LEAD + LT + 300 + LT / 2
    assert entry.curvature([mid_exit])[0] == pytest.approx(0.5 / R, rel=1e-12)
    # back to straight and level: exact zeros
    assert entry.curvature([entry.end_m + 10])[0] == 0.0 and entry.cant_m([entry.end_m + 10])[0] == 0.0


def test_clothoid_position_against_fresnel_integrals(entry):
    # clothoid from a straight: x = A sqrt(pi) C(u/(A sqrt(pi))), y = A sqrt(pi) S(...), A^2 = R L (the Fresnel
    # integrals of scipy: C(t) = int cos(pi t'^2/2)); the quadrature of the layout is independent of them
    A = math.sqrt(R * LT)
    u = np.linspace(0.0, LT, 17)
    S_f, C_f = fresnel(u / (A * math.sqrt(math.pi)))
    p = entry.position(LEAD + u)
    np.testing.assert_allclose(p[:, 0], LEAD + A * math.sqrt(math.pi) * C_f, rtol=0, atol=1e-9)
    np.testing.assert_allclose(p[:, 1], A * math.sqrt(math.pi) * S_f, rtol=0, atol=1e-9)
    # heading: u^2 / (2 R L) in the transition
    np.testing.assert_allclose(entry.heading(LEAD + u), u ** 2 / (2 * R * LT), rtol=1e-13, atol=1e-16)


def test_heading_and_position_against_numerical_integration(entry):
    # a fine numerical integration of kappa (heading) and of (cos, sin)(heading) (position) over the whole layout,
    # both independent of the layout's exact per-piece formulas and its Gauss-Legendre quadrature
    s_end = entry.end_m + 30.0
    s = np.linspace(0.0, s_end, 200001)
    k = entry.curvature(s)
    psi = np.concatenate(([0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * np.diff(s))))
    x = np.concatenate(([0.0], np.cumsum(0.5 * (np.cos(psi[1:]) + np.cos(psi[:-1])) * np.diff(s))))
    y = np.concatenate(([0.0], np.cumsum(0.5 * (np.sin(psi[1:]) + np.sin(psi[:-1])) * np.diff(s))))
    pick = np.linspace(0, len(s) - 1, 23).astype(int)
    # trapezoid errors: h^2/12 * L * max|f''| with h = 3.1 mm: below 1e-7 rad and 1e-6 m here
    np.testing.assert_allclose(entry.heading(s[pick]), psi[pick], atol=1e-7)
    p = entry.position(s[pick])
    np.testing.assert_allclose(p[:, 0], x[pick], atol=1e-6)
    np.testing.assert_allclose(p[:, 1], y[pick], atol=1e-6)
    # the integral of the heading (used for the chord geometry between bodies) against quad
    hp = entry.heading_and_integral([150.0, 400.0])
    ref = [quad(lambda v: entry.heading([v])[0], 0.0, b, limit=400, points=[LEAD, LEAD + LT, 400.0])[0]
           for b in (150.0, 400.0)]
    np.testing.assert_allclose(hp[:, 1], ref, rtol=1e-9)


def test_left_curve_mirrors_right():
    right = TrackLayout([Straight(10.0), Transition(40.0), Curve(100.0, 500.0, 0.1, "right")])
    left = TrackLayout([Straight(10.0), Transition(40.0), Curve(100.0, 500.0, 0.1, "left")])
    s = np.linspace(-5.0, 200.0, 57)
    # the same operations on negated inputs (rounding symmetric under negation, asin odd, cos even): exact
    np.testing.assert_array_equal(left.evaluate(s), -right.evaluate(s))
    np.testing.assert_allclose(left.position(s)[:, 1], -right.position(s)[:, 1], atol=1e-12)
    a_r = right.unbalanced_lateral_acceleration(s, 25.0, 9.81)
    a_l = left.unbalanced_lateral_acceleration(s, 25.0, 9.81)
    np.testing.assert_allclose(a_l, a_r, atol=1e-15)
    # in the curve: V^2/R cos(phi) - g sin(phi), positive outwards (conventions)
    phi = math.asin(0.1 / RAIL_CENTRE_DISTANCE_M)
    assert a_r[-1] == pytest.approx(25.0 ** 2 / 500.0 * math.cos(phi) - 9.81 * math.sin(phi), rel=1e-14)


def test_frame_kinematics_against_differences_of_the_rotation(entry):
    # Omega (track components) = vee(R^T dR/dt) with R(s(t)) the frame's rotation, by central differences
    V = 30.0
    lay = TrackLayout([Straight(LEAD), Transition(LT), Curve(300.0, R, H, "right")], gradient=0.02)
    for s0 in (LEAD + 30.0, LEAD + LT + 50.0):
        h = 1e-4
        Rm, Rp = lay.rotation([s0 - h])[0], lay.rotation([s0 + h])[0]
        R0 = lay.rotation([s0])[0]
        W = R0.T @ (Rp - Rm) / (2 * h / V)
        omega = np.array([W[2, 1], W[0, 2], W[1, 0]])
        np.testing.assert_allclose(lay.frame_angular_velocity([s0], V)[0], omega, atol=1e-9)
        # acceleration of the origin: second difference of the global position, in track components
        hh = 1e-2
        pm, p0, pp = lay.position([s0 - hh, s0, s0 + hh])
        a_glob = (pp - 2 * p0 + pm) / (hh / V) ** 2
        np.testing.assert_allclose(lay.frame_acceleration([s0], V)[0], R0.T @ a_glob, atol=2e-5)
        # its rate: central differences of Omega along the track (inside the ramp phi'' = phi'^2 tan(phi) != 0)
        dom = (lay.frame_angular_velocity([s0 + V * 1e-4], V)[0] - lay.frame_angular_velocity([s0 - V * 1e-4], V)[0]
               ) / 2e-4
        np.testing.assert_allclose(lay.frame_angular_acceleration([s0], V)[0], dom, rtol=1e-6, atol=1e-12)
        # gravity (0, 0, g) in the track frame
        np.testing.assert_allclose(lay.gravity([s0], 9.81)[0], R0.T @ np.array([0.0, 0.0, 9.81]), atol=1e-12)


def test_compiled_evaluation_matches_and_clamps_outside(entry):
    """The compiled layout_at against the transition's closed forms a quarter into the entry clothoid (u = 1/4:
    κ = u/R, dκ/ds = 1/(R L_T), cant u H: φ = asin(u H / b), dφ/ds = (H/L_T)/(b cos φ), b the rail-centre distance),
    and straight and level before the first piece and after the last (this layout ends on a straight)."""
    p = entry.packed()
    out = np.zeros(4)
    layout_at(p.pieces, p.par, -100.0, out)
    assert np.all(out == 0.0)  # before the first piece: straight and level, exact zeros
    layout_at(p.pieces, p.par, entry.end_m + 100.0, out)
    assert np.all(out == 0.0)  # after the last piece: the final straight's values, exact zeros
    u = 0.25
    layout_at(p.pieces, p.par, LEAD + u * LT, out)
    phi = math.asin(u * H / RAIL_CENTRE_DISTANCE_M)
    expected = [u / R, 1.0 / (R * LT), phi, H / LT / (RAIL_CENTRE_DISTANCE_M * math.cos(phi))]
    # a few roundings per value (the piece's interpolation, asin, cos): 8 eps relative
    np.testing.assert_allclose(out, expected, rtol=8 * np.finfo(float).eps, atol=0.0)


@pytest.mark.parametrize("section, key", [(Curve(10.0, -5.0), "radius_m"), (Curve(10.0, 500.0, 150.0), "cant_m"),
                                          (Curve(10.0, 500.0, MAX_CANT_M + 0.01), "cant_m"),
                                          (Transition(-1.0), "length_m"), (Curve(10.0, 500.0, 0.1, "up"),
                                                                           "direction")])
def test_bad_sections_name_the_key(section, key):
    with pytest.raises(LayoutError, match=key):
        TrackLayout([Straight(5.0), section])
