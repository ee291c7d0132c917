r"""Standard power spectral densities of track irregularities and irregularities generated from them (the spectra's
published coefficients, tabulated below, and the default wavelength band are declared in
:mod:`exudyn_wheelrail.standards`).

PSD convention (used throughout)
--------------------------------
**One-sided, per angular wavenumber**: ``S(Ω)`` in m²/(rad/m) with ``Ω = 2π/λ`` in rad/m, such that the variance of
the irregularity in a band is ``σ² = ∫ S(Ω) dΩ`` over ``Ω_1 ≤ Ω ≤ Ω_2`` (Ω > 0 only).  Per cycles/m (``n = 1/λ``) the
same spectrum is ``S_n(n) = 2π S(2π n)``.  Channels and signs: :mod:`exudyn_wheelrail.conventions` (alignment y,
vertical level z, cross level c = z_right - z_left, gauge deviation g).

FRA track classes 1–6 (Hamid & Yang 1981; as tabulated in Garg & Dukkipati, *Dynamics of Railway Vehicle Systems*,
Academic Press 1984, and Zhai, *Vehicle–Track Coupled Dynamics*, Springer 2020)
----------------------------------------------------------------------------------------------------------------
With ``k = 0.25``, ``Ω_c = 0.8245`` rad/m, ``A_v``, ``A_a`` in cm²·rad/m and S in cm²/(rad/m) (converted here by
1e-4 to m²):

.. math::
   S_{level} = \frac{k A_v Ω_c^2}{Ω^2 (Ω^2 + Ω_c^2)},\quad
   S_{alignment} = \frac{k A_a Ω_c^2}{Ω^2 (Ω^2 + Ω_c^2)},\quad
   S_{cross\,level} = S_{gauge} = \frac{4 k A_v Ω_c^2}{(Ω^2 + Ω_c^2)(Ω^2 + Ω_s^2)}

=====  ======  ======  ======
class  A_v     A_a     Ω_s
=====  ======  ======  ======
1      1.2107  3.3634  0.6046
2      1.0181  1.2107  0.9308
3      0.6816  0.4128  0.8520
4      0.5376  0.3027  1.1312
5      0.2095  0.0762  0.8209
6      0.0339  0.0339  0.4380
=====  ======  ======  ======

Class 6 is the best track.  The FRA fit covers wavelengths of 1.524–304.8 m.

German high-speed spectra, low and high interference (Deutsche Bahn; as given in Zhai 2020 and, e.g., Guo, Xia, De
Roeck & Liu, Computers & Structures 112–113 (2012) 205–216)
------------------------------------------------------------------------------------------------------------------
With ``Ω_c = 0.8246``, ``Ω_r = 0.0206``, ``Ω_s = 0.4380`` rad/m, ``b = 0.75`` m (half the rail-centre distance) and
A in m·rad (S in m²/(rad/m)):

.. math::
   S_{level} = \frac{A_v Ω_c^2}{(Ω^2 + Ω_r^2)(Ω^2 + Ω_c^2)},\quad
   S_{alignment} = \frac{A_a Ω_c^2}{(Ω^2 + Ω_r^2)(Ω^2 + Ω_c^2)},\quad
   S_{gauge} = \frac{A_g Ω_c^2 Ω^2}{(Ω^2 + Ω_r^2)(Ω^2 + Ω_c^2)(Ω^2 + Ω_s^2)}

and for the cross level the published ``A_v b^{-2} Ω_c^2 Ω^2 / ((Ω^2 + Ω_r^2)(Ω^2 + Ω_c^2)(Ω^2 + Ω_s^2))``, which is
dimensionally the PSD of the cross-level *angle* ``c/(2b)``; the cross level as a height difference (the channel
here) is therefore ``(2b)^2`` times it, ``4 A_v Ω_c^2 Ω^2/(...)`` — the same factor 4 on the level coefficient as the
FRA cross level.

===========  =========  =========  =========
interference A_a        A_v        A_g
===========  =========  =========  =========
low          2.119e-7   4.032e-7   5.32e-8
high         6.125e-7   1.080e-6   1.032e-7
===========  =========  =========  =========

Generation
----------
A sum of harmonics with random phases (Shinozuka & Jan, J. Sound Vib. 25 (1972) 111–128) on the wavenumber grid of
the generated length ``L``: ``Ω_k = 2π k/L`` inside the band ``2π/λ_max ≤ Ω_k ≤ 2π/λ_min``, amplitude
``a_k = sqrt(2 S(Ω_k) ΔΩ)`` with ``ΔΩ = 2π/L`` and phase ``φ_k`` uniform in [0, 2π) from the seed, evaluated at the
samples ``s_j = s_0 + j Δs`` by one inverse real FFT:

.. math::  x(s) = \sum_k a_k \cos(Ω_k (s - s_0) + φ_k)

The signal is periodic in L; its mean square over L is exactly ``Σ a_k²/2 = Σ S(Ω_k) ΔΩ``, the band integral of the
spectrum to the quadrature's accuracy.  Each channel has its own phases (channels independent), drawn from one
``numpy.random.default_rng(seed)`` in the order of :data:`~.irregularities.CHANNELS`: the same seed, band, length and
sampling give the same track.  The samples are interpolated like measured data
(:class:`~.irregularities.ChannelTable`); ``Δs ≤ λ_min/8`` is required: a cubic spline through a sine of wavelength
λ sampled at Δs errs by at most ``(5/384) (2π Δs/λ)^4`` of its amplitude, 0.5 % at 8 and 0.1 % at 12 samples per
wavelength (the default 0.25 m for λ_min = 3 m).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad

from ..standards import (DEFAULT_BAND_M, FRA_CLASSES, FRA_K, FRA_OMEGA_C, GERMAN_B, GERMAN_OMEGA, GERMAN_SPECTRA,
                         TRACK_SPECTRA)
from .irregularities import CHANNELS, ChannelTable

__all__ = ["SPECTRA", "TrackSpectrum", "SpectralIrregularity", "DEFAULT_BAND_M", "DEFAULT_STEP_M",
           "spectrum_by_name"]

#: sample spacing of generated irregularities by default [m]
DEFAULT_STEP_M = 0.25

_CM2 = 1e-4  # cm² -> m²


@dataclass(frozen=True)
class TrackSpectrum:
    """One standard spectrum (module docstring): ``family`` ``"fra"`` (``level`` the class 1–6) or ``"german"``
    (``level`` ``"low"`` / ``"high"``)."""

    name: str
    family: str
    level: object
    source: str

    def psd(self, channel: str, omega_rad_m) -> np.ndarray:
        """One-sided PSD ``S(Ω)`` [m²/(rad/m)] of ``channel`` at the angular wavenumbers ``omega_rad_m`` (> 0)."""
        if channel not in CHANNELS:
            raise ValueError(f"spectrum {self.name}: unknown channel {channel!r} (expected {', '.join(CHANNELS)})")
        w2 = np.asarray(omega_rad_m, dtype=float) ** 2
        if self.family == "fra":
            a_v, a_a, om_s = FRA_CLASSES[self.level]
            c2 = FRA_OMEGA_C ** 2
            if channel == "level":
                return _CM2 * FRA_K * a_v * c2 / (w2 * (w2 + c2))
            if channel == "alignment":
                return _CM2 * FRA_K * a_a * c2 / (w2 * (w2 + c2))
            return _CM2 * 4.0 * FRA_K * a_v * c2 / ((w2 + c2) * (w2 + om_s ** 2))
        a_a, a_v, a_g = GERMAN_SPECTRA[self.level]
        om_c, om_r, om_s = GERMAN_OMEGA
        c2 = om_c ** 2
        base = c2 / ((w2 + om_r ** 2) * (w2 + c2))
        if channel == "level":
            return a_v * base
        if channel == "alignment":
            return a_a * base
        if channel == "cross_level":
            return (2.0 * GERMAN_B) ** 2 * (a_v / GERMAN_B ** 2) * base * w2 / (w2 + om_s ** 2)
        return a_g * base * w2 / (w2 + om_s ** 2)

    def band_variance(self, channel: str, band_m=DEFAULT_BAND_M) -> float:
        """``∫ S(Ω) dΩ`` over the wavelength band ``(λ_min, λ_max)`` [m²]: the variance of the channel in the band."""
        lo, hi = _band(band_m, self.name)
        return float(quad(lambda w: float(self.psd(channel, w)), 2 * math.pi / hi, 2 * math.pi / lo, limit=200,
                          epsabs=0.0, epsrel=1e-10)[0])


#: the standard spectra by name (:data:`exudyn_wheelrail.standards.TRACK_SPECTRA`)
SPECTRA = {name: TrackSpectrum(name, *entry) for name, entry in TRACK_SPECTRA.items()}


def spectrum_by_name(name: str) -> TrackSpectrum:
    """The :class:`TrackSpectrum` called ``name`` (a key of :data:`SPECTRA`)."""
    if isinstance(name, TrackSpectrum):
        return name
    if name not in SPECTRA:
        raise ValueError(f"spectrum {name!r}: expected one of {', '.join(SPECTRA)}")
    return SPECTRA[name]


def _band(band_m, what) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in band_m)
    except (TypeError, ValueError):
        raise ValueError(f"{what}: wavelength band {band_m!r}: expected (lambda_min_m, lambda_max_m)") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi):
        raise ValueError(f"{what}: wavelength band {band_m!r}: expected 0 < lambda_min_m < lambda_max_m")
    return lo, hi


class SpectralIrregularity(ChannelTable):
    """Irregularity channels generated from a standard spectrum (module docstring, "Generation").

    Parameters: ``spectrum`` a name of :data:`SPECTRA` (or a :class:`TrackSpectrum`); ``length_m`` the generated
    length (the signal's period; the table starts at ``start_m`` and is held constant beyond it); ``seed`` a
    non-negative integer; ``band_m`` the wavelength band ``(λ_min, λ_max)`` [m]; ``step_m`` the sample spacing
    (at most λ_min/8); ``channels`` the channels generated (default all four); ``scale`` a factor on every amplitude
    (1 = the standard)."""

    def __init__(self, spectrum, length_m: float, seed: int, band_m=DEFAULT_BAND_M, step_m: float = DEFAULT_STEP_M,
                 channels=tuple(CHANNELS), start_m: float = 0.0, scale: float = 1.0):
        self.spectrum = spectrum_by_name(spectrum)
        what = f"generated irregularity ({self.spectrum.name})"
        lo, hi = _band(band_m, what)
        for key, value in (("length_m", length_m), ("step_m", step_m), ("start_m", start_m), ("scale", scale)):
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"{what}: {key} = {value!r}: expected a finite number")
        if not step_m > 0.0 or step_m > lo / 8.0:
            raise ValueError(f"{what}: step_m = {step_m} must be positive and at most lambda_min/8 = {lo / 8.0:g} m")
        if not length_m >= hi:
            raise ValueError(f"{what}: length_m = {length_m} must cover the longest wavelength ({hi:g} m)")
        if not scale >= 0.0:
            raise ValueError(f"{what}: scale = {scale} must not be negative")
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise ValueError(f"{what}: seed = {seed!r}: expected a non-negative integer")
        channels = tuple(channels)
        for c in channels:
            if c not in CHANNELS:
                raise ValueError(f"{what}: unknown channel {c!r} (expected {', '.join(CHANNELS)})")
        n = math.ceil(length_m / step_m)
        n += n % 2
        if n > 20_000_000:
            raise ValueError(f"{what}: {n} samples (length_m / step_m) is too many; use a longer step_m")
        self.length_m = n * step_m                    # the period (whole samples)
        self.seed, self.band_m, self.step_m, self.scale = int(seed), (lo, hi), float(step_m), float(scale)
        d_omega = 2.0 * math.pi / self.length_m
        k = np.arange(n // 2 + 1)
        omega = k * d_omega
        inside = (omega >= 2.0 * math.pi / hi) & (omega <= 2.0 * math.pi / lo)
        rng = np.random.default_rng(self.seed)
        samples = {}
        for c in CHANNELS:                            # phases drawn for every channel: a subset keeps its phases
            phase = rng.uniform(0.0, 2.0 * math.pi, size=len(k))
            if c not in channels:
                continue
            amp = np.zeros(len(k))
            amp[inside] = scale * np.sqrt(2.0 * self.spectrum.psd(c, omega[inside]) * d_omega)
            samples[c] = np.fft.irfft(0.5 * n * amp * np.exp(1j * phase), n=n)
        s = start_m + step_m * np.arange(n)
        self.omega_rad_m = omega[inside]
        super().__init__(s, samples, name=f"{self.spectrum.name} seed {self.seed}")

    def __repr__(self):
        return (f"SpectralIrregularity({self.spectrum.name!r}, length_m={self.length_m:g}, seed={self.seed}, "
                f"band_m={self.band_m}, step_m={self.step_m:g}, channels={tuple(self.channels)})")
