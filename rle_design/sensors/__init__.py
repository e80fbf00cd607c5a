"""Camera rendering (RGB, depth, segmentation) on CPU, pinhole calibration, noise models, F/T sensors and
antipodal grasp proposals on point clouds."""

from rle_design.sensors.camera import (
    MJ_TO_CV,
    CameraIntrinsics,
    CameraSpec,
    camera_id,
    camera_intrinsics,
    camera_spec,
)
from rle_design.sensors.force_torque import ft_reading
from rle_design.sensors.gl import RenderError, create_context
from rle_design.sensors.grasps import antipodal_grasps, estimate_normals
from rle_design.sensors.noise import DepthNoise, RgbNoise, add_noise
from rle_design.sensors.rgbd import BACKGROUND, Frame, RgbdSensor

__all__ = [
    "BACKGROUND",
    "MJ_TO_CV",
    "CameraIntrinsics",
    "CameraSpec",
    "DepthNoise",
    "Frame",
    "RenderError",
    "RgbNoise",
    "RgbdSensor",
    "add_noise",
    "antipodal_grasps",
    "camera_id",
    "camera_intrinsics",
    "camera_spec",
    "create_context",
    "estimate_normals",
    "ft_reading",
]
