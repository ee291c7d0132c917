"""Vehicle data files (``vehicles/*.toml``): schema, loader and validation; the result is a
:class:`~.vehicle_records.VehicleData` (its dataclasses: :mod:`.vehicle_records`).

The schema is written out with examples in ``vehicles/README.md``; this docstring is its short form.
Units are in the key names (SI): ``_kg``, ``_kg_m2``, ``_m``, ``_N``, ``_N_per_m``, ``_N_s_per_m``,
``_N_m_per_rad``.  Frames and signs: :mod:`exudyn_wheelrail.conventions` (x forward, y right, z down); heights are
measured **upwards from the top of rail** (a height h is the track-frame coordinate z = -h).

Layouts (``[vehicle] layout``)
------------------------------
``"car"``       car body on two bogies, two wheelsets each (Manchester benchmark vehicle 1).
``"bogie"``     one bogie frame on two wheelsets; the car body is replaced by a constant vertical load per side
                (``[load]``) at the secondary spring points, and the secondary suspension's horizontal elements
                (x, y, yaw, optional bump stop) connect the frame to the reference frame that moves with the
                vehicle (a bogie test rig / roller rig).
``"wheelset"``  one wheelset; a constant vertical load per side (``[load]``) at the axlebox points replaces the
                sprung mass, the primary suspension's horizontal elements (x, y) connect the axle to the reference
                frame.
In the ``bogie`` and ``wheelset`` layouts the vertical elements of the layer replaced by the load (kz, cz, and
the anti-roll bar) are not modelled, so those keys are rejected there: a dead load carries no stiffness.

Tables and keys (all required unless marked optional; unknown keys are errors)
----------------------------------------------------------------------------
``schema_version = 1``
``[vehicle]``      ``name``, ``layout``, ``source`` (citation of the numbers); ``description`` (optional).
``[wheelset]``     ``mass_kg``, ``Ixx_kg_m2`` (roll), ``Iyy_kg_m2`` (spin, about the axle), ``Izz_kg_m2`` (yaw);
                   the centre of mass is the axle centre, at height r0.
``[bogie_frame]``  ``mass_kg``, ``Ixx_kg_m2``, ``Iyy_kg_m2``, ``Izz_kg_m2``, ``cg_height_m`` (CG on the bogie
                   centre in x and y).  Layouts car, bogie.
``[car_body]``     as the bogie frame, plus optional ``cg_x_m``, ``cg_y_m`` (offset of the CG from the vehicle
                   centre = mid-point between the bogie centres; default 0).  Layout car.
``[car_body.flexible]`` optional (layout car; without it the car body is rigid): the car body as a free–free
                   beam (:mod:`~exudyn_wheelrail.rolling_stock.flexible_body`) centred on the CG, whose mass and inertia
                   are the ``[car_body]`` data: ``length_m``, ``EI_vertical_N_m2``, ``EI_lateral_N_m2``,
                   ``GJ_N_m2``, ``EA_N`` (all > 0), ``n_modes`` (elastic modes kept, >= 1), ``damping_ratio``
                   (modal damping: one ratio for all modes or an array of ``n_modes``, each in [0, 1)), optional
                   ``elements`` (beam elements, default :data:`~.flexible_body.DEFAULT_ELEMENTS`).  Or, instead of
                   the five beam keys, ``fe_model`` (an FE model of the car body: an ``.npz`` file or one of
                   Exudyn's ``FEMinterface.SaveToFile``, layouts in :func:`~.flexible_body.modes_from_fe_file`,
                   path relative to the TOML file; its mass must be ``[car_body]``'s within 1 %).  Every suspension
                   point on the car body must lie on it (within ``length_m``; an FE model: on a mesh node), and the
                   data's Iyy, Izz must not be below ``M L²/12`` (a uniform beam's).
``base_vehicle``   optional (top level): another vehicle file (a shipped name or a path relative to this file) whose
                   tables this file completes or overrides key by key — e.g. a flexible variant of a vehicle holds
                   only ``base_vehicle`` and ``[car_body.flexible]``.
``[primary]``      **per axlebox** (one element at each axle end): ``kx_N_per_m``, ``ky_N_per_m``, ``kz_N_per_m``,
                   ``cx_N_s_per_m``, ``cy_N_s_per_m``, ``cz_N_s_per_m`` (layout wheelset: x and y only).
``[secondary]``    **per bogie side**: the same six keys, plus **per bogie** ``yaw_stiffness_N_m_per_rad`` (bogie
                   rotation against the car body) and ``anti_roll_stiffness_N_m_per_rad`` (anti-roll bar, roll
                   of the car body against the bogie).  Layout bogie: kx, ky, cx, cy and the yaw stiffness only.
``[bump_stop]``    optional, lateral, **per bogie** (car body against bogie frame): ``clearance_m`` and the
                   characteristic beyond it as two equally long arrays ``displacement_m`` (relative lateral
                   displacement **measured from the centred position**, so every entry exceeds the clearance;
                   strictly increasing) and ``force_N`` (non-decreasing, >= 0).  Force is 0 up to the clearance,
                   linear between the points (the clearance point has force 0), linearly extrapolated with the
                   last slope beyond the table, and antisymmetric.
``[geometry]``     ``r0_m`` (nominal rolling radius = axle height), ``semi_wheelbase_m``,
                   ``semi_bogie_centre_distance_m`` (car), ``primary_lateral_semi_spacing_m``,
                   ``secondary_lateral_semi_spacing_m``, ``secondary_spring_height_m`` (car, bogie),
                   ``back_to_back_m``, ``gauge_m``, ``rail_inclination`` ('1/40', '1/20', 'none' or the tangent),
                   ``wheel_profile`` ('S1002' or a profile file), ``rail_profile`` ('UIC60'/'60E1' or a file);
                   file paths are relative to the TOML file.
``[load]``         layouts bogie and wheelset: ``vertical_force_per_side_N`` (>= 0, downwards).

The primary suspension acts at the axle centre height (the wheelset end of each element lies on the spin axis,
so the wheelset's spin cannot move it); the data files therefore carry no primary spring height.

Validation raises :class:`VehicleDataError` (a ``ValueError``) naming the key (``table.key``) and the file:
missing or unknown keys, wrong types, non-finite numbers, non-positive masses/inertias/lengths, negative
stiffness or damping, inertias violating the triangle inequality, a non-monotonic bump-stop table, and
inconsistent geometry (CG heights or the secondary springs at or below the axle, r0 <= 0, overlapping wheels,
back-to-back not below the gauge, a car-body CG outside its supports, a profile file that does not exist; a flexible
car body with a non-positive stiffness, no modes, damping ratios outside [0, 1), a suspension point off the body or
off the FE mesh, a length whose uniform-beam inertia exceeds the data's, an FE model of another mass), and
implausible lengths (:data:`QUANTITIES`, a value in millimetres is named as such).  Masses and loads far from the
usual ones give an :class:`~exudyn_wheelrail.validation.InputWarning` naming the file and the key.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..contact.pair import BACK_TO_BACK_M, GAUGE_M, INCLINATION_TAN, R0_M, back_to_back_problem
from ..conventions import parse_inclination
from ..profiles.profiles import RAIL_PROFILE_NAMES, WHEEL_PROFILE_NAMES
from ..validation import Quantity, read_toml
from .car_body_fe import read_fe_file
from .car_body_model import DEFAULT_ELEMENTS
from .vehicle_records import (BodyData, BumpStopData, FlexibleBodyData, GeometryData, SuspensionData,  # noqa: F401
                              VehicleData)

__all__ = [
    "SCHEMA_VERSION",
    "FlexibleBodyData",
    "LAYOUTS",
    "VEHICLES_DIR",
    "VehicleDataError",
    "BodyData",
    "SuspensionData",
    "BumpStopData",
    "GeometryData",
    "VehicleData",
    "load_vehicle",
    "load_vehicle_with_overrides",
    "vehicle_from_dict",
    "shipped_vehicles",
]

SCHEMA_VERSION = 1
LAYOUTS = ("car", "bogie", "wheelset")

# Plausibility of the data (beyond sign and type): lengths outside these ranges are errors (a value in millimetres
# is recognised as such), masses and loads outside their typical ranges are warnings.  The wheel-rail placement
# (r0_m, gauge_m, back_to_back_m, rail_inclination) is judged by the ranges of :mod:`..contact.pair`.
QUANTITIES = {
    "geometry.semi_wheelbase_m": Quantity("semi-wheelbase (half the axle spacing of a bogie)", "m", 0.3, 2.5),
    "geometry.semi_bogie_centre_distance_m": Quantity("semi bogie-centre distance", "m", 0.5, 15.0),
    "geometry.primary_lateral_semi_spacing_m": Quantity("lateral semi-spacing of the primary suspension", "m",
                                                        0.2, 1.8),
    "geometry.secondary_lateral_semi_spacing_m": Quantity("lateral semi-spacing of the secondary suspension", "m",
                                                          0.2, 1.8),
    "geometry.secondary_spring_height_m": Quantity("secondary spring height above the rail", "m", 0.1, 3.0),
    "bogie_frame.cg_height_m": Quantity("bogie-frame CG height above the rail", "m", 0.1, 2.0),
    "car_body.cg_height_m": Quantity("car-body CG height above the rail", "m", 0.1, 4.5),
    "car_body.flexible.length_m": Quantity("length of the flexible car body", "m", 3.0, 40.0),
    "bump_stop.clearance_m": Quantity("bump-stop clearance", "m", 0.0, 0.3),
    "bump_stop.displacement_m": Quantity("bump-stop displacement", "m", 0.0, 0.5),
    "wheelset.mass_kg": Quantity("wheelset mass", "kg", typical=(300.0, 5000.0)),
    "bogie_frame.mass_kg": Quantity("bogie-frame mass", "kg", typical=(500.0, 15000.0)),
    "car_body.mass_kg": Quantity("car-body mass", "kg", typical=(3000.0, 150000.0)),
    "load.vertical_force_per_side_N": Quantity("vertical load per side", "N", typical=(1.0e3, 3.0e5)),
}

#: The shipped vehicle files (``vehicles/`` at the repository root, beside the package).
VEHICLES_DIR = Path(__file__).resolve().parents[2] / "vehicles"


class VehicleDataError(ValueError):
    """Bad vehicle data; the message names the key (``table.key``) and the file."""


# --------------------------------------------------------------------------------------------------- reading
_BODY_KEYS = ("mass_kg", "Ixx_kg_m2", "Iyy_kg_m2", "Izz_kg_m2")
_SPRING_KEYS = ("kx_N_per_m", "ky_N_per_m", "kz_N_per_m")
_DAMPER_KEYS = ("cx_N_s_per_m", "cy_N_s_per_m", "cz_N_s_per_m")
_SECONDARY_EXTRA = ("yaw_stiffness_N_m_per_rad", "anti_roll_stiffness_N_m_per_rad")
_GEOMETRY_ALWAYS = ("r0_m", "primary_lateral_semi_spacing_m", "back_to_back_m", "gauge_m", "rail_inclination",
                    "wheel_profile", "rail_profile")

# required / optional keys per table and layout
_REQUIRED = {
    "car": {
        "vehicle": ("name", "layout", "source"),
        "wheelset": _BODY_KEYS,
        "bogie_frame": _BODY_KEYS + ("cg_height_m",),
        "car_body": _BODY_KEYS + ("cg_height_m",),
        "primary": _SPRING_KEYS + _DAMPER_KEYS,
        "secondary": _SPRING_KEYS + _DAMPER_KEYS + _SECONDARY_EXTRA,
        "geometry": _GEOMETRY_ALWAYS + ("semi_wheelbase_m", "semi_bogie_centre_distance_m",
                                        "secondary_lateral_semi_spacing_m", "secondary_spring_height_m"),
    },
    "bogie": {
        "vehicle": ("name", "layout", "source"),
        "wheelset": _BODY_KEYS,
        "bogie_frame": _BODY_KEYS + ("cg_height_m",),
        "primary": _SPRING_KEYS + _DAMPER_KEYS,
        "secondary": ("kx_N_per_m", "ky_N_per_m", "cx_N_s_per_m", "cy_N_s_per_m", "yaw_stiffness_N_m_per_rad"),
        "geometry": _GEOMETRY_ALWAYS + ("semi_wheelbase_m", "secondary_lateral_semi_spacing_m",
                                        "secondary_spring_height_m"),
        "load": ("vertical_force_per_side_N",),
    },
    "wheelset": {
        "vehicle": ("name", "layout", "source"),
        "wheelset": _BODY_KEYS,
        "primary": ("kx_N_per_m", "ky_N_per_m", "cx_N_s_per_m", "cy_N_s_per_m"),
        "geometry": _GEOMETRY_ALWAYS,
        "load": ("vertical_force_per_side_N",),
    },
}
_OPTIONAL = {
    "vehicle": ("description",),
    "car_body": ("cg_x_m", "cg_y_m", "flexible"),
    "bump_stop": ("clearance_m", "displacement_m", "force_N"),
}
_BUMP_STOP_LAYOUTS = ("car", "bogie")
_WHY_ABSENT = {
    "bogie": "in layout 'bogie' the car body is replaced by [load] (a dead load has no stiffness)",
    "wheelset": "in layout 'wheelset' the sprung mass is replaced by [load] (a dead load has no stiffness)",
}


class _Reader:
    """Typed access to the parsed TOML with errors naming the key and the file."""

    def __init__(self, data: dict, where: str):
        self.data = data
        self.where = where

    def error(self, key: str, message: str) -> VehicleDataError:
        return VehicleDataError(f"{self.where}: {key}: {message}")

    def table(self, name: str) -> dict:
        value = self.data.get(name)
        if value is None:
            raise self.error(f"[{name}]", "missing table")
        if not isinstance(value, dict):
            raise self.error(name, f"expected a table [{name}], got {type(value).__name__}")
        return value

    def number(self, table: str, key: str, *, positive=False, non_negative=False, default=None) -> float:
        tab = self.data.get(table, {})
        if key not in tab:
            if default is not None:
                return float(default)
            raise self.error(f"{table}.{key}", "missing key")
        value = tab[key]
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(f"{table}.{key}", f"expected a number, got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise self.error(f"{table}.{key}", f"must be finite, got {value!r}")
        if positive and not value > 0.0:
            raise self.error(f"{table}.{key}", f"must be positive, got {value!r}")
        if non_negative and value < 0.0:
            raise self.error(f"{table}.{key}", f"must not be negative, got {value!r}")
        return value

    def plausible(self, table: str, key: str, value: float, quantity: Quantity | None = None) -> float:
        """``value`` judged by its :class:`~..validation.Quantity` (default ``QUANTITIES['table.key']``): an error
        naming the file and the key if implausible, an :class:`~..validation.InputWarning` naming them if unusual."""
        q = quantity if quantity is not None else QUANTITIES[f"{table}.{key}"]
        return q.check(f"{self.where}: {table}.{key}", value, error=VehicleDataError)

    def string(self, table: str, key: str, default=None) -> str:
        tab = self.data.get(table, {})
        if key not in tab:
            if default is not None:
                return default
            raise self.error(f"{table}.{key}", "missing key")
        value = tab[key]
        if not isinstance(value, str) or not value.strip():
            raise self.error(f"{table}.{key}", f"expected a non-empty string, got {value!r}")
        return value.strip()

    def numbers(self, table: str, key: str) -> tuple[float, ...]:
        tab = self.data.get(table, {})
        if key not in tab:
            raise self.error(f"{table}.{key}", "missing key")
        value = tab[key]
        if not isinstance(value, list) or not value:
            raise self.error(f"{table}.{key}", f"expected a non-empty array of numbers, got {value!r}")
        out = []
        for v in value:
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
                raise self.error(f"{table}.{key}", f"expected finite numbers, got {v!r}")
            out.append(float(v))
        return tuple(out)


def _check_keys(r: _Reader, layout: str) -> None:
    required = _REQUIRED[layout]
    allowed_tables = set(required) | {"bump_stop"} if layout in _BUMP_STOP_LAYOUTS else set(required)
    for name, value in r.data.items():
        if name == "schema_version":
            continue
        if name not in allowed_tables:
            why = _WHY_ABSENT.get(layout, "")
            raise r.error(f"[{name}]", f"table not used in layout {layout!r}" + (f" ({why})" if why else "") +
                          f"; allowed tables: {', '.join(sorted(allowed_tables))}")
        if not isinstance(value, dict):
            raise r.error(name, f"expected a table [{name}], got {type(value).__name__}")
        allowed = set(required.get(name, ())) | set(_OPTIONAL.get(name, ()))
        for key in value:
            if key not in allowed:
                all_keys = set(_SPRING_KEYS + _DAMPER_KEYS + _SECONDARY_EXTRA)
                hint = f" ({_WHY_ABSENT[layout]})" if key in all_keys and layout in _WHY_ABSENT else ""
                raise r.error(f"{name}.{key}", f"unknown key for layout {layout!r}{hint}; allowed: "
                                               f"{', '.join(sorted(allowed))}")
    for name, keys in required.items():
        tab = r.table(name)
        for key in keys:
            if key not in tab:
                raise r.error(f"{name}.{key}", "missing key")
    if "bump_stop" in r.data:
        for key in _OPTIONAL["bump_stop"]:
            if key not in r.data["bump_stop"]:
                raise r.error(f"bump_stop.{key}", "missing key")


def _body(r: _Reader, table: str, cg_height_m: float | None = None) -> BodyData:
    m, ixx, iyy, izz = (r.number(table, k, positive=True) for k in _BODY_KEYS)
    r.plausible(table, "mass_kg", m)
    for a, b, c, names in ((ixx, iyy, izz, "Ixx + Iyy >= Izz"), (iyy, izz, ixx, "Iyy + Izz >= Ixx"),
                           (izz, ixx, iyy, "Izz + Ixx >= Iyy")):
        if a + b < c * (1.0 - 1e-12):
            raise r.error(f"{table}.Ixx_kg_m2/Iyy_kg_m2/Izz_kg_m2",
                          f"principal inertias ({ixx:g}, {iyy:g}, {izz:g}) violate {names} (no rigid body has them)")
    h = (cg_height_m if cg_height_m is not None else
         r.plausible(table, "cg_height_m", r.number(table, "cg_height_m", positive=True)))
    return BodyData(m, ixx, iyy, izz, h, r.number(table, "cg_x_m", default=0.0),
                    r.number(table, "cg_y_m", default=0.0))


_FLEXIBLE_BEAM_KEYS = ("length_m", "EI_vertical_N_m2", "EI_lateral_N_m2", "GJ_N_m2", "EA_N")
_FLEXIBLE_KEYS = _FLEXIBLE_BEAM_KEYS + ("n_modes", "damping_ratio", "elements", "fe_model")


def _flexible(r: _Reader, car: BodyData, base: Path | None) -> FlexibleBodyData:
    """``[car_body.flexible]``: keys, signs, the modes, and the body's consistency with ``[car_body]``."""
    t = "car_body.flexible"
    tab = r.data["car_body"]["flexible"]
    if not isinstance(tab, dict):
        raise r.error(t, f"expected a table [{t}], got {type(tab).__name__}")
    for key in tab:
        if key not in _FLEXIBLE_KEYS:
            raise r.error(f"{t}.{key}", f"unknown key; allowed: {', '.join(_FLEXIBLE_KEYS)}")
    sub = _Reader({t: tab}, r.where)
    if "n_modes" not in tab:
        raise r.error(f"{t}.n_modes", "missing key (the number of elastic modes kept, >= 1)")
    n = tab.get("n_modes")
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise r.error(f"{t}.n_modes", f"expected an integer >= 1 (the elastic modes kept), got {n!r}")
    raw = tab.get("damping_ratio")
    if raw is None:
        raise r.error(f"{t}.damping_ratio", "missing key (one modal damping ratio for all modes or one per mode)")
    zeta = sub.numbers(t, "damping_ratio") if isinstance(raw, list) else (sub.number(t, "damping_ratio"),) * n
    if len(zeta) != n:
        raise r.error(f"{t}.damping_ratio", f"{len(zeta)} ratios for n_modes = {n} (give one or {n})")
    if any(not 0.0 <= z < 1.0 for z in zeta):
        raise r.error(f"{t}.damping_ratio", f"ratios must lie in [0, 1) (not percentages), got {list(zeta)}")
    elements = tab.get("elements")
    if elements is not None and (isinstance(elements, bool) or not isinstance(elements, int) or elements < 2):
        raise r.error(f"{t}.elements", f"expected an integer >= 2, got {elements!r}")
    if "fe_model" not in tab:
        n_max = 6 * (elements or DEFAULT_ELEMENTS)           # 6 DOFs per node, n_e + 1 nodes, 6 rigid modes
        if n > n_max:
            raise r.error(f"{t}.n_modes", f"{n} modes but a beam of {elements or DEFAULT_ELEMENTS} elements has "
                                          f"{n_max} elastic modes")
    if "fe_model" in tab:
        given = [k for k in _FLEXIBLE_BEAM_KEYS + ("elements",) if k in tab]
        if given:
            raise r.error(f"{t}.fe_model", f"give either fe_model or the beam keys, not both ({', '.join(given)})")
        path = Path(sub.string(t, "fe_model"))
        if not path.is_absolute() and base is not None:
            path = base / path
        if not path.is_file():
            raise r.error(f"{t}.fe_model", f"FE model file not found ({path})")
        return FlexibleBodyData(n, tuple(zeta), fe_model=str(path))
    beam = {k: sub.number(t, k) for k in _FLEXIBLE_BEAM_KEYS}
    for k, v in beam.items():
        if not v > 0.0:
            raise r.error(f"{t}.{k}", f"must be positive, got {v!r}")
    L = sub.plausible(t, "length_m", beam["length_m"], QUANTITIES["car_body.flexible.length_m"])
    for key, inertia in (("Iyy_kg_m2", car.Iyy_kg_m2), ("Izz_kg_m2", car.Izz_kg_m2)):
        uniform = car.mass_kg * L * L / 12.0
        if inertia < uniform * (1.0 - 1e-9):
            raise r.error(f"{t}.length_m", f"{L} m: a uniform beam of the car body's mass has the inertia M L²/12 = "
                                           f"{uniform:.4g} kg m², above car_body.{key} = {inertia:.4g} (the body "
                                           f"may be at most {math.sqrt(12.0 * inertia / car.mass_kg):.3f} m long)")
    return FlexibleBodyData(n, tuple(zeta), elements=elements, **beam)


def _check_flexible_points(r: _Reader, vehicle: "VehicleData") -> None:
    """Every suspension point of the car body on the flexible body."""
    fx = vehicle.car_body.flexible
    pts = vehicle.car_body_attachment_points_m()
    t = "car_body.flexible"
    if fx.fe_model is None:
        half = 0.5 * fx.length_m
        for p in pts:
            if abs(p[0]) > half:
                raise r.error(f"{t}.length_m", f"{fx.length_m} m: the secondary suspension point at x = {p[0]:g} m "
                                               f"from the car-body CG is off the body (x within ±{half:g} m)")
        return
    try:
        nodes, mass, _ = read_fe_file(fx.fe_model)
    except ValueError as exc:
        raise r.error(f"{t}.fe_model", str(exc)) from None
    ones = np.zeros(mass.shape[0])
    ones[0::3] = 1.0
    m_fe = float(ones @ (mass @ ones))
    if abs(m_fe / vehicle.car_body.mass_kg - 1.0) > 0.01:
        raise r.error(f"{t}.fe_model", f"the FE model's mass {m_fe:.6g} kg differs from car_body.mass_kg = "
                                       f"{vehicle.car_body.mass_kg:.6g} kg by more than 1 %")
    for p in pts:
        d = float(np.min(np.linalg.norm(nodes - p[None, :], axis=1)))
        if d > 1e-6:
            raise r.error(f"{t}.fe_model", f"the suspension point {np.round(p, 4).tolist()} m (from the CG) is not a "
                                           f"node of the FE mesh (nearest node {d:.3g} m away)")


def _suspension(r: _Reader, table: str, layout: str) -> SuspensionData:
    tab = r.data[table]
    k = tuple(r.number(table, key, non_negative=True) if key in tab else 0.0 for key in _SPRING_KEYS)
    c = tuple(r.number(table, key, non_negative=True) if key in tab else 0.0 for key in _DAMPER_KEYS)
    extra = [r.number(table, key, non_negative=True) if key in tab else 0.0 for key in _SECONDARY_EXTRA]
    return SuspensionData(k, c, *extra)


def _profile(r: _Reader, key: str, names: tuple[str, ...], base: Path | None) -> str:
    value = r.string("geometry", key)
    if value.upper() in names:
        return value.upper()
    path = Path(value)
    if not path.is_absolute() and base is not None:
        path = base / path
    if not path.is_file():
        raise r.error(f"geometry.{key}", f"{value!r} is neither one of {', '.join(names)} nor an existing profile "
                                         f"file (looked for {path})")
    return str(path)


def _geometry(r: _Reader, layout: str, base: Path | None) -> GeometryData:
    g = "geometry"
    tab = r.data[g]
    r0 = r.number(g, "r0_m")
    if not r0 > 0.0:
        raise r.error(f"{g}.r0_m", f"the nominal rolling radius must be positive, got {r0!r}")
    r.plausible(g, "r0_m", r0, R0_M)
    gauge = r.plausible(g, "gauge_m", r.number(g, "gauge_m", positive=True), GAUGE_M)
    b2b = r.plausible(g, "back_to_back_m", r.number(g, "back_to_back_m", positive=True), BACK_TO_BACK_M)
    problem = back_to_back_problem(gauge, b2b, "the gauge (geometry.gauge_m)")
    if problem:
        raise r.error(f"{g}.back_to_back_m", problem)
    raw_inclination = tab.get("rail_inclination")
    if isinstance(raw_inclination, bool) or not isinstance(raw_inclination, (str, int, float)):
        raise r.error(f"{g}.rail_inclination", f"expected '1/40', '1/20', 'none' or a number, got {raw_inclination!r}")
    try:
        inclination = parse_inclination(raw_inclination)
    except ValueError as exc:
        raise r.error(f"{g}.rail_inclination", str(exc)) from None
    r.plausible(g, "rail_inclination", inclination, INCLINATION_TAN)
    wheel = _profile(r, "wheel_profile", WHEEL_PROFILE_NAMES, base)
    rail = _profile(r, "rail_profile", RAIL_PROFILE_NAMES, base)

    def length(key):
        return r.plausible(g, key, r.number(g, key, positive=True)) if key in tab else None

    b1 = length("primary_lateral_semi_spacing_m")
    a = length("semi_wheelbase_m")
    lb = length("semi_bogie_centre_distance_m")
    b2 = length("secondary_lateral_semi_spacing_m")
    hs = length("secondary_spring_height_m")
    if a is not None and a <= r0:
        raise r.error(f"{g}.semi_wheelbase_m", f"{a} m is not larger than r0 = {r0} m: the wheels of a bogie "
                                               "would overlap")
    if lb is not None and lb <= a + r0:
        raise r.error(f"{g}.semi_bogie_centre_distance_m", f"{lb} m is not larger than semi_wheelbase + r0 = "
                                                           f"{a + r0} m: the inner wheelsets would overlap")
    if hs is not None and hs <= r0:
        raise r.error(f"{g}.secondary_spring_height_m", f"{hs} m is not above the axle (r0 = {r0} m)")
    return GeometryData(r0, b2b, gauge, inclination, wheel, rail, b1, a, lb, b2, hs)


def _bump_stop(r: _Reader) -> BumpStopData:
    t = "bump_stop"
    clearance = r.plausible(t, "clearance_m", r.number(t, "clearance_m", non_negative=True))
    u = r.numbers(t, "displacement_m")
    for v in u:
        r.plausible(t, "displacement_m", v)
    f = r.numbers(t, "force_N")
    if len(u) != len(f):
        raise r.error(f"{t}.displacement_m/force_N", f"arrays of different length ({len(u)} and {len(f)})")
    if u[0] <= clearance:
        raise r.error(f"{t}.displacement_m", f"first displacement {u[0]} m is not beyond the clearance {clearance} m "
                                             "(displacements are measured from the centred position)")
    if any(b <= a for a, b in zip(u, u[1:])):
        raise r.error(f"{t}.displacement_m", f"not strictly increasing: {list(u)}")
    if any(v < 0.0 for v in f):
        raise r.error(f"{t}.force_N", f"forces must not be negative (the characteristic is antisymmetric): {list(f)}")
    if any(b < a for a, b in zip(f, f[1:])):
        raise r.error(f"{t}.force_N", f"not monotonic (must not decrease with the displacement): {list(f)}")
    return BumpStopData(clearance, u, f)


def vehicle_from_dict(data: dict, source: str | Path = "<dict>", base_dir: Path | None = None) -> VehicleData:
    """Validate parsed TOML content; ``source`` names the file in error messages, ``base_dir`` resolves relative
    profile paths."""
    where = str(source)
    r = _Reader(data, where)
    version = data.get("schema_version")
    if version is None:
        raise r.error("schema_version", f"missing key (expected schema_version = {SCHEMA_VERSION})")
    if isinstance(version, bool) or version != SCHEMA_VERSION:
        raise r.error("schema_version", f"unsupported version {version!r} (this reader: {SCHEMA_VERSION})")
    r.table("vehicle")
    layout = r.string("vehicle", "layout")
    if layout not in LAYOUTS:
        raise r.error("vehicle.layout", f"{layout!r} is not one of {', '.join(LAYOUTS)}")
    _check_keys(r, layout)
    geometry = _geometry(r, layout, base_dir)
    wheelset = _body(r, "wheelset", cg_height_m=geometry.r0_m)
    bogie = car = secondary = None
    if layout in ("car", "bogie"):
        bogie = _body(r, "bogie_frame")
        if bogie.cg_height_m <= geometry.r0_m:
            raise r.error("bogie_frame.cg_height_m", f"{bogie.cg_height_m} m is not above the axle (r0 = "
                                                     f"{geometry.r0_m} m)")
        secondary = _suspension(r, "secondary", layout)
    if layout == "car":
        car = _body(r, "car_body")
        if car.cg_height_m <= geometry.r0_m:
            raise r.error("car_body.cg_height_m", f"{car.cg_height_m} m is not above the axle (r0 = {geometry.r0_m} m)")
        if abs(car.cg_x_m) >= geometry.semi_bogie_centre_distance_m:
            raise r.error("car_body.cg_x_m", f"{car.cg_x_m} m puts the CG outside the bogie centres "
                                             f"(±{geometry.semi_bogie_centre_distance_m} m)")
        if abs(car.cg_y_m) >= geometry.secondary_lateral_semi_spacing_m:
            raise r.error("car_body.cg_y_m", f"{car.cg_y_m} m puts the CG outside the secondary springs "
                                             f"(±{geometry.secondary_lateral_semi_spacing_m} m)")
        for table in ("primary", "secondary"):
            if not r.number(table, "kz_N_per_m") > 0.0:
                raise r.error(f"{table}.kz_N_per_m", "must be positive in layout 'car' (it carries the weight)")
        if "flexible" in r.data["car_body"]:
            car = BodyData(**{**car.__dict__, "flexible": _flexible(r, car, base_dir)})
    primary = _suspension(r, "primary", layout)
    bump = _bump_stop(r) if "bump_stop" in data else None
    load = (r.plausible("load", "vertical_force_per_side_N", r.number("load", "vertical_force_per_side_N",
                                                                      non_negative=True))
            if "load" in data else 0.0)
    vehicle = VehicleData(
        name=r.string("vehicle", "name"), layout=layout, source=r.string("vehicle", "source"), wheelset=wheelset,
        primary=primary, geometry=geometry, bogie_frame=bogie, car_body=car, secondary=secondary, bump_stop=bump,
        vertical_force_per_side_N=load, description=r.string("vehicle", "description", default=""),
        path=Path(source) if isinstance(source, Path) else None)
    if car is not None and car.flexible is not None:
        _check_flexible_points(r, vehicle)
    return vehicle


def load_vehicle(source: str | Path) -> VehicleData:
    """Load and validate a vehicle file: a path to a ``.toml`` file or the name of a shipped vehicle
    (``'manchester_vehicle1'``, ``'single_bogie'``, ``'single_wheelset'``; see :func:`shipped_vehicles`)."""
    path = Path(source)
    if not path.suffix and not path.exists():
        path = VEHICLES_DIR / f"{source}.toml"
    if not path.is_file():
        raise VehicleDataError(f"{source}: vehicle file not found (shipped vehicles: "
                               f"{', '.join(shipped_vehicles()) or 'none'})")
    data = _read_toml(path)
    return vehicle_from_dict(data, path.resolve(), base_dir=path.resolve().parent)


def _read_toml(path: Path, _seen: tuple = ()) -> dict:
    """The parsed file with its ``base_vehicle`` (module docstring) merged in: the base's tables completed or
    overridden key by key (sub-tables likewise); base profile paths are made absolute."""
    path = Path(path).resolve()
    if path in _seen:
        raise VehicleDataError(f"{path}: base_vehicle: circular reference ({' -> '.join(map(str, _seen + (path,)))})")
    data = read_toml(path, VehicleDataError)
    base = data.pop("base_vehicle", None)
    if base is None:
        return data
    if not isinstance(base, str) or not base.strip():
        raise VehicleDataError(f"{path}: base_vehicle: expected a vehicle name or file, got {base!r}")
    base_path = Path(base) if Path(base).suffix else VEHICLES_DIR / f"{base}.toml"
    if not base_path.is_absolute() and Path(base).suffix:
        base_path = path.parent / base_path
    if not base_path.is_file():
        raise VehicleDataError(f"{path}: base_vehicle: {base!r} not found (looked for {base_path})")
    merged = _read_toml(base_path, _seen + (path,))
    geo = merged.get("geometry", {})
    for key in ("wheel_profile", "rail_profile"):          # relative profile files of the base stay the base's
        v = geo.get(key)
        if isinstance(v, str) and (Path(v).suffix and not Path(v).is_absolute()):
            geo[key] = str(base_path.resolve().parent / v)

    def merge(into: dict, new: dict):
        for k, v in new.items():
            if isinstance(v, dict) and isinstance(into.get(k), dict):
                merge(into[k], v)
            else:
                into[k] = v

    merge(merged, data)
    return merged


def shipped_vehicles() -> list[str]:
    """Names of the vehicle files in ``vehicles/``."""
    return sorted(p.stem for p in VEHICLES_DIR.glob("*.toml")) if VEHICLES_DIR.is_dir() else []


def load_vehicle_with_overrides(source: str | Path, overrides: dict | None = None) -> VehicleData:
    """:func:`load_vehicle` with some values of the file replaced: ``overrides`` maps ``"table.key"`` (as in the
    TOML file, e.g. ``"primary.ky_N_per_m"``, ``"secondary.cy_N_s_per_m"``) to the new value (SI units of the key's
    name).  Only keys present in the file can be overridden; an unknown table or key, or a value that is not a
    number (a list of numbers for the bump-stop arrays), raises :class:`VehicleDataError` naming the key and the
    file.  The patched data go through the same validation as a file (:func:`vehicle_from_dict`)."""
    base = load_vehicle(source)
    if not overrides:
        return base
    data = _read_toml(base.path)
    where = f"{base.path} (with overrides)"
    for dotted, value in overrides.items():
        table, _, key = str(dotted).partition(".")
        if not key or "." in key:
            raise VehicleDataError(f"{base.path}: override {dotted!r}: expected 'table.key', e.g. 'primary.ky_N_per_m'")
        tab = data.get(table)
        if not isinstance(tab, dict):
            tables = sorted(k for k, v in data.items() if isinstance(v, dict))
            raise VehicleDataError(f"{base.path}: override {dotted!r}: unknown table [{table}]; tables: "
                                   f"{', '.join(tables)}")
        if key not in tab:
            raise VehicleDataError(f"{base.path}: override {dotted!r}: unknown key {key!r} in [{table}]; keys: "
                                   f"{', '.join(sorted(tab))}")
        ok_number = not isinstance(value, bool) and isinstance(value, (int, float, np.integer, np.floating))
        ok_list = (isinstance(value, (list, tuple)) and isinstance(tab[key], list) and
                   all(not isinstance(v, bool) and isinstance(v, (int, float, np.integer, np.floating)) for v in value))
        if isinstance(tab[key], str):
            raise VehicleDataError(f"{base.path}: override {dotted!r}: text values (names, profiles) cannot be "
                                   "overridden; use a vehicle file")
        if not (ok_number or ok_list) or (ok_number and isinstance(tab[key], list)):
            what = "a list of numbers" if isinstance(tab[key], list) else "a number"
            raise VehicleDataError(f"{base.path}: override {dotted!r}: expected {what}, got {value!r}")
        tab[key] = [float(v) for v in value] if ok_list else float(value)
    return vehicle_from_dict(data, where, base_dir=base.path.parent)
