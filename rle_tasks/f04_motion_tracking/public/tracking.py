"""BeyondMimic's tracking quantities: the 160-D observation, the reward terms and the terminations.

Frames: the anchor is ``G1.anchor_body`` (torso). The reference is re-anchored to the robot as in
BeyondMimic: every reference body is moved so that the reference anchor lies at the robot anchor's
x, y (the reference anchor's own height kept) and is turned by the yaw between the two anchors.
Quaternions are ``w x y z``.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

__all__ = [
    "OBS_DIM",
    "REWARD_TERMS",
    "RewardTerm",
    "TERMINATION",
    "kernel",
    "observation",
    "quat_angle",
    "relative_reference",
]

OBS_DIM = 160
"""58 reference joint pos/vel + 3 anchor position error + 6 anchor orientation error + 3 + 3 IMU
velocities + 29 joint positions (minus default) + 29 joint velocities + 29 previous action."""


@dataclass(frozen=True)
class RewardTerm:
    """``weight * exp(-err^2 / sigma^2)``; ``err^2`` is a mean over tracked bodies where it says so."""

    name: str
    weight: float
    sigma: float


REWARD_TERMS = (
    RewardTerm("anchor_pos", 0.5, 0.3),
    RewardTerm("anchor_ori", 0.5, 0.4),
    RewardTerm("body_pos", 1.0, 0.3),
    RewardTerm("body_ori", 1.0, 0.4),
    RewardTerm("body_lin_vel", 1.0, 1.0),
    RewardTerm("body_ang_vel", 1.0, 3.14),
)
"""BeyondMimic's tracking terms (sigma in m, rad, m/s, rad/s)."""
ACTION_RATE_WEIGHT = -0.1
"""Times the squared norm of the action change per policy step."""
JOINT_LIMIT_WEIGHT = -10.0
"""Times the summed excursion [rad] past the soft joint limits (90 % of the range)."""
SOFT_LIMIT_FACTOR = 0.9

TERMINATION = {"anchor_height": 0.25, "anchor_gravity_z": 0.8, "end_effector_height": 0.25}
"""Episode ends when the anchor height error [m], the difference of the gravity direction's z component
in the anchor frame [1], or an ankle/wrist height error [m] exceeds its bound."""
END_EFFECTORS = (
    "left_ankle_roll_link",
    "right_ankle_roll_link",
    "left_wrist_yaw_link",
    "right_wrist_yaw_link",
)


def kernel(err_sq: float, sigma: float) -> float:
    """``exp(-err^2 / sigma^2)``: 1 at zero error, ``e^-1`` at one sigma."""
    return float(np.exp(-err_sq / sigma**2))


def _mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.zeros(4)
    mujoco.mju_mulQuat(out, a, b)
    return out


def _conj(q: np.ndarray) -> np.ndarray:
    return np.array([q[0], -q[1], -q[2], -q[3]])


def _rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    out = np.zeros(3)
    mujoco.mju_rotVecQuat(out, np.asarray(v, dtype=float), q)
    return out


def _mat(q: np.ndarray) -> np.ndarray:
    m = np.zeros(9)
    mujoco.mju_quat2Mat(m, q)
    return m.reshape(3, 3)


def yaw_only(q: np.ndarray) -> np.ndarray:
    """The yaw part of a rotation (heading of its x axis), as a quaternion."""
    m = _mat(q)
    yaw = np.arctan2(m[1, 0], m[0, 0])
    return np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])


def quat_angle(q: np.ndarray) -> float:
    """Rotation angle [rad] in [0, pi] of a unit quaternion."""
    return float(2.0 * np.arctan2(np.linalg.norm(q[1:]), abs(q[0])))


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products of (..., 4) quaternions (w x y z), broadcast."""
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ],
        axis=-1,
    )


def quat_angles(q: np.ndarray) -> np.ndarray:
    """Rotation angles [rad] in [0, pi] of (..., 4) unit quaternions."""
    return 2.0 * np.arctan2(np.linalg.norm(q[..., 1:], axis=-1), np.abs(q[..., 0]))


def relative_reference(
    ref_pos: np.ndarray,
    ref_quat: np.ndarray,
    ref_anchor: int,
    robot_anchor_pos: np.ndarray,
    robot_anchor_quat: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Reference body poses (B, 3), (B, 4) moved onto the robot's anchor (x, y and yaw; z kept)."""
    delta_pos = np.array(robot_anchor_pos, dtype=float)
    delta_pos[2] = ref_pos[ref_anchor, 2]
    delta = yaw_only(_mul(robot_anchor_quat, _conj(ref_quat[ref_anchor])))
    pos = delta_pos + (ref_pos - ref_pos[ref_anchor]) @ _mat(delta).T
    return pos, quat_mul(delta, ref_quat)


def observation(
    ref_joint_pos: np.ndarray,
    ref_joint_vel: np.ndarray,
    ref_anchor_pos: np.ndarray,
    ref_anchor_quat: np.ndarray,
    anchor_pos: np.ndarray,
    anchor_quat: np.ndarray,
    base_lin_vel: np.ndarray,
    base_ang_vel: np.ndarray,
    joint_pos_rel: np.ndarray,
    joint_vel: np.ndarray,
    last_action: np.ndarray,
) -> np.ndarray:
    """The 160-D observation (robot-side quantities as measured, noise included).

    Args:
        ref_joint_pos, ref_joint_vel: Reference joint angles [rad] and rates [rad/s] (29 each).
        ref_anchor_pos, ref_anchor_quat: Reference anchor pose, world frame.
        anchor_pos, anchor_quat: Robot anchor pose, world frame.
        base_lin_vel, base_ang_vel: Pelvis velocities in the pelvis frame [m/s, rad/s] (the IMU).
        joint_pos_rel: Joint angles minus the default pose [rad].
        joint_vel: Joint rates [rad/s].
        last_action: The previous action (29).
    """
    inv = _conj(anchor_quat)
    pos_b = _rotate(inv, ref_anchor_pos - anchor_pos)
    ori_b = _mat(_mul(inv, ref_anchor_quat))[:, :2].reshape(-1)
    return np.concatenate(
        [
            ref_joint_pos,
            ref_joint_vel,
            pos_b,
            ori_b,
            base_lin_vel,
            base_ang_vel,
            joint_pos_rel,
            joint_vel,
            last_action,
        ]
    )
