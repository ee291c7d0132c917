"""The non-Hertzian patch and Hertz against the exact half-space solution on S1002/UIC60, and what each costs.

Case: the Manchester A-2.2 wheelset (S1002 on UIC60 1:40, gauge 1435 mm, back-to-back 1360 mm, r0 0.46 m, E from
G = 82 GPa, ν = 0.28) at the lateral shifts ``--y-mm`` (no yaw), in the pose where Hertz carries 10 kN per wheel
(``solve_quasi_static``).  For every contact of the right wheel at that pose, at the kernel's penetration:

* the exact solution (``contact.patch.exact_of_contact``: one row of cells per strip of the profiles'
  interpenetration, ``--n-x`` cells along the rolling direction, ``--ref-strips`` strips);
* the patch (``contact.patch.solve_strips``, ``--strips`` strips) and Hertz (the kernel's point);
* normal force, patch area, peak pressure, contact angle of the resultant: relative errors against the exact one;
* time: one patch solve and the exact solve (each with its strips' geometry), wall clock, best of ``--repeats``.

Run:  python benchmarks/patch_accuracy.py [--out benchmarks/results/patch_accuracy.json]
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from exudyn_wheelrail.analysis.quasi_static import solve_quasi_static
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact import patch as P

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
import manchester_a22 as A22  # noqa: E402

HERE = Path(__file__).resolve().parent
DEFAULT_Y_MM = "-3,-1,0,0.5,1,2,4,5,7,9"


def rel(a, b):
    return float(a / b - 1.0)


def best_time(fn, repeats):
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        value = fn()
        best = min(best, time.perf_counter() - t)
    return best, value


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--y-mm", default=DEFAULT_Y_MM)
    ap.add_argument("--strips", type=int, default=P.N_STRIPS)
    ap.add_argument("--ref-strips", type=int, default=64)
    ap.add_argument("--n-x", type=int, default=48)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=str(HERE / "results" / "patch_accuracy.json"))
    args = ap.parse_args(argv)
    contact = A22.build_contact()
    rows = []
    for y_mm in (float(v) for v in args.y_mm.split(",")):
        res = solve_quasi_static(contact, y_mm * 1e-3, 0.0, A22.WHEEL_LOAD_N, A22.SPEED_M_S, mu=A22.MU,
                                 shear_modulus_Pa=A22.SHEAR_MODULUS_PA, poisson=A22.POISSON, creep_law="fastsim")
        out = contact.evaluate(np.array([[y_mm * 1e-3, res.z_m, res.roll_rad]]))
        pose = contact.side_poses(contact.poses)[0].copy()
        for slot in range(K.N_SLOTS):
            row = out[0, slot].copy()
            if not (row[K.F_STATUS] > 0 and row[K.F_NORMAL_FORCE] > 0):
                continue
            t_ref, (_, ref, angle) = best_time(lambda: P.exact_of_contact(
                contact.nodes, contact.meta, contact.curve_ids[0], row, pose, 0.0, contact.E_star,
                n_strips=args.ref_strips, n_x=args.n_x), 1)
            t_patch, (_, sol) = best_time(lambda: P.patch_of_contact(contact.nodes, contact.meta, contact.curve_ids[0],
                                                                     row, pose, 0.0, contact.E_star,
                                                                     n_strips=args.strips), args.repeats)
            hertz_area = np.pi * row[K.F_SEMI_A] * row[K.F_SEMI_B]
            entry = dict(
                y_mm=y_mm, region=("tread", "flange", "tread-2")[slot], penetration_um=row[K.F_PENETRATION] * 1e6,
                exact=dict(normal_force_N=ref.normal_force_N, area_mm2=ref.area_m2 * 1e6,
                           contact_angle_rad=angle, peak_pressure_MPa=ref.peak_pressure_Pa / 1e6, seconds=t_ref),
                patch=dict(force=rel(sol.normal_force_N, ref.normal_force_N), area=rel(sol.area_m2, ref.area_m2),
                           angle=rel(sol.contact_angle_rad, angle), peak=rel(sol.peak_pressure_Pa, ref.peak_pressure_Pa),
                           epsilon=sol.epsilon, iterations=sol.iterations, seconds=t_patch),
                hertz=dict(force=rel(row[K.F_NORMAL_FORCE], ref.normal_force_N), area=rel(hertz_area, ref.area_m2),
                           angle=rel(row[K.F_CONTACT_ANGLE], angle)))
            rows.append(entry)
            p, h = entry["patch"], entry["hertz"]
            print(f"y {y_mm:5.1f} mm {entry['region']:7} N {ref.normal_force_N:7.0f} N | patch force {p['force']:+.3f} "
                  f"area {p['area']:+.3f} angle {p['angle']:+.3f} ({t_patch * 1e6:.0f} us) | Hertz {h['force']:+.3f} "
                  f"{h['area']:+.3f} {h['angle']:+.3f}", flush=True)
    result = dict(case="Manchester A-2.2 pair, no yaw, Hertz pose of 10 kN", strips=args.strips,
                  ref_strips=args.ref_strips, n_x=args.n_x, load_average=os.getloadavg()[0], rows=rows)
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    print(f"wrote {args.out} (load {result['load_average']:.2f})")


if __name__ == "__main__":
    main()
