"""The cost of the non-Hertzian patch in the dynamics: the connector's compiled call with the patch against the same
call with Hertz, on the same states.

States: every contact call of one RTRI run (20 m span, 250 km/h, ``--preset``, Hertz), recorded with the kernel's
warm start before each call (``bench_contact_stages.record_run``; ``--stride`` keeps every n-th).  Both connectors
(``contact_patch="hertz"`` and ``"non-hertzian"``, otherwise the same model) evaluate every state from its recorded
warm start in a numba loop (``bench_contact_stages.stage_core``), interleaved in ``--rounds`` rounds; the CPU time of
the thread (``time.thread_time``), the minimum per round kept.  Reported: µs per call (8 wheels) of each, their
ratio, and the contacts per call that carry the patch (``FLAG_PATCH``) or fell back to Hertz
(``FLAG_PATCH_FAILED``).  The machine's load before and after.

The table's answers against the patch solved online, on the same states: every wheel of every state, the kernel's
output (the Hertz connector's) passed once through the table (``patch_table.patch_tabulated``) and once through the
pass (``patch_pass.patch_wheels``); the wheel's normal force (the sum of its contacts') compared: median, 99th,
99.9th percentile and worst relative error, and the share of wheel evaluations the table sends online (its answer
then is the pass's, bit for bit).

Run:  python benchmarks/bench_patch_cost.py [--stride 3] [--rounds 5] [--preset default]
Writes benchmarks/results/patch_cost.json.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from exudyn_wheelrail.contact.kernel import FLAG_PATCH, FLAG_PATCH_FAILED
from exudyn_wheelrail.contact.patch_pass import patch_params, patch_wheels
from exudyn_wheelrail.contact.patch_table import patch_tabulated
from exudyn_wheelrail.contact.layout import F_FLAGS, F_NORMAL_FORCE, F_STATUS
from exudyn_wheelrail.multibody.core_data import ST_OUT, ST_SIDE_POSES, ST_WARM
from exudyn_wheelrail.scenarios.build import build_scenario
from exudyn_wheelrail.simulation.presets import PRESETS

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_contact_stages as stages  # noqa: E402

HERE = Path(__file__).resolve().parent


def connector(contact_patch: str):
    case = stages.rtri_case()
    case = type(case)(span_m=case.span_m, record=False, run=case.run,
                      contact=case.contact.__class__(**{**case.contact.as_dict(),
                                                        "fastsim_grid": tuple(case.contact.fastsim_grid),
                                                        "contact_patch": contact_patch}))
    return build_scenario(case.scenario()).contact


def time_calls(c, qs, vs, ts, ws) -> float:
    """CPU µs per call of the compiled core over the states (one pass, after a warm-up pass)."""
    warm = c._state[ST_WARM]
    stages.stage_core(qs, vs, ts, ws, warm, c._data, c._f, c.results, 0, min(len(ts), 20))
    t = time.thread_time()
    stages.stage_core(qs, vs, ts, ws, warm, c._data, c._f, c.results, 0, len(ts))
    return (time.thread_time() - t) / len(ts) * 1e6


def patch_counts(c, qs, vs, ts, ws) -> dict:
    warm = c._state[ST_WARM]
    out = c._state[ST_OUT]
    patched = failed = loaded = 0
    for i in range(len(ts)):
        stages.stage_core(qs, vs, ts, ws, warm, c._data, c._f, c.results, i, i + 1)
        live = (out[..., F_STATUS] > 0) & (out[..., F_NORMAL_FORCE] > 0)
        flags = out[..., F_FLAGS].astype(np.int64)
        loaded += int(live.sum())
        patched += int((live & (flags & FLAG_PATCH > 0)).sum())
        failed += int((flags & FLAG_PATCH_FAILED > 0).sum())
    n = len(ts)
    return {"loaded_contacts_per_call": loaded / n, "patch_contacts_per_call": patched / n,
            "patch_failures_per_call": failed / n}


def wheel_force(rows) -> float:
    live = (rows[:, F_STATUS] > 0) & (rows[:, F_NORMAL_FORCE] > 0)
    return float(rows[live, F_NORMAL_FORCE].sum())


def table_against_online(hertz, patch, qs, vs, ts, ws) -> dict:
    """The table's answer against the pass solved online for every wheel of every state (module docstring)."""
    kc = patch._kc
    par, data, slots = patch.patch_table.arrays()
    work = patch_params()
    out, poses = hertz._state[ST_OUT], hertz._state[ST_SIDE_POSES]
    errors, online = [], 0
    for i in range(len(ts)):
        stages.stage_core(qs, vs, ts, ws, hertz._state[ST_WARM], hertz._data, hertz._f, hertz.results, i, i + 1)
        for w in range(poses.shape[0]):
            one = slice(w, w + 1)
            tab, direct = out[one].copy(), out[one].copy()
            patch_tabulated(par, data, slots, kc.nodes, kc.meta, kc.curve_ids[one], poses[one], kc.params, tab, work)
            patch_wheels(kc.nodes, kc.meta, kc.curve_ids[one], poses[one], kc.params, direct, work)
            online += int(np.array_equal(tab, direct))
            errors.append(abs(wheel_force(tab[0]) / wheel_force(direct[0]) - 1.0))
    e = np.array(errors)
    return {"wheel_evaluations": len(e), "solved_online": online,
            "table_vs_online_wheel_force": dict(zip(("median", "p99", "p99_9", "max"),
                                                    (float(v) for v in np.percentile(e, [50, 99, 99.9, 100]))))}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--stride", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--preset", default="default", choices=sorted(PRESETS))
    ap.add_argument("--out", default=str(HERE / "results" / "patch_cost.json"))
    args = ap.parse_args(argv)
    stages.set_preset(args.preset)
    load_before = os.getloadavg()
    qs, vs, ts, ws, status = stages.record_run()
    sel = slice(0, None, args.stride)
    qs, vs, ts, ws = (np.ascontiguousarray(a[sel]) for a in (qs, vs, ts, ws))
    hertz, patch = connector("hertz"), connector("non-hertzian")
    times = {"hertz": [], "non-hertzian": []}
    for _ in range(args.rounds):
        for name, c in (("hertz", hertz), ("non-hertzian", patch)):
            times[name].append(time_calls(c, qs, vs, ts, ws))
    counts = patch_counts(patch, qs, vs, ts, ws)
    accuracy = table_against_online(hertz, patch, qs, vs, ts, ws)
    best = {k: min(v) for k, v in times.items()}
    load_after = os.getloadavg()
    result = dict(case=f"RTRI 20 m, 250 km/h, preset {args.preset}, states of the Hertz run (status {status})",
                  states=len(ts), us_per_call=best, rounds=times, ratio=best["non-hertzian"] / best["hertz"],
                  **counts, **accuracy, load_before=list(load_before), load_after=list(load_after))
    print(f"{len(ts)} states; hertz {best['hertz']:.1f} us, non-hertzian {best['non-hertzian']:.1f} us per call: "
          f"ratio {result['ratio']:.2f}; patch contacts per call {counts['patch_contacts_per_call']:.2f} of "
          f"{counts['loaded_contacts_per_call']:.2f}, failures {counts['patch_failures_per_call']:.3f}; load "
          f"{load_before[0]:.2f} -> {load_after[0]:.2f}")
    err = accuracy["table_vs_online_wheel_force"]
    print(f"table against the online patch: {accuracy['solved_online']} of {accuracy['wheel_evaluations']} wheel "
          f"evaluations solved online; wheel force error median {err['median']:.2%}, p99 {err['p99']:.2%}, "
          f"p99.9 {err['p99_9']:.2%}, worst {err['max']:.2%}")
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
