"""Reference bin-clearing policy: depth-based part detection, highest part first, one part per trip.

Uses only its observations: at the look pose above the bin the wrist RGB-D frame is lifted to world
points with the published calibration (``K``, ``pose``); points above the bin floor form the pile and
the highest one (with its 20 mm neighbourhood) is the next pick. The hand descends on it with the
magnet on until the magnet reports contact or the wrist force rises, lifts, carries the part over the
nest, waits until the nest sensor reads empty, releases 50 mm above the belt and looks again.
"""

from __future__ import annotations

import numpy as np

from .kinematics import fk, ik_down

BASE = np.array([0.0, 0.0, 0.40])
LOOK = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 1.9, 0.785])
BIN_C = np.array([0.50, 0.0])
BIN_HALF = np.array([0.1325, 0.173])
BIN_FLOOR = 0.40
MARGIN = 0.03
PAD = 0.150
NEST = np.array([0.27, -0.42, 0.45 + 0.05 + 0.150])
LIFT_Z = 0.80
MAX_QD = 1.5
DT = 0.05

_state: dict = {}


def make_policy() -> None:
    _state.clear()


def reset() -> None:
    _state.clear()
    _state.update(mode="look", plan=[], target=None, wait=0.0, misses=0, q_cmd=None, magnet=0.0)


def _goto(q_from: np.ndarray, q_to: np.ndarray) -> list[np.ndarray]:
    n = max(1, int(np.ceil(np.max(np.abs(q_to - q_from)) / (MAX_QD * DT))))
    return [q_from + (q_to - q_from) * (k + 1) / n for k in range(n)]


def _ik(p_world: np.ndarray, seed: np.ndarray) -> np.ndarray:
    q, _ = ik_down(np.asarray(p_world, dtype=float) - BASE, 0.0, seed)
    return q


def _detect(cam: dict) -> np.ndarray | None:
    depth, K, pose = cam["depth"].astype(float), cam["K"], cam["pose"]
    h, w = depth.shape
    v, u = np.mgrid[0:h, 0:w]
    z = depth
    pts = np.stack([(u - K[0, 2]) / K[0, 0] * z, (v - K[1, 2]) / K[1, 1] * z, z], -1).reshape(-1, 3)
    world = pts @ pose[:3, :3].T + pose[:3, 3]
    inside = np.all(np.abs(world[:, :2] - BIN_C) < BIN_HALF - 0.005, axis=1) & (world[:, 2] > BIN_FLOOR + 0.0025) & (world[:, 2] < BIN_FLOOR + 0.10)
    world = world[inside]
    if len(world) < 5:
        return None
    reach = np.all(np.abs(world[:, :2] - BIN_C) < BIN_HALF - MARGIN, axis=1)
    cand = world[reach] if reach.sum() >= 5 else world
    top = cand[np.argmax(cand[:, 2])]
    near = world[(np.linalg.norm(world[:, :2] - top[:2], axis=1) < 0.02) & (world[:, 2] > top[2] - 0.006)]
    c = near.mean(0)
    c[:2] = np.clip(c[:2], BIN_C - BIN_HALF + MARGIN, BIN_C + BIN_HALF - MARGIN)
    return np.array([c[0], c[1], top[2]])


def act(obs: dict) -> np.ndarray:
    s = _state
    if not s:
        reset()
    q = np.asarray(obs["q"], dtype=float)
    if s["q_cmd"] is None:
        s["q_cmd"] = q.copy()
    contact = obs["magnet"][1] > 0.5
    mode = s["mode"]
    if s["plan"]:
        s["q_cmd"] = s["plan"].pop(0)
    elif mode == "look":
        if np.max(np.abs(q - LOOK)) > 0.03:
            s["plan"] = _goto(s["q_cmd"], LOOK)
        elif "wrist" in obs and np.max(np.abs(obs["dq"])) < 0.05:
            target = _detect(obs["wrist"])
            if target is None:
                s["misses"] += 1
                s["mode"] = "look" if s["misses"] < 3 else "done"
            else:
                s["target"] = target
                above = _ik(target + [0, 0, 0.08 + PAD], LOOK)
                s["plan"] = _goto(s["q_cmd"], above)
                s["mode"] = "descend"
                s["z"] = target[2] + 0.08
                s["magnet"] = 1.0
    elif mode == "descend":
        if contact:
            s["mode"], s["wait"] = "grip", 0.0
        elif s["z"] < s["target"][2] - 0.012:
            s["mode"], s["magnet"] = "lift_empty", 0.0
        else:
            s["z"] -= 0.004
            s["q_cmd"] = _ik(np.array([*s["target"][:2], s["z"] + PAD]), s["q_cmd"])
    elif mode == "grip":
        s["wait"] += DT
        if s["wait"] >= 0.15:
            up = _ik(np.array([*s["target"][:2], LIFT_Z]), s["q_cmd"])
            s["plan"] = _goto(s["q_cmd"], up)
            s["mode"] = "carry"
    elif mode == "lift_empty":
        s["plan"] = _goto(s["q_cmd"], LOOK)
        s["mode"] = "look"
    elif mode == "carry":
        if not contact:
            s["magnet"], s["mode"] = 0.0, "look"
        else:
            over = _ik(np.array([NEST[0], NEST[1], LIFT_Z]), s["q_cmd"])
            low = _ik(NEST, over)
            s["plan"] = _goto(s["q_cmd"], over) + _goto(over, low)
            s["mode"] = "release"
            s["wait"] = 0.0
    elif mode == "release":
        if obs["nest"][0] == 0 and obs["nest"][1] < 0.5:
            s["magnet"] = 0.0
            s["wait"] += DT
            if s["wait"] >= 0.25:
                up = _ik(np.array([NEST[0], NEST[1], LIFT_Z]), s["q_cmd"])
                s["plan"] = _goto(s["q_cmd"], up)
                s["mode"], s["misses"] = "look", 0
    return np.concatenate([s["q_cmd"], [s["magnet"]]])


__all__ = ["act", "fk", "make_policy", "reset"]
