"""Appearance variations: lighting, table tint and block colour jitter that the hidden set perturbs.

Each term is a ``rle_design.scene.Perturbation`` applied to a compiled model (``Variation.apply``
returns a perturbed copy). Camera noise is drawn beside it as a ``SensorNoise``. Ranges are
development-visible; the draws of the hidden set come from the secret.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.scene import Perturbation, Uniform, VariationSpace, element_id
from rle_design.sensors import DepthNoise, RgbNoise

from .scene import BLOCK_RGBA, TABLE_RGBA
from .shapes import BLOCKS


@dataclass(frozen=True)
class HeadlightScale(Perturbation):
    """One factor on the headlight's diffuse colour (the main light of the scene)."""

    name: str
    range: Uniform
    neutral: float = 1.0

    def edit_spec(self, spec: mujoco.MjSpec, values: tuple[float, ...]) -> None:
        spec.visual.headlight.diffuse = list(np.asarray(spec.visual.headlight.diffuse) * values[0])

    def apply(self, model: mujoco.MjModel, values: tuple[float, ...]) -> None:
        model.vis.headlight.diffuse = np.asarray(model.vis.headlight.diffuse) * values[0]


@dataclass(frozen=True)
class KeyLightTilt(Perturbation):
    """Tilt of the key light's direction: x and y components of its (normalised) direction [1]."""

    name: str
    range: Uniform
    light: str = "key"
    neutral: float = 0.0

    @property
    def size(self) -> int:
        return 2

    def edit_spec(self, spec: mujoco.MjSpec, values: tuple[float, ...]) -> None:
        spec.light(self.light).dir = [values[0], values[1], -1.0]

    def apply(self, model: mujoco.MjModel, values: tuple[float, ...]) -> None:
        v = np.array([values[0], values[1], -1.0])
        model.light_dir[element_id(model, "light", self.light)] = v / np.linalg.norm(v)


@dataclass(frozen=True)
class Tint(Perturbation):
    """Per-channel factors on the RGB of a material or of geoms (3 values)."""

    name: str
    range: Uniform
    base: tuple[float, float, float, float]
    material: str = ""
    geoms: tuple[str, ...] = ()
    neutral: float = 1.0

    @property
    def size(self) -> int:
        return 3

    def _rgba(self, values: tuple[float, ...]) -> np.ndarray:
        rgba = np.array(self.base, float)
        rgba[:3] = np.clip(rgba[:3] * np.asarray(values), 0.0, 1.0)
        return rgba

    def edit_spec(self, spec: mujoco.MjSpec, values: tuple[float, ...]) -> None:
        if self.material:
            spec.material(self.material).rgba = list(self._rgba(values))
        for g in self.geoms:
            spec.geom(g).rgba = list(self._rgba(values))

    def apply(self, model: mujoco.MjModel, values: tuple[float, ...]) -> None:
        if self.material:
            model.mat_rgba[element_id(model, "material", self.material)] = self._rgba(values)
        for g in self.geoms:
            model.geom_rgba[element_id(model, "geom", g)] = self._rgba(values)


BLOCK_GEOMS = tuple(f"block_{b.name}_{j}" for b in BLOCKS for j in range(len(b.boxes)))
"""Every block geom (they share one colour)."""

APPEARANCE = VariationSpace(
    (
        HeadlightScale("headlight", Uniform(0.7, 1.25, "1")),
        KeyLightTilt("key_tilt", Uniform(-0.6, 0.6, "1")),
        Tint("table_tint", Uniform(0.75, 1.1, "1"), TABLE_RGBA, material="table_mat"),
        Tint("block_tint", Uniform(0.8, 1.15, "1"), BLOCK_RGBA, geoms=BLOCK_GEOMS),
    )
)
"""Appearance terms drawn per evaluation group."""


@dataclass(frozen=True)
class SensorNoise:
    """Camera noise of one evaluation group.

    Attributes:
        rgb_sigma: Colour noise standard deviation [8-bit units].
        depth_k: Quadratic depth noise coefficient [1/m].
        dropout: Depth dropout probability [1].
    """

    rgb_sigma: float
    depth_k: float
    dropout: float

    @classmethod
    def sample(cls, rng: np.random.Generator) -> SensorNoise:
        """Draw from the published ranges: sigma 1-4, k 1e-3-2.5e-3 1/m, dropout 0-2 %."""
        return cls(
            float(rng.uniform(1.0, 4.0)), float(rng.uniform(1e-3, 2.5e-3)), float(rng.uniform(0, 0.02))
        )

    @property
    def rgb(self) -> RgbNoise:
        return RgbNoise(self.rgb_sigma)

    @property
    def depth(self) -> DepthNoise:
        return DepthNoise(self.depth_k, self.dropout)
