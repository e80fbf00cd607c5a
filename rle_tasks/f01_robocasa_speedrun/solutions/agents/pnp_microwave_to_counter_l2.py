"""PickPlaceMicrowaveToCounter at L2: the L3 program (``run``) on a perceived scene.

No world state: the object's category comes from the instruction. The open door (``microwave door``)
gives the microwave's front (its hinge edge), the door's x and the top; the object is seen in the
cavity from the agent views and again by the hand camera from the entry pose (its top layer's
principal axes give its box); the plate on the counter is the ``plate`` instance away from the object
(the turntable is one too), looked for by turning the base when no view holds it. Once grasped, the
object is taken to move rigidly with the hand. Like the L3 program, it works in the wall's frame.
The weak part is the object's box from the few pixels it covers (4-60 in the agent views): the top
is the highest point seen from any pose, a round top's radius the mean of its two spreads (the
oblique view stretches it), and the fingers must land within about 5 mm of the L3 program's grasp.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness.geometry import quat_to_mat, rotz
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import CAMERAS, Robot

from .objects_l2 import FLAT, TOP_LAYER
from .perceive import clouds
from .pick import ROUND
from .pnp_microwave_to_counter import run

BIAS = 0.024
"""A mask's median lies about this far in front of a small object's centre (its front surface) [m]."""
ELONGATED = 1.6
"""Ratio of the top layer's principal spreads above which the object is a long box (an oblique view
stretches a round top by up to 1.5)."""
LOOK_TURNS = (0.6, -0.6)
"""Base turns [rad] to look for a plate no view holds."""


def category_of(instruction: str) -> str:
    """The object in "Pick the <category> from the microwave ..."."""
    words = instruction.split()
    return words[words.index("the") + 1].strip(".,")


class SeenView:
    """``WorldView``'s counterpart from segmentation and depth."""

    def __init__(self, robot: Robot, motion: Motion) -> None:
        self.robot, self.motion = robot, motion
        self.prompt = category_of(robot.observe()["instruction"])
        turntable = max(clouds(robot, "microwave plate"), key=lambda c: len(c.points), default=None)
        self.floor = None if turntable is None else float(np.median(turntable.points[:, 2]))
        self.box = None
        self.top_seen, self.points_seen = -np.inf, 0
        self._object(CAMERAS)
        if self.box is None and turntable is not None:  # the object stands near the turntable's centre
            t = np.median(turntable.points, axis=0)
            self.box = (np.array([t[0], t[1], self.floor + 0.03]), np.full(3, 0.03), np.eye(3))
        if self.box is None:
            raise LookupError("object not seen")
        c = self.box[0]
        door = max(clouds(robot, "microwave door"), key=lambda c: len(c.points), default=None)
        if door is not None:
            p = door.core if len(door.core) >= 20 else door.points
            self.door_x = float(np.median(p[:, 0]))
            self.front = float(np.percentile(p[:, 1], 98))
            self.top = float(np.percentile(p[:, 2], 99))
        else:  # the door out of view: the microwave's size about the object
            self.door_x, self.front, self.top = c[0] - 0.2, c[1] - 0.19, c[2] + 0.25
        self.start = self.box[0].copy()
        self._plate = self._find_plate()
        self.local = None
        self.rot0 = None

    def _object(self, cams: tuple[str, ...]) -> None:
        """Update the object's box from ``cams``: the top is the highest seen so far (a partial view
        sees less of it), the centre and extents those of the view with the most points."""
        near = None if self.box is None else self.box[0]
        found = clouds(self.robot, self.prompt, cams, min_points=3)
        if near is not None:
            found = [c for c in found if np.linalg.norm(c.centre - near) < 0.12]
        if not found:
            return
        pts = np.concatenate([c.points for c in found])
        mid = np.median(pts, axis=0)
        pts = pts[np.linalg.norm(pts - mid, axis=1) < 0.1]
        if self.floor is None:
            self.floor = float(np.percentile(pts[:, 2], 2))
        floor = self.floor
        top = max(float(np.percentile(pts[:, 2], 98)), self.top_seen)
        self.top_seen = top
        if len(pts) < self.points_seen and self.box is not None:
            c, half, rot = self.box
            hz = max((top - floor) / 2, 0.01)
            self.box = (np.array([c[0], c[1], floor + hz]), np.array([*half[:2], hz]), rot)
            return
        self.points_seen = len(pts)
        layer = pts[pts[:, 2] > top - TOP_LAYER]
        flat = len(layer) < 3 or float(np.mean(layer[:, 2] > top - FLAT)) > 0.5
        if flat and (layer[:, 2] > top - FLAT).sum() >= 10:
            layer = layer[layer[:, 2] > top - FLAT]  # a flat top: its face only, not the side below it
        xy = np.median(pts[:, :2], axis=0) + [0.0, BIAS]
        spread = np.percentile(pts[:, :2], 95, axis=0) - np.percentile(pts[:, :2], 5, axis=0)
        hz = max((top - floor) / 2, 0.01)
        yaw, half = 0.0, np.array([hz, hz, hz])
        if not flat:  # a ball: round in every direction
            half[:] = max(hz, float(np.max(spread)) / 2)
        elif len(layer) >= 10:
            w, v = np.linalg.eigh(np.cov((layer[:, :2] - layer[:, :2].mean(axis=0)).T))
            long = float(np.ptp((layer[:, :2]) @ v[:, 1]))
            narrow = float(np.ptp((layer[:, :2]) @ v[:, 0]))
            if w[1] > ELONGATED**2 * max(w[0], 1e-9):
                yaw = float(np.arctan2(v[1, 0], v[0, 0]))
                half = np.array([narrow / 2, long / 2, hz])
            else:
                r = (narrow + long) / 4  # the view stretches a round top along it
                half = np.array([r, r + 2 * ROUND, hz])  # a flat-topped cylinder: not a ball
        self.box = (np.array([xy[0], xy[1], floor + hz]), half, rotz(yaw))

    def _find_plate(self) -> np.ndarray | None:
        for turn in (0.0, *LOOK_TURNS):
            if turn:
                o = self.robot.obs
                self.motion.drive_to(
                    o["base_pos"][0], o["base_pos"][1], float(o["base_yaw"]) + turn, max_steps=40
                )
            found = [
                c for c in clouds(self.robot, "plate") if np.linalg.norm(c.centre[:2] - self.start[:2]) > 0.3
            ]
            if turn:
                self.motion.drive_to(o["base_pos"][0], o["base_pos"][1], float(o["base_yaw"]), max_steps=40)
            if found:
                best = max(found, key=lambda c: len(c.points))
                p = np.concatenate([c.points for c in found if np.linalg.norm(c.centre - best.centre) < 0.15])
                top = float(np.percentile(p[:, 2], 95))
                rim = p[p[:, 2] > top - 0.01]
                return np.array([*np.median(rim[:, :2], axis=0), top])
        return None

    def object(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if self.local is None:
            self.robot.observe()
            self._object(CAMERAS)
            return self.box
        c = np.asarray(self.robot.obs["ee_pos"]) + self.hold()[0]
        return c, self.box[1], self.box[2]

    def plate(self) -> tuple[np.ndarray, float]:
        if self._plate is None:
            raise LookupError("no plate seen")
        return np.array([self._plate[0], self._plate[1], self._plate[2]]), float(self._plate[2])

    def grasped(self) -> None:
        o = self.robot.observe()
        r = quat_to_mat(o["ee_quat"])
        self.local = r.T @ (self.box[0] - np.asarray(o["ee_pos"]))

    def hold(self) -> tuple[np.ndarray, float]:
        o = self.robot.observe()
        offset = quat_to_mat(o["ee_quat"]) @ self.local
        return offset, float(self.box[1][2] - offset[2])


def solve(robot: Robot, motion: Motion) -> bool:
    try:
        view = SeenView(robot, motion)
        if view._plate is None:
            return False
        return run(robot, motion, view)
    except LookupError:
        return False
