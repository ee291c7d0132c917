r"""Manchester vehicle 1 through an R = 600 m curve with 150 mm cant at cant deficiency and at cant excess, and at
cant deficiency over generated track irregularities.

Run:  python examples/curving.py --out DIR [--deficiency-kmh 120] [--excess-kmh 60] [--transition-m 60]
                                 [--spectrum german_low] [--seed 1]

Each case is the ``curving`` command's run (:mod:`exudyn_wheelrail.scenarios.curving`: straight track, a clothoid
transition with a linear cant ramp, the circular curve; the vehicle in track-following frames, RK44) and writes
``DIR/<case>/summary.json`` and ``timeseries.csv``.  The plot ``DIR/curving.png`` shows, along the track distance of
the leading wheelset, per wheelset ΣY (the lateral force between both rails and the wheelset, positive outwards on
the track) with the Prud'homme limit ``10 kN + P/3`` of the static axle load P (EN 14363's track-shift limit, a 2 m
mean there; the raw signal here), Y/Q of every outer wheel with EN 14363's 0.8, and the angle of attack with the
geometric value ``a/R`` of a bogie's wheelsets held parallel to its frame (a reference, not a limit).  The dashed
lines mark the steady-state means; the printed table compares ΣΣY with m a_nc.  The third case runs the
deficiency case over irregularities of all four channels generated from a standard spectrum (the spectra module's
band, the given seed), faded in before the circular curve (:func:`~exudyn_wheelrail.scenarios.curving.
spectral_irregularity`): its steady means average over the response to them.
"""
from __future__ import annotations

import argparse
import dataclasses
import math
from pathlib import Path

import numpy as np

from exudyn_wheelrail.analysis.safety import EN14363_YQ_LIMIT, prudhomme_limit_N
from exudyn_wheelrail.conventions import outward_sign
from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle
from exudyn_wheelrail.scenarios.curving import CurvingCase, run_curving, spectral_irregularity
from exudyn_wheelrail.track.spectra import SPECTRA

RADIUS_M = 600.0
CANT_M = 0.150


def _cases(args):
    deficiency = CurvingCase("manchester_vehicle1", RADIUS_M, CANT_M, args.deficiency_kmh, args.transition_m)
    irregular = dataclasses.replace(deficiency, irregularity=spectral_irregularity(deficiency, args.spectrum,
                                                                                   args.seed))
    return {"deficiency": deficiency,
            "excess": CurvingCase("manchester_vehicle1", RADIUS_M, CANT_M, args.excess_kmh, args.transition_m),
            f"deficiency, {args.spectrum} seed {args.seed}": irregular}


def plot(results: dict, path: Path, semi_wheelbase_m: float) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, len(results), figsize=(6.5 * len(results), 9.5), sharex="col", squeeze=False)
    for col, (name, res) in enumerate(results.items()):
        ts, s = res.timeseries, res.summary
        n = s["n_wheelsets"]
        x = ts["s_leading_m"]
        kappa = ts["curvature_w1_1_m"]
        out = np.where(kappa != 0.0, [outward_sign(k) for k in kappa], -1.0)
        axle_load = 2.0 * np.mean([q for wq in s["Q_N"] for q in wq.values()]) if s.get("Q_N") else None
        ax_y, ax_q, ax_a = axes[:, col]
        for j in range(n):
            sum_y = -out * (ts[f"Y_w{j + 1}_right_N"] + ts[f"Y_w{j + 1}_left_N"])
            line, = ax_y.plot(x, sum_y / 1e3, lw=0.8, label=f"wheelset {j + 1}")
            outer = np.where(kappa > 0, ts[f"YQ_w{j + 1}_left"], ts[f"YQ_w{j + 1}_right"])
            ax_q.plot(x, outer, lw=0.8, color=line.get_color())
            ax_a.plot(x, 1e3 * out * ts[f"yaw_w{j + 1}_rad"], lw=0.8, color=line.get_color())
            if s.get("sum_Y_N") is not None:
                ax_y.axhline(s["sum_Y_N"][j] / 1e3, color=line.get_color(), ls="--", lw=0.6)
        if axle_load:
            lim = prudhomme_limit_N(static_axle_load_N=axle_load) / 1e3
            for sign in (1, -1):
                ax_y.axhline(sign * lim, color="r", lw=1.0)
            ax_y.text(x[0], lim, " Prud'homme 10 kN + P/3", color="r", va="bottom", fontsize=8)
        ax_q.axhline(EN14363_YQ_LIMIT, color="r", lw=1.0)
        ax_q.text(x[0], EN14363_YQ_LIMIT, " EN 14363 Y/Q 0.8", color="r", va="bottom", fontsize=8)
        ref = 1e3 * semi_wheelbase_m / RADIUS_M
        ax_a.axhline(ref, color="0.4", lw=1.0, ls=":")
        ax_a.text(x[0], ref, " a/R (bogie chord)", color="0.4", va="bottom", fontsize=8)
        ax_y.set_title(f"{name}: {s['speed_km_h']:g} km/h, a_nc = {s['unbalanced_lateral_acceleration_m_s2']:.2f} "
                       f"m/s², status {s['status']}")
        ax_y.set_ylabel("ΣY per wheelset [kN] (outwards)")
        ax_q.set_ylabel("Y/Q outer wheel")
        ax_a.set_ylabel("angle of attack [mrad]")
        ax_a.set_xlabel("track distance of the leading wheelset [m]")
        ax_y.legend(fontsize=8, loc="lower right")
        for ax in (ax_y, ax_q, ax_a):
            ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--deficiency-kmh", type=float, default=120.0, help="speed of the cant-deficiency case [km/h]")
    p.add_argument("--excess-kmh", type=float, default=60.0, help="speed of the cant-excess case [km/h]")
    p.add_argument("--transition-m", type=float, default=60.0, help="length of the entry transition [m]")
    p.add_argument("--spectrum", default="german_low", choices=tuple(SPECTRA),
                   help="spectrum of the irregularities of the third case")
    p.add_argument("--seed", type=int, default=1, help="seed of the generated irregularities")
    args = p.parse_args(argv)
    out = Path(args.out)
    results = {}
    print(f"{'case':>30} {'V km/h':>7} {'a_nc m/s2':>10} {'m a_nc kN':>10} {'sum sum Y kN':>13} {'error':>7}  steady")
    for name, case in _cases(args).items():
        res = run_curving(case, out_dir=out / name.replace(", ", "_").replace(" ", "_"))
        s = res.summary
        results[name] = res
        m_a = s["vehicle_mass_kg"] * s["unbalanced_lateral_acceleration_m_s2"]
        tot = sum(s["sum_Y_N"]) if s.get("sum_Y_N") is not None else math.nan
        print(f"{name:>30} {case.speed_km_h:7.1f} {s['unbalanced_lateral_acceleration_m_s2']:10.3f} {m_a / 1e3:10.2f} "
              f"{tot / 1e3:13.2f} {(tot - m_a) / m_a:7.2%}  {s.get('steady')}")
    plot(results, out / "curving.png", load_vehicle("manchester_vehicle1").geometry.semi_wheelbase_m)
    print(f"wrote {out / 'curving.png'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
