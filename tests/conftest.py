"""Shared test settings: offscreen GL, reduced physics batteries unless RLE_FULL_BATTERY=1."""

import os

import pytest

import rle_design  # noqa: F401  (pins the BLAS kernel family before any test module loads numpy)

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("PYOPENGL_PLATFORM", os.environ["MUJOCO_GL"])
os.environ.pop("RLE_SECRET", None)  # tests choose their secrets explicitly


@pytest.fixture(scope="session")
def full_battery() -> bool:
    """True when the full (slow) physics batteries are requested."""
    return os.environ.get("RLE_FULL_BATTERY") == "1"
