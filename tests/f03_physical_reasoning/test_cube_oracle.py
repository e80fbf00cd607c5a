"""03-pocket-cube's Harbor oracle: a privileged session serves the reference's plan, nothing else does."""

from __future__ import annotations

import importlib.util
import shutil
from pathlib import Path

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.devenv import layout_workspace
from rle_tasks.core.runtime.secrets import Secret
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.cube.scene import instance
from rle_tasks.f03_physical_reasoning.solutions.pocket_cube import harbor_oracle
from rle_tasks.f03_physical_reasoning.solutions.pocket_cube.reference import plan

SECRET = Secret(b"cube-oracle-test", public=False)


def _client(workspace: Path):
    spec = importlib.util.spec_from_file_location("cube_client", workspace / "client.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _session(tmp_path: Path, name: str, privileged: bool) -> tuple[dict, Path]:
    spec = get_task("03-pocket-cube")
    ws = layout_workspace(spec, tmp_path / name, secret=SECRET, attempt=name, privileged=privileged)
    try:
        with _client(ws.workspace).connect() as env:
            obs = env.reset()
            env.seal()
        ws.server.wait(30)
    finally:
        ws.close()
    art = tmp_path / f"{name}-art"
    art.mkdir()
    shutil.copyfile(ws.ledger_path, art / "ledger.jsonl")
    return obs, art


def test_only_an_oracle_session_serves_the_plan_and_its_report_says_so(tmp_path):
    spec = get_task("03-pocket-cube")
    assert spec.privileged_oracle
    obs, art = _session(tmp_path, "oracle-1", privileged=True)
    assert obs["plan"] == plan(instance(SECRET.for_attempt("oracle-1")).state)
    report = spec.verify(art, VerifyContext(secret=SECRET, attempt="oracle-1"))
    assert "ledger.privileged" in [e.code for e in report.errors]
    assert report.native_metrics["privileged_session"] is True
    obs, art = _session(tmp_path, "agent-1", privileged=False)
    assert "plan" not in obs
    report = spec.verify(art, VerifyContext(secret=SECRET, attempt="agent-1"))
    assert "ledger.privileged" not in [e.code for e in report.errors]


def test_the_exported_oracle_needs_only_the_agents_image(tmp_path):
    solve = harbor_oracle(get_task("03-pocket-cube"), tmp_path)
    assert "python3 /solution/oracle.py" in solve
    assert sorted(p.name for p in tmp_path.iterdir()) == ["oracle.py", "top_turns.py", "two_hands.py"]
    for path in tmp_path.iterdir():
        text = path.read_text()
        assert "rle_tasks" not in text and "from ." not in text
        compile(text, path.name, "exec")
    assert "MOVES = {'Y': pitch_y, 'Z': yaw}" in (tmp_path / "oracle.py").read_text()
