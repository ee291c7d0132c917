r"""The flexible deck of a scenario (``[structure]``): its lateral support motion, the deck columns recorded beyond
the recorder's mid-span ones, and the deck's part of the summary.

Support motion (``[structure.support_motion]``)
-----------------------------------------------
:func:`support_motion` makes the smooth harmonic burst of :class:`~exudyn_wheelrail.structures.support_motion.
SmoothHarmonicSupportMotion` — a lateral ground displacement ``y_g = Y w(τ) sin 2πfτ`` of all supports **and of the
track off the deck** (synchronous), C² quintic ramps of ``ramp_cycles`` periods, ``max |ÿ_g|`` over the burst equal
to ``peak_acceleration_m_s2`` — entered into the deck in the relative-motion formulation (effective modal load
``-Γ ÿ_g``; the rails at ``y_g + Φ_y q``).  ``plateau_cycles = "auto"`` keeps the plateau to the end of the run.

Recorded columns (:func:`deck_probes`; span i = 1, 2, …; wheelset j = 1 leading)
---------------------------------------------------------------------------------
From the modal state at every recorded state (``q̈ = Q − diag(2ζω) q̇ − diag(ω²) q − Γ ÿ_g``, the connector's
generalized forces ``Q`` of the monitor's evaluation of that state):

* ``deck_acceleration`` — ``deck_acceleration_s<i>_p<k>_m_s2``: vertical acceleration (+ down) on the track centre
  line at the nine points ``x = k L/10`` (k = 1 … 9) of span i: the points of the EN 1990 deck-acceleration check;
* ``deck_wheelsets`` — ``deck_deflection_w<j>_m``: vertical deflection (+ down) of the deck under wheelset j (the
  connector's deck state of that evaluation; 0 off the deck);
* ``deck_lateral`` — ``deck_mid_lateral_rel_s<i>_m``: lateral displacement (+ right) of the rails' centre line at
  rail top at mid-span, relative to the supports (``Φ_y q``); ``deck_mid_lateral_acceleration_s<i>_m_s2``: its
  absolute lateral acceleration ``ÿ_g + Φ_y q̈``; with a support motion ``ground_lateral_m`` and
  ``ground_lateral_acceleration_m_s2`` (``y_g``, ``ÿ_g``).

Summary (``summary["deck"]``, :func:`deck_summary`)
---------------------------------------------------
Per span: the largest mid-span deflection and accelerations; the **quasi-static reference** (a simply supported
span, ``continuous = false``: the mid-span influence line of the static axle loads, ``P a (3L² − 4a²)/(48 EI_y)``
for a load at ``a ≤ L/2`` from the nearer support, summed over the axles at their places ``s_start + V t + x_j``)
and the dynamic amplification over it; the **moving-force reference** (the deck alone under the static axle loads
moving at V, :func:`~.moving_forces.simulate_moving_forces`, same modes and time step: the ratio of
the coupled deflection to it is the vehicle–bridge interaction).  The **EN 1990 deck-acceleration check**
(EN 1990:2002/A1:2005, A2.4.4.2.1(4)P): the peak vertical deck acceleration over the nine points of every span,
with the modes up to the EN 1990 cut-off max(30 Hz, 1.5 f1, f3) (:func:`en1990_cutoff_Hz`), against
:data:`EN1990_DECK_ACCELERATION_LIMITS_M_S2` — 3.5 m/s² for ballasted track, 5 m/s² for direct fastening
(``structure.track_form`` picks the verdict; both are reported).  A single vehicle is not the HSLM load model of
EN 1991-2: the check shows the coupled model at work, not a design verification.  With a support motion, per span
the lateral reference ``5 m a_p L⁴/(384 EI_z) · 1/(1 − r²)`` (the beam under its uniform inertia load ``m a_p``,
amplified as a single mode at ``r = f/f_lat,1`` with ``f_lat,1 = π/(2L²) √(EI_z/m)``; simply supported spans) beside
the recorded relative mid-span motion.
"""
from __future__ import annotations

import inspect
import math

import numpy as np

from ..standards import EN1990_DECK_ACCELERATION_LIMITS_M_S2, TRACK_FORMS
from ..structures.beam import DeckSection
from ..structures.load_models import flexural_rigidity_Nm2
from ..structures.support_motion import SmoothHarmonicSupportMotion
from .defaults import LATERAL_EI_RATIO

__all__ = ["DECK_GROUPS", "TRACK_FORMS", "EN1990_DECK_ACCELERATION_LIMITS_M_S2", "CHECK_POINTS_X_OVER_L",
           "PLATEAU_AUTO", "support_motion_default", "en1990_cutoff_Hz", "cutoff_of_frequencies_Hz", "support_motion",
           "deck_probes",
           "deck_summary", "deck_scalars", "bending_stiffness_Nm2", "structure_section"]

#: column groups of the deck beyond the recorder's ``deck`` group (module docstring), in the order they are written
DECK_GROUPS = ("deck_acceleration", "deck_wheelsets", "deck_lateral")
# EN1990_DECK_ACCELERATION_LIMITS_M_S2 (EN 1990 A2.4.4.2.1(4)P, by track form) and TRACK_FORMS are declared in
# exudyn_wheelrail.standards.
#: the check points along each span (x/L): L/10 … 9L/10
CHECK_POINTS_X_OVER_L = tuple(k / 10.0 for k in range(1, 10))
#: ``plateau_cycles = PLATEAU_AUTO``: the burst's plateau lasts to the end of the run
PLATEAU_AUTO = "auto"


def support_motion_default(name: str):
    """The default of a :class:`~exudyn_wheelrail.structures.support_motion.SmoothHarmonicSupportMotion` option
    (declared there)."""
    return inspect.signature(SmoothHarmonicSupportMotion.__init__).parameters[name].default


def bending_stiffness_Nm2(span_m: float, mass_kg_m: float, f1_Hz: float, lateral_f1_Hz=None) -> tuple:
    """``(EI_y, EI_z)`` of a deck of mass ``m`` per length whose simply supported span ``L`` has the first vertical
    bending frequency ``f1``: ``EI_y = m (2 L² f1/π)²``; ``EI_z`` the same of ``lateral_f1_Hz``, else
    :data:`~.defaults.LATERAL_EI_RATIO` ``EI_y`` (the bridge crossing's deck and a scenario's deck given by its
    frequencies)."""
    EI = flexural_rigidity_Nm2(span_m, mass_kg_m, f1_Hz)
    if lateral_f1_Hz is None:
        return EI, LATERAL_EI_RATIO * EI
    return EI, flexural_rigidity_Nm2(span_m, mass_kg_m, lateral_f1_Hz)


def structure_section(st: dict) -> DeckSection:
    """The section of a normalised ``[structure]``: its ``section``, or the bending-only section of its
    ``mass_kg_m`` and ``f1_Hz`` (and ``lateral_f1_Hz``) for its first span
    (:func:`bending_stiffness_Nm2`, :meth:`~exudyn_wheelrail.structures.beam.DeckSection.bending_only`)."""
    if st.get("section") is not None:
        return DeckSection(**st["section"])
    EI_y, EI_z = bending_stiffness_Nm2(st["spans_m"][0], st["mass_kg_m"], st["f1_Hz"], st.get("lateral_f1_Hz"))
    return DeckSection.bending_only(st["mass_kg_m"], EI_y, EI_z)


def en1990_cutoff_Hz(spans_m, sec: DeckSection) -> float:
    """EN 1990 A2.4.4.2.1(4)P: modes up to max(30 Hz, 1.5 f1, f3), the largest over the spans, with the simply
    supported Euler–Bernoulli bending frequencies ``f_n = n²π/(2L²) √(EI_y/m)`` of each span (section ``sec``)."""
    return max(cutoff_of_frequencies_Hz(sec.vertical_frequency_Hz(L), sec.vertical_frequency_Hz(L, 3))
               for L in spans_m)


def cutoff_of_frequencies_Hz(f1_Hz: float, f3_Hz: float) -> float:
    """EN 1990 A2.4.4.2.1(4)P's cut-off ``max(30 Hz, 1.5 f1, f3)`` of a deck's first and third vertical
    frequencies."""
    return max(30.0, 1.5 * float(f1_Hz), float(f3_Hz))


def support_motion(sm: dict, end_time_s: float):
    """The :class:`~exudyn_wheelrail.structures.support_motion.SmoothHarmonicSupportMotion` of a normalised
    ``[structure.support_motion]`` table for a run ending at ``end_time_s`` (``plateau_cycles = "auto"``: the
    plateau lasts until one period past the end of the run)."""
    f = sm["frequency_Hz"]
    plateau = sm["plateau_cycles"]
    if plateau == PLATEAU_AUTO:
        plateau = max(0, math.ceil((end_time_s - sm["start_s"]) * f - sm["ramp_cycles"] + 1.0))
    return SmoothHarmonicSupportMotion(sm["peak_acceleration_m_s2"], f, ramp_cycles=sm["ramp_cycles"],
                                       plateau_cycles=plateau, start_s=sm["start_s"])


def _span_starts(spans_m, start_m) -> np.ndarray:
    return start_m + np.concatenate(([0.0], np.cumsum(spans_m)[:-1]))


class _DeckColumns:
    """Recorder probe of the ``deck_acceleration``, ``deck_wheelsets`` and ``deck_lateral`` groups (module
    docstring)."""

    def __init__(self, contact, bridge, modes, spans_m, start_m, n_wheelsets: int):
        self.c, self.bridge = contact, bridge
        x0 = _span_starts(spans_m, start_m)
        s_pts = np.array([x + f * L for x, L in zip(x0, spans_m) for f in CHECK_POINTS_X_OVER_L])
        s_mid = x0 + 0.5 * np.asarray(spans_m)
        self.phi_pts = modes.shape_at(s_pts)[:, 1, :]                     # z rows at the check points
        self.phi_mid_y = modes.shape_at(s_mid)[:, 0, :]                   # y rows at mid-span
        self.w2 = np.diag(modes.modal_stiffness()).copy()
        self.d = np.diag(modes.modal_damping()).copy()
        load = bridge.support_load
        self.gamma = None if load is None else np.asarray(load.gamma, dtype=float).copy()
        self.n_pts, self.n_ws, self.n_sp = len(s_pts), int(n_wheelsets), len(s_mid)
        self.columns = ([("deck_acceleration", f"deck_acceleration_s{i + 1}_p{k + 1}_m_s2")
                         for i in range(self.n_sp) for k in range(len(CHECK_POINTS_X_OVER_L))]
                        + [("deck_wheelsets", f"deck_deflection_w{j + 1}_m") for j in range(self.n_ws)]
                        + [("deck_lateral", f"deck_mid_lateral_rel_s{i + 1}_m") for i in range(self.n_sp)]
                        + [("deck_lateral", f"deck_mid_lateral_acceleration_s{i + 1}_m_s2")
                           for i in range(self.n_sp)])
        if self.gamma is not None:
            self.columns += [("deck_lateral", "ground_lateral_m"), ("deck_lateral", "ground_lateral_acceleration_m_s2")]

    def fill(self, mbs, t, out):
        q, q_t = self.bridge.coordinates(mbs)
        q_tt = self.c.modal_forces_N() - self.w2 * q - self.d * q_t         # modal equations, M = I
        y_g, _, a_g = self.bridge.ground_state(t)
        if self.gamma is not None:
            q_tt -= self.gamma * a_g                                          # effective load of the support motion
        k = self.n_pts
        out[:k] = self.phi_pts @ q_tt
        out[k:k + self.n_ws] = self.c.deck_state()[:, 1]
        k += self.n_ws
        out[k:k + self.n_sp] = self.phi_mid_y @ q
        out[k + self.n_sp:k + 2 * self.n_sp] = a_g + self.phi_mid_y @ q_tt
        if self.gamma is not None:
            out[k + 2 * self.n_sp:k + 2 * self.n_sp + 2] = (y_g, a_g)


def deck_probes(*, contact, bridge, modes, spans_m, start_m, n_wheelsets: int) -> list:
    """The recorder probes of the deck columns (module docstring); call after the support motion is added."""
    return [_DeckColumns(contact, bridge, modes, spans_m, start_m, n_wheelsets)]


# ================================================================================================== summary
def _max_abs(v) -> float | None:
    v = np.asarray(v, dtype=float)
    return float(np.nanmax(np.abs(v))) if v.size and np.isfinite(v).any() else None


def _axle_loads_N(h) -> np.ndarray:
    return np.asarray(h.model.load_path.wheel, dtype=float).sum(axis=1)         # per wheelset: both wheels


def _quasi_static_mid_span_m(h, t, x0: float, L: float, EI: float) -> np.ndarray:
    """Mid-span deflection of a simply supported span under the static axle loads at their places at times t."""
    x_ws = np.asarray(h.vehicle.wheelset_x_m(), dtype=float)
    a = h.model.track_distance_m(x_ws[None, :], t[:, None]) - x0                  # (n_t, n_ws) along the span
    near = np.minimum(a, L - a)
    w = _axle_loads_N(h) * near * (3.0 * L * L - 4.0 * near * near) / (48.0 * EI)
    return np.where((a > 0.0) & (a < L), w, 0.0).sum(axis=1)


def _moving_force_mid_span_m(h, t) -> np.ndarray:
    """Mid-span deflection of every span (n_t, n_spans) of the deck alone under the static axle loads moving at V."""
    from .moving_forces import simulate_moving_forces   # here: the scenario check (spec) imports this module
    st = h.scenario["structure"]
    x_ws = np.asarray(h.vehicle.wheelset_x_m(), dtype=float)
    dt = float(h.run.dt_s)
    t_mf, q, _ = simulate_moving_forces(h.modes, x_m=x_ws, forces_N=[[0.0, p, 0.0] for p in _axle_loads_N(h)],
                                        speed_m_s=h.speed_m_s, s_start_m=h.model.s_start_m,
                                        end_time_s=round(float(t[-1]) / dt) * dt, dt_s=dt)
    s_mid = _span_starts(st["spans_m"], st["start_m"]) + 0.5 * np.asarray(st["spans_m"])
    w = q @ h.modes.shape_at(s_mid)[:, 1, :].T
    return np.column_stack([np.interp(t, t_mf, w[:, i]) for i in range(len(s_mid))])   # at the recorded times


def deck_summary(h, ts: dict) -> tuple[dict, list]:
    """``summary["deck"]`` (module docstring) of a run with a structure and a time series; and notes."""
    st = h.scenario["structure"]
    sec = structure_section(st)
    t = ts["time_s"]
    notes = []
    simply_supported = not st["continuous"]
    cut_en1990 = en1990_cutoff_Hz(st["spans_m"], sec)
    to_cutoff = st["modes_cutoff_Hz"] == "en1990" or float(st["modes_cutoff_Hz"]) >= cut_en1990
    moving = _moving_force_mid_span_m(h, t) if len(t) > 1 else None
    motion = h.support_motion
    spans, peak = [], (None, None, None)
    for i, (x0, L) in enumerate(zip(_span_starts(st["spans_m"], st["start_m"]), st["spans_m"])):
        w = ts[f"deck_mid_deflection_s{i + 1}_m"]
        w_max = float(np.max(w))
        acc = {k + 1: _max_abs(ts[f"deck_acceleration_s{i + 1}_p{k + 1}_m_s2"])
               for k in range(len(CHECK_POINTS_X_OVER_L))}
        k_max = max(acc, key=lambda k: acc[k])
        if peak[0] is None or acc[k_max] > peak[0]:
            peak = (acc[k_max], i + 1, k_max)
        sp = {"span": i + 1, "start_m": float(x0), "length_m": float(L),
              "max_mid_span_deflection_m": w_max,
              "max_abs_mid_span_acceleration_m_s2": _max_abs(ts[f"deck_mid_acceleration_s{i + 1}_m_s2"]),
              "max_abs_acceleration_check_points_m_s2": acc[k_max],
              "check_point_of_max": f"p{k_max} (x = {CHECK_POINTS_X_OVER_L[k_max - 1]:g} L)",
              "quasi_static_max_mid_span_deflection_m": None, "dynamic_amplification_mid_span": None,
              "moving_force_max_mid_span_deflection_m": None, "coupled_over_moving_force": None,
              "max_abs_mid_lateral_rel_m": _max_abs(ts[f"deck_mid_lateral_rel_s{i + 1}_m"]),
              "max_abs_mid_lateral_acceleration_m_s2": _max_abs(ts[f"deck_mid_lateral_acceleration_s{i + 1}_m_s2"]),
              "first_vertical_frequency_euler_bernoulli_Hz": sec.vertical_frequency_Hz(L),
              "first_lateral_frequency_euler_bernoulli_Hz": sec.lateral_frequency_Hz(L)}
        if simply_supported:
            qs = float(np.max(_quasi_static_mid_span_m(h, t, x0, L, sec.EI_y_Nm2)))
            sp["quasi_static_max_mid_span_deflection_m"] = qs
            sp["dynamic_amplification_mid_span"] = w_max / qs if qs > 0.0 else None
        if moving is not None:
            mf = float(np.nanmax(moving[:, i]))
            sp["moving_force_max_mid_span_deflection_m"] = mf
            sp["coupled_over_moving_force"] = w_max / mf if mf > 0.0 else None
        if motion is not None and simply_supported:
            r = motion.frequency_Hz / sec.lateral_frequency_Hz(L)
            qs_lat = 5.0 * sec.m_kg_m * motion.peak_acceleration_m_s2 * L ** 4 / (384.0 * sec.EI_z_Nm2)
            sp["support_motion_quasi_static_mid_lateral_m"] = qs_lat
            sp["support_motion_amplification_single_mode"] = 1.0 / (1.0 - r * r) if r < 1.0 else None
        spans.append(sp)
    if not simply_supported:
        notes.append("continuous deck: the quasi-static influence-line reference of a simply supported span is not "
                     "evaluated (deck.spans.*.quasi_static_max_mid_span_deflection_m = null)")
    limit = EN1990_DECK_ACCELERATION_LIMITS_M_S2[st["track_form"]]
    check = {"rule": "EN 1990/A1 A2.4.4.2.1(4)P: peak vertical deck acceleration, modes up to max(30 Hz, 1.5 f1, f3); "
                     "limits 3.5 m/s2 ballasted track, 5 m/s2 direct fastening",
             "peak_m_s2": peak[0], "span": peak[1], "check_point": f"p{peak[2]}",
             "track_form": st["track_form"], "limit_m_s2": limit, "passed": bool(peak[0] <= limit),
             "ballasted_limit_m_s2": EN1990_DECK_ACCELERATION_LIMITS_M_S2["ballasted"],
             "ballasted_ok": bool(peak[0] <= EN1990_DECK_ACCELERATION_LIMITS_M_S2["ballasted"]),
             "direct_fastening_limit_m_s2": EN1990_DECK_ACCELERATION_LIMITS_M_S2["direct_fastening"],
             "direct_fastening_ok": bool(peak[0] <= EN1990_DECK_ACCELERATION_LIMITS_M_S2["direct_fastening"]),
             "en1990_cutoff_Hz": cut_en1990, "modes_to_en1990_cutoff": bool(to_cutoff),
             "note": "one vehicle, not the HSLM load model of EN 1991-2: illustrative, not a design check"}
    if not to_cutoff:
        notes.append(f"structure.modes_cutoff_Hz = {st['modes_cutoff_Hz']} Hz is below the EN 1990 cut-off "
                     f"{cut_en1990:.4g} Hz: the deck-acceleration check lacks modes the rule includes")
    n_ws = len(h.model.wheelsets)
    out = {"spans": spans, "EN1990_A2_deck_acceleration": check,
           "max_deflection_under_wheelsets_m": {f"w{j + 1}": float(np.max(ts[f"deck_deflection_w{j + 1}_m"]))
                                                for j in range(n_ws)},
           "references": {
               "quasi_static": "simply supported span: mid-span influence line of the static axle loads (lever-rule "
                               "load path), P a (3L^2 - 4a^2)/(48 EI_y), at s_start + V t + x_j",
               "moving_force": "the deck alone under the static axle loads moving at V (structures."
                               "simulate_moving_forces, same modes and time step): coupled / moving force is the "
                               "vehicle-bridge interaction"},
           "support_motion": None}
    if motion is not None:
        out["support_motion"] = {
            "record": "sine burst of the ground displacement with C2 quintic ramps (structures.support_motion."
                      "SmoothHarmonicSupportMotion), all supports and the track off the deck together (synchronous)",
            "peak_acceleration_m_s2": motion.peak_acceleration_m_s2, "frequency_Hz": motion.frequency_Hz,
            "ramp_cycles": motion.ramp_cycles, "plateau_cycles": motion.plateau_cycles, "start_s": motion.start_s,
            "ramp_s": motion.ramp_s, "plateau_acceleration_m_s2": motion.plateau_acceleration_m_s2,
            "displacement_amplitude_m": motion.amplitude_m,
            "max_abs_ground_displacement_m": _max_abs(ts["ground_lateral_m"]),
            "max_abs_ground_acceleration_m_s2": _max_abs(ts["ground_lateral_acceleration_m_s2"]),
            "lateral_reference": "simply supported span: 5 m a_p L^4/(384 EI_z) (uniform inertia load m a_p) times "
                                 "1/(1 - r^2), r = f/f_lat1 (first lateral mode, Euler-Bernoulli)"}
    return out, notes


def deck_scalars(deck: dict) -> dict:
    """The deck's scalar results for a sweep's table (``deck.*``)."""
    spans = deck["spans"]
    en = deck["EN1990_A2_deck_acceleration"]

    def largest(key):
        vals = [s[key] for s in spans if s.get(key) is not None]
        return max(vals) if vals else None

    return {"deck.en1990_peak_acceleration_m_s2": en["peak_m_s2"], "deck.en1990_passed": en["passed"],
            "deck.max_mid_span_deflection_m": largest("max_mid_span_deflection_m"),
            "deck.dynamic_amplification_mid_span": largest("dynamic_amplification_mid_span"),
            "deck.coupled_over_moving_force": largest("coupled_over_moving_force"),
            "deck.max_deflection_under_wheelsets_m": max(deck["max_deflection_under_wheelsets_m"].values()),
            "deck.max_abs_mid_lateral_rel_m": largest("max_abs_mid_lateral_rel_m")}
