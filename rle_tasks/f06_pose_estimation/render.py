"""Rendering evaluation items into observations and labels (verifier side and development server).

An observation is the dict handed to ``estimator.update``: ``rgb`` ``(240, 320, 3)`` uint8, ``t``
[s], ``K`` ``(3, 3)`` intrinsics [px] and ``T_world_cam`` ``(4, 4)`` (OpenCV camera to world [m]),
plus ``depth`` ``(240, 320)`` float32 planar depth [m] and ``valid`` ``(240, 320)`` bool for the
RGB-D variants (B, C, D). Labels carry the pose, the shape and the block's visible fraction.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

import numpy as np

from rle_design.scene import Variation, element_id
from rle_design.sensors import RgbdSensor, add_noise

from .appearance import BLOCK_GEOMS, SensorNoise
from .episodes import FrameSpec
from .scene import CAMERA, HEIGHT_PX, WIDTH, PoseScene

OCCLUDED_BELOW = 0.9
"""A frame counts as occluded when less than this share of the block's pixels is visible."""


@dataclass(frozen=True)
class Label:
    """Ground truth of one frame.

    Attributes:
        pose: ``(x, y, theta, shape)`` [m, m, rad, id].
        visible: Visible share of the block's pixels (1 when nothing covers it).
    """

    pose: np.ndarray
    visible: float

    @property
    def occluded(self) -> bool:
        return self.visible < OCCLUDED_BELOW


class Renderer:
    """Renders frames of one scene model; owns the GL context (close it, or use ``with``).

    Args:
        model: Compiled scene (``scene.compile_scene``).
        depth: Put ``depth`` and ``valid`` into observations.
    """

    def __init__(self, model, depth: bool = True) -> None:
        self.base = copy.deepcopy(model)  # pristine: appearance terms apply to the nominal model
        self.scene = PoseScene(model)
        self.depth = depth
        self.sensor = RgbdSensor(model, CAMERA, WIDTH, HEIGHT_PX, segmentation=True)
        self._block_geoms = np.array([element_id(model, "geom", g) for g in BLOCK_GEOMS])
        self._robot_geoms = np.array(
            [g for g in range(model.ngeom) if (model.geom(g).name or "").startswith("panda/")]
        )

    def __enter__(self) -> Renderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self.sensor.close()

    def apply(self, variation: Variation) -> None:
        """Use the appearance of ``variation`` (applied to the shared model in place)."""
        fresh = variation.apply(self.base)
        m = self.sensor.model
        m.vis.headlight.diffuse = fresh.vis.headlight.diffuse
        m.light_dir[:] = fresh.light_dir
        m.mat_rgba[:] = fresh.mat_rgba
        m.geom_rgba[:] = fresh.geom_rgba

    def render(
        self, frames: list[FrameSpec], noise: SensorNoise, rng: np.random.Generator
    ) -> tuple[list[dict], list[Label]]:
        """Observations and labels of ``frames`` (the arm starts at home and warm-starts from frame to frame)."""
        obs, labels = [], []
        scene, m = self.scene, self.sensor.model
        scene.set_arm(scene.home)  # every item starts from the same arm pose (determinism)
        for f in frames:
            scene.set_block(f.pose)
            scene.reach(np.asarray(f.tip))
            scene.forward()
            frame = self.sensor.render(scene.data)
            ids = frame.geom_ids()
            seen = int(np.isin(ids, self._block_geoms).sum())
            alpha = m.geom_rgba[self._robot_geoms, 3].copy()
            m.geom_rgba[self._robot_geoms, 3] = 0.0
            try:
                full = int(np.isin(self.sensor.render(scene.data).geom_ids(), self._block_geoms).sum())
            finally:
                m.geom_rgba[self._robot_geoms, 3] = alpha
            frame = add_noise(frame, rng, depth=noise.depth if self.depth else None, rgb=noise.rgb)
            cam = frame.camera
            o = {
                "rgb": frame.rgb,
                "t": float(f.t),
                "K": cam.intrinsics.matrix,
                "T_world_cam": cam.world_from_camera.copy(),
            }
            if self.depth:
                o["depth"] = frame.depth.astype(np.float32)
                o["valid"] = frame.valid.copy()
            obs.append(o)
            labels.append(Label(f.pose.as_array(), seen / full if full else 0.0))
        return obs, labels
