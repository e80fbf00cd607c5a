"""OpenFridge at L3: grip the door's handle and walk the base around the hinge until the door is open.

The base first stands squarely in front of the handle (``doors.OPEN_STANDOFF`` back, facing the door);
the tool, pitched down by ``doors.PITCH`` so that the arm reaches it comfortably, closes its fingers on
the vertical handle bar. Then the base turns as a rigid body about the hinge axis (``Motion.orbit``)
with the arm holding its pose on the base: the handle travels on the door's circle and the door swings
open with the robot, which lets go once the door is past the success threshold (``doors.open_door``).
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness import world
from rle_tasks.envs.kitchen.harness.geometry import quat_to_mat
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from .doors import open_door


def solve(robot: Robot, motion: Motion) -> bool:
    obs = robot.observe()
    f = world.target_fixture(obs)
    out = quat_to_mat(f["door_quat"]) @ np.array([0.0, -1.0, 0.0])  # outward normal of the door's front
    return open_door(robot, motion, np.asarray(f["door_pos"]), np.asarray(f["sites"]["handle"]), out)
