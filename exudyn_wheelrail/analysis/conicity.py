r"""Equivalent conicity of a wheelset/track pair from its rolling-radius-difference function.

Definitions and conventions
---------------------------
``y`` is the lateral shift of the wheelset relative to the track, positive towards the **right** rail (see
:mod:`exudyn_wheelrail.conventions`).  The rolling-radius-difference function is

.. math::  \Delta r(y) = r_\mathrm{right}(y) - r_\mathrm{left}(y)   \qquad [\mathrm{m}],

which is increasing and (for a symmetric wheelset on a symmetric track) odd.  For a pair of pure cones of
half-angle ``gamma`` on knife-edge rails ``Delta r = 2 gamma y``.

The *equivalent conicity* ``gamma_e(yhat)`` (often written ``tan gamma_e``) is the conicity of the pure cone that
would make the wheelset perform the same free kinematic (Klingel) oscillation as the actual profiles do at the
lateral amplitude ``yhat``.  It is therefore a *function of the amplitude*, not a single number; EN 15302 /
EN 14363 practice quotes it at the reference amplitude ``yhat = 3 mm``.  Three evaluation methods are provided:

``"wavelength"`` — kinematic (Klingel) definition.
    A free wheelset rolling without slip obeys, with ``x`` the distance travelled along the track, ``e`` half the
    distance between the two contact points and ``r0`` the nominal rolling radius, Klingel's kinematic equation

    .. math:: y''(x) = -\frac{\Delta r(y)}{2 e r_0}.

    For a cone this is harmonic with the Klingel wavelength ``lambda = 2 pi sqrt(e r0 / gamma)``
    (:func:`klingel_wavelength`).  For a general ``Delta r`` the nonlinear equation is integrated from the turning
    point ``y(0) = yhat, y'(0) = 0`` (``scipy.integrate.solve_ivp``, DOP853, ``rtol = 1e-12``); the wavelength is
    the distance between two successive passes through the *other* turning point (event ``y' = 0`` crossed
    upwards), i.e. one full period, and ``gamma_e = e r0 (2 pi / lambda)^2`` inverts Klingel's formula.  This is
    the method of EN 15302:2008+A1:2010, Annex B ("integration of the nonlinear differential equation").  For a
    non-odd ``Delta r`` the excursion on the opposite side differs from ``yhat``; it is checked to stay inside the
    sampled range.

``"harmonic"`` — harmonic linearisation (describing function, Wickens; Krylov–Bogoliubov equivalent
linearisation).
    The motion is assumed sinusoidal, ``y = yhat sin psi``, and ``Delta r`` is replaced by the linear function
    that has the same fundamental Fourier component:

    .. math:: \gamma_e = \frac{1}{2\pi\hat y}\int_0^{2\pi}\Delta r(\hat y\sin\psi)\,\sin\psi\,d\psi
                       = \frac{1}{\pi\hat y^2}\int_{-\hat y}^{\hat y}
                         \frac{\Delta r(y)\,y}{\sqrt{\hat y^2-y^2}}\,dy .

    For ``Delta r = 2 gamma y`` this gives ``gamma`` exactly; for ``2 gamma y + 2 c y^3`` it gives
    ``gamma + 3/4 c yhat^2``.  Only the odd part of ``Delta r`` contributes.

``"regression"`` — linear regression of the ``Delta r`` function (EN 15302:2008+A1:2010, Annex C).
    ``Delta r`` is fitted over ``[-yhat, yhat]`` by a straight line ``a + 2 gamma_e y`` (least squares, with
    intercept), each ``y`` weighted by the time a sinusoidal motion of amplitude ``yhat`` spends there,
    ``w(y) = 1 / sqrt(yhat^2 - y^2)``.  *Caveat:* the weighting of Annex C is taken from the specification of
    this module; the text of the annex itself was not available to us (see "Sources" below).  With this weight
    the normal equations decouple (``int w y dy = 0`` on the symmetric interval, ``int w y^2 dy = pi yhat^2 / 2``)
    and the slope reduces *exactly* to the harmonic-linearisation integral above — the two methods coincide for
    every ``Delta r``; ``tests/test_conicity.py`` checks this, and checks the regression against an independent
    discrete weighted ``numpy.polyfit``.

The harmonic and wavelength definitions agree to first order in the nonlinearity (e.g. both give
``gamma + 3/4 c yhat^2 + O(c^2 yhat^4)`` for the cubic above) but differ at large nonlinearity.

Numerics
--------
The sampled ``Delta r`` is interpolated **linearly** (``numpy.interp``).  For ``"harmonic"`` and ``"regression"``
the weighted integrals of that piecewise-linear interpolant are evaluated **in closed form** segment by segment
(substitution ``y = yhat sin theta`` removes the end-point singularity; antiderivatives of ``sin^k theta``), so the
only error is the interpolation error, ``O(h^2 max|Delta r''|)`` for a sample spacing ``h``: use a dense sweep
(e.g. ``h <= 0.01 mm``) for smooth functions.  Kinks (flange contact) are integrated exactly when they are sample
points, and a repeated ``y`` value with two different ``Delta r`` values encodes a jump of ``Delta r``.

Input data
----------
``y_m`` and ``delta_r_m`` may be given in any order (they are sorted together by ``y``).  If the samples cover both
signs of ``y`` they are used as they are.  If all samples lie on one side of zero (typically ``y >= 0``) the
function is assumed **odd** and extended by ``Delta r(-y) = -Delta r(y)``; a sample at ``y = 0`` must then have
``Delta r = 0``.  The amplitude must satisfy ``-yhat >= min(y)`` and ``yhat <= max(y)`` (after the extension).

Sources (consulted via public catalogue pages; no text or code copied)
----------------------------------------------------------------------
* EN 15302:2008+A1:2010 *Railway applications — Method for determining the equivalent conicity* (CEN/TC 256).
  Scope and table of contents (e.g. shop.standards.ie; SIS SS-EN 15302:2008+A1:2010; ONORM EN 15302:2011-02 on
  catalogue.normdocs.ru): the standard sets the *principles* of the calculation and a benchmark with reference
  profiles, reference results and tolerances (Annexes D–F), but "does not impose any particular numerical
  calculation method"; it gives informative examples of the use of the Klingel formula (Annex B, "integration of
  the nonlinear differential equation") and of the linear regression of the ``Delta r`` function (Annex C).
* EN 15302:2021 *Wheel-rail contact geometry parameters — Definitions and methods for evaluation* (table of
  contents on secure.madcad.com): 9.1.1 mathematical description of the kinematic lateral wheelset motion, 9.1.2
  wavelength of a coned wheelset, 9.2 equivalent conicity, 9.3 nonlinearity parameter; CEN/TR 17792 gives the
  background (standards.iteh.ai).  UIC Code 519 (2004) is the predecessor with the same principles.
* Definition as an amplitude-dependent equivalent cone slope giving the same wavelength of the sinusoidal motion:
  German Wikipedia, "Äquivalente Konizität".
* J. Klingel (1883), "Über den Lauf der Eisenbahnwagen auf gerader Bahn", Organ für die Fortschritte des
  Eisenbahnwesens 38: kinematic oscillation ``y'' + gamma/(e r0) y = 0``, ``lambda = 2 pi sqrt(e r0/gamma)``.
  Its limits (3-D geometry effects) are discussed by M. Antali, G. Stepan, S.J. Hogan, "Kinematic oscillations
  of railway wheelsets", Multibody System Dynamics 34 (2015).
* A.H. Wickens, *Fundamentals of Rail Vehicle Dynamics*, Swets & Zeitlinger 2003 — equivalent conicity by
  quasi-/harmonic linearisation of the wheel–rail geometry.
* O. Polach, D. Nicklisch, "Wheel/rail contact geometry parameters in regard to vehicle behaviour and their
  alteration with wear", Wear 366–367 (2016) — conicity as a function of amplitude, nonlinearity parameter.

Units: SI throughout (metres; conicities dimensionless).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["equivalent_conicity", "conicity_curve", "klingel_wavelength", "METHODS", "REFERENCE_AMPLITUDE_M"]

#: Evaluation methods accepted by :func:`equivalent_conicity`.
METHODS = ("harmonic", "wavelength", "regression")

#: Reference amplitude at which equivalent conicity is usually quoted (EN 15302 / EN 14363 practice) [m].
REFERENCE_AMPLITUDE_M = 3.0e-3

#: Minimum number of samples of the Delta r function.
MIN_SAMPLES = 3

_ODE_RTOL = 1e-12
_ODE_ATOL = 1e-14


# ----------------------------------------------------------------------------------------------------------------
# public API
# ----------------------------------------------------------------------------------------------------------------
def klingel_wavelength(conicity: float, half_contact_distance_m: float = 0.75, r0_m: float = 0.46) -> float:
    """Wavelength [m] of the kinematic (Klingel) oscillation of a coned wheelset.

    ``lambda = 2 pi sqrt(e r0 / gamma)`` with ``e`` = half the lateral distance between the contact points [m],
    ``r0`` = nominal rolling radius [m] and ``gamma`` = (equivalent) conicity [-] (Klingel 1883).
    """
    gamma = _positive_finite(conicity, "conicity")
    e = _positive_finite(half_contact_distance_m, "half_contact_distance_m")
    r0 = _positive_finite(r0_m, "r0_m")
    return 2.0 * math.pi * math.sqrt(e * r0 / gamma)


def equivalent_conicity(y_m, delta_r_m, amplitude_m: float, method: str = "harmonic",
                        half_contact_distance_m: float = 0.75, r0_m: float = 0.46) -> float:
    """Equivalent conicity ``gamma_e`` [-] at the lateral amplitude ``amplitude_m`` (``yhat``) [m].

    Parameters
    ----------
    y_m, delta_r_m:
        Samples of the rolling-radius-difference function ``Delta r(y) = r_right - r_left`` [m] versus the
        lateral wheelset shift ``y`` [m] (positive towards the right rail).  Any order.  Either both signs of
        ``y``, or one side only, in which case ``Delta r`` is assumed odd (see the module docstring).
    amplitude_m:
        Lateral amplitude ``yhat > 0`` [m]; ``[-yhat, yhat]`` must lie inside the sampled range.  EN 15302 /
        EN 14363 practice uses :data:`REFERENCE_AMPLITUDE_M` = 3 mm.
    method:
        ``"harmonic"`` (describing function), ``"wavelength"`` (integration of Klingel's nonlinear equation,
        EN 15302 Annex B) or ``"regression"`` (weighted linear regression, EN 15302 Annex C).
    half_contact_distance_m, r0_m:
        ``e`` and ``r0`` [m]; used by ``"wavelength"`` only (the result for a cone does not depend on them; for a
        nonlinear ``Delta r`` only through the product ``e r0``, which scales the wavelength but not
        ``gamma_e``).

    Raises
    ------
    ValueError
        on NaN/inf samples, arrays of different lengths or shapes, fewer than :data:`MIN_SAMPLES` samples, a
        non-positive amplitude or one outside the sampled range, an unknown method, or (``"wavelength"``) a
        ``Delta r`` that produces no oscillation.
    """
    method = _check_method(method)
    y, dr = _prepare_samples(y_m, delta_r_m)
    return _conicity_prepared(y, dr, amplitude_m, method, half_contact_distance_m, r0_m)


def conicity_curve(y_m, delta_r_m, amplitudes_m, method: str = "harmonic",
                   half_contact_distance_m: float = 0.75, r0_m: float = 0.46) -> np.ndarray:
    """Equivalent conicity for each amplitude of ``amplitudes_m`` (array of the same shape, [-]).

    Same arguments and errors as :func:`equivalent_conicity`; the samples are validated once.
    """
    method = _check_method(method)
    y, dr = _prepare_samples(y_m, delta_r_m)
    amps = np.asarray(amplitudes_m, dtype=float)
    if amps.size == 0:
        raise ValueError("amplitudes_m is empty: give at least one amplitude")
    out = np.empty(amps.shape, dtype=float)
    for idx, amp in np.ndenumerate(amps):
        out[idx] = _conicity_prepared(y, dr, float(amp), method, half_contact_distance_m, r0_m)
    return out


# ----------------------------------------------------------------------------------------------------------------
# input handling
# ----------------------------------------------------------------------------------------------------------------
def _positive_finite(value, name: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be positive and finite, got {v!r}")
    return v


def _check_method(method) -> str:
    if not isinstance(method, str) or method.lower() not in METHODS:
        raise ValueError(f"unknown method {method!r}: expected one of {', '.join(METHODS)}")
    return method.lower()


def _prepare_samples(y_m, delta_r_m) -> tuple[np.ndarray, np.ndarray]:
    """Validate, sort by y (stable, so repeated y keep their order) and, for one-sided data, extend oddly."""
    y = np.asarray(y_m, dtype=float)
    dr = np.asarray(delta_r_m, dtype=float)
    if y.ndim != 1 or dr.ndim != 1:
        raise ValueError(f"y_m and delta_r_m must be 1-D arrays, got shapes {y.shape} and {dr.shape}")
    if y.size != dr.size:
        raise ValueError(f"y_m and delta_r_m have different lengths ({y.size} and {dr.size})")
    if y.size < MIN_SAMPLES:
        raise ValueError(f"too few samples of the Delta r function: {y.size} (need at least {MIN_SAMPLES})")
    if not np.all(np.isfinite(y)):
        raise ValueError("y_m contains NaN or infinite values")
    if not np.all(np.isfinite(dr)):
        raise ValueError("delta_r_m contains NaN or infinite values")

    order = np.argsort(y, kind="stable")
    y, dr = y[order], dr[order]

    if y[0] >= 0.0 or y[-1] <= 0.0:  # one-sided: assume Delta r odd
        if y[0] == y[-1]:
            raise ValueError("all samples have the same y: the Delta r function is not sampled over a range")
        if y[-1] <= 0.0:  # only y <= 0: mirror to y >= 0 first
            y, dr = -y[::-1], -dr[::-1]
        at_zero = y == 0.0
        if np.any(at_zero):
            tol = 1e-9 * float(np.max(np.abs(dr))) + 1e-15
            if np.any(np.abs(dr[at_zero]) > tol):
                raise ValueError("one-sided samples are extended as an odd function, so Delta r(0) must be 0; "
                                 f"got {dr[at_zero][0]!r} m at y = 0 (give samples for both signs of y instead)")
            y, dr = y[~at_zero], dr[~at_zero]
        y = np.concatenate((-y[::-1], [0.0], y))
        dr = np.concatenate((-dr[::-1], [0.0], dr))
    if np.unique(y).size < 2:
        raise ValueError("the Delta r function must be sampled at two or more distinct y values")
    return y, dr


def _check_amplitude(y: np.ndarray, amplitude_m) -> float:
    amp = _positive_finite(amplitude_m, "amplitude_m")
    tol = 1e-12 * max(abs(y[0]), abs(y[-1]))
    if amp > y[-1] + tol or -amp < y[0] - tol:
        raise ValueError(f"amplitude {amp:.6g} m exceeds the sampled range of y "
                         f"[{y[0]:.6g}, {y[-1]:.6g}] m: [-amplitude, +amplitude] must be covered")
    return amp


def _conicity_prepared(y, dr, amplitude_m, method, half_contact_distance_m, r0_m) -> float:
    amp = _check_amplitude(y, amplitude_m)
    if method == "harmonic":
        return _harmonic(y, dr, amp)
    if method == "regression":
        return _regression(y, dr, amp)
    e = _positive_finite(half_contact_distance_m, "half_contact_distance_m")
    r0 = _positive_finite(r0_m, "r0_m")
    return _wavelength_conicity(y, dr, amp, e, r0)


# ----------------------------------------------------------------------------------------------------------------
# closed-form weighted moments of the piecewise-linear interpolant
# ----------------------------------------------------------------------------------------------------------------
def _weighted_moments(y: np.ndarray, dr: np.ndarray, amp: float) -> tuple[float, float, float, float, float]:
    r"""Integrals over ``[-amp, amp]`` with weight ``w = 1/sqrt(amp^2 - y^2)`` of the linear interpolant ``f``.

    Returns ``(S0, Sy, Syy, Sf, Syf)`` = integrals of ``w``, ``w y``, ``w y^2``, ``w f``, ``w y f``.  With
    ``y = amp sin(theta)``: ``w dy = d theta`` and ``int sin^k`` has the antiderivatives ``theta``, ``-cos``,
    ``theta/2 - sin(2 theta)/4``.  On a segment ``f = f0 + b (y - y0)``; differences are formed in a
    cancellation-free way.
    """
    inside = (y > -amp) & (y < amp)
    ys = np.concatenate(([-amp], y[inside], [amp]))
    # values at the segment ends: interior samples keep their own value, so a repeated y (jump) is preserved
    fs = np.concatenate(([np.interp(-amp, y, dr)], dr[inside], [np.interp(amp, y, dr)]))
    y0, y1 = ys[:-1], ys[1:]
    f0, f1 = fs[:-1], fs[1:]
    width = y1 - y0
    keep = width > 0.0  # zero-width segments (jumps) carry no weight
    y0, y1, f0, f1, width = y0[keep], y1[keep], f0[keep], f1[keep], width[keep]
    slope = (f1 - f0) / width
    a = f0 - slope * y0  # f = a + slope * y on the segment

    th0 = np.arcsin(np.clip(y0 / amp, -1.0, 1.0))
    th1 = np.arcsin(np.clip(y1 / amp, -1.0, 1.0))
    dth = th1 - th0
    half_sum = 0.5 * (th0 + th1)
    d_i0 = dth                                                       # int d theta
    d_i1 = 2.0 * np.sin(half_sum) * np.sin(0.5 * dth)                # int sin theta = cos th0 - cos th1
    d_i2 = 0.5 * (dth - np.cos(th0 + th1) * np.sin(dth))             # int sin^2 theta

    s0 = float(np.sum(d_i0))
    sy = amp * float(np.sum(d_i1))
    syy = amp * amp * float(np.sum(d_i2))
    sf = float(np.sum(a * d_i0 + slope * amp * d_i1))
    syf = float(np.sum(a * amp * d_i1 + slope * amp * amp * d_i2))
    return s0, sy, syy, sf, syf


def _harmonic(y, dr, amp) -> float:
    """Describing function: gamma_e = 1/(pi amp^2) * int w y Delta r dy (module docstring)."""
    *_, syf = _weighted_moments(y, dr, amp)
    return syf / (math.pi * amp * amp)


def _regression(y, dr, amp) -> float:
    """Weighted least-squares line ``a + 2 gamma_e y`` through Delta r on [-amp, amp], weight 1/sqrt(amp^2-y^2).

    Solves the full 2x2 normal equations (intercept included) with the continuous weighted moments; returns half
    the fitted slope.
    """
    s0, sy, syy, sf, syf = _weighted_moments(y, dr, amp)
    det = s0 * syy - sy * sy
    slope = (s0 * syf - sy * sf) / det
    return 0.5 * slope


# ----------------------------------------------------------------------------------------------------------------
# kinematic wavelength (integration of Klingel's nonlinear equation)
# ----------------------------------------------------------------------------------------------------------------
def _wavelength_conicity(y, dr, amp, e, r0) -> float:
    """gamma_e = e r0 (2 pi / lambda)^2 with lambda the period of y'' = -Delta r(y) / (2 e r0), y(0)=amp, y'(0)=0.

    Non-dimensional form: u = y/amp, tau = x/L with L^2 = 2 e r0 amp / Delta r(amp), so that
    u'' = -Delta r(amp u) / Delta r(amp) and u(0) = 1, u'(0) = 0.
    """
    dr_amp = float(np.interp(amp, y, dr))
    if not dr_amp > 0.0:
        raise ValueError(f"Delta r({amp:.6g} m) = {dr_amp:.6g} m is not positive: no restoring kinematic "
                         "oscillation starts from this amplitude (Delta r must increase through zero)")
    length_scale = math.sqrt(2.0 * e * r0 * amp / dr_amp)

    # a first estimate of the period from the harmonic linearisation, for the integration span only
    gamma_h = _harmonic(y, dr, amp)
    stiffness = 2.0 * gamma_h * amp / dr_amp
    period_est = 2.0 * math.pi / math.sqrt(stiffness) if stiffness > 0.0 else 2.0 * math.pi

    def rhs(_tau, state):
        return (state[1], -np.interp(amp * state[0], y, dr) / dr_amp)

    def lower_turning_point(_tau, state):  # u' crosses zero upwards at the far-side turning point
        return state[1]

    lower_turning_point.direction = 1.0

    span = 2.0 * period_est
    for _ in range(8):
        sol = solve_ivp(rhs, (0.0, span), (1.0, 0.0), method="DOP853", rtol=_ODE_RTOL, atol=_ODE_ATOL,
                        events=lower_turning_point)
        if not sol.success:
            raise ValueError(f"integration of Klingel's equation failed: {sol.message}")
        t_ev = sol.t_events[0]
        if t_ev.size >= 2:
            break
        span *= 2.0
    else:
        raise ValueError(f"no kinematic oscillation found at amplitude {amp:.6g} m "
                         "(the Delta r function is not restoring over the sampled range)")

    y_far = amp * float(sol.y_events[0][0][0])
    tol = 1e-9 * max(abs(y[0]), abs(y[-1]))
    if y_far < y[0] - tol:
        raise ValueError(f"starting at +{amp:.6g} m the wheelset swings to {y_far:.6g} m, beyond the sampled "
                         f"range [{y[0]:.6g}, {y[-1]:.6g}] m: extend the Delta r samples")
    wavelength = (float(t_ev[1]) - float(t_ev[0])) * length_scale
    return e * r0 * (2.0 * math.pi / wavelength) ** 2
