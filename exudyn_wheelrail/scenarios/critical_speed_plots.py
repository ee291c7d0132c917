"""The figures of the running-stability analysis (:mod:`.critical_speed`): the root locus, the damping ratio against
speed and the bifurcation diagram, drawn from the written tables."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .drawing import pyplot

__all__ = ["write_figures", "FIGURES"]

#: figure name -> file name
FIGURES = {"root_locus": "root_locus.png", "damping_ratio": "damping_ratio.png", "bifurcation": "bifurcation.png"}
#: the root-locus figure shows the oscillating modes up to this frequency [Hz] and from this real part [1/s] (the
#: hunting region; the stiff contact and wheelset modes are in the table)
ROOT_LOCUS_MAX_HZ = 20.0
ROOT_LOCUS_MIN_REAL_1_S = -40.0
#: the damping-ratio figure shows the modes whose damping ratio falls below this somewhere in the range
DAMPING_SHOWN_BELOW = 0.3


def _modes(table: dict) -> dict:
    """mode -> (speeds, frequency, damping ratio, real part, lateral share) arrays, by speed."""
    out = {}
    for i, m in enumerate(table["mode"]):
        out.setdefault(m, []).append(i)
    cols = ("speed_kmh", "frequency_hz", "damping_ratio", "real_part_1_per_s", "lateral_share")
    return {m: tuple(np.array([table[c][i] for i in rows], dtype=float) for c in cols) for m, rows in out.items()}


def _save(plt, fig, out: Path, name: str, paths: dict) -> None:
    """Lay out, write as ``out / FIGURES[name]`` (its path into ``paths[name]``) and close ``fig``."""
    fig.tight_layout()
    paths[name] = str(out / FIGURES[name])
    fig.savefig(paths[name], dpi=110)
    plt.close(fig)


def write_figures(out: Path, table: dict, bif: dict, summary: dict) -> dict:
    """Draw the three figures into ``out``; returns their paths by :data:`FIGURES` name."""
    plt = pyplot()
    modes = _modes(table)
    vcrit = summary.get("linear_critical_speed_kmh")
    paths = {}

    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    speeds = np.array(table["speed_kmh"], dtype=float)
    norm = plt.Normalize(float(np.min(speeds)), float(np.max(speeds))) if len(speeds) else None
    sc = None
    for v, f, z, re, share in modes.values():
        shown = (f > 0.0) & (f <= ROOT_LOCUS_MAX_HZ) & (re >= ROOT_LOCUS_MIN_REAL_1_S)
        if not shown.any():
            continue
        ax.plot(re[shown], f[shown], "-", color="0.8", lw=0.6, zorder=1)
        sc = ax.scatter(re[shown], f[shown], c=v[shown], s=6 + 14 * share[shown], cmap="viridis", norm=norm,
                        zorder=2)
    ax.axvline(0.0, color="k", lw=0.8)
    if sc is not None:
        fig.colorbar(sc, ax=ax, label="speed [km/h]")
    ax.set(xlabel="real part σ [1/s]", ylabel="frequency [Hz]",
           title=f"root locus: modes up to {ROOT_LOCUS_MAX_HZ:g} Hz, σ ≥ {ROOT_LOCUS_MIN_REAL_1_S:g} 1/s "
                 "(marker size: lateral share; all modes in root_locus.csv)")
    ax.title.set_fontsize(9)
    ax.grid(True, alpha=0.3)
    _save(plt, fig, out, "root_locus", paths)

    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    j = 0
    for m, (v, f, z, re, share) in modes.items():
        if not (np.nanmin(z) < DAMPING_SHOWN_BELOW and np.nanmax(share) >= 0.5 and np.nanmax(f) > 0.0):
            continue
        label = f"mode {m} ({np.nanmean(f):.3g} Hz)" if j < 10 else None
        ax.plot(v, z, "o-", ms=3, color=f"C{j % 10}", label=label)
        j += 1
    ax.axhline(0.0, color="k", lw=0.8)
    if vcrit is not None:
        ax.axvline(vcrit, color="r", ls="--", lw=1.0, label=f"linear critical speed {vcrit:.1f} km/h")
    ax.set(xlabel="speed [km/h]", ylabel="damping ratio [-]", ylim=(-0.2, DAMPING_SHOWN_BELOW),
           title="lateral modes: damping ratio against speed")
    ax.grid(True, alpha=0.3)
    if j:
        ax.legend(fontsize=7)
    _save(plt, fig, out, "damping_ratio", paths)

    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    ws = sorted(set(bif["wheelset"]))
    for w in ws:
        color = f"C{(w - 1) % 10}"
        for branch in ("stable", "unstable"):
            rows = sorted((bif["speed_kmh"][i], bif["amplitude_m"][i], bif["persists"][i])
                          for i in range(len(bif["wheelset"]))
                          if bif["wheelset"][i] == w and bif["branch"][i] == branch)
            if not rows:
                continue
            v = np.array([r[0] for r in rows])
            a = 1e3 * np.array([r[1] for r in rows], dtype=float)
            if branch == "unstable":
                ax.plot(v, a, "x--", ms=5, lw=1.0, color=color,
                        label="unstable cycles (estimate)" if w == ws[0] else None)
                continue
            p = np.array([r[2] for r in rows], dtype=bool)
            ax.plot(v, a, "-", lw=1.0, color=color, label=f"wheelset {w}")
            ax.plot(v[p], a[p], "o", ms=4, color=color)
            ax.plot(v[~p], a[~p], "o", ms=4, mfc="none", color=color)
    vnl = summary.get("nonlinear_critical_speed_kmh")
    if vnl is not None:
        ax.axvline(vnl, color="k", ls="--", lw=1.0, label=f"nonlinear critical speed {vnl:.1f} km/h")
    if vcrit is not None:
        ax.axvline(vcrit, color="r", ls=":", lw=1.0, label=f"linear critical speed {vcrit:.1f} km/h")
        if "unstable" in bif["branch"]:          # where the unstable cycles shrink to the centred state
            ax.plot([vcrit], [0.0], "s", ms=6, mfc="none", color="r")
    ax.set(xlabel="speed [km/h]", ylabel="limit-cycle amplitude [mm]",
           title="bifurcation diagram: amplitude at the end of each run (filled: persists; hollow: decays); "
                 "x: unstable cycles")
    ax.title.set_fontsize(9)
    ax.grid(True, alpha=0.3)
    if ws:
        ax.legend(fontsize=7)
    _save(plt, fig, out, "bifurcation", paths)
    return paths
