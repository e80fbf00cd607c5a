"""Antipodal parallel-jaw grasp proposals on a point cloud, in Contact-GraspNet's output schema.

``antipodal_grasps(points, rng)`` samples contact points on the cloud, estimates surface normals by
local PCA (``estimate_normals``), looks for an opposite surface point along each contact's inward
normal within the gripper's opening, keeps the pairs whose normals lie in each other's friction
cones, chooses an approach direction about the closing axis (the one closest to the view ray that
keeps the hand and fingers out of the cloud) and returns::

    pred_grasps_cam   (K, 4, 4)  grasp poses in the cloud's (camera) frame [m]
    scores            (K,)       in [0, 1], best first
    contact_pts       (K, 3)     one contact per grasp [m]; the other is contact + opening * x axis
    gripper_openings  (K,)       distance between the two contacts [m]

Gripper convention (Contact-GraspNet's, Franka Panda hand): the pose's z axis is the approach
direction, its x axis the closing direction (from ``contact_pts`` towards the opposite contact), and
its origin is the gripper base (the hand's mounting flange); the finger-tip centre, midway between the
two contacts, lies ``TIP_DEPTH`` = 0.1034 m along z. So ``grasp @ [0, 0, TIP_DEPTH, 1]`` is the point
the fingers close on, and ``contact_pts + 0.5 * opening * x`` equals it.

Normals are oriented away from the cloud's centroid (the view point breaks near ties), which suits
segmented single objects; inward is then ``-normal``. Everything random draws from the ``rng`` given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["TIP_DEPTH", "GripperGeometry", "PANDA_GRIPPER", "antipodal_grasps", "estimate_normals"]

TIP_DEPTH = 0.1034
"""Distance from the gripper base (pose origin) to the finger-tip centre along the approach [m]."""


@dataclass(frozen=True)
class GripperGeometry:
    """A parallel-jaw gripper as boxes in the grasp frame (x closing, z approach) [m].

    Attributes:
        max_opening: Widest opening between the finger pads.
        tip_depth: Finger-tip centre along z from the base.
        palm_depth: z of the palm's face (fingers start here).
        palm_half: Half extents (x, y) of the palm.
        finger_thickness: Finger thickness along x.
        finger_half_width: Finger half width along y.
        tip_margin: Finger length beyond the tip centre along z.
    """

    max_opening: float = 0.08
    tip_depth: float = TIP_DEPTH
    palm_depth: float = 0.0584
    palm_half: tuple[float, float] = (0.102, 0.031)
    finger_thickness: float = 0.01
    finger_half_width: float = 0.01
    tip_margin: float = 0.01


PANDA_GRIPPER = GripperGeometry()
"""The Franka Panda hand (0.08 m opening)."""


def _knn(points: np.ndarray, k: int, chunk: int = 256) -> tuple[np.ndarray, np.ndarray]:
    """Indices (N, k) and distances (N, k) [m] of each point's k nearest points (itself first)."""
    n = len(points)
    k = min(k, n)
    idx = np.empty((n, k), dtype=np.int64)
    dist = np.empty((n, k))
    sq = np.einsum("ij,ij->i", points, points)
    for a in range(0, n, chunk):
        p = points[a : a + chunk]
        d2 = np.maximum(sq[a : a + chunk, None] - 2.0 * p @ points.T + sq[None, :], 0.0)
        part = np.argpartition(d2, k - 1, axis=1)[:, :k]
        rows = np.arange(len(p))[:, None]
        order = np.argsort(d2[rows, part], axis=1, kind="stable")
        idx[a : a + chunk] = part[rows, order]
        dist[a : a + chunk] = np.sqrt(d2[rows, idx[a : a + chunk]])
    return idx, dist


def estimate_normals(
    points: np.ndarray, k: int = 16, viewpoint: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit normals by local PCA over the ``k`` nearest neighbours.

    Args:
        points: (N, 3) points [m].
        k: Neighbourhood size.
        viewpoint: (3,) tie-breaking view point [m] (default the origin, a camera frame's centre).

    Returns:
        normals (N, 3) pointing away from the centroid (towards ``viewpoint`` where the centroid does not
        decide); surface variation (N,) ``l0 / (l0 + l1 + l2)`` of the covariance eigenvalues, 0 on a
        plane and 1/3 for isotropic scatter; neighbour indices (N, k).
    """
    pts = np.asarray(points, dtype=np.float64)
    idx, _ = _knn(pts, k)
    nb = pts[idx] - pts[idx].mean(axis=1, keepdims=True)
    cov = np.einsum("nki,nkj->nij", nb, nb) / max(idx.shape[1], 1)
    w, v = np.linalg.eigh(cov)
    normals = v[:, :, 0]
    variation = w[:, 0] / np.maximum(w.sum(axis=1), 1e-18)
    out = pts - pts.mean(axis=0)
    out /= np.maximum(np.linalg.norm(out, axis=1, keepdims=True), 1e-12)
    view = (np.zeros(3) if viewpoint is None else np.asarray(viewpoint, float)) - pts
    view /= np.maximum(np.linalg.norm(view, axis=1, keepdims=True), 1e-12)
    side = np.einsum("ij,ij->i", normals, out)
    side = np.where(np.abs(side) > 0.2, side, np.einsum("ij,ij->i", normals, view))
    normals = np.where(side[:, None] < 0, -normals, normals)
    return normals, variation, idx


def _frame(closing: np.ndarray, approach_hint: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """(A, 3, 3) rotations with x = ``closing`` and z turned about it by ``angles`` from the hint's
    component perpendicular to x."""
    x = closing / np.linalg.norm(closing)
    z0 = approach_hint - (approach_hint @ x) * x
    if np.linalg.norm(z0) < 1e-6:
        z0 = np.cross(x, [1.0, 0.0, 0.0] if abs(x[0]) < 0.9 else [0.0, 1.0, 0.0])
    z0 /= np.linalg.norm(z0)
    y0 = np.cross(z0, x)
    z = np.cos(angles)[:, None] * z0 + np.sin(angles)[:, None] * y0
    y = np.cross(z, x)
    return np.stack([np.broadcast_to(x, z.shape), y, z], axis=2)


def _collides(local: np.ndarray, opening: float, g: GripperGeometry, clearance: float) -> bool:
    """Whether points (M, 3) in a grasp frame enter the palm or the closed fingers."""
    x, y, z = np.abs(local[:, 0]), np.abs(local[:, 1]), local[:, 2]
    palm = (x < g.palm_half[0]) & (y < g.palm_half[1]) & (z > -0.02) & (z < g.palm_depth - clearance)
    fingers = (
        (x > opening / 2 + clearance)
        & (x < opening / 2 + g.finger_thickness + clearance)
        & (y < g.finger_half_width)
        & (z > g.palm_depth)
        & (z < g.tip_depth + g.tip_margin)
    )
    return bool(np.any(palm | fingers))


def antipodal_grasps(
    points: np.ndarray,
    rng: np.random.Generator,
    *,
    num_samples: int = 256,
    max_points: int = 1500,
    obstacles: np.ndarray | None = None,
    gripper: GripperGeometry = PANDA_GRIPPER,
    friction_angle: float = 0.35,
    min_opening: float = 0.004,
    line_radius: float = 0.003,
    pad_radius: float = 0.01,
    approach_angles: int = 12,
    clearance: float = 0.002,
    nms_distance: float = 0.005,
    max_grasps: int = 100,
    k: int = 16,
) -> dict[str, np.ndarray]:
    """Antipodal grasps of the cloud ``points`` (see the module docstring for the schema).

    Args:
        points: (N, 3) surface points of the object [m], camera frame (the view point at the origin).
        rng: Source of every random draw (subsampling, contact samples).
        num_samples: Contact points tried.
        max_points: The cloud is subsampled to at most this many points.
        obstacles: (M, 3) further points [m] (the scene around the object) the gripper must not enter.
        gripper: Gripper geometry (opening, finger and palm boxes).
        friction_angle: Half angle [rad] of the friction cones the contact line must lie in.
        min_opening: Smallest distance between the contacts [m].
        line_radius: Largest distance [m] of the opposite point from the contact's normal line (raised
            to the cloud's point spacing).
        pad_radius: Radius of a finger pad's patch [m] for the support term.
        approach_angles: Approach directions tried about the closing axis.
        clearance: Free margin [m] kept between the gripper's boxes and the points.
        nms_distance: Grasps whose tip centres lie closer than this [m] with parallel closing axes are
            merged into the best one.
        max_grasps: Grasps returned at most.
        k: Neighbours of the normal estimate.

    Returns:
        ``pred_grasps_cam`` (K, 4, 4), ``scores`` (K,), ``contact_pts`` (K, 3), ``gripper_openings`` (K,),
        best first; K = 0 when no pair fits (e.g. the object is wider than the opening every way).
        ``score`` is antipodality times support: antipodality maps the worse of the two contacts'
        angles between normal and contact line from ``friction_angle`` .. 0 to 0 .. 1; support is the
        mean over both contacts of the fraction of the pad patch's points whose normals agree with the
        contact's within ``friction_angle``, times the patch's planarity (1 - 3 surface variation).
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    if len(pts) > max_points:
        pts = pts[np.sort(rng.choice(len(pts), max_points, replace=False))]
    empty = {
        "pred_grasps_cam": np.zeros((0, 4, 4)),
        "scores": np.zeros(0),
        "contact_pts": np.zeros((0, 3)),
        "gripper_openings": np.zeros(0),
    }
    if len(pts) < max(k, 8):
        return empty
    normals, variation, nbr = estimate_normals(pts, k)
    spacing = float(np.median(np.linalg.norm(pts[nbr[:, 1]] - pts, axis=1)))
    radius = max(line_radius, 1.5 * spacing)
    cos_f = np.cos(friction_angle)
    # Support of each point as a pad contact: agreeing normals in the pad patch, times planarity.
    sq = np.einsum("ij,ij->i", pts, pts)
    support = np.empty(len(pts))
    for a in range(0, len(pts), 256):
        d2 = sq[a : a + 256, None] - 2.0 * pts[a : a + 256] @ pts.T + sq[None, :]
        near = d2 < pad_radius**2
        agree = (normals[a : a + 256] @ normals.T) > cos_f
        support[a : a + 256] = (near & agree).sum(axis=1) / np.maximum(near.sum(axis=1), 1)
    support *= np.clip(1.0 - 3.0 * variation, 0.0, 1.0)

    samples = rng.choice(len(pts), min(num_samples, len(pts)), replace=False)
    p = pts[samples]
    n = normals[samples]
    rel = pts[None, :, :] - p[:, None, :]  # (S, N, 3)
    depth = -np.einsum("snj,sj->sn", rel, n)  # along the inward normal
    off = np.linalg.norm(rel + depth[..., None] * n[:, None, :], axis=2)
    facing = -(n @ normals.T) > cos_f  # opposite normal anti-parallel
    ok = (depth > min_opening) & (depth < gripper.max_opening) & (off < radius) & facing
    view = -(pts.mean(axis=0))  # towards the camera
    hint = -view / max(np.linalg.norm(view), 1e-12)  # approach along the view ray
    angles = np.linspace(0.0, 2 * np.pi, approach_angles, endpoint=False)
    angles = angles[np.argsort(np.minimum(angles, 2 * np.pi - angles), kind="stable")]
    block = pts if obstacles is None else np.concatenate([pts, np.asarray(obstacles, float).reshape(-1, 3)])
    out_pose, out_score, out_contact, out_open = [], [], [], []
    for s in range(len(samples)):
        cand = np.nonzero(ok[s])[0]
        if len(cand) == 0:
            continue
        j = cand[np.argmin(depth[s, cand])]  # first surface the inward line meets
        c1, c2 = p[s], pts[j]
        line = c2 - c1
        width = float(np.linalg.norm(line))
        d = line / width
        anti = min(float(-n[s] @ d), float(normals[j] @ d))
        if anti < cos_f:
            continue
        score = (anti - cos_f) / (1.0 - cos_f) * 0.5 * (support[samples[s]] + support[j])
        centre = 0.5 * (c1 + c2)
        for rot in _frame(d, hint, angles):
            origin = centre - gripper.tip_depth * rot[:, 2]
            local = (block - origin) @ rot
            if not _collides(local, width, gripper, clearance):
                pose = np.eye(4)
                pose[:3, :3] = rot
                pose[:3, 3] = origin
                out_pose.append(pose)
                out_score.append(score)
                out_contact.append(c1)
                out_open.append(width)
                break
    if not out_pose:
        return empty
    order = np.argsort(-np.asarray(out_score), kind="stable")
    keep: list[int] = []
    for i in order:
        tip = out_pose[i][:3, :3] @ [0, 0, gripper.tip_depth] + out_pose[i][:3, 3]
        dup = False
        for kpt in keep:
            tk = out_pose[kpt][:3, :3] @ [0, 0, gripper.tip_depth] + out_pose[kpt][:3, 3]
            if (
                np.linalg.norm(tip - tk) < nms_distance
                and abs(out_pose[i][:3, 0] @ out_pose[kpt][:3, 0]) > 0.95
            ):
                dup = True
                break
        if not dup:
            keep.append(int(i))
        if len(keep) >= max_grasps:
            break
    return {
        "pred_grasps_cam": np.array([out_pose[i] for i in keep]),
        "scores": np.array([out_score[i] for i in keep], dtype=np.float64),
        "contact_pts": np.array([out_contact[i] for i in keep]),
        "gripper_openings": np.array([out_open[i] for i in keep], dtype=np.float64),
    }
