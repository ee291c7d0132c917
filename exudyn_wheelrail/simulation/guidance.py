r"""Flange climb that friction cannot stop: the derailment quotient of a wheel held above Nadal's limit over 2 m of
running.

Nadal's limit (:func:`~exudyn_wheelrail.analysis.safety.nadal_limit`) is the quotient Y/Q of the lateral force Y
(towards the wheel's field side, the flange pressing its rail outwards) and the wheel load Q at which a flange
contact on the flank (angle γ, friction μ) is in limiting friction: ``(tan γ − μ)/(1 + μ tan γ)``, 1.34 for S1002's
70° flank with μ = 0.3.  Above it nothing holds the flange down and it climbs.  A short impact above the limit is
not a derailment — the climb needs running distance —, so the quotient is taken over the running distance of EN
14363's derailment-quotient window, 2 m (:data:`~exudyn_wheelrail.analysis.safety.EN14363_WINDOW_M`): the quotient
of the sums of Y and Q over the states of the last 2 m (a lifted wheel, Q = 0, adds nothing to either), which
equals ``(Y/Q)_2m`` for a steady flange contact and stays finite while the wheel hops.  When it exceeds Nadal's
limit the wheel is reported **derailed** (flange climb) at that state, with the wheelset and wheel.  (EN 14363's own
limit on ``(Y/Q)_2m``, 0.8, is an acceptance limit with margin, evaluated on the recorded run by the criteria.)

The detail also states the wheelset's track-shift force ΣY (the lateral force of both wheels on the track) over
the same 2 m against Prud'homme's limit ``10 kN + P/3`` (P the axle load of the first checked state): with the
flange climbing, a track on ballast would also be shifted far beyond what it resists, which the model's rigid
rails do not show.
"""
from __future__ import annotations

import math
from collections import deque

import numpy as np

from ..analysis.safety import EN14363_WINDOW_M, prudhomme_limit_N
from ..multibody import connector as C
from ..multibody.monitor import SIDES, Status

__all__ = ["FlangeClimbCheck"]


class FlangeClimbCheck:
    """``check(contact, t)`` after the monitor evaluated the contact at the state of time ``t``: a ``derailment``
    :class:`~exudyn_wheelrail.multibody.monitor.Status` when a wheel's 2 m quotient exceeds ``nadal_limit``, else
    None.  Inactive for a flangeless wheel (``nadal_limit`` NaN) or a standing vehicle."""

    def __init__(self, n_wheelsets: int, speed_m_s: float, nadal_limit: float, window_m: float = EN14363_WINDOW_M):
        self.n = int(n_wheelsets)
        self.nadal_limit = float(nadal_limit)
        self.window_s = window_m / speed_m_s if speed_m_s > 0.0 else math.inf
        self.window_m = float(window_m)
        self.active = math.isfinite(self.nadal_limit) and math.isfinite(self.window_s)
        self._states = deque()                  # (t, Y towards the field side per wheel, Q per wheel)
        self._sum_y = np.zeros(2 * self.n)
        self._sum_q = np.zeros(2 * self.n)
        self._axle_load_N = None
        self._t_first = None
        self.max_quotient = np.zeros(2 * self.n)  #: per wheel: the largest 2 m quotient seen
        self._right = np.arange(2 * self.n) % 2 == 0

    def __call__(self, contact, t: float) -> Status | None:
        if not self.active:
            return None
        res = contact.results                        # this state's evaluation (the monitor's), per wheel and slot
        fy = res[:, :, C.RES_F_TRACK_Y].sum(axis=1)
        y_out = np.where(self._right, -fy, fy)       # towards each wheel's field side
        q = np.maximum(-res[:, :, C.RES_F_TRACK_Z].sum(axis=1), 0.0)
        if self._axle_load_N is None:
            self._axle_load_N = q[0::2] + q[1::2]
            self._t_first = float(t)
        self._states.append((float(t), y_out, q))
        self._sum_y += y_out
        self._sum_q += q
        while self._states and t - self._states[0][0] > self.window_s:
            _, y0, q0 = self._states.popleft()
            self._sum_y -= y0
            self._sum_q -= q0
        if t - self._t_first < self.window_s * (1.0 - 1e-9):
            return None                                    # less than 2 m run so far
        with np.errstate(divide="ignore", invalid="ignore"):
            quotient = np.where(self._sum_q > 0.0, self._sum_y / self._sum_q, 0.0)
        np.maximum(self.max_quotient, quotient, out=self.max_quotient)
        w = int(np.argmax(quotient))
        if not quotient[w] > self.nadal_limit:
            return None
        k = w // 2
        n_states = len(self._states)
        track_shift = abs(self._sum_y[2 * k] - self._sum_y[2 * k + 1]) / n_states   # ΣY on the track, both wheels
        P = float(self._axle_load_N[k])
        shift = (f"; track-shift force ΣY over the same 2 m {track_shift / 1e3:.4g} kN = "
                 f"{track_shift / prudhomme_limit_N(static_axle_load_N=P):.3g} x Prud'homme's limit "
                 f"{prudhomme_limit_N(static_axle_load_N=P) / 1e3:.4g} kN" if P > 0.0 else "")
        return Status("derailment", float(t), k, SIDES[w % 2],
                      f"flange climb: Y/Q averaged over the last {self.window_m:g} m of running = {quotient[w]:.4g} "
                      f"> Nadal's limit {self.nadal_limit:.4g} of the flange: friction no longer holds the flange "
                      f"down, the wheel climbs" + shift)
