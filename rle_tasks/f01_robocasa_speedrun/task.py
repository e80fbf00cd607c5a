"""TaskSpecs of family 01: five kitchen tasks x three harness levels, one metered session each.

Budget (card): 8 h, 1 GPU, 50,000 charged development steps (each reset and executed action one step,
observations free); then one terminal evaluation phase of five trials in five ``target`` kitchens
(at most 1,000 actions each, 1 h), whose actions do not count as development. The target kitchens
of a task derive from the verifier secret (``targets``), shared by its three levels so that the
levels are comparable. The artifact is the session's sealed ledger.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from rle_tasks.core.secrets import Secret, current_secret, derive_seed
from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec
from rle_tasks.envs.kitchen.env import KitchenScenes
from rle_tasks.envs.kitchen.workspace import lay_out_harness

__all__ = [
    "BUDGET",
    "CONTRACT",
    "KITCHEN_TASKS",
    "STEP_BUDGET",
    "TRIALS",
    "KitchenTaskId",
    "scenes",
    "targets",
    "task_specs",
]

HERE = Path(__file__).resolve().parent
STEP_BUDGET = 50_000
"""Charged development steps (card)."""
TRIALS = 5
"""Evaluation trials (card)."""
ACTIONS_PER_TRIAL = 1000
"""Actions one evaluation trial may take (card)."""
EVAL_WALL_S = 3600.0
"""Wall time of the evaluation phase [s] (card)."""
BUDGET = Budget(wall_time_s=8 * 3600.0, cpus=4, gpus=1, steps=STEP_BUDGET, verifier_timeout_s=1800.0)
CONTRACT = ArtifactContract(
    required=("ledger.jsonl",),
    optional=("*.py", "**/*.py", "*.md"),
    description="ledger.jsonl: the sealed ledger of your metered session, as the ledger server wrote it "
    "(`rle dev` prints its path), beside the controller and utility code you developed (kept with the "
    "submission, not run). The evaluation trials are re-executed from the ledger in the target kitchens; "
    "nothing else is read.",
    max_total_bytes=256 * 1024 * 1024,
)


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


def targets(secret: Secret, kitchen: KitchenTaskId) -> tuple[tuple[int, int], ...]:
    """(layout seed, episode seed) of each evaluation trial: HMAC(secret, "01-<slug>", "target/<k>/...")."""
    tid = f"01-{kitchen.slug}"
    return tuple(
        (derive_seed(secret, tid, f"target/{k}/layout"), derive_seed(secret, tid, f"target/{k}/episode"))
        for k in range(TRIALS)
    )


def scenes(
    kitchen: KitchenTaskId, level: int, secret: Secret, *, image_size: tuple[int, int] | None = (128, 128)
) -> KitchenScenes:
    """The session's scene set: pretrain kitchens for development, the secret's targets for evaluation."""
    from rle_design.ledger import EvaluationPhase

    return KitchenScenes(
        kitchen.task,
        level,
        targets(secret, kitchen),
        EvaluationPhase(TRIALS, ACTIONS_PER_TRIAL, EVAL_WALL_S),
        image_size=image_size,
    )


def instruction(kitchen: KitchenTaskId, level: int) -> str:
    from .scoring import rubric

    text = (HERE / "instruction.md").read_text()
    levels = (HERE / "assets" / f"harness_l{level}.md").read_text()
    return (
        text.replace("{TASK}", kitchen.task)
        .replace("{SUMMARY}", kitchen.summary)
        .replace("{LEVEL}", str(level))
        .replace("{HARNESS}", levels.strip())
        + "\n"
        + rubric(kitchen.task_id(level)).markdown_table()
        + "\n"
    )


def task_specs() -> list[TaskSpec]:
    from .solutions import SOLUTIONS
    from .verifier import verifier

    specs = []
    for kitchen in KITCHEN_TASKS:
        for level in LEVELS:
            tid = kitchen.task_id(level)

            def make_dev_env(
                workspace: Path, kitchen: KitchenTaskId = kitchen, level: int = level
            ) -> KitchenScenes:
                lay_out_harness(workspace, level)
                return scenes(kitchen, level, current_secret())

            specs.append(
                TaskSpec(
                    quick_reduces=False,  # a recorded ledger: quick verifies the same
                    id=tid,
                    family=1,
                    title=f"RoboCasa speed-run, {kitchen.task}: {kitchen.summary} (harness L{level})",
                    instruction=instruction(kitchen, level),
                    budget=BUDGET,
                    contract=CONTRACT,
                    make_dev_env=make_dev_env,
                    verify=verifier(kitchen, level),
                    solutions=SOLUTIONS[tid].names if tid in SOLUTIONS else (),
                    solutions_module="rle_tasks.f01_robocasa_speedrun.solutions",
                )
            )
    return specs
