"""Motion primitives of the LIBERO-10 scripted experts (``experts``): the ``_Driver`` that closes the
loop between a skill and the environment (one 7-D OSC action per 20 Hz control step, recording states,
observations, views and injected noise), the moves a skill is made of (``_move`` towards a point,
``_descend`` straight down onto one, ``_hold`` still, ``_pose`` until an orientation is reached too,
``_settle`` until the initial state's objects rest) and the rotation helpers they use (rotation
vectors, Rodrigues, yaw)."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from rle_tasks.envs.libero import LiberoEnv

POS_STEP = 0.05
"""Largest end-effector displacement of one action unit [m] (robosuite OSC ``output_max``)."""
ROT_STEP = 0.5
"""Largest rotation of one action unit [rad]."""
OPEN, CLOSED = -1.0, 1.0
STALL_STEPS, STALL_CENTRED = 8, 0.008
"""A descent also ends when the hand has not moved 1 mm up or down in this many steps while within
this horizontal distance of its point [m]: fingers resting on a rim, pushed to and fro across the
centring tolerance (measured on task 8: 37 steps held at a moka pot's lid)."""


def _axis_angle(rot: np.ndarray) -> np.ndarray:
    """Rotation vector of a rotation matrix [rad]."""
    c = np.clip((np.trace(rot) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(c)
    if angle < 1e-9:
        return np.zeros(3)
    axis = np.array([rot[2, 1] - rot[1, 2], rot[0, 2] - rot[2, 0], rot[1, 0] - rot[0, 1]])
    n = np.linalg.norm(axis)
    if n < 1e-9:  # angle ~ pi: the axis from the symmetric part
        w, v = np.linalg.eigh(rot)
        axis = v[:, np.argmax(w)]
        return axis * angle
    return axis / n * angle


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix about a unit ``axis`` (Rodrigues)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * k @ k


def _rz(yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class _Driver:
    """Closes the loop between skills and the environment, one action per control step."""

    def __init__(
        self,
        env: LiberoEnv,
        horizon: int,
        first_obs: dict,
        record: bool = False,
        noise: float = 0.0,
        rng: np.random.Generator | None = None,
        view_every: int = 1,
    ) -> None:
        self.env, self.horizon, self.record = env, horizon, record
        self.view_every = max(1, int(view_every))
        self.view_frames: list[int] = [0]
        self.noise, self.rng = float(noise), rng
        self.executed: list[np.ndarray] = []
        self.scene = env.scene()
        self.sim_states: list[np.ndarray] = [env.sim_state()] if record else []
        self.observations: list[np.ndarray] = [first_obs["state"]] if record else []
        self.views: dict[str, list[np.ndarray]] = (
            {v: [first_obs[v]] for v in ("agentview", "wrist")} if record and "agentview" in first_obs else {}
        )
        self.down = self.scene["eef_rot"].copy()  # the start orientation: fingers down
        self.actions: list[np.ndarray] = []
        self.success = False
        self.log: list[str] = []
        self.grasp: tuple = ()

    @property
    def done(self) -> bool:
        return self.success or len(self.actions) >= self.horizon

    def act(self, action: np.ndarray) -> None:
        # float32 as stored in demonstrations (and as a policy serves): a replay is then exact
        action = np.asarray(action, dtype=np.float32).astype(np.float64)
        sent = action
        if self.noise > 0.0:  # DART: execute a perturbed action, keep the expert's as the label
            kick = np.r_[self.rng.normal(0.0, self.noise, 6), 0.0]  # the gripper command stays
            sent = np.clip(action + kick, -1.0, 1.0).astype(np.float32).astype(np.float64)
            self.executed.append(sent)
        frame = len(self.actions) + 1  # the frame this step's observation is
        views = bool(self.views) and frame % self.view_every == 0
        obs, self.success = self.env.step(sent, views=views)
        self.actions.append(np.asarray(action, dtype=np.float64))
        self.scene = self.env.scene()
        if self.record:
            self.sim_states.append(self.env.sim_state())
            self.observations.append(obs["state"])
            if views:
                self.view_frames.append(frame)
                for v, frames in self.views.items():
                    frames.append(obs[v])

    def toward(self, pos: np.ndarray, rot: np.ndarray, grip: float, gain: float = 1.0) -> np.ndarray:
        sc = self.scene
        dp = np.clip(gain * (pos - sc["eef_pos"]) / POS_STEP, -1.0, 1.0)
        dr = np.clip(_axis_angle(rot @ sc["eef_rot"].T) / ROT_STEP, -1.0, 1.0)
        return np.concatenate([dp, dr, [grip]])


def _move(d: _Driver, pos, rot, grip, tol=0.01, max_steps=60, gain=1.0, stall: int = 0) -> Iterator[None]:
    """Towards ``pos`` until within ``tol``; with ``stall`` > 0 also ends when the distance has not
    shrunk by 1 mm in that many steps (something blocks the way)."""
    dist: list[float] = []
    for _ in range(max_steps):
        dist.append(float(np.linalg.norm(d.scene["eef_pos"] - pos)))
        if d.done or dist[-1] < tol or (stall and len(dist) > stall and dist[-stall - 1] - dist[-1] < 0.001):
            return
        d.act(d.toward(np.asarray(pos, float), rot, grip, gain))
        yield


def _descend(
    d: _Driver, point: np.ndarray, rot: np.ndarray, grip: float, max_steps: int = 60
) -> Iterator[None]:
    """Straight down onto ``point``: the horizontal error is removed before the gripper drops further
    (fingers a few mm from an object's side), and the descent ends early when the fingers rest on
    something (no progress for five steps)."""
    heights: list[float] = []  # while descending
    every: list[float] = []  # at every step
    for _ in range(max_steps):
        if d.done:
            return
        e = point - d.scene["eef_pos"]
        if np.linalg.norm(e) < 0.005:
            return
        every.append(float(d.scene["eef_pos"][2]))
        if (
            len(every) > STALL_STEPS
            and np.ptp(every[-STALL_STEPS:]) < 0.001
            and np.hypot(e[0], e[1]) < STALL_CENTRED
        ):
            return  # resting while the last millimetres of centring go back and forth
        target = point.copy()
        # centred within 4 mm for the last 3 cm; higher up a larger error is corrected on the way down
        if np.hypot(e[0], e[1]) > 0.004 + 0.1 * max(0.0, -e[2] - 0.03):
            target[2] = d.scene["eef_pos"][2]  # hold the height until centred
            heights.clear()
        else:
            heights.append(float(d.scene["eef_pos"][2]))
            if len(heights) > 5 and heights[-6] - heights[-1] < 0.001:
                return  # resting on the table or the object
        a = d.toward(target, rot, grip, gain=0.7)
        a[2] = np.clip(a[2], -0.5, 0.5)  # at most 2.5 cm a step near objects
        d.act(a)
        yield


def _hold(d: _Driver, grip: float, steps: int) -> Iterator[None]:
    pos, rot = d.scene["eef_pos"].copy(), d.scene["eef_rot"].copy()
    for _ in range(steps):
        if d.done:
            return
        d.act(d.toward(pos, rot, grip))
        yield


def _pose(d: _Driver, pos, rot, grip, tol=0.01, rot_tol=0.05, max_steps=60, gain=1.0) -> Iterator[None]:
    """Like ``_move``, but until the orientation is reached as well (within ``rot_tol`` rad)."""
    pos = np.asarray(pos, float)
    for _ in range(max_steps):
        sc = d.scene
        if d.done or (
            np.linalg.norm(sc["eef_pos"] - pos) < tol
            and np.linalg.norm(_axis_angle(rot @ sc["eef_rot"].T)) < rot_tol
        ):
            return
        d.act(d.toward(pos, rot, grip, gain))
        yield


def _settle(d: _Driver, max_steps: int = 40) -> None:
    """Hold still until no object moves by 1 mm in a step: LIBERO's official initial states leave
    objects slightly interpenetrating, and some pop up to a metre high before they come to rest."""
    before = {n: o["pos"].copy() for n, o in d.scene["objects"].items()}
    for _ in _hold(d, OPEN, max_steps):
        now = {n: o["pos"].copy() for n, o in d.scene["objects"].items()}
        if max(float(np.linalg.norm(now[n] - before[n])) for n in now) < 0.001:
            return
        before = now
