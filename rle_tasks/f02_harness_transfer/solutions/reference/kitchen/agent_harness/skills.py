"""Kitchen skills from images, depth and the segmenter. ``Skills(client)`` wraps the metered client:
``robot`` (``act``, ``observe``), ``motion`` (closed-loop primitives), navigation and looking around
(here), grasping (``grasping.Grasping``), fixtures in view (``fixtures.FixtureViews``) and drawer pushing
(``articulation.Drawers``). Module functions elsewhere: ``fixtures.find_open_door``,
``articulation.close_door`` / ``push_drawer_holding``, ``knobs.turn_knob``, ``dishes`` (bowls). Each skill
returns True when it believes it worked; none raises on a failure of the robot (a missed grasp returns
False). Kitchen conventions: ``kitchen``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .articulation import Drawers
from .fixtures import FixtureViews
from .geometry import quat_mul, rotz
from .grasping import Grasping
from .kitchen import FACING, FAR_PITCH, FAR_TURN, LANE_Y, LOOK_PITCH, ROAM, STAND_Y
from .motion import Motion, facing_quat
from .perception import clean, clouds, in_box, merged
from .robot import CAMERAS, Robot

__all__ = ["Skills"]


class Skills(Grasping, FixtureViews, Drawers):
    """The skills of one robot (see the module docstring).

    Args:
        client: The metered client (``reset``, ``step``, ``observe``, ``query``).
    """

    def __init__(self, client: Any) -> None:
        self.client = client
        self.robot = Robot(client)
        self.motion = Motion(self.robot)
        self.log: list[str] = []
        self.home_base: tuple[np.ndarray, np.ndarray] | None = None

    def reset(self) -> dict[str, Any]:
        """Reset the session (one charged step) and remember the arm's home pose on the base."""
        o = self.robot.reset()
        self.home_base = (np.asarray(o["ee_pos_base"], float), np.asarray(o["ee_quat_base"], float))
        return o

    def home(self) -> None:
        """The tool back to its pose at the reset (relative to the base): the arm's own ready posture,
        from which every skill starts well."""
        if self.home_base is None:
            return
        o = self.obs
        p, q = self.home_base
        yaw = float(o["base_yaw"])
        qb = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])
        world = np.asarray(o["base_pos"], float) + rotz(yaw) @ p
        self.motion.move_tool(world, quat_mul(qb, q), tol=0.03, rot_tol=0.1, max_steps=120)

    # -- basics -------------------------------------------------------------------------------

    @property
    def obs(self) -> dict[str, Any]:
        return self.robot.obs if self.robot.obs else self.robot.observe()

    def note(self, text: str) -> None:
        """Record a line of the skill log (returned by the entry point), stamped with the time [s]."""
        self.log.append(f"[{float(self.obs.get('time', 0.0)):6.2f}] {text}")

    def base_point(self, forward: float, left: float, z: float) -> np.ndarray:
        """World point at ``forward``, ``left`` [m] in the base frame and height ``z`` [m]."""
        o = self.obs
        return np.array([*(np.asarray(o["base_pos"][:2]) + rotz(o["base_yaw"])[:2, :2] @ [forward, left]), z])

    def look(self, turn: float = 0.0, pitch: float = LOOK_PITCH) -> None:
        """Raise the hand over the base with the eye-in-hand camera looking ``turn`` [rad] left of the
        base's heading and ``pitch`` down: an overview of the counters ahead (and beside for a turn)."""
        o = self.obs
        self.motion.move_tool(
            self.base_point(0.12, 0.0, 1.6), facing_quat(o["base_yaw"] + turn, pitch), tol=0.03, max_steps=150
        )

    def tuck(self) -> None:
        """The hand high over the base (safe for driving), looking ahead; a low hand first backs out
        towards the base (from under a counter top's edge)."""
        o = self.obs
        if o["ee_pos"][2] < 1.0:
            back = np.asarray(o["ee_pos"], float).copy()
            back[:2] += (
                0.1
                * (np.asarray(o["base_pos"][:2]) - back[:2])
                / max(float(np.linalg.norm(np.asarray(o["base_pos"][:2]) - back[:2])), 1e-6)
            )
            self.motion.move_tool(back, None, tol=0.02, max_steps=30)
            self.motion.move_tool_by([0.0, 0.0, 0.15], tol=0.03, max_steps=40)
            self.home()
        elif float(np.asarray(self.obs["ee_pos_base"])[0]) > 0.4:
            self.home()  # from far out straight up to the look pose the elbow jams (under a wall cabinet)
        self.look(0.0)

    def carry_pose(self) -> None:
        """Bring the hand (holding an object) close over the base, 1.15 m up, before driving."""
        self.motion.move_tool(self.base_point(0.3, 0.0, 1.15), None, tol=0.03, max_steps=120)

    def goto(self, x: float, y: float, heading: float = FACING, *, lane: bool | None = None) -> bool:
        """Drive the base to (x, y) [m] facing ``heading``; a long drive along the run first backs out
        to ``LANE_Y`` (clear of open doors and drawers) unless ``lane`` is False."""
        o = self.obs
        far = abs(x - o["base_pos"][0]) > 0.3
        if lane or (lane is None and far):
            if o["base_pos"][1] > LANE_Y + 0.05:
                self.motion.drive_to(o["base_pos"][0], LANE_Y, heading, tol=0.05, max_steps=120)
            self.motion.drive_to(x, LANE_Y, heading, tol=0.05, max_steps=300)
        r = self.motion.drive_to(x, y, heading, tol=0.02, max_steps=200)
        return r.reached

    # -- perception ---------------------------------------------------------------------------

    def see(
        self,
        prompt: str,
        lo: tuple[float, float, float] = (-np.inf, -np.inf, -np.inf),
        hi: tuple[float, float, float] = (np.inf, np.inf, np.inf),
        cameras: tuple[str, ...] = CAMERAS,
        tries: int = 3,
    ) -> np.ndarray:
        """World points [m] of ``prompt`` inside the box [lo, hi] in ``cameras`` now (a new image per try
        when nothing is seen; the segmenter misses small instances at times)."""
        for k in range(tries):
            pts = in_box(merged(clouds(self.client, self.obs, prompt, cameras)), lo, hi)
            if len(pts) >= 3:
                return pts
            if k < tries - 1:
                self.motion.wait(1)
        return np.zeros((0, 3))

    def find(
        self,
        prompt: str,
        lo: tuple[float, float, float] = (-np.inf, -np.inf, -np.inf),
        hi: tuple[float, float, float] = (np.inf, np.inf, np.inf),
        turns: tuple[float, ...] = (0.0, 0.8, -0.8),
        radius: float | None = 0.08,
    ) -> np.ndarray:
        """Points [m] of one instance of ``prompt`` in [lo, hi]: looked for from the look pose turned by
        each of ``turns`` [rad] in turn; cleaned within ``radius`` of their median (None keeps all)."""
        for turn in turns:
            self.look(turn)
            pts = self.see(prompt, lo, hi)
            if len(pts) >= 3:
                return clean(pts, radius) if radius else pts
        return np.zeros((0, 3))

    def find_far(
        self,
        prompt: str,
        lo: tuple[float, float, float] = (-np.inf, -np.inf, -np.inf),
        hi: tuple[float, float, float] = (np.inf, np.inf, np.inf),
    ) -> np.ndarray:
        """Points [m] of ``prompt`` in [lo, hi] seen looking along the run to either side (the hand turned
        ``FAR_TURN`` off the heading, tilted ``FAR_PITCH`` down): finds what stands up to about 2.5 m away,
        coarsely (the look pose sees about 1 m around); failing that, from ``ROAM`` m to the left and then
        to the right on ``LANE_Y``."""
        x0 = float(self.obs["base_pos"][0])
        for k, dx in enumerate((0.0, *ROAM)):
            if k:
                self.tuck()
                self.goto(x0 + dx, LANE_Y, lane=True)
            for turn in (FAR_TURN, -FAR_TURN):
                self.look(turn, FAR_PITCH)
                pts = self.see(prompt, lo, hi, tries=2)
                if len(pts) >= 5:
                    return pts
        return np.zeros((0, 3))

    def search(
        self,
        prompt: str,
        lo: tuple[float, float, float] = (-np.inf, -np.inf, -np.inf),
        hi: tuple[float, float, float] = (np.inf, np.inf, np.inf),
        radius: float | None = 0.08,
        stand_y: float = STAND_Y,
    ) -> np.ndarray:
        """``find``; failing that ``find_far``, a drive to stand in front of what it saw (at ``stand_y``)
        and ``find`` again. Points [m] as ``find`` returns them (empty when not found)."""
        pts = self.find(prompt, lo, hi, radius=radius)
        if len(pts) >= 3:
            return pts
        far = self.find_far(prompt, lo, hi)
        if len(far) < 5:
            return np.zeros((0, 3))
        x = float(np.median(far[:, 0]))
        self.note(f"{prompt} seen far off, near x {x:.2f}")
        self.tuck()
        self.goto(x, stand_y)
        return self.find(prompt, lo, hi, radius=radius)

    def extent_x(self, prompt: str, lo=(-np.inf, -np.inf, -np.inf), hi=(np.inf, np.inf, np.inf)):
        """(x min, x max) [m] of what ``prompt`` shows in [lo, hi] now, or None."""
        pts = self.see(prompt, lo, hi, tries=1)
        if len(pts) < 5:
            return None
        return float(np.percentile(pts[:, 0], 2)), float(np.percentile(pts[:, 0], 98))
