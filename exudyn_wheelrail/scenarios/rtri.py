r"""The rigid-rail RTRI validation case (Montenegro, Neves, Calçada, Tanabe & Sogabe, Computers & Structures 152
(2015) 200–214, Figs. 5–7) with the project's wheel–rail contact.

**Every result of this module uses substitute inputs** — the test vehicle, its profiles, the deviation amplitude
and transition and the test speeds are not published (``shared/reference/rtri_scenario.md``).  The published values
and the assumptions are :class:`~exudyn_wheelrail.scenarios.rtri_assumptions.RtriAssumptions` plus the few
output-side assumptions of :class:`RtriCaseAssumptions` below; :func:`assumptions_table` lists all of them with
their origin, and every ``summary.json`` carries that table.

What is simulated
-----------------
Manchester benchmark vehicle 1 (``vehicles/manchester_vehicle1.toml``: car body, two bogies, four wheelsets) with
S1002 wheels on UIC60 rails inclined 1:40, gauge and back-to-back from the vehicle file, on a rigid straight track
whose centre line is displaced laterally by one span's deflection (:class:`~..multibody.track.SpanDeflection`:
δ sin(π x/L) with C2 end transitions of length l_t), at the constant running speed V imposed by the model frame
(:mod:`..multibody.vehicle_builder`: the frame translates with V, the wheelsets spin, the car body is held
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

How it runs
-----------
:class:`RtriCase` is a **spec**: :meth:`RtriCase.scenario` writes it as a normalised scenario (vehicle, one span
deflection, contact and run settings, the recorded groups; :mod:`.scenario`), :func:`run_rtri` builds it with
:func:`~.scenario.build_scenario` and runs it through the one solve wrapper (:func:`exudyn_wheelrail.simulation.
runner.run`: watched by the run monitor; the summary's ``status`` is one of :mod:`exudyn_wheelrail.simulation.
status`).  The time series below are the scenario recorder's columns (:mod:`exudyn_wheelrail.simulation.
recorder`) under the case's names (:data:`RTRI_COLUMNS`).

Outputs (one row per time step, the state at ``time_s``)
---------------------------------------------------------
The recorder reads the contact as the run monitor evaluated it at the state's own time (Exudyn's pre-step function
receives the end time of the coming step; the runner passes the state's time — evaluating at the passed time would
shift the rails by V h, up to 69 mm at 250 km/h).  A run of n steps has n + 1 rows.

* ``carbody_lateral_acceleration_rear_m_s2`` — track-frame (y right) acceleration of the car-body point above the
  rear bogie centre at floor level (``floor_height_m`` above the rail top, an assumption), from Exudyn's
  rigid-body output ``OutputVariableType.Acceleration`` at that local position (``GetObjectOutputBody``: the
  node's translational acceleration plus the angular-acceleration and centripetal terms — what a ``SensorBody``
  on that point returns).  Kinematic acceleration, without gravity.  ``carbody_lateral_accelerometer_rear_m_s2``
  is what an accelerometer fixed to the floor reads: the specific force (a − g) in the car body's own y axis,
  which includes g times the car-body roll.
* ``lateral_contact_force_w1_right_N`` — y component (track frame, y to the right) of the total contact force
  (normal + creep, tread + flange region) that the **rail exerts on the right wheel of the leading wheelset**
  (``WheelRailContact.wheel_force_N``).  A flange contact of the right wheel gives a **negative** value (the rail
  pushes the wheel to the left).  The straight track's y axis is used: the deviated rail is turned by at most
  πδ/L = 1.6 mrad, which changes the value by at most 0.0016 |Fx|.  The paper's Fig. 6 most likely shows the
  opposite sign (the force of the wheel on the rail, positive during a flange impact, as Y is usually plotted);
  ``derailment_quotient_w1_right`` uses that sign: Y/Q = −Fy/Q (positive when the right flange presses against
  its rail), NaN when the wheel is lifted (Q = 0).
* ``vertical_contact_force_w1_right_N`` — wheel load Q = −Fz (z down), positive.
* ``flange_contact_w1_right`` — 1 when the wheel's *flange region* (the profile beyond the tread/flange split in
  the throat, :class:`~..profiles.profiles.WheelProfile`) carries a contact (``WheelRailContact.flange_contact``),
  else 0.  A contact high on the flange root can still belong to the tread region (contact angles up to ~0.55
  rad); ``contact_angle_w1_right_rad`` shows it (the angle of the most loaded region).
* extras: the track deviation under the leading wheelset and the wheelset's lateral displacement relative to its
  rails (the contact search's pose), ``Y_w<j>_<side>_N`` / ``Q_w<j>_<side>_N`` of every wheel (j = 1 leading … 4),
  the flange flags of both leading wheels, the car body's lateral displacement above the rear bogie.

Default speeds (justification of ``RtriAssumptions.speeds_km_h`` = 100, 150, 200, 250 km/h)
-------------------------------------------------------------------------------------------
The plant runs up to 250 km/h (published); the deviation, a half sine of length L, excites the vehicle at about
f = V/(2L): 0.69–1.74 Hz on the 20 m span and 0.35–0.87 Hz on the 40 m span for 100–250 km/h, which brackets
the car body's lateral, yaw and roll-sway frequencies on the secondary suspension (≈ 0.5–1.5 Hz for the
Manchester coach), so the set spans the resonant range Fig. 7 is about; 100 km/h is the lowest speed for which
the whole car passes the 20 m span within the paper's 2500 steps.  The representative speed for Figs. 5/6 and the
20 m vs 40 m check is 250 km/h (:class:`RtriCaseAssumptions`), the plant's maximum, chosen before any run.

Peaks
-----
``summary["peaks"]`` covers the whole run (not evaluated for a ``diverged`` run), ``summary["peaks_passage"]``
the response to the deviation (until the
whole car has left the span and run the run-out), ``summary["after_passage"]`` what is left afterwards (a lateral
oscillation that does not decay is self-excited and is flagged in the notes).  Besides the raw peak of the lateral
force, the peak of its 10 ms moving average (:data:`AVERAGE_WINDOW_S`) is given: the raw force carries spikes of
the wheelset's almost undamped ~200 Hz vertical bounce on the Hertz spring (see below), whose heights are not
converged in dt; the averaged peak is (``tests/test_rtri.py``).

What the model gives with the stated assumptions (Newmark, 1 ms, FASTSIM 24 x 8)
--------------------------------------------------------------------------------
Passage peaks, ``python -m exudyn_wheelrail rtri-sweep --spans 20 40 --out DIR`` (duration "auto"):

=====  =======  ==============  ================  =================  =======================
span   V km/h   max |a| m/s²    max |Y| kN (raw)  max |Y| kN (10ms)  flange region w1 right
=====  =======  ==============  ================  =================  =======================
20 m   100      0.33            6.5               3.3                no
20 m   150      0.64            5.6               3.5                no
20 m   200      0.80            22.4              11.8               no (flange root, 0.34 rad)
20 m   250      1.27            32.8              22.5               no (flange root, 0.56 rad)
40 m   100      0.21            6.9               3.3                no
40 m   150      0.35            5.2               3.4                no
40 m   200      0.53            6.1               3.6                no
40 m   250      0.76            6.8               3.4                no
=====  =======  ==============  ================  =================  =======================

* Reproduced: a much larger lateral force at 20 m than at 40 m (250 km/h: 4.8x raw, 6.6x averaged; 200 km/h
  3.7x / 3.3x), no flange contact at 40 m, a larger car-body acceleration at 20 m at every speed.
* **Not reproduced with the stated δ = 10 mm: the flange impact at 20 m.**  At 250 km/h the leading wheelset
  reaches 5.89 mm relative to the track (the exact-theory creep table; the table above is FASTSIM's); the contact
  of S1002 on UIC60 1:40 jumps to the flange flank at 6.25 mm, so it stays on the flange root (tread region).  The
  flange impact appears from δ = 12 mm (l_t ≤ 3 m) and is asserted at δ = 14 mm; the measured sensitivity is in
  :mod:`.rtri_assumptions`.
* At 250 km/h this vehicle model hunts after the passage (±6 mm limit cycle, flange-root contacts), at 200 km/h
  and below a ±1–2 mm limit cycle remains: 250 km/h is above the model's critical speed; the passage peaks above
  are before the hunting has built up, the whole-run peaks at 250 km/h include it.
* The wheel load Q of the leading right wheel swings between 0 and ~300 kN (static 54.5 kN) whenever the contact
  jumps: the single-point tread region changes its normal force by up to ~30 kN at a jump (S1002/UIC60 near the
  centred position and near the throat; the warm-started kernel also follows a stale branch, hysteresis), which
  excites the ~200 Hz wheelset bounce; the only vertical damping in that mode is the primary damper (0.2 % of
  critical) — neither contact damping nor a compliant rail/roller is modelled.
"""
from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..simulation import status as S
from ..simulation.settings import DURATION_AUTO, NEWMARK_BETA, NEWMARK_GAMMA, ContactSettings, RunSettings
from .rtri_assumptions import RTRI, RtriAssumptions
from .scenario import (
    DEFAULT_FLOOR_HEIGHT_M,
    build_scenario,
    peaks,
    run_model,
    validate_scenario,
    write_csv,
    write_json,
)

__all__ = [
    "RtriCaseAssumptions",
    "RTRI_CASE",
    "RtriCase",
    "RtriResult",
    "RTRI_COLUMNS",
    "TIMESERIES_REQUIRED",
    "assumptions_table",
    "run_rtri",
    "write_rtri_outputs",
    "run_sweep",
    "plot_fig5",
    "plot_fig6",
    "plot_fig7",
]

#: moving-average window of the smoothed lateral-force peak: two periods of the wheelset's ~200 Hz vertical bounce
#: on the Hertz spring (removes the bounce spikes, keeps the ~4 Hz lateral motion and the ~15 ms flange events)
AVERAGE_WINDOW_S = 0.010
#: the case's time-series columns and the scenario recorder's column each one is (:mod:`~exudyn_wheelrail.
#: simulation.recorder`); then ``Y_w<j>_<side>_N``, ``Q_w<j>_<side>_N`` of every wheel (:func:`rtri_columns`)
RTRI_COLUMNS = {
    "time_s": "time_s",
    "carbody_lateral_acceleration_rear_m_s2": "carbody_lateral_acceleration_rear_m_s2",
    "lateral_contact_force_w1_right_N": "Y_w1_right_N",
    "vertical_contact_force_w1_right_N": "Q_w1_right_N",
    "flange_contact_w1_right": "flange_w1_right",
    "track_deviation_w1_m": "track_lateral_w1_m",
    "wheelset1_lateral_rel_track_m": "y_rel_w1_m",
    "derailment_quotient_w1_right": "YQ_w1_right",
    "contact_angle_w1_right_rad": "contact_angle_w1_right_rad",
    "flange_contact_w1_left": "flange_w1_left",
    "carbody_lateral_accelerometer_rear_m_s2": "carbody_lateral_accelerometer_rear_m_s2",
    "carbody_lateral_displacement_rear_m": "carbody_lateral_displacement_rear_m",
}
#: the contract columns of ``timeseries.csv`` (further columns follow them)
TIMESERIES_REQUIRED = tuple(RTRI_COLUMNS)[:5]
#: the scenario groups the case records
RTRI_GROUPS = ("Y", "Q", "YQ", "flange", "contact_angle", "wheelset_lateral", "track", "carbody")


def rtri_columns(n_wheelsets: int) -> dict:
    """:data:`RTRI_COLUMNS` followed by every wheel's ``Y`` and ``Q`` (wheelset by wheelset, right then left)."""
    cols = dict(RTRI_COLUMNS)
    for j in range(1, n_wheelsets + 1):
        for side in ("right", "left"):
            cols[f"Y_w{j}_{side}_N"] = f"Y_w{j}_{side}_N"
            cols[f"Q_w{j}_{side}_N"] = f"Q_w{j}_{side}_N"
    return cols


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
    this run, e.g. ``{"primary.ky_N_per_m": 7.8e6}`` (recorded in the summary's assumptions)."""

    span_m: float
    speed_km_h: float
    run: RunSettings
    contact: ContactSettings
    deviation_amplitude_m: float | None
    transition_length_m: float | None
    vehicle_overrides: dict | None
    assumptions: RtriAssumptions
    case_assumptions: RtriCaseAssumptions

    def __init__(self, span_m: float = 20.0, speed_km_h: float | None = None, *, run: RunSettings | None = None,
                 contact: ContactSettings | None = None, deviation_amplitude_m: float | None = None,
                 transition_length_m: float | None = None, vehicle_overrides: dict | None = None,
                 assumptions: RtriAssumptions = RTRI, case_assumptions: RtriCaseAssumptions = RTRI_CASE,
                 **settings):
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
                      assumptions=assumptions, case_assumptions=case_assumptions)
        for k, v in values.items():
            object.__setattr__(self, k, v)
        self._check()

    def _check(self):
        from ..validation import finite

        def number(name, value, lo=None, hi=None, lo_open=True):
            value = finite(name, value)
            if lo is not None and (value <= lo if lo_open else value < lo):
                raise ValueError(f"{name} = {value!r}: must be {'>' if lo_open else '>='} {lo}")
            if hi is not None and value > hi:
                raise ValueError(f"{name} = {value!r}: must be <= {hi}")
            return value

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
        """The run's :class:`~..multibody.vehicle_data.VehicleData`: the assumptions' vehicle with
        ``vehicle_overrides`` applied."""
        from ..multibody.vehicle_data import load_vehicle_with_overrides
        return load_vehicle_with_overrides(self.assumptions.vehicle, self.vehicle_overrides)

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
        return (a.lead_in_m + float(self.span_m) + self.transition_m + _vehicle_extent_m(self.vehicle())
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
            "vehicle": {"name": self.assumptions.vehicle, "speed_km_h": float(self.speed_km_h), "start_s_m": 0.0,
                        "overrides": dict(self.vehicle_overrides or {})},
            "track": [{"type": "span_deflection", "span_length_m": sd.span_length_m, "amplitude_m": sd.amplitude_m,
                       "start_m": sd.start_m, "transition_length_m": sd.transition_length_m,
                       "direction": sd.direction}],
            "contact": self.contact.as_dict(),
            "run": self.run_settings().as_dict(),
            "outputs": {"timeseries": list(RTRI_GROUPS), "formats": ["csv"], "plots": False, "criteria": False,
                        "carbody_points": [{"name": "rear", "x_m": "rear_bogie", "y_m": 0.0,
                                            "height_m": self.case_assumptions.floor_height_m}]},
        }
        return validate_scenario(spec, source="RTRI case")


def _vehicle_extent_m(vehicle) -> float:
    x = vehicle.wheelset_x_m()
    return float(max(x) - min(x))


def _coverage(case: RtriCase, vehicle, run: RunSettings) -> tuple[dict, list[str]]:
    """What the run covers (track distances of the leading wheelset, times) and notes."""
    a = case.assumptions
    V = case.speed_m_s
    L, lt = float(case.span_m), case.transition_m
    e = _vehicle_extent_m(vehicle)
    x = vehicle.wheelset_x_m()
    x_rear_bogie_lead = sorted(x)[1]          # the rear bogie's leading wheelset
    sd = case.span_deflection()
    s_enter = sd.start_m - 0.5 * lt           # deviation begins
    s_leave = sd.end_m + 0.5 * lt             # deviation ends
    d_rear = max(x) - x_rear_bogie_lead
    t_end = run.end_time_s
    cov = {
        "vehicle_extent_m": e,
        "deviation_begins_at_track_distance_m": s_enter,
        "deviation_ends_at_track_distance_m": s_leave,
        "t_leading_wheelset_enters_span_s": s_enter / V,
        "t_leading_wheelset_leaves_span_s": s_leave / V,
        "t_rear_bogie_enters_span_s": (s_enter + d_rear) / V,
        "t_whole_car_left_span_s": (s_leave + e) / V,
        "t_needed_with_run_out_s": (a.lead_in_m + L + lt + e + a.run_out_m) / V,
        "t_end_s": t_end,
    }
    cov["steps_needed"] = int(math.ceil(cov["t_needed_with_run_out_s"] / run.dt_s - 1e-9))
    cov["leading_wheelset_crosses_span"] = t_end >= cov["t_leading_wheelset_leaves_span_s"]
    cov["whole_car_passes_span"] = t_end >= cov["t_whole_car_left_span_s"]
    notes = []
    if not cov["leading_wheelset_crosses_span"]:
        notes.append(f"the run ends at {t_end:.3f} s, before the leading wheelset has left the span "
                     f"({cov['t_leading_wheelset_leaves_span_s']:.3f} s); peak values may be missed")
    elif not cov["whole_car_passes_span"]:
        notes.append(f"the run ends at {t_end:.3f} s: the leading wheelset crosses the whole span (leaves at "
                     f"{cov['t_leading_wheelset_leaves_span_s']:.3f} s) but the trailing wheelset leaves it only at "
                     f"{cov['t_whole_car_left_span_s']:.3f} s ({cov['steps_needed']} steps needed with the run-out); "
                     "the rear-bogie car-body acceleration may not have peaked")
    elif t_end < cov["t_needed_with_run_out_s"]:
        notes.append(f"the whole car has left the span at {cov['t_whole_car_left_span_s']:.3f} s; the run-out of "
                     f"{a.run_out_m} m would need {cov['steps_needed']} steps")
    if case.speed_km_h > a.plant_max_speed_km_h:
        notes.append(f"speed {case.speed_km_h} km/h exceeds the plant's limit {a.plant_max_speed_km_h} km/h")
    return cov, notes


# ================================================================================================ running
@dataclass
class RtriResult:
    """Time series (column name -> array; empty without recording), the summary dict, the case and the run's
    outcome (:class:`~exudyn_wheelrail.simulation.runner.RunOutcome`)."""

    timeseries: dict
    summary: dict
    case: RtriCase = None
    outcome: object = None


def _case_peaks(ts: dict, dt: float, t_max: float | None = None) -> dict:
    """The case's peak values of the recorded rows with ``time_s <= t_max`` (all rows for ``None``): the per-column
    peaks of :func:`~.scenario.peaks` under the case's names, the flange-contact durations and the 10 ms
    moving-average peak of the lateral force."""
    if t_max is not None:
        keep = ts["time_s"] <= t_max + 1e-9
        ts = {k: v[keep] for k, v in ts.items()}
    t = ts["time_s"]
    if len(t) == 0:
        return {}
    p = peaks(ts)
    Y = p["lateral_contact_force_w1_right_N"]
    acc = p["carbody_lateral_acceleration_rear_m_s2"]
    Q = p["vertical_contact_force_w1_right_N"]
    fl = ts["flange_contact_w1_right"] > 0.5
    out = {
        "max_abs_lateral_contact_force_w1_right_N": Y["max_abs"],
        "lateral_contact_force_w1_right_at_peak_N": Y["value_at_max_abs"],
        "time_of_max_abs_lateral_force_s": Y["time_of_max_abs_s"],
        "max_abs_carbody_lateral_acceleration_rear_m_s2": acc["max_abs"],
        "time_of_max_carbody_acceleration_s": acc["time_of_max_abs_s"],
        "max_abs_carbody_lateral_accelerometer_rear_m_s2": p["carbody_lateral_accelerometer_rear_m_s2"]["max_abs"],
        "flange_contact_w1_right": bool(fl.any()),
        "flange_contact_w1_right_duration_s": float(fl.sum() * dt),
        "flange_contact_w1_right_first_time_s": float(t[fl][0]) if fl.any() else None,
        "flange_contact_w1_left": bool((ts["flange_contact_w1_left"] > 0.5).any()),
        "max_derailment_quotient_w1_right": p["derailment_quotient_w1_right"]["max"],
        "min_wheel_load_w1_right_N": Q["min"],
        "max_wheel_load_w1_right_N": Q["max"],
        "wheel_lift_w1_right_duration_s": float((ts["vertical_contact_force_w1_right_N"] <= 0.0).sum() * dt),
        "max_abs_wheelset1_lateral_rel_track_m": p["wheelset1_lateral_rel_track_m"]["max_abs"],
        "max_contact_angle_w1_right_rad": p["contact_angle_w1_right_rad"]["max"],
    }
    n = max(1, int(round(AVERAGE_WINDOW_S / dt)))
    y_raw = ts["lateral_contact_force_w1_right_N"]
    if len(y_raw) >= n:
        y_avg = np.convolve(y_raw, np.ones(n) / n, mode="valid")
        i = int(np.nanargmax(np.abs(y_avg)))
        out["max_abs_lateral_contact_force_w1_right_10ms_avg_N"] = float(abs(y_avg[i]))
        out["time_of_max_abs_lateral_force_10ms_avg_s"] = float(0.5 * (t[i] + t[i + n - 1]))
    out["max_abs_Y_any_wheel_N"] = max(v["max_abs"] for k, v in p.items() if k.startswith("Y_w"))
    out["min_Q_any_wheel_N"] = min(v["min"] for k, v in p.items() if k.startswith("Q_w"))
    return out


def _after_passage(ts: dict, t_passage_end: float) -> dict:
    """Motion left after the passage (the whole car off the span plus the run-out): a lateral oscillation of the
    leading wheelset that does not decay there is self-excited (hunting), not the response to the deviation."""
    t = ts["time_s"]
    keep = t > t_passage_end + 1e-9
    if not keep.any():
        return {"recorded": False}
    return {"recorded": True, "from_s": float(t_passage_end), "to_s": float(t[keep][-1]),
            "max_abs_wheelset1_lateral_rel_track_m":
                float(np.nanmax(np.abs(ts["wheelset1_lateral_rel_track_m"][keep]))),
            "max_abs_carbody_lateral_acceleration_rear_m_s2":
                float(np.nanmax(np.abs(ts["carbody_lateral_acceleration_rear_m_s2"][keep]))),
            "max_abs_lateral_contact_force_w1_right_N":
                float(np.nanmax(np.abs(ts["lateral_contact_force_w1_right_N"][keep]))),
            "min_wheel_load_w1_right_N": float(np.nanmin(ts["vertical_contact_force_w1_right_N"][keep]))}


def run_rtri(case: RtriCase, progress=None, view=None) -> RtriResult:
    """Build the case's spec (:meth:`RtriCase.scenario`, :func:`~.scenario.build_scenario`), warm up, run it
    through the one solve wrapper (timed: ``mbs.SolveDynamic`` only) and collect the outputs.  ``summary["status"]``
    is one of :data:`~exudyn_wheelrail.simulation.status.STATUSES` (``status_detail``: time, wheelset, side, the
    monitor's detail, a hint); the time series keep the rows up to the last valid state.  ``progress``: a callable
    for one line before the run (e.g. ``print``).  ``view``: an object with ``attach(model)`` (called with the built
    :class:`~.scenario.ScenarioModel` before the solve) and ``close()`` (after it), e.g.
    :class:`~exudyn_wheelrail.interactive.view3d.RtriView` (Exudyn's renderer)."""
    vehicle = case.vehicle()
    if vehicle.layout != "car" or vehicle.car_body is None:
        raise ValueError(f"vehicle {case.assumptions.vehicle!r}: the RTRI case needs a car (layout 'car')")
    h = build_scenario(case.scenario())
    run = h.run
    if progress:
        progress(f"RTRI: span {case.span_m:g} m, {case.speed_km_h:g} km/h, {run.solver}, dt {run.dt_s:g} s, "
                 f"{run.duration_s:g} s ({run.steps} steps), {case.contact.wheel_rail}"
                 + (f", creep law {case.contact.creep_law}" if h.contact else ""))
    outcome = run_model(h, progress=False, view=view)
    status = outcome.status
    rec = h.recorder.table() if h.recorder is not None else {}
    ts = {name: rec[col] for name, col in rtri_columns(len(h.model.wheelsets)).items()} if rec else {}
    cov, notes = _coverage(case, vehicle, run)
    evaluate = bool(ts) and len(ts["time_s"]) > 0 and status.kind != S.DIVERGED
    after = _after_passage(ts, cov["t_needed_with_run_out_s"]) if evaluate else {}
    passage = _case_peaks(ts, run.dt_s, cov["t_needed_with_run_out_s"]) if evaluate else {}
    if after.get("recorded") and passage and (after["max_abs_wheelset1_lateral_rel_track_m"] >
                                              0.5 * passage["max_abs_wheelset1_lateral_rel_track_m"]):
        notes.append(f"after the passage (t > {after['from_s']:.3f} s) the leading wheelset still oscillates laterally "
                     f"by up to {after['max_abs_wheelset1_lateral_rel_track_m'] * 1e3:.2f} mm (passage peak "
                     f"{passage['max_abs_wheelset1_lateral_rel_track_m'] * 1e3:.2f} mm): a self-excited oscillation "
                     "(hunting / limit cycle), not the response to the deviation; whole-run peaks include it")
    if case.contact.wheel_rail == "springs":
        notes.append("wheel_rail = springs: cost baseline only (the deviation does not act on linear springs)")
    notes += outcome.warnings
    if status.kind != S.OK:
        notes.append(f"the run ended {status.kind} (status_detail): the time series hold the rows up to the last "
                     "valid state"
                     + ("; peaks not evaluated" if status.kind == S.DIVERGED else ""))
    table = _case_assumptions_table(case)
    solve_seconds = outcome.solve_seconds
    sim_time = outcome.t_end_s
    summary = {
        "case": "RTRI rigid-rail validation case (Montenegro et al., Comput. Struct. 152 (2015) 200-214), "
                "SUBSTITUTE INPUTS: see 'assumptions'",
        "status": status.kind,
        "status_detail": status.as_dict(),
        "events": [{"kind": e.kind, "time_s": e.time_s, "wheelset": e.wheelset, "side": e.side, "detail": e.detail}
                   for e in outcome.events[:200]],
        "n_events": len(outcome.events),
        "solve_seconds": solve_seconds,
        "steps": run.steps,
        "dt_s": run.dt_s,
        "duration_s": run.end_time_s,
        "simulated_time_s": sim_time,
        "real_time_factor": sim_time / solve_seconds if solve_seconds > 0 else None,
        "rows_recorded": int(len(ts.get("time_s", []))),
        "rows_dropped_after_divergence": outcome.rows_dropped,
        "rejected_steps": outcome.rejected_steps,
        "contact_omega_rad_s": outcome.contact_omega_rad_s,
        "speed_km_h": float(case.speed_km_h),
        "speed_m_s": case.speed_m_s,
        "span_m": float(case.span_m),
        "deviation_amplitude_m": case.delta_m,
        "transition_length_m": case.transition_m,
        "deviation_start_m": case.span_deflection().start_m,
        "run_settings": run.as_dict(),
        "contact_settings": case.contact.as_dict(),
        "solver": {"name": run.solver, "exudyn": run.describe_solver()},
        "wheel_rail": case.contact.wheel_rail,
        "creep_law": case.contact.creep_law if case.contact.wheel_rail == "contact" else None,
        "geometry": h.contact.geometry_statistics() if h.contact is not None else None,
        "skipped": h.contact.skipped() if h.contact is not None else None,
        "fastsim_grid": list(case.contact.fastsim_grid),
        "contact_calls": int(h.contact.n_calls) if h.contact is not None else 0,
        "vehicle": vehicle.name,
        "wheel_rail_pair": repr(h.pair),
        "coverage": cov,
        "notes": notes,
        "peak_windows": {"peaks": "the whole run",
                         "peaks_passage": "t <= coverage.t_needed_with_run_out_s (the whole car has left the span "
                                          "and run the run-out): the response to the deviation",
                         "after_passage": "t > coverage.t_needed_with_run_out_s (what is left: a self-excited "
                                          "oscillation if it does not decay)"},
        "peaks": _case_peaks(ts, run.dt_s) if evaluate else {},
        "peaks_passage": passage,
        "after_passage": after,
        "sign_conventions": {
            "lateral_contact_force_w1_right_N": "force of the rail ON the wheel, track y (+ = towards the right); "
                                                "a right-flange contact is negative. The paper's Fig. 6 likely "
                                                "plots the opposite sign (force on the rail)",
            "derailment_quotient_w1_right": "-Fy/Q: positive when the right flange presses on its rail",
            "carbody_lateral_acceleration_rear_m_s2": "track-frame y acceleration (no gravity) of the car-body "
                                                      "point above the rear bogie centre at floor level "
                                                      "(Exudyn rigid-body Acceleration output at that point)",
            "flange_contact_w1_right": "the wheel's flange region (beyond the throat split) carries a contact",
        },
        "assumptions": table,
    }
    return RtriResult(timeseries=ts, summary=summary, case=case, outcome=outcome)


def _case_assumptions_table(case: RtriCase) -> dict:
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
    if case.vehicle_overrides:
        table["RtriAssumptions"]["vehicle"]["overrides_in_this_run"] = dict(case.vehicle_overrides)
        table["RtriAssumptions"]["vehicle"]["origin"] += "; values OVERRIDDEN for this run (overrides_in_this_run)"
    return table


# ================================================================================================ outputs
def write_rtri_outputs(result: RtriResult, out_dir, plots: bool = True) -> dict:
    """Write ``timeseries.csv``, ``summary.json`` and (``plots``) the Fig. 5/6 PNGs into ``out_dir``; returns the
    paths."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"timeseries": out / "timeseries.csv", "summary": out / "summary.json"}
    write_csv(paths["timeseries"], result.timeseries)
    write_json(paths["summary"], result.summary)
    if plots and result.timeseries and len(result.timeseries["time_s"]) > 1:
        paths["fig5"] = out / "fig5_carbody_acceleration.png"
        paths["fig6"] = out / "fig6_lateral_force.png"
        plot_fig5(result, paths["fig5"])
        plot_fig6(result, paths["fig6"])
    return paths


def _title(summary: dict) -> str:
    return (f"RTRI case, span {summary['span_m']:g} m, {summary['speed_km_h']:g} km/h, δ = "
            f"{summary['deviation_amplitude_m'] * 1e3:g} mm, l_t = {summary['transition_length_m']:g} m, "
            f"{summary['solver']['name']}, dt {summary['dt_s'] * 1e3:g} ms\n"
            "SUBSTITUTE inputs (Manchester vehicle 1, S1002/UIC60 1:40; assumed δ, l_t) — see summary.json")


def _finish(plt, fig, ax, path):
    """Common finish of the Fig. 5/6 plots: small title, grid, legend, saved and closed."""
    ax.title.set_fontsize(8)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _spans(ax, summary):
    c = summary["coverage"]
    ax.axvspan(c["t_leading_wheelset_enters_span_s"], c["t_leading_wheelset_leaves_span_s"], color="C1", alpha=0.12,
               label="leading wheelset on the deviation")
    t_rear_leave = c["t_rear_bogie_enters_span_s"] + (c["t_leading_wheelset_leaves_span_s"] -
                                                      c["t_leading_wheelset_enters_span_s"])
    ax.axvspan(c["t_rear_bogie_enters_span_s"], t_rear_leave, color="C2", alpha=0.10,
               label="rear bogie's leading wheelset on the deviation")


def _passage(ax, summary, t_peak_s, y_plotted, text):
    """The end of the passage window (the window of ``peaks_passage``: what ``rtri`` prints and the validation
    report tabulates) and the passage peak, circled on the plotted curve (``y_plotted`` in the plot's unit)."""
    c = summary["coverage"]
    t_end = c["t_needed_with_run_out_s"]
    if t_end <= c["t_end_s"]:
        ax.axvline(t_end, color="0.3", ls=":", lw=1.0, label=f"end of the passage window ({t_end:.3f} s)")
    ax.plot([t_peak_s], [y_plotted], "o", mfc="none", mec="k", ms=8, gid="passage_peak",
            label=f"passage peak {text} at {t_peak_s:.3f} s")


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_fig5(result: RtriResult, path):
    """Car-body lateral acceleration above the rear bogie vs time (cf. paper Fig. 5)."""
    plt = _pyplot()
    ts, s = result.timeseries, result.summary
    fig, ax = plt.subplots(figsize=(9, 4.5))
    _spans(ax, s)
    ax.plot(ts["time_s"], ts["carbody_lateral_acceleration_rear_m_s2"], "C0-", lw=1.0,
            label="car body above the rear bogie, floor level (track frame)")
    ax.plot(ts["time_s"], ts["carbody_lateral_accelerometer_rear_m_s2"], "C3-", lw=0.6, alpha=0.6,
            label="same point, body-fixed accelerometer (incl. g·roll)")
    p = s.get("peaks_passage") or {}
    if "time_of_max_carbody_acceleration_s" in p:
        t_pk = p["time_of_max_carbody_acceleration_s"]
        i = int(np.argmin(np.abs(ts["time_s"] - t_pk)))
        _passage(ax, s, t_pk, ts["carbody_lateral_acceleration_rear_m_s2"][i],
                 f"|a| = {p['max_abs_carbody_lateral_acceleration_rear_m_s2']:.3f} m/s²")
    ax.set(xlabel="time [s]", ylabel="car-body lateral acceleration [m/s²]", title=_title(s))
    _finish(plt, fig, ax, path)


def plot_fig6(result: RtriResult, path):
    """Lateral contact force on the right wheel of the leading wheelset vs time (cf. paper Fig. 6)."""
    plt = _pyplot()
    ts, s = result.timeseries, result.summary
    fig, ax = plt.subplots(figsize=(9, 4.5))
    _spans(ax, s)
    t = ts["time_s"]
    ax.plot(t, ts["lateral_contact_force_w1_right_N"] * 1e-3, "C0-", lw=0.8,
            label="rail on wheel, track y (+ right): right-flange contact is negative")
    n = max(1, int(round(AVERAGE_WINDOW_S / s["dt_s"])))
    if len(t) >= n:
        avg = np.convolve(ts["lateral_contact_force_w1_right_N"], np.ones(n) / n, mode="valid")
        ax.plot(t[n - 1:] - 0.5 * (n - 1) * s["dt_s"], avg * 1e-3, "k-", lw=1.2,
                label=f"{AVERAGE_WINDOW_S * 1e3:g} ms moving average")
    fl = ts["flange_contact_w1_right"] > 0.5
    if fl.any():
        ax.plot(t[fl], ts["lateral_contact_force_w1_right_N"][fl] * 1e-3, "r.", ms=3,
                label="flange region in contact")
    p = s.get("peaks_passage") or {}
    if "time_of_max_abs_lateral_force_10ms_avg_s" in p:
        t_pk = p["time_of_max_abs_lateral_force_10ms_avg_s"]
        k = int(np.argmin(np.abs(t[n - 1:] - 0.5 * (n - 1) * s["dt_s"] - t_pk)))
        _passage(ax, s, t_pk, avg[k] * 1e-3, f"|Y| ({AVERAGE_WINDOW_S * 1e3:g} ms average) = "
                 f"{p['max_abs_lateral_contact_force_w1_right_10ms_avg_N'] * 1e-3:.2f} kN")
    ax.set(xlabel="time [s]", ylabel="Y, wheelset 1 (leading), right wheel [kN]", title=_title(s))
    _finish(plt, fig, ax, path)


# ================================================================================================== sweep
SWEEP_COLUMNS = ("span_m", "speed_km_h", "status", "steps", "solve_seconds", "real_time_factor",
                 "max_abs_carbody_lateral_acceleration_rear_m_s2", "max_abs_lateral_contact_force_w1_right_N",
                 "max_abs_lateral_contact_force_w1_right_10ms_avg_N", "flange_contact_w1_right",
                 "flange_contact_w1_right_duration_s", "max_derailment_quotient_w1_right",
                 "min_wheel_load_w1_right_N", "max_abs_wheelset1_lateral_rel_track_m", "whole_car_passes_span",
                 "after_passage_max_abs_wheelset1_lateral_rel_track_m",
                 "run_max_abs_carbody_lateral_acceleration_rear_m_s2")
_SWEEP_PEAKS = SWEEP_COLUMNS[6:14]     # from peaks_passage


def _sweep_task(case: RtriCase, case_dir):
    try:
        r = run_rtri(case)
        if case_dir is not None:
            write_rtri_outputs(r, case_dir)
        return r.summary
    except Exception as exc:   # one failing case must not stop the sweep
        return {"status": f"error: {type(exc).__name__}: {exc}".splitlines()[0], "span_m": float(case.span_m),
                "speed_km_h": float(case.speed_km_h), "steps": None, "peaks": {}, "coverage": {}}


def run_sweep(spans_m, speeds_km_h, out_dir, *, workers: int | None = None, run: RunSettings | None = None,
              contact: ContactSettings | None = None, deviation_amplitude_m: float | None = None,
              transition_length_m: float | None = None, write_cases: bool = True, progress=print) -> list[dict]:
    """All (span, speed) cases in parallel processes; writes ``sweep.csv``, ``sweep.json``,
    ``fig7_max_carbody_acceleration.png`` (and each case's outputs under ``cases/`` if ``write_cases``).  ``run``:
    default the case's run with ``duration_s="auto"`` (each case covers its whole passage); ``contact``: the case's
    default."""
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from multiprocessing import get_context
    spans_m = [float(s) for s in spans_m]
    speeds_km_h = [float(v) for v in speeds_km_h]
    if not spans_m or not speeds_km_h:
        raise ValueError("the sweep needs at least one span and one speed")
    if run is None:
        run = dataclasses.replace(RtriCase().run, duration_s=DURATION_AUTO)
    cases = [RtriCase(span_m=L, speed_km_h=V, run=run, contact=contact,
                      deviation_amplitude_m=deviation_amplitude_m, transition_length_m=transition_length_m)
             for L in spans_m for V in speeds_km_h]        # validates every case before starting
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    workers = max(1, min(int(workers or os.cpu_count() or 1), len(cases)))
    summaries = []
    with ProcessPoolExecutor(max_workers=workers, mp_context=get_context("spawn")) as pool:
        futures = {pool.submit(_sweep_task, c, (out / "cases" / f"L{c.span_m:g}_V{c.speed_km_h:g}")
                               if write_cases else None): c for c in cases}
        for f in as_completed(futures):
            s = f.result()
            summaries.append(s)
            if progress:
                p = s.get("peaks_passage", {})
                progress(f"  span {s['span_m']:g} m, {s['speed_km_h']:g} km/h: {s['status']}; max |a_cb| "
                         f"{p.get('max_abs_carbody_lateral_acceleration_rear_m_s2', float('nan')):.3f} m/s², max |Y| "
                         f"{p.get('max_abs_lateral_contact_force_w1_right_N', float('nan')) / 1e3:.1f} kN, flange "
                         f"{p.get('flange_contact_w1_right')}")
    summaries.sort(key=lambda s: (s["span_m"], s["speed_km_h"]))
    rows = []
    for s in summaries:
        p, c = s.get("peaks_passage", {}), s.get("coverage", {})
        row = {k: s.get(k) for k in ("span_m", "speed_km_h", "status", "steps", "solve_seconds", "real_time_factor")}
        for k in _SWEEP_PEAKS:
            row[k] = p.get(k)
        row["whole_car_passes_span"] = c.get("whole_car_passes_span")
        row["after_passage_max_abs_wheelset1_lateral_rel_track_m"] = s.get("after_passage", {}).get(
            "max_abs_wheelset1_lateral_rel_track_m")
        row["run_max_abs_carbody_lateral_acceleration_rear_m_s2"] = s.get("peaks", {}).get(
            "max_abs_carbody_lateral_acceleration_rear_m_s2")
        rows.append(row)
    import csv
    with open(out / "sweep.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(SWEEP_COLUMNS))
        w.writeheader()
        w.writerows(rows)
    meta = {"assumptions": assumptions_table(), "run_settings": run.as_dict(),
            "contact_settings": (contact or RtriCase().contact).as_dict(), "rows": rows}
    write_json(out / "sweep.json", meta)
    plot_fig7(rows, out / "fig7_max_carbody_acceleration.png")
    return summaries


def plot_fig7(rows, path):
    """Maximum car-body lateral acceleration vs speed, one line per span (cf. paper Fig. 7)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    flange_labelled = False
    for i, L in enumerate(sorted({r["span_m"] for r in rows})):
        sel = sorted((r for r in rows if r["span_m"] == L and r["status"] == "ok"), key=lambda r: r["speed_km_h"])
        if not sel:
            continue
        v = [r["speed_km_h"] for r in sel]
        a = [r["max_abs_carbody_lateral_acceleration_rear_m_s2"] for r in sel]
        ax.plot(v, a, "o-", color=f"C{i}", label=f"L = {L:g} m")
        fl = [r for r in sel if r["flange_contact_w1_right"]]
        if fl:
            ax.plot([r["speed_km_h"] for r in fl], [r["max_abs_carbody_lateral_acceleration_rear_m_s2"] for r in fl],
                    "s", mfc="none", mec="r", ms=10,
                    label=None if flange_labelled else "flange contact (wheelset 1, right wheel)")
            flange_labelled = True
    ax.set(xlabel="speed [km/h]", ylabel="passage peak |a|, car body, rear [m/s²]",
           title="RTRI case — SUBSTITUTE inputs (Manchester vehicle 1, assumed δ, l_t)")
    ax.title.set_fontsize(9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
