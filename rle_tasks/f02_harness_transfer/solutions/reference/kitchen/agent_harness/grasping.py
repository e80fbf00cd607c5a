"""Grasping: a close look from above, a top-down grasp across an object's narrower side, placing it on a
surface (``Grasping``, mixed into ``skills.Skills``)."""

from __future__ import annotations

import numpy as np

from .geometry import world_points
from .kitchen import EMPTY, FINGER_CLEARANCE, GRASP_DEPTH, GRASP_DEPTH_ROUND, PICK_TORSO, Held
from .motion import down_quat
from .perception import HAND, clean, in_box

__all__ = ["Grasping"]


class Grasping:
    """Picking and placing (methods of ``skills.Skills``)."""

    def close_look(self, prompt: str, xy: np.ndarray, top_z: float, height: float = 0.2) -> np.ndarray:
        """Points [m] of ``prompt`` near ``xy`` seen by the eye-in-hand camera from ``height`` above
        ``top_z``, looking straight down (low: the wrist stays under the wall cabinets, 1.45 m up)."""
        q = down_quat(self.obs["base_yaw"] + np.pi / 2)
        self.motion.move_tool([xy[0], xy[1], top_z + height], q, tol=0.02, max_steps=120)
        lo = (xy[0] - 0.15, xy[1] - 0.15, top_z - 0.3)
        hi = (xy[0] + 0.15, xy[1] + 0.15, top_z + 0.15)
        return clean(self.see(prompt, lo, hi, cameras=(HAND,), tries=4), 0.07)

    def _grasp_yaw(self, pts: np.ndarray) -> tuple[float, bool]:
        """(yaw of a top-down grasp closing across the object's narrower side [rad], round) from its
        top-view points; of the two equivalent yaws the one nearest the arm's home (base + pi/2)."""
        home = float(self.obs["base_yaw"]) + np.pi / 2
        xy = pts[:, :2] - pts[:, :2].mean(axis=0)
        if len(xy) < 8:
            return home, True
        w, v = np.linalg.eigh(np.cov(xy.T))
        round_ = w[0] > 0.45 * w[1]
        if round_:
            return home, True
        minor = v[:, 0]
        axis = float(np.arctan2(minor[1], minor[0]))
        return float(home + ((axis - home + np.pi / 2) % np.pi - np.pi / 2)), False

    def pick(self, prompt: str, guess: np.ndarray, lift: float = 0.15) -> Held | None:
        """Grasp the ``prompt`` object near ``guess`` [m] from above and lift it by ``lift`` [m]: a
        close look from above, a grasp across its narrower side, the fingers at its equator (round) or
        2 cm below its top; None when it was not seen or the fingers closed on nothing."""
        top = float(guess[2])
        self.motion.set_torso(PICK_TORSO)
        for attempt in range(2):
            pts = self.close_look(prompt, np.asarray(guess[:2]), top)
            if len(pts) < 5:
                self.note(f"pick: no close view of {prompt}")
                return None
            c = np.median(pts, axis=0)
            top = float(np.percentile(pts[:, 2], 95))
            ring = self._support(c, pts)
            cap = in_box(pts, (-np.inf, -np.inf, top - 0.012), (np.inf, np.inf, np.inf))
            yaw, round_ = self._grasp_yaw(
                in_box(pts, (-np.inf, -np.inf, top - 0.03), (np.inf, np.inf, np.inf))
            )
            xy = cap[:, :2].mean(axis=0) if len(cap) >= 3 else c[:2]  # the top's centre: no view bias
            depth = GRASP_DEPTH_ROUND if round_ else GRASP_DEPTH
            z = max(top - depth, ring + FINGER_CLEARANCE)
            q = down_quat(yaw)
            self.motion.move_tool(
                [xy[0], xy[1], z + 0.08], q, tol=0.01, max_steps=100, speed=0.5, gripper=-1.0
            )
            self.motion.move_tool(
                [xy[0], xy[1], z + 0.08], q, tol=0.004, max_steps=30, speed=0.3, correct=True
            )
            self.motion.move_tool([xy[0], xy[1], z], q, tol=0.004, max_steps=80, speed=0.3, correct=True)
            self.note(
                f"grasp {prompt}: target {np.round([*xy, z], 3)} yaw {yaw:.2f} round {round_} tool {np.round(self.obs['ee_pos'], 3)} top {top:.3f} n {len(pts)}"
            )
            o = self.motion.close_gripper(steps=10)
            if o["gripper"] > EMPTY:
                held = Held(prompt, float(o["ee_pos"][2] - ring))
                self.motion.move_tool_by([0.0, 0.0, lift], tol=0.02, max_steps=40, gripper=1.0)
                if self.obs["gripper"] > EMPTY:
                    self.note(f"picked {prompt} at {np.round(xy, 3)} (support {ring:.2f})")
                    return held
            self.note(f"pick {prompt}: missed (attempt {attempt}, opening {self.obs['gripper']:.4f})")
            self.motion.open_gripper(steps=6)
            self.tuck()
            guess = np.array([xy[0], xy[1], top])
        return None

    def _support(self, c: np.ndarray, pts: np.ndarray) -> float:
        """Height [m] of the surface under an object centred at ``c`` (hand camera's points in a ring
        around it, below its top)."""
        o = self.obs
        allpts = in_box(
            world_points(o, HAND), (c[0] - 0.12, c[1] - 0.12, -np.inf), (c[0] + 0.12, c[1] + 0.12, np.inf)
        )
        r = float(np.max(np.linalg.norm(pts[:, :2] - c[:2], axis=1))) if len(pts) else 0.04
        d = np.linalg.norm(allpts[:, :2] - c[:2], axis=1)
        ring = allpts[(d > r + 0.015) & (d < r + 0.08) & (allpts[:, 2] < np.percentile(pts[:, 2], 50))]
        if len(ring) < 10:
            return float(np.min(pts[:, 2])) - 0.01
        return float(np.percentile(ring[:, 2], 50))

    def place(
        self, held: Held, xy: np.ndarray, support_z: float, drop: float = 0.015, carry_z: float | None = None
    ) -> None:
        """Carry the held object to above ``xy`` [m], lower it until its bottom is ``drop`` [m] above the
        surface at ``support_z`` [m], let go and raise the hand 0.3 m."""
        q = self.obs["ee_quat"]
        z = support_z + held.below + drop
        cz = max(z + 0.12, self.obs["ee_pos"][2]) if carry_z is None else carry_z
        self.motion.move_tool(
            [xy[0], xy[1], cz], q, tol=0.015, max_steps=200, speed=0.5, gripper=1.0, correct=True
        )
        r = self.motion.move_tool(
            [xy[0], xy[1], z], q, tol=0.008, max_steps=80, speed=0.6, gripper=1.0, correct=True
        )
        self.note(f"release at {np.round(self.obs['ee_pos'], 3)} for {np.round([*xy, z], 3)} ({r.reached})")
        self.motion.open_gripper(steps=8)
        self.motion.move_tool_by([0.0, 0.0, 0.3], tol=0.03, max_steps=50, gripper=-1.0)
        self.note(f"placed {held.prompt} at {np.round(xy, 3)} on {support_z:.2f}")
