"""The RTRI explorer's matplotlib window: one slider per :data:`~.explorer.PARAMETERS` entry and the Fig. 5/6
quantities, re-run and redrawn when a slider is released.

>>> fig = ExplorerFigure()          # builds the figure and runs the default case   # doctest: +SKIP
>>> fig.show()                      # interactive backend: drag a slider, release -> re-run, redraw

Plots (time axis [s]; shaded: the leading wheelset / the rear bogie's leading wheelset on the deviation)
--------------------------------------------------------------------------------------------------------
1. lateral contact force of the rail on the **right wheel of wheelset 1**, track y (+ right) [kN], raw and its
   10 ms moving average (cf. paper Fig. 6; a right-flange contact is negative, :mod:`..scenarios.rtri`);
2. car-body lateral acceleration above the rear bogie at floor level, track frame [m/s²] (cf. Fig. 5);
3. lateral displacement of wheelset 1 relative to the track [mm], with the track deviation under it [mm].

The previous run stays in light grey for comparison.  A slider changes the value at once but re-runs only on
release of the mouse button (dragging does not queue runs); :meth:`ExplorerFigure.set_values` does the same
programmatically.  The status lines give the update time: the run (build, solve, outputs) and the redraw
(that of the previous update: the figure is drawn once per update).  The figure
says which settings the explorer uses (RK44 1 ms, passage window; :mod:`.explorer`) and that the inputs are
substitutes.
"""
from __future__ import annotations

import time

import numpy as np

from ..scenarios.rtri import AVERAGE_WINDOW_S
from .explorer import PARAMETERS, ExplorerSettings, ExplorerUpdate, RtriExplorer

__all__ = ["ExplorerFigure"]


def _moving_average(t, y, dt, window_s=AVERAGE_WINDOW_S):
    n = max(1, int(round(window_s / dt)))
    if len(y) < n:
        return t, y
    return t[n - 1:] - 0.5 * (n - 1) * dt, np.convolve(y, np.ones(n) / n, mode="valid")


class ExplorerFigure:
    """Build the explorer window (module docstring).  ``explorer`` defaults to a new :class:`RtriExplorer`
    (``settings``, ``values`` as there); the default case is run once while building."""

    def __init__(self, explorer: RtriExplorer | None = None, settings: ExplorerSettings | None = None, **values):
        import matplotlib.pyplot as plt
        from matplotlib.widgets import Slider

        self.plt = plt
        self.explorer = explorer or RtriExplorer(settings=settings, **values)
        if explorer is not None and values:
            self.explorer.values.update(self.explorer._checked(values))
        self.fig = plt.figure(figsize=(13.5, 8.5))
        self.axes = []
        for i in range(3):
            self.axes.append(self.fig.add_axes([0.07, 0.69 - 0.30 * i, 0.55, 0.27],
                                               sharex=self.axes[0] if self.axes else None))
        self.sliders = {}
        for i, p in enumerate(PARAMETERS):
            ax = self.fig.add_axes([0.76, 0.93 - 0.055 * i, 0.17, 0.03])
            s = Slider(ax, p.label, p.lo, p.hi, valinit=self.explorer.values[p.name], valfmt="%.3g")
            s.label.set_fontsize(8)
            s.valtext.set_fontsize(8)
            s.on_changed(self._changed)
            self.sliders[p.name] = s
        self.status = self.fig.text(0.655, 0.47, "", fontsize=8, va="top", family="monospace")
        note = self.explorer.settings.describe().replace(", run until", ",\nrun until")
        self.fig.text(0.655, 0.05, note + "\n(full run: Newmark 1 ms, 2.5 s, online geometry; differences in\n"
                      "exudyn_wheelrail/interactive/explorer.py)\nSUBSTITUTE inputs: Manchester vehicle 1, S1002/UIC60 "
                      "1:40, assumed δ, l_t\n(see the run summary's assumptions)", fontsize=7, va="bottom",
                      color="0.3")
        self._pending = False
        self._busy = False
        self.last: ExplorerUpdate | None = None
        self.last_redraw_s = 0.0
        # blitting: the plots and the status are "animated" (drawn over a saved background of the static parts:
        # sliders, notes); a full draw (resize, slider drag) saves a new background
        self._dynamic = list(self.axes) + [self.status]
        for a in self._dynamic:
            a.set_animated(True)
        self._background = None
        self.fig.canvas.mpl_connect("draw_event", self._on_draw)
        self.fig.canvas.mpl_connect("button_release_event", self._released)
        self.fig.canvas.mpl_connect("key_press_event", self._key)
        self.apply()

    # ------------------------------------------------------------------------------------------------ events
    def _on_draw(self, _event):
        c = self.fig.canvas
        self._background = c.copy_from_bbox(self.fig.bbox)
        self._draw_dynamic()

    def _draw_dynamic(self):
        for a in self._dynamic:
            self.fig.draw_artist(a)
        self.fig.canvas.blit(self.fig.bbox)

    def _redraw(self, full: bool = False):
        c = self.fig.canvas
        if full or self._background is None:
            c.draw()                               # -> draw_event: new background, then the dynamic artists
        else:
            c.restore_region(self._background)
            self._draw_dynamic()

    def _changed(self, _value):
        self._pending = True
        self.status.set_text("release the mouse button (or press Enter) to re-run")

    def _released(self, _event):
        if self._pending and not self._busy:
            self.apply()

    def _key(self, event):
        if event.key == "enter" and not self._busy:
            self.apply()

    # ---------------------------------------------------------------------------------------------- actions
    def set_values(self, **values) -> ExplorerUpdate:
        """Move the sliders to ``values`` (parameter name -> value) and re-run, as a release would."""
        self.explorer._checked(values)
        for k, v in values.items():
            s = self.sliders[k]
            s.eventson = False
            s.set_val(v)
            s.eventson = True
        self._background = None                     # the sliders moved: a full draw saves a new background
        return self.apply()

    def apply(self) -> ExplorerUpdate:
        """Re-run with the sliders' values and redraw; returns the update (``update.seconds``: the run;
        :attr:`last_redraw_s`: the redraw)."""
        self._busy = True
        try:
            values = {k: float(s.val) for k, s in self.sliders.items()}
            try:
                u = self.explorer.update(**values)
            except (RuntimeError, ValueError) as exc:
                self.status.set_text(f"run failed: {exc}"[:300])
                self.fig.canvas.draw_idle()
                raise
            previous, self.last = self.last, u
            t0 = time.perf_counter()
            self.status.set_text(self._status_text(u))      # one draw per update: the redraw time shown is the
            self._draw(u, previous)                         # previous update's
            self._redraw()
            self.last_redraw_s = time.perf_counter() - t0
            self._pending = False
            return u
        finally:
            self._busy = False

    def _status_text(self, u: ExplorerUpdate) -> str:
        p = u.peaks
        return (f"run {u.seconds:.2f} s ({u.case.run.steps} steps) + redraw {self.last_redraw_s:.2f} s (previous"
                f" update)\n"
                f"passage peaks:\n"
                f"  |Y| w1 right     {p['max_abs_lateral_contact_force_w1_right_N'] / 1e3:7.2f} kN\n"
                f"  |Y| 10 ms avg    {p['max_abs_lateral_contact_force_w1_right_10ms_avg_N'] / 1e3:7.2f} kN\n"
                f"  |a| car body     {p['max_abs_carbody_lateral_acceleration_rear_m_s2']:7.3f} m/s²\n"
                f"  |y| w1 rel track {p['max_abs_wheelset1_lateral_rel_track_m'] * 1e3:7.2f} mm\n"
                f"  flange region w1 right: {'yes' if p['flange_contact_w1_right'] else 'no'}")

    def _draw(self, u: ExplorerUpdate, previous: ExplorerUpdate | None):
        ts, s = u.result.timeseries, u.result.summary
        t = ts["time_s"]
        dt = s["dt_s"]
        ax_y, ax_a, ax_d = self.axes
        for ax in self.axes:
            ax.clear()
            c = s["coverage"]
            ax.axvspan(c["t_leading_wheelset_enters_span_s"], c["t_leading_wheelset_leaves_span_s"], color="C1",
                       alpha=0.12)
            t_rear = c["t_rear_bogie_enters_span_s"]
            ax.axvspan(t_rear, t_rear + c["t_leading_wheelset_leaves_span_s"] - c["t_leading_wheelset_enters_span_s"],
                       color="C2", alpha=0.10)
            ax.grid(True, alpha=0.3)
        if previous is not None:
            pt = previous.result.timeseries
            ax_y.plot(*_moving_average(pt["time_s"], pt["lateral_contact_force_w1_right_N"] * 1e-3,
                                       previous.result.summary["dt_s"]), color="0.75", lw=1.0, label="previous run")
            ax_a.plot(pt["time_s"], pt["carbody_lateral_acceleration_rear_m_s2"], color="0.75", lw=1.0,
                      label="previous run")
            ax_d.plot(pt["time_s"], pt["wheelset1_lateral_rel_track_m"] * 1e3, color="0.75", lw=1.0,
                      label="previous run")
        ax_y.plot(t, ts["lateral_contact_force_w1_right_N"] * 1e-3, "C0-", lw=0.6, alpha=0.7, label="raw")
        ax_y.plot(*_moving_average(t, ts["lateral_contact_force_w1_right_N"] * 1e-3, dt), "k-", lw=1.1,
                  label=f"{AVERAGE_WINDOW_S * 1e3:g} ms average")
        fl = ts["flange_contact_w1_right"] > 0.5
        if fl.any():
            ax_y.plot(t[fl], ts["lateral_contact_force_w1_right_N"][fl] * 1e-3, "r.", ms=3, label="flange region")
        ax_y.set_ylabel("Y w1 right [kN]\n(rail on wheel, +y right)", fontsize=8)
        ax_a.plot(t, ts["carbody_lateral_acceleration_rear_m_s2"], "C0-", lw=1.0, label="car body, rear, floor")
        ax_a.set_ylabel("car-body lateral\nacceleration [m/s²]", fontsize=8)
        ax_d.plot(t, ts["wheelset1_lateral_rel_track_m"] * 1e3, "C0-", lw=1.0, label="wheelset 1 relative to track")
        ax_d.plot(t, ts["track_deviation_w1_m"] * 1e3, "C3--", lw=0.8, label="track deviation under wheelset 1")
        ax_d.set_ylabel("lateral [mm]", fontsize=8)
        ax_d.set_xlabel("time [s]")
        v = u.values
        ax_y.set_title(f"RTRI case: {v['speed_km_h']:.0f} km/h, span {v['span_m']:.1f} m, "
                       f"δ {v['deviation_mm']:.1f} mm, μ {v['friction']:.2f}", fontsize=9)
        ax_y.legend(fontsize=7, loc="lower left", ncol=2)
        ax_d.legend(fontsize=7, loc="lower left", ncol=2)
        for ax in self.axes:
            ax.tick_params(labelsize=8)
            ax.locator_params(axis="y", nbins=5)
        for ax in self.axes[:2]:
            ax.tick_params(labelbottom=False)

    # ------------------------------------------------------------------------------------------------ output
    def save(self, path, dpi: int = 100):
        """Save the window as an image."""
        for a in self._dynamic:
            a.set_animated(False)
        try:
            self.fig.savefig(path, dpi=dpi)
        finally:
            for a in self._dynamic:
                a.set_animated(True)

    def show(self):
        """Open the window (blocks until it is closed; needs an interactive matplotlib backend)."""
        self.plt.show()
