r"""The linearised vehicle on straight rigid track: the model of the ``run`` command at speed V, its centred running
state, the state matrix of its linearisation about that state and the modes (:func:`linear_modes`).

Model and operating point
-------------------------
The model is the one a scenario builds (:func:`~.build.build_scenario`): the vehicle file's bodies and suspension
(bump stops included, inactive inside their clearance), the wheel–rail connector with the vehicle's profiles,
Hertz and the default creep law (the table of Kalker's exact theory), perfect straight rigid track, the frame
translating with V.  The vehicle starts in static equilibrium on the rails (wheelsets spinning at V/r0) and runs
:data:`~.critical_speed_defaults.SETTLE_DURATION_S` on the perfect track: the longitudinal creep forces bring each
wheelset's spin to the rolling speed of its actual contact radius and the longitudinal restraint settles.  The
state at the end is the operating point (symmetric: no lateral motion arises on perfect track); the largest
remaining acceleration is reported (``residual_acceleration``).

Linearisation
-------------
Coordinates: per rigid body the displacement ``(x, y, z)`` in the track frame and a small rotation ``(θx, θy, θz)``
about the track axes (roll, pitch/spin, yaw), ``R = exp(θ̃) R0``; their rates are the perturbation variables.  The
Exudyn node of a body (a Lie-group rotation-vector node) carries the rotation vector and the body-frame angular
velocity; a perturbation ``(u, u̇)`` sets ``R = exp(θ̃) R0`` and ``ω = θ̇ + exp(θ̃) ω0`` (ω0 the operating point's
angular velocity in the track frame, the wheelsets' spin), and the accelerations Exudyn computes (its system
right-hand side and mass matrix, every force element and the connector evaluated as in a time step) give
``θ̈ = R ω̇_body − θ̇ × ω0``.  The spin thereby enters exactly: gyroscopic coupling of roll and yaw, the spin
creepage of the yawed, rolled wheelset.  Other nodes (modal coordinates) are perturbed additively.  The Jacobian
``A = ∂(u̇, ü)/∂(u, u̇)`` is formed by central differences (steps in :mod:`.critical_speed_defaults`), the
contact's warm start restored before every evaluation.  What the linearisation contains, by construction the full
model's: the real profiles' contact geometry and its derivatives at the centred position (not an equivalent
conicity), Hertz, the creep law's tangent at the operating point's creepages (zero lateral creepage, the small
longitudinal one of rolling and the spin creepage of the contact angle, sin γ / r0 per wheel — whose partial slip
lowers the tangent of Kalker's exact theory and of FASTSIM below Kalker's linear coefficients: on S1002/UIC60 1:40
at the centre, γ = 0.024 rad, by 10 % longitudinally and 5 % laterally), the gravitational stiffness and the spin
creepage terms of the contact geometry, the suspension, gravity.

Checked against the classical reduced models (tests/test_critical_speed_linearisation.py): a free wheelset's
kinematic frequency, the rigid bogie's kinematic wavelength and the restrained wheelset's characteristic polynomial,
with the rigid geometry's conicity and roll per shift and Kalker's coefficients of the operating point's ellipse.
"""
from __future__ import annotations

import time
from pathlib import Path

import exudyn as exu
import numpy as np
from scipy.spatial.transform import Rotation

from ..analysis.stability import modes_of
from .build import build_scenario
from .critical_speed_defaults import (ANGULAR_VELOCITY_STEP_RAD_S, LATERAL_SHARE_MIN, POSITION_STEP_M,
                                      RIGID_MODE_MAGNITUDE_1_S, ROTATION_STEP_RAD, SETTLE_DT_S, SETTLE_DURATION_S,
                                      SETTLE_SOLVER, VELOCITY_STEP_M_S)
from .run import run_model

__all__ = ["COORDINATE_NAMES", "LATERAL_COORDINATES", "vehicle_entry", "settled_scenario", "linearise",
           "OperatingPoint", "operating_point",
           "linear_modes", "lateral_share", "LinearisationError"]

#: the six coordinates of a rigid body (track frame: x forward, y right, z down; small rotations about them)
COORDINATE_NAMES = ("x", "y", "z", "roll", "pitch", "yaw")
#: the lateral coordinates (a hunting mode's): lateral displacement, roll, yaw
LATERAL_COORDINATES = ("y", "roll", "yaw")
_RIGID_NODE = "RigidBodyRotVecLG"


class LinearisationError(RuntimeError):
    """The model cannot be linearised (e.g. algebraic constraints, a settling run that did not end ``ok``)."""


def vehicle_entry(vehicle: str) -> dict:
    """The scenario's ``[vehicle]`` source of a vehicle name or file: ``{"file": path}`` for an existing file,
    else ``{"name": vehicle}`` (a shipped vehicle)."""
    p = Path(vehicle)
    return {"file": str(p.resolve())} if p.suffix == ".toml" or p.is_file() else {"name": vehicle}


def settled_scenario(vehicle: str, speed_kmh: float, duration_s: float = SETTLE_DURATION_S, track=None,
                     record: bool = False) -> dict:
    """The scenario of the vehicle at ``speed_kmh`` on straight rigid track (``track``: its irregularity
    components; default none) for ``duration_s``, the settling run's integrator and step."""
    return {"schema_version": 2, "scenario": {"name": "critical_speed"},
            "vehicle": {**vehicle_entry(vehicle), "speed_km_h": float(speed_kmh)},
            "track": list(track or []),
            "run": {"duration_s": float(duration_s), "solver": SETTLE_SOLVER, "dt_s": SETTLE_DT_S,
                    "record": bool(record)},
            "outputs": {"timeseries": ["wheelset_lateral"], "plots": False, "criteria": False}}


def _body_coordinates(h):
    """``(labels, rigid)``: a label ``"<body> <coordinate>"`` per ODE2 coordinate and, per rigid body, its first
    coordinate's index."""
    mbs = h.mbs
    n = len(mbs.systemData.GetODE2Coordinates())
    labels = [f"coordinate {i}" for i in range(n)]
    names = {int(b.node): b.name for b in h.model.bodies} if h.model is not None else {}
    rigid = []
    for node in range(mbs.systemData.NumberOfNodes()):
        if str(mbs.GetNode(node)["nodeType"]) != _RIGID_NODE:
            continue
        k = mbs.GetNodeODE2Index(node)
        rigid.append(k)
        for c, name in enumerate(COORDINATE_NAMES):
            labels[k + c] = f"{names.get(node, f'node{node}')} {name}"
    return labels, rigid


class OperatingPoint:
    """The operating point's node coordinates ``q0``, velocities ``v0`` and the first coordinate of every rigid body
    (``rigid``); :meth:`perturbed` maps a perturbation in track-frame coordinates to node coordinates (module
    docstring)."""

    def __init__(self, q0, v0, rigid):
        self.q0 = np.asarray(q0, dtype=float)
        self.v0 = np.asarray(v0, dtype=float)
        self.rigid = list(rigid)
        self.R0 = {k: Rotation.from_rotvec(self.q0[k + 3:k + 6]) for k in self.rigid}
        self.w0 = {k: self.R0[k].apply(self.v0[k + 3:k + 6]) for k in self.rigid}     # angular velocity, track frame

    def perturbed(self, u, ud):
        """``(q, v, rotations)``: the node coordinates and velocities of the perturbation ``u`` (displacements, small
        rotations about the track axes) with rates ``ud``, and every rigid body's rotation (by first coordinate)."""
        q, v = self.q0 + u, self.v0 + ud
        rot = {}
        for k in self.rigid:
            dR = Rotation.from_rotvec(u[k + 3:k + 6])
            rot[k] = dR * self.R0[k]
            q[k + 3:k + 6] = rot[k].as_rotvec()
            v[k + 3:k + 6] = rot[k].inv().apply(ud[k + 3:k + 6] + dR.apply(self.w0[k]))
        return q, v, rot


def operating_point(h) -> OperatingPoint:
    """The :class:`OperatingPoint` of a built model at its current state."""
    cfg = exu.ConfigurationType.Current
    sd = h.mbs.systemData
    return OperatingPoint(sd.GetODE2Coordinates(configuration=cfg), sd.GetODE2Coordinates_t(configuration=cfg),
                          _body_coordinates(h)[1])


def linearise(h) -> tuple[np.ndarray, list, np.ndarray]:
    """``(A, labels, a0)`` of a built and run model (:class:`~.build.ScenarioModel`) at its current state: the
    state matrix of the perturbation ``[u, u̇]`` (module docstring), a label per displacement coordinate and the
    accelerations at the state itself (the operating point's residual)."""
    mbs, sd = h.mbs, h.mbs.systemData
    cfg = exu.ConfigurationType.Current
    q0 = np.array(sd.GetODE2Coordinates(configuration=cfg))
    v0 = np.array(sd.GetODE2Coordinates_t(configuration=cfg))
    labels, rigid = _body_coordinates(h)
    n = len(q0)
    warm = h.contact.save_warm_start() if h.contact is not None else None    # before the solver's own calls
    solver = exu.MainSolverStatic()
    solver.InitializeSolver(mbs, _quiet_settings())      # (sets the current state to the initial one)
    if solver.GetAEsize() or solver.GetODE1size():
        raise LinearisationError("the model has algebraic or first-order coordinates: the linearisation takes "
                                 "second-order coordinates only (a 'spring' longitudinal restraint)")
    sd.SetODE2Coordinates(q0, configuration=cfg)
    sd.SetODE2Coordinates_t(v0, configuration=cfg)
    solver.ComputeMassMatrix(mbs)
    mass = np.array(solver.GetSystemMassMatrix())[:n, :n]
    state = OperatingPoint(q0, v0, rigid)

    def accelerations(u, ud):
        q, v, rot = state.perturbed(u, ud)
        if warm is not None:
            h.contact.restore_warm_start(warm)
        sd.SetODE2Coordinates(q, configuration=cfg)
        sd.SetODE2Coordinates_t(v, configuration=cfg)
        solver.ComputeODE2RHS(mbs)
        a = np.linalg.solve(mass, np.array(solver.GetSystemResidual())[:n])
        for k in rigid:
            a[k + 3:k + 6] = rot[k].apply(a[k + 3:k + 6]) - np.cross(ud[k + 3:k + 6], state.w0[k])
        return a

    steps_q = np.full(n, POSITION_STEP_M)
    steps_v = np.full(n, VELOCITY_STEP_M_S)
    for k in rigid:
        steps_q[k + 3:k + 6] = ROTATION_STEP_RAD
        steps_v[k + 3:k + 6] = ANGULAR_VELOCITY_STEP_RAD_S
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    zero = np.zeros(n)
    try:
        for j in range(n):
            e = np.zeros(n)
            e[j] = steps_q[j]
            A[n:, j] = (accelerations(e, zero) - accelerations(-e, zero)) / (2.0 * steps_q[j])
            e = np.zeros(n)
            e[j] = steps_v[j]
            A[n:, n + j] = (accelerations(zero, e) - accelerations(zero, -e)) / (2.0 * steps_v[j])
        a0 = accelerations(zero, zero)
    finally:
        if warm is not None:
            h.contact.restore_warm_start(warm)
        sd.SetODE2Coordinates(q0, configuration=cfg)
        sd.SetODE2Coordinates_t(v0, configuration=cfg)
    return A, labels, a0


def _quiet_settings():
    """Exudyn settings of the evaluations: no console output, no solution or sensor files."""
    s = exu.SimulationSettings()
    s.staticSolver.verboseMode = 0
    s.solution.file.write = False
    s.solution.sensors.active = False
    return s


def lateral_share(shapes, labels) -> np.ndarray:
    """Per mode (column of ``shapes``), the share of its squared displacement amplitude in the lateral
    coordinates (:data:`LATERAL_COORDINATES`) of the rigid bodies."""
    lat = np.array([lab.rsplit(" ", 1)[-1] in LATERAL_COORDINATES for lab in labels])
    p = np.abs(np.asarray(shapes)) ** 2
    tot = p.sum(axis=0)
    return p[lat].sum(axis=0) / np.where(tot > 0.0, tot, 1.0)


def linear_modes(vehicle: str, speed_kmh: float, settle_s: float = SETTLE_DURATION_S) -> dict:
    """Build the vehicle at ``speed_kmh`` on perfect straight track, settle, linearise (module docstring); returns a
    plain (picklable) dict: ``speed_kmh``, ``eigenvalues`` (complex array), ``shapes`` (displacement parts),
    ``labels``, ``lateral_share``, ``candidate`` (a lateral oscillating mode: lateral share at least
    :data:`~.critical_speed_defaults.LATERAL_SHARE_MIN`, not a rigid-body mode), ``residual_acceleration``
    (largest |acceleration| at the operating point, m/s² or rad/s²), ``settle_status`` and ``seconds``."""
    t0 = time.perf_counter()
    h = build_scenario(settled_scenario(vehicle, speed_kmh, settle_s))
    outcome = run_model(h, progress=False)
    if outcome.status.kind != "ok":
        raise LinearisationError(f"the settling run at {speed_kmh:g} km/h ended {outcome.status.kind}")
    A, labels, a0 = linearise(h)
    modes = modes_of(A)
    share = lateral_share(modes.shapes, labels)
    candidate = ((share >= LATERAL_SHARE_MIN) & (np.abs(modes.eigenvalues) > RIGID_MODE_MAGNITUDE_1_S)
                 & (modes.eigenvalues.imag > 0.0))
    return {"speed_kmh": float(speed_kmh), "eigenvalues": modes.eigenvalues, "shapes": modes.shapes,
            "labels": labels, "lateral_share": share, "candidate": candidate,
            "residual_acceleration": float(np.max(np.abs(a0))), "settle_status": outcome.status.kind,
            "seconds": time.perf_counter() - t0}
