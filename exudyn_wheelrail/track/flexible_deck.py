r"""The flexible track over a bridge deck: the segment of :mod:`.flexible` whose sleepers over the deck rest through
the ballast on the deck beam of :class:`~exudyn_wheelrail.structures.bridge.BridgeModel` instead of the ground —
embankment, abutment and span in one model, with the change of support at the abutments.

>>> deck = BridgeModel(spans_m=(20.0,), section=..., start_m=10.0)                          # doctest: +SKIP
>>> model = TrackOnDeckModel(TrackParameters.from_file(), -10.0, 50.0, deck, ballast_height_m=1.0)  # doctest: +SKIP
>>> modes = model.modes()                 # coupled modes of track and deck       # doctest: +SKIP
>>> track = add_flexible_track(mbs, modes)                                        # doctest: +SKIP

Coupling.  A sleeper at track distance s strictly inside a span (``start_m < s < start_m + length``; sleepers on the
abutment lines rest on the ground) has its ballast between the sleeper and the deck point under it, at the
height ``ballast_height_m`` above the deck's beam axis (the top of the deck slab): the deck point moves down by
``w_d(s) ± (b/2) θx_d(s)`` under the rail seats and laterally by ``v_d(s) + e θx_d(s)`` (the bridge's rigid
section; :mod:`exudyn_wheelrail.structures.bridge`).  The ballast energy then splits as on the ground: the vertical
track beam's sleeper against ``w_d``, the roll beam's against ``θx_d`` (stiffness ``k_b b²/4``), the lateral one's
against ``v_d + e θx_d`` — but the deck ties the three beams together (torsion moves the deck top laterally), so the
reduced model is one set of coupled modes of the three beams and the deck (mass-normalised, damping projected).
The deck's own damping is stiffness-proportional, ``C_d = (2ζ/ω_1) K_d`` with the deck's ``damping_ratio`` at its
first mode ``ω_1`` (higher deck modes are damped more than with the bridge model's constant modal ratio).

The interface rows (``y_rail``, ``z_rail``, ``θ_rail``) are the rails' absolute motion (track and deck together),
read by the connector exactly as for the track on the ground; :meth:`TrackOnDeckModes.deck_displacement` gives the
deck's.  Not covered: the deck-acceleration columns and summary of a ``[structure]`` scenario (those read
:class:`~exudyn_wheelrail.structures.bridge.BridgeModes`); the rails' expansion devices and the longitudinal
interaction of rails and deck.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from ..structures.beam import hermite
from ..structures.bridge import BridgeModel
from .flexible import FlexibleTrackModel, FlexibleTrackModes
from .flexible_parameters import KINDS, TrackParameters

__all__ = ["TrackOnDeckModel", "TrackOnDeckModes"]

_DOF_V, _DOF_W, _DOF_TX, _DOF_TY, _DOF_TZ = 1, 2, 3, 4, 5


class TrackOnDeckModel(FlexibleTrackModel):
    """A flexible track segment (:class:`~.flexible.FlexibleTrackModel`) partly on the deck ``deck`` (module
    docstring); ``ballast_height_m``: the ballast's bottom above the deck's beam axis [m]."""

    def __init__(self, params: TrackParameters, start_m: float, length_m: float, deck: BridgeModel,
                 ballast_height_m: float):
        super().__init__(params, start_m, length_m)
        if not isinstance(deck, BridgeModel):
            raise TypeError(f"deck={deck!r}: expected a BridgeModel")
        if not (isinstance(ballast_height_m, (int, float)) and math.isfinite(ballast_height_m)
                and ballast_height_m >= 0.0):
            raise ValueError(f"ballast_height_m = {ballast_height_m!r}: expected a finite height >= 0 m")
        self.deck = deck
        self.ballast_height_m = float(ballast_height_m)
        x = self.sleeper_s_m - deck.start_m
        self.on_deck = (x > 1e-9) & (x < deck.length_m - 1e-9)
        self._free = deck.free_dofs()
        self._g = {row: np.array([self._deck_row(xj, row) for xj in x[self.on_deck]]).reshape(-1, len(self._free))
                   for row in ("w", "v", "tx")}

    def _deck_row(self, x_m: float, row: str) -> np.ndarray:
        """The deck's ``w``, ``v`` or ``θx`` at deck coordinate x as a row over its free DOFs (the element's own
        interpolation: Hermite for w and v, dw/dx = -θy, dv/dx = θz; linear for θx)."""
        els = self.deck._mesh["elements"]
        e = next(el for el in els if el[2] - 1e-9 <= x_m <= el[2] + el[3] + 1e-9)
        a, b, x0, Le, _ = e
        xi = min(max((x_m - x0) / Le, 0.0), 1.0)
        out = np.zeros(self.deck.n_dof)
        if row == "tx":
            out[6 * a + _DOF_TX] = 1.0 - xi
            out[6 * b + _DOF_TX] = xi
        else:
            N, _, _ = hermite(np.array([xi]), Le)
            N = N[0]
            if row == "w":
                out[[6 * a + _DOF_W, 6 * a + _DOF_TY, 6 * b + _DOF_W, 6 * b + _DOF_TY]] = N * [1.0, -1.0, 1.0, -1.0]
            else:
                out[[6 * a + _DOF_V, 6 * a + _DOF_TZ, 6 * b + _DOF_V, 6 * b + _DOF_TZ]] = N
        return out[self._free]

    def assemble_coupled(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
        """Dense ``(M, K, C, offsets)`` of the three beams and the supported deck, DOFs in the order vertical,
        roll, lateral beam (each as :meth:`assemble`), then the deck's free DOFs; ``offsets[kind]`` the first DOF
        of each block (``"deck"`` included)."""
        n = self.n_dof
        Md, Kd = self.deck.assemble(supported=True)
        nd = Md.shape[0]
        N = 3 * n + nd
        M, K, C = np.zeros((N, N)), np.zeros((N, N)), np.zeros((N, N))
        off = {k: i * n for i, k in enumerate(KINDS)}
        off["deck"] = 3 * n
        sl_d = slice(3 * n, N)
        M[sl_d, sl_d] = Md.toarray()
        K[sl_d, sl_d] = Kd.toarray()
        w1 = math.sqrt(scipy.linalg.eigh(K[sl_d, sl_d], M[sl_d, sl_d], subset_by_index=(0, 0), eigvals_only=True)[0])
        C[sl_d, sl_d] = 2.0 * self.deck.damping_ratio / w1 * K[sl_d, sl_d]
        j_deck = np.flatnonzero(self.on_deck)
        e = self.ballast_height_m
        deck_rows = {"vertical": self._g["w"], "roll": self._g["tx"], "lateral": self._g["v"] + e * self._g["tx"]}
        for kind in KINDS:
            Mk, Kk, Ck = (m.toarray() for m in self.assemble(kind))
            o = off[kind]
            sl = slice(o, o + n)
            M[sl, sl], K[sl, sl], C[sl, sl] = Mk, Kk, Ck
            kb, cb = self.params.beam(kind)[5:7]
            for i, j in enumerate(j_deck):
                s_dof = o + 2 * self.n_nodes + j
                g = deck_rows[kind][i]
                for A, c in ((K, kb), (C, cb)):
                    # the ballast of this sleeper acts on (sleeper - deck point), not on the sleeper alone
                    A[s_dof, sl_d] -= c * g
                    A[sl_d, s_dof] -= c * g
                    A[sl_d, sl_d] += c * np.outer(g, g)
        return M, K, C, off

    def modes(self, f_max_Hz: float | None = None, damping: str = "full", kinds=KINDS,
              static_correction: bool = True) -> "TrackOnDeckModes":
        """The coupled modes of track and deck up to ``f_max_Hz`` (default the parameters' ``modes_up_to_Hz``) with
        the full projected damping (``damping``, ``kinds``: as the ground model; only ``"full"`` and all beams);
        ``static_correction`` as the ground model's (the residual flexibility from the coupled stiffness)."""
        if damping != "full" or tuple(kinds) != KINDS:
            raise ValueError("the track on a deck is reduced with all beams and the full projected damping")
        f_max = self.params.modes_up_to_Hz if f_max_Hz is None else float(f_max_Hz)
        M, K, C, off = self.assemble_coupled()
        w2, phi = scipy.linalg.eigh(K, M, subset_by_value=(-np.inf, (2.0 * math.pi * f_max) ** 2))
        modes = TrackOnDeckModes(self, np.sqrt(np.maximum(w2, 0.0)), phi, phi.T @ C @ phi, off, f_max)
        modes.static_correction = bool(static_correction)
        modes._stiffness = (K, off) if static_correction else None
        return modes


class TrackOnDeckModes(FlexibleTrackModes):
    """The coupled modes of :class:`TrackOnDeckModel`: every mode spans the three beams and the deck (``slices``
    of every beam cover all modes); the interface, the Exudyn entry (:func:`~.flexible.add_flexible_track`) and the
    outputs as :class:`~.flexible.FlexibleTrackModes`, the ballast forces on the deck relative to the deck."""

    def __init__(self, model: TrackOnDeckModel, omega, phi, D, off, f_max_Hz):
        n = model.n_dof
        self.model = model
        self.f_max_Hz = float(f_max_Hz)
        self.damping = "full"
        self.omega_rad_s = omega
        self.frequencies_Hz = omega / (2.0 * math.pi)
        self.kinds = ("coupled",) * len(omega)
        self.shapes = {k: phi[off[k]:off[k] + n] for k in KINDS}
        self.deck_shapes = phi[off["deck"]:]
        self.slices = {k: slice(0, len(omega)) for k in KINDS}
        self.damping_matrix = D
        self.table = self._shape_table()

    def __repr__(self):
        m = self.model
        return (f"TrackOnDeckModes({self.n_modes} coupled modes up to {self.f_max_Hz:g} Hz; {m.length_m:g} m, "
                f"{int(m.on_deck.sum())} of {m.n_sleepers} sleepers on the deck)")

    def _static_flexibility(self, s_pts: np.ndarray) -> np.ndarray:
        """The coupled model's static flexibility at the rails, (n_points, 3, 3) at ``s_pts`` (rows y_rail, z_rail,
        θ_rail: the lateral, vertical and roll beams' rail fields, coupled through the deck)."""
        K, off = self._stiffness
        mdl = self.model
        e, xi = mdl._locate(s_pts)
        N, _, _ = hermite(xi, mdl.h_m)
        lu = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(K))
        G = np.empty((s_pts.size, 3, 3))
        for c0 in range(0, s_pts.size, 128):                 # in chunks of points: the right-hand sides are dense
            pts = np.arange(c0, min(c0 + 128, s_pts.size))
            Psi = np.zeros((K.shape[0], pts.size, 3))
            for row, kind in enumerate(("lateral", "vertical", "roll")):
                for j in range(4):
                    Psi[off[kind] + 2 * e[pts] + j, np.arange(pts.size), row] = N[pts, j]
            X = lu.solve(Psi.reshape(K.shape[0], -1)).reshape(Psi.shape)
            G[pts] = np.einsum("nia,nib->iab", Psi, X)
        return G

    def deck_displacement(self, s_m, q) -> np.ndarray:
        """Deck ``(v, w, θx)`` on its axis at track distance(s) ``s_m`` (zero off the deck) for modal coordinates q."""
        s = np.atleast_1d(np.asarray(s_m, dtype=float))
        out = np.zeros((s.size, 3))
        u = self.deck_shapes @ np.asarray(q, dtype=float)
        m = self.model
        for i, x in enumerate(s - m.deck.start_m):
            if 0.0 <= x <= m.deck.length_m:
                out[i] = [m._deck_row(x, r) @ u for r in ("v", "w", "tx")]
        return out

    def deck_shape_at(self, s_m) -> np.ndarray:
        """The deck's ``(v, w, θx)`` on its axis at track distance(s) ``s_m`` as rows over the modal coordinates,
        (k, 3, n_modes) (zero off the deck): ``deck_displacement(s, q) = deck_shape_at(s) @ q``, and the same rows
        give the deck's velocity and acceleration from ``q̇``, ``q̈``."""
        s = np.atleast_1d(np.asarray(s_m, dtype=float))
        out = np.zeros((s.size, 3, self.n_modes))
        m = self.model
        for i, x in enumerate(s - m.deck.start_m):
            if 0.0 <= x <= m.deck.length_m:
                out[i] = np.array([m._deck_row(x, r) for r in ("v", "w", "tx")]) @ self.deck_shapes
        return out

    def _deck_support_rows(self) -> dict:
        """The deck's ``w``, ``v``, ``θx`` under every on-deck sleeper as rows over the modal coordinates."""
        rows = self.__dict__.get("_deck_rows")
        if rows is None:
            rows = self._deck_rows = {r: self.model._g[r] @ self.deck_shapes for r in ("w", "v", "tx")}
        return rows

    def support_forces_N(self, q, q_t, sleepers=None) -> dict:
        """As :meth:`~.flexible.FlexibleTrackModes.support_forces_N`, the ballast of the sleepers on the deck acting
        on the sleeper's motion relative to the deck point under it."""
        out = super().support_forces_N(q, q_t, sleepers)
        m, p = self.model, self.model.params
        j = np.arange(m.n_sleepers) if sleepers is None else np.atleast_1d(np.asarray(sleepers))
        on = m.on_deck[j]
        if not on.any():
            return out
        rows = self._deck_support_rows()
        i = (np.cumsum(m.on_deck) - 1)[j[on]]                                # row of each on-deck sleeper in _g
        q, q_t = np.asarray(q, dtype=float), np.asarray(q_t, dtype=float)
        d = {r: (rows[r][i] @ q, rows[r][i] @ q_t) for r in ("w", "v", "tx")}   # the deck under the sleepers
        b, e = p.rail_centre_distance_m, m.ballast_height_m
        for side, sgn in (("left", -1.0), ("right", 1.0)):
            u, u_t = (d["w"][k] + sgn * 0.5 * b * d["tx"][k] for k in (0, 1))
            out[f"ballast_vertical_{side}_N"][on] -= (0.5 * p.ballast_k_vertical_N_m * u
                                                      + 0.5 * p.ballast_c_vertical_Ns_m * u_t)
        u, u_t = (d["v"][k] + e * d["tx"][k] for k in (0, 1))
        out["ballast_lateral_N"][on] -= p.ballast_k_lateral_N_m * u + p.ballast_c_lateral_Ns_m * u_t
        return out
