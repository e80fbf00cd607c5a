"""The kitchens of family 01: the five tasks, the three harness levels, the target kitchens each task's
evaluation draws from the secret, and the session's scene set (the card's numbers: ``constants``)."""

from __future__ import annotations

from dataclasses import dataclass

from rle_tasks.core.runtime.secrets import Secret, derive_seed
from rle_tasks.core.task import Budget
from rle_tasks.envs.kitchen.sessions import KitchenScenes

from .constants import (
    ACTIONS_PER_TRIAL,
    CPUS,
    EVAL_WALL_S,
    GPUS,
    STEP_BUDGET,
    TRIALS,
    VERIFIER_TIMEOUT_S,
    WALL_TIME_S,
)

BUDGET = Budget(
    wall_time_s=WALL_TIME_S, cpus=CPUS, gpus=GPUS, steps=STEP_BUDGET, verifier_timeout_s=VERIFIER_TIMEOUT_S
)
"""The card's budget of every family-01 task."""


@dataclass(frozen=True)
class KitchenTaskId:
    """One of the five kitchen tasks of the card.

    Attributes:
        slug: Id word (``open-fridge`` ...).
        task: Kitchen task name (``rle_tasks.envs.kitchen.tasks``).
        summary: The card's one-line description.
    """

    slug: str
    task: str
    summary: str

    def task_id(self, level: int) -> str:
        return f"01-{self.slug}-l{level}"


KITCHEN_TASKS = (
    KitchenTaskId("open-fridge", "OpenFridge", "open the refrigerator door"),
    KitchenTaskId("close-cabinet", "CloseCabinet", "close the cabinet door"),
    KitchenTaskId("turn-on-stove", "TurnOnStove", "turn on the specified burner"),
    KitchenTaskId("pnp-counter-to-drawer", "PickPlaceCounterToDrawer", "move the target into the drawer"),
    KitchenTaskId(
        "pnp-microwave-to-counter",
        "PickPlaceMicrowaveToCounter",
        "move the target to its counter destination",
    ),
)
LEVELS = (1, 2, 3)
SPLIT = False
"""Kitchens of every layout kind: pretrain kitchens from the pretrain (kind, style family) combinations,
target kitchens from the target ones (``rle_tasks.envs.kitchen.styles.split``); False: every kitchen is
the one-wall kitchen."""


def kitchen_level(task_id: str) -> tuple[KitchenTaskId, int]:
    """The kitchen task and harness level of a task id (``01-<slug>-l<level>``)."""
    for k in KITCHEN_TASKS:
        for level in LEVELS:
            if k.task_id(level) == task_id:
                return k, level
    raise KeyError(f"no family-01 task {task_id!r}")


def targets(secret: Secret, kitchen: KitchenTaskId) -> tuple[tuple[int, int], ...]:
    """(layout seed, episode seed) of each evaluation trial: HMAC(secret, "01-<slug>", "target/<k>/...")."""
    tid = f"01-{kitchen.slug}"
    return tuple(
        (derive_seed(secret, tid, f"target/{k}/layout"), derive_seed(secret, tid, f"target/{k}/episode"))
        for k in range(TRIALS)
    )


def scenes(
    kitchen: KitchenTaskId,
    level: int,
    secret: Secret,
    *,
    image_size: tuple[int, int] | None = (128, 128),
    split: bool | None = None,
) -> KitchenScenes:
    """The session's scene set: pretrain kitchens for development, the secret's targets for evaluation;
    ``split``: kitchens of every layout kind (None: ``SPLIT``)."""
    from rle_design.ledger import EvaluationPhase

    return KitchenScenes(
        kitchen.task,
        level,
        targets(secret, kitchen),
        EvaluationPhase(TRIALS, ACTIONS_PER_TRIAL, EVAL_WALL_S),
        image_size=image_size,
        split=SPLIT if split is None else split,
    )
