"""Time to first result: each main command on an empty numba cache (the first run after an install), then again
warm, and ``--help`` of every command; per command the compile time of every compiled function it compiled.

What a new user runs first (the README's commands):

* ``example``  — ``python examples/contact_geometry.py`` (the README's main example);
* ``rtri``     — ``python -m exudyn_wheelrail rtri --span 20 --preset default``;
* ``run``      — ``python -m exudyn_wheelrail run examples/scenarios/bridge_20m.toml`` (a shipped scenario);
* ``bridge-crossing`` — two Manchester coaches over the 20 m span (full interaction, ``--model vehicles``);
* ``curving``  — ``python -m exudyn_wheelrail curving --vehicle manchester_vehicle1 --radius-m 1000 --cant-m 0.1
  --speed-kmh 100``.

**Cold** is what a fresh install meets: every command runs in its own copy of the package, examples and vehicles
(made here, without any ``__pycache__``: no numba cache and no bytecode of the package; the installed libraries
keep theirs, as pip leaves them), so each command compiles exactly what it needs.  **Warm** is the same command
run again in the same copy (``--warm-repeats`` times; the run of least overhead is reported, all are kept).  The
commands run as Python runs by default, writing the package's bytecode on the first run (``PYTHONDONTWRITEBYTECODE``
is removed from their environment: with it, every warm run would compile the package's sources again).  Wall times are of the whole process (``time.perf_counter`` around ``subprocess``);
where the command prints its solve time (``solve X s``) that is reported too, and ``overhead`` = wall − solve.
Compile times come from numba's ``numba:compile`` events recorded in every process of the command (its own and
the second process a first run starts to compile a share of its kernels; summed, and the count of processes that
compiled reported): per function its exclusive time (its own typing, lowering and code generation, without the functions it compiles on the way) and
the count of specializations compiled, in CPU seconds of the process (less disturbed by other work on a shared
machine than wall time).

The machine load (``os.getloadavg``) is given beside every timing.  Writes ``benchmarks/results/cold_start.json``.

Run:  python benchmarks/bench_cold_start.py [--only rtri,example] [--help-repeats 3] [--warm-repeats 3]
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
RESULTS = REPO / "benchmarks" / "results" / "cold_start.json"
#: what a command reads besides the installed libraries: copied into every command's fresh folder
COPY_ITEMS = ("exudyn_wheelrail", "examples", "vehicles")
IGNORE = shutil.ignore_patterns("__pycache__", "*.pyc", "*.nbi", "*.nbc")

#: the commands (name -> arguments after ``python``; ``{out}`` an output folder)
COMMANDS = {
    "example": ["examples/contact_geometry.py"],
    "rtri": ["-m", "exudyn_wheelrail", "rtri", "--span", "20", "--preset", "default", "--out", "{out}"],
    "run": ["-m", "exudyn_wheelrail", "run", "examples/scenarios/bridge_20m.toml", "--out", "{out}"],
    "bridge-crossing": ["-m", "exudyn_wheelrail", "bridge-crossing", "--span-m", "20", "--bridge-mass-kg-per-m",
                        "15000", "--bridge-frequency-hz", "5", "--damping-ratio", "0.01", "--modes", "3", "--train",
                        "vehicles/trains/manchester_x2.toml", "--model", "vehicles", "--speed-kmh", "200",
                        "--out", "{out}"],
    "curving": ["-m", "exudyn_wheelrail", "curving", "--vehicle", "manchester_vehicle1", "--radius-m", "1000",
                "--cant-m", "0.1", "--speed-kmh", "100", "--out", "{out}"],
}
#: ``--help`` of the top level and of every command named here
HELP_COMMANDS = ("", "geometry", "conicity", "creep-table", "rtri", "rtri-sweep", "run", "sweep",
                 "validation-report", "explore", "bridge-crossing", "bridge-crossing-sweep", "curving")

_SOLVE = re.compile(r"solve (\d+(?:\.\d+)?) s")

# ---- every process of a command records numba's compile events -------------------------------------------------
#: a ``sitecustomize`` module (imported by every Python process at start-up) on the cold run's path: with
#: WHEELRAIL_BENCH_RECORD set, the process records its compile events and writes them to that folder at exit
#: (the command's process and any it starts, e.g. the second process compiling a share of a first run's kernels)
_RECORDER = r'''
import atexit, json, os, time
folder = os.environ.get("WHEELRAIL_BENCH_RECORD")
if folder:
    from numba.core import event
    stack, per = [], {}
    class Recorder(event.Listener):
        def on_start(self, ev):
            stack.append([time.process_time(), 0.0])
        def on_end(self, ev):
            t0, nested = stack.pop()
            t = time.process_time() - t0
            if stack:
                stack[-1][1] += t
            f = getattr(ev.data["dispatcher"], "py_func", None)
            name = f"{getattr(f, '__module__', '?')}.{getattr(f, '__qualname__', '?')}"
            row = per.setdefault(name, [0.0, 0, 0.0])
            row[0] += t - nested
            row[1] += 1
            if not stack:
                row[2] += t
    event.register("numba:compile", Recorder())
    def dump():
        with open(os.path.join(folder, f"{os.getpid()}.json"), "w") as fh:
            json.dump({"per": per}, fh)
    atexit.register(dump)
'''


def _load() -> float:
    return round(os.getloadavg()[0], 2)


def _fresh_copy(root: Path) -> Path:
    for item in COPY_ITEMS:
        shutil.copytree(REPO / item, root / item, ignore=IGNORE)
    return root


def _env(copy: Path, record: Path | None = None) -> dict:
    env = dict(os.environ)
    env.pop("NUMBA_CACHE_DIR", None)                 # the cache beside the copy's sources: empty
    # Python's default: the package's bytecode written on the first run and read by every later one, as on a user's
    # machine (a shell with PYTHONDONTWRITEBYTECODE set would make every warm run compile the package's sources
    # again, ~0.1-0.2 s)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPATH"] = str(copy)
    env["MPLBACKEND"] = "Agg"
    env.pop("WHEELRAIL_BENCH_RECORD", None)
    if record is not None:                          # the recorder first on the path, its folder given
        (record / "site").mkdir(parents=True)
        (record / "site" / "sitecustomize.py").write_text(_RECORDER)
        env["PYTHONPATH"] = os.pathsep.join([str(record / "site"), str(copy)])
        env["WHEELRAIL_BENCH_RECORD"] = str(record)
    return env


def _run(copy: Path, args: list, record: Path | None) -> dict:
    cmd = [sys.executable] + args
    env = _env(copy, record)
    load0 = _load()
    t0 = time.perf_counter()
    r = subprocess.run(cmd, cwd=copy, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    m = _SOLVE.search(r.stdout + r.stderr)
    row = {"wall_s": round(wall, 2), "exit_code": r.returncode, "load": [load0, _load()]}
    if m:
        row["solve_s"] = float(m.group(1))
        row["overhead_s"] = round(wall - row["solve_s"], 2)
    if r.returncode != 0:
        row["stderr_tail"] = r.stderr[-600:]
    return row


def time_command(name: str, args: list, warm_repeats: int = 1) -> dict:
    with tempfile.TemporaryDirectory(prefix=f"cold-{name}-") as tmp:
        copy = _fresh_copy(Path(tmp))
        out = str(Path(tmp) / "out")
        argv = [a.replace("{out}", out) for a in args]
        record = Path(tmp) / "compile"
        cold = _run(copy, argv, record)
        per, processes = {}, 0
        for path in record.glob("*.json"):           # every process's events, summed
            events = json.loads(path.read_text())["per"]
            processes += bool(events)
            for k, v in events.items():
                row = per.setdefault(k, [0.0, 0, 0.0])
                for i in range(3):
                    row[i] += v[i]
        warms = [_run(copy, argv, None) for _ in range(warm_repeats)]
        warm = min(warms, key=lambda w: w.get("overhead_s", w["wall_s"]))
        if warm_repeats > 1:
            warm = {**warm, "of_repeats": warm_repeats,
                    "all_wall_s": [w["wall_s"] for w in warms], "all_overhead_s": [w.get("overhead_s") for w in warms]}
    functions = sorted(({"function": k, "exclusive_cpu_s": round(v[0], 3), "specializations": v[1],
                         "top_level_cpu_s": round(v[2], 3)} for k, v in per.items()
                        if k.startswith("exudyn_wheelrail.")), key=lambda d: -d["exclusive_cpu_s"])
    total = sum(v[0] for v in per.values())
    return {"command": "python " + " ".join(args), "cold": cold, "warm": warm,
            "compile_cpu_s": round(total, 2), "compiling_processes": processes,
            "compile_cpu_s_package_functions": round(sum(f["exclusive_cpu_s"] for f in functions), 2),
            "specializations": sum(f["specializations"] for f in functions), "functions": functions}


def time_help(repeats: int) -> dict:
    env = dict(os.environ)
    rows = {}
    for cmd in HELP_COMMANDS:
        args = [sys.executable, "-m", "exudyn_wheelrail"] + ([cmd] if cmd else []) + ["--help"]
        best = float("inf")
        for _ in range(repeats):
            t0 = time.perf_counter()
            r = subprocess.run(args, cwd=REPO, env=env, capture_output=True, text=True)
            best = min(best, time.perf_counter() - t0)
            if r.returncode != 0:
                raise SystemExit(f"error: {' '.join(args[1:])} exited {r.returncode}: {r.stderr.strip()[-300:]}")
        rows[cmd or "(top level)"] = round(best, 3)
    return {"best_of": repeats, "wall_s": rows, "load": _load()}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", default="", help="comma-separated command names (default: all): "
                                               + ", ".join(COMMANDS))
    ap.add_argument("--help-repeats", type=int, default=3, help="runs of each --help (best taken)")
    ap.add_argument("--warm-repeats", type=int, default=3,
                    help="warm runs of each command (the one of least overhead, else of least wall time, reported)")
    ap.add_argument("--no-write", action="store_true", help="print only, do not write the result file")
    a = ap.parse_args(argv)
    names = [n for n in a.only.split(",") if n] or list(COMMANDS)
    unknown = sorted(set(names) - set(COMMANDS))
    if unknown:
        ap.error(f"--only: unknown command(s) {unknown}; expected names from {list(COMMANDS)}")
    result = {"machine": {"cpu": platform.processor() or platform.machine(), "cores": os.cpu_count(),
                          "python": platform.python_version()},
              "help": time_help(a.help_repeats), "commands": {}}
    print(f"--help (best of {a.help_repeats}, load {result['help']['load']}):")
    for k, v in result["help"]["wall_s"].items():
        print(f"  {k:24s} {v:6.2f} s")
    for name in names:
        row = time_command(name, COMMANDS[name], a.warm_repeats)
        result["commands"][name] = row
        c, w = row["cold"], row["warm"]
        solve = f", solve {w['solve_s']:.2f} s, overhead {w['overhead_s']:.2f} s" if "solve_s" in w else ""
        print(f"{name}: cold {c['wall_s']:.1f} s (load {c['load'][0]}-{c['load'][1]}; compile {row['compile_cpu_s']} "
              f"s CPU, {row['specializations']} specializations), warm {w['wall_s']:.2f} s{solve} "
              f"(load {w['load'][0]}); exit {c['exit_code']}/{w['exit_code']}")
        for f in row["functions"][:8]:
            print(f"    {f['exclusive_cpu_s']:6.2f} s  x{f['specializations']}  {f['function']}")
    if not a.no_write:
        try:
            import numba
            result["versions"] = {"numba": numba.__version__}
        except ImportError:
            pass
        RESULTS.write_text(json.dumps(result, indent=1) + "\n")
        print(f"wrote {RESULTS.relative_to(REPO)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
