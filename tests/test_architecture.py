"""The package's structure: a layered house (docs/README.md, section "Architecture").

Read from the package's own source (every ``import`` statement, at module level or inside a function): each folder
(and each module at the top of the package) sits on one floor of :data:`FLOORS`, and an import goes to the same
folder or to a floor below — never up, never sideways between two folders of one floor; so no import cycle spans two
folders.  No module imports another module's private name (``_x``): what two modules share has a public name where
it is owned.  No package file is longer than :data:`MAX_LINES`.  These are the rules of docs/README.md, written once
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
    ("cli", "cli.py"),
    ("__main__.py",),
)
#: the longest package file [lines]
MAX_LINES = 700


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


def test_every_import_goes_to_the_same_folder_or_a_floor_below():
    wrong = []
    for module in MODULES:
        unit = _unit(module)
        for target, _, line in _imports(module):
            other = _unit(target)
            if unit is None or other is None or other == unit:
                continue
            if _floor(other) >= _floor(unit):
                wrong.append(f"{MODULES[module].relative_to(PACKAGE.parent)}:{line} imports {target} "
                             f"({unit} on floor {_floor(unit)}, {other} on floor {_floor(other)})")
    assert not wrong, "\n".join(wrong)


def test_no_module_imports_another_modules_private_name():
    private = [f"{MODULES[m].relative_to(PACKAGE.parent)}:{line} imports {name} from {target}"
               for m in MODULES for target, name, line in _imports(m)
               if name is not None and name.startswith("_") and not name.startswith("__") and target != m]
    assert not private, "\n".join(private)


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_package_file_is_longer_than_the_limit(module):
    n = MODULES[module].read_text(encoding="utf-8").count("\n")
    assert n <= MAX_LINES, f"{MODULES[module].relative_to(PACKAGE.parent)}: {n} lines (split it by job)"


def test_the_checks_see_an_upward_import_and_a_private_one():
    """The reading itself: a planted upward import and a private import inside a function are found (guards
    against a check that cannot fail, e.g. a parser that stops seeing relative imports)."""
    probe = "exudyn_wheelrail.contact.probe"
    src = "from ..simulation.runner import run\n\ndef f():\n    from ..profiles.validation import _x\n"
    found = list(_imports(probe, src))
    assert ("exudyn_wheelrail.simulation.runner", "run", 1) in found
    assert ("exudyn_wheelrail.profiles.validation", "_x", 4) in found
    assert _floor(_unit("exudyn_wheelrail.simulation.runner")) > _floor(_unit(probe))
