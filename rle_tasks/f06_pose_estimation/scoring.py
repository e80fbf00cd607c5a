"""Rubric of the four ``06-pose-*`` tasks (the card's formula, declared once).

Per evaluation group (ten independent frames, or one push trajectory): the five largest translation
errors and the five largest wrapped angle errors are averaged separately,

    g = 1/2 exp(-(e_xy / 0.01)^2) + 1/2 exp(-(e_theta / 0.1)^2)   if every shape id is right, else 0,

and the reward is R = max(0, 0.3 mean(g over frame groups) + 0.7 mean(g over trajectories) - D) with
the speed deduction D = 0.2 clip((10 - nu) / 9, 0, 1), nu the verifier-measured frames per second.
A failed load or interface gate scores zero (cap ``gate``).
"""

from __future__ import annotations

import math

import numpy as np

from rle_tasks.core.scoring import Cap, CheckpointSpec, Deduction, Fraction, PassRule, Rubric

WORST = 5
"""Errors averaged per group (the largest ones)."""
XY_SCALE = 0.01
"""Translation error scale of g [m]."""
THETA_SCALE = 0.1
"""Angle error scale of g [rad]."""
W_FRAMES, W_TRAJ = 0.3, 0.7
"""Weights of the frame groups and of the trajectories."""
SPEED_MAX = 0.2
"""Largest speed deduction [1]."""
FPS_FULL, FPS_FLOOR = 10.0, 1.0
"""No deduction at or above FPS_FULL frames/s, the full deduction at or below FPS_FLOOR."""
VARIANT = "estimator"
"""The single variant name of the rubric."""
PASS = PassRule(at=0.5)
"""A checkpoint counts as passed at g >= 0.5."""
TASK_IDS = ("06-pose-a-rgb", "06-pose-b-rgbd", "06-pose-c-learned", "06-pose-d-agnostic")


def wrap_angle(a: np.ndarray | float) -> np.ndarray:
    """Angle difference wrapped to [-pi, pi) [rad]."""
    return (np.asarray(a, float) + math.pi) % (2 * math.pi) - math.pi


def group_errors(pred: np.ndarray, truth: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-frame translation error [m], absolute wrapped angle error [rad] and shape correctness.

    Args:
        pred: ``(N, 4)`` predictions ``(x, y, theta, shape_id)``; a row of NaN is a missing prediction
            (infinite errors, wrong shape).
        truth: ``(N, 4)`` labels.
    """
    pred, truth = np.asarray(pred, float), np.asarray(truth, float)
    e_xy = np.hypot(pred[:, 0] - truth[:, 0], pred[:, 1] - truth[:, 1])
    e_th = np.abs(wrap_angle(pred[:, 2] - truth[:, 2]))
    ok = np.isfinite(pred).all(1) & (pred[:, 3] == truth[:, 3])
    e_xy = np.where(np.isfinite(e_xy), e_xy, np.inf)
    e_th = np.where(np.isfinite(e_th), e_th, np.inf)
    return e_xy, e_th, ok


def worst_mean(errors: np.ndarray, k: int = WORST) -> float:
    """Mean of the ``k`` largest errors (all of them when fewer)."""
    e = np.sort(np.asarray(errors, float))[::-1][:k]
    return float(np.mean(e)) if len(e) else math.inf


def group_score(pred: np.ndarray, truth: np.ndarray) -> tuple[float, dict]:
    """The card's g of one group and its native metrics."""
    e_xy, e_th, ok = group_errors(pred, truth)
    w_xy, w_th = worst_mean(e_xy), worst_mean(e_th)
    g = 0.5 * math.exp(-((w_xy / XY_SCALE) ** 2)) + 0.5 * math.exp(-((w_th / THETA_SCALE) ** 2))
    g = g if bool(ok.all()) else 0.0
    finite = np.isfinite(e_xy) & np.isfinite(e_th)
    metrics = {
        "g": g,
        "worst5_xy_m": w_xy if math.isfinite(w_xy) else None,
        "worst5_theta_rad": w_th if math.isfinite(w_th) else None,
        "mean_xy_m": float(e_xy[finite].mean()) if finite.any() else None,
        "mean_theta_rad": float(e_th[finite].mean()) if finite.any() else None,
        "shape_accuracy": float(ok.mean()) if len(ok) else 0.0,
        "frames": int(len(ok)),
    }
    return g, metrics


def speed_deduction(fps: float) -> float:
    """D = 0.2 clip((10 - nu) / 9, 0, 1); a non-finite or zero rate takes the full deduction."""
    if not math.isfinite(fps) or fps <= 0:
        return SPEED_MAX
    return SPEED_MAX * float(np.clip((FPS_FULL - fps) / (FPS_FULL - FPS_FLOOR), 0.0, 1.0))


def reward(g_frames: list[float], g_traj: list[float], fps: float) -> float:
    """R of the card (the rubric's report computes the same; this is the closed form for tests)."""
    ga = float(np.mean(g_frames)) if g_frames else 0.0
    gb = float(np.mean(g_traj)) if g_traj else 0.0
    return max(0.0, W_FRAMES * ga + W_TRAJ * gb - speed_deduction(fps))


def make_rubric(task_id: str) -> Rubric:
    """The rubric of one of ``TASK_IDS``."""
    if task_id not in TASK_IDS:
        raise ValueError(f"unknown task '{task_id}'. Tasks of family 06: {', '.join(TASK_IDS)}")
    return Rubric(
        task_id=task_id,
        family="06",
        workflow="perception_estimation",
        variants=(VARIANT,),
        aggregate="variant_mean",
        checkpoints=(
            CheckpointSpec(
                "frames",
                W_FRAMES,
                "mean g over the ten groups of ten independent frames",
                Fraction(
                    "g = 1/2 exp(-(e_xy/0.01 m)^2) + 1/2 exp(-(e_theta/0.1 rad)^2) over the worst 5 "
                    "errors of a group; 0 if a shape id is wrong"
                ),
                pass_rule=PASS,
            ),
            CheckpointSpec(
                "trajectories",
                W_TRAJ,
                "mean g over the ten push trajectories (<= 60 frames each)",
                Fraction("g as for frames, one group per trajectory"),
                pass_rule=PASS,
            ),
        ),
        caps=(Cap("gate", 0.0, "the estimator or model fails to load or breaks the interface"),),
        deductions=(
            Deduction("speed", SPEED_MAX, "speed nu below 10 frames/s: 0.2 clip((10 - nu)/9, 0, 1)"),
        ),
        max_deduction=SPEED_MAX,
    )


RUBRICS = {tid: make_rubric(tid) for tid in TASK_IDS}
"""Rubric per task id."""


def rubrics() -> dict[str, Rubric]:
    """Task id -> rubric, for every task of the family."""
    return dict(RUBRICS)


def diagnostics(report) -> dict[str, float]:
    """Native diagnostics (results page): the frame rate, the worst-five errors averaged over the frame
    groups and trajectories, and median errors on static against occluded frames (the paper's
    static-versus-occluded comparison)."""
    m = report.native_metrics
    out = {}
    if "fps" in m:
        out["fps [1/s]"] = m["fps"]
    sets = [s for s in (m.get("groups") or []) + (m.get("trajectories") or []) if isinstance(s, dict)]
    if sets:
        out["worst-5 xy [mm]"] = 1e3 * sum(s["worst5_xy_m"] for s in sets) / len(sets)
        out["worst-5 theta [deg]"] = math.degrees(sum(s["worst5_theta_rad"] for s in sets) / len(sets))
    split = m.get("static_vs_occluded") or {}
    for kind in ("static", "occluded"):
        if split.get(kind, {}).get("frames"):
            out[f"{kind} median xy [mm]"] = 1e3 * split[kind]["median_xy_m"]
    return out
