"""Baseline: a controller that raises (shelf integration must fail with this text)."""


def reset(arm, target, payload_kg, layout):
    raise RuntimeError("controller deliberately failed: no motion plan")


def control(t, qpos, qvel, ctrl):
    raise RuntimeError("controller deliberately failed: no motion plan")
