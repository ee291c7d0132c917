"""Helpers shared by the contact benchmarks: finding right-wheel side-frame poses at which the kernel uses the
concave search (status 2), and the region bounds of the packed curves.

Curve ids in ``WheelsetContact`` / ``WheelRailPair.packed()``: 0 = rail, 1 = tread region, 2 = flange region.
A pose is ``(c_y, c_z, roll)`` of the wheelset relative to the rail in the side frame (right-side convention,
y to the field side, z down).
"""
from __future__ import annotations

import numpy as np

from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact.search import vertical_overlap_search
from exudyn_wheelrail.contact.wheelset import WheelsetContact

REGION_NAMES = ("tread", "flange")
C_Z_PROBE_M = -0.46


def region_bounds(nodes, meta, curve: int) -> tuple[float, float]:
    first = int(meta[curve, 0])
    n = int(meta[curve, 1])
    return float(nodes[first, 0]), float(nodes[first + n - 1, 0])


def max_overlap_at(contact: WheelsetContact, c_y: float, c_z: float, roll: float, n: int = 400):
    """Maximum vertical overlap of each region (tread, flange) at a pose; -inf where nothing overlaps."""
    res = []
    for curve in (1, 2):
        lo, hi = region_bounds(contact.nodes, contact.meta, curve)
        found, s_w, s_r, dv = vertical_overlap_search(contact.nodes, contact.meta, contact.mono, 0, curve, c_y, c_z,
                                                      np.cos(roll), np.sin(roll), lo, hi, n, n, True)
        res.append(dv if found else -np.inf)
    return res


def lowered_pose(contact: WheelsetContact, c_y: float, roll: float, overlap_m: float) -> float:
    """c_z at which the deeper region's maximum vertical overlap is ``overlap_m`` (overlap is linear in c_z)."""
    dv = max(max_overlap_at(contact, c_y, C_Z_PROBE_M, roll))
    return C_Z_PROBE_M + overlap_m - dv


def kernel_regions(contact1: WheelsetContact, c_y: float, c_z: float, roll: float) -> np.ndarray:
    """Kernel output (2, N_FIELDS) of the right wheel at a side pose, global mode, fresh start."""
    contact1.reset()
    contact1.params[K.P_GLOBAL] = 1.0
    pose = np.array([[c_y, c_z, roll], [0.0, 0.0, 0.0]])
    K.evaluate_wheels(contact1.nodes, contact1.meta, contact1.mono, contact1.curve_ids, pose, contact1.warm,
                      contact1.params, contact1.out)
    return contact1.out[0].copy()


def scan_concave_poses(pair, rolls_rad, c_ys_m, overlaps_m) -> list[dict]:
    """Poses on a grid at which the kernel (global mode) reports status 2 (concave) for a region.

    Each hit: pose, region, the kernel's wheel parameter s_w, whether s_w is an end of the region (the maximum of
    the region's vertical overlap sits at the tread/flange split point), kernel penetration and curvatures.
    """
    contact1 = WheelsetContact(pair, 1, global_search=True)
    hits = []
    for roll in rolls_rad:
        for c_y in c_ys_m:
            dv0 = max(max_overlap_at(contact1, c_y, C_Z_PROBE_M, roll))
            if not np.isfinite(dv0):
                continue
            for ov in overlaps_m:
                c_z = C_Z_PROBE_M + ov - dv0
                out = kernel_regions(contact1, c_y, c_z, roll)
                for reg in (0, 1):
                    o = out[reg]
                    if int(o[K.F_STATUS]) != K.STATUS_CONCAVE:
                        continue
                    lo, hi = region_bounds(contact1.nodes, contact1.meta, 1 + reg)
                    s_w = float(o[K.F_S_WHEEL])
                    hits.append({"c_y": float(c_y), "c_z": float(c_z), "roll": float(roll), "overlap_target": ov,
                                 "region": reg, "curve": 1 + reg, "s_w_kernel": s_w,
                                 "at_region_end": bool(min(abs(s_w - lo), abs(s_w - hi)) < 1e-7),
                                 "penetration_kernel": float(o[K.F_PENETRATION]),
                                 "kw_lat": float(o[K.F_KW_LAT]), "kr_lat": float(o[K.F_KR_LAT]),
                                 "iterations": int(o[K.F_ITERATIONS]),
                                 "other_region_status": int(out[1 - reg, K.F_STATUS]),
                                 "other_region_s_w": float(out[1 - reg, K.F_S_WHEEL]),
                                 "other_region_penetration": float(out[1 - reg, K.F_PENETRATION])})
    return hits
