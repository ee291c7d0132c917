"""What the command modules share: the parser with one-line errors, the error and warning lines, the positive-integer
option type, the ``--progress`` option and where progress goes, the figure-file check, the run-status lines and the
``KEY=VALUE`` options (``--set``, ``--param``).  It holds no command of its own."""
from __future__ import annotations

import argparse
import contextlib
import re
import shutil
import sys
import time
import warnings

from ..validation import InputWarning, output_file


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors ``error: <option>: <problem>`` and exit code 2 (no usage block)."""

    def error(self, message):
        m = re.match(r"argument ([^:]+): (.*)", message, re.S)
        if m:
            message = f"{m.group(1)}: {m.group(2)}"
        else:
            m = re.match(r"the following arguments are required: (.*)", message, re.S)
            if m:
                message = f"{m.group(1)}: missing (required by {self.prog}; see {self.prog} --help)"
            else:
                m = re.match(r"unrecognized arguments: (.*)", message, re.S)
                if m:
                    message = f"{m.group(1)}: unrecognized argument(s) of {self.prog} (see {self.prog} --help)"
        print_line("error", message)
        sys.exit(2)


def print_line(kind: str, message) -> None:
    """``kind: message`` as one line on stderr (line breaks of the message joined with '; ')."""
    text = "; ".join(part.strip() for part in str(message).splitlines() if part.strip())
    print(f"{kind}: {text}", file=sys.stderr)


def show_warning(message, category, filename, lineno, file=None, line=None, _default=warnings.showwarning):
    """``warnings.showwarning`` of a command: an :class:`~exudyn_wheelrail.validation.InputWarning` as one line
    ``warning: ...``, any other warning as Python shows it."""
    if issubclass(category, InputWarning):
        print_line("warning", message)
    else:
        _default(message, category, filename, lineno, file, line)


@contextlib.contextmanager
def inputs_checked():
    """Around a run whose inputs the command's check has judged (and named an unusual value by its option or key):
    the run's own validation of the same inputs does not name them again."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        yield


def positive_int(option: str):
    """argparse type: a positive integer."""

    def parse(text):
        try:
            n = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
        if n < 1:
            raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
        return n
    parse.__name__ = option
    return parse


#: with stderr not a terminal (a log file, a pipe), a progress bar asked for by ``--progress`` writes one line at
#: most this often [s], and its last state when the run ends
PROGRESS_LINE_INTERVAL_S = 10.0


def add_progress_argument(p: argparse.ArgumentParser) -> None:
    """The one progress option of every long command (:func:`progress_bar`, :func:`progress_lines`)."""
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="progress on stderr (default: shown when stderr is a terminal; into a file or a pipe "
                        "whole lines only)")


def show_progress(args) -> bool:
    """``--progress`` / ``--no-progress`` as given, else whether stderr is a terminal."""
    return sys.stderr.isatty() if args.progress is None else bool(args.progress)


class ProgressLines:
    """The stream of a progress bar when stderr is not a terminal: each redraw of the bar (``"\\r"`` and the bar,
    :class:`~exudyn_wheelrail.simulation.recorder.ProgressBar`) is held and written as a line of its own at most every
    :data:`PROGRESS_LINE_INTERVAL_S`; the bar's close (its status and the line end) writes the last state."""

    def __init__(self, stream):
        self.stream = stream
        self.pending = ""
        self.written_at = time.perf_counter()

    def write(self, text: str) -> None:
        if text.startswith("\r"):
            self.pending = text[1:].rstrip()
            if time.perf_counter() - self.written_at >= PROGRESS_LINE_INTERVAL_S:
                self.stream.write(self.pending + "\n")
                self.written_at = time.perf_counter()
        else:
            self.stream.write(self.pending + text)
            self.pending = ""

    def flush(self) -> None:
        self.stream.flush()


def progress_bar(args):
    """What a single run's progress bar is drawn on: ``False`` (no bar), stderr (a terminal: redrawn in place) or
    :class:`ProgressLines` on stderr."""
    if not show_progress(args):
        return False
    return sys.stderr if sys.stderr.isatty() else ProgressLines(sys.stderr)


def progress_lines(args):
    """The print-like callable of a command's progress lines (a sweep's cases, a table's chunks, a report's
    sections) on stderr, or ``None``."""
    if not show_progress(args):
        return None
    return lambda text: print(text, file=sys.stderr, flush=True)


#: a progress line of one finished task of many: ``[k/N] ...``
_COUNTED = re.compile(r"\s*\[(\d+)/(\d+)\]\s*(.*)")
#: the width of a counting bar's bar [characters]
COUNT_BAR_WIDTH = 30


class CountBar:
    """A bar of finished tasks redrawn in place on a terminal (:func:`progress_count`): every line ``[k/N] text``
    redraws ``[#####.....] k/N, elapsed, remaining (from the mean rate), the text``; other lines are printed as they
    are; the bar ends its line at N."""

    def __init__(self, stream):
        self.stream = stream
        self.start = time.perf_counter()
        self.first = None

    def __call__(self, text: str) -> None:
        m = _COUNTED.match(text)
        if m is None:
            print(text, file=self.stream, flush=True)
            return
        k, n, rest = int(m.group(1)), int(m.group(2)), m.group(3)
        if self.first is None:
            self.first = k - 1                          # tasks taken from an earlier run: not in the rate
        elapsed = time.perf_counter() - self.start
        done = k - self.first
        left = (n - k) * elapsed / done if done > 0 else 0.0
        full = COUNT_BAR_WIDTH * k // max(n, 1)
        bar = "#" * full + "." * (COUNT_BAR_WIDTH - full)
        line = f"[{bar}] {k}/{n}  {_clock(elapsed)} elapsed, {_clock(left)} left  {rest}"
        width = _terminal_columns() - 1
        self.stream.write("\r" + line[:width].ljust(width))
        if k >= n:
            self.stream.write("\n")
        self.stream.flush()


def _clock(seconds: float) -> str:
    m, s = divmod(int(round(seconds)), 60)
    return f"{m}:{s:02d}" if m < 60 else f"{m // 60}:{m % 60:02d}:{s:02d}"


def _terminal_columns() -> int:
    return shutil.get_terminal_size((100, 24)).columns


def progress_count(args):
    """The progress of a command of many tasks (``[k/N] ...`` lines): a :class:`CountBar` on a terminal, whole lines
    (:func:`progress_lines`) into a file or a pipe, or ``None``."""
    if not show_progress(args):
        return None
    return CountBar(sys.stderr) if sys.stderr.isatty() else progress_lines(args)


def _figure_suffixes() -> tuple[str, ...]:
    from matplotlib.backend_bases import FigureCanvasBase
    return tuple(f".{k}" for k in sorted(FigureCanvasBase.get_supported_filetypes()))


def check_figure(option: str, path) -> None:
    """A figure file to write (``None``: none): a writable place and a suffix matplotlib can write."""
    if path is not None:
        output_file(option, path, _figure_suffixes(), what="figure file")


def print_status(summary):
    """A run's status, hint and cost lines from its summary."""
    st = summary["status_detail"]
    rtf = summary["real_time_factor"] or 0.0
    line = f"status: {summary['status']}"
    if st["kind"] != "ok":
        where = "" if st["wheelset"] is None else f" wheelset {st['wheelset']}" + (
            f" {st['side']}" if st["side"] else "")
        when = "" if st["time_s"] is None else f" at t = {st['time_s']:.6g} s"
        line += f"{where}{when}: {st['detail']}"
    print(line)
    if st["hint"]:
        print(f"hint: {st['hint']}")
    print(f"{summary['steps']} steps of {summary['dt_s']:g} s planned ({summary['duration_s']:.4g} s); solve "
          f"{summary['solve_seconds']:.2f} s for {summary['simulated_time_s']:.4g} s simulated (real-time factor "
          f"{rtf:.2f}), exit code {st['exit_code']}")


def _split_values(text: str) -> list[str]:
    """Split ``V1,V2,...`` at the commas outside brackets and quotes (``[20, 40],[30]`` is two values)."""
    out, cur, depth, quote = [], [], 0, None
    for ch in text:
        if quote:
            quote = None if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == "," and depth == 0:
            out.append("".join(cur))
            cur = []
            continue
        cur.append(ch)
    out.append("".join(cur))
    return out


def key_values(text: str, option: str, many: bool):
    """argparse type of ``KEY=VALUE`` (``many``: ``KEY=V1,V2,...``): the key and its parsed value(s)."""
    from ..scenarios.scenario import parse_value
    if "=" not in text:
        raise argparse.ArgumentTypeError(f"expected KEY={'V1,V2,...' if many else 'VALUE'}, got {text!r}")
    key, value = text.split("=", 1)
    key = key.strip()
    if not key:
        raise argparse.ArgumentTypeError(f"{text!r}: empty key")
    if not many:
        return key, parse_value(value)
    values = _split_values(value)
    if any(not v.strip() for v in values):
        raise argparse.ArgumentTypeError(f"{text!r}: empty value in the list")
    return key, [parse_value(v) for v in values]


def key_value_dict(pairs, option: str) -> dict:
    """The ``(key, value)`` pairs of a repeatable ``option`` as a dict; a key given twice is bad input."""
    out = {}
    for key, value in pairs or []:
        if key in out:
            raise ValueError(f"{option} {key}: given twice")
        out[key] = value
    return out
