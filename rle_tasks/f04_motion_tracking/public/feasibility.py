"""Dynamic feasibility of a clip on the shipped G1: inverse dynamics with contact wrenches per frame,
and the verdict.

``check_clip`` runs ``inverse_dynamics.InverseDynamics`` on every frame of a clip (``qvel`` and ``qacc``
by ``finite_differences``, the feet's contacts by ``stance_flags``; the method is described there) and
gathers the joint torques and base residuals into a ``ClipFeasibility``: a clip passes when no joint needs
more than ``MARGIN`` of its effort limit in any frame and every frame's base residual is within
``FORCE_TOL`` and ``MOMENT_TOL`` (its contacts can produce the motion), and no collision point lies more
than ``PENETRATION_TOL`` below the floor.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np

from .clip import Clip, clip_qpos
from .g1 import FOOT_FRICTION
from .g1_constants import G1
from .inverse_dynamics import (
    FORCE_TOL,
    MOMENT_TOL,
    PENETRATION_TOL,
    InverseDynamics,
    finite_differences,
    stance_flags,
)

__all__ = ["MARGIN", "ClipFeasibility", "check_clip"]

MARGIN = 0.9
"""A clip passes when no joint needs more than this fraction of its effort limit in any frame."""


@dataclass
class ClipFeasibility:
    """Per-frame torques and base residuals of a clip, and the verdict."""

    frames: np.ndarray
    """(F,) clip frame indices checked."""
    torque: np.ndarray
    """(F, 29) joint torques [N m]."""
    effort: np.ndarray
    """(29,) effort limits [N m]."""
    residual: np.ndarray
    """(F, 6) base residuals (force [N], moment [N m])."""
    contacts: list[tuple[str, ...]]
    """Bodies in contact per frame."""
    solver: list[str]
    lowest: np.ndarray | None = None
    """(F,) height of the lowest collision point [m] (None: not measured)."""
    lowest_body: list[str] | None = None
    margin: float = MARGIN
    joints: tuple[str, ...] = field(default=G1.joints)

    @property
    def ratio(self) -> np.ndarray:
        """(F, 29) |torque| / effort limit."""
        return np.abs(self.torque) / self.effort

    @property
    def worst(self) -> tuple[str, int, float]:
        """Worst joint, its frame and its ratio."""
        r = self.ratio
        f, j = np.unravel_index(int(np.argmax(r)), r.shape)
        return self.joints[j], int(self.frames[f]), float(r[f, j])

    @property
    def over_limit(self) -> np.ndarray:
        """Frames where some joint needs more than its effort limit."""
        return self.frames[(self.ratio > 1.0).any(axis=1)]

    @property
    def over_margin(self) -> np.ndarray:
        """Frames where some joint needs more than ``margin`` of its limit."""
        return self.frames[(self.ratio > self.margin).any(axis=1)]

    @property
    def infeasible(self) -> np.ndarray:
        """Frames whose base equations no admissible contact meets (residual beyond the tolerances)."""
        return self.frames[self._bad_residual()]

    @property
    def flight(self) -> np.ndarray:
        """Frames without any contact."""
        return self.frames[[not c for c in self.contacts]]

    def _bad_residual(self) -> np.ndarray:
        return (np.linalg.norm(self.residual[:, :3], axis=1) > FORCE_TOL) | (
            np.linalg.norm(self.residual[:, 3:], axis=1) > MOMENT_TOL
        )

    @property
    def through_floor(self) -> np.ndarray:
        """Frames with a collision point more than ``PENETRATION_TOL`` below the floor."""
        if self.lowest is None:
            return self.frames[:0]
        return self.frames[self.lowest < -PENETRATION_TOL]

    @property
    def passed(self) -> bool:
        return len(self.over_margin) == 0 and len(self.infeasible) == 0 and len(self.through_floor) == 0

    def joint_table(self) -> list[dict]:
        """Per joint: effort, worst |torque|, its ratio and frame, frames over the margin."""
        r = self.ratio
        out = []
        for j, name in enumerate(self.joints):
            f = int(np.argmax(r[:, j]))
            out.append(
                {
                    "joint": name,
                    "effort": float(self.effort[j]),
                    "max_torque": float(np.abs(self.torque[f, j])),
                    "max_ratio": float(r[f, j]),
                    "frame": int(self.frames[f]),
                    "frames_over_margin": int((r[:, j] > self.margin).sum()),
                    "frames_over_limit": int((r[:, j] > 1.0).sum()),
                }
            )
        return out

    def summary(self) -> dict:
        joint, frame, ratio = self.worst
        infeasible = self._bad_residual()
        flight = np.array([not c for c in self.contacts])
        return {
            "passed": self.passed,
            "margin": self.margin,
            "worst_joint": joint,
            "worst_frame": frame,
            "worst_ratio": ratio,
            "frames": len(self.frames),
            "frames_over_margin": self.over_margin.tolist(),
            "frames_over_limit": self.over_limit.tolist(),
            "infeasible_stance_frames": self.frames[infeasible & ~flight].tolist(),
            "non_ballistic_flight_frames": self.frames[infeasible & flight].tolist(),
            "flight_frames": int(flight.sum()),
            "max_residual_force": float(np.linalg.norm(self.residual[:, :3], axis=1).max()),
            "max_residual_moment": float(np.linalg.norm(self.residual[:, 3:], axis=1).max()),
            "force_tol": FORCE_TOL,
            "moment_tol": MOMENT_TOL,
            "qp_fallbacks": int(sum(s == "nnls" for s in self.solver)),
            "through_floor_frames": self.through_floor.tolist(),
            "lowest_point": None if self.lowest is None else float(self.lowest.min()),
            "lowest_body": None if self.lowest is None else self.lowest_body[int(np.argmin(self.lowest))],
        }


def check_clip(
    clip: Clip,
    *,
    frames: range | list[int] | None = None,
    mu: float = FOOT_FRICTION,
    margin: float = MARGIN,
    model: mujoco.MjModel | None = None,
) -> ClipFeasibility:
    """Inverse dynamics of ``clip`` (all frames, or ``frames``) with admissible contact wrenches."""
    solver = InverseDynamics(model, mu=mu)
    qpos = clip_qpos(clip)
    qvel, qacc = finite_differences(solver.model, qpos, 1.0 / clip.fps)
    idx = np.arange(clip.frames) if frames is None else np.asarray(list(frames), dtype=int)
    stance = stance_flags(clip.contacts)
    torque, residual, contacts, names, lowest = [], [], [], [], []
    for f in idx:
        r = solver.solve(qpos[f], qvel[f], qacc[f], stance[f])
        lowest.append(solver.lowest_point())
        torque.append(r.torque)
        residual.append(r.residual)
        contacts.append(tuple(r.wrenches))
        names.append(r.solver)
    return ClipFeasibility(
        frames=idx,
        torque=np.array(torque),
        effort=solver.effort.copy(),
        residual=np.array(residual),
        contacts=contacts,
        solver=names,
        lowest=np.array([z for z, _ in lowest]),
        lowest_body=[b for _, b in lowest],
        margin=margin,
    )
