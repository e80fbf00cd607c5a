"""The seam between the kitchen tasks and a kitchen simulator.

Families 01 and 02 need five things of a kitchen: ``reset`` to a task's initial state in a given
kitchen, ``step`` with a 12-D action, ``observe``, the task's ``success`` predicate and its ``stages``
(each conjunct of the predicate, for family 02's partial credit). ``KitchenBackend`` states that
interface; ``BuiltinKitchen`` implements it on the MjSpec kitchen of this package (what the metered
sessions serve).

A RoboCasa-backed implementation is not shipped: RoboCasa is not installable here (not on the package
registry, ~10 GB of assets fetched at run time, robosuite APIs newer than the released wheel). An
operator who has it would implement ``KitchenBackend`` as follows, and nothing else changes:

- ``reset(task, layout, style, episode)``: ``robocasa.environments.kitchen.<Task>(robots="PandaOmron",
  layout_ids=layout, style_ids=style, seed=episode, camera_names=[robot0_agentview_left,
  robot0_agentview_right, robot0_eye_in_hand], camera_heights=128, camera_widths=128,
  camera_depths=True)``, then ``env.reset()``;
- ``step(action)``: RoboCasa's PandaOmron action has the same 12 entries in the same order (arm 0:6,
  gripper 6, base 7:10, torso 10, mode 11); pass it unchanged to ``env.step``;
- ``observe()``: rename ``robot0_base_pos``, ``robot0_base_quat``, ``robot0_base_to_eef_pos`` ... to this
  package's keys (``rle_design.control.mobile``), images from ``<camera>_image`` and ``<camera>_depth``
  (RoboCasa's depth is normalised: convert with ``robosuite.utils.camera_utils.get_real_depth_map``);
- ``success()``: ``env._check_success()``; ``stages()``: the conjuncts of that method, written out per
  task as ``rle_tasks.envs.kitchen.tasks`` does (RoboCasa has no stage API).
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import mujoco
import numpy as np

from rle_tasks.envs.kitchen.env import KitchenEnv
from rle_tasks.envs.kitchen.scene import build_scene

__all__ = ["BuiltinKitchen", "KitchenBackend"]


@runtime_checkable
class KitchenBackend(Protocol):
    """A kitchen simulator serving the kitchen tasks."""

    def reset(self, task: str, layout: int, episode: int) -> dict[str, Any]:
        """Initial state of ``task`` in kitchen ``layout`` with episode ``episode``; the observation."""

    def step(self, action: np.ndarray) -> dict[str, Any]:
        """One 12-D action (20 Hz); the observation."""

    def observe(self) -> dict[str, Any]:
        """The current observation."""

    def success(self) -> bool:
        """The task's success predicate on the current state."""

    def stages(self) -> dict[str, bool]:
        """Each conjunct of the success predicate, by name."""


class BuiltinKitchen:
    """``KitchenBackend`` on this package's MjSpec kitchen.

    Args:
        level: Harness level of the observation (1-3).
        image_size: Camera images (None renders none).
    """

    def __init__(self, level: int = 1, image_size: tuple[int, int] | None = (128, 128)) -> None:
        self.level = level
        self.image_size = image_size
        self.env: KitchenEnv | None = None
        self.model: mujoco.MjModel | None = None
        self.data: mujoco.MjData | None = None

    def reset(self, task: str, layout: int, episode: int) -> dict[str, Any]:
        scene = build_scene(layout, task, episode)
        self.env = KitchenEnv(xml=scene.xml, scene=scene, level=self.level, image_size=self.image_size)
        self.model = self.env.build()
        self.env.prepare(self.model)
        self.data = mujoco.MjData(self.model)
        self.env.reset(self.model, self.data)
        return self.observe()

    def _ready(self) -> KitchenEnv:
        if self.env is None:
            raise RuntimeError("BuiltinKitchen: reset() first")
        return self.env

    def step(self, action: np.ndarray) -> dict[str, Any]:
        self._ready().step(self.model, self.data, np.asarray(action, dtype=float))
        return self.observe()

    def observe(self) -> dict[str, Any]:
        return self._ready().observe(self.model, self.data)

    def success(self) -> bool:
        return self._ready().success(self.model, self.data)

    def stages(self) -> dict[str, bool]:
        return self._ready().conditions(self.model, self.data)
