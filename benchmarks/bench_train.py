"""Trains over a bridge: the full vehicle–bridge interaction of an 8-car train against the moving-load model.

Model: ``bridge-crossing`` (:mod:`exudyn_wheelrail.scenarios.bridge_crossing`) — a simply supported 20 m span (and
40 m) of 15 t/m, first bending frequency :data:`F1_HZ`, :data:`DAMPING` modal damping, :data:`MODES` vertical modes;
the train ``vehicles/trains/manchester_x8.toml`` (8 Manchester vehicles, 26 m cars end to end, 32 wheelsets) as

* ``vehicles``: the full interaction (:mod:`exudyn_wheelrail.scenarios.bridge_crossing_vehicles`: every car a
  multibody vehicle, one wheel–rail contact for the 32 wheelsets coupled to the deck's modes);
* ``moving-loads``: the train's static axle loads (lever rule) as constant moving forces.

Both at the same time step (the vehicles model's, given to both) and the same free vibration after the train.
Per run: status, solve time, real-time factor (simulated / solve time), cost per wheelset and step, and the peak
mid-span displacement and acceleration — raw, and low-passed at 1.5 f1 (:func:`resonant_peak`: the part of the
first mode, what a resonance builds up); the interaction's effect = vehicles / moving loads.

* ``cost``: both spans, f1 = :data:`F1_HZ`, at the speed ``v_i = f1 d / i`` (d = 26 m the car length,
  i = :data:`RESONANCE_ORDER`) and at :data:`OFF_RESONANCE_KM_H`;
* ``resonance``: the 20 m span made to resonate within the train's validity range (:data:`RESONANCE_DECK`: f1 =
  3 Hz, so ``v_1 = f1 d`` = 281 km/h, with a heavier, more damped deck than the ``cost`` one so that the deck
  acceleration stays well below g — at 15 t/m and 1 % the moving loads give 20 m/s² at v_1 = 374 km/h for f1 = 4 Hz
  and the full interaction ends ``derailed``): the moving loads over :data:`RESONANCE_SWEEP_KM_H`, the full
  interaction at :data:`RESONANCE_VEHICLES_KM_H`; the resonance peak of each model is its largest value over
  its speeds.

Load average (``uptime``) before and after every run.

Run:  python benchmarks/bench_train.py [--parts cost resonance] [--spans 20 40] [--free-vibration-s 0.5]
Writes benchmarks/results/train.json.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).resolve().parent / "results" / "train.json"
CONSIST = Path(__file__).resolve().parents[1] / "vehicles" / "trains" / "manchester_x8.toml"
MASS_KG_M = 15.0e3
F1_HZ = 6.0
DAMPING = 0.01
MODES = 3
CAR_LENGTH_M = 26.0
RESONANCE_ORDER = 2                       #: v_2 = f1 d / 2 = 78 m/s = 281 km/h on the 20 m span
OFF_RESONANCE_KM_H = 200.0
FREE_VIBRATION_S = 0.5
#: the resonance study's deck (20 m span): f1 [Hz], mass per length [kg/m], damping ratio
RESONANCE_DECK = dict(span_m=20.0, f1_Hz=3.0, mass_kg_m=30.0e3, damping_ratio=0.02)
RESONANCE_SWEEP_KM_H = (250.0, 260.0, 265.0, 270.0, 275.0, 280.0, 285.0, 290.0, 300.0, 310.0)
RESONANCE_VEHICLES_KM_H = (265.0, 272.5, 280.0)


def uptime() -> str:
    return subprocess.run(["uptime"], capture_output=True, text=True, check=False).stdout.strip()


def resonant_peak(t, a, f_cut_Hz: float) -> float:
    """Largest |a| of the signal low-passed at ``f_cut_Hz`` (ideal filter in the frequency domain, the record
    zero-padded to twice its length against wrap-around)."""
    a = np.asarray(a, dtype=float)
    n = 2 * a.size
    spec = np.fft.rfft(a, n)
    spec[np.fft.rfftfreq(n, float(t[1] - t[0])) > f_cut_Hz] = 0.0
    return float(np.max(np.abs(np.fft.irfft(spec, n)[:a.size])))


def crossing(span_m: float, speed_m_s: float, model: str, dt_s: float, free_s: float, *, f1_Hz: float = F1_HZ,
             mass_kg_m: float = MASS_KG_M, damping_ratio: float = DAMPING) -> dict:
    from exudyn_wheelrail.scenarios.bridge_crossing import BridgeCrossing, run_bridge_crossing
    from exudyn_wheelrail.scenarios.bridge_crossing_loads import consist_axles
    case = BridgeCrossing(span_m=span_m, mass_kg_m=mass_kg_m, f1_Hz=f1_Hz, damping_ratio=damping_ratio,
                          n_modes=MODES, axles=consist_axles(CONSIST) if model == "moving-loads" else None,
                          speed_m_s=speed_m_s, model=model, train_file=str(CONSIST), free_vibration_s=free_s,
                          dt_s=dt_s)
    load_before = uptime()
    t0 = time.perf_counter()
    r = run_bridge_crossing(case)
    wall = time.perf_counter() - t0
    s = r.summary
    n_ws = s["load_model"]["n_axles"]
    ts = r.timeseries
    ok = s["status"] == "ok"
    out = {"span_m": span_m, "f1_Hz": f1_Hz, "mass_kg_m": mass_kg_m, "damping_ratio": damping_ratio,
           "speed_km_h": speed_m_s * 3.6, "model": model, "status": s["status"],
           "dt_s": s["dt_s"], "steps": s["steps"], "solve_seconds": s["solve_seconds"], "wall_seconds": wall,
           "simulated_seconds": s["simulated_seconds"], "real_time_factor": s["real_time_factor"],
           "us_per_wheelset_step": s["solve_seconds"] / s["steps"] / n_ws * 1e6, "wheelsets": n_ws,
           "max_abs_deck_midspan_displacement_m": s["max_abs_deck_midspan_displacement_m"],
           "max_abs_deck_midspan_acceleration_m_s2": s["max_abs_deck_midspan_acceleration_m_s2"],
           "resonant_deck_midspan_acceleration_m_s2": (resonant_peak(ts["time_s"], ts[
               "deck_midspan_acceleration_m_s2"], 1.5 * f1_Hz) if ok else None),
           "uptime_before": load_before, "uptime_after": uptime()}
    if model == "vehicles" and isinstance(s["load_model"].get("details"), dict):
        crit = s["load_model"]["details"].get("criteria", {})
        out["criteria_passed_every_car"] = crit.get("passed")
    return out


def _report(r: dict) -> None:
    res = r["resonant_deck_midspan_acceleration_m_s2"]
    print(f"{r['span_m']:4.0f} m f1 {r['f1_Hz']:g} Hz {r['speed_km_h']:6.1f} km/h {r['model']:12s} {r['status']:8s} "
          f"solve {r['solve_seconds']:7.2f} s for {r['simulated_seconds']:.3f} s (RTF {r['real_time_factor']:.3f}), "
          f"{r['us_per_wheelset_step']:6.1f} us/(wheelset step)"
          + (f", |w| {r['max_abs_deck_midspan_displacement_m'] * 1e3:.4f} mm, |a| "
             f"{r['max_abs_deck_midspan_acceleration_m_s2']:.4f} m/s2 (< 1.5 f1: {res:.4f})" if res is not None
             else "") + f"; {r['uptime_after']}", flush=True)


_PEAKS = ("max_abs_deck_midspan_displacement_m", "max_abs_deck_midspan_acceleration_m_s2",
          "resonant_deck_midspan_acceleration_m_s2")


def main(argv=None) -> int:
    from exudyn_wheelrail.rolling_stock.train import load_consist
    from exudyn_wheelrail.scenarios.defaults import STEPS_PER_PERIOD
    from exudyn_wheelrail.scenarios.bridge_crossing_vehicles import contact_dt_s
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--parts", nargs="+", choices=("cost", "resonance"), default=["cost", "resonance"])
    ap.add_argument("--spans", type=float, nargs="+", default=[20.0, 40.0])
    ap.add_argument("--free-vibration-s", type=float, default=FREE_VIBRATION_S)
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args(argv)
    consist = load_consist(CONSIST)
    dt = min(contact_dt_s(consist), 1.0 / (STEPS_PER_PERIOD * MODES ** 2 * F1_HZ))     # the command's rule
    result = {"what": "8-car train over a simply supported span: full interaction vs moving loads (bench_train.py)",
              "consist": str(CONSIST), "modes": MODES, "dt_s": dt, "free_vibration_s": args.free_vibration_s,
              "uptime_start": uptime()}
    if "cost" in args.parts:
        rows = []
        for span in args.spans:
            for v in (F1_HZ * CAR_LENGTH_M / RESONANCE_ORDER, OFF_RESONANCE_KM_H / 3.6):
                pair = {m: crossing(span, v, m, dt, args.free_vibration_s) for m in ("moving-loads", "vehicles")}
                for r in pair.values():
                    _report(r)
                    rows.append(r)
                mv, ve = pair["moving-loads"], pair["vehicles"]
                if mv["status"] == ve["status"] == "ok":
                    for q in _PEAKS:
                        ve[f"vehicles_over_moving_loads.{q}"] = ve[q] / mv[q]
                        print(f"    interaction: {q} x {ve[q] / mv[q]:.4f}")
        result["cost"] = dict(mass_kg_m=MASS_KG_M, f1_Hz=F1_HZ, damping_ratio=DAMPING, rows=rows)
    if "resonance" in args.parts:
        deck = dict(RESONANCE_DECK)
        span = deck.pop("span_m")
        rows = {"moving-loads": [], "vehicles": []}
        for model, speeds in (("moving-loads", RESONANCE_SWEEP_KM_H), ("vehicles", RESONANCE_VEHICLES_KM_H)):
            for kmh in speeds:
                r = crossing(span, kmh / 3.6, model, dt, args.free_vibration_s, **deck)
                _report(r)
                rows[model].append(r)
        peaks = {}
        for model, rs in rows.items():
            ok = [r for r in rs if r["status"] == "ok"]
            peaks[model] = {q: max(r[q] for r in ok) if ok else None for q in _PEAKS}
            best = max(ok, key=lambda r: r["max_abs_deck_midspan_displacement_m"]) if ok else None
            peaks[model]["speed_of_peak_displacement_km_h"] = best["speed_km_h"] if best else None
        ratio = {q: (peaks["vehicles"][q] / peaks["moving-loads"][q]
                     if peaks["vehicles"][q] and peaks["moving-loads"][q] else None) for q in _PEAKS}
        print("resonance peaks:", json.dumps(peaks), "\nvehicles / moving loads:", json.dumps(ratio))
        result["resonance"] = dict(deck=RESONANCE_DECK, rows=rows, peaks=peaks, vehicles_over_moving_loads=ratio)
    result.update(uptime_end=uptime(), date=time.strftime("%Y-%m-%dT%H:%M:%S%z"))
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(result, fh, indent=2, default=lambda o: o.item() if isinstance(o, np.generic) else str(o))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
