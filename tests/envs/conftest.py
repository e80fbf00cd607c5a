"""Fixtures of the environment tests."""

import pytest

from rle_design.errors import RleError
from rle_tasks.envs.libero import libero_python


@pytest.fixture(scope="session")
def libero_side_env():
    """The LIBERO side environment's interpreter; tests that drive LIBERO skip, naming `make
    libero-venv`, where it was not created (`make test` creates it first)."""
    try:
        return libero_python()
    except RleError as exc:
        pytest.skip(str(exc))
