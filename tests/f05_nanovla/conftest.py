"""Fixtures of the family-05 tests."""

from pathlib import Path

import pytest

from rle_tasks.core.solutions import materialise

REFERENCE_STEPS = "MAX_STEPS = 8_000"


@pytest.fixture
def short_reference(tmp_path):
    """``make(task, steps=20)``: a copy of the task's shipped reference recipe in ``tmp_path/sub``
    whose training stops after ``steps`` optimiser steps (the full recipe trains for minutes)."""

    def make(task, steps: int = 20) -> Path:
        source = (materialise(task, "reference") / "solution.py").read_text()
        assert REFERENCE_STEPS in source
        sub = tmp_path / "sub"
        sub.mkdir()
        (sub / "solution.py").write_text(source.replace(REFERENCE_STEPS, f"MAX_STEPS = {steps}"))
        return sub

    return make
