"""The programs' kitchen frame: every observation turned about the world z so that the fixture the robot
starts in front of faces -y, as in a one-wall kitchen.

The programs were written for fixtures whose fronts face world -y (the one-wall kitchen) and reason in
world axes. Every layout kind's runs meet at right angles and the robot starts facing its target
fixture, heading ``yaw + pi/2`` within 0.05 rad (``yaw``: the fixture's facing, a multiple of pi/2),
so at any level the episode's first ``base_yaw`` gives the run's yaw: ``yaw`` = the multiple of pi/2
nearest ``base_yaw - pi/2``. ``Straightened`` serves a client's observations turned by ``-yaw`` and,
where the L3 world state shows the run (its floor-standing fixtures), shifted so that the run's back
line is y = 0, as the one-wall kitchen's wall (the L2 and L1 programs get the turn only); the actions
need no turn, as every one is in the base's frame (tool deltas, base velocities). With ``yaw`` = 0
(one-wall kitchens, and every kind's first run, whose back line is y = 0) observations pass through
untouched.

World-frame entries turned: ``base_pos``, ``base_yaw``, ``ee_pos``, ``ee_quat``; L2 ``cameras``'
``world_from_camera``; L3 ``objects`` (``pos``, ``quat``) and ``fixtures`` (``pos``, ``yaw``,
``facing``, ``sites``, ``interior`` centre and orientation, ``<part>_pos``/``<part>_quat``). Only
numpy is imported: the Harbor oracle ships this module with the programs.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["Straightened", "run_yaw"]


def run_yaw(base_yaw: float) -> float:
    """The multiple of pi/2 nearest ``base_yaw - pi/2`` [rad] (0.0 for a one-wall kitchen)."""
    k = int(np.round((base_yaw - np.pi / 2) / (np.pi / 2))) % 4
    return 0.0 if k == 0 else float(k * np.pi / 2)


def _wrap(a: float) -> float:
    return float((a + np.pi) % (2 * np.pi) - np.pi)


class Straightened:
    """A ``LedgerClient`` look-alike serving ``client``'s observations in the straightened frame."""

    def __init__(self, client: Any) -> None:
        self.client = client
        self.yaw = 0.0
        self.shift = np.zeros(3)

    def _turn(self, obs: dict[str, Any], reset: bool) -> dict[str, Any]:
        if reset:
            self.yaw = run_yaw(float(obs["base_yaw"]))
        if self.yaw == 0.0:
            return obs
        c, s = np.cos(-self.yaw), np.sin(-self.yaw)
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        if reset:
            self.shift = np.zeros(3)
            if "fixtures" in obs:  # the back line of the run: its floor-standing fixtures' backs
                backs = [
                    (rot @ np.asarray(f["pos"], float))[1] + float(f["size"][1]) / 2
                    for f in obs["fixtures"].values()
                    if float(f["pos"][2]) == 0.0 and abs(_wrap(float(f["yaw"]) - self.yaw)) < 1e-6
                ]
                self.shift[1] = -max(backs)
        qz = np.array([np.cos(-self.yaw / 2), 0.0, 0.0, np.sin(-self.yaw / 2)])
        p = lambda v: rot @ np.asarray(v, float) + self.shift  # noqa: E731
        q = lambda v: _qmul(qz, np.asarray(v, float))  # noqa: E731
        out = dict(obs)
        out["base_pos"], out["ee_pos"], out["ee_quat"] = (
            p(obs["base_pos"]),
            p(obs["ee_pos"]),
            q(obs["ee_quat"]),
        )
        out["base_yaw"] = _wrap(float(obs["base_yaw"]) - self.yaw)
        if "cameras" in obs:
            t = np.eye(4)
            t[:3, :3], t[:3, 3] = rot, self.shift
            out["cameras"] = {
                k: {**v, "world_from_camera": t @ np.asarray(v["world_from_camera"])}
                for k, v in obs["cameras"].items()
            }
        if "objects" in obs:
            out["objects"] = {
                k: {**o, "pos": p(o["pos"]), "quat": q(o["quat"])} for k, o in obs["objects"].items()
            }
        if "fixtures" in obs:
            out["fixtures"] = {k: self._fixture(f, p, q) for k, f in obs["fixtures"].items()}
        return out

    def _fixture(self, f: dict[str, Any], p, q) -> dict[str, Any]:
        g = dict(f)
        g["pos"] = p(f["pos"])
        if "yaw" in f:
            g["yaw"] = _wrap(float(f["yaw"]) - self.yaw)
            g["facing"] = (p([*np.asarray(f["facing"], float)[:2], 0.0]) - self.shift)[
                :2
            ]  # a direction: not shifted
        g["sites"] = {k: p(v) for k, v in f["sites"].items()}
        if "interior" in f:
            g["interior"] = {
                **f["interior"],
                "center": p(f["interior"]["center"]),
                "quat": q(f["interior"]["quat"]),
            }
        for key, v in f.items():
            if key.endswith("_pos") and key != "pos":
                g[key] = p(v)
            elif key.endswith("_quat"):
                g[key] = q(v)
        return g

    def reset(self, **options: Any) -> dict[str, Any]:
        return self._turn(self.client.reset(**options), reset=True)

    def step(self, action: Any) -> dict[str, Any]:
        return self._turn(self.client.step(action), reset=False)

    def observe(self) -> dict[str, Any]:
        return self._turn(self.client.observe(), reset=False)

    def query(self, name: str, **args: Any) -> Any:
        return self.client.query(name, **args)  # image-space answers (segmentation masks): not turned

    def info(self) -> dict[str, Any]:
        return self.client.info()


def _qmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )
