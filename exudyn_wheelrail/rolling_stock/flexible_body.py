r"""The flexible car body in Exudyn: the beam or FE modes of :mod:`.car_body_model` (:mod:`.car_body_fe`) entered as a
floating-frame-of-reference body (``ObjectFFRFreducedOrder``, :func:`add_flexible_car_body`), the car body of a
vehicle (:func:`add_vehicle_car_body`, its handle :class:`FlexibleBodyHandle`) and the kinematics of points fixed
to it (:class:`BodyPointKinematics`).

Exudyn (:func:`add_flexible_car_body`)
--------------------------------------
``ObjectFFRFreducedOrder`` needs a mesh of *position* nodes.  A few beam sections carry three points each, ``h``
from the axis at 120° (above it, lower right, lower left: their centroid is on the axis) — the ends, the attachment
sections, :data:`DEFAULT_SECTIONS` stations and their mirror images (a section set symmetric about the middle) —
and every attachment point (suspension, bump stop) one more point on a rigid arm from the beam node at its x
(``u_P = u + θ × r_P``: the map ``T`` from nodal DOFs to point displacements).  With the generalized coordinates
``g`` = (the six rigid motions about the CG, the m modal coordinates), nodal DOFs ``G g`` and point displacements
``S g = T G g``, the point mass and stiffness matrices are ``Lᵀ (Gᵀ M G) L`` and ``Lᵀ (Gᵀ K G) L`` with the left
inverse ``L`` of ``S`` that uses the section points only (the arms carry no mass; the section rows of ``S`` must
have full column rank: the sections must resolve the modes), and the mode basis is ``T Φ``.  Every field Exudyn's
FEM tools contract with the point mass matrix that lies in the range of ``S`` — translations, rotations about the
frame origin, the modes — is therefore exact: the reduced matrices are ``I`` and ``diag(ω²)``, the rigid–elastic
coupling is zero, mass and inertia tensor are the beam's, and the centre of mass (the fit of the point positions;
set from the beam all the same) is on the axis at the CG.

The second-order terms of the FFRF (the rotated deformation fields ``e_i × ψ``: inertia change and Coriolis
coupling by deformation) are those of the point set; the rotated fields of off-axis points are not fields of the
beam and act, through ``L``, as a spurious coupling.  Measured (free body, yaw rate 0.3 rad/s, 1 s, RK44 and Newmark
alike, largest change of a modal amplitude against the non-rotating body): with the points on the axis, ``h``
above and ``h`` to the right (centroid off the axis) 280 % at ``h = 1 m``, 28 % at 0.1 m, 2.8 % at 1 cm, 0.3 % at
1 mm; with the symmetric layout above (centroid on the axis) and ``h = 1 cm``: 0.14 %, in the torsion modes (at
0.03 rad/s: 0.016 %) — the physical gyroscopic coupling, which the off-axis layout also reaches at 0.1 mm.  Offsets
below 1 cm cost precision (point-matrix entries ``I_p / h²``): at 1 mm the energy of a rolling free body drifts by
5e-6 in 0.5 s, at 1 cm by 5e-8.  Hence ``h = 1 cm`` (:data:`_POINT_OFFSET_M`).  The cost of the
FFRF object per evaluation grows with its mesh points and steeply with the number of modes
(``benchmarks/bench_flexible_car_body.py``, ``docs/validation.md``), hence the small point set.  The suspension
attaches with ``MarkerSuperElementPosition`` on its point and the rotational springs (yaw, anti-roll bar) with
``MarkerSuperElementRigid`` on the three points of the beam section (its rotation is the section's).

Reference-frame node and solvers: the frame is a ``NodeRigidBodyRotVecLG`` (``exu.NodeType.RotationRotationVector``,
the node of the other bodies) — Exudyn's explicit Lie-group Runge–Kutta solvers (RK44, the project's default)
integrate it, and so does the implicit Newmark/generalized-α solver.  (Exudyn's default FFRF node, Euler parameters,
carries an algebraic normalisation constraint that the explicit solvers refuse.)  An explicit solver's step must
resolve the highest kept mode (:func:`highest_mode_rad_s`: ω dt <= 2√2 for RK44; the RTRI case refuses a larger
step before it builds); the implicit Newmark rule is unconditionally stable for it.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass

import exudyn as exu
import numpy as np
import scipy.sparse as sp
from exudyn.FEM import FEMinterface, ObjectFFRFreducedOrderInterface
from exudyn.itemInterface import (MarkerNodePosition, MarkerNodeRigid, MarkerSuperElementPosition,
                                  MarkerSuperElementRigid)

from ..structures.beam import N_DOF_NODE
from .body_handle import BodyHandle
from .car_body_fe import modes_from_fe_file
from .car_body_model import (DEFAULT_ELEMENTS, CarBodyModes, beam_from_car_body, mesh_node, rigid_fields, skew,
                             skew_minus)

__all__ = [
    "DEFAULT_SECTIONS",
    "BodyPointKinematics",
    "car_body_modes",
    "add_vehicle_car_body",
    "highest_mode_rad_s",
    "FlexibleBodyHandle",
    "FlexibleCarBody",
    "add_flexible_car_body",
]

#: beam sections (besides the ends and the attachment points) that carry FFRF mesh points: the FFRF object's cost
#: per evaluation grows with its mesh points (benchmarks/bench_flexible_car_body.py), the reduced matrices are exact
#: for any section set that resolves the modes
DEFAULT_SECTIONS = 5
#: distance of a mesh section's three points from the beam axis [m]: small, so that the FFRF's second-order
#: (rotated-deformation) terms of the point set tend to the beam's, not so small that precision suffers (module
#: docstring)
_POINT_OFFSET_M = 1.0e-2


# ========================================================================================== Exudyn entry
@dataclass
class FlexibleCarBody:
    """What :func:`add_flexible_car_body` created.  ``node`` the reference-frame node (RotationRotationVector),
    ``modal_node`` the modal coordinates, ``body`` the ``ObjectFFRFreducedOrder``; ``point_markers`` maps an
    attachment point (body coordinates from the CG, rounded to µm) to its ``MarkerSuperElementPosition``;
    ``rigid_markers`` a beam node's x to its ``MarkerSuperElementRigid``."""

    modes: CarBodyModes
    node: object
    modal_node: object
    body: object
    points_m: np.ndarray
    point_markers: dict
    rigid_markers: dict
    mass_points: np.ndarray = None         #: the point mass matrix handed to Exudyn (3 n_points square, body axes)
    stiffness_points: np.ndarray = None    #: the point stiffness matrix

    def coordinates(self, mbs) -> tuple[np.ndarray, np.ndarray]:
        ovt = exu.OutputVariableType
        return (np.asarray(mbs.GetNodeOutput(self.modal_node, ovt.Coordinates)),
                np.asarray(mbs.GetNodeOutput(self.modal_node, ovt.Coordinates_t)))


def _key(r) -> tuple:
    return tuple(round(float(v), 6) for v in r)


def _sections(x: np.ndarray, required_x, n_sections: int) -> list[int]:
    """Beam nodes that carry FFRF mesh points: the ends, the nodes at ``required_x`` and the nodes nearest to
    ``n_sections`` equally spaced stations."""
    idx = {0, len(x) - 1}
    idx.update(int(np.argmin(np.abs(x - xr))) for xr in required_x)
    idx.update(int(np.argmin(np.abs(x - xs))) for xs in np.linspace(x[0], x[-1], n_sections))
    return sorted(idx)


def _symmetric(idx: list[int], x: np.ndarray) -> list[int]:
    """``idx`` with the mirror (about the body's middle) of every node that has one in the mesh."""
    mid = 0.5 * (x[0] + x[-1])
    out = set(idx)
    for i in idx:
        j = int(np.argmin(np.abs(x - (2.0 * mid - x[i]))))
        if abs(x[j] - (2.0 * mid - x[i])) < 1e-9:
            out.add(j)
    return sorted(out)


def add_flexible_car_body(mbs, modes: CarBodyModes, p_cg_in_frame, *, attach_points_m=(), gravity=(0.0, 0.0, 0.0),
                          rigid_marker_points_m=(), name: str = "car_body",
                          n_sections: int = DEFAULT_SECTIONS) -> FlexibleCarBody:
    """Add the FFRF car body (module docstring) with its reference frame at ``p_cg_in_frame`` (axes parallel to the
    simulation frame), a ``MarkerSuperElementPosition`` at every attachment point (body coordinates from the CG;
    beam: on a beam node's x; FE model: a mesh node) and a ``MarkerSuperElementRigid`` for every point of
    ``rigid_marker_points_m`` (keyed by its x: beam — the three points of the beam section there; FE model — the
    four mesh nodes nearest to the point, which must not be collinear)."""
    attach = np.asarray(attach_points_m, dtype=float).reshape(-1, 3)
    if modes.beam is not None:
        beam = modes.beam
        x = beam.mesh_x_m()
        M, K = beam.assemble()
        n = len(x)
        h = _POINT_OFFSET_M
        ang = np.radians([-90.0, 30.0, 150.0])     # above (z down), lower right, lower left: centroid on the axis
        offsets = np.column_stack([np.zeros(3), h * np.cos(ang), h * np.sin(ang)])
        required = np.r_[attach[:, 0], np.asarray(rigid_marker_points_m, dtype=float).reshape(-1, 3)[:, 0]]
        sections = _symmetric(_sections(x, required, n_sections), x)
        points = [np.array([x[i], 0.0, 0.0]) + o for i in sections for o in offsets]
        owner = [i for i in sections for _ in offsets]
        arm_of = {}
        for p in attach:
            i = int(np.argmin(np.abs(x - p[0])))
            if abs(x[i] - p[0]) > 1e-9:
                raise ValueError(f"attachment point {p.tolist()} m: x is not a beam node (mesh nodes: {x.round(4)})")
            arm_of[_key(p)] = len(points)
            points.append(np.array(p, dtype=float))
            owner.append(i)
        points = np.array(points)
        T = np.zeros((3 * len(points), N_DOF_NODE * n))
        for k, (p, i) in enumerate(zip(points, owner)):
            T[3 * k:3 * k + 3, N_DOF_NODE * i:N_DOF_NODE * i + 3] = np.eye(3)
            T[3 * k:3 * k + 3, N_DOF_NODE * i + 3:N_DOF_NODE * i + 6] = skew_minus(p - np.array([x[i], 0.0, 0.0]))
        # generalized coordinates g = (rigid 6, modal m) -> point displacements S g; point matrices from the
        # beam's exact matrices over g (module docstring)
        G = np.hstack([rigid_fields(x), modes.shapes])
        S = T @ G
        n_carrier = 3 * 3 * len(sections)              # the section points carry the mass; the arms are massless
        Sc = S[:n_carrier]
        if np.linalg.svd(Sc / np.linalg.norm(Sc, axis=0), compute_uv=False)[-1] < 1e-6:
            raise ValueError(f"the {len(sections)} mesh sections of the flexible car body do not resolve its "
                             f"{modes.n_modes} modes: give more sections (n_sections)")
        Splus = np.zeros((S.shape[1], S.shape[0]))
        Splus[:, :n_carrier] = np.linalg.pinv(Sc)
        Mp, Kp = Splus.T @ (G.T @ M @ G) @ Splus, Splus.T @ (G.T @ K @ G) @ Splus
        psi = S[:, 6:]
        # centre of mass of the beam: mass-weighted axis positions (translation field against the position field)
        tx = np.zeros(N_DOF_NODE * n)
        tx[0::N_DOF_NODE] = 1.0
        px = np.zeros(N_DOF_NODE * n)
        px[0::N_DOF_NODE] = x
        com = np.array([tx @ M @ px / (tx @ M @ tx), 0.0, 0.0])
        node_points = {round(float(x[i]), 6): [3 * k, 3 * k + 1, 3 * k + 2] for k, i in enumerate(sections)}
    else:
        points = modes.fe["points"]
        Mp, Kp = modes.fe["mass"].toarray(), modes.fe["stiffness"].toarray()
        psi = modes.fe["shapes_points"]
        arm_of = {_key(p): mesh_node(points, p) for p in attach}
        ones = np.tile(np.eye(3), (len(points), 1))
        m = (ones.T @ Mp @ ones)[0, 0]
        com = (ones.T @ Mp @ points.reshape(-1)) / m
        node_points = {}
        for pr in np.asarray(rigid_marker_points_m, dtype=float).reshape(-1, 3):
            near = np.argsort(np.linalg.norm(points - pr[None, :], axis=1))[:4]
            spread = np.linalg.svd(points[near] - points[near].mean(axis=0), compute_uv=False)
            if spread[1] < 1e-6 * max(spread[0], 1e-12):
                raise ValueError(f"rigid marker at {pr.tolist()} m: the nearest FE nodes are collinear")
            node_points[round(float(pr[0]), 6)] = [int(i) for i in near]
    fem = FEMinterface()
    fem.nodes = {"Position": points}
    fem.massMatrix = sp.csr_matrix(Mp)
    fem.stiffnessMatrix = sp.csr_matrix(Kp)
    fem.modeBasis = {"matrix": np.asarray(psi), "type": "NormalModes"}
    fem.eigenValues = modes.omega_rad_s ** 2
    cms = ObjectFFRFreducedOrderInterface(fem, rigidBodyNodeType=exu.NodeType.RotationRotationVector)
    d = cms.AddObjectFFRFreducedOrder(mbs, positionRef=[float(v) for v in p_cg_in_frame],
                                      gravity=[float(v) for v in gravity], name=name)
    obj, rigid, modal = d["oFFRFreducedOrder"], d["nRigidBody"], d["nGenericODE2"]
    mbs.SetObjectParameter(obj, "centerOfMass", [float(v) for v in com])
    mc = exu.MatrixContainer()
    mc.SetWithDenseMatrix(modes.modal_damping(), useDenseMatrix=False)
    mbs.SetObjectParameter(obj, "dampingMatrixReduced", mc)
    point_markers = {k: mbs.AddMarker(MarkerSuperElementPosition(bodyNumber=obj, meshNodeNumbers=[int(i)],
                                                                 weightingFactors=[1.0]))
                     for k, i in arm_of.items()}
    rigid_markers = {}
    for pr in np.asarray(rigid_marker_points_m, dtype=float).reshape(-1, 3):
        nodes = node_points.get(round(float(pr[0]), 6))
        if nodes is None:
            raise ValueError(f"rigid marker at x = {pr[0]} m: not a beam node of the flexible car body")
        rigid_markers[round(float(pr[0]), 6)] = mbs.AddMarker(MarkerSuperElementRigid(
            bodyNumber=obj, meshNodeNumbers=nodes, weightingFactors=[1.0 / len(nodes)] * len(nodes),
            offset=[0.0, 0.0, 0.0]))
    return FlexibleCarBody(modes=modes, node=rigid, modal_node=modal, body=obj, points_m=points,
                           point_markers=point_markers, rigid_markers=rigid_markers, mass_points=Mp,
                           stiffness_points=Kp)


# ================================================================================= the car body of a vehicle
def highest_mode_rad_s(vehicle) -> float:
    """The highest kept elastic mode of the vehicle's flexible car body [rad/s] (0 for a rigid car body): what an
    explicit time step must resolve (the solvers' limits: :mod:`exudyn_wheelrail.simulation.solvers`)."""
    cb = vehicle.car_body
    if cb is None or cb.flexible is None:
        return 0.0
    return float(car_body_modes(vehicle).omega_rad_s.max())


@functools.lru_cache(maxsize=8)
def car_body_modes(vehicle) -> CarBodyModes:
    """The elastic modes of a vehicle's flexible car body (``[car_body.flexible]``): the beam of
    :func:`~.car_body_model.beam_from_car_body` meshed with nodes at the bogie centres, or the FE model's modes (cached per
    vehicle: the result is shared, do not modify it)."""
    cb = vehicle.car_body
    fx = cb.flexible
    if fx is None:
        raise ValueError(f"{vehicle.name}: the car body is rigid (no [car_body.flexible] table)")
    if fx.fe_model is not None:
        return modes_from_fe_file(fx.fe_model, fx.n_modes, fx.damping_ratio)
    x_nodes = sorted({round(float(p[0]), 9) for p in vehicle.car_body_attachment_points_m()})
    beam = beam_from_car_body(cb, length_m=fx.length_m, EI_vertical_N_m2=fx.EI_vertical_N_m2,
                              EI_lateral_N_m2=fx.EI_lateral_N_m2, GJ_N_m2=fx.GJ_N_m2, EA_N=fx.EA_N,
                              n_elements=fx.elements or DEFAULT_ELEMENTS, node_x_m=tuple(x_nodes))
    return beam.modes(fx.n_modes, fx.damping_ratio)


@dataclass
class FlexibleBodyHandle(BodyHandle):
    """The flexible car body in a :class:`~.vehicle_builder.VehicleModel`: ``node`` is the reference frame
    (at the CG, the body's mean axes), ``body`` the ``ObjectFFRFreducedOrder``, ``marker``/``marker_node`` a
    ``MarkerNodeRigid`` of the frame; ``flexible`` the :class:`FlexibleCarBody`."""

    flexible: FlexibleCarBody | None = None

    def position_marker(self, mbs, r_local_m):
        """Marker of a body point (relative to the CG, body axes): an attachment point's
        ``MarkerSuperElementPosition``, or the frame node's position at the CG."""
        if np.allclose(r_local_m, 0.0, atol=1e-9):
            return mbs.AddMarker(MarkerNodePosition(nodeNumber=self.node))
        key = _key(r_local_m)
        if key not in self.flexible.point_markers:
            raise ValueError(f"{self.name}: {list(key)} m (from the CG) is not an attachment point of the "
                             f"flexible car body ({sorted(self.flexible.point_markers)})")
        return self.flexible.point_markers[key]

    def rigid_marker(self, r_local_m):
        """``MarkerSuperElementRigid`` of the beam section at the point's x (its orientation is the section's;
        for rotational springs)."""
        key = round(float(r_local_m[0]), 6)
        if key not in self.flexible.rigid_markers:
            raise ValueError(f"{self.name}: no rigid marker at x = {key} m of the flexible car body")
        return self.flexible.rigid_markers[key]


def add_vehicle_car_body(mbs, vehicle, p_cg_in_frame, *, gravity, name: str, preload_N=None):
    """The flexible car body of ``vehicle`` in ``mbs``, as a body handle for :func:`~.vehicle_builder.build_vehicle`
    (markers at :meth:`~.vehicle_data.VehicleData.car_body_attachment_points_m`, rigid markers at the bogie
    centres).  ``preload_N`` (n_bogies, 2): the secondary springs' static vertical forces (positive: carrying the
    body, left then right); the modal coordinates then start at the static deflection ``q = Ω⁻² Φ_Pᵀ f_P`` under
    them (gravity, uniform, does not load the free–free elastic modes), so the body does not start a bending
    oscillation, and the frame moves vertically by the springs' mean elastic displacement, so the springs keep their
    preload length: exact static equilibrium for a car body symmetric about its CG (a CG offset leaves a pitch
    residual of the order of the elastic displacement)."""
    modes = car_body_modes(vehicle)
    pts = vehicle.car_body_attachment_points_m()
    fb = add_flexible_car_body(mbs, modes, p_cg_in_frame, attach_points_m=pts, gravity=gravity,
                               rigid_marker_points_m=pts.reshape(-1, 3, 3)[:, 2, :], name=name)  # bogie centres
    if preload_N is not None:
        f = np.asarray(preload_N, dtype=float)
        springs = pts.reshape(-1, 3, 3)[:, :2, :]                   # per bogie: left, right (bump stop third)
        phi = modes.point_shapes(springs.reshape(-1, 3))            # (2 n_bogies, 3, n_modes)
        Q = -(phi[:, 2, :] * f.reshape(-1)[:, None]).sum(axis=0)     # force on the body: -preload along z (down)
        q = Q / modes.omega_rad_s ** 2
        mbs.SetNodeParameter(fb.modal_node, "initialCoordinates", q.tolist())
        # the frame sinks by the springs' mean elastic lift, so they start at their preload length
        q0 = np.array(mbs.GetNodeParameter(fb.node, "initialCoordinates"), dtype=float)
        q0[2] -= float(np.mean(phi[:, 2, :] @ q))
        mbs.SetNodeParameter(fb.node, "initialCoordinates", q0.tolist())
    marker = mbs.AddMarker(MarkerNodeRigid(nodeNumber=fb.node))
    return FlexibleBodyHandle(name=name, node=fb.node, body=fb.body, marker=marker, marker_node=marker,
                              p_cg_in_frame=np.asarray(p_cg_in_frame, dtype=float),
                              mass_kg=vehicle.car_body.mass_kg, flexible=fb)


# ================================================================================== kinematics of body points
class BodyPointKinematics:
    """Acceleration, specific force and displacement of points fixed to the flexible car body, from the frame
    node's and the modal node's outputs (no mesh node needed at the point):

    ``a_P = a_O + R [α × ρ + ω × (ω × ρ) + 2 ω × Φ_P q̇ + Φ_P q̈]``, ``ρ = r_P + Φ_P q`` (ω, α body axes; R the
    frame's rotation; Φ_P the mode shapes at the point, :meth:`CarBodyModes.point_shapes`)."""

    def __init__(self, handle, r_points_m):
        self.ovt = exu.OutputVariableType
        self.fb = handle.flexible
        self.r = np.atleast_2d(np.asarray(r_points_m, dtype=float))
        self.phi, self.theta = self.fb.modes.point_shapes(self.r, rotations=True)     # (n, 3, m) each
        self._phi_2d = np.ascontiguousarray(self.phi.reshape(-1, self.phi.shape[2]))
        self._theta_2d = np.ascontiguousarray(self.theta.reshape(-1, self.theta.shape[2]))
        self.p_ref = np.asarray(handle.p_cg_in_frame, dtype=float)         # the frame node's reference position
        self._i_frame = self._i_modal = None

    def state(self, mbs):
        """``(R, a, u, θ)``: the frame's rotation matrix, the points' accelerations (n, 3) and displacements from
        their reference positions (n, 3) in the simulation frame, and the small rotations of their sections (n, 3)
        in body axes (the local axes at a point are ``R (I + θ̃)``)."""
        o = self.ovt
        node, modal = self.fb.node, self.fb.modal_node
        R = np.asarray(mbs.GetNodeOutput(node, o.RotationMatrix)).reshape(3, 3)
        if self._i_frame is None:                     # ODE2 indices (known after Assemble)
            self._i_frame, self._i_modal = mbs.GetNodeODE2Index(node), mbs.GetNodeODE2Index(modal)
        c_tt = np.asarray(mbs.systemData.GetODE2Coordinates_tt())      # the nodes give no Coordinates_tt output
        a0 = c_tt[self._i_frame:self._i_frame + 3]
        al = c_tt[self._i_frame + 3:self._i_frame + 6]                  # Lie-group node: dω_local/dt
        qtt = c_tt[self._i_modal:self._i_modal + self.phi.shape[2]]
        w = np.asarray(mbs.GetNodeOutput(node, o.AngularVelocityLocal))
        p0 = np.asarray(mbs.GetNodeOutput(node, o.Position))
        q = np.asarray(mbs.GetNodeOutput(modal, o.Coordinates))
        qt = np.asarray(mbs.GetNodeOutput(modal, o.Coordinates_t))
        n = self.r.shape[0]
        P = self._phi_2d
        rho = self.r + (P @ q).reshape(n, 3)                          # elastic displacement added, body axes
        W, A = skew(w), skew(al)                                    # a × b = ã b (np.cross is slow on 3-vectors)
        acc_local = rho @ (A + W @ W).T + 2.0 * (P @ qt).reshape(n, 3) @ W.T + (P @ qtt).reshape(n, 3)
        return R, a0 + acc_local @ R.T, p0 + rho @ R.T - self.p_ref - self.r, (self._theta_2d @ q).reshape(n, 3)
