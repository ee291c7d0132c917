r"""Exudyn 3-D view of a wheel–rail model: wheels, rails, bridge deck, contact points and contact-force arrows.

>>> h = build_scenario(RtriCase(duration_s=0.2).scenario())                  # doctest: +SKIP
>>> view = WheelRailView.for_rtri(h)          # graphics added; re-assembles the system          # doctest: +SKIP
>>> view.configure(h.system_container)        # camera on the leading bogie                       # doctest: +SKIP
>>> h.system_container.renderer.Start(); h.mbs.SolveDynamic(h.settings, solverType=h.solver_type) # doctest: +SKIP

What is drawn (all in the model frame of :mod:`exudyn_wheelrail.rolling_stock.vehicle_builder`: the track frame —
x forward, y right, z **down** — translating with the running speed; the camera puts -z up)
---------------------------------------------------------------------------------------------------------------
* **wheels**: solids of revolution of the actual wheel profile in place (:func:`.shapes.wheel_contour`: flange and
  tread from the :class:`~exudyn_wheelrail.contact.WheelRailPair`, rim/web/hub simplified), attached to the
  wheelset bodies (so they move, roll, yaw and spin with them), with an axle and a dark marker on each web that
  shows the spin; drawn semi-transparent (``wheel_alpha``) so that the contact points and arrows inside stay
  visible;
* **rails**: the rail-head profile as placed by the pair with a simplified UIC60 web and foot
  (:func:`.shapes.rail_section`), swept along x over the vehicle plus ``rail_margin_m`` on each side; every station
  is displaced by the rails' displacement at its track distance ``s = s_start + V t + x``: the track irregularity
  (the RTRI span deflection), the bridge deck's rail displacement ``Φ(s) q`` and the support motion ``y_g(t)``,
  multiplied by ``deflection_scale`` (1 = true size; the bodies are not scaled, so use 1 when the wheels shall sit
  on the rails);
* **bridge deck** (with a bridge): a box of ``deck_width_m`` whose top lies ``track_bed_depth_m`` below the rail
  top and which is symmetric about the beam axis (``rail_height_m`` below the rail top), from abutment to
  abutment, displaced like the rails;
* **car body and bogie frames** (``show_bodies``): translucent boxes of stated, simplified size;
* **contact points and forces**: a sphere at every active contact point (per wheel and region: tread, flange,
  second tread zone) and an arrow of the total contact force **of the rail on the wheel** (normal + creep; the
  connector's ``RES_F_TRACK_*``) starting at the contact point, length ``force_scale_m_per_N`` × |F| — a wheel
  load of 55 kN is 0.28 m at the default 5e-6 m/N.  Both in :data:`CONTACT_RGBA` (magenta), a colour nothing else
  in the scene uses (the screenshot test looks for it).  ``show_contact_forces = False`` hides them.

Which contact state is drawn
----------------------------
The connector's last evaluation (``contact.results``, copied when the frame is built): during a solve that is the
solver's latest right-hand side or the recorder's evaluation — within one time step of the drawn state; after a
solve call :meth:`WheelRailView.show_current_state` to draw exactly the final state.  The frame function only
reads (``results.copy()``: one C-level copy under the GIL, the compiled contact call does not release the GIL),
so it never disturbs the solve; time and bridge coordinates come from the *visualization* state.

Cost: the frame function (rails swept in numpy, a sphere and an arrow per contact) takes ≈ 15 ms for the RTRI
model (measured, 8 contacts); Exudyn calls it at ``visualizationSettings.general.graphicsUpdateInterval`` (0.1 s
wall time) while solving.
"""
from __future__ import annotations

import math
import os
import sys
from dataclasses import dataclass

import numpy as np

from . import shapes

__all__ = ["CONTACT_RGBA", "ViewOptions", "WheelRailView", "RtriView", "view_rotation", "check_display"]

#: colour of contact points and force arrows (RGBA); nothing else in the scene is magenta
CONTACT_RGBA = (1.0, 0.0, 1.0, 1.0)
WHEEL_RGBA = (0.55, 0.57, 0.62, 0.5)
RAIL_RGBA = (0.45, 0.36, 0.30, 1.0)
DECK_RGBA = (0.72, 0.72, 0.68, 1.0)
CAR_RGBA = (0.20, 0.45, 0.75, 0.12)
BOGIE_RGBA = (0.35, 0.40, 0.45, 0.35)
MARK_RGBA = (0.12, 0.12, 0.12, 1.0)


@dataclass
class ViewOptions:
    """Drawing options (SI units)."""

    force_scale_m_per_N: float = 5e-6       #: arrow length per newton of contact force [m/N]
    contact_sphere_radius_m: float = 0.025
    arrow_radius_m: float = 0.015
    wheel_alpha: float = 0.5                 #: opacity of the wheels (contacts inside stay visible)
    rail_margin_m: float = 8.0               #: rails drawn this far beyond the outer wheelsets [m]
    rail_station_spacing_m: float = 0.5      #: sweep stations of the rails [m]
    deflection_scale: float = 1.0            #: drawing factor on rail/deck displacements (irregularity, deck)
    deck_width_m: float = 5.5
    track_bed_depth_m: float = 0.75          #: rail top to deck top (ballast, sleeper, rail) [m]
    deck_station_spacing_m: float = 1.0
    show_bodies: bool = True                 #: car body and bogie frames as translucent boxes
    wheel_tiles: int = 32

    def __post_init__(self):
        for name in ("force_scale_m_per_N", "contact_sphere_radius_m", "arrow_radius_m", "rail_station_spacing_m",
                     "deck_station_spacing_m", "deck_width_m"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0.0):
                raise ValueError(f"ViewOptions.{name} = {v!r}: expected a positive number")
        if not 0.0 < self.wheel_alpha <= 1.0:
            raise ValueError(f"ViewOptions.wheel_alpha = {self.wheel_alpha!r}: expected (0, 1]")
        if not (math.isfinite(self.deflection_scale) and self.deflection_scale >= 0.0):
            raise ValueError(f"ViewOptions.deflection_scale = {self.deflection_scale!r}: expected >= 0")


def view_rotation(azimuth_deg: float = 35.0, elevation_deg: float = 12.0) -> np.ndarray:
    """Rotation (3, 3) from the model frame (x forward, y right, z down) to Exudyn's view frame (x right on the
    screen, y up, z towards the viewer): seen from the right-hand side of the track (x to the right, -z up), then
    turned by ``azimuth_deg`` about the vertical (positive: the camera moves forward, towards +x) and raised by
    ``elevation_deg``.  Proper rotation (det = +1)."""
    side = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])   # columns: images of e_x, e_y, e_z
    a, e = math.radians(azimuth_deg), math.radians(elevation_deg)
    yaw = np.array([[math.cos(a), 0.0, -math.sin(a)], [0.0, 1.0, 0.0], [math.sin(a), 0.0, math.cos(a)]])
    pitch = np.array([[1.0, 0.0, 0.0], [0.0, math.cos(e), -math.sin(e)], [0.0, math.sin(e), math.cos(e)]])
    return pitch @ yaw @ side


def check_display() -> None:
    """Raise ``RuntimeError`` on Linux without an X/Wayland display: Exudyn's renderer (GLFW) aborts the whole
    process there instead of failing (measured, Exudyn 1.13.6)."""
    if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise RuntimeError("no display (DISPLAY is not set): Exudyn's renderer needs one; run under Xvfb "
                           "(exudyn_wheelrail.interactive.headless.VirtualDisplay) or use the headless outputs")


def _triangles(points, triangles, rgba):
    import exudyn.graphics as gr
    return gr.FromPointsAndTrigs(points, triangles, color=list(rgba))


class WheelRailView:
    """Graphics of a vehicle model with its wheel–rail contact (module docstring).

    Parameters
    ----------
    mbs : the Exudyn ``MainSystem``.  The view adds body graphics and one ground object with a
        ``graphicsDataUserFunction``; call ``mbs.Assemble()`` afterwards (:meth:`for_rtri` does).
    model : the :class:`~exudyn_wheelrail.rolling_stock.vehicle_builder.VehicleModel`.
    pair : the :class:`~exudyn_wheelrail.contact.WheelRailPair` of the contact.
    contact : the :class:`~exudyn_wheelrail.multibody.connector.WheelRailContact` (its ``results`` are drawn).
    track : the :class:`~exudyn_wheelrail.track.rigid.RigidStraightTrack` (irregularity) or ``None``.
    bridge : an :class:`~exudyn_wheelrail.structures.bridge_exudyn.ExudynBridge` or ``None``.
    """

    def __init__(self, mbs, model, pair, contact, *, track=None, bridge=None, options: ViewOptions | None = None):
        import exudyn as exu
        import exudyn.graphics as gr

        self.exu = exu
        self.gr = gr
        self.mbs = mbs
        self.model = model
        self.pair = pair
        self.contact = contact
        self.track = track
        self.bridge = bridge
        self.options = options or ViewOptions()
        #: draw contact points and force arrows (toggle at any time)
        self.show_contact_forces = True
        self._results = None            # frozen results (show_current_state) or None: read contact.results
        o = self.options
        x_ws = np.array([ws.p_cg_in_frame[0] for ws in model.wheelsets])
        x0, x1 = float(x_ws.min()) - o.rail_margin_m, float(x_ws.max()) + o.rail_margin_m
        n = max(2, int(math.ceil((x1 - x0) / o.rail_station_spacing_m)) + 1)
        self.rail_x_m = np.linspace(x0, x1, n)
        right = shapes.rail_section(pair)
        self.rail_sections = (right, shapes.mirror_section(right))
        self._static_rails = None
        self._add_body_graphics()
        self.ground = mbs.CreateGround(name="wheel_rail_view", graphicsDataUserFunction=self._frame, show=True)

    # ------------------------------------------------------------------------------------------ construction
    @classmethod
    def for_rtri(cls, h, options: ViewOptions | None = None) -> "WheelRailView":
        """The view of a built vehicle model (:func:`~exudyn_wheelrail.scenarios.scenario.build_scenario`, e.g. of
        an :class:`~exudyn_wheelrail.scenarios.rtri.RtriCase`'s spec); re-assembles."""
        if h.contact is None:
            raise ValueError("the model has no contact (wheel_rail='springs'): nothing to view")
        view = cls(h.mbs, h.model, h.pair, h.contact, track=h.track, options=options)
        h.mbs.Assemble()
        return view

    def _add_body_graphics(self):
        gr, mbs, o = self.gr, self.mbs, self.options
        contour = shapes.wheel_contour(self.pair).tolist()
        wheel_rgba = list(WHEEL_RGBA[:3]) + [o.wheel_alpha]
        for ws in self.model.wheelsets:
            bc = ws.contact_semi_spacing_m
            g = [gr.SolidOfRevolution([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], contour, color=wheel_rgba,
                                      nTiles=o.wheel_tiles),
                 gr.SolidOfRevolution([0.0, 0.0, 0.0], [0.0, -1.0, 0.0], contour, color=wheel_rgba,
                                      nTiles=o.wheel_tiles),
                 gr.Cylinder([0.0, -bc, 0.0], [0.0, 2.0 * bc, 0.0], radius=0.08, color=list(WHEEL_RGBA[:3]) + [1.0],
                             nTiles=16)]
            for sign in (1.0, -1.0):                     # spin markers on the webs, towards -z at the start
                g.append(gr.Brick([0.0, sign * (bc - 0.005), -0.25], [0.05, 0.05, 0.2], color=list(MARK_RGBA)))
            mbs.SetObjectParameter(ws.body, "VgraphicsData", g)
            mbs.SetObjectParameter(ws.body, "Vshow", True)
        if not o.show_bodies:
            return
        v = self.model.vehicle
        for bg in self.model.bogies:
            a = v.geometry.semi_wheelbase_m or 1.3
            b1 = v.geometry.primary_lateral_semi_spacing_m
            g = [gr.Brick([0.0, s * b1, 0.0], [2.0 * a + 0.9, 0.18, 0.22], color=list(BOGIE_RGBA)) for s in (1, -1)]
            g.append(gr.Brick([0.0, 0.0, 0.0], [0.35, 2.0 * b1, 0.18], color=list(BOGIE_RGBA)))
            mbs.SetObjectParameter(bg.body, "VgraphicsData", g)
            mbs.SetObjectParameter(bg.body, "Vshow", True)
        cb = self.model.car_body
        if cb is not None:
            lb = v.geometry.semi_bogie_centre_distance_m
            z_floor, z_roof = -1.15, -3.9                     # heights above rail (simplified coach)
            zc = 0.5 * (z_floor + z_roof) - cb.p_cg_in_frame[2]
            g = [gr.Brick([0.0, 0.0, zc], [2.0 * lb + 6.0, 2.9, z_floor - z_roof], color=list(CAR_RGBA))]
            mbs.SetObjectParameter(cb.body, "VgraphicsData", g)
            mbs.SetObjectParameter(cb.body, "Vshow", True)

    # ------------------------------------------------------------------------------------------------ state
    def show_current_state(self) -> np.ndarray:
        """Draw the model's *current* state: copy it (and its time) into Exudyn's visualization state and evaluate
        the contact there; the contacts stay frozen on that evaluation until :meth:`follow_solver`.  Call after a
        solve, before a screenshot.  Returns the contact results drawn."""
        exu = self.exu
        sd = self.mbs.systemData
        cur, vis = exu.ConfigurationType.Current, exu.ConfigurationType.Visualization
        t = float(sd.GetTime(cur))
        sd.SetSystemState(sd.GetSystemState(cur), configuration=vis)
        sd.SetTime(t, configurationType=vis)
        self._results = self.contact.evaluate(self.mbs, t).copy()
        self.mbs.SendRedrawSignal()
        return self._results

    def follow_solver(self):
        """Draw the connector's latest evaluation again (default)."""
        self._results = None

    def _visual_state(self):
        exu = self.exu
        vis = exu.ConfigurationType.Visualization
        t = float(self.mbs.systemData.GetTime(vis))
        q = None
        if self.bridge is not None:
            q = np.asarray(self.mbs.GetNodeOutput(self.bridge.modal_node, exu.OutputVariableType.Coordinates,
                                                  configuration=vis), dtype=float)
        return t, q

    def rail_offsets_m(self, x_m, t_s: float, q_bridge=None) -> tuple[np.ndarray, np.ndarray]:
        """Lateral and vertical displacement (y right, z down) [m] of the rails' centre line at model-frame x and
        time t: irregularity + deck ``Φ(s) q`` + ground motion ``y_g(t)`` (unscaled)."""
        s = self.model.track_distance_m(np.asarray(x_m, dtype=float), t_s)
        dy = np.zeros_like(s)
        dz = np.zeros_like(s)
        if self.track is not None:
            off = self.track.rail_offset(s)
            dy += off.y_m
            dz += off.z_m
        if self.bridge is not None:
            if q_bridge is not None and q_bridge.size:
                d = self.bridge.modes.rail_displacement(s, q_bridge)
                dy += d[..., 0]
                dz += d[..., 1]
            dy += self.bridge.ground_state(t_s)[0]
        return dy, dz

    # --------------------------------------------------------------------------------------------- graphics
    def _frame(self, mbs, item):
        t, q = self._visual_state()
        results = self._results if self._results is not None else self.contact.results.copy()
        return self.scene_graphics(t, q, results)

    def scene_graphics(self, t_s: float, q_bridge=None, results=None) -> list:
        """Graphics data of the ground-fixed scene at time t: rails, deck, contacts (``results``: the connector's
        results array, default its last evaluation)."""
        g = self.rail_graphics(t_s, q_bridge)
        if self.bridge is not None:
            g += self.deck_graphics(t_s, q_bridge)
        if self.show_contact_forces:
            g += self.contact_graphics(self.contact.results if results is None else results)
        return g

    def rail_graphics(self, t_s: float, q_bridge=None) -> list:
        dy, dz = self.rail_offsets_m(self.rail_x_m, t_s, q_bridge)
        k = self.options.deflection_scale
        if not (np.any(dy) or np.any(dz)) or k == 0.0:
            if self._static_rails is None:
                self._static_rails = [_triangles(*shapes.swept_mesh(sec, self.rail_x_m), RAIL_RGBA)
                                      for sec in self.rail_sections]
            return list(self._static_rails)
        return [_triangles(*shapes.swept_mesh(sec, self.rail_x_m, k * dy, k * dz), RAIL_RGBA)
                for sec in self.rail_sections]

    def deck_graphics(self, t_s: float, q_bridge=None) -> list:
        """The deck box (module docstring) in the model frame at time t."""
        o = self.options
        bm = self.bridge.modes.model
        e = float(bm.rail_height_m)
        top = o.track_bed_depth_m
        bottom = max(2.0 * e - top, top + 0.3)
        x0 = float(bm.start_m) - self.model.track_distance_m(0.0, t_s)
        length = float(bm.length_m)
        n = max(2, int(math.ceil(length / o.deck_station_spacing_m)) + 1)
        x = x0 + np.linspace(0.0, length, n)
        dy, dz = self.rail_offsets_m(x, t_s, q_bridge)
        if self.track is not None:                    # the deck carries the track; the irregularity is the rails'
            off = self.track.rail_offset(self.model.track_distance_m(x, t_s))
            dy, dz = dy - off.y_m, dz - off.z_m
        sec = shapes.rectangle_section(-0.5 * o.deck_width_m, 0.5 * o.deck_width_m, top, bottom)
        k = o.deflection_scale
        return [_triangles(*shapes.swept_mesh(sec, x, k * dy, k * dz), DECK_RGBA)]

    def contact_graphics(self, results) -> list:
        """Spheres at the active contact points and arrows of the rail's force on the wheel (model frame)."""
        from ..multibody import connector as C
        gr, o = self.gr, self.options
        res = np.asarray(results)
        active = (res[:, :, C.RES_STATUS] > 0) & (res[:, :, C.RES_N] > 0.0)
        out = []
        rgba = list(CONTACT_RGBA)
        for w, reg in zip(*np.nonzero(active)):
            r = res[w, reg]
            p = r[C.RES_P_X:C.RES_P_Z + 1]
            f = r[C.RES_F_TRACK_X:C.RES_F_TRACK_Z + 1]
            if not (np.all(np.isfinite(p)) and np.all(np.isfinite(f))):
                continue
            out.append(gr.Sphere(point=p.tolist(), radius=o.contact_sphere_radius_m, color=rgba, nTiles=8))
            v = f * o.force_scale_m_per_N
            if float(np.linalg.norm(v)) > 4.0 * o.arrow_radius_m:
                out.append(gr.Arrow(p.tolist(), v.tolist(), o.arrow_radius_m, color=rgba, nTiles=10))
        return out

    # ------------------------------------------------------------------------------------------------ camera
    def configure(self, SC, *, focus: str = "leading_bogie", window_size=(1024, 768), azimuth_deg: float = 35.0,
                  elevation_deg: float = 12.0, zoom_m: float | None = None, show_text: bool = True):
        """Visualization settings for this view: camera (``focus`` "leading_bogie" or "vehicle"; ``zoom_m`` the
        zoom, about half the visible height [m]; seen from the right side, ``azimuth_deg``/``elevation_deg`` as in
        :func:`view_rotation`), window size, no coordinate triad (its red and blue would mix into magenta at edges),
        no drawing of nodes, markers, connectors, loads and sensors.  Returns the visualization settings."""
        vs = SC.visualizationSettings
        x_ws = [ws.p_cg_in_frame[0] for ws in self.model.wheelsets]
        if focus == "leading_bogie":
            xs = sorted(x_ws)[-2:]                   # the leading bogie's wheelsets (or the only wheelset)
            centre = [float(np.mean(xs)), 0.0, -0.35]
            zoom = 1.5 if zoom_m is None else zoom_m
        elif focus == "vehicle":
            centre = [0.5 * (min(x_ws) + max(x_ws)), 0.0, -1.5]
            zoom = 7.0 if zoom_m is None else zoom_m
        else:
            raise ValueError(f"focus={focus!r}: expected 'leading_bogie' or 'vehicle'")
        R = view_rotation(azimuth_deg, elevation_deg)
        # Exudyn's render state: the model rotation is stored transposed (OpenGL order) and the centre point in view
        # coordinates (measured: centre = R p puts the model point p in the middle of the window)
        self._camera = (float(zoom), R, (R @ np.asarray(centre)).tolist())
        adv = vs.openGL.advanced
        adv.initialModelRotation = R.T.tolist()
        adv.initialCenterPoint = self._camera[2]
        adv.initialZoom = float(zoom)
        adv.initialMaxSceneSize = 30.0
        adv.depthSorting = True                      # transparent wheels/bodies drawn back to front
        vs.general.autoFitScene = False
        vs.view0.window.renderWindowSize = [int(window_size[0]), int(window_size[1])]
        vs.view0.scene.drawCoordinateSystem = 0
        vs.view0.scene.drawWorldBasis = False
        vs.general.showSolverInformation = show_text
        vs.general.showSolutionInformation = show_text
        # the computation info (bottom line) stays on: with view0.window.showComputationInfo = False the frames come
        # out blank (measured: Exudyn 1.13.6, Mesa llvmpipe under Xvfb)
        vs.general.showHelpOnStartup = 0
        for group in (vs.nodes, vs.markers, vs.connectors, vs.loads, vs.sensors):
            group.show = False
        return vs

    def apply_camera(self, SC):
        """Set the camera of :meth:`configure` in a running renderer (``SC.renderer.SetModelView``)."""
        from scipy.spatial.transform import Rotation
        if getattr(self, "_camera", None) is None:
            raise RuntimeError("call configure(SC) first")
        zoom, R, centre = self._camera
        SC.renderer.SetModelView(zoom, Rotation.from_matrix(R).as_rotvec().tolist(), centre)


    # ------------------------------------------------------------------------------------------------ window
    def open_window(self, SC, settings=None, realtime_factor: float = 0.25, focus: str = "leading_bogie"):
        """Open Exudyn's renderer on this view (:meth:`configure` with ``focus``); with the solver ``settings``
        (``exu.SimulationSettings``) the solve runs in slow motion at ``realtime_factor`` × real time."""
        if not (math.isfinite(realtime_factor) and realtime_factor > 0.0):
            raise ValueError(f"realtime_factor = {realtime_factor!r}: expected a positive number")
        check_display()
        self.configure(SC, focus=focus)
        if settings is not None:
            ti = settings.timeIntegration
            ti.simulateInRealtime = True
            ti.realtimeFactor = float(realtime_factor)
        if not SC.renderer.Start():
            raise RuntimeError("Exudyn's renderer could not be started (no display? set DISPLAY or run under Xvfb)")
        self._SC = SC

    def close_window(self, wait: bool = True):
        """Draw the final state; with ``wait`` keep the window until it is closed (Q, Escape or the window's close
        button); stop the renderer."""
        SC = getattr(self, "_SC", None)
        if SC is None:
            return
        try:
            self.show_current_state()
            if wait:
                print("3-D view: close the renderer window (or press Q / Escape) to continue", file=sys.stderr)
                SC.renderer.DoIdleTasks(-1)
        finally:
            SC.renderer.Stop()
            self._SC = None


class RtriView:
    """Exudyn's renderer for :func:`~exudyn_wheelrail.scenarios.rtri.run_rtri` (its ``view=`` hook): ``attach``
    adds a :class:`WheelRailView`, opens the window and slows the solve to ``realtime_factor`` × real time (0.25:
    the 2.5 s run takes 10 s); ``close`` keeps the window open until it is closed (``wait=True``; Space/Q/Escape)
    and stops the renderer.  The measured ``solve_seconds`` then include the rendering and the slow motion."""

    def __init__(self, options: ViewOptions | None = None, realtime_factor: float = 0.25, focus: str = "leading_bogie",
                 wait: bool = True):
        if not (math.isfinite(realtime_factor) and realtime_factor > 0.0):
            raise ValueError(f"realtime_factor = {realtime_factor!r}: expected a positive number")
        self.options = options
        self.realtime_factor = float(realtime_factor)
        self.focus = focus
        self.wait = wait
        self.view = None

    def attach(self, h):
        self.view = WheelRailView.for_rtri(h, self.options)
        self.view.open_window(h.system_container, h.settings, self.realtime_factor, self.focus)

    def close(self):
        if self.view is not None:
            self.view.close_window(self.wait)
