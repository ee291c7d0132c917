"""The wheel–rail connector: one Exudyn item coupling every wheelset of a model to its rails.

>>> model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=50.0)                        # doctest: +SKIP
>>> contact = add_wheel_rail_contact(mbs, model.wheelset_nodes, WheelRailPair("S1002", "UIC60"),
...                                  speed_m_s=50.0, track=RigidStraightTrack(irregularity))  # doctest: +SKIP

What it is
----------
One ``ObjectGenericODE2`` spanning all wheelset nodes (Lie-group rigid nodes, ``NodeType.RotationRotationVector``)
with no mass of its own (an empty mass matrix: a zero one would store n² zeros in the system's sparse mass matrix)
and a force user function.  Each right-hand-side evaluation makes **one compiled call**
(:func:`~.connector_core.contact_forces_core`, the model data packed once at construction) that, for every wheel,

1. takes the wheelset pose from the node coordinates (position, rotation vector → rotation matrix; roll and yaw
   from the axle direction) and subtracts the rail's lateral/vertical displacement (the track irregularity) at
   the wheel's track distance ``s = s_start + V t + x`` (the model frame translates with the running speed V —
   :mod:`exudyn_wheelrail.rolling_stock.vehicle_builder`; ``frame="track"``: wheelsets that move along x);
2. solves the contact geometry and Hertz for the tread and flange regions (:mod:`exudyn_wheelrail.contact.kernel`,
   warm-started from the previous call);
3. places each contact point in 3-D (the yaw lead of :func:`~exudyn_wheelrail.contact.creepage.
   yawed_contact_point_core`), computes the creepages (:mod:`exudyn_wheelrail.contact.creepage`) from the
   wheelset's velocity and angular velocity and the rail material velocity (``(-V, 0, 0)`` in the moving frame);
4. evaluates the creep law (by default the USETAB-style table of Kalker's exact theory; FASTSIM or a cheap law
   on request: :mod:`exudyn_wheelrail.creep.registry`) in the contact frame;
5. applies ``N n_rail + Fx x_c + Fy y_c`` at the contact point and the spin moment ``Mz z_c`` to the wheelset
   (generalized forces: force in the global frame, torque in the body frame — the Lie-group node's velocity
   coordinates are the body-frame angular velocity), and records the equal and opposite force on the rail.

Separation gives no force; re-contact is found by the kernel's separation bound and warm/global search.

Implicit solvers: a Jacobian user function returns ``-∂f/∂q fODE2 - ∂f/∂q_t fODE2_t``, by default semi-analytic
(:mod:`.contact_jacobian`: one evaluation of the compiled call and the derivatives of its results — Hertz along
the normal, the creep law's tangent with the creepages' velocity derivatives, the deck coupling — forward
differences where a contact's normal turns fast, e.g. in the flange root); :attr:`WheelRailContact.jacobian_method`
``"forward_difference"`` gives the structured forward differences of the same compiled call (position and
velocity perturbations; rotations perturbed by body-frame increments, the Lie-group tangent), with the warm-start
state saved and restored; block diagonal per wheelset, so 12 calls whatever the number of wheelsets (plus 6 with a
bridge, below).

A structure under the rails (``structure=``)
--------------------------------------------
What moves the rails — a bridge deck or a flexible track, both an
:class:`~exudyn_wheelrail.structures.bridge_exudyn.ExudynBridge` — makes the object also span the structure's modal
node: coordinates ``[6 per wheelset..., n_m modal]``, forces ``[force, torque per wheelset..., Q]``, still one
compiled call per evaluation.  The deck under each wheelset moves its rails (displacement, roll and material
velocity), and minus the wheel forces are projected on the modes, ``Q += Φ(s_k)^T (F_ry, F_rz, M_rx)`` (frames and
signs: :mod:`exudyn_wheelrail.structures.deck_kinematics`).  Wheels off the deck see the rigid track.
A lateral support motion of the bridge (``bridge.add_support_motion``) moves the rails of every wheelset by the
ground displacement and velocity ``y_g(t)``, ``ẏ_g(t)``, evaluated once per force or Jacobian call.

Jacobian: the wheelset columns as above (their modal rows are the change of ``Φ(s_k)^T F_r,k``, including the
change of ``Φ`` when the x coordinate moves s_k); the modal columns by the chain rule through the deck state under
each wheelset (6 calls for any number of modes and wheelsets; tested against column-by-column differences).

Outputs
-------
:attr:`WheelRailContact.results` ``(n_wheels, 3, N_RES)`` holds the last evaluation per wheel (``2k`` right,
``2k+1`` left) and kernel slot (0 tread, 1 flange, 2 the tread's second zone in two-point tread contact); fields
``RES_*`` of :mod:`exudyn_wheelrail.contact.layout` (also importable from here).  Forces are **on the wheel**;
``RES_F_TRACK_*`` is the total contact force (normal + creep) in the track/model frame (y right, z down: a wheel
load Q is ``-RES_F_TRACK_Z``); ``RES_DECK_*``, ``RES_ON_DECK``, ``RES_GROUND_*`` the deck offset used (relative to
the supports) and the ground motion.  ``kernel_output``: the contact search's own output; ``modal_forces_N``,
``rail_forces_N``, ``deck_state``, ``wheelset_rail_pose``: the bridge coupling and the pose relative to the rails.
Invalid states (NaN coordinates) raise :class:`ContactStateError` naming the wheelset and the time.
"""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
from exudyn.itemInterface import ObjectGenericODE2, VObjectGenericODE2

from .. import contact_defaults as DEFAULT
from ..contact import geometry_table as GT
from ..contact.creepage import DEFAULT_V_MIN_M_S
from ..contact.layout import (  # noqa: F401  (the result and creep-parameter fields, importable from here)
    CP_AB_MAX, CP_AB_MIN, CP_G, CP_MU, CP_NU, CP_NX, CP_NY, CP_V_MIN, N_CP, N_RES, N_SLOTS, N_STATS, RES_A, RES_B,
    RES_CREEP_STATUS, RES_DECK_ROLL, RES_DECK_Y, RES_DECK_Z, RES_DELTA, RES_ETA, RES_F_TRACK_X, RES_F_TRACK_Y,
    RES_F_TRACK_Z, RES_FLAGS, RES_FX, RES_FY, RES_GAMMA, RES_GROUND_VY, RES_GROUND_Y, RES_MZ, RES_N, RES_ON_DECK,
    RES_P_X, RES_P_Y, RES_P_Z, RES_PHI, RES_S_TRACK, RES_STATUS, RES_V, RES_XI, STAT_CONCAVE, STAT_FALLBACK,
    STAT_FLANGE_SKIPPED, STAT_OFF_DECK, STAT_ON_DECK, STAT_TABLE, STAT_TREAD_SKIPPED)
from ..contact.pair import WheelRailPair
from ..contact.wheelset import WheelsetContact
from ..creep.fastsim import DEFAULT_NX, DEFAULT_NY
from ..creep.registry import CREEP_AB_CLAMPED, CREEP_LAWS, combined_elastic_constants, creep_model  # noqa: F401
from ..creep.registry import creep_forces as _creep  # noqa: F401  (the compiled creep dispatch, importable here)
from ..jit import compile_ahead
from ..structures.bridge_exudyn import ExudynBridge
from ..structures.deck_kinematics import DECK_GROUND_VY, DECK_GROUND_Y, N_DECK_STATE, deck_arrays
from ..validation import finite, poisson_ratio, youngs_modulus
from .connector_core import compile_shares, contact_forces_core, contact_jacobian_core
from .core_data import (FRAME_CURVED, FRAME_MOVING, FRAME_PITCH, FRAME_S_START, FRAME_SPEED, N_FRAME, W_WHEELSET,
                        WS_HALF_GAUGE, compiled_for, contact_data, geometry_tuple, model_tuple, state_tuple,
                        vehicle_tuple, work_arrays)
from .direct_call import COUNT_CALLS, COUNT_REUSED, N_COUNTS, KeptEvaluation, call_data, compiled_call, forces_step
from .contact_jacobian import JACOBIAN_METHODS, N_BLOCK, needs_differences, semi_analytic_jacobian
from ..rolling_stock.placement import place_on_rails, static_axle_offset_m  # noqa: F401  (importable from here)
from .rotations import rotation_from_vector  # noqa: F401  (importable from here)
from .rotations import rotation_vector_from_matrix as _rotation_vector_from_matrix  # noqa: F401
from ..track.layout import TrackLayout
from ..track.rigid import RigidStraightTrack

__all__ = ["WheelRailContact", "add_wheel_rail_contact", "contact_forces_core", "contact_jacobian_core",
           "ContactStateError", "CREEP_LAWS", "GEOMETRY_MODES", "place_on_rails", "static_axle_offset_m", "N_RES",
           "RES_STATUS", "RES_N", "RES_FX", "RES_FY", "RES_MZ", "RES_F_TRACK_X", "RES_F_TRACK_Y", "RES_F_TRACK_Z",
           "RES_P_X", "RES_P_Y", "RES_P_Z", "RES_GAMMA", "RES_XI", "RES_ETA", "RES_PHI", "RES_A", "RES_B",
           "RES_DELTA", "RES_V", "RES_CREEP_STATUS", "RES_FLAGS", "RES_S_TRACK", "RES_DECK_Y", "RES_DECK_Z",
           "RES_DECK_ROLL", "RES_ON_DECK", "RES_GROUND_Y", "RES_GROUND_VY"]

#: Exudyn node type (``mbs.GetNode(n)['nodeType']``) of the wheelset nodes the connector accepts: the Lie-group
#: rigid-body node with a rotation vector, created with ``nodeType=exu.NodeType.RotationRotationVector``
WHEELSET_NODE_TYPE_PREFIX = "RigidBodyRotVec"
#: contact geometry: "online" search at every evaluation, or the precomputed "table" (contact.geometry_table)
GEOMETRY_MODES = DEFAULT.GEOMETRY_MODES


class ContactStateError(RuntimeError):
    """The multibody state handed to the contact is not usable (NaN/inf coordinates).  ``time_s`` and
    ``wheelset`` (None when the bridge's coordinates are the bad ones) say where."""

    def __init__(self, message: str, time_s: float | None = None, wheelset: int | None = None):
        super().__init__(message)
        self.time_s = time_s
        self.wheelset = wheelset


class WheelRailContact:
    """The wheel–rail contact of all wheelsets of a model as one Exudyn ``ObjectGenericODE2`` (module docstring).

    Parameters
    ----------
    mbs : the Exudyn ``MainSystem`` (not yet assembled).
    wheelset_nodes : Exudyn node numbers of the wheelsets (``NodeType.RotationRotationVector``, reference
        rotation zero, i.e. the wheelset axes parallel to the track axes at the reference configuration).
    pair : the wheel and rail profiles in place (:class:`~exudyn_wheelrail.contact.WheelRailPair`).
    speed_m_s : running speed V [m/s] (rail material velocity ``-V`` in the moving frame).
    track : :class:`~exudyn_wheelrail.track.rigid.RigidStraightTrack` (irregularities); default a perfect track.
    s_start_m : track distance of the model frame's origin at t = 0.
    frame : ``"moving"`` (the model frame translates with V; default, as :func:`exudyn_wheelrail.rolling_stock.vehicle_builder.build_vehicle`)
        or ``"track"`` (the frame is fixed to the track; wheelsets carry their forward speed themselves).
    creep_law : a name of :data:`exudyn_wheelrail.creep.registry.LAWS` (:data:`CREEP_LAWS`); default ``"table"``,
        the USETAB-style table of Kalker's exact theory, as in the paper.  The rules every law follows (semi-axis
        ratio clamped at equal area and flagged ``CREEP_AB_CLAMPED`` in ``RES_CREEP_STATUS``, Coulomb bound) are
        those of :mod:`exudyn_wheelrail.creep.registry`.  The defaults of ``creep_law``, ``mu`` and ``geometry``
        are declared in :mod:`exudyn_wheelrail.contact_defaults`.
    creep_table : a :class:`~exudyn_wheelrail.creep.table.CreepTable` or a table file for ``"table"`` (default:
        the packaged table).
    mu : friction coefficient.  ``E_*``, ``nu_*``: materials (Hertz uses both; the creep laws use Kalker's
        quasi-identical combination).
    fastsim_grid : ``(n_x, n_y)`` of FASTSIM.
    global_search : run the kernel's global scan at every evaluation (slower; follows jumps without warm start).
    jacobian : ``"numerical"`` — the connector's own Jacobian user function for implicit solvers (default; how it
        differentiates: :attr:`jacobian_method`); ``None`` — none (Exudyn's own handling).
    structure : what moves the rails, an :class:`~exudyn_wheelrail.structures.bridge_exudyn.ExudynBridge` in the
        same ``mbs`` — a bridge deck (:func:`~exudyn_wheelrail.structures.bridge_exudyn.add_bridge`) or a flexible
        track (:func:`~exudyn_wheelrail.track.flexible.add_flexible_track`) — or ``None`` (rigid track).  The object
        then also spans its modal node: wheels on the deck see the deck's rail displacement and velocity, and the
        forces on the rails go to the modal coordinates (module docstring, "A structure under the rails").
        The deck's track distances are those of the track (``BridgeModel.start_m``), the same s as the irregularity.  A
        support motion of the bridge (``bridge.add_support_motion``, before or after this call) moves the rails of every
        wheelset laterally by the ground displacement and velocity as well.
    layout : a :class:`~exudyn_wheelrail.track.layout.TrackLayout` (curves, cant, gradient) or ``None`` (straight
        track).  Each wheelset's coordinates are then relative to the local track frame at its own s, and the
        creepages get the terms of the turning frame (:mod:`.connector_core`, "Curved track"); the bodies' inertia
        terms and the suspension geometry of the curve are
        :class:`~exudyn_wheelrail.rolling_stock.track_following.TrackFollowingFrame`'s.  Needs ``frame="moving"``.
    contact_patch : ``"hertz"`` or ``"non-hertzian"``: the patch's resultant where Hertz does not hold
        (:mod:`exudyn_wheelrail.contact.patch_pass`; the implicit solvers' Jacobian then differences numerically),
        read from its table (:mod:`exudyn_wheelrail.contact.patch_table`, ``patch_grid`` or its default grid; built
        once, cached) where it covers the pose and the curves are the same on every wheel, else solved online.
    """

    def __init__(self, mbs, wheelset_nodes, pair: WheelRailPair, *, speed_m_s: float,
                 track: RigidStraightTrack | None = None, s_start_m: float = 0.0, frame: str = "moving",
                 creep_law: str = DEFAULT.CREEP_LAW, mu: float = DEFAULT.FRICTION, E_wheel_Pa: float = 2.1e11,
                 nu_wheel: float = 0.28, E_rail_Pa: float = 2.1e11, nu_rail: float = 0.28,
                 fastsim_grid=(DEFAULT_NX, DEFAULT_NY),
                 creep_table=None, global_search: bool = False, jacobian: str | None = "numerical",
                 v_min_m_s: float = DEFAULT_V_MIN_M_S, name: str = "wheel_rail_contact", structure=None,
                 geometry: str = DEFAULT.GEOMETRY, geometry_grid=None, layout=None,
                 contact_patch: str = DEFAULT.CONTACT_PATCH, patch_grid=None):
        if structure is not None and not isinstance(structure, ExudynBridge):
            raise TypeError(f"structure={structure!r}: expected an ExudynBridge, what moves the rails (a deck: "
                            "structures.add_bridge; a flexible track: track.add_flexible_track), or None")
        if frame not in ("moving", "track"):
            raise ValueError(f"frame={frame!r}: expected 'moving' or 'track'")
        if layout is not None:
            if not isinstance(layout, TrackLayout):
                raise TypeError(f"layout={layout!r}: expected a TrackLayout (exudyn_wheelrail.track.layout) or None")
            if frame != "moving":
                raise ValueError("layout: a curved track needs frame='moving' (the track-following frames)")
        if creep_law not in CREEP_LAWS:
            raise ValueError(f"creep_law={creep_law!r}: expected one of {sorted(CREEP_LAWS)}")
        if geometry not in GEOMETRY_MODES:
            raise ValueError(f"geometry={geometry!r}: expected one of {GEOMETRY_MODES}")
        if not isinstance(pair, WheelRailPair):
            raise TypeError(f"pair: expected a WheelRailPair (exudyn_wheelrail.contact), got {type(pair).__name__}")
        speed_m_s = finite("speed_m_s", speed_m_s)
        if not speed_m_s >= 0.0:
            raise ValueError(f"speed_m_s: {speed_m_s!r}: expected a finite speed >= 0")
        mu = finite("mu", mu)
        if not mu >= 0.0:
            raise ValueError(f"mu: {mu!r}: expected a finite friction coefficient >= 0")
        E_wheel_Pa = youngs_modulus("E_wheel_Pa", E_wheel_Pa)
        E_rail_Pa = youngs_modulus("E_rail_Pa", E_rail_Pa)
        nu_wheel = poisson_ratio("nu_wheel", nu_wheel)
        nu_rail = poisson_ratio("nu_rail", nu_rail)
        s_start_m = finite("s_start_m", s_start_m)
        try:
            n_x, n_y = fastsim_grid
        except (TypeError, ValueError):
            raise ValueError(f"fastsim_grid: expected two positive integers (n_x, n_y), got {fastsim_grid!r}") from None
        if not all(not isinstance(v, bool) and int(v) == v and v >= 1 for v in (n_x, n_y)):
            raise ValueError(f"fastsim_grid: expected two positive integers (n_x, n_y), got {fastsim_grid!r}")
        v_min_m_s = finite("v_min_m_s", v_min_m_s)
        if not v_min_m_s > 0.0:
            raise ValueError(f"v_min_m_s: {v_min_m_s!r}: expected a speed > 0 (the creepages' standstill guard)")
        self.nodes_exu = list(wheelset_nodes)
        if not self.nodes_exu:
            raise ValueError("wheelset_nodes: no wheelset nodes given")
        n_ws = len(self.nodes_exu)
        p_ref = np.zeros((n_ws, 3))
        for k, n in enumerate(self.nodes_exu):
            try:
                node_type = str(mbs.GetNode(n).get("nodeType", ""))
            except Exception as exc:          # Exudyn raises its own error types for a bad index
                raise ValueError(f"wheelset_nodes: node {n!r} is not a node of this system ({exc})") from None
            if not node_type.startswith(WHEELSET_NODE_TYPE_PREFIX):
                raise ValueError(f"wheelset_nodes: node {n} is a {node_type or 'non-rigid'} node; the wheel-rail "
                                 f"contact needs Lie-group rigid-body nodes with a rotation vector: create the "
                                 f"wheelset bodies with nodeType=exu.NodeType.RotationRotationVector "
                                 f"(NodeRigidBodyRotVecLG)")
            ref = np.asarray(mbs.GetNodeParameter(n, "referenceCoordinates"), dtype=float)
            if np.any(np.abs(ref[3:]) > 1e-12):
                raise ValueError(f"wheelset_nodes: node {n}: the reference rotation must be zero (wheelset axes "
                                 "parallel to the track axes); put the initial rotation into the initial coordinates")
            p_ref[k] = ref[:3]
        self.p_ref = p_ref
        self.pair = pair
        self.track = track if track is not None else RigidStraightTrack()
        self.creep_law = creep_law
        self._frame = np.zeros(N_FRAME)          # V, moving frame, s_start: read by the compiled call
        self._frame[FRAME_SPEED] = speed_m_s
        self._frame[FRAME_MOVING] = 1.0 if frame == "moving" else 0.0
        self._frame[FRAME_S_START] = s_start_m
        self.layout = layout
        if layout is not None:
            packed = layout.packed()
            self._frame[FRAME_CURVED] = 1.0
            self._frame[FRAME_PITCH] = layout.theta_rad
            lay = (np.ascontiguousarray(packed.pieces, dtype=float), np.ascontiguousarray(packed.par, dtype=float))
        else:
            lay = (None, None)           # straight track: nothing of the layout is compiled
        self._kc = WheelsetContact(pair, n_ws, E_wheel_Pa, nu_wheel, E_rail_Pa, nu_rail, global_search=global_search,
                                   contact_patch=contact_patch)
        self.contact_patch = contact_patch
        self.patch_table = None          # the patch's table (contact.patch_table), where the patch is read from one
        if contact_patch == "non-hertzian" and np.all(self._kc.curve_ids == self._kc.curve_ids[0]):
            self.patch_table = self._kc.use_patch_table(patch_grid)
        self.geometry = geometry
        self.geometry_table = None
        if geometry == "table":
            if global_search:
                raise ValueError("geometry='table' replaces the search: it cannot be combined with global_search=True")
            ids = self._kc.curve_ids
            if not np.all(ids == ids[0]):
                raise ValueError("geometry='table' needs the same wheel/rail curves on every wheel")
            self.geometry_table = GT.geometry_table(self._kc.nodes, self._kc.meta, self._kc.mono, ids[0],
                                                    self._kc.params, geometry_grid)
            table = self.geometry_table.arrays()
        else:
            table = None                 # the online search for every wheel: nothing of the table is compiled
        self._stats = np.zeros(N_STATS, dtype=np.int64)
        G, nu = combined_elastic_constants(E_wheel_Pa, nu_wheel, E_rail_Pa, nu_rail)
        creep = creep_model(creep_law, mu=mu, shear_modulus_Pa=G, poisson=nu, fastsim_grid=fastsim_grid,
                            v_min_m_s=v_min_m_s, creep_table=creep_table)
        self.cp = creep.cp
        self.creep_table = creep.table
        packed = self.track.packed()
        irr = (np.ascontiguousarray(packed.rows, dtype=float), np.ascontiguousarray(packed.knots, dtype=float),
               np.ascontiguousarray(packed.coefs, dtype=float))
        # the bridge: its shape table (empty arrays, no modal coordinates, without a bridge)
        self.structure = structure
        self._deck, self.n_modes = deck_arrays(structure, n_ws)
        self._rail_delta = np.zeros((n_ws, 6))
        self._phi_ws = np.zeros((n_ws, 3, self.n_modes))
        self._rail_f = np.zeros((n_ws, 3))
        self._deck_state = np.zeros((n_ws, N_DECK_STATE))
        self._side_poses = np.zeros((2 * n_ws, 3))
        kc = self._kc
        # the compiled call's packed arguments (connector_core): model data, updated arrays, scratch: one object
        self._model = model_tuple(vehicle_tuple(self.p_ref, self._frame, *lay), irr,
                                  geometry_tuple(kc.nodes, kc.meta, kc.mono, kc.curve_ids, kc.params, table, kc.scan,
                                                 kc.patch),
                                  creep.core, self._deck)
        self._state = state_tuple(kc.warm, kc.out, self._side_poses, self._stats, self._rail_delta, self._phi_ws,
                                  self._rail_f, self._deck_state)
        self._work = work_arrays(n_ws)
        self._data = contact_data(self._model, self._state, self._work)
        n = 6 * n_ws + self.n_modes
        self.n_coordinates = n
        self._f = np.zeros(n)
        self._jac = np.zeros((n, n))
        self.results = np.zeros((2 * n_ws, N_SLOTS, N_RES))
        self._kept = KeptEvaluation(n, kc.warm, self._stats)      # forces_step's kept evaluation and counters
        self._counts = np.zeros(N_COUNTS, dtype=np.int64)
        self._call = call_data(self._data, self._f, self.results, *self._kept.arrays, self._counts)
        # the compiled force call for exactly the argument types forces() passes, at the first call; on a first run
        # one share of its callees is compiled here, the other in a second process while the model is assembled
        self._compiling = compile_ahead(contact_forces_core, self._core_args(),
                                        *compile_shares(self._f, self._f, 0.0, self._model, self._state, self._work,
                                                        self._f, self.results))
        self._forces_core = self._first_forces_core
        self._forces_step = self._first_forces_step
        self._step_entry = None
        self._direct = compiled_call(self._call, n, self._f, self._compiled_forces_step, self.forces,
                                     self._state_error, name, structure)   # forces_step without Python
        node_numbers = self.nodes_exu + ([structure.modal_node] if structure is not None else [])
        user_function = self._direct.function if self._direct is not None else self._force_uf
        kwargs = dict(name=name, nodeNumbers=node_numbers, massMatrix=exu.MatrixContainer(),
                      forceUserFunction=user_function, visualization=VObjectGenericODE2(show=False))
        if jacobian == "numerical":
            kwargs["jacobianUserFunction"] = self._jacobian_uf
        elif jacobian is not None:
            raise ValueError(f"jacobian={jacobian!r}: expected 'numerical' or None")
        obj = ObjectGenericODE2(**kwargs)
        self.object = mbs.AddObject(obj)
        mbs.variables[f"{name}_{self.object}"] = self    # the model keeps it (the compiled path's slot holds none)
        self._exu = exu

    def _core_args(self) -> tuple:
        """Arguments of the types the force call is compiled for (those :meth:`forces` passes)."""
        return self._f, self._f, 0.0, self._data, self._f, self.results

    def _first_forces_core(self, *args):
        """The first force call: compiles (or loads) the compiled call for exactly the argument types forces()
        passes — no type dispatch per call after — and makes it the connector's."""
        self._compiling.wait()
        self._forces_core = compiled_for(contact_forces_core, *self._core_args())
        return self._forces_core(*args)

    def _compiled_forces_step(self):
        """The compiled :func:`~.direct_call.forces_step` for exactly :meth:`forces`'s arguments (compiled or loaded
        at the first call, as :meth:`_first_forces_core`); both call paths run it."""
        if self._step_entry is None:
            self._compiling.wait()
            self._step_entry = self._forces_step = compiled_for(forces_step, self._f, self._f, 0.0, self._call)
        return self._step_entry

    def _first_forces_step(self, *args):
        return self._compiled_forces_step()(*args)

    @property
    def call_path(self) -> str:
        """How Exudyn calls the force evaluation: ``"compiled"`` (a native function, no Python per call so far) or
        ``"python"`` (:meth:`forces`; :mod:`.direct_call`).  Asking may compile it (as its first call would)."""
        direct = self._direct
        return "compiled" if direct is not None and direct.bind() and direct.counts()[1] == 0 else "python"

    @property
    def compiled_step(self) -> tuple:
        """``(DirectCall, CallData)`` of the compiled path (:mod:`.direct_call`; None, CallData: Python path)."""
        return self._direct, self._call

    def compiled_path_counts(self) -> tuple[int, int]:
        """``(calls, of which through Python)`` of the compiled path's native function ((0, 0) without one)."""
        return self._direct.counts() if self._direct is not None else (0, 0)

    @property
    def n_calls(self) -> int:
        """Contact evaluations of the force calls (either path) since construction or :meth:`warm_up`."""
        return int(self._counts[COUNT_CALLS])

    @property
    def n_reused(self) -> int:
        """Force calls answered by the evaluation kept by :meth:`evaluate_state`."""
        return int(self._counts[COUNT_REUSED])

    @property
    def speed_m_s(self) -> float:
        """Running speed V [m/s]."""
        return float(self._frame[FRAME_SPEED])

    @property
    def s_start_m(self) -> float:
        """Track distance [m] of the model frame's origin at t = 0."""
        return float(self._frame[FRAME_S_START])

    @property
    def moving_frame(self) -> bool:
        """Whether the model frame translates with V (``frame="moving"``)."""
        return bool(self._frame[FRAME_MOVING] != 0.0)

    # -- the compiled call -------------------------------------------------------------------------------------
    def _set_ground(self, t: float) -> None:
        """Ground (support) motion of the bridge at t into the deck parameters of the compiled call (zero without
        one)."""
        motion = self.structure.support_motion if self.structure is not None else None
        par, _, _, _, _, _, _ = self._deck         # deck_arrays: par, the shape table, residual, prediction
        if motion is None:
            par[DECK_GROUND_Y] = par[DECK_GROUND_VY] = 0.0
            return
        y, v, _ = motion.state(t)
        if not (math.isfinite(y) and math.isfinite(v)):
            raise ContactStateError(f"wheel-rail contact at t = {t:.6g} s: the bridge's support motion gives a "
                                    f"non-finite ground state (y = {y!r}, v = {v!r})", time_s=float(t))
        par[DECK_GROUND_Y] = y
        par[DECK_GROUND_VY] = v

    def ground_state(self, t: float) -> tuple[float, float]:
        """``(y_g, ẏ_g)`` added to the rails at t (the bridge's support motion; zeros without one)."""
        motion = self.structure.support_motion if self.structure is not None else None
        if motion is None:
            return 0.0, 0.0
        y, v, _ = motion.state(float(t))
        return float(y), float(v)

    def _args(self, q, q_t, t):
        """``(q, q_t, t, data)`` of the compiled force and Jacobian calls (:mod:`.connector_core`)."""
        return q, q_t, t, self._data

    def forces(self, q, q_t, t: float) -> np.ndarray:
        """Generalized contact forces for the object coordinates (force global, torque body frame per wheelset, then
        the generalized modal forces of the bridge, if any); updates :attr:`results`.  Raises
        :class:`ContactStateError` for non-finite coordinates."""
        # the hot path: nothing allocated for Exudyn's float64 arrays; the ground state only with a bridge
        q = np.ascontiguousarray(q, dtype=float)
        q_t = np.ascontiguousarray(q_t, dtype=float)
        n = self.n_coordinates
        if q.shape != (n,) or q_t.shape != (n,):
            raise ValueError(f"coordinates of shapes {q.shape}, {q_t.shape}: expected ({n},) each "
                             f"(6 per wheelset{f' + {self.n_modes} modal' if self.n_modes else ''})")
        t = float(t)
        if self.structure is not None:
            self._set_ground(t)
        bad = self._forces_step(q, q_t, t, self._call)
        if bad >= 0:
            raise self._state_error(bad, t)
        return self._f

    def evaluate_state(self, q, q_t, t: float) -> np.ndarray:
        """Evaluate the contact at ``(q, q_t, t)`` (:attr:`results`, the forces) without changing the warm start, and
        keep this evaluation for the next :meth:`forces` call: if that call is at exactly the same state (bitwise, as
        the first stage of an explicit step after the run monitor's check of the state it starts from), it takes
        the kept forces, results, counters and warm start instead of computing them again — the same numbers the
        computation gives, since it would start from the same warm start.  Any other call discards it.  Returns the
        generalized forces (as :meth:`forces`).

        The kept evaluation stays in place (forces, results, the warm start it left) until the next call; the warm
        start it started from is put back when that call does not take it (:class:`~.direct_call.KeptEvaluation`),
        and :meth:`save_warm_start` meanwhile answers with that one."""
        self._kept.begin()
        q = np.ascontiguousarray(q, dtype=float)
        q_t = np.ascontiguousarray(q_t, dtype=float)
        try:
            f = self.forces(q, q_t, t)
        except BaseException:
            self._kept.abort()
            raise
        self._kept.keep(q, q_t, t)
        return f

    def _state_error(self, bad: int, t: float) -> ContactStateError:
        """The :class:`ContactStateError` of a non-finite state (``bad`` from the compiled call)."""
        if bad == len(self.nodes_exu):
            return ContactStateError(f"wheel-rail contact at t = {t:.6g} s: the bridge's modal coordinates are "
                                     "non-finite — the simulation diverged (time step too large?)", time_s=t)
        return ContactStateError(f"wheel-rail contact at t = {t:.6g} s: wheelset {bad} (node "
                                 f"{self.nodes_exu[bad]}) has non-finite coordinates — the simulation diverged "
                                 "(time step too large?)", time_s=t, wheelset=int(bad))

    def _force_uf(self, mbs, t, itemIndex, q, q_t):
        return self.forces(q, q_t, t)

    #: how :meth:`_jacobian_uf` differentiates the contact, one of :data:`~.contact_jacobian.JACOBIAN_METHODS`:
    #: ``"semi_analytic"`` (one contact call, :mod:`.contact_jacobian`) or ``"forward_difference"`` (the structured
    #: differences of :func:`~.connector_core.contact_jacobian_core`: 14 calls, 20 with wheelsets on a deck)
    jacobian_method = JACOBIAN_METHODS[0]
    #: Jacobian evaluations since construction and the contact calls they made (not in :attr:`n_calls`)
    n_jacobian_calls = 0
    n_jacobian_contact_calls = 0
    #: of these, the evaluations by forward differences (``"forward_difference"``, or a fast-turning normal)
    n_jacobian_differenced = 0

    def _jacobian_uf(self, mbs, t, itemIndex, q, q_t, fODE2, fODE2_t):
        self._kept.discard()
        if self.jacobian_method not in JACOBIAN_METHODS:
            raise ValueError(f"jacobian_method = {self.jacobian_method!r}: expected one of {JACOBIAN_METHODS}")
        q = np.ascontiguousarray(q, dtype=float)
        q_t = np.ascontiguousarray(q_t, dtype=float)
        t = float(t)
        self._set_ground(t)
        self.n_jacobian_calls += 1
        if self.jacobian_method == "semi_analytic":
            # one contact call at the state, then its derivatives (no contact call) unless a normal turns fast
            bad = self._forces_core(q, q_t, t, self._data, self._f, self.results)
            self.n_jacobian_contact_calls += 1
            if bad >= 0:
                raise self._state_error(bad, t)
            if not needs_differences(self.results, self._kc.out):
                blocks = self.__dict__.get("_tangent_blocks")
                if blocks is None:
                    shape = (len(self.nodes_exu), N_BLOCK, N_BLOCK)
                    blocks = self._tangent_blocks = (np.zeros(shape), np.zeros(shape))
                semi_analytic_jacobian(q, q_t, self._data, self._f, self.results, float(fODE2), float(fODE2_t),
                                       self._jac, *blocks)
                return self._jac
        self._compiling.wait()          # a first run: the force call's callees in the cache before it compiles
        contact_jacobian_core(*self._args(q, q_t, t), self._f, self.results, float(fODE2), float(fODE2_t),
                              self._jac, 1e-7, 1e-7, 1e-5)
        # the differences (also the semi-analytic one's answer to a fast-turning normal, contact_jacobian): the
        # unperturbed call, 12 perturbed ones, the final one at the state; 6 more for the deck under any wheelset
        self.n_jacobian_differenced += 1
        self.n_jacobian_contact_calls += 14 + (6 if self.n_modes and np.any(self._deck_state[:, 6] > 0.5) else 0)
        return self._jac

    # -- state of the model ----------------------------------------------------------------------------------------
    def coordinates(self, mbs):
        """Current (q, q_t) of the object's nodes from the Exudyn system: the wheelset nodes, then the bridge's
        modal node (if any)."""
        exu = self._exu
        nodes = self.nodes_exu + ([self.structure.modal_node] if self.structure is not None else [])
        q = np.concatenate([np.atleast_1d(mbs.GetNodeOutput(n, exu.OutputVariableType.Coordinates)) for n in nodes])
        v = np.concatenate([np.atleast_1d(mbs.GetNodeOutput(n, exu.OutputVariableType.Coordinates_t)) for n in nodes])
        return q, v

    def evaluate(self, mbs, t: float) -> np.ndarray:
        """Evaluate the contact at the model's current state (e.g. after a step, for outputs) without changing the
        warm start; returns :attr:`results`.  ``t`` must be the time *of that state* (the track irregularity is
        evaluated at ``s_start + V t + x``): Exudyn calls a pre-step user function with the time at the *end* of the
        coming step while the state is still at its start — pass the previous step's time there.  The evaluation is
        kept for a next :meth:`forces` call at the same state (:meth:`evaluate_state`)."""
        q, v = self.coordinates(mbs)
        self.evaluate_state(q, v, t)
        return self.results

    def warm_up(self, mbs, jacobian: bool = True) -> None:
        """Load (or compile) the compiled code outside a timed solve: one force and, with ``jacobian``, one
        Jacobian evaluation at the model's current state; the warm start is left as it was."""
        q, v = self.coordinates(mbs)
        self._kept.discard()
        warm = self._kc.warm.copy()
        try:
            self.forces(q, v, 0.0)
            if jacobian:
                self._jacobian_uf(mbs, 0.0, self.object, q, v, 1.0, 0.0)
            if self._direct is not None:
                self._direct.bind()
        finally:
            self._kc.warm[:] = warm
            self._counts[:] = 0
            self.n_jacobian_calls = self.n_jacobian_contact_calls = self.n_jacobian_differenced = 0

    def save_warm_start(self) -> np.ndarray:
        """A copy of the contact search's warm-start state (restore with :meth:`restore_warm_start`); with an
        evaluation kept by :meth:`evaluate_state`, the one it started from."""
        return self._kept.warm_start()

    def restore_warm_start(self, state: np.ndarray) -> None:
        self._kept.clear()
        self._kc.warm[:] = state

    # -- readable results ------------------------------------------------------------------------------------------
    def kernel_output(self) -> np.ndarray:
        """The contact search's output of the last evaluation behind :attr:`results`: ``(2 n, N_SLOTS, N_FIELDS)``
        per wheel (``2k`` right, ``2k+1`` left) and slot, fields ``F_*`` of :mod:`exudyn_wheelrail.contact.layout`
        in the wheel's side frame (wheel and rail parameters, normals, penetration and gap, ``dN/dδ``).  A
        read-only view, overwritten by the next evaluation (copy it to keep it)."""
        view = self._kc.out.view()
        view.flags.writeable = False
        return view

    def kernel_parameters(self) -> np.ndarray:
        """The contact search's parameter array (``P_*`` of :mod:`exudyn_wheelrail.contact.layout`), read at every
        evaluation: an entry changed here (e.g. the concave search's discretisation) applies from the next one."""
        return self._kc.params

    def wheel_force_N(self, wheelset: int, side: str) -> np.ndarray:
        """Total contact force (both regions) on a wheel, model frame, from the last evaluation."""
        w = 2 * wheelset + (0 if side == "right" else 1)
        return self.results[w, :, RES_F_TRACK_X:RES_F_TRACK_Z + 1].sum(axis=0)

    def modal_forces_N(self) -> np.ndarray:
        """Generalized modal forces on the bridge from the last evaluation (a copy; empty without a bridge)."""
        return self._f[6 * len(self.nodes_exu):].copy()

    def rail_forces_N(self) -> np.ndarray:
        """Per wheelset the force on the rails that was projected on the deck (last evaluation): rows
        ``(Fy, Fz, Mx)`` — minus the contact forces on the wheels, y right, z down, Mx about the deck's deflected
        rail-top centre line (z down: positive turns +y towards +z); filled on and off the deck."""
        return self._rail_f.copy()

    def deck_state(self) -> np.ndarray:
        """Per wheelset the deck state under it (last evaluation): displacement ``(y, z, θ)`` of the rails' centre
        line at rail top, its material velocity ``(ẏ, ż, θ̇)`` and a 0/1 on-deck flag (zero off the deck) — relative
        to the supports (a support motion's ``y_g``, ``ẏ_g`` come on top: :meth:`ground_state`); then the residual
        flexibility there (``structures.deck_kinematics.DS_RESIDUAL``, zero without a static correction)."""
        return self._deck_state.copy()

    def deck_shape_array(self) -> np.ndarray:
        """Per wheelset the structure's mode shapes ``Φ(s)`` under it (n, 3, n_modes; rows y, z, θ of the rails,
        zero off the structure) as of the last evaluation: the connector's own array (read-only view, updated by
        every evaluation)."""
        v = self._phi_ws.view()
        v.flags.writeable = False
        return v

    def predict_rail_loads(self, forces_N) -> None:
        """Per wheelset a prediction of its generalized force on the rails ``(F_y, F_z, M_x)`` (n_wheelsets, 3;
        track frame, z down, M_x about the rails' centre line), e.g. the static wheel loads: with a structure's
        residual flexibility the contact geometry is found on rails already moved by the predicted residual
        displacement, and found again only where the solve moves them further
        (:func:`~.connector_core.series_compliance`).  The results do not depend on it beyond the geometry's
        linearization over that distance; it saves the second geometry pass."""
        F = np.asarray(forces_N, dtype=float)
        _, _, _, _, _, _, prediction = self._deck  # deck_arrays: par, the shape table, residual, prediction
        if F.shape != prediction.shape or not np.all(np.isfinite(F)):
            raise ValueError(f"forces_N of shape {F.shape}: expected finite values of shape {prediction.shape}")
        prediction[:] = F
        self._kept.discard()

    def wheelset_rail_pose(self) -> np.ndarray:
        """Per wheelset the pose relative to its rail pair that the contact search used (last evaluation): rows
        ``(y_rel, z_rel, roll_rel)`` — lateral and vertical displacement of the axle centre from the rails' centre
        line at rail top (irregularity, ground motion and deck included; in the rail pair's frame, rolled with the
        deck and the cross level) [m] and roll relative to the rails
        [rad].  ``y_rel`` is the lateral wheelset–rail displacement from the rails' centre line (a gauge deviation
        moves the rails, not their centre line)."""
        side_poses, half_gauge = self.rail_pose_arrays()
        pose = side_poses[0::2].copy()
        pose[:, 0] += half_gauge
        return pose

    def rail_pose_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """The arrays :meth:`wheelset_rail_pose` is made of, overwritten in place by every evaluation (views, not
        copies: for readers that take them once and must not allocate per state): the pose ``(c_y, c_z, roll)`` of
        each wheel relative to its rail (2 n, 3; wheel ``2k`` the right one, its rows are the wheelset's pose less
        the half gauge in ``c_y``) and per wheelset the half gauge (n,) [m]."""
        return self._side_poses, self._work[W_WHEELSET][:, WS_HALF_GAUGE]

    def geometry_statistics(self) -> dict:
        """Wheel evaluations answered by the geometry table and by the online search since the start (both count
        the Jacobian's perturbed calls)."""
        st = self._stats
        return {"mode": self.geometry, "wheel_evaluations_table": int(st[STAT_TABLE]),
                "wheel_evaluations_online": int(st[STAT_FALLBACK]),
                "table": self.geometry_table.describe() if self.geometry_table is not None else None}

    def skipped(self) -> dict:
        """What the contact evaluation skipped since the start, because the scene did not need it (counts include
        the Jacobian's perturbed calls).  Each skip is tested to change results by less than a stated tolerance
        (tests/test_skips.py)."""
        st = self._stats
        n_online = int(st[STAT_FALLBACK])
        n_regions = 2 * n_online
        frac = (lambda a, b: float(a) / b if b else 0.0)
        return {
            "contact_search_by_geometry_table": {
                "skipped": int(st[STAT_TABLE]), "of_wheel_evaluations": int(st[STAT_TABLE]) + n_online,
                "what": "the online search replaced by the precomputed geometry (rigid rail profile)"
                        + ("" if self.geometry == "table" else "; off (geometry 'online')")},
            "flange_search_far_from_flange": {
                "skipped": int(st[STAT_FLANGE_SKIPPED]), "of_online_flange_regions": n_online,
                "fraction": frac(st[STAT_FLANGE_SKIPPED], n_online),
                "what": "flange region reported apart by the separation bound (gap larger than the motion since "
                        "its last search), no search"},
            "tread_search_lifted_off": {
                "skipped": int(st[STAT_TREAD_SKIPPED]), "of_online_tread_regions": n_online,
                "what": "tread region reported apart by the separation bound (wheel lifted), no search"},
            "concave_search": {
                "run": int(st[STAT_CONCAVE]), "skipped": n_regions - int(st[STAT_CONCAVE]),
                "of_online_regions": n_regions,
                "what": "the concave (discretised) search runs only where the convex one fails or lands on a "
                        "conformal point"},
            "bridge_coupling": {
                "skipped": int(st[STAT_OFF_DECK]) if self.structure is not None else None,
                "of_wheelset_evaluations": int(st[STAT_ON_DECK] + st[STAT_OFF_DECK]),
                "what": "deck state and modal projection only for wheelsets on the deck"
                        + ("" if self.structure is not None else "; no bridge in this model")},
            "spin_terms": {"skipped": 0, "what": "not skipped: the creep laws always include spin"},
        }

    def flange_contact(self, wheelset: int, side: str) -> bool:
        """Whether the flange region carries a contact (last evaluation)."""
        w = 2 * wheelset + (0 if side == "right" else 1)
        return bool(self.results[w, 1, RES_STATUS] > 0 and self.results[w, 1, RES_N] > 0.0)


def add_wheel_rail_contact(mbs, wheelset_nodes, pair: WheelRailPair, **options) -> WheelRailContact:
    """Add the wheel–rail contact of the given wheelset nodes to ``mbs`` (before ``mbs.Assemble()``); options as
    :class:`WheelRailContact`.  Returns the contact handle (results, forces, the Exudyn object number)."""
    return WheelRailContact(mbs, wheelset_nodes, pair, **options)

