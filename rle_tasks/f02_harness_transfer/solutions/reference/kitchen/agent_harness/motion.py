"""Closed-loop motion primitives over the 12-D action.

Every primitive only calls ``Robot.act``, so each of its steps is one metered action. World poses are
(position [m], quaternion w, x, y, z); ``move_tool`` drives the arm controller's target (observed as
``target_pos_base``/``target_quat_base``) towards the desired tool pose at most ``POS_STEP`` /
``ROT_STEP`` per action and stops when the measured tool pose is within the tolerances. ``orbit``
drives the base around a vertical axis with the arm holding its pose on the base, so a grasped handle
travels on a circle about that axis (a door about its hinge).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .geometry import mat_to_quat, quat_conj, quat_mul, rotvec, rotz
from .robot import BASE_SPEED, POS_STEP, ROT_STEP, TORSO_STEP, YAW_SPEED, Robot

__all__ = ["DT", "Motion", "MoveResult", "down_quat", "facing_quat"]

DT = 0.05
"""Duration of one action [s] (20 Hz)."""
CORRECT_GAIN = 0.25
"""Fraction of the measured pose error added to the target per action by ``move_tool(correct=True)``."""
CORRECT_ZONE = 0.05
"""Distance to the goal [m] within which ``move_tool(correct=True)`` integrates the error."""
CORRECT_MAX = 0.08
"""Largest position correction per axis [m]."""


def down_quat(yaw: float = 0.0) -> np.ndarray:
    """World orientation of a tool pointing down (tool z = -world z), its fingers' closing axis turned
    by ``yaw`` [rad] about the world z."""
    base = np.array([0.0, 1.0, 0.0, 0.0])  # 180 degrees about x: tool z down
    turn = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])
    return quat_mul(turn, base)


def facing_quat(heading: float, pitch: float = 0.0) -> np.ndarray:
    """World orientation of a tool pointing along the horizontal ``heading`` [rad] (about the world z
    from +x), tilted down by ``pitch`` [rad], its fingers closing horizontally: the grasp of a vertical
    bar (a door handle) from the front; ``pitch`` = pi/2 gives ``down_quat(heading + pi/2)``."""
    c, s = np.cos(heading), np.sin(heading)
    z = np.array([np.cos(pitch) * c, np.cos(pitch) * s, -np.sin(pitch)])
    x = np.array([-s, c, 0.0])
    return mat_to_quat(np.column_stack([x, np.cross(z, x), z]))


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
        correct: bool = False,
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
            correct: Within ``CORRECT_ZONE`` of the goal, integrate the measured position error into the
                controller's target (at most ``CORRECT_MAX`` per axis): removes the steady-state sag of
                the arm far out or under a load.
        """
        steps, err = 0, np.inf
        bias = np.zeros(3)
        for steps in range(1, max_steps + 1):
            o = self.obs
            p_des, q_des = self._to_base(pos, quat)
            if correct:
                p_now, _ = self._to_base(o["ee_pos"], None)
                if np.linalg.norm(p_des - p_now) < CORRECT_ZONE:
                    bias = np.clip(bias + CORRECT_GAIN * (p_des - p_now), -CORRECT_MAX, CORRECT_MAX)
            d_pos = p_des + bias - np.asarray(o["target_pos_base"])
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

    def orbit(
        self,
        pivot: Any,
        angle: float,
        *,
        rate: float = 0.6,
        accel: float = 1.5,
        gain: float = 4.0,
        tol: float = 0.02,
        yaw_tol: float = 0.03,
        max_steps: int = 300,
        stop: Callable[[dict[str, Any]], bool] | None = None,
    ) -> MoveResult:
        """Turn the base as a rigid body about the vertical axis through ``pivot`` by ``angle`` (base mode).

        The base's position and heading rotate together (counter-clockwise seen from above for a
        positive ``angle``) and the arm holds its pose on the base, so the tool travels on a circle about
        the axis: with a door handle in the hand and the hinge as ``pivot``, the door swings with the
        robot. The reference turns with a trapezoidal profile (``rate``, capped so that the base moves at
        most 0.8 of its full speed, and ``accel``); the base tracks it with feed-forward plus ``gain`` on
        the pose error.

        Args:
            pivot: A point of the axis [m] (world; z ignored).
            angle: Turn [rad], relative to the base's pose at the call.
            rate: Top turn rate of the reference [rad/s].
            accel: Angular acceleration and deceleration of the reference [rad/s^2].
            gain: Feedback on the position and heading errors [1/s].
            tol: Final position tolerance of the base [m].
            yaw_tol: Final heading tolerance [rad].
            max_steps: Actions at most.
            stop: Ends the turn early (reached) when it returns True for an observation.
        """
        o = self.obs
        p = np.asarray(pivot, float)[:2]
        r0 = np.asarray(o["base_pos"][:2], float) - p
        yaw0 = float(o["base_yaw"])
        rate = min(rate, 0.8 * BASE_SPEED / max(float(np.linalg.norm(r0)), 1e-6))
        turn = abs(float(angle))
        increments = []  # the reference's turn per action, trapezoidal
        done, speed = 0.0, 0.0
        while done < turn - 1e-9:
            speed = min(rate, speed + accel * DT, np.sqrt(2 * accel * (turn - done)) + accel * DT / 2)
            increments.append(min(speed * DT, turn - done))
            done += increments[-1]
        n = len(increments)
        phi, steps, err = 0.0, 0, np.inf
        for steps in range(1, max_steps + 1):
            d_phi = float(np.sign(angle)) * increments[steps - 1] if steps <= n else 0.0
            rot = rotz(phi)[:2, :2]
            ff = rot @ np.array([-r0[1], r0[0]]) * d_phi / DT
            v = ff + gain * (p + rot @ r0 - np.asarray(o["base_pos"][:2]))
            w = d_phi / DT + gain * _wrap(yaw0 + phi - o["base_yaw"])
            local = rotz(o["base_yaw"])[:2, :2].T @ v
            cmd = np.array([local[0] / BASE_SPEED, local[1] / BASE_SPEED, w / YAW_SPEED])
            o = self.robot.act(base=np.clip(cmd, -1, 1), mode="base")
            phi += d_phi
            if stop is not None and stop(o):
                return MoveResult(True, steps, 0.0)
            err = float(np.linalg.norm(p + rotz(phi)[:2, :2] @ r0 - np.asarray(o["base_pos"][:2])))
            if steps >= n and err < tol and abs(_wrap(yaw0 + phi - o["base_yaw"])) < yaw_tol:
                return MoveResult(True, steps, err)
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
