r"""The non-Hertzian contact patch: elastic strips across the rolling direction, on the profiles' own geometry.

Where the curvatures of wheel and rail are not constant over the patch (the conformal S1002/UIC60 tread near the
centred position, the flange root, worn profiles) Hertz's single ellipse misses the patch's size and shape and the
contact angle that varies across it.  This module computes the patch of one contact zone from the interpenetration
of the *undeformed* profiles, strip by strip across the rolling direction, and its pressure from the elastic
half-space.

Geometry of the strips (rigid rail, wheel of revolution, yaw neglected — as for Hertz in :mod:`.normal`)
------------------------------------------------------------------------------------------------------
The **contact plane** is the tangent plane of the rail at the kernel's contact point ``o``: normal
``n_rail_in_side`` (outward, towards the wheel), lateral tangent ``t = (-n_z, n_y)`` (side frame).  A strip is a
lateral coordinate η along ``t``; at each η the rail and the wheel profile are cut by the line ``o + η t + ζ n``
(Newton on each curve's arc length, the wheel's tread and flange curves sharing the profile's arc length) and

* ``g(η) = ζ_rail - ζ_wheel`` is the interpenetration of the undeformed profiles along ``n`` (positive: overlap);
* ``A(η) = (κ_w,roll(η) + κ_r,roll)/2`` the relative curvature in the rolling direction (the wheel's by Meusnier,
  ``n_z/r`` of its own normal, as in the kernel): the interpenetration at ``(x, η)`` is ``g(η) - A(η) x²``;
* ``γ(η)`` the contact angle of the rail normal at the strip (positive towards the track centre, as the kernel's).

The zone is the interval around ``o`` where ``g > 0`` (stepping out, then bisecting), so a conformal zone with two
maxima of ``g`` is one patch.

The method
----------
It starts from the virtual-penetration method of Kik and Piotrowski (J. Kik, J. Piotrowski, Proc. 2nd Mini
Conference on Contact Mechanics and Wear of Rail/Wheel Systems, Budapest 1996, 52–61; J. Piotrowski, W. Kik,
Vehicle System Dynamics 46 (2008) 27–48): the patch from the overlap of the undeformed surfaces brought together by
only a fraction ε of the penetration δ₀ = max g, a pressure semi-elliptic along each strip.  Measured against the
exact half-space solution (:mod:`.halfspace`) on S1002/UIC60 that method with its ε = 0.55 and its pressure
proportional to the virtual overlap makes the patch 8–30 % too large on Hertzian geometry and, on the conformal
tread at the centred position, the force 11 % and the contact angle 15 % too small (``docs/validation.md``).  Two
changes, each exact where Hertz is:

1. **ε and the lengths from Hertz.**  The lateral curvature ``B = ε δ₀ / w²`` is read from the half-width ``w`` of
   the region ``g > (1 - ε) δ₀``, and ε is the value Hertz gives for the curvatures ``(A(η₀), B)`` at δ₀
   (``ε = b² B/δ₀``), found by a damped fixed point; the strips' half-lengths follow Hertz's ellipse, ``x_l(η) =
   √(f(η)/A(η)) · √(ε_x/ε)`` with ``f = g - (1 - ε) δ₀`` and ``ε_x = a² A/δ₀``.  On a quadratic ``g`` this is
   Hertz's ellipse for any ε, and the fixed point is Hertz's (KP's ε = 0.55 is one value of it).
2. **The lateral distribution from the half-space.**  The pressure is ``p(x, η) = q(η) √(1 - x²/x_l(η)²)``, with
   ``x_l = ρ q`` (ρ = a/p₀ of that Hertz solution: Hertz's pressure has this form), and the strip peaks ``q_j``
   solve the Boussinesq displacement at every strip centre, ``Σ_k C_jk q_k = g_j`` where loaded, ``q ≥ 0``, no
   interpenetration at an unloaded strip's centre (active set, as :mod:`.halfspace`), iterated with
   ``x_l = ρ q`` to a fixed point.  ``C_jk = (1/(π E*)) ∬_strip k √(1 - x²/x_l,k²)/√(x² + (η_j - η)²)`` — across
   the strip in closed form (``asinh``), along it with ``x = x_l sin θ``, ``θ = (π/2) u²`` (which removes the
   logarithmic singularity of a strip's own centre) by Gauss–Legendre quadrature in ``u``.  Hertz's pressure
   satisfies these equations (it satisfies the displacement everywhere in the patch), so on Hertzian geometry the
   fixed point is Hertz's; on a conformal zone the strips share the load as the half-space makes them: the flat
   parts of ``g`` carry load at a lower interpenetration than a local rule would give them, a second hump of ``g``
   its own lobe.

**Resultants**: the strip loads ``N_j = (π/2) q_j x_l,j w_j``; ``N = Σ N_j``; the force's direction is the sum of
the strips' normals ``(sin γ_j, cos γ_j)`` weighted by their loads (its contact angle); its point the load-weighted
mean η; the area ``Σ 2 x_l,j w_j``; the equivalent ellipse of the tangential problem has the patch's lateral
half-width and its area.

Assumptions: elastic half-space of one material pair in the contact plane (patch small against the bodies' radii;
the patch's curvature across it enters only through the strips' normals), frictionless normal problem (no coupling
of normal and tangential), rolling direction along the rail, the pressure semi-elliptic along each strip.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..jit import compiled
from ..profiles.curve import curve_eval, curve_point
from .layout import F_NR_Y, F_NR_Z, F_PR_Y, F_PR_Z, F_S_RAIL, F_S_WHEEL
from .normal import hertz_from_penetration

__all__ = ["N_STRIPS", "N_STRIP_FIELDS", "S_G", "S_A", "S_GAMMA", "S_RADIUS", "S_RAIL_Y", "S_RAIL_Z", "S_S_RAIL",
           "S_S_WHEEL", "S_OK", "S_ETA", "S_WIDTH", "PatchSolution", "PatchError", "strip_at", "zone_edges",
           "fill_strips", "strip_influence", "solve_strips", "hertz_start", "patch_of_contact", "gauss_nodes"]

#: strips across a patch
N_STRIPS = 32
#: Gauss–Legendre points of the integral along a strip
N_GAUSS = 16
#: the fixed points' relative tolerance, their iteration bound and damping
FIXED_POINT_TOL = 1e-7
#: an unloaded strip's half-length in the influence matrix, relative to the longest
LENGTH_FLOOR = 1e-3
FIXED_POINT_MAX = 200
DAMPING = 0.5

# one strip's fields (a row of the strips' array)
S_G = 0          # interpenetration g of the undeformed profiles along the plane's normal [m]
S_A = 1          # relative curvature in the rolling direction [1/m]
S_GAMMA = 2      # contact angle of the rail normal at the strip [rad]
S_RADIUS = 3     # wheel's rolling radius at the strip [m]
S_RAIL_Y = 4     # rail point of the strip, side frame [m]
S_RAIL_Z = 5
S_S_RAIL = 6     # rail arc length [m]
S_S_WHEEL = 7    # wheel arc length [m]
S_OK = 8         # 1 when both Newton solves converged
S_ETA = 9        # the strip's lateral coordinate in the contact plane [m]
S_WIDTH = 10     # the strip's width [m]
N_STRIP_FIELDS = 11

_NEWTON_TOL_M = 1e-10
_NEWTON_MAX = 12
_BISECTIONS = 40
_STEP_M = 5e-4        # stepping out of the zone
_MAX_HALF_WIDTH_M = 0.06


@compiled(refcount=False)
def _rail_at(nodes, meta, rail, s0, o_y, o_z, t_y, t_z, eta):
    """Arc length of the rail point with lateral coordinate η on the plane (Newton from s0): (s, ok)."""
    s = s0
    for _ in range(_NEWTON_MAX):
        py, pz, ty, tz = curve_point(nodes, meta, rail, s)
        f = (py - o_y) * t_y + (pz - o_z) * t_z - eta
        df = ty * t_y + tz * t_z
        if abs(df) < 1e-6:
            return s, False
        ds = f / df
        s -= ds
        if abs(ds) < _NEWTON_TOL_M:
            return s, True
    return s, False


@compiled(refcount=False)
def _wheel_curve(nodes, meta, tread, flange, s):
    """The wheel curve holding arc length ``s`` (the flange before the tread's first node, else the tread: the two
    share the whole profile's arc length)."""
    if flange >= 0 and s < nodes[int(meta[tread, 0]), 0]:
        return flange
    return tread


@compiled(refcount=False)
def _wheel_at(nodes, meta, tread, flange, s0, c_y, c_z, cos_r, sin_r, o_y, o_z, t_y, t_z, eta):
    """Arc length of the wheel point (placed by the pose) with lateral coordinate η on the plane: (s, ok)."""
    s = s0
    for _ in range(_NEWTON_MAX):
        curve = _wheel_curve(nodes, meta, tread, flange, s)
        py, pz, ty, tz = curve_point(nodes, meta, curve, s)
        wy = c_y + cos_r * py - sin_r * pz
        wz = c_z + sin_r * py + cos_r * pz
        f = (wy - o_y) * t_y + (wz - o_z) * t_z - eta
        df = (cos_r * ty - sin_r * tz) * t_y + (sin_r * ty + cos_r * tz) * t_z
        if abs(df) < 1e-6:
            return s, False
        ds = f / df
        s -= ds
        if abs(ds) < _NEWTON_TOL_M:
            return s, True
    return s, False


@compiled(refcount=False)
def strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, s_r0, s_w0, k_rail_roll,
             eta, row):
    """Fill ``row`` (fields S_*) with the strip at lateral coordinate ``eta`` of the plane (``o``, ``n``); the
    Newton solves start from ``s_r0``, ``s_w0``.  Returns the interpenetration g."""
    t_y = -n_z
    t_z = n_y
    s_r, ok_r = _rail_at(nodes, meta, rail, s_r0, o_y, o_z, t_y, t_z, eta)
    s_w, ok_w = _wheel_at(nodes, meta, tread, flange, s_w0, c_y, c_z, cos_r, sin_r, o_y, o_z, t_y, t_z, eta)
    ry, rz, _, _, rny, rnz, _ = curve_eval(nodes, meta, rail, s_r)
    curve = _wheel_curve(nodes, meta, tread, flange, s_w)
    qy, qz, _, _, _, qnz, _ = curve_eval(nodes, meta, curve, s_w)
    wy = c_y + cos_r * qy - sin_r * qz
    wz = c_z + sin_r * qy + cos_r * qz
    g = ((ry - o_y) - (wy - o_y)) * n_y + ((rz - o_z) - (wz - o_z)) * n_z
    row[S_G] = g
    row[S_A] = 0.5 * (qnz / qz + k_rail_roll)
    row[S_GAMMA] = math.atan2(-rny, -rnz)
    row[S_RADIUS] = qz
    row[S_RAIL_Y] = ry
    row[S_RAIL_Z] = rz
    row[S_S_RAIL] = s_r
    row[S_S_WHEEL] = s_w
    row[S_OK] = 1.0 if (ok_r and ok_w) else 0.0
    row[S_ETA] = eta
    return g


@compiled(refcount=False)
def zone_edges(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, s_r0, s_w0,
               k_rail_roll, level, row):
    """The interval (η_lo, η_hi) around η = 0 where the interpenetration exceeds ``level`` (stepping out by
    _STEP_M, then bisecting); ``g(0) > level`` is assumed."""
    out_lo = 0.0
    out_hi = 0.0
    for side in range(2):
        sgn = -1.0 if side == 0 else 1.0
        inside = 0.0
        outside = sgn * _STEP_M
        sr, sw = s_r0, s_w0
        while abs(outside) < _MAX_HALF_WIDTH_M:
            if strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, sr, sw,
                        k_rail_roll, outside, row) <= level:
                break
            sr, sw = row[S_S_RAIL], row[S_S_WHEEL]
            inside = outside
            outside += sgn * _STEP_M
        for _ in range(_BISECTIONS):
            mid = 0.5 * (inside + outside)
            if strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, sr, sw,
                        k_rail_roll, mid, row) > level:
                inside = mid
            else:
                outside = mid
        if side == 0:
            out_lo = inside
        else:
            out_hi = inside
    return out_lo, out_hi


@compiled(refcount=False)
def fill_strips(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, s_r0, s_w0,
                k_rail_roll, eta_lo, eta_hi, strips):
    """The strips of equal width over [η_lo, η_hi] (their centres), each row of ``strips`` filled (S_*)."""
    n = strips.shape[0]
    w = (eta_hi - eta_lo) / n
    # from the contact point outwards, so that each Newton solve starts next to its answer
    j0 = min(max(int((0.0 - eta_lo) / w), 0), n - 1)
    sr, sw = s_r0, s_w0
    for j in range(j0, n):
        strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, sr, sw, k_rail_roll,
                 eta_lo + (j + 0.5) * w, strips[j])
        strips[j, S_WIDTH] = w
        sr, sw = strips[j, S_S_RAIL], strips[j, S_S_WHEEL]
    sr, sw = s_r0, s_w0
    for j in range(j0 - 1, -1, -1):
        strip_at(nodes, meta, rail, tread, flange, c_y, c_z, cos_r, sin_r, o_y, o_z, n_y, n_z, sr, sw, k_rail_roll,
                 eta_lo + (j + 0.5) * w, strips[j])
        strips[j, S_WIDTH] = w
        sr, sw = strips[j, S_S_RAIL], strips[j, S_S_WHEEL]




# ----------------------------------------------------------------------------------------------- the method
class PatchError(RuntimeError):
    """The patch could not be solved (no overlap, a strip's geometry failed, a fixed point did not settle)."""


@dataclass(frozen=True)
class PatchSolution:
    """One contact zone's patch: per strip (arrays over the strips) and its resultants, SI units."""

    eta_m: np.ndarray            # strip centres in the contact plane
    width_m: float               # strip width
    peak_Pa: np.ndarray          # q_j: pressure at x = 0
    half_length_m: np.ndarray    # x_l,j (0 where unloaded)
    gamma_rad: np.ndarray        # the strips' contact angles
    load_N: np.ndarray           # the strips' forces
    epsilon: float               # the virtual penetration's fraction
    penetration_m: float         # δ₀ = max g
    iterations: int

    @property
    def normal_force_N(self) -> float:
        return float(self.load_N.sum())

    @property
    def area_m2(self) -> float:
        return float(2.0 * self.half_length_m.sum() * self.width_m)

    @property
    def peak_pressure_Pa(self) -> float:
        return float(self.peak_Pa.max())

    @property
    def contact_angle_rad(self) -> float:
        """Contact angle of the resultant: the strips' normals weighted by their loads."""
        return float(math.atan2(np.dot(self.load_N, np.sin(self.gamma_rad)),
                                np.dot(self.load_N, np.cos(self.gamma_rad))))

    @property
    def eta_resultant_m(self) -> float:
        return float(np.dot(self.load_N, self.eta_m) / self.load_N.sum())

    @property
    def lateral_extent_m(self) -> tuple[float, float]:
        loaded = np.flatnonzero(self.load_N > 0.0)
        return (float(self.eta_m[loaded[0]] - 0.5 * self.width_m), float(self.eta_m[loaded[-1]] + 0.5 * self.width_m))

    def equivalent_ellipse(self) -> tuple[float, float]:
        """(a, b): the patch's lateral half-width b and the semi-axis a along rolling of the same area."""
        lo, hi = self.lateral_extent_m
        b = 0.5 * (hi - lo)
        return self.area_m2 / (math.pi * b), b


def gauss_nodes(n: int = N_GAUSS):
    """Gauss–Legendre nodes and weights on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


_GX, _GW = gauss_nodes()
_THETA = 0.5 * np.pi * _GX * _GX
_SIN = np.sin(_THETA)
_WEIGHT = _GW * np.pi * _GX * np.cos(_THETA) ** 2


def strip_influence(eta_m, width_m: float, half_length_m, E_star_Pa: float) -> np.ndarray:
    r"""``C[j, k]``: the displacement of both bodies at strip j's centre per unit peak pressure of strip k
    (pressure ``√(1 - x²/x_l,k²)`` over strip k) [m/Pa] (module docstring)."""
    e = np.asarray(eta_m)[:, None] - np.asarray(eta_m)[None, :]
    xl = np.maximum(np.asarray(half_length_m, dtype=float), 1e-12)[None, :, None]
    x = xl * _SIN
    e1 = (e - 0.5 * width_m)[:, :, None]
    e2 = (e + 0.5 * width_m)[:, :, None]
    inner = (_WEIGHT * (np.arcsinh(e2 / x) - np.arcsinh(e1 / x))).sum(axis=-1)
    return 2.0 * xl[:, :, 0] * inner / (np.pi * E_star_Pa)


def _active_set(C, rhs, candidate, active):
    """q >= 0 with C q = rhs where q > 0 and C q >= rhs at the other candidates (Kalker's NORM iteration, from the
    set ``active``)."""
    active = active & candidate
    q = np.zeros(rhs.size)
    for _ in range(4 * rhs.size + 4):
        idx = np.flatnonzero(active)
        q[:] = 0.0
        if idx.size:
            q[idx] = np.linalg.solve(C[np.ix_(idx, idx)], rhs[idx])
        negative = q < 0.0
        if negative.any():
            active &= ~negative
            continue
        violated = candidate & ~active & (C @ q < rhs)
        if not violated.any():
            return q
        active |= violated
    raise PatchError("the strips' active set did not settle")


def _width_above(g, level, width):
    return width * np.count_nonzero(g > level)


def hertz_start(g, A, width_m: float, E_star_Pa: float):
    """The Hertz-consistent virtual penetration (module docstring, change 1): ``(ε, a, b, p0, j0)`` of the Hertz
    solution at the curvatures ``(A(η₀), B)``, with δ₀ = max g at strip j0."""
    j0 = int(np.argmax(g))
    d0 = float(g[j0])
    eps = 0.5
    for _ in range(FIXED_POINT_MAX):
        half = 0.5 * _width_above(g, (1.0 - eps) * d0, width_m)
        B = eps * d0 / (half * half)
        _, _, a, b, _ = hertz_from_penetration(float(A[j0]), B, E_star_Pa, d0, 0.0)
        new = b * b * B / d0
        if abs(new - eps) < FIXED_POINT_TOL:
            eps = new
            break
        eps += DAMPING * (new - eps)
    else:
        raise PatchError("the virtual penetration's fixed point did not settle")
    n = hertz_from_penetration(float(A[j0]), B, E_star_Pa, d0, 0.0)[0]
    return eps, a, b, 1.5 * n / (math.pi * a * b), j0


def solve_strips(eta_m, width_m: float, g, A, gamma, E_star_Pa: float) -> PatchSolution:
    """The patch of the strips (centres ``eta_m`` of equal width, interpenetration ``g``, rolling curvature ``A``,
    contact angle ``gamma``; module docstring)."""
    eta = np.asarray(eta_m, dtype=float)
    g = np.asarray(g, dtype=float)
    A = np.asarray(A, dtype=float)
    if not (g.max() > 0.0):
        raise PatchError("the profiles do not overlap")
    if not (A > 0.0).all():
        raise PatchError("a strip's rolling curvature is not positive (a wheel of revolution on a straight rail "
                         "has A > 0)")
    eps, a, b, p0, j0 = hertz_start(g, A, width_m, E_star_Pa)
    d0 = float(g[j0])
    f = np.maximum(g - (1.0 - eps) * d0, 0.0)
    rho = a / p0
    q = p0 * np.sqrt(f / (eps * d0))
    candidate = g > 0.0
    for it in range(1, FIXED_POINT_MAX + 1):
        # an unloaded strip's column: a short strip (its length floored), so that loading it is not free
        xl = np.maximum(rho * q, LENGTH_FLOOR * rho * q.max())
        new = _active_set(strip_influence(eta, width_m, xl, E_star_Pa), g, candidate, q > 0.0)
        change = float(np.abs(new - q).max() / new.max())
        q += DAMPING * (new - q)
        if change < FIXED_POINT_TOL:
            q = new
            break
    else:
        raise PatchError("the strips' pressure did not settle")
    xl = rho * q
    return PatchSolution(eta, float(width_m), q, xl, np.asarray(gamma, dtype=float), 0.5 * math.pi * q * xl * width_m,
                         eps, d0, it)


def patch_of_contact(nodes, meta, curve_ids, row, pose, k_rail_roll: float, E_star_Pa: float,
                     n_strips: int = N_STRIPS):
    """The patch of one kernel output row ``row`` (fields of :mod:`.layout`) of a wheel at the side-frame ``pose``
    (c_y, c_z, roll), the wheel's curves ``curve_ids`` (rail, tread, flange or -1): ``(strips, PatchSolution)``."""
    rail, tread, flange = (int(c) for c in curve_ids)
    c_y, c_z, roll = (float(v) for v in pose)
    args = (nodes, meta, rail, tread, flange, c_y, c_z, math.cos(roll), math.sin(roll), row[F_PR_Y], row[F_PR_Z],
            row[F_NR_Y], row[F_NR_Z], row[F_S_RAIL], row[F_S_WHEEL], k_rail_roll)
    scratch = np.zeros(N_STRIP_FIELDS)
    lo, hi = zone_edges(*args, 0.0, scratch)
    strips = np.zeros((n_strips, N_STRIP_FIELDS))
    fill_strips(*args, lo, hi, strips)
    if not (strips[:, S_OK] > 0.0).all():
        raise PatchError("a strip's profile points were not found (Newton did not converge)")
    return strips, solve_strips(strips[:, S_ETA], strips[0, S_WIDTH], strips[:, S_G], strips[:, S_A],
                                strips[:, S_GAMMA], E_star_Pa)
