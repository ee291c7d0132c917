r"""The RTRI explorer without a GUI: slider values in, a re-run of the RTRI case and its update time out.

>>> ex = RtriExplorer()                                   # warms up the compiled code once   # doctest: +SKIP
>>> u = ex.update(speed_km_h=200.0, deviation_mm=12.0)    # other values keep their last setting # doctest: +SKIP
>>> u.seconds, u.peaks["max_abs_carbody_lateral_acceleration_rear_m_s2"]                       # doctest: +SKIP

The GUI (:mod:`.explorer_figure`) puts one slider on each :data:`PARAMETERS` entry and calls :meth:`RtriExplorer.
update` on release.  Each update builds and runs one :class:`~exudyn_wheelrail.scenarios.rtri.RtriCase` (substitute
inputs and assumptions of :mod:`exudyn_wheelrail.scenarios.rtri`, recorded in the result's summary):

* speed [km/h], span [m], deviation amplitude δ [mm] — the case's ``speed_km_h``, ``span_m``,
  ``deviation_amplitude_m``;
* friction coefficient μ — the case's ``ContactSettings.friction``;
* four suspension factors on the values of ``vehicles/manchester_vehicle1.toml`` (``RtriCase.vehicle_overrides``):
  primary longitudinal stiffness ``primary.kx_N_per_m`` (per axlebox; it sets the wheelsets' yaw stiffness in the
  bogie, hence their hunting stability), primary lateral stiffness ``primary.ky_N_per_m``, secondary lateral
  stiffness ``secondary.ky_N_per_m`` and secondary lateral damping ``secondary.cy_N_s_per_m`` (per bogie side;
  the car body's lateral mode).  The Manchester coach has no yaw damper.

Explorer settings versus the full run (why, and what it changes)
----------------------------------------------------------------
The full RTRI run (``python -m exudyn_wheelrail rtri``) is Newmark (trapezoidal) at 1 ms for the paper's 2.5 s:
1.3–1.6 s of solve on this project's machine (one core, shared) — more than the 1 s an update may take.  The
explorer (:class:`ExplorerSettings`) therefore runs

* **RK44 at 1 ms** instead of Newmark at 1 ms (explicit: one contact call per stage, no Jacobian; RK44's
  stability limit on this model lies between 2 and 2.5 ms, measured), and
* only the **passage window**: until the whole car has left the span plus the assumptions' run-out
  (``(lead_in + L + l_t + e + run_out)/V``: 0.93 s at 250 km/h on 20 m), the window of the full run's
  ``peaks_passage`` — the response to the deviation; what follows (the limit cycle above the critical speed) is
  not computed.

Measured on the RTRI case (20 m, 250 km/h; ``tests/test_explorer.py`` checks the first three within 2 %, 5 % and
15 %): car-body lateral acceleration +0.3 % (1.184 vs 1.180 m/s²), 10 ms-averaged lateral force of wheelset 1 right
+0.4 % (15.77 vs 15.71 kN), raw peak lateral force -3.8 % (19.6 vs 20.4 kN; the raw peak is the ~200 Hz wheelset
bounce on the Hertz spring, not converged in dt with either scheme — :mod:`..scenarios.rtri`).  At the corners
100/250 km/h × 20/40 m and 175 km/h on 30 m (``benchmarks/bench_explorer.py``) the car-body acceleration stays
within 0.3 %, the averaged force within 2.5 % and the raw force within 8.5 %; with a flange impact (δ = 12 mm) +1.0 %,
-4.1 % and -16 %.  Update time (build, warm-up, solve, outputs) on the RTRI case 0.49 s min / 0.52 s median on a
shared 2-CPU machine (other runs of the benchmark: median 0.36–0.52 s, with the machine's other jobs), plus
0.2–0.25 s for the window's redraw; it grows with the simulated time L/V: 0.7–1.0 s at 100 km/h on 20 m, 0.9–1.3 s
on 40 m (3.0 s simulated), where the explorer is hardly faster than the full run.

``ExplorerSettings(contact=ContactSettings(geometry="table"))`` (``explore --geometry table``; the contact geometry
precomputed for the
rigid rail, as the project's ``fast`` preset) halves the update on the RTRI case (0.25 s; +0.2 %, +0.9 %, -2.7 %
against the full run) but moves some raw peaks more (175 km/h on 30 m: -23 %; the flange impact: 10 ms average
-9 %, raw -41 %); it is not the default.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from ..scenarios.rtri import RTRI, RTRI_CASE, RtriCase, RtriResult, run_rtri
from ..simulation.settings import DURATION_AUTO, ContactSettings, RunSettings

__all__ = ["Parameter", "PARAMETERS", "SUSPENSION_KEYS", "ExplorerSettings", "ExplorerUpdate", "RtriExplorer",
           "PEAK_KEYS", "compare_with_full_run"]


@dataclass(frozen=True)
class Parameter:
    """One slider: keyword of :meth:`RtriExplorer.update`, label (with unit), range and default."""

    name: str
    label: str
    lo: float
    hi: float
    default: float


#: the suspension factors and the vehicle-file key each one multiplies
SUSPENSION_KEYS = {
    "primary_kx_factor": "primary.kx_N_per_m",
    "primary_ky_factor": "primary.ky_N_per_m",
    "secondary_ky_factor": "secondary.ky_N_per_m",
    "secondary_cy_factor": "secondary.cy_N_s_per_m",
}

PARAMETERS = (
    Parameter("speed_km_h", "speed [km/h]", 100.0, RTRI.plant_max_speed_km_h, RTRI_CASE.representative_speed_km_h),
    Parameter("span_m", "span L [m]", 10.0, 40.0, 20.0),
    Parameter("deviation_mm", "deviation δ [mm]", 1.0, 20.0, RTRI.deviation_amplitude_m * 1e3),
    Parameter("friction", "friction μ [-]", 0.05, 0.6, RTRI_CASE.friction_coefficient),
    Parameter("primary_kx_factor", "primary k_x × file", 0.25, 4.0, 1.0),
    Parameter("primary_ky_factor", "primary k_y × file", 0.25, 4.0, 1.0),
    Parameter("secondary_ky_factor", "secondary k_y × file", 0.25, 4.0, 1.0),
    Parameter("secondary_cy_factor", "secondary c_y × file", 0.25, 4.0, 1.0),
)
_BY_NAME = {p.name: p for p in PARAMETERS}

#: the peaks an update reports (from the summary's ``peaks_passage``)
PEAK_KEYS = ("max_abs_lateral_contact_force_w1_right_N", "max_abs_lateral_contact_force_w1_right_10ms_avg_N",
             "max_abs_carbody_lateral_acceleration_rear_m_s2", "max_abs_wheelset1_lateral_rel_track_m",
             "flange_contact_w1_right")


@dataclass(frozen=True)
class ExplorerSettings:
    """How an update runs (module docstring): the run settings (solver and time step; the duration follows from
    ``window``), the contact settings (``geometry="table"``, the ``fast`` preset's precomputed geometry, is about 2x
    faster), and the run window ``"passage"`` (until the whole car has left the span plus the run-out) or
    ``"published"`` (the paper's 2.5 s)."""

    run: RunSettings = field(default_factory=lambda: RunSettings(solver="rk44", duration_s=DURATION_AUTO))
    contact: ContactSettings = field(default_factory=ContactSettings)
    window: str = "passage"

    def __post_init__(self):
        if self.window not in ("passage", "published"):
            raise ValueError(f"window={self.window!r}: expected 'passage' or 'published'")

    def describe(self) -> str:
        w = ("run until the whole car has left the span + run-out" if self.window == "passage"
             else f"{RTRI.n_steps_published * RTRI.time_step_s:g} s")
        return (f"explorer: {self.run.solver.upper()} {self.run.dt_s * 1e3:g} ms, {w}, {self.contact.geometry} "
                f"contact geometry, creep law {self.contact.creep_law}")


@dataclass
class ExplorerUpdate:
    """One update: the slider values, the case run, its result, the wall time [s] of the update (build, warm-up,
    solve, outputs) and the passage peaks (:data:`PEAK_KEYS`)."""

    values: dict
    case: RtriCase
    result: RtriResult
    seconds: float
    peaks: dict = field(default_factory=dict)


class RtriExplorer:
    """Programmatic RTRI explorer (module docstring).  ``values`` override the :data:`PARAMETERS` defaults;
    ``warm_up`` runs a 5-step case once so that the first update does not pay for loading the compiled code."""

    def __init__(self, settings: ExplorerSettings | None = None, warm_up: bool = True, **values):
        self.settings = settings or ExplorerSettings()
        self.values = {p.name: p.default for p in PARAMETERS}
        self.values.update(self._checked(values))
        self.history: list[ExplorerUpdate] = []
        if warm_up:
            case = self.case(**self.values)
            run_rtri(case.replace(duration_s=5 * case.run.dt_s))

    @staticmethod
    def _checked(values: dict) -> dict:
        out = {}
        for k, v in values.items():
            if k not in _BY_NAME:
                raise ValueError(f"unknown explorer parameter {k!r}; parameters: {', '.join(_BY_NAME)}")
            p = _BY_NAME[k]
            try:
                v = float(v)
            except (TypeError, ValueError):
                raise ValueError(f"{k} = {v!r}: expected a number") from None
            if not (math.isfinite(v) and p.lo <= v <= p.hi):
                raise ValueError(f"{k} = {v!r}: outside the explorer's range [{p.lo:g}, {p.hi:g}] ({p.label})")
            out[k] = v
        return out

    def case(self, **values) -> RtriCase:
        """The :class:`RtriCase` of the given slider values (missing ones: the current values)."""
        v = {**self.values, **self._checked(values)}
        from ..rolling_stock.vehicle_data import load_vehicle
        vehicle = load_vehicle(RTRI.vehicle)
        base = {"primary": vehicle.primary, "secondary": vehicle.secondary}
        axis = {"kx": 0, "ky": 1, "cy": 1}
        overrides = {}
        for name, key in SUSPENSION_KEYS.items():
            if v[name] != 1.0:
                table, k = key.split(".")
                data = base[table]
                values_file = data.stiffness_N_per_m if k.startswith("k") else data.damping_N_s_per_m
                overrides[key] = float(values_file[axis[k[:2]]] * v[name])
        s = self.settings
        case = RtriCase(span_m=v["span_m"], speed_km_h=v["speed_km_h"], run=s.run, contact=s.contact,
                        deviation_amplitude_m=v["deviation_mm"] * 1e-3, friction=v["friction"],
                        vehicle_overrides=overrides or None)
        duration = (case.passage_time_s() if s.window == "passage"
                    else RTRI.n_steps_published * RTRI.time_step_s)
        return case.replace(duration_s=duration)

    def update(self, **changes) -> ExplorerUpdate:
        """Apply ``changes`` (parameter name -> value), re-run the case and return the update (also appended to
        :attr:`history`).  Raises ``RuntimeError`` when the run fails (the message of the summary's status)."""
        values = {**self.values, **self._checked(changes)}
        t0 = time.perf_counter()
        case = self.case(**values)
        result = run_rtri(case)
        seconds = time.perf_counter() - t0
        if result.summary["status"] != "ok":
            raise RuntimeError(f"RTRI run failed for {values}: {result.summary['status']}")
        self.values = values
        p = result.summary.get("peaks_passage", {})
        u = ExplorerUpdate(values=dict(values), case=case, result=result, seconds=seconds,
                           peaks={k: p.get(k) for k in PEAK_KEYS})
        self.history.append(u)
        return u


def compare_with_full_run(explorer: RtriExplorer | None = None, **values) -> dict:
    """Run the explorer's case and the full run (Newmark 1 ms, ``duration_s="auto"``: at least the published 2.5 s,
    enough for the passage) for the same values; returns ``{"explorer": peaks, "full": peaks, "relative": (explorer
    - full)/full, "explorer_seconds", "full_seconds"}`` over the passage window (:data:`PEAK_KEYS`, numeric ones in
    ``relative``)."""
    ex = explorer or RtriExplorer()
    u = ex.update(**values)
    full_case = u.case.replace(solver="newmark", dt_s=RTRI.time_step_s, duration_s=DURATION_AUTO, geometry="online")
    t0 = time.perf_counter()
    full = run_rtri(full_case)
    full_seconds = time.perf_counter() - t0
    pf = full.summary["peaks_passage"]
    full_peaks = {k: pf.get(k) for k in PEAK_KEYS}
    rel = {k: (u.peaks[k] - full_peaks[k]) / full_peaks[k] for k in PEAK_KEYS
           if isinstance(full_peaks[k], float) and full_peaks[k]}
    return {"values": u.values, "explorer": u.peaks, "full": full_peaks, "relative": rel,
            "explorer_seconds": u.seconds, "full_seconds": full_seconds, "explorer_settings": ex.settings.describe()}
