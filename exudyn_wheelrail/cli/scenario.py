"""The scenario commands: ``run`` (a scenario file: build, solve, evaluate) and ``sweep`` (a scenario over the
cartesian product of parameter values, in parallel)."""
from __future__ import annotations

from ..simulation.status import exit_code
from ..validation import output_dir
from .bridge import print_crossing_result
from .common import (add_progress_argument, inputs_checked, key_value_dict, key_values, positive_int, print_status,
                     progress_bar, progress_lines)


def _check_sweep(args) -> None:
    output_dir("--out", args.out)
    if not args.param:
        raise ValueError("--param: missing (give at least one --param KEY=V1,V2,...)")


def _run_figures(args) -> str:
    """The module of the figures ``run`` draws in a second process (the scenario's plots)."""
    return "exudyn_wheelrail.scenarios.plots"


def cmd_run_scenario(args):
    from ..scenarios.scenario import run_scenario
    from ..scenarios.spec_crossing import is_crossing
    scn = args.scenario_spec
    veh = scn['vehicle']
    if is_crossing(scn):                          # a bridge crossing: as the bridge-crossing command shows it
        st, source = scn["structure"], veh.get("hslm") or veh.get("axles") or veh.get("consist")
        print(f"scenario {scn['scenario']['name']}: bridge crossing, {veh['load_model']}, {source}, spans "
              f"{' + '.join(f'{x:g}' for x in st['spans_m'])} m"
              + (f", modes file {st['modes_file']}" if "modes_file" in st else
                 f"{' continuous' if st.get('continuous') else ''}, f1 = {st['f1_Hz']:g} Hz")
              + f", {st['modes']} modes, "
              f"{veh['speed_km_h']:g} km/h, {scn['run']['solver']}")
        with inputs_checked():
            result = run_scenario(scn, args.out, progress=progress_bar(args))
        return print_crossing_result(result)
    print(f"scenario {scn['scenario']['name']}: {veh.get('name') or veh.get('file') or veh.get('consist')}, "
          f"{scn['vehicle']['speed_km_h']:g} km/h, {scn['run']['solver']}, dt {scn['run']['dt_s']:g} s, duration "
          f"{scn['run']['duration_s']}{', bridge' if 'structure' in scn else ''}")
    with inputs_checked():
        result = run_scenario(scn, args.out, progress=progress_bar(args), figures=args.figures)
    s = result.summary
    print_status(s)
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
    from ..scenarios.scenario import apply_overrides, load_scenario
    output_dir("--out", args.out)
    scn = load_scenario(args.scenario)
    overrides = key_value_dict(args.set, "--set")
    if overrides:
        scn = apply_overrides(scn, overrides, source=f"{args.scenario} with --set")
    args.scenario_spec = scn


def cmd_sweep_scenario(args):
    from ..scenarios.sweep import sweep
    params = key_value_dict(args.param, "--param")
    base = args.scenario
    overrides = key_value_dict(args.set, "--set")
    if overrides:
        from ..scenarios.scenario import apply_overrides, load_scenario
        base = apply_overrides(load_scenario(args.scenario), overrides, source=f"{args.scenario} with --set")
    n = 1
    for v in params.values():
        n *= len(v)
    print(f"sweep of {args.scenario}: {n} cases ({' x '.join(f'{k}: {len(v)}' for k, v in params.items())}), "
          f"{args.workers or 'all'} worker processes")
    result = sweep(base, params, out_dir=args.out, workers=args.workers,
                   plot_result=args.plot_result, plot_parameter=args.plot_param,
                   write_cases=not args.no_case_outputs, progress=progress_lines(args))
    for note in result.notes:
        print("note:", note)
    print("wrote " + ", ".join(result.paths.values()))
    return exit_code(result.table["status"])


def add_run_parser(sub) -> None:
    """The ``run`` command's parser: its options, their check and its function."""
    sr = sub.add_parser("run", help="run a scenario file (TOML; schema: exudyn_wheelrail/scenarios/scenario.py)",
                        description="Build, solve and evaluate a scenario: writes timeseries.csv/.npz, summary.json "
                                    "(peaks, scalars, running criteria) and plots into --out.")
    sr.add_argument("scenario", help="scenario file (.toml), e.g. examples/scenarios/rtri_20m.toml")
    sr.add_argument("--out", required=True, help="output directory")
    add_progress_argument(sr)
    sr.add_argument("--set", action="append", metavar="KEY=VALUE",
                    type=lambda t: key_values(t, "--set", many=False),
                    help="override a value by its dotted key, repeatable (run.duration_s=0.5, "
                         "track.0.amplitude_m=0.005)")
    sr.set_defaults(func=cmd_run_scenario, check=_check_run, figures_of=_run_figures)


def add_sweep_parser(sub) -> None:
    """The ``sweep`` command's parser: its options, their check and its function."""
    ss = sub.add_parser("sweep", help="a scenario over a parameter grid in parallel: one table and one plot",
                        description="Runs the cartesian product of the --param values over a scenario in parallel "
                                    "processes; writes sweep.csv (one row per case), sweep.json, sweep_plot.png and "
                                    "cases/case_*/.")
    ss.add_argument("scenario", help="base scenario file (.toml)")
    ss.add_argument("--param", action="append", metavar="KEY=V1,V2,...",
                    type=lambda t: key_values(t, "--param", many=True),
                    help="a swept parameter by its dotted key and its values, repeatable "
                         "(vehicle.speed_km_h=100,150,200 --param track.0.span_length_m=20,40)")
    ss.add_argument("--set", action="append", metavar="KEY=VALUE",
                    type=lambda t: key_values(t, "--set", many=False),
                    help="a fixed override of the base scenario, repeatable")
    ss.add_argument("--out", required=True, help="output directory")
    ss.add_argument("--workers", type=positive_int("--workers"), default=None,
                    help="worker processes (default: all cores)")
    ss.add_argument("--plot-result", default=None,
                    help="scalar result plotted (default max_abs_Y_any_wheel_N, for a bridge crossing "
                         "max_abs_deck_midspan_acceleration_m_s2; any column of sweep.csv)")
    ss.add_argument("--plot-param", default=None, help="parameter on the x axis (default: the first --param)")
    ss.add_argument("--no-case-outputs", action="store_true", help="do not write each case's files")
    add_progress_argument(ss)
    ss.set_defaults(func=cmd_sweep_scenario, check=_check_sweep)

