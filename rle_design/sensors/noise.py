"""Sensor noise models driven by an explicit ``numpy.random.Generator`` (never the global state).

Depth noise follows the structured-light / stereo model ``sigma(z) = k * z^2`` (e.g. ``k = 1.5e-3 /m``
gives 1.5 mm at 1 m and 6 mm at 2 m), plus independent pixel dropout. RGB noise is additive Gaussian
in 8-bit intensity units.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from rle_design.errors import RleError
from rle_design.sensors.rgbd import Frame


def _check(name: str, value: float, upper: float | None = None) -> None:
    if not np.isfinite(value) or value < 0 or (upper is not None and value > upper):
        bound = f"[0, {upper}]" if upper is not None else ">= 0"
        raise RleError(f"noise parameter {name}={value} must be finite and {bound}", code="sensor.noise")


@dataclass(frozen=True)
class DepthNoise:
    """Depth noise ``z' = z + N(0, (k z^2)^2)`` with pixel dropout.

    Attributes:
        k: Quadratic noise coefficient [1/m]: standard deviation at depth z is ``k * z**2`` [m].
        dropout: Probability that a valid pixel loses its depth (set to 0 and marked invalid).
    """

    k: float = 1.5e-3
    dropout: float = 0.0

    def __post_init__(self) -> None:
        _check("k", self.k)
        _check("dropout", self.dropout, 1.0)

    def sigma(self, z: np.ndarray | float) -> np.ndarray:
        """Standard deviation [m] at planar depth ``z`` [m]."""
        return self.k * np.square(z)

    def apply(
        self, depth: np.ndarray, valid: np.ndarray, rng: np.random.Generator
    ) -> tuple[np.ndarray, np.ndarray]:
        """Noisy copy of ``depth`` [m] and the updated validity mask (only valid pixels get noise)."""
        z = np.asarray(depth, dtype=np.float32)
        noisy = z + (rng.standard_normal(z.shape) * self.sigma(z)).astype(np.float32)
        out = np.where(valid, noisy, z).astype(np.float32)
        mask = np.asarray(valid, bool).copy()
        if self.dropout > 0:
            drop = (rng.random(z.shape) < self.dropout) & mask
            out[drop] = 0.0
            mask &= ~drop
        return out, mask


@dataclass(frozen=True)
class RgbNoise:
    """Additive Gaussian colour noise, clipped to [0, 255].

    Attributes:
        sigma: Standard deviation in 8-bit intensity units.
    """

    sigma: float = 2.0

    def __post_init__(self) -> None:
        _check("sigma", self.sigma)

    def apply(self, rgb: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """Noisy uint8 copy of ``rgb``."""
        noisy = (
            np.asarray(rgb, dtype=np.float32)
            + rng.standard_normal(np.shape(rgb)).astype(np.float32) * self.sigma
        )
        return np.clip(np.rint(noisy), 0, 255).astype(np.uint8)


def add_noise(
    frame: Frame, rng: np.random.Generator, depth: DepthNoise | None = None, rgb: RgbNoise | None = None
) -> Frame:
    """A new ``Frame`` with depth and/or RGB noise applied (segmentation and camera unchanged)."""
    out = frame
    if depth is not None:
        d, valid = depth.apply(frame.depth, frame.valid, rng)
        out = replace(out, depth=d, valid=valid)
    if rgb is not None:
        out = replace(out, rgb=rgb.apply(frame.rgb, rng))
    return out
