"""The bridge crossing's deck: its section (:func:`deck_section`), the bending modes of every span computed alone
(:func:`deck_modes`, :func:`vertical_modes`) and the EN 1990 cut-off frequency of a span (:func:`en1990_cutoff_Hz`)."""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..structures.beam import N_DOF_NODE, DeckSection
from ..structures.bridge import BridgeModel, BridgeModes
from .bridge_crossing_case import ELEMENTS_PER_MODE, MIN_ELEMENTS, BridgeCrossing
from .deck import en1990_cutoff_Hz as span_cutoff_Hz

__all__ = ["deck_section", "elements_per_span", "DeckModes", "deck_modes", "vertical_modes", "en1990_cutoff_Hz"]


def deck_section(case: BridgeCrossing):
    """The :class:`~exudyn_wheelrail.structures.beam.DeckSection` of every span: ``m``, ``EI_y`` from ``f1`` of
    the first span, ``EI_z`` (:attr:`BridgeCrossing.EI_z_Nm2`: from the lateral frequency, else
    :data:`LATERAL_EI_RATIO` ``EI_y``), the torsional and axial values placeholders
    (:meth:`~exudyn_wheelrail.structures.beam.DeckSection.bending_only`; rail height 0)."""
    return DeckSection.bending_only(case.mass_kg_m, case.EI_Nm2, case.EI_z_Nm2)


def elements_per_span(case: BridgeCrossing) -> int:
    """Beam elements of every span: ``max(MIN_ELEMENTS, ELEMENTS_PER_MODE N)``, N the larger of the vertical and
    lateral mode counts."""
    return max(MIN_ELEMENTS, ELEMENTS_PER_MODE * max(case.n_modes, case.lateral_modes))


def _span_modes(case: BridgeCrossing, k: int):
    """Span ``k`` alone (a simply supported :class:`~exudyn_wheelrail.structures.bridge.BridgeModel`): its
    ``N`` lowest vertical and ``N_L`` lowest lateral bending modes — ``(model, omega (N + N_L,), shapes)``, the
    vertical first.  A lateral mode keeps its lateral DOFs (v, θz) only: the section decouples them exactly from
    the others, so this removes the eigen-solver's rounding and vertical loads leave it exactly at rest."""
    n, n_l = case.n_modes, case.lateral_modes
    model = BridgeModel((case.chain_m[k],), deck_section(case), continuous=False, damping_ratio=case.damping_ratio,
                        rail_height_m=0.0, start_m=case.span_start_m(k), elements_per_span=elements_per_span(case))
    f_top = n ** 2 * case.span_f1_Hz(k)
    if n_l:
        f_top = max(f_top, n_l ** 2 * case.span_lateral_f1_Hz(k))
    every = model.modes(f_max_Hz=1.05 * f_top)
    idx = every.of_kind("vertical")[:n]
    if idx.size < n:
        raise RuntimeError(f"the deck model has {idx.size} vertical modes below {1.05 * f_top:g} Hz, expected {n}")
    omega, shapes = every.omega_rad_s[idx], every.shapes[:, idx]
    if n_l:
        lat = every.of_kind("lateral")[:n_l]
        if lat.size < n_l:
            raise RuntimeError(f"the deck model has {lat.size} lateral modes below {1.05 * f_top:g} Hz, expected "
                               f"{n_l}")
        keep = np.zeros(model.n_dof, dtype=bool)
        keep[1::N_DOF_NODE] = keep[5::N_DOF_NODE] = True
        omega = np.concatenate([omega, every.omega_rad_s[lat]])
        shapes = np.concatenate([shapes, np.where(keep[:, None], every.shapes[:, lat], 0.0)], axis=1)
    return model, omega, shapes


@dataclass(frozen=True)
class DeckModes:
    """The modes of the deck (:func:`deck_modes`): ``modes`` (:class:`~exudyn_wheelrail.structures.bridge.
    BridgeModes` of the whole chain), ``vertical`` and ``lateral`` (per span, the indices of its modes in
    ``modes``)."""

    modes: object
    vertical: tuple
    lateral: tuple


def deck_modes(case: BridgeCrossing) -> DeckModes:
    """Every span's ``N`` vertical and ``N_L`` lateral bending modes, each span computed alone (the spans are
    independent simply supported decks: the modes of equal spans stay separate, never mixed as the eigenvectors
    of a repeated eigenvalue would be), as modes of the chain (:class:`~exudyn_wheelrail.structures.bridge.
    BridgeModel` with ``continuous=False``: doubled nodes at the joints); span after span, vertical first."""
    n, n_l = case.n_modes, case.lateral_modes
    parts = [_span_modes(case, k) for k in range(case.n_spans)]
    if case.n_spans == 1:
        model, omega, shapes = parts[0]
    else:
        model = BridgeModel(case.chain_m, deck_section(case), continuous=False, damping_ratio=case.damping_ratio,
                            rail_height_m=0.0, start_m=case.deck_start_m, elements_per_span=elements_per_span(case))
        per_span = N_DOF_NODE * (elements_per_span(case) + 1)           # the nodes of a span, its own at joints
        shapes = np.zeros((model.n_dof, case.n_spans * (n + n_l)))
        for k, (_, _, sk) in enumerate(parts):
            shapes[k * per_span:(k + 1) * per_span, k * (n + n_l):(k + 1) * (n + n_l)] = sk
        omega = np.concatenate([p[1] for p in parts])
    first = [k * (n + n_l) for k in range(case.n_spans)]
    return DeckModes(BridgeModes(model, omega, shapes),
                     vertical=tuple(np.arange(i, i + n) for i in first),
                     lateral=tuple(np.arange(i + n, i + n + n_l) for i in first))


def vertical_modes(case: BridgeCrossing):
    """The N lowest vertical bending modes of the (first) span (:class:`~exudyn_wheelrail.structures.bridge.
    BridgeModes`)."""
    model, omega, shapes = _span_modes(replace(case, spans_m=None, lateral_modes=0), 0)
    return BridgeModes(model, omega, shapes)


def en1990_cutoff_Hz(case: BridgeCrossing, span: int = 0) -> float:
    """EN 1990 A2.4.4.2.1(4)P: modes up to max(30 Hz, 1.5 f1, f3) (``f3 = 9 f1``) of span ``span`` (0-based)."""
    sec = deck_section(case)
    return span_cutoff_Hz((case.chain_m[span],), sec)

