"""A train's wheelsets on one wheel–rail connector (:class:`~.connector.WheelRailContact`), its cars placed on the
rails."""
from __future__ import annotations

from ..contact.pair import WheelRailPair
from ..rolling_stock.train import place_train_on_track
from ..track.rigid import RigidStraightTrack
from .connector import WheelRailContact, add_wheel_rail_contact

__all__ = ["add_train_contact"]


def add_train_contact(mbs, train, pair: WheelRailPair, *, track=None, place: bool = True,
                      **options) -> WheelRailContact:
    """Couple every wheelset of a train (:func:`exudyn_wheelrail.rolling_stock.train.build_train` with
    ``wheel_rail="none"``), car after car, front first, to the rails by **one** connector (the run monitor and the
    recorder watch one connector), before ``mbs.Assemble()``.  ``track``: default a perfect straight track;
    ``options`` as :class:`WheelRailContact` (``creep_law``, ``mu``, ``structure``, ...); the train's speed and start
    are its own.  ``place``: every car in static equilibrium on the rails and on the displaced track
    (:func:`~exudyn_wheelrail.rolling_stock.train.place_train_on_track`).  Returns the connector, also kept as
    ``train.contact``."""
    track = track if track is not None else RigidStraightTrack()
    train.contact = add_wheel_rail_contact(mbs, train.wheelset_nodes, pair, speed_m_s=train.speed_m_s, track=track,
                                           s_start_m=train.s_start_m, **options)
    if place:
        place_train_on_track(mbs, train, pair, track)
    return train.contact
