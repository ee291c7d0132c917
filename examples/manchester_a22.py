"""Manchester contact benchmark, case A-2.2: creep forces of a wheelset shifted laterally with yaw.

S1002 wheels on UIC60 rails inclined 1:40, gauge 1435 mm (14 mm below the top of rail), flange back-to-back
1360 mm, r0 = 0.46 m; 10 kN vertical load on each wheel; V = 2 m/s; mu = 0.3; G = 82 GPa; nu = 0.28 (E = 2G(1+nu)
for the Hertz problem).  Lateral shift y = 0 ... 10 mm in 0.5 mm steps, positive towards the right rail.

Yaw sign (our choice, stated): psi = +2.4 mrad per mm of y, i.e. the nose (+x) turns towards the rail the wheelset
is shifted to (positive yaw about z-down turns +x towards +y).  This is the curve-like attitude of a leading
wheelset with a positive angle of attack: its right (outer) flange leads, touching the rail ahead of the axle.  It is
also the sign of the benchmark's input as distributed with CONTACT (Vollebregt), in a frame with x forward, y to the
right rail and z down like ours.  Free rolling (zero axle moment) is solved, not a prescribed pitch rate.

Run:  python examples/manchester_a22.py --out a22.csv [--plot a22.png] [--creep-law fastsim|table|exact]
      [--contact-patch hertz|non-hertzian]

With ``--contact-patch non-hertzian`` each contact where Hertz does not hold (the conformal tread near y = 0, the
flange root) is the non-Hertzian patch's resultant: its normal force, contact angle and point, and for the creep
law the equivalent ellipse of its area and lateral extent (exudyn_wheelrail.contact.patch_pass).
CSV: one row per contact point, columns y_m, yaw_rad, side, region, y_rail_m, contact_angle_rad, normal_force_N,
longitudinal_force_N, lateral_force_N (creep forces Fx, Fy on the wheel in the contact frame), then extras
(see EXTRA_COLUMNS; vertical_force_N is the upward component of the whole contact force on the wheel).
"""
from __future__ import annotations

import argparse
import csv
import sys

import numpy as np

from exudyn_wheelrail.analysis.quasi_static import CREEP_LAWS, creep_law_by_name, solve_quasi_static
from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
from exudyn_wheelrail.contact_defaults import CONTACT_PATCH, CONTACT_PATCHES

SHEAR_MODULUS_PA = 82e9
POISSON = 0.28
WHEEL_LOAD_N = 10e3
SPEED_M_S = 2.0
MU = 0.3
YAW_PER_Y = 2.4e-3 / 1e-3           # rad per m of lateral shift (2.4 mrad per mm), sign: see the docstring

COLUMNS = ("y_m", "yaw_rad", "side", "region", "y_rail_m", "contact_angle_rad", "normal_force_N",
           "longitudinal_force_N", "lateral_force_N")
EXTRA_COLUMNS = ("spin_moment_Nm", "vertical_force_N", "xi", "eta", "phi_per_m", "a_m", "b_m", "rolling_radius_m",
                 "y_wheel_m", "lead_m", "z_m", "roll_rad", "pitch_rate_rad_s", "converged", "flags")


def build_contact(contact_patch="hertz"):
    pair = WheelRailPair("S1002", "UIC60", gauge_m=1.435, inclination="1/40", back_to_back_m=1.360, r0_m=0.46)
    e_pa = 2.0 * SHEAR_MODULUS_PA * (1.0 + POISSON)
    return WheelsetContact(pair, global_search=True, E_wheel_Pa=e_pa, nu_wheel=POISSON, E_rail_Pa=e_pa,
                           nu_rail=POISSON, contact_patch=contact_patch)


def check_creep_law(name):
    """The creep law ``name``, called once on a plain contact: ValueError with the reason when it is unusable
    (not importable, or e.g. its data table has not been built)."""
    law = creep_law_by_name(name)
    try:
        law(4e-3, 4e-3, 1e-3, 0.0, 0.0, WHEEL_LOAD_N, MU, SHEAR_MODULUS_PA, POISSON)
    except Exception as exc:            # any failure of the law makes it unusable here; report why
        raise ValueError(f"creep law {name!r} is not usable: {type(exc).__name__}: {exc}") from exc
    return law


def run(y_values_m, creep_law="fastsim", contact_patch="hertz"):
    """Quasi-static solutions for the lateral shifts, yaw = YAW_PER_Y * y; ``creep_law`` a name of CREEP_LAWS,
    ``contact_patch`` one of CONTACT_PATCHES."""
    check_creep_law(creep_law)
    contact = build_contact(contact_patch)
    return [solve_quasi_static(contact, float(y), YAW_PER_Y * float(y), WHEEL_LOAD_N, SPEED_M_S, mu=MU,
                               shear_modulus_Pa=SHEAR_MODULUS_PA, poisson=POISSON, creep_law=creep_law)
            for y in y_values_m]


def rows(results):
    out = []
    for res in results:
        for p in res.points:
            out.append(dict(
                y_m=res.y_m, yaw_rad=res.yaw_rad, side=p.side, region=p.region, y_rail_m=p.y_rail_m,
                contact_angle_rad=p.contact_angle_rad, normal_force_N=p.normal_force_N, longitudinal_force_N=p.Fx_N,
                lateral_force_N=p.Fy_N, spin_moment_Nm=p.Mz_Nm, vertical_force_N=-float(p.force_on_wheel_in_track[2]),
                xi=p.xi, eta=p.eta, phi_per_m=p.phi_per_m, a_m=p.a_m, b_m=p.b_m, rolling_radius_m=p.rolling_radius_m,
                y_wheel_m=p.y_wheel_m, lead_m=p.lead_m, z_m=res.z_m, roll_rad=res.roll_rad,
                pitch_rate_rad_s=res.pitch_rate_rad_s, converged=int(res.converged), flags=";".join(p.flags)))
    return out


def write_csv(table, path):
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=COLUMNS + EXTRA_COLUMNS)
        writer.writeheader()
        for row in table:
            writer.writerow({k: (f"{v:.10g}" if isinstance(v, float) else v) for k, v in row.items()})


def plot(table, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 2, figsize=(12, 8))
    ax = ax.ravel()
    for side, marker in (("right", "o"), ("left", "x")):
        for region, color in (("tread", "C0"), ("flange", "C3")):
            sel = [r for r in table if r["side"] == side and r["region"] == region]
            if not sel:
                continue
            y = np.array([r["y_m"] for r in sel]) * 1e3
            kw = dict(color=color, ms=5, label=f"{side} {region}")
            ax[0].plot(y, [r["normal_force_N"] / 1e3 for r in sel], marker, **kw)
            ax[1].plot(y, [r["longitudinal_force_N"] / 1e3 for r in sel], marker, **kw)
            ax[2].plot(y, [r["lateral_force_N"] / 1e3 for r in sel], marker, **kw)
            ax[3].plot(y, np.degrees([r["contact_angle_rad"] for r in sel]), marker, **kw)
    labels = ("normal force N [kN]", "longitudinal creep force Fx [kN]", "lateral creep force Fy [kN]",
              "contact angle [deg]")
    for a, label in zip(ax, labels):
        a.set(xlabel="lateral shift y [mm] (yaw 2.4 mrad/mm)", ylabel=label)
        a.grid(True, alpha=0.3)
    ax[0].legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, help="CSV file, one row per contact point")
    parser.add_argument("--plot", help="PNG file with forces and contact angles over y")
    parser.add_argument("--creep-law", default="fastsim", choices=sorted(CREEP_LAWS))
    parser.add_argument("--contact-patch", default=CONTACT_PATCH, choices=CONTACT_PATCHES,
                        help="normal contact: Hertz's ellipse, or the non-Hertzian patch where Hertz does not hold")
    parser.add_argument("--y-mm", help="comma-separated lateral shifts in mm (default 0:0.5:10)")
    args = parser.parse_args(argv)
    try:
        check_creep_law(args.creep_law)
    except ValueError as exc:
        parser.exit(2, f"error: {exc}\n")
    if args.y_mm:
        try:
            y_values = [float(v) * 1e-3 for v in args.y_mm.split(",")]
        except ValueError:
            parser.exit(2, f"error: --y-mm {args.y_mm!r}: expected comma-separated numbers (mm)\n")
    else:
        y_values = np.round(np.arange(0, 21) * 0.5e-3, 12)
    results = run(y_values, args.creep_law, args.contact_patch)
    table = rows(results)
    write_csv(table, args.out)
    if args.plot:
        plot(table, args.plot, f"Manchester A-2.2, S1002/UIC60 1:40, {args.creep_law}, {args.contact_patch}, "
                               "free rolling")
    print(f"{'y mm':>5} {'side':5} {'region':6} {'angle':>6} {'N kN':>7} {'Fx kN':>7} {'Fy kN':>7}  status")
    for res in results:
        status = "ok" if res.converged else f"NOT CONVERGED: {res.message}"
        for p in res.points:
            print(f"{res.y_m * 1e3:5.1f} {p.side:5} {p.region:6} {p.contact_angle_rad:6.3f} "
                  f"{p.normal_force_N / 1e3:7.3f} {p.Fx_N / 1e3:7.3f} {p.Fy_N / 1e3:7.3f}  {status}")
    print(f"wrote {args.out}" + (f" and {args.plot}" if args.plot else ""))
    return 0 if all(r.converged for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
