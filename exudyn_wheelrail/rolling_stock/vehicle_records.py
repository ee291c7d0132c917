"""The validated vehicle description: the frozen dataclasses a vehicle file is read into (:class:`VehicleData`
with its bodies, suspension elements, bump stop and geometry) and the layout quantities derived from them
(wheelset and bogie positions, total mass, the car body's attachment points, the tape-circle spacing).  The schema,
the reader and its validation: :mod:`.vehicle_data`."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..profiles.profiles import resolve_wheel
from ..profiles.standard import S1002_FLANGE_BACK_Y_M

__all__ = ["FlexibleBodyData", "BodyData", "SuspensionData", "BumpStopData", "GeometryData", "VehicleData"]


@dataclass(frozen=True)
class FlexibleBodyData:
    """``[car_body.flexible]``: the car body as a free–free beam (or an FE model), its kept modes and their damping
    (see the module docstring; the model is :mod:`~exudyn_wheelrail.rolling_stock.flexible_body`)."""

    n_modes: int
    damping_ratio: tuple[float, ...]
    length_m: float | None = None
    EI_vertical_N_m2: float | None = None
    EI_lateral_N_m2: float | None = None
    GJ_N_m2: float | None = None
    EA_N: float | None = None
    elements: int | None = None
    fe_model: str | None = None


@dataclass(frozen=True)
class BodyData:
    """A rigid body: mass, principal inertias about its CG (axes parallel to the track frame), CG position.

    ``cg_height_m`` is measured upwards from the top of rail; ``cg_x_m``/``cg_y_m`` are the CG offsets from the
    body's nominal centre (only the car body may have them).  ``flexible``: the car body's flexible model
    (``[car_body.flexible]``), ``None`` for a rigid body."""

    mass_kg: float
    Ixx_kg_m2: float
    Iyy_kg_m2: float
    Izz_kg_m2: float
    cg_height_m: float
    cg_x_m: float = 0.0
    cg_y_m: float = 0.0
    flexible: FlexibleBodyData | None = None

    @property
    def inertia_kg_m2(self) -> np.ndarray:
        """Diagonal inertia tensor about the CG (3, 3)."""
        return np.diag([self.Ixx_kg_m2, self.Iyy_kg_m2, self.Izz_kg_m2])


@dataclass(frozen=True)
class SuspensionData:
    """Linear spring–damper of one suspension element: stiffness and damping along track x, y, z.

    Primary: per axlebox; secondary: per bogie side.  ``yaw_stiffness_N_m_per_rad`` and
    ``anti_roll_stiffness_N_m_per_rad`` are per bogie (secondary only, 0 otherwise)."""

    stiffness_N_per_m: tuple[float, float, float]
    damping_N_s_per_m: tuple[float, float, float]
    yaw_stiffness_N_m_per_rad: float = 0.0
    anti_roll_stiffness_N_m_per_rad: float = 0.0


@dataclass(frozen=True)
class BumpStopData:
    """Lateral bump stop (per bogie): zero force up to the clearance, then the piecewise-linear table.

    ``displacement_m`` is measured from the centred position (includes the clearance).  Beyond the table the
    force is extrapolated with the last slope; the characteristic is antisymmetric."""

    clearance_m: float
    displacement_m: tuple[float, ...]
    force_N: tuple[float, ...]

    def knots(self) -> tuple[np.ndarray, np.ndarray]:
        """Table including the clearance point: ``(u_m, F_N)``, u from the clearance upwards, F(clearance) = 0."""
        return (np.concatenate([[self.clearance_m], self.displacement_m]),
                np.concatenate([[0.0], self.force_N]))

    def ramps(self) -> tuple[np.ndarray, np.ndarray]:
        """Equivalent sum of ramps: ``F(u) = sign(u) Σ_i dk_i max(|u| - u_i, 0)`` — returns ``(u_i, dk_i)``.

        ``dk_i`` is the change of slope at knot ``u_i`` (the first is the first slope); the sum reproduces the
        piecewise-linear table exactly and continues with the last slope beyond it."""
        u, f = self.knots()
        slopes = np.diff(f) / np.diff(u)
        return u[:-1].copy(), np.diff(np.concatenate([[0.0], slopes]))

    def force(self, u_m):
        """Bump-stop force (N, same sign as the displacement) for relative lateral displacements ``u_m`` (m)."""
        u = np.asarray(u_m, dtype=float)
        knots, dk = self.ramps()
        a = np.abs(u)[..., None]
        return np.sign(u) * np.sum(dk * np.maximum(a - knots, 0.0), axis=-1)


@dataclass(frozen=True)
class GeometryData:
    """Vehicle and wheel–rail geometry (metres; heights above the top of rail).  Keys a layout does not use are
    ``None``."""

    r0_m: float
    back_to_back_m: float
    gauge_m: float
    rail_inclination_tan: float
    wheel_profile: str
    rail_profile: str
    primary_lateral_semi_spacing_m: float
    semi_wheelbase_m: float | None = None
    semi_bogie_centre_distance_m: float | None = None
    secondary_lateral_semi_spacing_m: float | None = None
    secondary_spring_height_m: float | None = None


@dataclass(frozen=True)
class VehicleData:
    """A validated vehicle description (see the module docstring for the schema)."""

    name: str
    layout: str
    source: str
    wheelset: BodyData
    primary: SuspensionData
    geometry: GeometryData
    bogie_frame: BodyData | None = None
    car_body: BodyData | None = None
    secondary: SuspensionData | None = None
    bump_stop: BumpStopData | None = None
    vertical_force_per_side_N: float = 0.0
    description: str = ""
    path: Path | None = field(default=None, compare=False)

    # ---------------------------------------------------------------------------------------- derived layout
    @property
    def n_bogies(self) -> int:
        return {"car": 2, "bogie": 1, "wheelset": 0}[self.layout]

    @property
    def n_wheelsets(self) -> int:
        return {"car": 4, "bogie": 2, "wheelset": 1}[self.layout]

    def bogie_x_m(self) -> list[float]:
        """Bogie centre x positions (vehicle frame: origin at the vehicle centre), front first."""
        if self.layout == "car":
            lb = self.geometry.semi_bogie_centre_distance_m
            return [lb, -lb]
        return [0.0] if self.layout == "bogie" else []

    def wheelset_x_m(self) -> list[float]:
        """Wheelset x positions, front (leading) first."""
        if self.layout == "wheelset":
            return [0.0]
        a = self.geometry.semi_wheelbase_m
        return [x for xb in self.bogie_x_m() for x in (xb + a, xb - a)]

    def wheelset_bogie(self) -> list[int | None]:
        """Index of the bogie each wheelset belongs to (``None`` in the wheelset layout)."""
        return [None] if self.layout == "wheelset" else [i // 2 for i in range(self.n_wheelsets)]

    @property
    def total_mass_kg(self) -> float:
        """Mass of all modelled bodies (the dead load of the bogie/wheelset layouts is not a mass)."""
        m = self.n_wheelsets * self.wheelset.mass_kg
        if self.bogie_frame is not None:
            m += self.n_bogies * self.bogie_frame.mass_kg
        if self.car_body is not None:
            m += self.car_body.mass_kg
        return m

    def wheel_flange_back_y_m(self) -> float:
        """Flange-back position in the wheel profile frame (negative; -0.070 m for S1002)."""
        if self.geometry.wheel_profile.upper() == "S1002":
            return S1002_FLANGE_BACK_Y_M
        return float(resolve_wheel(self.geometry.wheel_profile).flange_back_y_m)

    def car_body_attachment_points_m(self) -> np.ndarray:
        """Points where the suspension acts on the car body, relative to its CG (body axes parallel to the track
        frame, z down) [m], shape (n, 3): per bogie (front first) the left and right secondary springs and the
        bogie centre at secondary height (bump stop; the yaw and anti-roll springs act on the body section there)."""
        if self.layout != "car":
            return np.zeros((0, 3))
        cb, geo = self.car_body, self.geometry
        b2, hs = geo.secondary_lateral_semi_spacing_m, geo.secondary_spring_height_m
        p_cg = np.array([cb.cg_x_m, cb.cg_y_m, -cb.cg_height_m])
        pts = [(xb, y, -hs) for xb in self.bogie_x_m() for y in (-b2, b2, 0.0)]
        return np.array(pts, dtype=float) - p_cg[None, :]

    def tape_circle_semi_spacing_m(self) -> float:
        """Lateral distance of each wheel's tape circle from the track centre line (0.75 m for S1002 at
        back-to-back 1.360 m): back_to_back/2 - (flange-back position in the wheel profile frame)."""
        return 0.5 * self.geometry.back_to_back_m - self.wheel_flange_back_y_m()
