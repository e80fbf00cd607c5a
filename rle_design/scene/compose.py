"""Composition: a design with a catalog arm attached at a site, a payload at the tool, in an arena.

The composed model owns the physics options: options of attached children (xarm7 sets
``integrator=implicitfast``) are overwritten by the arena's ``PhysicsOptions`` so every arm is tested
alike. Which site carries the arm is the caller's (the task's) choice: the toolkit knows no site name.
"""

from __future__ import annotations

import mujoco

from rle_design.catalog import load_catalog, part_fragment_path
from rle_design.errors import ConfigError, MjcfError
from rle_design.scene.arena import Arena
from rle_design.scene.attach import attach, root_body
from rle_design.scene.robots import TOOL_SITE, load_robot, robot_constants

__all__ = ["attach_arm", "attach_part", "attach_payload", "compile_spec", "compose"]


_ARENA = Arena()


def attach_arm(spec: mujoco.MjSpec, arm_id: str, site: str, prefix: str | None = None) -> str:
    """Attach a catalog arm (root body on ``site``); returns the name prefix of its elements.

    Args:
        spec: The design, edited in place.
        arm_id: Catalog arm id.
        site: Site of ``spec`` that carries the arm's root frame.
        prefix: Name prefix of the arm's elements (default ``"<arm_id>/"``); the arm's tool site is
            ``prefix + TOOL_SITE``.
    """
    arm = robot_constants(arm_id)
    prefix = prefix if prefix is not None else f"{arm_id}/"
    attach(spec, load_robot(arm_id, keyframes=False), site, prefix, body=arm.root_body)
    return prefix


def attach_part(spec: mujoco.MjSpec, part_id: str, site: str, prefix: str) -> mujoco.MjsBody:
    """Attach a catalog part fragment (one root body) at a site."""
    part = load_catalog("parts").get(part_id)
    frag = mujoco.MjSpec.from_file(str(part_fragment_path(part)))
    try:
        root = root_body(frag)
    except MjcfError:
        roots = len(list(frag.worldbody.bodies))
        raise MjcfError(f"part fragment {part.fragment} must have one root body, has {roots}") from None
    return attach(spec, root, site, prefix)


def attach_payload(
    spec: mujoco.MjSpec, payload_id: str, tool_site: str, prefix: str = "payload/"
) -> mujoco.MjsBody:
    """Attach a payload part (e.g. ``"payload_1kg"``) rigidly at an arm's tool site."""
    return attach_part(spec, payload_id, tool_site, prefix=prefix)


def compose(
    robot: mujoco.MjSpec,
    arm_id: str | None = None,
    payload_id: str | None = None,
    *,
    mount_site: str | None = None,
    arena: Arena | None = _ARENA,
) -> mujoco.MjSpec:
    """Compose a scene from a design spec (edited in place and returned).

    Args:
        robot: The design, e.g. a submitted ``robot.xml`` loaded with ``load_design``.
        arm_id: Catalog arm to attach at ``mount_site`` (prefix ``"<arm_id>/"``), or None.
        payload_id: Payload part fixed at the arm's tool site (requires ``arm_id``).
        mount_site: Site of the design that carries the arm (required with ``arm_id``).
        arena: Floor, lights and physics options the composition owns; None leaves the design's
            (MuJoCo then warns about, and drops, an attached arm's differing options).

    Raises:
        MjcfError: A payload without an arm, an unknown arm.
        ConfigError: An arm without ``mount_site``.
        MissingElement: ``mount_site`` is not a site of the design (lists the sites).
    """
    if payload_id and not arm_id:
        raise MjcfError("a payload needs an arm to hold it", code="compose.payload_without_arm")
    if arm_id and not mount_site:
        raise ConfigError("compose: an arm needs mount_site, the design's site that carries it")
    if arena is not None and arena.physics is not None:
        arena.physics.edit_spec(robot)  # before attaching, so children's options do not conflict
    if arm_id:
        prefix = attach_arm(robot, arm_id, mount_site)
        if payload_id:
            attach_payload(robot, payload_id, prefix + TOOL_SITE)
    if arena is not None:
        arena.edit_spec(robot)
    return robot


def compile_spec(spec: mujoco.MjSpec) -> mujoco.MjModel:
    """Compile, turning MuJoCo's ValueError into ``MjcfError`` carrying its message."""
    try:
        return spec.compile()
    except ValueError as exc:
        raise MjcfError(f"MuJoCo compile error: {exc}", code="mjcf.compile") from None
