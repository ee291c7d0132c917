r"""Recording a run: one row per recorded state, the columns given by **probes**, each probe a group of columns of
one kind; and the progress bar.

The runner (:mod:`.runner`) calls :meth:`Recorder.record` for every accepted state on the recording grid (every
``record_every``-th multiple of ``dt_s``), *after* the run monitor has evaluated the contact at that state: the
probes read the connector's results of that evaluation (``results``, ``wheelset_rail_pose``; the wheels' columns in
one compiled call, :func:`wheel_columns`) and Exudyn's outputs of the bodies — the contact is never evaluated twice
for one state.  A row is filled in place and copied into the table once.

Column groups (:data:`GROUPS`, in the order the columns are stored; wheelset j = 1 leading, wheel ``<side>`` right
or left looking in the running direction; track frame of :mod:`exudyn_wheelrail.conventions`: x forward, y right,
z down):

* ``Y`` ``Y_w<j>_<side>_N`` — y component of the total contact force (normal + creep, both regions) of the rail
  **on** the wheel; ``Q`` ``Q_w<j>_<side>_N`` — the wheel load −F_z (positive pressing);
  ``YQ`` ``YQ_w<j>_<side>`` — Y towards the wheel's field side (−F_y right, +F_y left) over Q, NaN when lifted;
  ``flange`` ``flange_w<j>_<side>`` — 1 when the wheel's flange region carries a contact;
  ``contact_angle`` ``contact_angle_w<j>_<side>_rad`` — contact angle of the most loaded region (NaN: lifted);
* ``wheelset_lateral`` ``y_rel_w<j>_m`` — lateral displacement of the axle centre relative to its rails' centre
  line (irregularity and deck included; what the contact search used);
* ``track`` ``track_lateral_w<j>_m``, ``track_vertical_w<j>_m`` — the track irregularity (y, z) under wheelset j;
* ``carbody`` per car-body point p: ``carbody_lateral_acceleration_<p>_m_s2``, ``carbody_vertical_acceleration_
  <p>_m_s2`` (track frame, kinematic: no gravity; Exudyn's rigid-body ``Acceleration`` output at the point; a
  flexible car body: its frame's and modes' motion at the point, :class:`~..rolling_stock.flexible_body.
  BodyPointKinematics`, the accelerometer then in the axes of the deformed section; a rigid car body's points are
  read by Exudyn sensors stored in memory when the probes are built with the model's ``mbs``: the same outputs,
  no Python call per state),
  ``carbody_lateral_accelerometer_<p>_m_s2``, ``carbody_vertical_accelerometer_<p>_m_s2`` (the specific force
  a − g in the car body's own axes: what a floor accelerometer reads; ≈ −9.81 vertical at rest),
  ``carbody_lateral_displacement_<p>_m``, ``carbody_vertical_displacement_<p>_m`` (track frame);
* ``deck`` per span i: ``deck_mid_deflection_s<i>_m``, ``deck_mid_acceleration_s<i>_m_s2`` (vertical, + down, at
  mid-span on the track centre line; the acceleration from the modal equations at the state,
  q̈ = Q − diag(2ζω) q̇ − diag(ω²) q).

``time_s`` and ``s_leading_m`` (track distance of the leading wheelset) are always recorded.
"""
from __future__ import annotations

import math
import sys
import time

import numpy as np

from ..contact.layout import N_SLOTS, RES_F_TRACK_Y, RES_F_TRACK_Z, RES_GAMMA, RES_N, RES_STATUS, SLOT_FLANGE
from ..jit import compiled
from ..rolling_stock.flexible_body import BodyPointKinematics
from ..track.rigid import irregularity_at

__all__ = ["GROUPS", "SIDES", "Recorder", "ProgressBar", "PROGRESS_MIN_STEPS", "vehicle_probes"]

#: column groups, in the order they are stored
GROUPS = ("Y", "Q", "YQ", "flange", "contact_angle", "wheelset_lateral", "track", "carbody", "deck")
SIDES = ("right", "left")            # wheel 2k right, 2k+1 left (the connector's order)
#: runs with at least this many steps get the progress bar (shorter runs finish before it would help)
PROGRESS_MIN_STEPS = 200


class Recorder:
    """Rows of the ``probes``' columns, one per :meth:`record` call; ``time_s`` first.  A probe has ``columns``
    (a list of ``(group, name)``) and either ``fill(mbs, t, row)`` writing its slice of the row of a state, or —
    for columns that are a function of the time alone, or that Exudyn's sensors stored during the run —
    ``fill_rows(t, rows)`` writing its columns of many rows at once (``t`` (m,), ``rows`` (m, k)); those are filled
    by :meth:`complete` (the runner calls it at the end of a solve; reading :attr:`data` does too)."""

    def __init__(self, probes, n_rows_hint: int = 64):
        self.probes = list(probes)
        self.columns = ["time_s"]
        self.groups = {}
        self._slices = []
        for p in self.probes:
            start = len(self.columns)
            for group, name in p.columns:
                self.columns.append(name)
                self.groups.setdefault(group, []).append(name)
            self._slices.append(slice(start, len(self.columns)))
        self._data = np.full((max(1, int(n_rows_hint)), len(self.columns)), np.nan)
        self.n = 0
        self._n_complete = 0                                   # rows whose time-only columns are filled
        self._row = np.full(len(self.columns), np.nan)          # the row being filled; its slices per probe
        self._fills = [(p.fill, self._row[sl]) for p, sl in zip(self.probes, self._slices)
                       if not hasattr(p, "fill_rows")]
        self._time_only = [(p, sl) for p, sl in zip(self.probes, self._slices) if hasattr(p, "fill_rows")]

    def record(self, mbs, t: float) -> None:
        if self.n >= self._data.shape[0]:
            self._grow(2 * self._data.shape[0])
        row = self._row
        row.fill(np.nan)
        row[0] = t
        for fill, out in self._fills:
            fill(mbs, t, out)
        self._data[self.n] = row
        self.n += 1

    def watched_columns(self, contact, reserve: int = 0):
        """For the compiled force call's watch (:mod:`.watch`) of ``contact``: ``(table, first wheel column, first
        wheelset column, first deck column, the deck probe's rows)`` (a column -1: not recorded; the rows a
        :class:`~..structures.deck_response.DeckRowArrays`, or None without a watched deck probe) with room for
        ``reserve`` more rows — the table it writes the rows of those probes into (:meth:`take_watched` then counts
        them) —, or None when a probe fills its columns from Python at every state (or reads another contact)."""
        cols = {"wheels": -1, "wheelset_lateral": -1, "deck": -1}
        deck = None
        for p, sl in zip(self.probes, self._slices):
            if hasattr(p, "fill_rows"):
                continue
            kind = getattr(p, "watched", None)
            if kind not in cols or cols[kind] >= 0 or p.c is not contact:
                return None
            cols[kind] = sl.start
            if kind == "deck":
                deck = p.rows
        if reserve and self._data.shape[0] < self.n + reserve:
            self._grow(self.n + int(reserve))
        return self._data, cols["wheels"], cols["wheelset_lateral"], cols["deck"], deck

    def _grow(self, rows: int) -> None:
        """The table with ``rows`` rows, its rows so far kept, the new ones NaN."""
        grown = np.full((rows, self._data.shape[1]), np.nan)
        grown[:self.n] = self._data[:self.n]
        self._data = grown

    def take_watched(self, n: int) -> None:
        """The table holds ``n`` rows (written by the watch, :meth:`watched_columns`)."""
        self.n = int(n)
        self._n_complete = min(self._n_complete, self.n)

    def complete(self) -> None:
        """Fill the ``fill_rows`` columns of the rows recorded since the last call."""
        if self._n_complete < self.n:
            rows = slice(self._n_complete, self.n)
            t = self._data[rows, 0]
            for p, sl in self._time_only:
                p.fill_rows(t, self._data[rows, sl])            # a view: written in place
            self._n_complete = self.n

    @property
    def data(self) -> np.ndarray:
        """The table (rows ``[:n]`` are the recorded states), every column filled."""
        self.complete()
        return self._data

    @property
    def last_time_s(self) -> float | None:
        return float(self._data[self.n - 1, 0]) if self.n else None

    def keep_until(self, t_s: float) -> int:
        """Drop the rows after ``t_s`` (inclusive bound); returns how many were dropped."""
        keep = int(np.searchsorted(self._data[:self.n, 0], t_s + 1e-12, side="right"))
        dropped = self.n - keep
        self.n = keep
        self._n_complete = min(self._n_complete, keep)
        return dropped

    def table(self) -> dict:
        d = self.data[:self.n]
        return {name: d[:, i].copy() for i, name in enumerate(self.columns)}


# ============================================================================================== probes
class _TrackDistance:
    """``s_leading_m``: track distance of the leading wheelset, ``s0 + V t``."""

    def __init__(self, s_leading0_m: float, speed_m_s: float):
        self.s0, self.V = float(s_leading0_m), float(speed_m_s)
        self.columns = [("", "s_leading_m")]

    def fill_rows(self, t, rows):
        rows[:, 0] = self.s0 + self.V * t


@compiled(inline="always")
def wheel_force_yz(res, w):
    """Track-frame y and z components [N] of the total contact force of the rail on wheel ``w`` (the sum over its
    slots in slot order, as :meth:`~exudyn_wheelrail.multibody.connector.WheelRailContact.wheel_force_N`) and the
    lateral force towards the wheel's field side (wheel ``2k`` the right one: ``-F_y``; ``2k+1`` the left: ``F_y``)."""
    fy = res[w, 0, RES_F_TRACK_Y]
    fz = res[w, 0, RES_F_TRACK_Z]
    for j in range(1, N_SLOTS):
        fy = fy + res[w, j, RES_F_TRACK_Y]
        fz = fz + res[w, j, RES_F_TRACK_Z]
    return fy, fz, (-fy if w % 2 == 0 else fy)


@compiled(refcount=False)
def wheel_columns(res, out):
    """The ``_Wheels`` columns of one state from the connector's results ``res`` (2 n, N_SLOTS, N_RES) into
    ``out`` (5 x 2 n: Y, Q, YQ, flange, contact angle per wheel); sums over the slots in slot order, as
    :meth:`~exudyn_wheelrail.multibody.connector.WheelRailContact.wheel_force_N`."""
    n_w = res.shape[0]
    for w in range(n_w):
        fy, fz, y_out = wheel_force_yz(res, w)
        q = -fz + 0.0                                         # no -0.0
        out[w] = fy
        out[n_w + w] = q
        out[2 * n_w + w] = y_out / q if q > 0.0 else math.nan
        out[3 * n_w + w] = 1.0 if (res[w, SLOT_FLANGE, RES_STATUS] > 0 and res[w, SLOT_FLANGE, RES_N] > 0.0) \
            else 0.0
        reg = 0                                               # the most loaded region (first maximum, first NaN)
        for j in range(1, N_SLOTS):
            a = res[w, reg, RES_N]
            b = res[w, j, RES_N]
            if a == a and (b != b or b > a):
                reg = j
        out[4 * n_w + w] = res[w, reg, RES_GAMMA] if res[w, reg, RES_N] > 0.0 else math.nan


class _Wheels:
    """Groups ``Y``, ``Q``, ``YQ``, ``flange``, ``contact_angle`` of every wheel, from the contact's results (one
    compiled call, :func:`wheel_columns`)."""

    def __init__(self, contact, n_wheelsets: int):
        self.c = contact
        self.n = int(n_wheelsets)
        if contact.results.shape[0] != 2 * self.n:     # the compiled fill does not check bounds
            raise ValueError(f"the recorder expects {self.n} wheelsets but the contact couples "
                             f"{contact.results.shape[0] // 2}: give it the model whose wheelsets the contact couples")
        wheels = [(j, side) for j in range(self.n) for side in SIDES]
        self.columns = ([("Y", f"Y_w{j + 1}_{s}_N") for j, s in wheels]
                        + [("Q", f"Q_w{j + 1}_{s}_N") for j, s in wheels]
                        + [("YQ", f"YQ_w{j + 1}_{s}") for j, s in wheels]
                        + [("flange", f"flange_w{j + 1}_{s}") for j, s in wheels]
                        + [("contact_angle", f"contact_angle_w{j + 1}_{s}_rad") for j, s in wheels])
        wheel_columns(np.zeros_like(contact.results), np.zeros(len(self.columns)))  # loaded here, not in the solve
        self.watched = "wheels"                        # the watch (watch.py) fills these columns in its call

    def fill(self, mbs, t, out):
        wheel_columns(self.c.results, out)


class _WheelsetLateral:
    """``y_rel_w<j>_m`` from the contact search's wheelset–rail pose (the first column of
    :meth:`~..multibody.connector.WheelRailContact.wheelset_rail_pose`: the right wheels' ``c_y`` plus the half
    gauge, added into the row from views of the connector's arrays taken once)."""

    def __init__(self, contact, n_wheelsets: int):
        self.c = contact
        self.columns = [("wheelset_lateral", f"y_rel_w{j + 1}_m") for j in range(n_wheelsets)]
        pose_arrays = getattr(contact, "rail_pose_arrays", None)
        if pose_arrays is not None:
            side_poses, half_gauge = pose_arrays()
            self._c_y, self._half_gauge = side_poses[0::2, 0], half_gauge
            self.fill = self._fill_views
            self.watched = "wheelset_lateral"          # as the watch (watch.py) fills them in its call

    def fill(self, mbs, t, out):
        out[:] = self.c.wheelset_rail_pose()[:, 0]

    def _fill_views(self, mbs, t, out):
        np.add(self._c_y, self._half_gauge, out=out)


@compiled
def track_columns(rows, knots, coefs, s, out):
    """The irregularity (y, z) at the track distances ``s`` (m, n) into ``out`` (m, 2 n): y for every wheelset, then
    z."""
    n = s.shape[1]
    for i in range(s.shape[0]):
        for j in range(n):
            v = irregularity_at(rows, knots, coefs, s[i, j])
            out[i, j] = v[0]
            out[i, n + j] = v[3]


class _Track:
    """``track_lateral_w<j>_m``, ``track_vertical_w<j>_m``: the irregularity under each wheelset (a function of the
    time: filled for all rows at once)."""

    def __init__(self, model, track):
        self.model = model
        self.x = np.array([float(ws.p_cg_in_frame[0]) for ws in model.wheelsets])
        p = track.packed()
        self.packed = (p.rows, p.knots, p.coefs)
        n = len(self.x)
        self.columns = ([("track", f"track_lateral_w{j + 1}_m") for j in range(n)]
                        + [("track", f"track_vertical_w{j + 1}_m") for j in range(n)])

    def fill_rows(self, t, rows):
        s = self.model.track_distance_m(self.x[None, :], np.asarray(t)[:, None])      # (m, n)
        out = np.empty((len(t), 2 * len(self.x)))
        track_columns(*self.packed, np.ascontiguousarray(s, dtype=float), out)
        rows[:] = out


class _CarBodyPoints:
    """Accelerations, accelerometer readings and displacements of points fixed to the car body.

    Given ``mbs`` (before ``mbs.Assemble()``), a rigid car body's points are read by Exudyn sensors stored in memory
    (``SensorBody``: per point ``Acceleration`` and ``Displacement``, and the body's ``RotationMatrix``; the same
    outputs as ``GetObjectOutputBody``, evaluated by Exudyn after every step), and the columns are filled when the
    table is read (``fill_rows``) — no Python call per recorded state.  Otherwise (or a flexible car body)
    every recorded state reads the body's outputs (:meth:`fill`)."""

    def __init__(self, model, points, mbs=None):
        import exudyn as exu
        ovt = exu.OutputVariableType
        self._rotation, self._acceleration, self._displacement = (ovt.RotationMatrix, ovt.Acceleration,
                                                                  ovt.Displacement)
        cb = model.car_body
        self.body = cb.body
        self.gravity = np.array([0.0, 0.0, model.gravity_m_s2])
        self.local = [(np.asarray(pos, dtype=float) - cb.p_cg_in_frame).tolist() for _, pos in points]
        self.flexible = None
        self.sensors = None
        if getattr(cb, "flexible", None) is not None:     # flexible car body: frame + modal motion at the points
            self.flexible = BodyPointKinematics(cb, self.local)
            self.fill = self._fill_flexible
        elif mbs is not None:
            from exudyn.itemInterface import SensorBody

            def sensor(variable, loc=(0.0, 0.0, 0.0)):
                return mbs.AddSensor(SensorBody(bodyNumber=self.body, localPosition=list(loc),
                                                outputVariableType=variable, storeInternal=True))
            self.mbs = mbs
            self.sensors = ([(sensor(self._acceleration, loc), sensor(self._displacement, loc)) for loc in self.local],
                            sensor(self._rotation))
            self.fill_rows = self._fill_stored
        self.columns = []
        for name, _ in points:
            self.columns += [("carbody", f"carbody_{d}_{q}_{name}_{u}")
                             for q, u in (("acceleration", "m_s2"), ("accelerometer", "m_s2"), ("displacement", "m"))
                             for d in ("lateral", "vertical")]

    def fill(self, mbs, t, out):
        output = mbs.GetObjectOutputBody               # (body, variable, local position): three calls per point
        body = self.body
        R = np.asarray(output(body, self._rotation)).reshape(3, 3)
        k = 0
        for loc in self.local:
            a = np.asarray(output(body, self._acceleration, loc))
            u = np.asarray(output(body, self._displacement, loc))
            f = R.T @ (a - self.gravity)
            out[k] = a[1]
            out[k + 1] = a[2]
            out[k + 2] = f[1]
            out[k + 3] = f[2]
            out[k + 4] = u[1]
            out[k + 5] = u[2]
            k += 6

    def _fill_stored(self, t, rows):
        """The columns of the states at the times ``t`` (m,) into ``rows`` (m, k) from the sensors' stored data
        (same numbers as :meth:`fill` at those states; every time must have its sensor row)."""
        get = self.mbs.GetSensorStoredData
        points, rotation = self.sensors
        data = get(rotation)
        rot = data[:, 1:10].reshape(-1, 3, 3)
        idx = np.searchsorted(data[:, 0], t - 1e-9)
        idx_ok = np.minimum(idx, len(data) - 1)
        missing = (idx >= len(data)) | (np.abs(data[idx_ok, 0] - t) > 1e-9)
        if np.any(missing):
            t_bad = float(t[np.argmax(missing)])
            raise RuntimeError(f"car-body points: the sensors stored no state at t = {t_bad:.9g} s (stored: "
                               f"{len(data)} states from {data[0, 0]:.9g} to {data[-1, 0]:.9g} s; Exudyn stores "
                               f"one every simulationSettings.solutionSettings.sensorsWritePeriod: set it to the "
                               f"time step)")
        R = rot[idx]
        for i, (s_acc, s_disp) in enumerate(points):
            a = get(s_acc)[idx, 1:4]
            u = get(s_disp)[idx, 1:4]
            # R^T (a - g), component by component
            v = a - self.gravity
            rows[:, 6 * i] = a[:, 1]
            rows[:, 6 * i + 1] = a[:, 2]
            rows[:, 6 * i + 2] = R[:, 0, 1] * v[:, 0] + R[:, 1, 1] * v[:, 1] + R[:, 2, 1] * v[:, 2]
            rows[:, 6 * i + 3] = R[:, 0, 2] * v[:, 0] + R[:, 1, 2] * v[:, 1] + R[:, 2, 2] * v[:, 2]
            rows[:, 6 * i + 4] = u[:, 1]
            rows[:, 6 * i + 5] = u[:, 2]

    def _fill_flexible(self, mbs, t, out):
        R, a, u, theta = self.flexible.state(mbs)
        for i in range(len(self.local)):
            f = R.T @ (a[i] - self.gravity)
            th = theta[i]                                 # into the section's axes, R (I + θ̃): f - θ × f
            f = f - (th[1] * f[2] - th[2] * f[1], th[2] * f[0] - th[0] * f[2], th[0] * f[1] - th[1] * f[0])
            out[6 * i:6 * i + 6] = (a[i, 1], a[i, 2], f[1], f[2], u[i, 1], u[i, 2])


class _DeckMidSpans:
    """Deflection and acceleration of the deck at every mid-span, on the track centre line."""

    def __init__(self, contact, bridge, modes, spans_m, start_m):
        self.c, self.bridge = contact, bridge
        x0 = start_m + np.concatenate(([0.0], np.cumsum(spans_m)[:-1]))
        s_mid = x0 + 0.5 * np.asarray(spans_m)
        self.phi = modes.shape_at(s_mid)[:, 1, :]                     # (n_spans, n_modes): z rows
        self.w2 = np.diag(modes.modal_stiffness()).copy()
        self.d = np.diag(modes.modal_damping()).copy()
        self.columns = []
        for i in range(len(s_mid)):
            self.columns += [("deck", f"deck_mid_deflection_s{i + 1}_m"),
                             ("deck", f"deck_mid_acceleration_s{i + 1}_m_s2")]

    def fill(self, mbs, t, out):
        q, q_t = self.bridge.coordinates(mbs)
        q_tt = self.c.modal_forces_N() - self.w2 * q - self.d * q_t          # modal equations, M = I
        for i in range(self.phi.shape[0]):
            out[2 * i] = self.phi[i] @ q
            out[2 * i + 1] = self.phi[i] @ q_tt


def vehicle_probes(*, model, contact, track, speed_m_s: float, s_leading0_m: float, carbody_points=(),
                   bridge=None, modes=None, deck_spans_m=None, deck_start_m=None, mbs=None) -> list:
    """The probes of a vehicle model with the wheel–rail connector, in :data:`GROUPS` order: ``carbody_points``
    a list of ``(name, position in the vehicle frame [m], z down)`` (needs a car body; given ``mbs``, not yet
    assembled, a rigid car body's points are read by sensors stored in memory); the deck's with a bridge."""
    n = len(model.wheelsets)
    probes = [_TrackDistance(s_leading0_m, speed_m_s), _Wheels(contact, n), _WheelsetLateral(contact, n),
              _Track(model, track)]
    if carbody_points:
        probes.append(_CarBodyPoints(model, carbody_points, mbs))
    if bridge is not None:
        probes.append(_DeckMidSpans(contact, bridge, modes, deck_spans_m, deck_start_m))
    return probes


# ======================================================================================== progress bar
class ProgressBar:
    """A text progress bar on a stream (stderr by default), redrawn when the run passes the next whole percent:
    ``[#######-------------]  35 %  t = 0.875 / 2.500 s  elapsed 1.2 s  left 2.2 s``.  ``stream``: ``None`` or
    ``True`` for stderr (a run's ``progress=True``), else the stream to draw on."""

    def __init__(self, t_end_s: float, stream=None, label: str = "", width: int = 30):
        self.t_end = float(t_end_s)
        self.stream = sys.stderr if stream is None or stream is True else stream
        self.label = label
        self.width = int(width)
        self.last = -1
        self.t0 = time.perf_counter()
        self.updates = 0

    def update(self, t_s: float) -> None:
        pct = int(min(100.0, max(0.0, 100.0 * float(t_s) / self.t_end)) + 1e-9)
        if pct <= self.last:
            return
        self.last = pct
        self.updates += 1
        elapsed = time.perf_counter() - self.t0
        left = f"{elapsed * (100 - pct) / pct:.1f}" if pct > 0 else "?"
        n = int(round(self.width * pct / 100))
        self.stream.write(f"\r{self.label}[{'#' * n}{'-' * (self.width - n)}] {pct:3d} %  t = {float(t_s):.3f} / "
                          f"{self.t_end:.3f} s  elapsed {elapsed:.1f} s  left {left} s ")
        self.stream.flush()

    def close(self, status: str = "") -> None:
        self.stream.write(f"  {status}\n" if status else "\n")
        self.stream.flush()
