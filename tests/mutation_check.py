#!/usr/bin/env python
"""Mutation check of the physics core: do the tests notice deliberate faults?

Run from the repository root (it is a script, not a test module: pytest collects ``test_*.py`` only)::

    python tests/mutation_check.py --list                      # the mutants, checked against the current tree
    python tests/mutation_check.py --workers 2 --json benchmarks/results/mutation_check.json
    python tests/mutation_check.py --only hertz-kappa-x1.02,creepage-spin-sign

What it does
------------
1. Copies the repository (package, tests, pyproject.toml, vehicles/, examples/, docs/, README) into a temporary
   folder, one copy per worker, with a ``shared`` symlink beside each copy (``tests/reference_paths.py`` looks for
   ``../shared/reference``).  ``__pycache__`` folders (bytecode and numba caches) are not copied.
2. Runs the union of the selected mutants' tests once on the unmutated copy; if that fails the check aborts
   (a failing baseline would make every mutant look killed).
3. For every mutant: replaces one exact source snippet (it must occur exactly once in the copy's file) in the
   copy, runs ``python -m pytest -x -q -n 0 -p no:cacheprovider <tests>`` in the copy's folder with ``PYTHONPATH`` set
   to the copy, then restores the file.  A small plugin (``-p``) checks in the subprocess that
   ``exudyn_wheelrail.__file__`` lies inside the copy (a usage error, exit code 4, otherwise).

   Every run gets its own empty ``NUMBA_CACHE_DIR`` and writes no bytecode: numba's ``cache=True`` index is keyed
   by the source file's modification time and size, and a cached caller embeds its callee's compiled code, so a
   cache reused across runs could hide a mutation (or a restored file could pick up a mutant's cache).  The price
   is a cold compile per run (``--cache-cost`` measures it: each selected mutant's tests unmutated, cold then warm).

Outcome per mutant: KILLED (pytest exit code 1: a test failed), SURVIVED (exit code 0), or ERROR (anything else:
collection or usage error, timeout, snippet not found) -- reported separately, not counted as a kill.  The kill
rate is killed / (killed + survived).
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import dataclasses
import datetime as _dt
import json
import os
import platform
import queue
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
#: what the tests read besides the package: copied into every copy (missing entries are skipped)
COPY_ITEMS = ("exudyn_wheelrail", "tests", "pyproject.toml", "vehicles", "examples", "docs", "README.md",
              "constraints.txt")
IGNORE = shutil.ignore_patterns("__pycache__", "*.pyc", "*.nbi", "*.nbc", ".hypothesis", ".pytest_cache")
DEFAULT_TIMEOUT_S = 1200.0


@dataclasses.dataclass(frozen=True)
class Mutant:
    id: str
    file: str                 # relative to the repository root
    find: str                 # exact snippet, must occur exactly once
    replace: str
    description: str
    tests: tuple              # pytest node ids / files, relative to the repository root
    k: str | None = None      # optional pytest -k expression

    def pytest_args(self) -> list[str]:
        args = list(self.tests)
        if self.k:
            args += ["-k", self.k]
        return args


def _m(id, file, find, replace, description, tests, k=None):
    return Mutant(id, file, find, replace, description, tuple(tests), k)


P = "exudyn_wheelrail/"
T = "tests/"

# ------------------------------------------------------------------------------------------------------------------
# The mutants.  Kinds: sign flip, constant off by 1-2 %, swapped arguments, dropped term, off-by-one.
# Test sets: the unit-test files of the mutated module first (pytest -x stops at the first failure, so a killed
# mutant costs little), then the files that exercise it through the rest of the chain (kernel -> connector ->
# RTRI regression).  Measured (2 cores shared, load ~1-2): about 30 min for all mutants with 1 worker, baseline
# included; every run compiles its numba functions cold (the connector's about 1.5 min of it).
# ------------------------------------------------------------------------------------------------------------------
MUTANTS = [
    # ---- profiles: curves, standard definitions, readers --------------------------------------------------------
    _m("curve-curvature-basis-typo", P + "profiles/curve.py",
       "e5 = 0.5 * (6.0 * u - 24.0 * u2 + 20.0 * u3)",
       "e5 = 0.5 * (6.0 * u - 24.0 * u2 + 20.0 * u2)",
       "quintic Hermite: second derivative of the h5 basis with u2 for u3 (curvature wrong between nodes)",
       [T + "test_curve.py", T + "test_standard_profiles.py"]),
    _m("curve-rotation-sense", P + "profiles/curve.py",
       "rot = np.array([[c, -sn], [sn, c]])",
       "rot = np.array([[c, sn], [-sn, c]])",
       "ProfileCurve.transformed rotates the wrong way (rail cant applied away from the track centre)",
       [T + "test_curve.py", T + "test_standard_profiles.py", T + "test_contact_search.py"]),
    _m("s1002-flange-back-datum", P + "profiles/standard.py",
       "S1002_FLANGE_BACK_Y_M = -0.070 ",
       "S1002_FLANGE_BACK_Y_M = -0.0707 ",
       "S1002 flange-back datum 1 % off (-70.7 mm): wheel placed 0.7 mm off laterally in the pair",
       [T + "test_standard_profiles.py", T + "test_contact_search.py", T + "test_kernel_hertz_assembly.py",
        T + "test_geometry_sweep.py", T + "test_conicity.py"]),
    _m("uic60-crown-radius-2pc", P + "profiles/standard.py",
       "UIC60_HEAD_RADII_M = (0.300, 0.080, 0.013)",
       "UIC60_HEAD_RADII_M = (0.306, 0.080, 0.013)",
       "60E1 crown radius R300 -> R306 (2 %): geometry stays tangent-continuous",
       [T + "test_standard_profiles.py", T + "test_contact_search.py", T + "test_geometry_sweep.py",
        T + "test_conicity.py"]),
    _m("simpack-rotate-sign", P + "profiles/simpack.py",
       "p = np.column_stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]])",
       "p = np.column_stack([c * p[:, 0] + s * p[:, 1], -s * p[:, 0] + c * p[:, 1]])",
       "SIMPACK reader: 'rotate' applied in the opposite sense",
       [T + "test_profile_readers.py"]),
    _m("simpack-shift-sign", P + "profiles/simpack.py",
       "p = p + [shift_y, shift_z]",
       "p = p - [shift_y, shift_z]",
       "SIMPACK reader: 'shift.y/shift.z' subtracted instead of added",
       [T + "test_profile_readers.py"]),
    # ---- contact search: convex Newton, concave search, kernel -------------------------------------------------
    _m("newton-residual-sign", P + "contact/search.py",
       "f1 = rty * dy + rtz * dz",
       "f1 = rty * dy - rtz * dz",
       "convex Newton: sign slip in the first contact condition t_r . (p_w - p_r) = 0",
       [T + "test_contact_search.py", T + "test_kernel_hertz_assembly.py", T + "test_geometry_sweep.py",
        T + "test_skips.py", T + "test_geometry_table.py", T + "stress/test_stress_kernel_fuzz.py"]),
    _m("newton-jacobian-sign", P + "contact/search.py",
       "j21 = rk * tt",
       "j21 = -rk * tt",
       "convex Newton: sign of the rail-curvature term of the Jacobian (dn_r/ds = kappa t_r) flipped",
       [T + "test_contact_search.py", T + "test_kernel_hertz_assembly.py", T + "test_geometry_sweep.py",
        T + "test_skips.py", T + "test_geometry_table.py", T + "stress/test_stress_kernel_fuzz.py"]),
    _m("concave-refine-mismatch-sign", P + "contact/search.py",
       "return wtz * rty - rtz * wty",
       "return wtz * rty + rtz * wty",
       "concave search: slope mismatch of the refinement with a wrong sign (maximum located at the wrong place)",
       [T + "test_contact_search.py", T + "test_quasi_static.py::test_centred_wheelset_is_symmetric",
        T + "test_geometry_sweep.py", T + "test_skips.py", T + "test_geometry_table.py",
        T + "stress/test_stress_kernel_fuzz.py"]),
    _m("concave-sampling-off-by-one", P + "contact/search.py",
       "h_w = (s_w_hi - s_w_lo) / (n_wheel - 1)\n    y_min = 1e30",
       "h_w = (s_w_hi - s_w_lo) / n_wheel\n    y_min = 1e30",
       "concave search: wheel sample spacing /n instead of /(n-1) (the last sample misses the region's end)",
       [T + "test_flange_root_contact.py", T + "test_contact_search.py", T + "test_geometry_sweep.py",
        T + "test_skips.py", T + "test_geometry_table.py", T + "stress/test_stress_kernel_fuzz.py"]),
    _m("kernel-penetration-vertical", P + "contact/kernel.py",
       "delta = -((wy - ry) * rny + (wz - rz) * rnz)\n    r_roll = qz",
       "delta = -((wz - rz) * rnz)\n    r_roll = qz",
       "kernel: penetration without the lateral term of the normal distance (dropped term)",
       [T + "test_contact_search.py", T + "test_kernel_hertz_assembly.py", T + "test_geometry_sweep.py",
        T + "test_skips.py", T + "test_geometry_table.py", T + "stress/test_stress_kernel_fuzz.py"]),
    _m("kernel-meusnier-dropped", P + "contact/kernel.py",
       "k_w_roll = qnz / r_roll ",
       "k_w_roll = 1.0 / r_roll ",
       "kernel: wheel rolling curvature 1/r instead of Meusnier's cos(psi)/r (dropped factor)",
       [T + "test_kernel_hertz_assembly.py", T + "test_contact_search.py", T + "test_geometry_sweep.py",
        T + "test_skips.py", T + "test_geometry_table.py", T + "stress/test_stress_kernel_fuzz.py"]),
    _m("kernel-contact-angle-sign", P + "contact/kernel.py",
       "o[F_CONTACT_ANGLE] = np.arctan2(-rny, -rnz)",
       "o[F_CONTACT_ANGLE] = np.arctan2(rny, -rnz)",
       "kernel: contact angle with the wrong sign",
       [T + "test_contact_search.py", T + "test_kernel_hertz_assembly.py", T + "test_geometry_sweep.py",
        T + "test_skips.py", T + "test_geometry_table.py", T + "stress/test_stress_kernel_fuzz.py"]),
    _m("scan-cache-spacing", P + "contact/search.py",
       "    h = (s_w_hi - s_w_lo) / (n_wheel - 1)\n    pts = np.empty((n_wheel, 2))",
       "    h = (s_w_hi - s_w_lo) / n_wheel\n    pts = np.empty((n_wheel, 2))",
       "the scan's cached wheel points at the wrong arc lengths (spacing / n instead of / (n - 1))",
       [T + "test_scan_overlap.py", T + "test_contact_search.py"]),
    _m("wheelset-left-roll-not-mirrored", P + "contact/wheelset.py",
       "sp[1::2, 2] = -poses[:, 2]",
       "sp[1::2, 2] = poses[:, 2]",
       "WheelsetContact: the left wheel's side-frame roll not mirrored",
       [T + "test_contact_search.py", T + "test_quasi_static.py", T + "test_geometry_sweep.py", T + "test_skips.py",
        T + "test_geometry_table.py", T + "stress/test_stress_kernel_fuzz.py"]),
    # ---- Hertz ---------------------------------------------------------------------------------------------------
    _m("hertz-kappa-x1.02", P + "contact/normal.py",
       "return m, n, (4.0 / 3.0) * q * q * q, q, sat",
       "return m, n, 1.02 * (4.0 / 3.0) * q * q * q, q, sat",
       "Hertz kappa x 1.02 (stiffness Kh 2 % high)",
       [T + "test_hertz.py", T + "test_kernel_hertz_assembly.py", T + "test_rtri_regression.py",
        T + "test_geometry_sweep.py", T + "test_vehicle_builder.py"]),
    _m("hertz-m-n-orientation", P + "contact/normal.py",
       "m, n, kappa, q, sat = _table_eval(math.log(A / B))\n    return n, m, kappa, q, sat",
       "m, n, kappa, q, sat = _table_eval(math.log(A / B))\n    return m, n, kappa, q, sat",
       "Hertz: for A > B the long semi-axis is not turned to y (m and n swapped)",
       [T + "test_hertz.py", T + "test_kernel_hertz_assembly.py", T + "test_geometry_sweep.py",
        T + "test_vehicle_builder.py"]),
    _m("hertz-relative-curvature-half", P + "contact/kernel.py",
       "A = 0.5 * (k_w_roll + k_r_roll)",
       "A = k_w_roll + k_r_roll",
       "kernel: relative curvature A without the factor 1/2",
       [T + "test_kernel_hertz_assembly.py", T + "test_hertz.py", T + "test_geometry_sweep.py",
        T + "test_vehicle_builder.py"]),
    _m("hertz-semi-axes-constant", P + "contact/normal.py",
       "c0 = np.cbrt(0.75 * N / (E_star * S))",
       "c0 = np.cbrt(0.765 * N / (E_star * S))",
       "Hertz from force: c0 = (3N/(4E*(A+B)))^(1/3) with 0.765 for 3/4 (2 %; semi-axes 0.7 % large)",
       [T + "test_hertz.py", T + "test_geometry_sweep.py", T + "test_vehicle_builder.py"]),
    _m("hertz-tangent-stiffness", P + "contact/normal.py",
       "return k_eff * delta, 1.5 * k_eff, mx * c0, my * c0, status | sat",
       "return k_eff * delta, k_eff, mx * c0, my * c0, status | sat",
       "Hertz: dN/ddelta without the factor 3/2",
       [T + "test_hertz.py", T + "test_kernel_hertz_assembly.py", T + "test_geometry_sweep.py",
        T + "test_vehicle_builder.py"]),
    # ---- creepages -----------------------------------------------------------------------------------------------
    _m("creepage-spin-sign", P + "contact/creepage.py",
       "return xi, eta, phi, v_roll, status",
       "return xi, eta, -phi, v_roll, status",
       "spin creepage phi with the wrong sign",
       [T + "test_creepage.py", T + "test_rtri_regression.py", T + "test_quasi_static.py"]),
    _m("creepage-lateral-axis-swapped", P + "contact/creepage.py",
       "yx, yy, yz = _cross(zx, zy, zz, xx, xy, xz)",
       "yx, yy, yz = _cross(xx, xy, xz, zx, zy, zz)",
       "contact frame: y_c = x_c x z_c (arguments swapped: left-handed frame, eta flipped)",
       [T + "test_creepage.py", T + "test_quasi_static.py"]),
    _m("creepage-rolling-speed-spin", P + "contact/creepage.py",
       "fx, fy, fz = _cross(wx - spin * ax, wy - spin * ay, wz - spin * az, rx, ry, rz)",
       "fx, fy, fz = _cross(wx, wy, wz, rx, ry, rz)",
       "rolling speed: the wheel's spin not removed from the contact-point velocity (V halved, creepages doubled)",
       [T + "test_creepage.py", T + "test_quasi_static.py"]),
    _m("creepage-rolling-radius-roll", P + "contact/creepage.py",
       "rho = -sr * dy + cr * dz",
       "rho = cr * dz",
       "yawed contact point: rolling radius rho without the roll term (dropped term)",
       [T + "test_creepage.py", T + "test_rtri_regression.py", T + "test_quasi_static.py"]),
    # ---- creep laws ----------------------------------------------------------------------------------------------
    _m("exact-influence-xx-yy-swapped", P + "creep/kalker_exact.py",
       "axx = f * ((1.0 - poisson) * i1 + poisson * ixx)\n                    ayy",
       "axx = f * ((1.0 - poisson) * i1 + poisson * iyy)\n                    ayy",
       "exact theory: Cerruti influence u_x uses the y^2/r^3 integral instead of x^2/r^3 (swapped)",
       [T + "test_kalker_exact.py"]),
    _m("exact-pressure-parabolic", P + "creep/kalker_exact.py",
       "shape = np.sqrt(np.maximum(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0))",
       "shape = np.maximum(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0)",
       "exact theory: parabolic instead of Hertz's ellipsoidal pressure as the traction bound",
       [T + "test_kalker_exact.py"]),
    _m("fastsim-L3-ratio-swapped", P + "creep/fastsim.py",
       "L3 = math.pi * a * math.sqrt(a / b) / (4.0 * C23 * shear_modulus)",
       "L3 = math.pi * a * math.sqrt(b / a) / (4.0 * C23 * shear_modulus)",
       "FASTSIM: spin flexibility L3 with sqrt(b/a) for sqrt(a/b)",
       [T + "test_fastsim.py"]),
    _m("fastsim-element-centre-off-by-one", P + "creep/fastsim.py",
       "x = ay - (i + 0.5) * dx ",
       "x = ay - (i + 1.0) * dx ",
       "FASTSIM: tractions at the element's trailing end instead of its centre (off by one half element)",
       [T + "test_fastsim.py"]),
    _m("she-cubic-coefficient", P + "creep/laws.py",
       "eps = 1.0 - beta / 3.0 + beta * beta / 27.0",
       "eps = 1.0 - beta / 3.0 + beta * beta / 9.0",
       "Shen-Hedrick-Elkins: beta^2/9 for beta^2/27 in the saturation factor",
       [T + "test_creep_laws.py"]),
    _m("polach-spin-creepage-b", P + "creep/laws.py",
       "s_yc = eta + phi * a",
       "s_yc = eta + phi * b",
       "Polach: effective lateral creepage eta + phi b instead of eta + phi a",
       [T + "test_creep_laws.py"]),
    _m("polach-km-ratio-swapped", P + "creep/laws.py",
       "k_m = 1.0 + 6.3 * (1.0 - math.exp(-a / b))",
       "k_m = 1.0 + 6.3 * (1.0 - math.exp(-b / a))",
       "Polach: spin factor k_M with exp(-b/a) for exp(-a/b)",
       [T + "test_creep_laws.py"]),
    _m("linear-c33-exponent-sign", P + "creep/linear.py",
       "c33 = 32.0 / (15.0 * math.pi) * c23 * (a / b) ** -1.5",
       "c33 = 32.0 / (15.0 * math.pi) * c23 * (a / b) ** 1.5",
       "linear theory: C33* with (a/b)^1.5 for (a/b)^-1.5",
       [T + "test_creep_linear.py", T + "test_creep_laws.py"]),
    _m("linear-nu-lagrange-weight", P + "creep/linear.py",
       "l2 = nu * (nu - 0.25) / 0.125",
       "l2 = nu * (nu - 0.25) / 0.25",
       "Kalker coefficients: quadratic Lagrange weight of the nu = 0.5 column with a wrong denominator",
       [T + "test_creep_linear.py"]),
    # ---- creep table ---------------------------------------------------------------------------------------------
    _m("table-hermite-slope-weights-swapped", P + "creep/table.py",
       "        al = h / (x2 - x0)\n        be = (x1 - x0) / (x2 - x0)\n",
       "        al = (x1 - x0) / (x2 - x0)\n        be = h / (x2 - x0)\n",
       "creep table: cubic-Hermite slope weights al/be swapped at the interval's lower end (exact at nodes, "
       "wrong slopes on a non-uniform axis)",
       [T + "test_creep_table.py", T + "test_creep_table_interpolation.py", T + "test_rtri_regression.py",
        T + "test_quasi_static.py", T + "test_connector.py"]),
    _m("table-hermite-slope-weights-swapped-hi", P + "creep/table.py",
       "        al = (x3 - x2) / (x3 - x1)\n        be = h / (x3 - x1)\n",
       "        al = h / (x3 - x1)\n        be = (x3 - x2) / (x3 - x1)\n",
       "creep table: cubic-Hermite slope weights al/be swapped at the interval's upper end",
       [T + "test_creep_table.py", T + "test_creep_table_interpolation.py", T + "test_rtri_regression.py",
        T + "test_quasi_static.py", T + "test_connector.py"]),
    _m("table-spin-normalisation-swapped", P + "creep/table.py",
       "return f * C11, f * C22, f * math.sqrt((C11 * b) ** 2 + (C22 * a) ** 2)",
       "return f * C11, f * C22, f * math.sqrt((C11 * a) ** 2 + (C22 * b) ** 2)",
       "creep table: spin normalisation with a and b swapped",
       [T + "test_creep_table.py", T + "test_creep_table_interpolation.py", T + "test_rtri_regression.py",
        T + "test_quasi_static.py", T + "test_connector.py"]),
    _m("table-symmetry-spin-not-mirrored", P + "creep/table.py",
       "        vy = -vy\n        vp = -vp\n",
       "        vy = -vy\n",
       "creep table lookup: the symmetry (xi, -eta, -phi) applied without mirroring the spin",
       [T + "test_creep_table.py", T + "test_creep_table_interpolation.py", T + "test_quasi_static.py",
        T + "test_connector.py"]),
    _m("table-r-secant-off-by-one", P + "creep/table.py",
       "wr = _weights(r_nodes, ir, r, True, ir + 2 < nr, order)",
       "wr = _weights(r_nodes, ir, r, True, ir + 3 < nr, order)",
       "creep table: radial secant slope one interval too early (off-by-one at the r_max end)",
       [T + "test_creep_table.py", T + "test_creep_table_interpolation.py", T + "test_rtri_regression.py",
        T + "test_quasi_static.py", T + "test_connector.py"]),
    _m("coulomb-guard-1.02", P + "creep/registry.py",
       "bound = cp[CP_MU] * N\n",
       "bound = 1.02 * cp[CP_MU] * N\n",
       "connector: the Coulomb guard holds the creep force at 1.02 muN instead of muN",
       [T + "test_connector.py::test_connector_creep_forces_never_exceed_coulomb",
        T + "test_connector.py::test_creep_law_dispatch_matches_the_creep_modules", T + "test_rtri_regression.py"]),
    # ---- connector: force/torque assembly --------------------------------------------------------------------------
    _m("connector-spin-moment-dropped", P + "multibody/connector_core.py",
       "tx += dy * Fgz - dz * Fgy + Mz * frame[2, 0]\n"
       "                ty += dz * Fgx - dx * Fgz + Mz * frame[2, 1]\n"
       "                tz += dx * Fgy - dy * Fgx + Mz * frame[2, 2]",
       "tx += dy * Fgz - dz * Fgy\n"
       "                ty += dz * Fgx - dx * Fgz\n"
       "                tz += dx * Fgy - dy * Fgx",
       "connector: the spin moment Mz z_c dropped from the wheelset torque",
       [T + "test_connector.py", T + "test_connector_torque_balance.py", T + "test_rtri_regression.py",
        T + "test_vehicle_builder.py", T + "test_bridge_coupling.py", T + "test_rtri.py"]),
    _m("connector-torque-not-transposed", P + "multibody/connector_core.py",
       "f_out[o + 3] = R[0, 0] * tx + R[1, 0] * ty + R[2, 0] * tz\n"
       "        f_out[o + 4] = R[0, 1] * tx + R[1, 1] * ty + R[2, 1] * tz\n"
       "        f_out[o + 5] = R[0, 2] * tx + R[1, 2] * ty + R[2, 2] * tz",
       "f_out[o + 3] = R[0, 0] * tx + R[0, 1] * ty + R[0, 2] * tz\n"
       "        f_out[o + 4] = R[1, 0] * tx + R[1, 1] * ty + R[1, 2] * tz\n"
       "        f_out[o + 5] = R[2, 0] * tx + R[2, 1] * ty + R[2, 2] * tz",
       "connector: torque to the body frame with R instead of R^T (frame rotation)",
       [T + "test_connector.py", T + "test_connector_torque_balance.py", T + "test_vehicle_builder.py",
        T + "test_bridge_coupling.py", T + "test_rtri.py"]),
    _m("connector-lever-arm-cross-order", P + "multibody/connector_core.py",
       "ty += dz * Fgx - dx * Fgz",
       "ty += dx * Fgz - dz * Fgx",
       "connector: moment about the axle (y) with the lever-arm cross product reversed",
       [T + "test_connector.py", T + "test_connector_torque_balance.py", T + "test_rtri_regression.py",
        T + "test_vehicle_builder.py", T + "test_bridge_coupling.py", T + "test_rtri.py"]),
    _m("connector-left-normal-not-mirrored", P + "multibody/connector_core.py",
       "ow[F_PW_Z], mirror * ow[F_NR_Y]",
       "ow[F_PW_Z], ow[F_NR_Y]",
       "connector: the left wheel's rail normal not mirrored to the track frame",
       [T + "test_connector.py", T + "test_connector_torque_balance.py", T + "test_vehicle_builder.py",
        T + "test_bridge_coupling.py", T + "test_rtri.py"]),
    _m("track-residual-force-sign", P + "structures/deck_kinematics.py",
       "res[i] += gv[i] * N",
       "res[i] -= gv[i] * N",
       "flexible track: the rails' residual displacement towards the wheel instead of away from it (the static "
       "correction stiffens the contact)",
       [T + "test_track_static_correction.py"]),
    _m("connector-yaw-sign", P + "multibody/connector_core.py",
       "yaw = math.atan2(-ex, ey)",
       "yaw = math.atan2(ex, ey)",
       "connector: wheelset yaw from the axle direction with the wrong sign (yaw lead of the contact reversed)",
       [T + "test_connector.py", T + "test_connector_torque_balance.py", T + "test_rtri_regression.py",
        T + "test_vehicle_builder.py", T + "test_bridge_coupling.py", T + "test_rtri.py"]),
    _m("connector-kalker-ab-inverted", P + "creep/registry.py",
       "C11, C22, C23 = _linear.kalker_coefficients_core(math.log(ab), cp[CP_NU], t_nodes, coef, 0)",
       "C11, C22, C23 = _linear.kalker_coefficients_core(math.log(1.0 / ab), cp[CP_NU], t_nodes, coef, 0)",
       "connector: Kalker's coefficients looked up at b/a instead of a/b",
       [T + "test_connector.py", T + "test_connector_torque_balance.py", T + "test_vehicle_builder.py",
        T + "test_bridge_coupling.py", T + "test_rtri.py"]),
    # ---- track ---------------------------------------------------------------------------------------------------
    _m("track-transition-2pc-longer", P + "track/rigid.py",
       "h = 0.5 * transition\n",
       "h = 0.51 * transition\n",
       "track: span-end transitions 2 % longer than stated",
       [T + "test_track.py", T + "test_rtri_regression.py"]),
    _m("track-far-end-slope-sign", P + "track/rigid.py",
       "return v, -d1, d2\n",
       "return v, d1, d2\n",
       "track: the far-end transition's slope not mirrored (sign)",
       [T + "test_track.py", T + "test_rtri_regression.py"]),
    _m("track-transition-curvature-term", P + "track/rigid.py",
       "value = f * h5 + lt * f1 * h4 + lt * lt * f2 * h3\n",
       "value = f * h5 + lt * f1 * h4\n",
       "track: transition value without the curvature term (dropped term)",
       [T + "test_track.py", T + "test_rtri_regression.py"]),
    # ---- bridge --------------------------------------------------------------------------------------------------
    _m("bridge-torsion-lever-sign", P + "structures/modal_shapes.py",
       "out[0, k] = v + ez * th\n",
       "out[0, k] = v - ez * th\n",
       "bridge projection: rail lateral displacement v - e_z theta_x (sign of the torsion lever)",
       [T + "test_bridge.py", T + "test_bridge_moving_force_reference.py", T + "test_bridge_coupling.py",
        T + "test_bridge_support_motion.py"]),
    _m("bridge-hermite-n4-sign", P + "structures/modal_shapes.py",
       "N4 = Le * (xi3 - xi2)",
       "N4 = Le * (xi2 - xi3)",
       "bridge projection: Hermite shape function N4 with the wrong sign",
       [T + "test_bridge.py", T + "test_bridge_moving_force_reference.py", T + "test_bridge_support_motion.py"]),
    _m("bridge-modal-damping-factor", P + "structures/modal_basis.py",
       "return np.diag(2.0 * self.damping_ratio * self.omega_rad_s)",
       "return np.diag(self.damping_ratio * self.omega_rad_s)",
       "bridge: modal damping zeta*omega instead of 2*zeta*omega",
       [T + "test_bridge.py", T + "test_bridge_moving_force_reference.py"]),
    _m("fryba-modal-force-factor", P + "structures/fryba.py",
       "A = 2.0 * P / (m * L)",
       "A = P / (m * L)",
       "Fryba moving-force solution: modal force without the factor 2 (2P/(mL))",
       [T + "test_bridge.py", T + "test_bridge_moving_force_reference.py"]),
    _m("fryba-free-vibration-undamped", P + "structures/fryba.py",
       "ez = np.exp(-z * wj * tf)",
       "ez = np.ones_like(tf)",
       "Fryba moving-force solution: post-exit free vibration without its damping",
       [T + "test_bridge.py", T + "test_bridge_moving_force_reference.py"]),
    # ---- recording ---------------------------------------------------------------------------------------------
    _m("recorder-sensor-accelerometer-not-transposed", P + "simulation/recorder.py",
       "rows[:, 6 * i + 2] = R[:, 0, 1] * v[:, 0] + R[:, 1, 1] * v[:, 1] + R[:, 2, 1] * v[:, 2]",
       "rows[:, 6 * i + 2] = R[:, 1, 0] * v[:, 0] + R[:, 1, 1] * v[:, 1] + R[:, 1, 2] * v[:, 2]",
       "car-body accelerometer from the stored sensors: R (a - g) instead of R^T (a - g) (lateral reading)",
       [T + "test_step_overhead.py"]),
    # ---- criteria ------------------------------------------------------------------------------------------------
    _m("yq-right-wheel-sign", P + "analysis/safety.py",
       "    if side == \"right\":\n        return -f\n",
       "    if side == \"right\":\n        return f\n",
       "Y of the right wheel with the wrong sign (Y = +F_y instead of -F_y)",
       [T + "test_safety_comfort.py", T + "test_scenarios.py", T + "test_plots.py"]),
    _m("nadal-denominator-sign", P + "analysis/safety.py",
       "return (t - mu) / (1.0 + mu * t)",
       "return (t - mu) / (1.0 - mu * t)",
       "Nadal's limit with (1 - mu tan gamma) in the denominator",
       [T + "test_safety_comfort.py", T + "test_scenarios.py", T + "test_plots.py"]),
    _m("sliding-window-off-by-one", P + "analysis/comfort.py",
       "return max(1, int(round(L / (V * dt))))",
       "return max(1, int(round(L / (V * dt))) + 1)",
       "2 m sliding mean: window one sample too long",
       [T + "test_safety_comfort.py", T + "test_scenarios.py", T + "test_plots.py"]),
    _m("prudhomme-axle-load", P + "analysis/safety.py",
       "return a * (10.0e3 + 2.0 * q0 / 3.0)",
       "return a * (10.0e3 + q0 / 3.0)",
       "Prud'homme: 10 kN + Q0/3 (wheel load read as axle load)",
       [T + "test_safety_comfort.py", T + "test_scenarios.py", T + "test_plots.py"]),
    _m("sperling-one-sided-factor", P + "analysis/comfort.py",
       "amp = 2.0 * np.abs(spec) / n",
       "amp = np.abs(spec) / n",
       "Sperling: one-sided amplitude spectrum without the factor 2",
       [T + "test_safety_comfort.py", T + "test_scenarios.py", T + "test_plots.py"]),
    _m("en14363-filter-single-pass", P + "analysis/filters.py",
       "    y = _cascade(sos, np.ascontiguousarray(y[::-1]), zi * y[-1])[::-1]\n",
       "\n",
       "EN 14363 filters: single forward pass instead of forward-backward (phase lag, half the order)",
       [T + "test_filters.py", T + "test_safety_comfort.py", T + "test_scenarios.py", T + "test_plots.py"]),
    _m("en14363-force-lowpass-2pc", P + "analysis/safety.py",
       "EN14363_FORCE_LOWPASS_HZ = 20.0",
       "EN14363_FORCE_LOWPASS_HZ = 20.4",
       "EN 14363: force low-pass corner 20.4 Hz instead of 20 Hz (2 %)",
       [T + "test_safety_comfort.py", T + "test_scenarios.py", T + "test_plots.py"]),
    # ==============================================================================================================
    # The capabilities added after the physics core: trains, the bridge crossings' load models, sprung masses,
    # curves and the track-following frames, irregularity spectra and defects, the flexible track (ground, deck,
    # moving window) and the flexible car body.  Test sets: the files that cover the module (whole files, not
    # single tests: their tests are being extended).  Measured on the tree before the tests of these modules were
    # extended (git 575fcb7, 1 worker, load ~1-4): 26 of 35 killed, 27 min with the 4 min baseline
    # (benchmarks/results/mutation_check_newer_before.json).  A survivor costs its whole test files (test_train.py
    # alone about 2 min with its cold compile).
    # ==============================================================================================================
    # ---- trains and consists -------------------------------------------------------------------------------------
    _m("train-gap-sign", P + "rolling_stock/train.py",
       "x.append(x[-1] - 0.5 * a.length_m - self.gap_m - 0.5 * b.length_m)",
       "x.append(x[-1] - 0.5 * a.length_m + self.gap_m - 0.5 * b.length_m)",
       "consist: the gap between car ends added with the wrong sign (cars overlap by the gap instead of standing "
       "apart by it)",
       [T + "test_train.py"]),
    _m("train-consist-length-gap-off-by-one", P + "rolling_stock/train.py",
       "self.gap_m * (self.n_cars - 1))",
       "self.gap_m * self.n_cars)",
       "consist length: one gap per car instead of one per pair of adjacent cars (off by one)",
       [T + "test_train.py"]),
    _m("train-coupler-damper-dropped", P + "rolling_stock/train.py",
       "damping=[cp.cx_N_s_per_m, cp.cy_N_s_per_m, 0.0]",
       "damping=[0.0, cp.cy_N_s_per_m, 0.0]",
       "coupler: the longitudinal damper dropped (only the draft-gear spring acts)",
       [T + "test_train.py"]),
    _m("train-coupler-kx-ky-swapped", P + "rolling_stock/train.py",
       "stiffness=[cp.kx_N_per_m, cp.ky_N_per_m, 0.0]",
       "stiffness=[cp.ky_N_per_m, cp.kx_N_per_m, 0.0]",
       "coupler: longitudinal and lateral stiffness swapped",
       [T + "test_train.py"]),
    # ---- bridge crossing: axle-load trains (HSLM), closed forms ---------------------------------------------------
    _m("hslm-articulated-bogies-off-by-one", P + "structures/load_models.py",
       "for k in range(n + 1):",
       "for k in range(n):",
       "HSLM-A: N articulated bogies instead of N + 1 (two axles short; the rear end coach and power car moved "
       "forward by D)",
       [T + "test_bridge_crossing.py"]),
    _m("hslm-a2-bogie-spacing-of-a4", P + "standards.py",
       "\"A2\": (17, 19.0, 3.5, 200.0)",
       "\"A2\": (17, 19.0, 3.0, 200.0)",
       "EN 1991-2 Table 6.3: HSLM-A2 with the bogie axle spacing of A4 (d = 3.0 m instead of 3.5 m)",
       [T + "test_bridge_crossing.py"]),
    _m("modal-response-acceleration-damping-factor", P + "structures/load_models.py",
       "acc = f - 2.0 * z * wj * v - wj * wj * q",
       "acc = f - z * wj * v - wj * wj * q",
       "closed-form moving-load response: modal acceleration with zeta*omega instead of 2*zeta*omega",
       [T + "test_bridge_crossing.py"]),
    _m("flexural-rigidity-2pi", P + "structures/load_models.py",
       "(2.0 * float(span_m) ** 2 * float(f1_Hz) / math.pi) ** 2",
       "(2.0 * float(span_m) ** 2 * float(f1_Hz) / (2.0 * math.pi)) ** 2",
       "EI from f1 with 2 pi for pi (f1 = pi/(2 L^2) sqrt(EI/m) read as an angular frequency; EI 4 times low)",
       [T + "test_bridge_crossing.py"]),
    # ---- bridge crossing: sprung masses --------------------------------------------------------------------------
    _m("sprung-damper-factor", P + "scenarios/bridge_crossing_sprung.py",
       "\"c_N_s_m\": 2.0 * case.sprung_damping_ratio * m * w",
       "\"c_N_s_m\": case.sprung_damping_ratio * m * w",
       "sprung masses: suspension damper zeta m omega instead of 2 zeta m omega",
       [T + "test_bridge_crossing.py"]),
    _m("sprung-deck-velocity-convective-dropped", P + "scenarios/bridge_crossing_sprung.py",
       "w_t = pz @ q_t + self.V * (dpz @ q)",
       "w_t = pz @ q_t",
       "sprung masses: deck velocity under the moving axle without the convective term V Phi'(s) q",
       [T + "test_bridge_crossing.py"]),
    _m("sprung-interaction-force-sign", P + "scenarios/bridge_crossing_sprung.py",
       "return pz.T @ (self.P + f), -f, f",
       "return pz.T @ (self.P - f), -f, f",
       "sprung masses: the suspension force acts on the deck with the wrong sign (action = reaction broken)",
       [T + "test_bridge_crossing.py"]),
    # ---- curves: the layout ---------------------------------------------------------------------------------------
    _m("layout-cant-rate-cos-dropped", P + "track/layout.py",
       "out[3] = dh / (base * math.cos(phi))",
       "out[3] = dh / base",
       "layout: cant-angle rate dphi/ds = h'/b without the 1/cos(phi) of phi = asin(h/b)",
       [T + "test_track_layout.py", T + "test_curving.py"]),
    _m("layout-gravity-gradient-sign", P + "track/layout.py",
       "np.full_like(phi, -g * s_th)",
       "np.full_like(phi, g * s_th)",
       "layout: gravity along the track on a gradient with the wrong sign (uphill pulls forward)",
       [T + "test_track_layout.py", T + "test_curving.py"]),
    _m("layout-clothoid-heading-half", P + "track/layout.py",
       "out[j, 0] = psi_a[lo] + ka * u + 0.5 * dk * u * u",
       "out[j, 0] = psi_a[lo] + ka * u + dk * u * u",
       "compiled heading in a clothoid: kappa' u^2 instead of kappa' u^2 / 2",
       [T + "test_track_layout.py", T + "test_curving.py"]),
    # ---- curves: the track-following frames ------------------------------------------------------------------------
    _m("track-following-gradient-gravity-sign", P + "rolling_stock/track_following.py",
       "F[i, 0] = m[i] * (-g * s_th - a1[0] - a3[0])",
       "F[i, 0] = m[i] * (g * s_th - a1[0] - a3[0])",
       "track-following frame: the gradient's gravity term along x with the wrong sign",
       [T + "test_curving.py"]),
    _m("track-following-gyroscopic-dropped", P + "rolling_stock/track_following.py",
       "T[i, a] = -(I_dOm + a1[a] + a2[a] + a3[a] - I_wO)",
       "T[i, a] = -(I_dOm + a1[a] + a3[a] - I_wO)",
       "track-following frame: the spinning wheelset's gyroscopic moment Omega x I omega_s dropped",
       [T + "test_curving.py"]),
    _m("track-following-versine-heading-dropped", P + "rolling_stock/track_following.py",
       "y_h = hp[kB, 1] - hp[kA, 1] - hp[kA, 0] * d",
       "y_h = hp[kB, 1] - hp[kA, 1]",
       "track-following frame: lateral offset of body B's frame without the term -psi(s_A) d (not the versine)",
       [T + "test_curving.py"]),
    # ---- irregularities: compiled components (track/rigid.py) ---------------------------------------------------
    _m("defect-bump-full-depth", P + "track/rigid.py",
       "a = 0.5 * rows[r, 4]",
       "a = rows[r, 4]",
       "cosine bump: amplitude d instead of d/2 of d (1 - cos)/2 (twice as deep)",
       [T + "test_irregularities.py", T + "test_track.py"]),
    _m("defect-dipped-joint-slope-half", P + "track/rigid.py",
       "return d * (1.0 - ax), -d * sign * 2.0 / length, 0.0",
       "return d * (1.0 - ax), -d * sign / length, 0.0",
       "dipped joint: slope d/L instead of 2 d/L (the chain rule's dx/ds = 2/L dropped to 1/L)",
       [T + "test_irregularities.py", T + "test_track.py"]),
    # ---- irregularities: per-rail channels and defects --------------------------------------------------------------
    _m("channels-from-rails-difference-sign", P + "track/irregularities.py",
       "channels[diff] = a - b",
       "channels[diff] = b - a",
       "ChannelTable.from_rails: cross level / gauge as left minus right (sign of the difference channel)",
       [T + "test_irregularities.py"]),
    _m("defect-one-rail-full-mean", P + "track/irregularities.py",
       "parts = [(mean, self.depth_m if sign == 0.0 else 0.5 * self.depth_m)]",
       "parts = [(mean, self.depth_m)]",
       "defect on one rail: its full depth in the mean channel instead of half (the other rail moves too)",
       [T + "test_irregularities.py"]),
    # ---- irregularity spectra and their generation ------------------------------------------------------------------
    _m("spectra-fra-cross-level-factor", P + "track/spectra.py",
       "return _CM2 * 4.0 * FRA_K * a_v * c2 / ((w2 + c2) * (w2 + om_s ** 2))",
       "return _CM2 * 2.0 * FRA_K * a_v * c2 / ((w2 + c2) * (w2 + om_s ** 2))",
       "FRA cross level and gauge PSD with 2 k A_v for 4 k A_v",
       [T + "test_spectra.py"]),
    _m("spectra-fra-av-aa-swapped", P + "track/spectra.py",
       "a_v, a_a, om_s = FRA_CLASSES[self.level]",
       "a_a, a_v, om_s = FRA_CLASSES[self.level]",
       "FRA spectra: A_v and A_a of the class swapped (level with the alignment coefficient)",
       [T + "test_spectra.py"]),
    _m("spectra-amplitude-without-2", P + "track/spectra.py",
       "amp[inside] = scale * np.sqrt(2.0 * self.spectrum.psd(c, omega[inside]) * d_omega)",
       "amp[inside] = scale * np.sqrt(self.spectrum.psd(c, omega[inside]) * d_omega)",
       "generated irregularity: harmonic amplitude sqrt(S dOmega) instead of sqrt(2 S dOmega) (half the variance)",
       [T + "test_spectra.py"]),
    _m("standards-fra-class4-omega-s-of-class5", P + "standards.py",
       "4: (0.5376, 0.3027, 1.1312)",
       "4: (0.5376, 0.3027, 0.8209)",
       "FRA class 4 with the Omega_s of class 5 (0.8209 instead of 1.1312 rad/m)",
       [T + "test_spectra.py"]),
    # ---- flexible track on the ground -------------------------------------------------------------------------------
    _m("flexible-pad-lateral-1.2", P + "track/flexible_parameters.py",
       "2 * self.pad_k_lateral_N_m, 2 * self.pad_c_lateral_Ns_m",
       "2.4 * self.pad_k_lateral_N_m, 2 * self.pad_c_lateral_Ns_m",
       "flexible track: the lateral beam's pad stiffness 1.2 times the two rails' 2 k_py",
       [T + "test_flexible_track.py"]),
    _m("flexible-support-parallel", P + "track/flexible_parameters.py",
       "return kp * kb / (kp + kb) / self.sleeper_spacing_m",
       "return (kp + kb) / self.sleeper_spacing_m",
       "flexible track: pad and ballast in parallel instead of in series in the support stiffness per metre",
       [T + "test_flexible_track.py", T + "test_flexible_window.py"]),
    _m("flexible-ballast-damping-dropped", P + "track/flexible.py",
       "cv.append(np.array([cp, cp, -cp, -cp, cb]))",
       "cv.append(np.array([cp, cp, -cp, -cp, 0.0]))",
       "flexible track: the ballast damper dropped from the assembled damping matrix",
       [T + "test_flexible_track.py"]),
    # ---- flexible track over a deck ---------------------------------------------------------------------------------
    _m("track-on-deck-lateral-lever-sign", P + "track/flexible_deck.py",
       "\"lateral\": self._g[\"v\"] + e * self._g[\"tx\"]}",
       "\"lateral\": self._g[\"v\"] - e * self._g[\"tx\"]}",
       "track on a deck: the deck top's lateral motion v - e theta_x (sign of the torsion lever arm)",
       [T + "test_flexible_track.py", T + "test_track_on_deck_train.py"]),
    _m("track-on-deck-damping-factor", P + "track/flexible_deck.py",
       "C[sl_d, sl_d] = 2.0 * self.deck.damping_ratio / w1 * K[sl_d, sl_d]",
       "C[sl_d, sl_d] = self.deck.damping_ratio / w1 * K[sl_d, sl_d]",
       "track on a deck: stiffness-proportional deck damping zeta/omega_1 K instead of 2 zeta/omega_1 K",
       [T + "test_flexible_track.py", T + "test_track_on_deck_train.py"]),
    # ---- flexible track: the moving window --------------------------------------------------------------------------
    _m("window-sleeper-shift-off-by-one", P + "track/flexible_window.py",
       "2 * model.n_nodes + k + np.arange(ns)",
       "2 * model.n_nodes + k - 1 + np.arange(ns)",
       "moving window: the sleepers moved by k - 1 bays while the rail moves by k (off by one)",
       [T + "test_flexible_window.py"]),
    _m("window-quasi-static-rate-kept", P + "track/flexible_window.py",
       "v_d = T @ (q_t - V * w * (dA_old.T @ F))",
       "v_d = T @ q_t",
       "moving window: the travelling bowl's rate V diag(w^-2) Phi'^T F not taken out before the shift (dropped "
       "term)",
       [T + "test_flexible_window.py"]),
    # ---- flexible car body ----------------------------------------------------------------------------------------
    _m("car-body-modal-damping-factor", P + "rolling_stock/car_body_model.py",
       "return np.diag(2.0 * self.damping_ratio * self.omega_rad_s)",
       "return np.diag(self.damping_ratio * self.omega_rad_s)",
       "flexible car body: modal damping zeta omega instead of 2 zeta omega",
       [T + "test_flexible_car_body.py"]),
    _m("car-body-rotary-inertia-swapped", P + "rolling_stock/car_body_model.py",
       "rotary_inertia_y_kg_m2_m=rot[\"Iyy_kg_m2\"],\n                       rotary_inertia_z_kg_m2_m=rot[\"Izz_kg_m2\"]",
       "rotary_inertia_y_kg_m2_m=rot[\"Izz_kg_m2\"],\n                       rotary_inertia_z_kg_m2_m=rot[\"Iyy_kg_m2\"]",
       "flexible car body: the pitch and yaw rotary inertias of the section swapped (i_y from Izz, i_z from Iyy)",
       [T + "test_flexible_car_body.py"]),
    _m("car-body-point-coriolis-factor", P + "rolling_stock/flexible_body.py",
       "+ 2.0 * (P @ qt).reshape(n, 3) @ W.T",
       "+ (P @ qt).reshape(n, 3) @ W.T",
       "flexible car body: point acceleration with omega x Phi q' instead of the Coriolis term 2 omega x Phi q'",
       [T + "test_flexible_car_body.py"]),
    # ---- bridge crossings: EN 1990 A2 check, default step, resonance speeds ----------------------------------------
    _m("standards-en1990-limits-swapped", P + "standards.py",
       "{\"ballasted\": 3.5, \"direct_fastening\": 5.0}",
       "{\"ballasted\": 5.0, \"direct_fastening\": 3.5}",
       "EN 1990 A2 deck-acceleration limits of the two track forms swapped (5 m/s2 for ballasted track)",
       [T + "test_scenario_deck.py", T + "test_bridge_crossing.py"]),
    _m("bridge-crossing-en1990-passed-inverted", P + "scenarios/bridge_crossing_summary.py",
       "\"passed\": bool(peak <= limit) if judged else None",
       "\"passed\": bool(peak >= limit) if judged else None",
       "bridge crossing: the EN 1990 A2 check passes when the peak reaches the limit (inequality reversed)",
       [T + "test_bridge_crossing.py"]),
    _m("bridge-crossing-span-resonance-km-h", P + "scenarios/bridge_crossing_summary.py",
       "[speed_km_h(v) for v in resonance_speeds_m_s(deck.f1_Hz[k], spacing)]",
       "[v / 3.6 for v in resonance_speeds_m_s(deck.f1_Hz[k], spacing)]",
       "bridge crossing: the spans' resonance speeds converted m/s -> km/h by dividing by 3.6",
       [T + "test_bridge_crossing.py"]),
    _m("en1991-damping-below-25-m", P + "scenarios/en1991_dynamic.py",
       "z20 + slope * max(0.0, 20.0 - float(span_m))", "z20 + slope * max(0.0, 25.0 - float(span_m))",
       "EN 1991-2 check: Table 6.6's damping rising below 25 m instead of 20 m",
       [T + "test_en1991_dynamic.py"]),
    _m("en1991-cutoff-modes-floor", P + "scenarios/en1991_dynamic.py",
       "math.ceil(math.sqrt(cutoff / sec.vertical_frequency_Hz(L)) - 1e-9)",
       "math.floor(math.sqrt(cutoff / sec.vertical_frequency_Hz(L)) + 1e-9)",
       "EN 1991-2 check: the modes up to the last below the cut-off instead of the first at or above it",
       [T + "test_en1991_dynamic.py"]),
    _m("modes-file-mass-scale-not-in-normalisation", P + "structures/modes_file.py",
       "scale = 1.0 / np.sqrt(r * data.modal_mass_kg)", "scale = 1.0 / np.sqrt(data.modal_mass_kg)",
       "modes file: the shapes normalised by the file's modal masses, not the mass bound's r m_j",
       [T + "test_deck_sources.py"]),
    _m("modes-file-frequency-scale-by-r", P + "structures/modes_file.py",
       "omega = 2.0 * math.pi * data.frequency_hz / math.sqrt(r)", "omega = 2.0 * math.pi * data.frequency_hz / r",
       "modes file: a mass bound r scales the frequencies by 1/r instead of 1/sqrt(r)",
       [T + "test_deck_sources.py"]),
    _m("modes-file-joint-not-a-break", P + "structures/modes_file.py",
       "cuts.add(int(i) + 1)                             # a joint", "pass                                             # a joint",
       "modes file: a position given twice (a joint between two decks) not a break of the splines",
       [T + "test_deck_sources.py"]),
    _m("continuous-deck-step-bound-simply-supported", P + "scenarios/bridge_crossing_case.py",
       "band = CLAMPED_BAND if self.continuous else 0.0", "band = 0.0",
       "continuous deck: the time step's highest frequency N² f1 of a simply supported span (below the deck's)",
       [T + "test_deck_sources.py"]),
    _m("global-deck-quasi-static-omega", P + "scenarios/bridge_crossing_probes.py",
       "modes.shape_at(self.x0 + 0.5 * self.L)[1] / modes.omega_rad_s ** 2",
       "modes.shape_at(self.x0 + 0.5 * self.L)[1] / modes.omega_rad_s",
       "a continuous or modes-file deck's quasi-static deflection divided by omega instead of omega squared",
       [T + "test_deck_sources.py"]),
    _m("global-deck-cutoff-second-mode", P + "scenarios/bridge_crossing_deck.py",
       "cuts.append(cutoff_of_frequencies_Hz(f[0], f[min(2, f.size - 1)]))",
       "cuts.append(cutoff_of_frequencies_Hz(f[0], f[min(1, f.size - 1)]))",
       "a continuous or modes-file deck's EN 1990 cut-off from its second vertical mode instead of the third",
       [T + "test_deck_sources.py"]),
    _m("stability-damping-ratio-sign", P + "analysis/stability.py",
       "zeta = np.where(mag > 0.0, -lam.real / np.where(mag > 0.0, mag, 1.0), np.nan)",
       "zeta = np.where(mag > 0.0, lam.real / np.where(mag > 0.0, mag, 1.0), np.nan)",
       "running stability: the damping ratio of an eigenvalue with the wrong sign (+sigma/|lambda|)",
       [T + "test_critical_speed_reference.py", T + "test_critical_speed_quick.py"]),
    _m("stability-limit-cycle-rule-inverted", P + "analysis/stability.py",
       "last >= min_amplitude and zeta <= max_damping_ratio)", "last >= min_amplitude and zeta >= max_damping_ratio)",
       "running stability: a limit cycle persists when its trend decays faster than the threshold (rule inverted)",
       [T + "test_critical_speed_reference.py"]),
    _m("stability-gyroscopic-term-sign", P + "scenarios/critical_speed_linear.py",
       "a[k + 3:k + 6] = rot[k].apply(a[k + 3:k + 6]) - np.cross(ud[k + 3:k + 6], state.w0[k])",
       "a[k + 3:k + 6] = rot[k].apply(a[k + 3:k + 6]) + np.cross(ud[k + 3:k + 6], state.w0[k])",
       "running stability: the linearisation's rotation rate term theta' x omega0 with the wrong sign",
       [T + "test_critical_speed_quick.py"]),
    _m("stability-eigenvector-check-off", P + "analysis/stability.py",
       "if np.linalg.norm(A @ v - lam[k] * v) > EIGENVECTOR_RESIDUAL_MAX * scale * np.linalg.norm(v):",
       "if False:",
       "running stability: the eigenvectors of the state matrix not checked (LAPACK's balancing left as it is)",
       [T + "test_critical_speed_reference.py", T + "test_critical_speed_linearisation.py"]),
    _m("stability-spin-not-rotated", P + "scenarios/critical_speed_linear.py",
       "v[k + 3:k + 6] = rot[k].inv().apply(ud[k + 3:k + 6] + dR.apply(self.w0[k]))",
       "v[k + 3:k + 6] = rot[k].inv().apply(ud[k + 3:k + 6] + self.w0[k])",
       "running stability: a perturbed rotation leaves the operating point's angular velocity (the spin) unrotated",
       [T + "test_critical_speed_linearisation.py", T + "test_critical_speed_quick.py"]),
    _m("stability-linger-max-change", P + "analysis/stability.py",
       "k = int(ok[np.argmin(change[ok])])", "k = int(ok[np.argmax(change[ok])])",
       "running stability: the unstable cycle read where the two bracketing runs change most",
       [T + "test_critical_speed_reference.py"]),
    _m("crossing-contact-step-half-period", P + "scenarios/bridge_crossing_vehicles.py",
       "2.0 * math.pi / (CONTACT_STEPS_PER_PERIOD * _contact_omega(consist))",
       "math.pi / (CONTACT_STEPS_PER_PERIOD * _contact_omega(consist))",
       "full-interaction crossing: its step half the rule's (40 steps per bounce period)",
       [T + "test_crossing_step.py"]),
    _m("speed-km-h-not-rounded", P + "conventions.py",
       'return float(f"{v:.{KM_H_DIGITS}g}")', "return float(v)",
       "speeds converted m/s -> km/h without rounding to 12 significant digits",
       [T + "test_sweep_faults.py"]),
    _m("bridge-crossing-default-dt-passage-factor", P + "scenarios/bridge_crossing_case.py",
       "2.0 * min(case.chain_m) / (STEPS_PER_PERIOD",
       "1.0 * min(case.chain_m) / (STEPS_PER_PERIOD",
       "bridge crossing: default step with L/(40 N V) for 2L/(40 N V) (the passage bound halved)",
       [T + "test_bridge_crossing.py"]),
    _m("bridge-crossing-en1990-midspan-column", P + "scenarios/bridge_crossing_summary.py",
       "_max_abs(ts[\"deck_en1990_max_abs_acceleration_m_s2\"])",
       "_max_abs(ts[\"deck_midspan_acceleration_m_s2\"])",
       "bridge crossing: the EN 1990 A2 peak read from the mid-span column (all modes, one point) instead of the "
       "largest of L/10 ... 9L/10 with the modes up to the cut-off (wrong column)",
       [T + "test_bridge_crossing.py"]),
    _m("vehicles-hertz-dt-without-2", P + "scenarios/bridge_crossing_vehicles.py",
       "omega = max(omega, math.sqrt(2.0 * k / v.wheelset.mass_kg))",
       "omega = max(omega, math.sqrt(k / v.wheelset.mass_kg))",
       "bridge crossing with vehicles: the wheelset's bounce on its two Hertz springs with k for 2 k (step bound "
       "sqrt 2 too large)",
       [T + "test_train.py"]),
    # ---- support motion -----------------------------------------------------------------------------------------
    _m("support-motion-ramp-down-slope-sign", P + "structures/support_motion.py",
       "return s, -ds / Tr, dds / (Tr * Tr)",
       "return s, ds / Tr, dds / (Tr * Tr)",
       "support motion: the ramp-down window's slope w' with the wrong sign (velocity and acceleration wrong there)",
       [T + "test_bridge_support_motion.py"]),
    _m("support-motion-load-sign", P + "structures/support_motion.py",
       "np.multiply(self.gamma, -self.motion.state(float(t))[2], out=self._f)",
       "np.multiply(self.gamma, self.motion.state(float(t))[2], out=self._f)",
       "support motion: effective load +Gamma a_g instead of -Gamma a_g",
       [T + "test_bridge_support_motion.py"]),
    # ---- steady curving ----------------------------------------------------------------------------------------
    _m("curving-angle-of-attack-sign", P + "analysis/curving.py",
       "res[\"angle_of_attack_rad\"].append(float(np.mean(out_s * ts[f\"yaw_w{j + 1}_rad\"][sel])))",
       "res[\"angle_of_attack_rad\"].append(float(np.mean(-out_s * ts[f\"yaw_w{j + 1}_rad\"][sel])))",
       "steady curving: the angle of attack's sign (positive with the wheelset turned towards the curve's outside)",
       [T + "test_curving.py"]),
    # ---- measured irregularity files ------------------------------------------------------------------------------
    _m("measured-rails-gauge-sign", P + "track/measured.py",
       "channels[\"gauge\"] = col[\"y_right\"] - col[\"y_left\"]",
       "channels[\"gauge\"] = col[\"y_left\"] - col[\"y_right\"]",
       "measured irregularities: gauge from the rail columns as y_left - y_right",
       [T + "test_irregularities.py"]),
    # ---- flexible track outputs under the wheels -------------------------------------------------------------------
    _m("flexible-outputs-sides-swapped", P + "track/flexible_outputs.py",
       "SIDES = {\"left\": -1.0, \"right\": 1.0}",
       "SIDES = {\"left\": 1.0, \"right\": -1.0}",
       "flexible track outputs: left rail at y = +b/2 (the sides' roll lever swapped)",
       [T + "test_track_on_deck_train.py"]),
    _m("flexible-outputs-totals-ground-deck-swapped", P + "track/flexible_outputs.py",
       "deck = float(per_sleeper[on_deck].sum())\n    ground = float(per_sleeper[~on_deck].sum())",
       "deck = float(per_sleeper[~on_deck].sum())\n    ground = float(per_sleeper[on_deck].sum())",
       "flexible track outputs: the ballast force totals of the sleepers on the ground and on the deck swapped",
       [T + "test_track_on_deck_train.py"]),
    # ---- the run's checks in the compiled force call ----------------------------------------------------------------
    _m("watch-checks-the-predicted-state", P + "simulation/watch.py",
       "if st[W_PENDING] != 0.0 and t > st[W_PENDING_T]:",
       "if st[W_PENDING] != 0.0 and t >= st[W_PENDING_T]:",
       "the watch checks the last stage's predicted state at a grid time instead of the accepted one",
       [T + "test_watch.py"]),
    _m("watch-stopping-state-recorded", P + "simulation/watch.py",
       "self.recorder.n and self.recorder.last_time_s == t:",
       "self.recorder.n and self.recorder.last_time_s == -t:",
       "a run stopped from the watch keeps the stopping state's row (the pre-step path never records it)",
       [T + "test_watch.py"]),
    _m("watch-window-maxima-kept", P + "simulation/watch.py",
       "self.guidance.max_quotient[:] = self._mq_saved",
       "pass",
       "a stop by the monitor in the watch keeps the flange-climb window's update of the stopping state",
       [T + "test_watch.py"]),
    _m("kept-curves-without-key", P + "contact/kernel.py",
       "return kept[block + KEPT_S_WHEEL] == s_w and kept[block + KEPT_S_RAIL] == s_r",
       "return kept[block + KEPT_S_WHEEL] == kept[block + KEPT_S_WHEEL]",
       "the search and a region separated by its bound take the curves kept at another warm start",
       [T + "test_contact_search.py"]),
    _m("stability-bound-too-low", P + "simulation/monitor_core.py",
       "if math.sqrt(bound * (1.0 + BOUND_MARGIN)) * h <= below:",
       "if math.sqrt(0.9 * bound) * h <= below:",
       "the stability estimate skips states whose eigenvalue may exceed the running maximum",
       [T + "stress/test_stress_monitor_core.py"]),
    _m("curve-point-unnormalised-tangent", P + "profiles/curve.py",
       "return py, pz, dy / speed, dz / speed",
       "return py, pz, dy, dz",
       "the searches' point-and-tangent evaluation differs from the full evaluation (tangent not normalised)",
       [T + "test_curve.py"]),
    _m("multilinear-sum-shifted-psi", P + "creep/table.py",
       "                    fx += w4 * v[ips - 1 + m, 0]\n                    fy += w4 * v[ips - 1 + m, 1]\n"
       "                    mz += w4 * v[ips - 1 + m, 2]\n    return sx",
       "                    fx += w4 * v[ips - 2 + m, 0]\n                    fy += w4 * v[ips - 2 + m, 1]\n"
       "                    mz += w4 * v[ips - 2 + m, 2]\n    return sx",
       "the multilinear creep table sums the psi nodes one interval off",
       [T + "test_creep_table_interpolation.py"], k="multilinear"),
    _m("table-linear-law-cubic", P + "creep/registry.py",
       "ORDER_CUBIC if law == _TABLE else ORDER_LINEAR", "ORDER_CUBIC",
       "the table_linear law interpolates cubically (the fast preset's law not the one it names)",
       [T + "test_connector.py"], k="table_laws"),
    _m("watched-deck-forces-of-wheelsets", P + "simulation/watch.py",
       "    Q[:] = wc.call.f[m0:]", "    Q[:] = wc.call.f[:Q.shape[0]]",
       "the watched deck columns take the wheelsets' forces for the modal forces",
       [T + "test_watch.py"], k="bridge_crossing"),
]


# ------------------------------------------------------------------------------------------------------------------
# copies and runs
# ------------------------------------------------------------------------------------------------------------------
PLUGIN = '''"""Loaded by tests/mutation_check.py (-p): the package under test must be the copy's."""
import os

import pytest


def pytest_configure(config):
    import exudyn_wheelrail
    copy = os.path.realpath(os.environ["MUTATION_CHECK_COPY"])
    where = os.path.realpath(exudyn_wheelrail.__file__)
    if not where.startswith(copy + os.sep):
        raise pytest.UsageError(f"mutation check: exudyn_wheelrail imported from {where}, not from the copy {copy}")
    with open(os.environ["MUTATION_CHECK_WHERE"], "w") as fh:
        fh.write(where)
'''


def shared_source() -> Path:
    """The folder ``shared`` beside the repository (what tests/reference_paths.py uses), resolved."""
    p = (REPO.parent / "shared").resolve()
    if not (p / "reference").is_dir():
        raise SystemExit(f"no shared references at {p / 'reference'}")
    return p


def make_copy(root: Path, name: str) -> Path:
    dst = root / name
    dst.mkdir()
    for item in COPY_ITEMS:
        src = REPO / item
        if src.is_dir():
            shutil.copytree(src, dst / item, ignore=IGNORE)
        elif src.is_file():
            shutil.copy2(src, dst / item)
    return dst


@dataclasses.dataclass
class RunResult:
    exit_code: int | None
    seconds: float
    output: str
    where: str | None
    timed_out: bool


def run_pytest(copy: Path, args: list[str], timeout_s: float, scratch: Path, plugin_dir: Path,
               extra_pytest: list[str] | None = None, numba_cache: Path | None = None) -> RunResult:
    """``python -m pytest -x -q -p no:cacheprovider <args>`` in ``copy`` with PYTHONPATH = copy, an empty numba
    cache (unless ``numba_cache`` is given) and no bytecode; the process group is killed on timeout."""
    scratch.mkdir(parents=True, exist_ok=True)
    cache = numba_cache if numba_cache is not None else Path(tempfile.mkdtemp(prefix="numba_", dir=scratch))
    where_file = scratch / f"where_{os.getpid()}_{threading.get_ident()}_{time.monotonic_ns()}.txt"
    env = dict(os.environ)
    env.update({
        "PYTHONPATH": os.pathsep.join([str(copy), str(plugin_dir)]),
        "NUMBA_CACHE_DIR": str(cache),
        "PYTHONDONTWRITEBYTECODE": "1",
        "MUTATION_CHECK_COPY": str(copy),
        "MUTATION_CHECK_WHERE": str(where_file),
        "MPLBACKEND": "Agg",
    })
    env.pop("PYTHONSTARTUP", None)
    # -n 0: one process per run (the check runs its mutants in parallel itself, and test workers would each compile
    # the kernels again into the run's empty cache)
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-n", "0", "-p", "no:cacheprovider", "-p",
           "_mutation_check_plugin"]
    cmd += list(extra_pytest or []) + args
    t0 = time.monotonic()
    proc = subprocess.Popen(cmd, cwd=copy, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            start_new_session=True)
    timed_out = False
    try:
        out, _ = proc.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        timed_out = True
        try:
            os.killpg(proc.pid, signal.SIGKILL)        # the group of the process started here, by its id
        except ProcessLookupError:
            pass
        out, _ = proc.communicate()
    seconds = time.monotonic() - t0
    where = where_file.read_text() if where_file.exists() else None
    if numba_cache is None:
        shutil.rmtree(cache, ignore_errors=True)
    return RunResult(None if timed_out else proc.returncode, seconds, out or "", where, timed_out)


def failing_tests(output: str) -> list[str]:
    return [m.group(1) for m in re.finditer(r"^(?:FAILED|ERROR) (\S+)", output, re.M)]


def summary_line(output: str) -> str:
    """pytest's final line (e.g. '51 passed, 1 skipped in 80.3s'), or ''."""
    for line in reversed(output.rstrip().splitlines()):
        if re.search(r"\b(passed|failed|error|errors|no tests ran)\b.* in [0-9.]+s", line):
            return line.strip("= ").strip()
    return ""


def last_lines(output: str, n: int = 25) -> str:
    return "\n".join(output.rstrip().splitlines()[-n:])


def classify(res: RunResult) -> str:
    if res.timed_out:
        return "timeout"
    if res.where is None:
        return "error"                  # the plugin did not confirm the copy (usage/collection error before)
    if res.exit_code == 1:
        return "killed"
    if res.exit_code == 0:
        return "survived"
    return "error"


def apply_mutant(copy: Path, m: Mutant) -> tuple[Path, str] | str:
    """Write the mutant into the copy; returns (path, original text) or an error message."""
    path = copy / m.file
    if not path.is_file():
        return f"file {m.file} not found"
    text = path.read_text(encoding="utf-8")
    n = text.count(m.find)
    if n != 1:
        return f"snippet occurs {n} times in {m.file} (must be exactly once)"
    path.write_text(text.replace(m.find, m.replace), encoding="utf-8")
    return path, text


def check_snippets(mutants) -> list[str]:
    problems = []
    for m in mutants:
        path = REPO / m.file
        if not path.is_file():
            problems.append(f"{m.id}: {m.file} not found")
            continue
        n = path.read_text(encoding="utf-8").count(m.find)
        if n != 1:
            problems.append(f"{m.id}: snippet occurs {n} times in {m.file}")
        for t in m.tests:
            if not (REPO / t.split("::")[0]).is_file():
                problems.append(f"{m.id}: test file {t} not found")
    ids = [m.id for m in mutants]
    dup = {i for i in ids if ids.count(i) > 1}
    if dup:
        problems.append(f"duplicate ids: {sorted(dup)}")
    return problems


def baseline_selection(mutants) -> list[list[str]]:
    """Pytest argument lists that together cover every selected mutant's tests: the union of the node ids of
    the mutants without -k (a whole file subsumes its node ids), plus one run per distinct -k selection."""
    files, nodes, with_k = set(), set(), []
    for m in mutants:
        if m.k:
            if m.pytest_args() not in with_k:
                with_k.append(m.pytest_args())
            continue
        for t in m.tests:
            (nodes if "::" in t else files).add(t)
    nodes = {n for n in nodes if n.split("::")[0] not in files}
    runs = []
    plain = sorted(files) + sorted(nodes)
    if plain:
        runs.append(plain)
    return runs + with_k


def _git_state() -> dict | None:
    """The commit of the repository the copies are made from and its files under :data:`COPY_ITEMS` that differ
    from it (what the results were measured on); None without git."""
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=REPO, capture_output=True, text=True,
                                check=True).stdout.strip()
        status = subprocess.run(["git", "status", "--porcelain", "--", *COPY_ITEMS], cwd=REPO, capture_output=True,
                                text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    return {"commit": commit, "modified_files": [line[3:] for line in status.splitlines() if line.strip()]}


def _load():
    try:
        return list(os.getloadavg())
    except OSError:
        return None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", help="comma-separated mutant ids")
    ap.add_argument("--list", action="store_true", help="list the mutants (snippets checked) and exit")
    ap.add_argument("--workers", type=int, default=1, help="parallel mutant runs (one repository copy each)")
    ap.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S, help="seconds per pytest run")
    ap.add_argument("--json", help="write the results to this file")
    ap.add_argument("--keep", action="store_true", help="keep the temporary copies")
    ap.add_argument("--skip-baseline", action="store_true", help="do not run the unmutated tests first (debugging)")
    ap.add_argument("--cache-cost", action="store_true",
                    help="measure the cold-cache cost: run each selected mutant's tests unmutated twice, with an "
                         "empty and then with the warm numba cache, and exit")
    args = ap.parse_args(argv)

    mutants = MUTANTS
    if args.only:
        want = [s.strip() for s in args.only.split(",") if s.strip()]
        unknown = [w for w in want if w not in {m.id for m in MUTANTS}]
        if unknown:
            ap.error(f"unknown mutant id(s): {', '.join(unknown)}")
        mutants = [m for m in MUTANTS if m.id in want]
    problems = check_snippets(mutants)

    if args.list:
        for m in mutants:
            print(f"{m.id:42s} {m.file}\n    {m.description}\n    tests: {' '.join(m.pytest_args())}")
        print(f"\n{len(mutants)} mutants")
        if problems:
            print("PROBLEMS:\n  " + "\n  ".join(problems))
            return 1
        return 0
    if args.workers < 1:
        ap.error("--workers must be >= 1")

    started = _dt.datetime.now().isoformat(timespec="seconds")
    t_start = time.monotonic()
    load_start = _load()
    root = Path(tempfile.mkdtemp(prefix="mutation_check_"))
    print(f"work folder {root}; load average {load_start}", flush=True)
    try:
        (root / "shared").symlink_to(shared_source(), target_is_directory=True)
        plugin_dir = root / "plugin"
        plugin_dir.mkdir()
        (plugin_dir / "_mutation_check_plugin.py").write_text(PLUGIN)
        scratch = root / "scratch"
        copies = [make_copy(root, f"repo{i}") for i in range(args.workers)]

        if args.cache_cost:
            rows = []
            for m in mutants:
                cache = scratch / f"cache_{m.id}"
                cache.mkdir(parents=True)
                cold = run_pytest(copies[0], m.pytest_args(), args.timeout, scratch, plugin_dir, numba_cache=cache)
                warm = run_pytest(copies[0], m.pytest_args(), args.timeout, scratch, plugin_dir, numba_cache=cache)
                shutil.rmtree(cache, ignore_errors=True)
                rows.append({"id": m.id, "tests": m.pytest_args(), "cold_s": cold.seconds, "warm_s": warm.seconds,
                             "cold_exit": cold.exit_code, "warm_exit": warm.exit_code})
                print(f"{m.id:42s} cold {cold.seconds:7.1f} s   warm {warm.seconds:7.1f} s", flush=True)
            if args.json:
                Path(args.json).parent.mkdir(parents=True, exist_ok=True)
                Path(args.json).write_text(json.dumps({"cache_cost": rows, "load_start": load_start,
                                                       "load_end": _load()}, indent=1))
            return 0

        # the copy must pass the selected tests unmutated
        baseline = []
        if not args.skip_baseline:
            for sel in baseline_selection(mutants):
                res = run_pytest(copies[0], sel, args.timeout * 3, scratch, plugin_dir)
                status = classify(res)
                baseline.append({"tests": sel, "exit_code": res.exit_code, "seconds": round(res.seconds, 1),
                                 "package_imported_from": res.where, "pytest_summary": summary_line(res.output)})
                print(f"baseline ({len(sel)} test paths): exit {res.exit_code}, {res.seconds:.0f} s, "
                      f"package from {res.where}", flush=True)
                if status != "survived":
                    print(last_lines(res.output, 60))
                    print("ABORT: the unmutated copy does not pass its tests")
                    return 2

        pool = queue.Queue()
        for c in copies:
            pool.put(c)
        results = {}
        loads = []
        lock = threading.Lock()

        def job(m: Mutant):
            copy = pool.get()
            try:
                applied = apply_mutant(copy, m)
                if isinstance(applied, str):
                    return m, "error", None, 0.0, applied, [], None, ""
                path, original = applied
                try:
                    res = run_pytest(copy, m.pytest_args(), args.timeout, scratch, plugin_dir)
                finally:
                    path.write_text(original, encoding="utf-8")
                status = classify(res)
                note = ""
                if status == "timeout":
                    note = f"timeout after {args.timeout:.0f} s"
                elif status == "error":
                    note = f"exit code {res.exit_code}: " + last_lines(res.output, 8)
                return (m, status, res.exit_code, res.seconds, note, failing_tests(res.output), res.where,
                        summary_line(res.output))
            finally:
                pool.put(copy)

        print(f"\n{'mutant':42s} {'result':9s} {'seconds':>8s}  killed by / pytest summary", flush=True)
        with cf.ThreadPoolExecutor(max_workers=args.workers) as ex:
            futures = [ex.submit(job, m) for m in mutants]
            for fut in cf.as_completed(futures):
                m, status, code, seconds, note, failed, where, summary = fut.result()
                with lock:
                    results[m.id] = {"id": m.id, "file": m.file, "description": m.description,
                                     "tests": m.pytest_args(), "result": status, "exit_code": code,
                                     "seconds": round(seconds, 1), "failed_tests": failed, "note": note,
                                     "package_imported_from": where, "pytest_summary": summary,
                                     "find": m.find, "replace": m.replace}
                    load = _load()
                    if load:
                        loads.append(load[0])
                    why = failed[0] if failed else note.splitlines()[0] if note else summary
                    print(f"{m.id:42s} {status.upper():9s} {seconds:8.1f}  {why[:90]}", flush=True)

        ordered = [results[m.id] for m in mutants]
        killed = sum(r["result"] == "killed" for r in ordered)
        survived = [r for r in ordered if r["result"] == "survived"]
        other = [r for r in ordered if r["result"] not in ("killed", "survived")]
        rate = killed / (killed + len(survived)) if killed + len(survived) else float("nan")
        total = time.monotonic() - t_start
        load_end = _load()
        print(f"\nkill rate {killed}/{killed + len(survived)} = {rate:.1%}   "
              f"(errors/timeouts, not counted: {len(other)})")
        if survived:
            print("survivors:")
            for r in survived:
                print(f"  {r['id']}: {r['description']}")
        if other:
            print("not decided (error/timeout):")
            for r in other:
                print(f"  {r['id']}: {r['result']}: {r['note'].splitlines()[0] if r['note'] else ''}")
        print(f"total {total / 60:.1f} min; load average start {load_start}, end {load_end}")
        if args.json:
            out = {
                "started": started, "git": _git_state(), "total_seconds": round(total, 1), "workers": args.workers,
                "timeout_s": args.timeout, "python": sys.version.split()[0], "platform": platform.platform(),
                "cpu_count": os.cpu_count(), "load_average_start": load_start, "load_average_end": load_end,
                "load_1min_mean_at_mutant_ends": (sum(loads) / len(loads)) if loads else None,
                "numba_cache": "empty NUMBA_CACHE_DIR per pytest run, PYTHONDONTWRITEBYTECODE=1",
                "baseline": baseline, "n_mutants": len(ordered), "killed": killed, "survived": len(survived),
                "not_decided": len(other), "kill_rate": rate,
                "survivors": [{"id": r["id"], "description": r["description"]} for r in survived],
                "mutants": ordered,
            }
            Path(args.json).parent.mkdir(parents=True, exist_ok=True)
            Path(args.json).write_text(json.dumps(out, indent=1, ensure_ascii=False))
            print(f"results written to {args.json}")
        return 0
    finally:
        if args.keep:
            print(f"kept {root}")
        else:
            shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
