"""The track under the wheels over a bridge deck (exudyn_wheelrail/track/flexible_outputs.py) and the example
examples/train_on_ballasted_bridge.py: the under-wheel outputs against the full finite-element statics, the deck's
static deflection with the track layer against the bare span's, a short run of a train with and without the track
layer against static equilibrium and the track's load spreading, and the example's bad-input errors."""
from __future__ import annotations

import dataclasses
import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.structures import BridgeModel, DeckSection
from exudyn_wheelrail.track import TrackParameters
from exudyn_wheelrail.track.flexible_deck import TrackOnDeckModel
from exudyn_wheelrail.track.flexible_outputs import support_force_totals_N, track_under_wheels

ROOT = Path(__file__).resolve().parent.parent
PARAMS = TrackParameters.from_file()
B = PARAMS.rail_centre_distance_m
SPAN_M, DECK_START_M = 10.0, 0.0
#: a 10 m concrete span, 10 t/m, first bending frequency ~10 Hz
DECK_EI = 1.0e4 * (2.0 * SPAN_M ** 2 * 10.0 / math.pi) ** 2
#: the wheelset's wheel loads (left, right) [N]: unequal, so that the roll beam is loaded too
Q_LR = (60.0e3, 80.0e3)
#: the rails' lateral places over b/2 in the track frame of track/flexible.py (y right, z down, looking in the running
#: direction): the left rail at y = -b/2, the right at +b/2.  A roll theta about x moves a point at y by z = y theta
#: ((theta e_x) x (y e_y) = y theta e_z), so a rail's vertical motion is z + (+-b/2) theta.  Typed here from that
#: definition, not read from the package.
RAIL_Y_OVER_HALF_B = {"left": -1.0, "right": 1.0}
#: the support-force totals and their references (not per-point quantities)
TOTALS = ("ballast_total_N", "ballast_ground_N", "ballast_deck_N")


def _deck(damping_ratio: float = 0.01) -> BridgeModel:
    """The 10 m simply supported test deck (EI_z = 10 EI_y, GJ = EI_y), on which the track is laid."""
    sec = DeckSection(m_kg_m=1.0e4, EI_y_Nm2=DECK_EI, EI_z_Nm2=10 * DECK_EI, GJ_Nm2=DECK_EI, EA_N=1e3 * DECK_EI,
                      Ip_kgm2_m=4.0e4)
    return BridgeModel((SPAN_M,), sec, continuous=False, damping_ratio=damping_ratio, rail_height_m=0.0,
                       start_m=DECK_START_M, elements_per_span=20)


def _model():
    deck = _deck()
    return TrackOnDeckModel(PARAMS, -5.8, 22.2, deck, ballast_height_m=0.0)        # mid-span on a sleeper


@pytest.fixture(scope="module")
def full_statics():
    """The full finite-element statics (track beams and deck, no reduction) under one wheelset at each of three
    points: on the deck at mid-span over a sleeper, on the embankment over a sleeper and mid-bay; the load at a rail
    node (there the interface's roll row, linear between table points, and the rail's Hermite field coincide)."""
    mdl = _model()
    M, K, C, off = mdl.assemble_coupled()
    out = {}
    h = mdl.h_m
    for name, s in (("deck", DECK_START_M + 0.5 * SPAN_M), ("ground", -2.8), ("ground, mid-bay", -2.5)):
        i = int(round((s - mdl.start_m) / h))
        assert abs(mdl.start_m + i * h - s) < 1e-9
        f = np.zeros(K.shape[0])
        f[off["vertical"] + 2 * i] = sum(Q_LR)                     # F_z on the rails' centre line
        f[off["roll"] + 2 * i] = 0.5 * B * (Q_LR[1] - Q_LR[0])      # M_x: the right rail's excess
        u = np.linalg.solve(K, f)
        out[name] = (s, i, u)
    return mdl, off, out


def _reference(mdl, off, s, i, u):
    """The under-wheel quantities from the full DOF vector, by the model's definitions (pads between the rail over
    a sleeper and its seat, ballast halves under the seats on the ground or against the deck point under them)."""
    nn, ns = mdl.n_nodes, mdl.n_sleepers
    zv, zr = u[off["vertical"]:off["vertical"] + mdl.n_dof], u[off["roll"]:off["roll"] + mdl.n_dof]
    ud = u[off["deck"]:]
    j = int(round((s - mdl.start_m) / PARAMS.sleeper_spacing_m))
    n_sl = 2 * mdl.sleeper_node[j]
    ref = {}
    for side, sgn in RAIL_Y_OVER_HALF_B.items():
        ref[f"rail_z_{side}_m"] = zv[2 * i] + sgn * 0.5 * B * zr[2 * i]
        seat = zv[2 * nn + j] + sgn * 0.5 * B * zr[2 * nn + j]
        ref[f"sleeper_z_{side}_m"] = seat
        ref[f"pad_vertical_{side}_N"] = PARAMS.pad_k_vertical_N_m * (zv[n_sl] + sgn * 0.5 * B * zr[n_sl] - seat)
        x = mdl.sleeper_s_m[j] - mdl.deck.start_m
        below = 0.0
        if mdl.on_deck[j]:
            below = mdl._deck_row(x, "w") @ ud + sgn * 0.5 * B * (mdl._deck_row(x, "tx") @ ud)
        ref[f"ballast_vertical_{side}_N"] = 0.5 * PARAMS.ballast_k_vertical_N_m * (seat - below)
    xd = s - mdl.deck.start_m
    ref["deck_z_m"] = mdl._deck_row(xd, "w") @ ud if 0.0 <= xd <= mdl.deck.length_m else 0.0
    # the ballast of every sleeper: all of them carry the wheelset's load in statics; split into the sleepers on
    # the deck (strictly between its ends, by their track distance) and those on the ground
    tot = 0.0
    on_deck = {"ballast_ground_N": 0.0, "ballast_deck_N": 0.0}
    for jj in range(ns):
        s_j = mdl.sleeper_s_m[jj]
        where = "ballast_deck_N" if DECK_START_M < s_j < DECK_START_M + SPAN_M else "ballast_ground_N"
        for sgn in RAIL_Y_OVER_HALF_B.values():
            seat = zv[2 * nn + jj] + sgn * 0.5 * B * zr[2 * nn + jj]
            below = 0.0
            if mdl.on_deck[jj]:
                xx = mdl.sleeper_s_m[jj] - mdl.deck.start_m
                below = mdl._deck_row(xx, "w") @ ud + sgn * 0.5 * B * (mdl._deck_row(xx, "tx") @ ud)
            tot += 0.5 * PARAMS.ballast_k_vertical_N_m * (seat - below)
            on_deck[where] += 0.5 * PARAMS.ballast_k_vertical_N_m * (seat - below)
    ref["ballast_total_N"] = tot
    ref.update(on_deck)
    return ref


def _errors(mdl, off, statics, modes) -> dict:
    """Per point and quantity: (helper's value, full model's value, the largest full value of that unit)."""
    out = {}
    F = np.array([[0.0, sum(Q_LR), 0.5 * B * (Q_LR[1] - Q_LR[0])]])
    for name, (s, i, u) in statics.items():
        ref = _reference(mdl, off, s, i, u)
        q = modes.static_coordinates([s], F)
        got = track_under_wheels(modes, [s], q, np.zeros_like(q))
        assert got["on_segment"][0]
        for key, v in ref.items():
            if key not in TOTALS:
                scale = max(abs(ref[k]) for k in ref if k[-2:] == key[-2:] and k not in TOTALS)
                out[name, key] = (float(got[key][0]), v, scale)
        # equilibrium: the ballast of all sleepers, on the ground and on the deck, carries the wheelset
        assert ref["ballast_total_N"] == pytest.approx(sum(Q_LR), rel=1e-9)
        totals = support_force_totals_N(modes, q, np.zeros_like(q))
        out[name, "ballast_total_N"] = (totals["total_N"], sum(Q_LR), sum(Q_LR))
        # and its two parts, the sleepers on the ground and those on the deck (the full model's ballast forces)
        out[name, "ballast_ground_N"] = (totals["ground_N"], ref["ballast_ground_N"], sum(Q_LR))
        out[name, "ballast_deck_N"] = (totals["deck_N"], ref["ballast_deck_N"], sum(Q_LR))
    return out


def test_under_wheel_outputs_match_full_statics_with_all_modes(full_statics):
    """With every mode kept the reduced statics are the full statics: the helper's values (from the modal state
    through the shape table and the support rows) equal the full model's to round-off.  The modal sum's error is
    of the order of eps times the condition of K (the squared ratio of the highest to the lowest frequency,
    ~1e9 here): 1e-6 of the largest value of a kind."""
    mdl, off, statics = full_statics
    modes = mdl.modes(f_max_Hz=1e9)
    assert modes.n_modes == 3 * mdl.n_dof + len(mdl.deck.free_dofs())
    for k, (got, ref, scale) in _errors(mdl, off, statics, modes).items():
        assert got == pytest.approx(ref, abs=1e-6 * scale), k


def test_under_wheel_outputs_with_the_default_truncation(full_statics):
    """With the track file's cut-off (800 Hz): the rail's deflection under the wheel within the truncation error of
    the track on the ground (−3 % measured, docs/track.md; bounded at 5 %), the sleepers and the ballast (carried
    by the low modes) and the ballast's sum as well.  The pad force at a sleeper right under the wheel carries the
    local compression of the rail-on-pad branch, which the truncation cuts: its error falls as the cut-off
    rises (800, 1200, 2000 Hz), within 5 % at 2000 Hz."""
    mdl, off, statics = full_statics
    assert PARAMS.modes_up_to_Hz == 800.0
    pad = {}
    for f in (800.0, 1200.0, 2000.0):
        err = _errors(mdl, off, statics, mdl.modes(f_max_Hz=f))
        pad[f] = max(abs(g / r - 1.0) for (n, k), (g, r, _) in err.items() if k.startswith("pad"))
        if f == PARAMS.modes_up_to_Hz:
            for (name, key), (got, ref, scale) in err.items():
                if not key.startswith("pad"):
                    assert got == pytest.approx(ref, abs=0.05 * scale), (name, key)
    assert pad[800.0] > pad[1200.0] > pad[2000.0]
    assert pad[2000.0] < 0.05, pad


def _deck_mid_ratio(mdl) -> float:
    """The deck's static mid-span deflection under a wheelset at mid-span (full model) over P L³/(48 EI)."""
    M, K, C, off = mdl.assemble_coupled()
    s = DECK_START_M + 0.5 * SPAN_M
    i = int(round((s - mdl.start_m) / mdl.h_m))
    assert abs(mdl.start_m + i * mdl.h_m - s) < 1e-9
    f = np.zeros(K.shape[0])
    f[off["vertical"] + 2 * i] = sum(Q_LR)
    u = np.linalg.solve(K, f)
    return float(mdl._deck_row(s - mdl.deck.start_m, "w") @ u[off["deck"]:]) / (sum(Q_LR) * SPAN_M ** 3
                                                                                 / (48.0 * DECK_EI))


@pytest.mark.parametrize("segment, rel", [((0.2, 9.6), 0.05), ((-5.8, 22.2), 0.15)], ids=["deck only", "embankments"])
def test_deck_deflection_with_the_track_layer(segment, rel):
    """The deck's static mid-span deflection under a wheelset at mid-span with the track layer against the bare
    span's P L³/(48 EI), changed by (first order in the small ratios, each derived for the continuously supported
    rail, β its decay wavenumber):

    * the rails' bending stiffness in parallel with the deck: −2 EI_rail/EI_deck;
    * the load's spreading over the sleepers: Zimmermann's distribution keeps the load's force, first and second
      moments, and the mid-span influence line is a cubic plus |x − L/2|³/(12 EI): −6/(βL)³;
    * with the track continuing onto the embankments, the rails resist the deck's end rotation θ = P L²/(16 EI): a
      beam on an elastic foundation over a kink θ of its foundation puts the moment EI_rail β θ on each side, which
      lifts mid-span by −(3/8) (EI_rail/EI_deck) βL.

    Tolerance on the predicted change: 5 % with the track on the deck only (second order in ratios of 3e-3, and the
    discrete sleepers); 15 % with the embankments (the end moment is computed for the unrestrained deck rotation
    and a rigid ground, both neglected in the estimate)."""
    deck = _deck()
    mdl = TrackOnDeckModel(PARAMS, *segment, deck, ballast_height_m=0.0)
    k = PARAMS.support_stiffness_per_rail_N_m2()
    EI_r = PARAMS.rail_E_Pa * PARAMS.rail_I_vertical_m4
    beta = (k / (4.0 * EI_r)) ** 0.25
    change = -2.0 * EI_r / DECK_EI - 6.0 / (beta * SPAN_M) ** 3
    if segment[0] < DECK_START_M:
        change -= 0.375 * EI_r / DECK_EI * beta * SPAN_M
    assert _deck_mid_ratio(mdl) - 1.0 == pytest.approx(change, rel=rel)


def test_off_segment_and_bad_state():
    mdl = _model()
    modes = mdl.modes(f_max_Hz=400.0)
    q = np.zeros(modes.n_modes)
    got = track_under_wheels(modes, [mdl.start_m - 1.0], q, q)
    # off the segment: assigned zero (exact)
    assert not got["on_segment"][0] and got["rail_z_right_m"][0] == 0.0 and np.isnan(got["pad_vertical_left_N"][0])
    with pytest.raises(ValueError, match="modal coordinates"):
        track_under_wheels(modes, [0.0], q[:-1], q)
    with pytest.raises(TypeError, match="FlexibleTrackModes"):
        track_under_wheels(object(), [0.0], q, q)


# ============================================================================================== the example
def _example():
    spec = importlib.util.spec_from_file_location("train_on_ballasted_bridge",
                                                  ROOT / "examples" / "train_on_ballasted_bridge.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("argv, message", [
    (["--dt", "0"], "--dt: 0.0: expected a finite value > 0"),
    (["--dt", "0.001"], "--dt: 0.001 s: RK44 is unstable"),
    (["--speed-kmh", "-10"], "--speed-kmh: -10.0"),
    (["--speed-kmh", "nan"], "--speed-kmh: nan"),
    (["--speed-kmh", "2000"], "--speed-kmh: 2000 is not a plausible running speed"),
    (["--duration", "0.1", "--quick"], "--duration: give either"),
    (["--duration", "-1"], "--duration: -1.0"),
    (["--deck-modes", "0"], "--deck-modes: 0"),
    (["--train", "no_such_train"], "--train: "),
])
def test_example_bad_input(argv, message, capsys, tmp_path):
    ex = _example()
    with pytest.raises(SystemExit) as e:
        ex.parse_args(argv + ["--out", str(tmp_path / "o")])
    assert e.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert message in err, err


def _one_car(tmp_path) -> Path:
    consist = tmp_path / "one_car.toml"
    consist.write_text('schema_version = 1\n[train]\nname = "1 x Manchester vehicle 1"\nsource = "test"\n'
                       '[[car]]\nvehicle = "manchester_vehicle1"\nlength_m = 26.0\n')
    return consist


def test_example_step_beyond_the_wheel_on_rail_mode(tmp_path, capsys):
    """A step the track's modes carry (below 2√2/ω of 800 Hz) but the wheel on the rail's modal mass does not:
    refused before either run, naming --dt and the largest stable step."""
    ex = _example()
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as e:
        ex.main(["--train", str(_one_car(tmp_path)), "--duration", "0.02", "--deck-modes", "3", "--dt", "5e-4",
                 "--out", str(out)])
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert "error: --dt: 0.0005 s: RK44 is unstable for the wheel on the flexible rail" in err
    assert not out.exists()


def test_example_short_run(tmp_path):
    """One car over a short run: both runs end ok; at t = 0 (the static equilibrium on the rails, the leading
    wheelset over the first abutment)

    * the ballast of all sleepers, on the embankment and on the deck, carries the train's static wheel loads: to
      the reduced track's equilibrium error (0.02 % measured on the ground, docs/track.md; bound 0.1 %);
    * with rigid rails no load is on the span (the deck's modes vanish at the abutment): deflection 0 to round-off;
      with the track layer the leading wheelset's load P spreads over the abutment onto the deck: for Zimmermann's
      distribution the part beyond the load point has the first moment P/(4β), and the mid-span influence line of
      the span is below its tangent at the support, x L²/(16 EI), so 0 < w_mid <= P L²/(64 β EI)."""
    ex = _example()
    out = tmp_path / "out"
    summary = ex.main(["--train", str(_one_car(tmp_path)), "--duration", "0.02", "--deck-modes", "3",
                       "--out", str(out)])
    assert summary["exit_status"] == {"rigid": "ok", "ballasted": "ok"}
    assert json.loads((out / "summary.json").read_text())["exit_status"]["ballasted"] == "ok"
    assert (out / "figure.png").stat().st_size > 0

    def table(name):
        rows = (out / f"{name}.csv").read_text().splitlines()
        head = rows[0].split(",")
        data = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
        return {h: data[:, k] for k, h in enumerate(head)}

    rigid, ball = table("rigid"), table("ballasted")
    wheel_loads = [c for c in ball if c.startswith("Q_w")]
    W = sum(ball[c][0] for c in wheel_loads)
    assert ball["ballast_ground_total_N"][0] + ball["ballast_deck_total_N"][0] == pytest.approx(W, rel=1e-3)
    assert abs(rigid["deck_mid_z_m"][0]) < 1e-12
    deck = ex.deck_inputs()
    EI = deck["mass_kg_m"] * (2.0 * deck["span_m"] ** 2 * deck["f1_Hz"] / math.pi) ** 2
    P = ball["Q_w1_right_N"][0] + ball["Q_w1_left_N"][0]
    k = PARAMS.support_stiffness_per_rail_N_m2()
    beta = (k / (4.0 * PARAMS.rail_E_Pa * PARAMS.rail_I_vertical_m4)) ** 0.25
    assert 0.0 < ball["deck_mid_z_m"][0] <= P * deck["span_m"] ** 2 / (64.0 * beta * EI)
    # every wheel has its track columns, finite on the segment
    for j in (1, 2, 3, 4):
        for side in ("right", "left"):
            for c in ("rail_z", "sleeper_z", "pad", "ballast"):
                unit = "N" if c in ("pad", "ballast") else "m"
                assert np.all(np.isfinite(ball[f"{c}_w{j}_{side}_{unit}"]))


# ================================================================== the deck under the loads the track puts on it
def _statics_at_mid_span(segment):
    """The full finite-element statics (no reduction) of the track on the 10 m deck over ``segment`` under one
    wheelset at mid-span: (model, offsets, DOF vector)."""
    deck = _deck()
    mdl = TrackOnDeckModel(PARAMS, *segment, deck, ballast_height_m=0.0)
    M, K, C, off = mdl.assemble_coupled()
    s = DECK_START_M + 0.5 * SPAN_M
    i = int(round((s - mdl.start_m) / mdl.h_m))
    assert abs(mdl.start_m + i * mdl.h_m - s) < 1e-9                  # the load at a rail node
    f = np.zeros(K.shape[0])
    f[off["vertical"] + 2 * i] = sum(Q_LR)
    f[off["roll"] + 2 * i] = 0.5 * B * (Q_LR[1] - Q_LR[0])
    return mdl, off, np.linalg.solve(K, f)


@pytest.mark.parametrize("segment", [(0.2, 9.6), (-5.8, 22.2)], ids=["deck only", "embankments"])
def test_the_deck_deflects_as_the_simply_supported_beam_under_the_ballast_forces(segment):
    """Action and reaction between track and deck, against the statics of a simply supported beam written here.
    From the full statics, the ballast of every sleeper pushes on what is under it with the force of its two halves
    (k_b/2 on the rail seat's deflection relative to the ground or to the deck point under it, z down): a force
    F_j = Σ_sides and a moment T_j = Σ_sides ±(b/2) per sleeper.  Then

    * equilibrium: Σ F_j over all sleepers (ground and deck) is the wheelset's load ΣQ and Σ T_j its roll moment
      b/2 (Q_right - Q_left); with the track on the deck only, the deck alone receives both;
    * the deck, loaded by nothing but the F_j and T_j of its sleepers, deflects at mid-span as the Euler–Bernoulli
      span: w(L/2) = Σ F_j c_j (3L² - 4c_j²)/(48 EI), c_j = min(x_j, L - x_j), and twists as the St Venant shaft
      fixed in torsion at both ends (fork bearings): θ(L/2) = Σ T_j c_j/(2 GJ).  The deck's Hermite (bending) and
      linear (torsion) elements reproduce these exactly at their nodes (mid-span is one) for loads placed anywhere
      by their own shape functions (the elements span the homogeneous solutions).

    Tolerance: the solve's round-off, ε times the condition of K (~1e9, the squared ratio of the highest to the
    lowest frequency): 1e-6 relative."""
    mdl, off, u = _statics_at_mid_span(segment)
    nn, n = mdl.n_nodes, mdl.n_dof
    zv, zr, ud = u[off["vertical"]:off["vertical"] + n], u[off["roll"]:off["roll"] + n], u[off["deck"]:]
    k_half = 0.5 * PARAMS.ballast_k_vertical_N_m
    F, T = np.zeros(mdl.n_sleepers), np.zeros(mdl.n_sleepers)
    for j in range(mdl.n_sleepers):
        x = mdl.sleeper_s_m[j] - DECK_START_M
        for sgn in RAIL_Y_OVER_HALF_B.values():
            seat = zv[2 * nn + j] + sgn * 0.5 * B * zr[2 * nn + j]
            below = 0.0
            if mdl.on_deck[j]:
                below = mdl._deck_row(x, "w") @ ud + sgn * 0.5 * B * (mdl._deck_row(x, "tx") @ ud)
            F[j] += k_half * (seat - below)
            T[j] += sgn * 0.5 * B * k_half * (seat - below)
    moment = 0.5 * B * (Q_LR[1] - Q_LR[0])
    assert F.sum() == pytest.approx(sum(Q_LR), rel=1e-6)
    assert T.sum() == pytest.approx(moment, rel=1e-6)
    on = mdl.on_deck
    if segment[0] > DECK_START_M:
        assert on.all()                                        # every sleeper on the deck: it carries everything
    else:
        # the rails continuing onto the embankments hold the deck's ends: the ground sleepers there carry (or, near
        # the abutments, pull) a share, and the deck receives ΣQ minus that share
        assert abs(F[~on].sum()) > 1e-3 * sum(Q_LR)
    c = np.minimum(mdl.sleeper_s_m[on] - DECK_START_M, SPAN_M - (mdl.sleeper_s_m[on] - DECK_START_M))
    w_ref = np.sum(F[on] * c * (3 * SPAN_M ** 2 - 4 * c ** 2)) / (48.0 * DECK_EI)
    theta_ref = np.sum(T[on] * c) / (2.0 * DECK_EI)           # GJ = DECK_EI in this section
    mid = 0.5 * SPAN_M
    assert mdl._deck_row(mid, "w") @ ud == pytest.approx(w_ref, rel=1e-6)
    assert mdl._deck_row(mid, "tx") @ ud == pytest.approx(theta_ref, rel=1e-6)


def _brute_force_vertical_statics(segment, load_s_m, load_N):
    """The vertical statics of the track on the 10 m span written here from the physics, as a reference for the
    package's finite-element model: the two rails one Euler–Bernoulli beam (2 E I_vertical, free ends at the
    segment's first and last sleeper), at every sleeper two pads (2 k_pad) to the sleeper, under it the ballast
    (k_ballast) to rigid ground or, strictly inside the span, to the deck: one simply supported Euler–Bernoulli beam
    (EI_deck).  Hermite beam elements between consecutive sleepers (and the deck's supports): the elements span the
    beams' homogeneous solutions, so with every load at a node the nodal values are the continuum's exactly.
    Returns (rail, sleeper, deck) deflections at ``load_s_m`` (a sleeper) [m], z down."""
    d = PARAMS.sleeper_spacing_m
    n_bays = int(math.ceil(segment[1] / d - 1e-9))
    xs = segment[0] + d * np.arange(n_bays + 1)                             # the sleepers
    on = (xs - DECK_START_M > 1e-9) & (xs - DECK_START_M < SPAN_M - 1e-9)
    xd = np.concatenate(([DECK_START_M], xs[on], [DECK_START_M + SPAN_M]))   # the deck's nodes
    nr, ns, nd = xs.size, xs.size, xd.size
    i_s, i_d = 2 * nr, 2 * nr + ns                                           # first sleeper and deck DOF
    K = np.zeros((i_d + 2 * nd,) * 2)

    def beam(first, x, EI):
        for e in range(x.size - 1):
            h = x[e + 1] - x[e]
            ke = EI / h ** 3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                                         [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
            dofs = first + 2 * e + np.arange(4)
            K[np.ix_(dofs, dofs)] += ke

    def spring(a, b, k):
        K[a, a] += k
        if b is not None:
            K[b, b] += k
            K[a, b] -= k
            K[b, a] -= k

    beam(0, xs, 2.0 * PARAMS.rail_E_Pa * PARAMS.rail_I_vertical_m4)
    beam(i_d, xd, DECK_EI)
    deck_node = {j: 1 + k for k, j in enumerate(np.flatnonzero(on))}
    for j in range(ns):
        spring(2 * j, i_s + j, 2.0 * PARAMS.pad_k_vertical_N_m)
        spring(i_s + j, i_d + 2 * deck_node[j] if on[j] else None, PARAMS.ballast_k_vertical_N_m)
    free = np.setdiff1d(np.arange(K.shape[0]), [i_d, i_d + 2 * (nd - 1)])  # the deck's supports: w = 0
    j = int(np.argmin(np.abs(xs - load_s_m)))
    assert abs(xs[j] - load_s_m) < 1e-9
    f = np.zeros(K.shape[0])
    f[2 * j] = load_N
    u = np.zeros(K.shape[0])
    u[free] = np.linalg.solve(K[np.ix_(free, free)], f[free])
    mid = int(np.argmin(np.abs(xd - (DECK_START_M + 0.5 * SPAN_M))))
    assert abs(xd[mid] - (DECK_START_M + 0.5 * SPAN_M)) < 1e-9
    return u[2 * j], u[i_s + j], u[i_d + 2 * mid]


@pytest.mark.parametrize("segment", [(0.2, 9.6), (-5.8, 22.2)], ids=["deck only", "embankments"])
def test_rail_sleeper_and_deck_deflection_against_a_brute_force_model(segment):
    """The package's full statics (wheelset at mid-span over a sleeper) against the model written out above: the
    rail's deflection under the wheel is the deck's plus the track's own compression in series (pads, ballast) and
    bending, all three computed independently.  The vertical beam sees the wheelset's whole load (the unequal wheel
    loads only add the roll beam and the deck's torsion, decoupled from bending).  What separates the two: the
    package's deck elements (0.5 m) carry the sleepers' forces by their shape functions and read the deck under a
    sleeper by interpolation; inside an element that holds a point force F the interpolation misses at most that of
    a clamped element, F h³/(192 EI), against the span's ΣQ L³/(48 EI): (h/L)³/4 = 3e-5 of the deck's deflection,
    and the same absolute error on the rail and the sleeper.  Asserted: 2e-4 of the deck's mid-span deflection."""
    mdl, off, u = _statics_at_mid_span(segment)
    s = DECK_START_M + 0.5 * SPAN_M
    rail, sleeper, deck = _brute_force_vertical_statics(segment, s, sum(Q_LR))
    zv = u[off["vertical"]:off["vertical"] + mdl.n_dof]
    i = int(round((s - mdl.start_m) / mdl.h_m))
    j = int(round((s - mdl.start_m) / PARAMS.sleeper_spacing_m))
    got = (zv[i * 2], zv[2 * mdl.n_nodes + j], mdl._deck_row(0.5 * SPAN_M, "w") @ u[off["deck"]:])
    tol = 2e-4 * deck
    for name, g, ref in zip(("rail", "sleeper", "deck"), got, (rail, sleeper, deck)):
        assert g == pytest.approx(ref, abs=tol), name
    assert rail - deck > 0.3 * rail          # the track's own share (pads, ballast, rail bending): ~half the rail's


def test_a_lateral_load_bends_and_twists_the_deck_through_the_ballast_above_its_axis():
    """A lateral force at mid-span on the rails of the track on the 10 m deck (deck only), the ballast's underside
    e = 0.5 m above the deck's axis: by each sleeper's statics the ballast passes on to the deck exactly the lateral
    force its pads take from the rails, F_j = 2 k_pad,lat (u_rail - u_sleeper) (raw track values), at height e.  So
    the deck, loaded by nothing else, bends laterally as the simply supported span, v(L/2) = Σ F_j c_j (3L² -
    4c_j²)/(48 EI_z), and twists as the fork-supported shaft under the moments e F_j: with z down, a force +y at
    z = -e has the moment +e F_y about x; the rails, bent in roll by the deck's varying twist, add their pads'
    moments R_j = (k_pad b²/2)(φ_rail - φ_sleeper) (summing to zero); θ(L/2) = Σ (e F_j + R_j) c_j/(2 GJ) (the
    deck's elements reproduce both at a node, as above; the round-off ε cond(K): 1e-6).  And Σ F_j is the applied
    force."""
    e, F_y = 0.5, 30.0e3
    deck = _deck()
    mdl = TrackOnDeckModel(PARAMS, 0.2, 9.6, deck, ballast_height_m=e)
    _, K, _, off = mdl.assemble_coupled()
    s = DECK_START_M + 0.5 * SPAN_M
    i = int(round((s - mdl.start_m) / mdl.h_m))
    assert abs(mdl.start_m + i * mdl.h_m - s) < 1e-9 and mdl.on_deck.all()
    f = np.zeros(K.shape[0])
    f[off["lateral"] + 2 * i] = F_y
    u = np.linalg.solve(K, f)
    nn, n = mdl.n_nodes, mdl.n_dof
    lat, rol, ud = u[off["lateral"]:off["lateral"] + n], u[off["roll"]:off["roll"] + n], u[off["deck"]:]
    seat = 2 * np.asarray(mdl.sleeper_node)
    F = 2.0 * PARAMS.pad_k_lateral_N_m * (lat[seat] - lat[2 * nn:])
    # the rails resist the deck's varying twist in roll: their pads' moments (two pads b/2 off the centre line) pass
    # through the sleepers to the deck as well
    R = PARAMS.pad_k_vertical_N_m * B ** 2 / 2.0 * (rol[seat] - rol[2 * nn:])
    assert F.sum() == pytest.approx(F_y, rel=1e-6)
    assert abs(R.sum()) < 1e-6 * e * F_y                       # no roll load applied: the rails' moments cancel
    c = np.minimum(mdl.sleeper_s_m - DECK_START_M, SPAN_M - (mdl.sleeper_s_m - DECK_START_M))
    v_ref = np.sum(F * c * (3 * SPAN_M ** 2 - 4 * c ** 2)) / (48.0 * 10 * DECK_EI)
    theta_ref = np.sum((e * F + R) * c) / (2.0 * DECK_EI)       # GJ = DECK_EI in this section
    mid = 0.5 * SPAN_M
    assert mdl._deck_row(mid, "v") @ ud == pytest.approx(v_ref, rel=1e-6)
    assert mdl._deck_row(mid, "tx") @ ud == pytest.approx(theta_ref, rel=1e-6)
    assert theta_ref > 0.0


def test_the_deck_carries_its_damping_ratio_in_its_first_mode():
    """The deck in the coupled model has stiffness-proportional damping for the deck's damping ratio ζ (0.01 here):
    with the ballast's dampers set to zero, the coupled damping's deck block is the deck's alone, and the deck's
    first mode (of its own mass and stiffness, by LAPACK here) has φᵀCφ / (2 ω φᵀMφ) = ζ, every higher mode
    ζ ω/ω_1 (a property of C ∝ K).  Tolerance: the lowest eigenvalue of the deck's (M, K) is known to ε times its
    spread λ_max/λ_min (~1e8: the axial modes), here and in the package's own solve for ω_1: 10 ε λ_max/λ_min."""
    zeta = 0.01
    deck = _deck(damping_ratio=zeta)
    params = dataclasses.replace(PARAMS, ballast_c_vertical_Ns_m=0.0, ballast_c_lateral_Ns_m=0.0)
    _, _, C, off = TrackOnDeckModel(params, 0.2, 9.6, deck, ballast_height_m=0.5).assemble_coupled()
    Cd = C[off["deck"]:, off["deck"]:]
    Md, Kd = (m.toarray() for m in deck.assemble(supported=True))
    L = np.linalg.cholesky(Md)
    w2, phi = np.linalg.eigh(np.linalg.solve(L, np.linalg.solve(L, Kd).T))
    w = np.sqrt(w2[:4])
    shapes = np.linalg.solve(L.T, phi[:, :4])                  # M-orthonormal deck modes
    ratio = np.einsum("ik,ij,jk->k", shapes, Cd, shapes) / (2.0 * w)
    np.testing.assert_allclose(ratio, zeta * w / w[0], rtol=10.0 * np.finfo(float).eps * w2[-1] / w2[0])
