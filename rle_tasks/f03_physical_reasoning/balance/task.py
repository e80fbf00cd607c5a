"""TaskSpec of ``03-balance-coins``: find the heavy cube among nine with a two-pan balance."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.task import TaskSpec

from ..constants import BALANCE_ID
from ..task import current_secret, ledger_contract, ledger_task, task_instruction
from .env import make_env
from .scoring import RUBRIC
from .verifier import instance

HERE = Path(__file__).resolve().parent
CONTRACT = ledger_contract(
    "ledger.jsonl: the sealed ledger of the metered development session (written by the ledger server "
    "outside the workspace; copy it into the submission)."
)


def make_dev_env(workspace: Path):
    """The metered environment of the instance of the current secret (the public one without a secret)."""
    return make_env(instance(current_secret()))


def task_spec() -> TaskSpec:
    return ledger_task(
        BALANCE_ID,
        "Tabletop physical reasoning: find the heavy cube among nine with a balance",
        task_instruction(HERE, RUBRIC.markdown_table()),
        CONTRACT,
        make_dev_env,
        ("reference", "baseline/five_weighings", "baseline/unsealed"),
        "rle_tasks.f03_physical_reasoning.solutions.balance_coins",
    )
