"""TaskSpec of ``03-pocket-cube``: solve a physical 2x2x2 cube with two fixed Pandas."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec
from rle_tasks.f03_physical_reasoning.cube.scene import BUDGET_STEPS, TASK_ID, WALL_TIME_S

HERE = Path(__file__).resolve().parent


def instruction() -> str:
    """The agent instruction with the rubric's table appended."""
    from .verifier import RUBRIC

    text = (HERE.parent / "instructions" / "pocket_cube.md").read_text()
    return text + "\n" + RUBRIC.markdown_table() + "\n"


def make_dev_env(workspace: Path):
    """The metered environment of the scramble of the current secret (the public one without a secret).

    Serving an operator's oracle trial (``serving_privileged``), each observation also holds ``plan``:
    the reference's moves for this scramble (``solutions.pocket_cube.reference.plan``), which the
    exported oracle executes. Agents never get it; the ledger says the session was privileged."""
    from rle_tasks.core.secrets import current_secret
    from rle_tasks.core.task import serving_privileged

    from .env import make_env
    from .scene import instance

    inst = instance(current_secret())
    env = make_env(inst)
    if not serving_privileged():
        return env
    from ..solutions.pocket_cube.reference import plan

    moves = tuple(plan(inst.state))
    return dataclasses.replace(env, observers=(*env.observers, ("plan", _Plan(moves))))


@dataclasses.dataclass(frozen=True)
class _Plan:
    """Observer of a privileged session: the reference's plan (a constant list of move names)."""

    moves: tuple[str, ...]

    def __call__(self, model, data) -> list[str]:
        return list(self.moves)


def task_spec() -> TaskSpec:
    from .verifier import verify

    return TaskSpec(
        quick_reduces=False,  # a recorded ledger: quick verifies the same
        id=TASK_ID,
        family=3,
        title="Tabletop physical reasoning: solve a physical 2x2x2 cube with two arms",
        instruction=instruction(),
        budget=Budget(wall_time_s=WALL_TIME_S, cpus=4, gpus=1, steps=BUDGET_STEPS, verifier_timeout_s=1800.0),
        contract=ArtifactContract(
            required=("ledger.jsonl",),
            description="ledger.jsonl: the sealed ledger of the metered attempt (written by the ledger server "
            "outside the workspace; copy it into the submission).",
        ),
        make_dev_env=make_dev_env,
        verify=verify,
        solutions=(
            "reference",
            "baseline/idle",
            "baseline/dropped",
            "baseline/reset",
            "baseline/forced_twist",
            "baseline/unsealed",
        ),
        solutions_module="rle_tasks.f03_physical_reasoning.solutions.pocket_cube",
        privileged_oracle=True,
    )
