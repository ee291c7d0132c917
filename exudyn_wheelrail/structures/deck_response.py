"""A deck's recorded response from its modal state: one row of quantities at a state in one compiled call
(:func:`deck_row`), the same from Python at every recorded state and inside the connector's compiled force call
(the run's watch).

The deck's modes are mass-normalised (``M = I``); with the modal stiffness ``w2 = ω²`` and damping ``d = 2ζω`` on
the diagonal and the modal forces ``Q`` of the state, the modal accelerations are ``q̈ = Q − d q̇ − w2 q``.  Every
quantity is a shape row times ``q``, ``q̇`` or ``q̈``, or the largest absolute value of several such rows.
:class:`DeckRowArrays` holds the rows, in the order the bridge crossing records them: the first span's mid-span
displacement, velocity and acceleration, its support slopes, the accelerations at its check points and their
largest magnitude with the modes up to the cut-off; with lateral modes the lateral mid-span displacement and
acceleration; for a chain of spans every span's mid-span displacement, acceleration and largest check-point
acceleration (and its lateral pair).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..jit import compiled

__all__ = ["DeckRowArrays", "deck_row", "empty_deck_row_arrays"]


class DeckRowArrays(NamedTuple):
    """The shape rows and modal constants of :func:`deck_row` (every array float64, C-contiguous; ``n`` modes)."""

    w2: np.ndarray              #: (n,) modal stiffness ω² [1/s²]
    d: np.ndarray               #: (n,) modal damping 2ζω [1/s]
    phi_mid: np.ndarray         #: (n,) vertical shape at the first span's middle
    slopes: np.ndarray          #: (2, n) its slopes dw/dx at the two supports
    phi_pts: np.ndarray         #: (p, n) vertical shapes at its check points
    phi_pts_cut: np.ndarray     #: (p, n) the same, the modes above the cut-off zeroed
    phi_lat_mid: np.ndarray     #: (n,) lateral shape at its middle (the lateral modes only)
    lateral: bool               #: the lateral pair is recorded
    span_mid: np.ndarray        #: (k, n) per span of a chain its mid-span vertical shape (k = 0: one span)
    span_cut: np.ndarray        #: (k, p, n) its check points' shapes, its own modes up to its cut-off
    span_lat: np.ndarray        #: (k, n) its mid-span lateral shape


def empty_deck_row_arrays() -> DeckRowArrays:
    """Arrays of :class:`DeckRowArrays`'s types for no deck (a compiled caller keeps one type with or without
    a deck)."""
    one, two = np.zeros(0), np.zeros((0, 0))
    return DeckRowArrays(one, one, one, two, two, two, one, False, two, np.zeros((0, 0, 0)), two)


@compiled(refcount=False)
def deck_row(q, q_t, Q, w2, d, phi_mid, slopes, phi_pts, phi_pts_cut, phi_lat_mid, lateral, span_mid, span_cut,
             span_lat, q_tt, out):
    """One row of the deck's quantities (module docstring, in :class:`DeckRowArrays`' order) into ``out`` from the
    modal state ``q``, ``q_t`` and the modal forces ``Q``; ``q_tt`` (n,) receives the modal accelerations."""
    n = q.shape[0]
    for j in range(n):
        q_tt[j] = Q[j] - d[j] * q_t[j] - w2[j] * q[j]
    out[0] = np.dot(phi_mid, q)
    out[1] = np.dot(phi_mid, q_t)
    out[2] = np.dot(phi_mid, q_tt)
    out[3] = np.dot(slopes[0], q)
    out[4] = np.dot(slopes[1], q)
    k = 5
    for i in range(phi_pts.shape[0]):
        out[k + i] = np.dot(phi_pts[i], q_tt)
    k += phi_pts.shape[0]
    out[k] = _max_abs_rows(phi_pts_cut, q_tt)
    k += 1
    if lateral:
        out[k] = np.dot(phi_lat_mid, q)
        out[k + 1] = np.dot(phi_lat_mid, q_tt)
        k += 2
    for s in range(span_mid.shape[0]):
        out[k] = np.dot(span_mid[s], q)
        out[k + 1] = np.dot(span_mid[s], q_tt)
        out[k + 2] = _max_abs_rows(span_cut[s], q_tt)
        k += 3
        if lateral:
            out[k] = np.dot(span_lat[s], q)
            out[k + 1] = np.dot(span_lat[s], q_tt)
            k += 2


@compiled(refcount=False)
def _max_abs_rows(A, x):
    """``max_i |A[i] · x|``."""
    m = 0.0
    for i in range(A.shape[0]):
        v = abs(np.dot(A[i], x))
        if v > m:
            m = v
    return m
