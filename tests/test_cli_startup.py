"""The command line's start-up and progress: building the parser and every ``--help`` load no numerical code, the
contact defaults are declared once, and progress is one option shown the same way by every long command."""
import argparse
import inspect
import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from exudyn_wheelrail import contact_defaults
from exudyn_wheelrail.cli import build_parser
from exudyn_wheelrail.cli.common import ProgressLines, show_progress
from exudyn_wheelrail.scenarios.drawing import decimated
from exudyn_wheelrail.simulation.presets import PRESETS, apply_preset
from exudyn_wheelrail.simulation.recorder import ProgressBar
from exudyn_wheelrail.simulation.settings import ContactSettings, RunSettings

ROOT = Path(__file__).resolve().parents[1]
#: what neither the parser nor any --help may import: the numerical libraries and the compiled code
#: (docs/README.md, "What the command line shows before any work")
HEAVY = ("exudyn", "numpy", "numba", "matplotlib", "scipy", "exudyn_wheelrail.multibody", "exudyn_wheelrail.contact",
         "exudyn_wheelrail.creep")


def _commands():
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sorted(sub.choices)


def test_the_parser_and_every_help_import_no_numerical_code():
    code = ("import sys\n"
            "from exudyn_wheelrail.cli import main\n"
            f"for argv in [[]] + [[c] for c in {_commands()!r}]:\n"
            "    try:\n"
            "        main(argv + ['--help'])\n"
            "    except SystemExit as e:\n"
            "        assert e.code == 0, (argv, e.code)\n"
            f"heavy = {HEAVY!r}\n"
            "print(sorted(m for m in sys.modules if m in heavy or m.startswith(tuple(h + '.' for h in heavy))))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip().splitlines()[-1] == "[]"


def test_contact_defaults_are_declared_once():
    from exudyn_wheelrail.multibody.connector import GEOMETRY_MODES, WheelRailContact
    params = inspect.signature(WheelRailContact.__init__).parameters
    assert params["creep_law"].default is contact_defaults.CREEP_LAW
    assert params["mu"].default is contact_defaults.FRICTION
    assert params["geometry"].default is contact_defaults.GEOMETRY
    assert GEOMETRY_MODES is contact_defaults.GEOMETRY_MODES
    c = ContactSettings()
    assert (c.creep_law, c.friction, c.geometry) == (contact_defaults.CREEP_LAW, contact_defaults.FRICTION,
                                                     contact_defaults.GEOMETRY)


def test_every_preset_applies_to_the_default_settings():
    # a preset's contact values are checked where it is applied (listing the presets loads no creep-law code)
    for name in PRESETS:
        run, contact, record = apply_preset(name, RunSettings(duration_s=1.0), ContactSettings())
        assert record["name"] == name and contact.geometry in contact_defaults.GEOMETRY_MODES


def test_progress_is_one_option_of_every_long_command():
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    for command in ("rtri", "rtri-sweep", "run", "sweep", "validation-report", "creep-table", "bridge-crossing",
                    "bridge-crossing-sweep", "curving"):
        flags = {f for a in sub[command]._actions for f in a.option_strings if a.dest == "progress"}
        assert {"--progress", "--no-progress"} <= flags, command
    base = ["creep-table", "--out", "t.npz"]
    assert parser.parse_args(base).progress is None                    # default: decided by the terminal
    assert parser.parse_args(base + ["--progress"]).progress is True
    assert parser.parse_args(base + ["--no-progress"]).progress is False
    assert parser.parse_args(base + ["--quiet"]).progress is False      # the creep table's former flag
    assert parser.parse_args(["run", "s.toml", "--out", "o", "--no-progress"]).progress is False
    assert show_progress(argparse.Namespace(progress=True)) and not show_progress(argparse.Namespace(progress=False))
    assert show_progress(argparse.Namespace(progress=None)) == sys.stderr.isatty()


def test_a_progress_bar_into_a_file_writes_whole_lines():
    log = io.StringIO()
    bar = ProgressBar(1.0, stream=ProgressLines(log), label="run: ")
    for k in range(1001):
        bar.update(k * 1e-3)
    bar.close("ok")
    text = log.getvalue()
    assert "\r" not in text and text.endswith(" ok\n")
    assert text.count("\n") == 1 and "] 100 %" in text                # a short run: its last state only


def test_run_shows_progress_in_a_pipe_only_when_asked(tmp_path):
    def run(*extra):
        return subprocess.run([sys.executable, "-m", "exudyn_wheelrail", "run",
                               str(ROOT / "examples" / "scenarios" / "harmonic_track.toml"), "--out", str(tmp_path),
                               "--set", "run.duration_s=0.2", "--set", "run.creep_law=fastsim", *extra],
                              capture_output=True, text=True, timeout=600, cwd=ROOT)
    r = run()
    assert r.returncode == 0, r.stderr
    assert "%" not in r.stderr and "status: ok" in r.stdout              # stderr is a pipe: no progress
    r = run("--progress")
    assert r.returncode == 0 and "100 %" in r.stderr and "\r" not in r.stderr and r.stderr.endswith("ok\n")
    assert json.loads((tmp_path / "summary.json").read_text())["steps"] == 200


def test_decimated_lines_keep_every_peak_in_order():
    t = np.linspace(0.0, 1.0, 100_001)
    y = np.sin(40.0 * t) + np.where(np.abs(t - 0.61731) < 2e-5, 3.0, 0.0)
    td, yd = decimated(t, y, max_points=2000)
    assert td.size <= 2000 and np.all(np.diff(td) >= 0.0)
    assert yd.max() == y.max() and yd.min() == y.min()
    assert decimated(t[:500], y[:500])[0].size == 500                 # short lines as they are
