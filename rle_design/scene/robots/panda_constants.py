"""Franka Emika Panda (robosuite 1.5.2 ``panda/robot.xml``) constants."""

from __future__ import annotations

import math

from rle_design.scene.robots.constants import RobotConstants

PANDA = RobotConstants(
    id="panda",
    joints=tuple(f"joint{i}" for i in range(1, 8)),
    home=(0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785),
    stowed=(0.0, math.pi / 16.0, 0.0, -math.pi / 2.0 - math.pi / 3.0, 0.0, math.pi - 0.2, math.pi / 4),
    actuators=tuple(f"torq_j{i}" for i in range(1, 8)),
    torque_limits=(80.0, 80.0, 80.0, 80.0, 80.0, 12.0, 12.0),
    source="home: Franka's ready pose; stowed: robosuite init_qpos; limits: robosuite motor ctrlrange",
)
