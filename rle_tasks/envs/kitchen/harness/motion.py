"""Level 2: closed-loop motion primitives over the 12-D action (public, laid into the workspace).

Every primitive only calls ``Robot.act``, so each of its steps is one metered action. World poses are
(position [m], quaternion w, x, y, z); ``move_tool`` drives the arm controller's target (observed as
``target_pos_base``/``target_quat_base``) towards the desired tool pose at most ``POS_STEP`` /
``ROT_STEP`` per action and stops when the measured tool pose is within the tolerances.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .geometry import quat_conj, quat_mul, rotvec, rotz
from .robot import BASE_SPEED, POS_STEP, ROT_STEP, TORSO_STEP, YAW_SPEED, Robot

__all__ = ["Motion", "MoveResult", "down_quat"]


def down_quat(yaw: float = 0.0) -> np.ndarray:
    """World orientation of a tool pointing down (tool z = -world z), its fingers' closing axis turned
    by ``yaw`` [rad] about the world z."""
    base = np.array([0.0, 1.0, 0.0, 0.0])  # 180 degrees about x: tool z down
    turn = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])
    return quat_mul(turn, base)


@dataclass(frozen=True)
class MoveResult:
    """How a primitive ended: ``reached`` within tolerance, after ``steps`` actions, remaining ``error`` [m]."""

    reached: bool
    steps: int
    error: float


def _wrap(a: float) -> float:
    return float((a + np.pi) % (2 * np.pi) - np.pi)


class Motion:
    """Motion primitives of one robot.

    Args:
        robot: The ``Robot``.
    """

    def __init__(self, robot: Robot) -> None:
        self.robot = robot

    @property
    def obs(self) -> dict[str, Any]:
        return self.robot.obs if self.robot.obs else self.robot.observe()

    def _to_base(self, pos: np.ndarray, quat: np.ndarray | None) -> tuple[np.ndarray, np.ndarray | None]:
        o = self.obs
        r = rotz(o["base_yaw"])
        p = r.T @ (np.asarray(pos, float) - np.asarray(o["base_pos"]))
        if quat is None:
            return p, None
        qb = np.array([np.cos(o["base_yaw"] / 2), 0.0, 0.0, np.sin(o["base_yaw"] / 2)])
        return p, quat_mul(quat_conj(qb), np.asarray(quat, float))

    def move_tool(
        self,
        pos: Any,
        quat: Any = None,
        *,
        tol: float = 0.01,
        rot_tol: float = 0.05,
        max_steps: int = 150,
        speed: float = 1.0,
        gripper: float | None = None,
    ) -> MoveResult:
        """Move the tool to a world pose (``quat`` None keeps the current orientation).

        Args:
            pos: Desired tool position [m] (world).
            quat: Desired tool orientation (world), or None.
            tol: Position tolerance [m].
            rot_tol: Orientation tolerance [rad].
            max_steps: Actions at most.
            speed: Fraction of the full-scale step used per action (0, 1].
            gripper: Gripper command held during the motion (None keeps the last).
        """
        steps, err = 0, np.inf
        for steps in range(1, max_steps + 1):
            o = self.obs
            p_des, q_des = self._to_base(pos, quat)
            d_pos = p_des - np.asarray(o["target_pos_base"])
            arm = np.zeros(6)
            arm[:3] = np.clip(d_pos / POS_STEP, -speed, speed)
            if q_des is not None:
                rv = rotvec(quat_mul(q_des, quat_conj(np.asarray(o["target_quat_base"]))))
                arm[3:] = np.clip(rv / ROT_STEP, -speed, speed)
            o = self.robot.act(arm=arm, gripper=gripper)
            p_now, _ = self._to_base(o["ee_pos"], None)
            err = float(np.linalg.norm(p_des - p_now))
            ok = err < tol
            if q_des is not None:
                _, q_now = self._to_base(o["ee_pos"], o["ee_quat"])
                ok = ok and float(np.linalg.norm(rotvec(quat_mul(q_des, quat_conj(q_now))))) < rot_tol
            if ok:
                return MoveResult(True, steps, err)
        return MoveResult(False, steps, err)

    def move_tool_by(self, delta_world: Any, **kwargs: Any) -> MoveResult:
        """Translate the tool by ``delta_world`` [m] keeping its orientation."""
        o = self.obs
        return self.move_tool(
            np.asarray(o["ee_pos"]) + np.asarray(delta_world, float), o["ee_quat"], **kwargs
        )

    def gripper(self, command: float, steps: int = 12) -> dict[str, Any]:
        """Hold the arm and set the gripper (-1 open, +1 closed) for ``steps`` actions."""
        o = self.obs
        for _ in range(steps):
            o = self.robot.act(gripper=command)
        return o

    def open_gripper(self, steps: int = 12) -> dict[str, Any]:
        return self.gripper(-1.0, steps)

    def close_gripper(self, steps: int = 12) -> dict[str, Any]:
        return self.gripper(1.0, steps)

    def drive_to(
        self,
        x: float,
        y: float,
        yaw: float | None = None,
        *,
        tol: float = 0.02,
        yaw_tol: float = 0.03,
        max_steps: int = 200,
    ) -> MoveResult:
        """Drive the base to (x, y) [m] and heading ``yaw`` [rad] in the world (base mode)."""
        steps, err = 0, np.inf
        for steps in range(1, max_steps + 1):
            o = self.obs
            d = np.array([x, y]) - np.asarray(o["base_pos"][:2])
            local = rotz(o["base_yaw"])[:2, :2].T @ d
            dyaw = 0.0 if yaw is None else _wrap(yaw - o["base_yaw"])
            err = float(np.linalg.norm(d))
            if err < tol and abs(dyaw) < yaw_tol:
                return MoveResult(True, steps - 1, err)
            gain = 2.0
            cmd = np.array(
                [gain * local[0] / BASE_SPEED, gain * local[1] / BASE_SPEED, gain * dyaw / YAW_SPEED]
            )
            self.robot.act(base=np.clip(cmd, -1, 1), mode="base")
        # settle one step with the base commanded still
        self.robot.act(mode="base")
        return MoveResult(False, steps, err)

    def set_torso(self, height: float, *, tol: float = 0.005, max_steps: int = 60) -> MoveResult:
        """Move the torso lift to ``height`` [m] (0..0.34)."""
        steps, err = 0, np.inf
        for steps in range(1, max_steps + 1):
            o = self.obs
            err = float(height - o["torso"])
            if abs(err) < tol:
                return MoveResult(True, steps - 1, abs(err))
            self.robot.act(torso=float(np.clip(err / TORSO_STEP, -1, 1)))
        return MoveResult(False, steps, abs(err))

    def wait(self, steps: int) -> dict[str, Any]:
        """Hold everything for ``steps`` actions."""
        o = self.obs
        for _ in range(steps):
            o = self.robot.act()
        return o
