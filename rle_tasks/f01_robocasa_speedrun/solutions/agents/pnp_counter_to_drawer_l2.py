"""PickPlaceCounterToDrawer at L2: perceive the object and the open drawer, then the L3 program's
drive, pick and place.

No world state: the object's category comes from the instruction; ``objects_l2`` finds the object
(its top, centre and grasp axis) and the counter under it, the open drawer's floor (height, centre,
pull direction, extents) and how far the fixtures' fronts stand on either side of the drawer. The
base drives beside the drawer on the object's side unless a tall fixture stands there, as the L3
program does; the grasp is re-aimed from the hand camera's view at the pre-grasp pose.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import CAMERAS, Robot

from .objects_l2 import category_of, drawer, front_line, object_seen, support_z, tall_at
from .pick import PICK_ACTIONS, PLACE_ACTIONS, out_of_actions, pick, place
from .pnp_counter_to_drawer import AVOID, BASE_FRONT, CABINET_GAP, COLUMN, DECK_HALF_WIDTH, VIA

SIDE_PANEL = 0.04
"""The drawer cabinet's side beyond the drawer box [m]."""
COUNTER_Z = 0.92
"""Counter height assumed while the counter is not seen [m]."""
HAND = ("robot/arm/eye_in_hand",)


def solve(robot: Robot, motion: Motion) -> bool:
    obs = robot.observe()
    prompt = category_of(obs["instruction"])
    d = None
    for _ in range(3):
        d = drawer(robot)
        if d is not None:
            break
        motion.wait(1)
    if d is None:
        return False
    obj = object_seen(robot, prompt, COUNTER_Z)
    best = None
    for side in (1.0, -1.0):
        at = d.centre + side * (d.half_width + SIDE_PANEL + COLUMN) * d.lateral
        front = front_line(robot, at, d.out, DECK_HALF_WIDTH, d)
        if front is None:
            continue
        goal = at + (front + CABINET_GAP + BASE_FRONT) * d.out
        cost = AVOID if tall_at(robot, at, d.out, front, 0.15) else 0.0
        cost += float(np.linalg.norm(obj.centre[:2] - goal[:2])) if obj is not None else 0.0
        if best is None or cost < best[0]:
            best = (cost, goal, side, front)
    if best is None:
        return False
    _, goal, side, front = best
    heading = float(np.arctan2(-d.out[1], -d.out[0]))
    o = robot.obs
    start = np.asarray(o["base_pos"][:2])
    sideways = start + float(np.dot(goal[:2] - start, d.lateral[:2])) * d.lateral[:2]
    motion.drive_to(sideways[0], sideways[1], heading, max_steps=120)
    motion.drive_to(goal[0], goal[1], heading, max_steps=120)
    near = obj.centre if obj is not None else None
    obj = object_seen(robot, prompt, COUNTER_Z, near) or obj  # seen again from beside the drawer
    if obj is None:
        return False
    counter = support_z(robot, obj.centre) or COUNTER_Z
    obj = object_seen(robot, prompt, counter, obj.centre) or obj
    edge = d.centre + (front - VIA) * d.out  # just behind the fronts, in front of any appliance
    via = obj.centre[:2] + float(np.dot(edge[:2] - obj.centre[:2], d.out[:2])) * d.out[:2]
    last = [obj]

    def locate():
        """The object from the hand camera once above it (else from every camera), else as last seen."""
        cams = HAND if len(last) > 1 else CAMERAS
        s = object_seen(robot, prompt, counter, last[-1].centre, cams) or object_seen(
            robot, prompt, counter, last[-1].centre
        )
        last.append(s or last[-1])
        return last[-1]

    held = None
    for _ in range(2):
        if out_of_actions(robot, PICK_ACTIONS + 6):
            break
        held = pick(robot, motion, None, counter, locate=locate, via=via)
        if held is not None:
            break
        motion.open_gripper(steps=6)
        last[:] = last[:1]
    if held is None or out_of_actions(robot, PLACE_ACTIONS):
        return False
    drop = d.centre + side * min(0.08, d.half[1] - 0.08) * d.lateral + 0.04 * d.out
    place(robot, motion, held, drop[:2], d.floor, carry_z=counter + held.below + 0.08)
    motion.wait(5)
    return bool(robot.observe()["success"])
