"""``rle import-motion``: a retargeted G1 CSV (Unitree's LAFAN1 retargeting format) to a 50 Hz clip.

The CSV has no header, one frame per line at 30 fps: pelvis ``x y z`` [m], pelvis quaternion
``qx qy qz qw`` and the 29 joint angles [rad] in MJCF order. Root positions and joint angles are
resampled linearly, the orientation by spherical linear interpolation; velocities and body poses come
from ``Clip.from_qpos``. A foot counts as in stance while its sole is within ``STANCE_HEIGHT`` of the
floor.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from rle_design.errors import RleError

from .clip import CLIP_FPS, Clip
from .g1 import g1_model
from .g1_constants import G1
from .keying import foot_ground_height

__all__ = ["CSV_FPS", "import_motion", "read_csv", "resample"]

CSV_FPS = 30.0
"""Frame rate of the retargeted CSV files [Hz]."""
STANCE_HEIGHT = 0.02
"""A foot is marked in stance when its body is at most this high above its flat-on-floor height [m]."""
_COLS = 7 + G1.dof


def read_csv(path: Path | str) -> np.ndarray:
    """(N, 36) ``qpos`` from the CSV (quaternion reordered to w x y z and normalised).

    Raises:
        RleError: ``motion.csv`` for an unreadable file, a wrong column count, fewer than two frames,
            a non-finite value or a zero quaternion.
    """
    try:
        raw = np.loadtxt(path, delimiter=",", ndmin=2, dtype=np.float64)
    except (OSError, ValueError) as exc:
        raise RleError(f"{path}: not a numeric CSV: {exc}", code="motion.csv") from None
    if raw.shape[1] != _COLS:
        raise RleError(
            f"{path}: {raw.shape[1]} columns; expected {_COLS} (x y z qx qy qz qw + {G1.dof} joints)",
            code="motion.csv",
        )
    if raw.shape[0] < 2 or not np.isfinite(raw).all():
        raise RleError(f"{path}: needs at least two frames of finite numbers", code="motion.csv")
    quat = raw[:, [6, 3, 4, 5]]
    norm = np.linalg.norm(quat, axis=1, keepdims=True)
    if (norm < 1e-6).any():
        raise RleError(f"{path}: a root quaternion is zero", code="motion.csv")
    return np.concatenate([raw[:, :3], quat / norm, raw[:, 7:]], axis=1)


def _slerp(q0: np.ndarray, q1: np.ndarray, s: float) -> np.ndarray:
    if q0 @ q1 < 0:
        q1 = -q1
    dot = min(float(q0 @ q1), 1.0)
    theta = np.arccos(dot)
    if theta < 1e-8:
        return q0
    return (np.sin((1 - s) * theta) * q0 + np.sin(s * theta) * q1) / np.sin(theta)


def resample(qpos: np.ndarray, fps_in: float = CSV_FPS, fps_out: float = CLIP_FPS) -> np.ndarray:
    """``qpos`` frames at ``fps_out`` over the same duration (the last input frame is the last time)."""
    t_in = np.arange(len(qpos)) / fps_in
    t_out = np.arange(int(np.floor(t_in[-1] * fps_out + 1e-9)) + 1) / fps_out
    out = np.zeros((len(t_out), qpos.shape[1]))
    for c in list(range(3)) + list(range(7, qpos.shape[1])):
        out[:, c] = np.interp(t_out, t_in, qpos[:, c])
    for i, t in enumerate(t_out):
        k = min(int(t * fps_in + 1e-9), len(qpos) - 2)
        out[i, 3:7] = _slerp(qpos[k, 3:7], qpos[k + 1, 3:7], t * fps_in - k)
    return out


def import_motion(csv: Path | str, out: Path | str) -> Clip:
    """Convert ``csv`` to a clip and save it to ``out`` (``.npz``)."""
    model = g1_model()
    qpos = resample(read_csv(csv))
    data = mujoco.MjData(model)
    feet = [model.body(f).id for f in G1.feet]
    z0 = foot_ground_height(model)
    contacts = np.zeros((len(qpos), 2), dtype=bool)
    for i, q in enumerate(qpos):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        contacts[i] = data.xpos[feet, 2] < z0 + STANCE_HEIGHT
    clip = Clip.from_qpos(model, qpos, contacts)
    clip.save(out)
    return clip
