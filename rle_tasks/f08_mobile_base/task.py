"""TaskSpec of 08-mobile-base: instruction, budget, artifact contract and development workspace."""

from __future__ import annotations

import shutil
from functools import partial
from pathlib import Path

from rle_design.catalog import load_catalog
from rle_design.paths import CATALOG_DIR, resolve_asset
from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec
from rle_tasks.f08_mobile_base.constants import CPUS, TASK_ID, WALL_TIME_S
from rle_tasks.f08_mobile_base.verifier import verify

HERE = Path(__file__).resolve().parent
SKELETON = HERE / "assets" / "skeleton_robot.xml"
"""Workspace skeleton (written by ``solutions/design_gen.py``)."""
PUBLIC_PACKAGE = "mobile_base"
"""Name of the public modules' package in the workspace."""
SOLUTION_NAMES = (
    "reference",
    "baseline/bad_mount",
    "baseline/non_catalog_profile",
    "baseline/raising_controller",
    "baseline/tall_narrow",
)
"""Shipped solutions, declared in ``solutions/__init__.py``."""


def instruction() -> str:
    """The agent instruction (``instruction.md``) with the rubric's credit table appended."""
    from rle_tasks.f08_mobile_base.scoring import RUBRIC

    return (HERE / "instruction.md").read_text() + "\n" + RUBRIC.markdown_table() + "\n"


def make_dev_env(workspace: Path) -> None:
    """Lay out the development workspace: arms, catalog, skeleton, the public scene and preview."""
    ws = Path(workspace)
    (ws / "catalog" / "parts").mkdir(parents=True, exist_ok=True)
    for name in ("profiles.yaml", "parts.yaml", "shelf.yaml"):
        shutil.copyfile(CATALOG_DIR / name, ws / "catalog" / name)
    for part in load_catalog("parts"):
        shutil.copyfile(CATALOG_DIR / part.fragment, ws / "catalog" / part.fragment)
    for arm in load_catalog("arms"):
        src = resolve_asset(arm.model).parent
        shutil.copytree(src, ws / "arms" / arm.id, dirs_exist_ok=True)
    (ws / "instruction.md").write_text(instruction())
    shutil.copyfile(SKELETON, ws / "skeleton_robot.xml")
    dest = ws / PUBLIC_PACKAGE
    if dest.exists():
        shutil.rmtree(dest)
    shutil.copytree(HERE / "public", dest, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))


def task_spec() -> TaskSpec:

    return TaskSpec(
        id=TASK_ID,
        family=8,
        title="Universal mobile-manipulator base",
        instruction=instruction(),
        budget=Budget(wall_time_s=WALL_TIME_S, cpus=CPUS),
        contract=ArtifactContract(
            required=("robot.xml", "controller.py"),
            description="robot.xml: the mecanum base (catalog profiles and immutable parts, arm_mount_site); "
            "controller.py: reset(arm, target, payload_kg, layout) and control(t, qpos, qvel, ctrl) at 50 Hz.",
        ),
        make_dev_env=make_dev_env,
        verify=partial(verify, task_id=TASK_ID),
        solutions=SOLUTION_NAMES,
        solutions_module="rle_tasks.f08_mobile_base.solutions",
        quick_note="quick reaches two shelf targets (T01, T12) from three directions (front, left, back) "
        "instead of every target and direction, checks the 1 and 2 kg payloads (not 0 kg) and drops some "
        "dynamic scenarios (backward and sideways accelerations, the arm swing); the score is partial",
    )
