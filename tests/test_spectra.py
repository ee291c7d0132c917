"""Standard track-irregularity spectra and the irregularities generated from them (exudyn_wheelrail.track.spectra),
against the published spectra typed again below from their sources -- never against the package's own tables or
its ``psd()``.

Conventions (those documented in exudyn_wheelrail/track/spectra.py, checked here)
----------------------------------------------------------------------------------
* ``S(Ω)`` is **one-sided** and **per angular wavenumber**: m²/(rad/m), ``Ω = 2π/λ`` in rad/m, Ω > 0 only, so that
  the variance of the irregularity in a band is ``σ² = ∫ S(Ω) dΩ`` over the band.  The same spectrum per cycles/m
  (``n = 1/λ``) is ``S_n(n) = 2π S(2π n)``; a two-sided spectrum would be ``S/2`` on -∞ < Ω < ∞.  A generated
  harmonic of amplitude ``a_k`` at ``Ω_k`` has mean square ``a_k²/2 = S(Ω_k) ΔΩ``, hence ``a_k = sqrt(2 S ΔΩ)``.
* ``scipy.signal.welch(x, fs=1/Δs, scaling="density")`` returns a one-sided PSD per cycles/m (fs in samples/m):
  per rad/m it is divided by 2π.
* The published FRA coefficients are in cm²·rad/m and give S in cm²/(rad/m): 1 cm² = (0.01 m)² = 1e-4 m².  The
  German coefficients are in m·rad and give S in m²/(rad/m) directly.  A wrong conversion (cm² for m², per cycle
  for per radian, one- for two-sided) is a factor 1e4, 2π or 2: every test below catches each of them.

Published spectra (typed again here)
------------------------------------
FRA track classes 1-6 (Hamid & Yang, "Analytical description of track-geometry variations", Transportation Research
Record 838 (1981), fitted to US track-geometry measurements; tabulated per class with ``k = 0.25`` and ``Ω_c =
0.8245`` rad/m in Garg & Dukkipati, *Dynamics of Railway Vehicle Systems*, Academic Press 1984, ch. 2, and Zhai,
*Vehicle-Track Coupled Dynamics*, Springer 2020, ch. 2 (US track spectra)), with S in cm²/(rad/m)::

    level       k A_v Ω_c² / (Ω² (Ω² + Ω_c²))
    alignment   k A_a Ω_c² / (Ω² (Ω² + Ω_c²))
    cross level 4 k A_v Ω_c² / ((Ω² + Ω_c²)(Ω² + Ω_s²))      (gauge: the same; ASSUMPTION, the package's
                                                             documented convention, not a published spectrum)

German high-speed spectra, low and high interference (the DB/ORE B176 spectra as quoted in Zhai 2020, ch. 2, and
in Guo, Xia, De Roeck & Liu, Computers & Structures 112-113 (2012) 205-216), with A in m·rad, S in m²/(rad/m)::

    level       A_v Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²))
    alignment   A_a Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²))
    gauge       A_g Ω_c² Ω² / ((Ω² + Ω_r²)(Ω² + Ω_c²)(Ω² + Ω_s²))
    cross level (A_v / b²) Ω_c² Ω² / ((Ω² + Ω_r²)(Ω² + Ω_c²)(Ω² + Ω_s²)),   b = 0.75 m

The published cross-level formula has units rad²/(rad/m): it is the PSD of the cross-level *angle* ``c/(2b)``; the
package's channel is the height difference ``c`` (m), i.e. ``(2b)²`` times it (documented in spectra.py).

All the spectra are rational in ``u = Ω²``: ``S = C u^m / Π_i (u + q_i)`` with distinct ``q_i ≥ 0`` (``_rational``).
Partial fractions turn that into ``S = Σ_i B_i / (Ω² + q_i)``, whose band integral is closed
(``B/sqrt(q) atan(Ω/sqrt(q))``, or ``-B/Ω`` for q = 0): the reference for every variance below.

What is checked
---------------
1. ``psd()`` of every class and channel equals the published formula at wavenumbers across the band (round-off).
2. ``band_variance()`` equals the closed-form band integral (quadrature tolerance).
3. The generated signal over one period: its discrete Fourier amplitudes are ``sqrt(2 S(Ω_k) ΔΩ)`` of the
   published S at every grid wavenumber of the band and zero outside (deterministic: the phases do not enter the
   moduli); its mean square is the band integral within the midpoint rule's bound.
4. Welch's estimate over 16 fixed realisations follows the published S in four sub-bands, within a chi-square
   tolerance (below).

Statistics of the Welch check (4.)
----------------------------------
Each realisation is L = 12 000 m at Δs = 0.25 m (48 000 samples), cut into Hann segments of M = 2048 samples
(512 m, bin width δ = 2π/512 rad/m) overlapping by half: K = 45 segments.  A segment's bin gathers ~23 harmonics
of independent uniform phase (L/512 of them, ~35 weighted by the window's kernel): nearly a complex Gaussian, so its
periodogram is ``E·χ²₂/2`` (a sum of N random phasors has a slightly smaller spread than that: conservative).  Hann
segments overlapping by half are correlated by ρ = 1/6 (Welch 1967; Percival & Walden 1993, sect. 6.17), so one
realisation's average has ν = 2K/(1 + 2ρ²) = 85.3 equivalent degrees of freedom, the 16 independent realisations
ν = 1364: ``log(P/E)`` has mean ψ(ν/2) - log(ν/2) ≈ -1/ν = -7e-4 and standard deviation sqrt(ψ'(ν/2)) = 0.0383.
Neighbouring Hann bins are correlated: the periodogram correlation of bins 1 and 2 apart is (2/3)² = 0.444 and
(1/6)² = 0.028 (from Σ w² e^{-2πi j n/M} / Σ w² = -2/3, 1/6 for w = sin²(πn/M)), so the mean of log(P/S) over a
sub-band of n_b bins has a standard deviation at most 0.0383 sqrt(1.944/n_b) (1.944 = 1 + 2·0.444 + 2·0.028).
The window also smooths the spectrum: the Hann periodogram kernel has second moment δ²/3 and fourth moment δ⁴/3,
so ``E/S - 1 ≈ S''/S δ²/6 + S''''/S δ⁴/72``.  For these rational spectra ``|S''/S| ≤ 24/Ω²``: ``|S''/S| =
|(ln S)'' + (ln S)'²|`` with ``(ln S)' = (2/Ω)(m - Σ Ω²/(Ω²+q_i))`` between -4/Ω and 2/Ω and ``|(ln S)''| ≤
(2m + 2 n_q)/Ω² ≤ 8/Ω²`` for at most three factors; ``|S''''/S| ≤ 1000/Ω⁴`` (the Ω⁻⁴ tail alone gives 4·5·6·7 =
840; on a fine grid the 32 spectra reach 20/Ω² and 826/Ω⁴).  The smoothing bias is then at most ``4/j² + 14/j⁴``
at bin j; the kernel's tail beyond D bins (~0.0135/D⁵ of its weight) adds < 1e-4 at the sub-bands' distance from
the band's edges (D ≥ 3.6 bins).  (The bias computed exactly for the cases here, the window's kernel summed over
the generated harmonics, is at most 0.4 %, well inside these bounds.)  Sub-bands of bins [12, 24), [24, 48),
[48, 96), [96, 168) (the band 3-150 m is bins 3.4-170.7): the tolerance on the sub-band mean of log(P/S) is
5 standard deviations + 1/ν + the smoothing bound + 1e-4: 0.106, 0.062, 0.041, 0.033 -- a factor 2 (log 2 = 0.69)
is 6.5 to 21 times that, 2π (1.84) 17 to 56 times; a 10 % error in a coefficient, or an Ω_s moved between
classes, is caught in the upper sub-bands.  The chi-square spread is an upper bound here: the generated harmonics
have fixed amplitudes (only their phases are random) and the 45 segments of a realisation tile nearly its whole
period, so the cross terms between harmonics average out and the estimate scatters less than that of a Gaussian
process.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import welch

from exudyn_wheelrail.track.irregularities import channel_values
from exudyn_wheelrail.track.spectra import SPECTRA, SpectralIrregularity, TrackSpectrum, spectrum_by_name

CHANNEL_NAMES = ("alignment", "level", "cross_level", "gauge")

# ------------------------------------------------------------------------------------------------ published tables
# FRA (Hamid & Yang 1981; Garg & Dukkipati 1984, ch. 2; Zhai 2020, ch. 2):
# class -> (A_v [cm² rad/m], A_a [cm² rad/m], Ω_s [rad/m], Ω_c [rad/m]); k = 0.25 for every class.
FRA_TABLE = {1: (1.2107, 3.3634, 0.6046, 0.8245),
             2: (1.0181, 1.2107, 0.9308, 0.8245),
             3: (0.6816, 0.4128, 0.8520, 0.8245),
             4: (0.5376, 0.3027, 1.1312, 0.8245),
             5: (0.2095, 0.0762, 0.8209, 0.8245),
             6: (0.0339, 0.0339, 0.4380, 0.8245)}
FRA_K_PUBLISHED = 0.25
CM2_IN_M2 = 0.01 ** 2          # 1 cm² = (0.01 m)²: S [m²/(rad/m)] = 1e-4 S [cm²/(rad/m)]
# German high-speed spectra (Zhai 2020, ch. 2; Guo et al. 2012): interference -> (A_a, A_v, A_g) [m rad]
GERMAN_TABLE = {"low": (2.119e-7, 4.032e-7, 0.532e-7), "high": (6.125e-7, 10.80e-7, 1.032e-7)}
GERMAN_OMEGA_C, GERMAN_OMEGA_R, GERMAN_OMEGA_S = 0.8246, 0.0206, 0.4380     # rad/m
GERMAN_B_M = 0.75              # half the distance of the rails' rolling circles [m]

ALL_NAMES = [f"fra_class_{c}" for c in FRA_TABLE] + [f"german_{lv}" for lv in GERMAN_TABLE]


def _published_psd(name, channel, omega):
    """The published one-sided PSD [m²/(rad/m)] at Ω [rad/m], written as in the sources (module docstring)."""
    w2 = np.asarray(omega, dtype=float) ** 2
    if name.startswith("fra_class_"):
        a_v, a_a, om_s, om_c = FRA_TABLE[int(name[len("fra_class_"):])]
        k = FRA_K_PUBLISHED
        if channel in ("level", "alignment"):
            a = a_v if channel == "level" else a_a
            s_cm2 = k * a * om_c ** 2 / (w2 * (w2 + om_c ** 2))                        # cm²/(rad/m)
        else:
            s_cm2 = 4 * k * a_v * om_c ** 2 / ((w2 + om_c ** 2) * (w2 + om_s ** 2))
        return s_cm2 * CM2_IN_M2
    a_a, a_v, a_g = GERMAN_TABLE[name[len("german_"):]]
    om_c, om_r, om_s, b = GERMAN_OMEGA_C, GERMAN_OMEGA_R, GERMAN_OMEGA_S, GERMAN_B_M
    if channel == "level":
        return a_v * om_c ** 2 / ((w2 + om_r ** 2) * (w2 + om_c ** 2))
    if channel == "alignment":
        return a_a * om_c ** 2 / ((w2 + om_r ** 2) * (w2 + om_c ** 2))
    if channel == "gauge":
        return a_g * om_c ** 2 * w2 / ((w2 + om_r ** 2) * (w2 + om_c ** 2) * (w2 + om_s ** 2))
    angle = (a_v / b ** 2) * om_c ** 2 * w2 / ((w2 + om_r ** 2) * (w2 + om_c ** 2) * (w2 + om_s ** 2))  # rad²/(rad/m)
    return (2 * b) ** 2 * angle                                   # the height difference c = 2b · angle [m]


def _rational(name, channel):
    """``(C, m, q)`` with ``S(Ω) = C u^m / Π (u + q_i)``, ``u = Ω²`` -- the published formula regrouped."""
    if name.startswith("fra_class_"):
        a_v, a_a, om_s, om_c = FRA_TABLE[int(name[len("fra_class_"):])]
        if channel in ("level", "alignment"):
            a = a_v if channel == "level" else a_a
            return CM2_IN_M2 * FRA_K_PUBLISHED * a * om_c ** 2, 0, (0.0, om_c ** 2)
        return CM2_IN_M2 * 4 * FRA_K_PUBLISHED * a_v * om_c ** 2, 0, (om_c ** 2, om_s ** 2)
    a_a, a_v, a_g = GERMAN_TABLE[name[len("german_"):]]
    c2, r2, s2 = GERMAN_OMEGA_C ** 2, GERMAN_OMEGA_R ** 2, GERMAN_OMEGA_S ** 2
    if channel in ("level", "alignment"):
        return (a_v if channel == "level" else a_a) * c2, 0, (r2, c2)
    if channel == "gauge":
        return a_g * c2, 1, (r2, c2, s2)
    b = GERMAN_B_M
    return (2 * b) ** 2 * (a_v / b ** 2) * c2, 1, (r2, c2, s2)     # the height difference: (2b)² x the angle's


def _partial_fractions(name, channel):
    """``[(B_i, q_i)]`` with ``S(Ω) = Σ B_i/(Ω² + q_i)``: ``1/Π(u+q_i) = Σ α_i/(u+q_i)``, ``α_i = Π_{j≠i} 1/(q_j -
    q_i)``; with the factor u, ``u/Π(u+q_i) = Σ -α_i q_i/(u+q_i)`` (Σ α_i = 0 for two factors or more)."""
    c, m, q = _rational(name, channel)
    out = []
    for i, qi in enumerate(q):
        alpha = math.prod(1.0 / (qj - qi) for j, qj in enumerate(q) if j != i)
        out.append((c * alpha * (-qi if m else 1.0), qi))
    return out


def _antiderivative(b, q, omega):
    return b / math.sqrt(q) * math.atan(omega / math.sqrt(q)) if q > 0.0 else -b / omega


def _band_integral(name, channel, omega_lo, omega_hi):
    """``∫ S dΩ`` over [Ω_lo, Ω_hi] in closed form (partial fractions)."""
    return math.fsum(_antiderivative(b, q, omega_hi) - _antiderivative(b, q, omega_lo)
                     for b, q in _partial_fractions(name, channel))


def _curvature_majorant(name, channel, omega):
    """A decreasing bound of ``|S''(Ω)|``: ``d²/dΩ² 1/(Ω²+q) = (6Ω² - 2q)/(Ω²+q)³``, at most ``6/(Ω²+q)²``."""
    w2 = np.asarray(omega, dtype=float) ** 2
    return sum(abs(b) * 6.0 / (w2 + q) ** 2 for b, q in _partial_fractions(name, channel))


# ------------------------------------------------------------------------------------------------ 1. the catalogue
def test_catalogue_is_the_six_fra_classes_and_the_two_german_levels():
    assert set(SPECTRA) == set(ALL_NAMES)
    for c in FRA_TABLE:
        sp = spectrum_by_name(f"fra_class_{c}")
        assert isinstance(sp, TrackSpectrum) and sp.family == "fra" and sp.level == c
    for lv in GERMAN_TABLE:
        sp = spectrum_by_name(f"german_{lv}")
        assert sp.family == "german" and sp.level == lv
    assert spectrum_by_name(SPECTRA["german_low"]) is SPECTRA["german_low"]


# wavenumbers from the longest to the shortest generated wavelengths and beyond (300 m ... 1 m) and each class's
# corner wavenumbers, where a wrong Ω_s or Ω_c shows most
OMEGA_CHECK = np.array([2 * math.pi / 300, 0.03, 0.1, 0.2, 0.4380, 0.6046, 0.8245, 1.1312, 2.0, 2 * math.pi])


@pytest.mark.parametrize("name", ALL_NAMES)
def test_psd_is_the_published_formula(name):
    """Every channel of every class.  The formula is a handful of products and quotients: both sides agree to a few
    ulp (1e-15); rtol 1e-12 leaves a margin of 1e3 and still catches a one-digit typo in a 5-digit coefficient
    (>= 1e-5 relative, e.g. 0.4128 -> 0.4182 is 1.3e-2)."""
    sp = SPECTRA[name]
    for ch in CHANNEL_NAMES:
        ref = _published_psd(name, ch, OMEGA_CHECK)
        np.testing.assert_allclose(sp.psd(ch, OMEGA_CHECK), ref, rtol=1e-12, atol=0, err_msg=f"{name} {ch}")
        # the test's two typings of the formula agree (the regrouped one feeds the integrals below)
        c, m, q = _rational(name, ch)
        u = OMEGA_CHECK ** 2
        np.testing.assert_allclose(c * u ** m / np.prod([u + qi for qi in q], axis=0), ref, rtol=1e-13)
        pf = sum(b / (u + qi) for b, qi in _partial_fractions(name, ch))
        # the partial fractions' terms cancel by up to 1.4e4 (German gauge and cross level at 2π/300 m): ~1e-11
        np.testing.assert_allclose(pf, ref, rtol=1e-9)


def test_units_cm2_to_m2_and_cross_level_height():
    """The unit conversions spelled out on one value each: FRA class 4 level at Ω = 0.5 rad/m from the table in
    cm²/(rad/m), by hand: 0.25 · 0.5376 · 0.8245² / (0.25 · (0.25 + 0.8245²)) = 0.39305 cm²/(rad/m) =
    3.9305e-5 m²/(rad/m); German low cross level at Ω = 0.5: the published angle PSD (A_v/b²)·Ω_c²·Ω²/(...) in
    rad²/(rad/m) times (2b)² = 2.25 m² for the height difference."""
    w = 0.5
    s_cm2 = 0.25 * 0.5376 * 0.8245 ** 2 / (w ** 2 * (w ** 2 + 0.8245 ** 2))
    assert s_cm2 == pytest.approx(0.39305, rel=1e-4)                    # the hand value, 5 digits
    assert SPECTRA["fra_class_4"].psd("level", w) == pytest.approx(s_cm2 * 1e-4, rel=1e-12)
    w2 = w ** 2
    angle = (4.032e-7 / 0.75 ** 2) * 0.8246 ** 2 * w2 / ((w2 + 0.0206 ** 2) * (w2 + 0.8246 ** 2) * (w2 + 0.4380 ** 2))
    assert SPECTRA["german_low"].psd("cross_level", w) == pytest.approx(1.5 ** 2 * angle, rel=1e-12)


@pytest.mark.parametrize("name", ALL_NAMES)
def test_band_variance_is_the_closed_form_integral(name):
    """``band_variance`` (scipy quad, epsrel 1e-10) against the closed form of the published S, for the default band
    3-150 m and a wider one (1-300 m).  The closed form's terms cancel by at most 430 (their absolute sum over
    the integral, German gauge): ~1e-13 relative; rtol 1e-8 allows quad's error estimate to be optimistic by 100."""
    sp = SPECTRA[name]
    for lo, hi in ((3.0, 150.0), (1.0, 300.0)):
        for ch in CHANNEL_NAMES:
            ref = _band_integral(name, ch, 2 * math.pi / hi, 2 * math.pi / lo)
            assert sp.band_variance(ch, (lo, hi)) == pytest.approx(ref, rel=1e-8), (name, ch, lo, hi)
    assert sp.band_variance("level") == pytest.approx(_band_integral(name, "level", 2 * math.pi / 150,
                                                                     2 * math.pi / 3), rel=1e-8)   # default band


# ------------------------------------------------------------------------------- 3. one period of a generated track
# L = 6000 m at 0.25 m: the grid is ΔΩ = 2π/L; the band's edges are put half-way between grid wavenumbers
# (λ_max = L/40.5, λ_min = L/2000.5: Ω_k for k = 41 ... 2000 are generated), so the generated set is exactly the
# midpoint rule of the band -- no grid point sits on an edge where rounding would decide.
PERIOD_M = 6000.0
PERIOD_STEP_M = 0.25
K_LO, K_HI = 41, 2000
PERIOD_BAND_M = (PERIOD_M / (K_HI + 0.5), PERIOD_M / (K_LO - 0.5))


@pytest.fixture(scope="module")
def one_period():
    """One generated track per spectrum (all four channels; fixed seeds, any seed gives the same moduli)."""
    return {name: SpectralIrregularity(name, PERIOD_M, seed=20 + i, band_m=PERIOD_BAND_M, step_m=PERIOD_STEP_M)
            for i, name in enumerate(ALL_NAMES)}


@pytest.mark.parametrize("name", ALL_NAMES)
def test_generated_harmonics_have_the_published_amplitudes_and_the_seeded_phases(one_period, name):
    """Over its period the signal's DFT holds each harmonic alone: ``X_k = (n/2) a_k e^{iφ_k}``, with ``a_k =
    sqrt(2 S(Ω_k) ΔΩ)`` (one-sided S per rad/m) and, as documented, ``φ_k`` drawn uniform in [0, 2π) from one
    ``numpy.random.default_rng(seed)``, n/2 + 1 per channel in the order alignment, level, cross level, gauge (the
    channels independent).  Round-off of the inverse and forward FFT: at most ~5 ε log2(n) of ||X||₂ in any bin,
    i.e. ≤ 5 · 2.2e-16 · 15 · sqrt(1960) max a_k = 7e-13 max a_k; the bound 1e-10 max a_k has a margin of 100 and
    catches any coefficient error above ~1e-6 (a wrong factor 2, 2π or 1e4, a wrong Ω_s or Ω_c, a shifted band) at
    every generated wavenumber; the phase of bin k is then within 1e-10 max a / a_k rad (max a / a_k ≤ 133 here:
    ≤ 1.4e-8 rad; bound used 2 · 1e-10 max a / a_k)."""
    g = one_period[name]
    n = len(g.s_m)
    assert n == round(PERIOD_M / PERIOD_STEP_M) and g.length_m == n * PERIOD_STEP_M
    d_omega = 2 * math.pi / PERIOD_M
    k = np.arange(n // 2 + 1)
    inside = (k >= K_LO) & (k <= K_HI)
    np.testing.assert_allclose(g.omega_rad_m, k[inside] * d_omega, rtol=1e-14)
    rng = np.random.default_rng(g.seed)
    for ch in CHANNEL_NAMES:
        phase = rng.uniform(0.0, 2 * math.pi, size=len(k))
        spectrum = 2.0 * np.fft.rfft(g.channels[ch]) / n
        expect = np.zeros(len(k))
        expect[inside] = np.sqrt(2.0 * _published_psd(name, ch, k[inside] * d_omega) * d_omega)
        atol = 1e-10 * expect.max()
        np.testing.assert_allclose(np.abs(spectrum), expect, rtol=0, atol=atol, err_msg=f"{name} {ch}")
        phase_error = np.angle(spectrum[inside] * np.exp(-1j * phase[inside]))
        assert np.all(np.abs(phase_error) <= 2 * atol / expect[inside]), (name, ch)


@pytest.mark.parametrize("name", ALL_NAMES)
def test_variance_is_the_band_integral_of_the_published_psd(one_period, name):
    """No statistics: the mean square over the period is ``Σ a_k²/2 = Σ S(Ω_k) ΔΩ`` exactly (Parseval; phases do
    not enter), the midpoint rule of the band integral on the grid.  Its error is ``Σ_k ΔΩ³/24 S''(ξ_k)``, bounded
    with the decreasing majorant of |S''| at each panel's left end.  The mean is zero (no Ω = 0 harmonic)."""
    g = one_period[name]
    d_omega = 2 * math.pi / PERIOD_M
    omega_k = np.arange(K_LO, K_HI + 1) * d_omega
    lo, hi = 2 * math.pi / PERIOD_BAND_M[1], 2 * math.pi / PERIOD_BAND_M[0]
    for ch in CHANNEL_NAMES:
        x = g.channels[ch]
        mean_square = float(np.mean(x ** 2))
        midpoint = math.fsum(_published_psd(name, ch, omega_k) * d_omega)
        # round-off: FFT (~5 ε log2 n relative to the rms) and the sum of 24 000 squares: << 1e-11
        assert mean_square == pytest.approx(midpoint, rel=1e-11), (name, ch)
        assert abs(np.mean(x)) <= 1e-12 * math.sqrt(mean_square)
        exact = _band_integral(name, ch, lo, hi)
        bound = float(np.sum(d_omega ** 3 / 24 * _curvature_majorant(name, ch, omega_k - 0.5 * d_omega)))
        assert bound < 2e-4 * exact                        # the check is sharp (a 1e-3 error would not pass)
        assert abs(mean_square - exact) <= bound + 1e-12 * exact, (name, ch, mean_square / exact - 1, bound / exact)


# --------------------------------------------------------------------------------------------------- 4. Welch
WELCH_LENGTH_M = 12_000.0
WELCH_STEP_M = 0.25
WELCH_BAND_M = (3.0, 150.0)
NPERSEG = 2048
REALISATIONS = 16
SUB_BANDS = ((12, 24), (24, 48), (48, 96), (96, 168))       # Welch bins j (Ω = j 2π/512 rad/m)
NU = 2 * 45 * REALISATIONS / (1 + 2 * (1 / 6) ** 2)            # equivalent degrees of freedom (module docstring)

WELCH_CASES = [("german_low", "alignment"), ("german_low", "level"), ("german_low", "cross_level"),
               ("german_low", "gauge"), ("german_high", "level"), ("fra_class_4", "level"),
               ("fra_class_4", "cross_level"), ("fra_class_6", "alignment"), ("fra_class_1", "gauge"),
               ("fra_class_3", "alignment")]


@pytest.fixture(scope="module")
def welch_estimates():
    """Welch PSD per rad/m of each case's channel, averaged over 16 realisations (seeds 100...115)."""
    out = {}
    for name in sorted({n for n, _ in WELCH_CASES}):
        channels = tuple(ch for n, ch in WELCH_CASES if n == name)
        acc = {ch: 0.0 for ch in channels}
        for r in range(REALISATIONS):
            g = SpectralIrregularity(name, WELCH_LENGTH_M, seed=100 + r, band_m=WELCH_BAND_M, step_m=WELCH_STEP_M,
                                     channels=channels)
            for ch in channels:
                x = g.channels[ch]
                assert len(x) == round(WELCH_LENGTH_M / WELCH_STEP_M)
                n_cyc, p_cyc = welch(x, fs=1.0 / WELCH_STEP_M, window="hann", nperseg=NPERSEG,
                                     noverlap=NPERSEG // 2, detrend=False, scaling="density")
                acc[ch] = acc[ch] + p_cyc / REALISATIONS
        for ch in channels:
            # one-sided per cycles/m -> one-sided per rad/m: S(Ω) = S_n(Ω/2π)/(2π)
            out[name, ch] = (2 * math.pi * n_cyc, acc[ch] / (2 * math.pi))
    return out


@pytest.mark.parametrize("name, channel", WELCH_CASES)
def test_welch_psd_follows_the_published_formula(welch_estimates, name, channel):
    """Welch's estimate (16 realisations, per rad/m) against the published S in four sub-bands; the tolerance is
    derived in the module docstring (chi-square spread, window smoothing)."""
    omega, p_rad = welch_estimates[name, channel]
    delta = 2 * math.pi / (NPERSEG * WELCH_STEP_M)
    np.testing.assert_allclose(omega[:200], np.arange(200) * delta, rtol=1e-12)
    # the sub-bands keep >= 3.6 bins from the band's edges (bins 3.41 and 170.67), where the window's tail is < 1e-4
    assert (2 * math.pi / WELCH_BAND_M[1]) / delta <= SUB_BANDS[0][0] - 3.6
    assert (2 * math.pi / WELCH_BAND_M[0]) / delta >= SUB_BANDS[-1][1] - 1 + 3.6
    sigma_bin = math.sqrt(2.0 / NU)
    for j0, j1 in SUB_BANDS:
        j = np.arange(j0, j1)
        log_mean = float(np.mean(np.log(p_rad[j] / _published_psd(name, channel, omega[j]))))
        tol = 5 * sigma_bin * math.sqrt(1.944 / len(j)) + 1 / NU + 4 / j0 ** 2 + 14 / j0 ** 4 + 1e-4
        assert abs(log_mean) < tol, (name, channel, (j0, j1), log_mean, tol)
    # outside the band there is nothing: far above it only the window's leakage (Hann sidelobes ~ d^-6)
    far = omega > 2 * (2 * math.pi / WELCH_BAND_M[0])
    inside = (omega > 2 * math.pi / WELCH_BAND_M[1]) & (omega < 2 * math.pi / WELCH_BAND_M[0])
    assert np.all(p_rad[far] < 1e-6 * np.max(p_rad[inside]))


# --------------------------------------------------------------------------------------- reproducibility, inputs
def test_same_seed_same_track_other_seed_other_track():
    a = SpectralIrregularity("german_high", 600.0, seed=5)
    b = SpectralIrregularity("german_high", 600.0, seed=5)
    c = SpectralIrregularity("german_high", 600.0, seed=6)
    for ch in a.channels:
        assert np.array_equal(a.channels[ch], b.channels[ch])  # same seed, same code: bit-equality
        assert not np.allclose(a.channels[ch], c.channels[ch])
    # a subset of channels keeps each channel's phases; channels are independent (uncorrelated)
    only = SpectralIrregularity("german_high", 600.0, seed=5, channels=("cross_level",))
    assert list(only.channels) == ["cross_level"]
    # the same phases through the same code: bit-equality
    assert np.array_equal(only.channels["cross_level"], a.channels["cross_level"])
    big = SpectralIrregularity("fra_class_5", 12_000.0, seed=2)
    r = np.corrcoef(big.channels["level"], big.channels["alignment"])[0, 1]
    # ~12000/75 = 160 independent long waves: |r| of independent channels ~ 1/sqrt(160) = 0.08; 0.4 is > 5 sigma
    assert abs(r) < 0.4


def test_contact_evaluation_interpolates_the_samples():
    g = SpectralIrregularity("fra_class_6", 300.0, seed=3, start_m=-20.0)
    v = channel_values(g, g.s_m)
    for ch, name in (("alignment", "alignment_m"), ("level", "level_m"), ("cross_level", "cross_level_m"),
                     ("gauge", "gauge_m")):
        np.testing.assert_allclose(getattr(v, name), g.channels[ch], rtol=0, atol=1e-15)
    assert g.s_m[0] == -20.0 and g.length_m == pytest.approx(300.0)
    # between the samples: the cubic spline of the band's shortest wave (3 m, 12 samples) errs by
    # <= (5/384)(2π/12)^4 = 0.1 % of its amplitude; the signal's amplitude is at most Σ a_k.  The exact signal is
    # summed here from the published PSD and the documented phase draw (alignment first from default_rng(seed)).
    mid = 0.5 * (g.s_m[1:] + g.s_m[:-1])
    exact = np.zeros_like(mid)
    d_omega = 2 * math.pi / g.length_m
    rng = np.random.default_rng(3)
    phase = rng.uniform(0.0, 2 * math.pi, size=round(g.length_m / g.step_m) // 2 + 1)   # alignment: first
    k = np.round(g.omega_rad_m / d_omega).astype(int)
    amp = np.sqrt(2 * _published_psd("fra_class_6", "alignment", g.omega_rad_m) * d_omega)
    for a, w, ph in zip(amp, g.omega_rad_m, phase[k]):
        exact += a * np.cos(w * (mid - g.s_m[0]) + ph)
    # (away from the table's ends, where the spline's zero end slopes add an error of the order Δs·|slope|)
    inner = slice(20, -20)
    err = np.max(np.abs(channel_values(g, mid[inner]).alignment_m - exact[inner]))
    assert err < 5 / 384 * (2 * math.pi / 12) ** 4 * np.sum(amp)


def test_bad_inputs():
    with pytest.raises(ValueError, match="spectrum 'fra_class_7'"):
        SpectralIrregularity("fra_class_7", 500.0, seed=1)
    with pytest.raises(ValueError, match="wavelength band"):
        SpectralIrregularity("german_low", 500.0, seed=1, band_m=(150.0, 3.0))
    with pytest.raises(ValueError, match="step_m"):
        SpectralIrregularity("german_low", 500.0, seed=1, step_m=0.5)
    with pytest.raises(ValueError, match="length_m"):
        SpectralIrregularity("german_low", 100.0, seed=1)
    with pytest.raises(ValueError, match="seed"):
        SpectralIrregularity("german_low", 500.0, seed=-1)
    with pytest.raises(ValueError, match="seed"):
        SpectralIrregularity("german_low", 500.0, seed=1.5)
    with pytest.raises(ValueError, match="unknown channel 'twist'"):
        SpectralIrregularity("german_low", 500.0, seed=1, channels=("twist",))
    with pytest.raises(ValueError, match="unknown channel"):
        SPECTRA["german_low"].psd("twist", 1.0)
