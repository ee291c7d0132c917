"""Write a modes file as an FE program would export it: the modes of a two-span continuous deck (2 x 25 m,
illustrative section) from the built-in beam model, every 0.5 m along the track axis, in the CSV layout of
``exudyn_wheelrail/structures/modes_file.py`` (one row per mode and position; vertical + down, lateral + right,
torsion right-hand about the running direction; modal masses of the shapes as written).

    python examples/bridges/export_modes.py examples/bridges/fe_modes_2x25m.csv

A real bridge's file comes from its FE model (a skewed, framed or haunched deck); this one lets the bridge file
``fe_modes_2x25m.toml`` run anywhere and can be checked against ``continuous_2x25m.toml`` (the same deck built in).
"""
from __future__ import annotations

import sys

import numpy as np

from exudyn_wheelrail.structures import BridgeModel, DeckSection

SPANS_M = (25.0, 25.0)
#: the deck of continuous_2x25m.toml at its nominal mass, with lateral, torsional and axial stiffness
SECTION = DeckSection(m_kg_m=14500.0, EI_y_Nm2=5.2e10, EI_z_Nm2=4.0e11, GJ_Nm2=3.0e10, EA_N=2.0e11,
                      Ip_kgm2_m=4.0e4)
F_MAX_HZ = 45.0
STEP_M = 0.5


def main(path: str) -> None:
    model = BridgeModel(SPANS_M, SECTION, continuous=True, elements_per_span=50)
    modes = model.modes(f_max_Hz=F_MAX_HZ)
    keep = [i for i, k in enumerate(modes.kinds) if k in ("vertical", "lateral", "torsion")]
    x = np.arange(0.0, sum(SPANS_M) + 0.5 * STEP_M, STEP_M)
    phi = modes.shape_at(x)                                  # (k, 3, n): y_rail, z_rail, θ_rail (rail height 0)
    scale = 1000.0                                           # shapes in mm-like magnitudes, modal mass 1e6 kg
    with open(path, "w") as fh:
        fh.write("# modes of a 2 x 25 m continuous deck (illustrative), exported by examples/bridges/export_modes.py\n")
        fh.write("mode,frequency_hz,modal_mass_kg,x_m,vertical,lateral,torsion\n")
        for j, i in enumerate(keep, 1):
            for xi, row in zip(x, phi[:, :, i]):
                fh.write(f"{j},{modes.frequencies_Hz[i]:.10g},{scale ** 2:.10g},{xi:.10g},{scale * row[1]:.10g},"
                         f"{scale * row[0]:.10g},{scale * row[2]:.10g}\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "fe_modes_2x25m.csv")
