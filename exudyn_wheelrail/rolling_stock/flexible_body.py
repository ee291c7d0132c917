r"""The flexible car body: a free–free 3-D Euler–Bernoulli beam reduced to its lowest elastic modes and entered into
Exudyn as a floating-frame-of-reference body (``ObjectFFRFreducedOrder``).

Beam model (:class:`CarBodyBeam`)
---------------------------------
The car body is a uniform beam along the track x axis through its centre of mass (CG), from ``-L/2`` to ``+L/2``
(body coordinates relative to the CG; y right, z **down**, the track frame of
:mod:`exudyn_wheelrail.conventions`), meshed with 2-node 3-D Euler–Bernoulli elements — the element of the bridge
deck (:func:`exudyn_wheelrail.structures.bridge.element_matrices`: Hermite cubics for the two bending planes, linear
functions for axial motion and torsion, consistent mass), plus the rotary inertia of the cross-section in bending
(Rayleigh's term ``∫ i_y w'² + i_z v'² dx``), which keeps the rigid-body inertia of the data exact (below).  Nodal
DOFs ``(u, v, w, θx, θy, θz)`` as the bridge (``dw/dx = -θy``, ``dv/dx = θz``).

Consistency with the rigid car body of the vehicle file (``[car_body]``: mass M, principal inertias Ixx, Iyy, Izz
about the CG): the beam's rigid-body mass and inertia **are** the data's —

* mass per length ``m = M / L``;
* polar (torsional) inertia per length ``I_p = Ixx / L``;
* bending rotary inertias per length ``i_y = (Iyy - M L²/12) / L`` and ``i_z = (Izz - M L²/12) / L``: a uniform
  beam of mass M and length L has the pitch and yaw inertia ``M L²/12``; the rest of the data's inertia is put
  into the cross-section's rotary inertia (it must not be negative: a car body shorter than ``sqrt(12 Iyy / M)``
  carries it).  The consistent mass matrix integrates rigid translations and rotations exactly (they lie in the
  element's shape space), so the beam's rigid-body inertia equals the data to round-off (tested).

The rotary inertia lowers the bending frequencies a little (Rayleigh beam); the analytic free–free references
``ω_n = (β_n L)² sqrt(EI / (m L⁴))`` with ``β_n L = 4.730, 7.853, 10.996`` (vertical and lateral bending) and
``ω_n = n π / L sqrt(GJ / I_p)`` (torsion) hold for ``i_y = i_z = 0``, which the tests use.

Discretisation error (sets the mesh, ``tests/test_flexible_car_body.py`` checks it): Hermite cubic bending with
consistent mass converges as ``h⁴`` (at 20 elements the third free–free bending frequency is well within 0.01 %);
linear torsion elements with consistent mass over-estimate ``ω_n`` by ``≈ (n π / n_e)² / 24`` (the discrete
dispersion of the bridge docstring), so 1 % on the third torsion mode needs ``n_e >= 3π / sqrt(0.24) = 19.2``
elements: :data:`DEFAULT_ELEMENTS` = 24 (0.64 % on the third, 0.07 % on the first).

Modes (:meth:`CarBodyBeam.modes`)
---------------------------------
The free–free generalized eigenproblem ``K φ = ω² M φ`` (dense, all DOFs) gives six rigid-body modes (ω = 0:
they are the reference frame's motion) and the elastic modes; the lowest ``n_modes`` elastic modes are kept,
mass-normalised (``Φᵀ M Φ = I``, ``Φᵀ K Φ = diag(ω²)``), each with its own damping ratio ``ζ_i`` (modal damping
``diag(2 ζ ω)``).  Being M-orthogonal to the rigid modes, they leave the reference frame at the CG with the body's
linear and (linearised) angular momentum: the frame is the body's mean axes (Tisserand frame, linearised).

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

External FE models (:func:`modes_from_fe_file`)
-----------------------------------------------
A car body's modes from an external FE model enter through the same FEM interface: an ``.npz`` file with the
mesh of position nodes and its mass and stiffness matrices (layout in :func:`modes_from_fe_file`); the free–free
modes are computed from them.  The attachment points must then be nodes of that mesh.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from ..structures.bridge import (
    _GROUPS,
    _LAT_IDX,
    _LAT_SIGN,
    _VER_IDX,
    _VER_SIGN,
    N_DOF_NODE,
    DeckSection,
    _hermite,
    element_matrices,
)

__all__ = [
    "FREE_FREE_BETA_L",
    "DEFAULT_ELEMENTS",
    "DEFAULT_SECTIONS",
    "BodyPointKinematics",
    "car_body_modes",
    "add_vehicle_car_body",
    "highest_mode_rad_s",
    "CarBodyBeam",
    "CarBodyModes",
    "FlexibleCarBody",
    "add_flexible_car_body",
    "beam_from_car_body",
    "modes_from_fe_file",
]

#: roots β_n L of the free–free beam's frequency equation cos βL cosh βL = 1 (n = 1, 2, 3)
FREE_FREE_BETA_L = (4.730040744862704, 7.853204624095838, 10.995607838001671)
#: beam elements of the car body by default (see the module docstring: 1 % on the third torsion mode needs 19.2)
DEFAULT_ELEMENTS = 24
#: beam sections (besides the ends and the attachment points) that carry FFRF mesh points: the FFRF object's cost
#: per evaluation grows with its mesh points (benchmarks/bench_flexible_car_body.py), the reduced matrices are exact
#: for any section set that resolves the modes
DEFAULT_SECTIONS = 5
#: distance of a mesh section's three points from the beam axis [m]: small, so that the FFRF's second-order
#: (rotated-deformation) terms of the point set tend to the beam's, not so small that precision suffers (module
#: docstring)
_POINT_OFFSET_M = 1.0e-2
#: eigenvalues below this fraction of the largest are rigid-body modes
_RIGID_TOL = 1e-9


# ============================================================================================= the beam model
@dataclass(frozen=True)
class CarBodyBeam:
    """Free–free uniform beam of the car body (module docstring), SI units; body coordinates relative to the CG.

    length_m : L.  mass_kg_m : m.  EI_vertical_N_m2 / EI_lateral_N_m2 : bending stiffness in the x–z / x–y plane.
    GJ_N_m2 : torsional stiffness.  EA_N : axial stiffness.  polar_inertia_kg_m2_m : I_p (torsion).
    rotary_inertia_y_kg_m2_m / rotary_inertia_z_kg_m2_m : cross-section rotary inertia in vertical / lateral
    bending (0: Euler–Bernoulli).  n_elements : target number of elements; ``node_x_m``: body x coordinates that
    must be mesh nodes (attachment points), the mesh between them is uniform with elements no longer than
    L / n_elements."""

    length_m: float
    mass_kg_m: float
    EI_vertical_N_m2: float
    EI_lateral_N_m2: float
    GJ_N_m2: float
    EA_N: float
    polar_inertia_kg_m2_m: float
    rotary_inertia_y_kg_m2_m: float = 0.0
    rotary_inertia_z_kg_m2_m: float = 0.0
    n_elements: int = DEFAULT_ELEMENTS
    node_x_m: tuple = ()

    def __post_init__(self):
        for name in ("length_m", "mass_kg_m", "EI_vertical_N_m2", "EI_lateral_N_m2", "GJ_N_m2", "EA_N",
                     "polar_inertia_kg_m2_m"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float, np.floating)) and math.isfinite(v) and v > 0.0):
                raise ValueError(f"CarBodyBeam.{name} = {v!r}: expected a finite positive number")
        for name in ("rotary_inertia_y_kg_m2_m", "rotary_inertia_z_kg_m2_m"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0.0):
                raise ValueError(f"CarBodyBeam.{name} = {v!r}: expected a finite number >= 0")
        if isinstance(self.n_elements, bool) or not isinstance(self.n_elements, (int, np.integer)) \
                or self.n_elements < 2:
            raise ValueError(f"CarBodyBeam.n_elements = {self.n_elements!r}: expected an integer >= 2")
        half = 0.5 * self.length_m
        for x in self.node_x_m:
            if not abs(x) <= half * (1.0 + 1e-12):
                raise ValueError(f"CarBodyBeam.node_x_m: {x} m is off the body (x in [{-half}, {half}] m from the "
                                 "CG)")

    # -- mesh and matrices -------------------------------------------------------------------------------------
    @property
    def section(self) -> DeckSection:
        return DeckSection(m_kg_m=self.mass_kg_m, EI_y_Nm2=self.EI_vertical_N_m2, EI_z_Nm2=self.EI_lateral_N_m2,
                           GJ_Nm2=self.GJ_N_m2, EA_N=self.EA_N, Ip_kgm2_m=self.polar_inertia_kg_m2_m)

    def mesh_x_m(self) -> np.ndarray:
        """Node x coordinates (body frame, from the CG), increasing: the ends, ``node_x_m`` and uniform
        subdivisions between them."""
        half = 0.5 * self.length_m
        breaks = np.unique(np.round(np.r_[-half, half, np.clip(self.node_x_m, -half, half)], 12))
        h = self.length_m / self.n_elements
        xs = [breaks[0]]
        for a, b in zip(breaks[:-1], breaks[1:]):
            n = max(1, int(math.ceil((b - a) / h - 1e-9)))
            xs.extend(a + (b - a) * np.arange(1, n + 1) / n)
        return np.array(xs)

    def assemble(self) -> tuple[np.ndarray, np.ndarray]:
        """Dense mass and stiffness matrices over all ``6 n_nodes`` DOFs (free–free: K has a 6-dimensional null
        space)."""
        x = self.mesh_x_m()
        n = N_DOF_NODE * len(x)
        M = np.zeros((n, n))
        K = np.zeros((n, n))
        sec = self.section
        gp, gw = np.polynomial.legendre.leggauss(4)
        cache = {}
        for e in range(len(x) - 1):
            Le = x[e + 1] - x[e]
            key = round(Le, 12)
            if key not in cache:
                Me, Ke = element_matrices(Le, sec)
                Me = Me.copy()
                for xi, w in zip(0.5 * (gp + 1.0), 0.5 * gw * Le):    # rotary inertia: ∫ i (slope)² dx
                    _, dN, _ = _hermite(xi, Le)
                    for idx, sign, i_rot in ((_VER_IDX, _VER_SIGN, self.rotary_inertia_y_kg_m2_m),
                                             (_LAT_IDX, _LAT_SIGN, self.rotary_inertia_z_kg_m2_m)):
                        if i_rot:
                            d = dN * sign
                            Me[np.ix_(idx, idx)] += w * i_rot * np.outer(d, d)
                cache[key] = (Me, Ke)
            Me, Ke = cache[key]
            sl = slice(N_DOF_NODE * e, N_DOF_NODE * (e + 2))
            M[sl, sl] += Me
            K[sl, sl] += Ke
        return M, K

    # -- analytic references (Euler–Bernoulli, St Venant) -------------------------------------------------------
    def bending_frequency_Hz(self, n: int, plane: str = "vertical") -> float:
        """Free–free bending frequency ``(β_n L)² sqrt(EI / (m L⁴)) / 2π`` (n = 1, 2, 3; no rotary inertia)."""
        EI = self.EI_vertical_N_m2 if plane == "vertical" else self.EI_lateral_N_m2
        return FREE_FREE_BETA_L[n - 1] ** 2 * math.sqrt(EI / (self.mass_kg_m * self.length_m ** 4)) / (2 * math.pi)

    def torsion_frequency_Hz(self, n: int) -> float:
        """Free–free torsion frequency ``n π / L sqrt(GJ / I_p) / 2π``."""
        return n * math.pi / self.length_m * math.sqrt(self.GJ_N_m2 / self.polar_inertia_kg_m2_m) / (2 * math.pi)

    # -- modes -------------------------------------------------------------------------------------------------
    def modes(self, n_modes: int, damping_ratio=0.0) -> "CarBodyModes":
        """The ``n_modes`` lowest elastic free–free modes (module docstring); ``damping_ratio`` one ζ for all or
        one per mode."""
        if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or n_modes < 1:
            raise ValueError(f"n_modes = {n_modes!r}: expected an integer >= 1")
        M, K = self.assemble()
        lam, vec = scipy.linalg.eigh(K, M)
        zero = np.max(np.abs(lam[:6]))                 # rigid modes: round-off of the largest eigenvalue
        if not (zero < _RIGID_TOL * lam[-1] and lam[6] > 1e3 * zero):
            raise RuntimeError(f"the free-free beam has no six rigid-body modes (eigenvalues {lam[:7]})")
        lam, vec = lam[6:], vec[:, 6:]
        if n_modes > lam.size:
            raise ValueError(f"n_modes = {n_modes}: the beam mesh has only {lam.size} elastic modes")
        lam, vec = lam[:n_modes], vec[:, :n_modes]
        vec = vec / np.sqrt(np.einsum("ij,ij->j", vec, M @ vec))
        for j in range(vec.shape[1]):                 # sign rule: the largest entry of every mode is positive
            i = int(np.argmax(np.abs(vec[:, j])))
            if vec[i, j] < 0.0:
                vec[:, j] = -vec[:, j]
        return CarBodyModes(beam=self, omega_rad_s=np.sqrt(lam), shapes=vec,
                            damping_ratio=_damping(damping_ratio, n_modes))

    def rigid_inertia(self) -> tuple[float, np.ndarray]:
        """Mass and inertia tensor about the CG of the beam's rigid-body motion, from its mass matrix."""
        M, _ = self.assemble()
        R = _rigid_fields(self.mesh_x_m())
        Mr = R.T @ M @ R
        return float(Mr[0, 0]), Mr[3:, 3:]


def _rigid_fields(x: np.ndarray) -> np.ndarray:
    """Nodal DOFs (6 n × 6) of the rigid motions about the origin: translations x, y, z, rotations about x, y, z."""
    R = np.zeros((N_DOF_NODE * len(x), 6))
    for i, xi in enumerate(x):
        b = N_DOF_NODE * i
        R[b:b + 3, 0:3] = np.eye(3)
        R[b:b + 3, 3:6] = _skew_minus(np.array([xi, 0.0, 0.0]))
        R[b + 3:b + 6, 3:6] = np.eye(3)
    return R


def _damping(damping_ratio, n_modes: int) -> np.ndarray:
    z = np.atleast_1d(np.asarray(damping_ratio, dtype=float))
    if z.size == 1:
        z = np.full(n_modes, float(z[0]))
    if z.size != n_modes:
        raise ValueError(f"damping_ratio: {z.size} ratios for {n_modes} modes (give one for all or one per mode)")
    if not np.all(np.isfinite(z) & (z >= 0.0) & (z < 1.0)):
        raise ValueError(f"damping_ratio = {z.tolist()}: expected ratios in [0, 1)")
    return z


def _skew(a) -> np.ndarray:
    """The 3 × 3 matrix ã with ``ã b = a × b``."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def _skew_minus(r: np.ndarray) -> np.ndarray:
    """The 3 × 3 matrix A with ``A θ = θ × r`` (= -r̃)."""
    rx, ry, rz = r
    return np.array([[0.0, rz, -ry], [-rz, 0.0, rx], [ry, -rx, 0.0]])


def beam_from_car_body(car_body, *, length_m: float, EI_vertical_N_m2: float, EI_lateral_N_m2: float,
                       GJ_N_m2: float, EA_N: float, n_elements: int = DEFAULT_ELEMENTS, node_x_m=()) -> CarBodyBeam:
    """The beam whose rigid-body mass and inertia are those of ``car_body`` (a
    :class:`~.vehicle_data.BodyData`; module docstring).  Raises ``ValueError`` if the data's pitch or yaw inertia
    is below that of the uniform beam, ``M L²/12``."""
    M, L = car_body.mass_kg, float(length_m)
    base = M * L * L / 12.0
    rot = {}
    for key, I in (("Iyy_kg_m2", car_body.Iyy_kg_m2), ("Izz_kg_m2", car_body.Izz_kg_m2)):
        if I < base * (1.0 - 1e-9):
            raise ValueError(f"car_body.{key} = {I:g} kg m² is below M L²/12 = {base:g} kg m² of a uniform beam of "
                             f"{L:g} m: shorten the flexible body (length_m <= {math.sqrt(12.0 * I / M):.3g} m)")
        rot[key] = max(I - base, 0.0) / L
    return CarBodyBeam(length_m=L, mass_kg_m=M / L, EI_vertical_N_m2=EI_vertical_N_m2,
                       EI_lateral_N_m2=EI_lateral_N_m2, GJ_N_m2=GJ_N_m2, EA_N=EA_N,
                       polar_inertia_kg_m2_m=car_body.Ixx_kg_m2 / L, rotary_inertia_y_kg_m2_m=rot["Iyy_kg_m2"],
                       rotary_inertia_z_kg_m2_m=rot["Izz_kg_m2"], n_elements=n_elements, node_x_m=tuple(node_x_m))


# ================================================================================================= the modes
@dataclass
class CarBodyModes:
    """Elastic free–free modes of the car body.  ``shapes`` (6 n_nodes × n_modes) nodal DOFs of a
    :class:`CarBodyBeam` (``beam``), mass-normalised; ``kinds`` the DOF group carrying each mode's kinetic energy
    ("vertical", "lateral", "torsion", "axial")."""

    beam: CarBodyBeam | None
    omega_rad_s: np.ndarray
    shapes: np.ndarray
    damping_ratio: np.ndarray
    fe: dict | None = None          #: an imported FE model: {"points", "mass", "stiffness", "shapes_points"}
    kinds: tuple = field(default=())

    def __post_init__(self):
        if self.beam is not None and not self.kinds:
            M, _ = self.beam.assemble()
            frac = []
            for dofs in _GROUPS.values():
                mask = np.zeros(M.shape[0], dtype=bool)
                for d in dofs:
                    mask[d::N_DOF_NODE] = True
                S = np.where(mask[:, None], self.shapes, 0.0)
                frac.append(np.einsum("ij,ij->j", S, M @ S))
            names = list(_GROUPS)
            self.kinds = tuple(names[i] for i in np.argmax(np.array(frac), axis=0))

    @property
    def n_modes(self) -> int:
        return int(self.omega_rad_s.size)

    @property
    def frequencies_Hz(self) -> np.ndarray:
        return self.omega_rad_s / (2.0 * math.pi)

    def modal_damping(self) -> np.ndarray:
        return np.diag(2.0 * self.damping_ratio * self.omega_rad_s)

    def point_shapes(self, r_points_m, rotations: bool = False):
        """Displacement of body points per unit modal coordinate, ``(n_points, 3, n_modes)``; ``r_points_m``
        (n, 3) relative to the CG in the body frame.  Beam: the element's own interpolation (Hermite for v, w,
        linear for u, θx) and the rigid arm ``u + θ × r``; imported FE model: the points must be mesh nodes.
        ``rotations=True``: also the small rotations of the beam section there (zero for an FE model of position
        nodes)."""
        r = np.atleast_2d(np.asarray(r_points_m, dtype=float))
        out = np.zeros((len(r), 3, self.n_modes))
        rot = np.zeros((len(r), 3, self.n_modes))
        if self.beam is None:
            pts = self.fe["points"]
            for k, p in enumerate(r):
                i = _mesh_node(pts, p)
                out[k] = self.fe["shapes_points"][3 * i:3 * i + 3]
            return (out, rot) if rotations else out
        x = self.beam.mesh_x_m()
        S = self.shapes
        for k, p in enumerate(r):
            e = int(np.clip(np.searchsorted(x, p[0], side="right") - 1, 0, len(x) - 2))
            Le = x[e + 1] - x[e]
            xi = (p[0] - x[e]) / Le
            N, dN, _ = _hermite(xi, Le)
            L = np.array([1.0 - xi, xi])
            a, b = N_DOF_NODE * e, N_DOF_NODE * (e + 1)
            u = L @ S[[a, b]]
            v = N @ (S[[a + 1, a + 5, b + 1, b + 5]] * _LAT_SIGN[:, None])
            w = N @ (S[[a + 2, a + 4, b + 2, b + 4]] * _VER_SIGN[:, None])
            th_x = L @ S[[a + 3, b + 3]]
            th_y = -(dN @ (S[[a + 2, a + 4, b + 2, b + 4]] * _VER_SIGN[:, None]))
            th_z = dN @ (S[[a + 1, a + 5, b + 1, b + 5]] * _LAT_SIGN[:, None])
            arm = np.array([0.0, p[1], p[2]])
            th = np.vstack([th_x, th_y, th_z])
            out[k] = np.vstack([u, v, w]) + np.cross(th.T, arm).T
            rot[k] = th
        return (out, rot) if rotations else out


def _mesh_node(points: np.ndarray, p, tol: float = 1e-6) -> int:
    d = np.linalg.norm(points - np.asarray(p, dtype=float)[None, :], axis=1)
    i = int(np.argmin(d))
    if d[i] > tol:
        raise ValueError(f"point {list(map(float, p))} m is not a node of the FE mesh (nearest {d[i]:.3g} m away)")
    return i


def read_fe_file(path) -> tuple[np.ndarray, sp.csr_matrix, sp.csr_matrix]:
    """``(points, mass, stiffness)`` of an FE model file (layouts: :func:`modes_from_fe_file`)."""
    try:
        with np.load(path) as f:
            ours = "points" in f.files
    except (ValueError, OSError) as exc:
        raise ValueError(f"{path}: not an FE model file (.npz): {exc}") from None
    if not ours:                                        # a file of Exudyn's FEMinterface.SaveToFile
        from exudyn.FEM import FEMinterface
        fem = FEMinterface()
        try:
            fem.LoadFromFile(str(path))
            points = np.asarray(fem.nodes["Position"], dtype=float)
            M, K = fem.GetMassMatrix(sparse=True), fem.GetStiffnessMatrix(sparse=True)
        except Exception as exc:                        # the FEM tools raise various types for a foreign file
            raise ValueError(f"{path}: neither the 'points/mass/stiffness' layout nor an Exudyn FEMinterface file "
                             f"with position nodes and matrices: {type(exc).__name__}: {exc}") from None
        M, K = sp.csr_matrix(M), sp.csr_matrix(K)
        if points.ndim != 2 or points.shape[1] != 3 or M.shape != (3 * len(points),) * 2 or K.shape != M.shape:
            raise ValueError(f"{path}: expected position nodes (n, 3) and mass/stiffness (3n, 3n), got "
                             f"{points.shape}, {M.shape}, {K.shape}")
        return points, M, K
    try:
        with np.load(path) as f:
            points = np.asarray(f["points"], dtype=float)

            def matrix(name):
                if name in f.files:
                    return sp.csr_matrix(np.asarray(f[name], dtype=float))
                return sp.csr_matrix((f[f"{name}_data"], f[f"{name}_indices"], f[f"{name}_indptr"]),
                                     shape=(3 * len(points),) * 2)

            M, K = matrix("mass"), matrix("stiffness")
    except (KeyError, ValueError, OSError) as exc:
        raise ValueError(f"{path}: not an FE model file (points, mass, stiffness): {exc}") from None
    if points.ndim != 2 or points.shape[1] != 3 or M.shape != (3 * len(points),) * 2 or K.shape != M.shape:
        raise ValueError(f"{path}: expected points (n, 3) and mass/stiffness (3n, 3n), got {points.shape}, {M.shape}, "
                         f"{K.shape}")
    return points, M, K


def modes_from_fe_file(path, n_modes: int, damping_ratio=0.0) -> CarBodyModes:
    """Free–free modes of an external FE model of the car body: an ``.npz`` file with

    * ``points`` (n, 3) — node positions [m] relative to the car body's CG, body axes (x forward, y right, z down);
    * ``mass`` and ``stiffness`` (3n, 3n) — the matrices over the nodes' x, y, z displacements (node-major), dense
      arrays or the three arrays ``<name>_data``, ``<name>_indices``, ``<name>_indptr`` of a CSR matrix;

    or a file written by Exudyn's ``FEMinterface.SaveToFile`` (its ``Position`` nodes, mass and stiffness
    matrices): a model imported with Exudyn's FEM tools (e.g. from Abaqus or ANSYS exports, or NETGEN/NGsolve) and
    saved, its nodes in the car body's axes relative to its CG.

    The six rigid-body modes are discarded (the reference frame carries them); the ``n_modes`` lowest elastic modes
    are kept, mass-normalised.  Rotational DOFs of shells or beams must be condensed out (the FFRF mesh has
    position nodes only)."""
    points, M, K = read_fe_file(path)
    lam, vec = scipy.linalg.eigh(K.toarray(), M.toarray())
    rigid = lam < _RIGID_TOL * lam[-1]
    lam, vec = lam[~rigid], vec[:, ~rigid]
    if n_modes > lam.size:
        raise ValueError(f"{path}: n_modes = {n_modes} but the model has {lam.size} elastic modes")
    lam, vec = lam[:n_modes], vec[:, :n_modes]
    vec = vec / np.sqrt(np.einsum("ij,ij->j", vec, M @ vec))
    return CarBodyModes(beam=None, omega_rad_s=np.sqrt(lam), shapes=vec,
                        damping_ratio=_damping(damping_ratio, n_modes),
                        fe={"points": points, "mass": M, "stiffness": K, "shapes_points": vec},
                        kinds=("fe",) * n_modes)


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
        import exudyn as exu
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
    import exudyn as exu
    from exudyn.FEM import FEMinterface, ObjectFFRFreducedOrderInterface
    from exudyn.itemInterface import MarkerSuperElementPosition, MarkerSuperElementRigid

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
            T[3 * k:3 * k + 3, N_DOF_NODE * i + 3:N_DOF_NODE * i + 6] = _skew_minus(p - np.array([x[i], 0.0, 0.0]))
        # generalized coordinates g = (rigid 6, modal m) -> point displacements S g; point matrices from the
        # beam's exact matrices over g (module docstring)
        G = np.hstack([_rigid_fields(x), modes.shapes])
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
        arm_of = {_key(p): _mesh_node(points, p) for p in attach}
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
    :func:`beam_from_car_body` meshed with nodes at the bogie centres, or the FE model's modes (cached per
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


def _body_handle_class():
    from .vehicle_builder import BodyHandle

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
                from exudyn.itemInterface import MarkerNodePosition
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

    return FlexibleBodyHandle


def add_vehicle_car_body(mbs, vehicle, p_cg_in_frame, *, gravity, name: str, preload_N=None):
    """The flexible car body of ``vehicle`` in ``mbs``, as a body handle for :func:`~.vehicle_builder.build_vehicle`
    (markers at :meth:`~.vehicle_data.VehicleData.car_body_attachment_points_m`, rigid markers at the bogie
    centres).  ``preload_N`` (n_bogies, 2): the secondary springs' static vertical forces (positive: carrying the
    body, left then right); the modal coordinates then start at the static deflection ``q = Ω⁻² Φ_Pᵀ f_P`` under
    them (gravity, uniform, does not load the free–free elastic modes), so the body does not start a bending
    oscillation, and the frame moves vertically by the springs' mean elastic displacement, so the springs keep their
    preload length: exact static equilibrium for a car body symmetric about its CG (a CG offset leaves a pitch
    residual of the order of the elastic displacement)."""
    from exudyn.itemInterface import MarkerNodeRigid

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
    cls = _body_handle_class()
    return cls(name=name, node=fb.node, body=fb.body, marker=marker, marker_node=marker,
               p_cg_in_frame=np.asarray(p_cg_in_frame, dtype=float), mass_kg=vehicle.car_body.mass_kg, flexible=fb)


# ================================================================================== kinematics of body points
class BodyPointKinematics:
    """Acceleration, specific force and displacement of points fixed to the flexible car body, from the frame
    node's and the modal node's outputs (no mesh node needed at the point):

    ``a_P = a_O + R [α × ρ + ω × (ω × ρ) + 2 ω × Φ_P q̇ + Φ_P q̈]``, ``ρ = r_P + Φ_P q`` (ω, α body axes; R the
    frame's rotation; Φ_P the mode shapes at the point, :meth:`CarBodyModes.point_shapes`)."""

    def __init__(self, handle, r_points_m):
        import exudyn as exu
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
        W, A = _skew(w), _skew(al)                                    # a × b = ã b (np.cross is slow on 3-vectors)
        acc_local = rho @ (A + W @ W).T + 2.0 * (P @ qt).reshape(n, 3) @ W.T + (P @ qtt).reshape(n, 3)
        return R, a0 + acc_local @ R.T, p0 + rho @ R.T - self.p_ref - self.r, (self._theta_2d @ q).reshape(n, 3)
