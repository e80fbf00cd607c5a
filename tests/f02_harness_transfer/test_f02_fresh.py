"""Family 02's fresh agents as tasks of their own (``02-group-NN-fresh-K``) and the Harbor second stage."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from rle_design.errors import RleError
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.devenv import layout_workspace
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f02_harness_transfer.fresh import HARNESS_ENV, _unit, group_report
from rle_tasks.f02_harness_transfer.groups import GROUPS
from rle_tasks.f02_harness_transfer.harbor_trials import export_fresh
from rle_tasks.f02_harness_transfer.verifier import units

SECRET = Secret(b"fresh-agent-test-secret", public=False)
GROUP = GROUPS[0]


@pytest.fixture(scope="module")
def harness(tmp_path_factory):
    root = materialise(
        get_task(GROUP.task_id), "reference", dest=tmp_path_factory.mktemp("ref") / "reference"
    )
    return root / "agent_harness"


def test_fresh_ids_resolve_only_for_real_groups_and_trials():
    spec = get_task("02-group-01-fresh-4")
    assert spec.family == 2 and spec.contract.required == ("ledger.jsonl",)
    assert spec.budget.steps == 5000 and spec.budget.wall_time_s == 3600.0 and spec.budget.gpus == 0
    for bad in ("02-group-01-fresh-5", "02-group-16-fresh-0", "02-group-1-fresh-0"):
        with pytest.raises(RleError) as exc:
            get_task(bad)
        assert exc.value.code == "task.unknown"
    from rle_tasks.core.registry import all_tasks

    assert not any("fresh" in t.id for t in all_tasks())  # a stage of family 02, not one of the 51


def test_a_fresh_agent_meets_the_kitchen_the_group_verifier_gives_it():
    ctx = VerifyContext(secret=SECRET)
    for k, unit in enumerate(units(GROUP, Path("."), ctx)):
        fresh = _unit(GROUP, k, SECRET)
        assert (fresh.task, fresh.layout_seed, fresh.episode_seed) == (
            unit.task,
            unit.layout_seed,
            unit.episode_seed,
        )
    # bound to an attempt, each trial draws another kitchen
    assert (
        _unit(GROUP, 0, SECRET.for_attempt("harbor-1")).layout_seed
        != units(GROUP, Path("."), ctx)[0].layout_seed
    )


def _client(workspace: Path):
    spec = importlib.util.spec_from_file_location("fresh_client", workspace / "client.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_served_fresh_session_is_gated_and_replayed(harness, tmp_path, monkeypatch):
    monkeypatch.setenv(HARNESS_ENV, str(harness))
    spec = get_task("02-group-01-fresh-2")
    ws = layout_workspace(
        spec, tmp_path / "ws", secret=SECRET, attempt="trial-a", ledger_dir=tmp_path / "ledgers"
    )
    try:
        files = set(ws.files)
        assert {"agent_harness/MANUAL.md", "instruction.md", "client.py"} <= files
        assert all(f.startswith("agent_harness/") or f in ("instruction.md", "client.py") for f in files)
        assert (ws.workspace / "instruction.md").read_text().startswith("# One task, one kitchen\n\nTask: ")
        with _client(ws.workspace).connect() as env:
            env.reset()
            nu = env.info()["action_size"]
            for _ in range(3):
                env.step(np.zeros(nu))
            env.seal()
        ws.server.wait(30)
    finally:
        ws.close()
    art = tmp_path / "art"
    art.mkdir()
    (art / "ledger.jsonl").write_bytes(ws.ledger_path.read_bytes())
    report = spec.verify(art, VerifyContext(secret=SECRET, attempt="trial-a"))
    native = report.native_metrics
    assert report.valid, report.errors
    assert native["steps"] == 4 and native["attempt"] == {"id": "trial-a", "bound": True}
    assert native["n"] == len(native["stages"]) > native["b"] >= 0
    assert report.score == pytest.approx(max(0.0, (native["m"] - native["b"]) / (native["n"] - native["b"])))
    wrong = spec.verify(art, VerifyContext(secret=SECRET, attempt="trial-b"))
    assert wrong.score == 0.0 and wrong.errors[0].code == "ledger.wrong_attempt"
    public = spec.verify(art, VerifyContext(secret=Secret(PUBLIC_KEY, public=True), attempt="trial-a"))
    assert public.score == 0.0 and public.errors[0].code == "ledger.forged_key"
    (art / "ledger.jsonl").unlink()
    missing = spec.verify(art, VerifyContext(secret=SECRET))
    assert missing.score == 0.0 and missing.errors[0].code.startswith("ledger.")


def test_the_harness_must_be_named(tmp_path, monkeypatch):
    monkeypatch.delenv(HARNESS_ENV, raising=False)
    with pytest.raises(RleError) as exc:
        layout_workspace(get_task("02-group-01-fresh-0"), tmp_path / "ws", secret=SECRET, serve=False)
    assert exc.value.code == "f02.no_harness"


def test_the_group_reward_is_the_mean_of_its_fresh_trials():
    names = [f"02-group-01-fresh-{k}" for k in range(5)]
    report = group_report(GROUP, [1.0, 0.5, None, 0.0, 1.0], names)
    assert report.task_id == "02-group-01" and report.score == pytest.approx(2.5 / 5)
    assert [e.code for e in report.errors] == ["f02.trial_failed"] and not report.native_metrics["partial"]
    assert report.native_metrics["successes"] == 2
    three = group_report(GROUP, [1.0, 0.5, None], names[:3])  # partial: the mean of the three that ran
    assert three.score == pytest.approx(1.5 / 3) and three.native_metrics["partial"]


def test_export_of_the_fresh_trials_holds_the_harness_and_the_scripted_oracle(harness, tmp_path):
    (task,) = export_fresh(GROUP.task_id, harness, tmp_path / "tasks", trials=1)
    assert task.name == "02-group-01-fresh-0"
    for context in (task / "environment", task / "environment" / "dev", task / "tests"):
        copied = context / "data" / "agent_harness" / "MANUAL.md"
        assert copied.read_bytes() == (harness / "MANUAL.md").read_bytes()
        assert f"ENV {HARNESS_ENV}=/opt/rle-data/agent_harness" in (context / "Dockerfile").read_text()
    assert (task / "environment" / "docker-compose.yaml").is_file()
    assert '--sidecar "/rle-ledger"' in (task / "tests" / "test.sh").read_text()
    assert "fresh_agent.run()" in (task / "solution" / "solve.sh").read_text()
    assert (task / "solution" / "fresh_agent.py").is_file()
    assert "scripted fresh agent" in (task / "README.md").read_text()


def test_transfer_trials_refuses_without_secret_group_or_manual(tmp_path, monkeypatch, capsys):
    from rle_tasks.cli import main

    monkeypatch.delenv("RLE_SECRET", raising=False)
    assert main(["transfer-trials", "02-group-01", str(tmp_path), "--agent", "oracle"]) == 2
    assert "RLE_SECRET is not set" in capsys.readouterr().err
    monkeypatch.setenv("RLE_SECRET", "s")
    assert main(["transfer-trials", "02-group-16", str(tmp_path), "--agent", "oracle"]) == 2
    assert "unknown group" in capsys.readouterr().err
    assert main(["transfer-trials", "02-group-01", str(tmp_path), "--agent", "oracle"]) == 2
    assert "error [f02.no_manual]" in capsys.readouterr().err


def test_a_session_served_with_other_limits_fails_with_the_limit_named(harness, tmp_path, monkeypatch):
    """Signed with the right key, but served with 50,000 steps instead of the card's 5,000 per agent."""
    import dataclasses

    from rle_tasks.core.task import Budget

    monkeypatch.setenv(HARNESS_ENV, str(harness))
    spec = get_task("02-group-01-fresh-1")
    loose = dataclasses.replace(spec, budget=Budget(wall_time_s=3600.0, steps=50_000))
    ws = layout_workspace(loose, tmp_path / "ws", secret=SECRET, attempt="trial-c", ledger_dir=tmp_path / "l")
    try:
        with _client(ws.workspace).connect() as env:
            env.reset()
            env.seal()
        ws.server.wait(30)
    finally:
        ws.close()
    art = tmp_path / "art"
    art.mkdir()
    (art / "ledger.jsonl").write_bytes(ws.ledger_path.read_bytes())
    report = spec.verify(art, VerifyContext(secret=SECRET, attempt="trial-c"))
    assert report.score == 0.0 and report.errors[0].code == "ledger.wrong_limits"
    assert "5000" in report.errors[0].message.replace(",", "")
