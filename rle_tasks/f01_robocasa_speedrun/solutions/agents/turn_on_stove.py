"""TurnOnStove at L3: grip the named knob from the front and twist it by 0.7 rad.

The tool approaches along +y (towards the wall) 15 cm in front of the knob, moves onto it, closes the
fingers on the knob's grip bar, turns about the knob's axis until the burner is on, then lets go and
backs away.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness.geometry import quat_mul
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

FORWARD = np.array([np.cos(-np.pi / 4), np.sin(-np.pi / 4), 0.0, 0.0])
"""Tool z along world +y (into the stove's front panel)."""
TWIST = 0.7
"""Knob turn commanded [rad] (on from 0.35)."""


def solve(robot: Robot, motion: Motion) -> bool:
    from rle_tasks.envs.kitchen.harness import world  # L3 only: the L2 program imports twist() from here

    obs = robot.observe()
    target = world.target(obs)
    knob = np.asarray(world.fixture(obs, target["fixture"])["sites"][target["burner"] + "_knob"])
    motion.open_gripper(steps=2)
    motion.move_tool(knob + [0.0, -0.15, 0.0], FORWARD, max_steps=200)
    return twist(robot, motion, knob)


def twist(robot: Robot, motion: Motion, knob: np.ndarray) -> bool:
    """From 15 cm in front of the knob at ``knob`` [m]: move onto it, grip, turn by ``TWIST``, let go,
    back away; returns the task's success."""
    motion.move_tool(knob, FORWARD, max_steps=100, speed=0.5)
    motion.close_gripper(steps=8)
    turn = np.array([np.cos(TWIST / 2), 0.0, np.sin(TWIST / 2), 0.0])
    motion.move_tool(robot.obs["ee_pos"], quat_mul(turn, FORWARD), max_steps=60, gripper=1.0)
    motion.open_gripper(steps=6)
    motion.move_tool_by([0.0, -0.12, 0.0], max_steps=40)
    return bool(robot.observe()["success"])
