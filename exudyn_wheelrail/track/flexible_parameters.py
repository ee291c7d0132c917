"""The parameters of the flexible track (rails, pads, sleepers, ballast, model resolution) and the track file that
holds them (:data:`DEFAULT_TRACK_FILE`, every value with its source): :class:`TrackParameters`, checked on
construction (:class:`TrackFileError` names the file and the key), and the three independent beams the track splits
into (:data:`KINDS`, :meth:`TrackParameters.beam`; :mod:`.flexible`)."""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from ..validation import read_toml

__all__ = ["DEFAULT_TRACK_FILE", "KINDS", "DAMPING_FORMS", "TrackFileError", "TrackParameters"]

#: the default track file: ballasted 60E1 track on concrete sleepers, every value with its source
DEFAULT_TRACK_FILE = Path(__file__).resolve().parent.parent / "data" / "track_60E1_ballasted.toml"
#: the three independent beams of the track (module docstring), in the order of the modal coordinates
KINDS = ("vertical", "roll", "lateral")
#: the projected modal damping kept: the full matrix Φᵀ C Φ per beam, or its diagonal
DAMPING_FORMS = ("full", "diagonal")


class TrackFileError(ValueError):
    """Invalid track parameters: the message names the file (or ``<parameters>``) and the key."""


# ------------------------------------------------------------------------------------------- parameters
#: (table, key) of every track-file entry -> (attribute, kind): "positive", "non_negative", "count"
_FILE_KEYS = {
    ("rail", "E_Pa"): ("rail_E_Pa", "positive"),
    ("rail", "I_vertical_m4"): ("rail_I_vertical_m4", "positive"),
    ("rail", "I_lateral_m4"): ("rail_I_lateral_m4", "positive"),
    ("rail", "mass_kg_m"): ("rail_mass_kg_m", "positive"),
    ("rail", "centre_distance_m"): ("rail_centre_distance_m", "positive"),
    ("pad", "k_vertical_N_m"): ("pad_k_vertical_N_m", "positive"),
    ("pad", "c_vertical_Ns_m"): ("pad_c_vertical_Ns_m", "non_negative"),
    ("pad", "k_lateral_N_m"): ("pad_k_lateral_N_m", "positive"),
    ("pad", "c_lateral_Ns_m"): ("pad_c_lateral_Ns_m", "non_negative"),
    ("sleeper", "spacing_m"): ("sleeper_spacing_m", "positive"),
    ("sleeper", "mass_kg"): ("sleeper_mass_kg", "positive"),
    ("sleeper", "roll_inertia_kgm2"): ("sleeper_roll_inertia_kgm2", "positive"),
    ("ballast", "k_vertical_N_m"): ("ballast_k_vertical_N_m", "positive"),
    ("ballast", "c_vertical_Ns_m"): ("ballast_c_vertical_Ns_m", "non_negative"),
    ("ballast", "k_lateral_N_m"): ("ballast_k_lateral_N_m", "positive"),
    ("ballast", "c_lateral_Ns_m"): ("ballast_c_lateral_Ns_m", "non_negative"),
    ("model", "elements_per_bay"): ("elements_per_bay", "count"),
    ("model", "modes_up_to_Hz"): ("modes_up_to_Hz", "positive"),
    ("model", "table_subdivision"): ("table_subdivision", "count"),
}
_KEY_OF = {attr: f"{t}.{k}" for (t, k), (attr, _) in _FILE_KEYS.items()}


@dataclass(frozen=True)
class TrackParameters:
    """The parameters of a flexible track (the track file's keys, module docstring; units in the names; per rail
    seat for the pads, per sleeper for the ballast).  Checked on construction: a bad value raises
    :class:`TrackFileError` naming the track-file key.  The defaults live in one place, the track file
    :data:`DEFAULT_TRACK_FILE` (:meth:`from_file`)."""

    rail_E_Pa: float
    rail_I_vertical_m4: float
    rail_I_lateral_m4: float
    rail_mass_kg_m: float
    rail_centre_distance_m: float
    pad_k_vertical_N_m: float
    pad_c_vertical_Ns_m: float
    pad_k_lateral_N_m: float
    pad_c_lateral_Ns_m: float
    sleeper_spacing_m: float
    sleeper_mass_kg: float
    sleeper_roll_inertia_kgm2: float
    ballast_k_vertical_N_m: float
    ballast_c_vertical_Ns_m: float
    ballast_k_lateral_N_m: float
    ballast_c_lateral_Ns_m: float
    elements_per_bay: int
    modes_up_to_Hz: float
    table_subdivision: int
    source: str = "<parameters>"

    def __post_init__(self):
        for attr, kind in _FILE_KEYS.values():
            v = getattr(self, attr)
            where = f"{self.source}: {_KEY_OF[attr]}"
            if kind == "count":
                if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
                    raise TrackFileError(f"{where}: {v!r}: expected an integer >= 1")
                continue
            if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) \
                    or not math.isfinite(float(v)):
                raise TrackFileError(f"{where}: {v!r}: expected a finite number")
            if kind == "positive" and not v > 0.0:
                raise TrackFileError(f"{where}: {v!r}: must be > 0")
            if kind == "non_negative" and v < 0.0:
                raise TrackFileError(f"{where}: {v!r}: must be >= 0 (a negative damping feeds energy in)")

    @classmethod
    def from_file(cls, path=None, **overrides) -> "TrackParameters":
        """The parameters of a track file (TOML; default :data:`DEFAULT_TRACK_FILE`), with attribute
        ``overrides`` (e.g. ``pad_k_vertical_N_m=1e9``).  Every key of the file is required."""
        path = Path(path) if path is not None else DEFAULT_TRACK_FILE
        if not path.is_file():
            raise TrackFileError(f"{path}: track file not found")
        data = read_toml(path, TrackFileError)
        tables = sorted({t for t, _ in _FILE_KEYS})
        for t in data:
            if t not in tables:
                raise TrackFileError(f"{path}: {t}: unknown table (expected {', '.join(tables)})")
        values = {}
        for (t, k), (attr, _) in _FILE_KEYS.items():
            tab = data.get(t)
            if not isinstance(tab, dict):
                raise TrackFileError(f"{path}: [{t}]: missing table")
            if k not in tab:
                raise TrackFileError(f"{path}: {t}.{k}: missing (required)")
            values[attr] = tab[k]
        for t in tables:
            for k in data[t]:
                if (t, k) not in _FILE_KEYS:
                    raise TrackFileError(f"{path}: {t}.{k}: unknown key")
        for attr in overrides:
            if attr not in values:
                raise TrackFileError(f"{path}: override {attr!r}: not a track parameter "
                                     f"(one of {', '.join(values)})")
        values.update(overrides)
        return cls(**values, source=str(path))

    def replace(self, **changes) -> "TrackParameters":
        d = {f.name: getattr(self, f.name) for f in fields(self)}
        d.update(changes)
        return TrackParameters(**d)

    # the three beams (module docstring): (EI, m, k_pad, c_pad, m_sleeper, k_ballast, c_ballast)
    def beam(self, kind: str) -> tuple:
        b2 = self.rail_centre_distance_m ** 2
        E, m = self.rail_E_Pa, self.rail_mass_kg_m
        if kind == "vertical":
            return (2 * E * self.rail_I_vertical_m4, 2 * m, 2 * self.pad_k_vertical_N_m, 2 * self.pad_c_vertical_Ns_m,
                    self.sleeper_mass_kg, self.ballast_k_vertical_N_m, self.ballast_c_vertical_Ns_m)
        if kind == "roll":
            return (E * self.rail_I_vertical_m4 * b2 / 2, m * b2 / 2, self.pad_k_vertical_N_m * b2 / 2,
                    self.pad_c_vertical_Ns_m * b2 / 2, self.sleeper_roll_inertia_kgm2,
                    self.ballast_k_vertical_N_m * b2 / 4, self.ballast_c_vertical_Ns_m * b2 / 4)
        if kind == "lateral":
            return (2 * E * self.rail_I_lateral_m4, 2 * m, 2 * self.pad_k_lateral_N_m, 2 * self.pad_c_lateral_Ns_m,
                    self.sleeper_mass_kg, self.ballast_k_lateral_N_m, self.ballast_c_lateral_Ns_m)
        raise ValueError(f"kind={kind!r}: expected one of {KINDS}")

    def support_stiffness_per_rail_N_m2(self) -> float:
        """Vertical support stiffness of one rail per metre, pad and half the ballast in series, smeared over
        the sleeper spacing [N/m²] (the ``k`` of Zimmermann's continuous support)."""
        kp, kb = self.pad_k_vertical_N_m, 0.5 * self.ballast_k_vertical_N_m
        return kp * kb / (kp + kb) / self.sleeper_spacing_m
