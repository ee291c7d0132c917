"""Command line: ``python -m exudyn_wheelrail <command> ...`` (scripts and regression tests call it; keep it stable).

Commands
--------
geometry   contact-geometry functions of a wheelset lateral sweep -> CSV (and an optional plot)
conicity   equivalent conicity (EN 15302 definitions) for an amplitude
creep-table  build a USETAB-style creep table (npz) with Kalker's exact theory or FASTSIM
rtri       the rigid-rail RTRI validation case (one span, one speed): time series, summary, Figs. 5/6
rtri-sweep the RTRI case over spans x speeds in parallel processes: table and Fig. 7
run        a scenario file (TOML: vehicle, track, optional bridge, run, outputs): time series, summary, criteria
sweep      a scenario over the cartesian product of parameter values (--param KEY=V1,V2,...) in parallel
validation-report  re-run the validations (Kalker E.3, creep table, Klingel, Frýba, RTRI) -> report.md + PNGs
explore    the RTRI explorer: sliders (speed, span, deviation, friction, suspension) re-run the case and redraw
bridge-crossing  a train (axle loads, HSLM-A, or vehicles) over a simply supported span: deck response, EN 1990
bridge-crossing-sweep  the crossing over many speeds in parallel: peak deck response against speed, resonances
curving    steady curving through an entry transition into a canted curve: sum Y, Y/Q, shift, attack angle

Lateral shifts are positive towards the **right** rail; all values in SI units.

Bad input (a malformed or implausible option, a profile that is not what it is given as, an output location that
cannot be written) is reported before any work as one line ``error: <option or file>: <problem>`` with exit code 2;
an unusual but plausible value as one line ``warning: ...``, and the run goes on.  A simulation (``rtri``,
``rtri-sweep``, ``run``, ``sweep``, ``bridge-crossing``, ``curving``) exits with the code of its status (:mod:`exudyn_wheelrail.simulation.status`):
0 ok, 3 derailed, 4 diverged, 5 step_rejected; 1 any other error.
"""
from __future__ import annotations

import argparse
import gc
import math
import re
import sys
import time
import warnings

from .validation import InputWarning, Quantity, output_dir, output_file

# Plausibility of the options that are not parameters of an API object (the wheel-rail pair's gauge, back-to-back
# distance, r0 and inclination are judged by the ranges of exudyn_wheelrail.contact.pair, the scenario's time step,
# span and transition lengths by exudyn_wheelrail.scenarios.scenario.QUANTITIES).
Y_MAX_M = Quantity("largest lateral shift of the sweep", "m", 1e-4, 0.05)
Y_STEP_M = Quantity("step of the lateral sweep", "m", 1e-6, 0.005)
WHEEL_LOAD_N = Quantity("wheel load", "N", 100.0, 1.0e6, typical=(5.0e3, 2.5e5))
CONICITY_AMPLITUDE_M = Quantity("lateral amplitude of the equivalent conicity", "m", 1e-4, 0.015)
CONTACT_DISTANCE_M = Quantity("distance between the nominal contact points", "m", 0.6, 2.2)
SPEED_KM_H = Quantity("running speed", "km/h", 0.1, 600.0)
DEVIATION_MM = Quantity("deviation amplitude", "mm", 0.0, 100.0, typical=(0.5, 50.0))
VIEW_SPEED = Quantity("simulated time per wall-clock time", "", 1e-4, 100.0)
#: largest number of points of a lateral sweep
MAX_SWEEP_STEPS = 20000


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors ``error: <option>: <problem>`` and exit code 2 (no usage block)."""

    def error(self, message):
        m = re.match(r"argument ([^:]+): (.*)", message, re.S)
        if m:
            message = f"{m.group(1)}: {m.group(2)}"
        else:
            m = re.match(r"the following arguments are required: (.*)", message, re.S)
            if m:
                message = f"{m.group(1)}: missing (required by {self.prog}; see {self.prog} --help)"
            else:
                m = re.match(r"unrecognized arguments: (.*)", message, re.S)
                if m:
                    message = f"{m.group(1)}: unrecognized argument(s) of {self.prog} (see {self.prog} --help)"
        _print_line("error", message)
        sys.exit(2)


def _print_line(kind: str, message) -> None:
    """``kind: message`` as one line on stderr (line breaks of the message joined with '; ')."""
    text = "; ".join(part.strip() for part in str(message).splitlines() if part.strip())
    print(f"{kind}: {text}", file=sys.stderr)


def _show_warning(message, category, filename, lineno, file=None, line=None, _default=warnings.showwarning):
    if issubclass(category, InputWarning):
        _print_line("warning", message)
    else:
        _default(message, category, filename, lineno, file, line)


def _positive_int(option: str):
    """argparse type: a positive integer."""

    def parse(text):
        try:
            n = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
        if n < 1:
            raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
        return n
    parse.__name__ = option
    return parse


#: with stderr not a terminal (a log file, a pipe), a progress bar asked for by ``--progress`` writes one line at
#: most this often [s], and its last state when the run ends
PROGRESS_LINE_INTERVAL_S = 10.0


def _add_progress_argument(p: argparse.ArgumentParser) -> None:
    """The one progress option of every long command (:func:`_progress_bar`, :func:`_progress_lines`)."""
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="progress on stderr (default: shown when stderr is a terminal; into a file or a pipe "
                        "whole lines only)")


def _show_progress(args) -> bool:
    """``--progress`` / ``--no-progress`` as given, else whether stderr is a terminal."""
    return sys.stderr.isatty() if args.progress is None else bool(args.progress)


class _ProgressLines:
    """The stream of a progress bar when stderr is not a terminal: each redraw of the bar (``"\\r"`` and the bar,
    :class:`~exudyn_wheelrail.simulation.recorder.ProgressBar`) is held and written as a line of its own at most every
    :data:`PROGRESS_LINE_INTERVAL_S`; the bar's close (its status and the line end) writes the last state."""

    def __init__(self, stream):
        self.stream = stream
        self.pending = ""
        self.written_at = time.perf_counter()

    def write(self, text: str) -> None:
        if text.startswith("\r"):
            self.pending = text[1:].rstrip()
            if time.perf_counter() - self.written_at >= PROGRESS_LINE_INTERVAL_S:
                self.stream.write(self.pending + "\n")
                self.written_at = time.perf_counter()
        else:
            self.stream.write(self.pending + text)
            self.pending = ""

    def flush(self) -> None:
        self.stream.flush()


def _progress_bar(args):
    """What a single run's progress bar is drawn on: ``False`` (no bar), stderr (a terminal: redrawn in place) or
    :class:`_ProgressLines` on stderr."""
    if not _show_progress(args):
        return False
    return sys.stderr if sys.stderr.isatty() else _ProgressLines(sys.stderr)


def _progress_lines(args):
    """The print-like callable of a command's progress lines (a sweep's cases, a table's chunks, a report's
    sections) on stderr, or ``None``."""
    if not _show_progress(args):
        return None
    return lambda text: print(text, file=sys.stderr, flush=True)


def _figure_suffixes() -> tuple[str, ...]:
    from matplotlib.backend_bases import FigureCanvasBase
    return tuple(f".{k}" for k in sorted(FigureCanvasBase.get_supported_filetypes()))


def _check_figure(option: str, path) -> None:
    if path is not None:
        output_file(option, path, _figure_suffixes(), what="figure file")


def _check_inclination(option: str, text) -> float:
    from .contact.pair import INCLINATION_TAN
    from .conventions import parse_inclination
    try:
        tan = parse_inclination(text)
    except ValueError as exc:
        raise ValueError(f"{option}: {exc}") from None
    return INCLINATION_TAN.check(option, tan)


def _check_pair_options(args) -> None:
    """The wheel-rail pair's options: plausible numbers, known profiles (the files are read when the pair is built,
    which checks that a wheel file holds a wheel and a rail file a rail)."""
    from .contact.pair import BACK_TO_BACK_M, GAUGE_M, R0_M, back_to_back_problem
    from .profiles.profiles import profile_spec_problem
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
    Y_MAX_M.check("--y-max", args.y_max)
    Y_STEP_M.check("--y-step", args.y_step)
    if args.y_step > args.y_max:
        raise ValueError(f"--y-step: {args.y_step:g} m is larger than --y-max {args.y_max:g} m")
    WHEEL_LOAD_N.check("--wheel-load", args.wheel_load)


def _check_geometry(args) -> None:
    output_file("--out", args.out, what="CSV file")
    _check_figure("--plot", args.plot)
    _check_pair_options(args)


def _check_conicity(args) -> None:
    _check_pair_options(args)
    CONICITY_AMPLITUDE_M.check("--amplitude", args.amplitude)
    if args.contact_distance is not None:
        CONTACT_DISTANCE_M.check("--contact-distance", args.contact_distance)


def _check_creep_table(args) -> None:
    from .creep.linear import table_poisson
    output_file("--out", args.out, (".npz",), what="creep table")
    table_poisson(args.nu, "--nu")


def _check_rtri_common(args) -> None:
    output_dir("--out", args.out)
    if args.delta_mm is not None:
        DEVIATION_MM.check("--delta-mm", args.delta_mm)
    if args.transition_m is not None:
        from .scenarios.scenario import QUANTITIES
        QUANTITIES["track.*.transition_length_m"].check("--transition-m", args.transition_m)
    args.settings = _rtri_settings(args)


def _check_rtri(args) -> None:
    from .scenarios.scenario import QUANTITIES
    _check_rtri_common(args)
    QUANTITIES["track.*.span_length_m"].check("--span", args.span)
    SPEED_KM_H.check("--speed-kmh", args.speed_kmh)
    VIEW_SPEED.check("--view-speed", args.view_speed)


def _check_rtri_sweep(args) -> None:
    from .scenarios.scenario import QUANTITIES
    _check_rtri_common(args)
    for span in args.spans or ():
        QUANTITIES["track.*.span_length_m"].check("--spans", span)
    for speed in args.speeds_kmh or ():
        SPEED_KM_H.check("--speeds-kmh", speed)


def _check_out_dir(args) -> None:
    output_dir("--out", args.out)


def _check_sweep(args) -> None:
    output_dir("--out", args.out)
    if not args.param:
        raise ValueError("--param: missing (give at least one --param KEY=V1,V2,...)")


def _check_explore(args) -> None:
    from .interactive.explorer import ExplorerSettings
    from .simulation.settings import DURATION_AUTO, ContactSettings, RunSettings, SettingsError
    _check_figure("--out", args.out)
    try:
        args.explorer_settings = ExplorerSettings(
            run=RunSettings(solver=args.solver, dt_s=args.dt, duration_s=DURATION_AUTO),
            contact=ContactSettings(geometry=args.geometry), window=args.window)
    except SettingsError as exc:
        raise _settings_error(exc) from None


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

    from .scenarios.plots import pyplot
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
    from .analysis.conicity import equivalent_conicity
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
    from .creep.build_table import build_table, grid_summary
    print(grid_summary(args.grid))
    path = build_table(args.out, generator=args.generator, grid=args.grid, workers=args.workers, poisson=args.nu,
                       options=dict(args.option or []), keep_parts=args.keep_parts, progress=_progress_lines(args))
    print(f"wrote {path}")
    return 0


def _duration(text):
    """argparse type of ``--duration``: a time in s or ``auto``."""
    from .simulation.settings import DURATION_AUTO
    if text == DURATION_AUTO:
        return text
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a time in s or {DURATION_AUTO!r}, got {text!r}") from None


def _steps(text):
    """argparse type of ``--steps``: a positive number of steps or ``auto``."""
    from .simulation.settings import DURATION_AUTO
    return text if text == DURATION_AUTO else _positive_int("--steps")(text)


#: the command line's option of each run/contact setting (errors name the option)
SETTING_OPTIONS = {"solver": "--solver", "dt_s": "--dt", "duration_s": "--duration", "creep_law": "--creep-law",
                   "geometry": "--geometry"}


def _settings_error(exc):
    """A :class:`~.simulation.settings.SettingsError` as a ValueError naming the option."""
    return ValueError(f"{SETTING_OPTIONS.get(exc.field, exc.field)}: {exc.problem}")


def _rtri_deviation(args):
    delta = None if args.delta_mm is None else args.delta_mm * 1e-3
    return delta, args.transition_m


def _print_status(summary):
    st = summary["status_detail"]
    rtf = summary["real_time_factor"] or 0.0
    line = f"status: {summary['status']}"
    if st["kind"] != "ok":
        where = "" if st["wheelset"] is None else f" wheelset {st['wheelset']}" + (
            f" {st['side']}" if st["side"] else "")
        when = "" if st["time_s"] is None else f" at t = {st['time_s']:.6g} s"
        line += f"{where}{when}: {st['detail']}"
    print(line)
    if st["hint"]:
        print(f"hint: {st['hint']}")
    print(f"{summary['steps']} steps of {summary['dt_s']:g} s planned ({summary['duration_s']:.4g} s); solve "
          f"{summary['solve_seconds']:.2f} s for {summary['simulated_time_s']:.4g} s simulated (real-time factor "
          f"{rtf:.2f}), exit code {st['exit_code']}")


def _print_rtri_summary(summary):
    import json
    p = summary.get("peaks_passage", {})
    _print_status(summary)
    if p:
        print(f"passage peaks: max |Y| w1 right {p['max_abs_lateral_contact_force_w1_right_N'] / 1e3:.2f} kN, max "
              f"|a| car body rear {p['max_abs_carbody_lateral_acceleration_rear_m_s2']:.3f} m/s^2, flange contact "
              f"w1 right: {'yes' if p['flange_contact_w1_right'] else 'no'} "
              f"({p['flange_contact_w1_right_duration_s'] * 1e3:.0f} ms)")
    for note in summary["notes"]:
        print("note:", note)
    print("assumptions (value, origin):")
    for group, items in summary["assumptions"].items():
        for name, item in items.items():
            if isinstance(item, dict):
                print(f"  {group}.{name} = {json.dumps(item['value'])}  [{item['origin']}]")
            else:
                print(f"  {group}.{name}: {item}")


def _rtri_settings(args):
    """``(RunSettings, ContactSettings, preset record)`` from the case's settings, ``--preset`` and the explicit
    options (which override it); the sweep's duration defaults to ``auto``."""
    import dataclasses

    from .scenarios.rtri import RtriCase
    from .simulation.presets import apply_preset
    from .simulation.settings import DURATION_AUTO, SettingsError
    case = RtriCase()
    run = case.run if args.command == "rtri" else dataclasses.replace(case.run, duration_s=DURATION_AUTO)
    duration = DURATION_AUTO if args.steps == DURATION_AUTO else args.duration
    try:
        run, contact, preset = apply_preset(args.preset, run, case.contact,
                                            run_options=dict(solver=args.solver, dt_s=args.dt, duration_s=duration),
                                            contact_options=dict(creep_law=args.creep_law, geometry=args.geometry))
        if isinstance(args.steps, int):         # --steps N: N steps of the resolved dt
            run = dataclasses.replace(run, duration_s=args.steps * run.dt_s)
    except SettingsError as exc:
        raise _settings_error(exc if not isinstance(args.steps, int) or exc.field != "duration_s" else
                              SettingsError("--steps", exc.problem)) from None
    return run, contact, preset


def _car_body_choices():
    from .scenarios.defaults import CAR_BODY_MODELS
    return CAR_BODY_MODELS + ("both",)


def _cmd_rtri_car_bodies(args, run, contact, delta, lt):
    """``rtri --car-body both``: the rigid and the flexible car body with the same settings and the same measurement
    points, each into its own directory, and the comparison figure."""
    from pathlib import Path

    from .scenarios.rtri import RtriCase, run_rtri, write_rtri_outputs
    from .scenarios.rtri_case import CAR_BODY_MODELS, CARBODY_POINTS
    from .scenarios.rtri_figures import plot_carbody_comparison
    from .simulation.status import exit_code
    results = {}
    for cb in CAR_BODY_MODELS:
        case = RtriCase(span_m=args.span, speed_km_h=args.speed_kmh, run=run, contact=contact,
                        deviation_amplitude_m=delta, transition_length_m=lt, car_body=cb,
                        carbody_points=tuple(CARBODY_POINTS))
        results[cb] = run_rtri(case, progress=print, progress_bar=_progress_bar(args))
        paths = write_rtri_outputs(results[cb], Path(args.out) / cb, plots=not args.no_plots)
        print(f"car body {cb}:")
        _print_status(results[cb].summary)
        print("wrote " + ", ".join(str(p) for p in paths.values()))
    for cb, r in results.items():
        for point, dirs in r.summary["comfort"].items():
            print(f"comfort, {cb} car body, {point}: " + ", ".join(
                f"{d} Sperling Wz {v['sperling_Wz']:.2f}, EN 14363 peak {v['en14363_peak_m_s2']:.3f} m/s^2"
                for d, v in dirs.items() if "sperling_Wz" in v))
    if not args.no_plots:
        fig = Path(args.out) / "fig5_carbody_rigid_vs_flexible.png"
        plot_carbody_comparison(results, fig)
        print(f"wrote {fig}")
    return exit_code(r.summary["status"] for r in results.values())


def cmd_rtri(args):
    from .scenarios.rtri import RtriCase, run_rtri, write_rtri_outputs
    delta, lt = _rtri_deviation(args)
    run, contact, preset = args.settings
    if args.car_body == "both":
        return _cmd_rtri_car_bodies(args, run, contact, delta, lt)
    case = RtriCase(span_m=args.span, speed_km_h=args.speed_kmh, run=run, contact=contact,
                    deviation_amplitude_m=delta, transition_length_m=lt, car_body=args.car_body)
    if preset:
        print(f"preset {preset['name']}: {preset['purpose']}; set {preset['set']}"
              + (f"; overridden {preset['overridden_by_options']}" if preset["overridden_by_options"] else ""))
    view = None
    if args.view:
        from .interactive.view3d import RtriView
        view = RtriView(realtime_factor=args.view_speed)
    result = run_rtri(case, progress=print, view=view, progress_bar=_progress_bar(args))
    result.summary["preset"] = preset
    paths = write_rtri_outputs(result, args.out, plots=not args.no_plots)
    _print_rtri_summary(result.summary)
    print("wrote " + ", ".join(str(p) for p in paths.values()))
    return result.summary["status_detail"]["exit_code"]


def cmd_rtri_sweep(args):
    from .scenarios.rtri import RTRI, run_sweep
    from .simulation.status import exit_code
    delta, lt = _rtri_deviation(args)
    speeds = args.speeds_kmh if args.speeds_kmh else list(RTRI.speeds_km_h)
    spans = args.spans if args.spans else list(RTRI.span_lengths_m)
    run, contact, preset = args.settings
    print(f"RTRI sweep: spans {spans} m, speeds {speeds} km/h, {run.solver}, dt {run.dt_s} s, duration "
          f"{run.duration_s}, geometry {contact.geometry}" + (f" (preset {preset['name']})" if preset else ""))
    summaries = run_sweep(spans, speeds, args.out, workers=args.workers, run=run, contact=contact,
                          deviation_amplitude_m=delta, transition_length_m=lt, write_cases=not args.no_case_outputs,
                          progress=_progress_lines(args))
    print(f"wrote {args.out}/sweep.csv, sweep.json, fig7_max_carbody_acceleration.png")
    return exit_code(s["status"] for s in summaries)


def _add_rtri_common(p: argparse.ArgumentParser, duration_default: str):
    from .simulation.presets import PRESETS
    from .simulation.solvers import SOLVERS
    p.add_argument("--preset", default=None, choices=tuple(PRESETS),
                   help="accuracy/speed preset (integrator, dt, contact geometry, creep law; explicit options "
                        "override it; the summary states what it set): "
                        + "; ".join(f"{k}: {v.purpose}" for k, v in PRESETS.items()).replace("%", "%%")
                        + ".  Without a preset: the paper's settings (newmark, 1 ms, online geometry)")
    p.add_argument("--solver", default=None, choices=SOLVERS,
                   help="newmark: trapezoidal rule (beta 1/4, gamma 1/2, the paper's; default without a preset); "
                        "rk44: explicit; others: see exudyn_wheelrail.simulation.settings")
    p.add_argument("--dt", type=float, default=None,
                   help="time step [s] (default 0.001, the paper's, or the preset's); never changes the duration")
    span = p.add_mutually_exclusive_group()
    span.add_argument("--duration", type=_duration, default=None,
                      help=f"simulated time [s] or 'auto' (at least the paper's 2.5 s and until the whole car is "
                           f"10 m past the span); steps = ceil(duration / dt); default {duration_default}")
    span.add_argument("--steps", type=_steps, default=None,
                      help="the simulated time as a number of steps of the run's dt (duration = steps x dt), or "
                           "'auto' (as --duration auto); instead of --duration")
    p.add_argument("--creep-law", default=None, help="creep law of the connector: table (default: Kalker's exact "
                                                     "theory, tabulated), fastsim, shen_hedrick_elkins, polach")
    p.add_argument("--geometry", default=None, choices=("online", "table"),
                   help="contact geometry: online search (default) or the precomputed table for the rigid rail "
                        "profile (built once, ~1 min, cached)")
    p.add_argument("--delta-mm", type=float, default=None,
                   help="deviation amplitude [mm] (default: RtriAssumptions, 10 mm; an override is marked in the "
                        "summary)")
    p.add_argument("--transition-m", type=float, default=None,
                   help="end-transition length [m] (default: RtriAssumptions, 3 m)")
    p.add_argument("--out", required=True, help="output directory")
    _add_progress_argument(p)


def _split_values(text: str) -> list[str]:
    """Split ``V1,V2,...`` at the commas outside brackets and quotes (``[20, 40],[30]`` is two values)."""
    out, cur, depth, quote = [], [], 0, None
    for ch in text:
        if quote:
            quote = None if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == "," and depth == 0:
            out.append("".join(cur))
            cur = []
            continue
        cur.append(ch)
    out.append("".join(cur))
    return out


def _key_values(text: str, option: str, many: bool):
    from .scenarios.scenario import parse_value
    if "=" not in text:
        raise argparse.ArgumentTypeError(f"expected KEY={'V1,V2,...' if many else 'VALUE'}, got {text!r}")
    key, value = text.split("=", 1)
    key = key.strip()
    if not key:
        raise argparse.ArgumentTypeError(f"{text!r}: empty key")
    if not many:
        return key, parse_value(value)
    values = _split_values(value)
    if any(not v.strip() for v in values):
        raise argparse.ArgumentTypeError(f"{text!r}: empty value in the list")
    return key, [parse_value(v) for v in values]


def _overrides(pairs, option: str) -> dict:
    out = {}
    for key, value in pairs or []:
        if key in out:
            raise ValueError(f"{option} {key}: given twice")
        out[key] = value
    return out


def _verdict(check: dict) -> str:
    """'passed' / 'NOT passed' / 'not evaluated (why)' of a criterion's dict."""
    if check.get("passed") is None:
        return f"not evaluated ({check.get('not_evaluated') or 'no verdict'})"
    return "passed" if check["passed"] else "NOT passed"


def cmd_run_scenario(args):
    from .scenarios.scenario import run_scenario
    scn = args.scenario_spec
    veh = scn['vehicle']
    print(f"scenario {scn['scenario']['name']}: {veh.get('name') or veh.get('file') or veh.get('consist')}, "
          f"{scn['vehicle']['speed_km_h']:g} km/h, {scn['run']['solver']}, dt {scn['run']['dt_s']:g} s, duration "
          f"{scn['run']['duration_s']}{', bridge' if 'structure' in scn else ''}")
    result = run_scenario(scn, args.out, progress=_progress_bar(args))
    s = result.summary
    _print_status(s)
    sc = s["scalars"]
    if sc.get("max_abs_Y_any_wheel_N") is not None:
        print(f"max |Y| any wheel {sc['max_abs_Y_any_wheel_N'] / 1e3:.2f} kN, max Y/Q {sc['max_YQ_any_wheel']:.3f}, "
              f"Q {sc['min_Q_any_wheel_N'] / 1e3:.1f} .. {sc['max_Q_any_wheel_N'] / 1e3:.1f} kN, flange contact: "
              f"{'yes' if sc['flange_contact_any_wheel'] else 'no'}")
    cr = s["criteria"]
    if isinstance(cr, dict) and "verdicts" in cr:
        print(f"running safety: {'passed' if cr['safety_passed'] else 'NOT passed'}")
        for k, v in cr["verdicts"].items():
            if v.get("worst_value") is not None:
                print(f"  {k}: {'ok' if v['passed'] else 'FAILED'} (worst {v['worst']}: {v['worst_value']:.4g})")
    for note in s["notes"]:
        print("note:", note)
    print("wrote " + ", ".join(result.paths.values()))
    return s["status_detail"]["exit_code"]


def _check_run(args) -> None:
    from .scenarios.scenario import apply_overrides, load_scenario
    output_dir("--out", args.out)
    scn = load_scenario(args.scenario)
    overrides = _overrides(args.set, "--set")
    if overrides:
        scn = apply_overrides(scn, overrides, source=f"{args.scenario} with --set")
    args.scenario_spec = scn


def cmd_sweep_scenario(args):
    from .scenarios.sweep import DEFAULT_PLOT_RESULT, sweep
    from .simulation.status import exit_code
    params = _overrides(args.param, "--param")
    base = args.scenario
    overrides = _overrides(args.set, "--set")
    if overrides:
        from .scenarios.scenario import apply_overrides, load_scenario
        base = apply_overrides(load_scenario(args.scenario), overrides, source=f"{args.scenario} with --set")
    n = 1
    for v in params.values():
        n *= len(v)
    print(f"sweep of {args.scenario}: {n} cases ({' x '.join(f'{k}: {len(v)}' for k, v in params.items())}), "
          f"{args.workers or 'all'} worker processes")
    result = sweep(base, params, out_dir=args.out, workers=args.workers,
                   plot_result=args.plot_result or DEFAULT_PLOT_RESULT, plot_parameter=args.plot_param,
                   write_cases=not args.no_case_outputs, progress=_progress_lines(args))
    for note in result.notes:
        print("note:", note)
    print("wrote " + ", ".join(result.paths.values()))
    return exit_code(result.table["status"])


def cmd_validation_report(args):
    from .scenarios.validation_report import write_report
    write_report(args.out, quick=args.quick, progress=_progress_lines(args))
    print(f"wrote {args.out}/report.md")
    return 0


def cmd_explore(args):
    import matplotlib
    values = _overrides(args.set, "--set")
    if args.out:
        matplotlib.use("Agg")
    from .interactive.explorer_figure import ExplorerFigure
    settings = args.explorer_settings
    if not args.out and matplotlib.get_backend().lower() in ("agg", "pdf", "ps", "svg", "cairo", "template"):
        raise RuntimeError(f"no interactive matplotlib backend ({matplotlib.get_backend()}; no display?): use "
                           "--out FILE.png for a headless run")
    fig = ExplorerFigure(settings=settings, **values)
    u = fig.last
    print(f"{settings.describe()}: run {u.seconds:.2f} s, redraw {fig.last_redraw_s:.2f} s")
    print(fig.status.get_text())
    if args.out:
        fig.save(args.out)
        print(f"wrote {args.out}")
    else:
        fig.show()
    return 0


#: the command line's option of each field of a bridge crossing (errors name the option)
BRIDGE_CROSSING_OPTIONS = {"span_m": "--span-m", "mass_kg_m": "--bridge-mass-kg-per-m",
                           "f1_Hz": "--bridge-frequency-hz",
                           "damping_ratio": "--damping-ratio", "n_modes": "--modes", "speed_m_s": "--speed-kmh",
                           "model": "--model", "free_vibration_s": "--free-vibration-s", "dt_s": "--dt",
                           "solver": "--solver", "track_form": "--track-form", "spans_m": "--spans-m",
                           "lateral_modes": "--lateral-modes", "lateral_f1_Hz": "--lateral-frequency-hz",
                           "sprung_frequency_Hz": "--sprung-frequency-hz",
                           "sprung_damping_ratio": "--sprung-damping-ratio"}


def _bridge_crossing_spans(args):
    """The chain of spans of ``--n-spans`` / ``--spans-m`` (None: the single span ``--span-m``), checked."""
    from .scenarios.bridge_crossing import MAX_SPANS, SPAN_M
    k = args.n_spans
    if k is not None and k > MAX_SPANS:
        raise ValueError(f"--n-spans: {k} spans, more than {MAX_SPANS}")
    if args.spans_m is None:
        return None if k is None or k == 1 else (float(args.span_m),) * k
    spans = [SPAN_M.check("--spans-m", x) for x in args.spans_m]
    if k is not None and k != len(spans):
        raise ValueError(f"--n-spans: {k} spans but --spans-m lists {len(spans)} span lengths")
    if spans[0] != args.span_m:
        raise ValueError(f"--spans-m: the first span {spans[0]:g} m is not --span-m {args.span_m:g} m (--span-m is "
                         "the first span of the chain)")
    if len(spans) > MAX_SPANS:
        raise ValueError(f"--spans-m: {len(spans)} spans, more than {MAX_SPANS}")
    return tuple(spans)


def _check_bridge_crossing(args) -> None:
    """Every option of ``bridge-crossing`` (the axle file read, the load model resolved) before any work; the
    :class:`~.scenarios.bridge_crossing.BridgeCrossing` goes to ``args.crossing``."""
    from pathlib import Path

    from .scenarios.bridge_crossing import (AXLE_LOAD_MODELS, F1_HZ, FREE_VIBRATION_S, MASS_KG_M, SPAN_M,
                                            BridgeCrossing, resolve_load_model, resolve_train_axles)
    from .simulation.settings import DT_S
    from .structures.load_models import hslm_a, read_axle_file
    output_dir("--out", args.out)
    if args.command == "bridge-crossing-sweep":
        args.speeds = _sweep_speeds_kmh(args)
        args.speed_kmh = args.speeds[0]
    SPAN_M.check("--span-m", args.span_m)
    MASS_KG_M.check("--bridge-mass-kg-per-m", args.bridge_mass_kg_per_m)
    F1_HZ.check("--bridge-frequency-hz", args.bridge_frequency_hz)
    SPEED_KM_H.check("--speed-kmh", args.speed_kmh)
    FREE_VIBRATION_S.check("--free-vibration-s", args.free_vibration_s)
    if args.dt is not None:
        DT_S.check("--dt", args.dt)
    z = args.damping_ratio
    if not (math.isfinite(z) and 0.0 <= z < 1.0):
        raise ValueError(f"--damping-ratio: {z:g} must be in [0, 1) (a ratio, not a percentage: 2 % is 0.02)")
    spans = _bridge_crossing_spans(args)
    if args.lateral_frequency_hz is not None:
        F1_HZ.check("--lateral-frequency-hz", args.lateral_frequency_hz)
    axles = None
    if args.axles is not None:
        axles = read_axle_file(args.axles)
    elif args.hslm is not None:
        try:
            axles = hslm_a(args.hslm)
        except ValueError as exc:
            raise ValueError(f"--hslm: {exc}") from None
    elif args.model in AXLE_LOAD_MODELS:
        if not Path(args.train).is_file():
            raise ValueError(f"--train: {args.train}: no such consist file")
        axles = resolve_train_axles(args.train)
    try:
        case = BridgeCrossing(span_m=args.span_m, mass_kg_m=args.bridge_mass_kg_per_m, f1_Hz=args.bridge_frequency_hz,
                              damping_ratio=z, n_modes=args.modes, axles=axles, speed_m_s=args.speed_kmh / 3.6,
                              model=args.model, free_vibration_s=args.free_vibration_s, dt_s=args.dt,
                              solver=args.solver, track_form=args.track_form, train_file=args.train,
                              spans_m=spans, lateral_modes=args.lateral_modes,
                              lateral_f1_Hz=args.lateral_frequency_hz,
                              sprung_frequency_Hz=args.sprung_frequency_hz,
                              sprung_damping_ratio=args.sprung_damping_ratio)
    except ValueError as exc:
        name, _, problem = str(exc).partition(": ")
        raise ValueError(f"{BRIDGE_CROSSING_OPTIONS.get(name, name)}: {problem}") from None
    resolve_load_model(case.model).check(case)
    args.crossing = case


#: most speeds of one bridge-crossing sweep
MAX_SWEEP_SPEEDS = 10_000


def _sweep_speeds_kmh(args) -> list[float]:
    """The speeds of ``bridge-crossing-sweep`` [km/h], each checked (``--speeds-kmh`` or ``--speed-range-kmh``)."""
    if args.speeds_kmh is not None:
        option, speeds = "--speeds-kmh", list(args.speeds_kmh)
    else:
        option = "--speed-range-kmh"
        first, last, step = args.speed_range_kmh
        for v in (first, last, step):
            if not math.isfinite(v):
                raise ValueError(f"{option}: {v!r} is not a finite number")
        if not step > 0 or last < first:
            raise ValueError(f"{option}: expected FIRST <= LAST and STEP > 0, got {first:g} {last:g} {step:g}")
        n = math.floor((last - first) / step + 1e-9) + 1
        if n > MAX_SWEEP_SPEEDS:
            raise ValueError(f"{option}: {n} speeds, more than {MAX_SWEEP_SPEEDS}")
        speeds = [first + k * step for k in range(n)]
    for v in speeds:
        SPEED_KM_H.check(option, v)
    return speeds


def cmd_bridge_crossing_sweep(args):
    from .scenarios.bridge_crossing import speed_sweep
    from .simulation.status import exit_code
    case = args.crossing
    src = case.axles.name if case.axles is not None else case.train_file
    print(f"bridge-crossing sweep: {case.model}, {src}, L = {case.span_m:g} m, f1 = {case.f1_Hz:g} Hz, "
          f"{case.n_modes} modes, {len(args.speeds)} speeds {min(args.speeds):g} ... {max(args.speeds):g} km/h, "
          f"{args.workers or 'all'} worker processes")
    result = speed_sweep(case, [v / 3.6 for v in args.speeds], out_dir=args.out, workers=args.workers,
                         write_cases=args.case_outputs, progress=_progress_lines(args))
    if result.resonance_speeds:
        print("resonance speeds f1 d/i: " + ", ".join(f"{r['speed_km_h']:.4g}" for r in result.resonance_speeds)
              + " km/h")
    print(f"{len(args.speeds)} speeds in {result.wall_seconds:.1f} s; wrote " + ", ".join(result.paths.values()))
    return exit_code(result.table["status"])


def cmd_bridge_crossing(args):
    from .scenarios.bridge_crossing import default_dt_s, run_bridge_crossing
    case = args.crossing
    src = case.axles.name if case.axles is not None else case.train_file
    chain = "" if case.n_spans == 1 else f" (spans {' + '.join(f'{x:g}' for x in case.chain_m)} m)"
    lateral = f" + {case.lateral_modes} lateral" if case.lateral_modes else ""
    print(f"bridge crossing: {case.model}, {src}, L = {case.span_m:g} m{chain}, f1 = {case.f1_Hz:g} Hz, "
          f"{case.n_modes}{lateral} modes, zeta = {case.damping_ratio:g}, {case.speed_m_s * 3.6:g} km/h, "
          f"{case.solver}, dt "
          f"{case.dt_s if case.dt_s is not None else default_dt_s(case):g} s")
    result = run_bridge_crossing(case, out_dir=args.out, progress=_progress_bar(args))
    s = result.summary
    st = s["status_detail"]
    print(f"status: {s['status']}" + (f": {st['detail']}" if st["kind"] != "ok" and st["detail"] else ""))
    if st["hint"]:
        print(f"hint: {st['hint']}")
    if s["max_abs_deck_midspan_displacement_m"] is not None:
        en = s["EN1990_A2_deck_acceleration"]
        qs = s["quasi_static"]
        print(f"max |w| mid-span {s['max_abs_deck_midspan_displacement_m'] * 1e3:.4g} mm (quasi-static "
              f"{qs['max_midspan_displacement_m'] * 1e3:.4g} mm, dynamic amplification "
              f"{qs['dynamic_amplification']:.3g}), max |a| mid-span "
              f"{s['max_abs_deck_midspan_acceleration_m_s2']:.4g} m/s^2; EN 1990 deck acceleration "
              f"{en['peak_acceleration_m_s2']:.4g} m/s^2 (limit {en['limit_m_s2']:g}, {en['track_form']}): "
              f"{_verdict(en)}")
    for sp in s.get("spans") or ():
        if sp["max_abs_midspan_displacement_m"] is not None:
            en = sp["EN1990_A2_deck_acceleration"]
            print(f"span {sp['span']} ({sp['span_m']:g} m): max |w| mid-span "
                  f"{sp['max_abs_midspan_displacement_m'] * 1e3:.4g} mm, max |a| mid-span "
                  f"{sp['max_abs_midspan_acceleration_m_s2']:.4g} m/s^2, EN 1990 "
                  f"{en['peak_acceleration_m_s2']:.4g} m/s^2: {_verdict(en)}")
    if s.get("max_abs_deck_lateral_midspan_displacement_m") is not None:
        print(f"lateral mid-span: max |v| {s['max_abs_deck_lateral_midspan_displacement_m'] * 1e3:.4g} mm, max |a_y| "
              f"{s['max_abs_deck_lateral_midspan_acceleration_m_s2']:.4g} m/s^2")
    if s["resonance_speeds"]:
        print("resonance speeds f1 d/i (d = %.4g m): %s km/h" % (
            s["characteristic_spacing_m"], ", ".join(f"{r['speed_km_h']:.4g}" for r in s["resonance_speeds"])))
    print(f"{s['steps']} steps of {s['dt_s']:g} s, solve {s['solve_seconds']:.2f} s for {s['simulated_seconds']:.4g} s "
          f"simulated, exit code {st['exit_code']}")
    for note in s["notes"]:
        print("note:", note)
    print("wrote " + ", ".join(result.paths.values()))
    return st["exit_code"]


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="python -m exudyn_wheelrail", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    g = sub.add_parser("geometry", help="contact-geometry functions of a lateral sweep")
    _add_pair_arguments(g)
    g.add_argument("--out", required=True, help="CSV file to write")
    g.add_argument("--plot", default=None, help="PNG file to write (optional)")
    g.set_defaults(func=cmd_geometry, check=_check_geometry)
    c = sub.add_parser("conicity", help="equivalent conicity")
    _add_pair_arguments(c)
    c.add_argument("--amplitude", type=float, default=0.003, help="lateral amplitude [m] (EN 15302: 3 mm)")
    c.add_argument("--method", default="harmonic", choices=("harmonic", "wavelength", "regression"))
    c.add_argument("--contact-distance", type=float, default=None,
                   help="distance between the nominal contact points 2e [m] (default back-to-back + 140 mm)")
    c.set_defaults(func=cmd_conicity, check=_check_conicity)
    t = sub.add_parser("creep-table", help="build a creep table (Kalker exact theory or FASTSIM) into an npz file",
                       description="Build a USETAB-style creep table (exudyn_wheelrail.creep.table): parallel, "
                                   "chunked, resumable (re-run the same command to continue), deterministic.")
    t.add_argument("--out", required=True, help="npz file to write (the package table: "
                                                "exudyn_wheelrail/data/creep_table.npz, exact generator only)")
    t.add_argument("--generator", default="exact", choices=("exact", "fastsim"),
                   help="exact: Kalker's exact theory (default); fastsim: FASTSIM stand-in (development)")
    t.add_argument("--workers", type=_positive_int("--workers"), default=None,
                   help="worker processes (default: all cores)")
    t.add_argument("--grid", default="default", choices=("coarse", "default"), help="node set (default: default)")
    t.add_argument("--nu", type=float, default=0.28, help="Poisson's ratio of the table (default 0.28, steel)")
    t.add_argument("--option", action="append", type=_parse_option, metavar="KEY=VALUE",
                   help="generator option, repeatable (FASTSIM: n_x, n_y, flexibility; exact: the solver's "
                        "keyword options, warm_start=1)")
    t.add_argument("--keep-parts", action="store_true", help="keep the per-chunk results after assembling")
    _add_progress_argument(t)
    t.add_argument("--quiet", dest="progress", action="store_false", default=None, help="the same as --no-progress")
    t.set_defaults(func=cmd_creep_table, check=_check_creep_table)
    r = sub.add_parser("rtri", help="the rigid-rail RTRI validation case (substitute inputs, see summary.json)",
                       description="RTRI rigid-rail case: Manchester vehicle 1 (substitute) on a rigid track with a "
                                   "span-deflection lateral deviation at constant speed; writes timeseries.csv, "
                                   "summary.json, fig5_carbody_acceleration.png, fig6_lateral_force.png")
    r.add_argument("--span", type=float, default=20.0, help="span length L [m] (default 20)")
    r.add_argument("--speed-kmh", type=float, default=250.0, help="running speed [km/h] (default 250)")
    _add_rtri_common(r, "2.5 s (the paper's 2500 steps of 1 ms)")
    r.add_argument("--no-plots", action="store_true", help="do not write the PNG figures")
    r.add_argument("--car-body", default="rigid", choices=_car_body_choices(),
                   help="car-body model: rigid (the vehicle file's; default), flexible (its variant with a "
                        "free-free beam car body: RtriAssumptions.flexible_vehicle), or both "
                        "(the two runs into OUT/rigid and OUT/flexible, their car-body accelerations side by side in "
                        "OUT/fig5_carbody_rigid_vs_flexible.png and the comfort indices of both printed)")
    r.add_argument("--view", action="store_true",
                   help="show the run in Exudyn's 3-D renderer (wheels, rails, contact points, force arrows); the "
                        "window stays open after the solve until closed (Q/Escape); solve_seconds then include it")
    r.add_argument("--view-speed", type=float, default=0.25,
                   help="with --view: simulated time per wall-clock time (default 0.25, slow motion)")
    r.set_defaults(func=cmd_rtri, check=_check_rtri)
    w = sub.add_parser("rtri-sweep", help="the RTRI case over spans and speeds in parallel (Fig. 7)",
                       description="Runs the RTRI case for every span x speed in parallel processes; writes "
                                   "sweep.csv, sweep.json, fig7_max_carbody_acceleration.png and cases/L*_V*/")
    w.add_argument("--spans", type=float, nargs="+", default=None, help="span lengths [m] (default 20 40)")
    w.add_argument("--speeds-kmh", type=float, nargs="+", default=None,
                   help="speeds [km/h] (default RtriAssumptions.speeds_km_h: 100 150 200 250)")
    w.add_argument("--workers", type=_positive_int("--workers"), default=None,
                   help="worker processes (default: all cores)")
    w.add_argument("--no-case-outputs", action="store_true", help="do not write each case's files")
    _add_rtri_common(w, "auto")
    w.set_defaults(func=cmd_rtri_sweep, check=_check_rtri_sweep)
    sr = sub.add_parser("run", help="run a scenario file (TOML; schema: exudyn_wheelrail/scenarios/scenario.py)",
                        description="Build, solve and evaluate a scenario: writes timeseries.csv/.npz, summary.json "
                                    "(peaks, scalars, running criteria) and plots into --out.")
    sr.add_argument("scenario", help="scenario file (.toml), e.g. examples/scenarios/rtri_20m.toml")
    sr.add_argument("--out", required=True, help="output directory")
    _add_progress_argument(sr)
    sr.add_argument("--set", action="append", metavar="KEY=VALUE",
                    type=lambda t: _key_values(t, "--set", many=False),
                    help="override a value by its dotted key, repeatable (run.duration_s=0.5, "
                         "track.0.amplitude_m=0.005)")
    sr.set_defaults(func=cmd_run_scenario, check=_check_run)
    ss = sub.add_parser("sweep", help="a scenario over a parameter grid in parallel: one table and one plot",
                        description="Runs the cartesian product of the --param values over a scenario in parallel "
                                    "processes; writes sweep.csv (one row per case), sweep.json, sweep_plot.png and "
                                    "cases/case_*/.")
    ss.add_argument("scenario", help="base scenario file (.toml)")
    ss.add_argument("--param", action="append", metavar="KEY=V1,V2,...",
                    type=lambda t: _key_values(t, "--param", many=True),
                    help="a swept parameter by its dotted key and its values, repeatable "
                         "(vehicle.speed_km_h=100,150,200 --param track.0.span_length_m=20,40)")
    ss.add_argument("--set", action="append", metavar="KEY=VALUE",
                    type=lambda t: _key_values(t, "--set", many=False),
                    help="a fixed override of the base scenario, repeatable")
    ss.add_argument("--out", required=True, help="output directory")
    ss.add_argument("--workers", type=_positive_int("--workers"), default=None,
                    help="worker processes (default: all cores)")
    ss.add_argument("--plot-result", default=None,
                    help="scalar result plotted (default max_abs_Y_any_wheel_N; any column of sweep.csv)")
    ss.add_argument("--plot-param", default=None, help="parameter on the x axis (default: the first --param)")
    ss.add_argument("--no-case-outputs", action="store_true", help="do not write each case's files")
    _add_progress_argument(ss)
    ss.set_defaults(func=cmd_sweep_scenario, check=_check_sweep)
    vr = sub.add_parser("validation-report", help="re-run the validations into report.md with plots",
                        description="Kalker's exact solver vs Table E.3, the creep table vs the exact solver, "
                                    "Klingel's wavelength, Frýba's moving force and the RTRI 20 m vs 40 m peaks: "
                                    "writes DIR/report.md and PNG plots.")
    vr.add_argument("--out", required=True, help="output directory")
    vr.add_argument("--quick", action="store_true",
                    help="fewer creep-table points, shorter Klingel/Frýba runs, no RTRI runs (< 60 s)")
    _add_progress_argument(vr)
    vr.set_defaults(func=cmd_validation_report, check=_check_out_dir)
    ex = sub.add_parser("explore", help="the RTRI explorer: sliders re-run the case and redraw Figs. 5/6 quantities",
                        description="Matplotlib window with sliders for speed, span, deviation amplitude, friction and "
                                    "suspension factors; releasing a slider re-runs the RTRI case (RK44 1 ms over the "
                                    "passage by default, see exudyn_wheelrail/interactive/explorer.py) and redraws. "
                                    "--out FILE.png runs once headless and saves the window.")
    ex.add_argument("--set", action="append", metavar="NAME=VALUE",
                    type=lambda t: _key_values(t, "--set", many=False),
                    help="initial slider value, repeatable: speed_km_h, span_m, deviation_mm, friction, "
                         "primary_kx_factor, primary_ky_factor, secondary_ky_factor, secondary_cy_factor")
    ex.add_argument("--solver", default="rk44", help="integrator of the explorer's runs (default rk44; "
                                                     "newmark, generalized_alpha, rk33, rk67, explicit_midpoint)")
    ex.add_argument("--dt", type=float, default=1e-3, help="time step [s] (default 0.001)")
    ex.add_argument("--geometry", default="online", choices=("online", "table"),
                    help="contact geometry: online search (default, as the full run) or the precomputed table "
                         "(about 2x faster updates, larger differences in raw force peaks)")
    ex.add_argument("--window", default="passage", choices=("passage", "published"),
                    help="passage: until the whole car has left the span + run-out (default); published: 2.5 s")
    ex.add_argument("--out", default=None, help="headless: run once with the --set values and save the window here")
    ex.set_defaults(func=cmd_explore, check=_check_explore)
    _add_bridge_crossing_parser(sub)
    _add_curving_parser(sub)
    return parser


def _add_bridge_crossing_parser(sub) -> None:
    bc = sub.add_parser("bridge-crossing", help="a train over a simply supported span: moving loads (or vehicles) on "
                                                "the modal deck in Exudyn",
                        description="A train crosses a simply supported Euler-Bernoulli span (EI from f1, m, L; N "
                                    "vertical modes, modal damping) built in Exudyn, or a chain of them (--spans-m, "
                                    "--n-spans), optionally with lateral modes (--lateral-modes); t = 0 when the "
                                    "first axle enters, the run ends when the last axle leaves (+ "
                                    "--free-vibration-s). Writes "
                                    "DIR/timeseries.csv and DIR/summary.json (deck values positive downward). Model: "
                                    "exudyn_wheelrail/scenarios/bridge_crossing.py.")
    _add_bridge_crossing_arguments(bc, sweep=False)
    bc.set_defaults(func=cmd_bridge_crossing, check=_check_bridge_crossing)
    sw = sub.add_parser("bridge-crossing-sweep", help="bridge-crossing over a range of speeds in parallel: peaks vs "
                                                      "speed, resonance speeds marked",
                        description="Runs bridge-crossing at every speed in parallel processes; writes sweep.csv "
                                    "(one row per speed), sweep.json and sweep_plot.png (max mid-span displacement "
                                    "and acceleration vs speed, resonance speeds f1 d/i marked, EN 1990 limit).")
    _add_bridge_crossing_arguments(sw, sweep=True)
    sw.set_defaults(func=cmd_bridge_crossing_sweep, check=_check_bridge_crossing)


def _add_bridge_crossing_arguments(bc, sweep: bool) -> None:
    from .scenarios.defaults import (DEFAULT_SOLVER, LATERAL_EI_RATIO, MAX_MODES, MODEL_NAMES, SPRUNG_DAMPING_RATIO,
                                     SPRUNG_FREQUENCY_HZ, STEPS_PER_PERIOD)
    from .simulation.solvers import SOLVERS
    from .standards import HSLM_NAMES, TRACK_FORMS
    bc.add_argument("--span-m", type=float, required=True, help="span length L [m]")
    bc.add_argument("--bridge-mass-kg-per-m", type=float, required=True, help="deck mass per length m [kg/m]")
    bc.add_argument("--bridge-frequency-hz", type=float, required=True,
                    help="first bending frequency f1 [Hz]; EI = m (2 L^2 f1 / pi)^2")
    bc.add_argument("--damping-ratio", type=float, required=True, help="modal damping ratio of every mode, 0 <= z < 1")
    bc.add_argument("--modes", type=_positive_int("--modes"), required=True,
                    help=f"vertical bending modes kept per span (1 to {MAX_MODES})")
    bc.add_argument("--n-spans", type=_positive_int("--n-spans"), default=None, metavar="K",
                    help="a chain of K equal simply supported spans of --span-m (default 1); each span an independent "
                         "deck; the deck_midspan_* columns and keys are the first span's, deck_span<k>_* each span's")
    bc.add_argument("--spans-m", type=float, nargs="+", default=None, metavar="L",
                    help="a chain of simply supported spans in running order [m]; the first must be --span-m (the "
                         "span of --bridge-frequency-hz: every span has its section, span k f1 (L1/Lk)^2)")
    bc.add_argument("--lateral-modes", type=int, default=0, metavar="N_L",
                    help=f"lateral bending modes kept per span (0 to {MAX_MODES}, default 0); moving vertical loads "
                         "leave them at rest, the vehicles model excites them")
    bc.add_argument("--lateral-frequency-hz", type=float, default=None, metavar="F_L",
                    help="first lateral bending frequency of the first span [Hz]: EI_z = m (2 L^2 F_L / pi)^2 "
                         f"(default EI_z = {LATERAL_EI_RATIO:g} EI_y, F_L = sqrt({LATERAL_EI_RATIO:g}) f1)")
    src = bc.add_mutually_exclusive_group(required=True)
    src.add_argument("--axles", default=None, metavar="FILE.csv",
                     help="axle file: CSV with columns x_m (distance behind the first axle, >= 0) and load_N "
                          "(downward force)")
    src.add_argument("--hslm", default=None, metavar="A1..A10",
                     help=f"a universal train of EN 1991-2 (Table 6.3, Fig. 6.12): {', '.join(HSLM_NAMES)}")
    src.add_argument("--train", default=None, metavar="FILE.toml", help="a consist file (vehicles under vehicles/)")
    bc.add_argument("--model", default=MODEL_NAMES[0], choices=MODEL_NAMES,
                    help="moving-loads: constant axle loads (default); vehicles: the full vehicle-bridge "
                         "interaction; sprung-masses: every axle a mass P/g on a spring and damper on the deck")
    bc.add_argument("--sprung-frequency-hz", type=float, default=SPRUNG_FREQUENCY_HZ, metavar="F_V",
                    help=f"sprung-masses: suspension frequency of every axle's mass [Hz] (default "
                         f"{SPRUNG_FREQUENCY_HZ:g}, assumed)")
    bc.add_argument("--sprung-damping-ratio", type=float, default=SPRUNG_DAMPING_RATIO, metavar="Z_V",
                    help=f"sprung-masses: suspension damping ratio (default {SPRUNG_DAMPING_RATIO:g}, assumed)")
    if sweep:
        sp = bc.add_mutually_exclusive_group(required=True)
        sp.add_argument("--speeds-kmh", type=float, nargs="+", default=None, help="the speeds [km/h]")
        sp.add_argument("--speed-range-kmh", type=float, nargs=3, default=None, metavar=("FIRST", "LAST", "STEP"),
                        help="the speeds FIRST, FIRST + STEP, ... up to LAST [km/h] (e.g. 100 420 10)")
        bc.add_argument("--workers", type=_positive_int("--workers"), default=None,
                        help="worker processes (default: all cores)")
        bc.add_argument("--case-outputs", action="store_true", help="write each speed's files under cases/")
    else:
        bc.add_argument("--speed-kmh", type=float, required=True, help="running speed [km/h]")
    bc.add_argument("--out", required=True, help="output directory")
    bc.add_argument("--free-vibration-s", type=float, default=0.0,
                    help="time simulated after the last axle has left the (last) span [s] (default 0)")
    bc.add_argument("--dt", type=float, default=None,
                    help=f"time step [s] (default: min(1/({STEPS_PER_PERIOD} f_N), 2L/({STEPS_PER_PERIOD} N V), "
                         "0.01 s), f_N = N^2 f1)")
    bc.add_argument("--solver", default=DEFAULT_SOLVER, choices=SOLVERS,
                    help=f"integrator (default {DEFAULT_SOLVER})")
    bc.add_argument("--track-form", default=TRACK_FORMS[0], choices=TRACK_FORMS,
                    help="the EN 1990 A2 deck-acceleration limit: ballasted 3.5 m/s^2 (default), direct_fastening "
                         "5 m/s^2")
    _add_progress_argument(bc)


#: the command line's option of each field of a curving case (errors name the option)
CURVING_OPTIONS = {"radius_m": "--radius-m", "cant_m": "--cant-m", "speed_km_h": "--speed-kmh",
                   "transition_m": "--transition-m", "direction": "--direction", "vehicle": "--vehicle",
                   "irregularity": "--irregularity-spectrum"}


def _add_curving_parser(sub) -> None:
    from .scenarios.defaults import DEFAULT_MIN_TRANSITION_M, DEFAULT_RAMP, LEAD_IN_M
    from .standards import DEFAULT_BAND_M, TRACK_SPECTRA
    cv = sub.add_parser("curving", help="steady curving: a vehicle through an entry transition into a circular "
                                        "curve; per wheelset sum Y, Y/Q, lateral shift, angle of attack",
                        description="Runs the vehicle from straight track through a clothoid transition with a linear "
                                    "cant ramp into a circular curve until it is steady, in track-following frames "
                                    "(exudyn_wheelrail/scenarios/curving.py, multibody/track_following.py). Writes "
                                    "DIR/summary.json (status, vehicle_mass_kg, unbalanced_lateral_acceleration_m_s2 "
                                    "in the track plane, positive outwards, sum_Y_N per wheelset: the steady lateral "
                                    "force between both rails and the wheelset, positive outwards on the track, so "
                                    "that its sum is m a_nc) and DIR/timeseries.csv.")
    cv.add_argument("--vehicle", required=True, metavar="NAME|FILE",
                    help="a shipped vehicle (the name of a vehicles/*.toml file, e.g. manchester_vehicle1) or a "
                         "vehicle file")
    cv.add_argument("--radius-m", type=float, required=True, help="radius of the circular curve [m]")
    cv.add_argument("--cant-m", type=float, required=True,
                    help="cant (superelevation of the outer rail) [m], 0 ... 0.2 (sin phi = cant / 1.5 m)")
    cv.add_argument("--speed-kmh", type=float, required=True, help="running speed [km/h]")
    cv.add_argument("--transition-m", type=float, default=None,
                    help=f"length of the entry transition (clothoid, linear cant ramp) [m] (default: the cant ramp "
                         f"1:{DEFAULT_RAMP:g}, at least {DEFAULT_MIN_TRANSITION_M:g} m; the leading wheelset starts "
                         f"{LEAD_IN_M:g} m before it)")
    cv.add_argument("--direction", default="right", choices=("right", "left"),
                    help="direction of the curve, looking in the running direction (default right)")
    cv.add_argument("--irregularity-spectrum", default=None, choices=tuple(TRACK_SPECTRA), metavar="NAME",
                    help="run over track irregularities (all four channels) generated from this standard spectrum "
                         f"({', '.join(TRACK_SPECTRA)}; exudyn_wheelrail/track/spectra.py) in the wavelength band "
                         f"{DEFAULT_BAND_M[0]:g}-{DEFAULT_BAND_M[1]:g} m over the run's distance, faded in from the "
                         "leading wheelset's start to the circular curve (default: a perfect track); needs --seed")
    cv.add_argument("--seed", type=int, default=None, metavar="N",
                    help="seed of the generated irregularity (a non-negative integer; the same seed gives the same "
                         "track)")
    cv.add_argument("--out", required=True, help="output directory")
    _add_progress_argument(cv)
    cv.set_defaults(func=cmd_curving, check=_check_curving)


def _check_curving(args) -> None:
    """Every option of ``curving`` before any work (the vehicle read, the radius against its wheelbase); the
    :class:`~.scenarios.curving.CurvingCase` goes to ``args.curving``."""
    from .scenarios.curving import CurvingCase, CurvingInputError, check_curving_case
    output_dir("--out", args.out)
    case = CurvingCase(args.vehicle, radius_m=args.radius_m, cant_m=args.cant_m, speed_km_h=args.speed_kmh,
                       transition_m=args.transition_m, direction=args.direction)
    if args.irregularity_spectrum is None and args.seed is not None:
        raise ValueError("--seed: given without --irregularity-spectrum (it seeds the generated irregularity)")
    if args.irregularity_spectrum is not None:
        if args.seed is None:
            raise ValueError(f"--seed: missing (required with --irregularity-spectrum {args.irregularity_spectrum})")
        if args.seed < 0:
            raise ValueError(f"--seed: {args.seed}: expected a non-negative integer")
    try:
        args.curving_vehicle = check_curving_case(case)
        if args.irregularity_spectrum is not None:
            import dataclasses

            from .scenarios.curving import spectral_irregularity
            irregularity = spectral_irregularity(case, args.irregularity_spectrum, args.seed,
                                                 vehicle=args.curving_vehicle)
            case = dataclasses.replace(case, irregularity=irregularity)
            check_curving_case(case, args.curving_vehicle)
    except CurvingInputError as exc:
        raise ValueError(f"{CURVING_OPTIONS.get(exc.option, exc.option)}: {exc.problem}") from None
    args.curving = case


def cmd_curving(args):
    from .scenarios.curving import run_curving
    from .simulation.recorder import ProgressBar
    case = args.curving
    v = args.curving_vehicle
    print(f"curving: {v.name}, R = {case.radius_m:g} m {case.direction}, cant {case.cant_m * 1000:g} mm, "
          f"{case.speed_km_h:g} km/h, transition {case.transition_length_m:g} m")
    if case.irregularity is not None:
        print(f"irregularity: {case.irregularity!r}")
    progress = None
    stream = _progress_bar(args)
    if stream:
        from .scenarios.curving import curving_distances
        progress = ProgressBar(curving_distances(case, v)["duration_s"], stream=stream, label="curving: ")
    result = run_curving(case, out_dir=args.out, progress=progress)
    s = result.summary
    if progress is not None:
        progress.close(s["status"])
    print(f"status: {s['status_text']}")
    print(f"a_nc = {s['unbalanced_lateral_acceleration_m_s2']:.3f} m/s^2, m a_nc = "
          f"{s['vehicle_mass_kg'] * s['unbalanced_lateral_acceleration_m_s2']:.0f} N")
    if s.get("sum_Y_N") is not None:
        print("sum Y per wheelset [N]: " + ", ".join(f"{y:.0f}" for y in s["sum_Y_N"])
              + f"; total {sum(s['sum_Y_N']):.0f} N; steady: {'yes' if s['steady'] else 'NO'}")
    for note in s.get("notes", []):
        print(f"note: {note}")
    print(f"wrote {args.out}/summary.json, {args.out}/timeseries.csv")
    return s["exit_code"]


def main(argv=None) -> int:
    """Run a command; bad input gives one line ``error: <what>: <problem>`` on stderr and exit code 2 (module
    docstring), an unusual value one line ``warning: ...``; any other failure (``RuntimeError``: e.g. a creep table
    that cannot be loaded, a recorder that failed, no display for a window) one line ``error: ...`` and exit code 1;
    a run's own status sets the exit code of a completed command (:mod:`.simulation.status`).

    ``argv`` None: the command line of this process (``python -m exudyn_wheelrail``, ``exudyn-wheelrail``).  Then the
    garbage collector is paused while the checks load the command's modules, and the objects alive after them (the
    modules: the numerical code) and at the end are frozen (``gc.freeze``): they live until the process ends, so
    neither the collector's full passes during the run nor those of the interpreter's exit walk them again."""
    from .simulation.status import EXIT_BAD_INPUT, EXIT_ERROR
    process = argv is None
    if process:
        gc.disable()
    with warnings.catch_warnings():
        warnings.showwarning = _show_warning
        warnings.simplefilter("always", InputWarning)
        args = build_parser().parse_args(argv)
        try:
            args.check(args)           # cheap checks of every option before any work
            if process:
                gc.freeze()
                gc.enable()
            return args.func(args)
        except ValueError as exc:      # bad input: an option, a key of a file, a value out of range
            _print_line("error", exc)
            return EXIT_BAD_INPUT
        except RuntimeError as exc:    # not the input: the environment or the run itself failed
            _print_line("error", exc)
            return EXIT_ERROR
        except OSError as exc:         # a file that cannot be read or written
            where = f"{exc.filename}: " if exc.filename else ""
            _print_line("error", f"{where}{exc.strerror or exc}")
            return EXIT_BAD_INPUT
        finally:
            if process:
                gc.freeze()


if __name__ == "__main__":
    sys.exit(main())
