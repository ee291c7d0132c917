"""A measured worn wheel on a measured worn rail: conformal contact, where Hertz's ellipse is wrong.

The pair (``examples/profiles``, SOURCE.md there): a wheel worn after a high mileage and the worn high rail of a curve,
both measured on a North American heavy-haul line.  The wheel has worn hollow and the rail's gauge corner has
worn to fit it, so over much of the wheelset's lateral travel the two profiles run close to each other across a
wide band and the contact is conformal.

For each lateral shift ``--y-mm`` (no yaw) the wheelset is put in the pose where Hertz carries ``--load-kn`` on each
wheel (:func:`~exudyn_wheelrail.analysis.quasi_static.solve_quasi_static`).  At that pose, for every contact of the
right wheel and at the kernel's penetration, three answers are compared:

* the exact one: the normal problem on the elastic half-space over the profiles' own interpenetration
  (``contact.patch.exact_of_contact``), 64 strips × 48 cells;
* the non-Hertzian patch (``contact.patch``, the strip count of the contact option ``non-hertzian``);
* what the contact option ``contact_patch="non-hertzian"`` writes (the pass: the patch where Hertz misses the
  overlap, Hertz where it holds, a blend between; its area is that of its equivalent ellipse), columns ``pass_*``;
* Hertz (the kernel's point and ellipse).

For each the normal force, the patch area, the contact angle of the resultant and the peak pressure are
compared.  The contact angle's error is absolute (rad): on a hollow tread the angle passes through zero, where a
relative error means nothing.

Run:  python examples/worn_profiles.py --out worn.csv [--plot worn.png] [--y-mm 0,2,...] [--load-kn 100]
CSV: one row per contact (columns COLUMNS); the printout gives each method's error against the exact solution.
"""
from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path

import numpy as np

from exudyn_wheelrail.analysis.quasi_static import QuasiStaticError, solve_quasi_static
from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact import patch as P
from exudyn_wheelrail.contact.pair import gauge_point
from exudyn_wheelrail.profiles.fitting import dense_from_points
from exudyn_wheelrail.profiles.profiles import RailProfile, WheelProfile
from exudyn_wheelrail.profiles.simpack import read_simpack_profile

PROFILES = Path(__file__).resolve().parent / "profiles"
WHEEL_FILE = PROFILES / "worn_high_mileage.prw"
RAIL_FILE = PROFILES / "site_b_hr.prr"
#: the wheel file's origin is its flange back; the tape circle is 70 mm from it
TAPE_CIRCLE_FROM_FLANGE_BACK_M = 0.070
#: the track of CONTACT's case with this pair (SOURCE.md): gauge at its depth, flange back distance, wheel radius
GAUGE_M, GAUGE_DEPTH_M = 1.4351, 0.015875
BACK_TO_BACK_M = 1.3474
R0_M = 0.444
SHEAR_MODULUS_PA = 82e9
POISSON = 0.28
SPEED_M_S = 2.0
MU = 0.3
DEFAULT_Y_MM = "0,2,4,6,8,10,11,12,13,14,14.5,15,15.5"

REGIONS = ("tread", "flange", "tread-2")     # the kernel's slots
COLUMNS = ("y_m", "region", "penetration_m", "lateral_extent_m",
           "exact_normal_force_N", "exact_area_m2", "exact_contact_angle_rad", "exact_peak_pressure_Pa",
           "patch_normal_force_N", "patch_area_m2", "patch_contact_angle_rad", "patch_peak_pressure_Pa",
           "pass_normal_force_N", "pass_area_m2", "pass_contact_angle_rad",
           "hertz_normal_force_N", "hertz_area_m2", "hertz_contact_angle_rad", "hertz_peak_pressure_Pa")


def build_pair() -> WheelRailPair:
    """The measured pair placed as SOURCE.md says."""
    y, z, _ = read_simpack_profile(WHEEL_FILE, kind="wheel")
    wheel = WheelProfile.from_dense(dense_from_points(y - TAPE_CIRCLE_FROM_FLANGE_BACK_M, z, smoothing=0.0,
                                                      name=WHEEL_FILE.stem),
                                    flange_back_y_m=-TAPE_CIRCLE_FROM_FLANGE_BACK_M)
    rail = RailProfile.from_file(RAIL_FILE, canted_tan=0.0, worn=True)
    # the gauge measured at this project's depth (gauge_point's default): each gauge face lies this much further from the track centre there
    # than at CONTACT's depth (the worn face leans towards the track centre below)
    outward = gauge_point(rail.curve)[1] - gauge_point(rail.curve, GAUGE_DEPTH_M)[1]
    return WheelRailPair(wheel, rail, gauge_m=GAUGE_M + 2.0 * outward, inclination="none",
                         back_to_back_m=BACK_TO_BACK_M, r0_m=R0_M)


def build_contact(contact_patch="hertz") -> WheelsetContact:
    e_pa = 2.0 * SHEAR_MODULUS_PA * (1.0 + POISSON)
    return WheelsetContact(build_pair(), global_search=True, E_wheel_Pa=e_pa, nu_wheel=POISSON, E_rail_Pa=e_pa,
                           nu_rail=POISSON, contact_patch=contact_patch)


def hertz_peak(row):
    """Hertz's peak pressure 3N/(2πab)."""
    return 1.5 * row[K.F_NORMAL_FORCE] / (math.pi * row[K.F_SEMI_A] * row[K.F_SEMI_B])


def run(y_values_m, load_n=100e3, ref_strips=64, n_x=48):
    """One dict per contact of the right wheel (COLUMNS) at each lateral shift (a shift without a rigid
    contact state, or a contact whose patch cannot be solved, is skipped with a warning)."""
    contact = build_contact()
    with_pass = build_contact("non-hertzian")
    strips = P.N_STRIPS
    rows = []
    for y in y_values_m:
        try:
            res = solve_quasi_static(contact, float(y), 0.0, load_n, SPEED_M_S, mu=MU,
                                     shear_modulus_Pa=SHEAR_MODULUS_PA, poisson=POISSON, creep_law="fastsim")
        except QuasiStaticError as exc:
            # beyond the flange's reach without yaw (this pair: above 15.5 mm) there is no rigid two-wheel state
            print(f"warning: y = {y * 1e3:g} mm skipped: {exc}", file=sys.stderr)
            continue
        wheelset = np.array([[float(y), res.z_m, res.roll_rad]])
        out = contact.evaluate(wheelset)
        pose = contact.side_poses(contact.poses)[0].copy()
        passed = with_pass.evaluate(wheelset)[0].copy()
        for slot in range(K.N_SLOTS):
            row = out[0, slot].copy()
            if not (row[K.F_STATUS] > 0 and row[K.F_NORMAL_FORCE] > 0.0):
                continue
            args = (contact.nodes, contact.meta, contact.curve_ids[0], row, pose, 0.0, contact.E_star)
            try:
                fine, exact, exact_angle = P.exact_of_contact(*args, n_strips=ref_strips, n_x=n_x)
                _, patch = P.patch_of_contact(*args, n_strips=strips)
            except P.PatchError as exc:
                print(f"warning: y = {y * 1e3:g} mm, {REGIONS[slot]}: skipped: {exc}", file=sys.stderr)
                continue
            p = passed[slot]
            rows.append(dict(
                y_m=float(y), region=REGIONS[slot], penetration_m=row[K.F_PENETRATION],
                lateral_extent_m=float(fine[-1, P.S_ETA] - fine[0, P.S_ETA]),
                exact_normal_force_N=exact.normal_force_N, exact_area_m2=exact.area_m2,
                exact_contact_angle_rad=exact_angle,
                exact_peak_pressure_Pa=exact.peak_pressure_Pa,
                patch_normal_force_N=patch.normal_force_N, patch_area_m2=patch.area_m2,
                patch_contact_angle_rad=patch.contact_angle_rad, patch_peak_pressure_Pa=patch.peak_pressure_Pa,
                pass_normal_force_N=p[K.F_NORMAL_FORCE], pass_area_m2=math.pi * p[K.F_SEMI_A] * p[K.F_SEMI_B],
                pass_contact_angle_rad=p[K.F_CONTACT_ANGLE],
                hertz_normal_force_N=row[K.F_NORMAL_FORCE],
                hertz_area_m2=math.pi * row[K.F_SEMI_A] * row[K.F_SEMI_B],
                hertz_contact_angle_rad=row[K.F_CONTACT_ANGLE], hertz_peak_pressure_Pa=hertz_peak(row)))
    return rows


def errors(row, method):
    """``method``'s errors against the exact solution: force, area, peak pressure (relative; the pass has no peak
    pressure), angle (rad)."""
    rel = {q: row[f"{method}_{q}"] / row[f"exact_{q}"] - 1.0 for q in ("normal_force_N", "area_m2",
                                                                        "peak_pressure_Pa")
           if f"{method}_{q}" in row}
    rel["contact_angle_rad"] = row[f"{method}_contact_angle_rad"] - row["exact_contact_angle_rad"]
    return rel


def write_csv(rows, path):
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=COLUMNS)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.10g}" if isinstance(v, float) else v) for k, v in row.items()})


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    y = np.array([r["y_m"] for r in rows]) * 1e3
    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    for method, style in (("exact", "k-o"), ("patch", "C0--x"), ("pass", "C2-.+"), ("hertz", "C3:s")):
        ax[0].plot(y, [r[f"{method}_normal_force_N"] / 1e3 for r in rows], style, label=method)
        ax[1].plot(y, [r[f"{method}_area_m2"] * 1e6 for r in rows], style, label=method)
        ax[2].plot(y, [r[f"{method}_contact_angle_rad"] for r in rows], style, label=method)
    for a, label in zip(ax, ("normal force at the penetration [kN]", "patch area [mm²]", "contact angle [rad]")):
        a.set(xlabel="lateral shift y [mm]", ylabel=label)
        a.grid(True, alpha=0.3)
    ax[0].legend()
    fig.suptitle("measured worn wheel on measured worn rail: Hertz and the patch against the exact solution")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, help="CSV file, one row per contact")
    parser.add_argument("--plot", help="PNG file: force, area and angle over y, each method")
    parser.add_argument("--y-mm", default=DEFAULT_Y_MM, help=f"comma-separated lateral shifts in mm ({DEFAULT_Y_MM})")
    parser.add_argument("--load-kn", type=float, default=100.0, help="vertical wheel load of Hertz's pose [kN]")
    args = parser.parse_args(argv)
    try:
        y_values = [float(v) * 1e-3 for v in args.y_mm.split(",")]
    except ValueError:
        y_values = [math.nan]
    if not all(abs(y) <= 0.03 for y in y_values):
        parser.exit(2, f"error: --y-mm {args.y_mm!r}: expected comma-separated lateral shifts within ±30 mm\n")
    if not 0.0 < args.load_kn <= 500.0:
        parser.exit(2, f"error: --load-kn {args.load_kn:g}: expected a wheel load in (0, 500] kN\n")
    rows = run(y_values, args.load_kn * 1e3)
    if not rows:
        parser.exit(1, "error: no lateral shift of --y-mm has a rigid contact state (see the warnings)\n")
    write_csv(rows, args.out)
    print(f"{'y mm':>6} {'region':7} {'width mm':>8} {'N exact kN':>10}"
          + "".join(f" | {m}: force  area  angle rad" for m in ("patch", "pass", "Hertz")))
    for r in rows:
        line = (f"{r['y_m'] * 1e3:6.2f} {r['region']:7} {r['lateral_extent_m'] * 1e3:8.1f} "
                f"{r['exact_normal_force_N'] / 1e3:10.2f}")
        for method in ("patch", "pass", "hertz"):
            e = errors(r, method)
            line += f" | {e['normal_force_N']:+6.1%} {e['area_m2']:+6.1%} {e['contact_angle_rad']:+.4f}"
        print(line)
    if args.plot:
        plot(rows, args.plot)
    print(f"wrote {args.out}" + (f" and {args.plot}" if args.plot else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
