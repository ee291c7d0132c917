"""The defaults of the wheel–rail contact, declared once: the connector
(:class:`~exudyn_wheelrail.multibody.connector.WheelRailContact`) takes them as its keyword defaults and the contact
settings of a run (:class:`~exudyn_wheelrail.simulation.settings.ContactSettings`) as theirs.

This module imports nothing, so that a front end can show the defaults before any work (the command line's
``--help``) without loading the compiled contact code.

>>> CREEP_LAW, FRICTION, GEOMETRY
('table', 0.3, 'online')
"""

__all__ = ["CREEP_LAW", "CREEP_LAW_NAMES", "FRICTION", "GEOMETRY", "GEOMETRY_MODES", "CONTACT_PATCH",
           "CONTACT_PATCHES"]


#: the creep laws' names (the connector's ``creep_law=``), in the order of their codes in the compiled dispatch
#: (:data:`exudyn_wheelrail.creep.registry.LAWS`: what each is, what it needs)
CREEP_LAW_NAMES = ("fastsim", "linear", "none", "table", "shen_hedrick_elkins", "polach", "table_linear")

#: creep law: the USETAB-style table of Kalker's exact theory, as in Montenegro et al. 2015 (a name of
#: :data:`CREEP_LAW_NAMES`)
CREEP_LAW = "table"
#: wheel–rail friction coefficient (dry steel on steel)
FRICTION = 0.3
#: contact geometry: "online" search at every evaluation, or the precomputed "table" for a rigid rail profile
#: (:mod:`exudyn_wheelrail.contact.geometry_table`)
GEOMETRY_MODES = ("online", "table")
GEOMETRY = GEOMETRY_MODES[0]
#: the normal contact: Hertz's ellipse at the contact point, or the non-Hertzian patch where Hertz does not hold
#: (:mod:`exudyn_wheelrail.contact.patch_pass`)
CONTACT_PATCHES = ("hertz", "non-hertzian")
CONTACT_PATCH = CONTACT_PATCHES[0]
