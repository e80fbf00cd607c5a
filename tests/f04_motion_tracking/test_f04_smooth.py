"""The output low-pass added to an exported policy's graph: actions = (1 - s) net(obs) + s a_prev, with
a_prev the last 29 entries of the input (the latest frame's previous action)."""

import numpy as np
import onnxruntime as ort
import pytest

from rle_tasks.core.solutions import materialise
from rle_tasks.f04_motion_tracking.solutions.smooth import low_pass


def _run(path, x):
    return ort.InferenceSession(str(path / "policy.onnx")).run(None, {"obs": x})[0]


@pytest.mark.parametrize("s", [0.0, 0.3, 0.5])
def test_low_pass_is_the_weighted_mean_of_the_net_and_the_previous_action(tmp_path, s):
    src = materialise("04-dance", "reference")  # history 4: inputs of 640
    dst = low_pass(src, tmp_path / "lp", s)
    x = np.random.default_rng(0).normal(size=(1, 640)).astype(np.float32)
    raw, out = _run(src, x), _run(dst, x)
    expected = np.float32(1 - s) * raw + np.float32(s) * x[:, -29:]
    assert np.allclose(out, expected, atol=1e-6), np.abs(out - expected).max()
    assert (dst / "policy_meta.json").read_bytes() == (src / "policy_meta.json").read_bytes()


def test_low_pass_refuses_a_weight_outside_0_1(tmp_path):
    with pytest.raises(ValueError, match=r"\[0, 1\)"):
        low_pass(materialise("04-dance", "reference"), tmp_path / "lp", 1.0)
