"""The package's compile decorator (:mod:`exudyn_wheelrail.jit`): what it promises about what gets compiled.

* a kernel called from another kernel with constant arguments is compiled once, for the arguments' types — plain
  numba (the reference) compiles one specialization per constant value;
* a first compilation prints its one-line notice once, and only on a terminal;
* a rigid, straight contact with the online search and a creep law without a table hands ``None`` for every
  optional part (geometry table, the deck's shapes and residual flexibility, the layout, the creep table), and the
  kernels that branch on those arguments compile with ``None`` (the other branch dropped by its type) and give the
  rigid track's values;
* a cached kernel is compiled afresh when any file of the package changes, not only its own;
* two processes adding entries to one kernel's cache at once never leave an entry that loads another
  specialization's machine code;
* ``compile_ahead`` compiles the share set aside in a second process, this process's share here, and nothing when
  the kernel is cached; the shares of the contact kernel and of the connector's call have exactly the types those
  kernels hand their callees (a wrong type would compile a specialization nobody calls).
"""
import io
import os
import shutil
import subprocess
import sys
import types
from pathlib import Path

import pytest
from numba import njit

from exudyn_wheelrail import jit, processes


def _pair(decorate):
    @decorate
    def callee(x, k):
        return x + k

    @decorate
    def caller(x):
        return callee(x, 0) + callee(x, 1) + callee(x, 2)

    return caller, callee


def test_constant_arguments_share_one_specialization():
    caller, callee = _pair(jit.compiled)
    assert caller(1.0) == 6.0
    assert [str(t) for t in callee.signatures[0]] == ["float64", "int64"] and len(callee.signatures) == 1
    # the reference: plain numba compiles the callee once per constant value (this is what the decorator removes)
    caller_ref, callee_ref = _pair(njit)
    assert caller_ref(1.0) == 6.0
    assert len(callee_ref.signatures) == 3


class _Terminal(io.StringIO):
    def __init__(self, tty):
        super().__init__()
        self.tty = tty

    def isatty(self):
        return self.tty


def _event(module):
    func = types.FunctionType((lambda: None).__code__, {}, "f")
    func.__module__ = module
    return types.SimpleNamespace(data={"dispatcher": types.SimpleNamespace(py_func=func)})


def test_compile_notice_once_and_only_on_a_terminal(monkeypatch):
    for tty, expected in ((True, jit.COMPILE_NOTICE + "\n"), (False, "")):
        stream = _Terminal(tty)
        monkeypatch.setattr(sys, "stderr", stream)
        notice = jit._CompileNotice()
        notice.on_start(_event("numpy.other_package"))        # not the package's: no notice, not counted
        assert stream.getvalue() == ""
        notice.on_start(_event("exudyn_wheelrail.contact.kernel"))
        notice.on_start(_event("exudyn_wheelrail.contact.search"))
        assert stream.getvalue() == expected


def test_a_rigid_straight_contact_passes_none_for_every_optional_part():
    """The connector on the rigid straight track with the online search and a law without a table hands the
    compiled call ``None`` where the optional data would be (the geometry table, the deck's shapes and residual
    flexibility, the layout, the creep table): that is what keeps their code from being compiled."""
    import exudyn as exu

    from exudyn_wheelrail.contact import WheelRailPair
    from exudyn_wheelrail.multibody import connector as C
    from exudyn_wheelrail.multibody.core_data import GEO_TABLE, VEH_LAYOUT, VEH_LAYOUT_PAR
    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle

    mbs = exu.SystemContainer().AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=20.0)
    pair = WheelRailPair("S1002", "UIC60", inclination="1/40")
    C.place_on_rails(mbs, model, pair)
    contact = C.add_wheel_rail_contact(mbs, [model.wheelsets[0].node], pair, speed_m_s=20.0, creep_law="fastsim")
    vehicle, _, geometry, creep, deck = contact._model
    assert vehicle[VEH_LAYOUT] is None and vehicle[VEH_LAYOUT_PAR] is None   # no layout
    assert geometry[GEO_TABLE] is None                                # no geometry table
    _, _, _, _, creep_table = creep                                   # creep_model's (code, cp, t_nodes, coef, tab)
    assert creep_table is None                                        # no creep table
    _, _, _, _, node_shapes, node_residual, _ = deck                  # deck_arrays
    assert node_shapes is None and node_residual is None              # no structure: no shapes, no residual


def test_the_none_branches_compile_and_give_the_rigid_values():
    """Each kernel that branches on an optional argument compiles with ``None`` there (numba drops the other
    branch by the argument's type; without that the ``None`` could not be typed) and gives what the rigid straight
    track means: no table forces, no residual flexibility, no deck, a frame that does not turn."""
    import numpy as np

    from exudyn_wheelrail.creep import registry
    from exudyn_wheelrail.multibody import connector_core
    from exudyn_wheelrail.structures import deck_kinematics

    assert registry._table_law(6e-3, 4e-3, 1e-3, 1e-3, 0.1, 5e4, 0.3, 8e10, 4.0, 3.5, None, 3) == (0.0, 0.0, 0.0)
    out = np.full(6, np.nan)
    deck_kinematics.residual_at(1.0, 0.0, np.zeros(1), np.ones(1), np.zeros((1, 2), dtype=np.int64), None, out)
    assert np.all(out == 0.0)                                          # set by assignment: exact
    phi, work = np.full((3, 2), np.nan), np.full(9, np.nan)
    assert not deck_kinematics._shapes_under(1.0, np.zeros(deck_kinematics.N_DECK_PAR), np.zeros(1), np.ones(1),
                                             np.zeros((1, 2), dtype=np.int64), None, np.ones(2), np.ones(2), phi,
                                             work)
    assert connector_core._frame_rate(None, None, 10.0, 30.0, 0.0, np.zeros(8)) == (0.0, 0.0, 0.0)


_OPTIONAL_KERNELS = r"""
from exudyn_wheelrail import jit


@jit.compiled
def only_with_data(x):
    return 2.0 * x


@jit.compiled
def if_else_on_optional(x, data):
    if data is None:
        y = x
    else:
        y = only_with_data(x)
    return y
"""

_OPTIONAL_RUN = r"""
import optional_kernels as k
assert k.if_else_on_optional(3.0, None) == 3.0
print(len(k.only_with_data.signatures))
assert k.if_else_on_optional(3.0, 1.0) == 6.0
print(len(k.only_with_data.signatures))
"""


def test_the_branch_of_a_present_argument_is_not_compiled_when_it_is_none(tmp_path):
    """The form the kernels use for optional data (an ``if``/``else`` on ``x is None`` of an argument): called with
    ``None``, the other branch's callee is never compiled; called with data, it is.  On an empty cache of its own
    (a cached caller would load its callee's code built in, and compile nothing either way)."""
    (tmp_path / "optional_kernels.py").write_text(_OPTIONAL_KERNELS)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), *sys.path]),
               NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    r = subprocess.run([sys.executable, "-c", _OPTIONAL_RUN], env=env, cwd=tmp_path, capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.split() == ["0", "1"]


_RIGID_RUN_COMPILES = r"""
import sys
import exudyn as exu
import numpy as np
from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.multibody import connector as C, connector_core
from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle
from exudyn_wheelrail.structures import deck_kinematics
mbs = exu.SystemContainer().AddSystem()
model = build_vehicle(mbs, "single_wheelset", speed_m_s=20.0)
pair = WheelRailPair("S1002", "UIC60", inclination="1/40")
C.place_on_rails(mbs, model, pair)
contact = C.add_wheel_rail_contact(mbs, [model.wheelsets[0].node], pair, speed_m_s=20.0, creep_law="fastsim")
mbs.Assemble()
contact.warm_up(mbs)
assert connector_core.contact_forces_core.signatures, "the contact call was not compiled"
print(len(connector_core.series_compliance.signatures), len(deck_kinematics.series_contacts.signatures))
"""


def _cached_kernels(folder: Path) -> set:
    """The kernels with a data file in the numba cache ``folder`` (``module.kernel`` names)."""
    return {path.name.split("-")[0] for path in folder.rglob("*.nbc")}


@pytest.mark.validation
def test_a_rigid_track_run_does_not_compile_the_series_solve(tmp_path):
    """A contact on the rigid track, compiled from an empty cache in its own process: the series solve with a
    structure's residual flexibility (``series_compliance``, ``series_contacts``, ~2 s of a first run) is not
    compiled.  (A validation test: it compiles the contact call, ~30 s.)"""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    r = subprocess.run([sys.executable, "-c", _RIGID_RUN_COMPILES], env=env, capture_output=True, text=True,
                       timeout=900)
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.split() == ["0", "0"]                          # not in this process
    compiled_anywhere = _cached_kernels(tmp_path / "cache")        # nor in compile_ahead's second process
    assert "connector_core.contact_geometry" in compiled_anywhere
    assert not {"connector_core.series_compliance", "deck_kinematics.series_contacts"} & compiled_anywhere


def test_a_kernel_compiles_afresh_when_another_file_of_the_package_changes(tmp_path):
    """A cached kernel whose machine code has a constant of another module built in: after that module alone
    changes, a new process gets the new value (the cache carries the whole package's source digest).  The
    reference, plain ``numba.njit(cache=True)``, keys its cache on the kernel's own file only and keeps running the
    old constant — the stale code this rules out.  Each run is a fresh process on a copy of the package with its
    own numba cache and no bytecode files (the two versions of the constant's file have the same size)."""
    pkg = tmp_path / "exudyn_wheelrail"
    shutil.copytree(Path(jit.__file__).parent, pkg, ignore=shutil.ignore_patterns("__pycache__"))
    (pkg / "_probe_constant.py").write_text("VALUE = 1.0\n")
    (pkg / "_probe_kernels.py").write_text(
        "from numba import njit\n\nfrom ._probe_constant import VALUE\nfrom .jit import compiled\n\n\n"
        "@compiled\ndef package_kernel():\n    return VALUE\n\n\n"
        "@njit(cache=True)\ndef plain_kernel():\n    return VALUE\n")
    env = dict(os.environ, PYTHONPATH=str(tmp_path), NUMBA_CACHE_DIR=str(tmp_path / "numba_cache"),
               PYTHONDONTWRITEBYTECODE="1")
    code = ("import exudyn_wheelrail as p; from exudyn_wheelrail import _probe_kernels as k; "
            "print(p.__file__, k.package_kernel(), k.plain_kernel(), k.package_kernel.stats.cache_hits.total())")

    def run():
        out = subprocess.run([sys.executable, "-c", code], env=env, cwd=tmp_path, capture_output=True, text=True,
                             check=True).stdout.split()
        assert Path(out[0]).is_relative_to(tmp_path)               # the copy, not the installed package
        return out[1:]

    assert run() == ["1.0", "1.0", "0"]                          # compiled and cached
    assert run() == ["1.0", "1.0", "1"]                          # loaded from the cache: nothing changed
    (pkg / "_probe_constant.py").write_text("VALUE = 2.0\n")
    assert run() == ["2.0", "1.0", "0"]                          # compiled afresh; plain numba: stale


def test_two_processes_adding_to_one_cache_never_mix_up_entries(tmp_path):
    """Two processes add a specialization of one kernel each: B writes its index entry, A (which read the index
    before that) writes its own, and B's data file lands last.  numba's own cache names a data file by the entries
    its index had when read (both pick number 1): A's entry then loads B's machine code.  The package's cache names
    each data file by its key: A's entry loads A's code (B's entry may be lost from the index — compiled again
    later — never mixed up)."""
    def files(kind):
        return kind(cache_path=str(tmp_path / kind.__name__), filename_base="kernel-1.py311", source_stamp="s")

    for kind, mixed_up in ((jit.IndexDataCacheFile, True), (jit._KeyedDataFile, False)):
        (tmp_path / kind.__name__).mkdir()
        a, b = files(kind), files(kind)
        deferred = []
        write_data = b._save_data
        b._save_data = lambda name, data: deferred.append((name, data))
        b.save("key-float64", b"code for float64")       # B: index entry written, its data file still to come
        a._load_index = lambda: {}                         # A read the index before B wrote it
        a.save("key-int64", b"code for int64")
        write_data(*deferred[0])                           # B's data file lands last
        reader = files(kind)
        if mixed_up:
            assert reader.load("key-int64") == b"code for float64"
        else:
            assert reader.load("key-int64") == b"code for int64"
            assert reader.load("key-float64") in (None, b"code for float64")


_AHEAD_KERNELS = """
from exudyn_wheelrail.jit import compiled


@compiled
def leaf_here(x):
    return 2.0 * x


@compiled
def leaf_aside(x):
    return x + 1.0


@compiled
def top(x):
    return leaf_here(x) + leaf_aside(x)
"""

_AHEAD_RUN = r"""
import os, sys
from exudyn_wheelrail import jit, processes
import ahead_kernels as k
started = []
popen = processes.subprocess.Popen
processes.subprocess.Popen = lambda *a, **kw: started.append(1) or popen(*a, **kw)
pending = jit.compile_ahead(k.top, (1.0,), [(k.leaf_here, (1.0,))], [(k.leaf_aside, (1.0,))])
here_now = len(k.leaf_here.signatures)
aside_now = len(k.leaf_aside.signatures)
pending.wait()
aside_cached = jit._is_cached(k.leaf_aside, (jit.numba.float64,))
value = k.top(1.0)
print(len(started), here_now, aside_now, aside_cached, value, k.leaf_aside.stats.cache_hits.total())
"""


def test_compile_ahead_compiles_the_share_set_aside_in_a_second_process(tmp_path):
    """On an empty cache: one second process compiles the share set aside into the cache (not this process), this
    process compiles its own share, and the kernel then loads the other share from the cache and gives the right
    value.  Run again: the kernel is cached, so no process is started and nothing is compiled ahead.  With
    ``COMPILE_AHEAD_ENV=0`` on an empty cache: no process, both shares compiled here."""
    (tmp_path / "ahead_kernels.py").write_text(_AHEAD_KERNELS)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), *sys.path]),
               NUMBA_CACHE_DIR=str(tmp_path / "cache"), **{jit.COMPILE_AHEAD_ENV: "1"})

    def run(**extra):
        r = subprocess.run([sys.executable, "-c", _AHEAD_RUN], env={**env, **extra}, cwd=tmp_path,
                           capture_output=True, text=True, timeout=300)
        assert r.returncode == 0, r.stderr[-2000:]
        return r.stdout.split()

    if processes.cpus() > 1:
        assert run() == ["1", "1", "0", "True", "4.0", "1"]      # the aside share loaded by the kernel's compile
    else:
        assert run() == ["0", "1", "1", "True", "4.0", "0"]      # one CPU: both shares compiled here
    assert run() == ["0", "0", "0", "True", "4.0", "0"]          # cached: nothing ahead, the kernel loaded
    one_process = {"NUMBA_CACHE_DIR": str(tmp_path / "cache-one"), jit.COMPILE_AHEAD_ENV: "0"}
    assert run(**one_process) == ["0", "1", "1", "True", "4.0", "0"]   # kept in one process: both here


def test_a_new_source_versions_entries_replace_the_old_ones_files(tmp_path):
    """Data files are named by source version and key: the new version's entry of the same key gets another file,
    and the old version's files go when the new version's index replaces the old one (nothing piles up)."""
    def files(stamp):
        return jit._KeyedDataFile(cache_path=str(tmp_path), filename_base="kernel-1.py311", source_stamp=stamp)

    old, new = files("old source"), files("new source")
    old.save("key-float64", b"old code")
    old.save("key-int64", b"old code for int64")
    assert len(list(tmp_path.glob("*.nbc"))) == 2
    new.save("key-float64", b"new code")
    assert [p.name for p in tmp_path.glob("*.nbc")] == [new.key_name("key-float64")]
    assert new.load("key-float64") == b"new code" and new.load("key-int64") is None
    assert old.load("key-float64") is None          # the old version's index is gone


def test_the_index_lock_excludes_a_second_holder(tmp_path):
    """The cache index's lock (POSIX): a second holder gets it only after the first released it."""
    import threading
    import time

    if jit.fcntl is None:
        pytest.skip("no fcntl: the index is written unlocked")
    order, held = [], threading.Event()

    def first():
        with jit._index_lock(str(tmp_path)):
            held.set()
            time.sleep(0.2)
            order.append("first released")

    thread = threading.Thread(target=first)
    thread.start()
    held.wait()
    with jit._index_lock(str(tmp_path)):
        order.append("second holds")
    thread.join()
    assert order == ["first released", "second holds"]


def test_the_contact_waits_for_the_second_process_before_its_first_call(monkeypatch):
    """The contact's first evaluation waits for the second process before it calls the kernel (the kernel's
    compilation must find the share set aside in the cache), and no later evaluation starts another."""
    import numpy as np

    from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
    from exudyn_wheelrail.contact import kernel as K
    from exudyn_wheelrail.contact import wheelset

    events = []

    class Waited:
        def wait(self):
            events.append("wait")

    def ahead(kernel, args, here, aside):
        events.append("ahead")
        return Waited()

    monkeypatch.setattr(wheelset, "compile_ahead", ahead)
    monkeypatch.setattr(K, "evaluate_wheels", lambda *a: events.append("kernel"))
    contact = WheelsetContact(WheelRailPair("S1002", "UIC60", inclination="1/40"))
    pose = np.array([[0.0, contact.pair.nominal_axle_height_m(), 0.0]])
    contact.evaluate(pose)
    contact.evaluate(pose)
    assert events == ["ahead", "wait", "kernel", "kernel"]


def _assert_shares_are_callee_types(kernel, sig, here, aside, monkeypatch):
    """Every job of the shares is a call ``kernel`` makes when compiled for ``sig``: an uncached copy of the
    kernel is compiled here, each share's dispatcher recording the argument types the copy's typing asks it for
    (the callee then loaded from the cache or compiled)."""
    from numba import types as nt

    requested = {}
    jobs = [*here, *aside]
    for dispatcher, _ in jobs:
        def recording(args, kws, d=dispatcher, inner=dispatcher.get_call_template):
            requested.setdefault(d, set()).add(tuple(nt.unliteral(a) for a in args))
            return inner(args, kws)
        monkeypatch.setattr(dispatcher, "get_call_template", recording)
    njit(kernel.py_func).compile(sig)
    for dispatcher, args in jobs:
        assert jit._signature(args) in requested.get(dispatcher, ()), dispatcher.py_func.__name__


def test_the_contact_kernels_shares_have_its_callees_types(monkeypatch):
    """:func:`~exudyn_wheelrail.contact.kernel.compile_shares`: every job is a specialization the kernel's region
    solve calls (compiled for the region solve's own signature, the one the kernel calls it with)."""
    import numpy as np

    from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
    from exudyn_wheelrail.contact import kernel as K

    contact = WheelsetContact(WheelRailPair("S1002", "UIC60", inclination="1/40"))
    args = (contact.nodes, contact.meta, contact.mono, contact.curve_ids, np.zeros((2, 3)), contact.warm,
            contact.params, contact.out, contact.scan)
    region = []                     # the region solve's signature, as the kernel calls it
    monkeypatch.setattr(K._solve_region, "get_call_template",
                        lambda a, kw, inner=K._solve_region.get_call_template: region.append(a) or inner(a, kw))
    scratch = np.empty((K.N_SCRATCH_ROWS, K.SCRATCH_WIDTH))
    njit(K.solve_wheels.py_func).compile(jit._signature(args + (scratch,)))
    monkeypatch.undo()
    assert region
    _assert_shares_are_callee_types(K._solve_region, tuple(region[0]), *K.compile_shares(*args), monkeypatch)


def test_the_connector_calls_shares_have_its_callees_types(monkeypatch):
    """:func:`~exudyn_wheelrail.multibody.connector_core.compile_shares`: every job is a specialization the
    connector's force call calls, for the arguments the connector passes."""
    import exudyn as exu

    from exudyn_wheelrail.contact import WheelRailPair
    from exudyn_wheelrail.multibody import connector as C
    from exudyn_wheelrail.multibody import connector_core
    from exudyn_wheelrail.rolling_stock.vehicle_builder import build_vehicle

    mbs = exu.SystemContainer().AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=20.0)
    pair = WheelRailPair("S1002", "UIC60", inclination="1/40")
    C.place_on_rails(mbs, model, pair)
    contact = C.add_wheel_rail_contact(mbs, [model.wheelsets[0].node], pair, speed_m_s=20.0)
    shares = connector_core.compile_shares(contact._f, contact._f, 0.0, contact._model, contact._state,
                                           contact._work, contact._f, contact.results)
    _assert_shares_are_callee_types(connector_core.contact_forces_core, jit._signature(contact._core_args()),
                                    *shares, monkeypatch)
