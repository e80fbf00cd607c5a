"""TaskSpecs of the four ``06-pose-*`` tasks: instruction, budget, artifact contract, verifier."""

from __future__ import annotations

import functools
from pathlib import Path

from rle_tasks.core.task import ArtifactContract, Budget, TaskSpec

from .constants import CPUS, GPUS, VERIFIER_TIMEOUT_S, WALL_TIME_S
from .contract import VARIANTS, Variant
from .verifier import verify

HERE = Path(__file__).resolve().parent
RESOURCES = {
    "a": "4 CPUs",
    "b": "4 CPUs",
    "c": "16 CPUs and 1 GPU for training; inference on one CPU thread",
    "d": "4 CPUs and 1 GPU in development; final inference on one CPU",
}
CONTRACTS = {
    False: "estimator.py: module-level reset() and update(obs) -> (x [m], y [m], theta [rad], shape_id); "
    "causal state allowed; any helper files beside it in the directory.",
    True: "model.pt: CPU TorchScript module, at most 20 M tensor elements, stateless: "
    "forward(rgb (1,3,240,320) in [0,1], depth (1,1,240,320) [m], valid (1,1,240,320)) -> "
    "(1, 6): x [m], y [m], theta [rad], logits of T, C, F.",
}


def instruction(v: Variant) -> str:
    """The agent instruction of one variant with the rubric's table appended."""
    from .scoring import RUBRICS

    text = (HERE / "instruction.md").read_text()
    head = f"# {v.task_id}: {v.title}\n\nVariant {v.letter.upper()}; resources: {RESOURCES[v.letter]}.\n"
    head += "Observations carry depth and a validity mask.\n" if v.depth else "Observations are RGB only.\n"
    return head + "\n" + text + "\n" + RUBRICS[v.task_id].markdown_table() + "\n"


def _dev_env(task_id: str, workspace: Path):
    from .devenv import make_dev_env

    return make_dev_env(task_id, workspace)


def task_specs() -> list[TaskSpec]:
    from .solutions import solution_names

    out = []
    for v in VARIANTS:
        out.append(
            TaskSpec(
                id=v.task_id,
                family=6,
                title=v.title,
                instruction=instruction(v),
                budget=Budget(
                    wall_time_s=WALL_TIME_S,
                    cpus=CPUS[v.letter],
                    gpus=GPUS[v.letter],
                    verifier_timeout_s=VERIFIER_TIMEOUT_S,
                ),
                contract=ArtifactContract(
                    required=(v.artifact,), optional=("*",), description=CONTRACTS[v.learned]
                ),
                make_dev_env=functools.partial(_dev_env, v.task_id),
                verify=functools.partial(verify, task_id=v.task_id),
                solutions=solution_names(v.letter),
                solutions_module=f"{__package__}.solutions.variant_{v.letter}",
                quick_note="quick scores 3 of the 10 frame groups and 3 of the 10 push trajectories (20 of "
                "their 60 frames); the score is partial",
            )
        )
    return out
