r"""The one solve wrapper: every run goes through :func:`solve` (:func:`run` for a :class:`~.settings.RunSettings`;
:func:`run_monitored` for a caller's own Exudyn settings).

>>> outcome = run(h.mbs, RunSettings(solver="rk44", duration_s=0.5), contact=h.contact, speed_m_s=V,
...               recorder=recorder)                                                    # doctest: +SKIP
>>> outcome.status.kind, outcome.status.hint, outcome.t_end_s                           # doctest: +SKIP

What a run does
---------------
:func:`solve` installs **one** Exudyn pre-step function.  Exudyn calls it before every step attempt with the time
at the *end* of that step while the state is still that of the last accepted step: a call whose end time is not
beyond the previous one is a retry after a rejected attempt (Newton did not converge; the state was rolled back).
For every new accepted state, in this order:

1. with ``grid_check``: a state that has passed a point of the ``dt_s`` grid without a state on it (the solver
   continued with reduced steps off the grid) stops the run: ``step_rejected``;
2. the run monitor's check (:meth:`~exudyn_wheelrail.simulation.monitor.RunMonitor.check`: derailment, invalid
   states, flange climb, lift-off, hunting; always on), then the flange-climb check of :mod:`.guidance`;
3. a stopping status returns False: Exudyn completes the step it was about to take and stops (the solve ends one
   step after the detected state); the detected state is not recorded;
4. the recorder (:mod:`.recorder`; the states on its grid, every ``record_every`` steps), then the progress bar.

The final state (after the last step, which Exudyn does not pass to the pre-step function) is checked and
recorded after the solve.

**The watch.**  On the connector's compiled call path with an explicit solver the states after the first are
checked in the compiled force call instead, on the first stage's own evaluation (:mod:`.watch`: the same checks,
the same numbers, no Python per step); the pre-step function then only builds the events of a state the watch
marked and stops the run for them (one step later than above: the solve ends two steps after the stopping state).
A run the watch cannot take (:func:`.watch.unwatchable`), or ``solve(..., watch=False)``, is checked as above.
:attr:`RunOutcome.watched_states` says how many states the watch checked.  Exceptions of ``SolveDynamic`` (Exudyn re-raises a user function's exception as
"Error in Python USER FUNCTION", the cause kept) and a solve that stops early are caught; the outcome is a
:class:`RunOutcome` whose :attr:`RunOutcome.status` is a :class:`~.status.RunStatus` (:mod:`.status`).

Contact frequency and time step
-------------------------------
Before the solve, :func:`contact_omega_rad_s` evaluates the monitor's estimate of the highest natural frequency
ω of each wheelset on its linearised contact stiffness at the initial state.  RK44 runs carry the estimate at
every state (the monitor's ``step_size`` event: ω h > 2√2, RK44's imaginary-axis limit in the solver table
:data:`~.solvers.METHODS`).  For the other solvers the same bound is the **resolution bound** of the contact oscillation: above
it the trapezoidal rule has fewer than about 3.3 steps per period of it (its discrete frequency
``2 atan(ω h/2)/h`` is 32 % low at ω h = 2√2) and a wheel lift or flange impact is integrated as nothing like the
contact's dynamics — a derailment found then is reported ``diverged``, not ``derailed``, with the step that
resolves it (:data:`~.solvers.RESOLUTION_LIMIT`).  Rows of a diverged RK44 run after its first ``step_size`` event are
dropped (the integration is unstable from that state on).  On a flexible track the same evaluation gives the creep
damping's decay rates with the rails' modal mass (:meth:`~exudyn_wheelrail.simulation.monitor.RunMonitor.
creep_decay_rate_1_s`): an RK44 step beyond σ h <= 2.785 is warned before the solve (an
:class:`~exudyn_wheelrail.validation.InputWarning` naming ``run.dt_s`` and the stable step; the command line
prints it as one line ``warning: ...``): the run would settle into a false steady lateral force (docs/track.md).
"""
from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import exudyn as exu

from ..contact.layout import RES_S_TRACK
from ..validation import InputWarning
from . import status as S
from .exudyn_settings import run_solver_settings
from .guidance import FlangeClimbCheck
from .monitor import RunMonitor
from .monitor_records import Status, contact_state_error, status_from_state_error
from .settings import RunSettings
from .solvers import METHODS, RESOLUTION_LIMIT, RK44
from .step_checks import check_explicit_step
from .watch import Watch, unwatchable

__all__ = ["RunOutcome", "solve", "run", "run_monitored", "contact_omega_rad_s"]

_SERIOUS = ("invalid_state", "derailment")


@dataclass
class RunOutcome:
    """What a run ended with.  ``stop``: the monitor-style :class:`~exudyn_wheelrail.simulation.monitor_records.Status`
    that ended it (``completed``/``hunting`` for a complete run); :attr:`status`: the run status."""

    stop: Status
    t_end_s: float
    t_goal_s: float
    dt_s: float
    solver: str
    solve_seconds: float
    events: list = field(default_factory=list)
    rejected_steps: int = 0
    rows_dropped: int = 0
    contact_omega_rad_s: list = field(default_factory=list)
    creep_rate_1_s: list = field(default_factory=list)
    max_omega_h: float = 0.0
    monitor: RunMonitor | None = None
    guidance: FlangeClimbCheck | None = None
    #: states checked in the compiled force call (:mod:`.watch`; 0: every state by the pre-step function)
    watched_states: int = 0

    @property
    def omega_rad_s(self) -> float:
        """The stiffest contact frequency of the initial state (:func:`contact_omega_rad_s`; RK44's running estimate
        when that is unknown) [rad/s]: what a time step must integrate for a normal run (a diverging state is
        stiffer still)."""
        return max(self.contact_omega_rad_s, default=0.0) or self.max_omega_h / self.dt_s

    @property
    def resolved(self) -> bool:
        """The time step resolves the contact frequency (:data:`~.solvers.RESOLUTION_LIMIT`; True when unknown)."""
        return not (self.omega_rad_s * self.dt_s > RESOLUTION_LIMIT)

    @property
    def status(self) -> S.RunStatus:
        return _classify(self)

    @property
    def warnings(self) -> list[str]:
        """What a completed run should say about its trustworthiness."""
        out = []
        m = self.monitor
        completed = self.stop.kind in ("completed", "hunting")
        if completed and m is not None and m.stability_exceeded is not None:
            out.append(f"{m.stability_exceeded} — the run completed, but the integration is at or beyond its stability limit")
        elif completed and self.solver != "rk44" and not self.resolved:
            out.append(f"the time step {self.dt_s:g} s does not resolve the wheel–rail contact oscillation (omega h "
                       f"= {self.omega_rad_s * self.dt_s:.3g} > {RESOLUTION_LIMIT:.3f}, omega = "
                       f"{self.omega_rad_s:.4g} rad/s): contact-force peaks are not converged in dt; "
                       f"dt_s <= {RESOLUTION_LIMIT / self.omega_rad_s:.3g} s resolves it")
        if self.rejected_steps:
            out.append(f"the solver rejected {self.rejected_steps} step attempt(s) (Newton did not converge) and "
                       "continued with reduced steps; rows are recorded on the dt_s grid only")
        return out


def _stable_step_hint(o: RunOutcome) -> str:
    w = o.omega_rad_s
    sigma = max(o.creep_rate_1_s, default=0.0)
    if o.solver == "rk44" and sigma > 0.0 and not (w > 0.0 and RK44.imaginary_axis_limit / w <= RK44.real_axis_limit / sigma):
        h = RK44.real_axis_limit / sigma
        return (f"the largest stable RK44 step is about {h:.3g} s (sigma h <= {RK44.real_axis_limit:.3f} with sigma = "
                f"{sigma:.4g} 1/s, the fastest decay rate of the creep damping, which grows as 1/V): use dt_s <= "
                f"{h:.3g} s, or the implicit solver newmark")
    if not w > 0.0:
        return f"reduce dt_s (now {o.dt_s:g} s)"
    h = RK44.imaginary_axis_limit / w
    if o.solver == "rk44":
        return (f"the largest stable RK44 step is about {h:.3g} s (omega h <= 2 sqrt 2 with omega = {w:.4g} rad/s, "
                f"the monitor's estimate of the stiffest wheel-rail contact mode): use dt_s <= {h:.3g} s, or the "
                f"implicit solver newmark")
    return (f"the wheel-rail contact oscillation (omega = {w:.4g} rad/s, the monitor's estimate) needs dt_s <= "
            f"{h:.3g} s (omega h <= 2 sqrt 2; now {o.dt_s:g} s)")


def _classify(o: RunOutcome) -> S.RunStatus:
    st = o.stop
    kind = S.MONITOR_KINDS.get(st.kind)
    if kind is None:
        raise RuntimeError(f"the run was stopped: {st}")
    args = dict(time_s=st.time_s, wheelset=st.wheelset, side=st.side, detail=st.detail)
    if kind == S.OK:
        detail = ("hunting: " + st.detail) if st.kind == "hunting" else st.detail
        return S.RunStatus(S.OK, time_s=o.t_end_s, detail=detail)
    if kind == S.DERAILED and o.solver != "rk44" and not o.resolved:
        return S.RunStatus(S.DIVERGED, **{**args, "detail": (
            f"derailment found with a time step that does not resolve the wheel-rail contact (omega h = "
            f"{o.omega_rad_s * o.dt_s:.3g} > {RESOLUTION_LIMIT:.3f}): not trustworthy; then: {st.detail}")},
            hint=_stable_step_hint(o))
    if kind == S.DIVERGED:
        newton = st.kind == "solver_failure" and o.solver in ("newmark", "generalized_alpha")
        hint = (f"Newton did not converge: reduce dt_s (e.g. to {o.dt_s / 2:g} s); "
                + _stable_step_hint(o)) if newton else _stable_step_hint(o)
        return S.RunStatus(S.DIVERGED, **args, hint=hint)
    if kind == S.STEP_REJECTED:
        return S.RunStatus(S.STEP_REJECTED, **args, hint=f"reduce dt_s (e.g. to {o.dt_s / 2:g} s) so that Newton "
                                                         "converges at every step")
    return S.RunStatus(kind, **args)


def contact_omega_rad_s(mbs, contact, t_s: float = 0.0) -> list[float]:
    """Per wheelset the highest natural frequency [rad/s] on its linearised contact stiffness at the current state
    (the run monitor's estimate, :class:`~exudyn_wheelrail.simulation.monitor.RunMonitor`; 0 for a wheelset
    without contact).  Installs a pre-step function: call before the run's own."""
    return _initial_estimates(mbs, contact, t_s)[0]


def _initial_estimates(mbs, contact, t_s: float = 0.0) -> tuple[list[float], list[float]]:
    """:func:`contact_omega_rad_s` and, from the same evaluation, per wheelset the fastest decay rate of the creep
    damping [1/s] (:meth:`~exudyn_wheelrail.simulation.monitor.RunMonitor.creep_decay_rate_1_s`)."""
    probe = RunMonitor(contact, stop_on=(), keep_history=False)
    probe.attach(mbs, t_start_s=t_s, rk44_dt_s=1.0)
    probe.check(mbs, t_s)
    return [float(w) for w in probe.max_omega_h], [float(r) for r in probe.creep_rate_1_s]


class _Hook:
    """The pre-step function (module docstring)."""

    def __init__(self, monitor, guidance, recorder, record_every, progress, dt_s, t0_s, grid_check, user_function,
                 watch=None):
        self.monitor, self.guidance, self.recorder, self.progress = monitor, guidance, recorder, progress
        self.user_function = user_function
        self.watch = watch                  # the states after the first are checked in the compiled force call
        self.every = int(record_every)
        self.dt = float(dt_s)
        self.t_tol = 1e-9 * self.dt         # a new step attempt ends more than this after the previous one
        self.t0 = float(t0_s)
        self.grid_check = grid_check
        self.t_pending = self.t0            # end time of the step attempted after the previous call
        self.t_state = None                 # time of the last state handled
        self.k_next = 0                     # next dt-grid index expected
        self.rejected = 0
        self.stop: Status | None = None     # a stop found here (step_rejected, flange climb)
        self.error = None
        self.last_recorded = None

    def __call__(self, mbs, t):
        t = float(t)
        if self.watch is not None and self.t_state is not None:
            return self.watched()
        if self.t_state is None or t > self.t_pending + self.t_tol:
            t_state = self.t_pending        # the previous attempt was accepted (or this is the first call)
        else:
            self.rejected += 1              # a retry: the state is the one already handled
            self.t_pending = t
            return self.stop is None and (self.monitor is None or self.monitor.status is None)
        self.t_pending = t
        try:
            go = self.state(mbs, t_state)
            if go and self.user_function is not None:   # the contact's results are those of the checked state
                go = bool(self.user_function(mbs, t))
            if self.watch is not None:
                self.watch.first_state_done(t_state, go)
            return go
        except Exception as exc:            # a failing probe must not hide inside Exudyn's error
            self.error = exc
            return False

    def watched(self, finish: bool = False) -> bool:
        """With the watch: the state it marked for Python, if any (:meth:`.watch.Watch.handle`; after the solve
        ``finish``: :meth:`.watch.Watch.finish`), the progress bar; False: stop."""
        w = self.watch
        try:
            st = w.finish() if finish else (w.handle() if w.pending else None)
        except Exception as exc:            # as a failing probe: not hidden inside Exudyn's error
            self.error = exc
            return False
        if st is not None and self.monitor.status is None:
            self.stop = st                  # the flange-climb window's (the monitor keeps its own)
        if self.t_state is None or w.t_checked > self.t_state:
            self.t_state = w.t_checked
        if self.progress is not None and self.t_state is not None:
            self.progress.update(self.t_state)
        return st is None

    def state(self, mbs, t_state: float) -> bool:
        """Handle a new accepted state; False: stop."""
        self.t_state = t_state
        if self.stop is not None or (self.monitor is not None and self.monitor.status is not None):
            return False
        k = (t_state - self.t0) / self.dt
        k_grid = int(round(k))
        on_grid = abs(k - k_grid) <= 1e-6
        if self.grid_check and not on_grid and k > self.k_next + 1e-6:
            t_miss = self.t0 + self.k_next * self.dt
            self.stop = Status("step_rejected", t_miss, None, None,
                               f"the solver rejected {self.rejected} step attempt(s) (Newton did not converge at "
                               f"dt_s = {self.dt:g} s) and continued with reduced steps off the dt_s grid: no state "
                               f"at t = {t_miss:.6g} s (the state after it is at {t_state:.6g} s); the rows end at "
                               f"the last state on the grid")
            return False
        if on_grid:
            self.k_next = k_grid + 1
        if self.monitor is not None:
            st = self.monitor.check(mbs, t_state)
            if st is not None:
                return False
            if self.guidance is not None:
                st = self.guidance(self.monitor.contact, t_state)
                if st is not None:
                    self.stop = self.monitor.annotate(st)
                    self.monitor.events.append(self.stop)
                    return False
        if self.recorder is not None and on_grid and k_grid % self.every == 0:
            self.recorder.record(mbs, t_state)
            self.last_recorded = t_state
        if self.progress is not None:
            self.progress.update(t_state)
        return True


def solve(mbs, sim, solver_type, monitor: RunMonitor | None, *, dt_s: float, solver: str, guidance=None,
          recorder=None, record_every: int = 1, progress=None, grid_check: bool = False, contact_omega=(),
          attach_monitor: bool = True, user_function=None, watch: bool = True) -> RunOutcome:
    """``mbs.SolveDynamic(sim, solverType=solver_type)`` watched by ``monitor`` (``mbs`` assembled; None only for a
    model without wheel–rail contact) with the pre-step function of the module docstring; ``solver`` the name
    (:data:`~.settings.SOLVERS`).  ``attach_monitor=False`` keeps an attachment the caller made
    (:meth:`~exudyn_wheelrail.simulation.monitor.RunMonitor.attach`); ``user_function(mbs, t)`` (Exudyn's
    arguments; a bool, False stops) is called after the checks of every new state.  ``watch``: check the states
    in the compiled force call where the run allows it (:mod:`.watch`; False: always the pre-step function).
    Returns the :class:`RunOutcome`."""
    ti = sim.timeIntegration
    t0 = float(ti.startTime)
    t_goal = float(ti.endTime)
    if monitor is not None and attach_monitor:
        monitor.attach(mbs, t_start_s=t0, rk44_dt_s=dt_s if solver == "rk44" else None)
    watcher = None
    if watch and monitor is not None and unwatchable(contact=monitor.contact, monitor=monitor, recorder=recorder,
                                                     solver_explicit=not METHODS[solver].implicit,
                                                     user_function=user_function) is None:
        watcher = Watch(monitor.contact, monitor, guidance, recorder, dt_s=dt_s, t0_s=t0,
                        n_steps=int(ti.numberOfSteps), record_every=record_every)
        watcher = watcher if watcher.start() else None
    hook = _Hook(monitor, guidance, recorder, record_every, progress, dt_s, t0, grid_check, user_function, watcher)
    mbs.SetPreStepUserFunction(hook)
    out = RunOutcome(stop=None, t_end_s=t0, t_goal_s=t_goal, dt_s=float(dt_s), solver=solver, solve_seconds=0.0,
                     monitor=monitor, guidance=guidance, contact_omega_rad_s=list(contact_omega))
    events = monitor.events if monitor is not None else []
    t_start = time.perf_counter()
    exc = None
    ok = False
    # Exudyn's end-of-solve check counts the allocations of the Python user functions (the contact's results, the
    # hook) and prints a 'may be slow' warning for any long run: by design here, not a finding of this run
    # (the check compares with solverCheckMemoryAllocationsThreshold; Exudyn 1.13.6 does not read the on/off flag)
    import exudyn.solver as exu_solver
    threshold = exu_solver.solverCheckMemoryAllocationsThreshold
    exu_solver.solverCheckMemoryAllocationsThreshold = float("inf")
    try:
        ok = mbs.SolveDynamic(sim, solverType=solver_type)
    except Exception as e:                 # Exudyn re-raises user-function exceptions (the cause is kept)
        exc = e
    finally:
        exu_solver.solverCheckMemoryAllocationsThreshold = threshold
        if watcher is not None:
            hook.watched(finish=True)
            out.watched_states = watcher.checks
    out.solve_seconds = time.perf_counter() - t_start
    out.t_end_s = float(mbs.systemData.GetTime())
    out.rejected_steps = hook.rejected
    out.events = events
    if monitor is not None:
        out.max_omega_h = max(monitor.max_omega_h)
        out.creep_rate_1_s = list(monitor.creep_rate_1_s)
    if hook.error is not None:
        raise RuntimeError(f"recording the run failed at t = {hook.t_state}: {type(hook.error).__name__}: "
                           f"{hook.error}") from hook.error
    stop = (monitor.status if monitor is not None else None) or hook.stop
    if exc is not None:
        out.stop = stop or _failure(monitor, exc, out.t_end_s, events)
    elif stop is not None:
        out.stop = stop
    elif not ok:
        out.stop = Status("solver_failure", out.t_end_s, None, None, "mbs.SolveDynamic reported failure (Newton "
                                                                     "did not converge or the solver aborted)")
        events.append(out.stop)
    else:
        out.stop = _completed(mbs, hook, monitor, out, events)
    onset = monitor.stability_exceeded if monitor is not None else None
    if recorder is not None and onset is not None and out.stop.kind in ("invalid_state", "solver_failure"):
        out.rows_dropped = recorder.keep_until(onset.time_s)     # unstable integration from that state on
    if recorder is not None:
        recorder.complete()             # columns read from what Exudyn stored during this solve
    if progress is not None:
        progress.update(hook.t_state if hook.t_state is not None else t0)
    return out


def _failure(monitor, exc, t_fail, events) -> Status:
    err = contact_state_error(exc)
    text = str(exc).splitlines()[0] if str(exc) else ""
    serious = [e for e in events if e.kind in _SERIOUS]
    if serious and monitor is not None:
        e = monitor.annotate(serious[0])
        later = (f"ContactStateError: {str(err).splitlines()[0]}" if err is not None else f"{type(exc).__name__}: "
                                                                                           f"{text}")
        return Status(e.kind, e.time_s, e.wheelset, e.side, e.detail + f" (not stopped; later: {later})")
    if err is not None:
        st = status_from_state_error(err, t_fail)
    else:
        st = Status("solver_failure", t_fail, None, None, f"{type(exc).__name__}: {text}")
    if monitor is not None:
        st = monitor.annotate(st)
    events.append(st)
    return st


def _completed(mbs, hook: _Hook, monitor, out: RunOutcome, events) -> Status:
    t_end = out.t_end_s
    if hook.t_state is None or t_end > hook.t_state + 0.5 * out.dt_s:       # the final state: not checked yet
        if not hook.state(mbs, t_end):
            return (monitor.status if monitor is not None else None) or hook.stop
    if abs(t_end - out.t_goal_s) > 0.5 * out.dt_s:
        st = Status("solver_failure", t_end, None, None, f"the solver stopped at t = {t_end:.6g} s of "
                                                         f"{out.t_goal_s:.6g} s")
        events.append(st)
        return st
    serious = [e for e in events if e.kind in _SERIOUS]
    if serious:                      # not stopped for (stop_on), but never reported as a completed run
        e = monitor.annotate(serious[0])
        return Status(e.kind, e.time_s, e.wheelset, e.side,
                      e.detail + f" (not stopped: run continued to t = {t_end:.6g} s)")
    warn = "" if monitor is None or monitor.stability_exceeded is None else \
        f" (warning: {monitor.stability_exceeded})"
    hunt = [h for h in (monitor.hunting if monitor is not None else []) if h is not None]
    if hunt:
        h = hunt[0]
        return Status("hunting", h.time_s, h.wheelset, None, h.detail + f"; run completed at t = {t_end:.6g} s" + warn)
    return Status("completed", t_end, None, None, "end time reached" + warn)


def _check_flexible_track_step(contact, settings: RunSettings, creep_rate_1_s=()) -> None:
    """A flexible track under the contact (:mod:`exudyn_wheelrail.track.flexible`): the explicit step against the
    wheel on the rail's modal mass over the track around the wheelsets' start, a ``TrackFileError`` naming
    ``run.dt_s`` before the solve (the run monitor checks the same stiffness on the same mass where the wheelsets are
    during the run); and an RK44 step against the creep damping on
    the rails (``creep_rate_1_s``: the monitor's decay rates at the initial state, the rails' modal mass included),
    an :class:`~exudyn_wheelrail.validation.InputWarning` naming ``run.dt_s`` and the stable step."""
    bridge = getattr(contact, "structure", None)
    if bridge is None or not hasattr(bridge.modes, "residual_table"):
        return
    s = [float(x) for x in contact.results[:, 0, RES_S_TRACK]]      # the wheelsets' track distance now
    dt = float(settings.dt_s)
    check_explicit_step(bridge.modes, settings.solver, dt, min(s) - 1.0, max(s) + 1.0)
    sigma = max(creep_rate_1_s, default=0.0)
    if settings.solver == "rk44" and sigma * dt > RK44.real_axis_limit:
        warnings.warn(f"run.dt_s = {dt:g} s: beyond RK44's stability limit of the creep damping on the flexible "
                      f"rails (sigma h = {sigma * dt:.3g} > {RK44.real_axis_limit:.3f}, sigma = {sigma:.4g} 1/s: the "
                      "lateral creep force as a damper on the rails' modal mass, growing as 1/V); the run would "
                      f"settle into a false steady lateral force: use run.dt_s <= {RK44.real_axis_limit / sigma:.3g} s (or "
                      "leave run.dt_s out: the scenario then takes a stable step for its speed)", InputWarning,
                      stacklevel=3)


def run(mbs, settings: RunSettings, contact, *, speed_m_s: float, recorder=None, progress=None,
        exu_settings=None, user_function=None, watch: bool = True) -> RunOutcome:
    """Run ``mbs`` (assembled) with ``settings`` (duration resolved), watched by a new
    :class:`~exudyn_wheelrail.simulation.monitor.RunMonitor` of ``contact`` and the flange-climb check
    (``speed_m_s`` the running speed; ``contact`` None only for the wheel–rail springs baseline, which has nothing
    to watch).  ``recorder``: a :class:`~.recorder.Recorder` (None or ``settings.record`` False: nothing recorded);
    ``progress``: a :class:`~.recorder.ProgressBar` or None; ``exu_settings``: ``(SimulationSettings,
    DynamicSolverType)`` of these settings when the caller changed them (a viewer slows the solve), else built
    here; ``user_function(mbs, t)``: called after the checks of every state (:func:`solve`), e.g. to update loads
    that follow the track; ``watch``: as :func:`solve`."""
    sim, solver_type = exu_settings if exu_settings is not None else run_solver_settings(settings)
    monitor = guidance = None
    omega = []
    if contact is not None:
        t0 = float(sim.timeIntegration.startTime)
        omega, creep = _initial_estimates(mbs, contact, t0)
        _check_flexible_track_step(contact, settings, creep)
        monitor = RunMonitor(contact)
        guidance = FlangeClimbCheck(len(contact.nodes_exu), speed_m_s, monitor.nadal_limit)
    return solve(mbs, sim, solver_type, monitor, dt_s=float(settings.dt_s), solver=settings.solver,
                 guidance=guidance, recorder=recorder if settings.record else None,
                 record_every=settings.record_every, progress=progress, grid_check=True, contact_omega=omega,
                 user_function=user_function, watch=watch)


def _solver_type(solver):
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
    the one solve wrapper, :func:`solve`.  Returns ``(status, t_end)``: the
    monitor's stopping status, an ``invalid_state`` from a :class:`~exudyn_wheelrail.multibody.connector.ContactStateError` (its time and
    wheelset), a ``solver_failure``, or — after a check of the final state — ``completed`` / ``hunting``; ``t_end``
    is the time the solver reached."""
    if monitor is None:
        raise ValueError("run_monitored needs a RunMonitor")
    solver = _solver_type(solver)
    name = next((k for k, m in METHODS.items() if getattr(exu.DynamicSolverType, m.exudyn_type) == solver), "newmark")
    n_steps = max(1, int(sim.timeIntegration.numberOfSteps))
    dt = (float(sim.timeIntegration.endTime) - float(sim.timeIntegration.startTime)) / n_steps
    attached = monitor.attached_to(mbs)                                # keep the caller's attachment and function
    outcome = solve(mbs, sim, solver, monitor, dt_s=dt, solver=name, attach_monitor=not attached,
                    user_function=monitor.user_function if attached else None)
    return outcome.stop, outcome.t_end_s
