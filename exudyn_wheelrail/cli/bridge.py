"""The bridge commands: ``bridge-crossing`` (a train over a simply supported span, a chain of them, a continuous deck or
a modes file's deck: deck response, EN 1990 deck acceleration) and ``bridge-crossing-sweep`` (the crossing over many
speeds in parallel: peaks against speed, resonance speeds)."""
from __future__ import annotations

import math
from decimal import Decimal
from pathlib import Path

from ..scenarios.defaults import (CONTACT_DT_S, CONTACT_STEPS_PER_PERIOD, DEFAULT_SOLVER, LATERAL_EI_RATIO, MAX_MODES,
                                  MODEL_NAMES, SPRUNG_DAMPING_RATIO, SPRUNG_FREQUENCY_HZ, STEPS_PER_PERIOD)
from ..simulation.settings import DT_S, SPEED_KM_H
from ..simulation.solvers import SOLVERS
from ..simulation.status import exit_code
from ..standards import HSLM_NAMES, TRACK_FORMS
from ..validation import output_dir
from .common import add_progress_argument, inputs_checked, positive_int, progress_bar, progress_lines


def _verdict(check: dict) -> str:
    """'passed' / 'NOT passed' / 'not evaluated (why)' of a criterion's dict."""
    if check.get("passed") is None:
        return f"not evaluated ({check.get('not_evaluated') or 'no verdict'})"
    return "passed" if check["passed"] else "NOT passed"


#: the command line's option of each field of a bridge crossing (errors name the option)
BRIDGE_CROSSING_OPTIONS = {"span_m": "--span-m", "mass_kg_m": "--bridge-mass-kg-per-m",
                           "f1_Hz": "--bridge-frequency-hz",
                           "damping_ratio": "--damping-ratio", "n_modes": "--modes", "speed_m_s": "--speed-kmh",
                           "model": "--model", "free_vibration_s": "--free-vibration-s", "dt_s": "--dt",
                           "solver": "--solver", "track_form": "--track-form", "spans_m": "--spans-m",
                           "lateral_modes": "--lateral-modes", "lateral_f1_Hz": "--lateral-frequency-hz",
                           "sprung_frequency_Hz": "--sprung-frequency-hz",
                           "sprung_damping_ratio": "--sprung-damping-ratio", "modes_file": "--modes-file",
                           "continuous": "--continuous"}


def _bridge_crossing_spans(args):
    """The chain of spans of ``--n-spans`` / ``--spans-m`` (None: the single span ``--span-m``), checked."""
    from ..scenarios.bridge_crossing_case import MAX_SPANS, SPAN_M
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
    :class:`~exudyn_wheelrail.scenarios.bridge_crossing.BridgeCrossing` goes to ``args.crossing``."""
    from ..scenarios.bridge_crossing_case import F1_HZ, FREE_VIBRATION_S, MASS_KG_M, SPAN_M, BridgeCrossing
    from ..scenarios.bridge_crossing_loads import consist_axles, resolve_load_model
    from ..scenarios.defaults import AXLE_LOAD_MODELS
    from ..structures.load_models import hslm_a, read_axle_file
    output_dir("--out", args.out)
    if args.command == "bridge-crossing-sweep":
        args.speeds = _sweep_speeds_kmh(args)
        args.speed_kmh = args.speeds[0]
    SPAN_M.check("--span-m", args.span_m)
    if args.modes_file is None:
        for option, value in (("--bridge-mass-kg-per-m", args.bridge_mass_kg_per_m),
                              ("--bridge-frequency-hz", args.bridge_frequency_hz),
                              ("--damping-ratio", args.damping_ratio)):
            if value is None:
                raise ValueError(f"{option}: missing (the built-in deck needs --bridge-mass-kg-per-m, "
                                 "--bridge-frequency-hz and --damping-ratio; or give --modes-file)")
    elif args.bridge_frequency_hz is not None:
        raise ValueError("--bridge-frequency-hz: not with --modes-file (the file gives the frequencies)")
    if args.bridge_mass_kg_per_m is not None:
        MASS_KG_M.check("--bridge-mass-kg-per-m", args.bridge_mass_kg_per_m)
    if args.bridge_frequency_hz is not None:
        F1_HZ.check("--bridge-frequency-hz", args.bridge_frequency_hz)
    SPEED_KM_H.check("--speed-kmh", args.speed_kmh)
    FREE_VIBRATION_S.check("--free-vibration-s", args.free_vibration_s)
    if args.dt is not None:
        DT_S.check("--dt", args.dt)
    z = args.damping_ratio
    if z is not None and not (math.isfinite(z) and 0.0 <= z < 1.0):
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
        axles = consist_axles(args.train)
    try:
        case = BridgeCrossing(span_m=args.span_m, mass_kg_m=args.bridge_mass_kg_per_m, f1_Hz=args.bridge_frequency_hz,
                              damping_ratio=z, n_modes=args.modes, axles=axles, speed_m_s=args.speed_kmh / 3.6,
                              model=args.model, free_vibration_s=args.free_vibration_s, dt_s=args.dt,
                              solver=args.solver, track_form=args.track_form, train_file=args.train,
                              spans_m=spans, lateral_modes=args.lateral_modes,
                              lateral_f1_Hz=args.lateral_frequency_hz,
                              sprung_frequency_Hz=args.sprung_frequency_hz,
                              sprung_damping_ratio=args.sprung_damping_ratio, continuous=args.continuous,
                              modes_file=args.modes_file)
    except ValueError as exc:
        name, _, problem = str(exc).partition(": ")
        raise ValueError(f"{BRIDGE_CROSSING_OPTIONS.get(name, name)}: {problem}") from None
    resolve_load_model(case.model).check(case)
    args.crossing = case
    if args.command == "bridge-crossing":
        args.scenario_spec = _crossing_spec(args, case)


def _crossing_spec(args, case) -> dict:
    """The normal form of the scenario the command runs (its unusual values were named by their options above)."""
    from ..scenarios.scenario import validate_scenario
    from ..scenarios.spec_crossing import crossing_scenario
    train = ({"axles": args.axles} if args.axles is not None else {"hslm": args.hslm} if args.hslm is not None
             else {"consist": args.train})
    with inputs_checked():
        return validate_scenario(crossing_scenario(case, train, speed_km_h=args.speed_kmh),
                                 source="bridge-crossing options")


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
        # exact decimals: FIRST + k STEP in decimal arithmetic (in floats, 150 + 9 x 10.1 is 240.89999999999998)
        d_first, d_step = Decimal(repr(first)), Decimal(repr(step))
        speeds = [float(d_first + k * d_step) for k in range(n)]
    for v in speeds:
        SPEED_KM_H.check(option, v)
    return speeds


def cmd_bridge_crossing_sweep(args):
    from ..scenarios.bridge_crossing import speed_sweep
    case = args.crossing
    src = case.axles.name if case.axles is not None else case.train_file
    print(f"bridge-crossing sweep: {case.model}, {src}, L = {case.span_m:g} m, f1 = {case.f1_Hz:g} Hz, "
          f"{case.n_modes} modes, {len(args.speeds)} speeds {min(args.speeds):g} ... {max(args.speeds):g} km/h, "
          f"{args.workers or 'all'} worker processes")
    result = speed_sweep(case, [v / 3.6 for v in args.speeds], out_dir=args.out, workers=args.workers,
                         write_cases=args.case_outputs, progress=progress_lines(args))
    if result.resonance_speeds:
        print("resonance speeds f1 d/i: " + ", ".join(f"{r['speed_km_h']:.4g}" for r in result.resonance_speeds)
              + " km/h")
    print(f"{len(args.speeds)} speeds in {result.wall_seconds:.1f} s; wrote " + ", ".join(result.paths.values()))
    return exit_code(result.table["status"])


def cmd_bridge_crossing(args):
    from ..scenarios.bridge_crossing import default_dt_s
    from ..scenarios.scenario import run_scenario
    case = args.crossing
    src = case.axles.name if case.axles is not None else case.train_file
    chain = "" if case.n_spans == 1 else f" (spans {' + '.join(f'{x:g}' for x in case.chain_m)} m)"
    lateral = f" + {case.lateral_modes} lateral" if case.lateral_modes else ""
    print(f"bridge crossing: {case.model}, {src}, L = {case.span_m:g} m{chain}, f1 = {case.f1_Hz:g} Hz, "
          f"{case.n_modes}{lateral} modes, zeta = {case.damping_ratio:g}, {case.speed_m_s * 3.6:g} km/h, "
          f"{case.solver}, dt "
          f"{case.dt_s if case.dt_s is not None else default_dt_s(case):g} s")
    with inputs_checked():
        result = run_scenario(args.scenario_spec, args.out, progress=progress_bar(args))
    return print_crossing_result(result)


def print_crossing_result(result) -> int:
    """The crossing's result on the terminal (status, deck peaks against EN 1990, resonance speeds, steps, notes,
    files); returns the exit code of its status."""
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


def add_bridge_crossing_parsers(sub) -> None:
    """The ``bridge-crossing`` and ``bridge-crossing-sweep`` commands' parsers: their options, their check and
    their functions."""
    bc = sub.add_parser("bridge-crossing", help="a train over a simply supported span: moving loads (or vehicles) on "
                                                "the modal deck in Exudyn",
                        description="A train crosses a simply supported Euler-Bernoulli span (EI from f1, m, L; N "
                                    "vertical modes, modal damping) built in Exudyn, or a chain of them (--spans-m, "
                                    "--n-spans), one deck continuous over them (--continuous) or a deck given by an "
                                    "FE program's modes (--modes-file), optionally with lateral modes "
                                    "(--lateral-modes); t = 0 when the "
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
    bc.add_argument("--span-m", type=float, required=True, help="span length L [m]")
    bc.add_argument("--bridge-mass-kg-per-m", type=float, default=None,
                    help="deck mass per length m [kg/m] (the built-in deck; with --modes-file only reported)")
    bc.add_argument("--bridge-frequency-hz", type=float, default=None,
                    help="first bending frequency f1 [Hz] of the first span as simply supported; EI = m (2 L^2 f1 / "
                         "pi)^2 (the built-in deck)")
    bc.add_argument("--damping-ratio", type=float, default=None,
                    help="modal damping ratio of every mode, 0 <= z < 1 (with --modes-file: default the file's)")
    bc.add_argument("--modes", type=positive_int("--modes"), required=True,
                    help=f"vertical bending modes kept per span (1 to {MAX_MODES}); a continuous deck keeps N x "
                         "spans, a modes file its N lowest modes")
    bc.add_argument("--continuous", action="store_true",
                    help="the spans (--spans-m, --n-spans) form one deck continuous over the intermediate supports")
    bc.add_argument("--modes-file", default=None, metavar="FILE.npz|FILE.csv",
                    help="the deck's modes from an FE program instead of the built-in beam: frequency_hz, "
                         "modal_mass_kg, x_m (from the first abutment), vertical (n x k, + down), optional lateral, "
                         "torsion, damping_ratio (exudyn_wheelrail/structures/modes_file.py); the spans give its "
                         "supports")
    bc.add_argument("--n-spans", type=positive_int("--n-spans"), default=None, metavar="K",
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
        bc.add_argument("--workers", type=positive_int("--workers"), default=None,
                        help="worker processes (default: all cores)")
        bc.add_argument("--case-outputs", action="store_true", help="write each speed's files under cases/")
    else:
        bc.add_argument("--speed-kmh", type=float, required=True, help="running speed [km/h]")
    bc.add_argument("--out", required=True, help="output directory")
    bc.add_argument("--free-vibration-s", type=float, default=0.0,
                    help="time simulated after the last axle has left the (last) span [s] (default 0)")
    bc.add_argument("--dt", type=float, default=None,
                    help=f"time step [s] (default: min(1/({STEPS_PER_PERIOD} f_N), 2L/({STEPS_PER_PERIOD} N V), "
                         f"0.01 s), f_N = N^2 f1; the vehicles model at most {CONTACT_STEPS_PER_PERIOD} steps per "
                         f"period of the stiffest wheelset's bounce on its Hertz contact and at most "
                         f"{CONTACT_DT_S:g} s)")
    bc.add_argument("--solver", default=DEFAULT_SOLVER, choices=SOLVERS,
                    help=f"integrator (default {DEFAULT_SOLVER})")
    bc.add_argument("--track-form", default=TRACK_FORMS[0], choices=TRACK_FORMS,
                    help="the EN 1990 A2 deck-acceleration limit: ballasted 3.5 m/s^2 (default), direct_fastening "
                         "5 m/s^2")
    add_progress_argument(bc)
