"""03-hidden-com: shipped solutions verify to their golden scores; the programs replay live.

The committed public-key ledgers are verified through the solutions mechanism (the reference's
replay takes ~25 s). Playing the reference live on a fresh session (~30 s plus the replay) on the
public instance and a second secret runs with RLE_FULL_BATTERY=1; the random-answers program (three
actions) always runs live.
"""

import os

import pytest

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import declaration, materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.hidden_com import verifier as hv
from rle_tasks.f03_physical_reasoning.solutions.hidden_com import record
from rle_tasks.f03_physical_reasoning.solutions.hidden_com.random_answers import guesses

PUBLIC = Secret(PUBLIC_KEY, public=True)
FULL = os.environ.get("RLE_FULL_BATTERY") == "1"


@pytest.mark.physics
@pytest.mark.parametrize(
    "name", ["reference", "baseline/random_answers", "baseline/late_answers", "baseline/unsealed"]
)
def test_shipped_solution_scores_its_golden_score(name):
    task = get_task("03-hidden-com")
    report = task.verify(materialise(task, name), VerifyContext(secret=PUBLIC, quick=True))
    assert report.score == pytest.approx(declaration(task).get(name).quick_score, abs=1e-12)
    if name == "reference":
        assert report.valid and report.score == pytest.approx(1.0)
    elif name == "baseline/random_answers":  # seed 0 guesses against the public instance
        truth = hv.instance(PUBLIC).quadrants
        assert report.valid and report.score == pytest.approx(
            sum(g == q for g, q in zip(guesses(0), truth)) / 3
        )
    elif name == "baseline/late_answers":  # box 0 right; boxes 1 and 2 answered after 12,000 idle steps
        assert report.valid and report.score == pytest.approx(1 / 3)
        assert report.checkpoints[0].measured["late_answer_actions"] == 2
        assert "2 answer action(s) refused as late" in report.checkpoints[0].message
    else:
        assert not report.valid and report.score == 0.0 and report.errors[0].code == "ledger.unsealed"


@pytest.mark.parametrize("seed", [1])
def test_random_answers_score_their_lucky_guesses(tmp_path, seed):
    # no probing: the score is the number of guesses that happen to match, / 3 (1/4 expected)
    truth = hv.instance(PUBLIC).quadrants
    expected = sum(g == q for g, q in zip(guesses(seed), truth)) / 3
    report = hv.verify(
        record("random_answers", PUBLIC, tmp_path / "s", seed=seed), VerifyContext(secret=PUBLIC)
    )
    assert report.valid and report.score == pytest.approx(expected)
    assert report.native_metrics["actions"] == 3


@pytest.mark.physics
@pytest.mark.skipif(not FULL, reason="drives a full metered session; runs with RLE_FULL_BATTERY=1")
@pytest.mark.parametrize("secret", [PUBLIC, Secret(b"h2", False)])
def test_reference_names_every_quadrant_live(tmp_path, secret):
    report = hv.verify(
        record("reference", secret, tmp_path / "s", camera_every=100_000), VerifyContext(secret=secret)
    )
    assert report.valid and report.score == pytest.approx(1.0)
