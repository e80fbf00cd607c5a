"""Served development sessions that can be audited: every request a ledger record, the budget per
attempt over every server process of it, `rle ledger show`, and servers that seal when stopped."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from rle_design.ledger import verify_ledger
from rle_design.ledger.show import describe_ledger
from rle_tasks.core.report import artifact_sha256
from rle_tasks.core.runtime.devenv import ledger_key
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.f06_pose_estimation import devserver
from rle_tasks.f06_pose_estimation.service import EVALUATIONS, open_session

TASK = "06-pose-b-rgbd"
PUBLIC = Secret(PUBLIC_KEY, public=True)
KEY = ledger_key(PUBLIC, TASK)


@pytest.fixture
def fake_renders(monkeypatch):
    """Design evaluations and labelled frames without rendering (what is recorded is the point here)."""
    scores = iter([0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.99])
    monkeypatch.setattr(
        devserver, "design_evaluation", lambda task, root: {"score": next(scores), "fps": 10.0}
    )
    monkeypatch.setattr(
        devserver, "labelled_frames", lambda seed, n, raised, depth: [({"t": 0.0}, np.zeros(3))] * n
    )


def _session(tmp_path: Path, attempt: str, n: int):
    ws = tmp_path / "ws"
    ws.mkdir(exist_ok=True)
    (ws / "estimator.py").write_text(f"# version {attempt} {n}\n")
    path = tmp_path / "ledgers" / f"{attempt}-session-{n:03d}.jsonl"
    path.parent.mkdir(exist_ok=True)
    return open_session(key=KEY, ledger_path=path, task_id=TASK, workspace=str(ws), attempt=attempt), path


def test_every_request_is_recorded_and_the_budget_belongs_to_the_attempt(tmp_path, fake_renders, capsys):
    s1, l1 = _session(tmp_path, "A", 1)
    s1.handle({"op": "frames"}, {"seed": 3, "n": 2})
    for _ in range(4):
        report = s1.handle({"op": "evaluate"}, None)[1]
    assert report["evaluations_left"] == EVALUATIONS - 4
    sha1 = report["submission_sha256"]
    assert sha1 == artifact_sha256(tmp_path / "ws")
    s1.seal()
    # a second server process of the same attempt: the budget goes on where the first left it
    s2, l2 = _session(tmp_path, "A", 2)
    assert s2.handle({"op": "info"}, None)[1]["evaluations_left"] == 2
    s2.handle({"op": "evaluate"}, None)
    s2.handle({"op": "evaluate"}, None)
    with pytest.raises(Exception) as exc:  # the seventh evaluation of attempt A
        s2.handle({"op": "evaluate"}, None)
    assert exc.value.code == "ledger.budget_exhausted" and "4 by earlier sessions" in exc.value.message
    s2.seal()
    # another attempt starts with the card's six
    s3, _ = _session(tmp_path, "B", 1)
    assert s3.handle({"op": "info"}, None)[1]["evaluations_left"] == EVALUATIONS
    s3.seal()

    v1, v2 = verify_ledger(l1, KEY, TASK), verify_ledger(l2, KEY, TASK)
    assert v1.valid and v1.steps == 4 and v2.valid and v2.steps == 2
    assert v2.opened["previous"] == {"sessions": [l1.name], "used": 4} and v2.opened["attempt"] == "A"
    text = describe_ledger(l1, v1)
    assert "ledger.valid" in text and text.count(" evaluate ") == 4 and " frames " in text
    assert "score=0.5" in text and f"submission_sha256={sha1[:12]}" in text
    from rle_tasks.cli import main

    assert main(["ledger", "show", str(l2)]) == 0  # no secret given: the public key
    out = capsys.readouterr().out
    assert "ledger.valid" in out and "score=0.9" in out and "earlier sessions of the attempt used 4" in out


def test_an_unsealed_ledger_of_a_killed_server_still_counts(tmp_path, fake_renders):
    s1, l1 = _session(tmp_path, "K", 1)
    s1.handle({"op": "evaluate"}, None)
    s1.handle({"op": "evaluate"}, None)  # never sealed: the process died
    s2, _ = _session(tmp_path, "K", 2)
    assert s2.handle({"op": "info"}, None)[1]["evaluations_used"] == 2
    s2.seal()


def _wait_for(path: Path, timeout: float = 90.0) -> None:
    deadline = time.monotonic() + timeout
    while not path.exists():
        assert time.monotonic() < deadline, f"{path} did not appear"
        time.sleep(0.1)


@pytest.mark.parametrize(
    ("task", "sig"),
    [(TASK, signal.SIGTERM), (TASK, signal.SIGINT), ("03-cantilever", signal.SIGTERM)],
)
def test_a_background_rle_dev_seals_and_removes_its_socket_when_stopped(tmp_path, task, sig):
    ws = tmp_path / "ws"
    proc = subprocess.Popen(
        [sys.executable, "-m", "rle_tasks.cli", "dev", task, "--workspace", str(ws), "--attempt", "bg-1"],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        start_new_session=True,  # as `rle dev &` from a script: SIGINT is not the terminal's
        env={**os.environ, "RLE_SECRET": ""},
    )
    try:
        sock = ws / ".rle" / "ledger.sock"
        _wait_for(sock)
        time.sleep(0.5)
        proc.send_signal(sig)
        out, _ = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    ledgers = list((tmp_path / "ws.ledger").glob("bg-1*.jsonl"))
    assert len(ledgers) == 1, out
    verdict = verify_ledger(ledgers[0], ledger_key(PUBLIC, task), task)
    assert verdict.valid, (verdict, out)
    assert not sock.exists()
    assert b"ledger sealed" in out
