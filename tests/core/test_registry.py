import re
from collections import Counter

import pytest

from rle_design.errors import RleError
from rle_tasks.cli import main
from rle_tasks.core.registry import all_tasks, get_task
from rle_tasks.core.task import WORKFLOW_ORDER


def test_51_unique_ids_in_nine_families():
    ids = [t.id for t in all_tasks()]
    assert len(ids) == 51 and len(set(ids)) == 51
    assert Counter(t.family for t in all_tasks()) == {1: 15, 2: 15, 3: 5, 4: 5, 5: 4, 6: 4, 7: 1, 8: 1, 9: 1}
    for t in all_tasks():
        assert re.fullmatch(r"0[1-9]-[a-z0-9-]+", t.id), t.id
        assert t.id.startswith(f"{t.family:02d}-")
        assert t.workflow in WORKFLOW_ORDER


def test_design_ids_present():
    for tid in ("08-mobile-base", "09-gello", "06-pose-a-rgb", "06-pose-d-agnostic", "03-balance-coins"):
        assert get_task(tid).id == tid


def test_unknown_task_lists_family_ids():
    with pytest.raises(RleError, match=r"task '08-nope' does not exist. Known ids: 08-mobile-base"):
        get_task("08-nope")


def test_cli_tasks_prints_51(capsys):
    assert main(["tasks"]) == 0
    out = capsys.readouterr().out
    assert "51 tasks" in out
    assert len([ln for ln in out.splitlines() if re.match(r"0[1-9]-", ln)]) == 51


def test_cli_unknown_task_exit_2(capsys):
    assert main(["show", "99-nothing"]) == 2
    assert "task.unknown" in capsys.readouterr().err
