"""Flexible structures under the track: railway bridges as modally reduced 3-D beams.

::

    from exudyn_wheelrail.structures import BridgeModel, DeckSection, add_bridge

The beam element shared with the flexible car body and the flexible track: :mod:`exudyn_wheelrail.structures.beam`;
the deck model and its modes: :mod:`exudyn_wheelrail.structures.bridge`; the mode shapes under a wheel and the
projection of wheel forces: :mod:`exudyn_wheelrail.structures.modal_shapes`; the Exudyn formulations and moving
forces: :mod:`exudyn_wheelrail.structures.bridge_exudyn` (the deck alone under moving forces in Exudyn:
:mod:`exudyn_wheelrail.scenarios.moving_forces`); Frýba's moving-force reference solution:
:mod:`exudyn_wheelrail.structures.fryba`; how the deck moves the rails under the wheelsets and where the wheel forces
go (the wheel–rail coupling): :mod:`exudyn_wheelrail.structures.deck_kinematics`.
"""
from .beam import DeckSection
from .bridge import BridgeModel, BridgeModes
from .bridge_exudyn import FORMULATIONS, ExudynBridge, MovingForces, add_bridge
from .fryba import fryba_moving_force
from .modal_shapes import ShapeTable, add_projected_force, modal_shape_and_slope_at, modal_shape_at, rail_state_at
from .support_motion import SmoothHarmonicSupportMotion, SupportMotion, SupportMotionLoad

__all__ = [
    "SupportMotion", "SmoothHarmonicSupportMotion", "SupportMotionLoad",
    "BridgeModel", "BridgeModes", "DeckSection", "ExudynBridge", "FORMULATIONS", "MovingForces", "ShapeTable",
    "add_bridge", "add_projected_force", "fryba_moving_force", "modal_shape_and_slope_at",
    "modal_shape_at", "rail_state_at",
]
