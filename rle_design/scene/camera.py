"""A fixed camera added to a body, placed by position and orientation or aimed at a point."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.errors import ConfigError
from rle_design.scene.config import SpecEdit, check_vector
from rle_design.scene.elements import find_body

__all__ = ["CameraConfig", "look_at_quat"]


def look_at_quat(
    pos: np.ndarray, target: np.ndarray, up: tuple[float, float, float] = (0.0, 0.0, 1.0)
) -> np.ndarray:
    """Orientation (w, x, y, z) of a MuJoCo camera at ``pos`` looking at ``target`` [m].

    MuJoCo cameras look along their -z axis with +y up; ``up`` picks the roll (the world z unless
    the view is vertical, then the world y).

    Raises:
        ConfigError: ``target`` coincides with ``pos``.
    """
    forward = np.asarray(target, float) - np.asarray(pos, float)
    dist = float(np.linalg.norm(forward))
    if dist < 1e-12:
        raise ConfigError("camera target coincides with the camera position")
    forward /= dist
    right = np.cross(forward, np.asarray(up, float))
    if np.linalg.norm(right) < 1e-9:
        right = np.cross(forward, np.array([0.0, 1.0, 0.0]))
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    rot = np.column_stack([right, true_up, -forward])
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, rot.reshape(-1))
    return quat


@dataclass(frozen=True)
class CameraConfig(SpecEdit):
    """A camera on a body; ``look_at`` (when given) overrides ``quat``."""

    name: str
    """Camera name (must not exist yet)."""
    body: str = "world"
    """Body that carries the camera."""
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Position in the body frame [m]."""
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    """Orientation in the body frame (w, x, y, z); the camera looks along its -z axis."""
    look_at: tuple[float, float, float] | None = None
    """Point in the body frame the camera aims at [m]; None: use ``quat``."""
    fovy_deg: float = 45.0
    """Vertical field of view [deg], in (0, 180)."""

    def validate(self) -> None:
        if not self.name:
            raise ConfigError("CameraConfig.name must not be empty")
        check_vector(self, "pos", self.pos, 3)
        check_vector(self, "quat", self.quat, 4)
        if not any(self.quat):
            raise ConfigError("CameraConfig.quat must not be the zero quaternion")
        if self.look_at is not None:
            check_vector(self, "look_at", self.look_at, 3)
            if np.allclose(self.look_at, self.pos):
                raise ConfigError(f"CameraConfig.look_at must differ from pos, both are {tuple(self.pos)}")
        if not 0.0 < self.fovy_deg < 180.0:
            raise ConfigError(f"CameraConfig.fovy_deg must be in (0, 180), got {self.fovy_deg}")

    def _edit(self, spec: mujoco.MjSpec) -> None:
        body = find_body(spec, self.body)
        if spec.camera(self.name) is not None:
            raise ConfigError(f"camera '{self.name}' already exists", code="scene.duplicate_camera")
        quat = self.quat if self.look_at is None else look_at_quat(np.array(self.pos), np.array(self.look_at))
        body.add_camera(name=self.name, pos=list(self.pos), quat=list(quat), fovy=self.fovy_deg)
