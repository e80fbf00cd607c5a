"""Composition entry points kept for existing callers; the implementation is ``rle_design.scene``.

``compose(spec, arm, payload, mount_site=...)`` keeps its old positional behaviour: ``floor`` and
``options`` map onto an ``Arena``; the mount site is the caller's (the toolkit names no task's site).
"""

from __future__ import annotations

import mujoco

from rle_design.scene import (
    TOOL_SITE,
    Arena,
    FloorConfig,
    PhysicsOptions,
    arm_ids,
    arm_model_path,
    attach_arm,
    attach_part,
    attach_payload,
    compile_spec,
    find_body,
    find_site,
)
from rle_design.scene import compose as _compose
from rle_design.scene import load_robot as _load_robot

__all__ = [
    "TOOL_SITE",
    "SceneOptions",
    "add_floor",
    "apply_options",
    "arm_ids",
    "arm_model_path",
    "attach_arm",
    "attach_part",
    "attach_payload",
    "compile_spec",
    "compose",
    "find_body",
    "find_site",
    "load_arm_spec",
]

SceneOptions = PhysicsOptions
"""Former name of ``PhysicsOptions``."""

_PHYSICS = PhysicsOptions()


def __getattr__(name: str):
    if name == "ARM_IDS":  # former constant: the arm list now comes from the catalog
        return arm_ids()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def load_arm_spec(arm_id: str) -> mujoco.MjSpec:
    """Fresh ``MjSpec`` of a catalog arm with a ``tool_site`` on its tool body (no keyframes)."""
    return _load_robot(arm_id, keyframes=False)


def add_floor(spec: mujoco.MjSpec, friction: float = 1.0, size: float = 20.0) -> None:
    """Ground plane at z = 0, sky and a light (``Arena`` without physics options)."""
    floor = FloorConfig(half_size=size, friction=(friction, 0.005, 0.0001))
    Arena(floor=floor, physics=None).edit_spec(spec)


def apply_options(spec: mujoco.MjSpec, options: PhysicsOptions = _PHYSICS) -> None:
    """Impose physics options on a spec."""
    options.edit_spec(spec)


def compose(
    robot: mujoco.MjSpec,
    arm_id: str | None = None,
    payload_id: str | None = None,
    floor: bool = True,
    options: PhysicsOptions | None = _PHYSICS,
    mount_site: str | None = None,
) -> mujoco.MjSpec:
    """``rle_design.scene.compose`` with the former signature (``floor`` flag, ``options``); an arm needs
    ``mount_site``."""
    arena = Arena(physics=options) if floor else Arena.bare(physics=options)
    return _compose(robot, arm_id, payload_id, mount_site=mount_site, arena=arena)
