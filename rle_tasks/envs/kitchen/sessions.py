"""The scenes of a metered kitchen session: ``KitchenScenes`` (one task at one harness level: development
resets play ``pretrain`` kitchens of public seeds, the evaluation phase five ``target`` kitchens whose
seeds the task derives from the verifier secret) and ``GroupScenes`` (several tasks, family 02)."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from typing import Any

import mujoco

from rle_design.control.layout import ACTION_SIZE
from rle_design.ledger import EvaluationPhase, LedgerError, SceneSet
from rle_tasks.envs.kitchen.composite_tasks import kitchen_task
from rle_tasks.envs.kitchen.env import LEVELS, KitchenEnv
from rle_tasks.envs.kitchen.scene import KitchenScene, build_scene

__all__ = [
    "PRETRAIN_BASE",
    "PRETRAIN_KITCHENS",
    "GroupScenes",
    "KitchenScenes",
    "episode_seed",
    "pretrain_seed",
]

PRETRAIN_KITCHENS = 50
"""Number of pretrain kitchen layouts (public)."""
PRETRAIN_BASE = 1_000_003
"""Layout seed of pretrain kitchen k is ``PRETRAIN_BASE + k`` (public)."""


def pretrain_seed(kitchen: int) -> int:
    """Layout seed of pretrain kitchen ``kitchen`` (0-based)."""
    return PRETRAIN_BASE + int(kitchen)


@dataclass(frozen=True)
class KitchenScenes(SceneSet):
    """The scenes of one kitchen task at one harness level.

    Attributes:
        task: Kitchen task name (``rle_tasks.envs.kitchen.tasks.TASKS``).
        level: Harness level (1-3).
        targets: (layout seed, episode seed) of each evaluation trial (from the verifier secret).
        evaluation: The terminal evaluation phase.
        image_size: Camera image size (None renders none: verification replays).
        pretrain_kitchens: Number of pretrain layouts.
        split: Pretrain kitchens are drawn from the pretrain (layout kind, style family) combinations
            and target kitchens from the target ones (``styles.split``); False: every kitchen is today's
            one-wall kitchen (``scene.build_scene``'s ``part``).
    """

    task: str
    level: int = 1
    targets: tuple[tuple[int, int], ...] = ()
    evaluation: EvaluationPhase | None = EvaluationPhase(trials=5, actions_per_trial=1000, wall_time_s=3600.0)
    image_size: tuple[int, int] | None = (128, 128)
    pretrain_kitchens: int = PRETRAIN_KITCHENS
    n_substeps: int = 25
    split: bool = False
    observation_doc: str = KitchenEnv.observation_doc

    def __post_init__(self) -> None:
        kitchen_task(self.task)  # KeyError listing the tasks when unknown
        if self.level not in LEVELS:
            raise ValueError(f"harness level must be one of {LEVELS}, got {self.level}")
        if self.evaluation is not None and len(self.targets) < self.evaluation.trials:
            raise ValueError(
                f"{self.evaluation.trials} evaluation trials need as many targets, got {len(self.targets)}"
            )

    def describe(self) -> str:
        kinds = " kinds split" if self.split else ""
        return f"kitchen {self.task} L{self.level} pretrain {self.pretrain_kitchens}{kinds}"

    def _part(self, part: str) -> str | None:
        return part if self.split else None

    def session_doc(self) -> str:
        return (
            f"Development: env.reset() starts the next of {self.pretrain_kitchens} pretrain kitchens; "
            f"env.reset(kitchen=k, seed=s) picks kitchen k (0-{self.pretrain_kitchens - 1}) and episode s. "
            + self.evaluation_doc()
        )

    def action_size(self) -> int:
        """The mobile manipulator's fixed layout (``KitchenEnv.action_size``): no scene is built."""
        return ACTION_SIZE

    def _env(self, scene: KitchenScene) -> KitchenEnv:
        return KitchenEnv(xml=scene.xml, scene=scene, level=self.level, image_size=self.image_size)

    def scene(self, key: str) -> KitchenEnv:
        parts = key.split("/")
        numbers = [int(p) for p in parts[1:] if p.isdigit()]
        if (
            parts[0] == "pretrain"
            and len(parts) == 3
            and len(numbers) == 2
            and numbers[0] < self.pretrain_kitchens
        ):
            k, s = numbers
            return self._env(
                build_scene(pretrain_seed(k), self.task, episode_seed(k, s), self._part("pretrain"))
            )
        if parts[0] == "target" and len(parts) == 2 and len(numbers) == 1 and numbers[0] < len(self.targets):
            layout, episode = self.targets[numbers[0]]
            return self._env(build_scene(layout, self.task, episode, self._part("target")))
        raise LedgerError(f"unknown scene '{key}'", code="ledger.bad_scene")

    def development_key(self, index: int, options: dict[str, Any]) -> str:
        unknown = set(options) - {"kitchen", "seed"}
        if unknown:
            raise LedgerError(
                f"unknown reset options {sorted(unknown)}; options: kitchen, seed, evaluation",
                code="ledger.bad_request",
            )
        kitchen, seed = options.get("kitchen", index % self.pretrain_kitchens), options.get("seed", index)
        if not (isinstance(kitchen, int) and 0 <= kitchen < self.pretrain_kitchens):
            raise LedgerError(
                f"kitchen must be an integer in [0, {self.pretrain_kitchens}), got {kitchen!r}",
                code="ledger.bad_request",
            )
        if not (isinstance(seed, int) and 0 <= seed < 2**31):
            raise LedgerError(
                f"seed must be an integer in [0, 2**31), got {seed!r}", code="ledger.bad_request"
            )
        return f"pretrain/{kitchen}/{seed}"

    def evaluation_key(self, trial: int) -> str:
        return f"target/{trial}"

    def success(self, env: KitchenEnv, model: mujoco.MjModel, data: mujoco.MjData) -> bool:
        return env.success(model, data)


def episode_seed(kitchen: int, seed: int) -> int:
    return int.from_bytes(hashlib.sha256(f"pretrain|{kitchen}|{seed}".encode()).digest()[:8], "little") >> 1


@dataclass(frozen=True)
class GroupScenes(KitchenScenes):
    """Development scenes of several kitchen tasks in one session (family 02): ``reset(task=...)`` picks
    the task (by default the tasks take turns), ``kitchen`` and ``seed`` as for ``KitchenScenes``; there
    is no evaluation phase.

    Attributes:
        tasks: The tasks a reset may pick (``task`` is the first).
    """

    tasks: tuple[str, ...] = ()
    evaluation: EvaluationPhase | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        for t in self.tasks:
            kitchen_task(t)
        if self.task not in self.tasks:
            raise ValueError(f"GroupScenes.task '{self.task}' must be one of its tasks {self.tasks}")

    def describe(self) -> str:
        return f"kitchen group {','.join(self.tasks)} L{self.level} pretrain {self.pretrain_kitchens}"

    def session_doc(self) -> str:
        return (
            f"Development: env.reset() starts the next episode, the tasks {', '.join(self.tasks)} taking turns "
            f"over {self.pretrain_kitchens} pretrain kitchens; env.reset(task=name, kitchen=k, seed=s) picks one. "
            "Every reset and action is charged."
        )

    def scene(self, key: str) -> KitchenEnv:
        parts = key.split("/")
        if parts[0] == "pretrain" and len(parts) == 4 and parts[1] in self.tasks:
            try:
                k, s = int(parts[2]), int(parts[3])
            except ValueError:
                k, s = -1, -1
            if 0 <= k < self.pretrain_kitchens and s >= 0:
                return self._env(
                    build_scene(pretrain_seed(k), parts[1], episode_seed(k, s), self._part("pretrain"))
                )
        raise LedgerError(f"unknown scene '{key}'", code="ledger.bad_scene")

    def development_key(self, index: int, options: dict[str, Any]) -> str:
        task = options.get("task", self.tasks[index % len(self.tasks)])
        if task not in self.tasks:
            raise LedgerError(
                f"task must be one of {', '.join(self.tasks)}, got {task!r}", code="ledger.bad_request"
            )
        rest = {k: v for k, v in options.items() if k != "task"}
        key = super().development_key(index, rest)
        return key.replace("pretrain/", f"pretrain/{task}/", 1)
