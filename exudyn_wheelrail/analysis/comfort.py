r"""Ride comfort of a recorded run: car-body accelerations filtered as EN 14363 evaluates them, peak and RMS values,
and Sperling's ride index Wz — plus the signal helpers that :mod:`exudyn_wheelrail.analysis.safety` shares
(input checks, zero-phase Butterworth filters, sliding means over a distance window).

Time series in, numbers out: plain numpy, SI units (accelerations in m/s², times in s, distances in m,
speeds in m/s, frequencies in Hz).  Every signal is sampled at one uniform time step ``dt_s``; the running speed
``speed_m_s`` (constant) converts distance windows to time windows.  Bad input raises ``ValueError`` with the
name of the offending argument: NaN/inf in a signal, signals of different lengths, a non-uniform time axis
(:func:`time_step_from_time`), a non-positive step or speed, a filter corner at or above the Nyquist frequency,
a record shorter than a window or than the filter's edge padding.

Filters (:func:`lowpass`, :func:`bandpass`)
-------------------------------------------
Digital Butterworth filters (:mod:`.filters`: second-order sections; the corner frequencies are pre-warped, so the
digital filter has the analogue Butterworth magnitude at the warped frequency Ω = 2 f_s tan(π f / f_s)), run
**forward and backward** (:func:`~.filters.zero_phase`): zero phase — a peak stays where it is — and the amplitude
gain is the *square* of the single-pass Butterworth magnitude,

* low-pass of order n, corner f_c:   G(f) = 1 / (1 + (Ω/Ω_c)^(2n)),
* band-pass of order n (a filter of order 2n),
  Ω_0² = Ω_1 Ω_2, B = Ω_2 − Ω_1:   G(f) = 1 / (1 + ((Ω² − Ω_0²) / (Ω B))^(2n)),

so G = 1/2 (−6 dB) at the corners and the roll-off is that of order 2n.  ``tests/test_safety_comfort.py`` checks
both formulas on steady sines.  The default order n = 4 is an **assumption**: the filter *types and corner
frequencies* below are those tabulated for EN 14363 / UIC 518 evaluations, but the standard's text on the filter
order and phase was not available to us.  Edge transients: the filter pads the record by an odd extension of
a few samples (:func:`~.filters.edge_padding`); the first and last ~1/f_low seconds of a band-passed record carry the high-pass transient.

EN 14363 quantities (:func:`carbody_acceleration_en14363`)
-----------------------------------------------------------
EN 14363 (UIC 518) evaluates the car-body accelerations ÿ*, z̈* (lateral, vertical, on the floor above the bogie
centres) **band-pass filtered 0.4–10 Hz**: their maxima ÿ*_max, z̈*_max and their RMS values s̈ÿ*, s̈z̈* (the table
of assessment quantities of UIC 518 / EN 14363 as summarised, e.g., in the GENSYS course notes "Acceptance test
according to UIC 518 and CEN/TC 256 WG 10 publication EN 14363"); the force quantities (Y, Q, ΣY) are low-pass
filtered at 20 Hz (:mod:`.safety`).  Here: the maximum of |a| of the band-passed signal, its RMS over the whole
record, and optionally a *sliding* RMS over a distance window (EN 14363 uses a sliding RMS over 100 m for the
instability criterion; for the ride RMS it evaluates track sections — one record here is one section).  The
standard's statistical step (percentiles over many sections) does not apply to one simulated run: the maximum is
reported.  No limit values are built in (give them to :func:`~.safety.running_criteria_summary`): the limits of
EN 14363 for these quantities could not be checked against the standard's text.

Sperling's ride index (:func:`sperling_index`)
-----------------------------------------------
For a sinusoidal acceleration of **peak amplitude** a [cm/s²] and frequency f [Hz] (Sperling & Betzhold 1956;
as commonly cited, e.g. Garg & Dukkipati, *Dynamics of Railway Vehicle Systems*, 1984):

    Wz = 0.896 (a³ F(f) / f)^(1/10)

with the weighting F(f) (:func:`sperling_weighting`)

* vertical: 0.325 f² (0.5 ≤ f < 5.9 Hz), 400/f² (5.9 ≤ f < 20 Hz), 1 (f ≥ 20 Hz);
* lateral:  0.8 f² (0.5 ≤ f < 5.4 Hz), 650/f² (5.4 ≤ f < 26 Hz), 1 (f ≥ 26 Hz);

(0.896 = 2.7 (2π)^(−3/5): the same index written with the displacement amplitude z [cm], Wz = 2.7 (z³ f⁵ F)^(1/10)).
A signal with several components is summed over the frequency bands i: Wz = (Σ Wz_i^10)^(1/10), i.e.
Wz = 0.896 (Σ a_i³ F(f_i)/f_i)^(1/10).  Convention here: the FFT of the whole record (``numpy.fft.rfft``, no
window, mean removed); a_i is the **peak amplitude** of line i of the one-sided amplitude spectrum
(2|X_k|/N; |X_k|/N at the Nyquist line) — the peak of the sinusoid, √2 times its RMS — converted from m/s² to
cm/s²; the lines from ``f_min_hz`` = 0.5 Hz (where F is defined from) to ``f_max_hz`` = 30 Hz (the usual range of
the index; limited to the Nyquist frequency) are the bands.  A sine with an integer number of periods in the
record falls on one line and gives Sperling's single-frequency value exactly, for any time step and any record
length.  **Caveat** (the known weakness of the cubic, per-line sum): for a sine between lines (leakage) or a
broad-band signal, the result depends on the record length (a longer record has more, smaller lines and
Σ a_i³ shrinks).  ``bands=`` (a list of band edges in Hz, e.g. :func:`third_octave_band_edges`) groups the lines
into bands with a_i = √(Σ_k a_k²) (the peak amplitude of the sine of the band's mean-square value, Parseval) at
the band's power-weighted mean frequency f_i, which removes most of that dependence for stationary signals and
gives the single-line value for a sine that lies within one band.
"""
from __future__ import annotations

import math

import numpy as np

from .filters import butterworth_sections, edge_padding, zero_phase

__all__ = [
    "EN14363_CARBODY_BAND_HZ",
    "DEFAULT_FILTER_ORDER",
    "SPERLING_RANGE_HZ",
    "SPERLING_RIDE_QUALITY_SCALE",
    "as_signal",
    "check_positive",
    "check_same_length",
    "time_step_from_time",
    "window_samples",
    "sliding_mean",
    "sliding_rms",
    "lowpass",
    "bandpass",
    "carbody_acceleration_en14363",
    "sperling_weighting",
    "sperling_index",
    "sperling_ride_quality",
    "third_octave_band_edges",
]

#: EN 14363 / UIC 518 band-pass of the car-body accelerations ÿ*, z̈* (maxima and RMS values) [Hz]
EN14363_CARBODY_BAND_HZ = (0.4, 10.0)
#: Butterworth order of one filter pass (ASSUMPTION, see the module doc); forward-backward doubles it
DEFAULT_FILTER_ORDER = 4
#: frequency range of Sperling's index [Hz] (F(f) is defined from 0.5 Hz; 30 Hz is the usual upper end)
SPERLING_RANGE_HZ = (0.5, 30.0)
#: Sperling's ride-quality scale, as commonly cited (Garg & Dukkipati 1984): upper Wz of each grade
SPERLING_RIDE_QUALITY_SCALE = ((1.0, "very good"), (2.0, "good"), (3.0, "satisfactory"),
                               (4.0, "acceptable for running"), (4.5, "not acceptable for running"),
                               (5.0, "dangerous"))


# ============================================================================================ input checks
def as_signal(x, name: str, min_length: int = 1) -> np.ndarray:
    """``x`` as a 1-D float array of finite values (``ValueError`` naming ``name`` otherwise)."""
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name}: not a numeric time series ({exc})") from None
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a 1-D time series, got an array of shape {a.shape}")
    if a.size < min_length:
        raise ValueError(f"{name}: {a.size} sample(s), at least {min_length} needed")
    bad = ~np.isfinite(a)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name}: {int(bad.sum())} non-finite value(s) (NaN or inf), the first at sample {i}")
    return a


def check_positive(value, name: str) -> float:
    """``value`` as a finite float > 0 (``ValueError`` otherwise)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r}: expected a number") from None
    if not (math.isfinite(v) and v > 0.0):
        raise ValueError(f"{name} = {value!r}: expected a finite value > 0")
    return v


def check_same_length(**signals) -> int:
    """Common length of the given 1-D arrays (``ValueError`` listing the lengths if they differ)."""
    lengths = {k: len(v) for k, v in signals.items()}
    if len(set(lengths.values())) > 1:
        raise ValueError("signals of different lengths: " + ", ".join(f"{k} = {n}" for k, n in lengths.items()))
    return next(iter(lengths.values()))


def time_step_from_time(time_s, rtol: float = 1e-6) -> float:
    """The uniform time step [s] of a time axis; ``ValueError`` if it is not strictly increasing or not uniform
    (every step within ``rtol`` of the mean step)."""
    t = as_signal(time_s, "time_s", min_length=2)
    d = np.diff(t)
    if np.any(d <= 0.0):
        i = int(np.flatnonzero(d <= 0.0)[0])
        raise ValueError(f"time_s: not strictly increasing (sample {i + 1}: {t[i + 1]!r} after {t[i]!r})")
    dt = (t[-1] - t[0]) / (t.size - 1)
    dev = np.abs(d - dt)
    if np.any(dev > rtol * dt):
        i = int(np.argmax(dev))
        raise ValueError(f"time_s: non-uniform sampling (step {d[i]!r} s at sample {i} vs mean step {dt!r} s, "
                         f"relative tolerance {rtol}); resample to a uniform step first")
    return float(dt)


def window_samples(window_m: float, speed_m_s: float, dt_s: float) -> int:
    """Number of samples of a distance window: round(L / (V dt)), at least 1.  The effective window is
    n V dt (reported by the evaluations)."""
    L = check_positive(window_m, "window_m")
    V = check_positive(speed_m_s, "speed_m_s")
    dt = check_positive(dt_s, "dt_s")
    return max(1, int(round(L / (V * dt))))


# ============================================================================================ sliding means
def sliding_mean(x, n: int, ignore_nan: bool = False) -> np.ndarray:
    """Means of all windows of ``n`` consecutive samples ("valid" windows: ``len(x) - n + 1`` values, the k-th over
    samples k … k+n−1).  Each sample stands for one time step, so a window of n samples covers n·dt (n·V·dt of
    track).  ``ignore_nan``: NaN samples are left out of their windows (mean of the others; NaN for a window without
    any valid sample) — otherwise a NaN raises.  ``ValueError`` if the record is shorter than the window."""
    n = int(n)
    if n < 1:
        raise ValueError(f"window of {n} samples: expected >= 1")
    if ignore_nan:
        a = np.asarray(x, dtype=float)
        if a.ndim != 1:
            raise ValueError(f"expected a 1-D time series, got shape {a.shape}")
        if np.isinf(a).any():
            raise ValueError("time series with inf values")
    else:
        a = as_signal(x, "signal")
    if a.size < n:
        raise ValueError(f"record of {a.size} samples is shorter than the window of {n} samples")
    valid = np.isfinite(a)
    s = np.concatenate(([0.0], np.cumsum(np.where(valid, a, 0.0))))
    c = np.concatenate(([0], np.cumsum(valid)))
    sums = s[n:] - s[:-n]
    counts = c[n:] - c[:-n]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)


def sliding_rms(x, n: int) -> np.ndarray:
    """RMS of all windows of ``n`` consecutive samples (see :func:`sliding_mean`)."""
    a = as_signal(x, "signal")
    return np.sqrt(np.maximum(sliding_mean(a * a, n), 0.0))


# ============================================================================================ filters
def _filtfilt(sos: np.ndarray, x: np.ndarray, name: str) -> np.ndarray:
    padlen = edge_padding(sos)
    if x.size <= padlen:
        raise ValueError(f"{name}: {x.size} samples are too few for the zero-phase filter (more than {padlen} needed)")
    return zero_phase(sos, x)


def lowpass(x, dt_s: float, cutoff_hz: float, order: int = DEFAULT_FILTER_ORDER, name: str = "signal") -> np.ndarray:
    """Zero-phase Butterworth low-pass (order ``order`` per pass, forward-backward; gain 1/(1 + (Ω/Ω_c)^(2n)),
    module doc).  ``cutoff_hz`` must lie below the Nyquist frequency 1/(2 dt)."""
    a = as_signal(x, name)
    fs = 1.0 / check_positive(dt_s, "dt_s")
    fc = check_positive(cutoff_hz, "cutoff_hz")
    if fc >= 0.5 * fs:
        raise ValueError(f"cutoff_hz = {fc} Hz is not below the Nyquist frequency {0.5 * fs} Hz (dt = {dt_s} s)")
    sos = butterworth_sections(order, fc, fs, "lowpass")
    return _filtfilt(sos, a, name)


def bandpass(x, dt_s: float, low_hz: float, high_hz: float, order: int = DEFAULT_FILTER_ORDER,
             name: str = "signal") -> np.ndarray:
    """Zero-phase Butterworth band-pass (order ``order`` per pass, a filter of order 2 ``order``, forward-backward; gain
    1/(1 + ((Ω² − Ω_0²)/(Ω B))^(2n)), module doc).  Needs 0 < low < high < Nyquist."""
    a = as_signal(x, name)
    fs = 1.0 / check_positive(dt_s, "dt_s")
    f1 = check_positive(low_hz, "low_hz")
    f2 = check_positive(high_hz, "high_hz")
    if not f1 < f2:
        raise ValueError(f"band {f1}–{f2} Hz: expected low_hz < high_hz")
    if f2 >= 0.5 * fs:
        raise ValueError(f"high_hz = {f2} Hz is not below the Nyquist frequency {0.5 * fs} Hz (dt = {dt_s} s)")
    sos = butterworth_sections(order, (f1, f2), fs, "bandpass")
    return _filtfilt(sos, a, name)


# ============================================================================================ EN 14363 accelerations
def carbody_acceleration_en14363(acc_m_s2, dt_s: float, speed_m_s: float | None = None,
                                 rms_window_m: float | None = None, band_hz=EN14363_CARBODY_BAND_HZ,
                                 order: int = DEFAULT_FILTER_ORDER, limits_m_s2: dict | None = None) -> dict:
    """Car-body acceleration band-pass filtered as EN 14363 evaluates it (0.4–10 Hz, module doc): maximum of |a|
    (``peak_m_s2``), RMS over the record (``rms_m_s2``) and, with ``speed_m_s`` and ``rms_window_m``, the maximum
    sliding RMS over that track length (``sliding_rms_max_m_s2``).  ``limits_m_s2`` (optional, keys ``"peak"``,
    ``"rms"``): adds pass/fail and margins (``None``: not assessed).  Also returns the filtered signal
    (``filtered_m_s2``).  ``peak_near_record_edge``: the peak lies within one period of the lower corner
    (1/0.4 Hz = 2.5 s) of either end of the record, where the filter's edge transient may have made it."""
    a = as_signal(acc_m_s2, "acc_m_s2")
    af = bandpass(a, dt_s, band_hz[0], band_hz[1], order=order, name="acc_m_s2")
    k = int(np.argmax(np.abs(af)))
    edge = int(math.ceil(1.0 / (float(band_hz[0]) * float(dt_s))))     # one period of the lower corner
    out = {"band_hz": [float(band_hz[0]), float(band_hz[1])], "filter_order_per_pass": int(order),
           "peak_m_s2": float(abs(af[k])), "index_of_peak": k, "time_of_peak_s": k * float(dt_s),
           "peak_near_record_edge": bool(k < edge or k >= a.size - edge),
           "rms_m_s2": float(np.sqrt(np.mean(af * af))), "sliding_rms_max_m_s2": None,
           "sliding_window_m": None, "filtered_m_s2": af}
    if rms_window_m is not None:
        if speed_m_s is None:
            raise ValueError("rms_window_m needs speed_m_s (distance window -> samples)")
        n = window_samples(rms_window_m, speed_m_s, dt_s)
        out["sliding_rms_max_m_s2"] = float(np.max(sliding_rms(af, n)))
        out["sliding_window_m"] = n * float(speed_m_s) * float(dt_s)
    out["assessment"] = {}
    for key, value_key in (("peak", "peak_m_s2"), ("rms", "rms_m_s2")):
        lim = None if limits_m_s2 is None else limits_m_s2.get(key)
        out["assessment"][key] = assess(out[value_key], lim)
    return out


def assess(value: float, limit: float | None) -> dict:
    """value / limit / margin (limit − value) / utilisation (value/limit) / passed (value <= limit; None
    without a limit)."""
    if limit is None:
        return {"value": float(value), "limit": None, "margin": None, "utilisation": None, "passed": None}
    lim = check_positive(limit, "limit")
    return {"value": float(value), "limit": lim, "margin": lim - float(value), "utilisation": float(value) / lim,
            "passed": bool(value <= lim)}


# ============================================================================================ Sperling
def sperling_weighting(f_hz, direction: str) -> np.ndarray:
    """Sperling's frequency weighting F(f) (dimensionless), ``direction`` "vertical" or "lateral" (module doc;
    as commonly cited).  Defined for f >= 0.5 Hz; smaller frequencies raise ``ValueError``."""
    f = np.asarray(f_hz, dtype=float)
    if not np.all(np.isfinite(f)) or np.any(f < SPERLING_RANGE_HZ[0]):
        raise ValueError(f"Sperling weighting is defined for f >= {SPERLING_RANGE_HZ[0]} Hz")
    if direction == "vertical":
        c_low, f1, c_high, f2 = 0.325, 5.9, 400.0, 20.0
    elif direction == "lateral":
        c_low, f1, c_high, f2 = 0.8, 5.4, 650.0, 26.0
    else:
        raise ValueError(f"direction = {direction!r}: expected 'vertical' or 'lateral'")
    return np.where(f < f1, c_low * f * f, np.where(f < f2, c_high / (f * f), 1.0))


def third_octave_band_edges(f_min_hz: float = 0.5, f_max_hz: float = 30.0) -> np.ndarray:
    """Edges [Hz] of one-third-octave bands (ratio 2^(1/3)) from ``f_min_hz`` until ``f_max_hz`` is covered."""
    lo = check_positive(f_min_hz, "f_min_hz")
    hi = check_positive(f_max_hz, "f_max_hz")
    if not lo < hi:
        raise ValueError("expected f_min_hz < f_max_hz")
    n = int(math.ceil(3.0 * math.log2(hi / lo) - 1e-12))
    return lo * 2.0 ** (np.arange(n + 1) / 3.0)


def sperling_index(acc_m_s2, dt_s: float, direction: str, f_min_hz: float = SPERLING_RANGE_HZ[0],
                   f_max_hz: float = SPERLING_RANGE_HZ[1], bands=None, detrend: bool = True) -> dict:
    """Sperling's ride index Wz of an acceleration record [m/s²] (module doc for the formula and the conventions).

    Returns ``Wz``, the band frequencies ``f_hz``, peak amplitudes ``amplitude_cm_s2`` and per-band ``Wz_i``,
    the frequency resolution ``df_hz`` = 1/(N dt) and the range used.  ``bands=None``: every FFT line in
    [f_min, min(f_max, Nyquist)] is a band; ``bands`` = increasing band edges [Hz]: lines grouped per band
    (a_i = √Σ a_k², f_i the power-weighted mean frequency).  ``detrend``: remove the mean first (only the 0 Hz line
    changes)."""
    a = as_signal(acc_m_s2, "acc_m_s2", min_length=4)
    dt = check_positive(dt_s, "dt_s")
    sperling_weighting(np.array([1.0]), direction)          # validates direction
    lo = check_positive(f_min_hz, "f_min_hz")
    hi = check_positive(f_max_hz, "f_max_hz")
    if lo < SPERLING_RANGE_HZ[0]:
        raise ValueError(f"f_min_hz = {lo}: the weighting is defined from {SPERLING_RANGE_HZ[0]} Hz")
    if not lo < hi:
        raise ValueError("expected f_min_hz < f_max_hz")
    n = a.size
    x = a - a.mean() if detrend else a
    spec = np.fft.rfft(x)
    f = np.fft.rfftfreq(n, dt)
    amp = 2.0 * np.abs(spec) / n
    amp[0] *= 0.5
    if n % 2 == 0:
        amp[-1] *= 0.5
    amp_cm = 100.0 * amp                                     # m/s² -> cm/s²
    nyq = 0.5 / dt
    hi_used = min(hi, nyq)
    sel = (f >= lo) & (f <= hi_used)
    if not sel.any():
        raise ValueError(f"no FFT line in [{lo}, {hi_used}] Hz (resolution {1.0 / (n * dt)} Hz): record too short")
    if bands is None:
        fb, ab = f[sel], amp_cm[sel]
    else:
        edges = np.asarray(bands, dtype=float)
        if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0) or edges[0] < SPERLING_RANGE_HZ[0]:
            raise ValueError("bands: expected increasing band edges [Hz] starting at >= 0.5 Hz")
        fb_list, ab_list = [], []
        fs_sel, as_sel = f[sel], amp_cm[sel]
        for k in range(edges.size - 1):
            last = k == edges.size - 2
            m = (fs_sel >= edges[k]) & ((fs_sel <= edges[k + 1]) if last else (fs_sel < edges[k + 1]))
            p = as_sel[m] ** 2
            if m.any() and p.sum() > 0.0:
                fb_list.append(float(np.sum(p * fs_sel[m]) / p.sum()))
                ab_list.append(float(np.sqrt(p.sum())))
        fb, ab = np.array(fb_list), np.array(ab_list)
    if fb.size:
        terms = ab ** 3 * sperling_weighting(fb, direction) / fb
        wz_i = 0.896 * terms ** 0.1
        wz = float(0.896 * terms.sum() ** 0.1)
    else:
        wz_i, wz = np.array([]), 0.0
    return {"Wz": wz, "direction": direction, "f_hz": fb, "amplitude_cm_s2": ab, "Wz_i": wz_i,
            "df_hz": 1.0 / (n * dt), "range_hz": [lo, float(hi_used)],
            "convention": "peak amplitude per FFT line (one-sided, 2|X|/N), cm/s²; Wz = 0.896 (Σ a³F/f)^0.1"}


def sperling_ride_quality(wz: float) -> str:
    """Grade of Sperling's ride-quality scale (:data:`SPERLING_RIDE_QUALITY_SCALE`, as commonly cited)."""
    w = float(wz)
    if not math.isfinite(w) or w < 0.0:
        raise ValueError(f"Wz = {wz!r}: expected a finite value >= 0")
    for upper, grade in SPERLING_RIDE_QUALITY_SCALE:
        if w <= upper:
            return grade
    return "dangerous"
