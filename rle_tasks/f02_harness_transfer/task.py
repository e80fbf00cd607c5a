"""TaskSpecs of family 02: fifteen activity groups (``02-group-01`` ... ``02-group-15``).

Budget (card): 8 h, 1 GPU, 75,000 charged steps of development on the group's three development tasks
in pretrain kitchens (three RGB views with metric depth, camera geometry, the simulator's segmenter,
proprioception; object and fixture poses withheld: harness level 2 of family 01 without its modules).
The artifact is ``agent_harness/`` (code and ``MANUAL.md``). Evaluation: five fresh agents, each with
1 h and 5,000 steps on the held-out task in an unseen kitchen derived from the secret
(``rle_tasks.f02_harness_transfer.transfer``).
"""

from __future__ import annotations

import re
from functools import partial
from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec
from rle_tasks.envs.kitchen.composite_tasks import COMPOSITES
from rle_tasks.envs.kitchen.sessions import GroupScenes
from rle_tasks.envs.kitchen.workspace import lay_out_harness

from .constants import AGENT_STEPS, AGENT_WALL_S, STEP_BUDGET, TRIALS
from .groups import GROUPS, SKILLS, Group
from .solutions import SOLUTIONS
from .verifier import QUICK_TRIALS, verify

__all__ = [
    "AGENT_STEPS",
    "AGENT_WALL_S",
    "BUDGET",
    "CONTRACT",
    "STEP_BUDGET",
    "TRIALS",
    "task_specs",
]

HERE = Path(__file__).resolve().parent
BUDGET = Budget(
    wall_time_s=8 * 3600.0,
    cpus=4,
    gpus=1,
    steps=STEP_BUDGET,
    verifier_timeout_s=TRIALS * AGENT_WALL_S + 600.0,
)
CONTRACT = ArtifactContract(
    required=("agent_harness/MANUAL.md",),
    optional=("agent_harness/**",),
    description="agent_harness/: your harness, with MANUAL.md naming its entry point on a line "
    "`Entry point: `module:function`` (called as function(client, instruction) by a fresh agent). Only this "
    "directory reaches the fresh agents.",
    max_total_bytes=32 * 1024 * 1024,
)


def dev_scenes(group: Group) -> GroupScenes:
    """The development session's scenes: the three development tasks in pretrain kitchens."""
    return GroupScenes(group.develop[0], level=2, tasks=group.develop)


def _template(text: str) -> str:
    """An instruction template with its roles as ``<role>``."""
    return re.sub(r"[{](\w+)[}]", r"<\1>", text)


def instruction(group: Group) -> str:
    from .scoring import rubric

    dev = "\n".join(
        f"- `{t}`: {_template(COMPOSITES[t].instruction)} (skills: {', '.join(SKILLS[t])})"
        for t in group.develop
    )
    text = (HERE / "instruction.md").read_text()
    return (
        text.replace("{GROUP}", f"{group.number} ({group.difficulty}): {group.title}").replace(
            "{DEVELOP}", dev
        )
        + "\n"
        + rubric(group.task_id).markdown_table()
        + "\n"
    )


def task_specs() -> list[TaskSpec]:
    specs = []
    for group in GROUPS:

        def make_dev_env(workspace: Path, group: Group = group) -> GroupScenes:
            lay_out_harness(workspace, 1)
            return dev_scenes(group)

        shipped = SOLUTIONS.get(group.task_id)
        specs.append(
            TaskSpec(
                id=group.task_id,
                family=2,
                title=f"RoboCasa harness transfer, group {group.number} ({group.difficulty}): {group.title}",
                instruction=instruction(group),
                budget=BUDGET,
                contract=CONTRACT,
                make_dev_env=make_dev_env,
                verify=partial(verify, task_id=group.task_id),
                solutions=shipped.names if shipped is not None else (),
                solutions_module="rle_tasks.f02_harness_transfer.solutions",
                quick_note=f"quick runs {QUICK_TRIALS} of the {TRIALS} fresh agents; the score is partial",
            )
        )
    return specs
