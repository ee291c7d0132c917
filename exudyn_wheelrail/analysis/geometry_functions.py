"""Contact-geometry functions: a quasi-static rigid sweep of a wheelset's lateral shift.

For each lateral shift y of the wheelset (positive towards the right rail) the vertical position z and the roll
angle are solved so that *both* wheels just touch their rails (rigid bodies, zero penetration at the deepest point
of each wheel).  Each evaluation uses the **global** search (a vertical-overlap scan of every wheel region before
Newton), so the result is the true contact at every shift: S1002 on UIC60 has contact *jumps*, and a Newton
iteration warm-started from the previous shift would stay on a local solution and give hysteresis.

Output per shift and contact point: positions on wheel and rail (profile frames), rolling radius, contact angle,
roll angle, the rolling-radius difference Δr = r_right - r_left and Hertz semi-axes for a nominal vertical wheel
load (normal force ``Q / cos(gamma)``).  Points whose gap is below ``two_point_tolerance_m`` count as contact too
(a second, simultaneous contact point).
"""
from __future__ import annotations

import csv
from dataclasses import dataclass, field

import numpy as np

from ..contact import kernel as K
from ..contact.normal import hertz_from_force
from ..contact.pair import WheelRailPair
from ..contact.wheelset import SIDES, SLOT_REGIONS, WheelsetContact

CSV_COLUMNS = ("y_m", "side", "region", "y_rail_m", "y_wheel_m", "contact_angle_rad", "rolling_radius_m",
               "roll_rad", "a_m", "b_m", "z_m", "delta_r_m", "gap_m", "flags")

#: meaning of the ``flags`` column (';'-separated): the contact is at an end of the wheel or rail profile data
#: (it may lie beyond them), the Hertz curvatures were clamped (conformal contact), or the flange contact lies past
#: the steepest point of the flank towards the tip (the wheel has ridden up its flange: rigid flange climbing).
ROW_FLAGS = ("profile_end", "hertz_clamped", "beyond_flank")


class RigidContactError(RuntimeError):
    """The rigid equilibrium (both wheels touching) could not be found for a pose."""


@dataclass
class RigidContactState:
    """Solution of the rigid contact problem for one lateral shift."""

    y_m: float
    z_m: float
    roll_rad: float
    out: np.ndarray                      # kernel output (2, N_SLOTS, N_FIELDS) in side frames
    iterations: int
    deepest: tuple = field(default=(0, 0))   # region index of the touching point per side


def _deepest(out, w):
    """Region of the deepest (or least separated) point of wheel w, ignoring regions without overlap."""
    pen = [out[w, r, K.F_PENETRATION] if out[w, r, K.F_STATUS] != K.STATUS_NO_OVERLAP else -np.inf for r in (0, 1)]
    if not np.isfinite(max(pen)):
        raise RigidContactError(f"{SIDES[w]} wheel does not face its rail (off the rail)")
    return int(np.argmax(pen))


def solve_rigid_contact(contact: WheelsetContact, y_m: float, z0_m: float | None = None, roll0_rad: float = 0.0,
                        tol_m: float = 1e-12, max_iter: int = 60) -> RigidContactState:
    """Vertical position and roll so that both wheels touch (rigid), for lateral shift ``y_m``.

    Newton on (z, roll) with the penetrations of the deepest point of each wheel as residuals; the Jacobian
    comes from the rigid motion of the contact points along the rail normals.
    """
    if contact.params[K.P_GLOBAL] == 0.0:
        raise ValueError("solve_rigid_contact needs a WheelsetContact built with global_search=True")
    z = contact.pair.nominal_axle_height_m() if z0_m is None else z0_m
    roll = roll0_rad
    for it in range(1, max_iter + 1):
        out = contact.evaluate(np.array([[y_m, z, roll]]))
        side_poses = contact.side_poses(np.array([[y_m, z, roll]]))
        res = np.zeros(2)
        jac = np.zeros((2, 2))
        regions = []
        for w in (0, 1):
            r = _deepest(out, w)
            regions.append(r)
            o = out[w, r]
            sigma = 1.0 if w == 0 else -1.0
            c_y, c_z = side_poses[w, 0], side_poses[w, 1]
            ny, nz = o[K.F_NR_Y], o[K.F_NR_Z]
            res[w] = o[K.F_PENETRATION]
            # wheel point moves by (0, dz) + sigma*droll*(-(p_z - c_z), p_y - c_y); d(delta) = -dp . n_r
            jac[w, 0] = -nz
            jac[w, 1] = -sigma * (-ny * (o[K.F_PW_Z] - c_z) + nz * (o[K.F_PW_Y] - c_y))
        if np.max(np.abs(res)) < tol_m:
            return RigidContactState(y_m, z, roll, out.copy(), it, tuple(regions))
        step = np.linalg.solve(jac, -res)
        # damping: at most 1 mm and 2 mrad per iteration
        scale = min(1.0, 1e-3 / max(abs(step[0]), 1e-30), 2e-3 / max(abs(step[1]), 1e-30))
        z += scale * step[0]
        roll += scale * step[1]
    raise RigidContactError(f"no rigid equilibrium at y = {y_m:.6g} m after {max_iter} iterations "
                            f"(residual penetrations {res.tolist()} m)")


@dataclass
class GeometrySweep:
    """Rows of contact-geometry functions (one per contact point) plus per-shift arrays."""

    rows: list[dict]
    y_m: np.ndarray
    z_m: np.ndarray
    roll_rad: np.ndarray
    delta_r_m: np.ndarray          # r_right - r_left of the deepest (main) contact points

    def write_csv(self, path):
        with open(path, "w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=CSV_COLUMNS)
            writer.writeheader()
            for row in self.rows:
                writer.writerow({k: (f"{v:.10g}" if isinstance(v, float) else v) for k, v in row.items()})


def contact_geometry_sweep(pair: WheelRailPair, y_values_m, wheel_load_N: float = 10e3,
                           two_point_tolerance_m: float = 1e-6, n_scan: int = 200,
                           contact: WheelsetContact | None = None) -> GeometrySweep:
    """Contact-geometry functions over lateral shifts ``y_values_m`` (see module docstring).

    ``wheel_load_N`` is the nominal vertical wheel load used for the Hertz semi-axes (normal force
    ``Q / cos(gamma)`` at a single contact point; shared in proportion of ``1/cos`` at two points is not attempted:
    each point is given the full nominal load, so ``a``, ``b`` at a two-point shift are upper bounds).
    """
    if not (np.isfinite(wheel_load_N) and wheel_load_N > 0):
        raise ValueError(f"wheel_load_N = {wheel_load_N} must be a positive number of newtons")
    y_values_m = np.asarray(y_values_m, dtype=float)
    if not np.all(np.isfinite(y_values_m)):
        raise ValueError("lateral shifts must be finite numbers (metres)")
    if contact is None:
        contact = WheelsetContact(pair, global_search=True, n_scan=n_scan)
    rows = []
    ys, zs, rolls, drs = [], [], [], []
    z, roll = None, 0.0
    for y in np.asarray(y_values_m, dtype=float):
        # the start point only speeds up the (z, roll) Newton; the contact search itself is global
        state = solve_rigid_contact(contact, float(y), z, roll)
        z, roll = state.z_m, state.roll_rad
        out = state.out
        r_main = [out[w, state.deepest[w], K.F_ROLLING_RADIUS] for w in (0, 1)]
        delta_r = r_main[0] - r_main[1]
        ys.append(y); zs.append(z); rolls.append(roll); drs.append(delta_r)
        for w, side in enumerate(SIDES):
            for r, region in enumerate(SLOT_REGIONS):
                o = out[w, r]
                if o[K.F_STATUS] == K.STATUS_NO_OVERLAP:
                    continue
                gap = -o[K.F_PENETRATION]
                if r != state.deepest[w] and gap > two_point_tolerance_m:
                    continue
                gamma = o[K.F_CONTACT_ANGLE]
                _, a, b, hertz_status = hertz_from_force(o[K.F_A_REL], o[K.F_B_REL], contact.E_star,
                                                         wheel_load_N / max(np.cos(gamma), 1e-3))
                y_wheel, y_rail = pair.profile_coordinates(o[K.F_S_WHEEL], o[K.F_S_RAIL])
                flags = []
                if int(o[K.F_FLAGS]) & K.FLAG_PROFILE_END:
                    flags.append("profile_end")
                if int(hertz_status) & 3:
                    flags.append("hertz_clamped")
                if region == "flange" and y_wheel < pair.wheel.flank_y_m - 1e-6:
                    flags.append("beyond_flank")
                rows.append(dict(y_m=float(y), side=side, region=region, y_rail_m=y_rail, y_wheel_m=y_wheel,
                                 contact_angle_rad=float(gamma), rolling_radius_m=float(o[K.F_ROLLING_RADIUS]),
                                 roll_rad=float(roll), a_m=float(a), b_m=float(b), z_m=float(z),
                                 delta_r_m=float(delta_r), gap_m=float(max(gap, 0.0)), flags=";".join(flags)))
    return GeometrySweep(rows, np.array(ys), np.array(zs), np.array(rolls), np.array(drs))
