r"""Hertz normal contact between wheel and rail (elliptical contact patch).

Usable from numba-compiled kernels (``@njit`` functions on plain floats) and from Python
(:class:`HertzContact`).  SI units throughout: curvatures in 1/m, lengths in m, moduli in Pa, forces in N.

Geometry
--------
Each body is described near the contact point by its principal curvatures (1/m, **convex positive**,
concave negative) in the rolling direction *x* and the lateral direction *y*:
``k_wx, k_wy`` (wheel) and ``k_rx, k_ry`` (rail).  The principal directions of both bodies are assumed to
coincide with x and y (true for a wheel of revolution on a straight prismatic rail when the wheelset yaw
angle is neglected in the curvature computation).  The relative curvatures are (Johnson 1985, §4.1)

.. math::  A = \tfrac12 (k_{wx} + k_{rx}), \qquad B = \tfrac12 (k_{wy} + k_{ry}),

so the gap between the undeformed surfaces is :math:`h = A x^2 + B y^2`.  The auxiliary angle
:math:`\theta` of the classical tables is :math:`\cos\theta = |B - A| / (A + B)`.

Elasticity
----------
.. math::  \frac{1}{E^*} = \frac{1-\nu_w^2}{E_w} + \frac{1-\nu_r^2}{E_r}.

Hertz solution (Johnson 1985, ch. 3 and §4.2; Kalker 1990)
--------------------------------------------------------
The pressure :math:`p = p_0\sqrt{1 - x^2/a^2 - y^2/b^2}` on an ellipse with semi-axes
:math:`a_\mathrm{L} \ge a_\mathrm{S}` (long, short), eccentricity
:math:`e^2 = 1 - a_\mathrm{S}^2 / a_\mathrm{L}^2`, produces inside the ellipse the normal surface
displacement (sum of both bodies) :math:`\bar u = (D_0 - D_\mathrm{L} s_\mathrm{L}^2 - D_\mathrm{S} s_\mathrm{S}^2)/(\pi E^*)`
(:math:`s_\mathrm{L}, s_\mathrm{S}` coordinates along the long and short axis) with
(:math:`K = K(e), E = E(e)` complete elliptic integrals of the first and second kind, modulus *e*)

.. math::
    D_0 = \pi p_0 a_\mathrm{S} K, \quad
    D_\mathrm{L} = \frac{\pi p_0 a_\mathrm{S}}{e^2 a_\mathrm{L}^2}(K - E), \quad
    D_\mathrm{S} = \frac{\pi p_0 a_\mathrm{S}}{e^2 a_\mathrm{L}^2}\Big(\frac{a_\mathrm{L}^2}{a_\mathrm{S}^2}E - K\Big).

Matching :math:`\bar u = \delta - A x^2 - B y^2` gives, with :math:`C_\mathrm{S} \ge C_\mathrm{L}` the larger
and smaller of (A, B), N the normal force and :math:`p_0 = 3N/(2\pi a_\mathrm{L} a_\mathrm{S})`
(the **long axis lies along the direction of the smaller relative curvature**):

* shape:      :math:`C_\mathrm{S}/C_\mathrm{L} = \big[(a_\mathrm{L}/a_\mathrm{S})^2 E - K\big] / (K - E)`;
* size:       :math:`a_\mathrm{L} = m\,c_0,\ a_\mathrm{S} = n\,c_0,\ c_0 = \big(3N/(4E^*(A+B))\big)^{1/3}`, with
  :math:`m = \big(2E/(\pi(1-e^2))\big)^{1/3},\ n = m\sqrt{1-e^2}` (sphere: *m = n = 1*);
* approach:   :math:`\delta = 3 N K / (2\pi a_\mathrm{L} E^*)`, hence :math:`N = K_h\,\delta^{3/2}` with

.. math::
    K_h = \kappa(\theta)\,\frac{E^*}{\sqrt{A+B}}, \qquad
    \kappa = \frac{\sqrt 3}{2}\Big(\frac{2\pi m}{3K}\Big)^{3/2}
    \qquad (\text{sphere: } \kappa = 4/3,\ K_h = \tfrac43 E^*\sqrt{R}\ \text{with}\ A = B = 1/(2R)),

  and the analytic tangent stiffness :math:`\mathrm dN/\mathrm d\delta = \tfrac32 K_h \delta^{1/2}`.
  In terms of the approach, :math:`c_0 = q\,\sqrt{\delta/(A+B)}` with :math:`q = (3\kappa/4)^{1/3}`.

Implementation
--------------
*m, n, κ, q* depend only on the curvature ratio.  At import they are computed from the complete elliptic
integrals (``scipy.special.ellipkm1`` / ``ellipe``; note scipy's parameter is :math:`e^2`) on a uniform
grid of :math:`u = |\ln(B/A)| \in [0, \ln 10^6]` (curvature ratio up to 10⁶, axis ratio up to ≈ 2900,
i.e. far beyond the 1/50 … 50 needed) with spacing 0.02, and stored as cubic-spline coefficients.  The
numba kernels evaluate one log, one cubic segment and a few square roots (interpolation error < 1e-9
relative; see ``tests/test_hertz.py``).  Only *m, n, q* are tabulated; κ = 4q³/3 is formed from *q* so that
the force and penetration paths are mutual inverses to rounding.  Ratios beyond the grid are saturated and
flagged.

Conformal / degenerate geometry
-------------------------------
Hertz theory requires A > 0 and B > 0.  Near-conformal contact (e.g. a concave wheel throat against the
rail gauge corner, or a worn hollow tread on a flat rail) gives A or B ≤ 0 or tiny; each relative curvature
is then floored at ``min_curvature`` (default :data:`DEFAULT_MIN_CURVATURE` = 0.1 1/m, i.e. an equivalent
relative radius 1/(2·0.1) = 5 m) and a status bit is set.  Justification of the default: genuine
wheel–rail relative curvatures are ≥ about 1 1/m in rolling direction (A ≈ 1/(2 r₀) ≈ 1.1 1/m for
r₀ = 0.46 m) and typically ≥ 0.2 1/m laterally even for worn, close-conformal treads, so the floor never alters
a valid non-conformal contact; at the floor the patch already reaches a semi-axis of ≈ 15–20 mm at
50 kN, comparable to the lateral extent over which profile curvatures are constant, where the Hertz
assumptions have broken down anyway (a non-Hertzian/multi-point model is needed there).  The floor only
keeps the answer finite, bounded and continuous.

Status flags (bit field, ``int``): :data:`STATUS_OK` = 0, :data:`STATUS_CLAMPED_A` = 1 (A floored),
:data:`STATUS_CLAMPED_B` = 2 (B floored), :data:`STATUS_RATIO_SATURATED` = 4 (curvature ratio beyond table),
:data:`STATUS_NO_CONTACT` = 8 (δ ≤ 0 or N ≤ 0: zero force, zero patch).  NaN curvatures are floored and
flagged like non-positive ones.

References
----------
* K. L. Johnson, *Contact Mechanics*, Cambridge University Press, 1985, chapter 4 (§4.1 geometry of
  non-conforming surfaces, §4.2 Hertz theory, elliptical contact) and chapter 3 (displacements under
  an ellipsoidal pressure on an elliptical region).
* J. J. Kalker, *Three-Dimensional Elastic Bodies in Rolling Contact*, Kluwer, 1990 (Hertz theory with
  the coefficients m, n as used in wheel–rail contact).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.special import ellipe, ellipkm1

from ..jit import compiled
from ..validation import finite, poisson_ratio, youngs_modulus

__all__ = [
    "DEFAULT_MIN_CURVATURE",
    "E_STEEL",
    "NU_STEEL",
    "G_STEEL",
    "STATUS_OK",
    "STATUS_CLAMPED_A",
    "STATUS_CLAMPED_B",
    "STATUS_RATIO_SATURATED",
    "STATUS_NO_CONTACT",
    "effective_modulus",
    "clamp_curvatures",
    "hertz_ellipse",
    "hertz_stiffness",
    "hertz_from_penetration",
    "hertz_from_force",
    "hertz_coefficients_exact",
    "HertzContact",
]

# ----------------------------------------------------------------------------------------------- constants
E_STEEL = 2.1e11  #: Young's modulus of wheel/rail steel, Pa
NU_STEEL = 0.28  #: Poisson's ratio of steel
G_STEEL = E_STEEL / (2.0 * (1.0 + NU_STEEL))  #: shear modulus, Pa (≈ 82 GPa, consistent with E, ν)

DEFAULT_MIN_CURVATURE = 0.1  #: floor for the relative curvatures A, B in 1/m (equivalent radius 5 m)
_TINY_CURVATURE = 1e-12  # absolute floor used if the caller passes min_curvature <= 0

STATUS_OK = 0
STATUS_CLAMPED_A = 1
STATUS_CLAMPED_B = 2
STATUS_RATIO_SATURATED = 4
STATUS_NO_CONTACT = 8


# ------------------------------------------------------------------------------- exact (scipy) coefficients
def _ratio_from_log_axis(g):
    """Curvature ratio C_S/C_L >= 1 for the axis ratio a_L/a_S = exp(g) (vectorised, g >= 0)."""
    p = np.exp(-2.0 * np.asarray(g, dtype=float))  # p = 1 - e^2 = (a_S/a_L)^2
    K = ellipkm1(p)  # K(e), scipy parameter m = e^2 = 1 - p (ellipkm1 takes p, accurate for e -> 1)
    E = ellipe(1.0 - p)
    with np.errstate(invalid="ignore", divide="ignore"):
        return (E / p - K) / (K - E)


def _log_axis_from_log_ratio(u):
    """Solve ln(C_S/C_L) = u for g = ln(a_L/a_S) by vectorised bisection (monotone, bracket [0, 14])."""
    u = np.atleast_1d(np.asarray(u, dtype=float))
    lo = np.zeros_like(u)
    hi = np.full_like(u, 14.0)  # a/b = e^14 ~ 1.2e6, curvature ratio >> 1e6
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        with np.errstate(invalid="ignore", divide="ignore"):
            above = np.log(_ratio_from_log_axis(mid)) >= u
        hi = np.where(above, mid, hi)
        lo = np.where(above, lo, mid)
    g = 0.5 * (lo + hi)
    g[u <= 0.0] = 0.0
    return g


def _coefficients_from_log_axis(g):
    """(m, n, kappa, q) for g = ln(a_L/a_S) (vectorised); exact sphere values at g = 0."""
    g = np.asarray(g, dtype=float)
    p = np.exp(-2.0 * g)
    K = ellipkm1(p)
    E = ellipe(1.0 - p)
    m = np.cbrt(2.0 * E / (np.pi * p))
    n = m * np.sqrt(p)
    kappa = 0.5 * np.sqrt(3.0) * (2.0 * np.pi * m / (3.0 * K)) ** 1.5
    q = np.cbrt(0.75 * kappa)
    return m, n, kappa, q


def hertz_coefficients_exact(A, B):
    """Reference (slow, scipy) Hertz coefficients ``(m_x, m_y, kappa)`` for positive A, B.

    Solves the eccentricity equation directly (no table); used to build the interpolation table and
    to measure its accuracy.  Not for use inside simulation loops.
    """
    A = float(A)
    B = float(B)
    if not (A > 0.0 and B > 0.0):
        raise ValueError("hertz_coefficients_exact needs A > 0 and B > 0")
    g = _log_axis_from_log_ratio(abs(math.log(B / A)))
    m, n, kappa, _ = _coefficients_from_log_axis(g)
    m, n, kappa = float(m[0]), float(n[0]), float(kappa[0])
    return (m, n, kappa) if A <= B else (n, m, kappa)


# ------------------------------------------------------------------------------------- interpolation table
_U_MAX = math.log(1.0e6)  # curvature ratio 1e6  (axis ratio ~ 2.9e3)
_H = 0.02
_N_NODES = int(math.ceil(_U_MAX / _H)) + 1


def _build_table():
    u = np.arange(_N_NODES) * _H
    g = _log_axis_from_log_ratio(u)
    m, n, kappa, q = _coefficients_from_log_axis(g)
    m[0] = n[0] = q[0] = 1.0
    kappa[0] = 4.0 / 3.0
    coef = np.empty((_N_NODES - 1, 3, 4))  # [interval, function (m, n, q), power (3, 2, 1, 0)]
    for j, f in enumerate((m, n, q)):
        cs = CubicSpline(u, f, bc_type="not-a-knot")
        coef[:, j, :] = cs.c.T
    return np.ascontiguousarray(coef)


_TABLE = _build_table()
_INV_H = 1.0 / _H
_U_TABLE_MAX = (_N_NODES - 1) * _H
_LAST = _N_NODES - 2


# ------------------------------------------------------------------------------------------- numba kernels
def effective_modulus(E_wheel, nu_wheel, E_rail, nu_rail) -> float:
    """E* in Pa: 1/E* = (1-ν_w²)/E_w + (1-ν_r²)/E_r (Johnson 1985, §4.2).

    ``ValueError`` for a Young's modulus that is not finite and > 0 or a Poisson's ratio outside -1 < ν <= 0.5
    (:mod:`exudyn_wheelrail.validation`): outside that range 1 - ν² may vanish or change sign."""
    E_w = youngs_modulus("E_wheel", E_wheel)
    E_r = youngs_modulus("E_rail", E_rail)
    nu_w = poisson_ratio("nu_wheel", nu_wheel)
    nu_r = poisson_ratio("nu_rail", nu_rail)
    return 1.0 / ((1.0 - nu_w * nu_w) / E_w + (1.0 - nu_r * nu_r) / E_r)


@compiled
def clamp_curvatures(A, B, min_curvature=DEFAULT_MIN_CURVATURE):
    """Floor the relative curvatures: returns ``(A', B', status)``; NaN is floored too."""
    floor = min_curvature if min_curvature > 0.0 else _TINY_CURVATURE
    status = 0
    if not (A >= floor):
        A = floor
        status |= STATUS_CLAMPED_A
    if not (B >= floor):
        B = floor
        status |= STATUS_CLAMPED_B
    return A, B, status


@compiled
def _table_eval(u):
    """Interpolated (m_long, n_short, kappa, q, saturated) for u = |ln(B/A)| >= 0."""
    sat = 0
    if u >= _U_TABLE_MAX:
        u = _U_TABLE_MAX
        sat = STATUS_RATIO_SATURATED
    i = int(u * _INV_H)
    if i > _LAST:
        i = _LAST
    t = u - i * _H
    c = _TABLE[i]
    m = ((c[0, 0] * t + c[0, 1]) * t + c[0, 2]) * t + c[0, 3]
    n = ((c[1, 0] * t + c[1, 1]) * t + c[1, 2]) * t + c[1, 3]
    q = ((c[2, 0] * t + c[2, 1]) * t + c[2, 2]) * t + c[2, 3]
    return m, n, (4.0 / 3.0) * q * q * q, q, sat


@compiled
def _oriented(A, B):
    """(m_x, m_y, kappa, q, sat) for already-clamped positive A, B."""
    if B >= A:  # smaller curvature along x -> long axis along x
        m, n, kappa, q, sat = _table_eval(math.log(B / A))
        return m, n, kappa, q, sat
    m, n, kappa, q, sat = _table_eval(math.log(A / B))
    return n, m, kappa, q, sat


@compiled
def hertz_ellipse(A, B, min_curvature=DEFAULT_MIN_CURVATURE):
    """Hertz coefficients ``(m_x, m_y, kappa)`` for relative curvatures A (along x), B (along y), 1/m.

    Semi-axes a_x = m_x·c0 (rolling x), b_y = m_y·c0 (lateral y) with c0 = (3N/(4E*(A+B)))^(1/3), and
    N = Kh·δ^1.5 with Kh = kappa·E*/sqrt(A+B).  A and B are floored at ``min_curvature`` first
    (use :func:`clamp_curvatures` to obtain the status flag).
    """
    A, B, _ = clamp_curvatures(A, B, min_curvature)
    mx, my, kappa, _q, _sat = _oriented(A, B)
    return mx, my, kappa


@compiled
def hertz_stiffness(A, B, E_star, min_curvature=DEFAULT_MIN_CURVATURE):
    """Generalised Hertz stiffness ``(Kh, status)`` in N/m^1.5 (N = Kh·δ^1.5)."""
    A, B, status = clamp_curvatures(A, B, min_curvature)
    _mx, _my, kappa, _q, sat = _oriented(A, B)
    return kappa * E_star / math.sqrt(A + B), status | sat


@compiled
def hertz_from_penetration(A, B, E_star, delta, min_curvature=DEFAULT_MIN_CURVATURE):
    """Normal force from the approach δ (m): returns ``(N, dN_ddelta, a, b, status)``.

    N = Kh·δ^1.5 (N), dN/dδ = 1.5·Kh·δ^0.5 (N/m), a = semi-axis along x, b = along y (m).
    δ <= 0 (or NaN) gives zeros and :data:`STATUS_NO_CONTACT`.
    """
    A, B, status = clamp_curvatures(A, B, min_curvature)
    if not (delta > 0.0):
        return 0.0, 0.0, 0.0, 0.0, status | STATUS_NO_CONTACT
    mx, my, kappa, q, sat = _oriented(A, B)
    rs = 1.0 / math.sqrt(A + B)
    sd = math.sqrt(delta)
    k_eff = kappa * E_star * rs * sd  # Kh * sqrt(delta)
    c0 = q * sd * rs
    return k_eff * delta, 1.5 * k_eff, mx * c0, my * c0, status | sat


@compiled
def hertz_from_force(A, B, E_star, N, min_curvature=DEFAULT_MIN_CURVATURE):
    """Approach and patch from the normal force N (N): returns ``(delta, a, b, status)``.

    c0 = (3N/(4E*(A+B)))^(1/3), a = m_x·c0 (along x), b = m_y·c0 (along y), δ = (A+B)·(c0/q)².
    N <= 0 (or NaN) gives zeros and :data:`STATUS_NO_CONTACT`.
    """
    A, B, status = clamp_curvatures(A, B, min_curvature)
    if not (N > 0.0):
        return 0.0, 0.0, 0.0, status | STATUS_NO_CONTACT
    mx, my, _kappa, q, sat = _oriented(A, B)
    S = A + B
    c0 = np.cbrt(0.75 * N / (E_star * S))
    r = c0 / q
    return S * r * r, mx * c0, my * c0, status | sat


# ------------------------------------------------------------------------------------------ Python wrapper
@dataclass(frozen=True)
class HertzContact:
    """Hertz contact of given geometry and materials (readable Python front end of the kernels).

    Build with :meth:`from_curvatures` (body curvatures) or directly from relative curvatures ``A``, ``B``
    (1/m, along x = rolling and y = lateral) and ``E_star`` (Pa).  Methods accept scalars or arrays.
    The stored ``A``, ``B`` are the values after flooring at ``min_curvature``; ``status`` holds the flags,
    ``m_x``, ``m_y``, ``kappa`` the Hertz coefficients and ``Kh`` the stiffness in N = Kh·δ^1.5.
    """

    A: float
    B: float
    E_star: float
    min_curvature: float = DEFAULT_MIN_CURVATURE
    status: int = field(init=False)
    m_x: float = field(init=False)
    m_y: float = field(init=False)
    kappa: float = field(init=False)
    Kh: float = field(init=False)  #: N/m^1.5

    def __post_init__(self):
        E_star = finite("E_star", self.E_star)
        if not E_star > 0.0:
            raise ValueError(f"E_star: {E_star:g} Pa is not an effective modulus (must be > 0)")
        A, B, status = clamp_curvatures(float(self.A), float(self.B), float(self.min_curvature))
        mx, my, kappa, q, sat = _oriented(A, B)
        set_ = object.__setattr__
        set_(self, "A", float(A))
        set_(self, "B", float(B))
        set_(self, "status", int(status | sat))
        set_(self, "m_x", float(mx))
        set_(self, "m_y", float(my))
        set_(self, "kappa", float(kappa))
        set_(self, "E_star", E_star)
        set_(self, "Kh", float(kappa * E_star / math.sqrt(A + B)))

    @classmethod
    def from_curvatures(cls, k_wx, k_wy, k_rx, k_ry, E_wheel=E_STEEL, nu_wheel=NU_STEEL,
                        E_rail=E_STEEL, nu_rail=NU_STEEL, min_curvature=DEFAULT_MIN_CURVATURE):
        """From principal curvatures (1/m, convex positive) of wheel (w) and rail (r) in x and y; ``ValueError`` for
        materials outside the elastic range (:func:`effective_modulus`)."""
        return cls(0.5 * (k_wx + k_rx), 0.5 * (k_wy + k_ry),
                   effective_modulus(E_wheel, nu_wheel, E_rail, nu_rail), min_curvature)

    @property
    def clamped(self) -> bool:
        """True if A or B was floored at ``min_curvature``."""
        return bool(self.status & (STATUS_CLAMPED_A | STATUS_CLAMPED_B))

    @property
    def theta(self) -> float:
        """Auxiliary angle θ in rad, cos θ = |B − A| / (A + B)."""
        return math.acos(abs(self.B - self.A) / (self.A + self.B))

    def force(self, delta):
        """Normal force N = Kh·δ^1.5 (N); zero for δ <= 0."""
        d = np.maximum(np.asarray(delta, dtype=float), 0.0)
        return self.Kh * d * np.sqrt(d)

    def stiffness(self, delta):
        """Tangent stiffness dN/dδ = 1.5·Kh·δ^0.5 (N/m); zero for δ <= 0."""
        return 1.5 * self.Kh * np.sqrt(np.maximum(np.asarray(delta, dtype=float), 0.0))

    def penetration(self, N):
        """Approach δ = (N/Kh)^(2/3) (m); zero for N <= 0."""
        return np.cbrt(np.square(np.maximum(np.asarray(N, dtype=float), 0.0) / self.Kh))

    def semi_axes(self, N):
        """Semi-axes ``(a, b)`` in m along x (rolling) and y (lateral) for normal force N."""
        c0 = np.cbrt(0.75 * np.maximum(np.asarray(N, dtype=float), 0.0) / (self.E_star * (self.A + self.B)))
        return self.m_x * c0, self.m_y * c0

    def max_pressure(self, N):
        """Peak Hertz pressure p0 = 3N/(2πab) (Pa); zero for N <= 0."""
        N = np.maximum(np.asarray(N, dtype=float), 0.0)
        a, b = self.semi_axes(N)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(N > 0.0, 1.5 * N / (np.pi * a * b), 0.0)
