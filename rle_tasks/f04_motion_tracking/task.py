"""TaskSpecs of family 04: one task per clip style, the same contract, verifier and workspace."""

from __future__ import annotations

import shutil
from functools import partial
from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec

from .clips import TASK_CLIPS, clip_path
from .constants import CPUS, GPUS, N_SEEDS, QUICK_SEEDS, VERIFIER_TIMEOUT_S, WALL_TIME_S
from .verifier import verify

HERE = Path(__file__).resolve().parent
PUBLIC_PACKAGE = "motion_tracking"
"""Name of the public modules' package in the workspace."""
REGISTERED: tuple[str, ...] = ("04-dance", "04-fight", "04-fall-getup")
"""Tasks registered with a verifier: those with a shipped reference policy (the others stay placeholders)."""
SOLUTION_NAMES = (
    "reference",
    "baseline/open_loop",
    "baseline/zero_action",
    "baseline/nan_output",
    "baseline/non_deterministic",
    "baseline/twelve_million",
)


def instruction(task_id: str) -> str:
    from rle_tasks.f04_motion_tracking.scoring import rubric

    style = TASK_CLIPS[task_id][0]
    text = (HERE / "instruction.md").read_text().replace("{clip}", style)
    return text + "\n" + rubric(task_id).markdown_table() + "\n"


def make_dev_env(workspace: Path, style: str):
    """Lay out the public modules (``motion_tracking/``) and the clip (``clips/<style>.npz``); no
    metered environment (training runs locally)."""
    ws = Path(workspace)
    dest = ws / PUBLIC_PACKAGE
    if dest.exists():
        shutil.rmtree(dest)
    shutil.copytree(HERE / "public", dest, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    (ws / "clips").mkdir(parents=True, exist_ok=True)
    shutil.copyfile(clip_path(style), ws / "clips" / f"{style}.npz")
    return None


def task_spec(task_id: str) -> TaskSpec:
    style, title = TASK_CLIPS[task_id]
    return TaskSpec(
        id=task_id,
        family=4,
        title=f"Whole-body motion tracking: {title}",
        instruction=instruction(task_id),
        budget=Budget(wall_time_s=WALL_TIME_S, cpus=CPUS, gpus=GPUS, verifier_timeout_s=VERIFIER_TIMEOUT_S),
        contract=ArtifactContract(
            required=("policy.onnx", "policy_meta.json"),
            description="policy.onnx: obs (1, 160 H) float32 -> actions (1, 29), at most 10 M parameters; "
            "policy_meta.json: history H (1-16), action_scale and default_pose (29 each, rad).",
        ),
        make_dev_env=partial(make_dev_env, style=style),
        verify=partial(verify, task_id=task_id),
        solutions=SOLUTION_NAMES,
        solutions_module="rle_tasks.f04_motion_tracking.solutions",
        quick_note=f"quick plays {QUICK_SEEDS} of the {N_SEEDS} hidden seeds; the score is partial",
    )


def task_specs() -> list[TaskSpec]:
    return [task_spec(t) for t in REGISTERED]
