"""exudyn-wheelrail: wheel–rail contact for the Exudyn multibody library.

Method: Montenegro, Neves, Calçada, Tanabe & Sogabe, Computers & Structures 152 (2015) 200–214.
Frames, units and signs: :mod:`exudyn_wheelrail.conventions`.

Main entry points::

    from exudyn_wheelrail.profiles import WheelProfile, RailProfile
    from exudyn_wheelrail.contact import WheelRailPair, WheelsetContact
    from exudyn_wheelrail.analysis.geometry_functions import contact_geometry_sweep
    from exudyn_wheelrail.analysis.conicity import equivalent_conicity
"""
__version__ = "0.1.0"
