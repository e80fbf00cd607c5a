"""TaskSpecs of family 01: five kitchen tasks x three harness levels, one metered session each.

Budget (card): 8 h, 1 GPU, 50,000 charged development steps (each reset and executed action one step,
observations free); then one terminal evaluation phase of five trials in five ``target`` kitchens
(at most 1,000 actions each, 1 h), whose actions do not count as development. The target kitchens
of a task derive from the verifier secret (``targets``), shared by its three levels so that the
levels are comparable. The artifact is the session's sealed ledger.
"""

from __future__ import annotations

from functools import partial
from pathlib import Path

from rle_tasks.core.runtime.secrets import current_secret
from rle_tasks.core.task import ArtifactContract, TaskSpec
from rle_tasks.envs.kitchen.sessions import KitchenScenes
from rle_tasks.envs.kitchen.workspace import lay_out_harness

from .kitchens import (
    ACTIONS_PER_TRIAL,
    BUDGET,
    EVAL_WALL_S,
    KITCHEN_TASKS,
    LEVELS,
    STEP_BUDGET,
    TRIALS,
    KitchenTaskId,
    scenes,
    targets,
)
from .verifier import verify

__all__ = [
    "ACTIONS_PER_TRIAL",
    "BUDGET",
    "CONTRACT",
    "EVAL_WALL_S",
    "KITCHEN_TASKS",
    "LEVELS",
    "STEP_BUDGET",
    "TRIALS",
    "KitchenTaskId",
    "scenes",
    "targets",
    "task_specs",
]

HERE = Path(__file__).resolve().parent
CONTRACT = ArtifactContract(
    required=("ledger.jsonl",),
    optional=("*.py", "**/*.py", "*.md"),
    description="ledger.jsonl: the sealed ledger of your metered session, as the ledger server wrote it "
    "(`rle dev` prints its path), beside the controller and utility code you developed (kept with the "
    "submission, not run). The evaluation trials are re-executed from the ledger in the target kitchens; "
    "nothing else is read.",
    max_total_bytes=256 * 1024 * 1024,
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
                    verify=partial(verify, task_id=tid),
                    solutions=SOLUTIONS[tid].names if tid in SOLUTIONS else (),
                    solutions_module="rle_tasks.f01_robocasa_speedrun.solutions",
                )
            )
    return specs
