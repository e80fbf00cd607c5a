"""Verifier of 07-bin-clearing: the submitted ``policy/`` package clears eight hidden piles.

Steps: the package must exist inside the submission (else score 0, cap ``unloadable``); it is
imported in the sandbox and ``make_policy()`` called (a fault: cap ``unloadable``); the smoke test
plays ``reset()`` and one ``act()`` on public pile 101 (a fault: cap ``smoke``, 0.1; a hang there
ends the verification, since every pile would start with the same call). Then every
hidden pile (drawn from the secret: ``PileSpec.draw(derive_rng(secret, task, "pile/<i>"))``) runs for
120 s simulated in a fresh sandbox child with 360 s of policy CPU time, through the core fan-out (``run_units``)
(``--jobs``). Quick mode (``--quick``, marked ``partial``) plays the first hidden pile for 30 s. A fault of the policy (exception, 30 s hang, CPU budget, bad action) ends that pile
where it stands: what was cleared counts, the fault is reported.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from rle_design.rollout.env import ActionError
from rle_design.sandbox import ParticipantFault, SandboxLimits, excerpt
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.parallel import run_units
from rle_tasks.core.runtime.policy import HANG_CODES, PolicyRunner
from rle_tasks.core.runtime.protocol import Budget, FunctionSpec, Protocol
from rle_tasks.core.runtime.secrets import derive_rng, seed_digest
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext

from .constants import N_PILES, QUICK_EPISODE_S, QUICK_PILES, TASK_ID
from .public.contract import FUNCTIONS, HANG_CAP_S
from .public.env import EPISODE_S, close_cameras, make_env
from .public.events import EventCounter
from .public.pile import PUBLIC_SEEDS, PileSpec
from .scoring import pile_score, pile_terms, rubric

POLICY_FILE = Path("policy") / "__init__.py"
POLICY_CPU_S = 360.0
"""Cumulative policy computation per pile [s] (the card's budget)."""
_DOC = {
    "make_policy": "(): builds the policy once after import",
    "reset": "(): start of a pile",
    "act": "obs: dict (time, q, dq, tau, ft, magnet, nest; overhead and wrist RGB-D at 10 Hz) -> (8,): "
    "seven joint-position targets [rad] and the magnet command in [0, 1]",
}
PROTOCOL = Protocol(
    module="policy",
    functions=tuple(
        FunctionSpec(name, _DOC[name], returns=shape, timeout_s=HANG_CAP_S)
        for name, shape in FUNCTIONS.items()
    ),
)
"""The contract of ``public/contract.py`` (``devrun`` checks every return the same way)."""
LIMITS = SandboxLimits(cpu_seconds=POLICY_CPU_S + 10, memory_bytes=4 << 30, startup_timeout_s=HANG_CAP_S)


def _runner(path: Path, hang_cap_s: float) -> PolicyRunner:
    return PolicyRunner(
        path, PROTOCOL, hang_cap_s=min(hang_cap_s, HANG_CAP_S),
        budget=Budget(max_faults=1, cpu_s=POLICY_CPU_S, restart=False), limits=LIMITS,
    )  # fmt: skip


def hidden_piles(ctx: VerifyContext) -> list[PileSpec]:
    """The hidden piles of the secret (the first ``QUICK_PILES`` in quick mode)."""
    n = QUICK_PILES if ctx.quick else N_PILES
    return [PileSpec.draw(derive_rng(ctx.secret, TASK_ID, f"pile/{i}")) for i in range(n)]


@dataclass(frozen=True)
class PileUnit:
    """One hidden pile of a verification (a runner unit; picklable)."""

    policy: str
    """The submitted policy file."""
    pile: PileSpec
    hang_cap_s: float
    """A call of the policy that takes longer is a hang [s]."""
    episode_s: float
    """Simulated time of the pile [s]."""


def run_pile(unit: PileUnit) -> dict:
    """Play the unit's policy on its pile; returns the event summary, faults and timings."""
    path, pile, hang_cap_s, episode_s = unit.policy, unit.pile, unit.hang_cap_s, unit.episode_s
    t0 = time.perf_counter()
    env = make_env(pile)
    model = env.build()
    env.prepare(model)
    data = mujoco.MjData(model)
    env.reset(model, data)
    counter = EventCounter(model, pile.n_parts, every=1, control_every=env.n_substeps)
    n_actions = int(round(episode_s / (env.n_substeps * model.opt.timestep)))
    fault = None
    calls = {"n": 0, "s": 0.0}
    with _runner(Path(path), hang_cap_s) as runner:

        def policy(obs: dict) -> np.ndarray:
            c0 = time.perf_counter()
            out = runner.call("act", obs)
            calls["n"] += 1
            calls["s"] += time.perf_counter() - c0
            return out

        t_sim = time.perf_counter()
        try:
            runner.call("make_policy")
            runner.call("reset")
            env.episode(model, data, policy, n_actions, terms=[counter])
        except ParticipantFault as exc:
            fault = {"code": exc.code, "message": exc.message, "time_s": round(float(data.time), 3)}
        except Exception as exc:  # noqa: BLE001 - a bad action (ActionError) or a crash of the policy's output
            code = getattr(exc, "code", "f07.episode")
            text = str(exc) if isinstance(exc, ActionError) else excerpt(exc)
            fault = {"code": code, "message": text, "time_s": round(float(data.time), 3)}
        cpu = runner.cpu_used_s
    close_cameras(model)
    summary = counter.counts.summary(pile.n_parts, episode_s)
    return {
        "pile": {"n_parts": pile.n_parts, "friction_scale": pile.friction_scale},
        "events": summary,
        "fault": fault,
        "sim_s": round(float(data.time), 3),
        "policy_calls": calls["n"],
        "timing": {  # wall-clock measurements: kept out of the (deterministic) report
            "wall_s": time.perf_counter() - t0,
            "episode_wall_s": time.perf_counter() - t_sim,
            "policy_wall_s": calls["s"],
            "policy_cpu_s": cpu,
        },
    }


def _load_and_smoke(path: Path, hang_cap_s: float, findings: Findings) -> str | None:
    """None when the policy loads and passes the smoke test, else the cap id."""
    env = make_env(PileSpec.public(PUBLIC_SEEDS[0]))
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    with _runner(path, hang_cap_s) as runner:
        try:
            missing = runner.missing()
            if missing:
                findings.add_error(
                    "f07.missing_function", f"policy/ does not define {', '.join(missing)}", "policy"
                )
                return "unloadable"
            runner.call("make_policy")
        except ParticipantFault as exc:
            findings.add_error(exc.code, f"policy could not be loaded: {exc.message}", "policy")
            return "unloadable"
        try:
            runner.call("reset")
            env.action(model, runner.call("act", env.observe(model, data)))
        except Exception as exc:  # noqa: BLE001 - ParticipantFault or ActionError
            code = getattr(exc, "code", "f07.smoke")
            text = str(exc) if isinstance(exc, ParticipantFault | ActionError) else excerpt(exc)
            findings.add_error(code, f"smoke test failed: {text}", "policy")
            return "smoke_hang" if code in HANG_CODES else "smoke"
        finally:
            close_cameras(model)
    return None


def verify(root: Path, ctx: VerifyContext, *, task_id: str = TASK_ID) -> VerifierReport:
    """Score the submission at ``root`` (see the module docstring)."""
    if task_id != TASK_ID:
        raise ValueError(f"this verifier scores {TASK_ID}, not {task_id}")
    findings = Findings()
    n = QUICK_PILES if ctx.quick else N_PILES
    rub = rubric(n)
    root = Path(root).resolve()
    path = root / POLICY_FILE
    base = {"quick": ctx.quick, "partial": ctx.quick, "secret": ctx.secret.label}
    if not path.is_file() or not path.resolve().is_relative_to(root):
        findings.add_error(
            "f07.no_policy", f"{POLICY_FILE} is missing (a policy/ package is required)", "policy"
        )
        return rub.report({}, valid=False, errors=findings.errors, caps=["unloadable"], native_metrics=base)
    cap = _load_and_smoke(path, ctx.hang_cap_s, findings)
    if cap == "unloadable":
        return rub.report({}, valid=False, errors=findings.errors, caps=[cap], native_metrics=base)
    if cap == "smoke_hang":  # a policy that hangs on its first observation is not played on the piles
        findings.add_error(
            "f07.not_played", "the hidden piles were not played after a hang in the smoke test"
        )
        return rub.report({}, valid=True, errors=findings.errors, caps=["smoke"], native_metrics=base)
    piles = hidden_piles(ctx)
    episode_s = QUICK_EPISODE_S if ctx.quick else EPISODE_S
    results = run_units(run_pile, [PileUnit(str(path), p, ctx.hang_cap_s, episode_s) for p in piles], ctx)
    per: dict[str, dict[str, float]] = {
        k: {} for k in ("complete", "clearance", "throughput", "clean_throughput")
    }
    deductions, scores, native_piles = {}, {}, {}
    for name, res in zip(rub.variants, results):
        terms = pile_terms(res["events"])
        for k in per:
            per[k][name] = terms[k]
        deductions[name] = terms["deduction"]
        scores[name] = pile_score(res["events"])
        native_piles[name] = {k: v for k, v in res.items() if k != "timing"}
        native_piles[name] |= {"score": scores[name], "parts_per_min": terms["p"]}
        if res["fault"] is not None:
            findings.add_error(res["fault"]["code"], f"{name}: {res['fault']['message']}", "policy")
    astray = {v: r["events"]["not_through_nest"] for v, r in zip(rub.variants, results)}
    if any(astray.values()):
        findings.add_error(
            "f07.not_through_nest",
            f"{sum(astray.values())} part(s) reached the belt's end or the outfeed without the nest releasing "
            "them one at a time, not cleared: " + ", ".join(f"{v}: {n}" for v, n in astray.items() if n),
            "policy",
        )
    fractions = [r["events"]["cleared_fraction"] for r in results]
    ppm = [native_piles[v]["parts_per_min"] for v in rub.variants]
    outcomes = {k: Outcome(v, measured={"per_pile": v}) for k, v in per.items()}
    native = base | {
        "clearance_pct": round(100.0 * float(np.mean(fractions)), 2),
        "parts_per_min": round(float(np.mean(ppm)), 3),
        "piles": native_piles,
        "episode_s": episode_s,
        "seed_digest": seed_digest(ctx.secret, TASK_ID),
    }
    return rub.report(
        outcomes, valid=True, errors=findings.errors, caps=[cap] if cap else [], deductions=deductions,
        native_metrics=native,
    )  # fmt: skip


__all__ = ["PROTOCOL", "PileUnit", "hidden_piles", "run_pile", "verify"]
