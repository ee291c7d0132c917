"""Timing of the wheel-rail contact kernel (exudyn_wheelrail.contact): searches and the all-wheels evaluation.

Measured on S1002 / UIC60 1:40 (``WheelRailPair()``) after JIT compilation (warm-up excluded), with
``time.perf_counter``, median (and min-max) of several repeats:

1. ``convex_newton`` for one wheel region: the tread of each of the 8 wheels at every step of the trajectory
   below, started from the kernel's warm start of that step (the previous step's solution), i.e. the kernel's
   first Newton attempt — inside a numba loop; separately, the same calls from Python;
2. ``vertical_overlap_search`` (the concave search) at the kernel defaults (n_wheel = n_rail = 100,
   refine = True) on a conformal pose (flange root / throat against the UIC60 gauge corner, found by a scan near
   c_y = 6.9 mm, roll = -0.73 mrad, 200 um vertical overlap) at which the kernel reports status 2 (concave) with
   the maximum inside the region; also the discrete variant (refine = False) and the coarse scan of global mode;
3. geometry + Hertz for 8 wheels (4 wheelsets, ``WheelsetContact(pair, n_wheelsets=4)``): ``evaluate_wheels``
   from a numba driver loop and ``WheelsetContact.evaluate`` from Python; warm mode (global_search=False) and
   global mode; a per-region breakdown (``solve_region`` for the tread regions / flange regions only); the cost
   of the pieces of the full search of a separated flange; a second warm-mode trajectory (+-5.5 mm) on which the
   flanges come within ~0.2 mm; and whether warm and global mode report the same contacts (steady state);
4. the same 8-wheel evaluation (warm) in plain Python: this file re-run in a subprocess with
   ``NUMBA_DISABLE_JIT=1`` (``--plain-python``), one untimed and one timed pass over the trajectory.

Trajectory ("time integration"): 4 wheelsets, lateral sinusoid y_k = 3 mm sin(2 pi t + k pi/2), 1000 evaluations
per period (lateral step <= 19 um), z and roll from the rigid two-wheel contact (``solve_rigid_contact``) at y_k,
then lowered by 75 +- 15 um (3 cycles per period) and rolled by +- 10 urad (2 cycles): every wheel is in tread
contact with ~40-100 um penetration; the flanges stay 2-7 mm away.  The trajectory is periodic, so repeated
passes run in the kernel's steady state (warm starts and separation bounds from the previous pass).

Run:  python benchmarks/bench_contact.py     (about 30-60 s; writes benchmarks/results/contact.json and .csv)
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import numba
from numba import njit

from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact.kernel import evaluate_wheels, solve_region
from exudyn_wheelrail.contact.pair import WheelRailPair
from exudyn_wheelrail.contact.search import (convex_newton, nearest_by_normal_distance, nearest_start,
                                             vertical_overlap_search)
from exudyn_wheelrail.contact.wheelset import WheelsetContact

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from contact_poses import REGION_NAMES, region_bounds, scan_concave_poses  # noqa: E402

RESULTS = HERE / "results"

N_WHEELSETS = 4
STEPS_PER_PERIOD = 1000
Y_AMPLITUDE_M = 3e-3
STRESS_AMPLITUDE_M = 5.5e-3   # second warm-mode trajectory: flange gaps down to ~0.2 mm, separation bounds expire
LOWERING_M = 75e-6
LOWERING_VAR_M = 15e-6
ROLL_VAR_RAD = 10e-6
PLAIN_PYTHON_MAX_S = 60.0     # plain-Python subprocess: at most 30 s untimed warm-up pass + 30 s timed pass

# conformal throat pose of the right wheel (side frame), see concave_pose()
THROAT_C_Y_M = 6.9e-3
THROAT_ROLL_RAD = -0.73e-3
THROAT_OVERLAP_M = 200e-6


# ---------------------------------------------------------------------------------------------------- machine
def machine_info() -> dict:
    cpu = ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        load = os.getloadavg()
    except OSError:
        load = (float("nan"),) * 3
    return {"platform_processor": platform.processor(), "cpu_model": cpu, "cpu_count": os.cpu_count(),
            "machine": platform.machine(), "system": f"{platform.system()} {platform.release()}",
            "python": platform.python_version(), "numba": numba.__version__, "numpy": np.__version__,
            "loadavg_1_5_15": [round(x, 2) for x in load], "git": git_state()}


def git_state() -> str:
    """Commit of the library under test (read-only git queries) and whether its files differ from it."""
    try:
        root = HERE.parent
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True,
                              timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "exudyn_wheelrail"], cwd=root,
                               capture_output=True, text=True, timeout=10).stdout.strip()
        return head + (" (+ uncommitted changes in exudyn_wheelrail)" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        return "?"


# ---------------------------------------------------------------------------------------------------- drivers
@njit(cache=False)
def _drive_newton(nodes, meta, rail, wheel, side_poses, starts, max_iter, tol, iters):
    """convex_newton for the tread of every wheel at every step, started from the kernel's warm start of that
    step (the solution of the previous step): exactly the kernel's first Newton attempt in warm mode."""
    n_fail = 0
    acc = 0.0
    for i in range(side_poses.shape[0]):
        for w in range(side_poses.shape[1]):
            roll = side_poses[i, w, 2]
            conv, s_r, s_w, it = convex_newton(nodes, meta, rail, wheel, side_poses[i, w, 0], side_poses[i, w, 1],
                                               np.cos(roll), np.sin(roll), starts[i, w, 0], starts[i, w, 1],
                                               max_iter, tol)
            iters[i, w] = it
            acc += s_w
            if not conv:
                n_fail += 1
    return acc, n_fail


@njit(cache=False)
def _drive_trig(side_poses):
    """The loop, pose reads and cos/sin of _drive_newton without the Newton call (reference)."""
    acc = 0.0
    for i in range(side_poses.shape[0]):
        for w in range(side_poses.shape[1]):
            roll = side_poses[i, w, 2]
            acc += side_poses[i, w, 0] + side_poses[i, w, 1] + np.cos(roll) + np.sin(roll)
    return acc


@njit(cache=False)
def _drive_concave(nodes, meta, mono, rail, wheel, c_y, c_z, cos_r, sin_r, s_lo, s_hi, n_wheel, n_rail, refine):
    acc = 0.0
    n_found = 0
    for i in range(c_y.size):
        found, s_w, s_r, dv = vertical_overlap_search(nodes, meta, mono, rail, wheel, c_y[i], c_z[i], cos_r[i],
                                                      sin_r[i], s_lo, s_hi, n_wheel, n_rail, refine)
        acc += dv
        if found:
            n_found += 1
    return acc, n_found


@njit(cache=False)
def _drive_wheels(nodes, meta, mono, curve_ids, side_poses, warm, params, out):
    """evaluate_wheels along a trajectory side_poses (n_steps, n_wheels, 3)."""
    acc = 0.0
    for i in range(side_poses.shape[0]):
        evaluate_wheels(nodes, meta, mono, curve_ids, side_poses[i], warm, params, out)
        acc += out[0, 0, K.F_NORMAL_FORCE]
    return acc


@njit(cache=False)
def _drive_wheels_record(nodes, meta, mono, curve_ids, side_poses, warm, params, out, status, iters, pen, starts):
    """evaluate_wheels along the trajectory, recording status, iterations, penetration and the warm start."""
    for i in range(side_poses.shape[0]):
        for w in range(out.shape[0]):
            starts[i, w, 0] = warm[w, 0, 0]
            starts[i, w, 1] = warm[w, 0, 1]
        evaluate_wheels(nodes, meta, mono, curve_ids, side_poses[i], warm, params, out)
        for w in range(out.shape[0]):
            for r in range(2):
                status[i, w, r] = out[w, r, K.F_STATUS]
                iters[i, w, r] = out[w, r, K.F_ITERATIONS]
                pen[i, w, r] = out[w, r, K.F_PENETRATION]


@njit(cache=False)
def _drive_regions(nodes, meta, mono, curve_ids, side_poses, warm, params, out, reg):
    """solve_region of one region (0 tread, 1 flange) of every wheel along the trajectory (cost breakdown)."""
    for i in range(side_poses.shape[0]):
        for w in range(side_poses.shape[1]):
            solve_region(nodes, meta, mono, curve_ids[w, 0], curve_ids[w, 1 + reg], side_poses[i, w, 0],
                         side_poses[i, w, 1], side_poses[i, w, 2], warm, params, out, w, reg)


@njit(cache=False)
def _piece(which, n, nodes, meta, mono, wheel, c_y, c_z, roll, s_r0, s_w0, s_lo, s_hi, params):
    """One step of the separated-flange path of solve_region, n times (cost of the pieces)."""
    cos_r = np.cos(roll)
    sin_r = np.sin(roll)
    n_scan = int(params[K.P_N_SCAN])
    acc = 0.0
    for _ in range(n):
        if which == 0:
            conv, s_r, s_w, it = convex_newton(nodes, meta, 0, wheel, c_y, c_z, cos_r, sin_r, s_r0, s_w0,
                                               int(params[K.P_NEWTON_MAX_ITER]), params[K.P_NEWTON_TOL])
            acc += s_w + it
        elif which == 1:
            found, s_w, s_r, dv = vertical_overlap_search(nodes, meta, mono, 0, wheel, c_y, c_z, cos_r, sin_r, s_lo,
                                                          s_hi, n_scan, 0, False)
            acc += s_w
        elif which == 2:
            s_w, s_r = nearest_start(nodes, meta, 0, wheel, c_y, c_z, cos_r, sin_r, s_lo, s_hi, n_scan, n_scan)
            acc += s_w
        elif which == 3:
            found, s_w, s_r, dv = vertical_overlap_search(nodes, meta, mono, 0, wheel, c_y, c_z, cos_r, sin_r, s_lo,
                                                          s_hi, int(params[K.P_N_CONCAVE_WHEEL]),
                                                          int(params[K.P_N_CONCAVE_RAIL]), params[K.P_REFINE] > 0.0)
            acc += s_w
        else:
            ok, all_ok, s_w, s_r, d = nearest_by_normal_distance(nodes, meta, 0, wheel, c_y, c_z, cos_r, sin_r, s_lo, s_hi,
                                                         n_scan, s_r0)
            acc += s_w
    return acc


# ---------------------------------------------------------------------------------------------------- helpers
class Timing(float):
    """Median wall time [s] (a float) that also carries the min and max of the repeats."""

    def __new__(cls, times):
        obj = super().__new__(cls, float(np.median(times)))
        obj.min = float(np.min(times))
        obj.max = float(np.max(times))
        return obj

    def per(self, n: float) -> "Timing":
        return Timing([float(self) / n, self.min / n, self.max / n])


def median_time(fn, repeats: int) -> Timing:
    """Median (and min/max) wall time [s] of fn() over ``repeats`` runs (fn must already be compiled)."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return Timing(times)


def row(part: str, path: str, t: Timing, note: str) -> dict:
    """A table row; t in seconds per call."""
    return {"part": part, "path": path, "us_per_call": float(t) * 1e6, "us_min": getattr(t, "min", float(t)) * 1e6,
            "us_max": getattr(t, "max", float(t)) * 1e6, "note": note}


def time_python_path(contact: WheelsetContact, poses: np.ndarray, repeats: int) -> Timing:
    """Seconds per ``contact.evaluate`` call over the pose sequence (n, n_wheelsets, 3); median of repeats."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for i in range(poses.shape[0]):
            contact.evaluate(poses[i])
        times.append((time.perf_counter() - t0) / poses.shape[0])
    return Timing(times)


def trajectory(pair: WheelRailPair, amplitude_m: float = Y_AMPLITUDE_M) -> np.ndarray:
    """Wheelset poses (STEPS_PER_PERIOD, N_WHEELSETS, 3) = (y, z, roll), track frame; periodic."""
    from exudyn_wheelrail.analysis.geometry_functions import solve_rigid_contact

    rigid = WheelsetContact(pair, 1, global_search=True)
    ys = np.linspace(-amplitude_m - 2e-4, amplitude_m + 2e-4, 2 * int(round(amplitude_m / 2e-4)) + 3)
    zs, rolls = [], []
    z, roll = None, 0.0
    for y in ys:
        st = solve_rigid_contact(rigid, float(y), z, roll)
        z, roll = st.z_m, st.roll_rad
        zs.append(z)
        rolls.append(roll)
    t = np.arange(STEPS_PER_PERIOD) / STEPS_PER_PERIOD
    poses = np.zeros((STEPS_PER_PERIOD, N_WHEELSETS, 3))
    for k in range(N_WHEELSETS):
        y = amplitude_m * np.sin(2 * np.pi * t + k * np.pi / 2)
        poses[:, k, 0] = y
        poses[:, k, 1] = (np.interp(y, ys, zs) + LOWERING_M
                          + LOWERING_VAR_M * np.sin(2 * np.pi * 3 * t + 1.3 * k))
        poses[:, k, 2] = np.interp(y, ys, rolls) + ROLL_VAR_RAD * np.sin(2 * np.pi * 2 * t + 0.7 * k)
    return poses


def side_trajectory(contact: WheelsetContact, poses: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(np.stack([contact.side_poses(p).copy() for p in poses]))



# ---------------------------------------------------------------------------------------------------- parts
def record_trajectory(contact: WheelsetContact, side_poses: np.ndarray) -> dict:
    """One pass along the (periodic) trajectory from the current warm state: statuses, iterations, penetrations
    and the warm start the kernel used at each step."""
    n, nw = side_poses.shape[0], side_poses.shape[1]
    rec = {"status": np.zeros((n, nw, 2)), "iters": np.zeros((n, nw, 2)), "pen": np.zeros((n, nw, 2)),
           "starts": np.zeros((n, nw, 2))}
    _drive_wheels_record(contact.nodes, contact.meta, contact.mono, contact.curve_ids, side_poses, contact.warm,
                         contact.params, contact.out, rec["status"], rec["iters"], rec["pen"], rec["starts"])
    return rec


def trajectory_stats(rec: dict) -> dict:
    res = {}
    for r, name in enumerate(("tread", "flange")):
        st = {int(k): int(v) for k, v in zip(*np.unique(rec["status"][:, :, r], return_counts=True))}
        it = {int(k): int(v) for k, v in zip(*np.unique(rec["iters"][:, :, r], return_counts=True))}
        res[name] = {"status_counts": st, "iteration_counts": it,
                     "searched_fraction": float(np.mean(rec["iters"][:, :, r] > 0)),
                     "iterations_mean": float(rec["iters"][:, :, r].mean()),
                     "penetration_um_min": float(rec["pen"][:, :, r].min() * 1e6),
                     "penetration_um_max": float(rec["pen"][:, :, r].max() * 1e6)}
    return res


def fmt_stats(s: dict) -> str:
    t, f = s["tread"], s["flange"]
    return (f"tread: status {t['status_counts']}, Newton it. mean {t['iterations_mean']:.2f} "
            f"{t['iteration_counts']}, delta {t['penetration_um_min']:.0f}..{t['penetration_um_max']:.0f} um; "
            f"flange: status {f['status_counts']}, it. mean {f['iterations_mean']:.2f}, searched in "
            f"{f['searched_fraction'] * 100:.1f} % of the evaluations (else skipped by the separation bound), "
            f"reported gap {-f['penetration_um_max'] / 1e3:.2f}..{-f['penetration_um_min'] / 1e3:.2f} mm")


def bench_convex(pair: WheelRailPair, poses: np.ndarray) -> list[dict]:
    """convex_newton for one region (tread), warm-started from the previous step's solution."""
    contact = WheelsetContact(pair, N_WHEELSETS, global_search=False)
    sp = side_trajectory(contact, poses)
    _drive_wheels(contact.nodes, contact.meta, contact.mono, contact.curve_ids, sp, contact.warm, contact.params,
                  contact.out)
    rec = record_trajectory(contact, sp)
    starts = np.ascontiguousarray(rec["starts"])
    tol = float(contact.params[K.P_NEWTON_TOL])
    max_iter = int(contact.params[K.P_NEWTON_MAX_ITER])
    nodes, meta = contact.nodes, contact.meta
    iters = np.zeros(sp.shape[:2], dtype=np.int64)
    n = sp.shape[0] * sp.shape[1]
    _drive_newton(nodes, meta, 0, 1, sp, starts, max_iter, tol, iters)
    _drive_trig(sp)
    t_loop = median_time(lambda: _drive_newton(nodes, meta, 0, 1, sp, starts, max_iter, tol, iters), 25).per(n)
    t_trig = median_time(lambda: _drive_trig(sp), 25).per(n)
    acc, n_fail = _drive_newton(nodes, meta, 0, 1, sp, starts, max_iter, tol, iters)
    hist = {int(k): int(v) for k, v in zip(*np.unique(iters, return_counts=True))}
    lat_step = np.max(np.abs(np.diff(sp[:, :, 0], axis=0)))
    # the same calls from Python (numba dispatcher: type checks, unboxing of 12 arguments, boxing of the tuple)
    m = 2000
    args = [(float(sp[i, w, 0]), float(sp[i, w, 1]), float(np.cos(sp[i, w, 2])), float(np.sin(sp[i, w, 2])),
             float(starts[i, w, 0]), float(starts[i, w, 1]))
            for i in range(sp.shape[0]) for w in range(sp.shape[1])][:m]

    def py_loop():
        for c_y, c_z, co, si, s_r, s_w in args:
            convex_newton(nodes, meta, 0, 1, c_y, c_z, co, si, s_r, s_w, max_iter, tol)

    py_loop()
    t_py = median_time(py_loop, 9).per(m)
    note = (f"{n} calls (8 tread regions x {sp.shape[0]} steps, start = kernel's warm start); iterations "
            f"{hist} (mean {iters.mean():.2f}), {n_fail} not converged (contact jumps: the kernel then rescans); "
            f"lateral step <= {lat_step * 1e6:.0f} um; includes cos/sin of the roll "
            f"(loop+cos/sin alone {float(t_trig) * 1e9:.0f} ns)")
    return [row("convex search (convex_newton), 1 region, warm", "numba loop", t_loop, note),
            row("convex search (convex_newton), 1 region, warm", "Python call", t_py,
                f"Python-call overhead {(float(t_py) - float(t_loop)) * 1e6:.2f} us/call (numba dispatcher)")]


def concave_pose(pair: WheelRailPair) -> dict:
    """A conformal pose of the right wheel near (c_y = THROAT_C_Y_M, roll = THROAT_ROLL_RAD) at which the kernel
    reports status 2 for a region with the maximum inside the region (not at the tread/flange split point)."""
    c_ys = np.arange(3.0e-3, 8.0001e-3, 0.05e-3)
    hits = scan_concave_poses(pair, [THROAT_ROLL_RAD], c_ys, [THROAT_OVERLAP_M])
    inner = [h for h in hits if not h["at_region_end"]]
    if not inner:
        raise RuntimeError("no pose with an interior concave (status 2) contact found")
    best = min(inner, key=lambda h: abs(h["c_y"] - THROAT_C_Y_M))
    best["n_hits_scanned"] = len(hits)
    best["n_hits_at_region_end"] = len(hits) - len(inner)
    return best


def bench_concave(pair: WheelRailPair) -> tuple[list[dict], dict]:
    contact = WheelsetContact(pair, 1)
    nodes, meta, mono = contact.nodes, contact.meta, contact.mono
    pose = concave_pose(pair)
    c_y0, c_z0, roll0, curve = pose["c_y"], pose["c_z"], pose["roll"], pose["curve"]
    rng = np.random.default_rng(1)
    n = 2000
    c_y = c_y0 + rng.uniform(-2e-6, 2e-6, n)
    c_z = c_z0 + rng.uniform(-2e-6, 2e-6, n)
    roll = roll0 + rng.uniform(-2e-6, 2e-6, n)
    cos_r, sin_r = np.cos(roll), np.sin(roll)
    s_lo, s_hi = region_bounds(nodes, meta, curve)
    n_w_def = int(contact.params[K.P_N_CONCAVE_WHEEL])
    n_r_def = int(contact.params[K.P_N_CONCAVE_RAIL])
    ref_def = bool(contact.params[K.P_REFINE] > 0)
    n_scan = int(contact.params[K.P_N_SCAN])
    rows = []
    configs = [(n_w_def, n_r_def, ref_def, "kernel default (concave search)"),
               (n_w_def, n_r_def, False, "discrete paper method, no refinement"),
               (n_scan, 0, False, "coarse scan of global mode (Newton start), n_scan")]
    for n_w, n_r, ref, label in configs:
        _drive_concave(nodes, meta, mono, 0, curve, c_y, c_z, cos_r, sin_r, s_lo, s_hi, n_w, n_r, ref)
        t = median_time(lambda: _drive_concave(nodes, meta, mono, 0, curve, c_y, c_z, cos_r, sin_r, s_lo, s_hi, n_w,
                                               n_r, ref), 9).per(n)
        found, s_w, s_r, dv = vertical_overlap_search(nodes, meta, mono, 0, curve, c_y0, c_z0, np.cos(roll0),
                                                      np.sin(roll0), s_lo, s_hi, n_w, n_r, ref)
        rows.append(row(f"concave search (vertical_overlap_search) n_wheel={n_w} n_rail={n_r} refine={ref}",
                        "numba loop", t, f"{label}; max vertical overlap {dv * 1e6:.2f} um at s_w {s_w * 1e3:.3f} mm"))
    cy_l, cz_l, cr_l, sr_l = c_y.tolist(), c_z.tolist(), cos_r.tolist(), sin_r.tolist()

    def py_loop():
        for i in range(n):
            vertical_overlap_search(nodes, meta, mono, 0, curve, cy_l[i], cz_l[i], cr_l[i], sr_l[i], s_lo, s_hi,
                                    n_w_def, n_r_def, ref_def)

    t_py = median_time(py_loop, 5).per(n)
    rows.append(row(f"concave search (vertical_overlap_search) n_wheel={n_w_def} n_rail={n_r_def} refine={ref_def}",
                    "Python call", t_py,
                    f"Python-call overhead {(float(t_py) - rows[0]['us_per_call'] * 1e-6) * 1e6:.2f} us/call"))
    return rows, pose


def bench_flange_pieces(pair: WheelRailPair, poses: np.ndarray) -> list[dict]:
    """Cost of the pieces of the full search of a separated flange region (solve_region when nothing overlaps:
    Newton fails -> scan -> nearest_start -> Newton -> concave search -> nearest_by_normal_distance), at
    step 0 of the trajectory, right wheel, started from the kernel's warm state."""
    contact = WheelsetContact(pair, N_WHEELSETS, global_search=False)
    sp = side_trajectory(contact, poses)
    _drive_wheels(contact.nodes, contact.meta, contact.mono, contact.curve_ids, sp, contact.warm, contact.params,
                  contact.out)
    c_y, c_z, roll = (float(x) for x in sp[0, 0])
    s_r0, s_w0 = float(contact.warm[0, 1, 0]), float(contact.warm[0, 1, 1])   # (s_rail, s_wheel)
    s_lo, s_hi = region_bounds(contact.nodes, contact.meta, 2)
    n = 2000
    names = ["convex_newton from the warm start (max_iter, does not converge)",
             "vertical_overlap_search(n_scan, 0, refine=False): scan of the region",
             "nearest_start(n_scan x n_scan) (nothing overlaps vertically)",
             "vertical_overlap_search(100, 100, refine=True): concave search",
             "nearest_by_normal_distance(n_scan): the gap"]
    rows = []
    for which, name in enumerate(names):
        a = (which, n, contact.nodes, contact.meta, contact.mono, 2, c_y, c_z, roll, s_r0, s_w0, s_lo, s_hi,
             contact.params)
        _piece(*a)
        t = median_time(lambda: _piece(*a), 7).per(n)
        rows.append(row(f"  separated-flange search, piece: {name}", "numba loop", t,
                        "the full search of a separated flange region runs each piece once"
                        + (" (convex_newton twice: from the warm start and after the scan)" if which == 0 else "")
                        + "; warm mode: only when the separation bound has expired"))
    return rows


def bench_wheels(pair: WheelRailPair, poses: np.ndarray, global_search: bool, label: str = "",
                 breakdown: bool = True) -> tuple[list[dict], dict, dict]:
    contact = WheelsetContact(pair, N_WHEELSETS, global_search=global_search)
    sp = side_trajectory(contact, poses)
    args = (contact.nodes, contact.meta, contact.mono, contact.curve_ids, sp, contact.warm, contact.params,
            contact.out)
    _drive_wheels(*args)                        # compile + warm start along the periodic trajectory
    rec = record_trajectory(contact, sp)
    stats = trajectory_stats(rec)
    n = sp.shape[0]
    mode = ("global" if global_search else "warm") + label
    t_nb = median_time(lambda: _drive_wheels(*args), 9).per(n)
    t_py = time_python_path(contact, poses, 5)
    rows = [row(f"8 wheels geometry+Hertz ({mode}, evaluate_wheels)", "numba loop", t_nb, fmt_stats(stats)),
            row(f"8 wheels geometry+Hertz ({mode}, WheelsetContact.evaluate)", "Python call", t_py,
                f"Python overhead {(float(t_py) - float(t_nb)) * 1e6:.1f} us/call (medians)")]
    # breakdown: tread regions only / flange regions only (solve_region of all 8 wheels, separate warm starts)
    for reg, name in ((0, "tread"), (1, "flange")) if breakdown else ():
        warm = contact.warm.copy()
        out = contact.out.copy()
        a = (contact.nodes, contact.meta, contact.mono, contact.curve_ids, sp, warm, contact.params, out, reg)
        _drive_regions(*a)
        t = median_time(lambda: _drive_regions(*a), 5).per(n)
        rows.append(row(f"  breakdown ({mode}): the 8 {name} regions only (solve_region)", "numba loop", t,
                        f"{float(t) / 8 * 1e6:.2f} us per {name} region"))
    return rows, stats, rec


def warm_vs_global(warm_rec: dict, glob_rec: dict) -> dict:
    """Do warm and global mode report the same tread contact along the trajectory (same steady state)?"""
    dp = np.abs(warm_rec["pen"][:, :, 0] - glob_rec["pen"][:, :, 0])
    differ = dp > 1e-7

    def no_contact(rec):   # wheels with neither region in contact
        return int(np.sum((rec["status"][:, :, 0] <= 0) & (rec["status"][:, :, 1] <= 0)))

    return {"wheel_steps": int(dp.size), "differ_by_more_than_0.1um": int(differ.sum()),
            "max_abs_penetration_difference_um": float(dp.max() * 1e6),
            "status_differs": int(np.sum(warm_rec["status"][:, :, 0] != glob_rec["status"][:, :, 0])),
            "wheel_steps_without_contact_warm": no_contact(warm_rec),
            "wheel_steps_without_contact_global": no_contact(glob_rec)}


def fmt_agree(a: dict, label: str) -> str:
    return (f"Warm vs global mode, tread regions, {label}: {a['differ_by_more_than_0.1um']} of {a['wheel_steps']} "
            f"wheel-steps differ in penetration by > 0.1 um (max {a['max_abs_penetration_difference_um']:.1f} um), "
            f"status differs in {a['status_differs']}; wheel-steps with no contact on the wheel at all: warm "
            f"{a['wheel_steps_without_contact_warm']}, global {a['wheel_steps_without_contact_global']}")


def record_mode(pair: WheelRailPair, poses: np.ndarray, global_search: bool) -> dict:
    """Steady-state record of a mode along a periodic trajectory (untimed)."""
    contact = WheelsetContact(pair, N_WHEELSETS, global_search=global_search)
    sp = side_trajectory(contact, poses)
    _drive_wheels(contact.nodes, contact.meta, contact.mono, contact.curve_ids, sp, contact.warm, contact.params,
                  contact.out)
    return record_trajectory(contact, sp)


def bench_plain_python(poses: np.ndarray) -> dict:
    """Run this file with NUMBA_DISABLE_JIT=1 on the trajectory (see run_calls)."""
    sub = np.ascontiguousarray(poses)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "poses.npy"
        np.save(path, sub)
        env = dict(os.environ, NUMBA_DISABLE_JIT="1")
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--plain-python", str(path)],
                              env=env, capture_output=True, text=True, timeout=600)
        wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"plain-Python subprocess failed:\n{proc.stdout}\n{proc.stderr}")
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    res["subprocess_wall_s"] = wall
    return res


def run_calls(contact: WheelsetContact, poses: np.ndarray, max_s: float = PLAIN_PYTHON_MAX_S) -> list[float]:
    """The plain-Python procedure: one untimed pass over the periodic trajectory (warm starts and separation
    bounds in their steady state), then a pass with every call timed.  Each pass stops after ``max_s / 2``."""
    t0 = time.perf_counter()
    for i in range(poses.shape[0]):
        contact.evaluate(poses[i])
        if time.perf_counter() - t0 > 0.5 * max_s:
            break
    times = []
    t0 = time.perf_counter()
    for i in range(poses.shape[0]):
        t1 = time.perf_counter()
        contact.evaluate(poses[i])
        times.append(time.perf_counter() - t1)
        if time.perf_counter() - t0 > 0.5 * max_s:
            break
    return times


def plain_python_child(path: str):
    """Subprocess entry (NUMBA_DISABLE_JIT=1): time WheelsetContact.evaluate on the given poses."""
    import numba.core.config as cfg
    poses = np.load(path)
    contact = WheelsetContact(WheelRailPair(), poses.shape[1], global_search=False)
    times = run_calls(contact, poses)
    print(json.dumps({"jit_disabled": bool(cfg.DISABLE_JIT), "calls": len(times),
                      "us_per_call_mean": float(np.mean(times) * 1e6),
                      "us_per_call_median": float(np.median(times) * 1e6)}))


def compiled_same_calls(pair: WheelRailPair, poses: np.ndarray, n_calls: int) -> Timing:
    """Compiled WheelsetContact.evaluate with exactly the plain-Python procedure (same poses, same start)."""
    means = [float(np.mean(run_calls(WheelsetContact(pair, poses.shape[1], global_search=False), poses[:n_calls])))
             for _ in range(5)]
    return Timing(means)


# ---------------------------------------------------------------------------------------------------- output
def markdown(rows: list[dict]) -> str:
    lines = ["| measurement | path | µs per call (median) | min–max of repeats | notes |",
             "|---|---|---:|---:|---|"]
    for r in rows:
        lines.append(f"| {r['part']} | {r['path']} | {r['us_per_call']:.2f} | {r['us_min']:.2f}–{r['us_max']:.2f} "
                     f"| {r['note']} |")
    return "\n".join(lines)


def main():
    t_start = time.perf_counter()
    info = machine_info()
    pair = WheelRailPair()
    poses = trajectory(pair)

    rows = []
    rows += bench_convex(pair, poses)
    concave_rows, pose_info = bench_concave(pair)
    rows += concave_rows
    warm_rows, warm_stats, warm_rec = bench_wheels(pair, poses, global_search=False)
    rows += warm_rows
    rows += bench_flange_pieces(pair, poses)
    stress_poses = trajectory(pair, STRESS_AMPLITUDE_M)
    stress_rows, stress_stats, stress_rec = bench_wheels(pair, stress_poses, global_search=False,
                                                         label=f", +-{STRESS_AMPLITUDE_M * 1e3:.1f} mm: flanges "
                                                               f"approach", breakdown=False)
    rows += stress_rows
    agree_stress = warm_vs_global(stress_rec, record_mode(pair, stress_poses, True))
    glob_rows, glob_stats, glob_rec = bench_wheels(pair, poses, global_search=True)
    rows += glob_rows
    agree = warm_vs_global(warm_rec, glob_rec)
    plain = bench_plain_python(poses)
    compiled_py = compiled_same_calls(pair, poses, plain["calls"])
    ratio = float(compiled_py) * 1e6 / plain["us_per_call_mean"]
    t_nb_warm = warm_rows[0]["us_per_call"]
    rows.append(row("8 wheels geometry+Hertz (warm, WheelsetContact.evaluate), plain Python", "NUMBA_DISABLE_JIT=1",
                    Timing([plain["us_per_call_mean"] * 1e-6]),
                    f"mean of {plain['calls']} calls (one timed pass over the trajectory after an untimed one), "
                    f"median {plain['us_per_call_median']:.0f} us; compiled, same calls: "
                    f"{float(compiled_py) * 1e6:.1f} us -> ratio compiled/plain = {ratio:.2e} "
                    f"(speed-up {1 / ratio:.0f}x; vs numba loop {plain['us_per_call_mean'] / t_nb_warm:.0f}x)"))

    target_us = 20.0
    summary = (f"Target <= {target_us:.0f} us per 8-wheel evaluation (warm, compiled): measured "
               f"{t_nb_warm:.1f} us (numba loop) -> {'MET' if t_nb_warm <= target_us else 'NOT MET'}")
    header = (f"CPU: {info['cpu_model'] or '?'} (platform.processor(): {info['platform_processor']!r}, "
              f"{info['cpu_count']} logical CPUs, load avg {info['loadavg_1_5_15']}); "
              f"Python {info['python']}, numba {info['numba']}, numpy {info['numpy']}; library at git {info['git']}")
    pose_line = (f"Concave pose (right wheel, side frame): c_y = {pose_info['c_y'] * 1e3:.2f} mm, "
                 f"c_z = {pose_info['c_z'] * 1e3:.4f} mm, roll = {pose_info['roll'] * 1e3:.2f} mrad, max vertical "
                 f"overlap {pose_info['overlap_target'] * 1e6:.0f} um; kernel: {REGION_NAMES[pose_info['region']]} "
                 f"region status 2 at s_w = {pose_info['s_w_kernel'] * 1e3:.3f} mm, penetration "
                 f"{pose_info['penetration_kernel'] * 1e6:.1f} um, kappa_w {pose_info['kw_lat']:.1f} 1/m, kappa_r "
                 f"{pose_info['kr_lat']:.1f} 1/m; (of {pose_info['n_hits_scanned']} status-2 regions found on the scan "
                 f"c_y = 3..8 mm, {pose_info['n_hits_at_region_end']} had their maximum at the tread/flange split "
                 f"point)")
    table = markdown(rows)
    print(header)
    print()
    print(table)
    print()
    print(summary)
    print(pose_line)
    agree_lines = [fmt_agree(agree, f"+-{Y_AMPLITUDE_M * 1e3:.1f} mm trajectory"),
                   fmt_agree(agree_stress, f"+-{STRESS_AMPLITUDE_M * 1e3:.1f} mm trajectory")]
    print("\n".join(agree_lines))

    RESULTS.mkdir(exist_ok=True)
    with open(RESULTS / "contact.json", "w") as fh:
        json.dump({"machine": info, "rows": rows, "summary": summary, "concave_pose": pose_info,
                   "trajectory": {"n_wheelsets": N_WHEELSETS, "steps_per_period": STEPS_PER_PERIOD,
                                  "y_amplitude_m": Y_AMPLITUDE_M, "lowering_m": LOWERING_M,
                                  "lowering_var_m": LOWERING_VAR_M, "roll_var_rad": ROLL_VAR_RAD},
                   "stats_warm": warm_stats, "stats_warm_stress": stress_stats, "stats_global": glob_stats,
                   "plain_python": plain,
                   "warm_vs_global": agree, "warm_vs_global_stress": agree_stress,
                   "runtime_s": time.perf_counter() - t_start}, fh, indent=1, default=float)
    with open(RESULTS / "contact.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=["part", "path", "us_per_call", "us_min", "us_max", "note"])
        w.writeheader()
        for r in rows:
            w.writerow({**r, **{k: f"{r[k]:.4g}" for k in ("us_per_call", "us_min", "us_max")}})
    print(f"(written {RESULTS / 'contact.json'} and contact.csv; runtime {time.perf_counter() - t_start:.0f} s)")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plain-python", metavar="POSES_NPY", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.plain_python:
        plain_python_child(a.plain_python)
    else:
        main()
