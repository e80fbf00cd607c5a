"""The private scene: table, Panda with a stick tool, three mocap blocks, the oblique camera.

Built with ``MjSpec`` from the toolkit: the canonical Panda (robosuite asset, ``load_robot``) with a
stick instead of its hand, rendered with its collision hulls (the visual meshes hold 127 k faces and
cap 240x320 rendering near 32 frames/s on two cores). The blocks are mocap bodies: a frame places
one block on the table and parks the others under it; push episodes are kinematic (the block follows
a quasi-static pushing path, the stick tip is placed behind it by inverse kinematics).

World frame: table top at z = 0, x away from the robot base, z up [m].
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.scene import PANDA, CameraConfig, element_id, load_robot
from rle_design.scene.attach import attach
from rle_design.scene.site import SiteConfig
from rle_design.sensors import CameraSpec, camera_spec

from .shapes import BLOCKS, HEIGHT

CAMERA = "pose_cam"
"""Name of the oblique sensor camera."""
WIDTH, HEIGHT_PX = 320, 240
"""Image size [px]."""
CAMERA_POS = (0.48, -0.45, 0.5)
"""Camera position [m]."""
CAMERA_TARGET = (0.0, 0.0, 0.0)
"""Point the camera aims at [m]."""
FOVY_DEG = 34.0
"""Vertical field of view [deg]."""
ROBOT_BASE = (-0.5, 0.0, 0.0)
"""Panda base position on the table [m]."""
STICK_LENGTH = 0.2
"""Stick length below the flange [m]."""
STICK_RADIUS = 0.008
"""Stick radius [m]."""
TIP_HEIGHT = 0.012
"""Height of the stick tip above the table while pushing [m]."""
PARK_Z = -1.0
"""Height at which unused blocks are parked (under the table) [m]."""
TABLE_HALF = (0.9, 0.7, 0.02)
"""Table half sizes [m]."""
BLOCK_RGBA = (0.8, 0.08, 0.06, 1.0)
"""Nominal block colour."""
TABLE_RGBA = (0.85, 0.82, 0.76, 1.0)
"""Nominal table tint (multiplies the checker texture)."""
PANDA_TOOL_BODY = "right_hand"
"""Flange body of the robosuite Panda (its z axis points out of the flange)."""


def build_spec() -> mujoco.MjSpec:
    """The private scene as an ``MjSpec`` (uncompiled)."""
    spec = mujoco.MjSpec()
    spec.visual.global_.offwidth = WIDTH
    spec.visual.global_.offheight = HEIGHT_PX
    spec.visual.headlight.ambient = [0.3, 0.3, 0.3]
    spec.visual.headlight.diffuse = [0.6, 0.6, 0.6]
    spec.add_texture(
        name="table_tex",
        type=mujoco.mjtTexture.mjTEXTURE_2D,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
        rgb1=[0.8, 0.8, 0.8],
        rgb2=[0.65, 0.65, 0.65],
        width=256,
        height=256,
    )
    mat = spec.add_material(name="table_mat", rgba=list(TABLE_RGBA), texrepeat=[8, 8])
    mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = "table_tex"
    world = spec.worldbody
    world.add_geom(
        name="table",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=list(TABLE_HALF),
        pos=[0.0, 0.0, -TABLE_HALF[2]],
        material="table_mat",
    )
    world.add_light(name="key", pos=[0.3, -0.3, 1.5], dir=[0.0, 0.0, -1.0], diffuse=[0.4, 0.4, 0.4])
    for i, block in enumerate(BLOCKS):
        body = world.add_body(name=f"block_{block.name}", mocap=True, pos=[0.0, 0.0, PARK_Z - i])
        for j, (cx, cy, hx, hy) in enumerate(block.boxes_in_frame()):
            body.add_geom(
                name=f"block_{block.name}_{j}",
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=[hx, hy, HEIGHT / 2],
                pos=[cx, cy, HEIGHT / 2],
                rgba=list(BLOCK_RGBA),
                contype=0,
                conaffinity=0,
            )
    SiteConfig(name="robot_mount", body="world", pos=ROBOT_BASE).edit_spec(spec)
    robot = _stick_panda()
    attach(spec, robot, "robot_mount", "panda/", body=PANDA.root_body)
    CameraConfig(name=CAMERA, pos=CAMERA_POS, look_at=CAMERA_TARGET, fovy_deg=FOVY_DEG).edit_spec(spec)
    spec.camera(CAMERA).resolution = [WIDTH, HEIGHT_PX]
    return spec


def _stick_panda() -> mujoco.MjSpec:
    """Panda with collision hulls as its visible geometry and a stick on the flange."""
    robot = load_robot("panda")
    for geom in list(robot.geoms):
        if geom.group == 1:  # visual meshes
            robot.delete(geom)
    for geom in robot.geoms:
        geom.rgba = [0.92, 0.92, 0.92, 1.0]
        geom.contype = 0
        geom.conaffinity = 0
    hand = robot.body(PANDA_TOOL_BODY)
    hand.add_geom(
        name="stick",
        type=mujoco.mjtGeom.mjGEOM_CAPSULE,
        fromto=[0.0, 0.0, 0.0, 0.0, 0.0, STICK_LENGTH],
        size=[STICK_RADIUS, 0, 0],
        rgba=[0.15, 0.15, 0.18, 1.0],
        contype=0,
        conaffinity=0,
    )
    hand.add_site(name="stick_tip", pos=[0.0, 0.0, STICK_LENGTH + STICK_RADIUS])
    return robot


@dataclass(frozen=True)
class BlockPose:
    """Planar pose and shape of the block.

    Attributes:
        x: Frame origin x [m].
        y: Frame origin y [m].
        theta: Rotation about world z [rad], wrapped to [-pi, pi).
        shape: Shape id (0 T, 1 C, 2 F).
    """

    x: float
    y: float
    theta: float
    shape: int

    def as_array(self) -> np.ndarray:
        return np.array([self.x, self.y, self.theta, float(self.shape)])


class PoseScene:
    """Compiled scene with setters for the block pose and the stick tip.

    Args:
        model: Compiled model of ``build_spec`` (possibly perturbed by an appearance variation).
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.data = mujoco.MjData(model)
        self._mocap = [int(model.body_mocapid[element_id(model, "body", f"block_{b.name}")]) for b in BLOCKS]
        self._tip = element_id(model, "site", "panda/stick_tip")
        joints = [element_id(model, "joint", f"panda/{j}") for j in PANDA.joints]
        self._qadr = np.array([model.jnt_qposadr[j] for j in joints])
        self._dadr = np.array([model.jnt_dofadr[j] for j in joints])
        self._lo = model.jnt_range[joints, 0]
        self._hi = model.jnt_range[joints, 1]
        self.home = np.array(PANDA.home)
        self.data.qpos[self._qadr] = self.home
        self.camera_id = element_id(model, "camera", CAMERA)

    def set_block(self, pose: BlockPose) -> None:
        """Place block ``pose.shape`` at the pose; park the others under the table."""
        for i, mid in enumerate(self._mocap):
            if i == pose.shape:
                self.data.mocap_pos[mid] = (pose.x, pose.y, 0.0)
                self.data.mocap_quat[mid] = (np.cos(pose.theta / 2), 0.0, 0.0, np.sin(pose.theta / 2))
            else:
                self.data.mocap_pos[mid] = (0.0, 0.0, PARK_Z - i)

    def set_arm(self, q: np.ndarray) -> None:
        """Joint positions of the arm [rad]."""
        self.data.qpos[self._qadr] = q

    def arm(self) -> np.ndarray:
        return self.data.qpos[self._qadr].copy()

    def reach(self, tip: np.ndarray, iters: int = 60) -> float:
        """Move the stick tip to ``tip`` [m] with the stick vertical (damped least squares, warm start,
        null-space pull towards the home posture).

        Returns:
            Remaining tip position error [m].
        """
        m, d = self.model, self.data
        jp = np.zeros((3, m.nv))
        jr = np.zeros((3, m.nv))
        err = np.inf
        for _ in range(iters):
            mujoco.mj_kinematics(m, d)
            mujoco.mj_comPos(m, d)
            pos = d.site_xpos[self._tip]
            axis = d.site_xmat[self._tip].reshape(3, 3)[:, 2]
            e_pos = np.asarray(tip) - pos
            e_rot = np.cross(axis, np.array([0.0, 0.0, -1.0]))
            err = float(np.linalg.norm(e_pos))
            if err < 2e-4 and np.linalg.norm(e_rot) < 1e-3:
                break
            mujoco.mj_jacSite(m, d, jp, jr, self._tip)
            jac = np.vstack([jp[:, self._dadr], 0.3 * jr[:, self._dadr]])
            e = np.concatenate([e_pos, 0.3 * e_rot])
            pinv = jac.T @ np.linalg.inv(jac @ jac.T + 1e-4 * np.eye(6))
            dq = pinv @ e + (np.eye(len(self._qadr)) - pinv @ jac) @ (0.1 * (self.home - d.qpos[self._qadr]))
            q = np.clip(d.qpos[self._qadr] + np.clip(dq, -0.3, 0.3), self._lo, self._hi)
            d.qpos[self._qadr] = q
        return err

    def forward(self) -> None:
        """Kinematics and camera poses for rendering."""
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_camlight(self.model, self.data)

    def camera(self) -> CameraSpec:
        """Published calibration of the sensor camera."""
        self.forward()
        return camera_spec(self.model, self.data, CAMERA, WIDTH, HEIGHT_PX)


def compile_scene() -> mujoco.MjModel:
    """The nominal compiled scene."""
    return build_spec().compile()


CALIBRATION_FILE = "calibration.json"
"""The published calibration in ``assets/`` (laid into every workspace)."""


def published_calibration() -> dict:
    """Image size, ``K`` [px] and ``T_world_cam`` (OpenCV camera to world) [m] of the sensor camera."""
    cam = PoseScene(compile_scene()).camera()
    return {
        "width": WIDTH,
        "height": HEIGHT_PX,
        "K": np.round(cam.intrinsics.matrix, 9).tolist(),
        "T_world_cam": np.round(cam.world_from_camera, 9).tolist(),
        "units": "K in pixels (OpenCV: pixel centres at integers); T_world_cam in metres",
    }
