"""A layout on its own: the kitchen of a ``Layout`` (no task, no objects), with the mobile Panda
standing at a given pose if asked, compiled-ready. For pictures of layouts and for the reachability
check (``floorplan``); task scenes are ``scene.build_scene``'s."""

from __future__ import annotations

import math

import mujoco
import numpy as np

from rle_design.scene.arena import Arena
from rle_design.scene.floor import FloorConfig
from rle_design.scene.mobile_panda import MobilePandaConfig
from rle_design.scene.robots import PANDA
from rle_tasks.envs.kitchen.fixture import Fixture
from rle_tasks.envs.kitchen.layout import Layout, build_layout
from rle_tasks.envs.kitchen.scene import ROBOT, TORSO_START, USERDATA

__all__ = ["layout_xml"]


def layout_xml(
    layout: Layout, robot: tuple[float, float, float] | None = None, *, size: tuple[int, int] = (640, 480)
) -> tuple[str, dict[str, Fixture]]:
    """MJCF of ``layout``'s kitchen and its fixtures by name; with ``robot`` = (x, y, yaw) [m, m, rad]
    the mobile Panda stands there, and the keyframe ``initial`` holds its arm at home, the torso at
    ``scene.TORSO_START`` and the fingers open. ``size``: the offscreen buffer (width, height) [px]."""
    spec = mujoco.MjSpec()
    spec.modelname = "kitchen_layout"
    spec.compiler.degree = False
    Arena(floor=FloorConfig(rgba=layout.style.floor)).edit_spec(spec)
    spec.nuserdata = USERDATA
    spec.visual.global_.offwidth, spec.visual.global_.offheight = size
    spec.stat.extent = 3.0
    fixtures = build_layout(spec, layout)
    if robot is None:
        return spec.to_xml(), fixtures
    x, y, yaw = robot
    spec.worldbody.add_site(
        name="robot_mount", pos=[x, y, 0.0], quat=[math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)], group=5
    )
    MobilePandaConfig(site="robot_mount", prefix=ROBOT.prefix).edit_spec(spec)
    model = spec.compile()
    data = mujoco.MjData(model)
    data.qpos[[model.jnt_qposadr[model.joint(j).id] for j in ROBOT.joints]] = PANDA.home
    data.qpos[model.jnt_qposadr[model.joint(ROBOT.torso_joint).id]] = TORSO_START
    data.ctrl[model.actuator(ROBOT.torso_actuator).id] = TORSO_START
    for finger, q in zip(ROBOT.fingers, (0.04, -0.04)):
        a = model.actuator(finger).id
        data.ctrl[a] = q
        data.qpos[model.jnt_qposadr[model.actuator_trnid[a, 0]]] = q
    spec.add_key(name="initial", qpos=data.qpos.tolist(), ctrl=data.ctrl.tolist())
    return spec.to_xml(), fixtures


def robot_geoms(model: mujoco.MjModel) -> np.ndarray:
    """Ids of the robot's geoms (bodies named with the robot's prefix)."""
    return np.array(
        [g for g in range(model.ngeom) if model.body(model.geom_bodyid[g]).name.startswith(ROBOT.prefix)]
    )
