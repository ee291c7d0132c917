"""Error vs cost of the concave-search discretisation (``vertical_overlap_search``), S1002 / UIC60 1:40.

Pose set: right-wheel side-frame poses (c_y, c_z, roll) on a grid (roll -3..3 mrad, c_y -3..8 mm, maximum
vertical overlap 50 / 150 / 300 um) at which the kernel (global mode, fresh start) reports **status 2** (concave)
for a region *and* the maximum lies inside the region; ~20 of them, spread over the hits (tread band against the
rail's 80 mm radius, S1002 throat / flange root against the UIC60 13 mm gauge corner).  Status-2 hits whose
maximum sits at the tread/flange split point (an end of the region) are counted but left out: there the first
sample is already exact.

For each pose, ``vertical_overlap_search`` of that region with n = n_wheel = n_rail in {10, 25, 50, 100, 200, 400},
``refine`` False (the paper's discrete method) and True (the kernel default is n = 100, refine = True), against a
**brute-force reference**: the wheel region sampled every 1 um of arc length, each point projected vertically onto
the rail through a dense rail table (every 0.25 um of arc length, linear interpolation: error < 1e-11 m), the best
sample refined by a bounded scalar maximisation with exact vertical projection (``brentq`` on the rail curve).
Both use the same vertically projectable rail stretch as the kernel (``WheelsetContact.mono``) and the same
curve evaluation (whose accuracy is tested separately); nothing else of the search code is shared.

Reported per (n, refine): max and RMS error of the contact location (distance between the wheel points at the
found and the reference parameter, mm) and of the maximum overlap (reference minus found, um), and us per call
(numba loop over the pose set, warm, median of repeats).  In conformal contact the overlap maximum is flat, so a
location error can be large while the overlap error is tiny: the per-pose CSV gives the width of the region
within 1 um of the maximum and the runner-up local maximum.

Run:  python benchmarks/bench_concave_discretisation.py   (about 30-60 s; writes benchmarks/results/
concave_discretisation.csv (summary) and concave_discretisation_poses.csv (per pose and setting))
"""
from __future__ import annotations

import csv
import json
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit
from scipy.optimize import brentq, minimize_scalar
from scipy.signal import argrelmax

from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact.pair import WheelRailPair
from exudyn_wheelrail.contact.search import vertical_overlap_search
from exudyn_wheelrail.contact.wheelset import WheelsetContact

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
sys.path.insert(0, str(HERE))
from bench_contact import machine_info  # noqa: E402
from contact_poses import REGION_NAMES, region_bounds, scan_concave_poses  # noqa: E402

N_VALUES = (10, 25, 50, 100, 200, 400)
N_POSES = 20
ROLLS_RAD = np.linspace(-3e-3, 3e-3, 13)
C_YS_M = np.arange(-3e-3, 8.0001e-3, 0.1e-3)
OVERLAPS_M = (50e-6, 150e-6, 300e-6)
WHEEL_SPACING_M = 1e-6
RAIL_SPACING_M = 0.25e-6
LOCATION_LIMIT_MM = 0.05
N_WIDE = 60                   # wider check: random grid poses (any kernel status), deepest region
WIDE_SETTINGS = ((50, True), (100, True), (100, False), (400, False))


# ---------------------------------------------------------------------------------------------------- reference
class VerticalReference:
    """Brute-force maximum vertical overlap of a wheel region over the rail's projectable stretch."""

    def __init__(self, pair: WheelRailPair, contact: WheelsetContact):
        self.pair = pair
        self.rail = pair.rail_side
        lo_row, hi_row = contact.mono[0]
        s0, s1 = float(contact.nodes[lo_row, 0]), float(contact.nodes[hi_row, 0])
        self.s = np.linspace(s0, s1, int((s1 - s0) / RAIL_SPACING_M) + 1)
        e = self.rail.evaluate(self.s)
        self.y = e[:, 0]
        self.z = e[:, 1]
        if not np.all(np.diff(self.y) > 0):
            raise RuntimeError("rail table: y must increase along the projectable stretch")

    @staticmethod
    def wheel_points(curve, s, pose):
        c_y, c_z, roll = pose
        e = curve.evaluate(np.atleast_1d(s))
        co, si = np.cos(roll), np.sin(roll)
        return c_y + co * e[:, 0] - si * e[:, 1], c_z + si * e[:, 0] + co * e[:, 1]

    def overlap_dense(self, y, z):
        dv = np.full(y.shape, -np.inf)
        ok = (y >= self.y[0]) & (y <= self.y[-1])
        dv[ok] = z[ok] - np.interp(y[ok], self.y, self.z)
        return dv

    def overlap_exact(self, curve, s_w, pose):
        y, z = self.wheel_points(curve, s_w, pose)
        y, z = float(y[0]), float(z[0])
        if not (self.y[0] <= y <= self.y[-1]):
            return -np.inf
        k = int(np.clip(np.searchsorted(self.y, y), 1, self.y.size - 1))
        s_r = brentq(lambda s: self.rail.evaluate([s])[0, 0] - y, self.s[k - 1], self.s[k], xtol=1e-16, rtol=1e-15)
        return z - float(self.rail.evaluate([s_r])[0, 1])

    def maximum(self, curve, pose) -> dict:
        s = np.linspace(curve.s_min, curve.s_max, int(curve.length / WHEEL_SPACING_M) + 1)
        y, z = self.wheel_points(curve, s, pose)
        dv = self.overlap_dense(y, z)
        k = int(np.argmax(dv))
        lo, hi = s[max(k - 2, 0)], s[min(k + 2, s.size - 1)]
        res = minimize_scalar(lambda x: -self.overlap_exact(curve, x, pose), bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-12})
        s_best, dv_best = (float(res.x), float(-res.fun)) if -res.fun >= dv[k] else (float(s[k]), float(dv[k]))
        # conditioning: width within 1 um of the maximum, runner-up local maximum (> 0.5 mm away)
        flat_mm = float(np.sum(dv >= dv_best - 1e-6) * WHEEL_SPACING_M * 1e3)
        finite = np.where(np.isfinite(dv), dv, -1.0)
        peaks = argrelmax(np.concatenate([[-1.0], finite, [-1.0]]), order=200)[0] - 1
        peaks = peaks[(peaks >= 0) & (peaks < s.size) & (np.abs(s[np.clip(peaks, 0, s.size - 1)] - s_best) > 5e-4)]
        if peaks.size:
            j = peaks[np.argmax(dv[peaks])]
            runner = (float(s[j]), float(dv_best - dv[j]))
        else:
            runner = (float("nan"), float("nan"))
        return {"s_w": s_best, "overlap": dv_best, "flat_width_1um_mm": flat_mm, "runner_up_s_w": runner[0],
                "runner_up_lower_by_um": runner[1] * 1e6}


# ---------------------------------------------------------------------------------------------------- timing
@njit(cache=False)
def _drive(nodes, meta, mono, curves, c_y, c_z, cos_r, sin_r, s_lo, s_hi, n, refine, reps):
    acc = 0.0
    for _ in range(reps):
        for i in range(c_y.size):
            found, s_w, s_r, dv = vertical_overlap_search(nodes, meta, mono, 0, curves[i], c_y[i], c_z[i], cos_r[i],
                                                          sin_r[i], s_lo[i], s_hi[i], n, n, refine)
            acc += dv
    return acc


def time_per_call(contact, poses, n, refine) -> float:
    a = (contact.nodes, contact.meta, contact.mono, poses["curve"], poses["c_y"], poses["c_z"], poses["cos"],
         poses["sin"], poses["s_lo"], poses["s_hi"], n, refine)
    _drive(*a, 1)
    t0 = time.perf_counter()
    _drive(*a, 1)
    one = time.perf_counter() - t0
    reps = max(1, int(0.05 / max(one, 1e-9)))
    times = []
    for _ in range(7):
        t0 = time.perf_counter()
        _drive(*a, reps)
        times.append(time.perf_counter() - t0)
    return float(np.median(times)) / (reps * poses["c_y"].size)


# ---------------------------------------------------------------------------------------------------- poses
def rail_zone(kappa_r: float) -> str:
    """UIC60 head zone from its lateral curvature (radii 300 / 80 / 13 mm)."""
    r_mm = 1e3 / kappa_r if kappa_r > 0 else float("inf")
    return {300: "crown R300", 80: "shoulder R80", 13: "gauge corner R13"}.get(int(round(r_mm)), f"R{r_mm:.0f}")



def select_poses(pair) -> tuple[list[dict], dict]:
    hits = scan_concave_poses(pair, ROLLS_RAD, C_YS_M, OVERLAPS_M)
    inner = [h for h in hits if not h["at_region_end"]]
    # the location of the maximum does not depend on the overlap (vertical shift): one hit per (c_y, roll, region)
    unique = {}
    for h in inner:
        unique.setdefault((round(h["c_y"], 7), round(h["roll"], 7), h["region"]), h)
    cand = sorted(unique.values(), key=lambda h: (h["region"], h["s_w_kernel"], h["c_y"], h["roll"]))
    idx = np.unique(np.round(np.linspace(0, len(cand) - 1, min(N_POSES, len(cand)))).astype(int))
    chosen = [cand[i] for i in idx]
    info = {"status2_region_hits": len(hits), "at_region_end": len(hits) - len(inner),
            "interior_unique_poses": len(cand), "chosen": len(chosen)}
    return chosen, info


def wide_check(pair, contact, ref, curves) -> tuple[list[dict], int]:
    """Errors of a few settings on N_WIDE random grid poses (deepest region, 50-300 um overlap, any status)."""
    from contact_poses import lowered_pose, max_overlap_at
    rng = np.random.default_rng(7)
    nodes, meta, mono = contact.nodes, contact.meta, contact.mono
    cases = []
    while len(cases) < N_WIDE:
        c_y = float(rng.uniform(C_YS_M[0], C_YS_M[-1]))
        roll = float(rng.uniform(ROLLS_RAD[0], ROLLS_RAD[-1]))
        dv = max_overlap_at(contact, c_y, -0.46, roll)
        if not np.any(np.isfinite(dv)):
            continue
        curve = 1 + int(np.argmax(dv))
        c_z = lowered_pose(contact, c_y, roll, float(rng.uniform(50e-6, 300e-6)))
        r = ref.maximum(curves[curve], (c_y, c_z, roll))
        cases.append((c_y, c_z, roll, curve, r))
    rows = []
    for n, refine in WIDE_SETTINGS:
        loc, ov = [], []
        for c_y, c_z, roll, curve, r in cases:
            lo, hi = region_bounds(nodes, meta, curve)
            found, s_w, s_r, dv = vertical_overlap_search(nodes, meta, mono, 0, curve, c_y, c_z, np.cos(roll),
                                                          np.sin(roll), lo, hi, n, n, refine)
            y1, z1 = ref.wheel_points(curves[curve], s_w, (c_y, c_z, roll))
            y0, z0 = ref.wheel_points(curves[curve], r["s_w"], (c_y, c_z, roll))
            loc.append(float(np.hypot(y1[0] - y0[0], z1[0] - z0[0]) * 1e3))
            ov.append(float((r["overlap"] - dv) * 1e6))
        loc, ov = np.array(loc), np.array(ov)
        rows.append({"n": n, "refine": refine, "location_error_max_mm": float(loc.max()),
                     "location_error_rms_mm": float(np.sqrt(np.mean(loc ** 2))),
                     "overlap_error_max_um": float(np.max(np.abs(ov))),
                     "poses_over_limit": int(np.sum(loc > LOCATION_LIMIT_MM))})
    at_end = sum(1 for c in cases if min(abs(c[4]["s_w"] - b) for b in region_bounds(nodes, meta, c[3])) < 1e-7)
    return rows, at_end


def main():
    t_start = time.perf_counter()
    pair = WheelRailPair()
    contact = WheelsetContact(pair, 1)
    nodes, meta = contact.nodes, contact.meta
    chosen, scan_info = select_poses(pair)
    ref = VerticalReference(pair, contact)
    curves = {1: pair.tread_side, 2: pair.flange_side}
    for h in chosen:
        h.update({f"ref_{k}": v for k, v in ref.maximum(curves[h["curve"]], (h["c_y"], h["c_z"], h["roll"])).items()})
    poses = {"curve": np.array([h["curve"] for h in chosen], dtype=np.int64),
             "c_y": np.array([h["c_y"] for h in chosen]), "c_z": np.array([h["c_z"] for h in chosen]),
             "cos": np.cos([h["roll"] for h in chosen]), "sin": np.sin([h["roll"] for h in chosen]),
             "s_lo": np.array([region_bounds(nodes, meta, h["curve"])[0] for h in chosen]),
             "s_hi": np.array([region_bounds(nodes, meta, h["curve"])[1] for h in chosen])}

    per_pose = []
    summary = []
    for refine in (False, True):
        for n in N_VALUES:
            loc, ov = [], []
            for i, h in enumerate(chosen):
                found, s_w, s_r, dv = vertical_overlap_search(nodes, meta, contact.mono, 0, h["curve"], h["c_y"],
                                                              h["c_z"], poses["cos"][i], poses["sin"][i],
                                                              poses["s_lo"][i], poses["s_hi"][i], n, n, refine)
                crv = curves[h["curve"]]
                pose = (h["c_y"], h["c_z"], h["roll"])
                y1, z1 = ref.wheel_points(crv, s_w, pose)
                y0, z0 = ref.wheel_points(crv, h["ref_s_w"], pose)
                e_loc = float(np.hypot(y1[0] - y0[0], z1[0] - z0[0]) * 1e3)
                e_ov = float((h["ref_overlap"] - dv) * 1e6)
                loc.append(e_loc)
                ov.append(e_ov)
                per_pose.append({"pose": i, "n": n, "refine": refine, "found": bool(found), "s_w_mm": s_w * 1e3,
                                 "overlap_um": dv * 1e6, "location_error_mm": e_loc, "overlap_error_um": e_ov})
            loc, ov = np.array(loc), np.array(ov)
            t = time_per_call(contact, poses, n, refine)
            summary.append({"n": n, "refine": refine, "us_per_call": t * 1e6,
                            "location_error_max_mm": float(loc.max()),
                            "location_error_rms_mm": float(np.sqrt(np.mean(loc ** 2))),
                            "overlap_error_max_um": float(np.max(np.abs(ov))),
                            "overlap_error_rms_um": float(np.sqrt(np.mean(ov ** 2))),
                            "overlap_error_min_signed_um": float(ov.min()),
                            "poses_over_limit": int(np.sum(loc > LOCATION_LIMIT_MM)),
                            "worst_pose": int(np.argmax(loc))})

    wide, wide_at_end = wide_check(pair, contact, ref, curves)

    # ---- output
    info = machine_info()
    lines = [f"CPU: {info['cpu_model']} ({info['cpu_count']} logical CPUs), Python {info['python']}, numba "
             f"{info['numba']}; library at git {info['git']}",
             f"Pose set: {len(chosen)} poses (of {scan_info['interior_unique_poses']} distinct poses where the kernel "
             f"reports status 2 with the maximum inside the region; of the scan's {scan_info['status2_region_hits']} "
             f"status-2 region hits, {scan_info['at_region_end']} had the maximum at the tread/flange split point "
             f"and are left out)",
             "",
             "| n = n_wheel = n_rail | refine | µs per call | location error max [mm] | location error RMS [mm] "
             f"| overlap error max [µm] | overlap error RMS [µm] | poses > {LOCATION_LIMIT_MM} mm |",
             "|---:|---|---:|---:|---:|---:|---:|---:|"]
    for r in summary:
        default = " (kernel default)" if r["n"] == 100 and r["refine"] else ""
        lines.append(f"| {r['n']}{default} | {r['refine']} | {r['us_per_call']:.2f} | "
                     f"{r['location_error_max_mm']:.3g} | {r['location_error_rms_mm']:.3g} | "
                     f"{r['overlap_error_max_um']:.3g} | {r['overlap_error_rms_um']:.3g} | "
                     f"{r['poses_over_limit']}/{len(chosen)} |")
    d = next(r for r in summary if r["n"] == int(contact.params[K.P_N_CONCAVE_WHEEL])
             and r["refine"] == bool(contact.params[K.P_REFINE]))
    met = d["location_error_max_mm"] <= LOCATION_LIMIT_MM
    verdict = (f"Default (n = {d['n']}, refine = {d['refine']}): location error max "
               f"{d['location_error_max_mm']:.3g} mm "
               f"(RMS {d['location_error_rms_mm']:.3g} mm), overlap error max {d['overlap_error_max_um']:.3g} um -> "
               f"requirement (<= {LOCATION_LIMIT_MM} mm) {'MET' if met else 'NOT MET'}")
    lines += ["", verdict, "",
              f"Wider check: {N_WIDE} random poses (c_y {C_YS_M[0] * 1e3:.0f}..{C_YS_M[-1] * 1e3:.0f} mm, roll "
              f"{ROLLS_RAD[0] * 1e3:.0f}..{ROLLS_RAD[-1] * 1e3:.0f} mrad, 50-300 um overlap, the deeper region, any "
              f"kernel status; {wide_at_end} with the maximum at a region end):", "",
              "| n | refine | location error max [mm] | RMS [mm] | overlap error max [µm] "
              f"| poses > {LOCATION_LIMIT_MM} mm |", "|---:|---|---:|---:|---:|---:|"]
    for r in wide:
        lines.append(f"| {r['n']} | {r['refine']} | {r['location_error_max_mm']:.3g} | "
                     f"{r['location_error_rms_mm']:.3g} "
                     f"| {r['overlap_error_max_um']:.3g} | {r['poses_over_limit']}/{N_WIDE} |")
    lines += ["", "Poses (right wheel, side frame):", "",
              "| # | region | rail zone | c_y [mm] | roll [mrad] | max overlap [µm] | ref. s_w [mm] | kernel s_w [mm] "
              "| kappa_w / kappa_r [1/m] | width within 1 µm [mm] | runner-up max: s_w [mm], lower by [µm] |",
              "|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    for i, h in enumerate(chosen):
        lines.append(f"| {i} | {REGION_NAMES[h['region']]} | {rail_zone(h['kr_lat'])} | {h['c_y'] * 1e3:.2f} | "
                     f"{h['roll'] * 1e3:.2f} | "
                     f"{h['ref_overlap'] * 1e6:.1f} | {h['ref_s_w'] * 1e3:.4f} | {h['s_w_kernel'] * 1e3:.4f} | "
                     f"{h['kw_lat']:.1f} / {h['kr_lat']:.1f} | {h['ref_flat_width_1um_mm']:.3f} | "
                     f"{h['ref_runner_up_s_w'] * 1e3:.2f}, {h['ref_runner_up_lower_by_um']:.1f} |")
    text = "\n".join(lines)
    print(text)

    RESULTS.mkdir(exist_ok=True)
    with open(RESULTS / "concave_discretisation.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(summary[0].keys()))
        w.writeheader()
        w.writerows(summary)
    pose_cols = ["c_y", "c_z", "roll", "overlap_target", "region", "s_w_kernel", "penetration_kernel", "kw_lat",
                 "kr_lat", "ref_s_w", "ref_overlap", "ref_flat_width_1um_mm", "ref_runner_up_s_w",
                 "ref_runner_up_lower_by_um"]
    with open(RESULTS / "concave_discretisation_poses.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(per_pose[0].keys()) + pose_cols)
        w.writeheader()
        for r in per_pose:
            w.writerow({**r, **{k: chosen[r["pose"]][k] for k in pose_cols}})
    with open(RESULTS / "concave_discretisation.json", "w") as fh:
        json.dump({"machine": info, "scan": scan_info, "summary": summary, "verdict": verdict, "wide_check": wide,
                   "poses": chosen, "runtime_s": time.perf_counter() - t_start}, fh, indent=1, default=float)
    print(f"\n(written {RESULTS}/concave_discretisation*.csv/.json; runtime {time.perf_counter() - t_start:.0f} s)")


if __name__ == "__main__":
    main()
