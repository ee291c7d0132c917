"""How the package compiles its kernels: :func:`compiled`, the one decorator of every numba-compiled function.

* **Cached.**  A kernel is compiled once per machine and source version and kept in numba's on-disk cache (the
  ``__pycache__`` folder beside its module, or ``NUMBA_CACHE_DIR``); every later process — a command, a test
  worker — loads it instead of compiling it again.
* **One specialization per argument type, not per constant.**  Called from another kernel with a constant
  argument (``_fill_at(out, w, 0, …)``), numba compiles a separate specialization for the constant's *value*
  (``Literal[int](0)``), and another for every other constant and for a variable.  A kernel made here is compiled
  for the argument's type only (``int64``): the same machine code serves every call site, and a first run compiles
  each kernel once.  No kernel of the package relies on a constant argument's value being known at compile time.
* **What a scene does not need is not compiled.**  Not done here but by the callers: optional data (a geometry
  table, a structure's shapes or residual flexibility, a track layout, a creep table) is passed as ``None`` when
  absent, and a kernel branches on ``x is None`` of an *argument*, which numba resolves from the argument's type
  before it compiles anything — the branch that is not taken is never compiled.
* **A first run says so.**  The first compilation of a package kernel in a process prints one line on standard
  error when it is a terminal (:data:`COMPILE_NOTICE`); a log file or a test gets nothing.
"""
from __future__ import annotations

import sys
from functools import partial

from numba import njit, types
from numba.core import event
from numba.core.registry import CPUDispatcher

__all__ = ["compiled", "COMPILE_NOTICE"]

#: the line shown on a terminal when a process first compiles a kernel of the package
COMPILE_NOTICE = ("compiling the package's numba kernels (first run after an install or an update only; later runs "
                  "load them from the cache) …")


def _typed_call_template(get_call_template, args, kws):
    """numba's call template of a kernel for a call from another kernel, typed by the arguments' types, not
    their constant values (module docstring)."""
    return get_call_template(tuple(types.unliteral(a) for a in args),
                             {name: types.unliteral(t) for name, t in kws.items()})


class _CompileNotice(event.Listener):
    """Prints :data:`COMPILE_NOTICE` once per process, at the first compilation of a package kernel, when standard
    error is a terminal."""

    def __init__(self):
        self.shown = False

    def on_start(self, ev):
        if self.shown:
            return
        func = getattr(ev.data.get("dispatcher"), "py_func", None)
        if not (getattr(func, "__module__", None) or "").startswith(__package__ + "."):
            return
        self.shown = True
        stream = sys.stderr
        if stream is not None and stream.isatty():
            print(COMPILE_NOTICE, file=stream, flush=True)

    def on_end(self, ev):
        pass


event.register("numba:compile", _CompileNotice())


def compiled(func=None, **options):
    """``@compiled`` or ``@compiled(inline="always")``: ``numba.njit(cache=True, **options)``, typed by argument types
    at calls from other kernels (module docstring).  With ``NUMBA_DISABLE_JIT=1`` the plain Python function."""
    def wrap(f):
        dispatcher = njit(cache=True, **options)(f)
        if isinstance(dispatcher, CPUDispatcher):
            dispatcher.get_call_template = partial(_typed_call_template, dispatcher.get_call_template)
        return dispatcher
    return wrap(func) if func is not None else wrap
