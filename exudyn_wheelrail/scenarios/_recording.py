"""Recording one row per accepted time step from an Exudyn pre-step user function (shared by the scenarios)."""
from __future__ import annotations

import math

import numpy as np


class StepRecorder:
    """Base of the scenario recorders: :meth:`pre_step` is the pre-step user function, subclasses implement
    :meth:`record` (one row of ``self.data`` at the state's time) and set ``self.columns``.

    Exudyn calls the pre-step function with the end time of the step it is about to attempt while the state is at
    the end of the last *accepted* step.  A call whose end time is not beyond the previous one means that attempt
    was rejected (Newton did not converge; the solver rolled the state back and retries with a smaller step): the
    state is unchanged.  A row is recorded for every new state on the grid of ``dt`` (states between, after a step
    reduction, are skipped), so the time axis stays uniform."""

    def __init__(self, dt: float, n_rows: int, columns: list[str]):
        self.dt = float(dt)
        self.columns = list(columns)
        self.data = np.full((n_rows, len(self.columns)), np.nan)
        self.n = 0
        self.t_state = 0.0                # time of the model's current state
        self.t_pending = 0.0              # end time of the step attempted after the previous call
        self.t_recorded = -math.inf       # time of the last recorded row
        self.rejected_steps = 0
        self.error = None

    def record(self, mbs, t: float) -> None:          # pragma: no cover - abstract
        raise NotImplementedError

    def on_recorded(self, t: float) -> None:
        """Hook after a row was recorded (e.g. a progress bar)."""

    def pre_step(self, mbs, t):
        t = float(t)
        if t > self.t_pending + 1e-9 * self.dt:
            self.t_state = self.t_pending        # the previous attempt was accepted
        else:
            self.rejected_steps += 1
        self.t_pending = t
        t_state = self.t_state
        try:
            if t_state > self.t_recorded + 0.5 * self.dt and \
                    abs(t_state - round(t_state / self.dt) * self.dt) <= 1e-6 * self.dt:
                self.record(mbs, t_state)
                self.t_recorded = t_state
                self.on_recorded(t_state)
        except Exception as exc:          # a failing recorder must not hide the cause inside Exudyn
            self.error = exc
            return False
        return True

    def next_row(self) -> np.ndarray:
        """The row to fill (the table grows when a run records more rows than planned)."""
        if self.n >= self.data.shape[0]:
            self.data = np.vstack([self.data, np.full_like(self.data, np.nan)])
        return self.data[self.n]

    def table(self) -> dict:
        d = self.data[:self.n]
        return {name: d[:, i].copy() for i, name in enumerate(self.columns)}
