r"""How the package's figures are drawn: :func:`pyplot` (on the Agg renderer, files only), :func:`decimated` (a long
series reduced to what the figure's pixels can show, every peak kept), and :class:`FigureProcess`: figures drawn by
a second process that a command starts before it builds and solves its run, so that the plotting library is
imported on the machine's second CPU meanwhile and the figures are drawn while this process writes its tables.
This module imports NumPy and the standard library only: the second process imports it, the figure module it is
given and the plotting library, nothing of the run."""
from __future__ import annotations

import importlib
import pickle
import sys
import warnings

import numpy as np

from ..processes import cpus, start_python

__all__ = ["pyplot", "decimated", "MAX_LINE_POINTS", "FigureProcess", "FIGURE_PROCESS_TIMEOUT_S"]

#: most points of a drawn line (:func:`decimated`)
MAX_LINE_POINTS = 4000


def pyplot():
    """``matplotlib.pyplot`` on the Agg renderer (files only, no window)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def decimated(x, y, max_points: int = MAX_LINE_POINTS):
    """``(x, y)`` of a line to draw: unchanged up to ``max_points`` points; a longer series is cut into
    ``max_points / 2`` consecutive slices and each is drawn by its smallest and largest sample, in their order — the
    envelope at a resolution finer than the figure's pixel columns, every peak kept."""
    x, y = np.asarray(x), np.asarray(y)
    n = y.size
    if n <= max_points:
        return x, y
    m = max_points // 2
    k = -(-n // m)                                        # samples per slice (the last one padded with its end)
    rows = np.pad(y, (0, m * k - n), mode="edge").reshape(m, k)
    first = np.arange(m) * k
    i_min, i_max = first + np.argmin(rows, axis=1), first + np.argmax(rows, axis=1)
    idx = np.minimum(np.column_stack([np.minimum(i_min, i_max), np.maximum(i_min, i_max)]).ravel(), n - 1)
    return x[idx], y[idx]


#: how long :meth:`FigureProcess.wait` waits for the second process's figures [s] (a second or two of drawing);
#: then it is stopped and the figures are drawn here
FIGURE_PROCESS_TIMEOUT_S = 120.0


class FigureProcess:
    """Figures drawn by a second process (module docstring).  ``module``: the figure functions' module (imported by
    the second process when it starts, with the plotting library).  Start it before the run, hand it the figures
    with :meth:`draw` once their data exist, do other work, then :meth:`wait`.  With one CPU, or where no second
    process can be started, the figures are drawn here (by :meth:`draw`, at once); a second process that fails or
    runs out of time leaves its figures to be drawn here (with a ``RuntimeWarning``; a figure that cannot be drawn
    raises its error here).  The figures are the same either way: the same functions, data and plotting library.
    Also a context manager: leaving it stops a second process that still runs."""

    def __init__(self, module):
        self._module = module
        self._aside = []                                  # the jobs handed to the second process
        self._second = (start_python(_PROGRAM, {"drawing": __name__, "file": __file__, "module": module.__name__})
                        if cpus() > 1 else None)

    @property
    def aside(self) -> bool:
        """Whether a second process draws (else: this one)."""
        return self._second is not None

    def draw(self, jobs) -> None:
        """Draw ``jobs``, each ``(function, args)`` with ``function`` a function of the module given (``args``
        picklable): handed to the second process, or drawn here at once."""
        jobs = list(jobs)
        for function, _ in jobs:
            if getattr(self._module, function.__name__, None) is not function:
                raise ValueError(f"{function.__qualname__} is not a function of {self._module.__name__}")
        if self._second is not None and self._second.send([(f.__name__, tuple(a)) for f, a in jobs]):
            self._aside += jobs
        else:
            self._draw_here(jobs)

    def wait(self) -> None:
        """Returns when every figure handed over is drawn (by the second process, or here where it failed)."""
        second, self._second = self._second, None
        if second is None:
            return
        code = second.wait(FIGURE_PROCESS_TIMEOUT_S)
        if code != 0:
            why = "ran out of time" if code is None else f"exit {code}: {second.error_line()}"
            warnings.warn(f"the second process drawing the figures failed ({why}); they are drawn here",
                          RuntimeWarning, stacklevel=2)
            self._draw_here(self._aside)
        second.discard_errors()

    def _draw_here(self, jobs) -> None:
        for function, args in jobs:
            function(*args)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self._second is not None:
            self._second.stop()
            self._second.discard_errors()
            self._second = None
        return False


def serve(head: dict, stream) -> None:
    """The second process of :class:`FigureProcess`: the plotting library and the figure module imported, then each
    list of jobs read from ``stream`` drawn, until the stream ends."""
    if __file__ != head["file"]:
        sys.exit("another copy of the package: " + __file__)
    pyplot()
    module = importlib.import_module(head["module"])
    while True:
        try:
            jobs = pickle.load(stream)
        except EOFError:
            return
        for name, args in jobs:
            getattr(module, name)(*args)


#: the second process's program (after :func:`~exudyn_wheelrail.processes.start_python`'s prelude); its figures are
#: written and closed by then, so it ends without the interpreter's teardown of the plotting library (~0.1 s the
#: command would wait for)
_PROGRAM = ("import importlib, os\n"
            "importlib.import_module(head['drawing']).serve(head, sys.stdin.buffer)\n"
            "sys.stdout.flush()\n"
            "sys.stderr.flush()\n"
            "os._exit(0)\n")
