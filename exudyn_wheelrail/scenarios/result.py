r"""The result of a scenario run (:class:`ScenarioResult`): what the runner (:mod:`.run`) returns and the writer
(:mod:`.outputs`) and the figures (:mod:`.plots`) read."""
from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["ScenarioResult"]


@dataclass
class ScenarioResult:
    """Time series (every recorded column -> array), the summary dict, the written files and the run's outcome."""

    timeseries: dict
    summary: dict
    paths: dict = field(default_factory=dict)
    outcome: object = None
