"""The TaskSpec of a family-03 task: every task's artifact is the sealed ledger of its metered session.

Budget (card, ``constants``): 9 h, 1 GPU, 50,000 charged steps in one continuous attempt (the hidden
COM: 12,000 steps per box, 1 h); resets restore the same scene. The artifact is the sealed ledger of
that attempt (``ledger.jsonl``): the scene the agent left behind is rebuilt from it (``session``), so
nothing else is submitted. ``ledger_task`` builds each task's spec; ``tabletop_task`` those of the
tasks with free pieces on the shared table (tower, cantilever).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path

from rle_tasks.core.runtime.secrets import current_secret as _current_secret
from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec, serving_privileged

from .constants import CPUS, GPUS, STEP_BUDGET, VERIFIER_TIMEOUT_S, WALL_TIME_S
from .scene import make_env
from .verifier import verify

HERE = Path(__file__).resolve().parent


def budget(steps: int = STEP_BUDGET, wall_time_s: float = WALL_TIME_S) -> Budget:
    """The card's budget of a task: ``steps`` charged steps in ``wall_time_s`` [s], 4 CPUs, 1 GPU."""
    return Budget(
        wall_time_s=wall_time_s, cpus=CPUS, gpus=GPUS, steps=steps, verifier_timeout_s=VERIFIER_TIMEOUT_S
    )


BUDGET = budget()
CONTRACT = ArtifactContract(
    required=("ledger.jsonl",),
    description="ledger.jsonl: the sealed ledger of your metered session, as the ledger server wrote it "
    "(`rle dev` prints its path). The final scene is rebuilt from it; nothing else is read.",
    max_total_bytes=256 * 1024 * 1024,
)


def ledger_contract(description: str) -> ArtifactContract:
    """The contract of a task whose only artifact is ``ledger.jsonl`` (``description`` says what it holds)."""
    return ArtifactContract(required=("ledger.jsonl",), description=description)


def task_instruction(task_dir: Path, rubric_table: str, common: bool = False) -> str:
    """The task's instruction (``<task_dir>/instruction.md``), with ``common`` the family's tabletop text
    (``instruction.md``), then the rubric table."""
    text = (Path(task_dir) / "instruction.md").read_text() + "\n"
    if common:
        text += (HERE / "instruction.md").read_text() + "\n"
    return text + rubric_table + "\n"


def ledger_task(
    task_id: str,
    title: str,
    instruction: str,
    contract: ArtifactContract,
    make_dev_env: Callable[[Path], object],
    solutions: tuple[str, ...],
    solutions_module: str,
    task_budget: Budget = BUDGET,
    privileged_oracle: bool = False,
) -> TaskSpec:
    """A family-03 TaskSpec: a recorded ledger, so quick mode verifies the same as full."""
    return TaskSpec(
        quick_reduces=False,
        id=task_id,
        family=3,
        title=title,
        instruction=instruction,
        budget=task_budget,
        contract=contract,
        make_dev_env=make_dev_env,
        verify=partial(verify, task_id=task_id),
        solutions=solutions,
        solutions_module=solutions_module,
        privileged_oracle=privileged_oracle,
    )


def tabletop_task(
    task_id: str,
    title: str,
    task_dir: Path,
    rubric_table: str,
    pieces: Callable[[], tuple],
    solutions: tuple[str, ...],
    solutions_module: str,
) -> TaskSpec:
    """A TaskSpec of free pieces on the shared table whose development environment serves the instance
    of the loaded secret.

    ``pieces()`` derives the instance from ``current_secret()`` (the attempt's) in the ``rle dev``
    process (which holds the secret to derive the ledger key anyway); the scene reaches the ledger
    server, never the agent's workspace.
    """

    def make_dev_env(workspace: Path):
        return make_env(pieces(), privileged=serving_privileged())

    instruction = task_instruction(task_dir, rubric_table, common=True)
    return ledger_task(
        task_id,
        title,
        instruction,
        CONTRACT,
        make_dev_env,
        solutions,
        solutions_module,
        privileged_oracle=True,
    )


def current_secret():
    """The secret of the session ``rle dev`` serves (bound to its attempt), else the loaded one."""
    return _current_secret()
