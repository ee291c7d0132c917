"""Main example: S1002 wheels on UIC60 rails inclined 1:40 — contact points, Hertz, geometry functions, conicity.

Run:  python examples/contact_geometry.py [--out DIR]
Writes DIR/geometry.csv and DIR/geometry.png (default DIR = ./out) and prints a summary.
"""
import argparse
from pathlib import Path

import numpy as np

from exudyn_wheelrail.analysis.conicity import equivalent_conicity
from exudyn_wheelrail.analysis.geometry_functions import contact_geometry_sweep, solve_rigid_contact
from exudyn_wheelrail.cli import plot_sweep
from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default="out")
    out = Path(parser.parse_args().out)
    out.mkdir(parents=True, exist_ok=True)

    pair = WheelRailPair("S1002", "UIC60", gauge_m=1.435, inclination="1/40", back_to_back_m=1.360, r0_m=0.46)
    print(pair)
    print(pair.wheel)

    # 1. one loaded pose: the rigid touching position at y = 3 mm, then lowered by 80 µm into the rails
    contact = WheelsetContact(pair, global_search=True)
    touch = solve_rigid_contact(contact, 0.003)
    points = contact.contact_points(0.003, touch.z_m + 80e-6, touch.roll_rad)
    print(f"\nwheelset at y = 3 mm, lowered 80 µm below rigid touch (roll {touch.roll_rad * 1e3:.3f} mrad):")
    for p in points:
        print(f"  {p.side:5s} {p.region:6s} ({p.method}): wheel y {p.y_wheel_profile_m * 1e3:7.2f} mm, "
              f"angle {np.degrees(p.contact_angle_rad):5.2f} deg, r {p.rolling_radius_m * 1e3:7.2f} mm, "
              f"delta {p.penetration_m * 1e6:5.1f} µm, N {p.normal_force_N / 1e3:6.1f} kN, "
              f"a x b {p.semi_axis_a_m * 1e3:.2f} x {p.semi_axis_b_m * 1e3:.2f} mm")

    # 2. contact-geometry functions over +-10 mm, and equivalent conicity
    sweep = contact_geometry_sweep(pair, np.arange(-0.010, 0.010 + 1e-9, 0.0005))
    sweep.write_csv(out / "geometry.csv")
    plot_sweep(sweep, out / "geometry.png", title="S1002 / UIC60 1:40, gauge 1435 mm, back-to-back 1360 mm")
    flange = [r["y_m"] for r in sweep.rows if r["region"] == "flange" and r["side"] == "right"]
    print(f"\nflange contact (right wheel) from y = {min(flange) * 1e3:.1f} mm")
    for amp in (0.001, 0.002, 0.003, 0.004):
        g = equivalent_conicity(sweep.y_m, sweep.delta_r_m, amp, method="harmonic")
        print(f"equivalent conicity at {amp * 1e3:.0f} mm amplitude: {g:.3f}")
    print(f"\nwrote {out / 'geometry.csv'} and {out / 'geometry.png'}")


if __name__ == "__main__":
    main()
