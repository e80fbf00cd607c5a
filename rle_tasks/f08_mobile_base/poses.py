"""Arm poses of the static battery, solved with the toolkit's IK (Pinocchio + OSQP).

Poses (documented in the README): ``stowed``; ``reach_<dir>``: the tool at ``REACH_FRACTION`` of the
arm's catalog reach from the mount, at shoulder height, toward front, front-left, left, back, right,
front-right; ``T01``..``T12``: the shelf targets with the base parked so that its front is
``PARK_GAP`` behind the shelf face, tool axis horizontal into the shelf. An unreachable target keeps
the IK's best configuration and reports its residual.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.catalog import load_catalog
from rle_design.kinematics.ik import solve_ik
from rle_design.scene import element_id
from rle_tasks.f08_mobile_base.public.scene import MOUNT_SITE, STOWED, Scene

REACH_FRACTION = 0.8
PARK_GAP = 0.05  # [m]
REACH_DIRS = {
    "front": 0.0,
    "front_left": np.pi / 4,
    "left": np.pi / 2,
    "back": np.pi,
    "right": -np.pi / 2,
    "front_right": -np.pi / 4,
}


@dataclass(frozen=True)
class Pose:
    """One arm pose of the battery.

    Attributes:
        name: ``stowed``, ``reach_<dir>`` or a target id.
        q: Arm joint configuration [rad].
        base_x: Chassis x at which the pose is evaluated [m].
        target: World target of the tool (None for ``stowed``) [m].
        residual: Tool distance to the target at ``q`` [m].
    """

    name: str
    q: tuple[float, ...]
    base_x: float
    target: tuple[float, float, float] | None
    residual: float


def park_x(scene: Scene) -> float:
    """Chassis x placing the base front ``PARK_GAP`` before the shelf face [m]."""
    return float(load_catalog("shelf").extra["front_x"]) - PARK_GAP - scene.front_extent()


def _ik(scene: Scene, data: mujoco.MjData, target_world: np.ndarray, axis_world: np.ndarray | None):
    ch = scene.chain
    tgt = ch.to_base(data, target_world)
    _, rot = ch.base_pose(data)
    axis = None if axis_world is None else rot.T @ axis_world
    seeds = [np.array(STOWED[scene.arm]), np.clip(np.zeros(len(ch.lower)), ch.lower, ch.upper)]
    best = None
    if axis is not None:
        seeds.insert(1, solve_ik(ch, tgt, seeds[0], max_iter=60).q)
    rng = np.random.default_rng(7)  # fixed restarts: the battery is deterministic
    lo, hi = np.maximum(ch.lower, -np.pi), np.minimum(ch.upper, np.pi)
    seeds += [rng.uniform(lo, hi) for _ in range(6)]
    for q0 in seeds:
        r = solve_ik(ch, tgt, q0, axis=axis, max_iter=120)
        if best is None or (r.position_error, r.axis_error) < (best.position_error, best.axis_error):
            best = r
        if best.converged:
            break
    return best


def battery_poses(
    scene: Scene, target_ids: tuple[str, ...] | None = None, reach_dirs: tuple[str, ...] | None = None
) -> list[Pose]:
    """Poses for ``scene.arm`` (targets and directions default to all)."""
    arm = load_catalog("arms").get(scene.arm)
    shelf = load_catalog("shelf")
    poses = [Pose("stowed", tuple(STOWED[scene.arm]), 0.0, None, 0.0)]
    data = scene.rest_data(0.0)
    mount = data.site_xpos[element_id(scene.model, "site", MOUNT_SITE)].copy()
    for name in reach_dirs or tuple(REACH_DIRS):
        ang = REACH_DIRS[name]
        tgt = mount + np.array([np.cos(ang), np.sin(ang), 0.0]) * REACH_FRACTION * arm.reach
        tgt[2] = mount[2] + arm.shoulder_height
        r = _ik(scene, data, tgt, None)
        poses.append(Pose(f"reach_{name}", tuple(r.q), 0.0, tuple(tgt), r.position_error))
    x = park_x(scene)
    data = scene.rest_data(x)
    for t in shelf.entries:
        if target_ids is not None and t.id not in target_ids:
            continue
        r = _ik(scene, data, np.array(t.pos), np.array([1.0, 0.0, 0.0]))
        poses.append(Pose(t.id, tuple(r.q), x, tuple(t.pos), r.position_error))
    return poses
