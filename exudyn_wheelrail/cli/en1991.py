"""The ``en1991-dynamic`` command: a railway bridge's dynamic check to EN 1991-2 §6.4.6 — every train at every
speed at both mass bounds, the deck acceleration against EN 1990 A2
(:mod:`exudyn_wheelrail.scenarios.en1991_dynamic`)."""
from __future__ import annotations

from pathlib import Path

from ..simulation.settings import SPEED_KM_H
from ..scenarios.defaults import CHECK_MIN_SPEED_KM_H, CHECK_REFINE_KM_H, CHECK_SPEED_STEP_KM_H
from ..standards import EN1991_DAMPING_PERCENT, HSLM_NAMES, TRACK_FORMS
from ..validation import output_dir
from .common import add_progress_argument, positive_int, progress_count


def add_en1991_dynamic_parser(sub) -> None:
    """The ``en1991-dynamic`` command's parser: its options, their check and its function."""
    p = sub.add_parser("en1991-dynamic", help="a bridge's dynamic check to EN 1991-2 6.4.6: HSLM-A1..A10 (or given "
                                              "trains) at every speed and mass bound, deck acceleration vs EN 1990",
                       description="Runs every train as moving axle loads over the bridge of --bridge at every speed "
                                   f"from {CHECK_MIN_SPEED_KM_H:g} km/h to 1.2 x the maximum line speed (steps <= "
                                   f"{CHECK_SPEED_STEP_KM_H:g} km/h, refined by {CHECK_REFINE_KM_H:g} km/h around each "
                                   "resonance speed) at the lower and upper bound of the deck mass, with the "
                                   "damping of EN 1991-2 Table 6.6 and the modes up to EN 1990's cut-off, in parallel; "
                                   "a run started again on the same --out takes the crossings already finished. "
                                   "Writes DIR/summary.json (verdict, max_deck_acceleration_m_s2, "
                                   "acceleration_limit_m_s2, governing, damping_ratio_used, modes, "
                                   "max_dynamic_enhancement), DIR/envelope.csv (one row per crossing), "
                                   "DIR/envelope.png and DIR/report.html; a bar of the finished crossings on a terminal, "
                                   "else a line per finished crossing [k/N] on stderr "
                                   "(exudyn_wheelrail/scenarios/en1991_dynamic.py).")
    p.add_argument("--bridge", required=True, metavar="FILE.toml",
                   help="the bridge file: [bridge] spans_m, EI_Nm2 (and continuous) or modes_file (and "
                        "modes_mass_kg_per_m), mass_kg_per_m (a number or [lower, upper]), "
                        f"structure ({', '.join(EN1991_DAMPING_PERCENT)}) or "
                        f"damping_ratio, track_form ({', '.join(TRACK_FORMS)}), additional_damping (true/false)")
    p.add_argument("--max-line-speed-kmh", type=float, required=True, metavar="V",
                   help="the line's maximum speed [km/h]: the check runs to 1.2 V")
    p.add_argument("--trains", nargs="+", default=None, metavar="A1|FILE.toml",
                   help=f"the trains: names of the universal trains ({', '.join(HSLM_NAMES)}) or consist files "
                        "(their static axle loads) (default: all ten HSLM-A)")
    p.add_argument("--speeds-kmh", type=float, nargs="+", default=None, metavar="V",
                   help="run these speeds [km/h] only (default: the grid of EN 1991-2 6.4.6.2)")
    p.add_argument("--workers", type=positive_int("--workers"), default=None, metavar="N",
                   help="worker processes (default: one per CPU)")
    p.add_argument("--out", required=True, help="output directory (finished crossings in DIR/runs are kept)")
    add_progress_argument(p)
    p.set_defaults(func=cmd_en1991_dynamic, check=_check_en1991_dynamic)


def _check_en1991_dynamic(args) -> None:
    """Every option before any work: the bridge file read, the trains resolved; the check goes to
    ``args.dynamic_check``."""
    from ..scenarios.bridge_crossing_loads import consist_axles
    from ..scenarios.en1991_dynamic import DynamicCheck, read_bridge_file, speed_grid_kmh
    output_dir("--out", args.out)
    v = SPEED_KM_H.check("--max-line-speed-kmh", args.max_line_speed_kmh)
    speed_grid_kmh(v)                             # 1.2 V at least the check's lowest speed
    if not Path(args.bridge).is_file():
        raise ValueError(f"--bridge: {args.bridge}: no such file")
    bridge = read_bridge_file(args.bridge)
    trains = tuple(args.trains) if args.trains is not None else HSLM_NAMES
    for t in trains:
        if t not in HSLM_NAMES:
            if not Path(t).is_file():
                raise ValueError(f"--trains: {t}: neither a universal train ({', '.join(HSLM_NAMES)}) nor a "
                                 "consist file")
            consist_axles(t)
    speeds = None
    if args.speeds_kmh is not None:
        speeds = tuple(SPEED_KM_H.check("--speeds-kmh", s) for s in args.speeds_kmh)
    check = DynamicCheck(bridge=bridge, max_line_speed_kmh=v, trains=trains, speeds_kmh=speeds)
    for bound in bridge.masses:                   # every crossing's case checked once, before any work
        try:
            check.crossing(trains[0], bound, (speeds or (v,))[0])
        except ValueError as exc:
            raise ValueError(f"--bridge: {args.bridge}: the crossing of mass bound {bound}: {exc}") from None
    args.dynamic_check = check


def cmd_en1991_dynamic(args) -> int:
    from ..scenarios.en1991_dynamic import run_dynamic_check
    from ..simulation.status import OK, exit_code
    check = args.dynamic_check
    n = len(check.runs())
    print(f"EN 1991-2 dynamic check of {args.bridge}: {len(check.trains)} train(s), "
          f"{len(check.bridge.masses)} mass bound(s), {n} crossings, damping "
          f"{100 * check.bridge.damping_ratio_used:.3g} %")
    s = run_dynamic_check(check, args.out, workers=args.workers, progress=progress_count(args))
    g = s["governing"] or {}
    a = s["max_deck_acceleration_m_s2"]
    print(f"verdict: {s['verdict'].upper()} — {s['verdict_reason']}"
          + (f"; governing {g['train']} at {g['speed_kmh']:g} km/h, mass bound {g['mass_bound']}" if g else ""))
    if a is not None:
        print(f"max deck acceleration {a:.4g} m/s^2 (limit {s['acceleration_limit_m_s2']:g} m/s^2)")
    print("wrote " + ", ".join(s["paths"].values()))
    # the crossings' statuses (a derailed or diverged run, an error), as the sweeps: a verdict is a result
    return exit_code([OK] * (s["crossings"] - len(s["not_completed"])) + [r["status"] for r in s["not_completed"]])
