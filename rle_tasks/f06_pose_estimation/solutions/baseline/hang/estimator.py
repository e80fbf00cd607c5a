"""Baseline: never returns from update (a hang: the per-call cap ends the run)."""

import time


def reset():
    return None


def update(obs):
    while True:
        time.sleep(1.0)
