"""Baseline ``idle``: holds the start posture with the magnet off; it never picks (clears nothing)."""

import numpy as np

_q = None


def make_policy():
    return None


def reset():
    global _q
    _q = None


def act(obs):
    global _q
    if _q is None:
        _q = np.asarray(obs["q"], dtype=float).copy()
    return np.concatenate([_q, [0.0]])
