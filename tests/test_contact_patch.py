"""The non-Hertzian contact patch (exudyn_wheelrail.contact.patch) and its exact reference, the normal contact
problem on the half-space solved on a grid (exudyn_wheelrail.contact.halfspace).

Independent references: Hertz's closed form (the half-space solver's check, and the patch method's on quadratic
geometry, where both must give Hertz's ellipse); the contact conditions themselves (no interpenetration, no
tension), recomputed here from Boussinesq's point-load solution; the exact half-space solution on the S1002/UIC60
profiles' own interpenetration (the patch method's check where Hertz does not hold).
"""
import csv
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.analysis.quasi_static import solve_quasi_static
from exudyn_wheelrail.contact import kernel as K
from exudyn_wheelrail.contact import patch as P
from exudyn_wheelrail.contact.halfspace import solve_halfspace
from exudyn_wheelrail.contact.normal import hertz_from_penetration

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
import manchester_a22 as A22  # noqa: E402
from scipy.integrate import quad  # noqa: E402

from exudyn_wheelrail.contact import strips as S  # noqa: E402
from exudyn_wheelrail.contact.patch_pass import SWITCH_HI, SWITCH_LO, hertz_miss  # noqa: E402

E_STAR = 2.1e11 / (2.0 * (1.0 - 0.3 ** 2))
DELTA = 5e-5

#: the targets of the patch against the exact half-space solution: normal force at a given penetration, patch area,
#: contact angle of the resultant (relative errors)
FORCE_TOL, AREA_TOL, ANGLE_TOL = 0.03, 0.10, 0.02


def hertz_grid(A, B, cells):
    """A grid of ``2 cells`` centres per axis over the interpenetration ellipse of δ = DELTA."""
    ax, by = math.sqrt(DELTA / A), math.sqrt(DELTA / B)
    x = -ax + (np.arange(2 * cells) + 0.5) * ax / cells
    y = -by + (np.arange(2 * cells) + 0.5) * by / cells
    return x, y, DELTA - A * x[None, :] ** 2 - B * y[:, None] ** 2


@pytest.mark.parametrize("A, B", [(1.0, 1.0), (0.5, 3.0)])
def test_halfspace_solution_is_hertz_within_the_grid_error(A, B):
    n, _, a, b, _ = hertz_from_penetration(A, B, E_STAR, DELTA, 0.0)
    x, y, d = hertz_grid(A, B, 16)
    sol = solve_halfspace(x, y, d, E_STAR)
    h = max(x[1] - x[0], y[1] - y[0])
    # the patch's edge is resolved to a cell: the area within the band of half a cell diagonal along the perimeter
    # (Ramanujan's perimeter of the ellipse)
    perimeter = math.pi * (3 * (a + b) - math.sqrt((3 * a + b) * (a + 3 * b)))
    band = perimeter * 0.5 * math.hypot(x[1] - x[0], y[1] - y[0]) / (math.pi * a * b)
    assert sol.area_m2 == pytest.approx(math.pi * a * b, rel=band)
    # force and peak pressure: the pressure vanishes at the edge like √(distance), so the edge band's share of the
    # force is of order band^(3/2); collocation at the centres is second order in h inside
    assert sol.normal_force_N == pytest.approx(n, rel=band ** 1.5)
    assert sol.peak_pressure_Pa == pytest.approx(1.5 * n / (math.pi * a * b), rel=band ** 1.5 + (h / b) ** 2)
    # the pressure field itself: Hertz's at every cell centre within the edge band's error of p0
    p0 = 1.5 * n / (math.pi * a * b)
    X, Y = np.meshgrid(x, y)
    semi = np.sqrt(np.clip(1 - (X / a) ** 2 - (Y / b) ** 2, 0, None))
    assert np.abs(sol.pressure_Pa - p0 * semi).max() < p0 * math.sqrt(2.5 * band)


def test_halfspace_solution_meets_the_contact_conditions():
    """No tension, and no interpenetration anywhere: the displacement recomputed from Boussinesq's point load
    (each cell's force at its centre, a cell's own contribution from the exact integral over a square) is at least
    the interpenetration at every centre, equal to it where loaded (within the point-load sum's error)."""
    x, y, d = hertz_grid(0.7, 2.0, 10)
    sol = solve_halfspace(x, y, d, E_STAR)
    assert (sol.pressure_Pa >= 0).all()
    dx, dy = x[1] - x[0], y[1] - y[0]
    X, Y = np.meshgrid(x, y)
    force = sol.pressure_Pa * dx * dy
    u = np.zeros_like(d)
    # own cell: ∬ 1/r over a dx × dy rectangle from its centre
    own = 2 * (dx * math.asinh(dy / dx) + dy * math.asinh(dx / dy))
    for j in range(y.size):
        for i in range(x.size):
            r = np.hypot(X - x[i], Y - y[j])
            r[j, i] = np.inf
            u[j, i] = (np.sum(force / r) + sol.pressure_Pa[j, i] * own) / (math.pi * E_STAR)
    loaded = sol.pressure_Pa > 0
    assert np.abs(u[loaded] - d[loaded]).max() < 0.03 * DELTA
    assert (u[~loaded] - d[~loaded]).min() > -0.03 * DELTA


@pytest.mark.parametrize("A, B", [(1.0, 0.2), (1.0, 1.0), (1.0, 8.0)])
def test_strips_give_hertz_on_quadratic_geometry(A, B):
    """g = δ - B η², A constant: the strip method's fixed points are Hertz's ellipse and pressure (module
    docstring); the strips' discretisation is the only error (32 strips over the overlap: 0.1–1 %)."""
    n, _, a, b, _ = hertz_from_penetration(A, B, E_STAR, DELTA, 0.0)
    half = math.sqrt(DELTA / B)
    eta = -half + (np.arange(32) + 0.5) * half / 16
    g = DELTA - B * eta ** 2
    sol = P.solve_strips(eta, eta[1] - eta[0], g, np.full(32, A), 0.01 * eta / half, E_STAR)
    # the patch's lateral edge is resolved to half a strip: the area within that band, the force and the peak
    # within its 3/2 power (the pressure vanishes like √(distance) at the edge), as for the grid above
    band = 0.5 * (eta[1] - eta[0]) / b
    assert sol.epsilon == pytest.approx(b * b * B / DELTA, rel=band)
    assert sol.normal_force_N == pytest.approx(n, rel=band ** 1.5)
    assert sol.area_m2 == pytest.approx(math.pi * a * b, rel=band)
    assert sol.peak_pressure_Pa == pytest.approx(1.5 * n / (math.pi * a * b), rel=band ** 1.5)
    # symmetric geometry, antisymmetric angles: the resultant is upright
    assert abs(sol.contact_angle_rad) < 1e-9


@pytest.mark.parametrize("s", [-3e5, -40.0, -1.0, -1e-3, 0.0, 2e-7, 3e-6, 0.07, 0.5, 2.0, 17.0, 900.0, 2e5])
def test_strip_function_against_quadrature(s):
    """H(s) = ∫₀^{π/2} cos²θ asinh(s/sin θ) dθ: table and expansions against adaptive quadrature (the table's
    Hermite error ~1e-9 relative; the expansions' at their ends ~s³ and ~1/s²)."""
    ref = quad(lambda t: math.cos(t) ** 2 * math.asinh(s / math.sin(t)), 0.0, math.pi / 2, limit=400,
               epsabs=1e-14, epsrel=1e-12)[0]
    assert P.strip_h(s) == pytest.approx(ref, rel=1e-8, abs=1e-13)


@pytest.mark.parametrize("xl, j, k", [(1e-3, 3, 3), (1e-3, 5, 3), (2e-4, 0, 6), (4e-3, 6, 5)])
def test_strip_influence_against_the_boussinesq_integral(xl, j, k):
    """C[j, k] against the integral of the semi-elliptic strip pressure over 1/r: across the strip by the
    antiderivative asinh (textbook), along it by adaptive quadrature (its logarithmic end point at x = 0 for the own
    strip handled by QUADPACK's extrapolation), instead of the table of H and the Gauss rule."""
    n, width, e_star = 8, 5e-4, 1.1e11
    lengths = np.full(n, 1e-3)
    lengths[k] = xl
    C = np.zeros((n, n))
    P.strip_influence(n, width, lengths, e_star, C)
    e = (j - k) * width

    def across(x):                           # ∫ over the strip's width of 1/√(x² + (e - η)²) dη, times the pressure
        return math.sqrt(max(1 - (x / xl) ** 2, 0.0)) * (math.asinh((e + 0.5 * width) / x)
                                                         - math.asinh((e - 0.5 * width) / x))

    ref = 2.0 * quad(across, 0.0, xl, epsabs=1e-14, epsrel=1e-10, limit=200)[0] / (math.pi * e_star)
    assert C[j, k] == pytest.approx(ref, rel=1e-5)


@pytest.fixture(scope="module")
def a22_contact():
    return A22.build_contact()


#: the exact solution's strips (rows of cells) across the overlap
REFERENCE_STRIPS = 64


def compare(contact, y_m, n_x=48):
    """The right wheel's contacts of the S1002/UIC60 wheelset at lateral shift ``y_m`` under 10 kN per wheel
    (Hertz's pose, no yaw): per contact (the patch at the default strip count, the exact solution on
    REFERENCE_STRIPS strips, its angle, the kernel row)."""
    res = solve_quasi_static(contact, y_m, 0.0, A22.WHEEL_LOAD_N, A22.SPEED_M_S, mu=A22.MU,
                             shear_modulus_Pa=A22.SHEAR_MODULUS_PA, poisson=A22.POISSON, creep_law="fastsim")
    out = contact.evaluate(np.array([[y_m, res.z_m, res.roll_rad]]))
    pose = contact.side_poses(contact.poses)[0].copy()
    cases = []
    for slot in range(K.N_SLOTS):
        row = out[0, slot].copy()
        if row[K.F_STATUS] > 0 and row[K.F_NORMAL_FORCE] > 0:
            args = (contact.nodes, contact.meta, contact.curve_ids[0], row, pose, 0.0, contact.E_star)
            _, ref, angle = P.exact_of_contact(*args, n_strips=REFERENCE_STRIPS, n_x=n_x)
            _, sol = P.patch_of_contact(*args)
            cases.append((sol, ref, angle, row))
    return cases


def test_patch_on_the_conformal_tread_against_the_exact_solution(a22_contact):
    """The centred S1002/UIC60 wheelset: one overlap zone 18 mm wide with two humps.  Hertz is visibly wrong there
    (force and area at the given penetration, contact angle of the resultant); the patch is within the targets."""
    (sol, ref, angle, row), = compare(a22_contact, 0.0, n_x=32)
    assert sol.normal_force_N == pytest.approx(ref.normal_force_N, rel=FORCE_TOL)
    assert sol.area_m2 == pytest.approx(ref.area_m2, rel=AREA_TOL)
    assert sol.contact_angle_rad == pytest.approx(angle, rel=ANGLE_TOL)
    hertz_area = math.pi * row[K.F_SEMI_A] * row[K.F_SEMI_B]
    assert row[K.F_NORMAL_FORCE] < 0.9 * ref.normal_force_N
    assert hertz_area < 0.8 * ref.area_m2
    assert row[K.F_CONTACT_ANGLE] < 0.85 * angle


#: lateral shifts of the wheelset [mm]: the conformal tread (-3 ... 1 mm), the tread (2, 4), the two-point contact
#: (5), the flange (7, 9)
POSITIONS_MM = (-3.0, -1.0, 0.0, 0.5, 1.0, 2.0, 4.0, 5.0, 7.0, 9.0)


@pytest.mark.validation
@pytest.mark.parametrize("y_mm", POSITIONS_MM)
def test_patch_against_the_exact_solution_at_ten_positions(a22_contact, y_mm):
    for sol, ref, angle, _ in compare(a22_contact, y_mm * 1e-3):
        assert sol.normal_force_N == pytest.approx(ref.normal_force_N, rel=FORCE_TOL)
        assert sol.area_m2 == pytest.approx(ref.area_m2, rel=AREA_TOL)
        assert sol.contact_angle_rad == pytest.approx(angle, rel=ANGLE_TOL)


# ------------------------------------------------------------------------------------------------ the pass
@pytest.fixture(scope="module")
def a22_patch_contact():
    return A22.build_contact("non-hertzian")


def right_wheel(contact, y_m, z_m, roll=0.0):
    out = contact.evaluate(np.array([[y_m, z_m, roll]]))
    return out[0].copy(), contact.side_poses(contact.poses)[0].copy()


def hertz_pose(contact, y_m):
    res = solve_quasi_static(contact, y_m, 0.0, A22.WHEEL_LOAD_N, A22.SPEED_M_S, mu=A22.MU,
                             shear_modulus_Pa=A22.SHEAR_MODULUS_PA, poisson=A22.POISSON, creep_law="fastsim")
    return res.z_m, res.roll_rad


def test_pass_writes_the_patch_resultant_where_hertz_misses(a22_contact, a22_patch_contact):
    """The centred wheelset (Hertz misses the overlap at its ellipse's edge by 25 % of δ): the pass's row is the
    patch of :func:`patch_of_contact` at the pass's strip count — force, contact angle of the resultant, the
    equivalent ellipse — and the normal is that angle's; the kernel's row (Hertz) is left where Hertz holds."""
    z, roll = hertz_pose(a22_contact, 0.0)
    hertz_rows, pose = right_wheel(a22_contact, 0.0, z, roll)
    rows, _ = right_wheel(a22_patch_contact, 0.0, z, roll)
    row = rows[K.SLOT_TREAD]
    assert int(row[K.F_FLAGS]) & K.FLAG_PATCH
    _, sol = P.patch_of_contact(a22_contact.nodes, a22_contact.meta, a22_contact.curve_ids[0],
                                hertz_rows[K.SLOT_TREAD], pose, 0.0, a22_contact.E_star,
                                n_strips=int(a22_patch_contact.patch[0][0][0]))
    assert row[K.F_NORMAL_FORCE] == pytest.approx(sol.normal_force_N, rel=1e-9)
    assert row[K.F_CONTACT_ANGLE] == pytest.approx(sol.contact_angle_rad, rel=1e-9)
    assert (row[K.F_SEMI_A], row[K.F_SEMI_B]) == pytest.approx(sol.equivalent_ellipse(), rel=1e-9)
    assert np.arctan2(-row[K.F_NR_Y], -row[K.F_NR_Z]) == pytest.approx(row[K.F_CONTACT_ANGLE], abs=1e-12)
    assert row[K.F_PENETRATION] == hertz_rows[K.SLOT_TREAD, K.F_PENETRATION]
    # one zone, one loaded contact on the wheel
    loaded = [s for s in range(K.N_SLOTS) if rows[s, K.F_STATUS] > 0 and rows[s, K.F_NORMAL_FORCE] > 0]
    assert loaded == [K.SLOT_TREAD]
    # the flange at 9 mm: Hertz holds (D = 0), the row is the kernel's
    z, roll = hertz_pose(a22_contact, 9e-3)
    h9, _ = right_wheel(a22_contact, 9e-3, z, roll)
    p9, _ = right_wheel(a22_patch_contact, 9e-3, z, roll)
    np.testing.assert_array_equal(p9, h9)


def test_switch_blends_continuously(a22_contact, a22_patch_contact):
    """Across the switch: the tread at y = 1.5 mm pressed from 15 to 40 µm (Hertz's miss D rises from below
    SWITCH_LO to above SWITCH_HI).  Normal force, contact angle and the point move smoothly: no step is more than
    6 x the mean step of the sweep (the blend's smoothstep spends its change over ~40 of the 120 steps: its
    steepest step is ~4.5 x the mean; a jump would put the whole change, 120 x the mean, into one step)."""
    z, roll = hertz_pose(a22_contact, 1.5e-3)
    fields = (K.F_NORMAL_FORCE, K.F_CONTACT_ANGLE, K.F_PR_Y)
    patch, miss = [], []
    for dz in np.linspace(-10e-6, 15e-6, 121):
        h, pose = right_wheel(a22_contact, 1.5e-3, z + dz, roll)
        p, _ = right_wheel(a22_patch_contact, 1.5e-3, z + dz, roll)
        patch.append(p[K.SLOT_TREAD, fields])
        c = math.cos(pose[2]), math.sin(pose[2])
        miss.append(hertz_miss(a22_contact.nodes, a22_contact.meta, 0, 1, 2, pose[0], pose[1], c[0], c[1],
                               h[K.SLOT_TREAD], 0.0, np.zeros(S.N_STRIP_FIELDS)))
        assert bool(int(p[K.SLOT_TREAD, K.F_FLAGS]) & K.FLAG_PATCH) == (miss[-1] > SWITCH_LO)
    assert miss[0] < SWITCH_LO and miss[-1] > SWITCH_HI          # the sweep crosses the whole switch
    steps = np.abs(np.diff(np.array(patch), axis=0))
    assert (steps.max(axis=0) <= 6.0 * steps.mean(axis=0)).all(), steps.max(axis=0) / steps.mean(axis=0)
    # the patch moved the contact: its angle and point differ from Hertz's at the deep end
    assert abs(patch[-1][1] - h[K.SLOT_TREAD, K.F_CONTACT_ANGLE]) > 1e-4


def test_a22_example_with_the_patch(tmp_path):
    """--contact-patch non-hertzian: the same columns; each wheel still carries 10 kN (the quasi-static balance
    with the patch's forces); at y = 0 the contact angle is the patch's resultant's, above Hertz's single point."""
    out_h, out_p = tmp_path / "h.csv", tmp_path / "p.csv"
    assert A22.main(["--out", str(out_h), "--y-mm", "0"]) == 0
    assert A22.main(["--out", str(out_p), "--y-mm", "0", "--contact-patch", "non-hertzian"]) == 0
    rows = {}
    for name, path in (("h", out_h), ("p", out_p)):
        with open(path, newline="") as fh:
            reader = csv.DictReader(fh)
            assert tuple(reader.fieldnames) == A22.COLUMNS + A22.EXTRA_COLUMNS
            rows[name] = list(reader)
    for r in rows["p"]:
        assert float(r["vertical_force_N"]) == pytest.approx(A22.WHEEL_LOAD_N, abs=0.05)
        assert "patch" in r["flags"]
    angle = {k: float(v[0]["contact_angle_rad"]) for k, v in rows.items()}
    assert angle["p"] > 1.15 * angle["h"]


def test_contact_patch_option_is_checked():
    with pytest.raises(ValueError, match="contact_patch='elliptic'"):
        A22.build_contact("elliptic")
    from exudyn_wheelrail.simulation.settings import ContactSettings, SettingsError
    with pytest.raises(SettingsError, match="contact_patch"):
        ContactSettings(contact_patch="elliptic")


# ------------------------------------------------------------------------------------------------ the table
SMALL_GRID = dict(y_min_m=-0.6e-3, y_max_m=0.6e-3, dy_m=0.1e-3, roll_min_rad=-0.5e-3, roll_max_rad=0.5e-3)


@pytest.fixture(scope="module")
def tabulated():
    from exudyn_wheelrail.contact.patch_table import PatchTableGrid
    contact = A22.build_contact("non-hertzian")
    grid = PatchTableGrid(droll_rad=0.25e-3, **SMALL_GRID)
    return contact, contact.use_patch_table(grid), grid


def test_table_is_the_pass_at_its_nodes(a22_contact, a22_patch_contact, tabulated):
    """At a node and a tabulated height the table returns the pass's own row (force through exp/log: 1e-12)."""
    from exudyn_wheelrail.contact.patch_table import PT_DELTA
    contact, table, grid = tabulated
    ys, rolls, deltas = grid.axes()
    i, j = 6, 2                                      # c_y = 0, roll = 0
    for m in (2, 5):
        # the height of that node and penetration: found again from the tabulated penetration of the deepest slot
        target = table.data[i, j, m, K.SLOT_TREAD, PT_DELTA]
        z = -0.46
        for _ in range(30):
            out = a22_contact.evaluate(np.array([[ys[i], z, rolls[j]]]))
            z += (target - out[0, K.SLOT_TREAD, K.F_PENETRATION]) / -out[0, K.SLOT_TREAD, K.F_NR_Z]
        direct, _ = right_wheel(a22_patch_contact, ys[i], z, rolls[j])
        tab, _ = right_wheel(contact, ys[i], z, rolls[j])
        for f in (K.F_NORMAL_FORCE, K.F_CONTACT_ANGLE, K.F_PR_Y, K.F_PR_Z, K.F_SEMI_A, K.F_SEMI_B, K.F_ROLLING_RADIUS):
            assert tab[K.SLOT_TREAD, f] == pytest.approx(direct[K.SLOT_TREAD, f], rel=1e-7, abs=1e-12), f


def test_table_converges_to_the_pass_between_its_nodes(a22_contact, a22_patch_contact, tabulated):
    """Between the nodes the force's error against the pass: at lateral offsets on the nodes and rolls midway
    between the finer grid's nodes it falls by more than half when the roll step is halved (linear interpolation:
    to about a third at these points, by h²); over random poses of the finer table it stays below 1 % RMS."""
    from exudyn_wheelrail.contact.patch_table import PatchTableGrid
    from exudyn_wheelrail.analysis.geometry_functions import solve_rigid_contact
    fine_contact, _, grid = tabulated
    coarse_contact = A22.build_contact("non-hertzian")
    coarse_contact.use_patch_table(PatchTableGrid(droll_rad=0.5e-3, **SMALL_GRID))
    ys = grid.axes()[0]
    rng = np.random.default_rng(7)
    errors = {"coarse": [], "fine": [], "random": []}
    for k in range(80):
        on_nodes = k < 40
        y = ys[rng.integers(1, ys.size - 1)] if on_nodes else rng.uniform(-0.55e-3, 0.55e-3)
        rigid = solve_rigid_contact(a22_contact, y)
        z = rigid.z_m + rng.uniform(10e-6, 50e-6)
        roll = 0.125e-3 * rng.choice([-1.0, 1.0]) if on_nodes else rng.uniform(-0.45e-3, 0.45e-3)
        direct, _ = right_wheel(a22_patch_contact, y, z, roll)
        for name, c in ((("coarse", coarse_contact), ("fine", fine_contact)) if on_nodes else
                        (("random", fine_contact),)):
            tab, _ = right_wheel(c, y, z, roll)
            for s in range(K.N_SLOTS):
                if direct[s, K.F_STATUS] > 0 and direct[s, K.F_NORMAL_FORCE] > 1e3:
                    errors[name].append(tab[s, K.F_NORMAL_FORCE] / direct[s, K.F_NORMAL_FORCE] - 1.0)
    rms = {k: float(np.sqrt(np.mean(np.square(v)))) for k, v in errors.items()}
    assert rms["fine"] < 0.5 * rms["coarse"], rms
    assert rms["random"] < 0.01, rms


def _slot_codes(table, grid, y, roll, slot, delta):
    """The codes of ``slot`` at the two heights bracketing ``delta`` at the four nodes around (y, roll)."""
    from exudyn_wheelrail.contact.patch_table import PT_CODE, PT_DELTA
    ys, rolls, _ = grid.axes()
    i = min(int((y - ys[0]) / grid.dy_m), ys.size - 2)
    j = min(int((roll - rolls[0]) / grid.droll_rad), rolls.size - 2)
    codes = set()
    for a in (0, 1):
        for b in (0, 1):
            col = table.data[i + a, j + b, :, slot]
            m = 0
            while m < col.shape[0] - 2 and col[m + 1, PT_DELTA] < delta:
                m += 1
            codes.update((float(col[m, PT_CODE]), float(col[m + 1, PT_CODE])))
    return codes


def test_table_answers_a_zone_merging_between_its_nodes(a22_contact, a22_patch_contact, tabulated):
    """The kernel's second tread maximum inside the first one's zone: where its slot has no force of its own at any
    of the cell's nodes (merged into the first at some, absent at the others), the table answers — the slot is the
    zone's tail (merged, no force) and the first slot's interpolated resultant is the whole zone's.  Against the pass
    solved online at the same random poses (about one in six has such a cell): the wheel's normal force within the
    table's own accuracy (1 % RMS, as between its nodes), and each answer the table's, not the online pass's."""
    from exudyn_wheelrail.analysis.geometry_functions import solve_rigid_contact
    from exudyn_wheelrail.contact.patch_table import CODE_MERGED, CODE_NONE
    contact, table, grid = tabulated
    rng = np.random.default_rng(3)
    errors = []
    for _ in range(200):
        y, roll = rng.uniform(-0.55e-3, 0.55e-3), rng.uniform(-0.45e-3, 0.45e-3)
        z = solve_rigid_contact(a22_contact, y).z_m + rng.uniform(10e-6, 50e-6)
        hertz, _ = right_wheel(a22_contact, y, z, roll)
        second = hertz[K.SLOT_TREAD_2]
        if not (second[K.F_STATUS] > 0 and second[K.F_NORMAL_FORCE] > 0.0):
            continue
        if _slot_codes(table, grid, y, roll, K.SLOT_TREAD_2, second[K.F_PENETRATION]) != {CODE_NONE, CODE_MERGED}:
            continue
        direct, _ = right_wheel(a22_patch_contact, y, z, roll)
        tab, _ = right_wheel(contact, y, z, roll)
        assert tab[K.SLOT_TREAD_2, K.F_STATUS] == K.STATUS_MERGED and tab[K.SLOT_TREAD_2, K.F_NORMAL_FORCE] == 0.0
        assert not np.array_equal(tab, direct)
        loaded = (tab[:, K.F_STATUS] > 0), (direct[:, K.F_STATUS] > 0)
        errors.append(tab[loaded[0], K.F_NORMAL_FORCE].sum() / direct[loaded[1], K.F_NORMAL_FORCE].sum() - 1.0)
    assert len(errors) >= 10, len(errors)
    assert float(np.sqrt(np.mean(np.square(errors)))) < 0.01, errors


def test_two_contacts_of_one_zone_are_one_patch(a22_contact, a22_patch_contact):
    """y = 0.2 mm (Hertz's pose): the kernel reports two tread contacts of one overlap zone (its two maxima, 7.1 and
    2.9 kN).  The pass makes them one patch: the deepest row carries the zone's patch (as patch_of_contact of that
    row), the other is merged with no force; the patch is not the sum of two patches."""
    z, roll = hertz_pose(a22_contact, 0.2e-3)
    hertz, pose = right_wheel(a22_contact, 0.2e-3, z, roll)
    rows, _ = right_wheel(a22_patch_contact, 0.2e-3, z, roll)
    loaded = [s for s in range(K.N_SLOTS) if hertz[s, K.F_STATUS] > 0 and hertz[s, K.F_NORMAL_FORCE] > 0]
    assert loaded == [K.SLOT_TREAD, K.SLOT_TREAD_2]
    deep, shallow = sorted(loaded, key=lambda s: -hertz[s, K.F_PENETRATION])
    assert rows[shallow, K.F_STATUS] == K.STATUS_MERGED and rows[shallow, K.F_NORMAL_FORCE] == 0.0
    _, sol = P.patch_of_contact(a22_contact.nodes, a22_contact.meta, a22_contact.curve_ids[0], hertz[deep], pose,
                                0.0, a22_contact.E_star, n_strips=int(a22_patch_contact.patch[0][0][0]))
    assert rows[deep, K.F_NORMAL_FORCE] == pytest.approx(sol.normal_force_N, rel=1e-9)
    assert sol.lateral_extent_m[0] < 0.0 < sol.lateral_extent_m[1]
