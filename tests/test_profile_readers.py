"""Tests of the profile point-file readers and the spline fit (exudyn_wheelrail.profiles.readers).

References are independent of the code under test: nominal dimensions of the standard profiles (EN 13715 S1002:
tape circle 70 mm from the flange back, flange height 28 mm, flange thickness 32.5 mm and qR 10.8 mm measured at
10 mm / 26 mm above the tape circle; UIC60 / 60E1: head width 72 mm, crown radius 300 mm, here inclined 1:40),
the raw numbers of the files themselves, and analytic circles.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference_paths import PROFILES_DIR
from exudyn_wheelrail.profiles.dense import DenseProfile
from exudyn_wheelrail.profiles.readers import (DEFAULT_SPACING_M, ProfileError, dense_from_points, load_profile,
                                               read_simpack_profile, read_yz_table)

REF = PROFILES_DIR
S1002_FILE = REF / "MBench_S1002_v3.prw"
UIC60_FILE = REF / "MBench_UIC60_v3.prr"


# ------------------------------------------------------------------------------------------------ helpers
def crown_points_m(n=61, half_width=0.03, radius=0.3):
    """A smooth rail-crown-like profile in metres: gauge side first, z = depth below the top."""
    y = np.linspace(-half_width, half_width, n)
    return y, radius - np.sqrt(radius ** 2 - y ** 2)


def write_table(path: Path, y, z, fmt="{:.9g} {:.9g}", header=None, comments=()):
    lines = list(comments)
    if header is not None:
        lines.append(header)
    lines += [fmt.format(a, b) for a, b in zip(y, z)]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_simpack(path: Path, y_mm, z_mm, type_=0, keys=None, point_begin=True, point_end=True, unit_f=1000.0):
    keys = dict({"mirror.y": 0, "mirror.z": 0, "inversion": 0, "units.len.f": unit_f}, **(keys or {}))
    lines = ["! test file", "  header.begin", "    version = 1", f"    type = {type_}   ! 0=rail, 1=wheel",
             "  header.end", "  spline.begin", "    approx.smooth = 0.0", "    comment = 'synthetic ! not a real asset'"]
    lines += [f"    {k} = {v}" for k, v in keys.items()]
    if point_begin:
        lines.append("    point.begin")
    lines += [f"{a:.8E}\t{b:.8E}" for a, b in zip(y_mm, z_mm)]
    if point_end:
        lines.append("    point.end")
    lines.append("  spline.end")
    path.write_text("\n".join(lines) + "\n")
    return path


def polyline_distance(points, py, pz):
    """Largest distance of ``points`` (k, 2) from the polyline through (py, pz)."""
    a = np.column_stack([py[:-1], pz[:-1]])
    ab = np.column_stack([np.diff(py), np.diff(pz)])
    worst = 0.0
    for q in points:
        t = np.clip(np.sum((q - a) * ab, axis=1) / np.sum(ab * ab, axis=1), 0.0, 1.0)
        worst = max(worst, float(np.min(np.hypot(*(a + t[:, None] * ab - q).T))))
    return worst


def curvature(d: DenseProfile):
    return (d.dy * d.ddz - d.dz * d.ddy) / np.hypot(d.dy, d.dz) ** 3


def raw_simpack_points(path):
    """Uncommented numeric point lines of a SIMPACK file, in file units (independent of the reader)."""
    rows, inside = [], False
    for line in path.read_text().splitlines():
        s = line.strip()
        if s == "point.begin":
            inside = True
        elif s == "point.end":
            inside = False
        elif inside and s and not s.startswith("!"):
            rows.append([float(v) for v in s.split()[:2]])
    return np.array(rows)


# ------------------------------------------------------------------------------------------------ shared files
def test_s1002_file_in_en13715_frame():
    y, z, meta = read_simpack_profile(S1002_FILE)
    assert meta["kind"] == "wheel" and meta["units"] == "mm" and meta["length_factor"] == 1000.0
    raw = raw_simpack_points(S1002_FILE)
    assert len(y) == len(raw) == 399                      # the commented-out first point is not read
    assert not np.any(np.isclose(y, -0.070, atol=1e-9))
    # flange back first, field side last, y increasing overall
    assert y[0] == y.min() and y[-1] == y.max()
    assert abs(y[0] - (-0.070)) < 0.5e-3                  # tape circle 70 mm from the flange back
    assert y[-1] == pytest.approx(0.060, abs=1e-9)
    # tread passes through the tape circle point (origin)
    i_tip = int(np.argmax(z))
    tread_y, tread_z = y[i_tip:], z[i_tip:]
    assert abs(np.interp(0.0, tread_y, tread_z)) < 5e-6
    # flange: towards the rail (+z), on the gauge side (-y), 28 mm high
    assert z.max() == pytest.approx(0.028, abs=5e-5)
    assert -0.070 < y[i_tip] < -0.040
    # flange thickness (at 10 mm above the tape circle, from the flange back) and qR (26 mm level - 10 mm level)
    flank_y, flank_z = y[i_tip:], z[i_tip:]
    flank = flank_z > 0.005
    y10 = np.interp(0.010, flank_z[flank][::-1], flank_y[flank][::-1])
    y26 = np.interp(0.026, flank_z[flank][::-1], flank_y[flank][::-1])
    assert y10 - (-0.070) == pytest.approx(0.0325, abs=1e-4)
    assert y10 - y26 == pytest.approx(0.0108, abs=1.5e-4)
    # exactly the file numbers, mirrored and in metres
    np.testing.assert_allclose(np.sort(y), np.sort(-raw[:, 0] / 1000.0), rtol=0, atol=1e-15)


def test_uic60_file_returned_as_is():
    y, z, meta = read_simpack_profile(UIC60_FILE, kind="rail")
    assert meta["kind"] == "rail" and "canted" in meta["comment"]
    raw = raw_simpack_points(UIC60_FILE)
    np.testing.assert_allclose(y, raw[:, 0] / 1000.0, rtol=0, atol=1e-15)   # no repositioning, same order
    np.testing.assert_allclose(z, raw[:, 1] / 1000.0, rtol=0, atol=1e-15)
    assert np.all(np.diff(y) > 0)
    # crown at the top: z (depth) smallest in the interior, about 0, both ends far below
    i_top = int(np.argmin(z))
    assert 0 < i_top < len(z) - 1 and abs(z[i_top]) < 1e-5
    assert z[0] > 0.030 and z[-1] > 0.030
    # head width 72 mm, measured 14 mm below the top
    gauge, field = slice(0, i_top), slice(i_top, None)
    y_gauge = np.interp(0.014, z[gauge][::-1], y[gauge][::-1])
    y_field = np.interp(0.014, z[field], y[field])
    assert y_field - y_gauge == pytest.approx(0.072, abs=3e-4)
    # 1:40 inwards inclination of an R300 crown moves the highest point ~300/40 = 7.5 mm to the field side of the
    # head centre line: +y is the field side
    offset = y[i_top] - 0.5 * (y_gauge + y_field)
    assert 0.006 < offset < 0.009


def test_shared_files_fit_and_hand_over():
    from exudyn_wheelrail.profiles.curve import ProfileCurve
    for path, outward in ((S1002_FILE, "+z"), (UIC60_FILE, "-z")):
        dense = load_profile(path)
        assert isinstance(dense, DenseProfile) and dense.name == path.stem
        y, z, _ = read_simpack_profile(path)
        # exact points (approx.smooth = 0) are interpolated
        assert polyline_distance(np.column_stack([y, z]), dense.y, dense.z) < 1e-6
        spacing = np.hypot(np.diff(dense.y), np.diff(dense.z))
        assert np.max(spacing) < 1.2 * DEFAULT_SPACING_M
        curve = ProfileCurve.from_dense(dense, outward)
        assert curve.fit_error_m < 1e-6


def test_kind_checks_on_shared_files():
    with pytest.raises(ProfileError, match="MBench_S1002_v3.prw.*type = 1"):
        read_simpack_profile(S1002_FILE, kind="rail")
    with pytest.raises(ProfileError, match="MBench_UIC60_v3.prr"):
        load_profile(UIC60_FILE, kind="wheel")


# ------------------------------------------------------------------------------------------------ SIMPACK semantics
def test_simpack_header_steps(tmp_path):
    y, z = crown_points_m()
    y_mm, z_mm = y * 1e3, z * 1e3
    keys = {"shift.y": 5.0, "shift.z": -1.0, "mirror.y": 1, "mirror.z": 1, "inversion": 1}
    yr, zr, meta = read_simpack_profile(write_simpack(tmp_path / "a.prr", y_mm, z_mm, keys=keys))
    # shift, then mirror, then metres; order normalised to increasing y
    expected_y = -(y_mm + 5.0) / 1e3
    expected_z = -(z_mm - 1.0) / 1e3
    order = np.argsort(expected_y)
    np.testing.assert_allclose(yr, expected_y[order], atol=1e-12)
    np.testing.assert_allclose(zr, expected_z[order], atol=1e-12)
    assert meta["steps"][:3] == ["shift by (5, -1)", "mirror y", "mirror z"]
    # rotation about x, +y towards +z, applied after the shift; angle unit via units.ang.f (degrees here)
    angle_deg = 2.0
    keys = {"rotate": angle_deg, "units.ang.f": 180.0 / math.pi, "shift.y": 1.0}
    yr, zr, _ = read_simpack_profile(write_simpack(tmp_path / "b.prr", y_mm, z_mm, keys=keys))
    a = math.radians(angle_deg)
    np.testing.assert_allclose(yr, (math.cos(a) * (y_mm + 1) - math.sin(a) * z_mm) / 1e3, atol=1e-12)
    np.testing.assert_allclose(zr, (math.sin(a) * (y_mm + 1) + math.cos(a) * z_mm) / 1e3, atol=1e-12)
    # active lateral bound removes points
    keys = {"bound.y.min": -20.0, "bound.y.max": 20.0}
    yr, _, _ = read_simpack_profile(write_simpack(tmp_path / "c.prr", y_mm, z_mm, keys=keys))
    assert yr.min() >= -0.020 and yr.max() <= 0.020 and len(yr) == np.sum(np.abs(np.round(y_mm, 6)) <= 20.0)


def test_simpack_weights_and_units_len_name(tmp_path):
    y, z = crown_points_m()
    path = tmp_path / "w.prr"
    write_simpack(path, y * 1e3, z * 1e3, unit_f=1.0)
    text = path.read_text().replace("units.len.f = 1.0", "units.len = 'mm'")
    path.write_text(text)
    yr, _, meta = read_simpack_profile(path)
    assert meta["units"] == "mm" and meta["length_factor_source"] == "units.len"
    assert meta["weights"] is None
    np.testing.assert_allclose(yr, y, atol=1e-12)
    # a third column holds SIMPACK spline weights: kept in the metadata, in the returned point order
    path = tmp_path / "w3.prr"
    write_simpack(path, y * 1e3, z * 1e3)
    text = path.read_text().splitlines()
    first = text.index("    point.begin") + 1
    for k in range(len(y)):
        text[first + k] += f"\t{1.0 + k}"
    path.write_text("\n".join(text) + "\n")
    _, _, meta = read_simpack_profile(path)
    np.testing.assert_array_equal(meta["weights"], 1.0 + np.arange(len(y)))  # small integers, parsed: exact


# ------------------------------------------------------------------------------------------------ error cases
def _expect(exc_info_path: Path, *words):
    """Context: a ProfileError naming the file and containing every word."""
    class _Ctx:
        def __enter__(self):
            self.cm = pytest.raises(ProfileError)
            self.info = self.cm.__enter__()
            return self.info

        def __exit__(self, *exc):
            handled = self.cm.__exit__(*exc)
            message = str(self.info.value)
            assert exc_info_path.name in message, message
            for w in words:
                assert w.lower() in message.lower(), message
            return handled
    return _Ctx()


def test_error_too_few_points(tmp_path):
    y, z = crown_points_m(n=5)
    path = write_table(tmp_path / "few.csv", y * 1e3, z * 1e3, fmt="{},{}")
    with _expect(path, "at least 10"):
        read_yz_table(path)
    prr = write_simpack(tmp_path / "few.prr", y * 1e3, z * 1e3)
    with _expect(prr, "at least 10"):
        read_simpack_profile(prr)


def test_error_nan_and_unparsable(tmp_path):
    y, z = crown_points_m()
    lines = [f"{a:.6f} {b:.6f}" for a, b in zip(y * 1e3, z * 1e3)]
    bad = list(lines)
    bad[20] = "nan 1.0"
    path = tmp_path / "nan.txt"
    path.write_text("\n".join(bad))
    with _expect(path, "line 21", "finite"):
        read_yz_table(path)
    bad = list(lines)
    bad[30] = "-3.0 1,2x"
    path = tmp_path / "text.txt"
    path.write_text("\n".join(["y z"] + bad))
    with _expect(path, "line 32", "cannot read"):
        read_yz_table(path)
    path = tmp_path / "inf.prw"
    rows = "\n".join(lines[:20] + ["1.0 inf"] + lines[20:])
    path.write_text(f"header.begin\ntype = 1\nheader.end\nspline.begin\nunits.len.f = 1000\npoint.begin\n{rows}\n"
                    "point.end\nspline.end\n")
    with _expect(path, "line 27", "not finite"):
        read_simpack_profile(path)
    path = tmp_path / "cols.txt"
    path.write_text("\n".join(lines[:15] + ["1.0 2.0 3.0"] + lines[15:]))
    with _expect(path, "line 16", "column"):
        read_yz_table(path)


def test_error_duplicated_point(tmp_path):
    y, z = crown_points_m()
    y, z = np.insert(y, 12, y[11]), np.insert(z, 12, z[11])
    path = write_table(tmp_path / "dup.txt", y * 1e3, z * 1e3)
    with _expect(path, "line 12", "line 13", "duplicated"):
        read_yz_table(path)


def test_error_lateral_backstep(tmp_path):
    y, z = crown_points_m()
    y = y.copy()
    y[30] = y[28]          # tread point stepping back towards the gauge side
    path = write_table(tmp_path / "back.txt", y * 1e3, z * 1e3)
    with _expect(path, "must increase", "monotonic", "line 30"):
        read_yz_table(path)


def test_error_fold_back_on_steep_part(tmp_path):
    # a gauge face going down steeply with a spike back up in the middle, then the crown
    face_z = np.linspace(0.030, 0.005, 11)
    face_y = -0.035 + 0.02 * (face_z - 0.005)
    face_z[5] = face_z[3]
    cy, cz = crown_points_m(n=31)
    y = np.concatenate([face_y, cy[1:]])
    z = np.concatenate([face_z, cz[1:]])
    path = write_table(tmp_path / "spike.txt", y * 1e3, z * 1e3)
    with _expect(path, "folds back", "line 5"):           # the turn at the point before the outlier
        read_yz_table(path)


def test_error_self_intersection(tmp_path):
    y, z = crown_points_m(n=81)
    # a small loop on the crown: the line comes back and crosses itself
    th = np.linspace(0, 2 * np.pi, 25)[1:-1]
    loop_y = 0.0 + 0.002 * np.sin(th)
    loop_z = 0.002 - 0.002 * np.cos(th)
    i0 = int(np.searchsorted(y, 0.0))
    y = np.concatenate([y[:i0], loop_y, y[i0:] + 1e-4])
    z = np.concatenate([z[:i0], loop_z, z[i0:]])
    path = write_table(tmp_path / "loop.csv", y * 1e3, z * 1e3, fmt="{:.6f};{:.6f}")
    with _expect(path, "intersects itself"):
        read_yz_table(path)


def test_error_units(tmp_path):
    y, z = crown_points_m()
    mm = write_table(tmp_path / "mm.txt", y * 1e3, z * 1e3)
    with _expect(mm, "millimetres"):
        read_yz_table(mm, units="m")
    metres = write_table(tmp_path / "m.txt", y, z)
    with _expect(metres, "metres"):
        read_yz_table(metres, units="mm")
    tiny = write_table(tmp_path / "tiny.txt", y * 50, z * 50)      # 3 units wide: neither m nor mm
    with _expect(tiny, "cannot infer"):
        read_yz_table(tiny)
    prr = write_simpack(tmp_path / "mm_as_m.prr", y * 1e3, z * 1e3, unit_f=1.0)
    with _expect(prr, "millimetres", "1000"):
        read_simpack_profile(prr)
    prr = write_simpack(tmp_path / "m_as_mm.prr", y, z, unit_f=1000.0)
    with _expect(prr, "metres"):
        read_simpack_profile(prr)
    hinted = write_table(tmp_path / "hint.txt", y, z, header="y [mm]  z [mm]")
    with _expect(hinted, "header", "mm"):
        read_yz_table(hinted)


def test_error_simpack_structure_and_type(tmp_path):
    y, z = crown_points_m()
    path = write_simpack(tmp_path / "nobegin.prr", y * 1e3, z * 1e3, point_begin=False)
    with _expect(path, "line 13", "point.begin' is missing"):
        read_simpack_profile(path)
    path = write_simpack(tmp_path / "empty.prr", [], [], point_begin=False, point_end=False)
    with _expect(path, "no 'point.begin'"):
        read_simpack_profile(path)
    path = write_simpack(tmp_path / "noend.prr", y * 1e3, z * 1e3, point_end=False)
    with _expect(path, "point.end", "missing"):
        read_simpack_profile(path)
    path = write_simpack(tmp_path / "wheel_type.prr", y * 1e3, z * 1e3, type_=1)
    with _expect(path, "type = 1", "extension"):
        read_simpack_profile(path)
    path = write_simpack(tmp_path / "rail.prr", y * 1e3, z * 1e3, type_=0)
    with _expect(path, "wheel profile was requested", "type = 0"):
        read_simpack_profile(path, kind="wheel")
    path = write_simpack(tmp_path / "bad_type.prr", y * 1e3, z * 1e3, type_=7)
    with _expect(path, "type = 7"):
        read_simpack_profile(path)


# ------------------------------------------------------------------------------------------------ tables
def test_units_auto_detection(tmp_path):
    y, z = crown_points_m()
    ym, zm, meta_m = read_yz_table(write_table(tmp_path / "m.txt", y, z, fmt="{:.12g} {:.12g}"))
    ymm, zmm, meta_mm = read_yz_table(write_table(tmp_path / "mm.txt", y * 1e3, z * 1e3, fmt="{:.12g} {:.12g}"))
    assert meta_m["units"] == "m" and meta_mm["units"] == "mm"
    assert "auto" in meta_m["units_source"] and "auto" in meta_mm["units_source"]
    np.testing.assert_allclose(ym, y, atol=1e-12)
    np.testing.assert_allclose(ymm, y, atol=1e-12)
    np.testing.assert_allclose(zmm, zm, atol=1e-12)
    _, _, meta_h = read_yz_table(write_table(tmp_path / "h.txt", y * 1e3, z * 1e3, header="y (mm), z (mm)",
                                             fmt="{:.9g}, {:.9g}"))
    assert meta_h["units"] == "mm" and "header" in meta_h["units_source"]


@pytest.mark.parametrize("fmt, delimiter", [("{:.9f},{:.9f}", "comma"), ("{:.9f} , {:.9f}", "comma"),
                                            ("{:.9f}\t{:.9f}", "tab"), ("{:.9f}   {:.9f}", "whitespace"),
                                            ("{:.9f};{:.9f}", "semicolon")])
def test_table_delimiters_header_comments(tmp_path, fmt, delimiter):
    y, z = crown_points_m()
    path = write_table(tmp_path / "t.csv", y * 1e3, z * 1e3, fmt=fmt, header="lateral;vertical",
                       comments=["# exported by a gauge", "   # indented comment"])
    yr, zr, meta = read_yz_table(path, kind="rail")
    assert meta["delimiter"] == delimiter and meta["header_line"] == "lateral;vertical" and meta["kind"] == "rail"
    np.testing.assert_allclose(yr, y, atol=1e-12)
    np.testing.assert_allclose(zr, z, atol=1e-12)


def test_table_decimal_comma_reversed_and_columns(tmp_path):
    y, z = crown_points_m()
    text = "\n".join(f"{k};{a:.6f};{b:.6f}".replace(".", ",") for k, (a, b) in enumerate(zip(y[::-1] * 1e3,
                                                                                             z[::-1] * 1e3)))
    path = tmp_path / "eu.csv"
    path.write_text(text + "\n")
    yr, zr, meta = read_yz_table(path, columns=(1, 2))
    assert meta["reversed"] and meta["delimiter"] == "semicolon"
    np.testing.assert_allclose(yr, y, atol=1e-9)
    np.testing.assert_allclose(zr, z, atol=1e-9)
    yr2, zr2, _ = read_yz_table(path, columns=(1, 2), mirror_z=True)
    np.testing.assert_allclose(zr2, -z, atol=1e-9)


@settings(max_examples=25, deadline=None)
@given(delim=st.sampled_from([",", ";", "\t", " ", "  "]), shift=st.floats(-50, 50), digits=st.integers(6, 10))
def test_table_roundtrip_property(tmp_path_factory, delim, shift, digits):
    y, z = crown_points_m()
    y_mm, z_mm = y * 1e3 + shift, z * 1e3
    path = tmp_path_factory.mktemp("rt") / "p.txt"
    path.write_text("\n".join(f"{a:.{digits}f}{delim}{b:.{digits}f}" for a, b in zip(y_mm, z_mm)))
    yr, zr, meta = read_yz_table(path, units="mm")
    np.testing.assert_allclose(yr, y_mm / 1e3, atol=1e-9)
    np.testing.assert_allclose(zr, z_mm / 1e3, atol=1e-9)


def test_load_profile_dispatch(tmp_path):
    y, z = crown_points_m()
    table = write_table(tmp_path / "crown.dat", y * 1e3, z * 1e3)
    dense = load_profile(table, "rail", smoothing=0)
    assert dense.name == "crown"
    assert polyline_distance(np.column_stack([y, z]), dense.y, dense.z) < 1e-6
    prr = write_simpack(tmp_path / "crown.prr", y * 1e3, z * 1e3)
    dense2 = load_profile(prr, "rail", name="x")
    assert dense2.name == "x"
    np.testing.assert_allclose(dense2.y[[0, -1]], y[[0, -1]], atol=1e-12)
    # a measured table is smoothed by default (0.01 mm gauge noise)
    radius = 0.02
    yn, zn = noisy_arc(radius, np.pi / 2, 1e-4, 1e-5, seed=3)
    noisy = write_table(tmp_path / "gauge.csv", yn * 1e3, zn * 1e3, fmt="{:.5f},{:.5f}", header="y [mm],z [mm]")
    dense3 = load_profile(noisy, "rail")
    n = len(dense3.y)
    assert np.max(np.abs(curvature(dense3)[n // 5: -n // 5] * radius - 1)) < 0.05


# ------------------------------------------------------------------------------------------------ spline fit
def noisy_arc(radius, angle, spacing, sigma, seed):
    rng = np.random.default_rng(seed)
    n = int(round(radius * angle / spacing)) + 1
    th = np.linspace(-angle / 2, angle / 2, n)
    y = radius * np.sin(th) + sigma * rng.standard_normal(n)
    z = radius * (1 - np.cos(th)) + sigma * rng.standard_normal(n)
    return y, z


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("radius, angle, spacing", [(0.020, np.pi / 2, 1e-4), (0.012, np.pi / 2, 1e-4),
                                                    (0.300, 0.3, 2e-4)])
def test_smoothing_recovers_noisy_circle(seed, radius, angle, spacing):
    sigma = 1e-5                                   # 0.01 mm gauge noise in each coordinate
    y, z = noisy_arc(radius, angle, spacing, sigma, seed)
    dense = dense_from_points(y, z)                # default smoothing: 0.01 mm gauge noise
    n = len(dense.y)
    mid = slice(int(0.2 * n), int(0.8 * n))
    kappa = curvature(dense)[mid]
    assert np.max(np.abs(kappa * radius - 1.0)) < 0.05
    deviation = np.hypot(dense.y, dense.z - radius) - radius
    assert np.sqrt(np.mean(deviation[mid] ** 2)) < sigma
    assert np.max(np.abs(deviation[mid])) < 2 * sigma
    assert np.max(np.abs(deviation)) < 4 * sigma
    step = np.hypot(np.diff(dense.y), np.diff(dense.z))
    assert np.all(step < 1.2 * DEFAULT_SPACING_M) and np.all(step > 0.8 * DEFAULT_SPACING_M)


@pytest.mark.parametrize("seed", range(2))
def test_smoothing_dense_noisy_scan(seed):
    """Samples closer than the noise (0.02 mm spacing, 0.01 mm noise): the chord lengths are mostly noise."""
    radius, sigma = 0.3, 1e-5
    y, z = noisy_arc(radius, 0.3, 2e-5, sigma, seed)
    dense = dense_from_points(y, z, smoothing=sigma, validate=False)
    n = len(dense.y)
    mid = slice(int(0.2 * n), int(0.8 * n))
    assert np.max(np.abs(curvature(dense)[mid] * radius - 1.0)) < 0.05
    assert np.max(np.abs(np.hypot(dense.y, dense.z - radius) - radius)) < 2 * sigma
    assert dense.y[0] < dense.y[-1]


def test_interpolation_of_exact_points():
    radius = 0.02
    th = np.linspace(-1.0, 1.0, 81)                 # 0.5 mm spacing
    y, z = radius * np.sin(th), radius * (1 - np.cos(th))
    dense = dense_from_points(y, z, smoothing=0)
    assert polyline_distance(np.column_stack([y, z]), dense.y, dense.z) < 1e-6
    assert np.max(np.abs(np.hypot(dense.y, dense.z - radius) - radius)) < 1e-6
    assert np.max(np.abs(curvature(dense)[100:-100] * radius - 1)) < 1e-2
    assert (dense.y[0], dense.z[0]) == pytest.approx((y[0], z[0]), abs=1e-15)
    assert (dense.y[-1], dense.z[-1]) == pytest.approx((y[-1], z[-1]), abs=1e-15)


def test_dense_derivatives_are_those_of_a_uniform_parameter():
    y, z = noisy_arc(0.02, np.pi / 2, 1e-4, 1e-5, 7)
    for smoothing in (0.0, None):
        if smoothing == 0.0:
            th = np.linspace(-0.7, 0.7, 200)
            y, z = 0.02 * np.sin(th), 0.02 * (1 - np.cos(th))
        d = dense_from_points(y, z, smoothing=smoothing)
        # the samples are uniform in tau: estimate d tau from chords and speeds, then compare differences
        speed = np.hypot(d.dy, d.dz)
        dtau = np.median(np.hypot(np.diff(d.y), np.diff(d.z)) / (0.5 * (speed[1:] + speed[:-1])))
        fd_y = (d.y[2:] - d.y[:-2]) / (2 * dtau)
        fd_z = (d.z[2:] - d.z[:-2]) / (2 * dtau)
        np.testing.assert_allclose(fd_y, d.dy[1:-1], atol=1e-5 * speed.max())
        np.testing.assert_allclose(fd_z, d.dz[1:-1], atol=1e-5 * speed.max())
        sd_y = (d.y[2:] - 2 * d.y[1:-1] + d.y[:-2]) / dtau ** 2
        acc = np.hypot(d.ddy, d.ddz).max()
        np.testing.assert_allclose(sd_y, d.ddy[1:-1], atol=2e-2 * acc)


def test_dense_from_points_validates_arrays():
    y, z = crown_points_m()
    with pytest.raises(ProfileError, match="my-profile.*gauge side"):
        dense_from_points(y[::-1], z[::-1], name="my-profile")
    with pytest.raises(ProfileError, match="crown.*smoothing"):
        dense_from_points(y, z, smoothing=-1.0, name="crown")
    with pytest.raises(ProfileError, match="pts.*at least 10"):
        dense_from_points(y[:6], z[:6], name="pts")
    with pytest.raises(ProfileError, match="crown-mm.*millimetres"):
        dense_from_points(y * 1e3, z * 1e3, name="crown-mm")
