"""FASTSIM: Kalker's algorithm for the simplified theory of rolling contact.

Reference: J.J. Kalker, "A fast algorithm for the simplified theory of rolling contact", Vehicle System
Dynamics 11 (1982) 1–13; flexibilities from the linear-theory coefficients of Kalker 1990, Table E.3
(:mod:`exudyn_wheelrail.creep.linear`).

Model (steady rolling, ``a`` along rolling, material enters the ellipse at the leading edge ``x = +a(y)``)
-------------------------------------------------------------------------------------------------------
Simplified theory: the elastic displacement difference is ``u = L p`` with one flexibility per creepage term
(three-flexibility variant): ``L1 = 8a/(3 C11 G)`` for ξ, ``L2 = 8a/(3 C22 G)`` for η and
``L3 = π a √(a/b)/(4 C23 G)`` for φ.  In the stick area the traction grows along each strip as

    ∂p_x/∂x = (ξ - φ y)/L1-or-L3 ,   ∂p_y/∂x = η/L2 + φ x/L3      (p = 0 at the leading edge),

precisely ``p_x = -(a(y)-x)(ξ/L1 - φ y/L3)``, ``p_y = -(a(y)-x) η/L2 + (x² - a(y)²) φ/(2 L3)``.
Integrating over the ellipse in full adhesion (``∫∫(a(y)-x) dA = 8a²b/3``, ``∫∫(a(y)²-x²)/2 dA = πa³b/4``):

    Fx = -(8a²b/(3L1)) ξ = -G c² C11 ξ,   Fy = -(8a²b/(3L2)) η - (πa³b/(4L3)) φ = -G c² (C22 η + c C23 φ),

which is how L1, L2, L3 are fixed (Kalker's signs: forces on the wheel).  The traction bound is the
simplified theory's **parabolic** pressure, ``|p| <= μ p_z``, ``p_z = 2N/(πab)·(1 - (x/a)² - (y/b)²)`` (it carries
N: ``∫∫ p_z dA = N``; Kalker 1982 uses the parabolic, not the Hertzian ellipsoidal, distribution because it makes
the simplified theory's total forces agree best with the exact theory at saturation).  Where the trial
traction exceeds the bound it is scaled back onto it (FASTSIM's slip rule).

Discretisation: ``n_y`` strips of equal width (midpoint rule in y), each strip divided into ``n_x`` equal
elements over its own length ``2a(y)``.  Tractions and the bound are evaluated at the element **centres**; the
stick increment between consecutive centres is the exact integral of the traction slope (so in full adhesion the
tractions are exact), and forces/moment are the midpoint sums.  (At the nodes the trailing edge's bound is zero,
which gives a 1/n error; the centres avoid it.)  Full-adhesion error O(1/n_x²), O(1/n_y²); with spin and partial
slip the slip-area update converges at first order in 1/n_x, hence the default n_x > n_y.

Mz = ∫∫ (x p_y - y p_x) dA (about the contact centre, positive about +z).  Caveat: with separate flexibilities
FASTSIM's Mz/η slope is ``G c³ C23 · L3/L2`` rather than Kalker's ``G c³ C23``, and its Mz/φ slope is
``-G c⁴ C33*`` with the simplified-theory ``C33*`` (see
:func:`exudyn_wheelrail.creep.linear.fastsim_spin_moment_coefficient`), not Kalker's exact C33.
"""
from __future__ import annotations

import math


from ..jit import compiled
from .linear import kalker_coefficients
from ._inputs import check_contact_inputs

__all__ = ["DEFAULT_NX", "DEFAULT_NY", "fastsim", "fastsim_core", "fastsim_flexibilities"]

#: Default number of elements along each strip (rolling direction) and of strips (lateral).  n_x > n_y because
#: with spin the slip-area update converges at first order in 1/n_x, the strips at second order in 1/n_y.
DEFAULT_NX = 48
DEFAULT_NY = 16


@compiled(refcount=False)
def fastsim_flexibilities(a, b, shear_modulus, C11, C22, C23):
    """``(L1, L2, L3)`` of the simplified theory [m/Pa]: ``8a/(3 C11 G)``, ``8a/(3 C22 G)``,
    ``π a √(a/b)/(4 C23 G)``."""
    L1 = 8.0 * a / (3.0 * C11 * shear_modulus)
    L2 = 8.0 * a / (3.0 * C22 * shear_modulus)
    L3 = math.pi * a * math.sqrt(a / b) / (4.0 * C23 * shear_modulus)
    return L1, L2, L3


@compiled(refcount=False)
def fastsim_core(a, b, xi, eta, phi, normal_force, mu, shear_modulus, C11, C22, C23, n_x, n_y, weighted=0):
    """Compiled FASTSIM on floats (no input checks): returns ``(Fx, Fy, Mz)`` on the wheel.

    ``weighted`` 0: three flexibilities L1, L2, L3; 1: Kalker's single weighted flexibility (see
    :func:`fastsim`).  ``normal_force <= 0`` or ``mu <= 0`` gives zeros.  ``n_x``, ``n_y`` >= 1."""
    if normal_force <= 0.0 or mu <= 0.0:
        return 0.0, 0.0, 0.0
    L1, L2, L3 = fastsim_flexibilities(a, b, shear_modulus, C11, C22, C23)
    if weighted != 0:
        c = math.sqrt(a * b)
        den = math.sqrt(xi * xi + eta * eta + c * c * phi * phi)
        if den == 0.0:
            return 0.0, 0.0, 0.0
        L = (abs(xi) * L1 + abs(eta) * L2 + c * abs(phi) * L3) / den
        L1 = L
        L2 = L
        L3 = L
    gx0 = xi / L1          # slope of p_x per unit x from ξ
    gs = phi / L3          # spin slope factor
    gy0 = eta / L2
    mu_p0 = mu * 2.0 * normal_force / (math.pi * a * b)   # μ × peak pressure
    inv_a2 = 1.0 / (a * a)
    dy = 2.0 * b / n_y
    Fx = 0.0
    Fy = 0.0
    Mz = 0.0
    for j in range(n_y):
        y = -b + (j + 0.5) * dy
        r = 1.0 - (y / b) * (y / b)
        if r <= 0.0:
            continue
        ay = a * math.sqrt(r)
        dx = 2.0 * ay / n_x
        wx = gx0 - gs * y
        px = 0.0          # traction at the previous element centre (0 before the leading edge)
        py = 0.0
        x_prev = ay       # the leading edge
        sx = 0.0
        sy = 0.0
        sm = 0.0
        for i in range(n_x):
            x = ay - (i + 0.5) * dx          # element centre
            step = x_prev - x                # dx/2 for the first element, dx after
            qx = px - step * wx
            qy = py - step * (gy0 + gs * 0.5 * (x_prev + x))   # exact integral of η/L2 + φx/L3 over the step
            bound = mu_p0 * (ay * ay - x * x) * inv_a2
            mag2 = qx * qx + qy * qy
            if mag2 > bound * bound:
                f = bound / math.sqrt(mag2)
                qx *= f
                qy *= f
            sx += qx
            sy += qy
            sm += x * qy - y * qx
            px = qx
            py = qy
            x_prev = x
        Fx += sx * dx * dy
        Fy += sy * dx * dy
        Mz += sm * dx * dy
    return Fx, Fy, Mz



def fastsim(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, n_x: int = DEFAULT_NX,
            n_y: int = DEFAULT_NY, nu_interpolation: str = "quadratic", flexibility: str = "three"):
    """Creep forces by Kalker's FASTSIM: ``(Fx, Fy, Mz)`` in N and N·m, forces **on the wheel**, in the contact
    frame, ``a`` [m] the semi-axis along rolling, ``b`` [m] lateral, creepages ξ, η [-] and φ [1/m] with the
    Kalker's signs (small creepage: ``Fx = -G c² C11 ξ``, ``Fy = -G c² (C22 η + c C23 φ)``).

    C11, C22, C23 come from Kalker's Table E.3 at ``a/b`` and ``poisson`` (so ``0.1 <= a/b <= 10`` and
    ``0 <= ν <= 0.5``, else ``ValueError``).  Raises ``ValueError`` for a, b <= 0, N < 0, μ < 0, G <= 0,
    non-finite inputs, or n_x, n_y < 1.  ``normal_force == 0`` (or μ == 0) gives zero forces.

    ``flexibility="three"`` (default): separate L1, L2, L3 — the forces are exactly linear-superposable at small
    creepage and reproduce C11, C22, C23 also for combined creepages, but in full sliding the force direction
    follows ``(ξ/L1, η/L2)`` rather than ``(ξ, η)`` (an angle error where C11 != C22, i.e. ν > 0).
    ``flexibility="weighted"``: Kalker's (1982) single flexibility
    ``L = (|ξ| L1 + |η| L2 + c |φ| L3)/√(ξ² + η² + c² φ²)`` — exact slopes for each pure creepage and a full-slip
    force opposite to the creepage, but not linear for combined creepages."""
    a, b, xi, eta, phi, N, mu, G = check_contact_inputs(a, b, xi, eta, phi, normal_force, mu, shear_modulus)
    if int(n_x) != n_x or int(n_y) != n_y or n_x < 1 or n_y < 1:
        raise ValueError(f"n_x and n_y must be integers >= 1, got {n_x}, {n_y}")
    if flexibility not in ("three", "weighted"):
        raise ValueError(f"flexibility must be 'three' or 'weighted', got {flexibility!r}")
    C11, C22, C23 = kalker_coefficients(a / b, poisson, nu_interpolation)
    return fastsim_core(a, b, xi, eta, phi, N, mu, G, C11, C22, C23, int(n_x), int(n_y),
                        1 if flexibility == "weighted" else 0)
