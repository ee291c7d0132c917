r"""Recording a run: one row per recorded state, the columns given by **probes**, each probe a group of columns of
one kind; and the progress bar.

The runner (:mod:`.runner`) calls :meth:`Recorder.record` for every accepted state on the recording grid (every
``record_every``-th multiple of ``dt_s``), *after* the run monitor has evaluated the contact at that state: the
probes read the connector's results of that evaluation (:meth:`~exudyn_wheelrail.multibody.connector.
WheelRailContact.wheel_force_N`, ``results``, ``wheelset_rail_pose``) and Exudyn's outputs of the bodies — the
contact is never evaluated twice for one state.

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
  <p>_m_s2`` (track frame, kinematic: no gravity; Exudyn's rigid-body ``Acceleration`` output at the point),
  ``carbody_lateral_accelerometer_<p>_m_s2``, ``carbody_vertical_accelerometer_<p>_m_s2`` (the specific force
  a − g in the car body's own axes: what a floor accelerometer reads; ≈ −9.81 vertical at rest),
  ``carbody_lateral_displacement_<p>_m``, ``carbody_vertical_displacement_<p>_m`` (track frame);
* ``deck`` per span i: ``deck_mid_deflection_s<i>_m``, ``deck_mid_acceleration_s<i>_m_s2`` (vertical, + down, at
  mid-span on the track centre line; the acceleration from the modal equations at the state,
  q̈ = Q − diag(2ζω) q̇ − diag(ω²) q).

``time_s`` and ``s_leading_m`` (track distance of the leading wheelset) are always recorded.
"""
from __future__ import annotations

import sys
import time

import numpy as np

__all__ = ["GROUPS", "SIDES", "Recorder", "ProgressBar", "PROGRESS_MIN_STEPS", "vehicle_probes"]

#: column groups, in the order they are stored
GROUPS = ("Y", "Q", "YQ", "flange", "contact_angle", "wheelset_lateral", "track", "carbody", "deck")
SIDES = ("right", "left")            # wheel 2k right, 2k+1 left (the connector's order)
#: runs with at least this many steps get the progress bar (shorter runs finish before it would help)
PROGRESS_MIN_STEPS = 200


class Recorder:
    """Rows of the ``probes``' columns, one per :meth:`record` call; ``time_s`` first.  A probe has ``columns``
    (a list of ``(group, name)``) and ``fill(mbs, t, row)`` writing its slice of the row."""

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
        self.data = np.full((max(1, int(n_rows_hint)), len(self.columns)), np.nan)
        self.n = 0

    def record(self, mbs, t: float) -> None:
        if self.n >= self.data.shape[0]:
            self.data = np.vstack([self.data, np.full_like(self.data, np.nan)])
        row = self.data[self.n]
        row[0] = t
        for p, sl in zip(self.probes, self._slices):
            p.fill(mbs, t, row[sl])
        self.n += 1

    @property
    def last_time_s(self) -> float | None:
        return float(self.data[self.n - 1, 0]) if self.n else None

    def keep_until(self, t_s: float) -> int:
        """Drop the rows after ``t_s`` (inclusive bound); returns how many were dropped."""
        keep = int(np.searchsorted(self.data[:self.n, 0], t_s + 1e-12, side="right"))
        dropped = self.n - keep
        self.n = keep
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

    def fill(self, mbs, t, out):
        out[0] = self.s0 + self.V * t


class _Wheels:
    """Groups ``Y``, ``Q``, ``YQ``, ``flange``, ``contact_angle`` of every wheel, from the contact's results."""

    def __init__(self, contact, n_wheelsets: int):
        from ..multibody import connector as C
        self.C = C
        self.c = contact
        self.n = int(n_wheelsets)
        wheels = [(j, side) for j in range(self.n) for side in SIDES]
        self.columns = ([("Y", f"Y_w{j + 1}_{s}_N") for j, s in wheels]
                        + [("Q", f"Q_w{j + 1}_{s}_N") for j, s in wheels]
                        + [("YQ", f"YQ_w{j + 1}_{s}") for j, s in wheels]
                        + [("flange", f"flange_w{j + 1}_{s}") for j, s in wheels]
                        + [("contact_angle", f"contact_angle_w{j + 1}_{s}_rad") for j, s in wheels])

    def fill(self, mbs, t, out):
        c, C = self.c, self.C
        n_w = 2 * self.n
        res = c.results
        F = res[:, :, C.RES_F_TRACK_X:C.RES_F_TRACK_Z + 1].sum(axis=1)   # per wheel, as wheel_force_N
        Y = F[:, 1]
        Q = -F[:, 2] + 0.0                                                # no -0.0
        y_out = np.where(np.arange(n_w) % 2 == 0, -Y, Y)                  # towards the wheel's field side
        out[:n_w] = Y
        out[n_w:2 * n_w] = Q
        with np.errstate(divide="ignore", invalid="ignore"):
            out[2 * n_w:3 * n_w] = np.where(Q > 0.0, y_out / np.where(Q > 0.0, Q, 1.0), np.nan)
        for w in range(n_w):
            out[3 * n_w + w] = 1.0 if c.flange_contact(w // 2, SIDES[w % 2]) else 0.0
        loads = res[:, :, C.RES_N]
        reg = np.argmax(loads, axis=1)
        rows = np.arange(n_w)
        out[4 * n_w:5 * n_w] = np.where(loads[rows, reg] > 0.0, res[rows, reg, C.RES_GAMMA], np.nan)


class _WheelsetLateral:
    """``y_rel_w<j>_m`` from the contact search's wheelset–rail pose."""

    def __init__(self, contact, n_wheelsets: int):
        self.c = contact
        self.columns = [("wheelset_lateral", f"y_rel_w{j + 1}_m") for j in range(n_wheelsets)]

    def fill(self, mbs, t, out):
        out[:] = self.c.wheelset_rail_pose()[:, 0]


class _Track:
    """``track_lateral_w<j>_m``, ``track_vertical_w<j>_m``: the irregularity under each wheelset."""

    def __init__(self, model, track):
        from ..multibody.track import irregularity_at
        self.model = model
        self.x = [float(ws.p_cg_in_frame[0]) for ws in model.wheelsets]
        p = track.packed()
        self.packed = (p.rows, p.knots, p.coefs)
        self.at = irregularity_at
        n = len(self.x)
        self.columns = ([("track", f"track_lateral_w{j + 1}_m") for j in range(n)]
                        + [("track", f"track_vertical_w{j + 1}_m") for j in range(n)])

    def fill(self, mbs, t, out):
        n = len(self.x)
        for j, x in enumerate(self.x):
            v = self.at(*self.packed, float(self.model.track_distance_m(x, t)))
            out[j] = v[0]
            out[n + j] = v[3]


class _CarBodyPoints:
    """Accelerations, accelerometer readings and displacements of points fixed to the car body."""

    def __init__(self, model, points):
        import exudyn as exu
        self.ovt = exu.OutputVariableType
        cb = model.car_body
        self.body = cb.body
        self.gravity = np.array([0.0, 0.0, model.gravity_m_s2])
        self.local = [(np.asarray(pos, dtype=float) - cb.p_cg_in_frame).tolist() for _, pos in points]
        self.columns = []
        for name, _ in points:
            self.columns += [("carbody", f"carbody_{d}_{q}_{name}_{u}")
                             for q, u in (("acceleration", "m_s2"), ("accelerometer", "m_s2"), ("displacement", "m"))
                             for d in ("lateral", "vertical")]

    def fill(self, mbs, t, out):
        ovt = self.ovt
        R = np.asarray(mbs.GetObjectOutputBody(self.body, ovt.RotationMatrix)).reshape(3, 3)
        k = 0
        for loc in self.local:
            a = np.asarray(mbs.GetObjectOutputBody(self.body, ovt.Acceleration, localPosition=loc))
            u = np.asarray(mbs.GetObjectOutputBody(self.body, ovt.Displacement, localPosition=loc))
            f = R.T @ (a - self.gravity)
            out[k:k + 6] = (a[1], a[2], f[1], f[2], u[1], u[2])
            k += 6


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
                   bridge=None, modes=None, deck_spans_m=None, deck_start_m=None) -> list:
    """The probes of a vehicle model with the wheel–rail connector, in :data:`GROUPS` order: ``carbody_points``
    a list of ``(name, position in the vehicle frame [m], z down)`` (needs a car body); the deck's with a bridge."""
    n = len(model.wheelsets)
    probes = [_TrackDistance(s_leading0_m, speed_m_s), _Wheels(contact, n), _WheelsetLateral(contact, n),
              _Track(model, track)]
    if carbody_points:
        probes.append(_CarBodyPoints(model, carbody_points))
    if bridge is not None:
        probes.append(_DeckMidSpans(contact, bridge, modes, deck_spans_m, deck_start_m))
    return probes


# ======================================================================================== progress bar
class ProgressBar:
    """A text progress bar on a stream (stderr by default), redrawn when the run passes the next whole percent:
    ``[#######-------------]  35 %  t = 0.875 / 2.500 s  elapsed 1.2 s  left 2.2 s``."""

    def __init__(self, t_end_s: float, stream=None, label: str = "", width: int = 30):
        self.t_end = float(t_end_s)
        self.stream = stream if stream is not None else sys.stderr
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
