r"""The flexible ballasted track: both rails as beams on discrete rail pads, sleepers as masses, ballast as discrete
spring–dampers; a finite segment reduced by its eigenmodes and coupled to the wheel–rail contact through the
deck interface of :mod:`exudyn_wheelrail.structures.deck_kinematics`.

>>> params = TrackParameters.from_file()                       # the 60E1 ballasted default  # doctest: +SKIP
>>> model = FlexibleTrackModel(params, start_m=-30.0, length_m=120.0)                       # doctest: +SKIP
>>> modes = model.modes()                                      # up to params.modes_up_to_Hz  # doctest: +SKIP
>>> track = add_flexible_track(mbs, modes)                     # an ExudynBridge handle       # doctest: +SKIP
>>> contact = add_wheel_rail_contact(mbs, nodes, pair, ..., structure=track)                    # doctest: +SKIP

Model
-----
Frames and signs of :mod:`exudyn_wheelrail.conventions` and :mod:`exudyn_wheelrail.structures.beam`: track
frame, x along the track (track distance ``s``), y right, z **down**; a roll θ > 0 (right-handed about +x) lowers
the right rail.  Each rail is an Euler–Bernoulli beam bending vertically (``E I_vertical``, displacement ``w``) and
laterally (``E I_lateral``, ``v``), mass ``m`` per metre, meshed with ``elements_per_bay`` two-node Hermite elements
(consistent mass) between sleepers.  Sleeper j at ``s = start_m + j d`` (j = 0 … n, the rail ends on the first and
last sleeper) is a rigid body with vertical ``z_j``, lateral ``y_j`` and roll ``θ_j`` (mass ``m_s``, roll inertia
``I_s``); sleeper bending is neglected (the first free–free bending mode of a concrete sleeper lies near the
upper end of the kept band).  Rail pad (per rail seat): vertical spring–damper ``k_p, c_p`` between the rail and
the sleeper's rail seat at ``y = ∓b/2`` (``b`` the rail centre distance: the seat moves down by ``z_j ± (b/2) θ_j``)
and a lateral one ``k_py, c_py`` between rail and sleeper.  Ballast (per sleeper): vertical ``k_b, c_b`` as two
halves under the rail seats (sleeper stiffness ``k_b`` in bounce, ``k_b b²/4`` in roll) and lateral ``k_by, c_by``.
Rail torsion and the rail's roll about its own foot are not modelled; a lateral force moves the rail as a beam.

The left–right symmetry splits the track exactly into three independent beams on discrete supports (the rails'
centre-line coordinates of the deck interface):

* **vertical** (bounce): ``z_rail = (w_L + w_R)/2`` with the sleepers' ``z``: bending stiffness 2EI, mass 2m, pad
  2k_p, sleeper m_s, ballast k_b;
* **roll**: ``θ_rail = (w_R − w_L)/b`` with the sleepers' roll: stiffness EI b²/2, inertia m b²/2, pad k_p b²/2,
  sleeper I_s, ballast k_b b²/4;
* **lateral**: ``y_rail = (v_L + v_R)/2`` with the sleepers' ``y``: 2EI_lateral, 2m, 2k_py, m_s, k_by.

The fourth, gauge spreading ``v_R − v_L``, is not excited by the interface's forces (the lateral force of a
wheelset is shared equally by the two rails) and is not represented: the contact sees both rails move together
laterally, and the rail under a flange does not give way more than the other.  The static wheel load on one rail
``P`` puts ``2P`` on the vertical beam, which deflects by Zimmermann's ``P β/(2k)`` with the single rail's
``β = (k/(4EI))^¼`` (``k`` the support stiffness of one rail per metre).

Over a bridge deck: :mod:`.flexible_deck` (the ballast on the deck beam over a span, coupled modes).
The parameters and the track file: :mod:`.flexible_parameters`; the closed-form references (Zimmermann, Winkler,
the continuously supported track): :mod:`.flexible_references`; the length of a segment: :mod:`.flexible_segment`.

Modal reduction and coupling
----------------------------
The segment is reduced by the undamped eigenmodes of each beam up to ``modes_up_to_Hz`` (mass-normalised,
``Φᵀ M Φ = I``, ``Φᵀ K Φ = diag(ω²)``), with the damping projected, ``Φᵀ C Φ`` (pads and ballast damp
non-proportionally: the full projected matrix is kept, one block per beam; ``damping="diagonal"`` keeps its
diagonal).  The modes' rail displacement ``(y_rail, z_rail, θ_rail)`` along the track is a
:class:`~exudyn_wheelrail.structures.modal_shapes.ShapeTable` with the rail height 0: the connector reads it exactly as
a bridge deck (:func:`~exudyn_wheelrail.structures.deck_kinematics.deck_arrays`: ``Φ(s) q`` under each wheelset,
forces back as ``Φ(s)ᵀ (F_y, F_z, M_x)``) — the contact force acts on the rails at the moving contact point
through the beam's Hermite shape functions, and the rails' displacement and velocity there enter the contact
geometry and the creepages.  ``y`` and ``z`` rows are the beams' cubic Hermite fields (exact); the roll row is
interpolated linearly between the table points (``table_subdivision`` points per element), as the deck's
torsion.  Off the segment the track is rigid (Φ = 0).

Why Euler–Bernoulli (:meth:`FlexibleTrackModel.timoshenko_correction`; shear coefficient 0.4, E/G = 2.6): shear
and rotary inertia lower the frequency of a free 60E1 bending wave by 2.7 % at 100 Hz, 5 % at 200 Hz, 10 % at
400 Hz, 17 % at 800 Hz and 26 % at the pinned–pinned wavenumber π/d; on the track the support carries part of the
stiffness, so below ~300 Hz (the vehicle–track band: full-track resonance, sleeper passing, wheel–rail forces
from irregularities) the Euler–Bernoulli rail is within a few per cent.  The modes kept between ~420 Hz and the
cut-off (the rail-on-pad branch) are kept for the flexibility they carry to the contact, not for their
frequencies; the pinned–pinned resonance (1.42 kHz Euler–Bernoulli for 60E1 at 0.6 m, ~1 kHz measured) is
neither kept nor valid here.

Static correction (``modes(static_correction=True)``, the default). The dropped modes carry part of the track's
static flexibility under a wheel — 3 % of it at the default 800 Hz, 21 % at 400 Hz (the rail-on-pad branch, which
carries the pad compression, starts at ~420 Hz; ``benchmarks/bench_flexible_track.py``). Their static part is kept:
:attr:`FlexibleTrackModes.residual_table` is the residual flexibility at the rails, ``G_res(s) = Ψ K⁻¹ Ψᵀ − Σ_kept φ
φᵀ/ω²`` along the table, and the connector puts it in series with the contacts of each wheelset
(:mod:`exudyn_wheelrail.structures.deck_kinematics`,
:func:`~exudyn_wheelrail.multibody.connector_core.series_compliance`): the static deflection under a wheel is then
the full model's at any cut-off, and the dropped modes respond quasi-statically (exact for loads well below their
frequencies; the error of a load at f is ~(f/f_d)² of the residual part, f_d ≳ 420 Hz the lowest dropped mode).
Neglected: the residual's coupling between wheelsets (0.2 % of the static deflection within a bogie at 400 Hz, 2.5 m
apart) and the creep forces' share; the roll row of the kept shapes is linear between the table's points (0.8 % of
the roll flexibility mid-element). Explicit RK44 is stable for ``ω dt < 2.83``; the wheel on the rail's modal mass,
through the contact in series with the residual, is the highest coupled frequency
(:func:`~.flexible_contact.contact_mode_Hz`), checked before a scenario runs: 0.46 ms at most for the default track
at 800 Hz, 0.79 ms at 400 Hz (0.35 and 0.42 ms without the correction).

Cost: one modal coordinate per kept mode, their number proportional to the segment's length (9.4 per metre at
800 Hz for the default track); the segment should carry the run (:func:`~.flexible_segment.segment_for_run`) and no more.
"""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg
from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2, VObjectGenericODE2

from ..jit import compiled
from ..structures.beam import bending_element, hermite
from ..structures.bridge_exudyn import ExudynBridge
from ..structures.deck_kinematics import residual_at
from ..structures.modal_shapes import NS_DV, NS_DW, NS_TH, NS_V, NS_W, ShapeTable, modal_shape_at
from .flexible_parameters import DAMPING_FORMS, KINDS, TrackFileError, TrackParameters

__all__ = ["FlexibleTrackModel", "FlexibleTrackModes", "add_flexible_track"]


class FlexibleTrackModel:
    """A straight segment of flexible track from ``start_m`` (the first sleeper) over ``length_m`` (rounded up to
    whole sleeper bays), on rigid ground; module docstring.  :meth:`assemble` gives the finite-element matrices of
    one of the three beams (:data:`KINDS`), :meth:`modes` the reduced model."""

    def __init__(self, params: TrackParameters, start_m: float, length_m: float):
        if not isinstance(params, TrackParameters):
            raise TypeError(f"params={params!r}: expected TrackParameters (TrackParameters.from_file())")
        if not (isinstance(start_m, (int, float)) and math.isfinite(start_m)):
            raise TrackFileError(f"flexible track start_m = {start_m!r}: expected a finite number")
        d = params.sleeper_spacing_m
        if not (isinstance(length_m, (int, float)) and math.isfinite(length_m) and length_m >= 2.0 * d):
            raise TrackFileError(f"flexible track length_m = {length_m!r}: expected at least two sleeper bays "
                                 f"({2.0 * d:g} m)")
        self.params = params
        self.start_m = float(start_m)
        self.n_bays = int(math.ceil(length_m / d - 1e-9))
        self.length_m = self.n_bays * d
        ne = params.elements_per_bay
        self.h_m = d / ne
        self.n_nodes = self.n_bays * ne + 1
        self.n_sleepers = self.n_bays + 1
        self.node_s_m = self.start_m + self.h_m * np.arange(self.n_nodes)
        self.sleeper_s_m = self.start_m + d * np.arange(self.n_sleepers)
        self.sleeper_node = np.arange(self.n_sleepers) * ne

    @property
    def n_dof(self) -> int:
        """DOFs of one beam: (u, du/ds) per node, then one per sleeper."""
        return 2 * self.n_nodes + self.n_sleepers

    def assemble(self, kind: str) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]:
        """``(M, K, C)`` of one beam (:data:`KINDS`): rail DOFs ``(u_i, du_i/ds)`` then the sleepers'."""
        EI, m, kp, cp, ms, kb, cb = self.params.beam(kind)
        Ke, Me = bending_element(self.h_m, EI, m)
        rows, cols, kv, mv, cv = [], [], [], [], []
        idx = np.arange(4)
        for e in range(self.n_nodes - 1):
            dofs = 2 * e + idx
            r, c = np.meshgrid(dofs, dofs, indexing="ij")
            rows.append(r.ravel())
            cols.append(c.ravel())
            kv.append(Ke.ravel())
            mv.append(Me.ravel())
            cv.append(np.zeros(16))
        for j in range(self.n_sleepers):
            a = 2 * self.sleeper_node[j]
            s = 2 * self.n_nodes + j
            rows.append(np.array([a, s, a, s, s]))
            cols.append(np.array([a, s, s, a, s]))
            kv.append(np.array([kp, kp, -kp, -kp, kb]))
            cv.append(np.array([cp, cp, -cp, -cp, cb]))
            mv.append(np.array([0.0, 0.0, 0.0, 0.0, ms]))
        r, c = np.concatenate(rows), np.concatenate(cols)
        n = self.n_dof

        def mat(v):
            return sp.csr_matrix((np.concatenate(v), (r, c)), shape=(n, n))

        return mat(mv), mat(kv), mat(cv)

    def load_vector(self, kind: str, s_m: float, force: float) -> np.ndarray:
        """Consistent nodal load of a point force (or moment, ``roll``) on the rail field at ``s_m``."""
        e, xi = self._locate(np.atleast_1d(s_m))
        N, _, _ = hermite(xi, self.h_m)
        f = np.zeros(self.n_dof)
        f[2 * e[0] + np.arange(4)] += force * N[0]
        return f

    def rail_field(self, kind: str, u: np.ndarray, s_m) -> tuple[np.ndarray, np.ndarray]:
        """The rail field ``u`` and ``du/ds`` of one beam's DOF vector(s) ``u`` (n_dof, ...) at ``s_m``."""
        e, xi = self._locate(np.atleast_1d(np.asarray(s_m, dtype=float)))
        N, dN, _ = hermite(xi, self.h_m)
        dofs = 2 * e[:, None] + np.arange(4)
        U = np.asarray(u)[dofs]                                      # (n_s, 4, ...)
        return np.einsum("ij,ij...->i...", N, U), np.einsum("ij,ij...->i...", dN, U)

    def bending_moment_Nm(self, kind: str, u: np.ndarray, s_m: float) -> float:
        """``-EI u''`` of the rail field at ``s_m`` (from the element to the left of a node; the bending moment
        of the beam, sagging positive with z down), for one beam's equivalent EI."""
        EI = self.params.beam(kind)[0]
        e, xi = self._locate(np.atleast_1d(s_m), left=True)
        h = self.h_m
        x = xi[0]
        _, _, d2N = hermite(x, h)
        return float(-EI * d2N @ np.asarray(u)[2 * e[0] + np.arange(4)])

    def nearest_sleeper(self, s_m, start_m: float | None = None) -> np.ndarray:
        """Index of the sleeper nearest to each track distance in ``s_m``, clipped to the segment; ``start_m``: where
        the segment starts now (a moving window's current start; default :attr:`start_m`)."""
        start = self.start_m if start_m is None else float(start_m)
        j = np.rint((np.asarray(s_m, dtype=float) - start) / self.params.sleeper_spacing_m).astype(int)
        return np.clip(j, 0, self.n_sleepers - 1)

    def _locate(self, s, left=False):
        x = (np.asarray(s, dtype=float) - self.start_m) / self.h_m
        if np.any(x < -1e-9) or np.any(x > self.n_nodes - 1 + 1e-9):
            raise ValueError(f"s = {s} m is off the flexible segment [{self.start_m}, "
                             f"{self.start_m + self.length_m}] m")
        e = np.clip(np.ceil(x - 1e-12).astype(int) - 1 if left else np.floor(x).astype(int), 0, self.n_nodes - 2)
        return e, x - e

    def static(self, kind: str, loads) -> np.ndarray:
        """Full finite-element static solution of one beam under point loads ``[(s_m, force), ...]``."""
        _, K, _ = self.assemble(kind)
        f = sum(self.load_vector(kind, s, F) for s, F in loads)
        return sp.linalg.spsolve(K.tocsc(), f)

    def receptance(self, kind: str, s_m: float, f_Hz) -> np.ndarray:
        """Full finite-element point receptance ``u(s)/F(s)`` [m/N] (or rad/(N m) for ``roll``) of one beam."""
        M, K, C = self.assemble(kind)
        f = self.load_vector(kind, s_m, 1.0)
        out = np.empty(len(np.atleast_1d(f_Hz)), dtype=complex)
        for i, fr in enumerate(np.atleast_1d(f_Hz)):
            w = 2.0 * math.pi * fr
            u = sp.linalg.spsolve((K - w * w * M + 1j * w * C).tocsc(), f.astype(complex))
            out[i] = f @ u
        return out

    def timoshenko_correction(self, f_Hz: float, shear_coefficient: float = 0.4,
                              E_over_G: float = 2.6) -> tuple[float, float]:
        """``(κ, Δf/f)`` at ``f_Hz``: the rail's free vertical bending wavenumber κ = (ω² m/EI)^¼ and the relative
        lowering of the bending frequency at that wavenumber by shear and rotary inertia,
        ``1 − 1/√(1 + (κ r)² (1 + E/(k_s G)))`` with ``r² = I/A`` (A from the mass, steel 7850 kg/m³)."""
        p = self.params
        kappa = ((2 * math.pi * f_Hz) ** 2 * p.rail_mass_kg_m / (p.rail_E_Pa * p.rail_I_vertical_m4)) ** 0.25
        r2 = p.rail_I_vertical_m4 / (p.rail_mass_kg_m / 7850.0)
        return kappa, 1.0 - 1.0 / math.sqrt(1.0 + kappa ** 2 * r2 * (1.0 + E_over_G / shear_coefficient))

    def modes(self, f_max_Hz: float | None = None, damping: str = "full", kinds=KINDS,
              static_correction: bool = True) -> "FlexibleTrackModes":
        """The reduced model: the eigenmodes of the three beams up to ``f_max_Hz`` (default the parameters'
        ``modes_up_to_Hz``) with the projected damping (:data:`DAMPING_FORMS`); ``kinds``: the beams reduced (the
        others keep no mode: rigid); ``static_correction``: the dropped modes' flexibility at the rails acts in
        series with the contact (:attr:`FlexibleTrackModes.residual_table`, module docstring)."""
        if damping not in DAMPING_FORMS:
            raise ValueError(f"damping={damping!r}: expected one of {DAMPING_FORMS}")
        f_max = self.params.modes_up_to_Hz if f_max_Hz is None else float(f_max_Hz)
        if not f_max > 0.0:
            raise TrackFileError(f"model.modes_up_to_Hz = {f_max!r}: must be > 0")
        w2_max = (2.0 * math.pi * f_max) ** 2
        blocks = []
        for kind in KINDS:
            if kind not in kinds:
                blocks.append((kind, np.zeros(0), np.zeros((self.n_dof, 0)), np.zeros((0, 0))))
                continue
            M, K, C = self.assemble(kind)
            w2, phi = scipy.linalg.eigh(K.toarray(), M.toarray(), subset_by_value=(-np.inf, w2_max))
            D = phi.T @ (C @ phi)
            if damping == "diagonal":
                D = np.diag(np.diag(D))
            blocks.append((kind, np.sqrt(np.maximum(w2, 0.0)), phi, D))
        return FlexibleTrackModes(self, blocks, f_max, damping, static_correction)


class FlexibleTrackModes:
    """The reduced flexible track (:meth:`FlexibleTrackModel.modes`): ``omega_rad_s`` (n_modes,), ``kinds``
    (per mode, :data:`KINDS`), ``shapes[kind]`` (n_dof of that beam × its modes), ``damping_matrix`` (n × n,
    block diagonal), ``table`` (the :class:`~exudyn_wheelrail.structures.modal_shapes.ShapeTable` the connector reads).
    Modal equations ``q̈ + D q̇ + diag(ω²) q = Q``; the same interface as
    :class:`~exudyn_wheelrail.structures.bridge.BridgeModes` where the deck machinery uses it."""

    def __init__(self, model: FlexibleTrackModel, blocks, f_max_Hz: float, damping: str,
                 static_correction: bool = True):
        self.model = model
        self.f_max_Hz = float(f_max_Hz)
        self.damping = damping
        self.static_correction = bool(static_correction)
        self.omega_rad_s = np.concatenate([b[1] for b in blocks])
        self.frequencies_Hz = self.omega_rad_s / (2.0 * math.pi)
        self.kinds = tuple(k for b in blocks for k in [b[0]] * len(b[1]))
        self.shapes = {b[0]: b[2] for b in blocks}
        self.slices = {}
        i = 0
        for b in blocks:
            self.slices[b[0]] = slice(i, i + len(b[1]))
            i += len(b[1])
        self.damping_matrix = scipy.linalg.block_diag(*[b[3] for b in blocks]) if blocks else np.zeros((0, 0))
        if self.damping_matrix.shape != (self.n_modes, self.n_modes):
            self.damping_matrix = np.zeros((self.n_modes, self.n_modes))
        self.table = self._shape_table()

    @property
    def n_modes(self) -> int:
        return int(self.omega_rad_s.shape[0])

    def __repr__(self):
        n = {k: self.slices[k].stop - self.slices[k].start for k in KINDS}
        return (f"FlexibleTrackModes({self.n_modes} modes up to {self.f_max_Hz:g} Hz: "
                + ", ".join(f"{v} {k}" for k, v in n.items()) + f"; {self.model.length_m:g} m)")

    def _shape_table(self) -> ShapeTable:
        mdl = self.model
        sub = mdl.params.table_subdivision
        n_el = (mdl.n_nodes - 1) * sub
        hs = mdl.h_m / sub
        s_pts = mdl.start_m + hs * np.arange(n_el + 1)
        e = np.minimum(np.arange(n_el + 1) // sub, mdl.n_nodes - 2)
        xi = (s_pts - mdl.node_s_m[e]) / mdl.h_m
        N, dN, _ = hermite(xi, mdl.h_m)
        dofs = 2 * e[:, None] + np.arange(4)
        ns = np.zeros((n_el + 1, 5, self.n_modes))
        for kind, rows in (("lateral", (NS_V, NS_DV)), ("vertical", (NS_W, NS_DW)), ("roll", (NS_TH, None))):
            phi = self.shapes[kind]
            if phi.shape[1] == 0:
                continue
            U = phi[dofs]                                           # (n_pts, 4, n_k)
            sl = self.slices[kind]
            ns[:, rows[0], sl] = np.einsum("ij,ijk->ik", N, U)
            if rows[1] is not None:
                ns[:, rows[1], sl] = np.einsum("ij,ijk->ik", dN, U)
        return ShapeTable(float(mdl.start_m), 0.0, hs * np.arange(n_el), np.full(n_el, hs),
                          np.column_stack([np.arange(n_el), np.arange(1, n_el + 1)]).astype(np.int64),
                          np.ascontiguousarray(ns))

    @property
    def residual_table(self) -> np.ndarray | None:
        """The static flexibility of the dropped modes at the rails, per point of :attr:`table`: (n_points, 6),
        columns ``G_yy, G_zz, G_θθ, G_yz, G_yθ, G_zθ`` of the 3 × 3 matrix ``G_res(s) = Ψ(s) K⁻¹ Ψ(s)ᵀ − Σ_k
        Φ_k(s) Φ_k(s)ᵀ/ω_k²`` ([m/N], [m/(N m)] = [rad/N], [rad/(N m)]; rows y_rail, z_rail, θ_rail; ``Ψ(s)`` the
        finite-element interpolation of the rail field at s, ``K`` the full stiffness, the sum over the kept modes)
        — what the reduced model lacks of the full model's static deflection under a force at s.  The connector
        puts it in series with each contact (:mod:`exudyn_wheelrail.structures.deck_kinematics`); None without
        ``static_correction``.  A beam kept rigid (no modes) has none."""
        if not getattr(self, "static_correction", False):
            return None
        if "_residual" not in self.__dict__:
            self._residual = self._residual_flexibility()
        return self._residual

    def residual_at(self, s_m) -> np.ndarray:
        """``G_res(s)`` (..., 3, 3) at track distance(s) ``s_m`` (:attr:`residual_table`, linear between the
        table's points as the connector reads it; zero off the segment or without the static correction)."""
        s = np.asarray(s_m, dtype=float)
        out = np.zeros((s.size, 3, 3))
        R = self.residual_table
        if R is not None:
            tb = self.table
            g = np.empty(6)
            for n, x in enumerate(s.ravel()):
                residual_at(float(x), tb.start_m, tb.elem_x0, tb.elem_len, tb.elem_nodes, R, g)
                out[n] = [[g[0], g[3], g[4]], [g[3], g[1], g[5]], [g[4], g[5], g[2]]]
        return out.reshape(s.shape + (3, 3))

    def _static_flexibility(self, s_pts: np.ndarray) -> np.ndarray:
        """The full finite-element model's static flexibility at the rails, (n_points, 3, 3) at ``s_pts`` (rows
        y_rail, z_rail, θ_rail; the three beams are independent: diagonal).  A beam without modes: zero."""
        mdl = self.model
        G = np.zeros((s_pts.size, 3, 3))
        e, xi = mdl._locate(s_pts)
        N, _, _ = hermite(xi, mdl.h_m)
        for kind, row in (("lateral", 0), ("vertical", 1), ("roll", 2)):
            if self.shapes[kind].shape[1] == 0:
                continue
            _, K, _ = mdl.assemble(kind)
            Psi = np.zeros((mdl.n_dof, s_pts.size))
            cols = np.arange(s_pts.size)
            for j in range(4):
                Psi[2 * e + j, cols] = N[:, j]
            X = sp.linalg.splu(K.tocsc()).solve(Psi)
            G[:, row, row] = np.einsum("ij,ij->j", Psi, X)
        return G

    def _residual_flexibility(self) -> np.ndarray:
        tb = self.table
        s_pts = tb.start_m + np.concatenate([tb.elem_x0, [tb.elem_x0[-1] + tb.elem_len[-1]]])
        G = self._static_flexibility(s_pts)
        rows = tb.node_shapes[:, [NS_V, NS_W, NS_TH], :]                  # (n_points, 3, n_modes) at the points
        G -= np.einsum("pik,pjk->pij", rows / self.omega_rad_s, rows / self.omega_rad_s)
        out = np.empty((s_pts.size, 6))
        for c, (i, j) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))):
            out[:, c] = G[:, i, j]
        out[:, :3] = np.maximum(out[:, :3], 0.0)        # round-off where the kept modes carry all of it
        return np.ascontiguousarray(out)

    # modal matrices (the deck machinery's names)
    def modal_mass(self) -> np.ndarray:
        return np.eye(self.n_modes)

    def modal_stiffness(self) -> np.ndarray:
        return np.diag(self.omega_rad_s ** 2)

    def modal_damping(self) -> np.ndarray:
        return self.damping_matrix.copy()

    def shape_at(self, s_m) -> np.ndarray:
        """``Φ(s)``: (..., 3, n_modes), rows y_rail, z_rail, θ_rail (zero off the segment)."""
        s = np.asarray(s_m, dtype=float)
        out = np.empty((s.size, 3, self.n_modes))
        for i, x in enumerate(s.ravel()):
            modal_shape_at(float(x), *self.table, out[i])
        return out.reshape(s.shape + (3, self.n_modes))

    def static_coordinates(self, s_m, forces) -> np.ndarray:
        """Modal coordinates of the static equilibrium under forces ``(Fy, Fz, Mx)`` (k, 3) on the rails' centre
        line at ``s_m`` (k,): ``q = diag(ω⁻²) Σ Φ(s_i)ᵀ F_i`` (the reduced model's own statics)."""
        s = np.atleast_1d(np.asarray(s_m, dtype=float))
        F = np.asarray(forces, dtype=float).reshape(-1, 3)
        Q = np.einsum("kij,ki->j", self.shape_at(s), F)
        return Q / self.omega_rad_s ** 2

    def receptance(self, kind: str, s_m: float, f_Hz) -> np.ndarray:
        """Point receptance of the reduced model (the row of ``kind`` at ``s_m``), with the kept damping, plus the
        residual flexibility of the static correction (frequency-independent: the dropped modes quasi-static)."""
        row = {"lateral": 0, "vertical": 1, "roll": 2}[kind]
        phi = self.shape_at(s_m)[row]
        residual = float(self.residual_at(s_m)[row, row])
        out = np.empty(len(np.atleast_1d(f_Hz)), dtype=complex)
        W2 = np.diag(self.omega_rad_s ** 2)
        for i, fr in enumerate(np.atleast_1d(f_Hz)):
            w = 2.0 * math.pi * fr
            out[i] = phi @ np.linalg.solve(W2 - w * w * np.eye(self.n_modes) + 1j * w * self.damping_matrix,
                                           phi) + residual
        return out

    def beam_dofs(self, q) -> dict:
        """The DOF vectors of the three beams (each n_dof, ...) for modal coordinates ``q`` (n_modes, ...)."""
        q = np.asarray(q, dtype=float)
        return {k: self.shapes[k] @ q[self.slices[k]] for k in KINDS}

    def _support_rows(self, kind: str) -> tuple[np.ndarray, np.ndarray]:
        """One beam's mode rows at the rail over each sleeper and at each sleeper (n_sleepers × its modes)."""
        rows = self.__dict__.setdefault("_rows", {})
        if kind not in rows:
            mdl, phi = self.model, self.shapes[kind]
            rows[kind] = (np.ascontiguousarray(phi[2 * mdl.sleeper_node]),
                          np.ascontiguousarray(phi[2 * mdl.n_nodes:]))
        return rows[kind]

    def sleeper_state(self, q, sleepers=None) -> dict:
        """Per sleeper (all, or the indices ``sleepers``): ``z_m`` (down), ``y_m`` (right), ``roll_rad`` for modal
        coordinates ``q``."""
        j = slice(None) if sleepers is None else np.asarray(sleepers)
        q = np.asarray(q, dtype=float)
        return {"z_m": self._support_rows("vertical")[1][j] @ q[self.slices["vertical"]],
                "roll_rad": self._support_rows("roll")[1][j] @ q[self.slices["roll"]],
                "y_m": self._support_rows("lateral")[1][j] @ q[self.slices["lateral"]]}

    def support_forces_N(self, q, q_t, sleepers=None) -> dict:
        """Per sleeper (all, or the indices ``sleepers``): vertical pad forces on the left and right rail seat and
        the ballast force under them (compression positive, z down), the lateral pad force (each rail, +y on the
        sleeper) and the lateral ballast force on the ground; spring and damper together."""
        p = self.model.params
        j = slice(None) if sleepers is None else np.asarray(sleepers)
        b = p.rail_centre_distance_m

        def both(kind, x):
            rail, sleeper = self._support_rows(kind)
            xk = np.asarray(x, dtype=float)[self.slices[kind]]
            return rail[j] @ xk, sleeper[j] @ xk

        (zr, zs), (zr_t, zs_t) = both("vertical", q), both("vertical", q_t)
        (tr, ts), (tr_t, ts_t) = both("roll", q), both("roll", q_t)
        (yr, ys), (yr_t, ys_t) = both("lateral", q), both("lateral", q_t)
        kp, cp = p.pad_k_vertical_N_m, p.pad_c_vertical_Ns_m
        kb, cb = 0.5 * p.ballast_k_vertical_N_m, 0.5 * p.ballast_c_vertical_Ns_m
        out = {}
        for side, sgn in (("left", -1.0), ("right", 1.0)):
            dr = zr + sgn * 0.5 * b * tr - (zs + sgn * 0.5 * b * ts)
            dr_t = zr_t + sgn * 0.5 * b * tr_t - (zs_t + sgn * 0.5 * b * ts_t)
            out[f"pad_vertical_{side}_N"] = kp * dr + cp * dr_t
            out[f"ballast_vertical_{side}_N"] = kb * (zs + sgn * 0.5 * b * ts) + cb * (zs_t + sgn * 0.5 * b * ts_t)
        out["pad_lateral_each_rail_N"] = p.pad_k_lateral_N_m * (yr - ys) + p.pad_c_lateral_Ns_m * (yr_t - ys_t)
        out["ballast_lateral_N"] = p.ballast_k_lateral_N_m * ys + p.ballast_c_lateral_Ns_m * ys_t
        return out


# ------------------------------------------------------------------------------------- the Exudyn system
class _CouplingDamping:
    """The off-diagonal part of the projected damping, ``-D_off q̇``, as the force of a second ``ObjectGenericODE2``
    on the modal node: one dense matrix–vector product per beam.  Measured (Exudyn 1.13.6, the crossing of
    benchmarks/bench_flexible_track.py): the full blocks in the object's sparse damping container made the solve
    2.3 times slower (7.4 s against 3.2 s at the same load), with the same results to 1e-10."""

    def __init__(self, modes: "FlexibleTrackModes"):
        self.blocks = []
        seen = set()
        for kind in KINDS:
            sl = modes.slices[kind]
            if (sl.start, sl.stop) in seen:                         # coupled modes: one block for all beams
                continue
            seen.add((sl.start, sl.stop))
            D = modes.damping_matrix[sl, sl].copy()
            np.fill_diagonal(D, 0.0)
            if D.size and np.any(D):
                self.blocks.append((sl, np.ascontiguousarray(D)))
        self.f = np.zeros(modes.n_modes)

    def force(self, mbs, t, itemIndex, q, q_t):
        q_t = np.asarray(q_t)
        for sl, D in self.blocks:
            _matvec(D, q_t[sl], self.f[sl])
        return -self.f


@compiled
def _matvec(D, v, out):
    """``out = D v`` in one thread: inside the solve a threaded BLAS competes with Exudyn for the cores (measured
    on 2 shared cores: a track of ~1300 modes solved 3-4.5 times slower with numpy's threaded BLAS)."""
    for i in range(D.shape[0]):
        acc = 0.0
        for j in range(D.shape[1]):
            acc += D[i, j] * v[j]
        out[i] = acc


def add_flexible_track(mbs, modes: FlexibleTrackModes, name: str = "flexible_track") -> ExudynBridge:
    """Enter the reduced track into ``mbs`` (before ``mbs.Assemble()``): one ``NodeGenericODE2`` with the modal
    coordinates, one ``ObjectGenericODE2`` with ``I``, ``diag(ω²)`` and the diagonal of the kept damping (sparse
    containers), and, with ``damping="full"``, a second one on the same node whose force is the damping's coupling
    ``-D_off q̇`` (:class:`_CouplingDamping`).  Returns an :class:`~exudyn_wheelrail.structures.bridge_exudyn.ExudynBridge`
    handle whose ``modes`` is the :class:`FlexibleTrackModes`: pass it as the connector's ``bridge=`` (the deck
    interface, module docstring)."""
    if not isinstance(modes, FlexibleTrackModes):
        raise TypeError(f"modes={modes!r}: expected FlexibleTrackModes (FlexibleTrackModel.modes())")
    n = modes.n_modes
    if n == 0:
        raise TrackFileError(f"{modes.model.params.source}: model.modes_up_to_Hz = {modes.f_max_Hz:g} Hz: no track "
                             "mode below it (the track is rigid at that band; raise it or use the rigid track)")

    def container(a):
        mc = exu.MatrixContainer()
        mc.SetWithSparseMatrix(sp.csr_matrix(a))
        return mc

    node = mbs.AddNode(NodeGenericODE2(name=f"{name}_modal", numberOfODE2Coordinates=n, referenceCoordinates=[0.0] * n,
                                       initialCoordinates=[0.0] * n, initialCoordinates_t=[0.0] * n))
    obj = mbs.AddObject(ObjectGenericODE2(name=name, nodeNumbers=[node], massMatrix=container(sp.identity(n)),
                                          stiffnessMatrix=container(sp.diags(modes.omega_rad_s ** 2)),
                                          dampingMatrix=container(sp.diags(np.diag(modes.damping_matrix))),
                                          visualization=VObjectGenericODE2(show=False)))
    coupling = _CouplingDamping(modes)
    if coupling.blocks:
        mbs.AddObject(ObjectGenericODE2(name=f"{name}_damping_coupling", nodeNumbers=[node],
                                        forceUserFunction=coupling.force, visualization=VObjectGenericODE2(show=False)))
        mbs.variables[f"{name}_damping_coupling"] = coupling          # keeps the user function's owner alive
    return ExudynBridge(modes, "modal", int(node), int(obj))
