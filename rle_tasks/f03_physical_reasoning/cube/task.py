"""TaskSpec of ``03-pocket-cube``: solve a physical 2x2x2 cube with two fixed Pandas."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from rle_tasks.core.task import TaskSpec, serving_privileged

from ..constants import CUBE_ID
from ..task import current_secret, ledger_contract, ledger_task, task_instruction
from .env import make_env
from .scene import instance
from .scoring import RUBRIC

HERE = Path(__file__).resolve().parent
CONTRACT = ledger_contract(
    "ledger.jsonl: the sealed ledger of the metered attempt (written by the ledger server outside the "
    "workspace; copy it into the submission)."
)


def make_dev_env(workspace: Path):
    """The metered environment of the scramble of the current secret (the public one without a secret).

    Serving an operator's oracle trial (``serving_privileged``), each observation also holds ``plan``:
    the reference's moves for this scramble (``solutions.pocket_cube.reference.plan``), which the
    exported oracle executes. Agents never get it; the ledger says the session was privileged."""
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
    return ledger_task(
        CUBE_ID,
        "Tabletop physical reasoning: solve a physical 2x2x2 cube with two arms",
        task_instruction(HERE, RUBRIC.markdown_table()),
        CONTRACT,
        make_dev_env,
        (
            "reference",
            "baseline/idle",
            "baseline/dropped",
            "baseline/reset",
            "baseline/forced_twist",
            "baseline/unsealed",
        ),
        "rle_tasks.f03_physical_reasoning.solutions.pocket_cube",
        privileged_oracle=True,
    )
