"""The family's ledger gate: missing, unsealed, truncated, altered or foreign ledgers score 0 with the reason."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from rle_design.ledger.testing import cut_seal
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.cantilever.verifier import verify
from rle_tasks.f03_physical_reasoning.scene import make_env

REFERENCE = Path(__file__).parents[2] / "rle_tasks/f03_physical_reasoning/solutions/reference/cantilever"
CTX = VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True)


def _copy(tmp_path: Path) -> Path:
    shutil.copy(REFERENCE / "ledger.jsonl", tmp_path / "ledger.jsonl")
    return tmp_path / "ledger.jsonl"


def _expect_zero(root: Path, code: str, ctx: VerifyContext = CTX) -> None:
    report = verify(root, ctx)
    assert report.score == 0.0 and not report.valid
    assert [e.code for e in report.errors] == [code]
    assert report.checkpoints[0].message.startswith("no score: ")


def test_missing_ledger(tmp_path: Path) -> None:
    _expect_zero(tmp_path, "ledger.missing")


def test_seal_cut_off(tmp_path: Path) -> None:
    cut_seal(_copy(tmp_path))
    _expect_zero(tmp_path, "ledger.unsealed")


def test_a_record_removed(tmp_path: Path) -> None:
    path = _copy(tmp_path)
    lines = path.read_bytes().splitlines(keepends=True)
    path.write_bytes(b"".join(lines[:3] + lines[4:]))
    report = verify(tmp_path, CTX)
    assert report.score == 0.0 and report.errors[0].code in ("ledger.truncated", "ledger.broken_chain")


def test_final_state_edited(tmp_path: Path) -> None:
    # the final scene is what the recorded actions produce: editing the last executed action is
    # editing the final state, and the record's MAC no longer matches
    path = _copy(tmp_path)
    lines = path.read_text().splitlines()
    i = max(k for k, line in enumerate(lines) if json.loads(line)["kind"] == "steps")
    rec = json.loads(lines[i])
    rec["payload"]["actions"][-1] = "00" * 8 * 12
    lines[i] = json.dumps(rec, separators=(",", ":"))
    path.write_text("\n".join(lines) + "\n")
    _expect_zero(tmp_path, "ledger.altered")


def test_ledger_of_another_secret_is_refused(tmp_path: Path) -> None:
    _copy(tmp_path)
    _expect_zero(
        tmp_path,
        "ledger.forged_key",
        VerifyContext(secret=Secret(b"hidden evaluation key", public=False), quick=True),
    )


def test_ledger_of_another_task_is_refused(tmp_path: Path) -> None:
    from rle_tasks.f03_physical_reasoning.tower.verifier import verify as verify_tower

    _copy(tmp_path)
    report = verify_tower(tmp_path, CTX)
    assert report.score == 0.0 and report.errors[0].code == "ledger.forged_key"


@pytest.mark.parametrize("content", [b"", b"not json\n", b"\x00" * 100])
def test_garbage_never_crashes(tmp_path: Path, content: bytes) -> None:
    (tmp_path / "ledger.jsonl").write_bytes(content)
    report = verify(tmp_path, CTX)
    assert report.score == 0.0 and report.errors


def test_a_session_is_bound_to_its_attempt(tmp_path):
    """The reference program in attempt "trial-A": its instance is the attempt's own (another block
    length than the unbound one), it verifies as trial-A and is refused as trial-B."""
    from rle_tasks.core.runtime.devenv import record_solution
    from rle_tasks.f03_physical_reasoning.cantilever import verifier as cantilever
    from rle_tasks.f03_physical_reasoning.scene import CONFIG
    from rle_tasks.f03_physical_reasoning.solutions import agents
    from rle_tasks.f03_physical_reasoning.task import BUDGET

    public = Secret(PUBLIC_KEY, public=True)
    bound = public.for_attempt("trial-A")
    inst = cantilever.instance(bound)
    assert inst.length != cantilever.instance(public).length
    assert cantilever.instance(public.for_attempt("trial-B")).length != inst.length

    def solve(client):
        agents.harmonic_cantilever(client.step, client.reset(), CONFIG.edge_x, CONFIG.top_z, scale=0.93)

    env = make_env(inst.pieces, privileged=True, images=False)
    sub = tmp_path / "s"
    record_solution(
        env, solve, sub / "ledger.jsonl", bound, "03-cantilever", BUDGET.steps, BUDGET.wall_time_s
    )
    task = get_task("03-cantilever")
    ok = task.verify(sub, VerifyContext(secret=public, attempt="trial-A"))
    assert ok.valid and ok.score > 0.75, ok.checkpoints[0].message
    assert ok.native_metrics["attempt"] == {"id": "trial-A", "bound": True}
    assert ok.native_metrics["block_length_m"] == inst.length
    other = task.verify(sub, VerifyContext(secret=public, attempt="trial-B"))
    assert other.score == 0.0 and other.errors[0].code == "ledger.wrong_attempt"
    unbound = task.verify(sub, VerifyContext(secret=public))
    assert unbound.score == ok.score and unbound.native_metrics["attempt"] == {
        "id": "trial-A",
        "bound": False,
    }
