"""03-pocket-cube: the shipped reference verifies to its golden score (baselines: test_cube_baselines.py).

The committed public-key ledgers (recorded by ``python -m rle_tasks.f03_physical_reasoning.solutions.
pocket_cube``) are verified through the solutions mechanism; the reference's replay takes ~35 s. The
reference on the second public scramble (committed ledger, the scramble injected because the public
secret's scramble is the first) and a live replay of the reference program run with RLE_FULL_BATTERY=1.
"""

import os
from pathlib import Path

import pytest

import rle_tasks.f03_physical_reasoning.cube.verifier as cube_verifier
from rle_tasks.core.registry import get_task
from rle_tasks.core.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import declaration, materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.cube.scene import PUBLIC_SCRAMBLES, CubeInstance
from rle_tasks.f03_physical_reasoning.solutions.pocket_cube import SECOND, record
from rle_tasks.f03_physical_reasoning.solutions.pocket_cube.reference import TURN_SENSE, plan

PUBLIC = Secret(PUBLIC_KEY, public=True)
CTX = VerifyContext(secret=PUBLIC, quick=True)
FULL = os.environ.get("RLE_FULL_BATTERY") == "1"
LEDGERS = Path(cube_verifier.__file__).parents[1] / "solutions" / "pocket_cube" / "ledgers"


def test_the_reference_plan_is_optimal_in_quarter_turns():
    for k, scramble in enumerate(PUBLIC_SCRAMBLES):
        optimal = CubeInstance.from_moves(scramble).optimal
        assert sum(m in TURN_SENSE for m in plan(scramble)) == optimal  # y and x pitches
        if k < 2:  # <U, R>: the y pitch alone (what ``solve`` executes)
            moves = plan(scramble, ("P",))
            assert sum(m in TURN_SENSE for m in moves) == optimal == 4 and set(moves) <= {"P", "U", "U'"}


@pytest.mark.physics
@pytest.mark.parametrize(
    "name",
    ["reference", "baseline/unsealed"],
)
def test_shipped_solution_scores_its_golden_score_for_its_reason(name):
    task = get_task("03-pocket-cube")
    report = task.verify(materialise(task, name), CTX)
    assert report.score == pytest.approx(declaration(task).get(name).quick_score, abs=1e-12)
    check = report.checkpoints[0]
    if name == "reference":  # R U R' U' solved by U R U' R' (world turns between pitches)
        assert (
            report.valid and report.score == 1.0 and check.message == "solved in 4 quarter turns, optimum 4"
        )
        assert check.measured["moves"] == ["U", "R", "U'", "R'"] and check.measured["rescues"] == 0
        assert check.measured["lowest_corner_above_stand_top"] > 0.005
    else:
        assert not report.valid and report.errors[0].code == "ledger.unsealed"


@pytest.mark.physics
@pytest.mark.skipif(not FULL, reason="45 s replay; RLE_FULL_BATTERY=1")
def test_reference_on_the_second_public_scramble_scores_one(monkeypatch):
    inst = CubeInstance.from_moves(PUBLIC_SCRAMBLES[1])
    monkeypatch.setattr(cube_verifier, "instance", lambda secret: inst)
    report = cube_verifier.verify(LEDGERS / SECOND, CTX)
    assert report.valid and report.score == 1.0
    assert report.checkpoints[0].measured["turns"] == inst.optimal == 4


@pytest.mark.physics
@pytest.mark.skipif(not FULL, reason="40 s session + 35 s replay; RLE_FULL_BATTERY=1")
def test_reference_program_replays_live(tmp_path):
    root = record("reference", PUBLIC, tmp_path / "ref", scramble=PUBLIC_SCRAMBLES[0])
    report = cube_verifier.verify(root, CTX)
    assert report.valid and report.score == 1.0
