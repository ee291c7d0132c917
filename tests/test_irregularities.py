"""Per-rail irregularities (exudyn_wheelrail.track.irregularities, the compiled channels of track.rigid) and
what the contact makes of them.

Independent references: a wheel–rail pair built with the wider gauge (``WheelRailPair(gauge_m=...)``) for a gauge
deviation; the rotation invariance of the contact (a wheelset posed in the rolled rail pair's frame on a perfect
track) for a cross level; the defect shapes' closed forms and finite differences; the per-rail sums of
conventions.py."""
from __future__ import annotations

import dataclasses
import math

import exudyn as exu
import numpy as np
import pytest

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.contact.layout import RES_N, RES_P_X, RES_P_Y, RES_P_Z
from exudyn_wheelrail.conventions import RAIL_CENTRE_DISTANCE_M, STANDARD_GAUGE_M
from exudyn_wheelrail.multibody import RigidStraightTrack, build_vehicle
from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.track.rigid import Harmonic, SpanDeflection
from exudyn_wheelrail.track.irregularities import ChannelTable, IsolatedDefect, channel_values, rail_values
from exudyn_wheelrail.track.measured import read_irregularity_csv

SPEED_M_S = 30.0


def _contact(pair, irregularity=None):
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=SPEED_M_S)
    contact = C.add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=SPEED_M_S, creep_law="fastsim",
                                       fastsim_grid=(16, 8), track=RigidStraightTrack(irregularity), jacobian=None)
    mbs.Assemble()
    return contact, SC


def _constant(channel, value):
    """A constant channel (a two-sample table is held constant: exact, unlike a long harmonic)."""
    return ChannelTable([-1e3, 1e3], {channel: [value, value]}, name=f"constant {channel}")


def _state(contact, y_m, z_m, roll_rad):
    """Coordinates of the single wheelset at axle-centre pose (y, z, roll) in the track frame, rolling at V."""
    p_ref = contact.p_ref[0]
    q = np.array([0.0, y_m - p_ref[1], z_m - p_ref[2], roll_rad, 0.0, 0.0])
    q_t = np.array([0.0, 0.0, 0.0, 0.0, -SPEED_M_S / 0.46, 0.0])
    return q, q_t


# tread contact a little below the unloaded height (tens of µm penetration), slightly off centre and rolled
POSE = (1.5e-3, -0.46 + 2.5e-4, 4e-4)
# The kernel's Newton iteration stops at 1e-11 m on positions; with ~5e-5 m penetration and N ∝ δ^1.5 two
# evaluations of the same geometry from inputs that differ by rounding differ by at most ~1.5 · 1e-11/5e-5 = 3e-7 of
# the force (creep forces alike): 1e-6 of the largest force bounds the comparison; a channel ignored by the contact
# moves the contact points by millimetres and the forces by percent.
RTOL = 1e-6


@pytest.fixture(scope="module")
def pair():
    return WheelRailPair("S1002", "UIC60", gauge_m=STANDARD_GAUGE_M, inclination="1/40")


@pytest.mark.parametrize("widening_m", [6e-3, -3e-3])
def test_gauge_deviation_is_the_pair_of_the_wider_gauge(pair, widening_m):
    wide = WheelRailPair("S1002", "UIC60", gauge_m=STANDARD_GAUGE_M + widening_m, inclination="1/40")
    ref, _sc1 = _contact(wide)
    dev, _sc2 = _contact(pair, _constant("gauge", widening_m))
    f_ref = ref.forces(*_state(ref, *POSE), 0.1).copy()
    f_dev = dev.forces(*_state(dev, *POSE), 0.1).copy()
    scale = np.max(np.abs(f_ref[:3]))
    assert scale > 1e4                                           # both wheels loaded
    np.testing.assert_allclose(f_dev, f_ref, rtol=0, atol=RTOL * scale)
    np.testing.assert_allclose(dev.results[..., [RES_P_X, RES_P_Y, RES_P_Z]],
                               ref.results[..., [RES_P_X, RES_P_Y, RES_P_Z]], rtol=0, atol=1e-9)
    # the pose relative to the rails' centre line is the wheelset's own (the rails moved apart, not their centre)
    np.testing.assert_allclose(dev.wheelset_rail_pose(), ref.wheelset_rail_pose(), rtol=0, atol=1e-15)
    # and the deviation matters: the nominal pair at the same pose gives other contact points
    nominal, _sc3 = _contact(pair)
    nominal.forces(*_state(nominal, *POSE), 0.1)
    assert np.max(np.abs(nominal.results[..., RES_P_Y] - ref.results[..., RES_P_Y])) > 1e-3


def _rx(theta, y, z):
    c, s = math.cos(theta), math.sin(theta)
    return c * y - s * z, s * y + c * z


def test_cross_level_is_a_roll_of_the_rail_pair(pair):
    """On rails rolled by θ = asin(c/b) about their centre line a wheelset at pose R_x(θ) p, roll + θ sees what a
    wheelset at p, roll sees on a perfect track: forces (track frame) R_x(θ) F, torques (body frame) equal,
    contact points R_x(θ) p_c."""
    cross_level = 6e-3
    theta = math.asin(cross_level / RAIL_CENTRE_DISTANCE_M)
    flat, _sc1 = _contact(pair)
    rolled, _sc2 = _contact(pair, _constant("cross_level", cross_level))
    y, z, roll = POSE
    f_flat = flat.forces(*_state(flat, y, z, roll), 0.1).copy()
    f_rolled = rolled.forces(*_state(rolled, *_rx(theta, y, z), roll + theta), 0.1).copy()
    scale = np.max(np.abs(f_flat[:3]))
    fy, fz = _rx(theta, f_flat[1], f_flat[2])
    np.testing.assert_allclose(f_rolled, [f_flat[0], fy, fz, *f_flat[3:]], rtol=0, atol=RTOL * scale)
    py, pz = _rx(theta, flat.results[..., RES_P_Y], flat.results[..., RES_P_Z])
    np.testing.assert_allclose(rolled.results[..., RES_P_Y], py, rtol=0, atol=1e-9)
    np.testing.assert_allclose(rolled.results[..., RES_P_Z], pz, rtol=0, atol=1e-9)
    # positive cross level lowers the right rail: a level wheelset loads its left wheel (index 1) more
    rolled.forces(*_state(rolled, 0.0, z, 0.0), 0.1)
    flat.forces(*_state(flat, 0.0, z, 0.0), 0.1)
    n_rolled, n_flat = rolled.results[..., RES_N].sum(axis=1), flat.results[..., RES_N].sum(axis=1)
    assert n_flat[1] == pytest.approx(n_flat[0], rel=1e-9) and n_flat[0] > 0.0
    assert n_rolled[1] > n_flat[1] and n_rolled[0] < n_flat[0]


def test_zero_channels_change_nothing(pair):
    """Zero cross level and gauge next to an alignment give the alignment's results bit for bit."""
    base = SpanDeflection(20.0, 4e-3, start_m=-5.0, transition_length_m=3.0)
    zeros = (Harmonic(0.0, 7.0, direction="gauge") + _constant("cross_level", 0.0)
             + IsolatedDefect("cusp", 0.0, 2.0, 0.0, rail="left"))
    a, _sc1 = _contact(pair, base)
    b, _sc2 = _contact(pair, base + zeros)
    for t in (0.0, 0.1, 0.2):
        state = _state(a, 1e-3, -0.46 + 2e-4, 1e-4)
        # zero channels add exact zeros to the same numbers, the same compiled code follows: bit-equality
        assert np.array_equal(a.forces(*state, t), b.forces(*state, t))
        assert np.array_equal(a.results, b.results)


# ------------------------------------------------------------------------------------------- channels and rails
def test_per_rail_sums_and_table_from_rails():
    s = np.linspace(0.0, 50.0, 101)
    rng = np.random.default_rng(3)
    yr, yl, zr, zl = (1e-3 * rng.standard_normal(len(s)) for _ in range(4))
    table = ChannelTable.from_rails(s, y_right_m=yr, y_left_m=yl, z_right_m=zr, z_left_m=zl, name="rails")
    r = rail_values(table, s)          # at the samples the splines interpolate
    for key, ref in (("y_right_m", yr), ("y_left_m", yl), ("z_right_m", zr), ("z_left_m", zl)):
        np.testing.assert_allclose(r[key], ref, rtol=0, atol=1e-15)
    v = channel_values(table, s)
    np.testing.assert_allclose(v.gauge_m, yr - yl, rtol=0, atol=1e-15)
    np.testing.assert_allclose(v.cross_level_m, zr - zl, rtol=0, atol=1e-15)
    # held outside the table, zero end slopes
    out = channel_values(table, [-10.0, 80.0])
    assert out.alignment_m[0] == pytest.approx(0.5 * (yr[0] + yl[0]), abs=1e-16)
    assert out.level_m[1] == pytest.approx(0.5 * (zr[-1] + zl[-1]), abs=1e-16)
    assert np.all(out.d_gauge == 0.0)  # held ends: assigned zero slopes


@pytest.mark.parametrize("shape, closed_form", [
    ("bump", lambda u, L, d: np.where((u > 0) & (u < L), 0.5 * d * (1 - np.cos(2 * np.pi * u / L)), 0.0)),
    ("cusp", lambda u, L, d: np.where(np.abs(2 * u / L) < 1, d * (1 - np.abs(2 * u / L)) ** 2, 0.0)),
    ("dipped_joint", lambda u, L, d: np.where(np.abs(2 * u / L) < 1, d * (1 - np.abs(2 * u / L)), 0.0)),
])
@pytest.mark.parametrize("rail, direction", [("left", "vertical"), ("right", "lateral"), ("both", "vertical")])
def test_isolated_defects_on_one_rail(shape, closed_form, rail, direction):
    s0, L, d = 12.0, 1.6, 2e-3
    defect = IsolatedDefect(shape, s0, L, d, rail=rail, direction=direction)
    s = np.linspace(s0 - 2.0, s0 + 3.0, 5001)
    r = rail_values(defect, s)
    shape_ref = closed_form(s - s0, L, d)
    axis = "z" if direction == "vertical" else "y"
    for side in ("right", "left"):
        expected = shape_ref if rail in (side, "both") else 0.0 * s
        np.testing.assert_allclose(r[f"{axis}_{side}_m"], expected, rtol=0, atol=1e-15)
        other = "y" if axis == "z" else "z"
        assert np.all(r[f"{other}_{side}_m"] == 0.0)  # the other direction: exact zeros
    # derivatives against central differences of the values (away from the kinks)
    v = channel_values(defect, s)
    name = "level" if direction == "vertical" else "alignment"
    value, slope, curv = getattr(v, f"{name}_m"), getattr(v, f"d_{name}"), getattr(v, f"dd_{name}")
    h = s[1] - s[0]
    kinks = np.array([s0, s0 + L, s0 + L / 2, s0 - L / 2])
    smooth = np.min(np.abs(s[1:-1, None] - kinks[None, :]), axis=1) > 2 * h
    # central differences: error h²/6 |y'''| ≤ h² (2π/L)³ d / 6 for the slope, likewise for the curvature
    err = h * h * (2 * np.pi / L) ** 4 * abs(d)
    np.testing.assert_allclose(((value[2:] - value[:-2]) / (2 * h))[smooth], slope[1:-1][smooth], rtol=0, atol=err)
    np.testing.assert_allclose(((slope[2:] - slope[:-2]) / (2 * h))[smooth], curv[1:-1][smooth], rtol=0, atol=err)


def test_harmonic_per_channel():
    h = Harmonic(1e-3, 10.0, phase_rad=0.3, direction="cross_level") + Harmonic(2e-3, 5.0, direction="gauge")
    s = np.linspace(0.0, 20.0, 41)
    v = channel_values(h, s)
    # the phase is computed as (2π/λ) s instead of 2π s/λ: rounding of the argument (< 1e-14 rad here) x amplitude
    np.testing.assert_allclose(v.cross_level_m, 1e-3 * np.sin(2 * np.pi * s / 10.0 + 0.3), rtol=0, atol=1e-17)
    np.testing.assert_allclose(v.gauge_m, 2e-3 * np.sin(2 * np.pi * s / 5.0), rtol=0, atol=2e-17)
    assert np.all(v.alignment_m == 0.0) and np.all(v.level_m == 0.0)  # channels not given: exact zeros
    # the whole-track evaluation (alignment, level) ignores the other channels
    assert np.all(h.evaluate(s).y_m == 0.0) and np.all(h.evaluate(s).z_m == 0.0)  # exact zeros


def test_bad_inputs():
    with pytest.raises(ValueError, match="unknown channel 'twist'"):
        ChannelTable([0.0, 1.0], {"twist": [0.0, 0.0]}, name="f.csv")
    with pytest.raises(ValueError, match="f.csv: s must increase strictly"):
        ChannelTable([0.0, 1.0, 1.0], {"gauge": [0.0, 0.0, 0.0]}, name="f.csv")
    with pytest.raises(ValueError, match="non-finite value"):
        ChannelTable([0.0, 1.0], {"gauge": [0.0, np.nan]})
    with pytest.raises(ValueError, match="defect shape 'dent'"):
        IsolatedDefect("dent", 0.0, 1.0, 1e-3)
    with pytest.raises(ValueError, match="defect rail 'middle'"):
        IsolatedDefect("bump", 0.0, 1.0, 1e-3, rail="middle")
    with pytest.raises(ValueError, match="length_m"):
        IsolatedDefect("bump", 0.0, 0.0, 1e-3)
    with pytest.raises(ValueError, match="direction"):
        Harmonic(1e-3, 5.0, direction="twist")
    with pytest.raises(ValueError, match="y_left_m"):
        ChannelTable.from_rails([0.0, 1.0], y_right_m=[0.0, 0.0])


# ----------------------------------------------------------------------------------------------- measured files
def _write(tmp_path, text, name="irr.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_measured_channels_in_mm_and_rails_in_m(tmp_path):
    s = np.linspace(0.0, 10.0, 11)
    a, lv, c, g = (np.round(1.5 * np.sin(0.7 * s + k), 4) for k in range(4))     # mm
    rows = "\n".join(f"{x},{p},{q},{r},{t}" for x, p, q, r, t in zip(s, a, lv, c, g))
    path = _write(tmp_path, "# measured 2026\ns_m, alignment_mm, level_mm, cross_level_mm, gauge_mm\n" + rows + "\n")
    table = read_irregularity_csv(path)
    v = channel_values(table, s)
    for name, ref in (("alignment_m", a), ("level_m", lv), ("cross_level_m", c), ("gauge_m", g)):
        np.testing.assert_allclose(getattr(v, name), 1e-3 * ref, rtol=0, atol=1e-15)
    # the same track as rail columns in metres (conventions.py: per rail)
    yr, yl, zr, zl = 1e-3 * (a + g / 2), 1e-3 * (a - g / 2), 1e-3 * (lv + c / 2), 1e-3 * (lv - c / 2)
    rows = "\n".join(",".join(repr(float(v)) for v in row) for row in zip(s, yr, yl, zr, zl))
    rails = read_irregularity_csv(_write(tmp_path, "s_m,y_right_m,y_left_m,z_right_m,z_left_m\n" + rows, "r.csv"))
    w = channel_values(rails, s)
    for name in ("alignment_m", "level_m", "cross_level_m", "gauge_m"):
        np.testing.assert_allclose(getattr(w, name), getattr(v, name), rtol=0, atol=1e-15)


@pytest.mark.parametrize("text, message", [
    ("s_m,level_mm\n0,1\n1,nan\n2,1\n", r"irr.csv:3: column 'level_mm': 'nan' is not a finite number"),
    ("s_m,level_mm\n0,1\n2,1\n1,1\n", r"irr.csv:4: the distance s_m decreases"),
    ("s_m,level_mm\n0,1\n0,1\n1,1\n", r"irr.csv:3: the distance s_m repeats"),
    ("s_m,twist_mm\n0,1\n1,1\n", r"irr.csv:1: unknown column 'twist_mm'"),
    ("s_m,level\n0,1\n1,1\n", r"irr.csv:1: column 'level' has no unit suffix"),
    ("s_m,level_m\n0,0.001\n1,2.5\n", r"irr.csv:3: column 'level_m': 2.5 m is implausible .* level_mm"),
    ("s_m,gauge_mm\n0,0.001\n1,-0.002\n", r"irr.csv:1: column 'gauge_mm': every value is below .* gauge_m"),
    ("level_mm,alignment_mm\n1,1\n2,2\n", r"irr.csv:1: missing the distance column s_m"),
    ("s_m,y_right_mm\n0,1\n1,1\n", r"irr.csv:1: rail column 'y_right' needs 'y_left'"),
    ("s_m,level_mm,z_right_mm,z_left_mm\n0,1,1,1\n1,1,1,1\n", r"'level' and the rail columns"),
    ("s_m,level_mm\n0,1\n1,x\n", r"irr.csv:3: column 'level_mm': not a number: 'x'"),
    ("s_m,level_mm\n0,1\n1\n", r"irr.csv:3: 1 values for 2 columns"),
])
def test_measured_file_errors_name_file_and_line(tmp_path, text, message):
    with pytest.raises(ValueError, match=message):
        read_irregularity_csv(_write(tmp_path, text))


# --------------------------------------------------------------------------------------------------- scenarios
def _scenario(track):
    return {"schema_version": 2, "vehicle": {"name": "manchester_vehicle1", "speed_km_h": 100.0}, "track": track,
            "run": {"duration_s": 1.0}}


def test_scenario_track_entries_build_the_same_irregularity(tmp_path):
    from exudyn_wheelrail.scenarios.build import build_track
    from exudyn_wheelrail.scenarios.spec import features_end_m, validate_scenario
    from exudyn_wheelrail.track.spectra import SpectralIrregularity
    path = _write(tmp_path, "s_m,gauge_mm\n0,0.5\n10,1.5\n20,0.5\n")
    scn = validate_scenario(_scenario([
        {"type": "spectrum", "spectrum": "fra_class_6", "seed": 4, "length_m": 200.0, "channels": ["cross_level"]},
        {"type": "defect", "shape": "cusp", "position_m": 30.0, "length_m": 2.0, "depth_m": 0.001, "rail": "left"},
        {"type": "harmonic", "amplitude_m": 0.001, "wavelength_m": 9.0, "direction": "gauge"},
        {"type": "measured", "file": str(path)}]), base_dir=tmp_path)
    assert validate_scenario(scn, base_dir=tmp_path) == scn                 # the normal form is a fixed point
    assert features_end_m(scn) == pytest.approx(200.0)
    ref = (SpectralIrregularity("fra_class_6", 200.0, 4, channels=("cross_level",))
           + IsolatedDefect("cusp", 30.0, 2.0, 0.001, rail="left") + Harmonic(0.001, 9.0, direction="gauge")
           + read_irregularity_csv(path))
    s = np.linspace(-5.0, 210.0, 2001)
    got, want = channel_values(build_track(scn).irregularity, s), channel_values(ref, s)
    for name in ("alignment_m", "level_m", "cross_level_m", "gauge_m"):
        # the same components evaluated by the same code: bit-equality
        assert np.array_equal(getattr(got, name), getattr(want, name))


def test_a_faded_spectrum_entry_rises_from_zero_to_the_table():
    """``fade_in_m``: the generated table times the raised cosine ``w = (1 - cos(π u))/2`` from ``start_m`` — zero,
    with its slope, before and at ``start_m``; at the table's samples inside the fade ``w`` times the table's value
    (checked at u = 1/4, w = 0.146, where a linear ramp would give 0.25, and u = 1/2); the table's own values from
    ``start_m + fade_in_m`` on, bit for bit at the samples inside the table (w = 1 exactly, and a spline at its
    knot returns the knot's value whatever its other coefficients) and, between samples 5 m beyond, within
    1e-9 of the table's amplitude (the clamped spline reaches back to the fade through ~20 samples, each passing
    on about a quarter).  ``fade_in_m = 0`` is no fade; longer than ``length_m`` an error."""
    from exudyn_wheelrail.scenarios.build import build_track
    from exudyn_wheelrail.scenarios.spec import ScenarioError, validate_scenario
    from exudyn_wheelrail.track.irregularities import FadedIn
    from exudyn_wheelrail.track.spectra import SpectralIrregularity
    entry = {"type": "spectrum", "spectrum": "german_low", "seed": 3, "length_m": 200.0, "start_m": 10.0}
    plain = build_track(validate_scenario(_scenario([entry]))).irregularity
    faded = build_track(validate_scenario(_scenario([{**entry, "fade_in_m": 40.0}]))).irregularity
    assert isinstance(faded, FadedIn) and isinstance(plain, SpectralIrregularity)
    assert (faded.s_from_m, faded.s_to_m) == (10.0, 50.0)
    names = ("alignment_m", "level_m", "cross_level_m", "gauge_m")
    before = channel_values(faded, np.linspace(-5.0, 10.0, 31))
    for name in names:
        assert np.all(getattr(before, name) == 0.0)
        assert np.all(getattr(before, "d_" + name[:-2]) == 0.0)
    for u in (0.25, 0.5):
        s_u = np.array([10.0 + 40.0 * u])                    # a sample (step 0.25 m)
        w = 0.5 * (1.0 - np.cos(np.pi * u))
        for name in names:
            assert getattr(channel_values(faded, s_u), name)[0] == pytest.approx(
                w * getattr(channel_values(plain, s_u), name)[0], rel=1e-12, abs=1e-18)
    samples = np.arange(50.0, 209.5, 0.25)                # knots inside the table (the last one, 209.75, is an end)
    between = np.arange(55.0, 210.0, 0.25) + 0.1
    scale = max(np.max(np.abs(getattr(channel_values(plain, samples), n))) for n in names)
    for name in names:
        assert np.array_equal(getattr(channel_values(faded, samples), name),
                              getattr(channel_values(plain, samples), name))
        assert np.max(np.abs(getattr(channel_values(faded, between), name)
                             - getattr(channel_values(plain, between), name))) <= 1e-9 * scale
    none = build_track(validate_scenario(_scenario([{**entry, "fade_in_m": 0.0}]))).irregularity
    assert isinstance(none, SpectralIrregularity)
    with pytest.raises(ScenarioError, match=r"track\.0\.fade_in_m: 300 m is longer than the generated length_m"):
        validate_scenario(_scenario([{**entry, "fade_in_m": 300.0}]))


def test_the_curving_spectrum_is_the_scenarios_track_entry():
    """The curving case's spectrum and seed reach the run as the scenario's ``spectrum`` track entry (faded in
    from the start to the circular curve), and build the irregularity :func:`spectral_irregularity` gives (the same
    code on the same inputs: bit for bit)."""
    from exudyn_wheelrail.scenarios.build import build_track
    from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle
    from exudyn_wheelrail.scenarios.curving import (CurvingCase, curving_distances, curving_scenario,
                                                    irregularity_fade_m, spectral_irregularity)
    from exudyn_wheelrail.scenarios.spec import validate_scenario
    case = CurvingCase("manchester_vehicle1", radius_m=1000.0, cant_m=0.1, speed_km_h=100.0,
                       irregularity_spectrum="german_low", seed=2)
    scn = validate_scenario(curving_scenario(case))
    (entry,) = scn["track"]
    assert entry["type"] == "spectrum" and entry["start_m"] == 0.0
    assert entry["fade_in_m"] == irregularity_fade_m(case)[1]            # to the start of the circular curve
    run_m = curving_distances(case, load_vehicle("manchester_vehicle1"))["total_m"]
    assert entry["length_m"] >= run_m                                     # generated over the whole run
    built = build_track(scn).irregularity
    ref = spectral_irregularity(dataclasses.replace(case, irregularity_spectrum=None, seed=None), "german_low", 2)
    assert repr(built) == repr(ref)
    s = np.linspace(-5.0, entry["length_m"], 4001)
    for name in ("alignment_m", "level_m", "cross_level_m", "gauge_m"):
        assert np.array_equal(getattr(channel_values(built, s), name), getattr(channel_values(ref, s), name))


@pytest.mark.parametrize("fields, option, words", [
    ({"irregularity_spectrum": "german_low"}, "seed", "missing"),
    ({"seed": 1}, "seed", "without a spectrum"),
    ({"irregularity_spectrum": "german_low", "seed": True}, "seed", "non-negative integer"),
    ({"irregularity_spectrum": "german_low", "seed": -2}, "seed", "non-negative integer"),
    ({"irregularity_spectrum": "german_low", "seed": 1.5}, "seed", "non-negative integer"),
    ({"irregularity_spectrum": "ballast", "seed": 1}, "irregularity_spectrum", "expected one of"),
])
def test_a_curving_case_checks_its_spectrum_and_seed(fields, option, words):
    """The curving case's spectrum and seed, checked before any work: the error names the field; a NumPy integer
    seed is a seed; an irregularity object and a spectrum together are refused."""
    from exudyn_wheelrail.scenarios.curving import (CurvingCase, CurvingInputError, check_curving_case,
                                                    curving_scenario)
    from exudyn_wheelrail.scenarios.spec import validate_scenario
    from exudyn_wheelrail.track.rigid import Harmonic
    base = dict(vehicle="manchester_vehicle1", radius_m=1000.0, cant_m=0.1, speed_km_h=100.0)
    with pytest.raises(CurvingInputError) as err:
        check_curving_case(CurvingCase(**base, **fields))
    assert err.value.option == option and words in err.value.problem
    numpy_seed = CurvingCase(**base, irregularity_spectrum="german_low", seed=np.int64(4))
    check_curving_case(numpy_seed)
    (entry,) = validate_scenario(curving_scenario(numpy_seed))["track"]    # the spec takes it as the integer 4
    assert entry["seed"] == 4 and type(entry["seed"]) is int
    with pytest.raises(CurvingInputError, match="not both"):
        check_curving_case(CurvingCase(**base, irregularity=Harmonic(0.001, 50.0), irregularity_spectrum="german_low",
                                       seed=1))


@pytest.mark.parametrize("entry, message", [
    ({"type": "spectrum", "spectrum": "ballast", "seed": 1, "length_m": 200.0}, r"track\.0\.spectrum: .*ballast"),
    ({"type": "spectrum", "spectrum": "german_low", "seed": -1, "length_m": 200.0}, r"track\.0\.seed"),
    ({"type": "spectrum", "spectrum": "german_low", "seed": 1, "length_m": 100.0}, r"track\.0: .*length_m"),
    ({"type": "spectrum", "spectrum": "german_low", "seed": 1, "length_m": 200.0, "band_m": [3.0]},
     r"track\.0\.band_m"),
    ({"type": "spectrum", "spectrum": "german_low", "seed": 1, "length_m": 200.0, "channels": ["twist"]},
     r"track\.0\.channels"),
    ({"type": "defect", "shape": "dent", "position_m": 1.0, "length_m": 1.0, "depth_m": 0.001},
     r"track\.0\.shape"),
    ({"type": "defect", "shape": "bump", "position_m": 1.0, "length_m": 1.0, "depth_m": 2.0},
     r"track\.0\.depth_m"),
    ({"type": "harmonic", "amplitude_m": 0.001, "wavelength_m": 9.0, "direction": "twist"},
     r"track\.0\.direction"),
])
def test_scenario_track_errors_name_the_key(entry, message):
    from exudyn_wheelrail.scenarios.spec import ScenarioError, validate_scenario
    with pytest.raises(ScenarioError, match=message):
        validate_scenario(_scenario([entry]))


def test_scenario_measured_file_error_names_key_and_line(tmp_path):
    from exudyn_wheelrail.scenarios.spec import ScenarioError, validate_scenario
    path = _write(tmp_path, "s_m,level_m\n0,0.001\n1,3.0\n")
    with pytest.raises(ScenarioError, match=r"track\.0\.file: .*irr\.csv:3: column 'level_m'"):
        validate_scenario(_scenario([{"type": "measured", "file": str(path)}]))


def test_vehicle_starts_on_rails_rolled_by_a_cross_level():
    """At t = 0 every wheelset is rolled with the rails under it (about their centre line): the wheel loads equal
    those on a perfect track (a wheelset left level would press one wheel c/2 ≈ 1.7 mm into its rail).  The poses
    agree to rounding, so the loads to the kernel's Newton tolerance (1e-11 m of ~1e-4 m penetration: 1e-6)."""
    from exudyn_wheelrail.scenarios.build import build_scenario
    from exudyn_wheelrail.scenarios.spec import validate_scenario

    def wheel_loads(track):
        scn = validate_scenario({"schema_version": 2, "track": track, "run": {"duration_s": 1.0},
                                 "vehicle": {"name": "manchester_vehicle1", "speed_km_h": 100.0}})
        h = build_scenario(scn)
        return h.contact.evaluate(h.mbs, 0.0)[..., RES_N].sum(axis=1)

    flat = wheel_loads([])
    rolled = wheel_loads([{"type": "harmonic", "amplitude_m": 0.004, "wavelength_m": 30.0, "phase_rad": 1.0,
                           "direction": "cross_level"}])
    assert np.min(flat) > 1e4
    np.testing.assert_allclose(rolled, flat, rtol=1e-6)
