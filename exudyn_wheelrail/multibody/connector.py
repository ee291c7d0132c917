"""The wheel–rail connector: one Exudyn item coupling every wheelset of a model to its rails.

>>> model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=50.0)                        # doctest: +SKIP
>>> contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, WheelRailPair("S1002", "UIC60"),
...                                  speed_m_s=50.0, track=RigidStraightTrack(irregularity))  # doctest: +SKIP

What it is
----------
One ``ObjectGenericODE2`` spanning all wheelset nodes (Lie-group rigid nodes, ``NodeType.RotationRotationVector``)
with no mass of its own and a force user function.  Each right-hand-side evaluation makes **one compiled call**
(:func:`contact_forces_core`) that, for every wheel,

1. takes the wheelset pose from the node coordinates (position, rotation vector → rotation matrix; roll and yaw
   from the axle direction) and subtracts the rail's lateral/vertical displacement (the track irregularity) at
   the wheel's track distance ``s = s_start + V t + x`` (the model frame translates with the running speed V —
   see :mod:`.vehicle_builder`; ``frame="track"`` for a model whose wheelsets move along x themselves);
2. solves the contact geometry and Hertz for the tread and flange regions (:mod:`exudyn_wheelrail.contact.kernel`,
   warm-started from the previous call);
3. places each contact point in 3-D (the yaw lead of :func:`~exudyn_wheelrail.contact.creepage.yawed_contact_point_core`),
   computes the creepages from the wheelset's velocity and angular velocity and the rail material velocity
   (``(-V, 0, 0)`` in the moving frame, zero on a fixed track) (:mod:`exudyn_wheelrail.contact.creepage`);
4. evaluates the creep law (by default the USETAB-style table of Kalker's exact theory; FASTSIM or a cheap law
   on request) in the contact frame;
5. applies ``N n_rail + Fx x_c + Fy y_c`` at the contact point and the spin moment ``Mz z_c`` to the wheelset
   (generalized forces: force in the global frame, torque in the body frame — the Lie-group node's velocity
   coordinates are the body-frame angular velocity), and records the equal and opposite force on the rail.

Separation gives no force; re-contact is found by the kernel's separation bound and warm/global search.

Implicit solvers: a Jacobian user function returns ``-∂f/∂q fODE2 - ∂f/∂q_t fODE2_t`` by forward differences of
the same compiled call (position and velocity perturbations; rotations perturbed by body-frame increments, the
Lie-group tangent), with the warm-start state saved and restored; block diagonal per wheelset, so 12 calls
whatever the number of wheelsets (plus 6 with a bridge, below).

Flexible bridge (``bridge=``)
-----------------------------
With an :class:`~exudyn_wheelrail.structures.bridge.ExudynBridge` the object also spans the bridge's modal node:
coordinates ``[6 per wheelset..., n_m modal]``, forces ``[force, torque per wheelset..., Q]``, still one compiled
call per evaluation.  Frames and signs are those of :mod:`exudyn_wheelrail.structures.bridge` (track frame, y
right, z down; θ right-handed about +x, so θ > 0 lowers the right rail).  For wheelset k at track distance
``s_k = s_start + V t + x_k`` (the axle centre; the same s as the irregularity):

* **deck state** ``(y_b, z_b, θ_b) = Φ(s_k) q`` and ``(ẏ_b, ż_b, θ̇_b) = Φ(s_k) q̇`` (:func:`~exudyn_wheelrail.
  structures.bridge.rail_state_at`; zero when s_k is off the deck): displacement and material velocity of the
  rails' centre line at rail-top level, roll of the rail pair about it;
* **rails** = the irregularity plus the deck: centre line at ``y_r = y_irr + y_b``, ``z_r = z_irr + z_b``, rolled
  by ``θ_b``.  The kernel gets the wheelset pose relative to the rail pair, ``y_rel = (p_y - y_r) cos θ_b + (p_z -
  z_r) sin θ_b``, ``z_rel = -(p_y - y_r) sin θ_b + (p_z - z_r) cos θ_b``, ``roll_rel = roll - θ_b`` (mirrored for
  the left side as before), and its contact points and rail normals are rotated back by ``R_x(θ_b)`` and shifted
  by ``(y_r, z_r)``;
* **creepages**: the rail material velocity at the contact point p is ``(-V, 0, 0) + (0, ẏ_b, ż_b) + θ̇_b e_x ×
  (p - (0, y_b, z_b))`` (i.e. ``v_y -= θ̇_b (p_z - z_b)``, ``v_z += θ̇_b (p_y - y_b)``) and the rail angular
  velocity ``(θ̇_b, 0, 0)`` (spin creepage).  The convective rate ``V Φ' q`` of the geometry under the moving
  wheel enters through the position dependence only;
* **forces on the deck**: on the rails act minus the wheel forces; per wheelset ``F_ry = -Σ F_y``, ``F_rz = -Σ
  F_z``, ``M_rx = -Σ [(p_y - y_b) F_z - (p_z - z_b) F_y] - Σ M_spin n_x`` (sums over both wheels and all contact
  regions; moments about the deck's deflected rail-top centre line; the spin moment's x component, zero on a
  straight track), and ``Q += Φ(s_k)^T (F_ry, F_rz, M_rx)``
  (:func:`~exudyn_wheelrail.structures.bridge.add_projected_force`) — the virtual work of the rail forces on the
  rail displacement the kinematics used, so the coupling is energy-consistent.  Longitudinal forces are not
  projected (the bridge model has no x row).

Wheels off the deck see the rigid track (``Φ = 0``; their results are identical to a model without bridge).

*Lateral support motion* (:meth:`~exudyn_wheelrail.structures.bridge.ExudynBridge.add_support_motion`,
:mod:`exudyn_wheelrail.structures.support_motion`): the modal coordinates are then the deck's motion relative to its
supports, and the ground displacement ``y_g(t)`` and velocity ``ẏ_g(t)`` of the bridge's support motion come on top
for **every** wheelset, on the deck and off it (synchronous ground motion: the track off the deck moves with the
ground): rails at ``y_r = y_irr + y_g + y_b``, material velocity ``v_y = ẏ_g + ẏ_b - θ̇_b (p_z - z_b)``, deck line
(moment arm, roll velocity) at ``y_g + y_b``.  They depend on time only (no Jacobian columns); they are evaluated
in Python once per force or Jacobian call and passed to the compiled call in ``deck_par``.  Results
``RES_GROUND_Y``, ``RES_GROUND_VY``; the wheelset pose relative to its rail pair (what the kernel solves for:
lateral wheelset–rail displacement) is :meth:`WheelRailContact.wheelset_rail_pose`.

Jacobian: the wheelset columns as above (their modal rows are the change of ``Φ(s_k)^T F_r,k``, including the
change of ``Φ`` when the x coordinate moves s_k); the modal columns by the chain rule — the contact depends on
``q`` and ``q̇`` only through the deck state under each wheelset, so the three offsets and three rates of all
wheelsets on the deck are perturbed together (6 calls for any number of modes and wheelsets):
``∂f_k/∂q = (∂f_k/∂u_k) Φ(s_k)``, ``∂Q/∂q = Σ_k Φ(s_k)^T (∂F_r,k/∂u_k) Φ(s_k)`` (tested against column-by-column
differences).  Results: ``RES_DECK_Y``, ``RES_DECK_Z``, ``RES_DECK_ROLL`` (the deck offset used, relative to the
supports: without the irregularity and the ground motion) and ``RES_ON_DECK`` per wheel;
:meth:`WheelRailContact.modal_forces_N`, :meth:`~WheelRailContact.rail_forces_N`,
:meth:`~WheelRailContact.deck_state`.

Outputs
-------
:attr:`WheelRailContact.results` ``(n_wheels, 3, N_RES)`` holds the last evaluation per wheel (``2k`` right,
``2k+1`` left) and kernel slot (0 tread, 1 flange, 2 the tread's second zone in two-point tread contact); fields
``RES_*``.  Forces are **on the wheel**; ``RES_F_TRACK_*``
is the total contact force (normal + creep) in the track/model frame (y right, z down: a wheel load Q is
``-RES_F_TRACK_Z``).  Invalid states (NaN coordinates) raise :class:`ContactStateError` naming the wheelset and the
time, instead of returning numbers.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..contact import geometry_table as GT
from ..contact import kernel as K
from ..contact.creepage import DEFAULT_V_MIN_M_S, creepages_core, yawed_contact_point_core
from ..contact.pair import WheelRailPair
from ..creep import linear as _linear
from ..creep.fastsim import DEFAULT_NX, DEFAULT_NY, fastsim_core
from ..creep.laws import polach_core, she_core
from ..creep.table import table_core
from ..structures.bridge import add_projected_force, rail_state_at
from ..validation import finite, poisson_ratio, youngs_modulus
from .track import RigidStraightTrack, irregularity_at

__all__ = ["WheelRailContact", "add_wheel_rail_contact", "contact_forces_core", "ContactStateError",
           "CREEP_LAWS", "N_RES"] + [n for n in dir() if n.startswith("RES_")]

#: Exudyn node type (``mbs.GetNode(n)['nodeType']``) of the wheelset nodes the connector accepts: the Lie-group
#: rigid-body node with a rotation vector, created with ``nodeType=exu.NodeType.RotationRotationVector``
WHEELSET_NODE_TYPE_PREFIX = "RigidBodyRotVec"

# ---- creep laws --------------------------------------------------------------------------------------------------
LAW_FASTSIM = 0
LAW_LINEAR = 1        # Kalker's linear theory, unsaturated (tests, small-creepage studies)
LAW_NONE = 2          # normal forces only
LAW_TABLE = 3         # the USETAB-style table of Kalker's exact theory (creep.table)
LAW_SHE = 4           # Shen-Hedrick-Elkins (creep.laws)
LAW_POLACH = 5        # Polach (creep.laws), k_A = k_S = 1
#: contact geometry: "online" search at every evaluation, or the precomputed "table" (contact.geometry_table)
GEOMETRY_MODES = ("online", "table")
CREEP_LAWS = {"fastsim": LAW_FASTSIM, "linear": LAW_LINEAR, "none": LAW_NONE, "table": LAW_TABLE,
              "shen_hedrick_elkins": LAW_SHE, "polach": LAW_POLACH}

# creep parameters cp[]
CP_MU = 0
CP_G = 1
CP_NU = 2
CP_NX = 3             # FASTSIM grid
CP_NY = 4
CP_V_MIN = 5          # standstill guard of the creepages [m/s]
CP_AB_MIN = 6         # semi-axis ratio range of the law (a/b clamped at equal area outside; flagged)
CP_AB_MAX = 7
N_CP = 8

# ---- results per wheel and region --------------------------------------------------------------------------------
RES_STATUS = 0        # kernel status (K.STATUS_*): > 0 contact
RES_N = 1             # normal force [N]
RES_FX = 2            # creep forces on the wheel in the contact frame [N]
RES_FY = 3
RES_MZ = 4            # spin moment [N m]
RES_F_TRACK_X = 5     # total contact force on the wheel, track/model frame [N]
RES_F_TRACK_Y = 6
RES_F_TRACK_Z = 7
RES_P_X = 8           # contact point, track/model frame [m]
RES_P_Y = 9
RES_P_Z = 10
RES_GAMMA = 11        # contact angle [rad]
RES_XI = 12
RES_ETA = 13
RES_PHI = 14          # [1/m]
RES_A = 15            # semi-axes [m]
RES_B = 16
RES_DELTA = 17        # penetration [m]
RES_V = 18            # rolling speed [m/s]
RES_CREEP_STATUS = 19  # contact.creepage CREEP_* bits (+ 64: a/b clamped for the creep law)
RES_FLAGS = 20        # kernel FLAG_* bits
RES_S_TRACK = 21      # track distance of the wheelset [m]
RES_DECK_Y = 22       # deck (bridge) displacement of the rails' centre line at rail top under the wheelset, used for
RES_DECK_Z = 23       # the contact: lateral y, vertical z (down) [m], roll about x [rad] (0 off the deck / no bridge);
RES_DECK_ROLL = 24    # the track irregularity comes on top
RES_ON_DECK = 25      # 1 when the wheelset's track distance lies on the deck, else 0
RES_GROUND_Y = 26     # lateral ground (support) motion y_g [m] and its velocity [m/s] added to the rails (bridge
RES_GROUND_VY = 27    # support motion; 0 without), on and off the deck
N_RES = 28

# per-wheelset deck state (deck_state rows): displacement y, z, roll, material velocity y, z, roll rate, on-deck flag
N_DECK_STATE = 7

CREEP_AB_CLAMPED = 64


class ContactStateError(RuntimeError):
    """The multibody state handed to the contact is not usable (NaN/inf coordinates).  ``time_s`` and
    ``wheelset`` (None when the bridge's coordinates are the bad ones) say where."""

    def __init__(self, message: str, time_s: float | None = None, wheelset: int | None = None):
        super().__init__(message)
        self.time_s = time_s
        self.wheelset = wheelset


@njit(cache=True)
def rotation_from_vector(rx, ry, rz, R):
    """Rodrigues: rotation matrix of the rotation vector (rx, ry, rz) into R (3, 3)."""
    th = math.sqrt(rx * rx + ry * ry + rz * rz)
    if th < 1e-12:
        s = 1.0
        c = 0.5
    else:
        s = math.sin(th) / th
        c = (1.0 - math.cos(th)) / (th * th)
    R[0, 0] = 1.0 - c * (ry * ry + rz * rz)
    R[1, 1] = 1.0 - c * (rx * rx + rz * rz)
    R[2, 2] = 1.0 - c * (rx * rx + ry * ry)
    R[0, 1] = -s * rz + c * rx * ry
    R[1, 0] = s * rz + c * rx * ry
    R[0, 2] = s * ry + c * rx * rz
    R[2, 0] = -s * ry + c * rx * rz
    R[1, 2] = -s * rx + c * ry * rz
    R[2, 1] = s * rx + c * ry * rz


@njit(cache=True)
def _creep(law, a, b, xi, eta, phi, N, cp, t_nodes, coef, tab):
    """Creep forces of the selected law (contract of :mod:`exudyn_wheelrail.creep`); returns (Fx, Fy, Mz, flag).
    ``tab``: the table's padded arrays (:meth:`~exudyn_wheelrail.creep.table.CreepTable.core_arrays`)."""
    Fx, Fy, Mz, flag = _creep_law(law, a, b, xi, eta, phi, N, cp, t_nodes, coef, tab)
    if law != LAW_LINEAR:
        # Coulomb: no law may exceed μN (the table's cubic interpolation overshoots by up to ~0.2 % near full
        # sliding, FASTSIM's discrete pressure by ~0.05 %): the resultant is held on the friction bound
        f_t = math.sqrt(Fx * Fx + Fy * Fy)
        bound = cp[CP_MU] * N
        if f_t > bound > 0.0:
            Fx *= bound / f_t
            Fy *= bound / f_t
    return Fx, Fy, Mz, flag


@njit(cache=True)
def _creep_law(law, a, b, xi, eta, phi, N, cp, t_nodes, coef, tab):
    """The selected law without the Coulomb guard of :func:`_creep`."""
    if law == LAW_NONE or N <= 0.0:
        return 0.0, 0.0, 0.0, 0
    flag = 0
    ab = a / b
    if ab < cp[CP_AB_MIN] or ab > cp[CP_AB_MAX]:
        # outside the law's range: same area (c) at the nearest allowed ratio, flagged
        c = math.sqrt(a * b)
        ab = min(max(ab, cp[CP_AB_MIN]), cp[CP_AB_MAX])
        a = c * math.sqrt(ab)
        b = c / math.sqrt(ab)
        flag = CREEP_AB_CLAMPED
    C11, C22, C23 = _linear.kalker_coefficients_core(math.log(ab), cp[CP_NU], t_nodes, coef, 0)
    G = cp[CP_G]
    if law == LAW_TABLE:
        Fx, Fy, Mz = table_core(a, b, xi, eta, phi, N, cp[CP_MU], G, C11, C22, tab[0], tab[1], tab[2], tab[3],
                                tab[4], tab[5], 3)
        return Fx, Fy, Mz, flag
    if law == LAW_SHE or law == LAW_POLACH:
        C33 = 32.0 / (15.0 * math.pi) * C23 * ab ** -1.5     # simplified-theory spin-moment coefficient
        if law == LAW_SHE:
            Fx, Fy, Mz = she_core(a, b, xi, eta, phi, N, cp[CP_MU], G, C11, C22, C23, C33)
        else:
            Fx, Fy, Mz = polach_core(a, b, xi, eta, phi, N, cp[CP_MU], G, C11, C22, C23, C33, 1.0, 1.0)
        return Fx, Fy, Mz, flag
    if law == LAW_LINEAR:
        c = math.sqrt(a * b)
        C33 = 32.0 / (15.0 * math.pi) * C23 * ab ** -1.5     # as creep.linear_creep_forces
        return (-G * c * c * C11 * xi, -G * c * c * (C22 * eta + c * C23 * phi),
                G * c * c * c * (C23 * eta - c * C33 * phi), flag)
    Fx, Fy, Mz = fastsim_core(a, b, xi, eta, phi, N, cp[CP_MU], G, C11, C22, C23, int(cp[CP_NX]), int(cp[CP_NY]),
                              0)
    return Fx, Fy, Mz, flag


@njit(cache=True)
def contact_forces_core(q, q_t, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs,
                        nodes, meta, mono, curve_ids, warm, params, gtab, side_poses, out, law, cp, t_nodes, coef,
                        tab, deck_par, deck_x0, deck_len, deck_nodes, deck_shapes, rail_delta, phi_ws, rail_f,
                        deck_state, f_out, res):
    """All wheelsets in one call.  ``q``, ``q_t`` (6 n + n_m): per wheelset displacement (global), rotation vector,
    velocity (global) and body-frame angular velocity (Lie-group node coordinates), then the n_m modal coordinates
    of the bridge (none without a bridge); ``p_ref`` (n, 3) reference positions.  Fills ``f_out`` (6 n + n_m):
    force (global) and torque (body frame) per wheelset, then the generalized modal forces of the deck; ``res``
    (2 n, N_SLOTS, N_RES).  Returns the index of the first wheelset with a non-finite state, n for non-finite modal
    coordinates, or -1.

    Bridge (module docstring, "Flexible bridge"): ``deck_par`` = (start_m, rail_height_m, y_g, ẏ_g) — the last two
    the lateral ground (support) motion at t, added to every wheelset's rails (zero: none; a 2-entry ``deck_par``
    means none) — and ``deck_x0``,
    ``deck_len``, ``deck_nodes``, ``deck_shapes`` the arrays of the deck's
    :class:`~exudyn_wheelrail.structures.bridge.ShapeTable` (empty arrays, n_m = 0: no bridge).  ``rail_delta``
    (n, 6): increments added to the deck state of every wheelset on the deck (zero; the Jacobian perturbs it).
    Outputs per wheelset: ``phi_ws`` (n, 3, n_m) ``Φ(s)``, ``rail_f`` (n, 3) the force on the rails (Fy, Fz, Mx
    about the deck's rail-top centre line) that is projected, ``deck_state`` (n, N_DECK_STATE)."""
    n_ws = p_ref.shape[0]
    n_w6 = 6 * n_ws
    n_m = q.shape[0] - n_w6
    q_m = q[n_w6:]
    q_m_t = q_t[n_w6:]
    f_m = f_out[n_w6:]
    d_start = deck_par[0]
    d_ez = deck_par[1]
    y_g = 0.0
    v_g = 0.0
    if deck_par.shape[0] >= 4:
        y_g = deck_par[2]
        v_g = deck_par[3]
    work_ds = np.empty((3, n_m))
    st = np.zeros(9)
    R = np.empty((3, 3))
    frame = np.empty((3, 3))
    pc = np.empty(3)
    nr = np.empty(3)
    e_axle = np.empty(3)
    p_centre = np.empty(3)
    v_centre = np.empty(3)
    omega = np.empty(3)
    v_rail = np.zeros(3)
    omega_rail = np.zeros(3)
    if moving_frame:
        v_rail[0] = -speed
    bad = -1
    s_ws = np.empty(n_ws)
    rolls = np.empty(n_ws)
    yaws = np.empty(n_ws)
    irr = np.empty((n_ws, 2))
    for k in range(n_ws):
        o = 6 * k
        finite = True
        for i in range(6):
            finite = finite and math.isfinite(q[o + i]) and math.isfinite(q_t[o + i])
        if not finite:
            if bad < 0:
                bad = k
            side_poses[2 * k, :] = np.nan
            side_poses[2 * k + 1, :] = np.nan
            continue
        rotation_from_vector(q[o + 3], q[o + 4], q[o + 5], R)
        ex, ey, ez = R[0, 1], R[1, 1], R[2, 1]        # axle direction (body y) in the track frame
        roll = math.asin(min(max(ez, -1.0), 1.0))
        yaw = math.atan2(-ex, ey)
        px = p_ref[k, 0] + q[o]
        py = p_ref[k, 1] + q[o + 1]
        pz = p_ref[k, 2] + q[o + 2]
        s = s_start + px + (speed * t if moving_frame else 0.0)
        y_irr, _, _, z_irr, _, _ = irregularity_at(irr_rows, irr_knots, irr_coefs, s)
        s_ws[k] = s
        rolls[k] = roll
        yaws[k] = yaw
        # deck state under the wheelset: displacement Φ(s) q and material velocity Φ(s) q̇ (zero off the deck)
        on = False
        if n_m > 0:
            on = rail_state_at(s, speed, d_start, d_ez, deck_x0, deck_len, deck_nodes, deck_shapes, q_m, q_m_t,
                               phi_ws[k], work_ds, st)
        for i in range(6):
            deck_state[k, i] = st[i] + rail_delta[k, i] if on else 0.0
        deck_state[k, 6] = 1.0 if on else 0.0
        gtab[3][GT.STAT_ON_DECK if on else GT.STAT_OFF_DECK] += 1
        # rails: the irregularity plus the ground motion plus the deck, rolled by θ about the centre line at rail
        # top; the pose relative to the rail pair is R_x(-θ) (p - p_rail), roll - θ (without a bridge: p - p_irr,
        # roll)
        y_r = y_irr + y_g + deck_state[k, 0]
        z_r = z_irr + deck_state[k, 1]
        th = deck_state[k, 2]
        c_th = math.cos(th)
        s_th = math.sin(th)
        irr[k, 0] = y_r
        irr[k, 1] = z_r
        dy = py - y_r
        dz = pz - z_r
        y_rel = c_th * dy + s_th * dz
        z_rel = -s_th * dy + c_th * dz
        side_poses[2 * k, 0] = y_rel
        side_poses[2 * k, 1] = z_rel
        side_poses[2 * k, 2] = roll - th
        side_poses[2 * k + 1, 0] = -y_rel
        side_poses[2 * k + 1, 1] = z_rel
        side_poses[2 * k + 1, 2] = -(roll - th)
    if n_m > 0:
        for i in range(n_m):
            if not (math.isfinite(q_m[i]) and math.isfinite(q_m_t[i])):
                if bad < 0:
                    bad = n_ws
    for i in range(f_out.shape[0]):
        f_out[i] = 0.0
    for k in range(n_ws):
        rail_f[k, 0] = 0.0
        rail_f[k, 1] = 0.0
        rail_f[k, 2] = 0.0
    res[:, :, :] = 0.0
    if bad >= 0:
        return bad
    GT.evaluate_wheels_tabulated(gtab[0], gtab[1], gtab[2], nodes, meta, mono, curve_ids, side_poses, warm, params,
                                 out, gtab[3])
    for k in range(n_ws):
        o = 6 * k
        rotation_from_vector(q[o + 3], q[o + 4], q[o + 5], R)
        for i in range(3):
            e_axle[i] = R[i, 1]
            p_centre[i] = p_ref[k, i] + q[o + i]
            v_centre[i] = q_t[o + i]
            omega[i] = R[i, 0] * q_t[o + 3] + R[i, 1] * q_t[o + 4] + R[i, 2] * q_t[o + 5]
        fx = 0.0
        fy = 0.0
        fz = 0.0
        tx = 0.0
        ty = 0.0
        tz = 0.0
        # deck under this wheelset: rail centre line (incl. irregularity and ground motion) y_r, z_r, roll th; deck
        # displacement yb, zb relative to the supports (the deck line is at y_g + yb, zb); the deck's material
        # velocity (vyb, vzb) of the centre line at rail top relative to the supports and roll rate wb
        y_r = irr[k, 0]
        z_r = irr[k, 1]
        yb = deck_state[k, 0]
        yb_line = y_g + yb
        zb = deck_state[k, 1]
        th = deck_state[k, 2]
        vyb = deck_state[k, 3]
        vzb = deck_state[k, 4]
        wb = deck_state[k, 5]
        c_th = math.cos(th)
        s_th = math.sin(th)
        omega_rail[0] = wb
        rfy = 0.0
        rfz = 0.0
        rmx = 0.0
        for side in range(2):
            w = 2 * k + side
            mirror = 1.0 if side == 0 else -1.0
            for reg in range(out.shape[1]):
                ow = out[w, reg]
                r = res[w, reg]
                r[RES_STATUS] = ow[K.F_STATUS]
                r[RES_FLAGS] = ow[K.F_FLAGS]
                r[RES_S_TRACK] = s_ws[k]
                r[RES_DECK_Y] = yb
                r[RES_DECK_Z] = zb
                r[RES_DECK_ROLL] = th
                r[RES_ON_DECK] = deck_state[k, 6]
                r[RES_GROUND_Y] = y_g
                r[RES_GROUND_VY] = v_g
                if ow[K.F_STATUS] <= 0:
                    continue
                N = ow[K.F_NORMAL_FORCE]
                # contact point and rail normal from the rail pair's frame to the track frame
                y_l = mirror * ow[K.F_PW_Y]
                z_l = ow[K.F_PW_Z]
                ny_l = mirror * ow[K.F_NR_Y]
                nz_l = ow[K.F_NR_Z]
                y_t = y_r + c_th * y_l - s_th * z_l
                z_t = z_r + s_th * y_l + c_th * z_l
                ny = c_th * ny_l - s_th * nz_l
                nz = s_th * ny_l + c_th * nz_l
                x_c, y_c, z_c, _, ok = yawed_contact_point_core(y_t, z_t, ny, nz, p_centre[0], p_centre[1],
                                                                 p_centre[2], rolls[k], yaws[k])
                if not ok:
                    x_c, y_c, z_c = p_centre[0], y_t, z_t
                pc[0] = x_c
                pc[1] = y_c
                pc[2] = z_c
                nr[0] = 0.0
                nr[1] = ny
                nr[2] = nz
                # rail material velocity at the contact point: (-V, 0, 0) + ground velocity + deck velocity
                # + θ̇ e_x × (p - deck line)
                v_rail[1] = v_g + vyb - wb * (z_c - zb)
                v_rail[2] = vzb + wb * (y_c - yb_line)
                xi, eta, phi, V, cstat = creepages_core(pc, nr, e_axle, p_centre, v_centre, omega, v_rail,
                                                         omega_rail, cp[CP_V_MIN], frame)
                Fx = 0.0
                Fy = 0.0
                Mz = 0.0
                if math.isfinite(xi) and (cstat & 12) == 0:     # no degenerate frame / invalid input
                    Fx, Fy, Mz, flag = _creep(law, ow[K.F_SEMI_A], ow[K.F_SEMI_B], xi, eta, phi, N, cp, t_nodes,
                                              coef, tab)
                    cstat |= flag
                else:
                    for i in range(3):
                        frame[0, i] = 0.0
                        frame[1, i] = 0.0
                        frame[2, i] = 0.0
                Fgx = N * nr[0] + Fx * frame[0, 0] + Fy * frame[1, 0]
                Fgy = N * nr[1] + Fx * frame[0, 1] + Fy * frame[1, 1]
                Fgz = N * nr[2] + Fx * frame[0, 2] + Fy * frame[1, 2]
                dx = pc[0] - p_centre[0]
                dy = pc[1] - p_centre[1]
                dz = pc[2] - p_centre[2]
                fx += Fgx
                fy += Fgy
                fz += Fgz
                tx += dy * Fgz - dz * Fgy + Mz * frame[2, 0]
                ty += dz * Fgx - dx * Fgz + Mz * frame[2, 1]
                tz += dx * Fgy - dy * Fgx + Mz * frame[2, 2]
                # on the rail: minus the force on the wheel, its moment about the deck's rail-top centre line and
                # the x component of minus the spin moment
                rfy -= Fgy
                rfz -= Fgz
                rmx -= (y_c - yb_line) * Fgz - (z_c - zb) * Fgy + Mz * frame[2, 0]
                r[RES_N] = N
                r[RES_FX] = Fx
                r[RES_FY] = Fy
                r[RES_MZ] = Mz
                r[RES_F_TRACK_X] = Fgx
                r[RES_F_TRACK_Y] = Fgy
                r[RES_F_TRACK_Z] = Fgz
                r[RES_P_X] = pc[0]
                r[RES_P_Y] = pc[1]
                r[RES_P_Z] = pc[2]
                r[RES_GAMMA] = ow[K.F_CONTACT_ANGLE]
                r[RES_XI] = xi
                r[RES_ETA] = eta
                r[RES_PHI] = phi
                r[RES_A] = ow[K.F_SEMI_A]
                r[RES_B] = ow[K.F_SEMI_B]
                r[RES_DELTA] = ow[K.F_PENETRATION]
                r[RES_V] = V
                r[RES_CREEP_STATUS] = cstat
        f_out[o] = fx
        f_out[o + 1] = fy
        f_out[o + 2] = fz
        # torque to the body frame: R^T tau
        f_out[o + 3] = R[0, 0] * tx + R[1, 0] * ty + R[2, 0] * tz
        f_out[o + 4] = R[0, 1] * tx + R[1, 1] * ty + R[2, 1] * tz
        f_out[o + 5] = R[0, 2] * tx + R[1, 2] * ty + R[2, 2] * tz
        rail_f[k, 0] = rfy
        rail_f[k, 1] = rfz
        rail_f[k, 2] = rmx
        if deck_state[k, 6] > 0.5:
            # generalized modal forces Φ(s)^T (Fy, Fz, Mx) of the force on the rails (bridge.add_projected_force)
            add_projected_force(s_ws[k], rfy, rfz, rmx, d_start, d_ez, deck_x0, deck_len, deck_nodes, deck_shapes,
                                work_ds, f_m)
    return -1


@njit(cache=True)
def contact_jacobian_core(q, q_t, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs,
                          nodes, meta, mono, curve_ids, warm, params, gtab, side_poses, out, law, cp, t_nodes, coef,
                          tab, deck_par, deck_x0, deck_len, deck_nodes, deck_shapes, rail_delta, phi_ws, rail_f,
                          deck_state, f0, res, f_odeq, f_odev, jac, h_pos, h_rot, h_vel):
    """``jac = -(∂f/∂q f_odeq + ∂f/∂q_t f_odev)`` by forward differences of :func:`contact_forces_core`;
    rotations perturbed by body-frame increments (R exp(h e_i)), matching the Lie-group update.  Structured: a
    wheelset's contact forces depend on its own coordinates (and the deck under it) only, so the same coordinate of
    all wheelsets is perturbed in one call — 12 calls whatever the number of wheelsets; the modal rows of those
    columns are ``Φ(s_k)^T`` times the change of wheelset k's rail force (and of ``Φ(s_k)`` when s moves).
    Bridge columns (chain rule): the contact depends on the modal coordinates only through the deck state under
    each wheelset, ``u_k = Φ(s_k) q_m`` and ``u̇_k = Φ(s_k) q̇_m`` (rows y, z, θ), so the three offsets and three
    rates of every wheelset on the deck are perturbed together (``rail_delta``: 6 calls for any number of modes and
    wheelsets): ``∂f_k/∂q_m = (∂f_k/∂u_k) Φ(s_k)``, ``∂Q/∂q_m = Σ_k Φ(s_k)^T (∂F_rail,k/∂u_k) Φ(s_k)``.
    The warm-start state is restored after every perturbed call."""
    n = q.shape[0]
    n_ws = p_ref.shape[0]
    n_w6 = 6 * n_ws
    n_m = n - n_w6
    warm0 = warm.copy()
    contact_forces_core(q, q_t, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs, nodes,
                        meta, mono, curve_ids, warm, params, gtab, side_poses, out, law, cp, t_nodes, coef, tab, deck_par,
                        deck_x0, deck_len, deck_nodes, deck_shapes, rail_delta, phi_ws, rail_f, deck_state, f0, res)
    warm[:] = warm0
    phi0 = phi_ws.copy()
    rf0 = rail_f.copy()
    on_deck = np.empty(n_ws, dtype=np.bool_)
    any_on = False
    for k in range(n_ws):
        on_deck[k] = deck_state[k, 6] > 0.5
        any_on = any_on or on_deck[k]
    f1 = np.empty(n)
    qp = q.copy()
    vp = q_t.copy()
    R = np.empty((3, 3))
    Rd = np.empty((3, 3))
    Rn = np.empty((3, 3))
    for r in range(n):
        for c in range(n):
            jac[r, c] = 0.0
    # the contact forces of a wheelset depend on its own coordinates only: the Jacobian is block diagonal, so the
    # i-th coordinate of every wheelset is perturbed in the same call (6 + 6 calls for any number of wheelsets)
    for i in range(6):
        # ---- coordinates
        h = h_pos if i < 3 else h_rot
        for k in range(n_ws):
            o = 6 * k
            if i < 3:
                qp[o + i] = q[o + i] + h_pos
            else:
                # body-frame increment: R' = R exp(h e_i) -> new rotation vector
                rotation_from_vector(q[o + 3], q[o + 4], q[o + 5], R)
                rotation_from_vector(h if i == 3 else 0.0, h if i == 4 else 0.0, h if i == 5 else 0.0, Rd)
                for a in range(3):
                    for b in range(3):
                        Rn[a, b] = R[a, 0] * Rd[0, b] + R[a, 1] * Rd[1, b] + R[a, 2] * Rd[2, b]
                _rotation_vector_from_matrix(Rn, qp, o + 3)
        contact_forces_core(qp, q_t, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs,
                            nodes, meta, mono, curve_ids, warm, params, gtab, side_poses, out, law, cp, t_nodes, coef,
                            tab, deck_par, deck_x0, deck_len, deck_nodes, deck_shapes, rail_delta, phi_ws, rail_f,
                            deck_state, f1, res)
        warm[:] = warm0
        for k in range(n_ws):
            o = 6 * k
            for r in range(6):
                jac[o + r, o + i] = -(f1[o + r] - f0[o + r]) / h * f_odeq
            for m in range(6):
                qp[o + m] = q[o + m]
            # modal rows: change of Φ(s_k)^T F_rail,k (s_k moves with the x coordinate)
            for j in range(n_m):
                d = 0.0
                for a in range(3):
                    d += phi_ws[k, a, j] * rail_f[k, a] - phi0[k, a, j] * rf0[k, a]
                jac[n_w6 + j, o + i] = -d / h * f_odeq
        # ---- velocities
        for k in range(n_ws):
            vp[6 * k + i] = q_t[6 * k + i] + h_vel
        contact_forces_core(q, vp, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs,
                            nodes, meta, mono, curve_ids, warm, params, gtab, side_poses, out, law, cp, t_nodes, coef,
                            tab, deck_par, deck_x0, deck_len, deck_nodes, deck_shapes, rail_delta, phi_ws, rail_f,
                            deck_state, f1, res)
        warm[:] = warm0
        for k in range(n_ws):
            o = 6 * k
            for r in range(6):
                jac[o + r, o + i] -= (f1[o + r] - f0[o + r]) / h_vel * f_odev
            vp[o + i] = q_t[o + i]
            for j in range(n_m):
                d = 0.0
                for a in range(3):
                    d += phi0[k, a, j] * (rail_f[k, a] - rf0[k, a])
                jac[n_w6 + j, o + i] -= d / h_vel * f_odev
    # ---- bridge columns by the chain rule through the deck state under each wheelset (6 calls)
    if n_m > 0 and any_on:
        g = np.empty(n_m)
        for a in range(6):
            if a < 2:
                h = h_pos
            elif a == 2:
                h = h_rot
            else:
                h = h_vel
            scale = f_odeq if a < 3 else f_odev
            row = a % 3                                  # the row of Φ the perturbed quantity belongs to
            for k in range(n_ws):
                rail_delta[k, a] = h
            contact_forces_core(q, q_t, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs,
                                nodes, meta, mono, curve_ids, warm, params, gtab, side_poses, out, law, cp, t_nodes, coef,
                                tab, deck_par, deck_x0, deck_len, deck_nodes, deck_shapes, rail_delta, phi_ws,
                                rail_f, deck_state, f1, res)
            warm[:] = warm0
            for k in range(n_ws):
                rail_delta[k, a] = 0.0
            for k in range(n_ws):
                if not on_deck[k]:
                    continue
                o = 6 * k
                for r in range(6):
                    d = (f1[o + r] - f0[o + r]) / h * scale
                    for j in range(n_m):
                        jac[o + r, n_w6 + j] -= d * phi0[k, row, j]
                for i2 in range(n_m):
                    d = 0.0
                    for b in range(3):
                        d += phi0[k, b, i2] * (rail_f[k, b] - rf0[k, b])
                    g[i2] = d / h * scale
                for i2 in range(n_m):
                    for j in range(n_m):
                        jac[n_w6 + i2, n_w6 + j] -= g[i2] * phi0[k, row, j]
    # leave res/out describing the unperturbed state
    contact_forces_core(q, q_t, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs, nodes,
                        meta, mono, curve_ids, warm, params, gtab, side_poses, out, law, cp, t_nodes, coef, tab, deck_par,
                        deck_x0, deck_len, deck_nodes, deck_shapes, rail_delta, phi_ws, rail_f, deck_state, f0, res)
    warm[:] = warm0


@njit(cache=True)
def _rotation_vector_from_matrix(R, v, o):
    """Rotation vector of R into v[o:o+3] (angle in [0, π])."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    c = min(max(0.5 * (tr - 1.0), -1.0), 1.0)
    th = math.acos(c)
    wx = R[2, 1] - R[1, 2]
    wy = R[0, 2] - R[2, 0]
    wz = R[1, 0] - R[0, 1]
    if th < 1e-8:
        v[o] = 0.5 * wx
        v[o + 1] = 0.5 * wy
        v[o + 2] = 0.5 * wz
        return
    s = math.sin(th)
    if s > 1e-6:
        f = th / (2.0 * s)
        v[o] = f * wx
        v[o + 1] = f * wy
        v[o + 2] = f * wz
        return
    # near π: axis from the diagonal
    ax = math.sqrt(max(0.5 * (R[0, 0] + 1.0), 0.0))
    ay = math.sqrt(max(0.5 * (R[1, 1] + 1.0), 0.0))
    az = math.sqrt(max(0.5 * (R[2, 2] + 1.0), 0.0))
    if ax >= ay and ax >= az:
        ay = math.copysign(ay, R[0, 1] + R[1, 0])
        az = math.copysign(az, R[0, 2] + R[2, 0])
    elif ay >= az:
        ax = math.copysign(ax, R[0, 1] + R[1, 0])
        az = math.copysign(az, R[1, 2] + R[2, 1])
    else:
        ax = math.copysign(ax, R[0, 2] + R[2, 0])
        ay = math.copysign(ay, R[1, 2] + R[2, 1])
    v[o] = th * ax
    v[o + 1] = th * ay
    v[o + 2] = th * az


# ---------------------------------------------------------------------------------------------- Python front
def _shear(E_wheel, nu_wheel, E_rail, nu_rail):
    """Kalker's quasi-identical combination: 1/G = (1/G_w + 1/G_r)/2, ν/G = (ν_w/G_w + ν_r/G_r)/2 (Kalker 1990,
    Sec. 1.5); for equal materials G and ν themselves."""
    G_w = E_wheel / (2.0 * (1.0 + nu_wheel))
    G_r = E_rail / (2.0 * (1.0 + nu_rail))
    G = 2.0 / (1.0 / G_w + 1.0 / G_r)
    nu = G * 0.5 * (nu_wheel / G_w + nu_rail / G_r)
    return G, nu


class WheelRailContact:
    """The wheel–rail contact of all wheelsets of a model as one Exudyn ``ObjectGenericODE2`` (module docstring).

    Parameters
    ----------
    mbs : the Exudyn ``MainSystem`` (not yet assembled).
    wheelset_nodes : Exudyn node numbers of the wheelsets (``NodeType.RotationRotationVector``, reference
        rotation zero, i.e. the wheelset axes parallel to the track axes at the reference configuration).
    pair : the wheel and rail profiles in place (:class:`~exudyn_wheelrail.contact.WheelRailPair`).
    speed_m_s : running speed V [m/s] (rail material velocity ``-V`` in the moving frame).
    track : :class:`~.track.RigidStraightTrack` (irregularities); default a perfect track.
    s_start_m : track distance of the model frame's origin at t = 0.
    frame : ``"moving"`` (the model frame translates with V; default, as :func:`.vehicle_builder.build_vehicle`)
        or ``"track"`` (the frame is fixed to the track; wheelsets carry their forward speed themselves).
    creep_law : ``"table"`` (default: the USETAB-style table of Kalker's exact theory, as in the paper,
        :mod:`exudyn_wheelrail.creep.table`), ``"fastsim"``, ``"shen_hedrick_elkins"``, ``"polach"`` (cheap laws,
        :mod:`exudyn_wheelrail.creep.laws`), ``"linear"`` (Kalker's linear theory, no saturation) or ``"none"``.
        Outside a law's semi-axis-ratio range (Table E.3's 0.1–10 for the laws built on it, the table's own range
        for ``"table"``) the law is evaluated for the ellipse of the same area at the nearest allowed ratio and the
        point is flagged (``RES_CREEP_STATUS`` bit 64).
    creep_table : a :class:`~exudyn_wheelrail.creep.table.CreepTable` or a table file for ``"table"`` (default:
        the packaged table).
    mu : friction coefficient.  ``E_*``, ``nu_*``: materials (Hertz uses both; the creep laws use Kalker's
        quasi-identical combination).
    fastsim_grid : ``(n_x, n_y)`` of FASTSIM.
    global_search : run the kernel's global scan at every evaluation (slower; follows jumps without warm start).
    jacobian : ``"numerical"`` — a compiled forward-difference Jacobian user function for implicit solvers
        (default); ``None`` — none (Exudyn's own handling).
    bridge : an :class:`~exudyn_wheelrail.structures.bridge.ExudynBridge` (:func:`~exudyn_wheelrail.structures.
        bridge.add_bridge` in the same ``mbs``) or ``None`` (rigid track).  The object then also spans the bridge's
        modal node: wheels on the deck see the deck's rail displacement and velocity, and the forces on the rails
        go to the modal coordinates (module docstring, "Flexible bridge").  The deck's track distances are those
        of the track (``BridgeModel.start_m``), the same s as the irregularity.  A support motion of the bridge
        (``bridge.add_support_motion``, before or after this call) moves the rails of every wheelset laterally
        by the ground displacement and velocity as well.
    """

    def __init__(self, mbs, wheelset_nodes, pair: WheelRailPair, *, speed_m_s: float,
                 track: RigidStraightTrack | None = None, s_start_m: float = 0.0, frame: str = "moving",
                 creep_law: str = "table", mu: float = 0.3, E_wheel_Pa: float = 2.1e11, nu_wheel: float = 0.28,
                 E_rail_Pa: float = 2.1e11, nu_rail: float = 0.28, fastsim_grid=(DEFAULT_NX, DEFAULT_NY),
                 creep_table=None, global_search: bool = False, jacobian: str | None = "numerical",
                 v_min_m_s: float = DEFAULT_V_MIN_M_S, name: str = "wheel_rail_contact", bridge=None,
                 geometry: str = "online", geometry_grid=None):
        import exudyn as exu
        from exudyn.itemInterface import ObjectGenericODE2, VObjectGenericODE2

        from ..contact.wheelset import WheelsetContact
        from ..structures.bridge import ExudynBridge

        if bridge is not None and not isinstance(bridge, ExudynBridge):
            raise TypeError(f"bridge={bridge!r}: expected an ExudynBridge (structures.bridge.add_bridge) or None")
        if frame not in ("moving", "track"):
            raise ValueError(f"frame={frame!r}: expected 'moving' or 'track'")
        if creep_law not in CREEP_LAWS:
            raise ValueError(f"creep_law={creep_law!r}: expected one of {sorted(CREEP_LAWS)}")
        if geometry not in GEOMETRY_MODES:
            raise ValueError(f"geometry={geometry!r}: expected one of {GEOMETRY_MODES}")
        if not isinstance(pair, WheelRailPair):
            raise TypeError(f"pair: expected a WheelRailPair (exudyn_wheelrail.contact), got {type(pair).__name__}")
        speed_m_s = finite("speed_m_s", speed_m_s)
        if not speed_m_s >= 0.0:
            raise ValueError(f"speed_m_s: {speed_m_s!r}: expected a finite speed >= 0")
        mu = finite("mu", mu)
        if not mu >= 0.0:
            raise ValueError(f"mu: {mu!r}: expected a finite friction coefficient >= 0")
        E_wheel_Pa = youngs_modulus("E_wheel_Pa", E_wheel_Pa)
        E_rail_Pa = youngs_modulus("E_rail_Pa", E_rail_Pa)
        nu_wheel = poisson_ratio("nu_wheel", nu_wheel)
        nu_rail = poisson_ratio("nu_rail", nu_rail)
        s_start_m = finite("s_start_m", s_start_m)
        try:
            n_x, n_y = fastsim_grid
        except (TypeError, ValueError):
            raise ValueError(f"fastsim_grid: expected two positive integers (n_x, n_y), got {fastsim_grid!r}") from None
        if not all(not isinstance(v, bool) and int(v) == v and v >= 1 for v in (n_x, n_y)):
            raise ValueError(f"fastsim_grid: expected two positive integers (n_x, n_y), got {fastsim_grid!r}")
        v_min_m_s = finite("v_min_m_s", v_min_m_s)
        if not v_min_m_s > 0.0:
            raise ValueError(f"v_min_m_s: {v_min_m_s!r}: expected a speed > 0 (the creepages' standstill guard)")
        self.nodes_exu = list(wheelset_nodes)
        if not self.nodes_exu:
            raise ValueError("wheelset_nodes: no wheelset nodes given")
        n_ws = len(self.nodes_exu)
        p_ref = np.zeros((n_ws, 3))
        for k, n in enumerate(self.nodes_exu):
            try:
                node_type = str(mbs.GetNode(n).get("nodeType", ""))
            except Exception as exc:          # Exudyn raises its own error types for a bad index
                raise ValueError(f"wheelset_nodes: node {n!r} is not a node of this system ({exc})") from None
            if not node_type.startswith(WHEELSET_NODE_TYPE_PREFIX):
                raise ValueError(f"wheelset_nodes: node {n} is a {node_type or 'non-rigid'} node; the wheel-rail "
                                 f"contact needs Lie-group rigid-body nodes with a rotation vector: create the "
                                 f"wheelset bodies with nodeType=exu.NodeType.RotationRotationVector "
                                 f"(NodeRigidBodyRotVecLG)")
            ref = np.asarray(mbs.GetNodeParameter(n, "referenceCoordinates"), dtype=float)
            if np.any(np.abs(ref[3:]) > 1e-12):
                raise ValueError(f"wheelset_nodes: node {n}: the reference rotation must be zero (wheelset axes "
                                 "parallel to the track axes); put the initial rotation into the initial coordinates")
            p_ref[k] = ref[:3]
        self.p_ref = p_ref
        self.pair = pair
        self.speed_m_s = float(speed_m_s)
        self.track = track if track is not None else RigidStraightTrack()
        self.s_start_m = float(s_start_m)
        self.moving_frame = frame == "moving"
        self.creep_law = creep_law
        self._kc = WheelsetContact(pair, n_ws, E_wheel_Pa, nu_wheel, E_rail_Pa, nu_rail, global_search=global_search)
        self.geometry = geometry
        self.geometry_table = None
        if geometry == "table":
            if global_search:
                raise ValueError("geometry='table' replaces the search: it cannot be combined with global_search=True")
            ids = self._kc.curve_ids
            if not np.all(ids == ids[0]):
                raise ValueError("geometry='table' needs the same wheel/rail curves on every wheel")
            self.geometry_table = GT.geometry_table(self._kc.nodes, self._kc.meta, self._kc.mono, ids[0],
                                                    self._kc.params, geometry_grid)
            par, cz_ref, data = self.geometry_table.arrays()
        else:
            par, cz_ref, data = GT._unused_arrays()
        self._gtab = (par, cz_ref, data, np.zeros(GT.N_STATS, dtype=np.int64))
        G, nu = _shear(E_wheel_Pa, nu_wheel, E_rail_Pa, nu_rail)
        cp = np.zeros(N_CP)
        cp[CP_MU] = mu
        cp[CP_G] = G
        cp[CP_NU] = nu
        cp[CP_NX], cp[CP_NY] = fastsim_grid
        cp[CP_V_MIN] = v_min_m_s
        cp[CP_AB_MIN] = _linear.A_OVER_B_MIN
        cp[CP_AB_MAX] = _linear.A_OVER_B_MAX
        self.cp = cp
        self._law = CREEP_LAWS[creep_law]
        if creep_law == "table":
            from ..creep.table import NU_TOLERANCE, load_table
            table = load_table(creep_table) if not hasattr(creep_table, "core_arrays") else creep_table
            if abs(nu - table.poisson) > NU_TOLERANCE + 1e-12:
                raise ValueError(f"creep table built for Poisson's ratio {table.poisson}, the materials give {nu:.3f} "
                                 f"(accepted ±{NU_TOLERANCE}); build a table for this ν (python -m exudyn_wheelrail "
                                 "creep-table --nu ...) or use creep_law='fastsim'")
            t_nodes, t_breaks, r_pad, th_pad, ps_pad, values_pad = table.core_arrays()
            self._tab = (np.ascontiguousarray(t_nodes, dtype=float), np.ascontiguousarray(t_breaks, dtype=np.int8),
                         np.ascontiguousarray(r_pad, dtype=float), np.ascontiguousarray(th_pad, dtype=float),
                         np.ascontiguousarray(ps_pad, dtype=float), np.ascontiguousarray(values_pad, dtype=float))
            cp[CP_AB_MIN], cp[CP_AB_MAX] = table.ratio_nodes[0], table.ratio_nodes[-1]
            self.creep_table = table
        else:
            self._tab = (np.zeros(2), np.zeros(2, np.int8), np.zeros(3), np.zeros(3), np.zeros(3),
                         np.zeros((2, 3, 3, 3, 3)))
            self.creep_table = None
        packed = self.track.packed()
        self._irr = (np.ascontiguousarray(packed.rows, dtype=float), np.ascontiguousarray(packed.knots, dtype=float),
                     np.ascontiguousarray(packed.coefs, dtype=float))
        # the bridge: its shape table (empty arrays, no modal coordinates, without a bridge)
        self.bridge = bridge
        if bridge is not None:
            tb = bridge.modes.table
            self.n_modes = int(bridge.modes.n_modes)
            self._deck = (np.array([tb.start_m, tb.rail_height_m, 0.0, 0.0], dtype=float),
                          np.ascontiguousarray(tb.elem_x0, dtype=float), np.ascontiguousarray(tb.elem_len, dtype=float),
                          np.ascontiguousarray(tb.elem_nodes, dtype=np.int64),
                          np.ascontiguousarray(tb.node_shapes, dtype=float))
        else:
            self.n_modes = 0
            self._deck = (np.zeros(4), np.zeros(0), np.zeros(0), np.zeros((0, 2), dtype=np.int64),
                          np.zeros((0, 5, 0)))
        self._rail_delta = np.zeros((n_ws, 6))
        self._phi_ws = np.zeros((n_ws, 3, self.n_modes))
        self._rail_f = np.zeros((n_ws, 3))
        self._deck_state = np.zeros((n_ws, N_DECK_STATE))
        n = 6 * n_ws + self.n_modes
        self.n_coordinates = n
        self._f = np.zeros(n)
        self._jac = np.zeros((n, n))
        self.results = np.zeros((2 * n_ws, K.N_SLOTS, N_RES))
        self._side_poses = np.zeros((2 * n_ws, 3))
        self.n_calls = 0
        node_numbers = self.nodes_exu + ([bridge.modal_node] if bridge is not None else [])
        kwargs = dict(name=name, nodeNumbers=node_numbers, massMatrix=np.zeros((n, n)),
                      forceUserFunction=self._force_uf, visualization=VObjectGenericODE2(show=False))
        if jacobian == "numerical":
            kwargs["jacobianUserFunction"] = self._jacobian_uf
        elif jacobian is not None:
            raise ValueError(f"jacobian={jacobian!r}: expected 'numerical' or None")
        obj = ObjectGenericODE2(**kwargs)
        self.object = mbs.AddObject(obj)
        self._exu = exu

    # -- the compiled call -------------------------------------------------------------------------------------
    def _set_ground(self, t: float) -> None:
        """Ground (support) motion of the bridge at t into ``deck_par[2:4]`` (zero without one)."""
        motion = self.bridge.support_motion if self.bridge is not None else None
        par = self._deck[0]
        if motion is None:
            par[2] = par[3] = 0.0
            return
        y, v, _ = motion.state(t)
        if not (math.isfinite(y) and math.isfinite(v)):
            raise ContactStateError(f"wheel-rail contact at t = {t:.6g} s: the bridge's support motion gives a "
                                    f"non-finite ground state (y = {y!r}, v = {v!r})", time_s=float(t))
        par[2] = y
        par[3] = v

    def ground_state(self, t: float) -> tuple[float, float]:
        """``(y_g, ẏ_g)`` added to the rails at t (the bridge's support motion; zeros without one)."""
        motion = self.bridge.support_motion if self.bridge is not None else None
        if motion is None:
            return 0.0, 0.0
        y, v, _ = motion.state(float(t))
        return float(y), float(v)

    def _args(self, q, q_t, t):
        kc = self._kc
        return (q, q_t, self.p_ref, t, self.speed_m_s, self.moving_frame, self.s_start_m, *self._irr, kc.nodes,
                kc.meta, kc.mono, kc.curve_ids, kc.warm, kc.params, self._gtab, self._side_poses, kc.out, self._law, self.cp,
                _linear._T_NODES, _linear._COEF, self._tab, *self._deck, self._rail_delta, self._phi_ws, self._rail_f,
                self._deck_state)

    def forces(self, q, q_t, t: float) -> np.ndarray:
        """Generalized contact forces for the object coordinates (force global, torque body frame per wheelset, then
        the generalized modal forces of the bridge, if any); updates :attr:`results`.  Raises
        :class:`ContactStateError` for non-finite coordinates."""
        q = np.ascontiguousarray(q, dtype=float)
        q_t = np.ascontiguousarray(q_t, dtype=float)
        if q.shape != (self.n_coordinates,) or q_t.shape != (self.n_coordinates,):
            raise ValueError(f"coordinates of shapes {q.shape}, {q_t.shape}: expected ({self.n_coordinates},) each "
                             f"(6 per wheelset{f' + {self.n_modes} modal' if self.n_modes else ''})")
        self._set_ground(float(t))
        bad = contact_forces_core(*self._args(q, q_t, float(t)), self._f, self.results)
        self.n_calls += 1
        if bad == len(self.nodes_exu):
            raise ContactStateError(f"wheel-rail contact at t = {t:.6g} s: the bridge's modal coordinates are "
                                    "non-finite — the simulation diverged (time step too large?)", time_s=float(t))
        if bad >= 0:
            raise ContactStateError(f"wheel-rail contact at t = {t:.6g} s: wheelset {bad} (node "
                                    f"{self.nodes_exu[bad]}) has non-finite coordinates — the simulation diverged "
                                    "(time step too large?)", time_s=float(t), wheelset=int(bad))
        return self._f

    def _force_uf(self, mbs, t, itemIndex, q, q_t):
        return self.forces(q, q_t, t)

    def _jacobian_uf(self, mbs, t, itemIndex, q, q_t, fODE2, fODE2_t):
        q = np.ascontiguousarray(q, dtype=float)
        q_t = np.ascontiguousarray(q_t, dtype=float)
        self._set_ground(float(t))
        contact_jacobian_core(*self._args(q, q_t, float(t)), self._f, self.results, float(fODE2), float(fODE2_t),
                              self._jac, 1e-7, 1e-7, 1e-5)
        return self._jac

    # -- state of the model ----------------------------------------------------------------------------------------
    def coordinates(self, mbs):
        """Current (q, q_t) of the object's nodes from the Exudyn system: the wheelset nodes, then the bridge's
        modal node (if any)."""
        exu = self._exu
        nodes = self.nodes_exu + ([self.bridge.modal_node] if self.bridge is not None else [])
        q = np.concatenate([np.atleast_1d(mbs.GetNodeOutput(n, exu.OutputVariableType.Coordinates)) for n in nodes])
        v = np.concatenate([np.atleast_1d(mbs.GetNodeOutput(n, exu.OutputVariableType.Coordinates_t)) for n in nodes])
        return q, v

    def evaluate(self, mbs, t: float) -> np.ndarray:
        """Evaluate the contact at the model's current state (e.g. after a step, for outputs) without changing the
        warm start; returns :attr:`results`.  ``t`` must be the time *of that state* (the track irregularity is
        evaluated at ``s_start + V t + x``): Exudyn calls a pre-step user function with the time at the *end* of the
        coming step while the state is still at its start — pass the previous step's time there."""
        q, v = self.coordinates(mbs)
        warm = self._kc.warm.copy()
        try:
            self.forces(q, v, t)
        finally:
            self._kc.warm[:] = warm
        return self.results

    def warm_up(self, mbs, jacobian: bool = True) -> None:
        """Load (or compile) the compiled code outside a timed solve: one force and, with ``jacobian``, one
        Jacobian evaluation at the model's current state; the warm start is left as it was."""
        q, v = self.coordinates(mbs)
        warm = self._kc.warm.copy()
        try:
            self.forces(q, v, 0.0)
            if jacobian:
                self._jacobian_uf(mbs, 0.0, self.object, q, v, 1.0, 0.0)
        finally:
            self._kc.warm[:] = warm
            self.n_calls = 0

    def save_warm_start(self) -> np.ndarray:
        """A copy of the contact search's warm-start state (restore with :meth:`restore_warm_start`)."""
        return self._kc.warm.copy()

    def restore_warm_start(self, state: np.ndarray) -> None:
        self._kc.warm[:] = state

    # -- readable results ------------------------------------------------------------------------------------------
    def wheel_force_N(self, wheelset: int, side: str) -> np.ndarray:
        """Total contact force (both regions) on a wheel, model frame, from the last evaluation."""
        w = 2 * wheelset + (0 if side == "right" else 1)
        return self.results[w, :, RES_F_TRACK_X:RES_F_TRACK_Z + 1].sum(axis=0)

    def modal_forces_N(self) -> np.ndarray:
        """Generalized modal forces on the bridge from the last evaluation (a copy; empty without a bridge)."""
        return self._f[6 * len(self.nodes_exu):].copy()

    def rail_forces_N(self) -> np.ndarray:
        """Per wheelset the force on the rails that was projected on the deck (last evaluation): rows
        ``(Fy, Fz, Mx)`` — minus the contact forces on the wheels, y right, z down, Mx about the deck's deflected
        rail-top centre line (z down: positive turns +y towards +z); filled on and off the deck."""
        return self._rail_f.copy()

    def deck_state(self) -> np.ndarray:
        """Per wheelset the deck state under it (last evaluation): displacement ``(y, z, θ)`` of the rails' centre
        line at rail top, its material velocity ``(ẏ, ż, θ̇)`` and a 0/1 on-deck flag (zero off the deck) — relative
        to the supports (a support motion's ``y_g``, ``ẏ_g`` come on top: :meth:`ground_state`)."""
        return self._deck_state.copy()

    def wheelset_rail_pose(self) -> np.ndarray:
        """Per wheelset the pose relative to its rail pair that the contact search used (last evaluation): rows
        ``(y_rel, z_rel, roll_rel)`` — lateral and vertical displacement of the axle centre from the rails' centre
        line at rail top (irregularity, ground motion and deck included; in the rail pair's frame, rolled with the
        deck) [m] and roll relative to the rails [rad].  ``y_rel`` is the lateral wheelset–rail displacement."""
        return self._side_poses[0::2].copy()

    def geometry_statistics(self) -> dict:
        """Wheel evaluations answered by the geometry table and by the online search since the start (both count
        the Jacobian's perturbed calls)."""
        st = self._gtab[3]
        return {"mode": self.geometry, "wheel_evaluations_table": int(st[GT.STAT_TABLE]),
                "wheel_evaluations_online": int(st[GT.STAT_FALLBACK]),
                "table": self.geometry_table.describe() if self.geometry_table is not None else None}

    def skipped(self) -> dict:
        """What the contact evaluation skipped since the start, because the scene did not need it (counts include
        the Jacobian's perturbed calls).  Each skip is tested to change results by less than a stated tolerance
        (tests/test_skips.py)."""
        st = self._gtab[3]
        n_online = int(st[GT.STAT_FALLBACK])
        n_regions = 2 * n_online
        frac = (lambda a, b: float(a) / b if b else 0.0)
        return {
            "contact_search_by_geometry_table": {
                "skipped": int(st[GT.STAT_TABLE]), "of_wheel_evaluations": int(st[GT.STAT_TABLE]) + n_online,
                "what": "the online search replaced by the precomputed geometry (rigid rail profile)"
                        + ("" if self.geometry == "table" else "; off (geometry 'online')")},
            "flange_search_far_from_flange": {
                "skipped": int(st[GT.STAT_FLANGE_SKIPPED]), "of_online_flange_regions": n_online,
                "fraction": frac(st[GT.STAT_FLANGE_SKIPPED], n_online),
                "what": "flange region reported apart by the separation bound (gap larger than the motion since "
                        "its last search), no search"},
            "tread_search_lifted_off": {
                "skipped": int(st[GT.STAT_TREAD_SKIPPED]), "of_online_tread_regions": n_online,
                "what": "tread region reported apart by the separation bound (wheel lifted), no search"},
            "concave_search": {
                "run": int(st[GT.STAT_CONCAVE]), "skipped": n_regions - int(st[GT.STAT_CONCAVE]),
                "of_online_regions": n_regions,
                "what": "the concave (discretised) search runs only where the convex one fails or lands on a "
                        "conformal point"},
            "bridge_coupling": {
                "skipped": int(st[GT.STAT_OFF_DECK]) if self.bridge is not None else None,
                "of_wheelset_evaluations": int(st[GT.STAT_ON_DECK] + st[GT.STAT_OFF_DECK]),
                "what": "deck state and modal projection only for wheelsets on the deck"
                        + ("" if self.bridge is not None else "; no bridge in this model")},
            "spin_terms": {"skipped": 0, "what": "not skipped: the creep laws always include spin"},
        }

    def flange_contact(self, wheelset: int, side: str) -> bool:
        """Whether the flange region carries a contact (last evaluation)."""
        w = 2 * wheelset + (0 if side == "right" else 1)
        return bool(self.results[w, 1, RES_STATUS] > 0 and self.results[w, 1, RES_N] > 0.0)


def add_wheel_rail_contact(mbs, wheelset_nodes, pair: WheelRailPair, **options) -> WheelRailContact:
    """Add the wheel–rail contact of the given wheelset nodes to ``mbs`` (before ``mbs.Assemble()``); options as
    :class:`WheelRailContact`.  Returns the contact handle (results, forces, the Exudyn object number)."""
    return WheelRailContact(mbs, wheelset_nodes, pair, **options)


def static_axle_offset_m(pair: WheelRailPair, wheel_load_N: float, r0_m: float, E_Pa: float = 2.1e11,
                         nu: float = 0.28) -> float:
    """Vertical offset (z down) of the centred wheelset's axle from its nominal height ``-r0`` at which each wheel
    carries ``wheel_load_N`` by its normal force (quasi-static, no creep): the rigid touching height plus the Hertz
    approach.  Used to start a simulation in equilibrium."""
    from ..analysis.quasi_static import solve_quasi_static
    from ..contact.wheelset import WheelsetContact

    contact = WheelsetContact(pair, 1, E_Pa, nu, E_Pa, nu, global_search=True)
    res = solve_quasi_static(contact, 0.0, 0.0, wheel_load_N, 1.0, shear_modulus_Pa=E_Pa / (2 * (1 + nu)),
                             poisson=nu, creep_law=lambda *a: (0.0, 0.0, 0.0), pitch_rate_rad_s=-1.0 / r0_m,
                             semi_axis_ratio_range=None)
    if not res.converged:
        raise RuntimeError(f"static wheelset position not found: {res.message}")
    return res.z_m - (-r0_m)


def place_on_rails(mbs, model, pair: WheelRailPair, E_Pa: float = 2.1e11, nu: float = 0.28) -> float:
    """Shift every body of a :class:`~.vehicle_builder.VehicleModel` vertically so the centred wheelsets start in
    static equilibrium on the rails (the suspension preloads are unchanged: all bodies move together).  Call before
    ``mbs.Assemble()``.  Returns the shift [m] (z down)."""
    loads = model.load_path.wheel if model.load_path is not None else None
    if loads is None:
        raise ValueError("the vehicle model has no static load path (build it with preload=True)")
    dz = static_axle_offset_m(pair, float(np.mean(loads)), model.wheelsets[0].r0_m, E_Pa, nu)
    for body in model.bodies:
        q0 = np.array(mbs.GetNodeParameter(body.node, "initialCoordinates"), dtype=float)
        q0[2] += dz
        mbs.SetNodeParameter(body.node, "initialCoordinates", q0.tolist())
    return dz
