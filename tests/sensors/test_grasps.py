"""Antipodal grasp proposals (rle_design.sensors.grasps) against closed forms on synthetic clouds."""

from __future__ import annotations

import numpy as np
import pytest

from rle_design.sensors.grasps import TIP_DEPTH, antipodal_grasps, estimate_normals

CENTRE = np.array([0.05, -0.02, 0.6])
"""Object centre in the camera frame [m] (0.6 m in front of the camera)."""


def box_cloud(half: np.ndarray, per_face: int, rng: np.random.Generator) -> np.ndarray:
    """Points uniform on the six faces of a box of half extents ``half`` [m] centred at ``CENTRE``."""
    faces = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            p = rng.uniform(-1.0, 1.0, (per_face, 3)) * half
            p[:, axis] = sign * half[axis]
            faces.append(p)
    return np.concatenate(faces) + CENTRE


def sphere_cloud(radius: float, n: int, rng: np.random.Generator) -> np.ndarray:
    """Points uniform on a sphere of ``radius`` [m] centred at ``CENTRE``."""
    v = rng.normal(size=(n, 3))
    return radius * v / np.linalg.norm(v, axis=1, keepdims=True) + CENTRE


def tips(g: dict[str, np.ndarray]) -> np.ndarray:
    """Finger-tip centres: the pose origin moved TIP_DEPTH along its z (approach)."""
    return g["pred_grasps_cam"][:, :3, 3] + TIP_DEPTH * g["pred_grasps_cam"][:, :3, 2]


def test_normals_of_a_plane_and_a_sphere() -> None:
    rng = np.random.default_rng(0)
    plane = np.column_stack([rng.uniform(-0.1, 0.1, (400, 2)), np.full(400, 0.5)])
    n, var, _ = estimate_normals(plane)
    assert np.allclose(np.abs(n[:, 2]), 1.0, atol=1e-9) and var.max() < 1e-9
    assert np.all(n[:, 2] < 0)  # a flat cloud: towards the view point (the camera at the origin)
    pts = sphere_cloud(0.03, 1500, rng)
    n, _, _ = estimate_normals(pts)
    outward = (pts - CENTRE) / 0.03
    assert np.median(np.einsum("ij,ij->i", n, outward)) > 0.99  # oriented away from the centroid


def test_box_grasped_across_its_narrow_faces() -> None:
    # A 0.05 x 0.12 x 0.20 m box: only the 0.05 m faces fit in the 0.08 m opening, so every antipodal
    # grasp closes along x with opening 0.05 m, one contact on each x face (x = +-0.025 from the centre).
    half = np.array([0.025, 0.06, 0.10])
    g = antipodal_grasps(box_cloud(half, 300, np.random.default_rng(1)), np.random.default_rng(2))
    assert len(g["scores"]) >= 5
    x_axis = g["pred_grasps_cam"][:, :3, 0]
    assert np.all(np.abs(x_axis[:, 0]) > 0.95)
    assert np.allclose(g["gripper_openings"], 0.05, atol=0.003)
    c1 = g["contact_pts"]
    c2 = c1 + g["gripper_openings"][:, None] * x_axis
    assert np.allclose(np.abs(c1[:, 0] - CENTRE[0]), 0.025, atol=1e-9)  # sampled on a face
    assert np.allclose(np.abs(c2[:, 0] - CENTRE[0]), 0.025, atol=0.003)
    assert np.all(np.sign(c1[:, 0] - CENTRE[0]) != np.sign(c2[:, 0] - CENTRE[0]))  # opposite faces
    assert np.all(np.diff(g["scores"]) <= 0) and g["scores"][0] > 0.9


def test_sphere_openings_are_its_diameter() -> None:
    # Antipodal points of a sphere are diametrically opposite: opening 2 r, tip centre at the centre.
    r = 0.03
    g = antipodal_grasps(sphere_cloud(r, 1500, np.random.default_rng(3)), np.random.default_rng(4))
    assert len(g["scores"]) >= 10
    assert np.allclose(g["gripper_openings"], 2 * r, atol=0.003)
    assert np.all(np.linalg.norm(tips(g) - CENTRE, axis=1) < 0.004)


@pytest.mark.parametrize("shape", ["cube", "sphere"])
def test_nothing_wider_than_the_opening(shape: str) -> None:
    # A 0.10 m cube and a 0.09 m sphere: every antipodal pair is >= 0.09 m apart, beyond 0.08 m.
    rng = np.random.default_rng(5)
    pts = box_cloud(np.full(3, 0.05), 300, rng) if shape == "cube" else sphere_cloud(0.045, 1500, rng)
    g = antipodal_grasps(pts, np.random.default_rng(6))
    assert g["pred_grasps_cam"].shape == (0, 4, 4) and g["scores"].shape == (0,)
    assert g["contact_pts"].shape == (0, 3) and g["gripper_openings"].shape == (0,)


def test_schema_frame_and_determinism() -> None:
    pts = box_cloud(np.array([0.02, 0.05, 0.07]), 250, np.random.default_rng(7))
    a = antipodal_grasps(pts, np.random.default_rng(8))
    b = antipodal_grasps(pts, np.random.default_rng(8))
    for key in ("pred_grasps_cam", "scores", "contact_pts", "gripper_openings"):
        assert a[key].dtype == np.float64 and np.array_equal(a[key], b[key])
    k = len(a["scores"])
    assert k > 0 and a["pred_grasps_cam"].shape == (k, 4, 4) and a["contact_pts"].shape == (k, 3)
    rot = a["pred_grasps_cam"][:, :3, :3]
    assert np.allclose(rot @ rot.transpose(0, 2, 1), np.eye(3), atol=1e-9)
    assert np.allclose(np.linalg.det(rot), 1.0) and np.allclose(a["pred_grasps_cam"][:, 3], [0, 0, 0, 1])
    # The documented offset: tip centre = contact + opening / 2 along the closing (x) axis.
    mid = a["contact_pts"] + 0.5 * a["gripper_openings"][:, None] * rot[:, :, 0]
    assert np.allclose(tips(a), mid, atol=1e-12)
    assert np.all((a["scores"] >= 0) & (a["scores"] <= 1))


def test_obstacles_keep_the_gripper_out_of_a_table() -> None:
    # The box stands on a table (the plane y = +0.07 below it, camera y down): with the table as
    # obstacles no grasp puts its palm corners or finger tips into or under the table, whereas the
    # box alone is also grasped from below.
    rng = np.random.default_rng(9)
    half = np.array([0.025, 0.07, 0.05])
    uv = rng.uniform(-0.25, 0.25, (3000, 2))
    table = np.column_stack([uv[:, 0], np.full(3000, half[1]), uv[:, 1]]) + CENTRE
    box = box_cloud(half, 300, rng)
    free = antipodal_grasps(box, np.random.default_rng(10))
    g = antipodal_grasps(box, np.random.default_rng(10), obstacles=table)
    assert 0 < len(g["scores"]) < len(free["scores"])
    corners = np.array([[sx * 0.102, sy * 0.031, 0.0] for sx in (-1, 1) for sy in (-1, 1)])
    for pose, width in zip(g["pred_grasps_cam"], g["gripper_openings"]):
        fingers = np.array([[s * width / 2, 0.0, TIP_DEPTH + 0.01] for s in (-1, 1)])
        pts = np.concatenate([corners, fingers]) @ pose[:3, :3].T + pose[:3, 3]
        assert np.all(pts[:, 1] < CENTRE[1] + half[1])  # above the table (up is -y)
