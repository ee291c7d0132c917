r"""The mode shapes of a deck under a wheel: the plain-array modal basis (:class:`ShapeTable`), its compiled
interpolation at a track distance (:func:`modal_shape_at`, :func:`modal_shape_and_slope_at`, :func:`rail_state_at`)
and the projection of rail forces on the modal coordinates (:func:`project_shapes`, :func:`add_projected_force`).
The bridge deck (:class:`~.bridge.BridgeModes`) and the flexible track
(:class:`~exudyn_wheelrail.track.flexible.FlexibleTrackModes`) both give their modes as a :class:`ShapeTable`.

Rail kinematics (derivation; frames of :mod:`.bridge`: deck coordinate ``x = s - start_m``, y right, z down).
A deck point at ``r = (0, y_r, -e_z)`` from the axis moves by ``u + θ × r``:
``Δy = v - r_z θx = v + e_z θx`` and ``Δz = w + y_r θx``.  Hence a positive torsion (right-hand about +x: the
right side, y > 0, goes down) moves the top of rail to the **right** by ``e_z θx``.  The quantities the contact
needs at track distance s are the displacement of the **track centre line at rail-top level** and the rail roll:

    ``y_rail = v + e_z θx``,   ``z_rail = w``,   ``θ_rail = θx``

(the rail at lateral position ``y_c`` moves down by ``z_rail + y_c θ_rail``).  In modal coordinates ``q``:
``(y_rail, z_rail, θ_rail) = Φ(s) q`` with the (3 × n_modes) matrix ``Φ(s)`` of :func:`modal_shape_at`: nodal
mode values and slopes interpolated with the element's own shape functions (cubic Hermite for v, w; linear for
θx), so the interpolation is the one the mass and stiffness matrices were integrated with.  Dual: a force
``(Fy, Fz)`` acting on the rails' centre line at rail-top level at s and a moment ``Mx`` about that line give the
generalized modal forces ``Q = Φ(s)^T (Fy, Fz, Mx)`` (:func:`add_projected_force`; virtual work ``δW = Fy δy_rail
+ Fz δz_rail + Mx δθ_rail``).  A force ``F`` at a rail point ``(y_c, z_c)`` (relative to the centre line at
rail-top level) has ``Mx = y_c Fz - z_c Fy``.  Off the deck ``Φ = 0``.  Longitudinal forces are not projected
(the axial modes exist in the model but no x row is provided; open point).

Coupling to the wheel–rail connector
------------------------------------
The connector (:mod:`exudyn_wheelrail.multibody.connector`) extends its zero-mass ``ObjectGenericODE2`` by
:attr:`~.bridge_exudyn.ExudynBridge.modal_node`: its coordinate vector becomes ``[6 per wheelset..., n_modes modal]`` and its force
user function returns the wheelset forces followed by the generalized modal forces ``Q``, all in **one** compiled
call per right-hand-side evaluation (no LoadCoordinate per mode, no sensor or pre-step lag).  Exudyn accepts a
GenericODE2 over a Lie-group rigid node and a NodeGenericODE2 (explicit RK44 and generalized-α; checked by
``tests/test_bridge.py::test_coupling_*`` against the closed-form linear solution); the modal node is the same for
both formulations, so the coupling does not depend on the choice.  How the deck moves the rails under a wheel
(displacement ``Φ(s) q``, material velocity ``Φ(s) q̇``, roll) and where the rail forces go (``Q += Φ(s)^T (F_y,
F_z, M_x)``) is :mod:`.deck_kinematics`, built on :func:`modal_shape_at`, :func:`shapes_times` and
:func:`project_shapes`.  The rate
of the rail geometry under the moving wheel, ``Φ(s) q̇ + V Φ'(s) q`` (:func:`modal_shape_and_slope_at`), enters
the contact through the position dependence only; the creepages see the material velocity.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..jit import compiled

__all__ = ["ShapeTable", "NS_V", "NS_DV", "NS_W", "NS_DW", "NS_TH", "find_element", "modal_shape_at",
           "modal_shape_and_slope_at", "rail_state_at", "shapes_times", "project_shapes", "add_projected_force",
           "modal_shapes_many"]

#: rows of the node-shape table: v, dv/dx, w, dw/dx, θx
NS_V, NS_DV, NS_W, NS_DW, NS_TH = range(5)


# ------------------------------------------------------------------------------------------ the modal basis
class ShapeTable(NamedTuple):
    """Plain arrays of a modal basis for the compiled functions (``modal_shape_at(s, *table, out)``).

    start_m, rail_height_m : as :class:`~.bridge.BridgeModel`; elem_x0 (n_el) element start (deck coordinate, increasing),
    elem_len (n_el), elem_nodes (n_el, 2) int64, node_shapes (n_nodes, 5, n_modes): v, dv/dx, w, dw/dx, θx of every
    mode at every node."""

    start_m: float
    rail_height_m: float
    elem_x0: np.ndarray
    elem_len: np.ndarray
    elem_nodes: np.ndarray
    node_shapes: np.ndarray



# ------------------------------------------------------------------------------------- compiled functions
@compiled
def find_element(x, elem_x0, elem_len):
    """Index of the element (increasing starts ``elem_x0``, lengths ``elem_len``) that holds the deck coordinate
    ``x``; -1 off the elements (or for a NaN)."""
    n = elem_x0.shape[0]
    if n == 0:
        return -1
    if not (x >= elem_x0[0] and x <= elem_x0[n - 1] + elem_len[n - 1]):      # also rejects NaN
        return -1
    i = np.searchsorted(elem_x0, x, side="right") - 1
    if i < 0:
        i = 0
    if i > n - 1:
        i = n - 1
    return i


@compiled
def _interp(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out, out_ds, with_slope):
    n_modes = node_shapes.shape[2]
    for i in range(3):
        for k in range(n_modes):
            out[i, k] = 0.0
            if with_slope:
                out_ds[i, k] = 0.0
    e = find_element(s_m - start_m, elem_x0, elem_len)
    if e < 0:
        return False
    Le = elem_len[e]
    xi = (s_m - start_m - elem_x0[e]) / Le
    xi2 = xi * xi
    xi3 = xi2 * xi
    N1 = 1.0 - 3.0 * xi2 + 2.0 * xi3
    N2 = Le * (xi - 2.0 * xi2 + xi3)
    N3 = 3.0 * xi2 - 2.0 * xi3
    N4 = Le * (xi3 - xi2)
    La = 1.0 - xi
    Lb = xi
    a = elem_nodes[e, 0]
    b = elem_nodes[e, 1]
    ez = rail_height_m
    for k in range(n_modes):
        v = N1 * node_shapes[a, 0, k] + N2 * node_shapes[a, 1, k] + N3 * node_shapes[b, 0, k] \
            + N4 * node_shapes[b, 1, k]
        w = N1 * node_shapes[a, 2, k] + N2 * node_shapes[a, 3, k] + N3 * node_shapes[b, 2, k] \
            + N4 * node_shapes[b, 3, k]
        th = La * node_shapes[a, 4, k] + Lb * node_shapes[b, 4, k]
        out[0, k] = v + ez * th
        out[1, k] = w
        out[2, k] = th
    if with_slope:
        dN1 = (-6.0 * xi + 6.0 * xi2) / Le
        dN2 = 1.0 - 4.0 * xi + 3.0 * xi2
        dN3 = (6.0 * xi - 6.0 * xi2) / Le
        dN4 = 3.0 * xi2 - 2.0 * xi
        for k in range(n_modes):
            dv = dN1 * node_shapes[a, 0, k] + dN2 * node_shapes[a, 1, k] + dN3 * node_shapes[b, 0, k] \
                + dN4 * node_shapes[b, 1, k]
            dw = dN1 * node_shapes[a, 2, k] + dN2 * node_shapes[a, 3, k] + dN3 * node_shapes[b, 2, k] \
                + dN4 * node_shapes[b, 3, k]
            dth = (node_shapes[b, 4, k] - node_shapes[a, 4, k]) / Le
            out_ds[0, k] = dv + ez * dth
            out_ds[1, k] = dw
            out_ds[2, k] = dth
    return True


@compiled
def modal_shape_at(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out):
    """``Φ(s)`` into ``out`` (3, n_modes): rows y_rail (= v + e_z θx), z_rail (= w), θ_rail (= θx) of every mode at
    track distance ``s_m`` (nodal values and slopes interpolated by the element's Hermite cubics; θx linear).
    Returns True on the deck; off the deck (or for a non-finite s) ``out`` is zero and False is returned.
    Arguments after ``s_m``: a :class:`ShapeTable` (``modal_shape_at(s, *modes.table, out)``)."""
    return _interp(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out, out, False)


@compiled
def modal_shape_and_slope_at(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out, out_ds):
    """``Φ(s)`` into ``out`` and ``dΦ/ds`` into ``out_ds`` (each (3, n_modes)); as :func:`modal_shape_at`."""
    return _interp(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out, out_ds, True)


@compiled
def rail_state_at(s_m, speed_m_s, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, q, q_t,
                  work, work_ds, out):
    """Rail state at track distance ``s_m`` from the modal coordinates ``q``, ``q_t`` into ``out`` (9,):
    ``[0:3]`` displacement ``Φ q`` (y_rail, z_rail, θ_rail), ``[3:6]`` deck (material) velocity ``Φ q̇``,
    ``[6:9]`` rate seen by a point moving along the track at ``speed_m_s``: ``Φ q̇ + V Φ' q``.  ``work``,
    ``work_ds``: scratch (3, n_modes).  Returns True on the deck (all zero off it)."""
    on = _interp(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, work, work_ds, True)
    shapes_times(work, q, q_t, out)
    n_modes = node_shapes.shape[2]
    for i in range(3):
        g = 0.0
        for k in range(n_modes):
            g += work_ds[i, k] * q[k]
        out[6 + i] = out[3 + i] + speed_m_s * g
    return on


@compiled
def shapes_times(phi, q, q_t, out):
    """``out[0:3] = Φ q`` and ``out[3:6] = Φ q̇`` for the shapes ``phi`` (3, n_modes) at one point (rows y_rail,
    z_rail, θ_rail): the rails' displacement and material velocity there."""
    for i in range(3):
        d = 0.0
        v = 0.0
        for k in range(phi.shape[1]):
            d += phi[i, k] * q[k]
            v += phi[i, k] * q_t[k]
        out[i] = d
        out[3 + i] = v


@compiled
def project_shapes(phi, Fy, Fz, Mx, f_modal):
    """``f_modal += Φᵀ (Fy, Fz, Mx)`` for the shapes ``phi`` (3, n_modes) at the force's point: the generalized
    modal forces of a force on the rails' centre line at rail-top level and a moment about it."""
    for k in range(phi.shape[1]):
        f_modal[k] += phi[0, k] * Fy + phi[1, k] * Fz + phi[2, k] * Mx


@compiled
def add_projected_force(s_m, Fy, Fz, Mx, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, work,
                        f_modal):
    """``f_modal += Φ(s)^T (Fy, Fz, Mx)``: generalized modal forces of a force on the rails' centre line at rail-top
    level (y right, z down) and a moment about it, at track distance ``s_m``.  ``work``: scratch (3, n_modes).
    Returns True if s is on the deck (nothing is added otherwise)."""
    on = _interp(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, work, work, False)
    if on:
        project_shapes(work, Fy, Fz, Mx, f_modal)
    return on


@compiled
def modal_shapes_many(s, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out, out_ds, with_slope):
    """:func:`modal_shape_at` (and the slopes if ``with_slope``) at every track distance of ``s`` into ``out[i]``
    (and ``out_ds[i]``)."""
    for i in range(s.shape[0]):
        _interp(s[i], start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out[i], out_ds[i],
                with_slope)

