"""RGB views of a scene's named cameras, one offscreen renderer per (model, camera, size), reused."""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.sensors import RgbdSensor

__all__ = ["close_renderers", "render_rgb"]

_SENSORS: dict[tuple[int, str, tuple[int, int]], tuple[mujoco.MjModel, RgbdSensor]] = {}


def render_rgb(
    model: mujoco.MjModel, data: mujoco.MjData, cameras: tuple[str, ...], size: tuple[int, int]
) -> dict[str, np.ndarray]:
    """Camera name -> (H, W, 3) uint8 image of the current state (``size`` = (H, W) [px]); geoms only,
    as a real camera sees them (no site markers)."""
    out = {}
    for name in cameras:
        key = (id(model), name, tuple(size))
        entry = _SENSORS.get(key)
        if entry is None or entry[0] is not model:
            entry = _SENSORS[key] = (
                model,
                RgbdSensor(model, name, size[1], size[0], fast=True, segmentation=False, sites=False),
            )
        out[name] = entry[1].render(data).rgb
    return out


def close_renderers() -> None:
    """Free every renderer (GL contexts)."""
    for _, sensor in _SENSORS.values():
        sensor.close()
    _SENSORS.clear()
