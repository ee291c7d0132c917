"""The ``critical-speed`` command's contract: bad input is one line ``error: <option>: <problem>`` with exit code 2
before any work; the linearisation's coordinate map (exudyn_wheelrail/scenarios/critical_speed_linear.py) is the
rigid-body kinematics it claims; the whole command writes its contract (``validation``: about a minute)."""
import csv
import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from exudyn_wheelrail.cli import main
from exudyn_wheelrail.scenarios.critical_speed_linear import OperatingPoint


def _error(capsys, argv) -> str:
    try:
        code = main(argv)
    except SystemExit as exc:                 # argparse's own errors (the parser's one-line form)
        code = exc.code
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and err.startswith("error: ")
    return err


@pytest.mark.parametrize("rng,problem", [(("300", "100"), "LO < HI"), (("5", "100"), "10-600"),
                                         (("100", "700"), "10-600"), (("100", "100"), "LO < HI")])
def test_bad_speed_range(capsys, tmp_path, rng, problem):
    err = _error(capsys, ["critical-speed", "--vehicle", "manchester_vehicle1", "--speed-range-kmh", *rng,
                          "--out", str(tmp_path / "out")])
    assert err.startswith("error: --speed-range-kmh:") and problem in err
    assert not (tmp_path / "out").exists()


def test_bad_vehicle(capsys, tmp_path):
    err = _error(capsys, ["critical-speed", "--vehicle", "no_such_vehicle", "--out", str(tmp_path / "o")])
    assert err.startswith("error: --vehicle:")
    bare = tmp_path / "bare.toml"
    bare.write_text('schema_version = 1\n[vehicle]\nname = "no wheelsets"\nlayout = "car"\n')
    err = _error(capsys, ["critical-speed", "--vehicle", str(bare), "--out", str(tmp_path / "o")])
    assert err.startswith("error: --vehicle:") and "no wheelsets" in err
    err = _error(capsys, ["critical-speed", "--vehicle", "manchester_vehicle1", "--workers", "0",
                          "--out", str(tmp_path / "o")])
    assert err.startswith("error: --workers:")


def test_perturbation_is_rigid_body_kinematics():
    """A body spinning with ω0 (track frame), perturbed by a small rotation rate θ̇ about the track axes: the node's
    body-frame angular velocity is R^T(θ̇ + ω0) at θ = 0, the same as differentiating R(t) = exp(θ̇ t) exp(ω0 t) R0
    numerically (central difference, 1e-7 s: agreement to 1e-6 rad/s)."""
    R0 = Rotation.from_rotvec([0.3, 2.9, -0.2])
    w0 = np.array([0.0, -120.0, 0.0])
    q0 = np.r_[0.0, 0.0, 0.0, R0.as_rotvec()]
    v0 = np.r_[0.0, 0.0, 0.0, R0.inv().apply(w0)]
    op = OperatingPoint(q0, v0, [0])
    rate = np.array([0.01, 0.0, -0.02])
    _, v, _ = op.perturbed(np.zeros(6), np.r_[0.0, 0.0, 0.0, rate])

    def R(t):
        return Rotation.from_rotvec(rate * t) * Rotation.from_rotvec(w0 * t) * R0
    h = 1e-7
    dR = (R(h).as_matrix() - R(-h).as_matrix()) / (2 * h)
    w_tilde = R0.as_matrix().T @ dR
    w_body = np.array([w_tilde[2, 1], w_tilde[0, 2], w_tilde[1, 0]])
    assert np.allclose(v[3:6], w_body, atol=1e-6)
    q, _, _ = op.perturbed(np.r_[0.0, 1e-3, 0.0, 0.0, 0.0, 1e-3], np.zeros(6))
    assert np.allclose(Rotation.from_rotvec(q[3:6]).as_matrix(),
                       (Rotation.from_rotvec([0, 0, 1e-3]) * R0).as_matrix(), atol=1e-12)
    assert q[1] == pytest.approx(1e-3)


@pytest.mark.validation
def test_command_writes_the_contract(tmp_path, capsys):
    """The whole command on the Manchester vehicle over 150-350 km/h: exit code 0, summary.json with the contract's
    keys, the two tables with their columns, the three figures; the critical speeds inside the range, the nonlinear
    one below the linear one (docs/stability.md: 169.5 and 333.5 km/h)."""
    out = tmp_path / "out"
    assert main(["critical-speed", "--vehicle", "manchester_vehicle1", "--speed-range-kmh", "150", "350",
                 "--workers", "2", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    for key in ("status", "linear_critical_speed_kmh", "hunting_frequency_hz", "nonlinear_critical_speed_kmh",
                "assumptions"):
        assert key in s
    assert s["status"] == "ok"
    assert 150.0 < s["nonlinear_critical_speed_kmh"] < s["linear_critical_speed_kmh"] < 350.0
    assert 1.0 < s["hunting_frequency_hz"] < 10.0
    with open(out / "root_locus.csv") as fh:
        assert next(csv.reader(fh))[:4] == ["speed_kmh", "mode", "frequency_hz", "damping_ratio"]
    with open(out / "bifurcation.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0])[:3] == ["speed_kmh", "wheelset", "amplitude_m"]
    unstable = [r for r in rows if r["branch"] == "unstable"]
    assert unstable and all(s["nonlinear_critical_speed_kmh"] < float(r["speed_kmh"])
                            < s["linear_critical_speed_kmh"] for r in unstable)
    assert any(r["found"] for r in s["unstable_branch"])
    for name in ("root_locus.png", "damping_ratio.png", "bifurcation.png"):
        assert (out / name).stat().st_size > 0
