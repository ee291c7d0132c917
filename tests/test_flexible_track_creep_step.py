"""The explicit step on the flexible track against the creep damping on the rails' modal mass.

A centred vehicle on perfect straight track carries no net lateral force per wheelset (symmetry). On the flexible
track the lateral creep force acts as a damper c22 = G a b C22 / V between the wheel and the rails, whose lateral
modal mass per wheelset (about 62 kg on the shipped ballasted track, modes to 800 Hz) is ~30 times smaller than the
wheelset's: the fastest decay rate sigma is 2.5e4 1/s at 50 km/h (4.5e3 1/s on the rigid track), and RK44 needs
sigma h <= 2.785 (its stability boundary on the negative real axis). Beyond it the first asymmetry (the moving
window's shift) grows by |R(-sigma h)| per step until the creep force saturates, and the run settles into a steady
net lateral force of ~27 kN per wheelset with status ok. These tests check that the pipeline's default step keeps
the symmetry at 20-300 km/h, that the 0.4 ms step at 50 km/h is warned before the solve naming run.dt_s and the
stable step, and that stable step against the integration itself (brute force with Kalker's linear law, +-10 %).
"""
from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest

from exudyn_wheelrail.simulation.monitor_stability import coupled_damper_rate_1_s
from exudyn_wheelrail.validation import InputWarning

VEHICLE = "manchester_vehicle1"
MODES_HZ = 800.0
#: the runs start a millimetre before the window's first move (the seed of any antisymmetric motion) and end this
#: long after it [s] (at the old 0.4 ms step the false lateral force is there one step after the move)
AFTER_SHIFT_S = 5e-3


def _first_move_start():
    """``(start_s_m, gap_m)``: the leading wheelset's start such that the moving window's first move comes after
    ``gap_m`` of running (the least gap its sleeper grid allows, plus 1 mm): the shift re-projects the rails' modal
    state, which rounds asymmetrically, and seeds an unstable lateral mode."""
    from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle_with_overrides
    from exudyn_wheelrail.track import DEFAULT_TRACK_FILE, TrackParameters
    from exudyn_wheelrail.track.flexible_window import window_length_m, window_margin_m
    params = TrackParameters.from_file(DEFAULT_TRACK_FILE)
    x = np.asarray(load_vehicle_with_overrides(VEHICLE, None).wheelset_x_m(), dtype=float)
    span = float(x.max() - x.min())
    m, d = window_margin_m(params), params.sleeper_spacing_m
    length = window_length_m(params, x, 1)
    eps = 1e-3
    s_rear0 = 10 * d + m + d - eps                  # (s_rear - m) just below a whole number of bays
    # the window moves once the wheelsets' centre is (L + d)/2 past its start (flexible_window.bays_due)
    gap = 0.5 * (length + d) - (m + d - eps + 0.5 * span)
    return s_rear0 + span, gap


def _centred_run(speed_km_h, dt_s=None):
    from exudyn_wheelrail.scenarios.build import build_scenario
    from exudyn_wheelrail.scenarios.run import run_model
    from exudyn_wheelrail.scenarios.spec import validate_scenario
    start, gap = _first_move_start()
    duration = gap / (speed_km_h / 3.6) + AFTER_SHIFT_S
    run = {"duration_s": duration, "solver": "rk44"}
    if dt_s is not None:
        run["dt_s"] = dt_s
    scn = validate_scenario({
        "schema_version": 2, "vehicle": {"name": VEHICLE, "speed_km_h": speed_km_h, "start_s_m": start},
        "run": run, "outputs": {"timeseries": ["Y", "Q"], "plots": False, "criteria": False},
        "flexible_track": {"length_m": "window", "modes_up_to_Hz": MODES_HZ}})
    h = build_scenario(scn)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InputWarning)
        out = run_model(h, progress=False)
    return h, out, [str(w.message) for w in caught if issubclass(w.category, InputWarning)]


def _net_lateral(h, out):
    """Per wheelset (rows) and recorded state (columns) the net lateral force Y_left + Y_right [N] and the
    wheelset's load Q_left + Q_right [N] (track frame)."""
    from exudyn_wheelrail.scenarios.run import scenario_summary
    ts = scenario_summary(h, out, "test").timeseries
    net = np.array([ts[f"Y_w{j}_left_N"] + ts[f"Y_w{j}_right_N"] for j in range(1, 5)])
    Q = np.array([ts[f"Q_w{j}_left_N"] + ts[f"Q_w{j}_right_N"] for j in range(1, 5)])
    return net, Q


@pytest.mark.parametrize("speed_km_h", [20.0, 50.0, 100.0, 200.0, 300.0])
def test_centred_vehicle_on_perfect_flexible_track_carries_no_net_lateral_force(speed_km_h):
    """At the step the pipeline chooses (no run.dt_s: flexible_track.default_step_s), through the window's
    first move and 5 ms beyond it (at the old 0.4 ms step the false state, 27 kN at 50 km/h and 13 kN at 100 km/h,
    is there one step after the move), every wheelset's net lateral force stays at rounding level.

    Bound: the two wheels are mirror images computed by the same operations, so Y_left + Y_right cancels exactly
    except where an operation mixes both sides (the rails' modal sums, the window's least-squares projection);
    each such operation can leave a few ulp of the largest force in it, the wheelset load Q (~108 kN), and the
    stable integration does not amplify them: at most 8 eps Q per step, summed over the run's steps as if they never
    decayed.  (Measured on this machine: 3e-12 N after 2707 steps; the bound is 5e-7 N there; the false state is
    ten orders of magnitude above it.)"""
    from exudyn_wheelrail.scenarios.flexible_track import default_step_s
    h, out, pre = _centred_run(speed_km_h)
    assert h.run.dt_s == default_step_s(speed_km_h / 3.6, MODES_HZ)      # the pipeline chose the step
    assert h.flexible_window.shifts >= 1                                 # the seed happened inside the run
    net, Q = _net_lateral(h, out)
    assert np.all(Q > 0.9 * Q[:, :1])                                    # the wheels stay loaded
    bound = 8.0 * np.finfo(float).eps * Q.max() * h.run.steps
    assert np.abs(net).max() <= bound, (np.abs(net).max(axis=1), bound)
    assert out.status.kind == "ok" and not out.warnings and not pre, (out.status, out.warnings, pre)


@pytest.fixture(scope="module")
def warned_run():
    """A step beyond the creep limit on the rails: 50 km/h at the explicit 0.4 ms step (two steps suffice for the check at t = 0)."""
    from exudyn_wheelrail.scenarios.build import build_scenario
    from exudyn_wheelrail.scenarios.run import run_model
    from exudyn_wheelrail.scenarios.spec import validate_scenario
    start, _ = _first_move_start()
    scn = validate_scenario({
        "schema_version": 2, "vehicle": {"name": VEHICLE, "speed_km_h": 50.0, "start_s_m": start},
        "run": {"duration_s": 8e-4, "solver": "rk44", "dt_s": 4e-4, "record": False},
        "outputs": {"plots": False, "criteria": False},
        "flexible_track": {"length_m": "window", "modes_up_to_Hz": MODES_HZ}})
    h = build_scenario(scn)
    with pytest.warns(InputWarning) as caught:
        out = run_model(h, progress=False)
    return h, out, [str(w.message) for w in caught if issubclass(w.category, InputWarning)]


def test_monitor_warns_for_the_0_4_ms_step_at_50_km_h(warned_run):
    """The run monitor's creep-damping estimate includes the rails' modal mass: the 0.4 ms step at 50 km/h (which
    the contact-stiffness check of the build passes) is warned before the solve, one line naming run.dt_s and a
    stable step below 0.4 ms, and flagged again at the first state in the status and the run's notes."""
    h, out, pre = warned_run
    assert len(pre) == 1 and "\n" not in pre[0]
    assert re.match(r"run\.dt_s = 0\.0004 s: beyond RK44's stability limit of the creep damping on the flexible "
                    r"rails .* use run\.dt_s <= 0\.000\d+ s", pre[0]), pre[0]
    step = [e for e in out.events if e.kind == "step_size"]
    assert step and step[0].time_s == 0.0 and "creep damping" in step[0].detail
    text = out.warnings[0]
    assert "\n" not in text and "creep damping" in text and "use dt_s <=" in text
    assert "(warning: step_size" in out.status.detail
    stable = float(text.split("use dt_s <= ")[1].split(" s")[0])
    assert 0.0 < stable < 4e-4                   # its value against the integration: the brute-force test below


def _brute_force_boundary_run(dt_s):
    """Kalker's linear law (the creep force never saturates: beyond the limit the run diverges) at ``dt_s``, 50 km/h,
    through the window's first move and 10 ms beyond it; returns (status, largest |net Y| [N])."""
    from exudyn_wheelrail.scenarios.build import build_scenario
    from exudyn_wheelrail.scenarios.run import run_model
    from exudyn_wheelrail.scenarios.spec import validate_scenario
    start, gap = _first_move_start()
    scn = validate_scenario({
        "schema_version": 2, "vehicle": {"name": VEHICLE, "speed_km_h": 50.0, "start_s_m": start},
        "contact": {"creep_law": "linear"},
        "run": {"duration_s": gap / (50.0 / 3.6) + 10e-3, "solver": "rk44", "dt_s": dt_s},
        "outputs": {"timeseries": ["Y", "Q"], "plots": False, "criteria": False},
        "flexible_track": {"length_m": "window", "modes_up_to_Hz": MODES_HZ}})
    h = build_scenario(scn)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InputWarning)
        out = run_model(h, progress=False)
    warned = any(issubclass(w.category, InputWarning) and "creep damping" in str(w.message) for w in caught)
    net, _ = _net_lateral(h, out)
    return out.status.kind, float(np.nanmax(np.abs(net))) if net.size else math.inf, warned


def test_monitor_stable_step_against_brute_force(warned_run):
    """The stable step the monitor names against the integration itself (brute force, Kalker's linear law): 10 %
    below it the seeded lateral motion decays (net lateral force at rounding level: the bound of the test above),
    10 % above it it grows without bound (RK44's amplification of the fastest creep mode, |R(-σh)| = 1.5 per step
    at σh = 3.06, reaches a diverged state within the 10 ms).  10 %: the estimate leaves out the tilt of the
    lateral creep force with the contact angle, spin and the rails' coupling between wheelsets (a few %)."""
    h, out, pre = warned_run
    assert pre[0].split("use run.dt_s <= ")[1].split(" s")[0] == out.warnings[0].split("use dt_s <= ")[1].split(
        " s")[0]                                                         # the same estimate before and during
    stable = float(out.warnings[0].split("use dt_s <= ")[1].split(" s")[0])
    kind, force, warned = _brute_force_boundary_run(0.9 * stable)
    steps = math.ceil((_first_move_start()[1] / (50.0 / 3.6) + 10e-3) / (0.9 * stable))
    # the bound of the test above, with the wheelset load rounded up to 120 kN
    assert kind == "ok" and force <= 8.0 * np.finfo(float).eps * 120e3 * steps and not warned, (kind, force)
    kind, force, warned = _brute_force_boundary_run(1.1 * stable)
    assert (kind == "diverged" or force > 1e3) and warned, (kind, force)


def test_coupled_damper_rate_against_the_assembled_coupled_system():
    """The monitor's creep estimate on a structure, ``B = A Aᵀ + H W Hᵀ``, against brute force: the damping matrix
    of the coupled body and modes assembled in full, ``D = Σ c_i d_i d_iᵀ`` with ``d_i = (g_i, -Φᵀ h_i)`` over the
    body's 6 coordinates and 5 mass-normalised modes, and the largest eigenvalue of ``diag(M, 1)^-1/2 D
    diag(M, 1)^-1/2`` by LAPACK (random dampers, body inertia and shapes, fixed seed; both sides are symmetric
    eigenvalue problems of condition ~1e2: 1e-10).  And by hand: one lateral damper through the body's centre on a
    structure with lateral inverse modal mass w has σ = c (1/m + w), the rigid body alone c/m."""
    rng = np.random.default_rng(7)
    n_d, n_m = 4, 5
    c = rng.uniform(1e4, 1e6, n_d)
    g = rng.normal(size=(n_d, 6))
    h = rng.normal(size=(n_d, 3))
    Phi = rng.normal(scale=0.1, size=(3, n_m))
    Q = np.linalg.qr(rng.normal(size=(6, 6)))[0]
    M = Q @ np.diag(rng.uniform(100.0, 2000.0, 6)) @ Q.T
    lam, V = np.linalg.eigh(M)
    Mh = V @ np.diag(lam ** -0.5) @ V.T
    D = np.zeros((6 + n_m, 6 + n_m))
    for i in range(n_d):
        d = np.concatenate([g[i], -Phi.T @ h[i]])
        D += c[i] * np.outer(d, d)
    S = np.eye(6 + n_m)
    S[:6, :6] = Mh
    brute = np.linalg.eigvalsh(S @ D @ S)[-1]
    sc = np.sqrt(c)[:, None]
    assert coupled_damper_rate_1_s(sc * g, sc * h, Mh, Phi @ Phi.T) == pytest.approx(brute, rel=1e-10)

    m, w, c0 = 1813.0, 1.0 / 62.0, 3.0e5
    g1 = np.array([[0.0, 1.0, 0.0, 0.0, 0.0, 0.0]]) * math.sqrt(c0)
    h1 = np.array([[1.0, 0.0, 0.0]]) * math.sqrt(c0)
    Mh1 = np.diag([m ** -0.5] * 3 + [0.01] * 3)
    W1 = np.diag([w, 0.0, 0.0])
    assert coupled_damper_rate_1_s(g1, h1, Mh1, W1) == pytest.approx(c0 * (1.0 / m + w), rel=1e-12)
    assert coupled_damper_rate_1_s(g1, h1, Mh1, 0.0 * W1) == pytest.approx(c0 / m, rel=1e-12)
