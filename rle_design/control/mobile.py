"""``MobileManipulatorEnv``: a mobile Panda (``rle_design.scene.mobile_panda``) driven by 12-D actions.

One action is the kitchen layout of ``rle_design.control.layout`` (values clipped to [-1, 1]):

| index | arm mode (``a[11] <= 0``) | base mode (``a[11] > 0``) |
|---|---|---|
| 0-5 | tool delta pose in the base frame (x ``POS_STEP`` m, x ``ROT_STEP`` rad) | ignored (the arm holds its pose on the base) |
| 6 | gripper (-1 open, +1 closed) | gripper |
| 7-9 | ignored (the base stands) | base velocity: forward, left [x ``base_speed`` m/s], yaw [x ``yaw_speed`` rad/s] |
| 10 | torso: height target moves by ``a x TORSO_STEP`` m | torso |

The arm's operational-space target is kept in the frame of the arm's root body (on the torso, on
the base), in ``MjData.userdata`` (position [m], then quaternion w, x, y, z), so the arm travels with
the base and the torso, and resets and replays restore it. Every physics step the target is mapped
to the world and the operational-space controller (the tabletop's) computes the arm torques; the base
velocity servos receive the commanded base-frame velocity rotated into the mount frame of the base
joints. ``n_substeps`` = 25 at a 2 ms step: 20 Hz control, as in RoboCasa.

Observation (free): ``time`` [s]; ``base_pos`` [m] and ``base_yaw`` [rad] of the base in the world;
``torso`` [m]; ``q``/``dq`` (7) [rad, rad/s]; ``ee_pos``/``ee_quat`` of the tool site in the world and
``ee_pos_base``/``ee_quat_base`` in the base frame; ``target_pos_base``/``target_quat_base``, the
controller's target in the base frame; ``gripper`` finger opening [m] (0..0.08); ``rgb``:
camera -> (H, W, 3) uint8 and ``depth``: camera -> (H, W) float32 metric depth [m] of the three cameras
(when ``image_size`` is set).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from rle_design.control.env import LEASH, portable_digest
from rle_design.control.layout import ACTION_SIZE, ARM, BASE, GRIPPER, MODE, POS_STEP, ROT_STEP, TORSO
from rle_design.control.osc import OperationalSpaceController, OscGains
from rle_design.ledger.session import MeteredEnv
from rle_design.scene.mobile_panda import TORSO_RANGE, MobilePandaNames
from rle_design.scene.robots import PANDA

__all__ = ["MobileManipulatorEnv", "TORSO_STEP"]

TORSO_STEP = 0.01
"""Torso height change of a full-scale torso action, per action [m]."""
OSC_REFRESH = 5
"""Physics steps between recomputations of the controller's Jacobian and inertias (10 ms)."""
FINGER_MAX = 0.04
"""Travel of one finger [m]."""
TARGET_SIZE = 7
"""``userdata`` entries holding the arm target (position, quaternion)."""


class _Robot:
    """Ids of one compiled model's robot (cached per model)."""

    def __init__(self, model: mujoco.MjModel, names: MobilePandaNames, gains: OscGains) -> None:
        self.osc = OperationalSpaceController(
            model, names.tool_site, names.joints, names.motors, PANDA.home, gains
        )
        self.fingers = np.array([model.actuator(f).id for f in names.fingers])
        self.finger_q = np.array([model.jnt_qposadr[model.actuator_trnid[a, 0]] for a in self.fingers])
        self.base_act = np.array([model.actuator(a).id for a in names.base_actuators])
        self.base_q = np.array([model.jnt_qposadr[model.joint(j).id] for j in names.base_joints])
        self.torso_act = model.actuator(names.torso_actuator).id
        self.torso_q = model.jnt_qposadr[model.joint(names.torso_joint).id]
        self.base = model.body(names.base_body).id
        self.arm_root = model.body(names.arm_base).id
        self.cameras = names.cameras
        if model.nuserdata < TARGET_SIZE:
            raise ValueError(
                f"the model needs nuserdata >= {TARGET_SIZE} for the arm target, has {model.nuserdata}"
            )


@functools.lru_cache(maxsize=32)
def _robot(model: mujoco.MjModel, names: MobilePandaNames, gains: OscGains) -> _Robot:
    return _Robot(model, names, gains)


def _frame(data: mujoco.MjData, body: int) -> tuple[np.ndarray, np.ndarray]:
    return data.xpos[body], data.xmat[body].reshape(3, 3)


@dataclass(frozen=True)
class MobileManipulatorEnv(MeteredEnv):
    """The mobile Panda in a scene (see the module docstring).

    Attributes:
        names: Element names of the robot.
        gains: Operational-space gains.
        image_size: (height, width) of the camera images [px]; None renders none.
        base_speed: Base translation speed of a full-scale base action [m/s].
        yaw_speed: Base turn rate of a full-scale base action [rad/s].
        box_quads: The cameras' ``RgbdSensor.box_quads``: 1 draws a box face as one quad (a scene built
            of boxes renders about 20 % faster on the CPU; geometry, depth and segmentation unchanged).
    """

    n_substeps: int = 25
    keyframe: str | None = "initial"
    names: MobilePandaNames = MobilePandaNames()
    gains: OscGains = OscGains()
    image_size: tuple[int, int] | None = (128, 128)
    base_speed: float = 0.5
    yaw_speed: float = 1.0
    box_quads: int | None = 1

    def _robot(self, model: mujoco.MjModel) -> _Robot:
        return _robot(model, self.names, self.gains)

    def fingerprint(self) -> str:
        """Digest of the scene independent of where its mesh files are installed [hex]."""
        return portable_digest(self.xml)

    def prepare(self, model: mujoco.MjModel) -> None:
        super().prepare(model)
        self._robot(model)

    def action_size(self, model: mujoco.MjModel) -> int:
        return ACTION_SIZE

    def action_range(self, model: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray]:
        """Every entry of the layout lies in [-1, 1] (``step`` clips to it)."""
        size = self.action_size(model)
        return np.full(size, -1.0), np.full(size, 1.0)

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        super().reset(model, data)
        self.hold_pose(model, data)

    def hold_pose(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Set the arm target to the tool site's current pose (in the arm root's frame)."""
        r = self._robot(model)
        pos, rot = _frame(data, r.arm_root)
        data.userdata[:3] = rot.T @ (data.site_xpos[r.osc.site] - pos)
        mat = rot.T @ data.site_xmat[r.osc.site].reshape(3, 3)
        mujoco.mju_mat2Quat(data.userdata[3:7], mat.reshape(-1))

    def target_world(self, model: mujoco.MjModel, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        """The arm target in the world: (position [m], quaternion w, x, y, z)."""
        r = self._robot(model)
        pos, rot = _frame(data, r.arm_root)
        root_quat = np.zeros(4)
        mujoco.mju_mat2Quat(root_quat, data.xmat[r.arm_root])
        quat = np.zeros(4)
        mujoco.mju_mulQuat(quat, root_quat, data.userdata[3:7])
        return pos + rot @ data.userdata[:3], quat

    def step(self, model: mujoco.MjModel, data: mujoco.MjData, ctrl: np.ndarray) -> None:
        act = np.clip(np.nan_to_num(np.asarray(ctrl, dtype=float)), -1.0, 1.0)
        r = self._robot(model)
        base_mode = act[MODE] > 0
        if not base_mode:
            d_pos = act[ARM][:3] * POS_STEP
            d_rot = act[ARM][3:] * ROT_STEP
            target = data.userdata[:3] + d_pos
            _, rot = _frame(data, r.arm_root)
            ee = rot.T @ (data.site_xpos[r.osc.site] - data.xpos[r.arm_root])
            data.userdata[:3] = ee + np.clip(target - ee, -LEASH, LEASH)
            angle = float(np.linalg.norm(d_rot))
            if angle > 0:
                dq = np.zeros(4)
                mujoco.mju_axisAngle2Quat(dq, d_rot / angle, angle)
                quat = np.zeros(4)
                mujoco.mju_mulQuat(quat, dq, data.userdata[3:7].copy())
                mujoco.mju_normalize4(quat)
                data.userdata[3:7] = quat
        opening = FINGER_MAX * (1.0 - act[GRIPPER]) / 2.0
        data.ctrl[r.fingers] = (opening, -opening)
        torso = data.ctrl[r.torso_act] + act[TORSO] * TORSO_STEP
        data.ctrl[r.torso_act] = np.clip(torso, *TORSO_RANGE)
        cmd = (
            act[BASE] * np.array([self.base_speed, self.base_speed, self.yaw_speed])
            if base_mode
            else np.zeros(3)
        )
        for k in range(self.n_substeps):
            mujoco.mj_step1(model, data)
            yaw = data.qpos[r.base_q[2]]
            c, s = np.cos(yaw), np.sin(yaw)
            data.ctrl[r.base_act] = (c * cmd[0] - s * cmd[1], s * cmd[0] + c * cmd[1], cmd[2])
            pos, quat = self.target_world(model, data)
            r.osc.apply(data, pos, quat, k % OSC_REFRESH == 0)
            self.substep(model, data, k)
            mujoco.mj_step2(model, data)
        mujoco.mj_forward(model, data)

    def substep(self, model: mujoco.MjModel, data: mujoco.MjData, k: int) -> None:
        """Hook of physics step ``k`` of an action (after the controller, before ``mj_step2``)."""

    observation_doc = (
        "time, base_pos, base_yaw, torso, q, dq, ee_pos, ee_quat, ee_pos_base, ee_quat_base, target_pos_base, "
        "target_quat_base, gripper, rgb and depth (per camera)"
    )

    def proprioception(self, model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
        """The robot's own state (see the module docstring)."""
        r = self._robot(model)
        pos, quat = r.osc.site_pose(data)
        bpos, brot = _frame(data, r.base)
        local = np.zeros(4)
        mujoco.mju_mat2Quat(local, (brot.T @ data.site_xmat[r.osc.site].reshape(3, 3)).reshape(-1))
        return {
            "time": float(data.time),
            "base_pos": bpos.copy(),
            "base_yaw": float(np.arctan2(brot[1, 0], brot[0, 0])),
            "torso": float(data.qpos[r.torso_q]),
            "q": data.qpos[r.osc.qadr].copy(),
            "dq": data.qvel[r.osc.dof].copy(),
            "ee_pos": pos,
            "ee_quat": quat,
            "ee_pos_base": brot.T @ (pos - bpos),
            "ee_quat_base": local,
            "gripper": float(data.qpos[r.finger_q[0]] - data.qpos[r.finger_q[1]]),
            "target_pos_base": brot.T @ (data.xpos[r.arm_root] - bpos) + data.userdata[:3],
            "target_quat_base": data.userdata[3:7].copy(),
        }

    def observe(self, model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
        obs = self.proprioception(model, data)
        if self.image_size is not None:
            from rle_design.control.cameras import render_rgbd

            obs["rgb"], obs["depth"] = render_rgbd(
                model, data, self._robot(model).cameras, self.image_size, self.box_quads
            )
        for name, fn in self.observers:
            obs[name] = fn(model, data)
        return obs
