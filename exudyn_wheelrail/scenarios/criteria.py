"""The running-safety and comfort criteria of a recorded run (:func:`running_criteria`) and of a train, the train's
and every car's (:func:`train_criteria`): for the scenario's evaluation (:mod:`.run`) and the bridge crossing's
vehicles (:mod:`.bridge_crossing_vehicles`)."""
from __future__ import annotations

from ..analysis.safety import running_criteria_summary
from ..rolling_stock.train import car_suffix

__all__ = ["running_criteria", "train_criteria"]


def running_criteria(ts, speed_m_s, wheel_columns, static, point, **options) -> dict:
    """:func:`~exudyn_wheelrail.analysis.safety.running_criteria_summary` of the recorded table ``ts``: the wheels of
    ``wheel_columns`` (their ``Y`` and ``Q`` columns; ``static`` the static wheel loads ``{"w<j>_<side>": Q0}``) and
    the comfort at the car-body point ``point`` (its ``carbody_lateral_accelerometer_<point>_m_s2`` and
    ``carbody_vertical_acceleration_<point>_m_s2`` columns; ``""``: comfort not evaluated)."""
    cols = {}
    if point:
        cols = {"lateral": f"carbody_lateral_accelerometer_{point}_m_s2",
                "vertical": f"carbody_vertical_acceleration_{point}_m_s2"}
    sub = {k: ts[k] for k in ["time_s"] + list(wheel_columns) + list(cols.values())}
    return running_criteria_summary(sub, speed_m_s, static_wheel_loads_N=static, carbody_columns=cols or None,
                                    **options)


def train_criteria(train, ts: dict, speed_m_s: float, static_wheel_loads_N: dict, wheel_columns, *, vehicle: str,
                   yq_limit: float, unloading_limit: float, carbody_point: str = "") -> dict:
    """The criteria of a train (:class:`~exudyn_wheelrail.rolling_stock.train.TrainModel`) from a recorded table:
    :func:`~exudyn_wheelrail.analysis.safety.running_criteria_summary` of all its wheels (``wheel_columns``: the
    ``Y_w<j>_<side>_N`` and ``Q_w<j>_<side>_N`` columns, train numbering; comfort at the leading car's point
    ``<carbody_point>_c1``) and, under ``cars``, every car's own (its wheels, its car-body point
    ``<carbody_point>_c<k>``; ``""``: comfort not evaluated); ``passed`` / ``safety_passed`` hold for every car."""
    options = dict(vehicle=vehicle, yq_limit=yq_limit, unloading_limit=unloading_limit)
    wheel_columns = list(wheel_columns)
    cars = []
    for k, car in enumerate(train.cars):
        wheels = tuple(f"w{j + 1}_" for j in train.wheelset_range(k))
        mine = [c for c in wheel_columns if c.split("_", 1)[1].startswith(wheels)]
        point = carbody_point + car_suffix(k) if carbody_point and car.car_body is not None else ""
        cars.append({"car": k + 1, "vehicle": car.vehicle.name,
                     **running_criteria(ts, speed_m_s, mine, static_wheel_loads_N, point, **options)})
    lead = carbody_point + car_suffix(0) if carbody_point and train.cars[0].car_body is not None else ""
    out = running_criteria(ts, speed_m_s, wheel_columns, static_wheel_loads_N, lead, **options)
    out["cars"] = cars
    out["safety_passed"] = bool(out["safety_passed"] and all(c["safety_passed"] for c in cars))
    out["passed"] = bool(out["passed"] and all(c["passed"] for c in cars))
    return out
