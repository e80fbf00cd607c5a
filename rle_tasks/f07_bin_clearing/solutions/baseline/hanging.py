"""Baseline ``hanging``: ``act`` never returns (the hang cap ends the call: smoke failure, cap 0.1)."""

import time


def make_policy():
    return None


def reset():
    return None


def act(obs):
    while True:
        time.sleep(0.5)
