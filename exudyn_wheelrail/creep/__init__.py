"""Creep forces: Kalker's linear-theory coefficients, FASTSIM, Kalker's exact theory, its table and cheap laws.

Forces are on the wheel, ``a`` along rolling, Kalker's signs: for small creepage ``Fx = -G c² C11 ξ``,
``Fy = -G c² (C22 η + c C23 φ)``, ``Mz = G c³ (C23 η - c C33 φ)``, ``c = √(ab)``.  The laws the wheel–rail
connector evaluates, by name, and their compiled dispatch: :mod:`.registry`.
"""
from .linear import (
    A_OVER_B_MAX,
    A_OVER_B_MIN,
    fastsim_spin_moment_coefficient,
    kalker_coefficients,
    kalker_coefficients_core,
    linear_creep_forces,
)
from .fastsim import DEFAULT_NX, DEFAULT_NY, fastsim, fastsim_core, fastsim_flexibilities
from .table import NU_TABLE, NU_TOLERANCE, CreepTable, load_table, table_core, table_forces
from .laws import polach, polach_core, she_core, shen_hedrick_elkins
from .kalker_exact import KalkerSolution, kalker_exact, kalker_exact_extrapolated, kalker_exact_solution

__all__ = [
    "A_OVER_B_MAX", "A_OVER_B_MIN", "kalker_coefficients", "kalker_coefficients_core", "linear_creep_forces",
    "fastsim_spin_moment_coefficient", "fastsim", "fastsim_core", "fastsim_flexibilities", "DEFAULT_NX",
    "DEFAULT_NY", "KalkerSolution", "kalker_exact", "kalker_exact_extrapolated", "kalker_exact_solution",
    "shen_hedrick_elkins", "she_core", "polach", "polach_core",
    "table_forces", "load_table", "CreepTable", "table_core", "NU_TABLE", "NU_TOLERANCE",
]
