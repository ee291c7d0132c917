r"""The RTRI case as a spec: :class:`RtriCase` (span, speed, deviation, vehicle-file overrides, run and contact
settings) written as a normalised scenario by :meth:`RtriCase.scenario`, and the case's assumptions with their
origin (:class:`RtriCaseAssumptions`, :func:`assumptions_table`).  The public import path of the case is
:mod:`exudyn_wheelrail.scenarios.rtri`; the run is :mod:`.rtri_run`.

What is simulated
-----------------
Manchester benchmark vehicle 1 (``vehicles/manchester_vehicle1.toml``: car body, two bogies, four wheelsets) with
S1002 wheels on UIC60 rails inclined 1:40, gauge and back-to-back from the vehicle file, on a rigid straight track
whose centre line is displaced laterally by one span's deflection (:class:`~..track.rigid.SpanDeflection`:
δ sin(π x/L) with C2 end transitions of length l_t), at the constant running speed V imposed by the model frame
(:mod:`..rolling_stock.vehicle_builder`: the frame translates with V, the wheelsets spin, the car body is held
longitudinally by a soft spring — the roller rig's holding link).  The contact is the project's connector
(:func:`~..multibody.connector.add_wheel_rail_contact`), the vehicle starts in static equilibrium on the rails
(:func:`~..multibody.connector.place_on_rails`).

Position of the deviation and length of the run
-----------------------------------------------
At t = 0 the leading wheelset stands at track distance s = 0; the first transition begins ``lead_in_m`` (10 m)
ahead of it, so the deviation lies ahead of the whole vehicle.  The leading wheelset has left the span (end of
the second transition) at ``s = lead_in + L + l_t``; the whole car at ``s = lead_in + L + l_t + e`` (e = 21.56 m,
leading to trailing wheelset); :meth:`RtriAssumptions.run_time_s` adds a run-out of 10 m.  The paper's 2500 steps
of 1 ms (2.5 s) cover at V:

* the leading wheelset crossing the whole span for V >= 47.5 km/h (L = 20 m) and V >= 76.3 km/h (L = 40 m);
* the whole car leaving the span for V >= 78.6 km/h (20 m) and V >= 107.4 km/h (40 m);
* the whole car plus the run-out for V >= 93.0 km/h (20 m) and V >= 121.8 km/h (40 m) —
  so the default speed set covers everything but the run-out (and, at 100 km/h, the trailing wheelset leaving
  the 40 m span: it leaves at 2.68 s).  ``duration_s="auto"`` (the sweep's default) runs
  ``max(2.5 s, time needed)``; every summary states what the run covers (``coverage`` and ``notes``).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from ..rolling_stock.vehicle_data import load_vehicle_with_overrides
from ..simulation.settings import DURATION_AUTO, ContactSettings, RunSettings
from ..simulation.solvers import NEWMARK_BETA, NEWMARK_GAMMA
from ..validation import finite
from .defaults import CAR_BODY_MODELS
from .rtri_assumptions import RTRI, RtriAssumptions
from .scenario import DEFAULT_FLOOR_HEIGHT_M, validate_scenario

__all__ = [
    "RtriCaseAssumptions",
    "RTRI_CASE",
    "CAR_BODY_MODELS",
    "CARBODY_POINTS",
    "RtriCase",
    "RTRI_GROUPS",
    "assumptions_table",
    "case_assumptions_table",
    "vehicle_extent_m",
]

#: the scenario groups the case records
RTRI_GROUPS = ("Y", "Q", "YQ", "flange", "contact_angle", "wheelset_lateral", "track", "carbody")
# CAR_BODY_MODELS, the car-body models of the case (``RtriCase.car_body``, ``rtri --car-body``), are declared in
# .defaults (the command line shows them).
#: the car-body measurement points at floor level (name -> position along the car, scenario ``x_m``); the rigid
#: case records ``rear`` (Fig. 5), the flexible one all three (comfort at the bogies and mid-car)
CARBODY_POINTS = {"front": "front_bogie", "centre": "centre", "rear": "rear_bogie"}


# ============================================================================================ ASSUMPTIONS block
# Assumptions this case needs that RtriAssumptions (rtri_assumptions.py) does not hold; assumptions_table() and
# summary.json list them together with RtriAssumptions.
@dataclass(frozen=True)
class RtriCaseAssumptions:
    """Output-side and modelling assumptions of the RTRI case not in :class:`RtriAssumptions` (origin given per
    field in :data:`_CASE_ORIGINS`)."""

    #: ASSUMPTION: height of the car-body floor (where the accelerometer sits) above the rail top [m]
    floor_height_m: float = DEFAULT_FLOOR_HEIGHT_M
    #: ASSUMPTION: the speed of Figs. 5/6 and of the 20 m vs 40 m check [km/h]
    representative_speed_km_h: float = 250.0
    #: ASSUMPTION: wheel–rail friction coefficient (dry steel on steel; the contact settings' default)
    friction_coefficient: float = field(default_factory=lambda: ContactSettings().friction)
    #: the creep law and FASTSIM's grid (the contact settings' defaults)
    creep_law: str = field(default_factory=lambda: ContactSettings().creep_law)
    fastsim_grid: tuple[int, int] = field(default_factory=lambda: ContactSettings().fastsim_grid)

    def __post_init__(self):
        if not (0.0 < self.floor_height_m < 5.0):
            raise ValueError(f"floor_height_m = {self.floor_height_m}: expected a height above rail in (0, 5) m")
        if not (0.0 < self.representative_speed_km_h <= RTRI.plant_max_speed_km_h):
            raise ValueError(f"representative_speed_km_h = {self.representative_speed_km_h}: expected (0, "
                             f"{RTRI.plant_max_speed_km_h}] km/h (the plant's range)")
        if not (0.0 <= self.friction_coefficient < 2.0):
            raise ValueError(f"friction_coefficient = {self.friction_coefficient}: expected [0, 2)")


RTRI_CASE = RtriCaseAssumptions()

_RTRI_ORIGINS = {
    "span_lengths_m": "published (Montenegro et al. 2015: spans compared)",
    "time_step_s": "published",
    "n_steps_published": "published (2500 steps)",
    "newmark_beta": "published",
    "newmark_gamma": "published",
    "plant_max_speed_km_h": "published (RTRI plant limit)",
    "deviation_direction": "published (lateral irregularity of a rigid track)",
    "vehicle": "ASSUMPTION: substitute vehicle (test vehicle unpublished; rtri_scenario.md)",
    "flexible_vehicle": "ASSUMPTION: the substitute vehicle with a flexible car body, first modes 10 Hz vertical "
                        "bending, 12 Hz torsion, 15 Hz lateral bending, 2 % damping (rtri_assumptions.py)",
    "deviation_amplitude_m": "ASSUMPTION: of the order of the code limits for deck-end rotation, πδ/L = 1.6 mrad "
                             "at 20 m (rtri_assumptions.py)",
    "transition_length_m": "ASSUMPTION: ≈ π λ, bending half-wavelength of the rails on their lateral support "
                           "(rtri_assumptions.py)",
    "deviation_sign": "ASSUMPTION: the span deflects towards +y (the right rail)",
    "speeds_km_h": "ASSUMPTION: up to the plant's limit; V/(2L) brackets the car body's 0.5-1.5 Hz lateral modes "
                   "(rtri.py docstring)",
    "lead_in_m": "ASSUMPTION: leading wheelset to the start of the first transition at t = 0",
    "run_out_m": "ASSUMPTION: distance run after the trailing wheelset has left the span",
}
_CASE_ORIGINS = {
    "floor_height_m": "ASSUMPTION (rtri.py): typical floor height of a standard-gauge passenger coach (~1.2 m); "
                      "the Manchester data give no floor height",
    "representative_speed_km_h": "ASSUMPTION (rtri.py): the plant's maximum speed, the most severe test condition; "
                                 "chosen before any run",
    "friction_coefficient": "ASSUMPTION (rtri.py): dry steel on steel, the connector's default",
    "creep_law": "published method (Montenegro et al. 2015): creep forces interpolated in a table of Kalker's exact "
                 "theory (our exudyn_wheelrail.creep.table)",
    "fastsim_grid": "ASSUMPTION (rtri.py): FASTSIM discretisation (n_x, n_y), used only with --creep-law fastsim",
}
_OTHER_MODEL_CHOICES = {
    "wheel_rail_pair": "S1002 on UIC60 1:40, gauge and back-to-back from the vehicle file (substitutes, "
                       "rtri_scenario.md)",
    "materials": "steel wheel and rail, E = 210 GPa, nu = 0.28 (connector defaults)",
    "longitudinal_restraint": "soft spring on the car body, 0.5 Hz, critically damped (vehicle_builder default: "
                              "the roller rig's holding link)",
    "bump_stops": "Manchester lateral bump stops (symbolic user function, vehicle_builder default)",
    "initial_state": "static equilibrium on the rails (place_on_rails), centred, no lateral disturbance",
}


def assumptions_table(assumptions: RtriAssumptions = RTRI,
                      case_assumptions: RtriCaseAssumptions = RTRI_CASE) -> dict:
    """Every input of the case that is not a property of the code, with its value and origin:
    ``{"RtriAssumptions": {name: {"value", "origin"}}, "RtriCaseAssumptions": {...}, "model_choices": {...}}``."""
    table = {"RtriAssumptions": {}, "RtriCaseAssumptions": {}, "model_choices": dict(_OTHER_MODEL_CHOICES)}
    for f in dataclasses.fields(assumptions):
        table["RtriAssumptions"][f.name] = {
            "value": getattr(assumptions, f.name),
            "origin": _RTRI_ORIGINS.get(f.name, "UNCLASSIFIED: see exudyn_wheelrail/scenarios/rtri_assumptions.py")}
    for f in dataclasses.fields(case_assumptions):
        table["RtriCaseAssumptions"][f.name] = {"value": getattr(case_assumptions, f.name),
                                                "origin": _CASE_ORIGINS[f.name]}
    return table



def case_assumptions_table(case: RtriCase) -> dict:
    """:func:`assumptions_table` with what this run overrides marked."""
    a = case.assumptions
    table = assumptions_table(a, case.case_assumptions)
    if (a.newmark_beta, a.newmark_gamma) != (NEWMARK_BETA, NEWMARK_GAMMA):
        raise ValueError("RtriAssumptions: the published Newmark parameters differ from the 'newmark' solver's")
    if case.deviation_amplitude_m is not None and case.delta_m != a.deviation_amplitude_m:
        table["RtriAssumptions"]["deviation_amplitude_m"]["used_in_this_run"] = case.delta_m
        table["RtriAssumptions"]["deviation_amplitude_m"]["origin"] += "; OVERRIDDEN for this run"
    if case.transition_length_m is not None and case.transition_m != a.transition_length_m:
        table["RtriAssumptions"]["transition_length_m"]["used_in_this_run"] = case.transition_m
        table["RtriAssumptions"]["transition_length_m"]["origin"] += "; OVERRIDDEN for this run"
    ca = case.case_assumptions
    if case.contact.creep_law != ca.creep_law:
        table["RtriCaseAssumptions"]["creep_law"]["used_in_this_run"] = case.contact.creep_law
    if case.contact.friction != ca.friction_coefficient:
        table["RtriCaseAssumptions"]["friction_coefficient"]["used_in_this_run"] = case.contact.friction
        table["RtriCaseAssumptions"]["friction_coefficient"]["origin"] += "; OVERRIDDEN for this run"
    if case.car_body != "rigid":
        table["RtriAssumptions"]["vehicle"]["used_in_this_run"] = case.vehicle_name
        table["RtriAssumptions"]["vehicle"]["origin"] += f"; car body {case.car_body}: flexible_vehicle"
    if case.vehicle_overrides:
        table["RtriAssumptions"]["vehicle"]["overrides_in_this_run"] = dict(case.vehicle_overrides)
        table["RtriAssumptions"]["vehicle"]["origin"] += "; values OVERRIDDEN for this run (overrides_in_this_run)"
    return table


# ================================================================================================ the case
_RUN_FIELDS = tuple(f.name for f in dataclasses.fields(RunSettings))
_CONTACT_FIELDS = tuple(f.name for f in dataclasses.fields(ContactSettings))


@dataclass(frozen=True, init=False)
class RtriCase:
    """One RTRI run: the span, the speed, the deviation (``None``: the assumptions' δ and l_t), the vehicle-file
    overrides, and the :class:`~exudyn_wheelrail.simulation.settings.RunSettings` / :class:`~exudyn_wheelrail.
    simulation.settings.ContactSettings` of the run.  Convenient construction: their fields may be given directly
    and override ``run`` / ``contact``::

        RtriCase(span_m=40, speed_km_h=200, solver="rk44", duration_s=1.0, creep_law="fastsim")

    Defaults: the paper's run (Newmark, the published 1 ms for the published 2.5 s) and the case's contact
    assumptions.  ``duration_s="auto"``: ``max(2.5 s, the time for the whole car to pass the span with lead-in and
    run-out)``.  ``wheel_rail="springs"`` replaces each contact by linear springs — a cost baseline for
    benchmarks only: the springs hold the wheels at the nominal rail position, the deviation does not act, and
    nothing is recorded (``record=False``).  ``vehicle_overrides``: numeric values of the vehicle file replaced for
    this run, e.g. ``{"primary.ky_N_per_m": 7.8e6}`` (recorded in the summary's assumptions).  ``car_body``: one of
    :data:`CAR_BODY_MODELS` (the flexible one is ``RtriAssumptions.flexible_vehicle``); ``carbody_points``: the
    measurement points recorded (names of :data:`CARBODY_POINTS`; default ``("rear",)`` for the rigid car body, all
    three for the flexible one)."""

    span_m: float
    speed_km_h: float
    run: RunSettings
    contact: ContactSettings
    deviation_amplitude_m: float | None
    transition_length_m: float | None
    vehicle_overrides: dict | None
    assumptions: RtriAssumptions
    case_assumptions: RtriCaseAssumptions
    car_body: str
    carbody_points: tuple

    def __init__(self, span_m: float = 20.0, speed_km_h: float | None = None, *, run: RunSettings | None = None,
                 contact: ContactSettings | None = None, deviation_amplitude_m: float | None = None,
                 transition_length_m: float | None = None, vehicle_overrides: dict | None = None,
                 assumptions: RtriAssumptions = RTRI, case_assumptions: RtriCaseAssumptions = RTRI_CASE,
                 car_body: str = "rigid", carbody_points: tuple | None = None, **settings):
        unknown = set(settings) - set(_RUN_FIELDS) - set(_CONTACT_FIELDS)
        if unknown:
            raise TypeError(f"RtriCase: unknown argument(s) {', '.join(sorted(unknown))} (fields of RunSettings: "
                            f"{', '.join(_RUN_FIELDS)}; of ContactSettings: {', '.join(_CONTACT_FIELDS)})")
        if run is None:
            run = RunSettings(solver="newmark", dt_s=assumptions.time_step_s,
                              duration_s=assumptions.n_steps_published * assumptions.time_step_s)
        if contact is None:
            contact = ContactSettings(creep_law=case_assumptions.creep_law,
                                      friction=case_assumptions.friction_coefficient,
                                      fastsim_grid=case_assumptions.fastsim_grid)
        run = dataclasses.replace(run, **{k: v for k, v in settings.items() if k in _RUN_FIELDS})
        contact = dataclasses.replace(contact, **{k: v for k, v in settings.items() if k in _CONTACT_FIELDS})
        values = dict(span_m=span_m, speed_km_h=case_assumptions.representative_speed_km_h if speed_km_h is None
                      else speed_km_h, run=run, contact=contact, deviation_amplitude_m=deviation_amplitude_m,
                      transition_length_m=transition_length_m, vehicle_overrides=vehicle_overrides,
                      assumptions=assumptions, case_assumptions=case_assumptions, car_body=car_body,
                      carbody_points=tuple(carbody_points) if carbody_points is not None else
                      (("rear",) if car_body == "rigid" else tuple(CARBODY_POINTS)))
        for k, v in values.items():
            object.__setattr__(self, k, v)
        self._check()

    def _check(self):
        def number(name, value, lo=None, hi=None, lo_open=True):
            value = finite(name, value)
            if lo is not None and (value <= lo if lo_open else value < lo):
                raise ValueError(f"{name} = {value!r}: must be {'>' if lo_open else '>='} {lo}")
            if hi is not None and value > hi:
                raise ValueError(f"{name} = {value!r}: must be <= {hi}")
            return value

        if self.car_body not in CAR_BODY_MODELS:
            raise ValueError(f"car_body = {self.car_body!r}: expected one of {', '.join(CAR_BODY_MODELS)}")
        if "rear" not in self.carbody_points or any(p not in CARBODY_POINTS for p in self.carbody_points):
            raise ValueError(f"carbody_points = {self.carbody_points!r}: expected names of {', '.join(CARBODY_POINTS)}"
                             " including 'rear' (Fig. 5)")
        number("span_m", self.span_m, 0.0, 1000.0)
        number("speed_km_h", self.speed_km_h, 0.0, 600.0)
        if self.deviation_amplitude_m is not None:
            number("deviation_amplitude_m", self.deviation_amplitude_m, lo=0.0, hi=0.1)
        if self.transition_length_m is not None:
            lt = number("transition_length_m", self.transition_length_m, lo=0.0, lo_open=False)
            if not lt < float(self.span_m):
                raise ValueError(f"transition_length_m = {lt} must be shorter than the span ({self.span_m} m)")
        elif not self.assumptions.transition_length_m < float(self.span_m):
            raise ValueError(f"span_m = {self.span_m}: must be longer than the transition length "
                             f"({self.assumptions.transition_length_m} m)")
        if self.contact.wheel_rail == "springs" and self.run.record:
            raise ValueError("wheel_rail='springs' is a cost baseline without the deviation: use record=False")
        if self.vehicle_overrides is not None:
            if not isinstance(self.vehicle_overrides, dict):
                raise ValueError(f"vehicle_overrides = {self.vehicle_overrides!r}: expected a dict "
                                 "{'table.key': value}")
            self.vehicle()                    # unknown keys and invalid values raise VehicleDataError here

    def replace(self, **changes) -> "RtriCase":
        """A copy with fields or run/contact settings changed (the constructor's keywords)."""
        values = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        return RtriCase(**{**values, **changes})

    # -- derived ---------------------------------------------------------------------------------------------------
    @property
    def speed_m_s(self) -> float:
        return float(self.speed_km_h) / 3.6

    @property
    def delta_m(self) -> float:
        return float(self.assumptions.deviation_amplitude_m if self.deviation_amplitude_m is None
                     else self.deviation_amplitude_m)

    @property
    def transition_m(self) -> float:
        return float(self.assumptions.transition_length_m if self.transition_length_m is None
                     else self.transition_length_m)

    def vehicle(self):
        """The run's :class:`~..rolling_stock.vehicle_data.VehicleData`: the assumptions' vehicle with
        ``vehicle_overrides`` applied."""
        return load_vehicle_with_overrides(self.vehicle_name, self.vehicle_overrides)

    @property
    def vehicle_name(self) -> str:
        """The vehicle file of the case's car-body model (:data:`CAR_BODY_MODELS`)."""
        return self.assumptions.vehicle if self.car_body == "rigid" else self.assumptions.flexible_vehicle

    def span_deflection(self):
        """The deviation: the assumptions' shape with this case's δ and l_t; the first transition begins
        ``lead_in_m`` ahead of the leading wheelset (s = 0 at t = 0)."""
        a = dataclasses.replace(self.assumptions, deviation_amplitude_m=self.delta_m,
                                transition_length_m=self.transition_m, span_lengths_m=(float(self.span_m),))
        return a.span_deflection(float(self.span_m))

    def passage_time_s(self) -> float:
        """Time for the whole car (leading to trailing wheelset) to pass the span with the lead-in and the run-out
        [s]."""
        a = self.assumptions
        return (a.lead_in_m + float(self.span_m) + self.transition_m + vehicle_extent_m(self.vehicle())
                + a.run_out_m) / self.speed_m_s

    def run_settings(self) -> RunSettings:
        """The run settings with ``duration_s="auto"`` resolved (:class:`RtriCase`)."""
        if self.run.duration_s != DURATION_AUTO:
            return self.run
        published = self.assumptions.n_steps_published * self.assumptions.time_step_s
        return self.run.with_duration(max(published, self.passage_time_s()))

    def scenario(self) -> dict:
        """The case as a normalised scenario (:mod:`.scenario`): the spec :func:`run_rtri` builds."""
        sd = self.span_deflection()
        spec = {
            "schema_version": 2,
            "scenario": {"name": f"rtri_L{float(self.span_m):g}_V{float(self.speed_km_h):g}",
                         "description": "RTRI rigid-rail validation case (substitute inputs)"},
            "vehicle": {"name": self.vehicle_name, "speed_km_h": float(self.speed_km_h), "start_s_m": 0.0,
                        "overrides": dict(self.vehicle_overrides or {})},
            "track": [{"type": "span_deflection", "span_length_m": sd.span_length_m, "amplitude_m": sd.amplitude_m,
                       "start_m": sd.start_m, "transition_length_m": sd.transition_length_m,
                       "direction": sd.direction}],
            "contact": self.contact.as_dict(),
            "run": self.run_settings().as_dict(),
            "outputs": {"timeseries": list(RTRI_GROUPS), "formats": ["csv"], "plots": False, "criteria": False,
                        "carbody_points": [{"name": p, "x_m": CARBODY_POINTS[p], "y_m": 0.0,
                                            "height_m": self.case_assumptions.floor_height_m}
                                           for p in self.carbody_points]},
        }
        return validate_scenario(spec, source="RTRI case")



def vehicle_extent_m(vehicle) -> float:
    """Distance e from the leading to the trailing wheelset of ``vehicle`` (a :class:`~..rolling_stock.vehicle_data.
    VehicleData`) [m]."""
    x = vehicle.wheelset_x_m()
    return float(max(x) - min(x))
