"""The choices and defaults of the scenarios' inputs that a front end shows before any work, declared once: the RTRI
case's car-body models (:mod:`.rtri_case`), the bridge crossing's load models, integrator and modal resolution
(:mod:`.bridge_crossing`) and the curving run's transition and lead-in (:mod:`.curving`, a scenario's ``[layout]``).
Those modules import them from here; their meaning is documented there.

This module imports nothing, so that the command line can build its options and ``--help`` without loading the
numerical code.
"""

__all__ = ["CAR_BODY_MODELS", "LOAD_MODELS", "MODEL_NAMES", "AXLE_LOAD_MODELS", "SPRUNG_FREQUENCY_HZ",
           "SPRUNG_DAMPING_RATIO", "DEFAULT_SOLVER", "STEPS_PER_PERIOD", "CONTACT_STEPS_PER_PERIOD", "CONTACT_DT_S", "CHECK_MIN_SPEED_KM_H",
           "CHECK_SPEED_STEP_KM_H", "CHECK_REFINE_KM_H", "CHECK_RESONANCES", "MAX_MODES", "LATERAL_EI_RATIO",
           "LEAD_IN_M", "DEFAULT_RAMP", "DEFAULT_MIN_TRANSITION_M", "default_transition_m"]

# ------------------------------------------------------------------------------------------------- RTRI case
#: the car-body models of the case (``RtriCase.car_body``, ``rtri --car-body``): the vehicle file's rigid car body
#: (``RtriAssumptions.vehicle``) or its flexible variant (``RtriAssumptions.flexible_vehicle``)
CAR_BODY_MODELS = ("rigid", "flexible")

# -------------------------------------------------------------------------------------------- bridge crossing
#: load model name -> ``"module:attribute"`` of its ``LoadModel`` (:mod:`.bridge_crossing`, "Load models"; the
#: moving loads in :mod:`.bridge_crossing_loads`)
LOAD_MODELS = {"moving-loads": "exudyn_wheelrail.scenarios.bridge_crossing_loads:MOVING_LOADS",
               "vehicles": "exudyn_wheelrail.scenarios.bridge_crossing_vehicles:VEHICLES",
               "sprung-masses": "exudyn_wheelrail.scenarios.bridge_crossing_sprung:SPRUNG_MASSES"}
MODEL_NAMES = tuple(LOAD_MODELS)
#: the load models that take the train as axle loads (a consist file's: ``bridge_crossing_loads.consist_axles``)
AXLE_LOAD_MODELS = ("moving-loads", "sprung-masses")
#: the sprung-masses model's suspension frequency [Hz] and damping ratio (assumed; its module docstring)
SPRUNG_FREQUENCY_HZ = 1.5
SPRUNG_DAMPING_RATIO = 0.2
#: the integrator of a crossing (a name of :data:`~exudyn_wheelrail.simulation.settings.SOLVERS`)
DEFAULT_SOLVER = "rk44"
#: time steps per period of the highest mode and of the N-th harmonic of a load's passage (``bridge_crossing``
#: module docstring)
STEPS_PER_PERIOD = 40
#: the vehicles model: time steps per period of the stiffest wheelset's bounce on its Hertz contact, and the largest
#: step (the contact runs' 1 ms) [s] (``bridge_crossing_vehicles.contact_dt_s``, whose docstring derives them)
CONTACT_STEPS_PER_PERIOD = 20
CONTACT_DT_S = 1e-3
#: the EN 1991-2 dynamic check (``en1991_dynamic``): its lowest speed (6.4.6.2(1): 40 m/s) and largest step of
#: the speed grid [km/h], the refinement step around a resonance speed [km/h] and how many resonance speeds
#: f1 d / i (i = 1 ... N) are refined around
CHECK_MIN_SPEED_KM_H = 144.0
CHECK_SPEED_STEP_KM_H = 10.0
CHECK_REFINE_KM_H = 2.5
CHECK_RESONANCES = 4
#: most vertical modes of a crossing
MAX_MODES = 60
#: ``EI_z / EI_y`` of the deck section when no lateral frequency is given
LATERAL_EI_RATIO = 10.0

# ----------------------------------------------------------------------------------------------- curving run
#: straight track ahead of the leading wheelset at t = 0 [m]
LEAD_IN_M = 5.0
#: default transition: the cant ramp 1 : DEFAULT_RAMP (EN 13803's usual limit for the cant gradient), at least
#: DEFAULT_MIN_TRANSITION_M [m]
DEFAULT_RAMP = 400.0
DEFAULT_MIN_TRANSITION_M = 20.0


def default_transition_m(cant_m: float) -> float:
    """The default transition length [m] for a cant ``cant_m`` [m]: the ramp 1 : :data:`DEFAULT_RAMP`, at least
    :data:`DEFAULT_MIN_TRANSITION_M` (the curving run's and a scenario's ``[layout]``)."""
    return max(DEFAULT_MIN_TRANSITION_M, DEFAULT_RAMP * cant_m)
