"""TaskSpecs of the family's tabletop tasks: shared budget, contract, development environment.

Budget (card): 9 h, 1 GPU, 50,000 charged steps in one continuous attempt; resets restore the same
scene. The artifact is the sealed ledger of that attempt (``ledger.jsonl``): the scene the agent left
behind is rebuilt from it (``session``), so nothing else is submitted.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from rle_tasks.core.secrets import current_secret as _current_secret
from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec, serving_privileged

HERE = Path(__file__).resolve().parent
STEP_BUDGET = 50_000
"""Charged steps of one attempt (card)."""
BUDGET = Budget(wall_time_s=9 * 3600.0, cpus=4, gpus=1, steps=STEP_BUDGET, verifier_timeout_s=1800.0)
CONTRACT = ArtifactContract(
    required=("ledger.jsonl",),
    description="ledger.jsonl: the sealed ledger of your metered session, as the ledger server wrote it "
    "(`rle dev` prints its path). The final scene is rebuilt from it; nothing else is read.",
    max_total_bytes=256 * 1024 * 1024,
)


def instruction(task_file: str, rubric_table: str) -> str:
    """Family instruction (``instruction.md``), the task's (``instructions/<task_file>``), the rubric table."""
    common = (HERE / "instruction.md").read_text()
    task = (HERE / "instructions" / task_file).read_text()
    return task + "\n" + common + "\n" + rubric_table + "\n"


def tabletop_task(
    task_id: str,
    title: str,
    task_file: str,
    rubric_table: str,
    verify: Callable,
    pieces: Callable[[], tuple],
    solutions: tuple[str, ...],
    solutions_module: str,
) -> TaskSpec:
    """A tabletop TaskSpec whose development environment serves the instance of the loaded secret.

    ``pieces()`` derives the instance from ``current_secret()`` (the attempt's) in the ``rle dev``
    process (which holds the secret to derive the ledger key anyway); the scene reaches the ledger server, never the
    agent's workspace.
    """
    from .scene import make_env

    def make_dev_env(workspace: Path):
        return make_env(pieces(), privileged=serving_privileged())

    return TaskSpec(
        quick_reduces=False,  # a recorded ledger: quick verifies the same
        id=task_id,
        family=3,
        title=title,
        instruction=instruction(task_file, rubric_table),
        budget=BUDGET,
        contract=CONTRACT,
        make_dev_env=make_dev_env,
        verify=verify,
        solutions=solutions,
        solutions_module=solutions_module,
        privileged_oracle=True,
    )


def current_secret():
    """The secret of the session ``rle dev`` serves (bound to its attempt), else the loaded one."""
    return _current_secret()
