"""Level 3: world-frame object and fixture state, the target's identity and the grasp state (public).

Reads the L3 keys of an observation: ``objects`` (name -> category, pos, quat, and the bounding box
``center``/``half`` in the object's frame [m]), ``fixtures`` (name -> kind, pos, size, ``joints``
(normalised 0 closed .. 1 open), ``sites`` (handles, knobs, burners: world positions), ``interior``
(centre, half extents, orientation), ``hinge_left``, and ``<part>_pos``/``<part>_quat`` of doors and
drawers), ``target`` (roles -> names: ``fixture``, ``object``, ``container``, ``burner``, ``knob``)
and ``grasped`` (the target object touches both fingers).
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["fixture", "grasped", "object_pose", "target", "target_fixture", "target_object"]


def target(obs: dict[str, Any]) -> dict[str, str]:
    """The task's roles -> names."""
    return dict(obs["target"])


def object_pose(obs: dict[str, Any], name: str) -> tuple[np.ndarray, np.ndarray]:
    """(position [m], quaternion) of an object in the world."""
    o = obs["objects"][name]
    return np.asarray(o["pos"]), np.asarray(o["quat"])


def fixture(obs: dict[str, Any], name: str) -> dict[str, Any]:
    """A fixture's state (see the module docstring)."""
    return obs["fixtures"][name]


def target_fixture(obs: dict[str, Any]) -> dict[str, Any]:
    """State of the task's target fixture."""
    return fixture(obs, obs["target"]["fixture"])


def target_object(obs: dict[str, Any]) -> dict[str, Any] | None:
    """State of the task's target object (None when the task has none)."""
    name = obs["target"].get("object")
    return None if name is None else obs["objects"][name]


def grasped(obs: dict[str, Any]) -> bool:
    """The target object touches both fingers."""
    return bool(obs.get("grasped", False))
