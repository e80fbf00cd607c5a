"""Pinhole model of MuJoCo cameras: intrinsics from fovy, OpenCV extrinsics, projection round trips."""

import math

import mujoco
import numpy as np
import pytest

from rle_design.errors import MissingElement, RleError
from rle_design.sensors import MJ_TO_CV, CameraIntrinsics, camera_intrinsics, camera_spec

XML = """
<mujoco>
  <worldbody>
    <camera name="down" pos="0 0 2" fovy="60" resolution="64 48"/>
    <body name="rig" pos="0.3 -0.2 1.1" euler="0.4 -0.3 0.7">
      <camera name="tilted" pos="0.05 0 0" euler="0.2 0.1 0" fovy="45"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture(scope="module")
def model_data():
    m = mujoco.MjModel.from_xml_string(XML)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    return m, d


def test_intrinsics_from_fovy_and_resolution(model_data):
    m, _ = model_data
    k = camera_intrinsics(m, "down")
    # fy = (H/2) / tan(fovy/2), square pixels, principal point at the centre of pixel centres.
    fy = 24.0 / math.tan(math.radians(30.0))
    assert (k.width, k.height) == (64, 48)
    assert k.fy == pytest.approx(fy, rel=1e-12)
    assert k.fx == pytest.approx(fy, rel=1e-12)
    assert (k.cx, k.cy) == (31.5, 23.5)
    assert np.allclose(k.matrix, [[fy, 0, 31.5], [0, fy, 23.5], [0, 0, 1]])
    k2 = camera_intrinsics(m, "tilted", 320, 240)
    assert k2.fy == pytest.approx(120.0 / math.tan(math.radians(22.5)))


def test_extrinsics_follow_opencv_convention(model_data):
    m, d = model_data
    cam = camera_spec(m, d, "down", 64, 48)
    # A MuJoCo camera with identity orientation looks along world -z with image-up = world +y:
    # OpenCV axes are x right = world +x, y down = world -y, z forward = world -z.
    assert np.allclose(cam.world_from_camera[:3, :3], MJ_TO_CV)
    assert np.allclose(cam.world_from_camera[:3, 3], [0, 0, 2])
    assert np.allclose(cam.camera_from_world @ cam.world_from_camera, np.eye(4))
    # A point 1 m below the camera and 0.1 m towards +x lands right of centre, same row.
    (uv,) = cam.project(np.array([0.1, 0.0, 1.0]))
    assert cam.to_camera(np.array([0.1, 0.0, 1.0]))[0] == pytest.approx([0.1, 0.0, 1.0])
    assert uv[0] == pytest.approx(31.5 + cam.intrinsics.fx * 0.1)
    assert uv[1] == pytest.approx(23.5)
    # World +y is image-up: smaller row index.
    (uv2,) = cam.project(np.array([0.0, 0.1, 1.0]))
    assert uv2[1] < 23.5


def test_project_backproject_round_trip(model_data):
    m, d = model_data
    cam = camera_spec(m, d, "tilted", 320, 240)
    rng = np.random.default_rng(7)
    local = np.column_stack(
        [rng.uniform(-0.3, 0.3, 50), rng.uniform(-0.2, 0.2, 50), rng.uniform(0.4, 3.0, 50)]
    )
    world = local @ cam.world_from_camera[:3, :3].T + cam.world_from_camera[:3, 3]
    uv = cam.project(world)
    z = cam.to_camera(world)[:, 2]
    assert np.allclose(z, local[:, 2])
    back = cam.backproject(z, pixels=uv)
    assert np.abs(back - world).max() < 1e-9


def test_backproject_image_of_constant_depth_is_a_plane(model_data):
    m, d = model_data
    cam = camera_spec(m, d, "down", 64, 48)
    pts = cam.backproject(np.full((48, 64), 1.5, np.float32))
    assert pts.shape == (64 * 48, 3)
    assert np.allclose(pts[:, 2], 0.5)  # camera at z = 2 looking down
    # Corner pixel (0, 0) is up-left: world -x, +y.
    assert pts[0, 0] < 0 and pts[0, 1] > 0


def test_points_behind_camera_get_nan_pixels(model_data):
    m, d = model_data
    cam = camera_spec(m, d, "down", 64, 48)
    uv = cam.project(np.array([[0.0, 0.0, 3.0]]))
    assert cam.to_camera(np.array([0.0, 0.0, 3.0]))[0, 2] == pytest.approx(-1.0)
    assert np.isnan(uv).all()


def test_unknown_camera_lists_available(model_data):
    m, _ = model_data
    with pytest.raises(MissingElement) as exc:
        camera_intrinsics(m, "wrist")
    assert str(exc.value) == "camera 'wrist' does not exist. Available cameras: down, tilted"


def test_bad_fovy_and_shapes_raise():
    with pytest.raises(RleError, match=r"fovy must lie in \(0, 180\) degrees, got 180.0"):
        CameraIntrinsics.from_fovy(180.0, 10, 10)
    m = mujoco.MjModel.from_xml_string(XML)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    cam = camera_spec(m, d, "down", 64, 48)
    with pytest.raises(RleError, match=r"depth image has shape \(4, 4\), camera expects \(48, 64\)"):
        cam.backproject(np.ones((4, 4)))
