"""Registration, instruction and README tables, and the metered development environment (``rle dev``)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

from rle_design.control import CartesianHelper
from rle_design.ledger import verify_ledger
from rle_tasks.core.registry import all_tasks, get_task
from rle_tasks.core.runtime.devenv import layout_workspace, ledger_key
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.f03_physical_reasoning.scoring import RUBRICS

README = Path(__file__).parents[2] / "rle_tasks/f03_physical_reasoning/README.md"
PUBLIC = Secret(PUBLIC_KEY, public=True)


def test_tower_and_cantilever_are_implemented_and_the_other_ids_registered() -> None:
    family = {t.id: t for t in all_tasks() if t.family == 3}
    assert {"03-tower", "03-cantilever", "03-balance-coins", "03-pocket-cube", "03-hidden-com"} <= set(family)
    assert family["03-tower"].implemented and family["03-cantilever"].implemented
    assert family["03-tower"].budget.steps == 50_000


def test_instruction_and_readme_carry_the_rubric_tables() -> None:
    readmes = "".join(p.read_text() for p in README.parent.rglob("README.md"))  # the family's and the cube's
    assert len(RUBRICS) == 5
    for task_id, rubric in RUBRICS.items():
        table = rubric.markdown_table()
        assert table in get_task(task_id).instruction and table in readmes


def _client(workspace: Path):
    spec = importlib.util.spec_from_file_location("f03_client", workspace / "client.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_dev_environment_serves_12d_actions_without_piece_poses(tmp_path: Path) -> None:
    ws = layout_workspace(get_task("03-cantilever"), tmp_path / "ws", secret=PUBLIC)
    try:
        with _client(ws.workspace).connect() as env:
            obs = env.reset()
            assert "bodies" not in obs and "qpos" not in obs
            assert {"front", "side", "top"} == set(obs["rgb"]) and obs["rgb"]["front"].shape == (120, 160, 3)
            helper = CartesianHelper(env.step, obs)
            goal = np.asarray(obs["arms"][0]["ee_pos"]) + [0.0, 0.05, -0.05]
            assert helper.move_to(goal, max_steps=60).reached
            assert env.info()["steps_used"] == 1 + helper.steps
            env.seal()
        ws.server.wait(10)
    finally:
        ws.close()
    verdict = verify_ledger(ws.ledger_path, ledger_key(PUBLIC, "03-cantilever"), "03-cantilever")
    assert verdict.valid and verdict.steps == 1 + helper.steps
    assert not any("block" in p.read_text(errors="ignore") for p in ws.workspace.rglob("*.py"))
