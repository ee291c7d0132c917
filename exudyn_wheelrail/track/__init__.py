"""The track as a function of distance: its layout (straight, curves, transitions, cant), the irregularities of each
rail (measured, harmonic, isolated defects, generated from standard spectra) and its flexibility (rails on pads,
sleepers and ballast).  The rigid straight track with whole-track irregularities lives in
:mod:`exudyn_wheelrail.track.rigid`."""

from .layout import Curve, Straight, TrackLayout, Transition  # noqa: E402,F401  (the track layout)
from .irregularities import (ChannelTable, FadedIn, IsolatedDefect,  # noqa: E402,F401  (per-rail channels)
                             channel_values, rail_values)
from .measured import read_irregularity_csv  # noqa: E402,F401  (measured irregularity files)
from .spectra import SPECTRA, SpectralIrregularity, TrackSpectrum  # noqa: E402,F401  (standard spectra)
from .flexible_parameters import DEFAULT_TRACK_FILE, TrackFileError, TrackParameters  # noqa: E402,F401
from .flexible import FlexibleTrackModel, FlexibleTrackModes, add_flexible_track  # noqa: E402,F401  (flexible track)
from .flexible_deck import TrackOnDeckModel, TrackOnDeckModes  # noqa: E402,F401  (the track over a deck)
from .flexible_window import FlexibleTrackWindow, window_length_m  # noqa: E402,F401  (the moving window)
from .flexible_outputs import track_under_wheels  # noqa: E402,F401  (rail, sleeper, pad, ballast under wheels)
