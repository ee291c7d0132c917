"""Wheel and rail profiles: the curves the contact search works on.

A :class:`WheelProfile` is split, as in Montenegro et al. (2015, Sec. 2.1), into two functions — the **tread** and
the **flange** — so that each can carry its own contact point.  The split lies in the concave throat between them
(by default the middle of the concave stretch next to the flange, where neither region can hold a convex contact).
A :class:`RailProfile` is one curve.  Both live in their profile frames (:mod:`exudyn_wheelrail.conventions`).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .curve import ProfileCurve
from .dense import DenseProfile
from .readers import load_profile
from .standard import S1002_FLANGE_BACK_Y_M, s1002_dense, uic60_dense
from ..validation import Quantity
from .validation import FLANGE_HEIGHT_RANGE_M, FLANGE_TIP_MAX_Y_M, ProfileError, check_profile_kind


#: Flange back relative to the tape circle for EN 13715 wheel profiles [m].
DEFAULT_FLANGE_BACK_Y_M = -0.070
#: Built-in profiles by name (upper case; :func:`resolve_wheel`, :func:`resolve_rail`): anything else is a file.
WHEEL_PROFILE_NAMES = ("S1002",)
RAIL_PROFILE_NAMES = ("UIC60", "60E1")


class WheelProfile:
    """A wheel profile in its profile frame (y to the field side, z = radius increase), split into tread/flange.

    Parameters
    ----------
    curve : the whole profile, arc length increasing from the flange back to the field side.
    flange_back_y_m : lateral coordinate of the flange back face in the profile frame.  Default -0.070 m: the tape
        circle lies 70 mm from the flange back for the EN 13715 profiles (S1002 and others).  It is a fixed datum
        of the profile frame, not inferred from the points (point files often stop short of the back face).
    split_y_m : lateral coordinate of the tread/flange split; ``None`` finds it in the throat (see module doc) and
        checks that the flange is a plausible one (15-45 mm high, on the flange side): a profile in the wrong units
        or frame is an error.  An explicit split is taken as stated.
    """

    def __init__(self, curve: ProfileCurve, flange_back_y_m: float | None = None, split_y_m: float | None = None,
                 name: str = "wheel"):
        self.curve = curve
        self.name = name
        s_nodes = curve.nodes[:, 0]
        p = curve.evaluate(s_nodes)
        if flange_back_y_m is None:
            flange_back_y_m = DEFAULT_FLANGE_BACK_Y_M
        self.flange_back_y_m = float(flange_back_y_m)
        i_tip = int(np.argmax(p[:, 1]))               # flange tip: largest radius increase
        self.flange_tip_y_m = float(p[i_tip, 0])
        self.flange_height_m = float(p[i_tip, 1] - np.interp(0.0, p[:, 0][i_tip:], p[:, 1][i_tip:]))
        if split_y_m is None:
            s_split = self._find_split(s_nodes[i_tip:], p[i_tip:])
        else:
            s_split = self.s_at_y(split_y_m)
        self.split_s = float(s_split)
        self.split_y_m = float(curve.position([s_split])[0, 0])
        #: the flange function; None for a profile without a flange (the whole curve is tread)
        self.flange = None if s_split <= curve.s_min else curve.sub(curve.s_min, s_split, name=f"{name}:flange")
        self.tread = curve if s_split <= curve.s_min else curve.sub(s_split, curve.s_max, name=f"{name}:tread")
        if self.flange is not None:
            self.flange.end_flags = 1          # flange back end is a profile end, the split is not
            self.tread.end_flags = 2           # field-side end is a profile end, the split is not
            lo, hi = FLANGE_HEIGHT_RANGE_M
            if split_y_m is None and not (lo <= self.flange_height_m <= hi
                                          and self.flange_tip_y_m < FLANGE_TIP_MAX_Y_M):
                raise ValueError(
                    f"{name}: flange height {self.flange_height_m * 1e3:.2f} mm with its tip at y = "
                    f"{self.flange_tip_y_m * 1e3:.2f} mm; expected a wheel profile in metres with the origin at the "
                    "tape circle, y to the field side and z = radius increase (flange "
                    f"{lo * 1e3:g}-{hi * 1e3:g} mm high, at y < {FLANGE_TIP_MAX_Y_M * 1e3:g} mm)")
            # steepest point of the flange flank (largest contact angle); a contact beyond it towards the tip means
            # the flange has ridden up past its flank (climbing)
            s_f = np.linspace(self.flange.s_min, self.flange.s_max, 4001)
            e_f = self.flange.evaluate(s_f)
            tip_side = e_f[:, 0] > self.flange_tip_y_m
            slope = np.abs(np.arctan2(e_f[:, 3], e_f[:, 2]))
            self.flank_y_m = float(e_f[tip_side, 0][np.argmax(slope[tip_side])])
            self.flank_angle_rad = float(np.max(slope[tip_side]))
        else:
            self.flank_y_m = float("nan")
            self.flank_angle_rad = float("nan")

    @staticmethod
    def _find_split(s, p):
        """Middle of the strongly concave throat between the flange tip and the tape circle.

        The throat is the stretch around the most concave point whose curvature is below half that extreme
        (S1002: the R13 fillet, section D).  A profile without a throat (e.g. a pure cone) is split where the
        slope leaves 1 rad, or at its flange-side end.
        """
        kappa = p[:, 6]
        flange_side = np.flatnonzero(p[:, 0] <= 0.0)
        if p[0, 3] < 0.7 and p[0, 1] <= p[min(len(p) - 1, 1), 1] + 1e-12 and not np.any(kappa < -1.0):
            return float(s[0])      # no flange: the profile never rises steeply towards the flange side
        k_min = kappa[flange_side].min() if flange_side.size else 0.0
        if k_min >= -1.0:          # no throat more concave than 1 m radius
            steep = np.flatnonzero(np.abs(np.arctan2(p[:, 3], p[:, 2])) > 1.0)
            return float(s[steep[-1]] if steep.size else s[0])
        i_min = flange_side[np.argmin(kappa[flange_side])]
        start = end = i_min
        while start > 0 and kappa[start - 1] < 0.5 * k_min:
            start -= 1
        while end + 1 < len(kappa) and kappa[end + 1] < 0.5 * k_min:
            end += 1
        return float(0.5 * (s[start] + s[end]))

    def s_at_y(self, y_m: float) -> float:
        """Arc length of the tread-side point with lateral coordinate ``y_m`` (after the flange tip)."""
        s = np.linspace(self.curve.s_min, self.curve.s_max, 20001)
        p = self.curve.position(s)
        i_tip = int(np.argmax(p[:, 1]))
        ys = p[i_tip:, 0]
        if not (ys[0] <= y_m <= ys[-1]):
            raise ValueError(f"{self.name}: y = {y_m} m outside the tread side [{ys[0]}, {ys[-1]}] m")
        return float(np.interp(y_m, ys, s[i_tip:]))

    # ------------------------------------------------------------------------------------------- factories
    @classmethod
    def from_dense(cls, dense: DenseProfile, node_spacing_m: float = 2.5e-4, **kw) -> "WheelProfile":
        """A wheel profile from dense profile-frame samples; a rail head given here is an error
        (:func:`~.validation.check_profile_kind`)."""
        kw.setdefault("name", dense.name)
        check_profile_kind(dense.y, dense.z, "wheel", kw["name"])
        return cls(ProfileCurve.from_dense(dense, outward="+z", node_spacing_m=node_spacing_m), **kw)

    @classmethod
    def s1002(cls, **kw) -> "WheelProfile":
        """The S1002 wheel (EN 13715), exact analytic definition."""
        kw.setdefault("flange_back_y_m", S1002_FLANGE_BACK_Y_M)
        kw.setdefault("name", "S1002")
        return cls.from_dense(s1002_dense(), **kw)

    @classmethod
    def from_file(cls, path, smoothing=None, **kw) -> "WheelProfile":
        """A wheel profile from a SIMPACK ``.prw`` file or a two-column y-z table (see :mod:`.readers`)."""
        kw.setdefault("name", Path(path).stem)
        return cls.from_dense(load_profile(path, kind="wheel", smoothing=smoothing), **kw)

    @classmethod
    def cone(cls, conicity: float, half_width_m: float = 0.05, flange_back_y_m: float = -0.070,
             name: str = "cone") -> "WheelProfile":
        """A pure cone (straight profile z = -conicity * y) without flange: for analytic checks."""
        y = np.linspace(-half_width_m, half_width_m, 4001)
        one = np.ones_like(y)
        dense = DenseProfile(y, -conicity * y, one, -conicity * one, 0 * y, 0 * y, name=name)
        return cls(ProfileCurve.from_dense(dense, "+z"), flange_back_y_m=flange_back_y_m, split_y_m=None,
                   name=name)

    def __repr__(self) -> str:
        if self.flange is None:
            return f"WheelProfile({self.name!r}: no flange)"
        return (f"WheelProfile({self.name!r}: flange back y={self.flange_back_y_m * 1e3:.2f} mm, "
                f"tread/flange split y={self.split_y_m * 1e3:.2f} mm, flange height {self.flange_height_m * 1e3:.2f} mm)")


#: Inclinations a rail profile's data are recognised to contain (tan of the angle).
STANDARD_CANTS = (0.0, 1.0 / 40.0, 1.0 / 30.0, 1.0 / 20.0)
#: rail inclination (tan of the cant angle): vertical up to 1:10
INCLINATION_TAN = Quantity("rail inclination (tan of the cant angle)", "", 0.0, 0.1)


class RailProfile:
    """A rail head profile in its profile frame (y to the field side, z down from the top).

    ``canted_tan`` is the inclination the *data* already contain (tan of the angle; a canted point file such as
    the Manchester UIC60).  ``None`` (default for files) detects it from the head's shape: on a vertical rail the
    crown top lies on the head's centre line; tilted towards the track centre by alpha, the top moves towards the
    field side by about (R_crown - d) tan(alpha), d being the depth where the head's centre is measured.  The
    estimate is snapped to 0, 1:40, 1:30 or 1:20 (within 0.004); anything else is an error asking to state it,
    so a canted file is never inclined twice without notice.  A stated ``canted_tan`` is checked against the
    estimate (within 0.01) unless ``worn=True``: on a worn head (a high rail's gauge corner worn away) the crown top
    no longer marks the inclination, and the stated value is taken as it is.
    """

    def __init__(self, curve: ProfileCurve, name: str = "rail", canted_tan: float | None = 0.0, worn: bool = False):
        self.curve = curve
        self.name = name
        self.estimated_cant_tan = self.estimate_cant_tan()
        if canted_tan is not None:
            canted_tan = INCLINATION_TAN.check(f"{name}: canted_tan", canted_tan)
        if worn and canted_tan is None:
            raise ValueError(f"{name}: a worn rail head needs the inclination its data contain stated "
                             "(canted_tan= / --rail-canted): its crown does not show it")
        if canted_tan is None:
            near = [c for c in STANDARD_CANTS if abs(c - self.estimated_cant_tan) < 0.004]
            if not near:
                raise ValueError(
                    f"{name}: the rail head looks inclined by tan = {self.estimated_cant_tan:.4f} (crown top off the "
                    "head centre line), which is not 0, 1:40, 1:30 or 1:20; state the inclination the data contain "
                    "(canted_tan= / --rail-canted; for a worn head also RailProfile(worn=True) / --rail-worn) — or check the "
                    "profile's lateral orientation (y to the field side)")
            canted_tan = near[0]
        elif not worn and abs(float(canted_tan) - self.estimated_cant_tan) > 0.01:
            raise ValueError(
                f"{name}: stated inclination of the data tan = {float(canted_tan):.4f} but the head looks inclined by "
                f"tan = {self.estimated_cant_tan:.4f}; check canted_tan / --rail-canted and the profile orientation "
                "(a worn head, whose crown does not show it: RailProfile(worn=True) / --rail-worn)")
        #: inclination already contained in the data, tan of the angle
        self.canted_tan = float(canted_tan)

    def estimate_cant_tan(self, depth_m: float = 0.010) -> float:
        """Inclination contained in the data, from the crown top's offset to the head centre ``depth_m`` below it."""
        s = np.linspace(self.curve.s_min, self.curve.s_max, 40001)
        e = self.curve.evaluate(s)
        i_top = int(np.argmin(e[:, 1]))
        z_line = e[i_top, 1] + depth_m
        left = np.flatnonzero(e[:i_top, 1] >= z_line)
        right = np.flatnonzero(e[i_top:, 1] >= z_line)
        if left.size == 0 or right.size == 0 or e[i_top, 6] <= 0:
            return float("nan")
        y_mid = 0.5 * (e[left[-1], 0] + e[i_top + right[0], 0])
        radius = 1.0 / e[i_top, 6]
        return float((e[i_top, 0] - y_mid) / (radius - depth_m))

    @classmethod
    def from_dense(cls, dense: DenseProfile, node_spacing_m: float = 2.5e-4, **kw) -> "RailProfile":
        """A rail profile from dense profile-frame samples; a wheel profile given here is an error
        (:func:`~.validation.check_profile_kind`)."""
        kw.setdefault("name", dense.name)
        check_profile_kind(dense.y, dense.z, "rail", kw["name"])
        return cls(ProfileCurve.from_dense(dense, outward="-z", node_spacing_m=node_spacing_m), **kw)

    @classmethod
    def uic60(cls, **kw) -> "RailProfile":
        """The UIC60 / 60E1 rail head (EN 13674-1), exact arc definition."""
        kw.setdefault("name", "UIC60")
        return cls.from_dense(uic60_dense(), **kw)

    @classmethod
    def from_file(cls, path, smoothing=None, canted_tan: float | None = None, **kw) -> "RailProfile":
        """A rail profile from a SIMPACK ``.prr`` file or a y-z table; ``canted_tan`` is the inclination the data
        already contain (the Manchester UIC60 file is canted 1:40), detected when None, so it is not applied twice
        (``worn=True``: stated, not checked; the class docstring)."""
        kw.setdefault("name", Path(path).stem)
        return cls.from_dense(load_profile(path, kind="rail", smoothing=smoothing), canted_tan=canted_tan, **kw)

    @classmethod
    def circular_crown(cls, radius_m: float, half_width_m: float = 0.03, name: str = "crown") -> "RailProfile":
        """A circular crown of radius ``radius_m`` (for analytic checks)."""
        th = np.linspace(-half_width_m / radius_m, half_width_m / radius_m, 6001)
        r = radius_m
        dense = DenseProfile(r * np.sin(th), r * (1 - np.cos(th)), r * np.cos(th), r * np.sin(th),
                             -r * np.sin(th), r * np.cos(th), name=name)
        return cls(ProfileCurve.from_dense(dense, "-z"), name=name)

    def __repr__(self) -> str:
        return f"RailProfile({self.name!r}, {self.curve!r})"


def profile_spec_problem(spec, kind: str) -> str | None:
    """Why ``spec`` names no ``kind`` ('wheel' / 'rail') profile — neither a built-in name
    (:data:`WHEEL_PROFILE_NAMES`, :data:`RAIL_PROFILE_NAMES`) nor an existing file — or None."""
    names = WHEEL_PROFILE_NAMES if kind == "wheel" else RAIL_PROFILE_NAMES
    if str(spec).strip().upper() in names:
        return None
    path = Path(spec)
    if path.is_file():
        return None
    if path.is_dir():
        return f"{str(spec)!r} is a directory, not a {kind} profile file"
    return f"{str(spec)!r} is neither a built-in {kind} profile ({', '.join(names)}) nor an existing file"


def resolve_wheel(spec) -> WheelProfile:
    """A :class:`WheelProfile` from a profile object, a built-in name (:data:`WHEEL_PROFILE_NAMES`) or a file path;
    :class:`~.validation.ProfileError` for anything else."""
    if isinstance(spec, WheelProfile):
        return spec
    problem = profile_spec_problem(spec, "wheel")
    if problem:
        raise ProfileError(f"wheel: {problem}")
    if str(spec).strip().upper() == "S1002":
        return WheelProfile.s1002()
    return WheelProfile.from_file(spec)


def resolve_rail(spec, canted_tan: float | None = None, worn: bool = False) -> RailProfile:
    """A :class:`RailProfile` from a profile object, a built-in name (:data:`RAIL_PROFILE_NAMES`: 'UIC60'/'60E1')
    or a file path (``worn``: :class:`RailProfile`'s); :class:`~.validation.ProfileError` for anything else."""
    if isinstance(spec, RailProfile):
        return spec
    problem = profile_spec_problem(spec, "rail")
    if problem:
        raise ProfileError(f"rail: {problem}")
    if str(spec).strip().upper() in RAIL_PROFILE_NAMES:
        return RailProfile.uic60(canted_tan=0.0 if canted_tan is None else canted_tan)
    return RailProfile.from_file(spec, canted_tan=canted_tan, worn=worn)
