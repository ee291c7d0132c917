"""The handle of one body of a vehicle model in Exudyn (:class:`BodyHandle`: its node, object and markers, nominal
position and mass), shared by the rigid bodies of :mod:`.vehicle_builder` and the flexible car body of
:mod:`.flexible_body`."""
from __future__ import annotations

from dataclasses import dataclass

import exudyn as exu
import numpy as np

__all__ = ["BodyHandle"]


@dataclass
class BodyHandle:
    """One rigid body of the model: Exudyn numbers and nominal data (simulation frame)."""

    name: str
    node: exu.NodeIndex
    body: exu.ObjectIndex
    marker: exu.MarkerIndex            #: MarkerBodyRigid at the CG (loads, sensors, rigid connectors)
    marker_node: exu.MarkerIndex       #: MarkerNodeRigid of the node (same point)
    p_cg_in_frame: np.ndarray          #: nominal CG position [m]
    mass_kg: float
