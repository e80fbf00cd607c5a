"""Family 08: universal mobile-manipulator base (``08-mobile-base``)."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec

HERE = Path(__file__).resolve().parent
SOLUTION_NAMES = (
    "reference",
    "baseline/bad_mount",
    "baseline/non_catalog_profile",
    "baseline/raising_controller",
    "baseline/tall_narrow",
)
"""Shipped solutions, declared in ``solutions/__init__.py``."""


def tasks() -> list[TaskSpec]:
    from rle_tasks.f08_mobile_base.harness import INSTRUCTION, make_dev_env
    from rle_tasks.f08_mobile_base.verifier import verify

    return [
        TaskSpec(
            id="08-mobile-base",
            family=8,
            title="Universal mobile-manipulator base",
            instruction=INSTRUCTION,
            budget=Budget(wall_time_s=2 * 3600.0, cpus=4),
            contract=ArtifactContract(
                required=("robot.xml", "controller.py"),
                description="robot.xml: the mecanum base (catalog profiles and immutable parts, arm_mount_site); "
                "controller.py: reset(arm, target, payload_kg, layout) and control(t, qpos, qvel, ctrl) at 50 Hz.",
            ),
            make_dev_env=make_dev_env,
            verify=verify,
            solutions=SOLUTION_NAMES,
            solutions_module=f"{__name__}.solutions",
        )
    ]
