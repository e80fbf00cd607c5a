"""``rle dev``: workspace layout, the metered server, and no hidden data in the workspace."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

from rle_design.errors import RleError
from rle_design.ledger import MeteredEnv, verify_ledger
from rle_tasks.core.runtime.devenv import default_attempt, layout_workspace, ledger_key
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret, current_secret, derive_seed
from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec

SECRET = Secret(b"private-verifier-secret-for-devenv-tests", public=False)
TASK = "09-gello"
ARM = """
<mujoco>
  <option timestep="0.002"/>
  <worldbody>
    <body name="link">
      <joint name="shoulder" type="hinge" axis="0 1 0" damping="0.1"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="0.4"/>
    </body>
  </worldbody>
  <actuator><motor name="tau" joint="shoulder"/></actuator>
</mujoco>
"""


def _dev_env(workspace: Path) -> MeteredEnv:
    (workspace / "scene.xml").write_text(ARM)
    return MeteredEnv(ARM, n_substeps=10)


def _spec(make_dev_env=_dev_env, verify=lambda d, c: None, steps: int | None = 50) -> TaskSpec:
    return TaskSpec(
        TASK,
        9,
        "test task",
        instruction="# Do the thing\nBuild a device.",
        budget=Budget(wall_time_s=3600.0, steps=steps),
        contract=ArtifactContract(required=("device.xml",)),
        make_dev_env=make_dev_env,
        verify=verify,
    )


def _client_module(workspace: Path):
    spec = importlib.util.spec_from_file_location("agent_client", workspace / "client.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_unimplemented_task_is_refused(tmp_path):
    with pytest.raises(RleError) as info:
        layout_workspace(TaskSpec("01-open-fridge-l1", 1, "placeholder"), tmp_path / "ws")
    assert info.value.code == "task.not_implemented"
    assert str(info.value) == (
        "task '01-open-fridge-l1' is registered but not implemented yet: it has no development environment. "
        "See `rle tasks` for the implemented ones"
    )
    assert not (tmp_path / "ws").exists()


def test_cli_dev_exits_2_for_an_unimplemented_task(tmp_path, monkeypatch, capsys):
    import rle_tasks.core.registry as registry
    from rle_tasks.cli import main

    monkeypatch.setattr(registry, "get_task", lambda task_id: TaskSpec(task_id, 1, "placeholder"))
    assert main(["dev", "04-run", "--workspace", str(tmp_path / "ws")]) == 2
    assert "error [task.not_implemented]: task '04-run' is registered" in capsys.readouterr().err


def test_metered_workspace_serves_a_verifiable_session_without_hidden_data(tmp_path):
    ws = layout_workspace(_spec(), tmp_path / "ws", secret=SECRET)
    try:
        assert ws.files == ("client.py", "instruction.md", "scene.xml")
        assert (ws.workspace / "instruction.md").read_text() == "# Do the thing\nBuild a device.\n"
        attempt = default_attempt(tmp_path / "ws")
        assert ws.attempt == attempt and attempt.startswith("ws-")
        assert ws.ledger_path == tmp_path / "ws.ledger" / f"{attempt}.jsonl"  # outside the workspace
        with _client_module(ws.workspace).connect() as env:
            obs = env.reset()
            assert set(obs) == {"qpos", "qvel", "time"}
            for _ in range(9):
                obs = env.step(np.array([0.05]))
            assert obs["time"] == pytest.approx(9 * 10 * 0.002)
            assert env.info()["budget"] == 50
            env.seal()
        ws.server.wait(10)
    finally:
        ws.close()
    verdict = verify_ledger(ws.ledger_path, ledger_key(SECRET, TASK), task_id=TASK)
    assert verdict.valid and verdict.steps == 10
    public = ledger_key(Secret(PUBLIC_KEY, public=True), TASK)
    assert verify_ledger(ws.ledger_path, public, TASK).code == "ledger.forged_key"

    hidden = [SECRET.key, ledger_key(SECRET, TASK), ledger_key(SECRET, TASK).hex().encode()]
    hidden += [str(derive_seed(SECRET, TASK, i)).encode() for i in range(16)]
    for path in ws.workspace.rglob("*"):
        if path.is_file():
            content = path.read_bytes()
            for item in hidden:
                assert item not in content, f"hidden data found in {path.name}"


def test_layout_only_writes_the_client_but_starts_nothing(tmp_path):
    ws = layout_workspace(_spec(), tmp_path / "ws", serve=False, secret=SECRET)
    assert ws.server is None and ws.ledger_path is None
    assert "client.py" in ws.files and not (tmp_path / "ws.ledger").exists()
    assert "Budget: 50 charged steps." in (ws.workspace / "client.py").read_text()


def test_unmetered_family_gets_instruction_and_its_own_files(tmp_path):
    def plain(workspace: Path) -> None:
        (workspace / "template.xml").write_text("<mujoco/>")

    ws = layout_workspace(_spec(make_dev_env=plain, steps=None), tmp_path / "ws", secret=SECRET)
    assert ws.files == ("instruction.md", "template.xml") and ws.server is None


def test_ledger_keys_differ_per_task_and_secret():
    assert ledger_key(SECRET, "09-gello") != ledger_key(SECRET, "08-mobile-base")
    assert ledger_key(SECRET, TASK) != ledger_key(Secret(b"other-secret", public=False), TASK)
    assert len(ledger_key(SECRET, TASK)) == 32


def test_cli_dev_serves_in_the_foreground_until_the_agent_seals(tmp_path, monkeypatch, capsys):
    import threading
    import time

    import rle_tasks.core.registry as registry
    from rle_tasks.cli import main

    monkeypatch.setattr(registry, "get_task", lambda task_id: _spec())
    workspace = tmp_path / "ws"
    steps: list[int] = []

    def agent() -> None:
        deadline = time.monotonic() + 60
        while not (workspace / ".rle" / "ledger.sock").exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        with _client_module(workspace).connect() as env:
            env.reset()
            env.step([0.0])
            steps.append(env.info()["steps_used"])
            env.seal()

    thread = threading.Thread(target=agent)
    thread.start()
    assert main(["dev", TASK, "--workspace", str(workspace)]) == 0  # returns once sealed
    thread.join(10)
    assert steps == [2]
    out = capsys.readouterr().out
    assert f"Metered environment listening on {workspace / '.rle' / 'ledger.sock'}" in out
    assert out.splitlines()[0].startswith("rle dev serves in the foreground")
    public = Secret(PUBLIC_KEY, public=True)  # no secret given: public key
    ledger = tmp_path / "ws.ledger" / f"{default_attempt(workspace)}.jsonl"
    assert verify_ledger(ledger, ledger_key(public, TASK), TASK).valid


def _seal_one(ws) -> None:
    try:
        with _client_module(ws.workspace).connect() as env:
            env.reset()
            env.seal()
        ws.server.wait(10)
    finally:
        ws.close()


def test_an_attempt_has_one_metered_session(tmp_path, monkeypatch, capsys):
    import rle_tasks.core.registry as registry
    from rle_tasks.cli import main

    ws = layout_workspace(_spec(), tmp_path / "ws", secret=SECRET, attempt="trial-42")
    _seal_one(ws)
    assert ws.ledger_path == tmp_path / "ws.ledger" / "trial-42.jsonl"
    opened = json.loads(ws.ledger_path.read_text().splitlines()[0])["payload"]
    assert opened["attempt"] == "trial-42"
    with pytest.raises(RleError) as info:  # the same attempt again, even from another workspace name
        layout_workspace(_spec(), tmp_path / "ws", secret=SECRET, attempt="trial-42")
    assert info.value.code == "ledger.attempt_used" and "trial-42.jsonl" in str(info.value)
    monkeypatch.setattr(registry, "get_task", lambda task_id: _spec())
    assert main(["dev", TASK, "--workspace", str(tmp_path / "ws"), "--attempt", "trial-42"]) == 2
    assert "error [ledger.attempt_used]" in capsys.readouterr().err
    other = layout_workspace(_spec(), tmp_path / "ws", secret=SECRET, attempt="trial-43")  # a new attempt
    _seal_one(other)
    assert other.ledger_path.name == "trial-43.jsonl"


def test_the_development_environment_is_built_from_the_attempts_secret(tmp_path):
    seen = []

    def record(workspace: Path):
        seen.append(current_secret())

    for attempt in ("a-1", "a-2"):
        layout_workspace(
            _spec(make_dev_env=record, steps=None), tmp_path / attempt, secret=SECRET, attempt=attempt
        )
    assert [s.attempt for s in seen] == ["a-1", "a-2"] and all(s.key == SECRET.key for s in seen)
    assert derive_seed(seen[0], TASK, 0) != derive_seed(seen[1], TASK, 0)
    assert derive_seed(SECRET.for_attempt(""), TASK, 0) == derive_seed(SECRET, TASK, 0)  # unbound: as before
    assert ledger_key(seen[0], TASK) == ledger_key(SECRET, TASK)  # the key never depends on the attempt
    with pytest.raises(RleError) as info:
        SECRET.for_attempt("../escape")
    assert info.value.code == "attempt.invalid"
