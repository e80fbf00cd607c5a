"""Physical properties of catalogue instances: mass, size and the reference grasp planner's view
(grasp width, graspable), from the collision geometry."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_tasks.envs.kitchen.catalogue_data import instance
from rle_tasks.envs.kitchen.catalogue_geometry import Part, add_geoms, geometry

GRIPPER_OPENING = 0.08
"""Panda gripper's full opening [m]."""


POSITION_TOL = 0.005
"""The grasp planner's positioning tolerance before it closes (``pick``'s final ``tol``) [m]."""


GRASP_REACH = GRIPPER_OPENING / 2 - POSITION_TOL
"""Farthest the grasped band may reach from the box centre along the closing axis [m]."""


PALM = 0.016
"""Grasp depth below the top [m] (``pick.PALM``)."""


PALM_ROUND = 0.03
"""Grasp depth below a round object's top [m] (``pick.PALM_ROUND``)."""


ROUND = 0.008
"""Spread of the half extents below which an object counts as round [m] (``pick.ROUND``)."""


FINGER_CLEARANCE = 0.022
"""Least height of the pads' centre above the support [m] (``pick.FINGER_CLEARANCE``)."""


EMPTY = 0.01
"""Finger opening below which the closed hand holds nothing [m] (``pick.EMPTY``)."""


PAD_HALF_HEIGHT = 0.008
"""Half height of the Panda gripper's finger pads [m] (robosuite ``panda_gripper.xml``)."""


@dataclass(frozen=True)
class Properties:
    """What the catalogue derives for an instance (SI units).

    Attributes:
        mass: Mass [kg].
        center: Centre of the box around the collision geometry, body frame [m].
        half: Half extents of that box [m].
        closing_axis: Body axis (0 x, 1 y) the planner closes the fingers along (the narrower side).
        grasp_height: Height of the pads' centre above the object's lowest point [m].
        band: (low, high) of the collision geometry along the closing axis in the pads' band, relative to
            the box centre [m].
        width: Extent of that band [m] (``band[1] - band[0]``).
        graspable: Fits the planner's grasp (see the module docstring).
    """

    mass: float
    center: tuple[float, float, float]
    half: tuple[float, float, float]
    closing_axis: int
    grasp_height: float
    band: tuple[float, float]
    width: float
    graspable: bool

    @property
    def size(self) -> tuple[float, float, float]:
        """Full extents of the bounding box [m]."""
        return tuple(2 * h for h in self.half)


def _probe(instance_id: str) -> tuple[mujoco.MjModel, mujoco.MjData]:
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(name="probe")
    body.add_freejoint()
    add_geoms(body, spec, "probe", instance(instance_id), visual=False)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def _part_mesh(part: Part):
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
        raise ValueError(f"grasp band of a '{part.kind}' part is not implemented")
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, np.asarray(part.quat))
    tf = np.eye(4)
    tf[:3, :3] = rot.reshape(3, 3)
    tf[:3, 3] = part.pos
    mesh.apply_transform(tf)
    return mesh


def _slab_points(mesh, z_lo: float, z_hi: float) -> np.ndarray:
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


@functools.cache
def properties(instance_id: str) -> Properties:
    """Mass, bounding box and grasp band of an instance (see the module docstring)."""
    model, _ = _probe(instance_id)
    meshes = [_part_mesh(part) for part in geometry(instance_id).parts]
    verts = np.concatenate([np.asarray(m.vertices) for m in meshes])
    lo, hi = verts.min(axis=0), verts.max(axis=0)
    center, half = (lo + hi) / 2, (hi - lo) / 2
    axis = 0 if half[0] <= half[1] else 1
    depth = PALM_ROUND if float(np.ptp(half)) < ROUND else PALM
    z_tool = max(hi[2] - depth, lo[2] + FINGER_CLEARANCE)
    band_lo, band_hi = np.inf, -np.inf
    for mesh in meshes:
        pts = _slab_points(mesh, z_tool - PAD_HALF_HEIGHT, z_tool + PAD_HALF_HEIGHT)
        if len(pts):
            band_lo = min(band_lo, float(pts[:, axis].min()))
            band_hi = max(band_hi, float(pts[:, axis].max()))
    band = (band_lo - center[axis], band_hi - center[axis])
    width = band[1] - band[0] if np.isfinite(band_lo) else 0.0
    reach = max(abs(band[0]), abs(band[1])) if np.isfinite(band_lo) else math.inf
    return Properties(
        mass=float(model.body_subtreemass[1]),
        center=tuple(float(v) for v in center),
        half=tuple(float(v) for v in half),
        closing_axis=axis,
        grasp_height=float(z_tool - lo[2]),
        band=tuple(float(v) for v in band),
        width=float(width),
        graspable=bool(reach <= GRASP_REACH and width >= EMPTY and z_tool <= hi[2]),
    )
