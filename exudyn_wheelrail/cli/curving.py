"""The ``curving`` command: steady curving of a vehicle through an entry transition into a canted curve (sum Y, Y/Q,
lateral shift, angle of attack per wheelset)."""
from __future__ import annotations

from ..scenarios.defaults import DEFAULT_MIN_TRANSITION_M, DEFAULT_RAMP, LEAD_IN_M
from ..standards import DEFAULT_BAND_M, TRACK_SPECTRA
from ..validation import output_dir
from .common import add_progress_argument, progress_bar

#: the command line's option of each field of a curving case (errors name the option)
CURVING_OPTIONS = {"radius_m": "--radius-m", "cant_m": "--cant-m", "speed_km_h": "--speed-kmh",
                   "transition_m": "--transition-m", "direction": "--direction", "vehicle": "--vehicle",
                   "irregularity": "--irregularity-spectrum", "irregularity_spectrum": "--irregularity-spectrum",
                   "seed": "--seed"}


def add_curving_parser(sub) -> None:
    """The ``curving`` command's parser: its options, their check and its function."""
    cv = sub.add_parser("curving", help="steady curving: a vehicle through an entry transition into a circular "
                                        "curve; per wheelset sum Y, Y/Q, lateral shift, angle of attack",
                        description="Runs the vehicle from straight track through a clothoid transition with a linear "
                                    "cant ramp into a circular curve until it is steady, in track-following frames "
                                    "(exudyn_wheelrail/scenarios/curving.py, rolling_stock/track_following.py). Writes "
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
    add_progress_argument(cv)
    cv.set_defaults(func=cmd_curving, check=_check_curving)


def _check_curving(args) -> None:
    """Every option of ``curving`` before any work (the vehicle read, the radius against its wheelbase); the
    :class:`~exudyn_wheelrail.scenarios.curving.CurvingCase` goes to ``args.curving``."""
    from ..scenarios.curving import CurvingCase, CurvingInputError, check_curving_case
    output_dir("--out", args.out)
    case = CurvingCase(args.vehicle, radius_m=args.radius_m, cant_m=args.cant_m, speed_km_h=args.speed_kmh,
                       transition_m=args.transition_m, direction=args.direction,
                       irregularity_spectrum=args.irregularity_spectrum, seed=args.seed)
    try:
        args.curving_vehicle = check_curving_case(case)
    except CurvingInputError as exc:
        raise ValueError(f"{CURVING_OPTIONS.get(exc.option, exc.option)}: {exc.problem}") from None
    args.curving = case


def cmd_curving(args):
    from ..scenarios.curving import run_curving, spectrum_component
    case = args.curving
    v = args.curving_vehicle
    print(f"curving: {v.name}, R = {case.radius_m:g} m {case.direction}, cant {case.cant_m * 1000:g} mm, "
          f"{case.speed_km_h:g} km/h, transition {case.transition_length_m:g} m")
    if case.irregularity_spectrum is not None:
        c = spectrum_component(case, case.irregularity_spectrum, case.seed, v)
        print(f"irregularity: spectrum {c['spectrum']}, seed {c['seed']}, generated over {c['length_m']:g} m from "
              f"s = {c['start_m']:g} m, faded in over {c['fade_in_m']:g} m")
    result = run_curving(case, out_dir=args.out, progress=progress_bar(args))
    s = result.summary
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
