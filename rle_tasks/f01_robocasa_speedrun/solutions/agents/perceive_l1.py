"""L1 perception: the agent views' depth as world points through the self-calibration, vertical planes
found by RANSAC, and a door's geometry from its front plane and the bar standing proud of it.

No segmenter and no camera model from the harness: ``calibrate_l1`` gives the cameras, the base pose
(proprioception) places them in the world. A door is the largest vertical plane in a height band in
front of the robot; its handle the points ``perceive.BAR_FRONT`` proud of that plane within its extent;
the hinge is the face's edge farther from the handle (as at L2: ``perceive.door``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rle_tasks.envs.kitchen.harness.geometry import deproject, world_from_base
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from .calibrate_l1 import AGENT_VIEWS, Calibration, cameras
from .perceive import BAR_FRONT, EDGE_SKIP, HANDLE_PROUD, HINGE_INSET, PLANE_TOL, Door, plane

__all__ = ["Scene", "door", "scene", "vertical_planes"]

ROBOT_CLEAR = 0.42
"""Points nearer than this ahead of the base origin may be the robot's own arm [m] (base frame x)."""
MAX_RANGE = 2.5
"""Depth beyond which pixels are ignored [m]."""
RANSAC_TRIES = 300
"""Plane hypotheses per search."""
MIN_SPAN = 0.3
"""A door face spans at least this wide [m]."""
GAP = 0.05
"""A gap this wide along a plane ends a face [m]."""
LOOK = 0.5
"""Turn of the base towards a door's hinge side for a second view [rad]."""


@dataclass(frozen=True)
class Scene:
    """World points [m] of the agent views (``points``), the camera each came from (``cam``) and the
    cameras' positions (``eyes``, same order as ``calibrate_l1.AGENT_VIEWS``)."""

    points: np.ndarray
    cam: np.ndarray
    eyes: np.ndarray
    base: np.ndarray
    """4 x 4 world_from_base at the observation."""


def scene(robot: Robot, cal: Calibration) -> Scene:
    """The current observation's agent-view points in the world, the robot's own arm left out."""
    obs = robot.obs
    cams = cameras(cal, obs)
    wb = world_from_base(obs)
    pts, ids, eyes = [], [], []
    for i, c in enumerate(AGENT_VIEWS):
        t = cams[c]["world_from_camera"]
        p = deproject(np.asarray(obs["depth"][c], np.float32), cams[c]["K"], max_depth=MAX_RANGE)
        p = p @ t[:3, :3].T + t[:3, 3]
        ahead = (p - wb[:3, 3]) @ wb[:3, 0]
        p = p[ahead > ROBOT_CLEAR]
        pts.append(p)
        ids.append(np.full(len(p), i))
        eyes.append(t[:3, 3])
    return Scene(np.concatenate(pts), np.concatenate(ids), np.array(eyes), wb)


def vertical_planes(
    points: np.ndarray, rng: np.random.Generator, tries: int = RANSAC_TRIES
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(point, unit normal, inlier mask) of the vertical plane with the most inliers (within
    ``PLANE_TOL``) among ``tries`` hypotheses through two points."""
    best = (None, None, np.zeros(len(points), bool))
    if len(points) < 10:
        return best
    for _ in range(tries):
        a, b = points[rng.choice(len(points), 2, replace=False)]
        d = b[:2] - a[:2]
        if np.linalg.norm(d) < 0.05:
            continue
        n = np.array([-d[1], d[0], 0.0]) / np.linalg.norm(d)
        inl = np.abs((points - a) @ n) < PLANE_TOL
        if inl.sum() > best[2].sum():
            best = (a, n, inl)
    return best


def _run(s: np.ndarray, at: float) -> tuple[float, float]:
    """(lo, hi) of the connected run (no gap over ``GAP``) of the sorted values ``s`` that contains ``at``
    (or the nearest), ``EDGE_SKIP`` values in from each end."""
    gaps = np.nonzero(np.diff(s) > GAP)[0]
    mid = min(int(np.searchsorted(s, at)), len(s) - 1)
    below, above = gaps[gaps < mid], gaps[gaps >= mid]
    seg = s[(below[-1] + 1 if len(below) else 0) : (above[0] + 1 if len(above) else len(s))]
    return seg[min(EDGE_SKIP, len(seg) - 1)], seg[max(len(seg) - 1 - EDGE_SKIP, 0)]


def door(
    robot: Robot, cal: Calibration, z_band: tuple[float, float], motion: Motion | None = None, seed: int = 0
) -> Door | None:
    """The door in front of the robot: the largest vertical plane among the points in ``z_band``
    (heights [m]) facing the robot, its face the connected run of the plane's points above the band's
    floor, its handle the bar proud of it. With ``motion`` the base then turns ``LOOK`` towards the
    hinge side and the face's far edge is taken from both views (it often lies outside the first).
    None when no bar is found."""
    sc = scene(robot, cal)
    p = sc.points
    band = p[(p[:, 2] > z_band[0]) & (p[:, 2] < z_band[1])]
    a, n, inl = vertical_planes(band, np.random.default_rng(seed))
    if a is None:
        return None
    c, n = plane(band[inl], sc.eyes.mean(axis=0))
    u = np.cross([0.0, 0.0, 1.0], n)
    on = p[(np.abs((p - c) @ n) < PLANE_TOL) & (p[:, 2] > z_band[0])]
    if len(on) < 20:
        return None
    lo, hi = _run(np.sort((on - c) @ u), float(np.median((band[inl] - c) @ u)))
    if hi - lo < MIN_SPAN:
        return None
    face = on[((on - c) @ u > lo) & ((on - c) @ u < hi)]
    zlo, zhi = np.percentile(face[:, 2], 1), np.percentile(face[:, 2], 99)
    d, sh = (p - c) @ n, (p - c) @ u
    bar = p[(d > 0.015) & (d < 0.08) & (sh > lo) & (sh < hi) & (p[:, 2] > zlo) & (p[:, 2] < zhi)]
    if len(bar) < 5:
        return None
    bu = (bar - c) @ u  # the bar: the densest 10 cm slice along u
    centres = np.linspace(lo, hi, 60)
    x0 = centres[int(np.argmax([np.sum(np.abs(bu - x) < 0.05) for x in centres]))]
    bar = bar[np.abs(bu - x0) < 0.05]
    if len(bar) < 5 or not BAR_FRONT[0] < np.percentile((bar - c) @ n, 90) < BAR_FRONT[1]:
        return None
    shb = float(np.median((bar - c) @ u))
    handle = c + shb * u + HANDLE_PROUD * n
    handle[2] = float(np.mean(np.percentile(bar[:, 2], [5, 95])))
    side = -1.0 if abs(shb - lo) > abs(shb - hi) else 1.0  # the hinge's side along u
    if motion is not None:
        o = robot.obs
        yaw = float(o["base_yaw"]) + (LOOK if np.cross(sc.base[:3, 0], side * u)[2] > 0 else -LOOK)
        motion.drive_to(o["base_pos"][0], o["base_pos"][1], yaw, max_steps=40)
        q = scene(robot, cal).points
        on = np.concatenate([on, q[(np.abs((q - c) @ n) < PLANE_TOL) & (q[:, 2] > z_band[0])]])
        lo, hi = _run(np.sort((on - c) @ u), shb)
    edge = lo if side < 0 else hi
    hinge = c + edge * u - HINGE_INSET * n
    return Door(hinge, handle, n, float(hi - lo))
