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


@pytest.fixture(scope="session")
def libero10_task0(libero_side_env):
    """LIBERO-10 task 0, state only, in one side process shared by the tests that need no other."""
    from rle_tasks.envs.libero import LiberoEnv

    with LiberoEnv("libero_10", 0, render=False) as env:
        yield env


@pytest.fixture(scope="session")
def libero10_task0_rendered(libero_side_env):
    """LIBERO-10 task 0 with both 128 px views, shared by the tests that need images."""
    from rle_tasks.envs.libero import LiberoEnv

    with LiberoEnv("libero_10", 0) as env:
        yield env
