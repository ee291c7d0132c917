"""The 3-D view (exudyn_wheelrail.interactive.view3d, shapes, screenshot, headless).

References, independent of the code under test:

* the profiles themselves (the wheel's tape-circle radius r0 and flange-tip radius, the rail top at z = 0, the
  nominal UIC60 height 172 mm), and the right-hand rule for the mesh normals;
* the connector's own results (``contact.results``: the contact points the scene must put a sphere on), read
  through Exudyn's ``SC.renderer.GetGraphicsData()`` — what the renderer would draw, without a window;
* pixels of frames rendered by Exudyn's OpenGL renderer under Xvfb (skipped without Xvfb): image size, not
  uniform, the contact colour (magenta, reserved for contacts and arrows) present with contact forces shown and
  absent without.
"""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from exudyn_wheelrail.contact import WheelRailPair
from exudyn_wheelrail.interactive import shapes
from exudyn_wheelrail.interactive.headless import VirtualDisplay, xvfb_available
from exudyn_wheelrail.interactive.view3d import CONTACT_RGBA, WheelRailView, view_rotation
from exudyn_wheelrail.multibody import connector as C
from exudyn_wheelrail.scenarios.rtri import RtriCase
from exudyn_wheelrail.scenarios.scenario import build_scenario, run_model

REPO = Path(__file__).resolve().parents[1]
PAIR = WheelRailPair("S1002", "UIC60", inclination="1/40")


# ------------------------------------------------------------------------------------------------- shapes
def test_rail_section_is_the_placed_head_on_a_uic60_body():
    sec = shapes.rail_section(PAIR)
    assert shapes.signed_area(sec) > 0.0
    assert sec[:, 1].min() == pytest.approx(0.0, abs=1e-6)                 # rail top at z = 0
    assert sec[:, 1].max() == pytest.approx(shapes.RAIL_HEIGHT_M)           # foot at 172 mm
    head = sec[sec[:, 1] < 0.014]                                           # above the gauge-measuring depth
    assert head[:, 0].min() == pytest.approx(PAIR.gauge_m / 2, abs=2e-3)     # gauge face near gauge/2
    # area of a UIC60 section is 76.7 cm^2; the simplified web/foot must be of that order
    assert 0.005 < shapes.signed_area(sec) < 0.010
    left = shapes.mirror_section(sec)
    assert shapes.signed_area(left) > 0.0 and left[:, 0].max() < 0.0


def test_wheel_contour_follows_the_wheel_profile():
    c = shapes.wheel_contour(PAIR)
    assert np.allclose(c[0], c[-1])                                         # closed
    curve = PAIR.wheel.curve                                                # profile frame: z = radius increase
    tip = PAIR.r0_m + curve.position(np.linspace(curve.s_min, curve.s_max, 4001))[:, 1].max()
    assert c[:, 1].max() == pytest.approx(tip, abs=3e-4)                     # flange tip radius
    tape = PAIR.wheel_offset_y_m                                            # tape circle: radius r0
    outer = c[1:-6]
    assert np.interp(tape, outer[:, 0], outer[:, 1]) == pytest.approx(PAIR.r0_m, abs=1e-5)
    assert c[:, 1].min() == pytest.approx(shapes.WHEEL_HUB_RADIUS_M)


def test_swept_mesh_normals_point_out_of_the_section():
    sec = shapes.rectangle_section(-1.0, 1.0, 0.5, 1.5)
    x = np.linspace(0.0, 2.0, 5)
    pts, tri = shapes.swept_mesh(sec, x, dy_m=0.1 * x, dz_m=np.zeros_like(x))
    assert pts.shape == (5 * 4, 3) and tri.shape == (2 * 4 * 4, 3)
    p0, p1, p2 = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    n = np.cross(p1 - p0, p2 - p0)
    centre = np.stack([(p0[:, 0] + p1[:, 0] + p2[:, 0]) / 3, 0.1 * (p0[:, 0] + p1[:, 0] + p2[:, 0]) / 3,
                       np.full(len(tri), 1.0)], -1)                          # section centre at that x
    out = (p0 + p1 + p2) / 3 - centre
    assert np.all(np.einsum("ij,ij->i", n, out) > 0.0)
    assert pts[:, 1].max() == pytest.approx(1.0 + 0.2)                       # lateral offset applied


def test_view_rotation_is_proper_and_puts_up_on_top():
    R = view_rotation(35.0, 20.0)
    assert np.allclose(R @ R.T, np.eye(3)) and np.linalg.det(R) == pytest.approx(1.0)
    up = R @ np.array([0.0, 0.0, -1.0])                                      # model "up" is -z
    assert up[1] > 0.9                                                       # screen y
    side = view_rotation(0.0, 0.0)
    assert np.allclose(side @ [1.0, 0.0, 0.0], [1.0, 0.0, 0.0])              # forward runs to the right


# ----------------------------------------------------------------------------------- scene without a window
@pytest.fixture(scope="module")
def rtri_view():
    case = RtriCase(duration_s=0.3)             # 0.3 s: the leading wheelset is on the deviation (250 km/h)
    h = build_scenario(case.scenario())
    view = WheelRailView.for_rtri(h)
    assert run_model(h, progress=False).status.ok
    h.case = case
    return h, view


def test_graphics_data_has_a_contact_sphere_on_every_contact_point(rtri_view):
    h, view = rtri_view
    res = view.show_current_state()
    active = (res[:, :, C.RES_STATUS] > 0) & (res[:, :, C.RES_N] > 0.0)
    points = res[active][:, C.RES_P_X:C.RES_P_Z + 1]
    assert len(points) >= 8
    sp = h.system_container.renderer.GetGraphicsData()["spheres"]
    magenta = np.all(np.isclose(sp["colors"], CONTACT_RGBA, atol=1e-6), axis=1)
    drawn = np.asarray(sp["points"])[magenta]
    assert len(drawn) == len(points)
    d = np.linalg.norm(drawn[:, None, :] - points[None, :, :], axis=-1)
    assert np.all(d.min(axis=1) < 1e-5) and np.all(d.min(axis=0) < 1e-5)
    # arrows: magenta triangles reaching from each contact point along the force of the rail on the wheel
    tri = h.system_container.renderer.GetGraphicsData(flatShapes=True)["triangles"]
    mag = np.all(np.isclose(tri["colors"], CONTACT_RGBA, atol=1e-6), axis=(1, 2))
    arrow_pts = np.asarray(tri["points"])[mag].reshape(-1, 3)
    F = res[active][:, C.RES_F_TRACK_X:C.RES_F_TRACK_Z + 1]
    tips = points + view.options.force_scale_m_per_N * F
    assert np.all(np.linalg.norm(arrow_pts[:, None, :] - tips[None, :, :], axis=-1).min(axis=0) < 1e-3)
    view.show_contact_forces = False
    try:
        gd = h.system_container.renderer.GetGraphicsData(flatShapes=True)
        assert not np.any(np.all(np.isclose(gd["spheres"]["colors"], CONTACT_RGBA, atol=1e-6), axis=1))
        assert not np.any(np.all(np.isclose(gd["triangles"]["colors"], CONTACT_RGBA, atol=1e-6), axis=(1, 2)))
    finally:
        view.show_contact_forces = True


def test_rails_carry_the_span_deflection_under_the_wheelset(rtri_view):
    h, view = rtri_view
    t = float(h.mbs.systemData.GetTime())
    x_lead = h.model.wheelsets[0].p_cg_in_frame[0]
    dy, dz = view.rail_offsets_m([x_lead], t)
    s = h.model.track_distance_m(x_lead, t)
    expected = h.case.span_deflection().evaluate(np.array([s])).y_m[0]
    assert dy[0] == pytest.approx(expected, abs=1e-12) and expected > 5e-3   # on the span at t = 0.3 s
    rails = view.rail_graphics(t)
    y = np.asarray(rails[0]["points"]).reshape(-1, 3)
    near = np.abs(y[:, 0] - x_lead) < 0.26                                   # the station under the wheelset
    assert y[near, 1].max() == pytest.approx(shapes.rail_section(PAIR)[:, 0].max() + expected, abs=0.02 * expected
                                             + 2e-4)


# --------------------------------------------------------------------------------------- screenshot (Xvfb)
def _contact_pixels(img):
    """Pixels of the contact colour (magenta, shaded): red and blue high and alike, green low."""
    rgb = img[..., :3].astype(float)
    if rgb.max() <= 1.0:
        rgb = rgb * 255.0
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return (r > 90) & (b > 90) & (g < 0.55 * np.minimum(r, b)) & (np.abs(r - b) < 50)


@pytest.mark.skipif(not xvfb_available(), reason="Xvfb is not installed (apt-get install xvfb): the OpenGL renderer "
                                                 "needs an X display; the screenshot check is skipped")
def test_screenshot_under_xvfb_shows_contact_forces_only_when_switched_on(tmp_path):
    import matplotlib.image as mpimg
    env_path = os.pathsep.join([str(REPO)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])
    with VirtualDisplay() as display:
        env = {**display.env(), "PYTHONPATH": env_path}
        r = subprocess.run([sys.executable, "-m", "exudyn_wheelrail.interactive.screenshot", "--out", str(tmp_path),
                            "--steps", "20", "--size", "640x480"], env=env, cwd=REPO, capture_output=True,
                           text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    info = json.loads(r.stdout.strip().splitlines()[-1])
    assert info["contacts_drawn"] >= 8
    with_c = mpimg.imread(info["with_contacts"])
    without = mpimg.imread(info["without_contacts"])
    for img in (with_c, without):
        assert img.shape[:2] == (480, 640)
        assert img[..., :3].std() > 0.05 * (255.0 if img.max() > 1.0 else 1.0)   # not blank / uniform
    n_with, n_without = int(_contact_pixels(with_c).sum()), int(_contact_pixels(without).sum())
    assert n_with >= 100, f"contact colour on {n_with} pixels only"
    assert n_without == 0, f"contact colour on {n_without} pixels with contact forces switched off"
    # the two frames differ only where the contact graphics are
    diff = np.any(np.abs(with_c[..., :3].astype(float) - without[..., :3].astype(float)) > 1e-6, axis=-1)
    assert diff.sum() < 0.05 * diff.size
