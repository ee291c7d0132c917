"""Tasks for the sweep executors' fault tests (``tests/test_sweep_faults.py``), in a module of their own so that a
spawned worker process can import them."""
from __future__ import annotations

import os
from pathlib import Path


def die_once(marker: str, value):
    """Kills its worker process the first time (``marker`` does not exist yet), returns ``value`` after."""
    path = Path(marker)
    if not path.exists():
        path.write_text("died")
        os._exit(3)
    return value


def die_always(value):
    """Kills its worker process every time."""
    os._exit(3)


def square(value):
    return value * value
