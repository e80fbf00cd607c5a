"""The family-01 verifier on shipped ledgers: the reference scores R = s [0.8 + 0.2 (1 - d/50,000)] from
its replayed trials, and every broken or foreign ledger scores 0 with its reason."""

import gzip
import os
import shutil

import pytest

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f01_robocasa_speedrun.solutions import make_ledgers
from rle_tasks.f01_robocasa_speedrun.task import KITCHEN_TASKS

PUBLIC = Secret(PUBLIC_KEY, public=True)
CTX = VerifyContext(secret=PUBLIC)
TASK = "01-turn-on-stove-l3"


@pytest.fixture(scope="module")
def reference_report():
    task = get_task(TASK)
    return task.verify(materialise(task, "reference"), CTX)


def test_reference_scores_the_card_formula_from_its_replayed_trials(reference_report):
    r = reference_report
    s, d = r.native_metrics["s"], r.native_metrics["development_steps"]
    assert r.valid and s == 1.0 and 0 < d < 2000
    assert r.score == pytest.approx(s * (0.80 + 0.20 * (1 - d / 50_000)), abs=1e-12)
    assert [t["success"] for t in r.native_metrics["trials"]] == [True] * 5
    assert all(0 < t["success_at"] <= t["actions"] <= 1000 for t in r.native_metrics["trials"])
    assert not r.errors


def test_verification_is_deterministic(reference_report):
    task = get_task(TASK)
    again = task.verify(materialise(task, "reference"), CTX)
    assert again.to_dict() | {"elapsed_s": 0} == reference_report.to_dict() | {"elapsed_s": 0}


@pytest.mark.parametrize(
    "name,code",
    [("baseline/tampered", "ledger.altered"), ("baseline/idle", None)],
)
def test_baselines_score_zero_for_their_reason(name, code):
    task = get_task(TASK)
    r = task.verify(materialise(task, name), CTX)
    assert r.score == 0.0
    if code is None:
        assert r.valid and r.native_metrics["successes"] == 0 and len(r.native_metrics["trials"]) == 5
    else:
        assert not r.valid and r.errors[0].code == code


def test_budget_exhausted_develops_fifty_thousand_steps_and_scores_zero():
    task = get_task("01-open-fridge-l1")
    r = task.verify(materialise(task, "baseline/budget_exhausted"), CTX)
    assert r.score == 0.0 and r.valid
    assert r.native_metrics["development_steps"] == 50_000 and r.native_metrics["trials"] == []


def test_missing_linked_and_foreign_ledgers_score_zero(tmp_path):
    task = get_task(TASK)
    src = materialise(task, "reference") / "ledger.jsonl"
    empty = tmp_path / "empty"
    empty.mkdir()
    assert task.verify(empty, CTX).errors[0].code == "ledger.missing"
    linked = tmp_path / "linked"
    linked.mkdir()
    (linked / "ledger.jsonl").symlink_to(src)
    assert task.verify(linked, CTX).errors[0].code == "ledger.missing"
    other = get_task("01-turn-on-stove-l2")  # the same program's ledger submitted for another level
    r = other.verify(src.parent, CTX)
    assert r.score == 0.0 and r.errors[0].code == "ledger.forged_key"
    private = task.verify(src.parent, VerifyContext(secret=Secret(b"another secret entirely", public=False)))
    assert private.score == 0.0 and private.errors[0].code == "ledger.forged_key"


def test_a_session_served_with_another_budget_is_refused(tmp_path, monkeypatch):
    kitchen = next(k for k in KITCHEN_TASKS if k.task == "TurnOnStove")
    monkeypatch.setattr(make_ledgers, "STEP_BUDGET", 100)
    make_ledgers.record(kitchen, 3, make_ledgers.idle, tmp_path)
    (tmp_path / "ledger.jsonl").write_bytes(gzip.decompress((tmp_path / "ledger.jsonl.gz").read_bytes()))
    (tmp_path / "ledger.jsonl.gz").unlink()
    r = get_task(TASK).verify(tmp_path, CTX)
    assert r.score == 0.0 and r.errors[0].code == "ledger.wrong_limits"
    assert "development budget was 100 steps" in r.errors[0].message
    shutil.rmtree(tmp_path)


DEFAULT_REFERENCES = ("01-open-fridge-l3", "01-turn-on-stove-l2")
"""References replayed by default; every one with RLE_FULL_BATTERY=1 (reduced form of a physics test)."""
SHIPPED = [
    (t.id, n)
    for t in (get_task(k.task_id(lv)) for k in KITCHEN_TASKS for lv in (1, 2, 3))
    for n in t.solutions
    if n != "reference" or t.id in DEFAULT_REFERENCES or os.environ.get("RLE_FULL_BATTERY") == "1"
]


@pytest.mark.physics
@pytest.mark.parametrize("task_id,name", SHIPPED, ids=[f"{t}:{n}" for t, n in SHIPPED])
def test_every_shipped_solution_verifies_to_its_golden_score(task_id, name):
    from rle_tasks.core.solutions import declaration

    task = get_task(task_id)
    report = task.verify(materialise(task, name), CTX)
    assert report.score == pytest.approx(declaration(task).get(name).quick_score, abs=1e-12)
