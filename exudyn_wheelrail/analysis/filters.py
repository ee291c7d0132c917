r"""Zero-phase Butterworth filters of recorded signals: the digital low-pass and band-pass as second-order sections
(:func:`butterworth_sections`) and their forward–backward run (:func:`zero_phase`).

Design (the bilinear transform with pre-warped corners: e.g. A. V. Oppenheim & R. W. Schafer, *Discrete-Time
Signal Processing*, 3rd ed. 2010, §7.2; T. W. Parks & C. S. Burrus, *Digital Filter Design*, 1987, ch. 7).  The
analogue Butterworth prototype of order n has no zeros and its poles on the unit circle of the left half-plane,
``p_k = exp(iπ (2k + n + 1) / (2n))``, k = 0 … n − 1, with gain 1 at s = 0.  A corner f is pre-warped to
``Ω = 2 f_s tan(π f / f_s)``, so that the digital filter has the analogue magnitude at the warped frequency:

* low-pass of corner Ω_c: the poles ``Ω_c p_k``; n zeros at infinity;
* band-pass Ω_1 … Ω_2 (``B = Ω_2 − Ω_1``, ``Ω_0² = Ω_1 Ω_2``; the substitution ``s → (s² + Ω_0²)/(s B)``): each
  prototype pole p gives the two poles ``p B/2 ± √((p B/2)² − Ω_0²)``; n zeros at s = 0 and n at infinity (a
  filter of order 2n).

The bilinear transform ``z = (2 f_s + s)/(2 f_s − s)`` takes the poles inside the unit circle, s = 0 to z = 1 and
infinity to z = −1, and the gain k of the analogue filter (``Ω_c^n``, band-pass ``B^n``) to
``k Π(2 f_s − s_zero) / Π(2 f_s − s_pole)`` (over the finite zeros and all poles): the digital magnitude is 1 where
the analogue one is, at z = 1 (low-pass) or at the centre ``ω_0 = 2 atan(Ω_0 / (2 f_s))`` (band-pass).  A section is a pair of complex-conjugate poles (or the two real poles of one prototype pole)
with two zeros — low-pass (−1, −1), band-pass (+1, −1) — ``b = (b0, b1, b2)``, ``a = (1, a1, a2)``; the real
pole of a low-pass of odd order is a first-order section.  The sections are ordered by their poles' distance from
the unit circle, the nearest last; the gain is on the first section.

Filtering (:func:`zero_phase`): each section in the transposed direct form II — ``y = b0 x + s1``,
``s1 ← b1 x − a1 y + s2``, ``s2 ← b2 x − a2 y`` — over the signal extended at both ends by its odd reflection
about the end sample (:func:`edge_padding` samples), the states started at the steady state of a step of the first
sample's height (a level start passes without a transient), forward, then backward over the reversed output; the
extension is then cut off.  The gain is the square of the single-pass magnitude and the phase zero.
"""
from __future__ import annotations

import cmath
import math

import numpy as np

from ..jit import compiled

__all__ = ["butterworth_sections", "edge_padding", "step_states", "sections_response", "zero_phase"]


def _digital(s: complex, fs2: float) -> complex:
    """The bilinear transform of the analogue point ``s`` (``fs2`` = 2 f_s)."""
    return (fs2 + s) / (fs2 - s)


def _pair(z: complex) -> tuple[float, float]:
    """``(a1, a2)`` of the conjugate pole pair ``z``, ``z̄``."""
    return -2.0 * z.real, abs(z) ** 2


def butterworth_sections(order: int, corners_hz, fs_hz: float, kind: str) -> np.ndarray:
    """The digital Butterworth ``kind`` = ``"lowpass"`` (``corners_hz`` one corner) or ``"bandpass"`` (two corners)
    of ``order`` n as an ``(n_sections, 6)`` array of rows ``(b0, b1, b2, 1, a1, a2)`` (module docstring).  The
    corners must lie in (0, f_s/2), increasing; the callers check them and name the input."""
    n = int(order)
    if n < 1 or n != order:
        raise ValueError(f"order = {order!r}: expected an integer >= 1")
    fs2 = 2.0 * float(fs_hz)
    warp = [fs2 * math.tan(math.pi * float(f) / float(fs_hz)) for f in np.atleast_1d(corners_hz)]
    proto = [cmath.exp(1j * math.pi * (2 * k + n + 1) / (2 * n)) for k in range(n // 2)]   # upper half-plane
    rows, radii = [], []
    gain = [1.0]                                            # k Π(2 f_s − s_zero) / Π(2 f_s − s_pole), built up

    def add(b, a1, a2, radius):
        rows.append([b[0], b[1], b[2], 1.0, a1, a2])
        radii.append(radius)

    def pole(s: complex, pair: bool) -> complex:
        """The digital pole of ``s`` (with its conjugate if ``pair``), its factor taken into the gain."""
        gain[0] /= abs(fs2 - s) ** 2 if pair else (fs2 - s.real)
        return _digital(s, fs2)

    if kind == "lowpass":
        wc = warp[0]
        gain[0] = wc ** n
        for p in proto:
            z = pole(wc * p, True)
            add((1.0, 2.0, 1.0), *_pair(z), abs(z))
        if n % 2:
            z = pole(complex(-wc, 0.0), False).real
            add((1.0, 1.0, 0.0), -z, 0.0, abs(z))
    elif kind == "bandpass":
        w1, w2 = warp
        bw, w0 = w2 - w1, math.sqrt(w1 * w2)
        gain[0] = (bw * fs2) ** n                           # B^n and the n zeros at s = 0
        for p in proto:
            h = 0.5 * bw * p
            root = cmath.sqrt(h * h - w0 * w0)
            for s in (h + root, h - root):
                z = pole(s, True)
                add((1.0, 0.0, -1.0), *_pair(z), abs(z))
        if n % 2:                                          # the prototype's real pole -1
            h = -0.5 * bw
            d = h * h - w0 * w0
            if d >= 0.0:                                   # two real poles
                z1 = pole(complex(h + math.sqrt(d), 0.0), False).real
                z2 = pole(complex(h - math.sqrt(d), 0.0), False).real
                add((1.0, 0.0, -1.0), -(z1 + z2), z1 * z2, max(abs(z1), abs(z2)))
            else:
                z = pole(complex(h, math.sqrt(-d)), True)
                add((1.0, 0.0, -1.0), *_pair(z), abs(z))
    else:
        raise ValueError(f"kind {kind!r}: expected 'lowpass' or 'bandpass'")
    sos = np.array([rows[i] for i in np.argsort(radii, kind="stable")], dtype=float)
    sos[0, :3] *= gain[0]
    return sos


def sections_response(sos: np.ndarray, omega_rad) -> np.ndarray:
    """The complex frequency response of the cascade ``sos`` at the digital frequencies ``omega_rad``
    (``ω = 2π f / f_s``)."""
    z1 = np.exp(-1j * np.asarray(omega_rad, dtype=float))
    h = np.ones_like(z1)
    for b0, b1, b2, a0, a1, a2 in sos:
        h = h * (b0 + b1 * z1 + b2 * z1 * z1) / (a0 + a1 * z1 + a2 * z1 * z1)
    return h


def edge_padding(sos: np.ndarray) -> int:
    """Samples of the odd extension at each end: three times the cascade's length, ``2 n_sections + 1`` less the
    sections whose second-order coefficients are all zero (first-order sections)."""
    first_order = min(int((sos[:, 2] == 0).sum()), int((sos[:, 5] == 0).sum()))
    return 3 * (2 * len(sos) + 1 - first_order)


def step_states(sos: np.ndarray) -> np.ndarray:
    """The sections' states ``(s1, s2)`` in the steady state of a unit step at the cascade's input (each section's
    input is the previous one's steady output, its DC gain times the step)."""
    states = np.zeros((len(sos), 2))
    level = 1.0
    for k, (b0, b1, b2, _, a1, a2) in enumerate(sos):
        gain = (b0 + b1 + b2) / (1.0 + a1 + a2)
        s2 = (b2 - a2 * gain) * level
        states[k] = ((b1 - a1 * gain) * level + s2, s2)
        level *= gain
    return states


@compiled
def _cascade(sos, x, states):
    """The cascade ``sos`` run over ``x`` from the states ``states`` (transposed direct form II, section after
    section); returns the output."""
    y = x.copy()
    for k in range(sos.shape[0]):
        b0, b1, b2, a1, a2 = sos[k, 0], sos[k, 1], sos[k, 2], sos[k, 4], sos[k, 5]
        s1, s2 = states[k, 0], states[k, 1]
        for i in range(y.size):
            xi = y[i]
            yi = b0 * xi + s1
            s1 = b1 * xi - a1 * yi + s2
            s2 = b2 * xi - a2 * yi
            y[i] = yi
    return y


def zero_phase(sos: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``x`` filtered forward and backward by the cascade ``sos`` over its odd extension (module docstring); ``x``
    must be longer than :func:`edge_padding` (the callers check it and name the signal)."""
    x = np.ascontiguousarray(x, dtype=float)
    sos = np.ascontiguousarray(sos, dtype=float)
    p = edge_padding(sos)
    ext = np.concatenate((2.0 * x[0] - x[p:0:-1], x, 2.0 * x[-1] - x[-2:-p - 2:-1]))
    zi = step_states(sos)
    y = _cascade(sos, ext, zi * ext[0])
    y = _cascade(sos, np.ascontiguousarray(y[::-1]), zi * y[-1])[::-1]
    return np.ascontiguousarray(y[p:len(y) - p])
