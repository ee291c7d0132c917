"""Measured worn profiles (examples/profiles, examples/worn_profiles.py): read by the project's readers, and their
conformal contact, where Hertz is wrong and the non-Hertzian patch is not, against the exact half-space solution.

Reference: the normal problem on the elastic half-space solved exactly over the profiles' own interpenetration
(contact.halfspace, checked against Hertz in test_contact_patch.py).  Tolerances: the patch's accuracy targets
against that solution (force 3 %, area 10 %); the contact angle's error absolute, 1 mrad: that target's 2 % at the
largest angle of the sweep (0.05 rad), since on a hollow tread the angle passes through zero where no relative error
is meaningful.
"""
import sys
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.cli import main as cli_main
from exudyn_wheelrail.profiles.profiles import RailProfile

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
import worn_profiles as W  # noqa: E402

FORCE_TOL, AREA_TOL, ANGLE_TOL_RAD = 0.03, 0.10, 1e-3


@pytest.fixture(scope="module")
def sweep():
    return W.run([0.0, 13e-3, 15e-3])


def test_worn_rail_needs_its_inclination_stated():
    """A worn head's crown does not show the rail's inclination: a stated value is refused against the estimate,
    and taken as it is with worn=True (within the plausible range), which in turn needs it stated."""
    with pytest.raises(ValueError, match="looks inclined"):
        RailProfile.from_file(W.RAIL_FILE, canted_tan=0.0)
    with pytest.raises(ValueError, match="worn rail head needs the inclination"):
        RailProfile.from_file(W.RAIL_FILE, canted_tan=None, worn=True)
    assert RailProfile.from_file(W.RAIL_FILE, canted_tan=0.0, worn=True).canted_tan == 0.0
    for bad in (float("nan"), 0.5):
        with pytest.raises(ValueError, match="canted_tan"):
            RailProfile.from_file(W.RAIL_FILE, canted_tan=bad, worn=True)


def test_measured_pair_is_placed_as_stated():
    """The placed rails are 1435.1 mm apart at CONTACT's gauge depth of 15.875 mm (measured on the placed rail:
    the fitted curve's sampling, 2 µm, bounds the error); the wheel's tape circle is 70 mm from its flange back
    with z = 0 there within the file's digits; the flange's height and tip are those of the file's points (the
    tip's top is flat: its position within 0.5 mm)."""
    from exudyn_wheelrail.contact.pair import gauge_point
    pair = W.build_pair()
    _, y_gauge = gauge_point(pair.rail_side, W.GAUGE_DEPTH_M)
    assert 2.0 * y_gauge == pytest.approx(W.GAUGE_M, abs=4e-6)
    y, z, _ = W.read_simpack_profile(W.WHEEL_FILE, kind="wheel")
    tip = int(np.argmax(z))
    assert pair.wheel.flange_height_m == pytest.approx(z[tip], abs=1e-5)
    assert pair.wheel.flange_tip_y_m == pytest.approx(y[tip] - 0.070, abs=0.5e-3)   # the tip's top is flat
    assert abs(float(pair.wheel.curve.position([pair.wheel.s_at_y(0.0)])[0, 1])) < 1e-6


def test_patch_meets_the_exact_solution_where_hertz_does_not(sweep):
    """At 0 mm the contact is nearly Hertzian (Hertz within 2 % in force); at 13 and 15 mm the hollow wheel lies in
    the worn rail over 18-24 mm: Hertz misses the area by more than 20 % and the force by more than 5 %, the patch
    meets the exact solution within its targets everywhere."""
    by_y = {round(r["y_m"] * 1e3): r for r in sweep if r["region"] == "tread"}
    assert set(by_y) == {0, 13, 15}
    for row in sweep:
        for method in ("patch", "pass"):        # the patch itself, and what contact_patch="non-hertzian" writes
            p = W.errors(row, method)
            assert abs(p["normal_force_N"]) < FORCE_TOL, (method, row)
            assert abs(p["area_m2"]) < AREA_TOL, (method, row)
            assert abs(p["contact_angle_rad"]) < ANGLE_TOL_RAD, (method, row)
    assert abs(W.errors(by_y[0], "hertz")["normal_force_N"]) < 0.02
    for y in (13, 15):
        h = W.errors(by_y[y], "hertz")
        assert h["area_m2"] < -0.20 and h["normal_force_N"] < -0.05, (y, h)
        assert by_y[y]["lateral_extent_m"] > 0.015


def test_example_command_line(tmp_path, capsys):
    out = tmp_path / "worn.csv"
    assert W.main(["--out", str(out), "--y-mm", "12"]) == 0
    header = out.read_text().splitlines()[0].split(",")
    assert tuple(header) == W.COLUMNS
    for bad in ("12;13", "nan", "40"):
        with pytest.raises(SystemExit):
            W.main(["--out", str(out), "--y-mm", bad])
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("error: --y-mm"), err


def test_worn_rail_on_the_command_line(tmp_path, capsys):
    """The geometry command takes the worn rail with --rail-canted and --rail-worn; --rail-worn alone, or the file
    without it, is a one-line error before any work."""
    out = tmp_path / "geometry.csv"
    base = ["geometry", "--rail", str(W.RAIL_FILE), "--inclination", "none", "--y-max", "0.004", "--y-step", "0.002",
            "--out", str(out)]
    assert cli_main(base + ["--rail-canted", "0", "--rail-worn"]) == 0
    assert out.exists()
    out.unlink()
    builtin = ["geometry", "--rail", "UIC60", "--out", str(out)]
    for args, words in ((base + ["--rail-worn"], "--rail-worn: a worn rail head needs --rail-canted"),
                        (base + ["--rail-canted", "0"], "--rail-worn"),
                        (builtin + ["--rail-canted", "1/40", "--rail-worn"], "--rail-worn: applies to a measured"),
                        (base + ["--rail-canted", "0.5", "--rail-worn"], "--rail-canted")):
        assert cli_main(args) != 0
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("error:") and words in err[0], err
        assert not out.exists()
