"""Baseline: returns NaN (fails the interface gate: non-finite output)."""


def reset():
    return None


def update(obs):
    return (float("nan"), 0.0, 0.0, 0)
