"""PickPlaceMicrowaveToCounter at L3: take the object out of the open microwave, set it on the plate.

The microwave's cavity (0.26 m high) leaves no room above the object for a hand pointing down, so
the hand reaches in through the opening leaning ``PITCH`` forward, its fingers closing sideways
(turned by up to ``MAX_TURN`` to close across a box's narrow side), from a base standing 1 m from the
wall in front of the object. It pulls the object straight out (a round one then turns to hang from
a hand pointing down), lifts it (over the open door, hinged on the microwave's left, when the plate
lies beyond it), drives sideways to the plate with the arm holding still and the base's acceleration
limited, lowers the object onto the plate's centre and lets go. Butter lying lengthwise across the
opening is the weak case: a turn of the reach beyond ``MAX_TURN`` hits the cavity's walls.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness.geometry import quat_to_mat
from rle_tasks.envs.kitchen.harness.motion import Motion, down_quat
from rle_tasks.envs.kitchen.harness.robot import Robot

from .pick import EMPTY, FAR, ROUND, box, out_of_actions

PITCH = 0.9
"""Lean of the tool from straight down towards the wall while grasping [rad]."""
FIT = 0.062
"""Object length [m] above which the fingers turn to close across the object's narrow side."""
MAX_TURN = 0.6
"""Largest turn of the reach direction away from straight into the microwave [rad]."""
PALM = 0.026
"""Distance from the tool to the palm along the tool's axis [m]."""
BASE_Y = -0.95
"""Base position while grasping: distance from the wall [m] (closer, the arm folds onto itself)."""
OUTSIDE = 0.2
"""Tool distance in front of the microwave's front while entering and leaving [m]."""
DOOR_CLEARANCE = 0.04
"""Height of the held object's bottom above the open door's top edge [m]."""
PLACE_STANDOFF = 0.42
"""Distance from the base's centre to the plate's centre along y when placing [m]."""
RAMP = 0.1
"""Base acceleration limit while carrying (``Motion.drive_to``'s ``ramp``)."""
TORSO = 0.15
"""Torso height while grasping [m]."""
SET_DOWN = 0.005
"""Height of the object's bottom above the plate when the fingers open [m]."""
GRIPPER_MAX = 0.08
"""Finger opening of a fully open gripper [m] (an action's gripper value g opens it to
GRIPPER_MAX (1 - g) / 2)."""
GRASP_ACTIONS, LIFT_ACTIONS, DRIVE_ACTIONS, SET_ACTIONS = 360, 240, 310, 265
"""Most actions of a grasp attempt, of taking the object out (and turning a ball), of the drives to
the plate and of setting it down and letting go."""
FACING_WALL = np.pi / 2


def _reach(c: np.ndarray, half: np.ndarray, rot: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Grasp (tool position [m], quaternion) of an object whose box has world centre ``c``, half extents
    ``half`` in its own axes and rotation ``rot``: leaning ``PITCH`` into the microwave, closing across
    an object longer than ``FIT`` on its narrower horizontal side as far as a turn of the reach within
    ``MAX_TURN`` allows, the palm clear of the object."""
    half = np.asarray(half)
    up = int(np.argmax(np.abs(rot[2])))
    i, j = (k for k in range(3) if k != up)
    turn = 0.0
    if 2 * max(half[i], half[j]) > FIT and abs(half[i] - half[j]) >= 0.004:  # long: close across it
        a = rot[:, i] if half[i] < half[j] else rot[:, j]
        turn = float((np.arctan2(a[1], a[0]) + np.pi / 2) % np.pi - np.pi / 2)  # closing axis vs +x
        turn = float(np.clip(turn, -MAX_TURN, MAX_TURN))
    # the arm's home yaw (facing the wall); down_quat leans a negative pitch towards (sin yaw, -cos yaw):
    # into the microwave, turned by ``turn``
    q = down_quat(FACING_WALL + np.pi / 2 + turn, -PITCH)
    tz = quat_to_mat(q)[:, 2]
    # half length of the object along the tool axis: a ball's radius, an upright cylinder's support
    # (radius times the axis' horizontal part plus the half height times its vertical part), a box's
    local = np.abs(rot.T @ tz)
    if float(np.ptp(half)) < ROUND:
        extent = float(np.max(half))
    elif abs(half[i] - half[j]) < 0.004:
        extent = float(half[i] * np.hypot(local[i], local[j]) + half[up] * local[up])
    else:
        extent = float(local @ half)
    return c - max(0.0, extent - PALM + 0.004) * tz, q


class WorldView:
    """What the program knows of the scene, from the world state (L3); an L2 program passes its
    perceived counterpart to ``run``."""

    def __init__(self, robot: Robot) -> None:
        from rle_tasks.envs.kitchen.harness import world  # L3 only

        obs = robot.observe()
        self.robot = robot
        target = world.target(obs)
        mw = world.fixture(obs, target["fixture"])
        self.name, self.plate_name = target["object"], target["container"]
        self.front = float(mw["pos"][1] - mw["size"][1] / 2)
        """The microwave's front (y) [m]."""
        self.door_x = float(mw["pos"][0] - mw["size"][0] / 2)
        """The open door's x [m] (hinged on the microwave's left)."""
        self.top = float(mw["pos"][2] + mw["size"][2])
        """The microwave's top [m]."""

    def object(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(world centre [m], half extents in its own axes [m], rotation) of the object's box."""
        obs = self.robot.observe()
        c, _, rot = box(obs, self.name)
        return c, np.asarray(obs["objects"][self.name]["half"]), rot

    def plate(self) -> tuple[np.ndarray, float]:
        """(position [m], top height [m]) of the plate on the counter."""
        obs = self.robot.observe()
        pc, ph, _ = box(obs, self.plate_name)
        return np.asarray(obs["objects"][self.plate_name]["pos"]), float(pc[2] + ph[2])

    def grasped(self) -> None:
        """Called once the fingers hold the object."""

    def hold(self) -> tuple[np.ndarray, float]:
        """The held object's centre relative to the tool [m] and the tool's height above its bottom [m]."""
        return _hold(self.robot.observe(), self.name)


def solve(robot: Robot, motion: Motion) -> bool:
    return run(robot, motion, WorldView(robot))


def run(robot: Robot, motion: Motion, view) -> bool:
    """The program on the scene as ``view`` (a ``WorldView`` or a perceived one) tells it."""
    obs = robot.observe()
    front, door_x = view.front, view.door_x
    c, _, _ = view.object()
    motion.drive_to(float(c[0]) + 0.05, float(obs["base_pos"][1]), FACING_WALL, max_steps=120)
    motion.drive_to(float(c[0]) + 0.05, BASE_Y, FACING_WALL, max_steps=80)
    motion.set_torso(TORSO)
    held = False
    for _ in range(2):
        if out_of_actions(robot, GRASP_ACTIONS):
            break
        g, q = _reach(*view.object())
        tz = quat_to_mat(q)[:, 2]
        motion.move_tool([g[0], front - OUTSIDE, g[2] + 0.03], q, tol=0.02, max_steps=150, gripper=-1.0)
        motion.move_tool(g - 0.08 * tz, q, tol=0.01, max_steps=100, correct=True)
        motion.move_tool(g, q, tol=0.005, max_steps=60, speed=0.5, correct=True)
        motion.close_gripper(steps=10)
        if robot.observe()["gripper"] >= EMPTY:
            held = True
            view.grasped()
            break
        motion.move_tool(g - 0.1 * tz, q, tol=0.02, max_steps=40, gripper=-1.0)
    if not held or out_of_actions(robot, LIFT_ACTIONS):
        return False
    # out of the microwave; a round object turns to hang from a hand pointing down (the palm then sits
    # on top of it and cannot push it off the plate when the fingers open)
    tool = np.asarray(robot.observe()["ee_pos"]) + [0.0, 0.0, 0.02]
    motion.move_tool(tool, q, tol=0.01, max_steps=20, gripper=1.0, correct=True)
    tool[1] = front - OUTSIDE
    motion.move_tool(tool, q, tol=0.02, max_steps=60, speed=0.6, gripper=1.0, correct=True)
    obs = robot.observe()
    pp, plate_top = view.plate()
    offset, bottom = view.hold()
    carry = plate_top + bottom + 0.08
    if float(np.ptp(view.object()[1])) < ROUND:
        motion.move_tool([tool[0], tool[1], carry], q, tol=0.02, max_steps=40, gripper=1.0)
        q = down_quat(FACING_WALL + np.pi / 2)
        motion.move_tool(robot.observe()["ee_pos"], q, tol=0.02, max_steps=40, gripper=1.0)
        offset, bottom = view.hold()
        carry = plate_top + bottom + 0.08
    over_door = pp[0] < door_x + 0.05
    if over_door:
        carry = max(carry, view.top + DOOR_CLEARANCE + bottom)
    tool = np.asarray(obs["ee_pos"])
    motion.move_tool([tool[0], tool[1], carry], q, tol=0.02, max_steps=80, gripper=1.0)
    # stand in front of the plate with the object above its centre (the arm holds still on the base)
    obs = robot.observe()
    base_x = float(pp[0] - offset[0] - (obs["ee_pos"][0] - obs["base_pos"][0]))
    base_y = float(pp[1] - PLACE_STANDOFF)
    if out_of_actions(robot, DRIVE_ACTIONS):
        return False
    # sideways first (the object passes in front of the microwave), backed off past the door's edge
    # when it stands in the way, then up to the counter
    side_y = BASE_Y - 0.12 if over_door else float(obs["base_pos"][1])
    if over_door:
        motion.drive_to(float(obs["base_pos"][0]), side_y, FACING_WALL, max_steps=60, ramp=RAMP)
    motion.drive_to(base_x, side_y, FACING_WALL, max_steps=150, ramp=RAMP)
    motion.drive_to(base_x, base_y, FACING_WALL, max_steps=100, ramp=RAMP)
    if out_of_actions(robot, SET_ACTIONS):
        return False
    offset, bottom = view.hold()
    above = np.array([pp[0] - offset[0], pp[1] - offset[1], carry])
    motion.move_tool(above, q, tol=0.01, max_steps=100, gripper=1.0, correct=True)
    offset, bottom = view.hold()
    down = np.array([pp[0] - offset[0], pp[1] - offset[1], plate_top + bottom + SET_DOWN])
    motion.move_tool(down, q, tol=0.006, max_steps=60, speed=0.5, gripper=1.0, correct=True)
    # open a little (a wide-open hand flicks a ball away), back off along the tool's axis, then rise
    width = float(robot.observe()["gripper"]) + 0.015
    motion.gripper(1.0 - 2.0 * width / GRIPPER_MAX, steps=6)
    tz = quat_to_mat(q)[:, 2]
    motion.move_tool(down - 0.06 * tz, q, tol=0.02, max_steps=30)
    c = np.asarray(robot.observe()["ee_pos"]) + view.hold()[0]
    tool = np.asarray(robot.observe()["ee_pos"])
    motion.move_tool([tool[0], tool[1] - 0.05, c[2] + FAR], q, tol=0.02, max_steps=60, gripper=-1.0)
    motion.wait(5)
    return bool(robot.observe()["success"])


def _hold(obs: dict, name: str) -> tuple[np.ndarray, float]:
    """The held object's centre relative to the tool [m] and the tool's height above its bottom [m]."""
    c, h, _ = box(obs, name)
    offset = c - np.asarray(obs["ee_pos"])
    return offset, float(h[2] - offset[2])
