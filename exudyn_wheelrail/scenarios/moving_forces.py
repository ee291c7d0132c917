"""The bridge deck alone under constant moving forces (no vehicle) in Exudyn: :func:`simulate_moving_forces`
(its modal coordinates at every step, e.g. the reference of a coupled crossing or of the moving-load model) and
:func:`benchmark_formulations` (the modal and the FFRF formulation of :mod:`exudyn_wheelrail.structures.bridge_exudyn`
against Frýba's closed form)."""
from __future__ import annotations

import math
import time

import exudyn as exu
import numpy as np

from ..simulation.exudyn_settings import simulation_settings
from ..structures.beam import DeckSection
from ..structures.bridge import BridgeModel, BridgeModes
from ..structures.bridge_exudyn import FORMULATIONS, add_bridge
from ..structures.fryba import fryba_moving_force
from ..validation import finite

__all__ = ["simulate_moving_forces", "benchmark_formulations"]


def simulate_moving_forces(modes: BridgeModes, *, x_m, forces_N, speed_m_s: float, s_start_m: float,
                           end_time_s: float, dt_s: float, formulation: str = "modal", solver: str = "implicit",
                           support_motion=None):
    """Run a bridge under constant moving forces in Exudyn (no vehicle): returns ``(t, q, seconds per step)``
    with ``q`` (n_t, n_modes) the modal coordinates at every step.  ``solver``: ``"implicit"`` (generalized-α,
    spectral radius 1: the trapezoidal rule, no numerical damping) or ``"explicit"`` (RK44; modal only).
    ``support_motion``: a lateral ground motion of the supports (:meth:`ExudynBridge.add_support_motion`); ``q`` is
    then the motion relative to the supports."""
    if solver not in ("implicit", "explicit"):
        raise ValueError(f"solver={solver!r}: expected 'implicit' or 'explicit'")
    if solver == "explicit" and formulation == "ffrf":
        raise ValueError("the FFRF formulation holds its frame by constraints: use solver='implicit'")
    T, h = finite("end_time_s", end_time_s), finite("dt_s", dt_s)
    for name, x in (("end_time_s", T), ("dt_s", h)):
        if not x > 0.0:
            raise ValueError(f"{name}={x!r}: expected a value > 0")
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    bridge = add_bridge(mbs, modes, formulation)
    bridge.add_moving_forces(mbs, x_m, forces_N, speed_m_s, s_start_m)
    if support_motion is not None:
        bridge.add_support_motion(mbs, support_motion)
    sensor = bridge.add_sensor(mbs)
    mbs.Assemble()
    n_steps = max(1, int(round(T / h)))
    ss = simulation_settings(n_steps * h, h, spectral_radius=1.0)
    if solver == "implicit":
        t0 = time.perf_counter()
        mbs.SolveDynamic(ss)
    else:
        t0 = time.perf_counter()
        mbs.SolveDynamic(ss, solverType=exu.DynamicSolverType.RK44)
    cost = (time.perf_counter() - t0) / n_steps
    data = mbs.GetSensorStoredData(sensor)
    return data[:, 0], data[:, 1:], cost


def benchmark_formulations(n_repeat: int = 3, dt_s: float = 5e-4, f_max_Hz: float = 150.0) -> dict:
    """The modal and FFRF formulations on the same moving-force case (the figures of the module docstring):
    a simply supported 20 m span (m = 15 t/m, f1 = 4.53 Hz, ζ = 0), one 200 kN force at 40 m/s, 0.75 s;
    returns per formulation the peak mid-span deflection error against :func:`fryba_moving_force` (relative to
    the peak) and the best-of-``n_repeat`` seconds per step."""
    sec = DeckSection(m_kg_m=15e3, EI_y_Nm2=2.0e10, EI_z_Nm2=1.0e11, GJ_Nm2=6e9, EA_N=2e11, Ip_kgm2_m=6e4)
    L, P, V = 20.0, 2e5, 40.0
    modes = BridgeModel((L,), sec, elements_per_span=20).modes(f_max_Hz=f_max_Hz)
    out = {"n_modes": modes.n_modes}
    for form in FORMULATIONS:
        best = math.inf
        for _ in range(n_repeat):
            t, q, cost = simulate_moving_forces(modes, x_m=[0.0], forces_N=[[0.0, P, 0.0]], speed_m_s=V,
                                                s_start_m=0.0, end_time_s=0.75, dt_s=dt_s, formulation=form)
            best = min(best, cost)
        w = q @ modes.shape_at(L / 2)[1]
        ref = fryba_moving_force(L / 2, t, force_N=P, speed_m_s=V, span_m=L, EI_Nm2=sec.EI_y_Nm2,
                                 m_kg_m=sec.m_kg_m, n_terms=60)
        out[form] = {"error_rel_peak": float(np.max(np.abs(w - ref)) / np.max(np.abs(ref))), "s_per_step": best,
                     "w_mid_m": w}
    return out
