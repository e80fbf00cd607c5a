"""Kitchen skills from images, depth and the segmenter: find, drive, pick, place, push a drawer shut,
close a hinged door, turn a knob.

Kitchen conventions (the same in every kitchen, measured in development): one straight run of base
units against the wall, the wall is the plane y = 0 and the units' fronts face -y at y = ``FRONT_Y``
(the fridge's at -0.7 m); counter tops at ``COUNTER_Z``; the robot starts facing the wall (heading
``FACING``). Every position is in the world frame [m], every angle in radians.

``Skills(client)`` wraps the metered client: ``robot`` (``act``, ``observe``), ``motion`` (closed-loop
primitives) and the skills below. Each skill returns True when it believes it worked; none raises on
a failure of the robot (a missed grasp returns False).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .geometry import quat_mul, rotz, world_points
from .motion import Motion, down_quat, facing_quat
from .perception import HAND, clean, clouds, in_box, merged
from .robot import CAMERAS, Robot

__all__ = [
    "COUNTER_Z",
    "EMPTY",
    "FACING",
    "FRONT_Y",
    "Drawer",
    "Held",
    "OpenDoor",
    "Skills",
    "close_door",
    "find_open_door",
    "push_drawer_holding",
    "turn_knob",
]

FACING = np.pi / 2
"""Base heading that faces the wall [rad]."""
FRONT_Y = -0.6
"""y of the base units' fronts [m]."""
COUNTER_Z = 0.92
"""Height of the counter tops [m]."""
LANE_Y = -1.45
"""Base y for long drives along the run: clear of open doors (up to 0.6 m out) and drawers [m]."""
STAND_Y = -1.25
"""Base y in front of a unit for work at its front (drawer handle, knobs, the open drawer's tray) [m]."""
SIDE_GAP = 0.16
"""Base centre's distance from the side of an open drawer when standing beside it [m]."""
BESIDE_Y = -0.81
"""Base y beside an open drawer, as near the units as the deck allows [m]."""
FINGER_CLEARANCE = 0.022
"""Least height of the tool above the support under a grasped object [m]."""
GRASP_DEPTH = 0.021
"""Grasp depth below the top of a flat-topped object [m] (the palm stays clear)."""
GRASP_DEPTH_ROUND = 0.03
"""Grasp depth below the top of a round object (fruit) [m]: the fingers reach its equator."""
EMPTY = 0.008
"""Finger opening [m] below which the closed fingers hold nothing."""
WORK_TORSO = 0.15
"""Torso height at the start and for work at the fronts of the units (drawer, knobs) [m]."""
PICK_TORSO = 0.15
"""Torso height for picking and placing [m]: the arm's root 1.0 m up, where it reaches the counter
tops far out without sagging."""
FAR_TURN = 1.45
"""Turn of the hand off the base's heading for a look along the run [rad]."""
FAR_PITCH = 0.5
"""Tilt below the horizontal of the eye-in-hand camera for a look along the run [rad]."""
ROAM = (-1.6, 1.6)
"""Offsets along the run from where ``find_far`` looks again when it saw nothing [m]."""
LOOK_PITCH = 1.1
"""Tilt below the horizontal of the eye-in-hand camera in the look pose [rad]."""


@dataclass(frozen=True)
class Held:
    """An object in the hand: ``below`` is the tool's height above the object's lowest point [m]."""

    prompt: str
    below: float


@dataclass(frozen=True)
class Drawer:
    """An open drawer seen by ``Skills.find_open_drawer``.

    Attributes:
        x: Centre along the run [m].
        width: Width of its cabinet [m].
        front_y: y of the drawer front's outer face [m].
        handle_z: Height of its handle bar [m].
        floor_z: Height of the tray's floor [m].
        open_by: How far it is pulled out [m].
    """

    x: float
    width: float
    front_y: float
    handle_z: float
    floor_z: float
    open_by: float

    @property
    def tray(self) -> np.ndarray:
        """Centre (x, y) of the part of the tray in front of the counter top [m]."""
        return np.array([self.x, (self.front_y + 0.03 + FRONT_Y - 0.02) / 2])


class Skills:
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

    def close_look(self, prompt: str, xy: np.ndarray, top_z: float, height: float = 0.2) -> np.ndarray:
        """Points [m] of ``prompt`` near ``xy`` seen by the eye-in-hand camera from ``height`` above
        ``top_z``, looking straight down (low: the wrist stays under the wall cabinets, 1.45 m up)."""
        q = down_quat(self.obs["base_yaw"] + np.pi / 2)
        self.motion.move_tool([xy[0], xy[1], top_z + height], q, tol=0.02, max_steps=120)
        lo = (xy[0] - 0.15, xy[1] - 0.15, top_z - 0.3)
        hi = (xy[0] + 0.15, xy[1] + 0.15, top_z + 0.15)
        return clean(self.see(prompt, lo, hi, cameras=(HAND,), tries=4), 0.07)

    def find_open_drawer(self) -> Drawer | None:
        """The drawer that stands out of the run (its points over 0.15 m in front of ``FRONT_Y``: closed
        drawers' handles stand 0.066 m proud)."""
        lo, hi = (-np.inf, -np.inf, 0.6), (np.inf, FRONT_Y - 0.15, 0.95)
        for turn in (0.0, 0.8, -0.8):
            self.look(turn)
            pts = self.see("drawer", lo, hi)
            if len(pts) >= 20:
                break
        else:
            return None
        handle = self.see("drawer cabinet handle", lo, hi, tries=2)
        body = pts[np.linalg.norm(pts[:, :2] - np.median(pts[:, :2], axis=0), axis=1) < 0.6]
        x0, x1 = np.percentile(body[:, 0], [1, 99])
        width = float(min((0.5, 0.6, 0.7), key=lambda w: abs(w - (x1 - x0 + 0.02))))
        x = float(np.median(handle[:, 0])) if len(handle) >= 3 else float((x0 + x1) / 2)
        if abs((x1 - x0 + 0.02) - width) < 0.04:  # the whole front seen: its middle is the better centre
            x = float((x0 + x1) / 2)
        if len(handle) >= 3:
            front = float(np.median(handle[:, 1])) + 0.035
            hz = float(np.median(handle[:, 2]))
        else:
            front = float(np.percentile(body[:, 1], 2))
            hz = 0.78
        inner = in_box(
            body,
            (x - width / 2 + 0.05, front + 0.04, -np.inf),
            (x + width / 2 - 0.05, FRONT_Y - 0.05, np.inf),
        )
        floor = float(np.percentile(inner[:, 2], 5)) if len(inner) >= 10 else hz - 0.08
        d = Drawer(x, width, front, hz, floor, FRONT_Y - 0.021 - front)
        self.note(
            f"open drawer at x {x:.2f} width {width:.1f} front {front:.2f} floor {floor:.2f} handle z {hz:.2f}"
        )
        return d

    # -- manipulation -------------------------------------------------------------------------

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

    # -- drawers ------------------------------------------------------------------------------

    def push_drawer(self, d: Drawer) -> bool:
        """Push the drawer shut: the closed fingers, pointing at its front below the handle, ride ahead
        of the base, which drives towards the run until the front is in line with the units; then the
        hand backs off. True when the hand reached the closed front's line."""
        reach = 0.6  # hand ahead of the base's centre [m]
        self.motion.set_torso(WORK_TORSO)
        self.tuck()
        self.goto(d.x, d.front_y - 0.1 - reach)
        q = facing_quat(FACING, 1.1)  # pitched down: the wrist stays clear of the counter top's edge
        z = d.handle_z - 0.07
        self.motion.close_gripper(steps=4)
        self.motion.move_tool(self.base_point(reach, 0.0, z + 0.12), q, tol=0.03, max_steps=100)
        r = self.motion.move_tool(self.base_point(reach, 0.0, z), q, tol=0.01, max_steps=60, correct=True)
        hand = self.obs["ee_pos"]
        self.note(f"push start {r} hand {np.round(hand, 3)} base {np.round(self.obs['base_pos'], 3)}")
        goal = FRONT_Y + 0.012 - (hand[1] - self.obs["base_pos"][1])
        self.motion.drive_to(hand[0], goal, FACING, tol=0.01, max_steps=150)
        y = float(self.obs["ee_pos"][1])
        self.note(
            f"pushed drawer: hand at y {y:.3f}, base {np.round(self.obs['base_pos'], 3)}, goal {goal:.3f} from hand {np.round(hand, 3)}"
        )
        self.motion.drive_to(hand[0], goal - 0.2, FACING, tol=0.03, max_steps=60)
        self.tuck()
        return y > FRONT_Y - 0.03


HAND_AHEAD = 0.1
"""Reach of the hand's body beyond the tool centre along the fingers' closing axis [m] (it is about 0.2 m
across, the closed fingers about 0.08 m)."""
HOLD_PUSH_OFFSET = 0.21
"""Sideways offset from a drawer's middle where a holding hand pushes it: clear of the handle bar (at
most 0.3 m long) [m]."""
HOLD_PUSH_Z = 0.74
"""Tool height for pushing a drawer with the hand's body while holding an object [m] (the drawer's front
spans 0.68-0.88 m, the hand's body starts about 5 cm above the tool centre)."""


def push_drawer_holding(sk: Skills, d: Drawer, held: Held, side: float) -> bool:
    """Push the drawer shut with the side of the hand's body while the fingers keep holding ``held``: the
    tool pointing down with the fingers closing along y (the body leads the object by ``HAND_AHEAD``),
    ``HOLD_PUSH_OFFSET`` to ``side`` (+1: +x) of the drawer's middle, the base driving towards the run.
    Returns True when the drawer no longer stands out and the object is still held."""
    reach = 0.6
    q = down_quat(FACING)
    z = max(HOLD_PUSH_Z, d.handle_z - 0.1 + held.below - 0.03)
    x = d.x + side * HOLD_PUSH_OFFSET
    sk.motion.move_tool(sk.base_point(0.35, 0.0, 1.1), q, tol=0.03, max_steps=100)
    sk.goto(x, d.front_y - HAND_AHEAD - 0.08 - reach)
    sk.motion.move_tool(sk.base_point(reach, 0.0, z + 0.12), q, tol=0.03, max_steps=100)
    sk.motion.move_tool(sk.base_point(reach, 0.0, z), q, tol=0.01, max_steps=60, correct=True)
    hand = np.asarray(sk.obs["ee_pos"], float)
    goal = DOOR_Y - HAND_AHEAD + 0.02 - (hand[1] - sk.obs["base_pos"][1])
    sk.motion.drive_to(float(hand[0]), goal, FACING, tol=0.01, max_steps=150)
    sk.note(f"pushed drawer holding {held.prompt}: hand {np.round(sk.obs['ee_pos'], 3)}, goal {goal:.3f}")
    sk.motion.drive_to(float(hand[0]), goal - 0.15, FACING, tol=0.03, max_steps=60)
    sk.motion.move_tool(sk.base_point(0.35, 0.0, 1.1), None, tol=0.03, max_steps=100)
    holding = float(sk.obs["gripper"]) > EMPTY
    sk.look(0.0)
    lo, hi = (d.x - d.width / 2, -np.inf, 0.6), (d.x + d.width / 2, FRONT_Y - 0.12, 0.95)
    out = sk.see("drawer", lo, hi, tries=2)  # a closed drawer's handle stands 0.07 m proud
    sk.note(f"drawer points still out: {len(out)}; holding {holding}")
    return holding and len(out) < 10


DOOR_Y = FRONT_Y - 0.021
"""y of a hinged base-cabinet door's hinge axis (the closed door's front face) [m]."""
DOOR_PUSH_Z = 0.55
"""Height of the fingertips on an open door when pushing it shut [m] (its handle bar starts about 0.65 m up)."""
DOOR_INSIDE = 0.2
"""Push this far closer to the hinge than the door's free edge, clear of the handle [m]."""
DOOR_CLEAR = 0.03
"""Tool centre in front of the door's face at contact [m]."""
DOOR_STANDOFF = 0.55
"""Horizontal distance from the base's centre to the contact point [m]."""
DOOR_MIN_SIDE = 0.42
"""Least distance of the base's centre line from the hinge along the door [m]: keeps the base clear of
the run (and of a prouder neighbour, a fridge) on the hinge side."""
DOOR_OVERTURN = 0.15
"""Turn past the door's estimated opening, taking up the gap to the door and pressing it shut [rad]."""


@dataclass(frozen=True)
class OpenDoor:
    """An open hinged base-cabinet door seen by ``find_open_door``.

    Attributes:
        hinge: (x, y) of its hinge axis [m].
        along: Unit (x, y) from the hinge towards the free edge.
        out: Unit (x, y) normal of the face to push (away from its cabinet).
        length: Hinge to free edge [m].
        opened: Opening angle [rad] (0 closed).
        closing: +1 when closing turns the door counter-clockwise seen from above, else -1.
    """

    hinge: np.ndarray
    along: np.ndarray
    out: np.ndarray
    length: float
    opened: float
    closing: float


def _door_points(sk: Skills) -> np.ndarray:
    """Points [m] of cabinet doors standing out of the run (below the counter tops) in view now."""
    return sk.see("cabinet door", (-np.inf, -np.inf, 0.15), (np.inf, FRONT_Y - 0.12, 0.9), tries=2)


def _cabinet_side(sk: Skills, hinge: np.ndarray, along: np.ndarray, length: float) -> tuple[float, str]:
    """+1 when the door's cabinet lies on the +x side of the hinge, -1 on the -x side, with the evidence.

    The handle stands 3.5 cm proud of the door's outer face (away from the cabinet); failing a clear view of
    it, the open cabinet shows its interior (depth points well behind the fronts) on its side of the hinge,
    a closed neighbour its front."""
    normal = np.array([-along[1], along[0]])
    lo, hi = (-np.inf, -np.inf, 0.5), (np.inf, FRONT_Y - 0.1, 0.9)
    handle = sk.see("cabinet handle", lo, hi, tries=2)
    if len(handle):
        off = (handle[:, :2] - hinge) @ normal
        near = np.abs((handle[:, :2] - hinge) @ along - (length - 0.06)) < 0.12
        proud = off[near & (np.abs(off) > 0.012) & (np.abs(off) < 0.08)]
        if len(proud) >= 3 and abs(float(np.mean(np.sign(proud)))) > 0.5:
            out_sign = float(np.sign(np.median(proud)))
            return -float(np.sign(out_sign * normal[0])) or 1.0, f"handle ({len(proud)} points)"
    o = sk.obs
    pts = np.concatenate([world_points(o, cam) for cam in CAMERAS])
    pts = in_box(pts, (-np.inf, FRONT_Y + 0.05, 0.25), (np.inf, -0.05, 0.8))
    counts = {}
    for side in (1.0, -1.0):
        a, b = sorted((hinge[0] + side * 0.05, hinge[0] + side * (length - 0.05)))
        counts[side] = int(np.sum((pts[:, 0] > a) & (pts[:, 0] < b)))
    side = max(counts, key=counts.get)
    return side, f"interior {counts}"


def find_open_door(sk: Skills) -> OpenDoor | None:
    """The hinged base-cabinet door standing open: found from the look pose (turning), then seen from in
    front of it (base at ``LANE_Y``); its plane is the line through its points seen from above, the hinge
    where that line meets the run's front, the face to push the one away from its cabinet."""
    pts = np.zeros((0, 3))
    for turn in (0.0, 0.8, -0.8, 1.3, -1.3):
        sk.look(turn)
        pts = _door_points(sk)
        if len(pts) >= 30:
            break
    if len(pts) < 30:
        sk.note("no open cabinet door in sight")
        return None
    x0 = float(np.median(pts[:, 0]))
    sk.tuck()
    sk.goto(x0, LANE_Y, lane=True)
    views = [pts]
    for turn in (0.0, 0.5, -0.5):
        sk.look(turn)
        views.append(_door_points(sk))
    pts = np.concatenate(views)
    pts = pts[np.abs(pts[:, 0] - np.median(pts[:, 0])) < 0.7]
    xy = pts[:, :2]
    c = xy.mean(axis=0)
    w, v = np.linalg.eigh(np.cov((xy - c).T))
    along = v[:, 1] if v[1, 1] < 0 else -v[:, 1]  # towards the free edge (out of the run, -y)
    if abs(along[1]) < 0.2:
        sk.note(f"door points do not stand out of the run (direction {np.round(along, 2)})")
        return None
    hinge = c + along * (DOOR_Y - c[1]) / along[1]
    length = float(np.percentile((xy - hinge) @ along, 98))
    sk.look(0.0)
    side, why = _cabinet_side(sk, hinge, along, length)
    closed = np.array([side, 0.0])  # the closed door runs from the hinge across its cabinet
    opened = float(np.arccos(np.clip(along @ closed, -1.0, 1.0)))
    closing = float(np.sign(along[0] * closed[1] - along[1] * closed[0]))
    normal = np.array([-along[1], along[0]])
    out = normal if normal @ closed < 0 else -normal
    d = OpenDoor(hinge, along, out, length, opened, closing)
    sk.note(
        f"open door: hinge {np.round(hinge, 3)} along {np.round(along, 2)} length {length:.2f} opened {opened:.2f} "
        f"cabinet side {side:+.0f} ({why}), {len(pts)} points, spread {np.round(np.sqrt(w), 3)}"
    )
    return d


def close_door(sk: Skills, d: OpenDoor) -> bool:
    """Push an open hinged door shut: stand facing its outer face, the tool pointing down (a thin hand)
    against it below the handle, and turn the base as a rigid body about the hinge (``Motion.orbit``) by the
    door's opening plus ``DOOR_OVERTURN``, the arm holding its pose on the base. True when the hand ended
    near the closed door's line."""
    reach = max(d.length - DOOR_INSIDE, 0.15)
    contact = np.array([*(d.hinge + reach * d.along + DOOR_CLEAR * d.out), DOOR_PUSH_Z])
    stand = d.hinge + max(reach, DOOR_MIN_SIDE) * d.along + (DOOR_STANDOFF + DOOR_CLEAR) * d.out
    heading = float(np.arctan2(-d.out[1], -d.out[0]))
    sk.tuck()
    sk.goto(float(stand[0]), LANE_Y, lane=True)
    sk.motion.drive_to(float(stand[0]), float(stand[1]), FACING, tol=0.03, max_steps=150)
    sk.motion.drive_to(float(stand[0]), float(stand[1]), heading, tol=0.03, yaw_tol=0.05, max_steps=120)
    sk.home()
    tool = down_quat(heading)
    sk.motion.close_gripper(steps=2)
    sk.motion.move_tool([*contact[:2] + 0.1 * d.out, DOOR_PUSH_Z + 0.1], tool, tol=0.03, max_steps=120)
    sk.motion.move_tool([*contact[:2] + 0.1 * d.out, DOOR_PUSH_Z], tool, tol=0.02, max_steps=60)
    r = sk.motion.move_tool(contact, tool, tol=0.015, max_steps=40, speed=0.5)
    sk.note(
        f"door push from {np.round(sk.obs['base_pos'][:2], 3)}: hand {np.round(sk.obs['ee_pos'], 3)} ({r.reached})"
    )
    # about 4 s of turning; blocked by the shut door, the base stops short of the overturn
    sk.motion.orbit(d.hinge, d.closing * (d.opened + DOOR_OVERTURN), max_steps=140)
    hand = np.asarray(sk.obs["ee_pos"][:2], float)
    ok = abs(float(hand[1]) - DOOR_Y) < 0.15  # the hand stays about 0.1 m out (the shut door stops the turn)
    sk.note(f"door pushed: hand {np.round(hand, 3)}, base {np.round(sk.obs['base_pos'][:2], 3)}")
    sk.motion.move_tool_by([0.0, -0.1, 0.0], tol=0.03, max_steps=30)
    sk.motion.drive_to(float(sk.obs["base_pos"][0]), LANE_Y + 0.1, None, tol=0.05, max_steps=80)
    sk.tuck()
    return ok


FORWARD = np.array([np.cos(-np.pi / 4), np.sin(-np.pi / 4), 0.0, 0.0])
"""Tool z along world +y (into a unit's front), fingers closing along x."""
KNOB_STANDOFF = 0.15
"""Distance of the look-and-refine pose in front of a knob [m]."""
KNOB_BASE_Y = -1.15
"""Base y for work on the stove's knobs [m]."""


def _knob_refine(sk: Skills, prompt: str) -> np.ndarray | None:
    """Knob grip position [m] from the eye-in-hand camera looking at it face-on: the mask's median
    across, its front-most 30 % along the view."""
    pts = sk.see(prompt, cameras=(HAND,), tries=4)
    pts = clean(pts, 0.04)
    if len(pts) < 3:
        return None
    return np.array([np.median(pts[:, 0]), np.percentile(pts[:, 1], 30), np.median(pts[:, 2])])


def turn_knob(sk: Skills, burner: str, on: bool) -> bool:
    """Turn the ``burner`` ("front left" ...) knob on or off (a lit burner's knob stands at +0.9 rad about
    its axis, off within 0.35 rad of 0): find the knob (turning the look pose, else the stove first), stand in
    front of it, look at it face-on from ``KNOB_STANDOFF``, grip its bar and twist."""
    prompt = f"{burner} knob"
    lo, hi = (-np.inf, -np.inf, 0.6), (np.inf, FRONT_Y + 0.02, 1.0)
    pts = sk.find(prompt, lo, hi, turns=(0.0, 0.8, -0.8, 1.3, -1.3), radius=0.04)
    if len(pts) < 3:
        stove = sk.find("stove", (-np.inf, -np.inf, 0.3), (np.inf, 0.0, 1.0), radius=None)
        if len(stove) < 3:
            stove = sk.find_far("stove", (-np.inf, -np.inf, 0.3), (np.inf, 0.0, 1.0))
        if len(stove) < 3:
            sk.note("no stove in sight")
            return False
        sk.tuck()
        sk.goto(float(np.median(stove[:, 0])), KNOB_BASE_Y)
        pts = sk.find(prompt, lo, hi, radius=0.04)
        if len(pts) < 3:
            sk.note(f"no {prompt} in sight")
            return False
    knob = np.median(pts, axis=0)
    sk.note(f"{prompt} near {np.round(knob, 3)}")
    sk.tuck()
    sk.goto(float(knob[0]), KNOB_BASE_Y)
    sk.home()
    sk.motion.open_gripper(steps=2)
    sk.motion.move_tool(knob + [0.0, -KNOB_STANDOFF, 0.0], FORWARD, max_steps=200)
    fine = _knob_refine(sk, prompt)
    if fine is not None:
        knob = fine
    sk.motion.move_tool(knob, FORWARD, max_steps=100, speed=0.5)
    sk.motion.close_gripper(steps=8)
    # The tool turns about +y, the knob's axis points along -y: +0.7 takes an off knob (0) to -0.7 (on),
    # +0.9 takes a lit burner's knob (+0.9) back to 0 (off).
    twist = 0.7 if on else 0.9
    turn = np.array([np.cos(twist / 2), 0.0, np.sin(twist / 2), 0.0])
    sk.motion.move_tool(sk.obs["ee_pos"], quat_mul(turn, FORWARD), max_steps=60, gripper=1.0)
    sk.motion.open_gripper(steps=6)
    sk.motion.move_tool_by([0.0, -0.12, 0.0], max_steps=40)
    sk.note(f"turned {prompt} {'on' if on else 'off'} at {np.round(knob, 3)}")
    sk.tuck()
    return True
