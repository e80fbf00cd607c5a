"""Piles: brackets dumped into the bin from a seed and left to settle.

A pile is drawn from one ``numpy`` generator: the part count (12-16), the brackets' friction factor
(0.7-1.3) and the dump. The dump places the brackets in a 3 x 4 grid of cells over the bin's inner
floor, in up to two layers, 40 and 100 mm above the floor (well below the 0.25 m above which 3 mm
plates tunnel with the cell's 5 ms contact time constant), each with a random resting family
(flanges up 40 %, flanges down 40 %, on a flange's side 20 %), a random yaw, up to 10 deg of tilt
and up to 10 mm of offset in its cell. The pile then settles for ``SETTLE_S`` with the arm at its
start posture; the settled state is what an episode starts from.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from .workcell import BIN_CENTER, BIN_FLOOR_TOP, BIN_INNER, NAMES, build_workcell, home_qpos, joint_names

PARTS_RANGE = (12, 16)
"""Fewest and most brackets of a pile."""
FRICTION_RANGE = (0.7, 1.3)
"""Range of the brackets' friction factor [1]."""
LAYER_HEIGHTS = (0.040, 0.100)
"""Drop heights of the two layers above the bin floor [m]."""
GRID = (3, 4)
"""Cells along x and y."""
SETTLE_S = 1.5
"""Settling time after the dump [s]."""
PUBLIC_SEEDS = (101, 102, 103, 104, 105)
"""Seeds of the public development piles."""


@dataclass(frozen=True)
class PileSpec:
    """One pile.

    Attributes:
        seed: Seed of the dump.
        n_parts: Number of brackets.
        friction_scale: Factor on the brackets' friction [1].
    """

    seed: int
    n_parts: int
    friction_scale: float

    @classmethod
    def draw(cls, rng: np.random.Generator) -> PileSpec:
        """Count, friction and dump seed from one generator."""
        n = int(rng.integers(PARTS_RANGE[0], PARTS_RANGE[1] + 1))
        f = float(rng.uniform(*FRICTION_RANGE))
        return cls(seed=int(rng.integers(0, 2**31 - 1)), n_parts=n, friction_scale=round(f, 6))

    @classmethod
    def public(cls, seed: int) -> PileSpec:
        """A public development pile."""
        return cls.draw(np.random.default_rng(seed))


def _quat(roll: float, pitch: float, yaw: float) -> np.ndarray:
    q = np.zeros(4)
    mujoco.mju_euler2Quat(q, np.array([roll, pitch, yaw]), "xyz")
    return q


def dump_poses(pile: PileSpec) -> np.ndarray:
    """Spawn poses of the brackets, ``(n, 7)``: position [m] and quaternion (w, x, y, z)."""
    rng = np.random.default_rng(pile.seed)
    nx, ny = GRID
    cells = [(layer, i, j) for layer in range(2) for i in range(nx) for j in range(ny)]
    first = rng.permutation(nx * ny)
    second = nx * ny + rng.permutation(nx * ny)
    order = list(first) + list(second)
    cx, cy = (BIN_INNER[0] - 0.03) / nx, (BIN_INNER[1] - 0.03) / ny
    out = np.zeros((pile.n_parts, 7))
    for k in range(pile.n_parts):
        layer, i, j = cells[order[k]]
        x = BIN_CENTER[0] - (BIN_INNER[0] - 0.03) / 2 + (i + 0.5) * cx + rng.uniform(-0.01, 0.01)
        y = BIN_CENTER[1] - (BIN_INNER[1] - 0.03) / 2 + (j + 0.5) * cy + rng.uniform(-0.01, 0.01)
        z = BIN_FLOOR_TOP + LAYER_HEIGHTS[layer]
        family = rng.choice(3, p=(0.4, 0.4, 0.2))
        tilt = np.radians(rng.uniform(-10, 10, size=2))
        roll = (0.0, math.pi, math.pi / 2)[family] + tilt[0]
        out[k, :3] = (x, y, z + (0.03 if family == 1 else 0.0))
        out[k, 3:] = _quat(roll, tilt[1], rng.uniform(-math.pi, math.pi))
    return out


def part_qpos_adr(model: mujoco.MjModel, n_parts: int) -> np.ndarray:
    """qpos address of each bracket's free joint, ``(n,)``."""
    return np.array([model.jnt_qposadr[model.body(NAMES.part(i)).jntadr[0]] for i in range(n_parts)])


def arm_qpos_adr(model: mujoco.MjModel) -> np.ndarray:
    """qpos addresses of the seven arm joints."""
    return np.array([model.jnt_qposadr[model.joint(j).id] for j in joint_names()])


def settle_pile(model: mujoco.MjModel, pile: PileSpec) -> mujoco.MjData:
    """Dump the pile into the bin and let it settle; returns the settled state (time reset to 0)."""
    data = mujoco.MjData(model)
    adr = part_qpos_adr(model, pile.n_parts)
    poses = dump_poses(pile)
    for k, a in enumerate(adr):
        data.qpos[a : a + 7] = poses[k]
    data.qpos[arm_qpos_adr(model)] = home_qpos()
    data.ctrl[:7] = home_qpos()
    mujoco.mj_forward(model, data)
    mujoco.mj_step(model, data, int(round(SETTLE_S / model.opt.timestep)))
    data.time = 0.0
    data.qvel[:] = 0.0
    data.qacc_warmstart[:] = 0.0
    mujoco.mj_forward(model, data)
    return data


def build_pile(pile: PileSpec) -> tuple[mujoco.MjSpec, mujoco.MjModel, mujoco.MjData]:
    """The workcell of ``pile`` and its settled state (stored as keyframe ``"pile"`` in the spec)."""
    spec = build_workcell(pile.n_parts, pile.friction_scale)
    model = spec.compile()
    data = settle_pile(model, pile)
    spec.add_key(name="pile", qpos=data.qpos.tolist(), ctrl=data.ctrl.tolist(),
                 mpos=data.mocap_pos.ravel().tolist(), mquat=data.mocap_quat.ravel().tolist())  # fmt: skip
    return spec, model, data


__all__ = [
    "PUBLIC_SEEDS",
    "PileSpec",
    "arm_qpos_adr",
    "build_pile",
    "dump_poses",
    "part_qpos_adr",
    "settle_pile",
]
