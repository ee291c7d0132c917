"""The defaults of the wheel–rail contact, declared once: the connector
(:class:`~exudyn_wheelrail.multibody.connector.WheelRailContact`) takes them as its keyword defaults and the contact
settings of a run (:class:`~exudyn_wheelrail.simulation.settings.ContactSettings`) as theirs.

This module imports nothing (but ``typing``), so that a front end can show the defaults before any work (the command line's
``--help``) without loading the compiled contact code.

>>> CREEP_LAW, FRICTION, GEOMETRY
('table', 0.3, 'online')
"""

from typing import NamedTuple

__all__ = ["CREEP_LAW", "FRICTION", "GEOMETRY", "GEOMETRY_MODES", "CreepLaw", "LAWS"]


class CreepLaw(NamedTuple):
    """One creep law of :data:`LAWS`."""

    code: int                  #: the value the compiled dispatch switches on (:mod:`exudyn_wheelrail.creep.registry`)
    summary: str               #: what it is (for listings)
    needs_table: bool          #: evaluates the USETAB-style table of the exact theory (:mod:`exudyn_wheelrail.creep.table`), loaded once
    uses_fastsim_grid: bool    #: evaluates FASTSIM on the ``(n_x, n_y)`` grid of ``cp[CP_NX]``, ``cp[CP_NY]``
    coulomb_bound: bool        #: the resultant is held on μN


#: the creep laws by name (the connector's ``creep_law=``); the codes are the dispatch's switch values
LAWS = {
    "fastsim": CreepLaw(0, "Kalker's simplified theory FASTSIM", False, True, True),
    "linear": CreepLaw(1, "Kalker's linear theory, unsaturated (small-creepage studies)", False, False, False),
    "none": CreepLaw(2, "no creep forces (normal forces only)", False, False, True),
    "table": CreepLaw(3, "USETAB-style table of Kalker's exact theory", True, False, True),
    "shen_hedrick_elkins": CreepLaw(4, "Shen-Hedrick-Elkins saturation of the linear theory", False, False, True),
    "polach": CreepLaw(5, "Polach's law, k_A = k_S = 1", False, False, True),
}

#: creep law: the USETAB-style table of Kalker's exact theory, as in Montenegro et al. 2015 (a name of
#: :data:`LAWS`)
CREEP_LAW = "table"
#: wheel–rail friction coefficient (dry steel on steel)
FRICTION = 0.3
#: contact geometry: "online" search at every evaluation, or the precomputed "table" for a rigid rail profile
#: (:mod:`exudyn_wheelrail.contact.geometry_table`)
GEOMETRY_MODES = ("online", "table")
GEOMETRY = GEOMETRY_MODES[0]
