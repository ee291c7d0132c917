"""The run monitor's stability estimate of an explicit (RK44) step: per wheelset the highest frequency on its
linearised contact stiffness against RK44's imaginary-axis limit (LAPACK's eigenvalue where the compiled screening
value came close), and the fastest decay rate of its creep damping against the real-axis limit (the module
docstring of :mod:`.monitor`, "Invalid states").  :class:`StabilityEstimate` holds these checks for
:class:`~.monitor.RunMonitor`, which provides the records they read (``contact``, ``rk44_dt_s``, the wheelsets'
inertia, the compiled records ``_wss``, ``_G``, ``_par`` and ``_phi_ws``) and ``_stop``."""
from __future__ import annotations

import math

import numpy as np

from ..contact import layout as L
from ..creep.linear import A_OVER_B_MAX, A_OVER_B_MIN, kalker_coefficients
from ..multibody.rotations import rotation_from_vector
from . import monitor_core as MC
from .monitor_records import Status
from .solvers import RK44

__all__ = ["StabilityEstimate", "coupled_damper_rate_1_s", "wheelset_inertia", "STABILITY_SCREEN_MARGIN"]

#: relative margin below RK44's imaginary-axis limit (:data:`~.solvers.RK44`) above which the compiled value of the stability estimate (Jacobi's method,
#: :func:`.monitor_core.largest_eigenvalue_psd`, relative error near 1e-15) is replaced by LAPACK's eigenvalue before
#: anything is decided
STABILITY_SCREEN_MARGIN = 1e-6


def wheelset_inertia(mbs, nodes):
    """Per wheelset node: (mass, inverse square root of the 3x3 body inertia) of the ObjectRigidBody on it, or None
    when there is none."""
    found = {}
    for i in range(mbs.systemData.NumberOfObjects()):
        d = mbs.GetObject(i)
        if d.get("objectType") == "RigidBody" and int(d.get("nodeNumber", -1)) in [int(n) for n in nodes]:
            J = np.asarray(d["inertia"], dtype=float)      # Ixx, Iyy, Izz, Iyz, Ixz, Ixy
            I3 = np.array([[J[0], J[5], J[4]], [J[5], J[1], J[3]], [J[4], J[3], J[2]]])
            ev, U = np.linalg.eigh(I3)
            found[int(d["nodeNumber"])] = (float(d["mass"]), U @ np.diag(1.0 / np.sqrt(ev)) @ U.T)
    return [found.get(int(n)) for n in nodes]


def coupled_damper_rate_1_s(rows_g: np.ndarray, rows_h: np.ndarray, Mh: np.ndarray, W: np.ndarray) -> float:
    """The fastest decay rate [1/s] of dampers between a rigid body and a structure's modes: damper i (coefficient
    c_i) acts along ``g_i`` on the body (6: force direction and its moment) and along ``h_i`` on the structure at the
    same point (its directions in the structure's rows), ``rows_g[i] = √c_i g_i``, ``rows_h[i] = √c_i h_i``;
    ``Mh = M^-1/2`` of the body, ``W = Φ Φᵀ`` the structure's inverse modal mass there (mass-normalised modes Φ).
    The coupled damping ``D = Σ c_i d_i d_iᵀ``, ``d_i = (g_i, -Φᵀ h_i)``, against ``diag(M, 1)`` has the nonzero
    eigenvalues of ``B = A Aᵀ + H W Hᵀ`` (``A = rows_g Mh``, ``H = rows_h``; B is one row per damper): the largest
    is returned (:meth:`RunMonitor.creep_decay_rate_1_s`)."""
    A = rows_g @ Mh
    H = rows_h
    return float(np.linalg.eigvalsh(A @ A.T + H @ W @ H.T)[-1])


class StabilityEstimate:
    """The stability checks of :class:`~.monitor.RunMonitor` against the RK44 step (module docstring)."""

    def creep_decay_rate_1_s(self, k: int, q) -> float:
        """The fastest decay rate σ [1/s] of wheelset k's creep damping at the evaluated state: at small creepage
        every contact acts on the rolling wheelset like two dampers, ``c_x = G a b C11 / V`` along the track's x and
        ``c_y = G a b C22 / V`` across it (Kalker's linear theory, :func:`~exudyn_wheelrail.creep.linear.
        kalker_coefficients` at the patch's a/b; G, ν the connector's), acting at the contact point; σ is the
        largest eigenvalue of ``M^-1/2 D M^-1/2`` with ``D = Σ c g gᵀ``, ``g = (t, r × t)`` (r the lever from the
        axle centre) and the wheelset's mass and inertia M.  It grows as 1/V: an explicit step needs σ h <= 2.785
        (:data:`RK44.real_axis_limit`) or it integrates a limit cycle of the creep forces instead of rolling.  0 without
        a loaded contact or with the creep law ``none``.

        On a structure (a flexible track, a deck) the lateral damper also acts on the rails, whose inverse modal
        mass at the wheelset is ``W = Φ Φᵀ`` (rows y, z, θ; :func:`.monitor_core.rail_mobility`): σ is then the
        largest eigenvalue of ``B = A Aᵀ + H W Hᵀ`` over the dampers (rows ``√c g M^-1/2`` and ``√c h``, h the
        damper's direction on the rails: y and its moment about the rails' centre line; the longitudinal damper
        has none), the same nonzero eigenvalues as the coupled system's ``M^-1/2 D M^-1/2``
        (:func:`coupled_damper_rate_1_s`, used in every case: on the rigid track ``W = 0``, and B has those of the
        wheelset's ``M^-1/2 D M^-1/2``).  A flexible rail's lateral modal mass per wheelset is tens of kilograms
        (62 kg on the shipped ballasted track, modes to 800 Hz) against the wheelset's 1.8 t: the Manchester vehicle
        at 50 km/h has σ = 2.5e4 1/s there, 4.5e3 1/s on the rigid track, and an explicit step beyond it settles
        into a false steady lateral force of nearly μ Q per wheel instead of diverging (docs/track.md, "The creep
        damping on the rails")."""
        c = self.contact
        inertia = self._inertia[k] if self._inertia is not None else None
        if inertia is None or c.creep_law == "none":
            return 0.0
        G_mod, nu = float(c.cp[L.CP_G]), min(max(float(c.cp[L.CP_NU]), 0.0), 0.5)
        res = c.results
        centre = np.asarray(c.p_ref[k], dtype=float) + np.asarray(q[6 * k:6 * k + 3], dtype=float)
        rows_g, rows_h = [], []
        for w in (2 * k, 2 * k + 1):
            for r in res[w]:
                N, a, b, V = r[L.RES_N], r[L.RES_A], r[L.RES_B], abs(r[L.RES_V])
                if not (N > 0.0 and a > 0.0 and b > 0.0 and V > 0.0):
                    continue
                c11, c22, _ = kalker_coefficients(min(max(a / b, A_OVER_B_MIN), A_OVER_B_MAX), nu)
                lever = np.array([r[L.RES_P_X], r[L.RES_P_Y], r[L.RES_P_Z]]) - centre
                for coefficient, t_dir in ((c11, (1.0, 0.0, 0.0)), (c22, (0.0, 1.0, 0.0))):
                    root_c = math.sqrt(G_mod * a * b * coefficient / V)
                    # the damper on the wheelset (direction and moment about the axle centre) and on the rails (y, z,
                    # θ about their centre line, as contact_rows)
                    rows_g.append(root_c * np.concatenate([t_dir, np.cross(lever, t_dir)]))
                    rows_h.append(root_c * np.array((t_dir[1], t_dir[2], t_dir[2] * (r[L.RES_P_Y] - r[L.RES_DECK_Y])
                                                     - t_dir[1] * (r[L.RES_P_Z] - r[L.RES_DECK_Z]))))
        if not rows_g:
            return 0.0
        phi = self._phi_ws[k]                                         # no structure: no columns, W = 0
        return coupled_damper_rate_1_s(np.array(rows_g), np.array(rows_h), self._mass_scaling(k, q), phi @ phi.T)

    def _mass_scaling(self, k: int, q) -> np.ndarray:
        """``M^-1/2`` of wheelset k at its current rotation (6x6, global: ``1/√m`` and ``(R I Rᵀ)^-1/2``) in a
        scratch array, for the eigenvalues of a stiffness or damping matrix against the wheelset's inertia."""
        mass, I_inv_sqrt = self._inertia[k]
        R, Mh = self._R, self._Mh
        rotation_from_vector(q[6 * k + 3], q[6 * k + 4], q[6 * k + 5], R)
        Mh[:3, :3] = np.eye(3) / math.sqrt(mass)
        Mh[3:, 3:] = R @ I_inv_sqrt @ R.T
        return Mh

    def _creep_stability(self, t, q):
        """At the first checked state of an RK44 run: the creep damping's decay rates against the step
        (:meth:`creep_decay_rate_1_s`; the speed is constant, the rates change with the patch size only, as
        N^(2/3)); beyond RK44's real-axis limit a ``step_size`` event stops the run."""
        h = self.rk44_dt_s
        self.creep_rate_1_s = [self.creep_decay_rate_1_s(k, q) for k in range(self.n_wheelsets)]
        k = int(np.argmax(self.creep_rate_1_s))
        sh = self.creep_rate_1_s[k] * h
        if sh > RK44.real_axis_limit and self.stability_exceeded is None:
            st = Status("step_size", t, k, None, f"time step {h:.4g} s beyond the RK44 stability limit of the creep "
                        f"damping (sigma h = {sh:.3g} > {RK44.real_axis_limit:.3f}, sigma = {sh / h:.4g} 1/s, growing as "
                        f"1/V at low speed): use dt_s <= {RK44.real_axis_limit / (sh / h):.3g} s or the implicit solver "
                        "newmark")
            self.stability_exceeded = st
            self._stop(st)

    def _stability_exact(self, t, k, q):
        """The stability estimate of wheelset k with LAPACK's eigenvalue (the compiled screening value came close
        to or above RK44's limit): the highest frequency on its linearised contact stiffness (module docstring)."""
        h = self.rk44_dt_s
        n_rows = int(self._wss[k, MC.WS_ROWS])
        G = self._G[k, :n_rows, :6].copy()
        Mh = self._mass_scaling(k, q)
        A = G @ Mh                                     # K = G^T G: eigenvalues of Mh K Mh = those of A A^T
        B = A @ A.T
        MC.rail_mobility(k, n_rows, self._G, self._phi_ws, B, np.zeros((3, 3)))   # the rails' modal mass (structure)
        lam = float(np.linalg.eigvalsh(B)[-1]) if n_rows > 1 else float(B[0, 0])
        wh = math.sqrt(max(lam, 0.0)) * h
        self._wss[k, MC.WS_MAX_OMEGA_H] = max(float(self._wss[k, MC.WS_MAX_OMEGA_H]), wh)
        if wh > RK44.imaginary_axis_limit and self.stability_exceeded is None:
            st = Status("step_size", t, k, None, f"time step {h:.4g} s beyond the RK44 stability limit of the "
                        f"contact stiffness (omega h = {wh:.3g} > {RK44.imaginary_axis_limit:.3f}, omega = {wh / h:.4g} rad/s: "
                        f"stable below {RK44.imaginary_axis_limit / (wh / h):.3g} s)")
            self.stability_exceeded = st
            self._par[MC.PAR_STAB_SCREEN] = math.inf       # decided once
            self._stop(st)
