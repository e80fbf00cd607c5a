"""CloseCabinet at L1: the L2 program's push and orbit on an open door perceived from the agent views.

No camera model, no segmenter: the session's first call calibrates the agent views with the hand
(``calibrate_l1``). Below the counter top the fixtures' fronts are the largest vertical plane facing the
base; the open door is the largest vertical plane standing out of them towards the robot, the hinge
where the two meet, the handle the bar proud of the door near its free end (``perceive_l1.open_door``).
As at L2 the opening angle is not measured: the orbit turns by up to the door's full range and stops
when the task's success holds (``doors.close_door``).
"""

from __future__ import annotations

from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from .calibrate_l1 import calibration
from .doors import close_door
from .perceive_l1 import open_door

BELOW_COUNTER = (0.35, 0.85)
"""Heights searched for the fronts and the open door [m] (counter tops stand about 0.9 m high)."""
FULL_OPEN = 1.57
"""A door's full range [rad] (the task opens it to 0.90-1.00 of it)."""


def solve(robot: Robot, motion: Motion) -> bool:
    robot.observe()
    cal = calibration(robot, motion)
    robot.observe()
    est = open_door(robot, cal, BELOW_COUNTER)
    if est is None:
        return False
    return close_door(robot, motion, est.hinge, est.handle, est.out, FULL_OPEN)
