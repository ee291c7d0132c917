"""A second Python process that works beside this one: started with this interpreter and this process's import path
(so it imports the same copy of the package), fed over its standard input, its error output kept for the message of
a failure.  Used where a command has work for the machine's second CPU: compiling kernels ahead
(:func:`exudyn_wheelrail.jit.compile_ahead`) and drawing figures while the run is built and solved
(:class:`exudyn_wheelrail.scenarios.drawing.FigureProcess`)."""
from __future__ import annotations

import os
import pickle
import subprocess
import sys
import tempfile

__all__ = ["cpus", "SecondProcess", "start_python"]


def cpus() -> int:
    """The CPUs this process may run on."""
    affinity = getattr(os, "sched_getaffinity", None)
    return len(affinity(0)) if affinity is not None else (os.cpu_count() or 1)


#: what every second process runs: the parent's import path from the first pickled object on its standard input
#: (``head``), the entry's module imported (the parent's copy of it, checked), the entry called with ``head`` and the
#: rest of the input; then the process ends without the interpreter's teardown (its work is written and closed by
#: then: the compiled kernels in the cache, the figures in their files)
_PROGRAM = ("import importlib, os, pickle, sys\n"
            "head = pickle.load(sys.stdin.buffer)\n"
            "sys.path[:] = head['path']\n"
            "module = importlib.import_module(head['entry_module'])\n"
            "if module.__file__ != head['entry_file']:\n"
            "    sys.exit('another copy of the package: ' + module.__file__)\n"
            "getattr(module, head['entry'])(head, sys.stdin.buffer)\n"
            "sys.stdout.flush()\n"
            "sys.stderr.flush()\n"
            "os._exit(0)\n")


class SecondProcess:
    """A started second process: its ``proc`` (:class:`subprocess.Popen`, standard input open) and its error
    output."""

    def __init__(self, proc: subprocess.Popen, errors):
        self.proc = proc
        self._errors = errors

    def send(self, obj) -> bool:
        """Pickle ``obj`` to the process's standard input (pickled whole first: an object that cannot be pickled
        raises before anything is written); False when the process has ended (the caller's wait reports why)."""
        data = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
        try:
            self.proc.stdin.write(data)
            self.proc.stdin.flush()
            return True
        except (OSError, ValueError):             # a closed pipe: the process has ended
            return False

    def close_input(self) -> None:
        """End the process's input (it reads no more; a program waiting for input sees its end)."""
        try:
            self.proc.stdin.close()
        except OSError:
            pass

    def wait(self, timeout_s: float) -> int | None:
        """Wait at most ``timeout_s`` for the end; the exit code, or None when it ran out (the process is then
        stopped).  An interrupt stops the process and is raised."""
        self.close_input()
        try:
            return self.proc.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            self.stop()
            return None
        except BaseException:
            self.stop()
            raise

    def stop(self) -> None:
        """Stop the process if it still runs."""
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        self.close_input()

    def error_line(self) -> str:
        """The last line the process wrote on its error output ('no message' if none); closes that output."""
        if self._errors is None or self._errors.closed:
            return "no message"
        self._errors.seek(0)
        tail = self._errors.read().decode(errors="replace").strip().splitlines()[-1:]
        self._errors.close()
        return tail[0] if tail else "no message"

    def discard_errors(self) -> None:
        """Close the error output unread."""
        if self._errors is not None:
            self._errors.close()


def start_python(entry, head: dict) -> SecondProcess | None:
    """Start a second Python process that runs ``entry(head, stream)`` (``entry``: a module-level function of this
    package, imported there from this process's copy of it; ``stream``: the rest of its standard input, which stays
    open for :meth:`~SecondProcess.send`).  ``head`` (a dict) is given this process's import path and the entry.
    None where no second process can be started: no interpreter to start (an embedded or frozen Python) or the
    start failed.  ``-P``: nothing of the working folder shadows a module before the parent's import path is in
    place."""
    if not sys.executable or getattr(sys, "frozen", False):
        return None
    module = sys.modules[entry.__module__]
    try:
        errors = tempfile.TemporaryFile()
        proc = subprocess.Popen([sys.executable, "-P", "-c", _PROGRAM], stdin=subprocess.PIPE,
                                stdout=subprocess.DEVNULL, stderr=errors)
    except Exception:
        return None
    second = SecondProcess(proc, errors)
    second.send(dict(head, path=list(sys.path), entry_module=module.__name__, entry_file=module.__file__,
                     entry=entry.__name__))
    return second
