"""The bridge crossing's run: the deck and the load model built in Exudyn, one run through the project's runner,
its evaluation (:func:`run_bridge_crossing`, :class:`BridgeCrossingResult`) and its files
(:func:`write_bridge_crossing_outputs`: ``timeseries.csv``, ``summary.json``)."""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import exudyn as exu
import numpy as np

from ..simulation.recorder import PROGRESS_MIN_STEPS, ProgressBar, Recorder
from ..simulation.runner import run
from ..simulation.settings import RunSettings
from ..structures.bridge_exudyn import add_bridge
from .bridge_crossing_case import BridgeCrossing, default_dt_s
from .bridge_crossing_deck import deck_modes, en1990_cutoff_Hz
from .bridge_crossing_loads import resolve_load_model
from .bridge_crossing_probes import DeckProbe, FirstAxleProbe, deck_columns
from .bridge_crossing_summary import crossing_summary, deck_status, deflection_bound_m, midspan_displacement_columns
from .outputs import write_csv, write_json

__all__ = ["BridgeCrossingResult", "run_bridge_crossing", "write_bridge_crossing_outputs"]


@dataclass
class BridgeCrossingResult:
    """``timeseries`` (column -> array), ``summary`` (the contents of summary.json), the runner's ``outcome``,
    the written ``paths``."""

    timeseries: dict
    summary: dict
    outcome: object = None
    paths: dict = field(default_factory=dict)


def run_bridge_crossing(case: BridgeCrossing, out_dir=None, progress=False) -> BridgeCrossingResult:
    """Build the deck and the load model in Exudyn, run the crossing through the project's runner and evaluate
    it (module docstring); write ``timeseries.csv`` and ``summary.json`` into ``out_dir`` (None: nothing written).
    ``progress``: a progress bar — ``True`` on stderr, or a stream to draw it on; ``False``: none."""
    load_model = resolve_load_model(case.model)
    load_model.check(case)
    t_build = time.perf_counter()
    deck = deck_modes(case)
    modes = deck.modes
    cutoffs = [en1990_cutoff_Hz(case, k) for k in range(case.n_spans)]
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    bridge = add_bridge(mbs, modes, "modal", name="deck")
    handle = load_model.build(mbs, case, bridge)
    axle_x = np.asarray(handle.axle_x_m, dtype=float)
    duration = (float(axle_x[-1]) + case.length_m) / case.speed_m_s + case.free_vibration_s
    dt = case.dt_s
    if dt is None:
        dt = default_dt_s(case) if handle.max_dt_s is None else min(default_dt_s(case), float(handle.max_dt_s))
    settings = RunSettings(solver=case.solver, dt_s=dt, duration_s=duration, progress=bool(progress))
    probes = [FirstAxleProbe(case, axle_x, handle.axle_load_N),
              DeckProbe(case, bridge, deck, handle.modal_forces, cutoffs)]
    probes += list(handle.probes)
    recorder = Recorder(probes, n_rows_hint=settings.steps + 2)
    mbs.Assemble()
    if handle.contact is not None:
        handle.contact.warm_up(mbs, jacobian=settings.implicit)       # compiled code loaded before the timed solve
    build_seconds = time.perf_counter() - t_build
    bar = None
    if progress and settings.steps >= PROGRESS_MIN_STEPS:
        bar = ProgressBar(settings.end_time_s, stream=progress, label="bridge-crossing: ")
    outcome = run(mbs, settings, handle.contact, speed_m_s=case.speed_m_s, recorder=recorder, progress=bar)
    if bar is not None:
        bar.close(outcome.status.kind)
    ts = recorder.table()
    status = deck_status(outcome.status, ts, deflection_bound_m(modes, case, handle, settings.end_time_s),
                         deck_columns(case), midspan_displacement_columns(case))
    summary = crossing_summary(case, deck, cutoffs, handle, settings, outcome, ts, build_seconds, status)
    result = BridgeCrossingResult(timeseries=ts, summary=summary, outcome=outcome)
    if out_dir is not None:
        result.paths = write_bridge_crossing_outputs(result, out_dir)
    return result


def write_bridge_crossing_outputs(result: BridgeCrossingResult, out_dir) -> dict:
    """``timeseries.csv`` (every recorded column) and ``summary.json`` into ``out_dir`` (created); returns the
    paths."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"timeseries_csv": out / "timeseries.csv", "summary": out / "summary.json"}
    write_csv(paths["timeseries_csv"], result.timeseries)
    write_json(paths["summary"], result.summary)
    return {k: str(v) for k, v in paths.items()}
