"""The metered environment of ``03-pocket-cube``: two arms, 14-D actions, the cube's mechanism inside.

``CubeEnv`` is the tabletop environment (``rle_design.control.TabletopEnv``) over ``scene.scene_xml``
with both arms and 7 numbers per arm (``left/`` then ``right/``):

| index | meaning |
|---|---|
| 0-2, 7-9 | tool-site position delta of the left, right arm (base frame) x 0.02 m |
| 3-5, 10-12 | tool-site rotation delta (rotation vector, base frame) x 0.1 rad |
| 6, 13 | gripper: -1 open, +1 closed |

Every physics step of an action applies the cube's detent (``CubeDetent``) between ``mj_step1`` and
``mj_step2`` (``substep``), so the replay of a ledger runs the same mechanism.

Session counters (``MjData.userdata``, so resets and replays reproduce them; observation
``cube_session``): after every action the cube is read (``reading.read``); a reading within
``turns.SETTLED_TOL`` of the lattice that differs from the last settled state is a transition,
classified by ``turns.classify``: its quarter turns join ``turns`` (a half turn counts 2), an
unclassified one ``unclassified``. This is the session's turn counter, the count the verifier checks
against its own finer recount of the replay.

Reset abandons the attempt (card): a reset after time 0 restores the scramble, restarts the counters
and marks the attempt void (``attempt_void``); a void attempt scores 0 whatever follows.

Drop rescue: an action whose two gripper entries are both at least ``RESCUE_LEVEL`` (outside the
command range [-1, 1]) puts the cube back on its stand, keeping its lattice state: each cubie is set to
its nearest lattice orientation relative to the DBL cubie, the whole cube to the lattice orientation
nearest its current one, at rest. It costs one step (it is an action: the arms hold their targets and
both grippers open for its 50 ms). Move the hands clear of the stand first. Completed turns are kept
(the counters do not change unless the snap itself completes a layer that was past halfway).

Observation: the tabletop's ``time``, ``arms`` (two), ``rgb`` = {``front``: (240, 320, 3)} every
``camera_every`` actions, and ``cube_session`` = {``turns``, ``unclassified``, ``rescues``,
``attempt_void``}; no cube pose.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np

from rle_design.control import TabletopEnv
from rle_design.control.layout import GRIPPER
from rle_tasks.f03_physical_reasoning.cube.coords import decode, encode
from rle_tasks.f03_physical_reasoning.cube.detent import CubeDetent
from rle_tasks.f03_physical_reasoning.cube.group import QUATS, ROTATIONS
from rle_tasks.f03_physical_reasoning.cube.lattice import ANCHOR, CUBIES
from rle_tasks.f03_physical_reasoning.cube.reading import CubeReading, read_quats
from rle_tasks.f03_physical_reasoning.cube.scene import CUBE_CENTRE, CUBE_NAME, CubeInstance, scene_xml
from rle_tasks.f03_physical_reasoning.cube.turns import SETTLED_TOL, classify

__all__ = [
    "ARM_ACTION",
    "N_USERDATA",
    "RESCUE_LEVEL",
    "SAMPLE_EVERY",
    "CubeEnv",
    "counters",
    "make_env",
    "rescue_action",
]

ARM_ACTION = GRIPPER + 1
"""Numbers per arm: 6 pose deltas and the gripper (14 for the two arms)."""
N_SUBSTEPS = 25
"""Physics steps per action: 2 ms x 25 = 50 ms (20 Hz), as the other tabletop tasks."""
RESCUE_LEVEL = 2.0
"""Both gripper entries at or above this value make an action a drop rescue."""
SAMPLE_EVERY = 5
"""Physics steps between the verifier's cube readings along a replay (10 ms)."""
IMAGE_SIZE = (240, 320)
STATE, TURNS, UNCLASSIFIED, RESCUES, VOID = range(5)
"""``userdata`` slots: settled state (coordinate + 1, 0 = none yet), quarter turns, unclassified
transitions, rescues, resets that abandoned the attempt."""
N_USERDATA = 5


@functools.lru_cache(maxsize=8)
def _cube_ids(model: mujoco.MjModel) -> tuple[CubeDetent, np.ndarray, np.ndarray, np.ndarray, int, int]:
    """Detent, cubie body ids, ball qpos and dof addresses, free joint qpos and dof addresses."""
    detent = CubeDetent(model, CUBE_NAME)
    balls = [model.joint(f"{CUBE_NAME}_{c}_ball").id for c in CUBIES]
    free = model.joint(CUBE_NAME + "_free").id
    return (
        detent,
        detent.bodies.copy(),
        np.array([model.jnt_qposadr[j] for j in balls]),
        np.array([model.jnt_dofadr[j] for j in balls]),
        int(model.jnt_qposadr[free]),
        int(model.jnt_dofadr[free]),
    )


def counters(model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
    """The ``cube_session`` observation: the session's counters."""
    u = data.userdata
    return {
        "turns": int(u[TURNS]),
        "unclassified": int(u[UNCLASSIFIED]),
        "rescues": int(u[RESCUES]),
        "attempt_void": bool(u[VOID] > 0),
    }


def cube_reading(model: mujoco.MjModel, data: mujoco.MjData) -> CubeReading:
    """Nearest lattice state and misalignment of the cube (positions current)."""
    return read_quats(data.xquat[_cube_ids(model)[1]])


def rescue_action(n_arms: int = 2) -> np.ndarray:
    """The drop-rescue action (arms hold, grippers at ``RESCUE_LEVEL``)."""
    a = np.zeros(ARM_ACTION * n_arms)
    a[GRIPPER::ARM_ACTION] = RESCUE_LEVEL
    return a


def _quat(mat: np.ndarray) -> np.ndarray:
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.asarray(mat, dtype=np.float64).ravel())
    return q


@dataclass(frozen=True)
class CubeEnv(TabletopEnv):
    """The two-arm cube environment (module docstring).

    Attributes:
        recorder: Verifier only: a list that receives a ``CubeReading`` every ``SAMPLE_EVERY`` physics
            steps (not part of the scene; ``None`` in sessions).
    """

    arms: tuple[str, ...] = ("left/", "right/")
    arm_action_size: int = ARM_ACTION
    n_substeps: int = N_SUBSTEPS
    cameras: tuple[str, ...] = ("front",)
    image_size: tuple[int, int] | None = IMAGE_SIZE
    observers: tuple = (("cube_session", counters),)
    recorder: list | None = field(default=None, compare=False, repr=False)

    def prepare(self, model: mujoco.MjModel) -> None:
        super().prepare(model)
        _cube_ids(model)

    def substep(self, model: mujoco.MjModel, data: mujoco.MjData, k: int) -> None:
        detent, bodies = _cube_ids(model)[:2]
        detent.apply(data)
        if self.recorder is not None and k % SAMPLE_EVERY == 0:
            self.recorder.append(read_quats(data.xquat[bodies]))

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        void = data.userdata[VOID] + (1 if data.time > 0 else 0)
        super().reset(model, data)
        data.userdata[:] = 0.0
        data.userdata[VOID] = void
        self._count(model, data)

    def step(self, model: mujoco.MjModel, data: mujoco.MjData, ctrl: np.ndarray) -> None:
        action = np.nan_to_num(np.asarray(ctrl, dtype=float))
        if (action[GRIPPER :: self.arm_action_size] >= RESCUE_LEVEL).all():
            self._rescue(model, data)
            action = np.zeros_like(action)
            action[GRIPPER :: self.arm_action_size] = -1.0
        super().step(model, data, action)
        self._count(model, data)

    def _count(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        reading = cube_reading(model, data)
        if not reading.misalignment <= SETTLED_TOL:
            return
        code = encode(reading.state) + 1
        u = data.userdata
        if u[STATE] == 0:
            u[STATE] = code
        elif u[STATE] != code:
            move = classify(decode(int(u[STATE]) - 1), reading.state)
            if move is None:
                u[UNCLASSIFIED] += 1
            else:
                u[TURNS] += 2 if move.endswith("2") else 1
            u[STATE] = code

    def _rescue(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Put the cube on its stand on the lattice, at rest (module docstring)."""
        _, bodies, ball_q, ball_v, free_q, free_v = _cube_ids(model)
        mujoco.mj_kinematics(model, data)
        rel = cube_reading(model, data).state.orient  # relative to DBL
        anchor_world = data.xmat[bodies[ANCHOR]].reshape(3, 3)
        whole = int(np.argmax(np.einsum("rij,ij->r", ROTATIONS, anchor_world)))  # nearest lattice rotation
        for i, b in enumerate(bodies):
            world = ROTATIONS[whole] @ ROTATIONS[rel[i]]
            built = model.body_quat[b]  # the cubie's fixed orientation in the core frame
            built_mat = np.zeros(9)
            mujoco.mju_quat2Mat(built_mat, built)
            data.qpos[ball_q[i] : ball_q[i] + 4] = _quat(built_mat.reshape(3, 3).T @ world)
            data.qvel[ball_v[i] : ball_v[i] + 3] = 0.0
        data.qpos[free_q : free_q + 3] = CUBE_CENTRE
        data.qpos[free_q + 3 : free_q + 7] = QUATS[0]
        data.qvel[free_v : free_v + 6] = 0.0
        data.userdata[RESCUES] += 1
        mujoco.mj_forward(model, data)


def make_env(
    inst: CubeInstance,
    *,
    privileged: bool = False,
    image_size: tuple[int, int] | None = IMAGE_SIZE,
    camera_every: int = 10,
    recorder: list | None = None,
) -> CubeEnv:
    """The metered environment of ``inst`` (``privileged``: reference programs and tests only;
    ``camera_every`` and ``image_size`` change what is rendered, not the scene or its fingerprint)."""
    return CubeEnv(
        xml=scene_xml(inst, N_USERDATA),
        privileged=privileged,
        image_size=image_size,
        camera_every=camera_every,
        recorder=recorder,
    )
