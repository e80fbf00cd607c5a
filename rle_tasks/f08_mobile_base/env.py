"""Shelf integration trials: the submitted controller drives the base to the shelf and holds a target.

Protocol of one trial: the base starts at rest at the origin facing +x with the stowed arm and the
payload; ``reset(arm, target, payload_kg, layout)`` is called once, then ``control(t, qpos, qvel,
ctrl)`` at ``CONTROL_HZ`` (zero-order hold of the returned command, clipped to the actuator ranges).
The trial succeeds when the tool site stays within the tolerance of the target for the hold time
before ``EPISODE_S``; it fails at the first shelf contact by any robot geom, at a tilt above
``TILT_MAX_DEG``, at a sustained loss of wheel support, or at a participant fault (exception,
timeout, non-finite or wrongly shaped command), whose message is kept.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.catalog import load_catalog
from rle_design.rollout import ContactBetween, HoldAtTarget, SimulationWarnings, TiltLimit, run_episode
from rle_design.sandbox import ParticipantFault
from rle_design.stability import SupportLoad, SupportLost
from rle_tasks.core.runtime.protocol import Budget, FunctionSpec, Protocol
from rle_tasks.f08_mobile_base.batteries import LOSS_DURATION_S, LOSS_FRACTION, TILT_MAX_DEG
from rle_tasks.f08_mobile_base.public.scene import Scene

CONTROL_HZ = 50
EPISODE_S = 8.0
CALL_TIMEOUT_S = 30.0  # the card's hang cap per call [s]; VerifyContext.hang_cap_s caps it further
MAX_FAULTS_PER_ARM = 3
# Shelf trials: one controller runner per (arm, payload); a hang ends it, after 3 faults trials are skipped.
CONTROLLER_BUDGET = Budget(max_faults=MAX_FAULTS_PER_ARM, cpu_s=600.0, restart=True)
CONTROLLER = Protocol(
    module="submission",  # the name in every fault message of the shipped reports
    functions=(
        FunctionSpec(
            "reset",
            "arm: str, target: (3,) [m], payload_kg: float [kg], layout: dict (layout())",
            returns=None,
            timeout_s=CALL_TIMEOUT_S,
        ),
        FunctionSpec(
            "control",
            "t [s], qpos: (nq,), qvel: (nv,), ctrl: (nu,); returns the command (nu,) at 50 Hz",
            returns=("nu",),
            timeout_s=CALL_TIMEOUT_S,
        ),
    ),
)
SAMPLE_EVERY = 5  # physics steps between wheel-load samples


def layout(scene: Scene) -> dict:
    """Indices the controller needs (passed to ``reset``): qpos/qvel addresses and actuator order."""
    m = scene.model
    wheels = [m.joint(j).name for j in range(m.njnt) if m.joint(j).name.endswith("_spin")]
    return {
        "actuators": [m.actuator(i).name for i in range(m.nu)],
        "chassis_qpos": [int(m.jnt_qposadr[m.body_jntadr[scene.chassis]]) + i for i in range(7)],
        "chassis_qvel": [int(m.jnt_dofadr[m.body_jntadr[scene.chassis]]) + i for i in range(6)],
        "wheel_joints": wheels,
        "wheel_qvel": [int(m.jnt_dofadr[m.joint(w).id]) for w in wheels],
        "arm_joints": list(scene.chain.joint_names),
        "arm_qpos": [int(a) for a in scene.chain.qpos_adr],
        "arm_qvel": [int(a) for a in scene.chain.dof_adr],
        "wheel_actuators": [int(a) for a in scene.wheel_act],
        "arm_actuators": [int(a) for a in scene.arm_act],
        "control_hz": CONTROL_HZ,
        "timestep": float(m.opt.timestep),
    }


def trial_terms(scene: Scene, target: np.ndarray) -> tuple[SupportLoad, list]:
    """Terms of one trial, in the order they are checked at each control boundary.

    Wheel loads are sampled every ``SAMPLE_EVERY`` physics steps; a shelf contact by a robot geom
    fails the trial at any physics step; at each control period the trial fails at a chassis tilt
    above ``TILT_MAX_DEG`` or a sustained loss of wheel support, and succeeds once the tool has stayed
    within the tolerance of the target for the hold time.
    """
    shelf = load_catalog("shelf").extra
    m = scene.model
    n_sub = int(round(1.0 / (CONTROL_HZ * m.opt.timestep)))
    load = SupportLoad(scene.probe.supports, scene.mass * 9.81, LOSS_FRACTION, LOSS_DURATION_S, SAMPLE_EVERY)
    return load, [
        load,
        # every physics step: a touch shorter than a control period still counts
        ContactBetween(m.ngeom, scene.robot_geoms, scene.shelf_geoms, every=1, what="shelf collision"),
        TiltLimit(scene.chassis, TILT_MAX_DEG, every=n_sub, what="chassis tilt"),
        SupportLost(load, every=n_sub, what="wheel support"),
        SimulationWarnings(every=n_sub),  # a diverging simulation is never a success
        HoldAtTarget(
            scene.tool_site,
            target,
            float(shelf["tolerance"]),
            float(shelf["hold_time"]),
            every=n_sub,
            period=1.0 / CONTROL_HZ,
        ),
    ]


def run_trial(scene: Scene, sandbox, target: np.ndarray, payload_kg: float) -> dict:
    """One trial; returns a JSON-safe dict with ``success`` and the measured values.

    Raises:
        ParticipantFault: From the controller (the caller records it and restarts the sandbox).
    """
    m = scene.model
    data = scene.rest_data(0.0)
    lo, hi = m.actuator_ctrlrange.T
    n_sub = int(round(1.0 / (CONTROL_HZ * m.opt.timestep)))
    target = np.asarray(target, dtype=float)
    sandbox.call("reset", scene.arm, target, float(payload_kg), layout(scene), timeout=None)
    load, terms = trial_terms(scene, target)
    tilt, hold = terms[2], terms[5]

    def control(model: mujoco.MjModel, d: mujoco.MjData, t: float) -> None:
        # the state arrays are written to the child before the call returns: no copies needed
        cmd = sandbox.call(
            "control", float(d.time), d.qpos, d.qvel, d.ctrl, timeout=None, shape=(m.nu,), finite=True
        )
        np.minimum(np.maximum(np.asarray(cmd, dtype=float), lo), hi, out=d.ctrl)  # np.clip, cheaper per call

    ep = run_episode(
        m,
        data,
        int(round(EPISODE_S * CONTROL_HZ)) * n_sub,
        control=control,
        control_every=n_sub,
        terms=terms,
        prepare=sandbox.wake,  # the controller wakes up during the last physics step of each period
    )
    end = ep.end
    return {
        "success": ep.success,
        "reason": end.message if end is not None else "timeout: the target was not held long enough",
        "min_error_m": hold.best,
        "final_error_m": hold.error(data),
        "peak_tilt_deg": tilt.peak_deg,
        "min_wheel_frac": load.min_share,
        "time_s": float(data.time),
    }


__all__ = ["CONTROL_HZ", "EPISODE_S", "ParticipantFault", "layout", "run_trial", "trial_terms"]
