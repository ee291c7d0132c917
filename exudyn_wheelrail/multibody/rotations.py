"""Rotation vector ↔ rotation matrix (compiled): the rotation parameters of Exudyn's Lie-group rigid-body nodes.

A node's rotation coordinates are the rotation vector ``v = θ e`` (angle θ [rad] about the unit axis e); its
rotation matrix ``R_GB`` maps body-frame components to global (track/model) ones.  Rodrigues' formula,
``R = I + sin θ/θ [v×] + (1 - cos θ)/θ² [v×]²``; the inverse from the trace and the skew part (angle in [0, π]).
"""
from __future__ import annotations

import math

from ..jit import compiled

__all__ = ["rotation_from_vector", "rotation_vector_from_matrix"]


@compiled
def rotation_from_vector(rx, ry, rz, R):
    """Rodrigues: rotation matrix of the rotation vector (rx, ry, rz) [rad] into R (3, 3)."""
    th = math.sqrt(rx * rx + ry * ry + rz * rz)
    if th < 1e-12:
        s = 1.0
        c = 0.5
    else:
        s = math.sin(th) / th
        c = (1.0 - math.cos(th)) / (th * th)
    R[0, 0] = 1.0 - c * (ry * ry + rz * rz)
    R[1, 1] = 1.0 - c * (rx * rx + rz * rz)
    R[2, 2] = 1.0 - c * (rx * rx + ry * ry)
    R[0, 1] = -s * rz + c * rx * ry
    R[1, 0] = s * rz + c * rx * ry
    R[0, 2] = s * ry + c * rx * rz
    R[2, 0] = -s * ry + c * rx * rz
    R[1, 2] = -s * rx + c * ry * rz
    R[2, 1] = s * rx + c * ry * rz


@compiled
def rotation_vector_from_matrix(R, v, o):
    """Rotation vector [rad] of R into ``v[o:o+3]`` (angle in [0, π]).

    The angle from ``atan2(sin θ, cos θ)`` with ``2 sin θ e = (R₃₂ - R₂₃, R₁₃ - R₃₁, R₂₁ - R₁₂)`` and ``2 cos θ = tr R
    - 1`` — accurate at every angle (``acos`` of the trace alone loses half the digits at small angles).  Below
    about 154° (cos θ > -0.9) the vector is ``θ/(2 sin θ)`` times that skew part; closer to π the axis comes from the
    symmetric part, ``R + Rᵀ = 2 cos θ I + 2 (1 - cos θ) e eᵀ``, its sign from the skew part."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    wx = R[2, 1] - R[1, 2]
    wy = R[0, 2] - R[2, 0]
    wz = R[1, 0] - R[0, 1]
    sn = 0.5 * math.sqrt(wx * wx + wy * wy + wz * wz)
    cs = 0.5 * (tr - 1.0)
    th = math.atan2(sn, cs)
    if cs > -0.9:
        f = 0.5 if sn < 1e-300 else th / (2.0 * sn)    # θ/(2 sin θ) -> 1/2 at θ -> 0
        v[o] = f * wx
        v[o + 1] = f * wy
        v[o + 2] = f * wz
        return
    k = 1.0 - cs                                        # 1 - cos θ in [1.9, 2]
    ax = math.sqrt(max((R[0, 0] - cs) / k, 0.0))
    ay = math.sqrt(max((R[1, 1] - cs) / k, 0.0))
    az = math.sqrt(max((R[2, 2] - cs) / k, 0.0))
    if ax >= ay and ax >= az:
        ax = math.copysign(ax, wx) if wx != 0.0 else ax
        ay = (R[0, 1] + R[1, 0]) / (2.0 * k * ax)
        az = (R[0, 2] + R[2, 0]) / (2.0 * k * ax)
    elif ay >= az:
        ay = math.copysign(ay, wy) if wy != 0.0 else ay
        ax = (R[0, 1] + R[1, 0]) / (2.0 * k * ay)
        az = (R[1, 2] + R[2, 1]) / (2.0 * k * ay)
    else:
        az = math.copysign(az, wz) if wz != 0.0 else az
        ax = (R[0, 2] + R[2, 0]) / (2.0 * k * az)
        ay = (R[1, 2] + R[2, 1]) / (2.0 * k * az)
    n = math.sqrt(ax * ax + ay * ay + az * az)
    v[o] = th * ax / n
    v[o + 1] = th * ay / n
    v[o + 2] = th * az / n
