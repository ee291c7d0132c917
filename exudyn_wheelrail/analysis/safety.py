r"""Running safety of a recorded run: derailment quotient Y/Q (Nadal, EN 14363, the Japanese duration criterion),
wheel unloading ΔQ/Q and wheel lift, the track shift force ΣY (Prud'homme), and :func:`running_criteria_summary`,
which evaluates a recorded time-series table (the columns of :mod:`exudyn_wheelrail.scenarios.rtri`) against all of
them and the comfort quantities of :mod:`.comfort`.

Plain numpy/scipy; SI units (forces in N, times in s, distances in m, speeds in m/s); signals sampled at one
uniform step ``dt_s``; the constant running speed ``speed_m_s`` converts distance windows to samples
(:func:`~.comfort.window_samples`: n = round(L/(V dt)), the effective window n V dt is reported).  Bad input raises
``ValueError`` (NaN/inf, different lengths, non-uniform time axis, non-positive step/speed/load, window longer than
the record).  Every criterion reports ``value``, ``limit``, ``margin`` = limit − value (the quantity's unit),
``utilisation`` = value/limit and ``passed``.

Forces and signs
----------------
Q: the vertical wheel force (wheel load), positive pressing the wheel on the rail.  Y: the lateral force of the
wheel **on the rail**, positive **outwards** (towards the field side of that wheel — the direction in which a
flange contact pushes its rail).  With track axes (y to the right) and the force of the rail on the wheel
F_y (what :mod:`..scenarios.rtri` records as ``Y_w<j>_<side>_N``): Y_right = −F_y, Y_left = +F_y
(:func:`flange_lateral_force_N`).  The track shift force of a wheelset is the sum of its wheels' forces on the
track in the track's y axis, ΣY = −(F_y,right + F_y,left); its sign does not matter (|·| is assessed).

Nadal (:func:`nadal_limit`)
---------------------------
Flange climbing starts when, at a flange contact of angle γ with sliding friction μ (the friction force opposing
the climb), the quotient reaches (Nadal 1908; as commonly stated, the basis of the Y/Q limits of UIC 518 and
EN 14363)

    (Y/Q)_Nadal = (tan γ − μ) / (1 + μ tan γ)  = tan(γ − arctan μ).

γ = 70°, μ = 0.36 gives 1.200 (the value EN 14363 admits in curves R < 250 m, as commonly cited); γ = 60°,
μ = 0.36 gives 0.845.

EN 14363 derailment quotient (:func:`derailment_quotient_en14363`)
------------------------------------------------------------------
EN 14363:2016 (as UIC 518 and EN 14363:2005; processing as tabulated in the GENSYS course notes "Acceptance test
according to UIC 518 and CEN/TC 256 WG 10 publication EN 14363" — the standard's own text was not available to
us): Y and Q low-pass filtered at 20 Hz (:func:`~.comfort.lowpass`; order: module doc
of :mod:`.comfort`), the quotient Y/Q per wheel, its **sliding mean over 2 m of track** ((Y/Q)_2m), whose maximum
must not exceed **(Y/Q)_lim = 0.8** — the limit of the standard's usual case (track with curve radii R ≥ 250 m);
1.2 is commonly cited for R < 250 m (pass ``limit=``).  Departures, stated: (i) the window slides by one sample
(V dt), not in the standard's steps of 0.5 m (the GENSYS course notes on UIC 518/EN 14363 tabulate "sliding mean
2 m, sampling interval 0.5 m") — the maximum over every sample's window is ≥ that over a 0.5 m grid, so this is on
the safe side; (ii) the standard's statistics over many track sections (the 99.85 % percentile) do not apply to
one simulated run: the maximum is assessed.  Samples of a lifted wheel (filtered Q ≤ 0: Y/Q undefined) are left
out of their windows and counted (``lifted_samples_excluded``); the wheel-lift criterion (on the unfiltered Q)
fails for a lifted wheel.

Japanese derailment coefficient with duration (:func:`derailment_quotient_jnr`)
------------------------------------------------------------------------------
In Japan the wheel load is written P and the lateral force Q, so the "derailment coefficient Q/P" is the Y/Q of
this module.  The JNR criterion (established in the 1960s; reviewed by Ishida & Matsuo, "Safety criteria for
evaluation of railway vehicle derailment", Quarterly Report of RTRI (late 1990s), and Ishida, Tezuka, Ueki,
Fukazawa & Matsuo, "Safety criteria for evaluation of the railway vehicle derailment", RTRI Report 9(8), 1995):
Y/Q ≤ 0.8; for short exceedances a limit inversely proportional to their duration is admitted (the Japanese
encyclopaedia Nipponica, entry 脱線係数: "for phenomena shorter than 0.05 s a larger value inversely proportional
to the time is allowed").  **Implemented, as commonly cited:**

    (Y/Q)_lim(t) = 0.8            for t ≥ 0.05 s,
    (Y/Q)_lim(t) = 0.04 s / t     for t < 0.05 s     (continuous at 0.05 s),

applied per **excursion**: every interval in which Y/Q stays above 0.8 (start and end by linear interpolation of
the crossings of 0.8 between samples; an excursion cut by the start or end of the record is flagged
``truncated``) has a duration t and a peak; it passes if peak ≤ (Y/Q)_lim(t).  (The duration of exceedance of 0.8
with the peak of the excursion is the conservative reading: the duration above any higher level is shorter.)
The constant 0.04 s is as commonly cited; the primary JNR text was not available to us.

Wheel unloading and wheel lift (:func:`wheel_unloading`, :func:`wheel_lift`)
----------------------------------------------------------------------------
ΔQ/Q = (Q_static − Q)/Q_static per wheel; assessed is its maximum against ``limit``.  Default **0.6** (a value
commonly used for the wheel unloading, e.g. on twisted track); Japanese running tests commonly cite **0.8** for the
dynamic wheel-load reduction.  Neither value was checked against the standards' text: pass the limit of the rule
you apply.  Wheel lift: Q ≤ 0 (a lifted wheel carries no load; the RTRI recorder gives exactly 0); reported are the
number of lifted samples and the lift intervals (crossings of Q = 0 by linear interpolation), and any lift fails.

Track shift force, Prud'homme (:func:`prudhomme_limit_N`, :func:`track_shift_force_en14363`)
-------------------------------------------------------------------------------------------
EN 14363 (after Prud'homme): ΣY of a wheelset, low-pass 20 Hz, sliding mean over 2 m (as for Y/Q), maximum of its
magnitude ≤ (ΣY_2m)_lim = α (10 + 2Q_0/3) kN, **Q_0 the static vertical wheel force in kN** (2Q_0 = P the static
axle load: Prud'homme's 10 + P/3 kN); α = 1.0 for locomotives and passenger vehicles, 0.85 for freight wagons.
(Q_0 is the wheel force: reading it as the axle load would double Prud'homme's load term, 10 + 2P/3 kN.)
"""
from __future__ import annotations

import math
import re

import numpy as np

from . import comfort as C
from .comfort import assess, as_signal, check_positive, check_same_length

__all__ = [
    "EN14363_YQ_LIMIT",
    "EN14363_YQ_LIMIT_SMALL_RADIUS",
    "EN14363_WINDOW_M",
    "EN14363_FORCE_LOWPASS_HZ",
    "JNR_YQ_LIMIT",
    "JNR_DURATION_S",
    "WHEEL_UNLOADING_LIMIT",
    "PRUDHOMME_ALPHA",
    "nadal_limit",
    "flange_lateral_force_N",
    "derailment_quotient",
    "derailment_quotient_en14363",
    "exceedance_intervals",
    "jnr_limit",
    "derailment_quotient_jnr",
    "wheel_unloading",
    "wheel_lift",
    "prudhomme_limit_N",
    "track_shift_force_en14363",
    "running_criteria_summary",
]

#: EN 14363 (Y/Q)_lim, the usual case (curve radii R >= 250 m)
EN14363_YQ_LIMIT = 0.8
#: (Y/Q)_lim commonly cited for EN 14363 in curves R < 250 m (= Nadal at 70°, μ = 0.36)
EN14363_YQ_LIMIT_SMALL_RADIUS = 1.2
#: EN 14363 sliding-mean window of Y/Q and ΣY [m]
EN14363_WINDOW_M = 2.0
#: EN 14363 low-pass of the wheel–rail forces [Hz]
EN14363_FORCE_LOWPASS_HZ = 20.0
#: Japanese (JNR) derailment-coefficient limit for exceedances of at least JNR_DURATION_S
JNR_YQ_LIMIT = 0.8
#: duration [s] below which the JNR limit rises as JNR_YQ_LIMIT * JNR_DURATION_S / t (= 0.04 s / t)
JNR_DURATION_S = 0.05
#: default wheel-unloading limit ΔQ/Q (see the module doc: pass the limit of the rule applied)
WHEEL_UNLOADING_LIMIT = 0.6
#: Prud'homme factor α of EN 14363
PRUDHOMME_ALPHA = {"passenger": 1.0, "locomotive": 1.0, "freight": 0.85}


# ============================================================================================ Nadal
def nadal_limit(flange_angle_rad: float, friction_coefficient: float) -> float:
    """Nadal's limit (tan γ − μ)/(1 + μ tan γ) for the flange angle γ [rad] in (0, π/2) and μ >= 0."""
    g = float(flange_angle_rad)
    mu = float(friction_coefficient)
    if not (math.isfinite(g) and 0.0 < g < 0.5 * math.pi):
        raise ValueError(f"flange_angle_rad = {flange_angle_rad!r}: expected an angle in (0, pi/2) rad")
    if not (math.isfinite(mu) and mu >= 0.0):
        raise ValueError(f"friction_coefficient = {friction_coefficient!r}: expected a finite value >= 0")
    t = math.tan(g)
    return (t - mu) / (1.0 + mu * t)


# ============================================================================================ Y/Q
def flange_lateral_force_N(rail_on_wheel_fy_N, side: str) -> np.ndarray:
    """Y (force of the wheel on the rail, positive outwards) from the track-frame y component of the force of the
    rail on the wheel (y to the right): −F_y for the right wheel, +F_y for the left wheel."""
    f = as_signal(rail_on_wheel_fy_N, "rail_on_wheel_fy_N")
    if side == "right":
        return -f
    if side == "left":
        return f.copy()
    raise ValueError(f"side = {side!r}: expected 'right' or 'left'")


def derailment_quotient(Y_N, Q_N) -> np.ndarray:
    """Y/Q per sample; NaN where the wheel is lifted (Q <= 0: the quotient is undefined)."""
    Y = as_signal(Y_N, "Y_N")
    Q = as_signal(Q_N, "Q_N")
    check_same_length(Y_N=Y, Q_N=Q)
    out = np.full(Y.shape, np.nan)
    ok = Q > 0.0
    out[ok] = Y[ok] / Q[ok]
    return out


def derailment_quotient_en14363(Y_N, Q_N, dt_s: float, speed_m_s: float, limit: float = EN14363_YQ_LIMIT,
                                window_m: float = EN14363_WINDOW_M,
                                lowpass_hz: float | None = EN14363_FORCE_LOWPASS_HZ) -> dict:
    """EN 14363 assessment of one wheel: max of the 2 m sliding mean of Y/Q (module doc) against ``limit``.
    ``lowpass_hz=None`` skips the 20 Hz pre-filter (signals already filtered)."""
    Y = as_signal(Y_N, "Y_N")
    Q = as_signal(Q_N, "Q_N")
    check_same_length(Y_N=Y, Q_N=Q)
    dt = check_positive(dt_s, "dt_s")
    n = C.window_samples(window_m, speed_m_s, dt)
    if lowpass_hz is not None:
        Y = C.lowpass(Y, dt, lowpass_hz, name="Y_N")
        Q = C.lowpass(Q, dt, lowpass_hz, name="Q_N")
    yq = derailment_quotient(Y, Q)
    lifted = int(np.count_nonzero(np.isnan(yq)))
    if lifted == yq.size:
        raise ValueError("Q_N: the wheel is lifted (Q <= 0) at every sample; Y/Q is undefined")
    m = C.sliding_mean(yq, n, ignore_nan=True)
    k = int(np.nanargmax(m))
    out = assess(float(m[k]), limit)
    out.update({"window_samples": n, "window_m": n * float(speed_m_s) * dt, "index_of_max_window_start": k,
                "time_of_max_window_start_s": k * dt, "max_instantaneous": float(np.nanmax(yq)),
                "lifted_samples_excluded": lifted, "lowpass_hz": lowpass_hz})
    return out


# ============================================================================================ JNR duration criterion
def exceedance_intervals(x, dt_s: float, threshold: float, inclusive: bool = False, t0_s: float = 0.0) -> list:
    """Intervals where ``x`` > ``threshold`` (``inclusive``: >=), each a dict with ``t_start_s``, ``t_end_s``,
    ``duration_s``, ``peak``, ``index_peak``, ``truncated`` (cut by the record's start or end).  Start and end are
    the crossings of the threshold by linear interpolation between the neighbouring samples (O(dt²) accurate for
    smooth signals); at the record's ends, the first/last sample's time."""
    a = as_signal(x, "x")
    dt = check_positive(dt_s, "dt_s")
    thr = float(threshold)
    above = a >= thr if inclusive else a > thr
    if not above.any():
        return []
    d = np.diff(np.concatenate(([0], above.astype(np.int8), [0])))
    starts = np.flatnonzero(d == 1)
    ends = np.flatnonzero(d == -1) - 1
    out = []
    N = a.size
    for i0, i1 in zip(starts, ends):
        if i0 > 0:
            x0, x1 = a[i0 - 1], a[i0]
            frac = (thr - x0) / (x1 - x0) if x1 != x0 else 1.0
            ts = (i0 - 1 + frac) * dt
        else:
            ts = 0.0
        if i1 < N - 1:
            x0, x1 = a[i1], a[i1 + 1]
            frac = (x0 - thr) / (x0 - x1) if x1 != x0 else 0.0
            te = (i1 + frac) * dt
        else:
            te = (N - 1) * dt
        seg = a[i0:i1 + 1]
        ip = int(i0 + np.argmax(seg))
        out.append({"t_start_s": t0_s + ts, "t_end_s": t0_s + te, "duration_s": te - ts, "peak": float(a[ip]),
                    "index_peak": ip, "truncated": bool(i0 == 0 or i1 == N - 1)})
    return out


def jnr_limit(duration_s, base_limit: float = JNR_YQ_LIMIT, reference_duration_s: float = JNR_DURATION_S):
    """JNR derailment-coefficient limit for an exceedance of duration t [s]: ``base_limit`` for t >= the reference
    duration, base·t_ref/t (= 0.04 s/t) below it (module doc, as commonly cited).  t <= 0 gives inf (an
    instantaneous touch of the threshold)."""
    t = np.asarray(duration_s, dtype=float)
    if np.any(~np.isfinite(t)) or np.any(t < 0.0):
        raise ValueError("duration_s: expected finite durations >= 0")
    b = check_positive(base_limit, "base_limit")
    tr = check_positive(reference_duration_s, "reference_duration_s")
    with np.errstate(divide="ignore"):
        lim = np.where(t >= tr, b, b * tr / np.where(t > 0.0, t, 0.0))
    return float(lim) if lim.ndim == 0 else lim


def derailment_quotient_jnr(yq, dt_s: float, base_limit: float = JNR_YQ_LIMIT,
                            reference_duration_s: float = JNR_DURATION_S) -> dict:
    """Japanese duration criterion on a Y/Q series (module doc): every excursion above ``base_limit`` with its
    duration, peak, time-dependent limit and utilisation; ``passed`` if every peak <= its limit.  ``value`` is the
    largest utilisation (peak / limit), assessed against 1; without any excursion it is max(Y/Q) / base_limit."""
    q = as_signal(yq, "yq")
    dt = check_positive(dt_s, "dt_s")
    exc = exceedance_intervals(q, dt, base_limit)
    worst = 0.0
    for e in exc:
        lim = jnr_limit(e["duration_s"], base_limit, reference_duration_s)
        e["limit"] = lim
        e["utilisation"] = e["peak"] / lim if math.isfinite(lim) else 0.0
        e["passed"] = bool(e["peak"] <= lim)
        worst = max(worst, e["utilisation"])
    if not exc:
        worst = float(np.max(q)) / base_limit if np.max(q) > 0.0 else 0.0
    out = assess(worst, 1.0)
    out.update({"excursions": exc, "max_yq": float(np.max(q)), "base_limit": float(base_limit),
                "reference_duration_s": float(reference_duration_s),
                "longest_excursion_s": max((e["duration_s"] for e in exc), default=0.0)})
    return out


# ============================================================================================ wheel unloading / lift
def wheel_unloading(Q_N, static_wheel_load_N: float, limit: float = WHEEL_UNLOADING_LIMIT) -> dict:
    """ΔQ/Q = (Q_static − Q)/Q_static per sample (``series``) and its maximum against ``limit`` (module doc)."""
    Q = as_signal(Q_N, "Q_N")
    q0 = check_positive(static_wheel_load_N, "static_wheel_load_N")
    dq = (q0 - Q) / q0
    k = int(np.argmax(dq))
    out = assess(float(dq[k]), limit)
    out.update({"index_of_max": k, "static_wheel_load_N": q0, "series": dq})
    return out


def wheel_lift(Q_N, dt_s: float) -> dict:
    """Wheel lift (Q <= 0): number of lifted samples, the lift intervals (:func:`exceedance_intervals` of −Q at
    0, inclusive) and their total duration; ``passed`` = no lifted sample."""
    Q = as_signal(Q_N, "Q_N")
    dt = check_positive(dt_s, "dt_s")
    n = int(np.count_nonzero(Q <= 0.0))
    iv = exceedance_intervals(-Q, dt, 0.0, inclusive=True)
    for e in iv:
        e["min_load_N"] = -e.pop("peak")
        e["index_min_load"] = e.pop("index_peak")
    return {"value": n, "limit": 0, "passed": n == 0, "lifted_samples": n, "intervals": iv,
            "total_duration_s": float(sum(e["duration_s"] for e in iv)), "margin": None, "utilisation": None}


# ============================================================================================ Prud'homme
def prudhomme_limit_N(static_wheel_load_N: float | None = None, alpha: float = 1.0,
                      static_axle_load_N: float | None = None) -> float:
    """(ΣY_2m)_lim = α (10 kN + 2 Q_0/3) [N], Q_0 the static wheel load; or give the static axle load P = 2 Q_0
    (then α (10 kN + P/3)).  Exactly one of the two loads."""
    if (static_wheel_load_N is None) == (static_axle_load_N is None):
        raise ValueError("give exactly one of static_wheel_load_N and static_axle_load_N")
    a = check_positive(alpha, "alpha")
    if static_wheel_load_N is not None:
        q0 = check_positive(static_wheel_load_N, "static_wheel_load_N")
    else:
        q0 = 0.5 * check_positive(static_axle_load_N, "static_axle_load_N")
    return a * (10.0e3 + 2.0 * q0 / 3.0)


def track_shift_force_en14363(sum_Y_N, dt_s: float, speed_m_s: float, static_wheel_load_N: float,
                              alpha: float = 1.0, window_m: float = EN14363_WINDOW_M,
                              lowpass_hz: float | None = EN14363_FORCE_LOWPASS_HZ) -> dict:
    """EN 14363 track shift force of one wheelset: max |2 m sliding mean of ΣY| [N] against Prud'homme's limit
    (module doc).  ``lowpass_hz=None`` skips the 20 Hz pre-filter."""
    s = as_signal(sum_Y_N, "sum_Y_N")
    dt = check_positive(dt_s, "dt_s")
    n = C.window_samples(window_m, speed_m_s, dt)
    if lowpass_hz is not None:
        s = C.lowpass(s, dt, lowpass_hz, name="sum_Y_N")
    m = C.sliding_mean(s, n)
    k = int(np.argmax(np.abs(m)))
    out = assess(float(abs(m[k])), prudhomme_limit_N(static_wheel_load_N, alpha))
    out.update({"signed_value_N": float(m[k]), "window_samples": n, "window_m": n * float(speed_m_s) * dt,
                "time_of_max_window_start_s": k * dt, "alpha": float(alpha),
                "static_wheel_load_N": float(static_wheel_load_N), "lowpass_hz": lowpass_hz})
    return out


# ============================================================================================ summary
_WHEEL_COLUMN = re.compile(r"^Y_w(\d+)_(right|left)_N$")


def _wheels(ts: dict) -> list[tuple[int, str, str, str]]:
    """(wheelset, side, Y column, Q column) of every wheel in the table; the w1-right contract columns of
    rtri.py if no per-wheel columns are there."""
    found = []
    for name in ts:
        m = _WHEEL_COLUMN.match(name)
        if m and f"Q_w{m.group(1)}_{m.group(2)}_N" in ts:
            found.append((int(m.group(1)), m.group(2), name, f"Q_w{m.group(1)}_{m.group(2)}_N"))
    if not found and "lateral_contact_force_w1_right_N" in ts and "vertical_contact_force_w1_right_N" in ts:
        found.append((1, "right", "lateral_contact_force_w1_right_N", "vertical_contact_force_w1_right_N"))
    return sorted(found, key=lambda w: (w[0], w[1] != "right"))


def _static_load(Q: np.ndarray, key: str, static_wheel_loads_N) -> float:
    if static_wheel_loads_N is None:
        return check_positive(Q[0], f"first sample of Q of {key} (static wheel load)")
    if isinstance(static_wheel_loads_N, dict):
        if key not in static_wheel_loads_N:
            raise ValueError(f"static_wheel_loads_N: no entry for {key!r}")
        return check_positive(static_wheel_loads_N[key], f"static_wheel_loads_N[{key!r}]")
    return check_positive(static_wheel_loads_N, "static_wheel_loads_N")


def _strip(d: dict) -> dict:
    """Without the per-sample arrays (JSON-friendly)."""
    return {k: v for k, v in d.items() if not isinstance(v, np.ndarray)}


def _worst(per: dict, key: str = "utilisation") -> dict:
    """passed (all, None if none assessed), the name and entry of the largest ``key``."""
    flags = [v["passed"] for v in per.values() if v.get("passed") is not None]
    name = None
    best = -math.inf
    for k, v in per.items():
        u = v.get(key)
        if u is not None and u > best:
            best, name = u, k
    return {"passed": all(flags) if flags else None, "worst": name,
            "worst_value": None if name is None else per[name]["value"],
            "worst_utilisation": None if name is None else per[name].get("utilisation")}


def running_criteria_summary(ts: dict, speed_m_s: float, *, vehicle: str = "passenger",
                             static_wheel_loads_N=None, yq_limit: float = EN14363_YQ_LIMIT,
                             unloading_limit: float = WHEEL_UNLOADING_LIMIT,
                             lowpass_hz: float | None = EN14363_FORCE_LOWPASS_HZ,
                             window_m: float = EN14363_WINDOW_M, flange_angle_rad: float | None = None,
                             friction_coefficient: float | None = None, carbody_columns: dict | None = None,
                             carbody_limits_m_s2: dict | None = None, sperling_limit: float | None = None,
                             time_rtol: float = 1e-6) -> dict:
    """All criteria of a recorded run, one dict (JSON-serialisable: no arrays).

    ``ts``: column name -> array, with ``time_s`` (uniform) and the columns of
    :mod:`exudyn_wheelrail.scenarios.rtri`'s ``timeseries.csv``: per wheel ``Y_w<j>_<side>_N`` (track-frame y
    force of the rail on the wheel) and ``Q_w<j>_<side>_N`` (wheel load) — without them the contract columns
    ``lateral_contact_force_w1_right_N`` / ``vertical_contact_force_w1_right_N`` (one wheel) — and the car-body
    accelerations.  ``speed_m_s``: constant running speed.  ``vehicle``: "passenger", "locomotive" (α = 1.0) or
    "freight" (α = 0.85) for Prud'homme.  ``static_wheel_loads_N``: one value, a dict ``{"w1_right": …}``, or
    ``None`` = the first sample of each wheel's Q (a run that starts in static equilibrium, as the RTRI case does).
    ``flange_angle_rad`` with ``friction_coefficient``: adds Nadal's limit as a further Y/Q criterion.
    ``carbody_columns``: {"lateral": name, "vertical": name} (default: ``carbody_lateral_accelerometer_rear_m_s2``
    if present — what a floor accelerometer reads — else ``carbody_lateral_acceleration_rear_m_s2``; a column
    ``carbody_vertical_acceleration*`` for vertical).  ``carbody_limits_m_s2`` ({"peak": …, "rms": …}, optional)
    and ``sperling_limit`` (optional): without them the comfort quantities are reported, not assessed.

    What is evaluated: per wheel, EN 14363 (Y/Q)_2m (Y, Q low-passed at ``lowpass_hz``), Nadal (if given, on the
    same (Y/Q)_2m), the JNR duration criterion on the **unfiltered** Y/Q (the criterion is about short
    exceedances), ΔQ/Q and wheel lift on the unfiltered Q (ΔQ/Q after the low-pass is added as
    ``value_after_lowpass``, not assessed); per wheelset with both wheels, Prud'homme's ΣY_2m;
    per car-body direction, the EN 14363 band-passed peak/RMS and Sperling's Wz of the unfiltered acceleration.

    Returns ``{"inputs", "criteria", "verdicts", "safety_passed", "passed", "notes"}``; ``criteria`` holds per
    wheel / wheelset / direction the entries of the functions above; ``verdicts`` per criterion ``passed`` (and
    the worst wheel); ``safety_passed`` = every safety criterion passed; ``passed`` also counts the comfort
    criteria that have a limit.
    """
    if not isinstance(ts, dict):
        raise ValueError("ts: expected a dict of column name -> array")
    if "time_s" not in ts:
        raise ValueError("ts: no 'time_s' column")
    t = as_signal(ts["time_s"], "time_s", min_length=2)
    dt = C.time_step_from_time(t, rtol=time_rtol)
    V = check_positive(speed_m_s, "speed_m_s")
    if vehicle not in PRUDHOMME_ALPHA:
        raise ValueError(f"vehicle = {vehicle!r}: expected one of {sorted(PRUDHOMME_ALPHA)}")
    alpha = PRUDHOMME_ALPHA[vehicle]
    notes = []
    wheels = _wheels(ts)
    if not wheels:
        raise ValueError("ts: no wheel force columns (Y_w<j>_<side>_N with Q_w<j>_<side>_N, or the w1-right "
                         "contract columns of rtri.py)")
    cc = dict(carbody_columns or {})
    for direction, col in cc.items():
        if direction not in ("lateral", "vertical"):
            raise ValueError(f"carbody_columns: unknown direction {direction!r}")
        if col not in ts:
            raise ValueError(f"carbody_columns[{direction!r}] = {col!r}: no such column")
    if "lateral" not in cc:
        for c in ("carbody_lateral_accelerometer_rear_m_s2", "carbody_lateral_acceleration_rear_m_s2"):
            if c in ts:
                cc["lateral"] = c
                break
    if "vertical" not in cc:
        vert = sorted(c for c in ts if c.startswith("carbody_vertical_acceleration"))
        if vert:
            cc["vertical"] = vert[0]
    # only the columns used are checked (others, e.g. rtri.py's derailment_quotient_w1_right, may hold NaN)
    used = ["time_s"] + [c for w in wheels for c in w[2:]] + list(cc.values())
    cols = {name: as_signal(ts[name], name) for name in used}
    check_same_length(**cols)
    n = C.window_samples(window_m, V, dt)
    criteria = {"derailment_quotient_en14363": {}, "derailment_quotient_jnr": {}, "wheel_unloading": {},
                "wheel_lift": {}, "track_shift_force_prudhomme": {}}
    if flange_angle_rad is not None or friction_coefficient is not None:
        if flange_angle_rad is None or friction_coefficient is None:
            raise ValueError("Nadal's limit needs both flange_angle_rad and friction_coefficient")
        criteria["derailment_quotient_nadal"] = {}
        nadal = nadal_limit(flange_angle_rad, friction_coefficient)
    Yw, Qs = {}, {}
    for j, side, ycol, qcol in wheels:
        key = f"w{j}_{side}"
        Y = flange_lateral_force_N(cols[ycol], side)
        Q = cols[qcol]
        q0 = _static_load(Q, key, static_wheel_loads_N)
        Yw[key], Qs[key] = (cols[ycol], Q), q0
        en = derailment_quotient_en14363(Y, Q, dt, V, yq_limit, window_m, lowpass_hz)
        criteria["derailment_quotient_en14363"][key] = en
        if "derailment_quotient_nadal" in criteria:
            criteria["derailment_quotient_nadal"][key] = assess(en["value"], nadal)
        yq = derailment_quotient(Y, Q)
        if np.isnan(yq).any():
            yq = np.where(np.isnan(yq), 0.0, yq)     # lifted: reported by the lift criterion
            notes.append(f"{key}: {int(np.count_nonzero(Q <= 0.0))} lifted sample(s) left out of Y/Q "
                         f"(set to 0 for the JNR excursions, excluded from the EN 14363 means)")
        criteria["derailment_quotient_jnr"][key] = derailment_quotient_jnr(yq, dt)
        un = _strip(wheel_unloading(Q, q0, unloading_limit))
        if lowpass_hz is not None:                   # for information: the same after the force low-pass
            un["value_after_lowpass"] = float(np.max((q0 - C.lowpass(Q, dt, lowpass_hz, name=qcol)) / q0))
        criteria["wheel_unloading"][key] = un
        criteria["wheel_lift"][key] = wheel_lift(Q, dt)
    for j in sorted({w[0] for w in wheels}):
        r, l_ = f"w{j}_right", f"w{j}_left"
        if r in Yw and l_ in Yw:
            sumY = -(Yw[r][0] + Yw[l_][0])                 # force of the wheelset on the track, track y
            q0 = 0.5 * (Qs[r] + Qs[l_])
            criteria["track_shift_force_prudhomme"][f"ws{j}"] = track_shift_force_en14363(
                sumY, dt, V, q0, alpha, window_m, lowpass_hz)
    if not criteria["track_shift_force_prudhomme"]:
        notes.append("track shift force not evaluated: no wheelset with both wheels' forces in the table")
    # ------------------------------------------------------------------ comfort
    comfort = {}
    for direction, col in cc.items():
        acc = C.carbody_acceleration_en14363(cols[col], dt, limits_m_s2=carbody_limits_m_s2)
        if acc["peak_near_record_edge"]:
            notes.append(f"carbody_{direction}: the peak of the band-passed acceleration lies within "
                         f"{1.0 / C.EN14363_CARBODY_BAND_HZ[0]:g} s of an end of the record (filter edge transient "
                         f"possible)")
        sp = C.sperling_index(cols[col], dt, direction)
        comfort[f"carbody_{direction}"] = {"column": col, **_strip(acc)}
        comfort[f"sperling_{direction}"] = {"column": col, "Wz": sp["Wz"], "df_hz": sp["df_hz"],
                                            "range_hz": sp["range_hz"],
                                            "ride_quality": C.sperling_ride_quality(sp["Wz"]),
                                            **{k: v for k, v in assess(sp["Wz"], sperling_limit).items()
                                               if k != "value"}}
        if sp["df_hz"] > 0.25:
            notes.append(f"sperling_{direction}: frequency resolution {sp['df_hz']:.3g} Hz (record "
                         f"{t.size * dt:.3g} s) is coarse for the 0.5–2 Hz car-body modes")
    if not comfort:
        notes.append("no car-body acceleration column: comfort not evaluated")
    criteria.update(comfort)
    # ------------------------------------------------------------------ verdicts
    safety_keys = [k for k in criteria if k.startswith(("derailment", "wheel_", "track_shift"))]
    verdicts = {}
    for k in safety_keys:
        verdicts[k] = _worst(criteria[k])
    for k in comfort:
        verdicts[k] = {"passed": comfort[k].get("passed") if k.startswith("sperling")
                       else _worst(comfort[k]["assessment"])["passed"]}
    safety_flags = [verdicts[k]["passed"] for k in safety_keys if verdicts[k]["passed"] is not None]
    all_flags = [v["passed"] for v in verdicts.values() if v["passed"] is not None]
    return {
        "inputs": {"dt_s": dt, "speed_m_s": V, "n_samples": int(t.size), "duration_s": float((t.size - 1) * dt),
                   "window_m_requested": float(window_m), "window_samples": n, "window_m_effective": n * V * dt,
                   "force_lowpass_hz": lowpass_hz, "vehicle": vehicle, "prudhomme_alpha": alpha,
                   "yq_limit_en14363": float(yq_limit), "unloading_limit": float(unloading_limit),
                   "static_wheel_loads_N": Qs, "wheels": [f"w{j}_{s}" for j, s, _, _ in wheels],
                   "nadal_limit": nadal if "derailment_quotient_nadal" in criteria else None},
        "criteria": criteria,
        "verdicts": verdicts,
        "safety_passed": all(safety_flags) if safety_flags else None,
        "passed": all(all_flags) if all_flags else None,
        "notes": notes,
    }
