"""Shipped solutions verify to their golden scores, each failing one for its named reason.

Replaying a tower ledger takes about a minute on a 2-core machine: the reduced battery (``make test``)
verifies the tower reference, ``RLE_FULL_BATTERY=1`` adds the knocked-over baseline.
"""

from __future__ import annotations

import os

import pytest

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import declaration, materialise
from rle_tasks.core.task import VerifyContext

CTX = VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True)


def _verify(task_id: str, name: str):
    task = get_task(task_id)
    report = task.verify(materialise(task, name), CTX)
    golden = declaration(task).get(name).quick_score
    assert report.score == pytest.approx(golden, abs=1e-9)
    return report


def test_cantilever_reference_reaches_0_8() -> None:
    report = _verify("03-cantilever", "reference")
    assert report.valid and report.score >= 0.8
    assert report.checkpoints[0].measured["blocks_on_table"] == 4


def test_cantilever_past_its_tipping_point_loses_its_top() -> None:
    report = _verify("03-cantilever", "baseline/overreach")
    assert report.valid and report.score < 0.6
    assert report.checkpoints[0].measured["blocks_on_table"] < 4


@pytest.mark.parametrize("task_id", ["03-cantilever", "03-tower"])
def test_unsealed_reference_scores_zero(task_id: str) -> None:
    report = _verify(task_id, "baseline/unsealed")
    assert report.score == 0.0 and report.errors[0].code == "ledger.unsealed"


FULL = os.environ.get("RLE_FULL_BATTERY") == "1"
TOWER = ["reference", "baseline/knocked_over"] if FULL else ["reference"]


@pytest.mark.physics
@pytest.mark.parametrize("name", TOWER)
def test_tower_solutions(name: str) -> None:
    report = _verify("03-tower", name)
    assert report.valid
    if name == "reference":
        assert report.score >= 0.7
        assert report.checkpoints[0].measured["pieces_on_table"] == 12
    else:
        assert report.score < 0.3  # the sweep leaves the pieces lying: about 60 mm of H* = 348 mm
