"""How long a segment of flexible track (or a moving window) must be: the margin beyond the outermost wheelsets in
decay lengths of the vertical support (:data:`MARGIN_DECAY_LENGTHS`, :func:`segment_margin_m`) and the segment that
carries every wheelset over a run (:func:`segment_for_run`)."""
from __future__ import annotations

import math

from .flexible_parameters import TrackParameters

__all__ = ["MARGIN_DECAY_LENGTHS", "decay_length_m", "segment_margin_m", "segment_for_run"]


#: the margin a segment keeps beyond the outermost wheelsets, in decay lengths 1/β of the vertical support: there a
#: wheel load's static deflection ``e^{-βx}(cos βx + sin βx)`` is below 0.5 % of its peak
MARGIN_DECAY_LENGTHS = 5.0


def decay_length_m(params: TrackParameters) -> float:
    """``1/β`` [m] of the vertical support, ``β = (k/(4EI))^¼`` with the single rail's EI and support stiffness
    per metre (:meth:`TrackParameters.support_stiffness_per_rail_N_m2`)."""
    k = params.support_stiffness_per_rail_N_m2()
    return (4.0 * params.rail_E_Pa * params.rail_I_vertical_m4 / k) ** 0.25


def segment_margin_m(params: TrackParameters) -> float:
    """The default margin of a segment (or moving window) beyond the outermost wheelsets [m]:
    :data:`MARGIN_DECAY_LENGTHS` decay lengths, at least two sleeper bays."""
    return max(MARGIN_DECAY_LENGTHS * decay_length_m(params), 2.0 * params.sleeper_spacing_m)


def segment_for_run(s_rear_start_m: float, s_front_end_m: float, params: TrackParameters,
                    margin_m: float | None = None) -> tuple[float, float]:
    """``(start_m, length_m)`` of a segment that carries every wheelset over a run, from the rearmost wheelset's
    start to the leading wheelset's end, plus ``margin_m`` at both ends (default :func:`segment_margin_m`)."""
    if margin_m is None:
        margin_m = segment_margin_m(params)
    d = params.sleeper_spacing_m
    start = math.floor((s_rear_start_m - margin_m) / d) * d
    return float(start), float(s_front_end_m + margin_m - start)
