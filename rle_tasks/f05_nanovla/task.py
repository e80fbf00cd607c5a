"""TaskSpec of ``05-libero-open``: instruction, budget, artifact contract, development workspace."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec

HERE = Path(__file__).resolve().parent
SOLUTION_NAMES = (
    "baseline/mean_action",
    "baseline/nan_server",
    "baseline/too_large",
    "baseline/over_budget",
    "baseline/reads_eval_states",
)
"""Shipped solutions, declared in ``solutions/__init__.py``."""


def instruction() -> str:
    """The agent instruction (``instruction.md``) with the rubric's credit table appended."""
    from rle_tasks.f05_nanovla.scoring import RUBRIC

    return (HERE / "instruction.md").read_text() + "\n" + RUBRIC.markdown_table() + "\n"


def make_dev_env(workspace: Path):
    from rle_tasks.f05_nanovla.devenv import make_dev_env as make

    return make(workspace)


def task_spec() -> TaskSpec:
    from rle_tasks.f05_nanovla.verifier import TASK_ID, verify

    return TaskSpec(
        id=TASK_ID,
        family=5,
        title="nanoVLA recipe engineering: LIBERO-10, open track",
        instruction=instruction(),
        budget=Budget(
            wall_time_s=4 * 3600.0, cpus=48, gpus=1, memory_mb=64 * 1024, verifier_timeout_s=12 * 3600.0
        ),
        contract=ArtifactContract(
            required=("solution.py",),
            description="solution.py: one UTF-8 file of at most 1 MiB defining train(demos_dir) (writes ckpt.pt "
            "and optionally meta.json in its working directory within 1,800 s + 120 s) and "
            "serve(socket_path) (answers the policy socket protocol with chunks of 1-64 actions, 7-D in [-1, 1]); "
            "nothing else in the directory is read.",
        ),
        make_dev_env=make_dev_env,
        verify=verify,
        solutions=SOLUTION_NAMES,
        solutions_module="rle_tasks.f05_nanovla.solutions",
        episode_scored=True,
        harbor_unsupported="its images would need the LIBERO side environment and the demonstration dataset "
        "(several GB), and its development server (LIBERO, ledger key) a process outside the agent's user; "
        "run it with `rle dev` and `rle verify`",
    )
