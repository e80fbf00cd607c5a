"""Grasp planning of the LIBERO-10 scripted experts (``experts``): the Panda hand's footprint and
its overlap with neighbouring objects' collision boxes, the choice of a top-down grasp (fingers
across an object's narrower side, at an angle or shifted along it, or pinching a hollow object's
rim) that keeps the hand clear of the neighbours, the grasp-and-lift skill with its retries, and the
check whether a hand pointing horizontally would meet a neighbour behind its grip point."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from rle_tasks.envs.libero.expert_motion import CLOSED, OPEN, _descend, _Driver, _hold, _move, _rz

FINGER_AXIS = 0
"""Axis of the end-effector site frame along which the Panda's fingers close."""
MAX_GRASP_WIDTH = 0.07
"""Widest object span the open fingers take with room to spare [m] (the Panda opens to 0.08 m)."""
HAND_HALF, HAND_WIDTH = 0.11, 0.07
"""Footprint of the Panda hand with open fingers: half-length along the fingers, width across [m]."""
HAND_LIFT = 0.005
"""Height of the hand's collision body above the grasp point (the finger pads' centre) [m]."""
WALL_IN, RIM_DEPTH = 0.006, 0.025
"""A rim grasp holds the wall this far inside the outer surface and this far below the top [m]."""
HIGH_GRASP_DEPTH = 0.012
"""A repeated grasp holds the object this far below its top, at its body's axis [m]."""
GRASP_TRIES = 3
"""Attempts at one grasp before the expert moves on."""
HAND_BACK = 0.22
"""A hand pointing horizontally, with its forearm, occupies this far behind its grip point [m]
(task 9: at 0.17 m the hand met the other mug)."""
HIGH_FIRST = ("moka_pot",)
"""Objects whose first grasp is the high one (at the body's axis, below the top): a moka pot's handle
and spout rise above its body and stop the hand of a grasp across its box (task 8)."""


def _world_box(obj: dict) -> tuple[np.ndarray, np.ndarray]:
    """World axis-aligned bounds of an object's collision box."""
    lo, hi = obj["box_lo"], obj["box_hi"]
    corners = np.array([[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1]) for c in (lo[2], hi[2])])
    world = obj["pos"] + corners @ obj["rot"].T
    return world.min(0), world.max(0)


def _hand_overlap(center: np.ndarray, finger_dir: np.ndarray, z_bottom: float, others: list[dict]) -> float:
    """Summed overlap [m^2] of the hand's footprint (HAND_HALF along the fingers, HAND_WIDTH/2 across)
    with the horizontal boxes of the objects whose tops rise above the hand's lower face."""
    across = np.array([-finger_dir[1], finger_dir[0]])
    corners = np.array(
        [
            center[:2] + a * HAND_HALF * finger_dir[:2] + b * HAND_WIDTH / 2 * across
            for a in (-1, 1)
            for b in (-1, 1)
        ]
    )
    lo, hi = corners.min(0), corners.max(0)
    total = 0.0
    for o in others:
        olo, ohi = _world_box(o)
        if ohi[2] < z_bottom:
            continue
        w = min(hi[0], ohi[0]) - max(lo[0], olo[0])
        h = min(hi[1], ohi[1]) - max(lo[1], olo[1])
        if w > 0 and h > 0:
            total += w * h
    return total


def _rim_grasp(point, top, narrow, width, others) -> tuple[float, np.ndarray, np.ndarray]:
    """(cost, finger direction, grasp point) pinching the wall of a hollow object at the end of its
    narrower axis: fingers close radially across the wall, RIM_DEPTH below the top."""
    u = np.array([narrow[0], narrow[1], 0.0]) / max(1e-9, np.hypot(narrow[0], narrow[1]))
    best = None
    for sign in (1.0, -1.0):
        p = point + sign * (width / 2 - WALL_IN) * u
        p[2] = top - RIM_DEPTH
        cost = _hand_overlap(p, u, p[2] + HAND_LIFT, others)
        if best is None or cost < best[0]:
            best = (cost, u, p)
    return best


def _grasp_frame(
    d: _Driver, name: str, yaw_jitter: float, high: bool = False
) -> tuple[np.ndarray, np.ndarray, float]:
    """(grasp point, gripper rotation, object height) of a top-down grasp.

    The fingers close across the object's narrower side, or at an angle to it (steps of 15 degrees)
    at which the object still fits between them, and the grasp may move along the object's long side
    (up to 3 cm): the choice keeps the hand's footprint clear of the neighbouring objects that rise
    above its lower face, and otherwise stays closest to a centred grasp across the narrower side.
    """
    sc = d.scene
    obj = sc["objects"][name]
    lo, hi = obj["box_lo"], obj["box_hi"]
    rot = obj["rot"]
    center = obj["pos"] + rot @ ((lo + hi) / 2.0)
    ext = hi - lo
    narrow_i = 0 if ext[0] <= ext[1] else 1
    narrow, wide = rot[:, narrow_i], rot[:, 1 - narrow_i]
    a, b = float(ext[narrow_i]), float(ext[1 - narrow_i])
    top = max(center[2] + abs(rot[2] @ ((hi - lo) / 2.0)), center[2])
    height = float(ext[2])
    point = center.copy()
    point[2] = max(top - min(0.03, 0.5 * height), center[2] - 0.5 * height + 0.01)
    if high:
        point[:2] = obj["pos"][:2]
        point[2] = top - HIGH_GRASP_DEPTH
    others = [o for n, o in sc["objects"].items() if n != name]
    wide_h = np.array([wide[0], wide[1], 0.0]) / max(1e-9, np.hypot(wide[0], wide[1]))
    reach = max(0.0, b / 2 - 0.02)  # the fingers stay 2 cm inside the object's ends
    best = None
    for k in (0, 1, -1, 2, -2, 3, -3, 4, -4, 5, -5, 6):
        th = k * np.pi / 12
        if a * abs(np.cos(th)) + b * abs(np.sin(th)) > MAX_GRASP_WIDTH:
            continue
        fdir = np.cos(th) * narrow + np.sin(th) * wide
        fdir = np.array([fdir[0], fdir[1], 0.0]) / max(1e-9, np.hypot(fdir[0], fdir[1]))
        for shift in (0.0, 0.015, -0.015, 0.03, -0.03):
            if abs(shift) > reach:
                continue
            p = point + shift * wide_h
            cost = _hand_overlap(p, fdir, p[2] + HAND_LIFT, others) + 1e-5 * (abs(k) + 100 * abs(shift))
            if best is None or cost < best[0]:
                best = (cost, fdir, p)
    if best is None:  # wider than the open fingers everywhere (a mug, a bowl): pinch the rim
        best = _rim_grasp(point, top, narrow, a, others)
    fdir, point = best[1], best[2]
    finger = d.down[:, FINGER_AXIS]
    yaw_now = np.arctan2(finger[1], finger[0])
    dyaw = (np.arctan2(fdir[1], fdir[0]) - yaw_now + np.pi / 2) % np.pi - np.pi / 2 + yaw_jitter
    return point, _rz(dyaw) @ d.down, height


def _grasp(d: _Driver, name: str, rng: np.random.Generator) -> Iterator[None]:
    """Pick ``name`` from above and lift it; up to ``GRASP_TRIES`` attempts (an attempt that leaves
    the object on the table opens, rises and aims again). Sets ``d.grasp`` = (grasp point, gripper
    rotation, lift height, lifted [m])."""
    lifted, safe_z = 0.0, d.scene["eef_pos"][2]
    for attempt in range(GRASP_TRIES):
        yaw, offset = float(rng.normal(0.0, 0.05)), rng.normal(0.0, 0.003, 2)
        # after a miss: the object's top at its body axis (a lid knob, a cap)
        high = attempt > 0 or name.startswith(HIGH_FIRST)
        point, grip_rot, _ = _grasp_frame(d, name, yaw, high)
        point[:2] += offset
        safe_z = max(point[2] + 0.12, d.scene["eef_pos"][2])
        above = point.copy()
        above[2] = safe_z
        yield from _move(d, above, grip_rot, OPEN, tol=0.015)
        # the object may have moved (settling, a neighbour's release): aim at where it is now
        point, grip_rot, _ = _grasp_frame(d, name, yaw, high)
        point[:2] += offset
        above = point.copy()
        above[2] = safe_z
        yield from _move(d, above, grip_rot, OPEN, tol=0.008, max_steps=20)
        yield from _descend(d, point, grip_rot, OPEN)
        yield from _hold(d, CLOSED, 12)
        z_grasp = d.scene["objects"][name]["pos"][2]
        lift = d.scene["eef_pos"].copy()
        lift[2] = safe_z + 0.05
        yield from _move(d, lift, grip_rot, CLOSED, tol=0.02)
        held = d.scene["objects"][name]
        lifted = float(held["pos"][2] - z_grasp)
        # where the hand holds the object: the object's box centre relative to the end effector
        center = held["pos"] + held["rot"] @ ((held["box_lo"] + held["box_hi"]) / 2.0)
        d.grasp = (point, grip_rot, lift[2], lifted, center - d.scene["eef_pos"])
        if lifted > 0.03 or d.done:
            return
        yield from _hold(d, OPEN, 6)


def _behind_hand(grip: np.ndarray, approach: np.ndarray, others: list[dict]) -> bool:
    """Whether a hand pointing horizontally along ``approach`` with its grip point at ``grip`` (and
    its forearm behind it, ``HAND_BACK`` along the approach, ``HAND_HALF`` each side) meets an
    object that rises above the hand's lower face: sampled on a grid of its footprint."""
    across = np.cross([0.0, 0.0, 1.0], approach)[:2]
    z_bottom = grip[2] - HAND_WIDTH / 2
    boxes = [b for b in (_world_box(o) for o in others) if b[1][2] > z_bottom]
    for t in np.linspace(0.02, HAND_BACK, 8):
        for w in np.linspace(-HAND_HALF, HAND_HALF, 9):
            q = grip[:2] - t * approach[:2] + w * across
            if any(np.all(q > lo[:2]) and np.all(q < hi[:2]) for lo, hi in boxes):
                return True
    return False
