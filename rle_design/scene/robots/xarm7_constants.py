"""UFACTORY xArm7 (robosuite 1.5.2 ``xarm7/robot.xml``) constants."""

from __future__ import annotations

import math

from rle_design.scene.robots.constants import RobotConstants

XARM7 = RobotConstants(
    id="xarm7",
    joints=tuple(f"joint{i}" for i in range(1, 8)),
    home=(0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0),
    stowed=(0.0, 0.0, 0.0, 0.39 * math.pi, 0.0, 0.39 * math.pi, 0.0),
    actuators=tuple(f"torq_j{i}" for i in range(1, 8)),
    torque_limits=(80.0,) * 7,
    source="home: elbow and wrist bent 1 rad; stowed: robosuite init_qpos; limits: robosuite motor ctrlrange",
)
