"""Reference bin-clearing policy: depth-based part detection, flat top surfaces first, one part per trip.

Uses only its observations. A depth frame (the overhead camera while the hand is over the nest, else
the wrist camera at the look pose) is lifted to world points with the published calibration (``K``,
``pose``) and binned into a 4 mm height map of the bin; cells above the bin floor are the pile. The
next pick is the highest cell whose 20 mm neighbourhood is flat (a web or a flange face, where the
square pad seats), else the highest cell. The hand moves on straight Cartesian paths at a safe
height, approaches with the magnet on until the magnet reports contact (a wrist force without contact
slows it down), lifts, carries the part to the nest, waits above it while the nest sensor reads a
part, lowers it close to the belt and releases it. A nest blocked by several parts (two brackets
hooked together) is cleared by lifting one out and delivering it once the nest is free.
"""

import numpy as np

from .kinematics import fk, ik_down

BASE = np.array([0.0, 0.0, 0.40])
LOOK = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 1.9, 0.785])
BIN_C = np.array([0.50, 0.0])
BIN_HALF = np.array([0.1325, 0.173])
BIN_FLOOR = 0.40
MARGIN = 0.045
TOOL = 0.150
"""Flange to pad face [m] (published geometry)."""
NEST = np.array([0.255, -0.42, 0.45 + 0.06 + TOOL])
LIFT_Z = 0.80
MAX_QD = 1.6
DT = 0.05
CELL = 0.004
DESCENT = 0.006
PUTBACK = np.array([0.50, 0.0, BIN_FLOOR + 0.12 + TOOL])
"""Where the part we carry is dropped back onto the pile when others block the nest (flange) [m]."""
NEST_BOX = (np.array([0.225, -0.465]), np.array([0.315, -0.375]))
"""Pick area inside the nest (x, y) [m]: the pad stays clear of the gate and the rails."""
CONTACT_FZ = 3.0
"""Wrist force rise that also counts as contact [N]."""

_state: dict = {}


def make_policy() -> None:
    _state.clear()


def reset() -> None:
    _state.clear()
    _state.update(mode="look", plan=[], target=None, wait=0.0, misses=0, q_cmd=None, magnet=0.0, fz0=None)


def _goto(q_from: np.ndarray, q_to: np.ndarray, qd: float = MAX_QD) -> list[np.ndarray]:
    """Joint path with a cosine velocity profile, peak speed about ``qd`` [rad/s]."""
    span = float(np.max(np.abs(q_to - q_from)))
    n = max(2, int(np.ceil(span * np.pi / 2 / (qd * DT))))
    s = 0.5 - 0.5 * np.cos(np.pi * np.arange(1, n + 1) / n)
    return [q_from + (q_to - q_from) * k for k in s]


def _line(p0: np.ndarray, p1: np.ndarray, seed: np.ndarray, speed: float) -> list[np.ndarray]:
    """Straight flange path from p0 to p1 (world [m]), pointing down, peak ``speed`` [m/s] (cosine)."""
    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    n = max(2, int(np.ceil(np.linalg.norm(p1 - p0) * np.pi / 2 / (speed * DT))))
    out, q = [], seed
    for k in range(1, n + 1):
        q = _ik(p0 + (p1 - p0) * (0.5 - 0.5 * np.cos(np.pi * k / n)), q)
        out.append(q)
    return out


def _vertical(xy: np.ndarray, z0: float, z1: float, seed: np.ndarray, speed: float) -> list[np.ndarray]:
    """Straight vertical flange path from z0 to z1 [m] at peak ``speed`` [m/s]."""
    return _line([xy[0], xy[1], z0], [xy[0], xy[1], z1], seed, speed)


def _flange(q: np.ndarray) -> np.ndarray:
    """World position of the flange for joint angles ``q`` [m]."""
    return fk(q)[:3, 3] + BASE


def _transfer(q0: np.ndarray, p1: np.ndarray, speed: float = 0.8, down: float = 0.5) -> list[np.ndarray]:
    """From ``q0`` up to ``LIFT_Z``, straight across at ``LIFT_Z``, down to ``p1``: never through a wall."""
    p0 = _flange(q0)
    top0, top1 = np.array([p0[0], p0[1], max(p0[2], LIFT_Z)]), np.array([p1[0], p1[1], max(p1[2], LIFT_Z)])
    plan = _line(p0, top0, q0, 0.5) if top0[2] - p0[2] > 1e-3 else []
    plan += _line(top0, top1, plan[-1] if plan else q0, speed)
    if top1[2] - p1[2] > 1e-3:
        plan += _line(top1, p1, plan[-1], down)
    return plan


def _ik(p_world: np.ndarray, seed: np.ndarray) -> np.ndarray:
    q, _ = ik_down(np.asarray(p_world, dtype=float) - BASE, 0.0, seed)
    return q


def _cloud(cam: dict) -> np.ndarray:
    depth, K, pose = np.asarray(cam["depth"], dtype=float), cam["K"], cam["pose"]
    h, w = depth.shape
    v, u = np.mgrid[0:h, 0:w]
    pts = np.stack([(u - K[0, 2]) / K[0, 0] * depth, (v - K[1, 2]) / K[1, 1] * depth, depth], -1).reshape(
        -1, 3
    )
    world = pts @ np.asarray(pose)[:3, :3].T + np.asarray(pose)[:3, 3]
    inside = np.all(np.abs(world[:, :2] - BIN_C) < BIN_HALF - 0.004, axis=1)
    return world[inside & (world[:, 2] > BIN_FLOOR + 0.0025) & (world[:, 2] < BIN_FLOOR + 0.10)]


def detect(cam: dict) -> np.ndarray | None:
    """Pick point (x, y, top z) [m] in the world, or None when the bin looks empty."""
    pts = _cloud(cam)
    if len(pts) < 8:
        return None
    lo = BIN_C - BIN_HALF
    shape = tuple(np.ceil(2 * BIN_HALF / CELL).astype(int))
    ij = np.clip(((pts[:, :2] - lo) / CELL).astype(int), 0, np.array(shape) - 1)
    hmap = np.full(shape, -1.0)
    np.maximum.at(hmap, (ij[:, 0], ij[:, 1]), pts[:, 2])
    occ = hmap > 0
    r = 2  # 5 x 5 cells = 20 mm
    pad = np.pad(hmap, r, constant_values=-1.0)
    flat = np.zeros(shape)
    for di in range(-r, r + 1):
        for dj in range(-r, r + 1):
            nb = pad[r + di : r + di + shape[0], r + dj : r + dj + shape[1]]
            flat += np.abs(nb - hmap) < 0.003
    reach = np.zeros(shape, dtype=bool)
    m = int(np.ceil(MARGIN / CELL))
    reach[m:-m, m:-m] = True
    for want in (occ & reach & (flat >= 15), occ & reach & (flat >= 8), occ & reach, occ):
        if want.any():
            score = np.where(want, hmap, -np.inf)
            i, j = np.unravel_index(int(np.argmax(score)), shape)
            xy = lo + (np.array([i, j]) + 0.5) * CELL
            xy = np.clip(xy, lo + MARGIN, BIN_C + BIN_HALF - MARGIN)
            return np.array([xy[0], xy[1], hmap[i, j]])
    return None


def detect_nest(cam: dict) -> np.ndarray | None:
    """Highest point of the parts lying in the nest (x, y, z) [m], or None."""
    depth, K, pose = np.asarray(cam["depth"], dtype=float), cam["K"], cam["pose"]
    h, w = depth.shape
    v, u = np.mgrid[0:h, 0:w]
    pts = np.stack([(u - K[0, 2]) / K[0, 0] * depth, (v - K[1, 2]) / K[1, 1] * depth, depth], -1).reshape(
        -1, 3
    )
    world = pts @ np.asarray(pose)[:3, :3].T + np.asarray(pose)[:3, 3]
    lo, hi = NEST_BOX
    sel = np.all((world[:, :2] > lo - 0.02) & (world[:, :2] < hi + 0.02), axis=1)
    sel &= (world[:, 2] > 0.4525) & (world[:, 2] < 0.53)
    if sel.sum() < 5:
        return None
    top = world[sel][np.argmax(world[sel][:, 2])]
    return np.array([*np.clip(top[:2], lo, hi), top[2]])


def act(obs: dict) -> np.ndarray:
    s = _state
    if not s:
        reset()
    q = np.asarray(obs["q"], dtype=float)
    if s["q_cmd"] is None:
        s["q_cmd"] = q.copy()
    contact = obs["magnet"][1] > 0.5
    mode = s["mode"]
    pushed = s["fz0"] is not None and abs(float(obs["ft"][2]) - s["fz0"]) > CONTACT_FZ
    if mode == "approach":
        if contact:
            s["plan"], s["mode"], s["wait"] = [], "grip", 0.0
        elif pushed:  # a force without magnet contact: go on slowly from here
            s["plan"], s["mode"] = [], "descend"
            s["z"] = float(_flange(s["q_cmd"])[2]) - TOOL
        elif s["plan"]:
            s["q_cmd"] = s["plan"].pop(0)
        else:
            s["mode"] = "descend"
    elif s["plan"]:
        s["q_cmd"] = s["plan"].pop(0)
    elif mode == "above":  # at rest above the pick: the unloaded wrist force, then the approach
        s["loads"].append(float(obs["ft"][2]))
        if len(s["loads"]) >= 4:
            s["fz0"], s["loads"] = float(np.mean(s["loads"][1:])), []
            s["plan"] = _vertical(s["target"][:2], LIFT_Z, s["z"] + TOOL, s["q_cmd"], 0.6)
            s["mode"] = "approach"
    elif mode == "look":
        if np.max(np.abs(q - LOOK)) > 0.03:
            plan = _transfer(s["q_cmd"], _flange(LOOK))
            s["plan"] = plan + _goto(plan[-1], LOOK)
        elif "wrist" in obs and np.max(np.abs(obs["dq"])) < 0.05:
            _start_pick(s, detect(obs["wrist"]))
    elif mode == "descend":
        if contact:
            s["mode"], s["wait"] = "grip", 0.0
        elif (pushed and s["z"] < s["target"][2] + 0.01) or s["z"] < s["target"][2] - 0.012:
            s["mode"], s["magnet"] = "look", 0.0  # blocked or nothing there: look again
        else:
            s["z"] -= DESCENT
            s["q_cmd"] = _ik(np.array([*s["target"][:2], s["z"] + TOOL]), s["q_cmd"])
    elif mode == "grip":
        s["wait"] += DT
        if s["wait"] >= 0.15:
            z_now = float(fk(q)[2, 3]) + BASE[2]  # flange height where the magnet caught the part
            first = _vertical(s["target"][:2], z_now, z_now + 0.05, s["q_cmd"], 0.1)  # let it hang free
            s["plan"] = first + _vertical(s["target"][:2], z_now + 0.05, LIFT_Z, first[-1], 0.5)
            s["mode"] = "carry"
    elif mode == "carry":
        if not contact:
            s["magnet"], s["mode"] = 0.0, "look"
        else:
            s["plan"] = _transfer(s["q_cmd"], NEST, 0.7, 0.3)
            s["mode"], s["wait"] = "release", 0.0
    elif mode == "release":
        if obs["nest"][0] == 0:
            s["magnet"] = 0.0
            s["wait"] += DT
            if s["wait"] >= 0.25:
                s["plan"] = _vertical(NEST[:2], NEST[2], LIFT_Z, s["q_cmd"], 0.6)
                s["mode"] = "replan"
        else:  # a part still in the nest: wait above it, never pin it under the one we carry
            s["plan"] = _vertical(NEST[:2], NEST[2], NEST[2] + 0.1, s["q_cmd"], 0.3)
            s["mode"], s["wait"] = "hover", 0.0
    elif mode == "hover":
        s["wait"] += DT
        if obs["nest"][0] == 0:
            s["plan"] = _vertical(NEST[:2], NEST[2] + 0.1, NEST[2], s["q_cmd"], 0.3)
            s["mode"], s["wait"] = "release", 0.0
        elif obs["nest"][0] >= 2 and s["wait"] > 1.0:  # blocked: our part back to the bin, then unblock
            s["plan"] = _transfer(s["q_cmd"], PUTBACK, 0.7, 0.4)
            s["mode"] = "putback"
    elif mode == "putback":
        s["magnet"] = 0.0
        s["wait"] += DT
        if s["wait"] >= 0.25:
            s["mode"] = "replan"
            s["plan"] = _transfer(s["q_cmd"], np.array([NEST[0], NEST[1], LIFT_Z]))
    elif mode == "replan" and "overhead" in obs:
        if obs["nest"][0] >= 2 and obs["nest"][1] < 0.5:  # blocked: lift one out, deliver it after
            _start_pick(s, detect_nest(obs["overhead"]))
        else:
            target = detect(obs["overhead"])
            if target is None:
                s["mode"] = "look"
            else:
                _start_pick(s, target)
    return np.concatenate([s["q_cmd"], [s["magnet"]]])


def _start_pick(s: dict, target: np.ndarray | None) -> None:
    if target is None:
        s["misses"] += 1
        s["mode"] = "look" if s["misses"] < 3 else "done"
        return
    s["misses"] = 0
    s["target"] = target
    s["z"] = target[2] + 0.04
    s["plan"] = _transfer(s["q_cmd"], np.array([target[0], target[1], LIFT_Z]))  # then the approach
    s["mode"], s["magnet"], s["fz0"], s["loads"] = "above", 1.0, None, []


__all__ = ["act", "detect", "make_policy", "reset"]
