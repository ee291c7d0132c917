"""Published tables the models compute with, as plain values, declared once: the universal trains HSLM-A of
EN 1991-2 (used by :mod:`exudyn_wheelrail.structures.load_models`), the deck-acceleration limits of EN 1990 A2
(:mod:`exudyn_wheelrail.scenarios.deck`) and the standard spectra of track irregularities
(:mod:`exudyn_wheelrail.track.spectra`).  Their sources, formulas and checks are in those modules' docstrings.

This module imports nothing, so that a front end can list the choices before any work (the command line's
``--help``) without loading the numerical code.

>>> HSLM_NAMES[0], HSLM_NAMES[-1], len(TRACK_SPECTRA)
('A1', 'A10', 8)
"""

__all__ = ["HSLM_A", "HSLM_NAMES", "HSLM_POWER_CAR_AXLES_M", "HSLM_POWER_CAR_TO_END_COACH_M",
           "HSLM_END_COACH_TO_BOGIE_M", "EN1991_DAMPING_PERCENT", "EN1991_ADDITIONAL_DAMPING_MAX_SPAN_M",
           "EN1990_DECK_ACCELERATION_LIMITS_M_S2", "TRACK_FORMS", "FRA_CLASSES",
           "FRA_K", "FRA_OMEGA_C", "GERMAN_SPECTRA", "GERMAN_OMEGA",
           "GERMAN_B", "TRACK_SPECTRA", "DEFAULT_BAND_M"]

# ------------------------------------------------------------------------------- EN 1991-2:2003, HSLM-A trains
#: EN 1991-2:2003 Table 6.3: universal train -> (N intermediate coaches, coach length D [m], bogie axle spacing
#: d [m], point force P [kN])
HSLM_A = {"A1": (18, 18.0, 2.0, 170.0), "A2": (17, 19.0, 3.5, 200.0), "A3": (16, 20.0, 2.0, 180.0),
          "A4": (15, 21.0, 3.0, 190.0), "A5": (14, 22.0, 2.0, 170.0), "A6": (13, 23.0, 2.0, 180.0),
          "A7": (13, 24.0, 2.0, 190.0), "A8": (12, 25.0, 2.5, 190.0), "A9": (11, 26.0, 2.0, 210.0),
          "A10": (11, 27.0, 2.0, 210.0)}
HSLM_NAMES = tuple(HSLM_A)
#: EN 1991-2:2003 Figure 6.12: axle places of a power car from its leading axle [m]
HSLM_POWER_CAR_AXLES_M = (0.0, 3.0, 14.0, 17.0)
#: Figure 6.12: from the power car's axle next to the end coach to the end coach's first axle [m]
HSLM_POWER_CAR_TO_END_COACH_M = 3.525
#: Figure 6.12: from the end coach's first axle to the centre of the first articulated bogie, minus D [m]
HSLM_END_COACH_TO_BOGIE_M = -3.525 / 2.0

# ------------------------------------------------------------------------------ EN 1991-2:2003, bridge damping
#: EN 1991-2:2003 Table 6.6: lower limit of the damping ratio ζ [%] of a span L by structure type: (ζ for
#: L >= 20 m, increase per metre below 20 m), i.e. ζ = ζ_20 + s (20 - L) for L < 20 m
EN1991_DAMPING_PERCENT = {"steel_composite": (0.5, 0.125), "prestressed_concrete": (1.0, 0.07),
                          "reinforced_concrete": (1.5, 0.07), "filler_beam": (1.5, 0.07)}
#: EN 1991-2:2003 6.4.6.3.1(3): the additional damping Δζ of Eq. (6.13) applies to spans below this [m]
EN1991_ADDITIONAL_DAMPING_MAX_SPAN_M = 30.0

# ------------------------------------------------------------------- EN 1990 A2, deck acceleration of a bridge
#: EN 1990:2002/A1:2005 A2.4.4.2.1(4)P: largest peak vertical deck acceleration [m/s²] by track form
#: (γ_bt ballasted track, γ_df direct fastening)
EN1990_DECK_ACCELERATION_LIMITS_M_S2 = {"ballasted": 3.5, "direct_fastening": 5.0}
TRACK_FORMS = tuple(EN1990_DECK_ACCELERATION_LIMITS_M_S2)

# ----------------------------------------------------------------------- standard spectra of track irregularities
#: FRA track classes (Hamid & Yang 1981): class -> (A_v, A_a, Ω_s) [cm² rad/m, cm² rad/m, rad/m]
FRA_CLASSES = {1: (1.2107, 3.3634, 0.6046), 2: (1.0181, 1.2107, 0.9308), 3: (0.6816, 0.4128, 0.8520),
               4: (0.5376, 0.3027, 1.1312), 5: (0.2095, 0.0762, 0.8209), 6: (0.0339, 0.0339, 0.4380)}
#: the FRA spectra's k and Ω_c [rad/m]
FRA_K = 0.25
FRA_OMEGA_C = 0.8245
#: German high-speed spectra: interference -> (A_a, A_v, A_g) [m rad]
GERMAN_SPECTRA = {"low": (2.119e-7, 4.032e-7, 5.32e-8), "high": (6.125e-7, 1.080e-6, 1.032e-7)}
#: the German spectra's Ω_c, Ω_r, Ω_s [rad/m] and b [m] (half the rail-centre distance)
GERMAN_OMEGA = (0.8246, 0.0206, 0.4380)
GERMAN_B = 0.75
#: the standard spectra by name -> (family, level, source): ``"fra"`` with the class, ``"german"`` with the
#: interference
TRACK_SPECTRA = {**{f"fra_class_{c}": ("fra", c, f"FRA class {c} (Hamid & Yang 1981)") for c in FRA_CLASSES},
                 **{f"german_{lv}": ("german", lv, f"German high-speed, {lv} interference") for lv in GERMAN_SPECTRA}}
#: wavelength band of generated irregularities by default [m] (EN 13848-1's D1–D3 together: 3–150 m)
DEFAULT_BAND_M = (3.0, 150.0)
