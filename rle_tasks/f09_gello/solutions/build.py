"""Builds the reference leaders: ``python -m rle_tasks.f09_gello.solutions.build [ROBOT ...]`` (build
time only). The design is ``design`` (exact counterweights and spring, the placements), the fastening
and the placement search ``attached``.
"""

from __future__ import annotations

import shutil
import tempfile
import time
from pathlib import Path

import mujoco

from rle_tasks.f09_gello.leaders import ROBOTS
from rle_tasks.f09_gello.solutions.attached import clear_fastened, write_leader
from rle_tasks.f09_gello.solutions.design import PKG

BUILD_OPTIONS = {"xarm7": {"search": False, "descent": 3, "box": 0.005}}
"""Per-robot options of ``attached.clear_fastened``: xarm7's joint search finds nothing better than
the greedy's first pass, so its greedy passes run to the end and a coordinate descent over the whole
design (every part, clearance at its full slope, parts inside the next link heavily counted, further
spring mounts) follows; its re-balance keeps each weight within 5 mm of its placement (at 15 mm the
optimiser moved every weight outwards, lighter: 11.9 % of the fine grid became 16.8 %). panda's and
ur5e's leaders are built as before."""


def build_all(target: Path = PKG / "solutions" / "reference", robots: tuple[str, ...] = ROBOTS) -> None:
    """Write the reference leaders (``solutions/reference/<robot>/lead.xml``): the exact design with
    every part fastened and re-balanced (``attached.clear_fastened``). The rest of every shipped
    solution is declared in ``solutions/__init__.py`` and materialised by ``rle_tasks.core.solutions``.
    ``robots``: the leaders to write (each is built on its own: the others' files are left as they are)."""
    with tempfile.TemporaryDirectory() as tmp:
        for robot in robots:
            t0 = time.perf_counter()
            des = clear_fastened(robot, verbose=True, **BUILD_OPTIONS.get(robot, {}))
            path = write_leader(robot, des, Path(tmp) / robot)
            m = mujoco.MjModel.from_xml_path(str(path))
            print(
                f"{robot}: reference mass {m.body_mass.sum():.3f} kg, {time.perf_counter() - t0:.0f} s, {des}"
            )
            (target / robot).mkdir(parents=True, exist_ok=True)
            shutil.copyfile(path, target / robot / "lead.xml")


if __name__ == "__main__":
    import sys

    build_all(robots=tuple(sys.argv[1:]) or ROBOTS)  # e.g. ``... build ur5e xarm7``
