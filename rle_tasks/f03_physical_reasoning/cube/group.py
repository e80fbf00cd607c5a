"""The 24 proper rotations of a cube: matrices, quaternions, products and the nearest lattice rotation.

Every orientation a cubie can take on the lattice, relative to the cube's core, is one of these 24
rotations. Rotations are indexed ``0..23`` (index 0 is the identity); products and inverses are
precomputed tables so that the move model never multiplies floating-point matrices.
"""

from __future__ import annotations

import itertools

import numpy as np


def _all_rotations() -> np.ndarray:
    mats = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1, -1), repeat=3):
            m = np.zeros((3, 3), dtype=np.int64)
            for row, col in enumerate(perm):
                m[row, col] = signs[row]
            if round(np.linalg.det(m)) == 1:
                mats.append(m)
    mats.sort(key=lambda m: (not np.array_equal(m, np.eye(3, dtype=np.int64)), tuple(m.ravel())))
    return np.stack(mats)


ROTATIONS: np.ndarray = _all_rotations()
"""``(24, 3, 3)`` integer rotation matrices; ``ROTATIONS[0]`` is the identity."""
IDENTITY = 0

_KEY = {m.tobytes(): i for i, m in enumerate(ROTATIONS)}
MUL: np.ndarray = np.array([[_KEY[(a @ b).tobytes()] for b in ROTATIONS] for a in ROTATIONS], dtype=np.int64)
"""``MUL[a, b]`` is the index of ``ROTATIONS[a] @ ROTATIONS[b]``."""
INV: np.ndarray = np.array([_KEY[m.T.copy().tobytes()] for m in ROTATIONS], dtype=np.int64)
"""``INV[a]`` is the index of the inverse (transpose) of ``ROTATIONS[a]``."""


def index_of(matrix: np.ndarray) -> int:
    """Index of an exact lattice rotation matrix (entries in {-1, 0, 1}).

    Raises:
        ValueError: The matrix is not one of the 24 cube rotations.
    """
    key = np.asarray(np.rint(matrix), dtype=np.int64)
    if not np.allclose(key, matrix, atol=1e-9) or key.tobytes() not in _KEY:
        raise ValueError(f"not a cube rotation: {np.asarray(matrix).tolist()}")
    return _KEY[key.tobytes()]


def quarter_turn(axis: np.ndarray, sign: int) -> int:
    """Index of the rotation by ``sign * 90`` degrees (right-hand rule) about a unit lattice axis."""
    a = np.asarray(axis, dtype=np.float64)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return index_of(np.eye(3) + sign * k + k @ k)  # Rodrigues at 90 degrees: sin = 1, 1 - cos = 1


def _matrix_to_quat(m: np.ndarray) -> np.ndarray:
    w = np.sqrt(max(0.0, 1.0 + np.trace(m))) / 2.0
    if w > 1e-6:
        return np.array(
            [w, (m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w), (m[1, 0] - m[0, 1]) / (4 * w)]
        )
    # 180-degree rotation: axis from the diagonal.
    axis = np.sqrt(np.maximum(0.0, (np.diag(m) + 1.0) / 2.0))
    i = int(np.argmax(axis))
    for j in range(3):
        if j != i:
            axis[j] = np.copysign(axis[j], m[i, j] + m[j, i])
    return np.array([0.0, *axis])


QUATS: np.ndarray = np.stack([_matrix_to_quat(m.astype(np.float64)) for m in ROTATIONS])
"""``(24, 4)`` unit quaternions ``(w, x, y, z)`` of ``ROTATIONS`` (MuJoCo's order)."""


def nearest(quats: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Nearest lattice rotation of each of a batch of unit quaternions.

    Args:
        quats: ``(n, 4)`` unit quaternions ``(w, x, y, z)``.

    Returns:
        ``(index, angle)``: ``(n,)`` lattice rotation indices and ``(n,)`` angles [rad] between each
        quaternion and its nearest lattice rotation (0 on the lattice, at most about 62.8 degrees).
    """
    q = np.asarray(quats, dtype=np.float64).reshape(-1, 4)
    dots = np.abs(q @ QUATS.T)
    idx = np.argmax(dots, axis=1)
    cos_half = np.clip(dots[np.arange(len(q)), idx], 0.0, 1.0)
    return idx, 2.0 * np.arccos(cos_half)
