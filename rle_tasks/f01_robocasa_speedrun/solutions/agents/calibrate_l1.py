"""Camera self-calibration at L1: the agent views' focal length and poses on the base, from the hand.

L1 gives images, metric depth and proprioception, no camera model. The two agent-view cameras are fixed
on the base, so their poses in the base frame are constants of the robot: the hand (fingers closed, tool
pointing down, orientation held) visits ``GRID``, tool positions in the base frame (``ee_pos_base``) in
view of both cameras, about 320 actions in all. Per camera the background is the per-pixel farthest
depth over the images (the hand covers each pixel in few of them); the hand is what stands ``NEAR``
closer than it; the fingertips are the lowest two rows of its part within ``HAND_BAND`` of its farthest
depth (the cameras see the hand from behind, over the arm, which is nearer). The fingertips are hidden
in about a third of the poses: RANSAC over the poses, then least squares on the (u, v, depth) <-> tool
position correspondences fit each camera's focal length and pose (the principal point is the image
centre). Measured against the model's cameras: ``tests/f01_robocasa_speedrun/test_f01_l1_calibration.py``.

The hand camera is not calibrated (the L1 programs perceive with the agent views only).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import ndimage
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from rle_tasks.envs.kitchen.harness.geometry import world_from_base
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import CAMERAS, Robot

__all__ = ["AGENT_VIEWS", "Calibration", "calibrate", "calibration", "cameras", "fit"]

AGENT_VIEWS = CAMERAS[:2]
"""The cameras calibrated: left and right agent views (fixed on the base)."""
GRID = tuple(
    (x, y, z)
    for x, ys in ((0.28, (-0.2, 0.0, 0.2)), (0.4, (0.2, 0.0, -0.2)))
    for i, y in enumerate(ys)
    for z in ((0.95, 1.15, 1.35) if i % 2 == 0 else (1.35, 1.15, 0.95))
)
"""Tool positions in the base frame [m] (snake order): in view of both agent views, at least 0.15 m
short of the target fixture's front (the robot spawns 0.55-0.65 m from it)."""
NEAR = 0.03
"""A pixel shows the hand where it is this much closer than the background [m]."""
HAND_BAND = 0.08
"""The hand: its pixels within this depth of its farthest [m]."""
MIN_PIXELS = 20
"""Fewest pixels of a hand worth a feature."""
INLIER = (2.5, 0.025)
"""A pose whose tip lies within this of a fit ([px], [m]) agrees with it."""
SAMPLE = 5
"""Poses per RANSAC sample."""
TRIES = 60
"""RANSAC samples."""
SETTLE = 4
"""Actions held at each pose before the images are taken."""


@dataclass(frozen=True)
class Calibration:
    """Per agent view: ``K`` (3 x 3 [px]) and ``base_from_camera`` (4 x 4, OpenCV convention [m]);
    ``rms`` the fit's reprojection error [px] and ``steps`` the actions it cost."""

    K: dict[str, np.ndarray]
    base_from_camera: dict[str, np.ndarray]
    rms: dict[str, float]
    steps: int


_CACHE: dict[int, Calibration] = {}


def calibration(robot: Robot, motion: Motion) -> Calibration:
    """The session's calibration: measured on the first call (``calibrate``), then remembered."""
    key = id(robot)
    if key not in _CACHE:
        _CACHE[key] = calibrate(robot, motion)
    return _CACHE[key]


def cameras(cal: Calibration, obs: dict[str, Any]) -> dict[str, dict[str, np.ndarray]]:
    """The L2-style ``cameras`` entry (``K``, ``world_from_camera``) of the agent views at ``obs``."""
    wb = world_from_base(obs)
    return {c: {"K": cal.K[c], "world_from_camera": wb @ cal.base_from_camera[c]} for c in AGENT_VIEWS}


def calibrate(robot: Robot, motion: Motion) -> Calibration:
    """Visit ``GRID`` with the hand, detect it in each agent view, fit each camera."""
    o = robot.observe()
    quat = np.asarray(o["ee_quat"], float)  # the tool's orientation, held
    start_pos = np.asarray(o["ee_pos"], float)
    start, steps = robot.info().get("steps_used"), 0
    shots = []  # (tool position in the base frame, depth per camera)
    motion.close_gripper(steps=8)  # fingers together: one tip
    for p in GRID:
        wb = world_from_base(robot.obs)
        r = motion.move_tool(wb[:3, :3] @ np.asarray(p) + wb[:3, 3], quat, tol=0.01, max_steps=60)
        motion.wait(SETTLE)
        steps += r.steps + SETTLE
        o = robot.obs
        shots.append(
            (np.asarray(o["ee_pos_base"], float), {c: np.asarray(o["depth"][c], float) for c in AGENT_VIEWS})
        )
    motion.move_tool(start_pos, quat, tol=0.01, max_steps=60, gripper=-1.0)  # back out of the views
    used = robot.info().get("steps_used")
    steps = used - start if isinstance(used, int) and isinstance(start, int) else steps
    ks, poses, rms = {}, {}, {}
    for cam in AGENT_VIEWS:
        ks[cam], poses[cam], rms[cam] = fit([s[0] for s in shots], [s[1][cam] for s in shots])
    return Calibration(ks, poses, rms, steps)


def _blobs(depths: list[np.ndarray]) -> list[np.ndarray]:
    """Per image, the hand's mask: the largest component closer than the background by ``NEAR``."""
    bg = np.max(np.stack(depths), axis=0)
    out = []
    for d in depths:
        m = (d > 0) & (d < bg - NEAR)
        lab, n = ndimage.label(m)
        if n:
            sizes = ndimage.sum(m, lab, range(1, n + 1))
            m = lab == 1 + int(np.argmax(sizes))
        out.append(m)
    return out


def _feature(depth: np.ndarray, mask: np.ndarray) -> np.ndarray | None:
    """(u, v, depth) of the fingertips in one image: among the hand's pixels within ``HAND_BAND`` of its
    farthest depth (the hand, not the arm nearer the camera), the lowest two rows."""
    v, u = np.nonzero(mask)
    if len(v) < MIN_PIXELS:
        return None
    z = depth[v, u]
    hand = z >= np.percentile(z, 99.5) - HAND_BAND
    v, u, z = v[hand], u[hand], z[hand]
    tip = v >= v.max() - 1
    return np.array([u[tip].mean(), v[tip].mean(), float(np.median(z[tip]))])


def _project(theta: np.ndarray, pts: np.ndarray, c0) -> np.ndarray:
    """(u, v, depth) of base-frame points; ``theta`` = (f, rotation vector, position) of the camera."""
    f, (cx, cy) = theta[0], c0
    rot = Rotation.from_rotvec(theta[1:4]).as_matrix()  # base_from_camera rotation
    pc = (pts - theta[4:7]) @ rot  # camera coordinates
    return np.column_stack([f * pc[:, 0] / pc[:, 2] + cx, f * pc[:, 1] / pc[:, 2] + cy, pc[:, 2]])


def _solve(obs: np.ndarray, pts: np.ndarray, theta0: np.ndarray, c0) -> np.ndarray:
    def res(th):
        p = _project(th, pts, c0)
        return np.concatenate(
            [p[:, 0] - obs[:, 0], p[:, 1] - obs[:, 1], (p[:, 2] - obs[:, 2]) * th[0] / obs[:, 2]]
        )

    return least_squares(res, theta0, loss="soft_l1", f_scale=1.5).x


def _rigid(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(R, t) with b = R a + t in the least-squares sense (Kabsch)."""
    ca, cb = a.mean(0), b.mean(0)
    u, _, vt = np.linalg.svd((a - ca).T @ (b - cb))
    s = np.diag([1.0, 1.0, np.sign(np.linalg.det(vt.T @ u.T))])
    r = vt.T @ s @ u.T
    return r, cb - r @ ca


def _fit_subset(obs: np.ndarray, pts: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    h, w = shape
    f0, c0 = 0.9 * w, ((w - 1) / 2, (h - 1) / 2)  # a 60-degree view, centred
    cam = np.column_stack(
        [(obs[:, 0] - c0[0]) * obs[:, 2] / f0, (obs[:, 1] - c0[1]) * obs[:, 2] / f0, obs[:, 2]]
    )
    r, t = _rigid(cam, pts)
    return _solve(obs, pts, np.concatenate([[f0], Rotation.from_matrix(r).as_rotvec(), t]), c0)


def _errors(theta: np.ndarray, obs: np.ndarray, pts: np.ndarray, c0) -> np.ndarray:
    p = _project(theta, pts, c0)
    return np.maximum(
        np.linalg.norm(p[:, :2] - obs[:, :2], axis=1) / INLIER[0], np.abs(p[:, 2] - obs[:, 2]) / INLIER[1]
    )


def fit(tool_base: list[np.ndarray], depths: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, float]:
    """(K, base_from_camera, rms reprojection [px]) of one camera from the hand's tool positions in the
    base frame and the camera's depth images (one per position). Poses where the fingertips are hidden
    (by the hand or the arm) are outliers: RANSAC over ``SAMPLE``-pose subsets (``TRIES``, seeded), the
    largest consensus within ``INLIER`` refitted. The principal point is the image centre."""
    feats = [_feature(d, m) for d, m in zip(depths, _blobs(depths), strict=True)]
    keep = [i for i, f in enumerate(feats) if f is not None]
    obs = np.array([feats[i] for i in keep])
    pts = np.array([tool_base[i] for i in keep], float)
    h, w = depths[0].shape
    c0 = ((w - 1) / 2, (h - 1) / 2)
    rng = np.random.default_rng(0)
    best = None
    for _ in range(TRIES):
        pick = rng.choice(len(obs), SAMPLE, replace=False)
        theta = _fit_subset(obs[pick], pts[pick], (h, w))
        good = _errors(theta, obs, pts, c0) < 1.0
        if best is None or good.sum() > best.sum():
            best = good
    theta = _fit_subset(obs[best], pts[best], (h, w))
    good = _errors(theta, obs, pts, c0) < 1.0
    obs, pts = obs[good], pts[good]
    theta = _solve(obs, pts, theta, c0)
    p = _project(theta, pts, c0)
    rms = float(np.sqrt(np.mean(np.sum((p[:, :2] - obs[:, :2]) ** 2, axis=1))))
    k = np.array([[theta[0], 0, c0[0]], [0, theta[0], c0[1]], [0, 0, 1.0]])
    b = np.eye(4)
    b[:3, :3] = Rotation.from_rotvec(theta[1:4]).as_matrix()
    b[:3, 3] = theta[4:7]
    return k, b, rms
