"""The product's linearisation of the full model (exudyn_wheelrail/scenarios/critical_speed_linear.py: the ``run``
command's wheelset settled on straight rigid track and linearised by central differences) against the classical
reduced models of one wheelset, every coefficient taken from parts of the contact that the dynamics does not enter:

* the rigid contact geometry at the centre — local conicity λ (half the slope of the rolling-radius difference),
  rolling radius r0 and the wheelset's roll per lateral shift σ = dφ/dy — from the quasi-static sweep of
  exudyn_wheelrail/analysis/geometry_functions.py (both wheels just touching, no dynamics, no creep);
* the half distance b of the two contact points and Hertz's semi-axes a, b_H at the settled operating point, and
  Kalker's linear creep coefficients at a/b_H (Table E.3): f11 = G a b_H C11, f22 = G a b_H C22;
* the restraint of the vehicle file (primary springs and dampers per axlebox at ±d).

One kinematic term enters the reduced models beside Klingel's: the contact points lie r0 below the axle, so a roll
rate moves them laterally (−r0 φ̇ in the track frame, z down), and the wheelset rolls with its lateral shift (one
wheel rides higher: φ = σ y, σ < 0).  The lateral creepage of the shifting wheelset is therefore κ ẏ/V − ψ with
κ = 1 − r0 σ (1.015 on S1002/UIC60 1:40, 1.032 on the 1:20 cone below), not ẏ/V − ψ.  Left out of the reduced
models and small here: the gravitational and spin-creep stiffnesses (the normal forces' and the spin creepage's
lateral resultants: on S1002/UIC60 1:40 each about 1.2 MN/m with opposite signs, net about 0.1–0.2 MN/m, against
the restraint's 7.8 MN/m and the creep forces' ~20 MN/rad), the spin moment,
the dynamics of the stiff roll and bounce on the Hertz springs (~200 Hz against the modes compared, ≤ 35 Hz) and
the difference between the rigid geometry's roll and the elastic contact's.
"""
import math

import numpy as np
import pytest

from exudyn_wheelrail.analysis.geometry_functions import contact_geometry_sweep
from exudyn_wheelrail.analysis.stability import modes_of
from exudyn_wheelrail.contact.layout import CP_G, CP_NU, RES_A, RES_B, RES_P_Y
from exudyn_wheelrail.creep.linear import kalker_coefficients
from exudyn_wheelrail.rolling_stock.vehicle_data import load_vehicle
from exudyn_wheelrail.scenarios.build import build_scenario
from exudyn_wheelrail.scenarios.critical_speed_linear import lateral_share, linearise, settled_scenario
from exudyn_wheelrail.scenarios.run import run_model

SHIFTS_M = np.array([-2e-6, -1e-6, 0.0, 1e-6, 2e-6])     # inside the tread zone at the centre (±0.25 mm on S1002)
CONE = 0.05                                               # the cone's slope (1:20)


def _variant(directory, name, text):
    p = directory / f"{name}.toml"
    p.write_text(f'schema_version = 1\nbase_vehicle = "single_wheelset"\n[vehicle]\nname = "{name}"\n{text}')
    return str(p)


@pytest.fixture(scope="module")
def vehicles(tmp_path_factory):
    """The single wheelset (S1002 on UIC60 1:40) restrained as shipped, the same wheelset free (restraint
    negligible: 1 N/m, no dampers) and free on a 1:20 cone (a straight wheel profile, no flange); the single bogie
    with a rigid primary (1e9 N/m: its yaw restraint of the wheelsets ~400 times the creep forces' yaw stiffness)
    and free of the moving frame (1 N/m, no dampers)."""
    d = tmp_path_factory.mktemp("linearisation")
    y = np.linspace(-0.05, 0.05, 201)
    (d / "cone.csv").write_text("y [m], z [m]\n" + "".join(f"{a:.6f}, {-CONE * a:.9f}\n" for a in y))
    free = "[primary]\nkx_N_per_m = 1.0\nky_N_per_m = 1.0\ncx_N_s_per_m = 0.0\ncy_N_s_per_m = 0.0\n"
    bogie = ("[primary]\nkx_N_per_m = 1.0e9\nky_N_per_m = 1.0e9\ncx_N_s_per_m = 0.0\ncy_N_s_per_m = 0.0\n"
             "[secondary]\nkx_N_per_m = 1.0\nky_N_per_m = 1.0\ncy_N_s_per_m = 0.0\nyaw_stiffness_N_m_per_rad = 1.0\n")
    (d / "rigid_bogie.toml").write_text('schema_version = 1\nbase_vehicle = "single_bogie"\n[vehicle]\n'
                                        f'name = "rigid bogie"\n{bogie}')
    return {"restrained": "single_wheelset", "rigid_bogie": str(d / "rigid_bogie.toml"),
            "free": _variant(d, "free", free),
            "free_cone": _variant(d, "free_cone",
                                  free + f'[geometry]\nwheel_profile = "{(d / "cone.csv").as_posix()}"\n')}


def _linearised(vehicle, speed_kmh, creep_law):
    scn = settled_scenario(vehicle, speed_kmh)
    scn["contact"] = {"creep_law": creep_law}
    h = build_scenario(scn)
    assert run_model(h, progress=False).status.kind == "ok"
    A, labels, _ = linearise(h)
    sweep = contact_geometry_sweep(h.pair, SHIFTS_M)
    r0 = [row["rolling_radius_m"] for row in sweep.rows if row["y_m"] == 0.0]
    res = h.contact.results
    geo = {"conicity": np.polyfit(SHIFTS_M, sweep.delta_r_m, 1)[0] / 2.0,
           "roll_per_shift": np.polyfit(SHIFTS_M, sweep.roll_rad, 1)[0],
           "r0": r0[0], "b": 0.5 * (res[0, 0, RES_P_Y] - res[1, 0, RES_P_Y]),
           "a_hertz": res[0, 0, RES_A], "b_hertz": res[0, 0, RES_B], "G": h.contact.cp[CP_G],
           "nu": h.contact.cp[CP_NU]}
    assert len(r0) == 2 and r0[0] == pytest.approx(r0[1], rel=1e-9)        # centred: both wheels alike
    assert res[1, 0, RES_A] == pytest.approx(geo["a_hertz"], rel=1e-6)
    return A, labels, geo


def _lateral_oscillating(A, labels, f_max_hz, yaw_weight_m=None):
    """Eigenvalues (Im > 0) of the lateral modes (lateral share ≥ 0.5) below ``f_max_hz``; with ``yaw_weight_m``
    only the yaw-dominated ones (|ψ| · yaw_weight_m > |y| in the wheelset's shape)."""
    ms = modes_of(A)
    lam = ms.eigenvalues
    keep = (lam.imag > 0) & (lam.imag / (2 * math.pi) < f_max_hz) & (lateral_share(ms.shapes, labels) >= 0.5)
    if yaw_weight_m is not None:
        y, yaw = np.abs(ms.shapes[labels.index("wheelset0 y")]), np.abs(ms.shapes[labels.index("wheelset0 yaw")])
        keep &= yaw * yaw_weight_m > y
    return lam[keep]


@pytest.mark.parametrize("name", ["free", "free_cone"])
def test_free_wheelset_kinematic_frequency(vehicles, name):
    """A free wheelset at low speed (10 m/s, the default creep law) oscillates with the kinematic frequency of its
    rolling without creep: κ ẏ = V ψ, b ψ̇ = −V λ y / r0 give f = V/(2π) √(λ/(b r0 κ)) — Klingel's with the roll
    factor κ (module docstring).  Tolerance 1 %: the creep's finite stiffness changes the frequency by
    O((m V ω / f22)²) ≈ 2.5e-4 here; the rigid geometry's roll per shift, used for κ, differs from the elastic
    contact's (from the full model's stiffness matrix, roll and bounce condensed: −0.047 against −0.033 1/m on
    S1002/UIC60 1:40, the same to 1e-3 on the cone), which moves the frequency by 0.35 % on S1002/UIC60 and by
    < 1e-4 on the cone.  (The mode's damping is not compared: at this speed it is a small balance of the inertia's
    and the spin creepage's terms that the kinematic model does not contain.)"""
    V = 10.0
    A, labels, g = _linearised(vehicles[name], V * 3.6, "table")
    kappa = 1.0 - g["r0"] * g["roll_per_shift"]
    f_ref = V / (2 * math.pi) * math.sqrt(g["conicity"] / (g["b"] * g["r0"] * kappa))
    lam = _lateral_oscillating(A, labels, 5.0)
    assert len(lam) == 1, lam
    assert lam[0].imag / (2 * math.pi) == pytest.approx(f_ref, rel=0.01)


def test_rigid_bogie_kinematic_wavelength(vehicles):
    """The single bogie with a rigid primary, free of the frame, at low speed (10 m/s) with Kalker's linear creep law
    rolls with the kinematic wavelength derived here for the rigid two-axle bogie (wheelsets at ±a, creep forces per
    wheel f11, f22, inertia negligible): the lateral forces' balance gives κ ẏ = V ψ, the yaw moments'
    f11 b (b ψ̇/V + λ y/r0) + κ f22 a² ψ̇/V = 0, so L = 2π √(b r0 κ (1 + κ (f22/f11) a²/b²) / λ) — the textbook's
    2π √(b r0 (1 + a²/b²)/λ) for κ = 1 and f11 = f22 (6 % shorter here: Kalker's C22/C11 = 0.81 and κ = 1.015).
    Tolerance 1 %: inertia O((m V ω / f)²) < 1e-4, the rigid primary's compliance ~2e-3, the elastic contact's roll
    against the rigid geometry's (κ enters twice here) ≤ 0.6 %."""
    V = 10.0
    A, labels, g = _linearised(vehicles["rigid_bogie"], V * 3.6, "linear")
    a = load_vehicle("single_bogie").geometry.semi_wheelbase_m
    C11, C22, _ = kalker_coefficients(g["a_hertz"] / g["b_hertz"], g["nu"])
    kappa = 1.0 - g["r0"] * g["roll_per_shift"]
    wavelength = 2 * math.pi * math.sqrt(g["b"] * g["r0"] * kappa * (1 + kappa * C22 / C11 * a * a / g["b"] ** 2)
                                         / g["conicity"])
    lam = _lateral_oscillating(A, labels, 3.0)
    assert len(lam) == 1, lam
    assert V / (lam[0].imag / (2 * math.pi)) == pytest.approx(wavelength, rel=0.01)


def _quartic(V, g, m, I, ky, kpsi, cy, cpsi):
    """det(s² M + s C + K) of the restrained wheelset with linear creep (f11, f22 from Kalker's Table E.3 at the
    operating point's ellipse), coefficients of s⁴ … s⁰:

        m ÿ + (2 f22 κ / V + cy) ẏ − 2 f22 ψ + ky y = 0
        I ψ̈ + (2 f11 b² / V + cψ) ψ̇ + 2 f11 b λ y / r0 + kψ ψ = 0
        (m s² + c1 s + ky)(I s² + c2 s + kψ) + 2 f22 · 2 f11 b λ / r0 = 0
    """
    C11, C22, _ = kalker_coefficients(g["a_hertz"] / g["b_hertz"], g["nu"])
    f11 = g["G"] * g["a_hertz"] * g["b_hertz"] * C11
    f22 = g["G"] * g["a_hertz"] * g["b_hertz"] * C22
    b, lam, r0 = g["b"], g["conicity"], g["r0"]
    kappa = 1.0 - r0 * g["roll_per_shift"]
    c1, c2 = 2 * f22 * kappa / V + cy, 2 * f11 * b * b / V + cpsi
    return np.polymul([m, c1, ky], [I, c2, kpsi]) + np.array([0, 0, 0, 0, 4 * f11 * f22 * b * lam / r0])


@pytest.mark.parametrize("speed_kmh", [200.0, 300.0, 400.0])
def test_restrained_wheelset_against_characteristic_polynomial(vehicles, speed_kmh):
    """The shipped single wheelset (primary springs and dampers to the moving frame) with Kalker's linear creep
    law: the full model's yaw-dominated oscillating mode (the restrained wheelset's "hunting" mode, 31–36 Hz) is
    the quartic's root of largest frequency.  Tolerance 1 % of |λ|: the terms left out (module docstring) change it
    by less than 1e-3 (measured ≤ 3e-4) — its yaw restraint (63 MN m/rad) and creep coupling dwarf them.  (The slower, lateral-dominated modes
    are not compared: there the stiffnesses left out are ~3–7 % of the lateral restraint and the roll's coupling
    through the creep forces counts — they differ from the quartic's by 1–5 %.)"""
    w = load_vehicle("single_wheelset")
    d = w.geometry.primary_lateral_semi_spacing_m
    (kx, ky, _), (cx, cy, _) = w.primary.stiffness_N_per_m, w.primary.damping_N_s_per_m
    coeff = dict(m=w.wheelset.mass_kg, I=w.wheelset.Izz_kg_m2, ky=2 * ky, kpsi=2 * kx * d * d, cy=2 * cy,
                 cpsi=2 * cx * d * d)
    A, labels, g = _linearised(vehicles["restrained"], speed_kmh, "linear")
    roots = np.roots(_quartic(speed_kmh / 3.6, g, **coeff))
    ref = roots[np.argmax(roots.imag)]            # the yaw mode (the slower lateral one joins it above ~250 km/h)
    assert ref.imag > 0
    lam = _lateral_oscillating(A, labels, 60.0, yaw_weight_m=g["b"])
    assert len(lam) == 1, lam
    assert abs(lam[0] - ref) <= 0.01 * abs(ref), (lam[0], ref)
