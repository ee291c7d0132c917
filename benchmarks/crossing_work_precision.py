"""Work against precision of the full vehicle–bridge interaction: the README's 8-car crossing at several time steps.

The case (README): ``bridge-crossing --span-m 20 --bridge-mass-kg-per-m 15000 --bridge-frequency-hz 5
--damping-ratio 0.01 --modes 3 --train vehicles/trains/crh6_intercity_8car.toml --model vehicles --speed-kmh 250``
(32 wheelsets, one contact, RK44), run through the command line with ``--dt`` from this script's ``--dt`` (the command's own
default step among them, and the finest as the reference).  Per step: the solve time, the deck's peaks (mid-span
displacement and acceleration, the EN 1990 acceleration — every deck point, modes up to the cut-off) and the
wheel forces' peaks (largest |Y| and largest Q over all wheels), each as the relative error against the finest
step's; with the convergence of the reference itself (its difference to the next finer step).  Load average beside
every run.

Run:  python benchmarks/crossing_work_precision.py [--dt 1e-3 5.55e-4 2.5e-4 1.25e-4 6.25e-5]
Writes benchmarks/results/crossing_work_precision.json.
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results" / "crossing_work_precision.json"
COMMAND = ["bridge-crossing", "--span-m", "20", "--bridge-mass-kg-per-m", "15000", "--bridge-frequency-hz", "5",
           "--damping-ratio", "0.01", "--modes", "3", "--train", str(ROOT / "vehicles/trains/crh6_intercity_8car.toml"),
           "--model", "vehicles", "--speed-kmh", "250"]
#: the compared peaks: (name, how it is read)
QUANTITIES = ("deck displacement", "deck acceleration", "EN 1990 acceleration", "max |Y|", "max Q")


def peaks(folder: Path) -> dict:
    s = json.loads((folder / "summary.json").read_text())
    sc = s["scalars"]
    with open(folder / "timeseries.csv", newline="") as fh:
        rows = csv.reader(fh)
        names = next(rows)
        data = np.array([[float(x) for x in r] for r in rows])
    col = {n: i for i, n in enumerate(names)}
    y = [col[n] for n in names if n.startswith("Y_w") and n.endswith("_N")]
    q = [col[n] for n in names if n.startswith("Q_w") and n.endswith("_N")]
    return {"status": s["status"], "solve_seconds": s["solve_seconds"], "steps": s["steps"], "dt_s": s["dt_s"],
            "deck displacement": sc["deck.max_mid_span_deflection_m"],
            "deck acceleration": sc["max_abs_deck_midspan_acceleration_m_s2"],
            "EN 1990 acceleration": sc["deck.en1990_peak_acceleration_m_s2"],
            "max |Y|": float(np.abs(data[:, y]).max()), "max Q": float(data[:, q].max())}


def run(dt: float | None, work: Path) -> dict:
    out = work / (f"dt_{dt:g}" if dt is not None else "dt_default")
    cmd = [sys.executable, "-m", "exudyn_wheelrail", *COMMAND, "--out", str(out)]
    if dt is not None:
        cmd += ["--dt", repr(dt)]
    load = os.getloadavg()[0]
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    r = peaks(out)
    r["load_1min"] = [round(load, 2), round(os.getloadavg()[0], 2)]
    return r


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dt", type=float, nargs="+", default=[1e-3, 2.5e-4, 1.25e-4, 6.25e-5],
                    help="time steps [s] besides the command's default (the finest is the reference)")
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        runs = [run(None, work)] + [run(dt, work) for dt in sorted(args.dt, reverse=True)]
    ref = min(runs, key=lambda r: r["dt_s"])
    finer = sorted(runs, key=lambda r: r["dt_s"])
    for r in runs:
        r["relative_error"] = {k: abs(r[k] - ref[k]) / abs(ref[k]) for k in QUANTITIES}
    reference_convergence = ({k: abs(finer[1][k] - finer[0][k]) / abs(finer[0][k]) for k in QUANTITIES}
                             if len(finer) > 1 else None)
    print("| dt [ms] | steps | solve [s] | " + " | ".join(f"{k} error" for k in QUANTITIES) + " | load |")
    print("|---:|---:|---:|" + "---:|" * len(QUANTITIES) + "---|")
    for r in sorted(runs, key=lambda r: -r["dt_s"]):
        errs = " | ".join(f"{100 * r['relative_error'][k]:.3f} %" for k in QUANTITIES)
        print(f"| {1e3 * r['dt_s']:.4g} | {r['steps']} | {r['solve_seconds']:.2f} | {errs} | "
              f"{r['load_1min'][0]}–{r['load_1min'][1]} |")
    if reference_convergence is not None:
        print("reference against the next finer step: "
              + ", ".join(f"{k} {100 * v:.4f} %" for k, v in reference_convergence.items()))
    Path(args.out).write_text(json.dumps({"command": COMMAND, "runs": runs, "reference_dt_s": ref["dt_s"],
                                          "reference_convergence": reference_convergence}, indent=2))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
