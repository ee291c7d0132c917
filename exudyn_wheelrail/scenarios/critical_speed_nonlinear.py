r"""Constant-speed runs of the full nonlinear model after a lateral disturbance: does a limit cycle persist, and how
large is it (:func:`limit_cycle_run`)?

Each run is a scenario of the ``run`` command (:func:`~.run.run_scenario`): the vehicle on straight rigid track with
one lateral alignment defect of both rails — a 1 − cos bump :data:`~.critical_speed_defaults.BUMP_DEPTH_M` deep and
:data:`~.critical_speed_defaults.BUMP_LENGTH_M` long, :data:`~.critical_speed_defaults.BUMP_POSITION_M` ahead of the
leading wheelset (``track`` type ``defect``, ``shape = "bump"``, ``direction = "lateral"``) — over
:data:`~.critical_speed_defaults.RUN_DISTANCE_M`, with the full contact (profiles, Hertz, the creep table).  From
the recorded lateral displacement of every wheelset relative to its rails (``y_rel_w<j>_m``) against the distance
run, the limit-cycle amplitude is half the peak-to-peak over the last
:data:`~.critical_speed_defaults.CYCLE_WINDOW_M`, and the cycle persists when it is at least
:data:`~.critical_speed_defaults.PERSIST_AMPLITUDE_M` and the trend of the last
:data:`~.critical_speed_defaults.TREND_WINDOWS` windows' amplitudes decays no faster than a mode of damping ratio
:data:`~.critical_speed_defaults.PERSIST_DAMPING_RATIO` (:func:`~exudyn_wheelrail.analysis.stability.limit_cycle`).  A run that derails is an unbounded oscillation (it persists); a run that diverges or has its step
rejected is no answer (``limit_cycle`` None, its status kept: the analysis reports it and leaves the speed out).  The
same scenario runs with ``python -m exudyn_wheelrail run`` (:func:`disturbance_scenario` gives it).
"""
from __future__ import annotations

import time

import numpy as np

from ..analysis.stability import limit_cycle, window_amplitudes, zero_crossing_frequency_hz
from ..rolling_stock.vehicle_data import load_vehicle
from ..simulation.status import DERAILED, OK
from .critical_speed_defaults import (BRANCH_WINDOW_M, BUMP_DEPTH_M, BUMP_LENGTH_M, BUMP_POSITION_M, CYCLE_WINDOW_M,
                                      MIN_RUN_DURATION_S, PERSIST_AMPLITUDE_M, PERSIST_DAMPING_RATIO, RUN_DISTANCE_M,
                                      RUN_DT_S, RUN_SOLVER, TREND_WINDOWS)
from .critical_speed_linear import vehicle_entry
from .run import run_scenario

__all__ = ["disturbance_scenario", "limit_cycle_run", "bump_component", "disturbance_passed_m"]


def bump_component(depth_m: float = BUMP_DEPTH_M, length_m: float = BUMP_LENGTH_M,
                   position_m: float = BUMP_POSITION_M) -> dict:
    """The lateral disturbance as a scenario ``[[track]]`` component."""
    return {"type": "defect", "shape": "bump", "position_m": float(position_m), "length_m": float(length_m),
            "depth_m": float(depth_m), "rail": "both", "direction": "lateral"}


def disturbance_passed_m(wheelset_x_m) -> list:
    """Per wheelset (``wheelset_x_m``: the vehicle's x positions, front first), the distance run at which it has
    passed the bump: the bump's end plus its distance behind the front wheelset."""
    return [BUMP_POSITION_M + BUMP_LENGTH_M + (wheelset_x_m[0] - x) for x in wheelset_x_m]


def disturbance_scenario(vehicle: str, speed_kmh: float, depth_m: float = BUMP_DEPTH_M,
                         distance_m: float = RUN_DISTANCE_M) -> dict:
    """The scenario of one constant-speed run after the lateral disturbance (module docstring)."""
    duration = max(distance_m / (speed_kmh / 3.6), MIN_RUN_DURATION_S)
    return {"schema_version": 2, "scenario": {"name": f"stability_{speed_kmh:g}kmh"},
            "vehicle": {**vehicle_entry(vehicle), "speed_km_h": float(speed_kmh)},
            "track": [bump_component(depth_m)],
            "run": {"duration_s": duration, "solver": RUN_SOLVER, "dt_s": RUN_DT_S},
            "outputs": {"timeseries": ["wheelset_lateral", "flange"], "plots": False, "criteria": False,
                        "formats": ["npz"]}}


def limit_cycle_run(vehicle: str, speed_kmh: float, depth_m: float = BUMP_DEPTH_M,
                    distance_m: float = RUN_DISTANCE_M) -> dict:
    """One run (module docstring); a plain dict: ``speed_kmh``, ``status`` (the run's), ``amplitude_m`` (per
    wheelset, front first), ``persists`` (per wheelset), ``frequency_hz`` (of a persisting cycle, from the zero
    crossings over the last window; NaN otherwise), ``trend_damping_ratio`` (per wheelset, the equivalent damping ratio of
    the amplitude's trend: negative when it grows), ``limit_cycle`` (any wheelset's persists; None when the run diverged or had its step rejected),
    ``flange_contact`` (in the last window), ``seconds`` (build and solve), ``simulated_s``, and per wheelset the
    history: ``window_start_m`` (the distance run where the wheelset has passed the disturbance) and
    ``window_amplitude_m`` (the amplitude over consecutive windows of
    :data:`~.critical_speed_defaults.BRANCH_WINDOW_M` from there, up to the run's end or derailment).  A run that
    derails counts as a persisting (unbounded) oscillation with NaN amplitudes.  Runs in a worker process."""
    t0 = time.perf_counter()
    scn = disturbance_scenario(vehicle, speed_kmh, depth_m, distance_m)
    res = run_scenario(scn, None, progress=False)
    status = res.summary["status"]
    ts = res.timeseries
    s = ts["time_s"] * speed_kmh / 3.6
    cols = sorted((c for c in ts if c.startswith("y_rel_w")), key=lambda c: int(c[len("y_rel_w"):-len("_m")]))
    amps, ratios, persist, freq = [], [], [], []
    last = s >= np.nanmax(s) - CYCLE_WINDOW_M if len(s) else np.zeros(0, dtype=bool)
    for c in cols:
        a, r, p = limit_cycle(s, ts[c], CYCLE_WINDOW_M, TREND_WINDOWS, PERSIST_AMPLITUDE_M, PERSIST_DAMPING_RATIO)
        amps.append(a)
        ratios.append(r)
        persist.append(p)
        freq.append(zero_crossing_frequency_hz(ts["time_s"][last], ts[c][last]) if p else float("nan"))
    flange = [c for c in ts if c.startswith("flange_")]
    start = disturbance_passed_m(load_vehicle(vehicle).wheelset_x_m())           # front first, as the columns
    history = [window_amplitudes(s, ts[c], s0, BRANCH_WINDOW_M) if len(s) else [] for c, s0 in zip(cols, start)]
    if status != OK:                     # derailed: unbounded; diverged, step rejected: no answer
        amps = freq = ratios = [float("nan")] * len(cols)
        persist = [True if status == DERAILED else None] * len(cols)
    limit = True if status == DERAILED else bool(any(persist)) if status == OK else None
    return {"speed_kmh": float(speed_kmh), "status": status, "amplitude_m": amps, "persists": persist,
            "trend_damping_ratio": ratios, "frequency_hz": freq,
            "limit_cycle": limit,
            "flange_contact": bool(any(np.any(ts[c][last] > 0.5) for c in flange)),
            "seconds": time.perf_counter() - t0, "simulated_s": float(ts["time_s"][-1]) if len(s) else 0.0,
            "disturbance_depth_m": float(depth_m), "window_start_m": start, "window_amplitude_m": history}
