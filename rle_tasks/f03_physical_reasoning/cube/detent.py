"""Detent of the pocket cube: the internal mechanism that lets a layer turn only as a whole.

Each of the 12 pairs of face-adjacent slots holds two cubies ``(i, j)`` that straddle one boundary
plane, with normal ``a`` (the axis along which the two slots differ). Every physics step:

1. Each cubie's slot is read from its nearest lattice orientation relative to the DBL cubie.
2. For the occupants ``(i, j)`` of each adjacent-slot pair, ``M = R_i^T R_j`` is ``j``'s orientation
   relative to ``i`` and ``L`` the nearest of the 24 lattice rotations; the error ``E = L^T M`` is a
   rotation by ``theta`` about ``axis`` in ``j``'s frame, and ``e = sin(theta) axis`` (the vee of the
   skew part of ``E``).
3. The only legitimate relative motion of a straddling pair is a turn about ``a`` (``a_j`` in ``j``'s
   frame). The couple on ``j`` is

       tau_j = -k (e . a_j) a_j - K e_perp - C w_perp      [N m],   tau_i = -M tau_j (in i's frame),

   with ``e_perp`` and the relative angular velocity ``w_perp`` the parts off ``a_j``: a soft detent
   ``k`` along the turn axis (the nearest lattice rotation, and with it the slot pairing, changes 45
   degrees into a turn, so a turn pushed past halfway completes and one released before returns) and a
   stiff hold ``K`` (damped by ``C``) against any tilt, as a real cube's core and interlocking tongues
   are. A layer turn strains the four pairs on its boundary: its restoring torque is ``4 k sin(theta)``.

The couples act between cubies only (generalised forces on the ball joints whose reactions on the core
cancel), so they conserve momentum; the core is a passive carrier. Gains are the model's numeric
``<cube>_detent`` = ``(k, K, C)``. The torques depend on the cubies' current orientations: apply them
between ``mj_step1`` and ``mj_step2`` (``scripted.step`` does), where ``xmat`` is up to date.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.errors import MissingElement
from rle_tasks.f03_physical_reasoning.cube.group import ROTATIONS
from rle_tasks.f03_physical_reasoning.cube.lattice import ANCHOR, CUBIES, SLOTS

__all__ = ["SLOT_PAIRS", "CubeDetent"]

SLOT_PAIRS: np.ndarray = np.array(
    [(s, t) for s in range(8) for t in range(s + 1, 8) if int(np.abs(SLOTS[s] - SLOTS[t]).sum()) == 2]
)
"""``(12, 2)`` face-adjacent slot pairs (slots differing in one coordinate)."""
_PAIR_AXIS = np.array([int(np.flatnonzero(SLOTS[s] != SLOTS[t])[0]) for s, t in SLOT_PAIRS])
_SLOT_INDEX = {tuple(p): k for k, p in enumerate(SLOTS)}
_SLOT_OF = np.array([[_SLOT_INDEX[tuple(ROTATIONS[r] @ SLOTS[c])] for r in range(24)] for c in range(8)])
"""``_SLOT_OF[cubie, rotation]``: the slot a cubie occupies at that lattice orientation."""
_AXIS_IN = ROTATIONS.astype(np.float64)
"""``_AXIS_IN[r, k]`` (row ``k`` of ``R_r``, i.e. ``R_r^T e_k``): lattice axis ``k`` of the DBL frame in the
frame of a cubie at orientation ``r``."""
_LATTICE = ROTATIONS.astype(np.float64)
_FLAT = _LATTICE.reshape(24, 9).T
_ONE_HOT = np.eye(8)
_ARANGE = np.arange(8)


def _vee_maps() -> np.ndarray:
    """``(24, 3, 9)``: ``_VEE[r] @ vec(M)`` = ``vee(skew(L_r^T M)) = sin(theta) axis`` (row-major vec)."""
    out = np.zeros((24, 3, 9))
    for r, lat in enumerate(_LATTICE):
        for k, (a, b) in enumerate(((2, 1), (0, 2), (1, 0))):
            # (L^T M)[a, b] = sum_c L[c, a] M[c, b]
            for c in range(3):
                out[r, k, 3 * c + b] += 0.5 * lat[c, a]
                out[r, k, 3 * c + a] -= 0.5 * lat[c, b]
    return out


_VEE = _vee_maps()


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
        self.bodies = np.array([model.jnt_bodyid[j] for j in joints])
        """Body ids of the cubies, ``CUBIES`` order."""
        self._dofs = np.array([np.arange(3) + model.jnt_dofadr[j] for j in joints])

    def torques(self, xmat: np.ndarray, qvel_local: np.ndarray) -> np.ndarray:
        """``(8, 3)`` detent torques [N m], each in its cubie's frame (the ball joint's dofs).

        Args:
            xmat: ``(8, 3, 3)`` cubie orientations (world or core frame; only products ``R_i^T R_j``
                are used).
            qvel_local: ``(8, 3)`` cubie angular velocities relative to the core, each in its own frame
                (the ball joints' ``qvel``).
        """
        # Nearest lattice rotation of R_DBL^T R_n: max over L of trace(L^T R_DBL^T R_n) = vec(R_DBL L).vec(R_n).
        rot = np.argmax(xmat.reshape(8, 9) @ (xmat[ANCHOR] @ _LATTICE).reshape(24, 9).T, axis=1)
        occupant = np.full(8, -1)
        occupant[_SLOT_OF[_ARANGE, rot]] = _ARANGE
        i, j = occupant[SLOT_PAIRS[:, 0]], occupant[SLOT_PAIRS[:, 1]]
        ok = (i >= 0) & (j >= 0)  # a broken state (two cubies in one slot) drops the pairs it breaks
        i, j = i[ok], j[ok]
        m = xmat[i].transpose(0, 2, 1) @ xmat[j]
        flat = m.reshape(-1, 9)
        e = (_VEE[np.argmax(flat @ _FLAT, axis=1)] @ flat[:, :, None])[:, :, 0]
        a_j = _AXIS_IN[rot[j], _PAIR_AXIS[ok]]
        # -k (e.a) a - K (e - (e.a) a)
        tau_j = (self.tilt_stiffness - self.stiffness) * (e * a_j).sum(axis=1, keepdims=True) * a_j
        tau_j -= self.tilt_stiffness * e
        if self.tilt_damping:
            w = qvel_local[j] - (m.transpose(0, 2, 1) @ qvel_local[i][:, :, None])[:, :, 0]
            tau_j -= self.tilt_damping * (w - (w * a_j).sum(axis=1, keepdims=True) * a_j)
        return _ONE_HOT[j].T @ tau_j - _ONE_HOT[i].T @ (m @ tau_j[:, :, None])[:, :, 0]

    def apply(self, data: mujoco.MjData) -> None:
        """Write the detent torques into ``data.qfrc_applied`` (only the cube's ball-joint dofs).

        Call after ``mj_step1`` (or ``mj_kinematics``), before ``mj_step2``.
        """
        data.qfrc_applied[self._dofs] = self.torques(
            data.xmat[self.bodies].reshape(8, 3, 3), data.qvel[self._dofs]
        )
