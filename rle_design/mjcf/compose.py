"""Composition through ``mujoco.MjSpec``: arms attached at a site, payloads at the tool, floor and scene.

The composed model owns the physics options: options of attached children (xarm7 sets
``integrator=implicitfast``) are overwritten by ``SceneOptions`` so every arm is tested alike.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from rle_design.catalog import load_catalog, part_fragment_path
from rle_design.errors import MissingElement, MjcfError
from rle_design.paths import resolve_asset

ARM_IDS = ("panda", "ur5e", "xarm7")
MOUNT_SITE = "arm_mount_site"
TOOL_SITE = "tool_site"


@dataclass(frozen=True)
class SceneOptions:
    """Physics options imposed on every composed scene.

    Attributes:
        timestep: Integration step [s].
        integrator: MuJoCo integrator.
        cone: Friction cone; elliptic avoids the creep of pyramidal cones under sustained lateral load.
        noslip_iterations: Post-solve no-slip iterations (removes soft-contact and frictionloss creep).
        gravity: Gravity vector [m/s^2].
    """

    timestep: float = 0.002
    integrator: int = int(mujoco.mjtIntegrator.mjINT_IMPLICITFAST)
    cone: int = int(mujoco.mjtCone.mjCONE_ELLIPTIC)
    noslip_iterations: int = 5
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)


def _names(items) -> list[str]:
    return [i.name for i in items if i.name]


def find_site(spec: mujoco.MjSpec, name: str) -> mujoco.MjsSite:
    """Site by name or ``MissingElement`` listing the sites."""
    site = spec.site(name)
    if site is None:
        raise MissingElement("site", name, available=_names(spec.sites), code="contract.missing_site")
    return site


def find_body(spec: mujoco.MjSpec, name: str) -> mujoco.MjsBody:
    body = spec.body(name)
    if body is None:
        raise MissingElement("body", name, available=_names(spec.bodies), code="contract.missing_body")
    return body


def arm_model_path(arm_id: str) -> Path:
    """MJCF of a canonical arm (robosuite asset, located without importing robosuite)."""
    if arm_id not in ARM_IDS:
        raise MjcfError(f"unknown arm '{arm_id}'. Available arms: {', '.join(ARM_IDS)}", code="arm.unknown")
    return resolve_asset(load_catalog("arms").get(arm_id).model)


def load_arm_spec(arm_id: str) -> mujoco.MjSpec:
    """Fresh ``MjSpec`` of a canonical arm with a ``tool_site`` on its tool body."""
    path = arm_model_path(arm_id)
    arm = load_catalog("arms").get(arm_id)
    spec = mujoco.MjSpec.from_file(str(path))
    tool = find_body(spec, arm.tool_body)
    if spec.site(TOOL_SITE) is None:
        tool.add_site(name=TOOL_SITE, pos=[0, 0, 0], size=[0.005] * 3, group=5)
    return spec


def attach_arm(
    spec: mujoco.MjSpec, arm_id: str, site_name: str = MOUNT_SITE, prefix: str | None = None
) -> str:
    """Attach a canonical arm at ``site_name``; returns the name prefix of the arm's elements."""
    site = find_site(spec, site_name)
    arm_spec = load_arm_spec(arm_id)
    root = find_body(arm_spec, load_catalog("arms").get(arm_id).root_body)
    prefix = prefix if prefix is not None else f"{arm_id}/"
    site.attach_body(root, prefix, "")
    return prefix


def attach_part(spec: mujoco.MjSpec, part_id: str, site_name: str, prefix: str) -> mujoco.MjsBody:
    """Attach a catalog part fragment (one root body) at a site."""
    part = load_catalog("parts").get(part_id)
    frag = mujoco.MjSpec.from_file(str(part_fragment_path(part)))
    roots = [b for b in frag.worldbody.bodies]
    if len(roots) != 1:
        raise MjcfError(f"part fragment {part.fragment} must have one root body, has {len(roots)}")
    return find_site(spec, site_name).attach_body(roots[0], prefix, "")


def attach_payload(spec: mujoco.MjSpec, payload_id: str, tool_site: str) -> mujoco.MjsBody:
    """Attach a payload part (e.g. ``"payload_1kg"``) rigidly at the arm's tool site."""
    return attach_part(spec, payload_id, tool_site, prefix="payload/")


def add_floor(spec: mujoco.MjSpec, friction: float = 1.0, size: float = 20.0) -> None:
    """Ground plane at z = 0 and a light, unless a plane named ``floor`` exists."""
    if spec.geom("floor") is None:
        spec.worldbody.add_geom(
            name="floor",
            type=mujoco.mjtGeom.mjGEOM_PLANE,
            size=[size, size, 0.05],
            friction=[friction, 0.005, 0.0001],
            rgba=[0.82, 0.84, 0.86, 1],
        )
    if spec.texture("sky") is None:
        spec.add_texture(
            name="sky",
            type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
            builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT,
            rgb1=[0.93, 0.95, 0.98],
            rgb2=[0.62, 0.70, 0.80],
            width=64,
            height=64,
        )
    if not spec.lights:
        spec.worldbody.add_light(
            name="key",
            pos=[1.5, -1.5, 3.0],
            dir=[-0.4, 0.4, -1.0],
            type=int(mujoco.mjtLightType.mjLIGHT_DIRECTIONAL),
        )
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
    spec.visual.headlight.diffuse = [0.5, 0.5, 0.5]


def apply_options(spec: mujoco.MjSpec, options: SceneOptions = SceneOptions()) -> None:
    spec.option.timestep = options.timestep
    spec.option.integrator = options.integrator
    spec.option.cone = options.cone
    spec.option.noslip_iterations = options.noslip_iterations
    spec.option.gravity = np.asarray(options.gravity, dtype=float)


def compose(
    robot: mujoco.MjSpec,
    arm_id: str | None = None,
    payload_id: str | None = None,
    floor: bool = True,
    options: SceneOptions | None = SceneOptions(),
) -> mujoco.MjSpec:
    """Compose a scene from a robot spec (edited in place and returned).

    Args:
        robot: The design, e.g. a submitted ``robot.xml`` loaded with ``load_design``.
        arm_id: Canonical arm to mount at ``arm_mount_site``, or None.
        payload_id: Payload part to fix at the arm's tool site (requires ``arm_id``).
        floor: Add a floor plane and light.
        options: Physics options the composition owns; None keeps the robot's.
    """
    if payload_id and not arm_id:
        raise MjcfError("a payload needs an arm to hold it", code="compose.payload_without_arm")
    if options is not None:
        apply_options(robot, options)  # before attaching, so children's options do not conflict
    if arm_id:
        prefix = attach_arm(robot, arm_id)
        if payload_id:
            attach_payload(robot, payload_id, prefix + TOOL_SITE)
    if floor:
        add_floor(robot)
    if options is not None:
        apply_options(robot, options)
    return robot


def compile_spec(spec: mujoco.MjSpec) -> mujoco.MjModel:
    """Compile, turning MuJoCo's ValueError into ``MjcfError`` carrying its message."""
    try:
        return spec.compile()
    except ValueError as exc:
        raise MjcfError(f"MuJoCo compile error: {exc}", code="mjcf.compile") from None
