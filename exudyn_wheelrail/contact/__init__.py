"""Wheel–rail contact: profile placement, contact search, Hertz normal problem, creepages, the compiled kernel."""
from .creepage import Creepages, contact_frame, creepages, wheelset_axis, yawed_contact_point
from .pair import WheelRailPair
from .wheelset import ContactPoint, WheelsetContact

__all__ = ["WheelRailPair", "WheelsetContact", "ContactPoint", "Creepages", "creepages", "contact_frame",
           "wheelset_axis", "yawed_contact_point"]
