"""Verifier of ``08-mobile-base``: measurements per arm, renders; the rubric is ``scoring.RUBRIC``.

Each arm-dependent checkpoint scores the minimum over the three arms (``per_variant`` holds each
arm's value). A failed structure checkpoint (validity) or a failed load checkpoint caps the reward
(declared caps ``structure`` and ``required_load``). The load checkpoint fails when the
required 1 kg load cannot be handled: a pose of the static battery at 0 or 1 kg in which the machine
cannot stand, or ``shelf_1kg`` below ``LOAD_PASS`` (fewer than half of the targets held by some arm).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from rle_design.errors import RleError
from rle_design.mjcf import load_design, match_profiles
from rle_design.sandbox import ParticipantFault, SandboxLimits, wake_poll_for
from rle_design.scene import Variation, element_id
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.parallel import run_units
from rle_tasks.core.runtime.policy import PolicyRunner
from rle_tasks.core.runtime.secrets import derive_rng
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext
from rle_tasks.f08_mobile_base import batteries as B
from rle_tasks.f08_mobile_base.env import CONTROLLER, CONTROLLER_BUDGET, run_trial
from rle_tasks.f08_mobile_base.poses import battery_poses
from rle_tasks.f08_mobile_base.public.scene import ARMS, CHASSIS, TASK_ID, VARIATIONS, build_scene
from rle_tasks.f08_mobile_base.scoring import DESIGN_NORMS, LOAD_PASS, RUBRIC
from rle_tasks.f08_mobile_base.validity import check_validity, interpenetration

QUICK_TARGETS = ("T01", "T12")


def _design_metrics(design, model) -> dict:
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    chassis = element_id(model, "body", CHASSIS)
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for g in range(model.ngeom):
        c, h = model.geom_aabb[g][:3], model.geom_aabb[g][3:]
        corners = c + h * np.array([[a, b, e] for a in (-1, 1) for b in (-1, 1) for e in (-1, 1)])
        pts = data.geom_xpos[g] + corners @ data.geom_xmat[g].reshape(3, 3).T
        lo, hi = np.minimum(lo, pts.min(0)), np.maximum(hi, pts.max(0))
    prof = match_profiles(design, model)
    bottom = lo[2]
    return {
        "footprint_m2": float((hi[0] - lo[0]) * (hi[1] - lo[1])),
        "length_m": float(hi[0] - lo[0]),
        "width_m": float(hi[1] - lo[1]),
        "height_m": float(hi[2] - bottom),
        "base_mass_kg": float(model.body_subtreemass[chassis]),
        "profile_length_m": prof.total_length,
        "profile_cost_eur": prof.total_cost,
    }


def _design_score(metrics: dict) -> tuple[float, dict]:
    parts = {}
    for key, (good, bad) in DESIGN_NORMS.items():
        parts[key] = float(np.clip((bad - metrics[key]) / (bad - good), 0.0, 1.0))
    return float(np.mean(list(parts.values()))), parts


def _variation(ctx: VerifyContext, label: str) -> Variation:
    return VARIATIONS.sample(derive_rng(ctx.secret, TASK_ID, label))


def _evaluate_arm(design, root: Path, arm: str, ctx: VerifyContext, report: Findings) -> dict:
    quick = ctx.quick
    out: dict = {"arm": arm}
    scenes = {
        kg: build_scene(
            design.fresh_spec, arm, kg, variation=_variation(ctx, f"{arm}/static/{kg}"), visual=False
        )
        for kg in (0, 1, 2)
    }
    sc0 = scenes[0]
    d = sc0.rest_data()
    bad = interpenetration(sc0.model, d, sc0.robot_geoms)
    out["mount_ok"] = not bad
    if bad:
        report.add_error("f08.interpenetration", f"{arm}: at rest, {'; '.join(bad[:5])}")
    targets = QUICK_TARGETS if quick else None
    poses = battery_poses(
        scenes[2], target_ids=targets, reach_dirs=("front", "left", "back") if quick else None
    )
    out["ik"] = {p.name: p.residual for p in poses if p.target is not None}
    cases = [B.static_case(scenes[kg], p, kg) for kg in ((1, 2) if quick else (0, 1, 2)) for p in poses]
    out["static"] = [c.__dict__ | {"passed": c.passed} for c in cases]
    out["static_score"] = float(np.mean([c.passed for c in cases]))
    out["required_load_ok"] = not any(c.tips for c in cases if c.payload_kg <= 1)
    out["static_2kg_ok"] = all(c.passed for c in cases if c.payload_kg == 2)
    dyn_scene = build_scene(
        design.fresh_spec, arm, 2, variation=_variation(ctx, f"{arm}/dynamic"), visual=False
    )
    dyn = B.dynamic_battery(dyn_scene, poses, derive_rng(ctx.secret, TASK_ID, f"{arm}/dynamic/rng"), quick)
    out["dynamic"] = dyn
    out["dynamic_score"] = float(np.mean([s["passed"] for s in dyn]))
    out["poses"] = poses
    # simulated seconds per scene (for the physics-floor benchmark)
    out["sim_s"] = {
        "static": {kg: B.SETTLE_S * sum(c.payload_kg == kg for c in cases) for kg in (0, 1, 2)},
        "dynamic": float(sum(s["duration_s"] for s in dyn)),
    }
    return out


def _shelf(design, root: Path, arm: str, ctx: VerifyContext, report: Findings, kg: int) -> dict:
    from rle_design.catalog import load_catalog

    shelf = load_catalog("shelf")
    ids = QUICK_TARGETS if ctx.quick else tuple(t.id for t in shelf.entries)
    scene = build_scene(
        design.fresh_spec, arm, kg, shelf=True, variation=_variation(ctx, f"{arm}/shelf/{kg}"), visual=False
    )
    trials = {}
    with PolicyRunner(
        root / "controller.py",
        CONTROLLER,
        dims={"nu": scene.model.nu},
        hang_cap_s=ctx.hang_cap_s,
        budget=CONTROLLER_BUDGET,
        limits=SandboxLimits(cpu_seconds=CONTROLLER_BUDGET.cpu_s, wake_poll_s=wake_poll_for(ctx.jobs)),
        workdir_files={"robot.xml": root / "robot.xml"},
    ) as controller:
        for t in shelf.entries:
            if t.id not in ids:
                continue
            rng = derive_rng(ctx.secret, TASK_ID, f"{arm}/shelf/{kg}/{t.id}")
            target = np.array(t.pos) + rng.uniform(-0.01, 0.01, 3)
            if controller.exhausted:
                trials[t.id] = {"success": False, "reason": "skipped after repeated controller faults"}
                continue
            try:
                trials[t.id] = run_trial(scene, controller, target, float(kg))
            except ParticipantFault as exc:  # recorded by the runner, which restarts the controller
                trials[t.id] = {"success": False, "reason": f"controller fault {exc.code}: {exc.message}"}
                report.add_error(exc.code, f"{arm} {kg} kg {t.id}: {exc.message}", "controller.py")
    return trials


def _render(design, arm_out: dict, arm: str, out_dir: Path, report: Findings) -> None:
    try:
        from rle_design.viz.render import render_png
        from rle_tasks.f08_mobile_base.poses import park_x

        out_dir.mkdir(parents=True, exist_ok=True)
        poses = {p.name: p for p in arm_out["poses"]}
        free = build_scene(design.fresh_spec, arm, 1)
        shelf = build_scene(design.fresh_spec, arm, 1, shelf=True)
        target = "T07" if "T07" in poses else "T01"
        views = [
            ("stowed", free, None, 0.0, dict(lookat=[0.2, 0, 0.45], distance=2.0)),
            ("extended", free, "reach_front", 0.0, dict(lookat=[0.35, 0, 0.5], distance=2.2)),
            ("integration", shelf, target, park_x(shelf), dict(distance=2.2, azimuth=-60.0, elevation=-25.0)),
        ]
        for label, sc, pname, x, cam in views:
            d = sc.rest_data(x)
            if pname in poses:
                d.qpos[sc.chain.qpos_adr] = poses[pname].q
            mujoco.mj_forward(sc.model, d)
            cam.setdefault("lookat", [x + 0.45, 0, 0.55])
            render_png(sc.model, d, out_dir / f"{arm}_{label}.png", **cam)
    except Exception as exc:  # noqa: BLE001 - renders accompany the report; their failure is not a score
        report.add_error("render.failed", f"{arm}: {type(exc).__name__}: {exc}")


@dataclass(frozen=True)
class ArmUnit:
    """One part of one arm's evaluation (a runner unit; picklable)."""

    root: str
    """The submission directory."""
    arm: str
    part: str
    """``"stability"``, ``"shelf1"`` or ``"shelf2"``."""
    key: bytes
    """The secret's key, and whether it is the public one."""
    public: bool
    quick: bool
    hang_cap_s: float


def _arm_job(unit: ArmUnit) -> tuple[dict, list]:
    """One unit of work in a worker process: (results, error entries)."""
    from rle_tasks.core.runtime.secrets import Secret

    root, arm, part = unit.root, unit.arm, unit.part
    ctx = VerifyContext(secret=Secret(unit.key, unit.public), quick=unit.quick, hang_cap_s=unit.hang_cap_s)
    sink = Findings()
    try:
        design = load_design(Path(root))
        if part == "stability":
            out = _evaluate_arm(design, Path(root), arm, ctx, sink)
        else:
            out = {"trials": _shelf(design, Path(root), arm, ctx, sink, int(part[-1]))}
    except RleError as exc:
        return {"fault": (exc.code, exc.message)}, [(e.code, e.message, e.path) for e in sink.errors]
    return out, [(e.code, e.message, e.path) for e in sink.errors]


PARTS = ("stability", "shelf1", "shelf2")


def _evaluate_arms(root: Path, ctx: VerifyContext, report: Findings, problems: list) -> dict[str, dict]:
    """Per-arm evaluations as 9 units (arm x part), in ``ctx.jobs`` worker processes when > 1; results
    are merged in a fixed order, so the report does not depend on scheduling."""
    units = [(a, p) for p in PARTS for a in ARMS]
    args = [
        ArmUnit(str(root), a, p, ctx.secret.key, ctx.secret.public, ctx.quick, ctx.hang_cap_s)
        for a, p in units
    ]
    results = run_units(_arm_job, args, ctx, max_jobs=len(args))
    arms: dict[str, dict] = {}
    faults: dict[str, tuple[str, str]] = {}
    for (arm, part), (out, errors) in zip(units, results):
        for code, msg, path in errors:
            report.add_error(code, msg, path)
        if "fault" in out:
            faults.setdefault(arm, out["fault"])
            continue
        if part == "stability":
            arms.setdefault(arm, {}).update(out)
        else:
            arms.setdefault(arm, {}).setdefault("shelf", {})[int(part[-1])] = out["trials"]
    for arm, (code, msg) in faults.items():
        problems.append((code, f"{arm}: {msg}"))
        report.add_error(code, f"{arm}: {msg}", "robot.xml")
        arms.pop(arm, None)
    for o in arms.values():
        o["sim_s"]["shelf"] = {
            kg: float(sum(t.get("time_s", 0.0) for t in o["shelf"][kg].values())) for kg in (1, 2)
        }
    return arms


def verify(root: Path, ctx: VerifyContext, *, task_id: str = TASK_ID) -> VerifierReport:
    """Verify a submission directory (robot.xml, controller.py)."""
    if task_id != TASK_ID:
        raise ValueError(f"this verifier scores {TASK_ID}, not {task_id}")
    report = Findings()
    problems: list[tuple[str, str]] = []
    design = None
    try:
        design = load_design(root)
        problems = check_validity(design)
    except RleError as exc:
        problems = [(exc.code, exc.message)]
    for code, msg in problems:
        report.add_error(code, msg, "robot.xml")
    if not (root / "controller.py").is_file():
        problems.append(("artifact.missing_file", "controller.py is missing"))
        report.add_error("artifact.missing_file", "controller.py is missing", "controller.py")
    arms: dict[str, dict] = {}
    if design is not None and not any(
        c.startswith(("mjcf", "contract", "artifact.unsafe")) for c, _ in problems
    ):
        arms = _evaluate_arms(root, ctx, report, problems)
    mount_ok = {a: bool(arms.get(a, {}).get("mount_ok", False)) for a in ARMS}
    valid = not problems and all(mount_ok.values())
    out: dict[str, Outcome] = {}
    out["validity"] = Outcome(
        {a: float(mount_ok[a] and not problems) for a in ARMS},
        "valid"
        if valid
        else "; ".join(m for _, m in problems[:5]) or "an arm interpenetrates the base at rest",
        measured={"findings": [c for c, _ in problems]},
    )
    metrics, dscore, parts = {}, 0.0, {}
    if design is not None and arms:
        metrics = _design_metrics(design, design.compile())
        dscore, parts = _design_score(metrics)
    out["design_resources"] = Outcome(
        {a: dscore for a in ARMS}, "normalised resource use", measured=metrics | {"subscores": parts}
    )

    def per_arm(fn) -> dict:
        return {a: (fn(arms[a]) if a in arms else 0.0) for a in ARMS}

    out["static_stability"] = Outcome(
        per_arm(lambda o: o["static_score"]),
        _static_message(arms),
        measured={a: _static_summary(o) for a, o in arms.items()},
    )
    out["dynamic_stability"] = Outcome(
        per_arm(lambda o: o["dynamic_score"]),
        "; ".join(
            f"{a}: {', '.join(_scenario_failure(s) for s in o['dynamic'] if not s['passed']) or 'all passed'}"
            for a, o in arms.items()
        ),
        measured={a: o["dynamic"] for a, o in arms.items()},
    )
    for kg in (1, 2):
        sh = per_arm(lambda o, kg=kg: float(np.mean([t["success"] for t in o["shelf"][kg].values()])))
        fails = {
            a: {tid: t["reason"] for tid, t in o["shelf"][kg].items() if not t["success"]}
            for a, o in arms.items()
        }
        msg = (
            "; ".join(f"{a}: {len(f)} failed ({next(iter(f.values()))})" for a, f in fails.items() if f)
            or "all targets held"
        )
        out[f"shelf_{kg}kg"] = Outcome(sh, msg, measured={a: o["shelf"][kg] for a, o in arms.items()})
    stand_ok = all(arms.get(a, {}).get("required_load_ok", False) for a in ARMS)
    load_ok = stand_ok and min(out["shelf_1kg"].per_variant.values()) >= LOAD_PASS
    if ctx.out_dir is not None and design is not None:
        for a, o in arms.items():
            _render(design, o, a, Path(ctx.out_dir), report)
    caps = ([] if valid else ["structure"]) + ([] if load_ok else ["required_load"])
    return RUBRIC.report(
        out,
        valid=valid,
        errors=report.errors,
        caps=caps,
        native_metrics={
            "quick": ctx.quick,
            "design": metrics,
            "required_load_ok": load_ok,
            "stands_with_required_load": stand_ok,
            "cap_reason": None
            if valid and load_ok
            else ("structure (validity)" if not valid else "required 1 kg load"),
            "ik_residual_m": {a: o["ik"] for a, o in arms.items()},
            "simulated_s": {a: o["sim_s"] for a, o in arms.items()},
        },
    )


def _scenario_failure(s: dict) -> str:
    """A failed dynamic scenario's name, with the MuJoCo warning that failed it if any."""
    return f"{s['scenario']} ({s['warning']})" if s.get("warning") else s["scenario"]


def _static_summary(o: dict) -> dict:
    cases = o["static"]
    worst = min(cases, key=lambda c: c["margin"])
    return {
        "min_margin_m": worst["margin"],
        "worst_pose": f"{worst['pose']} @ {worst['payload_kg']} kg",
        "min_force_angle_deg": min(c["force_angle_deg"] for c in cases),
        "min_wheel_frac": min(c["min_wheel_frac"] for c in cases),
        "failed": [
            f"{c['pose']}@{c['payload_kg']}kg" + (f" ({c['warning']})" if c.get("warning") else "")
            for c in cases
            if not c["passed"]
        ],
    }


def _static_message(arms: dict) -> str:
    parts = []
    for a, o in arms.items():
        failed = _static_summary(o)["failed"]
        if failed:
            parts.append(f"{a}: {len(failed)} poses fail ({', '.join(failed[:4])})")
    return "; ".join(parts) or "all poses stable"
