"""Shared test settings: offscreen GL, reduced physics batteries unless RLE_FULL_BATTERY=1."""

import os

import pytest

import rle_design  # noqa: F401  (pins the BLAS kernel family before any test module loads numpy)
from rle_design.errors import RleError

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("PYOPENGL_PLATFORM", os.environ["MUJOCO_GL"])
os.environ.pop("RLE_SECRET", None)  # tests choose their secrets explicitly


@pytest.fixture(autouse=True, scope="module")
def _release_memory_after_each_file():
    """Frees the cached renderers (GL contexts holding whole scenes) and returns freed heap to the
    system after each test file: a pytest-xdist worker runs hundreds of files in one process, and two
    of them must fit in the CI machine's memory beside the processes the tests start."""
    yield
    import contextlib
    import ctypes
    import gc

    from rle_design.control.cameras import close_renderers

    close_renderers()
    gc.collect()
    with contextlib.suppress(OSError, AttributeError):  # not glibc
        ctypes.CDLL("libc.so.6").malloc_trim(0)


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
