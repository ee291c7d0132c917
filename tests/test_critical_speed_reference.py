"""The linear stability tools (exudyn_wheelrail/analysis/stability.py) against independent references: Klingel's
kinematic frequency of a free wheelset, the characteristic polynomial of the restrained two-degree-of-freedom
wheelset (derived here) and its Routh-Hurwitz stability boundary, the rigid bogie's kinematic wavelength, the known
trends of the critical speed; the mode tracking, the zero crossing and the limit-cycle measure on constructed data.

Data: the Manchester vehicle 1 wheelset (m = 1813 kg, I_z = 1120 kg m², r0 = 0.46 m), b = 0.75 m, conicity 0.2,
Kalker's creep coefficients of the order of 10 MN (Knothe & Stichel, Rail Vehicle Dynamics, 2017)."""
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from exudyn_wheelrail.analysis.stability import (ModeSet, bogie_kinematic_wavelength_m, bogie_state_matrix,
                                                 first_zero_crossing, frequency_damping, klingel_frequency_hz,
                                                 limit_cycle, linger_amplitude, modes_of, track_modes,
                                                 wheelset_state_matrix, window_amplitudes)

DATA = Path(__file__).parent / "data" / "stability"
M_WS, I_WS, R0, B, CON = 1813.0, 1120.0, 0.46, 0.75, 0.2
F = 10e6
KY, KPSI = 2 * 3.884e6 / 100.0, 2 * 31.391e6 * 1.0 ** 2 / 100.0      # soft restraint: critical speed in range


def _oscillating(A):
    ms = modes_of(A)
    osc = ms.listed & (ms.eigenvalues.imag > 0)
    return ms.eigenvalues[osc]


@pytest.mark.parametrize("speed", [10.0, 30.0, 80.0])
def test_free_wheelset_klingel_limit(speed):
    """Without creep damping (f11 = f22 -> inf: pure rolling) the free wheelset's oscillating mode has Klingel's
    frequency.  Tolerance 1 %: the inertia terms change the frequency by O((m V ω / f)²) (the Wickens
    expansion of the quartic), here below 1e-6 with f = 1e11 N."""
    A = wheelset_state_matrix(speed, M_WS, I_WS, CON, B, R0, 1e11, 1e11)
    lam = _oscillating(A)
    assert len(lam) == 1
    f = lam[0].imag / (2 * math.pi)
    assert f == pytest.approx(klingel_frequency_hz(speed, CON, B, R0), rel=0.01)
    # and the textbook wavelength 2π √(b r0 / λ) (independent of the speed)
    assert speed / f == pytest.approx(2 * math.pi * math.sqrt(B * R0 / CON), rel=0.01)


def _quartic(speed, f11, f22, ky, kpsi, con=CON):
    """The characteristic polynomial det(s² M + s C + K) of the restrained wheelset, coefficients of s⁴ ... s⁰:

        m ÿ + 2 f22 (ẏ/V - ψ) + ky y = 0,   I ψ̈ + 2 f11 b (b ψ̇/V + λ y/r0) + kψ ψ = 0
        (m s² + c1 s + ky)(I s² + c2 s + kψ) + 2 f22 · 2 f11 b λ / r0 = 0,  c1 = 2 f22 / V, c2 = 2 f11 b² / V
    """
    c1, c2 = 2 * f22 / speed, 2 * f11 * B * B / speed
    return np.array([M_WS * I_WS, M_WS * c2 + I_WS * c1, M_WS * kpsi + c1 * c2 + ky * I_WS, c1 * kpsi + c2 * ky,
                     ky * kpsi + 4 * f11 * f22 * B * con / R0])


def _hurwitz(speed, f11=F, f22=F, ky=KY, kpsi=KPSI, con=CON):
    """The Routh-Hurwitz determinant of the quartic whose sign change is the stability boundary (a4..a0 > 0):
    a3 a2 a1 - a3² a0 - a4 a1²."""
    a4, a3, a2, a1, a0 = _quartic(speed, f11, f22, ky, kpsi, con)
    return (a3 * a2 * a1 - a3 * a3 * a0 - a4 * a1 * a1) / (a3 * a2 * a1)


@pytest.mark.parametrize("speed", [20.0, 60.0, 120.0])
def test_restrained_wheelset_against_characteristic_polynomial(speed):
    """The state matrix's eigenvalues are the roots of the quartic derived above (the same linear ODE in two
    forms: agreement to round-off; 1e-6 relative)."""
    A = wheelset_state_matrix(speed, M_WS, I_WS, CON, B, R0, F, F, KY, KPSI)
    lam = np.sort_complex(np.linalg.eigvals(A))
    roots = np.sort_complex(np.roots(_quartic(speed, F, F, KY, KPSI)))
    assert np.allclose(lam, roots, rtol=1e-6, atol=1e-9 * np.abs(roots).max())


def _min_damping(speed, **kw):
    p = dict(f11=F, f22=F, ky=KY, kpsi=KPSI, con=CON)
    p.update(kw)
    A = wheelset_state_matrix(speed, M_WS, I_WS, p["con"], B, R0, p["f11"], p["f22"], p["ky"], p["kpsi"])
    return float(np.min(modes_of(A).damping_ratio))


def test_restrained_wheelset_critical_speed_routh_hurwitz():
    """The speed where the least damped mode's damping ratio crosses zero (on a 1 m/s grid, interpolated by
    first_zero_crossing) is the Routh-Hurwitz boundary.  Tolerance 1 %: linear interpolation of ζ(V) over a step
    of 1 m/s around a crossing near 100 m/s (ζ is smooth; the interpolation error is O(step²) ≈ 1e-4 relative)."""
    v_rh = brentq(_hurwitz, 5.0, 500.0)
    grid = np.arange(5.0, 500.0, 1.0)
    v_grid = first_zero_crossing(grid, [_min_damping(v) for v in grid])
    assert v_grid == pytest.approx(v_rh, rel=0.01)
    assert _min_damping(0.99 * v_rh) > 0.0 > _min_damping(1.01 * v_rh)


def test_trends_of_the_critical_speed():
    """Higher conicity -> lower critical speed; a stiffer yaw restraint -> higher (Wickens; Knothe & Stichel,
    Rail Vehicle Dynamics): the Routh-Hurwitz boundary of the restrained wheelset."""
    def v_crit(**kw):
        return brentq(lambda v: _hurwitz(v, **kw), 1.0, 5000.0)
    assert v_crit(con=0.3) < v_crit(con=0.2) < v_crit(con=0.1)
    assert v_crit(kpsi=2 * KPSI) > v_crit(kpsi=KPSI) > v_crit(kpsi=0.5 * KPSI)


@pytest.mark.parametrize("speed,a", [(30.0, 1.28), (70.0, 1.28), (50.0, 1.0)])
def test_rigid_bogie_kinematic_wavelength(speed, a):
    """The rigid two-axle bogie with f11 = f22 and no creep damping (f -> inf) rolls with the wavelength
    2π √(b r0 (1 + a²/b²) / λ).  Tolerance 1 %: inertia corrections O((m V ω / f)²) < 1e-6 with f = 1e11 N."""
    m, izz = 2615.0 + 2 * M_WS, 3067.0 + 2 * (I_WS + M_WS * a * a)
    A = bogie_state_matrix(speed, m, izz, CON, B, R0, a, 1e11, 1e11)
    lam = _oscillating(A)
    assert len(lam) == 1
    wavelength = speed / (lam[0].imag / (2 * math.pi))
    assert wavelength == pytest.approx(bogie_kinematic_wavelength_m(CON, B, R0, a), rel=0.01)
    assert bogie_kinematic_wavelength_m(CON, B, R0, a) == pytest.approx(
        2 * math.pi * math.sqrt(B * R0 * (1 + a * a / (B * B)) / CON), rel=1e-12)


def test_frequency_and_damping_ratio_of_eigenvalues():
    """λ = ω_n(-ζ ± i√(1-ζ²)) gives back f = ω_n√(1-ζ²)/2π and ζ; a real eigenvalue: f = 0, ζ = -sign(σ)."""
    wn, z = 2 * math.pi * 5.0, 0.07
    lam = np.array([wn * (-z + 1j * math.sqrt(1 - z * z)), -3.0 + 0j, 2.0 + 0j])
    f, zeta = frequency_damping(lam)
    assert f[0] == pytest.approx(5.0 * math.sqrt(1 - z * z), rel=1e-12)
    assert zeta.tolist() == pytest.approx([z, 1.0, -1.0], rel=1e-12)


def test_mode_tracking_follows_crossing_modes():
    """Two modes whose frequencies cross between two speeds (shapes orthogonal) are followed by their shapes, not
    swapped by their frequency order; a shuffled order is undone."""
    shapes = np.eye(3, dtype=complex)
    a = ModeSet([-1 + 10j, -1 + 12j, -5 + 0j], shapes)
    b = ModeSet([-5 + 0j, -1.1 + 12.2j, -0.9 + 10.5j], shapes[:, [2, 0, 1]])     # modes 0 and 1 crossed, shuffled
    ta, tb = track_modes([a, b])
    assert np.allclose(tb.shapes, ta.shapes)
    assert tb.eigenvalues[0] == -1.1 + 12.2j and tb.eigenvalues[2] == -5


def test_first_zero_crossing():
    assert first_zero_crossing([1, 2, 3], [0.3, 0.1, -0.1]) == pytest.approx(2.5)
    assert first_zero_crossing([1, 2, 3], [0.3, 0.2, 0.1]) is None
    assert first_zero_crossing([1, 2, 3], [-0.1, 0.2, 0.1]) == 1.0
    assert first_zero_crossing([1, 2, 3], [0.2, float("nan"), -0.2]) == pytest.approx(2.0)


def test_limit_cycle_measure():
    """A sustained sine persists with its amplitude (half its peak-to-peak); sines whose envelope decays like a mode
    of damping ratio ζ (per cycle of 20 m: amplitude e^(−2π ζ s/20)) give that ζ back and persist only below the
    threshold 1e-3 — for a short wavelength and a long one alike; a tiny one is below the amplitude threshold; a
    steady offset with a tiny oscillation is no cycle."""
    s = np.linspace(0.0, 1500.0, 300001)
    amp, zeta, persists = limit_cycle(s, 1e-3 * np.sin(2 * math.pi * s / 20.0), 100.0, 5, 0.2e-3, 1e-3)
    assert amp == pytest.approx(1e-3, rel=1e-4) and zeta == pytest.approx(0.0, abs=1e-6) and persists
    for wavelength in (20.0, 90.0):
        for z_true, expected in ((0.02, False), (0.003, False), (0.0003, True), (-0.001, True)):
            x = 1e-3 * np.exp(-2 * math.pi * z_true * s / wavelength) * np.sin(2 * math.pi * s / wavelength)
            amp, zeta, persists = limit_cycle(s, x, 100.0, 5, 1e-12, 1e-3)
            # the windows' peak-to-peak sample the envelope within a wavelength of their start, the crossings count
            # the cycles to one in ~5 (90 m): ζ back to 25 % (the threshold's decisions are a factor 3 away)
            assert zeta == pytest.approx(z_true, rel=0.25, abs=2e-5) and persists is expected, (wavelength, z_true)
    assert not limit_cycle(s, 1e-5 * np.sin(s), 100.0, 5, 0.2e-3, 1e-3)[2]
    assert not limit_cycle(s, 5e-3 + 1e-5 * np.sin(s), 100.0, 5, 0.2e-3, 1e-3)[2]


def test_mode_shapes_are_eigenvectors_of_a_linearised_wheelset():
    """Every shape modes_of returns is an eigenvector of its matrix: |A v − λ v| ≤ 1e-9 max|A_ij| |v|.  The matrix
    (tests/data/stability/) is the single wheelset linearised at 300 km/h with the linear creep law; its couplings
    that vanish by symmetry came out of the central differences as round-off (1e-31 … 1e-22 beside entries of 1e6),
    on which LAPACK's balancing returned eigenvectors with residuals of ~1e2 (measured with NumPy 2.4 / OpenBLAS):
    wrong lateral shares, the hunting mode not recognised."""
    A = np.loadtxt(DATA / "wheelset_300kmh_linear_creep.csv", delimiter=",")
    ms = modes_of(A, n_displacement=A.shape[0])
    scale = np.abs(A).max()
    for k in range(A.shape[0]):
        v = ms.shapes[:, k]
        assert np.linalg.norm(A @ v - ms.eigenvalues[k] * v) <= 1e-9 * scale * np.linalg.norm(v), k
    # and the eigenvalues are those of the matrix (to its conditioning: the pitch angle's zero eigenvalue)
    assert np.allclose(np.sort_complex(ms.eigenvalues), np.sort_complex(np.linalg.eigvals(A)), atol=1e-6)


def test_window_amplitudes():
    """Consecutive windows of a sine a wavelength long or longer give its amplitude; a steady offset does not count;
    a last window shorter than half a window is left out, a longer one kept."""
    s = np.linspace(0.0, 105.0, 21001)
    amps = window_amplitudes(s, 2.0 + 1e-3 * np.sin(2 * math.pi * s / 20.0), 5.0, 20.0)
    assert len(amps) == 5
    assert amps == pytest.approx([1e-3] * 5, rel=1e-4)
    for end, n in ((114.0, 5), (116.0, 6)):
        s = np.linspace(0.0, end, 20001)
        assert len(window_amplitudes(s, np.sin(s), 5.0, 20.0)) == n


def test_linger_amplitude_of_two_runs_around_an_unstable_cycle():
    """Two runs started just either side of an unstable cycle of amplitude A*: their distance to it in ln(amplitude)
    grows like ε e^(μk) per window (the cycle's instability) after a transient that decays like e^(−2k) (the other
    modes); one run decays to a floor, the other stops at the stable cycle (10 A*).  Where both linger the rule reads
    A* back: the drift is symmetric in ln(amplitude), so the geometric mean removes it; what is left is the
    transient where the rule reads — within 2 % for these parameters (ε = 0.03, μ = 0.5 per window, the transient at
    50 % of A* at the first window; measured 0.9 %)."""
    k = np.arange(30.0)
    a_star = 2e-4
    drift = 0.03 * np.exp(0.5 * k)
    transient = 1.0 + 0.5 * np.exp(-2.0 * k)
    decaying = np.maximum(a_star * transient * np.exp(-drift), 1e-9)
    persisting = np.minimum(a_star * transient * np.exp(drift), 10 * a_star)
    i, amp = linger_amplitude(decaying, persisting, 2.0)
    assert i is not None and amp == pytest.approx(a_star, rel=0.02)
    assert abs(math.log(persisting[i] / decaying[i])) <= math.log(2.0)
    # runs that part within the first window: no window qualifies
    assert linger_amplitude([1e-4, 1e-5, 1e-6], [1e-3, 2e-3, 2e-3], 2.0)[0] is None
    assert math.isnan(linger_amplitude([1e-4, 1e-5, 1e-6], [1e-3, 2e-3, 2e-3], 2.0)[1])
