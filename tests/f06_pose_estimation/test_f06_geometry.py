"""Closed forms of the scene: the published calibration projects table points to the rendered pixels,
rendered depth of the table plane matches the plane's analytic depth, the blocks' footprints."""

import json
from pathlib import Path

import numpy as np
import pytest

from rle_tasks.f06_pose_estimation.scene import (
    CALIBRATION_FILE,
    CAMERA,
    HEIGHT_PX,
    WIDTH,
    BlockPose,
    PoseScene,
    compile_scene,
    published_calibration,
)
from rle_tasks.f06_pose_estimation.shapes import BLOCKS, HEIGHT

ASSETS = Path(__file__).resolve().parents[2] / "rle_tasks" / "f06_pose_estimation" / "assets"


def test_block_areas_and_centroids():
    # T: 120 x 30 + 30 x 90 mm^2; C and F: 30 x 120 + 2 x 60 x 30 and 30 x 120 + 75 x 30 + 45 x 30 mm^2
    assert [b.area for b in BLOCKS] == pytest.approx([0.0063, 0.0072, 0.0072])
    for b in BLOCKS:
        boxes = np.array(b.boxes_in_frame())
        w = 4 * boxes[:, 2] * boxes[:, 3]
        assert (w[:, None] * boxes[:, :2]).sum(0) == pytest.approx([0.0, 0.0], abs=1e-12)


@pytest.fixture(scope="module")
def rendered():
    from rle_design.sensors import RgbdSensor

    model = compile_scene()
    scene = PoseScene(model)
    scene.set_block(BlockPose(0.0, 0.0, 0.3, 0))
    scene.reach(np.array([-0.2, 0.0, 0.25]))
    scene.forward()
    with RgbdSensor(model, CAMERA, WIDTH, HEIGHT_PX, segmentation=True) as sensor:
        frame = sensor.render(scene.data)
    return scene, frame


def test_published_calibration_file_is_the_scene_camera():
    published = json.loads((ASSETS / CALIBRATION_FILE).read_text())
    now = published_calibration()
    assert np.allclose(published["K"], now["K"]) and np.allclose(published["T_world_cam"], now["T_world_cam"])


@pytest.mark.render
def test_table_point_projects_where_the_published_calibration_says(rendered):
    scene, frame = rendered
    cal = json.loads((ASSETS / CALIBRATION_FILE).read_text())
    k, pose = np.array(cal["K"]), np.array(cal["T_world_cam"])
    table = scene.model.geom("table").id
    ids = frame.geom_ids()
    # table points X (z = 0) at the centres of chosen pixels, from the published ray cut with the
    # plane; each projects back as u = fx Xc/Zc + cx, v = fy Yc/Zc + cy and the rendered image shows
    # the table there, at the depth Zc
    for u, v in ((40, 200), (280, 210), (300, 60), (160, 230)):
        ray = pose[:3, :3] @ np.array([(u - k[0, 2]) / k[0, 0], (v - k[1, 2]) / k[1, 1], 1.0])
        x = pose[:3, 3] - pose[:3, 3][2] / ray[2] * ray
        xc = pose[:3, :3].T @ (x - pose[:3, 3])
        uv = np.array([k[0, 0] * xc[0] / xc[2] + k[0, 2], k[1, 1] * xc[1] / xc[2] + k[1, 2]])
        assert np.abs(uv - (u, v)).max() < 0.5
        assert ids[v, u] == table
        assert abs(frame.depth[v, u] - xc[2]) < 1e-3


@pytest.mark.render
def test_table_depth_is_plane_depth(rendered):
    scene, frame = rendered
    cam = scene.camera()
    k = cam.intrinsics
    r = cam.world_from_camera[:3, :3]
    c = cam.world_from_camera[:3, 3]
    ids = frame.geom_ids()
    table = scene.model.geom("table").id
    v, u = np.nonzero(ids == table)
    sel = slice(None, None, 97)
    v, u = v[sel], u[sel]
    # ray d = R [(u - cx)/fx, (v - cy)/fy, 1]; plane z = 0: planar depth Z = -c_z / d_z
    d = np.stack([(u - k.cx) / k.fx, (v - k.cy) / k.fy, np.ones_like(u, float)], 1) @ r.T
    z_expected = -c[2] / d[:, 2]
    assert np.abs(frame.depth[v, u] - z_expected).max() < 1e-3


@pytest.mark.render
def test_block_top_face_depth(rendered):
    scene, frame = rendered
    cam = scene.camera()
    ids = frame.geom_ids()
    block = [scene.model.geom(f"block_T_{j}").id for j in range(2)]
    v, u = np.nonzero(np.isin(ids, block))
    pts = cam.backproject(frame.depth[v, u].astype(float), pixels=np.stack([u, v], 1))
    # the most frequent height of the block's visible points is its top face at HEIGHT
    hist, edges = np.histogram(pts[:, 2], bins=60, range=(0.0, 0.06))
    assert edges[np.argmax(hist)] == pytest.approx(HEIGHT, abs=1e-3)


def test_contact_tip_closed_form():
    from rle_tasks.f06_pose_estimation.episodes import contact_tip
    from rle_tasks.f06_pose_estimation.scene import STICK_RADIUS, TIP_HEIGHT

    # T at theta = 0: its bar spans x in [-0.06, 0.06] in the block frame (the centroid shift is along y
    # only); pushing along +x puts the stick at x - (0.06 + r + gap)
    tip = contact_tip(BlockPose(0.01, 0.02, 0.0, 0), np.array([1.0, 0.0]), gap=0.002)
    assert tip == pytest.approx((0.01 - (0.06 + STICK_RADIUS + 0.002), 0.02, TIP_HEIGHT))
    # rotated by pi/2, the bar lies along y: pushing along +y meets the bar's end at 0.06
    tip = contact_tip(BlockPose(0.0, 0.0, np.pi / 2, 0), np.array([0.0, 1.0]), gap=0.0)
    assert tip[1] == pytest.approx(-(0.06 + STICK_RADIUS))


def test_stick_reaches_every_contact_point_of_a_push():
    from rle_tasks.f06_pose_estimation.episodes import push_episode

    scene = PoseScene(compile_scene())
    for seed in range(3):
        scene.set_arm(scene.home)
        for f in push_episode(np.random.default_rng(seed), 60):
            assert scene.reach(np.array(f.tip)) < 1e-3
