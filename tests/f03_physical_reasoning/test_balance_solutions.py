"""03-balance-coins: shipped solutions verify to their golden scores; the agent programs replay live.

The committed public-key ledgers (``solutions/balance_coins/ledgers``) are verified through the
solutions mechanism: the reference (replay ~35 s) and the unsealed baseline always, five weighings
with RLE_FULL_BATTERY=1. Playing the programs live on fresh sessions (about a minute each, plus the
replay) also runs with RLE_FULL_BATTERY=1, on the public instance and on a second secret.
"""

import os

import pytest

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import declaration, materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.balance import verifier as bv
from rle_tasks.f03_physical_reasoning.solutions.balance_coins import PROGRAMS, record

PUBLIC = Secret(PUBLIC_KEY, public=True)
FULL = os.environ.get("RLE_FULL_BATTERY") == "1"
SHIPPED = ["reference", "baseline/unsealed"] + (["baseline/five_weighings"] if FULL else [])
EXPECTED = {
    "reference": (1.0, 2, None),
    "baseline/five_weighings": (0.4, 5, None),
    "baseline/unsealed": (0.0, None, "ledger.unsealed"),
}


@pytest.mark.physics
@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_solution_scores_its_golden_score(name):
    task = get_task("03-balance-coins")
    report = task.verify(materialise(task, name), VerifyContext(secret=PUBLIC, quick=True))
    score, weighings, code = EXPECTED[name]
    assert report.score == pytest.approx(declaration(task).get(name).quick_score, abs=1e-12)
    assert report.score == pytest.approx(score)
    if code is None:
        assert report.valid and report.native_metrics["weighings"] == weighings
    else:
        assert not report.valid and report.errors[0].code == code


LIVE = [
    ("reference", PUBLIC),
    ("reference", Secret(b"e", False)),
    ("five_weighings", PUBLIC),
    ("wrong_cube", PUBLIC),
]


@pytest.mark.physics
@pytest.mark.skipif(not FULL, reason="drives full metered sessions; runs with RLE_FULL_BATTERY=1")
@pytest.mark.parametrize(("program", "secret"), LIVE)
def test_program_scores_as_expected_live(program, secret, tmp_path):
    report = bv.verify(record(program, secret, tmp_path / program), VerifyContext(secret=secret))
    assert report.valid
    assert report.score == pytest.approx(PROGRAMS[program])
    assert report.native_metrics["weighings"] == (5 if program == "five_weighings" else 2)
