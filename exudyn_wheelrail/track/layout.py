r"""The track layout as a function of the track distance s: straight, circular curve, clothoid transition with a
linear cant ramp, right- and left-hand curves, a constant gradient.

Signs and frames: :mod:`exudyn_wheelrail.conventions` ("Curves, cant and gradient"): curvature ``κ = dψ/ds``
positive in a right-hand curve, cant ``h`` and cant angle ``φ`` (``sin φ = h / 1.5 m``, EN 13803) of the same sign
(positive lowers the right rail), gradient positive uphill (pitch ``θ = atan(gradient)``).

Layout
------
A :class:`TrackLayout` is a list of sections starting at ``start_m`` (straight track before it, the last section's
curvature and cant continued after it):

* :class:`Straight` — ``κ = 0``, ``h = 0``;
* :class:`Curve` — ``κ = ±1/R``, ``h = ±H`` (``direction`` ``"right"`` or ``"left"``);
* :class:`Transition` — the **clothoid** (Euler spiral): the curvature varies linearly in s from the end value of
  the section before to the start value of the section after, ``κ(s) = κ_a + (κ_b − κ_a) u/L`` (``u`` the
  distance into the transition, L its length), and the cant with it (the **linear cant ramp**,
  ``h(s) = h_a + (h_b − h_a) u/L``), the standard transition of EN 13803 (clothoid with a straight ramp; e.g.
  Lichtberger, *Track Compendium*, ch. 2; Esveld, *Modern Railway Track*, 2nd ed., §2.3).

Per section the curvature and the cant are linear in s; the packed form (:meth:`TrackLayout.packed`) holds, per
piece, ``(s_a, s_b, κ_a, κ_b, h_a, h_b)`` and :func:`layout_at` evaluates it in compiled code (binary search of the
piece, linear interpolation): ``κ``, ``dκ/ds``, ``φ`` and ``dφ/ds = (dh/ds) / (1.5 m · cos φ)``.

Heading and position
--------------------
The heading ``ψ(s) = ∫ κ ds`` is exact per piece (``ψ_a + κ_a u + (κ_b − κ_a) u²/(2L)``).  The plan-view position
is ``x(s) = ∫ cos θ cos ψ ds``, ``y(s) = ∫ cos θ sin ψ ds`` and the height ``z(s) = −s sin θ`` (z down), evaluated
by composite 5-point Gauss–Legendre quadrature on sub-intervals of at most :data:`QUADRATURE_STEP_M` (ψ is a
quadratic in s: the quadrature error is far below a micrometre per kilometre).  For a clothoid from a straight
(``κ_a = 0``, ``κ_b = 1/R``) the position is given by the Fresnel integrals, ``x = A√π C(u/(A√π))``,
``y = A√π S(u/(A√π))`` with ``A² = R L`` (``tests/test_track_layout.py`` checks it).

Track frame
-----------
The track frame at s (x along the track, y right, z down; :mod:`exudyn_wheelrail.conventions`) is
``R(s) = R_z(ψ) R_y(θ) R_x(φ)`` applied to the global axes (the track frame at ``s = 0``).  A point moving along
the centre line at the constant speed V has, in the track frame,

* the angular velocity of its frame ``Ω = V (φ' − κ sin θ, κ cos θ sin φ, κ cos θ cos φ)`` (:meth:`TrackLayout.
  frame_angular_velocity`; ψ̇ = Vκ about the global vertical, φ̇ = Vφ' about the track x axis, θ constant),
* the acceleration ``a_O = V² κ cos θ (0, cos φ, −sin φ)`` (the centripetal acceleration of the plan-view curve,
  radius ``cos θ/κ``, horizontal speed ``V cos θ``, towards the centre; ``n_h = R_z(ψ) ŷ`` has the track-frame
  components ``(0, cos φ, −sin φ)``),
* gravity ``g (−sin θ, cos θ sin φ, cos θ cos φ)``.

How a vehicle uses this in the frame that follows the track: :mod:`exudyn_wheelrail.analysis.curving`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..conventions import CURVE_DIRECTION_SIGN, RAIL_CENTRE_DISTANCE_M
from ..jit import compiled
from ..validation import finite

__all__ = ["Straight", "Curve", "Transition", "TrackLayout", "PackedLayout", "layout_at", "layout_many", "heading_many",
           "LAYOUT_KAPPA", "LAYOUT_DKAPPA", "LAYOUT_PHI", "LAYOUT_DPHI", "N_LAYOUT", "MAX_CANT_M",
           "MAX_RADIUS_M", "MAX_TRANSITION_M", "QUADRATURE_STEP_M", "LayoutError", "curve_quantities"]

#: largest cant [m] a layout accepts (EN 13803: 160-180 mm in normal, up to 200 mm in exceptional cases)
MAX_CANT_M = 0.200
#: plausible ranges of a curve's input (the curving run's and a scenario's ``[layout]``; a value outside was evidently
#: given in another unit): the largest radius [m] and the longest transition [m]
MAX_RADIUS_M = 1.0e5
MAX_TRANSITION_M = 1000.0
#: longest sub-interval of the position quadrature [m]
QUADRATURE_STEP_M = 2.0

# fields of layout_at's output
LAYOUT_KAPPA = 0      #: curvature κ [1/m]
LAYOUT_DKAPPA = 1     #: dκ/ds [1/m²]
LAYOUT_PHI = 2        #: cant angle φ [rad]
LAYOUT_DPHI = 3       #: dφ/ds [rad/m]
N_LAYOUT = 4

_GL_X = np.array([-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640])
_GL_W = np.array([0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                  0.2369268850561891])


class LayoutError(ValueError):
    """A bad layout value: the message names the section and the key."""


@dataclass(frozen=True)
class Straight:
    """Straight track of ``length_m``."""

    length_m: float


@dataclass(frozen=True)
class Curve:
    """Circular curve of radius ``radius_m`` (> 0), cant ``cant_m`` (>= 0, raises the outer rail), turning to
    ``direction`` (``"right"`` or ``"left"``), of ``length_m``."""

    length_m: float
    radius_m: float
    cant_m: float = 0.0
    direction: str = "right"

    @property
    def curvature_1_m(self) -> float:
        return CURVE_DIRECTION_SIGN[self.direction] / self.radius_m

    @property
    def signed_cant_m(self) -> float:
        return CURVE_DIRECTION_SIGN[self.direction] * self.cant_m


@dataclass(frozen=True)
class Transition:
    """Clothoid transition of ``length_m``: curvature and cant linear in s from the section before to the one
    after (module docstring)."""

    length_m: float


@dataclass(frozen=True)
class PackedLayout:
    """The arrays of :func:`layout_at`: ``pieces`` (n, 6) rows ``(s_a, s_b, κ_a, κ_b, h_a, h_b)``, sorted, and
    ``par = (RAIL_CENTRE_DISTANCE_M,)``."""

    pieces: np.ndarray
    par: np.ndarray


@compiled
def layout_at(pieces, par, s, out):
    """Fill ``out[LAYOUT_*]`` (κ, dκ/ds, φ, dφ/ds) at track distance ``s`` from the packed pieces.  Before the
    first piece: straight and level (the first piece's start values); after the last: its end values continued."""
    n = pieces.shape[0]
    base = par[0]
    if n == 0:
        out[0] = 0.0
        out[1] = 0.0
        out[2] = 0.0
        out[3] = 0.0
        return
    if s <= pieces[0, 0]:
        k, dk, h, dh = pieces[0, 2], 0.0, pieces[0, 4], 0.0
    elif s >= pieces[n - 1, 1]:
        k, dk, h, dh = pieces[n - 1, 3], 0.0, pieces[n - 1, 5], 0.0
    else:
        lo = 0
        hi = n - 1
        while lo < hi:                      # last piece with s_a <= s
            mid = (lo + hi + 1) // 2
            if pieces[mid, 0] <= s:
                lo = mid
            else:
                hi = mid - 1
        p = pieces[lo]
        L = p[1] - p[0]
        u = (s - p[0]) / L if L > 0.0 else 0.0
        dk = (p[3] - p[2]) / L if L > 0.0 else 0.0
        dh = (p[5] - p[4]) / L if L > 0.0 else 0.0
        k = p[2] + (p[3] - p[2]) * u
        h = p[4] + (p[5] - p[4]) * u
    sphi = h / base
    phi = math.asin(sphi)
    out[0] = k
    out[1] = dk
    out[2] = phi
    out[3] = dh / (base * math.cos(phi))


@compiled
def layout_many(pieces, par, s):
    """:func:`layout_at` for an array of s: (len(s), N_LAYOUT)."""
    out = np.empty((s.shape[0], 4))
    for i in range(s.shape[0]):
        layout_at(pieces, par, s[i], out[i])
    return out


@compiled
def heading_many(pieces, psi_a, Psi_a, s):
    """Heading ψ(s) and its integral Ψ(s) = ∫ ψ ds from the layout start, (len(s), 2), exact for the piecewise
    linear curvature (``psi_a``, ``Psi_a`` their values at the pieces' starts).  Straight before the first piece,
    the last piece's end curvature continued after it."""
    n = pieces.shape[0]
    out = np.zeros((s.shape[0], 2))
    for j in range(s.shape[0]):
        sj = s[j]
        if sj <= pieces[0, 0]:
            continue
        if sj >= pieces[n - 1, 1]:
            i = n - 1
            L = pieces[i, 1] - pieces[i, 0]
            ka, kb = pieces[i, 2], pieces[i, 3]
            dk = (kb - ka) / L if L > 0.0 else 0.0
            psi_e = psi_a[i] + ka * L + 0.5 * dk * L * L
            Psi_e = Psi_a[i] + psi_a[i] * L + ka * L * L / 2.0 + dk * L * L * L / 6.0
            u = sj - pieces[i, 1]
            out[j, 0] = psi_e + kb * u
            out[j, 1] = Psi_e + psi_e * u + kb * u * u / 2.0
            continue
        lo = 0
        hi = n - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if pieces[mid, 0] <= sj:
                lo = mid
            else:
                hi = mid - 1
        L = pieces[lo, 1] - pieces[lo, 0]
        ka, kb = pieces[lo, 2], pieces[lo, 3]
        dk = (kb - ka) / L if L > 0.0 else 0.0
        u = sj - pieces[lo, 0]
        out[j, 0] = psi_a[lo] + ka * u + 0.5 * dk * u * u
        out[j, 1] = Psi_a[lo] + psi_a[lo] * u + ka * u * u / 2.0 + dk * u * u * u / 6.0
    return out


class TrackLayout:
    """Sections from ``start_m`` on (straight and level before), constant ``gradient`` (rise/run, positive
    uphill).  Values outside the checked ranges raise :class:`LayoutError` naming the section and key."""

    def __init__(self, sections, start_m: float = 0.0, gradient: float = 0.0):
        self.sections = list(sections)
        self.start_m = finite("start_m", start_m)
        self.gradient = finite("gradient", gradient)
        if abs(self.gradient) > 0.1:
            raise LayoutError(f"gradient = {gradient!r}: expected a rise per length within +-0.1 (10 %); was it "
                              "given in per mille or percent?")
        self.theta_rad = math.atan(self.gradient)
        for i, sec in enumerate(self.sections):
            self._check(i, sec)
        self._pieces = self._build_pieces()
        self._par = np.array([RAIL_CENTRE_DISTANCE_M])
        self._build_heading_and_position()

    # ------------------------------------------------------------------------------------------ construction
    @staticmethod
    def _check(i, sec):
        where = f"section {i} ({type(sec).__name__})"
        if not isinstance(sec, (Straight, Curve, Transition)):
            raise LayoutError(f"{where}: expected Straight, Curve or Transition")
        if not (math.isfinite(sec.length_m) and sec.length_m >= 0.0):
            raise LayoutError(f"{where}: length_m = {sec.length_m!r}: expected a finite length >= 0 m")
        if isinstance(sec, Curve):
            if not (math.isfinite(sec.radius_m) and sec.radius_m > 0.0):
                raise LayoutError(f"{where}: radius_m = {sec.radius_m!r}: expected a finite radius > 0 m")
            if not (math.isfinite(sec.cant_m) and 0.0 <= sec.cant_m <= MAX_CANT_M):
                raise LayoutError(f"{where}: cant_m = {sec.cant_m!r}: expected 0 ... {MAX_CANT_M} m (was it given "
                                  f"in mm?)")
            if sec.direction not in CURVE_DIRECTION_SIGN:
                raise LayoutError(f"{where}: direction = {sec.direction!r}: expected 'right' or 'left'")

    @staticmethod
    def _values(sec):
        if isinstance(sec, Curve):
            return sec.curvature_1_m, sec.signed_cant_m
        return 0.0, 0.0

    def _build_pieces(self) -> np.ndarray:
        rows = []
        s = self.start_m
        n = len(self.sections)
        for i, sec in enumerate(self.sections):
            if isinstance(sec, Transition):
                prev = self._values(self.sections[i - 1]) if i > 0 else (0.0, 0.0)
                nxt = self._values(self.sections[i + 1]) if i + 1 < n else prev
                ka, ha, kb, hb = prev[0], prev[1], nxt[0], nxt[1]
            else:
                ka, ha = self._values(sec)
                kb, hb = ka, ha
            if sec.length_m > 0.0:
                rows.append((s, s + sec.length_m, ka, kb, ha, hb))
            s += sec.length_m
        if not rows:
            rows.append((self.start_m, self.start_m, 0.0, 0.0, 0.0, 0.0))
        return np.ascontiguousarray(np.array(rows, dtype=float))

    def _heading_piece(self, i, u):
        s_a, s_b, ka, kb = self._pieces[i, :4]
        L = s_b - s_a
        return self._psi_a[i] + ka * u + ((kb - ka) * u * u / (2.0 * L) if L > 0.0 else 0.0)

    def _integrate_piece(self, i, u_end):
        """∫_0^u_end (cos ψ, sin ψ) du over piece i (composite Gauss–Legendre)."""
        u_end = np.asarray(u_end, dtype=float)
        n_sub = np.maximum(1, np.ceil(np.abs(u_end) / QUADRATURE_STEP_M)).astype(int)
        out = np.zeros(u_end.shape + (2,))
        for idx in np.ndindex(u_end.shape):
            m = int(n_sub[idx])
            h = float(u_end[idx]) / m
            mids = (np.arange(m) + 0.5) * h
            u = (mids[:, None] + 0.5 * h * _GL_X[None, :]).ravel()
            w = np.tile(_GL_W, m) * 0.5 * h
            psi = self._heading_piece(i, u)
            out[idx] = (np.sum(w * np.cos(psi)), np.sum(w * np.sin(psi)))
        return out

    def _build_heading_and_position(self):
        p = self._pieces
        n = p.shape[0]
        self._psi_a = np.zeros(n)
        self._xy_a = np.zeros((n, 2))
        psi = 0.0
        xy = np.array([self.start_m, 0.0])      # straight before the first piece: along the global x axis
        for i in range(n):
            self._psi_a[i] = psi
            self._xy_a[i] = xy
            L = p[i, 1] - p[i, 0]
            psi = float(self._heading_piece(i, L))
            xy = xy + self._integrate_piece(i, np.array(L))
        self._psi_end = psi
        self._xy_end = xy
        # Ψ = ∫ ψ ds at the pieces' starts (exact: ψ is quadratic per piece)
        self._Psi_a = np.zeros(n)
        for i in range(1, n):
            L = p[i - 1, 1] - p[i - 1, 0]
            ka, kb = p[i - 1, 2], p[i - 1, 3]
            self._Psi_a[i] = (self._Psi_a[i - 1] + self._psi_a[i - 1] * L + ka * L * L / 2.0
                              + (kb - ka) * L * L / 6.0)

    def heading_and_integral(self, s) -> np.ndarray:
        """(len(s), 2): ψ(s) and Ψ(s) = ∫ ψ ds (:func:`heading_many`)."""
        return heading_many(self._pieces, self._psi_a, self._Psi_a, np.atleast_1d(np.asarray(s, dtype=float)))

    def heading_arrays(self):
        """``(pieces, psi_a, Psi_a)`` of :func:`heading_many`."""
        return self._pieces, self._psi_a, self._Psi_a

    # ------------------------------------------------------------------------------------------- evaluation
    @property
    def end_m(self) -> float:
        return float(self._pieces[-1, 1])

    def packed(self) -> PackedLayout:
        return PackedLayout(self._pieces.copy(), self._par.copy())

    def evaluate(self, s) -> np.ndarray:
        """(len(s), N_LAYOUT): κ, dκ/ds, φ, dφ/ds (:func:`layout_at`)."""
        return layout_many(self._pieces, self._par, np.atleast_1d(np.asarray(s, dtype=float)))

    def curvature(self, s):
        return self.evaluate(s)[:, LAYOUT_KAPPA]

    def curvature_rate(self, s):
        return self.evaluate(s)[:, LAYOUT_DKAPPA]

    def cant_m(self, s):
        return RAIL_CENTRE_DISTANCE_M * np.sin(self.evaluate(s)[:, LAYOUT_PHI])

    def cant_angle(self, s):
        return self.evaluate(s)[:, LAYOUT_PHI]

    def cant_angle_rate(self, s):
        return self.evaluate(s)[:, LAYOUT_DPHI]

    def _piece_index(self, s):
        return np.clip(np.searchsorted(self._pieces[:, 0], s, side="right") - 1, 0, self._pieces.shape[0] - 1)

    def heading(self, s):
        """ψ(s) [rad] (exact per piece)."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        out = np.empty_like(s)
        p = self._pieces
        for j, sj in enumerate(s):
            if sj <= p[0, 0]:
                out[j] = 0.0
            elif sj >= p[-1, 1]:
                out[j] = self._psi_end + p[-1, 3] * (sj - p[-1, 1])
            else:
                i = int(self._piece_index(sj))
                out[j] = self._heading_piece(i, sj - p[i, 0])
        return out

    def position(self, s) -> np.ndarray:
        """Global position (x, y, z) [m] of the centre line at s, (len(s), 3); z down."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        p = self._pieces
        out = np.zeros((s.shape[0], 3))
        c_th = math.cos(self.theta_rad)
        for j, sj in enumerate(s):
            if sj <= p[0, 0]:
                xy = np.array([sj, 0.0])
            elif sj >= p[-1, 1]:
                k = p[-1, 3]
                u = sj - p[-1, 1]
                psi0 = self._psi_end
                if abs(k) * u < 1e-9:
                    d = np.array([math.cos(psi0), math.sin(psi0)]) * u
                else:                               # circular arc continued
                    d = np.array([math.sin(psi0 + k * u) - math.sin(psi0), math.cos(psi0) - math.cos(psi0 + k * u)]
                                 ) / k
                xy = self._xy_end + d
            else:
                i = int(self._piece_index(sj))
                xy = self._xy_a[i] + self._integrate_piece(i, np.array(sj - p[i, 0]))
            # the plan view is shortened by cos(theta) on a gradient
            out[j, 0] = xy[0] * c_th
            out[j, 1] = xy[1] * c_th
            out[j, 2] = -sj * math.sin(self.theta_rad)
        return out

    def rotation(self, s) -> np.ndarray:
        """Rotation matrices R(s) (len(s), 3, 3): track-frame components -> global components."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        psi = self.heading(s)
        phi = self.cant_angle(s)
        th = self.theta_rad
        out = np.empty((s.shape[0], 3, 3))
        cy, sy = math.cos(th), math.sin(th)
        Ry = np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])
        for j in range(s.shape[0]):
            cz, sz = math.cos(psi[j]), math.sin(psi[j])
            cx, sx = math.cos(phi[j]), math.sin(phi[j])
            Rz = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
            Rx = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
            out[j] = Rz @ Ry @ Rx
        return out

    def frame_angular_velocity(self, s, speed_m_s: float) -> np.ndarray:
        """Ω of the track frame moving with V, track-frame components (len(s), 3) (module docstring)."""
        e = self.evaluate(s)
        k, phi, dphi = e[:, LAYOUT_KAPPA], e[:, LAYOUT_PHI], e[:, LAYOUT_DPHI]
        c_th, s_th = math.cos(self.theta_rad), math.sin(self.theta_rad)
        V = float(speed_m_s)
        return V * np.stack([dphi - k * s_th, k * c_th * np.sin(phi), k * c_th * np.cos(phi)], axis=1)

    def frame_angular_acceleration(self, s, speed_m_s: float) -> np.ndarray:
        """dΩ/dt (track-frame components, derivative of the components) at constant V, (len(s), 3); inside a
        linear cant ramp φ'' = φ'² tan φ (h' constant, φ = asin(h/b)); the steps of φ' at the ramp's ends are
        not impulses here."""
        e = self.evaluate(s)
        k, dk, phi, dphi = e[:, 0], e[:, 1], e[:, 2], e[:, 3]
        c_th, s_th = math.cos(self.theta_rad), math.sin(self.theta_rad)
        V2 = float(speed_m_s) ** 2
        return V2 * np.stack([dphi * dphi * np.tan(phi) - dk * s_th,
                              c_th * (dk * np.sin(phi) + k * np.cos(phi) * dphi),
                              c_th * (dk * np.cos(phi) - k * np.sin(phi) * dphi)], axis=1)

    def frame_acceleration(self, s, speed_m_s: float) -> np.ndarray:
        """Acceleration of the frame origin moving along the centre line at constant V, track-frame components
        (len(s), 3)."""
        e = self.evaluate(s)
        k, phi = e[:, LAYOUT_KAPPA], e[:, LAYOUT_PHI]
        a = float(speed_m_s) ** 2 * k * math.cos(self.theta_rad)
        return np.stack([np.zeros_like(a), a * np.cos(phi), -a * np.sin(phi)], axis=1)

    def gravity(self, s, g_m_s2: float) -> np.ndarray:
        """Gravity acceleration in track-frame components (len(s), 3)."""
        phi = self.cant_angle(s)
        c_th, s_th = math.cos(self.theta_rad), math.sin(self.theta_rad)
        g = float(g_m_s2)
        return np.stack([np.full_like(phi, -g * s_th), g * c_th * np.sin(phi), g * c_th * np.cos(phi)], axis=1)

    # --------------------------------------------------------------------------------------------- helpers
    @classmethod
    def curve_entry(cls, radius_m: float, cant_m: float, transition_m: float, *, direction: str = "right",
                    lead_in_m: float = 0.0, curve_m: float = 1e5, start_m: float = 0.0,
                    gradient: float = 0.0) -> "TrackLayout":
        """Straight ``lead_in_m``, transition ``transition_m``, then the curve (``curve_m`` long; continued after)."""
        secs = []
        if lead_in_m > 0.0:
            secs.append(Straight(lead_in_m))
        if transition_m > 0.0:
            secs.append(Transition(transition_m))
        secs.append(Curve(curve_m, radius_m, cant_m, direction))
        return cls(secs, start_m=start_m, gradient=gradient)

    def unbalanced_lateral_acceleration(self, s, speed_m_s: float, g_m_s2: float) -> np.ndarray:
        """a_nc = V²|κ| cos θ cos φ − g cos θ sin|φ| [m/s²], track plane, positive outwards (conventions)."""
        e = self.evaluate(s)
        k, phi = e[:, LAYOUT_KAPPA], e[:, LAYOUT_PHI]
        sign = np.where(k > 0.0, 1.0, np.where(k < 0.0, -1.0, np.sign(phi)))
        c_th = math.cos(self.theta_rad)
        return sign * (speed_m_s ** 2 * k * c_th * np.cos(phi) - g_m_s2 * c_th * np.sin(phi))


def curve_quantities(layout: TrackLayout, radius_m: float, cant_m: float, s_m: float, speed_m_s: float,
                     g_m_s2: float) -> dict:
    """What a vehicle engineer reads off a curve of ``radius_m`` and ``cant_m`` (>= 0) run at ``speed_m_s``:
    ``cant_angle_rad`` (``sin φ = h / 1.5 m``), ``unbalanced_lateral_acceleration_m_s2`` (a_nc of the layout at
    ``s_m``, a point of the circular curve: :meth:`TrackLayout.unbalanced_lateral_acceleration`, positive outwards)
    and ``balance_speed_km_h`` (the speed at which a_nc = 0 on the level, ``√(g tan φ R)``)."""
    phi = math.asin(cant_m / RAIL_CENTRE_DISTANCE_M)
    return {"cant_angle_rad": phi,
            "unbalanced_lateral_acceleration_m_s2": float(layout.unbalanced_lateral_acceleration([s_m], speed_m_s,
                                                                                                  g_m_s2)[0]),
            "balance_speed_km_h": math.sqrt(g_m_s2 * math.tan(phi) * radius_m) * 3.6}
