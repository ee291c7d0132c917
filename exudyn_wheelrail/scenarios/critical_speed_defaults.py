"""The choices and defaults of the running-stability analysis (the ``critical-speed`` command,
:mod:`.critical_speed`), declared once: the speed range and its limits, the linearisation's settling run and
difference steps, the lateral disturbance and the length of the nonlinear runs, how a limit cycle is measured and
when it counts as persisting.  Their meaning and reasons are given beside each value; the modules that compute
with them import them from here.

This module imports nothing, so that the command line can build its options and ``--help`` without loading the
numerical code.
"""

__all__ = ["SPEED_LIMITS_KM_H", "DEFAULT_SPEED_RANGE_KM_H", "LINEAR_GRID_STEP_KM_H", "BISECTION_TOLERANCE_KM_H",
           "SETTLE_DURATION_S", "SETTLE_SOLVER", "SETTLE_DT_S", "POSITION_STEP_M", "ROTATION_STEP_RAD",
           "VELOCITY_STEP_M_S", "ANGULAR_VELOCITY_STEP_RAD_S", "LATERAL_SHARE_MIN", "RIGID_MODE_MAGNITUDE_1_S",
           "BUMP_DEPTH_M", "BUMP_LENGTH_M", "BUMP_POSITION_M", "RUN_DISTANCE_M", "MIN_RUN_DURATION_S",
           "CYCLE_WINDOW_M", "TREND_WINDOWS", "PERSIST_AMPLITUDE_M", "PERSIST_DAMPING_RATIO", "NONLINEAR_GRID_POINTS",
           "RUN_SOLVER", "RUN_DT_S", "CONICITY_AMPLITUDE_M", "CONICITY_SWEEP_M", "CONICITY_STEP_M",
           "MOVING_BODY_SHARE", "BRANCH_POINTS", "BRANCH_MIN_DEPTH_M", "BRANCH_DEPTH_RATIO", "BRANCH_TOP_HALVINGS",
           "BRANCH_WINDOW_M", "BRANCH_LINGER_RATIO"]

# ------------------------------------------------------------------------------------------------ speed range
#: the speeds the analysis accepts [km/h]: below 10 km/h the creep forces' damping (∝ 1/V) makes every mode
#: overdamped and the runs long; 600 km/h is beyond any conventional vehicle's running speed
SPEED_LIMITS_KM_H = (10.0, 600.0)
#: the default speed range [km/h]
DEFAULT_SPEED_RANGE_KM_H = (50.0, 450.0)
#: largest step of the linear analysis's speed grid [km/h]; the crossing is then bisected to the tolerance
LINEAR_GRID_STEP_KM_H = 25.0
#: the bisection of a critical speed (linear and nonlinear) stops when the bracket is narrower than this [km/h]
BISECTION_TOLERANCE_KM_H = 2.0

# ------------------------------------------------------------------------------------------------ linearisation
#: the centred running state: the vehicle placed in static equilibrium on the rails runs this long on perfect
#: track before it is linearised [s] — the longitudinal creep forces set the wheelsets' spin to the rolling speed of
#: the actual contact radius and the soft longitudinal restraint (0.5 Hz, critically damped) settles
SETTLE_DURATION_S = 1.0
#: the settling run's integrator and step: the generalized-α method damps the stiff wheelset spin mode (the creep
#: damping of the spin, ∝ f11 / V, reaches |λ| ≈ 2200 1/s at 50 km/h, near RK44's limit at 1 ms, where RK44 keeps a
#: spurious oscillation of the spin and leaves the state ~30 rad/s² off equilibrium); any step the settling run takes
#: ends at the same operating point
SETTLE_SOLVER = "generalized_alpha"
SETTLE_DT_S = 1e-3
#: central-difference steps of the linearisation: positions [m], small rotations [rad], velocities [m/s],
#: angular velocities [rad/s].  1 µm and 1 µrad are ~1e-2 of the Hertz penetration's scale and ~1e-4 of the
#: 0.25 mm over which S1002/UIC60 1:40's contact point stays on one tread zone (the derivatives are those of the
#: real geometry at the centre); a velocity step of 1e-5 m/s is a creepage change of ~1e-7 at 100 km/h, deep in
#: the creep law's linear range
POSITION_STEP_M = 1e-6
ROTATION_STEP_RAD = 1e-6
VELOCITY_STEP_M_S = 1e-5
ANGULAR_VELOCITY_STEP_RAD_S = 1e-5
#: a mode is "lateral" (a candidate for hunting) when at least this share of its displacement shape's squared
#: amplitude lies in the lateral, roll and yaw coordinates
LATERAL_SHARE_MIN = 0.5
#: eigenvalues smaller than this in magnitude [1/s] are rigid-body modes (the wheelsets' spin angle): no frequency,
#: no damping ratio, left out of the critical speed
RIGID_MODE_MAGNITUDE_1_S = 1e-3

# ------------------------------------------------------------------------------------------------ nonlinear runs
#: the lateral disturbance: a 1 - cos bump of both rails, this deep [m] and long [m], starting this far ahead of the
#: leading wheelset [m] — a 3 mm alignment defect over 12 m (about one hunting wavelength) is a large but
#: realistic kick that reaches the S1002/UIC60 contact jump and, near the critical speed, the flange
BUMP_DEPTH_M = 0.003
BUMP_LENGTH_M = 12.0
BUMP_POSITION_M = 10.0
#: each constant-speed run covers this distance [m] (about 70 hunting wavelengths: long enough that an oscillation
#: decaying by a few per cent per 100 m shows its trend) ...
RUN_DISTANCE_M = 1500.0
#: ... and lasts at least this long [s]
MIN_RUN_DURATION_S = 4.0
#: the limit-cycle amplitude: half the peak-to-peak lateral displacement of a wheelset relative to its rails over
#: the last window of this length [m] (a steady offset is no oscillation) ...
CYCLE_WINDOW_M = 100.0
#: ... and its trend: the least-squares growth per window of the log of the last this many windows' amplitudes
TREND_WINDOWS = 5
#: a limit cycle persists when a wheelset's amplitude over the last window is at least this large [m] ...
PERSIST_AMPLITUDE_M = 0.2e-3
#: ... and its trend decays no faster than a mode of this damping ratio (per cycle: a slow mode and a fast one
#: alike): ζ ≤ 0.1 % halves an oscillation in more than 110 cycles — a limit cycle at the resolution of the runs;
#: a mode of the linear analysis at ζ = 0.1 % is within a few km/h of its zero crossing (the Manchester vehicle's
#: modes lose about 0.001 of ζ per 3 km/h there), which bounds the bias of the nonlinear critical speed where there
#: is no subcritical cycle
PERSIST_DAMPING_RATIO = 1e-3
#: the conicity reported beside the results: the equivalent conicity at this amplitude (EN 15302's reference) [m],
#: from a contact-geometry sweep over ±CONICITY_SWEEP_M in steps of CONICITY_STEP_M [m]
CONICITY_AMPLITUDE_M = 0.003
CONICITY_SWEEP_M = 0.006
CONICITY_STEP_M = 2e-5
#: a body "moves" in the hunting mode (``hunting_mode_bodies``) when its lateral amplitude is at least this share
#: of the largest
MOVING_BODY_SHARE = 0.2
#: speeds of the nonlinear grid over the range (before the bisection)
NONLINEAR_GRID_POINTS = 9

# ------------------------------------------------------------------------------------------------ unstable branch
#: speeds of the unstable branch: this many, evenly spaced strictly between the nonlinear and the linear critical
#: speed (where a subcritical bifurcation puts an unstable limit cycle between the centred state and the stable one)
BRANCH_POINTS = 4
#: the disturbance's depth is bisected between this [m] (1/64 of the nonlinear runs' 3 mm: a kick that decays at any
#: speed below the linear critical speed unless the unstable cycle is smaller than ~0.03 mm) and BUMP_DEPTH_M ...
BRANCH_MIN_DEPTH_M = BUMP_DEPTH_M / 64.0
#: ... geometrically, until the bracketing depths differ by at most this ratio: the two runs then start within ~3 %
#: (in amplitude) of the unstable cycle's stable manifold and linger near the cycle for ln(1/0.03) ≈ 3.5 e-foldings of
#: its instability before they part
BRANCH_DEPTH_RATIO = 1.07
#: a deepest run without an answer (a step rejected in flange contact) is tried again at half the depth, at most
#: this many times (down to 3/8 mm: still several times the unstable cycles found on S1002/UIC60 1:40)
BRANCH_TOP_HALVINGS = 3
#: the two bracketing runs' amplitudes are compared over windows of this length [m] (about one hunting wavelength:
#: 8–24 m for bogie hunting at 4–6 Hz between 170 and 350 km/h), per wheelset from where it has passed the
#: disturbance ...
BRANCH_WINDOW_M = 20.0
#: ... in the windows where they are still within this factor of each other (both near the unstable cycle)
BRANCH_LINGER_RATIO = 2.0
#: the integrator and step of the nonlinear runs: the ``run`` command's defaults, Newmark's trapezoidal rule (β = 1/4,
#: γ = 1/2: no numerical damping of the hunting motion, A-stable for the wheelsets' stiff spin mode, whose creep
#: damping ∝ 1/V puts RK44 at 1 ms beyond its stability limit below about 50 km/h — there it runs on, bounded by the
#: creep saturation, with a spurious spin oscillation that changes the lateral motion)
RUN_SOLVER = "newmark"
RUN_DT_S = 1e-3
