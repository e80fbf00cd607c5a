"""L2 perception shared by the L2 programs: segmented instances as world point clouds (``segment`` and
depth through the cameras' poses), plane fits and a door's geometry. No world state.

A door is estimated from its front face and its handle: the face's plane (normal horizontal, facing the
cameras that see it), the handle bar's centre ``HANDLE_PROUD`` in front of it at the bar's lateral
position and height, and the hinge at the face's edge farther from the handle.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rle_tasks.envs.kitchen.harness import geometry, perception
from rle_tasks.envs.kitchen.harness.robot import CAMERAS, Robot

__all__ = ["Cloud", "Door", "clouds", "door", "erode", "merge", "plane"]

HANDLE_PROUD = 0.035
"""The handle bar's axis stands this far in front of a door's front face [m]."""
HINGE_INSET = 0.005
"""The hinge axis lies this far behind the front face at its edge (front face to mid-panel) [m]."""
PLANE_TOL = 0.015
"""Points within this distance of a fitted plane are its inliers [m]."""
EDGE_SKIP = 3
"""A face's edge is its fourth outermost inlier (a few stray pixels of a noisy mask lie beyond it)."""
BAR_FRONT = (0.025, 0.06)
"""Range of the 90th percentile of a handle's distances in front of its door's face [m] (the bar's
front is 45 mm proud; a neighbouring door's handle seen beside an open door lies farther out)."""
CORE = 2
"""Pixels a mask is eroded by for fitting planes (the segmenter's masks are off by up to two)."""
SAME = 0.25
"""Instances of one prompt in two cameras whose medians lie this close are the same thing [m]."""


@dataclass(frozen=True)
class Cloud:
    """One segmented instance: its world points [m] and the camera's position [m]."""

    camera: str
    points: np.ndarray
    eye: np.ndarray
    core: np.ndarray
    """The points of the mask eroded by ``CORE`` pixels (none of a noisy boundary's)."""

    @property
    def centre(self) -> np.ndarray:
        return np.median(self.points, axis=0)


@dataclass(frozen=True)
class Door:
    """A door's estimate: hinge axis point, handle bar centre, outward normal [m], panel's width [m]."""

    hinge: np.ndarray
    handle: np.ndarray
    out: np.ndarray
    width: float


def clouds(robot: Robot, prompt: str, cameras: tuple[str, ...] = CAMERAS, min_points: int = 5) -> list[Cloud]:
    """Every instance of ``prompt`` seen by ``cameras`` in the current observation."""
    obs = robot.obs
    out = []
    for cam in cameras:
        seg = perception.segment(robot.client, prompt, cam)
        eye = np.asarray(obs["cameras"][cam]["world_from_camera"])[:3, 3]
        for mask in seg["masks"]:
            pts = geometry.world_points(obs, cam, mask)
            if len(pts) >= min_points:
                core = geometry.world_points(obs, cam, erode(mask, CORE))
                out.append(Cloud(cam, pts, eye, core))
    return out


def erode(mask: np.ndarray, px: int) -> np.ndarray:
    """``mask`` eroded by ``px`` pixels (4-neighbourhood)."""
    m = np.asarray(mask, bool).copy()
    for _ in range(px):
        e = m.copy()
        e[1:] &= m[:-1]
        e[:-1] &= m[1:]
        e[:, 1:] &= m[:, :-1]
        e[:, :-1] &= m[:, 1:]
        m = e
    return m


def merge(found: list[Cloud], seed: Cloud, radius: float = SAME) -> list[Cloud]:
    """The instances of ``found`` (other cameras' views) whose centre lies within ``radius`` of ``seed``'s."""
    return [c for c in found if np.linalg.norm(c.centre - seed.centre) < radius]


def plane(points: np.ndarray, eye: np.ndarray, vertical: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """(point, unit normal facing ``eye``) of the plane through ``points`` [m] (a vertical plane: its
    normal horizontal, by default), refitted on its inliers."""
    pts = np.asarray(points, float)
    for _ in range(2):
        c = np.median(pts, axis=0)
        n = np.linalg.svd(pts - c, full_matrices=False)[2][-1]
        if vertical:
            n[2] = 0.0
        n /= np.linalg.norm(n)
        d = (pts - c) @ n
        c = c + np.median(d) * n
        keep = np.abs((pts - c) @ n) < PLANE_TOL
        if keep.sum() >= 10:
            pts = pts[keep]
    if np.dot(eye - c, n) < 0:
        n = -n
    return c, n


def door(
    robot: Robot,
    door_prompt: str,
    handle_prompt: str,
    choose: Callable[[list[Cloud]], Cloud] | None = None,
) -> Door | None:
    """Estimate a door from the three cameras; ``choose`` picks the target among the door instances
    (default: the largest). None when the door or its handle is not seen."""
    doors = clouds(robot, door_prompt)
    if not doors:
        return None
    seed = choose(doors) if choose else max(doors, key=lambda c: len(c.points))
    views = merge(doors, seed)
    pts = np.concatenate([c.points for c in views])
    core = np.concatenate([c.core for c in views])
    eye = np.mean([c.eye for c in views], axis=0)
    c, n = plane(core if len(core) >= 30 else pts, eye)
    on = pts[np.abs((pts - c) @ n) < PLANE_TOL]
    u = np.cross([0.0, 0.0, 1.0], n)  # horizontal direction in the door's plane
    s = np.sort((on - c) @ u)
    lo, hi = s[min(EDGE_SKIP, len(s) - 1)], s[max(len(s) - 1 - EDGE_SKIP, 0)]
    zlo, zhi = np.percentile(on[:, 2], 1), np.percentile(on[:, 2], 99)
    bars = []  # (points in front of this face, its bar points): a bar's front stands BAR_FRONT proud
    for h in clouds(robot, handle_prompt):
        p = h.points
        d = (p - c) @ n
        sh = (p - c) @ u
        p = p[(d > -0.01) & (d < 0.08) & (sh > lo) & (sh < hi) & (p[:, 2] > zlo) & (p[:, 2] < zhi)]
        d = (p - c) @ n
        if len(p) >= 5 and BAR_FRONT[0] < np.percentile(d, 90) < BAR_FRONT[1]:
            bars.append((len(p), p[d > 0.015] if (d > 0.015).sum() >= 3 else p))
    if not bars:
        return None
    best = max(bars, key=lambda b: b[0])[1]
    bars = [p for _, p in bars if np.linalg.norm(np.median(p, axis=0) - np.median(best, axis=0)) < 0.1]
    bar = np.concatenate(bars)
    sh = float(np.median((bar - c) @ u))
    handle = c + sh * u + HANDLE_PROUD * n
    handle[2] = float(np.mean(np.percentile(bar[:, 2], [5, 95])))  # the bar's middle
    edge = lo if abs(sh - lo) > abs(sh - hi) else hi
    hinge = c + edge * u - HINGE_INSET * n
    return Door(hinge, handle, n, float(hi - lo))
