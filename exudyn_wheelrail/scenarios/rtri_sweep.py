r"""The RTRI sweep: every (span, speed) case of :class:`~.rtri_case.RtriCase` in parallel processes
(:func:`run_sweep`), written as ``sweep.csv`` (one row per case, :data:`SWEEP_COLUMNS`), ``sweep.json`` (the rows
with the assumptions table and the run and contact settings), Fig. 7 (:func:`~.rtri_figures.plot_fig7`) and each
case's outputs under ``cases/L<span>_V<speed>/``.  A case that fails is a row whose status names the error; the
others run on.  The public import path of the case is :mod:`exudyn_wheelrail.scenarios.rtri`.

What the model gives with the stated assumptions (Newmark, 1 ms, FASTSIM 24 x 8)
--------------------------------------------------------------------------------
How the table was produced: ``python -m exudyn_wheelrail rtri-sweep --spans 20 40 --out DIR`` run with the code of
commit 2d861b5 (2026-11-22), whose defaults were Newmark (β = 0.25, γ = 0.5), dt = 1 ms, Newton tolerance 1e-6,
duration "auto" (max(2.5 s, the whole car past the span with lead-in and run-out)), FASTSIM on a 24 x 8 grid,
μ = 0.3, the online contact search, δ = 10 mm, l_t = 3 m and the speeds 100, 150, 200, 250 km/h.  With today's
defaults the nearest command is ``python -m exudyn_wheelrail rtri-sweep --spans 20 40 --creep-law fastsim --out
DIR`` (Newton tolerance 1e-4).  The table has not been re-measured since; the contact kernel has changed after it
(one contact per overlap zone, commit 204c46d).  The values are the passage peaks (``summary["peaks_passage"]``):

=====  =======  ==============  ================  =================  =======================
span   V km/h   max |a| m/s²    max |Y| kN (raw)  max |Y| kN (10ms)  flange region w1 right
=====  =======  ==============  ================  =================  =======================
20 m   100      0.33            6.5               3.3                no
20 m   150      0.64            5.6               3.5                no
20 m   200      0.80            22.4              11.8               no (flange root, 0.34 rad)
20 m   250      1.27            32.8              22.5               no (flange root, 0.56 rad)
40 m   100      0.21            6.9               3.3                no
40 m   150      0.35            5.2               3.4                no
40 m   200      0.53            6.1               3.6                no
40 m   250      0.76            6.8               3.4                no
=====  =======  ==============  ================  =================  =======================

* Reproduced: a much larger lateral force at 20 m than at 40 m (250 km/h: 4.8x raw, 6.6x averaged; 200 km/h
  3.7x / 3.3x), no flange contact at 40 m, a larger car-body acceleration at 20 m at every speed.
* **Not reproduced with the stated δ = 10 mm: the flange impact at 20 m.**  At 250 km/h the leading wheelset
  reaches 5.89 mm relative to the track (with the exact-theory creep table, 0.36 mm short of the flange flank as
  ``tests/test_rtri.py`` asserts; the table above is FASTSIM's); the contact
  of S1002 on UIC60 1:40 jumps to the flange flank at 6.25 mm, so it stays on the flange root (tread region).  The
  flange impact appears from δ = 12 mm (l_t ≤ 3 m) and is asserted at δ = 14 mm; the measured sensitivity is in
  :mod:`.rtri_assumptions`.
* At 250 km/h this vehicle model hunts after the passage (±6 mm limit cycle, flange-root contacts), at 200 km/h
  and below a ±1–2 mm limit cycle remains: 250 km/h is above the model's critical speed; the passage peaks above
  are before the hunting has built up, the whole-run peaks at 250 km/h include it.
* The wheel load Q of the leading right wheel swings between 0 and ~300 kN (static 54.5 kN) whenever the contact
  jumps: the single-point tread region changes its normal force by up to ~30 kN at a jump (S1002/UIC60 near the
  centred position and near the throat; the warm-started kernel also follows a stale branch, hysteresis), which
  excites the ~200 Hz wheelset bounce; the only vertical damping in that mode is the primary damper (0.2 % of
  critical) — neither contact damping nor a compliant rail/roller is modelled.
"""
from __future__ import annotations

import csv
import dataclasses
import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from multiprocessing import get_context
from pathlib import Path

from ..simulation.settings import DURATION_AUTO, ContactSettings, RunSettings
from .rtri_case import RtriCase, assumptions_table
from .rtri_figures import plot_fig7
from .rtri_run import run_rtri, write_rtri_outputs
from .scenario import write_json

__all__ = ["SWEEP_COLUMNS", "run_sweep"]

SWEEP_COLUMNS = ("span_m", "speed_km_h", "status", "steps", "solve_seconds", "real_time_factor",
                 "max_abs_carbody_lateral_acceleration_rear_m_s2", "max_abs_lateral_contact_force_w1_right_N",
                 "max_abs_lateral_contact_force_w1_right_10ms_avg_N", "flange_contact_w1_right",
                 "flange_contact_w1_right_duration_s", "max_derailment_quotient_w1_right",
                 "min_wheel_load_w1_right_N", "max_abs_wheelset1_lateral_rel_track_m", "whole_car_passes_span",
                 "after_passage_max_abs_wheelset1_lateral_rel_track_m",
                 "run_max_abs_carbody_lateral_acceleration_rear_m_s2")
_SWEEP_PEAKS = SWEEP_COLUMNS[6:14]     # from peaks_passage


def _sweep_task(case: RtriCase, case_dir):
    try:
        r = run_rtri(case)
        if case_dir is not None:
            write_rtri_outputs(r, case_dir)
        return r.summary
    except Exception as exc:   # one failing case must not stop the sweep
        return {"status": f"error: {type(exc).__name__}: {exc}".splitlines()[0], "span_m": float(case.span_m),
                "speed_km_h": float(case.speed_km_h), "steps": None, "peaks": {}, "coverage": {}}


def run_sweep(spans_m, speeds_km_h, out_dir, *, workers: int | None = None, run: RunSettings | None = None,
              contact: ContactSettings | None = None, deviation_amplitude_m: float | None = None,
              transition_length_m: float | None = None, write_cases: bool = True, progress=print) -> list[dict]:
    """All (span, speed) cases in parallel processes; writes ``sweep.csv``, ``sweep.json``,
    ``fig7_max_carbody_acceleration.png`` (and each case's outputs under ``cases/`` if ``write_cases``).  ``run``:
    default the case's run with ``duration_s="auto"`` (each case covers its whole passage); ``contact``: the case's
    default."""
    spans_m = [float(s) for s in spans_m]
    speeds_km_h = [float(v) for v in speeds_km_h]
    if not spans_m or not speeds_km_h:
        raise ValueError("the sweep needs at least one span and one speed")
    if run is None:
        run = dataclasses.replace(RtriCase().run, duration_s=DURATION_AUTO)
    cases = [RtriCase(span_m=L, speed_km_h=V, run=run, contact=contact,
                      deviation_amplitude_m=deviation_amplitude_m, transition_length_m=transition_length_m)
             for L in spans_m for V in speeds_km_h]        # validates every case before starting
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    workers = max(1, min(int(workers or os.cpu_count() or 1), len(cases)))
    summaries = []
    with ProcessPoolExecutor(max_workers=workers, mp_context=get_context("spawn")) as pool:
        futures = {pool.submit(_sweep_task, c, (out / "cases" / f"L{c.span_m:g}_V{c.speed_km_h:g}")
                               if write_cases else None): c for c in cases}
        for f in as_completed(futures):
            s = f.result()
            summaries.append(s)
            if progress:
                p = s.get("peaks_passage", {})
                progress(f"  span {s['span_m']:g} m, {s['speed_km_h']:g} km/h: {s['status']}; max |a_cb| "
                         f"{p.get('max_abs_carbody_lateral_acceleration_rear_m_s2', float('nan')):.3f} m/s², max |Y| "
                         f"{p.get('max_abs_lateral_contact_force_w1_right_N', float('nan')) / 1e3:.1f} kN, flange "
                         f"{p.get('flange_contact_w1_right')}")
    summaries.sort(key=lambda s: (s["span_m"], s["speed_km_h"]))
    rows = []
    for s in summaries:
        p, c = s.get("peaks_passage", {}), s.get("coverage", {})
        row = {k: s.get(k) for k in ("span_m", "speed_km_h", "status", "steps", "solve_seconds", "real_time_factor")}
        for k in _SWEEP_PEAKS:
            row[k] = p.get(k)
        row["whole_car_passes_span"] = c.get("whole_car_passes_span")
        row["after_passage_max_abs_wheelset1_lateral_rel_track_m"] = s.get("after_passage", {}).get(
            "max_abs_wheelset1_lateral_rel_track_m")
        row["run_max_abs_carbody_lateral_acceleration_rear_m_s2"] = s.get("peaks", {}).get(
            "max_abs_carbody_lateral_acceleration_rear_m_s2")
        rows.append(row)
    with open(out / "sweep.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(SWEEP_COLUMNS))
        w.writeheader()
        w.writerows(rows)
    meta = {"assumptions": assumptions_table(), "run_settings": run.as_dict(),
            "contact_settings": (contact or RtriCase().contact).as_dict(), "rows": rows}
    write_json(out / "sweep.json", meta)
    plot_fig7(rows, out / "fig7_max_carbody_acceleration.png")
    return summaries
