"""OpenFridge at L3: grip the door's handle and walk the base around the hinge until the door is open.

The base first stands squarely in front of the handle (``STANDOFF`` back, facing the door); the tool,
pitched down by ``PITCH`` so that the arm reaches it comfortably, closes its fingers on the vertical
handle bar. Then the base turns as a rigid body about the hinge axis (``Motion.orbit``) with the arm
holding its pose on the base: the handle travels on the door's circle and the door swings open with
the robot, which lets go once the door is past the success threshold.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness import world
from rle_tasks.envs.kitchen.harness.geometry import quat_to_mat
from rle_tasks.envs.kitchen.harness.motion import Motion, facing_quat
from rle_tasks.envs.kitchen.harness.robot import Robot

STANDOFF = 0.6
"""Horizontal distance from the arm's root to the handle for the grasp [m]."""
PITCH = np.radians(60.0)
"""Tilt of the tool below the horizontal for the grasp [rad]."""
APPROACH = 0.1
"""Pre-grasp distance back along the tool axis [m]."""
SWING = 1.52
"""Turn of the orbit about the hinge [rad] (success at 0.90 x 1.57 = 1.413 rad)."""


def solve(robot: Robot, motion: Motion) -> bool:
    obs = robot.observe()
    f = world.target_fixture(obs)
    hinge = np.asarray(f["door_pos"])
    handle = np.asarray(f["sites"]["handle"])
    out = quat_to_mat(f["door_quat"]) @ np.array([0.0, -1.0, 0.0])  # outward normal of the door's front
    heading = float(np.arctan2(-out[1], -out[0]))  # facing the door
    grip = facing_quat(heading, PITCH)
    axis = quat_to_mat(grip)[:, 2]
    stand = handle[:2] + STANDOFF * out[:2]
    motion.drive_to(stand[0], stand[1], heading, max_steps=120)
    motion.move_tool(handle - APPROACH * axis, grip, max_steps=100, tol=0.02)
    motion.move_tool(handle, grip, max_steps=30, speed=0.5, tol=0.012)
    motion.close_gripper(steps=6)
    sign = -1.0 if f["hinge_left"] else 1.0  # opening turns clockwise (seen from above) for a left hinge
    motion.orbit(hinge, sign * SWING, stop=lambda o: bool(o["success"]))
    motion.open_gripper(steps=4)
    return bool(robot.observe()["success"])
