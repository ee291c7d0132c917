r"""The ``vehicles`` load model of ``bridge-crossing``: the full vehicle–bridge interaction of a train.

``python -m exudyn_wheelrail bridge-crossing ... --train FILE.toml --model vehicles``: the consist of the file
(:mod:`exudyn_wheelrail.rolling_stock.train`) is built in the crossing's Exudyn system
(:func:`~exudyn_wheelrail.rolling_stock.train.build_train`: one :class:`~exudyn_wheelrail.rolling_stock.vehicle_builder.
VehicleModel` per car, its couplers), and all its wheelsets are coupled to the rails and the deck by **one**
wheel–rail connector (:func:`~exudyn_wheelrail.multibody.add_wheel_rail_contact` with ``structure=`` the deck of the
crossing, as :func:`exudyn_wheelrail.scenarios.build.build_scenario` couples a vehicle to a deck: the deck under a
wheel moves its rails, the wheel forces drive the modes).  The rails are otherwise perfect (no irregularity); the
contact settings are the defaults of :class:`~exudyn_wheelrail.simulation.settings.ContactSettings`.

Conventions of the crossing: the deck spans ``[deck_start_m, deck_start_m + L]`` (L the sum of the spans of a
chain: the connector sees the whole chain's modes, vertical and lateral); at ``t = 0`` the train's leading
wheelset is at ``deck_start_m`` and the whole train behind it, every car in static equilibrium on the rails
(:func:`~exudyn_wheelrail.rolling_stock.train.place_train_on_track`; the unloaded deck is at rest).

Time step (:func:`contact_dt_s`): the crossing's default step, at most ``CONTACT_DT_S`` and at most the step
that resolves the stiffest wheelset bouncing on its linearised Hertz contact (``ω = √(2 k_H / m_wheelset)``,
``k_H = 1.5 Q/δ`` at the static wheel load Q,
:meth:`~exudyn_wheelrail.rolling_stock.vehicle_builder.RailSprings.from_hertz`) with
``CONTACT_STEPS_PER_PERIOD`` steps per period — an accuracy bound, chosen by the work–precision of the full
interaction (that oscillation carries the wheels' dynamic forces, and the deck accelerations they excite) — and at
most half the step at which that oscillation reaches the resolution bound ``ω h = 2√2``
(:data:`~exudyn_wheelrail.simulation.solvers.RESOLUTION_LIMIT`, a stability bound the accuracy bound is below).

Outputs beside the deck's: the wheels' ``Y``, ``Q``, ``YQ``, ``flange``, ``contact_angle`` columns (``w<j>``: the
train's wheelsets, car after car), the wheelsets' lateral position, and per car the car-body points above its
bogies at floor height (``rear_c<k>``, ``front_c<k>``; :func:`exudyn_wheelrail.scenarios.probes.train_probes`);
``summary.json`` ``load_model.details``: the consist, every car's place and wheelsets, and the running-safety and
comfort criteria of the train and of every car (:func:`exudyn_wheelrail.scenarios.criteria.train_criteria`).
"""
from __future__ import annotations

import math

import numpy as np

from ..analysis.safety import EN14363_YQ_LIMIT, WHEEL_UNLOADING_LIMIT
from ..contact.pair import WheelRailPair
from ..multibody.train_contact import add_train_contact
from ..rolling_stock.train import ConsistError, build_train, load_consist
from ..rolling_stock.vehicle_builder import RailSprings, static_load_path
from ..simulation.solvers import RESOLUTION_LIMIT
from ..simulation.settings import ContactSettings
from ..track.rigid import RigidStraightTrack
from .bridge_crossing_case import BridgeCrossing, step_rounded_down
from .defaults import CONTACT_DT_S, CONTACT_STEPS_PER_PERIOD
from .bridge_crossing_loads import LoadModel, LoadModelHandle
from .criteria import train_criteria
from .probes import train_probes
from .spec import DEFAULT_FLOOR_HEIGHT_M

__all__ = ["VEHICLES", "contact_dt_s", "hertz_dt_bound_s", "build_train_on_straight_track"]



def _consist(case: BridgeCrossing):
    if case.train_file is None:
        raise ValueError("--train: the vehicles model needs a consist file (--train FILE.toml)")
    try:
        return load_consist(case.train_file)
    except ConsistError as exc:
        raise ValueError(f"--train: {exc}") from None


def _contact_omega(consist) -> float:
    """ω [rad/s] of the stiffest wheelset of ``consist`` bouncing on its linearised Hertz contact."""
    omega = 0.0
    for car in consist.cars:
        v = car.vehicle
        q = float(np.max(static_load_path(v).wheel))
        k = RailSprings.from_hertz(wheel_load_N=q, r0_m=v.geometry.r0_m).k_vertical_N_per_m
        omega = max(omega, math.sqrt(2.0 * k / v.wheelset.mass_kg))
    return omega


def hertz_dt_bound_s(consist) -> float:
    """Half the step at which the stiffest wheelset of ``consist`` on its linearised Hertz contact reaches the
    resolution bound (module docstring) [s]."""
    return 0.5 * RESOLUTION_LIMIT / _contact_omega(consist)


def contact_dt_s(consist) -> float:
    """The largest step of the full interaction of ``consist`` (module docstring): ``min(CONTACT_DT_S, 2π/(N ω),
    hertz_dt_bound_s)`` with N = ``CONTACT_STEPS_PER_PERIOD``, rounded down to 3 significant digits [s]
    (:mod:`.defaults`).  ``CONTACT_DT_S`` is the contact runs' 1 ms (the RTRI case's published step).  N: RK44 damps
    an oscillation of ω h by about (ω h)^6/144 per step (its amplification factor on the imaginary axis, |R(iωh)| =
    1 - (ωh)^6/144 + O((ωh)^8)), i.e. by N (2π/N)^6/144 per period: 0.7 % at the N ≈ 9 the deck's rule alone gave
    the README's 8-car crossing, 0.013 % at N = 20.  Measured on that crossing (benchmarks/
    crossing_work_precision.py, against 1/16 ms): at N ≈ 9 (0.555 ms) the deck's peak acceleration is 4.7 % off, the
    EN 1990 acceleration 2.5 %, the largest lateral wheel force 3.7 %; at N ≈ 20 (0.25 ms) all within 0.4 %."""
    return step_rounded_down(min(CONTACT_DT_S, 2.0 * math.pi / (CONTACT_STEPS_PER_PERIOD * _contact_omega(consist)),
                                 hertz_dt_bound_s(consist)))


def _check(case: BridgeCrossing) -> None:
    """The consist file is read and validated (errors ``--train: <file>: <key>: <problem>``); nothing is built."""
    _consist(case)


def build_train_on_straight_track(mbs, consist, *, speed_m_s: float, s_start_m: float, structure=None):
    """``(train, track)``: the consist built in ``mbs`` with one wheel–rail connector (the first car's profiles,
    the default contact settings) on the straight rigid track, coupled to ``structure`` (what moves the rails, an
    :class:`~exudyn_wheelrail.structures.bridge_exudyn.ExudynBridge`: a deck or a flexible track) if given."""
    geo = consist.cars[0].vehicle.geometry
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    cs = ContactSettings()
    track = RigidStraightTrack()
    train = build_train(mbs, consist, speed_m_s=speed_m_s, s_start_m=s_start_m)
    add_train_contact(mbs, train, pair, track=track, creep_law=cs.creep_law, mu=cs.friction,
                      fastsim_grid=cs.fastsim_grid, geometry=cs.geometry, structure=structure)
    return train, track


def _build(mbs, case: BridgeCrossing, bridge) -> LoadModelHandle:
    consist = _consist(case)
    V = case.speed_m_s
    x_ws = consist.wheelset_x_m()
    s_start = case.deck_start_m - float(x_ws[0])               # the leading wheelset at the deck start at t = 0
    train, track = build_train_on_straight_track(mbs, consist, speed_m_s=V, s_start_m=s_start, structure=bridge)
    cs = ContactSettings()                                    # the settings build_train_on_straight_track uses
    contact = train.contact
    points = [{"name": name, "x_m": x, "y_m": 0.0, "height_m": DEFAULT_FLOOR_HEIGHT_M}
              for name, x in (("rear", "rear_bogie"), ("front", "front_bogie"))]
    probes = train_probes(train, contact, track, V, case.deck_start_m, points, mbs=mbs)
    static = {f"w{j + 1}_{side}": float(w[0 if side == "left" else 1])
              for j, w in enumerate(train.static_wheel_loads_N()) for side in ("right", "left")}

    def summary(ts: dict) -> dict:
        wheels = [c for c in ts if c.startswith(("Y_w", "Q_w")) and c.endswith("_N")]
        try:
            crit = train_criteria(train, ts, V, static, wheels, vehicle="passenger", yq_limit=EN14363_YQ_LIMIT,
                                  unloading_limit=WHEEL_UNLOADING_LIMIT, carbody_point="rear")
        except ValueError as exc:
            crit = {"error": str(exc)}
        return {"consist": {"name": consist.name, "file": consist.file, "source": consist.source,
                            "n_cars": consist.n_cars, "length_m": consist.length_m,
                            "total_mass_kg": consist.total_mass_kg, "gap_m": consist.gap_m,
                            "coupling": dict(consist.coupling.__dict__)},
                "cars": [{"car": k + 1, "vehicle": car.vehicle.name, "x_m": float(x),
                          "wheelsets": [j + 1 for j in train.wheelset_range(k)]}
                         for k, (car, x) in enumerate(zip(train.cars, train.car_x_m))],
                "contact": {"creep_law": cs.creep_law, "friction": cs.friction, "geometry": cs.geometry},
                "criteria": crit}

    return LoadModelHandle(contact=contact, axle_x_m=float(x_ws[0]) - x_ws, axle_load_N=consist.static_axle_loads_N(),
                           modal_forces=None, probes=probes,
                           summary=summary,
                           description=f"{consist.name}: {consist.n_cars} car(s), {len(x_ws)} wheelsets, full "
                                       f"vehicle-bridge interaction (one wheel-rail contact, {cs.creep_law})",
                           max_dt_s=contact_dt_s(consist))


#: the full vehicle–bridge interaction (module docstring)
VEHICLES = LoadModel(check=_check, build=_build)
