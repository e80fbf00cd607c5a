"""Kitchen objects: the robosuite wheel's object meshes (collision on their convex hulls) and
primitives, as free bodies.

Each category has a mass [kg], a colour and a flag for what it is: ``graspable`` objects fit the
Panda gripper (at most 0.07 m across in some horizontal direction), ``container`` objects (plate,
bowl) receive others. Meshes are referenced by absolute path inside the robosuite package, which is
an asset source only (never imported).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.paths import package_dir

__all__ = ["CATEGORIES", "Category", "add_object", "extent", "graspable", "containers"]

MESH_DIR = "models/assets/objects/meshes"
OBJECT_FRICTION = (1.0, 0.005, 0.0001)
"""Sliding, torsional, rolling friction of objects."""


@dataclass(frozen=True)
class Category:
    """An object category.

    Attributes:
        name: Category name (also the word an instruction uses).
        mass: Mass [kg].
        rgba: Colour.
        mesh: robosuite mesh file (without directory) or None for a primitive.
        scale: Mesh scale [1].
        shape: Primitive: ``sphere`` (size = radius), ``cylinder`` (radius, half height), ``box``
            (half extents), ``plate`` (radius, half height), ``bowl`` (radius, height).
        size: Primitive dimensions [m].
        graspable: Fits the gripper.
        container: Receives other objects.
    """

    name: str
    mass: float
    rgba: tuple[float, float, float, float]
    mesh: str | None = None
    scale: float = 1.0
    shape: str = "mesh"
    size: tuple[float, ...] = ()
    graspable: bool = True
    container: bool = False


CATEGORIES: dict[str, Category] = {
    c.name: c
    for c in (
        Category("apple", 0.15, (0.75, 0.1, 0.1, 1), shape="sphere", size=(0.035,)),
        Category("orange", 0.15, (0.95, 0.55, 0.1, 1), shape="sphere", size=(0.034,)),
        Category("lemon", 0.1, (0.95, 0.9, 0.2, 1), mesh="lemon.stl"),
        Category("bread", 0.1, (0.8, 0.6, 0.35, 1), mesh="bread.stl", scale=0.8),
        Category("can", 0.2, (0.8, 0.1, 0.15, 1), mesh="can.stl"),
        Category("cup", 0.15, (0.3, 0.5, 0.8, 1), shape="cylinder", size=(0.032, 0.045)),
        Category("butter", 0.12, (0.98, 0.92, 0.6, 1), shape="box", size=(0.045, 0.025, 0.02)),
        Category("milk", 0.3, (0.95, 0.95, 0.95, 1), mesh="milk.stl"),
        Category("bottle", 0.3, (0.2, 0.6, 0.3, 1), mesh="bottle.stl"),
        Category("cereal", 0.3, (0.85, 0.75, 0.2, 1), mesh="cereal.stl", graspable=False),
        Category(
            "plate",
            0.3,
            (0.95, 0.95, 0.97, 1),
            shape="plate",
            size=(0.11, 0.008),
            graspable=False,
            container=True,
        ),
        Category(
            "bowl",
            0.3,
            (0.6, 0.75, 0.85, 1),
            shape="bowl",
            size=(0.085, 0.06),
            graspable=False,
            container=True,
        ),
    )
}
"""Every object category by name."""


def graspable() -> tuple[str, ...]:
    """Names of the graspable categories."""
    return tuple(c.name for c in CATEGORIES.values() if c.graspable)


def containers() -> tuple[str, ...]:
    """Names of the container categories."""
    return tuple(c.name for c in CATEGORIES.values() if c.container)


def _mesh(spec: mujoco.MjSpec, cat: Category) -> str:
    name = f"mesh_{cat.name}"
    if spec.mesh(name) is None:
        path = package_dir("robosuite") / MESH_DIR / cat.mesh
        spec.add_mesh(name=name, file=str(path), scale=[cat.scale] * 3)
    return name


def _bowl(body: mujoco.MjsBody, name: str, radius: float, height: float, rgba, mass: float) -> None:
    """A bowl: a disc and a ring of 12 tilted wall slabs."""
    wall = 0.006
    body.add_geom(
        name=f"{name}_base",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[radius * 0.6, wall / 2, 0],
        pos=[0, 0, wall / 2],
        rgba=list(rgba),
        mass=mass * 0.3,
        friction=list(OBJECT_FRICTION),
        condim=4,
    )
    n = 12
    seg = 2 * radius * math.tan(math.pi / n) * 0.9
    for k in range(n):
        a = 2 * math.pi * k / n
        r = radius * 0.8
        tilt = 0.35
        quat = np.zeros(4)
        qz = np.array([math.cos(a / 2), 0, 0, math.sin(a / 2)])
        qy = np.array([math.cos(-tilt / 2), 0, math.sin(-tilt / 2), 0])
        mujoco.mju_mulQuat(quat, qz, qy)
        body.add_geom(
            name=f"{name}_wall{k}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[wall / 2, seg / 2, height / 2],
            pos=[r * math.cos(a), r * math.sin(a), height / 2],
            quat=list(quat),
            rgba=list(rgba),
            mass=mass * 0.7 / n,
            friction=list(OBJECT_FRICTION),
            condim=4,
        )


def _geoms(body: mujoco.MjsBody, spec: mujoco.MjSpec, name: str, cat: Category) -> None:
    common = dict(rgba=list(cat.rgba), friction=list(OBJECT_FRICTION), condim=4, solref=[0.004, 1.0])
    if cat.shape == "mesh":
        body.add_geom(
            name=name, type=mujoco.mjtGeom.mjGEOM_MESH, meshname=_mesh(spec, cat), mass=cat.mass, **common
        )
    elif cat.shape == "sphere":
        (r,) = cat.size
        body.add_geom(
            name=name,
            type=mujoco.mjtGeom.mjGEOM_SPHERE,
            size=[r, 0, 0],
            pos=[0, 0, r],
            mass=cat.mass,
            **common,
        )
    elif cat.shape in ("cylinder", "plate"):
        r, hh = cat.size
        body.add_geom(
            name=name,
            type=mujoco.mjtGeom.mjGEOM_CYLINDER,
            size=[r, hh, 0],
            pos=[0, 0, hh],
            mass=cat.mass,
            **common,
        )
    elif cat.shape == "box":
        body.add_geom(
            name=name,
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=list(cat.size),
            pos=[0, 0, cat.size[2]],
            mass=cat.mass,
            **common,
        )
    elif cat.shape == "bowl":
        _bowl(body, name, cat.size[0], cat.size[1], cat.rgba, cat.mass)
    else:
        raise ValueError(f"category '{cat.name}' has unknown shape '{cat.shape}'")


@functools.cache
def extent(category: str) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """(centre, half extents) of the axis-aligned box around a category's geoms in its body frame [m]."""
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(name="probe")
    body.add_freejoint()
    _geoms(body, spec, "probe", CATEGORIES[category])
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for g in range(model.ngeom):
        center, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
        rot = data.geom_xmat[g].reshape(3, 3)
        c = data.geom_xpos[g] + rot @ center
        h = np.abs(rot) @ half
        lo, hi = np.minimum(lo, c - h), np.maximum(hi, c + h)
    return tuple(float(v) for v in (lo + hi) / 2), tuple(float(v) for v in (hi - lo) / 2)


def add_object(
    spec: mujoco.MjSpec, name: str, category: str, pos: tuple[float, float, float], yaw: float = 0.0
) -> mujoco.MjsBody:
    """A free body ``name`` of ``category`` whose lowest point stands at ``pos[2]`` [m], turned by
    ``yaw`` [rad] about z; geoms are named ``name`` (or ``name_*`` for several)."""
    cat = CATEGORIES[category]
    quat = [math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)]
    center, half = extent(category)
    lift = half[2] - center[2]
    body = spec.worldbody.add_body(name=name, pos=[pos[0], pos[1], pos[2] + lift], quat=quat)
    body.add_freejoint(name=name)
    _geoms(body, spec, name, cat)
    return body
