"""The bin-clearing environment: one definition for the development session and the evaluation.

``BinClearingEnv`` is a ``rle_design.ledger.MeteredEnv`` (the workcell of one pile as MJCF, reset to
the settled pile stored as keyframe ``"pile"``), so ``rle dev`` serves it through the ledger and the
verifier plays the submitted policy on it with ``episode``. Both advance the scene with ``step``: the
command held for one 50 ms control period, then the cell's nest logic (``NestLogic``).

Observation (every 50 ms tick): ``time`` [s], ``q`` joint positions [rad], ``dq`` [rad/s], ``tau``
servo torques [N m], ``ft`` wrist force/torque in the flange frame [N, N m], ``magnet`` = (command,
pad in contact), ``nest`` = (parts sensed in the nest, gate open, parts counted at the belt's end).
On every second tick (10 Hz, ``time`` a multiple of 0.1 s) also ``overhead`` and ``wrist``: each a dict
of ``rgb`` (H, W, 3) uint8, ``depth`` (H, W) float32 planar depth [m], ``K`` 3x3 intrinsics and
``pose`` 4x4 world-from-camera (OpenCV axes). Part poses are never observed.

Action (every tick): seven joint-position targets [rad] (clipped to the joint ranges) and one magnet
command in [0, 1].
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from rle_design.ledger import MeteredEnv
from rle_design.rollout import run_episode
from rle_design.rollout.env import ActionError, advance
from rle_design.rollout.episode import Episode
from rle_design.scene.robots import robot_constants
from rle_design.sensors import RgbdSensor, ft_reading

from .pile import PileSpec, build_pile, part_qpos_adr
from .workcell import (
    ARM,
    BELT_TOP,
    BELT_WIDTH,
    BELT_X,
    BELT_Y,
    CAMERA_HZ,
    CONTROL_HZ,
    GATE_HEIGHT,
    NAMES,
    NEST_X,
    OVERHEAD,
    WRIST,
    joint_names,
)

NEST_DWELL_S = 0.5
"""Time the nest must hold exactly one part before the gate opens [s]."""
NEST_HEIGHT = 0.08
"""Height above the belt within which a part counts as in the nest [m]."""
GATE_CLEARANCE = 0.05
"""An open gate closes once no part's centre is within this distance past it [m] (half a bracket's
length, 30 mm, plus 20 mm): it never closes under a part leaving the nest."""
EPISODE_S = 120.0
"""Simulated time of one pile [s]."""
N_SUBSTEPS = 25
"""Physics steps per control period (2 ms x 25 = 50 ms)."""


def nest_members(model: mujoco.MjModel, data: mujoco.MjData, n_parts: int) -> np.ndarray:
    """Indices of the parts inside the nest (centre of mass in the nest volume, not on the magnet)."""
    pos = np.array([data.xipos[model.body(NAMES.part(i)).id] for i in range(n_parts)])
    inside = (
        (pos[:, 0] > NEST_X[0])
        & (pos[:, 0] < NEST_X[1])
        & (np.abs(pos[:, 1] - BELT_Y) < BELT_WIDTH / 2)
        & (pos[:, 2] > BELT_TOP - 0.01)
        & (pos[:, 2] < BELT_TOP + NEST_HEIGHT)
    )
    return np.flatnonzero(inside & ~held_parts(model, data, n_parts))


def held_parts(model: mujoco.MjModel, data: mujoco.MjData, n_parts: int) -> np.ndarray:
    """(n,) bool: part touches the magnet pad while the magnet is on."""
    out = np.zeros(n_parts, dtype=bool)
    if data.ctrl[7] <= 0.0 or data.ncon == 0:
        return out
    pad = model.geom(NAMES.magnet_pad).id
    g1, g2 = data.contact.geom1[: data.ncon], data.contact.geom2[: data.ncon]
    other = np.concatenate([g2[g1 == pad], g1[g2 == pad]])
    for g in other:
        name = model.body(model.geom_bodyid[g]).name
        if name.startswith("bracket"):
            out[int(name[7:])] = True
    return out


def gate_zone(model: mujoco.MjModel, data: mujoco.MjData, n_parts: int) -> np.ndarray:
    """(n,) bool: part on the belt between the nest's start and ``GATE_CLEARANCE`` past the gate (not held)."""
    pos = np.array([data.xipos[model.body(NAMES.part(i)).id] for i in range(n_parts)])
    zone = (
        (pos[:, 0] > NEST_X[0])
        & (pos[:, 0] < NEST_X[1] + GATE_CLEARANCE)
        & (np.abs(pos[:, 1] - BELT_Y) < BELT_WIDTH / 2)
        & (pos[:, 2] > BELT_TOP - 0.01)
        & (pos[:, 2] < BELT_TOP + NEST_HEIGHT)
    )
    return zone & ~held_parts(model, data, n_parts)


def cleared_parts(model: mujoco.MjModel, data: mujoco.MjData, n_parts: int) -> np.ndarray:
    """(n,) bool: part carried past the belt's end (centre of mass beyond ``BELT_X[1]``, off the belt)."""
    pos = np.array([data.xipos[model.body(NAMES.part(i)).id] for i in range(n_parts)])
    return (pos[:, 0] > BELT_X[1]) & (np.abs(pos[:, 1] - BELT_Y) < 0.2)


class NestLogic:
    """The nest's controller, run after every control period; its state lives in ``data.userdata``.

    ``userdata[0]``: time the nest has held exactly one part [s]; ``userdata[1]``: gate open
    (1) or closed (0); ``userdata[2]``: parts counted at the belt's end. The gate opens after
    ``NEST_DWELL_S`` with exactly one part and closes once that part is clear of it (``GATE_CLEARANCE``),
    or at once when a second part arrives while it is open: several parts together block the nest until the extras are removed.
    """

    def __init__(self, model: mujoco.MjModel, n_parts: int) -> None:
        self.n_parts = n_parts
        self.gate = model.body(NAMES.gate).mocapid[0]
        self.closed_z = BELT_TOP + GATE_HEIGHT / 2
        self.period = N_SUBSTEPS * model.opt.timestep

    def update(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        members = nest_members(model, data, self.n_parts)
        u = data.userdata
        if u[1] > 0.5:
            if len(members) > 1 or not gate_zone(model, data, self.n_parts).any():
                u[1], u[0] = 0.0, 0.0
        elif len(members) == 1:
            u[0] += self.period
            if u[0] >= NEST_DWELL_S - 1e-9:
                u[1] = 1.0
        else:
            u[0] = 0.0
        data.mocap_pos[self.gate, 2] = self.closed_z - (GATE_HEIGHT + 0.01) * u[1]
        u[2] = float(cleared_parts(model, data, self.n_parts).sum())


_SENSORS: dict[int, tuple[mujoco.MjModel, dict[str, RgbdSensor]]] = {}


def _sensors(model: mujoco.MjModel) -> dict[str, RgbdSensor]:
    entry = _SENSORS.get(id(model))
    if entry is None or entry[0] is not model:
        cams = {}
        for name, _, _, (h, w) in (OVERHEAD, WRIST):
            cams[name] = RgbdSensor(model, name, w, h, fast=True, segmentation=False)
        entry = _SENSORS[id(model)] = (model, cams)
    return entry[1]


def close_cameras(model: mujoco.MjModel) -> None:
    """Free the cameras rendered for ``model`` (their GL contexts); the next render opens new ones."""
    entry = _SENSORS.pop(id(model), None)
    if entry is not None:
        for sensor in entry[1].values():
            sensor.close()


def render_cameras(model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, dict[str, np.ndarray]]:
    """Both cameras' RGB-D frames with calibration (see the module docstring)."""
    out = {}
    for name, sensor in _sensors(model).items():
        f = sensor.render(data)
        out[name] = {"rgb": f.rgb, "depth": f.depth, "K": f.camera.intrinsics.matrix,
                     "pose": f.camera.world_from_camera}  # fmt: skip
    return out


@dataclass(frozen=True)
class BinClearingEnv(MeteredEnv):
    """The workcell of one pile (see the module docstring); build with ``make_env``.

    Attributes:
        n_parts: Brackets in the pile.
    """

    n_parts: int = 0

    def logic(self, model: mujoco.MjModel) -> NestLogic:
        return NestLogic(model, self.n_parts)

    def observe(self, model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
        jq = np.array([model.jnt_qposadr[model.joint(j).id] for j in joint_names()])
        jv = np.array([model.jnt_dofadr[model.joint(j).id] for j in joint_names()])
        contact = bool(held_contact(model, data))
        obs = {
            "time": float(data.time),
            "q": data.qpos[jq].copy(),
            "dq": data.qvel[jv].copy(),
            "tau": data.actuator_force[:7].copy(),
            "ft": ft_reading(model, data, NAMES.force, NAMES.torque, adhesion=True),
            "magnet": np.array([float(data.ctrl[7]), float(contact)]),
            "nest": np.array(
                [len(nest_members(model, data, self.n_parts)), data.userdata[1], data.userdata[2]]
            ),
        }
        tick = int(round(float(data.time) * CONTROL_HZ))
        if tick % (CONTROL_HZ // CAMERA_HZ) == 0:
            obs.update(render_cameras(model, data))
        return obs

    def action(self, model: mujoco.MjModel, action: Any) -> np.ndarray:
        arr = super().action(model, action)
        lo, hi = model.actuator_ctrlrange.T
        limited = model.actuator_ctrllimited.astype(bool)
        arr[limited] = np.clip(arr[limited], lo[limited], hi[limited])
        jr = np.array([model.jnt_range[model.joint(j).id] for j in joint_names()])
        arr[:7] = np.clip(arr[:7], jr[:, 0], jr[:, 1])
        return arr

    def step(self, model: mujoco.MjModel, data: mujoco.MjData, ctrl: np.ndarray) -> None:
        advance(model, data, self.action(model, ctrl), self.n_substeps)
        self.logic(model).update(model, data)

    def episode(self, model, data, policy, n_actions, terms=()) -> Episode:  # noqa: ANN001
        """Evaluation episode: ``policy(observe())`` every tick; the nest logic runs after each period."""
        logic = self.logic(model)

        def control(m: mujoco.MjModel, d: mujoco.MjData, t: float) -> None:
            d.ctrl[:] = self.action(m, policy(self.observe(m, d)))

        return run_episode(
            model, data, n_actions * self.n_substeps, control=control, control_every=self.n_substeps,
            terms=[NestTerm(logic, self.n_substeps), *terms],
        )  # fmt: skip


def held_contact(model: mujoco.MjModel, data: mujoco.MjData) -> bool:
    """True when the magnet pad touches a bracket."""
    if data.ncon == 0:
        return False
    pad = model.geom(NAMES.magnet_pad).id
    g1, g2 = data.contact.geom1[: data.ncon], data.contact.geom2[: data.ncon]
    return bool(np.any(g1 == pad) or np.any(g2 == pad))


class NestTerm:
    """Runs ``NestLogic`` after every control period inside ``run_episode`` (never ends the episode)."""

    name = "nest"
    final = False

    def __init__(self, logic: NestLogic, every: int) -> None:
        self.logic, self.every = logic, every

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        pass

    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> None:
        self.logic.update(model, data)


def _absolute_meshes(spec: mujoco.MjSpec) -> None:
    base = Path(robot_constants(ARM).model_path).parent
    meshdir = Path(spec.meshdir) if spec.meshdir else Path()
    for mesh in spec.meshes:
        if mesh.file and not Path(mesh.file).is_absolute():
            mesh.file = str((base / meshdir / mesh.file).resolve())


@functools.lru_cache(maxsize=16)
def make_env(pile: PileSpec) -> BinClearingEnv:
    """The environment of ``pile``: workcell, settled pile as keyframe ``"pile"``, 20 Hz control.

    Deterministic in ``pile``; the last 16 are kept (settling a pile costs about a second).
    """
    spec, _, _ = build_pile(pile)
    _absolute_meshes(spec)
    spec.meshdir = ""
    return BinClearingEnv(xml=spec.to_xml(), n_substeps=N_SUBSTEPS, keyframe="pile", n_parts=pile.n_parts)


__all__ = [
    "EPISODE_S",
    "ActionError",
    "BinClearingEnv",
    "NestLogic",
    "cleared_parts",
    "close_cameras",
    "held_parts",
    "make_env",
    "nest_members",
    "part_qpos_adr",
    "render_cameras",
]
