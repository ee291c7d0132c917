"""The solver table (exudyn_wheelrail.simulation.solvers) against what Exudyn's solvers do.

Every explicit solver integrates two one-degree-of-freedom systems with ``numberOfSteps`` fixed steps:

* an undamped oscillator ``m x'' + k x = 0`` (λ = ±iω): its amplitude ``√(x² + (ẋ/ω)²)`` must not grow at
  ``ω h = 0.98 × imaginary_axis_limit`` and must grow at ``1.02 ×``;
* a pure decay ``m v' = -c v`` (λ = -σ): ``|v|`` must not grow at ``σ h = 0.98 × real_axis_limit`` and must at
  ``1.02 ×``.

The analytic values (2√2 and √3 on the imaginary axis, 2, 2.5127 and 2.7853 on the real axis) are the roots of the
stability polynomials ``R(z) = Σ_{k<=s} z^k/k!`` of the 2-, 3- and 4-stage methods: ``|R(iy)|² = 1 - y⁴/12 + y⁶/36``
(RK3) and ``1 - y⁶/72 + y⁸/576`` (RK4), ``|R(-x)| = 1`` on the real axis — derived here, not read from the package.
Margin: 2 % of the limit changes ``|R|`` per step by about ``|d|R|/dz| × 0.02 z``, 0.5–5 % for these polynomials, so
400 steps grow or shrink the amplitude by a factor far from 1 (rounding: 400 steps × 1e-16 relative).
"""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
import pytest
from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2

from exudyn_wheelrail.simulation.solvers import IMPLICIT_SOLVERS, METHODS, SOLVERS, stable_step_s

STEPS = 400
EXPLICIT = [k for k, m in METHODS.items() if not m.implicit]


def _rk_polynomial_roots():
    """The analytic limits of the 2-, 3- and 4-stage methods (module docstring)."""
    def real_root(order):
        # |R(-x)| = 1: the first x > 0 where it is crossed (a scan from 0.5 in steps of 0.01, then bisection)
        f = lambda x: abs(sum((-x) ** k / math.factorial(k) for k in range(order + 1))) - 1.0    # noqa: E731
        lo = 0.5
        while f(lo + 0.01) < 0.0:
            lo += 0.01
        hi = lo + 0.01
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if f(mid) < 0.0 else (lo, mid)
        return lo
    return {"explicit_midpoint": (0.0, real_root(2)), "rk33": (math.sqrt(3.0), real_root(3)),
            "rk44": (2.0 * math.sqrt(2.0), real_root(4))}


def _run(solver: str, mass, damping, stiffness, x0, v0, h):
    mbs = exu.SystemContainer().AddSystem()
    n = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0], initialCoordinates=[x0], initialCoordinates_t=[v0],
                                    numberOfODE2Coordinates=1))
    mbs.AddObject(ObjectGenericODE2(nodeNumbers=[n], massMatrix=np.array([[mass]]),
                                    dampingMatrix=np.array([[damping]]), stiffnessMatrix=np.array([[stiffness]])))
    mbs.Assemble()
    s = exu.SimulationSettings()
    s.timeIntegration.endTime = STEPS * h
    s.timeIntegration.numberOfSteps = STEPS
    s.timeIntegration.verboseMode = 0
    s.solution.file.write = False
    s.timeIntegration.explicit.computeEndOfStepAccelerations = False
    mbs.SolveDynamic(s, solverType=getattr(exu.DynamicSolverType, METHODS[solver].exudyn_type))
    return float(mbs.systemData.GetODE2Coordinates()[0]), float(mbs.systemData.GetODE2Coordinates_t()[0])


def _oscillator_growth(solver, omega_h):
    w = 100.0                                   # k = 1e4 N/m on 1 kg
    x, v = _run(solver, 1.0, 0.0, w * w, 1e-3, 0.0, omega_h / w)
    return math.hypot(x, v / w) / 1e-3


def _decay_growth(solver, sigma_h):
    sigma = 100.0                               # c = 100 N s/m on 1 kg
    _, v = _run(solver, 1.0, sigma, 0.0, 0.0, 1.0, sigma_h / sigma)
    return abs(v)


def test_the_table_lists_every_solver_once_with_its_exudyn_type():
    assert SOLVERS == tuple(METHODS) and len(set(SOLVERS)) == len(SOLVERS)
    assert set(IMPLICIT_SOLVERS) == {"newmark", "generalized_alpha"}
    for name, m in METHODS.items():
        assert m.name == name and hasattr(exu.DynamicSolverType, m.exudyn_type)
        assert (m.imaginary_axis_limit is None) == (m.real_axis_limit is None) == m.implicit


@pytest.mark.parametrize("solver", sorted(_rk_polynomial_roots()))
def test_the_limits_of_the_classical_methods_are_the_roots_of_their_stability_polynomials(solver):
    imag, real = _rk_polynomial_roots()[solver]
    assert METHODS[solver].imaginary_axis_limit == pytest.approx(imag, rel=1e-12, abs=0.0)
    assert METHODS[solver].real_axis_limit == pytest.approx(real, rel=1e-12)


@pytest.mark.parametrize("solver", EXPLICIT)
def test_exudyn_keeps_an_undamped_oscillation_within_the_imaginary_axis_limit_and_not_beyond(solver):
    limit = METHODS[solver].imaginary_axis_limit
    if limit == 0.0:
        # no stable interval: the oscillation grows already at omega h = 0.5 (RK67: 2.3e-6 per step, 1e-3 over
        # the 400 steps; the explicit midpoint rule (1 + 0.5⁴/4)^(1/2) - 1 = 0.8 % per step)
        assert _oscillator_growth(solver, 0.5) > 1.0 + 1e-4
        assert stable_step_s(solver, 100.0) == 0.0
        return
    assert _oscillator_growth(solver, 0.98 * limit) <= 1.0
    assert _oscillator_growth(solver, 1.02 * limit) > 1.0 + 1e-3
    assert stable_step_s(solver, 100.0) == pytest.approx(limit / 100.0, rel=1e-15)


@pytest.mark.parametrize("solver", EXPLICIT)
def test_exudyn_keeps_a_decay_stable_within_the_real_axis_limit_and_not_beyond(solver):
    limit = METHODS[solver].real_axis_limit
    assert _decay_growth(solver, 0.98 * limit) < 1.0
    assert _decay_growth(solver, 1.02 * limit) > 1.0
