"""Cartesian movement helper: ``move_to(pos, quat)``, ``grasp()``, ``release()`` as ordinary actions.

The helper holds no simulator: it only calls ``step(action)`` (a 12 n-D action, each call one metered
step when ``step`` is a ``LedgerClient``'s) and reads the observation that call returns, so every
motion it makes is an ordinary action any agent could send and is metered like one.

``move_to`` drives the arm's *target* towards the goal along a straight line, at most ``POS_STEP``
and ``ROT_STEP`` per action (``speed`` scales both), then waits until the measured tool site is
within ``tol_pos`` [m] and ``tol_rot`` [rad] of the goal or ``max_steps`` pass. When the tool site
settles away from the goal (a payload's weight), the helper shifts the target by the residual, so
the final pose error is closed by measurement, not by a model of the load.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from rle_design.control.layout import ACTION_SIZE, GRIPPER, POS_STEP, ROT_STEP
from rle_design.control.osc import orientation_error

__all__ = ["ArmGroup", "CartesianHelper", "MoveResult"]

StepFn = Callable[[np.ndarray], dict[str, Any]]


@dataclass(frozen=True)
class MoveResult:
    """Outcome of one helper call.

    Attributes:
        reached: The tool site ended within tolerance of the goal.
        steps: Actions issued.
        pos_error: Final position error [m].
        rot_error: Final orientation error [rad].
    """

    reached: bool
    steps: int
    pos_error: float
    rot_error: float


class CartesianHelper:
    """Moves one arm of a ``TabletopEnv`` session through ``step`` (see the module docstring).

    Args:
        step: Sends one action, returns the observation (``LedgerClient.step`` or a session's).
        obs: The current observation (e.g. from ``reset`` or ``observe``).
        arm: Index of the arm moved; the other arms get holding actions (their grippers at
            ``grips[i]``).
        n_arms: Arms in the action.
        arm_size: Numbers per arm in the action (12, or 7 for the pose-and-gripper layout).
    """

    def __init__(
        self, step: StepFn, obs: dict[str, Any], arm: int = 0, n_arms: int = 1, arm_size: int = ACTION_SIZE
    ) -> None:
        self._step = step
        self.obs = obs
        self.arm = arm
        self.n_arms = n_arms
        self.arm_size = arm_size
        # every gripper keeps the command it has (the observation's ``gripper_command``; open where an
        # observation does not say): a helper made while an arm holds a part does not drop it
        arms = obs.get("arms", []) if isinstance(obs, dict) else []
        self.grips = [
            float(arms[i].get("gripper_command", -1.0)) if i < len(arms) else -1.0 for i in range(n_arms)
        ]
        self.grip = self.grips[arm]
        self.steps = 0
        self.issued: list[np.ndarray] = []
        self.record = False

    @property
    def state(self) -> dict[str, Any]:
        return self.obs["arms"][self.arm]

    def act(self, arm_action: np.ndarray | None = None, grip: float | None = None) -> dict[str, Any]:
        """Send one action: ``arm_action`` (6, in [-1, 1]) for this arm, holding actions for the others."""
        if grip is not None:
            self.grip = float(grip)
        action = np.zeros(self.arm_size * self.n_arms)
        action[GRIPPER :: self.arm_size] = self.grips
        base = self.arm_size * self.arm
        if arm_action is not None:
            action[base : base + 6] = np.clip(arm_action, -1.0, 1.0)
        action[base + GRIPPER] = self.grip
        if self.record:
            self.issued.append(action.copy())
        self.obs = self._step(action)
        self.steps += 1
        return self.obs

    def _to_base(self, vec: np.ndarray) -> np.ndarray:
        quat = np.asarray(self.state["base_quat"], dtype=float)
        w, x, y, z = quat
        rot = np.array(
            [
                [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
            ]
        )
        return rot.T @ vec

    def move_to(
        self,
        pos: np.ndarray,
        quat: np.ndarray | None = None,
        *,
        speed: float = 1.0,
        tol_pos: float = 0.002,
        tol_rot: float = 0.02,
        max_steps: int = 400,
    ) -> MoveResult:
        """Move the tool site to ``pos`` [m] (world) and ``quat`` (w, x, y, z; None keeps the target's)."""
        goal = np.asarray(pos, dtype=float)
        goal_q = np.asarray(self.state["target_quat"] if quat is None else quat, dtype=float)
        aim = goal.copy()
        n = 0
        settled = 0
        while n < max_steps:
            s = self.state
            d_pos = aim - np.asarray(s["target_pos"])
            d_rot = orientation_error(goal_q, np.asarray(s["target_quat"]))
            a = np.zeros(6)
            a[:3] = self._to_base(d_pos) / POS_STEP
            a[3:] = self._to_base(d_rot) / ROT_STEP
            peak = float(np.max(np.abs(a)))
            self.act(a * (speed / peak) if peak > speed else a)
            n += 1
            s = self.state
            e_pos = goal - np.asarray(s["ee_pos"])
            e_rot = orientation_error(goal_q, np.asarray(s["ee_quat"]))
            target_done = np.linalg.norm(aim - np.asarray(s["target_pos"])) < 1e-4
            still = np.linalg.norm(np.asarray(s["dq"])) < 0.05
            if np.linalg.norm(e_pos) < tol_pos and np.linalg.norm(e_rot) < tol_rot and still:
                return MoveResult(True, n, float(np.linalg.norm(e_pos)), float(np.linalg.norm(e_rot)))
            if target_done and np.linalg.norm(np.asarray(s["dq"])) < 0.02:
                settled += 1
                if settled >= 3:
                    aim = aim + e_pos  # close a steady-state offset by measurement
                    settled = 0
        s = self.state
        e_pos = float(np.linalg.norm(goal - np.asarray(s["ee_pos"])))
        e_rot = float(np.linalg.norm(orientation_error(goal_q, np.asarray(s["ee_quat"]))))
        reached = e_pos < tol_pos and e_rot < tol_rot
        if not reached:
            warnings.warn(
                f"move_to used its {max_steps} actions and ended {1000 * e_pos:.1f} mm and {e_rot:.3f} rad from the "
                f"goal (tolerance {1000 * tol_pos:.1f} mm, {tol_rot:.3f} rad): a pose the arm cannot reach, or a "
                "blocked path, keeps its error",
                RuntimeWarning,
                stacklevel=2,
            )
        return MoveResult(reached, n, e_pos, e_rot)

    def wait(self, steps: int) -> None:
        """Hold the current targets for ``steps`` actions."""
        for _ in range(steps):
            self.act()

    def grasp(self, steps: int = 15) -> MoveResult:
        """Close the gripper and hold still while the fingers close."""
        return self.set_gripper(1.0, steps)

    def release(self, steps: int = 15) -> MoveResult:
        """Open the gripper and hold still while the fingers open."""
        return self.set_gripper(-1.0, steps)

    def set_gripper(self, command: float, steps: int = 15) -> MoveResult:
        """Command the gripper to ``command`` (-1 open, +1 closed; values between aim the fingers part
        way, so a part narrower than the opening is squeezed gently) and hold still ``steps`` actions."""
        self.grip = float(command)
        self.wait(steps)
        return MoveResult(True, steps, 0.0, 0.0)


class ArmGroup:
    """One ``CartesianHelper`` per arm of one session, sharing its step function.

    ``arm(i)`` returns arm ``i``'s helper with the latest observation and every other arm's current
    gripper command in its holding actions, so an arm holding a part keeps holding it while another
    arm moves.

    Args:
        step: Sends one action, returns the observation.
        obs: The current observation.
        n_arms: Arms in the action.
        arm_size: Numbers per arm in the action.
    """

    def __init__(self, step: StepFn, obs: dict[str, Any], n_arms: int, arm_size: int = ACTION_SIZE) -> None:
        self.helpers = [
            CartesianHelper(step, obs, arm=i, n_arms=n_arms, arm_size=arm_size) for i in range(n_arms)
        ]
        self._last = self.helpers[0]

    def arm(self, i: int) -> CartesianHelper:
        helper = self.helpers[i]
        helper.obs = self._last.obs
        for other in self.helpers:
            helper.grips[other.arm] = other.grip
        self._last = helper
        return helper
