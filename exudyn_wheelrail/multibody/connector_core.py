"""The compiled call behind the wheel–rail connector: the contact forces of all wheelsets (and on the bridge deck)
in one call, and their Jacobian by structured forward differences.

The arguments (``contact_forces_core(q, q_t, t, data, f_out, res)``, the tuples in ``data``): :mod:`.core_data`.
Three stages (:func:`wheelset_poses`, :func:`contact_geometry`, :func:`wheel_forces`); the trigonometry of a
wheelset's roll, yaw and deck roll is evaluated once per wheelset, not per contact.

Per wheel it takes the wheelset pose from the node coordinates, subtracts the rails' position (irregularity, ground
motion, deck: :mod:`~exudyn_wheelrail.structures.deck_kinematics`; the cross level rolls the rail pair on top of the
deck roll, the gauge deviation moves each rail outwards by half of it in its side frame:
:mod:`exudyn_wheelrail.conventions`), solves the contact geometry and Hertz (:mod:`exudyn_wheelrail.contact.kernel`
or the geometry table; the non-Hertzian patch on request: :mod:`exudyn_wheelrail.contact.patch_pass`), places each
contact point in 3-D (yaw lead), computes the creepages and the creep law (:mod:`exudyn_wheelrail.creep.registry`) and applies
``N n_rail + Fx x_c + Fy y_c`` at the contact point and ``Mz z_c`` to the wheelset; the equal and opposite force
goes to the rails and, on the deck, to the modal coordinates.

Curved track (``frame[FRAME_CURVED]`` set): each wheelset's coordinates are relative to the local track frame at
its own s (:mod:`~exudyn_wheelrail.rolling_stock.track_following`), which turns with
``Ω = V (φ' − κ sin θ, κ cos θ sin φ, κ cos θ cos φ)`` (:mod:`exudyn_wheelrail.track.layout`).  Seen from it the
rail material at the contact point ``r`` (from the wheelset frame's origin on the centre line at rail top) moves
with ``−V e_x − Ω × r`` and turns with ``−Ω``: the longitudinal creepage of a wheel at ``y = ±b`` gains ``∓ κ b``
(the inner rail is shorter) and the spin ``−Ω·z_c/V`` — the kinematic yaw rate of the wheelset in the curve
(Knothe & Stichel, *Rail Vehicle Dynamics*, 2017, §8.2; Shabana et al., *Railroad Vehicle Dynamics*, 2008, §6.3).
On straight track nothing of this is evaluated.
"""
from __future__ import annotations

import math

import numpy as np

from ..contact import geometry_table as GT
from ..contact import kernel as K
from ..conventions import RAIL_CENTRE_DISTANCE_M
from ..contact.creepage import creepages_core, yawed_contact_point_cs
from ..contact.layout import (CP_V_MIN, F_CONTACT_ANGLE, F_DN_DDELTA, F_FLAGS, F_NORMAL_FORCE, F_NR_Y, F_NR_Z,
                              F_PENETRATION, F_PW_Y, F_PW_Z, F_SEMI_A, F_SEMI_B, F_STATUS, RES_A, RES_B,
                              RES_CREEP_STATUS, RES_DECK_ROLL, RES_DECK_Y, RES_DECK_Z, RES_DELTA, RES_ETA, RES_FLAGS,
                              RES_FX, RES_FY, RES_F_TRACK_X, RES_F_TRACK_Y, RES_F_TRACK_Z, RES_GAMMA, RES_GROUND_VY,
                              RES_GROUND_Y, RES_MZ, RES_N, RES_ON_DECK, RES_PHI, RES_P_X, RES_P_Y, RES_P_Z, RES_STATUS,
                              RES_S_TRACK, RES_V, RES_XI, STAT_OFF_DECK, STAT_ON_DECK)
from ..contact.patch_table import patch_contacts
from ..creep.registry import creep_forces
from ..jit import compiled, is_compiled
from ..structures.deck_kinematics import (DECK_GROUND_VY, DECK_GROUND_Y, DS_RESIDUAL, SC_AT, SC_AY, SC_AZ,
                                          SC_DELTA_G, SC_DN, SC_DN_G, SC_N, SC_N_G, SC_RATIO, deck_state_under,
                                          pose_relative_to_rails, project_shapes, rail_material_velocity,
                                          rail_moment_about_deck_line, rail_pair_to_track, rails_under,
                                          series_contacts)
from ..track.layout import LAYOUT_DPHI, LAYOUT_KAPPA, LAYOUT_PHI, layout_at
from ..track.rigid import irregularity_channels_at
from .core_data import (FRAME_CURVED, FRAME_MOVING, FRAME_PITCH, FRAME_S_START, FRAME_SPEED, GEO_PATCH, GEO_TABLE,
                        MODEL_DECK, MODEL_GEOMETRY, MODEL_VEHICLE, N_FRAME, ST_DECK_STATE, ST_OUT, ST_RAIL_F,
                        ST_SIDE_POSES, ST_STATS, ST_WARM, V_E_AXLE, V_N_RAIL, V_OMEGA, V_OMEGA_RAIL, V_P_CENTRE, V_P_CONTACT,
                        V_V_CENTRE, V_V_RAIL, VEH_FRAME, VEH_LAYOUT, VEH_LAYOUT_PAR, VEH_P_REF, W_CONTACTS, W_DECK,
                        W_FRAME, W_GEOMETRY, W_INDEX, W_LAYOUT, W_RESIDUAL, W_ROT, W_SERIES, W_VEC, W_WHEELSET,
                        WS_COS_ROLL, WS_COS_TH, WS_COS_YAW, WS_HALF_GAUGE, WS_ROLL, WS_S, WS_SIN_ROLL, WS_SIN_TH,
                        WS_SIN_YAW, WS_Y_RAIL, WS_YAW, WS_Z_RAIL)
from .rotations import rotation_from_vector, rotation_vector_from_matrix

__all__ = ["contact_forces_core", "contact_jacobian_core", "compile_shares", "wheelset_poses", "wheel_forces"]


@compiled(refcount=False)
def wheelset_poses(q, q_t, t, model, state, work):
    """Stage 1: per wheelset the rotation, roll and yaw (``work``), the track distance, the rails under it
    (irregularity, ground motion, deck state) and the pose of each wheel relative to its rail (``side_poses``).
    Returns the index of the first wheelset with a non-finite state, n for non-finite modal coordinates, or -1."""
    vehicle, track, geometry, creep, deck = model
    p_ref = vehicle[VEH_P_REF]
    frame_par = vehicle[VEH_FRAME]
    irr_rows, irr_knots, irr_coefs = track
    warm, out, side_poses, stats, rail_delta, phi_ws, rail_f, deck_state = state
    deck_work, rot, wsd = work[W_DECK], work[W_ROT], work[W_WHEELSET]
    speed = frame_par[FRAME_SPEED]
    moving_frame = frame_par[FRAME_MOVING] != 0.0
    s_start = frame_par[FRAME_S_START]
    n_ws = p_ref.shape[0]
    n_w6 = 6 * n_ws
    n_m = q.shape[0] - n_w6
    q_m = q[n_w6:]
    q_m_t = q_t[n_w6:]
    deck_par, _, _, _, _, _, _ = deck           # deck_arrays: par, the shape table, residual, prediction
    y_g = deck_par[DECK_GROUND_Y]
    bad = -1
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
        R = rot[k]
        rotation_from_vector(q[o + 3], q[o + 4], q[o + 5], R)
        ex, ey, ez = R[0, 1], R[1, 1], R[2, 1]        # axle direction (body y) in the track frame
        roll = math.asin(min(max(ez, -1.0), 1.0))
        yaw = math.atan2(-ex, ey)
        px = p_ref[k, 0] + q[o]
        py = p_ref[k, 1] + q[o + 1]
        pz = p_ref[k, 2] + q[o + 2]
        s = s_start + px + (speed * t if moving_frame else 0.0)
        y_irr, _, _, z_irr, _, _, c_irr, _, _, g_irr, _, _ = irregularity_channels_at(irr_rows, irr_knots,
                                                                                     irr_coefs, s)
        wk = wsd[k]
        wk[WS_S] = s
        wk[WS_ROLL] = roll
        wk[WS_YAW] = yaw
        wk[WS_COS_ROLL] = math.cos(roll)
        wk[WS_SIN_ROLL] = math.sin(roll)
        wk[WS_COS_YAW] = math.cos(yaw)
        wk[WS_SIN_YAW] = math.sin(yaw)
        on = deck_state_under(s, speed, deck, q_m, q_m_t, rail_delta[k], phi_ws[k], deck_work, deck_state[k])
        stats[STAT_ON_DECK if on else STAT_OFF_DECK] += 1
        # the pose relative to the rail pair (irregularity, ground motion and deck; without a bridge: p - p_irr),
        # rolled by the deck and the cross level
        y_r, z_r, th = rails_under(y_irr, z_irr, y_g, deck_state[k])
        if c_irr != 0.0:
            th += math.asin(c_irr / RAIL_CENTRE_DISTANCE_M)
        h_g = 0.5 * g_irr
        wk[WS_HALF_GAUGE] = h_g
        _side_poses(k, py, pz, roll, y_r, z_r, th, wk, side_poses)
    if n_m > 0:
        for i in range(n_m):
            if not (math.isfinite(q_m[i]) and math.isfinite(q_m_t[i])):
                if bad < 0:
                    bad = n_ws
    return bad


@compiled(refcount=False)
def _side_poses(k, p_y, p_z, roll, y_r, z_r, th, wk, side_poses):
    """The rails under wheelset k at ``(y_r, z_r)`` rolled by ``th`` into ``wk`` and the pose of each wheel
    relative to its rail into ``side_poses`` (the axle centre at ``(p_y, p_z)`` with ``roll``; each side frame's
    rail moved outwards by half the gauge deviation ``wk[WS_HALF_GAUGE]``)."""
    c_th = math.cos(th)
    s_th = math.sin(th)
    wk[WS_Y_RAIL] = y_r
    wk[WS_Z_RAIL] = z_r
    wk[WS_COS_TH] = c_th
    wk[WS_SIN_TH] = s_th
    h_g = wk[WS_HALF_GAUGE]
    y_rel, z_rel, roll_rel = pose_relative_to_rails(p_y, p_z, roll, y_r, z_r, th, c_th, s_th)
    side_poses[2 * k, 0] = y_rel - h_g
    side_poses[2 * k, 1] = z_rel
    side_poses[2 * k, 2] = roll_rel
    side_poses[2 * k + 1, 0] = -y_rel - h_g
    side_poses[2 * k + 1, 1] = z_rel
    side_poses[2 * k + 1, 2] = -roll_rel


@compiled(refcount=False)
def _frame_rate(pieces, par, s, speed, pitch, lay):
    """Angular velocity (track-frame components) of the local track frame at s moving with ``speed`` (module
    docstring, curved track); ``pieces = None`` (straight track): zero, and the layout is not compiled."""
    if pieces is None:
        return 0.0, 0.0, 0.0
    layout_at(pieces, par, s, lay)
    k = lay[LAYOUT_KAPPA]
    phi = lay[LAYOUT_PHI]
    c_th = math.cos(pitch)
    return (speed * (lay[LAYOUT_DPHI] - k * math.sin(pitch)), speed * k * c_th * math.sin(phi),
            speed * k * c_th * math.cos(phi))


@compiled(refcount=False)
def wheel_forces(q, q_t, model, state, work, f_out, res):
    """Stage 3, after :func:`wheelset_poses` and the geometry (``out``): per contact the point in 3-D (yaw lead),
    the creepages, the creep law and the force on the wheelset; the results ``res``, the forces ``f_out``, the
    force on the rails and its projection on the deck.  ``f_out``, ``rail_f`` and ``res`` must be zero on entry."""
    vehicle, track, geometry, creep, deck = model
    p_ref = vehicle[VEH_P_REF]
    frame_par = vehicle[VEH_FRAME]
    law, cp, t_nodes, coef, tab = creep
    warm, out, side_poses, stats, rail_delta, phi_ws, rail_f, deck_state = state
    rot, wsd, vec, frame = work[W_ROT], work[W_WHEELSET], work[W_VEC], work[W_FRAME]
    n_ws = p_ref.shape[0]
    n_w6 = 6 * n_ws
    f_m = f_out[n_w6:]
    curved = frame_par[FRAME_CURVED] != 0.0
    om_x = 0.0               # the local track frame's angular velocity (curved layout)
    om_y = 0.0
    om_z = 0.0
    deck_par, _, _, _, _, _, _ = deck           # deck_arrays: par, the shape table, residual, prediction
    y_g = deck_par[DECK_GROUND_Y]
    v_g = deck_par[DECK_GROUND_VY]
    v_min = cp[CP_V_MIN]
    pc = vec[V_P_CONTACT]
    nr = vec[V_N_RAIL]
    e_axle = vec[V_E_AXLE]
    p_centre = vec[V_P_CENTRE]
    v_centre = vec[V_V_CENTRE]
    omega = vec[V_OMEGA]
    v_rail = vec[V_V_RAIL]
    omega_rail = vec[V_OMEGA_RAIL]
    # the rail material moves with -V in a moving model frame; the rails' angular velocity is the deck's roll rate
    v_rail[0] = -frame_par[FRAME_SPEED] if frame_par[FRAME_MOVING] != 0.0 else 0.0
    v_rail[1] = 0.0
    v_rail[2] = 0.0
    omega_rail[1] = 0.0
    omega_rail[2] = 0.0
    for k in range(n_ws):
        o = 6 * k
        R = rot[k]
        wk = wsd[k]
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
        # the rails under this wheelset: centre line y_r, z_r (irregularity, ground, deck), roll (deck roll th and
        # cross level: c_th, s_th), half the gauge deviation; the deck state (relative to the supports) and its
        # roll rate, the rails' angular velocity
        y_r = wk[WS_Y_RAIL]
        z_r = wk[WS_Z_RAIL]
        ds = deck_state[k]
        th = ds[2]
        c_th = wk[WS_COS_TH]
        s_th = wk[WS_SIN_TH]
        h_g = wk[WS_HALF_GAUGE]
        omega_rail[0] = ds[5]
        if curved:
            om_x, om_y, om_z = _frame_rate(vehicle[VEH_LAYOUT], vehicle[VEH_LAYOUT_PAR], wk[WS_S],
                                           frame_par[FRAME_SPEED], frame_par[FRAME_PITCH], work[W_LAYOUT])
            omega_rail[0] = ds[5] - om_x
            omega_rail[1] = -om_y
            omega_rail[2] = -om_z
        rfy = 0.0
        rfz = 0.0
        rmx = 0.0
        for side in range(2):
            w = 2 * k + side
            mirror = 1.0 if side == 0 else -1.0
            for reg in range(out.shape[1]):
                ow = out[w, reg]
                r = res[w, reg]
                r[RES_STATUS] = ow[F_STATUS]
                r[RES_FLAGS] = ow[F_FLAGS]
                r[RES_S_TRACK] = wk[WS_S]
                r[RES_DECK_Y] = ds[0]
                r[RES_DECK_Z] = ds[1]
                r[RES_DECK_ROLL] = th
                r[RES_ON_DECK] = ds[6]
                r[RES_GROUND_Y] = y_g
                r[RES_GROUND_VY] = v_g
                if ow[F_STATUS] <= 0:
                    continue
                N = ow[F_NORMAL_FORCE]
                # contact point and rail normal from the side frame (its rail moved outwards by h_g) to the rail
                # pair's frame (mirrored for the left side) and on to the track frame
                y_t, z_t, ny, nz = rail_pair_to_track(mirror * (ow[F_PW_Y] + h_g), ow[F_PW_Z], mirror * ow[F_NR_Y],
                                                      ow[F_NR_Z], y_r, z_r, c_th, s_th)
                x_c, y_c, z_c, _, ok = yawed_contact_point_cs(y_t, z_t, ny, nz, p_centre[0], p_centre[1],
                                                               p_centre[2], wk[WS_COS_ROLL], wk[WS_SIN_ROLL],
                                                               wk[WS_COS_YAW], wk[WS_SIN_YAW])
                if not ok:
                    x_c, y_c, z_c = p_centre[0], y_t, z_t
                pc[0] = x_c
                pc[1] = y_c
                pc[2] = z_c
                nr[0] = 0.0
                nr[1] = ny
                nr[2] = nz
                rail_material_velocity(y_c, z_c, y_g, v_g, ds, v_rail)
                if curved:
                    # minus Ω × r, r from the wheelset frame's origin (axle's nominal x, centre line, rail top)
                    rx = x_c - p_ref[k, 0]
                    v_rail[0] = -frame_par[FRAME_SPEED] - (om_y * z_c - om_z * y_c)
                    v_rail[1] -= om_z * rx - om_x * z_c
                    v_rail[2] -= om_x * y_c - om_y * rx
                xi, eta, phi, V, cstat = creepages_core(pc, nr, e_axle, p_centre, v_centre, omega, v_rail,
                                                         omega_rail, v_min, frame)
                Fx = 0.0
                Fy = 0.0
                Mz = 0.0
                if math.isfinite(xi) and (cstat & 12) == 0:     # no degenerate frame / invalid input
                    Fx, Fy, Mz, flag = creep_forces(law, ow[F_SEMI_A], ow[F_SEMI_B], xi, eta, phi, N, cp, t_nodes,
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
                rmx -= rail_moment_about_deck_line(y_c, z_c, Fgy, Fgz, Mz * frame[2, 0], y_g, ds)
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
                r[RES_GAMMA] = ow[F_CONTACT_ANGLE]
                r[RES_XI] = xi
                r[RES_ETA] = eta
                r[RES_PHI] = phi
                r[RES_A] = ow[F_SEMI_A]
                r[RES_B] = ow[F_SEMI_B]
                r[RES_DELTA] = ow[F_PENETRATION]
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
        if ds[6] > 0.5:
            # generalized modal forces Φ(s)^T (Fy, Fz, Mx) of the force on the rails
            project_shapes(phi_ws[k], rfy, rfz, rmx, f_m)


@compiled
def contact_forces_core(q, q_t, t, data, f_out, res):
    """All wheelsets in one call (module docstring: the arguments).  Fills ``f_out`` and ``res`` and the state;
    returns the index of the first wheelset with a non-finite state, n for non-finite modal coordinates, or -1."""
    model = data.model
    state = data.state
    work = data.work
    bad = wheelset_poses(q, q_t, t, model, state, work)
    rail_f = state[ST_RAIL_F]
    for i in range(f_out.shape[0]):
        f_out[i] = 0.0
    for k in range(rail_f.shape[0]):
        rail_f[k, 0] = 0.0
        rail_f[k, 1] = 0.0
        rail_f[k, 2] = 0.0
    res[:, :, :] = 0.0
    if bad >= 0:
        return bad
    _, _, _, _, _, residual, _ = model[MODEL_DECK]     # the deck arrays' residual flexibility table (or None)
    contact_geometry(q, model, state, work, model[MODEL_GEOMETRY][GEO_TABLE], residual,
                     model[MODEL_GEOMETRY][GEO_PATCH])
    wheel_forces(q, q_t, model, state, work, f_out, res)
    return -1


@compiled(refcount=False)
def contact_geometry(q, model, state, work, table, residual, patch):
    """Stage 2: the contact geometry and Hertz of every wheel (the kernel's output ``state[ST_OUT]``), with
    ``table`` the geometry table's arrays (``model[MODEL_GEOMETRY][GEO_TABLE]``;
    :func:`~exudyn_wheelrail.contact.geometry_table.evaluate_wheels_tabulated`) and ``residual`` the structure's
    residual flexibility table (the deck arrays' ``node_residual``) in series with the contacts, ``patch`` the
    non-Hertzian patch's (``GEO_PATCH``).  Any may be ``None``: numba then compiles none of its code.  numba drops a
    branch by the type of a ``None`` argument only where the branch is the ``if`` or the ``else`` of that test: code
    after an early ``return`` is compiled, hence the if/else here.  (The geometry itself, :func:`_wheel_geometry`,
    is inlined, not called: every layer of compiled functions generates the machine code of all it calls again.)"""
    if residual is None:                 # an if/else on the argument's type: the other branch is not compiled
        _wheel_geometry(model, state, work, table, patch)
    else:
        _predict_residual(q, model, state, work)
        for attempt in range(2):
            _wheel_geometry(model, state, work, table, patch)
            # a solve that moves its rails further than the geometry's linearization is trusted: move them there
            # and find the geometry again (once)
            if attempt == 1 or not series_compliance(state, work, False):
                break
            _move_rails(q, model, state, work)
        series_compliance(state, work, True)


@compiled(inline="always")
def _wheel_geometry(model, state, work, table, patch):
    """The contact geometry and Hertz of every wheel at the poses of ``state``: the online search, or the geometry
    table ``table`` (not None); then the non-Hertzian patch (``patch`` not None)."""
    wheel_geometry(model, state[ST_SIDE_POSES], state[ST_WARM], state[ST_OUT], state[ST_STATS], table,
                   work[W_GEOMETRY], patch)


@compiled(inline="always")
def wheel_geometry(model, poses, warm, out, stats, table, scratch, patch):
    """The geometry stage on its own arrays: the contact geometry and Hertz of every wheel at ``poses`` (the
    side poses) from the warm start ``warm`` into ``out`` (the kernel's output), counting into ``stats`` — the
    online search, or the geometry table ``table`` (``model[MODEL_GEOMETRY][GEO_TABLE]``, an argument: numba
    compiles only the branch of its type), ``scratch`` the stage's work array (``work[W_GEOMETRY]``), ``patch`` the
    non-Hertzian patch's or ``None`` (:mod:`~exudyn_wheelrail.contact.patch_pass`).  What the core calls for the
    state's arrays, and what a benchmark calls for recorded states."""
    nodes, meta, mono, curve_ids, params, _, scan, _ = model[MODEL_GEOMETRY]
    if table is None:
        K.solve_wheels(nodes, meta, mono, curve_ids, poses, warm, params, out, scan, scratch)
        GT.count_fallback(out, stats)
    else:
        table_par, table_cz_ref, table_data = table
        GT.tabulated_wheels(table_par, table_cz_ref, table_data, nodes, meta, mono, curve_ids, poses, warm, params,
                            out, stats, scan, scratch)
    if patch is not None:
        patch_contacts(nodes, meta, curve_ids, poses, params, out, patch)


#: the rails' residual displacement beyond which the contact geometry is found again on the moved rails instead of
#: being linearized (the gap changes by a·Δu exactly for a rigid shift of the rail; what a linearization misses is
#: a contact region appearing or vanishing, which takes a shift comparable to the Hertz approach, ~50 µm) [m]
SERIES_REGEOMETRY_M = 2.0e-5


@compiled(refcount=False)
def _shift_rails(k, du_y, du_z, du_th, q, p_ref, state, work):
    """Move the rails under wheelset k by ``(du_y, du_z, du_th)`` (deck state and the wheels' poses)."""
    ds = state[ST_DECK_STATE][k]
    wk = work[W_WHEELSET][k]
    ds[0] += du_y
    ds[1] += du_z
    ds[2] += du_th
    _side_poses(k, p_ref[k, 1] + q[6 * k + 1], p_ref[k, 2] + q[6 * k + 2], wk[WS_ROLL], wk[WS_Y_RAIL] + du_y,
                wk[WS_Z_RAIL] + du_z, math.atan2(wk[WS_SIN_TH], wk[WS_COS_TH]) + du_th, wk, state[ST_SIDE_POSES])


@compiled(refcount=False)
def _predict_residual(q, model, state, work):
    """Before the geometry, with a residual flexibility: the rails of every wheelset on the structure moved by the
    residual displacement ``G_res F`` of its predicted rail load (deck arrays' ``rail_load_prediction``; zero: not
    moved), kept in ``work[W_RESIDUAL][:, :3]``."""
    deck = model[MODEL_DECK]
    _, _, _, _, _, _, pred = deck      # the deck arrays' rail_load_prediction
    deck_state = state[ST_DECK_STATE]
    store = work[W_RESIDUAL]
    p_ref = model[MODEL_VEHICLE][VEH_P_REF]
    for k in range(deck_state.shape[0]):
        ds = deck_state[k]
        for i in range(6):
            store[k, i] = 0.0
        if ds[6] < 0.5 or k >= pred.shape[0]:
            continue
        f0 = pred[k, 0]
        f1 = pred[k, 1]
        f2 = pred[k, 2]
        if f0 == 0.0 and f1 == 0.0 and f2 == 0.0:
            continue
        g = ds[DS_RESIDUAL:DS_RESIDUAL + 6]
        u_y = g[0] * f0 + g[3] * f1 + g[4] * f2         # the rails' displacement under the force on them: G F
        u_z = g[3] * f0 + g[1] * f1 + g[5] * f2
        u_th = g[4] * f0 + g[5] * f1 + g[2] * f2
        store[k, 0] = u_y
        store[k, 1] = u_z
        store[k, 2] = u_th
        _shift_rails(k, u_y, u_z, u_th, q, p_ref, state, work)


@compiled(refcount=False)
def _move_rails(q, model, state, work):
    """Move the rails of every wheelset from where the geometry was found (``work[W_RESIDUAL][:, :3]``) to the
    solve's residual displacement (``work[W_RESIDUAL][:, 3:]``)."""
    store = work[W_RESIDUAL]
    p_ref = model[MODEL_VEHICLE][VEH_P_REF]
    for k in range(store.shape[0]):
        du_y = store[k, 3] - store[k, 0]
        du_z = store[k, 4] - store[k, 1]
        du_th = store[k, 5] - store[k, 2]
        if du_y != 0.0 or du_z != 0.0 or du_th != 0.0:
            _shift_rails(k, du_y, du_z, du_th, q, p_ref, state, work)
        store[k, 0] = store[k, 3]
        store[k, 1] = store[k, 4]
        store[k, 2] = store[k, 5]


@compiled(refcount=False)
def series_compliance(state, work, final):
    """Stage 2b, after the geometry, with a structure's residual flexibility
    (:mod:`~exudyn_wheelrail.structures.deck_kinematics`): the contacts of every wheelset on the structure in series
    with the rails' residual flexibility there (:func:`~exudyn_wheelrail.structures.deck_kinematics.series_contacts`),
    from the penetrations found on the rails at their residual displacement ``work[W_RESIDUAL][:, :3]`` (the prediction of
    :func:`_predict_residual`, or zero); the solution u into ``work[W_RESIDUAL][:, 3:]``.  Not ``final``: returns True if a
    wheelset's u lies more than :data:`SERIES_REGEOMETRY_M` from where its geometry was found (the caller then
    moves the rails there, :func:`_move_rails`, and finds the geometry again: on the undeflected rail head a
    penetration deeper by the pads' compression shows a second, spurious tread maximum) and changes nothing else.
    ``final``: moves the deck state to u and replaces the kernel's normal force, dN/dδ, semi-axes and penetration
    (now the Hertz approach) by the series values (semi-axes and Hertz's dN/dδ scale with the square root of the
    approach)."""
    out = state[ST_OUT]
    deck_state = state[ST_DECK_STATE]
    wsd = work[W_WHEELSET]
    store = work[W_RESIDUAL]
    contacts = work[W_CONTACTS]
    scratch = work[W_SERIES]
    index = work[W_INDEX]
    n_reg = out.shape[1]
    again = False
    for k in range(deck_state.shape[0]):
        ds = deck_state[k]
        u0 = store[k, 0:3]
        if ds[6] < 0.5:
            continue
        h_g = wsd[k, WS_HALF_GAUGE]
        n = 0
        for side in range(2):
            w = 2 * k + side
            mirror = 1.0 if side == 0 else -1.0
            for reg in range(n_reg):
                ow = out[w, reg]
                if ow[F_STATUS] <= 0 or not ow[F_NORMAL_FORCE] > 0.0 or not ow[F_PENETRATION] > 0.0:
                    continue
                # contact point and rail normal in the rail pair's frame (as in wheel_forces)
                p_y = mirror * (ow[F_PW_Y] + h_g)
                p_z = ow[F_PW_Z]
                c = contacts[n]
                c[SC_AY] = mirror * ow[F_NR_Y]
                c[SC_AZ] = ow[F_NR_Z]
                c[SC_AT] = c[SC_AZ] * p_y - c[SC_AY] * p_z
                c[SC_N_G] = ow[F_NORMAL_FORCE]
                c[SC_DELTA_G] = ow[F_PENETRATION]
                c[SC_DN_G] = ow[F_DN_DDELTA]
                index[n, 0] = w
                index[n, 1] = reg
                n += 1
        if n > 0:
            series_contacts(ds[DS_RESIDUAL:DS_RESIDUAL + 6], contacts, n, u0, scratch)
            for i in range(3):
                store[k, 3 + i] = scratch[0, i]
        else:                        # lifted: the rails back at rest
            for i in range(3):
                store[k, 3 + i] = 0.0
        if not final:
            shift = max(abs(store[k, 3] - u0[0]), abs(store[k, 4] - u0[1]),
                        0.5 * RAIL_CENTRE_DISTANCE_M * abs(store[k, 5] - u0[2]))
            again = again or shift > SERIES_REGEOMETRY_M
            continue
        for i in range(3):           # the deck state: the rails at their final residual displacement
            ds[i] += store[k, 3 + i] - u0[i]
        for r in range(n):
            ow = out[index[r, 0], index[r, 1]]
            c = contacts[r]
            root = math.sqrt(c[SC_RATIO])
            ow[F_NORMAL_FORCE] = c[SC_N]
            ow[F_DN_DDELTA] = c[SC_DN]
            ow[F_SEMI_A] *= root
            ow[F_SEMI_B] *= root
            ow[F_PENETRATION] *= c[SC_RATIO]
    return again


def compile_shares(q, q_t, t, model, state, work, f_out, res):
    """:func:`contact_forces_core`'s callees as the two shares of :func:`~exudyn_wheelrail.jit.compile_ahead`, for
    the types of the call ``contact_forces_core(q, q_t, t, contact_data(model, state, work), f_out, res)``, about
    even: this process compiles the contact geometry (the search kernel, the largest part, which a static
    equilibrium found while the model is assembled needs next) and the other the poses and the forces
    (creepages, creep law, deck) — or, with the search kernel compiled already, this process the poses and the
    geometry and the other the forces.  The arguments are those the call hands each callee."""
    _, _, _, _, _, residual, _ = model[MODEL_DECK]
    nodes, meta, mono, curve_ids, params, table, scan, patch = model[MODEL_GEOMETRY]
    search = (nodes, meta, mono, curve_ids, state[ST_SIDE_POSES], state[ST_WARM], params, state[ST_OUT], scan)
    poses = (wheelset_poses, (q, q_t, t, model, state, work))
    forces = (wheel_forces, (q, q_t, model, state, work, f_out, res))
    geometry = (contact_geometry, (q, model, state, work, table, residual, patch))
    if is_compiled(K.evaluate_wheels, search):
        return [poses, geometry], [forces]
    return [geometry], [poses, forces]


@compiled
def contact_jacobian_core(q, q_t, t, data, f0, res, f_odeq, f_odev, jac, h_pos, h_rot, h_vel):
    """``jac = -(∂f/∂q f_odeq + ∂f/∂q_t f_odev)`` by forward differences of :func:`contact_forces_core` (same
    ``data``; ``f0`` receives the unperturbed forces), steps ``h_pos`` [m], ``h_rot`` [rad],
    ``h_vel`` [m/s, rad/s]; rotations perturbed by body-frame increments (R exp(h e_i)), matching the Lie-group
    update.  Structured: a wheelset's contact forces depend on its own coordinates (and the deck under it) only,
    so the same coordinate of all wheelsets is perturbed in one call — 12 calls whatever the number of wheelsets;
    the modal rows of those columns are ``Φ(s_k)^T`` times the change of wheelset k's rail force (and of ``Φ(s_k)``
    when s moves).  Bridge columns (chain rule): the contact depends on the modal coordinates only through the deck
    state under each wheelset, ``u_k = Φ(s_k) q_m`` and ``u̇_k = Φ(s_k) q̇_m`` (rows y, z, θ), so the three offsets
    and three rates of every wheelset on the deck are perturbed together (``rail_delta``: 6 calls for any number of
    modes and wheelsets): ``∂f_k/∂q_m = (∂f_k/∂u_k) Φ(s_k)``, ``∂Q/∂q_m = Σ_k Φ(s_k)^T (∂F_rail,k/∂u_k) Φ(s_k)``.
    The warm-start state is restored after every perturbed call."""
    warm, _, _, _, rail_delta, phi_ws, rail_f, deck_state = data.state
    n = q.shape[0]
    n_ws = data.model[MODEL_VEHICLE][VEH_P_REF].shape[0]
    n_w6 = 6 * n_ws
    n_m = n - n_w6
    warm0 = warm.copy()
    contact_forces_core(q, q_t, t, data, f0, res)
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
                rotation_vector_from_matrix(Rn, qp, o + 3)
        contact_forces_core(qp, q_t, t, data, f1, res)
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
        contact_forces_core(q, vp, t, data, f1, res)
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
            contact_forces_core(q, q_t, t, data, f1, res)
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
    contact_forces_core(q, q_t, t, data, f0, res)
    warm[:] = warm0
