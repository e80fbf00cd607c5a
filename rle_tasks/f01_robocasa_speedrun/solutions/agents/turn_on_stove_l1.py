"""TurnOnStove at L1: the named burner's knob found on the stove's front panel from the agent views'
depth, then the L3 program's grip and twist.

No camera model, no segmenter: the session's first call calibrates the agent views with the hand
(``calibrate_l1``). The arm moves out of the views (the tool to either side in turn, ``ASIDE``) and the
knobs are the four groups of points standing proud of the panel ahead (``perceive_l1.knobs``; with one
end of the row hidden, ``complete`` adds it); the
burner's name gives its knob's place in the row (``KNOB_ORDER``, left to right as the robot sees it,
the stove's layout). Kitchen conventions used, as at L2: the stove faces world -y.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness.geometry import world_from_base
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from .calibrate_l1 import calibration
from .perceive_l1 import knobs, scene
from .turn_on_stove import FORWARD, twist
from .turn_on_stove_l2 import REACH_SIDE, STANDOFF, burner_of

KNOB_ORDER = ("rear left", "front left", "front right", "rear right")
"""The stove's knobs from left to right on its front panel."""
PANEL_BAND = (0.55, 0.9)
"""Heights searched for the stove's front and its knobs [m]."""
ASIDE = ((0.1, -0.25, 1.2), (0.1, 0.25, 1.2))
"""Tool positions in the base frame [m] that keep the arm out of one side of the views."""


def complete(found: list[np.ndarray], world_from_base: np.ndarray) -> list[np.ndarray]:
    """Four evenly spaced knobs from three seen (one end hidden): the row extended by one spacing at
    the end that centres it best on the base (the robot starts in front of the stove, +-4 cm)."""
    step = (found[-1] - found[0]) / 2.0
    rows = [[found[0] - step, *found], [*found, found[-1] + step]]
    side = world_from_base[:3, 1]

    def offset(row: list[np.ndarray]) -> float:
        return abs(float((np.mean(row, axis=0) - world_from_base[:3, 3]) @ side))

    return min(rows, key=offset)


def solve(robot: Robot, motion: Motion) -> bool:
    obs = robot.observe()
    cal = calibration(robot, motion)
    index = KNOB_ORDER.index(burner_of(obs["instruction"]))
    quat = np.asarray(robot.obs["ee_quat"])
    views = []
    for p in ASIDE:
        wb = world_from_base(robot.obs)
        motion.move_tool(wb[:3, :3] @ np.asarray(p) + wb[:3, 3], quat, max_steps=60)
        views.append(scene(robot, cal, clear=None))
    found = knobs(robot, cal, PANEL_BAND, views)
    if len(found) == len(KNOB_ORDER) - 1:
        found = complete(found, views[0].base)
    if len(found) != len(KNOB_ORDER):
        return False
    knob = found[index]
    o = robot.obs
    side = knob[0] - o["base_pos"][0]  # from the arm's rest line (the tool is still aside)
    if abs(side) > REACH_SIDE:  # the outer knobs: step the base sideways, facing the wall
        motion.drive_to(o["base_pos"][0] + side, o["base_pos"][1], np.pi / 2)
    motion.open_gripper(steps=2)
    motion.move_tool(knob + [0.0, -STANDOFF, 0.0], FORWARD, max_steps=200)
    return twist(robot, motion, knob)
