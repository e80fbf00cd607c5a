"""RGB views of a scene's named cameras, one offscreen renderer per (model, camera, size), reused.

The renderers are kept in a least-recently-used cache of ``MAX_RENDERERS``: each holds a GL context
with the model's meshes and textures uploaded (about 150 MB for a two-arm tabletop) and keeps its
model alive, so a process that builds a new scene per episode would otherwise grow without bound.

``render_rgbd`` of several cameras updates their scenes one after the other and then draws them in
parallel threads (EGL, more than one CPU, a core idle; ``PARALLEL``): on a CPU renderer (Mesa llvmpipe) the vertex work of a draw
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
    draw in parallel threads where ``PARALLEL`` says so (the same arrays as one after the other)."""
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


PARALLEL = os.environ.get("RLE_RENDER_THREADS", "auto")
"""When ``render_rgbd`` draws its cameras in parallel threads (on more than one CPU): ``"auto"`` (the
default) where a core is idle at the call (``_core_idle``), ``"1"`` always, ``"0"`` never; from the
environment variable ``RLE_RENDER_THREADS``. Idle cores matter: with every core busy (parallel workers,
the test suite) the threads' context switches cost more than they save (two workers on two cores: 58 s
against 27 s drawing in turn, 2026-11-28)."""

_POOL: tuple[int, ThreadPoolExecutor] | None = None
_POOL_LOCK = threading.Lock()


def _cpus() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def _core_idle() -> bool:
    """Whether fewer threads are runnable now (``/proc/loadavg``'s fourth field, this one included)
    than this process may use CPUs; False where that is unknown."""
    try:
        with open("/proc/loadavg", "rb") as f:
            running = int(f.read().split()[3].split(b"/")[0])
    except (OSError, ValueError, IndexError):
        return False
    return running < _cpus()


def _pool(n: int) -> ThreadPoolExecutor | None:
    """The drawing threads of this process (a forked child makes its own), or None to draw in turn."""
    global _POOL
    if PARALLEL == "0" or n < 2 or _cpus() < 2 or (PARALLEL != "1" and not _core_idle()):
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
