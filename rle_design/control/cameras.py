"""RGB views of a scene's named cameras, one offscreen renderer per (model, camera, size), reused.

The renderers are kept in a least-recently-used cache of ``MAX_RENDERERS``: each holds a GL context
with the model's meshes and textures uploaded (about 150 MB for a two-arm tabletop) and keeps its
model alive, so a process that builds a new scene per episode would otherwise grow without bound.

``render_rgbd`` of several cameras updates their scenes one after the other and then draws them in
parallel threads (EGL, more than one CPU): on a CPU renderer (Mesa llvmpipe) the vertex work of a draw
runs in the calling thread, so each camera's own context draws on its own core; the images are those
of drawing one after the other (each context draws only its own scene).
"""

from __future__ import annotations

import os
import threading
from collections import OrderedDict
from concurrent.futures import ThreadPoolExecutor

import mujoco
import numpy as np

from rle_design.sensors import RgbdSensor
from rle_design.sensors.gl import parallel_ok, release_current

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
    state, from one draw per camera (geoms only); ``box_quads`` as ``RgbdSensor``'s. Several cameras
    draw in parallel threads where ``PARALLEL`` allows (the same arrays as one after the other)."""
    sensors = [_sensor(model, name, size, box_quads) for name in cameras]
    pool = _pool(len(sensors)) if all(parallel_ok(s.backend) for s in sensors) else None
    if pool is None:
        views = [s.render_rgbd(data) for s in sensors]
    else:
        release_current(sensors[0].backend)  # a context current here cannot be made current by a worker
        futures = []
        for s in sensors:  # one scene at a time (culling writes the model), each drawn as soon as updated
            s.update_scene(data)
            futures.append(pool.submit(s.draw_rgbd))
        views = [f.result() for f in futures]
    return {n: v[0] for n, v in zip(cameras, views)}, {n: v[1] for n, v in zip(cameras, views)}


PARALLEL = os.environ.get("RLE_RENDER_THREADS", "1") != "0"
"""Draw the cameras of ``render_rgbd`` in parallel threads (on more than one CPU); the environment
variable ``RLE_RENDER_THREADS=0`` turns it off (e.g. where parallel workers already use every core)."""

_POOL: tuple[int, ThreadPoolExecutor] | None = None
_POOL_LOCK = threading.Lock()


def _pool(n: int) -> ThreadPoolExecutor | None:
    """The drawing threads of this process (a forked child makes its own), or None to draw in turn."""
    global _POOL
    if not PARALLEL or n < 2 or (os.cpu_count() or 1) < 2:
        return None
    with _POOL_LOCK:
        if _POOL is None or _POOL[0] != os.getpid():
            _POOL = (os.getpid(), ThreadPoolExecutor(max_workers=4, thread_name_prefix="rle-draw"))
        return _POOL[1]


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
