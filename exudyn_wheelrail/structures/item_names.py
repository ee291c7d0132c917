"""Unique names of the Exudyn items of a structure (a bridge, its moving forces, its support-motion load)."""
from __future__ import annotations

__all__ = ["unique_name"]


def unique_name(mbs, base: str) -> str:
    """``base``, or ``base_2``, ``base_3``, … — the first name no object or node of ``mbs`` uses yet (with the
    node names this module derives from it)."""
    if not isinstance(base, str) or not base:
        raise ValueError(f"name={base!r}: expected a non-empty string")
    k = 1
    while True:
        cand = base if k == 1 else f"{base}_{k}"
        used = (int(mbs.GetObjectNumber(cand)) != -1
                or any(int(mbs.GetNodeNumber(n)) != -1 for n in (f"{cand}_modal", f"{cand}_ground",
                                                                 "NodeRigidBody:" + cand, "NodeGeneric:" + cand)))
        if not used:
            return cand
        k += 1
