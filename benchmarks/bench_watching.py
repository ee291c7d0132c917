"""Cost of watching and recording a run: the pre-step hook of :mod:`exudyn_wheelrail.simulation.runner`, per stage.

The RTRI 20 m case at 250 km/h (Manchester vehicle 1, 4 wheelsets), built as the CLI builds it:

* ``rk44`` — ``rtri --preset default`` (RK44, 1 ms, online geometry, table creep law);
* ``newmark`` — the paper's settings, ``rtri`` without a preset (Newmark beta 1/4, gamma 1/2, 1 ms).

Stages of one accepted state (µs per state):

* ``contact evaluation`` — the one contact call at the state (``WheelRailContact.forces``), made by the run
  monitor; every later stage reads its results;
* ``monitor checks`` — the run monitor's own work besides that call (fetching the coordinates, keeping the warm
  start; derailment, invalid states, flange climb, lift-off, deep penetration, hunting, the history; with RK44 the
  stability estimate);
* ``of which stability estimate`` (at rest only) — the monitor with RK44's estimate minus the monitor without it;
* ``guidance`` — the 2 m Y/Q flange-climb check (:mod:`exudyn_wheelrail.simulation.guidance`);
* ``recorder`` — one recorded row (:mod:`exudyn_wheelrail.simulation.recorder`);
* ``hook total`` — the whole pre-step function for a new state (grid check and progress included).

Two settings: **at rest** — the initial state, each stage called ``--calls`` times in a row (the contact's warm
start that of a solver call at the state; the time advanced by 0.1 µs per call where the contact is evaluated, so
that the track under the wheels stays the same, by dt for the guidance and the recorder; CPU time of the process,
``time.process_time``, the fastest of 5 blocks); **along the run** — the whole run, each stage timed inside the
real hook (timing wrappers around the stages, wall clock, the median over the states; the wrappers' own cost,
~0.2 µs each, is included).  Then the **solve times** (wall time inside ``mbs.SolveDynamic`` only, fresh model each repeat, the
configurations interleaved): the same model solved by Exudyn without any pre-step function ("unwatched") and
watched and recorded through the runner, as the CLI runs it; real-time factor = simulated / solve time.  Beside the
wall time the CPU time of the process (``time.process_time``), less disturbed by other work on a shared machine.

The machine load (``os.getloadavg``, 1 min) is printed before and after each part; the machine is shared, so
compare configurations of one session only.

Run:  python benchmarks/bench_watching.py [--repeats 3] [--calls 2000] [--solvers rk44 newmark] [--json PATH]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import sys
import time
from collections import defaultdict


from exudyn_wheelrail.simulation.monitor import RunMonitor
from exudyn_wheelrail.scenarios.rtri import RtriCase
from exudyn_wheelrail.scenarios.scenario import build_scenario
from exudyn_wheelrail.simulation import runner as R
from exudyn_wheelrail.simulation.guidance import FlangeClimbCheck
from exudyn_wheelrail.simulation.presets import apply_preset
from exudyn_wheelrail.simulation.recorder import Recorder

SPAN_M = 20.0
DURATION_S = 2.5
#: time increment of the at-rest calls that evaluate the contact [s]
EPS_S = 1e-7
#: the clock of the per-stage timings: CPU time of the process (a shared machine preempts; wall time would count it)
CLOCK = time.process_time


def load() -> str:
    return "load %.2f %.2f %.2f" % os.getloadavg()


def case(solver: str, duration_s: float = DURATION_S, record: bool = True) -> RtriCase:
    """``rk44``: the CLI's ``--preset default``; ``newmark``: the CLI without a preset (the paper's settings)."""
    base = RtriCase(span_m=SPAN_M)
    run, contact = base.run, base.contact
    if solver == "rk44":
        run, contact, _ = apply_preset("default", run, contact)
    return RtriCase(span_m=SPAN_M, run=run, contact=contact, duration_s=duration_s, record=record)


def build(solver: str, duration_s: float = DURATION_S, record: bool = True):
    h = build_scenario(case(solver, duration_s, record).scenario())
    h.contact.warm_up(h.mbs, jacobian=h.run.implicit)
    return h


def per_call_us(f, n: int, blocks: int = 5) -> float:
    """CPU µs per call: the fastest of ``blocks`` blocks of ``n // blocks`` calls (the machine is shared)."""
    f()
    m = max(1, n // blocks)
    best = math.inf
    for _ in range(blocks):
        t0 = CLOCK()
        for _ in range(m):
            f()
        best = min(best, (CLOCK() - t0) / m)
    return best * 1e6


# ------------------------------------------------------------------------------------------------ at rest
def at_rest(solver: str, n: int) -> dict:
    h = build(solver, duration_s=0.01)
    mbs, c = h.mbs, h.contact
    dt = h.run.dt_s
    q, v = c.coordinates(mbs)
    c.forces(q, v, 0.0)                     # a solver call at the state: the warm start of a running solve
    rk44 = h.run.solver == "rk44"
    # the contact is evaluated at the initial state: its time advances by EPS_S per call (the track under the
    # wheels stays where it is); the guidance and the recorder, which do not evaluate, advance by dt
    clock = {"t": 0.0, "t_eval": 0.0}

    def tick():
        clock["t"] += dt
        return clock["t"]

    def tick_eval():
        clock["t_eval"] += EPS_S
        return clock["t_eval"]

    def monitor(stability: bool):
        m = RunMonitor(c)
        m.attach(mbs, t_start_s=0.0, rk44_dt_s=dt if stability else None)
        return m

    m_on, m_off = monitor(rk44), monitor(False)
    guidance = FlangeClimbCheck(len(c.nodes_exu), h.speed_m_s, m_on.nadal_limit)
    rec = h.recorder
    rows = rec.data.shape[0]        # read before any row: the car-body columns come from a solve's stored sensors

    def record(t):
        if rec.n >= rows - 1:
            rec.n = 0
        rec.record(mbs, t)

    warm = c.save_warm_start()

    def evaluation():                       # the compiled contact call at the state, the warm start kept
        c.forces(q, v, tick_eval())
        c.restore_warm_start(warm)

    out = {"contact evaluation": per_call_us(evaluation, n)}
    total = per_call_us(lambda: m_on.check(mbs, tick_eval()), n)
    out["monitor checks"] = total - out["contact evaluation"]
    if rk44:
        out["of which stability estimate"] = total - per_call_us(lambda: m_off.check(mbs, tick_eval()), n)
    out["guidance"] = per_call_us(lambda: guidance(c, tick()), n)
    out["recorder"] = per_call_us(lambda: record(tick()), n)
    m_hook = monitor(rk44)
    g_hook = FlangeClimbCheck(len(c.nodes_exu), h.speed_m_s, m_hook.nadal_limit)
    hook = R._Hook(m_hook, g_hook, rec, 1, None, EPS_S, 0.0, True, None)
    k = {"i": 0}

    def state():
        k["i"] += 1
        if rec.n >= rows - 1:
            rec.n = 0
        hook.state(mbs, k["i"] * EPS_S)

    out["hook total"] = per_call_us(state, n)
    for name, m in (("monitor", m_on), ("monitor without stability", m_off), ("hook monitor", m_hook)):
        if m.status is not None:
            print(f"  note: {name} stopped at rest: {m.status}", file=sys.stderr)
    return out


# ------------------------------------------------------------------------------------------- along the run
class _Timers:
    """Timing wrappers around the hook's stages (class attributes patched for one run, restored after): per stage
    the wall time of every call inside the hook (``time.perf_counter``: cheap enough to wrap a call of a few µs;
    the median over the states is robust to the preemptions of a shared machine)."""

    def __init__(self):
        self.samples = defaultdict(list)
        self.in_hook = False
        self._saved = []

    def wrap(self, owner, name, key, hook=False):
        orig = getattr(owner, name)
        timers = self
        clock = time.perf_counter

        def timed(*args, **kwargs):
            if hook:
                timers.in_hook = True
            t0 = clock()
            try:
                return orig(*args, **kwargs)
            finally:
                if hook or timers.in_hook:
                    timers.samples[key].append(clock() - t0)
                if hook:
                    timers.in_hook = False
        self._saved.append((owner, name, orig))
        setattr(owner, name, timed)

    def restore(self):
        for owner, name, orig in reversed(self._saved):
            setattr(owner, name, orig)
        self._saved = []


def along_run(solver: str) -> dict:
    h = build(solver)
    c = h.contact
    tm = _Timers()
    tm.wrap(R._Hook, "state", "hook total", hook=True)
    tm.wrap(RunMonitor, "check", "monitor")
    tm.wrap(FlangeClimbCheck, "__call__", "guidance")
    tm.wrap(Recorder, "record", "recorder")
    tm.wrap(c, "forces", "contact evaluation")        # the contact call inside the hook (instance level)
    try:
        outcome = R.run(h.mbs, h.run, c, speed_m_s=h.speed_m_s, recorder=h.recorder,
                        exu_settings=(h.settings, h.solver_type))
    finally:
        tm.restore()
        c.__dict__.pop("forces", None)
    med = {k: statistics.median(v) * 1e6 for k, v in tm.samples.items() if v}
    out = {"contact evaluation": med.get("contact evaluation", 0.0),
           "monitor checks": med.get("monitor", 0.0) - med.get("contact evaluation", 0.0),
           "guidance": med.get("guidance", 0.0), "recorder": med.get("recorder", 0.0),
           "hook total": med.get("hook total", 0.0),
           "hook total, mean": statistics.fmean(tm.samples["hook total"]) * 1e6}
    out["states"] = len(tm.samples["hook total"])
    out["status"] = outcome.status.kind
    return out


# --------------------------------------------------------------------------------------------- solve times
def solve_unwatched(solver: str) -> tuple[float, float]:
    """(wall, CPU) seconds of the solve without any pre-step function."""
    h = build(solver, record=False)
    t0, c0 = time.perf_counter(), time.process_time()
    h.mbs.SolveDynamic(h.settings, solverType=h.solver_type)
    return time.perf_counter() - t0, time.process_time() - c0


def solve_watched(solver: str) -> tuple[float, float, str]:
    """(wall, CPU) seconds of the solve through the runner, watched and recorded, and the status.  The CPU time is
    that of the whole ``run`` call: it includes the initial contact-frequency estimate (one contact call)."""
    h = build(solver)
    c0 = time.process_time()
    outcome = R.run(h.mbs, h.run, h.contact, speed_m_s=h.speed_m_s, recorder=h.recorder,
                    exu_settings=(h.settings, h.solver_type))
    return outcome.solve_seconds, time.process_time() - c0, outcome.status.kind


def table(title: str, rows: dict, cols: list[str]) -> None:
    print(f"\n{title}\n")
    print("| stage | " + " | ".join(cols) + " |")
    print("|---|" + "---|" * len(cols))
    keys = []
    for r in rows.values():
        keys += [k for k in r if k not in keys and isinstance(r[k], float)]
    for k in keys:
        print(f"| {k} | " + " | ".join(f"{rows[c].get(k, float('nan')):.1f}" for c in cols) + " |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--calls", type=int, default=2000, help="calls per stage at rest")
    ap.add_argument("--solvers", nargs="+", default=["rk44", "newmark"], choices=["rk44", "newmark"])
    ap.add_argument("--skip-solves", action="store_true")
    ap.add_argument("--json", default=None, help="write the results here")
    args = ap.parse_args(argv)
    res = {"machine": os.uname().nodename, "cpus": os.cpu_count()}
    build("rk44", duration_s=0.005)                  # numba caches, Exudyn: outside every measurement
    print(f"at rest ({args.calls} calls per stage) — {load()}")
    rest = {s: at_rest(s, args.calls) for s in args.solvers}
    table(f"µs per state at rest ({load()})", rest, args.solvers)
    print(f"\nalong the run — {load()}")
    run = {s: along_run(s) for s in args.solvers}
    table(f"µs per state along the run, median over the states (wall clock; {load()}); states: "
          + ", ".join(f"{s} {run[s]['states']} ({run[s]['status']})" for s in args.solvers), run, args.solvers)
    res.update(at_rest=rest, along_run=run)
    if not args.skip_solves:
        wall, cpu = defaultdict(list), defaultdict(list)
        loads = []
        for _ in range(args.repeats):
            for s in args.solvers:                   # interleaved
                loads.append(os.getloadavg()[0])
                w, c = solve_unwatched(s)
                wall[(s, "unwatched")].append(w)
                cpu[(s, "unwatched")].append(c)
                loads.append(os.getloadavg()[0])
                w, c, kind = solve_watched(s)
                wall[(s, "watched")].append(w)
                cpu[(s, "watched")].append(c)
                if kind != "ok":
                    print(f"  {s} watched: status {kind}", file=sys.stderr)
        steps = round(DURATION_S / 1e-3)
        print(f"\nsolve times, {args.repeats} repeats interleaved (load during: {min(loads):.2f}–{max(loads):.2f}); "
              "wall: min / median; CPU: min\n")
        print("| solver | configuration | wall s | real-time factor (best wall) | µs per step (best wall) | CPU s | "
              "µs per step (CPU) |")
        print("|---|---|---|---|---|---|---|")
        res["solves"] = {}
        for s in args.solvers:
            for kind in ("unwatched", "watched"):
                ws, cs = wall[(s, kind)], cpu[(s, kind)]
                best, med, cb = min(ws), statistics.median(ws), min(cs)
                print(f"| {s} | {kind} | {best:.3f} / {med:.3f} | {DURATION_S / best:.2f} | {best / steps * 1e6:.0f} | "
                      f"{cb:.3f} | {cb / steps * 1e6:.0f} |")
                res["solves"][f"{s} {kind}"] = {"wall_s": ws, "cpu_s": cs}
            ratio = min(wall[(s, "watched")]) / min(wall[(s, "unwatched")])
            ratio_cpu = min(cpu[(s, "watched")]) / min(cpu[(s, "unwatched")])
            print(f"| {s} | watched / unwatched | {ratio:.3f} | | | {ratio_cpu:.3f} | |")
        res["load_during"] = [min(loads), max(loads)]
    print(f"\n{load()}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(res, f, indent=1, default=float)


if __name__ == "__main__":
    main()
