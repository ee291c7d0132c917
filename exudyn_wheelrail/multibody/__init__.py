"""Exudyn coupling: vehicles from data files, the vehicle builder, trains (consists), and the track irregularities.

::

    from exudyn_wheelrail.multibody import load_vehicle, build_vehicle, SpanDeflection, add_wheel_rail_contact
"""
from .connector import ContactStateError, WheelRailContact, add_wheel_rail_contact
from .monitor import RunMonitor, Status, run_monitored
from .placement import place_on_rails, static_axle_offset_m
from .track import (
    Harmonic,
    Irregularity,
    IrregularitySum,
    NoIrregularity,
    RigidStraightTrack,
    SampledIrregularity,
    SpanDeflection,
    irregularity_at,
    irregularity_many,
)
from .train import Consist, ConsistError, TrainModel, build_train, load_consist, shipped_trains
from .vehicle_builder import (
    LongitudinalRestraint,
    RailSprings,
    VehicleModel,
    WheelsetHandle,
    build_vehicle,
    simulation_settings,
    solver_settings,
    static_load_path,
)
from .vehicle_data import VehicleData, VehicleDataError, load_vehicle, shipped_vehicles, vehicle_from_dict

__all__ = [
    "load_vehicle", "vehicle_from_dict", "shipped_vehicles", "VehicleData", "VehicleDataError",
    "build_vehicle", "simulation_settings", "solver_settings", "static_load_path", "RailSprings", "LongitudinalRestraint",
    "VehicleModel", "WheelsetHandle",
    "Irregularity", "NoIrregularity", "SpanDeflection", "Harmonic", "SampledIrregularity", "IrregularitySum",
    "RigidStraightTrack", "irregularity_at", "irregularity_many",
    "add_wheel_rail_contact", "WheelRailContact", "ContactStateError", "place_on_rails", "static_axle_offset_m",
    "RunMonitor", "Status", "run_monitored",
    "load_consist", "shipped_trains", "build_train", "Consist", "ConsistError", "TrainModel",
]
