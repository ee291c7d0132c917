"""Rotation vector <-> rotation matrix of the Lie-group nodes (exudyn_wheelrail.multibody.rotations).

References, independent of the code under test: SciPy's ``Rotation`` (``from_rotvec``/``as_matrix``,
``from_matrix``/``as_rotvec``) and the round trip.  Tolerance: both are accurate to a few ulps of the angle; 1e-14
relative (or absolute below 1 rad) leaves a margin of ~50 ulps and still fails the old inverse, which lost half the
digits at small angles and took its near-π branch for 1e-8 < θ < 1e-6 (a 1e-7 rad rotation about x came back as
(1e-7, 1e-7, 1e-7)).
"""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from exudyn_wheelrail.multibody.rotations import rotation_from_vector, rotation_vector_from_matrix

ANGLES = [0.0, 1e-14, 1e-10, 1e-8, 3e-8, 1e-7, 1e-6, 1e-4, 0.01, 0.5, 1.0, 2.0, 2.7, 2.9, 3.1, np.pi - 1e-7]


@pytest.mark.parametrize("theta", ANGLES)
def test_matrix_and_vector_agree_with_scipy(theta):
    rng = np.random.default_rng(int(1e6 * theta) % 1000)
    R = np.zeros((3, 3))
    v = np.zeros(3)
    for _ in range(50):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        vec = theta * axis
        rotation_from_vector(*vec, R)
        np.testing.assert_allclose(R, Rotation.from_rotvec(vec).as_matrix(), rtol=0, atol=1e-15)
        rotation_vector_from_matrix(R, v, 0)
        tol = 1e-14 * max(theta, 1e-300)
        assert np.linalg.norm(v - vec) <= tol
        assert np.linalg.norm(v - Rotation.from_matrix(R).as_rotvec()) <= 2 * tol + 1e-300


def test_small_rotation_about_x_is_not_taken_for_a_half_turn():
    R = np.zeros((3, 3))
    v = np.zeros(3)
    rotation_from_vector(1e-7, 0.0, 0.0, R)
    rotation_vector_from_matrix(R, v, 0)
    np.testing.assert_allclose(v, [1e-7, 0.0, 0.0], rtol=0, atol=1e-21)
