"""03-balance-coins: the shipped agent programs verify to their expected scores (full battery only).

Each program drives the Panda through a metered session (~4-6k actions, about a minute) and the
verifier replays it (about as long), so these run with RLE_FULL_BATTERY=1; the default suite covers
the verifier with short sessions and synthetic final states (test_balance_task.py).
"""

import pytest

from rle_tasks.core.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning import balance_verifier as bv
from rle_tasks.f03_physical_reasoning.solutions.balance_coins import PROGRAMS, record


@pytest.mark.physics
@pytest.mark.parametrize(
    ("program", "secret"),
    [
        ("reference", Secret(PUBLIC_KEY, True)),
        ("reference", Secret(b"e", False)),
        ("five_weighings", Secret(PUBLIC_KEY, True)),
        ("wrong_cube", Secret(PUBLIC_KEY, True)),
    ],
)
def test_program_scores_as_expected(program, secret, tmp_path, full_battery):
    if not full_battery:
        pytest.skip("drives a full metered session; runs with RLE_FULL_BATTERY=1")
    report = bv.verify(record(program, secret, tmp_path / program), VerifyContext(secret=secret))
    assert report.valid
    assert report.score == pytest.approx(PROGRAMS[program])
    expected_w = 5 if program == "five_weighings" else 2
    assert report.native_metrics["weighings"] == expected_w
