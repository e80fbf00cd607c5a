"""Pick-and-place skills shared by the pick-and-place programs (L3: world-frame object poses; an L2
program passes ``pick`` a ``locate`` function that perceives the object instead).

Objects are grasped from above (``down_quat``) with the fingers closing across the object's narrower
horizontal side, as deep as the palm lets them (``PALM`` below the object's top, kept clear of the
surface below), and put down by lowering them until their bottom is just above the new support
before the fingers open. Moves that must be precise use ``move_tool(correct=True)``, which servos out
the controller's steady-state error. A grasp is checked by the finger opening (``EMPTY``), not by
``world.grasped``, which sees contacts with the finger bodies only and misses the finger pads'.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rle_tasks.envs.kitchen.harness.geometry import quat_to_mat
from rle_tasks.envs.kitchen.harness.motion import Motion, down_quat
from rle_tasks.envs.kitchen.harness.robot import Robot

__all__ = [
    "PICK_ACTIONS",
    "PLACE_ACTIONS",
    "TRIAL_ACTIONS",
    "Held",
    "Seen",
    "box",
    "grasp_yaw",
    "out_of_actions",
    "pick",
    "place",
    "seen",
]

TRIAL_ACTIONS = 1000
"""Actions one evaluation trial allows."""
DT = 0.05
"""Duration of one action [s]."""
FINGER_CLEARANCE = 0.022
"""Least height of the tool (the finger pads' centre) above the support while grasping [m]."""
PALM = 0.016
"""Grasp depth below an object's top [m]: the palm, 26 mm above the tool, stays 1 cm clear of it (a
can or cup pressed into the palm wedges and stays in the open hand)."""
PALM_ROUND = 0.03
"""Grasp depth below a round object's top [m]: the fingers must reach its equator (the palm touches)."""
PICK_ACTIONS = 380
"""Most actions ``pick`` takes."""
PLACE_ACTIONS = 300
"""Most actions ``place`` takes."""
APPROACH = 0.10
"""Height of the pre-grasp pose above the grasp pose [m]."""
RELEASE_DROP = 0.015
"""Height of the object's bottom above its new support when the fingers open [m]."""
ROUND = 0.008
"""Spread of an object's half extents [m] below which it counts as round (apple, orange, lemon)."""
EMPTY = 0.01
"""Finger opening [m] below which the closed fingers hold nothing."""
FAR = 0.30
"""Tool height above the released object's centre at the end of a placement [m] (fingers > 0.25 m)."""


@dataclass(frozen=True)
class Held:
    """An object in the hand: ``below`` is the tool's height above the object's lowest point [m];
    ``name`` its world-state name (None for a perceived object)."""

    name: str | None
    below: float


@dataclass(frozen=True)
class Seen:
    """What a grasp needs of an object: its box centre [m], half extents along the world axes [m],
    the top-down grasp's yaw [rad] and depth below the top [m]."""

    centre: np.ndarray
    half: np.ndarray
    yaw: float
    depth: float


def seen(obs: dict, name: str) -> Seen:
    """``Seen`` of an object from the world state (L3)."""
    c, h, _ = box(obs, name)
    half = np.asarray(obs["objects"][name]["half"])
    return Seen(c, h, grasp_yaw(obs, name), PALM_ROUND if float(np.ptp(half)) < ROUND else PALM)


def box(obs: dict, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(world centre [m], half extents in the world axes [m], 3 x 3 rotation) of an object's box."""
    from rle_tasks.envs.kitchen.harness import world  # L3 only: L2 programs import this module

    o = obs["objects"][name]
    pos, quat = world.object_pose(obs, name)
    rot = quat_to_mat(quat)
    return pos + rot @ np.asarray(o["center"]), np.abs(rot) @ np.asarray(o["half"]), rot


def out_of_actions(robot: Robot, reserve: int) -> bool:
    """The episode (its simulated time counts its actions) has fewer than ``reserve`` actions left."""
    return round(float(robot.obs["time"]) / DT) + reserve >= TRIAL_ACTIONS


def grasp_yaw(obs: dict, name: str) -> float:
    """Yaw [rad] of a top-down grasp (``down_quat``) closing across the object's narrower horizontal
    side (of the two body axes nearest the horizontal, so a cup lying on its side is held across);
    of the two equivalent yaws the one nearest the arm's home yaw (base heading + pi/2), which keeps
    the wrist in the middle of its range."""
    half = np.asarray(obs["objects"][name]["half"])
    _, _, rot = box(obs, name)
    home = float(obs["base_yaw"]) + np.pi / 2
    i, j = (k for k in range(3) if k != int(np.argmax(np.abs(rot[2]))))
    if abs(half[i] - half[j]) < 0.004:
        axis = home  # round: any closing axis
    else:
        a = rot[:, i] if half[i] < half[j] else rot[:, j]
        axis = float(np.arctan2(a[1], a[0]))
    return float(home + ((axis - home + np.pi / 2) % np.pi - np.pi / 2))


def pick(
    robot: Robot,
    motion: Motion,
    name: str | None,
    support_z: float,
    lift: float = 0.12,
    via_y: float | None = None,
    locate: Callable[[], Seen | None] | None = None,
    via: np.ndarray | None = None,
) -> Held | None:
    """Grasp object ``name`` standing on a surface at ``support_z`` [m] from above and lift it by
    ``lift`` [m]; returns the hold, or None when the fingers closed on nothing or it stayed behind.
    With ``via_y`` [m] the hand first travels at the pre-grasp height to ``via_y`` in front of the
    object (past appliances on the counter, under the wall cabinets) and then slides in; ``via`` [m]
    is that waypoint (x, y) in any kitchen. ``locate`` (L2) perceives the object in the current
    observation (before the approach and again at the pre-grasp pose, whose view corrects the
    grasp); without it the world state of ``name`` is read. Takes at most ``PICK_ACTIONS`` actions."""

    def look() -> Seen | None:
        return seen(robot.observe(), name) if locate is None else locate()

    s = look()
    if s is None:
        return None
    q = down_quat(s.yaw)
    z = max(s.centre[2] + s.half[2] - s.depth, support_z + FINGER_CLEARANCE)
    c = s.centre
    if via_y is not None and via_y < c[1]:
        motion.move_tool([c[0], via_y, z + APPROACH], q, tol=0.03, max_steps=120, gripper=-1.0)
    if via is not None:
        motion.move_tool([via[0], via[1], z + APPROACH], q, tol=0.03, max_steps=120, gripper=-1.0)
    motion.move_tool([c[0], c[1], z + APPROACH], q, tol=0.01, max_steps=150, gripper=-1.0, correct=True)
    s = look() or s
    c = s.centre
    if locate is not None:  # the close view's grasp
        q = down_quat(s.yaw)
        z = max(s.centre[2] + s.half[2] - s.depth, support_z + FINGER_CLEARANCE)
        motion.move_tool([c[0], c[1], z + APPROACH], q, tol=0.01, max_steps=40, gripper=-1.0, correct=True)
    motion.move_tool([c[0], c[1], z], q, tol=0.005, max_steps=60, speed=0.6, correct=True)
    motion.close_gripper(steps=10)
    obs = robot.observe()
    if obs["gripper"] < EMPTY:
        return None
    if locate is not None:  # the object stands on the support; in the hand it is hidden
        held = Held(None, float(obs["ee_pos"][2] - support_z))
        motion.move_tool_by([0.0, 0.0, lift], tol=0.01, max_steps=40, gripper=1.0, correct=True)
        return held if robot.observe()["gripper"] >= EMPTY else None
    c, h, _ = box(obs, name)
    held = Held(name, float(obs["ee_pos"][2] - (c[2] - h[2])))
    motion.move_tool_by([0.0, 0.0, lift], tol=0.01, max_steps=40, gripper=1.0, correct=True)
    if box(robot.observe(), name)[0][2] < c[2] + lift / 2:
        return None
    return held


def place(robot: Robot, motion: Motion, held: Held, xy: np.ndarray, support_z: float, carry_z: float) -> None:
    """Carry the held object at tool height ``carry_z`` [m] to above ``xy`` [m], lower it onto the surface
    at ``support_z`` [m], let go and raise the tool ``FAR`` above it (at most ``PLACE_ACTIONS`` actions)."""
    q = robot.observe()["ee_quat"]
    motion.move_tool([xy[0], xy[1], carry_z], q, tol=0.015, max_steps=150, gripper=1.0, correct=True)
    z = support_z + held.below + RELEASE_DROP
    motion.move_tool([xy[0], xy[1], z], q, tol=0.006, max_steps=80, speed=0.6, gripper=1.0, correct=True)
    motion.open_gripper(steps=8)
    obs = robot.observe()
    # FAR above the released object's centre (a perceived one's: its bottom, below the tool)
    top = (box(obs, held.name)[0][2] if held.name else z - held.below) + FAR
    motion.move_tool([obs["ee_pos"][0], obs["ee_pos"][1], top], q, tol=0.02, max_steps=60, gripper=-1.0)
