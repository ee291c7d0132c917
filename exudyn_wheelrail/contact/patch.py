r"""The non-Hertzian contact patch: elastic strips across the rolling direction, on the profiles' own geometry.

Where the curvatures of wheel and rail are not constant over the patch (the conformal S1002/UIC60 tread near the
centred position, the flange root, worn profiles) Hertz's single ellipse misses the patch's size and shape and the
contact angle that varies across it.  This module computes the patch of one contact zone from the interpenetration
``g(η) - A(η) x²`` of the *undeformed* profiles on strips across the rolling direction (:mod:`.strips`: the contact
plane, η the lateral coordinate in it, x along rolling) and its pressure from the elastic half-space.

The method
----------
The pressure is semi-elliptic along each strip, ``p(x, η_j) = q_j √(1 - x²/x_l,j²)`` — the form of Hertz's pressure
and of the method of Kik and Piotrowski (J. Kik, J. Piotrowski, Proc. 2nd Mini Conference on Contact Mechanics and
Wear of Rail/Wheel Systems, Budapest 1996, 52–61; J. Piotrowski, W. Kik, Vehicle System Dynamics 46 (2008) 27–48).
Their method takes the patch from the overlap of the surfaces brought together by a fraction ε = 0.55 of the
penetration and the pressure across the strips proportional to that overlap; measured against the exact half-space
solution (:mod:`.halfspace`) on S1002/UIC60 it makes the patch 8–30 % too large on Hertzian geometry and, on the
conformal tread at the centred position, the force 11 % and the contact angle 15 % too small
(``docs/validation.md``).  Here instead:

1. **The lengths from Hertz at each strip's own curvatures.**  Hertz's pressure has ``x_l = ρ q`` along every strip
   with one ratio ρ = a/p₀ of the ellipse's semi-axis along rolling to its peak pressure.  Each strip takes the ρ of
   the Hertz contact of its own curvatures, ``A_j`` along rolling and ``B_j = -g''(η_j)/2`` across (floored at
   :data:`B_FLOOR` ``A_j``: where ``g`` is flat or concave the strip is a two-dimensional contact along rolling,
   ρ → 1/(E* A)).  On a quadratic ``g`` every strip has Hertz's ρ.
2. **The strip peaks from the half-space.**  The ``q_j`` make the normal displacement of both bodies at every loaded
   strip's centre equal the interpenetration there, ``Σ_k C_jk q_k = g_j``, with ``q ≥ 0`` and no interpenetration at
   an unloaded strip's centre (Kalker's active set, as :mod:`.halfspace`); ``C_jk`` is Boussinesq's displacement at
   the centre of strip j per unit peak of strip k, ``(1/(π E*)) ∬_k √(1 - x²/x_l,k²)/√(x² + (η_j - η)²)``, which is
   ``2 x_l,k [H(e⁺/x_l,k) - H(e⁻/x_l,k)]/(π E*)`` for the strip's edges ``e^± = η_j - η_k ± w/2`` with the one
   function ``H(s) = ∫₀^{π/2} cos²θ asinh(s/sin θ) dθ`` (tabulated, :func:`strip_h`).  The lengths depend on the
   peaks (``x_l = ρ q``): a damped fixed point.  Hertz's pressure satisfies the displacement everywhere in its
   ellipse, so on Hertzian geometry the fixed point is Hertz's; on a conformal zone the strips share the load as
   the half-space makes them: a flat part of ``g`` carries load at a lower interpenetration than a local rule would
   give it, a second hump of ``g`` its own lobe.

The start is Hertz's ellipse at a virtual penetration (:func:`hertz_start`): the lateral curvature
``B = ε δ₀ / w_ε²`` read from the half-width ``w_ε`` of the region ``g > (1 - ε) δ₀`` and ε the value Hertz gives for
``(A(η₀), B)`` (``ε = b² B/δ₀``; on a quadratic ``g`` Hertz's own, 0.5 for a circle, lower for a patch long along
rolling).

**Resultants**: the strip loads ``N_j = (π/2) q_j x_l,j w``; ``N = Σ N_j``; the force's direction is the sum of the
strips' normals ``(sin γ_j, cos γ_j)`` weighted by their loads (its contact angle), its point the load-weighted mean
η; the area ``Σ 2 x_l,j w``; the equivalent ellipse of the tangential problem has the patch's lateral half-width and
its area.

Assumptions: elastic half-space of one material pair in the contact plane (patch small against the bodies' radii;
the patch's curvature across it enters only through the strips' normals), frictionless normal problem (no coupling
of normal and tangential), rolling direction along the rail, the pressure semi-elliptic along each strip (collocated
at its centre line).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scipy.special import ellipe, ellipkm1

from ..jit import compiled
from .layout import F_NR_Y, F_NR_Z, F_PR_Y, F_PR_Z, F_S_RAIL, F_S_WHEEL, F_SEMI_B
from .halfspace import solve_strip_geometry
from .normal import hertz_from_penetration
from .strips import N_STRIP_FIELDS, S_A, S_ETA, S_G, S_GAMMA, S_OK, S_WIDTH, fill_strips, zone_edges

__all__ = ["N_STRIPS", "FIXED_POINT_TOL", "FIXED_POINT_MAX", "DAMPING", "LENGTH_FLOOR", "B_FLOOR", "PatchSolution",
           "PatchError", "strip_h", "strip_influence", "hertz_start", "local_length_ratio", "solve_core", "scratch",
           "N_VECTORS", "resultants", "R_FORCE", "R_AREA", "R_SIN", "R_COS", "R_ETA", "R_HALF_WIDTH", "N_RESULTANTS",
           "solve_strips", "MIN_STEP_M", "row_zone_edges", "strips_of_contact", "patch_of_contact", "exact_of_contact"]

#: strips across a patch (against the exact solution on S1002/UIC60 at ten positions: 16 strips within 0.7 % in
#: force, 2.6 % in area, 1.1 % in the contact angle; docs/validation.md)
N_STRIPS = 16
#: the fixed points' relative tolerance, their iteration bound and damping
FIXED_POINT_TOL = 1e-6
FIXED_POINT_MAX = 200
DAMPING = 0.8
#: an unloaded strip's half-length in the influence matrix, relative to the longest (loading it is not free)
LENGTH_FLOOR = 1e-3
#: the floor of a strip's lateral curvature B_j, relative to its A_j (below it: a two-dimensional contact)
B_FLOOR = 1e-3



class PatchError(RuntimeError):
    """The patch could not be solved (no overlap, a strip's geometry failed, a fixed point did not settle)."""


# ------------------------------------------------------------------------------------- the strip function H(s)
#: H is tabulated over ln s in [ln H_S_MIN, ln H_S_MAX] (cubic Hermite, step H_DV); outside, its expansions
H_S_MIN = 1e-6
H_S_MAX = 1e5
H_DV = 0.02
#: H(s) → (π/4) ln(2s) + H_INF for large s (the constant is -∫cos²θ ln sin θ dθ over [0, π/2])
H_INF = 0.125 * math.pi * (1.0 + 2.0 * math.log(2.0))


def _dh_ds(s):
    """H'(s) = √(1+s²) (K(m) - E(m)), m = 1/(1+s²) (the η integral of the strip's kernel in closed form)."""
    s = np.asarray(s, dtype=float)
    m1 = s * s / (1.0 + s * s)                   # 1 - m, for K near m = 1
    return np.sqrt(1.0 + s * s) * (ellipkm1(m1) - ellipe(1.0 - m1))


def _h_table():
    """(H, dH/dv) at v = ln s on the grid: H integrated from H(s_min) = s_min ln(4/s_min) (its expansion for small
    s) by 8-point Gauss–Legendre on every interval of v, where H'(e^v) e^v is smooth."""
    v = np.arange(math.log(H_S_MIN), math.log(H_S_MAX) + 0.5 * H_DV, H_DV)
    gx, gw = np.polynomial.legendre.leggauss(8)
    mid, half = 0.5 * (v[1:] + v[:-1]), 0.5 * (v[1:] - v[:-1])
    t = np.exp(mid[:, None] + half[:, None] * gx[None, :])
    inc = (_dh_ds(t) * t * gw).sum(axis=1) * half
    h = np.concatenate(([H_S_MIN * math.log(4.0 / H_S_MIN)], H_S_MIN * math.log(4.0 / H_S_MIN) + np.cumsum(inc)))
    s = np.exp(v)
    return np.ascontiguousarray(np.column_stack([h, _dh_ds(s) * s])), float(v[0])


_H_TABLE, _H_V0 = _h_table()
_H_LAST = _H_TABLE.shape[0] - 2


@compiled(refcount=False)
def strip_h(s):
    """H(s) = ∫₀^{π/2} cos²θ asinh(s/sin θ) dθ (odd in s; module docstring)."""
    a = abs(s)
    if a < H_S_MIN:
        h = a * math.log(4.0 / a) if a > 0.0 else 0.0
    elif a > H_S_MAX:
        h = 0.25 * math.pi * math.log(2.0 * a) + H_INF
    else:
        x = (math.log(a) - _H_V0) / H_DV
        i = min(int(x), _H_LAST)
        u = x - i
        u2 = u * u
        u3 = u2 * u
        h = ((2.0 * u3 - 3.0 * u2 + 1.0) * _H_TABLE[i, 0] + (u3 - 2.0 * u2 + u) * H_DV * _H_TABLE[i, 1]
             + (-2.0 * u3 + 3.0 * u2) * _H_TABLE[i + 1, 0] + (u3 - u2) * H_DV * _H_TABLE[i + 1, 1])
    return h if s >= 0.0 else -h


@compiled(refcount=False)
def strip_influence(n, width, xl, e_star, C):
    """``C[j, k]`` (n × n): the displacement of both bodies at strip j's centre per unit peak pressure of strip k
    (strips of equal width, half-lengths ``xl``) [m/Pa]."""
    scale = 2.0 / (math.pi * e_star)
    for k in range(n):
        inv = 1.0 / xl[k]
        f = scale * xl[k]
        lower = strip_h((-k - 0.5) * width * inv)
        for j in range(n):
            upper = strip_h((j - k + 0.5) * width * inv)
            C[j, k] = f * (upper - lower)
            lower = upper


@compiled(refcount=False)
def _solve_dense(aug, m):
    """Solve the m × m system in ``aug[:m, :m]`` with right-hand side ``aug[:m, m]`` in place (Gaussian elimination,
    partial pivoting); the solution in ``aug[:m, m]``.  False if singular."""
    for c in range(m):
        p = c
        for r in range(c + 1, m):
            if abs(aug[r, c]) > abs(aug[p, c]):
                p = r
        if aug[p, c] == 0.0:
            return False
        if p != c:
            for k in range(c, m + 1):
                aug[c, k], aug[p, k] = aug[p, k], aug[c, k]
        for r in range(c + 1, m):
            f = aug[r, c] / aug[c, c]
            if f != 0.0:
                for k in range(c, m + 1):
                    aug[r, k] -= f * aug[c, k]
    for c in range(m - 1, -1, -1):
        v = aug[c, m]
        for k in range(c + 1, m):
            v -= aug[c, k] * aug[k, m]
        aug[c, m] = v / aug[c, c]
    return True


@compiled(refcount=False)
def _active_set(C, g, n, active, q, aug, idx):
    """q >= 0 with C q = g where q > 0 and C q >= g at the other strips with g > 0 (Kalker's NORM iteration from the
    set ``active`` (1.0 / 0.0), updated).  ``aug`` (n, n + 1) and ``idx`` (n,) scratch.  False if it cycles."""
    for _ in range(4 * n + 4):
        m = 0
        for j in range(n):
            if active[j] > 0.0:
                idx[m] = j
                m += 1
        for j in range(n):
            q[j] = 0.0
        if m > 0:
            for a in range(m):
                aug[a, m] = g[idx[a]]
                for b in range(m):
                    aug[a, b] = C[idx[a], idx[b]]
            if not _solve_dense(aug, m):
                return False
            negative = False
            for a in range(m):
                if aug[a, m] < 0.0:
                    active[idx[a]] = 0.0
                    negative = True
                else:
                    q[idx[a]] = aug[a, m]
            if negative:
                continue
        violated = False
        for j in range(n):
            if active[j] == 0.0 and g[j] > 0.0:
                u = 0.0
                for k in range(n):
                    u += C[j, k] * q[k]
                if u < g[j]:
                    active[j] = 1.0
                    violated = True
        if not violated:
            return True
    return False


@compiled(refcount=False)
def hertz_start(g, A, n, width, e_star):
    """The start (module docstring): ``(ε, a, p0, j0)`` of Hertz's ellipse at the curvatures ``(A(η₀), B)``, with
    δ₀ = max g at strip j0; ε < 0 if its fixed point did not settle."""
    j0 = 0
    for j in range(n):
        if g[j] > g[j0]:
            j0 = j
    d0 = g[j0]
    eps = 0.5
    a = 0.0
    p0 = 0.0
    for _ in range(FIXED_POINT_MAX):
        count = 0
        for j in range(n):
            if g[j] > (1.0 - eps) * d0:
                count += 1
        half = 0.5 * count * width
        B = eps * d0 / (half * half)
        force, _, a, b, _ = hertz_from_penetration(A[j0], B, e_star, d0, 0.0)
        p0 = 1.5 * force / (math.pi * a * b)
        new = b * b * B / d0
        if abs(new - eps) < FIXED_POINT_TOL:
            return new, a, p0, j0
        eps += DAMPING * (new - eps)
    return -1.0, a, p0, j0


@compiled(refcount=False)
def local_length_ratio(g, A, n, width, e_star, d0, rho):
    """ρ_j = a/p₀ of the Hertz contact of strip j's own curvatures A_j, B_j = -g''/2 (floored; module docstring)."""
    for j in range(n):
        jm = min(max(j, 1), n - 2)
        gpp = (g[jm + 1] - 2.0 * g[jm] + g[jm - 1]) / (width * width)
        B = max(-0.5 * gpp, B_FLOOR * A[j])
        force, _, a, b, _ = hertz_from_penetration(A[j], B, e_star, d0, 0.0)
        rho[j] = a * 2.0 * math.pi * a * b / (3.0 * force)


#: rows of the vectors' scratch of :func:`solve_core` (V_* by n)
_V_RHO = 0
_V_NEW = 1
_V_ACTIVE = 2
N_VECTORS = 3


@compiled
def scratch(n):
    """The work arrays of :func:`solve_core` for n strips: ``(C (n, n), aug (n, n + 1), vectors (N_VECTORS, n),
    idx (n,) int)``."""
    return np.zeros((n, n)), np.zeros((n, n + 1)), np.zeros((N_VECTORS, n)), np.zeros(n, dtype=np.int64)


@compiled(refcount=False)
def solve_core(g, A, n, width, e_star, q, xl, C, aug, vectors, idx):
    """The strip peaks ``q`` and half-lengths ``xl`` (module docstring) of n ≥ 3 strips of equal ``width`` with
    interpenetration ``g`` (max > 0) and rolling curvature ``A`` (> 0); ``C``, ``aug``, ``vectors``, ``idx`` the work
    arrays of :func:`scratch`.  Returns ``(iterations, ε)``; iterations < 0: -1 the start's fixed point, -2 the active
    set, -3 the strips' fixed point did not settle."""
    eps, a, p0, j0 = hertz_start(g, A, n, width, e_star)
    if eps < 0.0:
        return -1, eps
    d0 = g[j0]
    rho = vectors[_V_RHO]
    new = vectors[_V_NEW]
    active = vectors[_V_ACTIVE]
    local_length_ratio(g, A, n, width, e_star, d0, rho)
    for j in range(n):
        f = g[j] - (1.0 - eps) * d0
        q[j] = p0 * math.sqrt(f / (eps * d0)) if f > 0.0 else 0.0
    for it in range(1, FIXED_POINT_MAX + 1):
        longest = 0.0
        for j in range(n):
            longest = max(longest, rho[j] * q[j])
        for j in range(n):
            xl[j] = max(rho[j] * q[j], LENGTH_FLOOR * longest)
            active[j] = 1.0 if q[j] > 0.0 else 0.0
        strip_influence(n, width, xl, e_star, C)
        if not _active_set(C, g, n, active, new, aug, idx):
            return -2, eps
        top = 0.0
        change = 0.0
        for j in range(n):
            top = max(top, new[j])
            change = max(change, abs(new[j] - q[j]))
        if change < FIXED_POINT_TOL * top:
            for j in range(n):
                q[j] = new[j]
                xl[j] = rho[j] * q[j]
            return it, eps
        for j in range(n):
            q[j] += DAMPING * (new[j] - q[j])
    return -3, eps


#: the smallest step out of a zone towards its edges (Hertz's lateral semi-axis otherwise) [m]
MIN_STEP_M = 1e-4


@compiled(refcount=False)
def row_zone_edges(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, row, k_rail_roll, work):
    """The edges (η_lo, η_hi) of the overlap zone of a kernel output row (fields of :mod:`.layout`) in its contact
    plane (:func:`.strips.zone_edges`, stepping by Hertz's lateral semi-axis, at least MIN_STEP_M); ``work`` a
    strip row's scratch."""
    return zone_edges(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, row[F_PR_Y], row[F_PR_Z],
                      row[F_NR_Y], row[F_NR_Z], row[F_S_RAIL], row[F_S_WHEEL], k_rail_roll, 0.0,
                      max(row[F_SEMI_B], MIN_STEP_M), work)


# the resultants of a solved patch: res[R_*]
R_FORCE = 0       # Σ load_j, load_j = π/2 q_j x_l,j w (the integral of the strip's semi-elliptic pressure)
R_AREA = 1        # Σ 2 x_l,j w
R_SIN = 2         # Σ load_j sin γ_j and Σ load_j cos γ_j: the resultant's contact angle is their atan2
R_COS = 3
R_ETA = 4         # Σ load_j η_j: the resultant's lateral position is R_ETA / R_FORCE
R_HALF_WIDTH = 5  # half the lateral extent of the loaded strips (first to last), the equivalent ellipse's b
N_RESULTANTS = 6


@compiled(refcount=False)
def resultants(q, xl, width, gamma, eta, n, res):
    """The resultants (R_*) of the patch whose strips (centres ``eta``, contact angles ``gamma``, equal ``width``)
    carry the peaks ``q`` over the half-lengths ``xl`` into ``res``."""
    for k in range(N_RESULTANTS):
        res[k] = 0.0
    first = -1
    last = -1
    for j in range(n):
        load = 0.5 * math.pi * q[j] * xl[j] * width
        if load > 0.0:
            if first < 0:
                first = j
            last = j
        res[R_FORCE] += load
        res[R_AREA] += 2.0 * xl[j] * width
        res[R_SIN] += load * math.sin(gamma[j])
        res[R_COS] += load * math.cos(gamma[j])
        res[R_ETA] += load * eta[j]
    if first >= 0:
        res[R_HALF_WIDTH] = 0.5 * (last - first + 1) * width


# ------------------------------------------------------------------------------------------ Python front
@dataclass(frozen=True)
class PatchSolution:
    """One contact zone's patch: per strip (arrays over the strips) and its resultants, SI units."""

    eta_m: np.ndarray            # strip centres in the contact plane
    width_m: float               # strip width
    peak_Pa: np.ndarray          # q_j: pressure at x = 0
    half_length_m: np.ndarray    # x_l,j (0 where unloaded)
    gamma_rad: np.ndarray        # the strips' contact angles
    epsilon: float               # the start's virtual penetration fraction
    penetration_m: float         # δ₀ = max g
    iterations: int

    @property
    def load_N(self) -> np.ndarray:
        return 0.5 * math.pi * self.peak_Pa * self.half_length_m * self.width_m

    @property
    def _resultants(self) -> np.ndarray:
        res = np.zeros(N_RESULTANTS)
        resultants(self.peak_Pa, self.half_length_m, self.width_m, self.gamma_rad, self.eta_m, self.eta_m.size, res)
        return res

    @property
    def normal_force_N(self) -> float:
        return float(self._resultants[R_FORCE])

    @property
    def area_m2(self) -> float:
        return float(self._resultants[R_AREA])

    @property
    def peak_pressure_Pa(self) -> float:
        return float(self.peak_Pa.max())

    @property
    def contact_angle_rad(self) -> float:
        """Contact angle of the resultant: the strips' normals weighted by their loads."""
        res = self._resultants
        return float(math.atan2(res[R_SIN], res[R_COS]))

    @property
    def eta_resultant_m(self) -> float:
        res = self._resultants
        return float(res[R_ETA] / res[R_FORCE])

    @property
    def lateral_extent_m(self) -> tuple[float, float]:
        loaded = np.flatnonzero(self.load_N > 0.0)
        return (float(self.eta_m[loaded[0]] - 0.5 * self.width_m), float(self.eta_m[loaded[-1]] + 0.5 * self.width_m))

    def equivalent_ellipse(self) -> tuple[float, float]:
        """(a, b): the semi-axis a along rolling of the patch's area and its lateral half-width b."""
        res = self._resultants
        b = res[R_HALF_WIDTH]
        return float(res[R_AREA] / (math.pi * b)), float(b)


def solve_strips(eta_m, width_m: float, g, A, gamma, E_star_Pa: float) -> PatchSolution:
    """The patch of the strips (centres ``eta_m`` of equal width, interpenetration ``g``, rolling curvature ``A``,
    contact angle ``gamma``; module docstring); :class:`PatchError` if it cannot be solved."""
    eta = np.ascontiguousarray(eta_m, dtype=float)
    g = np.ascontiguousarray(g, dtype=float)
    A = np.ascontiguousarray(A, dtype=float)
    n = eta.size
    if n < 3 or g.shape != (n,) or A.shape != (n,):
        raise PatchError(f"the strips: {n} centres, {g.size} interpenetrations, {A.size} curvatures (>= 3 each)")
    if not g.max() > 0.0:
        raise PatchError("the profiles do not overlap")
    if not (A > 0.0).all():
        raise PatchError("a strip's rolling curvature is not positive (a wheel of revolution on a straight rail "
                         "has A > 0)")
    q = np.zeros(n)
    xl = np.zeros(n)
    it, eps = solve_core(g, A, n, float(width_m), float(E_star_Pa), q, xl, *scratch(n))
    if it < 0:
        raise PatchError({-1: "the start's virtual penetration did not settle", -2: "the strips' active set cycled",
                          -3: "the strips' pressure did not settle"}[it])
    return PatchSolution(eta, float(width_m), q, xl, np.asarray(gamma, dtype=float), float(eps), float(g.max()), it)


def strips_of_contact(nodes, meta, curve_ids, row, pose, k_rail_roll: float, n_strips: int = N_STRIPS):
    """The ``n_strips`` strips (fields S_* of :mod:`.strips`) across the overlap zone of one kernel output row
    ``row`` (fields of :mod:`.layout`) of a wheel at the side-frame ``pose`` (c_y, c_z, roll), the wheel's curves
    ``curve_ids`` (rail, tread, flange or -1); :class:`PatchError` where a strip's points are not found."""
    rail, tread, flange = (int(c) for c in curve_ids)
    c_y, c_z, roll = (float(v) for v in pose)
    args = (nodes, meta, rail, tread, flange, c_y, c_z, math.cos(roll), math.sin(roll), row[F_PR_Y], row[F_PR_Z],
            row[F_NR_Y], row[F_NR_Z], row[F_S_RAIL], row[F_S_WHEEL], k_rail_roll)
    lo, hi = row_zone_edges(nodes, meta, rail, tread, flange, c_y, c_z, math.cos(roll), math.sin(roll), row,
                            k_rail_roll, np.zeros(N_STRIP_FIELDS))
    strips = np.zeros((n_strips, N_STRIP_FIELDS))
    fill_strips(*args, lo, hi, strips)
    if not (strips[:, S_OK] > 0.0).all():
        raise PatchError("a strip's profile points were not found (Newton did not converge)")
    return strips


def patch_of_contact(nodes, meta, curve_ids, row, pose, k_rail_roll: float, E_star_Pa: float,
                     n_strips: int = N_STRIPS):
    """The patch of one kernel output row (arguments as :func:`strips_of_contact`): ``(strips, PatchSolution)``."""
    strips = strips_of_contact(nodes, meta, curve_ids, row, pose, k_rail_roll, n_strips)
    return strips, solve_strips(strips[:, S_ETA], strips[0, S_WIDTH], strips[:, S_G], strips[:, S_A],
                                strips[:, S_GAMMA], E_star_Pa)


def exact_of_contact(nodes, meta, curve_ids, row, pose, k_rail_roll: float, E_star_Pa: float,
                     n_strips: int = 64, n_x: int = 48):
    """The exact half-space solution (:func:`.halfspace.solve_strip_geometry`) over the interpenetration of one
    kernel output row's zone (arguments as :func:`strips_of_contact`), on ``n_strips`` strips × ``n_x`` cells — the
    patch's reference: ``(strips, HalfSpaceSolution, contact angle of its resultant)``."""
    strips = strips_of_contact(nodes, meta, curve_ids, row, pose, k_rail_roll, n_strips)
    exact = solve_strip_geometry(strips[:, S_ETA], strips[:, S_G], strips[:, S_A], n_x, E_star_Pa)
    return strips, exact, exact.contact_angle_rad(strips[:, S_GAMMA])
