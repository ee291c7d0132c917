"""The ``critical-speed`` command: a vehicle's running stability on straight track — the linear critical speed and
hunting mode from the eigenvalues of the linearised model, the nonlinear critical speed and bifurcation diagram from
runs after a lateral disturbance (:mod:`exudyn_wheelrail.scenarios.critical_speed`)."""
from __future__ import annotations

import math

from ..scenarios.critical_speed_defaults import (BRANCH_DEPTH_RATIO, BRANCH_MIN_DEPTH_M, BUMP_DEPTH_M, BUMP_LENGTH_M,
                                                 DEFAULT_SPEED_RANGE_KM_H, SPEED_LIMITS_KM_H)
from ..validation import output_dir
from .common import add_progress_argument, positive_int, progress_lines


def add_critical_speed_parser(sub) -> None:
    """The ``critical-speed`` command's parser: its options, their check and its function."""
    lo, hi = DEFAULT_SPEED_RANGE_KM_H
    p = sub.add_parser("critical-speed", help="running stability on straight track: linear critical speed and "
                                              "hunting mode (eigenvalues), nonlinear critical speed (runs after a "
                                              "lateral disturbance)",
                       description="Linearises the full model (the vehicle on perfect straight rigid track, the "
                                   "real profiles, Hertz, the creep table) about its centred running state at the "
                                   "speeds of the range and bisects the lowest speed where a lateral mode's damping "
                                   "ratio crosses zero (the linear critical speed, its frequency and mode shape); "
                                   f"runs the full model at constant speed after a {1e3 * BUMP_DEPTH_M:g} mm, "
                                   f"{BUMP_LENGTH_M:g} m lateral bump at speeds over the range in parallel and "
                                   "bisects the lowest speed where a limit cycle persists (the nonlinear critical "
                                   "speed); between the two, bisects the disturbance's depth between decay and the "
                                   "stable cycle (the unstable cycles).  Writes DIR/summary.json (status, "
                                   "linear_critical_speed_kmh, "
                                   "hunting_frequency_hz, hunting_mode_shape, nonlinear_critical_speed_kmh (null "
                                   "with a note when none is found in the range), conicity, assumptions, seconds), "
                                   "DIR/root_locus.csv (speed_kmh, mode, frequency_hz, damping_ratio, ...), "
                                   "DIR/bifurcation.csv (speed_kmh, wheelset, amplitude_m, ..., branch), "
                                   "DIR/linear_speeds.csv and the figures root_locus.png, damping_ratio.png, "
                                   "bifurcation.png (exudyn_wheelrail/scenarios/critical_speed.py).")
    p.add_argument("--vehicle", required=True, metavar="NAME|FILE",
                   help="a shipped vehicle (e.g. manchester_vehicle1) or a vehicle file (.toml)")
    p.add_argument("--speed-range-kmh", type=float, nargs=2, default=None, metavar=("LO", "HI"),
                   help=f"the speeds analysed [km/h], within {SPEED_LIMITS_KM_H[0]:g}-{SPEED_LIMITS_KM_H[1]:g} "
                        f"(default: {lo:g} {hi:g})")
    p.add_argument("--workers", type=positive_int("--workers"), default=None, metavar="N",
                   help="worker processes of the nonlinear runs (default: one per CPU; 1: in this process)")
    runs = 2 + math.ceil(math.log2(math.log(BUMP_DEPTH_M / BRANCH_MIN_DEPTH_M) / math.log(BRANCH_DEPTH_RATIO)))
    p.add_argument("--no-unstable-branch", dest="unstable_branch", action="store_false",
                   help="skip the bifurcation diagram's unstable branch (the disturbance bisected at speeds between "
                        f"the nonlinear and the linear critical speed: about {runs} runs per speed)")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    add_progress_argument(p)
    p.set_defaults(func=cmd_critical_speed, check=_check_critical_speed)


def _check_critical_speed(args) -> None:
    """Every option before any work; the case goes to ``args.case``."""
    from ..scenarios.critical_speed import CriticalSpeedCase, check_case
    output_dir("--out", args.out)
    rng = tuple(args.speed_range_kmh) if args.speed_range_kmh is not None else DEFAULT_SPEED_RANGE_KM_H
    case = CriticalSpeedCase(vehicle=args.vehicle, speed_range_kmh=rng, workers=args.workers,
                             unstable_branch=args.unstable_branch)
    check_case(case)
    args.case = case


def cmd_critical_speed(args) -> int:
    from ..scenarios.critical_speed import run_critical_speed
    from ..simulation.status import EXIT_ERROR
    case = args.case
    print(f"critical speed of {case.vehicle}: {case.speed_range_kmh[0]:g}-{case.speed_range_kmh[1]:g} km/h")
    s = run_critical_speed(case, args.out, progress=progress_lines(args))

    def kmh(v):
        return "none in the range" if v is None else f"{v:.1f} km/h"
    freq = s["hunting_frequency_hz"]
    linear_note = next((n[len("linear: "):] for n in s["notes"] if n.startswith("linear: ")), None)
    print(f"linear critical speed {kmh(s['linear_critical_speed_kmh'])}"
          + (f", hunting frequency {freq:.3g} Hz" if freq is not None else "")
          + (f" ({linear_note})" if s["linear_critical_speed_kmh"] is None and linear_note else ""))
    print(f"nonlinear critical speed {kmh(s['nonlinear_critical_speed_kmh'])}"
          + (f" ({s['nonlinear_note']})" if s["nonlinear_note"] else ""))
    found = [r for r in s["unstable_branch"] if r["found"]]
    if found:
        print("unstable cycles (leading wheelset): " + ", ".join(
            f"{r['speed_kmh']:g} km/h " + (f"{1e3 * r['amplitude_m'][0]:.3f} mm" if r["amplitude_m"][0] is not None
                                           and math.isfinite(r["amplitude_m"][0]) else "not read")
            for r in found))
    elif s["unstable_branch_note"]:
        print(f"unstable cycles: {s['unstable_branch_note']}")
    print("wrote " + ", ".join(s["paths"].values()))
    return 0 if s["status"] == "ok" else EXIT_ERROR
