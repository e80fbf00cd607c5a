"""State-based scripted experts for LIBERO-10 (they make family 05's demonstrations).

An expert reads the simulator's state (``LiberoEnv.scene``: end effector, object poses and collision
boxes, region sites, articulated joints, the BDDL goal), never an image, and drives the robot through
the policy interface: 7-D OSC actions at 20 Hz. It turns each goal predicate into a skill:

- ``in``/``on`` object, region-or-object: pick the object from above (fingers across its narrower
  side, grasp below its top) and release it above the target;
- ``turnon`` stove: turn the knob; ``close`` drawer or door: push it shut.

Each skill is a generator of actions; ``run_expert`` chains the skills of the goal in an order that
keeps them feasible (a drawer is filled before it is closed) and stops at success or the horizon.
Randomness (start jitter, grasp offsets) comes from the caller's seeded generator, so demonstrations
are reproducible.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from rle_tasks.envs.libero import LiberoEnv

__all__ = ["ExpertResult", "run_expert"]

POS_STEP = 0.05
"""Largest end-effector displacement of one action unit [m] (robosuite OSC ``output_max``)."""
ROT_STEP = 0.5
"""Largest rotation of one action unit [rad]."""
OPEN, CLOSED = -1.0, 1.0
FINGER_AXIS = 0
"""Axis of the end-effector site frame along which the Panda's fingers close."""
SETTLE_STEPS = 20
"""Steps held after the last skill for released objects to come to rest (success is checked per step)."""


@dataclass(frozen=True)
class ExpertResult:
    success: bool
    steps: int
    actions: np.ndarray
    """(steps, 7) the actions sent."""
    log: tuple[str, ...] = ()
    """One line per skill: what it did and what it left (for statistics and debugging)."""


def _axis_angle(rot: np.ndarray) -> np.ndarray:
    """Rotation vector of a rotation matrix [rad]."""
    c = np.clip((np.trace(rot) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(c)
    if angle < 1e-9:
        return np.zeros(3)
    axis = np.array([rot[2, 1] - rot[1, 2], rot[0, 2] - rot[2, 0], rot[1, 0] - rot[0, 1]])
    n = np.linalg.norm(axis)
    if n < 1e-9:  # angle ~ pi: the axis from the symmetric part
        w, v = np.linalg.eigh(rot)
        axis = v[:, np.argmax(w)]
        return axis * angle
    return axis / n * angle


def _rz(yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class _Driver:
    """Closes the loop between skills and the environment, one action per control step."""

    def __init__(self, env: LiberoEnv, horizon: int) -> None:
        self.env, self.horizon = env, horizon
        self.scene = env.scene()
        self.down = self.scene["eef_rot"].copy()  # the start orientation: fingers down
        self.actions: list[np.ndarray] = []
        self.success = False
        self.log: list[str] = []

    @property
    def done(self) -> bool:
        return self.success or len(self.actions) >= self.horizon

    def act(self, action: np.ndarray) -> None:
        _, self.success = self.env.step(action)
        self.actions.append(np.asarray(action, dtype=np.float64))
        self.scene = self.env.scene()

    def toward(self, pos: np.ndarray, rot: np.ndarray, grip: float, gain: float = 1.0) -> np.ndarray:
        sc = self.scene
        dp = np.clip(gain * (pos - sc["eef_pos"]) / POS_STEP, -1.0, 1.0)
        dr = np.clip(_axis_angle(rot @ sc["eef_rot"].T) / ROT_STEP, -1.0, 1.0)
        return np.concatenate([dp, dr, [grip]])


def _move(d: _Driver, pos, rot, grip, tol=0.01, max_steps=60, gain=1.0) -> Iterator[None]:
    for _ in range(max_steps):
        if d.done or np.linalg.norm(d.scene["eef_pos"] - pos) < tol:
            return
        d.act(d.toward(np.asarray(pos, float), rot, grip, gain))
        yield


def _descend(
    d: _Driver, point: np.ndarray, rot: np.ndarray, grip: float, max_steps: int = 60
) -> Iterator[None]:
    """Straight down onto ``point``: the horizontal error is removed before the gripper drops further
    (fingers a few mm from an object's side), and the descent ends early when the fingers rest on
    something (no progress for five steps)."""
    heights: list[float] = []  # while descending
    for _ in range(max_steps):
        if d.done:
            return
        e = point - d.scene["eef_pos"]
        if np.linalg.norm(e) < 0.005:
            return
        target = point.copy()
        if np.hypot(e[0], e[1]) > 0.004:
            target[2] = d.scene["eef_pos"][2]  # hold the height until centred
            heights.clear()
        else:
            heights.append(float(d.scene["eef_pos"][2]))
            if len(heights) > 5 and heights[-6] - heights[-1] < 0.001:
                return  # resting on the table or the object
        a = d.toward(target, rot, grip, gain=0.7)
        a[2] = np.clip(a[2], -0.5, 0.5)  # at most 2.5 cm a step near objects
        d.act(a)
        yield


def _hold(d: _Driver, grip: float, steps: int) -> Iterator[None]:
    pos, rot = d.scene["eef_pos"].copy(), d.scene["eef_rot"].copy()
    for _ in range(steps):
        if d.done:
            return
        d.act(d.toward(pos, rot, grip))
        yield


def _grasp_frame(d: _Driver, obj: dict, yaw_jitter: float) -> tuple[np.ndarray, np.ndarray, float]:
    """(grasp point, gripper rotation, object height) of a top-down grasp across the narrower side."""
    lo, hi = obj["box_lo"], obj["box_hi"]
    rot = obj["rot"]
    center = obj["pos"] + rot @ ((lo + hi) / 2.0)
    ext = hi - lo
    # the object's horizontal axes in the world; fingers (gripper y axis) close along the narrower one
    ax_x, ax_y = rot[:, 0], rot[:, 1]
    narrow = ax_x if ext[0] <= ext[1] else ax_y
    yaw_obj = np.arctan2(narrow[1], narrow[0])
    finger = d.down[:, FINGER_AXIS]
    yaw_now = np.arctan2(finger[1], finger[0])
    dyaw = (yaw_obj - yaw_now + np.pi / 2) % np.pi - np.pi / 2 + yaw_jitter  # fingers are symmetric
    grip_rot = _rz(dyaw) @ d.down
    top = max(center[2] + abs(rot[2] @ ((hi - lo) / 2.0)), center[2])
    height = float(ext[2])
    point = center.copy()
    point[2] = max(top - min(0.03, 0.5 * height), center[2] - 0.5 * height + 0.01)
    return point, grip_rot, height


def _pick_place(d: _Driver, name: str, target: str, rng: np.random.Generator) -> Iterator[None]:
    sc = d.scene
    obj = sc["objects"][name]
    yaw, offset = float(rng.normal(0.0, 0.05)), rng.normal(0.0, 0.003, 2)
    point, grip_rot, height = _grasp_frame(d, obj, yaw)
    point[:2] += offset
    safe_z = max(point[2] + 0.12, sc["eef_pos"][2])
    above = point.copy()
    above[2] = safe_z
    yield from _move(d, above, grip_rot, OPEN, tol=0.015)
    # the object may have moved (settling, a neighbour's release): aim at where it is now
    point, grip_rot, height = _grasp_frame(d, d.scene["objects"][name], yaw)
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
    lifted = d.scene["objects"][name]["pos"][2] - z_grasp
    goal = _target_point(d.scene, target)
    drop = goal.copy()
    # release with the object's bottom a little above the target's top (the grasp point sat below the
    # object's top by the same amount as now below the gripper)
    drop[2] = goal[2] + (point[2] - (obj["pos"][2] + obj["box_lo"][2])) + 0.03
    over = drop.copy()
    over[2] = max(drop[2] + 0.05, lift[2])
    yield from _move(d, over, grip_rot, CLOSED, tol=0.015)
    yield from _descend(d, drop, grip_rot, CLOSED)
    yield from _hold(d, OPEN, 10)
    up = d.scene["eef_pos"].copy()
    up[2] += 0.1
    yield from _move(d, up, grip_rot, OPEN, tol=0.02, max_steps=20)
    p = d.scene["objects"][name]["pos"]
    where = "in the target box" if _inside(d.scene, target, p) else "outside the target box"
    d.log.append(f"{name} -> {target}: lifted {lifted:.3f} m, left at {np.round(p, 3).tolist()} ({where})")


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


def _skills(d: _Driver, rng: np.random.Generator) -> Iterator[None]:
    goal = d.scene["goal"]
    for pred in goal:
        kind = pred[0]
        if kind in ("in", "on"):
            yield from _pick_place(d, pred[1], pred[2], rng)
        else:
            raise NotImplementedError(f"no expert skill for predicate {pred}")


def run_expert(env: LiberoEnv, init_index: int, rng: np.random.Generator) -> ExpertResult:
    """One demonstration from the official initial state ``init_index`` (``env`` started)."""
    env.reset(init_index)
    task = env.start()
    d = _Driver(env, task.max_steps)
    for _ in _hold(d, OPEN, SETTLE_STEPS // 2):  # official initial states drop objects from above
        pass
    for _ in _skills(d, rng):
        if d.done:
            break
    for _ in _hold(d, OPEN, SETTLE_STEPS):  # objects released last may need a moment to come to rest
        pass
    return ExpertResult(d.success, len(d.actions), np.asarray(d.actions), tuple(d.log))
