"""L2 perception of objects and open drawers for the pick-and-place programs (no world state).

An object is seen from above: its top is the highest of its points, its centre (x, y) the middle of
the points near the top (a box's top face, a ball's crown), its closing axis for a top-down grasp the
narrower principal axis of that top layer (none when it is round), and a curved top (few points at
its very top) asks for the deeper grasp of a round object. The support is the counter top around it.
An open drawer is its floor: the lowest dense level of its points, whose principal axes give the
pull direction (the one nearer the robot's heading) and the lateral one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rle_tasks.envs.kitchen.harness.geometry import world_points
from rle_tasks.envs.kitchen.harness.robot import CAMERAS, Robot

from .perceive import Cloud, clouds
from .pick import PALM, PALM_ROUND, Seen

__all__ = ["Drawer", "category_of", "drawer", "front_line", "object_seen", "support_z", "tall_at"]

TOP_LAYER = 0.012
"""Points this far below an object's top make its top layer [m]."""
FLAT = 0.003
"""A flat top has most of its top layer within this distance of the top [m]."""
ELONGATED = 1.25
"""Ratio of the top layer's principal spreads above which the grasp closes across the narrow one."""
ALIGN = 0.2
"""Search range of an open drawer's pull direction about the robot's heading at the start [rad] (the
robot starts facing the target fixture)."""
SKIP_MARGIN = 0.06
"""The open drawer's front panel spans its cabinet's width, this much beyond the drawer box's side [m]."""
STRAY = 0.12
"""Points of an object's masks farther than this from their median are not the object's [m]."""
SAME_OBJECT = 0.1
"""Instances of an object in two cameras within this distance [m] are the same object."""


def category_of(instruction: str) -> str:
    """The object's category in "Pick the <category> from ..."."""
    words = instruction.split()
    return words[words.index("the") + 1].strip(".,")


def _near(found: list[Cloud], near: np.ndarray | None) -> list[Cloud]:
    if not found:
        return []
    if near is None:
        seed = max(found, key=lambda c: len(c.points))
    else:
        seed = min(found, key=lambda c: float(np.linalg.norm(c.centre[:2] - near[:2])))
        if np.linalg.norm(seed.centre[:2] - near[:2]) > 0.15:
            return []
    return [c for c in found if np.linalg.norm(c.centre - seed.centre) < SAME_OBJECT]


def object_seen(
    robot: Robot,
    prompt: str,
    support: float,
    near: np.ndarray | None = None,
    cameras: tuple[str, ...] = CAMERAS,
) -> Seen | None:
    """``Seen`` of the object ``prompt`` standing on a surface at ``support`` [m] (the instance
    nearest ``near`` [m] when given); None when no camera sees it."""
    views = _near(clouds(robot, prompt, cameras), near)
    if not views:
        return None
    pts = np.concatenate([c.core if len(c.core) >= 10 else c.points for c in views])
    mid = np.median(pts, axis=0)
    # not the counter around it, nor stray boundary pixels on whatever lies in front or behind
    pts = pts[(pts[:, 2] > support + 0.003) & (np.linalg.norm(pts - mid, axis=1) < STRAY)]
    if len(pts) < 5:
        return None
    top = float(np.percentile(pts[:, 2], 98))
    layer = pts[pts[:, 2] > top - TOP_LAYER]
    flat = float(np.mean(layer[:, 2] > top - FLAT)) > 0.5
    if (layer[:, 2] > top - FLAT).sum() >= 10:
        layer = layer[layer[:, 2] > top - FLAT]  # a flat top: its face only
    xy = np.median(layer[:, :2], axis=0)
    home = float(robot.obs["base_yaw"]) + np.pi / 2
    axis = home
    if len(layer) >= 10:
        w, v = np.linalg.eigh(np.cov((layer[:, :2] - xy).T))
        if w[1] > ELONGATED**2 * max(w[0], 1e-9):
            axis = float(np.arctan2(v[1, 0], v[0, 0]))  # the narrower axis: fingers close along it
    yaw = float(home + ((axis - home + np.pi / 2) % np.pi - np.pi / 2))
    half_z = max((top - support) / 2, 0.005)
    centre = np.array([xy[0], xy[1], support + half_z])
    spread = np.percentile(pts[:, :2], 95, axis=0) - np.percentile(pts[:, :2], 5, axis=0)
    return Seen(centre, np.array([spread[0] / 2, spread[1] / 2, half_z]), yaw, PALM if flat else PALM_ROUND)


def support_z(robot: Robot, near: np.ndarray, radius: float = 0.25) -> float | None:
    """Height [m] of the counter top around ``near`` (the median of its points within ``radius``)."""
    zs = [
        c.points[np.linalg.norm(c.points[:, :2] - near[:2], axis=1) < radius, 2]
        for c in clouds(robot, "counter", CAMERAS[:2])
    ]
    z = np.concatenate(zs) if zs else np.zeros(0)
    z = z[z > 0.3]  # the top, not a cabinet's front
    return float(np.median(z)) if len(z) >= 10 else None


@dataclass(frozen=True)
class Drawer:
    """An open drawer: floor centre [m], floor height [m], outward pull direction and lateral axis
    (horizontal unit vectors), the floor's half extents along them [m] and the box's half width [m]."""

    centre: np.ndarray
    floor: float
    out: np.ndarray
    lateral: np.ndarray
    half: np.ndarray
    half_width: float


def drawer(robot: Robot) -> Drawer | None:
    """The open drawer: of the ``drawer`` instances, the one nearest the base along its heading (it
    stands out from the closed fronts towards the robot)."""
    obs = robot.obs
    base = np.asarray(obs["base_pos"][:2])
    ahead = np.array([np.cos(obs["base_yaw"]), np.sin(obs["base_yaw"])])
    found = clouds(robot, "drawer")
    if not found:
        return None
    near = min(float(np.dot(c.centre[:2] - base, ahead)) for c in found)
    seed = max(
        (c for c in found if np.dot(c.centre[:2] - base, ahead) < near + 0.5), key=lambda c: len(c.points)
    )
    views = [c for c in found if np.linalg.norm(c.centre - seed.centre) < 0.3]
    pts = np.concatenate([c.core if len(c.core) >= 10 else c.points for c in views])
    floor = float(np.percentile(pts[:, 2], 5))
    on = pts[np.abs(pts[:, 2] - floor) < 0.01, :2]
    if len(on) < 20:
        return None
    mid = np.median(on, axis=0)
    best = None  # the floor's rectangle: the pull direction near the heading with the tightest box
    for turn in np.arange(-ALIGN, ALIGN + 1e-9, 0.01):
        c, s_ = np.cos(obs["base_yaw"] + np.pi + turn), np.sin(obs["base_yaw"] + np.pi + turn)
        ab = (on - mid) @ np.array([[c, -s_], [s_, c]])
        area = float(np.prod(np.percentile(ab, 98, axis=0) - np.percentile(ab, 2, axis=0)))
        if best is None or area < best[0]:
            best = (area, np.array([c, s_]))
    out = best[1]  # towards the robot
    lat = np.array([-out[1], out[0]])
    a, b = (on - mid) @ out, (on - mid) @ lat
    lo = np.percentile(np.c_[a, b], 2, axis=0)
    hi = np.percentile(np.c_[a, b], 98, axis=0)
    centre = mid + (lo[0] + hi[0]) / 2 * out + (lo[1] + hi[1]) / 2 * lat
    s = (pts[:, :2] - centre) @ lat
    width = float(np.percentile(s, 99) - np.percentile(s, 1)) / 2
    return Drawer(np.r_[centre, floor], floor, np.r_[out, 0.0], np.r_[lat, 0.0], (hi - lo) / 2, width)


def front_line(
    robot: Robot, at: np.ndarray, out: np.ndarray, half_width: float, skip: Drawer
) -> float | None:
    """How far along ``out`` [m] from ``at`` the fixtures' fronts stand within ``half_width`` of it
    sideways: the most proud of the points seen between 0.1 and 0.95 m high, the open drawer
    ``skip`` and the robot's own body left out."""
    obs = robot.obs
    lat = np.array([-out[1], out[0], 0.0])
    base = np.asarray(obs["base_pos"][:2])
    best = []
    for cam in CAMERAS[:2]:
        p = world_points(obs, cam)
        p = p[(p[:, 2] > 0.1) & (p[:, 2] < 0.95)]
        p = p[np.linalg.norm(p[:, :2] - base, axis=1) > 0.4]
        s = (p - at) @ lat
        p = p[np.abs(s) < half_width]
        ds = (p[:, :2] - skip.centre[:2]) @ skip.lateral[:2]
        p = p[(np.abs(ds) > skip.half_width + SKIP_MARGIN) | (p[:, 2] < skip.floor - 0.05)]
        best.append((p - at) @ out)
    d = np.concatenate(best) if best else np.zeros(0)
    return float(np.percentile(d, 99)) if len(d) >= 20 else None


def tall_at(robot: Robot, at: np.ndarray, out: np.ndarray, front: float, reach: float) -> bool:
    """Whether a tall fixture (a fridge) stands within ``reach`` [m] sideways of ``at``: points
    between 1.25 and 1.4 m high (above the appliances on the counter, below the wall cabinets) less
    than 0.3 m behind the fronts (``front`` along ``out`` from ``at``) [m]."""
    obs = robot.obs
    lat = np.array([-out[1], out[0], 0.0])
    n = 0
    for cam in CAMERAS[:2]:
        p = world_points(obs, cam)
        p = p[(p[:, 2] > 1.25) & (p[:, 2] < 1.4)]
        n += int(np.sum((np.abs((p - at) @ lat) < reach) & ((p - at) @ out > front - 0.3)))
    return n >= 20
