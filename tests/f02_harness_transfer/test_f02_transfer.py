"""The transfer evaluation: baselines fail for their reasons, fresh agents are isolated from each other
and from the submission, and the development workspace serves the group's tasks."""

from pathlib import Path

import numpy as np
import pytest

from rle_design.ledger import LedgerClient
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.devenv import layout_workspace
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f02_harness_transfer.groups import GROUPS
from rle_tasks.f02_harness_transfer.transfer import TransferUnit, run_unit, targets

PUBLIC = Secret(PUBLIC_KEY, public=True)
QUICK = VerifyContext(secret=PUBLIC, quick=True)


@pytest.mark.parametrize(
    "name,agent,reason",
    [
        ("baseline/empty", "no_entry_point", "names no 'Entry point"),
        ("baseline/missing_function", "missing_function", "agent_harness.skills cannot be imported"),
        ("baseline/reads_hidden_state", "sandbox.forbidden", "«PermissionError: rle-sandbox: "),  # an excerpt
    ],
)
def test_baselines_score_zero_for_their_reason(name, agent, reason):
    task = get_task("02-group-01")
    report = task.verify(materialise(task, name), QUICK)
    assert report.score == 0.0 and report.valid
    trials = report.native_metrics["trials"]
    assert len(trials) == 2 and report.native_metrics["partial"] is True
    assert all(t["agent"] == agent and reason in t["message"] for t in trials)
    assert any(e.code == f"f02.{agent}" for e in report.errors)


def test_missing_manual_is_refused(tmp_path):
    (tmp_path / "agent_harness").mkdir()
    report = get_task("02-group-01").verify(tmp_path, QUICK)
    assert report.score == 0.0 and not report.valid and report.errors[0].code == "f02.no_manual"


MARKER_HARNESS = """
from pathlib import Path


def solve(client, instruction):
    client.reset()
    here = Path(__file__).resolve().parent
    seen = (here / "marker.txt").exists() or (here.parent / "marker.txt").exists()
    (here / "marker.txt").write_text("written by a fresh agent")
    (here.parent / "marker.txt").write_text("written by a fresh agent")
    return "saw a marker" if seen else "no marker"
"""


def test_fresh_agents_are_isolated_from_each_other_and_the_submission(tmp_path):
    harness = tmp_path / "agent_harness"
    harness.mkdir()
    (harness / "MANUAL.md").write_text("Entry point: `agent_harness.marker:solve`\n")
    (harness / "marker.py").write_text(MARKER_HARNESS)
    group = GROUPS[0]
    layout, episode = targets(PUBLIC, group)[0]
    results = [
        run_unit(
            TransferUnit(k, group.held_out, layout, episode, harness, b"k" * 32, f"iso/agent-{k}", steps=50)
        )
        for k in range(2)
    ]
    assert [r.agent for r in results] == ["ran", "ran"]
    assert all("returned no marker" in r.message for r in results), [r.message for r in results]
    assert not (harness / "marker.txt").exists() and not (tmp_path / "marker.txt").exists()
    assert all(r.status == "scored" and r.steps == 1 and r.b == r.m == 0 and r.score == 0.0 for r in results)


@pytest.mark.physics
def test_development_workspace_serves_the_three_tasks_without_poses(tmp_path):
    task = get_task("02-group-09")
    ws = layout_workspace(task, tmp_path / "ws", secret=PUBLIC, ledger_dir=tmp_path / "ledgers")
    try:
        assert {"instruction.md", "client.py", "harness/robot.py"} <= set(ws.files)
        assert "FruitFromDrawer" in (tmp_path / "ws" / "instruction.md").read_text()
        with LedgerClient(ws.server.socket_path) as c:
            obs = c.reset(task="CloseDrawer", kitchen=2)
            assert obs["instruction"] == "Close the open drawer."
            assert {"cameras", "rgb", "depth"} <= set(obs) and {"objects", "fixtures", "target"}.isdisjoint(
                obs
            )
            seg = c.query("segment", prompt="drawer", camera="robot/agentview_left")
            assert seg["masks"].dtype == bool and len(seg["scores"]) == len(seg["masks"])
            hold = np.zeros(12)
            hold[6] = hold[11] = -1.0
            c.step(hold)
            assert c.info()["budget"] == 75_000 and c.info()["development_steps"] == 2
            c.seal()
        ws.server.wait(30)
    finally:
        ws.close()
    assert Path(ws.ledger_path).is_file()
