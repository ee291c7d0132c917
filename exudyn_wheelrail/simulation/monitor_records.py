"""The run monitor's statuses and records: the :class:`Status` of a run or an event (its kinds), the
:class:`Interval` of a per-wheel condition, the :class:`WheelRecord` of one wheel, and the status of a
:class:`~exudyn_wheelrail.multibody.connector.ContactStateError` (non-finite coordinates) found in an exception's
chain.  The checks that produce them: :mod:`.monitor`."""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from ..multibody import connector as C
from ..multibody.direct_call import NATIVE_STATE_ERROR_MARK, pending_state_error

__all__ = ["Status", "Interval", "WheelRecord", "STATUS_KINDS", "STOP_KINDS", "SIDES", "contact_state_error",
           "status_from_state_error"]

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


def contact_state_error(exc: BaseException):
    """The ContactStateError in an exception's chain (Exudyn re-raises a user function's exception with it as the
    cause), or the one of a bad state the connector's compiled call path met (Exudyn reports its native exception
    as a failed solve: :func:`~exudyn_wheelrail.multibody.direct_call.pending_state_error`), or None."""
    seen = set()
    e = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, C.ContactStateError):
            return e
        if NATIVE_STATE_ERROR_MARK in str(e):
            return pending_state_error(str(e))
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return None


def status_from_state_error(err: C.ContactStateError, fallback_t: float | None) -> Status:
    msg = str(err).splitlines()[0]
    m = _STATE_ERROR.search(msg)
    wheelset = int(m.group(2)) if m else None
    mt = _STATE_ERROR_T.search(msg)
    try:
        t = float(mt.group(1)) if mt else fallback_t
    except ValueError:
        t = fallback_t
    return Status("invalid_state", t, wheelset, None, f"ContactStateError: {msg}")
