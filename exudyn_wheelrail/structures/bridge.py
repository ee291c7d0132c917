r"""Railway bridge: the finite-element model of a 3-D Euler–Bernoulli beam deck on supports (:class:`BridgeModel`)
and its eigenmodes (:class:`BridgeModes`), the modal basis that :mod:`.bridge_exudyn` enters into Exudyn.

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
bridge does not move with the running speed; the coupling to the moving model frame: :mod:`.modal_shapes`).  The beam
axis is the deck's shear centre and centre of mass (no mass or shear-centre eccentricity); the top of rail lies
``e_z = rail_height_m`` **above** it (at ``z = -e_z``).  Nodal degrees of freedom, 6 per node, in the track frame:
``(u, v, w, θx, θy, θz)`` — displacements along x, y, z and small rotations about x, y, z (right-hand rule).

* vertical bending (in the x–z plane, stiffness ``EI_y``): ``w(x)``, with ``dw/dx = -θy`` (a positive rotation
  about +y turns +x towards -z);
* lateral bending (x–y plane, ``EI_z``): ``v(x)``, with ``dv/dx = +θz``;
* torsion (``GJ``, mass moment of inertia per length ``I_p``): ``θx(x)``; axial (``EA``): ``u(x)``.

The rails' displacement under a wheel, ``Φ(s) q``, and where the wheel forces go, ``Φ(s)ᵀ F``:
:mod:`.modal_shapes` (from :attr:`BridgeModes.table`); the bridge in Exudyn: :mod:`.bridge_exudyn`; Frýba's
closed-form reference: :mod:`.fryba`; the beam element: :mod:`.beam`.

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

References
----------
P. A. Montenegro, S. G. M. Neves, R. Calçada, M. Tanabe, M. Sogabe, Computers & Structures 152 (2015)
200–214 (the train–bridge interaction that this model is for).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

from .beam import DOF_GROUPS, N_DOF_NODE, DeckSection, element_matrices
from .modal_basis import ModalBasis
from .modal_shapes import NS_DV, NS_DW, NS_TH, NS_V, NS_W, ShapeTable
from .checks import checked_number

__all__ = ["BridgeModel", "BridgeModes"]

_DENSE_EIGEN_LIMIT = 2000          # free DOFs up to which the dense generalized eigen solver is used


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
        spans = tuple(checked_number(f"spans_m[{i}]", L, positive=True) for i, L in enumerate(spans))
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
        z = checked_number("damping_ratio", self.damping_ratio, non_negative=True)
        if not z < 1.0:
            raise ValueError(f"damping_ratio={z}: expected 0 <= ζ < 1 (a ratio, not a percentage)")
        object.__setattr__(self, "damping_ratio", z)
        object.__setattr__(self, "rail_height_m", checked_number("rail_height_m", self.rail_height_m, non_negative=True))
        object.__setattr__(self, "start_m", checked_number("start_m", self.start_m))
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
            f_max_Hz = checked_number("f_max_Hz", f_max_Hz, positive=True)
        w2_max = math.inf if f_max_Hz is None else (2.0 * math.pi * f_max_Hz) ** 2
        if n_free <= _DENSE_EIGEN_LIMIT:
            Kd, Md = K.toarray(), M.toarray()
            if n_modes is not None:
                lam, vec = scipy.linalg.eigh(Kd, Md, subset_by_index=[0, int(n_modes) - 1])
            else:
                lam, vec = scipy.linalg.eigh(Kd, Md)
        else:                                                  # large meshes: shift-invert Lanczos about 0
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
        h = checked_number("h_m", h_m, positive=True)
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



class BridgeModes(ModalBasis):
    """Mass-normalised eigenmodes of a :class:`BridgeModel` (from :meth:`BridgeModel.modes`): a
    :class:`~.modal_basis.ModalBasis` with the finite-element model behind it.

    Attributes besides the basis's: ``model``, ``shapes`` (6 n_nodes × n_modes, all nodal DOFs, zero at the fixed
    ones), ``energy_fractions`` (per DOF group); ``kinds`` ("vertical", "lateral", "torsion", "axial") is the DOF
    group carrying the mode's kinetic energy."""

    def __init__(self, model: BridgeModel, omega_rad_s: np.ndarray, shapes: np.ndarray):
        self.model = model
        self.shapes = shapes
        M, _ = model.assemble(supported=False)
        self._mass_all_dofs = M
        frac = {}
        for g, dofs in DOF_GROUPS.items():
            mask = np.zeros(model.n_dof, dtype=bool)
            for d in dofs:
                mask[d::N_DOF_NODE] = True
            S = np.where(mask[:, None], shapes, 0.0)
            frac[g] = np.einsum("ij,ij->j", S, M @ S)
        names = list(frac)
        F = np.array([frac[g] for g in names])
        self.energy_fractions = {g: F[i] for i, g in enumerate(names)}
        mesh = model._mesh
        el = mesh["elements"]
        n_modes = shapes.shape[1]
        node_shapes = np.empty((model.n_nodes, 5, n_modes))
        node_shapes[:, NS_V] = shapes[1::6]
        node_shapes[:, NS_DV] = shapes[5::6]           # dv/dx = θz
        node_shapes[:, NS_W] = shapes[2::6]
        node_shapes[:, NS_DW] = -shapes[4::6]          # dw/dx = -θy
        node_shapes[:, NS_TH] = shapes[3::6]
        table = ShapeTable(float(model.start_m), float(model.rail_height_m),
                           np.array([e[2] for e in el], dtype=float), np.array([e[3] for e in el], dtype=float),
                           np.array([[e[0], e[1]] for e in el], dtype=np.int64), np.ascontiguousarray(node_shapes))
        super().__init__(omega_rad_s, model.damping_ratio, tuple(names[i] for i in np.argmax(F, axis=0)), table)

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
