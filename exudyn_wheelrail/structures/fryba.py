r"""Frýba's closed-form moving-force solution: the deflection of a simply supported Euler–Bernoulli span under
constant forces crossing it at a constant speed (:func:`fryba_moving_force`), the reference of the deck models.

References
----------
L. Frýba, *Vibration of solids and structures under moving loads*, Noordhoff 1972 / Thomas Telford 1999, Ch. 1
(simply supported beam under a moving constant force: the modal series solution).  L. Frýba, A rough assessment
of railway bridges for high speed trains, Engineering Structures 23 (2001) 548–556 (trains of equally spaced
forces, resonance speeds ``v = f_1 d / k``).
"""
from __future__ import annotations

import math

import numpy as np

from .checks import checked_number

__all__ = ["fryba_moving_force"]


def fryba_moving_force(x_m, t_s, *, force_N: float, speed_m_s: float, span_m: float, EI_Nm2: float,
                       m_kg_m: float, damping_ratio: float = 0.0, n_terms: int = 50, offsets_m=(0.0,)):
    """Deflection (z down) of a simply supported Euler–Bernoulli beam under constant forces ``force_N`` (down)
    moving at ``speed_m_s``, by the modal series of Frýba (1999, Ch. 1; written here with modal damping): for
    mode j (shape ``sin(jπx/L)``, ``ω_j = (jπ/L)² √(EI/m)``, excitation frequency ``Ω_j = jπv/L``)

        ``q̈_j + 2ζω_j q̇_j + ω_j² q_j = (2P/(mL)) sin(Ω_j (t - t_k))``   while force k is on the span,

    solved in closed form (particular + homogeneous solution from rest; after the force leaves, free damped
    vibration from the state at exit), ``w(x, t) = Σ_k Σ_j q_j^(k)(t) sin(jπx/L)``.  For ζ = 0 this is Frýba's
    ``v(x,t) = v0 Σ 1/(j²(j² - α²)) [sin jωt - (α/j) sin ω_j t] sin(jπx/L)`` with ``v0 = 2PL³/(π⁴EI)``,
    ``α = v/(2 f_1 L)``.  The force k enters the span (x = 0) at ``t_k = offsets_m[k]/v`` (offsets ≥ 0: following
    forces).  ``x_m``, ``t_s`` broadcast.  Exact resonance ``Ω_j = ω_j`` with ζ = 0 is handled by its limit."""
    P = checked_number("force_N", force_N)
    v = checked_number("speed_m_s", speed_m_s, positive=True)
    L = checked_number("span_m", span_m, positive=True)
    EI = checked_number("EI_Nm2", EI_Nm2, positive=True)
    m = checked_number("m_kg_m", m_kg_m, positive=True)
    z = checked_number("damping_ratio", damping_ratio, non_negative=True)
    if not z < 1.0:
        raise ValueError(f"damping_ratio={z}: expected 0 <= ζ < 1")
    if isinstance(n_terms, bool) or not isinstance(n_terms, (int, np.integer)) or n_terms < 1:
        raise ValueError(f"n_terms={n_terms!r}: expected an integer >= 1")
    offs = np.atleast_1d(np.asarray(offsets_m, dtype=float))
    if np.any(~np.isfinite(offs)) or np.any(offs < 0):
        raise ValueError("offsets_m: expected finite offsets >= 0")
    x, t = np.broadcast_arrays(np.asarray(x_m, dtype=float), np.asarray(t_s, dtype=float))
    w = np.zeros(x.shape)
    T_on = L / v
    A = 2.0 * P / (m * L)
    for j in range(1, int(n_terms) + 1):
        wj = (j * math.pi / L) ** 2 * math.sqrt(EI / m)
        Om = j * math.pi * v / L
        wd = wj * math.sqrt(1.0 - z * z)
        shape = np.sin(j * math.pi * x / L)
        for off in offs:
            tau = t - off / v
            q = _forced_response(A, wj, wd, z, Om, np.clip(tau, 0.0, T_on))
            qT, qT_t = _forced_response(A, wj, wd, z, Om, np.array(T_on), rate=True)
            tf = np.maximum(tau - T_on, 0.0)
            ez = np.exp(-z * wj * tf)
            q_free = ez * (qT * np.cos(wd * tf) + (qT_t + z * wj * qT) / wd * np.sin(wd * tf))
            q = np.where(tau <= T_on, q, q_free)
            w += np.where(tau > 0.0, q, 0.0) * shape
    return w


def _forced_response(A, w, wd, z, Om, t, rate=False):
    """Response from rest of ``q̈ + 2ζω q̇ + ω² q = A sin(Ω t)`` (and its rate)."""
    t = np.asarray(t, dtype=float)
    den = (w * w - Om * Om) ** 2 + (2.0 * z * w * Om) ** 2
    if den < 1e-24 * w ** 4:                     # undamped resonance: the limit Ω → ω
        q = A / (2.0 * w * w) * (np.sin(w * t) - w * t * np.cos(w * t))
        if not rate:
            return q
        return q, A / 2.0 * t * np.sin(w * t)
    a = A * (w * w - Om * Om) / den               # particular: a sin Ωt + b cos Ωt
    b = -A * 2.0 * z * w * Om / den
    c1 = -b                                        # homogeneous e^{-ζωt}(c1 cos ω_d t + c2 sin ω_d t), q(0)=q'(0)=0
    c2 = (-a * Om + z * w * c1) / wd
    e = np.exp(-z * w * t)
    q = a * np.sin(Om * t) + b * np.cos(Om * t) + e * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    if not rate:
        return q
    q_t = (a * Om * np.cos(Om * t) - b * Om * np.sin(Om * t)
           + e * ((-z * w * c1 + wd * c2) * np.cos(wd * t) + (-z * w * c2 - wd * c1) * np.sin(wd * t)))
    return q, q_t
