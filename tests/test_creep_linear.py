"""Kalker's linear-theory coefficients (Table E.3) and the linear creep forces (exudyn_wheelrail.creep.linear)."""
import math

import numpy as np
import pytest

from reference_paths import SHARED_REFERENCE
from exudyn_wheelrail.creep import kalker_coefficients, linear_creep_forces
from exudyn_wheelrail.creep.linear import TABLE_PATH, fastsim_spin_moment_coefficient

NUS = (0.0, 0.25, 0.5)


def _read_reference():
    """Independent reader of shared/reference/kalker_linear_coefficients.csv: list of (a/b, {(q, nu): value})."""
    rows = []
    for line in (SHARED_REFERENCE / "kalker_linear_coefficients.csv").read_text().splitlines():
        if line.startswith("#") or line.startswith("case") or not line.strip():
            continue
        case, g, *vals = line.split(",")
        ab = float(g) if case == "a<=b" else 1.0 / float(g)
        vals = [float(v) for v in vals]
        rows.append((ab, {(q, nu): vals[3 * qi + ni] for qi, q in enumerate(("C11", "C22", "C23"))
                          for ni, nu in enumerate(NUS)}))
    return sorted(rows, key=lambda r: r[0])


REF = _read_reference()


def test_package_copy_matches_shared_reference():
    assert TABLE_PATH.parent.name == "data" and TABLE_PATH.parent.parent.name == "exudyn_wheelrail"
    ref = [l for l in (SHARED_REFERENCE / "kalker_linear_coefficients.csv").read_text().splitlines()
           if not l.startswith("#")]
    pkg = TABLE_PATH.read_text()
    assert "Kalker 1990" in pkg and "Table E.3" in pkg
    assert [l for l in pkg.splitlines() if not l.startswith("#")] == ref
    assert len(REF) == 19


@pytest.mark.parametrize("mode", ["quadratic", "linear"])
def test_reproduces_every_table_entry(mode):
    for ab, vals in REF:
        for nu in NUS:
            c = kalker_coefficients(ab, nu, nu_interpolation=mode)
            for q, v in zip(("C11", "C22", "C23"), c):
                assert v == pytest.approx(vals[(q, nu)], rel=1e-12, abs=1e-12), (ab, nu, q)


def _curve(q_index, nu, n_per=40):
    abs_ = [r[0] for r in REF]
    out = []
    for k in range(len(abs_) - 1):
        t = np.linspace(math.log(abs_[k]), math.log(abs_[k + 1]), n_per)
        out.append((k, np.array([kalker_coefficients(math.exp(ti), nu)[q_index] for ti in t])))
    return out


@pytest.mark.parametrize("nu", NUS)
@pytest.mark.parametrize("qi,q", [(0, "C11"), (1, "C22"), (2, "C23")])
def test_no_overshoot_between_nodes(qi, q, nu):
    """PCHIP: on every interval the interpolant is monotone and stays between the two node values."""
    for k, v in _curve(qi, nu):
        lo, hi = sorted((REF[k][1][(q, nu)], REF[k + 1][1][(q, nu)]))
        assert v.min() >= lo - 1e-12 and v.max() <= hi + 1e-12, (q, nu, k)
        d = np.diff(v)
        assert np.all(d >= -1e-12) or np.all(d <= 1e-12), (q, nu, k)


def test_monotone_increasing_where_table_is():
    """The table increases with a/b in every column except C11 at nu = 0.5 (shallow minimum at a/b = 0.3)."""
    for qi, q in enumerate(("C11", "C22", "C23")):
        for nu in NUS:
            col = np.array([r[1][(q, nu)] for r in REF])
            vals = np.concatenate([v for _, v in _curve(qi, nu, 20)])
            if q == "C11" and nu == 0.5:
                assert np.any(np.diff(col) < 0)
                i3 = [r[0] for r in REF].index(0.3)
                assert np.all(np.diff(col[i3:]) > 0)
                continue
            assert np.all(np.diff(col) > 0), (q, nu)
            assert np.all(np.diff(vals) >= -1e-12), (q, nu)


def test_smooth_c1_at_nodes():
    """One-sided slopes at the interior nodes agree (C¹ in ln(a/b))."""
    h = 1e-6
    for ab, _ in REF[1:-1]:
        t = math.log(ab)
        for nu in (0.0, 0.28, 0.5):
            c0 = np.array(kalker_coefficients(ab, nu))
            left = (c0 - np.array(kalker_coefficients(math.exp(t - h), nu))) / h
            right = (np.array(kalker_coefficients(math.exp(t + h), nu)) - c0) / h
            assert np.allclose(left, right, rtol=1e-3, atol=1e-4 * np.abs(c0).max()), (ab, nu)


def test_nu_interpolation():
    for ab in (0.1, 0.37, 1.0, 2.9, 10.0):
        c = [np.array(kalker_coefficients(ab, nu)) for nu in NUS]
        # linear mode: midpoints
        assert np.allclose(kalker_coefficients(ab, 0.125, "linear"), 0.5 * (c[0] + c[1]), rtol=1e-13)
        assert np.allclose(kalker_coefficients(ab, 0.375, "linear"), 0.5 * (c[1] + c[2]), rtol=1e-13)
        # quadratic mode: the parabola through the three columns (independent: numpy.polyfit)
        for nu in (0.1, 0.28, 0.4):
            ref = [np.polyval(np.polyfit(NUS, [ci[q] for ci in c], 2), nu) for q in range(3)]
            assert np.allclose(kalker_coefficients(ab, nu), ref, rtol=1e-12)


def test_quadratic_nu_follows_the_narrow_contact_law():
    """Why quadratic in nu, on the package: for a narrow contact C11 -> pi²/(4(1-nu)) (Kalker's a/b -> 0 limit), so
    at the narrowest tabulated a/b = 0.1 the reference for nu = 0.28 is the Table E.3 entry at nu = 0.25 scaled by
    (1 - 0.25)/(1 - 0.28).  Its uncertainty: C11 (1 - nu) is not exactly constant at a/b = 0.1; over the 0.03 step it
    changes by about the largest secant slope of C11 (1 - nu) between the table's nu columns times 0.03 (0.28 %
    here).  The package's quadratic interpolation in nu stays within it (measured 0.23 %); the linear one
    misses by more than three times as much (1.4 %)."""
    ab, vals = REF[0]
    assert ab == pytest.approx(0.1)
    g = [vals[("C11", nu)] * (1 - nu) for nu in NUS]
    slope = max(abs(g[1] - g[0]) / (NUS[1] - NUS[0]), abs(g[2] - g[1]) / (NUS[2] - NUS[1]))
    ref = vals[("C11", 0.25)] * (1 - 0.25) / (1 - 0.28)
    unc = slope * 0.03 / g[1]
    quad = kalker_coefficients(ab, 0.28)[0]
    lin = kalker_coefficients(ab, 0.28, nu_interpolation="linear")[0]
    assert abs(quad / ref - 1) <= unc
    assert abs(lin / ref - 1) > 3 * unc


@pytest.mark.parametrize("ab,nu", [(0.0999, 0.25), (10.01, 0.25), (0.0, 0.25), (-1.0, 0.25), (float("nan"), 0.25),
                                   (1.0, -0.01), (1.0, 0.51), (1.0, float("inf"))])
def test_range_errors(ab, nu):
    with pytest.raises(ValueError):
        kalker_coefficients(ab, nu)


def test_range_ends_accepted_and_bad_mode():
    kalker_coefficients(0.1, 0.0)
    kalker_coefficients(10.0, 0.5)
    with pytest.raises(ValueError):
        kalker_coefficients(1.0, 0.25, nu_interpolation="cubic")


def test_linear_creep_forces_formula_and_signs():
    a, b, G, nu = 6e-3, 4e-3, 82e9, 0.28
    c = math.sqrt(a * b)
    C11, C22, C23 = kalker_coefficients(a / b, nu)
    C33s = fastsim_spin_moment_coefficient(a / b, nu)
    assert C33s == pytest.approx(32 / (15 * math.pi) * C23 * (b / a) ** 1.5)
    Fx, Fy, Mz = linear_creep_forces(a, b, 1e-4, 2e-4, 0.01, G, nu)
    assert Fx == pytest.approx(-G * c * c * C11 * 1e-4)
    assert Fy == pytest.approx(-G * c * c * (C22 * 2e-4 + c * C23 * 0.01))
    assert Mz == pytest.approx(G * c ** 3 * (C23 * 2e-4 - c * C33s * 0.01))
    assert Fx < 0 and linear_creep_forces(a, b, 0, 1e-4, 0, G, nu)[1] < 0
    assert linear_creep_forces(a, b, 0, 1e-4, 0, G, nu)[2] > 0
    assert linear_creep_forces(a, b, 0, 0, 0.01, G, nu)[2] < 0
    for bad in [(0, b, 0, 0, 0, G, nu), (a, -b, 0, 0, 0, G, nu), (a, b, math.nan, 0, 0, G, nu),
                (a, b, 0, 0, 0, 0.0, nu), (a, a * 20, 0, 0, 0, G, nu)]:
        with pytest.raises(ValueError):
            linear_creep_forces(*bad)
