"""The full interaction's time step (``bridge_crossing_vehicles.contact_dt_s``): an accuracy bound on the stiffest
wheelset's bounce on its Hertz contact.

* The derivation it rests on: RK44's amplification factor on the imaginary axis, ``R(z) = 1 + z + z²/2 + z³/6 +
  z⁴/24`` at ``z = iωh``, is ``1 - (ωh)⁶/144`` to leading order — checked against the polynomial itself; so an
  oscillation loses ``N (2π/N)⁶/144`` of its amplitude per period at N steps per period (0.013 % at the rule's 20).
* The command takes that bound for the vehicles model: its summary's step is ``contact_dt_s`` of the consist, i.e.
  20 steps per period of the stiffest wheelset's bounce ``ω = √(2 k_H / m)`` on the linearised Hertz spring of its
  static wheel load (the spring the code uses for its resolution bound; the test checks the rule's arithmetic and
  that the command applies it).
* Convergence (validation): the README's 8-car crossing at the rule's step and at half of it — RK44 is fourth order,
  so the error at the rule's step is about 16/15 of their difference; the deck's peaks (EN 1990 acceleration,
  mid-span acceleration and deflection) within 1 % (the wheel forces' convergence: benchmarks/
  crossing_work_precision.py).
"""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.rolling_stock.train import load_consist
from exudyn_wheelrail.rolling_stock.vehicle_builder import RailSprings, static_load_path
from exudyn_wheelrail.scenarios.build import build_crossing
from exudyn_wheelrail.scenarios.bridge_crossing_case import BridgeCrossing
from exudyn_wheelrail.scenarios.bridge_crossing_vehicles import contact_dt_s
from exudyn_wheelrail.scenarios.defaults import CONTACT_STEPS_PER_PERIOD

ROOT = Path(__file__).resolve().parents[1]
CONSIST = ROOT / "vehicles" / "trains" / "manchester_x2.toml"


@pytest.mark.parametrize("n", [8, 9, 12, 20, 40])
def test_rk44_damps_an_oscillation_by_the_sixth_power_of_its_step(n):
    x = 2 * math.pi / n
    z = 1j * x
    r = abs(1 + z + z ** 2 / 2 + z ** 3 / 6 + z ** 4 / 24)
    loss = 1.0 - r
    # the next term of |R(ix)| is O(x^8): relative deviation of the leading term bounded by x^2 (a generous bound of
    # the series' ratio here, x <= 0.79)
    assert loss == pytest.approx(x ** 6 / 144, rel=x ** 2)
    per_period = 1.0 - r ** n
    if n == CONTACT_STEPS_PER_PERIOD:
        assert per_period < 2e-4                     # 0.013 % per period at the rule's N


def test_the_vehicles_model_steps_twenty_times_per_period_of_the_stiffest_wheelset_bounce():
    consist = load_consist(CONSIST)
    dt = contact_dt_s(consist)
    omegas = []
    for car in consist.cars:
        v = car.vehicle
        q = float(np.max(static_load_path(v).wheel))
        k = RailSprings.from_hertz(wheel_load_N=q, r0_m=v.geometry.r0_m).k_vertical_N_per_m
        omegas.append(math.sqrt(2.0 * k / v.wheelset.mass_kg))
    period = 2 * math.pi / max(omegas)
    # at most 20 per period, rounded down to 3 significant digits (at most 1 % below)
    assert period / CONTACT_STEPS_PER_PERIOD * 0.99 <= dt <= period / CONTACT_STEPS_PER_PERIOD
    case = BridgeCrossing(span_m=20.0, mass_kg_m=15000.0, f1_Hz=5.0, damping_ratio=0.01, n_modes=3, axles=None,
                          speed_m_s=40.0, model="vehicles", train_file=str(CONSIST))
    built = build_crossing(case)
    assert built.run.dt_s == pytest.approx(dt, rel=1e-12)     # the deck's rule alone: 0.555 ms


@pytest.mark.validation
def test_the_readme_crossing_converges_at_the_rules_step(tmp_path):
    base = ["bridge-crossing", "--span-m", "20", "--bridge-mass-kg-per-m", "15000", "--bridge-frequency-hz", "5",
            "--damping-ratio", "0.01", "--modes", "3", "--train",
            str(ROOT / "vehicles" / "trains" / "crh6_intercity_8car.toml"), "--model", "vehicles", "--speed-kmh", "250"]
    out = {}
    for name, extra in (("rule", []), ("half", None)):
        if extra is None:
            extra = ["--dt", repr(out["rule"]["dt_s"] / 2)]
        folder = tmp_path / name
        subprocess.run([sys.executable, "-m", "exudyn_wheelrail", *base, "--out", str(folder), *extra], check=True,
                       capture_output=True)
        out[name] = json.loads((folder / "summary.json").read_text())
    for key in ("deck.en1990_peak_acceleration_m_s2", "max_abs_deck_midspan_acceleration_m_s2",
                "deck.max_mid_span_deflection_m"):
        a, b = out["rule"]["scalars"][key], out["half"]["scalars"][key]
        assert abs(a - b) * 16 / 15 <= 0.01 * abs(b), key
