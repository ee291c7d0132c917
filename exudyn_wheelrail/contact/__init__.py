"""Wheel–rail contact: profile placement, contact search, Hertz normal problem, the compiled kernel."""
from .pair import WheelRailPair
from .wheelset import ContactPoint, WheelsetContact

__all__ = ["WheelRailPair", "WheelsetContact", "ContactPoint"]
