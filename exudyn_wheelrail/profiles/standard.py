"""Exact analytic standard profiles: the S1002 wheel and the 60E1 (UIC60) rail head.

Both profiles are returned as :class:`~exudyn_wheelrail.profiles.dense.DenseProfile` in the profile frame of
:mod:`exudyn_wheelrail.profiles.dense` (metres; ``y`` lateral, positive towards the field side; points ordered
from the flange / gauge side to the field side):

* **S1002** wheel, z = radius increase over the tape circle (positive towards the rail).  The profile is the
  piecewise analytic definition of EN 13715 (S1002 profile, formerly UIC 510-2 Appendix, sections A to H:
  straight lines, polynomials of degree 7 and 8 and circular arcs), in the standard's own y-z frame: y = 0 is the
  tape circle, which is 70 mm from the flange back, so the flange back is at y = -70 mm and the field side end of
  the definition at y = +60 mm.  The coefficients are the ones published with the definition; we read them in the
  widely reproduced S1002 function attributed to H. Netter (DLR Oberpfaffenhofen), public e.g. in numerical
  analysis course material (Lund University, NUMA41) as ``s1002(S)`` with its section table and bounds, and
  cross-checked the flange sections E to H against the EN 15302:2021 Annex I reference wheels (public transcription
  ``rohrbecka/EN15302``, ``WheelA.swift``, zones 1-4 use the same arcs R20.5, R12, R20 and the same flange-face
  line, rounded to 4 decimals).
* **60E1** rail head (EN 13674-1, profile 60E1 = UIC 60), z = depth below the top of the rail (positive down),
  unrotated and symmetric about y = 0: crown R300, then R80, then R13, all tangent-continuous, then the head
  side with a 1:20 inclination (the head widens downwards), head width 72 mm where R13 meets the side.  Radii,
  slope and width: read on the GENSYS manual page "Creation of a rail profile from a drawing"
  (gensys.se/doc_html/kpf/create_UIC60.html).  The R300 crown spans y = -10.5 .. +10.5 mm: this follows from the
  arc centres of the 60E1 reference rail A of EN 15302:2021 Annex I.7 (public transcription ``rohrbecka/EN15302``,
  ``RailA.swift``).  Note: the GENSYS page instead gives joint widths 20.456 mm (R300|R80) and 52.053 mm (R80|R13);
  those would lower the crown by about 0.02 mm relative to the head sides and disagree with both EN 15302 and the
  Manchester benchmark file, so we do not use them.

Independent check: ``tests/test_standard_profiles.py`` compares both with the Manchester contact benchmark profile
files (SIMPACK format, see the test for the frames): largest deviation 0.1 um for S1002 and 0.03 um for 60E1
(canted 1:40, translation fitted), against a requirement of 0.05 mm.

Every section is sampled densely (default spacing 0.02 mm along the curve) with exact first and second derivatives
with respect to a parameter that increases along the point order: tau = y for graphs z(y), tau = +-angle for circular
arcs (this handles the vertical tangent of S1002 at the flange back) and tau = arc length for the straight 60E1 head
sides.  Consecutive sections share their joint point.
"""
from __future__ import annotations

import math

import numpy as np

from .dense import DenseProfile

_MM = 1e-3  # one millimetre in metres; the standards' numbers are in mm
_JOINT_TOLERANCE_M = 1e-6  # gap allowed between published section ends (coefficients are rounded to ~10 digits)
_JOINT_BLEND_LENGTH_M = 5e-3  # arc length over which such a gap is faded out (see _join)

# ----------------------------------------------------------------------------------------------------------------
# S1002 (EN 13715, S1002 profile; UIC 510-2).  Lengths in mm, standard frame.  Section letters as in the standard:
# H = flange back arc, G = flange tip arc, F = flange root arc, E = flange face line, D = throat arc,
# C and B = tread polynomials, A = field side 1:15 line.
# Source of every number below: EN 13715 S1002 definition table (sections A..H, bounds), read in the public
# "s1002(S)" table attributed to H. Netter (DLR) (see module docstring); E..H also agree with EN 15302:2021
# Annex I.2 (rohrbecka/EN15302 WheelA.swift) to its 4 printed decimals.
# ----------------------------------------------------------------------------------------------------------------
S1002_FLANGE_BACK_Y_M = -0.070  # EN 13715 S1002: flange back 70 mm from the tape circle (section H, vertical tangent)
S1002_FIELD_END_Y_M = 0.060  # EN 13715 S1002: field side end of section A

# Section joints (mm), from the flange back to the field side: H|G|F|E|D|C|B|A.  EN 13715 S1002 bounds table
# (Netter table "Bounds": H -70..-62.764705882, G ..-49.662510381, F ..-39.764473993, E ..-38.426669071,
# D ..-35, C ..-26, B ..+32.15796, A ..+60).
_S1002_BREAKS_MM = (-70.0, -62.764705882, -49.662510381, -39.764473993, -38.426669071, -35.0, -26.0, 32.15796, 60.0)
S1002_BREAKS_Y_M = tuple(b * _MM for b in _S1002_BREAKS_MM)
S1002_SECTION_NAMES = ("H", "G", "F", "E", "D", "C", "B", "A")  # order of the sections between the breaks

# Section A (EN 13715 S1002, A): z = A_A - B_A y  (1:15 field side line).  Netter table: A_A, B_A.
_S1002_A_MM = (1.364323640, -0.066666667)
# Section B (EN 13715 S1002, B): z = A_B - B_B y + C_B y^2 - D_B y^3 + E_B y^4 - F_B y^5 + G_B y^6 - H_B y^7 + I_B y^8,
# ascending coefficients with the standard's alternating signs applied.  Netter table: A_B..I_B.
_S1002_B_MM = (0.0, -3.358537058e-02, 1.565681624e-03, -2.810427944e-05, 5.844240864e-08, -1.562379023e-08,
               5.309217349e-15, -5.957839843e-12, 2.646656573e-13)
# Section C (EN 13715 S1002, C): z = -A_C - B_C y - C_C y^2 - ... - H_C y^7 (all signs negative).  Netter: A_C..H_C.
_S1002_C_MM = (-4.320221063e+03, -1.038384026e+03, -1.065501873e+02, -6.051367875, -2.054332446e-01,
               -4.169739389e-03, -4.687195829e-05, -2.252755540e-07)
# Section E (EN 13715 S1002, E): z = -A_E - B_E y (flange face line).  Netter: A_E = 93.576667419, B_E = 2.747477419.
_S1002_E_MM = (-93.576667419, -2.747477419)
# Arcs (EN 13715 S1002, D, F, G, H): z = A +- sqrt(B^2 - (y + C)^2), i.e. centre (y, z) = (-C, A), radius B;
# side +1 for '+sqrt' (upper half, z above the centre), -1 for '-sqrt'.  Netter table: A_x, B_x, C_x.
_S1002_ARCS_MM = {
    "D": ((-26.210665, 16.446), 13.0, -1),  # A_D = 16.446, B_D = 13, C_D = 26.210665
    "F": ((-58.558326413, 8.834924130), 20.0, +1),  # A_F = 8.834924130, B_F = 20, C_F = 58.558326413
    "G": ((-55.0, 16.0), 12.0, +1),  # A_G = 16, B_G = 12, C_G = 55
    "H": ((-49.5, 9.519259302), 20.5, +1),  # A_H = 9.519259302, B_H = 20.5, C_H = 49.5
}
_S1002_GRAPHS_MM = {"A": _S1002_A_MM, "B": _S1002_B_MM, "C": _S1002_C_MM, "E": _S1002_E_MM}

# ----------------------------------------------------------------------------------------------------------------
# 60E1 / UIC60 rail head (EN 13674-1, 60E1 profile drawing).  Radii, side slope and head width: EN 13674-1 60E1
# drawing, read on the GENSYS manual page "Creation of a rail profile from a drawing" (create_UIC60).  Width of
# the R300 crown: EN 15302:2021 Annex I.7 reference rail A (a 60E1 head inclined 1:20, judging by its arcs
# R300/R80/R13 and its 72 mm head width), public transcription
# rohrbecka/EN15302 RailA.swift, whose arc centres give sin(phi_R300) = 0.035007 (R300 to y = +-10.500 mm, R80
# centres at +-7.700 mm) and an R13 that meets the 1:20 side at y = +-36.000 mm (centre distance 46.0324 mm).
# ----------------------------------------------------------------------------------------------------------------
UIC60_HEAD_RADII_M = (0.300, 0.080, 0.013)  # EN 13674-1 60E1 drawing: crown R300, R80, corner R13 (GENSYS page)
UIC60_SIDE_SLOPE = 1.0 / 20.0  # EN 13674-1 60E1 drawing: head side inclination 1:20 (GENSYS page), dy/dz
UIC60_HEAD_WIDTH_M = 0.072  # EN 13674-1 60E1 drawing: head width 72 mm (GENSYS page), taken where R13 meets the side
# EN 13674-1 60E1: R300 crown from y = -10.5 to +10.5 mm, as given by EN 15302:2021 Annex I.7 rail A (see above).
_UIC60_R300_END_HALF_WIDTH_MM = 10.5


def _uic60_geometry_mm():
    """Centres (y, z) and joint angles of the 60E1 head arcs, field side half (y >= 0), mm.

    Angles phi are measured from the upward vertical at the arc centre towards the field side: a point of an arc is
    centre + R (sin phi, -cos phi).  R80 is tangent to R300 at y = 10.5 mm; R13 is tangent to R80 and to the 1:20
    side, which it meets at half the head width (y = 36 mm); this fixes the R80|R13 joint (y = 25.988 mm).
    """
    r300, r80, r13 = (r / _MM for r in UIC60_HEAD_RADII_M)
    c300 = (0.0, r300)  # top of rail at (0, 0)
    phi1 = math.asin(_UIC60_R300_END_HALF_WIDTH_MM / r300)
    c80 = (c300[0] + (r300 - r80) * math.sin(phi1), c300[1] - (r300 - r80) * math.cos(phi1))
    phi3 = math.atan(1.0 / UIC60_SIDE_SLOPE)  # R13 normal at the side joint, perpendicular to the 1:20 side
    c13_y = 0.5 * UIC60_HEAD_WIDTH_M / _MM - r13 * math.sin(phi3)
    phi2 = math.asin((c13_y - c80[0]) / (r80 - r13))
    c13 = (c13_y, c80[1] - (r80 - r13) * math.cos(phi2))
    side_start = (c13[0] + r13 * math.sin(phi3), c13[1] - r13 * math.cos(phi3))
    r80_end_y = c80[0] + r80 * math.sin(phi2)
    return dict(c300=c300, c80=c80, c13=c13, phi1=phi1, phi2=phi2, phi3=phi3, side_start=side_start,
                r80_end_y=r80_end_y)


_UIC60_GEOMETRY_MM = _uic60_geometry_mm()
_UIC60_HALF_BREAKS_MM = (_UIC60_R300_END_HALF_WIDTH_MM, _UIC60_GEOMETRY_MM["r80_end_y"],
                         _UIC60_GEOMETRY_MM["side_start"][0])
# Lateral positions of the section joints, gauge side to field side: side|R13|R80|R300|R80|R13|side (metres).
UIC60_BREAKS_Y_M = tuple(sorted(sign * b * _MM for b in _UIC60_HALF_BREAKS_MM for sign in (-1.0, 1.0)))
# Depth below the top of rail where the R13 corner meets the 1:20 side (derived, 14.2597 mm).
UIC60_SIDE_START_DEPTH_M = _UIC60_GEOMETRY_MM["side_start"][1] * _MM


# ----------------------------------------------------------------------------------------------------------------
# sampling helpers
# ----------------------------------------------------------------------------------------------------------------
def _interval_count(length_m: float, spacing_m: float) -> int:
    return max(3, math.ceil(length_m / spacing_m))


def _arc(name: str, centre_mm, radius_mm: float, theta_start: float, theta_end: float, spacing_m: float):
    """Arc centre + R (cos theta, sin theta) in (y, z) from theta_start to theta_end; tau = +-theta, increasing."""
    sense = 1.0 if theta_end > theta_start else -1.0
    radius_m = radius_mm * _MM
    theta = np.linspace(theta_start, theta_end, _interval_count(radius_m * abs(theta_end - theta_start), spacing_m) + 1)
    cos_t, sin_t = np.cos(theta), np.sin(theta)
    return DenseProfile(y=centre_mm[0] * _MM + radius_m * cos_t, z=centre_mm[1] * _MM + radius_m * sin_t,
                        dy=-sense * radius_m * sin_t, dz=sense * radius_m * cos_t,
                        ddy=-radius_m * cos_t, ddz=-radius_m * sin_t, name=name)


def _graph_arc(name: str, centre_mm, radius_mm: float, side: int, y_start_mm: float, y_end_mm: float, spacing_m):
    """Arc written as z = z_c + side * sqrt(R^2 - (y - y_c)^2), sampled by angle between two lateral positions."""
    def angle(y_mm):
        return side * math.acos(min(1.0, max(-1.0, (y_mm - centre_mm[0]) / radius_mm)))
    return _arc(name, centre_mm, radius_mm, angle(y_start_mm), angle(y_end_mm), spacing_m)


def _graph(name: str, coefficients_mm, y_start_mm: float, y_end_mm: float, spacing_m: float):
    """Polynomial graph z(y) = sum c_k y^k (mm) sampled about uniformly in arc length; tau = y (metres)."""
    z_mm = np.polynomial.Polynomial(coefficients_mm)
    dz_mm, ddz_mm = z_mm.deriv(1), z_mm.deriv(2)
    y_fine = np.linspace(y_start_mm, y_end_mm, 4001)
    slope = dz_mm(y_fine)
    speed = np.sqrt(1.0 + slope * slope)
    arc_mm = np.concatenate(([0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(y_fine))))
    count = _interval_count(arc_mm[-1] * _MM, spacing_m)
    y_mm = np.interp(np.linspace(0.0, arc_mm[-1], count + 1), arc_mm, y_fine)
    y_mm[0], y_mm[-1] = y_start_mm, y_end_mm
    return DenseProfile(y=y_mm * _MM, z=z_mm(y_mm) * _MM, dy=np.ones_like(y_mm), dz=dz_mm(y_mm),
                        ddy=np.zeros_like(y_mm), ddz=ddz_mm(y_mm) / _MM, name=name)


def _line(name: str, start_m, end_m, spacing_m: float):
    """Straight segment from start to end; tau = arc length."""
    start, end = np.asarray(start_m, float), np.asarray(end_m, float)
    length = float(np.hypot(*(end - start)))
    s = np.linspace(0.0, length, _interval_count(length, spacing_m) + 1)
    unit = (end - start) / length
    y, z = start[0] + unit[0] * s, start[1] + unit[1] * s
    y[-1], z[-1] = end
    return DenseProfile(y=y, z=z, dy=np.full_like(s, unit[0]), dz=np.full_like(s, unit[1]),
                        ddy=np.zeros_like(s), ddz=np.zeros_like(s), name=name)


def _fade_in_offset(section: DenseProfile, offset_m, blend_length_m: float) -> DenseProfile:
    """Shift the start of a section by ``offset_m`` (y, z), fading the shift out C2-smoothly along the first
    ``blend_length_m`` of arc length (quintic weight w(u) = 1 - 10u^3 + 15u^4 - 6u^5); derivatives stay exact."""
    chord = np.hypot(np.diff(section.y), np.diff(section.z))
    arc = np.concatenate(([0.0], np.cumsum(chord)))
    length = min(blend_length_m, 0.5 * arc[-1])
    u = np.clip(arc / length, 0.0, 1.0)
    w = (1.0 - u) ** 3 * (1.0 + 3.0 * u + 6.0 * u * u)
    dw = -30.0 * u * u * (1.0 - u) ** 2
    ddw = -60.0 * u * (1.0 - u) * (1.0 - 2.0 * u)
    speed = np.hypot(section.dy, section.dz)
    du = speed / length  # du/dtau
    ddu = (section.dy * section.ddy + section.dz * section.ddz) / (speed * length)  # d2u/dtau2
    oy, oz = offset_m
    return DenseProfile(section.y + oy * w, section.z + oz * w,
                        section.dy + oy * dw * du, section.dz + oz * dw * du,
                        section.ddy + oy * (ddw * du * du + dw * ddu), section.ddz + oz * (ddw * du * du + dw * ddu),
                        name=section.name)


def _join(sections: list[DenseProfile], name: str) -> DenseProfile:
    """Concatenate sections so that each start coincides exactly with the previous end.

    The published S1002 coefficients are rounded: the tread polynomial C misses the throat arc D by 0.12 um and the
    polynomial B by 0.04 um.  Such a gap (checked to be below 1 um) is closed by fading a shift of the following
    section out over its first 5 mm (at most half its length), which keeps the samples on a C2 curve with exact
    derivatives instead of leaving a 0.1 um step between two samples 0.02 mm apart.
    """
    joined = [sections[0]]
    for section in sections[1:]:
        previous = joined[-1]
        offset = (previous.y[-1] - section.y[0], previous.z[-1] - section.z[0])
        gap = math.hypot(*offset)
        if gap > _JOINT_TOLERANCE_M:
            raise ValueError(f"{name}: gap of {gap:.3e} m between '{previous.name}' and '{section.name}'")
        if gap > 0.0:
            section = _fade_in_offset(section, offset, _JOINT_BLEND_LENGTH_M)
            y, z = section.y.copy(), section.z.copy()
            y[0], z[0] = previous.y[-1], previous.z[-1]  # exact coincidence (rounding), so concatenate merges them
            section = DenseProfile(y, z, section.dy, section.dz, section.ddy, section.ddz, name=section.name)
        joined.append(section)
    return DenseProfile.concatenate(joined, name=name)


def _check_spacing(spacing_m: float) -> None:
    if not (0.0 < spacing_m <= 1e-3):
        raise ValueError(f"spacing_m must be in (0, 1 mm], got {spacing_m}")


# ----------------------------------------------------------------------------------------------------------------
# public API
# ----------------------------------------------------------------------------------------------------------------
def s1002_sections(spacing_m: float = 2e-5) -> list[DenseProfile]:
    """The S1002 sections H, G, F, E, D, C, B, A (flange back to field side), each sampled on its own.

    Section ends are evaluated from each section's own published formula, so consecutive sections meet only to the
    precision of the published coefficients (gaps below 0.2 um, at the ends of section C); :func:`s1002_dense`
    closes them (see ``_join``).
    """
    _check_spacing(spacing_m)
    sections = []
    for k, letter in enumerate(S1002_SECTION_NAMES):
        y_start, y_end = _S1002_BREAKS_MM[k], _S1002_BREAKS_MM[k + 1]
        name = f"S1002 {letter}"
        if letter in _S1002_ARCS_MM:
            centre, radius, side = _S1002_ARCS_MM[letter]
            sections.append(_graph_arc(name, centre, radius, side, y_start, y_end, spacing_m))
        else:
            sections.append(_graph(name, _S1002_GRAPHS_MM[letter], y_start, y_end, spacing_m))
    return sections


def s1002_dense(spacing_m: float = 2e-5) -> DenseProfile:
    """S1002 wheel profile (EN 13715) from the flange back (y = -70 mm) to the field side end (y = +60 mm).

    Profile frame, metres: y lateral (field side positive, tape circle at y = 0), z radius increase over the tape
    circle.  ``spacing_m`` is the approximate distance between samples along the curve.
    """
    return _join(s1002_sections(spacing_m), name="S1002")


def uic60_sections(spacing_m: float = 2e-5, depth_m: float = 0.030) -> list[DenseProfile]:
    """The 60E1 head sections gauge side, R13, R80, R300, R80, R13, field side (unrotated, top of rail at z = 0)."""
    _check_spacing(spacing_m)
    g = _UIC60_GEOMETRY_MM
    side_start_mm = g["side_start"]
    if depth_m <= side_start_mm[1] * _MM:
        raise ValueError(f"depth_m must exceed the start of the head side ({side_start_mm[1] * _MM:.6f} m)")
    r300, r80, r13 = (r / _MM for r in UIC60_HEAD_RADII_M)
    side_end_mm = (side_start_mm[0] + UIC60_SIDE_SLOPE * (depth_m / _MM - side_start_mm[1]), depth_m / _MM)

    # Field side half: centre + R (sin phi, -cos phi) is centre + R (cos theta, sin theta) with theta = phi - pi/2;
    # the gauge side half is its mirror image y -> -y, i.e. theta -> pi - theta, equivalent to theta = -pi/2 - phi.
    def field(phi):
        return phi - 0.5 * math.pi

    def gauge(phi):
        return -phi - 0.5 * math.pi

    def mirror(point):
        return (-point[0], point[1])

    phi1, phi2, phi3 = g["phi1"], g["phi2"], g["phi3"]
    return [
        _line("UIC60 gauge side 1:20", (-side_end_mm[0] * _MM, side_end_mm[1] * _MM),
              (-side_start_mm[0] * _MM, side_start_mm[1] * _MM), spacing_m),
        _arc("UIC60 gauge R13", mirror(g["c13"]), r13, gauge(phi3), gauge(phi2), spacing_m),
        _arc("UIC60 gauge R80", mirror(g["c80"]), r80, gauge(phi2), gauge(phi1), spacing_m),
        _arc("UIC60 R300", g["c300"], r300, gauge(phi1), field(phi1), spacing_m),
        _arc("UIC60 field R80", g["c80"], r80, field(phi1), field(phi2), spacing_m),
        _arc("UIC60 field R13", g["c13"], r13, field(phi2), field(phi3), spacing_m),
        _line("UIC60 field side 1:20", (side_start_mm[0] * _MM, side_start_mm[1] * _MM),
              (side_end_mm[0] * _MM, side_end_mm[1] * _MM), spacing_m),
    ]


def uic60_dense(spacing_m: float = 2e-5, depth_m: float = 0.030) -> DenseProfile:
    """60E1 (UIC60) rail head profile (EN 13674-1), unrotated, symmetric about y = 0, top of rail at z = 0.

    Runs from the gauge side at ``depth_m`` below the top of rail over the crown to the field side at the same
    depth.  Profile frame, metres: y lateral (field side positive), z depth below the top of rail.
    """
    return _join(uic60_sections(spacing_m, depth_m), name="UIC60")
