"""Tests of exudyn_wheelrail.analysis.conicity against independent (analytical) references."""

import math

import numpy as np
import pytest
from scipy.special import ellipk

from exudyn_wheelrail.analysis.conicity import (
    REFERENCE_AMPLITUDE_M,
    conicity_curve,
    equivalent_conicity,
    klingel_wavelength,
)

E_M = 0.75  # half distance between contact points [m]
R0_M = 0.46  # nominal rolling radius [m]
AMP = REFERENCE_AMPLITUDE_M  # 3 mm


def dense_y(y_max=0.010, step=1e-6):
    n = int(round(2 * y_max / step)) + 1
    return np.linspace(-y_max, y_max, n)


# ------------------------------------------------------------------------------------------------ pure cone
@pytest.mark.parametrize("gamma", [0.05, 0.2])
@pytest.mark.parametrize("method", ["harmonic", "regression"])
def test_cone_exact_linear_methods(gamma, method):
    y = np.linspace(-0.01, 0.01, 201)
    got = equivalent_conicity(y, 2 * gamma * y, AMP, method=method)
    assert got == pytest.approx(gamma, rel=1e-6)


@pytest.mark.parametrize("gamma", [0.05, 0.2])
def test_cone_wavelength(gamma):
    y = np.linspace(-0.01, 0.01, 201)
    got = equivalent_conicity(y, 2 * gamma * y, AMP, method="wavelength",
                              half_contact_distance_m=E_M, r0_m=R0_M)
    assert got == pytest.approx(gamma, rel=1e-4)


def test_cone_one_sided_data_is_extended_oddly():
    gamma = 0.05
    y = np.linspace(0.0, 0.01, 101)[::-1]  # only y >= 0, reversed order
    for method in ("harmonic", "regression", "wavelength"):
        assert equivalent_conicity(y, 2 * gamma * y, AMP, method=method) == pytest.approx(gamma, rel=1e-4)
    # only y <= 0 is treated the same way
    assert equivalent_conicity(-y, -2 * gamma * y, AMP) == pytest.approx(gamma, rel=1e-9)
    # a sample set starting away from zero: the odd extension interpolates through the origin
    y2 = np.linspace(0.0005, 0.01, 96)
    assert equivalent_conicity(y2, 2 * gamma * y2, AMP) == pytest.approx(gamma, rel=1e-9)


def test_klingel_wavelength_by_hand():
    # lambda = 2 pi sqrt(e r0 / gamma) = 2 pi sqrt(0.75 * 0.46 / 0.05) = 2 pi sqrt(6.9)
    # sqrt(6.9) = 2.626785107...; 2 pi * 2.626785107 = 16.5044...
    expected = 2 * 3.141592653589793 * 6.9 ** 0.5
    assert expected == pytest.approx(16.5045, abs=1e-3)
    assert klingel_wavelength(0.05, half_contact_distance_m=0.75, r0_m=0.46) == pytest.approx(expected, rel=1e-12)


def test_wavelength_method_reproduces_klingel_wavelength():
    # gamma_e = e r0 (2 pi / lambda)^2 is the inverse of Klingel's formula
    gamma = 0.05
    lam = klingel_wavelength(gamma, E_M, R0_M)
    assert E_M * R0_M * (2 * math.pi / lam) ** 2 == pytest.approx(gamma, rel=1e-14)


# ------------------------------------------------------------------------------------------------ cubic (Duffing)
# Delta r(y) = 2 gamma y + 2 c y^3 (hardening).
#
# Describing function: with y = A sin(psi),
#   gamma_e = 1/(2 pi A) int_0^{2 pi} (2 gamma A sin psi + 2 c A^3 sin^3 psi) sin psi dpsi
#           = 1/(2 pi A) (2 gamma A * pi + 2 c A^3 * 3 pi / 4)        [int sin^2 = pi, int sin^4 = 3 pi / 4]
#           = gamma + 3/4 c A^2.
#
# Kinematic wavelength: y'' = -(2 gamma y + 2 c y^3)/(2 e r0) = -w^2 (y + eps y^3), w^2 = gamma/(e r0), eps = c/gamma.
# Energy from the turning point A: y'^2 = w^2 (A^2 - y^2) (1 + eps (A^2 + y^2)/2).  Quarter period with
# y = A cos(theta):  T/4 = (1/w) int_0^{pi/2} dtheta / sqrt(1 + eps A^2 - (eps A^2/2) sin^2 theta)
#                        = K(m) / (w sqrt(1 + eps A^2)),   m = eps A^2 / (2 (1 + eps A^2))   (parameter m = k^2).
# Hence lambda = 4 K(m) / (w sqrt(1 + eps A^2)) and gamma_e = e r0 (2 pi/lambda)^2 = gamma (pi sqrt(1+eps A^2)/(2K))^2.
# First order: K ~ pi/2 (1 + m/4), m ~ eps A^2/2  =>  gamma_e ~ gamma (1 + eps A^2)(1 - eps A^2/4) ~ gamma + 3/4 c A^2.
def duffing_case(gamma=0.1, rel_nonlinearity=0.2, amp=AMP):
    """c chosen so that 3/4 c A^2 = rel_nonlinearity * gamma."""
    c = rel_nonlinearity * gamma / (0.75 * amp * amp)
    y = dense_y(0.006, 5e-7)
    return y, 2 * gamma * y + 2 * c * y ** 3, gamma, c


def duffing_exact_wavelength_conicity(gamma, c, amp):
    eps_a2 = (c / gamma) * amp * amp
    m = eps_a2 / (2 * (1 + eps_a2))
    w = math.sqrt(gamma / (E_M * R0_M))
    lam = 4 * ellipk(m) / (w * math.sqrt(1 + eps_a2))
    return E_M * R0_M * (2 * math.pi / lam) ** 2


def test_cubic_harmonic_closed_form():
    y, dr, gamma, c = duffing_case()
    got = equivalent_conicity(y, dr, AMP, method="harmonic")
    assert got == pytest.approx(gamma + 0.75 * c * AMP ** 2, rel=1e-6)


def test_cubic_wavelength_elliptic_integral():
    y, dr, gamma, c = duffing_case()
    got = equivalent_conicity(y, dr, AMP, method="wavelength", half_contact_distance_m=E_M, r0_m=R0_M)
    assert got == pytest.approx(duffing_exact_wavelength_conicity(gamma, c, AMP), rel=1e-5)


def test_cubic_methods_agree_to_first_order():
    # a moderate nonlinearity: the describing-function correction 3/4 c A^2 is 10 % of gamma
    y, dr, gamma, c = duffing_case(rel_nonlinearity=0.1)
    harm = equivalent_conicity(y, dr, AMP, method="harmonic")
    wave = equivalent_conicity(y, dr, AMP, method="wavelength")
    assert harm / gamma - 1 == pytest.approx(0.1, rel=1e-6)
    assert abs(wave - harm) / harm < 0.02
    # the difference is second order: halving the nonlinearity divides it by about four
    y2, dr2, _, _ = duffing_case(rel_nonlinearity=0.05)
    diff2 = abs(equivalent_conicity(y2, dr2, AMP, method="wavelength")
                - equivalent_conicity(y2, dr2, AMP, method="harmonic"))
    assert abs(wave - harm) / diff2 == pytest.approx(4.0, rel=0.15)


# ------------------------------------------------------------------------------------------------ piecewise linear
# Flange-like Delta r: slope 2 g1 for |y| <= y1, slope 2 g2 beyond (continuous):
#   Delta r(y) = 2 g2 y + 2 (g1 - g2) sat(y),  sat(y) = clip(y, -y1, y1).
# Harmonic integral, y = A sin psi, A > y1, psi1 = arcsin(y1/A), by symmetry 4x the quarter period:
#   int_0^{2pi} sat(A sin psi) sin psi dpsi
#     = 4 [ int_0^{psi1} A sin^2 psi dpsi + int_{psi1}^{pi/2} y1 sin psi dpsi ]
#     = 4 [ A (psi1/2 - sin(2 psi1)/4) + y1 cos(psi1) ]
#     = 2 A [ psi1 + rho sqrt(1 - rho^2) ]   with rho = y1/A  (sin 2psi1 = 2 rho cos psi1, y1 cos psi1 = A rho cos)
#   so gamma_e = g2 + (g1 - g2) (2/pi) [ arcsin(rho) + rho sqrt(1 - rho^2) ].
def flange_dr(y, g1, g2, y1):
    return 2 * g2 * y + 2 * (g1 - g2) * np.clip(y, -y1, y1)


def flange_harmonic_exact(g1, g2, y1, amp):
    if amp <= y1:
        return g1
    rho = y1 / amp
    return g2 + (g1 - g2) * (2 / math.pi) * (math.asin(rho) + rho * math.sqrt(1 - rho * rho))


@pytest.mark.parametrize("amp", [1.5e-3, 3e-3, 4e-3, 6e-3])
def test_piecewise_linear_harmonic_closed_form(amp):
    g1, g2, y1 = 0.05, 0.6, 2.0e-3
    y = np.linspace(-0.008, 0.008, 1235)  # grid does not contain the kink at +-2 mm
    assert not np.any(np.isclose(np.abs(y), y1, rtol=0, atol=1e-9))
    expected = flange_harmonic_exact(g1, g2, y1, amp)
    for method in ("harmonic", "regression"):
        got = equivalent_conicity(y, flange_dr(y, g1, g2, y1), amp, method=method)
        assert got == pytest.approx(expected, rel=1e-4)
    # with the kink on the grid the piecewise-linear interpolant is exact and so is the closed-form integration
    y_k = np.linspace(-0.008, 0.008, 1601)
    assert equivalent_conicity(y_k, flange_dr(y_k, g1, g2, y1), amp) == pytest.approx(expected, rel=1e-10)


# Wavelength of the flange-like case (independent, by matching sinusoid arcs): with w_i^2 = g_i/(e r0),
# region |y| <= y1: y'' = -w1^2 y; region y > y1: y'' = -w2^2 (y - yc), yc = y1 (1 - g1/g2).
# From the turning point A > y1 to y1: t2 = arccos((y1 - yc)/(A - yc)) / w2, speed v = w2 sqrt((A-yc)^2-(y1-yc)^2).
# From y1 to 0 inside: amplitude A1 = sqrt(y1^2 + v^2/w1^2), t1 = arcsin(y1/A1) / w1.  lambda = 4 (t1 + t2).
# (Check g1 = g2: yc = 0, A1 = A, t1 + t2 = (arcsin + arccos)(y1/A) / w = pi / (2 w).)
def flange_wavelength_exact(g1, g2, y1, amp):
    w1 = math.sqrt(g1 / (E_M * R0_M))
    w2 = math.sqrt(g2 / (E_M * R0_M))
    yc = y1 * (1 - g1 / g2)
    t2 = math.acos((y1 - yc) / (amp - yc)) / w2
    v = w2 * math.sqrt((amp - yc) ** 2 - (y1 - yc) ** 2)
    a1 = math.sqrt(y1 ** 2 + (v / w1) ** 2)
    t1 = math.asin(y1 / a1) / w1
    lam = 4 * (t1 + t2)
    return E_M * R0_M * (2 * math.pi / lam) ** 2


@pytest.mark.parametrize("amp", [3e-3, 5e-3])
def test_piecewise_linear_wavelength_closed_form(amp):
    g1, g2, y1 = 0.05, 0.6, 2.0e-3
    y = np.linspace(-0.008, 0.008, 1601)  # kink on the grid
    got = equivalent_conicity(y, flange_dr(y, g1, g2, y1), amp, method="wavelength",
                              half_contact_distance_m=E_M, r0_m=R0_M)
    assert got == pytest.approx(flange_wavelength_exact(g1, g2, y1, amp), rel=1e-5)


# ------------------------------------------------------------------------------------------------ regression
def test_regression_equals_harmonic_for_general_delta_r():
    # non-odd, nonlinear Delta r with an offset: the 1/sqrt(A^2-y^2)-weighted regression slope / 2 is the
    # describing function (int w y dy = 0, int w y^2 dy = pi A^2/2 decouple the normal equations)
    y = dense_y(0.008, 2e-6)
    dr = 1e-4 + 0.12 * y + 30.0 * y ** 2 + 4000.0 * y ** 3 + 2e-4 * np.tanh(y / 1e-3)
    for amp in (1e-3, 3e-3, 7e-3):
        harm = equivalent_conicity(y, dr, amp, method="harmonic")
        reg = equivalent_conicity(y, dr, amp, method="regression")
        assert reg == pytest.approx(harm, rel=1e-10)


def test_regression_against_discrete_weighted_polyfit():
    # independent reference: ordinary weighted least squares (numpy.polyfit) on Gauss-Chebyshev nodes
    # y_k = A cos((2k-1) pi / 2N), whose equal quadrature weights are exactly the weight 1/sqrt(A^2 - y^2)
    def f(y):
        return 2e-4 + 0.1 * y + 50.0 * y ** 2 + 3000.0 * y ** 3 + 5e5 * y ** 5

    y = dense_y(0.005, 1e-6)
    amp = 3e-3
    n = 4000
    nodes = amp * np.cos((2 * np.arange(1, n + 1) - 1) * np.pi / (2 * n))
    slope, _intercept = np.polyfit(nodes, f(nodes), 1)  # equal weights at Chebyshev nodes
    got = equivalent_conicity(y, f(y), amp, method="regression")
    assert got == pytest.approx(slope / 2, rel=1e-6)


def test_jump_encoded_by_repeated_y():
    # Delta r = 2 g y + 2 d sign(y): describing function of a relay, gamma_e = g + 4 d / (pi A)
    g, d, amp = 0.05, 1e-5, 3e-3
    y_pos = np.linspace(0, 0.006, 601)
    y = np.concatenate((-y_pos[::-1], y_pos))  # y = 0 appears twice: left value, then right value
    dr = 2 * g * y + 2 * d * np.concatenate((-np.ones(601), np.ones(601)))
    assert equivalent_conicity(y, dr, amp) == pytest.approx(g + 4 * d / (math.pi * amp), rel=1e-10)


# ------------------------------------------------------------------------------------------------ curve
def test_conicity_curve_matches_pointwise_and_shape():
    y, dr, gamma, c = duffing_case()
    amps = np.array([1e-3, 2e-3, 3e-3, 4e-3])
    curve = conicity_curve(y, dr, amps, method="harmonic")
    assert curve.shape == amps.shape
    np.testing.assert_allclose(curve, gamma + 0.75 * c * amps ** 2, rtol=1e-6)
    wave = conicity_curve(y, dr, amps[:2], method="wavelength")
    for a, val in zip(amps[:2], wave):
        assert val == pytest.approx(duffing_exact_wavelength_conicity(gamma, c, a), rel=1e-5)


# ------------------------------------------------------------------------------------------------ errors
def test_amplitude_outside_sampled_range():
    y = np.linspace(-0.004, 0.004, 81)
    with pytest.raises(ValueError, match="exceeds the sampled range"):
        equivalent_conicity(y, 0.1 * y, 0.005)
    y_asym = np.linspace(-0.002, 0.008, 101)
    with pytest.raises(ValueError, match="exceeds the sampled range"):
        equivalent_conicity(y_asym, 0.1 * y_asym, 0.003)
    with pytest.raises(ValueError, match="exceeds the sampled range"):
        conicity_curve(y, 0.1 * y, [0.001, 0.006])


@pytest.mark.parametrize("bad", [0.0, -0.003, float("nan"), float("inf")])
def test_bad_amplitude(bad):
    y = np.linspace(-0.01, 0.01, 21)
    with pytest.raises(ValueError, match="amplitude_m must be positive and finite"):
        equivalent_conicity(y, 0.1 * y, bad)


def test_nan_in_samples():
    y = np.linspace(-0.01, 0.01, 21)
    dr = 0.1 * y
    dr[3] = np.nan
    with pytest.raises(ValueError, match="delta_r_m contains NaN"):
        equivalent_conicity(y, dr, AMP)
    y2 = y.copy()
    y2[5] = np.nan
    with pytest.raises(ValueError, match="y_m contains NaN"):
        equivalent_conicity(y2, 0.1 * y, AMP)


def test_different_lengths():
    with pytest.raises(ValueError, match="different lengths"):
        equivalent_conicity(np.linspace(-0.01, 0.01, 21), np.zeros(20), AMP)


def test_too_few_points():
    with pytest.raises(ValueError, match="too few samples"):
        equivalent_conicity([-0.01, 0.01], [-0.001, 0.001], AMP)


def test_unknown_method():
    y = np.linspace(-0.01, 0.01, 21)
    with pytest.raises(ValueError, match="unknown method"):
        equivalent_conicity(y, 0.1 * y, AMP, method="fourier")


def test_one_sided_nonzero_at_origin():
    y = np.linspace(0, 0.01, 11)
    with pytest.raises(ValueError, match=r"Delta r\(0\) must be 0"):
        equivalent_conicity(y, 0.1 * y + 1e-4, AMP)


def test_wavelength_non_restoring():
    y = np.linspace(-0.01, 0.01, 21)
    with pytest.raises(ValueError, match="not positive"):
        equivalent_conicity(y, -0.1 * y, AMP, method="wavelength")


def test_wavelength_excursion_beyond_range():
    # offset Delta r (equilibrium at y = -1 mm): starting at +3 mm the wheelset swings to -5 mm, outside the
    # samples although [-3 mm, 3 mm] is covered
    y = np.linspace(-0.0035, 0.004, 151)
    with pytest.raises(ValueError, match="beyond the sampled"):
        equivalent_conicity(y, 0.1 * (y + 0.001), AMP, method="wavelength")


def test_klingel_wavelength_errors():
    with pytest.raises(ValueError, match="conicity must be positive"):
        klingel_wavelength(0.0)
    with pytest.raises(ValueError, match="r0_m must be positive"):
        klingel_wavelength(0.1, r0_m=-1.0)
