"""Quasi-static wheelset contact (exudyn_wheelrail.analysis.quasi_static) and the Manchester A-2.2 example.

Independent references: Kalker's linear theory (C11 from Kalker's Table E.3) with rolling radii from the closed-form
contact of a cone on a circular crown; mirror symmetry; equilibrium sums and the axle moment recomputed here from
the returned forces; the yaw-free rigid geometry sweep; Nadal's flange-climbing limit; the first-order yaw lead.
"""
import csv
import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from exudyn_wheelrail.analysis.geometry_functions import contact_geometry_sweep
from exudyn_wheelrail.analysis.quasi_static import (CREEP_LAWS, QuasiStaticError, creep_law_by_name,
                                                    solve_quasi_static)
from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
from exudyn_wheelrail.contact.creepage import wheelset_axis
from exudyn_wheelrail.creep import fastsim, kalker_coefficients
from exudyn_wheelrail.profiles import RailProfile, WheelProfile

G, NU = 82e9, 0.28
E = 2 * G * (1 + NU)
Q, V, MU = 10e3, 2.0, 0.3
EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "manchester_a22.py"


def make_contact(pair):
    return WheelsetContact(pair, global_search=True, E_wheel_Pa=E, nu_wheel=NU, E_rail_Pa=E, nu_rail=NU)


@pytest.fixture(scope="module")
def s1002():
    pair = WheelRailPair("S1002", "UIC60", gauge_m=1.435, inclination="1/40", back_to_back_m=1.360, r0_m=0.46)
    return pair, make_contact(pair)


def solve(contact, y, yaw=None, **kw):
    kw.setdefault("mu", MU)
    return solve_quasi_static(contact, y, 2.4 * y if yaw is None else yaw, Q, V, shear_modulus_Pa=G, poisson=NU,
                              **kw)


def axle_moment(res):
    """Moment about the axle of the creep forces and spin moments, recomputed from the returned points."""
    centre = np.array([0.0, res.y_m, res.z_m])
    e_a = wheelset_axis(res.roll_rad, res.yaw_rad)
    total = 0.0
    for p in res.points:
        f = p.frame_in_track
        tangential = p.Fx_N * f[0] + p.Fy_N * f[1]
        total += np.dot(np.cross(p.p_contact_in_track - centre, tangential) + p.Mz_Nm * f[2], e_a)
    return total


# ---- symmetry and equilibrium (S1002 / UIC60 1:40) -----------------------------------------------------------------
def test_centred_wheelset_is_symmetric(s1002):
    _, contact = s1002
    res = solve(contact, 0.0, 0.0)
    assert res.converged, res.message
    r = {p.side: p for p in res.points}
    assert sorted(r) == ["left", "right"] and len(res.points) == 2
    right, left = r["right"], r["left"]
    assert right.normal_force_N == pytest.approx(left.normal_force_N, rel=1e-9)
    assert right.Fx_N == pytest.approx(left.Fx_N, abs=1e-6)
    assert right.Fy_N == pytest.approx(-left.Fy_N, rel=1e-9)          # y_c points right on both: mirrored
    assert right.Mz_Nm == pytest.approx(-left.Mz_Nm, rel=1e-9)
    assert right.phi_per_m == pytest.approx(-left.phi_per_m, rel=1e-9) and right.phi_per_m < 0
    assert res.roll_rad == pytest.approx(0.0, abs=1e-12)
    # no net lateral force on the wheelset; each wheel carries Q
    assert res.force_on_wheelset_in_track()[1] == pytest.approx(0.0, abs=1e-6 * Q)
    assert res.vertical_support_N("right") == pytest.approx(Q, abs=1e-6 * Q)
    assert res.vertical_support_N("left") == pytest.approx(Q, abs=1e-6 * Q)
    # the spin of the 1:40 contact pushes each wheel outwards (towards its field side)
    assert right.Fy_N > 0 > left.Fy_N


@pytest.mark.parametrize("y", [0.002, 0.0055, 0.007, 0.010])
def test_vertical_equilibrium_and_free_rolling(s1002, y):
    _, contact = s1002
    res = solve(contact, y)
    assert res.converged, res.message
    for side in ("right", "left"):
        # upward components of the whole contact forces (normal + creep) on each wheel: the wheel load, to 1e-6 Q
        assert res.vertical_support_N(side) == pytest.approx(Q, abs=1e-6 * Q)
    # free rolling: the moment about the axle of all creep forces, recomputed here, vanishes (1e-6 Q r0)
    assert axle_moment(res) == pytest.approx(0.0, abs=1e-6 * Q * 0.46)
    assert res.residual_moment_Nm == pytest.approx(axle_moment(res), abs=1e-9)
    # yaw enters the kinematics: eta = -tan(yaw)/cos(g) to first order (free rolling, Kalker's rolling speed).
    # Derivation: V e_x . y_c / V with x_c the wheel circle's tangent at the lead angle theta ~ tan(yaw) tan(g):
    # -sin(yaw) cos(g) - sin(theta) sin(g) = -yaw (cos g + tan g sin g) = -yaw / cos g (the wheel surface at the
    # leading contact moves down, along -y_c's vertical part)
    for p in res.points:
        g = p.contact_angle_rad
        assert p.eta == pytest.approx(-math.tan(res.yaw_rad) / math.cos(g),
                                      rel=0.01 + 2 * abs(p.xi) + abs(res.roll_rad))
    flange = [p for p in res.points if p.region == "flange"]
    if flange:
        f = flange[0]
        # the creep force's vertical component is needed: the normal force alone does not carry the load
        assert abs(f.normal_force_N * math.cos(f.contact_angle_rad) - Q) > 1e3
        # saturation bound
        assert math.hypot(f.Fx_N, f.Fy_N) <= MU * f.normal_force_N * (1 + 1e-9)


def test_prescribed_pitch_rate_and_bad_input(s1002):
    _, contact = s1002
    res = solve(contact, 0.003, pitch_rate_rad_s=-V / 0.46)
    assert res.converged and not res.free_rolling
    # the rate given and its negation: exact
    assert res.pitch_rate_rad_s == -V / 0.46 and res.spin_speed_rad_s == V / 0.46
    assert abs(res.residual_moment_Nm) > 1.0                  # not free rolling: a driving/braking moment remains
    with pytest.raises(ValueError, match="global_search"):
        solve_quasi_static(WheelsetContact(contact.pair), 0.0, 0.0, Q, V, shear_modulus_Pa=G, poisson=NU)
    with pytest.raises(ValueError, match="wheel_load_N"):
        solve_quasi_static(contact, 0.0, 0.0, -Q, V, shear_modulus_Pa=G, poisson=NU)
    with pytest.raises(ValueError, match="speed_m_s"):
        solve_quasi_static(contact, 0.0, 0.0, Q, 0.0, shear_modulus_Pa=G, poisson=NU)
    with pytest.raises(ValueError, match="matching materials"):
        solve_quasi_static(contact, 0.0, 0.0, Q, V, shear_modulus_Pa=8.2e9, poisson=NU)
    with pytest.raises(ValueError, match="unknown creep law"):
        solve_quasi_static(contact, 0.0, 0.0, Q, V, shear_modulus_Pa=G, poisson=NU, creep_law="magic")
    # without the a/b clamp FASTSIM rejects the long flange ellipse (a/b ~ 17): a clear error, not a number
    with pytest.raises(QuasiStaticError, match="creep law failed at the right flange"):
        solve(contact, 0.010, semi_axis_ratio_range=None)


def test_creep_law_lookup(monkeypatch):
    assert creep_law_by_name("fastsim") is fastsim
    monkeypatch.setitem(CREEP_LAWS, "missing", ((("exudyn_wheelrail.no_such_module", "law"),
                                                 ("exudyn_wheelrail.creep", "no_such_law")), None))
    with pytest.raises(ValueError, match="not available.*no_such_module.*not importable.*no_such_law.*missing"):
        creep_law_by_name("missing")


def test_custom_creep_law_and_clamp_flag(s1002):
    _, contact = s1002
    seen = []

    def law(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson):
        seen.append(a / b)
        return fastsim(a, b, xi, eta, phi, normal_force, mu, shear_modulus, poisson)

    res = solve(contact, 0.010, creep_law=law)
    assert res.converged
    assert max(seen) == pytest.approx(10.0, rel=1e-12)        # the callable's default clamp: Table E.3's 0.1 ... 10
    flange = [p for p in res.points if p.region == "flange"][0]
    assert "creep_ratio_clamped" in flange.flags and flange.a_m / flange.b_m > 10


# ---- a cone on a circular crown against Kalker's linear theory ------------------------------------------------------
CONE, CROWN_R, R0 = 0.05, 0.08, 0.46


@pytest.fixture(scope="module")
def cone():
    pair = WheelRailPair(WheelProfile.cone(CONE), RailProfile.circular_crown(CROWN_R, half_width_m=0.05),
                         gauge_m=1.41, inclination="none", back_to_back_m=1.36, r0_m=R0)
    return pair, make_contact(pair)


def cone_rolling_radius(pair, c_y, c_z, roll):
    """Closed form (side frame): the wheel is the line through (Y_off, r0) with direction (1, -conicity) in the
    wheelset frame; the crown is the circle of radius R centred R below its top; the contact's wheel point is the
    foot of the circle centre on the line, its rolling radius the wheelset-frame z of that foot."""
    y_off = pair.wheel_offset_y_m
    depth = 0.014
    y_top = 0.5 * pair.gauge_m + math.sqrt(CROWN_R ** 2 - (CROWN_R - depth) ** 2)
    centre = np.array([y_top, CROWN_R])
    cr, sr = math.cos(roll), math.sin(roll)
    point = np.array([c_y + cr * y_off - sr * R0, c_z + sr * y_off + cr * R0])
    direction = np.array([cr - sr * (-CONE), sr + cr * (-CONE)])
    direction /= np.linalg.norm(direction)
    foot = point + np.dot(centre - point, direction) * direction
    return -sr * (foot[0] - c_y) + cr * (foot[1] - c_z)


@pytest.mark.parametrize("y", [0.5e-3, 1e-3])
def test_cone_free_rolling_matches_linear_theory(cone, y):
    pair, contact = cone
    mu = 5.0     # friction high enough for full adhesion: FASTSIM is then exactly linear (Kalker's C11)
    res = solve_quasi_static(contact, y, 0.0, Q, V, mu=mu, shear_modulus_Pa=G, poisson=NU)
    assert res.converged, res.message
    pts = {p.side: p for p in res.points}
    assert sorted(pts) == ["left", "right"] and len(res.points) == 2
    radius = {"right": cone_rolling_radius(pair, y, res.z_m, res.roll_rad),
              "left": cone_rolling_radius(pair, -y, res.z_m, -res.roll_rad)}
    for side in pts:
        assert pts[side].rolling_radius_m == pytest.approx(radius[side], abs=1e-6)   # (elastic penetration ~1e-4)
    # Kalker's linear theory: Fx = -k xi, k = G c^2 C11(a/b); xi = (V - Omega r)/V_roll, V_roll = (V + Omega r)/2;
    # free rolling: sum k r xi = 0 (normal forces pass through the axle, Fy acts in the axle's plane)
    k = {s: G * p.a_m * p.b_m * kalker_coefficients(p.a_m / p.b_m, NU)[0] for s, p in pts.items()}

    def xi(side, omega):
        r = radius[side]
        return (V - omega * r) / (0.5 * (V + omega * r))

    omega_ref = brentq(lambda w: sum(k[s] * radius[s] * xi(s, w) for s in pts), 0.9 * V / R0, 1.1 * V / R0,
                       xtol=1e-14)
    assert res.spin_speed_rad_s == pytest.approx(omega_ref, rel=1e-7)
    for side, p in pts.items():
        assert p.xi == pytest.approx(xi(side, omega_ref), rel=1e-3, abs=1e-8)
        assert p.Fx_N == pytest.approx(-k[side] * xi(side, omega_ref), rel=3e-3)
    # Klingel/Wickens to first order: xi = -/+ (r_R - r_L)/(r_R + r_L), Fx_right = -Fx_left = k dr/(2 r0) > 0 for y > 0
    dr = radius["right"] - radius["left"]
    assert dr == pytest.approx(2 * CONE * y, rel=0.1)
    assert pts["right"].Fx_N == pytest.approx(0.5 * (k["right"] + k["left"]) * dr / (2 * R0), rel=0.03)
    assert pts["left"].Fx_N == pytest.approx(-pts["right"].Fx_N, rel=0.03)
    assert pts["right"].Fx_N > 0


# ---- the yaw lead in the solution ------------------------------------------------------------------------------
def test_flange_contact_leads_for_positive_yaw(s1002):
    _, contact = s1002
    res = solve(contact, 0.010)
    f = [p for p in res.points if p.side == "right" and p.region == "flange"][0]
    psi, g = res.yaw_rad, f.contact_angle_rad
    # first order: lead = rho tan(psi) sin(g) / cos(g_w), g_w = g + roll (right wheel), rho = rolling radius
    first = f.rolling_radius_m * math.tan(psi) * math.sin(g) / math.cos(g + res.roll_rad)
    assert f.lead_m == pytest.approx(first, rel=0.01) and f.lead_m > 0.01
    # the contact's track x: the wheel itself is carried back by the yaw (-u sin psi, u its axial coordinate), the
    # flange point leads (the roll adds sin(psi) sin(roll) rho ~ 0.13 mm here)
    u = np.dot(f.p_contact_in_track - [0.0, res.y_m, res.z_m], wheelset_axis(res.roll_rad, psi))
    assert f.p_contact_in_track[0] == pytest.approx(f.lead_m - u * math.sin(psi), abs=3e-4)


# ---- the example -----------------------------------------------------------------------------------------------
def load_example():
    spec = importlib.util.spec_from_file_location("manchester_a22", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_example_a22_columns_and_physics(tmp_path, s1002):
    example = load_example()
    out = tmp_path / "a22.csv"
    png = tmp_path / "a22.png"
    assert example.main(["--out", str(out), "--plot", str(png), "--y-mm", "0,10"]) == 0
    assert png.stat().st_size > 10_000
    with open(out, newline="") as fh:
        reader = csv.DictReader(fh)
        header = reader.fieldnames
        table = list(reader)
    assert header[:9] == ["y_m", "yaw_rad", "side", "region", "y_rail_m", "contact_angle_rad", "normal_force_N",
                          "longitudinal_force_N", "lateral_force_N"]
    num = [{k: (v if k in ("side", "region", "flags") else float(v)) for k, v in r.items()} for r in table]
    assert {r["y_m"] for r in num} == {0.0, 0.01}
    assert all(r["converged"] == 1 for r in num)
    for y in (0.0, 0.01):
        assert [r["yaw_rad"] for r in num if r["y_m"] == y] == pytest.approx([2.4 * y] * 2, abs=1e-15)
        for side, s in (("right", 1.0), ("left", -1.0)):
            rows = [r for r in num if r["y_m"] == y and r["side"] == side]
            assert rows
            # the upward force on each wheel is 10 kN; from the required columns alone (y_c tilts by the contact
            # angle, its vertical component -/+ sin g; the yaw-lead tilt of x_c is neglected here: 1 %)
            assert sum(r["vertical_force_N"] for r in rows) == pytest.approx(10e3, abs=0.05)
            approx = sum(r["normal_force_N"] * math.cos(r["contact_angle_rad"])
                         + s * r["lateral_force_N"] * math.sin(r["contact_angle_rad"]) for r in rows)
            assert approx == pytest.approx(10e3, rel=0.01)
    # y = 0: symmetric tread contacts
    centred = {r["side"]: r for r in num if r["y_m"] == 0.0}
    assert centred["right"]["region"] == centred["left"]["region"] == "tread"
    assert centred["right"]["normal_force_N"] == pytest.approx(centred["left"]["normal_force_N"], rel=1e-9)
    # y = 10 mm: the right wheel is on its flange.  Our yaw-free geometry puts that contact beyond the steepest
    # flank point, at 0.80 rad (not > 0.9 rad): compare with the rigid geometry sweep (same definition of y_rail)
    pair, _ = s1002
    rigid = [r for r in contact_geometry_sweep(pair, [0.010]).rows if r["side"] == "right"]
    assert [r["region"] for r in rigid] == ["flange"]
    flange = [r for r in num if r["y_m"] == 0.01 and r["side"] == "right"]
    assert [r["region"] for r in flange] == ["flange"]
    f = flange[0]
    assert f["contact_angle_rad"] == pytest.approx(rigid[0]["contact_angle_rad"], abs=0.02)
    assert f["contact_angle_rad"] > 0.75
    assert f["y_rail_m"] == pytest.approx(rigid[0]["y_rail_m"], abs=5e-4)
    # lateral creep force on the right flange, derived: the flange contact leads (yaw > 0) where the wheel surface
    # moves down, so the wheel slides down the flange (and, yawed towards the rail, away from it): eta < 0 and
    # Fy = -G c^2 C22 eta > 0 along y_c = (0, cos g, -sin g): UP the flange (Nadal's climbing direction) with a
    # lateral component towards the rail.  So the creep force does not push the wheelset back; the whole contact
    # force does (normal force dominates), and its L/V is above Nadal's limit (only part of mu N acts upwards)
    g = f["contact_angle_rad"]
    assert f["eta"] < 0 and f["lateral_force_N"] > 0
    lateral_on_wheel = -f["normal_force_N"] * math.sin(g) + f["lateral_force_N"] * math.cos(g)
    assert lateral_on_wheel < -5e3
    nadal = (math.tan(g) - MU) / (1 + MU * math.tan(g))
    assert -lateral_on_wheel / f["vertical_force_N"] > nadal
    # the left tread's lateral creep force also pushes towards the right rail (yaw: eta = -tan psi < 0)
    left = [r for r in num if r["y_m"] == 0.01 and r["side"] == "left"][0]
    assert left["eta"] < 0 and left["lateral_force_N"] > 0


def test_example_reports_an_unusable_creep_law(tmp_path, monkeypatch, capsys):
    example = load_example()

    def broken(name):
        raise ValueError(f"creep law {name!r} is not available in this installation: tried nothing")

    monkeypatch.setattr(example, "creep_law_by_name", broken)
    with pytest.raises(SystemExit) as exc:
        example.main(["--out", str(tmp_path / "x.csv"), "--creep-law", "table"])
    assert exc.value.code == 2
    assert "creep law 'table' is not" in capsys.readouterr().err
    assert not (tmp_path / "x.csv").exists()
