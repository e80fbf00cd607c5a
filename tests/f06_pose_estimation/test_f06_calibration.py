"""The published calibration of family 06 agrees with its renderer and with its labels (issue 44).

A user reported that points back-projected from depth sit a constant 1.85 mm from the labelled
poses in world y. These tests pin the agreement of the three things an estimator relies on, with
the calibration as agents receive it (``assets/calibration.json``) and the pinhole closed form
written out here:

    camera point  Xc = R^T (X - C)                  (T_world_cam = [R | C], OpenCV axes)
    projection    u = fx Xc/Zc + cx,  v = fy Yc/Zc + cy   (pixel centres at integers)
    ray of (u, v) d = R [(u - cx)/fx, (v - cy)/fy, 1];  X = C + Z d  (Z: planar depth)

1. Projection of known points: the corners of thin square table marks (test-only geoms) and of the
   blocks' boxes at labelled poses. A convex box's silhouette is the convex hull of its projected
   corners, so the rendered segmentation must equal "pixel centre inside the hull"; the sub-pixel
   image shift that best explains the rendered mask, times the metric pixel size on the surface's
   plane, is the projection error [m]. Bound: 0.2 mm.
2. Back-projection of rendered depth at pixels whose closed-form ray meets a known plane (table,
   mark tops, block top faces at least 2 mm inside their edges): 3-D error bound 0.2 mm.
3. The labels: ``(x, y, theta)`` is the block frame (footprint centroid on the table, rotation about
   world z) of ``shapes.BLOCKS``: the silhouettes of 1. are drawn at the labelled pose.
4. The check itself sees an offset of the reported size: a calibration whose camera centre is moved
   by 1.85 mm along world y, or whose principal point follows the (u + 0.5) convention, fails it.

Measured (2026-11-28, mujoco 4.0.0, llvmpipe): zero mismatched pixels, fitted shifts <= 0.04 px
(<= 0.1 mm, the fit's resolution), depth errors <= 0.0005 mm: there is no offset to correct.
"""

from __future__ import annotations

import json
from pathlib import Path

import mujoco
import numpy as np
import pytest
from scipy.spatial import ConvexHull

from rle_tasks.f06_pose_estimation.scene import (
    CALIBRATION_FILE,
    CAMERA,
    HEIGHT_PX,
    WIDTH,
    BlockPose,
    PoseScene,
    build_spec,
    compile_scene,
)
from rle_tasks.f06_pose_estimation.shapes import BLOCKS, HEIGHT

ASSETS = Path(__file__).resolve().parents[2] / "rle_tasks" / "f06_pose_estimation" / "assets"
TOLERANCE = 0.2e-3
"""Largest projection or back-projection error at the table [m]."""
MARK_HALF = (0.025, 0.025, 0.0002)
"""Half sizes of a table mark: a 50 mm square, 0.4 mm thick [m]."""
MARKS = tuple(
    ((x, y, MARK_HALF[2]), 0.3 + 0.4 * k)
    for k, (x, y) in enumerate((x, y) for x in (-0.1, 0.0, 0.12) for y in (-0.12, 0.0, 0.12))
)
"""Centre [m] and yaw [rad] of each table mark (a 3 x 3 grid over the workspace)."""
POSES = (
    BlockPose(0.02, -0.03, 0.4, 0),
    BlockPose(-0.1, 0.12, -2.6, 0),
    BlockPose(-0.08, 0.1, -2.0, 1),
    BlockPose(0.13, 0.05, 1.1, 1),
    BlockPose(0.1, -0.09, 2.8, 2),
    BlockPose(-0.05, -0.12, -0.7, 2),
)
"""Labelled block poses: every shape, the workspace's corners and centre, all quadrants of theta."""
RAISED = np.array([-0.2, 0.0, 0.25])
"""Stick tip out of the view [m]."""


def _calibration() -> tuple[np.ndarray, np.ndarray]:
    cal = json.loads((ASSETS / CALIBRATION_FILE).read_text())
    return np.array(cal["K"], float), np.array(cal["T_world_cam"], float)


# -- the closed form ---------------------------------------------------------------------------------
def project(k: np.ndarray, pose: np.ndarray, x: np.ndarray) -> np.ndarray:
    """World points ``(N, 3)`` to pixels ``(N, 2)``: ``u = fx Xc/Zc + cx``, ``v = fy Yc/Zc + cy``."""
    xc = (np.atleast_2d(x) - pose[:3, 3]) @ pose[:3, :3]  # R^T (X - C), row-wise
    return np.stack([k[0, 0] * xc[:, 0] / xc[:, 2] + k[0, 2], k[1, 1] * xc[:, 1] / xc[:, 2] + k[1, 2]], 1)


def rays(k: np.ndarray, pose: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """World directions ``R [(u - cx)/fx, (v - cy)/fy, 1]`` (unit planar depth) of pixels ``(u, v)``."""
    d = np.stack([(u - k[0, 2]) / k[0, 0], (v - k[1, 2]) / k[1, 1], np.ones_like(u, float)], -1)
    return d @ pose[:3, :3].T


def cut(k: np.ndarray, pose: np.ndarray, u: np.ndarray, v: np.ndarray, h: float) -> np.ndarray:
    """Where the rays of pixels ``(u, v)`` meet the plane z = ``h`` [m]."""
    d = rays(k, pose, u, v)
    z = (h - pose[2, 3]) / d[..., 2]
    return pose[:3, 3] + z[..., None] * d


def backproject(k: np.ndarray, pose: np.ndarray, u: np.ndarray, v: np.ndarray, z: np.ndarray) -> np.ndarray:
    """World points ``C + Z d`` of pixels ``(u, v)`` at planar depths ``z`` [m]."""
    return pose[:3, 3] + z[..., None] * rays(k, pose, u, v)


def plane_scale(k: np.ndarray, pose: np.ndarray, uv: np.ndarray, h: float) -> np.ndarray:
    """2 x 2 metres per pixel on the plane z = ``h`` at pixel ``uv`` (columns: d/du, d/dv of x, y)."""
    eps = 1e-3
    p = cut(k, pose, np.array(uv[0]), np.array(uv[1]), h)[:2]
    du = cut(k, pose, np.array(uv[0] + eps), np.array(uv[1]), h)[:2] - p
    dv = cut(k, pose, np.array(uv[0]), np.array(uv[1] + eps), h)[:2] - p
    return np.stack([du, dv], 1) / eps


# -- silhouettes of boxes ----------------------------------------------------------------------------
def box_corners(centre, half, yaw: float) -> np.ndarray:
    """The 8 corners ``(8, 3)`` of a box turned by ``yaw`` about z [m]."""
    c, s = np.cos(yaw), np.sin(yaw)
    out = []
    for sx in (-1, 1):
        for sy in (-1, 1):
            for sz in (-1, 1):
                lx, ly = sx * half[0], sy * half[1]
                out.append(
                    (centre[0] + c * lx - s * ly, centre[1] + s * lx + c * ly, centre[2] + sz * half[2])
                )
    return np.array(out)


def block_boxes(pose: BlockPose) -> list[np.ndarray]:
    """Corners of each box of the labelled block: ``shapes.BLOCKS`` in the frame ``(x, y, theta)``."""
    c, s = np.cos(pose.theta), np.sin(pose.theta)
    return [
        box_corners(
            (pose.x + c * bx - s * by, pose.y + s * bx + c * by, HEIGHT / 2), (hx, hy, HEIGHT / 2), pose.theta
        )
        for bx, by, hx, hy in BLOCKS[pose.shape].boxes_in_frame()
    ]


def inside(hulls: list[np.ndarray], u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Pixels ``(u, v)`` inside the union of convex polygons (``ConvexHull.equations``, a u + b v + c <= 0)."""
    out = np.zeros(u.shape, bool)
    for eq in hulls:
        out |= np.all(
            eq[:, :1, None] * u.ravel() + eq[:, 1:2, None] * v.ravel() + eq[:, 2:, None] <= 0, 0
        ).reshape(u.shape)
    return out


def fit_shift(mask: np.ndarray, hulls: list[np.ndarray]) -> tuple[np.ndarray, int]:
    """Image shift [px] of the predicted silhouette that reproduces the rendered ``mask`` best (the
    centre of the shifts with the fewest mismatched pixels, on a 0.05 then a 0.005 px grid), and the
    mismatched pixels without a shift."""
    v, u = np.nonzero(mask)
    v0, v1, u0, u1 = v.min() - 4, v.max() + 5, u.min() - 4, u.max() + 5
    vv, uu = np.mgrid[v0:v1, u0:u1].astype(float)
    seen = mask[v0:v1, u0:u1]

    def mismatches(d: np.ndarray) -> int:
        return int((inside(hulls, uu - d[0], vv - d[1]) != seen).sum())

    best = np.zeros(2)
    for step, span in ((0.05, 1.0), (0.005, 0.06)):
        g = np.arange(-span, span + step / 2, step)
        cands = best + np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
        counts = np.array([mismatches(d) for d in cands])
        best = cands[counts == counts.min()].mean(0)
    return best, mismatches(np.zeros(2))


def projection_error(k, pose, mask, corners: list[np.ndarray], anchor: np.ndarray) -> tuple[float, int]:
    """Projection error [m] of boxes ``corners`` against the rendered ``mask``: the fitted image
    shift times the metric pixel size on the plane of ``anchor`` (a point of the surface), and the
    mismatched pixels without a shift."""
    hulls = [ConvexHull(project(k, pose, c)).equations for c in corners]
    shift, n = fit_shift(mask, hulls)
    uv = project(k, pose, anchor)[0]
    return float(np.linalg.norm(plane_scale(k, pose, uv, float(anchor[2])) @ shift)), n


# -- renders ---------------------------------------------------------------------------------------------
def _render(model: mujoco.MjModel, poses) -> list:
    from rle_design.sensors import RgbdSensor

    scene = PoseScene(model)
    scene.reach(RAISED)
    frames = []
    with RgbdSensor(model, CAMERA, WIDTH, HEIGHT_PX, segmentation=True) as sensor:
        for pose in poses:
            if pose is not None:
                scene.set_block(pose)
            scene.forward()
            frames.append(sensor.render(scene.data))
    return frames


@pytest.fixture(scope="module")
def marked():
    """Nominal scene plus the table marks (blocks parked under the table): model and frame."""
    spec = build_spec()
    for i, (centre, yaw) in enumerate(MARKS):
        spec.worldbody.add_geom(
            name=f"mark_{i}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=list(MARK_HALF),
            pos=list(centre),
            quat=[np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)],
            rgba=[0.1, 0.8, 0.1, 1.0],
            contype=0,
            conaffinity=0,
        )
    model = spec.compile()
    return model, _render(model, [None])[0]


@pytest.fixture(scope="module")
def blocks():
    """The shipped scene with a block at each of ``POSES``: model and frames."""
    model = compile_scene()
    return model, _render(model, POSES)


@pytest.mark.render
def test_every_frame_carries_the_published_calibration(marked, blocks):
    k, pose = _calibration()
    for frame in [marked[1], *blocks[1]]:
        assert np.abs(frame.camera.intrinsics.matrix - k).max() < 1e-8
        assert np.abs(frame.camera.world_from_camera - pose).max() < 1e-8


@pytest.mark.render
def test_table_marks_project_where_the_calibration_says(marked):
    model, frame = marked
    k, pose = _calibration()
    ids = frame.geom_ids()
    for i, (centre, yaw) in enumerate(MARKS):
        mask = ids == model.geom(f"mark_{i}").id
        assert mask.sum() > 200  # the whole mark is in view and unoccluded
        err, n = projection_error(k, pose, mask, [box_corners(centre, MARK_HALF, yaw)], np.array(centre))
        assert n <= 2, f"mark {i}: {n} pixels differ from the closed-form silhouette"
        assert err < TOLERANCE, f"mark {i} at {centre}: projection error {err * 1e3:.3f} mm"


@pytest.mark.render
def test_block_silhouettes_sit_at_their_labels(blocks):
    model, frames = blocks
    k, pose = _calibration()
    for label, frame in zip(POSES, frames):
        block = BLOCKS[label.shape]
        ids = [model.geom(f"block_{block.name}_{j}").id for j in range(len(block.boxes))]
        mask = np.isin(frame.geom_ids(), ids)
        err, n = projection_error(k, pose, mask, block_boxes(label), np.array([label.x, label.y, HEIGHT]))
        assert n <= 2, f"{label}: {n} pixels differ from the closed-form silhouette"
        assert err < TOLERANCE, f"{label}: silhouette {err * 1e3:.3f} mm from the label"


@pytest.mark.render
def test_depth_backprojects_onto_known_surfaces(marked, blocks):
    k, pose = _calibration()
    vv, uu = np.mgrid[0:HEIGHT_PX, 0:WIDTH].astype(float)
    # table: every table pixel whose ray meets z = 0 within 0.3 m of the centre
    model, frame = marked
    on_table = cut(k, pose, uu, vv, 0.0)
    sel = (frame.geom_ids() == model.geom("table").id) & (np.abs(on_table[..., :2]) < 0.3).all(-1)
    assert sel.sum() > 20000
    err = np.linalg.norm(backproject(k, pose, uu, vv, frame.depth.astype(float)) - on_table, axis=-1)[sel]
    assert err.max() < TOLERANCE
    # mark tops: pixels whose ray meets the top at least 3 mm inside its edges
    top = 2 * MARK_HALF[2]
    at = cut(k, pose, uu, vv, top)
    for i, (centre, yaw) in enumerate(MARKS):
        c, s = np.cos(yaw), np.sin(yaw)
        local = (at[..., :2] - centre[:2]) @ np.array([[c, -s], [s, c]])
        sel = (np.abs(local) < np.array(MARK_HALF[:2]) - 0.003).all(-1)
        assert sel.sum() > 100 and (frame.geom_ids()[sel] == model.geom(f"mark_{i}").id).all()
        err = np.linalg.norm(backproject(k, pose, uu, vv, frame.depth.astype(float)) - at, axis=-1)[sel]
        assert err.max() < TOLERANCE, f"mark {i}: {err.max() * 1e3:.4f} mm"
    # block top faces: pixels whose ray meets z = HEIGHT at least 2 mm inside the labelled footprint
    model, frames = blocks
    at = cut(k, pose, uu, vv, HEIGHT)
    for label, frame in zip(POSES, frames):
        c, s = np.cos(label.theta), np.sin(label.theta)
        local = ((at[..., :2] - (label.x, label.y)) @ np.array([[c, -s], [s, c]])).reshape(-1, 2)
        sel = np.ones(len(local), bool)
        for off in ((0, 0), (0.002, 0), (-0.002, 0), (0, 0.002), (0, -0.002)):
            sel &= BLOCKS[label.shape].contains(local + off)
        sel = sel.reshape(uu.shape)
        block = BLOCKS[label.shape]
        ids = [model.geom(f"block_{block.name}_{j}").id for j in range(len(block.boxes))]
        assert sel.sum() > 300 and np.isin(frame.geom_ids()[sel], ids).all()
        err = np.linalg.norm(backproject(k, pose, uu, vv, frame.depth.astype(float)) - at, axis=-1)[sel]
        assert err.max() < TOLERANCE, f"{label}: top face {err.max() * 1e3:.4f} mm off"


@pytest.mark.render
def test_the_check_sees_an_offset_of_the_reported_size(marked):
    """A camera centre moved 1.85 mm along world y, or a principal point at (W/2, H/2) (the
    (u + 0.5) convention), is measured as such and fails the bound."""
    model, frame = marked
    k, pose = _calibration()
    moved = pose.copy()
    moved[1, 3] += 0.00185
    half = k.copy()
    half[:2, 2] += 0.5
    ids = frame.geom_ids()
    centre, yaw = MARKS[4]  # the mark at the table centre
    mask = ids == model.geom("mark_4").id
    corners = [box_corners(centre, MARK_HALF, yaw)]
    err, n = projection_error(k, moved, mask, corners, np.array(centre))
    assert err == pytest.approx(0.00185, abs=TOLERANCE) and n > 20
    err, n = projection_error(half, pose, mask, corners, np.array(centre))
    assert err > 5 * TOLERANCE and n > 20
