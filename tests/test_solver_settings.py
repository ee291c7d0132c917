"""The integrators offered by ``simulation.exudyn_settings.solver_settings`` (the one list: the table of
``simulation.solvers``).

Checked: every name gives Exudyn settings of the stated integrator with a fixed step (step size, number of steps,
the scheme's parameters); unknown names and a spectral radius outside [0, 1] are clear errors; the run settings'
settings accept every name of the table.  One short RTRI run (300 steps of 1 ms, 250 km/h, the leading wheelset
before the deviation) with the new implicit (generalized-α) and a new explicit integrator (RK33) completes, and
its car-body acceleration peak and mean wheel load agree with the Newmark run of the same case — independent
integrators of the same equations must agree to within their truncation errors.
"""
import exudyn as exu
import numpy as np
import pytest

from exudyn_wheelrail.scenarios.rtri import RtriCase, run_rtri
from exudyn_wheelrail.simulation.exudyn_settings import solver_settings
from exudyn_wheelrail.simulation.settings import RunSettings
from exudyn_wheelrail.simulation.solvers import (GENERALIZED_ALPHA_SPECTRAL_RADIUS, IMPLICIT_SOLVERS, SOLVERS,
                                                 solver_description)

#: the Exudyn solver each name stands for (typed from the solvers' descriptions: Newmark is Exudyn's generalized-α
#: with useNewmark; the others by their names)
SOLVER_TYPES = {"newmark": "GeneralizedAlpha", "generalized_alpha": "GeneralizedAlpha",
                "explicit_midpoint": "ExplicitMidpoint", "rk33": "RK33", "rk44": "RK44", "rk67": "RK67"}

DT = 1e-3
STEPS = 300


@pytest.mark.parametrize("solver", sorted(SOLVER_TYPES))
def test_every_solver_name_builds_fixed_step_settings(solver):
    s, solver_type = solver_settings(solver, DT, 250, newton_tolerance=1e-4)
    assert solver_type == getattr(exu.DynamicSolverType, SOLVER_TYPES[solver])
    ti = s.timeIntegration
    assert ti.numberOfSteps == 250
    assert ti.endTime == pytest.approx(250 * DT)
    if solver in IMPLICIT_SOLVERS:
        assert ti.newton.useModifiedNewton
        assert ti.newton.relativeTolerance == pytest.approx(1e-4)
    else:
        assert not ti.explicit.computeEndOfStepAccelerations
        assert ti.explicit.useLieGroupIntegration
    assert solver_description(solver, 1e-4)


def test_newmark_and_generalized_alpha_parameters():
    s, _ = solver_settings("newmark", DT, 10, newmark_beta=0.3, newmark_gamma=0.6)
    ga = s.timeIntegration.generalizedAlpha
    assert ga.useNewmark and ga.useIndex2Constraints
    assert (ga.newmarkBeta, ga.newmarkGamma) == (pytest.approx(0.3), pytest.approx(0.6))
    s, _ = solver_settings("generalized_alpha", DT, 10)
    ga = s.timeIntegration.generalizedAlpha
    assert not ga.useNewmark and not ga.useIndex2Constraints
    assert ga.spectralRadius == pytest.approx(GENERALIZED_ALPHA_SPECTRAL_RADIUS)
    s, _ = solver_settings("generalized_alpha", DT, 10, spectral_radius=0.5)
    assert s.timeIntegration.generalizedAlpha.spectralRadius == pytest.approx(0.5)
    assert "0.5" in solver_description("generalized_alpha", spectral_radius=0.5)


def test_unknown_solver_and_bad_spectral_radius_are_clear_errors():
    with pytest.raises(ValueError, match=r"solver='dopri5'.*'newmark'.*'rk44'"):
        solver_settings("dopri5", DT, 10)
    with pytest.raises(ValueError, match="solver='nope'"):
        solver_description("nope")
    with pytest.raises(ValueError, match="spectral_radius"):
        solver_settings("generalized_alpha", DT, 10, spectral_radius=1.5)
    with pytest.raises(ValueError, match="solver: 'dopri5': expected one of newmark, generalized_alpha"):
        RtriCase(solver="dopri5")


def test_the_run_settings_offer_every_solver_of_the_table():
    assert set(SOLVERS) == set(SOLVER_TYPES)
    assert set(IMPLICIT_SOLVERS) == {"newmark", "generalized_alpha"}
    for solver in SOLVERS:
        assert RunSettings(solver=solver).implicit == (solver in IMPLICIT_SOLVERS)


@pytest.fixture(scope="module")
def newmark_run():
    return run_rtri(RtriCase(solver="newmark", dt_s=DT, duration_s=STEPS * DT))


@pytest.mark.parametrize("solver", ["generalized_alpha", "rk33"])
def test_short_rtri_run_with_a_new_integrator(solver, newmark_run):
    r = run_rtri(RtriCase(solver=solver, dt_s=DT, duration_s=STEPS * DT))
    s = r.summary
    assert s["status"] == "ok", s["status"]
    assert s["solver"]["name"] == solver and SOLVER_TYPES[solver] in s["solver"]["exudyn"]
    ts = r.timeseries
    assert len(ts["time_s"]) == STEPS + 1
    assert ts["time_s"][-1] == pytest.approx(STEPS * DT)
    for col in ("lateral_contact_force_w1_right_N", "carbody_lateral_acceleration_rear_m_s2",
                "vertical_contact_force_w1_right_N"):
        assert np.all(np.isfinite(ts[col])), col
    ref = newmark_run.timeseries
    # same equations, different integrators: the slow car-body response and the static wheel load agree
    a = s["peaks"]["max_abs_carbody_lateral_acceleration_rear_m_s2"]
    a_ref = newmark_run.summary["peaks"]["max_abs_carbody_lateral_acceleration_rear_m_s2"]
    assert a == pytest.approx(a_ref, rel=0.05)
    q = ts["vertical_contact_force_w1_right_N"]
    q_ref = ref["vertical_contact_force_w1_right_N"]
    assert q.mean() == pytest.approx(q_ref.mean(), rel=0.02)
