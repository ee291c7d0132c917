"""Placement of a wheel and rail profile pair for a wheelset on track (see :mod:`exudyn_wheelrail.conventions`).

:class:`WheelRailPair` turns profile-frame curves into *side-frame* curves:

* the rail, rotated by its inclination (head towards the track centre) and shifted so that its gauge point
  (the most inward point 14 mm below the top of rail) lies at ``gauge/2`` and its top at ``z = 0``;
* the wheel's tread and flange functions, in the wheelset frame (right-side convention): flange back at
  ``back_to_back/2``, tape circle at radius ``r0``.
"""
from __future__ import annotations

import numpy as np

from ..conventions import DEFAULT_BACK_TO_BACK_M, GAUGE_MEASURING_DEPTH_M, STANDARD_GAUGE_M, parse_inclination
from ..profiles.curve import ProfileCurve, pack_curves
from ..profiles.profiles import INCLINATION_TAN, RailProfile, WheelProfile, resolve_rail, resolve_wheel
from ..validation import Quantity

# Plausibility of the placement parameters (used by the pair, the vehicle files and the command line).
#: track gauge: 600 mm narrow gauge up to 1676 mm broad gauge, with margin
GAUGE_M = Quantity("track gauge", "m", 0.6, 1.8)
#: flange back-to-back distance (1.360 m for standard gauge; below the gauge, see back_to_back_problem)
BACK_TO_BACK_M = Quantity("flange back-to-back distance", "m", 0.5, 1.8)
#: nominal rolling radius: small tram and light-rail wheels (~0.15 m) up to large locomotive wheels (~0.65 m)
R0_M = Quantity("nominal rolling radius", "m", 0.1, 1.0)
#: gauge minus back-to-back distance: two flange thicknesses plus the play, > 0 and < 0.15 m
FLANGE_CLEARANCE_M = (0.0, 0.15)


def back_to_back_problem(gauge_m: float, back_to_back_m: float, gauge_name: str = "the gauge") -> str | None:
    """Why a back-to-back distance does not fit the gauge (it must lie below it by :data:`FLANGE_CLEARANCE_M`: two
    flanges and their play), or None; ``gauge_name`` names the gauge in the message."""
    lo, hi = FLANGE_CLEARANCE_M
    if lo < gauge_m - back_to_back_m < hi:
        return None
    return (f"{back_to_back_m:g} m must be below {gauge_name} {gauge_m:g} m by more than {lo:g} and less than "
            f"{hi:g} m (two flanges and their play)")


def gauge_point(curve: ProfileCurve, depth_m: float = GAUGE_MEASURING_DEPTH_M, spacing_m: float = 2e-6):
    """Top-of-rail height and gauge point (y, z) of a rail curve already in side-frame orientation."""
    s = np.linspace(curve.s_min, curve.s_max, max(1000, int(curve.length / spacing_m)))
    p = curve.position(s)
    z_top = float(np.min(p[:, 1]))
    z_gauge = z_top + depth_m
    below = p[:, 1] >= z_gauge
    if not below.any() or below.all():
        raise ValueError(f"{curve.name}: the rail profile does not reach {depth_m * 1e3:.0f} mm below its top; "
                         "the gauge point cannot be found")
    # the gauge point is the most inward point of the head at the measuring depth: first crossing from the top
    i_top = int(np.argmin(p[:, 1]))
    k = i_top
    while k > 0 and p[k, 1] < z_gauge:
        k -= 1
    f = (z_gauge - p[k + 1, 1]) / (p[k, 1] - p[k + 1, 1])
    y_gauge = float(p[k + 1, 0] + f * (p[k, 0] - p[k + 1, 0]))
    return z_top, y_gauge


class WheelRailPair:
    """Wheel and rail profiles placed for one wheelset on track (both sides use the same profiles).

    Parameters
    ----------
    wheel, rail : profile objects, or 'S1002' / 'UIC60', or file paths.
    gauge_m : track gauge measured 14 mm below the top of rail.
    inclination : rail inclination, '1/40', '1/20', 'none' or tan of the angle.  A rail profile that is already
        canted (``RailProfile.canted_tan``) is rotated only by the difference.
    back_to_back_m : wheel flange back-to-back distance.
    r0_m : nominal rolling (tape circle) radius.
    """

    def __init__(self, wheel="S1002", rail="UIC60", gauge_m: float = STANDARD_GAUGE_M, inclination="1/40",
                 back_to_back_m: float = DEFAULT_BACK_TO_BACK_M, r0_m: float = 0.46):
        # the numbers first (cheap), then the profiles
        self.gauge_m = GAUGE_M.check("gauge_m", gauge_m)
        self.back_to_back_m = BACK_TO_BACK_M.check("back_to_back_m", back_to_back_m)
        problem = back_to_back_problem(self.gauge_m, self.back_to_back_m)
        if problem:
            raise ValueError(f"back_to_back_m: {problem}")
        self.r0_m = R0_M.check("r0_m", r0_m)
        try:
            tan = parse_inclination(inclination)
        except ValueError as exc:
            raise ValueError(f"inclination: {exc}") from None
        self.inclination_tan = INCLINATION_TAN.check("inclination", tan)
        self.wheel: WheelProfile = resolve_wheel(wheel)
        self.rail: RailProfile = resolve_rail(rail)
        # rail: rotate towards the track centre by the net inclination, then place the gauge point and the top
        cant_rad = np.arctan(self.inclination_tan) - np.arctan(self.rail.canted_tan)
        rotated = self.rail.curve.transformed(-cant_rad)
        z_top, y_gauge = gauge_point(rotated)
        self.rail_side = rotated.transformed(0.0, (0.5 * self.gauge_m - y_gauge, -z_top), name=f"{self.rail.name}:side")
        # wheel: flange back at back_to_back/2, tape circle at radius r0
        self.wheel_offset_y_m = 0.5 * self.back_to_back_m - self.wheel.flange_back_y_m
        offset = (self.wheel_offset_y_m, self.r0_m)
        self.tread_side = self.wheel.tread.transformed(0.0, offset, name=f"{self.wheel.name}:tread:side")
        self.flange_side = (None if self.wheel.flange is None else
                            self.wheel.flange.transformed(0.0, offset, name=f"{self.wheel.name}:flange:side"))

    def packed(self):
        """(nodes, meta) with curve 0 = rail, 1 = tread, 2 = flange (side frame; absent for a flangeless wheel)."""
        return pack_curves([c for c in (self.rail_side, self.tread_side, self.flange_side) if c is not None])

    def nominal_axle_height_m(self) -> float:
        """Axle centre z (negative: above the rail top) when the tape circles touch a flat rail top."""
        return -self.r0_m

    def profile_coordinates(self, s_wheel_m: float, s_rail_m: float) -> tuple[float, float]:
        """Lateral coordinates of a contact in the wheel's and the rail's own profile frames, from the surface
        parameters (the side-frame curves share the arc length of their profile curves)."""
        return (float(self.wheel.curve.position([s_wheel_m])[0, 0]),
                float(self.rail.curve.position([s_rail_m])[0, 0]))

    def __repr__(self) -> str:
        return (f"WheelRailPair({self.wheel.name} on {self.rail.name} 1:{1 / self.inclination_tan:.0f}, "
                f"gauge {self.gauge_m:.4f} m, back-to-back {self.back_to_back_m:.4f} m, r0 {self.r0_m:.3f} m)"
                if self.inclination_tan else
                f"WheelRailPair({self.wheel.name} on {self.rail.name} vertical, gauge {self.gauge_m:.4f} m, "
                f"back-to-back {self.back_to_back_m:.4f} m, r0 {self.r0_m:.3f} m)")
