"""Every family folder has the same shape, and its instruction and README carry the rubric's table."""

import importlib
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
    rubric = importlib.import_module(f"{package}.scoring").RUBRIC
    table = rubric.markdown_table()
    readme = (_folder(package) / "README.md").read_text()
    assert table in readme, f"{package}/README.md does not hold RUBRIC.markdown_table()"
    for task in all_tasks():
        if task.implemented and task.id == rubric.task_id:
            assert table in task.instruction


def test_every_implemented_task_comes_from_a_family_folder():
    implemented = {t.family for t in all_tasks() if t.implemented}
    assert implemented and implemented <= set(PACKAGES)
