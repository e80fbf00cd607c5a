"""Loss of support: a support's normal force below a fraction of its static share for too long."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["SupportLossMonitor"]


@dataclass
class SupportLossMonitor:
    """Tracks, per support, how long its normal force stays below ``fraction * weight / n``.

    Attributes:
        weight: Total weight m g [N].
        n_supports: Number of supports sharing it.
        fraction: Threshold as a fraction of the static share weight / n [1].
        min_duration: Duration below the threshold that counts as a sustained loss [s].
    """

    weight: float
    n_supports: int
    fraction: float = 0.05
    min_duration: float = 0.1
    _below_since: np.ndarray = field(init=False, repr=False)
    longest: np.ndarray = field(init=False)
    min_force: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self._below_since = np.full(self.n_supports, np.nan)
        self.longest = np.zeros(self.n_supports)
        self.min_force = np.full(self.n_supports, np.inf)

    @property
    def threshold(self) -> float:
        """Normal-force threshold [N]."""
        return self.fraction * self.weight / self.n_supports

    def update(self, t: float, normal: np.ndarray) -> None:
        """Record normal forces ``normal`` [N] at time ``t`` [s] (calls must have increasing t)."""
        normal = np.asarray(normal, dtype=float)
        self.min_force = np.minimum(self.min_force, normal)
        below = normal < self.threshold
        start = np.isnan(self._below_since) & below
        self._below_since[start] = t
        self._below_since[~below] = np.nan
        run = np.where(below, t - self._below_since, 0.0)
        self.longest = np.fmax(self.longest, run)  # run is NaN-free; fmax would skip a NaN

    @property
    def lost(self) -> bool:
        """True once any support stayed below the threshold longer than ``min_duration``."""
        return bool(np.any(self.longest > self.min_duration))

    @property
    def longest_loss(self) -> float:
        """Longest continuous time any support spent below the threshold [s]."""
        return float(self.longest.max(initial=0.0))
