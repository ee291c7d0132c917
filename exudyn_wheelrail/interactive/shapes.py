"""Cross-sections and meshes for the 3-D view, built from the profiles in place (numpy only, no Exudyn).

Frames (:mod:`exudyn_wheelrail.conventions`): the *side frame* of :class:`~exudyn_wheelrail.contact.WheelRailPair`
(right-side convention: y outwards from the track centre line, z down, origin at rail-top height on the centre
line) for the 2-D sections; the model/track frame (x forward, y right, z down) for the swept meshes.  Metres.

* :func:`wheel_contour` — the wheel as a solid of revolution: the actual wheel profile (flange and tread) as the
  rim's outer surface, closed by a rim, a web and a hub of stated, simplified proportions;
* :func:`rail_section` — the rail: the actual rail-head profile (as inclined and placed by the pair) closed by a
  simplified UIC60 web and foot (nominal dimensions of EN 13674-1 60E1: height 172 mm, foot 150 mm, web 16.5 mm);
* :func:`swept_mesh` — a closed section swept along x with a lateral/vertical offset per station (the track
  irregularity, a deck deflection), as points and triangles with outward winding.
"""
from __future__ import annotations

import numpy as np

__all__ = ["RAIL_HEIGHT_M", "RAIL_FOOT_WIDTH_M", "RAIL_WEB_THICKNESS_M", "wheel_contour", "rail_section",
           "mirror_section", "swept_mesh", "rectangle_section", "signed_area"]

#: nominal UIC60 (60E1) dimensions used below the head [m]
RAIL_HEIGHT_M = 0.172
RAIL_FOOT_WIDTH_M = 0.150
RAIL_WEB_THICKNESS_M = 0.0165
RAIL_HEAD_DEPTH_M = 0.051          #: top of rail to the underside of the head
RAIL_FOOT_THICKNESS_M = 0.0115     #: foot edge thickness

#: simplified wheel body (drawing only): rim depth below the tape circle, web thickness, hub radius [m]
WHEEL_RIM_DEPTH_M = 0.065
WHEEL_WEB_THICKNESS_M = 0.030
WHEEL_HUB_RADIUS_M = 0.11


def signed_area(section) -> float:
    """Signed area of a closed polygon ``(n, 2)`` in the (y, z) plane (positive: counter-clockwise with y to the
    right and z up on paper, i.e. mathematically positive in (y, z))."""
    p = np.asarray(section, dtype=float)
    y, z = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(y * np.roll(z, -1) - np.roll(y, -1) * z))


def _sample(curve, n: int) -> np.ndarray:
    s = np.linspace(curve.s_min, curve.s_max, n)
    return curve.position(s)


def wheel_contour(pair, n_profile: int = 60) -> np.ndarray:
    """Contour ``(m, 2)`` of the right wheel for a solid of revolution about the axle: columns (axial coordinate
    along the axle from the axle centre, outwards [m]; radius [m]).

    The outer surface is the wheel profile in place (``pair.flange_side`` then ``pair.tread_side``, from the flange
    back to the field side: radius = ``r0`` + the profile's radius increase); the rim is closed
    :data:`WHEEL_RIM_DEPTH_M` below the tape circle and carried by a web (:data:`WHEEL_WEB_THICKNESS_M`, in the
    middle of the rim) down to the hub radius :data:`WHEEL_HUB_RADIUS_M` — simplified proportions, drawing only.
    Traversed so that the outer surface runs outwards (Exudyn's solid of revolution takes the left normal of the
    contour as the outward one).  The left wheel is the same contour about the mirrored axle direction."""
    parts = [_sample(pair.flange_side, n_profile // 3)] if pair.flange_side is not None else []
    parts.append(_sample(pair.tread_side, n_profile))
    outer = np.concatenate(parts)
    outer = outer[np.concatenate([[True], np.any(np.abs(np.diff(outer, axis=0)) > 1e-9, axis=1)])]
    y_back, y_field = float(outer[0, 0]), float(outer[-1, 0])
    r_rim = pair.r0_m - WHEEL_RIM_DEPTH_M
    y_mid = 0.5 * (y_back + y_field)
    w = 0.5 * WHEEL_WEB_THICKNESS_M
    inner = [(y_field, r_rim), (y_mid + w, r_rim), (y_mid + w, WHEEL_HUB_RADIUS_M), (y_mid - w, WHEEL_HUB_RADIUS_M),
             (y_mid - w, r_rim), (y_back, r_rim)]
    contour = np.vstack([[y_back, r_rim], outer, inner])
    return contour


def rail_section(pair, n_head: int = 40) -> np.ndarray:
    """Closed cross-section ``(m, 2)`` (side frame: y outwards from the track centre, z down) of the right rail:
    the rail-head profile as placed by the pair (inclined, gauge point at gauge/2, top at z = 0), then a
    simplified web and foot on the head's centre line (nominal UIC60 height, web and foot; the inclination of the
    lower part is not drawn).  Oriented with positive :func:`signed_area`."""
    head = _sample(pair.rail_side, n_head)                       # from the gauge side (inner) to the field side
    y_in, y_out = float(head[0, 0]), float(head[-1, 0])
    yc = 0.5 * (y_in + y_out)
    w, f = 0.5 * RAIL_WEB_THICKNESS_M, 0.5 * RAIL_FOOT_WIDTH_M
    zh, zf, zb = RAIL_HEAD_DEPTH_M, RAIL_HEIGHT_M - RAIL_FOOT_THICKNESS_M, RAIL_HEIGHT_M
    below = [(y_out, zh), (yc + w, zh + 0.015), (yc + w, zf - 0.012), (yc + f, zf), (yc + f, zb),
             (yc - f, zb), (yc - f, zf), (yc - w, zf - 0.012), (yc - w, zh + 0.015), (y_in, zh)]
    sec = np.vstack([head, below])
    return sec if signed_area(sec) > 0.0 else sec[::-1].copy()


def mirror_section(section) -> np.ndarray:
    """The section mirrored to the other side (y -> -y), re-oriented to positive :func:`signed_area`."""
    m = np.asarray(section, dtype=float) * np.array([-1.0, 1.0])
    return m[::-1].copy() if signed_area(m) < 0.0 else m


def rectangle_section(y_min: float, y_max: float, z_min: float, z_max: float) -> np.ndarray:
    """A rectangle in the (y, z) plane with positive :func:`signed_area` (e.g. a deck box)."""
    return np.array([[y_min, z_min], [y_max, z_min], [y_max, z_max], [y_min, z_max]], dtype=float)


def swept_mesh(section, x_m, dy_m=None, dz_m=None) -> tuple[np.ndarray, np.ndarray]:
    """Sweep a closed section along x: station i is the section at ``x_m[i]`` shifted by ``(dy_m[i], dz_m[i])``.

    Returns ``points (n_x * n_s, 3)`` (model frame) and ``triangles (2 (n_x - 1) n_s, 3)`` (0-based), wound so that
    their normals ``(p1 - p0) × (p2 - p0)`` point out of the section when it has positive :func:`signed_area`
    (ends left open)."""
    sec = np.asarray(section, dtype=float)
    x = np.asarray(x_m, dtype=float)
    n_x, n_s = x.size, sec.shape[0]
    if n_x < 2 or n_s < 3:
        raise ValueError(f"swept_mesh: need >= 2 stations and >= 3 section points (got {n_x}, {n_s})")
    dy = np.zeros(n_x) if dy_m is None else np.asarray(dy_m, dtype=float).reshape(n_x)
    dz = np.zeros(n_x) if dz_m is None else np.asarray(dz_m, dtype=float).reshape(n_x)
    pts = np.empty((n_x, n_s, 3))
    pts[:, :, 0] = x[:, None]
    pts[:, :, 1] = sec[None, :, 0] + dy[:, None]
    pts[:, :, 2] = sec[None, :, 1] + dz[:, None]
    i = np.arange(n_x - 1)[:, None] * n_s
    j = np.arange(n_s)[None, :]
    jn = (j + 1) % n_s
    a, b = i + j, i + jn                         # station i: points j, j+1
    c, d = a + n_s, b + n_s                      # station i+1
    tri = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    return pts.reshape(-1, 3), tri.astype(np.int64)
