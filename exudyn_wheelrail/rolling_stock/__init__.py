"""Rolling stock in Exudyn: vehicles from data files (:mod:`.vehicle_data`), their multibody model
(:mod:`.vehicle_builder`, with the flexible car body of :mod:`.flexible_body`), trains of coupled cars
(:mod:`.train`), a vehicle on a curved track in track-following frames (:mod:`.track_following`) and its start in
static equilibrium on the rails (:mod:`.placement`).

::

    from exudyn_wheelrail.rolling_stock import load_vehicle, build_vehicle, build_train

The wheel–rail connector that couples them to the track sits a floor above, in :mod:`exudyn_wheelrail.multibody`.
"""
from .placement import place_on_rails, start_on_track, static_axle_offset_m
from .train import Consist, ConsistError, TrainModel, build_train, load_consist, place_train_on_track, shipped_trains
from .vehicle_builder import (LongitudinalRestraint, RailSprings, VehicleModel, WheelsetHandle, build_vehicle,
                              static_load_path)
from .vehicle_data import VehicleDataError, load_vehicle, shipped_vehicles, vehicle_from_dict
from .vehicle_records import VehicleData

__all__ = [
    "load_vehicle", "vehicle_from_dict", "shipped_vehicles", "VehicleData", "VehicleDataError",
    "build_vehicle", "static_load_path", "RailSprings", "LongitudinalRestraint", "VehicleModel", "WheelsetHandle",
    "place_on_rails", "start_on_track", "static_axle_offset_m",
    "load_consist", "shipped_trains", "build_train", "place_train_on_track", "Consist", "ConsistError", "TrainModel",
]
