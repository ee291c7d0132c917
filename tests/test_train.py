"""Trains (exudyn_wheelrail.rolling_stock.train): consist files and their validation, the train model against its
cars alone, the couplers against Hooke's law and their dampers against c times the car ends' relative velocity, the
static axle loads against the train's weight and, axle by axle, against the lever rule worked by hand from the vehicle
files (the simulated contact forces and the package's static loads)."""
from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path

import exudyn as exu
import numpy as np
import pytest

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.contact.layout import RES_F_TRACK_X, RES_F_TRACK_Y, RES_F_TRACK_Z, RES_GAMMA
from exudyn_wheelrail.multibody import add_train_contact, add_wheel_rail_contact, build_vehicle, place_on_rails
from exudyn_wheelrail.track.rigid import Harmonic, IrregularitySum, RigidStraightTrack
from exudyn_wheelrail.rolling_stock.train import (ConsistError, build_train, consist_from_dict, load_consist,
                                              shipped_trains)
from exudyn_wheelrail.rolling_stock.placement import start_on_track
from exudyn_wheelrail.simulation.runner import run
from exudyn_wheelrail.simulation.settings import RunSettings

G = 9.81


def _pair(vehicle):
    geo = vehicle.geometry
    return WheelRailPair(geo.wheel_profile, geo.rail_profile, gauge_m=geo.gauge_m,
                         inclination=geo.rail_inclination_tan, back_to_back_m=geo.back_to_back_m, r0_m=geo.r0_m)


def _two_cars(coupling=None):
    c = load_consist("manchester_x8")
    return dataclasses.replace(c, cars=c.cars[:2], coupling=coupling or c.coupling)


# ------------------------------------------------------------------------------------------------ consist files
def test_shipped_consists():
    assert {"manchester_x8", "crh6_intercity_8car"} <= set(shipped_trains())
    m = load_consist("manchester_x8")
    assert m.n_cars == 8 and {c.vehicle.name for c in m.cars} == {"Manchester benchmark vehicle 1"}
    # end to end, no gap: the centres are one car length apart
    assert np.allclose(np.diff(m.car_x_m()), -26.0, rtol=0, atol=1e-12)
    crh = load_consist("crh6_intercity_8car")
    assert crh.n_cars == 8
    assert crh.length_m == pytest.approx(199.5, abs=1e-9)          # the published train length (see the file)
    assert crh.total_mass_kg == pytest.approx(8 * (37200 + 2 * 2700 + 4 * 1935), rel=1e-12)


_GOOD = {"schema_version": 1, "train": {"name": "t", "source": "assumed"},
         "car": [{"vehicle": "manchester_vehicle1", "length_m": 26.0, "count": 2}]}


def test_cars_stand_gap_apart_end_to_end():
    """A consist with a gap between car ends (the shipped ones have none): three cars of 26, 24.5 and 26 m, 0.8 m
    apart — by hand, the centres at 0, -(13 + 0.8 + 12.25) = -26.05 and -26.05 - (12.25 + 0.8 + 13) = -52.1 m and
    the length 76.5 + 2 x 0.8 = 78.1 m (sums of short decimals: 1e-12 m)."""
    data = {"schema_version": 1, "train": {"name": "t", "source": "assumed", "gap_m": 0.8},
            "car": [{"vehicle": "manchester_vehicle1", "length_m": 26.0},
                    {"vehicle": "manchester_vehicle1", "length_m": 24.5},
                    {"vehicle": "manchester_vehicle1", "length_m": 26.0}]}
    c = consist_from_dict(data, source="gap.toml")
    np.testing.assert_allclose(c.car_x_m(), [0.0, -26.05, -52.1], rtol=0, atol=1e-12)
    assert c.length_m == pytest.approx(78.1, abs=1e-12)


@pytest.mark.parametrize("edit, key, words", [
    (lambda d: d["train"].update(gap_m=-0.5), "train.gap_m", "overlap"),
    (lambda d: d["car"][0].update(length_m=20.0), "car.0.length_m", "overlap"),
    (lambda d: d["car"][0].update(vehicle="no_such_vehicle"), "car.0.vehicle", "not found"),
    (lambda d: d.update(coupling={"kx_N_per_m": -1.0e6}), "coupling.kx_N_per_m", ">= 0"),
    (lambda d: d.update(coupling={"cy_N_s_per_m": float("nan")}), "coupling.cy_N_s_per_m", "finite"),
    (lambda d: d["car"][0].update(count=0), "car.0.count", ">= 1"),
    (lambda d: d["car"][0].update(lenght_m=1.0), "car.0.lenght_m", "unknown key"),
    (lambda d: d.update(car=[{"vehicle": "single_wheelset", "length_m": 5.0, "count": 2}]), "coupling.enabled",
     "no car body"),
])
def test_bad_consist_names_file_and_key(tmp_path, edit, key, words):
    import copy
    data = copy.deepcopy(_GOOD)
    edit(data)
    consist_from_dict(copy.deepcopy(_GOOD), source="good.toml")         # the unedited data are accepted
    with pytest.raises(ConsistError) as exc:
        consist_from_dict(data, source=str(tmp_path / "bad.toml"))
    msg = str(exc.value)
    assert msg.startswith(f"{tmp_path / 'bad.toml'}: {key}:") and words in msg, msg


def test_consist_file_errors_name_the_file(tmp_path):
    p = tmp_path / "train.toml"
    p.write_text('schema_version = 1\n[train]\nname = "x"\nsource = "assumed"\n'
                 '[[car]]\nvehicle = "manchester_vehicle1"\nlength_m = 26.0\n[coupling]\nky_N_per_m = -5.0\n')
    with pytest.raises(ConsistError, match=rf"^{p}: coupling.ky_N_per_m: "):
        load_consist(p)
    with pytest.raises(ConsistError, match="not found"):
        load_consist(tmp_path / "missing.toml")


# --------------------------------------------------------------------------------------- the train model
def test_two_car_train_without_couplers_equals_each_car_alone():
    """Couplers off, same track: each car of a 2-car train (one connector for both) gets the contact results it
    gets alone (its own connector, the frame origin moved to its centre: s_start + x_k).  Car 1 sits at x = 0 in both
    models: identical operations, bit-identical results.  Car 2 sits at x_2 = -26 m in the train and at 0 alone: its
    positions differ by rounding, ε|x_2| = 5.8e-15 m, times the Hertz stiffness (~1.5e9 N/m) ≈ 1e-5 N per evaluation;
    allowed: 100 times that after the run."""
    consist = _two_cars(dataclasses.replace(load_consist("manchester_x8").coupling, enabled=False))
    vehicle = consist.cars[0].vehicle
    pair = _pair(vehicle)
    track = RigidStraightTrack(IrregularitySum([Harmonic(amplitude_m=3e-3, wavelength_m=31.0, direction="lateral"),
                                                Harmonic(amplitude_m=1e-3, wavelength_m=13.0, direction="vertical")]))
    V, s0 = 40.0, 5.0
    settings = RunSettings(solver="rk44", dt_s=1e-3, duration_s=0.15)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    train = build_train(mbs, consist, speed_m_s=V, s_start_m=s0)
    add_train_contact(mbs, train, pair, track=track)
    assert train.couplers == [] and len(train.wheelsets) == 8 and train.car_of_wheelset == [0] * 4 + [1] * 4
    names = [mbs.GetObject(i)["name"] for i in range(mbs.systemData.NumberOfObjects())]
    assert "car_body_c1" in names and "car_body_c2" in names
    mbs.Assemble()
    train.contact.warm_up(mbs)
    out = run(mbs, settings, train.contact, speed_m_s=V)
    assert out.status.kind == "ok"
    fields = [RES_F_TRACK_X, RES_F_TRACK_Y, RES_F_TRACK_Z]
    in_train = np.nan_to_num(train.contact.results[:, :, fields])
    for k in range(2):
        sc_k = exu.SystemContainer()
        mbs_k = sc_k.AddSystem()
        s_k = s0 + train.car_x_m[k]
        m = build_vehicle(mbs_k, vehicle, speed_m_s=V, s_start_m=s_k)
        c = add_wheel_rail_contact(mbs_k, m.wheelset_nodes, pair, speed_m_s=V, track=track, s_start_m=s_k)
        place_on_rails(mbs_k, m, pair)
        start_on_track(mbs_k, m, track)
        mbs_k.Assemble()
        c.warm_up(mbs_k)
        assert run(mbs_k, settings, c, speed_m_s=V).status.kind == "ok"
        alone = np.nan_to_num(c.results[:, :, fields])
        mine = in_train[8 * k:8 * k + 8]
        assert np.abs(alone).max() > 4e4                                   # wheels loaded: a meaningful check
        if k == 0:
            # car 1 at x = 0 in both: identical operations (docstring), bit-equality
            assert np.array_equal(mine, alone)
        else:
            tol = 100 * np.finfo(float).eps * abs(train.car_x_m[k]) * 1.5e9
            assert np.abs(mine - alone).max() <= tol


def test_coupler_force_is_k_times_prescribed_offset():
    """Car 2's body moved back by dx and right by dy from its nominal place (the gap grows by dx): the coupler pulls
    the front car back by kx dx and right by ky dy (Hooke; no velocity at t = 0, so no damper force)."""
    consist = _two_cars()
    cp = consist.coupling
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    train = build_train(mbs, consist, speed_m_s=0.0, wheel_rail="springs")
    assert len(train.couplers) == 1
    dx, dy = 2.0e-3, 1.5e-3
    node = train.cars[1].car_body.node
    q0 = np.array(mbs.GetNodeParameter(node, "initialCoordinates"), dtype=float)
    q0[0] -= dx
    q0[1] += dy
    mbs.SetNodeParameter(node, "initialCoordinates", q0.tolist())
    mbs.Assemble()
    f = train.coupler_forces_N(mbs)[0]                                   # on the front car's rear end
    assert f[0] == pytest.approx(-cp.kx_N_per_m * dx, rel=1e-9)          # tension pulls the front car back
    assert f[1] == pytest.approx(cp.ky_N_per_m * dy, rel=1e-9)           # the rear car's end is right of it
    assert f[2] == 0.0  # no vertical offset or rate: an exact zero


def test_coupler_damper_force_is_c_times_relative_velocity_at_the_car_ends():
    """Couplers with four different coefficients (so that no swap of them goes unnoticed); at t = 0 car 2's body is
    displaced back by dx (the gap has grown: tension) while the cars close at 0.03 m/s (compression rate), car 1
    yaws at w1, and the bodies move laterally.  In the model frame (x forward, y right, z down) the coupler's force
    on the front car's rear end is the spring-damper law of the element between the two car-end points:

        f_x = -(kx * gap growth + cx * gap growth rate),   f_y = ky * dy_end + cy * dvy_end,

    gap growth rate = v1x - v2x (the front car's end moving forward opens the gap), the ends' lateral velocities
    v_y + (w x r)_y = v_y + w_z r_x with r_x = -L/2 for the front car's rear end (a yaw to the right swings it
    left).  Tolerance 1e-9 relative: a few products and sums (round-off 1e-15) and the positions' cancellation in the
    gap growth, eps * 26 m / 2 mm ~ 3e-12."""
    from exudyn_wheelrail.rolling_stock.train import CouplingData
    cp = CouplingData(kx_N_per_m=8.0e6, cx_N_s_per_m=1.3e5, ky_N_per_m=2.1e5, cy_N_s_per_m=1.7e4, height_m=1.0)
    consist = _two_cars(cp)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    train = build_train(mbs, consist, speed_m_s=0.0, wheel_rail="springs")
    dx, dy = 2.0e-3, 1.5e-3                    # car 2 back by dx (gap grows), right by dy
    v1, w1 = (0.01, -0.01), 0.002              # car 1: forward 0.01 m/s, left 0.01 m/s, yaw rate 0.002 rad/s
    v2 = (0.04, 0.02)                          # car 2: forward 0.04 m/s (catching up), right 0.02 m/s
    for k, (q_set, v_set) in enumerate((({}, {0: v1[0], 1: v1[1], 5: w1}), ({0: -dx, 1: dy}, {0: v2[0], 1: v2[1]}))):
        node = train.cars[k].car_body.node
        q0 = np.array(mbs.GetNodeParameter(node, "initialCoordinates"), dtype=float)
        v0 = np.array(mbs.GetNodeParameter(node, "initialVelocities"), dtype=float)
        for i, val in q_set.items():
            q0[i] += val
        for i, val in v_set.items():
            v0[i] = val                        # RotVecLG: velocities (3 translational, 3 angular; rotation 0)
        mbs.SetNodeParameter(node, "initialCoordinates", q0.tolist())
        mbs.SetNodeParameter(node, "initialVelocities", v0.tolist())
    mbs.Assemble()
    f = train.coupler_forces_N(mbs)[0]
    half = 0.5 * consist.cars[0].length_m                      # the rear end is L/2 behind car 1's centre
    assert train.cars[0].car_body.p_cg_in_frame[0] == 0.0      # car body CG at the car's centre (lever arm L/2)
    gap_rate = v1[0] - v2[0]                                   # -0.03 m/s: closing
    vy_front_end = v1[1] + w1 * (-half)
    f_x = -(cp.kx_N_per_m * dx + cp.cx_N_s_per_m * gap_rate)   # -16000 + 3900 N
    f_y = cp.ky_N_per_m * dy + cp.cy_N_s_per_m * (v2[1] - vy_front_end)
    assert f[0] == pytest.approx(f_x, rel=1e-9)
    assert f[1] == pytest.approx(f_y, rel=1e-9)
    assert f[2] == 0.0                  # no vertical stiffness or damping: an exact zero


def test_static_axle_loads_sum_to_the_train_weight():
    """CRH6 8-car set: the lever-rule wheel loads of every car sum to its weight (exact up to rounding); the contact
    forces at t = 0, after every car was put on the rails, sum to each car's weight within what the creep forces at
    the initial state may add: place_on_rails balances the normal forces without creep; the connector adds the
    vertical part of the creep forces on the inclined contact planes, at most μ N sin γ per wheel."""
    consist = load_consist("crh6_intercity_8car")
    vehicle = consist.cars[0].vehicle
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    train = build_train(mbs, consist, speed_m_s=30.0)
    add_train_contact(mbs, train, _pair(vehicle), mu=0.3)
    mbs.Assemble()
    train.contact.warm_up(mbs, jacobian=False)
    # the car's weight by hand from vehicles/crh6_intercity_car.toml ([car_body] 37 200 kg, [bogie_frame] 2 700 kg
    # twice, [wheelset] 1 935 kg four times), not through the package's mass sums
    car_weight = (37200.0 + 2 * 2700.0 + 4 * 1935.0) * G
    weight = 8 * car_weight
    loads = train.static_wheel_loads_N()
    assert loads.shape == (32, 2)
    assert loads.sum() == pytest.approx(weight, rel=1e-12)
    res = train.contact.results
    q = -np.nansum(res[:, :, RES_F_TRACK_Z], axis=1).reshape(-1, 2)     # per wheel
    bound = 0.3 * math.sin(np.nanmax(np.abs(res[:, :, RES_GAMMA])))
    for k in range(consist.n_cars):
        w = train.wheelset_range(k)
        assert loads[w.start:w.stop].sum() == pytest.approx(car_weight, rel=1e-12)
        assert abs(q[w.start:w.stop].sum() / car_weight - 1.0) <= bound


def _offset_cg_consist(tmp_path, cg_x_m=(1.2, -0.7)) -> Path:
    """A 2-car train of Manchester vehicles 1 (vehicles/manchester_vehicle1.toml) whose car bodies' centres of mass
    lie ``cg_x_m`` ahead of the car centres (car 1 nose-heavy, car 2 tail-heavy): every bogie then carries a
    different load."""
    from exudyn_wheelrail.rolling_stock.vehicle_data import VEHICLES_DIR
    text = (VEHICLES_DIR / "manchester_vehicle1.toml").read_text()
    head = "[car_body]\nmass_kg = 32000.0\n"
    assert text.count(head) == 1
    lines = []
    for k, cg in enumerate(cg_x_m):
        path = tmp_path / f"car{k + 1}.toml"
        path.write_text(text.replace(head, f"{head}cg_x_m = {cg!r}\n"))
        lines.append(f'[[car]]\nvehicle = "{path}"\nlength_m = 26.0\n')
    consist = tmp_path / "offset_cg.toml"
    consist.write_text('schema_version = 1\n[train]\nname = "offset CG"\nsource = "assumed"\n' + "".join(lines))
    return consist


def test_axle_loads_by_the_lever_rule_are_the_simulated_static_contact_forces(tmp_path):
    """Per-axle static loads of a 2-car train whose car bodies' centres of mass are off the car centres, by hand
    from the vehicle files (read here with tomllib, not through the package): the car body's weight W on its two
    bogie pivots (x = +-l_b) by the lever rule, W (l_b +- x_cg) / (2 l_b) on the front/rear bogie; each bogie's
    load plus its frame's weight shared equally by its two wheelsets (the bogie frame's centre of mass midway
    between them); plus the wheelset's weight; left and right wheels equal (no lateral offset).

    Checked against (1) the package's static wheel loads (the same sums: 1e-12 relative) and (2) the simulated
    vertical contact forces, all wheels and both cars in one connector, 0.2 s at 30 m/s on perfect track.  The
    model starts each car's wheelsets at the height of the car's mean wheel load, so a wheelset carrying more or less
    bounces on its Hertz springs (~180 Hz, damping ratio ~0.2 %) about its static load; a Hann-weighted time mean
    of the contact force removes that oscillation (leakage of a sine over ~36 periods through the Hann window: well
    below 1e-4 of its amplitude, ~10 % of the load).  What stays is physical: the rolling resistance of the coned
    contacts (~1 N per wheel, carried to the longitudinal restraint at the car body's height) shifts load between
    the wheelsets by ~1e-4.  Tolerance 1e-3 of each axle load; a wrong lever (the CG offset's sign) errs by 5-16 %,
    a bogie frame's weight left out by 12 %."""
    import tomllib

    consist_path = _offset_cg_consist(tmp_path)
    expected = []
    for k in (1, 2):
        data = tomllib.loads((tmp_path / f"car{k}.toml").read_text())
        m_cb, x_cg = data["car_body"]["mass_kg"], data["car_body"]["cg_x_m"]
        m_bf, m_ws = data["bogie_frame"]["mass_kg"], data["wheelset"]["mass_kg"]
        lb, a = data["geometry"]["semi_bogie_centre_distance_m"], data["geometry"]["semi_wheelbase_m"]
        for x_bogie in (lb, -lb):                                      # front bogie first
            pivot = m_cb * G * (lb + math.copysign(1.0, x_bogie) * x_cg) / (2.0 * lb)
            expected += [0.5 * (pivot + m_bf * G) + m_ws * G] * 2     # its wheelsets at x_bogie + a, x_bogie - a
        assert a < lb
    expected = np.array(expected)
    assert np.ptp(expected) > 0.15 * expected.mean()                 # the loads really differ (20 kN)

    consist = load_consist(consist_path)
    assert [c.vehicle.car_body.cg_x_m for c in consist.cars] == [1.2, -0.7]
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    V = 30.0
    train = build_train(mbs, consist, speed_m_s=V, gravity_m_s2=G)
    add_train_contact(mbs, train, _pair(consist.cars[0].vehicle))
    loads = train.static_wheel_loads_N()
    np.testing.assert_allclose(loads.sum(axis=1), expected, rtol=1e-12)
    np.testing.assert_allclose(loads, np.column_stack([expected, expected]) / 2, rtol=1e-12)
    mbs.Assemble()
    train.contact.warm_up(mbs)
    rows = []

    def record(mbs_, t):
        rows.append(-np.nansum(train.contact.results[:, :, RES_F_TRACK_Z], axis=1))   # upward on each wheel
        return True

    out = run(mbs, RunSettings(solver="rk44", dt_s=1e-3, duration_s=0.2), train.contact, speed_m_s=V,
              user_function=record)
    assert out.status.kind == "ok"
    q = np.array(rows)                                                 # (steps, wheels)
    assert len(q) >= 199
    hann = np.sin(np.pi * (np.arange(len(q)) + 0.5) / len(q)) ** 2
    q_static = hann @ q / hann.sum()
    per_axle = q_static.reshape(-1, 2).sum(axis=1)
    np.testing.assert_allclose(per_axle, expected, rtol=1e-3)
    np.testing.assert_allclose(q_static, np.repeat(expected, 2) / 2, rtol=1e-3)
    # the start was not already the answer: the wheel loads at t = 0 differ from the static ones by several %
    assert np.max(np.abs(q[0].reshape(-1, 2).sum(axis=1) / expected - 1.0)) > 0.03


# ------------------------------------------------------------------------------------------- the scenario path
_TWO_CARS_TOML = ('schema_version = 1\n[train]\nname = "two coaches"\nsource = "assumed"\n'
                  '[[car]]\nvehicle = "manchester_vehicle1"\nlength_m = 26.0\ncount = 2\n')


def _train_scenario(consist_path, **vehicle):
    return {"schema_version": 2, "vehicle": {"consist": str(consist_path), "speed_km_h": 108.0, **vehicle},
            "track": [{"type": "harmonic", "amplitude_m": 0.002, "wavelength_m": 25.0, "direction": "lateral"}],
            "run": {"solver": "rk44", "dt_s": 1e-3, "duration_s": 0.1, "progress": False},
            "outputs": {"timeseries": ["Y", "Q", "YQ", "carbody"], "plots": False}}


def test_scenario_runs_a_train_with_outputs_per_car(tmp_path):
    from exudyn_wheelrail.scenarios.scenario import run_scenario
    p = tmp_path / "two.toml"
    p.write_text(_TWO_CARS_TOML)
    result = run_scenario(_train_scenario(p), tmp_path / "out")
    s = result.summary
    assert s["status"] == "ok"
    ts = result.timeseries
    for j in range(1, 9):                                             # every wheel of both cars
        assert f"Y_w{j}_right_N" in ts and f"YQ_w{j}_left" in ts
    for k in (1, 2):
        for point in ("rear", "front"):
            assert np.isfinite(ts[f"carbody_lateral_acceleration_{point}_c{k}_m_s2"]).all()
    cars = s["criteria"]["cars"]
    assert [c["car"] for c in cars] == [1, 2]
    # each car's criteria judge its own wheels (train numbering) and its own car-body point
    assert set(cars[1]["criteria"]["wheel_unloading"]) == {f"w{j}_{side}" for j in range(5, 9)
                                                           for side in ("right", "left")}
    assert cars[1]["criteria"]["carbody_lateral"]["column"] == "carbody_lateral_accelerometer_rear_c2_m_s2"
    assert s["criteria"]["passed"] == all(c["passed"] for c in cars) and s["scalars"]["criteria.car2.passed"] in (
        True, False)
    assert s["model"]["cars"][1]["wheelsets"] == [5, 6, 7, 8] and s["model"]["cars"][1]["x_m"] == -26.0
    assert (tmp_path / "out" / "summary.json").is_file()


def test_scenario_train_bad_input(tmp_path):
    from exudyn_wheelrail.scenarios.spec import ScenarioError, validate_scenario
    bad = tmp_path / "bad.toml"
    bad.write_text(_TWO_CARS_TOML.replace("count = 2", "count = 2\n[coupling]\nkx_N_per_m = -1.0"))
    with pytest.raises(ScenarioError, match=rf"vehicle.consist: {bad}: coupling.kx_N_per_m: "):
        validate_scenario(_train_scenario(bad), source="s.toml")
    good = tmp_path / "two.toml"
    good.write_text(_TWO_CARS_TOML)
    with pytest.raises(ScenarioError, match="s.toml: vehicle.overrides: not available for a train"):
        validate_scenario(_train_scenario(good, overrides={"primary.ky_N_per_m": 1.0}), source="s.toml")
    with pytest.raises(ScenarioError, match="s.toml: vehicle: give exactly one"):
        validate_scenario(_train_scenario(good, name="manchester_vehicle1"), source="s.toml")
    # the normal form validates again to itself
    scn = validate_scenario(_train_scenario(good))
    assert validate_scenario(scn) == scn


# ------------------------------------------------------------------------------------ full interaction, bridge
def _scaled_wheelset_consist(tmp_path, scale: float) -> Path:
    """A consist of one vehicles/single_wheelset.toml whose wheelset mass and inertias are scaled by ``scale`` (its
    dead load, the 'car' above an infinitely soft suspension, unchanged)."""
    from exudyn_wheelrail.rolling_stock.vehicle_data import VEHICLES_DIR
    text = (VEHICLES_DIR / "single_wheelset.toml").read_text()
    for key, value in (("mass_kg", 1813.0), ("Ixx_kg_m2", 1120.0), ("Iyy_kg_m2", 112.0), ("Izz_kg_m2", 1120.0)):
        old = f"{key} = {value}"
        assert text.count(old) == 1
        text = text.replace(old, f"{key} = {value * scale!r}")
    vehicle = tmp_path / f"wheelset_{scale}.toml"
    vehicle.write_text(text)
    consist = tmp_path / f"consist_{scale}.toml"
    consist.write_text(f'schema_version = 1\n[train]\nname = "wheelset x {scale}"\nsource = "assumed"\n'
                       f'[[car]]\nvehicle = "{vehicle}"\nlength_m = 3.0\n')
    return consist



@pytest.mark.parametrize("scale", [1.0, 0.1])
def test_hertz_step_bound_is_half_the_resolution_step_of_the_wheelset_bounce_worked_by_hand(tmp_path, scale):
    """The bridge crossing's step bound with vehicles (scenarios/bridge_crossing_vehicles.py module docstring): half the
    step h at which the wheelset bouncing on its two wheels' linearised Hertz springs (in parallel: 2 k_H, mass m)
    reaches omega h = 2 sqrt 2 (RK44's stability limit), omega = sqrt(2 k_H/m).  Worked here for
    vehicles/single_wheelset.toml with its wheelset mass m = 1813 kg x scale: Q = 45653.29 N + m x 9.81 m/s2 / 2 per
    wheel (the file's dead load per side and half the wheelset's weight; 54546.0 N at scale 1), r0 = 0.46 m; k_H = 1.5 Q/delta from
    RailSprings.from_hertz (the contact module's Hertz solution, tested against Hertz's tables elsewhere).
    Tolerance: the wheel load by hand against the load path's sum (a few ulp), through k_H ~ Q^(1/3): 1e-9."""
    from exudyn_wheelrail.rolling_stock.train import load_consist
    from exudyn_wheelrail.rolling_stock.vehicle_builder import RailSprings
    from exudyn_wheelrail.scenarios.bridge_crossing_vehicles import hertz_dt_bound_s

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                    # 181 kg is an unusual wheelset mass
        consist = load_consist(_scaled_wheelset_consist(tmp_path, scale))
    q_wheel = 45653.29 + 1813.0 * scale * 9.81 / 2.0
    k_h = RailSprings.from_hertz(wheel_load_N=q_wheel, r0_m=0.46).k_vertical_N_per_m
    omega = math.sqrt(2.0 * k_h / (1813.0 * scale))
    assert hertz_dt_bound_s(consist) == pytest.approx(0.5 * 2.0 * math.sqrt(2.0) / omega, rel=1e-9)
def test_full_interaction_tends_to_moving_load_as_unsprung_mass_vanishes(tmp_path):
    """One wheelset under a dead load (single_wheelset: the load above it is a constant force, the limit of an
    infinitely soft suspension) crossing a 20 m span, full interaction (bridge-crossing --model vehicles) against
    the moving constant axle load of the same consist (its static axle load: dead load + wheelset weight).  What
    separates them is the wheelset's inertia on the moving deck (force m z̈ ≈ 1813 kg × 0.33 m/s² ≈ 600 N against
    109 kN, 0.5 %) and the Hertz spring's dynamics: the difference of the mid-span deflection must shrink with the
    mass, linearly (the inertia force is m z̈): by at least 8 x for a 10 x smaller mass (measured 9.9 x; the margin
    covers what the Hertz spring's own dynamics add) — and be below 0.1 % of the peak at 0.1 x (measured 0.075 %).
    Same time step for both models (the stiffer contact's bound), so the rows are at the same times."""
    from exudyn_wheelrail.rolling_stock.train import load_consist
    from exudyn_wheelrail.scenarios.bridge_crossing import BridgeCrossing, run_bridge_crossing
    from exudyn_wheelrail.scenarios.bridge_crossing_loads import consist_axles
    from exudyn_wheelrail.scenarios.bridge_crossing_vehicles import hertz_dt_bound_s

    paths = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                    # 181 kg is an unusual wheelset mass: that is the point
        for scale in (1.0, 0.1):
            paths[scale] = _scaled_wheelset_consist(tmp_path, scale)
        dt = hertz_dt_bound_s(load_consist(paths[0.1]))
        diff = {}
        for scale, path in paths.items():
            runs = {}
            for model in ("vehicles", "moving-loads"):
                case = BridgeCrossing(span_m=20.0, mass_kg_m=15e3, f1_Hz=6.0, damping_ratio=0.01, n_modes=3,
                                      axles=consist_axles(path) if model == "moving-loads" else None,
                                      speed_m_s=200 / 3.6, model=model, train_file=str(path), free_vibration_s=0.1,
                                      dt_s=dt)
                runs[model] = run_bridge_crossing(case)
                assert runs[model].summary["status"] == "ok"
            a, b = (runs[m].timeseries for m in ("vehicles", "moving-loads"))
            assert np.array_equal(a["time_s"], b["time_s"])  # the same time grid: bit-equality
            w_ref = b["deck_midspan_displacement_m"]
            diff[scale] = np.max(np.abs(a["deck_midspan_displacement_m"] - w_ref)) / np.max(np.abs(w_ref))
    assert diff[1.0] > 3e-3                                 # the interaction is visible at the real mass
    assert diff[0.1] < diff[1.0] / 8 and diff[0.1] < 1e-3, diff


def test_bridge_crossing_vehicles_checks_the_consist_before_any_work(tmp_path):
    from exudyn_wheelrail.scenarios.bridge_crossing import BridgeCrossing, resolve_load_model
    bad = tmp_path / "bad.toml"
    bad.write_text(_TWO_CARS_TOML.replace("length_m = 26.0", "length_m = 10.0"))
    model = resolve_load_model("vehicles")
    case = BridgeCrossing(span_m=20.0, mass_kg_m=15e3, f1_Hz=6.0, damping_ratio=0.01, n_modes=3, axles=None,
                          speed_m_s=50.0, model="vehicles", train_file=str(bad))
    with pytest.raises(ValueError, match=rf"^--train: {bad}: car.0.length_m: 10.0 m: shorter than"):
        model.check(case)
    with pytest.raises(ValueError, match="^--train: the vehicles model needs a consist file"):
        model.check(BridgeCrossing(span_m=20.0, mass_kg_m=15e3, f1_Hz=6.0, damping_ratio=0.01, n_modes=3,
                                   axles=None, speed_m_s=50.0, model="vehicles"))


def test_consist_axles_are_the_static_wheelset_loads_behind_the_leader():
    """The moving-load model of a consist (manchester_x8: 8 Manchester vehicles 1, 26 m long, end to end), by hand
    from vehicles/manchester_vehicle1.toml: the wheelsets of one car at ±9.5 ± 1.28 m about its centre
    (semi_bogie_centre_distance_m, semi_wheelbase_m), i.e. 0, 2.56, 19, 21.56 m behind its leading one, car k's
    shifted by 26 k m; every axle of the symmetric car (centres of mass on the car's and the bogies' centres) carries
    a quarter of the car body (32 000 kg), half a bogie frame (2 615 kg) and its own wheelset (1 813 kg):
    11 120.5 kg g; the train 8 (32 000 + 2 x 2 615 + 4 x 1 813) kg g.  Places: sums of a few decimals below 200 m,
    1e-12 m; loads: a few roundings, 1e-12 relative."""
    from exudyn_wheelrail.scenarios.bridge_crossing_loads import consist_axles
    axles = consist_axles("manchester_x8")
    one_car = np.array([0.0, 2.56, 19.0, 21.56])
    assert np.allclose(axles.x_m, np.concatenate([one_car + 26.0 * k for k in range(8)]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(axles.load_N, (32000.0 / 4 + 2615.0 / 2 + 1813.0) * G, rtol=1e-12, atol=0)
    assert axles.load_N.sum() == pytest.approx(8 * (32000.0 + 2 * 2615.0 + 4 * 1813.0) * G, rel=1e-12)
