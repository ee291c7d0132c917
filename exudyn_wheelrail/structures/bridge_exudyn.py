r"""A modally reduced bridge in Exudyn: the two formulations (:func:`add_bridge`, :data:`FORMULATIONS`), the handle
(:class:`ExudynBridge`), constant forces moving over the deck (:class:`MovingForces`) and the lateral support
motion (:meth:`ExudynBridge.add_support_motion`).

Entering it into Exudyn (:func:`add_bridge`)
--------------------------------------------
Both formulations put the modal coordinates into one ``NodeGenericODE2`` (:attr:`ExudynBridge.modal_node`), and
external forces on the deck are applied by zero-mass ``ObjectGenericODE2`` items spanning that node (and, for a
contact, the vehicle's nodes) that return ``Φ(s)^T F`` (:class:`MovingForces`):

* ``formulation="modal"`` (default): one ``ObjectGenericODE2`` with mass ``I``, stiffness ``diag(ω²)`` and damping
  ``diag(2ζω)`` on the modal node.  Explicit and implicit solvers.
* ``formulation="ffrf"``: Exudyn's ``ObjectFFRFreducedOrder`` through its FEM tools (``FEMinterface`` →
  ``mbs.CreateFFRFReducedOrderObject``) with the reference frame held to the ground by coordinate constraints
  (implicit solvers).  The FFRF object needs a mesh of *position* nodes (3 coordinates each); the beam's 6-DOF
  nodes are mapped to three points each (axis, a point ``h`` above it, a point ``h`` to the right:
  ``u_P = u + θ × r_P``, the map ``T``), the mode basis is ``T Φ`` and the point-coordinate matrices are
  ``T⁺ᵀ M T⁺`` and ``T⁺ᵀ K T⁺`` (``T⁺`` the left inverse), so that the reduced matrices Exudyn computes are exactly
  ``I`` and ``diag(ω²)`` and its rigid-body inertia terms (mass, inertia tensor) are those of the beam.
  Modal damping is set as the object's ``dampingMatrixReduced = diag(2ζω)``.  It would carry a moving or
  rotating reference frame (a bridge on flexible or moving supports), which the fixed bridge does not need.

Measured trade-off (:func:`~exudyn_wheelrail.scenarios.moving_forces.benchmark_formulations`: simply supported 20 m span, f1 = 4.53 Hz, all 25 modes up to
150 Hz, one 200 kN force at 40 m/s, generalized-α with spectral radius 1, Δt = 0.5 ms, 1500 steps, the same
moving-force object on both; Exudyn 1.13.6, one core of a shared machine, best of 3):

=============  ===========================  ==============  =====================================
formulation    mid-span error vs Frýba       µs per step     3 continuous spans, 50 modes (µs/step)
=============  ===========================  ==============  =====================================
``"modal"``    0.073 % of the peak           8–11            15
``"ffrf"``     0.073 % of the peak           118             350
=============  ===========================  ==============  =====================================

Both integrate the same modal equations (the histories agree to 1e-12 m; the 0.07 % is the truncation of the
vertical modes above 150 Hz).  The FFRF object costs 15–25 times more per step (a rigid-body node held by 6
constraints, the FFRF inertia terms over the 3 × n_nodes mesh points evaluated every step) and needs an implicit
solver (explicit ones refuse its Euler-parameter node: "explicit integrator detected node … which contains
algebraic variables").  Use ``"modal"`` for a bridge on fixed supports; ``"ffrf"`` only as the entry point for a
moving or flexibly supported reference frame.

Lateral support motion (earthquake-like; :mod:`.support_motion`)
-----------------------------------------------------------------
:meth:`ExudynBridge.add_support_motion` imposes a lateral ground displacement ``y_g(t)`` on all supports together
(synchronous ground motion).  Relative-motion formulation, exact for the linear deck: absolute deck displacement =
rigid lateral translation ``y_g`` (the supports carry the deck along) + ``Φ q``, with the effective load
``-Γ ÿ_g(t)`` on the modal equations (``Γ = Φᵀ M r``, :meth:`~.bridge.BridgeModes.participation_factors`); the
connector adds ``y_g`` and ``ẏ_g`` to the rails' lateral position and material velocity under every wheelset
(on the deck and off it).  Measured (tests/test_bridge_support_motion.py, a 20 m span, 20 elements): ``Γ_n`` of
the first six lateral modes within 3.4e-6 Γ_1 of ``2√(2mL)/(nπ)`` (0 for even n and for all other mode kinds);
the static modal sum ``-Σ φ_n(L/2) Γ_n/ω_n² ÿ_g`` is the beam under the uniform inertia load,
``-5 m ÿ_g L⁴/(384 EI_z)``, within 4.4e-6; under a harmonic ground acceleration at 0.8 f_1 (ζ = 5 %) the
first lateral mode's history agrees with the single-DOF equation to 5e-4 of its peak and its steady state with
the amplification ``1/√((1-r²)²+(2ζr)²) = 2.711`` to 3e-4.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import exudyn as exu
import numpy as np
import scipy.sparse as sp
from exudyn.FEM import FEMinterface
from exudyn.itemInterface import (CoordinateConstraint, MarkerNodeCoordinate, NodeGenericODE2, NodePointGround,
                                  ObjectGenericODE2, SensorNode, VObjectGenericODE2)

from ..jit import compiled
from .bridge import BridgeModes
from .modal_basis import ModalBasis
from .item_names import unique_name
from .modal_shapes import add_projected_force
from .checks import checked_number
from .support_motion import SupportMotionLoad

__all__ = ["FORMULATIONS", "ExudynBridge", "MovingForces", "add_bridge"]

FORMULATIONS = ("modal", "ffrf")


@compiled
def _moving_forces_core(t, s_start_m, speed_m_s, x_m, forces, start_m, rail_height_m, elem_x0, elem_len,
                        elem_nodes, node_shapes, work, f_modal):
    for k in range(f_modal.shape[0]):
        f_modal[k] = 0.0
    s0 = s_start_m + speed_m_s * t
    for j in range(x_m.shape[0]):
        add_projected_force(s0 + x_m[j], forces[j, 0], forces[j, 1], forces[j, 2], start_m, rail_height_m, elem_x0,
                            elem_len, elem_nodes, node_shapes, work, f_modal)


class MovingForces:
    """Constant forces travelling along the track at a constant speed, applied to the deck: one zero-mass
    ``ObjectGenericODE2`` on the bridge's modal node whose force user function returns ``Σ Φ(s_j(t))^T F_j`` with
    ``s_j(t) = s_start_m + V t + x_j`` (``x_j`` the force's place in the frame moving with V, ahead > 0, like a
    wheel of :mod:`..rolling_stock.vehicle_builder`), and a zero Jacobian (the forces do not depend on the state).

    forces_N : (n, 3) rows ``(Fy, Fz, Mx)`` [N, N, N m] on the rails' centre line at rail-top level (z down:
    a vertical wheel load is ``Fz > 0``)."""

    def __init__(self, mbs, bridge: "ExudynBridge", x_m, forces_N, speed_m_s: float, s_start_m: float = 0.0,
                 name: str = "moving_forces"):
        x = np.atleast_1d(np.asarray(x_m, dtype=float)).ravel()
        F = np.asarray(forces_N, dtype=float)
        if F.ndim == 1:
            F = F.reshape(1, -1)
        if x.size == 0:
            raise ValueError("MovingForces: no force positions given")
        if F.shape != (x.size, 3):
            raise ValueError(f"MovingForces: forces_N has shape {F.shape}, expected ({x.size}, 3) rows (Fy, Fz, Mx)")
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(F))):
            raise ValueError("MovingForces: non-finite positions or forces")
        self.x_m = np.ascontiguousarray(x)
        self.forces_N = np.ascontiguousarray(F)
        self.speed_m_s = checked_number("speed_m_s", speed_m_s)
        self.s_start_m = checked_number("s_start_m", s_start_m)
        self.table = bridge.modes.table
        n = bridge.modes.n_modes
        self._f = np.zeros(n)
        self._t = np.nan                               # the time self._f holds (none yet)
        self._work = np.zeros((3, n))
        self._jac = np.zeros((n, n))
        self.object = mbs.AddObject(ObjectGenericODE2(
            name=unique_name(mbs, name), nodeNumbers=[bridge.modal_node], massMatrix=np.zeros((n, n)),
            forceUserFunction=self._force_uf, jacobianUserFunction=self._jacobian_uf,
            visualization=VObjectGenericODE2(show=False)))

    def forces(self, t: float) -> np.ndarray:
        """Generalized modal forces at time t (kept for the next call at the same time: an RK stage or a step's
        end and the next step's start evaluate one time twice).  The array is overwritten by the next call at
        another time."""
        t = float(t)
        if t != self._t:
            _moving_forces_core(t, self.s_start_m, self.speed_m_s, self.x_m, self.forces_N, *self.table,
                                self._work, self._f)
            self._t = t
        return self._f

    def _force_uf(self, mbs, t, itemIndex, q, q_t):
        return self.forces(t)

    def _jacobian_uf(self, mbs, t, itemIndex, q, q_t, fODE2, fODE2_t):
        return self._jac


@dataclass
class ExudynBridge:
    """Handle of a bridge in an Exudyn system (:func:`add_bridge`).

    modal_node : the ``NodeGenericODE2`` with the n_modes modal coordinates (both formulations) — the node a
        contact connector adds to its ``nodeNumbers``.
    object : the structural item (``ObjectGenericODE2`` or ``ObjectFFRFreducedOrder``).
    rigid_node, constraints : the FFRF reference-frame node and the constraints that hold it (``"ffrf"`` only).
    """

    modes: ModalBasis
    formulation: str
    modal_node: int
    object: int
    rigid_node: int | None = None
    constraints: tuple = ()
    ffrf_data: dict | None = None
    support_motion: object = None
    support_load: object = None
    #: called (without arguments) when a support motion is added: what must then evaluate the ground motion at every
    #: call, e.g. a connector on its compiled call path (which does not), switches to its Python path.  Weak
    #: references (``weakref.WeakMethod``); dead ones are skipped.
    support_motion_listeners: list = field(default_factory=list)

    def add_support_motion(self, mbs, motion, name: str = "support_motion"):
        """Impose a lateral ground motion ``y_g(t)`` on all supports (a :class:`.support_motion.SupportMotion`, e.g.
        :class:`~.support_motion.SmoothHarmonicSupportMotion`; relative-motion formulation of
        :mod:`.support_motion`): adds the effective load ``-Γ ÿ_g(t)`` on the modal node
        (:class:`~.support_motion.SupportMotionLoad`) and records the motion, so that a wheel–rail connector
        coupled to this bridge sees the rails at ``y_g + Φ_y q`` moving with ``ẏ_g + Φ_y q̇`` (on and off the deck:
        synchronous ground motion).  The modal coordinates stay the motion *relative* to the supports.  One
        support motion per bridge; call before ``mbs.Assemble()``."""
        if self.support_motion is not None:
            raise ValueError("this bridge already has a support motion (one per bridge: combine the records in one "
                             "SupportMotion)")
        load = SupportMotionLoad(mbs, self, motion, name=name)
        self.support_motion = motion
        self.support_load = load
        for ref in self.support_motion_listeners:
            listener = ref()
            if listener is not None:
                listener()
        return load

    def ground_state(self, t: float) -> tuple[float, float, float]:
        """``(y_g, ẏ_g, ÿ_g)`` of the support motion at time t (zeros without one)."""
        if self.support_motion is None:
            return 0.0, 0.0, 0.0
        return self.support_motion.state(float(t))

    def coordinates(self, mbs) -> tuple[np.ndarray, np.ndarray]:
        """Current modal coordinates and their rates."""
        q = np.asarray(mbs.GetNodeOutput(self.modal_node, exu.OutputVariableType.Coordinates), dtype=float)
        v = np.asarray(mbs.GetNodeOutput(self.modal_node, exu.OutputVariableType.Coordinates_t), dtype=float)
        return q, v

    def add_sensor(self, mbs, name: str = "bridge_modal_coordinates") -> int:
        """A node sensor storing the modal coordinates in memory (``mbs.GetSensorStoredData``: rows t, q...)."""
        return mbs.AddSensor(SensorNode(name=name, nodeNumber=self.modal_node, storeInternal=True,
                                        outputVariableType=exu.OutputVariableType.Coordinates))

    def add_moving_forces(self, mbs, x_m, forces_N, speed_m_s: float, s_start_m: float = 0.0,
                          name: str = "moving_forces") -> MovingForces:
        """Constant forces moving along the track (:class:`MovingForces`)."""
        return MovingForces(mbs, self, x_m, forces_N, speed_m_s, s_start_m, name=name)


def add_bridge(mbs, modes: ModalBasis, formulation: str = "modal", name: str = "bridge") -> ExudynBridge:
    """Enter a modally reduced bridge (:meth:`BridgeModel.modes`) into the Exudyn ``MainSystem`` ``mbs`` (before
    ``mbs.Assemble()``).

    name : base name of the Exudyn items (made unique: ``bridge``, ``bridge_2``, …).
    formulation : ``"modal"`` (default) — ``ObjectGenericODE2`` with ``I``, ``diag(ω²)``, ``diag(2ζω)`` on one
        ``NodeGenericODE2``; cheapest, explicit and implicit solvers.  ``"ffrf"`` — ``ObjectFFRFreducedOrder``
        via ``exudyn.FEM.FEMinterface`` and ``mbs.CreateFFRFReducedOrderObject``, frame held by constraints
        (implicit solvers); same modal equations, 15–25 times the cost per step (module docstring, measured).
    """
    if formulation not in FORMULATIONS:
        raise ValueError(f"formulation={formulation!r}: expected one of {FORMULATIONS}")
    if not isinstance(modes, ModalBasis):
        raise TypeError(f"modes={modes!r}: expected a ModalBasis (BridgeModel.modes(...), a modes file's "
                        "SampledModes)")
    if formulation == "ffrf" and not isinstance(modes, BridgeModes):
        raise ValueError("formulation='ffrf' needs the finite-element deck (BridgeModes): a modes file has no mesh")
    name = unique_name(mbs, name)
    if formulation == "modal":
        return _add_modal(mbs, modes, name)
    return _add_ffrf(mbs, modes, name)


def _add_modal(mbs, modes: ModalBasis, name: str) -> ExudynBridge:
    n = modes.n_modes
    node = mbs.AddNode(NodeGenericODE2(name=f"{name}_modal", numberOfODE2Coordinates=n, referenceCoordinates=[0.0] * n,
                                       initialCoordinates=[0.0] * n, initialCoordinates_t=[0.0] * n))
    obj = mbs.AddObject(ObjectGenericODE2(name=name, nodeNumbers=[node], massMatrix=modes.modal_mass(),
                                          stiffnessMatrix=modes.modal_stiffness(),
                                          dampingMatrix=modes.modal_damping(),
                                          visualization=VObjectGenericODE2(show=False)))
    return ExudynBridge(modes, "modal", int(node), int(obj))


def _add_ffrf(mbs, modes: BridgeModes, name: str) -> ExudynBridge:
    model = modes.model
    points, T = model.point_map(h_m=max(model.rail_height_m, 1.0))
    M, K = model.assemble(supported=False)
    # left inverse T⁺ = (TᵀT)⁻¹Tᵀ, block diagonal like T
    TtT = (T.T @ T).toarray()
    Tplus = sp.csr_matrix(np.linalg.solve(TtT, T.T.toarray()))
    fem = FEMinterface()
    fem.nodes = {"Position": points}
    fem.massMatrix = (Tplus.T @ M @ Tplus).tocsr()
    fem.stiffnessMatrix = (Tplus.T @ K @ Tplus).tocsr()
    fem.modeBasis = {"matrix": np.asarray(T @ modes.shapes), "type": "NormalModes"}
    fem.eigenValues = modes.omega_rad_s ** 2
    d = mbs.CreateFFRFReducedOrderObject(name=name, femInterface=fem)["FFRFReducedOrderObjectDict"]
    obj, rigid, modal = d["oFFRFreducedOrder"], d["nRigidBody"], d["nGenericODE2"]
    # the FEM tools compute the centre of mass from the reference positions of the points, which (points off
    # the axis) is not a rigid-body field of the beam; set it from the beam (on the axis, x by the mass)
    x_mid = np.cumsum((0.0,) + model.spans_m)[:-1] + 0.5 * np.array(model.spans_m)
    mL = np.array([sec.m_kg_m * L for sec, L in zip(model.section, model.spans_m)])
    mbs.SetObjectParameter(obj, "centerOfMass", [float(mL @ x_mid / mL.sum()), 0.0, 0.0])
    mc = exu.MatrixContainer()
    mc.SetWithDenseMatrix(modes.modal_damping(), useDenseMatrix=False)
    mbs.SetObjectParameter(obj, "dampingMatrixReduced", mc)
    # hold the reference frame: position and the three vector parts of the Euler parameters (the object carries
    # the normalisation constraint, which then fixes e0)
    n_coords = len(mbs.GetNodeParameter(rigid, "referenceCoordinates"))
    ground = mbs.AddNode(NodePointGround(name=f"{name}_ground"))
    m_ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
    fixed = [0, 1, 2] + list(range(n_coords - 3, n_coords))
    constraints = []
    for c in fixed:
        m = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=rigid, coordinate=c))
        constraints.append(int(mbs.AddObject(CoordinateConstraint(markerNumbers=[m_ground, m]))))
    return ExudynBridge(modes, "ffrf", int(modal), int(obj), rigid_node=int(rigid), constraints=tuple(constraints),
                        ffrf_data=d)
