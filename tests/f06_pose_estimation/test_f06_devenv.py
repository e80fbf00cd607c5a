"""The served development environment: renders by seed, metered design-set evaluations, sealed ledger."""

import importlib.util
import shutil

import numpy as np
import pytest

from rle_design.ledger.verify import verify_ledger
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.devenv import layout_workspace, ledger_key
from rle_tasks.core.runtime.secrets import load_secret
from rle_tasks.core.solutions import materialise
from rle_tasks.f06_pose_estimation.service import EVALUATIONS


def _client(ws):
    spec = importlib.util.spec_from_file_location("pose_client", ws / "pose_client.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_no_serve_writes_client_only(tmp_path):
    ws = layout_workspace(get_task("06-pose-a-rgb"), tmp_path / "ws", serve=False)
    assert ws.server is None
    assert set(ws.files) == {"instruction.md", "pose_client.py", "calibration.json"}
    text = (tmp_path / "ws" / "pose_client.py").read_text()
    assert "depth" not in text.split("obs:")[1].split("\n")[0]  # variant A: RGB only


@pytest.mark.render
def test_renders_evaluations_and_sealed_ledger(tmp_path):
    task = get_task("06-pose-b-rgbd")
    root = tmp_path / "ws"
    ws = layout_workspace(task, root, serve=True, ledger_dir=tmp_path / "ledger")
    try:
        for f in materialise(task, "reference").iterdir():
            shutil.copy(f, root / f.name)
        client = _client(root)
        with client.connect() as dev:
            a = dev.frames(seed=3, n=2)
            b = dev.frames(seed=3, n=2)
            assert np.array_equal(a[0][0]["rgb"], b[0][0]["rgb"])  # deterministic by seed
            obs, label = a[0]
            assert obs["rgb"].shape == (240, 320, 3) and obs["depth"].shape == (240, 320)
            assert label.shape == (3,)  # (x, y, theta): no shape label
            ep = dev.episode(seed=4, n=5)
            assert [o["t"] for o, _ in ep] == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4])
            report = dev.evaluate()
            assert report["score"] > 0.5
            assert dev.info()["evaluations_left"] == EVALUATIONS - 1
            for _ in range(EVALUATIONS - 1):
                dev._request("info")  # free
            dev.seal()
        ws.server.wait(30)
    finally:
        ws.close()
    verdict = verify_ledger(ws.ledger_path, ledger_key(load_secret(), task.id), task.id)
    assert verdict.valid, verdict
    assert verdict.steps == 1
