"""The 12-D action layout of the kitchen families, per arm, and its scaling.

One arm's action is 12 numbers in [-1, 1] (values outside are clipped):

| index | meaning |
|---|---|
| 0-2 | tool-site position delta (dx, dy, dz) in the robot base frame, times ``POS_STEP`` [m] |
| 3-5 | tool-site rotation delta (rotation vector, base frame), times ``ROT_STEP`` [rad] |
| 6 | gripper: -1 fully open, +1 closed |
| 7-9 | mobile base (inert for a fixed arm) |
| 10 | torso (inert for a fixed arm) |
| 11 | mode (inert for a fixed arm) |

The deltas move the controller's target pose (not the measured pose): a zero action holds the
target, so a resting arm does not drift. A scene of ``n`` arms takes ``12 n`` numbers, arm by arm.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "ACTION_SIZE",
    "ARM",
    "BASE",
    "GRIPPER",
    "MODE",
    "POS_STEP",
    "ROT_STEP",
    "TORSO",
    "gripper_action",
    "zero_action",
]

ACTION_SIZE = 12
"""Numbers per arm."""
ARM = slice(0, 6)
GRIPPER = 6
BASE = slice(7, 10)
TORSO = 10
MODE = 11
POS_STEP = 0.02
"""Target translation of a full-scale position action, per action [m] (0.4 m/s at 20 Hz)."""
ROT_STEP = 0.1
"""Target rotation of a full-scale rotation action, per action [rad]."""


def zero_action(n_arms: int = 1) -> np.ndarray:
    """A holding action (targets unchanged, grippers open) for ``n_arms`` arms."""
    a = np.zeros(ACTION_SIZE * n_arms)
    a[GRIPPER::ACTION_SIZE] = -1.0
    return a


def gripper_action(opening: float) -> float:
    """Gripper command in [-1, 1] for a finger opening fraction in [0, 1] (1 = fully open)."""
    return float(np.clip(1.0 - 2.0 * opening, -1.0, 1.0))
