"""Figures drawn by a second process (:class:`exudyn_wheelrail.scenarios.drawing.FigureProcess`) and the second
process itself (:mod:`exudyn_wheelrail.processes`):

* a figure drawn aside is the file drawn here, byte for byte (the same function, data and plotting library: one code
  path), and it is drawn by another process;
* the two processes share the figures, each drawn once; the command's own process joins in only where it gains
  time (the plotting library's import counted);
* a second process that dies, before or while drawing, leaves its figures to be drawn here, with a warning; with one
  CPU none is started;
* only functions of the module the process imported are accepted;
* a second process's failure is reported by its exit code and the last line of its error output; without an
  interpreter to start, none is started.
"""
from __future__ import annotations

import importlib
import os
import sys
from pathlib import Path

import pytest

from exudyn_wheelrail import processes
from exudyn_wheelrail.scenarios import drawing
from exudyn_wheelrail.scenarios.drawing import FigureProcess, pyplot

_FIGURES = '''
import os
import numpy as np
from exudyn_wheelrail.scenarios.drawing import pyplot


def line(path, y):
    """A line with a title and a legend (text, a path and the PNG encoder: what the package's figures use), and the
    drawing process's id beside the figure."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot(np.arange(len(y)), y, label="y")
    ax.set_title("a figure")
    ax.legend()
    fig.savefig(path, dpi=60)
    plt.close(fig)
    with open(str(path) + ".pid", "w") as fh:
        fh.write(str(os.getpid()))


def logged_line(path, y):
    """:func:`line`, the drawing process's id appended to a log beside the figure (one line per drawing)."""
    line(path, y)
    with open(str(path) + ".log", "a") as fh:
        fh.write(str(os.getpid()) + "\\n")


def fails_with(head, stream):
    """A second process's entry that fails, naming ``head["what"]``."""
    raise SystemExit("no " + head["what"])


def fails_in(pid, path, y):
    """Raises in process ``pid``, draws :func:`line` elsewhere."""
    if os.getpid() == pid:
        raise RuntimeError("this figure fails here")
    line(path, y)


def line_with(anything, path, y):
    """:func:`line`; ``anything`` is not used."""
    line(path, y)


def slow_line(path, y):
    """:func:`line` after a second's pause."""
    import time
    time.sleep(1.0)
    line(path, y)


def dies_unless_in(pid, path, y):
    """Ends its process (exit code 3) unless it runs in process ``pid``, where it draws :func:`line`."""
    if os.getpid() != pid:
        os._exit(3)
    line(path, y)
'''


@pytest.fixture
def figures_module(tmp_path, monkeypatch):
    (tmp_path / "figures_for_test.py").write_text(_FIGURES)
    monkeypatch.syspath_prepend(str(tmp_path))      # the second process gets this process's import path
    module = importlib.import_module("figures_for_test")
    yield module
    sys.modules.pop("figures_for_test", None)


def _pid(path) -> int:
    return int(Path(str(path) + ".pid").read_text())


def test_a_figure_drawn_aside_is_the_file_drawn_here(figures_module, tmp_path, monkeypatch):
    y = [0.0, 1.0, 0.5, 2.0]
    monkeypatch.setattr(drawing, "joins", lambda unclaimed, has_library: False)   # the other process draws it
    with FigureProcess(figures_module.__name__) as figures:
        assert figures.aside == (processes.cpus() > 1)
        figures.draw([(figures_module.line, (tmp_path / "aside.png", y))])
        figures.wait()
    figures_module.line(tmp_path / "here.png", y)
    assert (tmp_path / "aside.png").read_bytes() == (tmp_path / "here.png").read_bytes()
    if processes.cpus() > 1:
        assert _pid(tmp_path / "aside.png") != os.getpid()


def test_a_second_process_that_dies_leaves_its_figures_drawn_here(figures_module, tmp_path, monkeypatch):
    if processes.cpus() < 2:
        pytest.skip("one CPU: no second process")
    path = tmp_path / "fig.png"
    monkeypatch.setattr(drawing, "claim", lambda folder, k: False)    # this process claims none: the other does
    with FigureProcess(figures_module.__name__) as figures:
        figures.draw([(figures_module.dies_unless_in, (os.getpid(), path, [1.0, 2.0]))])
        with pytest.warns(RuntimeWarning, match=r"drawing the figures failed \(exit 3"):
            figures.wait()
    assert path.stat().st_size > 0 and _pid(path) == os.getpid()


def test_figures_for_a_process_that_has_ended_are_drawn_here(figures_module, tmp_path):
    if processes.cpus() < 2:
        pytest.skip("one CPU: no second process")
    path = tmp_path / "fig.png"
    with FigureProcess(figures_module.__name__) as figures:
        figures._second.proc.kill()               # the process ends before it is given its figures
        figures._second.proc.wait()
        with pytest.warns(RuntimeWarning, match=r"drawing the figures failed \(exit -?\d+"):
            figures.draw([(figures_module.line, (path, [1.0, 2.0]))])
        figures.wait()
    assert _pid(path) == os.getpid()


def test_a_figure_that_fails_here_stops_the_second_process_and_removes_the_claims(figures_module, tmp_path,
                                                                                    monkeypatch):
    """The second process busy with its first figure (a second's pause), this process claims the last one, which
    raises: the error reaches the caller, the second process is stopped and the claims' folder removed."""
    if processes.cpus() < 2:
        pytest.skip("one CPU: no second process")
    monkeypatch.setattr(drawing, "joins", lambda unclaimed, has_library: True)
    figures = FigureProcess(figures_module.__name__)
    proc = figures._second.proc
    figures.draw([(figures_module.slow_line, (tmp_path / "a.png", [1.0, 2.0])),
                  (figures_module.fails_in, (os.getpid(), tmp_path / "b.png", [1.0, 2.0]))])
    claims = Path(figures._claims)
    with pytest.raises(RuntimeError, match="this figure fails here"):
        figures.wait()
    assert proc.poll() is not None and not claims.exists()


def test_figures_that_cannot_be_pickled_are_drawn_here(figures_module, tmp_path):
    """Data the second process cannot be given (a lock): drawn here, the second process stopped, no claims'
    folder."""
    import threading
    path = tmp_path / "fig.png"
    with FigureProcess(figures_module.__name__) as figures:
        proc = figures._second.proc if figures.aside else None
        figures.draw([(figures_module.line_with, (threading.Lock(), path, [1.0, 2.0]))])
        assert figures._claims is None
        figures.wait()
    assert _pid(path) == os.getpid()
    assert proc is None or proc.poll() is not None


def test_with_nothing_to_draw_the_second_process_is_stopped_at_once(figures_module):
    """No figures handed over (no plots, an empty record): the second process is stopped, not waited for (its
    imports would take a second)."""
    if processes.cpus() < 2:
        pytest.skip("one CPU: no second process")
    figures = FigureProcess(figures_module.__name__)
    proc = figures._second.proc
    figures.draw([])
    figures.wait()
    assert proc.returncode is not None and proc.returncode != 0      # stopped, not ended by itself


def test_the_two_processes_share_the_figures_each_drawn_once(figures_module, tmp_path):
    """Seven figures: each drawn exactly once (the drawing process logged beside it), the second process's a run
    from the first, this process's a run from the last."""
    if processes.cpus() < 2:
        pytest.skip("one CPU: no second process")
    pyplot()                                      # this process has the plotting library: it joins in
    paths = [tmp_path / f"fig{k}.png" for k in range(7)]
    with FigureProcess(figures_module.__name__) as figures:
        figures.draw([(figures_module.logged_line, (p, [1.0, float(k)])) for k, p in enumerate(paths)])
        figures.wait()
    drawers = [Path(str(p) + ".log").read_text().split() for p in paths]
    assert all(len(d) == 1 for d in drawers), drawers                  # each once
    here = [d == [str(os.getpid())] for d in drawers]
    assert here == sorted(here)                                         # a run from the first, a run from the last


def test_this_process_joins_in_only_where_it_gains_time():
    """Without the plotting library, this process's first figure ends about two figures' time later (the import,
    the figure); the second process needs at most one (its current figure) plus one per unclaimed figure: this one
    joins from three unclaimed figures on (not for the two of rtri), with the library from one on."""
    assert [drawing.joins(u, False) for u in range(5)] == [False, False, False, True, True]
    assert [drawing.joins(u, True) for u in range(3)] == [False, True, True]


def test_with_one_cpu_the_figures_are_drawn_here(figures_module, tmp_path, monkeypatch):
    monkeypatch.setattr(drawing, "cpus", lambda: 1)
    path = tmp_path / "fig.png"
    with FigureProcess(figures_module.__name__) as figures:
        assert not figures.aside
        figures.draw([(figures_module.line, (path, [1.0, 2.0]))])
        figures.wait()
    assert _pid(path) == os.getpid()


def test_only_functions_of_the_module_given_are_drawn(figures_module, tmp_path, monkeypatch):
    monkeypatch.setattr(drawing, "cpus", lambda: 1)
    with FigureProcess(figures_module.__name__) as figures, pytest.raises(ValueError, match="is not a function of "
                                                                                    "figures_for_test"):
        figures.draw([(drawing.decimated, ([0.0], [0.0]))])


def test_a_second_process_reports_its_exit_code_and_last_error_line(figures_module):
    second = processes.start_python(figures_module.fails_with, {"what": "figures"})
    assert second is not None
    assert second.wait(60.0) == 1
    assert second.error_line() == "no figures"


def test_no_second_process_without_an_interpreter_to_start(monkeypatch):
    monkeypatch.setattr(processes.sys, "executable", "")
    assert processes.start_python(drawing.serve, {}) is None
