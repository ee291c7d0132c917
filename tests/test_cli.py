"""The command line's contract that scripts and regression tests rely on: the geometry CSV's leading columns and
its sweep, profile point files giving the analytic profiles' geometry, the conicity line, bad input -> exit code 2.

Each command's contract is checked once through a process (``python -m exudyn_wheelrail``: exit code, stdout,
stderr); further cases of the same command call its entry point :func:`exudyn_wheelrail.cli.main` in this process,
which returns the code the process exits with (``__main__``: ``sys.exit(main())``)."""
import csv
import re
import subprocess
import sys

import pytest
from reference_paths import PROFILES_DIR

from exudyn_wheelrail.cli import main as cli_main

PROFILES = PROFILES_DIR
CONTRACT_COLUMNS = ["y_m", "side", "region", "y_rail_m", "y_wheel_m", "contact_angle_rad", "rolling_radius_m",
                    "roll_rad", "a_m", "b_m"]


def run(*args):
    return subprocess.run([sys.executable, "-m", "exudyn_wheelrail", *args], capture_output=True, text=True,
                          timeout=300)


def read(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def builtin_csv(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "g.csv"
    r = run("geometry", "--wheel", "S1002", "--rail", "UIC60", "--inclination", "1/40", "--gauge", "1.435",
            "--back-to-back", "1.360", "--r0", "0.46", "--y-max", "0.010", "--y-step", "0.0005", "--out", str(out),
            "--plot", str(out.with_suffix(".png")))
    assert r.returncode == 0, r.stderr
    return out


def test_geometry_columns_and_sweep(builtin_csv):
    rows = read(builtin_csv)
    assert list(rows[0].keys())[:len(CONTRACT_COLUMNS)] == CONTRACT_COLUMNS
    ys = sorted({float(r["y_m"]) for r in rows})
    assert len(ys) == 41 and ys[0] == pytest.approx(-0.010) and ys[-1] == pytest.approx(0.010)
    for y in ys:          # every shift has a contact on each wheel
        sides = {r["side"] for r in rows if float(r["y_m"]) == y}
        assert sides == {"left", "right"}
    assert {r["region"] for r in rows} == {"tread", "flange"}
    assert builtin_csv.with_suffix(".png").stat().st_size > 10_000


def test_point_files_through_the_readers_reproduce_the_analytic_profiles(builtin_csv, tmp_path):
    # independent route: the Manchester benchmark point files (SIMPACK format, the UIC60 file already canted 1:40)
    out = tmp_path / "files.csv"
    assert cli_main(["geometry", "--wheel", str(PROFILES / "MBench_S1002_v3.prw"), "--rail",
                     str(PROFILES / "MBench_UIC60_v3.prr"), "--rail-canted", "1/40", "--inclination", "1/40",
                     "--out", str(out)]) == 0
    a, b = read(builtin_csv), read(out)
    assert [(x["y_m"], x["side"], x["region"]) for x in a] == [(x["y_m"], x["side"], x["region"]) for x in b]
    # the profiles agree to 0.1 µm; the sweep's rolling radii (hence Δr) to well below 1 µm
    for key, tol in (("rolling_radius_m", 1e-6), ("y_wheel_m", 1e-5), ("contact_angle_rad", 1e-3)):
        diff = max(abs(float(x[key]) - float(y[key])) for x, y in zip(a, b))
        assert diff < tol, (key, diff)


def test_conicity_prints_a_value_in_the_published_range(capsys):
    r = run("conicity", "--wheel", "S1002", "--rail", "UIC60", "--inclination", "1/40", "--amplitude", "0.003")
    assert r.returncode == 0, r.stderr
    value = float(re.search(r"equivalent conicity ([0-9.]+)", r.stdout).group(1))
    assert 0.1 < value < 0.25          # new S1002 on UIC60 1:40, 1435 mm: the range quoted in tests/test_geometry_sweep
    assert cli_main(["conicity", "--amplitude", "0.003", "--method", "wavelength"]) == 0
    value_w = float(re.search(r"equivalent conicity ([0-9.]+)", capsys.readouterr().out).group(1))
    assert value_w == pytest.approx(value, rel=0.05)   # the two definitions agree to first order


def test_bad_input_is_a_clear_error(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("y,z\n0,0\n1,nan\n")
    r = run("geometry", "--wheel", str(bad), "--out", str(tmp_path / "x.csv"))
    assert r.returncode == 2 and "bad.csv" in r.stderr
    assert cli_main(["geometry", "--gauge", "14.35", "--out", str(tmp_path / "x.csv")]) == 2
    assert "gauge" in capsys.readouterr().err
