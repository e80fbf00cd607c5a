"""Articulation: push an open drawer shut (``Drawers.push_drawer``, mixed into ``skills.Skills``; with an
object held, ``push_drawer_holding``) and an open hinged door (``close_door``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .kitchen import DOOR_Y, EMPTY, FACING, FRONT_Y, LANE_Y, WORK_TORSO, Drawer, Held
from .motion import down_quat, facing_quat

if TYPE_CHECKING:
    from .fixtures import OpenDoor
    from .skills import Skills

__all__ = ["Drawers", "close_door", "push_drawer_holding"]


class Drawers:
    """Drawer pushing (a method of ``skills.Skills``)."""

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
