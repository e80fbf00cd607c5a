"""Verifier of the ``06-pose-*`` tasks: hidden frame groups and push trajectories, run through the core fan-out (``run_units``).

Evaluation units are the ten frame groups and the ten push trajectories (quick mode: three of each,
trajectories of 20 frames; the report marks it ``partial``). Each unit, in a worker of
``run_units``: draws its appearance, noise and frames from the secret, renders them, and runs the
submission in its own sandboxed child: ``reset()`` before every independent frame and once before a
trajectory, then ``update(obs)`` per frame. A fault leaves that frame without a prediction (wrong
shape, infinite error). The frame rate nu is frames with a prediction divided by the child's CPU time
during their ``update`` calls (one thread: the rate on one CPU, whatever else loads the machine); the
report holds it rounded to 0.1 and capped at 10 frames/s (where the deduction ends), so a report is
the same from run to run; the unrounded timing goes to ``f06_timing.json`` in the output directory. Before the
units, a gate loads the submission and runs it on one public frame: a failed load, a missing
function or a bad reply there scores zero (cap ``gate``).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rle_design.sandbox import ParticipantFault
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.parallel import run_units
from rle_tasks.core.runtime.policy import PolicyRunner, distinct
from rle_tasks.core.runtime.secrets import Secret, derive_rng
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext

from .constants import N_GROUPS, N_TRAJ, QUICK_GROUPS, QUICK_TRAJ, QUICK_TRAJ_FRAMES, TRAJ_FRAMES
from .contract import (
    ESTIMATOR,
    ESTIMATOR_BUDGET,
    ESTIMATOR_LIMITS,
    MODEL_LIMITS,
    SHAPE_IDS,
    Variant,
    variant,
)
from .scoring import FPS_FULL, RUBRICS, VARIANT, group_score, speed_deduction

HERE = Path(__file__).resolve().parent
MODEL_RUNNER = HERE / "model_runner.py"
HIDDEN_KEY = "06-pose"
"""Hidden items derive from HMAC(secret, HIDDEN_KEY | label): the four variants share one hidden set."""
FPS_STEP = 0.1
"""Resolution of the reported frame rate [frames/s]."""
SMOKE_SEED = 20260601
"""Public seed of the gate's smoke frame."""


@dataclass(frozen=True)
class UnitJob:
    """One evaluation unit (picklable for worker processes)."""

    task_id: str
    root: str
    kind: str  # "frames" or "trajectory"
    index: int
    key: bytes
    public: bool
    quick: bool
    hang_cap_s: float


@dataclass(frozen=True)
class UnitResult:
    """Predictions and labels of one unit."""

    kind: str
    index: int
    pred: np.ndarray
    truth: np.ndarray
    visible: np.ndarray
    update_s: float
    updates: int
    faults: tuple[tuple[str, str], ...] = ()
    findings: tuple[tuple[str, str], ...] = field(default_factory=tuple)


_RENDERERS: dict[bool, object] = {}


def renderer(depth: bool):
    """The process's renderer (one GL context per worker process)."""
    if depth not in _RENDERERS:
        from .render import Renderer
        from .scene import compile_scene

        _RENDERERS[depth] = Renderer(compile_scene(), depth=depth)
    return _RENDERERS[depth]


def draw_unit(rng: np.random.Generator, kind: str, n_traj_frames: int):
    """Appearance, noise and frames of one unit from its generator."""
    from .appearance import APPEARANCE, SensorNoise
    from .episodes import frame_group, push_episode

    appearance = APPEARANCE.sample(rng)
    noise = SensorNoise.sample(rng)
    frames = frame_group(rng) if kind == "frames" else push_episode(rng, n_traj_frames)
    return appearance, noise, frames


def render_unit(v: Variant, rng: np.random.Generator, kind: str, n_traj_frames: int):
    """Observations and labels of one unit."""
    appearance, noise, frames = draw_unit(rng, kind, n_traj_frames)
    r = renderer(v.depth)
    r.apply(appearance)
    return r.render(frames, noise, rng)


def open_runner(v: Variant, root: Path, hang_cap_s: float) -> PolicyRunner:
    """The sandboxed estimator of a submission (the model wrapper for the learned variant)."""
    if v.learned:
        return PolicyRunner(
            MODEL_RUNNER,
            ESTIMATOR,
            hang_cap_s=hang_cap_s,
            budget=ESTIMATOR_BUDGET,
            limits=MODEL_LIMITS,
            workdir_files={"model.pt": root / "model.pt"},
        )
    return PolicyRunner(
        root / "estimator.py",
        ESTIMATOR,
        hang_cap_s=hang_cap_s,
        budget=ESTIMATOR_BUDGET,
        limits=ESTIMATOR_LIMITS,
    )


def check_prediction(value: np.ndarray) -> str | None:
    """Why a finite 4-vector is not a prediction (a shape id outside 0, 1, 2), or None."""
    sid = float(value[3])
    if sid != round(sid) or int(round(sid)) not in SHAPE_IDS:
        return f"shape_id {sid:g} is not one of {', '.join(map(str, SHAPE_IDS))}"
    return None


def run_frames(runner: PolicyRunner, obs: list[dict], independent: bool) -> tuple[np.ndarray, float, list]:
    """Predictions ``(N, 4)`` (NaN rows where a call faulted), CPU time of the child's updates [s], findings."""
    pred = np.full((len(obs), 4), np.nan)
    spent, findings = 0.0, []
    for i, o in enumerate(obs):
        if runner.exhausted:
            break
        try:
            if independent or i == 0:
                runner.call("reset")
            c0 = runner.cpu_used_s
            out = runner.call("update", o)
            spent += runner.cpu_used_s - c0
        except ParticipantFault:
            continue  # recorded by the runner
        why = check_prediction(out)
        if why is not None:
            findings.append(("f06.shape_id", f"estimator.update(): {why}"))
            continue
        pred[i] = out
    return pred, spent, findings


def run_unit(job: UnitJob) -> UnitResult:
    """Render and evaluate one unit (module level: runs in worker processes)."""
    v = variant(job.task_id)
    rng = derive_rng(Secret(job.key, job.public), HIDDEN_KEY, f"{job.kind}/{job.index}")
    n_traj = QUICK_TRAJ_FRAMES if job.quick else TRAJ_FRAMES
    obs, labels = render_unit(v, rng, job.kind, n_traj)
    with open_runner(v, Path(job.root), job.hang_cap_s) as runner:
        pred, spent, findings = run_frames(runner, obs, independent=job.kind == "frames")
        faults = tuple((r.code, r.message) for r in distinct(runner.faults))
        updates = int(np.isfinite(pred).all(1).sum())
    return UnitResult(
        job.kind,
        job.index,
        pred,
        np.array([lab.pose for lab in labels]),
        np.array([lab.visible for lab in labels]),
        spent,
        updates,
        faults,
        tuple(dict.fromkeys(findings)),
    )


def gate(v: Variant, root: Path, hang_cap_s: float) -> tuple[str, str] | None:
    """Load the submission and run it on one public frame; (code, message) of the failure, or None."""
    path = root / v.artifact
    if not path.is_file():
        return ("f06.missing", f"{v.artifact} is missing from the submission directory")
    rng = np.random.default_rng(SMOKE_SEED)
    obs, _ = render_unit(v, rng, "frames", 0)
    with open_runner(v, root, hang_cap_s) as runner:
        try:
            missing = runner.missing()
            if missing:
                return ("sandbox.missing_function", f"{v.artifact} does not define {', '.join(missing)}")
            runner.call("reset")
            out = runner.call("update", obs[0])
        except ParticipantFault as exc:
            return (exc.code, exc.message)
    why = check_prediction(out)
    return ("f06.shape_id", f"estimator.update(): {why}") if why else None


def _occlusion_metrics(results: list[UnitResult]) -> dict:
    out = {}
    truth = np.concatenate([r.truth for r in results])
    pred = np.concatenate([r.pred for r in results])
    vis = np.concatenate([r.visible for r in results])
    from .render import OCCLUDED_BELOW
    from .scoring import group_errors

    e_xy, e_th, ok = group_errors(pred, truth)
    for name, sel in (("static", vis >= OCCLUDED_BELOW), ("occluded", vis < OCCLUDED_BELOW)):
        fin = sel & np.isfinite(e_xy)
        out[name] = {
            "frames": int(sel.sum()),
            "median_xy_m": float(np.median(e_xy[fin])) if fin.any() else None,
            "median_theta_rad": float(np.median(e_th[fin])) if fin.any() else None,
            "shape_accuracy": float(ok[sel].mean()) if sel.any() else None,
        }
    return out


def reported_fps(measured: float) -> float:
    """The frame rate that enters the report and the deduction: rounded to ``FPS_STEP`` and capped at
    ``FPS_FULL`` (above it there is no deduction), so that timing jitter does not change a report."""
    if not math.isfinite(measured) or measured <= 0:
        return 0.0
    return min(FPS_FULL, round(round(measured / FPS_STEP) * FPS_STEP, 6))


def _write_timing(out_dir: Path, fps: float, cpu_s: float, updates: int, results: list[UnitResult]) -> None:
    """The unrounded timing beside the report (it varies from run to run; the report does not)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    units = [{"kind": r.kind, "index": r.index, "cpu_s": r.update_s, "updates": r.updates} for r in results]
    text = json.dumps({"fps": fps, "cpu_s": cpu_s, "updates": updates, "units": units}, indent=1)
    (out_dir / "f06_timing.json").write_text(text)


def _outcome(g: list[float], metrics: list[dict], what: str) -> Outcome:
    """Checkpoint outcome with a message naming why groups scored what they did."""
    frames = sum(m["frames"] for m in metrics)
    acc = sum(m["shape_accuracy"] * m["frames"] for m in metrics) / frames if frames else 0.0
    wrong = sum(m["shape_accuracy"] < 1.0 for m in metrics)
    xy = [m["worst5_xy_m"] for m in metrics if m["worst5_xy_m"] is not None]
    th = [m["worst5_theta_rad"] for m in metrics if m["worst5_theta_rad"] is not None]
    msg = f"mean g {np.mean(g):.3f} over {len(g)} {what}; shape accuracy {acc:.2f}"
    if wrong:
        msg += f" ({wrong} of {len(g)} with a wrong or missing shape id score 0)"
    if xy and th:
        msg += f"; mean worst-5 errors {1000 * np.mean(xy):.1f} mm, {np.mean(th):.3f} rad"
    return Outcome({VARIANT: float(np.mean(g))}, msg, {"g": g, "shape_accuracy": acc})


def verify(root: Path, ctx: VerifyContext, *, task_id: str) -> VerifierReport:
    """Verify a submission directory for one of the four tasks."""
    v = variant(task_id)
    rubric = RUBRICS[task_id]
    findings = Findings()
    root = Path(root).resolve()
    failed = gate(v, root, ctx.hang_cap_s)
    if failed is not None:
        findings.add_error(failed[0], f"gate: {failed[1]}", v.artifact)
        return rubric.report(
            {},
            valid=False,
            errors=findings.errors,
            caps=("gate",),
            native_metrics={"gate": {"code": failed[0], "message": failed[1]}, "partial": ctx.quick},
        )
    n_groups, n_traj = (QUICK_GROUPS, QUICK_TRAJ) if ctx.quick else (N_GROUPS, N_TRAJ)
    jobs = [
        UnitJob(task_id, str(root), kind, i, ctx.secret.key, ctx.secret.public, ctx.quick, ctx.hang_cap_s)
        for kind, n in (("frames", n_groups), ("trajectory", n_traj))
        for i in range(n)
    ]
    results = run_units(run_unit, jobs, ctx, max_jobs=len(jobs))
    per_unit, g = {"frames": [], "trajectory": []}, {"frames": [], "trajectory": []}
    for r in results:
        score, metrics = group_score(r.pred, r.truth)
        g[r.kind].append(score)
        per_unit[r.kind].append(metrics)
        for code, msg in r.faults + r.findings:
            if not any(e.code == code and e.message == msg for e in findings.errors):
                findings.add_error(code, f"{r.kind} {r.index}: {msg}", v.artifact)
    spent = sum(r.update_s for r in results)
    updates = sum(r.updates for r in results)
    measured_fps = updates / spent if spent > 0 and updates else 0.0
    fps = reported_fps(measured_fps)
    ded = speed_deduction(fps)
    if ctx.out_dir is not None:
        _write_timing(Path(ctx.out_dir), measured_fps, spent, updates, results)
    frames_total = sum(len(r.truth) for r in results)
    shape_ok = sum(m["shape_accuracy"] * m["frames"] for ms in per_unit.values() for m in ms)
    outcomes = {
        "frames": _outcome(g["frames"], per_unit["frames"], "frame groups"),
        "trajectories": _outcome(g["trajectory"], per_unit["trajectory"], "trajectories"),
    }
    native = {
        "partial": ctx.quick,
        "fps": fps,
        "fps_note": f"frames/s rounded to {FPS_STEP:g} and capped at {FPS_FULL:g} (no deduction above)",
        "speed_deduction": ded,
        "frames_evaluated": frames_total,
        "predictions": updates,
        "shape_accuracy": shape_ok / frames_total if frames_total else 0.0,
        "groups": per_unit["frames"],
        "trajectories": per_unit["trajectory"],
        "static_vs_occluded": _occlusion_metrics(results),
    }
    if ctx.quick:
        native["partial_note"] = (
            f"quick mode: {n_groups} frame groups and {n_traj} trajectories of {QUICK_TRAJ_FRAMES} frames "
            f"instead of {N_GROUPS} and {N_TRAJ} of {TRAJ_FRAMES}"
        )
    if fps < FPS_FULL:
        findings.add_error("f06.slow", f"estimator runs at {fps:.1f} frames/s (< 10): deduction {ded:.3f}")
    return rubric.report(
        outcomes, valid=True, errors=findings.errors, deductions={VARIANT: ded}, native_metrics=native
    )
