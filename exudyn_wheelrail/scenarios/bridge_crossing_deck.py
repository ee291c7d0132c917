"""The bridge crossing's deck: its section (:func:`deck_section`), its modes (:func:`deck_modes`: a chain's span by
span, a continuous deck's, a modes file's; :func:`vertical_modes`) and the EN 1990 cut-off frequency of a simply
supported span (:func:`en1990_cutoff_Hz`)."""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..structures.beam import N_DOF_NODE, DeckSection
from ..structures.bridge import BridgeModel, BridgeModes
from ..structures.modes_file import SampledModes
from .bridge_crossing_case import CLAMPED_BAND, ELEMENTS_PER_MODE, MIN_ELEMENTS, BridgeCrossing
from .deck import cutoff_of_frequencies_Hz
from .deck import en1990_cutoff_Hz as span_cutoff_Hz

__all__ = ["deck_section", "elements_per_span", "DeckModes", "deck_modes", "chain_modes", "continuous_modes",
           "file_modes", "file_reference", "file_modes_to_cutoff", "span_moves", "span_mode_sets", "span_references",
           "SPAN_SHARE", "vertical_modes", "en1990_cutoff_Hz"]


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
        omega, shapes = _with_lateral(model, every, n_l, omega, shapes, f"the deck model below {1.05 * f_top:g} Hz")
    return model, omega, shapes


def _with_lateral(model, every, n_l, omega, shapes, what):
    """``omega``, ``shapes`` followed by the ``n_l`` lowest lateral modes of ``every``, each keeping its lateral DOFs
    (v, θz) only: the section decouples them exactly from the others, so this removes the eigen-solver's rounding
    and vertical loads leave them exactly at rest."""
    lat = every.of_kind("lateral")[:n_l]
    if lat.size < n_l:
        raise RuntimeError(f"{what}: {lat.size} lateral modes, expected {n_l}")
    keep = np.zeros(model.n_dof, dtype=bool)
    keep[1::N_DOF_NODE] = keep[5::N_DOF_NODE] = True
    return (np.concatenate([omega, every.omega_rad_s[lat]]),
            np.concatenate([shapes, np.where(keep[:, None], every.shapes[:, lat], 0.0)], axis=1))


@dataclass(frozen=True)
class DeckModes:
    """The modes of the deck (:func:`deck_modes`): ``modes`` (the
    :class:`~exudyn_wheelrail.structures.modal_basis.ModalBasis` of the whole deck), ``vertical`` and ``lateral``
    (per span, the indices of its modes in ``modes``: a span's own of a chain, every mode of that kind of a deck
    whose modes span it whole), ``f1_Hz`` (per span, its first vertical frequency: the span's own of a chain, the
    deck's otherwise; the resonance speeds ``f1 d/i``), ``cutoffs_Hz`` (per span, EN 1990's
    ``max(30 Hz, 1.5 f1, f3)``) and, for a chain, ``euler_bernoulli_top_Hz`` (per span, ``N² f1_k``)."""

    modes: object
    vertical: tuple
    lateral: tuple
    f1_Hz: tuple = ()
    cutoffs_Hz: tuple = ()
    euler_bernoulli_top_Hz: tuple = ()
    cutoff_known: tuple = ()

    def reaches_cutoff(self, k: int) -> bool:
        """Whether span ``k``'s vertical modes reach its cut-off: the highest kept is at or above it (a chain's span
        also when ``N² f1_k``, the Euler–Bernoulli value its mesh approximates from above, is:
        ``euler_bernoulli_top_Hz``); never when the cut-off is not known (``cutoff_known``: a deck with fewer
        than three vertical modes has no f3)."""
        if self.cutoff_known and not self.cutoff_known[k]:
            return False
        f = self.modes.frequencies_Hz[self.vertical[k]]
        if f.size and f[-1] >= self.cutoffs_Hz[k]:
            return True
        return bool(self.euler_bernoulli_top_Hz) and self.euler_bernoulli_top_Hz[k] >= self.cutoffs_Hz[k]


def deck_modes(case: BridgeCrossing) -> DeckModes:
    """The deck's modes: a chain's span by span (:func:`chain_modes`), a continuous deck's
    (:func:`continuous_modes`), a modes file's (:func:`file_modes`)."""
    if case.modes_file is not None:
        return file_modes(case)
    if case.continuous:
        return continuous_modes(case)
    return chain_modes(case)


def chain_modes(case: BridgeCrossing) -> DeckModes:
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
                     lateral=tuple(np.arange(i + n, i + n + n_l) for i in first),
                     f1_Hz=tuple(case.span_f1_Hz(k) for k in range(case.n_spans)),
                     cutoffs_Hz=tuple(en1990_cutoff_Hz(case, k) for k in range(case.n_spans)),
                     euler_bernoulli_top_Hz=tuple(n ** 2 * case.span_f1_Hz(k) for k in range(case.n_spans)))


def continuous_modes(case: BridgeCrossing) -> DeckModes:
    """The ``N K`` lowest vertical and ``N_L K`` lowest lateral bending modes of the deck continuous over its ``K``
    spans' intermediate supports (:class:`~exudyn_wheelrail.structures.bridge.BridgeModel` with
    ``continuous=True``, the spans' common section, ``max(20, 8N)`` elements per span); a lateral mode keeps its
    lateral DOFs only (as a chain's); vertical first."""
    n, n_l, k_sp = case.n_modes, case.lateral_modes, case.n_spans
    model = BridgeModel(case.chain_m, deck_section(case), continuous=True, damping_ratio=case.damping_ratio,
                        rail_height_m=0.0, start_m=case.deck_start_m, elements_per_span=elements_per_span(case))
    # enough modes for every span's f3 too (the cut-off's reference): (3 + CLAMPED_BAND)² f1_k bounds the third
    f_ref = max(case.f_N_Hz, max((3 + CLAMPED_BAND) ** 2 * case.span_f1_Hz(k) for k in range(k_sp)))
    every = model.modes(f_max_Hz=1.05 * f_ref)
    idx = every.of_kind("vertical")[:n * k_sp]
    if idx.size < n * k_sp:
        raise RuntimeError(f"the continuous deck has {idx.size} vertical modes below {1.05 * case.f_N_Hz:g} Hz, "
                           f"expected {n * k_sp}")
    omega, shapes = every.omega_rad_s[idx], every.shapes[:, idx]
    if n_l:
        omega, shapes = _with_lateral(model, every, n_l * k_sp, omega, shapes,
                                      f"the continuous deck below {1.05 * f_ref:g} Hz")
    modes = BridgeModes(model, omega, shapes)
    reference = _reference_of(every, case)
    return _whole_deck(case, modes, np.arange(n * k_sp), np.arange(n * k_sp, n * k_sp + n_l * k_sp), reference)


def _sampled(case: BridgeCrossing, data) -> SampledModes:
    supports = np.concatenate([[0.0], np.cumsum(case.chain_m)])
    return SampledModes(data, start_m=case.deck_start_m, supports_x_m=supports, mass_scale=case.mass_scale,
                        damping_ratio=case.damping_ratio)


def file_reference(case: BridgeCrossing) -> tuple:
    """Every span's first frequency, EN 1990 cut-off and whether it is known (:func:`span_references`) from **all**
    the modes of the case's modes file — whatever number of them a crossing keeps."""
    return _reference_of(_sampled(case, case.file_modes), case)


def _reference_of(every, case) -> tuple:
    """:func:`span_references` of the vertical modes of ``every`` (a deck's fuller basis) on the case's spans."""
    moves = span_moves(every, case.chain_m, case.deck_start_m)
    return span_references(every, span_mode_sets(moves, every.of_kind("vertical")))


def file_modes_to_cutoff(case: BridgeCrossing) -> int | None:
    """How many of the modes file's lowest modes reach every span's EN 1990 cut-off (the first vertical mode of the
    span at or above it, and every mode below); None when a span's vertical modes end below it or its cut-off is
    not known."""
    every = _sampled(case, case.file_modes)
    sets = span_mode_sets(span_moves(every, case.chain_m, case.deck_start_m), every.of_kind("vertical"))
    f1s, cuts, known = span_references(every, sets)
    f = every.frequencies_Hz
    firsts = []
    for k, mine in enumerate(sets):
        above = [f[i] for i in mine if f[i] >= cuts[k]]
        if not known[k] or not above:
            return None
        firsts.append(min(above))
    return int(np.count_nonzero(f <= max(firsts)))


def file_modes(case: BridgeCrossing) -> DeckModes:
    """The ``N`` lowest modes of the case's modes file
    (:class:`~exudyn_wheelrail.structures.modes_file.SampledModes`: mass-normalised, the splines broken at the
    spans' supports, the mass scale of a mass bound; the case's damping ratio, else the file's); every span's
    first frequency and cut-off from all the file's modes (:func:`file_reference`)."""
    modes = _sampled(case, case.file_modes.lowest(case.n_modes))
    return _whole_deck(case, modes, modes.of_kind("vertical"), modes.of_kind("lateral"), file_reference(case))


#: a mode moves a span when its largest vertical displacement there is at least this fraction of its largest
SPAN_SHARE = 1e-3


def span_moves(modes, chain_m, start_m) -> list:
    """Per span (``chain_m`` from track distance ``start_m``), which modes move it (boolean, per mode): a displacement
    there at least :data:`SPAN_SHARE` of the mode's largest over the deck (every mode of a continuous deck, a span's
    own of a modes file of separate decks)."""
    length = float(sum(chain_m))
    x = start_m + np.linspace(0.0, length, 200 * len(chain_m) + 1)
    largest = np.max(np.abs(modes.shape_at(x)), axis=(0, 1))                       # (n_modes,)
    out, x0 = [], start_m
    for L in chain_m:
        xs = x0 + L * np.linspace(0.01, 0.99, 99)
        out.append(np.max(np.abs(modes.shape_at(xs)), axis=(0, 1)) >= SPAN_SHARE * largest)
        x0 += L
    return out


def span_mode_sets(moves, indices) -> list:
    """Per span, the modes of ``indices`` that move it (``moves``: :func:`span_moves`)."""
    indices = np.asarray(indices, dtype=np.int64)
    return [indices[m[indices]] for m in moves]


def span_references(modes, vertical_sets) -> tuple:
    """``(f1, cut-off, known)`` per span from its vertical modes (``vertical_sets``: :func:`span_mode_sets`): its
    first frequency and EN 1990's ``max(30 Hz, 1.5 f1, f3)`` — with fewer than three vertical modes f3 is not known
    (the highest stands for it and ``known`` is False: the cut-off is then never reached)."""
    f1s, cuts, known = [], [], []
    for k, mine in enumerate(vertical_sets):
        f = np.sort(modes.frequencies_Hz[mine])
        if f.size == 0:
            raise ValueError(f"span {k + 1} of the deck: no vertical mode moves it")
        f1s.append(float(f[0]))
        cuts.append(cutoff_of_frequencies_Hz(f[0], f[min(2, f.size - 1)]))
        known.append(bool(f.size >= 3))
    return tuple(f1s), tuple(cuts), tuple(known)


def _whole_deck(case, modes, vertical, lateral, reference) -> DeckModes:
    """A :class:`DeckModes` whose modes span the whole deck: span ``k``'s modes are those that move it
    (:func:`span_moves`); its first frequency and cut-off are ``reference``'s (:func:`span_references` of the
    deck's fuller basis: its f3 whatever number of modes is kept)."""
    moves = span_moves(modes, case.chain_m, case.deck_start_m)
    per_span, lat_span = span_mode_sets(moves, vertical), span_mode_sets(moves, lateral)
    for k, mine in enumerate(per_span):
        if mine.size == 0:
            raise ValueError(f"n_modes: none of the {modes.n_modes} modes kept moves span {k + 1} vertically")
    f1s, cuts, known = reference
    return DeckModes(modes, vertical=tuple(per_span), lateral=tuple(lat_span), f1_Hz=f1s, cutoffs_Hz=cuts,
                     cutoff_known=known)


def vertical_modes(case: BridgeCrossing):
    """The N lowest vertical bending modes of the (first) span (:class:`~exudyn_wheelrail.structures.bridge.
    BridgeModes`)."""
    model, omega, shapes = _span_modes(replace(case, spans_m=None, lateral_modes=0), 0)
    return BridgeModes(model, omega, shapes)


def en1990_cutoff_Hz(case: BridgeCrossing, span: int = 0) -> float:
    """EN 1990 A2.4.4.2.1(4)P: modes up to max(30 Hz, 1.5 f1, f3) (``f3 = 9 f1``) of span ``span`` (0-based)."""
    sec = deck_section(case)
    return span_cutoff_Hz((case.chain_m[span],), sec)

