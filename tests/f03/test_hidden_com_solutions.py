"""03-hidden-com: shipped programs verify to their expected scores.

The reference probes each box with the arm (~6,200 actions, ~30 s, replay ~25 s): it runs with
RLE_FULL_BATTERY=1. The random-answers baseline (three actions) runs always.
"""

import pytest

from rle_tasks.core.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning import hidden_com_verifier as hv
from rle_tasks.f03_physical_reasoning.solutions.hidden_com import record
from rle_tasks.f03_physical_reasoning.solutions.hidden_com.random_answers import guesses

PUBLIC = Secret(PUBLIC_KEY, public=True)


@pytest.mark.parametrize("seed", [0, 1, 2])
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
@pytest.mark.parametrize("secret", [PUBLIC, Secret(b"h2", False)])
def test_reference_names_every_quadrant(tmp_path, secret, full_battery):
    if not full_battery:
        pytest.skip("drives a full metered session; runs with RLE_FULL_BATTERY=1")
    report = hv.verify(
        record("reference", secret, tmp_path / "s", camera_every=100_000), VerifyContext(secret=secret)
    )
    assert report.valid and report.score == pytest.approx(1.0)
