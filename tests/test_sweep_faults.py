"""Faults of the sweeps' executors and the sweeps' speed grid.

* A worker process that dies breaks Python's process pool and every unfinished task with it: on the local pool
  those tasks run again on a fresh pool (``sweep.run_tasks``) — every result arrives, the task that killed its
  worker once included; a task that kills its worker every time is reported failed after ``MAX_ATTEMPTS``, the
  others complete.  The same through ``bridge-crossing``'s speed sweep with one of two workers killed from outside
  while it runs: every speed ends ``ok`` with the numbers of a serial run (the same computation: bit-equality).
* Speeds are exact decimals: a speed given in km/h, held in m/s and reported in km/h again is the given decimal
  (``conventions.speed_km_h``), and the grid ``--speed-range-kmh FIRST LAST STEP`` is FIRST + k STEP in decimal
  arithmetic.
"""
from __future__ import annotations

import multiprocessing
import os
import signal
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))        # the workers import the tasks' module

import sweep_worker_tasks as tasks                               # noqa: E402

from exudyn_wheelrail.conventions import speed_km_h              # noqa: E402
from exudyn_wheelrail.scenarios import bridge_crossing as bc      # noqa: E402
from exudyn_wheelrail.scenarios.sweep import MAX_ATTEMPTS, SerialExecutor, run_tasks   # noqa: E402
from exudyn_wheelrail.structures.load_models import AxleTrain   # noqa: E402


def _run(fn, args_list, workers=2):
    results = {}
    run_tasks(None, workers, fn, args_list, results.__setitem__, lambda i, text: {"failed": text})
    return [results[i] for i in range(len(args_list))]


def test_a_task_that_kills_its_worker_once_is_run_again(tmp_path):
    args = [(str(tmp_path / f"m{i}"), i) for i in range(6)]
    (tmp_path / "m0").write_text("")           # every task but two dies on its first run
    (tmp_path / "m2").write_text("")
    assert _run(tasks.die_once, args) == list(range(6))


def test_a_task_that_always_kills_its_worker_is_reported_and_the_others_complete(tmp_path):
    out = _run(_Dispatch(), [(i,) for i in range(5)])
    assert [out[i] for i in (0, 1, 3, 4)] == [0, 1, 9, 16]
    assert "worker process died" in out[2]["failed"] and f"({MAX_ATTEMPTS} attempt(s) alone)" in out[2]["failed"]


class _Dispatch:
    """Picklable: task 2 kills its worker, the others square their value."""

    def __call__(self, i):
        return tasks.die_always(i) if i == 2 else tasks.square(i)


def test_a_speed_sweep_survives_a_worker_killed_from_outside():
    case = bc.BridgeCrossing(span_m=20.0, mass_kg_m=15e3, f1_Hz=5.0, damping_ratio=0.01, n_modes=2,
                             axles=AxleTrain(np.array([0.0, 2.5, 17.5, 20.0]), np.full(4, 170e3)), speed_m_s=50.0)
    speeds_kmh = [150.0 + 20.0 * k for k in range(6)]
    speeds = [v / 3.6 for v in speeds_kmh]
    serial = bc.speed_sweep(case, speeds, executor=SerialExecutor(), progress=None)
    killed = []

    def kill_one_worker(line):
        if not killed:
            children = multiprocessing.active_children()
            if children:
                os.kill(children[0].pid, signal.SIGKILL)
                killed.append(children[0].pid)
    result = bc.speed_sweep(case, speeds, workers=2, progress=kill_one_worker)
    assert killed, "no worker was running when the first speed finished"
    assert result.table["status"] == ["ok"] * len(speeds)
    assert result.table["speed_km_h"] == speeds_kmh                   # exact decimals
    for key in ("max_abs_deck_midspan_displacement_m", "max_abs_deck_midspan_acceleration_m_s2"):
        assert result.table[key] == serial.table[key]                 # the same computation: bit-equality


@pytest.mark.parametrize("v", [150.0, 240.0, 287.5, 300.0, 333.3, 36.0, 0.1])
def test_a_speed_in_km_h_survives_the_round_trip_through_m_s(v):
    assert speed_km_h(v / 3.6) == v
    assert abs(speed_km_h(np.nextafter(v / 3.6, 1e9)) - v) <= 1e-12 * v


def test_the_speed_range_is_a_grid_of_exact_decimals(tmp_path):
    from exudyn_wheelrail.cli.bridge import _sweep_speeds_kmh

    class Args:
        speeds_kmh = None
        speed_range_kmh = (150.0, 340.0, 10.1)
    got = _sweep_speeds_kmh(Args)
    assert got == [float(f"{150 + k * 10.1:.10g}") for k in range(19)]      # 150, 160.1, ... 331.8
    Args.speed_range_kmh = (150.0, 340.0, 10.0)
    assert _sweep_speeds_kmh(Args) == [150.0 + 10.0 * k for k in range(20)]
