r"""Running stability of a vehicle on straight track: the linear and the nonlinear critical speed and the hunting
mode (the ``critical-speed`` command).

>>> s = run_critical_speed(CriticalSpeedCase("manchester_vehicle1", (100.0, 400.0)), "out/stability")  # doctest: +SKIP
>>> s["linear_critical_speed_kmh"], s["hunting_frequency_hz"], s["nonlinear_critical_speed_kmh"]   # doctest: +SKIP

Method
------
1. **Linear** (:mod:`.critical_speed_linear`): at every speed of a grid over the range (steps of at most
   :data:`~.critical_speed_defaults.LINEAR_GRID_STEP_KM_H`) the full model is settled on perfect track and linearised
   about its centred running state; the eigenvalues give every mode's frequency and damping ratio (the root locus,
   modes tracked across speeds: :func:`~exudyn_wheelrail.analysis.stability.track_modes`).  The linear critical speed
   is the lowest speed where the smallest damping ratio of the lateral oscillating modes (lateral, roll and yaw
   motion at least :data:`~.critical_speed_defaults.LATERAL_SHARE_MIN` of the shape) reaches zero: bracketed on the
   grid, bisected to :data:`~.critical_speed_defaults.BISECTION_TOLERANCE_KM_H` and interpolated linearly in the
   last bracket.  The hunting frequency and shape are the unstable mode's there.
2. **Nonlinear** (:mod:`.critical_speed_nonlinear`): constant-speed runs of the full model after a lateral
   disturbance at :data:`~.critical_speed_defaults.NONLINEAR_GRID_POINTS` speeds over the range, in parallel
   (:func:`~.sweep.run_tasks`); the limit-cycle amplitude of every wheelset at the end of each run is the
   bifurcation diagram's stable branch.  The nonlinear critical speed is the lowest speed at which a limit cycle
   persists: bisected between the highest grid speed below the lowest persisting one and that one (the middle of the
   last bracket is reported, the bracket beside it).  A run that derails counts as persisting.
3. **Unstable branch** (:mod:`.critical_speed_branch`, unless ``unstable_branch`` is off): at speeds between the
   nonlinear and the linear critical speed, the unstable limit cycle from the disturbance's depth bisected between
   decay and the stable cycle.
4. **Outputs**: ``summary.json``, ``root_locus.csv`` (``speed_kmh, mode, frequency_hz, damping_ratio``, then
   ``real_part_1_per_s``, ``lateral_share``), ``bifurcation.csv`` (``speed_kmh, wheelset, amplitude_m``, then
   ``persists``, ``frequency_hz`` of a persisting cycle, ``status``, ``branch``: ``stable`` — the amplitude at the
   end of a run — or ``unstable``), ``linear_speeds.csv`` (per linearised speed: the least damped lateral mode),
   the figures (:mod:`.critical_speed_plots`).

The linear analysis runs in the calling process (one model at a time: a build, a settling run and the
linearisation take about 0.4 s once the compiled code is loaded, which a new process pays once); the nonlinear grid
runs on the sweep's executors (``workers`` processes; ``workers = 1``: in the calling process), its bisection in the
calling process.
"""
from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis.conicity import equivalent_conicity
from ..analysis.geometry_functions import contact_geometry_sweep
from ..analysis.stability import ModeSet, first_zero_crossing, track_modes
from ..contact.pair import WheelRailPair
from ..rolling_stock.vehicle_data import load_vehicle
from ..validation import output_dir, read_toml
from .critical_speed_defaults import (BISECTION_TOLERANCE_KM_H, BRANCH_DEPTH_RATIO, BRANCH_LINGER_RATIO,
                                      BRANCH_MIN_DEPTH_M, BRANCH_POINTS, BRANCH_WINDOW_M, BUMP_DEPTH_M, BUMP_LENGTH_M,
                                      CONICITY_AMPLITUDE_M, CONICITY_STEP_M, CONICITY_SWEEP_M, CYCLE_WINDOW_M,
                                      DEFAULT_SPEED_RANGE_KM_H, LATERAL_SHARE_MIN, LINEAR_GRID_STEP_KM_H,
                                      MOVING_BODY_SHARE, NONLINEAR_GRID_POINTS, PERSIST_AMPLITUDE_M,
                                      PERSIST_DAMPING_RATIO, RUN_DISTANCE_M, RUN_DT_S, RUN_SOLVER, SETTLE_DURATION_S,
                                      SPEED_LIMITS_KM_H, TREND_WINDOWS)
from .critical_speed_branch import branch_speeds, unstable_branch
from .critical_speed_linear import LinearisationError, linear_modes
from .critical_speed_nonlinear import limit_cycle_run
from .critical_speed_plots import write_figures
from .outputs import write_json, write_table_csv
from .sweep import SerialExecutor, run_tasks

__all__ = ["CriticalSpeedCase", "check_case", "run_critical_speed", "linear_critical_speed",
           "nonlinear_critical_speed", "least_damped", "same_mode", "mode_shape", "read_summary"]


@dataclass(frozen=True)
class CriticalSpeedCase:
    """What is analysed: ``vehicle`` (a shipped name or a vehicle file), the ``speed_range_kmh`` (lo, hi),
    ``workers`` (processes of the nonlinear runs; None: one per CPU; 1: in the calling process) and whether the
    bifurcation diagram's ``unstable_branch`` is computed (:mod:`.critical_speed_branch`)."""

    vehicle: str
    speed_range_kmh: tuple = DEFAULT_SPEED_RANGE_KM_H
    workers: int | None = None
    unstable_branch: bool = True


def check_case(case: CriticalSpeedCase):
    """Every input before any work (``ValueError`` naming the option): the speed range in order and inside
    :data:`~.critical_speed_defaults.SPEED_LIMITS_KM_H`, the vehicle readable and with wheelsets.  Returns the
    vehicle data."""
    lo, hi = (float(v) for v in case.speed_range_kmh)
    vmin, vmax = SPEED_LIMITS_KM_H
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo < vmin or hi > vmax:
        raise ValueError(f"--speed-range-kmh: {lo:g} {hi:g}: expected speeds within {vmin:g}-{vmax:g} km/h")
    if not lo < hi:
        raise ValueError(f"--speed-range-kmh: {lo:g} {hi:g}: expected LO < HI")
    if Path(case.vehicle).is_file():                     # what the file is, before its keys are checked
        data = read_toml(case.vehicle)
        if "train" in data or "car" in data:
            raise ValueError(f"--vehicle: {case.vehicle}: a train (consist) file: give one vehicle file")
        if "wheelset" not in data and "base_vehicle" not in data:
            raise ValueError(f"--vehicle: {case.vehicle}: the vehicle has no wheelsets (no [wheelset] table)")
    try:
        vehicle = load_vehicle(case.vehicle)
    except FileNotFoundError:
        raise ValueError(f"--vehicle: {case.vehicle}: no such vehicle file or shipped vehicle") from None
    except ValueError as exc:
        raise ValueError(f"--vehicle: {exc}") from None
    if len(vehicle.wheelset_x_m()) == 0:
        raise ValueError(f"--vehicle: {case.vehicle}: the vehicle has no wheelsets")
    if case.workers is not None and (isinstance(case.workers, bool) or int(case.workers) < 1):
        raise ValueError(f"--workers: {case.workers}: expected a positive integer")
    return vehicle


def least_damped(point: dict) -> tuple[float, int | None]:
    """``(damping_ratio, index)`` of the least damped lateral oscillating mode of a :func:`.linear_modes` result
    (``(inf, None)`` without any)."""
    lam = np.asarray(point["eigenvalues"])
    cand = np.flatnonzero(point["candidate"])
    if cand.size == 0:
        return math.inf, None
    zeta = -lam[cand].real / np.abs(lam[cand])
    k = int(cand[int(np.argmin(zeta))])
    return float(-lam[k].real / abs(lam[k])), k


def same_mode(point: dict, index: int, other: dict) -> int:
    """The index in ``other`` (a :func:`.linear_modes` result at a nearby speed) of mode ``index`` of ``point``: the
    lateral oscillating mode of ``other`` with the largest modal assurance criterion against it, ties to the nearest
    eigenvalue."""
    a = np.asarray(point["shapes"])[:, index]
    lam = np.asarray(point["eigenvalues"])[index]
    cand = np.flatnonzero(other["candidate"])
    B = np.asarray(other["shapes"])[:, cand]
    mac = np.abs(np.conj(a) @ B) ** 2 / (np.real(np.conj(a) @ a) * np.real(np.sum(np.conj(B) * B, axis=0)))
    near = np.abs(np.asarray(other["eigenvalues"])[cand] - lam)
    return int(cand[np.lexsort((near, -np.round(mac, 6)))[0]])


def mode_shape(point: dict, index: int) -> list:
    """The shape of mode ``index`` per rigid body: lateral displacement and yaw amplitude, scaled so that the largest
    lateral displacement is 1, with their phase [deg] (bodies in the model's order)."""
    shape = np.asarray(point["shapes"])[:, index]
    labels = point["labels"]
    lat = {lab.rsplit(" ", 1)[0]: shape[i] for i, lab in enumerate(labels) if lab.endswith(" y")}
    yaw = {lab.rsplit(" ", 1)[0]: shape[i] for i, lab in enumerate(labels) if lab.endswith(" yaw")}
    ref = max(lat.values(), key=abs) if lat else 1.0
    ref = ref if abs(ref) > 0.0 else 1.0
    out = []
    for body, y in lat.items():
        y_n, p_n = y / ref, yaw.get(body, 0.0) / ref
        out.append({"body": body, "lateral": float(abs(y_n)), "lateral_phase_deg": float(np.degrees(np.angle(y_n))),
                    "yaw_rad_per_m": float(abs(p_n)), "yaw_phase_deg": float(np.degrees(np.angle(p_n)))})
    return out


def _linear_grid(lo: float, hi: float) -> list:
    n = max(2, int(math.ceil((hi - lo) / LINEAR_GRID_STEP_KM_H)) + 1)
    return [float(v) for v in np.linspace(lo, hi, n)]


def _bisect(fn, lo, hi, lo_value, hi_value, unstable, progress, what):
    """Bisect ``[lo, hi]`` (``lo`` stable, ``hi`` unstable by ``unstable(value)``: True, False, or None for no answer,
    which ends the bisection) to the tolerance; every evaluated ``(speed, value)`` is returned, and the final
    bracket."""
    evaluated = []
    while hi - lo > BISECTION_TOLERANCE_KM_H:
        mid = 0.5 * (lo + hi)
        value = fn(mid)
        evaluated.append((mid, value))
        verdict = unstable(value)
        progress(f"{what} {mid:.1f} km/h: {'no answer' if verdict is None else 'unstable' if verdict else 'stable'}")
        if verdict is None:             # a run that failed: the bracket so far is the answer
            break
        if verdict:
            hi, hi_value = mid, value
        else:
            lo, lo_value = mid, value
    return evaluated, (lo, lo_value), (hi, hi_value)


def linear_critical_speed(case: CriticalSpeedCase, progress=None) -> dict:
    """The linear analysis (module docstring, 1.): ``points`` (speed -> :func:`.linear_modes` result),
    ``critical_kmh`` (None: no crossing in the range — every lateral mode damped, or one unstable already at the
    lowest speed: ``unstable_at_lowest``), ``frequency_hz``, ``shape`` (:func:`mode_shape`) and ``bracket_kmh``
    (the bisection's last bracket)."""
    progress = progress or (lambda text: None)
    lo, hi = (float(v) for v in case.speed_range_kmh)
    points = {}
    failed = {}
    for v in _linear_grid(lo, hi):
        try:
            p = points[v] = linear_modes(case.vehicle, v)
        except LinearisationError as exc:          # e.g. a settling run that did not end ok: that speed is left out
            failed[v] = str(exc)
            progress(f"linear {v:.1f} km/h: {exc}")
            continue
        progress(f"linear {v:.1f} km/h: least damped lateral mode zeta = {least_damped(p)[0]:.4g}")
    if not points:
        raise RuntimeError(f"the linearisation failed at every speed: {next(iter(failed.values()))}")
    speeds = sorted(points)
    zetas = [least_damped(points[v])[0] for v in speeds]
    crossing = first_zero_crossing(speeds, zetas)
    critical = frequency = shape = None
    bracket = None
    if crossing is not None and zetas[0] > 0.0:
        i = next(k for k, z in enumerate(zetas) if z <= 0.0)
        evaluated, (v_lo, p_lo), (v_hi, p_hi) = _bisect(
            lambda v: linear_modes(case.vehicle, v), speeds[i - 1], speeds[i], points[speeds[i - 1]],
            points[speeds[i]], lambda p: least_damped(p)[0] <= 0.0, progress, "linear")
        for v, p in evaluated:
            points[v] = p
        z_hi, k_hi = least_damped(p_hi)
        k_lo = same_mode(p_hi, k_hi, p_lo)             # the unstable mode followed back to the stable end
        lam_lo, lam_hi = np.asarray(p_lo["eigenvalues"])[k_lo], np.asarray(p_hi["eigenvalues"])[k_hi]
        z_lo = -lam_lo.real / abs(lam_lo)
        critical = v_lo + (v_hi - v_lo) * z_lo / (z_lo - z_hi) if z_lo > 0.0 else v_lo
        f_lo, f_hi = abs(lam_lo.imag) / (2 * math.pi), abs(lam_hi.imag) / (2 * math.pi)
        frequency = f_lo + (f_hi - f_lo) * (critical - v_lo) / (v_hi - v_lo)
        shape = mode_shape(p_hi, k_hi)
        bracket = [v_lo, v_hi]
    unstable_at_lowest = None
    if crossing is not None and zetas[0] <= 0.0:  # unstable at the lowest speed already: no crossing in the range
        k = least_damped(points[speeds[0]])[1]
        lam = np.asarray(points[speeds[0]]["eigenvalues"])[k]
        unstable_at_lowest = {"speed_kmh": speeds[0], "damping_ratio": zetas[0],
                              "frequency_hz": abs(lam.imag) / (2 * math.pi), "shape": mode_shape(points[speeds[0]], k)}
    return {"points": points, "critical_kmh": critical, "frequency_hz": frequency, "shape": shape,
            "bracket_kmh": bracket, "failed": failed, "unstable_at_lowest": unstable_at_lowest}


def _no_answer(speed_kmh: float, status: str) -> dict:
    """A nonlinear run that gave no answer (its worker died, it raised): ``limit_cycle`` None, the status kept."""
    return {"speed_kmh": float(speed_kmh), "status": status, "amplitude_m": [], "persists": [], "frequency_hz": [],
            "limit_cycle": None, "seconds": None}


def _run_or_no_answer(vehicle: str, speed_kmh: float) -> dict:
    """:func:`.limit_cycle_run` in this process (the bisection); an exception is a run without an answer."""
    try:
        return limit_cycle_run(vehicle, speed_kmh)
    except Exception as exc:
        return _no_answer(speed_kmh, f"error: {type(exc).__name__}: {exc}".splitlines()[0])


def nonlinear_critical_speed(case: CriticalSpeedCase, progress=None) -> dict:
    """The nonlinear analysis (module docstring, 2.): ``runs`` (speed -> :func:`.limit_cycle_run` result),
    ``critical_kmh`` (None: none in the range — no limit cycle, or one already at the lowest speed;
    ``note`` says which), ``bracket_kmh``, ``note``."""
    progress = progress or (lambda text: None)
    lo, hi = (float(v) for v in case.speed_range_kmh)
    grid = [float(v) for v in np.linspace(lo, hi, NONLINEAR_GRID_POINTS)]
    runs = {}

    def done(i, r):
        runs[grid[i]] = r
        progress(f"nonlinear [{len(runs)}/{len(grid)}] {grid[i]:.1f} km/h: {r['status']}, "
                 f"{'limit cycle' if r.get('limit_cycle') else 'decays'}")

    def failed(i, text):
        return _no_answer(grid[i], text)
    executor = SerialExecutor() if case.workers == 1 else None
    run_tasks(executor, case.workers, limit_cycle_run, [(case.vehicle, v) for v in grid], done, failed)
    speeds = [v for v in sorted(runs) if runs[v]["limit_cycle"] is not None]    # runs with an answer
    flags = [runs[v]["limit_cycle"] for v in speeds]
    critical = bracket = None
    note = None
    first = next((k for k, f in enumerate(flags) if f), None)
    if first is None:
        note = (f"no limit cycle persists at any speed of {lo:g}-{hi:g} km/h after the lateral disturbance: the "
                "nonlinear critical speed lies above the range")
    elif first == 0:
        note = (f"a limit cycle persists at the lowest speed of the range ({lo:g} km/h): the nonlinear critical speed "
                "lies below the range")
        bracket = [None, speeds[0]]
    else:
        evaluated, (v_lo, _), (v_hi, _) = _bisect(lambda v: _run_or_no_answer(case.vehicle, v), speeds[first - 1],
                                                  speeds[first], None, None, lambda r: r["limit_cycle"],
                                                  progress, "nonlinear")
        for v, r in evaluated:
            runs[v] = r
        critical = 0.5 * (v_lo + v_hi)
        bracket = [v_lo, v_hi]
    return {"runs": runs, "critical_kmh": critical, "bracket_kmh": bracket, "note": note}


def _conicity(vehicle) -> dict:
    """The contact geometry's conicity beside the results: the local one at the centred position (what the
    linearisation sees) and the equivalent conicity at :data:`~.critical_speed_defaults.CONICITY_AMPLITUDE_M`
    (harmonic linearisation)."""
    g = vehicle.geometry
    pair = WheelRailPair(g.wheel_profile, g.rail_profile, gauge_m=g.gauge_m, inclination=g.rail_inclination_tan,
                         back_to_back_m=g.back_to_back_m, r0_m=g.r0_m)
    h = CONICITY_STEP_M
    y = np.linspace(-CONICITY_SWEEP_M, CONICITY_SWEEP_M, int(round(2 * CONICITY_SWEEP_M / CONICITY_STEP_M)) + 1)
    sweep = contact_geometry_sweep(pair, y)
    centre = contact_geometry_sweep(pair, np.array([-h, h]))
    local = float((centre.delta_r_m[1] - centre.delta_r_m[0]) / (4.0 * h))
    return {"local_at_centre": local, "equivalent_at_3mm": float(equivalent_conicity(y, sweep.delta_r_m,
                                                                                      CONICITY_AMPLITUDE_M)),
            "amplitude_m": CONICITY_AMPLITUDE_M, "method": "harmonic linearisation of the rolling-radius difference"}


def _assumptions() -> dict:
    return {
        "model": "the full model of the run command: the vehicle file's bodies and suspension, the wheel-rail "
                 "connector (the real profiles, Hertz, Kalker's exact theory tabulated), perfect straight rigid "
                 "track, the frame moving with the speed",
        "operating_point": f"the centred running state after {SETTLE_DURATION_S:g} s on perfect track from the static "
                           "equilibrium (wheelset spin at the rolling speed of the actual contact radius)",
        "contact_geometry": "the real profiles' geometry and its derivatives at the centred position (local "
                            "conicity, contact angle and roll derivatives), not an equivalent conicity",
        "creep": "the creep law's tangent at the operating point's creepages: zero lateral creepage, the small "
                 "longitudinal one of rolling and the spin creepage of the contact angle (sin γ / r0 per wheel, "
                 "opposite on the two wheels); with Kalker's exact theory (the table) and FASTSIM that spin's partial "
                 "slip lowers the tangent below Kalker's linear coefficients (S1002/UIC60 1:40 at the centre: "
                 "longitudinal by 10 %, lateral by 5 %); the law 'linear' keeps them",
        "gravitational_stiffness": "included: the normal forces' lateral components of the contact geometry",
        "spin": "included: the spin creepage of the contact angle and of the yaw rate, gyroscopic coupling of the "
                "spinning wheelsets",
        "linearisation": "central differences of the accelerations in track-frame coordinates (displacements, "
                         "small rotations and their rates), every force element of the model",
        "hunting_mode": f"the lateral oscillating modes: lateral, roll and yaw at least {LATERAL_SHARE_MIN:g} of "
                        "the shape's squared amplitude",
        "nonlinear_runs": f"constant speed, a {1e3 * BUMP_DEPTH_M:g} mm, {BUMP_LENGTH_M:g} m lateral bump of both "
                          f"rails, {RUN_DISTANCE_M:g} m, {RUN_SOLVER} {1e3 * RUN_DT_S:g} ms; amplitude: the "
                          f"half the peak-to-peak y of each wheelset relative to its rails over the last "
                          f"{CYCLE_WINDOW_M:g} m; persisting: at least {1e3 * PERSIST_AMPLITUDE_M:g} mm and the "
                          f"least-squares trend of the last {TREND_WINDOWS} windows' amplitudes decaying no faster than "
                          f"a mode of damping ratio {PERSIST_DAMPING_RATIO:g} (per cycle); a derailed run persists, a "
                          "diverged one is left out",
        "unstable_branch": f"between the nonlinear and the linear critical speed ({BRANCH_POINTS} speeds): the bump's "
                           f"depth bisected between {1e3 * BRANCH_MIN_DEPTH_M:.3g} and {1e3 * BUMP_DEPTH_M:g} mm "
                           f"(to a ratio {BRANCH_DEPTH_RATIO:g}) between decay and the stable cycle; the amplitude "
                           f"where the two bracketing runs linger ({BRANCH_WINDOW_M:g} m windows, within a factor "
                           f"{BRANCH_LINGER_RATIO:g} of each other, least change): an estimate of the unstable "
                           "cycle's, measured as the stable branch's",
    }


def run_critical_speed(case: CriticalSpeedCase, out_dir, progress=None) -> dict:
    """The analysis (module docstring); writes into ``out_dir`` and returns the summary (``paths``: the files)."""
    vehicle = check_case(case)
    out = output_dir("--out", out_dir)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    say = progress or (lambda text: None)
    t0 = time.perf_counter()
    conicity = _conicity(vehicle)
    lin = linear_critical_speed(case, say)
    t1 = time.perf_counter()
    nl = nonlinear_critical_speed(case, say)
    t2 = time.perf_counter()
    speeds = branch_speeds(nl["critical_kmh"], lin["critical_kmh"], float(case.speed_range_kmh[1]))
    branch = unstable_branch(case.vehicle, speeds, case.workers, say) if case.unstable_branch else {}
    t3 = time.perf_counter()
    summary = _summary(case, vehicle, lin, nl, branch, conicity, (t1 - t0, t2 - t1, t3 - t2))
    paths = _write(out, lin, nl, branch, summary)
    summary["paths"] = paths
    write_json(out / "summary.json", summary)
    return summary


def _branch_summary(case, nl, branch) -> tuple[list, str | None]:
    """The unstable branch's entries for the summary and its note."""
    rows = [{k: r.get(k) for k in ("speed_kmh", "found", "amplitude_m", "stable_amplitude_m", "depth_bracket_m",
                                   "window_m", "note")}
            for _, r in sorted(branch.items())]
    if not case.unstable_branch:
        return rows, "not computed (unstable_branch off)"
    if not branch:
        return rows, ("no speed between the nonlinear and the linear critical speed in the range" if
                      nl["critical_kmh"] is not None else "no nonlinear critical speed in the range")
    if not any(r["found"] for r in branch.values()):
        return rows, "not found at any speed tried (see each entry's note)"
    return rows, None


def _summary(case, vehicle, lin, nl, branch, conicity, seconds) -> dict:
    notes = []
    for v, text in lin["failed"].items():
        notes.append(f"linear: {v:g} km/h left out: {text}")
    if lin["unstable_at_lowest"] is not None:
        notes.append(f"linear: a lateral mode is unstable at the lowest speed of the range "
                     f"({case.speed_range_kmh[0]:g} km/h): the linear critical speed lies below the range")
    elif lin["critical_kmh"] is None:
        notes.append(f"linear: every lateral mode is damped up to {case.speed_range_kmh[1]:g} km/h")
    if nl["note"]:
        notes.append(f"nonlinear: {nl['note']}")
    bad = [f"the nonlinear run at {v:g} km/h ended {r['status']}" for v, r in sorted(nl["runs"].items())
           if r["limit_cycle"] is None]                     # an executor's error, a diverged run: no answer
    residual = max(p["residual_acceleration"] for p in lin["points"].values())
    branch_rows, branch_note = _branch_summary(case, nl, branch)
    notes += [f"nonlinear: {b}: that speed is left out" for b in bad]
    return {"status": "ok" if not bad else "error: " + bad[0],
            "vehicle": vehicle.name, "vehicle_source": case.vehicle,
            "speed_range_kmh": [float(v) for v in case.speed_range_kmh],
            "linear_critical_speed_kmh": lin["critical_kmh"], "linear_bracket_kmh": lin["bracket_kmh"],
            "hunting_frequency_hz": lin["frequency_hz"], "hunting_mode_shape": lin["shape"],
            "hunting_mode_bodies": [b["body"] for b in lin["shape"] or [] if b["lateral"] >= MOVING_BODY_SHARE],
            "unstable_at_lowest_speed": lin["unstable_at_lowest"],
            "nonlinear_critical_speed_kmh": nl["critical_kmh"], "nonlinear_bracket_kmh": nl["bracket_kmh"],
            "nonlinear_note": nl["note"], "unstable_branch": branch_rows, "unstable_branch_note": branch_note,
            "notes": notes, "conicity": conicity,
            "assumptions": _assumptions(), "max_residual_acceleration": residual,
            "linear_speeds_kmh": sorted(lin["points"]), "nonlinear_speeds_kmh": sorted(nl["runs"]),
            "run_statuses": {f"{v:g}": nl["runs"][v]["status"] for v in sorted(nl["runs"])},
            "seconds": {"linear": seconds[0], "nonlinear": seconds[1], "unstable_branch": seconds[2],
                        "nonlinear_runs": [nl["runs"][v]["seconds"] for v in sorted(nl["runs"])]},
            "workers": case.workers}


def _root_locus(points: dict) -> tuple[dict, list]:
    speeds = sorted(points)
    sets = track_modes([ModeSet(points[v]["eigenvalues"], points[v]["shapes"]) for v in speeds])
    table = {"speed_kmh": [], "mode": [], "frequency_hz": [], "damping_ratio": [], "real_part_1_per_s": [],
             "lateral_share": []}
    for v, ms in zip(speeds, sets):
        share = _share_of(points[v], ms)
        for k in range(len(ms)):
            if not ms.listed[k]:
                continue
            table["speed_kmh"].append(v)
            table["mode"].append(k)
            table["frequency_hz"].append(float(ms.frequency_hz[k]))
            table["damping_ratio"].append(float(ms.damping_ratio[k]))
            table["real_part_1_per_s"].append(float(ms.eigenvalues[k].real))
            table["lateral_share"].append(float(share[k]))
    return table, sets


def _share_of(point: dict, ms: ModeSet) -> np.ndarray:
    """The lateral share of the modes of ``ms`` (the point's modes, reordered)."""
    lam = np.asarray(point["eigenvalues"])
    share = np.asarray(point["lateral_share"])
    return np.array([share[int(np.argmin(np.abs(lam - e)))] for e in ms.eigenvalues])


def _write(out: Path, lin, nl, branch, summary) -> dict:
    table, _ = _root_locus(lin["points"])
    write_table_csv(out / "root_locus.csv", table)
    speeds = sorted(lin["points"])
    least = [least_damped(lin["points"][v]) for v in speeds]
    lam = [np.asarray(lin["points"][v]["eigenvalues"])[k] if k is not None else complex("nan")
           for v, (_, k) in zip(speeds, least)]
    write_table_csv(out / "linear_speeds.csv", {
        "speed_kmh": speeds, "least_damped_lateral_damping_ratio": [z for z, _ in least],
        "least_damped_lateral_frequency_hz": [abs(x.imag) / (2 * math.pi) for x in lam],
        "residual_acceleration": [lin["points"][v]["residual_acceleration"] for v in speeds]})
    bif = {"speed_kmh": [], "wheelset": [], "amplitude_m": [], "persists": [], "frequency_hz": [], "status": [],
           "branch": []}

    def row(v, j, a, persists, f, status, which):
        for key, value in zip(bif, (v, j + 1, a, persists, f, status, which)):
            bif[key].append(value)
    for v in sorted(nl["runs"]):
        r = nl["runs"][v]
        for j, (a, p) in enumerate(zip(r["amplitude_m"], r["persists"])):
            row(v, j, a, bool(p), r.get("frequency_hz", [float("nan")] * (j + 1))[j], r["status"], "stable")
    for v in sorted(branch):
        for j, a in enumerate(branch[v]["amplitude_m"] if branch[v]["found"] else []):
            row(v, j, a, False, float("nan"), "ok", "unstable")
    write_table_csv(out / "bifurcation.csv", bif)
    paths = {"summary": str(out / "summary.json"), "root_locus": str(out / "root_locus.csv"),
             "bifurcation": str(out / "bifurcation.csv"), "linear_speeds": str(out / "linear_speeds.csv")}
    figures = write_figures(out, table, bif, summary)          # a table and its figure share a name: keys apart
    paths.update({f"{name}_figure": path for name, path in figures.items()})
    return paths


def read_summary(out_dir) -> dict:
    """The ``summary.json`` of an analysis written into ``out_dir``."""
    return json.loads((Path(out_dir) / "summary.json").read_text())
