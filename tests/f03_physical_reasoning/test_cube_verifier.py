"""03-pocket-cube verifier: the ledger gate, the replay, the end predicate, and the baselines' reasons.

The baselines are recorded here through real metered 14-D actions (``solutions/pocket_cube``) under the
public development key and verified; each must score 0 for its own reason.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from rle_design.ledger.testing import cut_seal
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.cube.group import QUATS
from rle_tasks.f03_physical_reasoning.cube.lattice import SOLVED
from rle_tasks.f03_physical_reasoning.cube.reading import CubePoses
from rle_tasks.f03_physical_reasoning.cube.scene import STAND_TOP_Z
from rle_tasks.f03_physical_reasoning.cube.verifier import final_check, verify
from rle_tasks.f03_physical_reasoning.solutions.pocket_cube import record

PUBLIC = Secret(PUBLIC_KEY, public=True)
CTX = VerifyContext(secret=PUBLIC, quick=True)
HALF = (0.032 - 0.0004) / 2


@pytest.fixture(scope="module")
def ledgers(tmp_path_factory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("cube-ledgers")
    return {name: record(name, PUBLIC, root / name) for name in ("idle", "dropped", "reset")}


def _copy(src: Path, tmp_path: Path) -> Path:
    shutil.copy(src / "ledger.jsonl", tmp_path / "ledger.jsonl")
    return tmp_path / "ledger.jsonl"


def _poses(centre_z: float, speed: float = 0.0, state=SOLVED) -> CubePoses:
    centre = np.array([0.0, 0.0, centre_z])
    return CubePoses(
        cubie_quats=QUATS[list(state.orient)],
        cubie_pos=centre + 0.016 * state.slots().astype(float),
        cubie_speed=np.full(8, speed),
        cubie_half=HALF,
    )


def test_final_check_accepts_a_solved_cube_held_above_the_stand():
    check = final_check(_poses(STAND_TOP_Z + 0.032 + 0.010))
    assert check.solved and check.reason == ""
    # lowest corner = centre - 16 mm - half a cubie = 10 mm + 0.2 mm gap above the stand top
    assert check.measured["lowest_corner_above_stand_top"] == pytest.approx(0.0102, abs=1e-6)


def test_final_check_names_every_failing_condition():
    resting = final_check(_poses(STAND_TOP_Z + 0.032 - 0.0002))
    assert not resting.solved and "on or beside its stand" in resting.reason
    assert "faces" not in resting.reason
    scrambled = SOLVED.apply_all(["R", "U"])
    moving = final_check(_poses(STAND_TOP_Z + 0.1, speed=0.05, state=scrambled))
    assert "faces are not uniform" in moving.reason and "moving at 0.050 m/s" in moving.reason
    assert "held" not in moving.reason


def test_task_is_registered_with_its_budget_and_rubric():
    task = get_task("03-pocket-cube")
    assert task.implemented and task.budget.steps == 50_000
    assert "| `solve` |" in task.instruction and "Cap `unclassified`" in task.instruction


@pytest.mark.physics
def test_idle_arms_leave_the_cube_scrambled_on_its_stand(ledgers):
    report = verify(ledgers["idle"], CTX)
    assert report.valid and report.score == 0.0
    message = report.checkpoints[0].message
    assert message.startswith("cube not solved") and "faces are not uniform" in message
    assert "rests on or beside its stand" in message
    assert report.native_metrics["turns"] == 0 and report.native_metrics["actions"] == 20
    assert verify(ledgers["idle"], CTX) == report  # deterministic


@pytest.mark.physics
def test_a_cube_knocked_off_its_stand_rests_on_the_table_and_scores_zero(ledgers):
    report = verify(ledgers["dropped"], CTX)
    assert report.valid and report.score == 0.0
    measured = report.checkpoints[0].measured
    assert "rests on the table" in report.checkpoints[0].message
    assert measured["lowest_corner_above_table"] < 0.001  # on the table top, 60 mm below the stand's
    assert measured["session_turns"] == measured["turns"]  # counters agree


@pytest.mark.physics
def test_a_reset_after_the_start_abandons_the_attempt(ledgers):
    report = verify(ledgers["reset"], CTX)
    assert report.valid and report.score == 0.0
    assert report.checkpoints[0].message == "attempt abandoned: 1 reset(s) after the start"


def _expect_invalid(root: Path, code: str, ctx: VerifyContext = CTX) -> None:
    report = verify(root, ctx)
    assert report.score == 0.0 and not report.valid
    assert [e.code for e in report.errors] == [code]


def test_missing_ledger_scores_zero(tmp_path):
    _expect_invalid(tmp_path, "ledger.missing")


@pytest.mark.physics
def test_unsealed_altered_or_foreign_ledgers_score_zero(ledgers, tmp_path):
    cut_seal(_copy(ledgers["idle"], tmp_path))
    _expect_invalid(tmp_path, "ledger.unsealed")

    path = _copy(ledgers["idle"], tmp_path)
    lines = path.read_text().splitlines()
    i = max(k for k, line in enumerate(lines) if json.loads(line)["kind"] == "steps")
    rec = json.loads(lines[i])
    rec["payload"]["actions"][-1] = "00" * 8 * 14
    lines[i] = json.dumps(rec, separators=(",", ":"))
    path.write_text("\n".join(lines) + "\n")
    _expect_invalid(tmp_path, "ledger.altered")

    _copy(ledgers["idle"], tmp_path)
    _expect_invalid(tmp_path, "ledger.forged_key", VerifyContext(secret=Secret(b"hidden", public=False)))


@pytest.mark.parametrize("content", [b"", b"not json\n", b"\x00" * 100])
def test_garbage_never_crashes(tmp_path, content):
    (tmp_path / "ledger.jsonl").write_bytes(content)
    report = verify(tmp_path, CTX)
    assert report.score == 0.0 and not report.valid and report.errors


@pytest.mark.physics
@pytest.mark.skipif(os.environ.get("RLE_FULL_BATTERY") != "1", reason="28 s; the reference covers it")
def test_one_quarter_turn_by_the_right_wrist_solves_a_depth_one_scramble_for_full_reward(
    tmp_path, monkeypatch
):
    """Positive path through real metered actions on a shallow test scramble (``U`` from solved): the right
    wrist turns the top layer back (``U'``, classified), pinches the cube and lifts it: reward
    opt/turns = 1/1."""
    import rle_tasks.f03_physical_reasoning.cube.verifier as cube_verifier
    from rle_tasks.f03_physical_reasoning.cube.scene import CubeInstance

    inst = CubeInstance.from_moves("U")
    root = record("top_turns", PUBLIC, tmp_path / "u", inst=inst, senses=(1.0,))
    monkeypatch.setattr(cube_verifier, "instance", lambda secret: inst)
    report = verify(root, CTX)
    measured = report.checkpoints[0].measured
    assert report.valid and report.score == 1.0, report.checkpoints[0].message
    assert measured["moves"] == ["U'"] and measured["session_turns"] == 1 and measured["optimal"] == 1
    assert measured["lowest_corner_above_stand_top"] > 0.005 and measured["misalignment_deg"] < 5.0
