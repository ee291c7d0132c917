r"""The paper's figures for the RTRI case (Montenegro et al. 2015, Figs. 5–7), drawn from a run's time series and
summary (:mod:`.rtri_run`) or from the sweep's rows (:mod:`.rtri_sweep`):

* :func:`plot_fig5` — the car-body lateral acceleration above the rear bogie vs time, the kinematic acceleration
  (track frame) and the body-fixed accelerometer's reading;
* :func:`plot_fig6` — the lateral contact force on the right wheel of the leading wheelset vs time, raw and its
  :data:`~.rtri_result.AVERAGE_WINDOW_S` moving average, with the flange-region contacts marked (the sign is the
  force of the rail on the wheel, :mod:`.rtri_run`);
* :func:`plot_fig7` — the passage peak of the car-body acceleration vs speed, one line per span;
* :func:`plot_carbody_comparison` — the car-body accelerations of the rigid and the flexible car body side by side
  (Fig. 5 style: lateral above each bogie and mid-car, and the vertical ones, where the bending modes act).

The module imports NumPy, :mod:`.drawing` and :mod:`.rtri_result` only: a second process that draws the figures
(:class:`~.drawing.FigureProcess`) imports it while the run is built.  Figs. 5 and 6 shade the time each leading
wheelset of a bogie runs on the deviation and circle the passage peak (``summary["peaks_passage"]``: what ``rtri``
prints and the validation report tabulates).  Every title states that
the inputs are substitutes.
"""
from __future__ import annotations

import numpy as np

from .drawing import decimated, pyplot
from .rtri_result import AVERAGE_WINDOW_S, RtriResult

__all__ = ["plot_fig5", "plot_fig6", "plot_fig7", "plot_carbody_comparison"]


def _title(summary: dict) -> str:
    return (f"RTRI case, span {summary['span_m']:g} m, {summary['speed_km_h']:g} km/h, δ = "
            f"{summary['deviation_amplitude_m'] * 1e3:g} mm, l_t = {summary['transition_length_m']:g} m, "
            f"{summary['solver']['name']}, dt {summary['dt_s'] * 1e3:g} ms\n"
            "SUBSTITUTE inputs (Manchester vehicle 1, S1002/UIC60 1:40; assumed δ, l_t) — see summary.json")


#: size [in] and margins (fractions of the figure) of Figs. 5 and 6: room for the two-line title, the axis labels
#: and the tick labels, fixed, so that the figure is laid out without a layout pass before it is drawn
FIG56_SIZE_IN = (9.0, 4.5)
FIG56_MARGINS = dict(left=0.09, right=0.985, bottom=0.11, top=0.885)


def _start():
    """Figure and axes of Fig. 5 or 6."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=FIG56_SIZE_IN)
    fig.subplots_adjust(**FIG56_MARGINS)
    return plt, fig, ax


def _set_title(ax, summary):
    """The case's title of Fig. 5 or 6, small, at the top of the axes: placed there, not by a layout pass that
    measures the axes' decorations (~0.05 s a figure; nothing sits above these axes)."""
    ax.set_title(_title(summary), fontsize=8, y=1.0)


def _finish(plt, fig, ax, path):
    """Common finish of the Fig. 5/6 plots: grid, legend, saved (drawn once) and closed."""
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _spans(ax, summary):
    c = summary["coverage"]
    ax.axvspan(c["t_leading_wheelset_enters_span_s"], c["t_leading_wheelset_leaves_span_s"], color="C1", alpha=0.12,
               label="leading wheelset on the deviation")
    t_rear_leave = c["t_rear_bogie_enters_span_s"] + (c["t_leading_wheelset_leaves_span_s"] -
                                                      c["t_leading_wheelset_enters_span_s"])
    ax.axvspan(c["t_rear_bogie_enters_span_s"], t_rear_leave, color="C2", alpha=0.10,
               label="rear bogie's leading wheelset on the deviation")


def _passage(ax, summary, t_peak_s, y_plotted, text):
    """The end of the passage window (the window of ``peaks_passage``: what ``rtri`` prints and the validation
    report tabulates) and the passage peak, circled on the plotted curve (``y_plotted`` in the plot's unit)."""
    c = summary["coverage"]
    t_end = c["t_needed_with_run_out_s"]
    if t_end <= c["t_end_s"]:
        ax.axvline(t_end, color="0.3", ls=":", lw=1.0, label=f"end of the passage window ({t_end:.3f} s)")
    ax.plot([t_peak_s], [y_plotted], "o", mfc="none", mec="k", ms=8, gid="passage_peak",
            label=f"passage peak {text} at {t_peak_s:.3f} s")


def plot_fig5(result: RtriResult, path):
    """Car-body lateral acceleration above the rear bogie vs time (cf. paper Fig. 5)."""
    plt, fig, ax = _start()
    ts, s = result.timeseries, result.summary
    _spans(ax, s)
    ax.plot(*decimated(ts["time_s"], ts["carbody_lateral_acceleration_rear_m_s2"]), "C0-", lw=1.0,
            label="car body above the rear bogie, floor level (track frame)")
    ax.plot(*decimated(ts["time_s"], ts["carbody_lateral_accelerometer_rear_m_s2"]), "C3-", lw=0.6, alpha=0.6,
            label="same point, body-fixed accelerometer (incl. g·roll)")
    p = s.get("peaks_passage") or {}
    if "time_of_max_carbody_acceleration_s" in p:
        t_pk = p["time_of_max_carbody_acceleration_s"]
        i = int(np.argmin(np.abs(ts["time_s"] - t_pk)))
        _passage(ax, s, t_pk, ts["carbody_lateral_acceleration_rear_m_s2"][i],
                 f"|a| = {p['max_abs_carbody_lateral_acceleration_rear_m_s2']:.3f} m/s²")
    ax.set(xlabel="time [s]", ylabel="car-body lateral acceleration [m/s²]")
    _set_title(ax, s)
    _finish(plt, fig, ax, path)


def plot_fig6(result: RtriResult, path):
    """Lateral contact force on the right wheel of the leading wheelset vs time (cf. paper Fig. 6)."""
    plt, fig, ax = _start()
    ts, s = result.timeseries, result.summary
    _spans(ax, s)
    t = ts["time_s"]
    ax.plot(*decimated(t, ts["lateral_contact_force_w1_right_N"] * 1e-3), "C0-", lw=0.8,
            label="rail on wheel, track y (+ right): right-flange contact is negative")
    n = max(1, int(round(AVERAGE_WINDOW_S / s["dt_s"])))
    if len(t) >= n:
        avg = np.convolve(ts["lateral_contact_force_w1_right_N"], np.ones(n) / n, mode="valid")
        ax.plot(*decimated(t[n - 1:] - 0.5 * (n - 1) * s["dt_s"], avg * 1e-3), "k-", lw=1.2,
                label=f"{AVERAGE_WINDOW_S * 1e3:g} ms moving average")
    fl = ts["flange_contact_w1_right"] > 0.5
    if fl.any():
        ax.plot(t[fl], ts["lateral_contact_force_w1_right_N"][fl] * 1e-3, "r.", ms=3,
                label="flange region in contact")
    p = s.get("peaks_passage") or {}
    if "time_of_max_abs_lateral_force_10ms_avg_s" in p:
        t_pk = p["time_of_max_abs_lateral_force_10ms_avg_s"]
        k = int(np.argmin(np.abs(t[n - 1:] - 0.5 * (n - 1) * s["dt_s"] - t_pk)))
        _passage(ax, s, t_pk, avg[k] * 1e-3, f"|Y| ({AVERAGE_WINDOW_S * 1e3:g} ms average) = "
                 f"{p['max_abs_lateral_contact_force_w1_right_10ms_avg_N'] * 1e-3:.2f} kN")
    ax.set(xlabel="time [s]", ylabel="Y, wheelset 1 (leading), right wheel [kN]")
    _set_title(ax, s)
    _finish(plt, fig, ax, path)


def plot_fig7(rows, path):
    """Maximum car-body lateral acceleration vs speed, one line per span (cf. paper Fig. 7)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    flange_labelled = False
    for i, L in enumerate(sorted({r["span_m"] for r in rows})):
        sel = sorted((r for r in rows if r["span_m"] == L and r["status"] == "ok"), key=lambda r: r["speed_km_h"])
        if not sel:
            continue
        v = [r["speed_km_h"] for r in sel]
        a = [r["max_abs_carbody_lateral_acceleration_rear_m_s2"] for r in sel]
        ax.plot(v, a, "o-", color=f"C{i}", label=f"L = {L:g} m")
        fl = [r for r in sel if r["flange_contact_w1_right"]]
        if fl:
            ax.plot([r["speed_km_h"] for r in fl], [r["max_abs_carbody_lateral_acceleration_rear_m_s2"] for r in fl],
                    "s", mfc="none", mec="r", ms=10,
                    label=None if flange_labelled else "flange contact (wheelset 1, right wheel)")
            flange_labelled = True
    ax.set(xlabel="speed [km/h]", ylabel="passage peak |a|, car body, rear [m/s²]",
           title="RTRI case — SUBSTITUTE inputs (Manchester vehicle 1, assumed δ, l_t)")
    ax.title.set_fontsize(9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_carbody_comparison(results: dict, path):
    """Car-body accelerations of the runs in ``results`` (car-body model name -> :class:`~.rtri_result.RtriResult`,
    e.g. rigid and flexible, recorded at the same points) side by side: one row per point (front bogie, mid-car,
    rear bogie), lateral (left column) and vertical (right column) kinematic acceleration vs time, with each run's
    Sperling index of the point (``summary["comfort"]``) in the legend."""
    plt = pyplot()
    first = next(iter(results.values()))
    points = [p for p in ("front", "centre", "rear")
              if all(f"carbody_lateral_acceleration_{p}_m_s2" in r.timeseries for r in results.values())]
    fig, axes = plt.subplots(len(points), 2, figsize=(12, 2.6 * len(points) + 0.8), sharex=True, squeeze=False)
    for i, p in enumerate(points):
        for j, d in enumerate(("lateral", "vertical")):
            ax = axes[i, j]
            for k, (name, r) in enumerate(results.items()):
                wz = r.summary.get("comfort", {}).get(p, {}).get(d, {}).get("sperling_Wz")
                label = f"{name} car body" + (f" (Sperling Wz {wz:.2f})" if wz is not None else "")
                ax.plot(*decimated(r.timeseries["time_s"], r.timeseries[f"carbody_{d}_acceleration_{p}_m_s2"]),
                        f"C{k}-", lw=0.9 if k == 0 else 0.7, alpha=1.0 if k == 0 else 0.85, label=label)
            ax.set_ylabel(f"{d} acc. {p} [m/s²]", fontsize=8)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    fig.suptitle("Car-body accelerations (track frame, no gravity), rigid vs flexible car body — " + _title(
        first.summary), fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
