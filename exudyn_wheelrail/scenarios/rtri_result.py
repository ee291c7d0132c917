r"""The result of an RTRI case run (:class:`RtriResult`) and the moving-average window of its smoothed lateral-force
peak (:data:`AVERAGE_WINDOW_S`): what the run (:mod:`.rtri_run`) produces and the figures (:mod:`.rtri_figures`)
read.  It imports nothing of the run (the figures' second process unpickles a result).  The public import path of
the case is :mod:`exudyn_wheelrail.scenarios.rtri`."""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["AVERAGE_WINDOW_S", "RtriResult"]

#: moving-average window of the smoothed lateral-force peak: two periods of the wheelset's ~200 Hz vertical bounce
#: on the Hertz spring (removes the bounce spikes, keeps the ~4 Hz lateral motion and the ~15 ms flange events)
AVERAGE_WINDOW_S = 0.010


@dataclass
class RtriResult:
    """Time series (column name -> array; empty without recording), the summary dict, the case
    (:class:`~.rtri_case.RtriCase`) and the run's outcome (:class:`~exudyn_wheelrail.simulation.runner.RunOutcome`);
    the figures read the first two."""

    timeseries: dict
    summary: dict
    case: object = None
    outcome: object = None
