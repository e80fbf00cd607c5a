"""Panda forward and inverse kinematics from Franka's published modified-DH parameters (numpy only).

Frames: ``fk`` returns the flange pose in the robot base frame (``link0``); the electromagnet's pad
face is ``PAD_OFFSET`` along the flange's z axis.
"""

from __future__ import annotations

import numpy as np

# (a [m], d [m], alpha [rad]) of joints 1..7 and the flange (Craig's convention), Franka documentation.
DH = (
    (0.0, 0.333, 0.0),
    (0.0, 0.0, -np.pi / 2),
    (0.0, 0.316, np.pi / 2),
    (0.0825, 0.0, np.pi / 2),
    (-0.0825, 0.384, -np.pi / 2),
    (0.0, 0.0, np.pi / 2),
    (0.088, 0.0, np.pi / 2),
)
FLANGE_D = 0.107
Q_LO = np.array([-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973])
Q_HI = np.array([2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973])


def _mdh(a: float, d: float, alpha: float, theta: float) -> np.ndarray:
    ca, sa, ct, st = np.cos(alpha), np.sin(alpha), np.cos(theta), np.sin(theta)
    return np.array(
        [
            [ct, -st, 0.0, a],
            [st * ca, ct * ca, -sa, -d * sa],
            [st * sa, ct * sa, ca, d * ca],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


def fk(q: np.ndarray) -> np.ndarray:
    """4x4 flange pose in the base frame for joint angles ``q`` [rad]."""
    T = np.eye(4)
    for (a, d, alpha), th in zip(DH, q):
        T = T @ _mdh(a, d, alpha, th)
    return T @ _mdh(0.0, FLANGE_D, 0.0, 0.0)


def jacobian(q: np.ndarray, eps: float = 1e-6) -> np.ndarray:
    """6x7 numerical Jacobian of (flange position, flange z axis) with respect to ``q``."""
    T0 = fk(q)
    f0 = np.concatenate([T0[:3, 3], T0[:3, 2], T0[:3, 0]])
    J = np.zeros((9, 7))
    for i in range(7):
        dq = np.array(q, dtype=float)
        dq[i] += eps
        T = fk(dq)
        J[:, i] = (np.concatenate([T[:3, 3], T[:3, 2], T[:3, 0]]) - f0) / eps
    return J


def ik_down(p: np.ndarray, yaw: float, q0: np.ndarray, iters: int = 60) -> tuple[np.ndarray, float]:
    """Joint angles putting the flange at ``p`` (base frame) pointing straight down, rotated ``yaw``.

    Damped least squares from ``q0``; returns (q, position error [m]).
    """
    q = np.array(q0, dtype=float)
    x_axis = np.array([np.cos(yaw), np.sin(yaw), 0.0])
    target = np.concatenate([p, [0.0, 0.0, -1.0], x_axis])
    w = np.array([1, 1, 1, 0.3, 0.3, 0.3, 0.1, 0.1, 0.1])
    for _ in range(iters):
        T = fk(q)
        err = target - np.concatenate([T[:3, 3], T[:3, 2], T[:3, 0]])
        if np.linalg.norm(err[:3]) < 2e-4 and np.linalg.norm(err[3:6]) < 2e-3:
            break
        J = jacobian(q) * w[:, None]
        e = err * w
        dq = J.T @ np.linalg.solve(J @ J.T + 1e-4 * np.eye(9), e)
        q = np.clip(q + np.clip(dq, -0.3, 0.3), Q_LO, Q_HI)
    return q, float(np.linalg.norm(fk(q)[:3, 3] - p))
