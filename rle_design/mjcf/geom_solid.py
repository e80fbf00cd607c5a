"""Geoms of a compiled model as solids: closed-form volumes, triangle meshes and manifolds.

A primitive becomes a closed triangle mesh (box exact; sphere, ellipsoid, cylinder and capsule as
inscribed polyhedra of ``SEGMENTS`` facets around: used for overlap tests, never for mass, which
takes the closed forms of ``geom_volume``); a mesh geom is its compiled vertices and faces (MuJoCo's recentred frame, i.e. the geom
frame), or its convex hull when those do not form a closed manifold (MuJoCo collides with the hull
anyway). Lengths in metres, volumes in m^3. trimesh and manifold3d are imported lazily.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import mujoco
import numpy as np

if TYPE_CHECKING:
    import trimesh

__all__ = ["SEGMENTS", "geom_manifold", "geom_trimesh", "geom_volume", "is_solid", "pose_matrix"]

SEGMENTS = 16
"""Facets around a round primitive's axis [1]: the inscribed 16-gon has 1 - sin(2 pi/16) 16 / (2 pi)
= 2.6 % less area than the circle (an overlap test in the part's favour, never a mass)."""
_GT = mujoco.mjtGeom
_NOT_SOLID = {int(_GT.mjGEOM_PLANE), int(_GT.mjGEOM_HFIELD), int(_GT.mjGEOM_SDF)}


def is_solid(model: mujoco.MjModel, g: int) -> bool:
    """Whether geom ``g`` is a bounded solid (not a plane, height field or SDF)."""
    return int(model.geom_type[g]) not in _NOT_SOLID


def geom_volume(model: mujoco.MjModel, g: int) -> float:
    """Volume of geom ``g`` by its closed form (meshes: the enclosed volume of the mesh) [m^3]."""
    t, s = int(model.geom_type[g]), model.geom_size[g]
    if t == _GT.mjGEOM_SPHERE:
        return float(4 / 3 * np.pi * s[0] ** 3)
    if t == _GT.mjGEOM_BOX:
        return float(8 * s[0] * s[1] * s[2])
    if t == _GT.mjGEOM_CYLINDER:
        return float(np.pi * s[0] ** 2 * 2 * s[1])
    if t == _GT.mjGEOM_CAPSULE:
        return float(np.pi * s[0] ** 2 * (2 * s[1] + 4 / 3 * s[0]))
    if t == _GT.mjGEOM_ELLIPSOID:
        return float(4 / 3 * np.pi * s[0] * s[1] * s[2])
    if t == _GT.mjGEOM_MESH:
        return abs(float(_mesh(model, int(model.geom_dataid[g])).volume))
    return 0.0


def _mesh(model: mujoco.MjModel, mesh_id: int) -> trimesh.Trimesh:
    import trimesh

    va, vn = int(model.mesh_vertadr[mesh_id]), int(model.mesh_vertnum[mesh_id])
    fa, fn = int(model.mesh_faceadr[mesh_id]), int(model.mesh_facenum[mesh_id])
    verts = model.mesh_vert[va : va + vn].astype(float)
    return trimesh.Trimesh(verts, model.mesh_face[fa : fa + fn].copy(), process=False)


def geom_trimesh(model: mujoco.MjModel, g: int) -> trimesh.Trimesh:
    """Closed triangle mesh of geom ``g`` in the geom frame [m].

    Raises:
        ValueError: For a plane, height field or SDF (``is_solid`` is False).
    """
    import trimesh

    t, s = int(model.geom_type[g]), model.geom_size[g]
    if t == _GT.mjGEOM_BOX:
        return trimesh.creation.box(extents=2 * s[:3])
    if t == _GT.mjGEOM_SPHERE:
        return trimesh.creation.uv_sphere(radius=s[0], count=[SEGMENTS // 2, SEGMENTS])
    if t == _GT.mjGEOM_ELLIPSOID:
        sphere = trimesh.creation.uv_sphere(radius=1.0, count=[SEGMENTS // 2, SEGMENTS])
        sphere.apply_scale(s[:3])
        return sphere
    if t == _GT.mjGEOM_CYLINDER:
        return trimesh.creation.cylinder(radius=s[0], height=2 * s[1], sections=SEGMENTS)
    if t == _GT.mjGEOM_CAPSULE:
        return trimesh.creation.capsule(height=2 * s[1], radius=s[0], count=[SEGMENTS, SEGMENTS])
    if t == _GT.mjGEOM_MESH:
        mesh = _mesh(model, int(model.geom_dataid[g]))
        return mesh if mesh.is_watertight and mesh.is_volume else mesh.convex_hull
    raise ValueError(f"geom {g} of type {t} is not a bounded solid")


def pose_matrix(xpos: np.ndarray, xmat: np.ndarray) -> np.ndarray:
    """4 x 4 homogeneous transform of a frame at ``xpos`` with rotation ``xmat`` (9,) or (3, 3)."""
    out = np.eye(4)
    out[:3, :3] = np.asarray(xmat, float).reshape(3, 3)
    out[:3, 3] = xpos
    return out


def geom_manifold(model: mujoco.MjModel, g: int, cache: dict | None = None):
    """``manifold3d.Manifold`` of geom ``g`` in the geom frame (cached in ``cache`` by geom id).

    A mesh that manifold3d refuses is replaced by its convex hull; a degenerate one (flat, no hull)
    by the empty solid.
    """
    import manifold3d

    if cache is not None and g in cache:
        return cache[g]
    try:
        mesh = geom_trimesh(model, g)
        man = _to_manifold(mesh)
        if man.status() != manifold3d.Error.NoError or man.is_empty():
            man = _to_manifold(mesh.convex_hull)
    except Exception:  # noqa: BLE001 - a flat or degenerate mesh (qhull refuses it): no volume, no overlap
        man = manifold3d.Manifold()
    if cache is not None:
        cache[g] = man
    return man


def _to_manifold(mesh: trimesh.Trimesh):
    import manifold3d

    return manifold3d.Manifold(
        manifold3d.Mesh64(
            vert_properties=np.ascontiguousarray(mesh.vertices, dtype=np.float64),
            tri_verts=np.ascontiguousarray(mesh.faces, dtype=np.uint64),
        )
    )
