"""Track irregularities (exudyn_wheelrail.track.rigid): continuity, shape, derivatives, tables, numba use.

References: the analytic sine of the span deflection, finite differences, the closed-form limit of the transition
(quartic for a short transition), np.interp-free spline facts (interpolation at the samples, zero end slopes)."""
import math

import numpy as np
import pytest
from numba import njit

from exudyn_wheelrail.track.rigid import (
    Harmonic,
    NoIrregularity,
    RigidStraightTrack,
    SampledIrregularity,
    SpanDeflection,
    irregularity_at,
)
from exudyn_wheelrail.scenarios.rtri_assumptions import RTRI, RtriAssumptions

SPANS = [SpanDeflection(20.0, 0.010, start_m=5.0, transition_length_m=3.0),
         SpanDeflection(40.0, 0.010, start_m=-7.0, transition_length_m=3.0),
         SpanDeflection(20.0, -0.004, start_m=0.0, transition_length_m=12.0, direction="vertical")]


def _col(values, direction):
    return ((values.y_m, values.dy_ds, values.d2y_ds2) if direction == "lateral"
            else (values.z_m, values.dz_ds, values.d2z_ds2))


@pytest.mark.parametrize("span", SPANS)
def test_span_is_c2_at_every_joint(span):
    eps = 1e-6
    scale = abs(span.amplitude_m) * math.pi / span.span_length_m            # the end slope k = πδ/L
    for joint in span.joints_m():
        v, d1, d2 = _col(span.evaluate([joint - eps, joint + eps]), span.direction)
        # jumps allowed: the change over 2 eps of a smooth function, bounded by its next derivative (in the
        # transition |dy/ds| <= k, |d2y/ds2| <= 1.5 k/l_t, |d3y/ds3| <= 6 k/l_t^2); a C1-only joint would show a
        # curvature jump of order δ(π/L)^2 or k/l_t, i.e. ~1e-4 1/m, five orders above the bound
        lt = span.transition_length_m
        assert abs(v[1] - v[0]) < 3 * eps * scale, joint
        assert abs(d1[1] - d1[0]) < 3 * eps * 1.5 * scale / lt, joint
        assert abs(d2[1] - d2[0]) < 3 * eps * 6 * scale / lt ** 2, joint


def test_without_transition_the_kink_is_there():
    """l_t = 0 reproduces the kinked shape: slope jumps from 0 to πδ/L at the span start."""
    span = SpanDeflection(20.0, 0.01, start_m=3.0)
    v = span.evaluate([3.0 - 1e-9, 3.0 + 1e-9])
    # before the span: an assigned zero slope (exact)
    assert v.dy_ds[0] == 0.0 and v.dy_ds[1] == pytest.approx(math.pi * 0.01 / 20.0)
    assert RTRI.end_rotation_rad(20.0) == pytest.approx((span.evaluate(3.0 + 1e-6).y_m) / 1e-6, rel=1e-6)


@pytest.mark.parametrize("span", SPANS)
def test_amplitude_symmetry_zero_outside_and_sine_inside(span):
    d, L, s0, h = span.amplitude_m, span.span_length_m, span.start_m, 0.5 * span.transition_length_m
    col = lambda s: _col(span.evaluate(s), span.direction)  # noqa: E731
    assert col(s0 + L / 2)[0] == pytest.approx(d, rel=1e-14)
    u = np.linspace(0.0, L / 2 + h + 2.0, 2001)
    left, right = col(s0 + L / 2 - u), col(s0 + L / 2 + u)
    assert np.allclose(left[0], right[0], atol=1e-15)          # symmetric about mid-span
    assert np.allclose(left[1], -right[1], atol=1e-15)         # slope antisymmetric
    assert np.allclose(left[2], right[2], atol=1e-15)
    outside = np.concatenate([np.linspace(s0 - h - 50, s0 - h, 200), np.linspace(s0 + L + h, s0 + L + h + 50, 200)])
    for c in col(outside):
        assert np.all(c == 0.0)  # outside the span: assigned zeros
    inner = np.linspace(s0 + h, s0 + L - h, 500)
    w = math.pi / L
    y, y1, y2 = col(inner)
    assert np.allclose(y, d * np.sin(w * (inner - s0)), rtol=0, atol=1e-15)
    assert np.allclose(y1, d * w * np.cos(w * (inner - s0)), rtol=0, atol=1e-15)
    assert np.allclose(y2, -d * w * w * np.sin(w * (inner - s0)), rtol=0, atol=1e-15)
    everywhere = col(np.linspace(s0 - h - 1, s0 + L + h + 1, 20001))[0]
    assert np.all(everywhere / d >= -1e-15) and np.all(everywhere / d <= 1 + 1e-15)   # no overshoot


def test_short_transition_is_the_quartic_kink_rounding():
    """For l_t << L the transition tends to y = k l_t (ξ³ - ξ⁴/2):
    3/32 k l_t at the span end, slope k/2, curvature 1.5 k/l_t."""
    d, L, lt = 0.01, 400.0, 0.4
    span = SpanDeflection(L, d, start_m=0.0, transition_length_m=lt)
    k = math.pi * d / L
    v = span.evaluate(0.0)
    assert v.y_m == pytest.approx(3 / 32 * k * lt, rel=1e-3)
    assert v.d2y_ds2 == pytest.approx(1.5 * k / lt, rel=1e-3)
    assert v.dy_ds == pytest.approx(k / 2, rel=1e-3)


IRREGULARITIES = {
    "span": SPANS[0],
    "span_vertical": SPANS[2],
    "harmonic": Harmonic(0.002, 12.5, phase_rad=0.3, direction="vertical"),
    "table": SampledIrregularity(np.linspace(0, 30, 61), 1e-3 * np.sin(np.linspace(0, 30, 61) * 0.7),
                                 1e-3 * np.cos(np.linspace(0, 30, 61) * 0.3)),
    "sum": SPANS[0] + Harmonic(0.001, 7.0) + SPANS[2],
}


@pytest.mark.parametrize("name", IRREGULARITIES)
def test_derivatives_against_finite_differences(name):
    irr = IRREGULARITIES[name]
    rng = np.random.default_rng(7)
    s = rng.uniform(-10.0, 40.0, 400)
    h = 1e-5
    v, vp, vm = irr.evaluate(s), irr.evaluate(s + h), irr.evaluate(s - h)
    for val, d1, d2 in (("y_m", "dy_ds", "d2y_ds2"), ("z_m", "dz_ds", "d2z_ds2")):
        fd1 = (getattr(vp, val) - getattr(vm, val)) / (2 * h)
        fd2 = (getattr(vp, d1) - getattr(vm, d1)) / (2 * h)
        assert np.allclose(getattr(v, d1), fd1, rtol=1e-6, atol=1e-10), (name, d1)
        assert np.allclose(getattr(v, d2), fd2, rtol=1e-5, atol=1e-9), (name, d2)


def test_sum_is_the_sum_of_the_parts():
    a, b, c = SPANS[0], Harmonic(0.001, 7.0), IRREGULARITIES["table"]
    s = np.linspace(-5, 35, 777)
    total = (a + b + c).evaluate(s)
    parts = [x.evaluate(s) for x in (a, b, c)]
    for field in ("y_m", "dy_ds", "d2y_ds2", "z_m", "dz_ds", "d2z_ds2"):
        assert np.allclose(getattr(total, field), sum(getattr(p, field) for p in parts), rtol=0, atol=1e-16)
    assert len((a + b + c).components) == 3
    assert np.all(NoIrregularity().evaluate(s).y_m == 0.0)  # zeros by construction
    assert (a + b).evaluate(np.zeros((3, 4))).y_m.shape == (3, 4)


def test_sampled_table_interpolates_and_holds(tmp_path):
    s = np.array([0.0, 1.0, 2.5, 4.0, 6.0])
    y = np.array([0.0, 1e-3, -2e-3, 0.5e-3, 1e-3])
    z = np.array([1e-3, 0.0, 0.0, 2e-3, -1e-3])
    path = tmp_path / "measured.csv"
    path.write_text("# measured irregularity, metres\ns_m,y_m,z_m,comment\n" +
                    "".join(f"{a},{b},{c},x\n" for a, b, c in zip(s, y, z)))
    table = SampledIrregularity.from_csv(path)
    v = table.evaluate(s)
    assert np.allclose(v.y_m, y, atol=1e-18) and np.allclose(v.z_m, z, atol=1e-18)
    ends = table.evaluate([s[0], s[-1]])
    assert np.allclose(ends.dy_ds, 0.0, atol=1e-15) and np.allclose(ends.dz_ds, 0.0, atol=1e-15)   # clamped ends
    out = table.evaluate([-3.0, 9.0])
    assert np.allclose(out.y_m, [y[0], y[-1]], rtol=0, atol=1e-17)
    assert np.allclose(out.z_m, [z[0], z[-1]], rtol=0, atol=1e-17)
    assert np.all(out.dy_ds == 0.0) and np.all(out.d2z_ds2 == 0.0)  # held ends: assigned zeros
    # C2 at the inner samples (cubic spline), C1 at the table ends
    for knot in s[1:-1]:
        lo_hi = table.evaluate([knot - 1e-9, knot + 1e-9])
        for field in ("y_m", "dy_ds", "d2y_ds2", "z_m", "dz_ds", "d2z_ds2"):
            assert abs(np.diff(getattr(lo_hi, field))[0]) < 1e-9, (knot, field)


@pytest.mark.parametrize("content, fragment", [
    ("s_m,y_m\n0,0\n1,0\n", "missing column 'z_m'"),
    ("s_m,y_m,z_m\n0,0,0\n0,1e-3,0\n", "s must increase strictly"),
    ("s_m,y_m,z_m\n0,0,0\n1,abc,0\n", "column 'y_m'"),
    ("s_m,y_m,z_m\n0,0,0\n", "at least two samples"),
])
def test_bad_table_names_the_file(tmp_path, content, fragment):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    with pytest.raises(ValueError, match="bad.csv") as err:
        SampledIrregularity.from_csv(path)
    assert fragment in str(err.value)


def test_bad_parameters():
    with pytest.raises(ValueError, match="transition_length_m"):
        SpanDeflection(10.0, 0.01, transition_length_m=10.0)
    with pytest.raises(ValueError, match="span_length_m"):
        SpanDeflection(0.0, 0.01)
    with pytest.raises(ValueError, match="direction"):
        SpanDeflection(10.0, 0.01, direction="sideways")
    with pytest.raises(ValueError, match="wavelength_m"):
        Harmonic(0.01, -1.0)


def test_kernel_is_callable_from_compiled_code():
    """The contact kernel calls the packed irregularity per wheel from numba: do the same here."""
    track = RigidStraightTrack(SPANS[0] + Harmonic(0.001, 9.0, direction="vertical"))
    p = track.packed()

    @njit
    def lateral_at_wheels(rows, knots, coefs, s_wheels):
        out = np.empty(s_wheels.shape[0])
        for i in range(s_wheels.shape[0]):
            out[i] = irregularity_at(rows, knots, coefs, s_wheels[i])[0]
        return out

    s = np.array([2.0, 10.0, 15.0, 24.0])
    assert np.allclose(lateral_at_wheels(p.rows, p.knots, p.coefs, s), track.rail_offset(s).y_m, rtol=0, atol=0)


def test_rtri_assumptions_in_one_place():
    a = RtriAssumptions()
    span = a.span_deflection(20.0)
    assert (span.amplitude_m, span.transition_length_m, span.direction) == (a.deviation_amplitude_m,
                                                                           a.transition_length_m, "lateral")
    assert span.start_m - span.transition_length_m / 2 == pytest.approx(a.lead_in_m)   # lead-in to the transition
    assert a.time_step_s == 1e-3 and a.span_lengths_m == (20.0, 40.0)
    assert (a.newmark_beta, a.newmark_gamma) == (0.25, 0.5)
    # the run covers lead-in, span, transition, vehicle and run-out at the given speed
    assert a.run_time_s(180.0, 40.0, 21.56) == pytest.approx((10 + 40 + 3 + 21.56 + 10) / 50.0)
    with pytest.raises(ValueError):
        RtriAssumptions(transition_length_m=25.0)
