"""Family 08: universal mobile-manipulator base (``08-mobile-base``)."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec

HERE = Path(__file__).resolve().parent


def tasks() -> list[TaskSpec]:
    from rle_tasks.f08_mobile_base.harness import INSTRUCTION, make_dev_env
    from rle_tasks.f08_mobile_base.verifier import verify

    sols = (
        [("reference", HERE / "reference")]
        + [(f"baseline/{p.name}", p) for p in sorted((HERE / "baseline").iterdir()) if p.is_dir()]
        if (HERE / "baseline").is_dir()
        else [("reference", HERE / "reference")]
    )
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
            solutions=tuple(sols),
        )
    ]
