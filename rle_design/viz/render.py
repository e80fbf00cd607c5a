"""Offscreen PNG renders on CPU (MUJOCO_GL=egl by default, osmesa as a fallback).

A free camera is aimed at the model's bounding box unless ``lookat``/``distance`` are given.
"""

from __future__ import annotations

import os
from pathlib import Path

import mujoco
import numpy as np

from rle_design.errors import RleError

os.environ.setdefault("MUJOCO_GL", "egl")


def model_extent(model: mujoco.MjModel, data: mujoco.MjData) -> tuple[np.ndarray, float]:
    """Centre [m] and radius [m] of the axis-aligned box around all non-plane geoms."""
    keep = model.geom_type != mujoco.mjtGeom.mjGEOM_PLANE
    if not keep.any():
        return np.zeros(3), 1.0
    centres = data.geom_xpos[keep]
    r = model.geom_rbound[keep][:, None]
    lo, hi = (centres - r).min(0), (centres + r).max(0)
    return (lo + hi) / 2, float(np.linalg.norm(hi - lo) / 2)


def collision_shadow_geoms(model: mujoco.MjModel) -> np.ndarray:
    """Ids of collision geoms on bodies that also carry visual-only geoms (hidden in renders)."""
    visual = (model.geom_contype == 0) & (model.geom_conaffinity == 0)
    bodies_with_visual = np.unique(model.geom_bodyid[visual])
    colliding = ~visual & np.isin(model.geom_bodyid, bodies_with_visual)
    colliding &= model.geom_type != mujoco.mjtGeom.mjGEOM_PLANE
    return np.flatnonzero(colliding)


def _ensure_offscreen(model: mujoco.MjModel, width: int, height: int) -> None:
    model.vis.global_.offwidth = max(int(model.vis.global_.offwidth), width)
    model.vis.global_.offheight = max(int(model.vis.global_.offheight), height)


def render_image(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    *,
    width: int = 640,
    height: int = 480,
    lookat: np.ndarray | None = None,
    distance: float | None = None,
    azimuth: float = 135.0,
    elevation: float = -20.0,
    shadows: bool = True,
    groups: tuple[int, ...] = (),
    sites: bool = True,
) -> np.ndarray:
    """RGB image (H x W x 3, uint8) from a free camera.

    Args:
        lookat: Point the camera looks at [m]; default the centre of the model.
        distance: Camera distance [m]; default 2.2 x the model radius.
        azimuth: [deg]. elevation: [deg], negative looks down.
        groups: Geom groups drawn besides 0-2 (e.g. a robot's detailed visual meshes kept in group 3
            for fast sensor renders).
        sites: Draw sites (markers).
    """
    _ensure_offscreen(model, width, height)
    centre, radius = model_extent(model, data)
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    cam.lookat[:] = centre if lookat is None else np.asarray(lookat, float)
    cam.distance = 2.2 * max(radius, 0.1) if distance is None else float(distance)
    cam.azimuth, cam.elevation = azimuth, elevation
    opt = mujoco.MjvOption()
    for g in groups:
        opt.geomgroup[g] = 1
    if not sites:
        opt.sitegroup[:] = 0
    try:
        renderer = mujoco.Renderer(model, height=height, width=width)
    except Exception as exc:  # no GL context available: say how to get one
        raise RleError(
            f"offscreen rendering unavailable (MUJOCO_GL={os.environ.get('MUJOCO_GL')}): {exc}. "
            "MUJOCO_GL must be set before mujoco is first imported; Mesa EGL/OSMesa: bash scripts/apt-deps.sh",
            code="render.unavailable",
        ) from None
    hidden = collision_shadow_geoms(model)
    saved = model.geom_rgba[hidden].copy()
    model.geom_rgba[hidden, 3] = 0.0
    try:
        with renderer:
            renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = shadows
            renderer.update_scene(data, camera=cam, scene_option=opt)
            return renderer.render().copy()
    finally:
        model.geom_rgba[hidden] = saved


def save_png(image: np.ndarray, path: str | os.PathLike) -> Path:
    from PIL import Image

    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(image).save(p)
    return p


def render_png(model: mujoco.MjModel, data: mujoco.MjData, path: str | os.PathLike, **kwargs) -> Path:
    """Render with ``render_image`` and write a PNG; returns the path."""
    return save_png(render_image(model, data, **kwargs), path)


def render_views(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    path: str | os.PathLike,
    views: list[tuple[str, dict]],
    *,
    width: int = 480,
    height: int = 360,
) -> Path:
    """Several labelled views side by side in one PNG (e.g. front, side, top)."""
    from PIL import Image, ImageDraw

    tiles = []
    for title, kw in views:
        img = Image.fromarray(render_image(model, data, width=width, height=height, **kw))
        ImageDraw.Draw(img).text((8, 6), title, fill=(20, 20, 20))
        tiles.append(img)
    sheet = Image.new("RGB", (width * len(tiles), height), "white")
    for i, t in enumerate(tiles):
        sheet.paste(t, (i * width, 0))
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    sheet.save(p)
    return p
