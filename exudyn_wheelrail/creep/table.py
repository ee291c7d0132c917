"""USETAB-style creep table: creep forces of a (slow) rolling-contact theory tabulated once, then interpolated.

Idea: Kalker's USETAB (J.J. Kalker, "Book of tables for the Hertzian creep-force law", in *Proceedings of the
2nd Mini Conference on Contact Mechanics and Wear of Rail/Wheel Systems*, Budapest 1996): the creep forces of the
exact theory are computed offline on a grid of *normalised* creepages and semi-axis ratios and interpolated at run
time.  Everything here (normalisation, grid, interpolation) is this package's own design, described below; the
table itself is built by :mod:`exudyn_wheelrail.creep.build_table` (``python -m exudyn_wheelrail creep-table``).

Contract (as every creep law of :mod:`exudyn_wheelrail.creep`)
--------------------------------------------------------------
``table_forces(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson) -> (Fx, Fy, Mz)`` in N and N·m,
forces **on the wheel** in the contact frame, ``a`` [m] the semi-axis along rolling, ``b`` [m] lateral,
``c = √(ab)``, Kalker's signs (small creepage: ``Fx = -G c² C11 ξ``, ``Fy = -G c² (C22 η + c C23 φ)``,
``Mz = G c³ (C23 η - c C33 φ)``).

Dimensional analysis and normalisation
--------------------------------------
For Hertzian contact of quasi-identical bodies, ``F/(μN)`` and ``Mz/(μNc)`` depend only on ``a/b``, ν and the
creepages made dimensionless with the creep stiffness and the friction limit.  With Kalker's linear coefficients
``C11, C22`` (Kalker 1990, Table E.3, :func:`exudyn_wheelrail.creep.linear.kalker_coefficients`) the table uses

    ξ̂ = ξ · G c² C11 / (3μN),   η̂ = η · G c² C22 / (3μN),
    φ̂ = φ · G c² √((C11 b)² + (C22 a)²) / (3μN),

    table values:  fx = Fx/(μN),  fy = Fy/(μN),  mz = Mz/(μN c).

* ξ̂, η̂: the factor 3 puts the end of the adhesion range near ξ̂ ≈ 1 (Vermeulen–Johnson's cubic law
  ``1 - (1 - ξ̂)³`` saturates exactly at ξ̂ = 1, FASTSIM at 32/(9π) ≈ 1.13); the linear slopes are
  ``fx = -3 ξ̂``, ``fy = -3 η̂``.
* φ̂ (spin): spin is the rigid slip ``(-φ y, φ x)``; its longitudinal part reaches ``φ b`` at the lateral edge and
  acts on the x-flexibility (∝ 1/C11), its lateral part ``φ a`` on the y-flexibility (∝ 1/C22).  φ̂ is the
  Euclidean combination of the two "equivalent creepages" normalised like ξ̂ and η̂.  The obvious alternative
  ``φ̃ = G c³ C23 φ/(3μN)`` was tried first and rejected: with it the spin moment saturates at φ̃ ≈ 0.006 for
  a/b = 0.05 but at φ̃ ≈ 1 for a/b ≥ 10 (FASTSIM, half of the pure-spin moment), a spread of 2.5 decades that a
  grid cannot resolve (measured max error of Mz 0.7 μNc on a 65 k-case table); with φ̂ the half-points of the
  pure-spin moment and lateral force all lie in 0.2 < φ̂ < 4 for 0.05 <= a/b <= 20.
* ``C11, C22`` are evaluated at ``a/b`` **clamped to 0.1 … 10** (Table E.3's range) and at the caller's ν.  The
  normalisation only has to be a smooth, consistent scaling used identically when building and when looking up;
  outside 0.1–10 it is no longer the exact linear stiffness, the table then carries the difference.  (``a`` and
  ``b`` in φ̂ and ``c`` are the true ones.)  Because of the clamp the tabulated functions have a kink at
  a/b = 0.1 and 10; both are grid nodes and the interpolation in a/b does not reach across them (below).

Symmetries (steady rolling, quasi-identical bodies), used to store only ξ̂ >= 0, η̂ >= 0::

    (ξ, η, φ) -> -(ξ, η, φ)   gives -(Fx, Fy, Mz)
    (ξ, η, φ) -> (ξ, -η, -φ)  gives (Fx, -Fy, -Mz)
    (ξ, η, φ) -> (-ξ, η, φ)   gives (-Fx, Fy, Mz)      (the product of the two)

(verified on the generator in ``tests/test_creep_table.py``).

Grid: polar coordinates of the normalised creepage vector
--------------------------------------------------------
``v = (ξ̂, η̂, φ̂)`` (after the symmetry reduction):  ``r = |v|``, ``θ = atan2(η̂, ξ̂)`` in [0, π/2],
``ψ = atan2(φ̂, √(ξ̂² + η̂²))`` in [-π/2, π/2] (ψ = ±π/2: pure spin).  Axes of the table: ``t = ln(a/b)``, r, θ, ψ.
Why polar: for large creepage the contact slides fully and the forces depend only on the *direction* of the
creepage vector (the rigid slip field scales as a whole), so along each ray the force goes from the linear slope
at r = 0 to a direction-dependent limit — one smooth 1-D curve per direction, resolved by a radial node list that
is dense in the adhesion–saturation transition (r ≈ 0.1 … 3) and geometric beyond.

Interpolation (``interpolation="cubic"``, the default)
-----------------------------------------------------
Tensor product of piecewise-cubic C¹ Hermite interpolants in each axis, slopes from the parabola through three
neighbouring nodes (the non-uniform Catmull–Rom rule; linear in the data, 4 nodes per axis, 256 values per
lookup).  Ends of the axes:

* r < 0, θ < 0, θ > π/2, |ψ| > π/2 are continued by the symmetries ("ghost" nodes filled at load time):
  ``F(-v) = -F(v)`` continues r through 0, the two mirror symmetries continue θ, and crossing a pole of ψ is the
  same as the opposite ψ with ``-F``.  The creep force is not odd-smooth at r = 0 (``F ≈ 3r - k r|r|``: the slip
  zone grows from the trailing edge at once), so the slope at r = 0 is the secant ``F(r1)/r1``; the default grid
  therefore has its first nodes at r = 0.001 and 0.01, which keeps the small-creepage slopes (Kalker's linear
  coefficients, as reproduced by the generator) to ~0.1 %.
* r > r_max (the last node, far into full sliding): the creepage vector is scaled back onto r = r_max keeping its
  direction (see "beyond the table" below); the last interval uses the secant slope at r_max.
* a/b: the interpolation never reaches across a/b = 0.1 and 10 (the normalisation's kinks; "break" nodes: the
  slope at a break node is the one-sided secant) nor beyond 0.05 … 20 (ValueError).

``interpolation="linear"`` gives plain multilinear interpolation on the same nodes (16 values per lookup, summed
over those 16 alone); the connector offers it as the creep law ``"table_linear"`` (the ``fast`` preset's: about
half the lookup's cost; midway between the nodes up to 2.9 % of μN instead of 1.0 %, docs/validation.md).
Measured on the default grid against FASTSIM (``benchmarks/bench_creep_table.py``, 4000 random off-grid points,
|ΔF|/(μN)): cubic RMS 0.10 %, 99.9 % quantile 1.0 %, max 3.1 % (one point at a/b = 0.09 where FASTSIM's own 16
strips make it rough); linear RMS 0.35 %, 99.9 % 2.5 %, max 3.7 %.  Cost (compiled, warm; two machines,
docs/performance.md): cubic 0.45–0.58 µs, linear 0.23–0.25 µs per lookup.

Beyond the table
----------------
* ``r > r_max`` (the normalised creepage vector is longer than the table's last radial node): the vector is
  scaled back onto r = r_max, *keeping its direction*, i.e. the force of the most-sliding tabulated state with
  the same slip direction field.  Exact in the full-sliding limit of the exact theory; the error is what the
  force still changes beyond r_max: with FASTSIM (default grid, r = 2 … 100 r_max, 1000 random directions)
  max 2.2 % of μN (2.7 % of μNc for Mz), RMS 0.16 % — directions dominated by spin approach full sliding slowly.
  Such creepages (|ξ| >~ 10 at usual loads) occur practically only as N -> 0, where μN -> 0 as well.
* ``a/b`` outside the table (0.05 … 20): ``ValueError`` (no extrapolation).
* ν: the table is built for one Poisson ratio (``NU_TABLE`` = 0.28, steel).  A lookup accepts
  ``|ν - ν_table| <= NU_TOLERANCE`` (0.02, i.e. 0.26 … 0.30): the normalisation uses C11, C22 at the *caller's*
  ν and the tabulated function of the normalised creepages is taken as ν-independent — an approximation.  Its
  main error is the direction of the force in (partial) sliding, which follows the physical creepage ratio ξ/η
  while the normalisation scales ξ and η by C11(ν) and C22(ν).  Measured with FASTSIM's weighted flexibility as a
  proxy (its full-slip force opposes the creepage, as in the exact theory; ``benchmarks/bench_creep_table.py``,
  FASTSIM tables at ν = 0.28 and at ν itself, default grid): the RMS of |ΔF|/(μN) grows from 0.21 % (table
  built at ν) to 0.30 % at |Δν| = 0.01, 0.48 % at 0.02 and 0.69 % at 0.03; the max changes little (it is
  dominated by the proxy's own roughness).  Hence the band ±0.02, inside which the total RMS stays <= 0.5 %.
  Outside it: ``ValueError`` (build a table for that ν with ``--nu``).

Table file (``.npz``, format version 1)
---------------------------------------
``ratio_nodes`` (a/b, ascending), ``ratio_breaks`` (bool, nodes the interpolation does not cross), ``r_nodes``,
``theta_nodes`` [rad], ``psi_nodes`` [rad] (symmetric about 0, both poles included), ``values``
``(n_ratio, n_r, n_theta, n_psi, 3)`` = (fx, fy, mz) at the nodes, ``cij_check`` ``(n_ratio, 2)`` = the C11, C22
used at the nodes (checked against the package's Table E.3 on load: a changed normalisation must not silently
corrupt the table) and ``metadata_json`` (generator and its options, ν, grid name, normalisation, canonical
problem, build date, package version, case count, build time).  The package table is
``exudyn_wheelrail/data/creep_table.npz`` (built by the exact solver); a FASTSIM-built development table must be
named ``creep_table_fastsim.npz`` or kept elsewhere.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..jit import compiled
from .linear import A_OVER_B_MAX, A_OVER_B_MIN, kalker_coefficients, table_poisson
from ._inputs import check_contact_inputs

__all__ = [
    "TABLE_PATH", "FASTSIM_TABLE_PATH", "FORMAT", "FORMAT_VERSION", "NU_TABLE", "NU_TOLERANCE",
    "NORMALISATION", "BUILD_COMMAND", "CreepTable", "load_table", "save_table", "pad_table", "table_forces",
    "table_core", "normalised_creepages", "physical_creepages", "normalisation_coefficients", "ORDER_LINEAR",
    "ORDER_CUBIC",
]

DATA_DIR = Path(__file__).resolve().parents[1] / "data"
#: The package table (built with the exact solver).
TABLE_PATH = DATA_DIR / "creep_table.npz"
#: Name reserved for a FASTSIM-built development table (never the package default).
FASTSIM_TABLE_PATH = DATA_DIR / "creep_table_fastsim.npz"
FORMAT = "exudyn_wheelrail.creep_table"
FORMAT_VERSION = 1
#: Poisson ratio the tables are built for (steel).
NU_TABLE = 0.28
#: Accepted |ν - ν_table| at lookup (normalisation with C11, C22 at the caller's ν; an approximation, see above).
NU_TOLERANCE = 0.02
#: Identifier + definition of the normalisation (stored in the metadata; load refuses another one).
NORMALISATION = ("lever-v1: xi_hat = xi*G*c^2*C11/(3*mu*N), eta_hat = eta*G*c^2*C22/(3*mu*N), "
                 "phi_hat = phi*G*c^2*sqrt((C11*b)^2 + (C22*a)^2)/(3*mu*N); C11, C22 = Kalker Table E.3 at "
                 "a/b clamped to [0.1, 10] (quadratic in nu); values Fx/(mu*N), Fy/(mu*N), Mz/(mu*N*c)")
BUILD_COMMAND = "python -m exudyn_wheelrail creep-table --out {path} --generator exact"

#: the interpolation orders of :func:`table_core` (``interpolation="linear"``, ``"cubic"``)
ORDER_LINEAR = 1
ORDER_CUBIC = 3


# ----------------------------------------------------------------------------------------------------------------
# normalisation
# ----------------------------------------------------------------------------------------------------------------
def normalisation_coefficients(a_over_b, poisson):
    """``(C11, C22)`` of the normalisation: Kalker's Table E.3 at ``a/b`` clamped to [0.1, 10] and ``poisson``."""
    ab = min(max(float(a_over_b), A_OVER_B_MIN), A_OVER_B_MAX)
    c11, c22, _ = kalker_coefficients(ab, poisson)
    return c11, c22


@compiled(refcount=False)
def _scales(a, b, normal_force, mu, shear_modulus, C11, C22):
    """Factors k with ``ξ̂ = kx ξ``, ``η̂ = ky η``, ``φ̂ = kp φ`` (module docstring)."""
    f = shear_modulus * a * b / (3.0 * mu * normal_force)      # G c² / (3μN)
    return f * C11, f * C22, f * math.sqrt((C11 * b) ** 2 + (C22 * a) ** 2)


def normalised_creepages(a, b, xi, eta, phi, normal_force, mu, shear_modulus, C11, C22):
    """``(ξ̂, η̂, φ̂)`` of the table's normalisation (module docstring); ``C11, C22`` from
    :func:`normalisation_coefficients`.  Requires ``normal_force > 0`` and ``mu > 0``."""
    kx, ky, kp = _scales(float(a), float(b), float(normal_force), float(mu), float(shear_modulus), float(C11),
                         float(C22))
    return kx * xi, ky * eta, kp * phi


def physical_creepages(a, b, xi_hat, eta_hat, phi_hat, normal_force, mu, shear_modulus, C11, C22):
    """Inverse of :func:`normalised_creepages`: ``(ξ, η, φ)`` for given normalised creepages."""
    kx, ky, kp = _scales(float(a), float(b), float(normal_force), float(mu), float(shear_modulus), float(C11),
                         float(C22))
    return xi_hat / kx, eta_hat / ky, phi_hat / kp


# ----------------------------------------------------------------------------------------------------------------
# compiled interpolator
# ----------------------------------------------------------------------------------------------------------------
@compiled(refcount=False)
def _interval(nodes, x):
    """Index i with nodes[i] <= x <= nodes[i+1] (clamped to the first/last interval); binary search."""
    lo = 0
    hi = nodes.size - 1
    if x <= nodes[0]:
        return 0
    if x >= nodes[hi]:
        return hi - 1
    while hi - lo > 1:
        mid = (lo + hi) >> 1
        if nodes[mid] <= x:
            lo = mid
        else:
            hi = mid
    return lo


@compiled(refcount=False)
def _weights(nodes, i, x, lo_ok, hi_ok, order):
    """Weights ``(w0, w1, w2, w3)`` on nodes ``i-1 .. i+2`` for x in [nodes[i], nodes[i+1]].

    order 1: linear (w[1], w[2]).  order 3: cubic Hermite, slope at each end of the interval from the parabola
    through that node and its two neighbours (non-uniform Catmull–Rom); ``lo_ok``/``hi_ok`` False: node i-1 /
    i+2 not usable (table end or break) -> secant slope at that end."""
    x1 = nodes[i]
    x2 = nodes[i + 1]
    h = x2 - x1
    s = (x - x1) / h
    if s < 0.0:
        s = 0.0
    elif s > 1.0:
        s = 1.0
    if order == 1:
        return 0.0, 1.0 - s, s, 0.0
    s2 = s * s
    s3 = s2 * s
    h00 = 2.0 * s3 - 3.0 * s2 + 1.0
    h10 = s3 - 2.0 * s2 + s
    h01 = -2.0 * s3 + 3.0 * s2
    h11 = s3 - s2
    # slope at x1: m1 = c10 f0 + c11 f1 + c12 f2 ; slope at x2: m2 = c21 f1 + c22 f2 + c23 f3
    if lo_ok:
        x0 = nodes[i - 1]
        al = h / (x2 - x0)
        be = (x1 - x0) / (x2 - x0)
        c10 = -al / (x1 - x0)
        c11 = al / (x1 - x0) - be / h
        c12 = be / h
    else:
        c10 = 0.0
        c11 = -1.0 / h
        c12 = 1.0 / h
    if hi_ok:
        x3 = nodes[i + 2]
        al = (x3 - x2) / (x3 - x1)
        be = h / (x3 - x1)
        c21 = -al / h
        c22 = al / h - be / (x3 - x2)
        c23 = be / (x3 - x2)
    else:
        c21 = -1.0 / h
        c22 = 1.0 / h
        c23 = 0.0
    return (h10 * h * c10, h00 + h10 * h * c11 + h11 * h * c21, h01 + h10 * h * c12 + h11 * h * c22,
            h11 * h * c23)


@compiled(refcount=False)
def table_core(a, b, xi, eta, phi, normal_force, mu, shear_modulus, C11, C22, t_nodes, t_breaks, r_nodes,
               th_nodes, ps_nodes, values, order):
    """Compiled table lookup on floats (no input checks): returns ``(Fx, Fy, Mz)`` on the wheel [N, N·m].

    ``C11, C22``: Kalker's coefficients at a/b clamped to [0.1, 10] and ν (the normalisation; e.g.
    ``kalker_coefficients_core(ln(clamped a/b), ν, ...)[:2]``).  Arrays: the *padded* arrays of a
    :class:`CreepTable` (``t_nodes`` = ln(a/b) nodes and ``t_breaks`` (int8), ``r_nodes`` with one ghost node
    below 0, ``th_nodes`` and ``ps_nodes`` with one ghost node at each end, ``values`` (n_t, n_r, n_th, n_ps, 3)).
    ``order`` 3: cubic Hermite, 1: multilinear.  ``normal_force <= 0`` or ``mu <= 0`` gives zeros; a/b outside
    the table is clamped (the Python wrapper raises instead)."""
    if normal_force <= 0.0 or mu <= 0.0:
        return 0.0, 0.0, 0.0
    kx, ky, kp = _scales(a, b, normal_force, mu, shear_modulus, C11, C22)
    vx = kx * xi
    vy = ky * eta
    vp = kp * phi
    sx = 1.0
    sy = 1.0
    if vx < 0.0:
        vx = -vx
        sx = -1.0
    if vy < 0.0:
        vy = -vy
        vp = -vp
        sy = -1.0
    rho = math.sqrt(vx * vx + vy * vy)
    r = math.sqrt(rho * rho + vp * vp)
    if r == 0.0:
        return 0.0, 0.0, 0.0
    th = math.atan2(vy, vx)
    ps = math.atan2(vp, rho)
    nr = r_nodes.size
    if r > r_nodes[nr - 1]:
        r = r_nodes[nr - 1]
    t = math.log(a / b)
    nt = t_nodes.size
    if t < t_nodes[0]:
        t = t_nodes[0]
    elif t > t_nodes[nt - 1]:
        t = t_nodes[nt - 1]
    # t: no ghosts, breaks stop the stencil
    it = _interval(t_nodes, t)
    wt = _weights(t_nodes, it, t, it > 0 and t_breaks[it] == 0, it + 2 < nt and t_breaks[it + 1] == 0, order)
    # r: ghost at index 0 (-r1), node r=0 at index 1; secant at r_max
    ir = _interval(r_nodes, r)
    if ir < 1:
        ir = 1
    wr = _weights(r_nodes, ir, r, True, ir + 2 < nr, order)
    # theta, psi: ghosts at both ends
    ith = _interval(th_nodes, th)
    if ith < 1:
        ith = 1
    elif ith > th_nodes.size - 3:
        ith = th_nodes.size - 3
    wth = _weights(th_nodes, ith, th, True, True, order)
    ips = _interval(ps_nodes, ps)
    if ips < 1:
        ips = 1
    elif ips > ps_nodes.size - 3:
        ips = ps_nodes.size - 3
    wps = _weights(ps_nodes, ips, ps, True, True, order)
    if order != ORDER_CUBIC:
        return _linear_sum(values, it, ir, ith, ips, wt, wr, wth, wps, sx, sy, mu * normal_force, math.sqrt(a * b))
    fx = 0.0
    fy = 0.0
    mz = 0.0
    # a zero weight of t or r skips its node (it may lie outside the table: t has no ghosts, r none above r_max);
    # theta and psi always have all four nodes (ghosts at both ends): no test in the inner loops, which run
    # branch-free (twice as fast along a run, measured; the sum is the same, term by term in the same order)
    for p in range(4):
        w1 = wt[p]
        if w1 == 0.0:
            continue
        k1 = it - 1 + p
        for q in range(4):
            w2 = w1 * wr[q]
            if w2 == 0.0:
                continue
            k2 = ir - 1 + q
            for u in range(4):
                w3 = w2 * wth[u]
                v = values[k1, k2, ith - 1 + u]
                for m in range(4):
                    w4 = w3 * wps[m]
                    fx += w4 * v[ips - 1 + m, 0]
                    fy += w4 * v[ips - 1 + m, 1]
                    mz += w4 * v[ips - 1 + m, 2]
    muN = mu * normal_force
    return sx * fx * muN, sy * fy * muN, sy * mz * muN * math.sqrt(a * b)


@compiled(refcount=False)
def _linear_sum(values, it, ir, ith, ips, wt, wr, wth, wps, sx, sy, muN, c):
    """The multilinear order's sum of :func:`table_core`: the 16 nodes its weights reach (the middle two of each
    axis's four)."""
    fx = 0.0
    fy = 0.0
    mz = 0.0
    for p in range(1, 3):
        w1 = wt[p]
        if w1 == 0.0:
            continue
        for q in range(1, 3):
            w2 = w1 * wr[q]
            if w2 == 0.0:
                continue
            for u in range(1, 3):
                w3 = w2 * wth[u]
                v = values[it - 1 + p, ir - 1 + q, ith - 1 + u]
                for m in range(1, 3):
                    w4 = w3 * wps[m]
                    fx += w4 * v[ips - 1 + m, 0]
                    fy += w4 * v[ips - 1 + m, 1]
                    mz += w4 * v[ips - 1 + m, 2]
    return sx * fx * muN, sy * fy * muN, sy * mz * muN * c


# ----------------------------------------------------------------------------------------------------------------
# table object, file format
# ----------------------------------------------------------------------------------------------------------------
@dataclass
class CreepTable:
    """A loaded creep table: the node lists and values as stored (``ratio_nodes`` … ``values``), the metadata,
    and the padded arrays of the compiled core (``t_nodes``, ``t_breaks``, ``r_pad``, ``th_pad``, ``ps_pad``,
    ``values_pad``: pass them to :func:`table_core`)."""
    ratio_nodes: np.ndarray
    ratio_breaks: np.ndarray
    r_nodes: np.ndarray
    theta_nodes: np.ndarray
    psi_nodes: np.ndarray
    values: np.ndarray
    metadata: dict
    path: Path | None = None
    t_nodes: np.ndarray = field(init=False, repr=False)
    t_breaks: np.ndarray = field(init=False, repr=False)
    r_pad: np.ndarray = field(init=False, repr=False)
    th_pad: np.ndarray = field(init=False, repr=False)
    ps_pad: np.ndarray = field(init=False, repr=False)
    values_pad: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        _check_grid(self.ratio_nodes, self.ratio_breaks, self.r_nodes, self.theta_nodes, self.psi_nodes)
        shape = (self.ratio_nodes.size, self.r_nodes.size, self.theta_nodes.size, self.psi_nodes.size, 3)
        if self.values.shape != shape:
            raise ValueError(f"table values have shape {self.values.shape}, expected {shape}")
        if not np.all(np.isfinite(self.values)):
            raise ValueError("table values contain NaN/inf (incomplete build?)")
        self.t_nodes = np.log(self.ratio_nodes)
        self.t_breaks = np.ascontiguousarray(self.ratio_breaks, dtype=np.int8)
        self.r_pad, self.th_pad, self.ps_pad, self.values_pad = pad_table(self.r_nodes, self.theta_nodes,
                                                                         self.psi_nodes, self.values)

    @property
    def poisson(self) -> float:
        return float(self.metadata["poisson"])

    @property
    def generator(self) -> str:
        return str(self.metadata["generator"])

    @property
    def ratio_range(self):
        return float(self.ratio_nodes[0]), float(self.ratio_nodes[-1])

    @property
    def r_max(self) -> float:
        return float(self.r_nodes[-1])

    def core_arrays(self):
        """``(t_nodes, t_breaks, r_pad, th_pad, ps_pad, values_pad)`` in the argument order of :func:`table_core`."""
        return self.t_nodes, self.t_breaks, self.r_pad, self.th_pad, self.ps_pad, self.values_pad


def _check_grid(ratio_nodes, ratio_breaks, r_nodes, theta_nodes, psi_nodes):
    ratio_nodes = np.asarray(ratio_nodes, float)
    if ratio_nodes.ndim != 1 or ratio_nodes.size < 2 or np.any(np.diff(ratio_nodes) <= 0) or ratio_nodes[0] <= 0:
        raise ValueError("ratio_nodes must be >= 2 positive ascending values")
    if np.asarray(ratio_breaks).shape != ratio_nodes.shape:
        raise ValueError("ratio_breaks must have the shape of ratio_nodes")
    r_nodes = np.asarray(r_nodes, float)
    if r_nodes.ndim != 1 or r_nodes.size < 3 or r_nodes[0] != 0.0 or np.any(np.diff(r_nodes) <= 0):
        raise ValueError("r_nodes must start at 0 and ascend (>= 3 nodes)")
    th = np.asarray(theta_nodes, float)
    if th.size < 3 or abs(th[0]) > 1e-15 or abs(th[-1] - math.pi / 2) > 1e-12 or np.any(np.diff(th) <= 0):
        raise ValueError("theta_nodes must ascend from 0 to pi/2 (>= 3 nodes)")
    ps = np.asarray(psi_nodes, float)
    if (ps.size < 3 or abs(ps[0] + math.pi / 2) > 1e-12 or abs(ps[-1] - math.pi / 2) > 1e-12
            or np.any(np.diff(ps) <= 0) or not np.allclose(ps, -ps[::-1], rtol=0, atol=1e-12)):
        raise ValueError("psi_nodes must ascend from -pi/2 to pi/2, symmetric about 0 (>= 3 nodes)")


def pad_table(r_nodes, theta_nodes, psi_nodes, values):
    """Add the ghost nodes of the symmetry continuation (module docstring) around the stored values.

    Returns ``(r_pad, th_pad, ps_pad, values_pad)``: r gets one node ``-r[1]`` below 0 with ``-F(r[1])``; ψ one
    node beyond each pole (``-π - ψ[1]`` with ``-F(θ, -ψ[1])`` …); θ one node below 0 (``-θ[1]``: (fx, -fy, -mz)
    at ``(θ[1], -ψ)``) and one above π/2 (``π - θ[-2]``: (-fx, fy, mz) at ``θ[-2]``)."""
    r = np.asarray(r_nodes, float)
    th = np.asarray(theta_nodes, float)
    ps = np.asarray(psi_nodes, float)
    v = np.asarray(values, float)
    nps = ps.size
    # psi: ghost below -pi/2 = -F(theta, psi[nps-2]) (psi[nps-2] = -psi[1]); above pi/2 = -F(theta, psi[1])
    ps_pad = np.concatenate(([-math.pi - ps[1]], ps, [math.pi - ps[-2]]))
    v1 = np.concatenate((-v[:, :, :, nps - 2:nps - 1], v, -v[:, :, :, 1:2]), axis=3)
    # theta: ghost below 0 at psi_j = (fx, -fy, -mz)(theta[1], -psi_j); psi_pad is symmetric -> reversed index
    sign_lo = np.array([1.0, -1.0, -1.0])
    sign_hi = np.array([-1.0, 1.0, 1.0])
    lo = v1[:, :, 1:2, ::-1, :] * sign_lo
    hi = v1[:, :, -2:-1, :, :] * sign_hi
    th_pad = np.concatenate(([-th[1]], th, [math.pi - th[-2]]))
    v2 = np.concatenate((lo, v1, hi), axis=2)
    # r: ghost below 0 = -F(r[1])
    r_pad = np.concatenate(([-r[1]], r))
    v3 = np.concatenate((-v2[:, 1:2], v2), axis=1)
    return (np.ascontiguousarray(r_pad), np.ascontiguousarray(th_pad), np.ascontiguousarray(ps_pad),
            np.ascontiguousarray(v3))


def _cij_at_nodes(ratio_nodes, poisson):
    return np.array([normalisation_coefficients(ab, poisson) for ab in ratio_nodes])


def save_table(path, ratio_nodes, ratio_breaks, r_nodes, theta_nodes, psi_nodes, values, metadata: dict):
    """Write a table file (format version 1, compressed npz); the file is replaced atomically."""
    path = Path(path)
    _check_grid(ratio_nodes, ratio_breaks, r_nodes, theta_nodes, psi_nodes)
    meta = dict(metadata)
    meta.setdefault("format", FORMAT)
    meta.setdefault("format_version", FORMAT_VERSION)
    meta.setdefault("normalisation", NORMALISATION)
    for key in ("generator", "poisson"):
        if key not in meta:
            raise ValueError(f"metadata must contain {key!r}")
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp.npz")
    np.savez_compressed(
        tmp, ratio_nodes=np.asarray(ratio_nodes, float), ratio_breaks=np.asarray(ratio_breaks, bool),
        r_nodes=np.asarray(r_nodes, float), theta_nodes=np.asarray(theta_nodes, float),
        psi_nodes=np.asarray(psi_nodes, float), values=np.asarray(values, float),
        cij_check=_cij_at_nodes(ratio_nodes, float(meta["poisson"])),
        metadata_json=np.array(json.dumps(meta, sort_keys=True)))
    tmp.replace(path)
    return path


def _missing_message(path: Path) -> str:
    return (f"creep table file not found: {path}\n"
            f"Build it (Kalker's exact theory; about 40-60 min on 2 cores at the default grid) with:\n"
            f"    {BUILD_COMMAND.format(path=path)}\n"
            f"or, for development only, a FASTSIM stand-in table (seconds) with:\n"
            f"    python -m exudyn_wheelrail creep-table --generator fastsim --out {FASTSIM_TABLE_PATH}\n"
            f"and pass table=load_table(that path).")


def load_table(path=None) -> CreepTable:
    """Read a creep table file (default: the package table ``exudyn_wheelrail/data/creep_table.npz``).

    Raises ``FileNotFoundError`` (with the command that builds it) if the file is missing, ``ValueError`` if it
    is not a valid table of this format or if its normalisation coefficients do not match the package's Kalker
    Table E.3 any more (then rebuild the table)."""
    path = Path(path) if path is not None else TABLE_PATH
    if not path.is_file():
        raise FileNotFoundError(_missing_message(path))
    try:
        with np.load(path, allow_pickle=False) as z:
            d = {k: z[k] for k in z.files}
    except (OSError, ValueError) as exc:
        raise ValueError(f"{path}: not a readable npz creep table ({exc})") from exc
    need = ("ratio_nodes", "ratio_breaks", "r_nodes", "theta_nodes", "psi_nodes", "values", "cij_check",
            "metadata_json")
    missing = [k for k in need if k not in d]
    if missing:
        raise ValueError(f"{path}: not a creep table (missing {missing})")
    meta = json.loads(str(d["metadata_json"]))
    if meta.get("format") != FORMAT or int(meta.get("format_version", -1)) != FORMAT_VERSION:
        raise ValueError(f"{path}: format {meta.get('format')!r} v{meta.get('format_version')} is not "
                         f"{FORMAT!r} v{FORMAT_VERSION}")
    if meta.get("normalisation") != NORMALISATION:
        raise ValueError(f"{path}: built with normalisation {meta.get('normalisation')!r}, this package uses "
                         f"{NORMALISATION!r}; rebuild the table")
    cij = _cij_at_nodes(d["ratio_nodes"], float(meta["poisson"]))
    if cij.shape != d["cij_check"].shape or not np.allclose(cij, d["cij_check"], rtol=1e-9, atol=0):
        raise ValueError(f"{path}: Kalker coefficients of the normalisation differ from the ones the table was "
                         f"built with (linear.py or its data changed); rebuild the table")
    return CreepTable(np.asarray(d["ratio_nodes"], float), np.asarray(d["ratio_breaks"], bool),
                      np.asarray(d["r_nodes"], float), np.asarray(d["theta_nodes"], float),
                      np.asarray(d["psi_nodes"], float), np.asarray(d["values"], float), meta, path)


_CACHE: dict = {}


def _default_table(path=None) -> CreepTable:
    key = str(Path(path).resolve()) if path is not None else str(TABLE_PATH)
    tab = _CACHE.get(key)
    if tab is None:
        tab = load_table(path)
        _CACHE[key] = tab
    return tab


# ----------------------------------------------------------------------------------------------------------------
# public lookup
# ----------------------------------------------------------------------------------------------------------------

def table_forces(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson, table=None,
                 interpolation: str = "cubic"):
    """Creep forces interpolated in a USETAB-style table: ``(Fx, Fy, Mz)`` in N and N·m, forces **on the
    wheel**, contact frame, ``a`` [m] semi-axis along rolling, ``b`` [m] lateral, creepages ξ, η [-], φ [1/m]
    (Kalker's signs, see the module docstring).

    ``table``: a :class:`CreepTable`, a path to a table file, or None for the package table
    ``exudyn_wheelrail/data/creep_table.npz`` (``FileNotFoundError`` telling how to build it when missing).
    ``interpolation``: ``"cubic"`` (default) or ``"linear"``.  A table given by path is loaded once and cached
    per path.

    Raises ``ValueError`` for non-finite input, a, b <= 0, N < 0, μ < 0, G <= 0, a/b outside the table's range,
    or ``|ν - ν_table| > NU_TOLERANCE``.  ``normal_force == 0`` or ``mu == 0`` gives zeros.  Creepages beyond the
    table are scaled back onto its edge keeping their direction (module docstring)."""
    a, b, xi, eta, phi, N, mu, G = check_contact_inputs(a, b, xi, eta, phi, normal_force, mu, shear_modulus)
    nu = table_poisson(poisson)
    if interpolation == "cubic":
        order = ORDER_CUBIC
    elif interpolation == "linear":
        order = ORDER_LINEAR
    else:
        raise ValueError(f"interpolation must be 'cubic' or 'linear', got {interpolation!r}")
    if table is None or isinstance(table, (str, Path)):
        table = _default_table(table)
    elif not isinstance(table, CreepTable):
        raise ValueError(f"table must be a CreepTable, a path or None, got {type(table).__name__}")
    lo, hi = table.ratio_range
    ab = a / b
    if ab < lo * (1 - 1e-12) or ab > hi * (1 + 1e-12):
        raise ValueError(f"a/b = {ab:g} is outside the creep table's range [{lo:g}, {hi:g}]")
    if abs(nu - table.poisson) > NU_TOLERANCE + 1e-12:
        raise ValueError(f"poisson = {nu:g}: the creep table was built for nu = {table.poisson:g} and accepts "
                         f"|nu - {table.poisson:g}| <= {NU_TOLERANCE:g} (build a table for this nu)")
    if N == 0.0 or mu == 0.0:
        return 0.0, 0.0, 0.0
    C11, C22 = normalisation_coefficients(ab, nu)
    return table_core(a, b, xi, eta, phi, N, mu, G, C11, C22, *table.core_arrays(), order)
