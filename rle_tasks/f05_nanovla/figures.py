"""Figures of family 05: ``python -m rle_tasks.f05_nanovla.figures`` writes ``assets/libero10_views.png``
(build time): what a served policy sees, both views of every LIBERO-10 task at official initial state 0."""

from __future__ import annotations

from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
SHEET = HERE / "assets" / "libero10_views.png"


def views_sheet(out: Path = SHEET, init_index: int = 0) -> Path:
    """Write a 2 x 10 sheet (agent view above wrist view, tasks 0-9 left to right) as PNG."""
    from PIL import Image

    from rle_tasks.envs.libero import LiberoEnv

    columns = []
    for task_id in range(10):
        with LiberoEnv("libero_10", task_id) as env:
            env.start()
            obs = env.reset(init_index)
        columns.append(np.concatenate([obs["agentview"], obs["wrist"]], axis=0))
    sheet = np.concatenate(columns, axis=1)
    out.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(sheet).save(out, optimize=True)
    return out


if __name__ == "__main__":
    print(views_sheet())
