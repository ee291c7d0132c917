"""The creep laws the wheel–rail connector evaluates, by name: the one list, its compiled dispatch and parameters.

>>> LAWS["fastsim"].uses_fastsim_grid
True
>>> sorted(CREEP_LAWS)[:2]
['fastsim', 'linear']

:data:`LAWS` maps a law's name to its :class:`CreepLaw` entry (as SciPy's ``METHODS`` for its ODE solvers): the
code the compiled dispatch switches on and what the law needs.  :func:`creep_model` packs, once per contact, the
parameters and arrays the compiled call hands to :func:`creep_forces`, which every contact evaluation calls for
every loaded contact (:mod:`exudyn_wheelrail.multibody.connector_core`).

Rules every law follows (the dispatch enforces them; contract of :mod:`exudyn_wheelrail.creep`: forces **on the
wheel** in the contact frame, ``a`` along rolling, small-creepage limit ``Fx = -G c² C11 ξ``,
``Fy = -G c² (C22 η + c C23 φ)``, ``Mz = G c³ (C23 η - c C33 φ)``, ``c = √(ab)``):

* no normal force (``N <= 0``) or the law ``"none"``: no creep force;
* ``a/b`` outside the law's range ``[cp[CP_AB_MIN], cp[CP_AB_MAX]]`` (Kalker's Table E.3, 0.1–10, for the laws
  built on his coefficients; the table's own range for ``"table"``): the law is evaluated for the ellipse of the
  same area at the nearest allowed ratio and the result is flagged :data:`CREEP_AB_CLAMPED`;
* Kalker's linear coefficients ``C11, C22, C23`` at ``a/b`` and the combined ν
  (:func:`~exudyn_wheelrail.creep.linear.kalker_coefficients_core`) are handed to every law;
* Coulomb: a law with ``coulomb_bound`` has its resultant ``√(Fx² + Fy²)`` held on ``μN`` (the table's cubic
  interpolation overshoots it by up to ~0.2 % near full sliding, FASTSIM's discrete pressure by ~0.05 %).

Adding a law: its compiled core in its own module of :mod:`exudyn_wheelrail.creep`, its name at the end of
:data:`exudyn_wheelrail.contact_defaults.CREEP_LAW_NAMES` (what the options offer before any numerical code is
loaded), then here one entry of :data:`LAWS` (the next code) and one branch of :func:`_law_forces`.

References: J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990 (linear theory,
Table E.3, FASTSIM, the exact theory behind the table); Shen, Hedrick & Elkins, VSD 12 (1983) 79–83; O. Polach,
Wear 258 (2005) 992–1000.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..contact_defaults import CREEP_LAW_NAMES
from ..contact.layout import CP_AB_MAX, CP_AB_MIN, CP_G, CP_MU, CP_NU, CP_NX, CP_NY, CP_V_MIN, N_CP
from ..jit import compiled
from . import linear as _linear
from .fastsim import fastsim_core
from .laws import polach_core, she_core
from .table import NU_TOLERANCE, ORDER_CUBIC, ORDER_LINEAR, load_table, table_core

__all__ = ["CreepLaw", "LAWS", "CREEP_LAWS", "CREEP_AB_CLAMPED", "CreepModel", "creep_model", "creep_forces",
           "combined_elastic_constants"]

#: bit of the connector's ``RES_CREEP_STATUS`` (on top of the creepage's ``CREEP_*`` bits): a/b was clamped to the
#: law's range
CREEP_AB_CLAMPED = 64


class CreepLaw(NamedTuple):
    """One creep law of :data:`LAWS`."""

    code: int                  #: the value :func:`creep_forces` switches on
    summary: str               #: what it is (for listings)
    needs_table: bool          #: evaluates the USETAB-style table of the exact theory (:mod:`.table`), loaded once
    uses_fastsim_grid: bool    #: evaluates FASTSIM on the ``(n_x, n_y)`` grid of ``cp[CP_NX]``, ``cp[CP_NY]``
    coulomb_bound: bool        #: the resultant is held on μN


#: the creep laws by name (the connector's ``creep_law=``; the names declared in
#: :data:`exudyn_wheelrail.contact_defaults.CREEP_LAW_NAMES`, in the order of their codes, the dispatch's switch values)
LAWS = dict(zip(CREEP_LAW_NAMES, (
    CreepLaw(0, "Kalker's simplified theory FASTSIM", False, True, True),
    CreepLaw(1, "Kalker's linear theory, unsaturated (small-creepage studies)", False, False, False),
    CreepLaw(2, "no creep forces (normal forces only)", False, False, True),
    CreepLaw(3, "USETAB-style table of Kalker's exact theory", True, False, True),
    CreepLaw(4, "Shen-Hedrick-Elkins saturation of the linear theory", False, False, True),
    CreepLaw(5, "Polach's law, k_A = k_S = 1", False, False, True),
    CreepLaw(6, "the table of Kalker's exact theory interpolated multilinearly (about half the lookup's cost)", True,
             False, True),
), strict=True))

#: name -> code of the compiled dispatch (derived from :data:`LAWS`)
CREEP_LAWS = {name: law.code for name, law in LAWS.items()}

_FASTSIM = LAWS["fastsim"].code
_LINEAR = LAWS["linear"].code
_NONE = LAWS["none"].code
_TABLE = LAWS["table"].code
_SHE = LAWS["shen_hedrick_elkins"].code
_POLACH = LAWS["polach"].code
_TABLE_LINEAR = LAWS["table_linear"].code
#: per code: whether the Coulomb bound applies (read by the compiled dispatch)
_BOUNDED = tuple(law.coulomb_bound for law in sorted(LAWS.values(), key=lambda law: law.code))
assert [law.code for law in sorted(LAWS.values(), key=lambda law: law.code)] == list(range(len(LAWS)))


@compiled(inline="always")
def creep_forces(law, a, b, xi, eta, phi, N, cp, t_nodes, coef, tab):
    """Creep forces ``(Fx, Fy, Mz, flag)`` of the law with code ``law`` (module docstring: its rules) on an
    ellipse ``a``, ``b`` [m] under ``N`` [N] at the creepages ``xi``, ``eta`` [-], ``phi`` [1/m]; ``cp`` the
    ``CP_*`` parameters, ``t_nodes``, ``coef`` Kalker's coefficient table (:mod:`.linear`), ``tab`` the creep
    table's padded arrays (:meth:`~exudyn_wheelrail.creep.table.CreepTable.core_arrays`; ``None`` for a law
    without a table).  ``flag`` is 0 or :data:`CREEP_AB_CLAMPED`."""
    Fx, Fy, Mz, flag = _law_forces(law, a, b, xi, eta, phi, N, cp, t_nodes, coef, tab)
    if _BOUNDED[law]:
        f_t = math.sqrt(Fx * Fx + Fy * Fy)
        bound = cp[CP_MU] * N
        if f_t > bound > 0.0:
            Fx *= bound / f_t
            Fy *= bound / f_t
    return Fx, Fy, Mz, flag


@compiled(inline="always")
def _law_forces(law, a, b, xi, eta, phi, N, cp, t_nodes, coef, tab):
    """The law of :func:`creep_forces` without the Coulomb bound."""
    if law == _NONE or N <= 0.0:
        return 0.0, 0.0, 0.0, 0
    flag = 0
    ab = a / b
    if ab < cp[CP_AB_MIN] or ab > cp[CP_AB_MAX]:
        # outside the law's range: same area (c) at the nearest allowed ratio, flagged
        c = math.sqrt(a * b)
        ab = min(max(ab, cp[CP_AB_MIN]), cp[CP_AB_MAX])
        a = c * math.sqrt(ab)
        b = c / math.sqrt(ab)
        flag = CREEP_AB_CLAMPED
    C11, C22, C23 = _linear.kalker_coefficients_core(math.log(ab), cp[CP_NU], t_nodes, coef, 0)
    G = cp[CP_G]
    if law == _TABLE or law == _TABLE_LINEAR:
        Fx, Fy, Mz = _table_law(a, b, xi, eta, phi, N, cp[CP_MU], G, C11, C22, tab,
                                ORDER_CUBIC if law == _TABLE else ORDER_LINEAR)
        return Fx, Fy, Mz, flag
    if law == _SHE or law == _POLACH:
        C33 = 32.0 / (15.0 * math.pi) * C23 * ab ** -1.5     # simplified-theory spin-moment coefficient
        if law == _SHE:
            Fx, Fy, Mz = she_core(a, b, xi, eta, phi, N, cp[CP_MU], G, C11, C22, C23, C33)
        else:
            Fx, Fy, Mz = polach_core(a, b, xi, eta, phi, N, cp[CP_MU], G, C11, C22, C23, C33, 1.0, 1.0)
        return Fx, Fy, Mz, flag
    if law == _LINEAR:
        c = math.sqrt(a * b)
        C33 = 32.0 / (15.0 * math.pi) * C23 * ab ** -1.5     # as creep.linear_creep_forces
        return (-G * c * c * C11 * xi, -G * c * c * (C22 * eta + c * C23 * phi),
                G * c * c * c * (C23 * eta - c * C33 * phi), flag)
    Fx, Fy, Mz = fastsim_core(a, b, xi, eta, phi, N, cp[CP_MU], G, C11, C22, C23, int(cp[CP_NX]), int(cp[CP_NY]),
                              0)
    return Fx, Fy, Mz, flag


@compiled(refcount=False)
def _table_law(a, b, xi, eta, phi, N, mu, G, C11, C22, tab, order):
    """The table of the exact theory (:func:`~.table.table_core`, interpolation ``order``) with its arrays ``tab``;
    ``None`` (a law without a table): zero, and the lookup is not compiled (numba drops the branch on a ``None``
    argument's type)."""
    if tab is None:
        return 0.0, 0.0, 0.0
    return table_core(a, b, xi, eta, phi, N, mu, G, C11, C22, tab[0], tab[1], tab[2], tab[3], tab[4], tab[5], order)


def combined_elastic_constants(E_wheel_Pa: float, nu_wheel: float, E_rail_Pa: float,
                               nu_rail: float) -> tuple[float, float]:
    """``(G [Pa], ν)`` of Kalker's quasi-identical combination of wheel and rail: ``1/G = (1/G_w + 1/G_r)/2``,
    ``ν/G = (ν_w/G_w + ν_r/G_r)/2`` (Kalker 1990, Sec. 1.5); for equal materials G and ν themselves."""
    G_w = E_wheel_Pa / (2.0 * (1.0 + nu_wheel))
    G_r = E_rail_Pa / (2.0 * (1.0 + nu_rail))
    G = 2.0 / (1.0 / G_w + 1.0 / G_r)
    nu = G * 0.5 * (nu_wheel / G_w + nu_rail / G_r)
    return G, nu


class CreepModel(NamedTuple):
    """A creep law ready for the compiled call (:func:`creep_model`)."""

    name: str
    cp: np.ndarray             #: the ``CP_*`` parameters
    table: object              #: the :class:`~exudyn_wheelrail.creep.table.CreepTable` (``needs_table``), else None
    core: tuple                #: ``(code, cp, t_nodes, coef, tab)``: the trailing arguments of :func:`creep_forces`


def creep_model(name: str, *, mu: float, shear_modulus_Pa: float, poisson: float, fastsim_grid,
                v_min_m_s: float, creep_table=None) -> CreepModel:
    """Pack the law ``name`` of :data:`LAWS` with friction ``mu``, the combined ``shear_modulus_Pa`` and ``poisson``
    (:func:`combined_elastic_constants`), the FASTSIM grid ``(n_x, n_y)`` and the creepages' standstill guard
    ``v_min_m_s`` [m/s].  ``creep_table``: a :class:`~exudyn_wheelrail.creep.table.CreepTable` or a table file for a
    law that ``needs_table`` (default: the packaged table); its Poisson's ratio must match ``poisson``.  Arguments
    are taken as validated (the connector checks them)."""
    if name not in LAWS:
        raise ValueError(f"creep_law={name!r}: expected one of {sorted(LAWS)}")
    law = LAWS[name]
    cp = np.zeros(N_CP)
    cp[CP_MU] = mu
    cp[CP_G] = shear_modulus_Pa
    cp[CP_NU] = poisson
    cp[CP_NX], cp[CP_NY] = fastsim_grid
    cp[CP_V_MIN] = v_min_m_s
    cp[CP_AB_MIN] = _linear.A_OVER_B_MIN
    cp[CP_AB_MAX] = _linear.A_OVER_B_MAX
    table = None
    tab = None                  # a law without a table: the table's lookup is not compiled
    if law.needs_table:
        table = load_table(creep_table) if not hasattr(creep_table, "core_arrays") else creep_table
        if abs(poisson - table.poisson) > NU_TOLERANCE + 1e-12:
            raise ValueError(f"creep table built for Poisson's ratio {table.poisson}, the materials give {poisson:.3f} "
                             f"(accepted ±{NU_TOLERANCE}); build a table for this ν (python -m exudyn_wheelrail "
                             "creep-table --nu ...) or use creep_law='fastsim'")
        t_nodes, t_breaks, r_pad, th_pad, ps_pad, values_pad = table.core_arrays()
        tab = (np.ascontiguousarray(t_nodes, dtype=float), np.ascontiguousarray(t_breaks, dtype=np.int8),
               np.ascontiguousarray(r_pad, dtype=float), np.ascontiguousarray(th_pad, dtype=float),
               np.ascontiguousarray(ps_pad, dtype=float), np.ascontiguousarray(values_pad, dtype=float))
        cp[CP_AB_MIN], cp[CP_AB_MAX] = table.ratio_nodes[0], table.ratio_nodes[-1]
    return CreepModel(name, cp, table, (law.code, cp, _linear._T_NODES, _linear._COEF, tab))
