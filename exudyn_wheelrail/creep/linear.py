"""Kalker's linear theory of rolling contact: creep coefficients C11, C22, C23 and the linear creep forces.

Table
-----
The coefficients are Kalker's (Kalker 1990, *Three-dimensional elastic bodies in rolling contact*, Kluwer,
Table E.3), shipped as package data ``exudyn_wheelrail/data/kalker_linear_coefficients.csv`` (a verbatim copy of
``shared/reference/kalker_linear_coefficients.csv`` with its citation header).  The table variable is
``g = a/b`` for ``a <= b`` and ``g = b/a`` for ``a > b`` (``a`` = semi-axis along rolling, ``b`` = lateral), for
Poisson's ratio ν = 0, 0.25, 0.5.  The table has **no C33**.

Interpolation (the choice made here)
------------------------------------
* in the semi-axis ratio: one **PCHIP** (Fritsch–Carlson monotone piecewise-cubic Hermite) interpolant per
  column in ``t = ln(a/b)``, across both branches of the table (19 nodes, ``a/b`` = 0.1 … 10).  It reproduces
  every node exactly, is C¹, and is monotone on every interval between nodes (no overshoot; e.g. C11 at ν = 0.5,
  which has a shallow minimum near a/b = 0.3 in the table, keeps that minimum at a node).
* in ν: by default **quadratic** Lagrange interpolation through ν = 0, 0.25, 0.5 (exact at the three columns).
  C11 grows like ``1/(1-ν)`` (Kalker's narrow-ellipse limit ``C11 -> π²/(4(1-ν))``); for that function quadratic
  interpolation errs by +0.5 % at ν = 0.28 while piecewise-linear interpolation errs by +1.8 %.
  ``nu_interpolation="linear"`` gives piecewise-linear interpolation between 0–0.25 and 0.25–0.5 instead.
* limits: ``0.1 <= a/b <= 10`` and ``0 <= ν <= 0.5`` (the table's range); outside them a ``ValueError`` is raised
  — there is no extrapolation.

Linear creep forces (forces on the wheel, Kalker's signs, c = √(ab))::

    Fx = -G c² C11 ξ,   Fy = -G c² (C22 η + c C23 φ),   Mz = G c³ (C23 η - c C33 φ)

Because the table has no C33, :func:`linear_creep_forces` uses for the spin term of Mz the coefficient of
Kalker's *simplified* theory with the FASTSIM flexibility L3 (:func:`fastsim_spin_moment_coefficient`, the exact
small-creepage limit of :func:`exudyn_wheelrail.creep.fastsim`) — **not** Kalker's exact C33.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator

from ..jit import compiled
from ..validation import finite, poisson_ratio

__all__ = [
    "TABLE_PATH", "A_OVER_B_MIN", "A_OVER_B_MAX", "NU_NODES", "load_table", "kalker_coefficients",
    "kalker_coefficients_core", "fastsim_spin_moment_coefficient", "linear_creep_forces", "table_poisson",
]

#: The package copy of Kalker's Table E.3.
TABLE_PATH = Path(__file__).resolve().parents[1] / "data" / "kalker_linear_coefficients.csv"
#: Range of the table in a/b (no extrapolation outside).
A_OVER_B_MIN = 0.1
A_OVER_B_MAX = 10.0
#: Poisson ratios of the table columns.
NU_NODES = (0.0, 0.25, 0.5)
_REL_TOL = 1e-12  # round-off accepted at the ends of the ranges

NU_QUADRATIC = 0
NU_LINEAR = 1


def load_table(path: str | Path | None = None):
    """Read the table: returns ``(a_over_b, values)``, ``a_over_b`` ascending (19,), ``values`` (19, 3, 3) indexed
    ``[node, quantity (C11, C22, C23), nu (0, 0.25, 0.5)]``."""
    path = Path(path) if path is not None else TABLE_PATH
    rows = []
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            line = line.strip()
            if not line or line.startswith("#") or line.startswith("case"):
                continue
            parts = line.split(",")
            case, g = parts[0].strip(), float(parts[1])
            if case == "a<=b":
                ab = g
            elif case == "a>b":
                ab = 1.0 / g
            else:
                raise ValueError(f"{path}: unknown case {case!r}")
            rows.append((ab, [float(v) for v in parts[2:11]]))
    rows.sort(key=lambda r: r[0])
    a_over_b = np.array([r[0] for r in rows])
    values = np.array([r[1] for r in rows]).reshape(-1, 3, 3)
    if np.any(np.diff(a_over_b) <= 0):
        raise ValueError(f"{path}: duplicate a/b nodes")
    return a_over_b, values


def _build_pchip(a_over_b, values):
    t = np.log(a_over_b)
    coef = np.empty((4, t.size - 1, 9))
    for q in range(3):
        for k in range(3):
            coef[:, :, 3 * q + k] = PchipInterpolator(t, values[:, q, k]).c
    return t, coef


_AB_NODES, _VALUES = load_table()
_T_NODES, _COEF = _build_pchip(_AB_NODES, _VALUES)


@compiled(refcount=False)
def kalker_coefficients_core(t, nu, t_nodes, coef, nu_mode):
    """Compiled evaluation: ``t = ln(a/b)`` within ``[t_nodes[0], t_nodes[-1]]`` (clamped), ``0 <= nu <= 0.5``
    (not checked).  ``coef`` = PCHIP coefficients (4, n-1, 9); ``nu_mode`` 0 quadratic, 1 linear in ν.
    Returns ``(C11, C22, C23)``."""
    n = t_nodes.size
    if t <= t_nodes[0]:
        t = t_nodes[0]
    if t >= t_nodes[n - 1]:
        t = t_nodes[n - 1]
    # interval search (19 nodes: linear scan is fine)
    i = 0
    while i < n - 2 and t > t_nodes[i + 1]:
        i += 1
    s = t - t_nodes[i]
    out0 = 0.0
    out1 = 0.0
    out2 = 0.0
    for q in range(3):
        v0 = ((coef[0, i, 3 * q] * s + coef[1, i, 3 * q]) * s + coef[2, i, 3 * q]) * s + coef[3, i, 3 * q]
        v1 = ((coef[0, i, 3 * q + 1] * s + coef[1, i, 3 * q + 1]) * s + coef[2, i, 3 * q + 1]) * s \
            + coef[3, i, 3 * q + 1]
        v2 = ((coef[0, i, 3 * q + 2] * s + coef[1, i, 3 * q + 2]) * s + coef[2, i, 3 * q + 2]) * s \
            + coef[3, i, 3 * q + 2]
        if nu_mode == 0:
            # Lagrange through nu = 0, 0.25, 0.5
            l0 = (nu - 0.25) * (nu - 0.5) / 0.125
            l1 = nu * (nu - 0.5) / (-0.0625)
            l2 = nu * (nu - 0.25) / 0.125
            v = l0 * v0 + l1 * v1 + l2 * v2
        else:
            if nu <= 0.25:
                w = nu / 0.25
                v = (1.0 - w) * v0 + w * v1
            else:
                w = (nu - 0.25) / 0.25
                v = (1.0 - w) * v1 + w * v2
        if q == 0:
            out0 = v
        elif q == 1:
            out1 = v
        else:
            out2 = v
    return out0, out1, out2


def _nu_mode(nu_interpolation: str) -> int:
    if nu_interpolation == "quadratic":
        return NU_QUADRATIC
    if nu_interpolation == "linear":
        return NU_LINEAR
    raise ValueError(f"nu_interpolation must be 'quadratic' or 'linear', got {nu_interpolation!r}")


def table_poisson(poisson, name: str = "poisson") -> float:
    """A Poisson's ratio the creep theories of this package cover: an elastic material's
    (:func:`~exudyn_wheelrail.validation.poisson_ratio`) within Kalker's Table E.3, ``NU_NODES[0] <= nu <=
    NU_NODES[-1]`` (round-off at the ends clamped); ``ValueError`` naming ``name`` otherwise."""
    nu = poisson_ratio(name, poisson)
    lo, hi = NU_NODES[0], NU_NODES[-1]
    if nu < lo - _REL_TOL or nu > hi + _REL_TOL:
        raise ValueError(f"{name}: {nu:g} is outside the range the creep theories of this package cover "
                         f"({lo:g} <= nu <= {hi:g}, that of Kalker's Table E.3); no extrapolation is done")
    return min(max(nu, lo), hi)


def _check_ratio_nu(a_over_b, poisson):
    a_over_b = float(a_over_b)
    if not math.isfinite(a_over_b) or a_over_b <= 0.0:
        raise ValueError(f"a/b must be finite and > 0, got {a_over_b}")
    if a_over_b < A_OVER_B_MIN * (1 - _REL_TOL) or a_over_b > A_OVER_B_MAX * (1 + _REL_TOL):
        raise ValueError(f"a/b = {a_over_b:g} is outside Kalker's table (Table E.3) range "
                         f"[{A_OVER_B_MIN:g}, {A_OVER_B_MAX:g}]; no extrapolation is done")
    return a_over_b, table_poisson(poisson)


def kalker_coefficients(a_over_b, poisson, nu_interpolation: str = "quadratic"):
    """Kalker's linear-theory creep coefficients ``(C11, C22, C23)`` for the semi-axis ratio ``a/b`` (a along
    rolling) and Poisson's ratio, interpolated in Kalker 1990 Table E.3 (see the module docstring for the scheme).

    Raises ``ValueError`` for ``a/b`` outside [0.1, 10] or ν outside [0, 0.5]."""
    a_over_b, poisson = _check_ratio_nu(a_over_b, poisson)
    return kalker_coefficients_core(math.log(a_over_b), poisson, _T_NODES, _COEF, _nu_mode(nu_interpolation))


def fastsim_spin_moment_coefficient(a_over_b, poisson, nu_interpolation: str = "quadratic"):
    """Spin-moment coefficient of the simplified theory with FASTSIM's flexibility ``L3`` (replaces Kalker's C33,
    which Table E.3 does not give).

    Simplified theory, full adhesion, spin only: ``p_x = -φ y (a(y) - x)/L3`` gives
    ``Mz = -∫∫ y p_x dA = -8 a² b³ φ /(15 L3)``; with ``L3 = π a² /(4 c C23 G)`` this is ``-G c⁴ C33* φ`` with
    ``C33* = 32/(15 π) · C23 · (b/a)^{3/2}``.  This is *not* Kalker's exact C33."""
    c11, c22, c23 = kalker_coefficients(a_over_b, poisson, nu_interpolation)
    return 32.0 / (15.0 * math.pi) * c23 * float(a_over_b) ** -1.5


def linear_creep_forces(a, b, xi, eta, phi, shear_modulus, poisson, nu_interpolation: str = "quadratic"):
    """Kalker's linear creep forces ``(Fx, Fy, Mz)`` in N and N·m, forces on the wheel (Kalker's signs)::

        Fx = -G c² C11 ξ,  Fy = -G c² (C22 η + c C23 φ),  Mz = G c³ (C23 η - c C33* φ),  c = √(ab)

    ``C33*`` is the simplified-theory (FASTSIM) spin-moment coefficient
    (:func:`fastsim_spin_moment_coefficient`), because Kalker's Table E.3 has no C33: the spin term of Mz is
    FASTSIM's small-creepage limit, not Kalker's exact theory.  No saturation (valid for small creepage only)."""
    a, b, xi, eta, phi = (finite(k, v) for k, v in dict(a=a, b=b, xi=xi, eta=eta, phi=phi).items())
    G = finite("shear_modulus", shear_modulus)
    if a <= 0.0 or b <= 0.0:
        raise ValueError(f"semi-axes must be > 0, got a={a}, b={b}")
    if G <= 0.0:
        raise ValueError(f"shear modulus must be > 0, got {G}")
    c11, c22, c23 = kalker_coefficients(a / b, poisson, nu_interpolation)
    c33 = 32.0 / (15.0 * math.pi) * c23 * (a / b) ** -1.5
    c = math.sqrt(a * b)
    Fx = -G * c * c * c11 * xi
    Fy = -G * c * c * (c22 * eta + c * c23 * phi)
    Mz = G * c ** 3 * (c23 * eta - c * c33 * phi)
    return Fx, Fy, Mz
