"""The Exudyn wheel–rail item: the connector (:mod:`.connector`; a train's wheelsets on one:
:mod:`.train_contact`), its compiled core (:mod:`.connector_core`) and its Jacobian (:mod:`.contact_jacobian`),
with the rotations they share (:mod:`.rotations`).

This face also gathers, for a model script, the pieces the item couples — vehicles and trains
(:mod:`exudyn_wheelrail.rolling_stock`) and the rigid track (:mod:`exudyn_wheelrail.track.rigid`) — all from the
floors below::

    from exudyn_wheelrail.multibody import load_vehicle, build_vehicle, SpanDeflection, add_wheel_rail_contact

The run (monitor, runner, the solver table and Exudyn's solver settings,
:func:`exudyn_wheelrail.simulation.exudyn_settings.simulation_settings`) sits above, in
:mod:`exudyn_wheelrail.simulation`.
"""
from ..rolling_stock.placement import place_on_rails, static_axle_offset_m
from ..rolling_stock.train import Consist, ConsistError, TrainModel, build_train, load_consist, shipped_trains
from ..rolling_stock.vehicle_builder import (LongitudinalRestraint, RailSprings, VehicleModel, WheelsetHandle,
                                             build_vehicle, static_load_path)
from ..rolling_stock.vehicle_data import VehicleDataError, load_vehicle, shipped_vehicles, vehicle_from_dict
from ..rolling_stock.vehicle_records import VehicleData
from ..track.rigid import (Harmonic, Irregularity, IrregularitySum, NoIrregularity, RigidStraightTrack,
                           SampledIrregularity, SpanDeflection, irregularity_at, irregularity_many)
from .connector import ContactStateError, WheelRailContact, add_wheel_rail_contact
from .train_contact import add_train_contact

__all__ = [
    "load_vehicle", "vehicle_from_dict", "shipped_vehicles", "VehicleData", "VehicleDataError",
    "build_vehicle", "static_load_path", "RailSprings", "LongitudinalRestraint",
    "VehicleModel", "WheelsetHandle",
    "Irregularity", "NoIrregularity", "SpanDeflection", "Harmonic", "SampledIrregularity", "IrregularitySum",
    "RigidStraightTrack", "irregularity_at", "irregularity_many",
    "add_wheel_rail_contact", "add_train_contact", "WheelRailContact", "ContactStateError", "place_on_rails", "static_axle_offset_m",
    "load_consist", "shipped_trains", "build_train", "Consist", "ConsistError", "TrainModel",
]
