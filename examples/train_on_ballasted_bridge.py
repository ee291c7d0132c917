r"""A short train over a simply supported span with the ballasted track: the deck response with and without the
track layer, and the track under every wheel.

The train (default vehicles/trains/manchester_x2.toml: two Manchester benchmark coaches) runs at constant speed
from the embankment over the single span of examples/scenarios/bridge_20m.toml (20 m, 15 t/m, f1 = 6 Hz from its
EI_y, 1 % damping) and onto the embankment beyond, twice:

(a) ``rigid``: as ``bridge-crossing --model vehicles`` builds it — rigid rails carried by the deck's vertical
    bending modes (the crossing's deck, :func:`~exudyn_wheelrail.scenarios.bridge_crossing.deck_modes`, its mass
    including the track's; modes up to the track's cut-off), rigid rails on the embankments;
(b) ``ballasted``: the ballasted 60E1 track (rails on pads, sleepers, ballast; exudyn_wheelrail/track/flexible_deck.py)
    over the same deck, whose own mass per metre is the crossing's less the rails' and sleepers' (the same total):
    one set of coupled modes of track and deck up to the track file's cut-off (800 Hz).

Both: one wheel–rail connector for all wheelsets (the crossing's contact settings), the train in static equilibrium
on its rails at t = 0 with the leading wheelset over the first abutment (in (b) with the track's static deflection
under every wheelset, :func:`~exudyn_wheelrail.scenarios.flexible_track.start_on_flexible_track`), explicit RK44 at
``--dt``, the project's runner (every state watched; the run's status), until the last wheelset leaves the span.

The flexible segment (b).  It carries the whole run: from the rearmost wheelset at t = 0 (or the first abutment,
whichever comes first) to the leading wheelset at the end (or the far abutment), plus five decay lengths 1/β of the
track's vertical support at both ends (:func:`~exudyn_wheelrail.track.flexible_segment.segment_for_run`; 3.9 m for the
default track, where a wheel load's static deflection has fallen below 1 % of its peak).  No wheel enters or leaves
the segment during the run.  Off the segment the track is rigid (``Φ = 0``), and the segment's rails end free on its
first and last sleeper: a wheel running onto the segment meets a free rail end, and leaving it steps from the
loaded rail end up onto the rigid rail.  Measured (examples/flexible_segment_ends.py: one coach at 200 km/h onto
and off a 20 m segment on the ground): entering, the leading wheel's Q swings between 5 and 85 kN within 3 m (the
free rail end deflects 0.89 mm under it, 0.48–0.53 mm inside the segment); leaving, the step of 0.51 mm onto the
rigid rail gives an impact of 2.5 MN and a lift-off — and the runner still reports ``ok`` (it watches derailment
and divergence, not impacts).  Neither is a property of the track, so the segment is chosen such that no wheel
comes near its ends.  The embankment parts of the segment are the track on rigid ground; the change of support at
each abutment is abrupt (no transition zone, no abutment backwall), and with rigid rails (a) the rail follows the
deck's end rotation with a kink at each abutment.

Accuracy of the under-wheel values (tests/test_track_on_deck_train.py, statics against the full finite-element
model): with the 800 Hz modes the rail's deflection under a wheel is 1.3–3.2 % low, the sleepers' displacements and
the ballast forces are within 0.1 %; the pad force at a sleeper right under a wheel is 15 % low (the local
compression of the rail-on-pad branch, above the cut-off; 8 % at 1200 Hz, 4 % at 2000 Hz), mid-bay within 1.2 %.

Measured (the defaults: 2 coaches, 8 wheelsets, 200 km/h, 1.216 s, RK44 0.25 ms; (b) 1205 coupled modes over
123.6 m, 33 of 207 sleepers on the deck; both runs ``ok``):

=====================================  ==============  ==============  =============
                                       (a) rigid       (b) ballasted   (b) − (a)
=====================================  ==============  ==============  =============
deck mid-span deflection, max          2.062 mm        2.032 mm        −1.5 %
deck mid-span acceleration, max |a|    0.985 m/s²      0.839 m/s²      −15 %
wheel load Q, max / min                69.9 / 39.6 kN  56.0 / 53.5 kN
change of Q within 2 m of an abutment  15.3 / 14.4 kN  1.0 / 0.85 kN   (first / far)
lateral force |Y|, max                 362 N           339 N
rail under a wheel, max                2.06 mm         2.52 mm
=====================================  ==============  ==============  =============

In (b) the nearest sleeper's seat moves up to 2.43 mm, its pad carries 16.0–20.7 kN and its ballast up to 21.9 kN.
With rigid rails the wheels meet a kink at each abutment (the deck's end rotation) and Q changes by up to 15 kN
there, which the track layer smooths to 1 kN; the deck's acceleration loses that high-frequency part.  The deck's
peak deflection changes by −1.5 %; in statics the track layer changes it by −0.25 % here (the rails' stiffness in
parallel, the load's spreading and the rails' restraint of the deck's end rotation, the three effects of
tests/test_track_on_deck_train.py), the rest is the dynamics (the track's mass on the ballast springs, the deck's
stiffness-proportional damping in (b) against the constant modal ratio in (a)).  Solve 2.3–2.4 s (a) and 46 s (b),
the modes of (b) 15–20 s (load 2.3–2.8, 2 shared cores).

Outputs (``--out``, default ``out/train_on_ballasted_bridge``):

* ``rigid.csv``, ``ballasted.csv`` — one row per step, the columns ``time_s``, ``s_leading_m``, ``deck_mid_z_m``
  (the deck's mid-span deflection, + down), ``deck_mid_acc_m_s2`` (its acceleration from the modal equations at
  the state, ``q̈ = Q − D q̇ − diag(ω²) q``), per wheelset j (1 leading, car after car) and wheel ``<side>``
  (right, left): ``Q_w<j>_<side>_N``, ``Y_w<j>_<side>_N`` (the recorder's wheel forces),
  ``rail_z_w<j>_<side>_m`` (the rail's vertical displacement under the wheel: in (a) the deck's under the
  wheelset, in (b) the flexible rail's), and in (b) at the sleeper nearest the wheelset
  ``sleeper_z_w<j>_<side>_m`` (its rail seat), ``pad_w<j>_<side>_N``, ``ballast_w<j>_<side>_N`` (compression
  positive; :func:`~exudyn_wheelrail.track.flexible_outputs.track_under_wheels`), and ``ballast_ground_total_N``,
  ``ballast_deck_total_N`` (all sleepers' vertical ballast forces on the ground and on the deck), and the
  recorder's other wheel and wheelset columns;
* ``summary.json`` — the inputs, per run the status, the peaks (not evaluated for a run that did not end ``ok``;
  among them the transition embankment–bridge: the largest change of a wheel's Q from its static value within 2 m
  of each abutment, ``max_abs_dQ_near_<start|end>_abutment_N``), solve and build times with the machine's load
  average, the model sizes; ``comparison``: the peaks with and without the track layer and their differences;
* ``figure.png`` — the deck's mid-span deflection and acceleration of both runs, and in (b) the leading wheelset's
  right wheel: Q, the rail's and the nearest sleeper's displacement, the pad and ballast forces.

Run:  python examples/train_on_ballasted_bridge.py [--quick] [--out DIR] [--train FILE] [--speed-kmh 200]
      [--duration S] [--dt 0.00025] [--deck-modes N]
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys
import time
from pathlib import Path

#: one BLAS thread unless the caller chose: the coupled model's dense eigen-solution and its damping coupling (one
#: dense matrix-vector product per RK stage) ran 2 and 3 times faster single-threaded on 2 shared cores (1299 modes,
#: 200 steps: solve 2.2 s against 6.9 s, modes 21 s against 46 s, load 2.6-2.9); read when numpy loads BLAS
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from exudyn_wheelrail.simulation.exudyn_settings import run_solver_settings

EXAMPLES = Path(__file__).resolve().parent
#: the deck: the span, mass, first frequency (from its EI_y) and damping of this scenario's [structure]
DECK_SCENARIO = EXAMPLES / "scenarios" / "bridge_20m.toml"
DEFAULT_TRAIN = "manchester_x2"
DEFAULT_SPEED_KM_H = 200.0
#: RK44 step [s]: the flexible track's wheel-on-rail mode needs <= 0.35 ms (docs/track.md); the same in both runs
DEFAULT_DT_S = 2.5e-4
#: --quick: simulated time [s] (the train's first metres onto the span)
QUICK_DURATION_S = 0.05
DEFAULT_OUT = Path("out") / "train_on_ballasted_bridge"
#: ASSUMPTION: the ballast's bottom at the deck's beam axis, as the crossing's rails are at it (rail height 0):
#: (a) and (b) differ by the track layer alone, and the deck's torsion and lateral bending stay decoupled from its
#: vertical bending in both
BALLAST_HEIGHT_M = 0.0
#: the two runs, (a) and (b) (module docstring)
RUNS = ("rigid", "ballasted")


class InputError(ValueError):
    """Bad input: the message names the option and the problem."""


# ============================================================================================= the inputs
def deck_inputs() -> dict:
    """Span, mass per metre, first bending frequency and damping ratio of :data:`DECK_SCENARIO`'s deck."""
    from exudyn_wheelrail.scenarios.spec import load_scenario
    st = load_scenario(DECK_SCENARIO)["structure"]
    if len(st["spans_m"]) != 1:
        raise InputError(f"{DECK_SCENARIO}: structure.spans_m: expected one span")
    L, sec = float(st["spans_m"][0]), st["section"]
    f1 = math.pi / (2.0 * L * L) * math.sqrt(sec["EI_y_Nm2"] / sec["m_kg_m"])
    return {"span_m": L, "mass_kg_m": float(sec["m_kg_m"]), "f1_Hz": f1, "damping_ratio": float(st["damping_ratio"]),
            "source": str(DECK_SCENARIO.relative_to(EXAMPLES.parent))}


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    ap.add_argument("--train", default=DEFAULT_TRAIN,
                    help=f"consist: a shipped name or a file (default {DEFAULT_TRAIN})")
    ap.add_argument("--speed-kmh", type=float, default=DEFAULT_SPEED_KM_H,
                    help=f"running speed [km/h] (default {DEFAULT_SPEED_KM_H:g})")
    ap.add_argument("--duration", type=float, default=None,
                    help="simulated time [s] (default: until the last wheelset leaves the span)")
    ap.add_argument("--dt", type=float, default=DEFAULT_DT_S, help=f"RK44 step [s] (default {DEFAULT_DT_S:g})")
    ap.add_argument("--deck-modes", type=int, default=None,
                    help="vertical deck modes of run (a) (default: those up to the track's cut-off frequency)")
    ap.add_argument("--quick", action="store_true", help=f"a short check: {QUICK_DURATION_S:g} s simulated")
    a = ap.parse_args(argv)
    try:
        check(a)
    except InputError as exc:
        ap.error(str(exc))
    return a


def check(a) -> None:
    """Every option checked, the consist read, before any work (:class:`InputError` naming the option)."""
    from exudyn_wheelrail.cli import SPEED_KM_H
    from exudyn_wheelrail.rolling_stock.train import ConsistError, load_consist
    from exudyn_wheelrail.scenarios.bridge_crossing import MAX_MODES
    from exudyn_wheelrail.track import TrackParameters
    from exudyn_wheelrail.simulation.solvers import RK44

    def positive(opt, v):
        if not (math.isfinite(v) and v > 0.0):
            raise InputError(f"{opt}: {v!r}: expected a finite value > 0")

    positive("--speed-kmh", a.speed_kmh)
    if (problem := SPEED_KM_H.problem(a.speed_kmh)) is not None:
        raise InputError(f"--speed-kmh: {problem}")
    positive("--dt", a.dt)
    params = TrackParameters.from_file()
    dt_max = RK44.imaginary_axis_limit / (2.0 * math.pi * params.modes_up_to_Hz)
    if a.dt >= dt_max:
        raise InputError(f"--dt: {a.dt:g} s: RK44 is unstable for the track's modes up to {params.modes_up_to_Hz:g} "
                         f"Hz at this step; use --dt < {dt_max:.3g} s")
    if a.duration is not None:
        positive("--duration", a.duration)
        if a.quick:
            raise InputError("--duration: give either --duration or --quick")
    if a.deck_modes is not None and not 1 <= a.deck_modes <= MAX_MODES:
        raise InputError(f"--deck-modes: {a.deck_modes}: expected an integer from 1 to {MAX_MODES}")
    try:
        a.consist = load_consist(a.train)
    except ConsistError as exc:
        raise InputError(f"--train: {exc}") from None
    if a.out.exists() and not a.out.is_dir():
        raise InputError(f"--out: {a.out}: exists and is not a directory")


# ================================================================================================ probes
class _Deck:
    """``deck_mid_z_m``, ``deck_mid_acc_m_s2``: the deck's mid-span deflection (its row ``phi_mid`` over the modal
    coordinates) and acceleration from the modal equations ``q̈ = Q − D q̇ − diag(ω²) q`` (Q the connector's
    generalized forces of the recorded state, D the full modal damping)."""

    columns = [("deck", "deck_mid_z_m"), ("deck", "deck_mid_acc_m_s2")]

    def __init__(self, handle, contact, phi_mid, w2, D):
        self.h, self.c = handle, contact
        self.phi = np.asarray(phi_mid, dtype=float)
        self.phi_w2 = self.phi * w2
        self.phi_D = self.phi @ D

    def fill(self, mbs, t, out):
        q, q_t = self.h.coordinates(mbs)
        out[0] = self.phi @ q
        out[1] = self.phi @ self.c.modal_forces_N() - self.phi_w2 @ q - self.phi_D @ q_t


class _RigidRails:
    """(a): ``rail_z_w<j>_<side>_m``, the rigid rail under each wheel carried by the deck (the connector's deck
    state under the wheelset: ``z ∓ (b/2) θ``)."""

    def __init__(self, contact, n_ws, b):
        from exudyn_wheelrail.simulation.recorder import SIDES
        self.c, self.n = contact, n_ws
        self.sgn = np.array([{"left": -0.5 * b, "right": 0.5 * b}[s] for s in SIDES])
        self.columns = [("rail", f"rail_z_w{j + 1}_{s}_m") for j in range(n_ws) for s in SIDES]

    def fill(self, mbs, t, out):
        st = self.c.deck_state()
        out[:] = (st[:self.n, 1:2] + st[:self.n, 2:3] * self.sgn[None, :]).ravel()


class _TrackUnderWheels:
    """(b): per wheel the flexible rail, the nearest sleeper's rail seat, its pad and ballast forces
    (:func:`~exudyn_wheelrail.track.flexible_outputs.track_under_wheels`), and the ballast totals."""

    def __init__(self, handle, train):
        from exudyn_wheelrail.simulation.recorder import SIDES
        self.h, self.train, self.modes = handle, train, handle.modes
        self.x = np.array([ws.p_cg_in_frame[0] for ws in train.wheelsets])
        self.sides = SIDES
        names = []
        for j in range(len(self.x)):
            for s in SIDES:
                names += [f"rail_z_w{j + 1}_{s}_m", f"sleeper_z_w{j + 1}_{s}_m", f"pad_w{j + 1}_{s}_N",
                          f"ballast_w{j + 1}_{s}_N"]
        self.columns = [("track", c) for c in names + ["ballast_ground_total_N", "ballast_deck_total_N"]]

    def fill(self, mbs, t, out):
        from exudyn_wheelrail.track.flexible_outputs import UNDER_WHEEL_KEYS, support_force_totals_N, track_under_wheels
        q, q_t = self.h.coordinates(mbs)
        u = track_under_wheels(self.modes, self.train.track_distance_m(self.x, t), q, q_t)
        cols = [u[k.format(side=s)] for s in self.sides for k in UNDER_WHEEL_KEYS]
        n = len(self.x)
        out[:8 * n] = np.stack(cols, axis=1).ravel()
        tot = support_force_totals_N(self.modes, q, q_t)
        out[8 * n] = tot["ground_N"]
        out[8 * n + 1] = tot["deck_N"]


# ================================================================================================== runs
def _crossing_case(a, deck):
    from exudyn_wheelrail.scenarios.bridge_crossing import MAX_MODES, BridgeCrossing
    from exudyn_wheelrail.track import TrackParameters
    n = a.deck_modes
    if n is None:             # the deck's vertical modes up to the track's cut-off (N² f1 for a simple span)
        n = min(MAX_MODES, int(math.floor(math.sqrt(TrackParameters.from_file().modes_up_to_Hz / deck["f1_Hz"]))))
    return BridgeCrossing(span_m=deck["span_m"], mass_kg_m=deck["mass_kg_m"], f1_Hz=deck["f1_Hz"],
                          damping_ratio=deck["damping_ratio"], n_modes=n, axles=None, speed_m_s=a.speed_kmh / 3.6,
                          model="vehicles", dt_s=a.dt, solver="rk44", train_file=str(a.consist.file or a.train))


def _duration_s(a, case) -> float:
    if a.quick:
        return QUICK_DURATION_S
    if a.duration is not None:
        return a.duration
    x = a.consist.wheelset_x_m()
    return (float(x[0] - x[-1]) + case.length_m) / case.speed_m_s


def _build_train(mbs, a, case, bridge):
    """The consist on the rails with the crossing's contact settings (as the ``vehicles`` load model), the leading
    wheelset at the deck start at t = 0."""
    from exudyn_wheelrail.scenarios.bridge_crossing_vehicles import build_train_on_straight_track
    from exudyn_wheelrail.scenarios.probes import train_probes
    consist, V = a.consist, case.speed_m_s
    s_start = case.deck_start_m - float(consist.wheelset_x_m()[0])
    train, track = build_train_on_straight_track(mbs, consist, speed_m_s=V, s_start_m=s_start, structure=bridge)
    return train, train_probes(train, train.contact, track, V, case.deck_start_m, [])


def _load() -> list:
    return [round(v, 2) for v in os.getloadavg()]


def _finish(mbs, a, case, duration, contact, handle, probes, t_build0, extra):
    """Assemble, run through the runner, and the run's record."""
    import exudyn as exu

    from exudyn_wheelrail.simulation import status as S
    from exudyn_wheelrail.simulation.recorder import Recorder
    from exudyn_wheelrail.simulation.runner import run
    from exudyn_wheelrail.simulation.settings import RunSettings
    settings = RunSettings(solver="rk44", dt_s=a.dt, duration_s=duration)
    rec = Recorder(probes, n_rows_hint=settings.steps + 2)
    mbs.Assemble()
    contact.warm_up(mbs, jacobian=False)
    build_s = time.perf_counter() - t_build0
    sim, solver_type = run_solver_settings(settings)
    sim.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    load0, t0 = _load(), time.perf_counter()
    outcome = run(mbs, settings, contact, speed_m_s=case.speed_m_s, recorder=rec, exu_settings=(sim, solver_type))
    solve_s = time.perf_counter() - t0
    ts = rec.table()
    status = outcome.status
    deck_cols = ("deck_mid_z_m", "deck_mid_acc_m_s2")
    if status.ok and ts and not all(np.all(np.isfinite(ts[c])) for c in deck_cols):
        bad = ~np.all([np.isfinite(ts[c]) for c in deck_cols], axis=0)
        status = S.RunStatus(S.DIVERGED, time_s=float(ts["time_s"][int(np.argmax(bad))]),
                             detail="the deck state is not finite: the integration of the modes is unstable",
                             hint="reduce --dt")
    return ts, {"status": status.as_dict(), "build_s": round(build_s, 2), "solve_s": round(solve_s, 2),
                "load_before_solve": load0, "load_after_solve": _load(), "steps": settings.steps,
                "simulated_s": duration, "real_time_factor": round(solve_s / duration, 2), **extra}


def run_rigid(a, case, duration):
    """(a): the crossing's deck, rigid rails on its modes."""
    import exudyn as exu

    from exudyn_wheelrail.scenarios.bridge_crossing import deck_modes
    from exudyn_wheelrail.structures import add_bridge
    t0 = time.perf_counter()
    modes = deck_modes(case).modes
    mbs = exu.SystemContainer().AddSystem()
    bridge = add_bridge(mbs, modes, "modal", name="deck")
    train, probes = _build_train(mbs, a, case, bridge)
    phi_mid = modes.shape_at(case.deck_start_m + 0.5 * case.span_m)[1]
    b = _rail_centre_distance_m()
    probes = [_Deck(bridge, train.contact, phi_mid, modes.omega_rad_s ** 2, modes.modal_damping()),
              _RigidRails(train.contact, len(train.wheelsets), b)] + probes
    return _finish(mbs, a, case, duration, train.contact, bridge, probes, t0,
                   {"deck_modes": modes.n_modes, "deck_frequencies_Hz": [round(f, 3) for f in modes.frequencies_Hz],
                    "deck_mass_kg_m": case.mass_kg_m})


def _rail_centre_distance_m() -> float:
    from exudyn_wheelrail.track import TrackParameters
    return TrackParameters.from_file().rail_centre_distance_m


def track_on_deck_modes(case, s_from_m: float, s_to_m: float):
    """(b)'s reduced model: the crossing's deck less the track's mass, the ballasted track over the segment that
    carries the wheels from ``s_from_m`` to ``s_to_m`` and the whole span, with five decay lengths at both ends."""
    from exudyn_wheelrail.scenarios.bridge_crossing import ELEMENTS_PER_MODE, MIN_ELEMENTS, deck_section
    from exudyn_wheelrail.structures import BridgeModel
    from exudyn_wheelrail.track import TrackParameters
    from exudyn_wheelrail.track.flexible_segment import segment_for_run
    from exudyn_wheelrail.track.flexible_deck import TrackOnDeckModel
    params = TrackParameters.from_file()
    m_track = 2.0 * params.rail_mass_kg_m + params.sleeper_mass_kg / params.sleeper_spacing_m
    section = dataclasses.replace(deck_section(case), m_kg_m=case.mass_kg_m - m_track)
    deck = BridgeModel((case.span_m,), section, continuous=False, damping_ratio=case.damping_ratio, rail_height_m=0.0,
                       start_m=case.deck_start_m, elements_per_span=max(MIN_ELEMENTS, ELEMENTS_PER_MODE * case.n_modes))
    seg = segment_for_run(min(s_from_m, case.deck_start_m), max(s_to_m, case.deck_start_m + case.length_m), params)
    return TrackOnDeckModel(params, *seg, deck, BALLAST_HEIGHT_M).modes(), m_track


def ballasted_modes(a, case, duration) -> dict:
    """(b)'s reduced model for the run (:func:`track_on_deck_modes`) and the check of ``--dt`` against the wheel on
    the flexible rail (:class:`InputError`), before either run starts."""
    from exudyn_wheelrail.simulation.solvers import RK44
    from exudyn_wheelrail.track.flexible_contact import CONTACT_STIFFNESS_N_M, contact_mode_Hz
    t0 = time.perf_counter()
    x = a.consist.wheelset_x_m()
    s0 = case.deck_start_m - float(x[0])
    s_rear0, s_front1 = s0 + float(x.min()), s0 + case.speed_m_s * duration + float(x.max())
    modes, m_track = track_on_deck_modes(case, s_rear0, s_front1)
    f_c = contact_mode_Hz(modes, s_rear0, s_front1)
    if 2.0 * math.pi * f_c * a.dt >= RK44.imaginary_axis_limit:
        raise InputError(f"--dt: {a.dt:g} s: RK44 is unstable for the wheel on the flexible rail ({f_c:.0f} Hz at "
                         f"{CONTACT_STIFFNESS_N_M:.0e} N/m); use --dt <= "
                         f"{RK44.imaginary_axis_limit / (2.0 * math.pi * f_c):.2g}")
    return {"modes": modes, "m_track": m_track, "f_c": f_c, "modes_s": time.perf_counter() - t0}


def run_ballasted(a, case, duration, prepared):
    """(b): the ballasted track over the deck (``prepared``: :func:`ballasted_modes`)."""
    import exudyn as exu

    from exudyn_wheelrail.track.flexible import add_flexible_track
    from exudyn_wheelrail.scenarios.flexible_track import start_on_flexible_track
    t0 = time.perf_counter()
    modes, m_track, f_c, modes_s = (prepared[k] for k in ("modes", "m_track", "f_c", "modes_s"))
    mbs = exu.SystemContainer().AddSystem()
    handle = add_flexible_track(mbs, modes)
    train, probes = _build_train(mbs, a, case, handle)
    start_on_flexible_track(mbs, train, handle, contact=train.contact)
    phi_mid = modes.deck_shape_at(case.deck_start_m + 0.5 * case.span_m)[0, 1]
    probes = [_Deck(handle, train.contact, phi_mid, modes.omega_rad_s ** 2, modes.modal_damping()),
              _TrackUnderWheels(handle, train)] + probes
    mdl = modes.model
    return _finish(mbs, a, case, duration, train.contact, handle, probes, t0,
                   {"coupled_modes": modes.n_modes, "modes_up_to_Hz": modes.f_max_Hz, "modes_s": round(modes_s, 2),
                    "segment_start_m": mdl.start_m, "segment_length_m": mdl.length_m, "sleepers": mdl.n_sleepers,
                    "sleepers_on_deck": int(mdl.on_deck.sum()), "ballast_height_m": BALLAST_HEIGHT_M,
                    "deck_mass_kg_m": case.mass_kg_m - m_track, "track_mass_kg_m": m_track,
                    "wheel_on_rail_mode_Hz": round(f_c, 1), "track_file": mdl.params.source})


# ============================================================================================ evaluation
def _peak(v):
    v = np.asarray(v, dtype=float)
    return float(np.max(np.abs(v))) if v.size and np.all(np.isfinite(v)) else None


#: half-width of the zone around an abutment over which the transition is judged [m]
TRANSITION_HALF_WIDTH_M = 2.0


def _transitions(ts, ok, x_ws, case) -> dict:
    """Per abutment (``start``, ``end``): the largest change of a wheel's Q from its value at t = 0 (the static
    equilibrium on the embankment) while its wheelset is within :data:`TRANSITION_HALF_WIDTH_M` of the abutment,
    over all wheels (None when no wheelset passed it)."""
    if not ok or not ts:
        return {}
    from exudyn_wheelrail.simulation.recorder import SIDES
    out = {}
    for name, s_a in (("start", case.deck_start_m), ("end", case.deck_start_m + case.length_m)):
        worst = None
        for j, xj in enumerate(x_ws):
            s_j = ts["s_leading_m"] - (x_ws[0] - xj)
            m = np.abs(s_j - s_a) <= TRANSITION_HALF_WIDTH_M
            if not m.any():
                continue
            for side in SIDES:
                Q = ts[f"Q_w{j + 1}_{side}_N"]
                d = float(np.max(np.abs(Q[m] - Q[0])))
                worst = d if worst is None else max(worst, d)
        out[f"max_abs_dQ_near_{name}_abutment_N"] = worst
    return out


def _peaks(ts, ok, n_ws) -> dict:
    if not ok or not ts:
        return {"note": "the run did not end ok: peaks not evaluated"}
    from exudyn_wheelrail.simulation.recorder import SIDES
    out = {"max_deck_mid_z_m": _peak(np.maximum(ts["deck_mid_z_m"], 0.0)),
           "max_abs_deck_mid_acc_m_s2": _peak(ts["deck_mid_acc_m_s2"])}
    for q in ("Q", "Y"):
        out[f"max_abs_{q}_N"] = max(_peak(ts[f"{q}_w{j + 1}_{s}_N"]) for j in range(n_ws) for s in SIDES)
    out["min_Q_N"] = min(float(np.min(ts[f"Q_w{j + 1}_{s}_N"])) for j in range(n_ws) for s in SIDES)
    out["max_rail_z_m"] = max(float(np.max(ts[f"rail_z_w{j + 1}_{s}_m"])) for j in range(n_ws) for s in SIDES)
    if "pad_w1_right_N" in ts:
        for k in ("sleeper_z", "pad", "ballast"):
            unit = "m" if k == "sleeper_z" else "N"
            out[f"max_{k}_{unit}"] = max(float(np.nanmax(ts[f"{k}_w{j + 1}_{s}_{unit}"]))
                                         for j in range(n_ws) for s in SIDES)
        out["min_pad_N"] = min(float(np.nanmin(ts[f"pad_w{j + 1}_{s}_N"])) for j in range(n_ws) for s in SIDES)
    return out


def compare(peaks: dict) -> dict:
    """The peaks with (ballasted) and without (rigid) the track layer, their difference and ratio."""
    r, b = peaks["rigid"], peaks["ballasted"]
    out = {}
    for k in ("max_deck_mid_z_m", "max_abs_deck_mid_acc_m_s2", "max_abs_Q_N", "max_abs_Y_N", "min_Q_N",
              "max_rail_z_m", "max_abs_dQ_near_start_abutment_N", "max_abs_dQ_near_end_abutment_N"):
        if r.get(k) is not None and b.get(k) is not None:
            out[k] = {"rigid": r[k], "ballasted": b[k], "difference": b[k] - r[k],
                      "relative": (b[k] - r[k]) / abs(r[k]) if r[k] else None}
    return out


def figure(series: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(3, 1, figsize=(8.0, 9.0), sharex=True)
    for name, ts in series.items():
        if not ts:
            continue
        ax[0].plot(ts["time_s"], 1e3 * ts["deck_mid_z_m"], label=name)
        ax[1].plot(ts["time_s"], ts["deck_mid_acc_m_s2"], label=name, lw=0.6)
        ax[2].plot(ts["time_s"], 1e-3 * ts["Q_w1_right_N"], label=f"Q, {name}", lw=0.6)
    b = series.get("ballasted")
    if b:
        ax[2].plot(b["time_s"], 1e-3 * b["pad_w1_right_N"], label="pad (nearest sleeper), ballasted", lw=0.6)
        ax[2].plot(b["time_s"], 1e-3 * b["ballast_w1_right_N"], label="ballast (nearest sleeper), ballasted", lw=0.6)
        ax2 = ax[0].twinx()
        ax2.plot(b["time_s"], 1e3 * b["rail_z_w1_right_m"], "k:", lw=0.6, label="rail under w1 right, ballasted")
        ax2.plot(b["time_s"], 1e3 * b["sleeper_z_w1_right_m"], "g:", lw=0.6, label="sleeper seat, ballasted")
        ax2.set_ylabel("w1 right [mm]")
        ax2.legend(loc="lower right", fontsize=7)
    ax[0].set_ylabel("deck mid-span deflection [mm]")
    ax[1].set_ylabel("deck mid-span acc. [m/s²]")
    ax[2].set_ylabel("leading wheelset, right [kN]")
    ax[2].set_xlabel("time [s]")
    for x in ax:
        x.legend(fontsize=7, loc="upper left")
        x.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> dict:
    a = parse_args(argv)
    from exudyn_wheelrail.scenarios.outputs import write_csv, write_json
    deck = deck_inputs()
    case = _crossing_case(a, deck)
    duration = _duration_s(a, case)
    n_ws = len(a.consist.wheelset_x_m())
    print(f"{a.consist.name}: {n_ws} wheelsets, {case.speed_m_s * 3.6:g} km/h over the {case.span_m:g} m span, "
          f"{duration:.3f} s, RK44 {a.dt * 1e3:g} ms")
    try:
        prepared = ballasted_modes(a, case, duration)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        raise SystemExit(2) from None
    print(f"  {prepared['modes']} [{prepared['modes_s']:.1f} s]")
    a.out.mkdir(parents=True, exist_ok=True)
    series, runs, peaks = {}, {}, {}
    for name, fn in zip(RUNS, (run_rigid, lambda *args: run_ballasted(*args, prepared))):
        ts, info = fn(a, case, duration)
        series[name], runs[name] = ts, info
        ok = info["status"]["kind"] == "ok"
        peaks[name] = _peaks(ts, ok, n_ws) | _transitions(ts, ok, a.consist.wheelset_x_m(), case)
        write_csv(a.out / f"{name}.csv", ts)
        p = peaks[name]
        print(f"  {name:9s}: {info['status']['kind']}, solve {info['solve_s']:.1f} s (build {info['build_s']:.1f} s, "
              f"load {info['load_before_solve'][0]:.2f}); max deck deflection "
              + (f"{p['max_deck_mid_z_m'] * 1e3:.3f} mm, |a| {p['max_abs_deck_mid_acc_m_s2']:.3f} m/s2, max Q "
                 f"{p['max_abs_Q_N'] * 1e-3:.1f} kN" if "max_deck_mid_z_m" in p else p.get("note", "")))
    summary = {"deck": deck, "deck_modes_rigid": case.n_modes, "train": a.consist.name,
               "train_file": a.consist.file, "speed_km_h": case.speed_m_s * 3.6, "duration_s": duration,
               "dt_s": a.dt, "solver": "rk44", "runs": runs, "peaks": peaks,
               "comparison": compare(peaks) if all("max_deck_mid_z_m" in p for p in peaks.values()) else None,
               "exit_status": {k: v["status"]["kind"] for k, v in runs.items()}}
    write_json(a.out / "summary.json", summary)
    figure(series, a.out / "figure.png")
    c = summary["comparison"]
    if c:
        for k, v in c.items():
            print(f"  {k}: rigid {v['rigid']:.6g}, ballasted {v['ballasted']:.6g} ({v['relative'] * 100:+.2f} %)"
                  if v["relative"] is not None else f"  {k}: {v}")
    print(f"  outputs: {a.out}")
    return summary


if __name__ == "__main__":
    summary = main()
    from exudyn_wheelrail.simulation.status import exit_code
    raise SystemExit(exit_code(summary["exit_status"].values()))
