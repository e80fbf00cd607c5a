"""The verifier's measurements of one device copy, shared by its scenarios (``verifier``).

Probe torques as the trim sees them (``_measure_probes``: settled holding torques with static
friction and sensing errors), hidden test poses (``_test_poses``), the adapted feedforward of
``trim.py`` (``_adapted_ff``), hold drift, backdrive and push creep per pose (``_hold_back_push``,
with ``PUSH_N`` for ``PUSH_S`` and a warned pose at ``WARNED_MOTION_RAD``), its warnings in the
report (``_report_warnings``), and the residual map, analytic and cross-checked in MuJoCo within
``CROSSCHECK_TOL`` (``_residuals``).
"""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.errors import MjcfError
from rle_design.kinematics import GravityMap, model_from_mujoco, springs_from_mujoco
from rle_tasks.core.report import Findings
from rle_tasks.f09_gello import battery, device
from rle_tasks.f09_gello.public import gello_helpers as helpers
from rle_tasks.f09_gello.trim_runner import TrimRunner

CROSSCHECK_TOL = 1e-6
PUSH_N = 1.0
PUSH_S = 0.05
PUSH_TOTAL_S = 1.0
WARNED_MOTION_RAD = float(np.pi)  # drift and creep recorded for a pose whose simulation warned [rad]


def _measure_probes(m: mujoco.MjModel, poses: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Holding torques of a device copy at settled poses, with static-friction and sensing errors."""
    tau = battery.residual_mujoco(m, poses)
    band = helpers.PROBE_FRICTION_BAND * m.dof_frictionloss
    return tau + rng.uniform(-1.0, 1.0, tau.shape) * band + rng.normal(0.0, helpers.PROBE_NOISE, tau.shape)


def _test_poses(ranges: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
    lo, hi = ranges[:, 0] + 3 * helpers.LIMIT_MARGIN, ranges[:, 1] - 3 * helpers.LIMIT_MARGIN
    return rng.uniform(lo, hi, size=(n, len(ranges)))


def _adapted_ff(
    trim: TrimRunner,
    plan: np.ndarray | None,
    arm: str,
    dev: mujoco.MjModel,
    home: np.ndarray,
    poses: np.ndarray,
    rng: np.random.Generator,
) -> np.ndarray | None:
    """Feedforward at ``poses`` after adapting to device copy ``dev``; None when trim failed."""
    if plan is None:
        return None
    q = np.vstack([home, plan])
    params = trim.adapt(arm, q, _measure_probes(dev, q, rng))
    if params is None:
        return None
    out = []
    for p in poses:
        f = trim.feedforward(p, params)
        if f is None:
            return None
        out.append(f)
    return np.array(out)


def _hold_back_push(
    dev: mujoco.MjModel,
    poses: np.ndarray,
    ff: np.ndarray,
    net: np.ndarray,
    hold_s: float,
    push_dirs: np.ndarray | None,
    failed: list[str],
    effort: np.ndarray | None = None,
) -> dict[str, list[float]]:
    """Hold drift, backdrive and push creep per pose; a pose whose scenarios raise a MuJoCo warning
    gets the worst values (score 0) and its warning is appended to ``failed``. ``effort`` (N, nv)
    [N m] is added per joint to the breakaway torque before the worst joint is taken (the torque to
    accelerate the design's added inertia)."""
    bm = device.battery_model(dev)
    out: dict[str, list[float]] = {"drift": [], "backdrive": [], "push": []}
    for k, q in enumerate(poses):
        try:
            drift = battery.hold_drift(bm, q, ff[k], hold_s)
            tau = battery.backdrive(bm, q, ff[k], net[k])
            back = float(np.max(tau + (effort[k] if effort is not None else 0.0)))
            push = (
                battery.push_recovery(bm, q, ff[k], PUSH_N * push_dirs[k], PUSH_S, PUSH_TOTAL_S)
                if push_dirs is not None
                else None
            )
        except battery.SimulationFailed as exc:
            failed.append(f"test pose {k}: {exc.message}")
            drift, back, push = WARNED_MOTION_RAD, battery.BACKDRIVE_CAP, WARNED_MOTION_RAD
        out["drift"].append(drift)
        out["backdrive"].append(back)
        if push_dirs is not None:
            out["push"].append(push)
    return out


def _report_warnings(report: Findings, robot: str, scenario: str, failed: list[str]) -> None:
    for line in failed:
        report.add_error(
            "battery.simulation_warning",
            f"{robot} {scenario}: {line}; the simulation diverged or overflowed, the pose scores 0",
            f"{robot}/lead.xml",
        )


def _residuals(
    m: mujoco.MjModel, poses: np.ndarray, report: Findings, robot: str
) -> tuple[np.ndarray, float]:
    """Analytic residual over poses, cross-checked in MuJoCo (MuJoCo wins on disagreement)."""
    try:
        km = model_from_mujoco(m)
        springs = springs_from_mujoco(m, km)
    except MjcfError as exc:
        report.add_error(exc.code, f"{exc.message}; residuals taken from MuJoCo", f"{robot}/lead.xml")
        return battery.residual_mujoco(m, poses), float("nan")
    r = battery.residual_map(km, springs, poses, GravityMap(km))
    check = battery.residual_mujoco(m, poses[:16])
    err = float(np.max(np.abs(check - r[:16])))
    if err > CROSSCHECK_TOL:
        report.add_error(
            "kinematics.crosscheck",
            f"analytic and MuJoCo residuals differ by {err:.3g} N m; MuJoCo values used",
            f"{robot}/lead.xml",
        )
        return battery.residual_mujoco(m, poses), err
    return r, err
