"""The package's structure: a layered house (docs/README.md, section "Architecture").

Read from the package's own source (every ``import`` statement, at module level or inside a function): each folder
(and each module at the top of the package) sits on one floor of :data:`FLOORS`, and an import goes to the same
folder or to a floor below — never up, never sideways between two folders of one floor; so no import cycle spans two
folders.  No module imports another module's private name (``_x``): what two modules share has a public name where
it is owned.  Only the front ends (the command line, the interactive tools) import package modules inside functions,
to defer a heavy import for start-up; the few other deferred imports are listed with their reason
(:data:`DEFERRED`).  No package file is longer than :data:`MAX_LINES`.  These are the rules of docs/README.md, written once
more here as the reference the code is held against.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "exudyn_wheelrail"

#: the floors, lowest first: a unit (a folder, or a module at the top of the package) imports only its own floor's
#: unit or units of lower floors
FLOORS = (
    ("processes.py", "native"),
    ("conventions.py", "jit.py", "standards.py", "contact_defaults.py", "validation.py"),
    ("profiles",),
    ("contact",),
    ("creep", "analysis"),
    ("structures",),
    ("track",),
    ("rolling_stock",),
    ("multibody",),
    ("simulation",),
    ("scenarios",),
    ("interactive",),
    ("cli",),
    ("__main__.py",),
)
#: the longest package file [lines]
MAX_LINES = 700
#: the units whose functions may import package modules (front ends deferring a heavy import for start-up)
FRONT_ENDS = ("cli", "interactive")
#: the other imports of a package module inside a function, each with its reason (file, imported module)
DEFERRED = {
    # the input check of a scenario file loads the rolling-stock readers only for a scenario that names a train or
    # overrides vehicle values (13 modules, ~0.13 s)
    ("exudyn_wheelrail/scenarios/spec.py", "exudyn_wheelrail.rolling_stock.train"),
    ("exudyn_wheelrail/scenarios/spec.py", "exudyn_wheelrail.rolling_stock.vehicle_data"),
    # the deck outputs need the moving-force reference only when they compute it (spec imports deck for its choices)
    ("exudyn_wheelrail/scenarios/deck.py", "exudyn_wheelrail.scenarios.moving_forces"),
}


def _modules() -> dict[str, Path]:
    out = {}
    for path in PACKAGE.rglob("*.py"):
        rel = path.relative_to(PACKAGE.parent).with_suffix("")
        name = ".".join(rel.parts)
        out[name[: -len(".__init__")] if name.endswith(".__init__") else name] = path
    return out


MODULES = _modules()


def _unit(module: str) -> str | None:
    """The folder or top-level module a module belongs to (None: the package's face itself)."""
    parts = module.split(".")
    if len(parts) == 1:
        return None
    if len(parts) == 2 and MODULES[module].name != "__init__.py":
        return parts[1] + ".py"
    return parts[1]


def _function_imports(module: str, source: str | None = None):
    """The imported modules of the package imports that stand inside a function of ``module``."""
    text = source if source is not None else MODULES[module].read_text(encoding="utf-8")
    inner = {(n.lineno, a.name) for f in ast.walk(ast.parse(text)) if isinstance(f, (ast.FunctionDef,
                                                                                      ast.AsyncFunctionDef))
             for n in ast.walk(f) if isinstance(n, (ast.Import, ast.ImportFrom)) for a in n.names}
    return sorted({target for target, name, line in _imports(module, source)
                   if (line, name if name is not None else target.rsplit(".", 1)[1]) in inner})


def _imports(module: str, source: str | None = None):
    """(imported module, imported name or None, line) for every import of a package module in ``module`` (its
    file, or ``source`` for a module that is not one of the package's files)."""
    path = MODULES.get(module)
    base = module if path is not None and path.name == "__init__.py" else module.rsplit(".", 1)[0]
    text = source if source is not None else path.read_text(encoding="utf-8")
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                target = base
                for _ in range(node.level - 1):
                    target = target.rsplit(".", 1)[0]
                target = f"{target}.{node.module}" if node.module else target
            else:
                target = node.module or ""
            for alias in node.names:
                if f"{target}.{alias.name}" in MODULES:
                    yield f"{target}.{alias.name}", None, node.lineno
                elif target in MODULES:
                    yield target, alias.name, node.lineno
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name in MODULES:
                    yield alias.name, None, node.lineno


def _floor(unit: str) -> int:
    for i, units in enumerate(FLOORS):
        if unit in units:
            return i
    raise AssertionError(f"{unit}: not on any floor of FLOORS (a new folder: give it its floor)")


def _upward(module: str, source: str | None = None) -> list[str]:
    """The imports of ``module`` that go up or sideways (to another unit of the same floor or a higher one)."""
    unit, wrong = _unit(module), []
    for target, _, line in _imports(module, source):
        other = _unit(target)
        if unit is None or other is None or other == unit:
            continue
        if _floor(other) >= _floor(unit):
            wrong.append(f"{module}:{line} imports {target} ({unit} on floor {_floor(unit)}, {other} on floor "
                         f"{_floor(other)})")
    return wrong


def _private(module: str, source: str | None = None) -> list[str]:
    """The private names ``module`` imports from another module."""
    return [f"{module}:{line} imports {name} from {target}" for target, name, line in _imports(module, source)
            if name is not None and name.startswith("_") and not name.startswith("__") and target != module]


def _hidden(module: str, source: str | None = None) -> list[str]:
    """The package imports inside functions of ``module`` that are neither a front end's nor listed in DEFERRED."""
    if _unit(module) in FRONT_ENDS:
        return []
    path = str(MODULES[module].relative_to(PACKAGE.parent)) if module in MODULES else module
    return [f"{path} imports {target} inside a function" for target in _function_imports(module, source)
            if (path, target) not in DEFERRED]


def test_every_import_goes_to_the_same_folder_or_a_floor_below():
    wrong = [w for m in MODULES for w in _upward(m)]
    assert not wrong, "\n".join(wrong)


def test_no_module_imports_another_modules_private_name():
    private = [w for m in MODULES for w in _private(m)]
    assert not private, "\n".join(private)


def test_only_the_front_ends_import_inside_functions():
    hidden = [w for m in MODULES for w in _hidden(m)]
    assert not hidden, "\n".join(hidden)
    listed = {(f, t) for f, t in DEFERRED}
    found = {(str(MODULES[m].relative_to(PACKAGE.parent)), t) for m in MODULES for t in _function_imports(m)}
    assert listed <= found, f"DEFERRED lists imports that are gone: {sorted(listed - found)}"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_package_file_is_longer_than_the_limit(module):
    n = MODULES[module].read_text(encoding="utf-8").count("\n")
    assert n <= MAX_LINES, f"{MODULES[module].relative_to(PACKAGE.parent)}: {n} lines (split it by job)"


def test_the_checks_see_an_upward_import_and_a_private_one():
    """The rules themselves on a planted module: an upward import, a private import and an import inside a function
    are each found once, and a downward public module-level import by none (guards against checks that cannot fail,
    e.g. a parser that stops seeing relative imports or a comparison turned the wrong way)."""
    probe = "exudyn_wheelrail.contact.probe"
    src = "from ..simulation.runner import run\n\ndef f():\n    from ..profiles.validation import _x\n"
    found = list(_imports(probe, src))
    assert ("exudyn_wheelrail.simulation.runner", "run", 1) in found
    assert ("exudyn_wheelrail.profiles.validation", "_x", 4) in found
    assert len(_upward(probe, src)) == 1 and "simulation.runner" in _upward(probe, src)[0]
    assert len(_private(probe, src)) == 1 and "_x" in _private(probe, src)[0]
    assert _hidden(probe, src) == [f"{probe} imports exudyn_wheelrail.profiles.validation inside a function"]
    # a downward, public, module-level import is none of these
    fine = "from ..profiles.validation import check_kind\n"
    assert not _upward(probe, fine) and not _private(probe, fine) and not _hidden(probe, fine)
