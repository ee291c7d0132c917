"""Stress (c) flange impact and (d) lift-off and re-contact, one wheelset of Manchester vehicle 1 (RK44).

(c) A lateral force pulse (120 kN, sin², 50 ms, at the axle centre) throws the wheelset at 100 km/h against the
    right rail: the flange contact is reached (contact angle > 0.8 rad; a convex contact's angle — wheel and rail
    normals opposite — at most the flank's steepest angle plus the rail inclination and the wheelset roll; a
    concave-search contact takes the rail normal at the normal foot and may lean further), forces stay finite,
    the left wheel stays on its tread, the primary springs bring the wheelset back and nothing derails.
(d) A 2 mm, 0.5 m raised-cosine bump of both rails at 200 km/h: the rails drop away faster than the wheel load can
    accelerate the wheelset (V² H/2 (2π/L)² = 4.9e2 m/s² > (2 x 45.65 kN + m g)/m = 60 m/s²), the wheels lift and
    land.  Reference: the same bounce as a one-degree-of-freedom model, m z̈ = m a - 2 cos γ K (δ0 + z - z_r)^1.5
    (K, δ0, γ of the static contact from the kernel, the rail z_r(V t) exact), integrated by scipy to 1e-10:
    the monitor's first lift-off starts within 0.5 ms of it and lasts as long within 5 %."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from stress_models import PAIR, build, finite_history, run

from exudyn_wheelrail.contact import WheelsetContact
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.multibody import SampledIrregularity
from exudyn_wheelrail.multibody import connector as C

MASS_KG = 1813.0
DEAD_LOAD_PER_SIDE_N = 45653.29


def test_flange_impact_from_a_lateral_force_pulse():
    F, t0, T = 120e3, 0.02, 0.05

    def pulse(t):
        return F * math.sin(math.pi * (t - t0) / T) ** 2 if t0 <= t <= t0 + T else 0.0

    m = build(100 / 3.6, lateral_force=pulse)
    flange_loaded = []
    convex_excess = []          # convex contact angle minus its geometric bound (normals opposite at the point)
    bound0 = m.monitor.flank_angle_rad + math.atan(1 / 40)

    def after_check(mbs, t):
        r = m.contact.results
        flange_loaded.append(bool(r[0, K.SLOT_FLANGE, C.RES_STATUS] > 0 and r[0, K.SLOT_FLANGE, C.RES_N] > 0))
        roll = abs(float(m.contact.wheelset_rail_pose()[0, 2])) if hasattr(m.contact, "wheelset_rail_pose") \
            else abs(float(m.contact._side_poses[0, 2]))
        convex = r[:, :, C.RES_STATUS] == K.STATUS_CONVEX
        if convex.any():
            convex_excess.append(float(np.max(r[convex, C.RES_GAMMA])) - (bound0 + roll))
        return True

    m.monitor.attach(m.mbs, user_function=after_check, rk44_dt_s=2.5e-4)
    status, t_end = run(m, 0.3, 2.5e-4)
    assert status.kind == "completed", str(status)
    assert finite_history(m.monitor)
    right, left = m.monitor.wheels
    h = m.monitor.history()
    assert 0.8 < right.max_contact_angle_rad < 0.5 * math.pi
    assert max(convex_excess) < 1e-3
    assert left.max_contact_angle_rad < 0.2
    assert any(flange_loaded)
    assert right.max_normal_force_N > 2 * 54.5e3 and math.isfinite(right.max_normal_force_N)
    assert abs(h["lateral_m"][-1, 0]) < 3e-3                      # back towards the centre after the pulse
    assert not m.monitor.events_of("derailment")


def _bump(height_m, length_m, s0_m):
    s = np.arange(-5.0, 60.0, 0.01)
    u = np.clip((s - s0_m) / length_m, 0.0, 1.0)
    return SampledIrregularity(s, 0.0 * s, -0.5 * height_m * (1.0 - np.cos(2 * np.pi * u)))   # z down: a rise


def _reference_lift_offs(height_m, length_m, s0_m, V, dz, t_end):
    """Lift-off intervals (start, duration) of the one-degree-of-freedom bounce model (module docstring)."""
    kc = WheelsetContact(PAIR, 1, global_search=True)
    o = kc.evaluate(np.array([[0.0, -PAIR.r0_m + dz, 0.0]]))[0, 0]
    d0, N0, gamma = o[K.F_PENETRATION], o[K.F_NORMAL_FORCE], o[K.F_CONTACT_ANGLE]
    Kh = N0 / d0 ** 1.5
    a = (2 * DEAD_LOAD_PER_SIDE_N + MASS_KG * 9.81) / MASS_KG
    assert 2 * N0 * math.cos(gamma) == pytest.approx(MASS_KG * a, rel=1e-3)      # in equilibrium at the start

    def z_rail(t):
        u = min(max((V * t - s0_m) / length_m, 0.0), 1.0)
        return -0.5 * height_m * (1.0 - math.cos(2 * math.pi * u))

    def f(t, y):
        d = d0 + y[0] - z_rail(t)
        return [y[1], a - 2 * math.cos(gamma) * Kh * max(d, 0.0) ** 1.5 / MASS_KG]

    ts = np.arange(0.0, t_end, 1e-5)
    sol = solve_ivp(f, (0.0, t_end), [0.0, 0.0], t_eval=ts, rtol=1e-10, atol=1e-13, max_step=2e-5)
    lifted = d0 + sol.y[0] - np.array([z_rail(t) for t in ts]) <= 0.0
    edges = np.flatnonzero(np.diff(lifted.astype(int))) + 1
    return [(ts[edges[i]], ts[edges[i + 1]] - ts[edges[i]]) for i in range(0, len(edges) - 1, 2)]


def test_lift_off_and_re_contact_over_a_vertical_bump():
    V, H, L, s0 = 200 / 3.6, 2e-3, 0.5, 2.0
    assert V ** 2 * 0.5 * H * (2 * math.pi / L) ** 2 > 5 * 60.0         # the rails fall away faster than 60 m/s²
    t_end = s0 / V + 0.06
    m = build(V, irregularity=_bump(H, L, s0))
    status, t_stop = run(m, t_end, 1e-4)
    assert status.kind == "completed", str(status)
    assert finite_history(m.monitor)
    ref = _reference_lift_offs(H, L, s0, V, m.dz, t_end)
    assert ref, "the reference bounce model does not lift"
    t_ref, dur_ref = ref[0]
    for wheel in m.monitor.wheels:                        # both rails carry the bump: both wheels lift together
        lift = wheel.lift_offs[0]
        assert lift.end_s is not None                     # it landed (re-contact)
        assert lift.start_s == pytest.approx(t_ref, abs=5e-4)
        assert lift.duration_s() == pytest.approx(dur_ref, rel=0.05)
        assert lift.peak > 1e-3                           # a gap of millimetres in the flight
        assert 54e3 < wheel.max_normal_force_N < 1e8      # the landing impact: large, finite
    r0, l0 = (w.lift_offs[0] for w in m.monitor.wheels)
    # mirror-symmetric model and excitation: both wheels lift and land at the same step; the events are detected on
    # the 0.1 ms step grid, so a rounding-level asymmetry at a threshold crossing may move one of them by a step
    dt = 1e-4
    assert abs(r0.start_s - l0.start_s) <= 1.01 * dt and abs(r0.end_s - l0.end_s) <= 1.01 * dt
    assert not m.monitor.events_of("derailment") and not m.monitor.events_of("invalid_state")
