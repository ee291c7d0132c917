r"""A car body's modes from an external FE model file (:func:`modes_from_fe_file`, :func:`read_fe_file`).

External FE models (:func:`modes_from_fe_file`)
-----------------------------------------------
A car body's modes from an external FE model enter through the same FEM interface: an ``.npz`` file with the
mesh of position nodes and its mass and stiffness matrices (layout in :func:`modes_from_fe_file`); the free–free
modes are computed from them.  The attachment points must then be nodes of that mesh.
"""
from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse as sp
from exudyn.FEM import FEMinterface

from .car_body_model import RIGID_TOL, CarBodyModes, damping_ratios

__all__ = ["read_fe_file", "modes_from_fe_file"]


def read_fe_file(path) -> tuple[np.ndarray, sp.csr_matrix, sp.csr_matrix]:
    """``(points, mass, stiffness)`` of an FE model file (layouts: :func:`modes_from_fe_file`)."""
    try:
        with np.load(path) as f:
            ours = "points" in f.files
    except (ValueError, OSError) as exc:
        raise ValueError(f"{path}: not an FE model file (.npz): {exc}") from None
    if not ours:                                        # a file of Exudyn's FEMinterface.SaveToFile
        fem = FEMinterface()
        try:
            fem.LoadFromFile(str(path))
            points = np.asarray(fem.nodes["Position"], dtype=float)
            M, K = fem.GetMassMatrix(sparse=True), fem.GetStiffnessMatrix(sparse=True)
        except Exception as exc:                        # the FEM tools raise various types for a foreign file
            raise ValueError(f"{path}: neither the 'points/mass/stiffness' layout nor an Exudyn FEMinterface file "
                             f"with position nodes and matrices: {type(exc).__name__}: {exc}") from None
        M, K = sp.csr_matrix(M), sp.csr_matrix(K)
        if points.ndim != 2 or points.shape[1] != 3 or M.shape != (3 * len(points),) * 2 or K.shape != M.shape:
            raise ValueError(f"{path}: expected position nodes (n, 3) and mass/stiffness (3n, 3n), got "
                             f"{points.shape}, {M.shape}, {K.shape}")
        return points, M, K
    try:
        with np.load(path) as f:
            points = np.asarray(f["points"], dtype=float)

            def matrix(name):
                if name in f.files:
                    return sp.csr_matrix(np.asarray(f[name], dtype=float))
                return sp.csr_matrix((f[f"{name}_data"], f[f"{name}_indices"], f[f"{name}_indptr"]),
                                     shape=(3 * len(points),) * 2)

            M, K = matrix("mass"), matrix("stiffness")
    except (KeyError, ValueError, OSError) as exc:
        raise ValueError(f"{path}: not an FE model file (points, mass, stiffness): {exc}") from None
    if points.ndim != 2 or points.shape[1] != 3 or M.shape != (3 * len(points),) * 2 or K.shape != M.shape:
        raise ValueError(f"{path}: expected points (n, 3) and mass/stiffness (3n, 3n), got {points.shape}, {M.shape}, "
                         f"{K.shape}")
    return points, M, K


def modes_from_fe_file(path, n_modes: int, damping_ratio=0.0) -> CarBodyModes:
    """Free–free modes of an external FE model of the car body: an ``.npz`` file with

    * ``points`` (n, 3) — node positions [m] relative to the car body's CG, body axes (x forward, y right, z down);
    * ``mass`` and ``stiffness`` (3n, 3n) — the matrices over the nodes' x, y, z displacements (node-major), dense
      arrays or the three arrays ``<name>_data``, ``<name>_indices``, ``<name>_indptr`` of a CSR matrix;

    or a file written by Exudyn's ``FEMinterface.SaveToFile`` (its ``Position`` nodes, mass and stiffness
    matrices): a model imported with Exudyn's FEM tools (e.g. from Abaqus or ANSYS exports, or NETGEN/NGsolve) and
    saved, its nodes in the car body's axes relative to its CG.

    The six rigid-body modes are discarded (the reference frame carries them); the ``n_modes`` lowest elastic modes
    are kept, mass-normalised.  Rotational DOFs of shells or beams must be condensed out (the FFRF mesh has
    position nodes only)."""
    points, M, K = read_fe_file(path)
    lam, vec = scipy.linalg.eigh(K.toarray(), M.toarray())
    rigid = lam < RIGID_TOL * lam[-1]
    lam, vec = lam[~rigid], vec[:, ~rigid]
    if n_modes > lam.size:
        raise ValueError(f"{path}: n_modes = {n_modes} but the model has {lam.size} elastic modes")
    lam, vec = lam[:n_modes], vec[:, :n_modes]
    vec = vec / np.sqrt(np.einsum("ij,ij->j", vec, M @ vec))
    return CarBodyModes(beam=None, omega_rad_s=np.sqrt(lam), shapes=vec,
                        damping_ratio=damping_ratios(damping_ratio, n_modes),
                        fe={"points": points, "mass": M, "stiffness": K, "shapes_points": vec},
                        kinds=("fe",) * n_modes)
