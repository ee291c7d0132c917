"""Tests of the Hertz normal contact (exudyn_wheelrail.contact.normal) against independent references.

References used (never the module's own numbers):
* closed-form sphere results, Kh = 4/3 E* sqrt(R), a = (3NR/(4E*))^(1/3) (Johnson 1985, §4.2);
* the classical m, n table ../shared/reference/hertz_m_n.csv;
* an in-test solution of the eccentricity equation with scipy.special.ellipk/ellipe (parameter e^2);
* a semi-analytic Boussinesq integration of the surface displacement under the ellipsoidal Hertz pressure
  (no elliptic integrals): u(x, y) must equal delta - A x^2 - B y^2 inside the ellipse;
* the 2-D (line contact) Hertz limit p0 = B b E* for very elongated ellipses;
* Johnson's equivalent-sphere approximation (Re = 1/(2 sqrt(AB))) for mildly elliptic contacts.
"""
from __future__ import annotations

import csv
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from reference_paths import HERTZ_M_N_TABLE
from exudyn_wheelrail.contact.normal import (
    DEFAULT_MIN_CURVATURE,
    G_STEEL,
    STATUS_CLAMPED_A,
    STATUS_CLAMPED_B,
    STATUS_NO_CONTACT,
    STATUS_RATIO_SATURATED,
    HertzContact,
    effective_modulus,
    hertz_ellipse,
    hertz_from_force,
    hertz_from_penetration,
    hertz_stiffness,
)

REF_TABLE = HERTZ_M_N_TABLE
E_ST, NU_ST = 2.1e11, 0.28


# --------------------------------------------------------------------------------------- independent helpers
def _coefficients_reference(A, B):
    """(m_x, m_y, kappa) solved directly from Johnson's eccentricity equation in e^2 (scipy parameter)."""
    lo_c, hi_c = min(A, B), max(A, B)
    ratio = hi_c / lo_c
    if ratio == 1.0:
        return 1.0, 1.0, 4.0 / 3.0

    def f(e2):  # (C_S / C_L) as function of e^2 minus target
        K, E = ellipk(e2), ellipe(e2)
        return ((E / (1.0 - e2)) - K) / (K - E) - ratio

    e2 = brentq(f, 1e-9, 1.0 - 1e-15, xtol=1e-16, rtol=1e-15, maxiter=500)
    K, E = ellipk(e2), ellipe(e2)
    m_long = (2.0 * E / (math.pi * (1.0 - e2))) ** (1.0 / 3.0)
    n_short = m_long * math.sqrt(1.0 - e2)
    kappa = math.sqrt(3.0) / 2.0 * (2.0 * math.pi * m_long / (3.0 * K)) ** 1.5
    return (m_long, n_short, kappa) if A <= B else (n_short, m_long, kappa)


def _boussinesq_displacement(x0, y0, a, b, p0, E_star, n_phi=8192):
    """Combined normal surface displacement at (x0, y0) inside the ellipse under p0*sqrt(1-x²/a²-y²/b²).

    u = 1/(pi E*) * integral p(Q)/|P-Q| dQ, written in polar coordinates about P: the 1/r singularity cancels
    with the Jacobian, the radial integral of sqrt(quadratic) is done in closed form and the (smooth,
    periodic) angular integral with the trapezoidal rule, which converges exponentially.
    """
    phi = np.linspace(0.0, 2.0 * np.pi, n_phi, endpoint=False)
    c, d = np.cos(phi), np.sin(phi)
    alpha = 1.0 - x0 * x0 / a**2 - y0 * y0 / b**2
    beta = -(x0 * c / a**2 + y0 * d / b**2)
    gamma = c * c / a**2 + d * d / b**2
    s_c = beta / gamma
    R2 = s_c * s_c + alpha / gamma
    R = np.sqrt(R2)
    t = -s_c  # lower limit of t = s - s_c; upper limit is R
    F_lo = 0.5 * (t * np.sqrt(np.maximum(R2 - t * t, 0.0)) + R2 * np.arcsin(np.clip(t / R, -1.0, 1.0)))
    inner = np.sqrt(gamma) * (R2 * np.pi / 4.0 - F_lo)
    return p0 * inner.mean() * 2.0 * np.pi / (np.pi * E_star)


def _theta_to_AB(theta_deg):
    c = math.cos(math.radians(theta_deg))
    return 1.0, (1.0 + c) / (1.0 - c)  # A <= B, cos(theta) = (B - A)/(A + B)


# ------------------------------------------------------------------------------------------------- tests
def test_effective_modulus_and_steel_defaults():
    Es = effective_modulus(E_ST, NU_ST, E_ST, NU_ST)
    assert Es == pytest.approx(E_ST / (2.0 * (1.0 - NU_ST**2)), rel=1e-14)
    Es2 = effective_modulus(2.0e11, 0.3, 1.0e11, 0.25)
    assert 1.0 / Es2 == pytest.approx((1 - 0.09) / 2e11 + (1 - 0.0625) / 1e11, rel=1e-14)
    assert G_STEEL == pytest.approx(82e9, rel=0.01)


@pytest.mark.parametrize("R", [0.005, 0.3, 0.46, 10.0])
@pytest.mark.parametrize("N", [1.0, 5e4, 2e5])
def test_sphere_on_plane(R, N):
    Es = effective_modulus(E_ST, NU_ST, E_ST, NU_ST)
    A = B = 1.0 / (2.0 * R)
    Kh_ref = 4.0 / 3.0 * Es * math.sqrt(R)
    a_ref = (3.0 * N * R / (4.0 * Es)) ** (1.0 / 3.0)
    delta_ref = a_ref**2 / R
    Kh, status = hertz_stiffness(A, B, Es, 1e-9)
    assert status == 0
    assert Kh == pytest.approx(Kh_ref, rel=1e-6)
    delta, a, b, status = hertz_from_force(A, B, Es, N, 1e-9)
    assert a == pytest.approx(a_ref, rel=1e-6) and b == pytest.approx(a_ref, rel=1e-6)
    assert delta == pytest.approx(delta_ref, rel=1e-6)
    N2, dN, a2, b2, _ = hertz_from_penetration(A, B, Es, delta_ref, 1e-9)
    assert N2 == pytest.approx(N, rel=1e-6) and a2 == pytest.approx(a_ref, rel=1e-6)


def test_two_spheres_and_crossed_cylinders():
    E1, nu1, E2, nu2 = 2.1e11, 0.28, 1.1e11, 0.34
    Es = effective_modulus(E1, nu1, E2, nu2)
    R1, R2, N = 0.02, 0.05, 800.0
    R = R1 * R2 / (R1 + R2)
    hc = HertzContact.from_curvatures(1 / R1, 1 / R1, 1 / R2, 1 / R2, E1, nu1, E2, nu2)
    assert hc.Kh == pytest.approx(4.0 / 3.0 * Es * math.sqrt(R), rel=1e-6)
    a, b = hc.semi_axes(N)
    a_ref = (3.0 * N * R / (4.0 * Es)) ** (1.0 / 3.0)
    assert a == pytest.approx(a_ref, rel=1e-6) and b == pytest.approx(a_ref, rel=1e-6)
    # equal crossed cylinders (wheel: rolling radius, rail: crown radius) == sphere of that radius on a plane
    Rc = 0.4
    hc = HertzContact.from_curvatures(1 / Rc, 0.0, 0.0, 1 / Rc)
    assert hc.Kh == pytest.approx(4.0 / 3.0 * hc.E_star * math.sqrt(Rc), rel=1e-6)


def _read_reference_table():
    rows = []
    with REF_TABLE.open() as fh:
        lines = [ln for ln in fh if not ln.startswith("#")]
    for row in csv.DictReader(lines):
        rows.append((float(row["theta_deg"]), float(row["m"]), float(row["n"])))
    return rows


def test_m_n_against_classical_table():
    rows = _read_reference_table()
    assert len(rows) >= 10
    worst = 0.0
    for theta, m_ref, n_ref in rows:
        A, B = _theta_to_AB(theta)
        mx, my, _ = hertz_ellipse(A, B, 1e-12)
        assert mx == pytest.approx(m_ref, rel=5e-3), theta
        assert my == pytest.approx(n_ref, rel=5e-3), theta
        # swapped orientation: the long axis follows the smaller curvature
        mx2, my2, _ = hertz_ellipse(B, A, 1e-12)
        assert (mx2, my2) == pytest.approx((n_ref, m_ref), rel=5e-3)
        worst = max(worst, abs(mx / m_ref - 1), abs(my / n_ref - 1))
    assert worst < 2.5e-3  # table is rounded to 3 decimals: n = 0.238 carries up to 0.2 %


def test_table_against_direct_elliptic_solution():
    """Interpolation table vs a direct solution, axis ratios 1/50 ... 50 (curvature ratios ~ 1/700 ... 700)."""
    rng = np.random.default_rng(1)
    worst = 0.0
    for lr in np.concatenate([rng.uniform(-6.6, 6.6, 300), [0.0, 1e-6, -1e-3, 0.02, 6.55, -6.55]]):
        A, B = 2.0, 2.0 * math.exp(lr)
        got = hertz_ellipse(A, B, 1e-12)
        ref = _coefficients_reference(A, B)
        worst = max(worst, max(abs(g / r - 1.0) for g, r in zip(got, ref)))
    assert worst < 1e-6


@pytest.mark.parametrize("ratio", [1.0, 1.7, 4.0, 0.25, 12.0])
def test_boussinesq_integration_of_hertz_pressure(ratio):
    """delta, a, b satisfy the contact problem: u(x, y) = delta - A x^2 - B y^2 inside the ellipse."""
    Es = effective_modulus(E_ST, NU_ST, E_ST, NU_ST)
    A, B, N = 1.1, 1.1 * ratio, 6.0e4
    delta, a, b, status = hertz_from_force(A, B, Es, N)
    assert status == 0
    p0 = 3.0 * N / (2.0 * math.pi * a * b)
    n_phi = 8192 if max(a / b, b / a) < 5 else 32768
    u0 = _boussinesq_displacement(0.0, 0.0, a, b, p0, Es, n_phi)
    assert u0 == pytest.approx(delta, rel=1e-6)
    for fx, fy in [(0.6, 0.0), (0.0, 0.6), (0.4, -0.5), (-0.7, 0.3)]:
        x, y = fx * a, fy * b
        u = _boussinesq_displacement(x, y, a, b, p0, Es, n_phi)
        assert u == pytest.approx(delta - A * x * x - B * y * y, rel=1e-6, abs=1e-7 * delta)


def test_line_contact_limit():
    """Very elongated ellipse: the central section is a 2-D Hertz contact, p0 = B b E* (R = 1/(2B))."""
    Es = effective_modulus(E_ST, NU_ST, E_ST, NU_ST)
    B, N = 1.0, 1.0e4
    errs = []
    for A in (1e-2, 1e-3, 1e-4, 1e-5):
        delta, a, b, status = hertz_from_force(A, B, Es, N, 1e-12)
        assert status == 0 and a > 15 * b
        p0 = 3.0 * N / (2.0 * math.pi * a * b)
        errs.append(abs(p0 / (B * b * Es) - 1.0))
    assert errs[-1] < 1e-3
    assert all(e2 < e1 for e1, e2 in zip(errs, errs[1:]))  # converges monotonically
    # the opposite orientation gives the same numbers with a and b swapped
    d1, a1, b1, _ = hertz_from_force(1e-4, 1.0, Es, N, 1e-12)
    d2, a2, b2, _ = hertz_from_force(1.0, 1e-4, Es, N, 1e-12)
    assert (d2, a2, b2) == pytest.approx((d1, b1, a1), rel=1e-12)


@pytest.mark.parametrize("ratio, tol", [(1.2, 1e-3), (1.5, 3e-3), (2.0, 1e-2)])
def test_equivalent_sphere_approximation_mild_ellipticity(ratio, tol):
    """Johnson's equivalent radius Re = 1/(2 sqrt(AB)): delta and sqrt(ab) within `tol` for B/A <= 2,
    and a/b ~ (B/A)^(2/3) within 0.2 %."""
    Es, N, A = 1.0e11, 2.0e4, 1.3
    B = ratio * A
    delta, a, b, _ = hertz_from_force(A, B, Es, N)
    Re = 1.0 / (2.0 * math.sqrt(A * B))
    assert delta == pytest.approx((9.0 * N**2 / (16.0 * Re * Es**2)) ** (1.0 / 3.0), rel=tol)
    assert math.sqrt(a * b) == pytest.approx((3.0 * N * Re / (4.0 * Es)) ** (1.0 / 3.0), rel=tol)
    assert a / b == pytest.approx(ratio ** (2.0 / 3.0), rel=2e-3)
    assert delta < (9.0 * N**2 / (16.0 * Re * Es**2)) ** (1.0 / 3.0)  # the approximation overestimates


@settings(max_examples=200, deadline=None)
@given(lA=st.floats(-3.0, 4.0), lB=st.floats(-3.0, 4.0), ldelta=st.floats(-9.0, -3.0))
def test_symmetry_swap(lA, lB, ldelta):
    A, B, delta, Es = 10.0**lA, 10.0**lB, 10.0**ldelta, 1.1e11
    N1, k1, a1, b1, s1 = hertz_from_penetration(A, B, Es, delta, 1e-6)
    N2, k2, a2, b2, s2 = hertz_from_penetration(B, A, Es, delta, 1e-6)
    assert N1 == pytest.approx(N2, rel=1e-12) and k1 == pytest.approx(k2, rel=1e-12)
    assert a1 == pytest.approx(b2, rel=1e-12) and b1 == pytest.approx(a2, rel=1e-12)
    # the long axis is along the direction of the smaller curvature
    if A < B:
        assert a1 >= b1
    elif A > B:
        assert a1 <= b1


@settings(max_examples=200, deadline=None)
@given(lA=st.floats(-1.0, 2.5), lr=st.floats(-2.8, 2.8), ldelta=st.floats(-8.0, -3.0))
def test_derivative_and_round_trip(lA, lr, ldelta):
    A, B, delta, Es = 10.0**lA, 10.0 ** (lA + lr), 10.0**ldelta, 1.1e11
    N, dN, a, b, status = hertz_from_penetration(A, B, Es, delta, 1e-9)
    assert status == 0
    h = 1e-4 * delta
    Np = hertz_from_penetration(A, B, Es, delta + h, 1e-9)[0]
    Nm = hertz_from_penetration(A, B, Es, delta - h, 1e-9)[0]
    assert dN == pytest.approx((Np - Nm) / (2 * h), rel=1e-6)
    d2, a2, b2, s2 = hertz_from_force(A, B, Es, N, 1e-9)
    assert s2 == 0
    assert d2 == pytest.approx(delta, rel=1e-12)
    assert a2 == pytest.approx(a, rel=1e-12) and b2 == pytest.approx(b, rel=1e-12)
    # exact power law N ~ delta^1.5, a, b ~ delta^0.5
    N4, _, a4, b4, _ = hertz_from_penetration(A, B, Es, 4.0 * delta, 1e-9)
    assert N4 == pytest.approx(8.0 * N, rel=1e-12) and a4 == pytest.approx(2.0 * a, rel=1e-12)


def test_no_contact():
    Es = 1e11
    for d in (0.0, -1e-5, float("nan")):
        N, dN, a, b, status = hertz_from_penetration(1.0, 2.0, Es, d)
        # no contact: assigned zeros (exact), likewise below
        assert (N, dN, a, b) == (0.0, 0.0, 0.0, 0.0) and status & STATUS_NO_CONTACT
    delta, a, b, status = hertz_from_force(1.0, 2.0, Es, -3.0)
    assert (delta, a, b) == (0.0, 0.0, 0.0) and status == STATUS_NO_CONTACT
    hc = HertzContact(1.0, 2.0, Es)
    assert hc.force(-1e-4) == 0.0 and hc.stiffness(-1e-4) == 0.0 and hc.penetration(-5.0) == 0.0


@pytest.mark.parametrize(
    "A, B, flag",
    [
        (-0.5, 2.0, STATUS_CLAMPED_A),  # concave wheel throat tighter than the rail in x (hypothetical)
        (1.0, -0.2, STATUS_CLAMPED_B),  # wheel throat (concave) vs rail gauge corner: A + B > 0 but B < 0
        (1.0, -3.0, STATUS_CLAMPED_B),  # A + B < 0
        (0.0, 0.0, STATUS_CLAMPED_A | STATUS_CLAMPED_B),
        (-1.0, -1.0, STATUS_CLAMPED_A | STATUS_CLAMPED_B),
        (float("nan"), 1.0, STATUS_CLAMPED_A),
        (1.0, 0.02, STATUS_CLAMPED_B),  # positive but below the floor (near-conformal)
    ],
)
def test_conformal_inputs_are_clamped(A, B, flag):
    Es = 1.1e11
    N, dN, a, b, status = hertz_from_penetration(A, B, Es, 1e-4)
    assert all(math.isfinite(v) and v > 0 for v in (N, dN, a, b))
    assert status & flag == flag
    delta, a2, b2, status2 = hertz_from_force(A, B, Es, 5e4)
    assert all(math.isfinite(v) and v > 0 for v in (delta, a2, b2)) and status2 & flag == flag
    assert all(math.isfinite(v) for v in hertz_ellipse(A, B))
    # the clamped answer equals the answer at the floor (continuous, bounded)
    f = DEFAULT_MIN_CURVATURE
    Ac = A if (A == A and A >= f) else f
    Bc = B if B >= f else f
    assert hertz_from_penetration(Ac, Bc, Es, 1e-4)[:4] == pytest.approx((N, dN, a, b), rel=1e-14)
    hc = HertzContact(A, B, Es)
    assert hc.clamped and math.isfinite(hc.Kh)


def test_ratio_saturation_flag():
    N, dN, a, b, status = hertz_from_penetration(1e-6, 50.0, 1e11, 1e-5, 1e-9)
    assert status & STATUS_RATIO_SATURATED and all(math.isfinite(v) for v in (N, dN, a, b))


def test_typical_wheel_rail():
    """r_wheel = 0.46 m, rail crown R = 0.3 m, flat wheel profile, steel, N = 50 kN (loose sanity)."""
    hc = HertzContact.from_curvatures(1 / 0.46, 0.0, 0.0, 1 / 0.3)
    a, b = hc.semi_axes(5.0e4)
    assert hc.status == 0
    assert 5.0e-3 < a < 7.5e-3  # along rolling direction (smaller relative curvature -> long axis)
    assert 3.5e-3 < b < 5.0e-3
    assert 0.8e9 < hc.max_pressure(5.0e4) < 1.2e9
    assert 3e-5 < hc.penetration(5.0e4) < 1.2e-4
    # consistency of the wrapper with the kernels
    delta, a2, b2, _ = hertz_from_force(hc.A, hc.B, hc.E_star, 5.0e4)
    assert (a2, b2, delta) == pytest.approx((a, b, hc.penetration(5.0e4)), rel=1e-12)
    assert hc.force(delta) == pytest.approx(5.0e4, rel=1e-12)
    assert hc.stiffness(delta) == pytest.approx(1.5 * 5.0e4 / delta, rel=1e-12)


def test_callable_from_numba_kernel():
    @njit
    def kernel(A, B, Es, deltas):
        total = 0.0
        for d in deltas:
            N, dN, a, b, status = hertz_from_penetration(A, B, Es, d)
            delta2, a2, b2, s2 = hertz_from_force(A, B, Es, N, 0.05)
            mx, my, kappa = hertz_ellipse(A, B)
            total += N + 0.0 * (delta2 + a2 + mx)
        return total

    ds = np.linspace(1e-6, 1e-4, 7)
    Es = 1.1e11
    ref = sum(hertz_from_penetration(1.0, 2.0, Es, d)[0] for d in ds)
    assert kernel(1.0, 2.0, Es, ds) == pytest.approx(ref, rel=1e-12)
