"""What a saved matplotlib figure shows: the axis labels and every line's label, gid and data, read from the
figure's artists when it is saved (``Figure.savefig`` wrapped), so a test checks the drawn data, not the code that
meant to draw it."""
from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np


def describe(fig) -> list[dict]:
    """Per axes: ``xlabel``, ``ylabel``, ``title`` and ``lines`` (label, gid, x, y as float arrays)."""
    out = []
    for ax in fig.axes:
        lines = [{"label": ln.get_label(), "gid": ln.get_gid(),
                  "x": np.asarray(ln.get_xdata(), dtype=float), "y": np.asarray(ln.get_ydata(), dtype=float)}
                 for ln in ax.get_lines()]
        legend = ax.get_legend()
        out.append({"xlabel": ax.get_xlabel(), "ylabel": ax.get_ylabel(), "title": ax.get_title(), "lines": lines,
                    "legend": [t.get_text() for t in legend.get_texts()] if legend else []})
    return out


@contextlib.contextmanager
def saved_figures(monkeypatch):
    """Within the block, every ``Figure.savefig(path)`` also records ``describe(fig)`` under the file name:
    yields the dict ``{file name: [axes descriptions]}``."""
    from matplotlib.figure import Figure
    captured = {}
    original = Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        captured[Path(str(fname)).name] = describe(self)
        return original(self, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", savefig)
    yield captured
