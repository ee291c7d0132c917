"""Command line: ``python -m exudyn_wheelrail <command> ...`` (scripts and regression tests call it; keep it stable).

Commands
--------
geometry   contact-geometry functions of a wheelset lateral sweep -> CSV (and an optional plot)
conicity   equivalent conicity (EN 15302 definitions) for an amplitude
creep-table  build a USETAB-style creep table (npz) with Kalker's exact theory or FASTSIM
rtri       the rigid-rail RTRI validation case (one span, one speed): time series, summary, Figs. 5/6
rtri-sweep the RTRI case over spans x speeds in parallel processes: table and Fig. 7
run        a scenario file (TOML: vehicle, track, optional bridge, run, outputs): time series, summary, criteria
sweep      a scenario over the cartesian product of parameter values (--param KEY=V1,V2,...) in parallel
validation-report  re-run the validations (Kalker E.3, creep table, Klingel, Frýba, RTRI) -> report.md + PNGs
explore    the RTRI explorer: sliders (speed, span, deviation, friction, suspension) re-run the case and redraw
bridge-crossing  a train (axle loads, HSLM-A, or vehicles) over a simply supported span: deck response, EN 1990
bridge-crossing-sweep  the crossing over many speeds in parallel: peak deck response against speed, resonances
curving    steady curving through an entry transition into a canted curve: sum Y, Y/Q, shift, attack angle
en1991-dynamic  a bridge's dynamic check to EN 1991-2 6.4.6: every train, speed and mass bound; verdict, report
critical-speed  running stability: linear critical speed and hunting mode, nonlinear critical speed, bifurcation

Lateral shifts are positive towards the **right** rail; all values in SI units.

Bad input (a malformed or implausible option, a profile that is not what it is given as, an output location that
cannot be written) is reported before any work as one line ``error: <option or file>: <problem>`` with exit code 2;
an unusual but plausible value as one line ``warning: ...``, and the run goes on.  A simulation (``rtri``,
``rtri-sweep``, ``run``, ``sweep``, ``bridge-crossing``, ``curving``) exits with the code of its status (:mod:`exudyn_wheelrail.simulation.status`):
0 ok, 3 derailed, 4 diverged, 5 step_rejected; 1 any other error.

The package is the command line's face (:func:`build_parser`, :func:`main`); the commands live one group to a module:
:mod:`.contact` (geometry, conicity, creep-table), :mod:`.rtri` (rtri, rtri-sweep, validation-report, explore),
:mod:`.scenario` (run, sweep), :mod:`.bridge` (bridge-crossing, bridge-crossing-sweep), :mod:`.curving` (curving),
:mod:`.en1991` (en1991-dynamic),
what they share in :mod:`.common`.  A command's numerical modules are imported inside its functions, when it runs:
building the parser and every ``--help`` load no numerical code.
"""
from __future__ import annotations

import argparse
import contextlib
import gc
import warnings

from ..simulation.settings import SPEED_KM_H
from ..simulation.status import EXIT_BAD_INPUT, EXIT_ERROR
from ..validation import InputWarning
from .bridge import add_bridge_crossing_parsers
from .common import Parser, print_line, show_warning
from .contact import add_conicity_parser, add_creep_table_parser, add_geometry_parser, plot_sweep
from .curving import add_curving_parser
from .en1991 import add_en1991_dynamic_parser
from .rtri import add_explore_parser, add_rtri_parser, add_rtri_sweep_parser, add_validation_report_parser
from .scenario import add_run_parser, add_sweep_parser
from .stability import add_critical_speed_parser

__all__ = ["SPEED_KM_H", "build_parser", "main", "plot_sweep"]


def build_parser() -> argparse.ArgumentParser:
    """The parser of every command, in the order of the module docstring's list."""
    parser = Parser(prog="python -m exudyn_wheelrail", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    for add_parser in (add_geometry_parser, add_conicity_parser, add_creep_table_parser, add_rtri_parser,
                       add_rtri_sweep_parser, add_run_parser, add_sweep_parser, add_validation_report_parser,
                       add_explore_parser, add_bridge_crossing_parsers, add_curving_parser,
                       add_en1991_dynamic_parser, add_critical_speed_parser):
        add_parser(sub)
    return parser


def _figures(args):
    """The figures' second process of a command that draws figures (its parser's ``figures_of(args)`` names their
    module, or None where this run draws none), started first thing: it imports the plotting library and the figure
    module on another CPU while this process checks the input, builds and solves
    (:class:`~exudyn_wheelrail.scenarios.drawing.FigureProcess`).  A context giving ``None`` otherwise."""
    figures_of = getattr(args, "figures_of", None)
    module = figures_of(args) if figures_of is not None else None
    if module is None:
        return contextlib.nullcontext()
    from ..scenarios.drawing import FigureProcess
    return FigureProcess(module)


def main(argv=None) -> int:
    """Run a command; bad input gives one line ``error: <what>: <problem>`` on stderr and exit code 2 (module
    docstring), an unusual value one line ``warning: ...``; any other failure (``RuntimeError``: e.g. a creep table
    that cannot be loaded, a recorder that failed, no display for a window) one line ``error: ...`` and exit code 1;
    a run's own status sets the exit code of a completed command (:mod:`exudyn_wheelrail.simulation.status`).

    ``argv`` None: the command line of this process (``python -m exudyn_wheelrail``, ``exudyn-wheelrail``).  Then the
    garbage collector is paused while the checks load the command's modules, and the objects alive after them (the
    modules: the numerical code) and at the end are frozen (``gc.freeze``): they live until the process ends, so
    neither the collector's full passes during the run nor those of the interpreter's exit walk them again."""
    process = argv is None
    if process:
        gc.disable()
    with warnings.catch_warnings():
        warnings.showwarning = show_warning
        warnings.simplefilter("always", InputWarning)
        args = build_parser().parse_args(argv)
        try:
            with _figures(args) as args.figures:
                args.check(args)       # cheap checks of every option before any work
                if process:
                    gc.freeze()
                    gc.enable()
                return args.func(args)
        except ValueError as exc:      # bad input: an option, a key of a file, a value out of range
            print_line("error", exc)
            return EXIT_BAD_INPUT
        except RuntimeError as exc:    # not the input: the environment or the run itself failed
            print_line("error", exc)
            return EXIT_ERROR
        except OSError as exc:         # a file that cannot be read or written
            where = f"{exc.filename}: " if exc.filename else ""
            print_line("error", f"{where}{exc.strerror or exc}")
            return EXIT_BAD_INPUT
        finally:
            if process:
                gc.freeze()
