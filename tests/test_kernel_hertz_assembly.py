"""The kernel's assembly of the normal problem: rolling curvature (Meusnier), relative curvatures A, B, semi-axes and
normal force, checked for a coned wheel on a circular crown against values computed here from the geometry.

References: Meusnier's theorem for a surface of revolution (the normal curvature of a parallel circle of radius r is
cos(psi)/r, psi = angle between the surface normal and the radial direction); Hertz through
``exudyn_wheelrail.contact.normal`` (tested on its own against the m, n table and a direct integration).
"""
import numpy as np
import pytest

from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact.normal import effective_modulus, hertz_from_penetration
from exudyn_wheelrail.profiles import RailProfile, WheelProfile

CONICITY = 0.05
CROWN_R = 0.08
R0 = 0.46


@pytest.fixture(scope="module")
def cone_pair():
    return WheelRailPair(WheelProfile.cone(CONICITY), RailProfile.circular_crown(CROWN_R, half_width_m=0.05),
                         gauge_m=1.41, inclination="none", back_to_back_m=1.36, r0_m=R0)


@pytest.mark.parametrize("y, roll, lower", [(0.0, 0.0, 60e-6), (0.002, 1e-3, 80e-6), (-0.003, 0.5e-3, 40e-6)])
def test_rolling_curvature_relative_curvatures_and_hertz(cone_pair, y, roll, lower):
    contact = WheelsetContact(cone_pair, global_search=True)
    out = contact.evaluate(np.array([[y, -R0 + lower, roll]]))
    o = out[0, 0]
    assert o[K.F_STATUS] == K.STATUS_CONVEX and o[K.F_PENETRATION] > 0
    # wheel point in the wheelset frame: radius r = its z; the cone's outward normal makes the angle atan(conicity)
    # with the radial direction, independent of where on the cone (a straight generatrix)
    r = o[K.F_ROLLING_RADIUS]
    psi = np.arctan(CONICITY)
    assert o[K.F_KW_ROLL] == pytest.approx(np.cos(psi) / r, rel=1e-9)
    assert o[K.F_KW_LAT] == pytest.approx(0.0, abs=1e-6)           # straight generatrix
    assert o[K.F_KR_LAT] == pytest.approx(1 / CROWN_R, rel=1e-6)   # crown
    assert o[K.F_KR_ROLL] == 0.0                                   # straight track
    A = 0.5 * np.cos(psi) / r
    B = 0.5 / CROWN_R
    assert o[K.F_A_REL] == pytest.approx(A, rel=1e-6)
    assert o[K.F_B_REL] == pytest.approx(B, rel=1e-6)
    n, dn, a, b, status = hertz_from_penetration(A, B, effective_modulus(2.1e11, 0.28, 2.1e11, 0.28),
                                                 o[K.F_PENETRATION])
    assert status == 0
    assert o[K.F_NORMAL_FORCE] == pytest.approx(n, rel=1e-6)
    assert o[K.F_DN_DDELTA] == pytest.approx(dn, rel=1e-6)
    assert (o[K.F_SEMI_A], o[K.F_SEMI_B]) == pytest.approx((a, b), rel=1e-6)
    assert a > b        # A < B: the longer semi-axis lies along rolling (smaller relative curvature)


def test_invalid_pose_is_flagged_by_the_compiled_kernel(cone_pair):
    contact = WheelsetContact(cone_pair)
    poses = contact.side_poses(np.array([[0.0, -R0, 0.0]])).copy()
    poses[0, 1] = np.nan
    K.evaluate_wheels(contact.nodes, contact.meta, contact.mono, contact.curve_ids, poses, contact.warm,
                      contact.params, contact.out)
    assert np.all(contact.out[0, :, K.F_STATUS] == K.STATUS_INVALID_POSE)
    assert np.all(np.isnan(contact.out[0, :, K.F_NORMAL_FORCE]))
    assert np.all(contact.out[1, :, K.F_STATUS] != K.STATUS_INVALID_POSE)     # the other wheel is evaluated


def test_deep_penetration_and_profile_end_are_flagged(cone_pair):
    contact = WheelsetContact(cone_pair, global_search=True)
    deep = contact.evaluate(np.array([[0.0, -R0 + 0.01, 0.0]]))[0, 0]       # 10 mm into the rail
    assert int(deep[K.F_FLAGS]) & K.FLAG_DEEP_PENETRATION
    off = contact.evaluate(np.array([[0.06, -R0, 0.0]]))[0, 0]             # shifted beyond the cone's 50 mm
    assert int(off[K.F_FLAGS]) & K.FLAG_PROFILE_END or off[K.F_STATUS] == K.STATUS_NO_OVERLAP
