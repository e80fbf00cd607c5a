"""The Harbor oracle of family 01: the reference program, playing the task through the sidecar.

An exported task's development server runs in its sidecar (``rle_tasks.core.export.harbor.sidecar``), so an
oracle trial scores only what is played there. ``harbor_oracle`` writes into the task's ``solution/``
the agent programs of ``agents`` (the same files, their harness imports pointed at the workspace's
``harness`` package, which holds the same modules) and ``oracle.py``, which connects with the
workspace's ``client.py`` and plays the session as ``make_ledgers`` does: one pretrain episode, then
the five evaluation trials, then the seal.

An L1 workspace's harness holds ``robot`` only, while the programs move with ``motion`` and transform
with ``geometry``: below ``LIBRARY_LEVEL`` the oracle brings those modules along as its own library
(``solution/lib/harness``, the level-2 harness, never ``world``), as an L1 agent brings the code it wrote.
The programs still read only their level's observations.
"""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.export.harbor.export import PLAYING_SOLVE_SH

HERE = Path(__file__).resolve().parent
HARNESS_IMPORT = "rle_tasks.envs.kitchen.harness"
"""The harness package as the programs import it; the workspace's copy is ``harness``."""
BUILD_ONLY = ("trial.py",)
"""Agent modules of development runs only (they need the verifier's scene sets)."""
LIBRARY_LEVEL = 2
"""Harness level whose modules an oracle below it ships as its own library."""
_LIBRARY_INIT = '''"""The oracle's own library: the kitchen harness modules of level {level} (robot, geometry,
perception, motion), imported as ``harness`` in place of the workspace's smaller one."""
'''

_ORACLE = '''"""Oracle of {task_id}: the reference program plays the session through the development sidecar."""

import sys

sys.path[:0] = [{library}"/workspace", "/solution"]

from agents import play  # noqa: E402
from client import connect  # noqa: E402

with connect() as env:
    wins = play(env, {task!r}, level={level})
    print(f"trials as the program saw them: {{wins}}", flush=True)
    env.seal()
'''


def harbor_oracle(spec, dest: Path) -> str | None:
    """Write the playing oracle of ``spec`` into ``dest``; returns ``solve.sh``, or None when no
    program of its task runs at its level.

    Raises:
        ValueError: a copied program still imports the verifier's package.
    """
    from ..kitchens import KITCHEN_TASKS, LEVELS
    from . import agents

    match = [(k, lv) for k in KITCHEN_TASKS for lv in LEVELS if k.task_id(lv) == spec.id]
    if not match or not agents.available(match[0][0].task, match[0][1]):
        return None
    kitchen, level = match[0]
    library = ""
    if level < LIBRARY_LEVEL:
        from rle_tasks.envs.kitchen.workspace import lay_out_harness

        init, *_ = lay_out_harness(Path(dest) / "lib", LIBRARY_LEVEL)
        init.write_text(_LIBRARY_INIT.format(level=LIBRARY_LEVEL))
        library = '"/solution/lib", '
    out = Path(dest) / "agents"
    out.mkdir(parents=True, exist_ok=True)
    for src in sorted((HERE / "agents").glob("*.py")):
        if src.name in BUILD_ONLY:
            continue
        text = src.read_text().replace(HARNESS_IMPORT, "harness")
        if "rle_tasks" in text:
            raise ValueError(f"{src.name} imports rle_tasks, which the agent's image does not hold")
        (out / src.name).write_text(text)
    (Path(dest) / "oracle.py").write_text(
        _ORACLE.format(task_id=spec.id, task=kitchen.task, level=level, library=library)
    )
    return PLAYING_SOLVE_SH
