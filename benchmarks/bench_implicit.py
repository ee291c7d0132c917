"""Implicit solvers on the RTRI case: contact calls per step, Newton iterations, solve time and the error of the peak
lateral force, for three Newton configurations (``NEWTON``): ``before`` — the connector's forward-difference
Jacobian (14 contact calls) kept across steps (Exudyn's modified Newton); ``after`` — the pipeline: its
semi-analytic Jacobian (one contact call, ``multibody/contact_jacobian.py``), kept across steps
(``exudyn_settings.solver_settings``); ``per_step`` — the semi-analytic Jacobian updated at every step
(``modifiedNewtonJacUpdatePerStep``).

1. **The command line, before and after** — ``python -m exudyn_wheelrail rtri --span 20 --speed-kmh 250
   --solver S --dt 0.001 --steps 2500 --out DIR --no-plots`` (recording on, as a user runs it; called in this
   process through ``exudyn_wheelrail.cli.main``), S = ``newmark`` and ``generalized_alpha``, and the ``default``
   preset (RK44 1 ms) for comparison; the configurations set the connector's ``jacobian_method`` and
   ``modifiedNewtonJacUpdatePerStep`` on the built model.  Configurations alternate, ``--repeats`` rounds
   (default 3); every run gives the solve time (``summary.json: solve_seconds``, inside ``SolveDynamic``), the
   process's CPU time of the whole command (build and outputs included: on a loaded machine the fairer cost
   measure), the 1-minute load average just before it, the
   contact calls per step of the forces (Newton residuals and the run monitor's one per state) and of the Jacobian
   (its own contact calls), Newton iterations and Jacobian evaluations per step (Exudyn's solver statistics).
2. **Work–precision rows of the implicit solvers** — newmark and generalized_alpha at 0.5, 1 and 2 ms, each
   configuration, the same error measures as ``benchmarks/work_precision.py`` (peak and RMS of the lateral force of
   wheelset 1's right wheel, car-body acceleration) against its cached converged reference
   (``results/work_precision_reference.npz``; run work_precision.py first if it is missing), and RK44 1 ms
   (``default``) and 0.25 ms (``accurate``) in the same session.

Run:  python benchmarks/bench_implicit.py [--repeats 3] [--parts cli rows]
Writes ``results/implicit.json`` and prints Markdown tables.  Run it alone (one heavy process at a time).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import work_precision as WP  # noqa: E402  (the reference, the error measures, the machine description)

from exudyn_wheelrail import cli  # noqa: E402
from exudyn_wheelrail.multibody import connector as C  # noqa: E402
from exudyn_wheelrail.scenarios import rtri_run  # noqa: E402

RESULTS = HERE / "results"
#: the Newton configurations: (connector jacobian_method, Jacobian updated every step)
NEWTON = {"before": ("forward_difference", False), "after": ("semi_analytic", False),
          "per_step": ("semi_analytic", True)}
CLI_SOLVERS = ("newmark", "generalized_alpha")
ROW_DT_MS = (0.5, 1.0, 2.0)


class _Capture:
    """Patches the RTRI build (the Newton configuration on the built model) and the connector's warm-up (counters
    from zero after it), and keeps the built model."""

    def __init__(self):
        self.newton = None
        self.h = None
        self._build = rtri_run.build_scenario
        self._warm_up = C.WheelRailContact.warm_up

    def __enter__(self):
        cap = self

        def build(spec):
            h = cap._build(spec)
            if cap.newton is not None and h.contact is not None and h.run.implicit:
                method, per_step = NEWTON[cap.newton]
                h.contact.jacobian_method = method
                h.settings.timeIntegration.newton.modifiedNewtonJacUpdatePerStep = per_step
            cap.h = h
            return h

        def warm_up(contact, mbs, jacobian=True):
            cap._warm_up(contact, mbs, jacobian)
            contact.n_jacobian_calls = contact.n_jacobian_contact_calls = contact.n_jacobian_differenced = 0

        rtri_run.build_scenario = build
        C.WheelRailContact.warm_up = warm_up
        return self

    def __exit__(self, *exc):
        rtri_run.build_scenario = self._build
        C.WheelRailContact.warm_up = self._warm_up

    def counts(self, steps: int) -> dict:
        h = self.h
        c = h.contact
        out = dict(forces_calls_per_step=c.n_calls / steps)
        it = h.mbs.sys.get("dynamicSolver").it if "dynamicSolver" in h.mbs.sys else None
        if h.run.implicit:
            out.update(jacobian_calls_per_step=c.n_jacobian_contact_calls / steps,
                       jacobians_per_step=c.n_jacobian_calls / steps,
                       jacobians_by_differences=int(c.n_jacobian_differenced))
            if it is not None:
                out.update(newton_iterations_per_step=it.newtonStepsCount / steps)
        else:
            out.update(jacobian_calls_per_step=0.0)
        out["contact_calls_per_step"] = out["forces_calls_per_step"] + out["jacobian_calls_per_step"]
        return out


# ---------------------------------------------------------------------------------------------------- 1. CLI
def cli_run(label: str, argv: list[str], newton: str | None) -> dict:
    with tempfile.TemporaryDirectory() as tmp, _Capture() as cap:
        cap.newton = newton
        load = os.getloadavg()[0]
        cpu0 = time.process_time()
        code = cli.main(argv + ["--out", tmp, "--no-plots"])
        cpu = time.process_time() - cpu0
        s = json.loads((Path(tmp) / "summary.json").read_text())
    steps = s["steps"]
    row = dict(label=label, newton=newton, exit_code=code, status=s["status"], solve_s=s["solve_seconds"],
               cpu_s=cpu, load_1min=load, steps=steps,
               peak_Y_N=s["peaks"].get("max_abs_lateral_contact_force_w1_right_N"))
    row.update(cap.counts(steps))
    return row


def cli_part(repeats: int) -> list[dict]:
    base = ["rtri", "--span", "20", "--speed-kmh", "250", "--dt", "0.001", "--steps", "2500"]
    configs = [(f"{s} {n}", base + ["--solver", s], n) for s in CLI_SOLVERS for n in NEWTON]
    configs.append(("rk44 (preset default)", ["rtri", "--span", "20", "--speed-kmh", "250", "--preset", "default",
                                              "--steps", "2500"], None))
    rows = []
    for rnd in range(repeats):
        for label, argv, newton in configs:
            r = cli_run(label, argv, newton)
            r["round"] = rnd
            rows.append(r)
            print(f"  {label:28s} round {rnd}: solve {r['solve_s']:.2f} s, CPU {r['cpu_s']:.2f} s (load "
                  f"{r['load_1min']:.2f}), "
                  f"{r['contact_calls_per_step']:.2f} contact calls/step, status {r['status']}", flush=True)
    return rows


def cli_table(rows: list[dict]) -> str:
    lines = ["| command | solve s (median; all) | CPU s (median) | load | contact calls/step (forces + Jacobian) "
             "| Newton it./step | Jacobians/step (by differences) | peak Y kN |",
             "|---|---|---|---|---|---|---|---|"]
    for label in dict.fromkeys(r["label"] for r in rows):
        rs = [r for r in rows if r["label"] == label]
        solve = [r["solve_s"] for r in rs]
        r0 = rs[0]
        it = f"{r0['newton_iterations_per_step']:.2f}" if "newton_iterations_per_step" in r0 else "—"
        jac = (f"{r0['jacobians_per_step']:.3f} ({r0['jacobians_by_differences']})" if "jacobians_per_step" in r0
               else "—")
        lines.append(f"| {label} | {statistics.median(solve):.2f}; {', '.join(f'{x:.2f}' for x in solve)} | "
                     f"{statistics.median(r['cpu_s'] for r in rs):.2f} | "
                     f"{min(r['load_1min'] for r in rs):.1f}–{max(r['load_1min'] for r in rs):.1f} | "
                     f"{r0['contact_calls_per_step']:.2f} ({r0['forces_calls_per_step']:.2f} + "
                     f"{r0['jacobian_calls_per_step']:.2f}) | {it} | {jac} | {r0['peak_Y_N'] / 1e3:.3f} |")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------------- 2. rows
def load_reference() -> dict:
    path = RESULTS / "work_precision_reference.npz"
    if not path.exists():
        raise SystemExit(f"{path}: missing; run benchmarks/work_precision.py first (it builds the reference)")
    with np.load(path, allow_pickle=False) as z:
        meta = json.loads(str(z["meta_json"]))
        return dict(series={k: z[k] for k in ("time_s", WP.Y_COL, WP.A_COL)}, meta=meta)


def row_run(solver: str, dt_ms: float, newton: str | None, ref: dict) -> dict:
    case = WP.make_case(solver, dt_ms * 1e-3, "table", "online")
    with _Capture() as cap:
        cap.newton = newton
        load = os.getloadavg()[0]
        cpu0 = time.process_time()
        result = WP.solve(case)
        cpu = time.process_time() - cpu0
    s = result.summary
    steps = s["steps"]
    row = dict(integrator=solver, newton=newton or "—", dt_ms=dt_ms, steps=steps, status=s["status"],
               solve_s=s["solve_seconds"], cpu_s=cpu, load_1min=load,
               real_time_factor=WP.T_END_S / s["solve_seconds"])
    row.update(cap.counts(steps))
    if s["status"] == "ok" and s.get("peaks"):
        info = dict(peak_Y_10ms_N=s["peaks"].get("max_abs_lateral_contact_force_w1_right_10ms_avg_N"))
        err = WP.errors(WP._series(result), info, ref["series"], ref["meta"]["reference"])
        row.update(peak_Y_N=s["peaks"]["max_abs_lateral_contact_force_w1_right_N"], **err)
    return row


def rows_part() -> list[dict]:
    ref = load_reference()
    rows = []
    configs = [(s, dt, n) for s in CLI_SOLVERS for dt in ROW_DT_MS for n in NEWTON]
    configs += [("rk44", 1.0, None), ("rk44", 0.25, None)]
    for solver, dt, newton in configs:
        r = row_run(solver, dt, newton, ref)
        rows.append(r)
        print(f"  {solver} {dt:g} ms {newton or ''}: {r['status']}, solve {r['solve_s']:.2f} s, CPU "
              f"{r['cpu_s']:.2f} s (load {r['load_1min']:.2f}), {r['contact_calls_per_step']:.2f} calls/step, "
              f"peak Y err {100 * r.get('peak_Y_rel_err', float('nan')):.3f} %", flush=True)
    return rows


def rows_table(rows: list[dict]) -> str:
    lines = ["| integrator | Newton | dt ms | status | solve s | CPU s | load | real-time factor | contact calls/step "
             "| Newton it./step | peak Y err % | RMS Y err % | peak a err % |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        def pct(k):
            v = r.get(k)
            return f"{100 * v:.3f}" if v is not None and np.isfinite(v) else "—"
        it = r.get("newton_iterations_per_step")
        lines.append(f"| {r['integrator']} | {r['newton']} | {r['dt_ms']:g} | {r['status']} | {r['solve_s']:.2f} | "
                     f"{r['cpu_s']:.2f} | {r['load_1min']:.1f} | {r['real_time_factor']:.2f} | "
                     f"{r['contact_calls_per_step']:.2f} | {'—' if it is None else f'{it:.2f}'} | "
                     f"{pct('peak_Y_rel_err')} | {pct('rms_Y_rel_err')} | {pct('peak_a_rel_err')} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3, help="rounds of the alternating command-line runs")
    ap.add_argument("--parts", nargs="+", choices=("cli", "rows"), default=["cli", "rows"])
    ap.add_argument("--out", default=str(RESULTS / "implicit.json"))
    args = ap.parse_args(argv)
    if args.repeats < 1:
        ap.error("--repeats must be >= 1")
    # warm-up (compiled code, Exudyn's first solve) outside the timed runs
    for solver in CLI_SOLVERS + ("rk44",):
        for newton in (tuple(NEWTON) if solver != "rk44" else (None,)):
            with _Capture() as cap:
                cap.newton = newton
                WP.solve(WP.make_case(solver, 1e-3, "table", "online", steps=5))
    out = dict(what=__doc__.split("\n\n")[0], machine=WP.machine_info(), newton=NEWTON)
    if "cli" in args.parts:
        print("1. command line, alternating rounds:")
        out["cli"] = cli_part(args.repeats)
    if "rows" in args.parts:
        print("2. work-precision rows:")
        out["rows"] = rows_part()
    out["machine_after"] = WP.machine_info()
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(out, fh, indent=2, allow_nan=True)
    if "cli" in out:
        print("\n### RTRI 20 m, 250 km/h, 2500 steps of 1 ms, recording on (command line)\n")
        print(cli_table(out["cli"]))
    if "rows" in out:
        print("\n### Work–precision rows (2.5 s simulated, recording on)\n")
        print(rows_table(out["rows"]))
    print(f"\nwrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
