"""docs/tutorial.md runs as written: its ```python blocks, in order, in one namespace, with nothing set up by the
test (a reader copying them into one session gets the same).  Blocks fenced ```python interactive``` need a screen
and a person (they open the renderer and wait for its window to be closed): they are compiled, and every name they
use must be defined by the blocks before them.

The only change to the text: the simulated time of section 5 is cut from 2 s to 20 ms (40 steps) to keep the
test short.  What the blocks computed is checked for what holds whatever the motion: one recorded row per step, wheel
loads finite and never pulling (Q >= 0), and at t = 0 the right wheel loaded more than the left (the wheelset starts
3 mm to the right at zero roll: the right wheel touches at a larger rolling radius, so it is pressed deeper).  The
physics of the same model over 0.6 s is tested with the example (tests/test_connector.py).
"""
from __future__ import annotations

import ast
import builtins
import re
from pathlib import Path

import numpy as np
import pytest

TUTORIAL = Path(__file__).resolve().parents[1] / "docs" / "tutorial.md"
FENCE = re.compile(r"^```(python[^\n]*)\n(.*?)^```[ \t]*$", re.S | re.M)
SIMULATED_TIME = ("end_time_s, step_s = 2.0, 5e-4", "end_time_s, step_s = 0.02, 5e-4")


def tutorial_blocks() -> list[tuple[str, str]]:
    """(info string, code) of every ```python block, in the order of the text."""
    return [(info.strip(), code) for info, code in FENCE.findall(TUTORIAL.read_text(encoding="utf-8"))]


def used_before_defined(code: str) -> set[str]:
    """Names a block reads that it does not define itself first (module level; functions see the module)."""
    tree = ast.parse(code)
    defined, needed = set(), set()
    for stmt in tree.body:
        stored = set()
        for node in ast.walk(stmt):
            if isinstance(node, ast.Name):
                if isinstance(node.ctx, ast.Store):
                    stored.add(node.id)
                elif node.id not in defined:
                    needed.add(node.id)
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                stored |= {(a.asname or a.name).split(".")[0] for a in node.names}
            elif isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                stored.add(node.name)
            elif isinstance(node, ast.arg):
                stored.add(node.arg)
        defined |= stored
    return needed - defined - set(dir(builtins))


def test_tutorial_blocks_run_in_order(capsys):
    blocks = tutorial_blocks()
    runnable = [code for info, code in blocks if info == "python"]
    interactive = [code for info, code in blocks if info == "python interactive"]
    assert len(runnable) + len(interactive) == len(blocks), [info for info, _ in blocks]   # no unknown fences
    assert len(runnable) >= 7 and interactive
    assert sum(code.count(SIMULATED_TIME[0]) for code in runnable) == 1, "section 5's simulated time line changed"
    ns: dict = {"__name__": "tutorial"}
    for i, (info, code) in enumerate(blocks):
        where = f"{TUTORIAL.name}, python block {i + 1}"
        if info == "python interactive":
            compile(code, where, "exec")
            missing = {name for name in used_before_defined(code) if name not in ns}
            assert not missing, f"{where} uses names no earlier block defines: {sorted(missing)}"
            continue
        exec(compile(code.replace(*SIMULATED_TIME), where, "exec"), ns)

    # section 5 ran the hand-made wheelset: one row per step, and loads near the static wheel load
    history = np.array(ns["history"])
    steps = round(0.02 / 5e-4)
    assert steps <= len(history) <= steps + 1
    assert history[-1, 0] == pytest.approx(0.02, abs=5e-4)
    Q = history[:, 1:]                                       # (right, left) wheel loads [N]
    assert np.all(np.isfinite(Q)) and np.all(Q >= 0.0) and Q[0, 0] > Q[0, 1]
    F = ns["F"]                                              # right wheel, track frame, z down: F_z = -Q
    assert np.all(np.isfinite(F)) and F[2] <= 0.0
    # section 6 built the vehicle in a new system; section 11 ran the explorer once
    assert len(ns["model"].wheelset_nodes) == 4 and ns["contact"].n_coordinates == 4 * 6
    assert ns["u"].peaks["max_abs_carbody_lateral_acceleration_rear_m_s2"] > 0.0
    assert "3-D view" not in capsys.readouterr().err                  # the interactive block did not run
