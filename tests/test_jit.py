"""The package's compile decorator (:mod:`exudyn_wheelrail.jit`): what it promises about what gets compiled.

* a kernel called from another kernel with constant arguments is compiled once, for the arguments' types — plain
  numba (the reference) compiles one specialization per constant value;
* a first compilation prints its one-line notice once, and only on a terminal;
* a rigid, straight contact with the online search and a creep law without a table hands ``None`` for every
  optional part (geometry table, the deck's shapes and residual flexibility, the layout, the creep table), and the
  kernels that branch on those arguments compile with ``None`` (the other branch dropped by its type) and give the
  rigid track's values;
* a cached kernel is compiled afresh when any file of the package changes, not only its own.
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

from exudyn_wheelrail import jit


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

    assert registry._table_law(6e-3, 4e-3, 1e-3, 1e-3, 0.1, 5e4, 0.3, 8e10, 4.0, 3.5, None) == (0.0, 0.0, 0.0)
    out = np.full(6, np.nan)
    deck_kinematics.residual_at(1.0, 0.0, np.zeros(1), np.ones(1), np.zeros((1, 2), dtype=np.int64), None, out)
    assert np.all(out == 0.0)                                          # set by assignment: exact
    phi, work = np.full((3, 2), np.nan), np.full(9, np.nan)
    assert not deck_kinematics._shapes_under(1.0, np.zeros(deck_kinematics.N_DECK_PAR), np.zeros(1), np.ones(1),
                                             np.zeros((1, 2), dtype=np.int64), None, np.ones(2), np.ones(2), phi,
                                             work)
    assert connector_core._frame_rate(None, None, 10.0, 30.0, 0.0, np.zeros(8)) == (0.0, 0.0, 0.0)


@jit.compiled
def _only_with_data(x):
    return 2.0 * x


@jit.compiled
def _if_else_on_optional(x, data):
    if data is None:
        y = x
    else:
        y = _only_with_data(x)
    return y


def test_the_branch_of_a_present_argument_is_not_compiled_when_it_is_none():
    """The form the kernels use for optional data (an ``if``/``else`` on ``x is None`` of an argument): called with
    ``None``, the other branch's callee is never compiled; called with data, it is."""
    assert _if_else_on_optional(3.0, None) == 3.0
    assert _only_with_data.signatures == []
    assert _if_else_on_optional(3.0, 1.0) == 6.0
    assert len(_only_with_data.signatures) == 1


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


@pytest.mark.validation
def test_a_rigid_track_run_does_not_compile_the_series_solve(tmp_path):
    """A contact on the rigid track, compiled from an empty cache in its own process: the series solve with a
    structure's residual flexibility (``series_compliance``, ``series_contacts``, ~2 s of a first run) is not
    compiled.  (A validation test: it compiles the contact call, ~30 s.)"""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    r = subprocess.run([sys.executable, "-c", _RIGID_RUN_COMPILES], env=env, capture_output=True, text=True,
                       timeout=900)
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.split() == ["0", "0"]


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
