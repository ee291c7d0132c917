r"""The result of a scenario run (:class:`ScenarioResult`): what the runner (:mod:`.run`) returns and the writer
(:mod:`.outputs`) and the figures (:mod:`.plots`) read."""
from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["ScenarioResult"]


@dataclass
class ScenarioResult:
    """Time series (every recorded column -> array), the summary dict, the written files, the run's outcome and
    whether it is a bridge crossing's (its columns and summary are the ``bridge-crossing`` command's; no figures)."""

    timeseries: dict
    summary: dict
    paths: dict = field(default_factory=dict)
    outcome: object = None
    crossing: bool = False
