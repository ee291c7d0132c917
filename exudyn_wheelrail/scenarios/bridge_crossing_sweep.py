"""The bridge crossing's speed sweeps: the same crossing at many speeds, one task per speed through the executors of
the scenario sweeps (:func:`speed_sweep`, :func:`sweep_case`), the table (:data:`SWEEP_COLUMNS`) and its files and
figure (:func:`plot_speed_sweep`)."""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..conventions import speed_km_h
from ..structures.load_models import resonance_speeds_m_s
from .bridge_crossing_case import BridgeCrossing, positive_number
from .bridge_crossing_loads import resolve_load_model
from .bridge_crossing_run import run_bridge_crossing
from .deck import EN1990_DECK_ACCELERATION_LIMITS_M_S2
from .outputs import write_json, write_table_csv
from .drawing import pyplot
from .sweep import run_tasks

__all__ = ["SWEEP_COLUMNS", "SpeedSweepResult", "sweep_case", "speed_sweep", "plot_speed_sweep"]


#: the columns of a speed sweep's table (sweep.csv), in order
SWEEP_COLUMNS = ("case", "speed_km_h", "status", "max_abs_deck_midspan_displacement_m",
                 "max_abs_deck_midspan_acceleration_m_s2", "en1990_peak_acceleration_m_s2", "en1990_passed",
                 "solve_seconds", "simulated_seconds", "steps", "case_dir")


@dataclass
class SpeedSweepResult:
    """``table`` (column -> list, one entry per speed, :data:`SWEEP_COLUMNS`), the base ``case``, the
    ``resonance_speeds`` of the train on the span, the written ``paths``, the sweep's ``wall_seconds``."""

    table: dict
    case: BridgeCrossing
    resonance_speeds: list
    wall_seconds: float = 0.0
    paths: dict = field(default_factory=dict)


def sweep_case(case: BridgeCrossing, case_dir=None) -> dict:
    """One speed of a sweep (runs in the worker): the row of :data:`SWEEP_COLUMNS`; an exception becomes
    ``status = "error: ..."`` (one case does not stop the others)."""
    row = {"speed_km_h": speed_km_h(case.speed_m_s), "case_dir": None if case_dir is None else str(case_dir)}
    try:
        s = run_bridge_crossing(case, out_dir=case_dir).summary
    except Exception as exc:
        return {**row, "status": f"error: {type(exc).__name__}: {exc}".splitlines()[0]}
    en = s["EN1990_A2_deck_acceleration"] or {}
    return {**row, "status": s["status"],
            "max_abs_deck_midspan_displacement_m": s["max_abs_deck_midspan_displacement_m"],
            "max_abs_deck_midspan_acceleration_m_s2": s["max_abs_deck_midspan_acceleration_m_s2"],
            "en1990_peak_acceleration_m_s2": en.get("peak_acceleration_m_s2"), "en1990_passed": en.get("passed"),
            "solve_seconds": s["solve_seconds"], "simulated_seconds": s["simulated_seconds"], "steps": s["steps"]}


def speed_sweep(case: BridgeCrossing, speeds_m_s, executor=None, out_dir=None, *, workers: int | None = None,
                write_cases: bool = False, progress=print) -> SpeedSweepResult:
    """``case`` at every speed of ``speeds_m_s``, one task per speed through ``executor`` — the executors of the
    scenario sweeps (:mod:`.sweep`: ``None`` a local process pool of ``workers`` spawned processes, any
    ``concurrent.futures.Executor``, a Dask client, :class:`~.sweep.SerialExecutor`); with ``out_dir``:
    ``sweep.csv``, ``sweep.json`` and ``sweep_plot.png`` (peak mid-span displacement and acceleration against the
    speed, the resonance speeds ``v_i = f1 d/i`` marked, the EN 1990 limit drawn), and each speed's own outputs
    under ``cases/`` with ``write_cases``."""
    speeds = [positive_number("speeds_m_s", v) for v in speeds_m_s]
    if not speeds:
        raise ValueError("speeds_m_s: no speed given")
    resolve_load_model(case.model).check(case)
    out = Path(out_dir) if out_dir is not None else None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    dirs = [str(out / "cases" / f"v{speed_km_h(v):07.2f}_kmh") if (out is not None and write_cases) else None
            for v in speeds]
    cases = [replace(case, speed_m_s=v) for v in speeds]
    rows = [None] * len(cases)
    t0 = time.perf_counter()

    def finished(i, r):
        rows[i] = r
        if progress:
            a = r.get("max_abs_deck_midspan_acceleration_m_s2")
            progress(f"  {r['speed_km_h']:.5g} km/h: {r['status']}" + (f"; max |a| {a:.4g} m/s^2" if a else ""))

    def failed(i, text):
        return {"speed_km_h": speed_km_h(speeds[i]), "case_dir": dirs[i], "status": text.splitlines()[0]}
    run_tasks(executor, workers, sweep_case, list(zip(cases, dirs)), finished, failed)
    wall = time.perf_counter() - t0
    table = {c: [] for c in SWEEP_COLUMNS}
    for i, r in enumerate(rows):
        for c in SWEEP_COLUMNS:
            table[c].append(i if c == "case" else r.get(c))
    spacing = case.axles.spacing_m if case.axles is not None else None
    res = [] if spacing is None else [{"i": i, "speed_m_s": v, "speed_km_h": speed_km_h(v)}
                                      for i, v in enumerate(resonance_speeds_m_s(case.f1_Hz, spacing), 1)]
    result = SpeedSweepResult(table=table, case=case, resonance_speeds=res, wall_seconds=wall)
    if out is not None:
        result.paths = _write_sweep(result, out)
    return result


def _write_sweep(result: SpeedSweepResult, out: Path) -> dict:
    t = result.table
    paths = {"csv": out / "sweep.csv", "json": out / "sweep.json", "plot": out / "sweep_plot.png"}
    write_table_csv(paths["csv"], t)
    write_json(paths["json"], {"case": result.case.as_dict(), "resonance_speeds": result.resonance_speeds,
                               "wall_seconds": result.wall_seconds, "table": t}, indent=1)
    plot_speed_sweep(result, paths["plot"])
    return {k: str(v) for k, v in paths.items()}


def plot_speed_sweep(result: SpeedSweepResult, path) -> None:
    """Peak mid-span displacement and acceleration against the speed (``ok`` cases), the resonance speeds
    ``v_i = f1 d/i`` inside the swept range as dashed vertical lines, the EN 1990 limit as a horizontal line."""
    plt = pyplot()
    t = result.table
    ok = [i for i in range(len(t["case"])) if t["status"][i] == "ok"]
    v = np.array([t["speed_km_h"][i] for i in ok])
    order = np.argsort(v)
    fig, axes = plt.subplots(2, 1, figsize=(7.5, 6.0), sharex=True)
    for ax, col, scale, label in ((axes[0], "max_abs_deck_midspan_displacement_m", 1e3, "max |w| mid-span [mm]"),
                                  (axes[1], "max_abs_deck_midspan_acceleration_m_s2", 1.0,
                                   "max |a| mid-span [m/s²]")):
        y = np.array([t[col][i] for i in ok], dtype=float) * scale
        ax.plot(v[order], y[order], "o-", ms=3)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    c = result.case
    limit = EN1990_DECK_ACCELERATION_LIMITS_M_S2[c.track_form]
    axes[1].axhline(limit, color="C3", lw=1, label=f"EN 1990 A2 limit ({c.track_form.replace('_', ' ')}) {limit:g} "
                                                   "m/s²")
    if v.size:
        lo, hi = float(v.min()), float(v.max())
        for r in result.resonance_speeds:
            if lo <= r["speed_km_h"] <= hi:
                for ax in axes:
                    ax.axvline(r["speed_km_h"], color="0.4", ls="--", lw=0.8)
                axes[0].annotate(f"f1 d/{r['i']}", (r["speed_km_h"], 1.0), xycoords=("data", "axes fraction"),
                                 ha="center", va="bottom", fontsize=7)
    axes[1].legend(fontsize=7)
    axes[1].set_xlabel("speed [km/h]")
    name = c.axles.name if c.axles is not None else c.train_file
    fig.suptitle(f"{name} over L = {c.span_m:g} m, f1 = {c.f1_Hz:g} Hz, ζ = {c.damping_ratio:g}, {c.n_modes} modes, "
                 f"{c.model}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
