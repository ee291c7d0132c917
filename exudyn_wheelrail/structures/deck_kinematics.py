"""How a bridge deck moves the rails under the wheelsets, and where the wheel forces go on the deck (compiled).

The wheel–rail connector (:mod:`exudyn_wheelrail.multibody.connector`) coupled to an
:class:`~.bridge.ExudynBridge` spans the bridge's modal node; its compiled call uses the functions here per
wheelset.  Frames and signs are those of :mod:`.bridge`: track frame, y right, z down; θ right-handed about +x, so
θ > 0 lowers the right rail.  For wheelset k at track distance ``s_k = s_start + V t + x_k`` (the axle centre; the
same s as the irregularity):

* **deck state** ``(y_b, z_b, θ_b) = Φ(s_k) q`` and ``(ẏ_b, ż_b, θ̇_b) = Φ(s_k) q̇`` (:func:`deck_state_under`,
  from :func:`~.bridge.rail_state_at`; zero when s_k is off the deck): displacement and material velocity of the
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
  (:func:`project_on_deck`) — the virtual work of the rail forces on the rail displacement the kinematics used, so
  the coupling is energy-consistent.  Longitudinal forces are not projected (the bridge model has no x row).

Wheels off the deck see the rigid track (``Φ = 0``; their results are identical to a model without bridge).

*Lateral support motion* (:meth:`~.bridge.ExudynBridge.add_support_motion`, :mod:`.support_motion`): the modal
coordinates are the deck's motion relative to its supports, and the ground displacement ``y_g(t)`` and velocity
``ẏ_g(t)`` come on top for **every** wheelset, on the deck and off it (synchronous ground motion: the track off the
deck moves with the ground).  They depend on time only; the connector evaluates them once per call and writes them
into the deck parameters (``DECK_GROUND_Y``, ``DECK_GROUND_VY``).

The deck arrays of the compiled call (:func:`deck_arrays`): ``(par, elem_x0, elem_len, elem_nodes, node_shapes)``
— ``par[DECK_*]`` and the :class:`~.bridge.ShapeTable` of the deck (empty arrays, no modes: no bridge).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .bridge import add_projected_force, rail_state_at

__all__ = ["N_DECK_STATE", "DECK_START", "DECK_RAIL_HEIGHT", "DECK_GROUND_Y", "DECK_GROUND_VY", "N_DECK_PAR",
           "deck_arrays", "deck_state_under", "rails_under", "pose_relative_to_rails", "rail_pair_to_track",
           "rail_material_velocity", "rail_moment_about_deck_line", "project_on_deck"]

#: rows of a wheelset's deck state: displacement y, z [m] and roll [rad] of the rails' centre line at rail top,
#: material velocity ẏ, ż [m/s] and roll rate [rad/s], on-deck flag (1.0 on the deck, else 0.0; all zero off it)
N_DECK_STATE = 7

# ---- deck parameters: par[DECK_*] -------------------------------------------------------------------------------
DECK_START = 0        # track distance of the deck's start [m] (BridgeModel.start_m)
DECK_RAIL_HEIGHT = 1  # rail top above the deck axis [m]
DECK_GROUND_Y = 2     # ground (support) displacement y_g [m] at the time of the call
DECK_GROUND_VY = 3    # ground velocity ẏ_g [m/s]
N_DECK_PAR = 4


def deck_arrays(bridge) -> tuple[tuple, int]:
    """``(deck, n_modes)``: the deck arrays of the compiled call for an
    :class:`~.bridge.ExudynBridge` (module docstring), or for none (``bridge=None``: no modes); the ground entries
    of ``par`` start at zero."""
    if bridge is None:
        return (np.zeros(N_DECK_PAR), np.zeros(0), np.zeros(0), np.zeros((0, 2), dtype=np.int64),
                np.zeros((0, 5, 0))), 0
    tb = bridge.modes.table
    par = np.zeros(N_DECK_PAR)
    par[DECK_START] = tb.start_m
    par[DECK_RAIL_HEIGHT] = tb.rail_height_m
    return (par, np.ascontiguousarray(tb.elem_x0, dtype=float), np.ascontiguousarray(tb.elem_len, dtype=float),
            np.ascontiguousarray(tb.elem_nodes, dtype=np.int64),
            np.ascontiguousarray(tb.node_shapes, dtype=float)), int(bridge.modes.n_modes)


@njit(cache=True)
def deck_state_under(s_m, speed_m_s, deck, q_m, q_m_t, delta, phi, work_ds, work, state):
    """Deck state under a wheelset at track distance ``s_m`` into ``state`` (:data:`N_DECK_STATE`): ``Φ(s) q`` and
    ``Φ(s) q̇`` of the modal coordinates ``q_m``, ``q_m_t`` plus the increments ``delta`` (6; the Jacobian's
    perturbation), zero off the deck.  ``phi`` (3, n_m) receives ``Φ(s)``; ``work_ds`` (3, n_m), ``work`` (9):
    scratch.  Returns True on the deck."""
    par, elem_x0, elem_len, elem_nodes, node_shapes = deck
    on = False
    if q_m.shape[0] > 0:
        on = rail_state_at(s_m, speed_m_s, par[DECK_START], par[DECK_RAIL_HEIGHT], elem_x0, elem_len, elem_nodes,
                           node_shapes, q_m, q_m_t, phi, work_ds, work)
    for i in range(6):
        state[i] = work[i] + delta[i] if on else 0.0
    state[6] = 1.0 if on else 0.0
    return on


@njit(cache=True)
def rails_under(y_irr_m, z_irr_m, y_ground_m, state):
    """``(y_r, z_r, θ)``: the rails' centre line at rail top (irregularity + ground + deck) [m] and its roll [rad]
    under a wheelset with deck ``state``."""
    return y_irr_m + y_ground_m + state[0], z_irr_m + state[1], state[2]


@njit(cache=True)
def pose_relative_to_rails(p_y, p_z, roll, y_r, z_r, th, c_th, s_th):
    """Pose ``(y_rel, z_rel, roll_rel)`` of the axle centre ``(p_y, p_z)`` [m] with roll [rad] relative to the rail
    pair at ``(y_r, z_r)`` rolled by ``th`` (``c_th``, ``s_th`` its cosine and sine): ``R_x(-θ) (p - p_rail)``,
    ``roll - θ`` (the rail pair's frame)."""
    dy = p_y - y_r
    dz = p_z - z_r
    return c_th * dy + s_th * dz, -s_th * dy + c_th * dz, roll - th


@njit(cache=True)
def rail_pair_to_track(y_l, z_l, ny_l, nz_l, y_r, z_r, c_th, s_th):
    """A point ``(y_l, z_l)`` [m] and a normal ``(ny_l, nz_l)`` of the rail pair's frame in the track frame:
    rotated by ``R_x(θ)`` (``c_th``, ``s_th`` its cosine and sine) and shifted by ``(y_r, z_r)``."""
    y_t = y_r + c_th * y_l - s_th * z_l
    z_t = z_r + s_th * y_l + c_th * z_l
    ny = c_th * ny_l - s_th * nz_l
    nz = s_th * ny_l + c_th * nz_l
    return y_t, z_t, ny, nz


@njit(cache=True)
def rail_material_velocity(y_c, z_c, y_ground_m, vy_ground_m_s, state, v_rail):
    """Lateral and vertical material velocity of the rail at the contact point ``(y_c, z_c)`` [m] (track frame)
    into ``v_rail[1:3]`` [m/s]: ground + deck velocity + ``θ̇ e_x × (p - deck line)``.  ``v_rail[0]`` (the running
    speed) is the caller's."""
    v_rail[1] = vy_ground_m_s + state[3] - state[5] * (z_c - state[1])
    v_rail[2] = state[4] + state[5] * (y_c - (y_ground_m + state[0]))


@njit(cache=True)
def rail_moment_about_deck_line(y_c, z_c, F_y, F_z, M_x, y_ground_m, state):
    """Moment about +x [N m] of the force ``(F_y, F_z)`` [N] at ``(y_c, z_c)`` [m] about the deck's deflected
    rail-top centre line (at ``y_g + y_b``, ``z_b``), plus the moment ``M_x`` (track frame)."""
    return (y_c - (y_ground_m + state[0])) * F_z - (z_c - state[1]) * F_y + M_x


@njit(cache=True)
def project_on_deck(s_m, F_y, F_z, M_x, deck, work, f_modal):
    """``f_modal += Φ(s)^T (F_y, F_z, M_x)``: the generalized modal forces of a force on the rails at track distance
    ``s_m`` (:func:`~.bridge.add_projected_force`); ``work`` (3, n_m) scratch.  Returns True on the deck."""
    par, elem_x0, elem_len, elem_nodes, node_shapes = deck
    return add_projected_force(s_m, F_y, F_z, M_x, par[DECK_START], par[DECK_RAIL_HEIGHT], elem_x0, elem_len,
                               elem_nodes, node_shapes, work, f_modal)
