"""TurnOnStove at L2: find the named burner's knob by segmentation and depth, then twist it.

No world state: the burner comes from the instruction, the knob from ``segment("<burner> knob")`` in
the three cameras and their depth images (``geometry.world_points``). A coarse estimate from the
start pose brings the tool 15 cm in front of the knob, looking at it (the base first steps sideways
to an outer knob); the eye-in-hand camera then sees the knob face-on and a second estimate places the
fingers on its grip bar. The grasp and twist are the L3 program's. Kitchen conventions used: the
stove's front faces world -y (the wall is the plane y = 0) and the robot starts facing the wall.
"""

from __future__ import annotations

import re
from collections.abc import Callable

import numpy as np

from rle_tasks.envs.kitchen.harness import geometry, perception
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import CAMERAS, Robot

from .turn_on_stove import FORWARD, twist

STANDOFF = 0.15
"""Distance of the look-and-refine pose in front of the knob [m]."""
REACH_SIDE = 0.12
"""Knobs further sideways than this from the tool [m] are first brought in front of the arm by the base."""
HAND = "robot/arm/eye_in_hand"


def burner_of(instruction: str) -> str:
    """The burner words of the instruction ("front left" ...)."""
    m = re.search(r"(front|rear) (left|right) burner", instruction)
    if m is None:
        raise ValueError(f"no burner named in {instruction!r}")
    return f"{m.group(1)} {m.group(2)}"


def _clean(pts: np.ndarray, radius: float = 0.04) -> np.ndarray:
    """Points within ``radius`` [m] of their median (drops background pixels of a noisy mask)."""
    if len(pts) == 0:
        return pts
    keep = np.linalg.norm(pts - np.median(pts, axis=0), axis=1) < radius
    return pts[keep]


def knob_points(robot: Robot, prompt: str, cameras: tuple[str, ...]) -> list[np.ndarray]:
    """World points [m] of the best mask of ``prompt`` in each camera that sees it."""
    obs = robot.obs
    out = []
    for cam in cameras:
        seg = perception.segment(robot.client, prompt, cam)
        if len(seg["masks"]) == 0:
            continue
        best = int(np.argmax(seg["scores"] * seg["masks"].sum(axis=(1, 2))))
        pts = _clean(geometry.world_points(obs, cam, seg["masks"][best]))
        if len(pts) >= 3:
            out.append(pts)
    return out


def coarse(robot: Robot, motion: Motion, prompt: str, tries: int = 4) -> np.ndarray | None:
    """Knob position [m] from every camera at the current pose, None when none sees it (after
    ``tries`` images). From above, the seen surface lies 1-2 cm above and behind the grip bar; the
    face-on ``refine`` removes that bias."""
    for _ in range(tries):
        clouds = knob_points(robot, prompt, CAMERAS)
        if clouds:
            return np.median(np.concatenate(clouds), axis=0)
        motion.wait(1)  # a new image (the segmenter may miss a small instance)
    return None


def refine(robot: Robot, motion: Motion, prompt: str, tries: int = 4) -> np.ndarray | None:
    """Knob grip position [m] from the eye-in-hand camera looking at the knob face-on: the mask's
    median across, its front-most 30 % along the view (the knob's face and grip bar)."""
    for _ in range(tries):
        clouds = knob_points(robot, prompt, (HAND,))
        if clouds:
            pts = clouds[0]
            x, z = np.median(pts[:, 0]), np.median(pts[:, 2])
            y = np.percentile(pts[:, 1], 30)
            return np.array([x, y, z])
        motion.wait(1)
    return None


def solve(
    robot: Robot, motion: Motion, debug: Callable[[str, np.ndarray | None], None] | None = None
) -> bool:
    """Turn on the instruction's burner; True when the task's success holds at the end.

    Args:
        robot: The robot of an L2 (or L3) session, after a reset.
        motion: Its motion primitives.
        debug: Called with ("coarse" | "fine", the knob estimate [m]) when given (development).
    """
    obs = robot.observe()
    prompt = burner_of(obs["instruction"]) + " knob"
    knob = coarse(robot, motion, prompt)
    if debug:
        debug("coarse", knob)
    if knob is None:
        return False
    o = robot.obs
    side = knob[0] - o["ee_pos"][0]
    if abs(side) > REACH_SIDE:  # the outer knobs: step the base sideways, facing the wall
        motion.drive_to(o["base_pos"][0] + side, o["base_pos"][1], np.pi / 2)
    motion.open_gripper(steps=2)
    motion.move_tool(knob + [0.0, -STANDOFF, 0.0], FORWARD, max_steps=200)
    fine = refine(robot, motion, prompt)
    if debug:
        debug("fine", fine)
    if fine is not None:
        knob = fine
    return twist(robot, motion, knob)
