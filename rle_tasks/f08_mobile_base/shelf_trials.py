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

import math

import mujoco
import numpy as np

from rle_design.catalog import load_catalog
from rle_design.sandbox import ParticipantFault
from rle_design.stability import SupportLossMonitor, root_tilt, sample_contacts
from rle_tasks.f08_mobile_base.batteries import LOSS_DURATION_S, LOSS_FRACTION, TILT_MAX_DEG
from rle_tasks.f08_mobile_base.scene import Scene

CONTROL_HZ = 50
EPISODE_S = 8.0
CALL_TIMEOUT_S = 30.0  # the card's hang cap; the verifier sets it on the sandbox (VerifyContext.hang_cap_s)
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


def run_trial(scene: Scene, sandbox, target: np.ndarray, payload_kg: float) -> dict:
    """One trial; returns a JSON-safe dict with ``success`` and the measured values.

    Raises:
        ParticipantFault: From the controller (the caller records it and restarts the sandbox).
    """
    shelf = load_catalog("shelf").extra
    tol, hold_time = float(shelf["tolerance"]), float(shelf["hold_time"])
    m = scene.model
    data = scene.rest_data(0.0)
    lo, hi = m.actuator_ctrlrange.T
    n_sub = int(round(1.0 / (CONTROL_HZ * m.opt.timestep)))
    n_blocks = int(round(EPISODE_S * CONTROL_HZ))
    target = np.asarray(target, dtype=float)
    sandbox.call("reset", scene.arm, target, float(payload_kg), layout(scene), timeout=None)
    monitor = SupportLossMonitor(scene.mass * 9.81, 4, LOSS_FRACTION, LOSS_DURATION_S)
    robot_mask = np.zeros(m.ngeom, dtype=bool)
    robot_mask[scene.robot_geoms] = True
    shelf_mask = np.zeros(m.ngeom, dtype=bool)
    shelf_mask[scene.shelf_geoms] = True
    held, best, peak_tilt = 0.0, math.inf, 0.0
    window: list[np.ndarray] = []
    reason = "timeout: the target was not held long enough"
    success = False
    for _ in range(n_blocks):
        cmd = sandbox.call(
            "control",
            float(data.time),
            data.qpos.copy(),
            data.qvel.copy(),
            data.ctrl.copy(),
            timeout=None,
            shape=(m.nu,),
            finite=True,
        )
        data.ctrl[:] = np.clip(np.asarray(cmd, dtype=float), lo, hi)
        for _ in range(n_sub // SAMPLE_EVERY):
            mujoco.mj_step(m, data, nstep=SAMPLE_EVERY)
            window = (window + [sample_contacts(m, data, scene.probe.supports).normal])[-10:]
            monitor.update(float(data.time), np.mean(window, axis=0))
        hit = None
        if data.ncon:
            g1, g2 = data.contact.geom1[: data.ncon], data.contact.geom2[: data.ncon]
            bad = (robot_mask[g1] & shelf_mask[g2]) | (robot_mask[g2] & shelf_mask[g1])
            if bad.any():
                c = int(np.argmax(bad))
                hit = (m.geom(int(g1[c])).name, m.geom(int(g2[c])).name)
        tilt = math.degrees(root_tilt(data, scene.chassis))
        peak_tilt = max(peak_tilt, tilt)
        err = float(np.linalg.norm(data.site_xpos[scene.tool_site] - target))
        best = min(best, err)
        if hit:
            reason = f"shelf collision: {hit[0]} touched {hit[1]} at t = {data.time:.2f} s"
            break
        if tilt > TILT_MAX_DEG:
            reason = f"tipping: chassis tilt {tilt:.1f} deg > {TILT_MAX_DEG} deg at t = {data.time:.2f} s"
            break
        if monitor.lost:
            reason = (
                f"sustained loss of wheel support ({monitor.longest_loss:.2f} s) at t = {data.time:.2f} s"
            )
            break
        held = held + 1.0 / CONTROL_HZ if err <= tol else 0.0
        if held >= hold_time - 1e-9:
            success, reason = True, "held"
            break
    return {
        "success": success,
        "reason": reason,
        "min_error_m": best,
        "final_error_m": float(np.linalg.norm(data.site_xpos[scene.tool_site] - target)),
        "peak_tilt_deg": peak_tilt,
        "min_wheel_frac": float(monitor.min_force.min()) / (scene.mass * 9.81 / 4),
        "time_s": float(data.time),
    }


__all__ = ["CONTROL_HZ", "EPISODE_S", "ParticipantFault", "layout", "run_trial"]
