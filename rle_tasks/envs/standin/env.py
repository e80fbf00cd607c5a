"""``StandinEnv``: one stand-in task driven by 14-D joint targets at 10 Hz.

State (16): per arm (``left/`` then ``right/``) its six joint angles [rad] and its two finger
positions [m] (0..0.04 and -0.04..0). Action (14): per arm six joint targets [rad] (clipped to the
joint ranges) and a gripper command in [0, 1] (1 open, 0 closed; each finger's target is
0.04 x command). Each action is held for ``SUBSTEPS`` physics steps of 2 ms, the joint targets
moving linearly from the previous action's over the first ``RAMP`` of them (a servo's trajectory
interpolation), physics stepped in C by the toolkit's ``rle_design.rollout.advance`` (the same zero-order
hold as every battery's episode loop; the step itself stays a method, since a served policy and the
dataset builder drive it from outside).

Views: ``head`` and ``front`` RGB, ``VIEW`` x ``VIEW`` x 3 uint8, rendered only when asked
(``observe(views=True)``). ``privileged()`` gives the objects' poses (scripted experts, tests);
nothing the served policy receives contains them.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.control.cameras import render_rgb
from rle_design.rollout import advance
from rle_tasks.envs.standin import tasks as _tasks
from rle_tasks.envs.standin.scene import (
    ARMS,
    CAMERAS,
    CLEAN,
    GRIPPER_OPEN,
    SceneLook,
    arm_joint_names,
    build_spec,
    finger_joint_names,
)

__all__ = ["ACTION_DIM", "HOME", "STATE_DIM", "StandinEnv", "VIEW"]

STATE_DIM = 16
ACTION_DIM = 14
VIEW = 128
SUBSTEPS = 50
"""Physics steps per action (10 Hz at 2 ms)."""
RAMP = 25
"""Physics steps over which a new joint target is interpolated from the previous one."""
HOME = np.array((0.0, -2.1, 2.4, -1.871, -1.571, 0.0))
"""Both arms' start posture [rad]: tool pointing down 0.22 m above the table and 0.26 m in front of
the base, behind the objects, so that neither wrist hides them from the head camera (the catalog's
UR5e home holds the wrists right above the work area)."""


class StandinEnv:
    """One task of the stand-in in one scene look (module docstring).

    Args:
        task: Task index (``tasks.TASKS``).
        look: Scene appearance (the robust track's perturbations; ``CLEAN`` for the open track).
    """

    def __init__(self, task: int, look: SceneLook = CLEAN) -> None:
        self.task_index = int(task)
        self.task = _tasks.TASKS[self.task_index]
        self.look = look
        self.model: mujoco.MjModel | None = None
        self.data: mujoco.MjData | None = None

    def _build(self) -> None:
        spec = build_spec(self.look)
        _tasks.add_objects(spec, self.task_index, 0, self.look)
        m = self.model = spec.compile()
        self.data = mujoco.MjData(m)
        self._q = np.concatenate([[m.jnt_qposadr[m.joint(j).id] for j in arm_joint_names(p)] for p in ARMS])
        self._f = np.array([m.jnt_qposadr[m.joint(j).id] for p in ARMS for j in finger_joint_names(p)])
        self._arm_act = np.concatenate([[m.actuator(j).id for j in arm_joint_names(p)] for p in ARMS])
        self._grip_act = np.array(
            [[m.actuator(p + "hand/gripper_finger_joint1").id, m.actuator(p + "hand/gripper_finger_joint2").id]
             for p in ARMS]
        )  # fmt: skip
        joints = [m.joint(j).id for p in ARMS for j in arm_joint_names(p)]
        self._lo, self._hi = m.jnt_range[joints, 0], m.jnt_range[joints, 1]
        self._body_pos0 = m.body_pos.copy()

    def reset(self, seed: int) -> dict[str, np.ndarray]:
        """Arms at home, grippers open, the objects at the layout of ``seed`` (settled for 0.2 s); the
        observation with views."""
        if self.model is None:
            self._build()
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        m.body_pos[:] = self._body_pos0
        _tasks.place_objects(m, d, self.task_index, seed, self.look)
        home = np.tile(HOME, 2)
        d.qpos[self._q] = home
        d.ctrl[self._arm_act] = home
        for i in range(2):
            d.qpos[self._f[2 * i]], d.qpos[self._f[2 * i + 1]] = GRIPPER_OPEN, -GRIPPER_OPEN
            d.ctrl[self._grip_act[i]] = (GRIPPER_OPEN, -GRIPPER_OPEN)
        mujoco.mj_forward(m, d)
        mujoco.mj_step(m, d, 100)  # objects settle on the table
        self._start = {o: d.xpos[m.body(o).id].copy() for o in self.task.objects}
        self._target = home.copy()
        self.steps = 0
        return self.observe(views=True)

    @property
    def state(self) -> np.ndarray:
        d = self.data
        out = np.empty(STATE_DIM)
        for i in range(2):
            out[8 * i : 8 * i + 6] = d.qpos[self._q[6 * i : 6 * i + 6]]
            out[8 * i + 6 : 8 * i + 8] = d.qpos[self._f[2 * i : 2 * i + 2]]
        return out

    def observe(self, views: bool = True) -> dict[str, np.ndarray]:
        """``state`` and, with ``views``, the ``head`` and ``front`` images."""
        obs = {"state": self.state}
        if views:
            obs |= render_rgb(self.model, self.data, CAMERAS, (VIEW, VIEW))
        return obs

    def step(self, action: np.ndarray) -> bool:
        """Execute one 14-D action (module docstring); whether the task's goal holds afterwards."""
        a = np.nan_to_num(np.asarray(action, float).reshape(ACTION_DIM))
        target = np.clip(np.concatenate([a[0:6], a[7:13]]), self._lo, self._hi)
        grip = np.clip(a[[6, 13]], 0.0, 1.0) * GRIPPER_OPEN
        m, d = self.model, self.data
        ctrl = d.ctrl.copy()
        for i in range(2):
            ctrl[self._grip_act[i]] = (grip[i], -grip[i])
        prev = self._target
        pieces = 5
        for k in range(1, pieces + 1):
            ctrl[self._arm_act] = prev + (target - prev) * (k / pieces)
            advance(m, d, ctrl, RAMP // pieces)
        advance(m, d, ctrl, SUBSTEPS - RAMP)
        self._target = target
        self.steps += 1
        return self.success()

    def success(self) -> bool:
        return _tasks.success(self.task_index, self.model, self.data, self._start)

    def privileged(self) -> dict[str, np.ndarray]:
        """Object -> (x, y, z, qw, qx, qy, qz) [m] (experts and tests only)."""
        m, d = self.model, self.data
        return {o: np.concatenate([d.xpos[m.body(o).id], d.xquat[m.body(o).id]]) for o in self.task.objects}
