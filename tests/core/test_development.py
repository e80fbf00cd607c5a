"""Development progress (family 05's figure) from the ledgers Harbor keeps of a trial's sidecar sessions.

Hand-built trial: session 1 opens at epoch 1000 s, session 2 at 1100 s (kept twice: its session file and
``ledger.jsonl``, one nonce). Episodes (wall since the session opened, candidate, success):

    s1: 10 A fail, 20 A success, 30 B success      s2: 5 A fail
    times since the first open: 10, 20, 30, 105
    best so far: A 0/1 = 0; A 1/2 = 0.5; B 1/1 = 1.0; A 1/3 (B still 1.0) = 1.0
"""

from __future__ import annotations

import base64
import json

import pytest

from rle_tasks.core.development import Episode, best_so_far, development_episodes, progress
from rle_tasks.core.export.harbor.results import read_job, systems
from rle_tasks.core.results import index_command


def _ledger(path, nonce, created, episodes, garbage=False):
    lines = [{"seq": 0, "kind": "open", "payload": {"nonce": nonce, "created": created, "unit": "episodes"}}]
    for i, (wall, sha, ok) in enumerate(episodes):
        payload = {
            "op": "episode",
            "submission_sha256": sha,
            "success": ok,
            "wall": wall,
            "cost": 1,
            "steps": i + 1,
        }
        lines.append({"seq": i + 1, "kind": "request", "payload": payload})
    lines.append({"seq": len(lines), "kind": "seal", "payload": {"elapsed_s": 60.0}})
    text = "\n".join(json.dumps(r) for r in lines) + "\n"
    if garbage:
        text += 'not json\n{"kind": "request", "payload": {"success": true}}\n[1, 2]\n'
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def _trial(job, name, task, reward, sessions=True):
    data = {
        "task_name": f"rle-bench/{task}",
        "trial_name": name,
        "agent_info": {"name": "agent", "model_info": {"name": "m"}},
        "agent_result": {},
        "verifier_result": {"rewards": {"reward": reward}},
        "started_at": "2026-11-28T08:00:00+00:00",
        "finished_at": "2026-11-28T09:00:00+00:00",
    }
    (job / name).mkdir(parents=True)
    (job / name / "result.json").write_text(json.dumps(data))
    if sessions:
        led = job / name / "artifacts" / "rle-ledger"
        _ledger(
            led / "a-session-001.jsonl", "n1", 1000.0, [(10, "A", False), (20, "A", True), (30, "B", True)]
        )
        _ledger(led / "a-session-002.jsonl", "n2", 1100.0, [(5, "A", False)], garbage=True)
        _ledger(led / "ledger.jsonl", "n2", 1100.0, [(5, "A", False)])


def test_episodes_and_best_success_so_far_by_hand(tmp_path):
    _trial(tmp_path, "t1", "05-robotwin-open", 0.5)
    episodes = development_episodes(tmp_path / "t1")
    assert episodes == (
        Episode(10.0, "A", False),
        Episode(20.0, "A", True),
        Episode(30.0, "B", True),
        Episode(105.0, "A", False),
    )
    assert best_so_far(episodes) == [(10.0, 0.0), (20.0, 0.5), (30.0, 1.0), (105.0, 1.0)]
    p = progress("t1", episodes, 0.5)
    assert p.episodes == 4 and p.official == 0.5
    assert progress("t2", (), 0.5) is None
    assert development_episodes(tmp_path / "no-such-trial") == ()


def test_the_family_section_shows_the_development_figure_only_where_sessions_ran_episodes(tmp_path, capsys):
    job = tmp_path / "job"
    _trial(job, "t1", "05-robotwin-open", 0.5)
    _trial(job, "t2", "09-gello", 0.8, sessions=False)
    ((result, _),) = systems(read_job(job)).values()
    assert set(result.development) == {"05-robotwin-open"}
    (p,) = result.development["05-robotwin-open"]
    assert p.curve == ((10.0, 0.0), (20.0, 0.5), (30.0, 1.0), (105.0, 1.0)) and p.official == pytest.approx(
        0.5
    )
    page = tmp_path / "index.html"
    assert index_command([str(job)], html=page) == 0
    html = page.read_text()
    png = html.split("<img alt='F05 development progress' src='data:image/png;base64,", 1)[1].split("'", 1)[0]
    assert base64.b64decode(png)[:8] == b"\x89PNG\r\n\x1a\n"
    assert "F09 development progress" not in html
