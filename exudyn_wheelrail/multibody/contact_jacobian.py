r"""The contact's stiffness and damping for implicit solvers, semi-analytic: one evaluation of the compiled contact
call (:func:`~.connector_core.contact_forces_core`) and the derivatives assembled from its results, instead of the
twelve perturbed calls of the forward-difference Jacobian (:func:`~.connector_core.contact_jacobian_core`).

What Exudyn asks for
--------------------
The Jacobian user function of the connector returns ``-(∂f/∂q a + ∂f/∂q̇ b)`` (``a``, ``b`` Exudyn's factors) for
the generalized forces ``f``: per wheelset the force in the track frame and the torque in the body frame, with
respect to the displacement (track frame), a body-frame rotation increment (``R' = R exp(θ_b)``, the Lie-group
update), the velocity (track frame) and the body-frame angular velocity; then the bridge's modal coordinates.
Newton's iteration matrix is ``M + β h² K + γ h C``: for a wheelset of 1.8 t at h = 1 ms the Hertz springs of two
wheels (``2 dN/dδ ≈ 2e9 N/m``) are 28 % of ``M/(β h²) = 7e9 N/m``, the creep damping on the spin (``f₁₁ r²/V``
against the spin inertia) tens of per cent: these two decide how fast Newton converges.

What is differentiated (per contact, track frame; ``r`` the contact point from the axle centre, ``n`` the outward
rail normal, ``(x_c, y_c, z_c)`` the contact frame, ``V`` the rolling speed guarded by ``v_min``)
----------------------------------------------------------------------------------------------------------------
* **Hertz along the normal:** the penetration of a rigid wheel moved by ``du`` and turned by ``dθ`` (track frame)
  changes by ``dδ = -n·du - (r × n)·dθ`` — the contact point is a stationary point of the penetration, so its own
  motion does not enter the first derivative (envelope theorem) — and the normal force by ``dN = N'(δ) dδ`` with
  the kernel's ``dN/dδ`` (``F_DN_DDELTA``, Hertz's ``1.5 N/δ`` at the point's curvatures).  Two blended maxima of
  one overlap zone (kernel ``FLAG_BLENDED``, ``N₁ = (1 - b) H₁(δ₁)``, ``N₂ = b H₂(δ₂)``): the weight ``b``'s change
  with both depths couples them (it outweighs Hertz's own stiffness there).  The rails' deck displacement
  ``(y, z, θ)`` moves the rail surface by ``(dy, dz)`` and ``dθ e_x × (p - rail line)``: ``dδ = n·`` that.
* **Creep damping:** the creepages are linear in the velocities, ``ξ = Δv·x_c/V``, ``η = Δv·y_c/V``,
  ``φ = (ω - ω_rail)·z_c/V`` with ``Δv = v + ω × r - v_rail``: ``∂ξ/∂v = x_c/V``, ``∂ξ/∂ω = (r × x_c)/V``,
  ``∂η/∂v = y_c/V``, ``∂η/∂ω = (r × y_c)/V``, ``∂φ/∂ω = z_c/V`` and minus the same for the rails' deck velocity
  and roll rate (exact with V held fixed: V moves ξ by ``-ξ dV/V``, relative ``|ξ|``).  The creep forces'
  derivatives with respect to the creepages, ``D = ∂(F_x, F_y, M_z)/∂(ξ, η, φ)``, and to the load (with the
  semi-axes ``∝ N^(1/3)``) are the **creep law's own tangent**, by forward differences of the law the contact call
  used (:func:`creep_tangent`: four law evaluations per contact, no contact call): Kalker's linear theory at small
  creepage, the saturating law's slope elsewhere (a secant or the linear tangent instead leaves 7 % of the spin
  block and costs a third iteration in one step of six).  Turning the wheelset turns its angular velocity
  ``ω = R ω_b`` (``∂ω/∂θ_b = -R [ω_b]×``): the yaw term of the lateral creepage, through the same tangent.
* **Body-frame torque:** ``τ_b = Rᵀ τ`` turns with the body, ``∂τ_b/∂θ_b = [τ_b]× + Rᵀ (∂τ/∂θ) R`` (exact).
* **Bridge:** the forces on the rails ``(F_y, F_z, M_x)`` about the deck's rail-top line (which moves with the
  deck: ``∂M_x/∂y = F_z``, ``∂M_x/∂z = -F_y`` of the wheel force) and their projection ``Φ(s)ᵀ`` on the modes.

Not differentiated (deliberately; they change the iteration count, never the converged result): the turn of the
normal and the migration of the contact point across the profiles (stiffness ``N κ_w κ_r/(κ_w + κ_r)``, tread
contacts ~1e5 N/m against ``dN/dδ ~ 1e9 N/m``), the change of the Hertz constant with the point's curvatures
(a few per cent of ``dN/dδ`` on S1002/UIC60), the creepages' dependence on the pose (conicity, yaw: ``f_ij`` times
``O(1)``, ~5e6 N/m), the rails' slope along x (irregularity, deviation, ``Φ'(s)``).  Where the normal turns fast —
a point of the concave search, a clamped (conformal) Hertz curvature, or ``δ κ_eff`` above
:data:`CONFORMAL_LIMIT` (the flange root against the gauge corner: the contact angle turns by ~1e4 rad/m, its
stiffness ``N dγ/dy`` is of the order of Hertz's) — the whole Jacobian is the structured forward differences
instead (:func:`needs_differences`).  ``tests/test_implicit_jacobian.py`` checks the exact parts against central
differences, the approximate ones against what they promise and Newton's contraction with this Jacobian.
"""
from __future__ import annotations

import numpy as np

from ..contact.creepage import CREEP_DEGENERATE_FRAME, CREEP_INVALID_INPUT, CREEP_REVERSED, contact_frame_core
from ..contact.kernel import FLAG_BLENDED, FLAG_HERTZ_CLAMPED, FLAG_PATCH
from ..contact.kernel import STATUS_CONVEX as K_STATUS_CONVEX
from ..contact.layout import (CP_V_MIN, F_DN_DDELTA, F_FLAGS, F_KR_LAT, F_KW_LAT, F_NR_Y, F_NR_Z, F_PENETRATION,
                              P_BLEND_DEPTH, RES_A, RES_B, RES_CREEP_STATUS, RES_ETA, RES_FX, RES_FY, RES_MZ, RES_N,
                              RES_P_X, RES_P_Y, RES_P_Z, RES_PHI, RES_STATUS, RES_V, RES_XI, SLOT_TREAD, SLOT_TREAD_2)
from ..creep.registry import CREEP_LAWS, creep_forces
from ..jit import compiled
from ..structures.deck_kinematics import DECK_GROUND_Y, rail_pair_to_track
from .core_data import (GEO_PARAMS, MODEL_CREEP, MODEL_DECK, MODEL_GEOMETRY, MODEL_VEHICLE, ST_DECK_STATE, ST_OUT,
                        ST_PHI_WS, V_E_AXLE, V_N_RAIL, VEH_P_REF, W_FRAME, W_ROT, W_VEC, W_WHEELSET, WS_COS_TH,
                        WS_SIN_TH, WS_Y_RAIL, WS_Z_RAIL)

__all__ = ["JACOBIAN_METHODS", "CONFORMAL_LIMIT", "semi_analytic_jacobian", "contact_tangent_blocks", "creep_tangent",
           "needs_differences"]

#: how the connector's Jacobian user function differentiates the contact: this module's semi-analytic
#: derivatives (the default) or the structured forward differences of the compiled call
JACOBIAN_METHODS = ("semi_analytic", "forward_difference")

_NO_LAW = CREEP_LAWS["none"]
#: creepage status bits under which the contact has no creep forces (wheel_forces sets them to zero)
_NO_CREEP = CREEP_DEGENERATE_FRAME | CREEP_INVALID_INPUT


#: forward-difference steps of the creep law in creepage space: ξ, η [-] and φ [1/m]; the load N relative
H_CREEPAGE = 1e-7
H_SPIN_1_M = 1e-5
H_LOAD_REL = 1e-6


@compiled
def creep_tangent(law, a, b, xi, eta, phi, N, Fx, Fy, Mz, cp, t_nodes, coef, tab, D, dF_dN):
    """The creep law's tangent at the creepages: ``D = ∂(F_x, F_y, M_z)/∂(ξ, η, φ)`` (3, 3) and ``dF_dN`` (3,) =
    ``∂(F_x, F_y, M_z)/∂N`` with the semi-axes following Hertz (``a, b ∝ N^(1/3)``), by forward differences of
    the law itself (:func:`~exudyn_wheelrail.creep.registry.creep_forces`, the one the contact call used; steps
    :data:`H_CREEPAGE`, :data:`H_SPIN_1_M`, :data:`H_LOAD_REL`) from its forces ``Fx``, ``Fy``, ``Mz`` at the point:
    four law evaluations, no contact call.  At small creepage this is Kalker's linear theory (``-G c² C₁₁`` …) as
    far as the law reproduces it."""
    for j in range(3):
        h = H_SPIN_1_M if j == 2 else H_CREEPAGE
        x1 = xi + h if j == 0 else xi
        e1 = eta + h if j == 1 else eta
        p1 = phi + h if j == 2 else phi
        fx, fy, mz, _ = creep_forces(law, a, b, x1, e1, p1, N, cp, t_nodes, coef, tab)
        D[0, j] = (fx - Fx) / h
        D[1, j] = (fy - Fy) / h
        D[2, j] = (mz - Mz) / h
    dn = H_LOAD_REL * N
    g = (1.0 + H_LOAD_REL) ** (1.0 / 3.0)
    fx, fy, mz, _ = creep_forces(law, a * g, b * g, xi, eta, phi, N + dn, cp, t_nodes, coef, tab)
    dF_dN[0] = (fx - Fx) / dn
    dF_dN[1] = (fy - Fy) / dn
    dF_dN[2] = (mz - Mz) / dn


# ---- the blocks of one wheelset: rows and columns of contact_tangent_blocks' Kq[k], Cv[k] (9, 9) ------------------
#: rows: force on the wheelset (track frame) 0-2, torque about the axle centre (track frame) 3-5, force on the
#: rails projected on the deck (F_y, F_z, M_x about the deck's rail-top centre line) 6-8
ROW_F = 0
ROW_TORQUE = 3
ROW_RAIL = 6
#: columns: wheelset displacement / velocity 0-2, rotation / angular velocity (track frame) 3-5, deck displacement
#: (y, z, θ) / its rate under the wheelset 6-8 (the rows of Φ(s))
COL_U = 0
COL_THETA = 3
COL_DECK = 6
N_BLOCK = 9


@compiled
def _cross(ax, ay, az, bx, by, bz):
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@compiled
def contact_tangent_blocks(q, q_t, data, res, Kq, Cv):
    """Per wheelset the derivatives of its contact forces at the state of the **last** contact call (its results
    ``res`` and the call's work arrays): ``Kq[k]`` (9, 9) with respect to the positions and ``Cv[k]`` (9, 9) with
    respect to the velocities, rows and columns :data:`ROW_F` … :data:`COL_DECK` (all in the track frame; the
    deck columns are the deck state under the wheelset, zero effect off the deck).  The module docstring says what
    is differentiated."""
    model = data.model
    state = data.state
    work = data.work
    p_ref = model[MODEL_VEHICLE][VEH_P_REF]
    law, cp, t_nodes, coef, tab = model[MODEL_CREEP]
    deck_par, _, _, _, _, _, _ = model[MODEL_DECK]    # deck_arrays: par, the shape table, residual, prediction
    y_g = deck_par[DECK_GROUND_Y]
    out = state[ST_OUT]
    deck_state = state[ST_DECK_STATE]
    rot = work[W_ROT]
    wsd = work[W_WHEELSET]
    vec = work[W_VEC]
    fr = work[W_FRAME]
    n_ws = p_ref.shape[0]
    v_min = cp[CP_V_MIN]
    params = model[MODEL_GEOMETRY][GEO_PARAMS]
    n_slots = res.shape[1]
    D = np.empty((3, 3))
    dFN = np.empty(3)
    active = np.zeros(n_slots, dtype=np.bool_)
    dNm = np.zeros((n_slots, n_slots))          # per wheel ∂N_slot/∂δ_slot'
    per_load = np.zeros((n_slots, N_BLOCK))     # per slot: the rows' change per unit normal load
    grad = np.zeros((n_slots, N_BLOCK))         # per slot: dδ/d(position columns)
    S = np.empty((3, N_BLOCK))    # ∂(ξ, η, φ)/∂(velocity columns)
    nr = vec[V_N_RAIL]
    e_axle = vec[V_E_AXLE]
    for k in range(n_ws):
        o = 6 * k
        R = rot[k]
        K = Kq[k]
        C = Cv[k]
        for i in range(N_BLOCK):
            for j in range(N_BLOCK):
                K[i, j] = 0.0
                C[i, j] = 0.0
        pcx = p_ref[k, 0] + q[o]
        pcy = p_ref[k, 1] + q[o + 1]
        pcz = p_ref[k, 2] + q[o + 2]
        for i in range(3):
            e_axle[i] = R[i, 1]
        c_th = wsd[k, WS_COS_TH]
        s_th = wsd[k, WS_SIN_TH]
        y_r = wsd[k, WS_Y_RAIL]          # the rails turn about their rail-top centre line (geometry) ...
        z_r = wsd[k, WS_Z_RAIL]
        ds = deck_state[k]
        y_d = y_g + ds[0]                # ... the deck's line carries their velocity and the moment
        z_d = ds[1]
        for side in range(2):
            w = 2 * k + side
            mirror = 1.0 if side == 0 else -1.0
            n_slots = res.shape[1]
            for reg in range(n_slots):
                active[reg] = False
                dNm[reg, 0] = 0.0
                dNm[reg, 1] = 0.0
                dNm[reg, 2] = 0.0
            for reg in range(n_slots):
                r_ = res[w, reg]
                N = r_[RES_N]
                if r_[RES_STATUS] <= 0 or not N > 0.0:
                    continue
                active[reg] = True
                ow = out[w, reg]
                dNm[reg, reg] = ow[F_DN_DDELTA]
                _, _, ny, nz = rail_pair_to_track(0.0, 0.0, mirror * ow[F_NR_Y], ow[F_NR_Z], 0.0, 0.0, c_th, s_th)
                nr[0] = 0.0
                nr[1] = ny
                nr[2] = nz
                yc = r_[RES_P_Y]
                zc = r_[RES_P_Z]
                rx = r_[RES_P_X] - pcx
                ry = yc - pcy
                rz = zc - pcz
                Fx = r_[RES_FX]
                Fy = r_[RES_FY]
                Mz = r_[RES_MZ]
                cstat = int(r_[RES_CREEP_STATUS])
                creep = law != _NO_LAW and (cstat & _NO_CREEP) == 0
                if creep:
                    if contact_frame_core(nr, e_axle, 1.0, fr) != 0:
                        creep = False
                    else:
                        if cstat & CREEP_REVERSED:
                            for i in range(3):
                                fr[0, i] = -fr[0, i]
                                fr[1, i] = -fr[1, i]
                        creep_tangent(law, r_[RES_A], r_[RES_B], r_[RES_XI], r_[RES_ETA], r_[RES_PHI], N, Fx, Fy,
                                      Mz, cp, t_nodes, coef, tab, D, dFN)
                # the contact's total force on the wheel (for the moment about the deck line's own motion)
                Fgy = N * nr[1]
                Fgz = N * nr[2]
                if creep:
                    Fgy += Fx * fr[0, 1] + Fy * fr[1, 1]
                    Fgz += Fx * fr[0, 2] + Fy * fr[1, 2]
                # the moment on the rails is about the deck line, which moves with the deck (exact)
                K[8, COL_DECK] += Fgz
                K[8, COL_DECK + 1] -= Fgy
                # ---- per unit normal load: the normal force and, through the load, the creep forces ...
                ex_ = nr[0]
                ey_ = nr[1]
                ez_ = nr[2]
                mz1 = 0.0
                if creep:
                    ex_ += dFN[0] * fr[0, 0] + dFN[1] * fr[1, 0]
                    ey_ += dFN[0] * fr[0, 1] + dFN[1] * fr[1, 1]
                    ez_ += dFN[0] * fr[0, 2] + dFN[1] * fr[1, 2]
                    mz1 = dFN[2]
                tx, ty, tz = _cross(rx, ry, rz, ex_, ey_, ez_)
                e9 = per_load[reg]
                e9[0] = ex_
                e9[1] = ey_
                e9[2] = ez_
                e9[3] = tx + mz1 * fr[2, 0]
                e9[4] = ty + mz1 * fr[2, 1]
                e9[5] = tz + mz1 * fr[2, 2]
                e9[6] = -ey_
                e9[7] = -ez_
                e9[8] = -((yc - y_d) * ez_ - (zc - z_d) * ey_ + mz1 * fr[2, 0])
                # ... and the penetration's gradient dδ/d(u, θ, deck y, z, θ): the wheel moves away along n, the
                # rails towards it (about their centre line)
                gx, gy, gz = _cross(rx, ry, rz, nr[0], nr[1], nr[2])
                gc = grad[reg]
                gc[0] = -nr[0]
                gc[1] = -nr[1]
                gc[2] = -nr[2]
                gc[3] = -gx
                gc[4] = -gy
                gc[5] = -gz
                gc[6] = nr[1]
                gc[7] = nr[2]
                gc[8] = -(zc - z_r) * nr[1] + (yc - y_r) * nr[2]
                if not creep:
                    continue
                # ---- creep damping: D ∂(ξ, η, φ)/∂(v, ω, deck rates)
                V = r_[RES_V]
                if not V >= v_min:
                    V = v_min
                for row in range(2):
                    cx, cy, cz = _cross(rx, ry, rz, fr[row, 0], fr[row, 1], fr[row, 2])
                    S[row, 0] = fr[row, 0] / V
                    S[row, 1] = fr[row, 1] / V
                    S[row, 2] = fr[row, 2] / V
                    S[row, 3] = cx / V
                    S[row, 4] = cy / V
                    S[row, 5] = cz / V
                    # the rail material velocity ẏ - θ̇ (z - z_d), ż + θ̇ (y - y_d) enters Δv with a minus sign
                    S[row, 6] = -fr[row, 1] / V
                    S[row, 7] = -fr[row, 2] / V
                    S[row, 8] = ((zc - z_d) * fr[row, 1] - (yc - y_d) * fr[row, 2]) / V
                for j in range(6):
                    S[2, j] = 0.0
                S[2, 3] = fr[2, 0] / V
                S[2, 4] = fr[2, 1] / V
                S[2, 5] = fr[2, 2] / V
                S[2, 6] = 0.0
                S[2, 7] = 0.0
                S[2, 8] = -fr[2, 0] / V           # the rails' angular velocity θ̇ about x
                for j in range(N_BLOCK):
                    dfx = D[0, 0] * S[0, j] + D[0, 1] * S[1, j] + D[0, 2] * S[2, j]
                    dfy = D[1, 0] * S[0, j] + D[1, 1] * S[1, j] + D[1, 2] * S[2, j]
                    dmz_j = D[2, 0] * S[0, j] + D[2, 1] * S[1, j] + D[2, 2] * S[2, j]
                    fx_ = dfx * fr[0, 0] + dfy * fr[1, 0]
                    fy_ = dfx * fr[0, 1] + dfy * fr[1, 1]
                    fz_ = dfx * fr[0, 2] + dfy * fr[1, 2]
                    cx, cy, cz = _cross(rx, ry, rz, fx_, fy_, fz_)
                    C[0, j] += fx_
                    C[1, j] += fy_
                    C[2, j] += fz_
                    C[3, j] += cx + dmz_j * fr[2, 0]
                    C[4, j] += cy + dmz_j * fr[2, 1]
                    C[5, j] += cz + dmz_j * fr[2, 2]
                    C[6, j] -= fy_
                    C[7, j] -= fz_
                    C[8, j] -= (yc - y_d) * fz_ - (zc - z_d) * fy_ + dmz_j * fr[2, 0]
            # two blended maxima of one overlap zone (kernel: FLAG_BLENDED): N_1 = (1 - b) H_1(δ_1),
            # N_2 = b H_2(δ_2), b the smoothstep of u = 1 - (δ_1 - δ_2)/(P δ_1): the weight's change couples them
            if (active[SLOT_TREAD] and active[SLOT_TREAD_2]
                    and int(out[w, SLOT_TREAD, F_FLAGS]) & FLAG_BLENDED
                    and int(out[w, SLOT_TREAD_2, F_FLAGS]) & FLAG_BLENDED):
                d1 = out[w, SLOT_TREAD, F_PENETRATION]
                d2 = out[w, SLOT_TREAD_2, F_PENETRATION]
                width = params[P_BLEND_DEPTH] * d1
                u = 1.0 - (d1 - d2) / width if width > 0.0 else 0.0
                if 0.0 < u < 1.0:
                    b = 0.5 * u * u * (3.0 - 2.0 * u)
                    db_du = 3.0 * u * (1.0 - u)
                    h1 = res[w, SLOT_TREAD, RES_N] / (1.0 - b)      # each maximum's own Hertz force
                    h2 = res[w, SLOT_TREAD_2, RES_N] / b
                    du_d1 = -d2 / (width * d1)
                    du_d2 = 1.0 / width
                    dNm[SLOT_TREAD, SLOT_TREAD] -= h1 * db_du * du_d1
                    dNm[SLOT_TREAD, SLOT_TREAD_2] -= h1 * db_du * du_d2
                    dNm[SLOT_TREAD_2, SLOT_TREAD] += h2 * db_du * du_d1
                    dNm[SLOT_TREAD_2, SLOT_TREAD_2] += h2 * db_du * du_d2
            # K += Σ_c Σ_d (per unit load of c) (∂N_c/∂δ_d) (∂δ_d/∂columns)
            for c in range(n_slots):
                if not active[c]:
                    continue
                for d in range(n_slots):
                    kcd = dNm[c, d]
                    if not active[d] or kcd == 0.0:
                        continue
                    for i in range(N_BLOCK):
                        a = per_load[c, i] * kcd
                        for j in range(N_BLOCK):
                            K[i, j] += a * grad[d, j]


#: largest δ κ_eff of a contact for which the turn of its normal is left out: the turn's stiffness N κ_eff against
#: Hertz's 1.5 N/δ is then below 1 %
CONFORMAL_LIMIT = 0.015


@compiled
def needs_differences(res, out):
    """Whether a contact of the state turns its normal too fast for the semi-analytic derivatives: a point of the
    concave search, a clamped (conformal) Hertz curvature, a non-Hertzian patch, or a relative lateral curvature with
    ``δ |κ_w κ_r/(κ_w + κ_r)| > CONFORMAL_LIMIT`` (the normal turns by ``κ_w κ_r/(κ_w + κ_r)`` per unit of
    tangential relative motion: the flange root against the gauge corner, where it reaches ~1e4 rad/m)."""
    for w in range(res.shape[0]):
        for reg in range(res.shape[1]):
            if res[w, reg, RES_STATUS] <= 0 or not res[w, reg, RES_N] > 0.0:
                continue
            if res[w, reg, RES_STATUS] != K_STATUS_CONVEX or int(out[w, reg, F_FLAGS]) & (FLAG_HERTZ_CLAMPED
                                                                                          | FLAG_PATCH):
                return True
            kw = out[w, reg, F_KW_LAT]
            kr = out[w, reg, F_KR_LAT]
            if not kw + kr > 0.0:
                return True
            if out[w, reg, F_PENETRATION] * abs(kw * kr / (kw + kr)) > CONFORMAL_LIMIT:
                return True
    return False


@compiled
def semi_analytic_jacobian(q, q_t, data, f0, res, f_odeq, f_odev, jac, Kq, Cv):
    """``jac = -(∂f/∂q f_odeq + ∂f/∂q̇ f_odev)`` of :func:`~.connector_core.contact_forces_core` at the state
    ``(q, q_t)`` of its **last** call (``f0`` its forces, ``res`` its results, ``data`` its packed arguments), from
    the derivatives of those results (:func:`contact_tangent_blocks`, module docstring) — no contact call — in
    Exudyn's coordinates of the Lie-group nodes (rotation: body-frame increment; angular velocity: body frame) and,
    with a bridge, its modal coordinates: the deck under a wheelset moves with ``u = Φ(s) q_m`` (``Φ(s)`` of the
    call), so ``∂f_k/∂q_m = (∂f_k/∂u) Φ`` and the modal forces ``Q = Σ_k Φ(s_k)ᵀ F_rail,k`` give
    ``Φᵀ ∂F_rail,k/∂(q_k, q_m)`` (Φ's change with the x coordinate, ``Φ'(s) F_rail``, is not differentiated).
    ``Kq``, ``Cv`` (n, 9, 9) scratch.  Whatever the state's contacts: the connector differences a state with a
    fast-turning normal instead (:func:`needs_differences`).

    The compiled code here calls no function of :mod:`.connector_core` (its cache would not see their changes);
    it reads the call's tuples and work arrays by their indices (:mod:`.core_data`)."""
    n = q.shape[0]
    for r in range(n):
        for c in range(n):
            jac[r, c] = 0.0
    contact_tangent_blocks(q, q_t, data, res, Kq, Cv)
    rot = data.work[W_ROT]
    phi_ws = data.state[ST_PHI_WS]
    deck_state = data.state[ST_DECK_STATE]
    n_ws = Kq.shape[0]
    n_w6 = 6 * n_ws
    n_m = n - n_w6
    A = np.empty((N_BLOCK, N_BLOCK))   # ∂f/∂(u, θ_b, deck) in Exudyn's rows (F track frame, τ body frame, rail)
    B = np.empty((N_BLOCK, N_BLOCK))   # ∂f/∂(v, ω_b, deck rates)
    T = np.empty(3)
    for k in range(n_ws):
        o = 6 * k
        R = rot[k]
        K = Kq[k]
        C = Cv[k]
        wb0 = q_t[o + 3]
        wb1 = q_t[o + 4]
        wb2 = q_t[o + 5]
        # columns: displacement, velocity and the deck's as they are; rotation and angular velocity from the body
        # frame, dθ = R dθ_b, dω = R dω_b; turning the body turns ω = R ω_b: dω = -R [ω_b]× dθ_b
        for i in range(N_BLOCK):
            for j in range(N_BLOCK):
                A[i, j] = K[i, j]
                B[i, j] = C[i, j]
            for j in range(3):
                kr = 0.0
                cr = 0.0
                for m in range(3):
                    kr += K[i, 3 + m] * R[m, j]
                    cr += C[i, 3 + m] * R[m, j]
                A[i, 3 + j] = kr
                B[i, 3 + j] = cr
            # -(C_ω R) [ω_b]×, column by column: [ω_b]× e_j = ω_b × e_j
            c0 = B[i, 3]
            c1 = B[i, 4]
            c2 = B[i, 5]
            T[0] = -(c1 * wb2 - c2 * wb1)
            T[1] = -(c2 * wb0 - c0 * wb2)
            T[2] = -(c0 * wb1 - c1 * wb0)
            for j in range(3):
                A[i, 3 + j] += T[j]
        # rows: torque to the body frame, τ_b = Rᵀ τ; its own turn [τ_b]× on the rotation columns
        for j in range(N_BLOCK):
            a0, a1, a2 = A[3, j], A[4, j], A[5, j]
            b0, b1, b2 = B[3, j], B[4, j], B[5, j]
            for i in range(3):
                A[3 + i, j] = R[0, i] * a0 + R[1, i] * a1 + R[2, i] * a2
                B[3 + i, j] = R[0, i] * b0 + R[1, i] * b1 + R[2, i] * b2
        t0 = f0[o + 3]
        t1 = f0[o + 4]
        t2 = f0[o + 5]
        A[3, 4] += -t2
        A[3, 5] += t1
        A[4, 3] += t2
        A[4, 5] += -t0
        A[5, 3] += -t1
        A[5, 4] += t0
        for i in range(6):
            for j in range(6):
                jac[o + i, o + j] = -(A[i, j] * f_odeq + B[i, j] * f_odev)
        if n_m == 0 or not deck_state[k, 6] > 0.5:
            continue
        phi = phi_ws[k]
        for jm in range(n_m):
            # modal rows of the wheelset columns: Φᵀ ∂F_rail/∂q_k; wheelset rows of the modal columns: ∂f_k/∂u Φ
            for c in range(6):
                d = 0.0
                for a in range(3):
                    d += phi[a, jm] * (A[ROW_RAIL + a, c] * f_odeq + B[ROW_RAIL + a, c] * f_odev)
                jac[n_w6 + jm, o + c] -= d
            for i in range(6):
                d = 0.0
                for a in range(3):
                    d += (A[i, COL_DECK + a] * f_odeq + B[i, COL_DECK + a] * f_odev) * phi[a, jm]
                jac[o + i, n_w6 + jm] -= d
        # modal block: Σ_k Φᵀ ∂F_rail/∂u Φ
        for im in range(n_m):
            for a in range(3):
                pa = phi[a, im]
                if pa == 0.0:
                    continue
                for b in range(3):
                    e = pa * (A[ROW_RAIL + a, COL_DECK + b] * f_odeq + B[ROW_RAIL + a, COL_DECK + b] * f_odev)
                    for jm in range(n_m):
                        jac[n_w6 + im, n_w6 + jm] -= e * phi[b, jm]
