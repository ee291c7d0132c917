"""Where the time of one wheel–rail contact call goes: the connector's compiled call profiled by stage.

The model: the RTRI case (20 m span, 250 km/h) with the ``default`` preset (RK44 at 1 ms, online contact search,
Kalker's exact theory by table), 4 wheelsets = 8 wheels.  Two sets of states:

* **at rest**: the initial state (wheelsets placed on the rails, t = 0), the warm start after a few calls: the
  steady case of a warm contact search;
* **dynamics**: every state the solver evaluated during the whole run (2.5 s, RK44 stages and the run monitor's
  evaluations), recorded with the kernel's warm start before each call (``--stride`` keeps every n-th).  Every
  timed call starts from its recorded warm start, so the search does the work it did in the run (including the
  rescans of a region that moved more than ``P_RESCAN_DISTANCE`` since its last scan).

Method: each stage runs in a numba loop over the states (no Python in between) and is timed on its own, with the
inputs the previous stages produced for that state (a first, untimed pass through the connector records them):

=====================  ===========================================================================================
``pose_irregularity``  :func:`~exudyn_wheelrail.multibody.connector_core.wheelset_poses` (rotation, roll/yaw and
                       their trigonometry, irregularity, deck state, pose relative to the rails)
``geometry``           the contact search of all wheels (``connector_core.contact_geometry``) minus ``hertz``
``hertz``              ``hertz_from_penetration`` for every loaded contact (the kernel calls it in the search)
``creepages``          per loaded contact: rails to track frame, yawed contact point, rail velocity, creepages
``creep_law``          ``creep_forces`` (the table) for every loaded contact
``assembly_results``   :func:`~exudyn_wheelrail.multibody.connector_core.wheel_forces` minus creepages and creep
                       law: force and torque assembly, result writing, rail forces and the bridge projection (no
                       bridge in this case: only its test); plus the clearing of the outputs in the core
``core_numba``         ``contact_forces_core`` in a numba loop (the sum of the above plus what lies between)
``dispatch_unboxing``  the same call from Python (the compiled entry ``forces()`` uses) minus ``core_numba``:
                       the unboxing of the arguments
``forces_wrapper``     ``WheelRailContact.forces`` minus the Python call of the core (input checks, bookkeeping)
``forces``             ``WheelRailContact.forces`` from Python: the cost of one contact call without Exudyn
=====================  ===========================================================================================

Timing: ``time.thread_time`` (CPU time of this thread: the machine is shared), the states split into chunks of
about 4 ms of work, each chunk repeated and its minimum kept; the restoring of the warm start (inside the timed
loops) is timed alone and subtracted.  All numbers are µs per contact call (8 wheels); the machine load
(``os.getloadavg``) is printed and stored before and after.

Run:  python benchmarks/bench_contact_stages.py [--stride 3] [--repeats 9]
Writes benchmarks/results/contact_stages.json.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numba
import numpy as np
from numba import njit

from exudyn_wheelrail.contact.creepage import creepages_core, yawed_contact_point_cs
from exudyn_wheelrail.contact.layout import (CP_V_MIN, F_A_REL, F_B_REL, F_NORMAL_FORCE, F_NR_Y, F_NR_Z,
                                             F_PENETRATION, F_PW_Y, F_PW_Z, F_STATUS, P_E_STAR, P_MIN_CURVATURE,
                                             P_RESCAN_DISTANCE, RES_A, RES_B, RES_ETA, RES_N, RES_PHI, RES_STATUS,
                                             RES_XI)
from exudyn_wheelrail.contact.normal import hertz_from_penetration
from exudyn_wheelrail.creep.registry import creep_forces
from exudyn_wheelrail.multibody.connector_core import (contact_forces_core, wheel_forces, wheel_geometry,
                                                       wheelset_poses)
from exudyn_wheelrail.multibody.core_data import (GEO_PARAMS, GEO_PATCH, GEO_TABLE, MODEL_CREEP, MODEL_GEOMETRY,
                                                  ST_DECK_STATE,
                                                  ST_OUT, ST_STATS, ST_WARM, V_E_AXLE, V_N_RAIL, V_OMEGA, V_OMEGA_RAIL,
                                                  V_P_CENTRE, V_P_CONTACT, V_V_CENTRE, V_V_RAIL, W_FRAME, W_GEOMETRY,
                                                  W_ROT, W_VEC, W_WHEELSET, WS_COS_ROLL, WS_COS_TH, WS_COS_YAW,
                                                  WS_SIN_ROLL, WS_SIN_TH, WS_SIN_YAW, WS_Y_RAIL, WS_Z_RAIL)
from exudyn_wheelrail.scenarios.rtri import RtriCase
from exudyn_wheelrail.multibody.direct_call import python_call_path
from exudyn_wheelrail.scenarios.scenario import build_scenario, run_model
from exudyn_wheelrail.simulation.presets import PRESETS
from exudyn_wheelrail.structures.deck_kinematics import rail_material_velocity, rail_pair_to_track

RESULTS = Path(__file__).resolve().parent / "results" / "contact_stages.json"
PRESET = "default"
CHUNK_S = 4e-3           # about this much work per timed chunk


def set_preset(name: str) -> None:
    """The preset of every model built from here on (``--preset``)."""
    global PRESET
    PRESET = name


def rtri_case() -> RtriCase:
    p = PRESETS[PRESET]
    return RtriCase(span_m=20.0, record=False, **p.run, **p.contact)


def record_run():
    """Every contact call of one RTRI run: (q, q_t, t, warm start before the call), and the run's status."""
    with python_call_path():                 # every call through c.forces, to be recorded
        h = build_scenario(rtri_case().scenario())
    c = h.contact
    calls = []
    forces = c.forces

    def recording(q, q_t, t):
        calls.append((np.array(q, dtype=float), np.array(q_t, dtype=float), float(t), c.save_warm_start()))
        return forces(q, q_t, t)
    c.forces = recording                     # the force user function and the monitor call c.forces
    outcome = run_model(h, progress=False)
    q, v, t, w = (np.array([x[i] for x in calls]) for i in range(4))
    return q, v, t, w, outcome.status.kind


# ---- the stages, each in a numba loop over states i0 .. i1-1 ------------------------------------------------------
@njit
def stage_restore(ws, warm, i0, i1):
    for i in range(i0, i1):
        warm[:] = ws[i]


@njit
def stage_core(qs, vs, ts, ws, warm, data, f, res, i0, i1):
    for i in range(i0, i1):
        warm[:] = ws[i]
        contact_forces_core(qs[i], vs[i], ts[i], data, f, res)


@njit
def stage_poses(qs, vs, ts, model, state, work, i0, i1):
    for i in range(i0, i1):
        wheelset_poses(qs[i], vs[i], ts[i], model, state, work)


@njit
def stage_geometry(sp_all, ws, warm, model, state, out_all, table, scratch, patch, i0, i1):
    stats = state[ST_STATS]
    for i in range(i0, i1):
        warm[:] = ws[i]
        wheel_geometry(model, sp_all[i], warm, out_all[i], stats, table, scratch, patch)


@njit
def stage_hertz(out_all, params, i0, i1):
    acc = 0.0
    for i in range(i0, i1):
        out = out_all[i]
        for w in range(out.shape[0]):
            for s in range(out.shape[1]):
                if out[w, s, F_STATUS] > 0:
                    n, dn, a, b, hs = hertz_from_penetration(out[w, s, F_A_REL], out[w, s, F_B_REL],
                                                             params[P_E_STAR], out[w, s, F_PENETRATION],
                                                             params[P_MIN_CURVATURE])
                    acc += n
    return acc


@njit
def stage_wheel_forces(qs, vs, model, state, work, out_all, rot_all, wsd_all, f, res, i0, i1):
    out = state[ST_OUT]
    for i in range(i0, i1):
        out[:] = out_all[i]
        work[W_ROT][:] = rot_all[i]
        work[W_WHEELSET][:] = wsd_all[i]
        f[:] = 0.0
        res[:] = 0.0
        wheel_forces(qs[i], vs[i], model, state, work, f, res)


@njit
def stage_copy_inputs(model, state, work, out_all, rot_all, wsd_all, f, res, i0, i1):
    """What :func:`stage_wheel_forces` does besides ``wheel_forces`` (subtracted)."""
    out = state[ST_OUT]
    for i in range(i0, i1):
        out[:] = out_all[i]
        work[W_ROT][:] = rot_all[i]
        work[W_WHEELSET][:] = wsd_all[i]
        f[:] = 0.0
        res[:] = 0.0


@njit
def stage_creepages(qs, vs, p_ref, out_all, rot_all, wsd_all, deck_state, vec, frame, v_min, i0, i1):
    """The creepage part of :func:`wheel_forces`, with its per-wheelset inputs."""
    acc = 0.0
    pc = vec[V_P_CONTACT]
    nr = vec[V_N_RAIL]
    e_axle = vec[V_E_AXLE]
    p_centre = vec[V_P_CENTRE]
    v_centre = vec[V_V_CENTRE]
    omega = vec[V_OMEGA]
    v_rail = vec[V_V_RAIL]
    omega_rail = vec[V_OMEGA_RAIL]
    for i in range(i0, i1):
        q = qs[i]
        q_t = vs[i]
        out = out_all[i]
        for k in range(p_ref.shape[0]):
            o = 6 * k
            R = rot_all[i, k]
            wk = wsd_all[i, k]
            ds = deck_state[k]
            for j in range(3):
                e_axle[j] = R[j, 1]
                p_centre[j] = p_ref[k, j] + q[o + j]
                v_centre[j] = q_t[o + j]
                omega[j] = R[j, 0] * q_t[o + 3] + R[j, 1] * q_t[o + 4] + R[j, 2] * q_t[o + 5]
            for side in range(2):
                w = 2 * k + side
                mirror = 1.0 if side == 0 else -1.0
                for reg in range(out.shape[1]):
                    ow = out[w, reg]
                    if ow[F_STATUS] <= 0:
                        continue
                    y_t, z_t, ny, nz = rail_pair_to_track(mirror * ow[F_PW_Y], ow[F_PW_Z], mirror * ow[F_NR_Y],
                                                          ow[F_NR_Z], wk[WS_Y_RAIL], wk[WS_Z_RAIL], wk[WS_COS_TH],
                                                          wk[WS_SIN_TH])
                    x_c, y_c, z_c, _, ok = yawed_contact_point_cs(y_t, z_t, ny, nz, p_centre[0], p_centre[1],
                                                                   p_centre[2], wk[WS_COS_ROLL], wk[WS_SIN_ROLL],
                                                                   wk[WS_COS_YAW], wk[WS_SIN_YAW])
                    pc[0] = x_c
                    pc[1] = y_c
                    pc[2] = z_c
                    nr[0] = 0.0
                    nr[1] = ny
                    nr[2] = nz
                    rail_material_velocity(y_c, z_c, 0.0, 0.0, ds, v_rail)
                    xi, eta, phi, V, cstat = creepages_core(pc, nr, e_axle, p_centre, v_centre, omega, v_rail,
                                                             omega_rail, v_min, frame)
                    acc += xi
    return acc


@njit
def stage_creep_law(res_all, creep, i0, i1):
    law, cp, t_nodes, coef, tab = creep
    acc = 0.0
    for i in range(i0, i1):
        res = res_all[i]
        for w in range(res.shape[0]):
            for s in range(res.shape[1]):
                rr = res[w, s]
                if rr[RES_STATUS] > 0:
                    Fx, Fy, Mz, fl = creep_forces(law, rr[RES_A], rr[RES_B], rr[RES_XI], rr[RES_ETA], rr[RES_PHI],
                                                  rr[RES_N], cp, t_nodes, coef, tab)
                    acc += Fx
    return acc


# ---- timing -------------------------------------------------------------------------------------------------------
def interleaved_us(stages: dict, n_states: int, repeats: int) -> dict:
    """µs per state of every ``stages[name](i0, i1)``: the states in chunks of about ``CHUNK_S`` of the costliest
    stage's work; per chunk the stages run in turn, ``repeats`` rounds (a load change hits all alike), each timed
    over enough passes for about ``CHUNK_S`` and its minimum kept."""
    probe = {}
    for name, fn in stages.items():
        fn(0, n_states)                                       # compile, caches
        t0 = time.thread_time()
        fn(0, n_states)
        probe[name] = max(time.thread_time() - t0, 1e-7) / n_states
    chunk = max(1, min(n_states, int(CHUNK_S / max(probe.values()))))
    passes = {name: max(1, int(CHUNK_S / (probe[name] * chunk))) for name in stages}
    total = dict.fromkeys(stages, 0.0)
    for i0 in range(0, n_states, chunk):
        i1 = min(i0 + chunk, n_states)
        best = dict.fromkeys(stages, math.inf)
        for _ in range(repeats):
            for name, fn in stages.items():
                t0 = time.thread_time()
                for _ in range(passes[name]):
                    fn(i0, i1)
                best[name] = min(best[name], (time.thread_time() - t0) / passes[name])
        for name in stages:
            total[name] += best[name]
    return {name: total[name] / n_states * 1e6 for name in stages}


def stage_inputs(c, qs, vs, ts, ws) -> tuple:
    """An untimed pass through the connector ``c``: every stage's inputs for every state, ``(out_all, res_all,
    sp_all, wsd_all, rot_all)`` — the kernel's output, the results, the side poses, the wheelset data, the
    rotations."""
    n = len(ts)
    state, work = c._state, c._work
    warm, out = state[ST_WARM], state[ST_OUT]
    out_all = np.empty((n,) + out.shape)
    res_all = np.empty((n,) + c.results.shape)
    sp_all = np.empty((n,) + c._side_poses.shape)
    wsd_all = np.empty((n,) + work[W_WHEELSET].shape)
    rot_all = np.empty((n,) + work[W_ROT].shape)
    for i in range(n):
        warm[...] = ws[i]
        c.forces(qs[i], vs[i], ts[i])
        out_all[i] = out
        res_all[i] = c.results
        sp_all[i] = c._side_poses
        wsd_all[i] = work[W_WHEELSET]
        rot_all[i] = work[W_ROT]
    return out_all, res_all, sp_all, wsd_all, rot_all


def profile(c, qs, vs, ts, ws, repeats: int, inputs: tuple) -> dict:
    """Stage costs (µs per call) of the connector ``c`` over the states (module docstring); ``inputs`` those of
    :func:`stage_inputs` for the same states."""
    n = len(ts)
    model, state, work, data = c._model, c._state, c._work, c._data
    warm = state[ST_WARM]
    f, res = c._f, c.results
    out_all, res_all, sp_all, wsd_all, rot_all = inputs
    out_tmp = np.empty_like(out_all)
    params = model[MODEL_GEOMETRY][GEO_PARAMS]
    table = model[MODEL_GEOMETRY][GEO_TABLE]
    patch = model[MODEL_GEOMETRY][GEO_PATCH]
    v_min = c.cp[CP_V_MIN]
    stages = {
        "restore": lambda a, b: stage_restore(ws, warm, a, b),
        "core_numba": lambda a, b: stage_core(qs, vs, ts, ws, warm, data, f, res, a, b),
        "pose_irregularity": lambda a, b: stage_poses(qs, vs, ts, model, state, work, a, b),
        "geometry_hertz": lambda a, b: stage_geometry(sp_all, ws, warm, model, state, out_tmp, table,
                                                      work[W_GEOMETRY], patch, a, b),
        "hertz": lambda a, b: stage_hertz(out_all, params, a, b),
        "creepages": lambda a, b: stage_creepages(qs, vs, c.p_ref, out_all, rot_all, wsd_all, state[ST_DECK_STATE],
                                                  work[W_VEC], work[W_FRAME], v_min, a, b),
        "creep_law": lambda a, b: stage_creep_law(res_all, model[MODEL_CREEP], a, b),
        "copies": lambda a, b: stage_copy_inputs(model, state, work, out_all, rot_all, wsd_all, f, res, a, b),
        "stage3": lambda a, b: stage_wheel_forces(qs, vs, model, state, work, out_all, rot_all, wsd_all, f, res, a,
                                                  b),
        "py_restore": lambda a, b: _py_restore(warm, ws, a, b),
        "core_python": lambda a, b: _py_core(c, warm, qs, vs, ts, ws, a, b),
        "forces_python": lambda a, b: _py_forces(c, warm, qs, vs, ts, ws, a, b),
    }
    t = interleaved_us(stages, n, repeats)
    r = {}
    r["pose_irregularity"] = t["pose_irregularity"]
    geometry_hertz = t["geometry_hertz"] - t["restore"]
    r["hertz"] = t["hertz"]
    r["geometry"] = geometry_hertz - t["hertz"]
    r["creepages"] = t["creepages"]
    r["creep_law"] = t["creep_law"]
    stage3 = t["stage3"] - t["copies"]
    r["assembly_results"] = stage3 - t["creepages"] - t["creep_law"]
    r["core_numba"] = t["core_numba"] - t["restore"]
    r["between_stages"] = r["core_numba"] - (t["pose_irregularity"] + geometry_hertz + stage3)
    core_py = t["core_python"] - t["py_restore"]
    r["forces"] = t["forces_python"] - t["py_restore"]
    r["dispatch_unboxing"] = core_py - r["core_numba"]
    r["forces_wrapper"] = r["forces"] - core_py
    r["loaded_contacts_per_call"] = float(np.mean(np.sum(res_all[:, :, :, RES_STATUS] > 0, axis=(1, 2))))
    return r


def _py_restore(warm, ws, i0, i1):
    for i in range(i0, i1):
        warm[...] = ws[i]


def _py_core(c, warm, qs, vs, ts, ws, i0, i1):
    core, data, f, res = c._forces_core, c._data, c._f, c.results     # the compiled call forces() makes
    for i in range(i0, i1):
        warm[...] = ws[i]
        core(qs[i], vs[i], ts[i], data, f, res)


def _py_forces(c, warm, qs, vs, ts, ws, i0, i1):
    forces = c.forces
    for i in range(i0, i1):
        warm[...] = ws[i]
        forces(qs[i], vs[i], ts[i])


STAGES = ("pose_irregularity", "geometry", "hertz", "creepages", "creep_law", "assembly_results", "between_stages",
          "core_numba", "dispatch_unboxing", "forces_wrapper", "forces")


def _git_rev() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              cwd=Path(__file__).resolve().parent, check=False).stdout.strip()
    except OSError:
        return ""


def rescan_effect(c, ws, sp_all) -> dict:
    """What the rescans change: the geometry search of every state (side poses ``sp_all`` of :func:`stage_inputs`)
    from its recorded warm start ``ws``, once as in the run and once with rescans off (a rescan distance of 1 m); the
    share of the wheel-calls whose outputs differ at all and whose total normal force (all slots) differs by more
    than 1e-9, 1e-3, 1e-2 relative, and the largest."""
    model, state = c._model, c._state
    warm = state[ST_WARM]
    scratch = c._work[W_GEOMETRY]
    n = len(ws)
    params = model[MODEL_GEOMETRY][GEO_PARAMS]
    table = model[MODEL_GEOMETRY][GEO_TABLE]
    patch = model[MODEL_GEOMETRY][GEO_PATCH]
    outs = []
    distance = params[..., P_RESCAN_DISTANCE].copy()
    for d in (distance, 1.0):
        params[..., P_RESCAN_DISTANCE] = d
        o = np.empty((n,) + state[ST_OUT].shape)
        stage_geometry(sp_all, ws, warm, model, state, o, table, scratch, patch, 0, n)
        outs.append(o)
    params[..., P_RESCAN_DISTANCE] = distance
    a, b = (np.nansum(o[..., F_NORMAL_FORCE], axis=2) for o in outs)
    rel = np.abs(a - b) / np.maximum(np.abs(a), 1.0)
    return {"wheel_calls": int(rel.size), "any_output_differs": float(np.mean(np.any(outs[0] != outs[1], axis=(2, 3)))),
            **{f"normal_force_differs_above_{t:g}": float(np.mean(rel > t)) for t in (1e-9, 1e-3, 1e-2)},
            "largest_relative_difference": float(np.nanmax(rel))}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--stride", type=int, default=3, help="keep every n-th recorded call of the run (default 3)")
    ap.add_argument("--repeats", type=int, default=9, help="repeats of every timed chunk (minimum kept)")
    ap.add_argument("--rest-calls", type=int, default=200, help="calls at rest (the same state repeated)")
    ap.add_argument("--preset", default="default", choices=sorted(PRESETS), help="the run's preset (default: default)")
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args(argv)
    set_preset(args.preset)
    load_before = os.getloadavg()
    print(f"load before: {load_before[0]:.2f} {load_before[1]:.2f} {load_before[2]:.2f}", flush=True)
    qs, vs, ts, ws, status = record_run()
    n_recorded = len(ts)
    sel = slice(0, None, args.stride)
    qs, vs, ts, ws = (np.ascontiguousarray(a[sel]) for a in (qs, vs, ts, ws))
    h = build_scenario(rtri_case().scenario())
    c = h.contact
    q0, v0 = c.coordinates(h.mbs)
    for _ in range(5):
        c.forces(q0, v0, 0.0)
    m = args.rest_calls
    rest_states = (np.repeat(q0[None], m, 0), np.repeat(v0[None], m, 0), np.zeros(m),
                   np.repeat(c.save_warm_start()[None], m, 0))
    rest = profile(c, *rest_states, args.repeats, stage_inputs(c, *rest_states))
    inputs = stage_inputs(c, qs, vs, ts, ws)
    dynamics = profile(c, qs, vs, ts, ws, args.repeats, inputs)
    rescans = rescan_effect(c, ws, inputs[2])
    print("what the rescans change (per wheel-call): " + ", ".join(f"{k} {v:.4g}" for k, v in rescans.items()))
    load_after = os.getloadavg()
    rows = [f"| {k} | {rest[k]:.2f} | {dynamics[k]:.2f} |" for k in STAGES]
    print("\n| stage | at rest [µs] | dynamics [µs] |\n|---|---:|---:|\n" + "\n".join(rows))
    print(f"loaded contacts per call: at rest {rest['loaded_contacts_per_call']:.2f}, dynamics "
          f"{dynamics['loaded_contacts_per_call']:.2f}; states: {len(ts)} of {n_recorded} recorded calls "
          f"(run status {status})")
    print(f"load after: {load_after[0]:.2f} {load_after[1]:.2f} {load_after[2]:.2f}")
    result = {
        "benchmark": "contact call by stage (benchmarks/bench_contact_stages.py)",
        "case": f"RTRI 20 m, 250 km/h, preset {PRESET!r} ({PRESETS[PRESET].run}, {PRESETS[PRESET].contact}), "
                "4 wheelsets",
        "units": "µs per contact call (8 wheels), CPU time of the thread, chunk minimum",
        "rest": rest, "dynamics": dynamics, "rescan_effect": rescans,
        "states": {"dynamics": len(ts), "recorded_calls": n_recorded, "stride": args.stride, "run_status": status,
                   "rest_calls": m},
        "load_before": list(load_before), "load_after": list(load_after),
        "machine": {"cpu": platform.processor() or platform.machine(), "logical_cpus": os.cpu_count(),
                    "python": sys.version.split()[0], "numba": numba.__version__, "numpy": np.__version__},
        "git": _git_rev(),
    }
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(result, indent=1))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
