"""Verifier of the family-04 tasks: contract checks, smoke checks, eight hidden seeds.

1. ``policy_meta.json`` and ``policy.onnx`` load (declared signature, at most 10 M parameters), else
   the report is invalid and scores 0.
2. Smoke: the graph gives bit-identical outputs for the same input twice (three fixed inputs) and
   finite outputs; in the episodes, no NaN output and no explosion in the first second. A failure caps
   the score at 0.1.
3. Each hidden seed (derived from the secret) runs ``evaluation.run_seed`` through the core fan-out (``run_units``);
   per seed s = 0.7 T + 0.3 U - 0.15 min(J/J_max, 1) - 0.05 F; the reward is the mean.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rle_design.errors import RleError
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.parallel import run_units
from rle_tasks.core.runtime.policy import PolicyFault
from rle_tasks.core.runtime.secrets import derive_seed, seed_digest
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext

from .clips import TASK_CLIPS
from .constants import N_SEEDS, QUICK_SEEDS
from .evaluation import SMOKE_STEPS, SeedUnit, load_policy, run_seed
from .scoring import J_MAX, rubric, seed_score

__all__ = ["smoke_inputs", "verify"]


def smoke_inputs(obs_dim: int) -> list[np.ndarray]:
    """Three fixed inputs of the determinism check: zeros, ones and a fixed normal draw."""
    rng = np.random.default_rng(4)
    return [np.zeros((1, obs_dim), np.float32), np.ones((1, obs_dim), np.float32)] + [
        rng.normal(size=(1, obs_dim)).astype(np.float32)
    ]


def _determinism(policy, obs_dim: int) -> str:
    """'' if the policy is deterministic and finite on the smoke inputs, else the reason."""
    for x in smoke_inputs(obs_dim):
        try:
            a, b = policy.run({"obs": x})["actions"], policy.run({"obs": x.copy()})["actions"]
        except PolicyFault as exc:
            return f"{exc.code}: {exc.message}"
        if not np.array_equal(a, b):
            return f"the same input gave different outputs (max difference {np.abs(a - b).max():.3g})"
    return ""


def verify(root: Path, ctx: VerifyContext, *, task_id: str) -> VerifierReport:
    """Score the policy at ``root`` on the clip of ``task_id`` (module docstring)."""
    style, root = TASK_CLIPS[task_id][0], Path(root)
    n = QUICK_SEEDS if ctx.quick else N_SEEDS
    rub = rubric(task_id, n)
    findings = Findings()
    try:
        meta, policy = load_policy(root)
    except RleError as exc:
        findings.add_error(exc.code, exc.message, exc.path)
        return rub.report({}, valid=False, errors=findings.errors, caps=["invalid"])
    caps = []
    reason = _determinism(policy, meta.obs_dim)
    if reason:
        findings.add_error("f04.smoke", f"smoke check: {reason}", "policy.onnx")
        caps.append("smoke")
    seeds = [derive_seed(ctx.secret, task_id, i) for i in range(n)]
    results = run_units(run_seed, [SeedUnit(str(root), style, s) for s in seeds], ctx)
    tracking, survival, deductions, native_seeds = {}, {}, {}, {}
    for name, r in zip(rub.variants, results):
        tracking[name], survival[name] = r["T"], r["U"]
        deductions[name] = rub.deduction(
            [("f04.jerk", min(r["J"] / J_MAX, 1.0))] + (["f04.fall"] if r["fell"] else [])
        )
        native_seeds[name] = {**r, "s": seed_score(r["T"], r["U"], r["J"], r["fell"])}
        if r["fault"]:
            findings.add_error(r["fault"], f"{name}: policy fault after {r['survived']} steps", "policy.onnx")
        if 0 <= r["explosion_step"] < SMOKE_STEPS:
            findings.add_error("f04.smoke", f"{name}: the simulation exploded at step {r['explosion_step']}")
        if (r["fault"] == "onnx.nonfinite" or 0 <= r["explosion_step"] < SMOKE_STEPS) and "smoke" not in caps:
            caps.append("smoke")
    native = {
        "mpjpe_mm": float(np.mean([r["mpjpe_mm"] for r in results])),
        "survival_pct": 100.0 * float(np.mean([r["U"] for r in results])),
        "seeds": native_seeds,
        "quick": ctx.quick,
        "seed_digest": seed_digest(ctx.secret, task_id),
    }
    outcomes = {
        "tracking": Outcome(tracking, f"T mean {np.mean(list(tracking.values())):.3f}"),
        "survival": Outcome(survival, f"survival {native['survival_pct']:.1f} %"),
    }
    return rub.report(
        outcomes, valid=True, errors=findings.errors, caps=caps, deductions=deductions, native_metrics=native
    )
