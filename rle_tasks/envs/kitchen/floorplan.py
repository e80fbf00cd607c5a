"""Where the mobile base can go: a 2-D occupancy grid of a compiled kitchen's floor, stand poses in front
of fixtures and a shortest path between two base poses.

The base's footprint (robosuite's Omron base, measured from its collision geoms: 0.70 m long, 0.50 m
wide, its centre ``FOOTPRINT_OFFSET`` behind the base joints' origin) is a rectangle, so paths are
planned for the footprint's centre in (x, y, heading) with the heading one of the four directions of
the runs' axes: a cell is free at a heading when the rectangle there (grown by ``MARGIN``) covers no
obstacle, and the base turns between headings only where the circle round the rectangle is free (it
turns about the footprint's centre: the base is holonomic). Obstacles are every geom that is not the
robot's and not the floor, below ``CEILING``, as its world bounding box.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass

import mujoco
import numpy as np
from scipy import ndimage

from rle_tasks.envs.kitchen.fixture import Fixture

__all__ = [
    "CELL",
    "FOOTPRINT_HALF",
    "FOOTPRINT_OFFSET",
    "MARGIN",
    "Grid",
    "centre_of",
    "free_stand_pose",
    "plan",
    "stand_pose",
]

CELL = 0.05
"""Grid resolution [m]."""
FOOTPRINT_HALF = (0.35, 0.25)
"""Half length and half width of the base's footprint [m]."""
FOOTPRINT_OFFSET = -0.2
"""Footprint centre along the base's heading from the base joints' origin [m]."""
MARGIN = 0.03
"""Clearance kept round the footprint [m]."""
CEILING = 2.2
"""Geoms starting above this height are no obstacle [m]."""
STANDOFF = 0.5
"""Base origin's distance from a fixture's front at its stand pose [m] (front of the deck 0.35 m off)."""


@dataclass(frozen=True)
class Grid:
    """Obstacles on the floor: ``occupied[i, j]`` covers x = x0 + (i + 0.5) CELL, y = y0 + (j + 0.5) CELL.

    ``free[k]`` says where the footprint's centre may stand at heading k x pi/2, ``turn`` where it may
    turn."""

    x0: float
    y0: float
    occupied: np.ndarray
    free: tuple[np.ndarray, ...]
    turn: np.ndarray

    def cell(self, x: float, y: float) -> tuple[int, int]:
        return int((x - self.x0) // CELL), int((y - self.y0) // CELL)

    def point(self, i: int, j: int) -> tuple[float, float]:
        return self.x0 + (i + 0.5) * CELL, self.y0 + (j + 0.5) * CELL

    def fits(self, pose: tuple[float, float, float]) -> bool:
        """The base fits at pose (x, y, yaw on one of the four headings)."""
        i, j = self.cell(*centre_of(pose))
        return bool(self.free[heading(pose[2])][i, j])

    @classmethod
    def of(cls, model: mujoco.MjModel, data: mujoco.MjData, ignore: set[int], pad: float = 1.6) -> Grid:
        """The grid of a compiled scene; geoms in ``ignore`` (the robot's) are no obstacles; the grid
        reaches ``pad`` past the obstacles' extent (beyond it counts as occupied)."""
        boxes = []
        for g in range(model.ngeom):
            if g in ignore or model.geom_type[g] == mujoco.mjtGeom.mjGEOM_PLANE:
                continue
            if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0:
                continue
            rot = data.geom_xmat[g].reshape(3, 3)
            c = data.geom_xpos[g] + rot @ model.geom_aabb[g, :3]
            h = np.abs(rot) @ model.geom_aabb[g, 3:]
            if c[2] - h[2] < CEILING:
                boxes.append((c - h, c + h))
        lo = np.min([b[0][:2] for b in boxes], axis=0) - pad
        hi = np.max([b[1][:2] for b in boxes], axis=0) + pad
        n = np.ceil((hi - lo) / CELL).astype(int)
        occ = np.zeros(n, dtype=bool)
        for a, b in boxes:
            i0, j0 = np.floor((a[:2] - lo) / CELL + 1e-6).astype(int)
            i1, j1 = np.ceil((b[:2] - lo) / CELL - 1e-6).astype(int)
            occ[max(i0, 0) : i1, max(j0, 0) : j1] = True
        occ[[0, -1], :] = True
        occ[:, [0, -1]] = True
        return cls(float(lo[0]), float(lo[1]), occ, *_configuration_space(occ))


def _configuration_space(occ: np.ndarray) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    hx, hy = (int(math.ceil((h + MARGIN) / CELL)) for h in FOOTPRINT_HALF)
    free = []
    for k in range(4):
        a, b = (hx, hy) if k % 2 == 0 else (hy, hx)
        free.append(~ndimage.binary_dilation(occ, np.ones((2 * a + 1, 2 * b + 1), bool)))
    r = int(math.ceil((math.hypot(*FOOTPRINT_HALF) + MARGIN) / CELL))
    yy, xx = np.mgrid[-r : r + 1, -r : r + 1]
    turn = ~ndimage.binary_dilation(occ, (xx**2 + yy**2) <= r * r)
    return tuple(free), turn


def stand_pose(f: Fixture, standoff: float = STANDOFF, shift: float = 0.0) -> tuple[float, float, float]:
    """Base pose (x, y, yaw) in front of ``f``'s front, facing it, the base origin ``standoff`` off and
    ``shift`` along the front (to the fixture's +x side) [m]."""
    fx_, fy_ = f.facing
    x, y = f.front
    x, y = x - fy_ * shift, y + fx_ * shift
    return x + fx_ * standoff, y + fy_ * standoff, math.atan2(-fy_, -fx_)


def free_stand_pose(grid: Grid, f: Fixture, standoff: float = STANDOFF) -> tuple[float, float, float] | None:
    """The stand pose in front of ``f`` nearest its middle (shifted along the front by at most a
    quarter of its width, in steps of one cell) where the base fits; None if there is none."""
    for k in range(int(f.size[0] / 4 / CELL) + 1):
        for shift in {k * CELL, -k * CELL}:
            pose = stand_pose(f, standoff, shift)
            if grid.fits(pose):
                return pose
    return None


def centre_of(pose: tuple[float, float, float]) -> tuple[float, float]:
    """Footprint centre of the base pose (x, y, yaw)."""
    x, y, yaw = pose
    return x + FOOTPRINT_OFFSET * math.cos(yaw), y + FOOTPRINT_OFFSET * math.sin(yaw)


def heading(yaw: float) -> int:
    """The nearest of the four headings k (yaw = k pi/2)."""
    return int(round(yaw / (math.pi / 2))) % 4


def plan(grid: Grid, start: tuple[float, float, float], goal: tuple[float, float, float]):
    """Shortest collision-free path of base poses from ``start`` to ``goal`` (x, y, yaw; yaws on the four
    headings), as footprint-centre waypoints (x, y, yaw), or None when there is none."""
    s = (*grid.cell(*centre_of(start)), heading(start[2]))
    g = (*grid.cell(*centre_of(goal)), heading(goal[2]))
    for i, j, k in (s, g):
        if not grid.free[k][i, j]:
            return None
    dist = {s: 0.0}
    prev: dict = {}
    heap = [(0.0, s)]
    steps = [(di, dj, math.hypot(di, dj)) for di in (-1, 0, 1) for dj in (-1, 0, 1) if di or dj]
    while heap:
        d, (i, j, k) = heapq.heappop(heap)
        if (i, j, k) == g:
            break
        if d > dist[(i, j, k)]:
            continue
        nbrs = [((i + di, j + dj, k), c) for di, dj, c in steps if grid.free[k][i + di, j + dj]]
        if grid.turn[i, j]:
            nbrs += [((i, j, (k + t) % 4), 0.5) for t in (1, 3)]
        for n, c in nbrs:
            nd = d + c
            if nd < dist.get(n, math.inf):
                dist[n], prev[n] = nd, (i, j, k)
                heapq.heappush(heap, (nd, n))
    if g not in dist:
        return None
    path = [g]
    while path[-1] != s:
        path.append(prev[path[-1]])
    return [(*grid.point(i, j), k * math.pi / 2) for i, j, k in reversed(path)]
