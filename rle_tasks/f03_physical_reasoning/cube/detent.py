"""Detent of the pocket cube: the internal mechanism that lets a layer turn only as a whole.

Each of the 12 pairs of face-adjacent slots holds two cubies ``(i, j)`` that straddle one boundary
plane, with normal ``a`` (the axis along which the two slots differ). Every physics step:

1. Each cubie's slot is read from its nearest lattice orientation relative to the DBL cubie.
2. For the occupants ``(i, j)`` of each adjacent-slot pair, ``Q = conj(q_i) q_j`` is ``j`` relative to
   ``i`` (``q`` are ball-joint quaternions, cubie relative to core) and ``L`` its nearest lattice
   rotation; the error ``conj(L) Q`` is a small rotation ``e = 2 sin(theta/2) axis`` in ``j``'s frame.
3. The only legitimate relative motion of a straddling pair is a turn about ``a`` (``a_j`` in ``j``'s
   frame). The couple on ``j`` is

       tau_j = -k (e . a_j) a_j - K e_perp - C w_perp      [N m], and  tau_i = -Q tau_j (in i's frame),

   with ``e_perp`` and the relative angular velocity ``w_perp`` the parts off ``a_j``: a soft detent
   ``k`` along the turn axis (it changes sign 45 degrees into a turn, where the nearest lattice rotation
   and the slot pairing change, so a turn pushed past halfway completes) and a stiff, damped hold ``K``,
   ``C`` against any tilt, as a real cube's core and interlocking tongues are. A layer turn strains
   the four pairs on its boundary: the layer's restoring torque is ``4 k theta``.

The couples act between cubies only (generalised forces on the ball joints whose reactions on the core
cancel), so they conserve momentum; the core is a passive carrier. Gains are the model's numeric
``<cube>_detent`` = ``(k, K, C)``.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.errors import MissingElement
from rle_tasks.f03_physical_reasoning.cube.group import QUATS, ROTATIONS
from rle_tasks.f03_physical_reasoning.cube.lattice import ANCHOR, CUBIES, SLOTS

__all__ = ["SLOT_PAIRS", "CubeDetent"]

SLOT_PAIRS: np.ndarray = np.array(
    [(s, t) for s in range(8) for t in range(s + 1, 8) if int(np.abs(SLOTS[s] - SLOTS[t]).sum()) == 2]
)
"""``(12, 2)`` face-adjacent slot pairs (slots differing in one coordinate)."""
_PAIR_AXIS = np.array([(SLOTS[s] != SLOTS[t]).astype(np.float64) for s, t in SLOT_PAIRS])
_SLOT_INDEX = {tuple(p): k for k, p in enumerate(SLOTS)}
_SLOT_OF = np.array([[_SLOT_INDEX[tuple(ROTATIONS[r] @ SLOTS[c])] for r in range(24)] for c in range(8)])
"""``_SLOT_OF[cubie, rotation]``: the slot a cubie occupies at that lattice orientation."""
_CONJ = np.array([1.0, -1.0, -1.0, -1.0])
_ONE_HOT = np.eye(8)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of ``(n, 3)`` arrays (``np.cross`` costs ~10x more on small arrays)."""
    a0, a1, a2 = a[:, 0], a[:, 1], a[:, 2]
    b0, b1, b2 = b[:, 0], b[:, 1], b[:, 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=1)


def _qmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    w1, v1 = a[:, :1], a[:, 1:]
    w2, v2 = b[:, :1], b[:, 1:]
    return np.concatenate(
        [w1 * w2 - (v1 * v2).sum(axis=1, keepdims=True), w1 * v2 + w2 * v1 + _cross(v1, v2)], 1
    )


def _rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate vectors ``v`` by unit quaternions ``q`` (row-wise)."""
    w, u = q[:, :1], q[:, 1:]
    t = 2.0 * _cross(u, v)
    return v + w * t + _cross(u, t)


def _nearest(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    dots = q @ QUATS.T
    idx = np.argmax(np.abs(dots), axis=1)
    return idx, QUATS[idx] * np.sign(dots[np.arange(len(q)), idx])[:, None]


def _joint(model: mujoco.MjModel, name: str) -> int:
    jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
    if jid < 0:
        raise MissingElement("joint", name, available=[model.joint(i).name for i in range(model.njnt)])
    return jid


class CubeDetent:
    """Computes and applies the detent couples of one cube in a compiled model.

    Args:
        model: Compiled model holding a cube built by ``CubeConfig``.
        name: The cube's name (``CubeConfig.name``).
    """

    def __init__(self, model: mujoco.MjModel, name: str = "cube") -> None:
        key = name + "_detent"
        nid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, key)
        if nid < 0:
            raise MissingElement(
                "numeric", key, available=[model.numeric(i).name for i in range(model.nnumeric)]
            )
        adr = model.numeric_adr[nid]
        self.stiffness, self.tilt_stiffness, self.tilt_damping = (
            float(v) for v in model.numeric_data[adr : adr + 3]
        )
        joints = [_joint(model, name + "_" + c + "_ball") for c in CUBIES]
        self._qpos = np.array([np.arange(4) + model.jnt_qposadr[j] for j in joints])
        self._dofs = np.array([np.arange(3) + model.jnt_dofadr[j] for j in joints])

    def torques(self, qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
        """``(8, 3)`` detent torques [N m], each in its cubie's frame (the ball joint's dofs).

        Args:
            qpos: The model's ``qpos`` vector.
            qvel: The model's ``qvel`` vector.
        """
        q = qpos[self._qpos]
        q = q / np.linalg.norm(q, axis=1, keepdims=True)
        w = qvel[self._dofs]
        rot, _ = _nearest(_qmul(np.broadcast_to(q[ANCHOR] * _CONJ, q.shape), q))
        slot = _SLOT_OF[np.arange(8), rot]
        occupant = np.full(8, -1)
        occupant[slot] = np.arange(8)
        i, j = occupant[SLOT_PAIRS[:, 0]], occupant[SLOT_PAIRS[:, 1]]
        ok = (i >= 0) & (j >= 0)
        i, j, axis = i[ok], j[ok], _PAIR_AXIS[ok]
        rel = _qmul(q[i] * _CONJ, q[j])
        _, near = _nearest(rel)
        e = 2.0 * _qmul(near * _CONJ, rel)[:, 1:]
        a_j = np.einsum("nki,nk->ni", ROTATIONS[rot[j]], axis)  # R_j^T a: the straddle axis in j's frame
        along = (e * a_j).sum(axis=1, keepdims=True) * a_j
        w_rel = w[j] - _rotate(rel * _CONJ, w[i])  # j's angular velocity relative to i, in j's frame
        w_perp = w_rel - (w_rel * a_j).sum(axis=1, keepdims=True) * a_j
        tau_j = -self.stiffness * along - self.tilt_stiffness * (e - along) - self.tilt_damping * w_perp
        # Each cubie is in at most three pairs; sum by one-hot matrices (np.add.at is slow on tiny arrays).
        return _ONE_HOT[j].T @ tau_j - _ONE_HOT[i].T @ _rotate(rel, tau_j)

    def apply(self, data: mujoco.MjData) -> None:
        """Write the detent torques into ``data.qfrc_applied`` (only the cube's ball-joint dofs)."""
        data.qfrc_applied[self._dofs] = self.torques(data.qpos, data.qvel)
