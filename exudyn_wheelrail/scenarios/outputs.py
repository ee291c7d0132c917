r"""Writing a scenario's results: the time series (CSV, NPZ), ``summary.json`` and the plots (:mod:`.plots`).

:func:`write_csv` and :func:`write_json` are the package's one writer of time series and summaries (the scenarios,
``rtri``, ``bridge-crossing``, ``curving``): CSV with 10 significant digits, JSON indented by 2 with every
non-finite number (NaN, ±inf) written as ``null`` — valid JSON for any reader (:func:`finite_or_none`)."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np

from .drawing import FigureProcess
from .plots import FIGURES, save_group_figure
from .result import ScenarioResult

__all__ = ["jsonable", "finite_or_none", "write_scenario_outputs", "write_csv", "write_json", "table_cell",
           "write_table_csv"]


def jsonable(o):
    """``json.dump``'s ``default``: NumPy scalars and arrays as Python values."""
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.bool_):
        return bool(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, tuple):
        return list(o)
    raise TypeError(f"{type(o).__name__} is not JSON serialisable")


def write_scenario_outputs(result: ScenarioResult, out_dir, figures: FigureProcess | None = None) -> dict:
    """Write ``timeseries.csv`` / ``.npz`` (the written groups), ``summary.json`` and the plots; returns the paths.
    ``figures``: a :class:`~.drawing.FigureProcess` of :mod:`.plots` started before the run (it draws its share of
    the plots while the tables are written); ``None``: drawn here.  A bridge crossing's result (``result.crossing``:
    its columns are the ``bridge-crossing`` command's) writes every recorded column to ``timeseries.csv`` and
    ``summary.json``, no figures."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    s = result.summary
    ts = result.timeseries
    if result.crossing:
        paths = {"timeseries_csv": out / "timeseries.csv", "summary": out / "summary.json"}
        write_csv(paths["timeseries_csv"], ts)
        write_json(paths["summary"], s)
        if figures is not None:
            figures.draw([])
            figures.wait()
        return {k: str(v) for k, v in paths.items()}
    o = s["scenario"]["outputs"]
    paths, plots, jobs = {}, {}, []
    if o["plots"] and ts and len(ts["time_s"]) > 1:
        train = s["model"].get("layout") == "train"
        drawn = ScenarioResult(ts, s)                                   # what the figures read
        for g in o["timeseries"]:
            # the car-body figure draws the points of outputs.carbody_points; a train records them per car
            # (<point>_c<k>), which it does not draw: no figure rather than an empty one
            if g in FIGURES and s["columns"].get(g) and not (train and g == "carbody"):
                plots[f"plot_{g}"] = out / f"plot_{g}.png"
                jobs.append((save_group_figure, (drawn, g, plots[f"plot_{g}"])))
    figures = figures if figures is not None else FigureProcess.here()
    figures.draw(jobs)
    if ts:
        cols = ["time_s", "s_leading_m"] + [c for g in o["timeseries"] for c in s["columns"].get(g, [])]
        if "csv" in o["formats"]:
            paths["timeseries_csv"] = out / "timeseries.csv"
            write_csv(paths["timeseries_csv"], {c: ts[c] for c in cols})
        if "npz" in o["formats"]:
            paths["timeseries_npz"] = out / "timeseries.npz"
            np.savez_compressed(paths["timeseries_npz"], **{c: ts[c] for c in cols})
    paths["summary"] = out / "summary.json"
    write_json(paths["summary"], s)
    figures.wait()
    return {k: str(v) for k, v in {**paths, **plots}.items()}


def write_csv(path, ts: dict) -> None:
    """A time series (column -> array) as CSV, 10 significant digits."""
    cols = list(ts)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        if cols and len(ts[cols[0]]):
            for row in np.column_stack([ts[c] for c in cols]):
                w.writerow([f"{v:.10g}" for v in row])


def table_cell(v) -> str:
    """One cell of a results table's CSV: empty for None, a float in full (``repr``: it reads back exactly), a list
    or dict as JSON, anything else as its text."""
    if v is None:
        return ""
    if isinstance(v, float):
        return repr(float(v))
    if isinstance(v, (list, dict)):
        return json.dumps(v)
    return str(v)


def write_table_csv(path, table: dict) -> None:
    """A results table (column -> list, one entry per row: a sweep's cases, a check's crossings) as CSV
    (:func:`table_cell`)."""
    cols = list(table)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for i in range(len(table[cols[0]]) if cols else 0):
            w.writerow([table_cell(table[c][i]) for c in cols])


def finite_or_none(o):
    """``o`` (dicts, lists, tuples, arrays, numbers) with every non-finite float (NaN, ±inf) replaced by None, the
    containers copied, everything else as it is."""
    if isinstance(o, dict):
        return {k: finite_or_none(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [finite_or_none(v) for v in o]
    if isinstance(o, np.ndarray):
        return finite_or_none(o.tolist())
    if isinstance(o, (float, np.floating)) and not math.isfinite(o):
        return None
    return o


def write_json(path, data: dict, indent: int = 2) -> None:
    """``data`` as JSON, indented by ``indent``, non-finite numbers as ``null`` (:func:`finite_or_none`)."""
    with open(path, "w") as fh:
        json.dump(finite_or_none(data), fh, indent=indent, allow_nan=False,
                  default=lambda o: finite_or_none(jsonable(o)))

