"""The kitchen's object catalogue: categories of graspable and receiving objects from the installed asset
wheels (robosuite's objects and the LIBERO-PRO asset wheels), each instance with its source, licence,
mass, size, collision geometry and grasp (mode and width).

The data is ``catalogue.yaml`` beside this module (categories -> instances, the sources and their
licences). Everything numeric is derived here from the source files, in SI units:

- collision geometry: the source's own collision geoms (the LIBERO objects' primitives, in the frame of
  the object's root body) or, where the source has none but its render mesh (robosuite: the collision
  geom is the render mesh, which MuJoCo would replace by one convex hull), a CoACD convex decomposition
  of that mesh, computed once and cached under ``cache_root()/catalogue/coacd/<key>`` where the key is
  the sha256 of the mesh file's bytes, its scale and ``COACD_PARAMS`` (nothing copied from the wheels
  is committed);
- mass [kg]: the category's typical real product mass (``catalogue.yaml``: ``mass`` with its
  ``mass_source``) for its first instance, the others scaled by their collision volume; one uniform
  density per instance, so the inertia is the collision geometry's scaled to that mass
  (``catalogue_mass``);
- size [m]: the axis-aligned box around the collision geometry in the body frame (z up);
- grasp: the reference grasp planner's grasp in the category's mode (``top``, ``flat``, ``rim``,
  ``handle``: ``catalogue_grasp``): tool point, closing axis, opening, the grasped band's width and
  whether it fits (``graspable``).

Pretrain and target kitchens draw disjoint instances of a category (``split``). The wheels are asset
sources only: their files are located through the import system's metadata, never imported.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from rle_tasks.envs.kitchen.catalogue_data import CATEGORIES, instance
from rle_tasks.envs.kitchen.catalogue_geometry import add_geoms, geometry
from rle_tasks.envs.kitchen.catalogue_grasp import properties
from rle_tasks.envs.kitchen.catalogue_mass import density


def split(category: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(pretrain, target) instances of a category.

    Rule: the graspable instances in catalogue order alternate pretrain, target, pretrain, ...; then the
    others likewise. The two sides are disjoint, and both hold a graspable instance wherever the
    category has two or more. A category with a single instance gives it to both (nothing to hold out).
    """
    ids = CATEGORIES[category].instances
    if len(ids) == 1:
        return ids, ids
    pre: list[str] = []
    tgt: list[str] = []
    for group in (
        [i for i in ids if properties(i).graspable],
        [i for i in ids if not properties(i).graspable],
    ):
        for k, iid in enumerate(group):
            (pre if k % 2 == 0 else tgt).append(iid)
    return tuple(pre), tuple(tgt)


def catalogue_table() -> str:
    """The catalogue as a markdown table: category, instances (split side), source, licence, mass [kg],
    size [m], grasp mode and width [m], and collision geometry."""
    rows = [
        "| category | instance | source (wheel: path) | licence | mass [kg] | size x y z [m] | grasp: mode, width [m] | collision |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for cat in CATEGORIES.values():
        pre, tgt = split(cat.name)
        for k, iid in enumerate(cat.instances):
            inst, props, geo = instance(iid), properties(iid), geometry(iid)
            role = "both" if len(cat.instances) == 1 else ("pretrain" if iid in pre else "target")
            size = " x ".join(f"{s:.3f}" for s in props.size)
            grasp = f"{props.mode}, {props.width:.3f}" + ("" if props.graspable else " (not graspable)")
            n = len(geo.parts)
            coll = (
                f"CoACD, {n} hull{'s' * (n > 1)}"
                if geo.collision == "coacd"
                else f"source, {n} primitive{'s' * (n > 1)}"
            )
            rows.append(
                f"| {cat.name if k == 0 else ''} | `{iid}` ({role}) | {inst.wheel}: `{inst.path}` | "
                f"{inst.licence} | {props.mass:.3f} | {size} | {grasp} | {coll} |"
            )
    return "\n".join(rows)


def add_instance(
    spec: mujoco.MjSpec,
    name: str,
    instance_id: str,
    pos: tuple[float, float, float],
    yaw: float = 0.0,
    visual: bool = True,
) -> mujoco.MjsBody:
    """A free body ``name`` of a catalogue instance whose lowest point stands at ``pos[2]`` [m] and whose
    bounding box is centred on ``pos[:2]`` [m] before the turn by ``yaw`` [rad] about z. Collision geoms
    are named ``name_c<k>`` (group 0; group 3 when ``visual``), all of one density giving the
    catalogue's mass (``catalogue_mass``); render meshes ``name_v<k>`` (group 1, no contacts, no mass;
    untextured, the category's colour)."""
    props = properties(instance_id)
    c, h = np.asarray(props.center), np.asarray(props.half)
    quat = np.array([math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)])
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, quat)
    offset = rot.reshape(3, 3) @ np.array([c[0], c[1], 0.0])
    origin = [pos[0] - offset[0], pos[1] - offset[1], pos[2] + h[2] - c[2]]
    body = spec.worldbody.add_body(name=name, pos=origin, quat=list(quat))
    body.add_freejoint(name=name)
    add_geoms(body, spec, name, instance(instance_id), visual, density=density(instance_id))
    return body


def mjcf_body(instance_id: str, visual: bool = True) -> str:
    """MJCF of a model holding the instance as a free body named after it (``/`` as ``_``) standing on
    z = 0, mesh files by absolute path; loads in the main MuJoCo."""
    spec = mujoco.MjSpec()
    spec.modelname = instance_id.replace("/", "_")
    add_instance(spec, instance_id.replace("/", "_"), instance_id, (0.0, 0.0, 0.0), visual=visual)
    return spec.to_xml()
