"""CloseCabinet at L2: perceive the open door and its handle, then the L3 program's push and orbit.

No world state: ``perceive.door`` segments ``cabinet door`` and ``cabinet handle`` in the three
cameras; of the doors seen, the target is the one nearest the base along its heading (the robot
starts facing the cabinet, beside the open door, which stands out towards it from the closed fronts). Its front plane, handle and hinge (the face's edge farther from the handle) come from the
back-projected depth. The door's opening angle is not measured: the orbit is asked to turn by the
door's full range and stops when the task's success holds (``doors.close_door``).
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from .doors import close_door
from .perceive import Cloud, door

FULL_OPEN = 1.57
"""A door's full range [rad] (the task opens it to 0.90-1.00 of it)."""
TRIES = 3
"""Observations tried (one action apart) before giving up on seeing the door and its handle."""


def solve(robot: Robot, motion: Motion) -> bool:
    obs = robot.observe()
    base = np.asarray(obs["base_pos"][:2])
    ahead = np.array([np.cos(obs["base_yaw"]), np.sin(obs["base_yaw"])])

    def nearest(found: list[Cloud]) -> Cloud:
        return min(found, key=lambda c: float(np.dot(c.centre[:2] - base, ahead)))

    for _ in range(TRIES):
        est = door(robot, "cabinet door", "cabinet handle", choose=nearest)
        if est is not None:
            return close_door(robot, motion, est.hinge, est.handle, est.out, FULL_OPEN)
        motion.wait(1)  # a new image: the segmenter may have missed an instance
    return False
