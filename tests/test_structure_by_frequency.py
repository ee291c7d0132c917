"""A scenario's deck given by its mass and frequencies (``[structure]`` ``mass_kg_m``, ``f1_Hz``, optional
``lateral_f1_Hz``) instead of a section: the section it stands for, the frequencies of the deck built from it
(against Euler–Bernoulli's closed form; one span and a chain), the same section as the ``bridge-crossing``
command's deck, overrides of the frequency and the span (the normal form keeps the frequencies, not a section
derived once), and the errors of a table that gives both forms, neither, or an implausible value."""
import math

import pytest

from exudyn_wheelrail.scenarios.bridge_crossing import BridgeCrossing, deck_section
from exudyn_wheelrail.scenarios.build import build_bridge_modes
from exudyn_wheelrail.scenarios.deck import structure_section
from exudyn_wheelrail.scenarios.defaults import LATERAL_EI_RATIO
from exudyn_wheelrail.scenarios.overrides import apply_overrides
from exudyn_wheelrail.scenarios.spec import ScenarioError, validate_scenario
from exudyn_wheelrail.structures.load_models import AxleTrain, flexural_rigidity_Nm2

#: the first bending frequency of a simply supported span of 20 cubic (Hermite) beam elements: its error is of the
#: order (π/n)⁴/1440 = 4e-7 (n = 20; the bridge crossing documents 3e-5 for its N-th mode with max(20, 8N)
#: elements); 1e-6 leaves the factor of the constant
FE_FIRST_MODE_REL = 1e-6

SPAN_M, MASS_KG_M, F1_HZ = 20.0, 15000.0, 5.0


def _scenario(**structure):
    return {"schema_version": 2, "vehicle": {"name": "manchester_vehicle1", "speed_km_h": 100.0},
            "run": {"duration_s": 1.0},
            "structure": {"spans_m": [SPAN_M], "start_m": 30.0, "damping_ratio": 0.01, "rail_height_m": 0.0,
                          **structure}}


def test_the_section_of_a_deck_given_by_its_frequencies():
    """``EI_y = m (2 L² f1/π)²`` of the first span, ``EI_z`` the same of the lateral frequency (else
    ``LATERAL_EI_RATIO EI_y``), the placeholders of a bending-only section; the normal form is a fixed point."""
    n = validate_scenario(_scenario(mass_kg_m=MASS_KG_M, f1_Hz=F1_HZ))
    assert "section" not in n["structure"] and n["structure"]["f1_Hz"] == F1_HZ
    assert validate_scenario(n) == n
    sec = structure_section(n["structure"])
    EI = MASS_KG_M * (2.0 * SPAN_M ** 2 * F1_HZ / math.pi) ** 2
    assert sec.m_kg_m == MASS_KG_M
    assert sec.EI_y_Nm2 == pytest.approx(EI, rel=1e-15)
    assert sec.EI_z_Nm2 == pytest.approx(LATERAL_EI_RATIO * EI, rel=1e-15)
    assert (sec.GJ_Nm2, sec.EA_N, sec.Ip_kgm2_m) == (sec.EI_y_Nm2, 1e3 * sec.EI_y_Nm2, 4.0 * MASS_KG_M)
    lateral = validate_scenario(_scenario(mass_kg_m=MASS_KG_M, f1_Hz=F1_HZ, lateral_f1_Hz=12.0))
    assert structure_section(lateral["structure"]).EI_z_Nm2 == flexural_rigidity_Nm2(SPAN_M, MASS_KG_M, 12.0)


def _closest(frequencies, f):
    return min(frequencies, key=lambda x: abs(x - f))


def test_the_deck_built_from_its_frequencies_has_them():
    """The deck's modes (20 cubic beam elements per span): the lowest vertical and lateral bending frequencies are
    ``f1`` and the lateral one given (:data:`FE_FIRST_MODE_REL`).  A chain of simply supported spans: the first span
    has ``f1``, the second (the same section) ``f1 (L1/L2)²``."""
    n = validate_scenario(_scenario(mass_kg_m=MASS_KG_M, f1_Hz=F1_HZ, lateral_f1_Hz=12.0))
    _, modes, _ = build_bridge_modes(n["structure"])
    f = sorted(modes.frequencies_Hz)
    assert f[0] == pytest.approx(F1_HZ, rel=FE_FIRST_MODE_REL)
    assert _closest(f, 12.0) == pytest.approx(12.0, rel=FE_FIRST_MODE_REL)
    chain = validate_scenario(_scenario(mass_kg_m=MASS_KG_M, f1_Hz=F1_HZ) | {})
    chain["structure"]["spans_m"] = [SPAN_M, 30.0]
    _, modes, _ = build_bridge_modes(validate_scenario(chain)["structure"])
    f = sorted(modes.frequencies_Hz)
    f2 = F1_HZ * (SPAN_M / 30.0) ** 2
    assert f[0] == pytest.approx(f2, rel=FE_FIRST_MODE_REL)
    assert _closest(f, F1_HZ) == pytest.approx(F1_HZ, rel=FE_FIRST_MODE_REL)


def test_overrides_change_the_frequency_or_the_span_not_a_derived_section():
    """``--set structure.f1_Hz`` on a deck given by its frequencies gives that frequency; a new span keeps ``f1``
    (the section follows the span), as the file says."""
    n = validate_scenario(_scenario(mass_kg_m=MASS_KG_M, f1_Hz=F1_HZ))
    faster = apply_overrides(n, {"structure.f1_Hz": 6.0})
    assert sorted(build_bridge_modes(faster["structure"])[1].frequencies_Hz)[0] == pytest.approx(
        6.0, rel=FE_FIRST_MODE_REL)
    longer = apply_overrides(n, {"structure.spans_m": [30.0]})
    assert sorted(build_bridge_modes(longer["structure"])[1].frequencies_Hz)[0] == pytest.approx(
        F1_HZ, rel=FE_FIRST_MODE_REL)


def test_the_same_section_as_the_bridge_crossings_deck():
    """The crossing's deck of the same span, mass and frequency has this section, value for value (the same
    function on the same numbers)."""
    n = validate_scenario(_scenario(mass_kg_m=MASS_KG_M, f1_Hz=F1_HZ))
    case = BridgeCrossing(span_m=SPAN_M, mass_kg_m=MASS_KG_M, f1_Hz=F1_HZ, damping_ratio=0.01, n_modes=3,
                          axles=AxleTrain(x_m=[0.0], load_N=[1e5]), speed_m_s=50.0)
    assert structure_section(n["structure"]) == deck_section(case)


@pytest.mark.parametrize("structure, message", [
    ({"mass_kg_m": MASS_KG_M, "f1_Hz": F1_HZ,
      "section": {"m_kg_m": 1.0, "EI_y_Nm2": 1.0, "EI_z_Nm2": 1.0, "GJ_Nm2": 1.0, "EA_N": 1.0, "Ip_kgm2_m": 1.0}},
     r"structure: give the section or the deck's mass and frequencies"),
    ({"mass_kg_m": MASS_KG_M}, r"structure\.f1_Hz: missing"),
    ({"lateral_f1_Hz": 12.0}, r"structure\.mass_kg_m: missing"),
    ({}, r"structure\.section: missing \(or give the deck's mass_kg_m and f1_Hz\)"),
    ({"mass_kg_m": MASS_KG_M, "f1_Hz": 500.0}, r"structure\.f1_Hz"),
    ({"mass_kg_m": -1.0, "f1_Hz": F1_HZ}, r"structure\.mass_kg_m"),
])
def test_a_deck_given_twice_or_not_at_all_is_an_error(structure, message):
    with pytest.raises(ScenarioError, match=message):
        validate_scenario(_scenario(**structure))
