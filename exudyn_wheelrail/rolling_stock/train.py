r"""Trains: a consist file (vehicles in order, their spacing, the couplers between car ends) and its Exudyn model.

>>> consist = load_consist("manchester_x8")                                                   # doctest: +SKIP
>>> train = build_train(mbs, consist, speed_m_s=50.0, s_start_m=0.0)                          # doctest: +SKIP
>>> add_train_contact(mbs, train, pair, track=track)       # exudyn_wheelrail.multibody       # doctest: +SKIP
>>> train.contact, train.cars[3].car_body, train.car_of_wheelset                              # doctest: +SKIP

Consist files (``vehicles/trains/*.toml``, ``schema_version = 1``; SI units, the unit in every key name)
-----------------------------------------------------------------------------------------------------------
======================  ================================================================================================
``[train]``             ``name``, ``source`` (citation of the numbers, or "assumed"), ``description`` (optional);
                        ``gap_m`` (optional, default :data:`DEFAULT_GAP_M`): distance between the ends of adjacent car
                        bodies (the coupling planes) [m], >= 0 — a negative gap is overlapping cars
``[coupling]``          (optional) the coupler/buffer spring–damper between adjacent car ends, acting between the
                        car-end points on the centre line at ``height_m`` above the rail top:
                        ``enabled`` (default true), ``kx_N_per_m``, ``cx_N_s_per_m`` (longitudinal), ``ky_N_per_m``,
                        ``cy_N_s_per_m`` (lateral), ``height_m``; defaults :class:`CouplingData` (with their sources);
                        no vertical stiffness (a coupler head carries no vertical load between the cars)
``[[car]]``             one entry per car or group of identical cars, front (leading) first: ``vehicle`` — a shipped
                        vehicle name (``vehicles/<name>.toml``) or a vehicle file path (relative to the consist file);
                        ``length_m`` — length of the car body between its ends (coupling planes) [m], the ends at
                        ``±length_m/2`` from the vehicle centre (mid-point of the bogie centres); ``count``
                        (optional, default 1) — that many identical cars in a row
======================  ================================================================================================

Spacing: the cars follow one another **end to end**, ``gap_m`` apart: the leading car's centre at model-frame x = 0
(where a single vehicle of :func:`~.vehicle_builder.build_vehicle` sits), car k + 1's centre at
``x_{k+1} = x_k - L_k/2 - gap - L_{k+1}/2`` (:meth:`Consist.car_x_m`).  Validation (one pass,
before anything is built; :class:`ConsistError`, message ``<file>: <key>: <problem>``): unknown or missing keys,
wrong types, a vehicle that cannot be loaded (:mod:`.vehicle_data`), non-positive lengths, ``count`` < 1, negative
stiffness or damping, a negative gap (overlapping car bodies), a car shorter than its wheelbase plus one wheel
diameter (its wheels would reach past its ends into the neighbour's), couplers between cars without a car body.

Model (:func:`build_train`)
---------------------------
One :class:`~.vehicle_builder.VehicleModel` per car in one ``mbs``: car k's items named with the suffix
``_c<k>`` (k = 1 leading), its bodies at its x offset in the model frame (the frame moving with V; a point at x is
at track distance ``s_start + V t + x``), each car with its own longitudinal restraint to the moving frame
(:class:`~.vehicle_builder.LongitudinalRestraint`: the restraint of a roller rig, per car).  The couplers are
``ObjectConnectorCartesianSpringDamper`` items from the rear-end point of car k to the front-end point of car
k + 1, unstressed at the nominal spacing (offset = the nominal gap): the force is ``k (Δ) + c Δ̇`` with Δ the
change of the end-to-end vector (x: the gap's growth; y: the lateral offset of the rear car's end to the right);
on a displaced track every car starts on the track under its own wheelsets, so adjacent car ends may start a little
apart laterally (the couplers start with that force).  A flexible car body gives the coupler its own marker
(``position_marker``; the car-end points must then be among its attachment points).
The wheel–rail connector sits a floor above (:func:`exudyn_wheelrail.multibody.connector.add_train_contact`): all
wheelsets, car after car, front first, are coupled to the rails by **one** connector (the run monitor and the
recorder watch one connector), and every car is put in static equilibrium on the rails
(:func:`~.placement.place_on_rails`) and on the displaced track (:func:`~.placement.start_on_track`:
:func:`place_train_on_track`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..validation import read_toml
from .placement import place_on_rails, start_on_track
from .vehicle_builder import GRAVITY_M_S2, StaticLoadPath, VehicleModel, build_vehicle, static_load_path
from .vehicle_data import VEHICLES_DIR, load_vehicle
from .vehicle_records import VehicleData

__all__ = ["TRAINS_DIR", "DEFAULT_GAP_M", "ConsistError", "CouplingData", "CarEntry", "Consist", "TrainModel",
           "load_consist", "consist_from_dict", "shipped_trains", "build_train", "place_train_on_track",
           "car_suffix"]

#: the shipped consist files
TRAINS_DIR = VEHICLES_DIR / "trains"
#: default distance between adjacent car-body ends [m]: 0, the coupling planes of coupled cars meet
DEFAULT_GAP_M = 0.0
_SCHEMA_VERSION = 1


class ConsistError(ValueError):
    """Bad consist data; the message names the file and the key (``<file>: <key>: <problem>``)."""


@dataclass(frozen=True)
class CouplingData:
    """The coupler/buffer spring–damper between two adjacent car ends (module docstring).

    Defaults — **assumed** (no published coupler data are used; the numbers are orders of magnitude, chosen so
    that the couplers hold the cars together without adding fast dynamics):

    * ``kx_N_per_m = 10e6``, ``cx_N_s_per_m = 100e3``: a stiff draft gear / buffer pair; the longitudinal mode of two
      40 t cars on it, √(2 k/m) / 2π = 3.6 Hz, lies well below the contact's frequencies; the damping is ≈ 10 % of
      its critical value 2 √(k m/2) = 2 · √(1e7 · 2e4);
    * ``ky_N_per_m = 100e3``, ``cy_N_s_per_m = 10e3``: the small lateral centring of a coupler head and the gangway
      between the car ends, small against a car's secondary lateral stiffness (Manchester vehicle 1: 4 × 160 kN/m);
    * ``height_m = 1.0``: about the height of the buffers and couplers of standard-gauge coaches above the rail top.
    """

    enabled: bool = True
    kx_N_per_m: float = 10.0e6
    cx_N_s_per_m: float = 100.0e3
    ky_N_per_m: float = 100.0e3
    cy_N_s_per_m: float = 10.0e3
    height_m: float = 1.0


@dataclass(frozen=True)
class CarEntry:
    """One car of a consist: its vehicle data, its source (name or path) and its body length [m]."""

    vehicle: VehicleData
    source: str
    length_m: float


@dataclass(frozen=True)
class Consist:
    """A validated consist: cars front first, the gap between car ends, the coupling."""

    name: str
    source: str
    cars: tuple[CarEntry, ...]
    gap_m: float = DEFAULT_GAP_M
    coupling: CouplingData = field(default_factory=CouplingData)
    description: str = ""
    file: str | None = None

    @property
    def n_cars(self) -> int:
        return len(self.cars)

    def car_x_m(self) -> np.ndarray:
        """Model-frame x of every car's centre: the leading car at 0, the others behind it, end to end ``gap_m``
        apart."""
        x = [0.0]
        for a, b in zip(self.cars[:-1], self.cars[1:]):
            x.append(x[-1] - 0.5 * a.length_m - self.gap_m - 0.5 * b.length_m)
        return np.array(x)

    def wheelset_x_m(self) -> np.ndarray:
        """Model-frame x of every wheelset, car after car, front first."""
        return np.array([xc + xw for xc, car in zip(self.car_x_m(), self.cars) for xw in car.vehicle.wheelset_x_m()])

    def static_axle_loads_N(self, gravity_m_s2: float = GRAVITY_M_S2) -> np.ndarray:
        """Static load of every wheelset on the rails (both wheels; the lever rule of
        :func:`~.vehicle_builder.static_load_path`), train order [N]."""
        return np.concatenate([static_load_path(c.vehicle, gravity_m_s2).wheel.sum(axis=1) for c in self.cars])

    @property
    def total_mass_kg(self) -> float:
        return float(sum(c.vehicle.total_mass_kg for c in self.cars))

    @property
    def length_m(self) -> float:
        """From the front end of the leading car to the rear end of the last one."""
        return float(sum(c.length_m for c in self.cars) + self.gap_m * (self.n_cars - 1))


def car_suffix(k: int) -> str:
    """Item-name suffix of car ``k`` (0-based): ``_c1`` for the leading car."""
    return f"_c{k + 1}"


# ============================================================================================ reading
def shipped_trains() -> list[str]:
    """Names of the consist files in ``vehicles/trains/``."""
    return sorted(p.stem for p in TRAINS_DIR.glob("*.toml")) if TRAINS_DIR.is_dir() else []


def load_consist(source) -> Consist:
    """Read and validate a consist file: a path to a ``.toml`` file or the name of a shipped consist
    (:func:`shipped_trains`)."""
    if isinstance(source, Consist):
        return source
    path = Path(source)
    if not path.suffix and not path.exists():
        path = TRAINS_DIR / f"{source}.toml"
    if not path.is_file():
        raise ConsistError(f"{source}: consist file not found (shipped trains: "
                           f"{', '.join(shipped_trains()) or 'none'})")
    data = read_toml(path, ConsistError)
    return consist_from_dict(data, source=str(path), base_dir=path.resolve().parent)


def consist_from_dict(data: dict, source: str = "<dict>", base_dir=None) -> Consist:
    """Validate a consist given as a dict (the TOML file's content); see the module docstring."""
    def err(key, msg):
        return ConsistError(f"{source}: {key}: {msg}")

    def table(value, key, required=(), optional=()):
        if not isinstance(value, dict):
            raise err(key, f"expected a table, got {type(value).__name__} {value!r}")
        for k in value:
            if k not in tuple(required) + tuple(optional):
                raise err(f"{key}.{k}" if key else k,
                          f"unknown key (allowed: {', '.join(tuple(required) + tuple(optional))})")
        for k in required:
            if k not in value:
                raise err(f"{key}.{k}" if key else k, "missing (required)")
        return value

    def number(value, key, lo=None, lo_open=False):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise err(key, f"expected a finite number, got {value!r}")
        if lo is not None and (value <= lo if lo_open else value < lo):
            raise err(key, f"{value!r}: must be {'>' if lo_open else '>='} {lo}")
        return float(value)

    def string(value, key):
        if not isinstance(value, str):
            raise err(key, f"expected a string, got {type(value).__name__} {value!r}")
        return value

    table(data, "", required=("schema_version", "train", "car"), optional=("coupling",))
    if data["schema_version"] != _SCHEMA_VERSION:
        raise err("schema_version",
                  f"{data['schema_version']!r}: this version reads schema_version = {_SCHEMA_VERSION}")
    tr = table(data["train"], "train", required=("name", "source"), optional=("description", "gap_m"))
    gap = tr.get("gap_m", DEFAULT_GAP_M)
    if isinstance(gap, (int, float)) and not isinstance(gap, bool) and gap < 0:
        raise err("train.gap_m", f"{gap!r}: negative — the car bodies would overlap (the gap between car ends must "
                                 "be >= 0)")
    gap = number(gap, "train.gap_m", lo=0.0)
    defaults = CouplingData()
    cp = table(data.get("coupling", {}), "coupling", optional=("enabled", "kx_N_per_m", "cx_N_s_per_m",
                                                                "ky_N_per_m", "cy_N_s_per_m", "height_m"))
    enabled = cp.get("enabled", True)
    if not isinstance(enabled, bool):
        raise err("coupling.enabled", f"expected true or false, got {enabled!r}")
    values = {}
    for k in ("kx_N_per_m", "cx_N_s_per_m", "ky_N_per_m", "cy_N_s_per_m"):
        values[k] = number(cp.get(k, getattr(defaults, k)), f"coupling.{k}", lo=0.0)
    values["height_m"] = number(cp.get("height_m", defaults.height_m), "coupling.height_m", lo=0.0)
    coupling = CouplingData(enabled=enabled, **values)
    cars_in = data["car"]
    if not isinstance(cars_in, list) or not cars_in:
        raise err("car", "expected one or more [[car]] tables")
    cars = []
    base = Path(base_dir) if base_dir is not None else None
    for i, c in enumerate(cars_in):
        key = f"car.{i}"
        table(c, key, required=("vehicle", "length_m"), optional=("count",))
        ref = string(c["vehicle"], f"{key}.vehicle")
        p = Path(ref)
        if p.suffix and not p.is_absolute() and base is not None:
            p = base / p
        try:
            vehicle = load_vehicle(p if p.suffix else ref)
        except ValueError as exc:
            raise err(f"{key}.vehicle", str(exc)) from None
        length = number(c["length_m"], f"{key}.length_m", lo=0.0, lo_open=True)
        x = vehicle.wheelset_x_m()
        reach = max(abs(v) for v in x) + vehicle.geometry.r0_m
        if 2.0 * reach > length:
            raise err(f"{key}.length_m", f"{length} m: shorter than the car's wheelbase plus one wheel diameter "
                                         f"({2 * reach:.3f} m): its wheels would overlap the neighbouring car's")
        count = c.get("count", 1)
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            raise err(f"{key}.count", f"expected an integer >= 1, got {count!r}")
        cars += [CarEntry(vehicle=vehicle, source=str(p if p.suffix else ref), length_m=length)] * count
    if coupling.enabled and len(cars) > 1:
        for i, c in enumerate(cars):
            if c.vehicle.car_body is None:
                raise err("coupling.enabled", f"car {i + 1} ({c.vehicle.name!r}, layout {c.vehicle.layout!r}) has no "
                                              "car body to couple: set coupling.enabled = false")
    return Consist(name=string(tr["name"], "train.name"), source=string(tr["source"], "train.source"),
                   cars=tuple(cars), gap_m=gap, coupling=coupling,
                   description=string(tr.get("description", ""), "train.description"),
                   file=source if source != "<dict>" else None)


# ============================================================================================ model
@dataclass
class TrainModel:
    """What :func:`build_train` created: the cars (one :class:`~.vehicle_builder.VehicleModel` each, front first),
    their centres' model-frame x, the couplers (Exudyn object numbers, between car k and k + 1) and the wheel–rail
    connector (None until :func:`exudyn_wheelrail.multibody.connector.add_train_contact` adds it).  Duck-types the parts of a ``VehicleModel`` the run
    monitor's, the recorder's and the deck outputs' callers use for all wheelsets (``wheelsets``, ``wheelset_nodes``,
    ``track_distance_m``, ``speed_m_s``, ``s_start_m``, ``gravity_m_s2``, ``load_path``, ``bodies``)."""

    consist: Consist
    cars: list[VehicleModel]
    car_x_m: np.ndarray
    couplers: list
    speed_m_s: float
    s_start_m: float
    gravity_m_s2: float
    contact: object = None
    start_shift_m: float | None = None       #: largest track displacement under a wheelset at t = 0 (None: none)
    car_body: object = None                  #: a train has no single car body (each car has its own)

    @property
    def wheelsets(self) -> list:
        """Every wheelset, car after car, front first (the connector's order)."""
        return [w for car in self.cars for w in car.wheelsets]

    @property
    def wheelset_nodes(self) -> list:
        return [w.node for w in self.wheelsets]

    @property
    def car_of_wheelset(self) -> list[int]:
        """Index (0-based) of the car of each wheelset."""
        return [k for k, car in enumerate(self.cars) for _ in car.wheelsets]

    def wheelset_range(self, k: int) -> range:
        """Indices (0-based, train order) of car ``k``'s wheelsets."""
        start = sum(len(c.wheelsets) for c in self.cars[:k])
        return range(start, start + len(self.cars[k].wheelsets))

    @property
    def bodies(self) -> list:
        return [b for car in self.cars for b in car.bodies]

    def track_distance_m(self, x_in_frame_m, t_s: float = 0.0):
        """Track distance s of a point at model-frame x at time t: ``s_start + V t + x``."""
        return self.s_start_m + self.speed_m_s * t_s + np.asarray(x_in_frame_m, dtype=float)

    @property
    def load_path(self) -> StaticLoadPath | None:
        """The cars' static load paths (:class:`~.vehicle_builder.StaticLoadPath`) stacked in train order (bogies,
        axleboxes, wheels car after car); None when the cars were built without preload."""
        if any(car.load_path is None for car in self.cars):
            return None
        return StaticLoadPath(*(np.concatenate([getattr(car.load_path, f) for car in self.cars])
                                for f in ("secondary", "primary", "wheel")))

    def static_wheel_loads_N(self) -> np.ndarray:
        """Static wheel loads of the lever rule (``VehicleModel.load_path``), (n_wheelsets, 2) in (left, right)."""
        return self.load_path.wheel

    def coupler_forces_N(self, mbs) -> np.ndarray:
        """Force of each coupler (x, y, z, model frame) on the **front** car's rear end, (n_couplers, 3); the rear
        car's front end gets the opposite.  Exudyn's ``f = k (p1 - p0 - offset) + c (v1 - v0)`` of the element from
        the front car (marker 0, which it acts on with +f) to the rear car (marker 1, -f): negative x is tension
        (the gap has grown; the coupler pulls the front car back), positive y pulls the front car's end right."""
        import exudyn as exu
        return np.array([np.asarray(mbs.GetObjectOutput(c, exu.OutputVariableType.Force), dtype=float)
                         for c in self.couplers]).reshape(len(self.couplers), 3)


def build_train(mbs, consist, *, speed_m_s: float, s_start_m: float = 0.0, wheel_rail: str = "none",
                gravity_m_s2: float = GRAVITY_M_S2, show: bool = False, **vehicle_options) -> TrainModel:
    """Create the Exudyn model of a consist in ``mbs`` (not assembled; module docstring).

    Parameters
    ----------
    consist : a :class:`Consist` or a consist file / shipped name for :func:`load_consist`.
    speed_m_s, s_start_m : running speed and the track distance of the model-frame origin (the leading car's
        centre) at t = 0.
    wheel_rail : ``"springs"`` — every car on linear rail springs (:func:`~.vehicle_builder.build_vehicle`);
        ``"none"`` — no wheel–rail coupling: the caller adds it, e.g. the connector of
        :func:`exudyn_wheelrail.multibody.connector.add_train_contact`.
    vehicle_options : further keyword arguments of :func:`~.vehicle_builder.build_vehicle` for every car
        (``longitudinal``, ``bump_stop``, ``preload``, ``rail_springs``).
    """
    consist = load_consist(consist)
    if wheel_rail not in ("springs", "none"):
        raise ValueError(f"wheel_rail={wheel_rail!r}: expected 'springs' or 'none' (the wheel-rail connector: "
                         "exudyn_wheelrail.multibody.connector.add_train_contact)")
    for key in ("name_suffix", "x_offset_m", "speed_m_s", "s_start_m", "wheel_rail", "gravity_m_s2"):
        if key in vehicle_options:
            raise ValueError(f"{key}: set by build_train, not a vehicle option")
    from exudyn.itemInterface import MarkerBodyPosition, ObjectConnectorCartesianSpringDamper

    xs = consist.car_x_m()
    cars = []
    for k, (entry, x) in enumerate(zip(consist.cars, xs)):
        cars.append(build_vehicle(mbs, entry.vehicle, speed_m_s=speed_m_s, s_start_m=s_start_m,
                                  wheel_rail=wheel_rail,
                                  gravity_m_s2=gravity_m_s2, show=show, name_suffix=car_suffix(k), x_offset_m=float(x),
                                  **vehicle_options))
    couplers = []
    cp = consist.coupling
    if cp.enabled:
        for k in range(len(cars) - 1):
            front, rear = cars[k], cars[k + 1]
            p_front = np.array([xs[k] - 0.5 * consist.cars[k].length_m, 0.0, -cp.height_m])        # its rear end
            p_rear = np.array([xs[k + 1] + 0.5 * consist.cars[k + 1].length_m, 0.0, -cp.height_m])  # its front end
            markers = [_car_end_marker(mbs, car.car_body, p, MarkerBodyPosition)
                       for car, p in ((front, p_front), (rear, p_rear))]
            couplers.append(mbs.AddObject(ObjectConnectorCartesianSpringDamper(
                name=f"coupler{car_suffix(k)}{car_suffix(k + 1)}", markerNumbers=markers,
                stiffness=[cp.kx_N_per_m, cp.ky_N_per_m, 0.0], damping=[cp.cx_N_s_per_m, cp.cy_N_s_per_m, 0.0],
                offset=(p_rear - p_front).tolist(),
                visualization={"show": show, "drawSize": -1.0, "color": [-1.0, -1.0, -1.0, -1.0]})))
    return TrainModel(consist=consist, cars=cars, car_x_m=xs, couplers=couplers, speed_m_s=float(speed_m_s),
                      s_start_m=float(s_start_m), gravity_m_s2=float(gravity_m_s2))


def _car_end_marker(mbs, car_body, p_in_frame, marker_type):
    """A position marker on the car body at the model-frame point ``p_in_frame`` (a flexible car body gives its own,
    on its mesh)."""
    local = np.asarray(p_in_frame, dtype=float) - car_body.p_cg_in_frame
    if hasattr(car_body, "position_marker"):
        return car_body.position_marker(mbs, local)
    return mbs.AddMarker(marker_type(bodyNumber=car_body.body, localPosition=local.tolist()))


def place_train_on_track(mbs, train: TrainModel, pair, track) -> float | None:
    """Every car in static equilibrium on the rails (:func:`~.placement.place_on_rails`) and on the displaced track
    (:func:`~.placement.start_on_track`); before ``mbs.Assemble()``.  Returns the largest
    track displacement under a wheelset at t = 0 (None: none) and stores it in ``train.start_shift_m``."""
    shifts = []
    for car in train.cars:
        place_on_rails(mbs, car, pair)
        shifts.append(start_on_track(mbs, car, track))
    shifts = [s for s in shifts if s is not None]
    train.start_shift_m = max(shifts) if shifts else None
    return train.start_shift_m
