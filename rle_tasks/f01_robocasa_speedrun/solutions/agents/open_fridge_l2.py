"""OpenFridge at L2: perceive the fridge's door and handle, then the L3 program's grip and orbit.

No world state: ``perceive.door`` segments ``fridge door`` and ``fridge handle`` in the three cameras,
back-projects their depth into the world, fits the door's front plane (its outward normal faces the
cameras) and places the handle bar's centre in front of it and the hinge at the face's edge farther
from the handle. ``doors.open_door`` then grips the bar and walks the base around the hinge.
"""

from __future__ import annotations

from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from .doors import open_door
from .perceive import door

TRIES = 3
"""Observations tried (one action apart) before giving up on seeing the door and its handle."""


def solve(robot: Robot, motion: Motion) -> bool:
    robot.observe()
    for _ in range(TRIES):
        est = door(robot, "fridge door", "fridge handle")
        if est is not None:
            return open_door(robot, motion, est.hinge, est.handle, est.out)
        motion.wait(1)  # a new image: the segmenter may have missed an instance
    return False
