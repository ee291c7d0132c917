"""The field layout of every array the compiled contact code fills or reads — each index declared here once.

The compiled functions pass plain float arrays; these integer constants name their last axis.  Every reader (the
kernel, the geometry table, the connector, the monitor, the analyses, the outputs) imports them from here.  The
module imports nothing, so any module may import it.

* ``F_`` — kernel output ``out[wheel, slot, F_*]`` (side frame), filled by :mod:`.kernel`;
* ``SLOT_`` — the slot axis of ``out`` and of the connector's results: tread, flange, the tread's second zone;
* ``W_`` — warm-start state ``warm[wheel, region, W_*]`` (region 0 tread, 1 flange) of :mod:`.kernel`;
* ``P_`` — kernel parameters ``params[P_*]`` (:func:`.kernel.default_params`);
* ``G_`` — geometry-table node data ``data[i_y, i_roll, slot, G_*]`` (:mod:`.geometry_table`);
* ``T_`` — geometry-table grid ``par[T_*]`` (:mod:`.geometry_table`);
* ``STAT_`` — evaluation counters ``stats[STAT_*]`` (the table's use and the skips of the connector);
* ``RES_`` — connector results ``results[wheel, slot, RES_*]`` (track/model frame, forces on the wheel;
  :class:`~exudyn_wheelrail.multibody.connector.WheelRailContact`);
* ``CP_`` — creep parameters ``cp[CP_*]`` (:mod:`exudyn_wheelrail.creep.registry`).

Each block ends with ``N_…``, the length of that axis.  Units are SI; "side frame" and "track frame" are those of
:mod:`exudyn_wheelrail.conventions`.
"""

# ---- kernel output per wheel and slot: out[w, slot, F_*] (side frame) --------------------------------------------
F_STATUS = 0          # kernel.STATUS_*
F_S_WHEEL = 1         # wheel surface parameter (arc length of the wheel curve, wheelset frame) [m]
F_S_RAIL = 2          # rail surface parameter [m]
F_PW_Y = 3            # wheel contact point, side frame [m]
F_PW_Z = 4
F_PR_Y = 5            # rail contact point, side frame [m]
F_PR_Z = 6
F_NR_Y = 7            # outward rail normal, side frame
F_NR_Z = 8
F_PENETRATION = 9     # delta [m], positive = interpenetration, negative = gap
F_CONTACT_ANGLE = 10  # gamma [rad], positive leaning towards the track centre
F_ROLLING_RADIUS = 11 # distance of the wheel point from the axle axis [m]
F_KW_LAT = 12         # wheel curvature, lateral (profile) direction [1/m], convex positive
F_KW_ROLL = 13        # wheel curvature, rolling direction [1/m]
F_KR_LAT = 14         # rail curvature, lateral direction [1/m]
F_KR_ROLL = 15        # rail curvature, rolling direction [1/m]
F_A_REL = 16          # Hertz relative curvature A (rolling) [1/m]
F_B_REL = 17          # Hertz relative curvature B (lateral) [1/m]
F_SEMI_A = 18         # ellipse semi-axis along rolling [m]
F_SEMI_B = 19         # ellipse semi-axis lateral [m]
F_NORMAL_FORCE = 20   # N [N]
F_DN_DDELTA = 21      # dN/ddelta [N/m]
F_ITERATIONS = 22     # Newton iterations used
F_HERTZ_STATUS = 23   # 0 ok, nonzero: curvature clamped (conformal), see contact.normal
F_FLAGS = 24          # kernel.FLAG_* bits
N_FIELDS = 25

# ---- output slots per wheel: out[w, slot, :], results[w, slot, :] ------------------------------------------------
SLOT_TREAD = 0        # the tread region's (deepest) contact
SLOT_FLANGE = 1       # the flange region's contact
SLOT_TREAD_2 = 2      # the tread region's second, separate contact zone (two-point contact on the tread)
N_SLOTS = 3

# ---- warm-start state per wheel and region: warm[w, reg, W_*] ----------------------------------------------------
W_S_RAIL = 0          # last rail parameter (NaN: none)
W_S_WHEEL = 1         # last wheel parameter
W_GAP = 2             # region's smallest gap [m] at the reference pose (global over the region), <= 0: unknown
W_POSE_Y = 3          # reference pose at which W_GAP was computed
W_POSE_Z = 4
W_POSE_ROLL = 5
W_ALT_S_RAIL = 6      # the region's other penetration zone (second-deepest local optimum of the last scan)
W_ALT_S_WHEEL = 7
W_SCAN_Y = 8          # c_y at the last global scan of the region
# the curves kept at the warm start (s_wheel, s_rail), as the search last evaluated them there: the next call's
# Newton search starts from them, and a region reported separated by its gap bound is filled from them, without
# evaluating the curves again (curve_eval of the same parameters: the same numbers).  A block of kept curves:
KEPT_S_WHEEL = 0      # the wheel and rail parameters the curves were evaluated at (NaN: none)
KEPT_S_RAIL = 1
KEPT_WHEEL = 2        # curve_eval of the wheel (wheelset frame, 7 values)
KEPT_RAIL = 9         # curve_eval of the rail (7 values)
KEPT_BLOCK = 16
W_CURVES = 9          # the warm start's block
W_ALT_CURVES = W_CURVES + KEPT_BLOCK    # the region's other zone's block (W_ALT_S_*): its Newton search too
N_WARM = W_ALT_CURVES + KEPT_BLOCK

# ---- kernel parameters: params[P_*] ------------------------------------------------------------------------------
P_E_STAR = 0
P_NEWTON_TOL = 1
P_NEWTON_MAX_ITER = 2
P_N_SCAN = 3
P_N_CONCAVE_WHEEL = 4
P_N_CONCAVE_RAIL = 5
P_REFINE = 6
P_GLOBAL = 7
P_RAIL_ROLL_CURVATURE = 8
P_MIN_CURVATURE = 9          # [1/m] Hertz clamp of A and B (conformal contact)
P_DEDUP_DISTANCE = 10
P_CONVEX_MIN_CURVATURE = 11   # [1/m] kappa_w + kappa_r needed to accept the convex search
P_MAX_PENETRATION = 12        # [m] penetration above which FLAG_DEEP_PENETRATION is set
P_WHEEL_LEVER = 13            # [m] largest distance of a wheel curve point from the axle centre
P_CURVATURE_BOUND = 14        # [1/m] bound of |kappa_w| + |kappa_r| (sampling margin of the gap bound)
P_N_STARTS = 15               # Newton starts from the scan's deepest local maxima
P_CONCAVE_NORMAL_WINDOW = 16  # [m] half-width around the concave maximum searched for the deepest normal point
P_RESCAN_DISTANCE = 17        # [m] warm mode: rescan a region in contact after this lateral motion since its last scan
P_BLEND_DEPTH = 18            # [-] blend two maxima of one overlap zone whose depths differ by less than this x depth
N_PARAMS = 19

# ---- geometry-table fields per node and slot: data[i_y, i_roll, slot, G_*] ---------------------------------------
G_STATUS = 0        # kernel status at the reference height
G_S_WHEEL = 1
G_S_RAIL = 2
G_QY = 3            # wheel point in the wheelset frame (curve coordinates) [m]
G_QZ = 4
G_PR_Y = 5          # rail point, side frame [m]
G_PR_Z = 6
G_NR_Y = 7          # outward rail normal, side frame
G_NR_Z = 8
G_DELTA = 9         # penetration at the reference height [m]
G_C2 = 10           # d²δ/dc_z² / 2 [1/m]
G_KW_LAT = 11
G_KW_ROLL = 12
G_KR_LAT = 13
G_KR_ROLL = 14
G_FLAGS = 15        # kernel flags at the reference height (FLAG_BLENDED: slot tread-2 shares the tread's zone)
G_PW_Y = 16         # wheel point at the node's pose, side frame [m]
G_PW_Z = 17
N_G = 18

# ---- geometry-table grid parameters: par[T_*] --------------------------------------------------------------------
T_Y0 = 0            # first lateral node c_y [m]
T_DY = 1            # lateral step [m]
T_NY = 2            # lateral node count
T_R0 = 3            # first roll node [rad]
T_DR = 4            # roll step [rad]
T_NR = 5            # roll node count
N_T = 6

# ---- evaluation counters: stats[STAT_*] (int64, since the start) -------------------------------------------------
STAT_TABLE = 0            # wheel evaluations answered by the table
STAT_FALLBACK = 1         # wheel evaluations outside the table (or geometry "online"), answered by the online kernel
STAT_FLANGE_SKIPPED = 2   # online: flange regions reported apart by the separation bound, without a search
STAT_CONCAVE = 3          # online: regions that needed the concave search (the convex one sufficed elsewhere)
STAT_TREAD_SKIPPED = 4    # online: tread regions reported apart by the separation bound (lift-off)
STAT_ON_DECK = 5          # wheelset evaluations on a bridge deck (coupled to its modes)
STAT_OFF_DECK = 6         # wheelset evaluations off the deck (or without a bridge): no deck coupling computed
N_STATS = 7

# ---- connector results per wheel and slot: results[w, slot, RES_*] (forces on the wheel) -------------------------
RES_STATUS = 0        # kernel status (kernel.STATUS_*): > 0 contact
RES_N = 1             # normal force [N]
RES_FX = 2            # creep forces on the wheel in the contact frame [N]
RES_FY = 3
RES_MZ = 4            # spin moment [N m]
RES_F_TRACK_X = 5     # total contact force on the wheel, track/model frame [N]
RES_F_TRACK_Y = 6
RES_F_TRACK_Z = 7
RES_P_X = 8           # contact point, track/model frame [m]
RES_P_Y = 9
RES_P_Z = 10
RES_GAMMA = 11        # contact angle [rad]
RES_XI = 12           # longitudinal, lateral creepage [-] and spin creepage [1/m]
RES_ETA = 13
RES_PHI = 14
RES_A = 15            # semi-axes [m]
RES_B = 16
RES_DELTA = 17        # penetration [m]
RES_V = 18            # rolling speed [m/s]
RES_CREEP_STATUS = 19  # contact.creepage CREEP_* bits (+ creep.registry.CREEP_AB_CLAMPED: a/b clamped for the law)
RES_FLAGS = 20        # kernel FLAG_* bits
RES_S_TRACK = 21      # track distance of the wheelset [m]
RES_DECK_Y = 22       # deck (bridge) displacement of the rails' centre line at rail top under the wheelset, used for
RES_DECK_Z = 23       # the contact: lateral y, vertical z (down) [m], roll about x [rad] (0 off the deck / no bridge);
RES_DECK_ROLL = 24    # the track irregularity comes on top
RES_ON_DECK = 25      # 1 when the wheelset's track distance lies on the deck, else 0
RES_GROUND_Y = 26     # lateral ground (support) motion y_g [m] and its velocity [m/s] added to the rails (bridge
RES_GROUND_VY = 27    # support motion; 0 without), on and off the deck
N_RES = 28

# ---- creep parameters: cp[CP_*] ----------------------------------------------------------------------------------
CP_MU = 0             # friction coefficient [-]
CP_G = 1              # combined shear modulus [Pa]
CP_NU = 2             # combined Poisson's ratio [-]
CP_NX = 3             # FASTSIM grid (cells along x, strips along y)
CP_NY = 4
CP_V_MIN = 5          # standstill guard of the creepages [m/s]
CP_AB_MIN = 6         # semi-axis ratio range of the law (a/b clamped at equal area outside; flagged)
CP_AB_MAX = 7
N_CP = 8
