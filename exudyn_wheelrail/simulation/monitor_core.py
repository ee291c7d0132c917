"""The compiled per-state work of the run monitor (:mod:`.monitor`): one call per checked state over the arrays of
the contact evaluation at that state, returning a code — 0: nothing happened; otherwise an event to look at.

:class:`~.monitor.RunMonitor` packs its constants and running records into the arrays below once and calls

``monitor_state(t, res, out, ws_poses, q, v, par, ws_par, ext, iv, wq, wflag, wss, rings, G, work, phi_ws, hist,
hist_row)``

* ``res`` (2 n, N_SLOTS, N_RES), ``out`` (2 n, N_SLOTS, N_FIELDS): the connector's results and the kernel output of
  the evaluation (:mod:`exudyn_wheelrail.contact.layout`); ``ws_poses`` (n, 3): the wheelset pose relative to its
  rails, ``(c_y, c_z, roll)`` in the right wheel's side frame (the left wheel's is ``(-c_y, c_z, -roll)``);
  ``q``, ``v``: the connector's coordinates and velocities (6 per wheelset first);
* ``par[PAR_*]``: the monitor's limits and the geometry of the pair; ``ws_par[k, WSP_*]`` per wheelset
  ``1/√mass``, ``I^(-1/2)`` of the body inertia (body frame, row-major) and the node's reference position (the
  stability estimate);
* running records, updated in place: ``ext[w, EXT_*]`` the extremes per wheel; ``iv[w, IV_LIFT|IV_FLANGE|IV_DEEP,
  IVF_*]`` the interval of each per-wheel condition (open flag, start, last state, peak, reasons); ``wss[k, WS_*]``
  per wheelset the hunting counter and the stability estimate; ``rings[k, 0|1, j]`` the last ``2 cycles`` half-cycle
  crossing times and peaks of the hunting detection;
* written per state (read by Python only for a non-zero code): ``wq[w, WQ_*]`` the per-wheel quantities of the state
  and ``wflag[w]`` its ``WF_*`` bits; ``G[k, i, :]`` the contact rows of wheelset k's stability estimate
  (:func:`contact_rows`, ``wss[k, WS_ROWS]`` of them, :data:`N_G` columns); ``work`` scratch space; ``phi_ws`` (n,
  3, n_m) the structure's mode shapes under each wheelset (the connector's; n_m = 0 without a structure);
* ``hist[hist_row]`` gets the state's history row (``hist_row < 0``: none): time, then per wheel
  ``(c_y, c_z, roll, N, Y, gamma, delta)``.

The quantities are those :mod:`.monitor` documents, computed in the order and with the operations of NumPy's
reductions over the slots (sums in slot order, maxima that propagate NaN), so a value recorded here is the value
a NumPy evaluation of the same arrays gives.  Extremes follow Python's ``max(a, b)`` (``a`` unless ``b > a``).
"""
from __future__ import annotations

import math

import numpy as np

from ..contact.kernel import FLAG_DEEP_PENETRATION, FLAG_PROFILE_END
from ..contact.layout import (F_DN_DDELTA, F_NR_Y, F_NR_Z, F_PENETRATION, F_S_WHEEL, N_SLOTS, RES_DECK_Y,
                              RES_DECK_Z, RES_DELTA, RES_F_TRACK_X, RES_F_TRACK_Y, RES_F_TRACK_Z, RES_FLAGS, RES_GAMMA,
                              RES_N, RES_P_X, RES_P_Y, RES_P_Z, RES_STATUS, SLOT_FLANGE)
from ..jit import compiled
from ..multibody.rotations import rotation_from_vector

# ---- constants: par[PAR_*] ---------------------------------------------------------------------------------------
PAR_LIFT_FORCE = 0        # a wheel whose normal forces sum to at most this is lifted [N]
PAR_LARGE_LATERAL = 1     # flange lateral force of other_wheel_lifted [N]; NaN: Prud'homme's limit c0 + c1 P
PAR_PRUDHOMME_C0 = 2      # Prud'homme's limit for the instantaneous axle load P > 0: c0 + c1 P [N]
PAR_PRUDHOMME_C1 = 3
PAR_PRUDHOMME_NONE = 4    # ... and for P <= 0 [N]
PAR_INVALID_PEN = 5       # penetration of an invalid state [m]
PAR_MAX_SPEED = 6         # plausible wheelset lateral / vertical speed [m/s]
PAR_MAX_RATE = 7          # plausible roll / yaw rate [rad/s]
PAR_Y_CROWN = 8           # rail crown, side frame [m]
PAR_Z_CROWN = 9
PAR_TIP_Y = 10            # flange tip (flangeless: the tread's flange-side end), wheelset side frame [m]
PAR_TIP_Z = 11
PAR_FIELD_Y = 12          # field-side end of the tread [m]
PAR_FIELD_Z = 13
PAR_FLANGED = 14          # 1.0 for a flanged wheel
PAR_S_FLANK = 15          # wheel parameter of the flank's tip-side end [m]
PAR_PROFILE_END_LAT = 16  # D3: lateral displacement beyond which a profile-end flange contact is a derailment [m]
PAR_HUNT_AMP = 17         # hunting half-cycle peak [m]
PAR_HUNT_NEED = 18        # consecutive half-cycles needed (2 x cycles)
PAR_STEP = 19             # RK44 step [s] of the stability estimate; 0: no estimate
PAR_STAB_SCREEN = 20      # omega h above which a wheelset's estimate is handed to Python (exact eigenvalue)
N_PAR = 21

# ---- per wheelset constants: ws_par[k, WSP_*] ----------------------------------------------------------------------
WSP_HAS_INERTIA = 0       # 1.0: a rigid body on the node (the stability estimate applies)
WSP_INV_SQRT_MASS = 1     # 1 / sqrt(mass)
WSP_I_INV_SQRT = 2        # 9 entries, row-major: I^(-1/2) of the body inertia (body frame)
WSP_P_REF = 11            # 3 entries: reference position of the node [m]
N_WSP = 14

# ---- extremes per wheel: ext[w, EXT_*] ---------------------------------------------------------------------------
EXT_MAX_LATERAL = 0
EXT_MIN_LATERAL = 1
EXT_MAX_N = 2
EXT_MAX_ABS_Y = 3
EXT_MAX_PENETRATION = 4
EXT_MAX_ANGLE = 5
EXT_MAX_GAP = 6
N_EXT = 7

# ---- intervals: iv[w, kind, IVF_*] -------------------------------------------------------------------------------
IV_LIFT = 0
IV_FLANGE = 1
IV_DEEP = 2
N_IV = 3
IVF_OPEN = 0
IVF_START = 1
IVF_LAST = 2
IVF_PEAK = 3
IVF_REASONS = 4           # REASON_* bits (flange climb)
N_IVF = 5

REASON_BEYOND_FLANK = 1
REASON_PROFILE_END = 2
REASON_OTHER_WHEEL_LIFTED = 4
#: reason bit -> name, in the monitor's words
REASON_NAMES = ((REASON_BEYOND_FLANK, "beyond_flank"), (REASON_PROFILE_END, "profile_end"),
                (REASON_OTHER_WHEEL_LIFTED, "other_wheel_lifted"))

# ---- per-wheel quantities of the state: wq[w, WQ_*] --------------------------------------------------------------
WQ_N = 0                  # sum of the loaded contacts' normal forces [N]
WQ_Y = 1                  # lateral force, track frame, all slots [N]
WQ_Q = 2                  # wheel load -F_z [N]
WQ_Y_FLANGE = 3           # lateral force of the loaded flange contact [N]
WQ_DEPTH = 4              # largest loaded penetration [m]
WQ_GAMMA = 5              # largest loaded contact angle (NaN: no contact) [rad]
WQ_GAP = 6                # smallest distance of the separated regions [m]
WQ_CY = 7                 # pose relative to the rail, side frame
WQ_CZ = 8
WQ_ROLL = 9
WQ_Y_TIP = 10             # flange tip and field-side tread end placed by the pose
WQ_Z_TIP = 11
WQ_Y_FIELD = 12
WQ_LOADED = 13            # 1.0: the wheel carries a loaded contact
N_WQ = 14

# ---- per-wheel event bits: wflag[w] ------------------------------------------------------------------------------
WF_NON_FINITE = 1
WF_PENETRATION = 2
WF_D1_TIP = 4             # flange tip beyond the crown
WF_D2_LIFTED = 8          # flange tip above the rail top
WF_D1_FIELD = 16          # field-side tread end inside the crown
WF_D3 = 32                # loaded profile-end flange contact far towards the field side
WF_FLANGE_START = 64
WF_FLANGE_END = 128
WF_LIFT_START = 256
WF_LIFT_END = 512
WF_DEEP_START = 1024
WF_DEEP_END = 2048
WF_REASONS_SHIFT = 16     # the state's REASON_* bits, shifted

# ---- per wheelset: wss[k, WS_*] ----------------------------------------------------------------------------------
WS_HUNT_SIGN = 0
WS_HUNT_PEAK = 1
WS_HUNT_COUNT = 2         # consecutive half-cycles with peaks >= amplitude (= stored peaks)
WS_HUNT_CROSSINGS = 3     # crossings stored since the last reset
WS_HUNT_REPORTED = 4      # 1.0 once the detection was handed to Python
WS_MAX_OMEGA_H = 5        # largest omega h of the stability estimate
WS_OMEGA_H = 6            # this state's omega h (the screening value; NaN when its bound kept it below the maximum)
WS_ROWS = 7               # contact rows of this state's estimate
WS_FLAGS = 8              # WSF_* bits of this state
N_WS = 9

#: columns of a contact row of the stability estimate ``G[k, i]``: the wheelset's 6 (translation, rotation), then
#: the force's direction on the rails (y, z, θ: :func:`rail_mobility`)
N_G = 9

WSF_VELOCITY = 1          # implausible wheelset velocity or rate
WSF_HUNTING = 2           # hunting detected (first time)
WSF_STABILITY = 4         # omega h near RK44's limit: Python decides with the exact eigenvalue

#: code bits returned by :func:`monitor_state`
CODE_WHEEL = 1
CODE_WHEELSET = 2

# ---- the stability estimate's scratch matrices: work[MW_*] (empty_arrays), each (2 N_SLOTS, 2 N_SLOTS) -----------
MW_R = 0                  # the wheelset's rotation matrix (top-left 3 x 3)
MW_S = 1                  # R I^(-1/2) R^T (top-left 3 x 3)
MW_T = 2                  # R I^(-1/2) (top-left 3 x 3)
MW_A = 3                  # the contact rows against the wheelset's inertia, A = G M^(-1/2)
MW_B = 4                  # A A^T (plus the rails' modal mass on a structure)
MW_JACOBI = 5             # the copy Jacobi's method rotates
MW_W = 6                  # the rails' inverse modal mass under the wheelset (top-left 3 x 3)
N_MW = 7


@compiled(inline="always")
def _max_nan(a, b):
    """NumPy's maximum of two values: NaN propagates."""
    if a != a or b != b:
        return math.nan
    return a if a >= b else b


@compiled(inline="always")
def _py_max(a, b):
    """Python's ``max(a, b)``: ``a`` unless ``b > a``."""
    return b if b > a else a


@compiled(inline="always")
def _py_min(a, b):
    return b if b < a else a


@compiled(refcount=False)
def _interval(iv, w, kind, active, t, value):
    """One state of a per-wheel condition; returns 1 when an interval starts, 2 when it ends, else 0."""
    if active:
        flag = 0
        if iv[w, kind, IVF_OPEN] == 0.0:
            iv[w, kind, IVF_OPEN] = 1.0
            iv[w, kind, IVF_START] = t
            iv[w, kind, IVF_PEAK] = value
            iv[w, kind, IVF_REASONS] = 0.0
            flag = 1
        iv[w, kind, IVF_LAST] = t
        if math.isfinite(value) and value > iv[w, kind, IVF_PEAK]:
            iv[w, kind, IVF_PEAK] = value
        return flag
    if iv[w, kind, IVF_OPEN] != 0.0:
        iv[w, kind, IVF_OPEN] = 0.0
        iv[w, kind, IVF_LAST] = t
        return 2
    return 0


@compiled(refcount=False)
def largest_eigenvalue_psd(B, n, work):
    """Largest eigenvalue of the symmetric n x n block ``B[:n, :n]`` (cyclic Jacobi on a copy in ``work``; relative
    accuracy near machine precision for a positive semi-definite matrix)."""
    for i in range(n):
        for j in range(n):
            work[i, j] = B[i, j]
    scale = 0.0
    for i in range(n):
        for j in range(n):
            scale += work[i, j] * work[i, j]
    if scale == 0.0:
        return 0.0
    for _ in range(50):
        off = 0.0
        for i in range(n):
            for j in range(i + 1, n):
                off += work[i, j] * work[i, j]
        if off <= 1e-32 * scale:
            break
        for p in range(n):
            for r in range(p + 1, n):
                apr = work[p, r]
                if apr == 0.0:
                    continue
                theta = (work[r, r] - work[p, p]) / (2.0 * apr)
                tt = (1.0 if theta >= 0.0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(tt * tt + 1.0)
                s = tt * c
                for k in range(n):
                    akp = work[k, p]
                    akr = work[k, r]
                    work[k, p] = c * akp - s * akr
                    work[k, r] = s * akp + c * akr
                for k in range(n):
                    apk = work[p, k]
                    ark = work[r, k]
                    work[p, k] = c * apk - s * ark
                    work[r, k] = s * apk + c * ark
    lam = work[0, 0]
    for i in range(1, n):
        if work[i, i] > lam:
            lam = work[i, i]
    return lam


@compiled(refcount=False)
def contact_rows(k, q, res, out, ws_par, G):
    """The stability estimate's rows of wheelset k: ``√(dN/dδ) (n, r × n)`` per loaded contact (n the rail normal in
    the model frame, r the lever from the axle centre to the contact point) into ``G[k]``; returns their number."""
    cx = ws_par[k, WSP_P_REF] + q[6 * k]
    cy = ws_par[k, WSP_P_REF + 1] + q[6 * k + 1]
    cz = ws_par[k, WSP_P_REF + 2] + q[6 * k + 2]
    n_rows = 0
    for side in range(2):
        w = 2 * k + side
        mirror = 1.0 if side == 0 else -1.0
        for j in range(out.shape[1]):
            if not (res[w, j, RES_STATUS] > 0 and res[w, j, RES_N] > 0.0):
                continue
            ny = mirror * out[w, j, F_NR_Y]
            nz = out[w, j, F_NR_Z]
            rx = res[w, j, RES_P_X] - cx
            ry = res[w, j, RES_P_Y] - cy
            rz = res[w, j, RES_P_Z] - cz
            sk = math.sqrt(max(out[w, j, F_DN_DDELTA], 0.0))
            G[k, n_rows, 0] = 0.0
            G[k, n_rows, 1] = sk * ny
            G[k, n_rows, 2] = sk * nz
            G[k, n_rows, 3] = sk * (ry * nz - rz * ny)
            G[k, n_rows, 4] = -sk * rx * nz
            G[k, n_rows, 5] = sk * rx * ny
            # on the rails (a structure's modes): the force's generalized direction (y, z, θ about the rails'
            # centre line, as the deck interface)
            G[k, n_rows, 6] = sk * ny
            G[k, n_rows, 7] = sk * nz
            G[k, n_rows, 8] = sk * (nz * (res[w, j, RES_P_Y] - res[w, j, RES_DECK_Y])
                                    - ny * (res[w, j, RES_P_Z] - res[w, j, RES_DECK_Z]))
            n_rows += 1
    return n_rows


#: relative margin of the stability estimate's bound (:func:`_omega_h`) over the Jacobi eigenvalue's rounding
#: (relative error near 1e-15): a state is left to its bound only when the bound is clear of the running maximum
BOUND_MARGIN = 1e-12


@compiled(refcount=False)
def _omega_h(k, n_rows, q, ws_par, G, phi_ws, h, work, below):
    """ω h of wheelset k from its rows: the largest eigenvalue of A Aᵀ, A = G Mh, Mh = diag(I/√m, R I^(-1/2) Rᵀ);
    ``-1.0`` instead when the eigenvalue is bounded at or below ``below`` (Gershgorin's bound of the positive
    semi-definite A Aᵀ, the largest absolute row sum, with :data:`BOUND_MARGIN`): the Jacobi iteration is skipped
    for a state that cannot raise the running maximum ``below``."""
    R = work[MW_R, :3, :3]
    rotation_from_vector(q[6 * k + 3], q[6 * k + 4], q[6 * k + 5], R)
    S = work[MW_S, :3, :3]                              # R I^(-1/2) R^T
    T = work[MW_T, :3, :3]
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for m in range(3):
                acc += R[i, m] * ws_par[k, WSP_I_INV_SQRT + 3 * m + j]
            T[i, j] = acc
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for m in range(3):
                acc += T[i, m] * R[j, m]
            S[i, j] = acc
    A = work[MW_A]
    sm = ws_par[k, WSP_INV_SQRT_MASS]
    for i in range(n_rows):
        for j in range(3):
            A[i, j] = G[k, i, j] * sm
        for j in range(3):
            acc = 0.0
            for m in range(3):
                acc += G[k, i, 3 + m] * S[m, j]
            A[i, 3 + j] = acc
    B = work[MW_B]
    for i in range(n_rows):
        for j in range(n_rows):
            acc = 0.0
            for m in range(6):
                acc += A[i, m] * A[j, m]
            B[i, j] = acc
    rail_mobility(k, n_rows, G, phi_ws, B, work[MW_W, :3, :3])
    bound = 0.0
    for i in range(n_rows):
        row = 0.0
        for j in range(n_rows):
            row += abs(B[i, j])
        bound = max(bound, row)
    if math.sqrt(bound * (1.0 + BOUND_MARGIN)) * h <= below:
        return -1.0
    lam = largest_eigenvalue_psd(B, n_rows, work[MW_JACOBI])
    return math.sqrt(max(lam, 0.0)) * h


@compiled(refcount=False)
def rail_mobility(k, n_rows, G, phi_ws, B, W):
    """The rails' share of wheelset k's stability estimate on a structure's modes (mass-normalised, ``phi_ws[k]``
    = Φ(s) under it, (3, n_m); nothing without modes): the contacts also move the rails, whose inverse modal mass
    at s is ``W = Φ Φᵀ``, so ``B_ij += g_iᵀ W g_j`` with g the rows' rail directions (``G[k, :, 6:9]``).  On a
    flexible track this is the wheel on the rail's small modal mass — the highest coupled frequency.  ``W``: a
    3 x 3 work array (overwritten)."""
    n_m = phi_ws.shape[2]
    if n_m == 0:
        return
    for a in range(3):
        for b in range(a, 3):
            acc = 0.0
            for m in range(n_m):
                acc += phi_ws[k, a, m] * phi_ws[k, b, m]
            W[a, b] = acc
            W[b, a] = acc
    if W[0, 0] == 0.0 and W[1, 1] == 0.0 and W[2, 2] == 0.0:
        return                                          # off the structure
    for i in range(n_rows):
        for j in range(n_rows):
            acc = 0.0
            for a in range(3):
                for b in range(3):
                    acc += G[k, i, 6 + a] * W[a, b] * G[k, j, 6 + b]
            B[i, j] += acc


@compiled(refcount=False)
def monitor_state(t, res, out, ws_poses, q, v, par, ws_par, ext, iv, wq, wflag, wss, rings, G, work, phi_ws, hist,
                  hist_row):
    """One checked state (module docstring); returns ``CODE_*`` bits, 0 when nothing needs Python."""
    n_ws = ws_poses.shape[0]
    n_w = 2 * n_ws
    code = 0
    lift_force = par[PAR_LIFT_FORCE]
    # ---- per wheelset: plausibility of the velocities, stability estimate
    for k in range(n_ws):
        flags = 0
        vy, vz = abs(v[6 * k + 1]), abs(v[6 * k + 2])
        wx, wz = abs(v[6 * k + 3]), abs(v[6 * k + 5])
        if _py_max(vy, vz) > par[PAR_MAX_SPEED] or _py_max(wx, wz) > par[PAR_MAX_RATE]:
            flags |= WSF_VELOCITY
        wss[k, WS_ROWS] = 0.0
        if par[PAR_STEP] > 0.0 and ws_par[k, WSP_HAS_INERTIA] != 0.0:
            n_rows = contact_rows(k, q, res, out, ws_par, G)
            wss[k, WS_ROWS] = n_rows
            if n_rows > 0:
                wh = _omega_h(k, n_rows, q, ws_par, G, phi_ws, par[PAR_STEP], work,
                              min(wss[k, WS_MAX_OMEGA_H], par[PAR_STAB_SCREEN]))
                wss[k, WS_OMEGA_H] = wh if wh >= 0.0 else np.nan
                if wh > par[PAR_STAB_SCREEN]:
                    flags |= WSF_STABILITY                  # near the limit: Python decides with the exact eigenvalue
                elif wh >= 0.0:                             # (-1: bounded below the running maximum, no change)
                    wss[k, WS_MAX_OMEGA_H] = _py_max(wss[k, WS_MAX_OMEGA_H], wh)
        wss[k, WS_FLAGS] = flags
        if flags != 0:
            code |= CODE_WHEELSET
    # ---- per wheel: the quantities of the state
    for w in range(n_w):
        k = w // 2
        right = w % 2 == 0
        n_sum = 0.0
        y_sum = 0.0
        z_sum = 0.0
        depth = 0.0
        gamma = -math.inf
        any_loaded = False
        for j in range(N_SLOTS):
            loaded = res[w, j, RES_STATUS] > 0 and res[w, j, RES_N] > 0.0
            any_loaded = any_loaded or loaded
            n_j = res[w, j, RES_N] if loaded else 0.0
            n_sum = n_j if j == 0 else n_sum + n_j
            y_sum = res[w, j, RES_F_TRACK_Y] if j == 0 else y_sum + res[w, j, RES_F_TRACK_Y]
            z_sum = res[w, j, RES_F_TRACK_Z] if j == 0 else z_sum + res[w, j, RES_F_TRACK_Z]
            depth = _max_nan(depth, res[w, j, RES_DELTA] if loaded else 0.0) if j > 0 else \
                (res[w, j, RES_DELTA] if loaded else 0.0)
            gamma = _max_nan(gamma, res[w, j, RES_GAMMA] if loaded else -math.inf)
        pen = -math.inf
        for j in range(N_SLOTS):
            p = out[w, j, F_PENETRATION]
            if math.isfinite(p) and p > pen:
                pen = p
        wq[w, WQ_N] = n_sum
        wq[w, WQ_Y] = y_sum
        wq[w, WQ_Q] = -z_sum
        fl_loaded = res[w, SLOT_FLANGE, RES_STATUS] > 0 and res[w, SLOT_FLANGE, RES_N] > 0.0
        wq[w, WQ_Y_FLANGE] = res[w, SLOT_FLANGE, RES_F_TRACK_Y] if fl_loaded else 0.0
        wq[w, WQ_DEPTH] = depth
        wq[w, WQ_GAMMA] = gamma if any_loaded else math.nan
        wq[w, WQ_GAP] = -pen
        c_y = ws_poses[k, 0] if right else -ws_poses[k, 0]
        c_z = ws_poses[k, 1]
        roll = ws_poses[k, 2] if right else -ws_poses[k, 2]
        wq[w, WQ_CY] = c_y
        wq[w, WQ_CZ] = c_z
        wq[w, WQ_ROLL] = roll
        wq[w, WQ_LOADED] = 1.0 if any_loaded else 0.0
    # ---- per wheel: records, checks, intervals
    for w in range(n_w):
        k = w // 2
        flags = 0
        any_loaded = wq[w, WQ_LOADED] != 0.0
        c_y, c_z, roll = wq[w, WQ_CY], wq[w, WQ_CZ], wq[w, WQ_ROLL]
        n_w_force = wq[w, WQ_N]
        depth = wq[w, WQ_DEPTH]
        gamma = wq[w, WQ_GAMMA]
        finite = math.isfinite(c_y) and math.isfinite(c_z) and math.isfinite(roll)
        for j in range(N_SLOTS):
            if res[w, j, RES_STATUS] > 0 and res[w, j, RES_N] > 0.0:
                if not (math.isfinite(res[w, j, RES_N]) and math.isfinite(res[w, j, RES_F_TRACK_X])
                        and math.isfinite(res[w, j, RES_F_TRACK_Y]) and math.isfinite(res[w, j, RES_F_TRACK_Z])
                        and math.isfinite(res[w, j, RES_GAMMA]) and math.isfinite(res[w, j, RES_DELTA])
                        and math.isfinite(res[w, j, RES_P_Y]) and math.isfinite(res[w, j, RES_P_Z])):
                    finite = False
        if not finite:
            flags |= WF_NON_FINITE
        ext[w, EXT_MAX_LATERAL] = _py_max(ext[w, EXT_MAX_LATERAL], c_y)
        ext[w, EXT_MIN_LATERAL] = _py_min(ext[w, EXT_MIN_LATERAL], c_y)
        ext[w, EXT_MAX_N] = _py_max(ext[w, EXT_MAX_N], n_w_force)
        ext[w, EXT_MAX_ABS_Y] = _py_max(ext[w, EXT_MAX_ABS_Y], abs(wq[w, WQ_Y]))
        ext[w, EXT_MAX_PENETRATION] = _py_max(ext[w, EXT_MAX_PENETRATION], depth)
        if any_loaded:
            ext[w, EXT_MAX_ANGLE] = _py_max(ext[w, EXT_MAX_ANGLE], gamma)
        if depth > par[PAR_INVALID_PEN]:
            flags |= WF_PENETRATION
        # derailment D1 / D2 (module docstring of .monitor)
        cr, sr = math.cos(roll), math.sin(roll)
        y_tip = c_y + cr * par[PAR_TIP_Y] - sr * par[PAR_TIP_Z]
        z_tip = c_z + sr * par[PAR_TIP_Y] + cr * par[PAR_TIP_Z]
        y_field = c_y + cr * par[PAR_FIELD_Y] - sr * par[PAR_FIELD_Z]
        wq[w, WQ_Y_TIP] = y_tip
        wq[w, WQ_Z_TIP] = z_tip
        wq[w, WQ_Y_FIELD] = y_field
        if y_tip >= par[PAR_Y_CROWN]:
            flags |= WF_D1_TIP
        elif par[PAR_FLANGED] != 0.0 and z_tip < par[PAR_Z_CROWN]:
            flags |= WF_D2_LIFTED
        elif y_field <= par[PAR_Y_CROWN]:
            flags |= WF_D1_FIELD
        # flange climb indications
        reasons = 0
        if res[w, SLOT_FLANGE, RES_STATUS] > 0 and res[w, SLOT_FLANGE, RES_N] > 0.0:
            if out[w, SLOT_FLANGE, F_S_WHEEL] < par[PAR_S_FLANK]:
                reasons |= REASON_BEYOND_FLANK
            fl = res[w, SLOT_FLANGE, RES_FLAGS]
            if math.isfinite(fl) and (int(fl) & FLAG_PROFILE_END) != 0:
                reasons |= REASON_PROFILE_END
                if c_y >= par[PAR_PROFILE_END_LAT]:
                    flags |= WF_D3
        other = w + 1 if w % 2 == 0 else w - 1
        y_flange = wq[w, WQ_Y_FLANGE]
        if wq[other, WQ_N] <= lift_force and y_flange != 0.0:
            limit = par[PAR_LARGE_LATERAL]
            if limit != limit:                              # Prud'homme, with the wheelset's instantaneous load
                P = wq[w, WQ_Q] + wq[other, WQ_Q]
                limit = par[PAR_PRUDHOMME_C0] + par[PAR_PRUDHOMME_C1] * P if P > 0.0 else par[PAR_PRUDHOMME_NONE]
            if abs(y_flange) > limit:
                reasons |= REASON_OTHER_WHEEL_LIFTED
        if reasons != 0 or iv[w, IV_FLANGE, IVF_OPEN] != 0.0:
            r = _interval(iv, w, IV_FLANGE, reasons != 0, t, gamma if reasons != 0 else 0.0)
            if reasons != 0:
                iv[w, IV_FLANGE, IVF_REASONS] = float(int(iv[w, IV_FLANGE, IVF_REASONS]) | reasons)
            if r == 1:
                flags |= WF_FLANGE_START
            elif r == 2:
                flags |= WF_FLANGE_END
        # lift-off
        lifted = n_w_force <= lift_force
        gap = wq[w, WQ_GAP]
        if lifted:
            ext[w, EXT_MAX_GAP] = _py_max(ext[w, EXT_MAX_GAP], gap)
        r = _interval(iv, w, IV_LIFT, lifted, t, gap if lifted else 0.0)
        if r == 1:
            flags |= WF_LIFT_START
        elif r == 2:
            flags |= WF_LIFT_END
        # deep penetration flag
        deep = False
        for j in range(N_SLOTS):
            if res[w, j, RES_STATUS] > 0 and res[w, j, RES_N] > 0.0:
                fj = res[w, j, RES_FLAGS]
                if math.isfinite(fj) and (int(fj) & FLAG_DEEP_PENETRATION) != 0:
                    deep = True
        if deep or iv[w, IV_DEEP, IVF_OPEN] != 0.0:
            r = _interval(iv, w, IV_DEEP, deep, t, depth)
            if r == 1:
                flags |= WF_DEEP_START
            elif r == 2:
                flags |= WF_DEEP_END
        if flags != 0:
            code |= CODE_WHEEL
        wflag[w] = flags | (reasons << WF_REASONS_SHIFT)
        if hist_row >= 0:
            o = 1 + 7 * w
            hist[hist_row, o] = c_y
            hist[hist_row, o + 1] = c_z
            hist[hist_row, o + 2] = roll
            hist[hist_row, o + 3] = n_w_force
            hist[hist_row, o + 4] = wq[w, WQ_Y]
            hist[hist_row, o + 5] = gamma
            hist[hist_row, o + 6] = depth
    if hist_row >= 0:
        hist[hist_row, 0] = t
    # ---- hunting per wheelset: half-cycles of c_y (right wheel) about the centre
    need = int(par[PAR_HUNT_NEED])
    amp = par[PAR_HUNT_AMP]
    for k in range(n_ws):
        y = ws_poses[k, 0]
        s = 1.0 if y > 0.0 else (-1.0 if y < 0.0 else 0.0)
        if s == 0.0:
            continue
        if wss[k, WS_HUNT_SIGN] == 0.0:
            wss[k, WS_HUNT_SIGN] = s
        if s != wss[k, WS_HUNT_SIGN]:
            if wss[k, WS_HUNT_PEAK] >= amp:
                c = int(wss[k, WS_HUNT_COUNT])
                rings[k, 1, c % need] = wss[k, WS_HUNT_PEAK]
                wss[k, WS_HUNT_COUNT] = c + 1
                n_c = int(wss[k, WS_HUNT_CROSSINGS])
                rings[k, 0, n_c % need] = t
                wss[k, WS_HUNT_CROSSINGS] = n_c + 1
            else:
                wss[k, WS_HUNT_COUNT] = 0.0
                rings[k, 0, 0] = t
                wss[k, WS_HUNT_CROSSINGS] = 1.0
            wss[k, WS_HUNT_SIGN] = s
            wss[k, WS_HUNT_PEAK] = 0.0
        wss[k, WS_HUNT_PEAK] = _py_max(wss[k, WS_HUNT_PEAK], abs(y))
        if wss[k, WS_HUNT_COUNT] >= need and wss[k, WS_HUNT_CROSSINGS] >= 3 and wss[k, WS_HUNT_REPORTED] == 0.0:
            wss[k, WS_HUNT_REPORTED] = 1.0
            wss[k, WS_FLAGS] = int(wss[k, WS_FLAGS]) | WSF_HUNTING
            code |= CODE_WHEELSET
    return code


@compiled(refcount=False)
def rail_poses(side_poses, half_gauge, ws_poses):
    """``ws_poses`` (n, 3): each wheelset's pose relative to its rails, ``(c_y, c_z, roll)`` of its right wheel with
    ``c_y`` measured from the rails' centre line — the right wheels' rows of ``side_poses`` (2 n, 3) with
    ``half_gauge`` (n,) added to ``c_y`` (the connector's
    :meth:`~exudyn_wheelrail.multibody.connector.WheelRailContact.wheelset_rail_pose`, without allocating)."""
    for k in range(ws_poses.shape[0]):
        ws_poses[k, 0] = side_poses[2 * k, 0] + half_gauge[k]
        ws_poses[k, 1] = side_poses[2 * k, 1]
        ws_poses[k, 2] = side_poses[2 * k, 2]


def hunting_rings_ordered(rings_k, count: int, crossings: int, need: int):
    """The last ``need`` crossing times and peaks of one wheelset's rings, oldest first."""
    ts = [rings_k[0, (crossings - need + i) % need] for i in range(need)]
    ps = [rings_k[1, (count - need + i) % need] for i in range(need)]
    return np.array(ts), np.array(ps)


def empty_arrays(n_ws: int, need: int):
    """The running arrays of a new monitor: ``(ext, iv, wq, wflag, wss, rings, G, work)``."""
    n_w = 2 * n_ws
    ext = np.zeros((n_w, N_EXT))
    ext[:, EXT_MAX_ANGLE] = -math.inf
    ext[:, EXT_MAX_LATERAL] = -math.inf
    ext[:, EXT_MIN_LATERAL] = math.inf
    iv = np.zeros((n_w, N_IV, N_IVF))
    wq = np.zeros((n_w, N_WQ))
    wflag = np.zeros(n_w, dtype=np.int64)
    wss = np.zeros((n_ws, N_WS))
    rings = np.zeros((n_ws, 2, max(1, need)))
    G = np.zeros((n_ws, 2 * N_SLOTS, N_G))
    work = np.zeros((N_MW, 2 * N_SLOTS, 2 * N_SLOTS))
    return ext, iv, wq, wflag, wss, rings, G, work
