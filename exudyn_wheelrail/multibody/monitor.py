"""Run monitor for a model with a :class:`~.connector.WheelRailContact`: flange climb, wheel lift-off, deep
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
previous call's time (the start time at the first call) — :meth:`.connector.WheelRailContact.evaluate`, which does
not change the warm start.  When a stopping status is found the function returns ``False``: Exudyn (1.13.6,
checked in ``tests/stress``) then still completes the step it was about to take and stops, so the solve ends one
step after the detected state, at ``mbs.systemData.GetTime()``.  :func:`run_monitored` wraps ``SolveDynamic``: it
catches :class:`~.connector.ContactStateError` (non-finite coordinates; Exudyn re-raises a user function's exception
with it as the ``__cause__``) and any other solver failure, checks the final state and returns ``(status, t_end)``.
Cost: one compiled contact evaluation plus Python bookkeeping per step, about 0.15–0.2 ms per step for one wheelset
(RK44 with the stability estimate; the plain RK44 step of that model costs about 0.07 ms).

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

* non-finite coordinates (:class:`~.connector.ContactStateError`, with its time and wheelset), or non-finite
  contact results for a finite state;
* a penetration above ``invalid_penetration_m`` (default 5 mm, 2.5 x the kernel's deep-penetration threshold: a
  Hertz force of tens of MN);
* a wheelset velocity (lateral or vertical, model frame) above ``max_speed_m_s`` (10 m/s) or a roll/yaw rate above
  ``max_rate_rad_s`` (20 rad/s) — reached by a diverging integration, not by a running wheelset;
* with RK44 (:func:`run_monitored` passes the step): the **stability estimate** — the highest natural frequency ω
  of each wheelset on its linearised contact stiffness (6x6: Σ dN/dδ g gᵀ over the loaded contacts, g = (n, r x n)
  with the rail normal n and the lever r from the axle centre, against the wheelset's mass and inertia) — exceeds
  RK44's limit ω h <= 2√2.  This alone is recorded as a ``step_size`` event (a short excursion may pass); every
  stopping status after it becomes ``invalid_state`` naming both ("the integration is not trustworthy; then: …"),
  so a diverged run is never reported as a derailment.  Creep damping is not in the estimate.

``time_limit``: the wall-clock limit ``time_limit_s`` was reached.  ``solver_failure``: ``SolveDynamic`` failed for
another reason (returned False, raised, or stopped early).  Completed runs end with ``completed`` — or ``hunting``
when hunting was detected (with a warning in the detail when the RK44 limit was exceeded on the way).  A run with
a derailment or invalid-state event that was not stopped (``stop_on`` without it) still ends with that status,
never with ``completed``.
"""
from __future__ import annotations

import math
import re
import time
from dataclasses import dataclass, field

import numpy as np

from ..analysis.safety import nadal_limit, prudhomme_limit_N
from ..contact import kernel as K
from ..contact import layout as L
from . import connector as C
from .rotations import rotation_from_vector

__all__ = ["Status", "Interval", "WheelRecord", "RunMonitor", "run_monitored", "STATUS_KINDS", "STOP_KINDS"]

#: every status kind; the first two are completed runs
STATUS_KINDS = ("completed", "hunting", "derailment", "invalid_state", "time_limit", "solver_failure")
#: kinds the monitor can stop a run for (``stop_on``)
STOP_KINDS = ("derailment", "invalid_state", "time_limit", "hunting", "flange_climb", "lift_off", "deep_penetration",
              "step_size")
SIDES = ("right", "left")          # wheel 2k right, 2k+1 left (the connector's order)


@dataclass(frozen=True)
class Status:
    """Outcome of a run or an event: ``kind`` (:data:`STATUS_KINDS`, or an event kind), the time of the state
    [s], the wheelset index and side (``"right"``/``"left"``) where it applies, and a readable detail."""

    kind: str
    time_s: float | None
    wheelset: int | None = None
    side: str | None = None
    detail: str = ""

    @property
    def completed(self) -> bool:
        """The run reached its end time (``completed`` or ``hunting``)."""
        return self.kind in ("completed", "hunting")

    def __str__(self) -> str:
        where = "" if self.wheelset is None else f" wheelset {self.wheelset}" + (f" {self.side}" if self.side else "")
        when = "" if self.time_s is None else f" at t = {self.time_s:.6g} s"
        return f"{self.kind}{where}{when}" + (f": {self.detail}" if self.detail else "")


@dataclass
class Interval:
    """A period of a per-wheel condition: from the first state with it to the first state without it (``end_s``
    None while it lasts; :meth:`duration_s` then counts to the last checked state)."""

    start_s: float
    end_s: float | None = None
    last_s: float = 0.0                 # last state checked inside the interval
    peak: float = 0.0                   # the interval's extreme value (gap for lift-off, depth for penetration)
    reasons: set = field(default_factory=set)

    def duration_s(self) -> float:
        return (self.end_s if self.end_s is not None else self.last_s) - self.start_s


@dataclass
class WheelRecord:
    """What the monitor recorded for one wheel (extremes over the checked states and the event intervals)."""

    wheelset: int
    side: str
    lift_offs: list = field(default_factory=list)
    flange_climbs: list = field(default_factory=list)
    deep_penetrations: list = field(default_factory=list)
    max_contact_angle_rad: float = -math.inf   # of the loaded contacts
    max_normal_force_N: float = 0.0            # sum over the wheel's contacts
    max_abs_lateral_force_N: float = 0.0       # |Y| of the wheel (track frame, all contacts)
    max_penetration_m: float = 0.0
    max_gap_m: float = 0.0                     # largest gap while lifted
    max_lateral_m: float = -math.inf           # c_y, towards the field side, relative to the rail
    min_lateral_m: float = math.inf

    def total_lift_s(self) -> float:
        return sum(i.duration_s() for i in self.lift_offs)


_STATE_ERROR = re.compile(r"t = ([-+0-9.eEinfa]+) s: wheelset (\d+)")
_STATE_ERROR_T = re.compile(r"t = ([-+0-9.eEinfa]+) s")


def _contact_state_error(exc: BaseException):
    """The ContactStateError in an exception's chain (Exudyn re-raises a user function's exception with it as the
    cause), or None."""
    seen = set()
    e = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, C.ContactStateError):
            return e
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return None


def _status_from_state_error(err: C.ContactStateError, fallback_t: float | None) -> Status:
    msg = str(err).splitlines()[0]
    m = _STATE_ERROR.search(msg)
    wheelset = int(m.group(2)) if m else None
    mt = _STATE_ERROR_T.search(msg)
    try:
        t = float(mt.group(1)) if mt else fallback_t
    except ValueError:
        t = fallback_t
    return Status("invalid_state", t, wheelset, None, f"ContactStateError: {msg}")


class _Hunting:
    """Consecutive half-cycles of the lateral displacement about the centre with peaks >= amplitude."""

    def __init__(self, amplitude_m: float, cycles: int):
        self.a = amplitude_m
        self.need = 2 * cycles
        self.sign = 0
        self.peak = 0.0
        self.count = 0
        self.crossings: list[float] = []
        self.peaks: list[float] = []

    def update(self, t: float, y: float) -> tuple[float, float] | None:
        """Returns (amplitude, frequency) when the count is reached (every time after), else None."""
        s = 1 if y > 0.0 else (-1 if y < 0.0 else 0)
        if s == 0:
            return None
        if self.sign == 0:
            self.sign = s
        if s != self.sign:
            if self.peak >= self.a:
                self.count += 1
                self.crossings.append(t)
                self.peaks.append(self.peak)
            else:
                self.count = 0
                self.crossings = [t]
                self.peaks = []
            self.sign = s
            self.peak = 0.0
        self.peak = max(self.peak, abs(y))
        if self.count >= self.need and len(self.crossings) >= 3:
            ts = self.crossings[-self.need:]
            f = 0.5 / float(np.mean(np.diff(ts))) if len(ts) >= 2 else float("nan")
            return float(min(self.peaks[-self.need:])), f
        return None


def _wheel_rail_poses(contact) -> np.ndarray:
    """Per wheel (2k right, 2k+1 left) its pose relative to its rail in the side frame, ``(c_y, c_z, roll)``, from
    the contact's last evaluation (what the kernel solved for)."""
    ws = np.asarray(contact.wheelset_rail_pose(), dtype=float).reshape(-1, 3)
    poses = np.empty((2 * len(ws), 3))
    poses[0::2] = ws
    poses[1::2, 0] = -ws[:, 0]
    poses[1::2, 1] = ws[:, 1]
    poses[1::2, 2] = -ws[:, 2]
    return poses


#: a flange contact counts as beyond the flank where the profile's slope is this much below the flank's steepest
FLANK_ANGLE_DROP_RAD = 0.05
#: RK44's stability limit on the imaginary axis, |omega h| <= 2 sqrt(2)
RK44_LIMIT = 2.0 * math.sqrt(2.0)


def _wheelset_inertia(mbs, nodes):
    """Per wheelset node: (mass, inverse square root of the 3x3 body inertia) of the ObjectRigidBody on it, or None
    when there is none."""
    found = {}
    for i in range(mbs.systemData.NumberOfObjects()):
        d = mbs.GetObject(i)
        if d.get("objectType") == "RigidBody" and int(d.get("nodeNumber", -1)) in [int(n) for n in nodes]:
            J = np.asarray(d["inertia"], dtype=float)      # Ixx, Iyy, Izz, Iyz, Ixz, Ixy
            I3 = np.array([[J[0], J[5], J[4]], [J[5], J[1], J[3]], [J[4], J[3], J[2]]])
            ev, U = np.linalg.eigh(I3)
            found[int(d["nodeNumber"])] = (float(d["mass"]), U @ np.diag(1.0 / np.sqrt(ev)) @ U.T)
    return [found.get(int(n)) for n in nodes]


class RunMonitor:
    """Per-step checks of a model with a :class:`~.connector.WheelRailContact` (module docstring).

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
        if not all(hasattr(contact, a) for a in ("evaluate", "kernel_output", "wheelset_rail_pose")):
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
        self.wheels = [WheelRecord(w // 2, SIDES[w % 2]) for w in range(2 * n_ws)]
        self._hunt = [_Hunting(self.hunting_amplitude_m, hunting_cycles) for _ in range(n_ws)]
        self.hunting: list = [None] * n_ws       # per wheelset: Status of the first detection
        self.events: list[Status] = []           # every event in order (the start of each interval)
        self.status: Status | None = None        # the stopping status (None while running / completed)
        self.n_checks = 0
        self.t_last: float | None = None
        self._t_prev = 0.0
        self._wall0 = None
        self._user = None
        self._hist: list = []
        self._reported: set = set()
        self.rk44_step_s = None
        self._inertia = None
        self._R = np.empty((3, 3))
        self._Mh = np.zeros((6, 6))
        #: per wheelset: the largest omega h of the RK44 stability estimate (0 without it)
        self.max_omega_h = [0.0] * n_ws
        #: the first ``step_size`` event (the RK44 stability limit exceeded), or None
        self.stability_exceeded: Status | None = None
        #: Nadal's limit Y/Q at the flank (the contact's friction coefficient), for reference
        self.nadal_limit = (nadal_limit(self.flank_angle_rad, float(contact.cp[L.CP_MU]))
                            if math.isfinite(self.flank_angle_rad) else float("nan"))

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
    def attach(self, mbs, user_function=None, t_start_s: float = 0.0, rk44_step_s: float | None = None):
        """Install :meth:`pre_step` as the pre-step user function of ``mbs``, followed by ``user_function(mbs, t)``
        if given (Exudyn's arguments; it must return a bool; the contact's results are then those of the checked
        state); ``t_start_s`` is the time of the initial state.  Starts the wall clock of ``time_limit_s``.
        ``rk44_step_s``: the step of an RK44 solve — enables the stability estimate (module docstring;
        :func:`run_monitored` sets it)."""
        self._user = user_function
        self._t_prev = float(t_start_s)
        self._wall0 = time.perf_counter()
        self.rk44_step_s = None if rk44_step_s is None else float(rk44_step_s)
        self._inertia = _wheelset_inertia(mbs, self.contact.nodes_exu) if self.rk44_step_s else None
        mbs.SetPreStepUserFunction(self.pre_step)
        self._attached_to = mbs
        return self

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

    def check(self, mbs, t: float) -> Status | None:
        """Evaluate the contact at the model's current state (``t`` = the time of that state), update the records and
        return the stopping :class:`Status`, or None."""
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
            res = c.evaluate(mbs, t)
        except C.ContactStateError as err:
            st = _status_from_state_error(err, t)
            return self._stop(st)
        # kinematic plausibility: wheelset velocities (lateral, vertical, moving frame) and roll/yaw rates (body
        # frame x, z; y is the spin) — exceeded only by a diverging integration
        q, v = c.coordinates(mbs)
        for k in range(self.n_wheelsets):
            vy, vz = abs(v[6 * k + 1]), abs(v[6 * k + 2])
            wx, wz = abs(v[6 * k + 3]), abs(v[6 * k + 5])
            if max(vy, vz) > self.max_speed_m_s or max(wx, wz) > self.max_rate_rad_s:
                self._stop(Status(
                    "invalid_state", t, k, None, f"wheelset velocity (lateral {vy:.3g}, vertical {vz:.3g} m/s) or "
                    f"roll/yaw rate ({wx:.3g}, {wz:.3g} rad/s) beyond the plausible {self.max_speed_m_s:g} m/s / "
                    f"{self.max_rate_rad_s:g} rad/s — the integration diverged (time step beyond the stability "
                    "limit?)"))
        out = c.kernel_output()        # kernel output of the same evaluation (wheel parameter of the contacts)
        if self._inertia is not None:
            self._stability(t, q, out, res)
        poses = _wheel_rail_poses(c)   # (2n, 3) wheel pose relative to its rail, side frame (of this evaluation)
        n_w = 2 * self.n_wheelsets
        loaded = (res[:, :, L.RES_STATUS] > 0) & (res[:, :, L.RES_N] > 0.0)           # (n_wheels, slots)
        any_loaded = loaded.any(axis=1)
        N = np.where(loaded, res[:, :, L.RES_N], 0.0).sum(axis=1)
        Y = res[:, :, L.RES_F_TRACK_Y].sum(axis=1)
        Q = -res[:, :, L.RES_F_TRACK_Z].sum(axis=1)
        Y_flange = np.where(loaded[:, L.SLOT_FLANGE], res[:, L.SLOT_FLANGE, L.RES_F_TRACK_Y], 0.0)
        depth = np.where(loaded, res[:, :, L.RES_DELTA], 0.0).max(axis=1)
        gamma = np.where(any_loaded, np.where(loaded, res[:, :, L.RES_GAMMA], -np.inf).max(axis=1), np.nan)
        deep = (loaded & ((res[:, :, L.RES_FLAGS].astype(np.int64) & K.FLAG_DEEP_PENETRATION) != 0)).any(axis=1)
        prof_end = (res[:, L.SLOT_FLANGE, L.RES_FLAGS].astype(np.int64) & K.FLAG_PROFILE_END) != 0
        pen = np.where(np.isfinite(out[:, :, L.F_PENETRATION]), out[:, :, L.F_PENETRATION], -np.inf)
        gap = -pen.max(axis=1)                      # smallest wheel-rail distance of the separated regions
        s_flange = out[:, L.SLOT_FLANGE, L.F_S_WHEEL]
        cols = [L.RES_N, L.RES_F_TRACK_X, L.RES_F_TRACK_Y, L.RES_F_TRACK_Z, L.RES_GAMMA, L.RES_DELTA, L.RES_P_Y,
                L.RES_P_Z]
        finite = np.all(np.isfinite(np.where(loaded[:, :, None], res[:, :, cols], 0.0)), axis=(1, 2)) & \
            np.all(np.isfinite(poses), axis=1)
        N, Y, Q, Y_flange, depth, gamma, gap = (a.tolist() for a in (N, Y, Q, Y_flange, depth, gamma, gap))
        hist_row = []
        for w in range(n_w):
            k, side = w // 2, SIDES[w % 2]
            rec = self.wheels[w]
            if not finite[w]:
                self._stop(Status("invalid_state", t, k, side, "non-finite contact results for a finite state"))
            c_y, c_z, roll = poses[w].tolist()
            rec.max_lateral_m = max(rec.max_lateral_m, c_y)
            rec.min_lateral_m = min(rec.min_lateral_m, c_y)
            rec.max_normal_force_N = max(rec.max_normal_force_N, N[w])
            rec.max_abs_lateral_force_N = max(rec.max_abs_lateral_force_N, abs(Y[w]))
            rec.max_penetration_m = max(rec.max_penetration_m, depth[w])
            if any_loaded[w]:
                rec.max_contact_angle_rad = max(rec.max_contact_angle_rad, gamma[w])
            # ---- invalid: a penetration no elastic contact has
            if depth[w] > self.invalid_penetration_m:
                self._stop(Status(
                    "invalid_state", t, k, side, f"penetration {depth[w] * 1e3:.3g} mm > "
                    f"{self.invalid_penetration_m * 1e3:g} mm (normal force {N[w] / 1e3:.4g} kN): far outside "
                    "elastic contact — diverged integration (time step?) or a state outside the model"))
            # ---- derailment D1 (crown outside [flange tip, field end]) and D2 (flange tip above the rail top)
            cr, sr = math.cos(roll), math.sin(roll)
            y_tip = c_y + cr * self.tip[0] - sr * self.tip[1]
            z_tip = c_z + sr * self.tip[0] + cr * self.tip[1]
            y_field = c_y + cr * self.field_end[0] - sr * self.field_end[1]
            if y_tip >= self.y_crown:
                self._stop(Status(
                    "derailment", t, k, side, f"flange tip {1e3 * (y_tip - self.y_crown):.1f} mm beyond the rail crown "
                    f"towards the field side (lateral displacement relative to the rail {c_y * 1e3:.1f} mm, limit "
                    f"{self.derail_lateral_m * 1e3:.1f} mm at zero roll; normal force {N[w] / 1e3:.3g} kN)"))
            elif self.flanged and z_tip < self.z_crown:
                self._stop(Status(
                    "derailment", t, k, side, f"flange tip {1e3 * (self.z_crown - z_tip):.1f} mm above the rail top: "
                    f"the wheel lifted by more than the flange height ({self.flange_height_m * 1e3:.1f} mm), the "
                    f"flange no longer overlaps the rail head (lateral displacement relative to the rail "
                    f"{c_y * 1e3:.1f} mm)"))
            elif y_field <= self.y_crown:
                self._stop(Status(
                    "derailment", t, k, side, f"field-side tread end {1e3 * (self.y_crown - y_field):.1f} mm inside "
                    f"the rail crown (lateral displacement relative to the rail {c_y * 1e3:.1f} mm): the wheel dropped "
                    "off towards the track centre"))
            # ---- flange climb indications
            reasons = set()
            if loaded[w, L.SLOT_FLANGE]:
                if s_flange[w] < self.s_flank:
                    reasons.add("beyond_flank")
                if prof_end[w]:
                    reasons.add("profile_end")
                    if c_y >= self.profile_end_lateral_m:
                        self._stop(Status(
                            "derailment", t, k, side, f"loaded flange contact at the end of the profile data with "
                            f"the wheel {c_y * 1e3:.1f} mm towards the field side (limit "
                            f"{self.profile_end_lateral_m * 1e3:.1f} mm)"))
            other = w + 1 if w % 2 == 0 else w - 1
            if N[other] <= self.lift_force_N and Y_flange[w] != 0.0:
                limit = self.large_lateral_force_N
                if limit is None:           # Prud'homme, with the wheelset's instantaneous axle load
                    P = Q[w] + Q[other]
                    limit = prudhomme_limit_N(static_axle_load_N=P) if P > 0.0 else 10e3
                if abs(Y_flange[w]) > limit:
                    reasons.add("other_wheel_lifted")
            if reasons or (rec.flange_climbs and rec.flange_climbs[-1].end_s is None):
                self._interval(rec.flange_climbs, bool(reasons), t, gamma[w] if reasons else 0.0, "flange_climb", k,
                               side, reasons, f"contact angle {gamma[w]:.3f} rad, Y {Y[w] / 1e3:.3g} kN, "
                                              f"Q {Q[w] / 1e3:.3g} kN")
            # ---- lift-off
            lifted = N[w] <= self.lift_force_N
            if lifted:
                rec.max_gap_m = max(rec.max_gap_m, gap[w])
            self._interval(rec.lift_offs, lifted, t, gap[w] if lifted else 0.0, "lift_off", k, side, None,
                           "no normal force")
            # ---- deep penetration flag
            if deep[w] or (rec.deep_penetrations and rec.deep_penetrations[-1].end_s is None):
                self._interval(rec.deep_penetrations, bool(deep[w]), t, depth[w], "deep_penetration", k, side, None,
                               f"penetration {depth[w] * 1e3:.3g} mm")
            if self.keep_history:
                hist_row += [c_y, c_z, roll, N[w], Y[w], gamma[w], depth[w]]
        # ---- hunting per wheelset (lateral displacement of the wheelset relative to the rails = c_y of its right
        # wheel)
        for k in range(self.n_wheelsets):
            h = self._hunt[k].update(t, float(poses[2 * k, 0]))
            if h is not None and self.hunting[k] is None:
                st = Status("hunting", t, k, None, f"lateral oscillation relative to the rails >= "
                            f"{h[0] * 1e3:.2f} mm in {self.hunting_cycles} consecutive cycles, {h[1]:.3g} Hz")
                self.hunting[k] = st
                self._stop(st)
        if self.keep_history:
            self._hist.append([t] + hist_row)
        return self.status

    def _interval(self, intervals, active, t, value, kind, k, side, reasons, detail):
        cur = intervals[-1] if intervals and intervals[-1].end_s is None else None
        if active:
            if cur is None:
                cur = Interval(t, None, t, value)
                intervals.append(cur)
                if kind in self.stop_on and self.status is None:
                    self._stop(Status(kind, t, k, side, detail + (f" ({', '.join(sorted(reasons))})" if reasons
                                                                   else "")))
                else:
                    self.events.append(Status(kind, t, k, side, detail + (
                        f" ({', '.join(sorted(reasons))})" if reasons else "")))
            cur.last_s = t
            cur.peak = max(cur.peak, value) if math.isfinite(value) else cur.peak
            if reasons:
                cur.reasons |= reasons
        elif cur is not None:
            cur.end_s = t
            cur.last_s = t

    def _stability(self, t, q, out, res):
        """RK44 stability estimate: the highest frequency of each wheelset on its linearised contact stiffness."""
        h = self.rk44_step_s
        R = self._R
        Mh = self._Mh
        for k in range(self.n_wheelsets):
            inertia = self._inertia[k]
            if inertia is None:
                continue
            mass, I_inv_sqrt = inertia
            rows = []
            cx, cy, cz = (float(self.contact.p_ref[k, i] + q[6 * k + i]) for i in range(3))
            for side in range(2):
                w = 2 * k + side
                mirror = 1.0 if side == 0 else -1.0
                for j in range(out.shape[1]):
                    if not (res[w, j, L.RES_STATUS] > 0 and res[w, j, L.RES_N] > 0.0):
                        continue
                    ny = mirror * out[w, j, L.F_NR_Y]
                    nz = out[w, j, L.F_NR_Z]
                    rx = res[w, j, L.RES_P_X] - cx
                    ry = res[w, j, L.RES_P_Y] - cy
                    rz = res[w, j, L.RES_P_Z] - cz
                    sk = math.sqrt(max(out[w, j, L.F_DN_DDELTA], 0.0))
                    # sqrt(k) (n, r x n), n = (0, ny, nz)
                    rows.append((0.0, sk * ny, sk * nz, sk * (ry * nz - rz * ny), -sk * rx * nz, sk * rx * ny))
            if not rows:
                continue
            G = np.array(rows)
            rotation_from_vector(q[6 * k + 3], q[6 * k + 4], q[6 * k + 5], R)
            Mh[:3, :3] = np.eye(3) / math.sqrt(mass)
            Mh[3:, 3:] = R @ I_inv_sqrt @ R.T              # (R I R^T)^(-1/2)
            A = G @ Mh                                     # K = G^T G: eigenvalues of Mh K Mh = those of A A^T
            lam = float(np.linalg.eigvalsh(A @ A.T)[-1]) if len(rows) > 1 else float(A[0] @ A[0])
            wh = math.sqrt(max(lam, 0.0)) * h
            self.max_omega_h[k] = max(self.max_omega_h[k], wh)
            if wh > RK44_LIMIT and self.stability_exceeded is None:
                st = Status("step_size", t, k, None, f"time step {h:.4g} s beyond the RK44 stability limit of the "
                            f"contact stiffness (omega h = {wh:.3g} > {RK44_LIMIT:.3f}, omega = {wh / h:.4g} rad/s: "
                            f"stable below {RK44_LIMIT / (wh / h):.3g} s)")
                self.stability_exceeded = st
                self._stop(st)

    # -- results --------------------------------------------------------------------------------------------------
    def history(self) -> dict:
        """Per checked state: ``time_s`` and per wheel ``(lateral_m, vertical_m, roll_rad, N, Y, gamma, delta)``
        arrays of shape (n_states, n_wheels) — pose relative to the rail (side frame), total normal force, lateral
        force Y (track frame), largest loaded contact angle (NaN: no contact), largest penetration."""
        if not self._hist:
            return {}
        a = np.array(self._hist, dtype=float)
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


def _solver_type(solver):
    import exudyn as exu
    if solver is None:
        return exu.DynamicSolverType.GeneralizedAlpha
    if isinstance(solver, str):
        key = solver.lower()
        if key in ("rk44", "rk4"):
            return exu.DynamicSolverType.RK44
        if key in ("newmark", "generalizedalpha", "generalized_alpha", "implicit"):
            return exu.DynamicSolverType.GeneralizedAlpha
        raise ValueError(f"solver {solver!r}: expected 'rk44', 'newmark' or an exudyn.DynamicSolverType")
    return solver


def run_monitored(mbs, sim, solver=None, monitor: RunMonitor | None = None) -> tuple[Status, float]:
    """``mbs.SolveDynamic(sim, solverType=solver)`` under ``monitor`` (attached here unless the caller attached it
    to ``mbs``, whose chained function is then kept; ``mbs`` assembled) through
    the one solve wrapper, :func:`exudyn_wheelrail.simulation.runner.solve`.  Returns ``(status, t_end)``: the
    monitor's stopping status, an ``invalid_state`` from a :class:`~.connector.ContactStateError` (its time and
    wheelset), a ``solver_failure``, or — after a check of the final state — ``completed`` / ``hunting``; ``t_end``
    is the time the solver reached."""
    if monitor is None:
        raise ValueError("run_monitored needs a RunMonitor")
    import exudyn as exu

    from ..simulation.runner import solve
    from ..simulation.settings import SOLVER_TYPES
    solver = _solver_type(solver)
    name = next((k for k, v in SOLVER_TYPES.items() if getattr(exu.DynamicSolverType, v) == solver), "newmark")
    n_steps = max(1, int(sim.timeIntegration.numberOfSteps))
    dt = (float(sim.timeIntegration.endTime) - float(sim.timeIntegration.startTime)) / n_steps
    attached = getattr(monitor, "_attached_to", None) is mbs          # keep the caller's attachment and function
    outcome = solve(mbs, sim, solver, monitor, dt_s=dt, solver=name, attach_monitor=not attached,
                    user_function=monitor._user if attached else None)
    return outcome.stop, outcome.t_end_s
