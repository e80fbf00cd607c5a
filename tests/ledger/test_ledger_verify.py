"""Every tampering of a sealed ledger is rejected with its own code; a clean ledger verifies."""

from __future__ import annotations

import hmac
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from rle_design.ledger import LedgerError, LedgerWriter, MeteredEnv, MeteredSession, verify_ledger
from rle_design.ledger.records import mac_input

KEY = b"ledger-test-key-0123456789abcdef"
TASK = "08-mobile-base"
PENDULUM = """
<mujoco>
  <option timestep="0.002"/>
  <worldbody>
    <body name="link">
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.02" mass="0.5"/>
    </body>
  </worldbody>
  <actuator><motor name="tau" joint="hinge"/></actuator>
</mujoco>
"""


def _session_ledger(
    path: Path, *, key: bytes = KEY, task: str = TASK, steps: int = 20, seal: bool = True, group: int = 4
) -> None:
    """open, reset, 20 actions in groups of 4 (5 steps records), seal: 8 lines, 21 charged steps."""
    session = MeteredSession(
        MeteredEnv(PENDULUM, n_substeps=5),
        task_id=task,
        budget=None,
        key=key,
        ledger_path=path,
        actions_per_record=group,
    )
    session.reset()
    for i in range(steps):
        session.step(np.array([0.1 * np.sin(i)]))
    if seal:
        session.seal()
    else:
        session.writer.flush()


@pytest.fixture()
def ledger(tmp_path) -> Path:
    path = tmp_path / "ledger.jsonl"
    _session_ledger(path)
    return path


def _lines(path: Path) -> list[bytes]:
    return path.read_bytes().splitlines()


def _write(path: Path, lines: list[bytes]) -> None:
    path.write_bytes(b"".join(line + b"\n" for line in lines))


def test_clean_ledger_verifies(ledger):
    verdict = verify_ledger(ledger, KEY, task_id=TASK)
    assert verdict.valid and verdict.code == "ledger.valid"
    assert verdict.steps == 21  # one reset + 20 actions
    assert verdict.message == "ledger.jsonl: sealed, 21 steps"
    assert len(verdict.head) == 64
    assert verify_ledger(ledger, KEY).valid  # task taken from the open record


def test_records_have_the_chained_fields(ledger):
    recs = [json.loads(line) for line in _lines(ledger)]
    assert [r["kind"] for r in recs] == ["open", "reset"] + ["steps"] * 5 + ["seal"]
    assert list(recs[0]) == ["seq", "kind", "task_id", "prev", "digest", "payload", "mac"]
    assert recs[0]["prev"] == "0" * 64
    assert recs[-1]["payload"]["steps"] == 21 and recs[-1]["payload"]["records"] == len(recs) - 1
    assert [r["payload"]["steps"] for r in recs[1:-1]] == [1, 5, 9, 13, 17, 21]
    first = np.frombuffer(bytes.fromhex(recs[2]["payload"]["actions"][1]), dtype=np.float64)
    np.testing.assert_array_equal(first, [0.1 * np.sin(1)])  # the executed action, exactly
    assert KEY.hex() not in ledger.read_text() and KEY.decode() not in ledger.read_text()


def test_one_record_per_action_when_not_grouped(tmp_path):
    path = tmp_path / "single.jsonl"
    _session_ledger(path, group=1, steps=7)
    kinds = [json.loads(line)["kind"] for line in _lines(path)]
    assert kinds == ["open", "reset"] + ["steps"] * 7 + ["seal"]
    assert verify_ledger(path, KEY, TASK).steps == 8


def test_inconsistent_counts_are_caught_even_with_the_key(tmp_path):
    writer = LedgerWriter(tmp_path / "forged.jsonl", KEY, TASK)
    writer.append("reset", {"steps": 1, "time": 0.0})
    writer.append_steps(["00" * 8], 99, 0.01, 0.0)  # claims 99 steps after 2
    writer.seal(99)
    verdict = verify_ledger(tmp_path / "forged.jsonl", KEY, TASK)
    assert verdict.code == "ledger.altered"
    assert verdict.message == "forged.jsonl: line 3 counts 99 steps, the records before it 2"


def test_missing_file(tmp_path):
    verdict = verify_ledger(tmp_path / "absent.jsonl", KEY)
    assert (verdict.valid, verdict.code) == (False, "ledger.missing")
    assert verdict.message.startswith("ledger absent.jsonl cannot be read: No such file or directory")


def test_missing_seal(tmp_path):
    path = tmp_path / "open.jsonl"
    _session_ledger(path, seal=False)
    verdict = verify_ledger(path, KEY, TASK)
    assert verdict.code == "ledger.unsealed"
    assert verdict.message == "open.jsonl: no seal record (session not closed, or truncated)"


def test_truncation_mid_record(ledger):
    data = ledger.read_bytes()
    ledger.write_bytes(data[: len(data) // 2])
    assert verify_ledger(ledger, KEY, TASK).code == "ledger.truncated"


def test_truncation_keeping_the_seal(ledger):
    lines = _lines(ledger)
    _write(ledger, lines[:5] + lines[-1:])  # records 5.. removed, seal kept
    verdict = verify_ledger(ledger, KEY, TASK)
    assert verdict.code == "ledger.truncated"
    assert verdict.message == "ledger.jsonl: records missing before line 6 (seq 7, expected 5)"


def test_truncation_dropping_the_seal(ledger):
    _write(ledger, _lines(ledger)[:-2])
    assert verify_ledger(ledger, KEY, TASK).code == "ledger.unsealed"


def test_reordering(ledger):
    lines = _lines(ledger)
    lines[4], lines[5] = lines[5], lines[4]
    _write(ledger, lines)
    verdict = verify_ledger(ledger, KEY, TASK)
    assert verdict.code == "ledger.reordered"
    assert verdict.message == "ledger.jsonl: line 5 holds seq 5, expected 4"


def test_altered_field(ledger):
    lines = _lines(ledger)
    assert b'"steps":9' in lines[3]
    lines[3] = lines[3].replace(b'"steps":9', b'"steps":8')
    _write(ledger, lines)
    verdict = verify_ledger(ledger, KEY, TASK)
    assert verdict.code == "ledger.altered"
    assert verdict.message == "ledger.jsonl: line 4 (seq 3) fails its MAC"


def test_altered_seal_step_count(ledger):
    lines = _lines(ledger)
    lines[-1] = lines[-1].replace(b'"steps":21', b'"steps":5')
    _write(ledger, lines)
    assert verify_ledger(ledger, KEY, TASK).code == "ledger.altered"


def test_seal_appended_twice(ledger):
    lines = _lines(ledger)
    _write(ledger, lines + lines[-1:])
    verdict = verify_ledger(ledger, KEY, TASK)
    assert verdict.code == "ledger.replayed_seal"
    assert verdict.message == f"ledger.jsonl: seal appears 2 times (lines {len(lines)}, {len(lines) + 1})"


def test_seal_from_another_ledger(ledger, tmp_path):
    other = tmp_path / "other.jsonl"
    _session_ledger(other)  # same key, task and length: only the ledger id differs
    _write(ledger, _lines(ledger)[:-1] + _lines(other)[-1:])
    verdict = verify_ledger(ledger, KEY, TASK)
    assert verdict.code == "ledger.replayed_seal"
    assert verdict.message == "ledger.jsonl: the seal belongs to another ledger"


def test_record_spliced_from_another_ledger_breaks_the_chain(ledger, tmp_path):
    other = tmp_path / "other.jsonl"
    _session_ledger(other)
    lines = _lines(ledger)
    lines[6] = _lines(other)[6]
    _write(ledger, lines)
    verdict = verify_ledger(ledger, KEY, TASK)
    assert verdict.code == "ledger.broken_chain"
    assert verdict.message == "ledger.jsonl: line 7 does not chain to line 6"


def test_forged_key(tmp_path):
    path = tmp_path / "forged.jsonl"
    _session_ledger(path, key=b"agent-guessed-key-0123456789abcd")
    verdict = verify_ledger(path, KEY, TASK)
    assert verdict.code == "ledger.forged_key"
    assert verdict.message == "forged.jsonl: no record has a valid MAC under the verifier's key"


def test_ledger_of_another_task(tmp_path):
    path = tmp_path / "gello.jsonl"
    _session_ledger(path, task="09-gello")
    verdict = verify_ledger(path, KEY, TASK)
    assert verdict.code == "ledger.wrong_task"
    assert verdict.message == "gello.jsonl: line 1 belongs to task '09-gello', expected '08-mobile-base'"


def test_records_after_the_seal(ledger, tmp_path):
    lines = _lines(ledger)
    _write(ledger, lines + lines[5:7])
    verdict = verify_ledger(ledger, KEY, TASK)
    assert verdict.code == "ledger.after_seal"
    assert verdict.message == f"ledger.jsonl: 2 record(s) after the seal on line {len(lines)}"


def test_a_record_written_after_the_seal_with_the_key_is_still_rejected(ledger):
    # Even the key holder cannot extend a sealed ledger into a valid one.
    lines = _lines(ledger)
    rec = json.loads(lines[-1])
    body = json.dumps(
        {
            "seq": rec["seq"] + 1,
            "kind": "steps",
            "task_id": TASK,
            "prev": "0" * 64,
            "digest": "0" * 64,
            "payload": {},
        },
        separators=(",", ":"),
    ).encode()[:-1]
    mac = hmac.digest(KEY, mac_input(body + b',"mac":"' + b"0" * 64 + b'"}'), "sha256").hex()
    _write(ledger, lines + [body + b',"mac":"' + mac.encode() + b'"}'])
    assert verify_ledger(ledger, KEY, TASK).code == "ledger.after_seal"


def test_malformed_line_and_empty_file(ledger, tmp_path):
    lines = _lines(ledger)
    _write(ledger, lines[:3] + [b"not json"] + lines[3:])
    assert verify_ledger(ledger, KEY, TASK).code == "ledger.malformed"
    empty = tmp_path / "empty.jsonl"
    empty.write_bytes(b"")
    assert verify_ledger(empty, KEY, TASK).code == "ledger.empty"


def test_writer_refuses_existing_files_and_short_keys(ledger, tmp_path):
    copy = tmp_path / "copy.jsonl"
    shutil.copy(ledger, copy)
    with pytest.raises(LedgerError) as info:
        LedgerWriter(copy, KEY, TASK)
    assert info.value.code == "ledger.exists"
    with pytest.raises(LedgerError) as info:
        LedgerWriter(tmp_path / "new.jsonl", b"short", TASK)
    assert info.value.code == "ledger.weak_key"
