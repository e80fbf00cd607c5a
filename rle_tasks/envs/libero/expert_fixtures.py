"""Articulated-fixture skills of the LIBERO-10 scripted experts (``experts``): finding the joint a
``close``/``turnon`` predicate or a region refers to (a drawer's slide, a door's or a knob's hinge),
the geometry of a hinged door (the opening it closes, its closed direction, reach and thickness),
and the skills that act on fixtures: push a drawer shut along its slide, swing a hinged door shut
along its arc, turn a stove's knob on about its axis."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from rle_tasks.envs.libero.expert_grasp import FINGER_AXIS, HAND_WIDTH
from rle_tasks.envs.libero.expert_motion import (
    CLOSED,
    OPEN,
    _descend,
    _Driver,
    _hold,
    _move,
    _pose,
    _rotation,
    _rz,
)

PUSH_GAP = 0.03
"""Gap between the fingers and a drawer's face before a push [m]."""
KNOB_TURN, KNOB_STEPS, KNOB_DEPTH = 0.9, 9, 0.015
"""A knob is turned by this angle [rad] in this many way points, gripped this far below its top [m]."""
PUSH_TILT = 0.6
"""Tilt of the fingers towards a push from pointing down [rad]."""
PUSH_TRIES = 3
"""Pushes at a drawer before the expert moves on."""
HINGE_PUSH_AT = 0.75
"""Where the fingers push a hinged door: this fraction of the door's reach from its hinge [1]."""
HINGE_STEP, HINGE_GAP, HINGE_PAST = 0.2, 0.01, 0.4
"""Door angle between two way points of a hinged-door push [rad]; gap between the hand's side and
the door's outer face (with its handle) before the push [m]; the way points run this far past
closed [rad]: the hand stands off the door by its handle's thickness, which the door is thinner
than where the hand pushes (6.4 cm measured on the microwave: 0.15 rad past left it at -0.03 rad,
not closed)."""
DOOR_MIN_REACH = 0.15
"""Least reach of a hinged part from its axis for it to be a door [m]: LIBERO-10's microwave door
reaches 0.267 m, the stove's knob (task 2, whose cook region is not behind anything) 0.071 m."""


def _joint_of(sc: dict, target: str) -> str:
    """The articulated joint a ``close``/``turnon`` predicate's argument refers to: the object's only
    joint, or for a region the joint of the same level (``white_cabinet_1_bottom_region`` ->
    ``white_cabinet_1_bottom_level``)."""
    names = list(sc["joints"])
    stem = target[: -len("_region")] if target.endswith("_region") else target
    for j in names:
        if j.startswith(stem):
            return j
    owner = [j for j in names if j.startswith(stem.rsplit("_", 1)[0])]
    if len(owner) == 1:
        return owner[0]
    raise NotImplementedError(f"no articulated joint for '{target}' among {names}")


def _slide_of(sc: dict, target: str) -> dict | None:
    """The slide joint (a drawer) a target region belongs to, or None."""
    if not target.endswith("_region"):
        return None
    try:
        j = sc["joints"][_joint_of(sc, target)]
    except NotImplementedError:
        return None
    return None if j["hinge"] else j


def _door_front(sc: dict, target: str) -> np.ndarray | None:
    """Outward normal of the opening a hinged door closes (horizontal unit vector), for a region
    behind such a door (a microwave's heating region), else None: such a region is placed into
    through the opening (``_through_door``). A hinged part that reaches less than
    ``DOOR_MIN_REACH`` from its axis (a knob) is no door."""
    if not target.endswith("_region") or target not in sc["sites"]:
        return None
    try:
        j = sc["joints"][_joint_of(sc, target)]
    except NotImplementedError:
        return None
    if not j["hinge"]:
        return None
    axis = j["axis"] / np.linalg.norm(j["axis"])
    anchor = np.asarray(j["anchor"], float)
    far = np.array(
        [[x, y] for x in (j["part_lo"][0], j["part_hi"][0]) for y in (j["part_lo"][1], j["part_hi"][1])]
    )
    radial = np.c_[far - anchor[:2], np.zeros(len(far))]
    reach = np.linalg.norm(radial, axis=1)
    if reach.max() < DOOR_MIN_REACH:
        return None
    u = radial[int(np.argmax(reach))]
    u_closed = _rotation(axis, float(j["range"][1] - j["qpos"])) @ (u / np.linalg.norm(u))
    n = np.cross(axis, u_closed)
    n[2] = 0.0
    n /= np.linalg.norm(n)
    # the box's far corner includes the door's thickness (14 degrees off on the microwave): the
    # opening faces along the region's horizontal axis closest to this estimate
    frame = sc["sites"][target]["rot"]
    n = max((frame[:, 0], frame[:, 1]), key=lambda a: abs(a @ n)) * 1.0
    n[2] = 0.0
    n /= np.linalg.norm(n)
    return n if n @ (anchor - sc["sites"][target]["pos"]) > 0 else -n


def _back_off(d: _Driver, rot: np.ndarray, push: np.ndarray, dist: float) -> Iterator[None]:
    """After a push: back away from the pushed part by ``dist`` against ``push`` and rise 10 cm."""
    back = d.scene["eef_pos"] - push * dist
    back[2] += 0.1
    yield from _move(d, back, rot, CLOSED, tol=0.02, max_steps=15)


def _log_close(d: _Driver, name: str, q0: float, kind: str) -> None:
    j = d.scene["joints"][name]
    d.log.append(
        f"close {name}{kind}: q {q0:.3f} -> {j['qpos']:.3f} (range {np.round(j['range'], 3).tolist()})"
    )


def _close_slide(d: _Driver, target: str) -> Iterator[None]:
    """Push a drawer shut: fingers closed, lowered in front of its face, pushed along the slide to the
    closed end of its range (LIBERO's cabinets close towards the top of the range)."""
    name = _joint_of(d.scene, target)
    q0 = d.scene["joints"][name]["qpos"]
    # the hand's thin side leads: its long axis (along the fingers) across the push
    ax = d.scene["joints"][name]["axis"]
    finger = d.down[:, FINGER_AXIS]
    dyaw = (np.arctan2(ax[0], -ax[1]) - np.arctan2(finger[1], finger[0]) + np.pi / 2) % np.pi - np.pi / 2
    rot = _rz(dyaw) @ d.down
    # fingers tilted towards the push: the forearm stays clear of the cabinet's face
    tilt = np.cross(ax / np.linalg.norm(ax), [0.0, 0.0, 1.0])
    rot = _rotation(tilt / max(1e-9, np.linalg.norm(tilt)), PUSH_TILT) @ rot
    for _ in range(PUSH_TRIES):
        j = d.scene["joints"][name]
        travel = float(j["range"][1] - j["qpos"])
        if travel <= 0.003 or d.done:
            break
        axis = j["axis"] / np.linalg.norm(j["axis"])
        lo, hi = j["part_lo"], j["part_hi"]
        center = (lo + hi) / 2.0
        half = float(np.abs(axis) @ ((hi - lo) / 2.0))
        start = center - axis * (half + PUSH_GAP)
        start[2] = lo[2] + 0.6 * (hi[2] - lo[2])
        above = start.copy()
        above[2] = max(hi[2] + 0.08, d.scene["eef_pos"][2])
        yield from _move(d, above, rot, CLOSED, tol=0.015)
        yield from _descend(d, start, rot, CLOSED)
        end = start + axis * (travel + PUSH_GAP + 0.01)
        yield from _move(d, end, rot, CLOSED, tol=0.01, gain=0.5, max_steps=80)
        yield from _back_off(d, rot, axis, 0.03)
    _log_close(d, name, q0, "")


def _leaf(sc: dict, target: str, name: str) -> tuple[np.ndarray, float, float]:
    """(closed direction, reach [m], thickness on the outer side [m]) of the hinged door ``name``
    of object ``target``: the direction from the hinge along the door when closed, snapped to the
    object's nearest horizontal axis (the door's bounding box alone is off by its thickness: 14
    degrees on the microwave), how far the door reaches, and how far its outer face (with any
    handle) stands off the hinge line, towards which the door swings open."""
    j = sc["joints"][name]
    axis = j["axis"] / np.linalg.norm(j["axis"])
    anchor = np.asarray(j["anchor"], float)
    radial = np.asarray(j["part_corners"], float) - anchor
    radial -= np.outer(radial @ axis, axis)
    reach = float(np.linalg.norm(radial, axis=1).max())
    far = radial[int(np.argmax(np.linalg.norm(radial, axis=1)))]
    closed = _rotation(axis, float(j["range"][1] - j["qpos"])) @ (far / reach)
    frame = sc["objects"][target]["rot"] if target in sc["objects"] else np.eye(3)
    snapped = max((frame[:, 0], -frame[:, 0], frame[:, 1], -frame[:, 1]), key=lambda a: float(a @ closed))
    u_now = _rotation(axis, float(j["qpos"] - j["range"][1])) @ snapped
    t = np.cross(axis, u_now)  # where the door's points go as it closes
    thick = float(max(0.0, -(radial @ t).min()))
    return snapped, reach, thick


def _close_hinge(d: _Driver, target: str) -> Iterator[None]:
    """Swing a hinged door shut: fingers closed and pointing down, the hand's thin side towards the
    door, lowered off its outer face at ``HINGE_PUSH_AT`` of its reach, then carried along the arc
    that point follows towards the closed end of the range (LIBERO's microwave closes at 0),
    ``HINGE_STEP`` a way point, the hand turning with the door, a little past closed so it seats."""
    name = _joint_of(d.scene, target)
    j = d.scene["joints"][name]
    q0 = float(j["qpos"])
    axis = j["axis"] / np.linalg.norm(j["axis"])
    anchor = np.asarray(j["anchor"], float)
    u_closed, reach, thick = _leaf(d.scene, target, name)
    z = float(j["part_lo"][2] + 0.5 * (j["part_hi"][2] - j["part_lo"][2]))
    off = thick + HAND_WIDTH / 2 + HINGE_GAP  # the hand's centre off the hinge line
    finger = d.down[:, FINGER_AXIS]
    q_closed = float(j["range"][1])
    turn = float(np.sign(axis[2]) or 1.0)
    for _ in range(PUSH_TRIES):
        q = float(d.scene["joints"][name]["qpos"])
        remaining = q_closed - q
        if remaining <= 0.02 or d.done:
            break

        u_now = _rotation(axis, q - q_closed) @ u_closed
        # the hand's long side (along the fingers) along the door: the nearer of the two ways now,
        # then turning with the door (continuously: no half turn where the nearer way changes)
        yaw0 = (
            np.arctan2(u_now[1], u_now[0]) - np.arctan2(finger[1], finger[0]) + np.pi / 2
        ) % np.pi - np.pi / 2

        def point(
            theta: float, q: float = q, yaw0: float = yaw0
        ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            u = _rotation(axis, q - q_closed + theta) @ u_closed
            t = np.cross(axis, u)
            p = anchor + HINGE_PUSH_AT * reach * u - off * t
            p[2] = z
            return p, t, _rz(yaw0 + turn * theta) @ d.down

        start, t, rot = point(0.0)
        above = start.copy()
        above[2] = max(float(j["part_hi"][2]) + 0.04, d.scene["eef_pos"][2])
        if d.scene["eef_pos"][2] < above[2] - 0.02:  # up first: over the door, never through it
            up = d.scene["eef_pos"].copy()
            up[2] = above[2]
            yield from _move(d, up, rot, CLOSED, tol=0.02, max_steps=20)
        yield from _pose(d, above, rot, CLOSED, tol=0.015, rot_tol=0.1)
        yield from _descend(d, start, rot, CLOSED)
        for theta in np.arange(HINGE_STEP, remaining + HINGE_PAST, HINGE_STEP):
            p, t, rot = point(float(theta))
            # past closed the door stops the hand: a short press each
            steps = 25 if theta < remaining + HINGE_STEP else 8
            yield from _pose(d, p, rot, CLOSED, tol=0.015, rot_tol=0.1, gain=0.7, max_steps=steps)
        yield from _back_off(d, rot, t, 0.05)
    _log_close(d, name, q0, " (hinge)")


def _turn_on(d: _Driver, target: str) -> Iterator[None]:
    """Turn a stove's knob on: pinch its bar across the narrower side, then turn the hand about the
    knob's axis (positions on the arc, the hand's yaw with it) to ``KNOB_TURN`` past the current
    angle; LIBERO's stoves are on from 0.5 rad."""
    name = _joint_of(d.scene, target)
    j = d.scene["joints"][name]
    q0 = j["qpos"]
    h = j["handle"]
    narrow_i = 0 if h["half"][0] <= h["half"][1] else 1
    narrow = h["rot"][:, narrow_i]
    finger = d.down[:, FINGER_AXIS]
    dyaw = (
        np.arctan2(narrow[1], narrow[0]) - np.arctan2(finger[1], finger[0]) + np.pi / 2
    ) % np.pi - np.pi / 2
    rot0 = _rz(dyaw) @ d.down
    top = h["pos"][2] + float(np.abs(h["rot"][2]) @ h["half"])
    point = h["pos"].copy()
    point[2] = top - KNOB_DEPTH
    above = point.copy()
    above[2] = max(top + 0.08, d.scene["eef_pos"][2])
    yield from _move(d, above, rot0, OPEN, tol=0.01)
    yield from _descend(d, point, rot0, OPEN)
    yield from _hold(d, CLOSED, 10)
    axis_pt = j["anchor"]
    grip = d.scene["eef_pos"].copy()
    sign = 1.0 if j["axis"][2] >= 0 else -1.0
    for k in range(1, KNOB_STEPS + 1):
        phi = sign * KNOB_TURN * k / KNOB_STEPS
        r = _rz(phi)
        pos = axis_pt + r @ (grip - axis_pt)
        for _ in range(3):
            if d.done:
                return
            d.act(d.toward(pos, r @ rot0, CLOSED))
            yield
    yield from _hold(d, OPEN, 6)
    up = d.scene["eef_pos"].copy()
    up[2] += 0.08
    yield from _move(d, up, d.scene["eef_rot"], OPEN, tol=0.02, max_steps=15)
    q = d.scene["joints"][name]["qpos"]
    d.log.append(f"turn on {name}: q {q0:.3f} -> {q:.3f}")
