"""The bridge crossing's recorded columns (:func:`deck_columns`, in the order of
:func:`~exudyn_wheelrail.structures.deck_response.deck_row`) and the recorder probes that fill them: the first axle's
place and the quasi-static deflection (:class:`FirstAxleProbe`), the deck's modal response (:class:`DeckProbe`)."""
from __future__ import annotations

import numpy as np

from ..structures.beam import N_DOF_NODE
from ..structures.deck_response import DeckRowArrays, deck_row
from ..structures.load_models import AxleTrain, quasi_static_midspan_deflection_m
from .bridge_crossing_deck import elements_per_span
from .deck import CHECK_POINTS_X_OVER_L

__all__ = ["DECK_COLUMNS", "LATERAL_COLUMNS", "SPAN_COLUMNS", "SPAN_LATERAL_COLUMNS", "deck_columns",
           "FirstAxleProbe", "DeckProbe"]

#: the recorded columns after ``time_s`` and ``x_first_axle_m`` (module docstring)
DECK_COLUMNS = (("deck_midspan_displacement_m", "deck_midspan_velocity_m_s", "deck_midspan_acceleration_m_s2",
                 "deck_support_rotation_start_rad", "deck_support_rotation_end_rad")
                + tuple(f"deck_acceleration_p{k + 1}_m_s2" for k in range(len(CHECK_POINTS_X_OVER_L)))
                + ("deck_en1990_max_abs_acceleration_m_s2",))
#: the first span's lateral columns, recorded with lateral modes (module docstring)
LATERAL_COLUMNS = ("deck_lateral_midspan_displacement_m", "deck_lateral_midspan_acceleration_m_s2")
#: the columns of every span of a chain (``{k}`` = 1, 2, ...; the lateral ones with lateral modes)
SPAN_COLUMNS = ("deck_span{k}_midspan_displacement_m", "deck_span{k}_midspan_acceleration_m_s2",
                "deck_span{k}_en1990_max_abs_acceleration_m_s2")
SPAN_LATERAL_COLUMNS = ("deck_span{k}_lateral_midspan_displacement_m",
                        "deck_span{k}_lateral_midspan_acceleration_m_s2")


def deck_columns(case) -> tuple:
    """The deck's recorded columns of ``case`` after ``time_s`` and the axle columns: :data:`DECK_COLUMNS` (the
    first span), :data:`LATERAL_COLUMNS` with lateral modes, and per span of a chain :data:`SPAN_COLUMNS` (and
    :data:`SPAN_LATERAL_COLUMNS`)."""
    cols = DECK_COLUMNS + (LATERAL_COLUMNS if case.lateral_modes else ())
    if case.n_spans > 1:
        per = SPAN_COLUMNS + (SPAN_LATERAL_COLUMNS if case.lateral_modes else ())
        cols += tuple(c.format(k=k + 1) for k in range(case.n_spans) for c in per)
    return cols


class FirstAxleProbe:
    """``x_first_axle_m``: deck coordinate of the first axle, ``V t``; ``deck_midspan_static_displacement_m``: the
    quasi-static deflection at the first span's middle under the static axle loads at their places (functions of the
    time) — a simply supported span's influence line (:func:`~exudyn_wheelrail.structures.load_models.
    quasi_static_midspan_deflection_m`), or, for a deck whose modes span it whole (continuous, a modes file),
    the static response of the modes kept, ``w(x_m) = Σ_j φ_j(x_m) Σ_k P_k φ_j(s_k) / ω_j²`` (the same basis as the
    dynamic response: their ratio is the dynamic enhancement of that model)."""

    def __init__(self, case, axle_x_m, axle_load_N, deck=None):
        self.V = float(case.speed_m_s)
        self.axles = AxleTrain(np.asarray(axle_x_m, dtype=float), np.asarray(axle_load_N, dtype=float),
                               name="static axle loads")
        self.L, self.EI = case.span_m, case.EI_Nm2
        self.x0 = case.deck_start_m
        self.modal = None
        if case.global_modes:
            modes = deck.modes
            self.modes = modes
            self.modal = modes.shape_at(self.x0 + 0.5 * self.L)[1] / modes.omega_rad_s ** 2
        self.columns = [("axle", "x_first_axle_m"), ("axle", "deck_midspan_static_displacement_m")]

    def fill_rows(self, t, rows):
        rows[:, 0] = self.V * t
        if self.modal is None:
            rows[:, 1] = quasi_static_midspan_deflection_m(t, self.axles, speed_m_s=self.V, span_m=self.L,
                                                           EI_Nm2=self.EI)
            return
        q = np.zeros((np.size(t), self.modes.n_modes))
        for x, p in zip(self.axles.x_m, self.axles.load_N):       # Σ_k P_k φ(s_k): one axle at a time (memory)
            q += p * self.modes.shape_at(self.x0 + self.V * np.asarray(t) - x)[:, 1, :]
        rows[:, 1] = q @ self.modal


class DeckProbe:
    """The deck's columns (:func:`deck_columns`) from the modal state and the modal accelerations: every column of the
    row in one compiled call (:func:`~exudyn_wheelrail.structures.deck_response.deck_row`).  The modal state is read
    from Exudyn, the modal forces from the load model (``modal_forces(mbs, t)``) — or, when they are those of the
    wheel–rail ``contact`` (``modal_forces=None``: the full interaction), the probe is **watched**: the run's
    watch fills its columns in the compiled force call from the connector's coordinates and forces
    (:mod:`~exudyn_wheelrail.simulation.watch`), the same arithmetic on the same numbers."""

    def __init__(self, case, bridge, deck, modal_forces, cutoffs_Hz, contact=None):
        modes = deck.modes
        cutoff_Hz = cutoffs_Hz[0]
        self.bridge = bridge
        self.c = contact if modal_forces is None else None
        if modal_forces is None and getattr(contact, "structure", None) is not bridge:
            raise ValueError("DeckProbe: modal_forces=None needs the contact whose structure is this bridge")
        self.modal_forces = modal_forces if modal_forces is not None else (lambda mbs, t: contact.modal_forces_N())
        self.watched = "deck" if self.c is not None else None
        L, x0 = case.span_m, case.deck_start_m
        phi, dphi = modes.shape_and_slope_at(np.array([x0 + 0.5 * L, x0, x0 + L]))
        slopes = dphi[1:, 1].copy()                                   # (2, n): dw/dx at the supports
        if case.n_spans > 1 and not case.global_modes:  # x0 + L also starts span 2: span 1's end node, dw/dx = -θy
            slopes[1] = -modes.shapes[N_DOF_NODE * elements_per_span(case) + 4]
        elif case.n_spans > 1:       # the slope at x0 + L from the left: the first span's end (a joint's other side
            slopes[1] = modes.shape_and_slope_at(np.nextafter(x0 + L, -np.inf))[1][1]   # starts the next deck)
        s_pts = x0 + L * np.asarray(CHECK_POINTS_X_OVER_L)
        phi_pts = np.ascontiguousarray(modes.shape_at(s_pts)[:, 1, :])
        keep = modes.frequencies_Hz <= 1.01 * cutoff_Hz          # FE frequencies lie slightly above the exact ones
        phi_pts_cut = np.ascontiguousarray(np.where(keep[None, :], phi_pts, 0.0))
        self.columns = [("deck", c) for c in deck_columns(case)]
        lateral = bool(case.lateral_modes)
        # the lateral columns: the lateral modes' y rows (a vertical mode's lateral DOFs are the eigen-solver's
        # rounding, about 1e-13 of its vertical ones)
        lat = np.zeros(modes.n_modes, dtype=bool)
        for idx in deck.lateral:
            lat[idx] = True
        n = modes.n_modes
        k_sp = case.n_spans if case.n_spans > 1 else 0
        span_mid = np.zeros((k_sp, n))
        span_cut = np.zeros((k_sp, len(CHECK_POINTS_X_OVER_L), n))
        span_lat = np.zeros((k_sp, n))
        for k in range(k_sp):
            xk, Lk = case.span_start_m(k), case.chain_m[k]
            mid = modes.shape_at(xk + 0.5 * Lk)
            mine = np.zeros(n, dtype=bool)
            mine[deck.vertical[k]] = True
            keep = mine & (modes.frequencies_Hz <= 1.01 * cutoffs_Hz[k])
            pts = modes.shape_at(xk + Lk * np.asarray(CHECK_POINTS_X_OVER_L))[:, 1, :]
            span_mid[k] = mid[1]
            span_cut[k] = np.where(keep[None, :], pts, 0.0)
            span_lat[k] = np.where(lat, mid[0], 0.0)
        self.rows = DeckRowArrays(
            w2=np.diag(modes.modal_stiffness()).copy(), d=np.diag(modes.modal_damping()).copy(),
            phi_mid=phi[0, 1].copy(), slopes=slopes, phi_pts=phi_pts,
            phi_pts_cut=phi_pts_cut,
            phi_lat_mid=(np.where(lat, modes.shape_at(x0 + 0.5 * L)[0], 0.0) if lateral else np.zeros(n)),
            lateral=lateral, span_mid=span_mid, span_cut=span_cut, span_lat=span_lat)
        self._q_tt = np.zeros(n)                        # the modal accelerations of the row being filled

    def fill(self, mbs, t, out):
        q, q_t = (np.atleast_1d(v) for v in self.bridge.coordinates(mbs))      # a scalar for one mode
        deck_row(q, q_t, np.atleast_1d(self.modal_forces(mbs, t)), *self.rows, self._q_tt, out)
