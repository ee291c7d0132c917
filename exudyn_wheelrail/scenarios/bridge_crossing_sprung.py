r"""The ``sprung-masses`` load model of ``bridge-crossing``: every axle a mass on a spring and a damper riding on
the deck.

``python -m exudyn_wheelrail bridge-crossing ... --model sprung-masses [--sprung-frequency-hz F_V]
[--sprung-damping-ratio Z_V]``: between the constant axle loads (``moving-loads``) and the full vehicle–bridge
interaction (``vehicles``).  Axle k (static load ``P_k``, from ``--axles``, ``--hslm`` or a consist's static axle
loads) carries a sprung mass ``m_k = P_k/g`` (the whole static axle load is sprung; ``g`` =
:data:`~exudyn_wheelrail.rolling_stock.vehicle_builder.GRAVITY_M_S2`) on a spring ``k_k = m_k (2π f_v)²`` and a
viscous damper ``c_k = 2 ζ_v m_k (2π f_v)`` whose lower end follows the deck at the axle's place
``s_k(t) = deck_start_m + V t - x_k`` (no unsprung mass, the wheel always in contact).  ``f_v`` and ``ζ_v``
(:data:`~exudyn_wheelrail.scenarios.bridge_crossing.SPRUNG_FREQUENCY_HZ` = 1.5 Hz,
:data:`~exudyn_wheelrail.scenarios.bridge_crossing.SPRUNG_DAMPING_RATIO` = 0.2: **assumed**, of the order of a
passenger coach's body bounce on its suspensions) are the same for every axle.

Equations (z down, ``z_k`` the mass's displacement from its static position on rigid ground, ``w_k = Φ_z(s_k) q``
and ``ẇ_k = Φ_z(s_k) q̇ + V Φ_z'(s_k) q`` the deck under the axle, zero off the deck)::

    m_k z̈_k = -f_k,      f_k = k_k (z_k - w_k) + c_k (ż_k - ẇ_k)
    q̈ + diag(2ζω) q̇ + diag(ω²) q = Σ_k Φ_z(s_k)ᵀ (P_k + f_k)

The masses are one ``NodeGenericODE2`` (``diag(m_k)``); the coupling is one zero-mass ``ObjectGenericODE2`` over the
deck's modal node and the masses' node whose force user function returns both right-hand sides.  Limits: as the
suspension softens (``f_v → 0``) or the masses vanish, ``f_k → 0`` and the deck sees the moving loads; the
deck's default time step is at most ``1/(40 f_v)`` (:data:`~exudyn_wheelrail.scenarios.bridge_crossing.
STEPS_PER_PERIOD` per period of the suspension).  Outputs beside the deck's: ``sprung_max_abs_acceleration_m_s2``
(the largest ``|z̈_k|`` over the axles, a comfort indicator of this simple model) and in ``summary.json``
``load_model.details`` the parameters and the peak interaction force ``max |f_k|`` relative to ``P_k``.
"""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2, VObjectGenericODE2

from ..rolling_stock.vehicle_builder import GRAVITY_M_S2
from .bridge_crossing_case import BridgeCrossing
from .bridge_crossing_loads import LoadModel, LoadModelHandle
from .defaults import STEPS_PER_PERIOD

__all__ = ["SPRUNG_MASSES", "sprung_parameters"]


def sprung_parameters(case: BridgeCrossing) -> dict:
    """Per axle ``m_kg``, ``k_N_m``, ``c_N_s_m`` (arrays) of the case's axles (module docstring)."""
    m = np.asarray(case.axles.load_N, dtype=float) / GRAVITY_M_S2
    w = 2.0 * math.pi * case.sprung_frequency_Hz
    return {"m_kg": m, "k_N_m": m * w * w, "c_N_s_m": 2.0 * case.sprung_damping_ratio * m * w}


def _check(case: BridgeCrossing) -> None:
    if case.axles is None:
        raise ValueError("--axles/--hslm: the sprung-masses model needs the axle loads (give --axles FILE.csv, "
                         "--hslm A1..A10 or --train FILE.toml)")
    if np.any(case.axles.load_N <= 0.0):
        k = int(np.argmax(case.axles.load_N <= 0.0))
        raise ValueError(f"--model: sprung-masses: axle {k + 1} has the load {case.axles.load_N[k]:g} N; a sprung mass "
                         "needs a downward load > 0")


class _Coupling:
    """The right-hand sides of the deck's modes and of the sprung masses (module docstring)."""

    def __init__(self, case, bridge, par):
        self.modes = bridge.modes
        self.n = bridge.modes.n_modes
        self.V = float(case.speed_m_s)
        self.x = np.asarray(case.axles.x_m, dtype=float)
        self.s0 = float(case.deck_start_m)
        self.P = np.asarray(case.axles.load_N, dtype=float)
        self.m, self.k, self.c = par["m_kg"], par["k_N_m"], par["c_N_s_m"]
        self.max_force = np.zeros_like(self.P)

    def rhs(self, t, q, q_t, z, z_t):
        """``(Q (n,), -f (n_axles,), f)``."""
        s = self.s0 + self.V * t - self.x
        phi, dphi = self.modes.shape_and_slope_at(s)
        pz, dpz = phi[:, 1, :], dphi[:, 1, :]                             # (n_axles, n)
        w = pz @ q
        w_t = pz @ q_t + self.V * (dpz @ q)
        f = self.k * (z - w) + self.c * (z_t - w_t)
        return pz.T @ (self.P + f), -f, f

    def split(self, y):
        y = np.asarray(y, dtype=float)
        return y[:self.n], y[self.n:]


def _build(mbs, case: BridgeCrossing, bridge) -> LoadModelHandle:
    par = sprung_parameters(case)
    cp = _Coupling(case, bridge, par)
    na, n = case.axles.n_axles, bridge.modes.n_modes
    node = mbs.AddNode(NodeGenericODE2(name="sprung_masses", numberOfODE2Coordinates=na,
                                       referenceCoordinates=[0.0] * na, initialCoordinates=[0.0] * na,
                                       initialCoordinates_t=[0.0] * na))
    mbs.AddObject(ObjectGenericODE2(name="sprung_masses", nodeNumbers=[node], massMatrix=np.diag(par["m_kg"]),
                                    visualization=VObjectGenericODE2(show=False)))
    out = np.zeros(n + na)

    def force_uf(mbs_, t, itemIndex, y, y_t):
        (q, z), (q_t, z_t) = cp.split(y), cp.split(y_t)
        out[:n], out[n:], _ = cp.rhs(t, q, q_t, z, z_t)
        return out

    mbs.AddObject(ObjectGenericODE2(name="sprung_coupling", nodeNumbers=[bridge.modal_node, node],
                                    massMatrix=np.zeros((n + na, n + na)), forceUserFunction=force_uf,
                                    visualization=VObjectGenericODE2(show=False)))

    def state(mbs_):
        q, q_t = (np.atleast_1d(v) for v in bridge.coordinates(mbs_))
        z = np.atleast_1d(np.asarray(mbs_.GetNodeOutput(node, exu.OutputVariableType.Coordinates), dtype=float))
        z_t = np.atleast_1d(np.asarray(mbs_.GetNodeOutput(node, exu.OutputVariableType.Coordinates_t), dtype=float))
        return q, q_t, z, z_t

    def modal_forces(mbs_, t):
        Q, _, f = cp.rhs(t, *state(mbs_))
        np.maximum(cp.max_force, np.abs(f), out=cp.max_force)
        return Q

    class _Masses:
        columns = [("sprung", "sprung_max_abs_acceleration_m_s2")]

        def fill(self, mbs_, t, row):
            _, minus_f, _ = cp.rhs(t, *state(mbs_))
            row[0] = np.max(np.abs(minus_f / cp.m))

    def summary(ts: dict) -> dict:
        return {"sprung_frequency_Hz": case.sprung_frequency_Hz, "sprung_damping_ratio": case.sprung_damping_ratio,
                "rule": "sprung mass m = P/g per axle, k = m (2 pi f_v)^2, c = 2 zeta_v m (2 pi f_v); no unsprung mass",
                "sprung_mass_kg": par["m_kg"], "max_abs_interaction_force_over_static_load":
                    float(np.max(cp.max_force / cp.P)),
                "max_abs_sprung_acceleration_m_s2": float(np.max(np.abs(ts["sprung_max_abs_acceleration_m_s2"])))}

    return LoadModelHandle(contact=None, axle_x_m=case.axles.x_m.copy(), axle_load_N=case.axles.load_N.copy(),
                           modal_forces=modal_forces, probes=[_Masses()], summary=summary,
                           description=f"{na} sprung masses ({case.axles.name}: m = P/g, f_v = "
                                       f"{case.sprung_frequency_Hz:g} Hz, zeta_v = {case.sprung_damping_ratio:g}) "
                                       f"moving at {case.speed_m_s * 3.6:.4g} km/h",
                           max_dt_s=1.0 / (STEPS_PER_PERIOD * case.sprung_frequency_Hz))


#: the moving sprung masses (module docstring)
SPRUNG_MASSES = LoadModel(check=_check, build=_build)
