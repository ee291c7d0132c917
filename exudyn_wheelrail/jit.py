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
* **A first run uses a second core.**  numba compiles a kernel and everything it calls in one thread, and a kernel's
  own compilation waits for its callees'.  :func:`compile_ahead` takes a kernel's callees as two shares of jobs:
  when a share set aside is missing from the cache and the machine has another CPU, a second Python process
  compiles it into the cache while this one compiles its own share; the kernel itself, compiled next, then loads
  both.  The first run's compilation takes about the time of the larger share instead of the sum.
* **Safe with several processes.**  Test workers and :func:`compile_ahead`'s second process write the same cache
  at once.  numba numbers a kernel's data files by the entries its index had when read, so two processes adding two
  specializations of one kernel can write them under one file name and leave an index entry that loads the other
  specialization's machine code.  Here a data file is named by a digest of its index key (one name per
  specialization, machine and bytecode), written before the index names it, and the index is read, updated and
  written under a lock (one lock file per cache folder; without ``fcntl``, i.e. on Windows, unlocked: an entry may
  then be lost and compiled again, never mixed up).
"""
from __future__ import annotations

import contextlib
import hashlib
import importlib
import os
import pickle
import sys
import warnings
from functools import cache, partial
from pathlib import Path

import numba
from numba import njit, types
from numba.core import event
from numba.core.caching import FunctionCache, IndexDataCacheFile
from numba.core.registry import CPUDispatcher

from .processes import SecondProcess, cpus, start_python

try:                                   # POSIX: the cache index's lock
    import fcntl
except ImportError:                    # Windows: no lock (module docstring)
    fcntl = None

__all__ = ["compiled", "compile_ahead", "is_compiled", "Pending", "COMPILE_NOTICE", "package_source_digest"]

#: the lock file of a cache folder's indexes (module docstring)
INDEX_LOCK_NAME = "exudyn_wheelrail-index.lock"
#: how long :meth:`Pending.wait` waits for the second process of :func:`compile_ahead` [s] (its share takes ~15 s
#: on an idle 2-core machine); then it is stopped and the kernel's own compilation compiles what is missing
COMPILE_AHEAD_TIMEOUT_S = 300.0
#: the environment variable that, set to ``0``, keeps :func:`compile_ahead` in one process (e.g. in each worker of
#: a parallel test run, whose workers already share the CPUs)
COMPILE_AHEAD_ENV = "EXUDYN_WHEELRAIL_COMPILE_AHEAD"
#: hexadecimal digits of a cache data file's name digest (:class:`_KeyedDataFile`)
DATA_NAME_DIGITS = 20

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


@contextlib.contextmanager
def _index_lock(folder):
    """Exclusive lock of the cache folder ``folder``'s indexes (module docstring).  Without ``fcntl``, or where the
    lock file cannot be opened or locked (a file system without locks, a lock file of another user), unlocked."""
    fd = None
    if fcntl is not None:
        try:
            fd = os.open(os.path.join(folder, INDEX_LOCK_NAME), os.O_RDONLY | os.O_CREAT, 0o666)
            fcntl.flock(fd, fcntl.LOCK_EX)
        except OSError:
            if fd is not None:
                os.close(fd)
            fd = None
    try:
        yield
    finally:
        if fd is not None:
            os.close(fd)                # closing releases the lock


class _KeyedDataFile(IndexDataCacheFile):
    """numba's index and data files of one kernel, safe when several processes add entries at once (module
    docstring): each data file named by a digest of its source version and key, written first; the index updated
    under the lock.  The data files of an index of another source version are removed when this version's index
    replaces it (numba reused their numbered names instead)."""

    def __init__(self, cache_path, filename_base, source_stamp):
        super().__init__(cache_path=cache_path, filename_base=filename_base, source_stamp=source_stamp)
        self._filename_base = filename_base

    def key_name(self, key) -> str:
        """The data file's name of index key ``key``: the kernel's file base and a digest of the source version and
        the key's text (the signature's type names, the machine's description, the bytecode's hashes: the same in
        every process)."""
        text = repr((self._source_stamp, key)).encode()
        return "%s.%s.nbc" % (self._filename_base, hashlib.sha256(text).hexdigest()[:DATA_NAME_DIGITS])

    def save(self, key, data):
        name = self.key_name(key)
        self._save_data(name, data)
        with _index_lock(self._cache_path):
            stale = self._stale_names()
            overloads = self._load_index()
            if overloads.get(key) != name:
                overloads[key] = name
                self._save_index(overloads)
            for old in stale - {name}:
                with contextlib.suppress(OSError):
                    os.unlink(self._data_path(old))

    def _stale_names(self) -> set:
        """The data files named by the index on disk when it is of another source version (else none)."""
        try:
            with open(self._index_path, "rb") as f:
                version = pickle.load(f)
                stamp, overloads = pickle.loads(f.read())
        except Exception:               # none, unreadable, of another numba: nothing known to remove
            return set()
        if version != self._version or stamp == self._source_stamp:
            return set()
        return {v for v in overloads.values() if isinstance(v, str) and v.startswith(self._filename_base + ".")}

    def has(self, key) -> bool:
        """Whether the index (of this source version) has an entry ``key``."""
        return key in self._load_index()


class _PackageSourceCache(FunctionCache):
    """numba's on-disk cache of one kernel (same place), whose index is valid only for the source of its own file
    *and* of the whole package (:func:`package_source_digest`), its files written by :class:`_KeyedDataFile`."""

    def __init__(self, py_func):
        super().__init__(py_func)
        stamp = (self._impl.locator.get_source_stamp(), package_source_digest())
        self._cache_file = _KeyedDataFile(cache_path=self._cache_path, filename_base=self._impl.filename_base,
                                          source_stamp=stamp)

    def has_overload(self, sig, target_context) -> bool:
        """Whether the cache holds the specialization ``sig`` (without loading it)."""
        return self._cache_file.has(self._index_key(sig, target_context.codegen()))


def compiled(func=None, *, refcount: bool = True, **options):
    """``@compiled`` or ``@compiled(inline="always")``: ``numba.njit(**options)`` cached on disk for the package's
    source version, typed by argument types at calls from other kernels (module docstring).  With
    ``NUMBA_DISABLE_JIT=1`` the plain Python function.

    ``refcount=False``: numba's reference counting of arrays is left out of this kernel (its ``_nrt`` option), for
    a kernel that only reads and writes arrays it is given and creates none.  numba counts every array a kernel
    receives or takes from a tuple with atomic increments and decrements (``NRT_incref``/``NRT_decref``, function
    calls); a small kernel called in a loop spends as much on them as on its arithmetic (measured on the contact
    search along the RTRI run: a third of its time).  A kernel that creates an array does not compile so."""
    if not refcount:
        options["_nrt"] = False

    def wrap(f):
        dispatcher = njit(**options)(f)
        if isinstance(dispatcher, CPUDispatcher):
            dispatcher._cache = _PackageSourceCache(f)
            dispatcher.get_call_template = partial(_typed_call_template, dispatcher.get_call_template)
        return dispatcher
    return wrap(func) if func is not None else wrap


def _signature(args) -> tuple:
    """The argument types numba dispatches a call with ``args`` by."""
    return tuple(numba.typeof(a) for a in args)


def is_compiled(dispatcher, args) -> bool:
    """Whether the specialization of ``dispatcher`` for the types of ``args`` is compiled in this process or in the
    cache (a plain function, ``NUMBA_DISABLE_JIT=1``: always)."""
    return not isinstance(dispatcher, CPUDispatcher) or _is_cached(dispatcher, _signature(args))


def _is_cached(dispatcher, sig) -> bool:
    """Whether ``dispatcher`` has ``sig`` compiled in this process or in its cache."""
    if sig in dispatcher.overloads:
        return True
    cache_ = getattr(dispatcher, "_cache", None)
    return isinstance(cache_, _PackageSourceCache) and cache_.has_overload(sig, dispatcher.targetctx)


class Pending:
    """The second process of :func:`compile_ahead`, still compiling (or none)."""

    def __init__(self, second: SecondProcess | None = None):
        self._second = second

    def wait(self) -> None:
        """Returns when the second process has ended (its share in the cache), at most
        :data:`COMPILE_AHEAD_TIMEOUT_S` later (then it is stopped: what it has not compiled, the kernel's own
        compilation compiles).  A process that failed says so (a first run then takes longer,
        nothing else changes: a ``RuntimeWarning``); an interrupt stops it."""
        second, self._second = self._second, None
        if second is None:
            return
        code = second.wait(COMPILE_AHEAD_TIMEOUT_S)
        if code not in (0, -9, None):
            warnings.warn(f"the second process compiling kernels ahead failed (exit {code}: "
                          f"{second.error_line()}); they compile here", RuntimeWarning, stacklevel=2)
        second.discard_errors()

    def stop(self) -> None:
        """Stop the second process if it still runs (what it has not compiled, the kernel's own compilation
        compiles)."""
        if self._second is not None:
            self._second.stop()


def _second_process(missing) -> Pending | None:
    """:func:`compile_ahead`'s second process for the jobs ``missing`` (started, its input complete), or None where
    none can be started (:func:`~exudyn_wheelrail.processes.start_python`)."""
    jobs = [(d.py_func.__module__, d.py_func.__qualname__, sig) for d, sig in missing]
    second = start_python(compile_jobs, {"jobs": pickle.dumps(jobs)})
    if second is None:
        return None
    second.close_input()
    return Pending(second)


def compile_ahead(kernel, args, here, aside=()) -> Pending:
    """Before the first call ``kernel(*args)``: when that specialization is in neither this process nor the cache,
    start a second process compiling the kernel's callees of ``aside`` into the cache and compile those of
    ``here`` in this process (module docstring).  Each job is ``(dispatcher, args)``, compiled for exactly the
    types of ``args`` (those the kernel hands the callee).  With one CPU, when all of ``aside`` is cached, where no
    second process can be started, or with :data:`COMPILE_AHEAD_ENV` ``=0``, both shares are compiled here.
    Returns the second process: call its
    ``wait()`` before the kernel's first call (the kernel's compilation then loads both shares from the cache; this
    process may do other work meanwhile).  Without a compiler (``NUMBA_DISABLE_JIT=1``) nothing."""
    if is_compiled(kernel, args):
        return Pending()
    here = [(d, _signature(a)) for d, a in here if isinstance(d, CPUDispatcher)]
    aside = [(d, _signature(a)) for d, a in aside if isinstance(d, CPUDispatcher)]
    missing = [(d, sig) for d, sig in aside if not _is_cached(d, sig)]
    parallel = cpus() > 1 and os.environ.get(COMPILE_AHEAD_ENV, "1") != "0"
    pending = _second_process(missing) if missing and parallel else None
    if pending is not None:
        missing = []
    try:
        for d, sig in here + missing:
            d.compile(sig)
    except BaseException:
        if pending is not None:
            pending.stop()
        raise
    return pending if pending is not None else Pending()


def compile_jobs(head: dict, stream=None) -> None:
    """The second process of :func:`compile_ahead` (:func:`~exudyn_wheelrail.processes.start_python`'s entry):
    compiles each of the pickled ``(module, qualified name, signature)`` jobs of ``head["jobs"]`` into the cache
    (unpickled here, once the parent's import path is in place)."""
    for module, qualname, sig in pickle.loads(head["jobs"]):
        target = importlib.import_module(module)
        for part in qualname.split("."):
            target = getattr(target, part)
        target.compile(sig)
