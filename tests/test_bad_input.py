"""Bad input gets one clear line before any work: on the command line ``error: <what>: <problem>`` on stderr with exit
code 2 (no traceback, no usage block, nothing on stdout), in the Python API a ``ValueError`` with the same kind of
message.  An unusual but plausible value is one line ``warning: ...`` and the run goes on.

The profile files are the Manchester benchmark files of the shared references; the y-z tables are their points as
the SIMPACK reader returns them (the documented profile frame), written in millimetres as a profile gauge would.
"""
import math
import re
import shutil
import subprocess
import sys
import time
import warnings

import numpy as np
import pytest
from reference_paths import PROFILES_DIR

from exudyn_wheelrail.cli import main as cli_main
from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
from exudyn_wheelrail.contact.normal import HertzContact, effective_modulus
from exudyn_wheelrail.creep import (fastsim, kalker_coefficients, kalker_exact, linear_creep_forces, polach,
                                    shen_hedrick_elkins, table_forces)
from exudyn_wheelrail.creep.build_table import build_table
from exudyn_wheelrail.rolling_stock.vehicle_data import VEHICLES_DIR, VehicleDataError, load_vehicle
from exudyn_wheelrail.profiles import RailProfile, WheelProfile
from exudyn_wheelrail.profiles.profiles import RAIL_PROFILE_NAMES, WHEEL_PROFILE_NAMES, resolve_rail, resolve_wheel
from exudyn_wheelrail.profiles.readers import ProfileError, profile_shape, read_simpack_profile
from exudyn_wheelrail.profiles.standard import s1002_dense, uic60_dense
from exudyn_wheelrail.scenarios.scenario import ScenarioError, load_scenario
from exudyn_wheelrail.validation import InputWarning

WHEEL_FILE = PROFILES_DIR / "MBench_S1002_v3.prw"
RAIL_FILE = PROFILES_DIR / "MBench_UIC60_v3.prr"
SCENARIO = """\
schema_version = 2
[vehicle]
name = "manchester_vehicle1"
speed_km_h = 100.0
[[track]]
type = "harmonic"
amplitude_m = {amplitude}
wavelength_m = {wavelength}
[run]
duration_s = 0.01
"""


def cli(*args):
    return subprocess.run([sys.executable, "-m", "exudyn_wheelrail", *map(str, args)], capture_output=True,
                          text=True, timeout=300)


def one_line_error(r, what, *fragments):
    """The run stopped with exit code 2 and exactly one line 'error: <what>: ...' holding every fragment, before
    any work (nothing on stdout)."""
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith(f"error: {what}: "), lines[0]
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])
    assert r.stdout == "", r.stdout
    return lines[0]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """The reference files as given, renamed to a neutral extension, with the header's type removed and the other
    kind's extension, and as y-z tables in the profile frame (mm); plus a regular file to put paths below."""
    d = tmp_path_factory.mktemp("bad_input")
    out = {"wheel": WHEEL_FILE, "rail": RAIL_FILE}
    for kind, src in (("wheel", WHEEL_FILE), ("rail", RAIL_FILE)):
        shutil.copy(src, d / f"{kind}_renamed.txt")
        y, z, _ = read_simpack_profile(src)
        rows = "\n".join(f"{a * 1e3:.6f},{b * 1e3:.6f}" for a, b in zip(y, z))
        (d / f"{kind}_table.csv").write_text("y [mm],z [mm]\n" + rows + "\n")
        mirrored = "\n".join(f"{-a * 1e3:.6f},{b * 1e3:.6f}" for a, b in zip(y[::-1], z[::-1]))
        (d / f"{kind}_mirrored.csv").write_text("y [mm],z [mm]\n" + mirrored + "\n")
        out[f"{kind}_renamed"] = d / f"{kind}_renamed.txt"
        out[f"{kind}_table"] = d / f"{kind}_table.csv"
        out[f"{kind}_mirrored"] = d / f"{kind}_mirrored.csv"
    # the rail file without its header type, named as a wheel file: only the shape can tell
    text = re.sub(r"(?m)^\s*type\s*=\s*0.*$", "", RAIL_FILE.read_text(), count=1)
    (d / "rail_untyped.prw").write_text(text)
    out["rail_untyped_as_prw"] = d / "rail_untyped.prw"
    out["regular_file"] = d / "file.txt"
    out["regular_file"].write_text("not a directory\n")
    out["dir"] = d
    return out


# ------------------------------------------------------------------------ 1. a rail given as a wheel and the reverse
@pytest.mark.parametrize("option, given, words", [
    ("--wheel", "rail", ["wheel profile", "rail profile"]),
    ("--rail", "wheel", ["rail profile", "wheel profile"]),
    ("--wheel", "rail_renamed", ["wheel profile", "rail profile"]),
    ("--rail", "wheel_renamed", ["rail profile", "wheel profile"]),
    ("--wheel", "rail_untyped_as_prw", ["given as a wheel profile but it looks like a rail head"]),
    ("--wheel", "rail_table", ["given as a wheel profile but it looks like a rail head", "72 mm wide"]),
    ("--rail", "wheel_table", ["given as a rail profile but it looks like a wheel profile", "flange"]),
    ("--wheel", "wheel_mirrored", ["mirrored"]),
])
def test_profile_of_the_other_kind_is_an_error(files, tmp_path, option, given, words):
    path = files[given]
    r = cli("geometry", option, path, "--out", tmp_path / "g.csv")
    one_line_error(r, str(path), *words)
    assert not (tmp_path / "g.csv").exists()


def test_profile_kind_errors_in_the_api(files):
    with pytest.raises(ProfileError, match="looks like a rail head"):
        resolve_wheel(files["rail_table"])
    with pytest.raises(ProfileError, match="looks like a wheel profile"):
        resolve_rail(files["wheel_table"])
    with pytest.raises(ValueError, match="looks like a rail head"):
        WheelRailPair(wheel=files["rail_untyped_as_prw"])
    with pytest.raises(ProfileError, match="looks like a rail head"):
        WheelProfile.from_dense(uic60_dense())
    with pytest.raises(ProfileError, match="looks like a wheel profile"):
        RailProfile.from_dense(s1002_dense())


def test_profiles_of_the_right_kind_pass(files):
    # the same tables in their roles are accepted (the check does not reject everything) ...
    wheel = WheelProfile.from_file(files["wheel_table"], smoothing=0)      # the file's exact points: interpolated
    rail = RailProfile.from_file(files["rail_table"], smoothing=0)
    assert wheel.flange is not None and 0.025 < wheel.flange_height_m < 0.035        # S1002: 28 mm over y = 0
    assert rail.canted_tan == pytest.approx(1 / 40)                                  # the file is canted 1:40
    # ... and the shape classification agrees with the analytic standards; shapes that are neither (a cone, a
    # crown: the analytic test profiles) are left alone
    assert profile_shape(s1002_dense().y, s1002_dense().z)[0] == "wheel"
    assert profile_shape(uic60_dense().y, uic60_dense().z)[0] == "rail"
    for curve in (WheelProfile.cone(0.05).curve, RailProfile.circular_crown(0.3).curve):
        p = curve.position(curve.nodes[:, 0])
        assert profile_shape(p[:, 0], p[:, 1])[0] is None


def test_the_check_comes_before_any_work(files, tmp_path, capsys):
    # requirement: the error within 10 s of the start; in-process (interpreter start-up excluded, so that a loaded
    # machine does not decide the result) the profile file is read and judged well within that
    t0 = time.perf_counter()
    code = cli_main(["geometry", "--wheel", str(files["rail_table"]), "--out", str(tmp_path / "g.csv")])
    elapsed = time.perf_counter() - t0
    err = capsys.readouterr().err
    assert code == 2 and err.startswith(f"error: {files['rail_table']}: ") and elapsed < 10.0, (code, err, elapsed)


# ----------------------------------------------------------------------------------- 2. elastic constants anywhere
def _single_wheelset():
    import exudyn as exu
    from exudyn_wheelrail.multibody import build_vehicle
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    model = build_vehicle(mbs, "single_wheelset", speed_m_s=30.0)
    return SC, mbs, model


def _materials_callers(tmp_path):
    """Every entry point that takes Poisson's ratio, as f(nu)."""
    from exudyn_wheelrail.multibody.connector import add_wheel_rail_contact
    pair = WheelRailPair()
    contact = (0.006, 0.004, 1e-3, 0.0, 0.0, 5e4, 0.3, 8.1e10)        # a, b, xi, eta, phi, N, mu, G

    def connector(nu):
        SC, mbs, model = _single_wheelset()
        return add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=30.0, nu_rail=nu)

    return {
        "effective_modulus": lambda nu: effective_modulus(2.1e11, nu, 2.1e11, 0.28),
        "HertzContact": lambda nu: HertzContact.from_curvatures(1 / 0.46, 0.0, 0.0, 1 / 0.3, nu_wheel=nu),
        "fastsim": lambda nu: fastsim(*contact, nu),
        "shen_hedrick_elkins": lambda nu: shen_hedrick_elkins(*contact, nu),
        "polach": lambda nu: polach(*contact, nu),
        "kalker_exact": lambda nu: kalker_exact(*contact, nu),
        "table_forces": lambda nu: table_forces(*contact, nu),
        "linear_creep_forces": lambda nu: linear_creep_forces(0.006, 0.004, 1e-3, 0.0, 0.0, 8.1e10, nu),
        "kalker_coefficients": lambda nu: kalker_coefficients(1.5, nu),
        "build_table": lambda nu: build_table(tmp_path / "t.npz", generator="fastsim", poisson=nu, progress=None),
        "WheelsetContact": lambda nu: WheelsetContact(pair, nu_wheel=nu),
        "connector": connector,
    }


@pytest.mark.parametrize("nu, words", [(0.7, "is not a Poisson's ratio"), (-1.5, "is not a Poisson's ratio"),
                                       (1.0, "is not a Poisson's ratio"), (math.nan, "is not a finite number")])
def test_poisson_ratio_outside_the_elastic_range_is_an_error_everywhere(tmp_path, nu, words):
    problems = set()
    for name, call in _materials_callers(tmp_path).items():
        with pytest.raises(ValueError) as err:
            call(nu)
        message = str(err.value)
        assert words in message, (name, message)
        problems.add(message.split(": ", 1)[1])     # one validation function: the same words after the name
    assert len(problems) == 1, problems
    assert not (tmp_path / "t.npz").exists()


def test_youngs_modulus_must_be_positive_and_finite():
    pair = WheelRailPair()
    for E in (0.0, -2.1e11, math.inf, math.nan):
        with pytest.raises(ValueError, match="E_wheel"):
            effective_modulus(E, 0.28, 2.1e11, 0.28)
        with pytest.raises(ValueError, match="E_rail_Pa"):
            WheelsetContact(pair, E_rail_Pa=E)
    with pytest.raises(ValueError, match="E_star"):
        HertzContact(1.0, 2.0, -1.0e11)
    from exudyn_wheelrail.multibody.connector import add_wheel_rail_contact
    SC, mbs, model = _single_wheelset()
    with pytest.raises(ValueError, match="E_wheel_Pa: 0 Pa is not a Young's modulus"):
        add_wheel_rail_contact(mbs, model.wheelset_nodes, pair, speed_m_s=30.0, E_wheel_Pa=0.0)


def test_the_limits_of_the_elastic_range_are_accepted():
    # 1/E* = 2 (1 - nu^2)/E: nu = 0.5 (incompressible) and nu = -0.5 both give E* = E / 1.5
    E = 2.1e11
    assert effective_modulus(E, 0.5, E, 0.5) == pytest.approx(E / 1.5, rel=1e-15)
    assert effective_modulus(E, -0.5, E, -0.5) == pytest.approx(E / 1.5, rel=1e-15)
    # the creep theories cover Kalker's table, 0 <= nu <= 0.5: an auxetic material is elastic but outside it
    with pytest.raises(ValueError, match="outside the range the creep theories"):
        fastsim(0.006, 0.004, 1e-3, 0.0, 0.0, 5e4, 0.3, 8.1e10, -0.5)


def test_cli_poisson_ratio(tmp_path):
    one_line_error(cli("creep-table", "--nu", "0.7", "--out", tmp_path / "t.npz"), "--nu", "Poisson's ratio")
    assert not (tmp_path / "t.npz").exists() and not (tmp_path / "t.npz.parts").exists()


# ----------------------------------------------------------------------------- 3. millimetres where metres belong
@pytest.mark.parametrize("args, option, unit", [
    (["geometry", "--gauge", "1435"], "--gauge", "millimetres"),
    (["geometry", "--back-to-back", "1360"], "--back-to-back", "millimetres"),
    (["geometry", "--r0", "460"], "--r0", "millimetres"),
    (["geometry", "--y-max", "10"], "--y-max", "millimetres"),
    (["geometry", "--y-step", "0.5"], "--y-step", "millimetres"),
    (["conicity", "--amplitude", "3"], "--amplitude", "millimetres"),
    (["rtri", "--span", "20000"], "--span", "millimetres"),
    (["rtri", "--dt", "1"], "--dt", "milliseconds"),
    (["rtri", "--transition-m", "3000"], "--transition-m", "millimetres"),
    (["rtri-sweep", "--spans", "20", "40000"], "--spans", "millimetres"),
])
def test_cli_value_in_the_wrong_unit(tmp_path, args, option, unit):
    out = ["--out", tmp_path / ("g.csv" if args[0] == "geometry" else "out")] if args[0] != "conicity" else []
    line = one_line_error(cli(*args, *out), option, "is not a plausible", f"{unit} given?", "expected about")
    assert not any(tmp_path.iterdir()), line


def test_api_value_in_the_wrong_unit(tmp_path):
    with pytest.raises(ValueError, match=r"gauge_m: 1435 is not a plausible track gauge in metres .*millimetres"):
        WheelRailPair(gauge_m=1435)
    with pytest.raises(ValueError, match=r"r0_m: 460 .*millimetres"):
        WheelRailPair(r0_m=460)
    for amplitude, wavelength, key in ((10, 25.0, "amplitude_m"), (0.002, 25000, "wavelength_m")):
        path = tmp_path / "s.toml"
        path.write_text(SCENARIO.format(amplitude=amplitude, wavelength=wavelength))
        with pytest.raises(ScenarioError, match=rf"s\.toml: track\.0\.{key}: .*millimetres given"):
            load_scenario(path)
    text = (VEHICLES_DIR / "manchester_vehicle1.toml").read_text()
    for old, new, key in (("semi_wheelbase_m = 1.28", "semi_wheelbase_m = 1280", "geometry.semi_wheelbase_m"),
                          ("clearance_m = 0.025", "clearance_m = 25", "bump_stop.clearance_m"),
                          ("cg_height_m = 1.80", "cg_height_m = 1800", "car_body.cg_height_m")):
        path = tmp_path / "v.toml"
        path.write_text(text.replace(old, new, 1))
        with pytest.raises(VehicleDataError, match=rf"v\.toml: {re.escape(key)}: .*millimetres given"):
            load_vehicle(path)


def test_unusual_values_warn_and_go_on(tmp_path):
    # a wheelset 1000 times heavier than usual: plausible input, a warning naming the file and the key
    text = (VEHICLES_DIR / "single_wheelset.toml").read_text()
    path = tmp_path / "heavy.toml"
    path.write_text(text.replace("mass_kg = 1813.0", "mass_kg = 1813000.0", 1))
    with pytest.warns(InputWarning, match=r"heavy\.toml: wheelset\.mass_kg: .*unusual wheelset mass"):
        vehicle = load_vehicle(path)
    assert vehicle.wheelset.mass_kg == 1813000.0
    with warnings.catch_warnings():                     # the shipped vehicles are usual
        warnings.simplefilter("error", InputWarning)
        load_vehicle("single_wheelset")
    # on the command line: one line 'warning: ...' and the run completes
    r = cli("geometry", "--wheel-load", "600e3", "--y-max", "0.001", "--y-step", "0.0005", "--out", tmp_path / "g.csv")
    assert r.returncode == 0, r.stderr
    assert r.stderr.strip().splitlines() == [r.stderr.strip()] and r.stderr.startswith("warning: --wheel-load: ")
    assert (tmp_path / "g.csv").stat().st_size > 0


# --------------------------------------------------------------------------------------- 4. unknown profile names
@pytest.mark.parametrize("option, name, names", [("--wheel", "S1003", WHEEL_PROFILE_NAMES),
                                                 ("--rail", "60E2", RAIL_PROFILE_NAMES)])
def test_unknown_profile_name(tmp_path, option, name, names):
    line = one_line_error(cli("geometry", option, name, "--out", tmp_path / "g.csv"), option, repr(name),
                          "neither a built-in", "nor an existing file")
    assert all(n in line for n in names)
    with pytest.raises(ProfileError, match=f"{name!r} is neither a built-in"):
        (resolve_wheel if option == "--wheel" else resolve_rail)(name)


# ---------------------------------------------------------------------------------------- 5. output locations
@pytest.mark.parametrize("args, option, place", [
    (["geometry", "--out", "{below}/g.csv"], "--out", "below"),
    (["geometry", "--out", "{dir}"], "--out", "dir"),
    (["geometry", "--out", "{dir}/g.csv", "--plot", "{below}/g.png"], "--plot", "below"),
    (["geometry", "--out", "{dir}/g.csv", "--plot", "{dir}/g.nosuchformat"], "--plot", "suffix"),
    (["creep-table", "--generator", "fastsim", "--out", "{below}/t.npz"], "--out", "below"),
    (["rtri", "--out", "{file}"], "--out", "file"),
    (["rtri-sweep", "--out", "{below}/sweep"], "--out", "below"),
    (["run", "{scenario}", "--out", "{file}"], "--out", "file"),
    (["sweep", "{scenario}", "--param", "vehicle.speed_km_h=100,150", "--out", "{below}/sweep"], "--out", "below"),
    (["validation-report", "--quick", "--out", "{file}"], "--out", "file"),
    (["explore", "--out", "{below}/x.png"], "--out", "below"),
])
def test_output_location_checked_before_any_work(files, tmp_path, args, option, place):
    scenario = tmp_path / "s.toml"
    scenario.write_text(SCENARIO.format(amplitude=0.002, wavelength=25.0))
    fill = dict(below=files["regular_file"], file=files["regular_file"], dir=tmp_path, scenario=scenario)
    r = cli(*(a.format(**fill) for a in args))
    words = {"below": "is a file, not a directory", "dir": "is a directory", "file": "existing file, not a directory",
             "suffix": "expected a figure file"}[place]
    one_line_error(r, option, words)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


# ------------------------------------------------------------------------------------------- 6. wheelset poses
def test_wheelset_pose_with_nan_names_the_entry():
    contact = WheelsetContact(WheelRailPair(), n_wheelsets=2)
    with pytest.raises(ValueError, match=r"wheelset 0 pose: y_m is NaN"):
        contact.evaluate([[np.nan, -0.46, 0.0], [0.0, -0.46, 0.0]])
    with pytest.raises(ValueError, match=r"wheelset 1 pose: roll_rad is NaN"):
        contact.evaluate([[0.0, -0.46, 0.0], [0.0, -0.46, np.nan]])
    with pytest.raises(ValueError, match=r"wheelset 1 pose: z_m is infinity"):
        contact.contact_points(0.0, np.inf, wheelset=1)
    with pytest.raises(ValueError, match=r"expected 2 pose\(s\) of 3 entries \(y_m, z_m, roll_rad\), got 3"):
        contact.evaluate([0.0, -0.46, 0.0])
    out = contact.evaluate([[0.0, -0.46, 0.0], [0.0, -0.46, 0.0]])      # still usable after the refusals
    assert np.all(np.isfinite(out[:, 0, 0]))


# ----------------------------------------------------------------------------------- Exudyn node type in messages
def test_wrong_node_type_names_the_node_type_to_use():
    import exudyn as exu
    from exudyn.itemInterface import NodeRigidBodyRxyz

    from exudyn_wheelrail.multibody.connector import add_wheel_rail_contact
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    node = mbs.AddNode(NodeRigidBodyRxyz(referenceCoordinates=[0.0, 0.0, -0.46, 0.0, 0.0, 0.0]))
    with pytest.raises(ValueError, match=r"RigidBodyRxyz node.*exu\.NodeType\.RotationRotationVector"):
        add_wheel_rail_contact(mbs, [node], WheelRailPair(), speed_m_s=30.0)


# ------------------------------------------------------------------------------------ argparse's own errors
@pytest.mark.parametrize("args, what", [([], "command"), (["frobnicate"], "command"), (["geometry"], "--out"),
                                        (["geometry", "--gauge", "wide", "--out", "x.csv"], "--gauge"),
                                        (["creep-table", "--workers", "0", "--out", "t.npz"], "--workers")])
def test_argument_errors_are_one_line(tmp_path, args, what):
    r = subprocess.run([sys.executable, "-m", "exudyn_wheelrail", *args], capture_output=True, text=True,
                       timeout=300, cwd=tmp_path)
    one_line_error(r, what)
    assert "usage:" not in r.stderr and not any(tmp_path.iterdir())
