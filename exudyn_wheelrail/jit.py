"""How the package compiles its kernels: :func:`compiled`, the one decorator of every numba-compiled function.

* **Cached.**  A kernel is compiled once per machine and source version and kept in numba's on-disk cache (the
  ``__pycache__`` folder beside its module, or ``NUMBA_CACHE_DIR``); every later process — a command, a test
  worker — loads it instead of compiling it again.  "Source version" is the whole package's: numba alone keys a
  kernel's cache on its own file, yet the machine code it keeps has the kernels it calls and the module constants
  it reads (from other files) built in, so an edit of ``contact/layout.py`` alone would leave every caller in
  another file running the old code.  Here each kernel's cache also carries a digest of every ``.py`` file of the
  package (:func:`package_source_digest`): any change of the package's source makes every kernel compile afresh.
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

import hashlib
import sys
from functools import cache, partial
from pathlib import Path

from numba import njit, types
from numba.core import event
from numba.core.caching import FunctionCache, IndexDataCacheFile
from numba.core.registry import CPUDispatcher

__all__ = ["compiled", "COMPILE_NOTICE", "package_source_digest"]

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


@cache
def package_source_digest() -> bytes:
    """SHA-256 of every ``.py`` file of the package (relative path and content, in path order), read once per
    process: the source version a cached kernel is valid for (module docstring)."""
    root = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0")
        digest.update(path.read_bytes())
    return digest.digest()


class _PackageSourceCache(FunctionCache):
    """numba's on-disk cache of one kernel (same place and files), whose index is valid only for the source of its
    own file *and* of the whole package (:func:`package_source_digest`)."""

    def __init__(self, py_func):
        super().__init__(py_func)
        stamp = (self._impl.locator.get_source_stamp(), package_source_digest())
        self._cache_file = IndexDataCacheFile(cache_path=self._cache_path, filename_base=self._impl.filename_base,
                                              source_stamp=stamp)


def compiled(func=None, **options):
    """``@compiled`` or ``@compiled(inline="always")``: ``numba.njit(**options)`` cached on disk for the package's
    source version, typed by argument types at calls from other kernels (module docstring).  With
    ``NUMBA_DISABLE_JIT=1`` the plain Python function."""
    def wrap(f):
        dispatcher = njit(**options)(f)
        if isinstance(dispatcher, CPUDispatcher):
            dispatcher._cache = _PackageSourceCache(f)
            dispatcher.get_call_template = partial(_typed_call_template, dispatcher.get_call_template)
        return dispatcher
    return wrap(func) if func is not None else wrap
