"""The plots a user puts in a report: scenario plots (``plot_<group>.png`` of ``python -m exudyn_wheelrail run``) and
the RTRI Figs. 5–7.  Read from the drawn figures (line data and labels), checked against independent references:

* units: every drawn series is its recorded column (SI) converted to the unit its axis label names, by a
  conversion table written here;
* names: every wheel's line is named ``wheelset j, side`` (j from 1 = leading), no line carries a column name;
* limits: the limit lines are the limits the run's criteria applied (set here to values that are not the defaults),
  the wheel-unloading limit drawn as the wheel load (1 − limit) Q₀ it allows with Q₀ = the vehicle's weight over its
  eight wheels (the Manchester car is symmetric), Prud'homme's as α (10 kN + 2 Q₀/3) written out here;
* the EN 14363 curves drawn reach the values the criteria assessed; the RTRI passage peaks are circled where the
  summary says they are.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from figure_capture import describe, saved_figures

from exudyn_wheelrail.analysis import safety
from exudyn_wheelrail.multibody import load_vehicle
from exudyn_wheelrail.scenarios.rtri import RtriCase, plot_fig5, plot_fig6, plot_fig7, run_rtri
from exudyn_wheelrail.scenarios.scenario import (
    apply_overrides,
    group_figure,
    load_scenario,
    run_scenario,
)

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "scenarios"

#: recorded column unit (from the column name's suffix) -> {unit named on the axis: factor}
UNITS = {"N": {"kN": 1e-3, "N": 1.0}, "m": {"mm": 1e3, "m": 1.0}, "m_s2": {"m/s²": 1.0}, "": {"-": 1.0}}
YQ_LIMIT, UNLOADING_LIMIT = 0.75, 0.5            # not the defaults: the plot must draw what the run applied


def _column_unit(column: str) -> str:
    for suffix in ("_m_s2", "_N", "_m"):
        if column.endswith(suffix):
            return suffix[1:]
    return ""


def _axis_unit(label: str) -> str:
    m = re.search(r"\[([^\]]+)\]", label)
    assert m, f"no unit in the axis label {label!r}"
    return m.group(1)


@pytest.fixture(scope="module")
def rtri_scenario():
    """rtri_20m.toml over 0.8 s (the leading bogie through the span) with non-default criteria limits."""
    scn = apply_overrides(load_scenario(EXAMPLES / "rtri_20m.toml"),
                          {"run.duration_s": 0.8, "outputs.criteria.yq_limit": YQ_LIMIT,
                           "outputs.criteria.unloading_limit": UNLOADING_LIMIT})
    r = run_scenario(scn, None, progress=False)
    assert r.summary["status"] == "ok" and "verdicts" in r.summary["criteria"]
    return r


@pytest.fixture(scope="module")
def bridge_scenario():
    scn = apply_overrides(load_scenario(EXAMPLES / "bridge_40m.toml"), {"run.duration_s": 0.3})
    r = run_scenario(scn, None, progress=False)
    assert r.summary["status"] == "ok"
    return r


def _figures(result):
    out = {}
    for g in result.summary["scenario"]["outputs"]["timeseries"]:
        if g == "flange":
            continue
        fig, _ = group_figure(result, g)
        out[g] = describe(fig)
        import matplotlib.pyplot as plt          # after group_figure has chosen the backend
        plt.close(fig)
    return out


@pytest.fixture(scope="module")
def figures(rtri_scenario, bridge_scenario):
    return {"rtri": _figures(rtri_scenario), "bridge": _figures(bridge_scenario)}


def _series_lines(axes):
    """(axes description, line) of every drawn time series (limit lines and legend-only entries left out)."""
    for ax in axes:
        for ln in ax["lines"]:
            if ln["x"].size > 2 and not (ln["gid"] or "").startswith(("limit:", "static", "yq2m:")):
                yield ax, ln


@pytest.mark.parametrize("case", ["rtri", "bridge"])
def test_every_series_is_a_recorded_column_in_the_unit_of_its_axis(case, figures, rtri_scenario, bridge_scenario):
    result = {"rtri": rtri_scenario, "bridge": bridge_scenario}[case]
    ts = result.timeseries
    t = ts["time_s"]
    checked = 0
    for group, axes in figures[case].items():
        assert axes[-1]["xlabel"] == "time [s]", group
        for ax in axes:
            _axis_unit(ax["ylabel"])
        for ax, ln in _series_lines(axes):
            # a series drawn against the time column holds it unchanged: exact
            if not np.array_equal(ln["x"], t):
                continue                                   # a derived series (ΣY₂ₘ at window centres)
            unit = _axis_unit(ax["ylabel"])
            matches = [c for c in result.summary["columns"][group]
                       if unit in UNITS[_column_unit(c)] and np.allclose(
                           ln["y"], ts[c] * UNITS[_column_unit(c)][unit], rtol=1e-12, atol=0.0, equal_nan=True)]
            assert matches, (group, ln["label"], ax["ylabel"])
            checked += 1
    assert checked >= 20


def test_wheel_lines_are_named_by_wheelset_and_side(figures, rtri_scenario):
    cols = rtri_scenario.summary["columns"]
    for group in ("Y", "Q", "YQ"):
        labels = [ln["label"] for ax, ln in _series_lines(figures["rtri"][group])]
        for c in cols[group]:
            j, side = re.search(r"_w(\d+)_(right|left)", c).groups()
            assert any(lab.startswith(f"wheelset {j}, {side}") for lab in labels), (group, c)
    for group, axes in figures["rtri"].items():
        for ax in axes:
            for text in ax["legend"]:
                assert not re.search(r"_w\d|_N\b|_m_s2|^_", text), (group, text)
                assert "wheelset 0" not in text
    # what right and left mean is said on the figure
    assert any("running direction" in ax["title"] or "running direction" in ax["ylabel"]
               for ax in figures["rtri"]["wheelset_lateral"])


def _limit(axes, gid):
    values = {float(v) for ax in axes for ln in ax["lines"] if ln["gid"] == gid for v in ln["y"]}
    assert values, f"no line {gid}"
    return values


def test_limit_lines_are_the_limits_the_run_applied(figures, rtri_scenario):
    s = rtri_scenario.summary
    assert s["criteria"]["inputs"]["yq_limit_en14363"] == YQ_LIMIT
    assert s["criteria"]["inputs"]["unloading_limit"] == UNLOADING_LIMIT
    f = figures["rtri"]
    q0 = load_vehicle("manchester_vehicle1").total_mass_kg * 9.81 / 8
    assert _limit(f["YQ"], "limit:yq_en14363") == {YQ_LIMIT}
    assert _limit(f["YQ"], "limit:yq_jnr") == {safety.JNR_YQ_LIMIT}
    (q_lim,) = _limit(f["Q"], "limit:wheel_unloading")
    assert q_lim == pytest.approx((1.0 - UNLOADING_LIMIT) * q0 * 1e-3, rel=1e-9)          # kN, as the axis
    assert "[kN]" in f["Q"][0]["ylabel"]
    alpha = 1.0                                           # EN 14363, passenger coach (the scenario's vehicle class)
    lim_kN = alpha * (10.0 + 2.0 * q0 * 1e-3 / 3.0)
    assert sorted(_limit(f["Y"], "limit:prudhomme")) == pytest.approx([-lim_kN, lim_kN], rel=1e-9)
    legends = " ".join(t for ax in f["YQ"] for t in ax["legend"])
    assert f"EN 14363 limit on (Y/Q)₂ₘ: {YQ_LIMIT:g}" in legends


def test_en14363_curves_reach_the_assessed_values(figures, rtri_scenario):
    crit = rtri_scenario.summary["criteria"]["criteria"]
    drawn = {ln["gid"][len("yq2m:"):]: np.nanmax(ln["y"]) for ax in figures["rtri"]["YQ"] for ln in ax["lines"]
             if (ln["gid"] or "").startswith("yq2m:")}
    assert sorted(drawn) == sorted(crit["derailment_quotient_en14363"])
    for key, v in crit["derailment_quotient_en14363"].items():
        assert drawn[key] == pytest.approx(v["value"], rel=1e-12), key
    sum_y = [ln for ln in figures["rtri"]["Y"][-1]["lines"] if ln["label"].startswith("wheelset ")]
    for ln in sum_y:
        j = ln["label"].split()[1]
        assert np.max(np.abs(ln["y"])) * 1e3 == pytest.approx(crit["track_shift_force_prudhomme"][f"ws{j}"]["value"],
                                                              rel=1e-12)


def test_carbody_plot_states_the_comfort_results(figures, rtri_scenario):
    crit = rtri_scenario.summary["criteria"]["criteria"]
    for ax, direction in zip(figures["rtri"]["carbody"], ("lateral", "vertical")):
        assert ax["ylabel"] == f"{direction} acceleration [m/s²]"
        legend = " ".join(ax["legend"])
        assert f"Sperling Wz = {crit[f'sperling_{direction}']['Wz']:.2f}" in legend
        assert f"peak {crit[f'carbody_{direction}']['peak_m_s2']:.3f} m/s²" in legend


# --------------------------------------------------------------------------------------------------- RTRI figures
@pytest.fixture(scope="module")
def rtri_run():
    """Newmark 1 ms over 0.75 s: the car-body acceleration peak of the 20 m case (~0.70 s) is inside."""
    return run_rtri(RtriCase(span_m=20.0, duration_s=0.75))


def test_rtri_figures_circle_the_passage_peaks(rtri_run, monkeypatch, tmp_path):
    p = rtri_run.summary["peaks_passage"]
    with saved_figures(monkeypatch) as figs:
        plot_fig5(rtri_run, tmp_path / "fig5.png")
        plot_fig6(rtri_run, tmp_path / "fig6.png")
    (ax5,) = figs["fig5.png"]
    (peak5,) = [ln for ln in ax5["lines"] if ln["gid"] == "passage_peak"]
    assert peak5["x"][0] == pytest.approx(p["time_of_max_carbody_acceleration_s"], abs=1e-12)
    assert abs(peak5["y"][0]) == pytest.approx(p["max_abs_carbody_lateral_acceleration_rear_m_s2"], rel=1e-12)
    assert "[m/s²]" in ax5["ylabel"]
    (ax6,) = figs["fig6.png"]
    (peak6,) = [ln for ln in ax6["lines"] if ln["gid"] == "passage_peak"]
    assert abs(peak6["y"][0]) * 1e3 == pytest.approx(p["max_abs_lateral_contact_force_w1_right_10ms_avg_N"],
                                                     rel=1e-9)
    assert "[kN]" in ax6["ylabel"] and "wheelset 1" in ax6["ylabel"]
    raw = [ln for ln in ax6["lines"] if ln["label"].startswith("rail on wheel")][0]
    np.testing.assert_allclose(raw["y"], rtri_run.timeseries["lateral_contact_force_w1_right_N"] * 1e-3, rtol=1e-12)


def test_fig7_names_the_wheel_of_the_flange_contact(monkeypatch, tmp_path):
    """A flange contact in the second span's cases only: the legend names it all the same."""
    rows = [dict(span_m=L, speed_km_h=v, status="ok", max_abs_carbody_lateral_acceleration_rear_m_s2=a,
                 flange_contact_w1_right=f) for L, v, a, f in [(20.0, 200.0, 0.8, False), (20.0, 250.0, 1.3, False),
                                                                (40.0, 200.0, 0.5, False), (40.0, 250.0, 0.8, True)]]
    with saved_figures(monkeypatch) as figs:
        plot_fig7(rows, tmp_path / "fig7.png")
    (ax,) = figs["fig7.png"]
    assert "[m/s²]" in ax["ylabel"] and ax["xlabel"] == "speed [km/h]"
    assert "flange contact (wheelset 1, right wheel)" in ax["legend"]
    lines = {ln["label"]: ln for ln in ax["lines"]}
    np.testing.assert_array_equal(lines["L = 20 m"]["y"], [0.8, 1.3])  # the rows' values plotted unchanged: exact
