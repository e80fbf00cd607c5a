"""Camera geometry, frame transforms and point clouds.

Conventions: quaternions are (w, x, y, z); the base frame has x forward, y left, z up, its origin on
the floor under the base (``obs["base_pos"]``, heading ``obs["base_yaw"]``); cameras follow OpenCV
(+z forward, +y down), ``obs["cameras"][name]`` gives ``K`` (3 x 3 [px]) and ``world_from_camera``
(4 x 4 [m]); ``depth`` is metric planar depth [m].
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = [
    "base_from_world",
    "deproject",
    "mat_to_quat",
    "pose_matrix",
    "project",
    "quat_conj",
    "quat_mul",
    "quat_to_mat",
    "rotvec",
    "rotz",
    "world_from_base",
    "world_points",
]


def rotz(yaw: float) -> np.ndarray:
    """3 x 3 rotation about z by ``yaw`` [rad]."""
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product a b of (w, x, y, z) quaternions."""
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )


def quat_conj(q: np.ndarray) -> np.ndarray:
    """Conjugate (inverse of a unit quaternion)."""
    return np.array([q[0], -q[1], -q[2], -q[3]])


def quat_to_mat(q: np.ndarray) -> np.ndarray:
    """3 x 3 rotation of a unit quaternion (w, x, y, z)."""
    w, x, y, z = np.asarray(q, float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def mat_to_quat(m: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z, w >= 0) of a 3 x 3 rotation."""
    m = np.asarray(m, float)
    t = np.trace(m)
    if t > 0:
        s = 2.0 * np.sqrt(1.0 + t)
        q = np.array([0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s])
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = np.zeros(4)
        q[0] = (m[k, j] - m[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (m[j, i] + m[i, j]) / s
        q[1 + k] = (m[k, i] + m[i, k]) / s
    q /= np.linalg.norm(q)
    return -q if q[0] < 0 else q


def rotvec(q: np.ndarray) -> np.ndarray:
    """Rotation vector [rad] of a unit quaternion (the shorter way round)."""
    q = np.asarray(q, float) / np.linalg.norm(q)
    if q[0] < 0:
        q = -q
    s = np.linalg.norm(q[1:])
    if s < 1e-12:
        return 2.0 * q[1:]
    return 2.0 * np.arctan2(s, q[0]) * q[1:] / s


def pose_matrix(pos: np.ndarray, quat: np.ndarray) -> np.ndarray:
    """4 x 4 homogeneous transform of a position [m] and quaternion."""
    t = np.eye(4)
    t[:3, :3] = quat_to_mat(quat)
    t[:3, 3] = pos
    return t


def world_from_base(obs: dict[str, Any]) -> np.ndarray:
    """4 x 4 pose of the robot base in the world."""
    t = np.eye(4)
    t[:3, :3] = rotz(obs["base_yaw"])
    t[:3, 3] = obs["base_pos"]
    return t


def base_from_world(obs: dict[str, Any]) -> np.ndarray:
    """4 x 4 transform from world to base coordinates."""
    return np.linalg.inv(world_from_base(obs))


def deproject(
    depth: np.ndarray, K: np.ndarray, mask: np.ndarray | None = None, max_depth: float = 5.0
) -> np.ndarray:
    """(N, 3) points in OpenCV camera coordinates [m] of the pixels with a valid depth (and in ``mask``)."""
    h, w = depth.shape
    v, u = np.mgrid[0:h, 0:w]
    ok = np.isfinite(depth) & (depth > 0) & (depth < max_depth)
    if mask is not None:
        ok &= mask
    z = depth[ok]
    x = (u[ok] - K[0, 2]) * z / K[0, 0]
    y = (v[ok] - K[1, 2]) * z / K[1, 1]
    return np.column_stack([x, y, z])


def world_points(obs: dict[str, Any], camera: str, mask: np.ndarray | None = None) -> np.ndarray:
    """(N, 3) world points [m] seen by ``camera`` (optionally only inside ``mask``)."""
    cam = obs["cameras"][camera]
    pts = deproject(np.asarray(obs["depth"][camera]), np.asarray(cam["K"]), mask)
    t = np.asarray(cam["world_from_camera"])
    return pts @ t[:3, :3].T + t[:3, 3]


def project(points_world: np.ndarray, K: np.ndarray, world_from_camera: np.ndarray) -> np.ndarray:
    """(N, 2) pixel coordinates (u, v) of world points (behind-camera points give NaN)."""
    t = np.linalg.inv(world_from_camera)
    p = np.asarray(points_world, float) @ t[:3, :3].T + t[:3, 3]
    z = np.where(p[:, 2] > 1e-9, p[:, 2], np.nan)
    return np.column_stack([K[0, 0] * p[:, 0] / z + K[0, 2], K[1, 1] * p[:, 1] / z + K[1, 2]])
