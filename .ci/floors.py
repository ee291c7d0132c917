"""Print pip constraints that pin every dependency of pyproject.toml (with the 'test' extra) to its lower bound.

The lower bounds are declared once, in pyproject.toml; this turns them into '==' pins for a run against the floors.
"""
import re
import sys
import tomllib
from pathlib import Path

project = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())["project"]
requirements = project["dependencies"] + project["optional-dependencies"]["test"]
for req in requirements:
    m = re.match(r"^\s*([A-Za-z0-9_.-]+)(\[[^\]]*\])?\s*(.*)$", req)
    name, spec = m.group(1), m.group(3)
    floor = re.search(r">=\s*([0-9][^,\s;]*)", spec)
    if floor is None:
        sys.exit(f"pyproject.toml: {req!r} has no '>=' lower bound")
    print(f"{name}=={floor.group(1)}")
