"""Pinhole camera model of a MuJoCo camera: intrinsics, extrinsics, projection and back-projection.

Conventions:
    * Pixels follow OpenCV: ``u`` is the column, ``v`` the row, the image origin is the top-left
      corner and pixel ``(u, v)`` has its centre at integer coordinates, so ``cx = (W - 1) / 2`` for a
      centred principal point and ``depth[v, u]`` is the depth at pixel ``(u, v)``.
    * The camera frame follows OpenCV: +x right, +y down, +z forward (optical axis). MuJoCo's camera
      frame is +x right, +y up, looking along -z, so ``R_cv = R_mj @ diag(1, -1, -1)``.
    * ``world_from_camera`` is the 4x4 transform taking OpenCV camera coordinates to world
      coordinates [m]; its inverse is the usual extrinsic matrix ``[R | t]``.
    * MuJoCo renders with a vertical field of view ``fovy`` and square pixels:
      ``fy = (H / 2) / tan(fovy / 2)`` and ``fx = fy``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.errors import MissingElement, RleError
from rle_design.scene.elements import element_id

MJ_TO_CV = np.diag([1.0, -1.0, -1.0])
"""Rotation from MuJoCo's camera frame (-z forward, +y up) to OpenCV's (+z forward, +y down)."""


@dataclass(frozen=True)
class CameraIntrinsics:
    """Pinhole intrinsics in pixels (OpenCV convention, pixel centres at integers).

    Attributes:
        width: Image width [px].
        height: Image height [px].
        fx: Horizontal focal length [px].
        fy: Vertical focal length [px].
        cx: Principal point column [px].
        cy: Principal point row [px].
    """

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    @classmethod
    def from_fovy(cls, fovy_deg: float, width: int, height: int) -> CameraIntrinsics:
        """Intrinsics of MuJoCo's perspective camera with vertical field of view ``fovy_deg`` [deg]."""
        if not 0.0 < fovy_deg < 180.0:
            raise RleError(f"fovy must lie in (0, 180) degrees, got {fovy_deg}", code="camera.fovy")
        if width < 1 or height < 1:
            raise RleError(f"image size must be positive, got {width}x{height}", code="camera.size")
        fy = 0.5 * height / math.tan(math.radians(fovy_deg) / 2.0)
        return cls(int(width), int(height), fy, fy, (width - 1) / 2.0, (height - 1) / 2.0)

    @property
    def matrix(self) -> np.ndarray:
        """The 3x3 camera matrix K."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])


def camera_id(model: mujoco.MjModel, camera: str | int) -> int:
    """Id of a named (or numbered) camera; raises ``MissingElement`` listing the model's cameras."""
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_CAMERA, i) or f"#{i}" for i in range(model.ncam)]
    if isinstance(camera, str):
        return element_id(model, "camera", camera)
    if not 0 <= int(camera) < model.ncam:
        raise MissingElement("camera", f"#{camera}", available=names)
    return int(camera)


def camera_intrinsics(
    model: mujoco.MjModel, camera: str | int, width: int | None = None, height: int | None = None
) -> CameraIntrinsics:
    """Intrinsics of an MJCF camera.

    Args:
        model: Compiled model.
        camera: Camera name or id.
        width: Image width [px]; defaults to the camera's ``resolution`` attribute.
        height: Image height [px]; defaults to the camera's ``resolution`` attribute.

    Raises:
        RleError: The camera is orthographic or declares ``sensorsize``/``focal`` intrinsics (only
            ``fovy`` cameras are modelled).
    """
    cid = camera_id(model, camera)
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_CAMERA, cid) or f"#{cid}"
    if int(model.cam_projection[cid]) != int(mujoco.mjtProjection.mjPROJ_PERSPECTIVE):
        raise RleError(
            f"camera '{name}' is orthographic; only perspective cameras are modelled", code="camera.kind"
        )
    if np.any(model.cam_sensorsize[cid] > 0):
        raise RleError(
            f"camera '{name}' uses sensorsize/focal intrinsics; give it a fovy instead", code="camera.kind"
        )
    res = model.cam_resolution[cid]
    w = int(width if width is not None else res[0])
    h = int(height if height is not None else res[1])
    return CameraIntrinsics.from_fovy(float(model.cam_fovy[cid]), w, h)


@dataclass(frozen=True)
class CameraSpec:
    """A camera's intrinsics and its pose at one instant.

    Attributes:
        name: Camera name in the model.
        id: Camera id in the model.
        intrinsics: Pinhole intrinsics.
        world_from_camera: 4x4 transform from OpenCV camera coordinates to world coordinates [m].
        near: Near clipping distance of the renderer [m].
        far: Far clipping distance of the renderer [m].
    """

    name: str
    id: int
    intrinsics: CameraIntrinsics
    world_from_camera: np.ndarray
    near: float
    far: float

    @property
    def camera_from_world(self) -> np.ndarray:
        """4x4 extrinsic matrix taking world coordinates to OpenCV camera coordinates."""
        rot = self.world_from_camera[:3, :3]
        out = np.eye(4)
        out[:3, :3] = rot.T
        out[:3, 3] = -rot.T @ self.world_from_camera[:3, 3]
        return out

    def to_camera(self, points_world: np.ndarray) -> np.ndarray:
        """World points [m] in OpenCV camera coordinates [m]; column 2 is the planar depth.

        Args:
            points_world: ``(N, 3)`` or ``(3,)`` world coordinates [m].

        Returns:
            ``(N, 3)`` camera coordinates.
        """
        pts = np.atleast_2d(np.asarray(points_world, dtype=float))
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise RleError(f"points must have shape (N, 3), got {pts.shape}", code="camera.shape")
        return pts @ self.camera_from_world[:3, :3].T + self.camera_from_world[:3, 3]

    def project(self, points_world: np.ndarray) -> np.ndarray:
        """Project world points to pixels.

        Args:
            points_world: ``(N, 3)`` or ``(3,)`` world coordinates [m].

        Returns:
            ``(N, 2)`` pixel coordinates ``(u, v)`` [px]; NaN for points not in front of the camera
            (their depth, ``to_camera(p)[:, 2]``, is <= 0).
        """
        cam = self.to_camera(points_world)
        z = cam[:, 2]
        k = self.intrinsics
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.where(z > 0, k.fx * cam[:, 0] / z + k.cx, np.nan)
            v = np.where(z > 0, k.fy * cam[:, 1] / z + k.cy, np.nan)
        return np.stack([u, v], axis=1)

    def backproject(
        self, depth: np.ndarray, mask: np.ndarray | None = None, pixels: np.ndarray | None = None
    ) -> np.ndarray:
        """Lift planar depth to world points.

        Args:
            depth: ``(H, W)`` planar depth image [m], or ``(N,)`` depths when ``pixels`` is given.
            mask: ``(H, W)`` boolean selection of pixels (default: every finite, positive depth).
            pixels: ``(N, 2)`` pixel coordinates ``(u, v)`` [px] paired with ``depth`` of shape (N,).

        Returns:
            ``(N, 3)`` world points [m], in row-major pixel order for an image.
        """
        k = self.intrinsics
        depth = np.asarray(depth, dtype=float)
        if pixels is not None:
            uv = np.atleast_2d(np.asarray(pixels, dtype=float))
            z = np.atleast_1d(depth)
            if uv.shape != (z.shape[0], 2):
                raise RleError(f"pixels {uv.shape} and depths {z.shape} do not pair up", code="camera.shape")
            u, v = uv[:, 0], uv[:, 1]
        else:
            if depth.shape != (k.height, k.width):
                raise RleError(
                    f"depth image has shape {depth.shape}, camera expects {(k.height, k.width)}",
                    code="camera.shape",
                )
            sel = np.isfinite(depth) & (depth > 0) if mask is None else np.asarray(mask, bool)
            v, u = np.nonzero(sel)
            z = depth[v, u]
            u, v = u.astype(float), v.astype(float)
        cam = np.stack([(u - k.cx) / k.fx * z, (v - k.cy) / k.fy * z, z], axis=1)
        return cam @ self.world_from_camera[:3, :3].T + self.world_from_camera[:3, 3]


def camera_spec(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    camera: str | int,
    width: int | None = None,
    height: int | None = None,
) -> CameraSpec:
    """The camera's intrinsics and current pose (``data`` must have run ``mj_kinematics``/``mj_forward``).

    Args:
        model: Compiled model.
        data: Data whose ``cam_xpos``/``cam_xmat`` are current.
        camera: Camera name or id.
        width: Image width [px] (default: the camera's ``resolution``).
        height: Image height [px] (default: the camera's ``resolution``).
    """
    cid = camera_id(model, camera)
    intr = camera_intrinsics(model, cid, width, height)
    pose = np.eye(4)
    pose[:3, :3] = data.cam_xmat[cid].reshape(3, 3) @ MJ_TO_CV
    pose[:3, 3] = data.cam_xpos[cid]
    extent = float(model.stat.extent)
    return CameraSpec(
        name=mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_CAMERA, cid) or f"#{cid}",
        id=cid,
        intrinsics=intr,
        world_from_camera=pose,
        near=float(model.vis.map.znear) * extent,
        far=float(model.vis.map.zfar) * extent,
    )
