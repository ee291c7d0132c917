"""The bridge crossing of a case built in Python (:func:`run_bridge_crossing`): the scenario's stages — the build
(:func:`~.build.build_crossing`), the run (:func:`~.run.run_model`), the evaluation (:func:`~.run.scenario_summary`)
and the writer (:func:`~.outputs.write_scenario_outputs`: ``timeseries.csv``, ``summary.json``)."""
from __future__ import annotations

from .bridge_crossing_case import BridgeCrossing
from .build import build_crossing
from .outputs import write_scenario_outputs
from .result import ScenarioResult
from .run import run_model, scenario_summary

__all__ = ["run_bridge_crossing"]


def run_bridge_crossing(case: BridgeCrossing, out_dir=None, progress=False) -> ScenarioResult:
    """Build the deck and the load model in Exudyn, run the crossing through the project's runner and evaluate
    it (:mod:`.bridge_crossing` docstring); write ``timeseries.csv`` and ``summary.json`` into ``out_dir`` (None:
    nothing written).  ``progress``: a progress bar — ``True`` on stderr, or a stream to draw it on; ``False``:
    none."""
    h = build_crossing(case)
    outcome = run_model(h, progress=progress, label="bridge-crossing: ")
    result = scenario_summary(h, outcome)
    if out_dir is not None:
        result.paths = write_scenario_outputs(result, out_dir)
    return result
