"""Start a vehicle in static equilibrium on its rails: the axle height at which each wheel carries its static load.

The vertical offset comes from the quasi-static contact of the centred wheelset (rigid touching height plus the
Hertz approach, :func:`~exudyn_wheelrail.analysis.quasi_static.solve_quasi_static` without creep); all bodies of
the vehicle move together, so the suspension preloads of the builder's static load path are unchanged.
Frames: the track/model frame of :mod:`exudyn_wheelrail.conventions` (z down); SI units.
"""
from __future__ import annotations

import numpy as np

from ..contact.pair import WheelRailPair

__all__ = ["static_axle_offset_m", "place_on_rails"]


def static_axle_offset_m(pair: WheelRailPair, wheel_load_N: float, r0_m: float, E_Pa: float = 2.1e11,
                         nu: float = 0.28) -> float:
    """Vertical offset (z down) of the centred wheelset's axle from its nominal height ``-r0`` at which each wheel
    carries ``wheel_load_N`` by its normal force (quasi-static, no creep): the rigid touching height plus the Hertz
    approach.  Used to start a simulation in equilibrium."""
    from ..analysis.quasi_static import solve_quasi_static
    from ..contact.wheelset import WheelsetContact

    contact = WheelsetContact(pair, 1, E_Pa, nu, E_Pa, nu, global_search=True)
    res = solve_quasi_static(contact, 0.0, 0.0, wheel_load_N, 1.0, shear_modulus_Pa=E_Pa / (2 * (1 + nu)),
                             poisson=nu, creep_law=lambda *a: (0.0, 0.0, 0.0), pitch_rate_rad_s=-1.0 / r0_m,
                             semi_axis_ratio_range=None)
    if not res.converged:
        raise RuntimeError(f"static wheelset position not found: {res.message}")
    return res.z_m - (-r0_m)


def place_on_rails(mbs, model, pair: WheelRailPair, E_Pa: float = 2.1e11, nu: float = 0.28) -> float:
    """Shift every body of a :class:`~.vehicle_builder.VehicleModel` vertically so the centred wheelsets start in
    static equilibrium on the rails (the suspension preloads are unchanged: all bodies move together).  Call before
    ``mbs.Assemble()``.  Returns the shift [m] (z down)."""
    loads = model.load_path.wheel if model.load_path is not None else None
    if loads is None:
        raise ValueError("the vehicle model has no static load path (build it with preload=True)")
    dz = static_axle_offset_m(pair, float(np.mean(loads)), model.wheelsets[0].r0_m, E_Pa, nu)
    for body in model.bodies:
        q0 = np.array(mbs.GetNodeParameter(body.node, "initialCoordinates"), dtype=float)
        q0[2] += dz
        mbs.SetNodeParameter(body.node, "initialCoordinates", q0.tolist())
    return dz
