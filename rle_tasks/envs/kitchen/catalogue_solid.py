"""Point queries on a catalogue instance's collision geometry (body frame, SI units): which points lie
inside it, its horizontal slices and a strip's profile along a direction. Every collision part is
convex (the LIBERO primitives, CoACD hulls), so a point is inside a part when it lies on the inner side
of all its face planes."""

from __future__ import annotations

import functools

import mujoco
import numpy as np

from rle_tasks.envs.kitchen.catalogue_geometry import Part, geometry


def part_mesh(part: Part):
    """A collision part as a trimesh in the body frame (cylinders with 32 sides, spheres subdivided twice)."""
    import trimesh

    if part.kind == "mesh":
        mesh = trimesh.load(part.mesh, force="mesh")
    elif part.kind == "box":
        mesh = trimesh.creation.box(extents=2 * np.asarray(part.size))
    elif part.kind == "cylinder":
        mesh = trimesh.creation.cylinder(radius=part.size[0], height=2 * part.size[1], sections=32)
    elif part.kind == "sphere":
        mesh = trimesh.creation.icosphere(subdivisions=2, radius=part.size[0])
    else:
        raise ValueError(f"a '{part.kind}' part is not implemented")
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, np.asarray(part.quat))
    tf = np.eye(4)
    tf[:3, :3] = rot.reshape(3, 3)
    tf[:3, 3] = part.pos
    mesh.apply_transform(tf)
    return mesh


@functools.cache
def meshes(instance_id: str) -> tuple:
    """The instance's collision parts as trimeshes in the body frame."""
    return tuple(part_mesh(p) for p in geometry(instance_id).parts)


@functools.cache
def _planes(instance_id: str) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]:
    """Per part, its convex hull's face planes (n, d) as rows [nx, ny, nz, d] (inside where
    n.p + d <= 0) and the hull's axis-aligned bounds (lo, hi) [m]."""
    from scipy.spatial import ConvexHull

    parts = []
    for m in meshes(instance_id):
        v = np.asarray(m.vertices)
        parts.append((ConvexHull(v).equations, v.min(axis=0), v.max(axis=0)))
    return tuple(parts)


def inside(instance_id: str, points: np.ndarray, margin: float = 0.0) -> np.ndarray:
    """Whether each point (N x 3, body frame [m]) lies within ``margin`` [m] of the collision geometry
    (the parts grown by ``margin`` along their face normals)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    hit = np.zeros(len(pts), dtype=bool)
    for eq, lo, hi in _planes(instance_id):
        # A part holds only points of its bounding box: the planes are tested on those alone. Grown by
        # a margin, a corner moves up to margin / sin(half its angle), so the box is then not used.
        idx = (
            np.flatnonzero(~hit & np.all((pts >= lo) & (pts <= hi), axis=1))
            if margin <= 0
            else np.arange(len(pts))
        )
        if idx.size:
            sub = pts[idx]
            hit[idx] |= np.all(sub @ eq[:, :3].T + eq[:, 3] <= margin, axis=1)
    return hit


def slab_points(mesh, z_lo: float, z_hi: float) -> np.ndarray:
    """Vertices of a convex piece's intersection with the slab z_lo <= z <= z_hi [m]: its vertices
    inside the slab and its edges' crossings of the two planes."""
    v = np.asarray(mesh.vertices)
    pts = [v[(v[:, 2] >= z_lo) & (v[:, 2] <= z_hi)]]
    a, b = v[mesh.edges_unique[:, 0]], v[mesh.edges_unique[:, 1]]
    for z in (z_lo, z_hi):
        dz = b[:, 2] - a[:, 2]
        cross = (a[:, 2] - z) * (b[:, 2] - z) < 0
        t = (z - a[cross, 2]) / dz[cross]
        pts.append(a[cross] + t[:, None] * (b[cross] - a[cross]))
    return np.concatenate(pts)


def slab(instance_id: str, z_lo: float, z_hi: float) -> np.ndarray:
    """Points spanning the collision geometry's intersection with the slab z_lo <= z <= z_hi [m]."""
    pts = [slab_points(m, z_lo, z_hi) for m in meshes(instance_id)]
    return np.concatenate(pts) if pts else np.zeros((0, 3))


STEP = 0.001
"""Spacing of the profile samples along the direction [m]."""


def profile(
    instance_id: str,
    origin: np.ndarray,
    u: np.ndarray,
    s: np.ndarray,
    half_width: float,
    z: np.ndarray,
    by_height: bool = False,
) -> np.ndarray:
    """Occupancy of the strip through ``origin`` (x, y) along the unit horizontal ``u``: for each
    distance ``s`` [m], whether any point at that distance, within ``half_width`` [m] across the strip and
    at any height of ``z`` [m], lies in the collision geometry (``by_height``: per height, s x z)."""
    v = np.array([-u[1], u[0]])
    t = np.linspace(-half_width, half_width, 5)
    S, T, Z = np.meshgrid(s, t, z, indexing="ij")
    xy = origin[None, None, None, :] + S[..., None] * u + T[..., None] * v
    pts = np.concatenate([xy, Z[..., None]], axis=-1).reshape(-1, 3)
    occ = inside(instance_id, pts).reshape(S.shape).any(axis=1)
    return occ if by_height else occ.any(axis=1)
