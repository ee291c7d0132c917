r"""Trains as constant moving axle loads: the axle list (:class:`AxleTrain`), the universal trains HSLM-A1 … A10 of
EN 1991-2, axle files, the resonance speeds, and the closed-form modal response of a simply supported
Euler–Bernoulli span to a train of moving loads (the reference of the moving-load runs).

>>> train = hslm_a("A1")                       # doctest: +SKIP
>>> train.n_axles, train.length_m              # doctest: +SKIP
(50, 397.525)
>>> train = read_axle_file("axles.csv")        # doctest: +SKIP

Axle list
---------
An :class:`AxleTrain` holds, for every axle in running order, its distance **behind the first axle** ``x_m``
(``x_0 = 0``, increasing, consecutive axles at least :data:`MIN_AXLE_SPACING_M` = 0.5 m apart: closer ones are
overlapping or out of order) and its **downward** force ``load_N`` (> 0 is a weight; a lifting force is allowed but
must be finite).  The first axle enters a span at ``t = 0``; axle k at
``t_k = x_k / V``.

Axle file (:func:`read_axle_file`): a CSV file with a header line naming the columns ``x_m`` and ``load_N`` (other
columns are ignored; ``#`` starts a comment line); one axle per line.  Errors name the file, the line and the
problem: a missing column, a value that is not a finite number, a negative position, positions not increasing
(overlapping axles), no axle.

HSLM-A (:func:`hslm_a`)
-----------------------
EN 1991-2:2003 (Eurocode 1, Actions on structures, Part 2: Traffic loads on bridges), 6.4.6.1.1, Table 6.3 and
Figure 6.12: the ten universal trains HSLM-A1 … A10, articulated trains of two power cars, two end coaches and
``N`` intermediate coaches of length ``D``, every axle carrying the point force ``P``; bogie axle spacing ``d``
(the power cars' 3.0 m).  Annex E gives the limits of validity of the model (E.1, Table E.1: e.g. a train at most
400 m long and 10 000 kN heavy) and the selection of the critical universal train (E.2).  :data:`HSLM_A` holds
Table 6.3 (``N``, ``D`` [m], ``d`` [m], ``P`` [kN]; it and Figure 6.12's layout are declared in
:mod:`exudyn_wheelrail.standards`):

=======  ==  ====  ===  ===
train    N   D     d    P
=======  ==  ====  ===  ===
A1       18  18    2.0  170
A2       17  19    3.5  200
A3       16  20    2.0  180
A4       15  21    3.0  190
A5       14  22    2.0  170
A6       13  23    2.0  180
A7       13  24    2.0  190
A8       12  25    2.5  190
A9       11  26    2.0  210
A10      11  27    2.0  210
=======  ==  ====  ===  ===

The fixed axle layout of Figure 6.12 (:data:`HSLM_POWER_CAR_AXLES_M`, :data:`HSLM_POWER_CAR_TO_END_COACH_M`,
:data:`HSLM_END_COACH_TO_BOGIE_M`), front to rear: a power car with axles at 0, 3, 14, 17 m; 3.525 m to the end
coach's first axle; its bogie (spacing ``d``); the centre of the first articulated (shared) bogie ``D − 3.525/2`` m
behind the end coach's first axle; ``N + 1`` articulated bogies (spacing ``d``) whose centres are ``D`` apart; the
mirrored end coach and power car.  Hence ``2N + 14`` axles and a first-to-last-axle length
``37.525 + (N + 2) D`` m (HSLM-A1: 50 axles, 397.525 m).  The layout was cross-checked against the HSLM-A axle
tables distributed with the CALDINTAV program (K. Nguyen Gia, J. M. Goicolea, Universidad Politécnica de Madrid),
which list the same positions.

Resonance speeds
----------------
A train whose loads repeat every ``d`` (HSLM-A: the coach length ``D``) excites the span's first mode at the
speeds ``v_i = f_1 d / i`` (i = 1, 2, …; Frýba 2001).  :func:`characteristic_spacing_m` finds ``d`` of an axle list as
its most frequent axle-to-axle distance (1 mm bins, every pair of axles counted, ties to the longer distance):
``D`` for an HSLM-A train, the spacing for equally spaced loads.

Closed-form modal response (:func:`modal_moving_load_response`)
----------------------------------------------------------------
Simply supported span ``L``, bending stiffness ``EI``, mass ``m`` per length, modal damping ζ in every mode;
``w(x, t) = Σ_j q_j(t) sin(jπx/L)`` (z down), ``ω_j = (jπ/L)² √(EI/m)``.  A force ``P`` (down) at
``x = V (t − t_k)`` loads mode j by ``(2P/(mL)) sin(Ω_j τ)``, ``Ω_j = jπV/L``, ``τ = t − t_k``, while
``0 ≤ τ ≤ L/V``; zero before and after.  From rest, with the receptance ``H = 1/(ω² − Ω² + 2iζωΩ)``:

* on the span: ``q = A Im(H e^{iΩτ}) + Re(C e^{λτ})``, ``λ = −ζω + iω_d``, ``ω_d = ω√(1 − ζ²)``, the complex
  constant ``C`` chosen so that ``q(0) = q̇(0) = 0``;
* after the load has left (``τ_e = L/V``): free vibration ``Re(C_e e^{λ(τ − τ_e)})`` from the state at ``τ_e``;
* undamped resonance (ζ = 0, Ω = ω): the limit ``q = A/(2ω²) (sin ωτ − ωτ cos ωτ)``;

the acceleration ``q̈ = f(τ) − 2ζω q̇ − ω² q`` from the closed-form ``q`` and ``q̇`` (exact), all superposed over
the loads and the modes.  This is the derivation of Frýba (1999, Ch. 1; written here with modal damping and in
complex form) and an independent implementation of :func:`~.fryba.fryba_moving_force`.

Quasi-static reference (:func:`quasi_static_midspan_deflection_m`): the mid-span influence line of a simply
supported span, ``P a (3L² − 4a²)/(48 EI)`` for a load at ``a ≤ L/2`` from the nearer support, summed over the
axles on the span at ``a_k = V t − x_k``; the dynamic amplification of a crossing is the peak dynamic mid-span
deflection over the peak of this.

References
----------
EN 1991-2:2003, 6.4.6.1.1 (Table 6.3, Figure 6.12) and Annex E.  L. Frýba, *Vibration of solids and structures
under moving loads*, Thomas Telford 1999, Ch. 1.  L. Frýba, A rough assessment of railway bridges for high speed
trains, Engineering Structures 23 (2001) 548–556.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..standards import (HSLM_A, HSLM_END_COACH_TO_BOGIE_M, HSLM_NAMES, HSLM_POWER_CAR_AXLES_M,
                         HSLM_POWER_CAR_TO_END_COACH_M)
from ..validation import InputWarning, csv_rows

__all__ = ["AxleTrain", "HSLM_A", "HSLM_NAMES", "HSLM_POWER_CAR_AXLES_M", "HSLM_POWER_CAR_TO_END_COACH_M",
           "HSLM_END_COACH_TO_BOGIE_M", "AXLE_FILE_COLUMNS", "MIN_AXLE_SPACING_M", "PLAUSIBLE_AXLE_LOAD_N",
           "MAX_PLAUSIBLE_AXLE_GAP_M", "axle_file_slips", "hslm_a", "hslm_name",
           "read_axle_file",
           "characteristic_spacing_m", "resonance_speeds_m_s", "flexural_rigidity_Nm2",
           "simply_supported_frequencies_Hz", "modal_moving_load_response", "quasi_static_midspan_deflection_m"]

#: the columns an axle file must have
AXLE_FILE_COLUMNS = ("x_m", "load_N")
#: smallest distance between two axles [m] (closer ones are one axle given twice)
MIN_AXLE_SPACING_M = 0.5
#: an axle file's plausible axle loads [N] (light vehicles 50 kN … the heaviest freight axles ~350 kN) and the
#: largest plausible gap between consecutive axles [m] (a coach's bogie centres ~19 m); outside: a warning
PLAUSIBLE_AXLE_LOAD_N = (1.0e4, 4.0e5)
MAX_PLAUSIBLE_AXLE_GAP_M = 40.0


@dataclass(frozen=True)
class AxleTrain:
    """Axles in running order: ``x_m`` distance behind the first axle (0 first, increasing), ``load_N`` downward
    force; ``name`` and ``source`` say what it is and where it comes from (module docstring)."""

    x_m: np.ndarray
    load_N: np.ndarray
    name: str = "axles"
    source: str = ""
    spacing_m: float | None = field(default=None)

    def __post_init__(self):
        x = np.atleast_1d(np.asarray(self.x_m, dtype=float)).ravel()
        p = np.atleast_1d(np.asarray(self.load_N, dtype=float)).ravel()
        where = f"{self.name}: " if self.name else ""
        if x.size == 0:
            raise ValueError(f"{where}no axle")
        if x.shape != p.shape:
            raise ValueError(f"{where}{x.size} positions but {p.size} loads")
        if not np.all(np.isfinite(x)) or not np.all(np.isfinite(p)):
            raise ValueError(f"{where}positions and loads must be finite numbers")
        if x[0] != 0.0:
            raise ValueError(f"{where}the first axle must be at x_m = 0 (distances behind the first axle), got "
                             f"{x[0]:g}")
        gaps = np.diff(x)
        if gaps.size and np.min(gaps) < MIN_AXLE_SPACING_M:
            k = int(np.argmin(gaps))
            raise ValueError(f"{where}axles {k + 1} and {k + 2} at {x[k]:g} m and {x[k + 1]:g} m are closer than "
                             f"{MIN_AXLE_SPACING_M:g} m (overlapping or out of order)")
        object.__setattr__(self, "x_m", x)
        object.__setattr__(self, "load_N", p)
        if self.spacing_m is None:
            object.__setattr__(self, "spacing_m", characteristic_spacing_m(x))

    @property
    def n_axles(self) -> int:
        return int(self.x_m.size)

    @property
    def length_m(self) -> float:
        """Distance from the first to the last axle [m]."""
        return float(self.x_m[-1])

    @property
    def total_load_N(self) -> float:
        return float(np.sum(self.load_N))

    def as_dict(self) -> dict:
        return {"name": self.name, "source": self.source, "n_axles": self.n_axles, "length_m": self.length_m,
                "total_load_N": self.total_load_N, "characteristic_spacing_m": self.spacing_m,
                "min_axle_spacing_m": float(np.min(np.diff(self.x_m))) if self.n_axles > 1 else None}


# ----------------------------------------------------------------------------------------------------- HSLM
def hslm_name(text: str) -> str:
    """``"A1"`` … ``"A10"`` from ``A1``, ``a1``, ``HSLM-A1``; ``ValueError`` naming the choices else."""
    key = str(text).strip().upper()
    if key.startswith("HSLM-"):
        key = key[5:]
    if key not in HSLM_A:
        raise ValueError(f"{text!r}: unknown universal train (expected one of {', '.join(HSLM_NAMES)}, "
                         "EN 1991-2 Table 6.3)")
    return key


def hslm_a(name: str) -> AxleTrain:
    """The universal train HSLM-``name`` (``"A1"`` … ``"A10"``) of EN 1991-2:2003, Table 6.3 and Figure 6.12, as
    axle places behind the first axle and the point force P on every axle (module docstring)."""
    key = hslm_name(name)
    n, D, d, p_kN = HSLM_A[key]
    power = np.asarray(HSLM_POWER_CAR_AXLES_M)
    x = list(power)
    first_end = power[-1] + HSLM_POWER_CAR_TO_END_COACH_M
    x += [first_end, first_end + d]                                   # end coach bogie
    c0 = first_end + D + HSLM_END_COACH_TO_BOGIE_M                   # first articulated bogie centre
    for k in range(n + 1):
        c = c0 + k * D
        x += [c - d / 2.0, c + d / 2.0]
    last_end = c0 + n * D + (D + HSLM_END_COACH_TO_BOGIE_M)          # mirrored: the rear end coach's last axle
    x += [last_end - d, last_end]
    rear = last_end + HSLM_POWER_CAR_TO_END_COACH_M
    x += list(rear + power)
    x = np.round(np.array(x), 9)
    return AxleTrain(x, np.full(x.size, p_kN * 1e3), name=f"HSLM-{key}",
                     source=f"EN 1991-2:2003 Table 6.3 / Figure 6.12: N = {n}, D = {D:g} m, d = {d:g} m, "
                            f"P = {p_kN:g} kN", spacing_m=D)


# ------------------------------------------------------------------------------------------------ axle file
def read_axle_file(path) -> AxleTrain:
    """An :class:`AxleTrain` from a CSV axle file (module docstring); ``ValueError`` ``<file>:<line>: <problem>``."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such axle file")
    xs, ps = [], []
    header = None
    for lineno, cells in csv_rows(path):
        if header is None:
            header = cells
            missing = [c for c in AXLE_FILE_COLUMNS if c not in header]
            if missing:
                raise ValueError(f"{path}:{lineno}: the header has no column {', '.join(missing)} (expected "
                                 f"the columns {', '.join(AXLE_FILE_COLUMNS)}; got {', '.join(header)})")
            ix, ip = header.index("x_m"), header.index("load_N")
            continue
        vals = []
        for col, i in (("x_m", ix), ("load_N", ip)):
            text = cells[i] if i < len(cells) else ""
            try:
                v = float(text)
            except ValueError:
                raise ValueError(f"{path}:{lineno}: {col} = {text!r} is not a number") from None
            if not math.isfinite(v):
                raise ValueError(f"{path}:{lineno}: {col} = {text!r} is not a finite number")
            vals.append(v)
        x, p = vals
        if x < 0.0:
            raise ValueError(f"{path}:{lineno}: x_m = {x:g} is negative (distances behind the first axle are "
                             ">= 0)")
        if not xs and x != 0.0:
            raise ValueError(f"{path}:{lineno}: the first axle must be at x_m = 0 (distances behind the first "
                             f"axle), got {x:g}")
        if xs and x - xs[-1] < MIN_AXLE_SPACING_M:
            raise ValueError(f"{path}:{lineno}: x_m = {x:g} is not at least {MIN_AXLE_SPACING_M:g} m behind the "
                             f"axle before ({xs[-1]:g} m): overlapping or out of order")
        xs.append(x)
        ps.append(p)
    if header is None or not xs:
        raise ValueError(f"{path}: no axle (expected a header line with {', '.join(AXLE_FILE_COLUMNS)} and one "
                         "line per axle)")
    for note in axle_file_slips(np.array(xs), np.array(ps)):
        warnings.warn(f"{path}: {note}; going on with them", InputWarning, stacklevel=2)
    return AxleTrain(np.array(xs), np.array(ps), name=path.stem, source=str(path))


def axle_file_slips(x_m, load_N) -> list[str]:
    """The plausible slips of an axle file (each a warning, the run goes on): loads not downward (upward ones, a sum
    that is no weight), loads that look like kN (all below :data:`PLAUSIBLE_AXLE_LOAD_N`'s lower end) or are
    heavier than any railway axle, a gap between consecutive axles longer than :data:`MAX_PLAUSIBLE_AXLE_GAP_M`
    (positions in mm?)."""
    notes = []
    lo, hi = PLAUSIBLE_AXLE_LOAD_N
    if np.sum(load_N) <= 0.0:
        notes.append(f"the axle loads sum to {np.sum(load_N):g} N, not a downward weight (load_N is positive "
                     "downwards)")
    elif np.any(load_N < 0.0):
        notes.append(f"{int(np.sum(load_N < 0.0))} axle load(s) upward (load_N is positive downwards)")
    if np.sum(load_N) > 0.0 and np.max(load_N) < lo:
        notes.append(f"the largest axle load is {np.max(load_N):g} N, below {lo:g} N: loads in kN? (load_N is in "
                     "newtons: 170 kN is 170000)")
    elif np.max(load_N) > hi:
        notes.append(f"an axle load of {np.max(load_N):g} N, above {hi:g} N (load_N is in newtons)")
    gaps = np.diff(x_m)
    if gaps.size and np.max(gaps) > MAX_PLAUSIBLE_AXLE_GAP_M:
        notes.append(f"consecutive axles {np.max(gaps):g} m apart, more than {MAX_PLAUSIBLE_AXLE_GAP_M:g} m: "
                     "positions in mm? (x_m is in metres)")
    return notes


# --------------------------------------------------------------------------------------------- resonance
def characteristic_spacing_m(x_m) -> float | None:
    """The most frequent axle-to-axle distance of the axle places ``x_m`` (every pair, 1 mm bins; ties to the
    longer distance); None for a single axle."""
    x = np.asarray(x_m, dtype=float)
    if x.size < 2:
        return None
    diff = np.round((x[None, :] - x[:, None])[np.triu_indices(x.size, 1)] * 1000.0).astype(np.int64)
    values, counts = np.unique(diff, return_counts=True)
    best = np.flatnonzero(counts == counts.max())
    return float(values[best[-1]]) / 1000.0


def resonance_speeds_m_s(f1_Hz: float, spacing_m: float, n: int = 4) -> list[float]:
    """``v_i = f_1 d / i`` for i = 1 … n [m/s]."""
    return [float(f1_Hz) * float(spacing_m) / i for i in range(1, int(n) + 1)]


# ------------------------------------------------------------------------------------------ the beam itself
def flexural_rigidity_Nm2(span_m: float, mass_kg_m: float, f1_Hz: float) -> float:
    """``EI`` of a simply supported Euler–Bernoulli span with first frequency ``f1``: ``f1 = π/(2L²) √(EI/m)`` ⇒
    ``EI = m (2 L² f1 / π)²``."""
    return float(mass_kg_m) * (2.0 * float(span_m) ** 2 * float(f1_Hz) / math.pi) ** 2


def simply_supported_frequencies_Hz(f1_Hz: float, n_modes: int) -> np.ndarray:
    """``f_j = j² f_1`` (j = 1 … n)."""
    return float(f1_Hz) * np.arange(1, int(n_modes) + 1, dtype=float) ** 2


def _sine_window_response(A, w, z, Om, tau, t_exit):
    """``q, q̇`` of ``q̈ + 2ζω q̇ + ω² q = A sin(Ω τ)`` for ``0 ≤ τ ≤ t_exit`` (0 else), from rest at τ = 0 (module
    docstring, complex form); ``tau`` an array."""
    wd = w * math.sqrt(1.0 - z * z)
    lam = complex(-z * w, wd)
    on = np.clip(tau, 0.0, t_exit)

    def forced(s):
        den = complex(w * w - Om * Om, 2.0 * z * w * Om)
        if abs(den) <= 1e-12 * w * w:                                  # undamped resonance: the limit
            q = A / (2.0 * w * w) * (np.sin(w * s) - w * s * np.cos(w * s))
            return q, 0.5 * A * s * np.sin(w * s)
        H = 1.0 / den
        e = np.exp(1j * Om * s)
        qp, vp = A * (H * e).imag, A * (1j * Om * H * e).imag
        qp0, vp0 = A * H.imag, A * (1j * Om * H).imag
        a = -qp0                                                       # C = a + ib: q_h(0) = -qp0, q̇_h(0) = -vp0
        b = (vp0 - z * w * a) / wd if wd > 0.0 else 0.0
        C = complex(a, b)
        eh = C * np.exp(lam * s)
        return qp + eh.real, vp + (lam * eh).real

    q, v = forced(on)
    qe, ve = forced(np.array(t_exit))
    s = np.maximum(tau - t_exit, 0.0)
    Ce = complex(float(qe), -(float(ve) + z * w * float(qe)) / wd)
    ef = Ce * np.exp(lam * s)
    after = tau > t_exit
    q = np.where(after, ef.real, q)
    v = np.where(after, (lam * ef).real, v)
    before = tau <= 0.0
    return np.where(before, 0.0, q), np.where(before, 0.0, v)


def modal_moving_load_response(x_m, t_s, axles: AxleTrain, *, speed_m_s: float, span_m: float, EI_Nm2: float,
                               m_kg_m: float, damping_ratio: float, n_modes: int):
    """Closed-form deflection ``w`` [m] and acceleration ``a`` [m/s²] (both + down) of a simply supported
    Euler–Bernoulli span at the places ``x_m`` (k,) and times ``t_s`` (n,) under ``axles`` moving at
    ``speed_m_s`` (the first axle enters at t = 0), with ``n_modes`` modes and modal damping ζ in every mode
    (module docstring).  Returns ``(w, a)``, each (n, k)."""
    x = np.atleast_1d(np.asarray(x_m, dtype=float))
    t = np.atleast_1d(np.asarray(t_s, dtype=float))
    L, V, m, z = float(span_m), float(speed_m_s), float(m_kg_m), float(damping_ratio)
    if not (L > 0 and V > 0 and m > 0 and EI_Nm2 > 0 and 0.0 <= z < 1.0):
        raise ValueError("modal_moving_load_response: expected span, speed, EI, m > 0 and 0 <= damping_ratio < 1")
    t_exit = L / V
    w_out = np.zeros((t.size, x.size))
    a_out = np.zeros((t.size, x.size))
    for j in range(1, int(n_modes) + 1):
        wj = (j * math.pi / L) ** 2 * math.sqrt(EI_Nm2 / m)
        Om = j * math.pi * V / L
        q = np.zeros(t.size)
        v = np.zeros(t.size)
        f = np.zeros(t.size)
        for xk, P in zip(axles.x_m, axles.load_N):
            A = 2.0 * P / (m * L)
            tau = t - xk / V
            qk, vk = _sine_window_response(A, wj, z, Om, tau, t_exit)
            q += qk
            v += vk
            f += np.where((tau > 0.0) & (tau <= t_exit), A * np.sin(Om * np.clip(tau, 0.0, t_exit)), 0.0)
        acc = f - 2.0 * z * wj * v - wj * wj * q
        shape = np.sin(j * math.pi * x / L)
        w_out += q[:, None] * shape[None, :]
        a_out += acc[:, None] * shape[None, :]
    return w_out, a_out


def quasi_static_midspan_deflection_m(t_s, axles: AxleTrain, *, speed_m_s: float, span_m: float,
                                      EI_Nm2: float) -> np.ndarray:
    """Static mid-span deflection [m] (+ down) of a simply supported span under the axles at their places at the
    times ``t_s`` (the first axle at the first support at t = 0): the influence line of the module docstring."""
    t = np.atleast_1d(np.asarray(t_s, dtype=float))
    L = float(span_m)
    a = float(speed_m_s) * t[:, None] - axles.x_m[None, :]                 # (n, k) places on the span
    near = np.minimum(a, L - a)
    on = (a >= 0.0) & (a <= L)
    w = np.where(on, axles.load_N[None, :] * near * (3.0 * L * L - 4.0 * near * near) / (48.0 * float(EI_Nm2)), 0.0)
    return w.sum(axis=1)
