"""Export a trained policy to the submission contract: ``policy.onnx`` + ``policy_meta.json``.

``export_policy`` traces a torch module mapping (1, 160 H) float32 observations to (1, 29) actions
(TorchScript-based exporter, opset 17, no external data). ``linear_policy`` writes a graph
``actions = obs @ W + b`` directly with ``onnx.helper`` (open-loop and zero-action policies).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .contract import META, ONNX, PolicyMeta
from .g1_constants import G1
from .tracking import OBS_DIM

__all__ = ["default_meta", "export_policy", "linear_policy", "open_loop_weights"]

OPSET = 17


def default_meta(history: int = 1) -> PolicyMeta:
    """Meta with the G1's action scale and default pose."""
    return PolicyMeta(history, tuple(G1.action_scale), tuple(G1.default_pose))


LAST_ACTION = slice(OBS_DIM - 29, OBS_DIM)
"""Where the previous action sits in one observation."""


def export_policy(module, out: Path | str, meta: PolicyMeta | None = None, smoothing: float = 1.0) -> Path:
    """Write ``module`` (torch, ``forward(obs) -> actions``) and its meta into ``out``.

    Args:
        smoothing: alpha of a first-order low-pass built into the graph, ``a = alpha module(obs) +
            (1 - alpha) a_prev`` with ``a_prev`` the previous action of the newest observation (the graph
            stays stateless); 1 exports ``module`` unchanged.
    """
    import torch

    meta = meta or default_meta()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    module = module.eval()
    if smoothing != 1.0:
        module = _smoothed(module, float(smoothing), OBS_DIM * (meta.history - 1))
    dummy = torch.zeros(1, meta.obs_dim)
    # trace first: a module holding a loaded TorchScript part (a ``--prior`` of ppo.py) only exports
    # from a traced whole
    with torch.no_grad():
        traced = torch.jit.trace(module, dummy)
    torch.onnx.export(
        traced,
        (dummy,),
        str(out / ONNX),
        input_names=["obs"],
        output_names=["actions"],
        opset_version=OPSET,
        dynamo=False,
    )
    (out / META).write_text(meta.to_json())
    return out


def _smoothed_class():
    import torch

    class Smoothed(torch.nn.Module):
        def __init__(self, inner, alpha: float, newest: int) -> None:
            super().__init__()
            self.inner, self.alpha = inner, alpha
            self.lo, self.hi = newest + LAST_ACTION.start, newest + LAST_ACTION.stop

        def forward(self, obs):
            return self.alpha * self.inner(obs) + (1.0 - self.alpha) * obs[:, self.lo : self.hi]

    return Smoothed


def _smoothed(inner, alpha: float, newest: int):
    """The smoothing wrapper (its class is built on first use: torch is imported lazily)."""
    return _smoothed_class()(inner, alpha, newest)


def open_loop_weights(meta: PolicyMeta) -> tuple[np.ndarray, np.ndarray]:
    """``W, b`` of open-loop replay: the reference joint angles of the newest observation (its first 29
    entries) as PD targets, ``a = (ref - default) / scale``."""
    w = np.zeros((meta.obs_dim, G1.dof), np.float32)
    first = OBS_DIM * (meta.history - 1)  # the newest observation is the last in the stack
    scale, default = np.asarray(meta.action_scale), np.asarray(meta.default_pose)
    w[first + np.arange(G1.dof), np.arange(G1.dof)] = 1.0 / scale
    return w, (-default / scale).astype(np.float32)


def linear_policy(
    out: Path | str, w: np.ndarray, b: np.ndarray, meta: PolicyMeta | None = None, *, noise: float = 0.0
) -> Path:
    """Write the graph ``actions = obs @ w + b`` (plus ``noise`` times a fresh normal draw on every call
    when ``noise > 0``: a non-deterministic graph) and its meta into ``out``."""
    import onnx
    from onnx import TensorProto, helper, numpy_helper

    meta = meta or default_meta()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    nodes = [helper.make_node("MatMul", ["obs", "W"], ["xw"]), helper.make_node("Add", ["xw", "b"], ["lin"])]
    inits = [
        numpy_helper.from_array(np.asarray(w, np.float32), "W"),
        numpy_helper.from_array(np.asarray(b, np.float32).reshape(1, -1), "b"),
    ]
    if noise > 0:
        nodes += [
            helper.make_node("RandomNormalLike", ["lin"], ["eps"], scale=float(noise)),
            helper.make_node("Add", ["lin", "eps"], ["actions"]),
        ]
    else:
        nodes.append(helper.make_node("Identity", ["lin"], ["actions"]))
    graph = helper.make_graph(
        nodes,
        "linear_policy",
        [helper.make_tensor_value_info("obs", TensorProto.FLOAT, [1, meta.obs_dim])],
        [helper.make_tensor_value_info("actions", TensorProto.FLOAT, [1, G1.dof])],
        inits,
    )
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", OPSET)], producer_name="rle-f04")
    model.ir_version = 8
    onnx.checker.check_model(model)
    (out / ONNX).write_bytes(model.SerializeToString())
    (out / META).write_text(meta.to_json())
    return out
