"""Shared test settings: offscreen GL, reduced physics batteries unless RLE_FULL_BATTERY=1."""

import os

import pytest

import rle_design  # noqa: F401  (pins the BLAS kernel family before any test module loads numpy)
from rle_design.errors import RleError

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("PYOPENGL_PLATFORM", os.environ["MUJOCO_GL"])
os.environ.pop("RLE_SECRET", None)  # tests choose their secrets explicitly


@pytest.fixture(scope="session")
def full_battery() -> bool:
    """True when the full (slow) physics batteries are requested."""
    return os.environ.get("RLE_FULL_BATTERY") == "1"


@pytest.fixture(scope="session")
def libero_side_env():
    """The LIBERO side environment's interpreter; tests that drive LIBERO skip, naming `make
    libero-venv`, where it was not created (`make test` creates it first)."""
    from rle_tasks.envs.libero import libero_python

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
