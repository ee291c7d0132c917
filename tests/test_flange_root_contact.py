"""Flange-root contact of S1002 on UIC60 1:40: one contact per overlap zone, checked against a brute force.

Near the flange root the tread's overlap zone grows across the tread/flange split (the split is the package's own
device, Montenegro et al. 2015 Sec. 2.1); the flange region then sees only the tail of that zone and must not
report it as a contact of its own, else the same interpenetration carries two Hertz forces.  (The kernel follows
the normal penetration of a concave point uphill and drops a region whose penetration still rises at its split end:
it has no maximum of its own.)

Poses: the left wheel flanges (wheelset shifted to y = -7.0 ... -6.0 mm in 0.02 mm steps), at roll 0 and 0.5 mrad;
the axle height puts the left wheel's largest *vertical* overlap with its rail at 150 µm (brute force, exact in z:
every wheel point moves down by the same dz), so the deepest normal penetration is 50-140 µm.

Reference (``penetration_maxima``): the whole wheel profile, tread and flange as one curve (the reference does not
know where the split is), sampled every 20 µm, penetration p(s) = minus the signed distance to the rail from
``tests/brute_force.py`` (nearest of ~1 µm rail samples, projected on its normal).  Every local maximum of p with
p > 0 is the deepest point of one overlap zone: one Hertz contact.  Each is refined on a 0.1 µm grid.

Asserted per pose and wheel, for the kernel's force-carrying contacts (``WheelsetContact.evaluate``, global search):

1. one contact per zone: each kernel contact lies in the acceptance interval of a *distinct* brute-force maximum,
   and every maximum has one -- a second contact in the same zone (a double count) or a missed zone fails;
2. its penetration equals the maximum's, |delta_k - delta_bf| <= PEN_TOL;
3. the total normal force equals the sum of the Hertz forces of the brute-force maxima (curvatures from the profile
   curves at the brute-force point, ``hertz_from_penetration``, itself tested against the m, n table).

Tolerances, from the conditioning (no measured numbers):

* brute force: the nearest rail sample lies <= h_r/2 (arc) from the foot of the normal; the distance projected on
  its normal overestimates the penetration by (h_r/2)^2 kappa_r (1 - kappa_r delta) / 2 <= EPS_BF = h_r^2
  max|kappa_r| / 8 (1.04e-11 m for h_r = 1 µm, max|kappa_r| = 83 1/m sampled every 1 µm along the rail), never
  underestimates;
* kernel: a converged point is the exact stationary point up to the Newton step tolerance (1e-11 m in s; the
  concave branch's golden section stops at 1e-10 m), which changes the penetration at a maximum only to second
  order, kappa_rel (1e-10 m)^2 / 2 < 1e-17 m; plus the rounding of a normal distance, EPS_DISTANCE = 1e-15 m;
* 0.1 µm grid of the refinement: the grid maximum misses the true one by <= kappa_bound h_f^2 / 8 (2e-13 m),
  kappa_bound >= |p''| = |kappa_w| + |kappa_r| / (1 - |kappa_r| delta);
  so PEN_TOL = EPS_BF + kappa_bound h_f^2 / 8 + EPS_DISTANCE;
* acceptance interval of a maximum: every wheel point whose brute-force penetration is within EPS_BF +
  EPS_DISTANCE of the maximum (a kernel point at the true maximum is there; nothing else can be told apart
  from it).  A well-curved maximum gives ~1 µm, a conformal one (kappa_rel ~ 0) ~15 µm;
* force: N ~ delta^1.5, so a depth error eps moves N by ((1 + eps/delta)^1.5 - 1) N ~ 1.5 eps/delta N; the
  curvatures (Hertz A, B) may differ by their change over the acceptance interval, taken as the spread of the
  Hertz force evaluated across it at the brute-force depth;
* two maxima are two zones only if the dip between them (prominence) exceeds what the 20 µm scan can hide,
  kappa_bound h_w^2 / 8 + EPS_BF (8.6e-9 m); a maximum less prominent than that but above the brute force's noise
  EPS_BF would make the reference ambiguous: asserted absent.

Densified where the zone's deepest point passes from the flange region through the throat into the tread
(``BAND_Y_MM``, 2.5 µm steps; roll 0: y = -6.670 ... -6.610 mm, roll 0.5 mrad: -6.430 ... -6.370 mm): there the
flange region's largest *vertical* overlap stays on the flank (magnified by the 70 deg flank) while the normal
penetration rises from the flank through the throat to the deepest point, just across the split -- one zone, whose
tail the flange region must not report with a force of its own (before the tread region takes over, the deepest
point lies in the conformal throat, a concave contact of the flange region).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.signal import find_peaks

from brute_force import FastRailDistance, max_vertical_overlap, wheel_points
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact.normal import E_STEEL, NU_STEEL, effective_modulus, hertz_from_penetration
from exudyn_wheelrail.contact.pair import WheelRailPair
from exudyn_wheelrail.contact.wheelset import SIDES, WheelsetContact

Y_GRID_MM = np.round(np.arange(-350, -299) * 0.02, 10)      # -7.00 ... -6.00 mm, 0.02 mm
ROLLS_MRAD = (0.0, 0.5)
VERTICAL_OVERLAP_M = 150e-6       # left wheel's largest vertical overlap (sets the axle height)
WHEEL_SCAN_M = 20e-6              # h_w: whole-wheel scan of the brute force
FINE_M = 1e-7                     # h_f: refinement grid around each maximum
EPS_DISTANCE_M = 1e-15            # rounding of a normal distance (~10 roundings of metre-sized coordinates)
MAX_PENETRATION_M = 2e-4          # bound of the penetrations here (for kappa_bound's 1 / (1 - kappa_r delta))
# where the zone's deepest point passes through the throat (module docstring): y [mm] per roll [mrad], 2.5 µm steps
BAND_Y_MM = {0.0: np.round(-6.670 + 0.0025 * np.arange(25), 10), 0.5: np.round(-6.430 + 0.0025 * np.arange(25), 10)}


@dataclass
class Reference:
    pair: WheelRailPair
    contact: WheelsetContact
    rd: FastRailDistance
    whole: object                 # the whole wheel curve (tread + flange), wheelset frame
    eps_bf: float
    kappa_bound: float
    pen_tol: float
    prominence_min: float
    E_star: float
    min_curvature: float


@pytest.fixture(scope="module")
def ref():
    pair = WheelRailPair("S1002", "UIC60", gauge_m=1.435, inclination="1/40", back_to_back_m=1.360, r0_m=0.46)
    rd = FastRailDistance(pair.rail_side)
    # the region curves share the whole profile's arc length (and node data), so s is comparable
    whole = pair.wheel.curve.transformed(0.0, (pair.wheel_offset_y_m, pair.r0_m))
    h_r = rd.s[1] - rd.s[0]
    kappa_r = float(np.max(np.abs(pair.rail_side.curvature(rd.s))))
    kappa_w = float(np.max(np.abs(whole.curvature(np.linspace(whole.s_min, whole.s_max,
                                                              int(whole.length / h_r) + 1)))))
    eps_bf = h_r ** 2 * kappa_r / 8
    kappa_bound = kappa_w + kappa_r / (1 - kappa_r * MAX_PENETRATION_M)
    contact = WheelsetContact(pair, global_search=True)
    return Reference(pair=pair, contact=contact, rd=rd, whole=whole, eps_bf=eps_bf, kappa_bound=kappa_bound,
                     pen_tol=eps_bf + kappa_bound * FINE_M ** 2 / 8 + EPS_DISTANCE_M,
                     prominence_min=kappa_bound * WHEEL_SCAN_M ** 2 / 8 + eps_bf,
                     E_star=effective_modulus(E_STEEL, NU_STEEL, E_STEEL, NU_STEEL),
                     min_curvature=float(contact.params[K.P_MIN_CURVATURE]))


def _penetration(ref, s, pose):
    return -ref.rd.signed_distance(wheel_points(ref.whole, s, pose))[0]


@dataclass
class Maximum:
    s: float                      # wheel arc length of the deepest point
    delta: float                  # its penetration
    lo: float                     # acceptance interval [lo, hi] (see the module docstring)
    hi: float
    s_interval: np.ndarray        # fine samples in it


def penetration_maxima(ref, pose):
    """Deepest points of the overlap zones of the whole wheel at a side-frame pose (brute force)."""
    cv = ref.whole
    s = np.linspace(cv.s_min, cv.s_max, int(cv.length / WHEEL_SCAN_M) + 1)
    p = _penetration(ref, s, pose)
    peaks, props = find_peaks(np.concatenate([[-np.inf], p, [-np.inf]]), prominence=(None, None))
    maxima = []
    for k, prominence in zip(peaks - 1, props["prominences"]):
        if p[k] <= 0 or prominence <= ref.eps_bf:           # no overlap, or the brute force's own noise
            continue
        assert prominence > ref.prominence_min, ("two maxima closer than the scan can separate", pose, s[k])
        # refine on the fine grid; widen the window while its edges are still within the acceptance threshold
        half = WHEEL_SCAN_M
        while True:
            s_f = np.arange(max(cv.s_min, s[k] - half), min(cv.s_max, s[k] + half) + FINE_M / 2, FINE_M)
            p_f = _penetration(ref, s_f, pose)
            inside = p_f >= p_f.max() - (ref.eps_bf + EPS_DISTANCE_M)
            open_lo = inside[0] and s_f[0] > cv.s_min
            open_hi = inside[-1] and s_f[-1] < cv.s_max
            if not (open_lo or open_hi):
                break
            half *= 2
            assert half <= 2e-3, ("no isolated maximum", pose, s[k])
        j = int(np.argmax(p_f))
        assert p_f[j] <= MAX_PENETRATION_M, (pose, p_f[j])       # kappa_bound holds up to this depth
        idx = np.flatnonzero(inside)
        maxima.append(Maximum(s=float(s_f[j]), delta=float(p_f[j]), lo=float(s_f[idx[0]] - FINE_M),
                              hi=float(s_f[idx[-1]] + FINE_M), s_interval=s_f[idx]))
    return maxima


def hertz_force_at(ref, s_w, delta, pose):
    """Hertz normal force of a contact at wheel point s_w with penetration delta, curvatures from the profiles:
    A = (wheel rolling curvature, Meusnier cos(psi)/r = n_z / r in the wheelset frame; straight rail: 0) / 2,
    B = (kappa_w + kappa_r at the foot of the normal on the rail) / 2."""
    py, pz, ty, tz, ny, nz, kappa_w = ref.whole.evaluate([s_w])[0]
    pw = wheel_points(ref.whole, s_w, pose)[0]
    rail = ref.pair.rail_side
    j = ref.rd.signed_distance(pw[None, :])[1][0]
    h = ref.rd.s[1] - ref.rd.s[0]

    def tangential_offset(s_r):                     # t_r(s_r) . (p_w - r(s_r)): zero at the foot of the normal
        e = rail.evaluate([s_r])[0]
        return e[2] * (pw[0] - e[0]) + e[3] * (pw[1] - e[1])

    s_foot = brentq(tangential_offset, ref.rd.s[j] - 2 * h, ref.rd.s[j] + 2 * h, xtol=1e-14)
    kappa_r = rail.curvature([s_foot])[0]
    return hertz_from_penetration(0.5 * nz / pz, 0.5 * (kappa_w + kappa_r), ref.E_star, delta, ref.min_curvature)[0]


def _force_tolerance(ref, m, pose):
    """What the kernel's Hertz force of this zone may differ by (module docstring): depth and curvature terms."""
    n_bf = hertz_force_at(ref, m.s, m.delta, pose)
    depth = ((1 + ref.pen_tol / m.delta) ** 1.5 - 1) * n_bf
    pick = np.unique(np.linspace(0, len(m.s_interval) - 1, min(len(m.s_interval), 41)).round().astype(int))
    s_probe = np.concatenate([[max(m.lo, ref.whole.s_min), min(m.hi, ref.whole.s_max)], m.s_interval[pick]])
    spread = max(abs(hertz_force_at(ref, s, m.delta, pose) - n_bf) for s in s_probe)
    return n_bf, depth + spread


def _cases():
    for roll in ROLLS_MRAD:
        for y in Y_GRID_MM:
            yield pytest.param(float(roll), float(y), id=f"roll={roll:.1f}mrad-y={y:+.2f}mm")
        for y in BAND_Y_MM[roll]:
            if not np.isclose(y, Y_GRID_MM).any():
                yield pytest.param(float(roll), float(y), id=f"roll={roll:.1f}mrad-y={y:+.4f}mm")


@pytest.mark.parametrize("roll_mrad, y_mm", list(_cases()))
def test_one_contact_per_overlap_zone_with_brute_force_depth_and_force(ref, roll_mrad, y_mm):
    y, roll = y_mm * 1e-3, roll_mrad * 1e-3
    # axle height: the left wheel's largest vertical overlap = VERTICAL_OVERLAP_M (side frame of the left wheel:
    # (-y, z, -roll), conventions.py); refine=False: the sampled maximum, exact enough for choosing a pose
    v0 = max_vertical_overlap(ref.whole, ref.pair.rail_side, (-y, -0.46, -roll), spacing_m=WHEEL_SCAN_M,
                              refine=False)[1]
    z = -0.46 - v0 + VERTICAL_OVERLAP_M
    out = ref.contact.evaluate(np.array([[y, z, roll]])).copy()
    n_contacts = 0
    for w, side in enumerate(SIDES):
        sigma = 1.0 if side == "right" else -1.0
        pose = (sigma * y, z, sigma * roll)
        maxima = penetration_maxima(ref, pose)
        if side == "left":
            assert maxima, pose                    # the pose does put the flanging wheel in contact
        contacts = [out[w, k] for k in range(K.N_SLOTS) if out[w, k, K.F_STATUS] > 0]
        n_contacts += len(contacts)
        where = f"{side} wheel, pose {pose}"
        bf_txt = [(round(m.s * 1e3, 4), round(m.delta * 1e6, 4)) for m in maxima]
        k_txt = [(round(float(o[K.F_S_WHEEL]) * 1e3, 4), round(float(o[K.F_PENETRATION]) * 1e6, 4),
                  round(float(o[K.F_NORMAL_FORCE]))) for o in contacts]
        msg = f"{where}: brute-force maxima (s mm, delta µm) {bf_txt}; kernel contacts (s mm, delta µm, N) {k_txt}"
        # 1. one kernel contact per overlap zone, at the zone's deepest point
        matched = []
        for o in contacts:
            i = int(np.argmin([abs(o[K.F_S_WHEEL] - m.s) for m in maxima])) if maxima else -1
            assert i >= 0 and maxima[i].lo <= o[K.F_S_WHEEL] <= maxima[i].hi, \
                f"kernel contact at s = {o[K.F_S_WHEEL] * 1e3:.4f} mm is at no penetration maximum; {msg}"
            matched.append(i)
        assert sorted(matched) == list(range(len(maxima))), f"double-counted or missed zone; {msg}"
        # 2. its depth
        for o, i in zip(contacts, matched):
            assert abs(o[K.F_PENETRATION] - maxima[i].delta) <= ref.pen_tol, \
                (o[K.F_PENETRATION] - maxima[i].delta, ref.pen_tol, msg)
        # 3. total normal force = the Hertz forces of the brute-force zones
        ref_forces = [_force_tolerance(ref, m, pose) for m in maxima]
        n_ref = sum(f for f, _ in ref_forces)
        tol = sum(t for _, t in ref_forces)
        n_kernel = float(out[w, :, K.F_NORMAL_FORCE].sum())
        assert abs(n_kernel - n_ref) <= tol, (n_kernel, n_ref, tol, msg)
    assert n_contacts >= 1
