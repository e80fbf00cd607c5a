"""05-libero-open's workspace: the linked demonstrations, the client, and metered episodes of the agent's
recipe served by the development server (a separate process holding LIBERO and the ledger key)."""

import importlib.util

import pytest

from rle_design.errors import RleError
from rle_design.ledger.verify import verify_ledger
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.devenv import layout_workspace, ledger_key
from rle_tasks.core.runtime.secrets import load_secret
from rle_tasks.core.solutions import materialise
from rle_tasks.envs.libero.replay import train
from rle_tasks.f05_nanovla import datasets

TASK = get_task("05-libero-open")


@pytest.fixture
def demos(tmp_path, monkeypatch):
    import hashlib
    import json

    import numpy as np

    d = tmp_path / "demos"
    d.mkdir()
    np.savez(
        d / "task00_init00.npz", actions=np.full((5, 7), 0.1, np.float32), state=np.zeros((6, 8), np.float32)
    )
    text = json.dumps({"files": {}, "views": False})
    (d / "manifest.json").write_text(text)
    (d / "manifest.sha256").write_text(hashlib.sha256(text.encode()).hexdigest() + "\n")
    monkeypatch.setenv(datasets.DATASET_ENV, str(d))
    return d


def _client(ws):
    spec = importlib.util.spec_from_file_location("libero_client", ws / "libero_client.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_layout_links_the_demonstrations_and_writes_the_client(tmp_path, demos):
    ws = layout_workspace(TASK, tmp_path / "ws", serve=False)
    root = tmp_path / "ws"
    assert ws.server is None
    assert (root / "demos").resolve() == demos.resolve() and (root / "submission").is_dir()
    text = (root / "libero_client.py").read_text()
    assert "20,000 episodes" in text and "def evaluate(self, directory, episodes, max_steps=None)" in text


def test_no_dataset_no_workspace(tmp_path, monkeypatch):
    monkeypatch.setenv(datasets.DATASET_ENV, str(tmp_path / "none"))
    with pytest.raises(RleError) as exc:
        layout_workspace(TASK, tmp_path / "ws", serve=False)
    assert exc.value.code == "f05.no_dataset" and "make libero-demos" in exc.value.message


def test_served_episodes_are_metered_and_bad_requests_refused(tmp_path, demos, libero_side_env):
    root = tmp_path / "ws"
    ws = layout_workspace(TASK, root, serve=True, ledger_dir=tmp_path / "ledger")
    try:
        sub = root / "submission"
        (sub / "solution.py").write_bytes(
            (materialise(TASK, "baseline/mean_action") / "solution.py").read_bytes()
        )
        assert train(sub / "solution.py", demos, sub) is None  # the agent trains in its workspace
        client = _client(root)
        with client.connect() as dev:
            with pytest.raises(RuntimeError, match="f05.dev_dir"):
                dev.evaluate("../outside", [(0, 0)])
            with pytest.raises(RuntimeError, match="ledger.bad_request"):
                dev.evaluate("submission", [(10, 0)])  # LIBERO-10 has tasks 0-9
            (res,) = dev.evaluate("submission", [(0, 3)], max_steps=4)
            assert res["init_index"] == 3 and res["steps"] == 4 and not res["success"] and res["fault"] == ""
            assert dev.info() == {
                "episodes_used": 1,
                "episodes_left": 19_999,
                "episodes_this_session": 1,
                "budget": 20_000,
            }
            dev.seal()
        ws.server.wait(30)
    finally:
        ws.close()
    verdict = verify_ledger(ws.ledger_path, ledger_key(load_secret(), TASK.id), TASK.id)
    assert verdict.valid and verdict.steps == 1, verdict


def test_the_robust_workspace_meters_under_its_own_task_id(tmp_path, demos):
    from rle_tasks.f05_nanovla.devenv import open_session

    robust = get_task("05-libero-robust")
    layout_workspace(robust, tmp_path / "ws", serve=False)
    assert "Evaluation client of 05-libero-robust" in (tmp_path / "ws" / "libero_client.py").read_text()
    key = ledger_key(load_secret(), robust.id)
    session = open_session(
        key=key, ledger_path=tmp_path / "l.jsonl", workspace=str(tmp_path / "ws"), task_id=robust.id
    )
    info = session.handle({"op": "info"}, None)[1]
    assert info == {"episodes_used": 0, "episodes_left": 20_000, "episodes_this_session": 0, "budget": 20_000}
    session.handle({"op": "seal"}, None)
    assert session.sealed
    assert verify_ledger(tmp_path / "l.jsonl", key, robust.id).valid
    assert not verify_ledger(tmp_path / "l.jsonl", key, "05-libero-open").valid
