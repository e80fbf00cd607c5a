"""Hidden evaluation of one seed: ``public.evaluate.rollout`` with the submitted graph loaded by the core
ONNX loader (one onnxruntime thread, declared signature, no agent code). The worker loads the graph
itself and returns plain numbers, so seeds fan out through the core fan-out (``run_units``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from rle_design.errors import RleError
from rle_tasks.core.runtime.onnx_policy import OnnxSignature, TensorSpec, _tensors, load_onnx_policy
from rle_tasks.core.runtime.policy import PolicyFault

from .clips import clip_path
from .public.clip import Clip
from .public.contract import MAX_PARAMS, ONNX, PolicyMeta, read_meta
from .public.evaluate import PolicyError, rollout
from .public.g1_constants import G1

__all__ = ["SMOKE_STEPS", "SeedUnit", "count_parameters", "load_policy", "run_seed"]

SMOKE_STEPS = 50
"""Policy steps of the first second, where an explosion is a smoke failure."""


def signature(meta: PolicyMeta) -> OnnxSignature:
    return OnnxSignature(
        inputs=(TensorSpec("obs", (1, meta.obs_dim)),),
        outputs=(TensorSpec("actions", (1, G1.dof)),),
        max_bytes=64 << 20,
        timeout_s=1.0,
    )


def count_parameters(root: Path) -> int:
    """Number of stored tensor elements of the (already validated) ``policy.onnx``: initializers and
    constant tensors, in subgraphs and functions too (the core loader's traversal)."""
    import onnx

    model = onnx.load_model_from_string((Path(root) / ONNX).read_bytes())
    return sum(math.prod(t.dims) if len(t.dims) else 1 for t in _tensors(model))


def load_policy(root: Path):
    """(meta, policy) of a submission.

    Raises:
        RleError: ``f04.meta``, an ``onnx.*`` ``PolicyFault``, or ``f04.params`` above ``MAX_PARAMS``.
    """
    meta = read_meta(root)
    policy = load_onnx_policy(ONNX, root, signature(meta))
    n = count_parameters(root)
    if n > MAX_PARAMS:
        raise RleError(f"{ONNX}: {n:,} parameters; the limit is {MAX_PARAMS:,}", code="f04.params", path=ONNX)
    return meta, policy


@dataclass(frozen=True)
class SeedUnit:
    """One hidden seed of a verification (a runner unit; picklable)."""

    root: str
    """The submission directory."""
    style: str
    """The clip."""
    seed: int
    """Seed of the perturbation, the terrain and the sensor noise."""


def run_seed(unit: SeedUnit) -> dict:
    """``rollout`` of the unit's clip for the policy in its root on the robot of its seed."""
    meta, policy = load_policy(Path(unit.root))

    def act(x):
        try:
            return policy.run({"obs": x})["actions"][0]
        except PolicyFault as exc:
            raise PolicyError(exc.code) from None

    return rollout(act, meta, Clip.load(clip_path(unit.style)), unit.seed)
