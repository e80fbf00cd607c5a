"""Reading the pocket cube from cubie poses: lattice state, misalignment, and the solved predicate.

Pure functions on poses (quaternions ``(w, x, y, z)``, positions [m], speeds [m/s]); ``poses_from_data``
is the only function that touches MuJoCo, and it only copies body poses out of ``MjData``.

Thresholds (derivations in the cube README):

- ``ALIGNED_TOL``  = 5 deg: the mechanism settles within 2 deg of the lattice (tested); 5 deg accepts
  every settled cube and rejects a layer held visibly off the lattice.
- ``STILL_SPEED``  = 0.02 m/s: free fall reaches it in 2 ms (one control step), and a layer turning at
  0.9 rad/s moves its cubie centres (22.6 mm from the axis) that fast.
- ``LIFT_CLEARANCE`` = 5 mm: a cube resting on the table has its lowest corner within contact
  penetration (< 1 mm) of the table top; 5 mm means it is held above it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.errors import MissingElement
from rle_tasks.f03_physical_reasoning.cube.group import nearest
from rle_tasks.f03_physical_reasoning.cube.lattice import ANCHOR, CUBIES, LatticeState

ALIGNED_TOL = math.radians(5.0)
STILL_SPEED = 0.02
LIFT_CLEARANCE = 0.005


@dataclass(frozen=True)
class CubePoses:
    """World poses and speeds of the eight cubies (``CUBIES`` order).

    Attributes:
        cubie_quats: ``(8, 4)`` cubie orientations.
        cubie_pos: ``(8, 3)`` cubie box centres [m].
        cubie_speed: ``(8,)`` linear speeds of the cubie centres [m/s].
        cubie_half: Half edge of a cubie box [m].
    """

    cubie_quats: np.ndarray
    cubie_pos: np.ndarray
    cubie_speed: np.ndarray
    cubie_half: float


@dataclass(frozen=True)
class CubeReading:
    """The nearest lattice state and how far the cube is from it.

    Attributes:
        state: Nearest lattice state, cubie orientations relative to the DBL cubie (so normalised).
        misalignment: Largest angle of any cubie, relative to DBL, from its lattice orientation [rad].
    """

    state: LatticeState
    misalignment: float


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    w1, v1 = a[..., :1], a[..., 1:]
    w2, v2 = b[..., :1], b[..., 1:]
    return np.concatenate(
        [w1 * w2 - np.sum(v1 * v2, axis=-1, keepdims=True), w1 * v2 + w2 * v1 + np.cross(v1, v2)], -1
    )


def relative_quats(cubie_quats: np.ndarray) -> np.ndarray:
    """``(8, 4)`` cubie orientations relative to the DBL cubie: ``conj(q_DBL) * q_i``."""
    q = np.asarray(cubie_quats, dtype=np.float64)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    conj = q[ANCHOR] * np.array([1.0, -1.0, -1.0, -1.0])
    return _quat_mul(np.broadcast_to(conj, q.shape), q)


def read(poses: CubePoses) -> CubeReading:
    """Nearest lattice state of the cubies (relative to the DBL cubie) and the misalignment.

    The core is an internal body and not used: the state is read from the visible cubies only.
    """
    return read_quats(poses.cubie_quats)


def read_quats(cubie_quats: np.ndarray) -> CubeReading:
    """``read`` from the ``(8, 4)`` cubie world orientations alone."""
    idx, angle = nearest(relative_quats(cubie_quats))
    return CubeReading(LatticeState(tuple(int(i) for i in idx)), float(np.max(angle)))


def lowest_corner(poses: CubePoses) -> float:
    """Height of the lowest cubie corner [m]."""
    corners = (
        np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * poses.cubie_half
    )
    mats = np.empty((8, 9))
    for i, q in enumerate(np.asarray(poses.cubie_quats, dtype=np.float64)):
        mujoco.mju_quat2Mat(mats[i], q / np.linalg.norm(q))
    world = np.einsum("nij,kj->nki", mats.reshape(8, 3, 3), corners) + poses.cubie_pos[:, None, :]
    return float(world[..., 2].min())


@dataclass(frozen=True)
class SolvedCheck:
    """The solved predicate and the quantities it was decided on.

    Attributes:
        solved: All six faces uniform, aligned, the cube still and above the table.
        reason: ``""`` when solved, else which condition failed.
        measured: The quantities, SI units (angles in degrees where the key ends in ``_deg``).
    """

    solved: bool
    reason: str
    measured: dict[str, float]


def check_solved(poses: CubePoses, table_z: float) -> SolvedCheck:
    """Decide the solved predicate (faces uniform and aligned, cube held still above the table).

    Args:
        poses: The cube's poses at the end of the attempt.
        table_z: Height of the table top [m].
    """
    reading = read(poses)
    low = lowest_corner(poses)
    speed = float(np.max(poses.cubie_speed))
    measured = {
        "misalignment_deg": math.degrees(reading.misalignment),
        "lowest_corner_above_table": low - table_z,
        "max_cubie_speed": speed,
    }
    if not all(np.isfinite(v) for v in measured.values()):
        return SolvedCheck(False, "cube poses are not finite", measured)
    if not reading.state.is_valid():
        return SolvedCheck(False, "cube broken: two cubies read in the same slot", measured)
    if not reading.state.is_solved():
        return SolvedCheck(False, "faces are not uniform: " + reading.state.facelets(), measured)
    if reading.misalignment > ALIGNED_TOL:
        return SolvedCheck(
            False,
            f"a layer is {measured['misalignment_deg']:.1f} deg off the lattice (> {math.degrees(ALIGNED_TOL):.0f})",
            measured,
        )
    if speed > STILL_SPEED:
        return SolvedCheck(False, f"cube moving at {speed:.3f} m/s (> {STILL_SPEED})", measured)
    if low - table_z < LIFT_CLEARANCE:
        return SolvedCheck(
            False,
            f"cube not held above the table: lowest corner {1000 * (low - table_z):.1f} mm above it (< 5)",
            measured,
        )
    return SolvedCheck(True, "", measured)


def poses_from_data(model: mujoco.MjModel, data: mujoco.MjData, name: str = "cube") -> CubePoses:
    """Copy the cubies' poses and speeds out of a simulation (after ``mj_forward``/``mj_step``)."""
    ids = []
    for body in [name + "_" + c for c in CUBIES]:
        bid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
        if bid < 0:
            raise MissingElement("body", body, available=[model.body(i).name for i in range(model.nbody)])
        ids.append(bid)
    vel = np.zeros(6)
    speeds = []
    for bid in ids:
        mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, bid, vel, 0)
        speeds.append(float(np.linalg.norm(vel[3:])))
    gid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name + "_" + CUBIES[0] + "_box")
    return CubePoses(
        cubie_quats=data.xquat[ids].copy(),
        cubie_pos=data.xpos[ids].copy(),
        cubie_speed=np.array(speeds),
        cubie_half=float(model.geom_size[gid][0]),
    )
