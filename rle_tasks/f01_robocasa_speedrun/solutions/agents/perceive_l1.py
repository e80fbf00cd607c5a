"""L1 perception: the agent views' depth as world points through the self-calibration, vertical planes
found by RANSAC, and a door's geometry from its front plane and the bar standing proud of it.

No segmenter and no camera model from the harness: ``calibrate_l1`` gives the cameras, the base pose
(proprioception) places them in the world. A door is the largest vertical plane in a height band in
front of the robot; its handle the points ``perceive.BAR_FRONT`` proud of that plane within its extent;
the hinge is the face's edge farther from the handle (as at L2: ``perceive.door``).
"""

from __future__ import annotations

from collections.abc import Callable
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
BODY = (0.25, 0.22)
"""The robot's torso and base: points less than this ahead of and beside the base origin [m]."""
PROUD_OF_FRONT = 0.04
"""An open door's points stand at least this far in front of the fixtures' fronts [m]."""
FREE_INSET = 0.06
"""An unseen handle is taken this far in from the door's free end [m]."""
OPEN_GAP = 0.15
"""A gap this wide along an open door's plane ends it (the arm hides parts of it) [m]."""
MAX_DOOR = 0.65
"""Widest door taken [m]."""
OUTER = 0.6
"""A bar nearer the hinge than this fraction of the door's width is not its handle."""
HANDLE_Z = 0.73
"""Height given to an open cabinet door's handle [m] (only its horizontal position is used)."""
KNOB_PROUD = (0.025, 0.075)
"""A knob's points stand this far in front of its panel [m]."""
KNOB_GAP = 0.04
"""Knobs lie farther apart than this along the panel [m]."""
KNOB_MIN_PIXELS = 3
"""Fewest points of a knob."""
KNOB_WIDTH = 0.07
"""A knob's points span at most this along its panel [m]."""
BAR_TIP = 0.007
"""A knob's grip point lies this far behind its grip bar's tip [m]."""
AHEAD_HALF = 0.3
"""Half width of the fixture ahead of the base searched for knobs [m]."""
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


def scene(robot: Robot, cal: Calibration, clear: float | None = ROBOT_CLEAR) -> Scene:
    """The current observation's agent-view points in the world, the robot's own arm left out: the
    points less than ``clear`` ahead of the base, or (``clear`` None) those within ``BODY`` of it."""
    obs = robot.obs
    cams = cameras(cal, obs)
    wb = world_from_base(obs)
    pts, ids, eyes = [], [], []
    for i, c in enumerate(AGENT_VIEWS):
        t = cams[c]["world_from_camera"]
        p = deproject(np.asarray(obs["depth"][c], np.float32), cams[c]["K"], max_depth=MAX_RANGE)
        p = p @ t[:3, :3].T + t[:3, 3]
        ahead, side = (p - wb[:3, 3]) @ wb[:3, 0], (p - wb[:3, 3]) @ wb[:3, 1]
        if clear is None:
            p = p[(ahead > BODY[0]) | (np.abs(side) > BODY[1])]
        else:
            p = p[ahead > clear]
        pts.append(p)
        ids.append(np.full(len(p), i))
        eyes.append(t[:3, 3])
    return Scene(np.concatenate(pts), np.concatenate(ids), np.array(eyes), wb)


def vertical_planes(
    points: np.ndarray,
    rng: np.random.Generator,
    tries: int = RANSAC_TRIES,
    normal: Callable[[np.ndarray], bool] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(point, unit normal, inlier mask) of the vertical plane with the most inliers (within
    ``PLANE_TOL``) among ``tries`` hypotheses through two points (whose normal ``normal`` accepts)."""
    best = (None, None, np.zeros(len(points), bool))
    if len(points) < 10:
        return best
    for _ in range(tries):
        a, b = points[rng.choice(len(points), 2, replace=False)]
        d = b[:2] - a[:2]
        if np.linalg.norm(d) < 0.05:
            continue
        n = np.array([-d[1], d[0], 0.0]) / np.linalg.norm(d)
        if normal is not None and not normal(n):
            continue
        inl = np.abs((points - a) @ n) < PLANE_TOL
        if inl.sum() > best[2].sum():
            best = (a, n, inl)
    return best


def _run(s: np.ndarray, at: float, gap: float = 0.05) -> tuple[float, float]:
    """(lo, hi) of the connected run (no gap over ``GAP``) of the sorted values ``s`` that contains ``at``
    (or the nearest), ``EDGE_SKIP`` values in from each end."""
    gaps = np.nonzero(np.diff(s) > gap)[0]
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


def _line_meet(c1: np.ndarray, n1: np.ndarray, c2: np.ndarray, n2: np.ndarray) -> np.ndarray:
    """The horizontal point where two vertical planes (point, normal) meet (z of ``c1``)."""
    a = np.array([n1[:2], n2[:2]])
    xy = np.linalg.solve(a, [n1[:2] @ c1[:2], n2[:2] @ c2[:2]])
    return np.array([xy[0], xy[1], c1[2]])


def open_door(robot: Robot, cal: Calibration, z_band: tuple[float, float], seed: int = 0) -> Door | None:
    """An open door standing out of the fixtures' fronts towards the robot (CloseCabinet): the fronts'
    plane (the largest vertical plane in ``z_band`` facing the base), the door's plane (the largest
    among the points ``PROUD_OF_FRONT`` in front of it, its normal across the base's heading), the hinge
    where the two meet, the handle the bar proud of the door near its free end (or, unseen, a point
    ``FREE_INSET`` in from that end). The door's normal points to the base's side of it."""
    sc = scene(robot, cal, clear=None)
    wb = sc.base
    fwd = wb[:3, 0]
    p = sc.points
    band = p[(p[:, 2] > z_band[0]) & (p[:, 2] < z_band[1])]
    rng = np.random.default_rng(seed)
    a, n_f, inl = vertical_planes(band, rng, normal=lambda n: abs(n @ fwd) > 0.9)
    if a is None:
        return None
    c_f, n_f = plane(band[inl], wb[:3, 3])
    ahead = (band - c_f) @ n_f  # > 0: in front of the fronts (towards the base)
    cand = band[ahead > PROUD_OF_FRONT]
    a, n, inl = vertical_planes(cand, rng, normal=lambda n: abs(n @ fwd) < 0.5)
    if a is None or inl.sum() < 30:
        return None
    c, n = plane(cand[inl], wb[:3, 3])
    u = np.cross([0.0, 0.0, 1.0], n)
    hinge = _line_meet(c, n, c_f, n_f)
    s = (cand[inl] - hinge) @ u
    sign = -1.0 if np.median(s) < 0 else 1.0
    free = sign * _run(np.sort(sign * s), 0.0, OPEN_GAP)[1]  # the far end of its points' run from the hinge
    if abs(free) < MIN_SPAN:  # the arm hid a stretch of the door: its farthest points
        free = sign * min(float(np.percentile(sign * s, 99)), MAX_DOOR)
    d, sh = (p - hinge) @ n, (p - hinge) @ u
    lo, hi = sorted((0.0, free))
    bar = p[
        (d > 0.015) & (d < 0.08) & (sh > lo) & (sh < hi) & (p[:, 2] > z_band[0]) & (p[:, 2] < z_band[1] + 0.1)
    ]
    shb = free - sign * FREE_INSET
    if len(bar) >= 5 and float(np.median((bar - hinge) @ u)) / free > OUTER:  # a bar on the door's outer part
        shb = float(np.median((bar - hinge) @ u))
    handle = hinge + shb * u + HANDLE_PROUD * n
    handle[2] = HANDLE_Z
    return Door(hinge - HINGE_INSET * n, handle, n, abs(free))


def knobs(
    robot: Robot, cal: Calibration, z_band: tuple[float, float], views: list[Scene]
) -> list[np.ndarray]:
    """Knob grip points [m] on the front panel of the fixture ahead of the base (within ``AHEAD_HALF``
    sideways), left to right as the base sees them, from the points of ``views`` (scenes taken from one
    base pose): the fronts' plane in ``z_band`` (the largest vertical plane facing the base), the points
    ``KNOB_PROUD`` in front of it grouped along the plane (gaps over ``KNOB_GAP``, groups at most
    ``KNOB_WIDTH`` wide), each group's grip ``BAR_TIP`` behind its front-most points."""
    wb = views[0].base
    p = np.concatenate([v.points for v in views])
    rel = p - wb[:3, 3]
    band = p[(p[:, 2] > z_band[0]) & (p[:, 2] < z_band[1]) & (np.abs(rel @ wb[:3, 1]) < AHEAD_HALF)]
    a, n, inl = vertical_planes(band, np.random.default_rng(0), normal=lambda n: abs(n @ wb[:3, 0]) > 0.9)
    if a is None:
        return []
    c, n = plane(band[inl], wb[:3, 3])
    d = (band - c) @ n
    k = band[(d > KNOB_PROUD[0]) & (d < KNOB_PROUD[1])]
    if len(k) < 3:
        return []
    right = -wb[:3, 1]
    s = (k - c) @ right
    order = np.argsort(s)
    k, s = k[order], s[order]
    out = []
    for g in np.split(np.arange(len(s)), np.nonzero(np.diff(s) > KNOB_GAP)[0] + 1):
        q = k[g]
        if len(g) < KNOB_MIN_PIXELS or np.ptp(s[g]) > KNOB_WIDTH:
            continue
        front = float(np.percentile((q - c) @ n, 95))
        grip = c + float(np.median((q - c) @ right)) * right + (front - BAR_TIP) * n
        grip[2] = float(np.mean(np.percentile(q[:, 2], [5, 95])))
        out.append(grip)
    return out
