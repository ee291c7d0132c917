"""Command line: ``python -m exudyn_wheelrail <command> ...`` (scripts and regression tests call it; keep it stable).

Commands
--------
geometry   contact-geometry functions of a wheelset lateral sweep -> CSV (and an optional plot)
conicity   equivalent conicity (EN 15302 definitions) for an amplitude

Lateral shifts are positive towards the **right** rail; all values in SI units.
"""
from __future__ import annotations

import argparse
import sys

import numpy as np


def _add_pair_arguments(p: argparse.ArgumentParser):
    p.add_argument("--wheel", default="S1002", help="wheel profile: S1002 or a .prw / y-z table file")
    p.add_argument("--rail", default="UIC60", help="rail profile: UIC60 (60E1) or a .prr / y-z table file")
    p.add_argument("--inclination", default="1/40", help="rail inclination: 1/40, 1/20, none (default 1/40)")
    p.add_argument("--rail-canted", default="auto",
                   help="inclination the rail file already contains (e.g. 1/40 for the Manchester UIC60 file); "
                        "auto (default) detects it from the head shape")
    p.add_argument("--gauge", type=float, default=1.435, help="track gauge 14 mm below the rail top [m]")
    p.add_argument("--back-to-back", type=float, default=1.360, help="flange back-to-back distance [m]")
    p.add_argument("--r0", type=float, default=0.46, help="nominal rolling radius [m]")
    p.add_argument("--y-max", type=float, default=0.010, help="largest lateral shift of the sweep [m]")
    p.add_argument("--y-step", type=float, default=0.0005, help="step of the sweep [m]")
    p.add_argument("--wheel-load", type=float, default=10e3, help="nominal vertical wheel load for a, b [N]")


def _pair_from_args(args):
    from .contact.pair import WheelRailPair
    from .conventions import parse_inclination
    from .profiles.profiles import resolve_rail, resolve_wheel
    canted = None if str(args.rail_canted).lower() == "auto" else parse_inclination(args.rail_canted)
    rail = resolve_rail(args.rail, canted_tan=canted)
    return WheelRailPair(resolve_wheel(args.wheel), rail, gauge_m=args.gauge, inclination=args.inclination,
                         back_to_back_m=args.back_to_back, r0_m=args.r0)


def _sweep(args, y_max=None):
    from .analysis.geometry_functions import contact_geometry_sweep
    y_max = args.y_max if y_max is None else y_max
    if not (np.isfinite(args.y_step) and np.isfinite(y_max) and args.y_step > 0 and y_max > 0):
        raise ValueError("--y-max and --y-step must be positive finite numbers (metres)")
    if y_max / args.y_step > 20000:
        raise ValueError(f"--y-max / --y-step = {y_max / args.y_step:.0f} steps: too many")
    n = int(round(y_max / args.y_step))
    y = np.linspace(-n * args.y_step, n * args.y_step, 2 * n + 1)
    return contact_geometry_sweep(_pair_from_args(args), y, wheel_load_N=args.wheel_load)


def plot_sweep(sweep, path, title=""):
    """Contact-geometry functions on one page (Δr, contact positions, angles, roll, ellipse)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
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
    fig.tight_layout()
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
    from .analysis.conicity import equivalent_conicity
    y_max = max(args.y_max, args.amplitude + 2 * args.y_step)
    sweep = _sweep(args, y_max=y_max)
    e = 0.5 * (args.back_to_back + 0.140) if args.contact_distance is None else 0.5 * args.contact_distance
    gamma = equivalent_conicity(sweep.y_m, sweep.delta_r_m, args.amplitude, method=args.method,
                                half_contact_distance_m=e, r0_m=args.r0)
    print(f"equivalent conicity {gamma:.4f} (amplitude {args.amplitude * 1e3:g} mm, method {args.method}, "
          f"{args.wheel}/{args.rail} {args.inclination}, gauge {args.gauge} m)")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m exudyn_wheelrail", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    g = sub.add_parser("geometry", help="contact-geometry functions of a lateral sweep")
    _add_pair_arguments(g)
    g.add_argument("--out", required=True, help="CSV file to write")
    g.add_argument("--plot", default=None, help="PNG file to write (optional)")
    g.set_defaults(func=cmd_geometry)
    c = sub.add_parser("conicity", help="equivalent conicity")
    _add_pair_arguments(c)
    c.add_argument("--amplitude", type=float, default=0.003, help="lateral amplitude [m] (EN 15302: 3 mm)")
    c.add_argument("--method", default="harmonic", choices=("harmonic", "wavelength", "regression"))
    c.add_argument("--contact-distance", type=float, default=None,
                   help="distance between the nominal contact points 2e [m] (default back-to-back + 140 mm)")
    c.set_defaults(func=cmd_conicity)
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, RuntimeError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
