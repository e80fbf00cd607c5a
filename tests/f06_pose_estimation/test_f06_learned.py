"""Variant C pieces: the model scripts and answers (1, 6); training images equal the in-graph ones."""

import numpy as np
import pytest
import torch

from rle_tasks.f06_pose_estimation.learned import BevPoseNet, Head, bev
from rle_tasks.f06_pose_estimation.train import _bev_np

pytestmark = pytest.mark.filterwarnings("ignore:`torch.jit.script` is deprecated:DeprecationWarning")


def test_numpy_and_torch_bird_eye_images_agree():
    rng = np.random.default_rng(1)
    p = rng.normal(0.0, 0.03, (500, 2)).astype(np.float32)
    t = torch.from_numpy(p)
    assert np.array_equal(_bev_np(p), bev(t, t.mean(0)).numpy()[0])


def test_scripted_model_signature():
    k = torch.tensor([[200.0, 0, 159.5], [0, 200.0, 119.5], [0, 0, 1]])
    pose = torch.eye(4)
    pose[2, 3] = 1.0  # camera 1 m above the plane, looking down (+z of OpenCV is world +z here)
    model = torch.jit.script(BevPoseNet(k, pose, 1.5, Head()))
    rgb = torch.zeros(1, 3, 240, 320)
    rgb[0, 0, 100:140, 140:180] = 1.0  # a red square
    depth = torch.full((1, 1, 240, 320), 0.5)  # world z = 1.5: on the "top face"
    out = model(rgb, depth, torch.ones(1, 1, 240, 320))
    assert out.shape == (1, 6) and torch.isfinite(out).all()
    # no red pixel: the documented fallback of zeros
    assert torch.equal(
        model(torch.zeros(1, 3, 240, 320), depth, torch.ones(1, 1, 240, 320)), torch.zeros(1, 6)
    )


def test_session_meters_evaluations(tmp_path, monkeypatch):
    from rle_design.ledger.records import LedgerError
    from rle_design.ledger.verify import verify_ledger
    from rle_tasks.f06_pose_estimation import devserver, service

    monkeypatch.setattr(devserver, "design_evaluation", lambda task_id, root: {"score": 0.5})
    key = b"k" * 32
    session = service.open_session(
        key=key, ledger_path=tmp_path / "l.jsonl", task_id="06-pose-a-rgb", workspace=str(tmp_path)
    )
    for i in range(service.EVALUATIONS):
        meta, out = session.handle({"op": "evaluate"}, None)
        assert meta["used"] == i + 1 and out["score"] == 0.5
    with pytest.raises(LedgerError, match="0 of the attempt's 6 left"):
        session.handle({"op": "evaluate"}, None)
    with pytest.raises(LedgerError, match="unknown operation 'render'"):
        session.handle({"op": "render"}, None)
    session.handle({"op": "seal"}, None)
    verdict = verify_ledger(tmp_path / "l.jsonl", key, "06-pose-a-rgb")
    assert verdict.valid and verdict.steps == service.EVALUATIONS
