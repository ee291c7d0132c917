r"""Prescribed lateral ground motion of a bridge's supports (earthquake-like), relative-motion formulation.

>>> motion = SmoothHarmonicSupportMotion(peak_acceleration_m_s2=1.5, frequency_Hz=1.5)          # doctest: +SKIP
>>> bridge = add_bridge(mbs, modes)                                                           # doctest: +SKIP
>>> bridge.add_support_motion(mbs, motion)     # modal load -Γ ÿ_g(t); the connector sees y_g(t)  # doctest: +SKIP

Formulation (exact for a linear structure on supports that all move together)
------------------------------------------------------------------------------
All supports move laterally (track frame y, right) by the same ground displacement ``y_g(t)``.  The deck's
absolute nodal displacements are split into the rigid-body motion that the moving supports impose and a
displacement relative to them,

    ``u = r y_g(t) + u_rel``,   ``r`` = 1 at every lateral DOF ``v``, 0 elsewhere,

where ``r`` is the quasi-static influence vector of a unit support translation: a rigid lateral translation of the
whole deck (``K r = 0``, so the supports' motion strains nothing).  ``u_rel`` vanishes at the supports and is
expanded in the fixed-support modes, ``u_rel = Φ q``.  Substituting into ``M ü + C u̇_rel + K u = F`` and projecting
on the modes gives the modal equations with the *effective earthquake load*

    ``q̈_n + 2 ζ_n ω_n q̇_n + ω_n² q_n = Φ_nᵀ F - Γ_n ÿ_g(t)``,   ``Γ_n = φ_nᵀ M r``   (participation factors)

(damping acts on the relative motion: modal damping, as for the fixed-support deck).  ``M`` is the consistent mass
on **all** DOFs: the support DOFs are coupled to the free ones by the consistent mass, and ``φ_n`` is zero there,
so ``φ_nᵀ M r`` is the exact projection of the inertia of the rigid motion.  For a simply supported
Euler–Bernoulli span with mass-normalised modes ``√(2/(mL)) sin(nπx/L)``: ``Γ_n = 2√(2mL)/(nπ)`` for odd n
(0 for even n), effective modal mass of the first mode ``Γ_1² = 8 mL/π²``.

What the wheels see: the rails' centre line at rail-top level is displaced laterally by ``y_g(t) + Φ_y(s) q`` and
moves with ``ẏ_g(t) + Φ_y(s) q̇`` (material velocity; vertical displacement and roll are unchanged by a lateral
ground motion) — :mod:`exudyn_wheelrail.multibody.connector` adds ``y_g``, ``ẏ_g`` of the bridge's support motion to
every wheelset's rail position and rail velocity.  The forces of the wheels on the rails enter the relative modal
equations unchanged (``Φᵀ F``: physical forces; the inertia of the rigid motion is the ``-Γ ÿ_g`` term).

Assumptions (stated)
--------------------
* **Synchronous (uniform) ground motion**: every support and the track off the deck (embankment, abutments) move
  together by ``y_g(t)`` — no wave passage, no spatial incoherence, no relative support displacement (which would
  need a pseudo-static part ``K_ff⁻¹ K_fs u_s`` per support).  So the rails off the deck move by ``y_g`` too and
  the model frame of the vehicle (inertial) does not; the vehicle feels the ground motion through the contact only.
* Lateral (track-frame y) only; vertical ground motion is not provided.  Piers are rigid (no soil–structure
  interaction).
* The default record, :class:`SmoothHarmonicSupportMotion`, is a harmonic **sine burst**: ground displacement
  ``y_g = Y w(τ) sin(Ω τ)`` (``τ = t - start_s``) with a window ``w`` that rises from 0 to 1 over ``ramp_cycles``
  periods by the quintic smoothstep ``10x³ - 15x⁴ + 6x⁵`` (C²: displacement, velocity and acceleration start from
  zero — no velocity jump of the rails under a vehicle at rest on them), stays 1 for ``plateau_cycles`` periods and
  falls back the same way (it ends at rest, with no residual displacement or velocity: no baseline drift).  On the
  plateau the acceleration is exactly ``-Y Ω² sin(Ω τ)``; ``Y`` is scaled so that the peak ground acceleration of
  the whole burst (ramps included) is the stated ``a_p``.
* Typical choice (examples/bridge_crossing.py ``--support-motion 1.5,1.5``): ``f = 1.5 Hz``, ``a_p = 1.5 m/s²``.
  Rationale: periods of 0.5–1 s lie at and just beyond the corner period T_C = 0.4–0.8 s of the EN 1998-1 type 1
  spectra, where strong ground motion carries large velocity and displacement, and they coincide with the lateral
  and roll suspension modes of a passenger coach (≈ 0.5–1.5 Hz): the vehicle is shaken, while a deck whose first
  lateral frequency is 10–17 Hz (20 m spans) follows the ground quasi-statically.  1–2 m/s² are the reference peak
  ground accelerations a_gR ≈ 0.1–0.2 g of moderate-seismicity zones in the EN 1998-1 national annexes.  The
  displacement amplitude is then 15 mm (one-period ramps; 17 mm without ramps).

Subclass :class:`SupportMotion` (implement :meth:`SupportMotion.state`) for another record (e.g. a sampled,
baseline-corrected accelerogram integrated by the user).
"""
from __future__ import annotations

import math

import numpy as np
from exudyn.itemInterface import ObjectGenericODE2, VObjectGenericODE2

from .item_names import unique_name
from .checks import checked_number

__all__ = ["SupportMotion", "SmoothHarmonicSupportMotion", "SupportMotionLoad", "smoothstep5"]


class SupportMotion:
    """A prescribed lateral ground (support) motion ``y_g(t)`` [m], track frame y (right).  Subclasses implement
    :meth:`state`; the rest follows from it."""

    def state(self, t_s: float) -> tuple[float, float, float]:
        """``(y_g, ẏ_g, ÿ_g)`` at time ``t_s`` [m, m/s, m/s²]."""
        raise NotImplementedError

    def displacement_m(self, t_s) -> np.ndarray:
        return np.vectorize(lambda t: self.state(float(t))[0], otypes=[float])(t_s)

    def velocity_m_s(self, t_s) -> np.ndarray:
        return np.vectorize(lambda t: self.state(float(t))[1], otypes=[float])(t_s)

    def acceleration_m_s2(self, t_s) -> np.ndarray:
        return np.vectorize(lambda t: self.state(float(t))[2], otypes=[float])(t_s)


def smoothstep5(x: float) -> tuple[float, float, float]:
    """Quintic smoothstep ``S(x) = 10x³ - 15x⁴ + 6x⁵`` on [0, 1] (0 below, 1 above) and its first two derivatives:
    ``S(0) = 0``, ``S(1) = 1``, ``S' = S'' = 0`` at both ends (C² joins)."""
    if x <= 0.0:
        return 0.0, 0.0, 0.0
    if x >= 1.0:
        return 1.0, 0.0, 0.0
    x2 = x * x
    return (x2 * x * (10.0 - 15.0 * x + 6.0 * x2), 30.0 * x2 * (1.0 - x) ** 2, 60.0 * x * (1.0 - x) * (1.0 - 2.0 * x))


class SmoothHarmonicSupportMotion(SupportMotion):
    """Sine burst of the ground displacement with C² ramps (module docstring):
    ``y_g(t) = Y w(τ) sin(Ω τ)``, ``τ = t - start_s``, ``Ω = 2π frequency_Hz``.

    peak_acceleration_m_s2 : the peak ground acceleration ``max |ÿ_g|`` of the whole burst [m/s²].  On the plateau
        the acceleration amplitude is ``a_plateau = Y Ω²`` (:attr:`plateau_acceleration_m_s2`); the ramps'
        product-rule terms ``Y (w'' sin + 2 w' Ω cos)`` raise the maximum above it (by 11 % for one-period ramps,
        1.8 % for two, 59 % for half a period), so ``Y`` is set such that the maximum over the burst is
        ``peak_acceleration_m_s2`` (without ramps ``a_plateau = peak``).
    frequency_Hz : ``f`` [Hz].
    ramp_cycles : duration of each ramp in periods (≥ 0; 0 = a sudden start: ``y_g = Y sin Ωτ`` from τ = 0, whose
        velocity jumps to ``YΩ`` — acceptable for a deck alone, not under a vehicle).
    plateau_cycles : periods at full amplitude (``math.inf``: no ramp-down, a steady harmonic).
    start_s : time at which the ramp starts (the ground is at rest before).
    """

    def __init__(self, peak_acceleration_m_s2: float, frequency_Hz: float, *, ramp_cycles: float = 1.0,
                 plateau_cycles: float = 2.0, start_s: float = 0.0):
        self.peak_acceleration_m_s2 = checked_number("peak_acceleration_m_s2", peak_acceleration_m_s2, non_negative=True)
        self.frequency_Hz = checked_number("frequency_Hz", frequency_Hz, positive=True)
        self.ramp_cycles = checked_number("ramp_cycles", ramp_cycles, non_negative=True)
        self.plateau_cycles = checked_number("plateau_cycles", plateau_cycles, non_negative=True, allow_inf=True)
        self.start_s = checked_number("start_s", start_s)
        self.omega_rad_s = 2.0 * math.pi * self.frequency_Hz
        period = 1.0 / self.frequency_Hz
        self.ramp_s = self.ramp_cycles * period
        self.plateau_s = self.plateau_cycles * period
        self.end_s = self.start_s + 2.0 * self.ramp_s + self.plateau_s       # inf for an endless plateau
        # unit plateau acceleration first, then scaled so that the burst's maximum is the stated peak
        self.amplitude_m = 1.0 / self.omega_rad_s ** 2
        self.overshoot = self.max_abs_acceleration_m_s2() if (self.ramp_s > 0.0 or self.plateau_s > 0.0) else 1.0
        self.plateau_acceleration_m_s2 = self.peak_acceleration_m_s2 / self.overshoot
        self.amplitude_m = self.plateau_acceleration_m_s2 / self.omega_rad_s ** 2

    def __repr__(self):
        return (f"SmoothHarmonicSupportMotion(peak_acceleration_m_s2={self.peak_acceleration_m_s2:g}, frequency_Hz="
                f"{self.frequency_Hz:g}, ramp_cycles={self.ramp_cycles:g}, plateau_cycles={self.plateau_cycles:g}, "
                f"start_s={self.start_s:g}; displacement amplitude {self.amplitude_m * 1e3:.3g} mm, plateau acceleration "
                f"{self.plateau_acceleration_m_s2:.3g} m/s2)")

    def window(self, tau: float) -> tuple[float, float, float]:
        """``w(τ)``, ``w'``, ``w''``."""
        Tr, Tp = self.ramp_s, self.plateau_s
        if tau < 0.0:
            return 0.0, 0.0, 0.0
        if Tr > 0.0 and tau < Tr:
            s, ds, dds = smoothstep5(tau / Tr)
            return s, ds / Tr, dds / (Tr * Tr)
        if tau <= Tr + Tp:
            return 1.0, 0.0, 0.0
        if Tr > 0.0:
            s, ds, dds = smoothstep5((2.0 * Tr + Tp - tau) / Tr)
            return s, -ds / Tr, dds / (Tr * Tr)
        return 0.0, 0.0, 0.0

    def state(self, t_s: float) -> tuple[float, float, float]:
        tau = float(t_s) - self.start_s
        if not tau > 0.0:                   # also NaN: the ground at rest
            return 0.0, 0.0, 0.0
        w, dw, ddw = self.window(tau)
        if w == 0.0 and dw == 0.0 and ddw == 0.0:
            return 0.0, 0.0, 0.0
        W = self.omega_rad_s
        sn, cs = math.sin(W * tau), math.cos(W * tau)
        Y = self.amplitude_m
        return (Y * w * sn, Y * (dw * sn + w * W * cs), Y * (ddw * sn + 2.0 * dw * W * cs - w * W * W * sn))

    def max_abs_acceleration_m_s2(self, points_per_period: int = 4000) -> float:
        """``max |ÿ_g|`` over the burst, sampled (the ramp-up with one plateau period, and the ramp-down)."""
        P = 1.0 / self.frequency_Hz
        T = self.ramp_s + min(self.plateau_s, P)
        x = np.linspace(0.0, T, max(2, int(points_per_period * T / P) + 1))
        vals = [abs(self.state(self.start_s + xi)[2]) for xi in x]
        if math.isfinite(self.end_s):
            vals += [abs(self.state(self.end_s - xi)[2]) for xi in x]
        return float(max(vals))


class SupportMotionLoad:
    """The effective earthquake load ``-Γ ÿ_g(t)`` on a bridge's modal coordinates: one zero-mass
    ``ObjectGenericODE2`` on :attr:`~.bridge_exudyn.ExudynBridge.modal_node` with a force user function and a zero
    Jacobian (the load depends on time only).  Created by :meth:`~.bridge_exudyn.ExudynBridge.add_support_motion`."""

    def __init__(self, mbs, bridge, motion: SupportMotion, name: str = "support_motion"):
        if not isinstance(motion, SupportMotion):
            raise TypeError(f"motion={motion!r}: expected a SupportMotion (e.g. SmoothHarmonicSupportMotion)")
        self.motion = motion
        self.gamma = np.ascontiguousarray(bridge.modes.participation_factors("lateral"))
        n = self.gamma.size
        self._f = np.zeros(n)
        self._jac = np.zeros((n, n))
        self.object = mbs.AddObject(ObjectGenericODE2(
            name=unique_name(mbs, name), nodeNumbers=[bridge.modal_node], massMatrix=np.zeros((n, n)),
            forceUserFunction=self._force_uf, jacobianUserFunction=self._jacobian_uf,
            visualization=VObjectGenericODE2(show=False)))

    def forces(self, t: float) -> np.ndarray:
        """``-Γ ÿ_g(t)``."""
        np.multiply(self.gamma, -self.motion.state(float(t))[2], out=self._f)
        return self._f

    def _force_uf(self, mbs, t, itemIndex, q, q_t):
        return self.forces(t)

    def _jacobian_uf(self, mbs, t, itemIndex, q, q_t, fODE2, fODE2_t):
        return self._jac
