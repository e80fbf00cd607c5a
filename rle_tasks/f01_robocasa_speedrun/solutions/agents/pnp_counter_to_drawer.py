"""PickPlaceCounterToDrawer at L3: pick the object off the counter top, drop it into the open drawer.

The open drawer sticks out 0.45 m in front of its cabinet at 0.68-0.88 m, so the base cannot come
near the counter in front of it (its column would hit the drawer) and the object, 0.3-0.5 m behind
the counter's front, is out of reach from there. The base therefore drives beside the drawer, on
the object's side, as close to the counter as its footprint allows (its low deck passes under the
drawer), grasps the object from above, carries it over the drawer and lowers it onto the drawer's
floor near its middle, then lets go and lifts the hand 0.3 m above the object.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from .pick import PICK_ACTIONS, PLACE_ACTIONS, box, out_of_actions, pick, place

COLUMN = 0.16
"""Clearance from the base's centre to the side of the drawer: the column's radius 0.125 m and a margin [m]."""
BASE_FRONT = 0.16
"""Reach of the base's deck in front of its centre [m]."""
CABINET_GAP = 0.05
"""Gap kept between the deck and the fronts of the cabinets (handles, knobs) [m]."""
DECK_HALF_WIDTH = 0.27
"""Half width of the base's deck [m]."""
TALL = 1.2
"""Height of a fixture [m] above which the arm at its home pose would hit its front."""
AVOID = 1.0
"""Cost [m] of a side with a tall fixture (a third of it for the microwave, which the hand passes)."""
VIA = 0.03
"""The hand approaches the object from this far behind the counter's front edge, in front of any
appliance on the counter [m]."""
FACING_WALL = np.pi / 2
"""Base heading that faces the wall [rad]."""


def _footprint(f: dict) -> tuple[float, float, float, float]:
    """x0, x1, y0, y1 of a fixture's footprint [m] (its box turned by its ``yaw``)."""
    yaw = float(f.get("yaw", 0.0))
    c, s = abs(np.cos(yaw)), abs(np.sin(yaw))
    hx = (c * f["size"][0] + s * f["size"][1]) / 2
    hy = (s * f["size"][0] + c * f["size"][1]) / 2
    return f["pos"][0] - hx, f["pos"][0] + hx, f["pos"][1] - hy, f["pos"][1] + hy


def _base_goal(obs: dict, drawer: dict, obj: np.ndarray) -> tuple[float, float, float]:
    """Base position (x, y [m]) beside the drawer, as close to the cabinets as allowed, and the side
    (+1: +x); of the two sides the one nearer the object unless a tall fixture (the fridge, which the
    arm must not hit) or the microwave (which the hand would sweep through) stands there, or another
    run's fixture takes the spot (an L-shaped kitchen's corner)."""
    dx, w = float(drawer["pos"][0]), float(drawer["size"][0])
    best = None
    for side in (1.0, -1.0):
        x = dx + side * (w / 2 + COLUMN)
        y, cost = -np.inf, 0.0
        run = [f for f in obs["fixtures"].values() if abs(float(f.get("yaw", 0.0))) < 1e-6]
        for f in run:
            fx, fw = float(f["pos"][0]), float(f["size"][0])
            front = float(f["pos"][1] - f["size"][1] / 2)
            if f["pos"][2] == 0.0 and abs(fx - x) < fw / 2 + DECK_HALF_WIDTH:
                y = (
                    min(y, front - CABINET_GAP - BASE_FRONT)
                    if np.isfinite(y)
                    else front - CABINET_GAP - BASE_FRONT
                )
                if f["size"][2] > TALL and abs(fx - x) < fw / 2 + 0.15:
                    cost += AVOID
            if f["kind"] == "microwave" and abs(fx - x) < fw / 2 + 0.1:
                cost += AVOID / 3
        for f in obs["fixtures"].values():  # another run's fixture where the base would stand: not there
            if abs(float(f.get("yaw", 0.0))) >= 1e-6 and f["pos"][2] == 0.0:
                x0, x1, y0, y1 = _footprint(f)
                if (
                    x0 < x + DECK_HALF_WIDTH
                    and x1 > x - DECK_HALF_WIDTH
                    and y0 < y + BASE_FRONT
                    and y1 > y - 0.4
                ):
                    cost += 3 * AVOID
        cost += float(np.hypot(obj[0] - x, obj[1] - y))
        if best is None or cost < best[3]:
            best = (x, y, side, cost)
    return best[0], best[1], best[2]


def solve(robot: Robot, motion: Motion) -> bool:
    from rle_tasks.envs.kitchen.harness import world  # L3 only: the L2 program imports constants from here

    obs = robot.observe()
    target = world.target(obs)
    drawer = world.fixture(obs, target["fixture"])
    name = target["object"]
    c, _, _ = box(obs, name)
    x, y, side = _base_goal(obs, drawer, c)
    motion.drive_to(x, float(obs["base_pos"][1]), FACING_WALL, max_steps=120)
    motion.drive_to(x, y, FACING_WALL, max_steps=120)
    counter_z = float(c[2] - box(obs, name)[1][2])
    via = float(drawer["pos"][1] - drawer["size"][1] / 2) + VIA
    held = None
    for _ in range(2):
        if out_of_actions(robot, PICK_ACTIONS + 6):
            break
        held = pick(robot, motion, name, counter_z, via_y=via)
        if held is not None:
            break
        motion.open_gripper(steps=6)
    if held is None or out_of_actions(robot, PLACE_ACTIONS):
        return False
    inner = drawer["interior"]
    ic, ih = np.asarray(inner["center"]), np.asarray(inner["half"])
    floor = float(ic[2] - ih[2])
    drop = np.array([ic[0] + side * min(0.08, ih[0] - 0.08), ic[1] - 0.04])
    place(robot, motion, held, drop, floor, carry_z=counter_z + held.below + 0.08)
    motion.wait(5)
    return bool(robot.observe()["success"])
