"""How a simulation is run (:class:`RunSettings`) and how its wheels touch the rails (:class:`ContactSettings`):
each field, its default and its check written once; the command line, the presets, the RTRI case and the scenario
files' ``[run]`` and ``[contact]`` tables all build these objects and nothing else.

>>> run = RunSettings(solver="rk44", dt_s=0.5e-3, duration_s=2.0)
>>> run.steps                 # derived from the duration, never the other way round
4000
>>> RunSettings(dt_s=0.01, duration_s=2.5).steps
250

Integrators: the table of :mod:`.solvers` (:data:`~.solvers.METHODS`); :func:`RunSettings.exudyn` sets them up
through :func:`~.exudyn_settings.solver_settings`
(:func:`~.exudyn_settings.run_solver_settings` of a :class:`RunSettings`).

Newton tolerance (:data:`NEWTON_TOLERANCE`, implicit solvers): 1e-4, Exudyn's relative and absolute residual
tolerance.  Measured on the RTRI case (20 m, 250 km/h, Newmark, 1 ms): 1e-4 gives the peaks of 1e-6 to within
1e-6 … 1e-4 relative (peak lateral force 20411 vs 20409 N, car-body acceleration equal to 4 digits) in 25 % less
time; 1e-3 moves the peak lateral force by 0.2 %.  One default for every run.

Errors: a bad value raises :class:`SettingsError` (a ``ValueError``) whose message is ``<field>: <problem>``; its
``field`` and ``problem`` let a front end name its own key or option instead (``run.dt_s``, ``--dt``).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from .. import contact_defaults as DEFAULT
from ..validation import Quantity, finite
from .solvers import DEFAULT_STEP_S, IMPLICIT_SOLVERS, NEWMARK_BETA, NEWMARK_GAMMA, SOLVERS, solver_description

__all__ = ["NEWTON_TOLERANCE", "DURATION_AUTO", "MAX_STEPS", "DT_S", "RUN_OUT_M", "SPEED_KM_H", "WHEEL_RAIL_MODES",
           "SettingsError", "RunSettings",
           "ContactSettings", "settings_from_mapping"]

#: Newton tolerance of the implicit solvers (module docstring: measured)
NEWTON_TOLERANCE = 1e-4
#: ``duration_s = DURATION_AUTO``: the spec decides (a scenario: until the trailing wheelset is ``run_out_m`` past
#: the end of the last track feature)
DURATION_AUTO = "auto"
#: most steps of one run
MAX_STEPS = 10_000_000
#: plausible time step and run-out (values outside are errors naming the unit they were evidently given in)
DT_S = Quantity("time step", "s", 1e-7, 0.01)
RUN_OUT_M = Quantity("run-out length", "m", 0.0, 1000.0)
#: plausible running speeds of the commands' speed options (``rtri``, ``rtri-sweep``, ``bridge-crossing``) and of a
#: bridge crossing's scenario
SPEED_KM_H = Quantity("running speed", "km/h", 0.1, 600.0)
#: ``ContactSettings.wheel_rail``: the wheel–rail connector, or linear springs at the nominal rail position (a cost
#: baseline: the track irregularities do not act, nothing is recorded)
WHEEL_RAIL_MODES = ("contact", "springs")


class SettingsError(ValueError):
    """A bad setting: ``str()`` is ``"<field>: <problem>"``."""

    def __init__(self, field_name: str, problem: str):
        super().__init__(f"{field_name}: {problem}")
        self.field = field_name
        self.problem = problem


def _number(name: str, value, lo=None, hi=None, lo_open=True, hi_open=False) -> float:
    if isinstance(value, (bool, str)):
        raise SettingsError(name, f"expected a number, got {value!r}")
    try:
        x = finite(name, value)
    except ValueError as exc:
        raise SettingsError(name, str(exc).split(": ", 1)[1]) from None
    if lo is not None and (x <= lo if lo_open else x < lo):
        raise SettingsError(name, f"{value!r}: must be {'>' if lo_open else '>='} {lo}")
    if hi is not None and (x >= hi if hi_open else x > hi):
        raise SettingsError(name, f"{value!r}: must be {'<' if hi_open else '<='} {hi}")
    return x


def _quantity(name: str, value, quantity: Quantity) -> float:
    x = _number(name, value)
    problem = quantity.problem(x)
    if problem:
        raise SettingsError(name, problem)
    return x


def _choice(name: str, value, choices) -> str:
    if not isinstance(value, str) or value not in choices:
        raise SettingsError(name, f"{value!r}: expected one of {', '.join(choices)}")
    return value


def _flag(name: str, value) -> bool:
    if not isinstance(value, bool):
        raise SettingsError(name, f"expected true or false, got {value!r}")
    return value


def _integer(name: str, value, lo: int, hi: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < lo or (hi is not None and value > hi):
        limits = f">= {lo}" + ("" if hi is None else f" and <= {hi}")
        raise SettingsError(name, f"{value!r}: expected an integer {limits}")
    return int(value)


@dataclass(frozen=True)
class RunSettings:
    """How a run is integrated and recorded (module docstring).  ``steps = ceil(duration_s / dt_s)``."""

    #: integrator, one of :data:`~.solvers.SOLVERS`
    solver: str = "newmark"
    #: time step [s] (fixed)
    dt_s: float = DEFAULT_STEP_S
    #: simulated time [s], or :data:`DURATION_AUTO` (the spec resolves it: :meth:`with_duration`)
    duration_s: float | str = DURATION_AUTO
    #: with ``duration_s = "auto"``: distance the trailing wheelset runs past the end of the last track feature [m]
    run_out_m: float = 10.0
    #: Newton tolerance of the implicit solvers (:data:`NEWTON_TOLERANCE`)
    newton_tolerance: float = NEWTON_TOLERANCE
    #: record a time series (one row per ``record_every`` steps)
    record: bool = True
    #: record every n-th state of the ``dt_s`` grid (n >= 1)
    record_every: int = 1
    #: a progress bar on stderr
    progress: bool = False

    def __post_init__(self):
        _choice("solver", self.solver, SOLVERS)
        dt = _quantity("dt_s", self.dt_s, DT_S)
        if isinstance(self.duration_s, str):
            if self.duration_s != DURATION_AUTO:
                raise SettingsError("duration_s", f"{self.duration_s!r}: expected a time in s or {DURATION_AUTO!r}")
        else:
            d = _number("duration_s", self.duration_s, lo=0.0)
            if d / dt > MAX_STEPS:
                raise SettingsError("duration_s", f"{d:g} s at dt_s = {dt:g} s: more than {MAX_STEPS} steps")
        _quantity("run_out_m", self.run_out_m, RUN_OUT_M)
        _number("newton_tolerance", self.newton_tolerance, lo=0.0, hi=1.0)
        _flag("record", self.record)
        _integer("record_every", self.record_every, 1)
        _flag("progress", self.progress)

    @property
    def steps(self) -> int:
        """Number of steps, ``ceil(duration_s / dt_s)`` (at least 1)."""
        if self.duration_s == DURATION_AUTO:
            raise ValueError("duration_s = 'auto' is not resolved yet (RunSettings.with_duration)")
        return max(1, int(math.ceil(float(self.duration_s) / float(self.dt_s) - 1e-9)))

    @property
    def end_time_s(self) -> float:
        """The time the run ends at: ``steps * dt_s`` (the duration rounded up to whole steps)."""
        return self.steps * float(self.dt_s)

    @property
    def implicit(self) -> bool:
        return self.solver in IMPLICIT_SOLVERS

    def with_duration(self, duration_s: float) -> "RunSettings":
        """A copy with the duration set (e.g. ``"auto"`` resolved by the spec)."""
        return dataclasses.replace(self, duration_s=float(duration_s))

    def describe_solver(self) -> str:
        """One line naming the Exudyn integrator."""
        return solver_description(self.solver, float(self.newton_tolerance), NEWMARK_BETA, NEWMARK_GAMMA)

    def as_dict(self) -> dict:
        return dataclasses.asdict(self)


@dataclass(frozen=True)
class ContactSettings:
    """How the wheels touch the rails: creep law, friction coefficient, FASTSIM grid, contact geometry (``"online"``
    search or the precomputed ``"table"`` for the rigid rail profile, :mod:`~exudyn_wheelrail.contact.
    geometry_table`), the wheel–rail element (:data:`WHEEL_RAIL_MODES`) and the normal contact (Hertz or the
    non-Hertzian patch).  The defaults of the creep law, the
    friction coefficient and the geometry are the connector's, declared in :mod:`exudyn_wheelrail.contact_defaults`;
    the creep laws are those of :data:`exudyn_wheelrail.creep.registry.LAWS`."""

    creep_law: str = DEFAULT.CREEP_LAW
    friction: float = DEFAULT.FRICTION
    #: FASTSIM's (n_x, n_y) grid (creep law "fastsim" only): 24 x 8, the grid of the RTRI case and the scenarios —
    #: a quarter of the points of FASTSIM's own default (:data:`~exudyn_wheelrail.creep.fastsim.DEFAULT_NX` x
    #: ``DEFAULT_NY``), for simulation cost
    fastsim_grid: tuple[int, int] = (24, 8)
    geometry: str = DEFAULT.GEOMETRY
    wheel_rail: str = WHEEL_RAIL_MODES[0]
    #: the normal contact: Hertz's ellipse, or the non-Hertzian patch where Hertz does not hold
    #: (:mod:`~exudyn_wheelrail.contact.patch_pass`)
    contact_patch: str = DEFAULT.CONTACT_PATCH

    def __post_init__(self):
        _choice("creep_law", self.creep_law, tuple(sorted(DEFAULT.CREEP_LAW_NAMES)))
        _number("friction", self.friction, lo=0.0, hi=2.0, lo_open=False, hi_open=True)
        try:
            grid = tuple(self.fastsim_grid)
        except TypeError:
            grid = ()
        if len(grid) != 2:
            raise SettingsError("fastsim_grid", f"{self.fastsim_grid!r}: expected two positive integers (n_x, n_y)")
        for g in grid:
            _integer("fastsim_grid", g, 1, 1000)
        object.__setattr__(self, "fastsim_grid", (int(grid[0]), int(grid[1])))
        _choice("geometry", self.geometry, DEFAULT.GEOMETRY_MODES)
        _choice("wheel_rail", self.wheel_rail, WHEEL_RAIL_MODES)
        _choice("contact_patch", self.contact_patch, DEFAULT.CONTACT_PATCHES)

    def as_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d["fastsim_grid"] = list(self.fastsim_grid)
        return d


def settings_from_mapping(cls, mapping: dict, key: str = ""):
    """``cls(**mapping)`` (:class:`RunSettings` or :class:`ContactSettings`) with unknown keys refused: a
    :class:`SettingsError` naming ``<key>.<name>`` (``key`` the table's name, e.g. ``"run"``) and the allowed
    keys; a bad value's error names ``<key>.<field>``."""
    names = [f.name for f in dataclasses.fields(cls)]
    prefix = f"{key}." if key else ""
    if not isinstance(mapping, dict):
        raise SettingsError(key or cls.__name__, f"expected a table, got {type(mapping).__name__} {mapping!r}")
    for k in mapping:
        if k not in names:
            raise SettingsError(f"{prefix}{k}", f"unknown key (allowed{' in [' + key + ']' if key else ''}: "
                                                f"{', '.join(names)})")
    values = dict(mapping)
    if cls is ContactSettings and isinstance(values.get("fastsim_grid"), list):
        values["fastsim_grid"] = tuple(values["fastsim_grid"])
    try:
        return cls(**values)
    except SettingsError as exc:
        raise SettingsError(f"{prefix}{exc.field}", exc.problem) from None
