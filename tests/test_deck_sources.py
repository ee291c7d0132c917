"""The bridge crossing's decks besides a chain of simply supported spans: a deck continuous over its intermediate
supports and a deck given by a modes file from an FE program (exudyn_wheelrail/structures/modes_file.py) — against
the two-span beam's closed-form modes, an independent modal solution of a moving load, and the built-in beam fed
through a modes file."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from exudyn_wheelrail.scenarios.bridge_crossing import BridgeCrossing, deck_modes, run_bridge_crossing
from exudyn_wheelrail.structures.load_models import AxleTrain, hslm_a
from exudyn_wheelrail.structures.modes_file import read_modes_file, write_modes_npz
from exudyn_wheelrail.validation import InputWarning

L, MASS, F1, ZETA = 20.0, 15.0e3, 5.0, 0.01
EI = MASS * (2.0 * L * L * F1 / math.pi) ** 2


def _clamped_pinned_roots(n):
    """β_k L of tan βL = tanh βL (a span pinned at one end, clamped at the other), k = 1 … n: the roots lie just
    below (k + 1/4) π."""
    return [brentq(lambda b: math.tan(b) - math.tanh(b), (k + 0.25) * math.pi - 0.3, (k + 0.25) * math.pi + 0.1)
            for k in range(1, n + 1)]


def _two_span_modes(n):
    """The 2n lowest vertical modes of a beam continuous over two equal spans (x from the first abutment): the
    antisymmetric ones are the simply supported span's, ``sin(kπx/L)``; the symmetric ones have zero slope over the
    middle support, each span a pinned–clamped beam ``sin βy − (sin βL/sinh βL) sinh βy`` (y from the outer
    support).  ``(ω, φ)`` pairs."""
    c = math.sqrt(EI / MASS)
    modes = [((k * math.pi / L) ** 2 * c, lambda x, k=k: np.sin(k * math.pi * np.asarray(x) / L))
             for k in range(1, n + 1)]
    for bl in _clamped_pinned_roots(n):
        b = bl / L

        def phi(x, b=b, bl=bl):
            x = np.asarray(x, dtype=float)
            y = np.where(x <= L, x, 2.0 * L - x)
            return np.sin(b * y) - math.sin(bl) / math.sinh(bl) * np.sinh(b * y)
        modes.append((b * b * c, phi))
    return sorted(modes, key=lambda p: p[0])


def test_a_two_span_continuous_deck_has_the_simply_supported_and_the_pinned_clamped_frequencies():
    case = BridgeCrossing(span_m=L, mass_kg_m=MASS, f1_Hz=F1, damping_ratio=ZETA, n_modes=3, axles=hslm_a("A1"),
                          speed_m_s=50.0, spans_m=(L, L), continuous=True)
    deck = deck_modes(case)
    f_fe = deck.modes.frequencies_Hz
    f_exact = np.array([w / (2.0 * math.pi) for w, _ in _two_span_modes(3)])
    # the Hermite beam element's frequencies lie above the exact ones by ~(β h)^4/720-ish: 3e-5 for the 3rd simply
    # supported mode at 20 elements per span (bridge.py); 24 elements per span here: 1e-4 bounds it
    assert f_fe.shape == (6,)
    np.testing.assert_allclose(f_fe, f_exact, rtol=1e-4)
    assert np.all(f_fe >= f_exact * (1 - 1e-12))                    # a conforming element: from above
    # the time step's highest frequency bounds the deck's highest kept mode (clamped–clamped band bound)
    assert case.f_N_Hz >= f_fe[-1]
    assert deck.f1_Hz == (pytest.approx(F1, rel=1e-5),) * 2
    # EN 1990's cut-off: max(30 Hz, 1.5 f1, f3) with the deck's own f1 and f3 (the third mode: 20 Hz)
    assert deck.cutoffs_Hz[0] == pytest.approx(max(30.0, 1.5 * f_fe[0], f_fe[2]))
    assert deck.reaches_cutoff(0)


def _modal_reference(modes, P, V, t, x_probe):
    """An independent modal solution of a constant force P moving at V over the two-span deck: every mode's
    ``q̈ + 2ζω q̇ + ω² q = P φ(Vt)/M_n`` (``M_n = m ∫ φ²``) integrated by SciPy's DOP853 at tight tolerances;
    the displacement and acceleration at ``x_probe``."""
    xs = np.linspace(0.0, 2.0 * L, 40001)
    w_sum, a_sum = np.zeros_like(t), np.zeros_like(t)
    for w, phi in modes:
        Mn = MASS * np.trapezoid(phi(xs) ** 2, xs)

        def load(tt, phi=phi, Mn=Mn):
            return P * phi(V * tt) / Mn if V * tt <= 2.0 * L else 0.0

        def rhs(tt, y, w=w, load=load):
            return [y[1], load(tt) - 2.0 * ZETA * w * y[1] - w * w * y[0]]
        sol = solve_ivp(rhs, (0.0, t[-1]), [0.0, 0.0], t_eval=t, method="DOP853", rtol=1e-11, atol=1e-16,
                        max_step=(t[-1]) / 2000)
        q, qd = sol.y
        qdd = np.array([load(tt) for tt in t]) - 2.0 * ZETA * w * qd - w * w * q
        w_sum += phi(x_probe) * q
        a_sum += phi(x_probe) * qdd
    return w_sum, a_sum


def test_a_moving_load_over_a_continuous_deck_equals_an_independent_modal_solution():
    P, V = 1.0e5, 200.0 / 3.6
    case = BridgeCrossing(span_m=L, mass_kg_m=MASS, f1_Hz=F1, damping_ratio=ZETA, n_modes=3,
                          axles=AxleTrain(np.array([0.0]), np.array([P])), speed_m_s=V, spans_m=(L, L),
                          continuous=True)
    res = run_bridge_crossing(case)
    assert res.summary["status"] == "ok"
    ts = res.timeseries
    t = np.asarray(ts["time_s"])
    w_ref, a_ref = _modal_reference(_two_span_modes(3), P, V, t, 0.5 * L)
    w, a = np.asarray(ts["deck_midspan_displacement_m"]), np.asarray(ts["deck_midspan_acceleration_m_s2"])
    # the same six modes: the differences are the FE frequencies (<= 2e-5 high: a phase drift of 2π Δf t <= 5e-3
    # rad of the highest mode over the 0.72 s run) and RK44's error (1e-5); the target is 1 % of the peak
    assert np.max(np.abs(w)) == pytest.approx(np.max(np.abs(w_ref)), rel=1e-3)
    assert np.max(np.abs(a)) == pytest.approx(np.max(np.abs(a_ref)), rel=5e-3)
    assert np.max(np.abs(w - w_ref)) <= 1e-2 * np.max(np.abs(w_ref))
    assert np.max(np.abs(a - a_ref)) <= 1e-2 * np.max(np.abs(a_ref))
    # the second span's middle moves up while the load is on the first (the continuity over the support)
    span2 = np.asarray(ts["deck_span2_midspan_displacement_m"])
    on_first = V * t < L
    assert np.min(span2[on_first]) < -0.05 * np.max(np.abs(w))


def _beam_case(**kw):
    base = dict(span_m=L, mass_kg_m=MASS, f1_Hz=F1, damping_ratio=ZETA, n_modes=3, axles=hslm_a("A1"),
                speed_m_s=250.0 / 3.6)
    return BridgeCrossing(**{**base, **kw})


def _export(modes, x_deck, path, scale=1.0, fmt="npz"):
    """The built-in deck's vertical modes as an FE program would export them: the track axis's vertical displacement
    at ``x_deck``, each shape times ``scale`` (its modal mass then ``scale²``, the shapes being mass-normalised)."""
    phi = modes.shape_at(x_deck)[:, 1, :].T * scale
    data = dict(frequency_hz=modes.frequencies_Hz, modal_mass_kg=np.full(modes.n_modes, scale ** 2), x_m=x_deck,
                vertical=phi)
    if fmt == "npz":
        return write_modes_npz(path, **data)
    rows = ["mode,frequency_hz,modal_mass_kg,x_m,vertical"]
    for j in range(modes.n_modes):
        rows += [f"{j + 1},{float(data['frequency_hz'][j])!r},{float(data['modal_mass_kg'][j])!r},{float(x)!r},"
                 f"{float(v)!r}" for x, v in zip(x_deck, phi[j])]
    path.write_text("\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("spans", [(L,), (L, 15.0)])
def test_the_modes_file_path_reproduces_the_built_in_beam(tmp_path, spans):
    beam = _beam_case(spans_m=spans if len(spans) > 1 else None)
    modes = deck_modes(beam).modes
    # positions every L/200 (a chain: its joint twice, the first value ending the span before)
    x = np.concatenate([np.linspace(0.0, spans[0], 201)] + ([spans[0] + np.linspace(0.0, spans[1], 161)]
                                                           if len(spans) > 1 else []))
    npz = _export(modes, x, tmp_path / "deck.npz", scale=7.0)
    csv = _export(modes, x, tmp_path / "deck.csv", scale=7.0, fmt="csv")
    ref = run_bridge_crossing(beam)
    by_npz = run_bridge_crossing(_beam_case(mass_kg_m=None, f1_Hz=None, n_modes=modes.n_modes, modes_file=str(npz),
                                            spans_m=beam.spans_m))
    by_csv = run_bridge_crossing(_beam_case(mass_kg_m=None, f1_Hz=None, n_modes=modes.n_modes, modes_file=str(csv),
                                            spans_m=beam.spans_m))
    assert by_npz.summary["deck"]["kind"] == "modes file"
    # the splines between positions h = L/200 apart differ from the element's cubics by ~(5/384)(kh)^4 of a mode's
    # amplitude, kh = 3π/200 for the third mode: 6e-8; the same frequencies and the same step: the deck's columns
    # agree to 1e-6 of their peaks
    for col in ("deck_midspan_displacement_m", "deck_midspan_acceleration_m_s2",
                "deck_en1990_max_abs_acceleration_m_s2", "deck_acceleration_p3_m_s2",
                "deck_support_rotation_start_rad", "deck_support_rotation_end_rad"):
        a, b = np.asarray(ref.timeseries[col]), np.asarray(by_npz.timeseries[col])
        assert a.shape == b.shape
        assert np.max(np.abs(a - b)) <= 1e-6 * np.max(np.abs(a)), col
        # CSV and NPZ hold the same numbers (repr round-trips): the same code path, the same bits
        np.testing.assert_array_equal(b, np.asarray(by_csv.timeseries[col]))
    # the quasi-static deflection of the modes kept against the simply supported span's influence line: the three
    # modes' truncation of sum 1/n^4 (the 5th mode's 1/625 and the rest), 0.2 % at most
    qs_ref, qs = ref.summary["quasi_static"], by_npz.summary["quasi_static"]
    assert qs["max_midspan_displacement_m"] == pytest.approx(qs_ref["max_midspan_displacement_m"], rel=3e-3)


def test_a_mass_bound_scales_the_files_modes_like_the_deck_mass(tmp_path):
    beam = _beam_case()
    x = np.linspace(0.0, L, 201)
    npz = _export(deck_modes(beam).modes, x, tmp_path / "deck.npz")
    r = 1.2                                                       # the upper bound: 20 % more mass
    heavy = _beam_case(mass_kg_m=r * MASS, f1_Hz=F1 / math.sqrt(r))  # the same EI: f1 / sqrt(r)
    scaled = _beam_case(mass_kg_m=r * MASS, f1_Hz=None, modes_file=str(npz), mass_scale=r)
    assert scaled.f1_Hz == pytest.approx(heavy.f1_Hz, rel=1e-5)
    a, b = run_bridge_crossing(heavy).summary, run_bridge_crossing(scaled).summary
    for key in ("max_abs_deck_midspan_displacement_m", "max_abs_deck_midspan_acceleration_m_s2"):
        assert b[key] == pytest.approx(a[key], rel=1e-4), key


def _write(tmp_path, name, **data):
    return write_modes_npz(tmp_path / name, **data)


@pytest.mark.parametrize("change, message", [
    (dict(vertical=np.zeros((2, 4))), r"vertical: shape \(2, 4\) disagrees with 2 modes \(frequency_hz\) x 5"),
    (dict(modal_mass_kg=np.array([1.0, -3.0])), "modal_mass_kg: -3: a modal mass must be > 0"),
    (dict(frequency_hz=np.array([2.0, 0.0])), "frequency_hz: 0: a natural frequency must be > 0"),
    (dict(x_m=np.array([0.0, 5.0, 4.0, 15.0, 20.0])), "x_m: 4 after 5: the positions must increase"),
    (dict(damping_ratio=np.array([0.02, 2.0])), "damping_ratio: 2: expected 0 <= ζ < 1"),
])
def test_a_bad_modes_file_is_one_line_naming_the_file_and_key(tmp_path, change, message):
    x = np.linspace(0.0, L, 5)
    good = dict(frequency_hz=np.array([5.0, 20.0]), modal_mass_kg=np.array([1.5e5, 1.5e5]), x_m=x,
                vertical=np.vstack([np.sin(np.pi * x / L), np.sin(2 * np.pi * x / L)]))
    path = _write(tmp_path, "bad.npz", **{**good, **change})
    with pytest.raises(ValueError, match=message) as info:
        read_modes_file(path)
    assert str(info.value).startswith(str(path)) and "\n" not in str(info.value)


def test_a_csv_modes_file_with_an_unknown_column_or_mismatched_positions_is_refused(tmp_path):
    p = tmp_path / "m.csv"
    p.write_text("mode,frequency_hz,modal_mass_kg,x_m,vertical,vertcal\n1,5,1,0,0,0\n")
    with pytest.raises(ValueError, match="vertcal: unknown column"):
        read_modes_file(p)
    p.write_text("mode,frequency_hz,modal_mass_kg,x_m,vertical\n1,5,1,0,0\n1,5,1,20,0\n2,20,1,0,0\n2,20,1,10,0\n")
    with pytest.raises(ValueError, match="x_m: mode 2 has other positions"):
        read_modes_file(p)
    p.write_text("mode,frequency_hz,modal_mass_kg,x_m,vertical\n1,5,1,0,0\n1,6,1,20,0\n")
    with pytest.raises(ValueError, match="frequency_hz: mode 1 has 2 different values"):
        read_modes_file(p)


def test_a_mode_with_a_zero_shape_and_positions_short_of_the_deck_are_warnings(tmp_path):
    x = np.linspace(0.0, 15.0, 16)
    path = _write(tmp_path, "short.npz", frequency_hz=np.array([5.0, 9.0]), modal_mass_kg=np.array([1e5, 1e5]),
                  x_m=x, vertical=np.vstack([np.sin(np.pi * x / 15.0), np.zeros_like(x)]))
    with pytest.warns(InputWarning, match="mode 2 .* has a zero shape"):
        read_modes_file(path)
    with pytest.warns(InputWarning, match="the shapes are zero outside them"):
        deck_modes(_beam_case(mass_kg_m=None, f1_Hz=None, n_modes=2, modes_file=str(path)))


def test_a_scenario_file_runs_a_continuous_deck_and_a_modes_file_as_the_command(tmp_path):
    from exudyn_wheelrail.cli import main
    beam = _beam_case()
    _export(deck_modes(beam).modes, np.linspace(0.0, L, 101), tmp_path / "deck.csv", fmt="csv")
    decks = {"continuous": ("spans_m = [20.0, 20.0]\ncontinuous = true\nmass_kg_m = 15000.0\nf1_Hz = 5.0\n"
                            "damping_ratio = 0.01\n",
                            ["--n-spans", "2", "--continuous", "--bridge-mass-kg-per-m", "15000",
                             "--bridge-frequency-hz", "5", "--damping-ratio", "0.01"]),
             "file": ("spans_m = [20.0]\nmodes_file = 'deck.csv'\ndamping_ratio = 0.01\n",
                      ["--modes-file", str(tmp_path / "deck.csv"), "--damping-ratio", "0.01"])}
    for name, (structure, options) in decks.items():
        f = tmp_path / f"{name}.toml"
        f.write_text("schema_version = 2\n[scenario]\nname = 'x'\n[vehicle]\nload_model = 'moving-loads'\n"
                     "hslm = 'A1'\nspeed_km_h = 300.0\n[structure]\n" + structure + "modes = 3\n")
        assert main(["run", str(f), "--out", str(tmp_path / f"run_{name}")]) == 0
        assert main(["bridge-crossing", "--span-m", "20", "--modes", "3", "--hslm", "A1", "--speed-kmh", "300",
                     "--out", str(tmp_path / f"cmd_{name}")] + options) == 0
        # the same case on the one path: the same numbers
        a = (tmp_path / f"run_{name}" / "timeseries.csv").read_bytes()
        assert a == (tmp_path / f"cmd_{name}" / "timeseries.csv").read_bytes()
    bad = tmp_path / "bad.toml"
    bad.write_text("schema_version = 2\n[scenario]\nname = 'x'\n[vehicle]\nload_model = 'moving-loads'\n"
                   "hslm = 'A1'\nspeed_km_h = 300.0\n[structure]\nspans_m = [20.0]\nmodes_file = 'none.csv'\n"
                   "modes = 3\ndamping_ratio = 0.01\n")
    assert main(["run", str(bad), "--out", str(tmp_path / "bad")]) == 2


@pytest.mark.parametrize("model", ["sprung-masses", "vehicles"])
def test_a_modes_files_deck_carries_every_load_model_as_the_built_in_beam(tmp_path, model):
    from pathlib import Path
    consist = str(Path(__file__).resolve().parents[1] / "vehicles" / "trains" / "manchester_x2.toml")
    train = dict(axles=hslm_a("A1"), speed_m_s=250.0 / 3.6) if model == "sprung-masses" else \
        dict(axles=None, speed_m_s=40.0, train_file=consist)
    beam = _beam_case(model=model, **train)
    npz = _export(deck_modes(beam).modes, np.linspace(0.0, L, 201), tmp_path / "deck.npz")
    by_file = _beam_case(model=model, mass_kg_m=None, f1_Hz=None, modes_file=str(npz), **train)
    a, b = run_bridge_crossing(beam), run_bridge_crossing(by_file)
    assert a.summary["status"] == b.summary["status"] == "ok"
    assert a.summary["steps"] == b.summary["steps"]
    # the same deck to ~1e-7 of a mode's amplitude, its slopes to ~(kh)³/24 = 4e-6 (kh = 3π/200, the splines
    # against the element's cubics): the rails under the wheels move by the slopes too (V dφ/dx q), and the
    # vehicles' Hertz contacts pass that on to the deck's acceleration — measured 1.4e-5 of its peak: 1e-4 holds it
    # with margin, and a wrong normalisation or shape (percent level) does not pass
    for col in ("deck_midspan_displacement_m", "deck_midspan_acceleration_m_s2"):
        x, y = np.asarray(a.timeseries[col]), np.asarray(b.timeseries[col])
        assert np.max(np.abs(x - y)) <= 1e-4 * np.max(np.abs(x)), col


def test_with_fewer_than_three_vertical_modes_kept_the_cutoff_is_the_whole_decks_and_not_reached(tmp_path):
    # 2 x 10 m continuous, f1 = 20 Hz, one mode per span: 20 and 31.2 Hz kept; the deck's f3 (80 Hz) sets the
    # cut-off, which the two modes do not reach
    case = BridgeCrossing(span_m=10.0, mass_kg_m=MASS, f1_Hz=20.0, damping_ratio=ZETA, n_modes=1, axles=hslm_a("A1"),
                          speed_m_s=50.0, spans_m=(10.0, 10.0), continuous=True)
    deck = deck_modes(case)
    assert deck.modes.frequencies_Hz[-1] < 40.0
    assert deck.cutoffs_Hz[0] == pytest.approx(80.0, rel=1e-3) and not deck.reaches_cutoff(0)
    # a modes file with 10, 40, 90 Hz keeping two: the cut-off is the file's f3 = 90 Hz, not reached
    x = np.linspace(0.0, L, 101)
    npz = _write(tmp_path, "three.npz", frequency_hz=np.array([10.0, 40.0, 90.0]), modal_mass_kg=np.full(3, 1e5),
                 x_m=x, vertical=np.vstack([np.sin(k * np.pi * x / L) for k in (1, 2, 3)]))
    kept = deck_modes(_beam_case(mass_kg_m=None, f1_Hz=None, n_modes=2, modes_file=str(npz)))
    assert kept.cutoffs_Hz[0] == pytest.approx(90.0) and not kept.reaches_cutoff(0)
    assert deck_modes(_beam_case(mass_kg_m=None, f1_Hz=None, n_modes=3, modes_file=str(npz))).reaches_cutoff(0)


def test_supports_match_positions_despite_the_spans_sum_rounding(tmp_path, recwarn):
    spans = (12.3, 12.3, 12.3, 12.3)                          # 36.900000000000006 m for the third support
    x = np.round(np.linspace(0.0, sum(spans), 121), 9)
    npz = _write(tmp_path, "four.npz", frequency_hz=np.array([5.0]), modal_mass_kg=np.array([1e5]), x_m=x,
                 vertical=np.abs(np.sin(np.pi * x / 12.3))[None, :])
    deck_modes(_beam_case(span_m=12.3, spans_m=spans, mass_kg_m=None, f1_Hz=None, n_modes=1, modes_file=str(npz)))
    assert not [w for w in recwarn if "not one of the positions" in str(w.message)]


@pytest.mark.parametrize("x, message", [
    ([0.0, 0.0, 10.0, 20.0], "x_m: 0 given twice at an end"),
    ([0.0, 10.0, 20.0, 20.0], "x_m: 20 given twice at an end"),
])
def test_a_position_twice_at_an_end_is_refused(tmp_path, x, message):
    x = np.array(x)
    path = _write(tmp_path, "ends.npz", frequency_hz=np.array([5.0]), modal_mass_kg=np.array([1e5]), x_m=x,
                  vertical=np.sin(np.pi * x / 20.0)[None, :])
    with pytest.raises(ValueError, match=message):
        read_modes_file(path)


def test_kept_modes_without_a_vertical_one_are_refused_as_the_modes_count(tmp_path):
    x = np.linspace(0.0, L, 21)
    path = _write(tmp_path, "lat.npz", frequency_hz=np.array([3.0, 5.0]), modal_mass_kg=np.array([1e5, 1e5]),
                  x_m=x, vertical=np.vstack([np.zeros_like(x), np.sin(np.pi * x / L)]),
                  lateral=np.vstack([np.sin(np.pi * x / L), np.zeros_like(x)]))
    with pytest.raises(ValueError, match="n_modes: the 1 lowest modes of the modes file .* have no vertical mode"):
        _beam_case(mass_kg_m=None, f1_Hz=None, n_modes=1, modes_file=str(path))
    assert _beam_case(mass_kg_m=None, f1_Hz=None, n_modes=2, modes_file=str(path)).f1_Hz == 5.0
