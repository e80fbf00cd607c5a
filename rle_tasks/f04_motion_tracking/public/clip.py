"""Reference clips at 50 Hz: joint and root trajectories plus forward-kinematics body poses.

A clip is stored as one compressed ``.npz`` (float32 arrays; keys as the fields of ``Clip``); its
body poses are the model's forward kinematics of its ``qpos`` (``Clip.from_qpos``), so a clip only
needs root poses and joint angles. Quaternions are ``w x y z``, positions in metres, world frame.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from pathlib import Path

import mujoco
import numpy as np

from rle_design.errors import RleError

from .g1_constants import G1

__all__ = ["CLIP_FPS", "Clip", "clip_qpos", "forward_kinematics"]

CLIP_FPS = 50.0
"""Frame rate of every clip [Hz] (the policy rate)."""


@dataclass(frozen=True)
class Clip:
    """One reference motion (T frames at ``fps``)."""

    fps: float
    joint_pos: np.ndarray
    """(T, 29) joint angles [rad], ``G1.joints`` order."""
    joint_vel: np.ndarray
    """(T, 29) joint rates [rad/s] (central differences)."""
    root_pos: np.ndarray
    """(T, 3) pelvis position [m]."""
    root_quat: np.ndarray
    """(T, 4) pelvis orientation (w x y z)."""
    body_pos_w: np.ndarray
    """(T, 14, 3) positions of ``G1.tracked_bodies`` [m]."""
    body_quat_w: np.ndarray
    """(T, 14, 4) orientations of the tracked bodies (w x y z)."""
    body_lin_vel_w: np.ndarray
    """(T, 14, 3) linear velocities of the tracked bodies' frames [m/s]."""
    body_ang_vel_w: np.ndarray
    """(T, 14, 3) angular velocities of the tracked bodies [rad/s]."""
    contacts: np.ndarray
    """(T, 2) stance flags of the left and right foot (generated clips; imported ones: foot height)."""

    @property
    def frames(self) -> int:
        return int(self.joint_pos.shape[0])

    @property
    def duration(self) -> float:
        """Clip length [s]."""
        return (self.frames - 1) / self.fps

    def qpos(self, frame: int) -> np.ndarray:
        """``qpos`` (36) of one frame."""
        return np.concatenate([self.root_pos[frame], self.root_quat[frame], self.joint_pos[frame]]).astype(
            np.float64
        )

    def save(self, path: Path | str) -> None:
        np.savez_compressed(
            path,
            **{f.name: np.asarray(getattr(self, f.name), dtype=np.float32) for f in fields(self)},
            body_names=np.array(G1.tracked_bodies),
        )

    @classmethod
    def load(cls, path: Path | str) -> Clip:
        """Read a clip written by ``save``.

        Raises:
            RleError: ``clip.format`` when a key is missing or the tracked bodies differ.
        """
        with np.load(path, allow_pickle=False) as z:
            missing = [f.name for f in fields(cls) if f.name not in z]
            if missing or "body_names" not in z:
                raise RleError(f"clip {path}: missing keys {missing or ['body_names']}", code="clip.format")
            if tuple(str(n) for n in z["body_names"]) != G1.tracked_bodies:
                raise RleError(
                    f"clip {path}: tracked bodies {list(z['body_names'])}; expected {list(G1.tracked_bodies)}",
                    code="clip.format",
                )
            values = {f.name: np.asarray(z[f.name], dtype=np.float64) for f in fields(cls)}
        values["fps"] = float(values["fps"])
        values["contacts"] = values["contacts"] > 0.5
        return cls(**values)

    @classmethod
    def from_qpos(
        cls, model: mujoco.MjModel, qpos: np.ndarray, contacts: np.ndarray, fps: float = CLIP_FPS
    ) -> Clip:
        """A clip from a (T, 36) ``qpos`` trajectory: velocities by central differences, bodies by FK."""
        qpos = np.asarray(qpos, dtype=np.float64)
        qvel = _differentiate(model, qpos, 1.0 / fps)
        pos, quat, lin, ang = forward_kinematics(model, qpos, qvel)
        return cls(
            fps=fps,
            joint_pos=qpos[:, 7:].copy(),
            joint_vel=qvel[:, 6:].copy(),
            root_pos=qpos[:, :3].copy(),
            root_quat=qpos[:, 3:7].copy(),
            body_pos_w=pos,
            body_quat_w=quat,
            body_lin_vel_w=lin,
            body_ang_vel_w=ang,
            contacts=np.asarray(contacts, dtype=bool),
        )


def clip_qpos(clip: Clip) -> np.ndarray:
    """(T, 36) ``qpos`` of a clip."""
    return np.concatenate([clip.root_pos, clip.root_quat, clip.joint_pos], axis=1)


def _differentiate(model: mujoco.MjModel, qpos: np.ndarray, dt: float) -> np.ndarray:
    n = len(qpos)
    qvel = np.zeros((n, model.nv))
    for t in range(n):
        a, b = max(t - 1, 0), min(t + 1, n - 1)
        if a != b:
            mujoco.mj_differentiatePos(model, qvel[t], (b - a) * dt, qpos[a], qpos[b])
    return qvel


def forward_kinematics(
    model: mujoco.MjModel, qpos: np.ndarray, qvel: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Positions, orientations, linear and angular velocities (world frame) of the tracked bodies."""
    ids = [model.body(b).id for b in G1.tracked_bodies]
    data = mujoco.MjData(model)
    n, k = len(qpos), len(ids)
    pos, quat = np.zeros((n, k, 3)), np.zeros((n, k, 4))
    lin, ang = np.zeros((n, k, 3)), np.zeros((n, k, 3))
    v6 = np.zeros(6)
    for t in range(n):
        data.qpos[:] = qpos[t]
        data.qvel[:] = 0.0 if qvel is None else qvel[t]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        mujoco.mj_comVel(model, data)
        pos[t], quat[t] = data.xpos[ids], data.xquat[ids]
        for j, b in enumerate(ids):
            mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_XBODY, b, v6, 0)
            ang[t, j], lin[t, j] = v6[:3], v6[3:]
    return pos, quat, lin, ang
