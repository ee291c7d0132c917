"""Closed-form references of the flexible track: Zimmermann's beam on a continuous elastic foundation under a point
load (deflection, bending moment), the steady state of a load moving over a Winkler beam, and the point receptance
of the continuously supported track (pad, sleeper mass, ballast)."""
from __future__ import annotations

import numpy as np

__all__ = ["zimmermann_deflection_m", "zimmermann_moment_Nm", "winkler_moving_load_deflection_m",
           "continuous_receptance_m_N"]


def zimmermann_deflection_m(P_N: float, EI_Nm2: float, k_N_m2: float) -> float:
    """Zimmermann/Winkler: deflection under a point load ``P`` on an infinite beam on a continuous elastic
    foundation, ``w0 = P β/(2k)``, ``β = (k/(4EI))^¼``."""
    beta = (k_N_m2 / (4.0 * EI_Nm2)) ** 0.25
    return P_N * beta / (2.0 * k_N_m2)


def zimmermann_moment_Nm(P_N: float, EI_Nm2: float, k_N_m2: float) -> float:
    """Bending moment under the load of :func:`zimmermann_deflection_m`: ``M0 = P/(4β)``."""
    return P_N / (4.0 * (k_N_m2 / (4.0 * EI_Nm2)) ** 0.25)


def winkler_moving_load_deflection_m(xi_m, P_N: float, EI_Nm2: float, m_kg_m: float, k_N_m2: float,
                                     speed_m_s: float, c_Ns_m2: float = 0.0) -> np.ndarray:
    """Steady-state deflection of an infinite beam on a viscoelastic Winkler foundation (``k``, ``c`` per metre)
    under a constant load moving at ``speed_m_s`` below the critical speed ``(4 k EI/m²)^¼``, at ``xi = x - V t``
    (Timoshenko 1927; Frýba 1972, Ch. 2): ``EI w'''' + m V² w'' - c V w' + k w = P δ(ξ)``; the decaying
    exponentials (roots of ``EI r⁴ + m V² r² - c V r + k``) on either side matched at ξ = 0 (w, w', w''
    continuous, ``EI`` times the jump of w''' equal to ``P``, z down positive)."""
    v_cr = (4.0 * k_N_m2 * EI_Nm2 / m_kg_m ** 2) ** 0.25
    if not speed_m_s < v_cr:
        raise ValueError(f"speed {speed_m_s} m/s is not below the critical speed {v_cr:.6g} m/s")
    roots = np.roots([EI_Nm2, 0.0, m_kg_m * speed_m_s ** 2, -c_Ns_m2 * speed_m_s, k_N_m2])
    neg = roots[roots.real < 0.0]            # decaying for ξ > 0
    pos = roots[roots.real > 0.0]            # decaying for ξ < 0
    # unknowns: a1, a2 (ξ > 0, roots neg), b1, b2 (ξ < 0, roots pos); conditions on w, w', w'', w'''
    A = np.zeros((4, 4), dtype=complex)
    rhs = np.zeros(4, dtype=complex)
    for d in range(4):
        A[d, 0:2] = neg ** d
        A[d, 2:4] = -(pos ** d)
    rhs[3] = P_N / EI_Nm2
    c = np.linalg.solve(A, rhs)
    xi = np.asarray(xi_m, dtype=float)
    xp, xm = np.maximum(xi, 0.0), np.minimum(xi, 0.0)
    w = np.where(xi >= 0.0, c[0] * np.exp(neg[0] * xp) + c[1] * np.exp(neg[1] * xp),
                 c[2] * np.exp(pos[0] * xm) + c[3] * np.exp(pos[1] * xm))
    return np.real(w)


def continuous_receptance_m_N(f_Hz, EI_Nm2: float, m_kg_m: float, k_pad_N_m2: float, c_pad_Ns_m2: float,
                              m_sleeper_kg_m: float, k_ballast_N_m2: float, c_ballast_Ns_m2: float) -> np.ndarray:
    """Point receptance ``w/F`` [m/N] of an infinite Euler–Bernoulli beam on a continuous two-layer support (pad,
    smeared sleeper mass, ballast; all per metre) — the continuously supported track model (Knothe & Grassie
    1993; Thompson 2009 Ch. 3): ``EI w'''' + (s(ω) − m ω²) w = F δ(x)`` with the support's dynamic stiffness
    ``s = k̃_p (k̃_b − ω² m_s)/(k̃_p + k̃_b − ω² m_s)``, ``k̃ = k + iωc``; ``w(0)/F = 1/(8 EI λ³)``,
    ``λ = ((s − mω²)/(4EI))^¼`` (principal root, decaying)."""
    w = 2.0 * np.pi * np.asarray(f_Hz, dtype=float)
    kp = k_pad_N_m2 + 1j * w * c_pad_Ns_m2
    kb = k_ballast_N_m2 + 1j * w * c_ballast_Ns_m2
    s = kp * (kb - w ** 2 * m_sleeper_kg_m) / (kp + kb - w ** 2 * m_sleeper_kg_m)
    lam = ((s - m_kg_m * w ** 2) / (4.0 * EI_Nm2)) ** 0.25
    return 1.0 / (8.0 * EI_Nm2 * lam ** 3)
