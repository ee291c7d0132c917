"""The contact commands: ``geometry`` (contact-geometry functions of a lateral sweep -> CSV and an optional plot),
``conicity`` (equivalent conicity for an amplitude) and ``creep-table`` (a creep table built into an npz file)."""
from __future__ import annotations

import argparse
import math

from ..validation import Quantity, output_file
from .common import add_progress_argument, check_figure, positive_int, progress_lines

# Plausibility of the contact options that are not parameters of an API object (the wheel-rail pair's gauge,
# back-to-back distance, r0 and inclination are judged by the ranges of exudyn_wheelrail.contact.pair).
Y_MAX_M = Quantity("largest lateral shift of the sweep", "m", 1e-4, 0.05)
Y_STEP_M = Quantity("step of the lateral sweep", "m", 1e-6, 0.005)
WHEEL_LOAD_N = Quantity("wheel load", "N", 100.0, 1.0e6, typical=(5.0e3, 2.5e5))
CONICITY_AMPLITUDE_M = Quantity("lateral amplitude of the equivalent conicity", "m", 1e-4, 0.015)
CONTACT_DISTANCE_M = Quantity("distance between the nominal contact points", "m", 0.6, 2.2)
#: largest number of points of a lateral sweep
MAX_SWEEP_STEPS = 20000


def _check_inclination(option: str, text) -> float:
    from ..contact.pair import INCLINATION_TAN
    from ..conventions import parse_inclination
    try:
        tan = parse_inclination(text)
    except ValueError as exc:
        raise ValueError(f"{option}: {exc}") from None
    return INCLINATION_TAN.check(option, tan)


def _check_pair_options(args) -> None:
    """The wheel-rail pair's options: plausible numbers, known profiles (the files are read when the pair is built,
    which checks that a wheel file holds a wheel and a rail file a rail)."""
    from ..contact.pair import BACK_TO_BACK_M, GAUGE_M, R0_M, back_to_back_problem
    from ..profiles.profiles import RAIL_PROFILE_NAMES, profile_spec_problem
    for option, kind in (("--wheel", "wheel"), ("--rail", "rail")):
        problem = profile_spec_problem(getattr(args, kind), kind)
        if problem:
            raise ValueError(f"{option}: {problem}")
    GAUGE_M.check("--gauge", args.gauge)
    BACK_TO_BACK_M.check("--back-to-back", args.back_to_back)
    problem = back_to_back_problem(args.gauge, args.back_to_back, "--gauge")
    if problem:
        raise ValueError(f"--back-to-back: {problem}")
    R0_M.check("--r0", args.r0)
    _check_inclination("--inclination", args.inclination)
    if str(args.rail_canted).lower() != "auto":
        _check_inclination("--rail-canted", args.rail_canted)
    elif args.rail_worn:
        raise ValueError("--rail-worn: a worn rail head needs --rail-canted (the inclination its data contain): its "
                         "crown does not show it")
    if args.rail_worn and str(args.rail).strip().upper() in RAIL_PROFILE_NAMES:
        raise ValueError(f"--rail-worn: applies to a measured rail file, not to the built-in {args.rail}")
    Y_MAX_M.check("--y-max", args.y_max)
    Y_STEP_M.check("--y-step", args.y_step)
    if args.y_step > args.y_max:
        raise ValueError(f"--y-step: {args.y_step:g} m is larger than --y-max {args.y_max:g} m")
    WHEEL_LOAD_N.check("--wheel-load", args.wheel_load)


def _check_geometry(args) -> None:
    output_file("--out", args.out, what="CSV file")
    check_figure("--plot", args.plot)
    _check_pair_options(args)


def _check_conicity(args) -> None:
    _check_pair_options(args)
    CONICITY_AMPLITUDE_M.check("--amplitude", args.amplitude)
    if args.contact_distance is not None:
        CONTACT_DISTANCE_M.check("--contact-distance", args.contact_distance)


def _check_creep_table(args) -> None:
    from ..creep.linear import table_poisson
    output_file("--out", args.out, (".npz",), what="creep table")
    table_poisson(args.nu, "--nu")


def _add_pair_arguments(p: argparse.ArgumentParser):
    p.add_argument("--wheel", default="S1002", help="wheel profile: S1002 or a .prw / y-z table file")
    p.add_argument("--rail", default="UIC60", help="rail profile: UIC60 (60E1) or a .prr / y-z table file")
    p.add_argument("--inclination", default="1/40", help="rail inclination: 1/40, 1/20, none (default 1/40)")
    p.add_argument("--rail-canted", default="auto",
                   help="inclination the rail file already contains (e.g. 1/40 for the Manchester UIC60 file); "
                        "auto (default) detects it from the head shape")
    p.add_argument("--rail-worn", action="store_true",
                   help="the rail file is a worn head: --rail-canted is taken as stated, not checked against the "
                        "crown (which wear has moved)")
    p.add_argument("--gauge", type=float, default=1.435, help="track gauge 14 mm below the rail top [m]")
    p.add_argument("--back-to-back", type=float, default=1.360, help="flange back-to-back distance [m]")
    p.add_argument("--r0", type=float, default=0.46, help="nominal rolling radius [m]")
    p.add_argument("--y-max", type=float, default=0.010, help="largest lateral shift of the sweep [m]")
    p.add_argument("--y-step", type=float, default=0.0005, help="step of the sweep [m]")
    p.add_argument("--wheel-load", type=float, default=10e3, help="nominal vertical wheel load for a, b [N]")


def _pair_from_args(args):
    from ..contact.pair import WheelRailPair
    from ..conventions import parse_inclination
    from ..profiles.profiles import resolve_rail, resolve_wheel
    canted = None if str(args.rail_canted).lower() == "auto" else parse_inclination(args.rail_canted)
    rail = resolve_rail(args.rail, canted_tan=canted, worn=args.rail_worn)
    return WheelRailPair(resolve_wheel(args.wheel), rail, gauge_m=args.gauge, inclination=args.inclination,
                         back_to_back_m=args.back_to_back, r0_m=args.r0)


def _sweep(args, y_max=None):
    from ..analysis.geometry_functions import contact_geometry_sweep
    y_max = args.y_max if y_max is None else y_max
    import numpy as np
    if not (math.isfinite(args.y_step) and math.isfinite(y_max) and args.y_step > 0 and y_max > 0):
        raise ValueError("--y-max, --y-step: must be positive finite numbers (metres)")
    if y_max / args.y_step > MAX_SWEEP_STEPS:
        raise ValueError(f"--y-step: --y-max / --y-step = {y_max / args.y_step:.0f} steps, more than "
                         f"{MAX_SWEEP_STEPS}")
    n = int(round(y_max / args.y_step))
    y = np.linspace(-n * args.y_step, n * args.y_step, 2 * n + 1)
    return contact_geometry_sweep(_pair_from_args(args), y, wheel_load_N=args.wheel_load)


def plot_sweep(sweep, path, title=""):
    """Contact-geometry functions on one page (Δr, contact positions, angles, roll, ellipse)."""
    import numpy as np

    from ..scenarios.drawing import pyplot
    plt = pyplot()
    rows = sweep.rows
    fig, ax = plt.subplots(2, 3, figsize=(14, 8))
    ax = ax.ravel()
    ax[0].plot(sweep.y_m * 1e3, sweep.delta_r_m * 1e3, ".-")
    ax[0].set(xlabel="lateral shift y [mm]", ylabel="Δr = r_right − r_left [mm]", title="rolling radius difference")
    for side, marker in (("right", "o"), ("left", "x")):
        for region, color in (("tread", "C0"), ("flange", "C3")):
            sel = [r for r in rows if r["side"] == side and r["region"] == region]
            if not sel:
                continue
            y = np.array([r["y_m"] for r in sel]) * 1e3
            label = f"{side} {region}"
            ax[1].plot(y, [r["y_wheel_m"] * 1e3 for r in sel], marker, color=color, ms=4, label=label)
            ax[2].plot(y, [r["y_rail_m"] * 1e3 for r in sel], marker, color=color, ms=4, label=label)
            ax[3].plot(y, np.degrees([r["contact_angle_rad"] for r in sel]), marker, color=color, ms=4, label=label)
            ax[5].plot(y, [r["a_m"] * 1e3 for r in sel], marker, color=color, ms=4, label=f"a {label}")
            ax[5].plot(y, [r["b_m"] * 1e3 for r in sel], marker, color=color, ms=4, mfc="none", alpha=0.5)
    ax[1].set(xlabel="y [mm]", ylabel="contact on wheel, profile y [mm]", title="contact position on the wheel")
    ax[2].set(xlabel="y [mm]", ylabel="contact on rail, profile y [mm]", title="contact position on the rail")
    ax[3].set(xlabel="y [mm]", ylabel="contact angle [deg]", title="contact angle")
    ax[4].plot(sweep.y_m * 1e3, sweep.roll_rad * 1e3, ".-")
    ax[4].set(xlabel="y [mm]", ylabel="roll [mrad]", title="wheelset roll")
    ax[5].set(xlabel="y [mm]", ylabel="semi-axes a (filled), b (open) [mm]", title="Hertz ellipse (nominal load)")
    ax[1].legend(fontsize=7)
    for a in ax:
        a.grid(True, alpha=0.3)
    fig.suptitle(title)
    fig.subplots_adjust(left=0.05, right=0.99, bottom=0.07, top=0.91, wspace=0.25, hspace=0.33)   # no layout pass
    fig.savefig(path, dpi=110)
    plt.close(fig)


def cmd_geometry(args):
    sweep = _sweep(args)
    sweep.write_csv(args.out)
    if args.plot:
        plot_sweep(sweep, args.plot, title=f"{args.wheel} on {args.rail} {args.inclination}, gauge {args.gauge} m, "
                                            f"back-to-back {args.back_to_back} m")
    print(f"wrote {len(sweep.rows)} contact points for {len(sweep.y_m)} lateral shifts to {args.out}")
    return 0


def cmd_conicity(args):
    from ..analysis.conicity import equivalent_conicity
    y_max = max(args.y_max, args.amplitude + 2 * args.y_step)
    sweep = _sweep(args, y_max=y_max)
    e = 0.5 * (args.back_to_back + 0.140) if args.contact_distance is None else 0.5 * args.contact_distance
    gamma = equivalent_conicity(sweep.y_m, sweep.delta_r_m, args.amplitude, method=args.method,
                                half_contact_distance_m=e, r0_m=args.r0)
    print(f"equivalent conicity {gamma:.4f} (amplitude {args.amplitude * 1e3:g} mm, method {args.method}, "
          f"{args.wheel}/{args.rail} {args.inclination}, gauge {args.gauge} m)")
    return 0


def _parse_option(text):
    if "=" not in text:
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {text!r}")
    key, value = text.split("=", 1)
    for conv in (int, float):
        try:
            return key.strip(), conv(value)
        except ValueError:
            pass
    return key.strip(), value.strip()


def cmd_creep_table(args):
    from ..creep.build_table import build_table, grid_summary
    print(grid_summary(args.grid))
    path = build_table(args.out, generator=args.generator, grid=args.grid, workers=args.workers, poisson=args.nu,
                       options=dict(args.option or []), keep_parts=args.keep_parts, progress=progress_lines(args))
    print(f"wrote {path}")
    return 0


def add_geometry_parser(sub) -> None:
    """The ``geometry`` command's parser: its options, their check and its function."""
    g = sub.add_parser("geometry", help="contact-geometry functions of a lateral sweep")
    _add_pair_arguments(g)
    g.add_argument("--out", required=True, help="CSV file to write")
    g.add_argument("--plot", default=None, help="PNG file to write (optional)")
    g.set_defaults(func=cmd_geometry, check=_check_geometry)


def add_conicity_parser(sub) -> None:
    """The ``conicity`` command's parser: its options, their check and its function."""
    c = sub.add_parser("conicity", help="equivalent conicity")
    _add_pair_arguments(c)
    c.add_argument("--amplitude", type=float, default=0.003, help="lateral amplitude [m] (EN 15302: 3 mm)")
    c.add_argument("--method", default="harmonic", choices=("harmonic", "wavelength", "regression"))
    c.add_argument("--contact-distance", type=float, default=None,
                   help="distance between the nominal contact points 2e [m] (default back-to-back + 140 mm)")
    c.set_defaults(func=cmd_conicity, check=_check_conicity)


def add_creep_table_parser(sub) -> None:
    """The ``creep-table`` command's parser: its options, their check and its function."""
    t = sub.add_parser("creep-table", help="build a creep table (Kalker exact theory or FASTSIM) into an npz file",
                       description="Build a USETAB-style creep table (exudyn_wheelrail.creep.table): parallel, "
                                   "chunked, resumable (re-run the same command to continue), deterministic.")
    t.add_argument("--out", required=True, help="npz file to write (the package table: "
                                                "exudyn_wheelrail/data/creep_table.npz, exact generator only)")
    t.add_argument("--generator", default="exact", choices=("exact", "fastsim"),
                   help="exact: Kalker's exact theory (default); fastsim: FASTSIM stand-in (development)")
    t.add_argument("--workers", type=positive_int("--workers"), default=None,
                   help="worker processes (default: all cores)")
    t.add_argument("--grid", default="default", choices=("coarse", "default"), help="node set (default: default)")
    t.add_argument("--nu", type=float, default=0.28, help="Poisson's ratio of the table (default 0.28, steel)")
    t.add_argument("--option", action="append", type=_parse_option, metavar="KEY=VALUE",
                   help="generator option, repeatable (FASTSIM: n_x, n_y, flexibility; exact: the solver's "
                        "keyword options, warm_start=1)")
    t.add_argument("--keep-parts", action="store_true", help="keep the per-chunk results after assembling")
    add_progress_argument(t)
    t.add_argument("--quiet", dest="progress", action="store_false", default=None, help="the same as --no-progress")
    t.set_defaults(func=cmd_creep_table, check=_check_creep_table)

