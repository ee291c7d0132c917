"""The EN 1991-2 dynamic check of a bridge given by an FE program's modes (``modes_file``) and of a deck continuous
over its intermediate supports (``continuous = true``): the modes-file check reproduces the built-in beam's at both
mass bounds; the modes reach EN 1990's cut-off; bad bridge files end before any work with one line."""
from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from bridge_file_check import check_bridge_file

from exudyn_wheelrail.scenarios import en1991_dynamic as E
from exudyn_wheelrail.scenarios.bridge_crossing import BridgeCrossing, deck_modes
from exudyn_wheelrail.scenarios.sweep import SerialExecutor
from exudyn_wheelrail.structures.load_models import hslm_a
from exudyn_wheelrail.structures.modes_file import write_modes_npz

L, EI, M_NOMINAL = 15.0, 1.0e10, 12000.0


def _beam_file(tmp_path, extra=""):
    f = tmp_path / "beam.toml"
    f.write_text(f"[bridge]\nspans_m = [{L}]\nEI_Nm2 = {EI}\nmass_kg_per_m = [10800.0, 13200.0]\n"
                 f"structure = 'steel_composite'\n{extra}")
    return f


def _modes_file(tmp_path, n_modes=4):
    """The built-in span's modes at the nominal mass as an FE program would export them (every L/300)."""
    f1 = math.pi / (2.0 * L * L) * math.sqrt(EI / M_NOMINAL)
    case = BridgeCrossing(span_m=L, mass_kg_m=M_NOMINAL, f1_Hz=f1, damping_ratio=0.01, n_modes=n_modes,
                          axles=hslm_a("A1"), speed_m_s=50.0)
    modes = deck_modes(case).modes
    x = np.linspace(0.0, L, 301)
    return write_modes_npz(tmp_path / "span.npz", frequency_hz=modes.frequencies_Hz,
                           modal_mass_kg=np.full(modes.n_modes, 4.0), x_m=x,
                           vertical=2.0 * modes.shape_at(x)[:, 1, :].T)


def test_a_modes_file_check_reproduces_the_built_in_beams_at_both_mass_bounds(tmp_path):
    npz = _modes_file(tmp_path)
    by_file = tmp_path / "file.toml"
    by_file.write_text(f"[bridge]\nspans_m = [{L}]\nmodes_file = '{npz.name}'\nmodes_mass_kg_per_m = {M_NOMINAL}\n"
                       "mass_kg_per_m = [10800.0, 13200.0]\nstructure = 'steel_composite'\n")
    runs = {}
    for name, path in (("beam", _beam_file(tmp_path)), ("file", by_file)):
        check = E.DynamicCheck(bridge=E.read_bridge_file(path), max_line_speed_kmh=250.0, trains=("A1", "A4"),
                               speeds_kmh=(262.0, 300.0))
        runs[name] = (check, E.run_dynamic_check(check, tmp_path / name, executor=SerialExecutor(), progress=None))
    (_, sb), (_, sf) = runs["beam"], runs["file"]
    # a mass bound r m scales the file's modes to f / sqrt(r): the beam's frequencies at that mass
    for bound in ("lower", "upper"):
        assert sf["modes"][bound]["f1_Hz"][0] == pytest.approx(sb["modes"][bound]["f1_Hz"][0], rel=1e-5)
        assert sf["modes"][bound]["n_modes"] == sb["modes"][bound]["n_modes"]
        assert sf["modes"][bound]["modes_reach_cutoff"] and sb["modes"][bound]["modes_reach_cutoff"]
    rows = {name: list(csv.DictReader(open(tmp_path / name / "envelope.csv", newline=""))) for name in runs}
    assert len(rows["beam"]) == len(rows["file"]) == 8
    # the splines between positions L/300 apart reproduce the element's cubics to ~(5/384)(4π/300)^4 = 4e-8 of
    # a mode's amplitude, the scaled frequencies to the FE rounding; the two runs' steps differ (the beam's from
    # N² f1, the file's from its N-th frequency, 3 digits): each within RK44's 7e-5 of the peak acceleration
    # (bridge_crossing.py, measured against the closed form), so they agree to 2e-4
    for a, b in zip(rows["beam"], rows["file"]):
        assert (a["train"], a["mass_bound"], a["speed_kmh"]) == (b["train"], b["mass_bound"], b["speed_kmh"])
        for key in ("max_deck_acceleration_m_s2", "max_deck_displacement_m"):
            assert float(b[key]) == pytest.approx(float(a[key]), rel=2e-4), (a, key)
    assert sf["verdict"] == sb["verdict"] and sf["governing"] == sb["governing"]
    assert sf["deck"].startswith("modes file") and sf["inputs"]["modes_mass_kg_per_m"] == M_NOMINAL


def test_a_continuous_decks_check_keeps_its_modes_to_the_cutoff(tmp_path):
    f = tmp_path / "two.toml"
    f.write_text("[bridge]\nspans_m = [20.0, 20.0]\ncontinuous = true\nEI_Nm2 = 3.0e10\nmass_kg_per_m = 15000.0\n"
                 "structure = 'prestressed_concrete'\n")
    check = E.DynamicCheck(bridge=E.read_bridge_file(f), max_line_speed_kmh=250.0, trains=("A1",))
    n, deck = check.deck("nominal")
    f_v = deck.modes.frequencies_Hz[deck.vertical[0]]
    # N K modes with the smallest N >= 3 whose highest reaches max(30, 1.5 f1, f3) of the continuous deck
    assert f_v.size == 2 * n and f_v[-1] >= deck.cutoffs_Hz[0]
    assert n == 3 or f_v[2 * (n - 1) - 1] < deck.cutoffs_Hz[0]
    # the two-span deck's first mode is the simply supported span's (antisymmetric): its resonance speeds
    f1 = math.pi / (2.0 * 400.0) * math.sqrt(3.0e10 / 15000.0)
    assert deck.f1_Hz[0] == pytest.approx(f1, rel=1e-5)
    d = hslm_a("A1").spacing_m
    assert check.resonances_kmh("A1", "nominal")[-1] == pytest.approx(3.6 * deck.f1_Hz[0] * d, abs=0.06)


@pytest.mark.parametrize("body, expected", [
    ("spans_m = [15.0]\nEI_Nm2 = 1e10\nmodes_file = 'span.npz'\nmass_kg_per_m = 12000.0\nstructure = 'filler_beam'\n",
     "bridge.modes_file: give either the built-in beam"),
    ("spans_m = [15.0]\nmodes_file = 'span.npz'\nmass_kg_per_m = [11000.0, 13000.0]\nstructure = 'filler_beam'\n",
     "bridge.modes_mass_kg_per_m: missing"),
    ("spans_m = [15.0]\nEI_Nm2 = 1e10\nmodes_mass_kg_per_m = 1.0\nmass_kg_per_m = 1.0e4\nstructure = 'filler_beam'\n",
     "bridge.modes_mass_kg_per_m: only with a modes_file"),
    ("spans_m = [15.0]\ncontinuous = true\nEI_Nm2 = 1e10\nmass_kg_per_m = 1.0e4\nstructure = 'filler_beam'\n",
     "bridge.continuous: a deck continuous over intermediate supports needs at least two spans"),
    ("spans_m = [15.0]\nmodes_file = 'none.npz'\nmass_kg_per_m = 1.0e4\nstructure = 'filler_beam'\n",
     "bridge.modes_file:"),
])
def test_a_bad_modes_bridge_file_is_one_line_before_any_work(tmp_path, capsys, body, expected):
    _modes_file(tmp_path)
    code, err, f, out = check_bridge_file(tmp_path, capsys, body)
    assert code == 2 and err.count("\n") == 0 and expected in err and str(f) in err, err
    assert not (out / "runs").exists()


def test_a_modes_file_whose_shapes_disagree_with_its_positions_is_named_by_the_command(tmp_path, capsys):
    x = np.linspace(0.0, L, 11)
    write_modes_npz(tmp_path / "bad.npz", frequency_hz=[5.0], modal_mass_kg=[1e5], x_m=x, vertical=np.zeros((1, 9)))
    code, err, _, _ = check_bridge_file(tmp_path, capsys, f"spans_m = [{L}]\nmodes_file = 'bad.npz'\n"
                                        "mass_kg_per_m = 1.0e4\nstructure = 'filler_beam'\n")
    assert code == 2 and err.count("\n") == 0 and "bad.npz: vertical: shape (1, 9) disagrees" in err, err


def test_a_modes_file_of_many_modes_keeps_those_up_to_the_cutoff(tmp_path):
    # 70 modes (n² 6 Hz, a simply supported span's): EN 1990's cut-off max(30, 9, 54) = 54 Hz is reached by the
    # third; the check keeps three (the file's count is no limit)
    x = np.linspace(0.0, L, 301)
    n = np.arange(1, 71)
    npz = write_modes_npz(tmp_path / "many.npz", frequency_hz=6.0 * n ** 2, modal_mass_kg=np.full(70, 1e5), x_m=x,
                          vertical=np.sin(np.pi * n[:, None] * x[None, :] / L))
    f = tmp_path / "many.toml"
    f.write_text(f"[bridge]\nspans_m = [{L}]\nmodes_file = '{npz.name}'\nmass_kg_per_m = 1.0e4\n"
                 "structure = 'filler_beam'\n")
    check = E.DynamicCheck(bridge=E.read_bridge_file(f), max_line_speed_kmh=200.0, trains=("A1",))
    assert check.n_modes("nominal") == 3
    assert check.deck("nominal")[1].cutoffs_Hz[0] == pytest.approx(54.0)


def test_a_changed_modes_file_is_computed_again_on_a_resumed_check(tmp_path):
    import re
    npz = _modes_file(tmp_path)
    f = tmp_path / "file.toml"
    f.write_text(f"[bridge]\nspans_m = [{L}]\nmodes_file = '{npz.name}'\nmass_kg_per_m = {M_NOMINAL}\n"
                 "structure = 'steel_composite'\n")
    out = tmp_path / "out"

    def run():
        lines = []
        check = E.DynamicCheck(bridge=E.read_bridge_file(f), max_line_speed_kmh=200.0, trains=("A1",),
                               speeds_kmh=(200.0,))
        s = E.run_dynamic_check(check, out, executor=SerialExecutor(), progress=lines.append)
        return s, [ln for ln in lines if re.match(r"\s+\[\d+/\d+\]", ln)]
    first, computed = run()
    assert len(computed) == 1
    assert run()[1] == []                                            # the same file: taken from DIR/runs
    with np.load(npz) as z:
        data = {k: z[k] for k in z.files}
    write_modes_npz(npz, **{**data, "modal_mass_kg": 2.0 * data["modal_mass_kg"]})   # another deck, same name
    again, computed = run()
    assert len(computed) == 1
    # twice the modal mass for the same shapes: half the modal forces' response
    assert again["max_deck_acceleration_m_s2"] == pytest.approx(0.5 * first["max_deck_acceleration_m_s2"], rel=1e-9)
