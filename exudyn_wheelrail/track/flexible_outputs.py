r"""The flexible track under the wheels: rail and sleeper displacements, pad and ballast forces at given track
distances, from the modal state of a reduced track (:class:`~.flexible.FlexibleTrackModes` on the ground or
:class:`~.flexible_deck.TrackOnDeckModes` over a deck).

>>> out = track_under_wheels(modes, s_m=[12.3, 14.8], q=q, q_t=q_t)                   # doctest: +SKIP
>>> out["rail_z_right_m"], out["pad_vertical_right_N"], out["ballast_vertical_right_N"]  # doctest: +SKIP

Quantities (:data:`UNDER_WHEEL_KEYS`; per point, ``<side>`` ``left`` / ``right`` the rail looking in the running
direction; track frame of :mod:`.flexible`: y right, z **down**, forces compression positive):

* ``rail_z_<side>_m`` — the rail's vertical displacement at the point, ``z_rail ∓ (b/2) θ_rail`` (the rails'
  centre-line motion of the deck interface, ``Φ(s) q``: what the wheel–rail contact sees); ``rail_y_m`` — the
  rails' lateral displacement (both rails move together, :mod:`.flexible`);
* the **nearest sleeper** (``sleeper`` its index, ``sleeper_s_m`` its track distance): ``sleeper_z_<side>_m`` —
  its rail seat's vertical displacement ``z_j ∓ (b/2) θ_j``; ``pad_vertical_<side>_N`` — the pad force at that
  seat; ``ballast_vertical_<side>_N`` — the ballast force under that seat (on the ground, or over a deck on the
  sleeper's motion relative to the deck point under it: the force the ballast puts on the deck);
* over a deck (:class:`~.flexible_deck.TrackOnDeckModes`): ``deck_z_m`` — the deck axis' vertical displacement
  under the point (zero off the deck).

Accuracy (statics against the full finite-element model, tests/test_track_on_deck_train.py): with all modes the
values are the full model's; with the default 800 Hz modes the rail's deflection under a wheel is 1.3–3.2 % low, the
sleeper displacements and ballast forces within 0.1 %, and the pad force at a sleeper right under the wheel 15 %
low (8 % at 1200 Hz, 4 % at 2000 Hz: the local compression of the rail-on-pad branch lies above the cut-off; no
static correction is applied), mid-bay within 1.2 %.

A point off the segment (where the track is rigid, ``Φ = 0``) has ``on_segment`` False, ``rail_*`` 0 and the
sleeper, pad and ballast values NaN (there is no flexible track there).  :func:`support_force_totals_N`: the
vertical ballast forces of the whole segment summed over the sleepers on the ground and over those on the deck
(in static equilibrium their sum is the vertical load on the rails).
"""
from __future__ import annotations

import numpy as np

from .flexible import FlexibleTrackModes

__all__ = ["SIDES", "UNDER_WHEEL_KEYS", "nearest_sleepers", "support_force_totals_N", "track_under_wheels"]

#: the rails, sign of their lateral position (left at y = -b/2, right at +b/2)
SIDES = {"left": -1.0, "right": 1.0}
#: the per-side quantities of :func:`track_under_wheels` (``{side}`` in :data:`SIDES`)
UNDER_WHEEL_KEYS = ("rail_z_{side}_m", "sleeper_z_{side}_m", "pad_vertical_{side}_N", "ballast_vertical_{side}_N")


def _check_modes(modes):
    if not isinstance(modes, FlexibleTrackModes):
        raise TypeError(f"modes={modes!r}: expected FlexibleTrackModes or TrackOnDeckModes")


def nearest_sleepers(modes, s_m) -> tuple[np.ndarray, np.ndarray]:
    """``(index, on_segment)`` of the sleeper nearest to each track distance in ``s_m`` (index clipped to the
    segment; ``on_segment`` False off it)."""
    _check_modes(modes)
    mdl = modes.model
    s = np.atleast_1d(np.asarray(s_m, dtype=float))
    on = (s >= mdl.start_m - 1e-9) & (s <= mdl.start_m + mdl.length_m + 1e-9)
    return mdl.nearest_sleeper(s), on


def track_under_wheels(modes, s_m, q, q_t) -> dict:
    """The track's state under the points ``s_m`` (track distances, e.g. the wheelsets') for modal coordinates
    ``q`` and rates ``q_t`` (module docstring): a dict of arrays over the points."""
    _check_modes(modes)
    s = np.atleast_1d(np.asarray(s_m, dtype=float))
    q = np.asarray(q, dtype=float)
    q_t = np.asarray(q_t, dtype=float)
    if q.shape != (modes.n_modes,) or q_t.shape != (modes.n_modes,):
        raise ValueError(f"q, q_t: expected {modes.n_modes} modal coordinates each, got {q.shape} and {q_t.shape}")
    mdl = modes.model
    b = mdl.params.rail_centre_distance_m
    j, on = nearest_sleepers(modes, s)
    rail = modes.shape_at(s) @ q                                   # (n, 3): y_rail, z_rail, θ_rail
    sl = modes.sleeper_state(q, j)
    f = modes.support_forces_N(q, q_t, j)
    out = {"on_segment": on, "sleeper": np.where(on, j, -1), "sleeper_s_m": np.where(on, mdl.sleeper_s_m[j], np.nan),
           "rail_y_m": rail[:, 0]}
    nan = np.where(on, 1.0, np.nan)
    for side, sgn in SIDES.items():
        out[f"rail_z_{side}_m"] = rail[:, 1] + sgn * 0.5 * b * rail[:, 2]
        out[f"sleeper_z_{side}_m"] = (sl["z_m"] + sgn * 0.5 * b * sl["roll_rad"]) * nan
        out[f"pad_vertical_{side}_N"] = f[f"pad_vertical_{side}_N"] * nan
        out[f"ballast_vertical_{side}_N"] = f[f"ballast_vertical_{side}_N"] * nan
    if hasattr(modes, "deck_displacement"):
        out["deck_z_m"] = modes.deck_displacement(s, q)[:, 1]
    return out


def support_force_totals_N(modes, q, q_t) -> dict:
    """The vertical ballast forces of all sleepers, summed: ``ground_N`` over the sleepers on the ground, ``deck_N``
    over those on a deck (0 on the ground model), ``total_N`` both (compression positive)."""
    _check_modes(modes)
    f = modes.support_forces_N(np.asarray(q, dtype=float), np.asarray(q_t, dtype=float))
    per_sleeper = f["ballast_vertical_left_N"] + f["ballast_vertical_right_N"]
    on_deck = getattr(modes.model, "on_deck", np.zeros(modes.model.n_sleepers, dtype=bool))
    deck = float(per_sleeper[on_deck].sum())
    ground = float(per_sleeper[~on_deck].sum())
    return {"ground_N": ground, "deck_N": deck, "total_N": ground + deck}
