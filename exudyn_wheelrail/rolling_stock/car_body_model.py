r"""The car body as a free–free 3-D Euler–Bernoulli beam (:class:`CarBodyBeam`) and its elastic modes
(:class:`CarBodyModes`): the model that :mod:`.flexible_body` enters into Exudyn as a floating-frame-of-reference body.

Beam model (:class:`CarBodyBeam`)
---------------------------------
The car body is a uniform beam along the track x axis through its centre of mass (CG), from ``-L/2`` to ``+L/2``
(body coordinates relative to the CG; y right, z **down**, the track frame of
:mod:`exudyn_wheelrail.conventions`), meshed with 2-node 3-D Euler–Bernoulli elements — the element of the bridge
deck (:func:`exudyn_wheelrail.structures.beam.element_matrices`: Hermite cubics for the two bending planes, linear
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
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from ..structures.beam import (DOF_GROUPS, LAT_IDX, LAT_SIGN, N_DOF_NODE, VER_IDX, VER_SIGN, DeckSection,
                               element_matrices, hermite)

__all__ = ["FREE_FREE_BETA_L", "DEFAULT_ELEMENTS", "RIGID_TOL", "CarBodyBeam", "CarBodyModes", "beam_from_car_body",
           "rigid_fields", "damping_ratios", "skew", "skew_minus", "mesh_node"]

#: roots β_n L of the free–free beam's frequency equation cos βL cosh βL = 1 (n = 1, 2, 3)
FREE_FREE_BETA_L = (4.730040744862704, 7.853204624095838, 10.995607838001671)
#: beam elements of the car body by default (see the module docstring: 1 % on the third torsion mode needs 19.2)
DEFAULT_ELEMENTS = 24
#: eigenvalues below this fraction of the largest are rigid-body modes
RIGID_TOL = 1e-9


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
                    _, dN, _ = hermite(xi, Le)
                    for idx, sign, i_rot in ((VER_IDX, VER_SIGN, self.rotary_inertia_y_kg_m2_m),
                                             (LAT_IDX, LAT_SIGN, self.rotary_inertia_z_kg_m2_m)):
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
        if not (zero < RIGID_TOL * lam[-1] and lam[6] > 1e3 * zero):
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
                            damping_ratio=damping_ratios(damping_ratio, n_modes))

    def rigid_inertia(self) -> tuple[float, np.ndarray]:
        """Mass and inertia tensor about the CG of the beam's rigid-body motion, from its mass matrix."""
        M, _ = self.assemble()
        R = rigid_fields(self.mesh_x_m())
        Mr = R.T @ M @ R
        return float(Mr[0, 0]), Mr[3:, 3:]


def rigid_fields(x: np.ndarray) -> np.ndarray:
    """Nodal DOFs (6 n × 6) of the rigid motions about the origin: translations x, y, z, rotations about x, y, z."""
    R = np.zeros((N_DOF_NODE * len(x), 6))
    for i, xi in enumerate(x):
        b = N_DOF_NODE * i
        R[b:b + 3, 0:3] = np.eye(3)
        R[b:b + 3, 3:6] = skew_minus(np.array([xi, 0.0, 0.0]))
        R[b + 3:b + 6, 3:6] = np.eye(3)
    return R


def damping_ratios(damping_ratio, n_modes: int) -> np.ndarray:
    """One modal damping ratio per mode (``damping_ratio`` one for all or one per mode), each in [0, 1)."""
    z = np.atleast_1d(np.asarray(damping_ratio, dtype=float))
    if z.size == 1:
        z = np.full(n_modes, float(z[0]))
    if z.size != n_modes:
        raise ValueError(f"damping_ratio: {z.size} ratios for {n_modes} modes (give one for all or one per mode)")
    if not np.all(np.isfinite(z) & (z >= 0.0) & (z < 1.0)):
        raise ValueError(f"damping_ratio = {z.tolist()}: expected ratios in [0, 1)")
    return z


def skew(a) -> np.ndarray:
    """The 3 × 3 matrix ã with ``ã b = a × b``."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def skew_minus(r: np.ndarray) -> np.ndarray:
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
            for dofs in DOF_GROUPS.values():
                mask = np.zeros(M.shape[0], dtype=bool)
                for d in dofs:
                    mask[d::N_DOF_NODE] = True
                S = np.where(mask[:, None], self.shapes, 0.0)
                frac.append(np.einsum("ij,ij->j", S, M @ S))
            names = list(DOF_GROUPS)
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
                i = mesh_node(pts, p)
                out[k] = self.fe["shapes_points"][3 * i:3 * i + 3]
            return (out, rot) if rotations else out
        x = self.beam.mesh_x_m()
        S = self.shapes
        for k, p in enumerate(r):
            e = int(np.clip(np.searchsorted(x, p[0], side="right") - 1, 0, len(x) - 2))
            Le = x[e + 1] - x[e]
            xi = (p[0] - x[e]) / Le
            N, dN, _ = hermite(xi, Le)
            L = np.array([1.0 - xi, xi])
            a, b = N_DOF_NODE * e, N_DOF_NODE * (e + 1)
            u = L @ S[[a, b]]
            v = N @ (S[[a + 1, a + 5, b + 1, b + 5]] * LAT_SIGN[:, None])
            w = N @ (S[[a + 2, a + 4, b + 2, b + 4]] * VER_SIGN[:, None])
            th_x = L @ S[[a + 3, b + 3]]
            th_y = -(dN @ (S[[a + 2, a + 4, b + 2, b + 4]] * VER_SIGN[:, None]))
            th_z = dN @ (S[[a + 1, a + 5, b + 1, b + 5]] * LAT_SIGN[:, None])
            arm = np.array([0.0, p[1], p[2]])
            th = np.vstack([th_x, th_y, th_z])
            out[k] = np.vstack([u, v, w]) + np.cross(th.T, arm).T
            rot[k] = th
        return (out, rot) if rotations else out


def mesh_node(points: np.ndarray, p, tol: float = 1e-6) -> int:
    """Index of the FE mesh node at the point ``p`` (within ``tol``); ``ValueError`` if there is none."""
    d = np.linalg.norm(points - np.asarray(p, dtype=float)[None, :], axis=1)
    i = int(np.argmin(d))
    if d[i] > tol:
        raise ValueError(f"point {list(map(float, p))} m is not a node of the FE mesh (nearest {d[i]:.3g} m away)")
    return i
