"""The flexible deck of a scenario with a lateral support motion (exudyn_wheelrail.scenarios.deck,
``[structure.support_motion]``), and examples/bridge_crossing.py mapped onto the shipped scenarios.

References, independent of the code under test:

* the simply supported Euler–Bernoulli beam under its uniform inertia load m a_p: mid-span deflection
  5 m a_p L⁴/(384 EI_z), amplified as its first lateral mode at r = f/f_lat,1 by 1/(1 − r²) (the statement of
  examples/bridge_crossing.py), with a tolerance built from the terms that reference neglects (the test's docstring);
* the trapezoidal rule's identity (w₊ − 2w + w₋)/h² = (a₊ + 2a + a₋)/4 between the recorded relative lateral
  deflection and the recorded lateral acceleration minus the ground's: the integrator's own relation, which holds
  only if the recorded acceleration carries the effective load −Γ ÿ_g of the support motion;
* the shipped scenario files for the example's command line (the mapping must give the files' normal forms).

The run covers only the ramp of the ground motion (667 steps): the vehicle has not reached the deck.
"""
import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.scenarios.scenario import (
    ScenarioError,
    apply_overrides,
    group_figure,
    load_scenario,
    run_scenario,
)
from exudyn_wheelrail.structures.support_motion import SmoothHarmonicSupportMotion

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "scenarios"


def _example():
    spec = importlib.util.spec_from_file_location("bridge_crossing", ROOT / "examples" / "bridge_crossing.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def ramp_run():
    """bridge_20m_support_motion.toml over the ramp of the ground motion (one period, 1.5 Hz): the leading wheelset
    reaches the deck 5 m after the ramp's end."""
    base = load_scenario(EXAMPLES / "bridge_20m_support_motion.toml")
    sm = base["structure"]["support_motion"]
    scn = apply_overrides(base, {"run.duration_s": sm["ramp_cycles"] / sm["frequency_Hz"], "outputs.plots": False,
                                 "outputs.criteria": False})
    r = run_scenario(scn, None, progress=False)
    assert r.summary["status"] == "ok"
    assert r.timeseries["s_leading_m"][-1] < scn["structure"]["start_m"]          # the deck carries no wheel
    return scn, r


def test_deck_lateral_motion_against_the_beam_under_its_inertia_load(ramp_run):
    r"""The largest mid-span lateral motion relative to the supports against ``w_ref = 5 m a_p L⁴/(384 EI_z) /
    (1 − r²)``.  Neglected by that reference, each bounded here:

    * modal truncation: the model keeps the first lateral mode only (the third lies at 9 f_lat,1, above the cut-off;
      the second has no participation), whose static share Γ₁ φ₁(L/2)/ω₁² = 4 m L⁴/(π⁵ EI_z) is 1536/(5π⁵) of the
      beam's: +0.39 %;
    * the burst is no steady harmonic: quasi-statically x = −(a − ä/ω² + …)/ω², so at the peak of |a| the
      amplification is 1 + κ_p r² instead of 1/(1 − r²) = 1 + r² + …, with κ_p = −ä/(Ω² a) there; and the jump of ä at
      the start of the C² ramp leaves a free vibration of amplitude |ä(0⁺)|/ω⁴ = κ_0 r² a_p/ω² (κ read from the
      record by finite differences);
    * damping (ζ = 1 %: (2ζr)² on the amplitude), the time step ((ω h)²/12 = 1e-3 on the period of a term of size
      r²) and the higher orders r⁴: together below 1e-3.
    """
    scn, r = ramp_run
    st = scn["structure"]
    sec, L = st["section"], st["spans_m"][0]
    sm = st["support_motion"]
    a_p, f = sm["peak_acceleration_m_s2"], sm["frequency_Hz"]
    f_lat = math.pi / (2.0 * L ** 2) * math.sqrt(sec["EI_z_Nm2"] / sec["m_kg_m"])
    ratio = f / f_lat
    w_ref = 5.0 * sec["m_kg_m"] * a_p * L ** 4 / (384.0 * sec["EI_z_Nm2"]) / (1.0 - ratio ** 2)
    # the record's shape factors
    motion = SmoothHarmonicSupportMotion(a_p, f, ramp_cycles=sm["ramp_cycles"], plateau_cycles=1.0,
                                         start_s=sm["start_s"])
    t = np.linspace(0.0, motion.ramp_s, 100_001)
    a = motion.acceleration_m_s2(t)
    a_tt = np.gradient(np.gradient(a, t), t)
    omega2 = motion.omega_rad_s ** 2
    k = int(np.argmax(np.abs(a)))
    kappa_p = -a_tt[k] / (omega2 * a[k])
    kappa_0 = abs(a_tt[10]) / (omega2 * a_p)                     # ä is constant near τ = 0⁺ (a ∝ τ²)
    truncation = 1536.0 / (5.0 * math.pi ** 5) - 1.0
    tol = truncation + ratio ** 2 * (abs(kappa_p - 1.0) + kappa_0) + 1e-3
    rel = r.timeseries["deck_mid_lateral_rel_s1_m"]
    assert np.max(np.abs(rel)) == pytest.approx(w_ref, rel=tol)
    assert np.max(np.abs(rel)) > w_ref                               # each neglected term adds (all > 0 here)
    # the summary's reference and ground motion
    sp = r.summary["deck"]["spans"][0]
    assert sp["support_motion_quasi_static_mid_lateral_m"] * sp["support_motion_amplification_single_mode"] == \
        pytest.approx(w_ref, rel=1e-12)
    assert r.summary["deck"]["support_motion"]["max_abs_ground_acceleration_m_s2"] == pytest.approx(a_p, rel=1e-4)


def test_recorded_lateral_acceleration_carries_the_effective_ground_load(ramp_run):
    """The relative acceleration (absolute minus ground) is what the trapezoidal rule integrates to the recorded
    relative deflection; without the −Γ ÿ_g term it would be off by about the ground acceleration itself.  The
    tolerance: Newton's 1e-6 on modal forces of the size Γ ÿ_g, times the (ω h)⁻² = 90 of the identity."""
    scn, r = ramp_run
    ts = r.timeseries
    h = scn["run"]["dt_s"]
    w = ts["deck_mid_lateral_rel_s1_m"]
    a_rel = ts["deck_mid_lateral_acceleration_s1_m_s2"] - ts["ground_lateral_acceleration_m_s2"]
    lhs = (w[2:] - 2.0 * w[1:-1] + w[:-2]) / h ** 2
    rhs = (a_rel[2:] + 2.0 * a_rel[1:-1] + a_rel[:-2]) / 4.0
    scale = np.max(np.abs(ts["ground_lateral_acceleration_m_s2"]))
    assert np.max(np.abs(lhs - rhs)) < 1e-4 * scale
    assert np.max(np.abs(a_rel)) < 0.1 * scale                    # the deck follows the ground quasi-statically


def test_deck_lateral_figure_draws_the_recorded_columns(ramp_run):
    import matplotlib.pyplot as plt

    _, r = ramp_run
    fig, axes = group_figure(r, "deck_lateral")
    try:
        ts = r.timeseries
        lines = {ln.get_label(): ln.get_ydata() for ax in axes for ln in ax.get_lines()}
        assert "[mm]" in axes[0].get_ylabel() and "[m/s²]" in axes[1].get_ylabel()
        ground = [ln for ln in axes[0].get_lines() if ln.get_label().startswith("ground")]
        np.testing.assert_allclose(ground[0].get_ydata(), ts["ground_lateral_m"] * 1e3, rtol=1e-12)
        assert any(np.allclose(y, ts["deck_mid_lateral_rel_s1_m"] * 1e3) for y in lines.values())
    finally:
        plt.close(fig)


# ------------------------------------------------------------------------------------------------------- example
def _without_description(scn: dict) -> dict:
    return {**scn, "scenario": {**scn["scenario"], "description": ""}}


def test_example_command_line_maps_onto_the_shipped_scenarios():
    mod = _example()
    assert mod.scenario(20, 200) == load_scenario(EXAMPLES / "bridge_20m.toml")
    assert mod.scenario(40, 200) == load_scenario(EXAMPLES / "bridge_40m.toml")
    mapped = mod.scenario(20, 200, support_motion=(1.5, 1.5))
    shipped = load_scenario(EXAMPLES / "bridge_20m_support_motion.toml")
    assert mapped["structure"]["start_m"] == pytest.approx(shipped["structure"]["start_m"], rel=1e-15)
    mapped["structure"]["start_m"] = shipped["structure"]["start_m"]
    assert _without_description(mapped) == _without_description(shipped)
    other = mod.scenario(40, 160, dt_s=5e-4, creep_law="linear", support_motion=(1.0, 2.0))
    assert other["vehicle"]["speed_km_h"] == 160 and other["run"]["dt_s"] == 5e-4
    assert other["contact"]["creep_law"] == "linear"
    lead_in = other["structure"]["start_m"] - other["vehicle"]["start_s_m"]
    assert lead_in == pytest.approx(5.0 + 160 / 3.6 / 2.0)
    with pytest.raises(ScenarioError, match=r"structure\.support_motion\.frequency_Hz"):
        mod.scenario(20, 200, support_motion=(1.5, 50.0))
