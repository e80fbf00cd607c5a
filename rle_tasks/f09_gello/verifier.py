"""Verifier of 09-gello: three variants (panda, ur5e, xarm7), ten checkpoints each.

Per variant: load and check the submitted leader (``submission``), run ``trim.py`` in the sandbox
(``trim_runner``), then the batteries (``battery``, ``clearance``) on

* the nominal submitted leader (motion clearance, passive residual/hold/backdrive),
* a hidden copy of the stock reference leader with the adapted feedforward (not limited to the
  servo torque, bounded at +-2 N m),
* hidden copies of the submitted leader with the adapted feedforward clipped to 0.35 N m
  (hold, backdrive, servo headroom, push recovery).

Hidden copies and test poses derive from ``derive_rng(secret, "09-gello", ...)`` and are never
written anywhere; the report carries only ``seed_digest``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np

from rle_design.mjcf.contract import Finding
from rle_design.scene import element_id, has_element
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.secrets import derive_rng
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext
from rle_tasks.f09_gello import battery, clearance, device, scoring, submission
from rle_tasks.f09_gello.constants import TASK_ID
from rle_tasks.f09_gello.leaders import ROBOTS
from rle_tasks.f09_gello.measurements import (
    _adapted_ff,
    _hold_back_push,
    _report_warnings,
    _residuals,
    _test_poses,
)
from rle_tasks.f09_gello.public import gello_helpers as helpers
from rle_tasks.f09_gello.trim_runner import TrimRunner

REFERENCE_FF_BOUND = 2.0
"""Feedforward bound on the reference arm [N m]: not a servo limit (about 2x its peak gravity torque),
only a guard that keeps the simulation finite for absurd outputs."""


@dataclass(frozen=True)
class Battery:
    """Sizes of the verification batteries.

    Attributes:
        grid: Workspace-grid poses for residual and headroom maps.
        clearance: Grid poses checked for collisions.
        test_poses: Hidden test poses for hold, backdrive and push.
        copies: Hidden copies of the submitted leader.
        hold_s: Hold duration after release [s].
    """

    grid: int = 4096
    clearance: int = 384
    test_poses: int = 6
    copies: int = 2
    hold_s: float = 2.0


FULL = Battery()
QUICK = Battery(grid=256, clearance=48, test_poses=2, copies=1, hold_s=0.5)


@dataclass
class VariantResult:
    scores: dict[str, float] = field(default_factory=dict)
    measured: dict[str, object] = field(default_factory=dict)
    deduction: float = 0.0
    valid: bool = True


#: Checkpoints whose measurement uses the submitted feedforward (zero when trim.py faults).
TRIM_DEPENDENT = (
    "reference_hold",
    "reference_backdrive",
    "combined_hold",
    "combined_backdrive",
    "push_recovery",
)


def verify_variant(robot: str, root: Path, ctx: VerifyContext, report: Findings) -> VariantResult:
    """All ten checkpoints of one robot."""
    size = QUICK if ctx.quick else FULL
    res = VariantResult()
    stock = device.stock_model(robot)
    ranges = stock.jnt_range.copy()
    dof = stock.nv
    home = np.array(helpers.HOME[robot])
    # unseen poses: the same distribution as the public workspace grid, drawn from the secret
    grid_seed = int(derive_rng(ctx.secret, TASK_ID, f"{robot}/grid").integers(2**63))
    grid = helpers.workspace_grid(ranges, size.grid, seed=grid_seed)
    poses = _test_poses(ranges, size.test_poses, derive_rng(ctx.secret, TASK_ID, f"{robot}/poses"))
    push_rng = derive_rng(ctx.secret, TASK_ID, f"{robot}/push")
    ang = push_rng.uniform(0, 2 * np.pi, size.test_poses)
    push_dirs = np.stack([np.cos(ang), np.sin(ang), np.zeros_like(ang)], axis=1)

    sub_dir = root / robot
    if not sub_dir.is_dir():
        report.add_error("artifact.missing_robot", f"submission has no directory '{robot}/'", robot)
        sub = submission.Submission(robot)
        sub.structure.append(Finding("artifact.missing_robot", f"missing '{robot}/'"))
    else:
        sub = submission.load_submission(robot, sub_dir)
    for f in sub.structure + sub.validity:
        report.add_error(f.code, f.message, f.path)
    res.valid = not sub.structure and not sub.validity
    res.deduction = scoring.RUBRIC.deduction(submission.deductions(sub))
    res.measured["device_mass_kg"] = sub.mass
    if sub.model is not None:
        res.measured["springs"] = submission.springs_summary(sub.model)  # every element adding passive torque

    trim = TrimRunner(sub_dir / "trim.py", dof, hang_cap_s=ctx.hang_cap_s)
    try:
        # a refused leader scores 0 at every checkpoint, the adapted reference arm's included: its
        # trim.py is part of the refused submission
        if sub.usable:
            plan = trim.plan(ranges)
            # adapted reference arm: hidden copy of the stock leader, feedforward unclipped
            var = device.draw_variation(derive_rng(ctx.secret, TASK_ID, f"{robot}/reference"), dof)
            ref_dev = device.apply_variation(stock, var)
            ref_r = battery.residual_mujoco(ref_dev, poses)
            ff = _adapted_ff(
                trim,
                plan,
                "reference",
                ref_dev,
                home,
                poses,
                derive_rng(ctx.secret, TASK_ID, f"{robot}/reference/probe"),
            )
            if ff is not None:
                ff = np.clip(ff, -REFERENCE_FF_BOUND, REFERENCE_FF_BOUND)
                failed: list[str] = []
                out = _hold_back_push(ref_dev, poses, ff, ref_r - ff, size.hold_s, None, failed)
                _report_warnings(report, robot, "adapted reference arm", failed)
                res.scores["reference_hold"] = scoring.mean_score("reference_hold", out["drift"])
                res.scores["reference_backdrive"] = scoring.mean_score(
                    "reference_backdrive", out["backdrive"]
                )
                res.measured["reference_drift_rad"] = out["drift"]
                res.measured["reference_backdrive_Nm"] = out["backdrive"]
            _submitted(robot, sub, trim, plan, home, grid, poses, push_dirs, size, ctx, report, res)
    finally:
        trim.close()
    if trim.faults:
        # Feedforward that faulted is unavailable: every checkpoint built on it scores zero.
        for cid in TRIM_DEPENDENT:
            res.scores[cid] = 0.0
        res.measured["trim_fault"] = trim.faults[0].code
    seen = set()
    for fault in trim.faults:
        key = (fault.code, fault.message)
        if key not in seen:
            seen.add(key)
            report.add_error(fault.code, fault.message, f"{robot}/trim.py")
    if ctx.out_dir is not None and sub.model is not None:
        _render(sub, home, Path(ctx.out_dir) / f"{TASK_ID}_{robot}.png", res)
    return res


def _submitted(robot, sub, trim, plan, home, grid, poses, push_dirs, size, ctx, report, res) -> None:
    m = sub.model
    added = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) for b in sub.added_bodies]
    frac, examples, sunk = clearance.collision_fraction(sub.design, added, grid[: size.clearance])
    res.scores["motion_clearance"] = scoring.BY_ID["motion_clearance"].score(frac)
    res.measured["collision_fraction"] = frac
    res.measured["collision_examples"] = examples
    if sunk:
        deepest = max(sunk, key=lambda o: o.depth_m)
        report.add_error(
            "clearance.interpenetration",
            f"an added part lies inside the next link across a joint at {len(sunk)} of "
            f"{len(grid[: size.clearance])} hidden grid poses where nothing else collides (each fails "
            "motion clearance); deepest: "
            f"{deepest.message.replace(f'at pose {deepest.pose}', f'at hidden pose {deepest.pose}')}",
            f"{robot}/lead.xml",
        )

    r, err = _residuals(m, grid, report, robot)
    worst = np.max(np.abs(r), axis=1)
    p95 = float(np.percentile(worst, 95))
    res.scores["passive_residual"] = scoring.BY_ID["passive_residual"].score(p95)
    res.measured["residual_p95_Nm"] = p95
    res.measured["residual_max_per_joint_Nm"] = np.max(np.abs(r), axis=0)
    res.measured["crosscheck_Nm"] = err

    r_test = battery.residual_mujoco(m, poses)
    zero = np.zeros_like(r_test)
    added = battery.added_inertia(m, device.stock_model(robot), poses)
    effort = battery.ACCEL_REF * added
    res.measured["added_inertia_kgm2"] = np.max(added, axis=0)
    res.measured["inertia_effort_Nm"] = [float(np.max(e)) for e in effort]
    failed: list[str] = []
    out = _hold_back_push(m, poses, zero, r_test, size.hold_s, None, failed, effort)
    _report_warnings(report, robot, "passive battery", failed)
    res.scores["passive_hold"] = scoring.mean_score("passive_hold", out["drift"])
    res.scores["passive_backdrive"] = scoring.mean_score("passive_backdrive", out["backdrive"])
    res.measured["passive_drift_rad"] = out["drift"]
    res.measured["passive_backdrive_Nm"] = out["backdrive"]

    nominal = trim.feedforward(home, None) if plan is not None else None
    if nominal is not None:
        res.measured["nominal_ff_error_home_Nm"] = float(
            np.max(np.abs(nominal - battery.residual_mujoco(m, home[None])[0]))
        )
    drift, back, push, util = [], [], [], []
    for c in range(size.copies):
        var = device.draw_variation(derive_rng(ctx.secret, TASK_ID, f"{robot}/device/{c}"), m.nv)
        dev = device.apply_variation(m, var)
        ff = _adapted_ff(
            trim,
            plan,
            "submitted",
            dev,
            home,
            poses,
            derive_rng(ctx.secret, TASK_ID, f"{robot}/device/{c}/probe"),
        )
        ff = (
            np.zeros((len(poses), m.nv))
            if ff is None
            else np.clip(ff, -scoring.SERVO_LIMIT, scoring.SERVO_LIMIT)
        )
        r_dev = battery.residual_mujoco(dev, poses)
        failed = []
        out = _hold_back_push(dev, poses, ff, r_dev - ff, size.hold_s, push_dirs, failed, effort)
        _report_warnings(report, robot, f"hidden copy {c}", failed)
        drift += out["drift"]
        back += out["backdrive"]
        push += out["push"]
        r_grid, _ = _residuals(dev, grid, report, robot)
        util.append(float(np.max(np.abs(r_grid))) / scoring.SERVO_LIMIT)
    res.scores["combined_hold"] = scoring.mean_score("combined_hold", drift)
    res.scores["combined_backdrive"] = scoring.mean_score("combined_backdrive", back)
    res.scores["servo_headroom"] = scoring.mean_score("servo_headroom", util)
    res.scores["push_recovery"] = scoring.mean_score("push_recovery", push)
    res.measured.update(
        combined_drift_rad=drift,
        combined_backdrive_Nm=back,
        push_creep_rad=push,
        servo_utilisation=util,
        headroom=[1.0 - u for u in util],
    )


def _render(sub, home: np.ndarray, path: Path, res: VariantResult) -> None:
    """The submitted leader at its home pose on a floor, lit (the device model itself has neither)."""
    from rle_design.errors import RleError
    from rle_design.scene import Arena
    from rle_design.viz.render import render_png

    m = sub.model
    if sub.design is not None:
        spec = sub.design.fresh_spec()
        Arena(physics=None).edit_spec(spec)  # floor, sky and lights; the device's own physics
        try:
            m = spec.compile()
        except ValueError:
            m = sub.model  # render the device as verified
    d = mujoco.MjData(m)
    # home by stock joint name: a leader with other joints (refused, still drawn) keeps its qpos0 there
    for name, q in zip(device.stock_names(sub.robot)[1], home):
        if has_element(m, "joint", name):
            d.qpos[m.jnt_qposadr[element_id(m, "joint", name)]] = q
    mujoco.mj_forward(m, d)
    try:
        render_png(m, d, path, width=480, height=360)
        res.measured["render"] = path.name
    except RleError as exc:  # no offscreen GL here: the report still stands
        res.measured["render"] = f"unavailable: {exc.message}"


def verify(root: Path, ctx: VerifyContext, *, task_id: str = TASK_ID) -> VerifierReport:
    """Verify a submission directory holding one directory per robot (``scoring.RUBRIC.variants``)."""
    if task_id != TASK_ID:
        raise ValueError(f"this verifier scores {TASK_ID}, not {task_id}")
    findings = Findings()
    results = {robot: verify_variant(robot, Path(root), ctx, findings) for robot in ROBOTS}
    outcomes = {
        c.id: Outcome(
            per_variant={robot: results[robot].scores.get(c.id, 0.0) for robot in ROBOTS},
            measured={robot: _metric_for(c.id, results[robot]) for robot in ROBOTS},
        )
        for c in scoring.CHECKPOINTS
    }
    deductions = {robot: results[robot].deduction for robot in ROBOTS}
    return scoring.RUBRIC.report(
        outcomes,
        valid=all(res.valid for res in results.values()),
        errors=findings.errors,
        deductions=deductions,
        native_metrics={
            "quick": bool(ctx.quick),
            "variant_score": None,  # filled by the rubric (mean-of-variants aggregation)
            "deduction": deductions,
            **{robot: results[robot].measured for robot in ROBOTS},
        },
    )


_METRIC_KEYS = {
    "motion_clearance": "collision_fraction",
    "passive_residual": "residual_p95_Nm",
    "passive_hold": "passive_drift_rad",
    "passive_backdrive": "passive_backdrive_Nm",
    "reference_hold": "reference_drift_rad",
    "reference_backdrive": "reference_backdrive_Nm",
    "combined_hold": "combined_drift_rad",
    "combined_backdrive": "combined_backdrive_Nm",
    "servo_headroom": "servo_utilisation",
    "push_recovery": "push_creep_rad",
}


def _metric_for(cid: str, res: VariantResult):
    return res.measured.get(_METRIC_KEYS[cid])
