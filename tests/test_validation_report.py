"""``python -m exudyn_wheelrail validation-report``.

* ``--quick``: the report is written with every section; the numbers of section (a) agree with Kalker's Table E.3
  (read independently through ``kalker_coefficients``) within the 1.5 % of tests/test_kalker_exact.py; the Klingel
  figure draws the simulated motion and Klingel's reference on the same scale (read from the saved figure's lines).
* section (e) (skipped by ``--quick``, run here on its own): the window it states (solver, Δt, steps, simulated
  and peak window) is the window of the runs it made, its peaks are the maxima of those runs' time series over the
  stated window, and the runs are those of the ``rtri`` command it names.
"""
from __future__ import annotations

import contextlib
import io
import re

import numpy as np
import pytest
from figure_capture import saved_figures

from exudyn_wheelrail.cli import main as cli_main
from exudyn_wheelrail.creep import kalker_coefficients
from exudyn_wheelrail.scenarios.validation_report import (
    A_RATIOS,
    HEADINGS,
    Y0_C,
    rtri_report_case,
    section_e,
)

TOL = 0.015


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    """The CLI in this process, with every saved figure's lines recorded."""
    out = tmp_path_factory.mktemp("validation_report")
    with pytest.MonkeyPatch.context() as mp, saved_figures(mp) as figures, \
            contextlib.redirect_stdout(io.StringIO()):
        assert cli_main(["validation-report", "--out", str(out), "--quick"]) == 0
    return out, figures


def test_report_and_plots_exist_with_every_section(quick_report):
    out, _ = quick_report
    text = (out / "report.md").read_text(encoding="utf-8")
    for heading in HEADINGS.values():
        assert heading in text, heading
    assert "**ERROR**" not in text
    for png in ("kalker_e3.png", "fryba.png", "klingel.png"):
        assert (out / png).stat().st_size > 1000, png
    assert "| NO |" not in text and "NO (40 m)" not in text


def test_quick_report_names_the_rtri_commands_it_skips(quick_report):
    out, _ = quick_report
    sec = (out / "report.md").read_text(encoding="utf-8").split(HEADINGS["e"])[1].split("\n## ")[0]
    assert "Skipped in `--quick`" in sec
    for span in (20, 40):
        assert f"`python -m exudyn_wheelrail rtri --span {span} --out DIR`" in sec


def test_section_a_numbers_within_1p5_percent_of_table_e3(quick_report):
    out, _ = quick_report
    text = (out / "report.md").read_text(encoding="utf-8")
    sec = text.split(HEADINGS["a"])[1].split("\n## ")[0]
    rows = {}
    for line in sec.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 10 and re.fullmatch(r"[0-9.]+", cells[0]):
            rows[float(cells[0])] = [float(cells[i]) for i in (1, 4, 7)]     # the solver's C11, C22, C23
    assert sorted(rows) == sorted(A_RATIOS)
    for ab, got in rows.items():
        ref = kalker_coefficients(ab, 0.28)
        for g, c in zip(got, ref):
            assert g == pytest.approx(c, rel=TOL), (ab, g, c)


def test_klingel_figure_draws_simulation_and_reference_on_the_same_scale(quick_report):
    """The figure's y axis is in mm; both curves start at the released offset Y0_C (the state at t = 0 and the
    reference's y0 cos(0)), and the simulated oscillation has the reference's amplitude.

    Tolerance of the amplitude ratio, 10 %: Klingel's motion is the kinematic limit (no inertia, no creep) and
    keeps the released offset as its amplitude; the simulated wheelset loses a few per cent of it in the release
    transient (a fast, creep-damped lateral oscillation in the first ~50 ms) and oscillates with the wavelength
    the inertia and creep give it (within TOL_C = 2 % of Klingel's): the half-cycle peaks stay within 2–3 % of y0.
    10 % leaves margin for that; a unit slip between the curves is a factor of 10 or more."""
    _, figures = quick_report
    (ax,) = figures["klingel.png"]
    assert "[mm]" in ax["ylabel"] and "[m]" in ax["xlabel"]
    lines = {ln["gid"]: ln for ln in ax["lines"]}
    sim, ref = lines["simulated"], lines["klingel"]
    np.testing.assert_array_equal(sim["x"], ref["x"])  # both drawn over the same distance array: exact
    y0_mm = Y0_C * 1e3
    assert sim["y"][0] == pytest.approx(y0_mm, rel=1e-9)          # the released state, at s = 0
    assert ref["y"][0] == pytest.approx(y0_mm, rel=1e-12)
    assert np.max(np.abs(ref["y"])) == pytest.approx(y0_mm, rel=1e-12)
    # amplitude after the first half wavelength (past the release transient) against the reference's; the
    # reference's first zero crossing is at a quarter wavelength
    s = sim["x"]
    later = s > 2.0 * s[np.argmax(ref["y"] < 0.0)]
    assert later.sum() > 0.5 * s.size
    ratio = np.max(np.abs(sim["y"][later])) / np.max(np.abs(ref["y"][later]))
    assert 0.9 < ratio < 1.1, ratio


# ------------------------------------------------------------------------------------------------- section (e)
@pytest.fixture(scope="module")
def report_e(tmp_path_factory):
    out = tmp_path_factory.mktemp("validation_report_e")
    lines, res = section_e(out, quick=False)
    return "\n".join(lines), res


def _row(text, first_cell):
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells and cells[0] == first_cell:
            return cells
    raise AssertionError(f"no table row {first_cell!r}")


def test_section_e_states_the_window_of_the_runs_it_made(report_e):
    text, res = report_e
    runs = res["runs"]
    for col, span in ((1, 20.0), (2, 40.0)):
        r = runs[span]
        t = r.timeseries["time_s"]
        solver, dt_ms, steps = (c.strip() for c in _row(text, "solver, Δt [ms], steps")[col].split(","))
        assert solver == r.case.run.solver == r.summary["solver"]["name"]
        assert float(dt_ms) * 1e-3 == pytest.approx(float(np.mean(np.diff(t))), rel=1e-9)
        assert int(steps) == len(t) - 1                                 # n steps: the states at 0 … n dt
        t0, t1 = (float(x) for x in _row(text, "simulated window [s]")[col].split("…"))
        assert t0 == t[0] and t1 == pytest.approx(t[-1], abs=5e-4)      # printed to 1 ms
        p0, p1 = (float(x) for x in _row(text, "peak window [s]")[col].split("…"))
        assert p0 == t[0]
        # the tabulated peaks are the maxima of the recorded series over the stated window (printed precision)
        inside = t <= p1 + 5e-4
        acc = float(_row(text, "max car-body lat. acc., rear [m/s²]")[col])
        a_max = np.max(np.abs(r.timeseries["carbody_lateral_acceleration_rear_m_s2"][inside]))
        assert acc == pytest.approx(a_max, abs=5e-4)
        y = float(_row(text, "max abs(Y) wheelset 1, right wheel [kN]")[col])
        assert y == pytest.approx(np.max(np.abs(r.timeseries["lateral_contact_force_w1_right_N"][inside])) / 1e3,
                                  abs=5e-3)
    # the peak window ends after the acceleration peak of the 20 m run (the report once ended its runs before it)
    r20 = runs[20.0]
    p1 = float(_row(text, "peak window [s]")[1].split("…")[1])
    assert r20.summary["peaks_passage"]["time_of_max_carbody_acceleration_s"] < p1
    assert "**Peaks over the passage window**" in text


def test_section_e_runs_are_the_rtri_commands_cases(report_e, monkeypatch, tmp_path):
    """The case the ``rtri`` command builds for the span the report names (its run intercepted) is the report's
    case; so are the runs' peaks the ones the command prints (its ``peaks_passage``)."""
    text, res = report_e
    import exudyn_wheelrail.scenarios.rtri as rtri_module
    built = []

    class Intercepted(Exception):
        pass

    def fake_run(case, **kwargs):
        built.append(case)
        raise Intercepted

    monkeypatch.setattr(rtri_module, "run_rtri", fake_run)
    for span in (20, 40):
        cmd = _row(text, "the same run")[1 if span == 20 else 2].strip("`").split()
        assert cmd[:3] == ["python", "-m", "exudyn_wheelrail"]
        args = [str(tmp_path) if a == "DIR" else a for a in cmd[3:]]
        with pytest.raises(Intercepted), contextlib.redirect_stdout(io.StringIO()):
            cli_main(args)
        assert built[-1] == rtri_report_case(span) == res["runs"][float(span)].case
    p20 = res["runs"][20.0].summary["peaks_passage"]
    assert float(_row(text, "max car-body lat. acc., rear [m/s²]")[1]) == pytest.approx(
        p20["max_abs_carbody_lateral_acceleration_rear_m_s2"], abs=5e-4)
