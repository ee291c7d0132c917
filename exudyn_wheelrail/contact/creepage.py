r"""Creepages of a wheel–rail contact from the rigid-body motion of the wheelset and of the rail.

Everything here is in the track frame of :mod:`exudyn_wheelrail.conventions` (x forward, y right, z down) and in
SI units.  The rail may move (a flexible bridge gives the rail material point at the contact a velocity and an
angular velocity); for a rigid track both are zero.

Contact frame ``contact`` (rows ``x_c, y_c, z_c`` of a 3x3 array, track components)
--------------------------------------------------------------------------------
* ``z_c`` — unit normal from the wheel **into** the rail: ``z_c = -n_rail`` (``n_rail`` the outward rail normal);
* ``x_c`` — the rolling direction in the tangent plane: ``x_c = ±unit(e_axle × z_c)``, ``e_axle`` the wheelset's
  lateral axis (pointing to the **right** for both wheels).  The sign is ``+`` when the wheelset runs forward
  relative to the rail (rolling speed ``V >= 0``, below), ``-`` when it runs backwards;
* ``y_c = z_c × x_c`` (right-handed).  Running forward, ``y_c`` points to the right for both wheels, tilted by the
  contact angle: ``y_c = (0, cos γ, -sin γ)`` on the right wheel (up the flange), ``(0, cos γ, +sin γ)`` on the
  left wheel (down its flange), γ the contact angle of :mod:`~exudyn_wheelrail.conventions`.

Creepages (Kalker 1990, *Three-dimensional elastic bodies in rolling contact*, ch. 1: rigid slip over rolling speed)
--------------------------------------------------------------------------------------------------------------
With ``r = p - c`` (contact point relative to the wheelset centre), the wheel material point velocity
``v_wheel = v_centre + ω_wheelset × r`` and the rail material point velocity ``v_rail`` at the contact::

    ξ = (v_wheel - v_rail) · x_c / V,   η = (v_wheel - v_rail) · y_c / V,   φ = (ω_wheelset - ω_rail) · z_c / V

(ξ, η dimensionless, φ in 1/m).  These are the signs of the creep-force contract of :mod:`exudyn_wheelrail.creep`
(forces on the wheel, small creepage ``Fx = -G c² C11 ξ``, ``Fy = -G c² (C22 η + c C23 φ)``): a wheel point that
slides forward (ξ > 0, e.g. a locked braked wheel) gets a backward force.  The rigid slip at a point (x, y) of the
contact patch is ``(ξ - φ y, η + φ x)·V``, as in FASTSIM.  Examples (wheelset speed V along +x, spin Ω about the
axle, ``ω_wheelset = -Ω e_axle`` because z points down): pure rolling on radius r (Ω = V/r) gives zero; a coned
wheel (contact angle γ) has φ = -Ω sin γ / V on the right wheel and +Ω sin γ / V on the left one; a wheelset
yawed by ψ (positive turns the nose towards +y) and running along x has η = -tan ψ on both wheels at free rolling.

Rolling speed V (the normaliser)
--------------------------------
Kalker's **mean rolling speed**: the mean of the speeds, along ``x_c``, with which wheel and rail material pass
through the contact point::

    V = ((v_cp - v_rail) + (v_cp - v_wheel)) · x_c / 2

The contact point is taken to move with the wheelset **without its spin about the axle**:
``v_cp = v_centre + (ω_wheelset - (ω_wheelset·ê_axle) ê_axle) × r`` (exact for a steady contact on a straight
track; the time derivative of the contact's position on the profiles is neglected).  Pure rolling at speed V gives
V; a locked wheel sliding at speed V gives V/2 (ξ = 2, Kalker's full-slide value); a wheel spinning on the spot
has V = Ω r/2 > 0, so wheel spin at standstill is not a division by zero.

* **Backwards running** (``V < 0``, the material passes from -x_c to +x_c): ``x_c`` and ``y_c`` are reversed so
  that ``x_c`` is always the direction of rolling (the creep-force laws assume the material enters the patch at
  ``x = +a``) and V becomes |V|; status bit :data:`CREEP_REVERSED`.  Reversing every velocity therefore leaves ξ and
  η unchanged and flips φ (the physical asymmetry of spin–lateral coupling).  Forces from a creep law are in the
  returned (reversed) frame.
* **Standstill guard**: the creepages are divided by ``max(|V|, v_min)``, default :data:`DEFAULT_V_MIN_M_S`
  = 0.01 m/s; when the guard is active status bit :data:`CREEP_STANDSTILL` is set (the creepages are then relative
  velocities over ``v_min``, a regularisation, not Kalker's creepages).  The returned V is the unguarded |V|.
* A normal parallel to the axle (no rolling direction), a zero normal or axle, or a non-finite input give NaN
  creepages and :data:`CREEP_DEGENERATE_FRAME` / :data:`CREEP_INVALID_INPUT`; the Python wrapper raises.

Contact point of a yawed wheelset (first-order lead/lag of the contact)
---------------------------------------------------------------------
The contact search works in the cross-section (pose y, z, roll; yaw neglected).  A yawed wheel of revolution
touches a straight prismatic rail where its normal has no x component, i.e. not at the lowest point of its
circle: with the wheelset orientation ``Q = R_z(ψ) R_x(roll)`` and a wheel point at axial coordinate u, radius ρ,
whose (unyawed) outward normal has axial/radial components (n_u, n_ρ), the point is rotated on its circle by θ
with ``cos ψ n_ρ sin θ + sin ψ sin(roll) n_ρ cos θ = sin ψ cos(roll) n_u``, which :func:`yawed_contact_point`
solves exactly.  To first order the contact lies ``x_lead = ρ tan ψ sin γ / cos γ_w ≈ ρ tan γ tan ψ`` ahead of the
axle's vertical plane on the right wheel and as far behind it on the left one (γ the contact angle, γ_w = γ ± roll
its angle to the axle): with the nose turned towards the right rail (ψ > 0) the right flange contact leads and the
left one lags.  **Approximation**: the profile point (u, ρ) itself is the yaw-free search's, so the result is exact
to first order in ψ only.  Against a brute-force 3-D minimum distance of a yawed torus on a cylinder
(``tests/test_creepage.py``) the lead is within 0.4 % at ψ = 2.4 mrad; the error grows like ψ² (1 % at
ψ = 24 mrad and γ = 0.8 rad, 10 % at γ = 1.2 rad, where the point climbs its wheel circle by ρθ²/2 ≈ 0.9 mm).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..jit import compiled

__all__ = [
    "DEFAULT_V_MIN_M_S", "CREEP_OK", "CREEP_STANDSTILL", "CREEP_REVERSED", "CREEP_DEGENERATE_FRAME",
    "CREEP_INVALID_INPUT", "Creepages", "contact_frame", "contact_frame_core", "creepages", "creepages_core",
    "wheelset_axis", "yawed_contact_point", "yawed_contact_point_core", "yawed_contact_point_cs",
    "creep_status_names",
]

#: Default standstill guard [m/s]: creepages are divided by max(|V|, v_min).
DEFAULT_V_MIN_M_S = 0.01

CREEP_OK = 0
CREEP_STANDSTILL = 1          # |V| < v_min: normalised by v_min
CREEP_REVERSED = 2            # V < 0: x_c and y_c reversed (running backwards)
CREEP_DEGENERATE_FRAME = 4    # no rolling direction (normal parallel to the axle, or a zero vector): NaN output
CREEP_INVALID_INPUT = 8       # a non-finite input: NaN output

_STATUS_NAMES = ((CREEP_STANDSTILL, "standstill"), (CREEP_REVERSED, "reversed"),
                 (CREEP_DEGENERATE_FRAME, "degenerate-frame"), (CREEP_INVALID_INPUT, "invalid-input"))

#: |e_axle × z_c| below this (sine of the angle between normal and axle) counts as a degenerate frame
_MIN_FRAME_SINE = 1e-9


def creep_status_names(status: int) -> tuple[str, ...]:
    """Names of the bits set in a creepage status (empty tuple: ok)."""
    return tuple(name for bit, name in _STATUS_NAMES if int(status) & bit)


# ---- compiled core ------------------------------------------------------------------------------------------------
@compiled(inline="always")
def _cross(ax, ay, az, bx, by, bz):
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@compiled(inline="always")
def contact_frame_core(n_rail, e_axle, direction, frame_out):
    """Fill ``frame_out`` (3, 3) with rows x_c, y_c, z_c (track frame) from the outward rail normal and the wheelset
    axis; ``direction`` +1 (forward) or -1 (x_c, y_c reversed).  Returns a status (0 or CREEP_DEGENERATE_FRAME /
    CREEP_INVALID_INPUT, frame NaN)."""
    nn = math.sqrt(n_rail[0] ** 2 + n_rail[1] ** 2 + n_rail[2] ** 2)
    na = math.sqrt(e_axle[0] ** 2 + e_axle[1] ** 2 + e_axle[2] ** 2)
    if not (math.isfinite(nn) and math.isfinite(na) and math.isfinite(direction)):
        frame_out[:, :] = np.nan
        return CREEP_INVALID_INPUT
    if nn == 0.0 or na == 0.0:
        frame_out[:, :] = np.nan
        return CREEP_DEGENERATE_FRAME
    zx = -n_rail[0] / nn
    zy = -n_rail[1] / nn
    zz = -n_rail[2] / nn
    tx, ty, tz = _cross(e_axle[0] / na, e_axle[1] / na, e_axle[2] / na, zx, zy, zz)
    nt = math.sqrt(tx * tx + ty * ty + tz * tz)
    if nt < _MIN_FRAME_SINE:
        frame_out[:, :] = np.nan
        return CREEP_DEGENERATE_FRAME
    s = 1.0 if direction >= 0.0 else -1.0
    xx = s * tx / nt
    xy = s * ty / nt
    xz = s * tz / nt
    yx, yy, yz = _cross(zx, zy, zz, xx, xy, xz)
    frame_out[0, 0] = xx
    frame_out[0, 1] = xy
    frame_out[0, 2] = xz
    frame_out[1, 0] = yx
    frame_out[1, 1] = yy
    frame_out[1, 2] = yz
    frame_out[2, 0] = zx
    frame_out[2, 1] = zy
    frame_out[2, 2] = zz
    return CREEP_OK


@compiled(inline="always")
def creepages_core(p_contact, n_rail, e_axle, p_centre, v_centre, omega_wheelset, v_rail, omega_rail, v_min,
                   frame_out):
    """Compiled creepages (no Python objects): all vectors (3,) in the track frame, ``v_min`` > 0 [m/s].

    Fills ``frame_out`` (3, 3) with the contact frame (rows x_c, y_c, z_c, reversed when running backwards) and
    returns ``(xi, eta, phi, V, status)``: creepages (φ in 1/m), the unguarded rolling speed |V| [m/s] and the
    CREEP_* bits (see the module docstring).  Invalid input gives NaN and a nonzero status, never an exception."""
    ok = math.isfinite(v_min) and v_min > 0.0
    for k in range(3):
        ok = ok and math.isfinite(p_contact[k]) and math.isfinite(p_centre[k]) and math.isfinite(v_centre[k]) \
            and math.isfinite(omega_wheelset[k]) and math.isfinite(v_rail[k]) and math.isfinite(omega_rail[k])
    if not ok:
        frame_out[:, :] = np.nan
        return np.nan, np.nan, np.nan, np.nan, CREEP_INVALID_INPUT
    status = contact_frame_core(n_rail, e_axle, 1.0, frame_out)
    if status != CREEP_OK:
        return np.nan, np.nan, np.nan, np.nan, status
    rx = p_contact[0] - p_centre[0]
    ry = p_contact[1] - p_centre[1]
    rz = p_contact[2] - p_centre[2]
    wx, wy, wz = omega_wheelset[0], omega_wheelset[1], omega_wheelset[2]
    cx, cy, cz = _cross(wx, wy, wz, rx, ry, rz)
    # wheel material point and relative velocity
    vwx = v_centre[0] + cx
    vwy = v_centre[1] + cy
    vwz = v_centre[2] + cz
    dvx = vwx - v_rail[0]
    dvy = vwy - v_rail[1]
    dvz = vwz - v_rail[2]
    # contact point: moves with the wheelset without its spin about the axle
    na = math.sqrt(e_axle[0] ** 2 + e_axle[1] ** 2 + e_axle[2] ** 2)
    ax = e_axle[0] / na
    ay = e_axle[1] / na
    az = e_axle[2] / na
    spin = wx * ax + wy * ay + wz * az
    fx, fy, fz = _cross(wx - spin * ax, wy - spin * ay, wz - spin * az, rx, ry, rz)
    vcx = v_centre[0] + fx
    vcy = v_centre[1] + fy
    vcz = v_centre[2] + fz
    xcx, xcy, xcz = frame_out[0, 0], frame_out[0, 1], frame_out[0, 2]
    v_roll = 0.5 * (((vcx - v_rail[0]) + (vcx - vwx)) * xcx + ((vcy - v_rail[1]) + (vcy - vwy)) * xcy
                    + ((vcz - v_rail[2]) + (vcz - vwz)) * xcz)
    if v_roll < 0.0:
        status |= CREEP_REVERSED
        for k in range(3):
            frame_out[0, k] = -frame_out[0, k]
            frame_out[1, k] = -frame_out[1, k]
        v_roll = -v_roll
    v_norm = v_roll
    if v_roll < v_min:
        status |= CREEP_STANDSTILL
        v_norm = v_min
    xi = (dvx * frame_out[0, 0] + dvy * frame_out[0, 1] + dvz * frame_out[0, 2]) / v_norm
    eta = (dvx * frame_out[1, 0] + dvy * frame_out[1, 1] + dvz * frame_out[1, 2]) / v_norm
    phi = ((wx - omega_rail[0]) * frame_out[2, 0] + (wy - omega_rail[1]) * frame_out[2, 1]
           + (wz - omega_rail[2]) * frame_out[2, 2]) / v_norm
    return xi, eta, phi, v_roll, status


@compiled(refcount=False)
def yawed_contact_point_core(p_y, p_z, n_y, n_z, c_x, c_y, c_z, roll, yaw):
    """Contact point of a yawed wheel of revolution (module docstring, last section).

    ``(p_y, p_z)``: wheel contact point of the yaw-free search and ``(n_y, n_z)`` the outward rail normal there
    (track frame, in the cross-section x = c_x of the wheelset centre ``(c_x, c_y, c_z)``); ``roll``, ``yaw`` [rad].
    Returns ``(x, y, z, theta, ok)``: the point rotated on its wheel circle by ``theta`` [rad] so that the wheel
    normal has no x component; ok False (NaN point) when no such angle exists (a normal almost along the axle)."""
    return yawed_contact_point_cs(p_y, p_z, n_y, n_z, c_x, c_y, c_z, math.cos(roll), math.sin(roll), math.cos(yaw),
                                  math.sin(yaw))


@compiled(refcount=False)
def yawed_contact_point_cs(p_y, p_z, n_y, n_z, c_x, c_y, c_z, cr, sr, cp, sp):
    """:func:`yawed_contact_point_core` with the cosine and sine of the roll (``cr``, ``sr``) and of the yaw
    (``cp``, ``sp``) given: the connector computes them once per wheelset for all its contacts."""
    dy = p_y - c_y
    dz = p_z - c_z
    u = cr * dy + sr * dz              # body (wheelset) frame: axial and radial coordinates of the point
    rho = -sr * dy + cr * dz
    w_u = -(cr * n_y + sr * n_z)       # wheel outward normal = -rail normal, in the body frame
    w_rho = -(-sr * n_y + cr * n_z)
    a = cp * w_rho
    b = sp * sr * w_rho
    k = sp * cr * w_u
    h = math.hypot(a, b)
    if not (h > 0.0) or abs(k) > h or not math.isfinite(k):
        return np.nan, np.nan, np.nan, np.nan, False
    theta = math.asin(k / h) - math.atan2(b, a)
    bx = rho * math.sin(theta)
    bz = rho * math.cos(theta)
    # Q = R_z(yaw) R_x(roll) applied to the body vector (bx, u, bz)
    qy = cr * u - sr * bz
    qz = sr * u + cr * bz
    x = c_x + cp * bx - sp * qy
    y = c_y + sp * bx + cp * qy
    z = c_z + qz
    return x, y, z, theta, True


# ---- Python front -------------------------------------------------------------------------------------------------
def _vec3(name, value) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    if v.shape != (3,):
        raise ValueError(f"{name} must be a 3-vector (track frame x, y, z), got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} contains NaN or infinity: {v.tolist()}")
    return v


def wheelset_axis(roll_rad: float = 0.0, yaw_rad: float = 0.0) -> np.ndarray:
    """Unit lateral axis of a wheelset (pointing right) in the track frame: ``R_z(yaw) R_x(roll) e_y``."""
    return np.array([-math.sin(yaw_rad) * math.cos(roll_rad), math.cos(yaw_rad) * math.cos(roll_rad),
                     math.sin(roll_rad)])


def contact_frame(n_rail_in_track, e_axle_in_track, direction: float = 1.0) -> np.ndarray:
    """Contact frame (3, 3), rows ``x_c, y_c, z_c`` in the track frame, from the outward rail normal and the
    wheelset axis (module docstring).  ``direction=-1`` reverses x_c and y_c.  Raises ``ValueError`` when the normal
    is parallel to the axle or a vector is zero/non-finite."""
    frame = np.empty((3, 3))
    status = contact_frame_core(_vec3("n_rail_in_track", n_rail_in_track), _vec3("e_axle_in_track", e_axle_in_track),
                                float(direction), frame)
    if status:
        raise ValueError("no contact frame: the rail normal is zero or parallel to the wheelset axis "
                         f"(n_rail = {list(n_rail_in_track)}, e_axle = {list(e_axle_in_track)})")
    return frame


@dataclass(frozen=True)
class Creepages:
    """Creepages of one contact (module docstring for the definitions and signs)."""

    xi: float                       # longitudinal [-]
    eta: float                      # lateral [-]
    phi_per_m: float                # spin [1/m]
    rolling_speed_m_s: float        # |V|, unguarded
    status: int                     # CREEP_* bits
    frame_in_track: np.ndarray      # rows x_c, y_c, z_c

    @property
    def standstill(self) -> bool:
        """The standstill guard was active (creepages divided by v_min)."""
        return bool(self.status & CREEP_STANDSTILL)

    @property
    def reversed(self) -> bool:
        """Running backwards: x_c and y_c were reversed."""
        return bool(self.status & CREEP_REVERSED)


def creepages(p_contact_in_track, p_centre_in_track, v_centre_in_track, omega_wheelset_in_track, n_rail_in_track,
              e_axle_in_track, v_rail_in_track=(0.0, 0.0, 0.0), omega_rail_in_track=(0.0, 0.0, 0.0),
              v_min_m_s: float = DEFAULT_V_MIN_M_S) -> Creepages:
    """Creepages ξ, η, φ at a contact point (see the module docstring).

    Parameters (all track frame, SI)
    --------------------------------
    p_contact_in_track : contact point.
    p_centre_in_track, v_centre_in_track, omega_wheelset_in_track : wheelset centre, its velocity, the wheelset's
        angular velocity.
    n_rail_in_track, e_axle_in_track : outward rail normal and wheelset lateral axis (right; any length).  The
        contact frame is built from them (:func:`contact_frame`); the axle is needed in any case, because the
        rolling speed removes the wheel's spin about it from the contact point's velocity.
    v_rail_in_track, omega_rail_in_track : velocity and angular velocity of the rail material point at the contact
        (zero for a rigid track).
    v_min_m_s : standstill guard (> 0).

    Raises ``ValueError`` for non-finite input, a degenerate frame or ``v_min_m_s <= 0``; the standstill guard and
    backwards running are reported in ``status`` (and the properties ``standstill``, ``reversed``).
    """
    v_min = float(v_min_m_s)
    if not (math.isfinite(v_min) and v_min > 0.0):
        raise ValueError(f"v_min_m_s must be a positive speed, got {v_min_m_s}")
    frame = np.empty((3, 3))
    xi, eta, phi, v, status = creepages_core(
        _vec3("p_contact_in_track", p_contact_in_track), _vec3("n_rail_in_track", n_rail_in_track),
        _vec3("e_axle_in_track", e_axle_in_track), _vec3("p_centre_in_track", p_centre_in_track),
        _vec3("v_centre_in_track", v_centre_in_track), _vec3("omega_wheelset_in_track", omega_wheelset_in_track),
        _vec3("v_rail_in_track", v_rail_in_track), _vec3("omega_rail_in_track", omega_rail_in_track), v_min, frame)
    if status & (CREEP_DEGENERATE_FRAME | CREEP_INVALID_INPUT):
        raise ValueError("no contact frame: the rail normal is zero or parallel to the wheelset axis "
                         f"(n_rail = {list(n_rail_in_track)}, e_axle = {list(e_axle_in_track)})")
    return Creepages(float(xi), float(eta), float(phi), float(v), int(status), frame)


def yawed_contact_point(p_wheel_yz_in_track, n_rail_yz_in_track, p_centre_in_track, roll_rad: float,
                        yaw_rad: float) -> tuple[np.ndarray, float]:
    """3-D contact point of a yawed wheelset from the yaw-free cross-section contact (module docstring).

    ``p_wheel_yz_in_track``: (y, z) of the wheel contact point found at yaw 0, ``n_rail_yz_in_track``: (y, z) of
    the outward rail normal there, ``p_centre_in_track``: wheelset centre (x, y, z).  Returns the point (3,) and the
    angle θ [rad] by which it was moved on its wheel circle (positive: forward, towards +x at yaw 0).  Raises
    ``ValueError`` when the normal is too close to the axle for the wheel normal to be made perpendicular to x."""
    p = np.asarray(p_wheel_yz_in_track, dtype=float)
    n = np.asarray(n_rail_yz_in_track, dtype=float)
    c = _vec3("p_centre_in_track", p_centre_in_track)
    if p.shape != (2,) or n.shape != (2,) or not (np.all(np.isfinite(p)) and np.all(np.isfinite(n))):
        raise ValueError("p_wheel_yz_in_track and n_rail_yz_in_track must be finite (y, z) pairs")
    x, y, z, theta, ok = yawed_contact_point_core(p[0], p[1], n[0], n[1], c[0], c[1], c[2], float(roll_rad),
                                                  float(yaw_rad))
    if not ok:
        raise ValueError(f"no contact point on the yawed wheel (yaw {yaw_rad} rad): the normal {n.tolist()} is "
                         "too close to the axle direction")
    return np.array([x, y, z]), float(theta)
