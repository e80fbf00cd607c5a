"""OpenFridge at L1: the L2 program's grip and orbit on a door perceived from the agent views' depth.

No camera model, no segmenter: the session's first call calibrates the agent views with the hand
(``calibrate_l1``, once per session). The fridge door is the largest vertical plane above the counter
in front of the robot, its handle the bar standing proud of it; the base turns towards the hinge side
for the door's far edge (``perceive_l1.door``). ``doors.open_door`` then grips the bar and walks the
base around the hinge.
"""

from __future__ import annotations

from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from .calibrate_l1 import calibration
from .doors import open_door
from .perceive_l1 import door

ABOVE_COUNTER = (1.0, 1.7)
"""Heights searched for the door's plane [m] (counter tops stand about 0.9 m high)."""


def solve(robot: Robot, motion: Motion) -> bool:
    robot.observe()
    cal = calibration(robot, motion)
    est = door(robot, cal, ABOVE_COUNTER, motion)
    if est is None:
        return False
    return open_door(robot, motion, est.hinge, est.handle, est.out)
