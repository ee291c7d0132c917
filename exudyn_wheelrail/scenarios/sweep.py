r"""Parameter sweeps over a scenario (:mod:`.scenario`) through any ``concurrent.futures.Executor``.

>>> from concurrent.futures import ProcessPoolExecutor                                       # doctest: +SKIP
>>> result = sweep("examples/scenarios/rtri_20m.toml",
...                {"vehicle.speed_km_h": [100, 150, 200, 250], "track.0.span_length_m": [20, 40]},
...                out_dir="out/sweep")                                                        # doctest: +SKIP
>>> result.table["max_abs_Y_any_wheel_N"]                                                      # doctest: +SKIP

What it does
------------
The **cartesian product** of the parameter values (in the order of ``parameters``; the last parameter varies
fastest) is applied to the base scenario as dotted-key overrides (:func:`~.scenario.apply_overrides`:
``vehicle.speed_km_h``, ``track.0.amplitude_m``, ``structure.section.m_kg_m``; array entries by index), and every case
is validated **before** anything runs (a bad key or value stops the sweep with an error naming the case and the
key).  Each case is one task ``executor.submit(run_case, scenario_dict, case_dir)``: the scenario goes to the
worker as a plain, picklable dict (never an Exudyn object), the worker builds, solves and evaluates it
(:func:`~.scenario.run_scenario`) and returns its ``summary`` (a plain dict whose ``status`` is one of
:data:`~exudyn_wheelrail.simulation.status.STATUSES`; a case that raises returns ``status = "error: ..."``
instead, so one case does not stop the others).

Executors
---------
* ``executor=None``: a local :class:`~concurrent.futures.ProcessPoolExecutor` with ``workers`` processes
  (default: the machine's cores, at most one per case; ``spawn`` start method), each case in its own process;
  a worker process that dies (killed, out of memory, a crash in compiled code) costs only time: the cases it took
  down with the pool run again on a fresh one, and a case that kills its worker alone every time is reported
  with an ``error: executor: ...`` status (:func:`run_tasks`);
* any :class:`concurrent.futures.Executor`: a ``ThreadPoolExecutor`` (the GIL serialises much of the work — the
  Python user functions of the contact run every step —, so it is for tests and I/O-bound setups), a
  ``ProcessPoolExecutor`` of your own, Dask's ``client.get_executor()`` (a ``distributed.Client`` itself is also
  accepted: its ``get_executor(pure=False)`` is used), :class:`SerialExecutor` (in the calling process, in order:
  debugging and the reference for tests), an MPI pool…  The executor is not shut down when it was passed in.
  On a cluster the workers need ``exudyn_wheelrail`` installed and, with ``write_cases`` (default), ``out_dir``
  on a file system they share with the caller; without it the gathered table still arrives (it is built from the
  returned summaries, not from files).

Outputs (``out_dir``; ``None`` writes nothing)
----------------------------------------------
``sweep.csv`` — **one row per case**, in case order: ``case`` (index), ``case_dir``, one column per parameter
(its value), ``status``, ``solve_seconds``, then the case's scalar results (``summary["scalars"]`` of
:func:`~.scenario.run_scenario`: peaks of every recorded column ``max_abs_<column>``, the wheel aggregates
``max_abs_Y_any_wheel_N``, ``max_YQ_any_wheel``, ``min_Q_any_wheel_N``, …, and the criteria
``criteria.<criterion>.passed / .worst_value / .worst_utilisation``, ``criteria.sperling_<dir>.Wz``, …; a bridge
crossing's: the deck's peaks and its EN 1990 check, :func:`~.bridge_crossing_summary.crossing_scalars`); a value
a case lacks is empty.  Floats are written with ``repr`` (exact round trip).  ``sweep.json`` — the base scenario,
the parameters and the same table.  ``sweep_plot.png`` — ``plot_result`` (default: :func:`default_plot_result`)
against ``plot_parameter`` (default: the first parameter), one line per combination of the other parameters'
values.  ``cases/case_<i>/`` — each case's own outputs (``write_cases``).

The returned :class:`SweepResult` holds ``table`` (a plain dict: column name -> list, one entry per case),
``summaries`` and ``scenarios`` (per case) and the written ``paths``.
"""
from __future__ import annotations

import itertools
import json
import math
import os
import threading
from concurrent.futures import Executor, Future, ProcessPoolExecutor, ThreadPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from multiprocessing import get_context
from pathlib import Path

from .drawing import pyplot
from .outputs import write_json, write_table_csv
from .overrides import apply_overrides, set_dotted
from .run import run_scenario
from .spec import ScenarioError, as_scenario
from .spec_crossing import is_crossing

__all__ = ["SweepResult", "SerialExecutor", "sweep", "run_case", "run_tasks", "MAX_ATTEMPTS", "SHARED_ROUNDS",
           "EXECUTOR_ERROR", "sweep_cases", "DEFAULT_PLOT_RESULT", "CROSSING_PLOT_RESULT", "default_plot_result",
           "TIMING_COLUMNS"]

#: the scalar plotted by default (present in every case of a vehicle scenario that ran)
DEFAULT_PLOT_RESULT = "max_abs_Y_any_wheel_N"
#: the scalar plotted by default for a bridge crossing (its summary's scalars: the deck's peaks)
CROSSING_PLOT_RESULT = "max_abs_deck_midspan_acceleration_m_s2"
#: columns that depend on the machine, not on the model (left out when comparing runs)
TIMING_COLUMNS = ("solve_seconds",)
MAX_CASES = 100_000


class SerialExecutor(Executor):
    """Runs every submitted call at once in the calling process (a ``concurrent.futures.Executor``)."""

    def submit(self, fn, /, *args, **kwargs):
        f = Future()
        try:
            f.set_result(fn(*args, **kwargs))
        except BaseException as exc:        # delivered through the future, as any executor does
            f.set_exception(exc)
        return f


@dataclass
class SweepResult:
    """``table``: column -> list (one entry per case); ``summaries``/``scenarios``: per case; ``paths``."""

    table: dict
    summaries: list
    scenarios: list
    parameters: dict
    paths: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)


def run_case(scenario: dict, case_dir=None) -> dict:
    """One sweep case (runs in the worker): the summary of :func:`~.scenario.run_scenario` without progress bar;
    an exception becomes ``status = "error: ..."``."""
    try:
        return run_scenario(scenario, case_dir, progress=False).summary
    except Exception as exc:                # one failing case must not stop the sweep
        return {"status": f"error: {type(exc).__name__}: {exc}".splitlines()[0], "scalars": {},
                "solve_seconds": None}


def sweep_cases(base_scenario, parameters: dict) -> tuple[dict, list, list]:
    """``(base, combinations, scenarios)``: the validated base scenario, the parameter combinations (dicts) and the
    validated scenario of every case."""
    base, _ = as_scenario(base_scenario)
    if not isinstance(parameters, dict) or not parameters:
        raise ScenarioError("parameters: expected a non-empty dict {dotted key: [values]}")
    values = {}
    for key, vals in parameters.items():
        probe = json.loads(json.dumps(base))
        set_dotted(probe, key, None)                 # the key must lead somewhere in the scenario
        if isinstance(vals, (str, bytes)) or not hasattr(vals, "__iter__"):
            raise ScenarioError(f"parameter {key!r}: expected a list of values, got {vals!r}")
        vals = list(vals)
        if not vals:
            raise ScenarioError(f"parameter {key!r}: no values")
        values[key] = vals
    n = math.prod(len(v) for v in values.values())
    if n > MAX_CASES:
        raise ScenarioError(f"parameters: {n} cases (more than {MAX_CASES})")
    combos = [dict(zip(values, combo)) for combo in itertools.product(*values.values())]
    scenarios = []
    for i, combo in enumerate(combos):
        desc = ", ".join(f"{k}={v!r}" for k, v in combo.items())
        scenarios.append(apply_overrides(base, combo, source=f"sweep case {i} ({desc})"))
    return base, combos, scenarios


def default_plot_result(base: dict) -> str:
    """The scalar a sweep of the scenario ``base`` (normal form) plots by default: :data:`CROSSING_PLOT_RESULT` for
    a bridge crossing, else :data:`DEFAULT_PLOT_RESULT`."""
    return CROSSING_PLOT_RESULT if is_crossing(base) else DEFAULT_PLOT_RESULT


#: how a result made by :func:`run_tasks` for a task the executor failed (not the task itself) starts its status
EXECUTOR_ERROR = "error: executor"
#: how often a task that killed its worker process alone is run (:func:`run_tasks`)
MAX_ATTEMPTS = 3
#: rounds of the unfinished tasks on a fresh shared pool after a worker died, before each runs alone
SHARED_ROUNDS = 2


def run_tasks(executor, workers, fn, args_list, on_result, failed):
    """Run ``fn(*args)`` for every ``args`` of ``args_list`` through ``executor`` (:func:`resolve_executor`) and call
    ``on_result(i, result)`` as each finishes (once per task).  An exception of the executor rather than of ``fn``
    (its arguments could not be sent, ...) gives ``on_result(i, failed(i, text))``, ``text`` starting with
    :data:`EXECUTOR_ERROR`.

    A worker process that dies breaks Python's process pool and every unfinished task with it, whichever task was
    at fault.  On the local pool (``executor`` None) the unfinished tasks then run again on a fresh pool; after
    :data:`SHARED_ROUNDS` rounds (the first included) that broke, each remaining task runs alone on a pool of its
    own — ``workers`` of them at a time —, up to :data:`MAX_ATTEMPTS` times: a task that kills its worker every time
    is reported failed (never dropped), every other task completes, and a dead worker costs only time.  An executor
    passed in is used as it is (one round; Dask retries a lost worker's tasks itself)."""
    pending = list(range(len(args_list)))
    rounds = 0
    while pending and (rounds < SHARED_ROUNDS or executor is not None):
        pending = _round(executor, workers, fn, args_list, pending, on_result, failed, last=executor is not None)
        rounds += 1
    if not pending:
        return
    lock = threading.Lock()

    def report(i, result):
        with lock:
            on_result(i, result)

    def alone(i):
        for attempt in range(1, MAX_ATTEMPTS + 1):
            if not _round(None, 1, fn, args_list, [i], report, failed, last=attempt == MAX_ATTEMPTS):
                return
    n = max(1, min(int(workers or os.cpu_count() or 1), len(pending)))
    with ThreadPoolExecutor(max_workers=n) as threads:
        for f in [threads.submit(alone, i) for i in pending]:
            f.result()


def _round(executor, workers, fn, args_list, indices, on_result, failed, last: bool) -> list:
    """One round of :func:`run_tasks` on ``indices``; the tasks the pool's breaking left unfinished (none when
    ``last``: they are reported failed)."""
    pool, own = resolve_executor(executor, workers, len(indices))
    broken = []

    def died(i, exc):
        if own and not last:
            broken.append(i)
        else:
            on_result(i, failed(i, f"{EXECUTOR_ERROR}: its worker process died"
                                   + (f" ({MAX_ATTEMPTS} attempt(s) alone)" if own else "") + f": {exc}"))
    try:
        futures = {}
        for i in indices:
            try:
                futures[pool.submit(fn, *args_list[i])] = i
            except BrokenProcessPool as exc:    # broken while the tasks were still being handed over
                died(i, exc)
        for f in as_completed(futures):
            i = futures[f]
            try:
                result = f.result()
            except BrokenProcessPool as exc:
                died(i, exc)
                continue
            except Exception as exc:            # the executor itself failed (could not unpickle, ...)
                result = failed(i, f"{EXECUTOR_ERROR}: {type(exc).__name__}: {exc}")
            on_result(i, result)
    finally:
        if own:
            pool.shutdown(wait=True, cancel_futures=True)
    return sorted(broken)


def resolve_executor(executor, workers, n_cases):
    """(executor, own): the executor to use and whether this function created it (and must shut it down)."""
    if executor is None:
        if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
            raise ValueError(f"workers = {workers!r}: expected a positive integer")
        w = max(1, min(int(workers or os.cpu_count() or 1), n_cases))
        return ProcessPoolExecutor(max_workers=w, mp_context=get_context("spawn")), True
    if not isinstance(executor, Executor) and callable(getattr(executor, "get_executor", None)):
        return executor.get_executor(pure=False), False          # a dask.distributed Client
    if not callable(getattr(executor, "submit", None)):
        raise TypeError(f"executor = {executor!r}: expected a concurrent.futures.Executor (or a dask Client)")
    return executor, False


def sweep(base_scenario, parameters: dict, executor=None, out_dir=None, *, workers: int | None = None,
          plot_result: str | None = None, plot_parameter: str | None = None, write_cases: bool = True,
          progress=print) -> SweepResult:
    """Run the cartesian product of ``parameters`` (dotted key -> list of values) over ``base_scenario`` (a
    scenario file or dict) through ``executor`` (module docstring) and gather one table; with ``out_dir`` write
    ``sweep.csv``, ``sweep.json``, ``sweep_plot.png`` and (``write_cases``) every case's outputs.  ``progress``: a
    callable for one line per finished case (``None``: quiet).  ``plot_result``: the plotted scalar (``None``:
    :func:`default_plot_result`)."""
    base, combos, scenarios = sweep_cases(base_scenario, parameters)
    if plot_result is None:
        plot_result = default_plot_result(base)
    keys = list(combos[0])
    if plot_parameter is None:
        plot_parameter = keys[0]
    elif plot_parameter not in keys:
        raise ScenarioError(f"plot_parameter = {plot_parameter!r}: not a swept parameter ({', '.join(keys)})")
    out = Path(out_dir) if out_dir is not None else None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    case_dirs = [str(out / "cases" / f"case_{i:03d}") if (out is not None and write_cases) else None
                 for i in range(len(scenarios))]
    summaries = [None] * len(scenarios)

    def finished(i, s):
        summaries[i] = s
        if progress:
            v = s.get("scalars", {}).get(plot_result)
            progress(f"  case {i} ({', '.join(f'{k}={combos[i][k]!r}' for k in keys)}): {s['status']}"
                     + (f"; {plot_result} = {v:.6g}" if isinstance(v, (int, float)) and v is not None else ""))

    def failed(i, text):
        return {"status": text.splitlines()[0], "scalars": {}, "solve_seconds": None}
    run_tasks(executor, workers, run_case, list(zip(scenarios, case_dirs)), finished, failed)
    table = _table(combos, case_dirs, summaries)
    result = SweepResult(table=table, summaries=summaries, scenarios=scenarios, parameters=dict(parameters))
    if out is not None:
        result.paths = _write(result, base, out, plot_result, plot_parameter)
    return result


def _table(combos, case_dirs, summaries) -> dict:
    keys = list(combos[0])
    scalar_names = []
    seen = set()
    for s in summaries:
        for k in s.get("scalars", {}):
            if k not in seen:
                seen.add(k)
                scalar_names.append(k)
    cols = ["case", "case_dir"] + keys + ["status", "solve_seconds"] + scalar_names
    table = {c: [] for c in cols}
    for i, (combo, d, s) in enumerate(zip(combos, case_dirs, summaries)):
        table["case"].append(i)
        table["case_dir"].append(d)
        for k in keys:
            table[k].append(combo[k])
        table["status"].append(s.get("status"))
        table["solve_seconds"].append(s.get("solve_seconds"))
        for k in scalar_names:
            table[k].append(s.get("scalars", {}).get(k))
    return table


def _write(result: SweepResult, base: dict, out: Path, plot_result: str, plot_parameter: str) -> dict:
    t = result.table
    paths = {"csv": out / "sweep.csv", "json": out / "sweep.json"}
    write_table_csv(paths["csv"], t)
    write_json(paths["json"], {"base_scenario": base, "parameters": result.parameters, "table": t}, indent=1)
    if plot_result not in t:
        result.notes.append(f"plot_result = {plot_result!r}: not in the table (no case produced it); no plot "
                            f"written. Scalars: {', '.join(c for c in t if c not in ('case', 'case_dir'))}")
    else:
        paths["plot"] = out / "sweep_plot.png"
        plot_sweep(t, list(result.parameters), plot_result, plot_parameter, paths["plot"])
    return {k: str(v) for k, v in paths.items()}


def _number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and v is not None and math.isfinite(v)


def plot_sweep(table: dict, keys: list, result: str, x_key: str, path) -> None:
    """``result`` against ``x_key``, one line per combination of the other parameters (failed cases left out)."""
    plt = pyplot()
    others = [k for k in keys if k != x_key]
    n = len(table["case"])
    xs = table[x_key]
    numeric_x = all(_number(x) for x in xs)
    categories = list(dict.fromkeys(xs)) if not numeric_x else None
    groups = {}
    for i in range(n):
        groups.setdefault(tuple(table[k][i] for k in others), []).append(i)
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for j, (label, rows) in enumerate(groups.items()):
        pts = [(xs[i] if numeric_x else categories.index(xs[i]), table[result][i]) for i in rows
               if table["status"][i] == "ok" and _number(table[result][i])]
        pts.sort()
        if not pts:
            continue
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=f"C{j % 10}",
                label=", ".join(f"{k} = {v}" for k, v in zip(others, label)) or None)
    if not numeric_x:
        ax.set_xticks(range(len(categories)), [str(c) for c in categories])
    ax.set(xlabel=x_key, ylabel=result, title=f"sweep: {result} vs {x_key}")
    ax.title.set_fontsize(9)
    ax.grid(True, alpha=0.3)
    if others:
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
