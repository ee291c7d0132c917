r"""Running stability of a linear(ised) vehicle: eigenvalues of a first-order state matrix, frequency and damping
ratio, mode tracking across speeds, the speed where a damping ratio crosses zero; the kinematic references
(Klingel, the rigid bogie) and two small linear models (a restrained wheelset, a rigid two-axle bogie) to test them
with; the limit-cycle amplitude of a time series.  Pure functions on arrays (NumPy, SciPy).

Modes of a state matrix
-----------------------
For ``dx/dt = A x`` an eigenvalue ``λ = σ + iω`` gives the mode ``exp(λ t)``: frequency ``f = ω / 2π`` (the damped
frequency) and damping ratio ``ζ = -σ / |λ|`` (ζ < 0: the mode grows).  A real eigenvalue is a non-oscillating
mode: ``f = 0`` and ``ζ = -sign(σ)``.  The eigenvalues of a real matrix come in conjugate pairs; a mode is listed
once (:attr:`ModeSet.listed`: ``ω >= 0``), all of them are tracked (their number does not change with the speed).

The eigenvectors are checked: LAPACK's balancing (``numpy.linalg.eig``) can scale a matrix whose couplings that are
zero by symmetry came out of central differences as round-off (1e-31 … 1e-22 beside entries of 1e6) by such powers
of two that the eigenvectors it transforms back are wrong — the linearised wheelset at 300 km/h gave residuals
``|A v − λ v|`` of 167 for unit vectors, while its eigenvalues were right.  A vector whose relative residual exceeds
:data:`EIGENVECTOR_RESIDUAL_MAX` is replaced by the right singular vector of ``A − λ I`` of its smallest singular
value (its null vector, without balancing).

Mode tracking
-------------
Between two neighbouring speeds the eigenvalues are paired by the assignment that minimises the sum of the
distances ``|λ_i - λ_j| / (|λ_i| + |λ_j| + 1)`` plus ``1 - MAC`` of their shapes where shapes are given (Hungarian
method, ``scipy.optimize.linear_sum_assignment``); ``MAC = |v_i^H v_j|² / (|v_i|² |v_j|²)``.

Linear wheelset and bogie (Wickens; Knothe & Stichel, *Rail Vehicle Dynamics*, 2017; Iwnicki (ed.),
*Handbook of Railway Vehicle Dynamics*, 2006)
--------------------------------------------------------------------------------------------------------------------
A wheelset of mass ``m`` and yaw inertia ``I``, lateral shift ``y`` and yaw ``ψ``, conicity ``λ``, half the
distance between the contact points ``b``, rolling radius ``r0``, running at speed ``V`` with Kalker's linear creep
coefficients ``f11`` (longitudinal) and ``f22`` (lateral) per wheel, no spin, no gravitational stiffness:

.. math::  m \ddot y + 2 f_{22} (\dot y / V - ψ) + k_y y = 0, \qquad
           I \ddot ψ + 2 f_{11} b (b \dot ψ / V + λ y / r_0) + k_ψ ψ = 0,

``k_y``, ``k_ψ`` the lateral and yaw stiffness to a frame moving with V (a restrained wheelset; zero: free).
Without creep damping (``f → ∞``) the free wheelset rolls kinematically with Klingel's frequency
``f_K = V / (2π) √(λ / (b r0))``.  Two such wheelsets held rigidly in a bogie at ``x = ±a`` (the frame's ``y``, ``ψ``;
wheelset ``y ± a ψ``) roll kinematically (``f11 = f22``) with the wavelength ``L = 2π √(b r0 (1 + a²/b²) / λ)``.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import linear_sum_assignment

__all__ = ["ModeSet", "modes_of", "EIGENVECTOR_RESIDUAL_MAX", "frequency_damping", "mac_matrix", "track_modes",
           "first_zero_crossing",
           "klingel_frequency_hz", "bogie_kinematic_wavelength_m", "wheelset_state_matrix", "bogie_state_matrix",
           "window_amplitude", "window_amplitudes", "limit_cycle", "linger_amplitude", "zero_crossing_frequency_hz"]

#: largest accepted residual of an eigenvector ``v`` of ``A``: ``|A v − λ v| ≤ this · max|A_ij| · |v|`` (a backward-
#: stable solver reaches ~n ε; an eigenvalue's condition may cost a few decades more)
EIGENVECTOR_RESIDUAL_MAX = 1e-9


class ModeSet:
    """The eigenvalues of a state matrix (``eigenvalues``, complex, all of them), their ``shapes`` (columns: the
    first half of the eigenvector, the displacement part when the state is ``[q, dq/dt]``), ``frequency_hz`` and
    ``damping_ratio``; ``listed`` marks one eigenvalue per mode (``Im λ >= 0``)."""

    def __init__(self, eigenvalues, shapes):
        self.eigenvalues = np.asarray(eigenvalues, dtype=complex)
        self.shapes = np.asarray(shapes, dtype=complex)
        self.frequency_hz, self.damping_ratio = frequency_damping(self.eigenvalues)
        self.listed = self.eigenvalues.imag >= 0.0

    def __len__(self) -> int:
        return len(self.eigenvalues)

    def reordered(self, order) -> "ModeSet":
        order = np.asarray(order, dtype=int)
        return ModeSet(self.eigenvalues[order], self.shapes[:, order])


def frequency_damping(eigenvalues) -> tuple[np.ndarray, np.ndarray]:
    """``(frequency_hz, damping_ratio)`` of eigenvalues ``λ = σ + iω``: ``|ω| / 2π`` and ``-σ / |λ|`` (for a real
    eigenvalue ``-sign(σ)``; a zero eigenvalue: NaN)."""
    lam = np.asarray(eigenvalues, dtype=complex)
    mag = np.abs(lam)
    with np.errstate(invalid="ignore", divide="ignore"):
        zeta = np.where(mag > 0.0, -lam.real / np.where(mag > 0.0, mag, 1.0), np.nan)
    return np.abs(lam.imag) / (2.0 * math.pi), zeta


def _checked_eig(A) -> tuple[np.ndarray, np.ndarray]:
    """``numpy.linalg.eig`` with every eigenvector checked and, where wrong, recomputed (module docstring)."""
    lam, vec = np.linalg.eig(A)
    scale = max(float(np.abs(A).max()), 1.0)
    eye = np.eye(A.shape[0])
    for k in range(len(lam)):
        v = vec[:, k]
        if np.linalg.norm(A @ v - lam[k] * v) > EIGENVECTOR_RESIDUAL_MAX * scale * np.linalg.norm(v):
            vec[:, k] = np.linalg.svd(A - lam[k] * eye)[2][-1].conj()
    return lam, vec


def modes_of(A, n_displacement: int | None = None, imag_tolerance: float = 1e-9) -> ModeSet:
    """The eigenvalues of the state matrix ``A`` (``numpy.linalg.eig``, the eigenvectors checked: module docstring),
    an imaginary part within ``imag_tolerance · max(1, |λ|)`` set to zero (a real eigenvalue); shapes the first
    ``n_displacement`` rows of the eigenvectors (default: half of the state), each scaled to a largest entry of 1;
    sorted by frequency."""
    A = np.asarray(A, dtype=float)
    lam, vec = _checked_eig(A)
    n = A.shape[0] // 2 if n_displacement is None else int(n_displacement)
    real = np.abs(lam.imag) <= imag_tolerance * np.maximum(1.0, np.abs(lam))
    lam = np.where(real, lam.real + 0j, lam)
    shapes = vec[:n, :].copy()
    for k in range(shapes.shape[1]):
        i = int(np.argmax(np.abs(shapes[:, k])))
        if abs(shapes[i, k]) > 0.0:
            shapes[:, k] /= shapes[i, k]
    order = np.lexsort((lam.imag, lam.real, np.abs(lam.imag)))
    return ModeSet(lam[order], shapes[:, order])


def mac_matrix(shapes_a, shapes_b) -> np.ndarray:
    """The modal assurance criterion of every column of ``shapes_a`` with every column of ``shapes_b``."""
    a = np.asarray(shapes_a, dtype=complex)
    b = np.asarray(shapes_b, dtype=complex)
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    return num / np.where(den > 0.0, den, 1.0)


def track_modes(mode_sets: list) -> list:
    """The mode sets of successive speeds (the same number of eigenvalues each) reordered so that entry ``k`` of
    each is the same mode (module docstring).  Returns new :class:`ModeSet` objects."""
    if not mode_sets:
        return []
    out = [mode_sets[0]]
    for cur in mode_sets[1:]:
        prev = out[-1]
        la, lb = prev.eigenvalues, cur.eigenvalues
        if len(la) != len(lb):
            raise ValueError(f"track_modes: {len(la)} and {len(lb)} eigenvalues: expected the same number")
        cost = np.abs(la[:, None] - lb[None, :]) / (np.abs(la)[:, None] + np.abs(lb)[None, :] + 1.0)
        if prev.shapes.shape[0] == cur.shapes.shape[0]:
            cost = cost + (1.0 - mac_matrix(prev.shapes, cur.shapes))
        rows, cols = linear_sum_assignment(cost)
        order = np.empty(len(la), dtype=int)
        order[rows] = cols
        out.append(cur.reordered(order))
    return out


def first_zero_crossing(x, y) -> float | None:
    """The lowest ``x`` where ``y`` (sampled at increasing ``x``) goes from positive to zero or negative, by linear
    interpolation between the two samples; ``x[0]`` when ``y[0] <= 0``; None when ``y`` stays positive.  NaN samples
    are skipped."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    ok = np.isfinite(y)
    x, y = x[ok], y[ok]
    if len(x) == 0:
        return None
    if y[0] <= 0.0:
        return float(x[0])
    for i in range(1, len(x)):
        if y[i] <= 0.0:
            return float(x[i - 1] + (x[i] - x[i - 1]) * y[i - 1] / (y[i - 1] - y[i]))
    return None


def klingel_frequency_hz(speed_m_s: float, conicity: float, half_contact_distance_m: float, r0_m: float) -> float:
    """Klingel's kinematic frequency of a free wheelset, ``V / (2π) √(λ / (b r0))`` [Hz]."""
    return speed_m_s / (2.0 * math.pi) * math.sqrt(conicity / (half_contact_distance_m * r0_m))


def bogie_kinematic_wavelength_m(conicity: float, half_contact_distance_m: float, r0_m: float,
                                 semi_wheelbase_m: float) -> float:
    """The kinematic wavelength of a rigid two-axle bogie, ``2π √(b r0 (1 + a²/b²) / λ)`` [m]."""
    b, a = half_contact_distance_m, semi_wheelbase_m
    return 2.0 * math.pi * math.sqrt(b * r0_m * (1.0 + a * a / (b * b)) / conicity)


def wheelset_state_matrix(speed_m_s: float, mass_kg: float, yaw_inertia_kg_m2: float, conicity: float,
                          half_contact_distance_m: float, r0_m: float, f11_N: float, f22_N: float,
                          ky_N_per_m: float = 0.0, kpsi_N_m_per_rad: float = 0.0) -> np.ndarray:
    """The state matrix of the linear wheelset (module docstring), state ``[y, ψ, dy/dt, dψ/dt]``."""
    V, m, I, b = speed_m_s, mass_kg, yaw_inertia_kg_m2, half_contact_distance_m
    M = np.diag([m, I])
    C = np.diag([2.0 * f22_N / V, 2.0 * f11_N * b * b / V])
    K = np.array([[ky_N_per_m, -2.0 * f22_N],
                  [2.0 * f11_N * b * conicity / r0_m, kpsi_N_m_per_rad]])
    return _first_order(M, C, K)


def bogie_state_matrix(speed_m_s: float, frame_mass_kg: float, frame_yaw_inertia_kg_m2: float, conicity: float,
                       half_contact_distance_m: float, r0_m: float, semi_wheelbase_m: float, f11_N: float,
                       f22_N: float) -> np.ndarray:
    """The state matrix of a rigid two-axle bogie (both wheelsets held rigidly at ``x = ±a``; mass and yaw inertia
    of the whole), state ``[y, ψ, dy/dt, dψ/dt]``: the creep forces of the two wheelsets (module docstring) summed,
    the lateral ones also as a yaw moment ``±a F_y``."""
    V, b, a = speed_m_s, half_contact_distance_m, semi_wheelbase_m
    M = np.diag([frame_mass_kg, frame_yaw_inertia_kg_m2])
    C = np.diag([4.0 * f22_N / V, 4.0 * (f11_N * b * b + f22_N * a * a) / V])
    K = np.array([[0.0, -4.0 * f22_N],
                  [4.0 * f11_N * b * conicity / r0_m, 0.0]])
    return _first_order(M, C, K)


def _first_order(M, C, K) -> np.ndarray:
    """``[[0, I], [-M⁻¹K, -M⁻¹C]]`` of ``M q'' + C q' + K q = 0``."""
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])


def window_amplitude(distance_m, values, start_m: float, end_m: float) -> float:
    """Half the peak-to-peak value of the samples with ``start_m <= distance < end_m`` (NaN ignored; NaN without
    any): an oscillation's amplitude, blind to a steady offset."""
    s = np.asarray(distance_m, dtype=float)
    v = np.asarray(values, dtype=float)
    sel = v[(s >= start_m) & (s < end_m)]
    sel = sel[np.isfinite(sel)]
    return float(0.5 * (np.max(sel) - np.min(sel))) if sel.size else float("nan")


def window_amplitudes(distance_m, values, start_m: float, window_m: float) -> list:
    """:func:`window_amplitude` over consecutive windows of ``window_m`` from ``start_m`` to the last sample (a last
    window shorter than half ``window_m`` left out)."""
    s = np.asarray(distance_m, dtype=float)
    end = float(np.nanmax(s)) if s.size else start_m
    n = int(math.floor((end - start_m) / window_m + 0.5))
    return [window_amplitude(s, values, start_m + k * window_m, start_m + (k + 1) * window_m) for k in range(n)]


def linger_amplitude(decaying, persisting, max_ratio: float) -> tuple[int | None, float]:
    """Where two responses that bracket an unstable limit cycle linger near it, and its amplitude there:
    ``decaying`` and ``persisting`` are the amplitudes over the same consecutive windows of the run that decays and
    of the run that reaches the stable cycle.  Of the windows where the two are within ``max_ratio`` of each other
    (both near the cycle), the one where both change least to the next window — the smallest
    ``|ln a[k+1] − ln a[k]|`` summed over the two runs — and the geometric mean of their amplitudes there.
    ``(None, NaN)`` where no window qualifies (the runs part before the first window ends)."""
    d = np.asarray(decaying, dtype=float)
    p = np.asarray(persisting, dtype=float)
    n = min(d.size, p.size)
    with np.errstate(divide="ignore", invalid="ignore"):
        ld, lp = np.log(d[:n]), np.log(p[:n])
        close = np.abs(lp - ld) <= math.log(max_ratio)
        change = np.abs(np.diff(ld)) + np.abs(np.diff(lp))
    ok = np.flatnonzero(close[:-1] & np.isfinite(change)) if n > 1 else np.zeros(0, dtype=int)
    if ok.size == 0:
        return None, float("nan")
    k = int(ok[np.argmin(change[ok])])
    return k, float(np.exp(0.5 * (ld[k] + lp[k])))


def limit_cycle(distance_m, values, window_m: float, n_windows: int, min_amplitude: float,
                max_damping_ratio: float) -> tuple[float, float, bool]:
    """``(amplitude, damping_ratio, persists)`` of an oscillation recorded against the distance run: ``amplitude`` is
    :func:`window_amplitude` over the last ``window_m``; ``damping_ratio`` the equivalent damping ratio of its trend —
    the least-squares decay per window of the log of the last ``n_windows`` windows' amplitudes over 2π times the
    cycles per window (counted from the zero crossings about the mean over those windows): ``ζ = −ln(ratio)/(2π
    n)``, negative when it grows; it persists when the amplitude is at least ``min_amplitude`` and the damping ratio
    at most ``max_damping_ratio``.  Judged per cycle, the rule treats a slow mode and a fast one alike."""
    s = np.asarray(distance_m, dtype=float)
    v = np.asarray(values, dtype=float)
    end = float(np.nanmax(s))
    amps = np.array([window_amplitude(s, v, end - (k + 1) * window_m, end - k * window_m + (1.0 if k == 0 else 0.0))
                     for k in range(n_windows)])[::-1]                                 # oldest first
    last = float(amps[-1])
    ok = np.isfinite(amps) & (amps > 0.0)
    span = (s >= end - n_windows * window_m) & np.isfinite(v)
    x = v[span] - np.mean(v[span]) if span.any() else v[span]
    crossings = int(np.count_nonzero(np.sign(x[1:]) * np.sign(x[:-1]) < 0))
    if ok.sum() < 2 or crossings < 2:
        return last, float("nan"), False
    ratio = float(np.exp(np.polyfit(np.arange(n_windows)[ok], np.log(amps[ok]), 1)[0]))
    cycles_per_window = 0.5 * crossings / n_windows
    zeta = -math.log(ratio) / (2.0 * math.pi * cycles_per_window)
    return last, zeta, bool(np.isfinite(last) and last >= min_amplitude and zeta <= max_damping_ratio)


def zero_crossing_frequency_hz(time_s, values) -> float:
    """The mean frequency of an oscillation about zero from its zero crossings (linearly interpolated): half a period
    between two successive crossings (NaN with fewer than three crossings)."""
    t = np.asarray(time_s, dtype=float)
    y = np.asarray(values, dtype=float)
    ok = np.isfinite(y)
    t, y = t[ok], y[ok]
    i = np.flatnonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)
    if len(i) < 3:
        return float("nan")
    tc = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    return float(0.5 / np.mean(np.diff(tc)))
