r"""The flexible track in a scenario (``[flexible_track]``): its keys, the segment that carries the run, the starting
state and the recorded columns.

Keys (all optional; the table's presence switches the flexible track on)
-------------------------------------------------------------------------
* ``file`` — a track file (TOML, :class:`~exudyn_wheelrail.track.flexible.TrackParameters`; relative to the scenario file); default the
  ballasted 60E1 track :data:`~exudyn_wheelrail.track.flexible_parameters.DEFAULT_TRACK_FILE`;
* ``start_m``, ``length_m`` — the segment (first sleeper, length in m), or ``"auto"`` (default): from the rearmost
  wheelset at t = 0 to the leading wheelset at the end of the run, plus five decay lengths at both ends
  (:func:`~exudyn_wheelrail.track.flexible_segment.segment_for_run`).  A given segment must carry every wheelset from start to end (else an
  error naming the key: a wheel leaving the segment would meet a rigid rail).  ``length_m = "window"``: a moving
  window (:mod:`exudyn_wheelrail.track.flexible_window`) of :func:`~exudyn_wheelrail.track.flexible_window.window_length_m` that travels with the vehicle —
  the modes and the cost per step do not depend on the run's length; ``start_m`` is then ``"auto"`` (or absent):
  the window starts five decay lengths behind the rearmost wheelset; explicit solvers only;
* ``shift_bays`` — with ``length_m = "window"``: the sleeper bays the window moves at a time (an integer >= 1,
  default :data:`~exudyn_wheelrail.track.flexible_window.DEFAULT_SHIFT_BAYS`; the window is that many bays longer than the vehicle and
  its margins need);
* ``modes_up_to_Hz`` — the modal truncation, default the track file's ``model.modes_up_to_Hz``.

The flexible track takes the contact's structure slot: it cannot be combined with a ``[structure]`` (the track on
a deck, :mod:`exudyn_wheelrail.track.flexible_deck`, is used from Python; the deck's columns and summary of a scenario read the bridge's
own modes).

Starting state (:func:`start_on_flexible_track`): the reduced track in static equilibrium under the static wheel
loads of the vehicle's load path (``q0 = diag(ω⁻²) Σ Φ(s_j)ᵀ F_j``, F_j the wheelset's vertical load and its roll
moment ``(b/2)(Q_right − Q_left)``), moving with the vehicle (``q̇0 = V diag(ω⁻²) Σ Φ'(s_j)ᵀ F_j``, the quasi-static
bowl), and every body of the vehicle moved by the rails' deflection under it (interpolated between the wheelsets)
— a run starts without a drop onto the track (tests/test_flexible_track.py: Q constant to 0.1 % on a stiff track).

Step check (explicit solvers, :func:`~exudyn_wheelrail.track.flexible_contact.contact_mode_Hz`): the highest kept mode and the wheel on the rail's modal mass
must satisfy ``ω dt < 2.83``; a step beyond is an error naming ``run.dt_s`` (or ``flexible_track.modes_up_to_Hz``)
before the run.  The creep damping on the rail's lateral modal mass sets a second limit that grows with the speed
(``σ h <= 2.785``, σ ~ f22 / (V m_rail)): the run monitor checks it at the first state
(:meth:`~exudyn_wheelrail.simulation.monitor.RunMonitor.creep_decay_rate_1_s`) and warns, naming the stable step.

Default step (:func:`default_step_s`): a scenario with a flexible track, an explicit solver and no ``run.dt_s``
runs at ``min(DEFAULT_STEP_CAP_S r, DEFAULT_STEP_MARGIN x CREEP_STEP_S_PER_M_S x V √r)`` with ``r = min(1,
STEP_REFERENCE_MODES_HZ / modes_up_to_Hz)``, at least :data:`DEFAULT_STEP_MIN_S` — the one place these numbers
are declared.  Both limits were found with modes to 800 Hz; more modes lower them: the highest kept mode in
proportion to the cut-off, the creep limit as the rails' inverse modal mass under a wheel grows, Σ φ_i² over the
kept modes, i.e. as their number — for bending modes (ω ~ k²) the square root of the cut-off.

Moving window (:func:`flexible_track_window`, after the contact is built): the runner's ``user_function``; the
recorded columns and the sleeper under a wheelset follow the window's current start.

Recorded columns (:func:`flexible_track_probes`, group ``flexible_track``; wheelset j = 1 leading): ``rail_z_w<j>_m``,
``rail_y_w<j>_m``, ``rail_roll_w<j>_rad`` (the rails' centre line under the wheelset, the contact's deck state),
and at the sleeper nearest to it ``sleeper_z_w<j>_m``, ``pad_left_w<j>_N``, ``pad_right_w<j>_N``,
``ballast_left_w<j>_N``, ``ballast_right_w<j>_N`` (compression positive).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..simulation.solvers import METHODS
from ..simulation.step_checks import check_explicit_step, flexible_track_limit
from ..structures.modal_shapes import modal_shape_and_slope_at
from ..track.flexible import FlexibleTrackModel
from ..track.flexible_parameters import DEFAULT_TRACK_FILE, TrackFileError, TrackParameters
from ..track.flexible_segment import segment_for_run
from ..track.flexible_window import (DEFAULT_SHIFT_BAYS, FlexibleTrackWindow, window_length_m, window_margin_m,
                                     window_start_m)

__all__ = ["FLEXIBLE_TRACK_KEYS", "FLEXIBLE_TRACK_GROUP", "AUTO", "WINDOW", "normalise_flexible_track",
           "flexible_track_modes", "flexible_track_window", "STEP_REFERENCE_MODES_HZ", "CREEP_STEP_S_PER_M_S",
           "DEFAULT_STEP_MARGIN", "DEFAULT_STEP_CAP_S", "DEFAULT_STEP_MIN_S", "default_step_s",
           "start_on_flexible_track", "flexible_track_probes", "flexible_track_summary"]

FLEXIBLE_TRACK_KEYS = ("file", "start_m", "length_m", "modes_up_to_Hz", "shift_bays")
#: the recorder group of the flexible track's columns
FLEXIBLE_TRACK_GROUP = "flexible_track"
AUTO = "auto"
#: ``length_m = "window"``: the moving window (:mod:`exudyn_wheelrail.track.flexible_window`)
WINDOW = "window"

# ---- the default explicit step of a flexible-track scenario (default_step_s): declared here only -----------------
#: the track's mode cut-off [Hz] at which the limits below were found (their scaling above it: module docstring)
STEP_REFERENCE_MODES_HZ = 800.0
#: the creep-damping limit of RK44 per unit speed [s per m/s]: the Manchester vehicle (56 kN wheels, S1002 on 60E1
#: 1:40) on the shipped ballasted track (modes to 800 Hz, 62 kg lateral modal mass of the rails per wheelset) with
#: Kalker's linear law was stable at 0.105 ms and diverged at 0.110 ms at 50 km/h (13.9 m/s), and stable at 0.22 ms,
#: diverged at 0.23 ms at 100 km/h (the limit proportional to V); the monitor's estimate gives 0.111 and 0.222 ms
CREEP_STEP_S_PER_M_S = 0.105e-3 / (50.0 / 3.6)
#: the default step's share of that limit: the creep coefficient grows with the patch area a b ~ N^(2/3), so 0.5
#: covers wheel loads up to 0.5^(-3/2) = 2.8 times the Manchester vehicle's (158 kN) on the shipped track
DEFAULT_STEP_MARGIN = 0.5
#: the largest default step [s] (modes to 800 Hz: the wheel on the rail's modal mass allows 0.46 ms, the check of
#: :func:`~exudyn_wheelrail.simulation.step_checks.check_explicit_step`); scaled by 800 Hz / ``modes_up_to_Hz`` for a higher cut-off
DEFAULT_STEP_CAP_S = 0.4e-3
#: the smallest default step [s] (it takes over below 9.5 km/h with modes to 800 Hz, where the creep limit falls
#: further; give ``run.dt_s`` there)
DEFAULT_STEP_MIN_S = 1.0e-5


def default_step_s(speed_m_s: float, modes_up_to_Hz: float) -> float:
    """The RK44 step of a flexible-track scenario that gives no ``run.dt_s`` [s]: the creep-damping limit
    :data:`CREEP_STEP_S_PER_M_S` x V times :data:`DEFAULT_STEP_MARGIN`, at most :data:`DEFAULT_STEP_CAP_S`, the two
    scaled for a cut-off above :data:`STEP_REFERENCE_MODES_HZ` (module docstring), at least
    :data:`DEFAULT_STEP_MIN_S`; rounded down to whole microseconds."""
    r = min(1.0, STEP_REFERENCE_MODES_HZ / float(modes_up_to_Hz))
    h = min(DEFAULT_STEP_CAP_S * r, DEFAULT_STEP_MARGIN * CREEP_STEP_S_PER_M_S * abs(float(speed_m_s)) * math.sqrt(r))
    return max(DEFAULT_STEP_MIN_S, math.floor(h * 1e6 + 1e-9) / 1e6)


def normalise_flexible_track(ft, error, base_dir: Path | None) -> dict:
    """The normal form of a ``[flexible_track]`` table; ``error(key, message)`` makes the scenario's error.  The
    track file is read here, so that its errors come before any work."""
    if not isinstance(ft, dict):
        raise error("flexible_track", f"expected a table, got {type(ft).__name__} {ft!r}")
    for k in ft:
        if k not in FLEXIBLE_TRACK_KEYS:
            raise error(f"flexible_track.{k}", f"unknown key (allowed in [flexible_track]: "
                                               f"{', '.join(FLEXIBLE_TRACK_KEYS)})")
    f = ft.get("file", str(DEFAULT_TRACK_FILE))
    if not isinstance(f, str):
        raise error("flexible_track.file", f"expected a string, got {f!r}")
    p = Path(f)
    if not p.is_absolute() and base_dir is not None:
        p = Path(base_dir) / p
    if not p.is_file():
        raise error("flexible_track.file", f"file not found: {p}")
    try:
        params = TrackParameters.from_file(p)
    except TrackFileError as exc:
        raise error("flexible_track.file", str(exc)) from None
    out = {"file": str(p.resolve())}
    for key in ("start_m", "length_m"):
        v = ft.get(key, AUTO)
        if v == WINDOW and key == "length_m":
            out[key] = v
            continue
        if v != AUTO:
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise error(f"flexible_track.{key}", f"{v!r}: expected a number in m or 'auto'"
                                                     + (" or 'window'" if key == "length_m" else ""))
            v = float(v)
        out[key] = v
    if out["length_m"] == WINDOW:
        if out["start_m"] != AUTO:
            raise error("flexible_track.start_m", f"{out['start_m']!r}: a moving window (length_m = 'window') places "
                                                  "itself; leave start_m out (or 'auto')")
        sb = ft.get("shift_bays", DEFAULT_SHIFT_BAYS)
        if isinstance(sb, bool) or not isinstance(sb, int) or sb < 1:
            raise error("flexible_track.shift_bays", f"{sb!r}: expected a whole number of sleeper bays >= 1")
        out["shift_bays"] = sb
    elif "shift_bays" in ft:
        raise error("flexible_track.shift_bays", "only with length_m = 'window' (a fixed segment does not move)")
    if (out["start_m"] == AUTO) != (out["length_m"] in (AUTO, WINDOW)):
        raise error("flexible_track.length_m", "give both start_m and length_m, or neither ('auto')")
    if out["length_m"] not in (AUTO, WINDOW) and out["length_m"] < 2.0 * params.sleeper_spacing_m:
        raise error("flexible_track.length_m", f"{out['length_m']!r} m: shorter than two sleeper bays "
                                               f"({2.0 * params.sleeper_spacing_m:g} m)")
    fm = ft.get("modes_up_to_Hz", params.modes_up_to_Hz)
    if isinstance(fm, bool) or not isinstance(fm, (int, float)) or not (math.isfinite(fm) and fm > 0.0):
        raise error("flexible_track.modes_up_to_Hz", f"{fm!r}: expected a frequency > 0 Hz")
    out["modes_up_to_Hz"] = float(fm)
    return out


def flexible_track_modes(ft: dict, *, s_start_m: float, wheelset_x_m, speed_m_s: float, end_time_s: float,
                         solver: str, dt_s: float, moving_window: bool = False):
    """The :class:`~exudyn_wheelrail.track.flexible.FlexibleTrackModes` of a normalised ``[flexible_track]`` for a run: the segment
    (given or ``auto``) checked to carry every wheelset from t = 0 to ``end_time_s``, or the moving window
    (``length_m = "window"``: its length for these wheelsets, placed behind the rearmost; the caller declares with
    ``moving_window=True`` that it attaches :func:`flexible_track_window` to the run, else an error: without it
    the wheels would leave the window), and the highest kept mode checked against the explicit solver's
    stability."""
    params = TrackParameters.from_file(ft["file"])
    x = np.asarray(wheelset_x_m, dtype=float)
    s_rear0 = s_start_m + float(x.min())
    s_front1 = s_start_m + speed_m_s * end_time_s + float(x.max())
    if ft["length_m"] == WINDOW:
        if not moving_window:
            raise TrackFileError("flexible_track.length_m = 'window': this build does not move the window with the "
                                 "vehicle (flexible_track_modes(..., moving_window=True) and flexible_track_window)")
        if METHODS[solver].implicit:
            raise TrackFileError(f"flexible_track.length_m = 'window': run.solver = {solver!r}: the moving window "
                                 "carries q and dq/dt over; use an explicit solver ('rk44')")
        start = window_start_m(params, s_rear0)
        length = window_length_m(params, x, ft["shift_bays"])
        m = window_margin_m(params)
        s_rear0, s_front1 = start + m, start + length - m             # the wheels' path within the window
    elif ft["length_m"] == AUTO:
        start, length = segment_for_run(s_rear0, s_front1, params)
    else:
        start, length = ft["start_m"], ft["length_m"]
        if s_rear0 < start or s_front1 > start + length:
            raise TrackFileError(f"flexible_track.length_m = {length:g} m (start_m = {start:g} m): the segment "
                                 f"[{start:g}, {start + length:g}] m does not carry the run, whose wheelsets span "
                                 f"[{s_rear0:.6g}, {s_front1:.6g}] m (the track is shorter than the vehicle's path)")
    limit = flexible_track_limit(solver)                         # before the modes are computed
    if limit is not None:
        f_lim = limit / (2.0 * math.pi * dt_s)
        if ft["modes_up_to_Hz"] >= f_lim:
            raise TrackFileError(f"flexible_track.modes_up_to_Hz = {ft['modes_up_to_Hz']:g} Hz: explicit {solver} at "
                                 f"run.dt_s = {dt_s:g} s is unstable above {f_lim:.4g} Hz (omega dt = {limit:.3g}); "
                                 "use run.solver = 'newmark' or a smaller step")
    modes = FlexibleTrackModel(params, start, length).modes(f_max_Hz=ft["modes_up_to_Hz"])
    check_explicit_step(modes, solver, dt_s, s_rear0, s_front1)
    return modes


def flexible_track_window(ft: dict, *, contact, handle, t_start_s: float = 0.0, then=None):
    """The :class:`~exudyn_wheelrail.track.flexible_window.FlexibleTrackWindow` of a normalised ``[flexible_track]`` with
    ``length_m = "window"`` (None for a fixed segment): create after the contact, pass as the runner's
    ``user_function`` (``then``: a further one called after it) and to :func:`flexible_track_probes`."""
    if ft["length_m"] != WINDOW:
        return None
    return FlexibleTrackWindow(handle, contact, shift_bays=ft["shift_bays"], t_start_s=t_start_s, then=then)


def _static_wheelset_forces(model, modes) -> np.ndarray:
    """Per wheelset ``(Fy, Fz, Mx)`` on the rails from the static wheel loads (left, right) of the load path."""
    b = modes.model.params.rail_centre_distance_m
    Q = np.asarray(model.load_path.wheel, dtype=float)                  # (n_ws, 2): left, right
    return np.column_stack([np.zeros(len(Q)), Q.sum(axis=1), 0.5 * b * (Q[:, 1] - Q[:, 0])])


def start_on_flexible_track(mbs, model, track_handle, contact=None) -> float:
    """Starting state (module docstring): the track's modal coordinates and rates, and the vehicle's bodies moved
    by the static deflection of the rails (lateral and vertical), each body by the deflection interpolated at its
    centre of mass between the wheelsets (the deflections differ by micrometres between wheelsets: no pitch is
    added).  With the wheel–rail ``contact`` given, the static loads are also its prediction of the rail loads
    (:meth:`~exudyn_wheelrail.multibody.connector.WheelRailContact.predict_rail_loads`: one contact-geometry pass
    per call with the static correction).  Call after the vehicle is placed on the rails, before
    ``mbs.Assemble()``.  Returns the largest static deflection under a wheelset [m]."""
    modes = track_handle.modes
    x = np.array([ws.p_cg_in_frame[0] for ws in model.wheelsets])
    s = model.track_distance_m(x, 0.0)
    F = _static_wheelset_forces(model, modes)
    if contact is not None:
        contact.predict_rail_loads(F)
    phi, dphi = _shape_and_slope(modes, s)
    w2 = modes.omega_rad_s ** 2
    q0 = np.einsum("kij,ki->j", phi, F) / w2
    q0_t = model.speed_m_s * np.einsum("kij,ki->j", dphi, F) / w2
    mbs.SetNodeParameter(track_handle.modal_node, "initialCoordinates", q0.tolist())
    mbs.SetNodeParameter(track_handle.modal_node, "initialCoordinates_t", q0_t.tolist())
    d = phi @ q0                                                         # (n_ws, 3): y, z, roll under each
    residual = getattr(modes, "residual_at", None)
    if residual is not None:                                             # the static correction's deflection
        d = d + np.einsum("kij,kj->ki", residual(s), F)
    order = np.argsort(x)
    for body in model.bodies:
        xc = float(body.p_cg_in_frame[0])
        q = np.array(mbs.GetNodeParameter(body.node, "initialCoordinates"), dtype=float)
        q[1] += float(np.interp(xc, x[order], d[order, 0]))
        q[2] += float(np.interp(xc, x[order], d[order, 1]))
        mbs.SetNodeParameter(body.node, "initialCoordinates", q.tolist())
    return float(np.max(np.abs(d[:, 1])))


def _shape_and_slope(modes, s):
    phi = np.empty((len(s), 3, modes.n_modes))
    dphi = np.empty_like(phi)
    for i, x in enumerate(s):
        modal_shape_and_slope_at(float(x), *modes.table, phi[i], dphi[i])
    return phi, dphi


class _TrackColumns:
    """Recorder probe of the ``flexible_track`` group (module docstring)."""

    def __init__(self, contact, handle, model, window=None):
        self.c, self.h, self.model, self.window = contact, handle, model, window
        self.modes = handle.modes
        self.x = np.array([ws.p_cg_in_frame[0] for ws in model.wheelsets])
        n = len(self.x)
        names = []
        for j in range(n):
            names += [f"rail_z_w{j + 1}_m", f"rail_y_w{j + 1}_m", f"rail_roll_w{j + 1}_rad", f"sleeper_z_w{j + 1}_m",
                      f"pad_left_w{j + 1}_N", f"pad_right_w{j + 1}_N", f"ballast_left_w{j + 1}_N",
                      f"ballast_right_w{j + 1}_N"]
        self.columns = [(FLEXIBLE_TRACK_GROUP, c) for c in names]

    def fill(self, mbs, t, out):
        q, q_t = self.h.coordinates(mbs)
        st = self.c.deck_state()
        mdl = self.modes.model
        s = self.model.track_distance_m(self.x, t)
        if self.window is not None:                  # the sleepers of the window at its current position
            k = self.window.sleeper_index(s)
        else:
            k = mdl.nearest_sleeper(s)
        for j in range(len(self.x)):
            a, b = self._rows(int(k[j]))
            out[8 * j:8 * j + 3] = (st[j, 1], st[j, 0], st[j, 2])
            out[8 * j + 3:8 * j + 8] = a @ q + b @ q_t

    #: the sleeper quantities of a row, in the columns' order: (method, key)
    _SLEEPER_OUTPUTS = (("sleeper_state", "z_m"), ("support_forces_N", "pad_vertical_left_N"),
                        ("support_forces_N", "pad_vertical_right_N"), ("support_forces_N", "ballast_vertical_left_N"),
                        ("support_forces_N", "ballast_vertical_right_N"))

    def _rows(self, j: int):
        """``(A, B)`` (5, n_modes): sleeper j's displacement, pad and ballast forces = ``A q + B q̇`` — the modes'
        own output functions (linear) applied to the identity once per sleeper the wheels meet."""
        cache = self.__dict__.setdefault("_cache", {})
        if j not in cache:
            n = self.modes.n_modes
            eye, zero = np.eye(n), np.zeros((n, n))
            f_q = self.modes.support_forces_N(eye, zero, [j])
            f_v = self.modes.support_forces_N(zero, eye, [j])
            z = self.modes.sleeper_state(eye, [j])["z_m"]
            a = np.array([z[0] if m == "sleeper_state" else f_q[key][0] for m, key in self._SLEEPER_OUTPUTS])
            b = np.array([np.zeros(n) if m == "sleeper_state" else f_v[key][0] for m, key in self._SLEEPER_OUTPUTS])
            cache[j] = (np.ascontiguousarray(a), np.ascontiguousarray(b))
        return cache[j]


def flexible_track_probes(*, contact, handle, model, window=None) -> list:
    """The recorder probes of the flexible track (module docstring); ``window``: the moving window
    (:func:`flexible_track_window`), whose current position the sleeper columns follow."""
    return [_TrackColumns(contact, handle, model, window)]


def flexible_track_summary(modes, window=None) -> dict:
    """The segment and the reduced model, for a run's summary; with a moving ``window`` its moves and its final
    position (``start_m``: where it starts now)."""
    mdl = modes.model
    n = {k: modes.slices[k].stop - modes.slices[k].start for k in modes.slices}
    extra = {} if window is None else {"window": window.summary()}
    return {**extra, "file": mdl.params.source, "start_m": mdl.start_m if window is None else window.start_m,
            "length_m": mdl.length_m,
            "sleepers": mdl.n_sleepers, "modes_up_to_Hz": modes.f_max_Hz, "modes": modes.n_modes,
            "modes_by_kind": n, "damping": modes.damping,
            "static_correction": bool(getattr(modes, "static_correction", False)),
            "not_represented": "gauge spreading (both rails move together laterally), rail torsion and roll on its "
                               "pad, sleeper bending, the dynamics of the modes above modes_up_to_Hz (pinned-pinned, "
                               "P1 contact resonance; with the static correction their static flexibility is kept "
                               "in series with the contacts); the track is rigid off the segment"}
