"""Registration, folder shape, README table, and verifier faults (cheap baselines)."""

from pathlib import Path

import pytest

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f07_bin_clearing.scoring import RUBRIC
from rle_tasks.f07_bin_clearing.verifier import verify

HERE = Path(__file__).resolve().parents[2] / "rle_tasks" / "f07_bin_clearing"


def test_registered_and_readme_table():
    task = get_task("07-bin-clearing")
    assert task.implemented and task.family == 7
    assert RUBRIC.markdown_table() in (HERE / "README.md").read_text()
    assert RUBRIC.markdown_table() in task.instruction


def _ctx(**kw):
    return VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True, hang_cap_s=2.0, **kw)


def test_missing_policy_scores_zero(tmp_path):
    rep = verify(tmp_path, _ctx())
    assert rep.score == 0.0 and not rep.valid
    assert rep.errors[0].code == "f07.no_policy"


def test_unimportable_policy_scores_zero(tmp_path):
    (tmp_path / "policy").mkdir()
    (tmp_path / "policy" / "__init__.py").write_text("import does_not_exist_anywhere\n")
    rep = verify(tmp_path, _ctx())
    assert rep.score == 0.0 and rep.cap == 0.0


@pytest.mark.physics
def test_raising_policy_is_capped_by_the_smoke_test(tmp_path):
    d = materialise("07-bin-clearing", "baseline/raising", tmp_path / "s")
    rep = verify(d, _ctx())
    assert rep.cap == 0.1 and rep.score == 0.0
    assert any("smoke test failed" in e.message for e in rep.errors)
