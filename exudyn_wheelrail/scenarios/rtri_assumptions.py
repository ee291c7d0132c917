"""Everything the rigid-rail RTRI validation case needs that is *not* published — in one place.

Reference case: Montenegro, Neves, Calçada, Tanabe & Sogabe, EURODYN 2014 / Computers & Structures 152 (2015)
200–214: a full-scale car on the rollers of RTRI's Rolling Stock Test Plant; the rollers move laterally to
reproduce the lateral deflection of a bridge span (what is and is not known: ``shared/reference/rtri_scenario.md``).
Every result computed with these values must be labelled as using them.

Each field below states its origin: **published** (the paper, as summarised in rtri_scenario.md) or
**ASSUMPTION** (with the reasoning).  The shape of the deviation (sine over the span, C2 end transitions) is
:class:`exudyn_wheelrail.track.rigid.SpanDeflection`.

Deviation amplitude δ = 10 mm (ASSUMPTION)
    The shape's end slope is k = πδ/L: 1.57 mrad on the 20 m span, 0.79 mrad on the 40 m span.  That is the order
    of magnitude design codes allow for the horizontal rotation of a deck end about a vertical axis (EN 1990
    Annex A2, A2.4.4.2.3, as we read it: 1.5 to 3.5 mrad depending on the line speed — not re-checked against the
    standard's text here), i.e. the largest deviation a bridge may show in service, which is what a running-safety
    test reproduces.  It exceeds the lateral wheel–rail clearance to flange contact of S1002 on UIC60 1:40
    (the contact jumps to the flange flank at 6.25 mm, computed by this project, README "contact jumps"), but the
    leading wheelset does not follow the deviation fully: at 250 km/h it reaches 5.89 mm relative to the track on
    the 20 m span, **0.36 mm short of the flange flank**, so the paper's flange impact at 20 m is not reproduced
    with this δ (the larger lateral force at 20 m and the absence of flange contact at 40 m are).  Measured
    sensitivity (``benchmarks/rtri_sensitivity.py``; Newmark 1 ms, RK44 1 ms and Newmark 0.5 ms agree on every
    yes/no): the 20 m flange contact appears between δ = 11 and 12 mm for l_t = 1–3 m and between 12 and 13 mm
    for l_t = 6 m; the 40 m span has no flange contact for any δ of 8–16 mm and l_t of 1–6 m (at least 1.08 mm
    short of the flanges); the 20 m / 40 m force ratio is at least 2 everywhere but at δ = 8 mm, l_t = 6 m.  The
    stated δ is kept (it is not tuned to the finding); ``tests/test_rtri.py`` asserts the flange impact at
    δ = 14 mm (2.2 mrad) and the 0.36 mm margin at δ = 10 mm.
Transition length l_t = 3 m (ASSUMPTION)
    A continuous welded rail cannot follow a kink; it spreads it over the length on which the track bends as a
    beam on an elastic lateral foundation, characteristic length λ = (4 EI / k)^(1/4).  With two UIC60 rails about
    their vertical axes, EI = 2 · 210 GPa · 512 cm⁴ ≈ 2.15e6 N m² (I_z ≈ 512 cm⁴ for 60E1, EN 13674-1), and a
    lateral track stiffness k ≈ 10 MN/m per metre of track (an ASSUMED order of magnitude for ballast + fastenings),
    λ ≈ 0.96 m; the bending response to a concentrated kink is confined to about half a wavelength, πλ ≈ 3.0 m.
    l_t/L = 0.15 (20 m) and 0.075 (40 m): the sine keeps most of the span.  l_t is the least certain input; studies
    should vary it (1 ... 6 m).
Flexible car body (``rtri --car-body flexible``; ASSUMPTION: the vehicle file ``manchester_vehicle1_flexible``)
    The paper attributes its remaining misfit of the car-body accelerations to the rigid car body of its model;
    neither the test vehicle's nor the Manchester coach's car-body flexibility is published.  The car body becomes
    a uniform free–free Euler–Bernoulli beam (:mod:`exudyn_wheelrail.rolling_stock.flexible_body`) whose mass and
    inertia are the Manchester data's: length 27.17 m, just below sqrt(12 Iyy / M) = 27.18 m, so a uniform beam
    of 32 t has the data's pitch and yaw inertia (1.97e6 kg m²) with almost no extra rotary inertia, polar inertia
    per length Ixx / L.  Its stiffnesses are chosen for the first free–free frequencies **10 Hz vertical bending,
    12 Hz torsion, 15 Hz lateral bending**: published first flexible modes of passenger car bodies lie at
    8–15 Hz (KTH rail vehicle dynamics course notes, as quoted in the car-body flexibility literature), the first
    vertical bending of long, light (high-speed) car bodies at 6–12 Hz (Dumitriu & Dihoru, Appl. Sci. 11 (2021)
    8502; Dumitriu et al., Appl. Sci. 14 (2024) 4687), and RTRI models the elastic modes of Shinkansen-type car
    bodies in this range (Takigami, Akiyama & Aida, QR of RTRI 62 (2021) 22–28: six target elastic modes fitted
    within 0.86 %); lateral bending of the wide shell is stiffer than vertical bending, torsion lies between.  The
    three modes below 20 Hz are kept (the next, torsion 24 Hz and vertical bending 27 Hz, are above the comfort
    weightings' sensitive range and cost: the FFRF object's cost grows steeply with its modes), each damped with
    2 % of critical (ASSUMPTION: structural damping of welded car-body shells of 1–3 % is the usual modelling
    range).  ``EA`` = 1e10 N (first axial mode 54 Hz, not kept).  Values in ``vehicles/manchester_vehicle1_
    flexible.toml``.
The substitute's running stability at 250 km/h (a consequence of the vehicle ASSUMPTION)
    The ``critical-speed`` command (docs/stability.md) on the Manchester vehicle 1, S1002/UIC60 1:40: linear critical
    speed 333.5 km/h (hunting 4.62 Hz), **nonlinear critical speed 169.7 km/h** — at the case's 250 km/h the
    centred running is linearly stable, but a disturbance (the span's deviation is one) leaves the bogies on a
    limit cycle (S1002/UIC60 1:40's contact point jumps between two tread zones 0.25 mm off the centre: conicity
    0.11 at the centre, 0.62 at 0.5 mm). The 20 m case run for 8 s keeps 2.4 mm (leading) and 1.5 mm (trailing
    wheelset) lateral amplitude after the span. The paper's test car (not published) is expected to run stably at the
    plant's 250 km/h; the substitute does not. The same vehicle with assumed yaw dampers (250 kN s/m per bogie side)
    has 163.9 km/h; on rails inclined 1:20 it is stable there (268.2 km/h) but that changes the wheel–rail pair. On
    a track gauge of 1437 mm (ASSUMED; the plant's gauge is adjustable, its setting unpublished) it is stable at
    250 km/h (nonlinear critical speed 274 km/h: conicity 0.043 at the centre; examples/stability/
    manchester_vehicle1_gauge_1437.toml). The case keeps its substitute; side by side (docs/stability.md, δ = 10 mm,
    Newmark 1 ms): the 20 m span's **flange impact** (the paper's finding) appears with the stable substitute (left
    wheels of wheelsets 1 and 3, 3 ms each, unfiltered |Y| 88.7 kN) and not with this one (20.8 kN, no flange
    contact); the peak Y at the right wheel of wheelset 1 is 23.2 against 20.4 kN (20 m) and 1.9 against 3.7 kN
    (40 m), the rear car-body acceleration 1.34 against 1.18 m/s² (20 m) and 0.59 against 0.63 m/s² (40 m); after
    the span the stable substitute decays where this one keeps a 2.46 mm limit cycle. What depends on the choice:
    the flange impact of the 20 m span at the stated δ, the lateral motion after the span, the peak values by
    6–50 %; the 20 m span's much higher lateral force than the 40 m span's holds with both.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..track.rigid import SpanDeflection

__all__ = ["RtriAssumptions", "RTRI"]


@dataclass(frozen=True)
class RtriAssumptions:
    """Inputs of the RTRI case; the origin of each value is written next to it (see the module docstring)."""

    # --- published (Montenegro et al. 2015; rtri_scenario.md)
    span_lengths_m: tuple[float, ...] = (20.0, 40.0)   #: published: the two spans compared
    time_step_s: float = 1.0e-3                        #: published
    n_steps_published: int = 2500                      #: published (2.5 s; see run_time_s for what a run needs)
    newmark_beta: float = 0.25                         #: published (no numerical dissipation)
    newmark_gamma: float = 0.5                         #: published
    plant_max_speed_km_h: float = 250.0                #: published: the plant's limit
    deviation_direction: str = "lateral"               #: published: a lateral irregularity of the rigid track

    # --- ASSUMPTIONS (not published)
    #: ASSUMPTION: substitute vehicle (rtri_scenario.md): Manchester vehicle 1, S1002 on UIC60 1:40, gauge 1435 mm
    vehicle: str = "manchester_vehicle1"
    #: ASSUMPTION: the same vehicle with a flexible car body (``--car-body flexible``; see the module docstring)
    flexible_vehicle: str = "manchester_vehicle1_flexible"
    #: ASSUMPTION δ: see the module docstring (of the order of the code limits for deck-end rotation)
    deviation_amplitude_m: float = 0.010
    #: ASSUMPTION l_t: see the module docstring (≈ π λ, the bending half-wavelength of the rails on their support)
    transition_length_m: float = 3.0
    #: ASSUMPTION: the span deflects towards +y (the right rail)
    deviation_sign: float = +1.0
    #: ASSUMPTION: a set of speeds up to the plant's limit
    speeds_km_h: tuple[float, ...] = (100.0, 150.0, 200.0, 250.0)
    #: ASSUMPTION: distance of the leading wheelset to the start of the first transition at t = 0
    lead_in_m: float = 10.0
    #: ASSUMPTION: distance run after the trailing wheelset has left the span (car-body response decays)
    run_out_m: float = 10.0

    def __post_init__(self):
        if not self.deviation_amplitude_m > 0.0 or not self.transition_length_m >= 0.0:
            raise ValueError("RtriAssumptions: the deviation amplitude must be positive and the transition length "
                             "non-negative")
        if any(self.transition_length_m >= L for L in self.span_lengths_m):
            raise ValueError("RtriAssumptions: transition_length_m must be shorter than every span")

    def span_deflection(self, span_length_m: float, start_m: float | None = None) -> SpanDeflection:
        """The deviation of one span; by default the span starts ``lead_in_m + l_t/2`` ahead of s = 0 (the leading
        wheelset's track distance at t = 0)."""
        if start_m is None:
            start_m = self.lead_in_m + 0.5 * self.transition_length_m
        return SpanDeflection(span_length_m=span_length_m, amplitude_m=self.deviation_sign * self.deviation_amplitude_m,
                              start_m=start_m, transition_length_m=self.transition_length_m,
                              direction=self.deviation_direction)

    def end_rotation_rad(self, span_length_m: float) -> float:
        """Slope of the untransitioned shape at the span ends, πδ/L."""
        return math.pi * self.deviation_amplitude_m / span_length_m

    def run_time_s(self, speed_km_h: float, span_length_m: float, vehicle_extent_m: float) -> float:
        """Time for the whole vehicle (leading to trailing wheelset: ``vehicle_extent_m``) to pass the span, with
        the lead-in and run-out distances."""
        distance = self.lead_in_m + span_length_m + self.transition_length_m + vehicle_extent_m + self.run_out_m
        return distance / (speed_km_h / 3.6)


#: The default assumptions.
RTRI = RtriAssumptions()
