r"""Quasi-static contact analysis of one wheelset: wheel loads, creepages and creep forces at a given lateral shift,
yaw angle and speed (the situation of the Manchester contact benchmark, case A-2.2).

Problem
-------
Given the lateral shift ``y`` (positive towards the right rail), the yaw angle ψ (positive turns the nose, +x,
towards +y: conventions of :mod:`exudyn_wheelrail.contact.creepage`), the vertical load ``Q`` on each wheel and the
forward speed ``V`` along the track, find

* the vertical position ``z`` and the roll angle of the wheelset such that each wheel carries ``Q``: the upward
  (−z) components of all contact forces on that wheel — normal forces **and creep forces** (on a flange the lateral
  creep force has a large vertical component) — sum to ``Q``;
* the pitch rate for **free rolling**: the total moment about the axle of the creep forces on the wheelset (the
  tangential forces Fx, Fy at their points and the spin moments Mz) is zero.  The normal forces are taken to pass
  through the axle (exact for a surface of revolution).  The pitch rate is ``ω·ê_axle``, negative when rolling
  forward (z points down); ``spin_speed_rad_s`` = −pitch rate.  A prescribed pitch rate may be given instead.

Three residuals (two loads, one moment) in three unknowns (z, roll, pitch rate), solved by a damped Newton method
with a forward-difference Jacobian (the creep forces' dependence on the loads and the creepages is strongly coupled
at a flange contact: a Jacobian of the normal problem alone would converge slowly or not at all there).
Convergence: both load residuals below ``tol_force_N`` (default 1e-6 Q) and the moment below ``tol_moment_Nm``
(default 1e-6 Q r0); the status is reported, not raised (:class:`QuasiStaticResult`).

Geometry, normal problem, creepages, creep forces
-------------------------------------------------
* geometry: :class:`~exudyn_wheelrail.contact.wheelset.WheelsetContact` in **global-search** mode at the pose
  (y, z, roll) — yaw is neglected by the search; the start is the rigid touching state of
  :func:`~exudyn_wheelrail.analysis.geometry_functions.solve_rigid_contact` lowered by the Hertz approach of ``Q``;
* normal forces and the Hertz semi-axes a (rolling), b (lateral) from the kernel (penetration → Hertz), or, for a
  contact built with ``contact_patch="non-hertzian"``, the non-Hertzian patch's resultant and equivalent ellipse
  where Hertz does not hold (:mod:`exudyn_wheelrail.contact.patch_pass`; flag ``patch``);
* creepages: :func:`~exudyn_wheelrail.contact.creepage.creepages_core`, wheelset centre (0, y, z) moving with
  (V, 0, 0), angular velocity ``pitch_rate · ê_axle``, rigid track.  Yaw enters here: the axle
  ``ê_axle = R_z(ψ) R_x(roll) e_y`` and the contact point, placed on its wheel circle at the yaw lead/lag
  (:func:`~exudyn_wheelrail.contact.creepage.yawed_contact_point`, first order in ψ — an approximation);
* creep forces: a law with the contract ``law(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson) ->
  (Fx, Fy, Mz)``, forces on the wheel in the contact frame (default :func:`exudyn_wheelrail.creep.fastsim`).  Laws
  built on Kalker's table accept ``0.1 <= a/b <= 10`` only, while flange contacts are long and narrow (S1002 on
  UIC60: a/b ≈ 17–24).  By default the law is then called with the ellipse of the **same area** (c = √(ab)) at the
  nearest limit of the law's range, and the point is flagged ``creep_ratio_clamped``
  (``semi_axis_ratio_range=None`` raises instead).

Force on the wheel at a contact, track frame: ``Fx x_c + Fy y_c - N z_c`` (the normal force ``N n_rail`` pushes
the wheel out of the rail).  Frames and signs: :mod:`exudyn_wheelrail.conventions` and
:mod:`exudyn_wheelrail.contact.creepage`.

Known limitations: a wheel region holds one contact point (kernel); yaw is neglected by the contact search (its
O(ψ²) effect on the cross-section, e.g. the wheels moving inwards by u(1 − cos ψ) ≈ 0.2 mm at 24 mrad, is not
seen); the contact point's lead is exact to first order in ψ only.
"""
from __future__ import annotations

import importlib
import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..contact import kernel as K
from ..contact.creepage import (DEFAULT_V_MIN_M_S, creep_status_names, creepages_core, wheelset_axis,
                                yawed_contact_point_core)
from ..contact.normal import hertz_from_force
from ..contact.wheelset import E_STEEL_PA, NU_STEEL, SIDES, SLOT_REGIONS, STATUS_NAMES, WheelsetContact
from .geometry_functions import RigidContactError, solve_rigid_contact

__all__ = ["QuasiStaticPoint", "QuasiStaticResult", "QuasiStaticError", "solve_quasi_static", "creep_law_by_name",
           "CREEP_LAWS", "DEFAULT_SHEAR_MODULUS_PA", "SEMI_AXIS_RATIO_RANGE"]

#: Shear modulus of steel consistent with the contact's default E and ν: E / (2 (1 + ν)) [Pa].
DEFAULT_SHEAR_MODULUS_PA = E_STEEL_PA / (2.0 * (1.0 + NU_STEEL))

#: a/b range of Kalker's Table E.3, which the coefficient-based laws (FASTSIM, linear, SHE, Polach) need; the
#: default clamp for a creep law given as a callable.
SEMI_AXIS_RATIO_RANGE = (0.1, 10.0)

#: Creep laws selectable by name: where to find them (module, attribute; tried in order) and the a/b range they
#: accept (None: any).  'table' is the tabulated Kalker exact theory, 'exact' the direct exact-theory solver (slow).
CREEP_LAWS = {
    "fastsim": ((("exudyn_wheelrail.creep", "fastsim"),), SEMI_AXIS_RATIO_RANGE),
    "table": ((("exudyn_wheelrail.creep", "table_forces"), ("exudyn_wheelrail.creep.table", "table_forces")),
              (0.05, 20.0)),
    "exact": ((("exudyn_wheelrail.creep", "kalker_exact"), ("exudyn_wheelrail.creep.kalker_exact", "kalker_exact")),
              None),
}

CreepLaw = Callable[..., tuple]


def creep_law_by_name(name: str) -> CreepLaw:
    """The creep law registered as ``name`` (:data:`CREEP_LAWS`); ``ValueError`` naming what is missing when it is
    unknown or cannot be imported."""
    if name not in CREEP_LAWS:
        raise ValueError(f"unknown creep law {name!r}; choose one of {', '.join(CREEP_LAWS)}")
    tried = []
    for module_name, attribute in CREEP_LAWS[name][0]:
        try:
            module = importlib.import_module(module_name)
        except ImportError:
            tried.append(f"{module_name} (not importable)")
            continue
        law = getattr(module, attribute, None)
        if callable(law):
            return law
        tried.append(f"{module_name}.{attribute} (missing)")
    raise ValueError(f"creep law {name!r} is not available in this installation: tried {'; '.join(tried)}")


class QuasiStaticError(RuntimeError):
    """The quasi-static problem could not be set up or evaluated (e.g. no rigid contact, a creep-law error)."""


@dataclass(frozen=True)
class QuasiStaticPoint:
    """One contact point of the quasi-static solution; forces on the wheel, SI units."""

    side: str                       # 'right' / 'left'
    region: str                     # 'tread' / 'flange'
    method: str                     # 'convex' / 'concave' (kernel search)
    p_contact_in_track: np.ndarray  # wheel contact point incl. the yaw lead (x, y, z) [m]
    p_rail_in_track: np.ndarray     # rail contact point of the yaw-free search (y, z) [m]
    lead_m: float                   # contact position ahead of the axle's vertical plane (wheel frame x) [m]
    y_wheel_m: float                # lateral coordinate on the wheel profile (profile frame)
    y_rail_m: float                 # lateral coordinate on the rail profile (profile frame, as the geometry CSV)
    contact_angle_rad: float
    rolling_radius_m: float
    penetration_m: float
    normal_force_N: float
    a_m: float                      # Hertz semi-axis along rolling
    b_m: float                      # lateral
    xi: float
    eta: float
    phi_per_m: float
    rolling_speed_m_s: float
    Fx_N: float                     # creep forces on the wheel, contact frame
    Fy_N: float
    Mz_Nm: float
    frame_in_track: np.ndarray      # rows x_c, y_c, z_c
    force_on_wheel_in_track: np.ndarray   # Fx x_c + Fy y_c - N z_c
    flags: tuple = ()               # kernel flags, creepage status, 'creep_ratio_clamped'


@dataclass
class QuasiStaticResult:
    """Solution for one (y, yaw): the pose, the pitch rate, the contact points and the convergence record."""

    y_m: float
    yaw_rad: float
    wheel_load_N: float
    speed_m_s: float
    z_m: float
    roll_rad: float
    pitch_rate_rad_s: float          # ω · ê_axle (negative when rolling forward)
    points: list = field(default_factory=list)
    converged: bool = False
    iterations: int = 0
    evaluations: int = 0
    residual_load_N: np.ndarray = field(default_factory=lambda: np.full(2, np.nan))   # right, left
    residual_moment_Nm: float = float("nan")
    free_rolling: bool = True
    message: str = ""

    @property
    def spin_speed_rad_s(self) -> float:
        """Rotation speed about the axle, positive when rolling forward (= −pitch rate)."""
        return -self.pitch_rate_rad_s

    def side_points(self, side: str) -> list:
        return [p for p in self.points if p.side == side]

    def vertical_support_N(self, side: str) -> float:
        """Upward (−z) sum of the contact forces on one wheel (= the wheel load when converged)."""
        return float(sum(-p.force_on_wheel_in_track[2] for p in self.side_points(side)))

    def force_on_wheelset_in_track(self) -> np.ndarray:
        """Sum of all contact forces on the wheelset, track frame."""
        return np.sum([p.force_on_wheel_in_track for p in self.points], axis=0) if self.points else np.zeros(3)


# ---------------------------------------------------------------------------------------------------------------
def _finite(name, value, positive=False, nonnegative=False):
    v = float(value)
    if not math.isfinite(v) or (positive and v <= 0.0) or (nonnegative and v < 0.0):
        kind = "a positive" if positive else ("a non-negative" if nonnegative else "a finite")
        raise ValueError(f"{name} = {value!r} must be {kind} number (SI units)")
    return v


class _Evaluator:
    """Residuals (load right, load left, axle moment) and contact points at (z, roll, pitch rate)."""

    def __init__(self, contact, y, yaw, load, speed, law, mu, shear_modulus, poisson, v_min, ratio_range):
        self.contact = contact
        self.y, self.yaw, self.load, self.speed = y, yaw, load, speed
        self.law, self.mu, self.G, self.nu = law, mu, shear_modulus, poisson
        self.v_min, self.ratio_range = v_min, ratio_range
        self.count = 0
        self._frame = np.empty((3, 3))
        self._zero = np.zeros(3)
        self._v_centre = np.array([speed, 0.0, 0.0])

    def _creep(self, a, b, xi, eta, phi, n, where):
        flags = ()
        ratio = a / b
        if self.ratio_range is not None and not (self.ratio_range[0] <= ratio <= self.ratio_range[1]):
            r = min(max(ratio, self.ratio_range[0]), self.ratio_range[1])
            c = math.sqrt(a * b)
            a, b = c * math.sqrt(r), c / math.sqrt(r)
            flags = ("creep_ratio_clamped",)
        try:
            fx, fy, mz = self.law(a, b, xi, eta, phi, n, self.mu, self.G, self.nu)
        except (ValueError, RuntimeError, ArithmeticError) as exc:
            raise QuasiStaticError(f"creep law failed at the {where} contact (a = {a:.4g} m, b = {b:.4g} m, "
                                   f"xi = {xi:.4g}, eta = {eta:.4g}, phi = {phi:.4g} 1/m, N = {n:.4g} N): {exc}") \
                from exc
        return float(fx), float(fy), float(mz), flags

    def __call__(self, z, roll, pitch_rate, detail=False):
        self.count += 1
        out = self.contact.evaluate(np.array([[self.y, z, roll]]))
        centre = np.array([0.0, self.y, z])
        e_axle = wheelset_axis(roll, self.yaw)
        omega = pitch_rate * e_axle
        support = np.zeros(2)
        moment = 0.0
        points = []
        for w, side in enumerate(SIDES):
            mirror = 1.0 if side == "right" else -1.0
            for reg, region in enumerate(SLOT_REGIONS):
                o = out[w, reg]
                status = int(o[K.F_STATUS])
                n_force = o[K.F_NORMAL_FORCE]
                if status <= 0 or not n_force > 0.0:
                    continue
                p_y, p_z = mirror * o[K.F_PW_Y], o[K.F_PW_Z]
                n_y, n_z = mirror * o[K.F_NR_Y], o[K.F_NR_Z]
                x, py, pz, theta, ok = yawed_contact_point_core(p_y, p_z, n_y, n_z, 0.0, self.y, z, roll, self.yaw)
                if not ok:
                    raise QuasiStaticError(f"{side} {region}: no contact point on the yawed wheel (normal along "
                                           "the axle)")
                p = np.array([x, py, pz])
                n_rail = np.array([0.0, n_y, n_z])
                xi, eta, phi, v_roll, cstat = creepages_core(p, n_rail, e_axle, centre, self._v_centre, omega,
                                                             self._zero, self._zero, self.v_min, self._frame)
                if cstat & 12:
                    raise QuasiStaticError(f"{side} {region}: creepages undefined ({creep_status_names(cstat)})")
                a, b = o[K.F_SEMI_A], o[K.F_SEMI_B]
                fx, fy, mz, cflags = self._creep(a, b, xi, eta, phi, n_force, f"{side} {region}")
                f = self._frame
                tangential = fx * f[0] + fy * f[1]
                force = tangential - n_force * f[2]
                support[w] -= force[2]
                moment += float(np.dot(np.cross(p - centre, tangential) + mz * f[2], e_axle))
                if detail:
                    flags = []
                    kf = int(o[K.F_FLAGS])
                    if kf & K.FLAG_PROFILE_END:
                        flags.append("profile_end")
                    if kf & K.FLAG_DEEP_PENETRATION:
                        flags.append("deep_penetration")
                    if kf & K.FLAG_HERTZ_CLAMPED:
                        flags.append("hertz_clamped")
                    if kf & K.FLAG_PATCH:
                        flags.append("patch")
                    if kf & K.FLAG_PATCH_FAILED:
                        flags.append("patch_failed")
                    flags += list(creep_status_names(cstat)) + list(cflags)
                    y_wheel, y_rail = self.contact.pair.profile_coordinates(o[K.F_S_WHEEL], o[K.F_S_RAIL])
                    points.append(QuasiStaticPoint(
                        side=side, region=region, method=STATUS_NAMES.get(status, str(status)),
                        p_contact_in_track=p, p_rail_in_track=np.array([mirror * o[K.F_PR_Y], o[K.F_PR_Z]]),
                        lead_m=_lead(p_y - self.y, p_z - z, roll, theta),
                        y_wheel_m=y_wheel, y_rail_m=y_rail, contact_angle_rad=float(o[K.F_CONTACT_ANGLE]),
                        rolling_radius_m=float(o[K.F_ROLLING_RADIUS]), penetration_m=float(o[K.F_PENETRATION]),
                        normal_force_N=float(n_force), a_m=float(a), b_m=float(b), xi=float(xi), eta=float(eta),
                        phi_per_m=float(phi), rolling_speed_m_s=float(v_roll), Fx_N=fx, Fy_N=fy, Mz_Nm=mz,
                        frame_in_track=f.copy(), force_on_wheel_in_track=force, flags=tuple(flags)))
        residual = np.array([support[0] - self.load, support[1] - self.load, moment])
        return residual, points, out


def _lead(dy, dz, roll, theta):
    """Wheel-frame x of the contact: radius of the point (distance from the axle) times sin(theta)."""
    rho = -math.sin(roll) * dy + math.cos(roll) * dz
    return rho * math.sin(theta)


def _initial_guess(contact, y, load, z0, roll0):
    """Rigid touching pose lowered by the Hertz approach of the load at each wheel's touching point."""
    try:
        rigid = solve_rigid_contact(contact, y, z0, roll0)
    except RigidContactError as exc:
        raise QuasiStaticError(f"no rigid contact state at y = {y:.6g} m: {exc}") from exc
    out = rigid.out
    dz = np.zeros(2)
    lateral = np.zeros(2)
    for w in (0, 1):
        o = out[w, rigid.deepest[w]]
        gamma = o[K.F_CONTACT_ANGLE]
        cos_g = max(math.cos(gamma), 0.2)
        delta, _, _, _ = hertz_from_force(o[K.F_A_REL], o[K.F_B_REL], contact.E_star, load / cos_g)
        dz[w] = delta / cos_g                       # lowering the wheel by dz deepens it by dz cos(gamma)
        lateral[w] = o[K.F_PW_Y]                    # side frame: distance to the right of (outwards from) centre
    half_span = max(0.5 * (lateral[0] + lateral[1]), 0.3)   # ~ half the distance between the contacts
    # positive roll lowers the right wheel: dz_right = dz + half_span droll
    return (rigid.z_m + 0.5 * (dz[0] + dz[1]), rigid.roll_rad + 0.5 * (dz[0] - dz[1]) / half_span)


def solve_quasi_static(contact: WheelsetContact, y_m: float, yaw_rad: float, wheel_load_N: float, speed_m_s: float,
                       *, mu: float = 0.3, shear_modulus_Pa: float = DEFAULT_SHEAR_MODULUS_PA,
                       poisson: float = NU_STEEL, creep_law: CreepLaw | str | None = None,
                       pitch_rate_rad_s: float | None = None, semi_axis_ratio_range="auto",
                       v_min_m_s: float = DEFAULT_V_MIN_M_S, tol_force_N: float | None = None,
                       tol_moment_Nm: float | None = None, max_iter: int = 40, z0_m: float | None = None,
                       roll0_rad: float = 0.0) -> QuasiStaticResult:
    """Quasi-static wheelset contact at lateral shift ``y_m`` and yaw ``yaw_rad`` (module docstring).

    Parameters
    ----------
    contact : a :class:`WheelsetContact` built with ``global_search=True`` (one wheelset).  Its materials must match
        ``shear_modulus_Pa`` and ``poisson`` (checked: E* = G/(1-ν) within 5 %).
    wheel_load_N : vertical load Q carried by each wheel [N] (> 0).
    speed_m_s : forward speed V of the wheelset along the track [m/s] (> 0).
    mu, shear_modulus_Pa, poisson : friction coefficient and the combined elastic constants of the creep law.
    creep_law : callable ``law(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson) -> (Fx, Fy, Mz)``, or a
        name of :data:`CREEP_LAWS`; default FASTSIM.
    pitch_rate_rad_s : prescribed pitch rate ω·ê_axle (negative forward) instead of free rolling.
    semi_axis_ratio_range : (min, max) of a/b at which the creep law is evaluated: outside it the ellipse of the
        same area at the nearest limit is used and the point flagged ``creep_ratio_clamped``.  "auto": the range
        registered for a named law (:data:`CREEP_LAWS`), :data:`SEMI_AXIS_RATIO_RANGE` for a callable; None: no
        clamping (a creep-law error is raised as :class:`QuasiStaticError`).
    tol_force_N, tol_moment_Nm : convergence tolerances (default 1e-6 Q and 1e-6 Q r0).
    z0_m, roll0_rad : start of the rigid (z, roll) search.

    Returns a :class:`QuasiStaticResult`; ``converged`` False (with ``message``) when Newton did not reach the
    tolerances.  Raises ``ValueError`` for bad input and :class:`QuasiStaticError` when the problem cannot be
    evaluated (no rigid contact, creep law failure).
    """
    if contact.params[K.P_GLOBAL] == 0.0:
        raise ValueError("solve_quasi_static needs a WheelsetContact built with global_search=True")
    if contact.n_wheelsets != 1:
        raise ValueError(f"solve_quasi_static works on one wheelset, the contact has {contact.n_wheelsets}")
    y = _finite("y_m", y_m)
    yaw = _finite("yaw_rad", yaw_rad)
    if abs(yaw) > 0.1:
        raise ValueError(f"yaw_rad = {yaw} is beyond 0.1 rad: the yaw-free contact search is meaningless there")
    load = _finite("wheel_load_N", wheel_load_N, positive=True)
    speed = _finite("speed_m_s", speed_m_s, positive=True)
    mu = _finite("mu", mu, nonnegative=True)
    G = _finite("shear_modulus_Pa", shear_modulus_Pa, positive=True)
    nu = _finite("poisson", poisson)
    if not 0.0 <= nu < 0.5:
        raise ValueError(f"poisson = {nu} must lie in [0, 0.5)")
    e_star_creep = G / (1.0 - nu)          # E* of two equal bodies: E/(2(1-nu^2)) with E = 2G(1+nu)
    if abs(e_star_creep / contact.E_star - 1.0) > 0.05:
        raise ValueError(f"the creep law's G = {G:.4g} Pa, nu = {nu} imply E* = {e_star_creep:.4g} Pa, but the "
                         f"contact was built with E* = {contact.E_star:.4g} Pa: give matching materials")
    if creep_law is None:
        creep_law = "fastsim"
    ratio_range = semi_axis_ratio_range
    if isinstance(creep_law, str):
        if isinstance(ratio_range, str) and ratio_range == "auto":
            ratio_range = CREEP_LAWS[creep_law][1] if creep_law in CREEP_LAWS else None
        creep_law = creep_law_by_name(creep_law)
    if not callable(creep_law):
        raise ValueError(f"creep_law must be callable or a name of {list(CREEP_LAWS)}, got {creep_law!r}")
    if isinstance(ratio_range, str):
        if ratio_range != "auto":
            raise ValueError(f"semi_axis_ratio_range must be 'auto', None or (min, max), got {ratio_range!r}")
        ratio_range = SEMI_AXIS_RATIO_RANGE
    if ratio_range is not None:
        lo, hi = (float(v) for v in ratio_range)
        if not 0.0 < lo <= 1.0 <= hi:
            raise ValueError(f"semi_axis_ratio_range = {semi_axis_ratio_range!r}: expected 0 < min <= 1 <= max")
        ratio_range = (lo, hi)
    r0 = contact.pair.r0_m
    tol_f = 1e-6 * load if tol_force_N is None else _finite("tol_force_N", tol_force_N, positive=True)
    tol_m = 1e-6 * load * r0 if tol_moment_Nm is None else _finite("tol_moment_Nm", tol_moment_Nm, positive=True)
    free = pitch_rate_rad_s is None

    evaluate = _Evaluator(contact, y, yaw, load, speed, creep_law, mu, G, nu, float(v_min_m_s), ratio_range)
    z, roll = _initial_guess(contact, y, load, z0_m, roll0_rad)
    if free:
        # kinematic start: rolling on the mean radius of the touching points
        out = contact.evaluate(np.array([[y, z, roll]]))
        radii = [out[w, r, K.F_ROLLING_RADIUS] for w in (0, 1) for r in (0, 1) if out[w, r, K.F_STATUS] > 0]
        r_mean = float(np.mean(radii)) if radii else r0
        pitch = -speed * math.cos(yaw) / r_mean
    else:
        pitch = _finite("pitch_rate_rad_s", pitch_rate_rad_s)
    n_unknowns = 3 if free else 2
    x = np.array([z, roll, pitch])
    scale = np.array([load, load, load * r0])                 # residual scaling for the merit function
    steps = np.array([1e-8, 1e-8, 1e-7 * abs(pitch) + 1e-9])    # forward-difference steps
    max_step = np.array([2e-4, 5e-4, 0.02 * abs(pitch) + 1e-6])

    def residual(v):
        r, _, _ = evaluate(v[0], v[1], v[2])
        return r[:n_unknowns]

    res = residual(x)
    converged = False
    message = ""
    it = 0
    for it in range(1, max_iter + 1):
        if abs(res[0]) <= tol_f and abs(res[1]) <= tol_f and (not free or abs(res[2]) <= tol_m):
            converged = True
            it -= 1
            break
        jac = np.empty((n_unknowns, n_unknowns))
        for j in range(n_unknowns):
            xp = x.copy()
            xp[j] += steps[j]
            jac[:, j] = (residual(xp) - res) / steps[j]
        try:
            dx = np.linalg.solve(jac, -res)
        except np.linalg.LinAlgError:
            dx = np.linalg.lstsq(jac, -res, rcond=None)[0]
        limit = np.max(np.abs(dx) / max_step[:n_unknowns])
        if limit > 1.0:
            dx /= limit
        merit = np.sum((res / scale[:n_unknowns]) ** 2)
        alpha = 1.0
        while True:
            trial = x.copy()
            trial[:n_unknowns] += alpha * dx
            res_trial = residual(trial)
            if np.sum((res_trial / scale[:n_unknowns]) ** 2) < (1.0 - 1e-4 * alpha) * merit or alpha < 1.0 / 64:
                break
            alpha *= 0.5
        x, res = trial, res_trial
    else:
        converged = abs(res[0]) <= tol_f and abs(res[1]) <= tol_f and (not free or abs(res[2]) <= tol_m)
    if not converged:
        message = (f"no convergence after {max_iter} Newton iterations: load residuals {res[0]:.3g}, {res[1]:.3g} N"
                   + (f", axle moment {res[2]:.3g} N m" if free else ""))
    full, points, _ = evaluate(x[0], x[1], x[2], detail=True)
    return QuasiStaticResult(
        y_m=y, yaw_rad=yaw, wheel_load_N=load, speed_m_s=speed, z_m=float(x[0]), roll_rad=float(x[1]),
        pitch_rate_rad_s=float(x[2]), points=points, converged=bool(converged), iterations=it,
        evaluations=evaluate.count, residual_load_N=full[:2].copy(), residual_moment_Nm=float(full[2]),
        free_rolling=free, message=message)
