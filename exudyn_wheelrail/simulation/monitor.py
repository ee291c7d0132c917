"""Run monitor for a model with a :class:`~exudyn_wheelrail.multibody.connector.WheelRailContact`: flange climb, wheel lift-off, deep
penetration, hunting, **derailment** and invalid states, with a clear :class:`Status` instead of garbage or NaN.

>>> monitor = RunMonitor(contact)                                              # doctest: +SKIP
>>> status, t_end = run_monitored(mbs, sim, exu.DynamicSolverType.RK44, monitor)  # doctest: +SKIP
>>> status.kind, status.time_s, status.wheelset, status.side                   # doctest: +SKIP
('derailment', 0.734, 0, 'right')

How it runs
-----------
:meth:`RunMonitor.attach` installs :meth:`RunMonitor.pre_step` as Exudyn's pre-step user function (chaining a
function already given).  Exudyn calls it before every step with the time at the *end* of the coming step while
the coordinates are still those at its start, so the monitor evaluates the contact at the time *of the state*: the
previous call's time (the start time at the first call) — one contact call as
:meth:`exudyn_wheelrail.multibody.connector.WheelRailContact.evaluate_state` (the warm start is kept), with the coordinates taken from the
system vectors.  An explicit step's first stage evaluates the contact at that same state: the connector hands it
the monitor's evaluation instead of computing it again (bit-identical; ``tests/test_watching.py``), so watching
costs no contact call of its own with an explicit solver.  When a stopping status is found the function returns ``False``: Exudyn (1.13.6,
checked in ``tests/stress``) then still completes the step it was about to take and stops, so the solve ends one
step after the detected state, at ``mbs.systemData.GetTime()``.  (The runner checks the states of an explicit
run on the compiled call path in the force call itself, with the same compiled checks: :mod:`.watch`.)
:func:`~.runner.run_monitored` wraps ``SolveDynamic``: it
catches :class:`~exudyn_wheelrail.multibody.connector.ContactStateError` (non-finite coordinates; Exudyn re-raises a user function's exception
with it as the ``__cause__``) and any other solver failure, checks the final state and returns ``(status, t_end)``.

Cost: the checks of a state are one compiled call over the arrays of that contact evaluation
(:mod:`.monitor_core`: every quantity, record, interval and the hunting counter below, and the stability estimate
with a Jacobi eigenvalue); it returns a code, and Python builds events only for a state where something starts,
ends or fires; the call's arguments are packed once and it is called without numba's type dispatch, the wheelset
poses are read from the connector's arrays without a copy.  For the RTRI vehicle (4 wheelsets, RK44) the monitor's
work besides the contact call is about 5–10 µs per state at rest and 8–11 µs along a run (median state, load
2.3–2.6); the contact call itself about 20–35 µs (``benchmarks/bench_watching.py``,
``benchmarks/bench_step_overhead.py``).

Quantities per wheel (wheel ``2k`` the right, ``2k+1`` the left wheel of wheelset k, as the connector) — all in the
*side frame* of the wheel's rail (:mod:`exudyn_wheelrail.conventions`: y towards the field side, z down; the pose
``(c_y, c_z, roll)`` of the wheel relative to its rail, irregularity and bridge deck included, as the connector
hands it to the kernel):

* **lift-off**: the wheel carries no normal force (sum over its contact slots ``<= lift_force_N``, default 0).
  Recorded as intervals (start = first state without force, end = first state with force again; resolution one
  step) with their duration and the largest gap in them — the smallest wheel–rail distance the kernel reports for
  the separated regions (a normal distance in any direction, e.g. the flange's clearance to the gauge corner; a
  guaranteed lower bound when the kernel's separation bound answered).
* **deep penetration**: a loaded contact with the kernel's ``FLAG_DEEP_PENETRATION`` (penetration above the
  kernel's ``P_MAX_PENETRATION``, 2 mm: far outside an elastic contact).  Recorded as intervals.
* **flange climb** (recorded as intervals with the reasons; does not stop the run) — any of

  - ``beyond_flank``: a loaded contact of the *flange region* lies on the tip side of the flange's steepest part
    (the largest contact angle of the flank, :attr:`~exudyn_wheelrail.profiles.profiles.WheelProfile.
    flank_angle_rad`, 70° on S1002's straight flank), where the profile's slope has fallen
    ``FLANK_ANGLE_DROP_RAD`` (0.05 rad) below it: past the flank the contact angle falls as the wheel rises, so
    Nadal's limit Y/Q falls and the climb runs away under a constant lateral force;
  - ``profile_end``: a loaded flange-region contact with the kernel's ``FLAG_PROFILE_END``;
  - ``other_wheel_lifted``: the other wheel of the wheelset carries no normal force while this wheel's flange
    region carries a lateral force above ``large_lateral_force_N`` (default: Prud'homme's track-shift limit
    10 kN + P/3, P the wheelset's instantaneous total wheel load) — the wheelset tips about its flange contact.
    (Flange impacts that make the other wheel hop meet it too.)

* **hunting** (per wheelset, recorded, does not stop): the wheelset's lateral displacement relative to the rails
  oscillates about the centre with half-cycle peaks ``>= hunting_amplitude_m`` (default 3 mm, about half the
  flangeway clearance of S1002 on UIC60 1:40, 7 mm) in at least ``hunting_cycles`` (3) consecutive cycles.  A
  forced oscillation of that size is reported the same way.

Derailment (stops the run)
--------------------------
A wheel is **derailed** when its rail no longer guides it laterally.  With the wheel placed by its pose relative
to its rail (side frame; the flange tip is the wheel's largest radius — for a flangeless wheel the flange-side end
of the tread — and the rail crown the highest point of the rail head):

(D1) **laterally off the rail**: the crown no longer lies between the flange tip and the field-side end of the
     tread: ``y_tip(pose) >= y_crown`` — the flange has passed over the rail top to the field side, every
     flange–rail contact now pushes the wheel further out and gravity pulls it down the field side of the head —
     or ``y_field_end(pose) <= y_crown`` (the wheel has dropped off its rail towards the track centre);
(D2) **lifted above the flange** (flanged wheels): the flange tip lies above the rail top, ``z_tip(pose) <
     z_crown`` — the wheel has climbed (or jumped) by more than the flange height (S1002: 28 mm) and the flange no
     longer overlaps the rail head, so nothing holds the wheel laterally (the end of a flange climb; the usual
     simulation criterion "wheel lift >= flange height");
(D3) **off the data**: a loaded flange-region contact lies at the end of the profile data (``FLAG_PROFILE_END``)
     while the wheel has moved towards the field side by more than ``y_crown - y_tip(0)`` less the flange width
     (from the flange back to its steepest point): no contact can be computed beyond the data (the flange back on
     the rail, or the flange beside the rail's data).  A profile-end contact of a wheel close to its place is
     only a climb indication.

All three follow from the geometry of the pose (D1, D2 also for a wheel in the air).  The earlier, practical
criteria (Nadal's Y/Q at the flank, a lift of a few mm) are the flange-climb events above; derailment here is the
point of no return.  The status names the wheelset, the wheel (``right``/``left``) and the time of the state.

Invalid states (stop the run)
-----------------------------
``invalid_state``:

* non-finite coordinates (:class:`~exudyn_wheelrail.multibody.connector.ContactStateError`, with its time and wheelset), or non-finite
  contact results for a finite state;
* a penetration above ``invalid_penetration_m`` (default 5 mm, 2.5 x the kernel's deep-penetration threshold: a
  Hertz force of tens of MN);
* a wheelset velocity (lateral or vertical, model frame) above ``max_speed_m_s`` (10 m/s) or a roll/yaw rate above
  ``max_rate_rad_s`` (20 rad/s) — reached by a diverging integration, not by a running wheelset;
* with RK44 (:func:`~.runner.run_monitored` passes the step): the **stability estimate** — the highest natural
  frequency ω of each wheelset on its linearised contact stiffness (6x6: Σ dN/dδ g gᵀ over the loaded contacts,
  g = (n, r x n) with the rail normal n and the lever r from the axle centre, against the wheelset's mass and
  inertia) — exceeds RK44's limit ω h <= 2√2 (per state the largest eigenvalue by Jacobi's method, unless
  Gershgorin's bound already keeps it at or below the run's largest so far; within
  :data:`~.monitor_stability.STABILITY_SCREEN_MARGIN` of the limit LAPACK's eigenvalue decides).  This alone is
  recorded as a ``step_size`` event (a short excursion may pass); every stopping status after it becomes
  ``invalid_state`` naming both ("the integration is not trustworthy; then: …"), so a diverged run is never
  reported as a derailment.  The creep damping (:meth:`RunMonitor.creep_decay_rate_1_s`: Kalker's linear theory
  on the loaded contacts, decay rates growing as 1/V) is checked at the first state against RK44's real-axis
  limit σ h <= 2.785: beyond it the run stops with the same ``step_size`` event (a low-speed run at 1 ms
  integrates a limit cycle of the creep forces, not rolling).

``time_limit``: the wall-clock limit ``time_limit_s`` was reached.  ``solver_failure``: ``SolveDynamic`` failed for
another reason (returned False, raised, or stopped early).  Completed runs end with ``completed`` — or ``hunting``
when hunting was detected (with a warning in the detail when the RK44 limit was exceeded on the way).  A run with
a derailment or invalid-state event that was not stopped (``stop_on`` without it) still ends with that status,
never with ``completed``.
"""
from __future__ import annotations

import math
import time

import numpy as np

from ..analysis.safety import nadal_limit, prudhomme_limit_N
from ..contact import layout as L
from ..multibody import connector as C
from ..multibody.core_data import compiled_for
from . import monitor_core as MC
from .monitor_records import (SIDES, STATUS_KINDS, STOP_KINDS, Interval, Status, WheelRecord,  # noqa: F401
                              contact_state_error, status_from_state_error)
from .monitor_stability import (STABILITY_SCREEN_MARGIN, StabilityEstimate, coupled_damper_rate_1_s,  # noqa: F401
                                wheelset_inertia)
from .solvers import RK44

__all__ = ["Status", "Interval", "WheelRecord", "RunMonitor", "STATUS_KINDS", "STOP_KINDS",
           "coupled_damper_rate_1_s"]

#: a flange contact counts as beyond the flank where the profile's slope is this much below the flank's steepest
FLANK_ANGLE_DROP_RAD = 0.05


def _reason_names(bits: int) -> set:
    return {name for bit, name in MC.REASON_NAMES if bits & bit}


#: interval kinds of the compiled records -> (event kind, WheelRecord list)
_INTERVALS = ((MC.IV_FLANGE, "flange_climb", "flange_climbs"), (MC.IV_LIFT, "lift_off", "lift_offs"),
              (MC.IV_DEEP, "deep_penetration", "deep_penetrations"))


class RunMonitor(StabilityEstimate):
    """Per-step checks of a model with a :class:`~exudyn_wheelrail.multibody.connector.WheelRailContact` (module docstring).

    Parameters
    ----------
    contact : the connector of the model.
    stop_on : kinds that stop the run (subset of :data:`STOP_KINDS`); default derailment, invalid states and the
        wall-clock limit.
    lift_force_N : a wheel whose normal forces sum to at most this is lifted off.
    large_lateral_force_N : flange lateral force of the ``other_wheel_lifted`` climb indication; None:
        Prud'homme's limit 10 kN + P/3 with P the wheelset's instantaneous total wheel load.
    invalid_penetration_m : penetration above which the state is invalid.
    max_speed_m_s, max_rate_rad_s : plausible wheelset lateral/vertical speed and roll/yaw rate (invalid above).
    hunting_amplitude_m, hunting_cycles : hunting detection.
    time_limit_s : wall-clock limit of the run from :meth:`attach` (None: none).
    keep_history : keep per-state arrays (:meth:`history`).
    """

    def __init__(self, contact, *, stop_on=("derailment", "invalid_state", "time_limit"), lift_force_N: float = 0.0,
                 large_lateral_force_N: float | None = None, invalid_penetration_m: float = 5e-3,
                 max_speed_m_s: float = 10.0, max_rate_rad_s: float = 20.0, hunting_amplitude_m: float = 3e-3,
                 hunting_cycles: int = 3, time_limit_s: float | None = None, keep_history: bool = True):
        bad = set(stop_on) - set(STOP_KINDS)
        if bad:
            raise ValueError(f"stop_on: unknown kinds {sorted(bad)}; expected a subset of {STOP_KINDS}")
        for name, v in (("lift_force_N", lift_force_N), ("invalid_penetration_m", invalid_penetration_m),
                        ("hunting_amplitude_m", hunting_amplitude_m), ("max_speed_m_s", max_speed_m_s),
                        ("max_rate_rad_s", max_rate_rad_s)):
            if not (math.isfinite(v) and v >= 0.0):
                raise ValueError(f"{name} = {v!r}: expected a finite value >= 0")
        if large_lateral_force_N is not None and not (math.isfinite(large_lateral_force_N) and
                                                      large_lateral_force_N > 0.0):
            raise ValueError(f"large_lateral_force_N = {large_lateral_force_N!r}: expected > 0 or None")
        if time_limit_s is not None and not (time_limit_s > 0.0):
            raise ValueError(f"time_limit_s = {time_limit_s!r}: expected > 0 or None")
        if not (isinstance(hunting_cycles, int) and hunting_cycles >= 1):
            raise ValueError(f"hunting_cycles = {hunting_cycles!r}: expected an integer >= 1")
        if not all(hasattr(contact, a) for a in ("forces", "kernel_output", "wheelset_rail_pose",
                                                 "save_warm_start")):
            raise TypeError("RunMonitor needs a WheelRailContact (multibody.connector)")
        self.contact = contact
        self.stop_on = tuple(stop_on)
        self.lift_force_N = float(lift_force_N)
        self.large_lateral_force_N = large_lateral_force_N
        self.invalid_penetration_m = float(invalid_penetration_m)
        self.max_speed_m_s = float(max_speed_m_s)
        self.max_rate_rad_s = float(max_rate_rad_s)
        self.hunting_amplitude_m = float(hunting_amplitude_m)
        self.hunting_cycles = hunting_cycles
        self.time_limit_s = time_limit_s
        self.keep_history = keep_history
        self._geometry(contact.pair)
        n_ws = len(contact.nodes_exu)
        self.n_wheelsets = n_ws
        self._wheels = [WheelRecord(w // 2, SIDES[w % 2]) for w in range(2 * n_ws)]
        self._open = [[None] * MC.N_IV for _ in range(2 * n_ws)]     # the open Interval of each wheel and kind
        self.hunting: list = [None] * n_ws       # per wheelset: Status of the first detection
        self.events: list[Status] = []           # every event in order (the start of each interval)
        self.status: Status | None = None        # the stopping status (None while running / completed)
        self.n_checks = 0
        self.t_last: float | None = None
        self._t_prev = 0.0
        self._wall0 = None
        self._user = None
        self._reported: set = set()
        self.rk44_dt_s = None
        self._inertia = None
        self._R = np.empty((3, 3))
        self._Mh = np.zeros((6, 6))
        #: the first ``step_size`` event (the RK44 stability limit exceeded), or None
        self.stability_exceeded: Status | None = None
        #: per wheelset the fastest decay rate of its creep damping at the first checked state [1/s]
        #: (:meth:`creep_decay_rate_1_s`; with the stability estimate only, else empty)
        self.creep_rate_1_s: list[float] = []
        #: Nadal's limit Y/Q at the flank (the contact's friction coefficient), for reference
        self.nadal_limit = (nadal_limit(self.flank_angle_rad, float(contact.cp[L.CP_MU]))
                            if math.isfinite(self.flank_angle_rad) else float("nan"))
        # the compiled records (monitor_core) and their constants
        self._need = 2 * hunting_cycles
        (self._ext, self._iv, self._wq, self._wflag, self._wss, self._rings, self._G,
         self._work) = MC.empty_arrays(n_ws, self._need)
        self._par = self._constants()
        self._ws_par = np.zeros((n_ws, MC.N_WSP))
        self._ws_par[:, MC.WSP_P_REF:MC.WSP_P_REF + 3] = np.asarray(contact.p_ref, dtype=float)
        self._hist = np.zeros((0, 1 + 7 * 2 * n_ws))
        self._hist_n = 0
        self._out = contact.kernel_output()      # read-only view of the kernel output, updated by every evaluation
        self._system = None                      # (mbs, its coordinate getters, the connector's global indices)
        # the wheelset poses relative to the rails, filled per state from the connector's arrays without allocating
        # (a contact without them: its wheelset_rail_pose())
        self._poses = np.zeros((n_ws, 3))
        pose_arrays = getattr(contact, "rail_pose_arrays", None)
        self._pose_arrays = pose_arrays() if pose_arrays is not None else None
        # the per-state call's arguments that stay the same objects for the whole run (filled in place)
        shapes = getattr(contact, "deck_shape_array", None)
        self._phi_ws = shapes() if shapes is not None else np.zeros((n_ws, 3, 0))
        self._records = (self._par, self._ws_par, self._ext, self._iv, self._wq, self._wflag, self._wss, self._rings,
                         self._G, self._work, self._phi_ws)
        self._load_compiled()

    def _load_compiled(self):
        """One call of the compiled check on copies of the records (loads or compiles it here, not inside a timed
        solve)."""
        n_ws = self.n_wheelsets
        records = [a.copy() for a in (self._ext, self._iv, self._wq, self._wflag, self._wss, self._rings, self._G,
                                      self._work)]
        # the deck shapes as themselves (a read-only view the check only reads): a copy would be writable, another
        # type, and the watch's call (which passes the view) would compile the check a second time
        args = (0.0, np.zeros_like(self.contact.results), self._out, np.zeros((n_ws, 3)), np.zeros(6 * n_ws),
                np.zeros(6 * n_ws), self._par.copy(), self._ws_par.copy(), *records, self._phi_ws, self._hist,
                -1)
        MC.monitor_state(*args)
        # the compiled specialization for exactly these argument types: no type dispatch per state
        self._monitor_state = compiled_for(MC.monitor_state, *args)
        if self._pose_arrays is not None:
            MC.rail_poses(*self._pose_arrays, np.zeros((n_ws, 3)))

    def _constants(self) -> np.ndarray:
        par = np.zeros(MC.N_PAR)
        par[MC.PAR_LIFT_FORCE] = self.lift_force_N
        par[MC.PAR_LARGE_LATERAL] = math.nan if self.large_lateral_force_N is None else self.large_lateral_force_N
        # Prud'homme's limit is affine in the axle load: its two coefficients from the one formula
        f3, f6 = prudhomme_limit_N(static_axle_load_N=3.0), prudhomme_limit_N(static_axle_load_N=6.0)
        par[MC.PAR_PRUDHOMME_C1] = (f6 - f3) / 3.0
        par[MC.PAR_PRUDHOMME_C0] = f3 - 3.0 * par[MC.PAR_PRUDHOMME_C1]
        par[MC.PAR_PRUDHOMME_NONE] = 10e3
        par[MC.PAR_INVALID_PEN] = self.invalid_penetration_m
        par[MC.PAR_MAX_SPEED] = self.max_speed_m_s
        par[MC.PAR_MAX_RATE] = self.max_rate_rad_s
        par[MC.PAR_Y_CROWN], par[MC.PAR_Z_CROWN] = self.y_crown, self.z_crown
        par[MC.PAR_TIP_Y], par[MC.PAR_TIP_Z] = self.tip
        par[MC.PAR_FIELD_Y], par[MC.PAR_FIELD_Z] = self.field_end
        par[MC.PAR_FLANGED] = 1.0 if self.flanged else 0.0
        par[MC.PAR_S_FLANK] = self.s_flank
        par[MC.PAR_PROFILE_END_LAT] = self.profile_end_lateral_m
        par[MC.PAR_HUNT_AMP] = self.hunting_amplitude_m
        par[MC.PAR_HUNT_NEED] = self._need
        par[MC.PAR_STEP] = 0.0
        par[MC.PAR_STAB_SCREEN] = RK44.imaginary_axis_limit * (1.0 - STABILITY_SCREEN_MARGIN)
        return par

    # -- geometry of the pair (side frame, wheelset frame for the wheel) -------------------------------------------
    def _geometry(self, pair):
        wheel = pair.wheel
        rail = pair.rail_side
        s = np.linspace(rail.s_min, rail.s_max, 20001)
        e = rail.evaluate(s)
        i = int(np.argmin(e[:, 1]))
        self.y_crown = float(e[i, 0])
        self.z_crown = float(e[i, 1])
        self.flanged = pair.flange_side is not None
        self.flange_height_m = float(wheel.flange_height_m) if self.flanged else 0.0
        if pair.flange_side is not None:
            f = pair.flange_side
            ef = f.evaluate(np.linspace(f.s_min, f.s_max, 8001))
            j = int(np.argmax(ef[:, 1]))
            self.tip = (float(ef[j, 0]), float(ef[j, 1]))          # flange tip, wheelset side frame
            # the tip-side end of the steepest part of the flank: the first point (from the flank towards the tip)
            # whose slope is FLANK_ANGLE_DROP_RAD below the steepest (S1002: a straight 70° flank; past its upper end
            # the contact angle falls on the tip radius)
            s_f = np.linspace(f.s_min, f.s_max, 8001)
            ang = np.abs(np.arctan2(ef[:, 3], ef[:, 2]))
            between = (s_f > s_f[j]) & (s_f <= wheel.s_at_y(wheel.flank_y_m) + 1e-12)
            steep = between & (ang >= wheel.flank_angle_rad - FLANK_ANGLE_DROP_RAD)
            self.s_flank = float(s_f[steep][0]) if steep.any() else float(wheel.s_at_y(wheel.flank_y_m))
            self.y_flank_top = float(ef[np.searchsorted(s_f, self.s_flank), 0])
            self.flank_angle_rad = float(wheel.flank_angle_rad)
            # flange width: from the flange back to its steepest point
            self.flange_width_m = float(wheel.flank_y_m - wheel.flange_back_y_m)
        else:
            t0 = pair.tread_side.evaluate(np.array([pair.tread_side.s_min]))[0]
            self.tip = (float(t0[0]), float(t0[1]))
            self.s_flank = -math.inf
            self.y_flank_top = float("nan")
            self.flank_angle_rad = float("nan")
            self.flange_width_m = 0.0
        t1 = pair.tread_side.evaluate(np.array([pair.tread_side.s_max]))[0]
        self.field_end = (float(t1[0]), float(t1[1]))
        #: lateral displacement (side frame, roll 0) at which the flange tip reaches the crown
        self.derail_lateral_m = self.y_crown - self.tip[0]
        #: D3: profile-end contacts of the flange count as derailment beyond this displacement
        self.profile_end_lateral_m = self.derail_lateral_m - self.flange_width_m

    # -- Exudyn hook ----------------------------------------------------------------------------------------------
    def attach(self, mbs, user_function=None, t_start_s: float = 0.0, rk44_dt_s: float | None = None):
        """Install :meth:`pre_step` as the pre-step user function of ``mbs``, followed by ``user_function(mbs, t)``
        if given (Exudyn's arguments; it must return a bool; the contact's results are then those of the checked
        state); ``t_start_s`` is the time of the initial state.  Starts the wall clock of ``time_limit_s``.
        ``rk44_dt_s``: the step of an RK44 solve — enables the stability estimate (module docstring;
        :func:`~.runner.run_monitored` sets it)."""
        self._user = user_function
        self._t_prev = float(t_start_s)
        self._wall0 = time.perf_counter()
        self.rk44_dt_s = None if rk44_dt_s is None else float(rk44_dt_s)
        self._inertia = wheelset_inertia(mbs, self.contact.nodes_exu) if self.rk44_dt_s else None
        self._par[MC.PAR_STEP] = self.rk44_dt_s or 0.0
        self._ws_par[:, MC.WSP_HAS_INERTIA] = 0.0
        for k, inertia in enumerate(self._inertia or ()):
            if inertia is not None:
                mass, I_inv_sqrt = inertia
                self._ws_par[k, MC.WSP_HAS_INERTIA] = 1.0
                self._ws_par[k, MC.WSP_INV_SQRT_MASS] = 1.0 / math.sqrt(mass)
                self._ws_par[k, MC.WSP_I_INV_SQRT:MC.WSP_I_INV_SQRT + 9] = np.asarray(I_inv_sqrt).ravel()
        mbs.SetPreStepUserFunction(self.pre_step)
        self._attached_to = mbs
        return self

    def attached_to(self, mbs) -> bool:
        """This monitor's pre-step function is attached to ``mbs`` (:meth:`attach`)."""
        return getattr(self, "_attached_to", None) is mbs

    @property
    def user_function(self):
        """The user function :meth:`attach` chained after the checks (None: none)."""
        return self._user

    def pre_step(self, mbs, t):
        """Exudyn pre-step user function: checks the state (at the previous call's time) and returns False to stop."""
        t_state = self._t_prev
        self._t_prev = float(t)
        if self.status is not None:
            return False
        st = self.check(mbs, t_state)
        go = True
        if self._user is not None:           # after the check: the contact's results are those of this state
            go = bool(self._user(mbs, t))
        return go and st is None

    # -- one check ------------------------------------------------------------------------------------------------
    def annotate(self, status: Status) -> Status:
        """A status after the RK44 stability limit was exceeded becomes ``invalid_state`` naming both (what follows
        an unstable step is not trustworthy); other statuses are returned unchanged."""
        st = self.stability_exceeded
        if st is None or status.kind in ("time_limit", "step_size", "completed", "hunting"):
            return status
        return Status("invalid_state", status.time_s, status.wheelset, status.side,
                      f"{st.detail} since t = {st.time_s:.6g} s — the integration is not trustworthy; "
                      f"then: {status.kind}: {status.detail}")

    def _stop(self, status: Status) -> Status | None:
        if status.kind in self.stop_on and self.status is None:
            status = self.annotate(status)
            self.events.append(status)
            self.status = status
            return status
        key = (status.kind, status.wheelset, status.side)
        if key not in self._reported:            # a non-stopping kind: reported once per wheel
            self._reported.add(key)
            self.events.append(status)
        return None

    def _evaluate(self, mbs, t: float):
        """The contact at the model's current state, time ``t`` of that state (as
        :meth:`~exudyn_wheelrail.multibody.connector.WheelRailContact.evaluate_state`: the warm start is kept, and an explicit step's first stage,
        at this same state, reuses the evaluation); returns the connector's coordinates and velocities.  The coordinates come from the system vectors (two Exudyn calls for any number of nodes)."""
        c = self.contact
        if self._system is None or self._system[0] is not mbs:
            import exudyn as exu
            sd = mbs.systemData
            self._system = (mbs, sd.GetODE2Coordinates, sd.GetODE2Coordinates_t, exu.ConfigurationType.Current,
                            np.asarray(sd.GetObjectLTGODE2(c.object), dtype=np.int64))
        _, coordinates, velocities, current, ltg = self._system
        q = coordinates(current, False)[ltg]           # (configuration, copy): a view of the system vector, indexed
        v = velocities(current, False)[ltg]
        c.evaluate_state(q, v, t)       # kept for the solver's next force call if it is at this very state
        return q, v

    def check(self, mbs, t: float) -> Status | None:
        """Evaluate the contact at the model's current state (``t`` = the time of that state), update the records and
        return the stopping :class:`Status`, or None.  The per-state work is one compiled call
        (:func:`.monitor_core.monitor_state`); Python builds events only when that call reports one."""
        if self.status is not None:
            return self.status
        self.n_checks += 1
        self.t_last = float(t)
        if self.time_limit_s is not None and self._wall0 is not None and \
                time.perf_counter() - self._wall0 > self.time_limit_s:
            return self._stop(Status("time_limit", t, None, None,
                                     f"wall-clock limit of {self.time_limit_s:g} s reached"))
        c = self.contact
        try:
            q, v = self._evaluate(mbs, float(t))
        except C.ContactStateError as err:
            st = status_from_state_error(err, t)
            return self._stop(st)
        row = -1
        if self.keep_history:
            if self._hist_n >= self._hist.shape[0]:
                self._grow_history(max(256, 2 * self._hist.shape[0]))
            row = self._hist_n
            self._hist_n += 1
        if self._pose_arrays is not None:
            poses = self._poses
            MC.rail_poses(*self._pose_arrays, poses)
        else:
            poses = c.wheelset_rail_pose()
        code = self._monitor_state(float(t), c.results, self._out, poses, q, v, *self._records, self._hist, row)
        if code:
            self._events_of_state(t, q, v)
        if self.n_checks == 1 and self._inertia is not None and self.status is None:
            self._creep_stability(t, q)
        return self.status

    # -- the same checks in the compiled force call (:mod:`.watch`) ----------------------------------------------
    def unwatchable(self) -> str | None:
        """Why this monitor's per-state work cannot run in the compiled force call (:mod:`.watch`), or None."""
        if self.time_limit_s is not None:
            return "a wall-clock limit"
        if self._pose_arrays is None:
            return "a contact without pose arrays"
        return None

    def watch_arrays(self) -> tuple:
        """``(out, side_poses, half_gauge, poses, records, hist)``: the arrays the compiled check of a state takes
        (:func:`.monitor_core.monitor_state`), the same objects the Python path passes."""
        return (self._out, *self._pose_arrays, self._poses, self._records, self._hist)

    @property
    def history_rows(self) -> int:
        """Rows of the history so far."""
        return self._hist_n

    def reserve_history(self, states: int) -> None:
        """Room for ``states`` more rows of the history (kept: no row is added by growing it while it is watched)."""
        if self.keep_history and self._hist.shape[0] < self._hist_n + states:
            self._grow_history(self._hist_n + states)

    def _grow_history(self, rows: int) -> None:
        """The history array with ``rows`` rows, its rows so far kept."""
        grown = np.zeros((rows, self._hist.shape[1]))
        grown[:self._hist_n] = self._hist[:self._hist_n]
        self._hist = grown

    def take_watched(self, n_checks: int, t_last: float, hist_rows: int) -> None:
        """The counters after states checked in the compiled force call."""
        self.n_checks, self.t_last, self._hist_n = int(n_checks), float(t_last), int(hist_rows)

    def events_of_state(self, t: float, q, v) -> Status | None:
        """The events of a state the compiled call checked and marked (as :meth:`check` builds them; the records
        still hold that state); returns the stopping status, or None."""
        self._events_of_state(t, q, v)
        return self.status

    def _events_of_state(self, t, q, v):
        """What the compiled call reported for this state, in the order of the checks: implausible velocities, the
        stability estimate, per wheel the invalid states, derailment and the intervals that start or end, then
        hunting."""
        wss = self._wss
        ws_flags = [int(f) for f in wss[:, MC.WS_FLAGS]]
        for k, f in enumerate(ws_flags):
            if f & MC.WSF_VELOCITY:
                vy, vz = abs(v[6 * k + 1]), abs(v[6 * k + 2])
                wx, wz = abs(v[6 * k + 3]), abs(v[6 * k + 5])
                self._stop(Status(
                    "invalid_state", t, k, None, f"wheelset velocity (lateral {vy:.3g}, vertical {vz:.3g} m/s) or "
                    f"roll/yaw rate ({wx:.3g}, {wz:.3g} rad/s) beyond the plausible {self.max_speed_m_s:g} m/s / "
                    f"{self.max_rate_rad_s:g} rad/s — the integration diverged (time step beyond the stability "
                    "limit?)"))
        for k, f in enumerate(ws_flags):
            if f & MC.WSF_STABILITY:
                self._stability_exact(t, k, q)
        for w in range(2 * self.n_wheelsets):
            f = int(self._wflag[w])
            if not f & ((1 << MC.WF_REASONS_SHIFT) - 1):
                continue
            k, side = w // 2, SIDES[w % 2]
            wq = self._wq[w]
            N, Y, Q = float(wq[MC.WQ_N]), float(wq[MC.WQ_Y]), float(wq[MC.WQ_Q])
            depth, gamma, c_y = float(wq[MC.WQ_DEPTH]), float(wq[MC.WQ_GAMMA]), float(wq[MC.WQ_CY])
            if f & MC.WF_NON_FINITE:
                self._stop(Status("invalid_state", t, k, side, "non-finite contact results for a finite state"))
            # ---- invalid: a penetration no elastic contact has
            if f & MC.WF_PENETRATION:
                self._stop(Status(
                    "invalid_state", t, k, side, f"penetration {depth * 1e3:.3g} mm > "
                    f"{self.invalid_penetration_m * 1e3:g} mm (normal force {N / 1e3:.4g} kN): far outside "
                    "elastic contact — diverged integration (time step?) or a state outside the model"))
            # ---- derailment D1 (crown outside [flange tip, field end]) and D2 (flange tip above the rail top)
            if f & MC.WF_D1_TIP:
                self._stop(Status(
                    "derailment", t, k, side, f"flange tip {1e3 * (wq[MC.WQ_Y_TIP] - self.y_crown):.1f} mm beyond "
                    f"the rail crown towards the field side (lateral displacement relative to the rail "
                    f"{c_y * 1e3:.1f} mm, limit {self.derail_lateral_m * 1e3:.1f} mm at zero roll; normal force "
                    f"{N / 1e3:.3g} kN)"))
            elif f & MC.WF_D2_LIFTED:
                self._stop(Status(
                    "derailment", t, k, side, f"flange tip {1e3 * (self.z_crown - wq[MC.WQ_Z_TIP]):.1f} mm above the "
                    f"rail top: the wheel lifted by more than the flange height ({self.flange_height_m * 1e3:.1f} "
                    f"mm), the flange no longer overlaps the rail head (lateral displacement relative to the rail "
                    f"{c_y * 1e3:.1f} mm)"))
            elif f & MC.WF_D1_FIELD:
                self._stop(Status(
                    "derailment", t, k, side, f"field-side tread end {1e3 * (self.y_crown - wq[MC.WQ_Y_FIELD]):.1f} "
                    f"mm inside the rail crown (lateral displacement relative to the rail {c_y * 1e3:.1f} mm): the "
                    "wheel dropped off towards the track centre"))
            if f & MC.WF_D3:
                self._stop(Status(
                    "derailment", t, k, side, f"loaded flange contact at the end of the profile data with the wheel "
                    f"{c_y * 1e3:.1f} mm towards the field side (limit {self.profile_end_lateral_m * 1e3:.1f} mm)"))
            # ---- the intervals: flange climb, lift-off, deep penetration
            reasons = _reason_names(f >> MC.WF_REASONS_SHIFT)
            details = {MC.IV_FLANGE: f"contact angle {gamma:.3f} rad, Y {Y / 1e3:.3g} kN, Q {Q / 1e3:.3g} kN",
                       MC.IV_LIFT: "no normal force", MC.IV_DEEP: f"penetration {depth * 1e3:.3g} mm"}
            for kind, start_bit, end_bit in ((MC.IV_FLANGE, MC.WF_FLANGE_START, MC.WF_FLANGE_END),
                                             (MC.IV_LIFT, MC.WF_LIFT_START, MC.WF_LIFT_END),
                                             (MC.IV_DEEP, MC.WF_DEEP_START, MC.WF_DEEP_END)):
                if f & start_bit:
                    self._interval_starts(w, kind, t, reasons if kind == MC.IV_FLANGE else set(), details[kind])
                elif f & end_bit:
                    self._interval_ends(w, kind, t)
        # ---- hunting per wheelset (lateral displacement of the wheelset relative to the rails = c_y of its right
        # wheel)
        for k, f in enumerate(ws_flags):
            if f & MC.WSF_HUNTING and self.hunting[k] is None:
                ts, peaks = MC.hunting_rings_ordered(self._rings[k], int(wss[k, MC.WS_HUNT_COUNT]),
                                                     int(wss[k, MC.WS_HUNT_CROSSINGS]), self._need)
                freq = 0.5 / float(np.mean(np.diff(ts))) if len(ts) >= 2 else float("nan")
                amp = float(min(peaks))
                st = Status("hunting", t, k, None, f"lateral oscillation relative to the rails >= "
                            f"{amp * 1e3:.2f} mm in {self.hunting_cycles} consecutive cycles, {freq:.3g} Hz")
                self.hunting[k] = st
                self._stop(st)

    def _interval_starts(self, w, kind, t, reasons, detail):
        name, attr = next((n, a) for kd, n, a in _INTERVALS if kd == kind)
        k, side = w // 2, SIDES[w % 2]
        cur = Interval(t, None, t, float(self._iv[w, kind, MC.IVF_PEAK]), set(reasons))
        getattr(self._wheels[w], attr).append(cur)
        self._open[w][kind] = cur
        st = Status(name, t, k, side, detail + (f" ({', '.join(sorted(reasons))})" if reasons else ""))
        if name in self.stop_on and self.status is None:
            self._stop(st)
        else:
            self.events.append(st)

    def _interval_ends(self, w, kind, t):
        cur = self._open[w][kind]
        self._open[w][kind] = None
        if cur is None:
            return
        self._sync_interval(cur, w, kind)
        cur.end_s = t
        cur.last_s = t

    def _sync_interval(self, cur, w, kind):
        iv = self._iv[w, kind]
        cur.last_s = float(iv[MC.IVF_LAST])
        cur.peak = float(iv[MC.IVF_PEAK])
        cur.reasons = _reason_names(int(iv[MC.IVF_REASONS]))

    # -- results --------------------------------------------------------------------------------------------------
    @property
    def wheels(self) -> list[WheelRecord]:
        """Per wheel (2k right, 2k+1 left) what the monitor recorded so far (:class:`WheelRecord`)."""
        ext = self._ext
        for w, rec in enumerate(self._wheels):
            rec.max_lateral_m = float(ext[w, MC.EXT_MAX_LATERAL])
            rec.min_lateral_m = float(ext[w, MC.EXT_MIN_LATERAL])
            rec.max_normal_force_N = float(ext[w, MC.EXT_MAX_N])
            rec.max_abs_lateral_force_N = float(ext[w, MC.EXT_MAX_ABS_Y])
            rec.max_penetration_m = float(ext[w, MC.EXT_MAX_PENETRATION])
            rec.max_contact_angle_rad = float(ext[w, MC.EXT_MAX_ANGLE])
            rec.max_gap_m = float(ext[w, MC.EXT_MAX_GAP])
            for kind, cur in enumerate(self._open[w]):
                if cur is not None:
                    self._sync_interval(cur, w, kind)
        return self._wheels

    @property
    def max_omega_h(self) -> list[float]:
        """Per wheelset the largest omega h of the RK44 stability estimate (0 without it)."""
        return [float(x) for x in self._wss[:, MC.WS_MAX_OMEGA_H]]

    def history(self) -> dict:
        """Per checked state: ``time_s`` and per wheel ``(lateral_m, vertical_m, roll_rad, N, Y, gamma, delta)``
        arrays of shape (n_states, n_wheels) — pose relative to the rail (side frame), total normal force, lateral
        force Y (track frame), largest loaded contact angle (NaN: no contact), largest penetration."""
        if not self._hist_n:
            return {}
        a = self._hist[:self._hist_n].copy()
        n_w = 2 * self.n_wheelsets
        body = a[:, 1:].reshape(len(a), n_w, 7)
        names = ("lateral_m", "vertical_m", "roll_rad", "normal_force_N", "lateral_force_N", "contact_angle_rad",
                 "penetration_m")
        d = {"time_s": a[:, 0]}
        for i, name in enumerate(names):
            d[name] = body[:, :, i]
        return d

    def events_of(self, kind: str) -> list[Status]:
        return [e for e in self.events if e.kind == kind]

    def summary(self) -> str:
        lines = [str(self.status) if self.status else "running/completed (no stopping status)"]
        for rec in self.wheels:
            lines.append(
                f"wheelset {rec.wheelset} {rec.side}: lateral {rec.min_lateral_m * 1e3:.2f}.."
                f"{rec.max_lateral_m * 1e3:.2f} mm, max N {rec.max_normal_force_N / 1e3:.1f} kN, max |Y| "
                f"{rec.max_abs_lateral_force_N / 1e3:.1f} kN, max angle {rec.max_contact_angle_rad:.3f} rad, max "
                f"penetration {rec.max_penetration_m * 1e3:.3f} mm, lift-offs {len(rec.lift_offs)} "
                f"({rec.total_lift_s() * 1e3:.1f} ms, max gap {rec.max_gap_m * 1e3:.2f} mm), flange climbs "
                f"{len(rec.flange_climbs)}, deep penetrations {len(rec.deep_penetrations)}")
        return "\n".join(lines)
