"""Bridge model (exudyn_wheelrail.structures.bridge): frequencies, mode shapes, rail kinematics, force projection,
Exudyn formulations, moving loads and the coupling mechanism for the wheel–rail connector.

References (independent of the finite-element code):
* Euler–Bernoulli frequencies of a simply supported span ``f_n = n²π/(2L²)√(EI/m)``, St Venant torsion
  ``f_n = n/(2L)√(GJ/I_p)``, the clamped–pinned span (root of ``tan λ = tanh λ``) for the symmetric mode of a
  two-span continuous beam, the sine mode shapes with modal mass mL/2;
* static beam formulas (point force on a simply supported span, torque on a span fixed in torsion at both ends);
* Frýba's series solution of a simply supported beam under a moving constant force (Frýba 1999, Ch. 1), and its
  textbook form written out here once more; the resonance speeds ``v = f1 d / k`` of a train of forces (Frýba,
  Eng. Struct. 23 (2001) 548–556);
* the closed-form solution (matrix exponential) of the linear coupled system mass–spring–bridge.
"""
import math

import numpy as np
import pytest
import scipy.linalg
from numba import njit
from scipy.optimize import brentq

from exudyn_wheelrail.structures import (
    BridgeModel,
    DeckSection,
    MovingForces,
    add_bridge,
    add_projected_force,
    fryba_moving_force,
    modal_shape_and_slope_at,
    modal_shape_at,
    rail_state_at,
)
from exudyn_wheelrail.scenarios.moving_forces import simulate_moving_forces
from exudyn_wheelrail.structures.beam import element_matrices

# a 20 m steel-concrete deck: f1 (vertical) 4.53 Hz, lateral 10.1 Hz, torsion 7.91 Hz
SEC = DeckSection(m_kg_m=15e3, EI_y_Nm2=2.0e10, EI_z_Nm2=1.0e11, GJ_Nm2=6e9, EA_N=2e11, Ip_kgm2_m=6e4)
L = 20.0


@pytest.fixture(scope="module")
def span_modes():
    return BridgeModel((L,), SEC).modes(f_max_Hz=150.0)


# ------------------------------------------------------------------------------------------ (i) frequencies
def test_simply_supported_frequencies_against_euler_bernoulli_and_st_venant():
    modes = BridgeModel((L,), SEC, elements_per_span=20).modes(n_modes=20)
    for kind, f_ref, n_max in (("vertical", SEC.vertical_frequency_Hz, 3), ("lateral", SEC.lateral_frequency_Hz, 2),
                               ("torsion", SEC.torsion_frequency_Hz, 2)):
        idx = modes.of_kind(kind)
        assert len(idx) >= n_max, kind
        for n in range(1, n_max + 1):
            f = modes.frequencies_Hz[idx[n - 1]]
            assert f == pytest.approx(f_ref(L, n), rel=5e-3), (kind, n)
            assert modes.energy_fractions[kind][idx[n - 1]] > 1 - 1e-9      # pure modes: no coupling of groups
    # the axial mode (fixed–free: one end held longitudinally): f = √(EA/m)/(4L)
    f_ax = modes.frequencies_Hz[modes.of_kind("axial")[0]]
    assert f_ax == pytest.approx(math.sqrt(SEC.EA_N / SEC.m_kg_m) / (4 * L), rel=5e-3)


def test_torsion_frequencies_follow_the_dispersion_of_linear_elements():
    """Linear torsion elements with consistent mass on a span fixed at both ends have the exact sine modes at the
    nodes and ω_h/ω = √(6(1 - cos kh) / ((kh)²(2 + cos kh))), k = nπ/L, h = L/n_e (≈ 1 + (kh)²/24): the mesh
    error of the torsion frequencies, and its second-order convergence."""
    for n_e in (10, 20, 40):
        model = BridgeModel((L,), SEC, elements_per_span=n_e)
        modes = model.modes(n_modes=24)
        f = modes.frequencies_Hz[modes.of_kind("torsion")][:3]
        # tolerance: a symmetric generalized eigensolver gives an eigenvalue λ to about ε λ_max / λ (λ_max the
        # largest eigenvalue of the discretised deck, an axial mode of the shortest element): 1e-10 at 10 elements,
        # 2e-8 at 40 (measured differences between LAPACK builds: up to 2.6e-9); a frequency has half of it
        M, K = model.assemble(supported=True)
        lam_max = scipy.linalg.eigh(K.toarray(), M.toarray(), eigvals_only=True)[-1]
        for n in (1, 2, 3):
            kh = n * math.pi / n_e
            ratio = math.sqrt(6 * (1 - math.cos(kh)) / (kh ** 2 * (2 + math.cos(kh))))
            rel = np.finfo(float).eps * lam_max / (2 * math.pi * f[n - 1]) ** 2
            assert f[n - 1] / SEC.torsion_frequency_Hz(L, n) == pytest.approx(ratio, rel=max(rel, 1e-12)), (n_e, n)


def test_two_span_continuous_beam_first_equals_single_span_second_is_clamped_pinned():
    modes = BridgeModel((L, L), SEC, continuous=True).modes(n_modes=12)
    vert = modes.frequencies_Hz[modes.of_kind("vertical")]
    # 1st: antisymmetric, each span as a simply supported one
    assert vert[0] == pytest.approx(SEC.vertical_frequency_Hz(L), rel=5e-3)
    # 2nd: symmetric, zero slope over the middle support: each span clamped–pinned, tan λ = tanh λ
    lam = brentq(lambda x: math.tan(x) - math.tanh(x), math.pi + 0.1, 1.5 * math.pi - 1e-3)
    assert lam == pytest.approx(3.9266, abs=1e-4)
    f2 = lam ** 2 / (2 * math.pi * L ** 2) * math.sqrt(SEC.EI_y_Nm2 / SEC.m_kg_m)
    assert vert[1] == pytest.approx(f2, rel=5e-3)
    lat = modes.frequencies_Hz[modes.of_kind("lateral")]
    assert lat[0] == pytest.approx(SEC.lateral_frequency_Hz(L), rel=5e-3)


def test_chain_of_simply_supported_spans_has_the_frequencies_of_each_span():
    L2 = 15.0
    modes = BridgeModel((L, L2), SEC, continuous=False).modes(n_modes=10)
    vert = np.sort(modes.frequencies_Hz[modes.of_kind("vertical")])
    ref = np.sort([SEC.vertical_frequency_Hz(L), SEC.vertical_frequency_Hz(L2), SEC.vertical_frequency_Hz(L, 2)])
    np.testing.assert_allclose(vert[:3], ref, rtol=5e-3)
    # a static force on the first span leaves the second one at rest
    all_modes = BridgeModel((L, L2), SEC, continuous=False).modes(n_modes=100)
    q = all_modes.project([7.0], [[0.0, 1e5, 0.0]]) / all_modes.omega_rad_s ** 2
    assert np.max(np.abs(all_modes.rail_displacement(np.linspace(L + 0.1, L + L2, 20), q))) < 1e-15
    assert all_modes.rail_displacement(7.0, q)[1] > 1e-4


def test_modes_are_mass_normalised_and_diagonalise_the_stiffness(span_modes):
    M, K = span_modes.model.assemble(supported=False)
    S = span_modes.shapes
    np.testing.assert_allclose(S.T @ M @ S, np.eye(span_modes.n_modes), atol=1e-10)
    np.testing.assert_allclose(S.T @ K @ S, np.diag(span_modes.omega_rad_s ** 2),
                               atol=1e-9 * span_modes.omega_rad_s[-1] ** 2)
    assert np.all(np.diff(span_modes.frequencies_Hz) >= 0)
    Ms, Ks = span_modes.model.assemble()
    assert Ms.shape == Ks.shape == (span_modes.model.free_dofs().size,) * 2
    assert np.all(np.linalg.eigvalsh(Ks.toarray()) > 0)            # the supports remove all rigid-body motion


def test_element_matrices_reproduce_rigid_body_motion_and_total_mass():
    Le = 1.3
    Me, Ke = element_matrices(Le, SEC)
    # rigid translations and rotations: no strain energy; translations carry the element mass
    x = np.array([0.0, Le])
    for d in range(3):
        r = np.zeros(12)
        r[[d, 6 + d]] = 1.0
        assert np.allclose(Ke @ r, 0.0, atol=1e-6 * np.abs(Ke).max())
        assert r @ Me @ r == pytest.approx(SEC.m_kg_m * Le, rel=1e-12)
    r = np.zeros(12)                       # rotation about z: v = θz x, θz = 1
    r[[1, 7]] = x
    r[[5, 11]] = 1.0
    assert np.allclose(Ke @ r, 0.0, atol=1e-6 * np.abs(Ke).max())
    r = np.zeros(12)                       # rotation about y: w = -θy x
    r[[2, 8]] = -x
    r[[4, 10]] = 1.0
    assert np.allclose(Ke @ r, 0.0, atol=1e-6 * np.abs(Ke).max())


# ------------------------------------------------------------------------------------ shapes and projection
def test_first_vertical_mode_is_the_mass_normalised_sine(span_modes):
    i = span_modes.of_kind("vertical")[0]
    s = np.linspace(0.0, L, 157)                                    # between the nodes too
    phi, dphi = span_modes.shape_and_slope_at(s)
    amp = math.sqrt(2.0 / (SEC.m_kg_m * L))                        # modal mass mL/2 -> unit
    np.testing.assert_allclose(phi[:, 1, i], amp * np.sin(math.pi * s / L), atol=2e-5 * amp)
    np.testing.assert_allclose(dphi[:, 1, i], amp * math.pi / L * np.cos(math.pi * s / L), atol=2e-3 * amp / L)
    assert np.allclose(phi[:, [0, 2], i], 0.0, atol=1e-12)
    # a torsion mode moves the rail laterally by e_z θ
    e_z = 1.2
    m2 = BridgeModel((L,), SEC, rail_height_m=e_z).modes(n_modes=6)
    j = m2.of_kind("torsion")[0]
    phi2 = m2.shape_at(s)
    amp_t = math.sqrt(2.0 / (SEC.Ip_kgm2_m * L))
    np.testing.assert_allclose(phi2[:, 2, j], amp_t * np.sin(math.pi * s / L), atol=5e-3 * amp_t)
    np.testing.assert_allclose(phi2[:, 0, j], e_z * phi2[:, 2, j], atol=1e-14)
    # off the deck: zero
    assert np.all(m2.shape_at([-0.01, L + 0.01, np.nan]) == 0.0)  # assigned zeros: exact


def _ss_point_load(x, a, P, EI):
    """Static deflection of a simply supported span (length L) under a point force P at a."""
    b = L - a
    x = np.asarray(x, dtype=float)
    left = P * b * x * (L ** 2 - b ** 2 - x ** 2) / (6 * EI * L)
    xr = L - x
    right = P * a * xr * (L ** 2 - a ** 2 - xr ** 2) / (6 * EI * L)
    return np.where(x <= a, left, right)


def _torsion_point_torque(x, a, T, GJ):
    x = np.asarray(x, dtype=float)
    return np.where(x <= a, T * (L - a) * x / (GJ * L), T * a * (L - x) / (GJ * L))


def test_projection_with_all_modes_gives_the_static_beam_solutions():
    """With all modes the static modal solution q = Ω⁻² Φ(a)^T F is the finite-element solution; it must match the
    beam formulas at the nodes (Hermite elements with consistent loads are nodally exact) for forces between nodes.
    A lateral force at rail height also twists the deck (Mx = e_z Fy) and the rail moves by v + e_z θ."""
    e_z = 0.9
    model = BridgeModel((L,), SEC, rail_height_m=e_z, start_m=100.0)
    modes = model.modes(n_modes=model.free_dofs().size)
    a = 7.3                                                        # between nodes (element length 1 m)
    x_nodes = model.node_x_m
    s_nodes = 100.0 + x_nodes
    Fy, Fz, Mx = 4e4, 1e5, 3e4
    q = modes.project([100.0 + a], [[Fy, Fz, Mx]]) / modes.omega_rad_s ** 2
    u = modes.rail_displacement(s_nodes, q)
    w_ref = _ss_point_load(x_nodes, a, Fz, SEC.EI_y_Nm2)
    v_ref = _ss_point_load(x_nodes, a, Fy, SEC.EI_z_Nm2)
    th_ref = _torsion_point_torque(x_nodes, a, Mx + e_z * Fy, SEC.GJ_Nm2)
    np.testing.assert_allclose(u[:, 1], w_ref, atol=1e-9 * np.abs(w_ref).max())
    np.testing.assert_allclose(u[:, 2], th_ref, atol=1e-9 * np.abs(th_ref).max())
    np.testing.assert_allclose(u[:, 0], v_ref + e_z * th_ref, atol=1e-9 * np.abs(v_ref).max())
    # and between the nodes (Hermite interpolation of the exact nodal values: close, not exact)
    xs = np.linspace(0.0, L, 333)
    w = modes.rail_displacement(100.0 + xs, q)[:, 1]
    np.testing.assert_allclose(w, _ss_point_load(xs, a, Fz, SEC.EI_y_Nm2), atol=2e-3 * np.abs(w_ref).max())


def _assert_same_sum(got, A, x):
    """``got`` is ``A @ x`` summed in another order (the compiled loop against NumPy's, which may block and vectorize
    the sum differently on another CPU or BLAS): each of the two sums of m terms is within (m - 1) eps sum|A_ij x_j|
    of the exact one, so they differ by at most 2 m eps sum|A_ij x_j| per element — cancellation between the terms
    (the shapes change sign along the span) is why the bound is on the sum of magnitudes, not on the result."""
    bound = 2 * A.shape[1] * np.finfo(float).eps * (np.abs(A) @ np.abs(x))
    assert np.all(np.abs(got - A @ x) <= bound), (got, A @ x, bound)


def test_compiled_functions_agree_with_the_wrappers_and_finite_differences(span_modes):
    tab = span_modes.table
    n = span_modes.n_modes
    rng = np.random.default_rng(1)
    q = rng.normal(size=n) * 1e-3
    q_t = rng.normal(size=n) * 1e-2
    V = 55.0
    out = np.empty((3, n))
    out_ds = np.empty((3, n))
    work = np.empty((3, n))
    work_ds = np.empty((3, n))
    state = np.empty(9)
    for s in (0.0, 3.3, 10.0, 19.99, L):
        assert modal_shape_at(s, *tab, out)
        # exact by construction: shape_at runs the same compiled interpolation on the same inputs
        np.testing.assert_array_equal(out, span_modes.shape_at(s))
        assert modal_shape_and_slope_at(s, *tab, out, out_ds)
        assert rail_state_at(s, V, *tab, q, q_t, work, work_ds, state)
        _assert_same_sum(state[:3], out, q)
        _assert_same_sum(state[3:6], out, q_t)
        f = np.zeros(n)
        assert add_projected_force(s, 1.0, 2.0, 3.0, *tab, work, f)
        _assert_same_sum(f, out.T, np.array([1.0, 2.0, 3.0]))
    # the rate seen by a point moving at V: d/dt [Φ(s0 + V t) q(t)] with q(t) = q + q_t t (central differences)
    s0, h = 8.1, 1e-6
    u = lambda t: span_modes.rail_displacement(s0 + V * t, q + q_t * t)  # noqa: E731
    rail_state_at(s0, V, *tab, q, q_t, work, work_ds, state)
    np.testing.assert_allclose(state[6:9], (u(h) - u(-h)) / (2 * h), rtol=1e-5, atol=1e-12)
    # off the deck nothing is added
    f = np.zeros(n)
    assert not add_projected_force(-1.0, 1.0, 1.0, 1.0, *tab, work, f) and not f.any()
    assert not modal_shape_at(L + 1.0, *tab, out) and not out.any()

    @njit
    def user_kernel(s, table, q):                # callable from a user's compiled code (the connector)
        phi = np.empty((3, table[5].shape[2]))
        modal_shape_at(s, table[0], table[1], table[2], table[3], table[4], table[5], phi)
        return phi @ q

    np.testing.assert_allclose(user_kernel(5.0, tuple(tab), q), span_modes.rail_displacement(5.0, q), rtol=1e-13)


# ------------------------------------------------------------------------------------ (ii) moving force
def newton_relative_tolerance():
    """Relative residual tolerance of the implicit solver's Newton iteration in the library's simulation settings."""
    from exudyn_wheelrail.simulation.exudyn_settings import simulation_settings

    return simulation_settings(1.0, 1.0).timeIntegration.newton.relativeTolerance


def _fryba_textbook(x, t, P, v, n_terms=60):
    """Frýba (1999, Ch. 1), undamped, force on the span: v0 Σ 1/(j²(j²-α²)) [sin jωt - α/j sin ω_j t] sin(jπx/L)."""
    v0 = 2 * P * L ** 3 / (math.pi ** 4 * SEC.EI_y_Nm2)
    om1 = (math.pi / L) ** 2 * math.sqrt(SEC.EI_y_Nm2 / SEC.m_kg_m)
    om = math.pi * v / L
    alpha = om / om1
    return sum(v0 / (j * j * (j * j - alpha ** 2)) * (np.sin(j * om * t) - alpha / j * np.sin(j * j * om1 * t))
               * math.sin(j * math.pi * x / L) for j in range(1, n_terms + 1))


def test_reference_solution_is_fryba_and_has_the_static_limit():
    P, v = 2e5, 40.0
    t = np.linspace(0.0, L / v, 201)
    ref = fryba_moving_force(L / 2, t, force_N=P, speed_m_s=v, span_m=L, EI_Nm2=SEC.EI_y_Nm2, m_kg_m=SEC.m_kg_m)
    np.testing.assert_allclose(ref, _fryba_textbook(L / 2, t, P, v, n_terms=50), atol=1e-12)
    # crawling force at mid-span: PL³/(48 EI)
    v_slow = 1e-3
    w = fryba_moving_force(L / 2, L / 2 / v_slow, force_N=P, speed_m_s=v_slow, span_m=L, EI_Nm2=SEC.EI_y_Nm2,
                           m_kg_m=SEC.m_kg_m, n_terms=200)
    assert float(w) == pytest.approx(P * L ** 3 / (48 * SEC.EI_y_Nm2), rel=1e-5)
    # free vibration after the exit continues the forced solution smoothly
    T = L / v
    w3 = fryba_moving_force(L / 2, [T - 1e-10, T + 1e-10], force_N=P, speed_m_s=v, span_m=L, EI_Nm2=SEC.EI_y_Nm2,
                            m_kg_m=SEC.m_kg_m)
    assert abs(w3[1] - w3[0]) < 1e-11 * abs(w3[0]) / 1e-4               # |dw/dt| < 0.1 m/s


@pytest.mark.parametrize("zeta", [0.0, 0.03])
def test_moving_force_mid_span_history_against_fryba(span_modes, zeta):
    """Exudyn (generalized-α, ρ∞ = 1, Δt = 0.5 ms) of the modal model with all 25 modes up to 150 Hz (5 vertical:
    j = 1..5) and the force projected at s = v t every RHS evaluation, against Frýba's series with 60 terms:
    mid-span deflection over the passage and 0.25 s of free vibration within 1 % of the peak."""
    modes = span_modes
    if zeta:
        modes = BridgeModel((L,), SEC, damping_ratio=zeta).modes(f_max_Hz=150.0)
    P, v = 2e5, 40.0                          # α = v/(2 f1 L) = 0.22
    t, q, _ = simulate_moving_forces(modes, x_m=[0.0], forces_N=[[0.0, P, 0.0]], speed_m_s=v, s_start_m=0.0,
                                     end_time_s=L / v + 0.25, dt_s=5e-4)
    w = q @ modes.shape_at(L / 2)[1]
    ref = fryba_moving_force(L / 2, t, force_N=P, speed_m_s=v, span_m=L, EI_Nm2=SEC.EI_y_Nm2, m_kg_m=SEC.m_kg_m,
                             damping_ratio=zeta, n_terms=60)
    peak = np.max(np.abs(ref))
    assert peak > 1.1 * P * L ** 3 / (48 * SEC.EI_y_Nm2)            # a dynamic case (amplification > 10 %)
    assert np.max(np.abs(w - ref)) < 0.01 * peak
    assert np.max(np.abs(w)) == pytest.approx(peak, rel=0.01)


def test_ffrf_formulation_equals_the_modal_one_and_has_the_beam_inertia(span_modes):
    import exudyn as exu

    P, v = 2e5, 40.0
    runs = {}
    for form in ("modal", "ffrf"):
        t, q, _ = simulate_moving_forces(span_modes, x_m=[0.0], forces_N=[[0.0, P, 0.0]], speed_m_s=v,
                                         s_start_m=0.0, end_time_s=L / v + 0.1, dt_s=5e-4, formulation=form)
        runs[form] = q @ span_modes.shape_at(L / 2)[1]
    ref = fryba_moving_force(L / 2, t, force_N=P, speed_m_s=v, span_m=L, EI_Nm2=SEC.EI_y_Nm2, m_kg_m=SEC.m_kg_m,
                             n_terms=60)
    assert np.max(np.abs(runs["ffrf"] - ref)) < 0.01 * np.max(np.abs(ref))
    # the same equations by two code paths: the modal run is linear (Newton exact in one iteration), the FFRF run's
    # Newton stops once the residual has dropped by the relative tolerance, so each step's correction may be off by
    # that fraction; summed over the run this is bounded by tolerance x total variation of the response (measured:
    # 2.3e-10 of the peak, i.e. ~1e-4 of this bound; the exact agreement depends on the CPU's rounding)
    np.testing.assert_allclose(runs["ffrf"], runs["modal"], rtol=0,
                               atol=newton_relative_tolerance() * np.abs(np.diff(runs["modal"])).sum())
    # the rigid-body data Exudyn derived from the point mesh are those of the beam
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    br = add_bridge(mbs, span_modes, "ffrf")
    assert mbs.GetObjectParameter(br.object, "mass") == pytest.approx(SEC.m_kg_m * L, rel=1e-10)
    J = np.asarray(mbs.GetObjectParameter(br.object, "inertia"))
    assert J[0, 0] == pytest.approx(SEC.Ip_kgm2_m * L, rel=1e-8)              # about the axis
    assert J[1, 1] == pytest.approx(SEC.m_kg_m * L ** 3 / 3, rel=1e-8)        # about the end (reference point)
    np.testing.assert_allclose(mbs.GetObjectParameter(br.object, "centerOfMass"), [L / 2, 0, 0], atol=1e-12)
    assert len(br.constraints) == 6 and br.rigid_node is not None


# ---------------------------------------------------------------------------------------- (iii) resonance
def test_train_of_forces_resonates_at_f1_d():
    """Ten equal forces at spacing d = 20 m (= L) over the 20 m span, ζ = 1 %: the maximum mid-span deflection
    against speed (Exudyn, modal model, 13 modes up to 60 Hz, Δt = 2 ms) peaks at v = f1 d (parabola through the
    three largest samples of a 2 % sweep), and every sample agrees with the superposed Frýba solution."""
    zeta, d, n_f, P = 0.01, 20.0, 10, 1.5e5
    modes = BridgeModel((L,), SEC, damping_ratio=zeta).modes(f_max_Hz=60.0)
    v_res = SEC.vertical_frequency_Hz(L) * d
    vs = v_res * np.linspace(0.8, 1.2, 21)
    offs = d * np.arange(n_f)
    w_max, w_ref = [], []
    for v in vs:
        T = (L + offs[-1]) / v + 0.3
        t, q, _ = simulate_moving_forces(modes, x_m=-offs, forces_N=[[0.0, P, 0.0]] * n_f, speed_m_s=v,
                                         s_start_m=0.0, end_time_s=T, dt_s=2e-3)
        w_max.append(np.max(np.abs(q @ modes.shape_at(L / 2)[1])))
        tt = np.arange(0.0, T, 5e-4)
        w_ref.append(np.max(np.abs(fryba_moving_force(L / 2, tt, force_N=P, speed_m_s=v, span_m=L,
                                                      EI_Nm2=SEC.EI_y_Nm2, m_kg_m=SEC.m_kg_m, damping_ratio=zeta,
                                                      n_terms=9, offsets_m=offs))))
    w_max, w_ref = np.array(w_max), np.array(w_ref)
    np.testing.assert_allclose(w_max, w_ref, rtol=0.01)
    k = int(np.argmax(w_max))
    assert 0 < k < len(vs) - 1
    y0, y1, y2 = w_max[k - 1:k + 2]
    dv = vs[1] - vs[0]
    v_peak = vs[k] + 0.5 * dv * (y0 - y2) / (y0 - 2 * y1 + y2)
    assert v_peak == pytest.approx(v_res, rel=0.03)
    assert w_max[k] > 3 * w_max[0]                                         # a real resonance peak


def test_train_of_forces_second_resonance_at_half_f1_d():
    zeta, d, n_f, P = 0.01, 20.0, 12, 1.5e5
    modes = BridgeModel((L,), SEC, damping_ratio=zeta).modes(f_max_Hz=60.0)
    v_res = SEC.vertical_frequency_Hz(L) * d / 2
    vs = v_res * np.linspace(0.85, 1.15, 31)
    offs = d * np.arange(n_f)
    w_max = []
    for v in vs:
        t, q, _ = simulate_moving_forces(modes, x_m=-offs, forces_N=[[0.0, P, 0.0]] * n_f, speed_m_s=v,
                                         s_start_m=0.0, end_time_s=(L + offs[-1]) / v + 0.3, dt_s=2e-3)
        w_max.append(np.max(np.abs(q @ modes.shape_at(L / 2)[1])))
    k = int(np.argmax(w_max))
    assert vs[k] == pytest.approx(v_res, rel=0.03)


# ------------------------------------------------------------------------- coupling mechanism (design note)
@pytest.mark.parametrize("formulation,solver", [("modal", "implicit"), ("modal", "explicit"), ("ffrf", "implicit")])
def test_coupling_generic_object_over_rigid_and_modal_nodes(formulation, solver):
    """The recommended connector mechanism: one zero-mass ObjectGenericODE2 over a Lie-group rigid-body node and the
    bridge's modal node, returning forces for both (here a spring–damper from a body to the deck at s0, the body
    released under gravity), against the closed-form solution of the linear coupled system."""
    import exudyn as exu
    from exudyn.itemInterface import (LoadMassProportional, MarkerBodyMass, NodeRigidBodyRotVecLG, ObjectGenericODE2,
                                      ObjectRigidBody, SensorNode)

    from exudyn_wheelrail.simulation.exudyn_settings import simulation_settings

    modes = BridgeModel((L,), SEC, damping_ratio=0.02, rail_height_m=0.8).modes(n_modes=6)
    n = modes.n_modes
    s0, mass, k, c, g = 7.0, 4e4, 2e7, 1e5, 9.81
    phi = modes.shape_at(s0)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    bridge = add_bridge(mbs, modes, formulation)
    node = mbs.AddNode(NodeRigidBodyRotVecLG(referenceCoordinates=[0.0, 0.0, -1.0, 0.0, 0.0, 0.0]))
    body = mbs.AddObject(ObjectRigidBody(mass=mass, inertia=[1e4, 2e4, 3e4, 0, 0, 0], nodeNumber=node))
    mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=body)),
                                     loadVector=[0.0, 0.0, g]))
    f = np.zeros(6 + n)

    def force(mbs, t, itemIndex, q, q_t):
        q, q_t = np.asarray(q), np.asarray(q_t)
        F = k * (q[2] - phi[1] @ q[6:]) + c * (q_t[2] - phi[1] @ q_t[6:])   # spring compression force
        f[:] = 0.0
        f[2] = -F                                                           # on the body (up)
        f[6:] = phi.T @ np.array([0.0, F, 0.0])                             # on the deck (down)
        return f

    mbs.AddObject(ObjectGenericODE2(nodeNumbers=[node, bridge.modal_node], massMatrix=np.zeros((6 + n, 6 + n)),
                                    forceUserFunction=force))
    sensor = mbs.AddSensor(SensorNode(nodeNumber=node, storeInternal=True,
                                      outputVariableType=exu.OutputVariableType.Coordinates))
    mbs.Assemble()
    h = 2e-4 if solver == "explicit" else 5e-4
    ss = simulation_settings(0.4, h)
    if solver == "explicit":
        mbs.SolveDynamic(ss, solverType=exu.DynamicSolverType.RK44)
    else:
        mbs.SolveDynamic(ss)
    data = mbs.GetSensorStoredData(sensor)[::20]
    # closed form: x = [z_body, q], M x'' + C x' + K x = f_g from rest
    pz = phi[1]
    Mm = np.diag(np.r_[mass, np.ones(n)])
    Km = np.block([[np.array([[k]]), -k * pz[None, :]],
                   [-k * pz[:, None], modes.modal_stiffness() + k * np.outer(pz, pz)]])
    Cm = np.block([[np.array([[c]]), -c * pz[None, :]],
                   [-c * pz[:, None], modes.modal_damping() + c * np.outer(pz, pz)]])
    A = np.block([[np.zeros((n + 1, n + 1)), np.eye(n + 1)], [-np.linalg.solve(Mm, Km), -np.linalg.solve(Mm, Cm)]])
    xs = np.r_[np.linalg.solve(Km, np.r_[mass * g, np.zeros(n)]), np.zeros(n + 1)]
    z_ref = np.array([(xs - scipy.linalg.expm(A * t) @ xs)[0] for t in data[:, 0]])
    tol = 1e-6 if solver == "explicit" else 5e-4        # trapezoidal rule at 0.5 ms vs RK44 at 0.2 ms
    assert np.max(np.abs(data[:, 3] - z_ref)) < tol * np.max(np.abs(z_ref))
    q_end, _ = bridge.coordinates(mbs)
    assert np.all(np.isfinite(q_end)) and abs(phi[1] @ q_end) > 0          # the deck moved under the body


def test_moving_forces_are_the_projection_at_v_t(span_modes):
    import exudyn as exu

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    br = add_bridge(mbs, span_modes)
    mf = br.add_moving_forces(mbs, [0.0, -2.5], [[1e3, 2e4, 0.0], [0.0, 3e4, 5e2]], speed_m_s=30.0, s_start_m=-4.0)
    t = 0.4                                                  # forces at s = 8 and 5.5
    ref = span_modes.project([8.0, 5.5], [[1e3, 2e4, 0.0], [0.0, 3e4, 5e2]])
    np.testing.assert_allclose(mf.forces(t), ref, rtol=1e-14)
    assert not mf.forces(0.0).any()                          # both still before the deck
    # several bridges and load objects in one system get unique Exudyn names
    br2 = add_bridge(mbs, span_modes, "ffrf")
    br2.add_moving_forces(mbs, [0.0], [[0.0, 1e4, 0.0]], speed_m_s=30.0)
    br.add_moving_forces(mbs, [0.0], [[0.0, 1e4, 0.0]], speed_m_s=30.0)
    mbs.Assemble()
    assert br2.modal_node != br.modal_node


# ----------------------------------------------------------------------------------------- (iv) input checks
@pytest.mark.parametrize("kwargs,exc,match", [
    (dict(spans_m=()), ValueError, "at least one span"),
    (dict(spans_m=(20.0, -5.0)), ValueError, r"spans_m\[1\]"),
    (dict(spans_m=(float("nan"),)), ValueError, "finite"),
    (dict(spans_m="20"), TypeError, "number"),
    (dict(section=(SEC, SEC)), ValueError, "2 sections given for 1 spans"),
    (dict(section="steel"), TypeError, "DeckSection"),
    (dict(damping_ratio=2.0), ValueError, "not a percentage"),
    (dict(damping_ratio=-0.1), ValueError, ">= 0"),
    (dict(elements_per_span=1), ValueError, "elements_per_span"),
    (dict(elements_per_span=4.5), ValueError, "elements_per_span"),
    (dict(rail_height_m=-1.0), ValueError, "rail_height_m"),
    (dict(continuous="yes"), TypeError, "continuous"),
])
def test_bad_model_input(kwargs, exc, match):
    args = dict(spans_m=(L,), section=SEC)
    args.update(kwargs)
    with pytest.raises(exc, match=match):
        BridgeModel(**args)


def test_bad_section_modes_and_exudyn_input(span_modes):
    import exudyn as exu

    with pytest.raises(ValueError, match="EI_y_Nm2"):
        DeckSection(m_kg_m=1e4, EI_y_Nm2=0.0, EI_z_Nm2=1.0, GJ_Nm2=1.0, EA_N=1.0, Ip_kgm2_m=1.0)
    model = BridgeModel((L,), SEC)
    with pytest.raises(ValueError, match="exactly one"):
        model.modes()
    with pytest.raises(ValueError, match="exactly one"):
        model.modes(n_modes=3, f_max_Hz=50.0)
    with pytest.raises(ValueError, match="n_modes"):
        model.modes(n_modes=0)
    with pytest.raises(ValueError, match="only 119 free DOFs"):
        model.modes(n_modes=500)
    with pytest.raises(ValueError, match=r"lowest is 4\.53"):
        model.modes(f_max_Hz=1.0)
    with pytest.raises(ValueError, match="expected"):
        span_modes.rail_displacement(5.0, np.zeros(3))
    with pytest.raises(ValueError, match="2 positions but 1 forces"):
        span_modes.project([1.0, 2.0], [[0.0, 1.0, 0.0]])
    with pytest.raises(ValueError, match="of_kind|kind"):
        span_modes.of_kind("bending")
    mbs = exu.SystemContainer().AddSystem()
    with pytest.raises(ValueError, match="formulation"):
        add_bridge(mbs, span_modes, formulation="fem")
    with pytest.raises(TypeError, match="expected a ModalBasis"):
        add_bridge(mbs, model)
    br = add_bridge(mbs, span_modes)
    with pytest.raises(ValueError, match=r"shape \(1, 2\)"):
        MovingForces(mbs, br, [0.0], [[1.0, 2.0]], speed_m_s=10.0)
    with pytest.raises(ValueError, match="non-finite"):
        MovingForces(mbs, br, [np.nan], [[1.0, 2.0, 3.0]], speed_m_s=10.0)
    with pytest.raises(ValueError, match="speed_m_s"):
        fryba_moving_force(1.0, 0.1, force_N=1.0, speed_m_s=0.0, span_m=L, EI_Nm2=1.0, m_kg_m=1.0)
    with pytest.raises(ValueError, match="solver='implicit'"):
        simulate_moving_forces(span_modes, x_m=[0.0], forces_N=[[0, 1, 0]], speed_m_s=1.0, s_start_m=0.0,
                               end_time_s=0.1, dt_s=1e-3, formulation="ffrf", solver="explicit")


def test_large_models_use_the_sparse_eigen_solver_consistently():
    """Above the dense limit the shift-invert Lanczos path gives the same frequencies (checked on a small model by
    lowering the limit)."""
    import exudyn_wheelrail.structures.bridge as B

    model = BridgeModel((L, 15.0), SEC, continuous=True, elements_per_span=10)
    dense = model.modes(n_modes=8)
    old = B._DENSE_EIGEN_LIMIT
    try:
        B._DENSE_EIGEN_LIMIT = 0
        sparse_n = model.modes(n_modes=8)
        sparse_f = model.modes(f_max_Hz=float(dense.frequencies_Hz[7]) * 1.0001)
    finally:
        B._DENSE_EIGEN_LIMIT = old
    np.testing.assert_allclose(sparse_n.frequencies_Hz, dense.frequencies_Hz, rtol=1e-9)
    np.testing.assert_allclose(sparse_f.frequencies_Hz, dense.frequencies_Hz, rtol=1e-9)
    # same shapes up to sign (distinct frequencies)
    for j in range(8):
        a, b = dense.shapes[:, j], sparse_n.shapes[:, j]
        assert min(np.abs(a - b).max(), np.abs(a + b).max()) < 1e-6 * np.abs(a).max()
