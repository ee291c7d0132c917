"""Rotation vector ↔ rotation matrix (compiled): the rotation parameters of Exudyn's Lie-group rigid-body nodes.

A node's rotation coordinates are the rotation vector ``v = θ e`` (angle θ [rad] about the unit axis e); its
rotation matrix ``R_GB`` maps body-frame components to global (track/model) ones.  Rodrigues' formula,
``R = I + sin θ/θ [v×] + (1 - cos θ)/θ² [v×]²``; the inverse from the trace and the skew part (angle in [0, π]).
"""
from __future__ import annotations

import math

from numba import njit

__all__ = ["rotation_from_vector", "rotation_vector_from_matrix"]


@njit(cache=True)
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


@njit(cache=True)
def rotation_vector_from_matrix(R, v, o):
    """Rotation vector [rad] of R into ``v[o:o+3]`` (angle in [0, π])."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    c = min(max(0.5 * (tr - 1.0), -1.0), 1.0)
    th = math.acos(c)
    wx = R[2, 1] - R[1, 2]
    wy = R[0, 2] - R[2, 0]
    wz = R[1, 0] - R[0, 1]
    if th < 1e-8:
        v[o] = 0.5 * wx
        v[o + 1] = 0.5 * wy
        v[o + 2] = 0.5 * wz
        return
    s = math.sin(th)
    if s > 1e-6:
        f = th / (2.0 * s)
        v[o] = f * wx
        v[o + 1] = f * wy
        v[o + 2] = f * wz
        return
    # near π: axis from the diagonal
    ax = math.sqrt(max(0.5 * (R[0, 0] + 1.0), 0.0))
    ay = math.sqrt(max(0.5 * (R[1, 1] + 1.0), 0.0))
    az = math.sqrt(max(0.5 * (R[2, 2] + 1.0), 0.0))
    if ax >= ay and ax >= az:
        ay = math.copysign(ay, R[0, 1] + R[1, 0])
        az = math.copysign(az, R[0, 2] + R[2, 0])
    elif ay >= az:
        ax = math.copysign(ax, R[0, 1] + R[1, 0])
        az = math.copysign(az, R[1, 2] + R[2, 1])
    else:
        ax = math.copysign(ax, R[0, 2] + R[2, 0])
        ay = math.copysign(ay, R[1, 2] + R[2, 1])
    v[o] = th * ax
    v[o + 1] = th * ay
    v[o + 2] = th * az
