"""Ship this machine's cached trainings of family-05 references: ``python -m rle_tasks.f05_nanovla.pin
TASK...`` copies each task's reference checkpoint from the training cache into ``checkpoints/`` and pins
it in ``manifest.json`` (``training.shipped`` reads them). Train first: ``rle demo --full --task TASK``
or ``rle verify TASK <reference> --quick``.
"""

from __future__ import annotations

import argparse
import json
from importlib.metadata import version

from rle_tasks.f05_nanovla import training


def pin(task_ids: list[str]) -> list[str]:
    """Copy this machine's cached training of each task's reference into ``checkpoints/`` and pin it in
    the manifest; returns the names written.

    Raises:
        LookupError: A task's reference has no cached training here (train it first).
    """
    from rle_tasks.core.registry import get_task
    from rle_tasks.core.solutions import materialise
    from rle_tasks.f05_nanovla.datasets import dataset_digest, dataset_dir

    entries = training.manifest()
    written = []
    for task_id in task_ids:
        recipe = (materialise(get_task(task_id), "reference") / "solution.py").read_bytes()
        dataset = dataset_digest(dataset_dir(task_id), task_id)
        found = training.cached_training(training.cache_entry(recipe, dataset))
        if found is None:
            raise LookupError(
                f"{task_id}: no cached training of its reference (run `rle demo --full --task {task_id}`)"
            )
        ckpt, meta, train_s = found
        name = f"{task_id}.reference"
        training.SHIPPED.mkdir(exist_ok=True)
        (training.SHIPPED / f"{name}.pt").write_bytes(ckpt)
        if meta is not None:
            (training.SHIPPED / f"{name}.meta.json").write_bytes(meta)
        entries[name] = {
            "solution_sha256": training.digest(recipe),
            "dataset_sha256": dataset,
            "torch": version("torch"),
            "train_limit_s": training.train_limit(),
            "ckpt_sha256": training.digest(ckpt),
            "meta_sha256": training.digest(meta) if meta is not None else None,
            "train_s": train_s,
        }
        written.append(name)
    (training.SHIPPED / "manifest.json").write_text(
        json.dumps(dict(sorted(entries.items())), indent=2) + "\n"
    )
    return written


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rle_tasks.f05_nanovla.pin")
    parser.add_argument("tasks", nargs="+", help="task ids whose reference training to ship")
    args = parser.parse_args(argv)
    for name in pin(args.tasks):
        print(f"pinned {training.SHIPPED / name}.pt")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
