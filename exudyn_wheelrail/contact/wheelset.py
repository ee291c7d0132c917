"""Python front of the contact kernel: wheelsets on a rigid track, readable results.

>>> from exudyn_wheelrail.contact import WheelsetContact
>>> contact = WheelsetContact(WheelRailPair("S1002", "UIC60", inclination="1/40"))   # doctest: +SKIP
>>> points = contact.contact_points(y_m=0.002, z_m=-0.46, roll_rad=0.0)            # doctest: +SKIP

Wheel order in every array: wheelset k has wheel ``2k`` (right) and ``2k+1`` (left).  The kernel works in side
frames; this module converts to and from the track frame (:mod:`exudyn_wheelrail.conventions`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..contact_defaults import CONTACT_PATCH, CONTACT_PATCHES
from ..jit import compile_ahead
from ..validation import poisson_ratio, youngs_modulus
from . import kernel as K
from .normal import E_STEEL as E_STEEL_PA
from .normal import NU_STEEL, effective_modulus
from .pair import WheelRailPair
from .patch_table import PatchTableGrid, patch_argument, patch_contacts, patch_table
from .search import monotone_rows

#: the entries of a wheelset pose (track frame), in the order of the pose arrays
POSE_ENTRIES = ("y_m", "z_m", "roll_rad")

REGIONS = ("tread", "flange")
#: region of each kernel output slot (K.SLOT_*): tread, flange, and the tread's second zone (two-point tread contact)
SLOT_REGIONS = ("tread", "flange", "tread")
SIDES = ("right", "left")
STATUS_NAMES = {K.STATUS_SEPARATED: "separated", K.STATUS_CONVEX: "convex", K.STATUS_CONCAVE: "concave",
                K.STATUS_NO_OVERLAP: "no-overlap", K.STATUS_MERGED: "merged", K.STATUS_INVALID_POSE: "invalid-pose"}


@dataclass(frozen=True)
class ContactPoint:
    """One wheel–rail contact point of a wheel region, track frame, SI units."""

    side: str                    # 'right' / 'left'
    region: str                  # 'tread' / 'flange'
    method: str                  # 'convex' / 'concave' (which search found it)
    p_wheel_in_track: np.ndarray  # (y, z) of the wheel surface point [m]
    p_rail_in_track: np.ndarray   # (y, z) of the rail surface point [m]
    n_rail_in_track: np.ndarray   # outward rail normal (y, z)
    y_wheel_profile_m: float     # lateral coordinate of the contact in the wheel's profile frame
    y_rail_profile_m: float      # lateral coordinate of the rail contact in the rail's profile frame
    s_wheel_m: float             # wheel surface parameter (arc length)
    s_rail_m: float              # rail surface parameter (arc length)
    penetration_m: float         # delta > 0: interpenetration
    contact_angle_rad: float     # positive towards the flange (track centre)
    rolling_radius_m: float
    curvature_wheel_lateral: float   # [1/m], convex positive
    curvature_wheel_rolling: float
    curvature_rail_lateral: float
    curvature_rail_rolling: float
    semi_axis_a_m: float         # along rolling
    semi_axis_b_m: float         # lateral
    normal_force_N: float
    dN_ddelta_N_per_m: float


class WheelsetContact:
    """Contact of ``n_wheelsets`` wheelsets, all with the same wheel/rail pair, with a rigid track.

    Parameters
    ----------
    pair : the placed profiles.
    n_wheelsets : number of wheelsets evaluated in one call.
    E_wheel_Pa, nu_wheel, E_rail_Pa, nu_rail : materials (steel by default).
    global_search : run the coarse vertical scan at every evaluation (follows contact jumps; a quasi-static
        sweep needs it) instead of warm-starting from the last solution.
    n_concave_wheel, n_concave_rail : discretisation of the concave search (points per wheel region / rail).
    refine : refine the concave search's maximum on the continuous curves (otherwise the discrete paper method).
    contact_patch : "hertz" (Hertz's ellipse at each contact point) or "non-hertzian" (the patch where Hertz does
        not hold: :mod:`~exudyn_wheelrail.contact.patch_pass`; its rows then carry the patch's resultant).
    """

    def __init__(self, pair: WheelRailPair, n_wheelsets: int = 1, E_wheel_Pa: float = E_STEEL_PA,
                 nu_wheel: float = NU_STEEL, E_rail_Pa: float = E_STEEL_PA, nu_rail: float = NU_STEEL,
                 global_search: bool = False, n_scan: int = 200, n_concave_wheel: int = 100, n_concave_rail: int = 100,
                 refine: bool = True, contact_patch: str = CONTACT_PATCH):
        if not isinstance(pair, WheelRailPair):
            raise TypeError(f"pair: expected a WheelRailPair, got {type(pair).__name__}")
        if isinstance(n_wheelsets, bool) or int(n_wheelsets) != n_wheelsets or n_wheelsets < 1:
            raise ValueError(f"n_wheelsets: expected a positive integer, got {n_wheelsets!r}")
        if contact_patch not in CONTACT_PATCHES:
            raise ValueError(f"contact_patch={contact_patch!r}: expected one of {CONTACT_PATCHES}")
        #: the patch's argument (:func:`~exudyn_wheelrail.contact.patch_table.patch_argument`; its patches solved
        #: online until :meth:`use_patch_table`), None for Hertz
        self.patch = patch_argument() if contact_patch == "non-hertzian" else None
        self.contact_patch = contact_patch
        E_wheel_Pa = youngs_modulus("E_wheel_Pa", E_wheel_Pa)
        E_rail_Pa = youngs_modulus("E_rail_Pa", E_rail_Pa)
        nu_wheel = poisson_ratio("nu_wheel", nu_wheel)
        nu_rail = poisson_ratio("nu_rail", nu_rail)
        self.pair = pair
        self.n_wheelsets = int(n_wheelsets)
        self.nodes, self.meta = pair.packed()
        self.mono = np.array([monotone_rows(self.nodes[int(m[0]):int(m[0] + m[1])], int(m[0])) for m in self.meta],
                             dtype=np.int64)
        n_wheels = 2 * self.n_wheelsets
        flange_id = 2 if pair.flange_side is not None else -1
        self.curve_ids = np.tile(np.array([0, 1, flange_id], dtype=np.int64), (n_wheels, 1))
        self.E_star = effective_modulus(E_wheel_Pa, nu_wheel, E_rail_Pa, nu_rail)
        wheel_curves = [c for c in (pair.tread_side, pair.flange_side) if c is not None]
        lever = max(float(np.max(np.hypot(c.nodes[:, 1], c.nodes[:, 2]))) for c in wheel_curves)
        # bound of |kappa_w| + |kappa_r| for the gap bound's sampling margin (1.25 x the largest node curvature)
        kappa_max = (max(float(np.max(np.abs(c.curvature(c.nodes[:, 0])))) for c in wheel_curves)
                     + float(np.max(np.abs(pair.rail_side.curvature(pair.rail_side.nodes[:, 0])))))
        self.params = K.default_params(self.E_star, global_search=global_search, n_scan=n_scan,
                                       n_concave_wheel=n_concave_wheel, n_concave_rail=n_concave_rail, refine=refine,
                                       wheel_lever_m=lever, curvature_bound=1.25 * kappa_max)
        #: the coarse scan's wheel points (the kernel places them instead of evaluating the wheel curve)
        self.scan = K.scan_array(self.nodes, self.meta, self.params[K.P_N_SCAN])
        self.warm = np.full((n_wheels, 2, K.N_WARM), np.nan)
        self.out = np.zeros((n_wheels, K.N_SLOTS, K.N_FIELDS))
        self._side_poses = np.zeros((n_wheels, 3))
        self._first_call = True
        #: last evaluated wheelset poses (y, z, roll); nominal height at start
        self.poses = np.tile([0.0, pair.nominal_axle_height_m(), 0.0], (self.n_wheelsets, 1))

    def use_patch_table(self, grid: PatchTableGrid | None = None):
        """Read the non-Hertzian patch from its table (:mod:`~exudyn_wheelrail.contact.patch_table`, built or loaded
        from the cache) instead of solving it at every evaluation; needs ``contact_patch="non-hertzian"`` and the
        same curves on every wheel.  Returns the table."""
        if self.patch is None:
            raise ValueError("use_patch_table: the contact was built with contact_patch='hertz'")
        if not np.all(self.curve_ids == self.curve_ids[0]):
            raise ValueError("use_patch_table: the table needs the same wheel/rail curves on every wheel")
        table = patch_table(self.nodes, self.meta, self.mono, self.curve_ids[0], self.params, self.patch[0][0], grid)
        self.patch = patch_argument(table, self.patch[0][0])
        return table

    def reset(self):
        """Forget the warm start (and the separation bounds)."""
        self.warm[:] = np.nan

    def checked_poses(self, poses) -> np.ndarray:
        """Wheelset poses as an (n_wheelsets, 3) float array (y_m, z_m, roll_rad per wheelset, track frame);
        ``ValueError`` for another size or a non-finite entry, naming the wheelset and the entry."""
        try:
            arr = np.asarray(poses, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"wheelset poses: expected numbers (y_m, z_m, roll_rad per wheelset), got "
                             f"{poses!r}") from None
        if arr.size != 3 * self.n_wheelsets:
            raise ValueError(f"wheelset poses: expected {self.n_wheelsets} pose(s) of 3 entries "
                             f"({', '.join(POSE_ENTRIES)}), got {arr.size} number(s) (shape {arr.shape})")
        arr = arr.reshape(self.n_wheelsets, 3)
        if not np.isfinite(arr).all():
            bad = np.argwhere(~np.isfinite(arr))
            k, j = (int(v) for v in bad[0])
            value = arr[k, j]
            what = "NaN" if np.isnan(value) else "infinity" if value > 0 else "-infinity"
            raise ValueError(f"wheelset {k} pose: {POSE_ENTRIES[j]} is {what} (NaN or infinity is not a pose; "
                             f"{len(bad)} such entr{'y' if len(bad) == 1 else 'ies'})")
        return arr

    def side_poses(self, poses: np.ndarray) -> np.ndarray:
        """Wheelset poses (n, 3) (y, z, roll) in the track frame -> per-wheel side-frame poses (2n, 3)."""
        return self._fill_side_poses(self.checked_poses(poses))

    def _fill_side_poses(self, poses: np.ndarray) -> np.ndarray:
        sp = self._side_poses
        sp[0::2] = poses
        sp[1::2, 0] = -poses[:, 0]
        sp[1::2, 1] = poses[:, 1]
        sp[1::2, 2] = -poses[:, 2]
        return sp

    def evaluate(self, poses) -> np.ndarray:
        """Raw kernel output (2n, N_SLOTS, N_FIELDS) for wheelset poses (n, 3) = (y, z, roll); side frames."""
        poses = self.checked_poses(poses)
        if self._first_call:            # a first run: the kernel's callees compiled in two processes, if it can
            self._first_call = False
            args = (self.nodes, self.meta, self.mono, self.curve_ids, self._side_poses, self.warm, self.params,
                    self.out, self.scan)
            compile_ahead(K.evaluate_wheels, args, *K.compile_shares(*args)).wait()
        K.evaluate_wheels(self.nodes, self.meta, self.mono, self.curve_ids, self._fill_side_poses(poses), self.warm,
                          self.params, self.out, self.scan)
        if self.patch is not None:
            patch_contacts(self.nodes, self.meta, self.curve_ids, self._side_poses, self.params, self.out, self.patch)
        self.poses[:] = poses
        return self.out

    def contact_points(self, y_m: float, z_m: float, roll_rad: float = 0.0, wheelset: int = 0,
                       include_separated: bool = False) -> list[ContactPoint]:
        """Readable contact points of one wheelset pose (track frame); other wheelsets keep their last pose."""
        if isinstance(wheelset, bool) or int(wheelset) != wheelset or not 0 <= wheelset < self.n_wheelsets:
            raise ValueError(f"wheelset: expected an index 0 ... {self.n_wheelsets - 1}, got {wheelset!r}")
        poses = self.poses.copy()
        poses[wheelset] = (y_m, z_m, roll_rad)
        out = self.evaluate(poses)
        return self.points_from_output(out, wheelset, include_separated)

    def points_from_output(self, out, wheelset: int = 0, include_separated: bool = False) -> list[ContactPoint]:
        points = []
        for side_index, side in enumerate(SIDES):
            w = 2 * wheelset + side_index
            mirror = 1.0 if side == "right" else -1.0
            for reg, region in enumerate(SLOT_REGIONS):
                o = out[w, reg]
                status = int(o[K.F_STATUS])
                if status <= 0 and not (include_separated and status == K.STATUS_SEPARATED):
                    continue
                s_w = o[K.F_S_WHEEL]
                y_wheel_profile, y_rail_profile = self.pair.profile_coordinates(s_w, o[K.F_S_RAIL])
                points.append(ContactPoint(
                    side=side, region=region, method=STATUS_NAMES.get(status, "separated") if status > 0 else "separated",
                    p_wheel_in_track=np.array([mirror * o[K.F_PW_Y], o[K.F_PW_Z]]),
                    p_rail_in_track=np.array([mirror * o[K.F_PR_Y], o[K.F_PR_Z]]),
                    n_rail_in_track=np.array([mirror * o[K.F_NR_Y], o[K.F_NR_Z]]),
                    y_wheel_profile_m=y_wheel_profile, y_rail_profile_m=y_rail_profile,
                    s_wheel_m=float(s_w), s_rail_m=float(o[K.F_S_RAIL]),
                    penetration_m=float(o[K.F_PENETRATION]), contact_angle_rad=float(o[K.F_CONTACT_ANGLE]),
                    rolling_radius_m=float(o[K.F_ROLLING_RADIUS]),
                    curvature_wheel_lateral=float(o[K.F_KW_LAT]), curvature_wheel_rolling=float(o[K.F_KW_ROLL]),
                    curvature_rail_lateral=float(o[K.F_KR_LAT]), curvature_rail_rolling=float(o[K.F_KR_ROLL]),
                    semi_axis_a_m=float(o[K.F_SEMI_A]), semi_axis_b_m=float(o[K.F_SEMI_B]),
                    normal_force_N=float(o[K.F_NORMAL_FORCE]), dN_ddelta_N_per_m=float(o[K.F_DN_DDELTA])))
        return points
