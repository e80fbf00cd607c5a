"""Door motions shared by the door programs of every level: they take the door's geometry as numbers
(the L3 programs read it from the world state, the L2 programs perceive it) and import no world state.

Geometry: ``hinge`` a point of the vertical hinge axis [m], ``handle`` the handle bar's centre [m],
``out`` the outward unit normal of the door's front face (horizontal). Which way the door swings
follows from these: opening pulls the handle along ``out``, closing pushes it against ``out``.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness.geometry import quat_to_mat
from rle_tasks.envs.kitchen.harness.motion import Motion, down_quat, facing_quat
from rle_tasks.envs.kitchen.harness.robot import Robot

__all__ = ["close_door", "open_door", "swing_sign"]

# opening (OpenFridge)
OPEN_STANDOFF = 0.6
"""Horizontal distance from the arm's root to the handle for the grasp [m]."""
PITCH = np.radians(60.0)
"""Tilt of the tool below the horizontal for the grasp [rad]."""
APPROACH = 0.1
"""Pre-grasp / pre-contact distance [m]."""
SWING = 1.52
"""Turn of the orbit about the hinge [rad] (success at 0.90 x 1.57 = 1.413 rad)."""
# closing (CloseCabinet)
INSIDE = 0.14
"""Push this far closer to the hinge than the handle, clear of it [m]."""
PUSH_Z = 0.55
"""Height of the fingertips on the door [m] (the handle bar starts about 0.65 m up)."""
CLEAR = 0.03
"""Tool centre in front of the door's front face at contact (the fingers are about 0.02 m thick) [m]."""
HANDLE_PROUD = 0.035
"""The handle bar's axis stands this far in front of the door's front face [m]."""
CLOSE_STANDOFF = 0.55
"""Horizontal distance from the arm's root to the contact point [m]."""
MIN_SIDE = 0.42
"""Least distance of the base's centre line from the hinge along the open door (about the distance
from the counter's front), keeping the base (0.25 m half width) clear of a deeper neighbour on the
hinge side (a fridge's door stands 0.1 m proud of the cabinet's) [m]."""
OVERTURN = 0.15
"""Turn past the door's measured angle, taking up the gap to the door and pressing it shut [rad]."""


def _flat(v: np.ndarray) -> np.ndarray:
    v = np.array(v, float)
    v[2] = 0.0
    return v / np.linalg.norm(v)


def swing_sign(hinge: np.ndarray, handle: np.ndarray, out: np.ndarray) -> float:
    """+1 when the door opens counter-clockwise seen from above (the handle moving along ``out``)."""
    r = np.asarray(handle, float) - np.asarray(hinge, float)
    return 1.0 if float(-r[1] * out[0] + r[0] * out[1]) > 0 else -1.0


def open_door(robot: Robot, motion: Motion, hinge: np.ndarray, handle: np.ndarray, out: np.ndarray) -> bool:
    """Stand ``OPEN_STANDOFF`` in front of the handle facing the door, grip the vertical bar with the
    tool pitched ``PITCH`` down, orbit the base about the hinge until the task succeeds, let go."""
    handle, out = np.asarray(handle, float), _flat(out)
    heading = float(np.arctan2(-out[1], -out[0]))  # facing the door
    grip = facing_quat(heading, PITCH)
    axis = quat_to_mat(grip)[:, 2]
    stand = handle[:2] + OPEN_STANDOFF * out[:2]
    motion.drive_to(stand[0], stand[1], heading, max_steps=120)
    motion.move_tool(handle - APPROACH * axis, grip, max_steps=100, tol=0.02)
    motion.move_tool(handle, grip, max_steps=30, speed=0.5, tol=0.012)
    motion.close_gripper(steps=6)
    sign = swing_sign(hinge, handle, out)
    motion.orbit(hinge, sign * SWING, stop=lambda o: bool(o["success"]))
    motion.open_gripper(steps=4)
    return bool(robot.observe()["success"])


def close_door(
    robot: Robot, motion: Motion, hinge: np.ndarray, handle: np.ndarray, out: np.ndarray, opened: float
) -> bool:
    """Push an open door (``opened`` [rad]) shut: stand in front of a point of its front below and
    inside the handle, touch it with the closed fingers pointing down, orbit the base about the hinge
    until the task succeeds."""
    hinge, handle, out = np.asarray(hinge, float), np.asarray(handle, float), _flat(out)
    along = handle - hinge - np.dot(handle - hinge, out) * out  # hinge -> handle in the door's plane
    along[2] = 0.0
    reach = float(np.linalg.norm(along))  # handle's distance from the hinge axis
    along /= reach
    contact = handle + (CLEAR - HANDLE_PROUD) * out - INSIDE * along
    contact[2] = PUSH_Z
    stand = hinge[:2] + max(reach - INSIDE, MIN_SIDE) * along[:2] + (CLOSE_STANDOFF + CLEAR) * out[:2]
    heading = float(np.arctan2(-out[1], -out[0]))  # facing the door
    motion.drive_to(stand[0], stand[1], robot.obs["base_yaw"], tol=0.05, max_steps=60)  # back off, then turn
    motion.drive_to(stand[0], stand[1], heading, tol=0.03, yaw_tol=0.06, max_steps=80)
    tool = down_quat(heading)  # fingers closing along the door's normal: a thin hand against the door
    motion.close_gripper(steps=1)
    motion.move_tool(contact + APPROACH * out, tool, max_steps=80, tol=0.02)
    motion.move_tool(contact, tool, max_steps=30, speed=0.5, tol=0.01)
    sign = -swing_sign(hinge, handle, out)  # closing turns against opening
    motion.orbit(hinge, sign * (opened + OVERTURN), stop=lambda o: bool(o["success"]))
    return bool(robot.observe()["success"])
