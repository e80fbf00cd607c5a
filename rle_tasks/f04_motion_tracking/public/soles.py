"""Sole polygons of the shipped G1's feet: the support area through which a stance foot pushes.

A sole is the convex hull (counter-clockwise, in the foot body's frame) of the foot capsules' lowest
lines, at the capsules' lowest height, with vertices within ``SOLE_SIMPLIFY`` of their neighbours' chord
dropped (the polygon only shrinks: conservative). The clip feasibility check (``inverse_dynamics``) puts a
friction pyramid at every vertex.
"""

from __future__ import annotations

import mujoco
import numpy as np

__all__ = ["SOLE_SIMPLIFY", "sole_polygon"]

SOLE_SIMPLIFY = 0.003
"""Sole-polygon vertices closer than this to the edge joining their neighbours are dropped [m] (the
polygon only shrinks: conservative)."""


def _capsule_ends(model: mujoco.MjModel, g: int) -> np.ndarray:
    """Segment end points (2, 3) of capsule ``g`` (a sphere: its centre twice) in its body's frame."""
    pos = model.geom_pos[g]
    if model.geom_type[g] != mujoco.mjtGeom.mjGEOM_CAPSULE:
        return np.array([pos, pos])
    axis = np.zeros(3)
    mujoco.mju_rotVecQuat(axis, np.array([0.0, 0.0, 1.0]), model.geom_quat[g])
    return np.array([pos - model.geom_size[g][1] * axis, pos + model.geom_size[g][1] * axis])


def sole_polygon(model: mujoco.MjModel, body: str) -> np.ndarray:
    """Vertices (k, 3) of a foot's sole in its body frame: the convex hull (counter-clockwise) of the
    foot capsules' lowest lines, at the capsules' lowest height."""
    b = model.body(body).id
    geoms = [
        g
        for g in range(model.ngeom)
        if model.geom_bodyid[g] == b and model.geom_contype[g] + model.geom_conaffinity[g]
    ]
    ends = np.vstack([_capsule_ends(model, g) for g in geoms])
    z = min(float(_capsule_ends(model, g)[:, 2].min() - model.geom_size[g][0]) for g in geoms)
    hull = _simplify(_hull_2d(ends[:, :2]), SOLE_SIMPLIFY)
    return np.column_stack([hull, np.full(len(hull), z)])


def _simplify(poly: np.ndarray, tol: float) -> np.ndarray:
    """Drop convex-polygon vertices within ``tol`` of the chord of their neighbours, nearest first."""
    poly = [np.asarray(v) for v in poly]
    while len(poly) > 4:
        dist = []
        for i, v in enumerate(poly):
            u, w = poly[i - 1], poly[(i + 1) % len(poly)]
            e = w - u
            dist.append(abs(e[0] * (v - u)[1] - e[1] * (v - u)[0]) / np.linalg.norm(e))
        i = int(np.argmin(dist))
        if dist[i] >= tol:
            break
        poly.pop(i)
    return np.array(poly)


def _hull_2d(points: np.ndarray) -> np.ndarray:
    pts = sorted({(round(float(x), 9), round(float(y), 9)) for x, y in points})
    if len(pts) <= 2:
        return np.array(pts)

    def half(seq):
        out: list = []
        for p in seq:
            while (
                len(out) >= 2
                and (
                    (out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                    - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])
                )
                <= 0
            ):
                out.pop()
            out.append(p)
        return out

    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])
