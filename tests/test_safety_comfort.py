"""Running-safety and comfort criteria (analysis/safety.py, analysis/comfort.py) against closed-form answers on
synthetic signals: Nadal's formula (via the friction-angle identity), sliding means of rectangular pulses, exceedance
durations of half-sine pulses, ΔQ/Q and lift times of a sinusoidal load, Prud'homme's limit, Butterworth gains,
Sperling's single-sine value, and the error handling."""

import json
import math

import numpy as np
import pytest

from exudyn_wheelrail.analysis import comfort as C
from exudyn_wheelrail.analysis import safety as S
from exudyn_wheelrail.scenarios.rtri import TIMESERIES_REQUIRED


# ------------------------------------------------------------------------------------------------ Nadal
@pytest.mark.parametrize("gamma_deg, mu, hand", [(70.0, 0.36, 1.2003), (60.0, 0.36, 0.8451), (70.0, 0.0, 2.7475)])
def test_nadal_known_values(gamma_deg, mu, hand):
    g = math.radians(gamma_deg)
    got = S.nadal_limit(g, mu)
    # independent form: Nadal = tan(gamma - friction angle), friction angle = atan(mu)
    assert got == pytest.approx(math.tan(g - math.atan(mu)), rel=1e-12)
    assert got == pytest.approx(hand, abs=1e-4)          # hand-computed with a pocket calculator


@pytest.mark.parametrize("gamma, mu", [(0.0, 0.3), (math.pi / 2, 0.3), (1.2, -0.1), (float("nan"), 0.3)])
def test_nadal_bad_input(gamma, mu):
    with pytest.raises(ValueError):
        S.nadal_limit(gamma, mu)


# ------------------------------------------------------------------------------------------------ sliding mean
@pytest.mark.parametrize("speed, dt", [(20.0, 0.005), (40.0, 0.001)])
@pytest.mark.parametrize("pulse_m", [0.4, 1.0, 2.0, 3.2])
def test_en14363_sliding_mean_of_rectangular_pulse(speed, dt, pulse_m):
    """A Y/Q pulse of length L_p (track) and height A: max of the 2 m mean = min(1, L_p / 2 m) A."""
    A, Q0 = 0.9, 50e3
    n = int(round(20.0 / (speed * dt)))                  # 20 m of track
    n_p = int(round(pulse_m / (speed * dt)))
    Y = np.zeros(n)
    Y[n // 3:n // 3 + n_p] = A * Q0
    Q = np.full(n, Q0)
    r = S.derailment_quotient_en14363(Y, Q, dt, speed, lowpass_hz=None)
    assert r["value"] == pytest.approx(min(1.0, pulse_m / 2.0) * A, rel=1e-12)
    assert r["window_m"] == pytest.approx(2.0, rel=1e-12)
    assert r["limit"] == 0.8
    assert r["passed"] == (min(1.0, pulse_m / 2.0) * A <= 0.8)
    assert r["margin"] == pytest.approx(0.8 - r["value"])


def test_en14363_force_lowpass_is_the_standards_20_hz():
    """EN 14363 low-passes the wheel forces at 20 Hz before the 2 m mean: the default assessment equals the one of
    forces pre-filtered here with scipy's zero-phase Butterworth at 20 Hz (order 4 per pass, the package's filter
    convention) and no further filter.  A short (5 ms) pulse carries content at and above 20 Hz, so a corner off by
    2 % changes the result by about 1 % (measured 1.3 %), far above the round-off of the same computation (1e-12)."""
    from scipy import signal
    speed, dt, Q0 = 80.0, 5e-4, 50e3
    n = 4000
    Y = np.zeros(n)
    Y[n // 2:n // 2 + 10] = 0.9 * Q0
    Q = np.full(n, Q0)
    sos = signal.butter(4, 20.0, btype="lowpass", fs=1.0 / dt, output="sos")
    expected = S.derailment_quotient_en14363(signal.sosfiltfilt(sos, Y), signal.sosfiltfilt(sos, Q), dt, speed,
                                             lowpass_hz=None)["value"]
    off = S.derailment_quotient_en14363(Y, Q, dt, speed, lowpass_hz=20.4)["value"]
    assert abs(off / expected - 1.0) > 1e-4            # the test can tell a 2 % corner shift
    assert S.derailment_quotient_en14363(Y, Q, dt, speed)["value"] == pytest.approx(expected, rel=1e-12)


def test_en14363_long_pulse_with_20hz_filter_keeps_plateau():
    speed, dt = 50.0, 0.001
    t = np.arange(4000) * dt                              # 200 m
    # 0.1 -> 0.6 -> 0.1 with raised-cosine ramps of 0.3 s (content far below 20 Hz, so no filter overshoot):
    # a plateau of 0.6 over 40 m, which the 20 Hz low-pass keeps
    ramp = lambda x: np.clip(0.5 - 0.5 * np.cos(np.pi * np.clip(x, 0.0, 1.0)), 0.0, 1.0)  # noqa: E731
    yq = 0.1 + 0.5 * ramp((t - 0.7) / 0.3) * ramp((2.3 - t) / 0.3)
    r = S.derailment_quotient_en14363(yq * 40e3, np.full(t.size, 40e3), dt, speed)
    assert r["value"] == pytest.approx(0.6, rel=1e-3)     # 4e-5: overshoot of the 8th-order response at the kinks
    assert r["passed"]


def test_sliding_mean_ignores_lifted_samples():
    x = np.array([1.0, np.nan, 3.0, 5.0])
    yq = S.derailment_quotient([1.0, 2.0], [2.0, 0.0])          # lifted wheel: Y/Q undefined
    assert yq[0] == 0.5 and np.isnan(yq[1])  # 1/2: exact
    np.testing.assert_allclose(C.sliding_mean(x, 2, ignore_nan=True), [1.0, 3.0, 4.0])
    with pytest.raises(ValueError, match="NaN"):
        C.sliding_mean(x, 2)


# ------------------------------------------------------------------------------------------------ JNR duration
def _half_sine(h, T, dt, pad=0.05):
    t = np.arange(int(round((T + 2 * pad) / dt)) + 1) * dt
    tau = t - pad
    return np.where((tau > 0) & (tau < T), h * np.sin(np.pi * tau / np.where(T > 0, T, 1)), 0.0)


@pytest.mark.parametrize("h, T, passes", [(1.2, 0.06, True), (1.2, 0.10, False), (2.0, 0.03, False),
                                          (0.95, 0.5, False)])
def test_jnr_duration_of_half_sine_pulse(h, T, passes):
    dt = 1e-4
    yq = _half_sine(h, T, dt)
    r = S.derailment_quotient_jnr(yq, dt)
    (e,) = r["excursions"]
    # time above 0.8 of h sin(pi t / T): T (1 - 2 asin(0.8/h) / pi)
    d = T * (1.0 - 2.0 * math.asin(0.8 / h) / math.pi)
    assert e["duration_s"] == pytest.approx(d, abs=2e-6)
    assert e["peak"] == pytest.approx(h, rel=1e-6)
    lim = 0.8 if d >= 0.05 else 0.04 / d
    assert e["limit"] == pytest.approx(lim, rel=1e-4)
    assert r["passed"] is passes
    assert r["value"] == pytest.approx(h / lim, rel=1e-4)


def test_jnr_limit_function():
    assert S.jnr_limit(0.05) == pytest.approx(0.8)
    assert S.jnr_limit(0.2) == pytest.approx(0.8)
    assert S.jnr_limit(0.02) == pytest.approx(2.0)         # 0.04 s / 0.02 s
    assert S.jnr_limit(0.0499999) == pytest.approx(0.8, rel=1e-5)   # continuous at 0.05 s
    with pytest.raises(ValueError):
        S.jnr_limit(-0.01)


def test_jnr_no_excursion_passes():
    r = S.derailment_quotient_jnr(np.full(100, 0.4), 1e-3)
    assert r["passed"] and r["excursions"] == [] and r["value"] == pytest.approx(0.5)


# ------------------------------------------------------------------------------------------------ ΔQ/Q and lift
@pytest.mark.parametrize("amp, passes", [(0.5, True), (0.7, False)])
def test_wheel_unloading_sinusoidal_load(amp, passes):
    Q0, f, dt = 60e3, 2.0, 1e-3                           # the trough t = 3/(4 f) = 0.375 s lies on the grid
    t = np.arange(2000) * dt
    Q = Q0 * (1.0 + amp * np.sin(2 * np.pi * f * t))
    r = S.wheel_unloading(Q, Q0)
    assert r["value"] == pytest.approx(amp, rel=1e-12)
    assert r["limit"] == 0.6 and r["passed"] is passes
    np.testing.assert_allclose(r["series"], -amp * np.sin(2 * np.pi * f * t), atol=1e-12)
    assert S.wheel_lift(Q, dt)["passed"]


def test_wheel_lift_time_of_sinusoidal_load():
    Q0, amp, f, dt, periods = 60e3, 1.5, 4.0, 1e-4, 8
    t = np.arange(int(round(periods / f / dt))) * dt
    Q = Q0 * (1.0 + amp * np.sin(2 * np.pi * f * t + 0.3))
    r = S.wheel_lift(Q, dt)
    # Q <= 0 where sin <= -1/amp: a fraction (pi - 2 asin(1/amp)) / (2 pi) of every period
    frac = (math.pi - 2.0 * math.asin(1.0 / amp)) / (2.0 * math.pi)
    assert len(r["intervals"]) == periods
    assert r["total_duration_s"] == pytest.approx(periods / f * frac, abs=1e-6)
    assert not r["passed"] and r["lifted_samples"] > 0


# ------------------------------------------------------------------------------------------------ Prud'homme
@pytest.mark.parametrize("alpha", [1.0, 0.85])
def test_prudhomme_constant_sum_y(alpha):
    Q0_wheel, sumY, dt, V = 60e3, -30e3, 1e-3, 40.0
    P_kN = 2 * Q0_wheel / 1e3                             # axle load 120 kN
    lim = alpha * (10.0 + P_kN / 3.0) * 1e3               # Prud'homme: alpha (10 + P/3) kN
    assert S.prudhomme_limit_N(Q0_wheel, alpha) == pytest.approx(lim, rel=1e-12)
    assert S.prudhomme_limit_N(static_axle_load_N=2 * Q0_wheel, alpha=alpha) == pytest.approx(lim, rel=1e-12)
    r = S.track_shift_force_en14363(np.full(1000, sumY), dt, V, Q0_wheel, alpha)
    assert r["value"] == pytest.approx(30e3, rel=1e-9)
    assert r["signed_value_N"] == pytest.approx(sumY, rel=1e-9)
    assert r["limit"] == pytest.approx(lim)
    assert r["utilisation"] == pytest.approx(30.0 / (lim / 1e3))
    assert r["passed"]


def test_prudhomme_needs_one_load():
    with pytest.raises(ValueError):
        S.prudhomme_limit_N()
    with pytest.raises(ValueError):
        S.prudhomme_limit_N(50e3, static_axle_load_N=100e3)


# ------------------------------------------------------------------------------------------------ filters
def _steady_amplitude(y, t, f, keep):
    """Amplitude of the f-component of y over the central `keep` part (least squares on sin/cos)."""
    n = y.size
    i0, i1 = int(n * (1 - keep) / 2), int(n * (1 + keep) / 2)
    M = np.column_stack([np.sin(2 * np.pi * f * t[i0:i1]), np.cos(2 * np.pi * f * t[i0:i1])])
    c = np.linalg.lstsq(M, y[i0:i1], rcond=None)[0]
    return math.hypot(*c)


def _warp(f, fs):
    return 2 * fs * math.tan(math.pi * f / fs)


@pytest.mark.parametrize("f, expect_one", [(5.0, True), (40.0, False), (60.0, False)])
def test_lowpass_gain(f, expect_one):
    fs, fc, n = 1000.0, 20.0, 4
    t = np.arange(int(20 * fs)) / fs
    y = C.lowpass(np.sin(2 * np.pi * f * t), 1 / fs, fc, order=n)
    g = _steady_amplitude(y, t, f, 0.5)
    # forward-backward: the square of the Butterworth magnitude at the prewarped frequency
    expected = 1.0 / (1.0 + (_warp(f, fs) / _warp(fc, fs)) ** (2 * n))
    if expect_one:
        assert g == pytest.approx(1.0, abs=0.01)
    assert g == pytest.approx(expected, rel=0.01)


@pytest.mark.parametrize("f, expect_one", [(2.0, True), (5.0, True), (0.2, False), (25.0, False)])
def test_bandpass_gain(f, expect_one):
    fs, (f1, f2), n = 200.0, C.EN14363_CARBODY_BAND_HZ, 4
    t = np.arange(int(200 * fs)) / fs
    y = C.bandpass(np.sin(2 * np.pi * f * t), 1 / fs, f1, f2, order=n)
    g = _steady_amplitude(y, t, f, 0.5)
    w, w1, w2 = _warp(f, fs), _warp(f1, fs), _warp(f2, fs)
    x = (w * w - w1 * w2) / (w * (w2 - w1))                # analogue band-pass: (Ω² − Ω0²)/(Ω B)
    expected = 1.0 / (1.0 + x ** (2 * n))
    if expect_one:
        assert g == pytest.approx(1.0, abs=0.01)
    assert g == pytest.approx(expected, rel=0.01)


def test_carbody_acceleration_peak_and_rms_of_inband_sine():
    fs, A, f = 200.0, 0.8, 2.0
    t = np.arange(int(60 * fs)) / fs
    # a sine faded in and out over 10 s (raised cosine) on a constant (quasi-static) offset, which the 0.4 Hz
    # high-pass removes; the fades keep the filter's edge transients away
    env = np.clip(np.minimum(t, t[-1] - t) / 10.0, 0.0, 1.0)
    env = 0.5 - 0.5 * np.cos(np.pi * env)
    r = C.carbody_acceleration_en14363(A * env * np.sin(2 * np.pi * f * t) + 0.3, 1 / fs, speed_m_s=50.0,
                                       rms_window_m=100.0, limits_m_s2={"peak": 1.0, "rms": 0.5})
    assert r["peak_m_s2"] == pytest.approx(A, rel=0.01)
    assert not r["peak_near_record_edge"]
    assert r["sliding_rms_max_m_s2"] == pytest.approx(A / math.sqrt(2), rel=0.02)
    assert r["sliding_window_m"] == pytest.approx(100.0)
    assert r["assessment"]["peak"]["passed"] and not r["assessment"]["rms"]["passed"]


# ------------------------------------------------------------------------------------------------ Sperling
def _wz_single(A_m_s2, f, direction):
    """Sperling for one sine of peak amplitude A: 0.896 (a^3 F(f) / f)^(1/10), a in cm/s^2; F written out here."""
    a = 100.0 * A_m_s2
    if direction == "vertical":
        F = 0.325 * f ** 2 if f < 5.9 else (400.0 / f ** 2 if f < 20.0 else 1.0)
    else:
        F = 0.8 * f ** 2 if f < 5.4 else (650.0 / f ** 2 if f < 26.0 else 1.0)
    return 0.896 * (a ** 3 * F / f) ** 0.1


@pytest.mark.parametrize("direction, f", [("lateral", 1.5), ("lateral", 8.0), ("vertical", 3.0),
                                          ("vertical", 12.0), ("vertical", 25.0)])
@pytest.mark.parametrize("dt, T", [(0.001, 10.0), (0.004, 10.0), (0.002, 24.0)])
def test_sperling_pure_sine_independent_of_sampling(direction, f, dt, T):
    A = 0.3                                                # peak amplitude [m/s^2]; integer periods in T
    t = np.arange(int(round(T / dt))) * dt
    r = C.sperling_index(A * np.sin(2 * np.pi * f * t + 0.7), dt, direction)
    assert r["Wz"] == pytest.approx(_wz_single(A, f, direction), rel=1e-9)
    rb = C.sperling_index(A * np.sin(2 * np.pi * f * t + 0.7), dt, direction, bands=C.third_octave_band_edges())
    assert rb["Wz"] == pytest.approx(_wz_single(A, f, direction), rel=1e-9)
    # Sperling's displacement form 2.7 (z^3 f^5 F)^(1/10), z = a / (2 pi f)^2 [cm]: agrees to the rounding of 0.896
    z_cm = 100.0 * A / (2 * math.pi * f) ** 2
    F = (_wz_single(A, f, direction) / 0.896) ** 10 * f / (100.0 * A) ** 3
    assert r["Wz"] == pytest.approx(2.7 * (z_cm ** 3 * f ** 5 * F) ** 0.1, rel=1e-3)


def test_sperling_two_sines_sum_of_tenth_powers():
    dt, T = 0.002, 20.0
    t = np.arange(int(round(T / dt))) * dt
    a = 0.2 * np.sin(2 * np.pi * 1.0 * t) + 0.5 * np.cos(2 * np.pi * 7.0 * t)
    w1, w2 = _wz_single(0.2, 1.0, "vertical"), _wz_single(0.5, 7.0, "vertical")
    assert C.sperling_index(a, dt, "vertical")["Wz"] == pytest.approx((w1 ** 10 + w2 ** 10) ** 0.1, rel=1e-9)


def test_sperling_bands_reduce_leakage():
    dt, A, f = 0.005, 0.5, 2.25
    t = np.arange(int(round(20.3 / dt))) * dt              # 45.7 periods: the sine lies between FFT lines
    a = A * np.sin(2 * np.pi * f * t)
    ref = _wz_single(A, f, "lateral")
    assert C.sperling_index(a, dt, "lateral", bands=C.third_octave_band_edges())["Wz"] == pytest.approx(ref, rel=0.01)


def test_sperling_weighting_branches_nearly_continuous():
    # the published branch constants make F almost continuous at the breaks (independent plausibility check)
    for d, fb in (("vertical", 5.9), ("lateral", 5.4)):
        lo, hi = C.sperling_weighting([fb - 1e-9, fb], d)
        assert hi == pytest.approx(lo, rel=0.05)
    assert C.sperling_weighting([20.0], "vertical")[0] == pytest.approx(1.0)
    with pytest.raises(ValueError):
        C.sperling_weighting([0.3], "vertical")
    assert C.sperling_ride_quality(2.4) == "satisfactory"


# ------------------------------------------------------------------------------------------------ summary
def _table(speed=50.0, dt=1e-3, T=4.0):
    """A table with the columns of rtri.py: two wheelsets, static loads 55 kN, a flange force pulse on w1 right."""
    t = np.arange(int(round(T / dt)) + 1) * dt
    ts = {name: np.zeros(t.size) for name in TIMESERIES_REQUIRED}
    ts["time_s"] = t
    pulse = (t >= 1.0) & (t < 1.0 + 1.0 / speed)           # 1 m of track
    for j in (1, 2):
        for side in ("right", "left"):
            ts[f"Y_w{j}_{side}_N"] = np.zeros(t.size)
            ts[f"Q_w{j}_{side}_N"] = np.full(t.size, 55e3)
    ts["Y_w1_right_N"] = np.where(pulse, -33e3, 0.0)       # rail pushes the right wheel left: Y = +33 kN
    ts["lateral_contact_force_w1_right_N"] = ts["Y_w1_right_N"].copy()
    ts["vertical_contact_force_w1_right_N"] = ts["Q_w1_right_N"].copy()
    ts["carbody_lateral_accelerometer_rear_m_s2"] = 0.4 * np.sin(2 * np.pi * 1.25 * t)
    return ts


def test_summary_of_rtri_like_table():
    speed, dt = 50.0, 1e-3
    ts = _table(speed, dt)
    ts = {k: v[:-1] for k, v in ts.items()}                # 4 s = 5 periods of 1.25 Hz
    s = S.running_criteria_summary(ts, speed, lowpass_hz=None, flange_angle_rad=math.radians(70.0),
                                   friction_coefficient=0.36)
    json.dumps(s)                                          # serialisable
    en = s["criteria"]["derailment_quotient_en14363"]["w1_right"]
    assert en["value"] == pytest.approx(0.6 * 0.5, rel=1e-9)        # Y/Q 0.6 over 1 m: half the 2 m mean
    assert s["inputs"]["wheels"] == ["w1_right", "w1_left", "w2_right", "w2_left"]
    assert s["inputs"]["static_wheel_loads_N"]["w1_right"] == 55e3
    nad = s["criteria"]["derailment_quotient_nadal"]["w1_right"]
    assert nad["limit"] == pytest.approx(math.tan(math.radians(70.0) - math.atan(0.36)))
    ws1 = s["criteria"]["track_shift_force_prudhomme"]["ws1"]
    assert ws1["value"] == pytest.approx(33e3 * 0.5, rel=1e-9)
    assert ws1["limit"] == pytest.approx((10.0 + 110.0 / 3.0) * 1e3)
    jnr = s["criteria"]["derailment_quotient_jnr"]["w1_right"]
    assert jnr["passed"] and jnr["excursions"] == []
    sp = s["criteria"]["sperling_lateral"]
    assert sp["Wz"] == pytest.approx(_wz_single(0.4, 1.25, "lateral"), rel=1e-9)
    assert sp["column"] == "carbody_lateral_accelerometer_rear_m_s2" and sp["passed"] is None
    assert s["safety_passed"] is True and s["passed"] is True


def test_summary_flags_lift_and_excessive_yq():
    speed, dt = 50.0, 1e-3
    ts = _table(speed, dt)
    ts["Q_w2_left_N"][2000:2010] = 0.0
    ts["Y_w1_right_N"] = np.where((ts["time_s"] >= 1.0) & (ts["time_s"] < 1.2), -55e3, 0.0)   # Y/Q = 1 over 10 m
    s = S.running_criteria_summary(ts, speed, vehicle="freight")
    assert s["inputs"]["prudhomme_alpha"] == 0.85
    assert not s["criteria"]["wheel_lift"]["w2_left"]["passed"]
    assert s["criteria"]["wheel_lift"]["w2_left"]["lifted_samples"] == 10
    assert not s["criteria"]["derailment_quotient_en14363"]["w1_right"]["passed"]
    assert not s["criteria"]["derailment_quotient_jnr"]["w1_right"]["passed"]   # 0.2 s above 0.8
    assert s["verdicts"]["wheel_lift"]["passed"] is False
    assert s["safety_passed"] is False
    assert any("lifted" in n for n in s["notes"])


def test_summary_ignores_nan_in_unused_columns_only():
    ts = _table()
    ts["derailment_quotient_w1_right"] = np.full(ts["time_s"].size, np.nan)    # rtri.py: NaN when lifted
    assert S.running_criteria_summary(ts, 50.0)["safety_passed"] is True
    ts["Q_w2_right_N"] = ts["Q_w2_right_N"].copy()
    ts["Q_w2_right_N"][5] = np.nan
    with pytest.raises(ValueError, match="Q_w2_right_N"):
        S.running_criteria_summary(ts, 50.0)


def test_summary_falls_back_to_contract_columns():
    ts = {k: v for k, v in _table().items() if not k.startswith(("Y_w", "Q_w"))}
    s = S.running_criteria_summary(ts, 50.0)
    assert list(s["criteria"]["derailment_quotient_en14363"]) == ["w1_right"]
    assert s["criteria"]["track_shift_force_prudhomme"] == {}


# ------------------------------------------------------------------------------------------------ errors
def test_errors():
    good = np.ones(100)
    bad = good.copy()
    bad[7] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        S.derailment_quotient_en14363(bad, good * 5e4, 1e-3, 30.0, lowpass_hz=None)
    with pytest.raises(ValueError, match="different lengths"):
        S.derailment_quotient_en14363(good, np.ones(99), 1e-3, 30.0, lowpass_hz=None)
    with pytest.raises(ValueError, match="speed_m_s"):
        S.derailment_quotient_en14363(good, good, 1e-3, 0.0, lowpass_hz=None)
    with pytest.raises(ValueError, match="shorter than the window"):
        S.derailment_quotient_en14363(good, good, 1e-3, 1.0, lowpass_hz=None)      # 2 m = 2000 samples
    with pytest.raises(ValueError, match="Nyquist"):
        C.lowpass(np.ones(1000), 0.03, 20.0)
    with pytest.raises(ValueError, match="too few"):
        C.bandpass(np.ones(20), 0.001, 0.4, 10.0)
    with pytest.raises(ValueError, match="direction"):
        C.sperling_index(np.ones(1000), 0.01, "longitudinal")
    with pytest.raises(ValueError, match="1-D"):
        C.sperling_index(np.ones((10, 10)), 0.01, "vertical")
    with pytest.raises(ValueError, match="static_wheel_load_N"):
        S.wheel_unloading(good, -1.0)
    with pytest.raises(ValueError, match="non-uniform"):
        C.time_step_from_time([0.0, 0.001, 0.002, 0.0035])
    with pytest.raises(ValueError, match="increasing"):
        C.time_step_from_time([0.0, 0.001, 0.001])
    ts = _table()
    ts["time_s"] = ts["time_s"].copy()
    ts["time_s"][100] += 3e-4
    with pytest.raises(ValueError, match="non-uniform"):
        S.running_criteria_summary(ts, 50.0)
    ts = _table()
    ts["Q_w1_left_N"] = ts["Q_w1_left_N"][:-1]
    with pytest.raises(ValueError, match="different lengths"):
        S.running_criteria_summary(ts, 50.0)
    with pytest.raises(ValueError, match="no wheel force columns"):
        S.running_criteria_summary({"time_s": np.arange(10) * 0.1}, 50.0)
    with pytest.raises(ValueError, match="vehicle"):
        S.running_criteria_summary(_table(), 50.0, vehicle="tram")
