"""Frýba's moving-force solution (``structures.fryba.fryba_moving_force``) against an independent numerical solution.

Reference: the modal equations of a simply supported Euler–Bernoulli beam (span L, EI, mass per length m, modal
damping ζ) under constant forces P (down, deflection w down) moving at speed v, force k at ``x_k(t) = v t - d_k``
(it enters at ``t = d_k / v``)::

    q̈_j + 2 ζ ω_j q̇_j + ω_j² q_j = (2 / (m L)) Σ_k P sin(jπ x_k(t) / L)   (only the forces with 0 <= x_k <= L),
    ω_j = (jπ/L)² √(EI/m),   w(x, t) = Σ_j q_j(t) sin(jπx/L),

integrated from rest by ``scipy.integrate.solve_ivp`` (DOP853, rtol 1e-11) piece by piece between the instants
at which a force enters or leaves the span (the load is only piecewise smooth there), through the passage and
through the free damped vibration after the last force has left.  Nothing of the package's closed form
(particular + homogeneous solution, state at exit, free vibration from it) is used.  The same number of modes is
used in both, so the modal truncation is not part of the comparison; it is, in the separate check of the
numerical solution against the static mid-span deflection ``P L³ / (48 EI)``.
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from exudyn_wheelrail.structures import fryba_moving_force

# a 20 m deck (f1 = 4.53 Hz), the beam data of tests/test_bridge.py
L, EI, M = 20.0, 2.0e10, 15e3
P = 2e5
N_MODES = 5                     # f_5 = 113 Hz
X_OUT = (L / 2, 0.3 * L)        # mid-span (odd modes) and 0.3 L (every mode)

# ODE accuracy: the global error of a tolerance-controlled integration of these linear oscillators grows at most
# about linearly with the number of periods of the fastest mode integrated (≤ ~300 here) times rtol, i.e. ≲ 3e-9
# of the peak for rtol 1e-11 (measured: ≤ 1.5e-13); the closed form is exact to round-off.  Tolerance 1e-8 of the
# peak: that bound with a margin of 5, and still 5 decades below the effect of an error in the closed form's damped
# terms (e.g. the free vibration after the exit computed without its decay: 3e-2 … 2e-1 of the peak here).
RTOL_ODE = 1e-11
TOL_REL_PEAK = 1e-8


def omegas(n_modes):
    j = np.arange(1, n_modes + 1)
    return (j * math.pi / L) ** 2 * math.sqrt(EI / M)


def modal_ode_deflection(t_out, *, speed, offsets, zeta, n_modes=N_MODES, force=P, x_out=X_OUT):
    """Deflection [m] (rows: ``x_out`` [m]) at the (sorted) times ``t_out`` [s] of the integrated modal equations."""
    t_out = np.asarray(t_out, float)
    assert np.all(np.diff(t_out) > 0) and t_out[0] >= 0.0
    j = np.arange(1, n_modes + 1)
    w = omegas(n_modes)
    offsets = np.asarray(offsets, float)
    gain = 2.0 * force / (M * L)

    def rhs(t, y):
        q, qd = y[:n_modes], y[n_modes:]
        x = speed * t - offsets
        on = (x >= 0.0) & (x <= L)
        load = gain * np.sin(np.outer(j, x[on]) * math.pi / L).sum(axis=1)
        return np.concatenate((qd, load - 2.0 * zeta * w * qd - w * w * q))

    # break points: every entry and exit (the load's derivative jumps there)
    breaks = np.concatenate((offsets / speed, (offsets + L) / speed))
    breaks = np.unique(np.concatenate(([0.0], breaks[(breaks > 0) & (breaks < t_out[-1])], [t_out[-1]])))
    y = np.zeros(2 * n_modes)
    q_out = np.empty((t_out.size, n_modes))
    # absolute tolerance: far below the smallest modal amplitude of interest (static q_j ~ gain / ω_j²)
    atol = RTOL_ODE * gain / w[-1] ** 2 * 1e-2
    for t0, t1 in zip(breaks[:-1], breaks[1:]):
        inside = (t_out >= t0) & (t_out <= t1)
        t_eval = np.unique(np.concatenate((t_out[inside], [t1])))       # ends with t1: the state carried on
        sol = solve_ivp(rhs, (t0, t1), y, method="DOP853", rtol=RTOL_ODE, atol=atol, t_eval=t_eval)
        assert sol.success, sol.message
        q_out[inside] = sol.y[:n_modes, np.searchsorted(t_eval, t_out[inside])].T
        y = sol.y[:, -1]
    return np.array([q_out @ np.sin(j * math.pi * x / L) for x in x_out])


def package(t, *, speed, offsets, zeta, x_out=X_OUT):
    return np.array([fryba_moving_force(x, t, force_N=P, speed_m_s=speed, span_m=L, EI_Nm2=EI, m_kg_m=M,
                                        damping_ratio=zeta, n_terms=N_MODES, offsets_m=offsets) for x in x_out])


def _compare(t, t_exit, **case):
    """Max |package - reference| on the span and after the exit, relative to the reference's peak; the
    reference's peak and its largest free vibration after the exit (relative to the peak)."""
    ref = modal_ode_deflection(t, **case)
    w = package(t, **case)
    peak = np.max(np.abs(ref))
    on, after = t <= t_exit, t > t_exit
    err = np.abs(w - ref) / peak
    return err[:, on].max(), err[:, after].max(), peak, np.abs(ref[:, after]).max() / peak, ref


# several forces: a bogie pair and a second bogie (offsets [m] behind the first force)
BOGIES = (0.0, 2.5, 17.5, 20.0)


@pytest.mark.parametrize("zeta", [0.0, 0.02, 0.05])
@pytest.mark.parametrize("offsets", [(0.0,), BOGIES], ids=["one_force", "four_forces"])
def test_fryba_equals_integrated_modal_equations_on_span_and_after_exit(zeta, offsets):
    """Deflection histories over the passage and 1 s of free vibration after the last force has left (40 m/s,
    α = v/(2 f1 L) = 0.22, a dynamic case)."""
    v = 40.0
    t_exit = (max(offsets) + L) / v
    t = np.linspace(0.0, t_exit + 1.0, 1201)[1:]
    err_on, err_after, peak, free, ref = _compare(t, t_exit, speed=v, offsets=offsets, zeta=zeta)
    assert err_on <= TOL_REL_PEAK, (err_on, "on span")
    assert err_after <= TOL_REL_PEAK, (err_after, "after the exit")
    # the post-exit part is a real test: a free vibration far above the tolerance
    assert free > 1e-2
    assert peak > 1.05 * P * L ** 3 / (48 * EI)             # dynamic amplification of one force: a dynamic case


def test_fryba_resonant_train_after_exit():
    """Equal forces at spacing d = L/2 at the speed v = f1 d (the first resonance of the train, Frýba 2001), ζ = 2 %:
    the free vibration after the train is large, so the decay of the post-exit solution is tested where it
    matters most."""
    f1 = omegas(1)[0] / (2 * math.pi)
    d = L / 2
    offsets = tuple(d * np.arange(6))
    v = f1 * d
    t_exit = (offsets[-1] + L) / v
    t = np.linspace(0.0, t_exit + 1.0, 1601)[1:]
    err_on, err_after, peak, free, ref = _compare(t, t_exit, speed=v, offsets=offsets, zeta=0.02)
    assert free > 0.3                                       # resonance: strong free vibration after the train
    assert err_on <= TOL_REL_PEAK and err_after <= TOL_REL_PEAK, (err_on, err_after)
    # and it decays: one second later the first mode's envelope e^{-ζ ω1 t} has dropped to 0.57
    late = t > t_exit + 0.9
    assert np.abs(ref[0, late]).max() < 0.7 * np.abs(ref[0, t > t_exit]).max()


def test_integrated_modal_equations_have_the_static_limit():
    """The independent solution itself: a force crawling to mid-span (v = 1 m/s, α = v/(2 f1 L) = 5.5e-3; ζ = 5 %
    so that the entry transient, ~α of the static deflection, has decayed by e^{-14} at mid-span) deflects the
    mid-span by P L³ / (48 EI) times the modal series truncated after n modes.

    Static modal series at mid-span: ``w = (2 P L³ / (π⁴ EI)) Σ_{j odd} 1/j⁴`` and ``Σ_{j odd} 1/j⁴ = π⁴/96``, so
    the truncated sum is ``P L³/(48 EI) (1 - T_n)`` with the tail ``T_n = (96/π⁴) Σ_{j odd > n} 1/j⁴`` (summed
    here).  The remaining dynamic difference is the quasi-static inertia factor ``1/(1 - (α/j)²)``, at most α² =
    3e-5 relative: tolerance 3 α²."""
    n = 3                                          # f_3 = 41 Hz: 10 s of integration stays cheap
    v = 1.0
    alpha = (math.pi * v / L) / omegas(1)[0]
    w = modal_ode_deflection(np.array([(L / 2) / v]), speed=v, offsets=(0.0,), zeta=0.05, n_modes=n,
                             x_out=(L / 2,))[0, 0]
    j = np.arange(n + 1, 2_000_001)
    tail = 96 / math.pi ** 4 * np.sum(1.0 / j[j % 2 == 1].astype(float) ** 4)
    static = P * L ** 3 / (48 * EI)
    assert w == pytest.approx(static * (1 - tail), rel=3 * alpha ** 2)
    assert tail > 10 * 3 * alpha ** 2                # the truncation is resolved: the test sees the modal series
