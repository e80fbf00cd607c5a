"""Scripted layer turns by applied torques (no robot): the mechanism's test and benchmark driver.

Faces are named in the cube's own frame, the frame of its DBL cubie (see ``reading``). A turn applies a
couple: torque ``+tau/4`` about the face's outward axis on each cubie of the turned layer and ``-tau/4``
on each cubie of the opposite layer (a pair of hands), so the cube gains no net torque. The couple is
held until the layer has turned ``release`` relative to the opposite layer (past the detent's halfway
point at 45 degrees), then removed; the detent completes the quarter turn and settles it. Every physics
step calls ``CubeDetent.apply`` first, as any stepping loop of a scene with a cube must.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_tasks.f03_physical_reasoning.cube.detent import CubeDetent
from rle_tasks.f03_physical_reasoning.cube.lattice import ANCHOR, CUBIES, FACE_NORMALS, MOVES
from rle_tasks.f03_physical_reasoning.cube.reading import CubeReading, poses_from_data, read, read_quats

__all__ = ["TurnResult", "scripted_turn", "step"]

_CONJ = np.array([1.0, -1.0, -1.0, -1.0])


@dataclass(frozen=True)
class TurnResult:
    """Outcome of one scripted turn.

    Attributes:
        move: The quarter turn asked for.
        push_steps: Physics steps with the couple applied.
        total_steps: Physics steps in all (push and settle).
        reading: Lattice state and misalignment after settling.
    """

    move: str
    push_steps: int
    total_steps: int
    reading: CubeReading


def step(model: mujoco.MjModel, data: mujoco.MjData, detent: CubeDetent, n: int = 1) -> None:
    """``n`` physics steps, each with the detent torque applied between ``mj_step1`` and ``mj_step2``."""
    for _ in range(n):
        mujoco.mj_step1(model, data)
        detent.apply(data)
        mujoco.mj_step2(model, data)


def _mat(q: np.ndarray) -> np.ndarray:
    m = np.empty(9)
    mujoco.mju_quat2Mat(m, q)
    return m.reshape(3, 3)


def _rel(q_ref: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Quaternion of ``q`` relative to ``q_ref``: ``conj(q_ref) q``."""
    out = np.empty(4)
    mujoco.mju_mulQuat(out, q_ref * _CONJ, q)
    return out


def _angle_about(q_now: np.ndarray, q_start: np.ndarray, axis: np.ndarray) -> float:
    """Rotation [rad] about ``axis`` from ``q_start`` to ``q_now`` (both in the same reference frame)."""
    delta = np.empty(4)
    mujoco.mju_mulQuat(delta, q_now, q_start * _CONJ)
    return 2.0 * math.atan2(float(delta[1:] @ axis), float(delta[0]))


def scripted_turn(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    detent: CubeDetent,
    move: str,
    *,
    name: str = "cube",
    torque: float = 0.02,
    release: float = math.radians(60.0),
    max_push_steps: int = 1000,
    settle_steps: int = 250,
    record: list[CubeReading] | None = None,
) -> TurnResult:
    """Turn one layer by a quarter turn with a torque couple, then let the detent settle it.

    Args:
        model: Compiled model with a cube.
        data: Its data (modified: the cube is stepped).
        detent: The cube's detent.
        move: A quarter turn, one of ``lattice.MOVES`` (faces in the DBL cubie's frame).
        name: The cube's name.
        torque: Couple magnitude [N m], shared by the four cubies of each layer.
        release: Layer angle, relative to the opposite layer, at which the couple is removed [rad].
        max_push_steps: Give up pushing after this many steps (a blocked layer).
        settle_steps: Steps after release.
        record: When given, a reading of the cube after every physics step is appended to it.
    """
    if move not in MOVES:
        raise ValueError(f"unknown move '{move}'; moves are {', '.join(MOVES)}")
    sense = -1.0 if len(move) == 1 else 1.0  # clockwise seen from outside = -90 deg about the normal
    mujoco.mj_kinematics(model, data)
    poses = poses_from_data(model, data, name)
    normal = FACE_NORMALS[move[0]].astype(np.float64)
    layer = read(poses).state.slots() @ normal > 0
    mover = int(np.flatnonzero(layer)[0])
    held = int(np.flatnonzero(~layer)[0])  # the opposite layer is the reference frame
    # The face normal in the held cubie's frame (constant while the opposite layer is held).
    axis_held = _mat(poses.cubie_quats[held]).T @ _mat(poses.cubie_quats[ANCHOR]) @ normal
    start = _rel(poses.cubie_quats[held], poses.cubie_quats[mover])
    bodies = np.array([mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name + "_" + c) for c in CUBIES])

    def advance() -> None:
        step(model, data, detent)
        if record is not None:
            mujoco.mj_kinematics(model, data)
            record.append(read_quats(data.xquat[bodies]))

    pushed = 0
    while pushed < max_push_steps:
        quats = data.xquat[bodies]
        now = _rel(quats[held], quats[mover])
        if sense * _angle_about(now, start, axis_held) >= release:
            break
        tau = sense * torque / 4.0 * (_mat(quats[held]) @ axis_held)
        data.xfrc_applied[bodies[layer], 3:] = tau
        data.xfrc_applied[bodies[~layer], 3:] = -tau
        advance()
        pushed += 1
    data.xfrc_applied[bodies, 3:] = 0.0
    for _ in range(settle_steps):
        advance()
    mujoco.mj_kinematics(model, data)
    return TurnResult(move, pushed, pushed + settle_steps, read_quats(data.xquat[bodies]))
