r"""A vehicle on a curved, canted track in **track-following frames**: the straight-track model of
:func:`~.vehicle_builder.build_vehicle` keeps its coordinates, each body's read as its pose relative to the local
track frame at its own track distance, and the curve enters through the terms below.

>>> model = build_vehicle(mbs, "manchester_vehicle1", speed_m_s=V, s_start_m=s0)          # doctest: +SKIP
>>> frame = TrackFollowingFrame(mbs, model, layout)        # before mbs.Assemble()          # doctest: +SKIP
>>> frame.update(mbs, 0.0)                                 # then before every step (the runner's user_function)

The formulation
---------------
The *trajectory* (track-following) coordinates of railway multibody codes: a reference frame moves along the
track centre line with the running speed and follows its heading, cant and gradient; the bodies' coordinates are
small motions relative to it, and the frame's motion enters the equations as inertia terms (Shabana, Zaazaa &
Sugiyama, *Railroad Vehicle Dynamics: A Computational Approach*, CRC 2008, ch. 3 and 6, the body trajectory
coordinate system; Shabana, *Mathematical Foundation of Railroad Vehicle Systems*, Wiley 2021, ch. 6-7; the same
frame underlies the curving chapters of Iwnicki (ed.), *Handbook of Railway Vehicle Dynamics*, CRC 2006, ch. 7 and
Knothe & Stichel, *Rail Vehicle Dynamics*, Springer 2017, ch. 8).  Here every body i has its own frame at
``s_i = s_start + V t + X_i`` (``X_i`` its nominal x in the model), the frame kinematics of
:mod:`exudyn_wheelrail.track.layout`: angular velocity ``Ω``, its rate ``Ω̇``, origin acceleration ``a_O``,
gravity ``g`` — all in track-frame components.

(a) **Inertia and gravity of the frame, on every body** (:meth:`TrackFollowingFrame.update`).  Newton–Euler in
the moving frame (e.g. Goldstein, *Classical Mechanics*, §4.10; Shabana et al. 2008, §6.2) for a body of mass m,
inertia I (track axes), centre of mass at ``r`` relative to its frame origin, velocity ``v_r`` and angular velocity
``ω_r`` relative to the frame:

.. math:: m \ddot r = F + m g - m a_O - m \dot Ω × r - m Ω × (Ω × r) - 2 m Ω × v_r

.. math:: I \dot ω_r + ω_r × I ω_r = M - I \dot Ω - Ω × I Ω - Ω × I ω_r - ω_r × I Ω + I (ω_r × Ω)

The model integrates the straight-track equations with gravity ``(0, 0, g)``; the difference is added as one
force and one torque per body (Exudyn ``LoadForceVector``/``LoadTorqueVector`` at the centre of mass, global =
track-frame components, set before every step):

* force ``m (g_track − (0, 0, g) − a_O − Ω̇ × r − Ω × (Ω × r))``: in the canted track plane this is the lateral
  ``m (g sin φ − V²κ cos φ)`` (outwards ``m (V²/R cos φ − g sin φ)``) and the vertical ``m (V²κ sin φ + g cos φ)``
  in place of ``m g`` (gradient: ``−m g sin θ`` along x, carried by the longitudinal restraint);
  ``r = (0, y_cg, z_cg)`` nominal (a car-body centre 1.8 m above the rails adds ``m Ω_z² r`` ≈ 4.5e-3 m/s² for
  V = 30 m/s, R = 600 m);
* torque ``−(I Ω̇ + Ω × I Ω + Ω × I ω_s + ω_s × I Ω − I (ω_s × Ω))`` with ``ω_s = (0, −V/r0, 0)`` the nominal
  spin of a wheelset (zero for the other bodies).  For a wheelset (``I_xx = I_zz``) the last two terms cancel and
  ``−Ω × I ω_s`` is the **gyroscopic moment** of the spinning axle in the turning frame: ``x`` component
  ``I_yy ω_s V κ cos φ = −I_yy V² κ cos φ / r0`` (the rails must supply ``dH/dt = Ω × H``, ``H = I_yy ω_s e_y``:
  the outer wheel is loaded by ``I_yy V² κ/(r0 · 2 b)`` more, the inner one less), ``z`` component
  ``−I_yy ω_s φ̇`` in the cant ramp.  ``I Ω̇`` is the car body's yaw inertia in the transition
  (``I_zz V² κ'``).
* The Coriolis term ``2 m Ω × v_r`` is left out: ``v_r`` is zero in steady curving and in the transition its
  effect is ``2 V κ |v_r|`` ≲ 1e-3 m/s² for body velocities of 0.1 m/s.

(b) **Creepages**: the rails seen from the wheelset's frame move with ``−V e_x − Ω × r`` at the contact point
``r`` and turn with ``−Ω``: the outer/inner longitudinal creepage ``∓ b κ`` and the spin ``κ cos γ`` of the turning
frame.  They belong to the contact connector (:mod:`exudyn_wheelrail.multibody.connector_core`), which evaluates them from the layout's
packed arrays.

(c) **Geometric coupling between bodies at different s**.  A suspension element joins a point of body A (frame at
``s_A``) and a point of body B (frame at ``s_B``).  Its relative displacement must be measured in one frame; the
model measures both in the common straight frame.  In A's frame, B's frame origin lies (small-angle) at the
lateral offset ``y_h = Ψ(s_B) − Ψ(s_A) − ψ(s_A) d`` (``d = s_B − s_A``, ``Ψ = ∫ ψ ds``: the versine ``κ d²/2`` in
a circular curve), turned by ``Δψ = ψ(s_B) − ψ(s_A)`` (``κ d``) about the vertical and by ``Δφ = φ(s_B) − φ(s_A)``
(the cant twist) about x.  A point ``v`` of B (relative to B's frame origin) is therefore displaced in A's frame by

.. math:: δ = (0,\; y_h \cos φ_A,\; −y_h \sin φ_A) + θ × v, \qquad θ = (Δφ,\; Δψ \cos θ_g \sin φ_A,\;
          Δψ \cos θ_g \cos φ_A),

and each element's offset is set so that it acts on the true relative displacement (:meth:`update`): a Cartesian
spring–damper's ``offset`` (force ``k (Δp − offset)``) becomes ``offset₀ − δ``, a rigid-body spring's rotational
offset ``offset₀ − θ``; the bump stops (their force law ignores ``offset``) get their bogie-side point moved
laterally by ``δ_y`` (a lateral force moved along its own line: no moment error).  This is what steers a bogie's
wheelsets: with the primary yaw stiffness the wheelsets stay nearly parallel to their bogie frame, so each sits
at an angle of attack ``≈ ∓ κ a`` in its own track frame; the car body rides at the versine ``κ l²/2`` inside the
track centre line at its centre (its frame).  Elements to the moving frame (the guidance and dead loads of the
bogie and wheelset layouts, the longitudinal restraint, the rail springs) act at their own body's s and need no
offset.

What is neglected (stated, small): the forces of an element are applied in the common model directions, not turned
by ``Δψ`` into B's frame (a lateral force F gets no longitudinal component ``F Δψ`` ≤ 1.6 % of F on a bogie
9.5 m from the car-body centre at R = 600 m; the lateral sums are unaffected to ``Δψ²/2``); the longitudinal
shortening ``∫ Δψ²/2`` of the chord (< 0.5 mm for 9.5 m at R = 600 m); the rate of the offsets in the dampers
(``V d/ds`` of the offsets: only in the transition, e.g. 0.04 m/s of versine rate between car body and bogie for
V = 30 m/s, LT = 60 m, R = 600 m); all of them vanish or are constant in the steady curve.
"""
from __future__ import annotations

import math

import numpy as np
from exudyn.itemInterface import LoadForceVector, LoadTorqueVector

from ..jit import compiled
from ..track.layout import TrackLayout, heading_many, layout_at

__all__ = ["TrackFollowingFrame"]


@compiled
def _cross(a, b, out):
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@compiled
def _frame_terms(pieces, par, psi_a, Psi_a, theta_g, V, g, s, m, r, inertia, spin, el_bodies, el_v, F, T, delta,
                 theta, lay):
    """The body loads F, T (n, 3) and the elements' δ, θ (n_el, 3) at the bodies' track distances s (module
    docstring (a), (c)); ``lay`` (n, N_LAYOUT) receives the layout values."""
    n = s.shape[0]
    c_th = math.cos(theta_g)
    s_th = math.sin(theta_g)
    hp = heading_many(pieces, psi_a, Psi_a, s)
    Om = np.empty(3)
    dOm = np.empty(3)
    a1 = np.empty(3)
    a2 = np.empty(3)
    a3 = np.empty(3)
    Iw = np.empty(3)
    IO = np.empty(3)
    for i in range(n):
        layout_at(pieces, par, s[i], lay[i])
        k, dk, phi, dphi = lay[i, 0], lay[i, 1], lay[i, 2], lay[i, 3]
        cp, sp = math.cos(phi), math.sin(phi)
        Om[0] = V * (dphi - k * s_th)
        Om[1] = V * k * c_th * sp
        Om[2] = V * k * c_th * cp
        # phi'' = phi'^2 tan(phi) inside a linear cant ramp (h' constant, phi = asin(h/b))
        dOm[0] = V * V * (dphi * dphi * math.tan(phi) - dk * s_th)
        dOm[1] = V * V * c_th * (dk * sp + k * cp * dphi)
        dOm[2] = V * V * c_th * (dk * cp - k * sp * dphi)
        ri = r[i]
        _cross(dOm, ri, a1)
        _cross(Om, ri, a2)
        _cross(Om, a2, a3)
        # gravity in the track frame minus the model's own (0, 0, g), minus a_O, Ω̇ × r and Ω × (Ω × r)
        F[i, 0] = m[i] * (-g * s_th - a1[0] - a3[0])
        F[i, 1] = m[i] * (g * c_th * sp - V * V * k * c_th * cp - a1[1] - a3[1])
        F[i, 2] = m[i] * (g * c_th * cp - g + V * V * k * c_th * sp - a1[2] - a3[2])
        I = inertia[i]
        w = spin[i]
        for a in range(3):
            Iw[a] = I[a, 0] * w[0] + I[a, 1] * w[1] + I[a, 2] * w[2]
            IO[a] = I[a, 0] * Om[0] + I[a, 1] * Om[1] + I[a, 2] * Om[2]
        _cross(Om, IO, a1)          # Ω × I Ω
        _cross(Om, Iw, a2)          # Ω × I ω_s
        _cross(w, IO, a3)           # ω_s × I Ω
        _cross(w, Om, Iw)           # ω_s × Ω (Iw reused)
        for a in range(3):
            I_dOm = I[a, 0] * dOm[0] + I[a, 1] * dOm[1] + I[a, 2] * dOm[2]
            I_wO = I[a, 0] * Iw[0] + I[a, 1] * Iw[1] + I[a, 2] * Iw[2]
            T[i, a] = -(I_dOm + a1[a] + a2[a] + a3[a] - I_wO)
    for e in range(el_bodies.shape[0]):
        kA = el_bodies[e, 0]
        kB = el_bodies[e, 1]
        d = s[kB] - s[kA]
        phiA = lay[kA, 2]
        y_h = hp[kB, 1] - hp[kA, 1] - hp[kA, 0] * d
        dpsi = hp[kB, 0] - hp[kA, 0]
        th = theta[e]
        th[0] = lay[kB, 2] - phiA - dpsi * s_th
        th[1] = dpsi * c_th * math.sin(phiA)
        th[2] = dpsi * c_th * math.cos(phiA)
        _cross(th, el_v[e], a1)
        delta[e, 0] = a1[0]
        delta[e, 1] = y_h * math.cos(phiA) + a1[1]
        delta[e, 2] = -y_h * math.sin(phiA) + a1[2]


class TrackFollowingFrame:
    """The curve terms (a) and (c) of the module docstring for a :class:`~.vehicle_builder.VehicleModel` built in
    ``mbs`` (create before ``mbs.Assemble()``; call :meth:`update` before every step, e.g. as the runner's
    ``user_function``)."""

    def __init__(self, mbs, model, layout: TrackLayout, *, gravity_m_s2: float | None = None):
        self.model = model
        self.layout = layout
        self.V = float(model.speed_m_s)
        self.g = float(model.gravity_m_s2 if gravity_m_s2 is None else gravity_m_s2)
        self.bodies = list(model.bodies)
        self._by_body = {int(b.body): k for k, b in enumerate(self.bodies)}
        n = len(self.bodies)
        self._x = np.array([b.p_cg_in_frame[0] for b in self.bodies])
        self._m = np.array([b.mass_kg for b in self.bodies])
        self._r = np.array([[0.0, b.p_cg_in_frame[1], b.p_cg_in_frame[2]] for b in self.bodies])
        self._inertia = []
        self._spin = np.zeros((n, 3))
        veh = model.vehicle
        ws_ids = {id(w) for w in model.wheelsets}
        for k, b in enumerate(self.bodies):
            data = veh.wheelset if id(b) in ws_ids else (veh.car_body if b is model.car_body else veh.bogie_frame)
            self._inertia.append(np.asarray(data.inertia_kg_m2, dtype=float))
            if id(b) in ws_ids:
                self._spin[k, 1] = b.spin_rad_s
        self._inertia = np.array(self._inertia)
        self.force_loads = [mbs.AddLoad(LoadForceVector(markerNumber=b.marker, loadVector=[0.0, 0.0, 0.0]))
                            for b in self.bodies]
        self.torque_loads = [mbs.AddLoad(LoadTorqueVector(markerNumber=b.marker, loadVector=[0.0, 0.0, 0.0]))
                             for b in self.bodies]
        # suspension elements joining two bodies: (object, kind, body A, body B, base offset, point v on B, marker)
        self.elements = []
        for group in ("primary", "secondary", "bump_stop", "secondary_rotational"):
            for obj in model.connectors.get(group, []):
                self._add_element(mbs, obj, group)
        self._pieces, self._psi_a, self._Psi_a = layout.heading_arrays()
        self._par = layout.packed().par
        self._el_bodies = np.array([[e[2], e[3]] for e in self.elements], dtype=np.int64).reshape(-1, 2)
        self._el_v = np.array([e[5] for e in self.elements], dtype=float).reshape(-1, 3)
        n_el = len(self.elements)
        self._F = np.zeros((n, 3))
        self._T = np.zeros((n, 3))
        self._delta = np.zeros((n_el, 3))
        self._theta = np.zeros((n_el, 3))
        self._lay = np.zeros((n, 4))
        self._last = None
        self.updates = 0

    def _marker_body_point(self, mbs, marker):
        m = mbs.GetMarker(marker)
        body = int(m["bodyNumber"])
        local = np.asarray(m.get("localPosition", [0.0, 0.0, 0.0]), dtype=float)
        return body, local

    def _add_element(self, mbs, obj, group):
        o = mbs.GetObject(obj)
        m0, m1 = o["markerNumbers"]
        b0, _ = self._marker_body_point(mbs, m0)
        b1, local1 = self._marker_body_point(mbs, m1)
        if b0 not in self._by_body or b1 not in self._by_body:
            return                                   # to the moving frame: acts at its own body's s
        kA, kB = self._by_body[b0], self._by_body[b1]
        bodyB = self.bodies[kB]
        p1 = bodyB.p_cg_in_frame + local1            # nominal point in the model frame
        v = p1 - np.array([bodyB.p_cg_in_frame[0], 0.0, 0.0])   # relative to B's frame origin
        if group == "bump_stop":
            kind, base = "marker", local1
        elif group == "secondary_rotational":
            kind, base = "rigid", np.asarray(o["offset"], dtype=float)
        else:
            kind, base = "cartesian", np.asarray(o["offset"], dtype=float)
        self.elements.append((obj, kind, kA, kB, base.copy(), v, m1))

    # ------------------------------------------------------------------------------------------------ terms
    def _compute(self, t: float):
        s = self.model.s_start_m + self.V * float(t) + self._x
        _frame_terms(self._pieces, self._par, self._psi_a, self._Psi_a, self.layout.theta_rad, self.V, self.g, s,
                     self._m, self._r, self._inertia, self._spin, self._el_bodies, self._el_v, self._F, self._T,
                     self._delta, self._theta, self._lay)
        return s

    def body_terms(self, t: float):
        """(forces (n, 3), torques (n, 3)) added to the bodies at time t (module docstring (a)), copies."""
        self._compute(t)
        return self._F.copy(), self._T.copy()

    def offsets(self, t: float):
        """Per element the displacement δ of B's point and the rotation θ in A's frame (module docstring (c)):
        arrays (n_elements, 3) each, copies."""
        self._compute(t)
        return self._delta.copy(), self._theta.copy()

    def update(self, mbs, t: float) -> bool:
        """Set the body loads and the element offsets for time t (returns True: the runner's ``user_function``
        contract).  Skipped when every body sees the same layout values as at the previous update (a constant
        curve or straight)."""
        self._compute(t)
        key = self._lay.tobytes()
        if key == self._last:
            return True
        self._last = key
        F, T = self._F, self._T
        for i in range(len(self.bodies)):
            mbs.SetLoadParameter(self.force_loads[i], "loadVector", F[i].tolist())
            mbs.SetLoadParameter(self.torque_loads[i], "loadVector", T[i].tolist())
        for (obj, kind, kA, kB, base, v, marker), delta, theta in zip(self.elements, self._delta, self._theta):
            if kind == "cartesian":
                mbs.SetObjectParameter(obj, "offset", (base - delta).tolist())
            elif kind == "rigid":
                off = base.copy()
                off[3:] -= theta
                mbs.SetObjectParameter(obj, "offset", off.tolist())
            else:
                local = base.copy()
                local[1] += delta[1]
                mbs.SetMarkerParameter(marker, "localPosition", local.tolist())
        self.updates += 1
        return True

    __call__ = update
