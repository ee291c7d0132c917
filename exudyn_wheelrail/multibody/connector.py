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
4. evaluates the creep law (FASTSIM by default, the USETAB-style table of Kalker's exact theory, or a cheap
   law) in the contact frame;
5. applies ``N n_rail + Fx x_c + Fy y_c`` at the contact point and the spin moment ``Mz z_c`` to the wheelset
   (generalized forces: force in the global frame, torque in the body frame — the Lie-group node's velocity
   coordinates are the body-frame angular velocity), and records the equal and opposite force on the rail.

Separation gives no force; re-contact is found by the kernel's separation bound and warm/global search.

Implicit solvers: a Jacobian user function returns ``-∂f/∂q fODE2 - ∂f/∂q_t fODE2_t`` by forward differences of
the same compiled call (position and velocity perturbations; rotations perturbed by body-frame increments, the
Lie-group tangent), with the warm-start state saved and restored; block diagonal per wheelset, so 12 calls
whatever the number of wheelsets.

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

from ..contact import kernel as K
from ..contact.creepage import DEFAULT_V_MIN_M_S, creepages_core, yawed_contact_point_core
from ..contact.pair import WheelRailPair
from ..creep import linear as _linear
from ..creep.fastsim import DEFAULT_NX, DEFAULT_NY, fastsim_core
from ..creep.laws import polach_core, she_core
from ..creep.table import table_core
from .track import RigidStraightTrack, irregularity_at

__all__ = ["WheelRailContact", "add_wheel_rail_contact", "contact_forces_core", "ContactStateError",
           "CREEP_LAWS", "N_RES"] + [n for n in dir() if n.startswith("RES_")]

# ---- creep laws --------------------------------------------------------------------------------------------------
LAW_FASTSIM = 0
LAW_LINEAR = 1        # Kalker's linear theory, unsaturated (tests, small-creepage studies)
LAW_NONE = 2          # normal forces only
LAW_TABLE = 3         # the USETAB-style table of Kalker's exact theory (creep.table)
LAW_SHE = 4           # Shen-Hedrick-Elkins (creep.laws)
LAW_POLACH = 5        # Polach (creep.laws), k_A = k_S = 1
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
N_RES = 22

CREEP_AB_CLAMPED = 64


class ContactStateError(RuntimeError):
    """The multibody state handed to the contact is not usable (NaN/inf coordinates)."""


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
                        nodes, meta, mono, curve_ids, warm, params, side_poses, out, law, cp, t_nodes, coef,
                        tab, f_out, res):
    """All wheelsets in one call.  ``q``, ``q_t`` (6 n): per wheelset displacement (global), rotation vector,
    velocity (global) and body-frame angular velocity (Lie-group node coordinates); ``p_ref`` (n, 3) reference
    positions.  Fills ``f_out`` (6 n): force (global) and torque (body frame) per wheelset, and ``res``
    (2 n, N_SLOTS, N_RES).  Returns the index of the first wheelset with a non-finite state, or -1."""
    n_ws = p_ref.shape[0]
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
        irr[k, 0] = y_irr
        irr[k, 1] = z_irr
        side_poses[2 * k, 0] = py - y_irr
        side_poses[2 * k, 1] = pz - z_irr
        side_poses[2 * k, 2] = roll
        side_poses[2 * k + 1, 0] = -(py - y_irr)
        side_poses[2 * k + 1, 1] = pz - z_irr
        side_poses[2 * k + 1, 2] = -roll
    for i in range(f_out.shape[0]):
        f_out[i] = 0.0
    res[:, :, :] = 0.0
    if bad >= 0:
        return bad
    K.evaluate_wheels(nodes, meta, mono, curve_ids, side_poses, warm, params, out)
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
        for side in range(2):
            w = 2 * k + side
            mirror = 1.0 if side == 0 else -1.0
            for reg in range(out.shape[1]):
                ow = out[w, reg]
                r = res[w, reg]
                r[RES_STATUS] = ow[K.F_STATUS]
                r[RES_FLAGS] = ow[K.F_FLAGS]
                r[RES_S_TRACK] = s_ws[k]
                if ow[K.F_STATUS] <= 0:
                    continue
                N = ow[K.F_NORMAL_FORCE]
                y_t = mirror * ow[K.F_PW_Y] + irr[k, 0]
                z_t = ow[K.F_PW_Z] + irr[k, 1]
                ny = mirror * ow[K.F_NR_Y]
                nz = ow[K.F_NR_Z]
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
    return -1


@njit(cache=True)
def contact_jacobian_core(q, q_t, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs,
                          nodes, meta, mono, curve_ids, warm, params, side_poses, out, law, cp, t_nodes, coef,
                          tab, f0, res, f_odeq, f_odev, jac, h_pos, h_rot, h_vel):
    """``jac = -(∂f/∂q f_odeq + ∂f/∂q_t f_odev)`` by forward differences of :func:`contact_forces_core`;
    rotations perturbed by body-frame increments (R exp(h e_i)), matching the Lie-group update.  Structured: the
    Jacobian is block diagonal per wheelset (a wheelset's contact forces depend on its own coordinates only), so
    the same coordinate of all wheelsets is perturbed in one call — 12 calls whatever the number of wheelsets.
    The warm-start state is restored after every perturbed call."""
    n = q.shape[0]
    warm0 = warm.copy()
    contact_forces_core(q, q_t, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs, nodes,
                        meta, mono, curve_ids, warm, params, side_poses, out, law, cp, t_nodes, coef, tab, f0, res)
    warm[:] = warm0
    f1 = np.empty(n)
    qp = q.copy()
    vp = q_t.copy()
    R = np.empty((3, 3))
    Rd = np.empty((3, 3))
    Rn = np.empty((3, 3))
    n_ws = n // 6
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
                            nodes, meta, mono, curve_ids, warm, params, side_poses, out, law, cp, t_nodes, coef,
                            tab, f1, res)
        warm[:] = warm0
        for k in range(n_ws):
            o = 6 * k
            for r in range(6):
                jac[o + r, o + i] = -(f1[o + r] - f0[o + r]) / h * f_odeq
            for m in range(6):
                qp[o + m] = q[o + m]
        # ---- velocities
        for k in range(n_ws):
            vp[6 * k + i] = q_t[6 * k + i] + h_vel
        contact_forces_core(q, vp, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs,
                            nodes, meta, mono, curve_ids, warm, params, side_poses, out, law, cp, t_nodes, coef,
                            tab, f1, res)
        warm[:] = warm0
        for k in range(n_ws):
            o = 6 * k
            for r in range(6):
                jac[o + r, o + i] -= (f1[o + r] - f0[o + r]) / h_vel * f_odev
            vp[o + i] = q_t[o + i]
    # leave res/out describing the unperturbed state
    contact_forces_core(q, q_t, p_ref, t, speed, moving_frame, s_start, irr_rows, irr_knots, irr_coefs, nodes,
                        meta, mono, curve_ids, warm, params, side_poses, out, law, cp, t_nodes, coef, tab, f0, res)
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
    creep_law : ``"fastsim"`` (default), ``"table"`` (the USETAB-style table of Kalker's exact theory,
        :mod:`exudyn_wheelrail.creep.table`), ``"shen_hedrick_elkins"``, ``"polach"`` (cheap laws,
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
    """

    def __init__(self, mbs, wheelset_nodes, pair: WheelRailPair, *, speed_m_s: float,
                 track: RigidStraightTrack | None = None, s_start_m: float = 0.0, frame: str = "moving",
                 creep_law: str = "fastsim", mu: float = 0.3, E_wheel_Pa: float = 2.1e11, nu_wheel: float = 0.28,
                 E_rail_Pa: float = 2.1e11, nu_rail: float = 0.28, fastsim_grid=(DEFAULT_NX, DEFAULT_NY),
                 creep_table=None, global_search: bool = False, jacobian: str | None = "numerical",
                 v_min_m_s: float = DEFAULT_V_MIN_M_S, name: str = "wheel_rail_contact"):
        import exudyn as exu
        from exudyn.itemInterface import ObjectGenericODE2, VObjectGenericODE2

        from ..contact.wheelset import WheelsetContact

        if frame not in ("moving", "track"):
            raise ValueError(f"frame={frame!r}: expected 'moving' or 'track'")
        if creep_law not in CREEP_LAWS:
            raise ValueError(f"creep_law={creep_law!r}: expected one of {sorted(CREEP_LAWS)}")
        if not (math.isfinite(speed_m_s) and speed_m_s >= 0.0):
            raise ValueError(f"speed_m_s={speed_m_s!r}: expected a finite speed >= 0")
        if not (math.isfinite(mu) and mu >= 0.0):
            raise ValueError(f"mu={mu!r}: expected a finite value >= 0")
        self.nodes_exu = list(wheelset_nodes)
        if not self.nodes_exu:
            raise ValueError("no wheelset nodes given")
        n_ws = len(self.nodes_exu)
        p_ref = np.zeros((n_ws, 3))
        for k, n in enumerate(self.nodes_exu):
            ref = np.asarray(mbs.GetNodeParameter(n, "referenceCoordinates"), dtype=float)
            if ref.size != 6:
                raise ValueError(f"node {n}: expected a rigid-body node with 6 coordinates (rotation vector), "
                                 f"got {ref.size}")
            if np.any(np.abs(ref[3:]) > 1e-12):
                raise ValueError(f"node {n}: the reference rotation must be zero (wheelset axes parallel to the "
                                 "track axes); put the initial rotation into the initial coordinates")
            p_ref[k] = ref[:3]
        self.p_ref = p_ref
        self.pair = pair
        self.speed_m_s = float(speed_m_s)
        self.track = track if track is not None else RigidStraightTrack()
        self.s_start_m = float(s_start_m)
        self.moving_frame = frame == "moving"
        self.creep_law = creep_law
        self._kc = WheelsetContact(pair, n_ws, E_wheel_Pa, nu_wheel, E_rail_Pa, nu_rail, global_search=global_search)
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
        n = 6 * n_ws
        self._f = np.zeros(n)
        self._jac = np.zeros((n, n))
        self.results = np.zeros((2 * n_ws, K.N_SLOTS, N_RES))
        self._side_poses = np.zeros((2 * n_ws, 3))
        self.n_calls = 0
        kwargs = dict(name=name, nodeNumbers=self.nodes_exu, massMatrix=np.zeros((n, n)),
                      forceUserFunction=self._force_uf, visualization=VObjectGenericODE2(show=False))
        if jacobian == "numerical":
            kwargs["jacobianUserFunction"] = self._jacobian_uf
        elif jacobian is not None:
            raise ValueError(f"jacobian={jacobian!r}: expected 'numerical' or None")
        obj = ObjectGenericODE2(**kwargs)
        self.object = mbs.AddObject(obj)
        self._exu = exu

    # -- the compiled call -------------------------------------------------------------------------------------
    def _args(self, q, q_t, t):
        kc = self._kc
        return (q, q_t, self.p_ref, t, self.speed_m_s, self.moving_frame, self.s_start_m, *self._irr, kc.nodes,
                kc.meta, kc.mono, kc.curve_ids, kc.warm, kc.params, self._side_poses, kc.out, self._law, self.cp,
                _linear._T_NODES, _linear._COEF, self._tab)

    def forces(self, q, q_t, t: float) -> np.ndarray:
        """Generalized contact forces for the object coordinates (force global, torque body frame per wheelset);
        updates :attr:`results`.  Raises :class:`ContactStateError` for non-finite coordinates."""
        q = np.ascontiguousarray(q, dtype=float)
        q_t = np.ascontiguousarray(q_t, dtype=float)
        bad = contact_forces_core(*self._args(q, q_t, float(t)), self._f, self.results)
        self.n_calls += 1
        if bad >= 0:
            raise ContactStateError(f"wheel-rail contact at t = {t:.6g} s: wheelset {bad} (node "
                                    f"{self.nodes_exu[bad]}) has non-finite coordinates — the simulation diverged "
                                    "(time step too large?)")
        return self._f

    def _force_uf(self, mbs, t, itemIndex, q, q_t):
        return self.forces(q, q_t, t)

    def _jacobian_uf(self, mbs, t, itemIndex, q, q_t, fODE2, fODE2_t):
        q = np.ascontiguousarray(q, dtype=float)
        q_t = np.ascontiguousarray(q_t, dtype=float)
        contact_jacobian_core(*self._args(q, q_t, float(t)), self._f, self.results, float(fODE2), float(fODE2_t),
                              self._jac, 1e-7, 1e-7, 1e-5)
        return self._jac

    # -- state of the model ----------------------------------------------------------------------------------------
    def coordinates(self, mbs):
        """Current (q, q_t) of the wheelset nodes from the Exudyn system."""
        exu = self._exu
        q = np.concatenate([mbs.GetNodeOutput(n, exu.OutputVariableType.Coordinates) for n in self.nodes_exu])
        v = np.concatenate([mbs.GetNodeOutput(n, exu.OutputVariableType.Coordinates_t) for n in self.nodes_exu])
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
