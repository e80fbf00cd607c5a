"""CloseCabinet at L3: push the open door's front with the hand and walk the base around the hinge.

The robot starts beside the hinge, facing the wall; the open door's front faces it. The base backs
off sideways and turns to stand in front of a point of the door's front below and inside the handle,
the tool (pointing down, fingers closed) moves against that point, and the base turns as a rigid body
about the hinge axis (``Motion.orbit``) with the arm holding its pose on the base: the hand travels on
the door's circle, pushing the door shut, until the door is closed (``doors.close_door``).
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness import world
from rle_tasks.envs.kitchen.harness.geometry import quat_to_mat
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from .doors import close_door


def solve(robot: Robot, motion: Motion) -> bool:
    obs = robot.observe()
    f = world.target_fixture(obs)
    q = np.asarray(f["door_quat"])
    opened = 2.0 * float(np.arctan2(abs(q[3]), q[0]))  # door angle about the vertical hinge [rad]
    out = quat_to_mat(q) @ np.array([0.0, -1.0, 0.0])  # outward normal of the door's front
    return close_door(robot, motion, np.asarray(f["door_pos"]), np.asarray(f["sites"]["handle"]), out, opened)
