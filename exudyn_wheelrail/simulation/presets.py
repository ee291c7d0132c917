"""Accuracy/speed presets of a vehicle run: ``--preset fast|default|accurate`` (``rtri``, ``rtri-sweep``).

A preset sets fields of the :class:`~.settings.RunSettings` (integrator, time step) and of the
:class:`~.settings.ContactSettings` (contact geometry — online search or the precomputed table,
:mod:`~exudyn_wheelrail.contact.geometry_table` — and creep law); options given explicitly override it, and the run
summary states the preset, what it set and what was overridden (:func:`apply_preset`).  The choice is made from the
work–precision study (``benchmarks/work_precision.py``, RTRI 20 m at 250 km/h against a converged RK44 0.05 ms
reference; table and reasons in ``benchmarks/README.md``).  Targets (one core): ``default`` at least 6x faster than
real time with at most 1 % error in the peak lateral contact force; ``fast`` at least 15x with at most 5 %.
Measured (``benchmarks/bench_presets.py``, 2 shared cores, load 1.0; real-time factor without / with recording,
peak lateral force error): accurate 1.0x / 1.0x, 0.05 %; default 3.8x / 4.0x, 0.57 %; fast 5.5x / 5.0x, 2.5 %
(on that machine the vehicle on linear rail springs runs at 8.6x) — the error targets are met, the speed targets
are not (benchmarks/README.md says why).  ``fast`` interpolates the creep table multilinearly (the law
``table_linear``): 10 % of its step for 0.7 % more error in the peak lateral force than the cubic table.

No preset sets the normal contact: every one runs Hertz's ellipse (the contact settings' default) unless the
non-Hertzian patch is asked for (``--contact-patch non-hertzian``, :mod:`~exudyn_wheelrail.contact.patch_pass`), on
top of any preset and at its cost (``docs/performance.md``); the presets' accuracy is measured against a reference
with Hertz.

Without a preset a front end keeps its own settings (``rtri``: the paper's Newmark β = 1/4, γ = 1/2, 1 ms, online
geometry).  A preset does not set the simulated duration.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from .settings import ContactSettings, RunSettings
from .solvers import DEFAULT_STEP_S

__all__ = ["Preset", "PRESETS", "TARGETS", "SPRINGS_RATIO_MAX", "apply_preset"]


@dataclass(frozen=True)
class Preset:
    """A preset: the :class:`RunSettings` and :class:`ContactSettings` fields it sets, and what it is for."""

    name: str
    run: dict
    contact: dict
    purpose: str

    def __post_init__(self):
        RunSettings(**self.run)                  # the fields exist and the values are valid
        # the contact fields exist; their values are checked where the preset is applied (:func:`apply_preset`
        # builds the ContactSettings: the creep law's name is checked against the creep laws' registry, which
        # loads their compiled code, so not when the presets are merely listed, e.g. by ``--help``)
        unknown = sorted(set(self.contact) - {f.name for f in dataclasses.fields(ContactSettings)})
        if unknown:
            raise ValueError(f"preset {self.name}: unknown contact settings {', '.join(unknown)}")


PRESETS = {
    "accurate": Preset("accurate", run=dict(solver="rk44", dt_s=0.25e-3),
                       contact=dict(geometry="online", creep_law="table"),
                       purpose="reference-quality runs: RK44 at 0.25 ms, online contact search, Kalker's exact "
                               "theory (table); peak lateral force converged to about 0.1 %"),
    "default": Preset("default", run=dict(solver="rk44", dt_s=DEFAULT_STEP_S),
                      contact=dict(geometry="online", creep_law="table"),
                      purpose="everyday runs: RK44 at 1 ms (the paper's step), online contact search, Kalker's "
                              "exact theory (table); peak lateral force within 1 % of the converged reference"),
    "fast": Preset("fast", run=dict(solver="rk44", dt_s=DEFAULT_STEP_S),
                   contact=dict(geometry="table", creep_law="table_linear"),
                   purpose="parameter studies and interactive use: RK44 at 1 ms with the precomputed contact "
                           "geometry (rigid rail profile) and Kalker's exact theory (table, interpolated "
                           "multilinearly); peak lateral force within 5 % of the converged reference"),
}

#: per preset: (minimum real-time factor on one core, maximum relative error of the peak lateral contact force of
#: wheelset 1, right wheel)
TARGETS = {"default": (6.0, 0.01), "fast": (15.0, 0.05)}
#: the ``default`` preset's cost against the same vehicle on linear rail springs (same solver, one run): at most this
SPRINGS_RATIO_MAX = 2.0


def apply_preset(preset: str | None, run: RunSettings, contact: ContactSettings, *, run_options: dict | None = None,
                 contact_options: dict | None = None) -> tuple[RunSettings, ContactSettings, dict | None]:
    """``run`` and ``contact`` (the front end's settings) with the preset's fields, then the explicitly given
    ``run_options`` / ``contact_options`` (field -> value; ``None`` values are not given) on top.  Returns
    ``(run, contact, record)``; ``record`` (``None`` without a preset) is for the run summary: the preset's name,
    purpose, what it set, what the options overrode, and its targets."""
    run_opts = {k: v for k, v in (run_options or {}).items() if v is not None}
    contact_opts = {k: v for k, v in (contact_options or {}).items() if v is not None}
    record = None
    if preset is not None:
        if preset not in PRESETS:
            raise ValueError(f"preset {preset!r}: expected one of {', '.join(PRESETS)}")
        p = PRESETS[preset]
        run = dataclasses.replace(run, **p.run)
        contact = dataclasses.replace(contact, **p.contact)
        record = {"name": p.name, "purpose": p.purpose, "set": {"run": dict(p.run), "contact": dict(p.contact)},
                  "overridden_by_options": {k: v for k, v in {**run_opts, **contact_opts}.items()
                                            if k in p.run or k in p.contact}}
        if preset in TARGETS:
            record["targets"] = {"min_real_time_factor": TARGETS[preset][0],
                                 "max_peak_lateral_force_error": TARGETS[preset][1]}
    return dataclasses.replace(run, **run_opts), dataclasses.replace(contact, **contact_opts), record
