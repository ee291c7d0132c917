"""The pipeline of a simulation: spec -> run settings -> build -> run (watched by the monitor) -> record -> outputs.

* :mod:`.settings` — :class:`RunSettings` (solver, time step, duration — the steps derived —, Newton tolerance,
  recording, progress) and :class:`ContactSettings` (creep law, friction, FASTSIM grid, contact geometry,
  wheel–rail element): every field and default declared once; the one list of solvers;
* :mod:`.presets` — accuracy/speed presets producing both;
* :mod:`.runner` — the one solve wrapper: one pre-step function calling the run monitor, the flange-climb check
  (:mod:`.guidance`), the recorder and the progress bar; a :class:`~.runner.RunOutcome` with its status;
* :mod:`.recorder` — the one recorder (columns from probes) and the progress bar;
* :mod:`.status` — the documented run statuses and the command line's exit codes.

The spec (vehicle, track, structure, contact settings) and its builder are the scenarios'
(:func:`exudyn_wheelrail.scenarios.scenario.build_scenario`); the RTRI case is one such spec.
"""
from .settings import ContactSettings, RunSettings, SettingsError
from .status import EXIT_CODES, STATUSES, RunStatus

__all__ = ["RunSettings", "ContactSettings", "SettingsError", "RunStatus", "STATUSES", "EXIT_CODES"]
