r"""Railway bridge: a 3-D Euler–Bernoulli beam deck on supports, reduced with its eigenmodes, entered into Exudyn.

>>> model = BridgeModel(spans_m=(20.0, 20.0), section=DeckSection(m_kg_m=15e3, EI_y_Nm2=2.4e10,
...                     EI_z_Nm2=1e11, GJ_Nm2=6e9, EA_N=2e11, Ip_kgm2_m=6e4), continuous=True,
...                     damping_ratio=0.02, rail_height_m=1.0, start_m=100.0)          # doctest: +SKIP
>>> modes = model.modes(f_max_Hz=60.0)                                                   # doctest: +SKIP
>>> bridge = add_bridge(mbs, modes, formulation="modal")                                # doctest: +SKIP
>>> bridge.add_moving_forces(mbs, x_m=[0.0], forces_N=[[0.0, 1e5, 0.0]], speed_m_s=50.0)  # doctest: +SKIP

Frames
------
The deck axis runs along the track: **deck coordinate** ``x = s - start_m`` (``s`` the track distance of
:mod:`exudyn_wheelrail.conventions`), ``y`` right, ``z`` **down** — the track frame, fixed to the ground (the
bridge does not move with the running speed; see the coupling note below for the moving model frame).  The beam
axis is the deck's shear centre and centre of mass (no mass or shear-centre eccentricity); the top of rail lies
``e_z = rail_height_m`` **above** it (at ``z = -e_z``).  Nodal degrees of freedom, 6 per node, in the track frame:
``(u, v, w, θx, θy, θz)`` — displacements along x, y, z and small rotations about x, y, z (right-hand rule).

* vertical bending (in the x–z plane, stiffness ``EI_y``): ``w(x)``, with ``dw/dx = -θy`` (a positive rotation
  about +y turns +x towards -z);
* lateral bending (x–y plane, ``EI_z``): ``v(x)``, with ``dv/dx = +θz``;
* torsion (``GJ``, mass moment of inertia per length ``I_p``): ``θx(x)``; axial (``EA``): ``u(x)``.

Rail kinematics (derivation).  A deck point at ``r = (0, y_r, -e_z)`` from the axis moves by ``u + θ × r``:
``Δy = v - r_z θx = v + e_z θx`` and ``Δz = w + y_r θx``.  Hence a positive torsion (right-hand about +x: the
right side, y > 0, goes down) moves the top of rail to the **right** by ``e_z θx``.  The quantities the contact
needs at track distance s are the displacement of the **track centre line at rail-top level** and the rail roll:

    ``y_rail = v + e_z θx``,   ``z_rail = w``,   ``θ_rail = θx``

(the rail at lateral position ``y_c`` moves down by ``z_rail + y_c θ_rail``).  In modal coordinates ``q``:
``(y_rail, z_rail, θ_rail) = Φ(s) q`` with the (3 × n_modes) matrix ``Φ(s)`` of :func:`modal_shape_at`: nodal
mode values and slopes interpolated with the element's own shape functions (cubic Hermite for v, w; linear for
θx), so the interpolation is the one the mass and stiffness matrices were integrated with.  Dual: a force
``(Fy, Fz)`` acting on the rails' centre line at rail-top level at s and a moment ``Mx`` about that line give the
generalized modal forces ``Q = Φ(s)^T (Fy, Fz, Mx)`` (:func:`add_projected_force`; virtual work ``δW = Fy δy_rail
+ Fz δz_rail + Mx δθ_rail``).  A force ``F`` at a rail point ``(y_c, z_c)`` (relative to the centre line at
rail-top level) has ``Mx = y_c Fz - z_c Fy``.  Off the deck ``Φ = 0``.  Longitudinal forces are not projected
(the axial modes exist in the model but no x row is provided; open point).

Beam model
----------
One or more spans (``spans_m``), each meshed with ``elements_per_span`` equal 2-node 3-D Euler–Bernoulli elements
(consistent mass: ``m`` for the three translations — bending by the Hermite cubics, axial by the linear functions
— and ``I_p`` for torsion; bending rotary inertia neglected, as in Euler–Bernoulli theory), element matrices
integrated by 4-point Gauss quadrature (exact).  ``continuous=False``: a chain of independent simply supported
decks (the nodes at a joint are doubled); ``continuous=True``: one deck continuous over the intermediate
supports.  Every support fixes ``v, w, θx`` (fork bearing; bending rotations free); ``u`` is fixed at the first
node of every independent deck.  :meth:`BridgeModel.assemble` gives ``(M, K)`` (scipy sparse), :meth:`BridgeModel.modes`
the mass-normalised eigenmodes (``Φ^T M Φ = I``, ``Φ^T K Φ = diag(ω²)``) for a number of modes or up to a
frequency, with modal damping ``2 ζ ω`` (one ratio for all modes).  Craig–Bampton modes are not provided: with
rigid supports there are no interface coordinates to keep (they matter once piers or a soil model are added).

Mesh accuracy (tests/test_bridge.py, 20 elements per span): bending frequencies 4e-7, 7e-6, 3e-5 above the
Euler–Bernoulli values for n = 1, 2, 3; torsion (linear elements, consistent mass) ``≈ (nπ/n_e)²/24`` too high
(the exact discrete dispersion is tested): 0.10 % and 0.41 % for the first two torsion modes.

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

Coupling to the wheel–rail connector
------------------------------------
The connector (:mod:`exudyn_wheelrail.multibody.connector`) extends its zero-mass ``ObjectGenericODE2`` by
:attr:`ExudynBridge.modal_node`: its coordinate vector becomes ``[6 per wheelset..., n_modes modal]`` and its force
user function returns the wheelset forces followed by the generalized modal forces ``Q``, all in **one** compiled
call per right-hand-side evaluation (no LoadCoordinate per mode, no sensor or pre-step lag).  Exudyn accepts a
GenericODE2 over a Lie-group rigid node and a NodeGenericODE2 (explicit RK44 and generalized-α; checked by
``tests/test_bridge.py::test_coupling_*`` against the closed-form linear solution); the modal node is the same for
both formulations, so the coupling does not depend on the choice.  How the deck moves the rails under a wheel
(displacement ``Φ(s) q``, material velocity ``Φ(s) q̇``, roll) and where the rail forces go (``Q += Φ(s)^T (F_y,
F_z, M_x)``) is :mod:`.deck_kinematics`, built on :func:`modal_shape_at`, :func:`shapes_times` and
:func:`project_shapes`.  The rate
of the rail geometry under the moving wheel, ``Φ(s) q̇ + V Φ'(s) q`` (:func:`modal_shape_and_slope_at`), enters
the contact through the position dependence only; the creepages see the material velocity.

Lateral support motion (earthquake-like; :mod:`.support_motion`)
-----------------------------------------------------------------
:meth:`ExudynBridge.add_support_motion` imposes a lateral ground displacement ``y_g(t)`` on all supports together
(synchronous ground motion).  Relative-motion formulation, exact for the linear deck: absolute deck displacement =
rigid lateral translation ``y_g`` (the supports carry the deck along) + ``Φ q``, with the effective load
``-Γ ÿ_g(t)`` on the modal equations (``Γ = Φᵀ M r``, :meth:`BridgeModes.participation_factors`); the
connector adds ``y_g`` and ``ẏ_g`` to the rails' lateral position and material velocity under every wheelset
(on the deck and off it).  Measured (tests/test_bridge_support_motion.py, a 20 m span, 20 elements): ``Γ_n`` of
the first six lateral modes within 3.4e-6 Γ_1 of ``2√(2mL)/(nπ)`` (0 for even n and for all other mode kinds);
the static modal sum ``-Σ φ_n(L/2) Γ_n/ω_n² ÿ_g`` is the beam under the uniform inertia load,
``-5 m ÿ_g L⁴/(384 EI_z)``, within 4.4e-6; under a harmonic ground acceleration at 0.8 f_1 (ζ = 5 %) the
first lateral mode's history agrees with the single-DOF equation to 5e-4 of its peak and its steady state with
the amplification ``1/√((1-r²)²+(2ζr)²) = 2.711`` to 3e-4.

References
----------
L. Frýba, *Vibration of solids and structures under moving loads*, Noordhoff 1972 / Thomas Telford 1999, Ch. 1
(simply supported beam under a moving constant force: the modal series solution).  L. Frýba, A rough assessment
of railway bridges for high speed trains, Engineering Structures 23 (2001) 548–556 (trains of equally spaced
forces, resonance speeds ``v = f_1 d / k``).  J. S. Przemieniecki, *Theory of matrix structural analysis*, 1968
(3-D beam element).  P. A. Montenegro, S. G. M. Neves, R. Calçada, M. Tanabe, M. Sogabe, Computers & Structures 152 (2015)
200–214 (the train–bridge interaction that this model is for).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import exudyn as exu
import numpy as np
import scipy.linalg
import scipy.sparse as sp

from ..jit import compiled

__all__ = [
    "DeckSection", "BridgeModel", "BridgeModes", "ShapeTable", "ExudynBridge", "MovingForces", "FORMULATIONS",
    "add_bridge", "modal_shape_at", "modal_shape_and_slope_at", "rail_state_at", "add_projected_force",
    "shapes_times", "project_shapes",
    "fryba_moving_force",
]

FORMULATIONS = ("modal", "ffrf")

#: nodal degrees of freedom, in this order
DOF_NAMES = ("u", "v", "w", "theta_x", "theta_y", "theta_z")
N_DOF_NODE = 6
#: DOF groups (mode kinds): vertical = (w, θy), lateral = (v, θz), torsion = θx, axial = u
_GROUPS = {"axial": (0,), "lateral": (1, 5), "vertical": (2, 4), "torsion": (3,)}
#: rows of the node-shape table: v, dv/dx, w, dw/dx, θx
_NS_V, _NS_DV, _NS_W, _NS_DW, _NS_TH = range(5)

_DENSE_EIGEN_LIMIT = 2000          # free DOFs up to which the dense generalized eigen solver is used


# ----------------------------------------------------------------------------------------------- input checks
def _finite(name, value, *, positive=False, non_negative=False):
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name}={value!r}: expected a number") from None
    if not math.isfinite(x):
        raise ValueError(f"{name}={value!r}: expected a finite number")
    if positive and not x > 0.0:
        raise ValueError(f"{name}={value!r}: expected a value > 0")
    if non_negative and not x >= 0.0:
        raise ValueError(f"{name}={value!r}: expected a value >= 0")
    return x


# --------------------------------------------------------------------------------------------------- section
@dataclass(frozen=True)
class DeckSection:
    """Cross-section of the deck (the beam axis is shear centre and centre of mass), SI units.

    m_kg_m : mass per length [kg/m] (deck, ballast/slab and track).
    EI_y_Nm2 : vertical bending stiffness (bending in the x–z plane, about the y axis) [N m²].
    EI_z_Nm2 : lateral bending stiffness (x–y plane, about z) [N m²].
    GJ_Nm2 : torsional stiffness (St Venant) [N m²].
    EA_N : axial stiffness [N].
    Ip_kgm2_m : mass moment of inertia per length about the beam axis [kg m²/m] (torsional inertia).
    """

    m_kg_m: float
    EI_y_Nm2: float
    EI_z_Nm2: float
    GJ_Nm2: float
    EA_N: float
    Ip_kgm2_m: float

    def __post_init__(self):
        for f in ("m_kg_m", "EI_y_Nm2", "EI_z_Nm2", "GJ_Nm2", "EA_N", "Ip_kgm2_m"):
            object.__setattr__(self, f, _finite(f"DeckSection.{f}", getattr(self, f), positive=True))

    # analytic references for a simply supported span of length L (Euler–Bernoulli, St Venant torsion)
    def vertical_frequency_Hz(self, L_m: float, n: int = 1) -> float:
        """``f_n = n²π/(2L²) √(EI_y/m)`` of a simply supported span."""
        L = _finite("L_m", L_m, positive=True)
        return n * n * math.pi / (2.0 * L * L) * math.sqrt(self.EI_y_Nm2 / self.m_kg_m)

    def lateral_frequency_Hz(self, L_m: float, n: int = 1) -> float:
        """``f_n = n²π/(2L²) √(EI_z/m)`` of a simply supported span."""
        L = _finite("L_m", L_m, positive=True)
        return n * n * math.pi / (2.0 * L * L) * math.sqrt(self.EI_z_Nm2 / self.m_kg_m)

    def torsion_frequency_Hz(self, L_m: float, n: int = 1) -> float:
        """``f_n = n/(2L) √(GJ/I_p)`` of a span with torsion fixed at both ends."""
        L = _finite("L_m", L_m, positive=True)
        return n / (2.0 * L) * math.sqrt(self.GJ_Nm2 / self.Ip_kgm2_m)


# -------------------------------------------------------------------------------------------- shape functions
def _hermite(xi, Le):
    """Cubic Hermite functions on [0, 1] for (value_a, slope_a, value_b, slope_b) and their x-derivatives."""
    N = np.array([1 - 3 * xi ** 2 + 2 * xi ** 3, Le * (xi - 2 * xi ** 2 + xi ** 3), 3 * xi ** 2 - 2 * xi ** 3,
                  Le * (-xi ** 2 + xi ** 3)])
    dN = np.array([(-6 * xi + 6 * xi ** 2) / Le, 1 - 4 * xi + 3 * xi ** 2, (6 * xi - 6 * xi ** 2) / Le,
                   -2 * xi + 3 * xi ** 2])
    ddN = np.array([(-6 + 12 * xi) / Le ** 2, (-4 + 6 * xi) / Le, (6 - 12 * xi) / Le ** 2, (-2 + 6 * xi) / Le])
    return N, dN, ddN


# element DOF indices (12 = 2 nodes × 6) and the sign that maps the nodal DOF to the slope of the Hermite cubic
_LAT_IDX = np.array([1, 5, 7, 11])          # v_a, θz_a, v_b, θz_b        (dv/dx = +θz)
_LAT_SIGN = np.array([1.0, 1.0, 1.0, 1.0])
_VER_IDX = np.array([2, 4, 8, 10])          # w_a, θy_a, w_b, θy_b        (dw/dx = -θy)
_VER_SIGN = np.array([1.0, -1.0, 1.0, -1.0])
_AX_IDX = np.array([0, 6])
_TOR_IDX = np.array([3, 9])


def element_matrices(Le: float, section: DeckSection) -> tuple[np.ndarray, np.ndarray]:
    """Consistent mass and stiffness matrices (12 × 12, DOFs ``u, v, w, θx, θy, θz`` of node a then b) of a
    3-D Euler–Bernoulli element of length ``Le``, by 4-point Gauss quadrature of the shape functions."""
    gp, gw = np.polynomial.legendre.leggauss(4)
    xs = 0.5 * (gp + 1.0)
    ws = 0.5 * gw * Le
    Me = np.zeros((12, 12))
    Ke = np.zeros((12, 12))
    for xi, w in zip(xs, ws):
        N, _, ddN = _hermite(xi, Le)
        L = np.array([1.0 - xi, xi])
        dL = np.array([-1.0, 1.0]) / Le
        for idx, sign, EI in ((_LAT_IDX, _LAT_SIGN, section.EI_z_Nm2), (_VER_IDX, _VER_SIGN, section.EI_y_Nm2)):
            n = N * sign
            b = ddN * sign
            Me[np.ix_(idx, idx)] += w * section.m_kg_m * np.outer(n, n)
            Ke[np.ix_(idx, idx)] += w * EI * np.outer(b, b)
        Me[np.ix_(_AX_IDX, _AX_IDX)] += w * section.m_kg_m * np.outer(L, L)
        Ke[np.ix_(_AX_IDX, _AX_IDX)] += w * section.EA_N * np.outer(dL, dL)
        Me[np.ix_(_TOR_IDX, _TOR_IDX)] += w * section.Ip_kgm2_m * np.outer(L, L)
        Ke[np.ix_(_TOR_IDX, _TOR_IDX)] += w * section.GJ_Nm2 * np.outer(dL, dL)
    return Me, Ke


# ------------------------------------------------------------------------------------------------ the model
@dataclass(frozen=True)
class BridgeModel:
    """A bridge deck of one or more spans as a 3-D Euler–Bernoulli beam along the track (module docstring).

    spans_m : span lengths [m], in running order.
    section : one :class:`DeckSection` for all spans or one per span.
    continuous : ``False`` — every span a separate simply supported deck; ``True`` — one deck continuous over the
        intermediate supports.
    damping_ratio : modal damping ratio ζ of every mode (0 ≤ ζ < 1).
    rail_height_m : ``e_z``, height of the top of rail above the beam axis [m] (≥ 0; torsion then moves the rail
        laterally by ``e_z θx``).
    start_m : track distance s of the first abutment (deck coordinate x = s - start_m).
    elements_per_span : beam elements per span (≥ 2).
    """

    spans_m: tuple
    section: DeckSection | tuple
    continuous: bool = False
    damping_ratio: float = 0.0
    rail_height_m: float = 0.0
    start_m: float = 0.0
    elements_per_span: int = 20
    _mesh: dict = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self):
        spans = self.spans_m
        if isinstance(spans, (str, bytes)):
            raise TypeError(f"spans_m={spans!r}: expected a number or a sequence of span lengths [m]")
        if isinstance(spans, (int, float)):
            spans = (spans,)
        try:
            spans = tuple(spans)
        except TypeError:
            raise TypeError(f"spans_m={self.spans_m!r}: expected a sequence of span lengths [m]") from None
        if not spans:
            raise ValueError("spans_m is empty: give at least one span length [m]")
        spans = tuple(_finite(f"spans_m[{i}]", L, positive=True) for i, L in enumerate(spans))
        object.__setattr__(self, "spans_m", spans)
        sections = self.section
        if isinstance(sections, DeckSection):
            sections = (sections,) * len(spans)
        else:
            try:
                sections = tuple(sections)
            except TypeError:
                sections = None
            if sections is None or isinstance(self.section, (str, bytes)) or not all(
                    isinstance(s, DeckSection) for s in sections):
                raise TypeError(f"section={self.section!r}: expected a DeckSection or a sequence of DeckSection, one "
                                "per span")
            if len(sections) != len(spans):
                raise ValueError(f"section: {len(sections)} sections given for {len(spans)} spans (give one for all "
                                 "or one per span)")
        object.__setattr__(self, "section", sections)
        if not isinstance(self.continuous, (bool, np.bool_)):
            raise TypeError(f"continuous={self.continuous!r}: expected True or False")
        z = _finite("damping_ratio", self.damping_ratio, non_negative=True)
        if not z < 1.0:
            raise ValueError(f"damping_ratio={z}: expected 0 <= ζ < 1 (a ratio, not a percentage)")
        object.__setattr__(self, "damping_ratio", z)
        object.__setattr__(self, "rail_height_m", _finite("rail_height_m", self.rail_height_m, non_negative=True))
        object.__setattr__(self, "start_m", _finite("start_m", self.start_m))
        ne = self.elements_per_span
        if isinstance(ne, bool) or not isinstance(ne, (int, np.integer)) or ne < 2:
            raise ValueError(f"elements_per_span={ne!r}: expected an integer >= 2")
        object.__setattr__(self, "_mesh", self._build_mesh())

    # -- mesh -----------------------------------------------------------------------------------------------
    def _build_mesh(self) -> dict:
        ne = int(self.elements_per_span)
        x_nodes, elements, supports, axial_fixed = [], [], [], []
        x0 = 0.0
        for k, L in enumerate(self.spans_m):
            if k == 0 or not self.continuous:
                first = len(x_nodes)
                x_nodes.append(x0)
                supports.append(first)
                if k == 0 or not self.continuous:
                    axial_fixed.append(first)
            else:
                first = len(x_nodes) - 1             # shared node over the intermediate support
            Le = L / ne
            for j in range(ne):
                x_nodes.append(x0 + L * (j + 1) / ne)
                elements.append((first + j, first + j + 1, x0 + L * j / ne, Le, k))
            supports.append(len(x_nodes) - 1)
            x0 += L
        x_nodes = np.array(x_nodes)
        fixed = set()
        for n in supports:
            fixed.update((N_DOF_NODE * n + 1, N_DOF_NODE * n + 2, N_DOF_NODE * n + 3))   # v, w, θx
        for n in axial_fixed:
            fixed.add(N_DOF_NODE * n)
        n_dof = N_DOF_NODE * len(x_nodes)
        free = np.array(sorted(set(range(n_dof)) - fixed), dtype=np.int64)
        return dict(x_nodes=x_nodes, elements=elements, supports=sorted(set(supports)), free=free, n_dof=n_dof,
                    fixed=np.array(sorted(fixed), dtype=np.int64))

    @property
    def length_m(self) -> float:
        """Total deck length [m]."""
        return float(sum(self.spans_m))

    @property
    def node_x_m(self) -> np.ndarray:
        """Deck coordinates of the nodes [m] (doubled at the joints of separate spans)."""
        return self._mesh["x_nodes"].copy()

    @property
    def n_nodes(self) -> int:
        return len(self._mesh["x_nodes"])

    @property
    def n_dof(self) -> int:
        """Number of nodal DOFs before the supports (6 per node)."""
        return self._mesh["n_dof"]

    @property
    def support_x_m(self) -> np.ndarray:
        """Deck coordinates of the supports [m]."""
        return np.unique(self._mesh["x_nodes"][self._mesh["supports"]])

    def free_dofs(self) -> np.ndarray:
        """Global indices (``6 node + DOF``) of the DOFs not fixed by the supports."""
        return self._mesh["free"].copy()

    # -- matrices -------------------------------------------------------------------------------------------
    def assemble(self, supported: bool = True) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """Mass and stiffness matrices (scipy CSR).  ``supported=True``: on the free DOFs (:meth:`free_dofs`; K
        positive definite); ``False``: on all ``6 n_nodes`` DOFs (K singular)."""
        rows, cols, mv, kv = [], [], [], []
        cache = {}
        for a, b, _, Le, k in self._mesh["elements"]:
            key = (Le, k)
            if key not in cache:
                cache[key] = element_matrices(Le, self.section[k])
            Me, Ke = cache[key]
            idx = np.r_[N_DOF_NODE * a:N_DOF_NODE * a + 6, N_DOF_NODE * b:N_DOF_NODE * b + 6]
            r, c = np.meshgrid(idx, idx, indexing="ij")
            rows.append(r.ravel())
            cols.append(c.ravel())
            mv.append(Me.ravel())
            kv.append(Ke.ravel())
        n = self.n_dof
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        M = sp.coo_matrix((np.concatenate(mv), (rows, cols)), shape=(n, n)).tocsr()
        K = sp.coo_matrix((np.concatenate(kv), (rows, cols)), shape=(n, n)).tocsr()
        if supported:
            f = self._mesh["free"]
            M = M[f][:, f].tocsr()
            K = K[f][:, f].tocsr()
        return M, K

    # -- modes ----------------------------------------------------------------------------------------------
    def modes(self, n_modes: int | None = None, f_max_Hz: float | None = None) -> "BridgeModes":
        """The lowest eigenmodes of the supported deck, mass-normalised: give **either** ``n_modes`` (a number of
        modes) **or** ``f_max_Hz`` (all modes up to that frequency)."""
        if (n_modes is None) == (f_max_Hz is None):
            raise ValueError("modes(): give either n_modes or f_max_Hz (exactly one)")
        M, K = self.assemble(supported=True)
        n_free = M.shape[0]
        if n_modes is not None:
            if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or n_modes < 1:
                raise ValueError(f"n_modes={n_modes!r}: expected an integer >= 1")
            if n_modes > n_free:
                raise ValueError(f"n_modes={n_modes}: the model has only {n_free} free DOFs (refine the mesh)")
        else:
            f_max_Hz = _finite("f_max_Hz", f_max_Hz, positive=True)
        w2_max = math.inf if f_max_Hz is None else (2.0 * math.pi * f_max_Hz) ** 2
        if n_free <= _DENSE_EIGEN_LIMIT:
            Kd, Md = K.toarray(), M.toarray()
            if n_modes is not None:
                lam, vec = scipy.linalg.eigh(Kd, Md, subset_by_index=[0, int(n_modes) - 1])
            else:
                lam, vec = scipy.linalg.eigh(Kd, Md)
        else:                                                  # large meshes: shift-invert Lanczos about 0
            from scipy.sparse.linalg import eigsh
            k = int(n_modes) if n_modes is not None else 20
            while True:
                lam, vec = eigsh(K.tocsc(), k=min(k, n_free - 1), M=M.tocsc(), sigma=0.0, which="LM")
                order = np.argsort(lam)
                lam, vec = lam[order], vec[:, order]
                if n_modes is not None or lam[-1] > w2_max or k >= n_free - 1:
                    break
                k *= 2
        lowest_Hz = math.sqrt(max(lam[0], 0.0)) / (2.0 * math.pi)
        keep = lam <= w2_max
        lam, vec = lam[keep], vec[:, keep]
        if lam.size == 0:
            raise ValueError(f"no mode below f_max_Hz={f_max_Hz} Hz (the lowest is {lowest_Hz:.4g} Hz)")
        # mass normalisation (eigh already gives Φ^T M Φ = I; enforce it for the sparse path) and a sign rule:
        # the largest entry of every mode is positive
        vec = vec / np.sqrt(np.einsum("ij,ij->j", vec, M @ vec))
        for j in range(vec.shape[1]):
            i = int(np.argmax(np.abs(vec[:, j])))
            if vec[i, j] < 0.0:
                vec[:, j] = -vec[:, j]
        shapes = np.zeros((self.n_dof, vec.shape[1]))
        shapes[self._mesh["free"]] = vec
        omega = np.sqrt(np.maximum(lam, 0.0))
        return BridgeModes(self, omega, shapes)

    # -- points for the FFRF mesh -------------------------------------------------------------------------
    def point_map(self, h_m: float = 1.0) -> tuple[np.ndarray, sp.csr_matrix]:
        """Three position points per beam node (axis; ``h_m`` above it; ``h_m`` to its right) and the map ``T``
        (9 n_nodes × 6 n_nodes) from the nodal DOFs to their displacements, ``u_P = u + θ × r_P``."""
        h = _finite("h_m", h_m, positive=True)
        offsets = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -h], [0.0, h, 0.0]])     # z down: above = -z
        x = self._mesh["x_nodes"]
        points = np.zeros((3 * len(x), 3))
        blocks = []
        for i, xi in enumerate(x):
            Tn = np.zeros((9, 6))
            for p, r in enumerate(offsets):
                points[3 * i + p] = (xi + r[0], r[1], r[2])
                rx, ry, rz = r
                Tn[3 * p:3 * p + 3, 0:3] = np.eye(3)
                Tn[3 * p:3 * p + 3, 3:6] = [[0.0, rz, -ry], [-rz, 0.0, rx], [ry, -rx, 0.0]]
            blocks.append(Tn)
        return points, sp.block_diag(blocks, format="csr")


# ------------------------------------------------------------------------------------------ the modal basis
class ShapeTable(NamedTuple):
    """Plain arrays of a modal basis for the compiled functions (``modal_shape_at(s, *table, out)``).

    start_m, rail_height_m : as :class:`BridgeModel`; elem_x0 (n_el) element start (deck coordinate, increasing),
    elem_len (n_el), elem_nodes (n_el, 2) int64, node_shapes (n_nodes, 5, n_modes): v, dv/dx, w, dw/dx, θx of every
    mode at every node."""

    start_m: float
    rail_height_m: float
    elem_x0: np.ndarray
    elem_len: np.ndarray
    elem_nodes: np.ndarray
    node_shapes: np.ndarray


class BridgeModes:
    """Mass-normalised eigenmodes of a :class:`BridgeModel` (from :meth:`BridgeModel.modes`).

    Attributes: ``model``, ``omega_rad_s``, ``frequencies_Hz``, ``damping_ratio`` (per mode), ``shapes``
    (6 n_nodes × n_modes, all nodal DOFs, zero at the fixed ones), ``kinds`` ("vertical", "lateral", "torsion",
    "axial": the DOF group carrying the mode's kinetic energy), ``energy_fractions`` (per group), ``table``
    (:class:`ShapeTable`).  Modal equations: ``q̈ + diag(2ζω) q̇ + diag(ω²) q = Q``.  ``damping_ratio`` may be
    edited per mode before :func:`add_bridge`."""

    def __init__(self, model: BridgeModel, omega_rad_s: np.ndarray, shapes: np.ndarray):
        self.model = model
        self.omega_rad_s = np.asarray(omega_rad_s, dtype=float)
        self.frequencies_Hz = self.omega_rad_s / (2.0 * math.pi)
        self.damping_ratio = np.full(self.n_modes, model.damping_ratio)
        self.shapes = shapes
        M, _ = model.assemble(supported=False)
        self._mass_all_dofs = M
        frac = {}
        for g, dofs in _GROUPS.items():
            mask = np.zeros(model.n_dof, dtype=bool)
            for d in dofs:
                mask[d::N_DOF_NODE] = True
            S = np.where(mask[:, None], shapes, 0.0)
            frac[g] = np.einsum("ij,ij->j", S, M @ S)
        names = list(frac)
        F = np.array([frac[g] for g in names])
        self.energy_fractions = {g: F[i] for i, g in enumerate(names)}
        self.kinds = tuple(names[i] for i in np.argmax(F, axis=0))
        mesh = model._mesh
        el = mesh["elements"]
        node_shapes = np.empty((model.n_nodes, 5, self.n_modes))
        node_shapes[:, _NS_V] = shapes[1::6]
        node_shapes[:, _NS_DV] = shapes[5::6]           # dv/dx = θz
        node_shapes[:, _NS_W] = shapes[2::6]
        node_shapes[:, _NS_DW] = -shapes[4::6]          # dw/dx = -θy
        node_shapes[:, _NS_TH] = shapes[3::6]
        self.table = ShapeTable(float(model.start_m), float(model.rail_height_m),
                                np.array([e[2] for e in el], dtype=float), np.array([e[3] for e in el], dtype=float),
                                np.array([[e[0], e[1]] for e in el], dtype=np.int64),
                                np.ascontiguousarray(node_shapes))

    @property
    def n_modes(self) -> int:
        return self.omega_rad_s.shape[0]

    def __repr__(self):
        f = ", ".join(f"{x:.3g}" for x in self.frequencies_Hz[:8])
        return f"BridgeModes({self.n_modes} modes: {f}{', ...' if self.n_modes > 8 else ''} Hz)"

    # modal matrices
    def modal_mass(self) -> np.ndarray:
        return np.eye(self.n_modes)

    def modal_stiffness(self) -> np.ndarray:
        return np.diag(self.omega_rad_s ** 2)

    def modal_damping(self) -> np.ndarray:
        return np.diag(2.0 * self.damping_ratio * self.omega_rad_s)

    def participation_factors(self, direction: str = "lateral") -> np.ndarray:
        """``Γ_n = φ_nᵀ M r`` (n_modes,): modal participation factors of a rigid translation ``r`` of the whole deck
        with its supports — ``"lateral"`` (track y: r = 1 at every v DOF) or ``"vertical"`` (z: every w DOF) — with
        the consistent mass on all DOFs (support DOFs included).  A ground acceleration ``ÿ_g`` of all supports
        loads the modal equations by ``-Γ ÿ_g`` (:mod:`.support_motion`); ``Γ_n²`` is the effective modal mass."""
        dof = {"lateral": 1, "vertical": 2}.get(direction)
        if dof is None:
            raise ValueError(f"direction={direction!r}: expected 'lateral' or 'vertical'")
        r = np.zeros(self.model.n_dof)
        r[dof::N_DOF_NODE] = 1.0
        return np.asarray(self.shapes.T @ (self._mass_all_dofs @ r), dtype=float)

    def of_kind(self, kind: str) -> np.ndarray:
        """Indices of the modes of one kind, in increasing frequency."""
        if kind not in _GROUPS:
            raise ValueError(f"kind={kind!r}: expected one of {sorted(_GROUPS)}")
        return np.array([i for i, k in enumerate(self.kinds) if k == kind], dtype=np.int64)

    # vectorised wrappers of the compiled functions
    def shape_at(self, s_m) -> np.ndarray:
        """``Φ(s)``: (..., 3, n_modes), rows y_rail, z_rail, θ_rail, at track distance(s) s (zero off the deck)."""
        s = np.asarray(s_m, dtype=float)
        out = np.empty((s.size, 3, self.n_modes))
        _shape_many(np.ascontiguousarray(s.ravel()), *self.table, out, out, False)
        return out.reshape(s.shape + (3, self.n_modes))

    def shape_and_slope_at(self, s_m) -> tuple[np.ndarray, np.ndarray]:
        """``Φ(s)`` and ``dΦ/ds`` (each (..., 3, n_modes))."""
        s = np.asarray(s_m, dtype=float)
        out = np.empty((s.size, 3, self.n_modes))
        out_ds = np.empty((s.size, 3, self.n_modes))
        _shape_many(np.ascontiguousarray(s.ravel()), *self.table, out, out_ds, True)
        sh = s.shape + (3, self.n_modes)
        return out.reshape(sh), out_ds.reshape(sh)

    def rail_displacement(self, s_m, q) -> np.ndarray:
        """``(y_rail, z_rail, θ_rail)`` (..., 3) at s for modal coordinates ``q`` (n_modes,)."""
        q = self._check_q(q)
        return self.shape_at(s_m) @ q

    def rail_velocity(self, s_m, q_t) -> np.ndarray:
        """Deck (material) velocity of the rail centre line ``Φ(s) q̇`` (..., 3)."""
        return self.shape_at(s_m) @ self._check_q(q_t)

    def rail_rate_moving(self, s_m, q, q_t, speed_m_s: float) -> np.ndarray:
        """Rate of the rail displacement seen from a point moving along the track at ``speed_m_s``:
        ``Φ(s) q̇ + V Φ'(s) q`` (..., 3)."""
        phi, dphi = self.shape_and_slope_at(s_m)
        return phi @ self._check_q(q_t) + float(speed_m_s) * (dphi @ self._check_q(q))

    def project(self, s_m, forces) -> np.ndarray:
        """Generalized modal forces ``Σ Φ(s_i)^T F_i`` of forces ``F_i = (Fy, Fz, Mx)`` (k, 3) at track distances
        ``s_i`` (k,) on the rails' centre line at rail-top level."""
        s = np.atleast_1d(np.asarray(s_m, dtype=float))
        F = np.asarray(forces, dtype=float).reshape(-1, 3)
        if F.shape[0] != s.size:
            raise ValueError(f"project: {s.size} positions but {F.shape[0]} forces (Fy, Fz, Mx)")
        return np.einsum("kij,ki->j", self.shape_at(s), F)

    def _check_q(self, q):
        q = np.asarray(q, dtype=float)
        if q.shape[-1:] != (self.n_modes,):
            raise ValueError(f"modal coordinates of shape {q.shape}: expected (..., {self.n_modes})")
        return q


# ------------------------------------------------------------------------------------- compiled functions
@compiled
def _find_element(x, elem_x0, elem_len):
    n = elem_x0.shape[0]
    if n == 0:
        return -1
    if not (x >= elem_x0[0] and x <= elem_x0[n - 1] + elem_len[n - 1]):      # also rejects NaN
        return -1
    i = np.searchsorted(elem_x0, x, side="right") - 1
    if i < 0:
        i = 0
    if i > n - 1:
        i = n - 1
    return i


@compiled
def _interp(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out, out_ds, with_slope):
    n_modes = node_shapes.shape[2]
    for i in range(3):
        for k in range(n_modes):
            out[i, k] = 0.0
            if with_slope:
                out_ds[i, k] = 0.0
    e = _find_element(s_m - start_m, elem_x0, elem_len)
    if e < 0:
        return False
    Le = elem_len[e]
    xi = (s_m - start_m - elem_x0[e]) / Le
    xi2 = xi * xi
    xi3 = xi2 * xi
    N1 = 1.0 - 3.0 * xi2 + 2.0 * xi3
    N2 = Le * (xi - 2.0 * xi2 + xi3)
    N3 = 3.0 * xi2 - 2.0 * xi3
    N4 = Le * (xi3 - xi2)
    La = 1.0 - xi
    Lb = xi
    a = elem_nodes[e, 0]
    b = elem_nodes[e, 1]
    ez = rail_height_m
    for k in range(n_modes):
        v = N1 * node_shapes[a, 0, k] + N2 * node_shapes[a, 1, k] + N3 * node_shapes[b, 0, k] \
            + N4 * node_shapes[b, 1, k]
        w = N1 * node_shapes[a, 2, k] + N2 * node_shapes[a, 3, k] + N3 * node_shapes[b, 2, k] \
            + N4 * node_shapes[b, 3, k]
        th = La * node_shapes[a, 4, k] + Lb * node_shapes[b, 4, k]
        out[0, k] = v + ez * th
        out[1, k] = w
        out[2, k] = th
    if with_slope:
        dN1 = (-6.0 * xi + 6.0 * xi2) / Le
        dN2 = 1.0 - 4.0 * xi + 3.0 * xi2
        dN3 = (6.0 * xi - 6.0 * xi2) / Le
        dN4 = 3.0 * xi2 - 2.0 * xi
        for k in range(n_modes):
            dv = dN1 * node_shapes[a, 0, k] + dN2 * node_shapes[a, 1, k] + dN3 * node_shapes[b, 0, k] \
                + dN4 * node_shapes[b, 1, k]
            dw = dN1 * node_shapes[a, 2, k] + dN2 * node_shapes[a, 3, k] + dN3 * node_shapes[b, 2, k] \
                + dN4 * node_shapes[b, 3, k]
            dth = (node_shapes[b, 4, k] - node_shapes[a, 4, k]) / Le
            out_ds[0, k] = dv + ez * dth
            out_ds[1, k] = dw
            out_ds[2, k] = dth
    return True


@compiled
def modal_shape_at(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out):
    """``Φ(s)`` into ``out`` (3, n_modes): rows y_rail (= v + e_z θx), z_rail (= w), θ_rail (= θx) of every mode at
    track distance ``s_m`` (nodal values and slopes interpolated by the element's Hermite cubics; θx linear).
    Returns True on the deck; off the deck (or for a non-finite s) ``out`` is zero and False is returned.
    Arguments after ``s_m``: a :class:`ShapeTable` (``modal_shape_at(s, *modes.table, out)``)."""
    return _interp(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out, out, False)


@compiled
def modal_shape_and_slope_at(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out, out_ds):
    """``Φ(s)`` into ``out`` and ``dΦ/ds`` into ``out_ds`` (each (3, n_modes)); as :func:`modal_shape_at`."""
    return _interp(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out, out_ds, True)


@compiled
def rail_state_at(s_m, speed_m_s, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, q, q_t,
                  work, work_ds, out):
    """Rail state at track distance ``s_m`` from the modal coordinates ``q``, ``q_t`` into ``out`` (9,):
    ``[0:3]`` displacement ``Φ q`` (y_rail, z_rail, θ_rail), ``[3:6]`` deck (material) velocity ``Φ q̇``,
    ``[6:9]`` rate seen by a point moving along the track at ``speed_m_s``: ``Φ q̇ + V Φ' q``.  ``work``,
    ``work_ds``: scratch (3, n_modes).  Returns True on the deck (all zero off it)."""
    on = _interp(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, work, work_ds, True)
    shapes_times(work, q, q_t, out)
    n_modes = node_shapes.shape[2]
    for i in range(3):
        g = 0.0
        for k in range(n_modes):
            g += work_ds[i, k] * q[k]
        out[6 + i] = out[3 + i] + speed_m_s * g
    return on


@compiled
def shapes_times(phi, q, q_t, out):
    """``out[0:3] = Φ q`` and ``out[3:6] = Φ q̇`` for the shapes ``phi`` (3, n_modes) at one point (rows y_rail,
    z_rail, θ_rail): the rails' displacement and material velocity there."""
    for i in range(3):
        d = 0.0
        v = 0.0
        for k in range(phi.shape[1]):
            d += phi[i, k] * q[k]
            v += phi[i, k] * q_t[k]
        out[i] = d
        out[3 + i] = v


@compiled
def project_shapes(phi, Fy, Fz, Mx, f_modal):
    """``f_modal += Φᵀ (Fy, Fz, Mx)`` for the shapes ``phi`` (3, n_modes) at the force's point: the generalized
    modal forces of a force on the rails' centre line at rail-top level and a moment about it."""
    for k in range(phi.shape[1]):
        f_modal[k] += phi[0, k] * Fy + phi[1, k] * Fz + phi[2, k] * Mx


@compiled
def add_projected_force(s_m, Fy, Fz, Mx, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, work,
                        f_modal):
    """``f_modal += Φ(s)^T (Fy, Fz, Mx)``: generalized modal forces of a force on the rails' centre line at rail-top
    level (y right, z down) and a moment about it, at track distance ``s_m``.  ``work``: scratch (3, n_modes).
    Returns True if s is on the deck (nothing is added otherwise)."""
    on = _interp(s_m, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, work, work, False)
    if on:
        project_shapes(work, Fy, Fz, Mx, f_modal)
    return on


@compiled
def _shape_many(s, start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out, out_ds, with_slope):
    for i in range(s.shape[0]):
        _interp(s[i], start_m, rail_height_m, elem_x0, elem_len, elem_nodes, node_shapes, out[i], out_ds[i],
                with_slope)


@compiled
def _moving_forces_core(t, s_start_m, speed_m_s, x_m, forces, start_m, rail_height_m, elem_x0, elem_len,
                        elem_nodes, node_shapes, work, f_modal):
    for k in range(f_modal.shape[0]):
        f_modal[k] = 0.0
    s0 = s_start_m + speed_m_s * t
    for j in range(x_m.shape[0]):
        add_projected_force(s0 + x_m[j], forces[j, 0], forces[j, 1], forces[j, 2], start_m, rail_height_m, elem_x0,
                            elem_len, elem_nodes, node_shapes, work, f_modal)


# ---------------------------------------------------------------------------------------------- Exudyn side
def _unique_name(mbs, base: str) -> str:
    """``base``, or ``base_2``, ``base_3``, … — the first name no object or node of ``mbs`` uses yet (with the
    node names this module derives from it)."""
    if not isinstance(base, str) or not base:
        raise ValueError(f"name={base!r}: expected a non-empty string")
    k = 1
    while True:
        cand = base if k == 1 else f"{base}_{k}"
        used = (int(mbs.GetObjectNumber(cand)) != -1
                or any(int(mbs.GetNodeNumber(n)) != -1 for n in (f"{cand}_modal", f"{cand}_ground",
                                                                 "NodeRigidBody:" + cand, "NodeGeneric:" + cand)))
        if not used:
            return cand
        k += 1


class MovingForces:
    """Constant forces travelling along the track at a constant speed, applied to the deck: one zero-mass
    ``ObjectGenericODE2`` on the bridge's modal node whose force user function returns ``Σ Φ(s_j(t))^T F_j`` with
    ``s_j(t) = s_start_m + V t + x_j`` (``x_j`` the force's place in the frame moving with V, ahead > 0, like a
    wheel of :mod:`..multibody.vehicle_builder`), and a zero Jacobian (the forces do not depend on the state).

    forces_N : (n, 3) rows ``(Fy, Fz, Mx)`` [N, N, N m] on the rails' centre line at rail-top level (z down:
    a vertical wheel load is ``Fz > 0``)."""

    def __init__(self, mbs, bridge: "ExudynBridge", x_m, forces_N, speed_m_s: float, s_start_m: float = 0.0,
                 name: str = "moving_forces"):
        from exudyn.itemInterface import ObjectGenericODE2, VObjectGenericODE2

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
        self.speed_m_s = _finite("speed_m_s", speed_m_s)
        self.s_start_m = _finite("s_start_m", s_start_m)
        self.table = bridge.modes.table
        n = bridge.modes.n_modes
        self._f = np.zeros(n)
        self._work = np.zeros((3, n))
        self._jac = np.zeros((n, n))
        self.object = mbs.AddObject(ObjectGenericODE2(
            name=_unique_name(mbs, name), nodeNumbers=[bridge.modal_node], massMatrix=np.zeros((n, n)),
            forceUserFunction=self._force_uf, jacobianUserFunction=self._jacobian_uf,
            visualization=VObjectGenericODE2(show=False)))

    def forces(self, t: float) -> np.ndarray:
        """Generalized modal forces at time t."""
        _moving_forces_core(float(t), self.s_start_m, self.speed_m_s, self.x_m, self.forces_N, *self.table,
                            self._work, self._f)
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

    modes: BridgeModes
    formulation: str
    modal_node: int
    object: int
    rigid_node: int | None = None
    constraints: tuple = ()
    ffrf_data: dict | None = None
    support_motion: object = None
    support_load: object = None

    def add_support_motion(self, mbs, motion, name: str = "support_motion"):
        """Impose a lateral ground motion ``y_g(t)`` on all supports (a :class:`.support_motion.SupportMotion`, e.g.
        :class:`~.support_motion.SmoothHarmonicSupportMotion`; relative-motion formulation of
        :mod:`.support_motion`): adds the effective load ``-Γ ÿ_g(t)`` on the modal node
        (:class:`~.support_motion.SupportMotionLoad`) and records the motion, so that a wheel–rail connector
        coupled to this bridge sees the rails at ``y_g + Φ_y q`` moving with ``ẏ_g + Φ_y q̇`` (on and off the deck:
        synchronous ground motion).  The modal coordinates stay the motion *relative* to the supports.  One
        support motion per bridge; call before ``mbs.Assemble()``."""
        from .support_motion import SupportMotionLoad

        if self.support_motion is not None:
            raise ValueError("this bridge already has a support motion (one per bridge: combine the records in one "
                             "SupportMotion)")
        load = SupportMotionLoad(mbs, self, motion, name=name)
        self.support_motion = motion
        self.support_load = load
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
        from exudyn.itemInterface import SensorNode
        return mbs.AddSensor(SensorNode(name=name, nodeNumber=self.modal_node, storeInternal=True,
                                        outputVariableType=exu.OutputVariableType.Coordinates))

    def add_moving_forces(self, mbs, x_m, forces_N, speed_m_s: float, s_start_m: float = 0.0,
                          name: str = "moving_forces") -> MovingForces:
        """Constant forces moving along the track (:class:`MovingForces`)."""
        return MovingForces(mbs, self, x_m, forces_N, speed_m_s, s_start_m, name=name)


def add_bridge(mbs, modes: BridgeModes, formulation: str = "modal", name: str = "bridge") -> ExudynBridge:
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
    if not isinstance(modes, BridgeModes):
        raise TypeError(f"modes={modes!r}: expected BridgeModes (BridgeModel.modes(...))")
    name = _unique_name(mbs, name)
    if formulation == "modal":
        return _add_modal(mbs, modes, name)
    return _add_ffrf(mbs, modes, name)


def _add_modal(mbs, modes: BridgeModes, name: str) -> ExudynBridge:
    from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2, VObjectGenericODE2

    n = modes.n_modes
    node = mbs.AddNode(NodeGenericODE2(name=f"{name}_modal", numberOfODE2Coordinates=n, referenceCoordinates=[0.0] * n,
                                       initialCoordinates=[0.0] * n, initialCoordinates_t=[0.0] * n))
    obj = mbs.AddObject(ObjectGenericODE2(name=name, nodeNumbers=[node], massMatrix=modes.modal_mass(),
                                          stiffnessMatrix=modes.modal_stiffness(),
                                          dampingMatrix=modes.modal_damping(),
                                          visualization=VObjectGenericODE2(show=False)))
    return ExudynBridge(modes, "modal", int(node), int(obj))


def _add_ffrf(mbs, modes: BridgeModes, name: str) -> ExudynBridge:
    from exudyn.FEM import FEMinterface
    from exudyn.itemInterface import CoordinateConstraint, MarkerNodeCoordinate, NodePointGround

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


# ------------------------------------------------------------------------------- moving-load reference solution
def fryba_moving_force(x_m, t_s, *, force_N: float, speed_m_s: float, span_m: float, EI_Nm2: float,
                       m_kg_m: float, damping_ratio: float = 0.0, n_terms: int = 50, offsets_m=(0.0,)):
    """Deflection (z down) of a simply supported Euler–Bernoulli beam under constant forces ``force_N`` (down)
    moving at ``speed_m_s``, by the modal series of Frýba (1999, Ch. 1; written here with modal damping): for
    mode j (shape ``sin(jπx/L)``, ``ω_j = (jπ/L)² √(EI/m)``, excitation frequency ``Ω_j = jπv/L``)

        ``q̈_j + 2ζω_j q̇_j + ω_j² q_j = (2P/(mL)) sin(Ω_j (t - t_k))``   while force k is on the span,

    solved in closed form (particular + homogeneous solution from rest; after the force leaves, free damped
    vibration from the state at exit), ``w(x, t) = Σ_k Σ_j q_j^(k)(t) sin(jπx/L)``.  For ζ = 0 this is Frýba's
    ``v(x,t) = v0 Σ 1/(j²(j² - α²)) [sin jωt - (α/j) sin ω_j t] sin(jπx/L)`` with ``v0 = 2PL³/(π⁴EI)``,
    ``α = v/(2 f_1 L)``.  The force k enters the span (x = 0) at ``t_k = offsets_m[k]/v`` (offsets ≥ 0: following
    forces).  ``x_m``, ``t_s`` broadcast.  Exact resonance ``Ω_j = ω_j`` with ζ = 0 is handled by its limit."""
    P = _finite("force_N", force_N)
    v = _finite("speed_m_s", speed_m_s, positive=True)
    L = _finite("span_m", span_m, positive=True)
    EI = _finite("EI_Nm2", EI_Nm2, positive=True)
    m = _finite("m_kg_m", m_kg_m, positive=True)
    z = _finite("damping_ratio", damping_ratio, non_negative=True)
    if not z < 1.0:
        raise ValueError(f"damping_ratio={z}: expected 0 <= ζ < 1")
    if isinstance(n_terms, bool) or not isinstance(n_terms, (int, np.integer)) or n_terms < 1:
        raise ValueError(f"n_terms={n_terms!r}: expected an integer >= 1")
    offs = np.atleast_1d(np.asarray(offsets_m, dtype=float))
    if np.any(~np.isfinite(offs)) or np.any(offs < 0):
        raise ValueError("offsets_m: expected finite offsets >= 0")
    x, t = np.broadcast_arrays(np.asarray(x_m, dtype=float), np.asarray(t_s, dtype=float))
    w = np.zeros(x.shape)
    T_on = L / v
    A = 2.0 * P / (m * L)
    for j in range(1, int(n_terms) + 1):
        wj = (j * math.pi / L) ** 2 * math.sqrt(EI / m)
        Om = j * math.pi * v / L
        wd = wj * math.sqrt(1.0 - z * z)
        shape = np.sin(j * math.pi * x / L)
        for off in offs:
            tau = t - off / v
            q = _forced_response(A, wj, wd, z, Om, np.clip(tau, 0.0, T_on))
            qT, qT_t = _forced_response(A, wj, wd, z, Om, np.array(T_on), rate=True)
            tf = np.maximum(tau - T_on, 0.0)
            ez = np.exp(-z * wj * tf)
            q_free = ez * (qT * np.cos(wd * tf) + (qT_t + z * wj * qT) / wd * np.sin(wd * tf))
            q = np.where(tau <= T_on, q, q_free)
            w += np.where(tau > 0.0, q, 0.0) * shape
    return w


def _forced_response(A, w, wd, z, Om, t, rate=False):
    """Response from rest of ``q̈ + 2ζω q̇ + ω² q = A sin(Ω t)`` (and its rate)."""
    t = np.asarray(t, dtype=float)
    den = (w * w - Om * Om) ** 2 + (2.0 * z * w * Om) ** 2
    if den < 1e-24 * w ** 4:                     # undamped resonance: the limit Ω → ω
        q = A / (2.0 * w * w) * (np.sin(w * t) - w * t * np.cos(w * t))
        if not rate:
            return q
        return q, A / 2.0 * t * np.sin(w * t)
    a = A * (w * w - Om * Om) / den               # particular: a sin Ωt + b cos Ωt
    b = -A * 2.0 * z * w * Om / den
    c1 = -b                                        # homogeneous e^{-ζωt}(c1 cos ω_d t + c2 sin ω_d t), q(0)=q'(0)=0
    c2 = (-a * Om + z * w * c1) / wd
    e = np.exp(-z * w * t)
    q = a * np.sin(Om * t) + b * np.cos(Om * t) + e * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    if not rate:
        return q
    q_t = (a * Om * np.cos(Om * t) - b * Om * np.sin(Om * t)
           + e * ((-z * w * c1 + wd * c2) * np.cos(wd * t) + (-z * w * c2 - wd * c1) * np.sin(wd * t)))
    return q, q_t
