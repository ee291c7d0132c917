"""The recorder's probes a scenario adds to the vehicle's (:func:`~exudyn_wheelrail.simulation.recorder.vehicle_probes`):
the car-body points of ``outputs.carbody_points`` placed on a car (:func:`carbody_x`) and the probes of a train
(:func:`train_probes`), for the scenario's builder (:mod:`.build`) and the bridge crossing's vehicles
(:mod:`.bridge_crossing_vehicles`)."""
from __future__ import annotations

import dataclasses

from ..rolling_stock.train import car_suffix
from ..simulation.recorder import vehicle_probes

__all__ = ["carbody_x", "train_probes"]


def carbody_x(x, vehicle) -> float:
    """The x of a car-body point in its car's frame [m]: a number as given, or ``"front_bogie"``, ``"rear_bogie"``,
    ``"centre"`` of ``vehicle`` (:class:`~exudyn_wheelrail.rolling_stock.vehicle_data.VehicleData`)."""
    if isinstance(x, str):
        return {"front_bogie": max(vehicle.bogie_x_m()), "rear_bogie": min(vehicle.bogie_x_m()), "centre": 0.0}[x]
    return float(x)


def train_probes(train, contact, track, speed_m_s: float, s_leading0_m: float, carbody_points, bridge=None,
                 modes=None, structure=None, mbs=None) -> list:
    """The recorder's probes of a train (:class:`~..rolling_stock.train.TrainModel`): the wheels, wheelsets and track of
    :func:`~..simulation.recorder.vehicle_probes` for all wheelsets (train order: ``w<j>`` numbers the wheelsets of
    the whole train, car after car), the deck's with a bridge, and every car's car-body points (``outputs.
    carbody_points``, x from that car's centre), named ``<point>_c<k>`` (k = 1 the leading car); ``mbs`` (not yet
    assembled) as for :func:`~..simulation.recorder.vehicle_probes`: the car-body points read by sensors."""
    st = structure or {}
    probes = vehicle_probes(model=train, contact=contact, track=track, speed_m_s=speed_m_s, s_leading0_m=s_leading0_m,
                            bridge=bridge, modes=modes, deck_spans_m=st.get("spans_m"), deck_start_m=st.get("start_m"))
    wheelsets = train.wheelsets
    for k, (car, x_car) in enumerate(zip(train.cars, train.car_x_m)):
        if car.car_body is None or not carbody_points:
            continue
        points = [(p["name"] + car_suffix(k), [x_car + carbody_x(p["x_m"], car.vehicle), p["y_m"], -p["height_m"]])
                  for p in carbody_points]
        # the car-body probe is the last of vehicle_probes without a bridge; the model lists every wheelset of the
        # connector (the wheel probes built alongside are checked against it and dropped)
        probes.append(vehicle_probes(model=dataclasses.replace(car, wheelsets=wheelsets), contact=contact, track=track,
                                     speed_m_s=speed_m_s, s_leading0_m=s_leading0_m, carbody_points=points,
                                     mbs=mbs)[-1])
    return probes

