"""Per-step cost of an RK44 run outside the compiled contact call: what the CLI's ``rtri --span 20 --preset default``
spends per step besides Exudyn's vehicle step and the contact kernel.

The model is the CLI's (:func:`exudyn_wheelrail.scenarios.rtri.run_rtri`'s case with ``--preset default``: RK44 at
1 ms, online contact search, table creep law, recording on; Manchester vehicle 1, 4 wheelsets, RTRI 20 m at
250 km/h, 2.5 s).  Three parts:

1. **Solve times** (wall time inside ``mbs.SolveDynamic``, as the run summary's ``solve_seconds``, and the thread's
   CPU time there, less disturbed by other work on a shared machine; fresh model each, the configurations
   interleaved, median of ``--repeats``): ``cli`` — watched and recorded through the runner as the CLI runs it
   (the connector on its compiled call path, :mod:`exudyn_wheelrail.multibody.direct_call`, the states checked in
   the compiled force call, :mod:`exudyn_wheelrail.simulation.watch`); ``cli_hook`` — the same with every state
   checked by the runner's pre-step function (``watch=False``: as before the watch); ``cli_python`` — the
   same on the connector's Python call path (each force call through Python, as before the compiled path);
   ``no_record`` — watched, not recorded; ``unwatched`` — the same contact model solved by Exudyn without a pre-step
   function (the contact computed at every stage); ``constant_force`` — the contact model with the force user
   function answering a fixed force vector (the initial state's contact forces) without any contact call, no
   pre-step function: Exudyn's vehicle step and its Python user-function dispatch (Python path); ``springs`` — the vehicle on
   linear rail springs (no user function; the ``springs`` baseline of ``bench_rtri.py``).  Real-time factor =
   simulated time / solve time.
2. **Along the run**, by piece: one ``cli_python`` run with every piece timed inside the real run
   (``time.perf_counter`` around the piece, ``--clock cpu`` for the thread's CPU time; on the compiled path no piece
   of the force call passes through Python to be timed).  Pieces (exclusive of the pieces nested in them):
   ``contact kernel`` (the compiled evaluation, ``WheelRailContact._forces_step``); ``forces() wrapper`` (argument
   checks, the kept-evaluation test); ``evaluate_state`` (keeping the monitor's evaluation for the first stage);
   ``monitor`` (:meth:`~exudyn_wheelrail.simulation.monitor.RunMonitor.check` besides the contact call: coordinates,
   the compiled checks); ``guidance`` (the 2 m flange-climb window); ``recorder`` (one row); ``hook`` (the runner's
   pre-step function besides all of these: time bookkeeping, grid check); ``Exudyn`` (the rest: the vehicle's
   step, the integrator, the calls into Python).  Two views: the **mean** (sums over the run / steps; they add up
   to the instrumented solve time, preemption on a shared machine included) and the **median step** (each piece's
   time within each step — from one call of the hook to the next —, the median over the steps: a typical step,
   blind to preempted steps but also to the contact search's rare expensive calls, its rescans).  The timers' own
   cost (an empty function timed in a loop: inside and outside the measured interval) is subtracted from the piece
   that contains it and reported.
3. **At rest** (the initial state, each piece called ``--calls`` times in a row, fastest of 5 blocks,
   ``time.perf_counter``): the same pieces alone, for reference.

The machine load (``os.getloadavg``) is given beside every part; the machine is shared, so compare figures of one
session only.  Writes ``benchmarks/results/step_overhead.json``.

Run:  python benchmarks/bench_step_overhead.py [--repeats 3] [--calls 3000] [--preset default|fast|accurate]
"""
from __future__ import annotations

import argparse
import contextlib
import json
import os
import platform
import statistics
import sys
import time
import timeit
from pathlib import Path

import numpy as np

from exudyn_wheelrail.multibody.direct_call import python_call_path
from exudyn_wheelrail.simulation.monitor import RunMonitor
from exudyn_wheelrail.scenarios.rtri import RtriCase
from exudyn_wheelrail.scenarios.scenario import build_scenario
from exudyn_wheelrail.simulation import runner as R
from exudyn_wheelrail.simulation.guidance import FlangeClimbCheck
from exudyn_wheelrail.simulation.presets import SPRINGS_RATIO_MAX, TARGETS, apply_preset

RESULTS = Path(__file__).resolve().parent / "results" / "step_overhead.json"
SPAN_M = 20.0
PRESET = "default"


def set_preset(name: str) -> None:
    """The preset of every model built from here on (``--preset``)."""
    global PRESET
    PRESET = name
CONFIGS = ("cli", "cli_hook", "cli_python", "no_record", "unwatched", "constant_force", "springs")
#: the configurations built on the connector's Python call path (direct_call.CALL_PATH_ENV): the CLI's run as it ran
#: before the compiled path, the constant-force floor (a Python function answering a fixed vector), and the pieces
#: timed along the run (the compiled path has no Python piece to time)
PYTHON_PATH = ("cli_python", "constant_force")


def load() -> list[float]:
    return [round(x, 2) for x in os.getloadavg()]


def case(record: bool = True, wheel_rail: str = "contact", duration_s: float | None = None) -> RtriCase:
    """The CLI's case: ``rtri --span 20 --preset default`` (``duration_s`` None: the case's 2.5 s)."""
    base = RtriCase(span_m=SPAN_M)
    run, contact, _ = apply_preset(PRESET, base.run, base.contact)
    kw = {} if duration_s is None else dict(duration_s=duration_s)
    return RtriCase(span_m=SPAN_M, run=run, contact=contact, record=record, wheel_rail=wheel_rail, **kw)


def build(record: bool = True, wheel_rail: str = "contact", duration_s: float | None = None,
          python_path: bool = False):
    """The CLI's model; ``python_path``: the connector on its Python call path."""
    with python_call_path() if python_path else contextlib.nullcontext():
        h = build_scenario(case(record, wheel_rail, duration_s).scenario())
    if h.contact is not None:
        h.contact.warm_up(h.mbs, jacobian=False)
    return h


class SolveClock:
    """Wall and thread CPU time inside every ``MainSystem.SolveDynamic`` while active (``with``): ``spans``, a list
    of ``(wall_s, cpu_s)``."""

    def __enter__(self):
        import exudyn
        self._cls = exudyn.MainSystem
        self._orig = orig = self._cls.SolveDynamic
        self.spans = spans = []

        def timed(*a, **k):
            w0, c0 = time.perf_counter(), time.thread_time()
            try:
                return orig(*a, **k)
            finally:
                spans.append((time.perf_counter() - w0, time.thread_time() - c0))
        self._cls.SolveDynamic = timed
        return self

    def __exit__(self, *exc):
        self._cls.SolveDynamic = self._orig


def solve_once(config: str) -> tuple[float, float]:
    """``(wall, CPU)`` time [s] inside ``mbs.SolveDynamic`` of one fresh model in configuration ``config``
    (:data:`CONFIGS`)."""
    h = build(record=config in ("cli", "cli_hook", "cli_python"),
              wheel_rail="springs" if config == "springs" else "contact",
              python_path=config in PYTHON_PATH)
    c = h.contact
    with SolveClock() as clock:
        if config in ("cli", "cli_hook", "cli_python", "no_record", "springs"):
            out = R.run(h.mbs, h.run, c, speed_m_s=h.speed_m_s, recorder=h.recorder,
                        exu_settings=(h.settings, h.solver_type), watch=config != "cli_hook")
            if out.status.kind != "ok":
                print(f"{config}: {out.status}", file=sys.stderr)
        else:
            if config == "constant_force":
                q, v = c.coordinates(h.mbs)
                f0 = c.forces(q, v, 0.0).copy()
                c.forces = lambda q, q_t, t: f0        # the user function Exudyn calls answers without the contact
            h.mbs.SolveDynamic(h.settings, solverType=h.solver_type)
    return clock.spans[-1]


# ---------------------------------------------------------------------------------------------- along the run
#: the clocks of the timed pieces: the wall clock (cheap to read; a preempted interval is an outlier the medians
#: ignore) or the thread's CPU time (a system call per reading: larger timer cost)
CLOCKS = {"wall": time.perf_counter, "cpu": time.thread_time}


class _Timer:
    """Per piece the intervals of ``clock``, each call's (``samples``) and their sums (``total``); timed calls nest,
    a piece's interval excludes the nested pieces'.  ``entries``: the clock at every entry of the piece named
    ``mark`` (the steps' starts); ``steps``: per sample the number of those entries before it."""

    def __init__(self, clock=time.perf_counter, mark=None):
        self.clock = clock
        self.total = {}
        self.count = {}
        self.samples = {}
        self.steps = {}                      # per sample: the number of marks before it (its step)
        self.stack = []                      # [name, start, nested]
        self.mark = mark
        self.entries = []

    def reset(self):
        for k in self.total:
            self.total[k], self.count[k] = 0.0, 0
            self.samples[k].clear()
            self.steps[k].clear()
        self.entries.clear()

    def wrap(self, name, fn):
        pc = self.clock
        total, count, stack = self.total, self.count, self.stack
        total.setdefault(name, 0.0)
        count.setdefault(name, 0)
        samples = self.samples.setdefault(name, [])
        steps = self.steps.setdefault(name, [])
        entries = self.entries
        mark = name == self.mark

        def timed(*a, **k):
            frame = [name, pc(), 0.0]
            if mark:
                entries.append(frame[1])
            step = len(entries)
            stack.append(frame)
            try:
                return fn(*a, **k)
            finally:
                stack.pop()
                dt = pc() - frame[1]
                total[name] += dt - frame[2]
                count[name] += 1
                samples.append(dt - frame[2])
                steps.append(step)
                if stack:
                    stack[-1][2] += dt
        return timed


class _TimedGuidance:
    def __init__(self, g, timer):
        self._call = timer.wrap("guidance", g.__call__)
        self.g = g

    def __call__(self, contact, t):
        return self._call(contact, t)


def timer_cost_us(clock, n: int = 20000) -> tuple[float, float]:
    """What one timed call adds [µs]: ``(own, outside)`` — inside the piece's own interval, and outside it (in the
    caller: the enclosing piece, or Exudyn for a piece Exudyn calls).  From an empty function called ``n`` times
    plain and timed (fastest of 5 blocks)."""
    def noop():
        return None
    own, full = [], []
    for _ in range(5):
        tm = _Timer(clock)
        timed = tm.wrap("noop", noop)
        t0 = clock()
        for _ in range(n):
            noop()
        t1 = clock()
        for _ in range(n):
            timed()
        t2 = clock()
        plain = (t1 - t0) / n
        full.append((t2 - t1) / n - plain)
        own.append(tm.total["noop"] / n - plain)
    o, f = max(0.0, min(own)), max(0.0, min(full))
    return o * 1e6, max(0.0, f - o) * 1e6


def along_the_run(clock: str = "wall") -> dict:
    """One ``cli_python`` run with its pieces timed (module docstring) by ``clock`` (:data:`CLOCKS`): µs per step by
    piece, from the sums over the run (``us_per_step``) and per step (``us_per_step_median``: each piece's time in
    each step — between two calls of the hook —, the median over the steps)."""
    h = build(record=True, python_path=True)
    c, mbs = h.contact, h.mbs
    tm = _Timer(CLOCKS[clock], mark="hook")
    c._forces_step = tm.wrap("contact kernel", c._forces_step)
    c.forces = tm.wrap("forces() wrapper", c.forces)           # _force_uf and evaluate_state call self.forces
    c.evaluate_state = tm.wrap("evaluate_state", c.evaluate_state)
    sim, solver_type = h.settings, h.solver_type
    t0 = float(sim.timeIntegration.startTime)
    omega = R.contact_omega_rad_s(mbs, c, t0)                   # as runner.run
    tm.reset()
    monitor = RunMonitor(c)
    monitor.check = tm.wrap("monitor", monitor.check)
    guidance = _TimedGuidance(FlangeClimbCheck(len(c.nodes_exu), h.speed_m_s, monitor.nadal_limit), tm)
    recorder = h.recorder
    recorder.record = tm.wrap("recorder", recorder.record)
    hook_call = R._Hook.__call__
    R._Hook.__call__ = tm.wrap("hook", hook_call)
    solve_dynamic = type(mbs).SolveDynamic
    span = []

    def timed_solve(*a, **k):                   # the clock around mbs.SolveDynamic only, as solve_seconds
        span.append(tm.clock())
        try:
            return solve_dynamic(*a, **k)
        finally:
            span.append(tm.clock())
    type(mbs).SolveDynamic = timed_solve
    try:
        out = R.solve(mbs, sim, solver_type, monitor, dt_s=float(h.run.dt_s), solver=h.run.solver, guidance=guidance,
                      recorder=recorder, record_every=h.run.record_every, grid_check=True, contact_omega=omega)
    finally:
        R._Hook.__call__ = hook_call
        type(mbs).SolveDynamic = solve_dynamic
    solve_s = span[1] - span[0]
    steps = h.run.steps
    own_us, outside_us = timer_cost_us(CLOCKS[clock])
    own, outside = own_us * 1e-6, outside_us * 1e-6
    n = tm.count
    # timed calls nested in each piece (their 'outside' cost lands in it); the rest are called by Exudyn
    nested = {"forces() wrapper": n["contact kernel"], "evaluate_state": n["evaluate_state"],
              "monitor": n["evaluate_state"], "hook": n["monitor"] + n["guidance"] + n["recorder"]}
    top_level = n["hook"] + (n["forces() wrapper"] - n["evaluate_state"])
    pieces = {name: (total - n[name] * own - nested.get(name, 0) * outside) * 1e6 / steps
              for name, total in tm.total.items()}
    pieces["Exudyn (vehicle, integrator, user-function dispatch)"] = (
        solve_s - sum(tm.total.values()) - top_level * outside) * 1e6 / steps
    timers = sum(n.values()) * (own + outside) * 1e6 / steps
    pieces["timers (subtracted above)"] = timers
    # the same per step (between two calls of the hook), the median over the steps: robust to the steps a shared
    # machine's preemption inflates (and blind to the rare expensive ones)
    n_marks = len(tm.entries)
    step_s = np.diff(tm.entries)                             # step i: samples with step index i + 1
    per_step, timed = {}, np.zeros(n_marks - 1)
    for name, v in tm.samples.items():
        idx = np.asarray(tm.steps[name])
        calls = np.bincount(idx, minlength=n_marks + 1)[1:n_marks]
        total = np.bincount(idx, weights=np.asarray(v), minlength=n_marks + 1)[1:n_marks]
        nested_calls = nested.get(name, 0) / n[name] * calls
        per_step[name] = total - calls * own - nested_calls * outside
        timed += calls
    timer_steps = timed * (own + outside)
    exudyn_steps = step_s - sum(per_step.values()) - timer_steps
    medians = {name: float(np.median(v)) * 1e6 for name, v in per_step.items()}
    medians["Exudyn (vehicle, integrator, user-function dispatch)"] = float(np.median(exudyn_steps)) * 1e6
    medians["timers (subtracted above)"] = float(np.median(timer_steps)) * 1e6
    step_us = float(np.median(step_s)) * 1e6
    return dict(status=out.status.kind, clock=clock, solve_seconds_instrumented=solve_s, steps=steps,
                calls=dict(n), timer_cost_us=dict(own=own_us, outside=outside_us), us_per_step=pieces,
                us_per_step_median=medians, step_us_median=step_us, contact_calls=c.n_calls, reused=c.n_reused)


# ---------------------------------------------------------------------------------------------------- at rest
def at_rest(calls: int) -> dict:
    h = build(record=True, duration_s=0.01, python_path=True)
    c, mbs = h.contact, h.mbs
    monitor = RunMonitor(c, keep_history=False)
    monitor.attach(mbs, t_start_s=0.0, rk44_dt_s=float(h.run.dt_s))
    guidance = FlangeClimbCheck(len(c.nodes_exu), h.speed_m_s, monitor.nadal_limit)
    rec = h.recorder
    q, v = c.coordinates(mbs)
    f, res, data = c._f, c.results, c._data
    warm = c.save_warm_start()

    def tm(fn):
        fn()
        return min(timeit.repeat(fn, number=calls, repeat=5)) / calls * 1e6

    def forces():
        c.forces(q, v, 0.0)

    def kept():
        c.evaluate_state(q, v, 0.0)
        c.forces(q, v, 0.0)

    def record():
        rec.n = 0
        rec.record(mbs, 0.0)
    # the probes that read every recorded state (those with fill_rows are filled once after the solve: the car-body
    # points from Exudyn's stored sensors, the time-only columns)
    fills = {type(p).__name__: (p.fill, np.empty(len(p.columns))) for p in rec.probes
             if hasattr(p, "fill") and not hasattr(p, "fill_rows")}
    out = {"contact kernel (compiled call)": tm(lambda: c._forces_core(q, v, 0.0, data, f, res)),
           "forces()": tm(forces),
           "evaluate_state + the first stage's forces()": tm(kept),
           "monitor.check (with its contact call)": tm(lambda: monitor.check(mbs, 0.0)),
           "guidance": tm(lambda: guidance(c, 0.0)),
           "recorder.record": tm(record)}
    for name, (fill, row) in fills.items():
        out[f"  recorder probe {name}"] = tm(lambda fill=fill, row=row: fill(mbs, 0.0, row))
    c.restore_warm_start(warm)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--calls", type=int, default=3000)
    ap.add_argument("--clock", default="wall", choices=tuple(CLOCKS), help="clock of the timed pieces")
    ap.add_argument("--configs", nargs="+", default=list(CONFIGS), choices=CONFIGS)
    ap.add_argument("--out", default=str(RESULTS))
    ap.add_argument("--preset", default=PRESET, choices=tuple(TARGETS),
                    help="the CLI preset of the case (default: %(default)s)")
    args = ap.parse_args(argv)
    set_preset(args.preset)
    solve_once("cli")                                   # numba caches, Exudyn: outside the measurements
    sim_time = case().run.steps * case().run.dt_s
    result = dict(case=f"rtri --span {SPAN_M:g} --preset {PRESET} (RK44 1 ms, 2.5 s, recording on)",
                  simulated_time_s=sim_time)

    load0 = load()
    rest = at_rest(args.calls)
    result["at_rest_us"] = rest
    result["at_rest_load"] = [load0, load()]

    load0 = load()
    run = along_the_run(args.clock)
    run["load"] = [load0, load()]
    result["along_the_run"] = run

    times = {cfg: [] for cfg in args.configs}
    loads = []
    for rep in range(args.repeats):
        for cfg in args.configs:                 # interleaved: a load change on the machine hits all alike
            times[cfg].append(solve_once(cfg))
            loads.append(load()[0])
            print(f"repeat {rep + 1}: {cfg:15s} {times[cfg][-1][0]:.3f} s wall, {times[cfg][-1][1]:.3f} s CPU  "
                  f"(load {loads[-1]:.2f})", flush=True)
    solves = {}
    for cfg, v in times.items():
        if not v:
            continue
        wall, cpu = statistics.median(x[0] for x in v), statistics.median(x[1] for x in v)
        solves[cfg] = dict(solve_seconds_median=wall, cpu_seconds_median=cpu, solve_seconds_all=[x[0] for x in v],
                           cpu_seconds_all=[x[1] for x in v], real_time_factor=sim_time / wall,
                           real_time_factor_cpu=sim_time / cpu)
    result["solves"] = solves
    result["solves_load_1min"] = [min(loads), max(loads)] if loads else None
    if "cli_python" in solves and "springs" in solves:
        result["cli_python_over_springs"] = (solves["cli_python"]["solve_seconds_median"]
                                             / solves["springs"]["solve_seconds_median"])
    if "cli_hook" in solves and "springs" in solves:
        result["cli_hook_over_springs"] = (solves["cli_hook"]["solve_seconds_median"]
                                           / solves["springs"]["solve_seconds_median"])
    if "cli" in solves and "springs" in solves:
        result["cli_over_springs"] = solves["cli"]["solve_seconds_median"] / solves["springs"]["solve_seconds_median"]
        result["cli_over_springs_cpu"] = (solves["cli"]["cpu_seconds_median"]
                                          / solves["springs"]["cpu_seconds_median"])
    result["targets"] = dict(real_time_factor_min=TARGETS[PRESET][0], springs_ratio_max=SPRINGS_RATIO_MAX)
    result.update(python=platform.python_version(), platform=platform.platform(), cpu_count=os.cpu_count(),
                  date=time.strftime("%Y-%m-%dT%H:%M:%S%z"))
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(result, fh, indent=2)

    print(f"\n### {result['case']}: per-step cost by piece, along the run (µs per step; load "
          f"{run['load'][0][0]:.2f}-{run['load'][1][0]:.2f})\n")
    print("| piece | µs/step, median step | µs/step, mean | calls/step |")
    print("|---|---:|---:|---:|")
    for name, us in run["us_per_step"].items():
        n = run["calls"].get(name)
        per_step = "" if n is None else f"{n / run['steps']:.2f}"
        print(f"| {name} | {run['us_per_step_median'][name]:.1f} | {us:.1f} | {per_step} |")
    print(f"\nmedian step {run['step_us_median']:.0f} µs; instrumented solve "
          f"{run['solve_seconds_instrumented']:.3f} s "
          f"(the means and the timers add up to it); timer cost per timed call {run['timer_cost_us']['own']:.2f} µs "
          f"inside + {run['timer_cost_us']['outside']:.2f} µs outside the interval\n")
    print(f"### at rest (µs per call; load {result['at_rest_load'][0][0]:.2f}-{result['at_rest_load'][1][0]:.2f})\n")
    print("| piece | µs |")
    print("|---|---:|")
    for name, us in rest.items():
        print(f"| {name} | {us:.2f} |")
    if solves:
        print(f"\n### solve times, median of {args.repeats} (load {result['solves_load_1min'][0]:.2f}-"
              f"{result['solves_load_1min'][1]:.2f})\n")
        print("| configuration | solve [s] wall / CPU | µs/step (wall) | real-time factor wall / CPU "
              "| all, wall [s] |")
        print("|---|---:|---:|---:|---|")
        steps = run["steps"]
        for cfg, s in solves.items():
            print(f"| {cfg} | {s['solve_seconds_median']:.3f} / {s['cpu_seconds_median']:.3f} | "
                  f"{s['solve_seconds_median'] / steps * 1e6:.0f} | {s['real_time_factor']:.2f} / "
                  f"{s['real_time_factor_cpu']:.2f} | {', '.join(f'{x:.3f}' for x in s['solve_seconds_all'])} |")
    if "cli_over_springs" in result:
        if "cli_hook_over_springs" in result:
            print(f"cli_hook / springs = {result['cli_hook_over_springs']:.2f} wall (the pre-step function checks "
                  "every state)")
        if "cli_python_over_springs" in result:
            print(f"\ncli_python / springs = {result['cli_python_over_springs']:.2f} wall (Python call path)")
        print(f"\ncli / springs = {result['cli_over_springs']:.2f} wall, {result['cli_over_springs_cpu']:.2f} CPU "
              f"(target <= {SPRINGS_RATIO_MAX:g}); real-time factor {solves['cli']['real_time_factor']:.2f} wall, "
              f"{solves['cli']['real_time_factor_cpu']:.2f} CPU (target >= {TARGETS[PRESET][0]:g})")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
