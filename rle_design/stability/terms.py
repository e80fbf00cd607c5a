"""Episode terms for machines standing on supports (wheels, feet): support load and its loss."""

from __future__ import annotations

import mujoco

from rle_design.rollout import Event, Term
from rle_design.stability.contacts import SupportSet, support_normal_list
from rle_design.stability.support_loss import SupportLossMonitor

__all__ = ["SupportLoad", "SupportLost"]


class SupportLoad(Term):
    """Samples the normal force of every support every ``every`` steps (never ends an episode).

    Loads are averaged over the last ``smooth`` samples before they reach the monitor (the soft
    contacts of a statically indeterminate support chatter at the 0.1 mm scale).

    Args:
        supports: Support geoms and ground.
        weight: Weight shared by the supports, m g [N].
        fraction: Loss threshold as a fraction of the static share ``weight / n`` [1].
        duration: Time below the threshold that counts as a sustained loss [s].
        every: Physics steps between samples.
        smooth: Samples averaged.
    """

    name = "support_load"

    def __init__(
        self,
        supports: SupportSet,
        weight: float,
        fraction: float,
        duration: float,
        every: int,
        smooth: int = 10,
    ) -> None:
        self.supports, self.every, self.smooth = supports, every, smooth
        self.monitor = SupportLossMonitor(weight, len(supports.names), fraction, duration)
        self.window: list[list[float]] = []

    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> Event | None:
        window = self.window
        window.append(support_normal_list(model, data, self.supports))
        if len(window) > self.smooth:
            del window[0]
        # the mean as np.mean computes it (rows added in order, then one division), in plain floats
        total = list(window[0])
        for row in window[1:]:
            for i, f in enumerate(row):
                total[i] += f
        n = len(window)
        self.monitor.update(float(data.time), [f / n for f in total])
        return None

    @property
    def min_share(self) -> float:
        """Smallest smoothed support load over the episode, as a fraction of the static share [1]."""
        m = self.monitor
        return float(m.min_force.min()) / (m.weight / m.n_supports)


class SupportLost(Term):
    """Fails once the ``SupportLoad`` monitor has seen a sustained loss (checked every ``every`` steps)."""

    name = "support_lost"

    def __init__(self, load: SupportLoad, every: int, what: str = "support") -> None:
        self.load, self.every, self.what = load, every, what

    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> Event | None:
        m = self.load.monitor
        if not m.lost:
            return None
        msg = f"sustained loss of {self.what} ({m.longest_loss:.2f} s) at t = {data.time:.2f} s"
        return Event(self.name, "fail", msg, t)
