r"""The 3-D two-node Euler–Bernoulli beam element shared by the bridge deck (:mod:`.bridge`), the flexible car body
(:mod:`exudyn_wheelrail.rolling_stock.car_body_model`) and the flexible track (:mod:`exudyn_wheelrail.track.flexible`,
:mod:`exudyn_wheelrail.track.flexible_deck`): the cross-section (:class:`DeckSection`), the nodal degrees of freedom,
the cubic Hermite shape functions and the element matrices.

Nodal degrees of freedom, 6 per node, in the beam's frame (x along the axis, y right, z **down**):
``(u, v, w, θx, θy, θz)`` — displacements along x, y, z and small rotations about x, y, z (right-hand rule).

* vertical bending (in the x–z plane, stiffness ``EI_y``): ``w(x)``, with ``dw/dx = -θy`` (a positive rotation
  about +y turns +x towards -z);
* lateral bending (x–y plane, ``EI_z``): ``v(x)``, with ``dv/dx = +θz``;
* torsion (``GJ``, mass moment of inertia per length ``I_p``): ``θx(x)``; axial (``EA``): ``u(x)``.

Element (:func:`element_matrices`): consistent mass ``m`` for the three translations — bending by the Hermite
cubics, axial by the linear functions — and ``I_p`` for torsion; bending rotary inertia neglected, as in
Euler–Bernoulli theory; matrices integrated by 4-point Gauss quadrature (exact).  :func:`bending_element` is the
same bending element in one plane in closed form (DOFs ``(u1, du1/dx, u2, du2/dx)``), the rails' of the flexible
track.

Reference: J. S. Przemieniecki, *Theory of matrix structural analysis*, 1968 (3-D beam element).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .checks import checked_number

__all__ = ["DOF_NAMES", "N_DOF_NODE", "DOF_GROUPS", "DeckSection", "hermite", "LAT_IDX", "LAT_SIGN", "VER_IDX",
           "VER_SIGN", "AX_IDX", "TOR_IDX", "element_matrices", "bending_element"]

#: nodal degrees of freedom, in this order
DOF_NAMES = ("u", "v", "w", "theta_x", "theta_y", "theta_z")
N_DOF_NODE = 6
#: DOF groups (mode kinds): vertical = (w, θy), lateral = (v, θz), torsion = θx, axial = u
DOF_GROUPS = {"axial": (0,), "lateral": (1, 5), "vertical": (2, 4), "torsion": (3,)}


# --------------------------------------------------------------------------------------------------- section
@dataclass(frozen=True)
class DeckSection:
    """Cross-section of the deck (the beam axis is shear centre and centre of mass), SI units.

    m_kg_m : mass per length [kg/m] (deck, ballast/slab and track).
    EI_y_Nm2 : vertical bending stiffness (bending in the x–z plane, about the y axis) [N m²].
    EI_z_Nm2 : lateral bending stiffness (x–y plane, about z) [N m²].
    GJ_Nm2 : torsional stiffness (St Venant) [N m²].
    EA_N : axial stiffness [N].
    Ip_kgm2_m : mass moment of inertia per length about the beam axis [kg m²/m] (torsional inertia).
    """

    m_kg_m: float
    EI_y_Nm2: float
    EI_z_Nm2: float
    GJ_Nm2: float
    EA_N: float
    Ip_kgm2_m: float

    def __post_init__(self):
        for f in ("m_kg_m", "EI_y_Nm2", "EI_z_Nm2", "GJ_Nm2", "EA_N", "Ip_kgm2_m"):
            object.__setattr__(self, f, checked_number(f"DeckSection.{f}", getattr(self, f), positive=True))

    @classmethod
    def bending_only(cls, m_kg_m: float, EI_y_Nm2: float, EI_z_Nm2: float) -> "DeckSection":
        """A section known only by its mass and bending stiffnesses (a deck given by its frequencies): the
        torsional (``GJ = EI_y``, ``I_p = m (2 m)²``) and axial (``EA = 1e3 EI_y / m²``) values are placeholders of
        the right order that act on no bending mode (the beam axis is shear centre and centre of mass)."""
        return cls(m_kg_m=m_kg_m, EI_y_Nm2=EI_y_Nm2, EI_z_Nm2=EI_z_Nm2, GJ_Nm2=EI_y_Nm2, EA_N=1e3 * EI_y_Nm2,
                   Ip_kgm2_m=m_kg_m * 4.0)

    # analytic references for a simply supported span of length L (Euler–Bernoulli, St Venant torsion)
    def vertical_frequency_Hz(self, L_m: float, n: int = 1) -> float:
        """``f_n = n²π/(2L²) √(EI_y/m)`` of a simply supported span."""
        L = checked_number("L_m", L_m, positive=True)
        return n * n * math.pi / (2.0 * L * L) * math.sqrt(self.EI_y_Nm2 / self.m_kg_m)

    def lateral_frequency_Hz(self, L_m: float, n: int = 1) -> float:
        """``f_n = n²π/(2L²) √(EI_z/m)`` of a simply supported span."""
        L = checked_number("L_m", L_m, positive=True)
        return n * n * math.pi / (2.0 * L * L) * math.sqrt(self.EI_z_Nm2 / self.m_kg_m)

    def torsion_frequency_Hz(self, L_m: float, n: int = 1) -> float:
        """``f_n = n/(2L) √(GJ/I_p)`` of a span with torsion fixed at both ends."""
        L = checked_number("L_m", L_m, positive=True)
        return n / (2.0 * L) * math.sqrt(self.GJ_Nm2 / self.Ip_kgm2_m)


# -------------------------------------------------------------------------------------------- shape functions
def hermite(xi, Le):
    """Cubic Hermite functions on [0, 1] for (value_a, slope_a, value_b, slope_b), their x-derivatives and second
    x-derivatives at ξ (a number: each (4,); an array of n: each (n, 4)) of an element of length ``Le``."""
    if np.ndim(xi):                   # an array of ξ; a number stays a Python or numpy scalar (scalar arithmetic)
        xi = np.asarray(xi, dtype=float)
    N = np.stack([1 - 3 * xi ** 2 + 2 * xi ** 3, Le * (xi - 2 * xi ** 2 + xi ** 3), 3 * xi ** 2 - 2 * xi ** 3,
                  Le * (-xi ** 2 + xi ** 3)], axis=-1)
    dN = np.stack([(-6 * xi + 6 * xi ** 2) / Le, 1 - 4 * xi + 3 * xi ** 2, (6 * xi - 6 * xi ** 2) / Le,
                   -2 * xi + 3 * xi ** 2], axis=-1)
    ddN = np.stack([(-6 + 12 * xi) / Le ** 2, (-4 + 6 * xi) / Le, (6 - 12 * xi) / Le ** 2, (-2 + 6 * xi) / Le],
                   axis=-1)
    return N, dN, ddN


# element DOF indices (12 = 2 nodes × 6) and the sign that maps the nodal DOF to the slope of the Hermite cubic
LAT_IDX = np.array([1, 5, 7, 11])          # v_a, θz_a, v_b, θz_b        (dv/dx = +θz)
LAT_SIGN = np.array([1.0, 1.0, 1.0, 1.0])
VER_IDX = np.array([2, 4, 8, 10])          # w_a, θy_a, w_b, θy_b        (dw/dx = -θy)
VER_SIGN = np.array([1.0, -1.0, 1.0, -1.0])
AX_IDX = np.array([0, 6])
TOR_IDX = np.array([3, 9])


def element_matrices(Le: float, section: DeckSection) -> tuple[np.ndarray, np.ndarray]:
    """Consistent mass and stiffness matrices (12 × 12, DOFs ``u, v, w, θx, θy, θz`` of node a then b) of a
    3-D Euler–Bernoulli element of length ``Le``, by 4-point Gauss quadrature of the shape functions."""
    gp, gw = np.polynomial.legendre.leggauss(4)
    xs = 0.5 * (gp + 1.0)
    ws = 0.5 * gw * Le
    Me = np.zeros((12, 12))
    Ke = np.zeros((12, 12))
    for xi, w in zip(xs, ws):
        N, _, ddN = hermite(xi, Le)
        L = np.array([1.0 - xi, xi])
        dL = np.array([-1.0, 1.0]) / Le
        for idx, sign, EI in ((LAT_IDX, LAT_SIGN, section.EI_z_Nm2), (VER_IDX, VER_SIGN, section.EI_y_Nm2)):
            n = N * sign
            b = ddN * sign
            Me[np.ix_(idx, idx)] += w * section.m_kg_m * np.outer(n, n)
            Ke[np.ix_(idx, idx)] += w * EI * np.outer(b, b)
        Me[np.ix_(AX_IDX, AX_IDX)] += w * section.m_kg_m * np.outer(L, L)
        Ke[np.ix_(AX_IDX, AX_IDX)] += w * section.EA_N * np.outer(dL, dL)
        Me[np.ix_(TOR_IDX, TOR_IDX)] += w * section.Ip_kgm2_m * np.outer(L, L)
        Ke[np.ix_(TOR_IDX, TOR_IDX)] += w * section.GJ_Nm2 * np.outer(dL, dL)
    return Me, Ke


def bending_element(h: float, EI: float, m: float) -> tuple[np.ndarray, np.ndarray]:
    """Euler–Bernoulli Hermite element, DOFs (u1, du1/dx, u2, du2/dx): stiffness and consistent mass."""
    K = EI / h ** 3 * np.array([[12.0, 6 * h, -12.0, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                                [-12.0, -6 * h, 12.0, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    M = m * h / 420.0 * np.array([[156.0, 22 * h, 54.0, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                                  [54.0, 13 * h, 156.0, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    return K, M
