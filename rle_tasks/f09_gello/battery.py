"""Measurements on a leader: analytic residual maps and MuJoCo hold, backdrive and push batteries.

All MuJoCo measurements use ``device.battery_model`` (dt 2 ms, ``noslip_iterations`` 10 so joint
``frictionloss`` truly sticks below its threshold instead of creeping, contacts off) and a frozen
feedforward torque ``tau_ff`` applied through ``qfrc_applied`` for the whole scenario.

* residual: ``r(q) = g(q) - tau_spring(q)`` [N m] (Pinocchio + spring model), cross-checked against
  MuJoCo ``qfrc_bias - qfrc_passive`` at rest;
* hold drift: largest joint excursion [rad] during ``hold_s`` after releasing the arm at rest;
* backdrive: per joint, with the other joints held (their friction raised to ``HELD_FRICTION``, as
  when a user steadies the arm and moves one joint), the smallest constant external torque that moves the joint by more than
  ``MOVE_RAD`` in the pushed direction within ``PROBE_S``, in the harder direction (bracketed around the friction-model
  prediction ``tau_f + |r - tau_ff|``, bisection when the bracket fails) [N m];
* added inertia: per joint, the torque ``ACCEL_REF x max(0, M_jj(q) - M_jj^stock(q))`` to accelerate
  what the design added (``added_inertia``); the backdrive checkpoints score breakaway plus this
  effort, so mass that makes the arm hold or recover better is paid for in how hard it is to move;
* push recovery: a force pulse at the handle, then the creep over the last ``CREEP_WINDOW_S`` [rad].

Every scenario watches MuJoCo's warning counters (``data.warning``): a scenario that raises one (bad
qacc, NaN, buffer overflow: a diverged or overflowed simulation, whose automatic state reset would
otherwise read as motion or as holding) raises ``SimulationFailed`` naming the warning; it is never
a pass.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.errors import RleError
from rle_design.kinematics import GravityMap, KinematicModel, spring_torque
from rle_design.rollout import Event, SimulationWarnings, Term, run_episode
from rle_design.scene import element_id
from rle_tasks.f09_gello.assembly import HANDLE_SITE

MOVE_RAD = 1e-4
PROBE_S = 0.2
BACKDRIVE_CAP = 1.5
HELD_FRICTION = 100.0
CREEP_WINDOW_S = 0.5
ACCEL_REF = 3.0
"""Joint acceleration of a deliberate teleoperation move [rad/s^2]: a 0.5 rad reach in 1 s on a
minimum-jerk profile peaks at (10 / sqrt(3)) x 0.5 rad / (1 s)^2 = 2.9 rad/s^2."""


class SimulationFailed(RleError):
    """A battery scenario raised a MuJoCo warning; the message names it and its time."""

    def __init__(self, message: str) -> None:
        super().__init__(message, code="battery.simulation_warning")


def _checked(d: mujoco.MjData) -> None:
    """Raise ``SimulationFailed`` if any warning counter is non-zero. ``_reset`` zeroes the counters
    (``mj_resetData``) and they only grow, so one read after a scenario sees every warning in it, also
    when a term ended the episode early (a diverged state reset reads as motion)."""
    grown = np.flatnonzero(SimulationWarnings.counts(d))
    if grown.size:
        names = ", ".join(mujoco.mjtWarning(int(i)).name for i in grown)
        raise SimulationFailed(f"simulation warning {names} by t = {d.time:.3f} s")


def residual_map(
    km: KinematicModel, springs: list, poses: np.ndarray, gmap: GravityMap | None = None
) -> np.ndarray:
    """Analytic residual r(q) = g(q) - tau_spring(q) over poses (N, n) [N m]."""
    g = (gmap or GravityMap(km))(poses)
    if springs:
        g = g - np.array([spring_torque(km, springs, q) for q in poses])
    return g


def residual_mujoco(m: mujoco.MjModel, poses: np.ndarray) -> np.ndarray:
    """MuJoCo residual at rest: ``qfrc_bias - qfrc_passive`` (gravity minus springs) [N m]."""
    d = mujoco.MjData(m)
    out = np.empty((len(poses), m.nv))
    for k, q in enumerate(poses):
        d.qpos[:] = q
        d.qvel[:] = 0.0
        mujoco.mj_forward(m, d)
        out[k] = d.qfrc_bias - d.qfrc_passive
    return out


def _reset(m: mujoco.MjModel, d: mujoco.MjData, q0: np.ndarray, tau: np.ndarray) -> None:
    mujoco.mj_resetData(m, d)
    d.qpos[:] = q0
    d.qfrc_applied[:] = tau
    mujoco.mj_forward(m, d)


class _Drift(Term):
    """Largest joint excursion from ``q0``, sampled every 10 steps and after the last [rad]."""

    name, every, final = "drift", 10, True

    def __init__(self, q0: np.ndarray) -> None:
        self.q0, self.worst = q0, 0.0

    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> Event | None:
        self.worst = max(self.worst, float(np.max(np.abs(data.qpos - self.q0))))
        return None


class _Moved(Term):
    """Succeeds once ``joint`` has moved more than ``MOVE_RAD`` in direction ``sign``."""

    name = "moved"

    def __init__(self, q0: np.ndarray, joint: int, sign: float) -> None:
        self.q0, self.joint, self.sign = q0, joint, sign

    def update(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> Event | None:
        if self.sign * (data.qpos[self.joint] - self.q0[self.joint]) > MOVE_RAD:
            return Event(self.name, "success", f"joint {self.joint} moved", t)
        return None


def hold_drift(m: mujoco.MjModel, q0: np.ndarray, tau_ff: np.ndarray, hold_s: float) -> float:
    """Largest excursion max_t max_i |q_i(t) - q0_i| after release at rest [rad]."""
    d = mujoco.MjData(m)
    _reset(m, d, q0, tau_ff)
    drift = _Drift(q0)
    run_episode(m, d, int(round(hold_s / m.opt.timestep)), terms=[drift])
    _checked(d)
    return drift.worst


def _moves(
    m: mujoco.MjModel, d: mujoco.MjData, q0: np.ndarray, tau: np.ndarray, joint: int, sign: float
) -> bool:
    """Whether ``joint`` moves by more than ``MOVE_RAD`` in direction ``sign`` within ``PROBE_S``."""
    _reset(m, d, q0, tau)
    moved = run_episode(m, d, int(round(PROBE_S / m.opt.timestep)), terms=[_Moved(q0, joint, sign)]).success
    _checked(d)
    return moved


def breakaway(
    m: mujoco.MjModel, q0: np.ndarray, tau_ff: np.ndarray, joint: int, sign: float, predicted: float
) -> float:
    """External torque magnitude that starts ``joint`` moving in direction ``sign`` [N m]."""
    d = mujoco.MjData(m)
    unit = np.zeros(m.nv)
    unit[joint] = sign

    def moves(t: float) -> bool:
        return _moves(m, d, q0, tau_ff + t * unit, joint, sign)

    lo, hi = max(0.0, 0.97 * predicted - 1e-3), min(BACKDRIVE_CAP, 1.03 * predicted + 1e-3)
    if lo == 0.0 and moves(0.0):
        return 0.0
    if not moves(lo) and moves(hi):
        return predicted
    lo, hi = 0.0, BACKDRIVE_CAP
    if moves(0.0):
        return 0.0
    if not moves(hi):
        return BACKDRIVE_CAP
    for _ in range(12):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if moves(mid) else (mid, hi)
    return hi


def backdrive(m: mujoco.MjModel, q0: np.ndarray, tau_ff: np.ndarray, net_residual: np.ndarray) -> np.ndarray:
    """Per-joint backdrive torque: breakaway in the harder direction [N m].

    Args:
        m: Battery model.
        q0: Pose [rad].
        tau_ff: Frozen feedforward [N m].
        net_residual: Predicted ``r(q0) - tau_ff`` (brackets the measurement) [N m].
    """
    out = np.empty(m.nv)
    friction = m.dof_frictionloss.copy()
    try:
        for j in range(m.nv):
            m.dof_frictionloss[:] = HELD_FRICTION
            m.dof_frictionloss[j] = friction[j]
            tf = float(friction[j])
            vals = [breakaway(m, q0, tau_ff, j, s, max(0.0, tf - s * net_residual[j])) for s in (1.0, -1.0)]
            out[j] = max(vals)
    finally:
        m.dof_frictionloss[:] = friction
    return out


def joint_inertia(m: mujoco.MjModel, poses: np.ndarray) -> np.ndarray:
    """Diagonal of the joint-space inertia matrix M(q) per pose, shape (N, nv) [kg m^2]: the inertia
    a user moves when turning one joint with the others held (armature included)."""
    d = mujoco.MjData(m)
    full = np.zeros((m.nv, m.nv))
    out = np.empty((len(poses), m.nv))
    for k, q in enumerate(np.asarray(poses, float)):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        mujoco.mj_crb(m, d)
        mujoco.mj_fullM(m, d, full)
        out[k] = np.diag(full)
    return out


def added_inertia(m: mujoco.MjModel, stock: mujoco.MjModel, poses: np.ndarray) -> np.ndarray:
    """Joint inertia the design adds over the stock leader, ``max(0, M_jj - M_jj^stock)`` per pose,
    shape (N, nv) [kg m^2]. Both models have the stock joints in the same order."""
    return np.maximum(joint_inertia(m, poses) - joint_inertia(stock, poses), 0.0)


def push_recovery(
    m: mujoco.MjModel, q0: np.ndarray, tau_ff: np.ndarray, force: np.ndarray, pulse_s: float, total_s: float
) -> float:
    """Creep over the last ``CREEP_WINDOW_S`` after a force pulse at the handle [rad].

    Args:
        force: World force at the handle site during the pulse [N].
        pulse_s: Pulse duration [s].
        total_s: Scenario duration from the start of the pulse [s].
    """
    d = mujoco.MjData(m)
    _reset(m, d, q0, tau_ff)
    sid = element_id(m, "site", HANDLE_SITE)
    body = int(m.site_bodyid[sid])
    dt = m.opt.timestep
    steps, pulse, window = int(round(total_s / dt)), int(round(pulse_s / dt)), int(round(CREEP_WINDOW_S / dt))
    qfrc = np.zeros(m.nv)
    k = 0

    def push(model: mujoco.MjModel, data: mujoco.MjData, t: float) -> None:
        nonlocal k
        qfrc[:] = 0.0
        if k < pulse:
            mujoco.mj_applyFT(
                model, data, np.asarray(force, float), np.zeros(3), data.site_xpos[sid].copy(), body, qfrc
            )
        data.qfrc_applied[:] = tau_ff + qfrc
        k += 1

    run_episode(m, d, steps - window, control=push)
    mark = d.qpos.copy()
    run_episode(m, d, window, control=push)
    _checked(d)
    return float(np.max(np.abs(d.qpos - mark)))
