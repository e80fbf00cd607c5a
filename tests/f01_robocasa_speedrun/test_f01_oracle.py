"""The Harbor oracle of every family-01 task with a program below L3 imports that program in its level's
workspace: the workspace's ``harness`` (an L1 one holds ``robot`` only) plus what the oracle ships.
A real Harbor trial of 01-turn-on-stove-l2 once failed with ImportError (its program borrowed from an
L3 one that imported ``world``); L1 programs move with ``motion``, which an L1 workspace lacks."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

from rle_tasks.core.registry import get_task
from rle_tasks.envs.kitchen.workspace import lay_out_harness
from rle_tasks.f01_robocasa_speedrun.kitchens import KITCHEN_TASKS
from rle_tasks.f01_robocasa_speedrun.solutions import agents
from rle_tasks.f01_robocasa_speedrun.solutions.oracle import harbor_oracle

BELOW_L3 = [
    (kitchen.task_id(level), kitchen.task, level)
    for kitchen in KITCHEN_TASKS
    for level in (1, 2)
    if kitchen.task in agents.PROGRAMS_BY_LEVEL[level]
]


def test_every_program_below_l3_is_covered():
    assert {t for t, _, lv in BELOW_L3 if lv == 1} >= {"01-open-fridge-l1", "01-turn-on-stove-l1"}
    assert len([t for t, _, lv in BELOW_L3 if lv == 2]) == 5


@pytest.mark.parametrize("task_id,task,level", BELOW_L3, ids=[t for t, _, _ in BELOW_L3])
def test_oracle_imports_its_program_in_the_level_s_workspace(tmp_path, task_id, task, level):
    sol, ws = tmp_path / "solution", tmp_path / "workspace"
    assert harbor_oracle(get_task(task_id), sol) is not None
    lay_out_harness(ws, level)
    oracle = (sol / "oracle.py").read_text()
    (line,) = re.findall(r"^sys\.path\[:0\] = \[.*\]$", oracle, flags=re.M)
    line = line.replace('"/solution', f'"{sol}').replace('"/workspace"', f'"{ws}"')
    code = (
        "import sys, importlib.abc\n"
        "class Block(importlib.abc.MetaPathFinder):\n"  # the project's own copies are not in the image
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name.startswith('rle_tasks'):\n"
        "            raise ImportError(name + ' is not in the agent image')\n"
        "sys.meta_path.insert(0, Block())\n"
        f"{line}\n"
        "import agents, harness\n"
        f"agents.solver({task!r}, {level})\n"
        "print(sorted(m for m in sys.modules if m.startswith('harness')))\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=tmp_path
    )
    assert run.returncode == 0, run.stderr[-2000:]
    assert "harness.world" not in run.stdout  # below L3 no program reaches the world state
