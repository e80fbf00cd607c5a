"""TaskSpec of 07-bin-clearing: instruction, budget, artifact contract and development workspace."""

from __future__ import annotations

import shutil
from functools import partial
from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec
from rle_tasks.f07_bin_clearing.constants import CPUS, TASK_ID, VERIFIER_TIMEOUT_S, WALL_TIME_S
from rle_tasks.f07_bin_clearing.verifier import verify

HERE = Path(__file__).resolve().parent
CALIBRATION = HERE / "assets" / "calibration.json"
"""Published geometry and camera calibration (``public.workcell.calibration()``, committed)."""
PUBLIC_PACKAGE = "bin_clearing"
"""Name of the public modules' package in the workspace."""
SOLUTION_NAMES = (
    "reference",
    "baseline/idle",
    "baseline/floor_dropper",
    "baseline/bin_slammer",
    "baseline/raising",
    "baseline/hanging",
)
"""Shipped solutions, declared in ``solutions/__init__.py``."""


def instruction() -> str:
    """The agent instruction (``instruction.md``) with the rubric's credit table appended."""
    from rle_tasks.f07_bin_clearing.scoring import RUBRIC

    return (HERE / "instruction.md").read_text() + "\n" + RUBRIC.markdown_table() + "\n"


def make_dev_env(workspace: Path):
    """Lay out the public modules and the calibration; return the metered environment of public pile 101."""
    from rle_tasks.f07_bin_clearing.public.env import make_env
    from rle_tasks.f07_bin_clearing.public.pile import PUBLIC_SEEDS, PileSpec

    dest = Path(workspace) / PUBLIC_PACKAGE
    if dest.exists():
        shutil.rmtree(dest)
    shutil.copytree(HERE / "public", dest, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    shutil.copyfile(CALIBRATION, Path(workspace) / "calibration.json")
    return make_env(PileSpec.public(PUBLIC_SEEDS[0]))


def task_spec() -> TaskSpec:

    return TaskSpec(
        id=TASK_ID,
        family=7,
        title="Contact-rich bin clearing onto a conveyor",
        instruction=instruction(),
        budget=Budget(wall_time_s=WALL_TIME_S, cpus=CPUS, steps=None, verifier_timeout_s=VERIFIER_TIMEOUT_S),
        contract=ArtifactContract(
            required=("policy/__init__.py",),
            optional=("policy/*",),
            description="policy/: an isolated package exposing make_policy(), reset() and act(obs) -> "
            "seven joint-position targets [rad] and one magnet command in [0, 1] per 20 Hz tick.",
        ),
        make_dev_env=make_dev_env,
        verify=partial(verify, task_id=TASK_ID),
        solutions=SOLUTION_NAMES,
        solutions_module="rle_tasks.f07_bin_clearing.solutions",
        quick_note="quick plays the first hidden pile for 30 s of simulated time (the evaluation: eight "
        "piles, 120 s each); the score is partial",
    )
