"""The robot and sensor API of the kitchen.

    from client import connect
    from agent_harness.robot import Robot

    with connect() as client:
        robot = Robot(client)
        obs = robot.reset()                      # one charged step; a pretrain kitchen
        obs = robot.act(arm=[0, 0, 1, 0, 0, 0])  # one charged step: tool up at full speed for 50 ms
        obs = robot.act(base=[1, 0, 0], mode="base")

Actions are 12 numbers in [-1, 1] at 20 Hz: arm 0-5 (tool delta pose in the base frame: x 0.02 m and
x 0.1 rad per action), gripper 6 (-1 open, +1 closed), base 7-9 (forward, left [x 0.5 m/s], yaw
[x 1 rad/s]; only in base mode), torso 10 (x 0.01 m per action), mode 11 (> 0 base mode: the arm holds;
otherwise arm mode: the base stands). Observations: ``time``, ``base_pos``, ``base_yaw``, ``torso``,
``q``, ``dq``, ``ee_pos``/``ee_quat`` (world), ``ee_pos_base``/``ee_quat_base`` (base frame),
``target_pos_base``/``target_quat_base`` (the arm controller's target, base frame), ``gripper`` (opening [m]), ``rgb`` and ``depth`` per camera (128 x 128), ``instruction``, ``success``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["ACTION_SIZE", "CAMERAS", "Robot", "action"]

ACTION_SIZE = 12
CAMERAS = ("robot/agentview_left", "robot/agentview_right", "robot/arm/eye_in_hand")
"""The three cameras: left and right agent views on the base, eye in hand."""
POS_STEP = 0.02
"""Tool translation of a full-scale arm action [m]."""
ROT_STEP = 0.1
"""Tool rotation of a full-scale arm action [rad]."""
BASE_SPEED = 0.5
"""Base speed of a full-scale base action [m/s]."""
YAW_SPEED = 1.0
"""Base turn rate of a full-scale base action [rad/s]."""
TORSO_STEP = 0.01
"""Torso travel of a full-scale torso action [m]."""


def action(
    arm: Any = (0, 0, 0, 0, 0, 0),
    gripper: float = -1.0,
    base: Any = (0, 0, 0),
    torso: float = 0.0,
    mode: str = "arm",
) -> np.ndarray:
    """The 12-D action (values clipped to [-1, 1]); ``mode`` is ``"arm"`` or ``"base"``."""
    if mode not in ("arm", "base"):
        raise ValueError(f"mode must be 'arm' or 'base', got {mode!r}")
    a = np.zeros(ACTION_SIZE)
    a[0:6] = np.asarray(arm, dtype=float)
    a[6] = gripper
    a[7:10] = np.asarray(base, dtype=float)
    a[10] = torso
    a[11] = 1.0 if mode == "base" else -1.0
    return np.clip(a, -1.0, 1.0)


class Robot:
    """The metered kitchen session seen as a robot.

    Args:
        client: A ``LedgerClient`` (``client.connect()`` in the workspace).

    Attributes:
        obs: The last observation.
        gripper: The gripper command held by ``act`` when none is given (-1 open, +1 closed).
    """

    def __init__(self, client: Any) -> None:
        self.client = client
        self.obs: dict[str, Any] = {}
        self.gripper = -1.0

    def observe(self) -> dict[str, Any]:
        """The current observation (free)."""
        self.obs = self.client.observe()
        return self.obs

    def reset(self, kitchen: int | None = None, seed: int | None = None) -> dict[str, Any]:
        """Start an episode in a pretrain kitchen (one charged step): by default the next one; ``kitchen``
        picks one of the 50 layouts and ``seed`` its episode (objects, spawn). In the evaluation phase,
        advance to the next trial (no options)."""
        options = {k: v for k, v in (("kitchen", kitchen), ("seed", seed)) if v is not None}
        self.gripper = -1.0
        self.obs = self.client.reset(**options)
        return self.obs

    def start_evaluation(self) -> dict[str, Any]:
        """Enter the terminal evaluation phase and start trial 0 (no way back to development)."""
        self.gripper = -1.0
        self.obs = self.client.reset(evaluation=True)
        return self.obs

    def act(
        self,
        arm: Any = (0, 0, 0, 0, 0, 0),
        gripper: float | None = None,
        base: Any = (0, 0, 0),
        torso: float = 0.0,
        mode: str = "arm",
    ) -> dict[str, Any]:
        """Execute one action (one charged step); the gripper keeps its last command when not given."""
        if gripper is not None:
            self.gripper = float(gripper)
        self.obs = self.client.step(action(arm, self.gripper, base, torso, mode))
        return self.obs

    def info(self) -> dict[str, Any]:
        """Budget, phase and trials (free)."""
        return self.client.info()
