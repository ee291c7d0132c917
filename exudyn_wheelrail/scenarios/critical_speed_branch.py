r"""The unstable branch of the bifurcation diagram: the limit cycle between the centred running state and the stable
cycle, found by bisecting the disturbance at constant speed (:func:`unstable_cycle`, :func:`unstable_branch`).

Between the nonlinear and the linear critical speed the centred running state is stable to small disturbances while
a stable limit cycle exists beside it (a subcritical bifurcation): an unstable limit cycle separates the states that
return to the centre from those that reach the stable cycle.  At a speed in that interval the runs of the full model
after the lateral bump (the nonlinear runs' disturbance, :mod:`.critical_speed_nonlinear`) decay for a bump shallower
than a threshold and reach the stable cycle for a deeper one.  The depth is bisected geometrically between
:data:`~.critical_speed_defaults.BRANCH_MIN_DEPTH_M` and :data:`~.critical_speed_defaults.BUMP_DEPTH_M` until the
bracketing depths differ by at most :data:`~.critical_speed_defaults.BRANCH_DEPTH_RATIO` (a deepest run without an
answer — a step rejected in flange contact — is tried again at half the depth, up to
:data:`~.critical_speed_defaults.BRANCH_TOP_HALVINGS` times); each run is judged by the nonlinear runs' rule
(:func:`~.critical_speed_nonlinear.limit_cycle_run`).  The two bracketing runs start close to
the unstable cycle's stable manifold, on either side: both approach the cycle, linger near it and then part — one
decays, the other grows.  The unstable cycle's amplitude per wheelset is read where they linger
(:func:`~exudyn_wheelrail.analysis.stability.linger_amplitude`: of the windows of
:data:`~.critical_speed_defaults.BRANCH_WINDOW_M` after the wheelset has passed the bump in which the two runs are
within :data:`~.critical_speed_defaults.BRANCH_LINGER_RATIO` of each other, the one where both change least; the
geometric mean of the two there).

What this estimate is: an amplitude of the motion near the unstable cycle, measured the way the stable branch is
(half the peak-to-peak lateral displacement of each wheelset relative to its rails over a window), good to the
distance the two runs still have from the cycle where they linger (a few per cent near the linear critical speed,
more where the cycle is strongly unstable and the runs leave it quickly).  Where the deepest bump decays or the
shallowest persists, or a run gives no answer, no unstable cycle is reported at that speed (the note says why).
"""
from __future__ import annotations

import math
import time

import numpy as np

from ..analysis.stability import linger_amplitude
from .critical_speed_defaults import (BRANCH_DEPTH_RATIO, BRANCH_LINGER_RATIO, BRANCH_MIN_DEPTH_M, BRANCH_POINTS,
                                      BRANCH_TOP_HALVINGS, BRANCH_WINDOW_M, BUMP_DEPTH_M)
from .critical_speed_nonlinear import limit_cycle_run
from .sweep import SerialExecutor, run_tasks

__all__ = ["unstable_cycle", "unstable_branch", "branch_speeds"]


def _not_found(speed_kmh: float, note: str, runs: int, t0: float | None) -> dict:
    """A speed without an unstable cycle: why (``note``), after how many runs, since ``t0`` (None: no time)."""
    return {"speed_kmh": float(speed_kmh), "found": False, "amplitude_m": [], "depth_bracket_m": None,
            "note": note, "runs": runs, "seconds": None if t0 is None else time.perf_counter() - t0}


def unstable_cycle(vehicle: str, speed_kmh: float) -> dict:
    """The unstable limit cycle at ``speed_kmh`` (module docstring); a plain dict: ``speed_kmh``, ``found``,
    ``amplitude_m`` (per wheelset, front first; NaN where the runs part before a window ends),
    ``depth_bracket_m`` (the last bracket of the bump's depth), ``window_m`` (per wheelset, where the runs linger:
    start and end of the window, distance run; None), ``stable_amplitude_m`` (the stable cycle's amplitude per
    wheelset: the deepest run's, where it ends), ``note``, ``runs`` (how many), ``seconds``.  Runs in a worker
    process."""
    t0 = time.perf_counter()
    runs = 0
    for halvings in range(BRANCH_TOP_HALVINGS + 1):        # a deep kick may end in a run without an answer
        deep = limit_cycle_run(vehicle, speed_kmh, BUMP_DEPTH_M / 2 ** halvings)
        runs += 1
        if deep["limit_cycle"] is not None:
            break
    top = deep                              # the deepest run with an answer: the stable cycle's amplitude
    if deep["limit_cycle"] is not True:
        what = "gives no answer" if deep["limit_cycle"] is None else "decays"
        return _not_found(speed_kmh, f"the {1e3 * deep['disturbance_depth_m']:g} mm disturbance {what} "
                                     f"({deep['status']})", runs, t0)
    shallow = limit_cycle_run(vehicle, speed_kmh, BRANCH_MIN_DEPTH_M)
    runs += 1
    if shallow["limit_cycle"] is not False:
        what = "gives no answer" if shallow["limit_cycle"] is None else "persists"
        return _not_found(speed_kmh, f"the {1e3 * BRANCH_MIN_DEPTH_M:.3g} mm disturbance {what} "
                                     f"({shallow['status']})", runs, t0)
    while deep["disturbance_depth_m"] / shallow["disturbance_depth_m"] > BRANCH_DEPTH_RATIO:
        r = limit_cycle_run(vehicle, speed_kmh, math.sqrt(deep["disturbance_depth_m"] * shallow["disturbance_depth_m"]))
        runs += 1
        if r["limit_cycle"] is None:
            return _not_found(speed_kmh, f"a run of the bisection ended {r['status']}", runs, t0)
        if r["limit_cycle"]:
            deep = r
        else:
            shallow = r
    amps, windows = [], []
    for d, p, w in zip(shallow["window_amplitude_m"], deep["window_amplitude_m"], deep["window_start_m"]):
        k, a = linger_amplitude(d, p, BRANCH_LINGER_RATIO)
        amps.append(a)
        windows.append(None if k is None else [w + k * BRANCH_WINDOW_M, w + (k + 1) * BRANCH_WINDOW_M])
    if all(w is None for w in windows):
        return _not_found(speed_kmh, "the bracketing runs part before their first common window ends", runs, t0)
    return {"speed_kmh": float(speed_kmh), "found": True, "amplitude_m": amps,
            "depth_bracket_m": [shallow["disturbance_depth_m"], deep["disturbance_depth_m"]],
            "window_m": windows, "stable_amplitude_m": top["amplitude_m"], "note": None, "runs": runs,
            "seconds": time.perf_counter() - t0}


def branch_speeds(nonlinear_kmh, linear_kmh, hi_kmh: float) -> list:
    """The speeds of the unstable branch: :data:`~.critical_speed_defaults.BRANCH_POINTS` evenly spaced strictly
    between the nonlinear and the linear critical speed (the range's upper end when the linear one lies above it);
    none without a nonlinear critical speed below the linear one; rounded to 0.1 km/h, without duplicates."""
    if nonlinear_kmh is None:
        return []
    top = min(linear_kmh, hi_kmh) if linear_kmh is not None else hi_kmh
    if top <= nonlinear_kmh:
        return []
    step = (top - nonlinear_kmh) / (BRANCH_POINTS + 1)
    speeds = {round(nonlinear_kmh + k * step, 1) for k in range(1, BRANCH_POINTS + 1)}     # 0.1 km/h: printable
    return sorted(v for v in speeds if nonlinear_kmh < v < top)


def unstable_branch(vehicle: str, speeds, workers, progress=None) -> dict:
    """:func:`unstable_cycle` at every speed of ``speeds`` in parallel (``workers`` processes, 1: in this process);
    speed -> result.  A speed without an answer (its runs failed, its worker died) is an entry with ``found`` False
    and a note: the branch is reported where found, and the analysis's ``status`` concerns the critical speeds."""
    progress = progress or (lambda text: None)
    speeds = [float(v) for v in speeds]
    out = {}

    def done(i, r):
        out[speeds[i]] = r
        progress(f"unstable branch [{len(out)}/{len(speeds)}] {speeds[i]:.1f} km/h: "
                 + (f"{1e3 * np.nanmax(r['amplitude_m']):.3f} mm" if r["found"] and np.isfinite(r["amplitude_m"]).any()
                    else str(r["note"])))

    def failed(i, text):
        return _not_found(speeds[i], text, 0, None)
    executor = SerialExecutor() if workers == 1 else None
    run_tasks(executor, workers, unstable_cycle, [(vehicle, v) for v in speeds], done, failed)
    return out
