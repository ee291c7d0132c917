"""How a run ends: the documented set of run statuses and the command line's exit codes.

Every run (:func:`~exudyn_wheelrail.simulation.runner.run`, hence ``rtri``, ``rtri-sweep``, ``run``, ``sweep``,
``explore``) is watched by the run monitor (:mod:`exudyn_wheelrail.simulation.monitor`) and ends with one of:

=================  =========  =====================================================================================
status             exit code  meaning
=================  =========  =====================================================================================
``ok``             0          the run reached its end time; every state passed the monitor's checks (hunting, lift-
                              offs and flange climbs that did not derail are reported as events and notes)
``derailed``       3          a wheel lost its guidance — with the time of the state, the wheelset (0 = leading)
                              and the wheel (``right``/``left``): the flange tip beyond the rail crown or lifted
                              above the rail top, a flange contact off the profile data (the monitor's D1–D3), or
                              the flange climbing under a derailment quotient that friction cannot hold: the
                              quotient Y/Q of the wheel averaged over 2 m of running above Nadal's limit of its
                              flange (:mod:`.guidance`)
``diverged``       4          the integration failed: a non-finite or physically impossible state (penetration,
                              wheelset speed), the solver failed (Newton did not converge, Exudyn raised), or a
                              derailment found while the time step does not integrate the wheel–rail contact
                              (RK44 beyond its stability limit ω h ≤ 2√2; another solver with ω h above that bound:
                              the contact oscillation is not resolved) — with a hint: the largest usable step from
                              the monitor's estimate of the stiffest contact frequency ω, or reduce ``dt_s`` for a
                              Newton failure
``step_rejected``  5          the implicit solver rejected steps and continued with reduced steps off the ``dt_s``
                              grid, so rows of the time series on that grid are missing: the run stops at the first
                              missing row (hint: reduce ``dt_s``)
=================  =========  =====================================================================================

Exit code 2: bad input (reported before any work starts, one line ``error: <option or key>: <problem>``); 1: any
other error.  A sweep exits with 1 if a case failed with an error, else with the largest exit code of its cases.

The monitor's own kinds (:data:`~exudyn_wheelrail.simulation.monitor_records.STATUS_KINDS`) map onto these
(:data:`MONITOR_KINDS`); its detail text is kept.  Time series keep the rows recorded up to the last valid state;
the peaks of a ``diverged`` run are not evaluated (no number of the diverged part is printed as a peak).
"""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["OK", "DERAILED", "DIVERGED", "STEP_REJECTED", "STATUSES", "EXIT_CODES", "EXIT_BAD_INPUT",
           "EXIT_ERROR", "MONITOR_KINDS", "RunStatus", "exit_code"]

OK = "ok"
DERAILED = "derailed"
DIVERGED = "diverged"
STEP_REJECTED = "step_rejected"
#: the run statuses, in the order of their exit codes
STATUSES = (OK, DERAILED, DIVERGED, STEP_REJECTED)
#: exit code of the command line per status
EXIT_CODES = {OK: 0, DERAILED: 3, DIVERGED: 4, STEP_REJECTED: 5}
#: exit code for bad input (before any work)
EXIT_BAD_INPUT = 2
#: exit code for any other error
EXIT_ERROR = 1
#: the monitor's stopping kinds -> run status (``time_limit``, a wall-clock limit, is not a run status: the pipeline
#: sets none; a run stopped by one is an error)
MONITOR_KINDS = {"completed": OK, "hunting": OK, "derailment": DERAILED, "invalid_state": DIVERGED,
                 "solver_failure": DIVERGED, "step_rejected": STEP_REJECTED}


@dataclass(frozen=True)
class RunStatus:
    """The end of a run: ``kind`` (:data:`STATUSES`), the time of the state [s], the wheelset (0 = leading) and
    wheel (``"right"``/``"left"``) where it applies, the monitor's detail and a hint what to change."""

    kind: str
    time_s: float | None = None
    wheelset: int | None = None
    side: str | None = None
    detail: str = ""
    hint: str = ""

    def __post_init__(self):
        if self.kind not in STATUSES:
            raise ValueError(f"kind = {self.kind!r}: expected one of {', '.join(STATUSES)}")

    @property
    def ok(self) -> bool:
        return self.kind == OK

    @property
    def exit_code(self) -> int:
        return EXIT_CODES[self.kind]

    def __str__(self) -> str:
        where = "" if self.wheelset is None else f" wheelset {self.wheelset}" + (f" {self.side}" if self.side else "")
        when = "" if self.time_s is None or self.kind == OK else f" at t = {self.time_s:.6g} s"
        text = f"{self.kind}{where}{when}" + (f": {self.detail}" if self.detail and self.kind != OK else "")
        return text + (f" (hint: {self.hint})" if self.hint else "")

    def as_dict(self) -> dict:
        return {"kind": self.kind, "time_s": self.time_s, "wheelset": self.wheelset, "side": self.side,
                "detail": self.detail, "hint": self.hint, "exit_code": self.exit_code}


def exit_code(kinds) -> int:
    """The exit code of runs ending with ``kinds`` (status kinds, or ``"error: ..."`` for a case that failed):
    :data:`EXIT_ERROR` if one failed, else the largest of theirs."""
    codes = [EXIT_CODES.get(k, EXIT_ERROR) for k in kinds]
    if EXIT_ERROR in codes:
        return EXIT_ERROR
    return max(codes, default=0)
