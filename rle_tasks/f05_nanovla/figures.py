"""Figures of family 05: ``python -m rle_tasks.f05_nanovla.figures [libero|standin]`` writes
``assets/libero10_views.png`` (both views of every LIBERO-10 task at official initial state 0) and
``assets/standin_views.png`` (both views of the stand-in's tasks, clean and with a robust-track look)
(build time): what a served policy sees."""

from __future__ import annotations

from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
SHEET = HERE / "assets" / "libero10_views.png"
STANDIN_SHEET = HERE / "assets" / "standin_views.png"


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


def standin_sheet(out: Path = STANDIN_SHEET, seed: int = 0, look_seed: int = 1_000_003) -> Path:
    """Write a 2 x 6 sheet (head above front; tasks 0-2 clean, then with one robust look) as PNG."""
    from PIL import Image

    import rle_design  # noqa: F401  (rendering backend before MuJoCo)
    from rle_tasks.envs.standin import TASKS, StandinEnv, robust_look

    columns = []
    for look in (None, robust_look(look_seed)):
        for t in range(len(TASKS)):
            env = StandinEnv(t) if look is None else StandinEnv(t, look)
            obs = env.reset(seed)
            columns.append(np.concatenate([obs["head"], obs["front"]], axis=0))
    out.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(np.concatenate(columns, axis=1)).save(out, optimize=True)
    return out


if __name__ == "__main__":
    import sys

    which = sys.argv[1:] or ["libero", "standin"]
    if "libero" in which:
        print(views_sheet())
    if "standin" in which:
        print(standin_sheet())
