"""One kitchen scene: a layout, a task's episode and the mobile Panda, compiled into MJCF.

``build_scene(layout_seed, task, episode_seed, part)`` is deterministic: the same seeds give the same
MJCF string (and so the same model digest recorded in ledgers). The layout comes from
``default_rng(layout_seed)``: today's one-wall kitchen (``layout.sample_one_wall``) when ``part`` is
None, else a kitchen of a (layout kind, style family) combination of ``part`` (``pretrain`` or
``target``, ``layout_kinds.sample_part``); the episode (target, objects, spawn) from ``default_rng(episode_seed)``.
The scene's keyframe ``initial`` holds the arm at its home posture, the torso at ``TORSO_START``,
the fingers open, the articulated joints at the episode's states and the objects settled on their
supports (``SETTLE_S`` of physics with the robot held still).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.scene.arena import Arena
from rle_design.scene.floor import FloorConfig
from rle_design.scene.mobile_panda import MobilePandaConfig, MobilePandaNames
from rle_design.scene.robots import PANDA
from rle_tasks.envs.kitchen.composite_tasks import kitchen_task
from rle_tasks.envs.kitchen.fixture import Fixture
from rle_tasks.envs.kitchen.layout import Layout, build_layout, sample_one_wall
from rle_tasks.envs.kitchen.layout_kinds import sample_part
from rle_tasks.envs.kitchen.objects import add_object, extent
from rle_tasks.envs.kitchen.tasks import Episode

__all__ = ["KitchenScene", "ROBOT", "TORSO_START", "build_scene", "scene_of"]

ROBOT = MobilePandaNames("robot/")
"""Names of the robot's elements."""
TORSO_START = 0.15
"""Torso height at the start of an episode [m]."""
SETTLE_S = 0.3
"""Physics time the objects settle before the keyframe is stored [s]."""
USERDATA = 7
"""``userdata`` entries (the arm target of ``MobileManipulatorEnv``)."""


@dataclass(frozen=True)
class KitchenScene:
    """A compiled-ready kitchen scene.

    Attributes:
        xml: MJCF (mesh files by absolute path).
        layout_seed: Seed of the layout.
        episode_seed: Seed of the episode.
        layout: The sampled layout.
        fixtures: Fixtures by name.
        episode: The task's sampled episode.
    """

    xml: str
    layout_seed: int
    episode_seed: int
    layout: Layout
    fixtures: dict[str, Fixture]
    episode: Episode

    @property
    def task(self) -> str:
        return self.episode.task


def _settle(model: mujoco.MjModel, data: mujoco.MjData, robot_dofs: np.ndarray, robot_q: np.ndarray) -> None:
    qadr = robot_q
    hold = data.qpos[qadr].copy()
    for _ in range(int(round(SETTLE_S / model.opt.timestep))):
        mujoco.mj_step(model, data)
        data.qpos[qadr] = hold
        data.qvel[robot_dofs] = 0.0
    data.qvel[:] = 0.0
    data.qacc_warmstart[:] = 0.0
    mujoco.mj_forward(model, data)


def _place(
    model: mujoco.MjModel, data: mujoco.MjData, p, fixtures: dict[str, Fixture], categories: dict[str, str]
) -> None:
    """Put object ``p`` inside its fixture's interior or on its container (free joint qpos), 5 mm above."""
    center, half = extent(p.category)
    lift = half[2] - center[2] + 0.005
    if p.inside is not None:
        box = fixtures[p.inside].interior
        b = model.body(box.body).id
        rot = data.xmat[b].reshape(3, 3)
        margin = np.maximum(np.asarray(box.half[:2]) - max(half[0], half[1]) - 0.01, 0.0)
        local = np.array([2 * p.pos[0] * margin[0], 2 * p.pos[1] * margin[1], box.center[2] - box.half[2]])
        local[:2] += box.center[:2]
        pos = data.xpos[b] + rot @ local
    else:
        host = model.body(p.on).id
        _, hh = extent(categories[p.on])
        pos = data.xpos[host] + np.array([p.pos[0] * hh[0], p.pos[1] * hh[1], 2 * hh[2] - 0.01])
    adr = model.jnt_qposadr[model.joint(p.name).id]
    data.qpos[adr : adr + 3] = pos + np.array([0.0, 0.0, lift])
    data.qpos[adr + 3 : adr + 7] = (math.cos(p.yaw / 2), 0.0, 0.0, math.sin(p.yaw / 2))


@functools.lru_cache(maxsize=8)
def build_scene(layout_seed: int, task: str, episode_seed: int, part: str | None = None) -> KitchenScene:
    """The scene of ``task`` in the kitchen of ``layout_seed`` with the episode of ``episode_seed``;
    ``part``: None for the one-wall kitchen, ``pretrain`` or ``target`` for a kitchen of that part of
    the kind x style split (see the module docstring).

    Raises:
        KeyError: ``task`` is not one of ``TASKS`` (the message lists them).
        ValueError: ``part`` is not None, ``pretrain`` or ``target``.
    """
    rng = np.random.default_rng(layout_seed)
    layout = sample_one_wall(rng) if part is None else sample_part(rng, part)
    return scene_of(layout, task, episode_seed, layout_seed)


def scene_of(layout: Layout, task: str, episode_seed: int, layout_seed: int = -1) -> KitchenScene:
    """The scene of ``task`` in ``layout`` with the episode of ``episode_seed`` (``layout_seed`` is only
    recorded)."""
    definition = kitchen_task(task)
    spec = mujoco.MjSpec()
    spec.modelname = "kitchen"
    spec.compiler.degree = False  # every angle of the kitchen (joint ranges) is in radians
    Arena(floor=FloorConfig(rgba=layout.style.floor)).edit_spec(spec)
    spec.nuserdata = USERDATA
    spec.visual.global_.offwidth = 640
    spec.visual.global_.offheight = 480
    spec.stat.extent = 3.0
    spec.visual.quality.numslices = 12  # round primitives in 12 slices: cameras render in 5-6 ms per view
    spec.visual.quality.numstacks = 6
    fixtures = build_layout(spec, layout)
    episode = definition.sample(fixtures, np.random.default_rng(episode_seed))
    x, y, yaw = episode.robot
    spec.worldbody.add_site(
        name="robot_mount", pos=[x, y, 0.0], quat=[math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)], group=5
    )
    MobilePandaConfig(site="robot_mount", prefix=ROBOT.prefix).edit_spec(spec)
    for p in episode.objects:
        placed_later = p.inside is not None or p.on is not None
        add_object(spec, p.name, p.category, (0.0, 0.0, -5.0) if placed_later else p.pos, p.yaw)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetData(model, data)
    arm_q = np.array([model.jnt_qposadr[model.joint(j).id] for j in ROBOT.joints])
    data.qpos[arm_q] = PANDA.home
    torso = model.jnt_qposadr[model.joint(ROBOT.torso_joint).id]
    data.qpos[torso] = TORSO_START
    data.ctrl[model.actuator(ROBOT.torso_actuator).id] = TORSO_START
    for finger, q in zip(ROBOT.fingers, (0.04, -0.04)):
        a = model.actuator(finger).id
        data.ctrl[a] = q
        data.qpos[model.jnt_qposadr[model.actuator_trnid[a, 0]]] = q
    for joint, frac in episode.joints:
        j = model.joint(joint).id
        low, high = model.jnt_range[j]
        data.qpos[model.jnt_qposadr[j]] = low + frac * (high - low)
    mujoco.mj_forward(model, data)
    for p in episode.objects:
        if p.inside is not None or p.on is not None:
            _place(model, data, p, fixtures, {q.name: q.category for q in episode.objects})
            mujoco.mj_forward(model, data)
    robot_joints = [model.joint(j).id for j in (*ROBOT.base_joints, ROBOT.torso_joint, *ROBOT.joints)]
    fingers = [model.actuator_trnid[model.actuator(f).id, 0] for f in ROBOT.fingers]
    robot_joints += fingers
    _settle(
        model,
        data,
        np.array([model.jnt_dofadr[j] for j in robot_joints]),
        np.array([model.jnt_qposadr[j] for j in robot_joints]),
    )
    spec.add_key(name="initial", qpos=data.qpos.tolist(), ctrl=data.ctrl.tolist())
    return KitchenScene(spec.to_xml(), int(layout_seed), int(episode_seed), layout, fixtures, episode)
