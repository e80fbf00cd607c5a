"""TaskSpec of ``03-hidden-com``: name the ballast quadrant of three sealed boxes."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec

from .hidden_com_scene import BUDGET_STEPS, WALL_TIME_S

HERE = Path(__file__).resolve().parent
TASK_ID = "03-hidden-com"


def instruction() -> str:
    """The agent instruction with the rubric's table appended."""
    from .hidden_com_verifier import RUBRIC

    return (HERE / "instructions" / "hidden_com.md").read_text() + "\n" + RUBRIC.markdown_table() + "\n"


def make_dev_env(workspace: Path):
    """The metered environment of the instance of the current secret (the public one without a secret)."""
    from rle_tasks.core.secrets import current_secret

    from .hidden_com_env import make_env
    from .hidden_com_verifier import instance

    return make_env(instance(current_secret()))


def task_spec() -> TaskSpec:
    from .hidden_com_verifier import verify

    return TaskSpec(
        quick_reduces=False,  # a recorded ledger: quick verifies the same
        id=TASK_ID,
        family=3,
        title="Tabletop physical reasoning: identify the ballast quadrant of three sealed boxes",
        instruction=instruction(),
        budget=Budget(wall_time_s=WALL_TIME_S, cpus=4, gpus=1, steps=BUDGET_STEPS, verifier_timeout_s=1800.0),
        contract=ArtifactContract(
            required=("ledger.jsonl",),
            description="ledger.jsonl: the sealed ledger of the metered session in which the three answers "
            "were given (written by the ledger server outside the workspace; copy it into the submission).",
        ),
        make_dev_env=make_dev_env,
        verify=verify,
        solutions=("reference", "baseline/random_answers", "baseline/late_answers", "baseline/unsealed"),
        solutions_module=f"{__package__}.solutions.hidden_com",
    )
