"""Kalker's exact theory (discretised): influence coefficients against quadrature of Cerruti's point-force
solution, creep coefficients against Kalker's Table E.3, full sliding against direct quadrature, symmetries,
saturation, slip area, warm start, input checks."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from exudyn_wheelrail.creep import (kalker_coefficients, kalker_exact, kalker_exact_extrapolated,
                                    kalker_exact_solution)
from exudyn_wheelrail.creep.kalker_exact import element_grid, line_influence, slip_operator

G = 82e9
NU = 0.28
N = 10e3
MU = 0.3
C_M = 6e-3


def _axes(a_over_b, c=C_M):
    return c * math.sqrt(a_over_b), c / math.sqrt(a_over_b)


def _cerruti(X, Y, nu):
    """Displacement difference of two identical half-spaces per unit point force on the wheel (G = 1):
    Johnson 1985 Eq. 3.86–3.87 doubled: (uxx, uxy, uyy)."""
    r = math.hypot(X, Y)
    return ((1 - nu) / r + nu * X * X / r ** 3) / math.pi, nu * X * Y / r ** 3 / math.pi, \
        ((1 - nu) / r + nu * Y * Y / r ** 3) / math.pi


def _quad_rect(xf, yf, xs, ys, hx, hy, nu, comp):
    f = lambda yy, xx: _cerruti(xf - xx, yf - yy, nu)[comp]  # noqa: E731
    v, _ = integrate.dblquad(f, xs - hx, xs + hx, ys - hy, ys + hy, epsabs=1e-13, epsrel=1e-10)
    return v


def test_self_influence_of_a_square_is_analytic():
    # ∫∫ over a square of side h centred on the field point: ∫∫ 1/r = 4 h ln(1+√2), ∫∫ x²/r³ = half of that
    n = 3
    Axx, Ayy = line_influence(1.0, 1.0, n, 1, 0.0)           # one strip, chord 2, dx = 2/3, dy = 2
    # with nu = 0 only the 1/r term remains; the element is 2/3 x 2: rectangle formula
    hx, hy = 1.0 / 3.0, 1.0
    ref = (2 * hx * math.asinh(hy / hx) + 2 * hy * math.asinh(hx / hy)) * 2 / math.pi
    assert Axx[0, 1, 1] == pytest.approx(ref, rel=1e-12)
    Axx, Ayy = line_influence(1.0, 1.0, 1, 1, 0.3)          # a 2 x 2 square
    h = 2.0
    i1 = 4 * h * math.log(1 + math.sqrt(2))
    assert Axx[0, 0, 0] == pytest.approx((0.7 * i1 + 0.3 * i1 / 2) / math.pi, rel=1e-12)


@pytest.mark.parametrize("pair", [(0, 5), (3, 12), (17, 2)])
def test_slip_operator_against_quadrature_of_cerruti(pair):
    a, b, n_x, n_y, nu = 1.3, 0.8, 4, 5, 0.28
    x, y, dx, dy = element_grid(a, b, n_x, n_y)
    Bxx, Bxy, Byy = slip_operator(a, b, n_x, n_y, nu)
    e, s = pair
    xs, ys, hx, hy = x[s], y[s], dx[s] / 2, dy / 2
    for comp, B in ((0, Bxx), (1, Bxy), (2, Byy)):
        centre = _quad_rect(x[e], y[e], xs, ys, hx, hy, nu, comp)
        upstream = _quad_rect(x[e] + dx[e], y[e], xs, ys, hx, hy, nu, comp)
        assert B[e, s] == pytest.approx((centre - upstream) / dx[e], rel=1e-7, abs=1e-10)


def _slopes(a_over_b, nu, solver=kalker_exact, **options):
    a, b = _axes(a_over_b)
    eps = 1e-7
    k = G * C_M * C_M * eps
    c11 = -solver(a, b, eps, 0.0, 0.0, N, MU, G, nu, **options)[0] / k
    c22 = -solver(a, b, 0.0, eps, 0.0, N, MU, G, nu, **options)[1] / k
    c23 = -solver(a, b, 0.0, 0.0, eps / C_M, N, MU, G, nu, **options)[1] / k
    return np.array([c11, c22, c23])


@pytest.mark.parametrize("a_over_b", [0.2, 1.0, 5.0])
def test_creep_coefficients_default_grid_within_1p5_percent_of_table_e3(a_over_b):
    ref = np.array(kalker_coefficients(a_over_b, NU))
    err = _slopes(a_over_b, NU) / ref - 1.0
    assert np.all(np.abs(err) < 0.015), err
    ref25 = np.array(kalker_coefficients(a_over_b, 0.25))          # a table column: no ν interpolation
    err25 = _slopes(a_over_b, 0.25) / ref25 - 1.0
    assert np.all(np.abs(err25) < 0.015), err25


# The extrapolation solves each creepage on 80 and on 160 elements along rolling: 3-4 s at a/b = 5 and at 1, ~12 s at
# a/b = 0.2, whose strips converge slowest (warm, load ~1).  The default run keeps a/b = 1 and 5 (the largest errors
# measured: 0.53 % and 0.61 %, the least margin); a/b = 0.2 (0.23 %) is under ``-m validation``.  The default grid's
# 1.5 % (above) is checked at all three ratios in the default run.
@pytest.mark.parametrize("a_over_b", [pytest.param(0.2, marks=pytest.mark.validation), 1.0, 5.0])
def test_creep_coefficients_extrapolated_within_0p7_percent(a_over_b):
    ref = np.array(kalker_coefficients(a_over_b, NU))
    err = _slopes(a_over_b, NU, kalker_exact_extrapolated) / ref - 1.0
    assert np.all(np.abs(err) < 0.007), err


def test_discretisation_error_shrinks_with_refinement_along_rolling():
    ref = np.array(kalker_coefficients(1.0, NU))
    errs = [np.abs(_slopes(1.0, NU, n_x=n, n_y=12) / ref - 1.0) for n in (20, 40, 80)]
    # C23 carries the largest (first-order) error: it must fall roughly by half per refinement
    assert errs[1][2] < 0.7 * errs[0][2] and errs[2][2] < 0.7 * errs[1][2]
    assert errs[2].max() < errs[0].max()


def test_saturation_gives_mu_n_opposite_to_the_creepage():
    a, b = _axes(1.4)
    for xi, eta in [(0.02, 0.0), (0.0, -0.03), (0.01, 0.01)]:
        Fx, Fy, Mz = kalker_exact(a, b, xi, eta, 0.0, N, MU, G, NU)
        assert math.hypot(Fx, Fy) == pytest.approx(MU * N, rel=2e-3)
        # in full sliding the slip is the rigid slip (plus a small elastic part): force opposite to it
        assert (Fx * xi + Fy * eta) / (math.hypot(Fx, Fy) * math.hypot(xi, eta)) < -0.999
    Fx, Fy, Mz = kalker_exact(a, b, 1e-5, 0.0, 0.0, N, MU, G, NU)
    assert abs(Fx) < 0.2 * MU * N


def test_full_sliding_with_spin_matches_quadrature_of_the_rigid_slip():
    # large creepages: the elastic slip (~μ p0 / G ≈ 7e-4) is negligible against the rigid slip (~0.2), so the
    # traction is -μ p_n w/|w| with w = (ξ - φy, η + φx) and the totals are plain integrals over the ellipse
    a, b = 6e-3, 4e-3
    xi, eta, phi = 0.2, 0.1, 80.0               # rotation centre (-η/φ, ξ/φ) = (-1.25 mm, 2.5 mm): inside
    p0 = 3 * N / (2 * math.pi * a * b)

    def integrand(k):
        def f(y, x):
            r = 1 - (x / a) ** 2 - (y / b) ** 2
            if r <= 0:
                return 0.0
            wx, wy = xi - phi * y, eta + phi * x
            w = math.hypot(wx, wy)
            px, py = -MU * p0 * math.sqrt(r) * wx / w, -MU * p0 * math.sqrt(r) * wy / w
            return (px, py, x * py - y * px)[k]
        return f

    ref = []
    for k in range(3):
        v, _ = integrate.dblquad(integrand(k), -a, a, lambda x: -b * math.sqrt(max(1 - (x / a) ** 2, 0)),
                                 lambda x: b * math.sqrt(max(1 - (x / a) ** 2, 0)), epsabs=1e-9, epsrel=1e-7)
        ref.append(v)
    Fx, Fy, Mz = kalker_exact(a, b, xi, eta, phi, N, MU, G, NU)
    c = math.sqrt(a * b)
    assert abs(Fx - ref[0]) < 0.01 * MU * N
    assert abs(Fy - ref[1]) < 0.01 * MU * N
    assert abs(Mz - ref[2]) < 0.01 * MU * N * c


def test_odd_symmetries():
    a, b = 5e-3, 3.5e-3
    for xi, eta, phi in [(2e-4, 1e-4, 0.4), (-5e-4, 3e-4, -1.5), (1e-3, -2e-3, 3.0)]:
        F = np.array(kalker_exact(a, b, xi, eta, phi, N, MU, G, NU))
        Fneg = np.array(kalker_exact(a, b, -xi, -eta, -phi, N, MU, G, NU))
        Fmirror = np.array(kalker_exact(a, b, xi, -eta, -phi, N, MU, G, NU))
        Fxi = np.array(kalker_exact(a, b, -xi, eta, phi, N, MU, G, NU))
        scale = np.array([MU * N, MU * N, MU * N * math.sqrt(a * b)])
        assert np.all(np.abs(Fneg + F) < 1e-6 * scale)
        assert np.all(np.abs(Fmirror - F * [1, -1, -1]) < 1e-6 * scale)
        assert np.all(np.abs(Fxi - F * [-1, 1, 1]) < 1e-6 * scale)


def test_linear_signs_match_the_contract():
    a, b = _axes(1.0)
    eps = 1e-7
    Fx, Fy, Mz = kalker_exact(a, b, eps, 0, 0, N, MU, G, NU)
    assert Fx < 0 and abs(Fy) < 1e-5 * abs(Fx)
    Fx, Fy, Mz = kalker_exact(a, b, 0, eps, 0, N, MU, G, NU)
    assert Fy < 0 and Mz > 0                      # Mz = G c³ C23 η
    Fx, Fy, Mz = kalker_exact(a, b, 0, 0, eps / C_M, N, MU, G, NU)
    assert Fy < 0 and Mz < 0                      # Fy = -G c³ C23 φ, Mz = -G c⁴ C33 φ


def test_slip_area_grows_from_the_trailing_edge():
    a, b = 6e-3, 4e-3
    fractions = []
    for xi in (1e-5, 1e-4, 3e-4):
        s = kalker_exact_solution(a, b, xi, 0.0, 0.0, N, MU, G, NU)
        fractions.append(s.slip_fraction)
        mid = s.slipping[s.slipping.shape[0] // 2]
        # along the middle strip (leading edge first): stick, then slip to the trailing edge
        if mid.any():
            first = int(np.argmax(mid))
            assert mid[first:].all() and not mid[:first].any()
        assert not s.slipping[:, 0].any()            # the leading edge sticks
        np.testing.assert_array_less(np.hypot(s.px_Pa, s.py_Pa), MU * s.pn_Pa * (1 + 1e-9) + 1e-6)
    assert fractions[0] < fractions[1] < fractions[2]


def test_warm_start_reaches_the_same_solution_with_fewer_sweeps():
    a, b = 6e-3, 4e-3
    s1 = kalker_exact_solution(a, b, 2e-4, 1e-4, 0.5, N, MU, G, NU)
    cold = kalker_exact_solution(a, b, 2.1e-4, 1e-4, 0.5, N, MU, G, NU)
    warm = kalker_exact_solution(a, b, 2.1e-4, 1e-4, 0.5, N, MU, G, NU, initial=s1)
    assert warm.sweeps < cold.sweeps
    for u, v in ((cold.Fx_N, warm.Fx_N), (cold.Fy_N, warm.Fy_N)):
        assert abs(u - v) < 1e-5 * MU * N


def test_zero_load_or_friction_gives_zero_and_bad_input_raises():
    # zero load or friction: exact zeros (returned as such)
    assert kalker_exact(5e-3, 4e-3, 1e-3, 0, 0, 0.0, MU, G, NU) == (0.0, 0.0, 0.0)
    assert kalker_exact(5e-3, 4e-3, 1e-3, 0, 0, N, 0.0, G, NU) == (0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="semi-axes"):
        kalker_exact(0.0, 4e-3, 1e-3, 0, 0, N, MU, G, NU)
    with pytest.raises(ValueError, match="xi"):
        kalker_exact(5e-3, 4e-3, float("nan"), 0, 0, N, MU, G, NU)
    with pytest.raises(ValueError, match="poisson"):
        kalker_exact(5e-3, 4e-3, 1e-3, 0, 0, N, MU, G, 0.7)
    with pytest.raises(ValueError, match="n_x"):
        kalker_exact(5e-3, 4e-3, 1e-3, 0, 0, N, MU, G, NU, n_x=1)
    with pytest.raises(RuntimeError, match="no convergence"):
        kalker_exact(5e-3, 4e-3, 1e-4, 0, 0, N, MU, G, NU, max_sweeps=1)
