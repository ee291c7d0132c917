r"""Manchester vehicle 1 crossing a flexible simply supported single-track concrete span (20 m or 40 m).

Run:  python examples/bridge_crossing.py --span 20 --speed-kmh 200 --out DIR [--dt 1e-3] [--creep-law fastsim]
          [--support-motion PEAK_M_S2,FREQ_HZ] [--view]

``--view`` shows the run in Exudyn's 3-D renderer (:mod:`exudyn_wheelrail.interactive.view3d`: wheels, rails, the
deck box, contact points and force arrows; slow motion, the window stays open until closed).

The vehicle (``vehicles/manchester_vehicle1.toml``: car body, two bogies, four wheelsets; S1002 on UIC60 1:40)
runs at constant speed on a straight track without irregularities; the deck is a modally reduced 3-D
Euler–Bernoulli beam (:mod:`exudyn_wheelrail.structures.bridge`, modal formulation) coupled to the wheel–rail
connector (``add_wheel_rail_contact(..., bridge=...)``: the deck's displacement and velocity under every wheelset
enter the contact, the contact forces load the deck).  At t = 0 the leading wheelset stands ``LEAD_IN_M`` before
the deck (in static equilibrium on the rigid track, :func:`~exudyn_wheelrail.multibody.place_on_rails`); the run
ends when the trailing wheelset is ``RUN_OUT_M`` past the far abutment (the free vibration of the deck after the
passage is in the record).  Solver: trapezoidal rule (generalized-α, ρ∞ = 1, modified Newton with the
connector's Jacobian), Δt = 1 ms.

Outputs in DIR
--------------
``timeseries.csv`` — one row per time step (the state at ``time_s``): ``s_leading_m`` (track distance of the
leading wheelset; deck from s = 0 to L), ``deck_mid_deflection_m`` (vertical, positive down),
``deck_mid_acceleration_m_s2`` (vertical, positive down), then per wheel ``w<j>_<side>`` (j = 1 leading … 4;
side right/left): ``Q_..._N`` wheel load (vertical force of the wheel on the rail, positive pressing),
``Y_..._N`` lateral force of the wheel on its rail, positive towards the field side (the direction in which a
flange pushes its rail: +y for the right wheel, -y for the left), ``YQ_...`` = Y/Q (derailment quotient, NaN
when lifted), ``dQQ_...`` = (Q0 - Q)/Q0 (wheel unloading; Q0 the static wheel load of the vehicle's load path),
and ``deck_z_w<j>_m`` the deck deflection under wheelset j (0 off the deck), ``y_rel_w<j>_m`` the lateral
wheelset–rail displacement (axle centre relative to the rails' centre line at rail top, in the rail pair's frame:
the pose the contact search solves for); with ``--support-motion`` also ``ground_y_m``, ``ground_acc_y_m_s2``,
``deck_mid_lateral_rel_m`` (relative to the supports), ``deck_mid_lateral_abs_m`` and
``deck_mid_lateral_acc_abs_m_s2`` (absolute).
``summary.json`` — inputs, the stated section assumptions, the modes, maxima, the EN 1990 A2 checks and a
``lateral`` block (wheelset–rail displacement, flange contact, the support motion and the deck's lateral response).

Deck acceleration check (EN 1990:2002/A1:2005, A2.4.4.2.1(4)P)
---------------------------------------------------------------
Peak vertical deck acceleration ≤ γ_bt = 3.5 m/s² (ballasted track) and ≤ γ_df = 5 m/s² (direct fastening),
with all modes up to the greater of 30 Hz, 1.5 f1 and f3 included.  The model keeps exactly the modes up to that
frequency (``f_cut_Hz`` in the summary), so the accelerations need no further filtering.  The acceleration is
taken at mid-span and, for the check, the maximum over nine points (L/10 … 9L/10) of the track centre line.
A single coach is not the load model HSLM of EN 1991-2 (no train of axles at resonance): the numbers show the
coupled model at work, not a design verification.

Results at 200 km/h (Δt = 1 ms, FASTSIM 24 × 8; Exudyn 1.13.6, one core of a shared machine)
-------------------------------------------------------------------------------------------
=====================================================  ==============  ==============
quantity                                               20 m span       40 m span
=====================================================  ==============  ==============
modes kept (f_cut)                                     7 (54 Hz)       7 (31.5 Hz)
max mid-span deflection                                1.370 mm        1.908 mm
  quasi-static influence-line maximum                  1.014 mm        1.552 mm
  deck under the moving static axle loads              1.378 mm        1.911 mm
max deck acceleration (9 points) / at mid-span         0.87 / 0.70     0.18 / 0.18 m/s²
EN 1990 A2 (3.5 ballasted, 5 direct fastening)         both met        both met
max Y/Q, max ΔQ/Q raw (10 ms average)                  0.005, 0.079    0.005, 0.094
                                                       (0.022)         (0.017)
solve time                                             0.3–0.4 s       0.4–0.6 s
=====================================================  ==============  ==============

The 20 m span at 200 km/h is near the second resonance of the bogie spacing (v = f1 d / 2 with d = 19 m:
205 km/h), hence the larger amplification (1.35 against 1.23).  The coupled deflections are 0.6 % / 0.2 % below
the moving-force ones (the vehicle–bridge interaction of a heavy concrete deck is small); deflections and deck
accelerations change by < 1 % (mid-span acceleration 4 %) when Δt is halved or quartered (20 m span).  The raw
ΔQ/Q is the wheelsets' ~183 Hz bounce (see the summary's note), not a deck effect.

Lateral support motion (``--support-motion PEAK_M_S2,FREQ_HZ``, e.g. ``1.5,1.5``)
----------------------------------------------------------------------------------
An earthquake-like lateral ground motion of all supports *and of the track off the deck* (synchronous), transmitted
to the vehicle through the contact only (:mod:`exudyn_wheelrail.structures.support_motion`: relative-motion
formulation, effective modal load ``-Γ ÿ_g``, rails at ``y_g + Φ_y q``).  Record: a sine burst of the ground
displacement with C² quintic ramps; PEAK is ``max |ÿ_g|`` (ramps included), the plateau amplitude is 10 % lower
(1.35 m/s² for 1.5), displacement amplitude 15.2 mm at 1.5 Hz.  The ramp (one period) starts at t = 0 and the
lead-in is extended by ``V/f`` so that the leading wheelset reaches the deck when it ends; the plateau lasts to
the end of the run.  Choice 1.5 m/s² at 1.5 Hz (stated assumption, rationale in the module docstring): periods of
0.5–1 s at/after the EN 1998-1 type 1 corner period and near the coach's lateral/roll suspension modes; 1–2 m/s²
the reference ground accelerations of moderate-seismicity zones.

Results, ``--support-motion 1.5,1.5`` at 200 km/h (Δt = 1 ms, FASTSIM 24 × 8):

=====================================================  ==============  ==============
quantity                                               20 m span       40 m span
=====================================================  ==============  ==============
deck first lateral frequency (EB: √(EI_z/EI_y) f1)     16.97 Hz        7.00 Hz
deck mid-span lateral, relative to supports, max       0.171 mm        1.087 mm
  quasi-static 5 m a_p L⁴/(384 EI_z)                   0.167 mm        0.983 mm
deck mid-span lateral acceleration, absolute, max      1.54 m/s²       1.70 m/s²
max wheelset–rail lateral displacement |y_rel|         1.06 mm         1.00 mm
flange contact (clearance 6.5 mm)                      none            none
max Y/Q raw (10 ms average); without motion 0.005      0.147 (0.146)   0.143 (0.142)
EN 14363 Y/Q (20 Hz, 2 m sliding mean; limit 0.8)      0.140           0.137
EN 14363 track shift force ΣY_2m (Prud'homme 46.4 kN)  15.1 kN         14.7 kN
max |Y| any wheel                                      8.5 kN          8.2 kN
max ΔQ/Q (10 ms average)                               0.070           0.072
vertical deck results (deflection, acceleration)       unchanged       unchanged
solve time                                             1.2 s           1.3 s
=====================================================  ==============  ==============

The deck follows the ground almost rigidly (relative motion ≈ 1 % of the ground's for 20 m, 7 % for 40 m; the
ratio to the quasi-static value is the amplification ``1/(1 - r²)`` at r = f/f_lat plus the wheels' lateral
forces); the vehicle is shaken through the rails: the wheelsets lag the rails by about 1 mm (the lateral creep
force needs that relative motion at 200 km/h; at walking speed the creep lock keeps it at micrometres,
tests/test_bridge_support_motion.py), and the car body's lateral/roll response builds up over the run: the
largest Y/Q occur near its end, partly after the vehicle has left the 20 m deck (on the moving embankment).  Y/Q
stays far below the flange-climbing limit 0.8.  The track shift force is Newton's law for the vehicle: a quarter
of its 44.5 t times the plateau ground acceleration 1.35 m/s² is 15.0 kN.  Halving Δt (20 m): Y/Q 0.148,
|y_rel| 1.046 mm.

Section assumptions (typical single-track ballasted prestressed-concrete decks; not from a specific bridge)
-----------------------------------------------------------------------------------------------------------
================  =====================  =====================  ==================================================
quantity          20 m span              40 m span              rationale
================  =====================  =====================  ==================================================
m [t/m]           15                     21                     concrete section 4.0 / 6.5 m² × 2.5 t/m³, ballast
                                                                bed with sleepers 0.55 m × 4 m × 1.8 t/m³ ≈ 4 t/m,
                                                                rails, parapets, ducts ≈ 1 t/m
f1 [Hz]           6.0                    3.5                    inside the EN 1991-2 Fig. 6.10 band of first
                                                                bending frequencies (20 m: 4.0–10.1 Hz; 40 m:
                                                                2.66–6.0 Hz; lower limit 80/L resp. 23.58 L^-0.592,
                                                                upper 94.76 L^-0.748)
EI_y [N m²]       3.50e10                2.67e11                from f1 = π/(2L²)·√(EI/m); I = 0.97 / 7.4 m⁴ with
                                                                E_c = 36 GPa (a 1.4 m voided slab / a 3 m box)
EI_z              8 EI_y                 4 EI_y                 (width/depth)² of a 5.5 m × 1.4 m slab, 6 m × 3 m box
GJ                1.0 EI_y               1.0 EI_y               St Venant J of the slab ≈ 3 I_y, of the box
                                                                ≈ 2.5 I_y, with G = E/2.4
I_p [kg m²/m]     m (b² + h²)/12         m (b² + h²)/12         b, h = 5.5, 1.4 m / 6, 3 m
EA [N]            1.44e11                2.34e11                E_c × concrete area
rail height e_z   1.45 m                 2.0 m                  beam axis to top of rail: centroid depth plus
                                                                ballast, sleeper and rail (≈ 0.75 m)
ζ                 1.0 %                  1.0 %                  EN 1991-2 Table 6.6, prestressed concrete, L ≥ 20 m
================  =====================  =====================  ==================================================
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import sys
from pathlib import Path

import exudyn as exu
import numpy as np

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.multibody import build_vehicle, simulation_settings
from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.simulation.recorder import Recorder
from exudyn_wheelrail.simulation.runner import run as run_watched
from exudyn_wheelrail.simulation.settings import RunSettings
from exudyn_wheelrail.structures import BridgeModel, DeckSection, add_bridge
from exudyn_wheelrail.structures.support_motion import SmoothHarmonicSupportMotion

LEAD_IN_M = 5.0          # leading wheelset before the deck at t = 0
RUN_OUT_M = 10.0         # trailing wheelset past the far abutment at the end
AVERAGE_WINDOW_S = 0.01  # moving average of Y/Q and dQ/Q (removes the ~183 Hz wheelset bounce)
GAMMA_BALLASTED_M_S2 = 3.5
GAMMA_DIRECT_FASTENING_M_S2 = 5.0
E_CONCRETE_PA = 36e9
SIDES_OUT = ("right", "left")
SUPPORT_MOTION_RAMP_CYCLES = 1.0   # C2 ramp of the ground-motion burst (one period), before the deck is reached
Y_OVER_Q_LIMIT = 0.8     # usual flange-climbing limit (Nadal, flange angle 70 deg, mu = 0.36; EN 14363), for context
FLANGE_CLEARANCE_M = 6.5e-3   # S1002 / UIC60 1:40, gauge 1435, back-to-back 1360: flange contact from y = 6.5 mm


def deck_assumptions(span_m: float) -> dict:
    """The stated section assumptions of the module docstring for a 20 m or 40 m span."""
    table = {
        20.0: dict(m_kg_m=15e3, f1_Hz=6.0, lateral_factor=8.0, b_m=5.5, h_m=1.4, area_m2=4.0, rail_height_m=1.45),
        40.0: dict(m_kg_m=21e3, f1_Hz=3.5, lateral_factor=4.0, b_m=6.0, h_m=3.0, area_m2=6.5, rail_height_m=2.0),
    }
    if span_m not in table:
        raise ValueError(f"span {span_m} m: the example has section assumptions for 20 m and 40 m only")
    a = dict(table[span_m])
    L, m = span_m, a["m_kg_m"]
    EI = m * (2.0 * L * L * a["f1_Hz"] / math.pi) ** 2
    a.update(span_m=L, EI_y_Nm2=EI, EI_z_Nm2=a["lateral_factor"] * EI, GJ_Nm2=1.0 * EI,
             Ip_kgm2_m=m * (a["b_m"] ** 2 + a["h_m"] ** 2) / 12.0, EA_N=E_CONCRETE_PA * a["area_m2"],
             damping_ratio=0.01, I_y_m4_at_36GPa=EI / E_CONCRETE_PA)
    return a


def build(span_m: float, speed_m_s: float, creep_law: str = "fastsim", fastsim_grid=(24, 8), support_motion=None):
    """Exudyn model (not yet assembled): returns a dict with mbs, model, bridge, contact, modes, sensors and run
    data.  ``support_motion``: ``(peak_m_s2, frequency_Hz)`` of a lateral ground-motion burst of all supports
    (module docstring) or None."""
    a = deck_assumptions(span_m)
    sec = DeckSection(m_kg_m=a["m_kg_m"], EI_y_Nm2=a["EI_y_Nm2"], EI_z_Nm2=a["EI_z_Nm2"], GJ_Nm2=a["GJ_Nm2"],
                      EA_N=a["EA_N"], Ip_kgm2_m=a["Ip_kgm2_m"])
    model_b = BridgeModel((span_m,), sec, damping_ratio=a["damping_ratio"], rail_height_m=a["rail_height_m"],
                          start_m=0.0, elements_per_span=20)
    f1 = sec.vertical_frequency_Hz(span_m)
    f_cut = max(30.0, 1.5 * f1, sec.vertical_frequency_Hz(span_m, 3))      # EN 1990 A2.4.4.2.1(4)P
    modes = model_b.modes(f_max_Hz=1.01 * f_cut)                             # the FE f3 lies a little above

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    from exudyn_wheelrail.multibody.vehicle_data import load_vehicle
    vehicle = load_vehicle("manchester_vehicle1")
    x_ws = vehicle.wheelset_x_m()
    lead_in = LEAD_IN_M
    if support_motion is not None:                     # the burst's ramp is over when the deck is reached
        lead_in += speed_m_s * SUPPORT_MOTION_RAMP_CYCLES / float(support_motion[1])
    s_start = -lead_in - max(x_ws)                     # leading wheelset at s = -lead_in at t = 0
    model = build_vehicle(mbs, vehicle, speed_m_s=speed_m_s, s_start_m=s_start)
    geo = vehicle.geometry
    pair = WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)
    C.place_on_rails(mbs, model, pair)
    bridge = add_bridge(mbs, modes)
    t_end = (span_m + RUN_OUT_M - s_start - min(x_ws)) / speed_m_s
    motion = None
    if support_motion is not None:
        peak, f = (float(x) for x in support_motion)
        ramp_s = SUPPORT_MOTION_RAMP_CYCLES / f
        # ramp from t = 0, plateau to the end of the run (the ramp-down would follow after it)
        motion = SmoothHarmonicSupportMotion(peak, f, ramp_cycles=SUPPORT_MOTION_RAMP_CYCLES,
                                             plateau_cycles=math.ceil((t_end - ramp_s) * f + 1.0), start_s=0.0)
        bridge.add_support_motion(mbs, motion)
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=speed_m_s, s_start_m=s_start,
                                       creep_law=creep_law, fastsim_grid=tuple(fastsim_grid), bridge=bridge)
    from exudyn.itemInterface import SensorNode
    sensors = {k: mbs.AddSensor(SensorNode(nodeNumber=bridge.modal_node, storeInternal=True, outputVariableType=o))
               for k, o in (("q", exu.OutputVariableType.Coordinates),
                            ("q_tt", exu.OutputVariableType.Coordinates_tt))}
    return dict(mbs=mbs, SC=SC, model=model, bridge=bridge, contact=contact, modes=modes, sensors=sensors,
                assumptions=a, f1_Hz=f1, f_cut_Hz=f_cut, s_start_m=s_start, t_end_s=t_end, pair=pair,
                x_ws=np.array(x_ws), section=sec, motion=motion, lead_in_m=lead_in)


class WheelsAndDeck:
    """Recorder probe (:mod:`exudyn_wheelrail.simulation.recorder`): per wheel Q and Y (towards the field side),
    the deck deflection under every wheelset, the lateral wheelset–rail displacement of every wheelset and the
    largest flange-region normal force — from the contact as the run monitor evaluated it at the state."""

    def __init__(self, h: dict):
        self.c = h["contact"]
        self.n_ws = len(h["model"].wheelsets)
        wheels = [f"w{j + 1}_{side}" for j in range(self.n_ws) for side in SIDES_OUT]
        self.columns = ([("wheels", f"{q}_{w}") for w in wheels for q in ("Q", "Y")]
                        + [("deck", f"deck_z_w{j + 1}") for j in range(self.n_ws)]
                        + [("lateral", f"y_rel_w{j + 1}") for j in range(self.n_ws)] + [("flange", "flange_N")])

    def fill(self, mbs, t, out):
        c, k = self.c, 0
        for j in range(self.n_ws):
            for side in SIDES_OUT:
                F = c.wheel_force_N(j, side)
                out[k] = -float(F[2]) + 0.0
                out[k + 1] = (-float(F[1]) if side == "right" else float(F[1])) + 0.0
                k += 2
        out[k:k + self.n_ws] = c.deck_state()[:, 1]
        out[k + self.n_ws:k + 2 * self.n_ws] = c.wheelset_rail_pose()[:, 0]
        out[k + 2 * self.n_ws] = float(np.max(c.results[:, 1, C.RES_N]))


def run(span_m: float, speed_km_h: float, dt_s: float = 1e-3, creep_law: str = "fastsim", progress=print,
        support_motion=None, view: bool = False) -> dict:
    V = speed_km_h / 3.6
    h = build(span_m, V, creep_law, support_motion=support_motion)
    mbs, contact, modes = h["mbs"], h["contact"], h["modes"]
    rec = Recorder([WheelsAndDeck(h)])
    view3d = None
    if view:                      # Exudyn's renderer: wheels, rails, deck, contact points and forces
        from exudyn_wheelrail.interactive.view3d import WheelRailView
        view3d = WheelRailView(mbs, h["model"], h["pair"], contact, bridge=h["bridge"])
    mbs.Assemble()
    contact.warm_up(mbs)
    steps = int(math.ceil(h["t_end_s"] / dt_s))
    ss = simulation_settings(steps * dt_s, dt_s, spectral_radius=1.0)
    ss.timeIntegration.newton.useModifiedNewton = True
    if view3d is not None:
        view3d.open_window(h["SC"], ss, realtime_factor=0.25, focus="vehicle")
    if progress:
        progress(f"span {span_m:g} m, {speed_km_h:g} km/h: {modes.n_modes} modes up to {modes.frequencies_Hz[-1]:.1f} "
                 f"Hz (f1 = {h['f1_Hz']:.2f} Hz, f_cut = {h['f_cut_Hz']:.1f} Hz), {steps} steps of {dt_s:g} s")
        if h["motion"] is not None:
            progress(f"support motion: {h['motion']}")
    # the one solve wrapper, watched by the run monitor; these Exudyn settings (trapezoidal rule as generalized-α
    # with ρ∞ = 1, modified Newton, Newton tolerance 1e-6) are the ones solved with
    settings = RunSettings(solver="generalized_alpha", dt_s=dt_s, duration_s=steps * dt_s, newton_tolerance=1e-6)
    try:
        outcome = run_watched(mbs, settings, contact, speed_m_s=V, recorder=rec,
                              exu_settings=(ss, exu.DynamicSolverType.GeneralizedAlpha))
    finally:
        if view3d is not None:
            view3d.close_window()
    if not outcome.status.ok:
        raise RuntimeError(f"the run ended {outcome.status}")
    solve_s = outcome.solve_seconds
    wheels = rec.data[:rec.n]
    dq = mbs.GetSensorStoredData(h["sensors"]["q"])
    da = mbs.GetSensorStoredData(h["sensors"]["q_tt"])
    n = min(len(wheels), len(dq), len(da))
    if np.max(np.abs(wheels[:n, 0] - dq[:n, 0])) > 1e-9 or np.max(np.abs(dq[:n, 0] - da[:n, 0])) > 1e-9:
        raise RuntimeError("recorder and sensor rows are not aligned in time")
    t = wheels[:n, 0]
    q, q_tt = dq[:n, 1:], da[:n, 1:]
    L = float(span_m)
    phi_mid = modes.shape_at(L / 2)[1]
    x_pts = L * np.arange(1, 10) / 10
    phi_pts = modes.shape_at(x_pts)[:, 1, :]                   # (9, n_m)
    w_mid = q @ phi_mid
    a_mid = q_tt @ phi_mid
    a_pts = q_tt @ phi_pts.T
    n_ws = len(h["model"].wheelsets)
    Q0_path = h["model"].load_path.wheel                       # (n_ws, 2) in SIDES = (left, right)
    cols = {"time_s": t, "s_leading_m": h["s_start_m"] + V * t + h["x_ws"].max(),
            "deck_mid_deflection_m": w_mid, "deck_mid_acceleration_m_s2": a_mid}
    k = 1
    Q0 = {}
    for j in range(n_ws):
        for side in SIDES_OUT:
            name = f"w{j + 1}_{side}"
            Q0[name] = float(Q0_path[j, 0 if side == "left" else 1])
            Q = wheels[:n, k]
            Y = wheels[:n, k + 1]
            with np.errstate(divide="ignore", invalid="ignore"):
                cols[f"Q_{name}_N"] = Q
                cols[f"Y_{name}_N"] = Y
                cols[f"YQ_{name}"] = np.where(Q > 0.0, Y / Q, np.nan)
                cols[f"dQQ_{name}"] = (Q0[name] - Q) / Q0[name]
            k += 2
    for j in range(n_ws):
        cols[f"deck_z_w{j + 1}_m"] = wheels[:n, k + j]
    for j in range(n_ws):
        cols[f"y_rel_w{j + 1}_m"] = wheels[:n, k + n_ws + j]
    flange_N = wheels[:n, k + 2 * n_ws]
    motion = h["motion"]
    if motion is not None:
        phi_mid_y = modes.shape_at(L / 2)[0]
        cols["ground_y_m"] = motion.displacement_m(t)
        cols["ground_acc_y_m_s2"] = motion.acceleration_m_s2(t)
        cols["deck_mid_lateral_rel_m"] = q @ phi_mid_y
        cols["deck_mid_lateral_abs_m"] = cols["ground_y_m"] + cols["deck_mid_lateral_rel_m"]
        cols["deck_mid_lateral_acc_abs_m_s2"] = cols["ground_acc_y_m_s2"] + q_tt @ phi_mid_y
    # quasi-static reference: mid-span influence line of the static axle loads, P a (3L² - 4a²)/(48 EI) (a ≤ L/2)
    P_axle = Q0_path.sum(axis=1)
    EI = h["assumptions"]["EI_y_Nm2"]
    s_ax = h["s_start_m"] + V * t[:, None] + h["x_ws"][None, :]
    a_ = np.minimum(s_ax, L - s_ax)
    w_static = np.where((s_ax > 0) & (s_ax < L), P_axle * a_ * (3 * L * L - 4 * a_ * a_) / (48 * EI), 0.0).sum(axis=1)
    summary = _summary(h, span_m, speed_km_h, dt_s, steps, solve_s, cols, a_pts, w_static, Q0, creep_law)
    summary["lateral"] = _lateral_summary(h, cols, flange_N, dt_s, V, Q0)
    # moving-force reference: the same deck under the static axle loads moving at V (no vehicle dynamics)
    from exudyn_wheelrail.structures import simulate_moving_forces
    t_mf, q_mf, _ = simulate_moving_forces(modes, x_m=h["x_ws"], forces_N=[[0.0, p, 0.0] for p in P_axle],
                                           speed_m_s=V, s_start_m=h["s_start_m"], end_time_s=steps * dt_s,
                                           step_s=dt_s)
    w_mf = q_mf @ phi_mid
    summary["deck"]["moving_force_reference"] = {
        "what": "the deck alone under the four static axle loads moving at V (simulate_moving_forces, same modes "
                "and time step): the difference to the coupled run is the vehicle-bridge interaction",
        "max_mid_span_deflection_m": float(np.max(w_mf)),
        "coupled_over_moving_force": summary["deck"]["max_mid_span_deflection_m"] / float(np.max(w_mf)),
    }
    return {"timeseries": cols, "summary": summary}


def _summary(h, span_m, speed_km_h, dt_s, steps, solve_s, cols, a_pts, w_static, Q0, creep_law):
    modes = h["modes"]
    a_mid_max = float(np.max(np.abs(cols["deck_mid_acceleration_m_s2"])))
    a_deck_max = float(np.max(np.abs(a_pts)))
    w_max = float(np.max(cols["deck_mid_deflection_m"]))
    wheels = list(Q0)
    yq = {w: float(np.nanmax(cols[f"YQ_{w}"])) for w in wheels}
    dqq = {w: float(np.nanmax(cols[f"dQQ_{w}"])) for w in wheels}
    n_avg = max(1, int(round(AVERAGE_WINDOW_S / dt_s)))
    kernel = np.ones(n_avg) / n_avg
    dqq_avg = {w: float(np.nanmax(np.convolve(cols[f"dQQ_{w}"], kernel, mode="valid"))) for w in wheels}
    yq_avg = {w: float(np.nanmax(np.convolve(cols[f"YQ_{w}"], kernel, mode="valid"))) for w in wheels}
    a = h["assumptions"]
    return {
        "case": "Manchester vehicle 1 crossing a simply supported single-track concrete span (examples/"
                "bridge_crossing.py); section properties are stated assumptions (module docstring)",
        "span_m": float(span_m), "speed_km_h": float(speed_km_h), "speed_m_s": speed_km_h / 3.6,
        "dt_s": dt_s, "steps": steps, "simulated_time_s": steps * dt_s, "solve_seconds": solve_s,
        "real_time_factor": steps * dt_s / solve_s, "contact_calls": int(h["contact"].n_calls),
        "solver": "generalized-alpha, spectral radius 1 (trapezoidal rule), modified Newton, connector Jacobian",
        "creep_law": creep_law, "track": "straight, no irregularities; S1002 / UIC60 1:40",
        "lead_in_m": h["lead_in_m"], "run_out_m": RUN_OUT_M,
        "assumptions": {k: (float(v) if isinstance(v, (int, float)) else v) for k, v in a.items()},
        "modes": {"n_modes": modes.n_modes, "f_cut_Hz": h["f_cut_Hz"], "f1_vertical_Hz": h["f1_Hz"],
                  "frequencies_Hz": [round(float(f), 3) for f in modes.frequencies_Hz],
                  "kinds": list(modes.kinds)},
        "deck": {
            "max_mid_span_deflection_m": w_max,
            "max_quasi_static_mid_span_deflection_m": float(np.max(w_static)),
            "dynamic_amplification_mid_span": w_max / float(np.max(w_static)),
            "max_abs_mid_span_acceleration_m_s2": a_mid_max,
            "max_abs_deck_acceleration_9_points_m_s2": a_deck_max,
        },
        "EN1990_A2_deck_acceleration": {
            "rule": "EN 1990/A1 A2.4.4.2.1(4)P: peak vertical deck acceleration with modes up to max(30 Hz, 1.5 f1, "
                    "f3); limits 3.5 m/s2 ballasted track, 5 m/s2 direct fastening",
            "peak_m_s2": a_deck_max,
            "ballasted_limit_m_s2": GAMMA_BALLASTED_M_S2, "ballasted_ok": a_deck_max <= GAMMA_BALLASTED_M_S2,
            "direct_fastening_limit_m_s2": GAMMA_DIRECT_FASTENING_M_S2,
            "direct_fastening_ok": a_deck_max <= GAMMA_DIRECT_FASTENING_M_S2,
            "note": "one coach, not the HSLM load model of EN 1991-2: illustrative, not a design check",
        },
        "wheels": {
            "static_wheel_load_N": Q0,
            "max_Y_over_Q": yq, "max_Y_over_Q_any_wheel": max(yq.values()),
            "max_wheel_unloading_dQ_over_Q": dqq, "max_dQ_over_Q_any_wheel": max(dqq.values()),
            "min_Q_any_wheel_N": float(min(np.min(cols[f"Q_{w}_N"]) for w in wheels)),
            "max_Q_any_wheel_N": float(max(np.max(cols[f"Q_{w}_N"]) for w in wheels)),
            "max_abs_Y_any_wheel_N": float(max(np.max(np.abs(cols[f"Y_{w}_N"])) for w in wheels)),
            "averaging_window_s": AVERAGE_WINDOW_S,
            "max_Y_over_Q_10ms_avg": yq_avg, "max_Y_over_Q_10ms_avg_any_wheel": max(yq_avg.values()),
            "max_dQ_over_Q_10ms_avg": dqq_avg, "max_dQ_over_Q_10ms_avg_any_wheel": max(dqq_avg.values()),
            "note": "the raw wheel loads carry the wheelsets' ~183 Hz bounce on the Hertz contact stiffness (almost "
                    "undamped: only the primary damper acts), excited where the rail slope changes (the deck end "
                    "rotations at the abutments); at dt = 1 ms it has ~5 steps per period and its peaks are not "
                    "converged in dt: the 10 ms moving averages remove it",
        },
        "sign_conventions": {
            "deck": "track frame, z down: deflection and acceleration positive downwards",
            "Q": "vertical force of the wheel on the rail, positive pressing",
            "Y": "lateral force of the wheel on its rail, positive towards the field side (+y right wheel, -y left)",
            "dQQ": "(Q0 - Q)/Q0, positive when the wheel is unloaded",
        },
    }


def _lateral_summary(h, cols, flange_N, dt_s, speed_m_s, Q0):
    """Lateral results: wheelset–rail displacement, flange contact, the EN 14363 derailment quotient and track
    shift force (:mod:`exudyn_wheelrail.analysis.safety`), and (with a support motion) the ground and the deck's
    lateral response."""
    from exudyn_wheelrail.analysis import safety
    n_ws = len(h["model"].wheelsets)
    yq_2m, shift = {}, {}
    for j in range(n_ws):
        for side in SIDES_OUT:
            w = f"w{j + 1}_{side}"
            yq_2m[w] = safety.derailment_quotient_en14363(cols[f"Y_{w}_N"], cols[f"Q_{w}_N"], dt_s, speed_m_s)
        # ΣY of the wheelset on the track (track y): Y is positive towards each wheel's field side
        sum_y = cols[f"Y_w{j + 1}_right_N"] - cols[f"Y_w{j + 1}_left_N"]
        q0 = 0.5 * (Q0[f"w{j + 1}_right"] + Q0[f"w{j + 1}_left"])
        shift[f"w{j + 1}"] = safety.track_shift_force_en14363(sum_y, dt_s, speed_m_s, q0)
    w_yq = max(yq_2m, key=lambda k: yq_2m[k]["value"])
    w_sh = max(shift, key=lambda k: shift[k]["value"])
    modes, sec = h["modes"], h["section"]
    L = h["assumptions"]["span_m"]
    y_rel = {f"w{j + 1}": float(np.max(np.abs(cols[f"y_rel_w{j + 1}_m"]))) for j in range(n_ws)}
    lat = modes.of_kind("lateral")
    out = {
        "what": "y_rel = lateral displacement of the axle centre relative to the rails' centre line at rail top (in "
                "the rail pair's frame; ground motion, deck and irregularity included): the pose the contact "
                "search solves for",
        "max_abs_wheelset_rail_lateral_m": y_rel,
        "max_abs_wheelset_rail_lateral_any_m": max(y_rel.values()),
        "flange_clearance_m": FLANGE_CLEARANCE_M,
        "flange_contact_steps": int(np.sum(flange_N > 0.0)),
        "max_flange_normal_force_N": float(np.max(flange_N)),
        "Y_over_Q_limit_for_context": Y_OVER_Q_LIMIT,
        "EN14363": {
            "what": "analysis.safety: Y and Q low-pass 20 Hz, sliding mean over 2 m of track; maxima over the run "
                    "(one simulated run, not the standard's statistics); limits 0.8 (Y/Q, R >= 250 m) and "
                    "Prud'homme alpha (10 kN + 2 Q0/3) with alpha = 1",
            "Y_over_Q_2m_max": yq_2m[w_yq]["value"], "Y_over_Q_2m_wheel": w_yq,
            "Y_over_Q_2m_limit": yq_2m[w_yq]["limit"],
            "Y_over_Q_2m_per_wheel": {k: v["value"] for k, v in yq_2m.items()},
            "track_shift_force_2m_max_N": shift[w_sh]["value"], "track_shift_force_2m_wheelset": w_sh,
            "prudhomme_limit_N": shift[w_sh]["limit"],
        },
        "deck_first_lateral_frequency_Hz": float(modes.frequencies_Hz[lat[0]]) if lat.size else None,
        "deck_first_lateral_frequency_euler_bernoulli_Hz": sec.lateral_frequency_Hz(L),
        "support_motion": None,
    }
    motion = h["motion"]
    if motion is not None:
        a_plateau = motion.plateau_acceleration_m_s2
        out["support_motion"] = {
            "record": "sine burst of the ground displacement with C2 quintic ramps "
                      "(structures.support_motion.SmoothHarmonicSupportMotion), all supports and the track off the "
                      "deck together (synchronous); ramp from t = 0 over one period, then the plateau to the end of "
                      "the run; the leading wheelset reaches the deck when the ramp ends",
            "peak_acceleration_m_s2": motion.peak_acceleration_m_s2,
            "frequency_Hz": motion.frequency_Hz,
            "plateau_acceleration_m_s2": a_plateau,
            "displacement_amplitude_m": motion.amplitude_m,
            "ramp_s": motion.ramp_s,
            "max_abs_ground_displacement_m": float(np.max(np.abs(cols["ground_y_m"]))),
            "max_abs_ground_acceleration_m_s2": float(np.max(np.abs(cols["ground_acc_y_m_s2"]))),
            "deck_mid_lateral_rel_max_abs_m": float(np.max(np.abs(cols["deck_mid_lateral_rel_m"]))),
            "deck_mid_lateral_quasi_static_m": 5.0 * sec.m_kg_m * motion.peak_acceleration_m_s2 * L ** 4
            / (384.0 * sec.EI_z_Nm2),
            "deck_mid_lateral_acc_abs_max_m_s2": float(np.max(np.abs(cols["deck_mid_lateral_acc_abs_m_s2"]))),
            "rationale": "1-2 Hz: periods at/after the EN 1998-1 type 1 corner period T_C and near the coach's "
                         "lateral/roll suspension modes; 1-2 m/s2: a_gR of moderate-seismicity zones "
                         "(structures/support_motion.py docstring)",
        }
    return out


def write_outputs(result: dict, out_dir) -> dict:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"timeseries": out / "timeseries.csv", "summary": out / "summary.json"}
    ts = result["timeseries"]
    names = list(ts)
    with open(paths["timeseries"], "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(names)
        for i in range(len(ts["time_s"])):
            w.writerow([f"{ts[k][i]:.9g}" for k in names])
    with open(paths["summary"], "w") as fh:
        json.dump(result["summary"], fh, indent=2)
    return paths


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--span", type=float, required=True, choices=(20.0, 40.0), help="span length [m]: 20 or 40")
    ap.add_argument("--speed-kmh", type=float, required=True, help="running speed [km/h], 0 < V <= 400")
    ap.add_argument("--out", required=True, help="output directory")
    ap.add_argument("--dt", type=float, default=1e-3, help="time step [s] (default 1e-3)")
    ap.add_argument("--creep-law", default="fastsim", choices=sorted(C.CREEP_LAWS),
                    help="creep law of the connector (default fastsim, 24 x 8)")
    ap.add_argument("--support-motion", metavar="PEAK_M_S2,FREQ_HZ", default=None,
                    help="lateral ground motion of all supports (and the track): a sine burst with this peak "
                         "acceleration [m/s2] and frequency [Hz], e.g. 1.5,1.5")
    ap.add_argument("--view", action="store_true", help="show the run in Exudyn's 3-D renderer (slow motion)")
    args = ap.parse_args(argv)
    support_motion = None
    if args.support_motion is not None:
        try:
            peak, freq = (float(x) for x in args.support_motion.split(","))
        except ValueError:
            ap.error(f"--support-motion {args.support_motion!r}: expected PEAK_M_S2,FREQ_HZ, e.g. 1.5,1.5")
        if not (math.isfinite(peak) and 0.0 < peak <= 10.0):
            ap.error(f"--support-motion: peak acceleration {peak} m/s2, expected 0 < a <= 10")
        if not (math.isfinite(freq) and 0.1 <= freq <= 20.0):
            ap.error(f"--support-motion: frequency {freq} Hz, expected 0.1 <= f <= 20")
        support_motion = (peak, freq)
    if not (math.isfinite(args.speed_kmh) and 0.0 < args.speed_kmh <= 400.0):
        ap.error(f"--speed-kmh {args.speed_kmh}: expected 0 < V <= 400")
    if not (math.isfinite(args.dt) and 0.0 < args.dt <= 2e-3):
        ap.error(f"--dt {args.dt}: expected 0 < dt <= 2e-3 s")
    try:
        result = run(args.span, args.speed_kmh, args.dt, args.creep_law, support_motion=support_motion,
                     view=args.view)
    except FileNotFoundError as exc:          # e.g. creep_law="table" before the table is built
        ap.exit(2, f"error: {exc}\n")
    paths = write_outputs(result, args.out)
    s = result["summary"]
    d, e, wh = s["deck"], s["EN1990_A2_deck_acceleration"], s["wheels"]
    print(f"solve {s['solve_seconds']:.1f} s ({s['real_time_factor']:.2f} x real time), "
          f"{s['contact_calls']} contact calls")
    print(f"mid-span deflection max {d['max_mid_span_deflection_m'] * 1e3:.3f} mm (quasi-static "
          f"{d['max_quasi_static_mid_span_deflection_m'] * 1e3:.3f} mm, "
          f"ratio {d['dynamic_amplification_mid_span']:.3f})")
    mf = d["moving_force_reference"]
    print(f"moving-force reference (static axle loads): max deflection {mf['max_mid_span_deflection_m'] * 1e3:.3f} mm "
          f"(coupled / moving force = {mf['coupled_over_moving_force']:.4f})")
    print(f"deck acceleration max {e['peak_m_s2']:.3f} m/s2 (mid-span {d['max_abs_mid_span_acceleration_m_s2']:.3f}): "
          f"ballasted {'OK' if e['ballasted_ok'] else 'EXCEEDED'} (3.5), direct fastening "
          f"{'OK' if e['direct_fastening_ok'] else 'EXCEEDED'} (5.0)")
    print(f"max Y/Q {wh['max_Y_over_Q_any_wheel']:.4f}, max dQ/Q {wh['max_dQ_over_Q_any_wheel']:.4f} (10 ms average "
          f"{wh['max_dQ_over_Q_10ms_avg_any_wheel']:.4f}), Q {wh['min_Q_any_wheel_N'] / 1e3:.1f} .. "
          f"{wh['max_Q_any_wheel_N'] / 1e3:.1f} kN")
    la = s["lateral"]
    print(f"max wheelset-rail lateral displacement {la['max_abs_wheelset_rail_lateral_any_m'] * 1e3:.3f} mm "
          f"(flange clearance {FLANGE_CLEARANCE_M * 1e3:.1f} mm), flange contact in {la['flange_contact_steps']} "
          f"steps, max Y/Q {wh['max_Y_over_Q_any_wheel']:.3f} (10 ms average "
          f"{wh['max_Y_over_Q_10ms_avg_any_wheel']:.3f}; limit for context {Y_OVER_Q_LIMIT})")
    en = la["EN14363"]
    print(f"EN 14363 (20 Hz, 2 m sliding mean): Y/Q {en['Y_over_Q_2m_max']:.3f} (limit {en['Y_over_Q_2m_limit']}), "
          f"track shift force {en['track_shift_force_2m_max_N'] / 1e3:.2f} kN (Prud'homme "
          f"{en['prudhomme_limit_N'] / 1e3:.1f} kN)")
    if la["support_motion"] is not None:
        sm = la["support_motion"]
        print(f"support motion: peak {sm['peak_acceleration_m_s2']:.2f} m/s2 at {sm['frequency_Hz']:.2f} Hz "
              f"(plateau {sm['plateau_acceleration_m_s2']:.2f} m/s2, {sm['displacement_amplitude_m'] * 1e3:.1f} mm); "
              f"deck mid-span lateral relative {sm['deck_mid_lateral_rel_max_abs_m'] * 1e3:.3f} mm (quasi-static "
              f"{sm['deck_mid_lateral_quasi_static_m'] * 1e3:.3f} mm), absolute acceleration "
              f"{sm['deck_mid_lateral_acc_abs_max_m_s2']:.2f} m/s2")
    print(f"wrote {paths['timeseries']} and {paths['summary']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
