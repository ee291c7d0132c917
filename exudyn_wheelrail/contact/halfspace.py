r"""The normal contact problem on the elastic half-space, solved exactly on a grid: the reference of the contact
patch.

Problem (Johnson 1985, §3.9 and ch. 4; Kalker 1990, ch. 2)
---------------------------------------------------------
Two bodies of the same elastic half-space type (combined modulus :math:`1/E^* = (1-\nu_w^2)/E_w +
(1-\nu_r^2)/E_r`) are pressed together by the rigid approach δ.  With ``d(x, y)`` the interpenetration of the
*undeformed* surfaces (positive where they overlap; ``d = δ - h`` for the separation ``h`` of the surfaces touching
at one point) and ``u(x, y)`` the sum of the normal surface displacements of both bodies, the contact conditions are

.. math::  p \ge 0, \qquad u - d \ge 0, \qquad p\,(u - d) = 0, \qquad
           u(x, y) = \frac{1}{\pi E^*} \iint \frac{p(x', y')}{\sqrt{(x - x')^2 + (y - y')^2}}\,dx'\,dy'

(Boussinesq's displacement of a point load, summed over both bodies).

Discretisation
--------------
A grid of rectangular cells ``dx × dy``, the pressure constant in each cell, the conditions at the cell centres
(collocation).  The displacement at a centre due to a unit pressure on a cell is Love's (1929) closed form: with
:math:`F(x, y) = x\,\mathrm{asinh}(y/|x|) + y\,\mathrm{asinh}(x/|y|)`, the antiderivative of
:math:`1/\sqrt{x^2 + y^2}` in both variables, the integral over the cell ``[x1, x2] × [y1, y2]`` (relative to the
centre) is :math:`F(x_2, y_2) - F(x_1, y_2) - F(x_2, y_1) + F(x_1, y_1)`.  The coefficients depend only on the
offset between two cells.

Only a cell where ``d > 0`` can carry pressure (``u > 0`` wherever some pressure acts, so ``u = d`` needs
``d > 0``); those cells are the unknowns.

Solution: Kalker's active-set iteration (NORM, Kalker 1990, §2.4): start with every candidate cell in contact;
solve ``C_AA p_A = d_A`` on the active set (Cholesky); drop the cells with negative pressure; add the cells
outside it that interpenetrate (``u < d``); repeat until neither happens.  The discrete problem is a strictly
convex quadratic programme (the influence matrix is symmetric positive definite), the iteration ends at its unique
solution: non-negative pressure, no interpenetration at any centre.

Accuracy: the pressure is exact for the discrete problem; against the continuous one the error is that of the
cell size — the patch's edge is resolved to within a cell, so the patch area carries an error ~ perimeter × cell /
area and the force a smaller one (the pressure vanishes at the edge).  The Hertz case is the check
(``tests/test_contact_patch.py``): elliptical patch and pressure within the grid's error.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import cho_factor, cho_solve

__all__ = ["HalfSpaceSolution", "influence_offsets", "solve_halfspace", "solve_strip_geometry",
           "MAX_ACTIVE_SET_ITERATIONS"]

#: the active-set iteration's bound (it ends in a handful of iterations on a contact patch; more means cycling)
MAX_ACTIVE_SET_ITERATIONS = 200


@dataclass(frozen=True)
class HalfSpaceSolution:
    """The pressure on the grid and its resultants (SI units)."""

    x_m: np.ndarray             # cell centres along x (rolling), (nx,)
    y_m: np.ndarray             # cell centres along y (lateral), (ny,)
    pressure_Pa: np.ndarray     # (ny, nx)
    cell_area_m2: float
    iterations: int

    @property
    def normal_force_N(self) -> float:
        return float(self.pressure_Pa.sum() * self.cell_area_m2)

    @property
    def area_m2(self) -> float:
        """Area of the cells in contact (pressure > 0)."""
        return float(np.count_nonzero(self.pressure_Pa > 0.0) * self.cell_area_m2)

    @property
    def peak_pressure_Pa(self) -> float:
        return float(self.pressure_Pa.max())

    def strip_loads_N_per_m(self) -> np.ndarray:
        """The force per unit of lateral width of each strip (a row of cells), (ny,)."""
        return self.pressure_Pa.sum(axis=1) * (self.cell_area_m2 / (self.y_m[1] - self.y_m[0])
                                               if self.y_m.size > 1 else self.cell_area_m2)

    def contact_angle_rad(self, gamma_rad) -> float:
        """Contact angle of the resultant when the row j of cells has the contact angle ``gamma_rad[j]``: the rows'
        normals weighted by their loads."""
        load = self.pressure_Pa.sum(axis=1)
        return float(np.arctan2(np.dot(load, np.sin(gamma_rad)), np.dot(load, np.cos(gamma_rad))))

    def strip_half_lengths_m(self) -> np.ndarray:
        """Half the extent along x of the cells in contact of each strip (0 where none), (ny,)."""
        dx = self.x_m[1] - self.x_m[0] if self.x_m.size > 1 else 0.0
        return 0.5 * dx * np.count_nonzero(self.pressure_Pa > 0.0, axis=1)


def _love(x, y):
    """x asinh(y/|x|) + y asinh(x/|y|), with its limit 0 where x or y is 0."""
    ax, ay = np.abs(x), np.abs(y)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(ax > 0.0, x * np.arcsinh(y / np.where(ax > 0.0, ax, 1.0)), 0.0)
        b = np.where(ay > 0.0, y * np.arcsinh(x / np.where(ay > 0.0, ay, 1.0)), 0.0)
    return a + b


def influence_offsets(dx: float, dy: float, nx: int, ny: int) -> np.ndarray:
    r"""The integral of :math:`1/\sqrt{x^2+y^2}` over a cell ``dx × dy`` seen from the centre of a cell ``(i, j)``
    cells away, for ``|i| < nx``, ``|j| < ny``: array (2 ny - 1, 2 nx - 1), offset (i, j) at ``[j + ny - 1,
    i + nx - 1]`` [m].  Times ``1/(π E*)``: the displacement per unit pressure."""
    i = np.arange(-(nx - 1), nx) * dx
    j = np.arange(-(ny - 1), ny) * dy
    X, Y = np.meshgrid(i, j)
    hx, hy = 0.5 * dx, 0.5 * dy
    return (_love(X + hx, Y + hy) - _love(X - hx, Y + hy) - _love(X + hx, Y - hy) + _love(X - hx, Y - hy))


def solve_halfspace(x_m, y_m, interpenetration_m, E_star_Pa: float) -> HalfSpaceSolution:
    """The exact pressure on the grid of cell centres ``x_m`` (nx, uniform), ``y_m`` (ny, uniform) for the
    interpenetration ``d`` of the undeformed surfaces (ny, nx) [m] (module docstring).  ``ValueError`` for a grid
    that is not uniform or an interpenetration of another shape; ``RuntimeError`` if the active set cycles."""
    x = np.asarray(x_m, dtype=float)
    y = np.asarray(y_m, dtype=float)
    d = np.asarray(interpenetration_m, dtype=float)
    if x.ndim != 1 or y.ndim != 1 or x.size < 2 or y.size < 2:
        raise ValueError("solve_halfspace: x_m and y_m must be 1-D with at least 2 cell centres each")
    if d.shape != (y.size, x.size):
        raise ValueError(f"solve_halfspace: interpenetration shape {d.shape}, expected (ny, nx) = "
                         f"{(y.size, x.size)}")
    dx, dy = x[1] - x[0], y[1] - y[0]
    if not (dx > 0 and dy > 0 and np.allclose(np.diff(x), dx, rtol=1e-9, atol=0.0)
            and np.allclose(np.diff(y), dy, rtol=1e-9, atol=0.0)):
        raise ValueError("solve_halfspace: the cell centres must be uniform and increasing")
    if not E_star_Pa > 0:
        raise ValueError(f"solve_halfspace: E_star_Pa = {E_star_Pa!r} must be positive")
    pressure = np.zeros_like(d)
    cand = np.flatnonzero(d.ravel() > 0.0)
    if cand.size == 0:
        return HalfSpaceSolution(x, y, pressure, dx * dy, 0)
    kern = influence_offsets(dx, dy, x.size, y.size) / (np.pi * E_star_Pa)
    jj, ii = np.divmod(cand, x.size)
    C = kern[(jj[:, None] - jj[None, :]) + y.size - 1, (ii[:, None] - ii[None, :]) + x.size - 1]
    rhs = d.ravel()[cand]
    active = np.ones(cand.size, dtype=bool)
    p = np.zeros(cand.size)
    tol = 1e-12 * float(rhs.max())
    for it in range(1, MAX_ACTIVE_SET_ITERATIONS + 1):
        idx = np.flatnonzero(active)
        p[:] = 0.0
        p[idx] = cho_solve(cho_factor(C[np.ix_(idx, idx)]), rhs[idx])
        negative = p < 0.0
        if negative.any():
            active &= ~negative
            continue
        u = C[:, idx] @ p[idx]
        violated = (~active) & (u < rhs - tol)
        if not violated.any():
            pressure.ravel()[cand] = p
            return HalfSpaceSolution(x, y, pressure, dx * dy, it)
        active |= violated
    raise RuntimeError(f"solve_halfspace: the active set did not settle in {MAX_ACTIVE_SET_ITERATIONS} iterations")


def solve_strip_geometry(eta_m, g_m, A_per_m, n_x: int, E_star_Pa: float) -> HalfSpaceSolution:
    """The exact solution for the interpenetration ``g(η) - A(η) x²`` of a contact patch's strips (centres
    ``eta_m``, uniform; :mod:`.patch`): one row of cells per strip, ``n_x`` cells along x over the longest overlap
    ``2 max √(g/A)``."""
    g = np.asarray(g_m, dtype=float)
    A = np.asarray(A_per_m, dtype=float)
    half = float(np.sqrt(np.maximum(g, 0.0) / A).max())
    if not half > 0.0:
        raise ValueError("solve_strip_geometry: the strips do not overlap")
    x = -half + (np.arange(n_x) + 0.5) * (2.0 * half / n_x)
    return solve_halfspace(x, eta_m, g[:, None] - A[:, None] * x[None, :] ** 2, E_star_Pa)
