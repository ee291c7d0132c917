r"""The figures of a scenario run: one per column group (``plot_<group>.png``), each quantity with its unit on its
axis, the criteria's limits as the run applied them."""
from __future__ import annotations

import re

import numpy as np

from ..analysis import comfort, safety
from ..analysis.safety import prudhomme_limit_N
from .deck import CHECK_POINTS_X_OVER_L, EN1990_DECK_ACCELERATION_LIMITS_M_S2
from .drawing import pyplot
from .result import ScenarioResult

__all__ = ["FIGURES", "group_figure", "save_group_figure"]

# ----------------------------------------------------------------------------------------------------- plots
# What a plot shows (one quantity per axis, its unit in the label) and how the lines are named: wheelset j
# (1 = leading) and the side as the user reads it.  Colours: one per side in the per-wheel plots, one per wheelset
# (or car-body point) where the wheelsets share an axis.
_SIDE_COLOUR = {"right": "C0", "left": "C3"}
_SIDE_NOTE = "right/left: looking in the running direction (track y + right)"
_WHEEL_COLUMN = re.compile(r"_w(\d+)_(right|left)")
#: colour of the criteria's limit lines
_LIMIT_COLOUR = "k"
_FIG_WIDTH_IN = 12.0


def _wheel_of(column: str) -> tuple[int, str]:
    """(wheelset number, side) of a per-wheel column name (``Y_w2_left_N`` -> (2, "left"))."""
    m = _WHEEL_COLUMN.search(column)
    return int(m.group(1)), m.group(2)


def _wheel_label(wheelset: int, side: str) -> str:
    """Legend name of a wheel: ``"wheelset 1, right"`` (wheelsets numbered from 1 = leading)."""
    return f"wheelset {wheelset}, {side}"


def _run_title(s: dict) -> str:
    scn = s["scenario"]
    run = scn["run"]
    return (f"{s['scenario_name']}: {s['model']['vehicle']}, {scn['vehicle']['speed_km_h']:g} km/h, {run['solver']}, "
            f"dt {run['dt_s'] * 1e3:g} ms, creep law {scn['contact']['creep_law']}\nwheelset 1 = leading; "
            f"{_SIDE_NOTE}")


def _criteria_inputs(s: dict) -> dict:
    """Limits and evaluation settings of the run's criteria: those the run applied (``summary["criteria"]``), or,
    where the criteria were not evaluated, those it would have applied (the scenario's settings and the defaults
    of :mod:`~..analysis.safety`)."""
    o = s["scenario"]["outputs"]["criteria"]
    ev = s.get("criteria") if isinstance(s.get("criteria"), dict) else {}
    inp = ev.get("inputs", {})
    return {"yq_limit": inp.get("yq_limit_en14363", o["yq_limit"]),
            "unloading_limit": inp.get("unloading_limit", o["unloading_limit"]),
            "window_m": inp.get("window_m_requested", safety.EN14363_WINDOW_M),
            "lowpass_hz": inp.get("force_lowpass_hz", safety.EN14363_FORCE_LOWPASS_HZ),
            "nadal_limit": inp.get("nadal_limit"),
            "alpha": inp.get("prudhomme_alpha", safety.PRUDHOMME_ALPHA[o["vehicle"]]),
            "criteria": ev.get("criteria", {})}


def _sliding_2m(x: np.ndarray, t: np.ndarray, speed_m_s: float, ci: dict, ignore_nan: bool = False):
    """The EN 14363 sliding mean over the criteria's window (2 m) of a series (already low-passed with
    :func:`_lowpassed`), as :mod:`~..analysis.safety` evaluates it: (window centre times, means), or ``None`` when
    the record is shorter than the window."""
    dt = float(t[1] - t[0])
    try:
        n = comfort.window_samples(ci["window_m"], speed_m_s, dt)
        m = comfort.sliding_mean(x, n, ignore_nan=ignore_nan)
    except ValueError:
        return None
    return t[: len(m)] + 0.5 * (n - 1) * dt, m


def _lowpassed(x: np.ndarray, dt: float, ci: dict, name: str):
    """The criteria's force low-pass (EN 14363: 20 Hz) of a series; ``ValueError`` if the record is too short."""
    if ci["lowpass_hz"] is None:
        return x
    return comfort.lowpass(x, dt, ci["lowpass_hz"], name=name)


def _limit_line(ax, value: float, label: str, gid: str, style: str = "--") -> None:
    ax.axhline(value, color=_LIMIT_COLOUR, ls=style, lw=1.3, label=label, gid=gid)


def _wheelsets(cols) -> list[int]:
    return sorted({_wheel_of(c)[0] for c in cols})


def _per_wheelset_axes(plt, n_rows: int, title: str):
    fig, axes = plt.subplots(n_rows, 1, figsize=(_FIG_WIDTH_IN, 1.2 + 2.1 * n_rows), sharex=True, squeeze=False,
                             layout="constrained")
    axes = axes[:, 0]
    fig.suptitle(title, fontsize=8)
    return fig, axes


def _figure_Y(plt, result: ScenarioResult):
    """Y per wheel, one axis per wheelset; below, the track shift force ΣY_2m per wheelset with Prud'homme's
    limit (EN 14363) when the run has both wheels of a wheelset."""
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    cols = s["columns"]["Y"]
    ci = _criteria_inputs(s)
    ws = _wheelsets(cols)
    both = [j for j in ws if f"Y_w{j}_right_N" in ts and f"Y_w{j}_left_N" in ts]
    fig, axes = _per_wheelset_axes(plt, len(ws) + (1 if both else 0), _run_title(s))
    for ax, j in zip(axes, ws):
        for c in cols:
            if _wheel_of(c)[0] == j:
                side = _wheel_of(c)[1]
                ax.plot(t, ts[c] * 1e-3, color=_SIDE_COLOUR[side], lw=0.7, label=_wheel_label(j, side))
        ax.set_ylabel("Y [kN]")
    axes[0].set_title("Y: lateral force of the rail on the wheel, track y (+ right)", fontsize=8)
    if both:
        ax = axes[len(ws)]
        dt = float(t[1] - t[0])
        v = s["speed_m_s"]
        limits = set()
        for k, j in enumerate(both):
            sum_y = -(ts[f"Y_w{j}_right_N"] + ts[f"Y_w{j}_left_N"])
            try:
                curve = _sliding_2m(_lowpassed(sum_y, dt, ci, "sum_Y_N"), t, v, ci)
            except ValueError:
                curve = None
            if curve is not None:
                ax.plot(curve[0], curve[1] * 1e-3, color=f"C{k}", lw=1.0, label=f"wheelset {j}")
            q0 = 0.5 * (s["model"]["static_wheel_loads_N"][f"w{j}_right"] +
                        s["model"]["static_wheel_loads_N"][f"w{j}_left"])
            limits.add(round(prudhomme_limit_N(q0, ci["alpha"]), 6))
        for lim in sorted(limits):
            label = f"Prud'homme limit α(10 kN + 2Q₀/3) = ±{lim * 1e-3:.1f} kN"
            _limit_line(ax, lim * 1e-3, label, "limit:prudhomme")
            _limit_line(ax, -lim * 1e-3, None, "limit:prudhomme")
        ax.set_ylabel("ΣY₂ₘ [kN]")
        ax.set_title(f"track shift force ΣY₂ₘ = −(F_y,right + F_y,left), {ci['lowpass_hz']:g} Hz low-pass, "
                     f"{ci['window_m']:g} m sliding mean (EN 14363), at the window centre", fontsize=8)
    return fig, axes


def _figure_Q(plt, result: ScenarioResult):
    """Q per wheel, one axis per wheelset, with the static wheel load and the wheel-unloading limit
    ΔQ/Q₀ as the wheel load Q = (1 − limit) Q₀ it allows."""
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    cols = s["columns"]["Q"]
    ci = _criteria_inputs(s)
    q_static = s["model"]["static_wheel_loads_N"]
    ws = _wheelsets(cols)
    fig, axes = _per_wheelset_axes(plt, len(ws), _run_title(s))
    lim = ci["unloading_limit"]
    for ax, j in zip(axes, ws):
        statics = set()
        for c in cols:
            jj, side = _wheel_of(c)
            if jj == j:
                ax.plot(t, ts[c] * 1e-3, color=_SIDE_COLOUR[side], lw=0.6, label=_wheel_label(j, side))
                statics.add(round(q_static[f"w{j}_{side}"], 6))
        for q0 in sorted(statics):
            ax.axhline(q0 * 1e-3, color="0.4", ls=":", lw=1.0, label=f"static wheel load Q₀ = {q0 * 1e-3:.1f} kN",
                       gid="static_wheel_load")
            _limit_line(ax, (1.0 - lim) * q0 * 1e-3,
                        f"wheel-unloading limit ΔQ/Q₀ = {lim:g} (Q = {(1.0 - lim) * q0 * 1e-3:.1f} kN)",
                        "limit:wheel_unloading")
        ax.set_ylabel("Q [kN]")
    axes[0].set_title("Q: wheel load (vertical force of the rail on the wheel, + pressing)", fontsize=8)
    return fig, axes


def _figure_YQ(plt, result: ScenarioResult):
    """Y/Q per wheel, one axis per wheelset: the instantaneous quotient (thin; the JNR criterion's limit, for
    exceedances of at least its reference duration) and the EN 14363 quotient (Y, Q low-passed, 2 m sliding mean;
    bold) with its limit; Nadal's limit when the run evaluated it."""
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    dt = float(t[1] - t[0])
    cols = s["columns"]["YQ"]
    ci = _criteria_inputs(s)
    ws = _wheelsets(cols)
    fig, axes = _per_wheelset_axes(plt, len(ws), _run_title(s))
    for ax, j in zip(axes, ws):
        for c in cols:
            jj, side = _wheel_of(c)
            if jj != j:
                continue
            ax.plot(t, ts[c], color=_SIDE_COLOUR[side], lw=0.5, alpha=0.45,
                    label=f"{_wheel_label(j, side)}: Y/Q instantaneous")
            y_col, q_col = f"Y_w{j}_{side}_N", f"Q_w{j}_{side}_N"
            if y_col in ts and q_col in ts:
                try:
                    y = _lowpassed(safety.flange_lateral_force_N(ts[y_col], side), dt, ci, "Y_N")
                    q = _lowpassed(ts[q_col], dt, ci, "Q_N")
                    curve = _sliding_2m(safety.derailment_quotient(y, q), t, s["speed_m_s"], ci, ignore_nan=True)
                except ValueError:
                    curve = None
                if curve is not None:
                    ax.plot(curve[0], curve[1], color=_SIDE_COLOUR[side], lw=1.6,
                            label=f"{_wheel_label(j, side)}: (Y/Q)₂ₘ (EN 14363)", gid=f"yq2m:w{j}_{side}")
        if abs(ci["yq_limit"] - safety.JNR_YQ_LIMIT) < 1e-12:
            _limit_line(ax, ci["yq_limit"], f"limit {ci['yq_limit']:g}: EN 14363 on (Y/Q)₂ₘ; JNR on Y/Q lasting "
                        f"≥ {safety.JNR_DURATION_S * 1e3:g} ms", "limit:yq_en14363")
        else:
            _limit_line(ax, ci["yq_limit"], f"EN 14363 limit on (Y/Q)₂ₘ: {ci['yq_limit']:g}", "limit:yq_en14363")
            _limit_line(ax, safety.JNR_YQ_LIMIT, f"JNR limit on Y/Q lasting ≥ {safety.JNR_DURATION_S * 1e3:g} ms: "
                        f"{safety.JNR_YQ_LIMIT:g}", "limit:yq_jnr", style="-.")
        if ci["nadal_limit"] is not None:
            _limit_line(ax, ci["nadal_limit"], f"Nadal limit {ci['nadal_limit']:.3g}", "limit:nadal", style=":")
        ax.set_ylabel("Y/Q [-]")
    axes[0].set_title(f"Y/Q, Y towards the wheel's field side; (Y/Q)₂ₘ: {ci['lowpass_hz']:g} Hz low-pass, "
                      f"{ci['window_m']:g} m sliding mean, at the window centre", fontsize=8)
    return fig, axes


def _figure_wheelset_lateral(plt, result: ScenarioResult):
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    fig, ax = plt.subplots(figsize=(_FIG_WIDTH_IN, 4.5), layout="constrained")
    for c in s["columns"]["wheelset_lateral"]:
        j = int(re.search(r"_w(\d+)_", c).group(1))
        ax.plot(t, ts[c] * 1e3, color=f"C{(j - 1) % 10}", lw=0.9, label=f"wheelset {j}")
    ax.set(xlabel="time [s]", ylabel="lateral displacement [mm]")
    fig.suptitle(_run_title(s), fontsize=8)
    ax.set_title("axle centre relative to the rails' centre line (+ right, looking in the running direction)",
                 fontsize=8)
    return fig, np.array([ax])


def _point_label(p: dict) -> str:
    x = p["x_m"]
    where = {"front_bogie": "above the front bogie", "rear_bogie": "above the rear bogie",
             "centre": "at the vehicle centre"}.get(x) if isinstance(x, str) else f"x = {x:g} m"
    side = f", y = {p['y_m']:g} m" if p.get("y_m") else ""
    return f"car body '{p['name']}' ({where}{side}, {p['height_m']:g} m above rail)"


def _figure_carbody(plt, result: ScenarioResult):
    """Lateral and vertical car-body acceleration (one axis each) of every car-body point; the criteria's
    point also with the signal the comfort criteria evaluate, and their results (Sperling's Wz, the EN 14363
    band-passed peak and RMS) written on the axis."""
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    ci = _criteria_inputs(s)
    points = s["scenario"]["outputs"]["carbody_points"]
    fig, axes = plt.subplots(2, 1, figsize=(_FIG_WIDTH_IN, 6.5), sharex=True, layout="constrained")
    fig.suptitle(_run_title(s), fontsize=8)
    for ax, direction in zip(axes, ("lateral", "vertical")):
        assessed = ci["criteria"].get(f"carbody_{direction}", {}).get("column")
        for k, p in enumerate(points):
            c = f"carbody_{direction}_acceleration_{p['name']}_m_s2"
            if c in ts:
                ax.plot(t, ts[c], color=f"C{k}", lw=0.9, label=_point_label(p))
            if assessed and assessed != c and assessed.endswith(f"_{p['name']}_m_s2"):
                ax.plot(t, ts[assessed], color=f"C{k}", lw=0.7, ls="--",
                        label=f"car body '{p['name']}', floor accelerometer (body axes, a − g)")
        ax.set_ylabel(f"{direction} acceleration [m/s²]")
        # the comfort criteria are numbers, not time series: their results are legend entries
        sp = ci["criteria"].get(f"sperling_{direction}")
        cb = ci["criteria"].get(f"carbody_{direction}")
        if sp or cb:
            what = "floor accelerometer" if "accelerometer" in assessed else "track frame"
            name = next((p["name"] for p in points if assessed.endswith(f"_{p['name']}_m_s2")), assessed)
            ax.plot([], [], " ", label=f"criteria on car body '{name}', {what}:")
        if sp:
            limit = "no limit set" if sp.get("limit") is None else f"limit {sp['limit']:g}"
            ax.plot([], [], " ", gid=f"criteria:sperling_{direction}",
                    label=f"  Sperling Wz = {sp['Wz']:.2f} ({sp['ride_quality']}; {limit})")
        if cb:
            lim = {k: v.get("limit") for k, v in cb.get("assessment", {}).items()}
            limit = ("no limit set" if not any(v is not None for v in lim.values()) else
                     ", ".join(f"{k} limit {v:g} m/s²" for k, v in lim.items() if v is not None))
            ax.plot([], [], " ", gid=f"criteria:carbody_{direction}",
                    label=f"  EN 14363 band-pass {cb['band_hz'][0]:g}–{cb['band_hz'][1]:g} Hz: peak "
                          f"{cb['peak_m_s2']:.3f} m/s², RMS {cb['rms_m_s2']:.3f} m/s² ({limit})")
    axes[0].set_title("acceleration: track frame (y right, z down), kinematic (no gravity)", fontsize=8)
    return fig, axes


def _figure_deck(plt, result: ScenarioResult):
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    fig, axes = plt.subplots(2, 1, figsize=(_FIG_WIDTH_IN, 6), sharex=True, layout="constrained")
    fig.suptitle(_run_title(s), fontsize=8)
    for c in s["columns"]["deck"]:
        i = int(re.search(r"_s(\d+)_", c).group(1))
        deflection = "deflection" in c
        ax = axes[0] if deflection else axes[1]
        ax.plot(t, ts[c] * (1e3 if deflection else 1.0), color=f"C{(i - 1) % 10}", lw=0.9, label=f"span {i}")
    axes[0].set(ylabel="deflection [mm]")
    axes[0].set_title("deck at mid-span, on the track centre line, vertical (+ down)", fontsize=8)
    axes[1].set(ylabel="acceleration [m/s²]")
    return fig, axes


def _figure_unloading(plt, result: ScenarioResult):
    """ΔQ/Q₀ per wheel, one axis per wheelset, with the wheel-unloading limit the criteria apply."""
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    cols = s["columns"]["unloading"]
    lim = _criteria_inputs(s)["unloading_limit"]
    ws = _wheelsets(cols)
    fig, axes = _per_wheelset_axes(plt, len(ws), _run_title(s))
    for ax, j in zip(axes, ws):
        for c in cols:
            jj, side = _wheel_of(c)
            if jj == j:
                ax.plot(t, ts[c], color=_SIDE_COLOUR[side], lw=0.6, label=_wheel_label(j, side))
        _limit_line(ax, lim, f"wheel-unloading limit ΔQ/Q₀ = {lim:g}", "limit:wheel_unloading")
        ax.set_ylabel("ΔQ/Q₀ [-]")
    axes[0].set_title("wheel unloading ΔQ/Q₀ = (Q₀ − Q)/Q₀, Q₀ the static wheel load (+ unloaded)", fontsize=8)
    return fig, axes


def _figure_deck_acceleration(plt, result: ScenarioResult):
    """Vertical deck acceleration at the nine check points of every span (one axis per span) with the EN 1990
    limit of the structure's track form."""
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    cols = s["columns"]["deck_acceleration"]
    spans = sorted({int(re.search(r"_s(\d+)_", c).group(1)) for c in cols})
    form = s["scenario"]["structure"]["track_form"]
    lim = EN1990_DECK_ACCELERATION_LIMITS_M_S2[form]
    fig, axes = _per_wheelset_axes(plt, len(spans), _run_title(s))
    for ax, i in zip(axes, spans):
        for c in cols:
            m = re.search(r"_s(\d+)_p(\d+)_", c)
            if int(m.group(1)) == i:
                k = int(m.group(2))
                ax.plot(t, ts[c], color=plt.cm.viridis((k - 1) / 8.0), lw=0.7,
                        label=f"span {i}, x = {CHECK_POINTS_X_OVER_L[k - 1]:g} L")
        _limit_line(ax, lim, f"EN 1990 A2 limit ({form.replace('_', ' ')}): ±{lim:g} m/s²", "limit:en1990")
        _limit_line(ax, -lim, None, "limit:en1990")
        ax.set_ylabel("acceleration [m/s²]")
    axes[0].set_title("deck, vertical acceleration (+ down) on the track centre line at L/10 … 9L/10 (EN 1990 "
                      "A2.4.4.2.1(4)P check points)", fontsize=8)
    return fig, axes


def _figure_deck_wheelsets(plt, result: ScenarioResult):
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    fig, ax = plt.subplots(figsize=(_FIG_WIDTH_IN, 4.5), layout="constrained")
    for c in s["columns"]["deck_wheelsets"]:
        j = int(re.search(r"_w(\d+)_", c).group(1))
        ax.plot(t, ts[c] * 1e3, color=f"C{(j - 1) % 10}", lw=0.9, label=f"wheelset {j}")
    ax.set(ylabel="deflection [mm]")
    fig.suptitle(_run_title(s), fontsize=8)
    ax.set_title("deck deflection under each wheelset, vertical (+ down); 0 off the deck", fontsize=8)
    return fig, np.array([ax])


def _figure_deck_lateral(plt, result: ScenarioResult):
    """Lateral deck response at mid-span (relative to the supports; absolute acceleration) and the ground motion."""
    s, ts = result.summary, result.timeseries
    t = ts["time_s"]
    fig, axes = plt.subplots(2, 1, figsize=(_FIG_WIDTH_IN, 6), sharex=True, layout="constrained")
    fig.suptitle(_run_title(s), fontsize=8)
    for c in s["columns"]["deck_lateral"]:
        displacement = c.endswith("_m")
        ax = axes[0] if displacement else axes[1]
        scale = 1e3 if displacement else 1.0
        if c.startswith("ground_"):
            ax.plot(t, ts[c] * scale, color="0.3", lw=0.9, ls="--", label="ground (supports and track)")
            continue
        i = int(re.search(r"_s(\d+)_", c).group(1))
        label = f"span {i}, mid-span, " + ("relative to the supports" if displacement else "absolute")
        ax.plot(t, ts[c] * scale, color=f"C{(i - 1) % 10}", lw=0.9, label=label)
    axes[0].set(ylabel="lateral displacement [mm]")
    axes[0].set_title("deck, lateral (+ right) at rail-top level on the track centre line", fontsize=8)
    axes[1].set(ylabel="lateral acceleration [m/s²]")
    return fig, axes


FIGURES = {"Y": _figure_Y, "Q": _figure_Q, "YQ": _figure_YQ, "wheelset_lateral": _figure_wheelset_lateral,
           "carbody": _figure_carbody, "deck": _figure_deck, "unloading": _figure_unloading,
           "deck_acceleration": _figure_deck_acceleration, "deck_wheelsets": _figure_deck_wheelsets,
           "deck_lateral": _figure_deck_lateral}


def group_figure(result: ScenarioResult, group: str):
    """The matplotlib figure of one column group (``plot_<group>.png``), not saved; returns (figure, axes)."""
    plt = pyplot()
    fig, axes = FIGURES[group](plt, result)
    for ax in axes:
        ax.grid(True, alpha=0.3)
        handles, labels = ax.get_legend_handles_labels()
        if handles:
            ax.legend(fontsize=6.5, loc="upper left", bbox_to_anchor=(1.005, 1.0), borderaxespad=0.0)
    axes[-1].set_xlabel("time [s]")
    return fig, axes


def save_group_figure(result: ScenarioResult, group: str, path) -> None:
    plt = pyplot()
    fig, _ = group_figure(result, group)
    fig.savefig(path, dpi=100)
    plt.close(fig)
