r"""A deck's modal basis as the track sees it (:class:`ModalBasis`): natural frequencies, modal damping, the kind of
every mode and the shape table (:class:`~.modal_shapes.ShapeTable`) that gives the rails' displacement ``Φ(s) q``
under a wheel and the generalized forces ``Φ(s)ᵀ F`` of a wheel force.  The shapes are **mass-normalised**: the
modal equations are ``q̈ + diag(2ζω) q̇ + diag(ω²) q = Q``.

Two sources give one: the built-in beam deck (:class:`~.bridge.BridgeModes`, from the finite-element model) and a
modes file from any FE program (:class:`~.modes_file.SampledModes`).  Whatever couples to a deck — Exudyn's modal
node (:func:`~.bridge_exudyn.add_bridge`), moving loads, sprung masses, the wheel–rail connector — reads only what
is declared here."""
from __future__ import annotations

import math

import numpy as np

from .modal_shapes import ShapeTable, modal_shapes_many

__all__ = ["ModalBasis", "MODE_KINDS"]

#: the kinds of a mode (the motion that carries it)
MODE_KINDS = ("axial", "lateral", "vertical", "torsion")


class ModalBasis:
    """Mass-normalised modes of a deck along the track (module docstring).

    Attributes: ``omega_rad_s``, ``frequencies_Hz``, ``damping_ratio`` (per mode; may be edited per mode before
    :func:`~.bridge_exudyn.add_bridge`), ``kinds`` (one of :data:`MODE_KINDS` per mode), ``table``
    (:class:`~.modal_shapes.ShapeTable`)."""

    def __init__(self, omega_rad_s, damping_ratio, kinds, table: ShapeTable):
        self.omega_rad_s = np.asarray(omega_rad_s, dtype=float)
        self.frequencies_Hz = self.omega_rad_s / (2.0 * math.pi)
        self.damping_ratio = np.broadcast_to(np.asarray(damping_ratio, dtype=float), (self.n_modes,)).copy()
        self.kinds = tuple(kinds)
        if len(self.kinds) != self.n_modes or any(k not in MODE_KINDS for k in self.kinds):
            raise ValueError(f"kinds={kinds!r}: expected one of {MODE_KINDS} per mode ({self.n_modes})")
        self.table = table

    @property
    def n_modes(self) -> int:
        return self.omega_rad_s.shape[0]

    def __repr__(self):
        f = ", ".join(f"{x:.3g}" for x in self.frequencies_Hz[:8])
        return f"{type(self).__name__}({self.n_modes} modes: {f}{', ...' if self.n_modes > 8 else ''} Hz)"

    # modal matrices
    def modal_mass(self) -> np.ndarray:
        return np.eye(self.n_modes)

    def modal_stiffness(self) -> np.ndarray:
        return np.diag(self.omega_rad_s ** 2)

    def modal_damping(self) -> np.ndarray:
        return np.diag(2.0 * self.damping_ratio * self.omega_rad_s)

    def participation_factors(self, direction: str = "lateral") -> np.ndarray:
        """``Γ_n = φ_nᵀ M r`` of a rigid translation of the deck with its supports (support motion): needs the
        deck's mass distribution, which only a finite-element model has (:class:`~.bridge.BridgeModes`)."""
        raise ValueError(f"{type(self).__name__}: no mass distribution, so no participation factors (a support "
                         "motion needs the built-in deck model)")

    def of_kind(self, kind: str) -> np.ndarray:
        """Indices of the modes of one kind, in increasing frequency."""
        if kind not in MODE_KINDS:
            raise ValueError(f"kind={kind!r}: expected one of {sorted(MODE_KINDS)}")
        idx = np.array([i for i, k in enumerate(self.kinds) if k == kind], dtype=np.int64)
        return idx[np.argsort(self.omega_rad_s[idx], kind="stable")]

    # vectorised wrappers of the compiled functions
    def shape_at(self, s_m) -> np.ndarray:
        """``Φ(s)``: (..., 3, n_modes), rows y_rail, z_rail, θ_rail, at track distance(s) s (zero off the deck)."""
        s = np.asarray(s_m, dtype=float)
        out = np.empty((s.size, 3, self.n_modes))
        modal_shapes_many(np.ascontiguousarray(s.ravel()), *self.table, out, out, False)
        return out.reshape(s.shape + (3, self.n_modes))

    def shape_and_slope_at(self, s_m) -> tuple[np.ndarray, np.ndarray]:
        """``Φ(s)`` and ``dΦ/ds`` (each (..., 3, n_modes))."""
        s = np.asarray(s_m, dtype=float)
        out = np.empty((s.size, 3, self.n_modes))
        out_ds = np.empty((s.size, 3, self.n_modes))
        modal_shapes_many(np.ascontiguousarray(s.ravel()), *self.table, out, out_ds, True)
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
