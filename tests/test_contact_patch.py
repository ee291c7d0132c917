"""The non-Hertzian contact patch (exudyn_wheelrail.contact.patch) and its exact reference, the normal contact
problem on the half-space solved on a grid (exudyn_wheelrail.contact.halfspace).

Independent references: Hertz's closed form (the half-space solver's check, and the patch method's on quadratic
geometry, where both must give Hertz's ellipse); the contact conditions themselves (no interpenetration, no
tension), recomputed here from Boussinesq's point-load solution; the exact half-space solution on the S1002/UIC60
profiles' own interpenetration (the patch method's check where Hertz does not hold).
"""
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.analysis.quasi_static import solve_quasi_static
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact import patch as P
from exudyn_wheelrail.contact.halfspace import solve_halfspace, solve_strip_geometry
from exudyn_wheelrail.contact.normal import hertz_from_penetration

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
import manchester_a22 as A22  # noqa: E402

E_STAR = 2.1e11 / (2.0 * (1.0 - 0.3 ** 2))
DELTA = 5e-5

#: the targets of the patch against the exact half-space solution: normal force at a given penetration, patch area,
#: contact angle of the resultant (relative errors)
FORCE_TOL, AREA_TOL, ANGLE_TOL = 0.03, 0.10, 0.02


def hertz_grid(A, B, cells):
    """A grid of ``2 cells`` centres per axis over the interpenetration ellipse of δ = DELTA."""
    ax, by = math.sqrt(DELTA / A), math.sqrt(DELTA / B)
    x = -ax + (np.arange(2 * cells) + 0.5) * ax / cells
    y = -by + (np.arange(2 * cells) + 0.5) * by / cells
    return x, y, DELTA - A * x[None, :] ** 2 - B * y[:, None] ** 2


@pytest.mark.parametrize("A, B", [(1.0, 1.0), (0.5, 3.0)])
def test_halfspace_solution_is_hertz_within_the_grid_error(A, B):
    n, _, a, b, _ = hertz_from_penetration(A, B, E_STAR, DELTA, 0.0)
    x, y, d = hertz_grid(A, B, 16)
    sol = solve_halfspace(x, y, d, E_STAR)
    h = max(x[1] - x[0], y[1] - y[0])
    # the patch's edge is resolved to a cell: the area within the band of half a cell diagonal along the perimeter
    # (Ramanujan's perimeter of the ellipse)
    perimeter = math.pi * (3 * (a + b) - math.sqrt((3 * a + b) * (a + 3 * b)))
    band = perimeter * 0.5 * math.hypot(x[1] - x[0], y[1] - y[0]) / (math.pi * a * b)
    assert sol.area_m2 == pytest.approx(math.pi * a * b, rel=band)
    # force and peak pressure: the pressure vanishes at the edge like √(distance), so the edge band's share of the
    # force is of order band^(3/2); collocation at the centres is second order in h inside
    assert sol.normal_force_N == pytest.approx(n, rel=band ** 1.5)
    assert sol.peak_pressure_Pa == pytest.approx(1.5 * n / (math.pi * a * b), rel=band ** 1.5 + (h / b) ** 2)
    # the pressure field itself: Hertz's at every cell centre within the edge band's error of p0
    p0 = 1.5 * n / (math.pi * a * b)
    X, Y = np.meshgrid(x, y)
    semi = np.sqrt(np.clip(1 - (X / a) ** 2 - (Y / b) ** 2, 0, None))
    assert np.abs(sol.pressure_Pa - p0 * semi).max() < p0 * math.sqrt(2.5 * band)


def test_halfspace_solution_meets_the_contact_conditions():
    """No tension, and no interpenetration anywhere: the displacement recomputed from Boussinesq's point load
    (each cell's force at its centre, a cell's own contribution from the exact integral over a square) is at least
    the interpenetration at every centre, equal to it where loaded (within the point-load sum's error)."""
    x, y, d = hertz_grid(0.7, 2.0, 10)
    sol = solve_halfspace(x, y, d, E_STAR)
    assert (sol.pressure_Pa >= 0).all()
    dx, dy = x[1] - x[0], y[1] - y[0]
    X, Y = np.meshgrid(x, y)
    force = sol.pressure_Pa * dx * dy
    u = np.zeros_like(d)
    # own cell: ∬ 1/r over a dx × dy rectangle from its centre
    own = 2 * (dx * math.asinh(dy / dx) + dy * math.asinh(dx / dy))
    for j in range(y.size):
        for i in range(x.size):
            r = np.hypot(X - x[i], Y - y[j])
            r[j, i] = np.inf
            u[j, i] = (np.sum(force / r) + sol.pressure_Pa[j, i] * own) / (math.pi * E_STAR)
    loaded = sol.pressure_Pa > 0
    assert np.abs(u[loaded] - d[loaded]).max() < 0.03 * DELTA
    assert (u[~loaded] - d[~loaded]).min() > -0.03 * DELTA


@pytest.mark.parametrize("A, B", [(1.0, 0.2), (1.0, 1.0), (1.0, 8.0)])
def test_strips_give_hertz_on_quadratic_geometry(A, B):
    """g = δ - B η², A constant: the strip method's fixed points are Hertz's ellipse and pressure (module
    docstring); the strips' discretisation is the only error (32 strips over the overlap: 0.1–1 %)."""
    n, _, a, b, _ = hertz_from_penetration(A, B, E_STAR, DELTA, 0.0)
    half = math.sqrt(DELTA / B)
    eta = -half + (np.arange(32) + 0.5) * half / 16
    g = DELTA - B * eta ** 2
    sol = P.solve_strips(eta, eta[1] - eta[0], g, np.full(32, A), 0.01 * eta / half, E_STAR)
    # the patch's lateral edge is resolved to half a strip: the area within that band, the force and the peak
    # within its 3/2 power (the pressure vanishes like √(distance) at the edge), as for the grid above
    band = 0.5 * (eta[1] - eta[0]) / b
    assert sol.epsilon == pytest.approx(b * b * B / DELTA, rel=band)
    assert sol.normal_force_N == pytest.approx(n, rel=band ** 1.5)
    assert sol.area_m2 == pytest.approx(math.pi * a * b, rel=band)
    assert sol.peak_pressure_Pa == pytest.approx(1.5 * n / (math.pi * a * b), rel=band ** 1.5)
    # symmetric geometry, antisymmetric angles: the resultant is upright
    assert abs(sol.contact_angle_rad) < 1e-9


@pytest.fixture(scope="module")
def a22_contact():
    return A22.build_contact()


def profile_case(contact, y_m):
    """The right wheel's contacts of the S1002/UIC60 wheelset at lateral shift ``y_m`` under 10 kN per wheel
    (Hertz's pose, no yaw): [(slot, kernel row, strips)]."""
    res = solve_quasi_static(contact, y_m, 0.0, A22.WHEEL_LOAD_N, A22.SPEED_M_S, mu=A22.MU,
                             shear_modulus_Pa=A22.SHEAR_MODULUS_PA, poisson=A22.POISSON, creep_law="fastsim")
    out = contact.evaluate(np.array([[y_m, res.z_m, res.roll_rad]]))
    pose = contact.side_poses(contact.poses)[0].copy()
    cases = []
    for slot in range(K.N_SLOTS):
        row = out[0, slot]
        if row[K.F_STATUS] > 0 and row[K.F_NORMAL_FORCE] > 0:
            strips, sol = P.patch_of_contact(contact.nodes, contact.meta, contact.curve_ids[0], row, pose, 0.0,
                                             contact.E_star, n_strips=64)
            cases.append((slot, row.copy(), strips, sol))
    return cases


def compare(contact, y_m, n_x=48):
    """Per contact of the position: (patch solution, exact solution, exact angle, kernel row)."""
    out = []
    for slot, row, strips, sol in profile_case(contact, y_m):
        ref = solve_strip_geometry(strips[:, P.S_ETA], strips[:, P.S_G], strips[:, P.S_A], n_x, contact.E_star)
        out.append((sol, ref, ref.contact_angle_rad(strips[:, P.S_GAMMA]), row))
    return out


def test_patch_on_the_conformal_tread_against_the_exact_solution(a22_contact):
    """The centred S1002/UIC60 wheelset: one overlap zone 18 mm wide with two humps.  Hertz is visibly wrong there
    (force and area at the given penetration, contact angle of the resultant); the patch is within the targets."""
    (sol, ref, angle, row), = compare(a22_contact, 0.0, n_x=32)
    assert sol.normal_force_N == pytest.approx(ref.normal_force_N, rel=FORCE_TOL)
    assert sol.area_m2 == pytest.approx(ref.area_m2, rel=AREA_TOL)
    assert sol.contact_angle_rad == pytest.approx(angle, rel=ANGLE_TOL)
    hertz_area = math.pi * row[K.F_SEMI_A] * row[K.F_SEMI_B]
    assert row[K.F_NORMAL_FORCE] < 0.9 * ref.normal_force_N
    assert hertz_area < 0.8 * ref.area_m2
    assert row[K.F_CONTACT_ANGLE] < 0.85 * angle


#: lateral shifts of the wheelset [mm]: the conformal tread (-3 ... 1 mm), the tread (2, 4), the two-point contact
#: (5), the flange (7, 9)
POSITIONS_MM = (-3.0, -1.0, 0.0, 0.5, 1.0, 2.0, 4.0, 5.0, 7.0, 9.0)
#: where the targets are not met (measured: the force +5.5 %, the contact angle +3.5 %; docs/validation.md)
MISSED_MM = (0.5,)


@pytest.mark.validation
@pytest.mark.parametrize("y_mm", [pytest.param(y, marks=pytest.mark.xfail(strict=True, reason="a plateau of the "
                                                                          "overlap: the strips load it too much"))
                                  if y in MISSED_MM else y for y in POSITIONS_MM])
def test_patch_against_the_exact_solution_at_ten_positions(a22_contact, y_mm):
    for sol, ref, angle, _ in compare(a22_contact, y_mm * 1e-3):
        assert sol.normal_force_N == pytest.approx(ref.normal_force_N, rel=FORCE_TOL)
        assert sol.area_m2 == pytest.approx(ref.area_m2, rel=AREA_TOL)
        assert sol.contact_angle_rad == pytest.approx(angle, rel=ANGLE_TOL)
