"""The demonstration datasets the recipes train on: LIBERO-10's (``make libero-demos``) and the bimanual
stand-in's (``make standin-demos``), where they are found and their manifest digests."""

from __future__ import annotations

import os
from pathlib import Path

from rle_tasks.core.verify import VerifierSetupError
from rle_tasks.f05_nanovla.constants import OPEN_ID, STANDIN_PER_TASK

__all__ = [
    "DATASET_ENV",
    "DATASET_PER_TASK",
    "DATASET_SEED",
    "DATASET_VIEW_EVERY",
    "STANDIN_DATASET_ENV",
    "STANDIN_DATASET_PER_TASK",
    "SUITE",
    "dataset_digest",
    "dataset_dir",
]

SUITE = "libero_10"
DATASET_ENV = "RLE_F05_DEMOS"
"""Names a demonstration dataset directory other than the default (tests, operators)."""
DATASET_SEED = 0
DATASET_PER_TASK = 50
"""Expert demonstrations per LIBERO-10 task in the training dataset (LIBERO ships 50 per task)."""
DATASET_VIEW_EVERY = 4
"""The dataset records both views at every 4th frame (0.2 s) and the state and action at every one.
Rendering the two views costs about 120 ms of one core against 13 ms for a control step, so a
4-frame stride builds the dataset in about a third of the time (roughly 2 instead of 6.5
core-hours); and a recipe that trains for 1,800 s on CPUs cannot encode much more than every 4th
frame of 400 demonstrations anyway (the reference encodes every other one of these)."""

STANDIN_DATASET_ENV = "RLE_F05_STANDIN_DEMOS"
STANDIN_DATASET_PER_TASK = 50
"""Expert demonstrations per stand-in task (RoboTwin 2.0's clean sets hold 50 per task)."""


def dataset_dir(task_id: str = OPEN_ID) -> Path:
    """The demonstrations the recipe trains on (``RLE_F05_DEMOS`` / ``RLE_F05_STANDIN_DEMOS`` or the
    default cache)."""
    if task_id in STANDIN_PER_TASK:
        from rle_tasks.envs.standin.demos import default_dir as standin_dir

        given = os.environ.get(STANDIN_DATASET_ENV)
        return Path(given) if given else standin_dir(STANDIN_DATASET_PER_TASK)
    from rle_tasks.envs.libero.demos import default_dir

    given = os.environ.get(DATASET_ENV)
    return (
        Path(given)
        if given
        else default_dir(SUITE, DATASET_SEED, DATASET_PER_TASK, views=True, view_every=DATASET_VIEW_EVERY)
    )


def dataset_digest(path: Path, task_id: str = OPEN_ID) -> str:
    """The dataset's manifest digest; ``VerifierSetupError`` when it is not built."""
    digest = path / "manifest.sha256"
    if not digest.is_file() and task_id in STANDIN_PER_TASK:
        raise VerifierSetupError(
            f"the stand-in demonstration dataset is not built at {path}: build it with `make standin-demos` "
            f"(or point {STANDIN_DATASET_ENV} at a dataset built by `python -m rle_tasks.envs.standin.demos`)",
            code="f05.no_dataset",
        )
    if not digest.is_file():
        raise VerifierSetupError(
            f"the demonstration dataset is not built at {path}: build it with `make libero-demos` "
            f"(or point {DATASET_ENV} at a dataset built by `python -m rle_tasks.envs.libero.demos`)",
            code="f05.no_dataset",
        )
    return digest.read_text().strip()
