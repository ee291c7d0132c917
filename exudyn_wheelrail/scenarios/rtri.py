r"""The rigid-rail RTRI validation case (Montenegro, Neves, Calçada, Tanabe & Sogabe, Computers & Structures 152
(2015) 200–214, Figs. 5–7) with the project's wheel–rail contact: the public import path of the case.

**Every result of the case uses substitute inputs** — the test vehicle, its profiles, the deviation amplitude
and transition and the test speeds are not published (``shared/reference/rtri_scenario.md``).  The published values
and the assumptions are :class:`~exudyn_wheelrail.scenarios.rtri_assumptions.RtriAssumptions` plus the few
output-side assumptions of :class:`~.rtri_case.RtriCaseAssumptions`; :func:`~.rtri_case.assumptions_table` lists
all of them with their origin (an origin that names ``rtri.py`` means the case, this import path), and every
``summary.json`` carries that table.

The case, one job per module (each re-exported here):

* :mod:`.rtri_case` — the case as a spec: :class:`RtriCase` (what is simulated, where the deviation lies, how long
  the run is) → the normalised scenario; the case's assumptions and :func:`assumptions_table`;
* :mod:`.rtri_result` — the result of a run (:class:`RtriResult`) and the averaging window of the smoothed
  lateral-force peak (:data:`AVERAGE_WINDOW_S`);
* :mod:`.rtri_run` — the run and its summary: :func:`run_rtri` (coverage, whole-run and passage peaks, what is left
  after the passage, notes), the time-series columns (:data:`RTRI_COLUMNS`), :func:`write_rtri_outputs`;
* :mod:`.rtri_figures` — the paper's Figs. 5, 6 and 7: :func:`plot_fig5`, :func:`plot_fig6`, :func:`plot_fig7`;
* :mod:`.rtri_sweep` — the sweep over spans and speeds (:func:`run_sweep`: ``sweep.csv``, ``sweep.json``, Fig. 7)
  and what the model gives with the stated assumptions.

Default speeds (justification of ``RtriAssumptions.speeds_km_h`` = 100, 150, 200, 250 km/h)
-------------------------------------------------------------------------------------------
-------------------------------------------------------------------------------------------
The plant runs up to 250 km/h (published); the deviation, a half sine of length L, excites the vehicle at about
f = V/(2L): 0.69–1.74 Hz on the 20 m span and 0.35–0.87 Hz on the 40 m span for 100–250 km/h, which brackets
the car body's lateral, yaw and roll-sway frequencies on the secondary suspension (≈ 0.5–1.5 Hz for the
Manchester coach), so the set spans the resonant range Fig. 7 is about; 100 km/h is the lowest speed for which
the whole car passes the 20 m span within the paper's 2500 steps.  The representative speed for Figs. 5/6 and the
20 m vs 40 m check is 250 km/h (:class:`RtriCaseAssumptions`), the plant's maximum, chosen before any run.
"""
from __future__ import annotations

from .rtri_assumptions import RTRI, RtriAssumptions
from .rtri_case import RTRI_CASE, RTRI_GROUPS, RtriCase, RtriCaseAssumptions, assumptions_table
from .rtri_figures import plot_fig5, plot_fig6, plot_fig7
from .rtri_result import AVERAGE_WINDOW_S, RtriResult
from .rtri_run import (
    RTRI_COLUMNS,
    TIMESERIES_REQUIRED,
    rtri_columns,
    run_rtri,
    write_rtri_outputs,
)
from .rtri_sweep import SWEEP_COLUMNS, run_sweep

__all__ = [
    "RtriCaseAssumptions",
    "RTRI_CASE",
    "RtriCase",
    "RtriResult",
    "RTRI_COLUMNS",
    "TIMESERIES_REQUIRED",
    "assumptions_table",
    "run_rtri",
    "write_rtri_outputs",
    "run_sweep",
    "plot_fig5",
    "plot_fig6",
    "plot_fig7",
    "RTRI",
    "RtriAssumptions",
    "RTRI_GROUPS",
    "AVERAGE_WINDOW_S",
    "rtri_columns",
    "SWEEP_COLUMNS",
]
