r"""How the package's figures are drawn: :func:`pyplot` (on the Agg renderer, files only), :func:`decimated` (a long
series reduced to what the figure's pixels can show, every peak kept), and :class:`FigureProcess`: figures drawn by
a second process that a command starts before it checks its input, builds and solves its run, so that the plotting
library and the figure module are imported on the machine's second CPU meanwhile; once the run's data exist, the
second process starts on the figures while this one writes its tables, and this one then draws from the other end.
This module imports NumPy and the standard library only: the second process imports it, the plotting library and
the figure module it is given (and what that module imports: the scenario figures' module brings the deck's
module and with it SciPy, Exudyn and numba; the RTRI figures' module nothing of the run)."""
from __future__ import annotations

import importlib
import os
import pickle
import shutil
import sys
import tempfile
import warnings

import numpy as np

from ..processes import cpus, start_python

__all__ = ["pyplot", "decimated", "MAX_LINE_POINTS", "FigureProcess", "FIGURE_PROCESS_TIMEOUT_S", "JOIN_UNCLAIMED",
           "joins", "claim"]

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
    """Figures drawn by a second process (module docstring).  ``module``: the name of the figure functions' module
    (imported by the second process when it starts, with the plotting library).  Start it before the run, hand it
    the figures with :meth:`draw` once their data exist, write the tables, then :meth:`wait`.

    The two processes share the figures: the second one draws them from the first on, this one (in :meth:`wait`)
    from the last back, and each figure is drawn by the one that claims it first (a claim is the creation of a file
    named by the figure's number, which only one process can create).  This process joins in only where it gains
    time: before its first figure it imports the plotting library (one to three figures' time), so it joins while
    at least :data:`JOIN_UNCLAIMED` figures are unclaimed, and once it has the library while any is.

    With one CPU, where no second process can be started, or for figures whose data cannot be pickled, every figure
    is drawn here; a second process that fails or runs out of time leaves its figures to be drawn here (with a
    ``RuntimeWarning``; a figure that cannot be drawn raises its error here).  The figures are the same either way:
    the same functions, data and plotting library.
    Also a context manager: leaving it stops a second process that still runs and removes the claims' folder."""

    def __init__(self, module: str | None):
        self.module = module
        self._jobs = None                                 # the figures handed over (draw)
        self._claims = None                               # their claims' folder, when shared with the second process
        self._second = (start_python(serve, {"figures": module}) if module is not None and cpus() > 1 else None)

    @classmethod
    def here(cls) -> FigureProcess:
        """No second process: every figure (of any module) drawn by this process in :meth:`wait`."""
        return cls(None)

    @property
    def aside(self) -> bool:
        """Whether a second process draws (else: this one)."""
        return self._second is not None

    def draw(self, jobs) -> None:
        """Hand over the figures, once: ``jobs``, each ``(function, args)`` with ``function`` a function of the
        module (``args`` picklable).  The second process starts on them at once; this process draws its share in
        :meth:`wait` (the command writes its tables in between)."""
        if self._jobs is not None:
            raise RuntimeError("FigureProcess.draw: the figures are handed over once")
        self._jobs = jobs = list(jobs)
        for function, _ in jobs if self.module is not None else ():
            if function.__module__ != self.module or getattr(sys.modules[self.module], function.__name__,
                                                             None) is not function:
                raise ValueError(f"{function.__qualname__} is not a function of {self.module}")
        if self._second is None:
            return
        try:                                              # the claims' folder, the figures pickled and sent
            self._claims = tempfile.mkdtemp(prefix="exudyn_wheelrail-figures-") if jobs else None
            sent = bool(jobs) and self._second.send({"claims": self._claims,
                                                     "jobs": [(f.__name__, tuple(a)) for f, a in jobs]})
        except Exception:                                 # no folder, data that cannot be pickled: all drawn here
            sent = False
        if not sent:                                      # nothing for the second process to draw
            code = self._second.proc.poll()
            if jobs and code is not None:                 # it had ended: say why
                warnings.warn(f"the second process drawing the figures failed (exit {code}: "
                              f"{self._second.error_line()}); they are drawn here", RuntimeWarning, stacklevel=2)
            self._end_second()

    def wait(self) -> None:
        """Draws this process's share, then returns when every figure handed over is drawn (by the second process,
        or here where it failed).  Whatever happens here (a figure that fails, an interrupt), the second process is
        stopped and the claims' folder removed."""
        jobs, self._jobs = self._jobs or [], []
        claims, second = self._claims, self._second
        try:
            if claims is None:                            # not shared: all here
                self._draw_here(jobs)
                drawn_here = set(range(len(jobs)))
            else:
                drawn_here = set()
                for k in range(len(jobs) - 1, -1, -1):
                    unclaimed = len(jobs) - len(os.listdir(claims))
                    if not joins(unclaimed, "matplotlib.pyplot" in sys.modules) or not claim(claims, k):
                        break
                    self._draw_here(jobs[k:k + 1])
                    drawn_here.add(k)
            if second is None or claims is None:          # nothing handed over: nothing to wait for
                return
            code = second.wait(FIGURE_PROCESS_TIMEOUT_S)
            if code != 0:
                why = "ran out of time" if code is None else f"exit {code}: {second.error_line()}"
                warnings.warn(f"the second process drawing the figures failed ({why}); they are drawn here",
                              RuntimeWarning, stacklevel=2)
                self._draw_here([j for k, j in enumerate(jobs) if k not in drawn_here])
        finally:
            self._end_second()

    def _end_second(self) -> None:
        """Stop the second process if it still runs, close its error output, remove the claims' folder."""
        second, self._second = self._second, None
        if second is not None:
            second.stop()
            second.discard_errors()
        claims, self._claims = self._claims, None
        if claims is not None:
            shutil.rmtree(claims, ignore_errors=True)

    def _draw_here(self, jobs) -> None:
        for function, args in jobs:
            function(*args)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._end_second()
        return False


#: how many figures must still be unclaimed for the command's own process to join in before it has imported the
#: plotting library.  The import takes one to three figures' time (~0.35 s against 0.12–0.3 s a figure) and leaves
#: the plotting library to the interpreter's teardown at exit (~0.1 s, which the second process skips), so joining
#: ends the last figure sooner only when the second process would still draw two more after its current one
JOIN_UNCLAIMED = 3


def joins(unclaimed: int, has_library: bool) -> bool:
    """Whether the command's own process takes the next figure, with ``unclaimed`` figures unclaimed and the
    plotting library imported here (``has_library``) or not (:data:`JOIN_UNCLAIMED`)."""
    return unclaimed >= (1 if has_library else JOIN_UNCLAIMED)


def claim(folder: str, k: int) -> bool:
    """Claim figure ``k`` (create the file ``k`` in ``folder``); False if the other process has claimed it."""
    try:
        os.close(os.open(os.path.join(folder, str(k)), os.O_CREAT | os.O_EXCL | os.O_WRONLY))
    except FileExistsError:
        return False
    return True


def serve(head: dict, stream) -> None:
    """The second process of :class:`FigureProcess` (:func:`~exudyn_wheelrail.processes.start_python`'s entry): the
    plotting library and the figure module ``head["figures"]`` imported, then the figures read from ``stream``
    drawn from the first on, each that it claims, until one is claimed by the other process; until the stream
    ends."""
    pyplot()
    module = importlib.import_module(head["figures"])
    while True:
        try:
            batch = pickle.load(stream)
        except EOFError:
            return
        for k, (name, args) in enumerate(batch["jobs"]):
            if not claim(batch["claims"], k):
                break
            getattr(module, name)(*args)
