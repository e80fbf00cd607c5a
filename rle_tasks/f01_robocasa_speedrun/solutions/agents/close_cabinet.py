"""CloseCabinet at L3: push the open door's front with the hand and walk the base around the hinge.

The robot starts beside the hinge, facing the wall; the open door's front faces it. The base backs
off sideways and turns to stand ``STANDOFF`` in front of a point of the door's front below and inside
the handle, the tool (pointing down, fingers closed) moves against that point, and the base turns as
a rigid body about the hinge axis (``Motion.orbit``) with the arm holding its pose on the base: the
hand travels on the door's circle, pushing the door shut, until the door is closed.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness import world
from rle_tasks.envs.kitchen.harness.geometry import quat_to_mat
from rle_tasks.envs.kitchen.harness.motion import Motion, down_quat
from rle_tasks.envs.kitchen.harness.robot import Robot

INSIDE = 0.14
"""Push this far closer to the hinge than the handle, clear of it [m]."""
PUSH_Z = 0.55
"""Height of the fingertips on the door [m] (the handle bar starts about 0.65 m up)."""
CLEAR = 0.03
"""Tool centre in front of the door's front face at contact (the fingers are about 0.02 m thick) [m]."""
HANDLE_PROUD = 0.035
"""The handle bar's axis stands this far in front of the door's front face [m]."""
APPROACH = 0.1
"""Pre-contact distance out from the door [m]."""
STANDOFF = 0.55
"""Horizontal distance from the arm's root to the contact point [m]."""
MIN_SIDE = 0.42
"""Least distance of the base's centre line from the hinge along the open door (about the distance
from the counter's front), keeping the base (0.25 m half width) clear of a deeper neighbour on the
hinge side (a fridge's door stands 0.1 m proud of the cabinet's) [m]."""
OVERTURN = 0.15
"""Turn past the door's measured angle, taking up the gap to the door and pressing it shut [rad]."""


def solve(robot: Robot, motion: Motion) -> bool:
    obs = robot.observe()
    f = world.target_fixture(obs)
    hinge = np.asarray(f["door_pos"])
    handle = np.asarray(f["sites"]["handle"])
    q = np.asarray(f["door_quat"])
    opened = 2.0 * float(np.arctan2(abs(q[3]), q[0]))  # door angle about the vertical hinge [rad]
    out = quat_to_mat(q) @ np.array([0.0, -1.0, 0.0])  # outward normal of the door's front
    along = handle - hinge - np.dot(handle - hinge, out) * out  # hinge -> handle in the door's plane
    along[2] = 0.0
    reach = float(np.linalg.norm(along))  # handle's distance from the hinge axis
    along /= reach
    contact = handle + (CLEAR - HANDLE_PROUD) * out - INSIDE * along
    contact[2] = PUSH_Z
    stand = hinge[:2] + max(reach - INSIDE, MIN_SIDE) * along[:2] + (STANDOFF + CLEAR) * out[:2]
    heading = float(np.arctan2(-out[1], -out[0]))  # facing the door
    motion.drive_to(stand[0], stand[1], obs["base_yaw"], tol=0.05, max_steps=60)  # back off, then turn
    motion.drive_to(stand[0], stand[1], heading, tol=0.03, yaw_tol=0.06, max_steps=80)
    tool = down_quat(heading)  # fingers closing along the door's normal: a thin hand against the door
    motion.close_gripper(steps=1)
    motion.move_tool(contact + APPROACH * out, tool, max_steps=80, tol=0.02)
    motion.move_tool(contact, tool, max_steps=30, speed=0.5, tol=0.01)
    # closing turns counter-clockwise (seen from above) for a left hinge
    sign = 1.0 if f["hinge_left"] else -1.0
    motion.orbit(hinge, sign * (opened + OVERTURN), stop=lambda o: bool(o["success"]))
    return bool(robot.observe()["success"])
