"""Accuracy/speed presets of a vehicle run: ``--preset fast|default|accurate`` (``rtri`` command, :func:`resolve`).

A preset fixes the integrator, the time step, the contact geometry (online search or the precomputed table,
:mod:`~exudyn_wheelrail.contact.geometry_table`) and the creep law; options given explicitly on the command line
override it, and the run summary states the preset, what it set and what was overridden.  The choice is made from
the work–precision study (``benchmarks/work_precision.py``, RTRI 20 m at 250 km/h against a converged RK44 0.05 ms
reference; table and reasons in ``benchmarks/README.md``).  Targets of issue 6 (one core): ``default`` at least 6x faster
than real time with at most 1 % error in the peak lateral contact force; ``fast`` at least 15x with at most 5 %.
Measured (``benchmarks/bench_presets.py``, shared machine): accurate 1.0x / 0.05 %; default 3.9x / 0.57 %; fast
5.8x / 1.8 % — the error targets are met, the speed targets are not (benchmarks/README.md says why).

Without a preset the ``rtri`` command keeps the paper's settings (Newmark β = 1/4, γ = 1/2, 1 ms, online geometry).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

#: simulated duration of a preset run when the number of steps is not given: the published 2500 steps of 1 ms
PRESET_DURATION_S = 2.5


@dataclass(frozen=True)
class Preset:
    name: str
    solver: str
    dt_s: float
    geometry: str
    creep_law: str
    purpose: str

    def settings(self) -> dict:
        d = asdict(self)
        d.pop("name")
        d.pop("purpose")
        return d


PRESETS = {
    "accurate": Preset("accurate", solver="rk44", dt_s=0.25e-3, geometry="online", creep_law="table",
                       purpose="reference-quality runs: RK44 at 0.25 ms, online contact search, Kalker's exact "
                               "theory (table); peak lateral force converged to about 0.1 %"),
    "default": Preset("default", solver="rk44", dt_s=1.0e-3, geometry="online", creep_law="table",
                      purpose="everyday runs: RK44 at 1 ms (the paper's step), online contact search, Kalker's "
                              "exact theory (table); peak lateral force within 1 % of the converged reference"),
    "fast": Preset("fast", solver="rk44", dt_s=1.0e-3, geometry="table", creep_law="table",
                   purpose="parameter studies and interactive use: RK44 at 1 ms with the precomputed contact "
                           "geometry (rigid rail profile) and Kalker's exact theory (table); peak lateral force "
                           "within 5 % of the converged reference"),
}

#: targets of issue 6 per preset: (minimum real-time factor on one core, maximum relative error of the peak
#: lateral contact force of wheelset 1, right wheel)
TARGETS = {"default": (6.0, 0.01), "fast": (15.0, 0.05)}


def resolve(preset: str | None, *, solver=None, dt_s=None, geometry=None, creep_law=None, steps=None,
            paper_defaults: dict | None = None) -> tuple[dict, dict | None]:
    """Run settings from a preset and explicit options.  Returns ``(settings, preset_record)``: ``settings`` has
    solver, dt_s, geometry, creep_law, steps; ``preset_record`` (``None`` without a preset) is for the run summary:
    the preset's name, purpose, what it set, what was overridden, and its targets."""
    explicit = {k: v for k, v in dict(solver=solver, dt_s=dt_s, geometry=geometry, creep_law=creep_law).items()
                if v is not None}
    if preset is None:
        base = dict(paper_defaults or {})
        base.update(explicit)
        base["steps"] = steps
        return base, None
    if preset not in PRESETS:
        raise ValueError(f"preset {preset!r}: expected one of {sorted(PRESETS)}")
    p = PRESETS[preset]
    settings = p.settings()
    settings.update(explicit)
    if steps is None:
        steps = int(round(PRESET_DURATION_S / settings["dt_s"]))
    settings["steps"] = steps
    record = {"name": p.name, "purpose": p.purpose, "set": p.settings(),
              "overridden_by_options": explicit, "steps": steps}
    if preset in TARGETS:
        record["targets"] = {"min_real_time_factor": TARGETS[preset][0],
                             "max_peak_lateral_force_error": TARGETS[preset][1]}
    return settings, record
