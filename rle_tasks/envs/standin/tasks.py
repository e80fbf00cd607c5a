"""The stand-in's tasks: objects, seeded layouts, success predicates and horizons.

Three RoboTwin-style two-arm tasks (names and instructions say what each asks). A layout is drawn
from a seed (``layout``); the same seed always gives the same object poses. Every task's objects are
free bodies added to the scene spec (``add_objects``); ``success`` reads the simulator state only.
Lengths [m], masses [kg].
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_tasks.envs.standin.scene import TOP_Z, SceneLook

__all__ = ["TASKS", "StandinTask", "layout"]


@dataclass(frozen=True)
class StandinTask:
    """One stand-in task.

    Attributes:
        name: Short name.
        instruction: The language instruction a request carries.
        max_steps: Horizon in control steps (10 Hz), about 1.6 x the scripted expert's length.
        objects: The free bodies the task adds.
    """

    name: str
    instruction: str
    max_steps: int
    objects: tuple[str, ...]


TASKS = (
    StandinTask("lift_pot", "lift the pot with both arms", 150, ("pot",)),
    StandinTask("handover_bar", "pass the bar from the left arm to the right arm", 260, ("bar",)),
    StandinTask(
        "place_pair", "put the red block and the blue block in the tray", 260, ("red", "blue", "tray")
    ),
)
"""Task index -> task."""

POT_HALF = (0.085, 0.085)
POT_WALL = (0.006, 0.05)
"""Pot wall thickness and half height [m]."""
HANDLE = (0.012, 0.035, 0.012)
"""Handle half extents [m]; one on each side of the pot along y, at the rim."""
BAR = (0.016, 0.11, 0.016)
BLOCK = 0.026
"""Block half size [m] (5.2 cm cubes; the gripper opens 8 cm)."""
TRAY = (0.075, 0.10, 0.004, 0.03)
"""Tray half extents x, y, floor half thickness and wall height [m]."""
LIFT = 0.08
"""How far the pot must rise [m]."""


def layout(task: int, seed: int) -> dict[str, tuple[float, float, float]]:
    """Object -> (x, y, yaw) on the table top from ``seed`` [m, m, rad]."""
    rng = np.random.default_rng([int(task), int(seed)])
    u = rng.uniform
    if TASKS[task].name == "lift_pot":
        return {"pot": (u(0.04, 0.16), u(-0.05, 0.05), u(-0.15, 0.15))}
    if TASKS[task].name == "handover_bar":
        return {"bar": (u(0.04, 0.16), u(0.10, 0.20), u(-0.25, 0.25))}
    return {
        "red": (u(0.0, 0.16), u(0.17, 0.30), u(-0.4, 0.4)),
        "blue": (u(0.0, 0.16), u(-0.30, -0.17), u(-0.4, 0.4)),
        "tray": (u(0.10, 0.16), u(-0.02, 0.02), 0.0),
    }


def _tint(rgb: tuple[float, float, float], look: SceneLook) -> list[float]:
    return [c * t for c, t in zip(rgb, look.tint, strict=True)] + [1.0]


def _geom(body, name, half, pos, rgba, mass=None) -> None:
    g = body.add_geom(
        name=name, type=mujoco.mjtGeom.mjGEOM_BOX, size=list(half), pos=list(pos), rgba=rgba,
        friction=[1.2, 0.005, 0.0001], condim=4, solref=[0.005, 1.0],
    )  # fmt: skip
    if mass is not None:
        g.mass = mass


def add_objects(spec: mujoco.MjSpec, task: int, seed: int, look: SceneLook) -> None:
    """Add the task's free bodies at the layout of ``seed`` (resting on the table top)."""
    top = TOP_Z + look.table_dz
    world = spec.worldbody
    for name, (x, y, yaw) in layout(task, seed).items():
        q = [np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)]
        if name == "pot":
            hx, hy = POT_HALF
            t, hz = POT_WALL
            body = world.add_body(name=name, pos=[x, y, top + 0.005], quat=q)
            body.add_freejoint(name=name)
            rgb = _tint((0.25, 0.30, 0.75), look)
            _geom(body, "pot_floor", (hx, hy, 0.005), (0, 0, 0), rgb, 0.25)
            for k, (sx, sy) in enumerate(((1, 0), (-1, 0), (0, 1), (0, -1))):
                half = (t, hy, hz) if sx else (hx, t, hz)
                _geom(body, f"pot_wall{k}", half, (sx * (hx - t), sy * (hy - t), hz), rgb, 0.08)
            hrgb = _tint((0.85, 0.75, 0.2), look)
            for k, sy in enumerate((1, -1)):
                pos = (0.0, sy * (hy + HANDLE[1]), 2 * hz - HANDLE[2])
                _geom(body, f"pot_handle{k}", HANDLE, pos, hrgb, 0.03)
        elif name == "bar":
            body = world.add_body(name=name, pos=[x, y, top + BAR[2]], quat=q)
            body.add_freejoint(name=name)
            _geom(body, name, BAR, (0, 0, 0), _tint((0.9, 0.45, 0.1), look), 0.12)
        elif name in ("red", "blue"):
            body = world.add_body(name=name, pos=[x, y, top + BLOCK], quat=q)
            body.add_freejoint(name=name)
            rgb = (0.85, 0.15, 0.12) if name == "red" else (0.12, 0.25, 0.85)
            _geom(body, name, (BLOCK,) * 3, (0, 0, 0), _tint(rgb, look), 0.08)
        else:
            tx, ty, tz, wall = TRAY
            body = world.add_body(name=name, pos=[x, y, top + tz])
            rgb = _tint((0.2, 0.6, 0.25), look)
            _geom(body, "tray_floor", (tx, ty, tz), (0, 0, 0), rgb)
            w = 0.005
            for k, (sx, sy) in enumerate(((1, 0), (-1, 0), (0, 1), (0, -1))):
                half = (w, ty, wall / 2) if sx else (tx, w, wall / 2)
                _geom(body, f"tray_wall{k}", half, (sx * (tx - w), sy * (ty - w), wall / 2), rgb)


def place_objects(model: mujoco.MjModel, data: mujoco.MjData, task: int, seed: int, look: SceneLook) -> None:
    """Move the task's bodies of a compiled scene to the layout of ``seed`` (free bodies through
    ``qpos``, the fixed tray through ``body_pos``); heights stay those ``add_objects`` gave."""
    for name, (x, y, yaw) in layout(task, seed).items():
        b = model.body(name).id
        q = [np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)]
        if model.body_jntnum[b]:
            adr = model.jnt_qposadr[model.body_jntadr[b]]
            data.qpos[adr : adr + 2] = (x, y)
            data.qpos[adr + 2] = model.body_pos[b, 2]
            data.qpos[adr + 3 : adr + 7] = q
        else:
            model.body_pos[b, :2] = (x, y)


def _touching(model: mujoco.MjModel, data: mujoco.MjData, body: int, prefix: str) -> bool:
    for c in data.contact[: data.ncon]:
        b1, b2 = model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]
        for a, b in ((b1, b2), (b2, b1)):
            if a == body and model.body(b).name.startswith(prefix):
                return True
    return False


def success(task: int, model: mujoco.MjModel, data: mujoco.MjData, start: dict[str, np.ndarray]) -> bool:
    """The task's goal holds in the current state (``start``: object -> initial position)."""
    name = TASKS[task].name
    if name == "lift_pot":
        b = model.body("pot").id
        up = data.xmat[b].reshape(3, 3)[:, 2]
        return bool(data.xpos[b, 2] - start["pot"][2] >= LIFT and up[2] >= np.cos(np.radians(20.0)))
    if name == "handover_bar":
        b = model.body("bar").id
        p = data.xpos[b]
        return bool(
            p[1] <= -0.08
            and p[2] - start["bar"][2] >= 0.08
            and _touching(model, data, b, "right/")
            and not _touching(model, data, b, "left/")
        )
    tray = model.body("tray").id
    tx, ty, tz, wall = TRAY
    centre = data.xpos[tray]
    for block in ("red", "blue"):
        b = model.body(block).id
        rel = data.xpos[b] - centre
        if abs(rel[0]) > tx - 0.01 or abs(rel[1]) > ty - 0.01 or rel[2] > wall + BLOCK:
            return False
        if _touching(model, data, b, "left/") or _touching(model, data, b, "right/"):
            return False
    return True
