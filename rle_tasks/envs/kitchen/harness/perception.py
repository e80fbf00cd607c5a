"""Level 2: perception tools (public, laid into the workspace).

``segment(client, prompt, camera)`` asks the simulator's segmenter (a stand-in for SAM3: instance masks
of a text prompt from the simulator's segmentation, with noise) and returns SAM3's output schema:
``masks`` (N, H, W) bool, ``boxes`` (N, 4) x0 y0 x1 y1 [px], ``scores`` (N,). Prompts match instance
labels word by word: ``"handle"`` finds every handle, ``"fridge handle"`` the fridge's, ``"apple"`` the
apples; labels are object categories and fixture parts (``fridge door``, ``cabinet door``, ``drawer``,
``front left knob``, ``rear right burner``, ``counter``, ``sink basin``, ``microwave``, ``plate`` ...).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .geometry import world_points

__all__ = ["object_points", "segment"]


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
