"""The RTRI commands: ``rtri`` (the rigid-rail RTRI case, one span and one speed), ``rtri-sweep`` (the case over spans
x speeds in parallel), ``validation-report`` (the validations re-run into report.md) and ``explore`` (the RTRI
explorer's window)."""
from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

from ..contact_defaults import CONTACT_PATCHES
from ..scenarios.defaults import CAR_BODY_MODELS
from ..simulation.presets import PRESETS, apply_preset
from ..simulation.settings import DURATION_AUTO, SPEED_KM_H, ContactSettings, RunSettings, SettingsError
from ..simulation.solvers import DEFAULT_STEP_S, SOLVERS
from ..simulation.status import exit_code
from ..validation import Quantity, output_dir
from .common import (add_progress_argument, check_figure, key_value_dict, key_values, positive_int,
                     print_status, progress_bar, progress_lines)

# Plausibility of the RTRI options that are not parameters of an API object (the time step, span and transition
# lengths are judged by exudyn_wheelrail.scenarios.scenario.QUANTITIES).
DEVIATION_MM = Quantity("deviation amplitude", "mm", 0.0, 100.0, typical=(0.5, 50.0))
VIEW_SPEED = Quantity("simulated time per wall-clock time", "", 1e-4, 100.0)


def _check_rtri_common(args) -> None:
    output_dir("--out", args.out)
    if args.delta_mm is not None:
        DEVIATION_MM.check("--delta-mm", args.delta_mm)
    if args.transition_m is not None:
        from ..scenarios.scenario import QUANTITIES
        QUANTITIES["track.*.transition_length_m"].check("--transition-m", args.transition_m)
    args.settings = _rtri_settings(args)


def _check_rtri(args) -> None:
    from ..scenarios.scenario import QUANTITIES
    _check_rtri_common(args)
    QUANTITIES["track.*.span_length_m"].check("--span", args.span)
    SPEED_KM_H.check("--speed-kmh", args.speed_kmh)
    VIEW_SPEED.check("--view-speed", args.view_speed)


def _check_rtri_sweep(args) -> None:
    from ..scenarios.scenario import QUANTITIES
    _check_rtri_common(args)
    for span in args.spans or ():
        QUANTITIES["track.*.span_length_m"].check("--spans", span)
    for speed in args.speeds_kmh or ():
        SPEED_KM_H.check("--speeds-kmh", speed)


def _check_out_dir(args) -> None:
    output_dir("--out", args.out)


def _check_explore(args) -> None:
    from ..interactive.explorer import ExplorerSettings
    check_figure("--out", args.out)
    try:
        args.explorer_settings = ExplorerSettings(
            run=RunSettings(solver=args.solver, dt_s=args.dt, duration_s=DURATION_AUTO),
            contact=ContactSettings(geometry=args.geometry), window=args.window)
    except SettingsError as exc:
        raise _settings_error(exc) from None


def _duration(text):
    """argparse type of ``--duration``: a time in s or ``auto``."""
    if text == DURATION_AUTO:
        return text
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a time in s or {DURATION_AUTO!r}, got {text!r}") from None


def _steps(text):
    """argparse type of ``--steps``: a positive number of steps or ``auto``."""
    return text if text == DURATION_AUTO else positive_int("--steps")(text)


#: the command line's option of each run/contact setting (errors name the option)
SETTING_OPTIONS = {"solver": "--solver", "dt_s": "--dt", "duration_s": "--duration", "creep_law": "--creep-law",
                   "geometry": "--geometry", "contact_patch": "--contact-patch"}


def _settings_error(exc):
    """A :class:`~exudyn_wheelrail.simulation.settings.SettingsError` as a ValueError naming the option."""
    return ValueError(f"{SETTING_OPTIONS.get(exc.field, exc.field)}: {exc.problem}")


def _rtri_deviation(args):
    delta = None if args.delta_mm is None else args.delta_mm * 1e-3
    return delta, args.transition_m


def _print_rtri_summary(summary):
    p = summary.get("peaks_passage", {})
    print_status(summary)
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
    from ..scenarios.rtri import RtriCase
    case = RtriCase()
    run = case.run if args.command == "rtri" else dataclasses.replace(case.run, duration_s=DURATION_AUTO)
    duration = DURATION_AUTO if args.steps == DURATION_AUTO else args.duration
    try:
        run, contact, preset = apply_preset(args.preset, run, case.contact,
                                            run_options=dict(solver=args.solver, dt_s=args.dt, duration_s=duration),
                                            contact_options=dict(creep_law=args.creep_law, geometry=args.geometry,
                                                                 contact_patch=args.contact_patch))
        if isinstance(args.steps, int):         # --steps N: N steps of the resolved dt
            run = dataclasses.replace(run, duration_s=args.steps * run.dt_s)
    except SettingsError as exc:
        raise _settings_error(exc if not isinstance(args.steps, int) or exc.field != "duration_s" else
                              SettingsError("--steps", exc.problem)) from None
    return run, contact, preset


def _car_body_choices():
    return CAR_BODY_MODELS + ("both",)


def _cmd_rtri_car_bodies(args, run, contact, delta, lt):
    """``rtri --car-body both``: the rigid and the flexible car body with the same settings and the same measurement
    points, each into its own directory, and the comparison figure."""
    from ..scenarios.rtri import RtriCase, run_rtri, write_rtri_outputs
    from ..scenarios.rtri_case import CARBODY_POINTS
    from ..scenarios.rtri_figures import plot_carbody_comparison
    results = {}
    for cb in CAR_BODY_MODELS:
        case = RtriCase(span_m=args.span, speed_km_h=args.speed_kmh, run=run, contact=contact,
                        deviation_amplitude_m=delta, transition_length_m=lt, car_body=cb,
                        carbody_points=tuple(CARBODY_POINTS))
        results[cb] = run_rtri(case, progress=print, progress_bar=progress_bar(args))
        paths = write_rtri_outputs(results[cb], Path(args.out) / cb, plots=not args.no_plots)
        print(f"car body {cb}:")
        print_status(results[cb].summary)
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


def _rtri_figures(args) -> str | None:
    """The module of the figures ``rtri`` draws in a second process (Figs. 5 and 6 of one car body; the comparison
    of two car bodies is drawn by the command's process), or None."""
    return None if args.no_plots or args.car_body == "both" else "exudyn_wheelrail.scenarios.rtri_figures"


def cmd_rtri(args):
    from ..scenarios.rtri import RtriCase, run_rtri, write_rtri_outputs
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
        from ..interactive.view3d import RtriView
        view = RtriView(realtime_factor=args.view_speed)
    result = run_rtri(case, progress=print, view=view, progress_bar=progress_bar(args))
    result.summary["preset"] = preset
    paths = write_rtri_outputs(result, args.out, plots=not args.no_plots, figures=args.figures)
    _print_rtri_summary(result.summary)
    print("wrote " + ", ".join(str(p) for p in paths.values()))
    return result.summary["status_detail"]["exit_code"]


def cmd_rtri_sweep(args):
    from ..scenarios.rtri import RTRI, run_sweep
    delta, lt = _rtri_deviation(args)
    speeds = args.speeds_kmh if args.speeds_kmh else list(RTRI.speeds_km_h)
    spans = args.spans if args.spans else list(RTRI.span_lengths_m)
    run, contact, preset = args.settings
    print(f"RTRI sweep: spans {spans} m, speeds {speeds} km/h, {run.solver}, dt {run.dt_s} s, duration "
          f"{run.duration_s}, geometry {contact.geometry}" + (f" (preset {preset['name']})" if preset else ""))
    summaries = run_sweep(spans, speeds, args.out, workers=args.workers, run=run, contact=contact,
                          deviation_amplitude_m=delta, transition_length_m=lt, write_cases=not args.no_case_outputs,
                          progress=progress_lines(args))
    print(f"wrote {args.out}/sweep.csv, sweep.json, fig7_max_carbody_acceleration.png")
    return exit_code(s["status"] for s in summaries)


def _add_rtri_common(p: argparse.ArgumentParser, duration_default: str):
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
                                                     "theory, tabulated), table_linear (the same table interpolated "
                                                     "multilinearly: cheaper, coarser), fastsim, "
                                                     "shen_hedrick_elkins, polach")
    p.add_argument("--geometry", default=None, choices=("online", "table"),
                   help="contact geometry: online search (default) or the precomputed table for the rigid rail "
                        "profile (built once, ~1 min, cached)")
    p.add_argument("--contact-patch", default=None, choices=CONTACT_PATCHES,
                   help="normal contact: hertz (default: Hertz's ellipse at each contact point) or non-hertzian (the "
                        "patch of the profiles' interpenetration where Hertz does not hold; slower)")
    p.add_argument("--delta-mm", type=float, default=None,
                   help="deviation amplitude [mm] (default: RtriAssumptions, 10 mm; an override is marked in the "
                        "summary)")
    p.add_argument("--transition-m", type=float, default=None,
                   help="end-transition length [m] (default: RtriAssumptions, 3 m)")
    p.add_argument("--out", required=True, help="output directory")
    add_progress_argument(p)


def cmd_validation_report(args):
    from ..scenarios.validation_report import write_report
    write_report(args.out, quick=args.quick, progress=progress_lines(args))
    print(f"wrote {args.out}/report.md")
    return 0


def cmd_explore(args):
    import matplotlib
    values = key_value_dict(args.set, "--set")
    if args.out:
        matplotlib.use("Agg")
    from ..interactive.explorer_figure import ExplorerFigure
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


def add_rtri_parser(sub) -> None:
    """The ``rtri`` command's parser: its options, their check and its function."""
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
    r.set_defaults(func=cmd_rtri, check=_check_rtri, figures_of=_rtri_figures)


def add_rtri_sweep_parser(sub) -> None:
    """The ``rtri-sweep`` command's parser: its options, their check and its function."""
    w = sub.add_parser("rtri-sweep", help="the RTRI case over spans and speeds in parallel (Fig. 7)",
                       description="Runs the RTRI case for every span x speed in parallel processes; writes "
                                   "sweep.csv, sweep.json, fig7_max_carbody_acceleration.png and cases/L*_V*/")
    w.add_argument("--spans", type=float, nargs="+", default=None, help="span lengths [m] (default 20 40)")
    w.add_argument("--speeds-kmh", type=float, nargs="+", default=None,
                   help="speeds [km/h] (default RtriAssumptions.speeds_km_h: 100 150 200 250)")
    w.add_argument("--workers", type=positive_int("--workers"), default=None,
                   help="worker processes (default: all cores)")
    w.add_argument("--no-case-outputs", action="store_true", help="do not write each case's files")
    _add_rtri_common(w, "auto")
    w.set_defaults(func=cmd_rtri_sweep, check=_check_rtri_sweep)


def add_validation_report_parser(sub) -> None:
    """The ``validation-report`` command's parser: its options, their check and its function."""
    vr = sub.add_parser("validation-report", help="re-run the validations into report.md with plots",
                        description="Kalker's exact solver vs Table E.3, the creep table vs the exact solver, "
                                    "Klingel's wavelength, Frýba's moving force and the RTRI 20 m vs 40 m peaks: "
                                    "writes DIR/report.md and PNG plots.")
    vr.add_argument("--out", required=True, help="output directory")
    vr.add_argument("--quick", action="store_true",
                    help="fewer creep-table points, shorter Klingel/Frýba runs, no RTRI runs (< 60 s)")
    add_progress_argument(vr)
    vr.set_defaults(func=cmd_validation_report, check=_check_out_dir)


def add_explore_parser(sub) -> None:
    """The ``explore`` command's parser: its options, their check and its function."""
    ex = sub.add_parser("explore", help="the RTRI explorer: sliders re-run the case and redraw Figs. 5/6 quantities",
                        description="Matplotlib window with sliders for speed, span, deviation amplitude, friction and "
                                    "suspension factors; releasing a slider re-runs the RTRI case (RK44 1 ms over the "
                                    "passage by default, see exudyn_wheelrail/interactive/explorer.py) and redraws. "
                                    "--out FILE.png runs once headless and saves the window.")
    ex.add_argument("--set", action="append", metavar="NAME=VALUE",
                    type=lambda t: key_values(t, "--set", many=False),
                    help="initial slider value, repeatable: speed_km_h, span_m, deviation_mm, friction, "
                         "primary_kx_factor, primary_ky_factor, secondary_ky_factor, secondary_cy_factor")
    ex.add_argument("--solver", default="rk44", help="integrator of the explorer's runs (default rk44; "
                                                     "newmark, generalized_alpha, rk33, rk67, explicit_midpoint)")
    ex.add_argument("--dt", type=float, default=DEFAULT_STEP_S, help=f"time step [s] (default {DEFAULT_STEP_S:g})")
    ex.add_argument("--geometry", default="online", choices=("online", "table"),
                    help="contact geometry: online search (default, as the full run) or the precomputed table "
                         "(about 2x faster updates, larger differences in raw force peaks)")
    ex.add_argument("--window", default="passage", choices=("passage", "published"),
                    help="passage: until the whole car has left the span + run-out (default); published: 2.5 s")
    ex.add_argument("--out", default=None, help="headless: run once with the --set values and save the window here")
    ex.set_defaults(func=cmd_explore, check=_check_explore)

