"""TaskSpec of ``03-hidden-com``: name the ballast quadrant of three sealed boxes."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.task import TaskSpec

from ..constants import HIDDEN_COM_ID, HIDDEN_COM_STEPS, HIDDEN_COM_WALL_TIME_S
from ..task import budget, current_secret, ledger_contract, ledger_task, task_instruction
from .env import make_env
from .scoring import RUBRIC
from .verifier import instance

HERE = Path(__file__).resolve().parent
CONTRACT = ledger_contract(
    "ledger.jsonl: the sealed ledger of the metered session in which the three answers were given (written "
    "by the ledger server outside the workspace; copy it into the submission)."
)


def make_dev_env(workspace: Path):
    """The metered environment of the instance of the current secret (the public one without a secret)."""
    return make_env(instance(current_secret()))


def task_spec() -> TaskSpec:
    return ledger_task(
        HIDDEN_COM_ID,
        "Tabletop physical reasoning: identify the ballast quadrant of three sealed boxes",
        task_instruction(HERE, RUBRIC.markdown_table()),
        CONTRACT,
        make_dev_env,
        ("reference", "baseline/random_answers", "baseline/late_answers", "baseline/unsealed"),
        "rle_tasks.f03_physical_reasoning.solutions.hidden_com",
        task_budget=budget(HIDDEN_COM_STEPS, HIDDEN_COM_WALL_TIME_S),
    )
