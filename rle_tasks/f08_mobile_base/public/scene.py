"""Scenes of family 08: a submitted base with the verifier's wheel model, a canonical arm, a payload
and (optionally) the shelf, plus the handles the checks need."""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np

from rle_design.catalog import load_catalog
from rle_design.kinematics.ik import ArmChain, chain_from_mujoco
from rle_design.scene import (
    TOOL_SITE,
    Arena,
    ComOffset,
    FrictionScale,
    Uniform,
    Variation,
    VariationSpace,
    arm_ids,
    compile_spec,
    compose,
    drop_visual_meshes,
    element_id,
    robot_constants,
)
from rle_design.stability import StabilityProbe, SupportSet

from .wheels import WHEELS, WheelModel, install_wheels

TASK_ID = "08-mobile-base"
ARMS = arm_ids()
CHASSIS = "chassis"
BATTERY = "battery"
ADAPTER = "universal_adapter"
MOUNT_SITE = "arm_mount_site"
PAYLOADS = {0: None, 1: "payload_1kg", 2: "payload_2kg"}
TIP_TILT_DEG = 2.0  # chassis tilt that counts as tipping [deg]
STOWED = {a: robot_constants(a).stowed for a in ARMS}
"""Stowed arm postures (robosuite's ``init_qpos`` of each model) [rad]."""


VARIATIONS = VariationSpace(
    (
        FrictionScale(
            "friction", Uniform(0.85, 1.15, "1"), pairs=tuple(f"{w}_ground" for w in WHEELS), axis=1
        ),
        ComOffset("payload_com", Uniform(-0.01, 0.01, "m"), body="payload/payload"),
    )
)
"""What the hidden evaluation perturbs: floor friction along the rollers and the payload's COM."""


@dataclass
class Scene:
    """A compiled scene and its handles.

    Attributes:
        model: Compiled model.
        arm: Arm id or None.
        chain: IK chain of the arm (None without arm).
        chassis: Chassis body id.
        probe: Stability probe (wheel supports on the floor).
        wheel_act: Actuator ids of the wheel drives (order ``WHEELS``).
        arm_act: Actuator ids of the arm torques (joint order).
        tool_site: Tool site id (-1 without arm).
        robot_geoms: Geom ids of the robot (base, arm, payload).
        shelf_geoms: Geom ids of the shelf.
        qpos_rest: Configuration at rest on the floor at the origin, arm stowed [m, rad].
    """

    model: mujoco.MjModel
    arm: str | None
    chain: ArmChain | None
    chassis: int
    probe: StabilityProbe
    wheel_act: np.ndarray
    arm_act: np.ndarray
    tool_site: int
    robot_geoms: np.ndarray
    shelf_geoms: np.ndarray
    qpos_rest: np.ndarray
    extra: dict = field(default_factory=dict)

    @property
    def mass(self) -> float:
        return float(self.model.body_subtreemass[self.chassis])

    def rest_data(self, x: float = 0.0, yaw: float = 0.0) -> mujoco.MjData:
        """State at rest with the chassis origin at (x, 0) and heading ``yaw`` [rad]."""
        d = mujoco.MjData(self.model)
        d.qpos[:] = self.qpos_rest
        d.qpos[0] += x
        d.qpos[3:7] = [np.cos(yaw / 2), 0, 0, np.sin(yaw / 2)]
        mujoco.mj_forward(self.model, d)
        return d

    def front_extent(self) -> float:
        """Largest x of the base (no arm) at rest, relative to the chassis origin [m]."""
        return float(self.extra["front_extent"])


def add_shelf(spec: mujoco.MjSpec) -> None:
    """The shelf of ``catalogs/shelf.yaml``: side panels, boards at the level heights, back panel."""
    shelf = load_catalog("shelf").extra
    x0, w, dep, t = (
        float(shelf["front_x"]),
        float(shelf["width"]),
        float(shelf["depth"]),
        float(shelf["board_thickness"]),
    )
    top = max(shelf["level_heights"]) + 0.30
    body = spec.worldbody.add_body(name="shelf", pos=[x0 + dep / 2, 0, 0])
    rgba = [0.62, 0.48, 0.32, 1]
    for i, z in enumerate(shelf["level_heights"]):
        body.add_geom(
            name=f"shelf_board_{i}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[dep / 2, w / 2, t / 2],
            pos=[0, 0, z - t / 2],
            rgba=rgba,
        )
    for side in (-1, 1):
        body.add_geom(
            name=f"shelf_side_{'l' if side > 0 else 'r'}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[dep / 2, t / 2, top / 2],
            pos=[0, side * (w / 2 + t / 2), top / 2],
            rgba=rgba,
        )
    body.add_geom(
        name="shelf_back",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[t / 2, w / 2 + t, top / 2],
        pos=[dep / 2 + t / 2, 0, top / 2],
        rgba=rgba,
    )


def _subtree_geoms(model: mujoco.MjModel, root: int) -> np.ndarray:
    bodies = [b for b in range(model.nbody) if _is_descendant(model, b, root)]
    return np.array([g for g in range(model.ngeom) if model.geom_bodyid[g] in bodies], dtype=int)


def _is_descendant(model: mujoco.MjModel, b: int, root: int) -> bool:
    while b > 0:
        if b == root:
            return True
        b = int(model.body_parentid[b])
    return root == 0


def build_scene(
    fresh_spec,
    arm: str | None = None,
    payload_kg: int = 0,
    *,
    shelf: bool = False,
    variation: Variation | None = None,
    visual: bool = True,
) -> Scene:
    """Compose and compile a scene.

    Args:
        fresh_spec: Callable returning a new ``MjSpec`` of the submitted base.
        arm: Canonical arm id or None.
        payload_kg: 0, 1 or 2.
        shelf: Add the shelf.
        variation: A draw of ``VARIATIONS`` (its payload term is dropped without payload), or None.
        visual: Keep the arm's visual meshes; False gives the same physics and compiles faster
            (``rle_design.scene.drop_visual_meshes``), for scenes nobody looks at.
    """
    spec = fresh_spec()
    Arena().edit_spec(spec)  # physics options, floor, sky and lights before the wheels
    wheel_names = install_wheels(spec, WheelModel())
    payload = PAYLOADS[payload_kg]
    compose(spec, arm, payload, mount_site=MOUNT_SITE)
    if arm and not visual:
        drop_visual_meshes(spec, f"{arm}/")
    if variation is not None:
        (variation if payload else variation.select("friction")).edit_spec(spec)
    if shelf:
        add_shelf(spec)
    spec.compiler.usethread = False  # sandboxed controllers may not create threads
    model = compile_spec(spec)
    chassis = element_id(model, "body", CHASSIS)
    supports = SupportSet.from_names(model, {w: [f"{w}_contact"] for w in WHEELS})
    probe = StabilityProbe(root_body=chassis, supports=supports, tip_tilt=np.radians(TIP_TILT_DEG))
    wheel_act = np.array([element_id(model, "actuator", n) for n in wheel_names])
    chain, arm_act, tool = None, np.zeros(0, dtype=int), -1
    qpos = model.qpos0.copy()
    if arm:
        joints = [
            model.joint(j).name
            for j in range(model.njnt)
            if model.joint(j).name.startswith(f"{arm}/") and model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE
        ]
        tool_name = f"{arm}/{TOOL_SITE}"
        chain = chain_from_mujoco(model, joints, tool_name)
        tool = element_id(model, "site", tool_name)
        arm_act = np.array(
            [i for i in range(model.nu) if model.actuator(i).name.startswith(f"{arm}/")], dtype=int
        )
        qpos[chain.qpos_adr] = STOWED[arm]
    # rest on the floor at the origin: wheel bottoms at z = 0
    d = mujoco.MjData(model)
    d.qpos[:] = qpos
    d.qpos[0:2] = 0.0
    d.qpos[3:7] = [1, 0, 0, 0]
    mujoco.mj_kinematics(model, d)
    wheel_bodies = [element_id(model, "body", w) for w in WHEELS]
    r = WheelModel().radius
    bottom = min(float(d.xpos[b][2]) for b in wheel_bodies) - r
    qpos[:] = d.qpos
    qpos[2] -= bottom - 2e-4
    robot = _subtree_geoms(model, chassis)
    shelf_geoms = np.array(
        [g for g in range(model.ngeom) if model.geom(g).name.startswith("shelf_")], dtype=int
    )
    d.qpos[:] = qpos
    mujoco.mj_kinematics(model, d)
    base_geoms = [g for g in robot if not _arm_or_payload(model, g, arm)]
    front = max(float(geom_world_aabb(model, d, g)[1][0]) for g in base_geoms) - float(d.qpos[0])
    return Scene(
        model,
        arm,
        chain,
        chassis,
        probe,
        wheel_act,
        arm_act,
        tool,
        robot,
        shelf_geoms,
        qpos,
        {"front_extent": front},
    )


def geom_world_aabb(model: mujoco.MjModel, data: mujoco.MjData, g: int) -> tuple[np.ndarray, np.ndarray]:
    """World axis-aligned bounding box (min, max) of geom ``g`` from its local AABB [m]."""
    c, h = model.geom_aabb[g][:3], model.geom_aabb[g][3:]
    corners = c + h * np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    rot = data.geom_xmat[g].reshape(3, 3)
    pts = data.geom_xpos[g] + corners @ rot.T
    return pts.min(axis=0), pts.max(axis=0)


def _arm_or_payload(model: mujoco.MjModel, g: int, arm: str | None) -> bool:
    name = model.body(model.geom_bodyid[g]).name
    return bool(arm) and name.startswith(f"{arm}/") or name.startswith("payload/")


def _as_slice(index: np.ndarray) -> slice | np.ndarray:
    """``index`` as a slice when it is a run of consecutive integers (a view instead of a copy)."""
    index = np.asarray(index)
    if index.size and np.array_equal(index, np.arange(index[0], index[0] + index.size)):
        return slice(int(index[0]), int(index[0]) + index.size)
    return index


def hold_torque(
    scene: Scene,
    data: mujoco.MjData,
    q_des: np.ndarray,
    qd_des: np.ndarray | None = None,
    omega: float = 20.0,
) -> np.ndarray:
    """Verifier arm controller: computed torque, bias (gravity, Coriolis) + M_arm (kp e + kd e_dot) with
    critically damped decoupled joints at natural frequency ``omega`` [rad/s], clipped to the limits [N m]."""
    ch = scene.chain
    m = scene.model
    cache = scene.extra.get("_hold")
    if cache is None:
        cache = scene.extra["_hold"] = (
            np.zeros((m.nv, m.nv)),
            np.ix_(ch.dof_adr, ch.dof_adr),
            *m.actuator_ctrlrange[scene.arm_act].T,
            _as_slice(ch.qpos_adr),
            _as_slice(ch.dof_adr),
        )
    full, block, lo, hi, qpos_at, dof_at = cache
    q = data.qpos[qpos_at]
    qd = data.qvel[dof_at]
    mujoco.mj_fullM(m, data, full)
    err = omega**2 * (q_des - q) + 2.0 * omega * ((0.0 if qd_des is None else qd_des) - qd)
    tau = data.qfrc_bias[dof_at] + full[block] @ err
    return np.minimum(np.maximum(tau, lo), hi)  # np.clip without its dispatch (called every physics step)
