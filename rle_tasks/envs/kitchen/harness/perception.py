"""Level 2: perception tools (public, laid into the workspace).

``segment(client, prompt, camera)`` asks the simulator's segmenter (a stand-in for SAM3: instance masks
of a text prompt from the simulator's segmentation, with noise) and returns SAM3's output schema:
``masks`` (N, H, W) bool, ``boxes`` (N, 4) x0 y0 x1 y1 [px], ``scores`` (N,). Prompts match instance
labels word by word: ``"handle"`` finds every handle, ``"fridge handle"`` the fridge's, ``"apple"`` the
apples; labels are object categories and fixture parts (``fridge door``, ``cabinet door``, ``drawer``,
``front left knob``, ``rear right burner``, ``counter``, ``sink basin``, ``microwave``, ``plate`` ...).

``grasp_proposals(obs, camera, mask)`` proposes parallel-jaw grasps on the depth image's points (a
stand-in for Contact-GraspNet: an antipodal sampler, ``rle_design.sensors.grasps``) and returns
Contact-GraspNet's schema: ``pred_grasps_cam`` (K, 4, 4) poses in the OpenCV camera frame,
``scores`` (K,), ``contact_pts`` (K, 3) [m], ``gripper_openings`` (K,) [m], best first. A pose's z axis
is the approach, its x axis the closing direction, its origin the gripper base; the finger-tip centre
lies ``TIP_DEPTH`` = 0.1034 m along z. The harness tool frame (``ee_pos``/``ee_quat``: the point
between the finger tips, x closing, z approach) is that pose moved ``TIP_DEPTH`` along z:
``tool_pose`` gives it in the world.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from rle_design.sensors.grasps import TIP_DEPTH, antipodal_grasps

from .geometry import deproject, mat_to_quat, world_points

__all__ = ["TIP_DEPTH", "grasp_proposals", "object_points", "segment", "tool_pose"]


def segment(client: Any, prompt: str, camera: str = "robot/agentview_left") -> dict[str, np.ndarray]:
    """SAM3-schema instance masks of ``prompt`` in ``camera``'s current image (a free query)."""
    return client.query("segment", prompt=prompt, camera=camera)


def object_points(
    client: Any,
    obs: dict[str, Any],
    prompt: str,
    camera: str = "robot/agentview_left",
    min_score: float = 0.5,
) -> list[np.ndarray]:
    """World points [m] of each instance of ``prompt`` seen by ``camera`` (one (N, 3) array per mask,
    largest first), from the segmentation and the depth image of ``obs``."""
    seg = segment(client, prompt, camera)
    out = []
    for mask, score in zip(seg["masks"], seg["scores"]):
        if score >= min_score:
            pts = world_points(obs, camera, mask)
            if len(pts):
                out.append(pts)
    return sorted(out, key=len, reverse=True)


def grasp_proposals(
    obs: dict[str, Any],
    camera: str = "robot/agentview_left",
    mask: np.ndarray | None = None,
    *,
    views: Sequence[tuple[str, np.ndarray | None]] = (),
    points_world: np.ndarray | None = None,
    rng: np.random.Generator | None = None,
    scene_radius: float = 0.15,
    **options: Any,
) -> dict[str, np.ndarray]:
    """Contact-GraspNet-schema grasps on the points of ``camera``'s depth image (inside ``mask``).

    Contacts are surface points seen by a camera, so one view of a convex object rarely holds both
    contacts of a grasp (its far side is hidden): add ``views`` of the object from other cameras (the
    other agent view, the eye-in-hand camera) or ``points_world`` seen earlier (the hand camera from
    another pose), and they join the cloud, in ``camera``'s frame.

    Args:
        obs: An L2 observation (``depth`` and ``cameras``).
        camera: Camera name (the frame of the answer).
        mask: (H, W) bool pixels of the object (e.g. a ``segment`` mask); None uses every pixel.
        views: Further (camera, mask) views of the same object in ``obs``.
        points_world: Further (M, 3) world points [m] of the object (e.g. ``world_points`` of an
            earlier observation).
        rng: Random source (default ``numpy.random.default_rng(0)``: the same answer for the same image).
        scene_radius: With a mask, the other points within this distance [m] of the object's points are
            obstacles the gripper must not enter (the counter under an object).
        **options: Passed to ``rle_design.sensors.grasps.antipodal_grasps`` (``num_samples``,
            ``friction_angle``, ``max_grasps`` ...).

    Returns:
        ``pred_grasps_cam`` (K, 4, 4), ``scores`` (K,), ``contact_pts`` (K, 3) [m], ``gripper_openings``
        (K,) [m], in the camera frame, best first (K may be 0).
    """
    rng = np.random.default_rng(0) if rng is None else rng
    cam_from_world = np.linalg.inv(np.asarray(obs["cameras"][camera]["world_from_camera"]))
    objects, rests = [], []
    for cam, m in ((camera, mask), *views):
        depth = np.asarray(obs["depth"][cam])
        K = np.asarray(obs["cameras"][cam]["K"])
        t = cam_from_world @ np.asarray(obs["cameras"][cam]["world_from_camera"])
        objects.append(deproject(depth, K, m) @ t[:3, :3].T + t[:3, 3])
        if m is not None:
            rests.append(deproject(depth, K, ~np.asarray(m, bool)) @ t[:3, :3].T + t[:3, 3])
    if points_world is not None:
        extra = np.asarray(points_world, float).reshape(-1, 3)
        objects.append(extra @ cam_from_world[:3, :3].T + cam_from_world[:3, 3])
    points = np.concatenate(objects)
    obstacles = None
    if rests and len(points):
        rest = np.concatenate(rests)
        lo, hi = points.min(axis=0) - scene_radius, points.max(axis=0) + scene_radius
        obstacles = rest[np.all((rest > lo) & (rest < hi), axis=1)]
        if len(obstacles) > 4000:
            obstacles = obstacles[np.sort(rng.choice(len(obstacles), 4000, replace=False))]
    return antipodal_grasps(points, rng, obstacles=obstacles, **options)


def tool_pose(grasp_cam: np.ndarray, obs: dict[str, Any], camera: str) -> tuple[np.ndarray, np.ndarray]:
    """World tool pose (position [m], quaternion w, x, y, z) of a ``pred_grasps_cam`` pose: the finger-tip
    centre and the gripper's orientation (x closing, z approach), for ``Motion.move_tool``."""
    world = np.asarray(obs["cameras"][camera]["world_from_camera"]) @ np.asarray(grasp_cam)
    return world[:3, :3] @ [0.0, 0.0, TIP_DEPTH] + world[:3, 3], mat_to_quat(world[:3, :3])
