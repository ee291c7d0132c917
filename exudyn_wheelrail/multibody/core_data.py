"""The packed arguments of the compiled contact call (:mod:`.connector_core`): the fields of its ``model``, ``state``
and ``work`` tuples by name, the functions that build them, the :class:`ContactData` that carries them in one
argument, and :func:`compiled_for` (a compiled specialization called without numba's type dispatch).

:class:`~.connector.WheelRailContact` packs everything once at construction and hands it over as

``contact_forces_core(q, q_t, t, data, f_out, res)``

* ``q``, ``q_t`` (6 n + n_m): per wheelset displacement (global), rotation vector, velocity (global) and body-frame
  angular velocity (Lie-group node coordinates), then the n_m modal coordinates of the bridge (none without one);
  ``t`` the time [s];
* ``data`` — a :class:`ContactData` (:func:`contact_data`) holding the three tuples below as ``data.model``,
  ``data.state`` and ``data.work``: one argument for numba to unbox per call instead of the forty arrays in them
  (about 0.1 µs each);
* ``model`` — constant data, ``model[MODEL_*]`` (:func:`model_tuple`): ``(vehicle, track, geometry, creep, deck)``:

  - ``vehicle[VEH_*]`` (:func:`vehicle_tuple`) ``= (p_ref, frame, layout, layout_par)``: reference positions
    (n, 3) [m] of the wheelset nodes (track/model frame), ``frame[FRAME_*]`` (running speed V [m/s], 1.0 for a
    model frame moving with V, track distance s_start [m] of the frame's origin at t = 0, 1.0 on a curved layout,
    the gradient's pitch [rad]) and the track layout's packed pieces and parameters
    (:func:`~exudyn_wheelrail.track.layout.layout_at`; read only when ``frame[FRAME_CURVED]`` is set; ``None`` on
    straight track);
  - ``track``: the irregularity's packed arrays ``(rows, knots, coefs)``
    (:func:`~exudyn_wheelrail.track.rigid.irregularity_channels_at`: alignment, vertical level, cross level and
    gauge deviation);
  - ``geometry[GEO_*]`` (:func:`geometry_tuple`) ``= (nodes, meta, mono, curve_ids, params, table, scan, patch)``: the
    profiles and kernel parameters of a :class:`~exudyn_wheelrail.contact.WheelsetContact`, the geometry table's
    ``(par, cz_ref, data)`` (:func:`~exudyn_wheelrail.contact.geometry_table.evaluate_wheels_tabulated`; ``None``
    for the online search, :func:`~.connector_core.contact_geometry`), the coarse scan's cached wheel points
    (:func:`~exudyn_wheelrail.contact.kernel.scan_array`) and the non-Hertzian patch's parameters
    (:func:`~exudyn_wheelrail.contact.patch_table.patch_argument`; ``None`` for Hertz);
  - ``creep``: ``(code, cp, t_nodes, coef, tab)`` of :func:`~exudyn_wheelrail.creep.registry.creep_model`;
  - ``deck``: :func:`~exudyn_wheelrail.structures.deck_kinematics.deck_arrays` (ground motion at t in its
    ``par``);

* ``state`` — arrays the call reads and updates, ``state[ST_*]`` (:func:`state_tuple`): ``(warm, out, side_poses,
  stats, rail_delta, phi_ws, rail_f, deck_state)``: the kernel's warm start and output, the per-wheel pose relative
  to the rails (2 n, 3), the ``STAT_*`` counters, the increments added to the deck state of every wheelset on the
  deck (n, 6; zero, the Jacobian perturbs it), and per wheelset ``Φ(s)`` (n, 3, n_m), the force on the rails
  ``(F_y, F_z, M_x)`` that is projected (n, 3) and the deck state (n, ``N_DECK_STATE``);
* ``work`` — scratch the call overwrites, allocated once (:func:`work_arrays`; nothing is allocated per call),
  ``work[W_*]``: ``(deck_work, rot, wheelset, vec, frame, lay, residual, contacts, series, index)``: the deck's rail
  state (9,), per wheelset its rotation matrix (n, 3, 3) and the quantities ``WS_*`` of its pose (n, ``N_WS``), the
  vectors ``V_*`` of a contact (``N_VEC``, 3), the contact frame (3, 3), the layout values at a wheelset (4,), and
  for a structure with residual flexibility (:func:`~.connector_core.series_compliance`) per wheelset the rails'
  residual displacement where the geometry was found and the solve's (n, 6), a wheelset's contacts
  (2 ``N_SLOTS``, ``N_SC``), the solve's scratch (7, 3) and the contacts' wheel and region (2 ``N_SLOTS``, 2);
* ``f_out`` (6 n + n_m): force (global) and torque (body frame) per wheelset, then the generalized modal forces;
  ``res`` (2 n, N_SLOTS, N_RES) the results (``RES_*``).

The indices are module constants: numba reads a tuple field at a constant index as the field itself (the same
machine code as a literal index).
"""
from __future__ import annotations

import numba
import numpy as np
from numba import types
from numba.experimental import structref

from ..contact.geometry_table import scratch_array as geometry_scratch
from ..contact.layout import N_SLOTS
from ..jit import compiled
from ..structures.deck_kinematics import N_SC
from ..track.layout import N_LAYOUT

__all__ = ["FRAME_SPEED", "FRAME_MOVING", "FRAME_S_START", "FRAME_CURVED", "FRAME_PITCH", "N_FRAME", "MODEL_VEHICLE",
           "MODEL_TRACK", "MODEL_GEOMETRY", "MODEL_CREEP", "MODEL_DECK", "VEH_P_REF", "VEH_FRAME", "VEH_LAYOUT",
           "VEH_LAYOUT_PAR", "GEO_NODES", "GEO_META", "GEO_MONO", "GEO_CURVE_IDS", "GEO_PARAMS", "GEO_TABLE",
           "GEO_SCAN", "GEO_PATCH", "ST_WARM", "ST_OUT", "ST_SIDE_POSES", "ST_STATS", "ST_RAIL_DELTA", "ST_PHI_WS",
           "ST_RAIL_F", "ST_DECK_STATE", "W_DECK", "W_ROT", "W_WHEELSET", "W_VEC", "W_FRAME", "W_LAYOUT", "W_RESIDUAL", "W_CONTACTS",
           "W_SERIES", "W_INDEX", "W_GEOMETRY", "model_tuple", "vehicle_tuple", "geometry_tuple", "state_tuple",
           "work_arrays", "ContactData", "contact_data", "compiled_for"]

# ---- model frame: frame[FRAME_*] ---------------------------------------------------------------------------------
FRAME_SPEED = 0       # running speed V [m/s]
FRAME_MOVING = 1      # 1.0: the model frame translates with V (rail material velocity -V); 0.0: fixed to the track
FRAME_S_START = 2     # track distance of the frame's origin at t = 0 [m]
FRAME_CURVED = 3      # 1.0: the wheelsets follow a track layout (creepage terms of the turning frame)
FRAME_PITCH = 4       # the layout's gradient as a pitch angle θ [rad]
N_FRAME = 5

# ---- per wheelset quantities of the call: work[2][k, WS_*] ----------------------------------------------------------
WS_S = 0              # track distance s of the axle centre [m]
WS_ROLL = 1           # roll and yaw of the wheelset (from its axle direction) [rad]
WS_YAW = 2
WS_COS_ROLL = 3       # their cosines and sines
WS_SIN_ROLL = 4
WS_COS_YAW = 5
WS_SIN_YAW = 6
WS_Y_RAIL = 7         # the rails' centre line under the wheelset (irregularity, ground, deck) [m]
WS_Z_RAIL = 8
WS_COS_TH = 9         # cosine and sine of the rail pair's roll θ (deck roll + cross level)
WS_SIN_TH = 10
WS_HALF_GAUGE = 11    # half the gauge deviation: each rail's outward shift in its side frame [m]
N_WS = 12

# ---- vectors of one contact (track frame): work[3][V_*] -----------------------------------------------------------
V_P_CONTACT = 0       # contact point [m]
V_N_RAIL = 1          # outward rail normal
V_E_AXLE = 2          # wheelset axle direction
V_P_CENTRE = 3        # axle centre [m]
V_V_CENTRE = 4        # its velocity [m/s]
V_OMEGA = 5           # wheelset angular velocity [rad/s]
V_V_RAIL = 6          # rail material velocity at the contact [m/s]
V_OMEGA_RAIL = 7      # rail angular velocity [rad/s]
N_VEC = 8

# ---- the model tuple: model[MODEL_*] (model_tuple) ------------------------------------------------------------------
MODEL_VEHICLE = 0     # vehicle[VEH_*]
MODEL_TRACK = 1       # the irregularity's (rows, knots, coefs)
MODEL_GEOMETRY = 2    # geometry[GEO_*]
MODEL_CREEP = 3       # the creep law's (code, cp, t_nodes, coef, tab)
MODEL_DECK = 4        # the deck arrays (structures.deck_kinematics.deck_arrays)

# ---- the vehicle: model[MODEL_VEHICLE][VEH_*] (vehicle_tuple) -------------------------------------------------------
VEH_P_REF = 0         # reference positions of the wheelset nodes (n, 3) [m]
VEH_FRAME = 1         # frame[FRAME_*]
VEH_LAYOUT = 2        # the track layout's packed pieces (None on straight track)
VEH_LAYOUT_PAR = 3    # and its parameters (None on straight track)

# ---- the contact geometry: model[MODEL_GEOMETRY][GEO_*] (geometry_tuple) --------------------------------------------
GEO_NODES = 0         # the profiles' nodes, metadata, monotonicity and curve ids of every wheel
GEO_META = 1
GEO_MONO = 2
GEO_CURVE_IDS = 3
GEO_PARAMS = 4        # the kernel's parameters per wheel
GEO_TABLE = 5         # the geometry table's (par, cz_ref, data), or None for the online search
GEO_SCAN = 6          # the coarse scan's cached wheel points
GEO_PATCH = 7         # the non-Hertzian patch's argument (contact.patch_table.patch_argument), or None for Hertz

# ---- the updated arrays: state[ST_*] (state_tuple) ------------------------------------------------------------------
ST_WARM = 0           # the kernel's warm start
ST_OUT = 1            # the kernel's output (2 n, N_SLOTS, N_FIELDS)
ST_SIDE_POSES = 2     # the pose of each wheel relative to its rail (2 n, 3)
ST_STATS = 3          # the STAT_* counters
ST_RAIL_DELTA = 4     # increments of the deck state per wheelset (n, 6; the Jacobian perturbs them)
ST_PHI_WS = 5         # Φ(s) per wheelset (n, 3, n_m)
ST_RAIL_F = 6         # the force on the rails per wheelset (n, 3): F_y, F_z, M_x
ST_DECK_STATE = 7     # the deck state per wheelset (n, N_DECK_STATE)

# ---- the scratch: work[W_*] (work_arrays) ---------------------------------------------------------------------------
W_DECK = 0            # the deck's rail state (9,)
W_ROT = 1             # per wheelset its rotation matrix (n, 3, 3)
W_WHEELSET = 2        # per wheelset the quantities WS_* (n, N_WS)
W_VEC = 3             # the vectors V_* of a contact (N_VEC, 3)
W_FRAME = 4           # the contact frame (3, 3)
W_LAYOUT = 5          # the layout values at a wheelset (N_LAYOUT,)
W_RESIDUAL = 6        # per wheelset the rails' residual displacement: where the geometry was found, the solve's (n, 6)
W_CONTACTS = 7        # a wheelset's contacts in series with the residual flexibility (2 N_SLOTS, N_SC)
W_SERIES = 8          # the series solve's scratch (7, 3)
W_INDEX = 9           # the contacts' wheel and region (2 N_SLOTS, 2)
W_GEOMETRY = 10       # the geometry stage's scratch (contact.geometry_table.scratch_array)


def model_tuple(vehicle, track, geometry, creep, deck) -> tuple:
    """The constant data ``model`` of the compiled call, ``model[MODEL_*]`` (module docstring)."""
    return (vehicle, track, geometry, creep, deck)


def vehicle_tuple(p_ref, frame, layout, layout_par) -> tuple:
    """``model[MODEL_VEHICLE]``, read as ``vehicle[VEH_*]`` (module docstring)."""
    return (p_ref, frame, layout, layout_par)


def geometry_tuple(nodes, meta, mono, curve_ids, params, table, scan, patch) -> tuple:
    """``model[MODEL_GEOMETRY]``, read as ``geometry[GEO_*]`` (module docstring)."""
    return (nodes, meta, mono, curve_ids, params, table, scan, patch)


def state_tuple(warm, out, side_poses, stats, rail_delta, phi_ws, rail_f, deck_state) -> tuple:
    """The updated arrays ``state`` of the compiled call, ``state[ST_*]`` (module docstring)."""
    return (warm, out, side_poses, stats, rail_delta, phi_ws, rail_f, deck_state)


def work_arrays(n_wheelsets: int) -> tuple:
    """The scratch tuple ``work`` of the compiled call (module docstring) for ``n_wheelsets``."""
    return (np.zeros(9), np.zeros((n_wheelsets, 3, 3)), np.zeros((n_wheelsets, N_WS)),
            np.zeros((N_VEC, 3)), np.zeros((3, 3)), np.zeros(N_LAYOUT), np.zeros((n_wheelsets, 6)),
            np.zeros((2 * N_SLOTS, N_SC)), np.zeros((7, 3)), np.zeros((2 * N_SLOTS, 2), dtype=np.int64),
            geometry_scratch())


@structref.register
class ContactDataType(types.StructRef):
    """Numba type of :class:`ContactData`."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class ContactData(structref.StructRefProxy):
    """The ``model``, ``state`` and ``work`` tuples of the compiled call in one object (module docstring); build it
    with :func:`contact_data`."""


structref.define_constructor(ContactData, ContactDataType, ["model", "state", "work"])
structref.define_boxing(ContactDataType, ContactData)


@compiled
def contact_data(model, state, work):
    """The :class:`ContactData` of the tuples (compiled and cached, like the calls that take it)."""
    return ContactData(model, state, work)


def compiled_for(dispatcher, *args):
    """The compiled specialization of the numba ``dispatcher`` for the types of ``args``, callable from Python
    without numba's type dispatch (for the contact call's arguments about 0.6 µs of the about 0.9 µs it costs per
    call).  The caller must then pass arguments of exactly these types (arrays of the same dtype, dimension and
    layout: nothing is checked).  Returns the dispatcher itself when numba offers no such entry."""
    compile_ = getattr(dispatcher, "compile", None)
    if compile_ is None:
        return dispatcher
    entry = compile_(tuple(numba.typeof(a) for a in args))
    return entry if callable(entry) else dispatcher

