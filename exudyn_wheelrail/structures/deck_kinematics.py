"""How a bridge deck moves the rails under the wheelsets, and where the wheel forces go on the deck (compiled).

The wheel–rail connector (:mod:`exudyn_wheelrail.multibody.connector`) coupled to an
:class:`~.bridge_exudyn.ExudynBridge` spans the bridge's modal node; its compiled call uses the functions here per
wheelset.  Frames and signs are those of :mod:`.bridge`: track frame, y right, z down; θ right-handed about +x, so
θ > 0 lowers the right rail.  For wheelset k at track distance ``s_k = s_start + V t + x_k`` (the axle centre; the
same s as the irregularity):

* **deck state** ``(y_b, z_b, θ_b) = Φ(s_k) q`` and ``(ẏ_b, ż_b, θ̇_b) = Φ(s_k) q̇`` (:func:`deck_state_under`,
  from :func:`~.modal_shapes.modal_shape_at`; zero when s_k is off the deck): displacement and material velocity of the
  rails' centre line at rail-top level, roll of the rail pair about it — the rows of :data:`N_DECK_STATE`;
* **rails** = the irregularity plus the ground motion plus the deck (:func:`rails_under`): centre line at
  ``y_r = y_irr + y_g + y_b``, ``z_r = z_irr + z_b``, rolled by ``θ_b``.  The contact search gets the wheelset pose
  relative to the rail pair (:func:`pose_relative_to_rails`), ``y_rel = (p_y - y_r) cos θ_b + (p_z - z_r) sin θ_b``,
  ``z_rel = -(p_y - y_r) sin θ_b + (p_z - z_r) cos θ_b``, ``roll_rel = roll - θ_b``, and its contact points and rail
  normals are rotated back by ``R_x(θ_b)`` and shifted by ``(y_r, z_r)`` (:func:`rail_pair_to_track`);
* **creepages**: the rail material velocity at the contact point p is ``(-V, 0, 0) + (0, ẏ_g + ẏ_b, ż_b) + θ̇_b e_x
  × (p - (0, y_g + y_b, z_b))`` (:func:`rail_material_velocity`) and the rail angular velocity ``(θ̇_b, 0, 0)`` (spin
  creepage).  The convective rate ``V Φ' q`` of the geometry under the moving wheel enters through the position
  dependence only;
* **forces on the deck**: on the rails act minus the wheel forces; per wheelset ``F_ry = -Σ F_y``, ``F_rz = -Σ
  F_z``, ``M_rx = -Σ [(p_y - y_g - y_b) F_z - (p_z - z_b) F_y] - Σ M_spin n_x`` (sums over both wheels and all
  contact regions; moments about the deck's deflected rail-top centre line, :func:`rail_moment_about_deck_line`;
  the spin moment's x component, zero on a straight track), and ``Q += Φ(s_k)^T (F_ry, F_rz, M_rx)``
  (:func:`~.modal_shapes.project_shapes` with the shapes the deck state used) — the virtual work of the rail forces on
  the rail displacement the kinematics used, so the coupling is energy-consistent.  Longitudinal forces are not projected (the bridge model has no x row).

Wheels off the deck see the rigid track (``Φ = 0``; their results are identical to a model without bridge).

*Lateral support motion* (:meth:`~.bridge_exudyn.ExudynBridge.add_support_motion`, :mod:`.support_motion`): the modal
coordinates are the deck's motion relative to its supports, and the ground displacement ``y_g(t)`` and velocity
``ẏ_g(t)`` come on top for **every** wheelset, on the deck and off it (synchronous ground motion: the track off the
deck moves with the ground).  They depend on time only; the connector evaluates them once per call and writes them
into the deck parameters (``DECK_GROUND_Y``, ``DECK_GROUND_VY``).

*Residual flexibility* (a structure whose modes carry a ``residual_table``, the flexible track's static correction,
:attr:`~exudyn_wheelrail.track.flexible.FlexibleTrackModes.residual_table`): the static flexibility ``G_res(s)``
(3 × 3 in ``y_rail, z_rail, θ_rail``) of the modes the reduction dropped, interpolated linearly between the table's
points into the deck state (:data:`DS_RESIDUAL`).  It acts in series with each contact
(:func:`series_contacts`): the normal forces ``N_r`` of a wheelset's contacts (both wheels, every region), at
points p_r (rail-pair frame, relative to the rails' centre line) with rail normals n_r, move the rails by the
generalized displacement ``u = −G_res Σ_r N_r a_r``, ``a_r = (n_y, n_z, n_z p_y − n_y p_z)`` (the force's
generalized direction, the same lever as the moment on the deck), and every contact carries Hertz's force at its
geometric penetration less the rail's motion along its normal, ``δ_r = δ_g,r + a_r·u``.  The quasi-static
response of the dropped modes is exact for loads varying slowly against their frequencies; neglected: the
coupling through ``G_res`` of different wheelsets (the pads' compression is local to the rail seats under a
wheel) and the creep forces' share (they load the kept modes only).

The deck arrays of the compiled call (:func:`deck_arrays`): ``(par, elem_x0, elem_len, elem_nodes, node_shapes,
node_residual, rail_load_prediction)`` — ``par[DECK_*]``, the :class:`~.modal_shapes.ShapeTable` of the deck, the
residual flexibility at its points (n_points, 6) (no bridge: empty element arrays and ``None`` for the shapes;
``None``: no residual; numba compiles nothing of what a ``None`` stands for) and per
wheelset a prediction of its generalized force on the rails ``(F_y, F_z, M_x)`` (n_wheelsets, 3; zero unless set,
e.g. the static wheel loads: the connector finds the contact geometry on rails already moved by the residual
displacement ``G_res F`` it predicts, and again only where the solve moves them further).
"""
from __future__ import annotations

import math

import numpy as np

from ..jit import compiled
from .modal_shapes import find_element, modal_shape_at, project_shapes, shapes_times

__all__ = ["N_DECK_STATE", "DS_RESIDUAL", "DECK_START", "DECK_RAIL_HEIGHT", "DECK_GROUND_Y", "DECK_GROUND_VY",
           "N_DECK_PAR", "deck_arrays", "deck_state_under", "rails_under", "pose_relative_to_rails",
           "rail_pair_to_track", "rail_material_velocity", "rail_moment_about_deck_line", "project_shapes",
           "series_contacts", "residual_at", "N_SC"]

#: rows of a wheelset's deck state: displacement y, z [m] and roll [rad] of the rails' centre line at rail top,
#: material velocity ẏ, ż [m/s] and roll rate [rad/s], on-deck flag (1.0 on the deck, else 0.0; all zero off it),
#: then the residual flexibility there (:data:`DS_RESIDUAL`: ``G_yy, G_zz, G_θθ, G_yz, G_yθ, G_zθ``; zero without)
N_DECK_STATE = 13
DS_RESIDUAL = 7

# ---- deck parameters: par[DECK_*] -------------------------------------------------------------------------------
DECK_START = 0        # track distance of the deck's start [m] (BridgeModel.start_m)
DECK_RAIL_HEIGHT = 1  # rail top above the deck axis [m]
DECK_GROUND_Y = 2     # ground (support) displacement y_g [m] at the time of the call
DECK_GROUND_VY = 3    # ground velocity ẏ_g [m/s]
N_DECK_PAR = 4


def deck_arrays(bridge, n_wheelsets: int = 0) -> tuple[tuple, int]:
    """``(deck, n_modes)``: the deck arrays of the compiled call for an
    :class:`~.bridge_exudyn.ExudynBridge` (module docstring), or for none (``structure=None``: no modes); the ground entries
    of ``par`` start at zero."""
    if bridge is None:
        return (np.zeros(N_DECK_PAR), np.zeros(0), np.zeros(0), np.zeros((0, 2), dtype=np.int64), None, None,
                np.zeros((n_wheelsets, 3))), 0
    tb = bridge.modes.table
    par = np.zeros(N_DECK_PAR)
    par[DECK_START] = tb.start_m
    par[DECK_RAIL_HEIGHT] = tb.rail_height_m
    residual = getattr(bridge.modes, "residual_table", None)
    if residual is not None:
        residual = np.ascontiguousarray(residual, dtype=float)
        if residual.shape[0] not in (0, tb.node_shapes.shape[0]) or residual.shape[1:] != (6,):
            raise ValueError(f"residual_table of shape {residual.shape}: expected ({tb.node_shapes.shape[0]}, 6), "
                             f"one row per point of the shape table")
        if residual.shape[0] == 0:
            residual = None
    return (par, np.ascontiguousarray(tb.elem_x0, dtype=float), np.ascontiguousarray(tb.elem_len, dtype=float),
            np.ascontiguousarray(tb.elem_nodes, dtype=np.int64),
            np.ascontiguousarray(tb.node_shapes, dtype=float), residual, np.zeros((n_wheelsets, 3))), \
        int(bridge.modes.n_modes)


@compiled(refcount=False)
def deck_state_under(s_m, speed_m_s, deck, q_m, q_m_t, delta, phi, work, state):
    """Deck state under a wheelset at track distance ``s_m`` into ``state`` (:data:`N_DECK_STATE`): ``Φ(s) q`` and
    ``Φ(s) q̇`` of the modal coordinates ``q_m``, ``q_m_t`` plus the increments ``delta`` (6; the Jacobian's
    perturbation), zero off the deck.  ``phi`` (3, n_m) receives ``Φ(s)`` (the connector projects the rail
    forces with it, :func:`~.modal_shapes.project_shapes`); ``work`` (9): scratch.  Returns True on the deck."""
    par, elem_x0, elem_len, elem_nodes = deck[0], deck[1], deck[2], deck[3]
    node_residual = deck[5]
    on = False
    if q_m.shape[0] > 0:
        on = _shapes_under(s_m, par, elem_x0, elem_len, elem_nodes, deck[4], q_m, q_m_t, phi, work)
    for i in range(6):
        state[i] = work[i] + delta[i] if on else 0.0
    state[6] = 1.0 if on else 0.0
    if on:
        residual_at(s_m, par[DECK_START], elem_x0, elem_len, elem_nodes, node_residual, state[DS_RESIDUAL:])
    else:
        for i in range(6):
            state[DS_RESIDUAL + i] = 0.0
    return on


@compiled(refcount=False)
def _shapes_under(s_m, par, elem_x0, elem_len, elem_nodes, node_shapes, q_m, q_m_t, phi, work):
    """``Φ(s)`` into ``phi`` (no slopes: the convective rate is not used here), then ``Φ q`` and ``Φ q̇`` into
    ``work``; returns True on the deck.  ``node_shapes = None`` (no structure): False, and nothing of the shape
    table is compiled (numba drops the branch on a ``None`` argument's type)."""
    if node_shapes is None:
        return False
    on = modal_shape_at(s_m, par[DECK_START], par[DECK_RAIL_HEIGHT], elem_x0, elem_len, elem_nodes, node_shapes,
                        phi)
    shapes_times(phi, q_m, q_m_t, work)
    return on


@compiled(refcount=False)
def residual_at(s_m, start_m, elem_x0, elem_len, elem_nodes, node_residual, out):
    """The residual flexibility ``G_yy, G_zz, G_θθ, G_yz, G_yθ, G_zθ`` at track distance ``s_m`` into ``out`` (6,):
    linear between the table's points (zero off the table or without a residual table)."""
    for i in range(6):
        out[i] = 0.0
    if node_residual is None:        # no residual table: the branch below is not compiled
        return
    if node_residual.shape[0] == 0:
        return
    e = find_element(s_m - start_m, elem_x0, elem_len)
    if e < 0:
        return
    xi = min(max((s_m - start_m - elem_x0[e]) / elem_len[e], 0.0), 1.0)
    a = elem_nodes[e, 0]
    b = elem_nodes[e, 1]
    for i in range(6):
        out[i] = (1.0 - xi) * node_residual[a, i] + xi * node_residual[b, i]


#: columns of a contact in :func:`series_contacts`: its generalized direction a (y, z, θ rows), the kernel's Hertz
#: force, penetration and dN/dδ at the geometric penetration (inputs); the force, the ratio δ_H/δ_g of the Hertz
#: approach to the geometric penetration and dN/dδ_g in series (outputs)
SC_AY, SC_AZ, SC_AT, SC_N_G, SC_DELTA_G, SC_DN_G, SC_N, SC_RATIO, SC_DN = range(9)
N_SC = 9


@compiled(refcount=False)
def _g_times(g, x0, x1, x2, out):
    out[0] = g[0] * x0 + g[3] * x1 + g[4] * x2
    out[1] = g[3] * x0 + g[1] * x1 + g[5] * x2
    out[2] = g[4] * x0 + g[5] * x1 + g[2] * x2


@compiled(refcount=False)
def series_contacts(g, contacts, n, u0, work):
    """The contacts ``contacts[:n]`` (rows :data:`N_SC`) of one wheelset on rails with the residual flexibility
    ``g`` (6: ``G_yy, G_zz, G_θθ, G_yz, G_yθ, G_zθ``; module docstring): the rails' residual displacement u (3,
    generalized) with ``u = −G Σ_r N_r a_r`` and every contact at ``δ_r = δ_g,r + a_r·u``, ``N_r = N_g,r
    (δ_r/δ_g,r)^1.5`` (Hertz at the kernel's curvatures; zero where δ_r ≤ 0).  Newton on ``u + G Σ N_r a_r = 0``
    from u = 0: its Jacobian ``I + G Σ N'_r a_r a_rᵀ`` is non-singular (G and the sum positive semi-definite) and
    the problem is the gradient of a convex potential, so the iteration converges (to round-off: |Δu| < 1e-14 m).
    ``u0`` (3): the residual displacement the rails already had when the penetrations were found (the connector's
    second pass, :func:`~exudyn_wheelrail.multibody.connector_core.series_compliance`): then ``δ_r = δ_g,r +
    a_r·(u − u0)``, Newton from ``u0``.  ``dN/dδ_g`` of each contact is that of its own compliance ``a_rᵀ G a_r``
    in series (the other contacts' share of it is neglected there).  ``work`` (7, 3) scratch; u is left in
    ``work[0]``.  Returns the number of Newton iterations."""
    u = work[0]
    res = work[1]
    gv = work[2]
    du = work[3]
    u[0] = u0[0]
    u[1] = u0[1]
    u[2] = u0[2]
    it = 0
    J = work[4:7]
    for it in range(1, 51):
        res[0] = u[0]
        res[1] = u[1]
        res[2] = u[2]
        for i in range(3):
            for j in range(3):
                J[i, j] = 1.0 if i == j else 0.0
        for r in range(n):
            c = contacts[r]
            d = c[SC_DELTA_G] + c[SC_AY] * (u[0] - u0[0]) + c[SC_AZ] * (u[1] - u0[1]) + c[SC_AT] * (u[2] - u0[2])
            if d <= 0.0:
                continue
            x = d / c[SC_DELTA_G]
            N = c[SC_N_G] * x * math.sqrt(x)
            dN = 1.5 * N / d
            _g_times(g, c[SC_AY], c[SC_AZ], c[SC_AT], gv)
            for i in range(3):
                res[i] += gv[i] * N
                J[i, 0] += gv[i] * dN * c[SC_AY]
                J[i, 1] += gv[i] * dN * c[SC_AZ]
                J[i, 2] += gv[i] * dN * c[SC_AT]
        # du = -J^-1 res (Cramer's rule, 3 x 3)
        det = (J[0, 0] * (J[1, 1] * J[2, 2] - J[1, 2] * J[2, 1]) - J[0, 1] * (J[1, 0] * J[2, 2] - J[1, 2] * J[2, 0])
               + J[0, 2] * (J[1, 0] * J[2, 1] - J[1, 1] * J[2, 0]))
        for col in range(3):
            m00, m01, m02 = J[0, 0], J[0, 1], J[0, 2]
            m10, m11, m12 = J[1, 0], J[1, 1], J[1, 2]
            m20, m21, m22 = J[2, 0], J[2, 1], J[2, 2]
            if col == 0:
                m00, m10, m20 = res[0], res[1], res[2]
            elif col == 1:
                m01, m11, m21 = res[0], res[1], res[2]
            else:
                m02, m12, m22 = res[0], res[1], res[2]
            du[col] = -(m00 * (m11 * m22 - m12 * m21) - m01 * (m10 * m22 - m12 * m20)
                        + m02 * (m10 * m21 - m11 * m20)) / det
        u[0] += du[0]
        u[1] += du[1]
        u[2] += du[2]
        if abs(du[0]) + abs(du[1]) + abs(du[2]) < 1e-14:
            break
    for r in range(n):
        c = contacts[r]
        d = c[SC_DELTA_G] + c[SC_AY] * (u[0] - u0[0]) + c[SC_AZ] * (u[1] - u0[1]) + c[SC_AT] * (u[2] - u0[2])
        x = max(d, 0.0) / c[SC_DELTA_G]
        c[SC_N] = c[SC_N_G] * x * math.sqrt(x)
        c[SC_RATIO] = x
        _g_times(g, c[SC_AY], c[SC_AZ], c[SC_AT], gv)
        crr = c[SC_AY] * gv[0] + c[SC_AZ] * gv[1] + c[SC_AT] * gv[2]
        dn_h = c[SC_DN_G] * math.sqrt(x)
        c[SC_DN] = dn_h / (1.0 + crr * dn_h)
    return it


@compiled(refcount=False)
def rails_under(y_irr_m, z_irr_m, y_ground_m, state):
    """``(y_r, z_r, θ)``: the rails' centre line at rail top (irregularity + ground + deck) [m] and its roll [rad]
    under a wheelset with deck ``state``."""
    return y_irr_m + y_ground_m + state[0], z_irr_m + state[1], state[2]


@compiled
def pose_relative_to_rails(p_y, p_z, roll, y_r, z_r, th, c_th, s_th):
    """Pose ``(y_rel, z_rel, roll_rel)`` of the axle centre ``(p_y, p_z)`` [m] with roll [rad] relative to the rail
    pair at ``(y_r, z_r)`` rolled by ``th`` (``c_th``, ``s_th`` its cosine and sine): ``R_x(-θ) (p - p_rail)``,
    ``roll - θ`` (the rail pair's frame)."""
    dy = p_y - y_r
    dz = p_z - z_r
    return c_th * dy + s_th * dz, -s_th * dy + c_th * dz, roll - th


@compiled
def rail_pair_to_track(y_l, z_l, ny_l, nz_l, y_r, z_r, c_th, s_th):
    """A point ``(y_l, z_l)`` [m] and a normal ``(ny_l, nz_l)`` of the rail pair's frame in the track frame:
    rotated by ``R_x(θ)`` (``c_th``, ``s_th`` its cosine and sine) and shifted by ``(y_r, z_r)``."""
    y_t = y_r + c_th * y_l - s_th * z_l
    z_t = z_r + s_th * y_l + c_th * z_l
    ny = c_th * ny_l - s_th * nz_l
    nz = s_th * ny_l + c_th * nz_l
    return y_t, z_t, ny, nz


@compiled
def rail_material_velocity(y_c, z_c, y_ground_m, vy_ground_m_s, state, v_rail):
    """Lateral and vertical material velocity of the rail at the contact point ``(y_c, z_c)`` [m] (track frame)
    into ``v_rail[1:3]`` [m/s]: ground + deck velocity + ``θ̇ e_x × (p - deck line)``.  ``v_rail[0]`` (the running
    speed) is the caller's."""
    v_rail[1] = vy_ground_m_s + state[3] - state[5] * (z_c - state[1])
    v_rail[2] = state[4] + state[5] * (y_c - (y_ground_m + state[0]))


@compiled
def rail_moment_about_deck_line(y_c, z_c, F_y, F_z, M_x, y_ground_m, state):
    """Moment about +x [N m] of the force ``(F_y, F_z)`` [N] at ``(y_c, z_c)`` [m] about the deck's deflected
    rail-top centre line (at ``y_g + y_b``, ``z_b``), plus the moment ``M_x`` (track frame)."""
    return (y_c - (y_ground_m + state[0])) * F_z - (z_c - state[1]) * F_y + M_x
