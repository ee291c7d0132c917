r"""The moving-window flexible track: a segment of a fixed number of sleeper bays that travels with the vehicle, so
that the cost per step does not grow with the length of the run.

>>> L = window_length_m(params, vehicle.wheelset_x_m())                                    # doctest: +SKIP
>>> start = window_start_m(params, s_start_m + min(vehicle.wheelset_x_m()))                # doctest: +SKIP
>>> modes = FlexibleTrackModel(params, start, L).modes()                                   # doctest: +SKIP
>>> track = add_flexible_track(mbs, modes)                                                 # doctest: +SKIP
>>> contact = add_wheel_rail_contact(mbs, ..., structure=track)                               # doctest: +SKIP
>>> window = FlexibleTrackWindow(track, contact)            # after mbs.Assemble()         # doctest: +SKIP
>>> run(mbs, settings, contact, speed_m_s=V, user_function=window)                         # doctest: +SKIP

Shift
-----
The track of :mod:`.flexible` on rigid ground is periodic with the sleeper spacing ``d``: a segment of n bays moved
by k bays has the same finite-element matrices and therefore the same modes Φ (per beam, mass-orthonormal,
``Φᵀ M Φ = I``), the same shape table and the same static correction.  When the vehicle has advanced, the window
moves forward by k whole bays and the state is carried over by the constant matrix, per beam,

    ``T_k = Φᵀ M S_k Φ``   (:func:`shift_matrix`),

with ``S_k`` the shift of the finite-element DOFs (rail node ``i + k e`` → ``i``, ``e`` elements per bay, both the
displacement and the slope; sleeper ``j + k`` → ``j``; the k new bays at the front start at rest): ``T_k q`` is
the M-orthogonal projection of the translated field on the kept modes.  The state is moved by
:func:`shifted_state`: the quasi-static field of the wheel forces F at the wheelsets, ``diag(ω⁻²) Φ(s)ᵀ F`` and
its rate ``V diag(ω⁻²) Φ'(s)ᵀ F`` (the bowl travelling with the vehicle), is taken out, the rest (the vibration)
moved by ``T_k``, and the quasi-static field of the window at its new position put back.  The kept modes'
static flexibility at a point ripples along a segment (truncation; ±0.3 % at 800 Hz, a tenth of the truncation
error): with the static correction (``FlexibleTrackModes.residual_table``, in series with the contact) the total
flexibility is the full model's everywhere and the same forces are put back; without it, the forces that keep
the rail under each wheelset where it was (the stiff contact would turn a micrometre's jump into kilonewtons).
The connector's deck parameter ``DECK_START`` (the track distance of the table's start,
:mod:`~exudyn_wheelrail.structures.deck_kinematics`) moves by ``k d``; the tables do not change.

**The window's current start is one fact**: the entry ``DECK_START`` of the deck parameters of the contact's
compiled model (what the connector reads at every call).  :attr:`FlexibleTrackWindow.start_m` reads it, only
:meth:`FlexibleTrackWindow.shift` writes it; everything that maps a track distance to the window (the rail field
:meth:`FlexibleTrackWindow.shape_at`, the sleeper of a track distance :meth:`FlexibleTrackWindow.sleeper_index`,
the scenario's flexible-track columns) goes through the window.  The modes' own ``table.start_m`` and
``model.start_m`` stay those of the window as built (its position at the start of the run): with a moving window,
``FlexibleTrackModes.shape_at`` and ``residual_at`` describe that first position, not the current one.

When (:meth:`FlexibleTrackWindow.bays_due`): at every new state (the runner's ``user_function``,
:func:`~exudyn_wheelrail.simulation.runner.run`, called after the run monitor's checks and the recording of the
state), once the centre of the wheelsets has passed ``k d / 2`` beyond the window's centre the window moves by k
bays: the centre is then ``k d / 2`` before it, every wheelset at the mirror image of its mirror wheelset's
position before the move, where the mirror-symmetric segment has the same modal flexibility (a single wheelset
meets no jump of it at all).  The window is ``⌈(2 m + span)/d⌉ + k`` bays long (:func:`window_length_m`), so that
the wheelsets always keep the margin ``m`` (:func:`window_margin_m`: five decay lengths 1/β of the vertical
support, at least two bays, the rule of :func:`.flexible_segment.segment_for_run`) to both ends, to within one step's
travel.  Only frames moving with the vehicle (``frame="moving"``, every wheelset at ``s = s_start + V t + x``)
and explicit solvers (the state is ``q, q̇``; an implicit solver's accelerations are not carried over) are
supported.

Exudyn 1.13.6 starts the next explicit (RK44) step from the coordinates set in the pre-step function
(``mbs.systemData.SetODE2Coordinates`` and ``SetODE2Coordinates_t``, configuration ``Current``, nothing else;
tests/test_flexible_window.py checks the continuation against the exact solution).  The contact is evaluated at
the shifted state after the move (``WheelRailContact.evaluate``): the evaluation the connector keeps for a next
call at the same state is that of the shifted state and window, never one of the state before the move.

What the move neglects (measured, tests/test_flexible_window.py and benchmarks/bench_flexible_track.py):

* the part of the translated vibration field outside the kept modes' span, dropped at each move: a static
  deflection field moved by ``T_k`` alone matches the full finite-element solution at the new position as closely
  as the kept modes themselves do (−3 % at the load at 800 Hz; the move changes it by at most 0.4 %);
* the field in the k bays that leave the window at the rear, and the k bays that enter at the front at rest: both
  lie beyond the margin, where a wheel load's static deflection is below 0.5 % of its peak;
* the kept modes' flexibility ripple between the wheelsets' positions before and after a move (vehicles with
  several wheelsets), and the end effects of a finite segment (the rails end on the first and last sleeper),
  which the margin keeps away from the wheels.

Against a fixed segment that carries the whole run (RK44 0.25 ms, 250 km/h into the RTRI lateral deviation, the
default 800 Hz modes with the static correction): the single wheelset of Manchester vehicle 1, 0.1 s over eleven
moves (88 modes against 150): the vertical wheel load Q differs by at most 0.30 % of its peak (166 N), the lateral
force by 18 N (0.65 % of its 2.8 kN peak), the rail's deflection under the wheel by 0.035 %, the ballast forces by
0.13 % (tests/test_flexible_window.py); the RTRI car (Manchester vehicle 1; benchmarks/bench_flexible_track.py,
0.4 s, 46 moves, 287 modes against 544): the wheel loads differ by at most 0.55 kN (0.8 % of the 68.5 kN peak; a fixed
segment 5 bays longer differs from the same reference by 0.29 kN), the lateral forces by 75 N (65 N), the rails'
deflection under the wheels by 0.18 % (0.34 %); the peaks of Q and Y agree to 0.1 %.  The differences recur at
every move and decay within a few milliseconds.  Over 1.5 s the run itself becomes sensitive once the flanges
work (the two fixed segments then differ by up to 11 kN from 0.45 s on, the window by up to 10 kN): compare peaks
and statistics there, not time histories (peaks: Q 68.46 kN on the window, 68.51 and 69.11 kN on the segments).
"""
from __future__ import annotations

import math

import numpy as np

from ..structures.deck_kinematics import DECK_START, N_DECK_PAR
from ..structures.modal_shapes import modal_shape_and_slope_at, modal_shape_at
from .flexible import FlexibleTrackModel, FlexibleTrackModes
from .flexible_parameters import KINDS, TrackParameters
from .flexible_segment import segment_margin_m

__all__ = ["DEFAULT_SHIFT_BAYS", "window_margin_m", "window_length_m",
           "window_start_m", "shift_gather", "shift_matrix", "shifted_state", "modal_state", "set_modal_state",
           "transfer_modal_state", "FlexibleTrackWindow"]

#: the bays a window of :func:`window_length_m` moves at a time: one, the shortest window (measured on the RTRI car,
#: benchmarks/bench_flexible_track.py: moves of 1, 2 and 4 bays disturb the wheel loads alike, 0.35-0.6 kN)
DEFAULT_SHIFT_BAYS = 1
def window_margin_m(params: TrackParameters) -> float:
    """The default margin behind the rearmost and ahead of the leading wheelset [m]: a fixed segment's
    (:func:`.flexible_segment.segment_margin_m`)."""
    return segment_margin_m(params)


def _check_shift_bays(shift_bays) -> int:
    if isinstance(shift_bays, bool) or not isinstance(shift_bays, (int, np.integer)) or shift_bays < 1:
        raise ValueError(f"shift_bays = {shift_bays!r}: expected an integer >= 1 (sleeper bays per window move)")
    return int(shift_bays)


def _check_margin(params: TrackParameters, margin_m) -> float:
    if margin_m is None:
        return window_margin_m(params)
    if isinstance(margin_m, bool) or not isinstance(margin_m, (int, float)) or not math.isfinite(margin_m) \
            or margin_m < params.sleeper_spacing_m:
        raise ValueError(f"margin_m = {margin_m!r}: expected a length of at least one sleeper bay "
                         f"({params.sleeper_spacing_m:g} m)")
    return float(margin_m)


def window_length_m(params: TrackParameters, wheelset_x_m, shift_bays: int = DEFAULT_SHIFT_BAYS,
                    margin_m: float | None = None) -> float:
    """Length [m] of the window a vehicle with wheelsets at ``wheelset_x_m`` (along the track, any origin) needs:
    the margin (default :func:`window_margin_m`) behind the rearmost and ahead of the leading wheelset, the
    wheelsets' span, and ``shift_bays`` bays to move by, in whole bays: ``⌈(2 m + span)/d⌉ + shift_bays`` bays."""
    if not isinstance(params, TrackParameters):
        raise TypeError(f"params={params!r}: expected TrackParameters")
    shift_bays = _check_shift_bays(shift_bays)
    m = _check_margin(params, margin_m)
    x = np.asarray(wheelset_x_m, dtype=float).ravel()
    if x.size == 0 or not np.all(np.isfinite(x)):
        raise ValueError(f"wheelset_x_m = {wheelset_x_m!r}: expected the finite positions of the wheelsets")
    d = params.sleeper_spacing_m
    return (math.ceil((2.0 * m + float(x.max() - x.min())) / d - 1e-9) + shift_bays) * d


def window_start_m(params: TrackParameters, s_rear_m: float, margin_m: float | None = None) -> float:
    """The first sleeper of a window whose rearmost wheelset is at ``s_rear_m``: the margin behind it, rounded down
    to a whole bay (from s = 0, so that every window position lies on the same sleeper grid)."""
    m = _check_margin(params, margin_m)
    d = params.sleeper_spacing_m
    return math.floor((float(s_rear_m) - m) / d + 1e-9) * d


# ------------------------------------------------------------------------------------------------ the shift
def shift_gather(model: FlexibleTrackModel, k: int) -> np.ndarray:
    """``S_k`` as a gather index over one beam's DOFs (module docstring): ``(S_k u)[i] = u[g[i]]`` for
    ``g[i] >= 0``, zero where ``g[i] = -1`` (the bays entering at the front)."""
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 0 <= k <= model.n_bays:
        raise ValueError(f"k = {k!r}: expected a whole number of bays in [0, {model.n_bays}]")
    k = int(k)
    g = np.full(model.n_dof, -1, dtype=np.int64)
    kn = k * model.params.elements_per_bay
    nn = model.n_nodes - kn                           # rail nodes that stay
    g[:2 * nn] = np.arange(2 * kn, 2 * model.n_nodes)
    ns = model.n_sleepers - k
    g[2 * model.n_nodes:2 * model.n_nodes + ns] = 2 * model.n_nodes + k + np.arange(ns)
    return g


def shift_matrix(modes: FlexibleTrackModes, k: int) -> np.ndarray:
    """``T_k`` (n_modes × n_modes, block diagonal per beam): modal coordinates of the window moved forward by ``k``
    bays from those of the window before the move, ``T_k = Φᵀ M S_k Φ`` per beam (module docstring)."""
    _check_modes(modes)
    model = modes.model
    g = shift_gather(model, k)
    keep = g >= 0
    T = np.zeros((modes.n_modes, modes.n_modes))
    for kind in KINDS:
        sl = modes.slices[kind]
        phi = modes.shapes[kind]
        if phi.shape[1] == 0:
            continue
        M = model.assemble(kind)[0]
        s_phi = np.zeros_like(phi)
        s_phi[keep] = phi[g[keep]]
        T[sl, sl] = phi.T @ (M @ s_phi)
    return T


def _check_modes(modes):
    if not isinstance(modes, FlexibleTrackModes) or type(modes.model) is not FlexibleTrackModel:
        raise TypeError(f"modes={modes!r}: a moving window needs the modes of a track on rigid ground "
                        "(FlexibleTrackModel.modes(); a track on a deck is not periodic)")


# ------------------------------------------------------------------------------------------------ the window
class FlexibleTrackWindow:
    """The moving window (module docstring) of the flexible track ``handle`` (:func:`.flexible.add_flexible_track`)
    under the wheel–rail ``contact`` coupled to it (``bridge=handle``, ``frame="moving"``).  Create after
    the contact (before or after ``mbs.Assemble()``); pass as the runner's ``user_function`` (it returns True), or
    call :meth:`update` from another pre-step function; ``then``: a further ``user_function(mbs, t)`` called after
    it (its result is returned).  ``margin_m``: default :func:`window_margin_m`; ``shift_bays``: the bays of a
    move, default all the window has beyond the wheelsets' span and the margins; ``t_start_s``: the time of the
    first state.

    The segment must be long enough for the margins and a move of at least one bay; the wheelsets must start
    inside it with the margin (else ``ValueError`` naming the window and the wheelsets).  :attr:`shifts` counts
    the moves, :attr:`bays_moved` the bays."""

    def __init__(self, handle, contact, *, margin_m: float | None = None, shift_bays: int | None = None,
                 t_start_s: float = 0.0, then=None):
        modes = handle.modes
        _check_modes(modes)
        if getattr(contact, "structure", None) is not handle:
            raise ValueError("contact: not coupled to this flexible track (add_wheel_rail_contact(..., structure=handle))")
        if not contact.moving_frame:
            raise ValueError("contact: the moving window needs frame='moving' (wheelsets at s = s_start + V t + x)")
        if then is not None and not callable(then):
            raise TypeError(f"then={then!r}: expected a user function (mbs, t) or None")
        self.handle, self.contact, self.modes = handle, contact, modes
        self.model = modes.model
        self.params = self.model.params
        self.d_m = self.params.sleeper_spacing_m
        self.margin_m = _check_margin(self.params, margin_m)
        self.then = then
        self._par = _deck_parameters(contact)
        if self._par[DECK_START] != modes.table.start_m:
            raise ValueError(f"contact: its deck start {self._par[DECK_START]!r} m is not the track table's "
                             f"{modes.table.start_m!r} m (a window is created once, before the run)")
        self.x_m = np.asarray(contact.p_ref[:, 0], dtype=float)        # wheelset x in the moving frame
        self.speed_m_s = contact.speed_m_s
        self.s_start_m = contact.s_start_m
        self._t_state = float(t_start_s)
        rear, front = self.wheelset_span_m(self._t_state)
        if rear - self.start_m < self.margin_m - 1e-9 or self.end_m - front < self.margin_m - 1e-9:
            raise ValueError(f"flexible track window [{self.start_m:g}, {self.end_m:g}] m: the wheelsets at "
                             f"[{rear:.6g}, {front:.6g}] m are not inside it with the margin {self.margin_m:.4g} m "
                             "at both ends (window_start_m, window_length_m)")
        room = int(math.floor((self.model.length_m - (front - rear) - 2.0 * self.margin_m) / self.d_m + 1e-9))
        if shift_bays is None:
            shift_bays = room
        elif _check_shift_bays(shift_bays) > room:
            raise ValueError(f"shift_bays = {shift_bays!r}: the window of {self.model.length_m:g} m leaves room for "
                             f"{max(room, 0)} bays beyond the wheelsets' span and the margins")
        if shift_bays < 1:
            raise ValueError(f"flexible track window of {self.model.length_m:g} m: too short to move for wheelsets "
                             f"spanning {front - rear:.6g} m with the margin {self.margin_m:.4g} m at both ends "
                             f"(window_length_m: at least "
                             f"{window_length_m(self.params, self.x_m, 1, self.margin_m):g} m)")
        self.shift_bays = int(shift_bays)
        self._T = {}
        self._flexibility = modes.omega_rad_s ** -2.0
        # with the static correction the kept and dropped modes together give the full model's flexibility, the
        # same at every window position: the wheel forces' quasi-static field moves unchanged (shifted_state)
        self._keep_rail = getattr(modes, "residual_table", None) is None
        self.shifts = 0
        self.bays_moved = 0

    # -- the one fact: the window's current start ----------------------------------------------------------------
    @property
    def start_m(self) -> float:
        """Track distance of the window's first sleeper now [m] (the connector's deck parameter ``DECK_START``)."""
        return float(self._par[DECK_START])

    @property
    def end_m(self) -> float:
        return self.start_m + self.model.length_m

    def wheelset_s_m(self, mbs, t: float) -> np.ndarray:
        """Track distance of every wheelset's axle centre in the state of ``mbs`` at time t [m], as the connector
        computes it (``s_start + V t + x``, x with the wheelset's longitudinal displacement)."""
        q, _ = self.contact.coordinates(mbs)
        n = self.x_m.shape[0]
        return self.s_start_m + self.speed_m_s * float(t) + self.x_m + q[0:6 * n:6]

    def wheelset_span_m(self, t: float) -> tuple[float, float]:
        """Track distance of the rearmost and the leading wheelset at time t [m]."""
        s = self.s_start_m + self.speed_m_s * float(t)
        return s + float(self.x_m.min()), s + float(self.x_m.max())

    def shape_at(self, s_m, start_m: float | None = None) -> np.ndarray:
        """``Φ(s)`` of the window at its current position (or starting at ``start_m``): (..., 3, n_modes), rows
        y_rail, z_rail, θ_rail (zero off the window); the current counterpart of ``FlexibleTrackModes.shape_at``."""
        tb = self.modes.table._replace(start_m=self.start_m if start_m is None else float(start_m))
        s = np.asarray(s_m, dtype=float)
        out = np.empty((s.size, 3, self.modes.n_modes))
        for i, x in enumerate(s.ravel()):
            modal_shape_at(float(x), *tb, out[i])
        return out.reshape(s.shape + (3, self.modes.n_modes))

    def shape_and_slope_at(self, s_m, start_m: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``Φ(s)`` and ``dΦ/ds`` of the window (at ``start_m``, default its current start) at the track distances
        ``s_m`` (k,), stacked as (3 k, n_modes): rows y, z, θ of each point in turn."""
        tb = self.modes.table._replace(start_m=self.start_m if start_m is None else float(start_m))
        s = np.atleast_1d(np.asarray(s_m, dtype=float))
        phi = np.empty((s.size, 3, self.modes.n_modes))
        dphi = np.empty_like(phi)
        for i, x in enumerate(s):
            modal_shape_and_slope_at(float(x), *tb, phi[i], dphi[i])
        return phi.reshape(-1, self.modes.n_modes), dphi.reshape(-1, self.modes.n_modes)

    def sleeper_index(self, s_m) -> np.ndarray:
        """Index (in the window now) of the sleeper nearest to each track distance ``s_m``, clipped to the window."""
        return self.model.nearest_sleeper(s_m, self.start_m)

    # -- the move ----------------------------------------------------------------------------------------------
    def shift_matrix(self, k: int) -> np.ndarray:
        """:func:`shift_matrix` of the window's modes, computed once per k."""
        T = self._T.get(k)
        if T is None:
            T = self._T[k] = shift_matrix(self.modes, k)
        return T

    def bays_due(self, t_state: float) -> int:
        """Bays to move before the step from the state at ``t_state``: :attr:`shift_bays` once the wheelsets'
        centre has passed ``shift_bays d / 2`` beyond the window's centre (after the move it lies as far before
        it: every wheelset moves to the mirror image of the position of its mirror wheelset, where the kept modes
        give the same flexibility), else 0."""
        rear, front = self.wheelset_span_m(t_state)
        c = 0.5 * (rear + front) - self.start_m
        return self.shift_bays if c >= 0.5 * (self.model.length_m + self.shift_bays * self.d_m) else 0

    def shift(self, mbs, k: int, t_state: float | None = None) -> None:
        """Move the window forward by ``k`` bays now: the modal coordinates and rates of the Exudyn system by
        :meth:`shift_matrix`, the connector's deck start by ``k d``; then the contact is evaluated at the shifted
        state (at ``t_state``, default the time of the last state handled)."""
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 1 <= k < self.model.n_bays:
            raise ValueError(f"k = {k!r}: expected a whole number of bays in [1, {self.model.n_bays - 1}]")
        t_state = self._t_state if t_state is None else float(t_state)
        s = self.wheelset_s_m(mbs, t_state)
        start = self.start_m + int(k) * self.d_m
        self.contact.evaluate(mbs, t_state)                         # the wheel forces of this state
        F = self.contact.rail_forces_N().ravel()                      # (Fy, Fz, Mx) per wheelset: A's rows
        A_old, dA_old = self.shape_and_slope_at(s)
        A_new, dA_new = self.shape_and_slope_at(s, start)
        q, q_t, _ = modal_state(mbs, self.handle.modal_node)
        q, q_t = shifted_state(q, q_t, self.shift_matrix(int(k)), self._flexibility, self.speed_m_s, F,
                               A_old, dA_old, A_new, dA_new, keep_rail=self._keep_rail)
        set_modal_state(mbs, self.handle.modal_node, q, q_t)
        self._par[DECK_START] = start
        self.shifts += 1
        self.bays_moved += int(k)
        # the connector keeps its last evaluation for a next call at the same state: make it the shifted state's
        self.contact.evaluate(mbs, t_state)

    def update(self, mbs, t: float) -> int:
        """The pre-step work (Exudyn's ``t``: the end of the coming step; the state is that of the previous call's
        ``t``, or ``t_start_s``): move the window if due; returns the bays moved."""
        t = float(t)
        k = self.bays_due(self._t_state)
        if k > 0:
            self.shift(mbs, k, self._t_state)
        self._t_state = t
        return k

    def __call__(self, mbs, t) -> bool:
        self.update(mbs, t)
        return True if self.then is None else bool(self.then(mbs, t))

    def summary(self) -> dict:
        return {"window_length_m": self.model.length_m, "start_m": self.start_m, "margin_m": self.margin_m,
                "shifts": self.shifts, "bays_moved": self.bays_moved}


def modal_state(mbs, modal_node: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(q, q̇, idx)`` of ``modal_node`` in the assembled system's current state (``idx``: its system indices)."""
    import exudyn as exu
    idx = np.asarray(mbs.systemData.GetNodeLTGODE2(int(modal_node)), dtype=np.int64)
    cur = exu.ConfigurationType.Current
    return (np.array(mbs.systemData.GetODE2Coordinates(cur), dtype=float)[idx],
            np.array(mbs.systemData.GetODE2Coordinates_t(cur), dtype=float)[idx], idx)


def set_modal_state(mbs, modal_node: int, q: np.ndarray, q_t: np.ndarray) -> None:
    """Set the coordinates and rates of ``modal_node`` in the system's current state (configuration ``Current``:
    the state the next explicit step starts from)."""
    import exudyn as exu
    idx = np.asarray(mbs.systemData.GetNodeLTGODE2(int(modal_node)), dtype=np.int64)
    cur = exu.ConfigurationType.Current
    sd = mbs.systemData
    for get, put, v in ((sd.GetODE2Coordinates, sd.SetODE2Coordinates, q),
                        (sd.GetODE2Coordinates_t, sd.SetODE2Coordinates_t, q_t)):
        x = np.array(get(cur), dtype=float)
        x[idx] = v
        put(x, cur)


def transfer_modal_state(mbs, modal_node: int, T: np.ndarray) -> None:
    """``q ← T q``, ``q̇ ← T q̇`` for ``modal_node`` in the system's current state (the plain shift)."""
    q, q_t, _ = modal_state(mbs, modal_node)
    if T.shape != (q.size, q.size):
        raise ValueError(f"T of shape {T.shape}: node {modal_node} has {q.size} coordinates")
    set_modal_state(mbs, modal_node, T @ q, T @ q_t)


def shifted_state(q, q_t, T, flexibility, speed_m_s, F, A_old, dA_old, A_new, dA_new, keep_rail: bool = True):
    """The modal state after a move (module docstring, "Shift"): the quasi-static deflection of the wheel forces
    ``F`` (r,) at the wheelsets, ``diag(ω⁻²) Aᵀ F`` and its rate ``V diag(ω⁻²) A'ᵀ F`` (``A``, ``A' = dA/ds``
    (r × n): the rows of the wheelsets' ``Φ(s)`` before and after the move), is taken out, the rest carried by
    ``T``, and the quasi-static part of the new window put back: for the same forces (``keep_rail=False``: the
    model's flexibility at the wheels does not depend on the window's position, as with the static correction),
    or for forces ``F'`` that keep the rail under the wheelsets where it was, ``A_new q' = A_old q`` (the kept
    modes' flexibility ripples along the window by a fraction of their truncation error: the rail does not jump
    under the stiff contact, the rail carries the small force difference instead).  The rates get the smallest
    correction (in the modal norm) that keeps ``A q̇``.  Returns ``(q', q̇')``."""
    w = np.asarray(flexibility, dtype=float)
    V = float(speed_m_s)
    q_d = T @ (q - w * (A_old.T @ F))
    v_d = T @ (q_t - V * w * (dA_old.T @ F))
    F_new = np.linalg.lstsq((A_new * w) @ A_new.T, A_old @ q - A_new @ q_d, rcond=None)[0] if keep_rail else F
    q_new = q_d + w * (A_new.T @ F_new)
    v_new = v_d + V * w * (dA_new.T @ F_new)
    v_new += A_new.T @ np.linalg.lstsq(A_new @ A_new.T, A_old @ q_t - A_new @ v_new, rcond=None)[0]
    return q_new, v_new


def _deck_parameters(contact) -> np.ndarray:
    """The deck parameter array of the contact's compiled model (``par`` of
    :func:`~exudyn_wheelrail.structures.deck_kinematics.deck_arrays`), read by name where the deck arrays name
    their members and else as their first member, checked to be that array."""
    deck = getattr(contact, "_deck", None)
    if deck is None:
        raise TypeError(f"contact={contact!r}: expected a WheelRailContact (multibody.connector)")
    par = getattr(deck, "par", None)
    if par is None:
        par = deck[0]
    if not (isinstance(par, np.ndarray) and par.ndim == 1 and par.shape[0] >= N_DECK_PAR and par.dtype == float):
        raise TypeError("contact: its deck arrays do not start with the deck parameters (deck_kinematics.deck_arrays)")
    return par
