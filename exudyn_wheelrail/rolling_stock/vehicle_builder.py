"""Exudyn model of a railway vehicle from :class:`~exudyn_wheelrail.rolling_stock.vehicle_data.VehicleData`.

:func:`build_vehicle` adds to an Exudyn ``MainSystem`` the rigid bodies (wheelsets, bogie frames, car body), the
suspensions, gravity, a longitudinal restraint and — optionally — linear springs in place of the wheel–rail
contact, and returns a :class:`VehicleModel` handle with everything a contact connector or a user script needs
(node/body/marker numbers, nominal positions, the spin speed, the track distance of a point).

Frame of the model ("simulation frame")
---------------------------------------
The track frame of :mod:`exudyn_wheelrail.conventions` (x forward, y right, z **down**, origin on the centre line
at rail-top height) **translating with the constant running speed V**.  Its origin is at the vehicle centre
(mid-point between the bogie centres; the wheelset/bogie centre for the smaller layouts) at t = 0 and moves
with it, so a point at simulation-frame x is at track distance ``s = s_start + V t + x``.  Gravity is
``(0, 0, +g)`` (mass-proportional loads on every body).

Longitudinal motion — design
----------------------------
The RTRI case is a roller rig: the car is held longitudinally and the rollers (the rails) move under it at the
running speed.  A frame translating with the constant speed V is inertial (Galilean), so Newton's laws hold in it
unchanged and the two pictures are the same model:

* bodies carry **no** forward velocity; the rails' material moves at ``(-V, 0, 0)`` and their geometry under a
  wheel at x is the track (irregularity) at ``s = s_start + V t + x`` (:meth:`VehicleModel.track_distance_m`);
* each wheelset spins about its axle with ``ω_y = -V/r0`` (rolling forward: with z down and y right, a negative
  rotation about +y moves the wheel top forward and leaves the contact point at rest relative to the rail).
  The spin is a real rotation degree of freedom of a Lie-group rigid node (``NodeType.RotationRotationVector``;
  the node's rotation vector stays bounded while the angle accumulates hundreds of radians);
* a **longitudinal restraint** holds the top body (car body / bogie frame / wheelset, by layout) at its place in
  the moving frame.  It carries only the resultant longitudinal creep force (rolling resistance), i.e. the
  force the rig's holding link carries.  Options (:class:`LongitudinalRestraint`):
  ``"spring"`` (default): a soft x-spring–damper from the moving frame to the top body's CG, tuned by default to
  0.5 Hz for the whole vehicle mass, critically damped — far below the contact and suspension frequencies, works
  with explicit and implicit solvers; ``"rigid"``: the body's x coordinate is fixed by a coordinate constraint
  (implicit solvers; explicit solvers eliminate it); ``"none"``: nothing (the creep forces alone keep the vehicle
  in place).
  The speed itself is imposed by the moving frame and the initial spin; the contact's longitudinal creep forces
  keep the spin at rolling speed.

Suspension elements
-------------------
* primary, per axlebox: a Cartesian (x, y, z in the track frame) spring–damper between the wheelset's axle point
  ``(0, ±b1, 0)`` (on the spin axis, so the spin does not move it) and the bogie frame point that coincides with
  it at the nominal position — the elements act at axle-centre height;
* secondary, per bogie side: a Cartesian spring–damper between bogie frame and car body at ``(x_bogie, ±b2,
  -h_secondary)``; the secondary yaw stiffness and the anti-roll bar are one rigid-body spring (rotational
  stiffness about z and x only) between bogie frame and car body;
* lateral bump stop, per bogie: a Cartesian element acting in y between car body and bogie frame at the bogie
  centre, secondary height, with the nonlinear force of the data (:class:`~.vehicle_data.BumpStopData`) given
  as an Exudyn **symbolic user function** (evaluated in C++; a sum of ramps reproduces the table exactly).
  ``bump_stop="python"`` uses a Python user function instead; ``"none"`` leaves the bump stops out.
  Cost, Manchester vehicle with rail springs, best of 3 runs of 2 s (Exudyn 1.13.6, one core): generalized-α at
  1 ms 80 µs/step without bump stops, 109 with the symbolic ones, 136 with the Python ones; RK44 at 0.25 ms 114,
  157 and 169 µs/step.  Exudyn has no native nonlinear-table spring: its limit stops (CoordinateSpringDamperExt)
  are linear and need a data node and post-Newton switching; the symbolic function's cost is mostly the call
  (a trivial symbolic function costs the same, about 2 µs per evaluation).
* preload: with ``preload=True`` (default) every vertical element carries, at the nominal geometry, the force of
  the static load path (lever rule: car body to bogies to axleboxes to wheels), so a symmetric vehicle starts in
  equilibrium (the CG heights of the data are those of the loaded vehicle).  Equilibrium itself does not depend
  on it (the load path is statically determinate up to the car body's warp, which the preload leaves at zero).

Wheel–rail coupling
-------------------
``wheel_rail="none"`` (default): nothing — the place of the contact connector, which gets the wheelset nodes,
bodies, markers and nominal positions from :class:`WheelsetHandle`.  What a contact connector needs to know about
the frame: the rail *material* moves with ``(-V, 0, 0)``; the rail *geometry* under a wheel whose axle is at
simulation-frame x is the track displaced by the irregularity (:mod:`exudyn_wheelrail.track.rigid`) at ``s = track_distance_m(x, t)``,
so a fixed point of the frame sees the rail move laterally with ``V·dy/ds`` and the rail axis has the direction
``(1, dy/ds, dz/ds)``.  Forces go on the wheelset node (``WheelsetHandle.marker_node``: LoadForceVector and
LoadTorqueVector, or a connector between ``VehicleModel.ground_marker`` and it).
``wheel_rail="springs"``: each wheel–rail contact is replaced by a linear Cartesian spring–damper (x, y, z) from
the wheel's tape-circle point **on the axle axis** ``(0, ±b_c, 0)`` to the rigid rail at the same nominal point,
preloaded with the static wheel load.  Because the wheelset end lies on the spin axis the springs exert no
moment about it: the spin is free (no creep), the x springs are the longitudinal restraint of the wheelsets.
Their lateral and longitudinal forces act at axle height (a real contact force acts at rail level, r0 lower):
a stand-in for tests and benchmarks, not a contact model.  Defaults: :class:`RailSprings`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (
    MarkerBodyPosition,
    MarkerBodyRigid,
    MarkerNodeRigid,
    ObjectConnectorCartesianSpringDamper,
    ObjectConnectorRigidBodySpringDamper,
)
from exudyn.rigidBodyUtilities import RigidBodyInertia

from ..contact.normal import E_STEEL, G_STEEL, NU_STEEL, effective_modulus, hertz_from_force
from ..creep.linear import kalker_coefficients
from .body_handle import BodyHandle
from .flexible_body import add_vehicle_car_body
from .vehicle_data import BumpStopData, VehicleData, load_vehicle

__all__ = [
    "GRAVITY_M_S2",
    "SIDES",
    "RailSprings",
    "LongitudinalRestraint",
    "BodyHandle",
    "WheelsetHandle",
    "VehicleModel",
    "StaticLoadPath",
    "static_load_path",
    "build_vehicle",
]

GRAVITY_M_S2 = 9.81  #: standard gravity used by default [m/s²]
SIDES = ("left", "right")  #: order of the two sides in every per-side array; y = -b (left), +b (right)
_SIDE_SIGN = (-1.0, 1.0)


# ------------------------------------------------------------------------------------------------ parameters
@dataclass(frozen=True)
class RailSprings:
    """Linear springs replacing one wheel–rail contact (``wheel_rail="springs"``), per wheel.

    Defaults = :meth:`from_hertz` at its defaults (rounded to three digits; ``tests/test_vehicle_builder.py``
    recomputes them): S1002 on UIC60 1:40, centred wheelset, wheel load 50 kN, steel (E = 210 GPa, ν = 0.28):

    * vertical: the linearised Hertz stiffness dN/dδ = 1.5 N/δ at N = 50 kN, δ = 51.0 µm from
      :func:`exudyn_wheelrail.contact.normal.hertz_from_force` with A = 1/(2 r0) (r0 = 0.46 m, straight rail) and
      B = (κ_wheel + 1/R_rail)/2, κ_wheel = -2.576 1/m (S1002 near the tape circle, from the profile) and
      R_rail = 0.300 m (UIC60 crown): **1.47e9 N/m**;
    * lateral and longitudinal: the tangential (no-slip) stiffness of the same contact patch, Mindlin's
      4 G c/(2 - ν) for elastically similar bodies (Johnson 1985, §7.2) with c = √(ab) = 6.26 mm: **1.19e9 N/m**;
    * vertical damping: 5 % of critical for half a Manchester wheelset (906.5 kg) on the vertical spring:
      **1.15e5 N s/m**;
    * lateral/longitudinal damping: Kalker's linear creep coefficient over a reference speed of 30 m/s,
      f22/V = G c² C22/V and f11/V = G c² C11/V (C from :func:`exudyn_wheelrail.creep.kalker_coefficients`):
      **3.24e5 and 4.00e5 N s/m** — creep acts on a rolling wheel like a damper of this size.
    """

    k_vertical_N_per_m: float = 1.47e9
    k_lateral_N_per_m: float = 1.19e9
    k_longitudinal_N_per_m: float = 1.19e9
    c_vertical_N_s_per_m: float = 1.15e5
    c_lateral_N_s_per_m: float = 3.24e5
    c_longitudinal_N_s_per_m: float = 4.00e5

    @classmethod
    def from_hertz(cls, wheel_load_N: float = 50e3, speed_m_s: float = 30.0, r0_m: float = 0.46,
                   wheel_lateral_curvature_1_m: float = -2.576, rail_crown_radius_m: float = 0.300,
                   damping_ratio: float = 0.05, wheel_mass_kg: float = 906.5) -> "RailSprings":
        """Springs from the project's Hertz and linear-creep implementations (see the class docstring)."""

        A = 0.5 / r0_m
        B = 0.5 * (wheel_lateral_curvature_1_m + 1.0 / rail_crown_radius_m)
        e_star = float(effective_modulus(E_STEEL, NU_STEEL, E_STEEL, NU_STEEL))
        delta, a, b, _status = hertz_from_force(A, B, e_star, wheel_load_N)
        k_v = 1.5 * wheel_load_N / delta
        c2 = a * b
        k_t = 4.0 * G_STEEL * math.sqrt(c2) / (2.0 - NU_STEEL)
        c11, c22, _c23 = kalker_coefficients(a / b, NU_STEEL)
        return cls(k_vertical_N_per_m=k_v, k_lateral_N_per_m=k_t, k_longitudinal_N_per_m=k_t,
                   c_vertical_N_s_per_m=2.0 * damping_ratio * math.sqrt(k_v * wheel_mass_kg),
                   c_lateral_N_s_per_m=G_STEEL * c2 * c22 / speed_m_s,
                   c_longitudinal_N_s_per_m=G_STEEL * c2 * c11 / speed_m_s)


@dataclass(frozen=True)
class LongitudinalRestraint:
    """How the top body (car body / bogie frame / wheelset) is held in the moving frame (see module docstring).

    ``kind``: ``"spring"``, ``"rigid"`` or ``"none"``.  For ``"spring"`` the stiffness and damping follow from
    the whole vehicle mass M: k = M (2π f)², c = 2 ζ √(k M); or give them directly (``stiffness_N_per_m`` and
    ``damping_N_s_per_m`` override)."""

    kind: str = "spring"
    frequency_Hz: float = 0.5
    damping_ratio: float = 1.0
    stiffness_N_per_m: float | None = None
    damping_N_s_per_m: float | None = None

    def parameters(self, mass_kg: float) -> tuple[float, float]:
        k = self.stiffness_N_per_m if self.stiffness_N_per_m is not None else mass_kg * (2 * math.pi *
                                                                                         self.frequency_Hz) ** 2
        c = (self.damping_N_s_per_m if self.damping_N_s_per_m is not None
             else 2.0 * self.damping_ratio * math.sqrt(k * mass_kg))
        return k, c


# --------------------------------------------------------------------------------------------------- handles
@dataclass
class WheelsetHandle(BodyHandle):
    """A wheelset: CG = axle centre; spin about the body y axis."""

    index: int = 0
    bogie: int | None = None           #: index into :attr:`VehicleModel.bogies`
    r0_m: float = 0.0
    spin_rad_s: float = 0.0            #: initial ω_y = -V/r0 (body and track y coincide at the nominal pose)
    contact_semi_spacing_m: float = 0.0  #: lateral distance of each tape circle from the axle centre


@dataclass(frozen=True)
class StaticLoadPath:
    """Static vertical forces (N, positive = weight carried) by the lever rule, used for the preloads.

    ``secondary[i, side]`` per bogie side, ``primary[j, side]`` per axlebox, ``wheel[j, side]`` per wheel
    (j = wheelset, front first; side order :data:`SIDES`)."""

    secondary: np.ndarray
    primary: np.ndarray
    wheel: np.ndarray


@dataclass
class VehicleModel:
    """What :func:`build_vehicle` created.  ``connectors`` maps a group name to its Exudyn objects:
    ``primary``, ``secondary``, ``secondary_rotational`` (yaw + anti-roll), ``bump_stop``, ``wheel_rail``
    (springs mode, wheelset-major, sides in :data:`SIDES` order), ``longitudinal``, ``guidance`` (bogie/wheelset
    layouts: the horizontal elements to the moving frame); ``loads`` holds the dead loads."""

    vehicle: VehicleData
    speed_m_s: float
    s_start_m: float
    gravity_m_s2: float
    wheel_rail: str
    ground: exu.ObjectIndex
    ground_marker: exu.MarkerIndex     #: MarkerBodyRigid on the ground at the origin
    wheelsets: list[WheelsetHandle]
    bogies: list[BodyHandle]
    car_body: BodyHandle | None
    connectors: dict[str, list] = field(default_factory=dict)
    loads: list = field(default_factory=list)
    load_path: StaticLoadPath | None = None
    rail_springs: RailSprings | None = None
    longitudinal: LongitudinalRestraint | None = None
    _keep_alive: list = field(default_factory=list, repr=False)  # symbolic user functions must outlive the model

    @property
    def bodies(self) -> list[BodyHandle]:
        """All bodies: car body, bogie frames, wheelsets."""
        return ([self.car_body] if self.car_body is not None else []) + list(self.bogies) + list(self.wheelsets)

    @property
    def wheelset_nodes(self) -> list:
        """Node numbers of the wheelsets, front first (what a contact connector takes)."""
        return [ws.node for ws in self.wheelsets]

    @property
    def top_body(self) -> BodyHandle:
        return self.car_body or (self.bogies[0] if self.bogies else self.wheelsets[0])

    def track_distance_m(self, x_in_frame_m, t_s: float = 0.0):
        """Track distance s of a point at simulation-frame x at time t: ``s_start + V t + x``."""
        return self.s_start_m + self.speed_m_s * t_s + np.asarray(x_in_frame_m, dtype=float)

    def wheel_rail_forces_N(self, mbs) -> np.ndarray:
        """Springs mode: force of each rail on its wheel in the simulation frame, shape (n_wheelsets, 2, 3)."""
        if self.wheel_rail != "springs":
            raise RuntimeError("wheel_rail_forces_N needs wheel_rail='springs'")
        # Exudyn's connector force f = k (p1 - p0 - offset) + d v acts as -f on marker 1 (the rail), +f on the wheel
        f = [np.asarray(mbs.GetObjectOutput(c, exu.OutputVariableType.Force)) for c in self.connectors["wheel_rail"]]
        return np.array(f).reshape(len(self.wheelsets), 2, 3)

    def wheel_loads_N(self, mbs) -> np.ndarray:
        """Springs mode: vertical wheel loads Q (N, positive = wheel pressing on the rail), (n_wheelsets, 2)."""
        return -self.wheel_rail_forces_N(mbs)[:, :, 2]


# ------------------------------------------------------------------------------------------- static loads
def static_load_path(vehicle: VehicleData, gravity_m_s2: float = GRAVITY_M_S2) -> StaticLoadPath:
    """Static vertical forces by the lever rule (see :class:`StaticLoadPath`).

    Car body weight to the two bogies by the longitudinal lever rule, to the two sides by the lateral one (the
    anti-roll bar carries no preload); each bogie's load and weight to its axleboxes (front/rear equally, the
    roll moment over the primary semi-spacing); each wheelset's load and weight to its wheels (over the
    tape-circle semi-spacing)."""
    g = gravity_m_s2
    geo = vehicle.geometry
    n_b, n_w = vehicle.n_bogies, vehicle.n_wheelsets
    secondary = np.zeros((n_b, 2))
    if vehicle.layout == "car":
        car = vehicle.car_body
        lb, b2 = geo.semi_bogie_centre_distance_m, geo.secondary_lateral_semi_spacing_m
        w = car.mass_kg * g
        for i, xb in enumerate(vehicle.bogie_x_m()):
            f_bogie = w * (lb + math.copysign(1.0, xb) * car.cg_x_m) / (2.0 * lb)
            for k, s in enumerate(_SIDE_SIGN):
                secondary[i, k] = f_bogie * (b2 + s * car.cg_y_m) / (2.0 * b2)
    elif vehicle.layout == "bogie":
        secondary[:] = vehicle.vertical_force_per_side_N
    primary = np.zeros((n_w, 2))
    if vehicle.layout == "wheelset":
        primary[:] = vehicle.vertical_force_per_side_N
    else:
        b1, b2 = geo.primary_lateral_semi_spacing_m, geo.secondary_lateral_semi_spacing_m
        for j, i in enumerate(vehicle.wheelset_bogie()):
            total = secondary[i].sum() + vehicle.bogie_frame.mass_kg * g
            moment = (secondary[i, 1] - secondary[i, 0]) * b2
            for k, s in enumerate(_SIDE_SIGN):
                primary[j, k] = 0.5 * (0.5 * total + s * moment / (2.0 * b1))
    b1, bc = geo.primary_lateral_semi_spacing_m, vehicle.tape_circle_semi_spacing_m()
    wheel = np.zeros((n_w, 2))
    for j in range(n_w):
        total = primary[j].sum() + vehicle.wheelset.mass_kg * g
        moment = (primary[j, 1] - primary[j, 0]) * b1
        for k, s in enumerate(_SIDE_SIGN):
            wheel[j, k] = 0.5 * total + s * moment / (2.0 * bc)
    return StaticLoadPath(secondary, primary, wheel)


# --------------------------------------------------------------------------------------------------- helpers
def _bump_stop_python(bump: BumpStopData):
    knots, dk = bump.ramps()
    knots, dk = [float(v) for v in knots], [float(v) for v in dk]

    def force(mbs, t, item, u, v, k, d, offset):
        a = abs(u[1])
        f = 0.0
        for ui, dki in zip(knots, dk):
            if a > ui:
                f += dki * (a - ui)
        return [0.0, math.copysign(f, u[1]) if f else 0.0, 0.0]

    return force


def _bump_stop_symbolic_source(bump: BumpStopData):
    esym = exu.symbolic
    knots, dk = bump.ramps()

    def force(mbs, t, item, u, v, k, d, offset):
        a = esym.abs(u[1])
        f = 0.0
        for ui, dki in zip(knots, dk):
            f = f + float(dki) * esym.max(a - float(ui), 0.0)
        return [0.0 * u[0], esym.sign(u[1]) * f, 0.0 * u[2]]

    return force


def _rotation_stiffness(k_roll: float, k_yaw: float) -> np.ndarray:
    k = np.zeros((6, 6))
    k[3, 3], k[5, 5] = k_roll, k_yaw
    return k


def build_vehicle(mbs, vehicle: VehicleData | str, *, speed_m_s: float = 0.0, wheel_rail: str = "none",
                  rail_springs: RailSprings | None = None,
                  longitudinal: LongitudinalRestraint | str | None = None, bump_stop: str = "symbolic",
                  preload: bool = True, gravity_m_s2: float = GRAVITY_M_S2, s_start_m: float = 0.0,
                  lock_spin: bool = False, show: bool = False, name_suffix: str = "",
                  x_offset_m: float = 0.0) -> VehicleModel:
    """Create the Exudyn model of ``vehicle`` in ``mbs`` (not assembled) and return its handle.

    Parameters
    ----------
    vehicle : a :class:`VehicleData` or a vehicle file / shipped name for :func:`load_vehicle`.
    speed_m_s : running speed V >= 0 (the frame moves with it; wheelsets spin at -V/r0 about y).
    wheel_rail : ``"none"`` (the contact connector is added by the caller) or ``"springs"`` (see module doc).
    rail_springs : spring parameters for ``"springs"``; default :class:`RailSprings`.
    longitudinal : a :class:`LongitudinalRestraint` or its kind (``"spring"``, ``"rigid"``, ``"none"``);
        default spring.
    bump_stop : ``"symbolic"`` (C++ symbolic user function), ``"python"`` (Python user function) or ``"none"``.
    preload : preload the vertical elements with the static load path (start near equilibrium).
    gravity_m_s2 : g, along +z.
    s_start_m : track distance of the frame origin at t = 0.
    lock_spin : fix every wheelset's spin coordinate by a coordinate constraint — for ``mbs.SolveStatic`` only
        (the spin has no stiffness, so the static Jacobian is singular without it); never for dynamics.
    show : draw the connectors in Exudyn's renderer.
    name_suffix : appended to the name of every named Exudyn item (bodies, nodes, connectors), so several vehicles
        can share one ``mbs`` (a train: :func:`~exudyn_wheelrail.rolling_stock.train.build_train`).
    x_offset_m : simulation-frame x of the vehicle centre (default 0: the frame origin); every body and suspension
        point is shifted by it, so the vehicle sits at track distance ``s_start + V t + x_offset`` at time t.
    """
    if not isinstance(vehicle, VehicleData):
        vehicle = load_vehicle(vehicle)
    if wheel_rail not in ("none", "springs"):
        raise ValueError(f"wheel_rail={wheel_rail!r}: expected 'none' or 'springs'")
    if bump_stop not in ("symbolic", "python", "none"):
        raise ValueError(f"bump_stop={bump_stop!r}: expected 'symbolic', 'python' or 'none'")
    if not (math.isfinite(speed_m_s) and speed_m_s >= 0.0):
        raise ValueError(f"speed_m_s = {speed_m_s!r}: expected a finite speed >= 0")
    if isinstance(longitudinal, str) or longitudinal is None:
        longitudinal = LongitudinalRestraint(kind=longitudinal or "spring")
    if longitudinal.kind not in ("spring", "rigid", "none"):
        raise ValueError(f"longitudinal kind {longitudinal.kind!r}: expected 'spring', 'rigid' or 'none'")
    rail_springs = rail_springs or RailSprings()
    if not math.isfinite(x_offset_m):
        raise ValueError(f"x_offset_m = {x_offset_m!r}: expected a finite distance")

    g = float(gravity_m_s2)
    geo = vehicle.geometry
    r0 = geo.r0_m
    path = static_load_path(vehicle, g) if preload else None
    ground = mbs.CreateGround()
    ground_marker = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localPosition=[0.0, 0.0, 0.0]))
    gravity = [0.0, 0.0, g]
    node_type = exu.NodeType.RotationRotationVector

    def rigid_body(name, data, p_cg, omega=(0.0, 0.0, 0.0)):
        name = name + name_suffix
        p_cg = (p_cg[0] + x_offset_m, p_cg[1], p_cg[2])
        inertia = RigidBodyInertia(mass=data.mass_kg, inertiaTensor=data.inertia_kg_m2)
        d = mbs.CreateRigidBody(name=name, inertia=inertia, referencePosition=list(map(float, p_cg)),
                                initialAngularVelocity=list(map(float, omega)), gravity=gravity,
                                nodeType=node_type, returnDict=True, show=show)
        body, node = d["bodyNumber"], d["nodeNumber"]
        marker = mbs.AddMarker(MarkerBodyRigid(bodyNumber=body, localPosition=[0.0, 0.0, 0.0]))
        marker_node = mbs.AddMarker(MarkerNodeRigid(nodeNumber=node))
        return dict(name=name, node=node, body=body, marker=marker, marker_node=marker_node,
                    p_cg_in_frame=np.asarray(p_cg, dtype=float), mass_kg=data.mass_kg)

    def point(handle, p_in_frame):
        local = np.asarray(p_in_frame, dtype=float) - handle.p_cg_in_frame
        if hasattr(handle, "position_marker"):          # the flexible car body: a marker on its mesh point
            return handle.position_marker(mbs, local)
        return mbs.AddMarker(MarkerBodyPosition(bodyNumber=handle.body, localPosition=list(map(float, local))))

    def ground_point(p_in_frame):
        return mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=list(map(float, p_in_frame))))

    def cartesian(name, m_upper, m_lower, k, c, force_on_lower_z=0.0, user_function=0):
        """Spring–damper upper -> lower; at the nominal pose it pushes the lower body down with the given force."""
        name = name + name_suffix
        k = [float(v) for v in k]
        offset = [0.0, 0.0, 0.0]
        if force_on_lower_z:
            if not k[2] > 0.0:
                raise ValueError(f"{name}: a preload needs a vertical stiffness")
            offset[2] = force_on_lower_z / k[2]  # force on marker 1 = -k (Δp - offset) = k·offset at Δp = 0
        return mbs.AddObject(ObjectConnectorCartesianSpringDamper(
            name=name, markerNumbers=[m_upper, m_lower], stiffness=k, damping=[float(v) for v in c], offset=offset,
            springForceUserFunction=user_function, visualization={"show": show, "drawSize": -1.0,
                                                                   "color": [-1.0, -1.0, -1.0, -1.0]}))

    connectors: dict[str, list] = {key: [] for key in ("primary", "secondary", "secondary_rotational", "bump_stop",
                                                       "wheel_rail", "longitudinal", "guidance")}
    loads: list = []
    keep: list = []

    # ---- bodies
    car = None
    if vehicle.layout == "car":
        cb = vehicle.car_body
        if cb.flexible is None:
            car = BodyHandle(**rigid_body("car_body", cb, (cb.cg_x_m, cb.cg_y_m, -cb.cg_height_m)))
        else:                                           # floating frame of reference body (flexible_body.py)
            car = add_vehicle_car_body(mbs, vehicle, (cb.cg_x_m + x_offset_m, cb.cg_y_m, -cb.cg_height_m),
                                       gravity=gravity, name="car_body" + name_suffix,
                                       preload_N=path.secondary if path is not None else None)
    bogies = []
    for i, xb in enumerate(vehicle.bogie_x_m()):
        bogies.append(BodyHandle(**rigid_body(f"bogie{i}", vehicle.bogie_frame,
                                              (xb, 0.0, -vehicle.bogie_frame.cg_height_m))))
    spin = -speed_m_s / r0
    bc = vehicle.tape_circle_semi_spacing_m()
    wheelsets = []
    for j, (xw, ib) in enumerate(zip(vehicle.wheelset_x_m(), vehicle.wheelset_bogie())):
        wheelsets.append(WheelsetHandle(**rigid_body(f"wheelset{j}", vehicle.wheelset, (xw, 0.0, -r0),
                                                     omega=(0.0, spin, 0.0)),
                                        index=j, bogie=ib, r0_m=r0, spin_rad_s=spin, contact_semi_spacing_m=bc))

    # ---- primary suspension (per axlebox) or the wheelset layout's guidance and dead load
    prim = vehicle.primary
    b1 = geo.primary_lateral_semi_spacing_m
    for ws in wheelsets:
        xw = ws.p_cg_in_frame[0]
        for k, s in enumerate(_SIDE_SIGN):
            p_box = (xw, s * b1, -r0)
            m_ws = point(ws, p_box)
            preload_z = path.primary[ws.index, k] if path is not None else 0.0
            if ws.bogie is not None:
                m_bogie = point(bogies[ws.bogie], p_box)
                connectors["primary"].append(cartesian(f"primary{ws.index}{SIDES[k][0]}", m_bogie, m_ws,
                                                       prim.stiffness_N_per_m, prim.damping_N_s_per_m, preload_z))
            else:
                kxy = (prim.stiffness_N_per_m[0], prim.stiffness_N_per_m[1], 0.0)
                cxy = (prim.damping_N_s_per_m[0], prim.damping_N_s_per_m[1], 0.0)
                if any(kxy) or any(cxy):
                    connectors["guidance"].append(cartesian(f"guidance{SIDES[k][0]}", ground_point(p_box), m_ws,
                                                            kxy, cxy))
                loads.append(mbs.AddLoad(exu.itemInterface.LoadForceVector(
                    markerNumber=m_ws, loadVector=[0.0, 0.0, vehicle.vertical_force_per_side_N])))

    # ---- secondary suspension (per bogie side), rotational springs, bump stops
    sec = vehicle.secondary
    if bogies:
        b2, hs = geo.secondary_lateral_semi_spacing_m, geo.secondary_spring_height_m
        for i, bg in enumerate(bogies):
            xb = bg.p_cg_in_frame[0]
            for k, s in enumerate(_SIDE_SIGN):
                p_spring = (xb, s * b2, -hs)
                m_bogie = point(bg, p_spring)
                if car is not None:
                    preload_z = path.secondary[i, k] if path is not None else 0.0
                    connectors["secondary"].append(cartesian(f"secondary{i}{SIDES[k][0]}", point(car, p_spring),
                                                             m_bogie, sec.stiffness_N_per_m, sec.damping_N_s_per_m,
                                                             preload_z))
                else:
                    kxy = (sec.stiffness_N_per_m[0], sec.stiffness_N_per_m[1], 0.0)
                    cxy = (sec.damping_N_s_per_m[0], sec.damping_N_s_per_m[1], 0.0)
                    if any(kxy) or any(cxy):
                        connectors["guidance"].append(cartesian(f"guidance{i}{SIDES[k][0]}", ground_point(p_spring),
                                                                m_bogie, kxy, cxy))
                    loads.append(mbs.AddLoad(exu.itemInterface.LoadForceVector(
                        markerNumber=m_bogie, loadVector=[0.0, 0.0, vehicle.vertical_force_per_side_N])))
            p_centre = (xb, 0.0, -hs)
            local_bogie = list(map(float, np.asarray(p_centre) - bg.p_cg_in_frame))
            m_bogie_rigid = mbs.AddMarker(MarkerBodyRigid(bodyNumber=bg.body, localPosition=local_bogie))
            if car is not None and hasattr(car, "rigid_marker"):    # the flexible car body's section there
                m_upper = car.rigid_marker(np.asarray(p_centre) - car.p_cg_in_frame)
            elif car is not None:
                m_upper = mbs.AddMarker(MarkerBodyRigid(bodyNumber=car.body, localPosition=list(map(
                    float, np.asarray(p_centre) - car.p_cg_in_frame))))
            else:
                m_upper = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localPosition=list(map(float, p_centre))))
            k_roll = sec.anti_roll_stiffness_N_m_per_rad if car is not None else 0.0
            if k_roll or sec.yaw_stiffness_N_m_per_rad:
                connectors["secondary_rotational"].append(mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
                    name=f"secondary_rot{i}{name_suffix}", markerNumbers=[m_upper, m_bogie_rigid],
                    stiffness=_rotation_stiffness(k_roll, sec.yaw_stiffness_N_m_per_rad).tolist(),
                    damping=np.zeros((6, 6)).tolist(), useIntrinsicFormulation=True,
                    visualization={"show": show, "drawSize": -1.0, "color": [-1.0, -1.0, -1.0, -1.0]})))
            if vehicle.bump_stop is not None and bump_stop != "none":
                m_up = point(car, p_centre) if car is not None else ground_point(p_centre)
                c = cartesian(f"bump_stop{i}", m_up, point(bg, p_centre), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
                if bump_stop == "python":
                    mbs.SetObjectParameter(c, "springForceUserFunction", _bump_stop_python(vehicle.bump_stop))
                else:
                    from exudyn.advancedUtilities import CreateSymbolicUserFunction
                    uf = CreateSymbolicUserFunction(mbs, _bump_stop_symbolic_source(vehicle.bump_stop),
                                                    "springForceUserFunction", c)
                    keep.append(uf)
                    mbs.SetObjectParameter(c, "springForceUserFunction", uf)
                connectors["bump_stop"].append(c)

    # ---- wheel-rail springs
    if wheel_rail == "springs":
        rs = rail_springs
        k = (rs.k_longitudinal_N_per_m, rs.k_lateral_N_per_m, rs.k_vertical_N_per_m)
        c = (rs.c_longitudinal_N_s_per_m, rs.c_lateral_N_s_per_m, rs.c_vertical_N_s_per_m)
        for ws in wheelsets:
            xw = ws.p_cg_in_frame[0]
            for kk, s in enumerate(_SIDE_SIGN):
                p_axle = (xw, s * bc, -r0)
                q = path.wheel[ws.index, kk] if path is not None else 0.0
                connectors["wheel_rail"].append(cartesian(f"wheel_rail{ws.index}{SIDES[kk][0]}", point(ws, p_axle),
                                                          ground_point(p_axle), k, c, q))

    # ---- longitudinal restraint of the top body
    model = VehicleModel(vehicle=vehicle, speed_m_s=float(speed_m_s), s_start_m=float(s_start_m), gravity_m_s2=g,
                         wheel_rail=wheel_rail, ground=ground, ground_marker=ground_marker, wheelsets=wheelsets,
                         bogies=bogies, car_body=car, connectors=connectors, loads=loads, load_path=path,
                         rail_springs=rail_springs if wheel_rail == "springs" else None, longitudinal=longitudinal,
                         _keep_alive=keep)
    top = model.top_body
    if longitudinal.kind == "spring":
        k_long, c_long = longitudinal.parameters(vehicle.total_mass_kg)
        connectors["longitudinal"].append(cartesian("longitudinal", ground_point(top.p_cg_in_frame),
                                                    point(top, top.p_cg_in_frame), (k_long, 0.0, 0.0),
                                                    (c_long, 0.0, 0.0)))
    elif longitudinal.kind == "rigid":
        connectors["longitudinal"].append(mbs.CreateCoordinateConstraint(
            name="longitudinal" + name_suffix, itemNumbers=[None, top.node], coordinates=[None, 0], show=show))
    if lock_spin:
        connectors["spin_lock"] = [mbs.CreateCoordinateConstraint(name=f"spin_lock{ws.index}{name_suffix}",
                                                                  itemNumbers=[None, ws.node], coordinates=[None, 4],
                                                                  show=show) for ws in wheelsets]
    return model
