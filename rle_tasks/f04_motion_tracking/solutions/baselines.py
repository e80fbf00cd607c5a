"""Build-time generators of the family-04 baselines (``Solution.transforms``): ONNX graphs written with
``onnx.helper`` into the materialised directory."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..public.export import default_meta, linear_policy, open_loop_weights
from ..public.g1_constants import G1

TWELVE_M_HIDDEN = 64_000
"""Hidden width of the oversized graph: 160 x 64,000 + 64,000 x 29 = 12.1 M parameters."""


def open_loop(root: Path) -> None:
    """Open-loop replay: the PD targets are the reference joint angles of the observation."""
    meta = default_meta()
    linear_policy(root, *open_loop_weights(meta), meta)


def zero_action(root: Path) -> None:
    """Zero action: the PD targets stay at the default pose."""
    meta = default_meta()
    linear_policy(root, np.zeros((meta.obs_dim, G1.dof), np.float32), np.zeros(G1.dof, np.float32), meta)


def nan_output(root: Path) -> None:
    """Open-loop replay plus a NaN bias: every output is NaN."""
    meta = default_meta()
    w, b = open_loop_weights(meta)
    linear_policy(root, w, b + np.float32("nan"), meta)


def non_deterministic(root: Path) -> None:
    """Open-loop replay plus 0.05 x a fresh normal draw per call (RandomNormalLike without a seed)."""
    meta = default_meta()
    linear_policy(root, *open_loop_weights(meta), meta, noise=0.05)


def twelve_million(root: Path) -> None:
    """A two-layer linear graph of 12.1 M parameters (zeros): over the 10 M limit."""
    from onnx import TensorProto, helper, numpy_helper

    meta = default_meta()
    w1 = np.zeros((meta.obs_dim, TWELVE_M_HIDDEN), np.float32)
    w2 = np.zeros((TWELVE_M_HIDDEN, G1.dof), np.float32)
    graph = helper.make_graph(
        [
            helper.make_node("MatMul", ["obs", "W1"], ["h"]),
            helper.make_node("MatMul", ["h", "W2"], ["actions"]),
        ],
        "twelve_million",
        [helper.make_tensor_value_info("obs", TensorProto.FLOAT, [1, meta.obs_dim])],
        [helper.make_tensor_value_info("actions", TensorProto.FLOAT, [1, G1.dof])],
        [numpy_helper.from_array(w1, "W1"), numpy_helper.from_array(w2, "W2")],
    )
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)], producer_name="rle-f04")
    model.ir_version = 8
    (Path(root) / "policy.onnx").write_bytes(model.SerializeToString())
    (Path(root) / "policy_meta.json").write_text(meta.to_json())
