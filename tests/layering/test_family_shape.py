"""Every family folder has the same shape, and its instruction and README carry the rubric's table."""

import functools
import importlib
import inspect
from pathlib import Path

import pytest

from rle_tasks.core.registry import all_tasks, family_packages

REQUIRED = ("__init__.py", "task.py", "instruction.md", "scoring.py", "verifier.py", "README.md")
FOLDERS = ("assets", "solutions")
PACKAGES = family_packages()


def _folder(package: str) -> Path:
    return Path(importlib.import_module(package).__file__).parent


@pytest.mark.parametrize("package", list(PACKAGES.values()))
def test_family_folder_shape(package):
    root = _folder(package)
    missing = [f for f in REQUIRED if not (root / f).is_file()] + [
        d for d in FOLDERS if not (root / d).is_dir()
    ]
    assert missing == [], f"{package} lacks {missing}"
    assert callable(importlib.import_module(package).tasks)
    assert (root / "solutions" / "__init__.py").is_file() and (root / "solutions" / "reference").is_dir()
    if (root / "public").is_dir():
        assert (root / "public" / "__init__.py").is_file()


@pytest.mark.parametrize("package", list(PACKAGES.values()))
def test_instruction_and_readme_show_the_declared_rubric(package):
    """Every task's instruction holds its own rubric's table, and the family's READMEs (the family's, or
    a task subpackage's) hold every distinct table."""
    rubrics = importlib.import_module(f"{package}.scoring").rubrics()
    readmes = "".join(p.read_text() for p in _folder(package).rglob("README.md"))
    implemented = [t for t in all_tasks() if t.implemented and t.family == int(package.split(".f")[1][:2])]
    assert implemented and {t.id for t in implemented} <= set(rubrics)
    for task in implemented:
        table = rubrics[task.id].markdown_table()
        assert table in task.instruction, f"{task.id}: the instruction lacks its rubric's table"
        assert table in readmes, f"{task.id}: no README of {package} holds its rubric's table"


def test_every_implemented_task_comes_from_a_family_folder():
    implemented = {t.family for t in all_tasks() if t.implemented}
    assert implemented and implemented <= set(PACKAGES)


@pytest.mark.parametrize("package", list(PACKAGES.values()))
def test_every_task_verifies_through_its_familys_verify(package):
    """One entry point: every implemented task's ``verify`` is its family's ``verifier.verify(root, ctx, *,
    task_id)`` bound to the task's id."""
    family_verify = importlib.import_module(f"{package}.verifier").verify
    family = int(package.split(".f")[1][:2])
    implemented = [t for t in all_tasks() if t.implemented and t.family == family]
    for task in implemented:
        v = task.verify
        assert isinstance(v, functools.partial), f"{task.id}: verify is {v!r}"
        assert v.func is family_verify and v.args == () and v.keywords == {"task_id": task.id}, task.id
    params = inspect.signature(family_verify).parameters
    assert list(params)[:2] == ["root", "ctx"] and params["task_id"].kind is inspect.Parameter.KEYWORD_ONLY
