"""TaskSpec of ``05-libero-open``: instruction, budget, artifact contract, development workspace."""

from __future__ import annotations

import functools
from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, ImageData, TaskSpec

from .constants import CPUS, GPUS, MEMORY_MB, VERIFIER_TIMEOUT_S, WALL_TIME_S
from .datasets import DATASET_ENV, STANDIN_DATASET_ENV, dataset_dir
from .verifier import PERTURBATIONS, verify

HERE = Path(__file__).resolve().parent
SOLUTION_NAMES = {
    "05-libero-open": (
        "reference",
        "baseline/mean_action",
        "baseline/nan_server",
        "baseline/too_large",
        "baseline/over_budget",
        "baseline/reads_eval_states",
    ),
    "05-libero-robust": ("reference", "baseline/mean_action", "baseline/too_large"),
    "05-robotwin-open": ("reference", "baseline/mean_action", "baseline/nan_server", "baseline/too_large"),
    "05-robotwin-robust": ("reference", "baseline/mean_action"),
}
"""Shipped solutions per task, declared in ``solutions/__init__.py``."""
TITLES = {
    "05-libero-open": "nanoVLA recipe engineering: LIBERO-10, open track",
    "05-libero-robust": "nanoVLA recipe engineering: LIBERO-10 under LIBERO-PRO perturbations, robust track",
    "05-robotwin-open": "nanoVLA recipe engineering: bimanual stand-in for RoboTwin 2.0, open track",
    "05-robotwin-robust": "nanoVLA recipe engineering: bimanual stand-in for RoboTwin 2.0, robust track",
}
CONTRACTS = {
    "libero": "solution.py: one UTF-8 file of at most 1 MiB defining train(demos_dir) (writes ckpt.pt "
    "and optionally meta.json in its working directory within 1,800 s + 120 s) and "
    "serve(socket_path) (answers the policy socket protocol with chunks of 1-64 actions, 7-D in [-1, 1]); "
    "nothing else in the directory is read.",
    "standin": "solution.py: one UTF-8 file of at most 1 MiB defining train(demos_dir) (writes ckpt.pt "
    "and optionally meta.json in its working directory within 1,800 s + 120 s) and "
    "serve(socket_path) (answers the policy socket protocol, env 'standin': 16-D state, chunks of 1-64 "
    "actions of 14 joint targets and gripper commands); nothing else in the directory is read.",
}


def instruction(task_id: str = "05-libero-open") -> str:
    """The agent instruction (``instruction.md``, and ``robust.md`` for the robust track) with the
    rubric's credit table appended."""
    from rle_tasks.f05_nanovla.scoring import EPISODE_SETS, rubric

    full = EPISODE_SETS[task_id]
    if task_id.startswith("05-robotwin"):
        text = f"# {task_id}: {TITLES[task_id]}\n\n" + (HERE / "standin.md").read_text()
        if task_id == "05-robotwin-robust":
            text += "\n" + (HERE / "standin_robust.md").read_text()
        return text + "\n" + rubric(task_id, full).markdown_table() + "\n"
    text = f"# {task_id}: {TITLES[task_id]}\n\n" + (HERE / "instruction.md").read_text()
    if task_id == "05-libero-robust":
        kinds = "\n".join(f"- `{suite}`: {what}" for suite, what in PERTURBATIONS.items())
        text += "\n" + (HERE / "robust.md").read_text().replace("{perturbations}", kinds)
    return text + "\n" + rubric(task_id, full).markdown_table() + "\n"


def make_dev_env(workspace: Path, task_id: str = "05-libero-open"):
    from rle_tasks.f05_nanovla.devenv import make_dev_env as make

    return make(workspace, task_id)


def _image_data(task_id: str) -> ImageData:
    """The demonstrations, in every exported image: the agent trains on them, the sidecar links them
    into the workspace, the verifier retrains on them."""
    standin = task_id.startswith("05-robotwin")
    return ImageData(
        name="standin-demos" if standin else "libero-demos",
        source=functools.partial(_dataset_dir, task_id),
        env=STANDIN_DATASET_ENV if standin else DATASET_ENV,
        build="make standin-demos" if standin else "make libero-demos",
    )


def _dataset_dir(task_id: str) -> Path:
    return dataset_dir(task_id)


def task_specs() -> list[TaskSpec]:
    return [task_spec(t) for t in SOLUTION_NAMES]


def task_spec(task_id: str = "05-libero-open") -> TaskSpec:
    return TaskSpec(
        id=task_id,
        family=5,
        title=TITLES[task_id],
        instruction=instruction(task_id),
        budget=Budget(
            wall_time_s=WALL_TIME_S,
            cpus=CPUS,
            gpus=GPUS,
            memory_mb=MEMORY_MB,
            verifier_timeout_s=VERIFIER_TIMEOUT_S,
        ),
        contract=ArtifactContract(
            required=("solution.py",),
            description=CONTRACTS["standin" if task_id.startswith("05-robotwin") else "libero"],
        ),
        make_dev_env=functools.partial(make_dev_env, task_id=task_id),
        verify=functools.partial(verify, task_id=task_id),
        solutions=SOLUTION_NAMES[task_id],
        solutions_module="rle_tasks.f05_nanovla.solutions",
        episode_scored=True,
        quick_note="quick trains the recipe in full, then evaluates the first "
        + ("12" if task_id.startswith("05-robotwin") else "2")
        + " episodes of the hidden set; the score is partial",
        harbor_data=(_image_data(task_id),),
        side_envs=() if task_id.startswith("05-robotwin") else ("libero",),
    )
