r"""The run's per-state work inside the compiled force call: the run monitor's checks, the flange-climb window and
the recorder's contact columns of every accepted state of an explicit run, with no Python per step.

Why
---
The runner's pre-step function (:mod:`.runner`) checks every accepted state from Python: it reads the coordinates
from Exudyn, evaluates the contact (kept for the step's first stage), calls the monitor's compiled check, the
flange-climb window and the recorder's probes.  Each piece is compiled, but the Python around them costs about as
much as a contact evaluation per step.  On the connector's compiled call path (:mod:`~..multibody.direct_call`)
an explicit Runge–Kutta step's first stage evaluates the contact at exactly that accepted state: the **watch**
does the same checks there, in the compiled call, on that evaluation.

Which call holds the accepted state
-----------------------------------
An explicit step from ``t_k`` calls the forces at its stages' times ``t_k + c_i h`` (RK44: ``c = 0, ½, ½, 1``);
its first stage is at the accepted state ``(t_k, q_k, q̇_k)``, and a stage with ``c = 1`` of the step before is at
the same time ``t_k`` but at a predicted state.  So the accepted state is the **last call at a time of the step
grid** ``t_0 + k h`` before a call at a later time: every call at a grid time keeps its coordinates and velocities
(``pend_q``, ``pend_v``), and the next call at a later time checks that state first, while the connector's arrays
still hold its evaluation.  Exudyn's explicit solvers call nothing else between (fixed step, no rejected step).

What is done there, in the order of the pre-step function (:meth:`~.runner._Hook.state`): the monitor's compiled
check (:func:`~.monitor_core.monitor_state`, with the wheelset poses and the history row), the flange-climb window
(:func:`~.guidance.window_quotient`) and, on the recording grid, the recorder's wheel and wheelset columns
(:func:`~.recorder.wheel_columns`, the wheelset poses) and a structure's deck columns (a watched deck probe: its
:func:`~..structures.deck_response.deck_row` from the structure's modal coordinates of the state and the modal
forces of its evaluation) written into the recorder's table. A state whose check needs
Python (the monitor's code, the window above Nadal's limit) is marked, its coordinates kept (``ev_q``, ``ev_v``);
the runner's pre-step function, called by Exudyn after that step, finds the mark and builds the events as it does
for a state it checks itself (:meth:`Watch.handle`) — the monitor's and the window's arrays still hold that state's
values, because the next state is checked only in the next step. A stop found there is taken as on the pre-step path
(the stopping state's row is dropped and the flange-climb maxima are those before it, as when the pre-step function
stops before the window and the recorder), but one step later: Exudyn completes the step it was about to take, so
the solve ends two steps after the stopping state instead of one. The first state (Exudyn's first pre-step call) and
the final state (after the solve) are checked by the pre-step function.

The numbers are those of the pre-step path bit for bit: the same compiled checks on the same evaluation
(``tests/test_watch.py``).  The watch needs the compiled call path, an explicit solver, and a run whose per-state
work is all compiled: no wall-clock limit, no caller's per-state user function, probes that are compiled or filled
after the run; otherwise the runner's pre-step function does the work (:func:`unwatchable`).  A structure under the
rails is no obstacle: its modal coordinates are the connector's last coordinates, and every array the checks read of
it (the shapes under the wheelsets, the modal forces) is written by the evaluation of the state being checked (a
bridge crossing of the full interaction, deck columns included: ``tests/test_watch.py``).
"""
from __future__ import annotations

import math

import numpy as np
from numba import types
from numba.experimental import structref

from ..jit import compiled
from ..multibody.direct_call import forces_step
from ..multibody.core_data import compiled_for
from ..structures.deck_response import deck_row, empty_deck_row_arrays
from .guidance import window_quotient
from .monitor_core import monitor_state, rail_poses
from .recorder import wheel_columns

__all__ = ["Watch", "unwatchable", "GRID_TOLERANCE"]

#: a time within this fraction of a step from a point of the step grid is on it (as the pre-step function's grid)
GRID_TOLERANCE = 1e-6

# ---- the watch's state: state[W_*] ---------------------------------------------------------------------------------
W_T0 = 0              # the grid's start time [s]
W_DT = 1              # the step [s]
W_PENDING = 2         # 1: pend_q, pend_v hold the latest call at a grid time
W_PENDING_T = 3       # its time [s]
W_DONE_T = 4          # the time of the last checked state (here or by the pre-step function) [s]
W_STOPPED = 5         # 1: the run stops, no further state is checked
W_EVENT = 6           # 1: the state at W_EVENT_T needs Python
W_EVENT_T = 7
W_EVENT_CODE = 8      # the monitor's code of that state
W_GUIDE = 9           # the wheel whose 2 m quotient exceeded Nadal's limit there (-1: none)
W_HIST_N = 10         # rows of the monitor's history
W_CHECKS = 11         # states checked here
W_ROWS = 12           # rows of the recorder's table
W_EVERY = 13          # record every this many steps (0: no recording)
W_GUIDE_ON = 14       # 1: the flange-climb window is active
W_WINDOW_S = 15       # its length [s]
W_NADAL = 16          # Nadal's limit
W_COL_WHEELS = 17     # the first column of the wheel columns in the recorder's table (-1: none)
W_COL_LATERAL = 18    # the first column of the wheelset columns (-1: none)
W_MISSED = 19         # states not checked because an earlier one still waited for Python (always 0 if sound)
W_COL_DECK = 20       # the first of the deck's columns in the recorder's table (-1: none)
W_MODAL = 21          # the first modal coordinate of the structure in the connector's coordinates (and forces)
N_W = 22

_FIELDS = ["call", "state", "pend_q", "pend_v", "ev_q", "ev_v", "res", "out", "side_poses", "half_gauge", "poses",
           "par", "ws_par", "ext", "iv", "wq", "wflag", "wss", "rings", "G", "work", "phi_ws", "hist", "g_idx", "ring_t",
           "ring_y", "ring_q", "sums", "max_quotient", "first", "mq_saved", "rows", "deck", "deck_state"]


@structref.register
class WatchCallType(types.StructRef):
    """Numba type of :class:`WatchCall`."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class WatchCall(structref.StructRefProxy):
    """What the watched step reads and writes: the connector's CallData (``call``), the watch's ``state``
    (``W_*``), the kept coordinates, and the arrays of the monitor, the flange-climb window and the recorder."""


structref.define_constructor(WatchCall, WatchCallType, _FIELDS)
structref.define_boxing(WatchCallType, WatchCall)


@compiled
def watch_call(call, state, pend_q, pend_v, ev_q, ev_v, res, out, side_poses, half_gauge, poses, par, ws_par, ext, iv,
               wq, wflag, wss, rings, G, work, phi_ws, hist, g_idx, ring_t, ring_y, ring_q, sums, max_quotient, first,
               mq_saved, rows, deck, deck_state):
    """The :class:`WatchCall` of these arrays (compiled and cached)."""
    return WatchCall(call, state, pend_q, pend_v, ev_q, ev_v, res, out, side_poses, half_gauge, poses, par, ws_par, ext,
                     iv, wq, wflag, wss, rings, G, work, phi_ws, hist, g_idx, ring_t, ring_y, ring_q, sums,
                     max_quotient, first, mq_saved, rows, deck, deck_state)


@compiled(refcount=False)
def _grid_index(st, t) -> int:
    """The grid index of time ``t``, or -1 when ``t`` is not on the grid."""
    x = (t - st[W_T0]) / st[W_DT]
    k = math.floor(x + 0.5)
    return int(k) if abs(x - k) <= GRID_TOLERANCE else -1


@compiled
def check_state(wc, t):
    """The accepted state at time ``t`` (``pend_q``, ``pend_v``; the connector's arrays hold its evaluation): the
    monitor's check, the flange-climb window, the recorder's row (module docstring)."""
    st = wc.state
    if st[W_STOPPED] != 0.0 or t <= st[W_DONE_T]:
        return
    if st[W_EVENT] != 0.0:
        st[W_MISSED] += 1.0
        return
    rail_poses(wc.side_poses, wc.half_gauge, wc.poses)
    row = int(st[W_HIST_N]) if wc.hist.shape[0] > 0 else -1
    code = monitor_state(t, wc.res, wc.out, wc.poses, wc.pend_q, wc.pend_v, wc.par, wc.ws_par, wc.ext, wc.iv, wc.wq,
                         wc.wflag, wc.wss, wc.rings, wc.G, wc.work, wc.phi_ws, wc.hist, row)
    if row >= 0:
        st[W_HIST_N] += 1.0
    st[W_CHECKS] += 1.0
    st[W_DONE_T] = t
    guide = -1
    if st[W_GUIDE_ON] != 0.0:
        wc.mq_saved[:] = wc.max_quotient
        guide = window_quotient(t, wc.res, st[W_WINDOW_S], st[W_NADAL], wc.g_idx, wc.ring_t, wc.ring_y, wc.ring_q,
                                wc.sums, wc.max_quotient, wc.first)
    if code != 0 or guide >= 0:
        st[W_EVENT] = 1.0
        st[W_EVENT_T] = t
        st[W_EVENT_CODE] = code
        st[W_GUIDE] = guide
        wc.ev_q[:] = wc.pend_q
        wc.ev_v[:] = wc.pend_v
    every = int(st[W_EVERY])
    if every > 0:
        k = _grid_index(st, t)
        if k >= 0 and k % every == 0:
            r = int(st[W_ROWS])
            row_out = wc.rows[r]
            row_out[0] = t
            c = int(st[W_COL_WHEELS])
            n_w = wc.res.shape[0]
            if c >= 0:
                wheel_columns(wc.res, row_out[c:c + 5 * n_w])
            c = int(st[W_COL_LATERAL])
            if c >= 0:
                for j in range(n_w // 2):
                    row_out[c + j] = wc.poses[j, 0]         # the right wheel's c_y plus the half gauge
            c = int(st[W_COL_DECK])
            if c >= 0:
                _deck_columns(wc, int(st[W_MODAL]), row_out[c:])
            st[W_ROWS] += 1.0


@compiled
def _deck_columns(wc, m0, out):
    """The deck's columns (:func:`~..structures.deck_response.deck_row`) from the structure's modal coordinates and
    rates of the accepted state and the connector's modal forces of its evaluation (``call.f``), each copied into
    its own vector as the pre-step path reads them."""
    q, q_t, Q = wc.deck_state[0], wc.deck_state[1], wc.deck_state[2]
    q[:] = wc.pend_q[m0:]
    q_t[:] = wc.pend_v[m0:]
    Q[:] = wc.call.f[m0:]
    dk = wc.deck
    deck_row(q, q_t, Q, dk[0], dk[1], dk[2], dk[3], dk[4], dk[5], dk[6], dk[7], dk[8], dk[9], dk[10],
             wc.deck_state[3], out)


@compiled
def watched_step(q, q_t, t, wc) -> int:
    """The force call with the watch (module docstring): first the accepted state kept by the previous call, then
    this call kept if it is at a grid time, then :func:`~..multibody.direct_call.forces_step`."""
    st = wc.state
    if st[W_PENDING] != 0.0 and t > st[W_PENDING_T]:
        st[W_PENDING] = 0.0
        check_state(wc, st[W_PENDING_T])
    if _grid_index(st, t) >= 0:
        wc.pend_q[:] = q
        wc.pend_v[:] = q_t
        st[W_PENDING_T] = t
        st[W_PENDING] = 1.0
    return forces_step(q, q_t, t, wc.call)


def unwatchable(*, contact, monitor, solver_explicit: bool, recorder=None, user_function=None) -> str | None:
    """Why a run cannot be watched in the compiled call (module docstring), or None when it can."""
    if contact is None or monitor is None:
        return "no run monitor"
    if not solver_explicit:
        return "an implicit solver (the accepted state is known only after Newton)"
    if user_function is not None:
        return "a per-state user function"
    why = monitor.unwatchable()
    if why is not None:
        return why
    if recorder is not None and recorder.watched_columns(contact) is None:
        return "a probe filled from Python at every state"
    direct, _ = contact.compiled_step
    if direct is None or contact.call_path != "compiled":
        return "the Python call path"
    return None


class Watch:
    """The watch of one run (module docstring): built before the solve for ``n_steps`` steps of ``dt_s`` from
    ``t0_s``, bound into the connector's compiled call by :meth:`start`; :meth:`handle` (the pre-step function,
    when :attr:`pending`), :meth:`finish` after the solve (a state still waiting, the counters, the plain call
    back)."""

    def __init__(self, contact, monitor, guidance, recorder, *, dt_s: float, t0_s: float, n_steps: int,
                 record_every: int = 1):
        self.contact, self.monitor, self.guidance, self.recorder = contact, monitor, guidance, recorder
        n = contact.n_coordinates
        st = np.zeros(N_W)
        st[W_T0], st[W_DT] = float(t0_s), float(dt_s)
        st[W_STOPPED] = 1.0                 # until the pre-step function has checked the first state
        st[W_GUIDE] = -1.0
        st[W_COL_WHEELS] = st[W_COL_LATERAL] = -1.0
        self.st = st
        self._pend_q, self._pend_v, self.ev_q, self.ev_v = (np.zeros(n) for _ in range(4))
        states = int(n_steps) + 2
        monitor.reserve_history(states)
        rows = np.zeros((0, 1))
        st[W_COL_DECK] = -1.0
        st[W_MODAL] = n - contact.n_modes                 # the structure's modal coordinates come last
        deck = None
        if recorder is not None:
            rows, c_wheels, c_lateral, c_deck, deck = recorder.watched_columns(
                contact, reserve=states // max(1, int(record_every)) + 2)
            st[W_EVERY] = int(record_every)
            st[W_COL_WHEELS], st[W_COL_LATERAL], st[W_COL_DECK] = c_wheels, c_lateral, c_deck
        if deck is None:
            deck = empty_deck_row_arrays()
        elif deck.w2.shape[0] != contact.n_modes:
            raise ValueError(f"the deck probe has {deck.w2.shape[0]} modes, the contact's structure "
                             f"{contact.n_modes}: not the same structure")
        deck_state = np.zeros((4, n - int(st[W_MODAL])))       # q, q_t, Q of the state; q_tt (deck_row)
        g = guidance.watch_arrays(dt_s) if guidance is not None else None
        if g is None:
            n_w = 2 * len(contact.nodes_exu)
            g = (np.zeros(3, dtype=np.int64), np.zeros(1), np.zeros((1, n_w)), np.zeros((1, n_w)), np.zeros((2, n_w)),
                 np.zeros(n_w), np.zeros(1 + n_w // 2))
        else:
            st[W_GUIDE_ON] = 1.0
            st[W_WINDOW_S], st[W_NADAL] = guidance.window_s, guidance.nadal_limit
        self._mq_saved = np.zeros_like(g[5])
        _, call = contact.compiled_step
        out, side_poses, half_gauge, poses, records, hist = monitor.watch_arrays()
        self._args = (call, st, self._pend_q, self._pend_v, self.ev_q, self.ev_v, contact.results, out, side_poses,
                      half_gauge, poses, *records, hist, *g, self._mq_saved, rows, tuple(deck), deck_state)
        self.call = watch_call(*self._args)
        self.bound = False
        self._checks0 = None                # the monitor's checks before the watch took over

    def start(self) -> bool:
        """Bind the watched step into the connector's compiled call; whether it is bound."""
        direct, _ = self.contact.compiled_step
        entry = compiled_for(watched_step, self._pend_q, self._pend_q, 0.0, self.call)
        self.bound = direct is not None and direct.bind_step(entry, watched_step, self.call)
        return self.bound

    def first_state_done(self, t_s: float, go: bool = True) -> None:
        """The pre-step function checked (and recorded) the state at ``t_s`` (the first; ``go`` False: it stopped the
        run): continue after it."""
        st = self.st
        st[W_DONE_T] = float(t_s)
        st[W_ROWS] = self.recorder.n if self.recorder is not None else 0
        st[W_HIST_N] = self.monitor.history_rows
        self._checks0 = self.monitor.n_checks
        st[W_STOPPED] = 0.0 if go and self.monitor.status is None else 1.0

    @property
    def pending(self) -> bool:
        """A checked state waits for Python (:meth:`handle`)."""
        return self.st[W_EVENT] != 0.0

    @property
    def t_checked(self) -> float:
        """The time of the last checked state [s]."""
        return float(self.st[W_DONE_T])

    @property
    def checks(self) -> int:
        """States checked in the compiled call."""
        return int(self.st[W_CHECKS])

    def _sync(self) -> None:
        st = self.st
        if self._checks0 is None:
            return
        self.monitor.take_watched(self._checks0 + int(st[W_CHECKS]), float(st[W_DONE_T]), int(st[W_HIST_N]))
        if self.recorder is not None:
            self.recorder.take_watched(int(st[W_ROWS]))

    def handle(self):
        """The events of the state waiting for Python, as the pre-step function builds them; returns the stopping
        :class:`~.monitor_records.Status`, or None (the run goes on)."""
        st = self.st
        self._sync()
        t = float(st[W_EVENT_T])
        code, wheel = int(st[W_EVENT_CODE]), int(st[W_GUIDE])
        m = self.monitor
        stop = m.events_of_state(t, self.ev_q, self.ev_v) if code else m.status
        if stop is None and wheel >= 0:
            stop = m.annotate(self.guidance.status_of(wheel, t))
            m.events.append(stop)
        elif stop is not None and st[W_GUIDE_ON] != 0.0:
            self.guidance.max_quotient[:] = self._mq_saved          # the window had not seen the stopping state
        st[W_EVENT] = 0.0
        if stop is not None:
            st[W_STOPPED] = 1.0
            if self.recorder is not None and self.recorder.n and self.recorder.last_time_s == t:
                self.recorder.take_watched(self.recorder.n - 1)     # the stopping state is not recorded
                st[W_ROWS] = self.recorder.n
        return stop

    def finish(self):
        """After the solve: the state still waiting (if any), the counters, the plain compiled call back; returns
        what :meth:`handle` returned (None without a waiting state)."""
        stop = None
        if self.bound:
            direct, _ = self.contact.compiled_step
            direct.bind_plain()
            self.bound = False
        if self.pending:
            stop = self.handle()
        self._sync()
        if self.st[W_MISSED]:
            raise RuntimeError(f"the run's watch left {int(self.st[W_MISSED])} state(s) unchecked: a force call came "
                               "between a checked state and the pre-step function that handles it")
        return stop
