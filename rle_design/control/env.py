"""``TabletopEnv``: the tabletop scene driven by 12-D actions through operational-space control.

A ``rle_design.ledger.MeteredEnv`` (one MJCF string built by ``rle_design.scene.tabletop``), so
``MeteredSession`` / ``rle dev`` serve it with one charged step per reset and per executed action
and the verifier can replay a ledger's actions on the same definition (``replay``). Everything the
controller keeps between actions (the target poses) lives in ``MjData`` (mocap bodies), so a reset
or a replay restores it exactly.

One action (``layout``): per arm ``arm_action_size`` numbers in [-1, 1] (12, the kitchen layout; 7 keeps
only the pose delta and the gripper, e.g. the 14-D two-arm cube task); each action moves the arm's target
by the scaled delta (the target is kept within ``LEASH`` of the tool site so contact cannot wind it up),
sets the gripper, then ``n_substeps`` physics steps run, the torques recomputed every step
(``OperationalSpaceController``, its matrices refreshed every ``OSC_REFRESH`` steps; ``mj_step1``/
``mj_step2`` so they use the current state). A subclass adds internal forces of its scene (e.g. a
mechanism's couples) in ``substep``, called every physics step between the controller and ``mj_step2``.

Observation (free): ``time`` [s]; ``arms``: one dict per arm with ``q``, ``dq`` (7) [rad, rad/s],
``ee_pos`` [m] / ``ee_quat`` (w, x, y, z) of the tool site, ``target_pos`` / ``target_quat``,
``gripper`` (finger opening [m], 0..0.08), ``base_pos`` [m] / ``base_quat``; ``rgb``: dict camera ->
(H, W, 3) uint8, rendered after a reset and every ``camera_every`` actions (absent otherwise and
when ``image_size`` is None); ``bodies`` (only when ``privileged``): free body -> (x, y, z, qw, qx,
qy, qz) [m] and ``sizes``: free body -> its first geom's size (box half extents) [m]. Privileged observations exist for reference programs and tests; agents get
``privileged=False``.
"""

from __future__ import annotations

import functools
import hashlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from rle_design.control.layout import ACTION_SIZE, ARM, GRIPPER, POS_STEP, ROT_STEP
from rle_design.control.osc import OperationalSpaceController, OscGains
from rle_design.ledger import MeteredEnv
from rle_design.scene.robots import PANDA
from rle_design.scene.tabletop import INITIAL_KEY, ArmNames

__all__ = ["LEASH", "TabletopEnv", "portable_digest"]

LEASH = 0.08
"""Largest distance between an arm's target and its tool site [m]."""
OSC_REFRESH = 5
"""Physics steps between recomputations of the controller's Jacobian and inertias (10 ms)."""
FINGER_MAX = 0.04
"""Travel of one finger [m]."""


class _Arm:
    def __init__(self, model: mujoco.MjModel, prefix: str, gains: OscGains) -> None:
        names = ArmNames(prefix)
        self.osc = OperationalSpaceController(
            model, names.tool_site, names.joints, names.motors, PANDA.home, gains
        )
        self.fingers = np.array([model.actuator(f).id for f in names.fingers])
        self.finger_q = np.array([model.jnt_qposadr[model.actuator_trnid[a, 0]] for a in self.fingers])
        self.mocap = model.body(names.target).mocapid[0]
        self.base = model.body(names.base).id


_ARMS: dict[int, tuple[mujoco.MjModel, tuple[_Arm, ...]]] = {}


@dataclass(frozen=True)
class TabletopEnv(MeteredEnv):
    """The tabletop (see the module docstring).

    Attributes:
        arms: Prefixes of the arms, in action order.
        keyframe: Keyframe a reset restores (``finish`` writes ``"initial"``).
        gains: Operational-space gains.
        cameras: Cameras rendered into ``rgb``.
        image_size: (height, width) of the RGB images [px]; None renders none.
        camera_every: Render every this many actions (and after every reset).
        privileged: Add the free bodies' poses to the observation (reference programs, tests).
        arm_action_size: Numbers per arm in an action: 12 (``layout``) or 7 (pose delta and gripper
            only; indices 0-6 keep their meaning).
    """

    arms: tuple[str, ...] = ("panda/",)
    keyframe: str | None = INITIAL_KEY
    gains: OscGains = OscGains()
    cameras: tuple[str, ...] = ("front", "side", "top")
    image_size: tuple[int, int] | None = (120, 160)
    camera_every: int = 10
    privileged: bool = False
    arm_action_size: int = ACTION_SIZE

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.arm_action_size not in (GRIPPER + 1, ACTION_SIZE):
            raise ValueError(
                f"TabletopEnv.arm_action_size must be {GRIPPER + 1} or {ACTION_SIZE}, got {self.arm_action_size}"
            )

    def fingerprint(self) -> str:
        """Digest of the scene that does not depend on where the mesh files are installed [hex].

        Each mesh file reference is replaced by the SHA-256 of the file's bytes before hashing the
        MJCF, so the same scene recorded on one checkout replays on another.
        """
        return portable_digest(self.xml)

    def _arm_ctl(self, model: mujoco.MjModel) -> tuple[_Arm, ...]:
        entry = _ARMS.get(id(model))
        if entry is None or entry[0] is not model:
            if len(_ARMS) > 16:
                _ARMS.clear()
            entry = _ARMS[id(model)] = (model, tuple(_Arm(model, p, self.gains) for p in self.arms))
        return entry[1]

    def prepare(self, model: mujoco.MjModel) -> None:
        super().prepare(model)
        self._arm_ctl(model)

    def action_size(self, model: mujoco.MjModel) -> int:
        return self.arm_action_size * len(self.arms)

    def action_range(self, model: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray]:
        """Every entry of the layout lies in [-1, 1] (``step`` clips to it)."""
        size = self.action_size(model)
        return np.full(size, -1.0), np.full(size, 1.0)

    def step(self, model: mujoco.MjModel, data: mujoco.MjData, ctrl: np.ndarray) -> None:
        act = np.clip(np.nan_to_num(np.asarray(ctrl, dtype=float)), -1.0, 1.0)
        arms = self._arm_ctl(model)
        n = self.arm_action_size
        for i, arm in enumerate(arms):
            a = act[n * i : n * (i + 1)]
            rot = data.xmat[arm.base].reshape(3, 3)
            d_pos = rot @ (a[ARM][:3] * POS_STEP)
            d_rot = rot @ (a[ARM][3:] * ROT_STEP)
            ee = data.site_xpos[arm.osc.site]
            target = data.mocap_pos[arm.mocap] + d_pos
            data.mocap_pos[arm.mocap] = ee + np.clip(target - ee, -LEASH, LEASH)
            dq = np.zeros(4)
            mujoco.mju_axisAngle2Quat(dq, d_rot / max(np.linalg.norm(d_rot), 1e-12), np.linalg.norm(d_rot))
            quat = np.zeros(4)
            mujoco.mju_mulQuat(quat, dq, data.mocap_quat[arm.mocap].copy())
            mujoco.mju_normalize4(quat)
            data.mocap_quat[arm.mocap] = quat
            opening = FINGER_MAX * (1.0 - a[GRIPPER]) / 2.0
            data.ctrl[arm.fingers] = (opening, -opening)
        for k in range(self.n_substeps):
            mujoco.mj_step1(model, data)
            for arm in arms:
                arm.osc.apply(
                    data, data.mocap_pos[arm.mocap], data.mocap_quat[arm.mocap], k % OSC_REFRESH == 0
                )
            self.substep(model, data, k)
            mujoco.mj_step2(model, data)
        mujoco.mj_forward(model, data)

    def substep(self, model: mujoco.MjModel, data: mujoco.MjData, k: int) -> None:
        """Hook of physics step ``k`` of an action, after ``mj_step1`` and the controller, before
        ``mj_step2`` (positions current): add the scene's internal forces here. Nothing by default."""

    observation_doc = (
        "time, arms (per arm: q, dq, ee_pos, ee_quat, target_pos, target_quat, gripper, base_pos, "
        "base_quat), rgb (per camera)"
    )

    def observe(self, model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
        obs: dict[str, Any] = {"time": float(data.time), "arms": []}
        for arm in self._arm_ctl(model):
            pos, quat = arm.osc.site_pose(data)
            base_quat = np.zeros(4)
            mujoco.mju_mat2Quat(base_quat, data.xmat[arm.base])
            obs["arms"].append(
                {
                    "q": data.qpos[arm.osc.qadr].copy(),
                    "dq": data.qvel[arm.osc.dof].copy(),
                    "ee_pos": pos,
                    "ee_quat": quat,
                    "target_pos": data.mocap_pos[arm.mocap].copy(),
                    "target_quat": data.mocap_quat[arm.mocap].copy(),
                    "gripper": float(data.qpos[arm.finger_q[0]] - data.qpos[arm.finger_q[1]]),
                    # the gripper command last sent (-1 open ... +1 closed), as the action gives it
                    "gripper_command": float(
                        np.clip(1.0 - 2.0 * data.ctrl[arm.fingers[0]] / FINGER_MAX, -1, 1)
                    ),
                    "base_pos": data.xpos[arm.base].copy(),
                    "base_quat": base_quat,
                }
            )
        period = self.n_substeps * model.opt.timestep
        tick = int(round(data.time / period))
        if self.image_size is not None and tick % self.camera_every == 0:
            from rle_design.control.cameras import render_rgb

            obs["rgb"] = render_rgb(model, data, self.cameras, self.image_size)
        if self.privileged:
            obs["bodies"] = free_body_poses(model, data)
            obs["sizes"] = {
                name: model.geom_size[model.body(name).geomadr[0]].copy() for name in obs["bodies"]
            }
        for name, fn in self.observers:
            obs[name] = fn(model, data)
        return obs


@functools.lru_cache(maxsize=32)
def portable_digest(xml: str) -> str:
    """SHA-256 of an MJCF string with every mesh, texture, height-field and skin file reference replaced
    by the SHA-256 of the file's bytes, so a scene digests alike wherever its assets are installed [hex]."""
    from lxml import etree

    root = etree.fromstring(xml.encode())
    for el in root.iter("mesh", "texture", "hfield", "skin"):
        file = el.get("file")
        if file:
            el.set("file", hashlib.sha256(Path(file).read_bytes()).hexdigest())
    return hashlib.sha256(etree.tostring(root)).hexdigest()


def free_body_poses(model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, np.ndarray]:
    """Free body name -> (x, y, z, qw, qx, qy, qz) from its free joint's qpos [m]."""
    out = {}
    for j in range(model.njnt):
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
            adr = model.jnt_qposadr[j]
            out[model.body(model.jnt_bodyid[j]).name] = data.qpos[adr : adr + 7].copy()
    return out
