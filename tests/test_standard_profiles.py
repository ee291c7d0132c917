"""Checks of the analytic S1002 and 60E1 (UIC60) profiles of :mod:`exudyn_wheelrail.profiles.standard`.

Independent check against the point files of the Manchester contact benchmark (SIMPACK format, mm), see
``../shared/reference/profiles``:

* ``MBench_S1002_v3.prw``: header ``mirror.y = 1``, the file's y is minus the standard's y (flange at file y = +70),
  z is the standard's z.  Compared in the standard frame.
* ``MBench_UIC60_v3.prr``: already canted 1:40 and with its own reference point.  Its z is depth below the top
  (positive down) and its gauge side is at negative y, like our frame: the head side at negative y is the steeper
  one (about 1:40 from the vertical = 1:20 side slope minus the 1:40 cant), the one at positive y the flatter one
  (about 3:40 = 1:20 + 1:40), which is what a head leaning towards the track centre on the negative-y side gives.
  We rotate our profile by atan(1/40) so that its head leans towards negative y and fit only a translation
  (found: file = ours + (-7.49, +0.09) mm).  The opposite sense leaves 0.9 mm, so the sense is unambiguous.

Metric: shortest distance of each file point to the polyline of our dense samples (spacing 0.02 mm, chord error
below 0.01 um for the smallest radius 12 mm), over the common range (file points whose projection does not fall
beyond an end of our curve; here all of them).  Requirement: max deviation <= 0.05 mm.  Measured when written:
S1002 max 0.093 um, rms 0.013 um (399 points); 60E1 max 0.030 um, rms 0.013 um (495 points).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from reference_paths import PROFILES_DIR
from exudyn_wheelrail.profiles.standard import (
    S1002_BREAKS_Y_M,
    S1002_FLANGE_BACK_Y_M,
    UIC60_BREAKS_Y_M,
    UIC60_HEAD_RADII_M,
    UIC60_HEAD_WIDTH_M,
    UIC60_SIDE_START_DEPTH_M,
    s1002_dense,
    s1002_sections,
    uic60_dense,
    uic60_sections,
)

REFERENCE_DIR = PROFILES_DIR
MAX_DEVIATION_MM = 0.05
RAIL_CANT = math.atan(1.0 / 40.0)


# --------------------------------------------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------------------------------------------
def read_simpack_points_mm(path: Path) -> np.ndarray:
    """(N, 2) array of the 'y z' pairs between point.begin and point.end of a SIMPACK profile file (mm)."""
    if not path.exists():
        raise FileNotFoundError(f"reference profile {path} not found: shared/ must sit beside the checkout")
    points, inside = [], False
    for raw in path.read_text().splitlines():
        line = raw.strip()
        if not line or line.startswith("!"):
            continue
        if line == "point.begin":
            inside = True
        elif line == "point.end":
            break
        elif inside:
            y_mm, z_mm = (float(v) for v in line.split()[:2])
            points.append((y_mm, z_mm))
    return np.array(points)


def distances_to_polyline(points: np.ndarray, curve: np.ndarray):
    """Shortest distance of each point to the polyline ``curve`` (both (N, 2)), its foot point, and whether the point
    lies beyond an end of the polyline (outside the common range: its projection falls more than 0.1 um before the
    first or after the last vertex)."""
    nearest = cKDTree(curve).query(points)[1]
    best = np.full(len(points), np.inf)
    foot = np.zeros_like(points)
    beyond_end = np.zeros(len(points), dtype=bool)
    last_segment = len(curve) - 2
    for first in (nearest - 1, nearest):  # the two segments adjacent to the nearest vertex
        first = np.clip(first, 0, last_segment)
        a, b = curve[first], curve[first + 1]
        ab = b - a
        t_raw = np.einsum("ij,ij->i", points - a, ab) / np.einsum("ij,ij->i", ab, ab)
        candidate = a + np.clip(t_raw, 0.0, 1.0)[:, None] * ab
        d = np.hypot(*(points - candidate).T)
        better = d < best
        best[better], foot[better] = d[better], candidate[better]
        overshoot = np.maximum(-t_raw, t_raw - 1.0) * np.hypot(*ab.T)  # distance past the segment along it
        beyond = ((first == 0) & (t_raw < 0.0) | (first == last_segment) & (t_raw > 1.0)) & (overshoot > 1e-4)
        beyond_end[better] = beyond[better]
    return best, foot, beyond_end


def rotate(points: np.ndarray, angle: float) -> np.ndarray:
    """Rotate (y, z-down) points about the origin; positive angle moves points above the origin (z < 0) towards -y,
    i.e. a rail head rotated by +angle leans towards negative y (y' = y cos + z sin, z' = -y sin + z cos)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.column_stack((c * points[:, 0] + s * points[:, 1], -s * points[:, 0] + c * points[:, 1]))


def fit_translation(points: np.ndarray, curve: np.ndarray, iterations: int = 50):
    """Least-squares translation t (only) such that ``curve + t`` matches ``points`` (Gauss-Newton on the
    point-to-curve distances of the common range).  Returns t, distances, inside-common-range mask."""
    t = points[np.argmin(points[:, 1])] - curve[np.argmin(curve[:, 1])]  # start: align the tops of rail
    for _ in range(iterations):
        d, foot, at_end = distances_to_polyline(points - t, curve)
        inside = ~at_end & (d > 0.0)
        normal = (points - t - foot)[inside] / d[inside, None]
        residual = d[inside]
        step = np.linalg.lstsq(normal, residual, rcond=None)[0]  # d_i(t + step) ~ d_i - n_i . step
        t = t + step
        if np.hypot(*step) < 1e-10:
            break
    d, _, at_end = distances_to_polyline(points - t, curve)
    return t, d, ~at_end


def profile_mm(profile) -> np.ndarray:
    return np.column_stack((profile.y, profile.z)) * 1e3


def tangent_angle(dy, dz) -> float:
    return math.atan2(dz, dy)


# --------------------------------------------------------------------------------------------------------------
# comparison with the Manchester benchmark files
# --------------------------------------------------------------------------------------------------------------
def s1002_deviation_mm():
    file_points = read_simpack_points_mm(REFERENCE_DIR / "MBench_S1002_v3.prw")
    standard_frame = np.column_stack((-file_points[:, 0], file_points[:, 1]))  # undo mirror.y = 1
    d, _, at_end = distances_to_polyline(standard_frame, profile_mm(s1002_dense()))
    return d[~at_end], int(np.count_nonzero(at_end))


def uic60_deviation_mm(cant: float):
    file_points = read_simpack_points_mm(REFERENCE_DIR / "MBench_UIC60_v3.prr")
    curve = rotate(profile_mm(uic60_dense(depth_m=0.045)), cant)
    t, d, inside = fit_translation(file_points, curve)
    return d[inside], int(np.count_nonzero(~inside)), t


def test_s1002_matches_manchester_benchmark():
    d, outside = s1002_deviation_mm()
    assert outside == 0  # the file covers -60 .. +69.6 mm, inside our -70 .. +60 mm
    assert len(d) > 300
    assert d.max() <= MAX_DEVIATION_MM, f"max {d.max():.5f} mm, rms {np.sqrt(np.mean(d**2)):.5f} mm"


def test_uic60_matches_manchester_benchmark_after_cant():
    d, outside, _ = uic60_deviation_mm(+RAIL_CANT)
    assert outside == 0
    assert len(d) > 400
    assert d.max() <= MAX_DEVIATION_MM, f"max {d.max():.5f} mm, rms {np.sqrt(np.mean(d**2)):.5f} mm"


def test_uic60_cant_sense_is_towards_negative_y():
    """The opposite sense (head leaning towards +y) leaves a clearly larger deviation: the sense is not arbitrary."""
    right, _, _ = uic60_deviation_mm(+RAIL_CANT)
    wrong, _, _ = uic60_deviation_mm(-RAIL_CANT)
    assert wrong.max() > 10.0 * max(right.max(), 1e-3)


# --------------------------------------------------------------------------------------------------------------
# joints, frame and derivatives
# --------------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("sections", [s1002_sections(), uic60_sections()], ids=["S1002", "UIC60"])
def test_sections_join_with_continuous_position_and_tangent(sections):
    # Neither standard has a kink: every joint of S1002 (EN 13715) and of the 60E1 head is tangent-continuous.  The
    # rounded S1002 coefficients leave 4e-6 rad (D|C) and 3e-6 rad (C|B) and gaps of 0.12 and 0.04 um.
    for previous, following in zip(sections[:-1], sections[1:]):
        gap_m = math.hypot(following.y[0] - previous.y[-1], following.z[0] - previous.z[-1])
        assert gap_m < 1e-6, f"{previous.name} | {following.name}: gap {gap_m:.3e} m"
        kink = tangent_angle(following.dy[0], following.dz[0]) - tangent_angle(previous.dy[-1], previous.dz[-1])
        kink = (kink + math.pi) % (2.0 * math.pi) - math.pi
        assert abs(kink) < 1e-3, f"{previous.name} | {following.name}: kink {kink:.3e} rad"


@pytest.mark.parametrize("profile", [s1002_dense(), uic60_dense()], ids=["S1002", "UIC60"])
def test_derivatives_are_consistent_with_samples(profile):
    chord = np.column_stack((np.diff(profile.y), np.diff(profile.z)))
    tangent = np.column_stack((profile.dy, profile.dz))
    tangent /= np.hypot(*tangent.T)[:, None]
    mid_tangent = tangent[:-1] + tangent[1:]  # parallel to the chord up to O(h^2); joints are tangent-continuous
    cross = chord[:, 0] * mid_tangent[:, 1] - chord[:, 1] * mid_tangent[:, 0]
    sine = cross / (np.hypot(*chord.T) * np.hypot(*mid_tangent.T))
    assert np.all(np.abs(sine) < 1e-4)
    assert np.all(np.einsum("ij,ij->i", chord, mid_tangent) > 0.0)  # parameter increases along the point order
    spacing = np.hypot(*chord.T)
    assert spacing.max() < 2.05e-5 and spacing.min() > 1e-6


def test_s1002_frame_and_breaks():
    wheel = s1002_dense()
    assert wheel.y[0] == pytest.approx(S1002_FLANGE_BACK_Y_M, abs=1e-12)
    assert wheel.y[-1] == pytest.approx(0.060, abs=1e-12)
    assert abs(wheel.dy[0]) < 1e-12 * abs(wheel.dz[0])  # vertical tangent at the flange back
    assert np.interp(0.0, wheel.y[wheel.y > -0.03], wheel.z[wheel.y > -0.03]) == pytest.approx(0.0, abs=1e-9)
    assert wheel.z.max() == pytest.approx(0.028, abs=1e-8)  # flange height 28 mm (G: 16 + R12)
    assert len(S1002_BREAKS_Y_M) == 9 and np.all(np.diff(S1002_BREAKS_Y_M) > 0)


def test_uic60_frame_symmetry_and_curvature():
    rail = uic60_dense()
    assert rail.z.min() == pytest.approx(0.0, abs=1e-9)
    assert rail.z[0] == pytest.approx(0.030) and rail.z[-1] == pytest.approx(0.030)
    assert np.allclose(rail.y, -rail.y[::-1], atol=1e-12) and np.allclose(rail.z, rail.z[::-1], atol=1e-12)
    assert np.all(np.diff(rail.y) > 0)
    assert UIC60_BREAKS_Y_M[-1] - UIC60_BREAKS_Y_M[0] == pytest.approx(UIC60_HEAD_WIDTH_M, abs=1e-6)
    assert UIC60_SIDE_START_DEPTH_M == pytest.approx(0.01426, abs=1e-5)
    curvature = (rail.dy * rail.ddz - rail.dz * rail.ddy) / np.hypot(rail.dy, rail.dz) ** 3
    for radius, (low, high) in zip(UIC60_HEAD_RADII_M, [(-1e-2, 1e-2), (1.1e-2, 2.5e-2), (2.7e-2, 3.5e-2)]):
        band = (np.abs(rail.y) > low) & (np.abs(rail.y) < high)
        assert np.allclose(np.abs(curvature[band]), 1.0 / radius, rtol=1e-9)


def test_spacing_keyword_and_depth_validation():
    coarse, fine = s1002_dense(spacing_m=1e-4), s1002_dense()
    assert 4.5 < len(fine.y) / len(coarse.y) < 5.5
    assert np.hypot(np.diff(coarse.y), np.diff(coarse.z)).max() < 1.01e-4
    deep = uic60_dense(depth_m=0.040)
    assert deep.z[0] == pytest.approx(0.040)
    assert deep.y[0] == pytest.approx(-(0.036 + (0.040 - UIC60_SIDE_START_DEPTH_M) / 20.0))
    with pytest.raises(ValueError):
        uic60_dense(depth_m=0.010)  # above the start of the head side
    with pytest.raises(ValueError):
        s1002_dense(spacing_m=0.0)
