r"""The RTRI explorer: sliders for speed, span, deviation amplitude, friction and suspension factors; releasing a
slider re-runs the RTRI case and redraws the Fig. 5/6 quantities (exudyn_wheelrail.interactive).

Run:  python examples/explore_rtri.py                       # the matplotlib window (needs a display)
      python examples/explore_rtri.py --out explorer.png    # headless: a small programmatic sweep, then the figure

The same window: ``python -m exudyn_wheelrail explore``.  Without a GUI the explorer is driven through
:meth:`~exudyn_wheelrail.interactive.explorer.RtriExplorer.update`, which returns the result and the measured
update time; the headless branch below does that for three deviation amplitudes and prints the passage peaks.
Settings (RK44 1 ms, run over the passage of the whole car) and their differences to the full Newmark run are in
``exudyn_wheelrail/interactive/explorer.py``; all inputs are the RTRI case's substitutes and assumptions.
"""
from __future__ import annotations

import argparse
import sys


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=None, help="headless: save the explorer window to this PNG")
    args = ap.parse_args(argv)
    import matplotlib
    if args.out:
        matplotlib.use("Agg")
    from exudyn_wheelrail.interactive.explorer import RtriExplorer
    from exudyn_wheelrail.interactive.explorer_figure import ExplorerFigure

    explorer = RtriExplorer()
    if not args.out:
        ExplorerFigure(explorer=explorer).show()
        return 0
    print(explorer.settings.describe())
    for delta_mm in (6.0, 10.0, 12.0):
        u = explorer.update(deviation_mm=delta_mm)
        p = u.peaks
        print(f"delta {delta_mm:4.1f} mm: update {u.seconds:.2f} s; max |Y| w1 right "
              f"{p['max_abs_lateral_contact_force_w1_right_N'] / 1e3:6.2f} kN (10 ms average "
              f"{p['max_abs_lateral_contact_force_w1_right_10ms_avg_N'] / 1e3:6.2f} kN), max |a| car body "
              f"{p['max_abs_carbody_lateral_acceleration_rear_m_s2']:.3f} m/s2, flange region "
              f"{'yes' if p['flange_contact_w1_right'] else 'no'}")
    fig = ExplorerFigure(explorer=explorer, deviation_mm=10.0)
    fig.save(args.out)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
