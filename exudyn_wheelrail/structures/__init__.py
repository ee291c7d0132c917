"""Flexible structures under the track: railway bridges as modally reduced 3-D beams.

::

    from exudyn_wheelrail.structures import BridgeModel, DeckSection, add_bridge

See :mod:`exudyn_wheelrail.structures.bridge` (the model, its modes, the Exudyn formulations and Frýba's
moving-force reference solution; the deck alone under moving forces in Exudyn:
:mod:`exudyn_wheelrail.scenarios.moving_forces`) and :mod:`exudyn_wheelrail.structures.deck_kinematics` (how the deck moves the
rails under the wheelsets and where the wheel forces go: the wheel–rail coupling).
"""
from .bridge import (
    BridgeModel,
    BridgeModes,
    DeckSection,
    ExudynBridge,
    FORMULATIONS,
    MovingForces,
    ShapeTable,
    add_bridge,
    add_projected_force,
    fryba_moving_force,
    modal_shape_and_slope_at,
    modal_shape_at,
    rail_state_at,
)
from .support_motion import SmoothHarmonicSupportMotion, SupportMotion, SupportMotionLoad

__all__ = [
    "SupportMotion", "SmoothHarmonicSupportMotion", "SupportMotionLoad",
    "BridgeModel", "BridgeModes", "DeckSection", "ExudynBridge", "FORMULATIONS", "MovingForces", "ShapeTable",
    "add_bridge", "add_projected_force", "fryba_moving_force", "modal_shape_and_slope_at",
    "modal_shape_at", "rail_state_at",
]
