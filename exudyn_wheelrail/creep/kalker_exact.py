"""Kalker's exact theory of steady-state rolling contact, discretised (the problem solved by Kalker's CONTACT).

References
----------
* J.J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990 — Ch. 5 (variational
  formulation, steady-state rolling, discretisation with piecewise-constant tractions on rectangles) and the
  Boussinesq–Cerruti surface influence functions of the elastic half-space.
* E.A.H. Vollebregt, "A Gauss–Seidel type solver for special convex programs, with application to frictional
  contact mechanics", J. Optim. Theory Appl. 87 (1995), and Vollebregt's later steady-rolling solvers in CONTACT
  that process whole lines in the rolling direction — the ideas used here (line Gauss–Seidel; each element's
  own 2×2 problem solved exactly on the friction disk).
* J.J. Kalker, "A fast algorithm for the simplified theory of rolling contact", Vehicle System Dynamics 11 (1982)
  — the strip discretisation and the marching along a strip.
* K.L. Johnson, *Contact Mechanics*, CUP 1985, Sec. 3.2 (point force on a half-space, Cerruti's solution).

Problem (frames and signs as the rest of :mod:`exudyn_wheelrail.creep`)
----------------------------------------------------------------------
Contact frame: ``x`` along rolling, ``y`` lateral, ``z = x × y`` into the rail; the wheel rolls so that its
material enters the ellipse ``(x/a)² + (y/b)² <= 1`` at the **leading edge** ``x = +a(y)`` and leaves it at
``x = -a(y)``.  ``p(x, y)`` is the tangential traction **on the wheel** [Pa].  The bodies are quasi-identical
elastic half-spaces (same G and ν; Kalker's case), so the tangential problem decouples from the normal one and the
normal pressure is Hertz's, ``p_n = (3N / 2πab) √(1 - (x/a)² - (y/b)²)``.

* Rigid slip (normalised by the rolling speed V): ``w = (ξ - φ y, η + φ x)``.
* Elastic displacement difference (wheel minus rail) ``u = A p``: for a unit point force on the wheel, each body
  displaces by Cerruti's solution, the rail oppositely (it carries -p), so for identical materials
  ``u_x = (1/πG)[(1-ν)/r + ν X²/r³] Q_x + (1/πG) ν X Y/r³ Q_y`` (X, Y = field minus source point, r = √(X²+Y²)),
  and symmetrically for ``u_y``.
* Steady-state slip: ``s = w - ∂u/∂x`` (the material derivative of u in steady rolling; the sign makes the
  simplified theory ``u = L p`` give FASTSIM's ``∂p/∂x = w/L``).
* Coulomb: ``|p| <= μ p_n``; stick where ``|p| < μ p_n`` (then ``s = 0``); slip where ``|p| = μ p_n`` and then
  ``p = -μ p_n s/|s|`` (friction on the wheel opposes the wheel's slip).

Discretisation
--------------
The ellipse is cut into ``n_y`` lateral strips of equal width ``dy = 2b/n_y``; strip j (centre ``y_j``) spans
its chord ``|x| <= a_j = a √(1 - (y_j/b)²)`` and is divided into ``n_x`` equal elements of length
``dx_j = 2 a_j/n_x`` (as FASTSIM divides its strips), so leading and trailing edges are exact in every strip.
Tractions are constant per element.  The influence coefficients are the exact integrals of the point-force
functions over each source rectangle, evaluated at field points (primitives:
``∫∫ 1/r = x asinh(y/|x|) + y asinh(x/|y|)``, ``∫∫ x²/r³ = y asinh(x/|y|)``, ``∫∫ y²/r³ = x asinh(y/|x|)``,
``∫∫ xy/r³ = -r``).  The derivative ∂u/∂x is Kalker's first-order upwind difference between an element centre
and the point one element length upstream (the next element towards the leading edge; for the leading element a
point outside the contact, where p = 0 but u is not): ``(∂u/∂x)_i ≈ (u_up(i) - u_i)/dx_j``.  The Hertz pressure
is sampled at the element centres and scaled so that the discrete pressures carry exactly N (full sliding gives
exactly μN).

Accuracy (measured, ``tests/test_kalker_exact.py``, ``benchmarks/bench_kalker_exact.py``): the error is first
order in the element length along rolling and nearly independent of ``n_y``, so the default grid is
``n_x × n_y = 80 × 20``.  It reproduces C11, C22 of Kalker's Table E.3 to about 0.6 % and C23 to about 1.4 % for
a/b = 0.2–5; :func:`kalker_exact_extrapolated` (Richardson over n_x and 2 n_x) brings all three within about
0.6 %.

Solver
------
Line Gauss–Seidel over the strips (each strip's n_x elements together, the other strips frozen; the iteration
matrix of this splitting has spectral radius about 0.45–0.6 on the default grid, while element-wise Gauss–Seidel
diverges for this non-symmetric operator).  Within a strip the x and y problems decouple except through the slip
direction; the strip is solved by marching from the leading edge with the local model ``u_i ≈ L q_i`` (the
simplified theory's flexibility, L chosen from the strip operator's spectrum for the fastest contraction), each
element's 2×2 problem solved exactly on the friction disk (stick if the trial traction is inside, else on the rim
with the slip direction from a Newton step on its angle), the rest of the strip's influence taken from the
previous iterate.  Sweeps stop when the largest traction change is below ``tol × μ max p_n``.  The operators of a
grid depend only on (a/b, ν, n_x, n_y) (for c = 1 m, G = 1 Pa) and are cached.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import prange

from ..jit import compiled
from ._inputs import check_contact_inputs, finite as _finite
from .linear import table_poisson

__all__ = [
    "DEFAULT_N_X", "DEFAULT_N_Y", "DEFAULT_TOL", "DEFAULT_MAX_SWEEPS", "DEFAULT_MAX_INNER", "KalkerSolution",
    "kalker_exact", "element_grid", "slip_operator", "line_influence",
    "kalker_exact_solution", "kalker_exact_extrapolated", "kalker_exact_core", "STATUS_CONVERGED",
    "STATUS_MAX_SWEEPS",
]

DEFAULT_N_X = 80
DEFAULT_N_Y = 20
DEFAULT_TOL = 1e-7
DEFAULT_MAX_SWEEPS = 500
DEFAULT_MAX_INNER = 10

STATUS_CONVERGED = 0
STATUS_MAX_SWEEPS = 1


@compiled
def _asinh_term(u, v):
    """``u·asinh(v/|u|)`` with its limit 0 at u = 0."""
    if u == 0.0:
        return 0.0
    return u * math.asinh(v / abs(u))


@compiled
def _primitives(x, y):
    """Primitives (F1, Fxx, Fyy, Fxy) whose mixed second derivative is 1/r, x²/r³, y²/r³, xy/r³."""
    fyy = _asinh_term(x, y)
    fxx = _asinh_term(y, x)
    r = math.sqrt(x * x + y * y)
    return fxx + fyy, fxx, fyy, -r


@compiled
def element_grid(a, b, n_x, n_y):
    """Element centres and sizes: row j (lateral strip) has centre ``y_j = -b + (j+½) dy``, ``dy = 2b/n_y``, and
    ``n_x`` elements of length ``dx_j = 2 a_j/n_x`` spanning the strip's chord ``|x| <= a_j = a √(1-(y_j/b)²)``;
    element ``e = j n_x + i`` with ``i = 0`` at the leading edge.  Returns ``(x, y, dx, dy)``."""
    n = n_x * n_y
    x = np.empty(n)
    y = np.empty(n)
    dx = np.empty(n)
    dy = 2.0 * b / n_y
    for j in range(n_y):
        yj = -b + (j + 0.5) * dy
        aj = a * math.sqrt(1.0 - (yj / b) ** 2)
        dxj = 2.0 * aj / n_x
        for i in range(n_x):
            e = j * n_x + i
            x[e] = aj - (i + 0.5) * dxj
            y[e] = yj
            dx[e] = dxj
    return x, y, dx, dy


@compiled(parallel=True)
def slip_operator(a, b, n_x, n_y, poisson):
    """The discrete steady-rolling slip operator for G = 1: ``s = w + B p`` with
    ``(B p)_e = (u_e - u_up(e))/dx_e`` (u = displacement difference at the element centre, up(e) = the point one
    element length upstream: the next element towards the leading edge, or for the leading element a point
    outside the contact area).  Returns ``(Bxx, Bxy, Byy)``, each (N, N) [1/Pa for G = 1 Pa]."""
    x, y, dx, dy = element_grid(a, b, n_x, n_y)
    n = n_x * n_y
    Bxx = np.empty((n, n))
    Bxy = np.empty((n, n))
    Byy = np.empty((n, n))
    f = 1.0 / math.pi
    hy = 0.5 * dy
    for e in prange(n):
        for q in range(2):                      # q = 0: the element centre, q = 1: the upstream point
            xf = x[e] + q * dx[e]
            yf = y[e]
            sign = 1.0 / dx[e] if q == 0 else -1.0 / dx[e]
            for js in range(n_y):
                Y = yf - y[js * n_x]
                # primitives at the n_x + 1 x-corners of the source row, for both y-edges
                s0 = js * n_x
                hx = 0.5 * dx[s0]
                prev_hi = _primitives(xf - (x[s0] + hx), Y + hy)
                prev_lo = _primitives(xf - (x[s0] + hx), Y - hy)
                for i in range(n_x):
                    s = s0 + i
                    X1 = xf - (x[s] - hx)             # X' upper limit (source left edge)
                    hi = _primitives(X1, Y + hy)
                    lo = _primitives(X1, Y - hy)
                    # ∫∫ over X' in [X - hx, X + hx] = F(X+hx) - F(X-hx); X + hx = xf - (x_s - hx)
                    i1 = (hi[0] - prev_hi[0]) - (lo[0] - prev_lo[0])
                    ixx = (hi[1] - prev_hi[1]) - (lo[1] - prev_lo[1])
                    iyy = (hi[2] - prev_hi[2]) - (lo[2] - prev_lo[2])
                    ixy = (hi[3] - prev_hi[3]) - (lo[3] - prev_lo[3])
                    axx = f * ((1.0 - poisson) * i1 + poisson * ixx)
                    ayy = f * ((1.0 - poisson) * i1 + poisson * iyy)
                    axy = f * poisson * ixy
                    if q == 0:
                        Bxx[e, s] = sign * axx
                        Bxy[e, s] = sign * axy
                        Byy[e, s] = sign * ayy
                    else:
                        Bxx[e, s] += sign * axx
                        Bxy[e, s] += sign * axy
                        Byy[e, s] += sign * ayy
                    prev_hi = hi
                    prev_lo = lo
    return Bxx, Bxy, Byy


@compiled
def line_influence(a, b, n_x, n_y, poisson):
    """Each line's influence on itself for G = 1: ``Axx[j, r, k]``, ``Ayy[j, r, k]`` — displacement at field point
    r of line j (r < n_x: the element centres, r = n_x: the point one element upstream of the leading element)
    from a unit traction on element k of the same line (no xy term: it vanishes on a line)."""
    x, y, dx, dy = element_grid(a, b, n_x, n_y)
    Axx = np.empty((n_y, n_x + 1, n_x))
    Ayy = np.empty((n_y, n_x + 1, n_x))
    f = 1.0 / math.pi
    hy = 0.5 * dy
    for j in range(n_y):
        o = j * n_x
        hx = 0.5 * dx[o]
        for r in range(n_x + 1):
            xf = x[o + r] if r < n_x else x[o] + dx[o]
            for k in range(n_x):
                X2 = xf - (x[o + k] - hx)
                X1 = xf - (x[o + k] + hx)
                p22 = _primitives(X2, hy)
                p12 = _primitives(X1, hy)
                p21 = _primitives(X2, -hy)
                p11 = _primitives(X1, -hy)
                i1 = p22[0] - p12[0] - p21[0] + p11[0]
                ixx = p22[1] - p12[1] - p21[1] + p11[1]
                iyy = p22[2] - p12[2] - p21[2] + p11[2]
                Axx[j, r, k] = f * ((1.0 - poisson) * i1 + poisson * ixx)
                Ayy[j, r, k] = f * ((1.0 - poisson) * i1 + poisson * iyy)
    return Axx, Ayy


@compiled
def _slip_direction(Sx, Sy, g, dxx, dyy):
    """Traction on the rim of the friction disk for an element with ``s = S + diag(dxx, dyy) p``:
    ``p = -g e`` with ``(S - g D e) × e = 0`` (Newton on the angle of e, from the direction of S)."""
    th = math.atan2(Sy, Sx)
    h = g * (dxx - dyy)
    for _ in range(30):
        c = math.cos(th)
        s = math.sin(th)
        fval = Sx * s - Sy * c - h * s * c
        dfval = Sx * c + Sy * s - h * (c * c - s * s)
        if dfval == 0.0:
            break
        step = fval / dfval
        th -= step
        if abs(step) < 1e-14:
            break
    return -g * math.cos(th), -g * math.sin(th)


@compiled
def _march_line(Ax, Ay, Lx, Ly, dx, rx, ry, g, qx, qy, st, tol, max_inner):
    """Solve one line's nonlinear problem ``s = r + B_line q`` with Coulomb's law, in place in ``qx``, ``qy``
    (G = 1 units), ``st`` = slip flags out.

    Splitting: ``B_line q = (u_i - u_up(i))/dx`` with ``u = A q``; the local part ``u_i ≈ L q_i`` (the simplified
    theory's flexibility, FASTSIM's picture) is marched exactly from the leading edge — each element's 2×2 problem
    solved on the friction disk — and the rest ``(A - L) q`` is taken from the previous iterate.  Returns the
    number of iterations."""
    n = qx.size
    Rx = np.empty(n + 1)
    Ry = np.empty(n + 1)
    dxx = Lx / dx
    dyy = Ly / dx
    it = 0
    for it in range(1, max_inner + 1):
        for r in range(n + 1):
            sx = 0.0
            sy = 0.0
            for k in range(n):
                sx += Ax[r, k] * qx[k]
                sy += Ay[r, k] * qy[k]
            if r < n:
                sx -= Lx * qx[r]
                sy -= Ly * qy[r]
            Rx[r] = sx
            Ry[r] = sy
        change = 0.0
        upx = Rx[n]          # upstream displacement of the leading element: the point outside the contact
        upy = Ry[n]
        for i in range(n):
            Sx = rx[i] + (Rx[i] - upx) / dx
            Sy = ry[i] + (Ry[i] - upy) / dx
            px = -Sx / dxx
            py = -Sy / dyy
            gi = g[i]
            if px * px + py * py > gi * gi:
                px, py = _slip_direction(Sx, Sy, gi, dxx, dyy)
                st[i] = 1
            else:
                st[i] = 0
            d = max(abs(px - qx[i]), abs(py - qy[i]))
            if d > change:
                change = d
            qx[i] = px
            qy[i] = py
            upx = Rx[i] + Lx * px
            upy = Ry[i] + Ly * py
        if change <= tol:
            break
    return it


@compiled
def kalker_exact_core(Bxx, Bxy, Byy, Axx, Ayy, Lx, Ly, x, y, dxe, n_x, n_y, xi, eta, phi, g, tol, max_sweeps,
                      max_inner, px, py, slip):
    """Compiled solver on a prepared grid (G = 1 units: tractions divided by G).

    ``g`` (N,) traction bound μ p_n / G; ``px``, ``py`` (N,) initial tractions / G (warm start), overwritten by
    the solution; ``slip`` (N,) int8 slip flags out.  Line Gauss–Seidel over the lateral strips: each line (the
    n_x elements of a strip, along rolling) is solved with the other lines frozen by :func:`_march_line`.
    Returns ``(sweeps, status)``."""
    n = n_x * n_y
    gmax = 0.0
    for e in range(n):
        gmax = max(gmax, g[e])
    rx = np.empty(n_x)
    ry = np.empty(n_x)
    qx = np.empty(n_x)
    qy = np.empty(n_x)
    st = np.empty(n_x, np.int8)
    status = STATUS_MAX_SWEEPS
    sweeps = 0
    thresh = tol * gmax
    for sweep in range(max_sweeps):
        sweeps = sweep + 1
        change = 0.0
        for j in range(n_y):
            o = j * n_x
            for i in range(n_x):
                e = o + i
                sx = xi - phi * y[e]
                sy = eta + phi * x[e]
                for s in range(o):
                    sx += Bxx[e, s] * px[s] + Bxy[e, s] * py[s]
                    sy += Bxy[e, s] * px[s] + Byy[e, s] * py[s]
                for s in range(o + n_x, n):
                    sx += Bxx[e, s] * px[s] + Bxy[e, s] * py[s]
                    sy += Bxy[e, s] * px[s] + Byy[e, s] * py[s]
                rx[i] = sx
                ry[i] = sy
                qx[i] = px[e]
                qy[i] = py[e]
            _march_line(Axx[j], Ayy[j], Lx[j], Ly[j], dxe[o], rx, ry, g[o:o + n_x], qx, qy, st, 0.1 * thresh,
                        max_inner)
            for i in range(n_x):
                e = o + i
                d = max(abs(qx[i] - px[e]), abs(qy[i] - py[e]))
                if d > change:
                    change = d
                px[e] = qx[i]
                py[e] = qy[i]
                slip[e] = st[i]
        if change <= thresh:
            status = STATUS_CONVERGED
            break
    return sweeps, status


def _hertz_bound(a, b, n_x, n_y, normal_force, mu):
    """Traction bound μ p_n per element [Pa]: Hertz's ellipsoidal pressure at the element centres, scaled so that
    the discrete pressures carry exactly N."""
    x, y, dx, dy = element_grid(a, b, n_x, n_y)
    shape = np.sqrt(np.maximum(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0))
    return mu * normal_force * shape / np.sum(shape * dx * dy)


_CACHE: dict = {}
_CACHE_SIZE = 2


def _line_flexibility(A):
    """Flexibility L of the line-local model ``u_i ≈ L q_i`` that makes the line iteration contract fastest: the
    iteration matrix is ``I - M/L`` with ``M = A_centres - 1·a_upstreamᵀ`` (real positive spectrum), so
    ``L = (λ_min + λ_max)/2`` of M."""
    n = A.shape[1]
    M = A[:n] - np.outer(np.ones(n), A[n])
    ev = np.linalg.eigvals(M).real
    return 0.5 * (ev.min() + ev.max())


def _operator(a_over_b, poisson, n_x, n_y):
    """Operators for c = √(ab) = 1 m and G = 1 Pa (they do not depend on c; they scale with 1/G), cached per
    (a/b, ν, n_x, n_y): ``(Bxx, Bxy, Byy, Axx_line, Ayy_line, Lx, Ly)``."""
    key = (round(float(a_over_b), 12), round(float(poisson), 12), int(n_x), int(n_y))
    op = _CACHE.get(key)
    if op is None:
        a1 = math.sqrt(a_over_b)
        # single precision halves the memory traffic of the sweeps (relative rounding 6e-8 of each coefficient;
        # sums are accumulated in double precision)
        Bxx, Bxy, Byy = (B.astype(np.float32) for B in slip_operator(a1, 1.0 / a1, n_x, n_y, poisson))
        Axx, Ayy = line_influence(a1, 1.0 / a1, n_x, n_y, poisson)
        Lx = np.array([_line_flexibility(Axx[j]) for j in range(n_y)])
        Ly = np.array([_line_flexibility(Ayy[j]) for j in range(n_y)])
        op = (Bxx, Bxy, Byy, Axx, Ayy, Lx, Ly)
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = op
    return op


@dataclass(frozen=True)
class KalkerSolution:
    """Result of :func:`kalker_exact_solution`: totals, the traction field and the slip area.

    Arrays are (n_y, n_x): row j is the lateral strip at ``y_m[j]``, column i runs from the leading edge (i = 0)
    to the trailing edge.  ``x_m`` element centres along rolling [m], ``px_Pa``, ``py_Pa`` tractions on the wheel,
    ``pn_Pa`` the Hertz pressure, ``slipping`` mask; ``sweeps`` line Gauss–Seidel sweeps used."""
    Fx_N: float
    Fy_N: float
    Mz_Nm: float
    x_m: np.ndarray
    y_m: np.ndarray
    px_Pa: np.ndarray
    py_Pa: np.ndarray
    pn_Pa: np.ndarray
    slipping: np.ndarray
    sweeps: int

    @property
    def slip_fraction(self) -> float:
        """Slipping share of the contact area."""
        dx = np.abs(np.diff(self.x_m, axis=1)[:, :1]) if self.x_m.shape[1] > 1 else np.ones((self.x_m.shape[0], 1))
        w = np.broadcast_to(dx, self.x_m.shape)
        return float((w * self.slipping).sum() / w.sum())


def _check(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, n_x, n_y, tol, max_sweeps):
    a, b, xi, eta, phi, N, mu, G = check_contact_inputs(a, b, xi, eta, phi, normal_force, mu, shear_modulus)
    nu = table_poisson(poisson)
    if int(n_x) != n_x or int(n_y) != n_y or n_x < 2 or n_y < 2:
        raise ValueError(f"n_x and n_y must be integers >= 2, got {n_x}, {n_y}")
    tol = _finite("tol", tol)
    if tol <= 0.0:
        raise ValueError(f"tol must be > 0, got {tol}")
    if int(max_sweeps) != max_sweeps or max_sweeps < 1:
        raise ValueError(f"max_sweeps must be an integer >= 1, got {max_sweeps}")
    return a, b, xi, eta, phi, N, mu, G, nu, int(n_x), int(n_y), tol, int(max_sweeps)


def kalker_exact_solution(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, n_x: int = DEFAULT_N_X,
                          n_y: int = DEFAULT_N_Y, tol: float = DEFAULT_TOL,
                          max_sweeps: int = DEFAULT_MAX_SWEEPS, initial=None,
                          max_inner: int = DEFAULT_MAX_INNER, initial_traction=None) -> KalkerSolution:
    """Solve the discretised steady rolling problem; return totals, traction field and slip area.

    Arguments as :func:`kalker_exact`.  ``initial``: a previous :class:`KalkerSolution` on the same grid
    (same a/b, n_x, n_y) used as a warm start; or ``initial_traction`` = ``(px_Pa, py_Pa)`` arrays (n_y, n_x) (the
    traction fields of such a solution, e.g. after a change of N or G).  Raises ``RuntimeError`` when the iteration does not converge
    within ``max_sweeps``."""
    a, b, xi, eta, phi, N, mu, G, nu, n_x, n_y, tol, max_sweeps = _check(
        a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, n_x, n_y, tol, max_sweeps)
    c = math.sqrt(a * b)
    x, y, dx, dy = element_grid(a, b, n_x, n_y)
    n = n_x * n_y
    px = np.zeros(n)
    py = np.zeros(n)
    slip = np.zeros(n, np.int8)
    pn = _hertz_bound(a, b, n_x, n_y, N, 1.0)
    if N > 0.0 and mu > 0.0:
        if initial is not None:
            if initial.px_Pa.shape != (n_y, n_x):
                raise ValueError(f"initial solution has grid {initial.px_Pa.shape[::-1]}, expected {(n_x, n_y)}")
            px[:] = initial.px_Pa.ravel() / G
            py[:] = initial.py_Pa.ravel() / G
            slip[:] = initial.slipping.ravel()
        elif initial_traction is not None:
            px0 = np.asarray(initial_traction[0], dtype=float)
            py0 = np.asarray(initial_traction[1], dtype=float)
            if px0.shape != (n_y, n_x) or py0.shape != (n_y, n_x):
                raise ValueError(f"initial_traction must be two ({n_y}, {n_x}) arrays (strips x elements)")
            px[:] = px0.ravel() / G
            py[:] = py0.ravel() / G
        Bxx, Bxy, Byy, Axx, Ayy, Lx, Ly = _operator(a / b, nu, n_x, n_y)
        # the operators are for c = 1 m: element coordinates scale with c, the spin creepage with 1/c
        g = mu * pn / G
        sweeps, status = kalker_exact_core(Bxx, Bxy, Byy, Axx, Ayy, Lx, Ly, x / c, y / c, dx / c, n_x, n_y, xi,
                                           eta, phi * c, g, tol, max_sweeps, max_inner, px, py, slip)
        if status != STATUS_CONVERGED:
            raise RuntimeError(f"kalker_exact: no convergence in {max_sweeps} sweeps (a={a}, b={b}, xi={xi}, "
                               f"eta={eta}, phi={phi}); raise max_sweeps or loosen tol")
        px *= G
        py *= G
    else:
        sweeps = 0
    dA = dx * dy
    Fx = float(np.sum(px * dA))
    Fy = float(np.sum(py * dA))
    Mz = float(np.sum((x * py - y * px) * dA))
    shape = (n_y, n_x)
    return KalkerSolution(Fx, Fy, Mz, x.reshape(shape), y.reshape(shape)[:, 0].copy(), px.reshape(shape),
                          py.reshape(shape), pn.reshape(shape), slip.reshape(shape).astype(bool), int(sweeps))


def kalker_exact(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, n_x: int = DEFAULT_N_X,
                 n_y: int = DEFAULT_N_Y, tol: float = DEFAULT_TOL, max_sweeps: int = DEFAULT_MAX_SWEEPS,
                 max_inner: int = DEFAULT_MAX_INNER):
    """Creep forces by Kalker's exact (three-dimensional, elastic half-space) theory of steady rolling.

    Returns ``(Fx, Fy, Mz)`` in N and N·m: forces **on the wheel** in the contact frame, moment about the contact
    normal through the ellipse centre.  ``a`` [m] semi-axis along rolling, ``b`` [m] lateral, creepages ξ, η [-],
    φ [1/m], ``normal_force`` N [N], friction coefficient μ, ``shear_modulus`` G [Pa] and ``poisson`` ν of both
    (quasi-identical) bodies.  Kalker's signs: for small creepage ``Fx = -G c² C11 ξ``,
    ``Fy = -G c² (C22 η + c C23 φ)``, ``Mz = G c³ (C23 η - c C33 φ)``, ``c = √(ab)``.

    Options: ``n_x`` elements along rolling per strip, ``n_y`` strips (accuracy: module docstring), ``tol``
    (traction change, relative to μ max p_n, that ends the iteration), ``max_sweeps`` (line Gauss–Seidel sweeps),
    ``max_inner`` (marching iterations per strip and sweep).  The slip operator of a
    grid is built once per (a/b, ν, n_x, n_y) and cached.  Raises ``ValueError`` for bad input, ``RuntimeError``
    if the iteration does not converge.  ``N == 0`` or ``μ == 0`` gives zeros."""
    s = kalker_exact_solution(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, n_x, n_y, tol,
                              max_sweeps, None, max_inner)
    return s.Fx_N, s.Fy_N, s.Mz_Nm


def kalker_exact_extrapolated(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson,
                              n_x: int = DEFAULT_N_X, n_y: int = DEFAULT_N_Y, **options):
    """Richardson extrapolation over n_x and 2 n_x elements along rolling (the discretisation error is first
    order in the element length along rolling, nearly independent of n_y — module docstring):
    ``F ≈ 2 F(2 n_x) - F(n_x)``.  For reference values in the adhesion-dominated range."""
    f1 = np.array(kalker_exact(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, n_x, n_y, **options))
    f2 = np.array(kalker_exact(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, 2 * n_x, n_y,
                               **options))
    return tuple(float(v) for v in 2.0 * f2 - f1)
