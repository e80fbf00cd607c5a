"""An output low-pass for an already exported family-04 policy whose torch module is gone (the shipped
dance student: the device run kept only its ONNX), added to its ONNX graph; a policy still in torch
gets the same filter from ``public.export.export_policy(smoothing=1 - s)`` (``distil.py --low-pass``):
``actions = (1 - s) net(obs) + s a_prev``, with ``a_prev`` the previous action the latest observation
frame carries (its last 29 entries, ``public/tracking.py``). The policy stays stateless (the history is
its input); s = 0 leaves the actions unchanged. It halves the action jerk J at s = 0.5 at the price of
a lag of about s / (1 - s) policy steps.

    python -m rle_tasks.f04_motion_tracking.solutions.smooth IN_DIR OUT_DIR S

copies ``policy_meta.json`` and writes the wrapped ``policy.onnx``.
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

import numpy as np

from ..public.contract import META, ONNX
from ..public.g1_constants import G1

__all__ = ["low_pass"]


def low_pass(src: Path, dst: Path, s: float) -> Path:
    """Write ``dst`` (``policy.onnx``, ``policy_meta.json``): the policy of ``src`` with the low-pass."""
    import onnx
    from onnx import helper, numpy_helper

    if not 0.0 <= s < 1.0:
        raise ValueError(f"the low-pass weight must lie in [0, 1), got {s}")
    model = onnx.load(str(Path(src) / ONNX))
    graph = model.graph
    obs, out = graph.input[0].name, graph.output[0].name
    used = {i.name for i in graph.initializer} | {o for n in graph.node for o in n.output}
    k = next(k for k in range(len(used) + 1) if not any(u.startswith(f"lp{k}_") for u in used))
    n = {name: f"lp{k}_{name}" for name in ("raw", "start", "end", "axis", "s", "keep", "prev", "old", "new")}
    for node in graph.node:  # a policy already low-passed gets a second stage
        node.output[:] = [n["raw"] if o == out else o for o in node.output]
    graph.initializer.extend(
        [
            numpy_helper.from_array(np.array([-G1.dof], np.int64), n["start"]),
            numpy_helper.from_array(np.array([2**31 - 1], np.int64), n["end"]),
            numpy_helper.from_array(np.array([1], np.int64), n["axis"]),
            numpy_helper.from_array(np.array(s, np.float32), n["s"]),
            numpy_helper.from_array(np.array(1.0 - s, np.float32), n["keep"]),
        ]
    )
    graph.node.extend(
        [
            helper.make_node("Slice", [obs, n["start"], n["end"], n["axis"]], [n["prev"]]),
            helper.make_node("Mul", [n["prev"], n["s"]], [n["old"]]),
            helper.make_node("Mul", [n["raw"], n["keep"]], [n["new"]]),
            helper.make_node("Add", [n["old"], n["new"]], [out]),
        ]
    )
    onnx.checker.check_model(model)
    dst = Path(dst)
    dst.mkdir(parents=True, exist_ok=True)
    onnx.save(model, str(dst / ONNX))
    shutil.copyfile(Path(src) / META, dst / META)
    return dst


def main() -> None:
    p = argparse.ArgumentParser(description="Add an output low-pass to an exported family-04 policy.")
    p.add_argument("src", type=Path)
    p.add_argument("dst", type=Path)
    p.add_argument("s", type=float)
    a = p.parse_args()
    print(f"wrote {low_pass(a.src, a.dst, a.s)}")


if __name__ == "__main__":
    main()
