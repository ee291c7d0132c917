"""The creep table's cubic interpolant (``creep.table.table_core``) on non-uniform nodes, and the shipped table
between its nodes against Kalker's exact theory.

The interpolant (module docstring of ``creep.table``): per axis a piecewise-cubic Hermite interpolant whose slope
at a node is the derivative of the parabola through that node and its two neighbours; tensor product over the
axes t = ln(a/b), r, θ, ψ of the normalised creepage.  Independent references:

* **C¹ continuity** (a property of the construction): along every axis, the one-sided difference quotients left and
  right of an interior node differ only by the curvature of the cubic pieces over the step δ.  For a cubic Hermite
  piece on [x1, x2] with parabola slopes, ``p''(x1+) = 4 f[x0,x1,x2] - 2 f[x1,x2,x3]`` and ``p''(x2-) =
  -2 f[x0,x1,x2] + 4 f[x1,x2,x3]`` (f[...] the second divided differences of the node values; a secant end slope
  drops its term), ``|p'''| <= 12 max|f[...]| / h``, so
  ``|D+ - D-| <= 6 δ M + 4 δ² M / h_min`` with M the largest second divided difference of the node values around
  the node (Taylor expansion of each cubic piece, exact to third order).  Slopes that are not one derivative
  shared by both neighbouring intervals give a jump of D+ - D- that does not vanish with δ.
* **exactness for quadratics**: the parabola through three nodes of a quadratic is the quadratic itself, so the
  slopes are exact and the cubic Hermite interpolant reproduces the quadratic wherever both end slopes are
  parabola slopes (not at table ends, where the slope is a secant); tensor product: a sum of products of
  quadratics in each axis is reproduced exactly (analytic reference).  Only non-uniform nodes test the weights:
  on uniform nodes the parabola slope is the central difference, whichever way its weights are assigned.
* **Kalker's exact theory** (``creep.kalker_exact``, run with the generator options the shipped table was built
  with, so that only the interpolation is compared) at points midway between the table's nodes in every axis.

Lookups go through the compiled core with physical inputs built here from the documented normalisation
(``ξ̂ = ξ G c² C11 / (3μN)``, ``η̂ = η G c² C22 / (3μN)``, ``φ̂ = φ G c² √((C11 b)² + (C22 a)²) / (3μN)``);
in the core C11, C22 are inputs, so arbitrary values serve for the synthetic tables.
"""
import math

import numpy as np
import pytest

from exudyn_wheelrail.creep.kalker_exact import kalker_exact
from exudyn_wheelrail.creep.table import (ORDER_CUBIC, ORDER_LINEAR, load_table, normalisation_coefficients,
                                          table_core, table_forces)

G, N, MU, C_REF, NU = 8.1e10, 2.5e4, 0.4, 7e-3, 0.28
EPS = np.finfo(float).eps


# ----------------------------------------------------------------------------------------------------------------
# lookups at normalised coordinates (t, r, θ, ψ)
# ----------------------------------------------------------------------------------------------------------------
def _physical(t, r, th, ps, C11, C22, c=C_REF):
    """(a, b, ξ, η, φ) whose normalised coordinates are (t = ln(a/b), r, θ, ψ), with c = √(ab)."""
    a, b = c * math.exp(0.5 * t), c * math.exp(-0.5 * t)
    f = G * a * b / (3 * MU * N)
    kx, ky, kp = f * C11, f * C22, f * math.sqrt((C11 * b) ** 2 + (C22 * a) ** 2)
    v = r * np.array([math.cos(ps) * math.cos(th), math.cos(ps) * math.sin(th), math.sin(ps)])
    return a, b, v[0] / kx, v[1] / ky, v[2] / kp


def lookup(arrays, point, C11=3.9, C22=3.4, order=ORDER_CUBIC):
    """Table value (Fx/(μN), Fy/(μN), Mz/(μNc)) of the compiled core at point = (t, r, θ, ψ)."""
    a, b, xi, eta, phi = _physical(*point, C11, C22)
    F = table_core(a, b, xi, eta, phi, N, MU, G, C11, C22, *arrays, order)
    return np.array(F) / (MU * N) * [1.0, 1.0, 1.0 / math.sqrt(a * b)]


def _second_divided_differences(x, f):
    """f[x_i, x_{i+1}, x_{i+2}] for every i; f (n, 3)."""
    d1 = np.diff(f, axis=0) / np.diff(x)[:, None]
    return np.diff(d1, axis=0) / (x[2:] - x[:-2])[:, None]


def kink(arrays, axis, k, idx):
    """One-sided difference quotients at node k of ``axis`` (index into that axis' array of ``arrays``), the other
    coordinates at the nodes ``idx`` (indices into their arrays).  Returns (|D+ - D-| per component, tolerance)."""
    t_nodes, _, r_pad, th_pad, ps_pad, values = arrays
    axes = (t_nodes, r_pad, th_pad, ps_pad)
    nodes = axes[axis]
    idx = list(idx)
    idx[axis] = k
    point = [axes[i][idx[i]] for i in range(4)]
    x = nodes[k]
    h_min = min(x - nodes[k - 1], nodes[k + 1] - x)
    delta = 1e-4 * h_min
    F0 = lookup(arrays, point)
    Fm = lookup(arrays, [x - delta if i == axis else point[i] for i in range(4)])
    Fp = lookup(arrays, [x + delta if i == axis else point[i] for i in range(4)])
    jump = np.abs((Fp - F0) / delta - (F0 - Fm) / delta)
    # the curvature bound from the node values along the axis (the data the interpolant uses)
    sl = [idx[0], idx[1], idx[2], idx[3]]
    sl[axis] = slice(max(k - 2, 0), min(k + 3, nodes.size))
    f_line = values[tuple(sl)]
    M = np.abs(_second_divided_differences(nodes[sl[axis]], f_line)).max(axis=0)
    # round-off: each lookup sums 256 weighted values (≤ 64 ε of the largest value, weights ≤ ~1.3 per axis) and
    # its coordinates pass through a/b, c, atan2, sqrt (a few ε relative: ≤ 16 ε |x| times the slope, bounded by
    # 1.5 max |first divided difference|); two lookups per quotient, divided by δ
    d1 = np.abs(np.diff(f_line, axis=0) / np.diff(nodes[sl[axis]])[:, None]).max(axis=0)
    noise = 2 * (64 * EPS * np.abs(f_line).max() + 16 * EPS * max(abs(x), 1.0) * 1.5 * d1) / delta
    return jump, 6 * delta * M + 4 * delta ** 2 * M / h_min + noise


# ----------------------------------------------------------------------------------------------------------------
# (a) C¹ continuity
# ----------------------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def shipped():
    return load_table()


def _interior_t(tab):
    """t nodes with a smooth stencil on both sides: interior, not a break node (the kinks of the normalisation)."""
    return [k for k in range(1, tab.t_nodes.size - 1) if not tab.t_breaks[k]]


def test_shipped_table_is_c1_along_r_at_every_interior_node(shipped):
    """r: the non-uniform axis of the shipped table (dense in the adhesion–saturation transition, geometric beyond);
    every interior node (including r_1 next to r = 0, whose left neighbour is the symmetry ghost), 45 lines."""
    arrays = shipped.core_arrays()
    r_pad = shipped.r_pad
    n_checked = 0
    for it in (3, 6, 9):
        for ith in (2, 6, 9):                       # padded indices (ghost at 0)
            for ips in (2, 9, 15, 20, 28):
                for k in range(2, r_pad.size - 1):  # padded: 0 ghost, 1 r = 0, last r_max
                    jump, tol = kink(arrays, 1, k, (it, 0, ith, ips))
                    assert np.all(jump <= tol), (it, r_pad[k], ith, ips, jump, tol)
                    n_checked += 1
    assert n_checked == 45 * 26


@pytest.mark.parametrize("axis", [0, 2, 3], ids=["t", "theta", "psi"])
def test_shipped_table_is_c1_along_t_theta_psi(shipped, axis):
    arrays = shipped.core_arrays()
    nodes = (shipped.t_nodes, shipped.r_pad, shipped.th_pad, shipped.ps_pad)[axis]
    if axis == 0:
        ks = _interior_t(shipped)
    else:                                           # padded arrays: interior nodes between the two end nodes
        ks = range(2, nodes.size - 2)
    for k in ks:
        for it in (1, 6, 9):
            for ir in (6, 14, 20, 23):
                for ith in (3, 8):
                    for ips in (4, 13, 24):
                        jump, tol = kink(arrays, axis, k, (it, ir, ith, ips))
                        assert np.all(jump <= tol), (axis, nodes[k], (it, ir, ith, ips), jump, tol)


def _synthetic_nodes():
    """Strongly non-uniform nodes on every axis (neighbouring steps differ by factors 2–8), with the padded layout
    of the core: r with a ghost below 0, θ and ψ with a ghost beyond each end."""
    t_nodes = -2.0 + np.cumsum([0.0, 0.3, 0.9, 0.4, 1.2, 0.5, 0.8])
    r_nodes = np.array([0.0, 0.2, 0.5, 1.4, 2.0, 4.5, 6.0])
    r_pad = np.concatenate(([-0.2], r_nodes))
    th_pad = np.array([-0.2, 0.0, 0.2, 0.55, 0.7, 1.2, math.pi / 2, math.pi / 2 + 0.4])
    ps_pad = np.array([-math.pi / 2 - 0.3, -math.pi / 2, -1.0, -0.7, 0.1, 0.3, 1.1, math.pi / 2, math.pi / 2 + 0.25])
    return t_nodes, r_pad, th_pad, ps_pad


def _fill(nodes, func):
    t, r, th, ps = np.meshgrid(*nodes, indexing="ij")
    return np.ascontiguousarray(np.stack(func(t, r, th, ps), axis=-1))


def _smooth(t, r, th, ps):
    """A smooth, non-polynomial function: its parabola slopes are inexact, so wrong slope weights show."""
    g = np.exp(-0.4 * r) * (1.0 + 0.3 * np.sin(2.0 * ps))
    return (np.sin(0.7 * t + 0.3) * g * np.cos(1.3 * th),
            np.cos(0.5 * t) * (1.0 - np.exp(-r)) * np.sin(th + 0.2 * ps),
            np.exp(0.2 * t) * g * np.sin(1.7 * ps - 0.4) * (1.0 + 0.2 * th * th))


def _synthetic_arrays(func, nodes=None):
    t_nodes, r_pad, th_pad, ps_pad = nodes if nodes is not None else _synthetic_nodes()
    values = _fill((t_nodes, r_pad, th_pad, ps_pad), func)
    return (np.ascontiguousarray(t_nodes), np.zeros(t_nodes.size, np.int8), np.ascontiguousarray(r_pad),
            np.ascontiguousarray(th_pad), np.ascontiguousarray(ps_pad), values)


@pytest.mark.parametrize("axis", [0, 1, 2, 3], ids=["t", "r", "theta", "psi"])
def test_synthetic_non_uniform_table_is_c1_along_every_axis(axis):
    arrays = _synthetic_arrays(_smooth)
    nodes = arrays[(0, 2, 3, 4)[axis]]
    # interior nodes: t 1 … n-2; r (padded) from r_1 to the node before r_max; θ, ψ (padded) between the end nodes
    ks = {0: range(1, nodes.size - 1), 1: range(2, nodes.size - 1)}.get(axis, range(2, nodes.size - 2))
    n_checked = 0
    for k in ks:
        for it in (1, 3, 5):
            for ir in (2, 4, 6):
                for ith in (2, 4, 5):
                    for ips in (2, 4, 6):
                        jump, tol = kink(arrays, axis, k, (it, ir, ith, ips))
                        assert np.all(jump <= tol), (axis, nodes[k], (it, ir, ith, ips), jump, tol)
                        n_checked += 1
    assert n_checked >= 100


# ----------------------------------------------------------------------------------------------------------------
# (b) exact for quadratics on non-uniform nodes
# ----------------------------------------------------------------------------------------------------------------
def _quadratic_factory(nodes):
    """Sums of products of quadratics in each axis, in coordinates scaled to the axis' span (values O(1))."""
    lo = [n[0] for n in nodes]
    span = [n[-1] - n[0] for n in nodes]

    def func(t, r, th, ps):
        u = [(x - l) / s for x, l, s in zip((t, r, th, ps), lo, span)]
        q = [1.0 + 0.7 * u[0] - 1.3 * u[0] ** 2, 0.4 - 1.1 * u[1] + 1.9 * u[1] ** 2,
             -0.2 + 1.6 * u[2] - 1.4 * u[2] ** 2, 0.9 + 0.5 * u[3] + 1.2 * u[3] ** 2]
        return (q[0] * q[1] * q[2] * q[3],
                q[0] * q[2] + 2.0 * q[1] * q[3] - u[1] ** 2 * u[2] ** 2,
                (1.0 - u[0] ** 2) * (u[1] - 0.5 * u[3] ** 2) + q[2] * u[3] ** 2 * u[0])
    return func


def _interior_points(nodes, n, seed):
    """Random points where every axis interpolates between two parabola slopes: t not in the first or last
    interval, r below the last interval (secant at r_max), θ ∈ [0, π/2], ψ ∈ [-π/2, π/2]."""
    t_nodes, r_pad, _, _ = nodes
    rng = np.random.default_rng(seed)
    return np.column_stack((rng.uniform(t_nodes[1], t_nodes[-2], n), rng.uniform(0.0, r_pad[-2], n),
                            rng.uniform(0.0, math.pi / 2, n), rng.uniform(-math.pi / 2, math.pi / 2, n)))


@pytest.mark.parametrize("node_set", ["synthetic", "shipped"])
def test_cubic_hermite_reproduces_quadratics_on_non_uniform_nodes(node_set, shipped):
    if node_set == "synthetic":
        nodes = _synthetic_nodes()
    else:                                          # the shipped table's node sets (its r nodes are non-uniform)
        nodes = (shipped.t_nodes, shipped.r_pad, shipped.th_pad, shipped.ps_pad)
    func = _quadratic_factory(nodes)
    arrays = _synthetic_arrays(func, nodes)
    points = _interior_points(nodes, 400, seed=11)
    # also points near every node of the non-uniform r axis, where neighbouring steps differ most
    r_near = np.repeat(nodes[1][2:-2], 4) * np.tile([0.9, 0.999, 1.001, 1.1], nodes[1].size - 4)
    extra = _interior_points(nodes, r_near.size, seed=12)
    extra[:, 1] = np.minimum(r_near, nodes[1][-2])
    points = np.vstack((points, extra))
    vmax = np.abs(arrays[5]).max()
    for p in points:
        ref = np.array(func(*p))
        err = np.abs(lookup(arrays, p) - ref)
        # round-off of 256 weighted values (weights ≤ ~1.3 per axis, so Σ|w| ≤ 3) and of the coordinates' round
        # trip through the physical inputs (a few ε relative, times slopes of O(1/span)): 256 ε of the largest value
        assert np.all(err <= 256 * EPS * vmax), (p, err)


def _multilinear_factory(nodes):
    """Sums of products of functions affine in each axis (scaled coordinates): what multilinear interpolation
    reproduces exactly."""
    lo = [n[0] for n in nodes]
    span = [n[-1] - n[0] for n in nodes]

    def func(t, r, th, ps):
        u = [(x - l) / s for x, l, s in zip((t, r, th, ps), lo, span)]
        return ((1.0 + 0.7 * u[0]) * (0.4 - 1.1 * u[1]) * (-0.2 + 1.6 * u[2]) * (0.9 + 0.5 * u[3]),
                u[0] * u[2] + 2.0 * u[1] * u[3] - u[1] * u[2] * u[3],
                (1.0 - u[0]) * (u[1] - 0.5 * u[3]) + u[2] * u[3] * u[0])
    return func


@pytest.mark.parametrize("node_set", ["synthetic", "shipped"])
def test_multilinear_order_reproduces_multilinear_functions_on_non_uniform_nodes(node_set, shipped):
    """The multilinear order (the ``table_linear`` law) sums only the 16 nodes its weights reach: it must still be
    the multilinear interpolant, exact for functions affine in each axis, in every interval (ends included)."""
    nodes = _synthetic_nodes() if node_set == "synthetic" else (shipped.t_nodes, shipped.r_pad, shipped.th_pad,
                                                                  shipped.ps_pad)
    func = _multilinear_factory(nodes)
    arrays = _synthetic_arrays(func, nodes)
    t_nodes, r_pad = nodes[0], nodes[1]
    rng = np.random.default_rng(21)
    points = np.column_stack((rng.uniform(t_nodes[0], t_nodes[-1], 400), rng.uniform(0.0, r_pad[-1], 400),
                              rng.uniform(0.0, math.pi / 2, 400), rng.uniform(-math.pi / 2, math.pi / 2, 400)))
    vmax = np.abs(arrays[5]).max()
    for p in points:
        err = np.abs(lookup(arrays, p, order=ORDER_LINEAR) - np.array(func(*p)))
        # round-off of 16 values with weights summing to 1 (≤ 16 ε of the largest value) and of the coordinates'
        # round trip through the physical inputs (a few ε relative times slopes of O(1/span)): twice that
        assert np.all(err <= 64 * EPS * vmax), (p, err)


# ----------------------------------------------------------------------------------------------------------------
# (c) the shipped table between its nodes against Kalker's exact theory
# ----------------------------------------------------------------------------------------------------------------
# Documented accuracy of the shipped table against the exact solver (docs/validation.md, table "Creep forces", with
# this test's measured worst case): limits 2 % of μN (forces) and 2 % of μNc (spin moment) at any point, 0.5 % RMS.
# Points midway between nodes in every axis are where a piecewise-cubic interpolant errs most, so the limits are
# checked there, on the radial intervals from the linear range (r ≈ 0.005) to full sliding (r ≈ 21), in three a/b
# intervals.
MAX_ERR, RMS_ERR = 0.02, 0.005
#: the same for the multilinear order (the ``table_linear`` law; docs/validation.md): 4 % and 1 %
MAX_ERR_LINEAR, RMS_ERR_LINEAR = 0.04, 0.01


def test_shipped_table_midway_between_nodes_against_the_exact_theory(shipped):
    opts = {k: shipped.metadata["generator_options"][k] for k in ("n_x", "n_y", "tol")}
    t, r, th, ps = shipped.t_nodes, shipped.r_nodes, shipped.theta_nodes, shipped.psi_nodes
    errs = []
    n_dir = 0
    for it in (3, 6, 9):                                  # a/b midway in 0.18–0.32, 1–1.78, 5.6–10
        t_mid = 0.5 * (t[it] + t[it + 1])
        ab = math.exp(t_mid)
        C11, C22 = normalisation_coefficients(ab, NU)
        for j in range(1, 22):                            # r midway in [r_j, r_j+1], r_j = 0.001 … 13.8
            r_mid = 0.5 * (r[j] + r[j + 1])
            for m in range(2):
                kt = (5 * j + 7 * m + it) % (th.size - 1)     # θ and ψ intervals taken in turn
                kp = (11 * j + 13 * m + 3 * it) % (ps.size - 1)
                n_dir += 1
                th_mid, ps_mid = 0.5 * (th[kt] + th[kt + 1]), 0.5 * (ps[kp] + ps[kp + 1])
                a, b, xi, eta, phi = _physical(t_mid, r_mid, th_mid, ps_mid, C11, C22)
                ref = np.array(kalker_exact(a, b, xi, eta, phi, N, MU, G, NU, **opts))
                for interpolation in ("cubic", "linear"):
                    tab = np.array(table_forces(a, b, xi, eta, phi, N, MU, G, NU, interpolation=interpolation))
                    errs.append((math.hypot(*(tab[:2] - ref[:2])) / (MU * N),
                                 abs(tab[2] - ref[2]) / (MU * N * math.sqrt(a * b))))
    e = np.array(errs).reshape(-1, 2, 2)
    assert e.shape[0] == n_dir == 126
    for k, (max_err, rms_err) in enumerate(((MAX_ERR, RMS_ERR), (MAX_ERR_LINEAR, RMS_ERR_LINEAR))):
        assert e[:, k].max(axis=0).max() <= max_err, (k, e[:, k].max(axis=0))
        assert np.sqrt(np.mean(e[:, k] ** 2, axis=0)).max() <= rms_err, (k, np.sqrt(np.mean(e[:, k] ** 2, axis=0)))
