"""Placing skills of the LIBERO-10 scripted experts (``experts``), for the ``in``/``on`` predicates:
pick an object from above and release it on a target (a region site, beside the other objects
released there, in front of an open drawer's centre; or an object), and place an object in a region
behind a hinged door by pinching its outward part with the hand pointing through the opening; with
the targets' geometry they need (a target's top centre, whether a position lies in a region)."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from rle_tasks.envs.libero.expert_fixtures import _slide_of
from rle_tasks.envs.libero.expert_grasp import _behind_hand, _grasp
from rle_tasks.envs.libero.expert_motion import (
    CLOSED,
    OPEN,
    _axis_angle,
    _descend,
    _Driver,
    _hold,
    _move,
    _pose,
)

DRAWER_FRONT_SHIFT = 0.025
"""How far in front of a drawer region's centre objects are released [m]."""
SLOT_SPACING, SLOT_GAP = 0.08, 0.01
"""Distance between objects released into the same region [m], widened to an object's extent along
the row plus the gap where it is wider (two moka pots, 0.081 m across, on a 0.15 m cook region)."""
STAGE_OFF = 0.10
"""An object whose grasp a hand pointing horizontally would block (``expert_grasp.HAND_BACK``)
is first set down this far in front of the region behind the door [m]."""
DOOR_APPROACH, DOOR_CLEARANCE, DOOR_DEPTH = 0.07, 0.02, 0.075
"""Placing through a door: approach and back-out distance in front of the pinched part and of the
opening [m]; the object's bottom lifted this far over the region's floor [m]; its body carried
this far past the region's front [m], or until the hand meets the door's frame (task 9: the hand
stops first, the mug's body 5.5 cm past the front)."""


def _pick_place(
    d: _Driver,
    name: str,
    target: str,
    rng: np.random.Generator,
    slot: tuple[int, int] = (0, 1),
    at: np.ndarray | None = None,
) -> Iterator[None]:
    """Pick ``name`` from above and release it on ``target`` (or on the table at the point ``at``)."""
    obj = d.scene["objects"][name]
    bottom = obj["pos"][2] + obj["box_lo"][2]
    yield from _grasp(d, name, rng)
    point, grip_rot, lift_z, lifted, held = d.grasp
    goal = _target_point(d.scene, target) if at is None else np.asarray(at, float)
    drop = goal.copy()
    drop[:2] -= held[:2]  # the object's centre, not the hand, over the target
    k, n = slot
    if n > 1 and target in d.scene["sites"]:  # several objects share a region: side by side
        site = d.scene["sites"][target]
        half = abs(float(site["size"][0]))
        u = site["rot"][:, 0]
        held_obj = d.scene["objects"][name]
        across = float(np.abs(u @ held_obj["rot"]) @ (held_obj["box_hi"] - held_obj["box_lo"]))
        # side by side with a gap, as long as the bodies stay inside the region
        spacing = max(min(2.0 * half / n, SLOT_SPACING), min(across + SLOT_GAP, 2.0 * (half - SLOT_GAP)))
        drop[:2] += (k - (n - 1) / 2.0) * spacing * u[:2]
    drawer = _slide_of(d.scene, target)
    if drawer is not None:  # an open drawer runs under its cabinet's face: release towards its front
        drop[:2] -= DRAWER_FRONT_SHIFT * drawer["axis"][:2]
    # release with the object's bottom a little above the target's top (the grasp point sat above the
    # object's bottom by the same amount as now below the gripper)
    drop[2] = goal[2] + (point[2] - bottom) + 0.03
    over = drop.copy()
    over[2] = max(drop[2] + 0.05, lift_z)
    yield from _move(d, over, grip_rot, CLOSED, tol=0.015)
    yield from _descend(d, drop, grip_rot, CLOSED)
    yield from _hold(d, OPEN, 10)
    up = d.scene["eef_pos"].copy()
    up[2] += 0.1
    yield from _move(d, up, grip_rot, OPEN, tol=0.02, max_steps=20)
    p = d.scene["objects"][name]["pos"]
    if at is not None:
        d.log.append(
            f"{name} -> {np.round(at, 3).tolist()}: lifted {lifted:.3f} m, left at {np.round(p, 3).tolist()}"
        )
        return
    where = "in the target box" if _inside(d.scene, target, p) else "outside the target box"
    d.log.append(f"{name} -> {target}: lifted {lifted:.3f} m, left at {np.round(p, 3).tolist()} ({where})")


def _through_door(
    d: _Driver, name: str, target: str, front: np.ndarray, rng: np.random.Generator
) -> Iterator[None]:
    """Place ``name`` in a region behind a hinged door (a mug into a microwave, task 9): the hand,
    pointing through the opening with its fingers horizontal, pinches the object's part that faces
    the opening's outside (a mug's handle bar), lifts it over the cavity's floor, carries it in until
    its body is ``DOOR_DEPTH`` past the region's front or the hand meets the frame, lowers it, lets
    go and backs out. From above,
    the hand holding a mug's rim is higher than the opening (README)."""
    bar = d.env.far_box(name)
    obj = d.scene["objects"][name]
    if bar is None or (bar["pos"] - obj["pos"])[:2] @ front[:2] <= 0.0:
        d.log.append(f"{name} -> {target}: no part of it faces the opening's outside")
        return
    inward = -front

    def pointing(approach: np.ndarray) -> np.ndarray:
        """Fingers horizontal, approach axis ``approach``: of the two such hands the one nearer the
        current orientation."""
        best = None
        x = np.cross([0.0, 0.0, 1.0], approach)
        for sgn in (1.0, -1.0):
            rot = np.column_stack([sgn * x, np.cross(approach, sgn * x), approach])
            angle = float(np.linalg.norm(_axis_angle(rot @ d.scene["eef_rot"].T)))
            if best is None or angle < best[0]:
                best = (angle, rot)
        return best[1]

    site = d.scene["sites"][target]
    depth = float(np.abs(site["rot"][:2, :2] @ site["size"][:2]) @ np.abs(inward[:2]))
    others = [o for n, o in d.scene["objects"].items() if n != name]
    if _behind_hand(bar["pos"], inward, others):
        # the hand and forearm, horizontal behind the pinched part, would sweep a neighbour (the
        # other mug): set the object down in front of the opening first, from above
        stage = site["pos"] - (depth + STAGE_OFF) * inward
        stage[2] = obj["pos"][2] + obj["box_lo"][2]
        yield from _pick_place(d, name, target, rng, at=stage)
        bar = d.env.far_box(name)
        obj = d.scene["objects"][name]
        if bar is None or (bar["pos"] - obj["pos"])[:2] @ front[:2] <= 0.0:
            d.log.append(f"{name} -> {target}: set down turned, no part of it faces the opening's outside")
            return
    grasp = bar["pos"].copy()
    grasp[:2] += rng.normal(0.0, 0.002, 2)
    approach = inward
    rot = pointing(approach)
    back = grasp - approach * DOOR_APPROACH
    high = back.copy()
    high[2] = max(grasp[2] + 0.12, d.scene["eef_pos"][2])
    yield from _pose(d, high, rot, OPEN, tol=0.02, max_steps=80)
    yield from _pose(d, back, rot, OPEN, tol=0.01, max_steps=40)
    yield from _move(d, grasp, rot, OPEN, tol=0.006, gain=0.6, max_steps=40)
    yield from _hold(d, CLOSED, 12)
    rot = pointing(inward)  # straight through the opening from here on
    floor = float(site["pos"][2] - abs(site["size"][2]))
    held = d.scene["objects"][name]
    bottom = held["pos"][2] + held["box_lo"][2]
    lift = d.scene["eef_pos"] + np.array([0.0, 0.0, max(0.0, floor - bottom) + DOOR_CLEARANCE])
    yield from _pose(d, lift, rot, CLOSED, tol=0.01, max_steps=30)
    held = d.scene["objects"][name]
    lifted = float(held["pos"][2] + held["box_lo"][2] - bottom)
    grip_to_body = d.scene["eef_pos"] - held["pos"]
    # the body's position: the region's centre across the opening, DOOR_DEPTH past its front
    goal = site["pos"].copy()
    goal[:2] += (DOOR_DEPTH - depth) * inward[:2]
    inside = goal + grip_to_body
    inside[2] = d.scene["eef_pos"][2]
    before = inside + front * DOOR_APPROACH
    yield from _pose(d, before, rot, CLOSED, tol=0.01, max_steps=60)
    yield from _move(d, inside, rot, CLOSED, tol=0.004, gain=0.6, max_steps=60, stall=5)
    down = d.scene["eef_pos"] - np.array([0.0, 0.0, DOOR_CLEARANCE - 0.005])
    yield from _move(d, down, rot, CLOSED, tol=0.005, gain=0.5, max_steps=10)
    yield from _hold(d, OPEN, 10)
    out = d.scene["eef_pos"] + front * DOOR_APPROACH
    yield from _move(d, out, rot, OPEN, tol=0.02, max_steps=30)
    p = d.scene["objects"][name]["pos"]
    where = "in the target box" if _inside(d.scene, target, p) else "outside the target box"
    d.log.append(
        f"{name} -> {target} (through the door): lifted {lifted:.3f} m, left at "
        f"{np.round(p, 3).tolist()} ({where})"
    )


def _inside(sc: dict, target: str, p: np.ndarray) -> bool:
    """Whether a body position lies in a region site's ``in`` box (objects as targets: not judged)."""
    s = sc["sites"].get(target)
    return s is not None and bool(np.all(p > s["in_lb"]) and np.all(p < s["in_ub"]))


def _target_point(sc: dict, target: str) -> np.ndarray:
    """Top centre of a target: a region site (its box's top face) or an object (its box's top)."""
    if target in sc["sites"]:
        s = sc["sites"][target]
        p = s["pos"].copy()
        p[2] = s["pos"][2] - s["size"][2] if s["size"][2] > 0.02 else s["pos"][2]
        return p
    o = sc["objects"][target]
    p = o["pos"] + o["rot"] @ ((o["box_lo"] + o["box_hi"]) / 2.0)
    p[2] = o["pos"][2] + o["box_hi"][2]
    return p
