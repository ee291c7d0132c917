"""Wheel and rail profiles: analytic standards, point-file readers, arc-length curves."""
from .curve import ProfileCurve
from .dense import DenseProfile
from .profiles import RailProfile, WheelProfile

__all__ = ["ProfileCurve", "DenseProfile", "RailProfile", "WheelProfile"]
