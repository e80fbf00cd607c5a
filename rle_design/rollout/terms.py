"""Episode terms: what an episode watches between physics chunks (termination, success, events).

A term is evaluated every ``every`` physics steps (a multiple of the episode's chunk, see
``episode.run_episode``), always after the physics of that chunk, in the order the terms are given.
It returns None to go on or an ``Event``: ``"fail"`` and ``"success"`` end the episode, ``"note"``
is recorded and the episode goes on.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import mujoco
import numpy as np

__all__ = [
    "ContactBetween",
    "Event",
    "HoldAtTarget",
    "SimulationWarnings",
    "Term",
    "TiltLimit",
    "root_tilt",
]

EventKind = Literal["fail", "success", "note"]


@dataclass(frozen=True)
class Event:
    """What a term reported.

    Attributes:
        term: Name of the term.
        kind: ``"fail"`` or ``"success"`` (both end the episode) or ``"note"``.
        message: Specific reason, with the time and the values involved.
        time: Episode time of the event [s].
    """

    term: str
    kind: EventKind
    message: str
    time: float

    @property
    def ends(self) -> bool:
        return self.kind != "note"


class Term(ABC):
    """Base of all terms.

    Attributes:
        name: Term name used in events.
        every: Physics steps between evaluations (>= 1).
    """

    name: str = "term"
    every: int = 1

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:  # noqa: B027 - optional hook
        """Called once before the first physics step of an episode."""

    @abstractmethod
    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> Event | None:
        """Evaluate after a chunk; ``t`` is the episode time [s]."""


def root_tilt(data: mujoco.MjData, body: int) -> float:
    """Angle between the body's z axis and the world z axis [rad]."""
    return float(math.acos(max(-1.0, min(1.0, float(data.xmat[body][8])))))


class TiltLimit(Term):
    """Fails when ``body``'s tilt exceeds ``max_deg``; keeps the peak tilt [deg]."""

    name = "tilt"

    def __init__(self, body: int, max_deg: float, every: int = 1, what: str = "tilt") -> None:
        self.body, self.max_deg, self.every, self.what = body, max_deg, every, what
        self.peak_deg = 0.0

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self.peak_deg = 0.0

    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> Event | None:
        tilt = math.degrees(root_tilt(data, self.body))
        self.peak_deg = max(self.peak_deg, tilt)
        if tilt > self.max_deg:
            msg = f"tipping: {self.what} {tilt:.1f} deg > {self.max_deg} deg at t = {data.time:.2f} s"
            return Event(self.name, "fail", msg, t)
        return None


class ContactBetween(Term):
    """Fails at the first contact between a geom of ``a`` and a geom of ``b``."""

    name = "contact"

    def __init__(self, ngeom: int, a: Sequence[int], b: Sequence[int], every: int = 1, what: str = "contact"):
        self.every, self.what = every, what
        self.mask_a = np.zeros(ngeom, dtype=bool)
        self.mask_a[np.asarray(a, dtype=int)] = True
        self.mask_b = np.zeros(ngeom, dtype=bool)
        self.mask_b[np.asarray(b, dtype=int)] = True
        self._a, self._b = self.mask_a.tolist(), self.mask_b.tolist()  # for the few-contact path

    def first_hit(self, model: mujoco.MjModel, data: mujoco.MjData) -> tuple[str, str] | None:
        """Names of the first offending geom pair, in the contact's geom order, or None."""
        n = data.ncon
        if not n:
            return None
        pairs = data.contact.geom
        if n <= 64:  # checked every physics step in some episodes: plain Python beats numpy here
            a, b = self._a, self._b
            for g1, g2 in pairs.tolist():
                if (a[g1] and b[g2]) or (a[g2] and b[g1]):
                    return model.geom(g1).name, model.geom(g2).name
            return None
        g1, g2 = pairs[:, 0], pairs[:, 1]
        bad = (self.mask_a[g1] & self.mask_b[g2]) | (self.mask_a[g2] & self.mask_b[g1])
        if not bad.any():
            return None
        c = int(np.argmax(bad))
        return model.geom(int(g1[c])).name, model.geom(int(g2[c])).name

    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> Event | None:
        hit = self.first_hit(model, data)
        if hit is None:
            return None
        msg = f"{self.what}: {hit[0]} touched {hit[1]} at t = {data.time:.2f} s"
        return Event(self.name, "fail", msg, t)


class HoldAtTarget(Term):
    """Succeeds once ``site`` has stayed within ``tolerance`` of ``target`` for ``hold_s``.

    The hold clock advances by ``period`` (the time between evaluations, ``every`` physics steps)
    per evaluation inside the tolerance and restarts outside it; the smallest distance is kept [m].
    """

    name = "hold"

    def __init__(
        self, site: int, target: np.ndarray, tolerance: float, hold_s: float, every: int, period: float
    ) -> None:
        self.site, self.target = site, np.asarray(target, dtype=float)
        self.tolerance, self.hold_s, self.every, self.period = tolerance, hold_s, every, period
        self.held, self.best = 0.0, math.inf

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self.held, self.best = 0.0, math.inf

    def error(self, data: mujoco.MjData) -> float:
        return float(np.linalg.norm(data.site_xpos[self.site] - self.target))

    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> Event | None:
        err = self.error(data)
        self.best = min(self.best, err)
        self.held = self.held + self.period if err <= self.tolerance else 0.0
        if self.held >= self.hold_s - 1e-9:
            return Event(self.name, "success", "held", t)
        return None


class SimulationWarnings(Term):
    """Fails when a MuJoCo warning counter (``data.warning``) grows during the episode.

    A diverging or overflowing simulation (bad qacc, contact or constraint buffer full, NaN in the
    state) is never a pass; the event names the warning.
    """

    name = "warning"

    def __init__(self, every: int = 1, final: bool = True) -> None:
        self.every, self.final = every, final  # final: also checked after the last step
        self._start = np.zeros(0, dtype=int)

    @staticmethod
    def counts(data: mujoco.MjData) -> np.ndarray:
        """Occurrences of each warning so far (index = ``mujoco.mjtWarning``)."""
        return np.array(data.warning.number, dtype=int)  # one array read, not one object per warning

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self._start = self.counts(data)

    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> Event | None:
        grown = np.flatnonzero(self.counts(data) > self._start)
        if grown.size == 0:
            return None
        names = ", ".join(mujoco.mjtWarning(int(i)).name for i in grown)
        return Event(self.name, "fail", f"simulation warning {names} at t = {data.time:.3f} s", t)
