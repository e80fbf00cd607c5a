"""Baseline ``bin_slammer``: swings the magnet between the look pose and a point 60 mm inside the bin's
far wall every 2 s, on joint-space paths at full servo speed: repeated hard bin impacts (``N_bin``),
nothing cleared."""

import numpy as np

from .kinematics import ik_down

LOOK = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 1.9, 0.785])
WALL = np.array([0.50, 0.17, 0.50 + 0.15 - 0.40])  # flange in the base frame: stem into the +y wall
_state = {}


def make_policy():
    _state["hit"], _ = ik_down(WALL, 0.0, LOOK)


def reset():
    _state["t0"] = None


def act(obs):
    if _state.get("t0") is None:
        _state["t0"] = float(obs["time"])
    phase = int((float(obs["time"]) - _state["t0"]) // 2.0) % 2
    return np.concatenate([_state["hit"] if phase else LOOK, [0.0]])
