"""Shipped solutions: the reference passes, baselines fail for their named reason (quick mode)."""

from pathlib import Path

import pytest

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import load_secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f06_pose_estimation.scoring import RUBRICS

README = Path(__file__).resolve().parents[2] / "rle_tasks" / "f06_pose_estimation" / "README.md"


def _verify(task_id, name):
    task = get_task(task_id)
    return task.verify(materialise(task, name), VerifyContext(secret=load_secret(None), quick=True))


def test_readme_holds_the_generated_table():
    assert RUBRICS["06-pose-a-rgb"].markdown_table() in README.read_text()


@pytest.mark.render
@pytest.mark.physics
def test_reference_b_scores_at_least_0_6():
    rep = _verify("06-pose-b-rgbd", "reference")
    assert rep.valid
    assert rep.score >= 0.6, rep.native_metrics
    assert rep.native_metrics["partial"] is True
    assert rep.native_metrics["shape_accuracy"] > 0.9


@pytest.mark.render
@pytest.mark.physics
def test_learned_reference_scores_at_least_0_6():
    rep = _verify("06-pose-c-learned", "reference")
    assert rep.valid
    assert rep.score >= 0.6, rep.native_metrics
    assert rep.native_metrics["speed_deduction"] == 0.0


@pytest.mark.render
@pytest.mark.physics
def test_wrong_shape_ids_score_zero_for_that_reason(full_battery):
    if not full_battery:
        pytest.skip("a second quick verification (about 25 s) runs with RLE_FULL_BATTERY=1")
    rep = _verify("06-pose-b-rgbd", "baseline/wrong_shape")
    assert rep.score == 0.0 and rep.valid
    assert rep.native_metrics["shape_accuracy"] == 0.0
    assert "shape accuracy 0.00 (3 of 3 with a wrong or missing shape id score 0)" in (
        rep.checkpoints[0].message
    )


@pytest.mark.render
def test_nan_output_fails_the_gate():
    rep = _verify("06-pose-b-rgbd", "baseline/nan_output")
    assert rep.score == 0.0 and rep.cap == 0.0
    assert rep.errors[0].code == "sandbox.non_finite"


@pytest.mark.render
def test_oversized_model_is_refused_before_inference():
    rep = _verify("06-pose-c-learned", "baseline/big_model")
    assert rep.score == 0.0
    assert rep.errors[0].code == "sandbox.import_error"
    assert "25000000 tensor elements" in rep.errors[0].message
