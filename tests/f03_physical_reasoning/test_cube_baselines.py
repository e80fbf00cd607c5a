"""03-pocket-cube: the shipped baselines (committed public-key ledgers) score 0, each for its stated reason."""

import pytest

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import declaration, materialise
from rle_tasks.core.task import VerifyContext

CTX = VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True)


@pytest.mark.physics
@pytest.mark.parametrize(
    "name", ["baseline/idle", "baseline/dropped", "baseline/reset", "baseline/forced_twist"]
)
def test_shipped_baseline_scores_zero_for_its_reason(name):
    task = get_task("03-pocket-cube")
    report = task.verify(materialise(task, name), CTX)
    assert report.valid and report.score == declaration(task).get(name).quick_score == 0.0
    check = report.checkpoints[0]
    if name == "baseline/idle":
        assert "faces are not uniform" in check.message and "rests on or beside its stand" in check.message
    elif name == "baseline/dropped":
        assert "rests on the table" in check.message and check.measured["turns"] == 0
    elif name == "baseline/reset":
        assert check.message == "attempt abandoned: 1 reset(s) after the start"
    else:  # the forced twist: one unclassified transition, so the 0.5 cap is reported
        assert check.measured["unclassified"] == 1 and report.cap == 0.5
        assert check.message.startswith("cube not solved")
