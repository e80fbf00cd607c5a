"""Perception: the segmenter's instance masks turned into world point clouds with the depth images.

``segment(client, prompt, camera)`` asks the simulator's segmenter (SAM3 schema: ``masks`` (N, H, W)
bool, ``boxes``, ``scores``). A prompt matches every instance whose label holds all its words:
``"drawer"`` finds drawers, drawer cabinets and drawer cabinet handles, ``"cabinet door"`` base and
wall cabinet doors; filter the points by where they are (``in_box``). Masks are noisy (a pixel or two
at the boundary, small instances sometimes missed), so clouds are cleaned around their median and a
miss is retried on the next image.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .geometry import world_points
from .robot import CAMERAS

__all__ = ["HAND", "clean", "clouds", "in_box", "merged", "segment"]

HAND = "robot/arm/eye_in_hand"
"""The eye-in-hand camera (looks along the tool's z axis)."""


def segment(client: Any, prompt: str, camera: str) -> dict[str, np.ndarray]:
    """SAM3-schema instance masks of ``prompt`` in ``camera``'s current image (a free query)."""
    return client.query("segment", prompt=prompt, camera=camera)


def clean(pts: np.ndarray, radius: float) -> np.ndarray:
    """The points within ``radius`` [m] of their median (drops background pixels of a noisy mask)."""
    if len(pts) == 0:
        return pts
    return pts[np.linalg.norm(pts - np.median(pts, axis=0), axis=1) < radius]


def clouds(
    client: Any,
    obs: dict[str, Any],
    prompt: str,
    cameras: Sequence[str] = CAMERAS,
    min_pixels: int = 1,
    max_depth: float = 4.0,
) -> list[tuple[str, np.ndarray]]:
    """(camera, world points [m]) of every instance of ``prompt`` seen in ``cameras`` (no cleaning)."""
    out = []
    for cam in cameras:
        seg = segment(client, prompt, cam)
        for mask in seg["masks"]:
            if int(mask.sum()) < min_pixels:
                continue
            depth = np.asarray(obs["depth"][cam])
            pts = world_points(obs, cam, np.asarray(mask, bool) & (depth < max_depth))
            if len(pts):
                out.append((cam, pts))
    return out


def in_box(pts: np.ndarray, lo: Sequence[float], hi: Sequence[float]) -> np.ndarray:
    """The points inside the world box [lo, hi] [m] (use +-inf for an open side)."""
    if len(pts) == 0:
        return pts
    return pts[np.all((pts >= np.asarray(lo)) & (pts <= np.asarray(hi)), axis=1)]


def merged(found: list[tuple[str, np.ndarray]]) -> np.ndarray:
    """All points of ``clouds``' answer in one (N, 3) array."""
    return np.concatenate([p for _, p in found]) if found else np.zeros((0, 3))
