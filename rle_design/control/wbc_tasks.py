"""Tasks of the whole-body QP (``wbc.WholeBodyQP``): what it tracks, with which weights and gains.

``WbcGains`` holds the weights [1] and PD gains [1/s^2, 1/s] of every task group the QP costs (the
whole-body COM, the named bodies' ``FrameTask``s, the swing feet, the stance feet's damping, the joint
posture), the regularisation of its unknowns, the torque-rate smoothing and the fraction of the effort
limits the torques may use. Every task's desired acceleration is ``a_ref + kp (x_ref - x) + kd (v_ref - v)``.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["FrameTask", "WbcGains"]


@dataclass(frozen=True)
class FrameTask:
    """A body task: its position (``pos`` weight) and/or orientation (``ori`` weight)."""

    body: str
    pos: float = 0.0
    ori: float = 0.0
    kp: float = 100.0
    kd: float = 20.0
    lead: int = 0
    """Track the reference this many frames ahead (a lag the plant cannot avoid: latency, saturation)."""


@dataclass(frozen=True)
class WbcGains:
    """Weights [1] and gains [1/s^2, 1/s] of the QP's tasks."""

    com: tuple[float, float, float] = (10.0, 10.0, 10.0)
    com_kp: float = 60.0
    com_kd: float = 15.0
    frames: tuple[FrameTask, ...] = ()
    swing_pos: float = 10.0
    swing_ori: float = 5.0
    swing_kp: float = 200.0
    swing_kd: float = 30.0
    contact_kd: float = 10.0
    posture: float = 0.5
    posture_kp: float = 100.0
    posture_kd: float = 20.0
    posture_lead: int = 0
    """Frames ahead the posture reference of ``lead_joints`` (indices into ``joints``) is taken."""
    lead_joints: tuple[int, ...] = ()
    reg_qdd: float = 1e-4
    reg_lam: float = 1e-4
    reg_tau: float = 1e-3
    tau_rate: float = 0.0
    """Weight of |(tau - tau_prev) / effort|^2: smooths the torques (the servo targets) between steps."""
    torque_fraction: float = 0.95
