r"""Steady curving: what a vehicle does in the circular part of a curve, from a run's time series
(:mod:`exudyn_wheelrail.scenarios.curving` makes the run).

Quantities (per wheelset j, wheel ``outer``/``inner`` in the curve; track plane; signs of
:mod:`exudyn_wheelrail.conventions`):

* ``sum_Y_N`` — ΣY, the lateral force between the two rails and the wheelset, **positive outwards as a force on
  the track** (the force of the wheelset on the rails; the rails push the wheelset inwards by as much).  In steady
  curving the sum over all wheelsets balances the unbalanced lateral inertia of everything the wheelsets carry,

  .. math:: \sum_j ΣY_j = m\,a_{nc},\qquad a_{nc} = \frac{V^2}{R}\cos φ - g \sin φ

  (track plane, positive outwards; ``sin φ = h / 1.5 m``): every body's lateral load in the canted frame,
  ``m_i (V²/R cos φ − g sin φ)`` outwards, passes through the suspensions to the wheelsets and from them to the
  rails (Iwnicki (ed.), *Handbook of Railway Vehicle Dynamics*, CRC 2006, ch. 7; EN 14363:2016 §7.6 uses ΣY and
  the cant deficiency the same way).  Vehicles of the ``bogie``/``wheelset`` layouts are held by the moving frame
  through their guidance elements: there ``ΣΣY + guidance = m a_nc`` (``guidance_lateral_N``, outwards);
* ``Y_N``, ``Q_N``, ``YQ`` per wheel — Y the lateral force of the wheel on its rail towards that rail's field side
  (a flanging wheel: positive), Q the wheel load, Y/Q their ratio (the recorder's ``YQ`` columns);
* ``lateral_shift_m`` — the wheelset's lateral displacement relative to its rails, positive outwards;
* ``angle_of_attack_rad`` — the wheelset's yaw relative to the local track tangent, positive when it is turned
  outwards (the outer wheel's flange leading into its rail; a bogie's leading wheelset in a curve);
* ``unbalanced_lateral_acceleration_m_s2`` — a_nc above, at the curve's cant and radius.

A free wheelset with coned wheels rolls without slip in a curve of radius R where its rolling radii satisfy
``r_outer/r_inner = (R + b)/(R − b)``, i.e. at the lateral shift ``y = r0 b / (R λ)`` (λ the rolling-radius
difference gradient, ``Δr = 2 λ y``; b half the distance of the contact points) — Knothe & Stichel, *Rail Vehicle
Dynamics*, Springer 2017, §8.2; Wickens, *Fundamentals of Rail Vehicle Dynamics*, 2003, ch. 3.
"""
from __future__ import annotations

import math

import numpy as np

from ..conventions import outward_sign
from ..profiles.profiles import resolve_wheel

__all__ = ["CURVING_GROUP", "STEADY_TOLERANCE", "STEADY_A_MIN_M_S2", "SIDES_IN_CURVE", "minimum_radius_m", "flange_play_m", "curving_columns",
           "carried_mass_kg", "averaging_window", "steady_state", "pure_rolling_shift_m"]

#: the recorder's column group of :func:`curving_columns` (a scenario's output group with a ``[layout]``)
CURVING_GROUP = "curving"
#: the run is steady when the means of ΣY over the two halves of the steady part differ, summed over the wheelsets,
#: by less than this fraction of the force balance's scale ``m max(|a_nc|, STEADY_A_MIN_M_S2)`` (m the mass the wheels
#: carry: the static wheel loads over g, the vehicle's mass for a car): half of the 2 %
#: within which ΣΣY must balance m a_nc, so that a drift left in the mean cannot by itself use up that target.  A
#: residual oscillation (the car body's slow lateral mode, a flange contact's chatter at 100 Hz) of amplitude A and
#: period P moves a half's mean by at most A P/(π T/2) and the mean over whole periods far less.
STEADY_TOLERANCE = 0.01
#: the unbalanced acceleration below which the force balance's scale is held (the balance is judged from 0.3 m/s²)
STEADY_A_MIN_M_S2 = 0.3
SIDES_IN_CURVE = ("outer", "inner")
#: flange thickness is measured this far above the tape circle [m] (EN 15313)
FLANGE_THICKNESS_HEIGHT_M = 0.010
#: smallest radius whatever the wheelbase [m]: below it the small-angle chord geometry of the track-following
#: frames (versines, yaw between bodies) is not checked
RADIUS_FLOOR_M = 100.0


def flange_play_m(vehicle) -> float:
    """Total lateral play of a wheelset between its rails: gauge − back-to-back − 2 × flange thickness (the
    thickness 10 mm above the tape circle, from the wheel profile)."""
    geo = vehicle.geometry
    wheel = resolve_wheel(geo.wheel_profile)
    c = wheel.curve
    s = np.linspace(c.s_min, c.s_max, 40001)
    e = c.evaluate(s)
    y_back = float(np.min(e[:, 0]))
    flange = (e[:, 1] >= FLANGE_THICKNESS_HEIGHT_M) & (e[:, 0] < y_back + 0.05)
    thickness = float(np.max(e[flange, 0])) - y_back
    return geo.gauge_m - geo.back_to_back_m - 2.0 * thickness


def minimum_radius_m(vehicle) -> tuple[float, str]:
    """The smallest radius the vehicle can follow and why: a rigid wheelbase 2a spans a chord whose versine
    (2a)²/(8R) must fit in the wheelsets' lateral play σ (:func:`flange_play_m`) — R_min = (2a)²/(8σ) — and not less
    than :data:`RADIUS_FLOOR_M`."""
    a = vehicle.geometry.semi_wheelbase_m
    floor = "the smallest radius of the track-following frames' small-angle chord geometry"
    if not a:
        return RADIUS_FLOOR_M, floor
    sigma = flange_play_m(vehicle)
    r = (2.0 * a) ** 2 / (8.0 * sigma) if sigma > 0.0 else math.inf
    wheelbase = (f"the bogie's wheelbase {2 * a:g} m in {sigma * 1000:.1f} mm lateral play between the rails "
                 f"needs (2a)^2/(8 play) = {r:.0f} m")
    if r < RADIUS_FLOOR_M:
        return RADIUS_FLOOR_M, f"{floor}; {wheelbase}"
    return r, wheelbase


def pure_rolling_shift_m(r0_m: float, b_m: float, radius_m: float, lam: float) -> float:
    """y = r0 b / (R λ) (module docstring)."""
    return r0_m * b_m / (radius_m * lam)


class _WheelsetYaw:
    """``yaw_w<j>_rad`` (yaw of the wheelset relative to the model frame = its local track frame) and
    ``curvature_w<j>_1_m`` (the layout's curvature under it); with guidance elements ``guidance_lateral_N`` (the
    track-frame y force of the guidance elements on the bodies)."""

    def __init__(self, model, layout):
        import exudyn as exu
        self.model = model
        self.layout = layout
        self.nodes = [w.node for w in model.wheelsets]
        self.x = np.array([w.p_cg_in_frame[0] for w in model.wheelsets])
        self._rot = exu.OutputVariableType.RotationMatrix
        self._force = exu.OutputVariableType.Force
        self.guidance = list(model.connectors.get("guidance", []))
        n = len(self.nodes)
        self.columns = ([(CURVING_GROUP, f"yaw_w{j + 1}_rad") for j in range(n)]
                        + [(CURVING_GROUP, f"curvature_w{j + 1}_1_m") for j in range(n)]
                        + ([(CURVING_GROUP, "guidance_lateral_N")] if self.guidance else []))

    def fill(self, mbs, t, out):
        n = len(self.nodes)
        for j, node in enumerate(self.nodes):
            R = np.asarray(mbs.GetNodeOutput(node, self._rot)).reshape(3, 3)
            out[j] = math.atan2(-R[0, 1], R[1, 1])
        out[n:2 * n] = self.layout.curvature(self.model.track_distance_m(self.x, t))
        if self.guidance:
            # Exudyn's connector force f acts as -f on marker 1 (the body), the ground point is marker 0
            out[2 * n] = -sum(float(mbs.GetObjectOutput(c, self._force)[1]) for c in self.guidance)


def curving_columns(model, layout) -> list:
    """The recorder probes of a curving run besides :func:`~exudyn_wheelrail.simulation.recorder.vehicle_probes`."""
    return [_WheelsetYaw(model, layout)]


def carried_mass_kg(model, gravity_m_s2: float) -> float:
    """The mass the wheels carry [kg]: the static wheel loads over g (with the dead loads of the bogie and wheelset
    layouts), the vehicle's mass for a model without a load path — the scale of the steady-state tolerance
    (:func:`steady_state`).  (What ΣY balances in the steady curve is the modelled bodies' mass times a_nc, less
    the guidance elements' force of the bogie and wheelset layouts, whose carried dead load the frame holds.)"""
    return (float(model.load_path.wheel.sum()) / gravity_m_s2 if model.load_path is not None
            else float(model.vehicle.total_mass_kg))


def averaging_window(t, signal, t_from_s: float, smoothing_s: float = 0.05) -> np.ndarray:
    """Rows of the steady part (``t >= t_from_s``) to average over: a whole number of periods of the slowest
    oscillation left in ``signal`` (its upward crossings of the part's mean, after a ``smoothing_s`` moving average
    that removes the contact's high-frequency content), from the first to the last crossing — the mean of a
    sinusoid over whole periods is exact, over a box of arbitrary length it is biased by up to A P/(π T) (the car
    body's lateral mode, about 0.5 Hz, decays slowly after the transition).  Without two crossings at least a
    quarter of the part apart: the whole part.  Returns a boolean mask."""
    t = np.asarray(t, dtype=float)
    part = t >= t_from_s - 1e-9
    if not np.any(part):
        raise ValueError(f"no recorded state after t = {t_from_s:g} s")
    idx = np.flatnonzero(part)
    x = np.asarray(signal, dtype=float)[idx]
    dt = float(np.median(np.diff(t[idx]))) if len(idx) > 1 else 1.0
    w = max(1, int(round(smoothing_s / dt)))
    xs = np.convolve(x, np.ones(w) / w, mode="same") if len(x) > w else x
    xs = xs - np.mean(xs[w:len(xs) - w] if len(xs) > 2 * w + 1 else xs)
    up = np.flatnonzero((xs[:-1] < 0.0) & (xs[1:] >= 0.0))
    up = up[(up >= w) & (up < len(xs) - w)]
    mask = np.zeros(t.shape, dtype=bool)
    if len(up) >= 2 and (up[-1] - up[0]) >= 0.25 * len(idx):
        mask[idx[up[0]]:idx[up[-1]]] = True
    else:
        mask[idx] = True
    return mask


def steady_state(ts: dict, model, layout, *, t_from_s: float, speed_m_s: float, gravity_m_s2: float,
                 a_nc_m_s2: float = 0.0) -> dict:
    """The steady-state quantities (module docstring) from the rows with ``time_s >= t_from_s``; ``a_nc_m_s2`` the
    unbalanced lateral acceleration of the steady curve (the scale of :data:`STEADY_TOLERANCE`)."""
    t = np.asarray(ts["time_s"])
    n = len(model.wheelsets)
    kappa = float(np.mean(ts["curvature_w1_1_m"][t >= t_from_s - 1e-9]))
    out_s = outward_sign(kappa)
    # the outward total, so that a curve and its mirror image get the same window
    total = -out_s * sum(ts[f"Y_w{j + 1}_right_N"] + ts[f"Y_w{j + 1}_left_N"] for j in range(n))
    sel = averaging_window(t, total, t_from_s)
    part = np.flatnonzero(t >= t_from_s - 1e-9)
    first, second = part[: len(part) // 2], part[len(part) // 2:]
    # wheel order of the recorder: right, left; outer is left in a right-hand curve
    sides = ("left", "right") if kappa > 0 else ("right", "left")
    res = {"sum_Y_N": [], "Y_N": [], "Q_N": [], "YQ": [], "YQ_max": [], "lateral_shift_m": [],
           "angle_of_attack_rad": [], "flange_contact": []}
    drift = []
    for j in range(n):
        fy = ts[f"Y_w{j + 1}_right_N"] + ts[f"Y_w{j + 1}_left_N"]   # rails on the wheelset, track y
        sumY = -out_s * fy                                            # wheelset on the track, outwards
        res["sum_Y_N"].append(float(np.mean(sumY[sel])))
        drift.append(abs(float(np.mean(sumY[second]) - np.mean(sumY[first]))))
        Y, Q, YQ, YQm, fl = {}, {}, {}, {}, {}
        for name, side in zip(SIDES_IN_CURVE, sides):
            # the wheel on its rail towards the field side: -F_y right, +F_y left (F_y: rail on wheel, track y)
            y_field = ts[f"Y_w{j + 1}_{side}_N"] * (-1.0 if side == "right" else 1.0)
            Y[name] = float(np.mean(y_field[sel]))
            Q[name] = float(np.mean(ts[f"Q_w{j + 1}_{side}_N"][sel]))
            YQ[name] = float(np.mean(ts[f"YQ_w{j + 1}_{side}"][sel]))
            YQm[name] = float(np.max(ts[f"YQ_w{j + 1}_{side}"][sel]))
            fl[name] = float(np.mean(ts[f"flange_w{j + 1}_{side}"][sel]))
        res["Y_N"].append(Y)
        res["Q_N"].append(Q)
        res["YQ"].append(YQ)
        res["YQ_max"].append(YQm)
        res["flange_contact"].append(fl)
        res["lateral_shift_m"].append(float(np.mean(out_s * ts[f"y_rel_w{j + 1}_m"][sel])))
        res["angle_of_attack_rad"].append(float(np.mean(out_s * ts[f"yaw_w{j + 1}_rad"][sel])))
    scale = carried_mass_kg(model, gravity_m_s2) * max(abs(float(a_nc_m_s2)), STEADY_A_MIN_M_S2)
    res["steady"] = bool(sum(drift) <= STEADY_TOLERANCE * scale)
    res["steady_drift_N"] = drift
    res["steady_tolerance_N"] = STEADY_TOLERANCE * scale
    res["steady_window_s"] = [float(t[sel][0]), float(t[sel][-1])]
    res["curvature_1_m"] = kappa
    if "guidance_lateral_N" in ts:
        res["guidance_lateral_N"] = float(np.mean(-out_s * ts["guidance_lateral_N"][sel]))
    return res
