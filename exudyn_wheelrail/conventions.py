"""Frames, units and sign conventions of exudyn-wheelrail — written down once, tested in ``tests/test_conventions.py``.

Units
-----
SI throughout: metres, radians, newtons, pascals, seconds.  Profile point files in millimetres are converted on
reading.  Names carry the unit where it is not obvious (``a_m``, ``roll_rad``).

Track frame ``track``
---------------------
Right-handed, as in Kalker's CONTACT and most railway codes:

* ``x`` forward (running direction),
* ``y`` lateral, positive to the **right** (looking forward) — a positive lateral shift moves a wheelset towards
  the right rail,
* ``z`` vertical, positive **downwards**; gravity acts along +z.

Origin on the track centre line at the height of the top of the (unworn) rails.

Wheelset frame ``wheelset``
---------------------------
Origin at the axle centre, axes parallel to the track frame at zero pose.  The wheelset *pose* used by the
contact search is ``(y_m, z_m, roll_rad)``: the position of the axle centre in the track frame and the roll angle
about x.  Positive roll (right-hand rule about x) lowers the right wheel.  Yaw is neglected by the search (as
in Montenegro et al. 2015) but carried by the kinematics of later modules.

Side frame ``side`` (right-side convention)
------------------------------------------
Both wheel–rail pairs are solved as *right-side* pairs.  For the right pair the side frame *is* the track frame
(y–z plane).  For the left pair the side frame is the track frame mirrored in y (``y_side = -y_track``); a
wheelset pose ``(y, z, roll)`` becomes ``(-y, z, -roll)`` there.  Hence in the side frame +y always points to
the field side (outwards) and the flange sits on the -y side of its wheel.

Profile frames ``profile``
--------------------------
A profile is a plane curve in its own frame (y positive towards the field side):

* wheel: origin at the tape circle (nominal rolling circle, r0) point, ``z`` = radius increase (positive towards
  the rail).  S1002's flange back lies at y = -70 mm.  Placed in the wheelset side frame at
  ``y = back_to_back/2 - y_flange_back + y_profile`` and ``z = r0 + z_profile``.
* rail: origin at the top of the unrotated rail head on its centre line, ``z`` positive downwards.  Placed in the
  side frame after rotation by the inclination (the head tilts towards the track centre) so that the gauge point —
  the most inward point of the gauge face 14 mm below the top of rail — lies at ``y = gauge/2`` and the top of the
  inclined rail at ``z = 0``.

Curves, normals and curvature
-----------------------------
Every profile curve is parameterised by arc length ``s`` (metres), increasing from the gauge/flange side to the
field side.  At each point it gives the position ``p``, the unit tangent ``t = dp/ds`` and the **outward** unit
normal ``n`` (out of the body's material: downwards/towards the rail for a wheel, upwards for a rail).  The signed
curvature is defined by ``dt/ds = -kappa * n``: **convex = positive** (a rail crown, a wheel tread), concave =
negative (the wheel's tread–flange throat).

Contact
-------
For a wheel point ``p_w`` and a rail point ``p_r`` with outward rail normal ``n_r``: ``d = p_w - p_r``; the
*penetration* is ``delta = -d · n_r`` (positive when the wheel point is inside the rail, i.e. ``d · n_r < 0``).
The contact conditions of the convex search (Montenegro et al. 2015, Eqs. 5–6) are ``t_r · d = 0`` and
``n_r · t_w = 0``.

The **contact angle** ``gamma`` of a contact point is the angle between the rail normal and the vertical, in the
side frame, positive when the normal leans towards the track centre (flange contact has a large positive angle):
``n_r = (-sin gamma, -cos gamma)`` in side-frame (y, z) components.  The **rolling radius** is the distance of the
wheel contact point from the axle axis.

Track irregularities (per rail)
-------------------------------
Four channels as functions of the track distance s (m), each the displacement of the rails from the ideal track:

* **alignment** ``y`` — lateral position of the rails' centre line (mean of both rails), track-frame y (+ right);
* **vertical level** ``z`` — vertical position of the centre line at rail top (mean of both rails), track-frame z
  (+ **down**: a positive level is a dip);
* **cross level** ``c`` — height of the left rail minus height of the right rail, ``c = z_right - z_left``
  (+ = the right rail lower).  It rolls the rail pair about its centre line by ``θ = asin(c / b)`` with the
  rail-centre distance ``b`` = :data:`RAIL_CENTRE_DISTANCE_M` = 1.5 m (standard gauge, as EN 13803 uses for
  cant); positive cross level is a positive roll (right-hand about x, lowers the right rail), like a wheelset's;
* **gauge deviation** ``g`` — lateral distance between the rails minus nominal, ``g = y_right - y_left``
  (+ = **wider**); the right rail moves by ``+g/2`` (to the right), the left rail by ``-g/2`` (to the left).

Per rail: ``y_right = y + g/2``, ``y_left = y - g/2``, ``z_right = z + c/2``, ``z_left = z - c/2`` (the rolled rail pair
puts the rail centres at these heights exactly, laterally to second order in θ).  In each side frame the rail is moved outwards by ``g/2``.

Curves, cant and gradient
-------------------------
The track layout (:mod:`exudyn_wheelrail.track.layout`) is a function of the track distance ``s`` measured along
the centre line.  Its **curvature** ``kappa(s) = dpsi/ds`` (heading ``psi`` about the global vertical, z down:
positive turns the running direction to the right) is **positive for a right-hand curve** (centre of the curve on
the +y side) and negative for a left-hand curve.  The **cant angle** ``phi`` is the roll of the track frame about
its x axis (right-hand rule, as the wheelset roll): positive lowers the right rail.  In a curve the outer rail is
raised, so a canted curve has ``phi`` of the sign of ``kappa``; the cant (superelevation) ``h`` carries the same
sign and ``sin phi = h / RAIL_CENTRE_DISTANCE_M`` (1.5 m, EN 13803).  The **gradient** is the rise per unit horizontal length, positive uphill;
the track frame pitches by ``theta = atan(gradient)`` (nose up).  Global frame: the track frame at ``s = 0``;
track frame = ``R_z(psi) R_y(theta) R_x(phi)`` applied to the global axes.  *Outwards* (away from the centre of
the curve) is ``-sign(kappa) y``.  The unbalanced (cant-deficiency) lateral acceleration in the track plane,
positive outwards, is ``a_nc = V^2 |kappa| cos(phi) - g sin|phi|``.

Creepages
---------
Contact frame (``z_c`` from the wheel into the rail, ``x_c`` the rolling direction, ``y_c = z_c × x_c``, to the right
on both wheels when running forward), the signs of ξ, η, φ, the rolling speed that normalises them, the standstill
guard and the yaw lead of the contact point: :mod:`exudyn_wheelrail.contact.creepage` (``tests/test_creepage.py``).
"""

#: Depth below the top of rail at which the track gauge is measured [m] (EN 13848-1).
GAUGE_MEASURING_DEPTH_M = 0.014

#: Standard gauge [m].
STANDARD_GAUGE_M = 1.435

#: Distance between the rail centres of standard gauge [m] (EN 13803): turns cross level into a roll angle.
RAIL_CENTRE_DISTANCE_M = 1.5

#: Default wheel flange back-to-back distance [m] (UIC 510-2 nominal).
DEFAULT_BACK_TO_BACK_M = 1.360

#: Sign of the curvature of a right-hand / left-hand curve (see "Curves, cant and gradient").
CURVE_DIRECTION_SIGN = {"right": 1.0, "left": -1.0}


def outward_sign(curvature_1_m) -> float:
    """+1/-1: the sign that turns a track-frame y component into 'positive outwards' in a curve of this curvature
    (-sign(kappa); +1 on straight track is arbitrary and never used there)."""
    return -1.0 if curvature_1_m > 0.0 else 1.0


#: Significant digits of a speed in km/h converted from m/s (:func:`speed_km_h`).
KM_H_DIGITS = 12


def speed_km_h(speed_m_s: float) -> float:
    """A speed in km/h from m/s, rounded to :data:`KM_H_DIGITS` significant digits: a speed given as a decimal in
    km/h, held in m/s (``v / 3.6``, one rounding) and converted back, is that decimal again (``240 / 3.6 * 3.6`` is
    ``240.00000000000003``; this gives 240.0), while the conversion's own error (~1e-16 relative) stays far below
    the rounding (1e-12)."""
    v = float(speed_m_s) * 3.6
    return float(f"{v:.{KM_H_DIGITS}g}") if v == v and abs(v) != float("inf") else v


#: Rail inclinations accepted by name (tan of the cant angle).
RAIL_INCLINATIONS = {"1/40": 1.0 / 40.0, "1/20": 1.0 / 20.0, "none": 0.0, "0": 0.0}


def parse_inclination(value) -> float:
    """Rail inclination as the tangent of the cant angle, from '1/40', '1:40', '1/20', 'none' or a number."""
    if isinstance(value, (int, float)):
        return float(value)
    text = str(value).strip().lower().replace(":", "/")
    if text in RAIL_INCLINATIONS:
        return RAIL_INCLINATIONS[text]
    try:
        if "/" in text:
            num, den = text.split("/", 1)
            value = float(num) / float(den)
        else:
            value = float(text)
    except (ValueError, ZeroDivisionError):
        raise ValueError(f"rail inclination {value!r}: expected '1/40', '1:20', 'none' or a number (tan of the "
                         "angle)") from None
    if not 0.0 <= value <= 0.1:
        raise ValueError(f"rail inclination {value!r} (tan) is outside 0 ... 0.1 (1:10); did you mean 1/{value:g}?")
    return value
