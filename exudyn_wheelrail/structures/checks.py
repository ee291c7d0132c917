"""The check of a number given to a structure model (a deck section, a bridge, a support motion, a moving force):
a float, finite unless told otherwise, and positive or non-negative where asked; the message names the input."""
from __future__ import annotations

import math

__all__ = ["checked_number"]


def checked_number(name, value, *, positive=False, non_negative=False, allow_inf=False):
    """``float(value)``: ``TypeError`` if it is not a number, ``ValueError`` naming ``name`` if it is NaN, infinite
    (unless ``allow_inf``), not > 0 (``positive``) or negative (``non_negative``)."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name}={value!r}: expected a number") from None
    if math.isnan(x) or (math.isinf(x) and not allow_inf):
        raise ValueError(f"{name}={value!r}: expected a finite number")
    if positive and not x > 0.0:
        raise ValueError(f"{name}={value!r}: expected a value > 0")
    if non_negative and not x >= 0.0:
        raise ValueError(f"{name}={value!r}: expected a value >= 0")
    return x

