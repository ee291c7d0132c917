"""Cheap (closed-form) creep-force laws: Shen–Hedrick–Elkins and Polach.

Contract (the same as :func:`exudyn_wheelrail.creep.fastsim.fastsim`)::

    law(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, **options) -> (Fx, Fy, Mz)

in N and N·m, forces **on the wheel**, in the contact frame, ``a`` [m] the semi-axis along rolling, ``b`` [m]
lateral, ``c = √(ab)``, creepages ξ, η [-] and spin φ [1/m] with Kalker's signs: for small creepage both laws give
Kalker's linear theory (:func:`exudyn_wheelrail.creep.linear.linear_creep_forces`)::

    Fx = -G c² C11 ξ,   Fy = -G c² (C22 η + c C23 φ),   Mz = G c³ (C23 η - c C33* φ)

C11, C22, C23 are Kalker's linear coefficients (Kalker 1990, Table E.3, via
:func:`~exudyn_wheelrail.creep.linear.kalker_coefficients`; hence ``0.1 <= a/b <= 10`` and ``0 <= ν <= 0.5``).
The table has **no C33**: as in :mod:`~exudyn_wheelrail.creep.linear`, the spin term of Mz uses the
simplified-theory coefficient ``C33* = 32/(15π) C23 (b/a)^{3/2}``
(:func:`~exudyn_wheelrail.creep.linear.fastsim_spin_moment_coefficient`), not Kalker's exact C33.  Neither
Shen–Hedrick–Elkins nor Polach defines a spin moment; the choice made here for **both** laws is stated below
(linear Kalker Mz times the law's own saturation ratio "saturated resultant / linear resultant").

Notation below: ``μN`` = friction coefficient × normal force (the Coulomb bound), ``G`` shear modulus.

1. Shen–Hedrick–Elkins (SHE)
----------------------------
Z.Y. Shen, J.K. Hedrick, J.A. Elkins, "A comparison of alternative creep force models for rail vehicle dynamic
analysis", Proc. 8th IAVSD Symposium (1983): Kalker's linear forces saturated by the Johnson–Vermeulen cubic as
modified by the authors::

    (S1)  Fx_lin = -G c² C11 ξ,   Fy_lin = -G c² (C22 η + c C23 φ),   F_lin = √(Fx_lin² + Fy_lin²)
    (S2)  β = F_lin / (μN)
    (S3)  F_res = μN (β - β²/3 + β³/27) = μN [1 - (1 - β/3)³]     for β <= 3
          F_res = μN                                               for β >  3
    (S4)  ε = F_res / F_lin = 1 - β/3 + β²/27  (β <= 3),   μN / F_lin  (β > 3)      (ε -> 1 for β -> 0)
    (S5)  Fx = ε Fx_lin,   Fy = ε Fy_lin
    (S6)  Mz = ε Mz_lin,   Mz_lin = G c³ (C23 η - c C33* φ)         [choice made here, see below]

The cubic reaches μN with zero slope and zero curvature at β = 3 (C² there), and ``|F| = F_res <= μN`` always.
Spin moment (S6): SHE give forces only; scaling the linear Kalker moment by the same factor ε is the choice made
here.  Caveat: when the linear lateral force cancels (``ξ = 0`` and ``C22 η + c C23 φ = 0``) then β = 0, ε = 1 and
Mz stays linear (unsaturated) however large η and φ are.  Also (known SHE behaviour) pure large spin saturates
``|Fy| -> μN``, whereas in Kalker's exact theory the spin-induced lateral force decreases again at large spin.

2. Polach
---------
O. Polach, "A fast wheel–rail forces calculation computer code", Vehicle System Dynamics 33 Suppl. (2000) 728–739
(spin; FORTRAN listing), and O. Polach, "Creep forces in simulations of traction vehicles running on adhesion
limit", Wear 258 (2005) 992–1000 (reduction factors).  Polach's forces point along the creepage; the signs below are
already those of this package (force on the wheel, opposite to the creepage)::

    (P1)  s_yC = η + φ a   if |η + φ a| > |η|,   else  s_yC = η        (effective lateral creepage with spin)
    (P2)  s = √(ξ² + η²),   s_C = √(ξ² + s_yC²)
    (P3)  c_jj = √((C11 ξ/s)² + (C22 η/s)²)                            (Kalker-weighted coefficient; Polach's
          C = 3G c_jj/(8a) in ε = (2/3) C π a² b s /(Qμ), Polach 2005 Eq. (3))
    (P4)  ε = π G a b c_jj s_C / (4 μN)
    (P5)  F = (2 μN/π) [ k_A ε/(1 + (k_A ε)²) + arctan(k_S ε) ]      (Polach 2005: Eq. (2) is the case
                                                                      k_A = k_S = 1 = Polach 2000)
    (P6)  Fx = -F ξ/s_C,   Fy = -F η/s_C - F_yS
    (P7)  k_M = 1 + 6.3 (1 - exp(-a/b)),   ε_M = (8/3) G b √(ab) C23 s_C / (μN k_M)
          δ = (ε_M² - 1)/(ε_M² + 1),   K_M = |ε_M| (δ³/3 - δ²/2 + 1/6) - (1/3) √((1 - δ²)³)
          F_yS = -(9/16) a μN K_M k_M φ / s_C                        (Polach 2000, spin section)
    (P8)  Mz = κ Mz_lin,  κ = F(ε_C) / (4 μN ε_C/π),
          ε_C = π G a b √((C11 ξ)² + (C22 s_yC)²) / (4 μN)           [choice made here, see below]

    (P9)  if |(Fx, Fy)| > μN: (Fx, Fy) scaled radially onto μN           [safeguard added here, see below]

Q = N is the wheel load in Polach's notation.  In (P4)–(P6) the resultant creepage ``s`` of the spin-free law is
replaced by ``s_C`` when there is spin, and the force components are split along ``(ξ, η)/s_C`` (the structure of
Polach's 2000 FORTRAN listing); without spin ``s_C = s`` and this is Polach's original law ``Fx = -F ξ/s``,
``Fy = -F η/s``.  If ``s = 0`` (pure spin) the translational part is zero and only F_yS remains.  ε_M is built on
``s_C`` (Polach's spin formula): only then is the linear limit of F_yS independent of ξ (below).  Source note: the
original paper was not at hand; the formulas were checked against a third-party transcription of the listing,
which has two evident slips that are *not* followed here (the s_yC condition inverted — it would give zero force
for pure spin — and ``|s_yC|`` instead of ``s_C`` in ε_M).

Closed form of the spin term (algebra, no approximation): with ``1 - δ = 2/(1+ε_M²)`` and
``1 - δ² = 4ε_M²/(1+ε_M²)²`` one finds ``K_M = -(2/3) |ε_M| / (1 + ε_M²)²``, hence::

    F_yS = G c³ C23 φ / (1 + ε_M²)²                                   (what the code evaluates)

so in the linear limit (ε_M -> 0) Polach's spin term is **exactly Kalker's** ``G c³ C23 φ`` (the geometric factor
k_M cancels), for any ξ.  The linear limits of (P5)/(P6) are ``Fx = -((k_A + k_S)/2) G c² c_jj ξ`` and
``Fy = -((k_A + k_S)/2) G c² c_jj η - G c³ C23 φ``: Kalker's C11 (pure ξ) and C22 (pure η) when k_A = k_S = 1.
For combined ξ and η the magnitude uses the weighted c_jj (P3), so the forces are not linearly superposable there
(Polach's construction: the force is along the creepage).

Reduction factors (Polach 2005): ``0 < k_S <= k_A <= 1``; the defaults ``k_A = k_S = 1`` are Polach's original law
with Kalker's coefficients.  Values below 1 model a contaminated (wet, oily, leaves …) contact — a lower initial
slope (k_A) and a lower slope in the slip area (k_S); Polach 2005 identifies them from measurements.  Here they act
on the creep force (P5) only; the spin term F_yS (P7) is Polach 2000's, unreduced.  ``k_S <= k_A`` keeps
``F < μN`` (the limit is approached from below).  Because the reductions lower the translational force but not
F_yS, with ``k < 1`` and spin opposite to the lateral creepage (``s_yC = η``, F_yS opposing ``F η/s_C``) the sum
(P6) can exceed the Coulomb bound (found up to 1.3 μN for k_S ≈ 0.06, a/b ≈ 3); (P9) scales (Fx, Fy) back onto
μN there.  (P9) is not part of Polach's method; with ``k_A = k_S = 1`` it was never active in 3·10⁵ random cases
over the whole a/b and ν range (largest |F|/μN = 1 + 4e-16, round-off) nor in a numerical maximisation.
Polach 2005's slip-velocity-dependent friction coefficient ``μ = μ0 [(1 - A) e^{-B w} + A]`` is not included: pass
the friction coefficient you want as ``mu``.

Spin moment (P8): Polach gives Fx, Fy only.  Same choice as for SHE: the linear Kalker moment times the law's
ratio "saturated / linear" resultant, here Polach's ``F(ε)/(4 μN ε/π)`` (-> (k_A + k_S)/2 for ε -> 0).  Its
argument ε_C is Polach's ε with c_jj weighted along the effective creepage ``(ξ, s_yC)`` instead of ``(ξ, η)``
(identical to ε for φ = 0); unlike ε it is defined and continuous also at ``ξ = η = 0`` with spin.

Limitation of the spin moments (S6) and (P8) (left as specified, not corrected): no theory bounds them by the
Coulomb limit of a moment, ``|Mz| <= μ ∫∫ p_Hertz r dA = (3/8) μN max(a, b) E(m)``, ``m = 1 - (min/max)²``
(E the complete elliptic integral of the second kind; the full-slip pure-spin moment).  Measured for pure spin
swept up to full slip (ν = 0.28): max |Mz| / bound = 17.8 (SHE), 11.1 (Polach) at a/b = 0.1; 3.0 / 1.3 at a/b = 0.5;
1.15 / 0.46 at a/b = 1; below 0.4 for a/b >= 2.  On the SHE cancellation line (above) Mz is unbounded.  And for
pure η the scaled moment tends to ``(C23/C22) μN c`` in full slip (0.31 / 0.40 / 0.53 μN c at a/b = 0.5 / 1 / 2),
where the exact theory and FASTSIM give Mz -> 0 (uniform slip direction, symmetric Hertz traction).

Both laws: ``normal_force == 0`` or ``mu == 0`` gives zero forces.  The compiled cores :func:`she_core`,
:func:`polach_core` take plain floats (including the coefficients) and do no checks; the wrappers
:func:`shen_hedrick_elkins`, :func:`polach` validate the input like :func:`~exudyn_wheelrail.creep.fastsim.fastsim`
and raise ``ValueError``.
"""
from __future__ import annotations

import math


from ..jit import compiled
from .linear import fastsim_spin_moment_coefficient, kalker_coefficients
from ._inputs import check_contact_inputs, finite as _finite

__all__ = ["shen_hedrick_elkins", "she_core", "polach", "polach_core"]

_PI = math.pi


@compiled(refcount=False)
def she_core(a, b, xi, eta, phi, normal_force, mu, shear_modulus, C11, C22, C23, C33):
    """Compiled Shen–Hedrick–Elkins law on floats (no input checks): ``(Fx, Fy, Mz)`` on the wheel.

    ``C11, C22, C23`` Kalker's linear coefficients, ``C33`` the spin-moment coefficient (the wrapper passes
    the simplified-theory C33*).  ``normal_force <= 0`` or ``mu <= 0`` gives zeros.  Formulas (S1)–(S6) of the
    module docstring."""
    if normal_force <= 0.0 or mu <= 0.0:
        return 0.0, 0.0, 0.0
    c = math.sqrt(a * b)
    gc2 = shear_modulus * c * c
    fx = -gc2 * C11 * xi
    fy = -gc2 * (C22 * eta + c * C23 * phi)
    mz = gc2 * c * (C23 * eta - c * C33 * phi)
    mu_n = mu * normal_force
    f_lin = math.hypot(fx, fy)
    beta = f_lin / mu_n
    if beta < 3.0:
        eps = 1.0 - beta / 3.0 + beta * beta / 27.0      # [1 - (1 - β/3)³]/β, no division
    else:
        eps = mu_n / f_lin
    return eps * fx, eps * fy, eps * mz


@compiled(refcount=False)
def _x_over_1px2(x):
    """x/(1 + x²) for x >= 0 without overflow of x²."""
    if x <= 1.0:
        return x / (1.0 + x * x)
    return 1.0 / (x + 1.0 / x)


@compiled(refcount=False)
def _polach_ratio(eps, k_a, k_s):
    """Polach's saturated / linear resultant: [k_A ε/(1+(k_A ε)²) + arctan(k_S ε)] / (2ε); (k_A+k_S)/2 at ε=0."""
    if eps < 1e-150:
        return 0.5 * (k_a + k_s)
    return (_x_over_1px2(k_a * eps) + math.atan(k_s * eps)) / (2.0 * eps)


@compiled(refcount=False)
def polach_core(a, b, xi, eta, phi, normal_force, mu, shear_modulus, C11, C22, C23, C33, k_a=1.0, k_s=1.0):
    """Compiled Polach law on floats (no input checks): ``(Fx, Fy, Mz)`` on the wheel.

    ``C11, C22, C23`` Kalker's linear coefficients, ``C33`` the spin-moment coefficient (the wrapper passes the
    simplified-theory C33*), ``k_a``, ``k_s`` Polach's (2005) reduction factors (1.0: Polach 2000).
    ``normal_force <= 0`` or ``mu <= 0`` gives zeros.  Formulas (P1)–(P9) of the module docstring."""
    if normal_force <= 0.0 or mu <= 0.0:
        return 0.0, 0.0, 0.0
    mu_n = mu * normal_force
    G = shear_modulus
    c = math.sqrt(a * b)
    # (P1), (P2)
    s_yc = eta + phi * a
    if not abs(s_yc) > abs(eta):
        s_yc = eta
    s_c = math.hypot(xi, s_yc)
    if s_c == 0.0:
        return 0.0, 0.0, 0.0
    s = math.hypot(xi, eta)
    gab = G * a * b
    # (P3)-(P6): translational creep force
    fx = 0.0
    fy = 0.0
    if s > 0.0:
        c_jj = math.hypot(C11 * xi / s, C22 * eta / s)
        eps = _PI * gab * c_jj * s_c / (4.0 * mu_n)
        F = 2.0 * mu_n / _PI * (_x_over_1px2(k_a * eps) + math.atan(k_s * eps))
        fx = -F * xi / s_c
        fy = -F * eta / s_c
    # (P7) lateral spin force, closed form F_yS = G c³ C23 φ / (1 + ε_M²)²
    k_m = 1.0 + 6.3 * (1.0 - math.exp(-a / b))
    eps_m = 8.0 / 3.0 * G * b * c * C23 * s_c / (mu_n * k_m)
    if eps_m < 1e150:
        d = 1.0 + eps_m * eps_m
        fy -= gab * c * C23 * phi / (d * d)
    # (P9) Coulomb safeguard (not Polach's): only reduction factors < 1 with spin can push |F| above muN
    f_res = math.hypot(fx, fy)
    if f_res > mu_n:
        fx *= mu_n / f_res
        fy *= mu_n / f_res
    # (P8) spin moment: linear Kalker moment times Polach's saturation ratio at the effective creepage
    eps_c = _PI * gab * math.hypot(C11 * xi, C22 * s_yc) / (4.0 * mu_n)
    mz = _polach_ratio(eps_c, k_a, k_s) * gab * c * (C23 * eta - c * C33 * phi)
    return fx, fy, mz


def _check_common(a, b, xi, eta, phi, normal_force, mu, shear_modulus):
    return check_contact_inputs(a, b, xi, eta, phi, normal_force, mu, shear_modulus)


def _coefficients(a, b, poisson, nu_interpolation):
    """(C11, C22, C23, C33*) from Table E.3 (ValueError outside 0.1 <= a/b <= 10, 0 <= ν <= 0.5)."""
    C11, C22, C23 = kalker_coefficients(a / b, poisson, nu_interpolation)
    C33 = fastsim_spin_moment_coefficient(a / b, poisson, nu_interpolation)
    return C11, C22, C23, C33


def shen_hedrick_elkins(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson,
                        nu_interpolation: str = "quadratic"):
    """Creep forces by the Shen–Hedrick–Elkins law (1983): ``(Fx, Fy, Mz)`` in N and N·m, forces **on the wheel**
    in the contact frame; ``a`` [m] semi-axis along rolling, ``b`` [m] lateral, creepages ξ, η [-], spin φ [1/m].

    Kalker's linear forces (Table E.3 coefficients at ``a/b``, ``poisson``) scaled by
    ``ε = F_res/F_lin``, ``F_res = μN[1 - (1 - β/3)³]`` for ``β = F_lin/(μN) <= 3``, ``μN`` above; Mz = linear
    Kalker moment (spin term with the simplified-theory C33*, Table E.3 has no C33) times the same ε.  See the
    module docstring, formulas (S1)–(S6).

    Raises ``ValueError`` for a, b <= 0, N < 0, μ < 0, G <= 0, non-finite inputs, ``a/b`` outside [0.1, 10] or
    ν outside [0, 0.5].  ``normal_force == 0`` or ``mu == 0`` gives zero forces."""
    a, b, xi, eta, phi, N, mu, G = _check_common(a, b, xi, eta, phi, normal_force, mu, shear_modulus)
    C11, C22, C23, C33 = _coefficients(a, b, poisson, nu_interpolation)
    return she_core(a, b, xi, eta, phi, N, mu, G, C11, C22, C23, C33)


def polach(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, k_a: float = 1.0, k_s: float = 1.0,
           nu_interpolation: str = "quadratic"):
    """Creep forces by Polach's method (2000, with spin; reduction factors of 2005): ``(Fx, Fy, Mz)`` in N and
    N·m, forces **on the wheel** in the contact frame; ``a`` [m] semi-axis along rolling, ``b`` [m] lateral,
    creepages ξ, η [-], spin φ [1/m].

    ``F = (2μN/π)[k_A ε/(1+(k_A ε)²) + arctan(k_S ε)]`` along the creepage, plus Polach's lateral spin force
    ``F_yS = G c³ C23 φ/(1+ε_M²)²`` (closed form of Polach's K_M expression); Mz = linear Kalker moment times
    Polach's saturation ratio; ``|(Fx, Fy)| <= μN`` enforced by a radial safeguard (only ever active with
    reduction factors < 1 and spin).  Exact formulas (P1)–(P9) in the module docstring.

    ``k_a``, ``k_s``: Polach's (2005) reduction factors, ``0 < k_s <= k_a <= 1``; the defaults 1.0 give Polach's
    original law with Kalker's coefficients, values < 1 model a contaminated contact (Polach 2005).

    Raises ``ValueError`` for a, b <= 0, N < 0, μ < 0, G <= 0, non-finite inputs, ``a/b`` outside [0.1, 10],
    ν outside [0, 0.5], or reduction factors outside ``0 < k_s <= k_a <= 1``.  ``normal_force == 0`` or
    ``mu == 0`` gives zero forces."""
    a, b, xi, eta, phi, N, mu, G = _check_common(a, b, xi, eta, phi, normal_force, mu, shear_modulus)
    k_a = _finite("k_a", k_a)
    k_s = _finite("k_s", k_s)
    if not (0.0 < k_s <= k_a <= 1.0):
        raise ValueError(f"Polach's reduction factors must satisfy 0 < k_s <= k_a <= 1 (Polach 2005), "
                         f"got k_a={k_a}, k_s={k_s}")
    C11, C22, C23, C33 = _coefficients(a, b, poisson, nu_interpolation)
    return polach_core(a, b, xi, eta, phi, N, mu, G, C11, C22, C23, C33, k_a, k_s)
