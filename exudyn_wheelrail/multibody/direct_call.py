"""The contact force call without Python: :func:`forces_step`, the one force evaluation both call paths run, and
:class:`DirectCall`, which hands it to Exudyn as a compiled function.

Two call paths, one evaluation
------------------------------
Exudyn calls the connector's force user function for every stage of every step.  Through Python that costs the
call itself (Exudyn converts the coordinates to Python lists and back, ~3 µs) and the wrapper around the compiled
call (~2.5 µs).  The **compiled path** removes both: a small native module (``exudyn_wheelrail.native.direct_force``,
built from C++ at install) offers functions of exactly the type Exudyn expects, for which pybind11 hands Exudyn the
plain function pointer; each is bound to a slot that holds the address of numba's native entry of
:func:`forces_step` for the connector's argument types (:func:`native_step_address`), the address of the
connector's :class:`CallData` and of its force vector.  :func:`forces_step` is the same compiled function the
Python path (:meth:`~.connector.WheelRailContact.forces`) calls — so both paths give the same numbers bit for bit.
The model keeps the connector alive (``mbs.variables``): the slot holds no reference to it.

:func:`forces_step` is the whole evaluation: it takes the evaluation kept by
:meth:`~.connector.WheelRailContact.evaluate_state` when called at exactly its state (bitwise), or puts back the warm
start that evaluation started from, then calls :func:`~.connector_core.contact_forces_core` and counts the call.

A bad state (non-finite coordinates) cannot raise a Python exception from the compiled path: the native function
records it and throws a C++ exception, which Exudyn reports as a failed solve; :meth:`DirectCall.bad_state` gives
the record back, from which the connector raises its :class:`~.connector.ContactStateError`
(:func:`pending_state_error`).

When the native module is missing (no compiler at install), the slots are all taken, or the connector needs Python
at every call (a bridge's support motion), the connector uses the Python path; :attr:`DirectCall.available` and the
connector's ``call_path`` say which ran, and :meth:`DirectCall.counts` proves it: the calls of the slot's function
and how many of them came through Python (zero on the compiled path).
"""
from __future__ import annotations

import contextlib
import os
import re
import warnings
import weakref

import numpy as np
from numba import types
from numba.core import cgutils
from numba.experimental import structref
from numba.extending import intrinsic

from ..jit import compiled
from .connector_core import contact_forces_core
from .core_data import ST_STATS, ST_WARM

try:
    from ..native import direct_force as _native
except ImportError:                 # built without a C++ compiler: the Python path only
    _native = None
#: how many connectors can be on the compiled path at once in a process (the native module's slots)
SLOTS = int(_native.SLOTS) if _native is not None else 0

__all__ = ["SLOTS", "CALL_PATH_ENV", "CALL_PATHS", "compiled_path_wanted", "python_call_path", "HOLD_FLAG", "HOLD_T",
           "N_HOLD", "COUNT_CALLS", "COUNT_REUSED", "N_COUNTS", "CallData", "call_data", "forces_step",
           "KeptEvaluation", "compiled_call", "meminfo_address", "native_step_address", "NATIVE_STEP_TYPE",
           "NATIVE_ARRAY_FIELDS", "DirectCall", "native_available", "pending_state_error", "NATIVE_STATE_ERROR_MARK"]

#: the environment variable that, set to ``python``, keeps every connector on the Python path (to compare the two
#: paths, or to profile the evaluation with Python's tools)
CALL_PATH_ENV = "EXUDYN_WHEELRAIL_CALL_PATH"
#: the values of :data:`CALL_PATH_ENV`
CALL_PATHS = ("compiled", "python")


def compiled_path_wanted() -> bool:
    """Whether connectors take the compiled path when they can (not with :data:`CALL_PATH_ENV` = ``python``);
    another value is a ``ValueError`` naming the variable."""
    value = os.environ.get(CALL_PATH_ENV, CALL_PATHS[0]).strip().lower()
    if value not in CALL_PATHS:
        raise ValueError(f"{CALL_PATH_ENV}={value!r}: expected one of {', '.join(CALL_PATHS)}")
    return value == CALL_PATHS[0]


@contextlib.contextmanager
def python_call_path():
    """Connectors built inside this context take the Python path (:data:`CALL_PATH_ENV` set meanwhile): to time or
    replace the force call from Python (benchmarks), or to compare the two paths."""
    saved = os.environ.get(CALL_PATH_ENV)
    os.environ[CALL_PATH_ENV] = "python"
    try:
        yield
    finally:
        if saved is None:
            os.environ.pop(CALL_PATH_ENV, None)
        else:
            os.environ[CALL_PATH_ENV] = saved


# ---- the kept evaluation's flag and time: call.hold[HOLD_*] -----------------------------------------------------
HOLD_FLAG = 0         # 1.0: an evaluation is kept (evaluate_state), 0.0: none
HOLD_T = 1            # its time [s]
N_HOLD = 2
# ---- counters: call.counts[COUNT_*] -----------------------------------------------------------------------------
COUNT_CALLS = 0       # evaluations of the contact (contact_forces_core)
COUNT_REUSED = 1      # calls answered by the kept evaluation
N_COUNTS = 2


@structref.register
class CallDataType(types.StructRef):
    """Numba type of :class:`CallData`."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class CallData(structref.StructRefProxy):
    """Everything one force evaluation reads and writes (:func:`call_data`): the connector's
    :class:`~.core_data.ContactData`, its force vector and results, the kept evaluation (flag and time, its
    coordinates and velocities, the warm start it started from, its counters' increments) and the counters."""


_FIELDS = ["data", "f", "res", "hold", "hold_q", "hold_q_t", "hold_warm", "hold_stats", "counts"]
structref.define_constructor(CallData, CallDataType, _FIELDS)
structref.define_boxing(CallDataType, CallData)


@compiled
def call_data(data, f, res, hold, hold_q, hold_q_t, hold_warm, hold_stats, counts):
    """The :class:`CallData` of these arrays (see :class:`CallData`; compiled and cached)."""
    return CallData(data, f, res, hold, hold_q, hold_q_t, hold_warm, hold_stats, counts)


@compiled(refcount=False)
def _same_bits(a, b) -> bool:
    """Whether two float64 vectors are equal bit for bit."""
    ai = a.view(np.int64)
    bi = b.view(np.int64)
    for i in range(ai.shape[0]):
        if ai[i] != bi[i]:
            return False
    return True


@compiled
def forces_step(q, q_t, t, call) -> int:
    """One force evaluation at ``(q, q_t, t)`` into ``call.f`` and ``call.res`` (module docstring); returns -1, or
    the index of the wheelset with non-finite coordinates (the number of wheelsets for the modal coordinates)."""
    hold = call.hold
    if hold[HOLD_FLAG] != 0.0:
        hold[HOLD_FLAG] = 0.0
        if t == hold[HOLD_T] and _same_bits(q, call.hold_q) and _same_bits(q_t, call.hold_q_t):
            stats = call.data.state[ST_STATS]
            stats += call.hold_stats
            call.counts[COUNT_REUSED] += 1
            return -1
        call.data.state[ST_WARM][:] = call.hold_warm          # the warm start the kept evaluation started from
    bad = contact_forces_core(q, q_t, t, call.data, call.f, call.res)
    call.counts[COUNT_CALLS] += 1
    return bad


@compiled
def meminfo_address(ref) -> int:
    """The address of a structref's meminfo (what the native module passes as the CallData)."""
    return _meminfo_address(ref)


@intrinsic
def _meminfo_address(typingctx, ref):
    """The address of a structref's payload holder (its meminfo), as an integer."""
    def codegen(context, builder, signature, args):
        st = cgutils.create_struct_proxy(signature.args[0])(context, builder, value=args[0])
        return builder.ptrtoint(st.meminfo, context.get_value_type(types.intp))
    return types.intp(ref), codegen


#: numba's native function type of forces_step for (C-contiguous float64 vectors q, q_t, float t, CallData) -> int64,
#: as the native module calls it (native/direct_force.cpp): status (i32) = f(result*, exception info**, q's fields,
#: q_t's fields, t, the CallData's meminfo).  A numba whose convention differs is not used (the Python path is).
NATIVE_STEP_TYPE = ("i32 (i64*, {i8*, i32, i8*, i8*, i32}**, i8*, i8*, i64, i64, double*, i64, i64, "
                    "i8*, i8*, i64, i64, double*, i64, i64, double, i8*)")
#: the fields of a numba array, in the order the native module passes them
NATIVE_ARRAY_FIELDS = ("meminfo", "parent", "nitems", "itemsize", "data", "shape", "strides")


def native_step_address(entry, dispatcher=None) -> int | None:
    """The address of numba's native function behind ``entry`` (a compiled specialization of ``dispatcher``,
    default :func:`forces_step`, or of another step of its arguments and result whose last argument is a
    structref; :func:`~.core_data.compiled_for`), or None when its calling convention is not the one the native
    module assumes (:data:`NATIVE_STEP_TYPE`, :data:`NATIVE_ARRAY_FIELDS`)."""
    overloads = getattr(forces_step if dispatcher is None else dispatcher, "overloads", None)
    if overloads is None:
        return None
    cres = next((c for c in overloads.values() if c.entry_point is entry), None)
    if cres is None:
        return None
    sig = cres.signature
    vector = types.Array(types.float64, 1, "C")
    if tuple(sig.args[:3]) != (vector, vector, types.float64) or sig.return_type != types.int64:
        return None
    ctx = cres.target_context
    fnty = ctx.call_conv.get_function_type(sig.return_type, sig.args)
    model = ctx.data_model_manager[vector]
    if str(fnty) != NATIVE_STEP_TYPE or tuple(getattr(model, "_fields", ())) != NATIVE_ARRAY_FIELDS:
        return None
    return int(cres.library.get_pointer_to_function(cres.fndesc.llvm_func_name))


def native_available() -> bool:
    """Whether the native module of the compiled path was built."""
    return _native is not None


_LIVE: dict = {}       # slot -> weak reference to its DirectCall
#: what the native function's exception for a bad state says (native/direct_force.cpp), and Exudyn's report of it
NATIVE_STATE_ERROR_MARK = "has non-finite coordinates (or the modal coordinates, if it is the last)"
_SLOT_MARK = re.compile(r"\[compiled call slot (\d+)\]")


class KeptEvaluation:
    """The evaluation :meth:`~.connector.WheelRailContact.evaluate_state` keeps for the next force call, in the
    arrays :class:`CallData` holds (``arrays``): the flag and time, the coordinates, the warm start it started from
    and its counters' increments.  :func:`forces_step` takes it (a call at exactly its state) or puts back its warm
    start; from Python: :meth:`begin` (before the evaluation), :meth:`keep` (after it), :meth:`abort` (it failed),
    :meth:`discard`, :meth:`warm_start` (the one the kept evaluation started from, else the current one) and
    :meth:`clear`."""

    def __init__(self, n: int, warm: np.ndarray, stats: np.ndarray):
        self.hold = np.zeros(N_HOLD)
        self.q, self.q_t = np.zeros(n), np.zeros(n)
        self.warm0, self.dstats = np.zeros_like(warm), np.zeros_like(stats)
        self._warm, self._stats = warm, stats
        self._stats0 = np.zeros_like(stats)

    @property
    def arrays(self) -> tuple:
        """``(hold, q, q_t, warm0, dstats)`` as :func:`call_data` takes them."""
        return self.hold, self.q, self.q_t, self.warm0, self.dstats

    def begin(self) -> None:
        self.discard()
        self.warm0[:] = self._warm
        self._stats0[:] = self._stats

    def abort(self) -> None:
        self._warm[:] = self.warm0

    def keep(self, q, q_t, t: float) -> None:
        np.subtract(self._stats, self._stats0, out=self.dstats)
        self.q[:] = q
        self.q_t[:] = q_t
        self.hold[HOLD_T] = float(t)
        self.hold[HOLD_FLAG] = 1.0

    def discard(self) -> None:
        """Drop the kept evaluation (if any), putting back the warm start it started from."""
        if self.hold[HOLD_FLAG] != 0.0:
            self._warm[:] = self.warm0
            self.hold[HOLD_FLAG] = 0.0

    def warm_start(self) -> np.ndarray:
        return (self.warm0 if self.hold[HOLD_FLAG] != 0.0 else self._warm).copy()

    def clear(self) -> None:
        """Forget the kept evaluation without touching the warm start."""
        self.hold[HOLD_FLAG] = 0.0


class DirectCall:
    """A slot of the native module for one connector's :class:`CallData` (module docstring).

    ``available`` is False (and :attr:`function` None) without the native module or a free slot.  The slot is bound
    to the compiled evaluation by :meth:`bind`, which the slot function calls (through Python, once) at its first
    call when nobody did before: a model is built without waiting for a compilation.  ``compiled_step()`` gives the
    compiled specialization of :func:`forces_step` for the connector's arguments (compiling or loading it).  A numba
    whose native convention differs leaves the slot unbound: its function then calls ``python_forces(q, q_t, t)``
    (the connector's Python path) through Python.  The slot is released when this object goes away."""

    def __init__(self, call: CallData, n: int, f: np.ndarray, compiled_step, python_forces, on_bad_state):
        self.slot = -1
        self.function = None
        self.bound = None                 # None: not tried yet; True: compiled; False: the Python path
        self._context = None              # the context of a step bound by bind_step (None: forces_step's)
        self._call = call                 # kept alive: the slot holds its meminfo and its force vector
        self._f = f
        self._compiled_step = compiled_step
        self._python_forces = weakref.WeakMethod(python_forces)
        self._on_bad_state = weakref.WeakMethod(on_bad_state)
        if _native is None:
            return
        slot = _native.acquire(int(n), _Binder(weakref.ref(self)))
        if slot < 0:
            return
        self.slot = slot
        self.function = getattr(_native, f"force_{slot}")
        _LIVE[slot] = weakref.ref(self)
        weakref.finalize(self, _release, slot)

    @property
    def available(self) -> bool:
        return self.function is not None

    def bind(self) -> bool:
        """Bind the slot to the compiled evaluation (once); whether it is bound (False: numba's native convention
        is not the assumed one, the slot's function takes the Python path)."""
        if self.bound is None and self.available:
            address = native_step_address(self._compiled_step())
            if address is not None:
                _native.bind(self.slot, address, meminfo_address(self._call), self._f.ctypes.data)
            self.bound = address is not None
        return bool(self.bound)

    def bind_step(self, entry, dispatcher, context) -> bool:
        """Bind the slot to another compiled step (``entry``, a specialization of ``dispatcher`` with
        :func:`forces_step`'s native type whose last argument, the structref ``context``, leads to this slot's
        :class:`CallData`, e.g. a run's watch around :func:`forces_step`); whether it is bound (False: the slot
        is not on the compiled path, or the step's convention differs; nothing changed).  :meth:`bind_plain` puts
        :func:`forces_step` back."""
        if not self.bind():
            return False
        address = native_step_address(entry, dispatcher)
        if address is None:
            return False
        self._context = context           # kept alive while the slot holds its meminfo
        _native.bind(self.slot, address, meminfo_address(context), self._f.ctypes.data)
        return True

    def bind_plain(self) -> None:
        """Bind the slot to :func:`forces_step` again after :meth:`bind_step`."""
        if self._context is None:
            return
        _native.bind(self.slot, native_step_address(self._compiled_step()), meminfo_address(self._call),
                     self._f.ctypes.data)
        self._context = None

    def take_python_path(self) -> None:
        """From now on the slot's function calls the connector's Python path (e.g. a support motion was added,
        which only the Python path evaluates)."""
        self.bound = False
        self._context = None
        if self.available:
            _native.unbind(self.slot)

    def python_forces(self, t, q, q_t):
        forces = self._python_forces()
        if forces is None:
            raise RuntimeError("wheel-rail contact: the connector of this force call no longer exists")
        return forces(q, q_t, t)

    def counts(self) -> tuple[int, int]:
        """``(calls, of which through Python)`` of the slot's function since it was bound."""
        return tuple(_native.counts(self.slot)) if self.available else (0, 0)

    def bad_state(self):
        """``(code, t)`` of the latest bad state the compiled path met since the last question (code -1: none)."""
        if not self.available:
            return -1, 0.0
        code, t = _native.bad_state(self.slot)
        return int(code), float(t)

    def state_error(self, code: int, t: float):
        """The connector's exception for a bad state (None once the connector is gone)."""
        make = self._on_bad_state()
        return make(code, t) if make is not None else None


class _Binder:
    """What the native slot calls: ``binder()`` before its first use (binds it; a weak reference, so that the slot
    does not keep its :class:`DirectCall` alive) and ``binder.forces(t, q, q_t)`` where it could not be bound."""

    def __init__(self, ref):
        self._ref = ref

    def _direct(self) -> DirectCall:
        direct = self._ref()
        if direct is None:
            raise RuntimeError("wheel-rail contact: the connector of this force call no longer exists")
        return direct

    def __call__(self) -> bool:
        return self._direct().bind()

    def forces(self, t, q, q_t):
        return self._direct().python_forces(t, q, q_t)


def compiled_call(call: CallData, n: int, f: np.ndarray, compiled_step, python_forces, on_bad_state, name: str,
                  structure=None) -> DirectCall | None:
    """The compiled path of a connector (:class:`DirectCall`), or None where it takes the Python path: not wanted
    (:data:`CALL_PATH_ENV`), the native module missing, a ``structure`` with a support motion (evaluated in Python
    at every call), or no free slot (with a warning).  A support motion added to ``structure`` later switches the
    slot to the Python path."""
    if not compiled_path_wanted() or _native is None:
        return None
    if structure is not None and structure.support_motion is not None:
        return None
    direct = DirectCall(call, n, f, compiled_step, python_forces, on_bad_state)
    if not direct.available:
        warnings.warn(f"{name}: every compiled call slot is taken ({SLOTS} connectors alive in this process); this "
                      "one takes the Python path (slower, the same numbers)", stacklevel=3)
        return None
    if structure is not None:
        structure.support_motion_listeners.append(weakref.WeakMethod(direct.take_python_path))
    return direct


def _release(slot: int) -> None:
    _LIVE.pop(slot, None)
    if _native is not None:
        _native.release(slot)


def pending_state_error(text: str):
    """The connector's :class:`~.connector.ContactStateError` for the bad state the compiled path reported in
    ``text`` (Exudyn's report of the native function's exception names the slot), or None; takes the slot's
    record."""
    m = _SLOT_MARK.search(text)
    ref = _LIVE.get(int(m.group(1))) if m else None
    direct = ref() if ref is not None else None
    if direct is None:
        return None
    code, t = direct.bad_state()
    return direct.state_error(code, t) if code >= 0 else None
