"""Baseline ``raising``: loads, but every ``act`` raises (fails the smoke test: reward capped at 0.1)."""


def make_policy():
    return None


def reset():
    return None


def act(obs):
    raise RuntimeError("controller not implemented")
