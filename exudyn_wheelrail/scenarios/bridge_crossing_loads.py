"""The bridge crossing's load models: what a load model is (:class:`LoadModel`) and hands back
(:class:`LoadModelHandle`), the resolution of a model's name (:func:`resolve_load_model`), the static axle loads of a
consist file (:func:`consist_axles`) and the constant moving axle loads (:data:`MOVING_LOADS`)."""
from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..rolling_stock.train import ConsistError, load_consist
from ..structures.load_models import AxleTrain
from .bridge_crossing_case import BridgeCrossing
from .defaults import LOAD_MODELS, MODEL_NAMES

__all__ = ["LoadModelHandle", "LoadModel", "resolve_load_model", "consist_axles", "MOVING_LOADS"]


@dataclass
class LoadModelHandle:
    """What a load model hands back (:data:`LOAD_MODELS`).

    contact : the wheel–rail contact the run monitor watches (``None``: nothing to watch, e.g. moving loads).
    axle_x_m : the axles' distances behind the first axle (running order; the first 0) [m].
    axle_load_N : their static (downward) loads [N].
    modal_forces : ``modal_forces(mbs, t) -> Q`` — the generalized forces on the bridge's modal node at the state
        being recorded (n_modes,), for the modal accelerations; ``None``: those of ``contact`` (its
        ``modal_forces_N()``, the full interaction), and the deck's columns are recorded by the run's watch in the
        compiled force call where the run allows it.
    probes : extra recorder probes (:class:`~exudyn_wheelrail.simulation.recorder.Recorder`), recorded after the
        deck's columns.
    summary : ``summary(table) -> dict`` merged into ``summary.json`` under ``"load_model"`` (optional).
    description : one line for the summary and the console.
    max_dt_s : the largest time step the load model integrates correctly (e.g. the wheel–rail contact's
        resolution bound); the default step is not larger (``None``: no bound).  A given ``dt_s`` is used as given.
    """

    contact: object | None
    axle_x_m: np.ndarray
    axle_load_N: np.ndarray
    modal_forces: Callable | None
    probes: list = field(default_factory=list)
    summary: Callable | None = None
    description: str = ""
    max_dt_s: float | None = None


@dataclass(frozen=True)
class LoadModel:
    """A load model: ``check(case)`` (``ValueError`` naming the option; no work) and ``build(mbs, case, bridge)
    -> LoadModelHandle`` (``bridge`` the :class:`~exudyn_wheelrail.structures.bridge_exudyn.ExudynBridge` of the
    deck, not assembled)."""

    check: Callable
    build: Callable


def _resolve(target: str, what: str, option: str):
    module, attr = target.split(":")
    try:
        mod = importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name is not None and module.startswith(exc.name):
            raise ValueError(f"{option}: {what} is not available in this installation (module {module} not "
                             "found)") from None
        raise
    entry = getattr(mod, attr, None)
    if entry is None:
        raise ValueError(f"{option}: {what} is not available in this installation ({module} has no {attr})")
    return entry


def resolve_load_model(name: str) -> LoadModel:
    """The :class:`LoadModel` of ``name`` (:data:`LOAD_MODELS`); ``ValueError`` ``"--model: ..."`` when it is not
    part of this installation."""
    if name not in LOAD_MODELS:
        raise ValueError(f"--model: {name!r}: expected one of {', '.join(MODEL_NAMES)}")
    return _resolve(LOAD_MODELS[name], f"the load model {name!r}", "--model")


def consist_axles(path) -> AxleTrain:
    """The static axle loads of a consist file (a shipped consist's name or a path) as an
    :class:`~exudyn_wheelrail.structures.load_models.AxleTrain` — the axle-load models of the same train: the
    wheelsets' distances behind the leading one, their lever-rule loads; ``ValueError`` ``"--train: ..."`` for a
    file that cannot be read."""
    try:
        consist = load_consist(path)
    except ConsistError as exc:
        raise ValueError(f"--train: {exc}") from None
    x = consist.wheelset_x_m()
    return AxleTrain(x_m=x[0] - x, load_N=consist.static_axle_loads_N(), name=consist.name, source=consist.source)


def _moving_loads_check(case: BridgeCrossing) -> None:
    if case.axles is None:
        raise ValueError("--axles/--hslm: the moving-load model needs the axle loads (give --axles FILE.csv or "
                         "--hslm A1..A10)")


def _moving_loads_build(mbs, case: BridgeCrossing, bridge) -> LoadModelHandle:
    ax = case.axles
    forces = np.zeros((ax.n_axles, 3))
    forces[:, 1] = ax.load_N                                      # Fz, z down: a weight is positive
    mf = bridge.add_moving_forces(mbs, -ax.x_m, forces, case.speed_m_s, s_start_m=case.deck_start_m,
                                  name="axle_loads")

    def modal_forces(mbs_, t):
        return mf.forces(t).copy()

    return LoadModelHandle(contact=None, axle_x_m=ax.x_m.copy(), axle_load_N=ax.load_N.copy(),
                           modal_forces=modal_forces,
                           description=f"{ax.n_axles} constant axle loads ({ax.name}) moving at "
                                       f"{case.speed_m_s * 3.6:.4g} km/h")


#: the constant moving axle loads
MOVING_LOADS = LoadModel(check=_moving_loads_check, build=_moving_loads_build)
