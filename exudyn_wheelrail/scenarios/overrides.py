r"""Dotted-key overrides of a normalised scenario (:mod:`.spec`): ``vehicle.speed_km_h``, ``track.0.amplitude_m``,
``structure.section.m_kg_m`` — what ``--set``, ``--param`` and :mod:`.sweep` apply."""
from __future__ import annotations

import copy
import tomllib

from .spec import V1_MOVED, ScenarioError, validate_scenario

__all__ = ["parse_value", "set_dotted", "apply_overrides"]


def parse_value(text: str):
    """A command-line value: a TOML value (``250``, ``1e-3``, ``true``, ``"x"``, ``[20, 40]``) or else the plain
    string (``newmark``, ``auto``)."""
    text = text.strip()
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def set_dotted(scn: dict, key: str, value) -> None:
    """Set ``scn[a][b]...`` for the dotted key ``a.b...`` in place; integers index arrays (``track.0.start_m``).
    The parent must exist (a missing optional table, ``contact`` or ``run``, is created); the key itself may be new
    (validation judges it).  The keys of :data:`V1_MOVED` are moved to their version-2 place."""
    if not isinstance(key, str) or not key or any(not p for p in key.split(".")):
        raise ScenarioError(f"parameter {key!r}: expected a dotted key such as vehicle.speed_km_h or "
                            "track.0.amplitude_m")
    key = V1_MOVED.get(key, key)
    parts = key.split(".")
    if parts[0] in ("contact", "run") and isinstance(scn, dict):
        scn.setdefault(parts[0], {})
    node = scn
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        where = ".".join(parts[:depth]) or "the top level"
        if isinstance(node, list):
            try:
                i = int(part)
            except ValueError:
                raise ScenarioError(f"parameter {key!r}: {where} is an array: expected an index, "
                                    f"got {part!r}") from None
            if not 0 <= i < len(node):
                raise ScenarioError(f"parameter {key!r}: {where} has {len(node)} entr"
                                    f"{'y' if len(node) == 1 else 'ies'} (index {i} out of range)")
            if last:
                node[i] = value
            else:
                node = node[i]
        elif isinstance(node, dict):
            if last:
                node[part] = value
            elif part not in node:
                raise ScenarioError(f"parameter {key!r}: no {'.'.join(parts[:depth + 1])!r} in the scenario")
            else:
                node = node[part]
        else:
            raise ScenarioError(f"parameter {key!r}: {where} is a value ({node!r}), not a table or an array")


def apply_overrides(scenario: dict, overrides: dict, source: str = "<overrides>") -> dict:
    """A validated copy of the normalised ``scenario`` with the dotted-key ``overrides`` applied."""
    scn = copy.deepcopy(scenario)
    for key, value in overrides.items():
        set_dotted(scn, key, value)
    return validate_scenario(scn, source=source, default_name=scenario.get("scenario", {}).get("name", "scenario"))
