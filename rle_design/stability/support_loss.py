"""Loss of support: a support's normal force below a fraction of its static share for too long."""

from __future__ import annotations

import math
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
    _since: list = field(init=False, repr=False)
    _longest: list = field(init=False, repr=False)
    _min: list = field(init=False, repr=False)

    def __post_init__(self) -> None:
        # plain lists: a few supports, updated every few physics steps of long episodes
        self._since = [math.nan] * self.n_supports
        self._longest = [0.0] * self.n_supports
        self._min = [math.inf] * self.n_supports

    @property
    def threshold(self) -> float:
        """Normal-force threshold [N]."""
        return self.fraction * self.weight / self.n_supports

    @property
    def longest(self) -> np.ndarray:
        """Longest continuous time below the threshold, per support [s]."""
        return np.array(self._longest)

    @property
    def min_force(self) -> np.ndarray:
        """Smallest normal force seen, per support (NaN once a NaN was seen) [N]."""
        return np.array(self._min)

    def update(self, t: float, normal: np.ndarray | list[float]) -> None:
        """Record normal forces ``normal`` [N] at time ``t`` [s] (calls must have increasing t)."""
        threshold, since, longest, low = self.threshold, self._since, self._longest, self._min
        values = normal if isinstance(normal, list) else np.asarray(normal, dtype=float).tolist()
        for i, f in enumerate(values):
            m = low[i]
            if f != f or m != m:  # np.minimum: NaN wins
                low[i] = math.nan
            elif f < m:
                low[i] = f
            if f < threshold:
                start = since[i]
                if start != start:
                    since[i] = start = t
                run = t - start
                if run > longest[i]:
                    longest[i] = run
            else:
                since[i] = math.nan  # a run of 0: longest (>= 0) stays

    @property
    def lost(self) -> bool:
        """True once any support stayed below the threshold longer than ``min_duration``."""
        return any(run > self.min_duration for run in self._longest)

    @property
    def longest_loss(self) -> float:
        """Longest continuous time any support spent below the threshold [s]."""
        return float(max(self._longest, default=0.0))
