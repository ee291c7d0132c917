"""The zero-phase Butterworth filters of exudyn_wheelrail.analysis.filters against independent references:

* the analogue Butterworth magnitude at the pre-warped frequency (closed form): low-pass
  |H|² = 1/(1 + (Ω/Ω_c)^(2n)), band-pass |H|² = 1/(1 + ((Ω² − Ω_0²)/(Ω B))^(2n)) — exact for the bilinear
  transform, so the design's response must meet it to what the rounding of its coefficients allows;
* SciPy's implementation of the same design and of the same forward–backward filter (``scipy.signal.butter``,
  ``sosfiltfilt``), an independent code: the designs' frequency responses and the filtered signals agree to what
  the coefficients' rounding allows.

That allowance is measured, not assumed (:func:`_rounding_allowance`): the largest change of the compared quantity
when every coefficient is perturbed by 4 units in the last place (a design rounds each coefficient once or a few
times; the poles of a narrow band lie within ~1e-3 of the unit circle, where the response is that sensitive); the
bound is 4 times it plus the closed form's own rounding (16 ulp of the values compared);
* properties of the filters: a level signal passes a low-pass unchanged (DC gain 1, the steady start) and is
  removed by a band-pass; the phase is zero (a symmetric pulse stays symmetric about its centre).
"""

import numpy as np
import pytest
from scipy import signal

from exudyn_wheelrail.analysis.filters import (butterworth_sections, edge_padding, sections_response, step_states,
                                               zero_phase)

EPS = np.finfo(float).eps
#: (kind, corners Hz, sampling Hz): the package's uses (EN 14363's 0.4-10 Hz band on car-body records, the 20 Hz force
#: low-pass at 1 ms and 0.5 ms), corners near the ends of the range (0.4 f_s; the band's lower corner at 1e-4 f_s)
#: and narrow bands (B/2 < Ω_0: an odd order's real prototype pole gives a complex pair, not two real poles)
CASES = [("bandpass", (0.4, 10.0), 1000.0), ("bandpass", (0.4, 10.0), 2000.0), ("bandpass", (0.5, 40.0), 100.0),
         ("bandpass", (2.0, 30.0), 200.0), ("bandpass", (4.0, 8.0), 100.0), ("bandpass", (0.4, 1.0), 1000.0),
         ("lowpass", 20.0, 1000.0), ("lowpass", 20.0, 2000.0), ("lowpass", 40.0, 100.0)]
ORDERS = (1, 2, 3, 4, 5, 7)


def _warp(f, fs):
    return 2.0 * fs * np.tan(np.pi * np.asarray(f) / fs)


def _ids(case):
    return f"{case[0]}-{case[1]}-{case[2]:g}Hz"


def _rounding_allowance(quantity, sos, seed=0):
    """The largest change of ``quantity(sos)`` when every coefficient of ``sos`` (a0 = 1 aside) is perturbed by
    ±4 units in the last place (3 random sign patterns)."""
    rng = np.random.default_rng(seed)
    base = quantity(sos)
    worst = 0.0
    for _ in range(3):
        u = rng.choice([-1.0, 1.0], size=sos.shape)
        u[:, 3] = 0.0
        worst = max(worst, float(np.max(np.abs(quantity(sos * (1.0 + 4 * EPS * u)) - base))))
    return worst


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("case", CASES, ids=_ids)
def test_magnitude_is_the_analogue_butterworth_at_the_warped_frequency(case, order):
    kind, corners, fs = case
    sos = butterworth_sections(order, corners, fs, kind)
    f = np.linspace(0.01, 0.49, 300) * fs
    g = np.abs(sections_response(sos, 2 * np.pi * f / fs)) ** 2
    w = _warp(f, fs)
    if kind == "lowpass":
        x = w / _warp(corners, fs)
    else:
        w1, w2 = _warp(corners[0], fs), _warp(corners[1], fs)
        x = (w * w - w1 * w2) / (w * (w2 - w1))
    expected = 1.0 / (1.0 + x ** (2 * order))
    allowance = _rounding_allowance(lambda c: np.abs(sections_response(c, 2 * np.pi * f / fs)) ** 2, sos)
    assert np.max(np.abs(g - expected)) <= 4.0 * allowance + 16 * EPS


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("case", CASES, ids=_ids)
def test_design_and_filter_agree_with_scipy_within_the_coefficients_rounding(case, order):
    kind, corners, fs = case
    sos = butterworth_sections(order, corners, fs, kind)
    ref = signal.butter(order, corners, btype=kind, fs=fs, output="sos")
    assert sos.shape == ref.shape
    w = np.linspace(1e-3, np.pi - 1e-3, 400)
    h, (_, h_ref) = sections_response(sos, w), signal.sosfreqz(ref, worN=w)
    allowance = _rounding_allowance(lambda c: sections_response(c, w), sos)
    assert np.max(np.abs(h - h_ref)) <= 4.0 * allowance + 16 * EPS * np.max(np.abs(h_ref))
    x = 3.0 + np.random.default_rng(order).standard_normal(3000)
    allowance = _rounding_allowance(lambda c: zero_phase(c, x), sos)
    assert np.max(np.abs(zero_phase(sos, x) - signal.sosfiltfilt(ref, x))) <= 4.0 * allowance + 16 * EPS * 3.0


@pytest.mark.parametrize("case", CASES, ids=_ids)
def test_a_level_signal_passes_the_low_pass_and_not_the_band_pass(case):
    kind, corners, fs = case
    sos = butterworth_sections(4, corners, fs, kind)
    level = np.full(500, 2.5)
    y = zero_phase(sos, level)
    expected = 2.5 if kind == "lowpass" else 0.0
    # started in its steady state: no transient, only the rounding of the coefficients (the DC gain is a product of
    # the sections' quotients) and of the recursion
    allowance = _rounding_allowance(lambda c: zero_phase(c, level), sos)
    assert np.max(np.abs(y - expected)) <= 4.0 * allowance + 64 * EPS * 2.5


def test_zero_phase_keeps_a_symmetric_pulse_symmetric():
    """A pulse in the middle of a 20 s record: the run both ways keeps its peak in place and the response symmetric
    (a causal single pass would delay it by the group delay, several ms); the ends, where the padding and the start
    states act, are left out: what is left of their transient after a quarter of the record decays as the slowest
    pole, r_max^(n/4) (the band-pass's r_max ≈ 0.9975 at its 0.4 Hz corner: ~4e-6)."""
    fs = 1000.0
    n = 20001
    t = (np.arange(n) - n // 2) / fs
    x = np.exp(-(t / 0.05) ** 2)
    middle = slice(n // 4, n - n // 4)
    for sos in (butterworth_sections(4, 20.0, fs, "lowpass"), butterworth_sections(4, (0.4, 10.0), fs, "bandpass")):
        y = zero_phase(sos, x)
        assert int(np.argmax(np.abs(y))) == n // 2
        r_max = max(np.max(np.abs(np.roots(row[3:]))) for row in sos)
        assert np.max(np.abs(y - y[::-1])[middle]) <= max(10.0 * r_max ** (n // 4), 1e-12) * np.max(np.abs(y))


def test_the_edge_padding_is_three_times_the_cascade():
    assert edge_padding(butterworth_sections(4, 20.0, 1000.0, "lowpass")) == 3 * (2 * 2 + 1)
    assert edge_padding(butterworth_sections(3, 20.0, 1000.0, "lowpass")) == 3 * (2 * 2 + 1 - 1)  # a 1st-order one
    assert edge_padding(butterworth_sections(4, (0.4, 10.0), 1000.0, "bandpass")) == 3 * (2 * 4 + 1)


def test_step_states_are_the_steady_state_of_a_unit_step():
    sos = butterworth_sections(3, 20.0, 1000.0, "lowpass")
    zi = step_states(sos)
    # run the cascade by hand over a long unit step from rest: its final states are the steady ones
    s = np.zeros((len(sos), 2))
    for _ in range(20000):
        v = 1.0
        for k, (b0, b1, b2, _, a1, a2) in enumerate(sos):
            y = b0 * v + s[k, 0]
            s[k] = (b1 * v - a1 * y + s[k, 1], b2 * v - a2 * y)
            v = y
    assert np.allclose(s, zi, rtol=0.0, atol=1e-12)


@pytest.mark.parametrize("order", [0, -1, 2.5])
def test_an_order_below_one_or_not_whole_is_refused(order):
    with pytest.raises(ValueError, match="order"):
        butterworth_sections(order, 20.0, 1000.0, "lowpass")
