r"""Flange climb that friction cannot stop: the derailment quotient of a wheel held above Nadal's limit over 2 m of
running.

Nadal's limit (:func:`~exudyn_wheelrail.analysis.safety.nadal_limit`) is the quotient Y/Q of the lateral force Y
(towards the wheel's field side, the flange pressing its rail outwards) and the wheel load Q at which a flange
contact on the flank (angle γ, friction μ) is in limiting friction: ``(tan γ − μ)/(1 + μ tan γ)``, 1.34 for S1002's
70° flank with μ = 0.3.  Above it nothing holds the flange down and it climbs.  A short impact above the limit is
not a derailment — the climb needs running distance —, so the quotient is taken over the running distance of EN
14363's derailment-quotient window, 2 m (:data:`~exudyn_wheelrail.analysis.safety.EN14363_WINDOW_M`): the quotient
of the sums of Y and Q over the states of the last 2 m (a lifted wheel, Q = 0, adds nothing to either), which
equals ``(Y/Q)_2m`` for a steady flange contact and stays finite while the wheel hops.  When it exceeds Nadal's
limit the wheel is reported **derailed** (flange climb) at that state, with the wheelset and wheel.  (EN 14363's own
limit on ``(Y/Q)_2m``, 0.8, is an acceptance limit with margin, evaluated on the recorded run by the criteria.)

The detail also states the wheelset's track-shift force ΣY (the lateral force of both wheels on the track) over
the same 2 m against Prud'homme's limit ``10 kN + P/3`` (P the axle load of the first checked state): with the
flange climbing, a track on ballast would also be shifted far beyond what it resists, which the model's rigid
rails do not show.
"""
from __future__ import annotations

import math

import numpy as np

from ..analysis.safety import EN14363_WINDOW_M, prudhomme_limit_N
from ..contact.layout import N_RES, N_SLOTS
from ..jit import compiled
from ..multibody.core_data import compiled_for
from .monitor_records import SIDES, Status
from .recorder import wheel_force_yz

__all__ = ["FlangeClimbCheck"]

# ---- the running window: idx[I_*] ------------------------------------------------------------------------------------
I_HEAD = 0            # ring position of the oldest state in the window
I_COUNT = 1           # states in the window
I_STARTED = 2         # 1 after the first state (axle loads and start time taken)
N_I = 3
#: ``window_quotient`` before the window spans 2 m of running
SHORT = -2
#: ``window_quotient`` with no quotient above the limit
BELOW = -1


@compiled(refcount=False)
def window_quotient(t, res, window_s, nadal, idx, ring_t, ring_y, ring_q, sums, max_quotient, first):
    """One state of the 2 m window (O(1) per state: running sums over a ring of the states in the window).

    ``res`` the connector's results of the state; ``ring_t`` (cap,), ``ring_y``, ``ring_q`` (cap, n_w) the states
    in the window (Y towards each wheel's field side, Q); ``sums`` (2, n_w) their sums; ``max_quotient`` (n_w) the
    largest quotient per wheel; ``first`` (1 + n_ws): the time and the axle loads of the first state.  The caller
    keeps ``idx[I_COUNT] < cap``.  Returns the wheel whose quotient exceeds ``nadal`` (the largest, first of equal),
    :data:`BELOW`, or :data:`SHORT` while less than the window has been run.  The sums take each state's values and
    drop the oldest in the order of arrival, as a sequence of additions and subtractions of whole states."""
    n_w = res.shape[0]
    cap = ring_t.shape[0]
    pos = (idx[I_HEAD] + idx[I_COUNT]) % cap
    ring_t[pos] = t
    for w in range(n_w):
        fy, fz, y_out = wheel_force_yz(res, w)        # y_out: towards the wheel's field side
        q = -fz
        if not (q >= 0.0 or q != q):                 # NumPy's maximum(q, 0): NaN propagates
            q = 0.0
        ring_y[pos, w] = y_out
        ring_q[pos, w] = q
    if idx[I_STARTED] == 0:
        idx[I_STARTED] = 1
        first[0] = t
        for k in range(n_w // 2):
            first[1 + k] = ring_q[pos, 2 * k] + ring_q[pos, 2 * k + 1]
    idx[I_COUNT] += 1
    for w in range(n_w):
        sums[0, w] += ring_y[pos, w]
        sums[1, w] += ring_q[pos, w]
    while idx[I_COUNT] > 0 and t - ring_t[idx[I_HEAD]] > window_s:
        h = idx[I_HEAD]
        for w in range(n_w):
            sums[0, w] -= ring_y[h, w]
            sums[1, w] -= ring_q[h, w]
        idx[I_HEAD] = (h + 1) % cap
        idx[I_COUNT] -= 1
    if t - first[0] < window_s * (1.0 - 1e-9):
        return SHORT                                  # less than 2 m run so far
    best = BELOW
    q_best = -math.inf
    for w in range(n_w):
        qw = sums[0, w] / sums[1, w] if sums[1, w] > 0.0 else 0.0
        m = max_quotient[w]
        if m == m and (qw != qw or qw > m):
            max_quotient[w] = qw
        if best < 0 or qw != qw or qw > q_best:      # argmax: the first maximum, the first NaN
            if q_best == q_best:
                best = w
                q_best = qw
    if not q_best > nadal:
        return BELOW
    return best


class FlangeClimbCheck:
    """``check(contact, t)`` after the monitor evaluated the contact at the state of time ``t``: a ``derailment``
    :class:`~.monitor_records.Status` when a wheel's 2 m quotient exceeds ``nadal_limit``, else
    None.  Inactive for a flangeless wheel (``nadal_limit`` NaN) or a standing vehicle.  The per-state work is one
    compiled call (:func:`window_quotient`)."""

    def __init__(self, n_wheelsets: int, speed_m_s: float, nadal_limit: float, window_m: float = EN14363_WINDOW_M):
        self.n = int(n_wheelsets)
        self.nadal_limit = float(nadal_limit)
        self.window_s = window_m / speed_m_s if speed_m_s > 0.0 else math.inf
        self.window_m = float(window_m)
        self.active = math.isfinite(self.nadal_limit) and math.isfinite(self.window_s)
        n_w = 2 * self.n
        self._idx = np.zeros(N_I, dtype=np.int64)
        self._ring_t = np.zeros(64)
        self._ring_y = np.zeros((64, n_w))
        self._ring_q = np.zeros((64, n_w))
        self._sums = np.zeros((2, n_w))                 # Y towards the field side, Q: sums over the window
        self._first = np.zeros(1 + self.n)              # time and axle loads of the first state
        self.max_quotient = np.zeros(n_w)  #: per wheel: the largest 2 m quotient seen
        # load (or compile) the compiled window here, not inside a timed solve: one call on copies; then its
        # specialization for exactly these argument types (no type dispatch per state; a grown ring keeps the types)
        args = (0.0, np.zeros((n_w, N_SLOTS, N_RES)), 1.0, 1.0, self._idx.copy(), self._ring_t.copy(),
                self._ring_y.copy(), self._ring_q.copy(), self._sums.copy(), self.max_quotient.copy(),
                self._first.copy())
        window_quotient(*args)
        self._window = compiled_for(window_quotient, *args)

    def _grow(self):
        """Double the ring, the window's states kept in order from position 0."""
        cap = self._ring_t.shape[0]
        order = (self._idx[I_HEAD] + np.arange(self._idx[I_COUNT])) % cap
        for name in ("_ring_t", "_ring_y", "_ring_q"):
            old = getattr(self, name)
            new = np.zeros((2 * cap,) + old.shape[1:])
            new[:len(order)] = old[order]
            setattr(self, name, new)
        self._idx[I_HEAD] = 0

    def watch_arrays(self, dt_s: float) -> tuple | None:
        """``(idx, ring_t, ring_y, ring_q, sums, max_quotient, first)`` for the compiled force call's watch
        (:mod:`.watch`), the ring grown to hold every state of a window at steps of ``dt_s``; None when inactive."""
        if not self.active:
            return None
        while self._ring_t.shape[0] < self.window_s / dt_s + 4:
            self._grow()
        return self._idx, self._ring_t, self._ring_y, self._ring_q, self._sums, self.max_quotient, self._first

    def __call__(self, contact, t: float) -> Status | None:
        if not self.active:
            return None
        if self._idx[I_COUNT] >= self._ring_t.shape[0]:
            self._grow()
        w = self._window(float(t), contact.results, self.window_s, self.nadal_limit, self._idx, self._ring_t,
                         self._ring_y, self._ring_q, self._sums, self.max_quotient, self._first)
        return self.status_of(w, t) if w >= 0 else None

    def status_of(self, w: int, t: float) -> Status:
        """The derailment of wheel ``w`` whose window quotient exceeded Nadal's limit at the state of time ``t``
        (the window's sums still those of that state)."""
        k = w // 2
        quotient = self._sums[0, w] / self._sums[1, w]
        n_states = int(self._idx[I_COUNT])
        track_shift = abs(self._sums[0, 2 * k] - self._sums[0, 2 * k + 1]) / n_states   # ΣY on the track, both wheels
        P = float(self._first[1 + k])
        shift = (f"; track-shift force ΣY over the same 2 m {track_shift / 1e3:.4g} kN = "
                 f"{track_shift / prudhomme_limit_N(static_axle_load_N=P):.3g} x Prud'homme's limit "
                 f"{prudhomme_limit_N(static_axle_load_N=P) / 1e3:.4g} kN" if P > 0.0 else "")
        return Status("derailment", float(t), k, SIDES[w % 2],
                      f"flange climb: Y/Q averaged over the last {self.window_m:g} m of running = {quotient:.4g} "
                      f"> Nadal's limit {self.nadal_limit:.4g} of the flange: friction no longer holds the flange "
                      f"down, the wheel climbs" + shift)
