"""Dense exact samples of a profile: the common hand-over format between profile sources and curves.

Every profile source (an analytic standard such as S1002 or UIC60, a SIMPACK point file, a measured y-z table)
produces a :class:`DenseProfile`: ordered points of the profile line together with their first and second
derivatives with respect to *any* monotone curve parameter tau (the source chooses it: lateral coordinate for a
graph, an angle for an arc, chord length for a spline).  :class:`~exudyn_wheelrail.profiles.curve.ProfileCurve`
turns these into an arc-length parameterised C2 curve.

Coordinates are those of the *profile frame* (see :mod:`exudyn_wheelrail.conventions`), in metres:

* ``y``: lateral, positive towards the field side (away from the track centre line);
* ``z``: for a wheel, radius increase over the nominal rolling (tape) circle, i.e. positive towards the rail;
  for a rail, depth below the top of the rail, i.e. positive downwards.

Points are ordered from the gauge (flange) side towards the field side: for a wheel from the flange back towards the
field-side chamfer, for a rail from the lower gauge face over the crown towards the field side.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class DenseProfile:
    """Dense samples (y, z) of a profile line with derivatives with respect to a curve parameter tau.

    Attributes are 1-D float arrays of equal length, metres (derivatives in metres per unit of tau).
    ``breaks_y`` optionally lists lateral coordinates of section joints (curvature jumps), for information.
    """

    y: np.ndarray
    z: np.ndarray
    dy: np.ndarray
    dz: np.ndarray
    ddy: np.ndarray
    ddz: np.ndarray
    name: str = "profile"

    def __post_init__(self):
        n = len(self.y)
        for field in ("z", "dy", "dz", "ddy", "ddz"):
            if len(getattr(self, field)) != n:
                raise ValueError(f"{self.name}: array '{field}' has length {len(getattr(self, field))}, expected {n}")
        if n < 4:
            raise ValueError(f"{self.name}: a dense profile needs at least 4 samples, got {n}")
        for field in ("y", "z", "dy", "dz", "ddy", "ddz"):
            if not np.all(np.isfinite(getattr(self, field))):
                raise ValueError(f"{self.name}: array '{field}' contains NaN or infinite values")

    @staticmethod
    def concatenate(parts: list["DenseProfile"], name: str = "profile") -> "DenseProfile":
        """Join consecutive sections (each already ordered) into one dense profile.

        Duplicate joint points (a section ending where the next begins) are kept once.
        """
        ys, zs, dys, dzs, ddys, ddzs = [], [], [], [], [], []
        for k, p in enumerate(parts):
            sl = slice(1, None) if k > 0 and np.hypot(p.y[0] - ys[-1][-1], p.z[0] - zs[-1][-1]) < 1e-12 else slice(None)
            ys.append(p.y[sl]); zs.append(p.z[sl]); dys.append(p.dy[sl]); dzs.append(p.dz[sl])
            ddys.append(p.ddy[sl]); ddzs.append(p.ddz[sl])
        return DenseProfile(np.concatenate(ys), np.concatenate(zs), np.concatenate(dys), np.concatenate(dzs),
                            np.concatenate(ddys), np.concatenate(ddzs), name=name)
