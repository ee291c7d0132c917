"""The wheel on the flexible rail: an upper estimate of the contact stiffness and the highest frequency of the
wheel on the rails' kept modal mass (:func:`contact_mode_Hz`), what an explicit time step must carry.  Frames and
units: :mod:`exudyn_wheelrail.conventions`."""
from __future__ import annotations

import math

import numpy as np

__all__ = ["CONTACT_STIFFNESS_N_M", "contact_mode_Hz"]

#: ASSUMPTION: an upper estimate of the wheel–rail contact stiffness for the step check [N/m] — a Hertz contact
#: under ~80 kN is ~1e9 N/m, a flange contact (two points, steep normal) up to a few times that
CONTACT_STIFFNESS_N_M = 4.0e9


def contact_mode_Hz(modes, s_from_m: float | None = None, s_to_m: float | None = None) -> float:
    """Upper estimate of the highest frequency of the coupled wheel–track system: the kept modes' highest, and a
    contact spring :data:`CONTACT_STIFFNESS_N_M` (roll: times (b/2)²) on the rail's modal mass at the contact,
    ``m_eff = 1/Σ_k φ_k(s)²`` per row of the deck interface (y, z, roll), the smallest over the segment (the wheelset
    is much heavier than that mass) or over the wheels' path ``[s_from_m, s_to_m]`` (the free rail ends are
    lighter).  With the static correction (``modes.residual_table``) the contact spring acts in series with the
    residual flexibility of that row at that point, ``k_eff = 1/(1/k + G_res)``.  Measured (RTRI car, 250 km/h,
    flange contact in the lateral deviation; the run reports ok either way): without the correction RK44 chatters
    at 0.5 ms with modes to 800 Hz (lateral force jumping 2–25 kN between steps) and not at 0.25 ms (estimate:
    0.35 ms); with it, 800 Hz chatters at 0.5 ms, 600 Hz diverges at 0.75 ms and is smooth at 0.5 ms, 400 Hz is
    smooth at 1 ms."""
    tb = modes.table
    s_pts = tb.start_m + np.append(tb.elem_x0, tb.elem_x0[-1] + tb.elem_len[-1])
    sel = np.ones(s_pts.shape, dtype=bool)
    if s_from_m is not None:
        sel &= (s_pts >= s_from_m - tb.elem_len[0]) & (s_pts <= s_to_m + tb.elem_len[0])
    ns = tb.node_shapes[sel]                                          # (n_pts, 5, n_modes): v, dv, w, dw, θ
    residual = getattr(modes, "residual_table", None)
    b = modes.model.params.rail_centre_distance_m
    k = (CONTACT_STIFFNESS_N_M, CONTACT_STIFFNESS_N_M, CONTACT_STIFFNESS_N_M * (0.5 * b) ** 2)
    f_c = 0.0
    for i, (row, ki) in enumerate(zip((0, 2, 4), k)):                # y, z, roll rows; residual columns 0, 1, 2
        inv_m = np.sum(ns[:, row, :] ** 2, axis=1)
        k_eff = ki if residual is None else 1.0 / (1.0 / ki + residual[sel, i])
        f_c = max(f_c, float(np.max(np.sqrt(k_eff * inv_m))) / (2.0 * math.pi))
    return max(f_c, float(modes.frequencies_Hz.max(initial=0.0)))
