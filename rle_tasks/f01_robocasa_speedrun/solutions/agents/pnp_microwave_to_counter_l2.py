"""PickPlaceMicrowaveToCounter at L2 (a draft, not registered as a reference: 1/5 target kitchens of
the public key, 2/6 pretrain kitchens; see the family README): the L3 program (``run``) on a perceived
scene.

No world state: the object's category comes from the instruction. The open door (``microwave door``)
gives the microwave's front (its hinge edge), the door's x and the top; the object is seen in the
cavity from the agent views and again by the hand camera from the entry pose (its top layer's
principal axes give its box); the plate on the counter is the ``plate`` instance away from the object
(the turntable is one too), looked for by turning the base when no view holds it. Once grasped, the
object is taken to move rigidly with the hand. Like the L3 program, it works in the wall's frame.
Where it fails: the object's height and extents from the few pixels it covers (the hand camera at the
entry pose sees its lower front, the agent views 4-60 pixels), so the reach closes the fingers on the
object's top edge and it slips out while being pulled from the cavity.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness.geometry import quat_to_mat, rotz
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import CAMERAS, Robot

from .objects_l2 import ELONGATED, FLAT, TOP_LAYER
from .perceive import clouds
from .pick import ROUND
from .pnp_microwave_to_counter import run

BIAS = 0.02
"""A mask's median lies this far in front of a small object's centre (its front surface) [m]."""
LOOK_TURNS = (0.6, -0.6)
"""Base turns [rad] to look for a plate no view holds."""
HAND = ("robot/arm/eye_in_hand",)


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
        self.floor = None if turntable is None else float(np.percentile(turntable.points[:, 2], 95))
        self.box = None
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
        near = None if self.box is None else self.box[0]
        found = [c for c in clouds(self.robot, self.prompt, cams, min_points=3)]
        if near is not None:
            found = [c for c in found if np.linalg.norm(c.centre - near) < 0.12]
        if not found:
            return
        pts = np.concatenate([c.points for c in found])
        mid = np.median(pts, axis=0)
        pts = pts[np.linalg.norm(pts - mid, axis=1) < 0.1]
        floor = self.floor if self.floor is not None else float(np.percentile(pts[:, 2], 2))
        self.floor = floor
        top = float(np.percentile(pts[:, 2], 98))
        layer = pts[pts[:, 2] > top - TOP_LAYER]
        flat = float(np.mean(layer[:, 2] > top - FLAT)) > 0.5
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
                r = max(narrow, long) / 2
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
            self._object(HAND)
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
