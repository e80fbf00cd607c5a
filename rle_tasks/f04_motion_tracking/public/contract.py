"""The submitted policy: ``policy.onnx`` (one input ``obs`` (1, 160 H), one output ``actions`` (1, 29),
float32) and ``policy_meta.json``.

``policy_meta.json`` keys: ``history`` (H, observations stacked oldest first, 1 to 16),
``action_scale`` (29 values, rad) and ``default_pose`` (29 values, rad): the PD targets are
``default_pose + action_scale * actions``. At most ``MAX_PARAMS`` parameters.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rle_design.errors import RleError

from .g1_constants import G1
from .tracking import OBS_DIM

__all__ = ["MAX_HISTORY", "MAX_PARAMS", "META", "ONNX", "PolicyMeta", "read_meta"]

ONNX, META = "policy.onnx", "policy_meta.json"
MAX_PARAMS = 10_000_000
MAX_HISTORY = 16
MAX_ACTION_SCALE = 1.0
"""Largest accepted action scale [rad per unit action]."""


@dataclass(frozen=True)
class PolicyMeta:
    history: int
    action_scale: tuple[float, ...]
    default_pose: tuple[float, ...]

    @property
    def obs_dim(self) -> int:
        return OBS_DIM * self.history

    def to_json(self) -> str:
        return json.dumps(
            {
                "history": self.history,
                "action_scale": list(self.action_scale),
                "default_pose": list(self.default_pose),
                "obs_dim": OBS_DIM,
                "joints": list(G1.joints),
                "policy_dt": 0.02,
            },
            indent=1,
        )


def _fail(msg: str) -> RleError:
    return RleError(f"{META}: {msg}", code="f04.meta", path=META)


def read_meta(root: Path) -> PolicyMeta:
    """Read and check ``policy_meta.json`` in the submission directory ``root``.

    Raises:
        RleError: ``f04.meta`` naming the missing or bad key.
    """
    base = Path(root).resolve()
    path = (base / META).resolve()
    if not path.is_relative_to(base) or not path.is_file():
        raise _fail("missing (a regular file in the submission directory)")
    if path.stat().st_size > 1 << 20:
        raise _fail("larger than 1 MiB")
    try:
        data = json.loads(path.read_text())
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise _fail(f"not JSON: {exc}") from None
    if not isinstance(data, dict):
        raise _fail("must be a JSON object with history, action_scale, default_pose")
    h = data.get("history")
    if not isinstance(h, int) or isinstance(h, bool) or not 1 <= h <= MAX_HISTORY:
        raise _fail(f"history must be an integer from 1 to {MAX_HISTORY}, got {h!r}")
    out = {}
    for key, bound in (("action_scale", MAX_ACTION_SCALE), ("default_pose", np.pi)):
        v = data.get(key)
        try:
            arr = np.asarray(v, dtype=np.float64)
        except (TypeError, ValueError):
            raise _fail(f"{key} must be a list of {G1.dof} numbers") from None
        if arr.shape != (G1.dof,) or not np.isfinite(arr).all() or np.abs(arr).max() > bound:
            raise _fail(f"{key} must be {G1.dof} finite numbers of magnitude at most {bound:g}")
        out[key] = tuple(float(x) for x in arr)
    return PolicyMeta(h, out["action_scale"], out["default_pose"])
