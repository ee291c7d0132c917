"""RTRI explorer: update time (run and redraw) and the explorer's peaks against the full run.

Run:  python benchmarks/bench_explorer.py [--updates 7] [--out benchmarks/results/explorer.json] [--no-grid]

* update time on the RTRI case (20 m, 250 km/h; deviation alternating 10 / 10.5 mm so every update is a new run):
  the run alone (:meth:`RtriExplorer.update`: build, warm-up, solve, outputs) and run + redraw of the matplotlib
  window (Agg backend, :class:`ExplorerFigure`); min and median over ``--updates`` updates;
* explorer (RK44 1 ms, passage window) vs the full run (Newmark 1 ms, ``duration_s="auto"``) for the RTRI case and
  four more speed/span corners and a flange impact (δ = 12 mm): relative differences of the passage peaks.

The load average of the machine is recorded with the numbers (the machine is shared; timings scale with it).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

from exudyn_wheelrail.interactive.explorer import RtriExplorer, compare_with_full_run  # noqa: E402
from exudyn_wheelrail.interactive.explorer_figure import ExplorerFigure  # noqa: E402

#: (speed km/h, span m, deviation mm): the RTRI case, four corners, and a flange impact (δ = 12 mm)
GRID = ((250.0, 20.0, 10.0), (100.0, 20.0, 10.0), (250.0, 40.0, 10.0), (100.0, 40.0, 10.0), (175.0, 30.0, 10.0),
        (250.0, 20.0, 12.0))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--updates", type=int, default=7)
    ap.add_argument("--out", default=str(Path(__file__).parent / "results" / "explorer.json"))
    ap.add_argument("--no-grid", action="store_true", help="skip the explorer-vs-full-run grid")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    ex = RtriExplorer()
    startup = time.perf_counter() - t0
    runs = []
    for i in range(args.updates):
        runs.append(ex.update(deviation_mm=10.0 if i % 2 == 0 else 10.5).seconds)
    fig = ExplorerFigure(explorer=ex, deviation_mm=10.0)
    totals, redraws = [], []
    for i in range(args.updates):
        u = fig.set_values(deviation_mm=10.5 if i % 2 == 0 else 10.0)
        totals.append(u.seconds + fig.last_redraw_s)
        redraws.append(fig.last_redraw_s)
    out = {
        "load_average_1min": os.getloadavg()[0], "cpus": os.cpu_count(), "settings": ex.settings.describe(),
        "startup_s": startup,
        "run_s": {"min": min(runs), "median": statistics.median(runs), "all": runs},
        "redraw_s": {"min": min(redraws), "median": statistics.median(redraws)},
        "run_plus_redraw_s": {"min": min(totals), "median": statistics.median(totals), "all": totals},
        "vs_full_run": [],
    }
    print(f"load average {out['load_average_1min']:.2f} on {out['cpus']} CPUs; {out['settings']}")
    print(f"run: min {min(runs):.3f} s, median {statistics.median(runs):.3f} s; run + redraw: min {min(totals):.3f} "
          f"s, median {statistics.median(totals):.3f} s (redraw median {statistics.median(redraws):.3f} s)")
    for V, L, d in ([] if args.no_grid else GRID):
        c = compare_with_full_run(ex, speed_km_h=V, span_m=L, deviation_mm=d)
        keep = ("explorer", "full", "relative", "explorer_seconds", "full_seconds")
        out["vs_full_run"].append({"speed_km_h": V, "span_m": L, "deviation_mm": d, **{k: c[k] for k in keep}})
        r = c["relative"]
        print(f"V {V:g} km/h, L {L:g} m, δ {d:g} mm: explorer {c['explorer_seconds']:.2f} s vs full "
              f"{c['full_seconds']:.2f} s; "
              f"a_cb {r['max_abs_carbody_lateral_acceleration_rear_m_s2'] * 100:+.1f} %, Y 10 ms "
              f"{r['max_abs_lateral_contact_force_w1_right_10ms_avg_N'] * 100:+.1f} %, Y raw "
              f"{r['max_abs_lateral_contact_force_w1_right_N'] * 100:+.1f} %")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(out, fh, indent=2)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
