"""Arc-length curves against analytic curves (circle, ellipse)."""
import numpy as np
import pytest

from exudyn_wheelrail.contact.pair import WheelRailPair
from exudyn_wheelrail.contact.search import rail_point, wheel_point, wheel_position
from exudyn_wheelrail.profiles.curve import ProfileCurve, pack_curves, curve_eval, curve_point
from exudyn_wheelrail.profiles.dense import DenseProfile


def ellipse_dense(a=0.02, b=0.01, n=20001):
    # lower half of an ellipse, ordered with increasing y; z down -> bulges towards +z (a wheel-like convex cap)
    t = np.linspace(np.pi * 0.9, np.pi * 0.1, n)
    return DenseProfile(a * np.cos(t), b * np.sin(t), -a * np.sin(t), b * np.cos(t), -a * np.cos(t), -b * np.sin(t),
                        name="ellipse"), (a, b)


def test_ellipse_position_tangent_curvature_between_nodes():
    dense, (a, b) = ellipse_dense()
    curve = ProfileCurve.from_dense(dense, outward="+z", node_spacing_m=5e-4)
    s = np.linspace(curve.s_min, curve.s_max, 3001)
    e = curve.evaluate(s)
    # analytic: the point lies on the ellipse, the tangent is the ellipse tangent, curvature a b / (..)^1.5
    t = np.arctan2(e[:, 1] / b, e[:, 0] / a)
    assert np.max(np.abs((e[:, 0] / a) ** 2 + (e[:, 1] / b) ** 2 - 1)) < 1e-8
    tan = np.column_stack([-a * np.sin(t), b * np.cos(t)])
    tan /= np.hypot(*tan.T)[:, None]
    assert np.max(np.abs(np.abs(np.sum(tan * e[:, 2:4], axis=1)) - 1)) < 1e-9
    kappa = a * b / (a * a * np.sin(t) ** 2 + b * b * np.cos(t) ** 2) ** 1.5
    assert np.max(np.abs(e[:, 6] / kappa - 1)) < 1e-5            # convex cap: positive curvature
    assert np.all(e[:, 5] > 0)                                    # outward normal towards +z
    # arc length: total length against the elliptic integral
    from scipy.special import ellipeinc
    m = 1 - (b / a) ** 2
    exact = a * (ellipeinc(np.pi * 0.4, m) - ellipeinc(-np.pi * 0.4, m))
    assert curve.length == pytest.approx(exact, rel=1e-9)


def test_transformed_and_sub_keep_the_parameter():
    dense, _ = ellipse_dense()
    curve = ProfileCurve.from_dense(dense, outward="+z")
    moved = curve.transformed(0.1, (0.5, -0.2))
    s = np.linspace(curve.s_min, curve.s_max, 101)
    p, q = curve.position(s), moved.position(s)
    rot = np.array([[np.cos(0.1), -np.sin(0.1)], [np.sin(0.1), np.cos(0.1)]])
    assert np.allclose(q, p @ rot.T + [0.5, -0.2], atol=1e-12)
    assert np.allclose(curve.curvature(s), moved.curvature(s), rtol=1e-10)
    part = curve.sub(0.01, 0.02)
    sp = np.linspace(0.01, 0.02, 101)
    assert np.allclose(part.position(sp), curve.position(sp), atol=1e-9)
    nodes, meta = pack_curves([curve, part])
    assert np.allclose(curve_eval(nodes, meta, 1, 0.015), curve_eval(curve.nodes, curve.meta, 0, 0.015), atol=1e-9)


def test_extension_beyond_the_ends_is_straight():
    dense, _ = ellipse_dense()
    curve = ProfileCurve.from_dense(dense, outward="+z")
    end = curve.evaluate([curve.s_max])[0]
    beyond = curve.evaluate([curve.s_max + 1e-3])[0]
    assert np.allclose(beyond[0:2], end[0:2] + 1e-3 * end[2:4], atol=1e-12)
    assert beyond[6] == 0.0  # straight extension: zero curvature, exact


def test_point_and_tangent_alone_are_those_of_the_full_evaluation():
    # curve_point (the searches that need no curvature) runs the same arithmetic as curve_eval without the second
    # derivatives: the same numbers bit for bit, inside, on the nodes (segment ends) and on the straight extensions
    nodes, meta = WheelRailPair().packed()
    pose = (3e-3, -0.46, 0.96, 1e-3, 2e-3 ** 0.5)    # c_y, c_z, cos and sin of a roll (any numbers)
    for c in range(meta.shape[0]):
        first, count = int(meta[c, 0]), int(meta[c, 1])
        lo, hi = nodes[first, 0], nodes[first + count - 1, 0]
        s_all = np.concatenate([np.linspace(lo - 2e-3, hi + 2e-3, 4001), nodes[first:first + count, 0]])
        for s in s_all:
            full = curve_eval(nodes, meta, c, s)
            assert curve_point(nodes, meta, c, s) == full[:4]
            assert rail_point(nodes, meta, c, s) == (full[0], full[1], full[4], full[5])
            assert wheel_position(nodes, meta, c, s, *pose[:2], pose[2], pose[4]) == \
                wheel_point(nodes, meta, c, s, *pose[:2], pose[2], pose[4])[:2]


def test_bad_input():
    with pytest.raises(ValueError, match="NaN"):
        DenseProfile(np.array([0, 1, np.nan, 3.0]), np.zeros(4), np.ones(4), np.zeros(4), np.zeros(4), np.zeros(4))
    with pytest.raises(ValueError, match="outward"):
        dense, _ = ellipse_dense()
        ProfileCurve.from_dense(dense, outward="up")
