"""RGB views of a scene's named cameras, one offscreen renderer per (model, camera, size), reused.

The renderers are kept in a least-recently-used cache of ``MAX_RENDERERS``: each holds a GL context
with the model's meshes and textures uploaded (about 150 MB for a two-arm tabletop) and keeps its
model alive, so a process that builds a new scene per episode would otherwise grow without bound.
"""

from __future__ import annotations

from collections import OrderedDict

import mujoco
import numpy as np

from rle_design.sensors import RgbdSensor

__all__ = ["MAX_RENDERERS", "close_renderers", "render_rgb", "render_rgbd"]

MAX_RENDERERS = 8
"""Renderers kept at once: the views of two or three live scenes (a kitchen has three cameras)."""

_SENSORS: OrderedDict[tuple[int, str, tuple[int, int], int | None], tuple[mujoco.MjModel, RgbdSensor]] = (
    OrderedDict()
)


def render_rgb(
    model: mujoco.MjModel, data: mujoco.MjData, cameras: tuple[str, ...], size: tuple[int, int]
) -> dict[str, np.ndarray]:
    """Camera name -> (H, W, 3) uint8 image of the current state (``size`` = (H, W) [px]); geoms only,
    as a real camera sees them (no site markers)."""
    return {name: _sensor(model, name, size).render(data).rgb for name in cameras}


def render_rgbd(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    cameras: tuple[str, ...],
    size: tuple[int, int],
    box_quads: int | None = None,
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """(camera -> (H, W, 3) uint8 colour, camera -> (H, W) float32 metric depth [m]) of the current
    state, from one draw per camera (geoms only); ``box_quads`` as ``RgbdSensor``'s."""
    rgb, depth = {}, {}
    for name in cameras:
        frame = _sensor(model, name, size, box_quads).render(data)
        rgb[name], depth[name] = frame.rgb, frame.depth
    return rgb, depth


def _sensor(
    model: mujoco.MjModel, name: str, size: tuple[int, int], box_quads: int | None = None
) -> RgbdSensor:
    key = (id(model), name, tuple(size), box_quads)
    entry = _SENSORS.get(key)
    if entry is not None and entry[0] is model:
        _SENSORS.move_to_end(key)
        return entry[1]
    if entry is not None:  # a freed model's id reused by a new one
        _SENSORS.pop(key)[1].close()
    while len(_SENSORS) >= MAX_RENDERERS:
        _SENSORS.popitem(last=False)[1][1].close()
    sensor = RgbdSensor(
        model, name, size[1], size[0], fast=True, segmentation=False, sites=False, box_quads=box_quads
    )
    _SENSORS[key] = (model, sensor)
    return sensor


def close_renderers() -> None:
    """Free every renderer (GL contexts)."""
    for _, sensor in _SENSORS.values():
        sensor.close()
    _SENSORS.clear()
