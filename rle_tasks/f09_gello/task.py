"""TaskSpec of 09-gello: instruction, budget, artifact contract and development environment."""

from __future__ import annotations

import shutil
from functools import partial
from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec
from rle_tasks.f09_gello.constants import CPUS, TASK_ID, VERIFIER_TIMEOUT_S, WALL_TIME_S
from rle_tasks.f09_gello.verifier import verify

HERE = Path(__file__).resolve().parent
TRIM_TEMPLATES = HERE / "assets" / "trim_templates"
BASELINES = ("uncompensated", "gravcomp_cheat", "over_mass", "hanging_trim")
"""Shipped baselines (``baseline/<name>``), declared in ``solutions/__init__.py``."""


def instruction() -> str:
    """The agent instruction (``instruction.md``), with the checkpoint table appended."""
    from rle_tasks.f09_gello.scoring import RUBRIC

    return (HERE / "instruction.md").read_text() + "\n## Checkpoints\n\n" + RUBRIC.markdown_table() + "\n"


def make_dev_env(workspace: Path) -> None:
    """Lay out the workspace: stock leaders, helpers, instruction and an empty submission skeleton."""
    ws = Path(workspace)
    ws.mkdir(parents=True, exist_ok=True)
    for robot in ("panda", "ur5e", "xarm7"):
        dest = ws / "leaders" / robot
        if dest.exists():
            shutil.rmtree(dest)
        shutil.copytree(HERE / "assets" / robot, dest)
        sub = ws / "submission" / robot
        if not sub.exists():
            shutil.copytree(HERE / "assets" / robot, sub)
            shutil.copy(TRIM_TEMPLATES / "zero_trim.py", sub / "trim.py")
    shutil.copy(HERE / "public" / "gello_helpers.py", ws / "gello_helpers.py")
    shutil.copy(TRIM_TEMPLATES / "regressor_trim.py", ws / "example_trim.py")
    (ws / "instruction.md").write_text(instruction())


def task_spec() -> TaskSpec:

    return TaskSpec(
        id=TASK_ID,
        family=9,
        title="Multi-robot GELLO gravity-compensation co-design",
        instruction=instruction(),
        budget=Budget(wall_time_s=WALL_TIME_S, cpus=CPUS, verifier_timeout_s=VERIFIER_TIMEOUT_S),
        contract=ArtifactContract(
            required=(
                "panda/lead.xml",
                "panda/trim.py",
                "ur5e/lead.xml",
                "ur5e/trim.py",
                "xarm7/lead.xml",
                "xarm7/trim.py",
            ),
            optional=("*/meshes/*.stl", "*/meshes/*.obj", "*/*.xml", "*/*.py", "*/*.json", "*/*.npz"),
            description="For each robot (panda, ur5e, xarm7): lead.xml (the modified leader with springs, "
            "counterweights, supports; meshes it references inside the directory) and trim.py exposing "
            "feedforward(q, params=None), plan_probe() and adapt(probes).",
            max_total_bytes=32 * 1024 * 1024,
        ),
        make_dev_env=make_dev_env,
        verify=partial(verify, task_id=TASK_ID),
        solutions=("reference", *(f"baseline/{b}" for b in BASELINES)),
        solutions_module="rle_tasks.f09_gello.solutions",
        quick_note="quick uses 256 workspace-grid poses (full 4,096), 48 clearance poses (384), 2 hidden test "
        "poses (6), 1 hidden copy (2) and 0.5 s holds (2 s); the score is partial",
    )
