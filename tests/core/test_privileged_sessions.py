"""Privileged development sessions (an operator's oracle trial): only tasks that declare a privileged
oracle serve one, and no score of one enters the index or a reward unless asked for on purpose."""

import pytest

from rle_design.errors import RleError
from rle_tasks.core.export.harbor.results import TrialRecord, systems
from rle_tasks.core.export.harbor.reward import reward_from_report
from rle_tasks.core.index import compute_index
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.devenv import layout_workspace

PRIVILEGED = {
    "task_id": "03-cantilever",
    "score": 0.8,
    "errors": [{"code": "ledger.privileged", "message": "m"}],
}


def test_a_task_without_a_privileged_oracle_refuses_a_privileged_session(tmp_path):
    with pytest.raises(RleError) as err:
        layout_workspace(get_task("07-bin-clearing"), tmp_path / "ws", serve=False, privileged=True)
    assert err.value.code == "task.no_privileged"
    assert get_task("03-cantilever").privileged_oracle and not get_task("03-balance-coins").privileged_oracle


def test_the_index_refuses_a_privileged_report_unless_allowed():
    with pytest.raises(RleError) as err:
        compute_index([PRIVILEGED])
    assert err.value.code == "index.privileged" and "oracle" in str(err.value)
    assert compute_index([PRIVILEGED], allow_privileged=True).task_scores["03-cantilever"] == 0.8


def test_a_harbor_job_with_a_privileged_trial_is_refused_unless_allowed():
    trial = TrialRecord("oracle", "03-cantilever", "t1", 0.8, privileged=True)
    with pytest.raises(RleError):
        systems([trial])
    assert systems([trial], allow_privileged=True)["oracle"][0].task_scores["03-cantilever"] == 0.8


def test_the_reward_of_a_privileged_report_is_zero_unless_the_verifier_verifies_the_oracle():
    report = {**PRIVILEGED, "checkpoints": [{"id": "overhang", "score": 0.8}]}
    assert reward_from_report(report, True) == {
        "reward": 0.0, "secret_private": 1.0, "privileged": 1.0, "overhang": 0.0
    }  # fmt: skip
    assert reward_from_report(report, True, oracle=True)["reward"] == 0.8
    plain = {"task_id": "03-cantilever", "score": 0.8, "errors": [], "checkpoints": []}
    assert reward_from_report(plain, True) == {"reward": 0.8, "secret_private": 1.0}
