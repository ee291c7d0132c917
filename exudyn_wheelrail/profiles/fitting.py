"""Smooth fit of ordered profile points into a :class:`~exudyn_wheelrail.profiles.dense.DenseProfile`.

:func:`dense_from_points` fits a C2 parametric cubic spline to ordered points (interpolating exact points, or
smoothing measurement noise of standard deviation ``sigma``) and resamples it densely, about
:data:`DEFAULT_SPACING_M` apart along the curve, with the spline's exact first and second derivatives.

Input and output are in the *profile frame* of :mod:`exudyn_wheelrail.conventions`, in **metres**, points ordered
from the gauge side to the field side.  Assumptions: the default noise :data:`DEFAULT_GAUGE_NOISE_M` (0.01 mm) is
typical of contact and laser profile gauges; the smoothing fit uses the discrepancy principle (RMS normal residual
= sigma) with ``scipy.interpolate.make_smoothing_spline`` and then FITPACK (``scipy.interpolate.splprep``) with the
residual sums of :data:`FITPACK_RESIDUAL_BANDS`; details in :func:`dense_from_points`.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.interpolate import BSpline, make_interp_spline, make_smoothing_spline, splprep
from scipy.optimize import brentq

from .dense import DenseProfile
from .validation import ProfileError, in_plausible_extent, profile_extent, validate_profile_points

#: Standard deviation of the measurement noise [m] assumed when ``smoothing=None``: 0.01 mm, typical of contact and
#: laser profile gauges.
DEFAULT_GAUGE_NOISE_M = 1.0e-5
#: Spacing [m] along the curve of the dense samples returned by :func:`dense_from_points`.
DEFAULT_SPACING_M = 2.0e-5
#: When interpolating (``smoothing=0``), points closer than this [m] to the previous kept point are dropped: they only
#: carry the rounding noise of the file (8 significant digits = 1 nm) and would turn it into huge curvature spikes.
#: The interpolant still passes within nanometres of the dropped points.
INTERPOLATION_MIN_SPACING_M = 1.0e-5
#: Residual sums tried for the final smoothing fit, as ``n + band * sqrt(2 n)`` times sigma^2: the mean of the
#: residual sum of n normal noise components plus 2, 3, 4 of its standard deviations.  All are consistent with the
#: noise; the fit with the fewest knots is kept (FITPACK occasionally adds superfluous knots that put wiggles into
#: the curvature when the target sits just below a noise realisation).
FITPACK_RESIDUAL_BANDS = (2.0, 3.0, 4.0)


def _chord_parameter(p: np.ndarray) -> np.ndarray:
    return np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])


def _normal_rms(spline: BSpline, t: np.ndarray, p: np.ndarray) -> float:
    """RMS of the residual components normal to the fitted curve at the data parameters."""
    r = p - spline(t)
    d = spline.derivative()(t)
    d = d / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-300)[:, None]
    return float(np.sqrt(np.mean((d[:, 0] * r[:, 1] - d[:, 1] * r[:, 0]) ** 2)))


def _penalised_fit(t: np.ndarray, p: np.ndarray, sigma: float) -> BSpline:
    """Cubic smoothing spline (knots at all data, penalty on the second derivative) of both coordinates with one
    common penalty, chosen so that the RMS normal residual equals ``sigma`` (discrepancy principle)."""
    t0, length = t[0], t[-1] - t[0]
    u = (t - t0) / length

    def build(log_lam: float) -> BSpline:
        lam = 10.0 ** log_lam
        sy = make_smoothing_spline(u, p[:, 0], lam=lam)
        sz = make_smoothing_spline(u, p[:, 1], lam=lam)
        m = min(len(sy.c), len(sz.c))
        return BSpline(sy.t * length + t0, np.column_stack([sy.c[:m], sz.c[:m]]), 3)

    def misfit(log_lam: float) -> float:
        return math.log(max(_normal_rms(build(log_lam), t, p), 1e-300) / sigma)

    lo, hi = -24.0, 8.0
    if misfit(hi) <= 0.0:            # even the straightest fit is within the noise
        return build(hi)
    if misfit(lo) >= 0.0:
        return build(lo)
    return build(brentq(misfit, lo, hi, xtol=0.02))


def _reparametrise(spline: BSpline, t: np.ndarray, p: np.ndarray):
    """Arc length along ``spline`` of the foot points of ``p`` (a few Newton steps from ``t``), in sorted order.

    Feet may lie slightly beyond the ends of the data range (the spline is continued polynomially there, at most
    2 % of the length), so end points do not pile up on one parameter value.  Points whose foot coincides (within 0.1 nm) with the previous
    one are dropped: they add nothing and would make the spline basis singular.
    """
    d1s, d2s = spline.derivative(1), spline.derivative(2)
    margin = 0.02 * (t[-1] - t[0])
    tau = t.copy()
    for _ in range(5):
        r = spline(tau) - p
        d1, d2 = d1s(tau), d2s(tau)
        g = np.sum(r * d1, axis=1)
        speed2 = np.sum(d1 * d1, axis=1)
        h = speed2 + np.sum(r * d2, axis=1)
        h = np.where(h > 0.1 * speed2, h, speed2)
        tau = np.clip(tau - g / h, t[0] - margin, t[-1] + margin)
    lo, hi = float(tau.min()), float(tau.max())
    fine = np.linspace(lo, hi, max(20 * len(t), 2001))
    speed = np.hypot(*d1s(fine).T)
    arc = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(fine))])
    s = np.interp(tau, fine, arc)
    order = np.argsort(s, kind="stable")
    s, p = s[order], p[order]
    keep = np.concatenate([[True], np.diff(s) > 1e-10])
    return s[keep] - s[keep][0], p[keep]


def _thin(p: np.ndarray, min_spacing: float) -> np.ndarray:
    """Indices of points kept so that consecutive kept points are at least ``min_spacing`` apart (ends kept)."""
    keep = [0]
    for k in range(1, len(p)):
        if np.hypot(*(p[k] - p[keep[-1]])) >= min_spacing:
            keep.append(k)
    last = len(p) - 1
    if keep[-1] != last:
        if len(keep) > 1 and np.hypot(*(p[last] - p[keep[-1]])) < min_spacing:
            keep[-1] = last
        else:
            keep.append(last)
    return np.array(keep)


def _fit_spline(p: np.ndarray, sigma: float) -> tuple[BSpline, np.ndarray]:
    """The fitted C2 cubic spline c(tau) and the data parameters."""
    t = _chord_parameter(p)
    if sigma == 0.0:
        return make_interp_spline(t, p, k=3), t
    preliminary = _penalised_fit(t, p, sigma)
    s, p_sorted = _reparametrise(preliminary, t, p)
    n = len(s)
    best = None
    for band in FITPACK_RESIDUAL_BANDS:
        target = (n + band * math.sqrt(2.0 * n)) * sigma ** 2
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                (tck, _), fp, ier, _ = splprep([p_sorted[:, 0], p_sorted[:, 1]], u=s, k=3, s=target,
                                               full_output=1, quiet=1)
            except ValueError:
                continue
        # ier 2 / 3: FITPACK met s only approximately (or stopped iterating on it): usable if fp is close
        if ier not in (-2, -1, 0, 2, 3) or not fp <= 1.5 * target:
            continue
        if best is None or len(tck[0]) < len(best[0]):
            best = tck
    if best is None:   # FITPACK failed: the penalised spline refitted on the new parameter
        return _penalised_fit(s, p_sorted, sigma), s
    knots, coeffs, degree = best
    m = len(knots) - degree - 1
    return BSpline(knots, np.column_stack([coeffs[0][:m], coeffs[1][:m]]), degree), s


def dense_from_points(y, z, smoothing: float | None = None, name: str = "profile", *,
                      spacing: float = DEFAULT_SPACING_M, validate: bool = True) -> DenseProfile:
    """Smooth C2 parametric fit of ordered profile points, densely resampled with exact derivatives.

    ``y``, ``z``: points in metres in the profile frame, ordered from the gauge side to the field side.
    The curve c(tau) = (y(tau), z(tau)) is a cubic B-spline (C2) in a parameter tau close to arc length:

    * ``smoothing=0``: interpolation.  tau = cumulative chord length; the not-a-knot cubic spline passes through
      every point (points closer than :data:`INTERPOLATION_MIN_SPACING_M` to their predecessor are dropped first, so
      that file rounding does not produce curvature spikes).  For exact point files (analytic standards exported
      as points, e.g. the Manchester benchmark files).
    * ``smoothing=sigma > 0``: ``sigma`` is the standard deviation [m] of the measurement noise normal to the
      profile.  (1) A cubic smoothing spline with knots at every point (``scipy.interpolate.make_smoothing_spline``,
      one penalty for both coordinates, so the fit does not depend on the orientation) is fitted on the chord
      length with the penalty chosen so that the RMS normal residual is ``sigma``.  (2) Each point is projected onto
      it and tau is set to the arc length of its foot point: this removes the jitter that noise puts into chord
      lengths (with dense noisy samples the chords are mostly noise).  (3) The final spline is FITPACK's smoothing
      spline (``scipy.interpolate.splprep``) on that parameter with a residual sum ``(n + b sqrt(2 n)) sigma^2``,
      b = 2, 3, 4 (:data:`FITPACK_RESIDUAL_BANDS`; FITPACK recommends n +- sqrt(2 n) for weights 1), keeping the
      fit with the fewest knots: FITPACK places knots only where the data need them, which keeps the curvature of
      smooth parts free of noise.  Should FITPACK fail, the spline of step (1) refitted on the new parameter is
      used.
    * ``smoothing=None``: ``sigma = DEFAULT_GAUGE_NOISE_M`` (0.01 mm, typical gauge noise).

    Returns a :class:`DenseProfile` sampled uniformly in tau with spacing about ``spacing`` along the curve, with the
    spline's exact first and second derivatives with respect to tau.  ``validate`` runs
    :func:`validate_profile_points` on the input first (the readers have already done so).
    """
    y = np.asarray(y, dtype=float).ravel()
    z = np.asarray(z, dtype=float).ravel()
    if validate:
        validate_profile_points(y, z, name)
        extent = profile_extent(y, z)
        if in_plausible_extent(extent * 1e-3):
            raise ProfileError(f"{name}: the points span {extent:.4g} m (bounding-box diagonal): they are evidently "
                               f"millimetres, but dense_from_points expects metres")
    elif len(y) != len(z) or len(y) < 4:
        raise ProfileError(f"{name}: need equally long y and z with at least 4 points")
    sigma = DEFAULT_GAUGE_NOISE_M if smoothing is None else float(smoothing)
    if not (sigma >= 0.0 and math.isfinite(sigma)):
        raise ProfileError(f"{name}: smoothing must be None, 0 or a positive noise level in metres, got {smoothing!r}")
    if not spacing > 0:
        raise ProfileError(f"{name}: spacing must be positive, got {spacing!r}")
    p = np.column_stack([y, z])
    if sigma == 0.0:
        p = p[_thin(p, INTERPOLATION_MIN_SPACING_M)]
        if len(p) < 4:
            raise ProfileError(f"{name}: fewer than 4 points are at least {INTERPOLATION_MIN_SPACING_M:g} m apart")
    spline, tau_data = _fit_spline(p, sigma)
    tau0, tau1 = float(tau_data[0]), float(tau_data[-1])
    count = max(int(math.ceil((tau1 - tau0) / spacing)) + 1, 4)
    tau = np.linspace(tau0, tau1, count)
    c0, c1, c2 = spline(tau), spline.derivative(1)(tau), spline.derivative(2)(tau)
    return DenseProfile(c0[:, 0].copy(), c0[:, 1].copy(), c1[:, 0].copy(), c1[:, 1].copy(), c2[:, 0].copy(),
                        c2[:, 1].copy(), name=name)
