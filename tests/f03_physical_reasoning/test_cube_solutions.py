"""03-pocket-cube: the shipped reference verifies to its golden score (baselines: test_cube_baselines.py).

The committed public-key ledgers (recorded by ``python -m rle_tasks.f03_physical_reasoning.solutions.
pocket_cube``) are verified through the solutions mechanism; the reference's replay takes ~20 s. The
reference on the second public scramble (committed ledger, the scramble injected because the public
secret's scramble is the first) and live sessions of the reference program on all six public scrambles
run with RLE_FULL_BATTERY=1.
"""

import os
from pathlib import Path

import numpy as np
import pytest

import rle_tasks.f03_physical_reasoning.cube.verifier as cube_verifier
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import declaration, materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.cube.distance import optimal_turns
from rle_tasks.f03_physical_reasoning.cube.scene import PUBLIC_SCRAMBLES, CubeInstance
from rle_tasks.f03_physical_reasoning.solutions.pocket_cube import SECOND, record
from rle_tasks.f03_physical_reasoning.solutions.pocket_cube.reference import PITCH, TURN_SENSE, plan

PUBLIC = Secret(PUBLIC_KEY, public=True)
CTX = VerifyContext(secret=PUBLIC, quick=True)
FULL = os.environ.get("RLE_FULL_BATTERY") == "1"
LEDGERS = Path(cube_verifier.__file__).parents[1] / "solutions" / "pocket_cube" / "ledgers"


def test_the_reference_plan_is_optimal_in_quarter_turns():
    """Top turns with the two whole-cube hand-offs (y pitch, yaw) reach every state in its optimal count."""
    rng = np.random.default_rng(0)
    states = [CubeInstance.from_moves(s).state for s in PUBLIC_SCRAMBLES]
    states += [CubeInstance.draw(rng).state for _ in range(4)]
    for state in states:
        moves = plan(state)
        assert set(moves) <= {"U", "U'", "Y", "Z"}
        assert sum(m in TURN_SENSE for m in moves) == optimal_turns(state)
        # replaying the plan in the world frame solves the cube
        for m in moves:
            state = state.rotated(PITCH[m]) if m in PITCH else state.apply(m)
        assert state.is_solved()


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
    if name == "reference":  # R U R' U' solved by U R U' R' (top turns between hand-offs)
        assert (
            report.valid and report.score == 1.0 and check.message == "solved in 4 quarter turns, optimum 4"
        )
        assert check.measured["moves"] == ["U", "R", "U'", "R'"] and check.measured["rescues"] == 0
        assert check.measured["lowest_corner_above_stand_top"] > 0.005
    else:
        assert not report.valid and report.errors[0].code == "ledger.unsealed"


@pytest.mark.physics
@pytest.mark.skipif(not FULL, reason="25 s replay; RLE_FULL_BATTERY=1")
def test_reference_on_the_second_public_scramble_scores_one(monkeypatch):
    inst = CubeInstance.from_moves(PUBLIC_SCRAMBLES[1])
    monkeypatch.setattr(cube_verifier, "instance", lambda secret: inst)
    report = cube_verifier.verify(LEDGERS / SECOND, CTX)
    assert report.valid and report.score == 1.0
    assert report.checkpoints[0].measured["turns"] == inst.optimal == 4


@pytest.mark.physics
@pytest.mark.skipif(not FULL, reason="40-65 s each (session and replay); RLE_FULL_BATTERY=1")
@pytest.mark.parametrize("k", range(len(PUBLIC_SCRAMBLES)))
def test_reference_program_solves_every_public_scramble_live(tmp_path, monkeypatch, k):
    """Public scrambles of depth 4-6, each solved in its optimal count through the metered client."""
    inst = CubeInstance.from_moves(PUBLIC_SCRAMBLES[k])
    root = record("reference", PUBLIC, tmp_path / "ref", inst=inst, scramble=PUBLIC_SCRAMBLES[k])
    monkeypatch.setattr(cube_verifier, "instance", lambda secret: inst)
    report = cube_verifier.verify(root, CTX)
    assert report.valid and report.score == 1.0
    assert report.checkpoints[0].measured["turns"] == inst.optimal
